//! `--max-*`: the [`Limits`] on what is read and allocated, raised or lowered per run.

use std::fmt;
use std::str::FromStr;

use clap::Args;
use ggx_scene::Limits;

/// A byte count written with an optional binary suffix: `512`, `64K`, `64M`, `16G`, `1T`
/// (`KiB`, `MB`, … are accepted too; every unit is a power of 1024).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ByteSize(pub u64);

impl FromStr for ByteSize {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let t = s.trim();
        let digits = t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len());
        let (number, unit) = t.split_at(digits);
        if number.is_empty() {
            return Err(format!("not a whole number of bytes: {s:?}"));
        }
        let shift = match unit.trim().to_ascii_uppercase().as_str() {
            "" | "B" => 0,
            "K" | "KB" | "KIB" => 10,
            "M" | "MB" | "MIB" => 20,
            "G" | "GB" | "GIB" => 30,
            "T" | "TB" | "TIB" => 40,
            _ => return Err(format!("unknown unit in {s:?} (use a whole number with K, M, G or T)")),
        };
        let n: u64 = number.parse().map_err(|_| format!("not a whole number of bytes: {s:?}"))?;
        n.checked_mul(1 << shift).map(ByteSize).ok_or_else(|| format!("{s} is more than 2^64 bytes"))
    }
}

impl fmt::Display for ByteSize {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let units = [(40, "T"), (30, "G"), (20, "M"), (10, "K")];
        match units.iter().find(|(shift, _)| self.0 != 0 && self.0.is_multiple_of(1u64 << shift)) {
            Some((shift, unit)) => write!(f, "{}{unit}", self.0 >> shift),
            None => write!(f, "{}", self.0),
        }
    }
}

/// The `--max-*` options shared by `ggx render` and `ggx info`.
#[derive(Clone, Copy, Debug, Args)]
pub struct LimitArgs {
    /// Largest scene file read.
    #[arg(long, value_name = "BYTES", default_value_t = ByteSize(Limits::default().max_scene_bytes))]
    pub max_scene_bytes: ByteSize,

    /// Largest mesh (OBJ) file read.
    #[arg(long, value_name = "BYTES", default_value_t = ByteSize(Limits::default().max_mesh_bytes))]
    pub max_mesh_bytes: ByteSize,

    /// Largest environment map decoded, in pixels (width x height).
    #[arg(long, value_name = "PIXELS", default_value_t = Limits::default().max_map_pixels)]
    pub max_map_pixels: u64,

    /// Most triangles after tessellation.
    #[arg(long, value_name = "N", default_value_t = Limits::default().max_triangles)]
    pub max_triangles: u64,

    /// Most memory that loading and rendering may need (meshes, BVH, maps, film), estimated
    /// before it is allocated; `ggx info` prints the estimate.
    #[arg(long, value_name = "BYTES", default_value_t = ByteSize(Limits::default().max_memory))]
    pub max_memory: ByteSize,
}

impl LimitArgs {
    /// The limits these options give.
    pub fn limits(&self) -> Limits {
        Limits {
            max_scene_bytes: self.max_scene_bytes.0,
            max_mesh_bytes: self.max_mesh_bytes.0,
            max_map_pixels: self.max_map_pixels,
            max_triangles: self.max_triangles,
            max_memory: self.max_memory.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_units() {
        let parse = |s: &str| s.parse::<ByteSize>().map(|b| b.0);
        assert_eq!(parse("512"), Ok(512));
        assert_eq!(parse("64K"), Ok(64 << 10));
        assert_eq!(parse("16G"), Ok(16 << 30));
        assert_eq!(parse("3 GiB"), Ok(3 << 30));
        assert_eq!(parse("2mb"), Ok(2 << 20));
        assert!(parse("1.5G").unwrap_err().contains("unknown unit"));
        assert!(parse("-1").unwrap_err().contains("not a whole number"));
        assert!(parse("99999999T").unwrap_err().contains("2^64"));
        assert!(parse("G").unwrap_err().contains("not a whole number"));
    }

    #[test]
    fn sizes_print_in_the_largest_exact_unit() {
        assert_eq!(ByteSize(64 << 20).to_string(), "64M");
        assert_eq!(ByteSize(16 << 30).to_string(), "16G");
        assert_eq!(ByteSize(1536).to_string(), "1536");
        assert_eq!(ByteSize(0).to_string(), "0");
        for b in [0, 1, 1024, 1 << 40, 3 << 20, 1025] {
            assert_eq!(ByteSize(b).to_string().parse::<ByteSize>(), Ok(ByteSize(b)));
        }
    }
}
