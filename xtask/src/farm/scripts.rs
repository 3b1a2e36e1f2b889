//! The Slurm scripts of `scripts/slurm/` and the stand-in for ggx that runs them without a
//! renderer ([`GGX_STUB`]); their tests here need bash but no Slurm.

use crate::render::workspace_root;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A stand-in for the ggx binary (`render --samples`, `merge`), see the script's header.
pub const GGX_STUB: &str = include_str!("ggx_stub.sh");

/// `scripts/slurm/` of the workspace.
pub fn slurm_dir() -> PathBuf {
    workspace_root().join("scripts").join("slurm")
}

/// One script of `scripts/slurm/` (`render-array.sbatch`, `merge.sbatch`, `frames-array.sbatch`, `submit.sh`).
pub fn slurm_script(name: &str) -> PathBuf {
    slurm_dir().join(name)
}

/// Writes [`GGX_STUB`] as the executable `dir/ggx` and returns its path.
pub fn install_stub(dir: &Path) -> Result<PathBuf, String> {
    use std::os::unix::fs::PermissionsExt;
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let path = dir.join("ggx");
    std::fs::write(&path, GGX_STUB).map_err(|e| format!("{}: {e}", path.display()))?;
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(path)
}

/// Every shell script of the farm: `scripts/slurm/*` and the stub's source.
pub fn shell_scripts() -> Result<Vec<PathBuf>, String> {
    let dir = slurm_dir();
    let mut scripts: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "sh" || x == "sbatch"))
        .collect();
    scripts.sort();
    scripts.push(workspace_root().join("xtask").join("src").join("farm").join("ggx_stub.sh"));
    Ok(scripts)
}

