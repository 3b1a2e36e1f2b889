//! The GGX micro-benchmark side by side: ggx-core's own criterion benchmark (`cargo bench -p
//! ggx-core --bench core`, one thread, 1024 cached inputs per iteration, bench profile at the
//! default target CPU) against Mitsuba 3's `MicrofacetDistribution` and `roughconductor` in
//! the LLVM variant (JIT-compiled for the host CPU, [`LANES`] lanes per launch), both at
//! alpha 0.3 with F = 1 on cosine-distributed directions.

use serde_json::Value;
use std::collections::BTreeMap;

/// Lanes per Mitsuba kernel launch (Dr.Jit is made for wide launches).
pub const LANES: u32 = 1 << 20;
/// GGX alpha of both benchmarks (ggx-core's bench uses 0.3).
pub const ALPHA: f32 = 0.3;

/// One row: what is measured, ggx-core's criterion id and Mitsuba's operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Op {
    /// Description.
    pub label: &'static str,
    /// `group/function` in ggx-core's criterion benchmark.
    pub ggx: &'static str,
    /// Key of the driver's `microbench` reply.
    pub mitsuba: &'static str,
}

/// Batch VNDF sampling, the operation with a speed goal of its own (issue 10).
pub const BATCH_VNDF: Op = Op {
    label: "reflected direction + pdf, VNDF (ggx: batch SoA)",
    ggx: "batch/sample_vndf",
    mitsuba: "sample_reflect",
};

/// The rows of the table: ggx-core's batch (SoA) functions, and its scalar functions (one
/// direction at a time) where Mitsuba's kernel computes the same quantity.
pub const OPS: [Op; 10] = [
    Op { label: "D(m) (ggx: scalar)", ggx: "scalar/D", mitsuba: "D" },
    Op { label: "D(m) (ggx: batch SoA)", ggx: "batch/D", mitsuba: "D" },
    Op { label: "visible normal (m, pdf) (ggx: scalar)", ggx: "scalar/sample_wm_vndf", mitsuba: "sample_wm_vndf" },
    BATCH_VNDF,
    Op { label: "f cos, F = 1 (ggx: batch SoA)", ggx: "batch/eval", mitsuba: "eval" },
    Op { label: "f cos, F = 1 (ggx: scalar)", ggx: "scalar/eval", mitsuba: "eval" },
    Op { label: "pdf, VNDF (ggx: batch SoA)", ggx: "batch/pdf", mitsuba: "pdf" },
    Op { label: "pdf, VNDF (ggx: scalar)", ggx: "scalar/pdf_vndf", mitsuba: "pdf" },
    Op {
        label: "BSDF sample with weight, VNDF (ggx: batch SoA, spherical caps)",
        ggx: "batch/sample",
        mitsuba: "sample",
    },
    Op { label: "BSDF sample with weight, VNDF (ggx: scalar)", ggx: "scalar/sample_vndf", mitsuba: "sample" },
];

/// The criterion filter selecting [`OPS`]' ggx benchmarks.
pub fn filter() -> String {
    let ids: Vec<String> = OPS.iter().map(|o| regex_escape(o.ggx)).collect();
    format!("^({})$", ids.join("|"))
}

/// `s` with regex metacharacters escaped.
fn regex_escape(s: &str) -> String {
    s.chars().fold(String::new(), |mut out, c| {
        if "\\.+*?()|[]{}^$".contains(c) {
            out.push('\\');
        }
        out.push(c);
        out
    })
}

/// Elements per second from criterion's `estimates.json` (median ns per iteration) and
/// `benchmark.json` (`throughput.Elements` per iteration).
pub fn per_second(estimates: &str, benchmark: &str) -> Result<f64, String> {
    let e: Value = serde_json::from_str(estimates).map_err(|e| format!("estimates.json: {e}"))?;
    let b: Value = serde_json::from_str(benchmark).map_err(|e| format!("benchmark.json: {e}"))?;
    let ns = e.pointer("/median/point_estimate").and_then(Value::as_f64).ok_or("estimates.json: no median")?;
    let elements = b.pointer("/throughput/Elements").and_then(Value::as_f64).ok_or("benchmark.json: no Elements")?;
    if !(ns > 0.0) {
        return Err(format!("estimates.json: median {ns} ns"));
    }
    Ok(elements / (ns * 1e-9))
}

/// Runs ggx-core's benchmark for [`OPS`] (`measurement` seconds each) and reads criterion's
/// results from `target/criterion`: criterion id -> elements per second.
pub fn run_ggx(measurement: u32) -> Result<BTreeMap<String, f64>, String> {
    let seconds = measurement.to_string();
    let filter = filter();
    crate::cargo(&[
        "bench",
        "-p",
        "ggx-core",
        "--bench",
        "core",
        "--",
        "--warm-up-time",
        "1",
        "--measurement-time",
        &seconds,
        "--noplot",
        &filter,
    ])?;
    let root = crate::render::workspace_root().join("target").join("criterion");
    let mut out = BTreeMap::new();
    for op in OPS {
        let dir = op.ggx.split('/').fold(root.clone(), |p, part| p.join(part)).join("new");
        let read = |name: &str| -> Result<String, String> {
            let p = dir.join(name);
            std::fs::read_to_string(&p).map_err(|e| format!("{}: {e}", p.display()))
        };
        out.insert(op.ggx.to_owned(), per_second(&read("estimates.json")?, &read("benchmark.json")?)?);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn criterion_results_are_read() {
        let e = "{\"mean\":{\"point_estimate\":2000.0},\"median\":{\"point_estimate\":1024.0}}";
        let b = "{\"group_id\":\"batch\",\"throughput\":{\"Elements\":1024}}";
        assert!((per_second(e, b).unwrap() - 1e9).abs() < 1e-3);
        assert!(per_second("{}", b).is_err());
        assert!(per_second(e, "{\"throughput\":null}").is_err());
        assert!(per_second("{\"median\":{\"point_estimate\":0}}", b).is_err());
    }

    #[test]
    fn the_filter_matches_exactly_the_rows() {
        assert!(filter().starts_with("^(scalar/D|batch/D|scalar/sample_wm_vndf|batch/sample_vndf|"), "{}", filter());
        assert!(filter().ends_with("|batch/sample|scalar/sample_vndf)$"), "{}", filter());
        assert_eq!(regex_escape("a.b(c)"), "a\\.b\\(c\\)");
    }
}
