//! Jobs as Slurm's clients see them: what to submit ([`JobSpec`]), the id `sbatch
//! --parsable` answers ([`JobId`]) and the state of each array task ([`TaskState`]) as
//! `squeue` reports it.

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// A job's id; for a job array, the array's (tasks are `ID_K`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct JobId(pub u32);

impl fmt::Display for JobId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// The state of one task (or of a job without array), from squeue's `%T`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TaskState {
    /// Waiting for resources, a dependency or the scheduler.
    Pending,
    /// Running.
    Running,
    /// Its script has ended and Slurm is cleaning up.
    Completing,
    /// Ended with exit code 0.
    Completed,
    /// Cancelled (scancel, or a dependency that can never be satisfied).
    Cancelled,
    /// Ended with a non-zero exit code.
    Failed,
    /// Killed at its time limit.
    Timeout,
    /// Any other state, by its name (NODE_FAIL, OUT_OF_MEMORY, SUSPENDED, REQUEUED, ...).
    Other(String),
}

/// The states that never change again.
const FINAL: [&str; 8] =
    ["COMPLETED", "CANCELLED", "FAILED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY", "BOOT_FAIL", "DEADLINE"];

impl TaskState {
    /// The state named `name` (squeue's `%T`).
    pub fn parse(name: &str) -> TaskState {
        match name {
            "PENDING" => TaskState::Pending,
            "RUNNING" => TaskState::Running,
            "COMPLETING" => TaskState::Completing,
            "COMPLETED" => TaskState::Completed,
            "CANCELLED" => TaskState::Cancelled,
            "FAILED" => TaskState::Failed,
            "TIMEOUT" => TaskState::Timeout,
            other => TaskState::Other(other.to_string()),
        }
    }

    /// True once the task has ended for good.
    pub fn is_final(&self) -> bool {
        match self {
            TaskState::Completed | TaskState::Cancelled | TaskState::Failed | TaskState::Timeout => true,
            TaskState::Other(name) => FINAL.contains(&name.as_str()),
            TaskState::Pending | TaskState::Running | TaskState::Completing => false,
        }
    }
}

impl fmt::Display for TaskState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = match self {
            TaskState::Pending => "PENDING",
            TaskState::Running => "RUNNING",
            TaskState::Completing => "COMPLETING",
            TaskState::Completed => "COMPLETED",
            TaskState::Cancelled => "CANCELLED",
            TaskState::Failed => "FAILED",
            TaskState::Timeout => "TIMEOUT",
            TaskState::Other(name) => name,
        };
        f.write_str(name)
    }
}

/// The state of every task of a job that Slurm still knows, by task index; a job without
/// array is task 0. A pending task cancelled before it started leaves no record: it is absent.
pub type JobStates = BTreeMap<u32, TaskState>;

/// The squeue format that [`parse_states`] reads: array job id, task index, state.
pub const SQUEUE_FORMAT: &str = "%F|%K|%T";

/// Parses squeue's `--array --format=%F|%K|%T` lines of job `job` (`%K` is `N/A` without array).
pub fn parse_states(job: JobId, text: &str) -> Result<JobStates, String> {
    let mut states = JobStates::new();
    for line in text.lines().map(str::trim).filter(|l| !l.is_empty()) {
        let fields: Vec<&str> = line.split('|').collect();
        let [array_job, task, state] = fields[..] else {
            return Err(format!("squeue: unexpected line `{line}`"));
        };
        if array_job != job.to_string() {
            continue;
        }
        let task = if task == "N/A" { 0 } else { task.parse().map_err(|_| format!("squeue: bad task in `{line}`"))? };
        states.insert(task, TaskState::parse(state));
    }
    Ok(states)
}

/// Parses `sbatch --parsable`'s answer, `ID` or `ID;CLUSTER`.
pub fn parse_job_id(text: &str) -> Result<JobId, String> {
    let id = text.trim().split(';').next().unwrap_or_default();
    id.parse().map(JobId).map_err(|_| format!("sbatch --parsable answered `{}`, not a job id", text.trim()))
}