/// Runs `shellcheck` on every farm script; fails with its findings.
pub fn shellcheck(shellcheck: &Path) -> Result<usize, String> {
    let scripts = shell_scripts()?;
    let out = Command::new(shellcheck).args(&scripts).output().map_err(|e| format!("{}: {e}", shellcheck.display()))?;
    if out.status.success() {
        Ok(scripts.len())
    } else {
        Err(format!("shellcheck found problems:\n{}", String::from_utf8_lossy(&out.stdout)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::farm::install::find_program;
    use std::process::Output;

    /// A scratch directory for one test, with the stub installed as `bin/ggx` and a scene file.
    struct Scratch {
        dir: PathBuf,
        ggx: PathBuf,
        scene: PathBuf,
    }

    impl Scratch {
        /// Creates `xtask-farm-NAME-PID` under the temporary directory.
        fn new(name: &str) -> Scratch {
            let dir = std::env::temp_dir().join(format!("xtask-farm-{name}-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            let ggx = install_stub(&dir.join("bin")).unwrap();
            let scene = dir.join("scene.toml");
            std::fs::write(&scene, "# a scene\n").unwrap();
            Scratch { dir, ggx, scene }
        }

        /// Runs a script of scripts/slurm with bash, `args` and extra variables.
        fn run(&self, script: &str, args: &[&str], env: &[(&str, &str)]) -> Output {
            let mut command = Command::new("bash");
            command.arg(slurm_script(script)).args(args).env("GGX", &self.ggx);
            for key in ["SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT", "SLURM_CPUS_PER_TASK", "GGX_TASKS", "GGX_OUT"]
            {
                command.env_remove(key);
            }
            command.envs(env.iter().copied()).output().unwrap()
        }

        /// Reads `samples=` of a stub film.
        fn samples(&self, film: &Path) -> String {
            let text = std::fs::read_to_string(film).unwrap_or_else(|e| panic!("{}: {e}", film.display()));
            text.lines().find_map(|l| l.strip_prefix("samples=")).unwrap().to_string()
        }
    }

    impl Drop for Scratch {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }

    /// The text a failed command wrote to stderr.
    fn stderr(out: &Output) -> String {
        String::from_utf8_lossy(&out.stderr).into_owned()
    }

    #[test]
    fn array_tasks_split_the_samples_exactly() {
        let s = Scratch::new("split");
        let scene = s.scene.to_str().unwrap();
        for spp in [1u32, 7, 10] {
            for tasks in 1..=spp {
                let out = s.dir.join(format!("p-{spp}-{tasks}"));
                let mut covered = Vec::new();
                for k in 0..tasks {
                    let (spp_s, tasks_s, k_s) = (spp.to_string(), tasks.to_string(), k.to_string());
                    let args = ["--spp", &spp_s, "--tasks", &tasks_s, "--out", out.to_str().unwrap(), scene];
                    let result = s.run("render-array.sbatch", &args, &[("SLURM_ARRAY_TASK_ID", &k_s)]);
                    assert!(result.status.success(), "{}", stderr(&result));
                    let range = s.samples(&out.join(format!("part-{k:04}.exr")));
                    let (a, b) = range.split_once("..").unwrap();
                    covered.push((a.parse::<u32>().unwrap(), b.parse::<u32>().unwrap()));
                }
                // Contiguous, in task order, none empty, exactly [0, spp).
                assert_eq!(covered[0].0, 0);
                assert_eq!(covered.last().unwrap().1, spp);
                assert!(covered.windows(2).all(|w| w[0].1 == w[1].0), "{covered:?}");
                assert!(covered.iter().all(|(a, b)| a < b), "{covered:?}");
            }
        }
        let merged = s.dir.join("merged.exr");
        let out = s.dir.join("p-10-3");
        let result = s.run("merge.sbatch", &["--out", out.to_str().unwrap(), "-o", merged.to_str().unwrap()], &[]);
        assert!(result.status.success(), "{}", stderr(&result));
        assert_eq!(s.samples(&merged), "0..10");
    }

    #[test]
    fn render_array_passes_the_frame_threads_and_render_options() {
        let s = Scratch::new("options");
        let out = s.dir.join("parts");
        let args = [
            "--spp",
            "8",
            "--tasks",
            "2",
            "--frame",
            "5",
            "--out",
            out.to_str().unwrap(),
            s.scene.to_str().unwrap(),
            "--",
            "--width",
            "32",
        ];
        let env = [("SLURM_ARRAY_TASK_ID", "1"), ("SLURM_CPUS_PER_TASK", "1")];
        let result = s.run("render-array.sbatch", &args, &env);
        assert!(result.status.success(), "{}", stderr(&result));
        let film = std::fs::read_to_string(out.join("part-0001.exr")).unwrap();
        assert!(film.contains("frame=5\n") && film.contains("samples=4..8\n") && film.contains("--width=32"), "{film}");
        assert!(stderr(&result).contains("task 1 of 2: samples 4..8"));
    }

    #[test]
    fn render_array_refuses_what_would_render_wrong() {
        let s = Scratch::new("refuse");
        let out = s.dir.join("parts");
        let (out, scene) = (out.to_str().unwrap(), s.scene.to_str().unwrap());
        // Arguments, variables, the message expected.
        type Case<'a> = (&'a [&'a str], &'a [(&'a str, &'a str)], &'a str);
        let cases: [Case; 7] = [
            (
                &["--spp", "2", "--tasks", "3", "--out", out, scene],
                &[("SLURM_ARRAY_TASK_ID", "0")],
                "some tasks would render nothing",
            ),
            (&["--spp", "8", "--tasks", "2", "--out", out, scene], &[("SLURM_ARRAY_TASK_ID", "2")], "outside 0..1"),
            (&["--spp", "8", "--tasks", "2", "--out", out, scene], &[], "no task index"),
            (
                &["--spp", "08", "--tasks", "2", "--out", out, scene],
                &[("SLURM_ARRAY_TASK_ID", "0")],
                "positive integer",
            ),
            (&["--spp", "8", "--out", out, scene], &[("SLURM_ARRAY_TASK_ID", "0")], "no task count"),
            (&["--spp", "8", "--tasks", "2", "--out", out], &[("SLURM_ARRAY_TASK_ID", "0")], "no scene"),
            (
                &["--spp", "8", "--tasks", "2", "--bogus", out, scene],
                &[("SLURM_ARRAY_TASK_ID", "0")],
                "unknown option --bogus",
            ),
        ];
        for (args, env, message) in cases {
            let result = s.run("render-array.sbatch", args, env);
            assert_eq!(result.status.code(), Some(2), "{args:?}: {}", stderr(&result));
            assert!(stderr(&result).contains(message), "{args:?}: {}", stderr(&result));
        }
        assert!(!Path::new(out).exists(), "a refused task writes nothing");
    }

    #[test]
    fn the_task_count_comes_only_from_a_full_array() {
        let s = Scratch::new("count");
        let out = s.dir.join("parts");
        let args = ["--spp", "8", "--out", out.to_str().unwrap(), s.scene.to_str().unwrap()];
        let full = [
            ("SLURM_ARRAY_TASK_ID", "3"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_MAX", "3"),
        ];
        let result = s.run("render-array.sbatch", &args, &full);
        assert!(result.status.success(), "{}", stderr(&result));
        assert_eq!(s.samples(&out.join("part-0003.exr")), "6..8");
        // A resubmitted task (--array=3) sees an array of one: it must be told the total.
        let resubmitted = [
            ("SLURM_ARRAY_TASK_ID", "3"),
            ("SLURM_ARRAY_TASK_COUNT", "1"),
            ("SLURM_ARRAY_TASK_MIN", "3"),
            ("SLURM_ARRAY_TASK_MAX", "3"),
        ];
        let result = s.run("render-array.sbatch", &args, &resubmitted);
        assert_eq!(result.status.code(), Some(2));
        assert!(stderr(&result).contains("pass --tasks N"), "{}", stderr(&result));
    }

    #[test]
    fn merge_fails_without_parts_and_names_missing_ranges() {
        let s = Scratch::new("merge");
        let out = s.dir.join("parts");
        std::fs::create_dir_all(&out).unwrap();
        let merged = s.dir.join("merged.exr");
        let merge_args = ["--out", out.to_str().unwrap(), "-o", merged.to_str().unwrap()];
        let result = s.run("merge.sbatch", &merge_args, &[]);
        assert_eq!(result.status.code(), Some(2));
        assert!(stderr(&result).contains("no parts"), "{}", stderr(&result));
        for k in ["0", "2"] {
            let args = ["--spp", "9", "--tasks", "3", "--out", out.to_str().unwrap(), s.scene.to_str().unwrap()];
            assert!(s.run("render-array.sbatch", &args, &[("SLURM_ARRAY_TASK_ID", k)]).status.success());
        }
        let result = s.run("merge.sbatch", &merge_args, &[]);
        assert_eq!(result.status.code(), Some(1));
        assert!(stderr(&result).contains("missing samples 3..6"), "{}", stderr(&result));
        assert!(!merged.exists());
    }

    #[test]
    fn frames_array_renders_the_frame_of_its_task() {
        let s = Scratch::new("frames");
        let out = s.dir.join("frames");
        let args = ["--out", out.to_str().unwrap(), "--spp", "4", s.scene.to_str().unwrap()];
        let result = s.run("frames-array.sbatch", &args, &[("SLURM_ARRAY_TASK_ID", "12")]);
        assert!(result.status.success(), "{}", stderr(&result));
        let film = std::fs::read_to_string(out.join("frame-0012.png")).unwrap();
        assert!(film.contains("frame=12\n") && film.contains("spp=4\n"), "{film}");
        let result = s.run("frames-array.sbatch", &["--out", out.to_str().unwrap(), s.scene.to_str().unwrap()], &[]);
        assert_eq!(result.status.code(), Some(2));
        assert!(stderr(&result).contains("no frame"));
    }

    #[test]
    fn submit_refuses_bad_requests_before_calling_sbatch() {
        let s = Scratch::new("submit");
        let out = s.dir.join("parts");
        let scene = s.scene.to_str().unwrap();
        // No sbatch is on this PATH: a refusal must come first.
        let env = [("PATH", "/nonexistent")];
        for (args, message) in [
            (vec!["--spp", "4", "--tasks", "5", "--out", out.to_str().unwrap(), scene], "use at most 4 tasks"),
            (vec!["--spp", "4", "--out", out.to_str().unwrap(), scene], "--tasks must be a positive integer"),
            (vec!["--spp", "4", "--tasks", "2", scene], "no output directory"),
        ] {
            let mut command = Command::new(find_program("bash").unwrap());
            let result = command.arg(slurm_script("submit.sh")).args(&args).envs(env).output().unwrap();
            assert_eq!(result.status.code(), Some(2), "{args:?}");
            assert!(stderr(&result).contains(message), "{args:?}: {}", stderr(&result));
        }
    }

    #[test]
    fn scripts_are_shellcheck_clean() {
        // The self-test installs shellcheck and always runs this check; here it needs one installed.
        match find_program("shellcheck") {
            Some(shellcheck) => assert!(super::shellcheck(&shellcheck).unwrap() >= 5),
            None => eprintln!("shellcheck is not installed: `cargo xtask farm --selftest` runs this check"),
        }
    }
}
