#!/usr/bin/env bash
# Submits a distributed render to Slurm: a job array whose N tasks each render a share of the
# samples (render-array.sbatch) and a merge job (merge.sbatch) that starts once every task has
# succeeded (--dependency=afterok; if a task fails or is cancelled, Slurm cancels the merge job).
# Prints the two job ids on stdout, as ARRAY_JOB_ID=... and MERGE_JOB_ID=... lines.
#
#   scripts/slurm/submit.sh --spp 256 --tasks 8 --out parts/ scenes/cornell.toml
#   SBATCH_PARTITION=gpu scripts/slurm/submit.sh --spp 64 --tasks 4 --out p/ scene.toml -- --width 320
#
# Options:
#   --spp N         total samples per pixel (required)
#   --tasks N       array tasks, 1..spp (required)
#   --out DIR       parts, logs (DIR/logs/) and the merged image go here (required)
#   -o FILE         the merged image, .exr or .png (default: DIR/merged.exr)
#   --frame N       the frame of a camera animation
#   --cpus N        CPUs (and ggx threads) per array task (default: 1)
#   --ggx PATH      the ggx binary, as the compute nodes see it (GGX; default: ggx on PATH)
#   -- ARGS...      further `ggx render` options for every task (e.g. --width 320)
# sbatch reads its own options for both jobs from the environment: SBATCH_PARTITION,
# SBATCH_ACCOUNT, SBATCH_TIMELIMIT, ...
set -euo pipefail

usage() {
    echo "usage: submit.sh --spp N --tasks N --out DIR [-o FILE] [--frame N] [--cpus N] [--ggx PATH] SCENE.toml [-- GGX_RENDER_OPTIONS...]" >&2
    echo "submit.sh: $1" >&2
    exit 2
}

is_positive() { [[ "$1" =~ ^[1-9][0-9]{0,8}$ ]]; }

ggx="${GGX:-ggx}"
spp=""
tasks=""
out=""
merged=""
frame=""
cpus=1
scene=""
while [ "$#" -gt 0 ]; do
    case "$1" in
        --spp | --tasks | --out | -o | --frame | --cpus | --ggx)
            [ "$#" -ge 2 ] || usage "$1 needs a value"
            case "$1" in
                --spp) spp="$2" ;;
                --tasks) tasks="$2" ;;
                --out) out="$2" ;;
                -o) merged="$2" ;;
                --frame) frame="$2" ;;
                --cpus) cpus="$2" ;;
                --ggx) ggx="$2" ;;
            esac
            shift 2
            ;;
        --)
            shift
            break
            ;;
        -h | --help) usage "help requested" ;;
        -*) usage "unknown option $1" ;;
        *)
            [ -z "$scene" ] || usage "more than one scene ($scene, $1)"
            scene="$1"
            shift
            ;;
    esac
done

[ -n "$scene" ] || usage "no scene given"
[ -n "$out" ] || usage "no output directory (--out DIR)"
is_positive "$spp" || usage "--spp must be a positive integer, not '$spp'"
is_positive "$tasks" || usage "--tasks must be a positive integer, not '$tasks'"
is_positive "$cpus" || usage "--cpus must be a positive integer, not '$cpus'"
[ "$tasks" -le "$spp" ] || usage "$tasks tasks for $spp samples: some tasks would render nothing; use at most $spp tasks"
merged="${merged:-$out/merged.exr}"
case "${BASH_SOURCE[0]}" in
    */*) here="${BASH_SOURCE[0]%/*}" ;;
    *) here=. ;;
esac
here="$(cd "$here" && pwd)"

# Slurm does not create the directories of --output files.
mkdir -p "$out/logs"

render_args=(--ggx "$ggx" --spp "$spp" --tasks "$tasks" --out "$out")
[ -z "$frame" ] || render_args+=(--frame "$frame")

# --parsable prints "jobid" or "jobid;cluster".
array_job="$(sbatch --parsable --array="0-$((tasks - 1))" --cpus-per-task="$cpus" --output="$out/logs/render-%A_%a.out" \
    "$here/render-array.sbatch" "${render_args[@]}" "$scene" -- "$@")"
array_job="${array_job%%;*}"
echo "ARRAY_JOB_ID=$array_job"
merge_job="$(sbatch --parsable --dependency="afterok:$array_job" --kill-on-invalid-dep=yes \
    --output="$out/logs/merge-%j.out" "$here/merge.sbatch" --ggx "$ggx" --out "$out" -o "$merged")"
merge_job="${merge_job%%;*}"

echo "submit: array job $array_job renders $scene ($spp spp) in $tasks tasks into $out" >&2
echo "submit: merge job $merge_job writes $merged once every task of $array_job succeeded" >&2
echo "MERGE_JOB_ID=$merge_job"