/// Fails unless exactly the tasks `tasks` of `job` are in `states`, all COMPLETED; the
/// message shows each other task's state and the end of its output file `output(k)`.
pub fn require_completed(
    job: JobId,
    states: &JobStates,
    tasks: &[u32],
    output: impl Fn(u32) -> PathBuf,
) -> Result<(), String> {
    let mut problems = Vec::new();
    for &k in tasks {
        if states.get(&k) != Some(&TaskState::Completed) {
            let state = states.get(&k).map_or("gone".to_string(), ToString::to_string);
            let path = output(k);
            let log = std::fs::read_to_string(&path).unwrap_or_default();
            let lines: Vec<&str> = log.lines().collect();
            let end = lines[lines.len().saturating_sub(8)..].join("\n");
            problems.push(format!("task {job}_{k}: {state}; {}:\n{end}", path.display()));
        }
    }
    if let Some(extra) = states.keys().find(|k| !tasks.contains(k)) {
        problems.push(format!("task {job}_{extra}: not expected"));
    }
    if problems.is_empty() { Ok(()) } else { Err(problems.join("\n")) }
}

/// `0:COMPLETED 1:CANCELLED ...`, for messages.
pub fn summary(states: &JobStates) -> String {
    states.iter().map(|(k, s)| format!("{k}:{s}")).collect::<Vec<_>>().join(" ")
}

/// What to submit with sbatch: a batch script, its arguments, its environment (added to
/// this process's, which sbatch exports to the job), and the options the farm needs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JobSpec {
    /// The batch script.
    pub script: PathBuf,
    /// The script's arguments.
    pub args: Vec<String>,
    /// `--array`, e.g. `0-7` or `3`.
    pub array: Option<String>,
    /// Variables set for the job.
    pub env: Vec<(String, String)>,
    /// `--dependency=afterok:ID` (with `--kill-on-invalid-dep=yes`: cancelled when ID fails).
    pub after_ok: Option<JobId>,
    /// `--job-name`.
    pub name: Option<String>,
    /// `--output`; by default the cluster's jobs directory (see [`JobSpec::sbatch_args`]).
    pub output: Option<PathBuf>,
}

impl JobSpec {
    /// A job running `script` with no arguments.
    pub fn new(script: impl Into<PathBuf>) -> JobSpec {
        JobSpec {
            script: script.into(),
            args: Vec::new(),
            array: None,
            env: Vec::new(),
            after_ok: None,
            name: None,
            output: None,
        }
    }

    /// Makes it a job array (`0-7`, `3`, `0,2,5`).
    pub fn array(mut self, array: impl Into<String>) -> JobSpec {
        self.array = Some(array.into());
        self
    }

    /// Appends arguments of the script.
    pub fn args<I: IntoIterator<Item = S>, S: Into<String>>(mut self, args: I) -> JobSpec {
        self.args.extend(args.into_iter().map(Into::into));
        self
    }

    /// Sets a variable for the job.
    pub fn env(mut self, key: impl Into<String>, value: impl Into<String>) -> JobSpec {
        self.env.push((key.into(), value.into()));
        self
    }

    /// Starts the job only once every task of `job` has succeeded.
    pub fn after_ok(mut self, job: JobId) -> JobSpec {
        self.after_ok = Some(job);
        self
    }

    /// Names the job.
    pub fn name(mut self, name: impl Into<String>) -> JobSpec {
        self.name = Some(name.into());
        self
    }

    /// Sets the job's output file (`%A`, `%a`, `%j` as in sbatch).
    pub fn output(mut self, output: impl Into<PathBuf>) -> JobSpec {
        self.output = Some(output.into());
        self
    }

