//! [`KernelVariant`]: which features a specialized kernel keeps, named the same on both
//! backends.

use ggx_scene::SceneFeatures;

/// Which features a kernel variant keeps (the others are compiled out: ggx-cpu's const
/// generics, ggx-wgpu's `override` constants).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct KernelVariant {
    /// Area lights and punctual lights (next-event estimation toward scene lights).
    pub area: bool,
    /// Environment.
    pub env: bool,
    /// Plastics.
    pub plastic: bool,
    /// Dielectrics and thin sheets (transmission, absorbing media).
    pub dielectric: bool,
    /// Textured materials (looked up at each shading point), normal maps, textured emission.
    pub textures: bool,
}

/// Every variant's name, indexed by [`KernelVariant::index`].
const NAMES: [&str; 32] = [
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
    "textures",
    "area+textures",
    "env+textures",
    "area+env+textures",
    "plastic+textures",
    "area+plastic+textures",
    "env+plastic+textures",
    "area+env+plastic+textures",
    "dielectric+textures",
    "area+dielectric+textures",
    "env+dielectric+textures",
    "area+env+dielectric+textures",
    "plastic+dielectric+textures",
    "area+plastic+dielectric+textures",
    "env+plastic+dielectric+textures",
    "area+env+plastic+dielectric+textures",
];

impl KernelVariant {
    /// The generic kernel: every feature compiled in.
    pub const ALL: KernelVariant =
        KernelVariant { area: true, env: true, plastic: true, dielectric: true, textures: true };

    /// The variant for a scene: only the features it uses, or [`Self::ALL`] when
    /// `specialize` is false. A scene with textures runs [`Self::ALL`]: textured scenes are
    /// rare enough that one kernel serves them, and the other variants stay texture-free.
    pub fn for_scene(features: &SceneFeatures, specialize: bool) -> KernelVariant {
        if !specialize || features.textures {
            return Self::ALL;
        }
        KernelVariant {
            area: features.area_lights || features.punctual_lights,
            env: features.env_map || features.constant_env,
            plastic: features.plastics,
            dielectric: features.dielectrics,
            textures: false,
        }
    }

    /// `area + 2 env + 4 plastic + 8 dielectric + 16 textures`, in `0..32`.
    pub fn index(&self) -> usize {
        usize::from(self.area)
            | usize::from(self.env) << 1
            | usize::from(self.plastic) << 2
            | usize::from(self.dielectric) << 3
            | usize::from(self.textures) << 4
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
        for i in 0..32 {
            let v = KernelVariant {
                area: i & 1 != 0,
                env: i & 2 != 0,
                plastic: i & 4 != 0,
                dielectric: i & 8 != 0,
                textures: i & 16 != 0,
            };
            assert_eq!(v.index(), i);
            let mut want: Vec<&str> = [
                (v.area, "area"),
                (v.env, "env"),
                (v.plastic, "plastic"),
                (v.dielectric, "dielectric"),
                (v.textures, "textures"),
            ]
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
        let textured = SceneFeatures { textures: true, ..glass };
        assert_eq!(KernelVariant::for_scene(&textured, true), KernelVariant::ALL);
    }
}
