//! `scenes/tolerances/diff.toml`: how far the wgpu render of a scene may stray from the CPU
//! render of the same seed. A `[default]` table plus optional `[scenes.<name>]` overrides;
//! unknown fields and scenes that do not exist are errors naming the file, line and field.

use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Bounds one scene must meet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    /// Per-channel relative error under which a pixel counts as equal.
    pub pixel: f64,
    /// Largest share (0 to 1) of pixels over `pixel`.
    pub max_over: f64,
    /// Largest relative MSE.
    pub max_rel_mse: f64,
    /// Largest mean FLIP of the tone-mapped images.
    pub max_flip: f64,
}

/// Every field optional: a scene table overrides only what it names.
#[derive(Clone, Copy, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTolerance {
    pixel: Option<f64>,
    max_over: Option<f64>,
    max_rel_mse: Option<f64>,
    max_flip: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    default: RawTolerance,
    #[serde(default)]
    scenes: BTreeMap<String, RawTolerance>,
}

/// The parsed file: defaults and per-scene overrides.
#[derive(Clone, Debug)]
pub struct Tolerances {
    path: PathBuf,
    default: Tolerance,
    scenes: BTreeMap<String, RawTolerance>,
}

impl Tolerances {
    /// Reads and validates the file. `known` lists the scene names a table may refer to.
    pub fn load(path: &Path, known: &[String]) -> Result<Tolerances, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Self::parse(path, &text, known)
    }

    /// [`Self::load`] on text already read.
    pub fn parse(path: &Path, text: &str, known: &[String]) -> Result<Tolerances, String> {
        let raw: RawFile = toml::from_str(text).map_err(|e| format!("{}: {e}", path.display()))?;
        let full = |field: &str, v: Option<f64>| {
            v.ok_or_else(|| format!("{}: [default] needs the field `{field}`", path.display()))
        };
        let default = Tolerance {
            pixel: full("pixel", raw.default.pixel)?,
            max_over: full("max_over", raw.default.max_over)?,
            max_rel_mse: full("max_rel_mse", raw.default.max_rel_mse)?,
            max_flip: full("max_flip", raw.default.max_flip)?,
        };
        let tolerances = Tolerances { path: path.to_owned(), default, scenes: raw.scenes };
        check(path, "default", &default)?;
        for name in tolerances.scenes.keys() {
            if !known.iter().any(|k| k == name) {
                return Err(format!("{}: [scenes.{name}] names no scene in scenes/", path.display()));
            }
            check(path, &format!("scenes.{name}"), &tolerances.get(name))?;
        }
        Ok(tolerances)
    }

    /// The bounds for `scene`: its table over the defaults.
    pub fn get(&self, scene: &str) -> Tolerance {
        let d = self.default;
        match self.scenes.get(scene) {
            None => d,
            Some(s) => Tolerance {
                pixel: s.pixel.unwrap_or(d.pixel),
                max_over: s.max_over.unwrap_or(d.max_over),
                max_rel_mse: s.max_rel_mse.unwrap_or(d.max_rel_mse),
                max_flip: s.max_flip.unwrap_or(d.max_flip),
            },
        }
    }

    /// The file the tolerances came from.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// Every bound finite and non-negative, shares at most 1.
fn check(path: &Path, table: &str, t: &Tolerance) -> Result<(), String> {
    for (field, v, max) in [
        ("pixel", t.pixel, f64::MAX),
        ("max_over", t.max_over, 1.0),
        ("max_rel_mse", t.max_rel_mse, f64::MAX),
        ("max_flip", t.max_flip, 1.0),
    ] {
        if !(v >= 0.0 && v <= max) {
            return Err(format!("{}: [{table}] {field} = {v} must be in [0, {max}]", path.display()));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const FILE: &str = "[default]\npixel = 1e-3\nmax_over = 0.0\nmax_rel_mse = 1e-10\nmax_flip = 1e-3\n\
                        [scenes.bunny]\nmax_over = 0.05\n";

    fn known() -> Vec<String> {
        vec!["bunny".into(), "cornell".into()]
    }

    #[test]
    fn scene_tables_override_only_what_they_name() {
        let t = Tolerances::parse(Path::new("t.toml"), FILE, &known()).unwrap();
        assert_eq!(t.get("cornell"), Tolerance { pixel: 1e-3, max_over: 0.0, max_rel_mse: 1e-10, max_flip: 1e-3 });
        assert_eq!(t.get("bunny").max_over, 0.05);
        assert_eq!(t.get("bunny").max_rel_mse, 1e-10);
    }

    #[test]
    fn errors_name_the_file_the_line_and_the_field() {
        let typo = FILE.replace("max_over = 0.05", "max_ovr = 0.05");
        let e = Tolerances::parse(Path::new("t.toml"), &typo, &known()).unwrap_err();
        assert!(e.contains("t.toml") && e.contains("line 7") && e.contains("max_ovr"), "{e}");
        let unknown = FILE.replace("scenes.bunny", "scenes.bunnny");
        let e = Tolerances::parse(Path::new("t.toml"), &unknown, &known()).unwrap_err();
        assert!(e.contains("scenes.bunnny"), "{e}");
        let negative = FILE.replace("max_flip = 1e-3", "max_flip = -1");
        let e = Tolerances::parse(Path::new("t.toml"), &negative, &known()).unwrap_err();
        assert!(e.contains("[default] max_flip"), "{e}");
        let missing = FILE.replace("pixel = 1e-3\n", "");
        let e = Tolerances::parse(Path::new("t.toml"), &missing, &known()).unwrap_err();
        assert!(e.contains("`pixel`"), "{e}");
    }

    #[test]
    fn the_committed_file_parses() {
        let names: Vec<String> =
            crate::render::scene_paths(&[]).unwrap().iter().map(|p| crate::render::scene_name(p)).collect();
        let path = crate::render::scenes_dir().join("tolerances/diff.toml");
        Tolerances::load(&path, &names).unwrap();
    }
}