    /// sbatch's arguments: `--parsable`, the options, the script and its arguments; the
    /// output goes to `jobs_dir/ID_K.out` (`ID.out` without array) unless set.
    pub fn sbatch_args(&self, jobs_dir: &Path) -> Vec<String> {
        let mut args = vec!["--parsable".to_string()];
        if let Some(array) = &self.array {
            args.push(format!("--array={array}"));
        }
        if let Some(name) = &self.name {
            args.push(format!("--job-name={name}"));
        }
        if let Some(job) = self.after_ok {
            args.push(format!("--dependency=afterok:{job}"));
            args.push("--kill-on-invalid-dep=yes".into());
        }
        let default_output = jobs_dir.join(if self.array.is_some() { "%A_%a.out" } else { "%j.out" });
        args.push(format!("--output={}", self.output.as_ref().unwrap_or(&default_output).display()));
        args.push(self.script.display().to_string());
        args.extend(self.args.iter().cloned());
        args
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn squeue_lines_become_states_by_task() {
        let text = "8|1|CANCELLED\n8|3|PENDING\n8|2|RUNNING\n8|0|COMPLETED\n9|0|RUNNING\n";
        let states = parse_states(JobId(8), text).unwrap();
        assert_eq!(states.len(), 4, "job 9 is another job");
        assert_eq!(states[&1], TaskState::Cancelled);
        assert_eq!(states[&3], TaskState::Pending);
        assert_eq!(
            parse_states(JobId(12), "12|N/A|OUT_OF_MEMORY\n").unwrap()[&0],
            TaskState::Other("OUT_OF_MEMORY".into())
        );
        assert!(parse_states(JobId(8), "8 1 RUNNING\n").is_err());
    }

    #[test]
    fn final_states_never_change_again() {
        for (name, is_final) in
            [("PENDING", false), ("RUNNING", false), ("COMPLETING", false), ("COMPLETED", true), ("CANCELLED", true)]
        {
            assert_eq!(TaskState::parse(name).is_final(), is_final, "{name}");
            assert_eq!(TaskState::parse(name).to_string(), name);
        }
        assert!(TaskState::parse("NODE_FAIL").is_final());
        assert!(!TaskState::parse("SUSPENDED").is_final());
    }

    #[test]
    fn completion_is_required_of_exactly_the_tasks_named() {
        let states: JobStates = [(0, TaskState::Completed), (1, TaskState::Failed)].into();
        let dir = std::env::temp_dir();
        let error =
            require_completed(JobId(4), &states, &[0, 1], |k| dir.join(format!("no-such-{k}.out"))).unwrap_err();
        assert!(error.contains("task 4_1: FAILED"), "{error}");
        assert!(require_completed(JobId(4), &states, &[0], |_| dir.clone()).unwrap_err().contains("4_1: not expected"));
        let error = require_completed(JobId(4), &states, &[0, 1, 2], |_| dir.clone()).unwrap_err();
        assert!(error.contains("4_2: gone"), "{error}");
        assert_eq!(summary(&states), "0:COMPLETED 1:FAILED");
    }

    #[test]
    fn sbatch_parsable_answers_are_job_ids() {
        assert_eq!(parse_job_id("123\n").unwrap(), JobId(123));
        assert_eq!(parse_job_id("77;ggxfarm").unwrap(), JobId(77));
        assert!(parse_job_id("Submitted batch job 5").is_err());
    }

    #[test]
    fn a_spec_becomes_sbatch_arguments() {
        let spec = JobSpec::new("/s/render.sbatch").array("3").args(["--tasks", "8"]).after_ok(JobId(41)).name("r");
        let args = spec.sbatch_args(Path::new("/jobs"));
        assert_eq!(
            args,
            [
                "--parsable",
                "--array=3",
                "--job-name=r",
                "--dependency=afterok:41",
                "--kill-on-invalid-dep=yes",
                "--output=/jobs/%A_%a.out",
                "/s/render.sbatch",
                "--tasks",
                "8"
            ]
        );
        let single = JobSpec::new("/s/merge.sbatch").sbatch_args(Path::new("/jobs"));
        assert_eq!(single, ["--parsable", "--output=/jobs/%j.out", "/s/merge.sbatch"]);
    }
}
