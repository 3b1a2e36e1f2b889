//! The Kubernetes manifests of `scripts/k8s/` checked offline: every YAML document against
//! the vendored JSON schema of its kind (`scripts/k8s/schema/`, from kubernetes-validate's
//! "strict" schemas, where an unknown field is an error), and the pods' shell run with the
//! ggx stub ([`check_pod_scripts`]).

use super::scripts::install_stub;
use crate::render::workspace_root;
use serde::Deserialize;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// `scripts/k8s/` of the workspace.
pub fn manifests_dir() -> PathBuf {
    workspace_root().join("scripts").join("k8s")
}

/// The vendored schemas.
pub fn schema_dir() -> PathBuf {
    manifests_dir().join("schema")
}

/// Every `scripts/k8s/*.yaml`, sorted.
pub fn manifests() -> Result<Vec<PathBuf>, String> {
    let dir = manifests_dir();
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "yaml" || x == "yml"))
        .collect();
    files.sort();
    Ok(files)
}

/// The YAML documents of `text` as JSON values; empty documents are skipped.
pub fn documents(text: &str) -> Result<Vec<Value>, String> {
    serde_norway::Deserializer::from_str(text)
        .map(|document| Value::deserialize(document).map_err(|e| e.to_string()))
        .filter(|v| !matches!(v, Ok(Value::Null)))
        .collect()
}

/// The schema file of a document: `KIND-GROUP-VERSION.json` (`job-batch-v1.json`), or
/// `KIND-VERSION.json` for the core group (`persistentvolumeclaim-v1.json`).
pub fn schema_name(document: &Value) -> Result<String, String> {
    let field = |name: &str| document.get(name).and_then(Value::as_str).ok_or_else(|| format!("no `{name}` string"));
    let (api_version, kind) = (field("apiVersion")?, field("kind")?.to_lowercase());
    Ok(match api_version.split_once('/') {
        Some((group, version)) => format!("{kind}-{}-{version}.json", group.split('.').next().unwrap_or(group)),
        None => format!("{kind}-{api_version}.json"),
    })
}

/// Compiled schemas by file name, each read and compiled once.
#[derive(Default)]
pub struct Schemas {
    /// The validators by schema file name.
    validators: BTreeMap<String, jsonschema::Validator>,
}

impl Schemas {
    /// The problems of one document ("/json/path: message"); empty when it is valid.
    pub fn validate(&mut self, document: &Value) -> Result<Vec<String>, String> {
        let name = schema_name(document)?;
        if !self.validators.contains_key(&name) {
            let path = schema_dir().join(&name);
            let text = std::fs::read_to_string(&path)
                .map_err(|e| format!("no vendored schema {} for this kind ({e}); see schema/NOTICE", path.display()))?;
            let schema: Value = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
            let validator = jsonschema::validator_for(&schema).map_err(|e| format!("{}: {e}", path.display()))?;
            self.validators.insert(name.clone(), validator);
        }
        let validator = &self.validators[&name];
        Ok(validator.iter_errors(document).map(|e| format!("{}: {e}", e.instance_path())).collect())
    }
}

/// Validates every document of every manifest; returns how many documents were checked.
pub fn check_all() -> Result<usize, String> {
    let mut schemas = Schemas::default();
    let (mut count, mut problems) = (0, Vec::new());
    for file in manifests()? {
        let text = std::fs::read_to_string(&file).map_err(|e| format!("{}: {e}", file.display()))?;
        for (i, document) in documents(&text).map_err(|e| format!("{}: {e}", file.display()))?.iter().enumerate() {
            count += 1;
            let found = schemas.validate(document).map_err(|e| format!("{} document {i}: {e}", file.display()))?;
            problems.extend(found.into_iter().map(|p| format!("{} document {i}: {p}", file.display())));
        }
    }
    if problems.is_empty() { Ok(count) } else { Err(problems.join("\n")) }
}

