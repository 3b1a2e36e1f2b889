//! `--accel`: the BVH kinds of ggx-cpu.

use std::time::Duration;

use ggx_cpu::AccelKind;

use crate::args::AccelArg;

/// The renderer's kind for `accel`.
pub fn kind(accel: AccelArg) -> AccelKind {
    match accel {
        AccelArg::Wide => AccelKind::Wide,
        AccelArg::Cwbvh => AccelKind::Cwbvh,
        AccelArg::Bvh2 => AccelKind::Bvh2,
    }
}

/// The `--accel` spelling.
pub fn name(accel: AccelArg) -> &'static str {
    match accel {
        AccelArg::Wide => "wide",
        AccelArg::Cwbvh => "cwbvh",
        AccelArg::Bvh2 => "bvh2",
    }
}

/// A build time as `1.23 ms` or `4.56 s`.
pub fn format_build_time(t: Duration) -> String {
    let secs = t.as_secs_f64();
    if secs < 1.0 { format!("{:.2} ms", secs * 1e3) } else { format!("{secs:.2} s") }
}
