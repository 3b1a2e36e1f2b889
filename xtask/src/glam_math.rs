//! `ci`'s check that the renderers' glam does its math through std, not libm.
//!
//! glam's `libm` feature routes `Vec3::length`, `normalize` and the rest through libm even
//! where std is linked, and libm 0.2's `sqrtf` on x86-64 is inline assembly of the legacy-SSE
//! `sqrtss`. Inside the x86-64-v3 tile kernel, whose AVX code leaves the upper halves of the
//! vector registers in use, that one instruction made peer three-spheres 1.29x slower on an
//! Intel Xeon (README, Speed). ggx-core therefore asks glam for `nostd-libm`: libm
//! only where std is absent. This check fails if any crate of the `ggx` binary's dependency
//! graph turns glam's `libm` feature on again.

/// The glam feature that forces libm's math over std's.
const FORCED_LIBM: &str = "glam feature \"libm\"";

/// Fails when the `ggx-cli` graph enables glam's `libm` feature, naming what enables it.
pub fn check() -> Result<(), String> {
    let tree = crate::cargo_stdout(&["tree", "-p", "ggx-cli", "-e", "features", "-i", "glam", "--prefix", "depth"])?;
    forced_libm(&tree)
}

/// Parses `cargo tree -e features -i glam --prefix depth` output: an error listing the lines
/// under glam's `libm` feature (what enables it) when that feature is on.
fn forced_libm(tree: &str) -> Result<(), String> {
    let lines: Vec<&str> = tree.lines().collect();
    let Some(at) = lines.iter().position(|l| l.trim_start_matches(|c: char| c.is_ascii_digit()) == FORCED_LIBM) else {
        return Ok(());
    };
    let depth = |l: &str| l.chars().take_while(char::is_ascii_digit).collect::<String>().parse::<u32>().unwrap_or(0);
    let own = depth(lines[at]);
    let enablers: Vec<&str> = lines[at + 1..].iter().take_while(|l| depth(l) > own).copied().collect();
    Err(format!(
        "{FORCED_LIBM} is enabled for the ggx binary: glam's Vec3 math would run through libm's \
         legacy-SSE sqrtss inside the AVX kernels. Ask for glam's `nostd-libm` instead. Enabled by:\n{}",
        enablers.join("\n")
    ))
}

#[cfg(test)]
mod tests {
    use super::forced_libm;

    #[test]
    fn passes_without_the_libm_feature() {
        let tree =
            "0glam v0.34.2\n1glam feature \"nostd-libm\"\n2ggx-core v0.1.0\n1glam feature \"std\"\n2ggx-cpu v0.1.0\n";
        assert_eq!(forced_libm(tree), Ok(()));
    }

    #[test]
    fn fails_with_the_libm_feature_and_names_its_enabler() {
        let tree = "0glam v0.34.2\n1glam feature \"libm\"\n2ggx-core v0.1.0\n3ggx-core feature \"default\"\n1glam feature \"std\"\n2ggx-cpu v0.1.0\n";
        let err = forced_libm(tree).unwrap_err();
        assert!(err.contains("2ggx-core v0.1.0") && err.contains("3ggx-core feature"), "{err}");
        assert!(!err.contains("ggx-cpu"), "{err}");
    }
}