/// Kubernetes' expansion of a container's command and args: `$$` is `$`, `$(NAME)` is the
/// value of NAME where `vars` has it, and anything else stays as written.
pub fn expand(text: &str, vars: &BTreeMap<String, String>) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(at) = rest.find('$') {
        out.push_str(&rest[..at]);
        rest = &rest[at..];
        if let Some(after) = rest.strip_prefix("$$") {
            out.push('$');
            rest = after;
        } else if let Some((name, after)) = rest.strip_prefix("$(").and_then(|r| r.split_once(')'))
            && let Some(value) = vars.get(name)
        {
            out.push_str(value);
            rest = after;
        } else {
            out.push('$');
            rest = &rest[1..];
        }
    }
    out.push_str(rest);
    out
}

/// The first container of a Job document: its environment and its shell script (`args[0]`
/// of `sh -c`), as Kubernetes expands it.
pub fn container_script(job: &Value) -> Result<(BTreeMap<String, String>, String), String> {
    let container = job.pointer("/spec/template/spec/containers/0").ok_or("no container")?;
    let env: BTreeMap<String, String> = container
        .get("env")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(|v| Some((v.get("name")?.as_str()?.to_string(), v.get("value")?.as_str()?.to_string())))
        .collect();
    let script = container.pointer("/args/0").and_then(Value::as_str).ok_or("no args[0] script")?;
    Ok((env.clone(), expand(script, &env)))
}

/// The one document of a manifest file of `scripts/k8s/`.
pub fn manifest(name: &str) -> Result<Value, String> {
    let path = manifests_dir().join(name);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut docs = documents(&text)?;
    if docs.len() == 1 {
        Ok(docs.remove(0))
    } else {
        Err(format!("{}: {} documents, not 1", path.display(), docs.len()))
    }
}

/// Reads `samples=` of a stub film.
fn stub_samples(film: &Path) -> Option<String> {
    std::fs::read_to_string(film).ok()?.lines().find_map(|l| l.strip_prefix("samples=")).map(str::to_string)
}

