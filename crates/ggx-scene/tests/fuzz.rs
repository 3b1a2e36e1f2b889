//! The parser never panics: random text and mutated scene files give `Ok` or a located,
//! short `Err`, under the default limits and under small ones.
//!
//! Each property runs `GGX_FUZZ_CASES` cases (default [`DEFAULT_CASES`], about ten seconds in
//! the dev profile); `cargo xtask fuzz` sets a long budget.

mod fuzz_cases;

use std::path::{Path, PathBuf};

use ggx_scene::{Limits, parse_scene, parse_scene_with};
use proptest::prelude::*;

const FILE: &str = "fuzz.toml";

/// Cases per property when `GGX_FUZZ_CASES` is not set.
const DEFAULT_CASES: u32 = 4096;

/// Longest error message accepted: user text is echoed in short form.
const MAX_MESSAGE_BYTES: usize = 2048;

/// Small limits that mutated scenes can cross: scene text, triangles, memory, map pixels.
fn small_limits() -> Limits {
    Limits {
        max_scene_bytes: 4096,
        max_mesh_bytes: 64 << 10,
        max_map_pixels: 4096,
        max_triangles: 20_000,
        max_memory: 4 << 20,
    }
}

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// A scene that touches every key of the format.
const EVERYTHING: &str = r#"
[camera]
position = [0, 1, 3.5]
look_at = [0, 1, 0]
up = [0, 1, 0]
fov_y = 40.0
resolution = [64, 32]

[integrator]
spp = 4
max_depth = 3
russian_roulette = 2
time = 1.5
seed = 9
sampler = "independent"
bsdf_sampling = "spherical-caps"
light_strategy = "nee"
mis_compensation = false

[materials.d]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[materials.c]
type = "conductor"
roughness = [0.2, 0.4]
eta = [0.2, 0.9, 1.1]
k = [3.9, 2.4, 2.1]
[materials.s]
type = "conductor"
alpha = 0.1
f0 = [0.9, 0.9, 0.9]
[materials.p]
type = "plastic"
roughness = 0.2
ior = 1.5
albedo = [0.1, 0.2, 0.3]
[materials.e]
type = "emissive"
radiance = [5, 5, 5]

[[shapes]]
type = "sphere"
material = "c"
center = [0, 1, 0]
radius = 0.5
subdivisions = 2
smooth = true
[[shapes]]
type = "rectangle"
material = "e"
transform = { translate = [0, 2, 0], rotate = [90, 0, 0], scale = 0.5 }
[[shapes]]
type = "box"
material = "p"
transform = { scale = [1, 2, 1] }
[[shapes]]
type = "disk"
material = "d"
segments = 16
[[shapes]]
type = "mesh"
material = "s"
file = "assets/bunny.obj"
smooth = false

[environment]
type = "procedural"
preset = "studio"
resolution = [32, 16]
scale = 1.0
rotation = 10.0
"#;

/// Tokens that are likely to reach deep validation paths.
const TOKENS: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "-1",
    "0",
    "1e40",
    "1.5",
    "[",
    "]",
    "{",
    "}",
    "=",
    ",",
    "\"",
    "\n",
    ".",
    "#",
    "[[shapes]]",
    "[[camera.keys]]",
    "time = 0.5",
    "[materials.x]",
    "type = \"mesh\"",
    "file = \"nope.obj\"",
    "material = \"zz\"",
    "alpha = [0.1]",
    "type = \"map\"",
    "type = \"constant\"",
    "scale = 0",
    "resolution = [0, 0]",
    "[environment]",
    "'",
    "\"\"\"",
    "1979-05-27",
    "true",
    "0x10",
    "é",
    "file = \"/dev/zero\"",
    "file = \".\"",
    "file = \"assets\"",
    "file = \"/dev/null\"",
    "subdivisions = 7",
    "seed = 4294967296",
    "radiance = [1e21, 1, 1]",
    "position = [0, 0, 1e20]",
    "type = \"emissive\"",
];

/// Values that numbers are replaced with: out of range, non-finite, huge, tiny, wrong type.
const VALUES: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "-1",
    "0",
    "-0.0",
    "1",
    "2",
    "1.5",
    "1e40",
    "1e39",
    "-3.5e38",
    "3.4e38",
    "1e20",
    "1e-30",
    "1e-50",
    "100000",
    "4294967296",
    "4294967295",
    "9223372036854775807",
    "-9223372036854775808",
    "7",
    "\"x\"",
    "[]",
    "[1, 2]",
    "true",
];

