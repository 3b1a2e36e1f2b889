//! The choice of sampling technique for [`crate::GgxConductor`].

/// How [`crate::GgxConductor::sample`] draws directions, and which density
/// [`crate::GgxConductor::pdf`] returns. `#[repr(u32)]` so it uploads to a GPU as is.
#[repr(u32)]
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(not(target_arch = "spirv"), derive(Debug))]
pub enum Sampling {
    /// Normals from `D(wm) wm.z` (Walter et al. 2007).
    Ndf = 0,
    /// Visible normals, Heitz 2018.
    Vndf = 1,
    /// Visible normals with spherical caps, Dupuy & Benyoub 2023 (same density as `Vndf`).
    SphericalCaps = 2,
    /// Bounded visible normals for reflection, Eto & Tokuyoshi 2023.
    Bounded = 3,
    /// Cosine-weighted hemisphere (baseline that ignores the BRDF).
    Cosine = 4,
    /// Uniform hemisphere (baseline).
    Uniform = 5,
}

impl Sampling {
    /// Every technique, in discriminant order.
    pub const ALL: [Sampling; 6] = [
        Sampling::Ndf,
        Sampling::Vndf,
        Sampling::SphericalCaps,
        Sampling::Bounded,
        Sampling::Cosine,
        Sampling::Uniform,
    ];

    /// The four microfacet-normal samplers.
    pub const MICROFACET: [Sampling; 4] = [Sampling::Ndf, Sampling::Vndf, Sampling::SphericalCaps, Sampling::Bounded];

    /// Technique for a GPU-side `u32`; unknown values map to `Vndf`.
    #[inline]
    pub fn from_u32(v: u32) -> Sampling {
        match v {
            0 => Sampling::Ndf,
            2 => Sampling::SphericalCaps,
            3 => Sampling::Bounded,
            4 => Sampling::Cosine,
            5 => Sampling::Uniform,
            _ => Sampling::Vndf,
        }
    }

    /// Short lowercase name (`"ndf"`, `"vndf"`, `"spherical-caps"`, `"bounded"`, `"cosine"`, `"uniform"`).
    pub fn name(self) -> &'static str {
        match self {
            Sampling::Ndf => "ndf",
            Sampling::Vndf => "vndf",
            Sampling::SphericalCaps => "spherical-caps",
            Sampling::Bounded => "bounded",
            Sampling::Cosine => "cosine",
            Sampling::Uniform => "uniform",
        }
    }
}
