//! The diff's results: one row per scene, a console line and the markdown report.

use super::tolerances::Tolerance;
use crate::render::Overrides;
use ggx_film::ImageMetrics;
use std::fmt::Write as _;
use std::path::PathBuf;

/// One scene's comparison.
#[derive(Clone, Debug)]
pub struct Row {
    /// Scene name.
    pub scene: String,
    /// Rendered size.
    pub resolution: [u32; 2],
    /// Samples per pixel of both renders.
    pub spp: u32,
    /// Kernel variant that ran.
    pub kernel: &'static str,
    /// CPU render time (BVH build excluded).
    pub cpu_seconds: f64,
    /// wgpu render time (pipeline compilation excluded).
    pub gpu_seconds: f64,
    /// wgpu image against the CPU image.
    pub metrics: ImageMetrics,
    /// Mean FLIP of the tone-mapped images.
    pub flip: f64,
    /// The scene's bounds.
    pub tolerance: Tolerance,
    /// Both backends rendered the same number of samples with the same kernel variant.
    pub same_spp: bool,
}

impl Row {
    /// Which bounds are exceeded, by name (empty when the scene passes).
    pub fn failures(&self) -> Vec<&'static str> {
        let (m, t) = (&self.metrics, &self.tolerance);
        let mut out = Vec::new();
        if !self.same_spp {
            out.push("spp/kernel");
        }
        if !(m.over_tolerance <= t.max_over) {
            out.push("pixels over");
        }
        if !(m.rel_mse <= t.max_rel_mse) {
            out.push("relMSE");
        }
        if !(self.flip <= t.max_flip) {
            out.push("FLIP");
        }
        out
    }

    /// True when every bound holds.
    pub fn passed(&self) -> bool {
        self.failures().is_empty()
    }

    /// One console line.
    pub fn line(&self) -> String {
        let verdict = if self.passed() { "ok".to_string() } else { format!("FAILED ({})", self.failures().join(", ")) };
        format!("{:<16} {}, FLIP {:.3e}: {verdict}", self.scene, self.metrics, self.flip)
    }
}

/// Everything `report.md` shows.
#[derive(Clone, Debug)]
pub struct Report {
    /// The wgpu adapter.
    pub adapter: String,
    /// Size and sample count asked for.
    pub overrides: Overrides,
    /// Where the bounds came from.
    pub tolerances: PathBuf,
    /// The CPU backend's BVH layout (`Wide`, `Cwbvh` or `Bvh2`).
    pub cpu_bvh: String,
    /// One per scene.
    pub rows: Vec<Row>,
}

impl Report {
    /// An empty report.
    pub fn new(adapter: String, overrides: Overrides, tolerances: PathBuf, cpu_bvh: String) -> Report {
        Report { adapter, overrides, tolerances, cpu_bvh, rows: Vec::new() }
    }

    /// The markdown report.
    pub fn markdown(&self) -> String {
        let mut s = String::from("# CPU vs wgpu: `cargo xtask diff`\n\n");
        let _ = writeln!(s, "- wgpu adapter: {}", self.adapter);
        let _ =
            writeln!(s, "- width {} px, {} spp, same seed on both backends", self.overrides.width, self.overrides.spp);
        let _ = writeln!(s, "- CPU BVH: {} (the wgpu backend traces a BVH2)", self.cpu_bvh);
        let _ = writeln!(s, "- bounds: `{}`", self.tolerances.display());
        s.push_str(
            "- relative error per channel `|gpu - cpu| / sqrt(cpu^2 + 0.01)`; a pixel is over when its largest \
             channel exceeds the pixel tolerance; FLIP on the tone-mapped sRGB images\n\n",
        );
        s.push_str(
            "| scene | size | spp | kernel | cpu s | wgpu s | RMSE | relMSE (max) | max rel | pixels over (max) | FLIP (max) | |\n",
        );
        s.push_str("|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---|\n");
        for r in &self.rows {
            let (m, t) = (&r.metrics, &r.tolerance);
            let verdict =
                if r.passed() { "ok".to_string() } else { format!("**FAILED**: {}", r.failures().join(", ")) };
            let _ = writeln!(
                s,
                "| {} | {}x{} | {} | {} | {:.2} | {:.2} | {:.2e} | {:.2e} ({:.0e}) | {:.2e} | {:.3}% ({:.1}%) | {:.2e} ({:.0e}) | {verdict} |",
                r.scene,
                r.resolution[0],
                r.resolution[1],
                r.spp,
                r.kernel,
                r.cpu_seconds,
                r.gpu_seconds,
                m.rmse,
                m.rel_mse,
                t.max_rel_mse,
                m.max_rel,
                100.0 * m.over_tolerance,
                100.0 * t.max_over,
                r.flip,
                t.max_flip,
            );
        }
        s.push_str("\nPer scene: `<scene>/cpu.exr`, `<scene>/wgpu.exr`, `<scene>/diff.png` (relative error, log scale 1e-7 black to 1 yellow), `<scene>/flip.png`.\n");
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(over: f64, rel_mse: f64, flip: f64) -> Row {
        Row {
            scene: "cornell".into(),
            resolution: [4, 4],
            spp: 2,
            kernel: "area",
            cpu_seconds: 0.1,
            gpu_seconds: 0.2,
            metrics: ImageMetrics { rmse: 0.0, rel_mse, max_rel: 0.0, over_tolerance: over },
            flip,
            tolerance: Tolerance { pixel: 1e-3, max_over: 0.01, max_rel_mse: 1e-6, max_flip: 1e-3 },
            same_spp: true,
        }
    }

    #[test]
    fn each_bound_fails_on_its_own_and_nan_fails() {
        assert!(row(0.01, 1e-6, 1e-3).passed());
        assert_eq!(row(0.02, 0.0, 0.0).failures(), ["pixels over"]);
        assert_eq!(row(0.0, 2e-6, 0.0).failures(), ["relMSE"]);
        assert_eq!(row(0.0, 0.0, 2e-3).failures(), ["FLIP"]);
        assert_eq!(row(0.0, f64::NAN, 0.0).failures(), ["relMSE"]);
        let mut r = row(0.0, 0.0, 0.0);
        r.same_spp = false;
        assert!(!r.passed());
    }

    #[test]
    fn report_has_a_row_per_scene_with_the_verdict() {
        let mut report =
            Report::new("llvmpipe".into(), Overrides { width: 4, spp: 2 }, "t.toml".into(), "Cwbvh".into());
        report.rows = vec![row(0.0, 0.0, 0.0), row(0.5, 0.0, 0.0)];
        let md = report.markdown();
        assert!(md.contains("llvmpipe"));
        assert_eq!(md.matches("| cornell |").count(), 2);
        assert!(md.contains("**FAILED**: pixels over"));
    }
}