#[derive(Clone, Debug)]
enum Edit {
    Delete(usize, usize),
    Insert(usize, usize),
    Replace(usize, char),
    /// Replaces the n-th number literal with `VALUES[v]`.
    Number(usize, usize),
    /// Inserts a run of `len` copies of a character: a long key, name, string or number.
    Long(usize, usize, char),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        1 => (any::<usize>(), 1usize..8).prop_map(|(at, len)| Edit::Delete(at, len)),
        1 => (any::<usize>(), 0..TOKENS.len()).prop_map(|(at, t)| Edit::Insert(at, t)),
        1 => (any::<usize>(), any::<char>()).prop_map(|(at, c)| Edit::Replace(at, c)),
        3 => (any::<usize>(), 0..VALUES.len()).prop_map(|(n, v)| Edit::Number(n, v)),
        1 => (any::<usize>(), 1usize..100_000, prop::sample::select(vec!['k', '9', 'é', ' ']))
            .prop_map(|(at, len, c)| Edit::Long(at, len, c)),
    ]
}

/// Applies edits at char positions (taken modulo the current length).
fn mutate(text: &str, edits: &[Edit]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for e in edits {
        let n = chars.len().max(1);
        match *e {
            Edit::Delete(at, len) => {
                let at = at % n;
                chars.drain(at.min(chars.len())..(at + len).min(chars.len()));
            }
            Edit::Insert(at, t) => {
                let at = (at % (chars.len() + 1)).min(chars.len());
                chars.splice(at..at, TOKENS[t].chars());
            }
            Edit::Number(n, v) => {
                let numbers = number_literals(&chars);
                if !numbers.is_empty() {
                    let (start, end) = numbers[n % numbers.len()];
                    chars.splice(start..end, VALUES[v].chars());
                }
            }
            Edit::Long(at, len, c) => {
                let at = (at % (chars.len() + 1)).min(chars.len());
                chars.splice(at..at, std::iter::repeat_n(c, len));
            }
            Edit::Replace(at, c) => {
                let len = chars.len();
                if len > 0 {
                    chars[at % len] = c;
                }
            }
        }
    }
    chars.into_iter().collect()
}

/// `(start, end)` char ranges of the number literals in `chars` (runs of digits, `.`, `-`,
/// `e` that start with a digit or a sign and do not follow a letter).
fn number_literals(chars: &[char]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let starts =
            chars[i].is_ascii_digit() || (chars[i] == '-' && chars.get(i + 1).is_some_and(char::is_ascii_digit));
        let after_word = i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_');
        if starts && !after_word {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || matches!(chars[i], '.' | '-' | 'e' | '+')) {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

/// Parses within the default limits and within [`small_limits`], and checks that errors
/// are located in `FILE` and short.
fn parse_ok_or_located(text: &str) -> Result<(), TestCaseError> {
    for limits in [Limits::default(), small_limits()] {
        if let Err(e) = parse_scene_with(text, FILE, &scenes_dir(), &limits) {
            let shown = e.to_string();
            let head = shown.chars().take(300).collect::<String>();
            prop_assert!(shown.len() <= MAX_MESSAGE_BYTES, "{} bytes: {head}…", shown.len());
            prop_assert!(shown.starts_with(&format!("{FILE}:")), "{shown}");
            let (line, column) = e.line_column().unwrap_or((0, 0));
            prop_assert!(line >= 1 && column >= 1 && line <= text.lines().count().max(1) + 1, "{shown}");
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: fuzz_cases::fuzz_cases(DEFAULT_CASES),
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x6767_7873),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn random_text_never_panics(text in "\\PC{0,300}") {
        parse_ok_or_located(&text)?;
    }

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        parse_ok_or_located(&String::from_utf8_lossy(&bytes))?;
    }

    #[test]
    fn mutated_scenes_never_panic(base in 0usize..4, edits in prop::collection::vec(edit(), 1..6)) {
        let text = match base {
            0 => EVERYTHING.to_owned(),
            1 => std::fs::read_to_string(scenes_dir().join("cornell.toml")).unwrap(),
            2 => std::fs::read_to_string(scenes_dir().join("turntable.toml")).unwrap(),
            _ => std::fs::read_to_string(scenes_dir().join("furnace.toml")).unwrap(),
        };
        parse_ok_or_located(&mutate(&text, &edits))?;
    }
}

#[test]
fn everything_scene_is_valid() {
    let scene = parse_scene(EVERYTHING, FILE, &scenes_dir()).unwrap_or_else(|e| panic!("{e}"));
    let f = scene.features;
    assert!(
        f.area_lights && f.env_map && f.diffuse && f.conductors && f.plastics && f.anisotropic && f.shading_normals
    );
    assert_eq!(scene.integrator.time_budget, Some(1.5));
}
