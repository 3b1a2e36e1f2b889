//! Mutation testing of the film-file reader (`read_film`, `read_film_info`: the files `ggx
//! merge` and `ggx render --resume` read from other machines).
//!
//! A small valid film file is mutated (bit flips, byte runs set to 0xFF or 0x00, truncation,
//! a spliced copy of another region) and read under a small pixel limit. The reader must
//! return a film within the limit, or an error that names the file; never panic or abort. On
//! Linux the test runs again in a child process whose address space is capped at
//! [`ADDRESS_SPACE_CAP`], so an allocation from an unchecked header size aborts the child and
//! fails the test. `GGX_FUZZ_CASES` sets the number of cases (default [`DEFAULT_CASES`]).

use std::path::{Path, PathBuf};

use ggx_film::{Film, FilmInfo, OutputOptions, SampleSum, Vec3, read_film, read_film_info, write_film};
use proptest::prelude::*;

/// Cases when `GGX_FUZZ_CASES` is unset.
const DEFAULT_CASES: u32 = 128;

/// Address space of the child process on Linux.
const ADDRESS_SPACE_CAP: u64 = 1 << 30;

/// The pixel limit the mutated files are read under.
const MAX_PIXELS: u64 = 1 << 12;

fn cases() -> u32 {
    match std::env::var("GGX_FUZZ_CASES") {
        Ok(v) => v.parse().unwrap_or_else(|e| panic!("GGX_FUZZ_CASES must be a number of cases, got {v:?}: {e}")),
        Err(_) => DEFAULT_CASES,
    }
}

/// A valid 12x7 film file's bytes.
fn film_bytes(dir: &Path) -> Vec<u8> {
    let mut film = Film::new(12, 7);
    for (i, p) in film.pixels_mut().iter_mut().enumerate() {
        let mut s = SampleSum::default();
        for k in 0..(i % 5) as u32 {
            s.add(Vec3::new(i as f32 * 0.1, k as f32, 1e-3));
        }
        *p = s;
    }
    let info = FilmInfo {
        scene: "s.toml".into(),
        scene_hash: "ab".into(),
        samples: [0, 4],
        total: 4,
        window: [0, 0, 12, 7],
        backend: "cpu cwbvh".into(),
        version: "0".into(),
        ..Default::default()
    };
    let path = dir.join("valid.exr");
    write_film(&path, &info, &film, true, &OutputOptions::default()).unwrap();
    std::fs::read(&path).unwrap()
}

/// One mutation of a file's bytes.
#[derive(Clone, Debug)]
enum Mutation {
    Flip { at: usize, bit: u8 },
    Fill { at: usize, len: usize, byte: u8 },
    Truncate { at: usize },
    Splice { from: usize, to: usize, len: usize },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), 0u8..8).prop_map(|(at, bit)| Mutation::Flip { at, bit }),
        (any::<usize>(), 1usize..9, prop_oneof![Just(0xFFu8), Just(0u8), Just(0x7F)])
            .prop_map(|(at, len, byte)| Mutation::Fill { at, len, byte }),
        any::<usize>().prop_map(|at| Mutation::Truncate { at }),
        (any::<usize>(), any::<usize>(), 1usize..64).prop_map(|(from, to, len)| Mutation::Splice { from, to, len }),
    ]
}

/// `bytes` after the mutations (positions taken modulo the length).
fn mutate(mut bytes: Vec<u8>, mutations: &[Mutation]) -> Vec<u8> {
    for m in mutations {
        let n = bytes.len().max(1);
        match *m {
            Mutation::Flip { at, bit } => {
                if let Some(b) = bytes.get_mut(at % n) {
                    *b ^= 1 << bit;
                }
            }
            Mutation::Fill { at, len, byte } => {
                let start = at % n;
                let end = (start + len).min(bytes.len());
                bytes[start.min(end)..end].fill(byte);
            }
            Mutation::Truncate { at } => bytes.truncate(at % n),
            Mutation::Splice { from, to, len } => {
                let (from, to) = (from % n, to % n);
                let len = len.min(bytes.len().saturating_sub(from)).min(bytes.len().saturating_sub(to));
                let chunk = bytes[from..from + len].to_vec();
                bytes[to..to + len].copy_from_slice(&chunk);
            }
        }
    }
    bytes
}

/// On Linux, outside the child: runs `name` in a child process with its address space capped
/// and asserts it passed (returns `true`); in the child, or without capping, `false`.
fn ran_capped(name: &str) -> bool {
    if !cfg!(target_os = "linux") || std::env::var_os("GGX_FILM_FUZZ_CHILD").is_some() {
        return false;
    }
    let exe = std::env::current_exe().expect("test binary path");
    let script = format!("ulimit -v {} && exec \"$0\" \"$@\"", ADDRESS_SPACE_CAP / 1024);
    let Ok(output) = std::process::Command::new("sh")
        .args(["-c", &script])
        .arg(&exe)
        .args(["--exact", name, "--nocapture", "--test-threads=1"])
        .env("GGX_FILM_FUZZ_CHILD", "1")
        .output()
    else {
        return false;
    };
    let text = format!("{}{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "{name} failed under a {ADDRESS_SPACE_CAP}-byte address space cap:\n{text}");
    assert!(text.contains("1 passed"), "{name} did not run in the child:\n{text}");
    true
}

fn dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("film_fuzz");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn mutated_film_files_are_read_or_refused_never_a_panic() {
    if ran_capped("mutated_film_files_are_read_or_refused_never_a_panic") {
        return;
    }
    let dir = dir();
    let valid = film_bytes(&dir);
    let path = dir.join("mutated.exr");
    let name = path.display().to_string();
    let config = ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() };
    proptest!(config, |(mutations in proptest::collection::vec(mutation(), 1..4))| {
        std::fs::write(&path, mutate(valid.clone(), &mutations)).unwrap();
        match read_film(&path, MAX_PIXELS) {
            Ok((_, film)) => prop_assert!(film.len() as u64 <= MAX_PIXELS),
            Err(e) => prop_assert!(e.to_string().contains(&name), "{e}"),
        }
        if let Err(e) = read_film_info(&path) {
            prop_assert!(e.to_string().contains(&name), "{e}");
        }
    });
}

#[test]
fn the_unmutated_file_reads_back() {
    let dir = dir();
    let path = dir.join("plain.exr");
    std::fs::write(&path, film_bytes(&dir)).unwrap();
    let (info, film) = read_film(&path, MAX_PIXELS).unwrap();
    assert_eq!((info.samples, film.len()), ([0, 4], 84));
    assert!(read_film(&path, 83).is_err(), "over the pixel limit");
}
