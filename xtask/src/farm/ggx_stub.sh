#!/usr/bin/env bash
# A stand-in for the ggx binary with the command line of `ggx render --samples/--resume` and
# `ggx merge`, so the Slurm scripts and the farm scenario run without a renderer: a "film" is a
# text file naming its scene, spp, frame and sample range. Like ggx, render interrupted by
# SIGTERM (scancel) writes the film so far (no samples: `samples=A..A`) and exits 130; --resume
# continues such a film. `merge` checks what ggx merge checks (same settings, disjoint ranges,
# every sample from 0) and writes exactly what one render of all the samples writes.
# GGX_STUB_SLEEP=S makes render take S seconds.
set -euo pipefail

fail() {
    echo "ggx-stub: $1" >&2
    exit "${2:-1}"
}

# Writes stdin to $1 through a temporary file, as ggx does.
write_atomic() {
    cat >"$1.tmp"
    mv "$1.tmp" "$1"
}

[ "$#" -ge 1 ] || fail "usage: ggx-stub render|merge ..." 2
command="$1"
shift
case "$command" in
    render)
        scene="" spp="" samples="" frame="0" out="" extra="" resume=""
        while [ "$#" -gt 0 ]; do
            case "$1" in
                --spp | --samples | --frame | --threads | --width | --height | --seed | --resume | -o)
                    [ "$#" -ge 2 ] || fail "$1 needs a value" 2
                    case "$1" in
                        --spp) spp="$2" ;;
                        --samples) samples="$2" ;;
                        --resume) resume="$2" ;;
                        --frame) frame="$2" ;;
                        --width | --height | --seed) extra="$extra $1=$2" ;;
                        -o) out="$2" ;;
                    esac
                    shift 2
                    ;;
                -*) fail "unknown option $1" 2 ;;
                *)
                    scene="$1"
                    shift
                    ;;
            esac
        done
        if [ -z "$scene" ] || [ -z "$out" ] || [ -z "$spp" ]; then fail "render needs SCENE, --spp N and -o OUT" 2; fi
        [ -r "$scene" ] || fail "cannot read scene $scene"
        samples="${samples:-0..$spp}"
        settings="$(printf 'scene=%s\nspp=%s\nframe=%s\noptions=%s' "$scene" "$spp" "$frame" "$extra")"
        if [ -n "$resume" ]; then
            [ -r "$resume" ] || fail "cannot read $resume"
            [ "$(grep -v '^samples=' "$resume")" = "$settings" ] || fail "$resume was rendered with other settings"
            saved="$(sed -n 's/^samples=//p' "$resume")"
            [ "${saved%..*}" = "${samples%..*}" ] || fail "$resume starts at ${saved%..*}, not ${samples%..*}"
        fi
        # Like ggx: SIGTERM stops the render, and what was rendered (nothing) is written.
        interrupted="" sleeper=""
        trap 'interrupted=1; [ -z "$sleeper" ] || kill "$sleeper" 2>/dev/null || true' TERM INT
        sleep "${GGX_STUB_SLEEP:-0}" &
        sleeper="$!"
        wait "$sleeper" || true
        if [ -n "$interrupted" ]; then
            printf '%s\nsamples=%s..%s\n' "$settings" "${samples%..*}" "${samples%..*}" | write_atomic "$out"
            echo "ggx-stub: interrupted: wrote the film so far to $out" >&2
            exit 130
        fi
        printf '%s\nsamples=%s\n' "$settings" "$samples" | write_atomic "$out"
        ;;
    merge)
        parts=() out=""
        while [ "$#" -gt 0 ]; do
            case "$1" in
                -o)
                    [ "$#" -ge 2 ] || fail "-o needs a value" 2
                    out="$2"
                    shift 2
                    ;;
                *)
                    parts+=("$1")
                    shift
                    ;;
            esac
        done
        if [ -z "$out" ] || [ "${#parts[@]}" -eq 0 ]; then fail "merge needs PARTS... and -o OUT" 2; fi
        settings="" ranges=""
        for part in "${parts[@]}"; do
            these="$(grep -v '^samples=' "$part")" || fail "cannot read $part"
            [ -z "$settings" ] || [ "$these" = "$settings" ] || fail "$part was rendered with other settings"
            settings="$these"
            range="$(sed -n 's/^samples=//p' "$part")"
            ranges="$ranges${range%..*} ${range#*..}"$'\n'
        done
        spp="$(sed -n 's/^spp=//p' <<<"$settings")"
        next=0 missing=""
        while read -r first end; do
            [ -n "$first" ] || continue
            [ "$first" -ge "$next" ] || fail "overlapping sample ranges at $first"
            [ "$first" -eq "$next" ] || missing="$missing $next..$first"
            next="$end"
        done < <(sort -n -k1,1 <<<"$ranges")
        [ "$next" -ge "$spp" ] || missing="$missing $next..$spp"
        [ -z "$missing" ] || fail "incomplete: missing samples$missing"
        printf '%s\nsamples=0..%s\n' "$settings" "$spp" | write_atomic "$out"
        ;;
    *) fail "unknown command $command" 2 ;;
esac
