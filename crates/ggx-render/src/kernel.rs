//! [`KernelVariant`]: which features a specialized kernel keeps, named the same on both
//! backends.

use ggx_scene::SceneFeatures;

/// Which features a kernel variant keeps (the others are compiled out: ggx-cpu's const
/// generics, ggx-wgpu's `override` constants).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct KernelVariant {
    /// Area lights.
    pub area: bool,
    /// Environment.
    pub env: bool,
    /// Plastics.
    pub plastic: bool,
    /// Dielectrics and thin sheets (transmission, absorbing media).
    pub dielectric: bool,
}

/// Every variant's name, indexed by [`KernelVariant::index`].
const NAMES: [&str; 16] = [
    "none",
    "area",
    "env",
    "area+env",
    "plastic",
    "area+plastic",
    "env+plastic",
    "area+env+plastic",
    "dielectric",
    "area+dielectric",
    "env+dielectric",
    "area+env+dielectric",
    "plastic+dielectric",
    "area+plastic+dielectric",
    "env+plastic+dielectric",
    "area+env+plastic+dielectric",
];

impl KernelVariant {
    /// The generic kernel: every feature compiled in.
    pub const ALL: KernelVariant = KernelVariant { area: true, env: true, plastic: true, dielectric: true };

    /// The variant for a scene: only the features it uses, or [`Self::ALL`] when
    /// `specialize` is false.
    pub fn for_scene(features: &SceneFeatures, specialize: bool) -> KernelVariant {
        if !specialize {
            return Self::ALL;
        }
        KernelVariant {
            area: features.area_lights,
            env: features.env_map || features.constant_env,
            plastic: features.plastics,
            dielectric: features.dielectrics,
        }
    }

    /// `area + 2 env + 4 plastic + 8 dielectric`, in `0..16`.
    pub fn index(&self) -> usize {
        usize::from(self.area)
            | usize::from(self.env) << 1
            | usize::from(self.plastic) << 2
            | usize::from(self.dielectric) << 3
    }

    /// The name, its features joined by `+` (`"area+env"`, `"none"`).
    pub fn name(&self) -> &'static str {
        NAMES[self.index()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_list_the_features() {
        for i in 0..16 {
            let v = KernelVariant { area: i & 1 != 0, env: i & 2 != 0, plastic: i & 4 != 0, dielectric: i & 8 != 0 };
            assert_eq!(v.index(), i);
            let mut want: Vec<&str> =
                [(v.area, "area"), (v.env, "env"), (v.plastic, "plastic"), (v.dielectric, "dielectric")]
                    .iter()
                    .filter(|(on, _)| *on)
                    .map(|(_, n)| *n)
                    .collect();
            if want.is_empty() {
                want.push("none");
            }
            assert_eq!(v.name(), want.join("+"));
        }
        assert_eq!(KernelVariant::for_scene(&SceneFeatures::default(), false), KernelVariant::ALL);
        let glass = SceneFeatures { dielectrics: true, constant_env: true, ..Default::default() };
        assert_eq!(KernelVariant::for_scene(&glass, true).name(), "env+dielectric");
    }
}