/// Runs the shell of the render Job's pods (one per index, `JOB_COMPLETION_INDEX` set) and
/// then the merge Job's, as Kubernetes would expand them, with the ggx stub on `PATH` and the
/// volume replaced by a directory under `scratch`: the parts must merge into all the samples.
pub fn check_pod_scripts(scratch: &Path) -> Result<String, String> {
    let _ = std::fs::remove_dir_all(scratch);
    let bin = scratch.join("bin");
    install_stub(&bin)?;
    let scene = scratch.join("scene.toml");
    std::fs::write(&scene, "# a scene\n").map_err(|e| format!("{}: {e}", scene.display()))?;
    let parts = scratch.join("parts");
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    let run = |script: &str, env: &BTreeMap<String, String>, vars: &[(&str, &str)]| {
        let out = Command::new("sh")
            .arg("-c")
            .arg(script)
            .envs(env)
            .envs(vars.iter().copied())
            .env("PATH", &path)
            .env("SCENE", &scene)
            .env("PARTS", &parts)
            .output()
            .map_err(|e| format!("sh: {e}"))?;
        if out.status.success() {
            Ok(())
        } else {
            Err(format!("{vars:?}: {} {}", out.status, String::from_utf8_lossy(&out.stderr)))
        }
    };
    let (env, script) = container_script(&manifest("render-indexed-job.yaml")?)?;
    let tasks: u32 = env.get("TASKS").and_then(|t| t.parse().ok()).ok_or("the render Job has no TASKS")?;
    for k in 0..tasks {
        run(&script, &env, &[("JOB_COMPLETION_INDEX", &k.to_string())])?;
    }
    let merged = scratch.join("merged.exr");
    let (merge_env, merge_script) = container_script(&manifest("merge-job.yaml")?)?;
    run(&merge_script, &merge_env, &[("MERGED", merged.to_str().unwrap_or_default())])?;
    let want = format!("0..{}", env.get("SPP").map_or("?", String::as_str));
    match stub_samples(&merged) {
        Some(got) if got == want => Ok(format!("{tasks} render pods and the merge pod: samples {want}")),
        got => Err(format!("the merge pod wrote samples {got:?}, not {want}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_manifest_is_valid_against_the_vendored_schemas() {
        let count = check_all().unwrap();
        assert!(count >= 3, "pvc, render job, merge job: {count}");
    }

    /// The render Job with `from` replaced by `to` in its text, validated.
    fn mutated(from: &str, to: &str) -> Vec<String> {
        let text = std::fs::read_to_string(manifests_dir().join("render-indexed-job.yaml")).unwrap();
        assert!(text.contains(from), "`{from}` is not in the manifest");
        let documents = documents(&text.replacen(from, to, 1)).unwrap();
        Schemas::default().validate(&documents[0]).unwrap()
    }

    #[test]
    fn a_misspelled_field_fails_validation() {
        let problems = mutated("completionMode: Indexed", "completionMod: Indexed");
        assert!(problems.iter().any(|p| p.contains("/spec") && p.contains("completionMod")), "{problems:?}");
        let problems = mutated("backoffLimitPerIndex: 2", "backoffLimitPerIndx: 2");
        assert!(!problems.is_empty());
    }

    #[test]
    fn a_wrong_type_or_value_fails_validation() {
        let problems = mutated("completions: 8", "completions: \"8\"");
        assert!(problems.iter().any(|p| p.starts_with("/spec/completions")), "{problems:?}");
        let problems = mutated("value: \"256\"", "value: 256");
        assert!(problems.iter().any(|p| p.contains("/env/1/value")), "{problems:?}");
    }

    #[test]
    fn an_unknown_kind_has_no_schema() {
        let document = documents("apiVersion: apps/v1\nkind: Deployment\n").unwrap().remove(0);
        assert_eq!(schema_name(&document).unwrap(), "deployment-apps-v1.json");
        assert!(Schemas::default().validate(&document).unwrap_err().contains("no vendored schema"));
        let core = documents("apiVersion: v1\nkind: PersistentVolumeClaim\n").unwrap().remove(0);
        assert_eq!(schema_name(&core).unwrap(), "persistentvolumeclaim-v1.json");
    }

    #[test]
    fn kubernetes_expansion_is_emulated() {
        let vars: BTreeMap<String, String> = [("SPP".to_string(), "64".to_string())].into();
        assert_eq!(expand("$(SPP) $$(SPP) $$((1 + 2)) $(NOPE) $HOME $", &vars), "64 $(SPP) $((1 + 2)) $(NOPE) $HOME $");
    }

    #[test]
    fn the_render_job_is_consistent() {
        let job = manifest("render-indexed-job.yaml").unwrap();
        let (env, _) = container_script(&job).unwrap();
        let completions = job.pointer("/spec/completions").and_then(Value::as_u64).unwrap();
        assert_eq!(env["TASKS"], completions.to_string(), "TASKS must equal spec.completions");
        assert!(env["TASKS"].parse::<u64>().unwrap() <= env["SPP"].parse().unwrap());
        assert_eq!(job.pointer("/spec/completionMode").and_then(Value::as_str), Some("Indexed"));
        assert_eq!(job.pointer("/spec/template/spec/restartPolicy").and_then(Value::as_str), Some("Never"));
        // Every `$(` of the shell is escaped (`$$(`): none relies on an unknown name staying as written.
        let raw = job.pointer("/spec/template/spec/containers/0/args/0").and_then(Value::as_str).unwrap();
        assert!(raw.match_indices("$(").all(|(i, _)| i > 0 && &raw[i - 1..i] == "$"), "{raw}");
        let claim = job.pointer("/spec/template/spec/volumes/0/persistentVolumeClaim/claimName");
        let pvc = manifest("pvc.yaml").unwrap();
        assert_eq!(claim, pvc.pointer("/metadata/name"), "the Job mounts pvc.yaml's claim");
    }

    #[test]
    fn the_pods_scripts_split_and_merge_the_samples() {
        let dir = std::env::temp_dir().join(format!("xtask-farm-k8s-{}", std::process::id()));
        let report = check_pod_scripts(&dir).unwrap();
        assert!(report.contains("8 render pods"), "{report}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
