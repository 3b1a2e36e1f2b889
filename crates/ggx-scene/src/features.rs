//! [`SceneFeatures`]: what a scene actually uses, so renderers can skip what it lacks.

use std::fmt;

/// The features a scene uses (materials count only when some shape uses them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SceneFeatures {
    /// Some shape is emissive (there are area lights for next-event estimation).
    pub area_lights: bool,
    /// The environment is an equirectangular map (file or procedural).
    pub env_map: bool,
    /// The environment is a constant radiance.
    pub constant_env: bool,
    /// Some shape uses a Lambertian material.
    pub diffuse: bool,
    /// Some shape uses a GGX conductor.
    pub conductors: bool,
    /// Some shape uses a GGX-coated plastic.
    pub plastics: bool,
    /// Some conductor has `alpha_x != alpha_y`.
    pub anisotropic: bool,
    /// Some triangle has per-vertex shading normals.
    pub shading_normals: bool,
    /// There are shapes and every one is emissive: nothing reflects light.
    pub emissive_only: bool,
    /// Some shape uses a GGX dielectric (paths can be transmitted).
    pub dielectrics: bool,
    /// Some shape uses the glTF metallic-roughness material.
    pub metal_rough: bool,
    /// Some used material reads a texture (parameters, normal map or emission).
    pub textures: bool,
    /// The scene has punctual lights (`KHR_lights_punctual`).
    pub punctual_lights: bool,
}

impl SceneFeatures {
    /// Names and values in bit order (bit 0 first).
    pub fn flags(&self) -> [(&'static str, bool); 13] {
        [
            ("area_lights", self.area_lights),
            ("env_map", self.env_map),
            ("constant_env", self.constant_env),
            ("diffuse", self.diffuse),
            ("conductors", self.conductors),
            ("plastics", self.plastics),
            ("anisotropic", self.anisotropic),
            ("shading_normals", self.shading_normals),
            ("emissive_only", self.emissive_only),
            ("dielectrics", self.dielectrics),
            ("metal_rough", self.metal_rough),
            ("textures", self.textures),
            ("punctual_lights", self.punctual_lights),
        ]
    }

    /// Bit `i` set when flag `i` of [`Self::flags`] is: area_lights = 1, env_map = 2,
    /// constant_env = 4, diffuse = 8, conductors = 16, plastics = 32, anisotropic = 64,
    /// shading_normals = 128, emissive_only = 256, dielectrics = 512, metal_rough = 1024,
    /// textures = 2048, punctual_lights = 4096. For GPU pipeline override constants.
    pub fn to_bits(&self) -> u32 {
        self.flags().iter().enumerate().fold(0, |bits, (i, (_, on))| bits | (u32::from(*on) << i))
    }

    /// Inverse of [`Self::to_bits`] (unknown bits are ignored).
    pub fn from_bits(bits: u32) -> Self {
        let b = |i: u32| bits & (1 << i) != 0;
        Self {
            area_lights: b(0),
            env_map: b(1),
            constant_env: b(2),
            diffuse: b(3),
            conductors: b(4),
            plastics: b(5),
            anisotropic: b(6),
            shading_normals: b(7),
            emissive_only: b(8),
            dielectrics: b(9),
            metal_rough: b(10),
            textures: b(11),
            punctual_lights: b(12),
        }
    }

    /// The enabled features, comma separated (`"none"` when there are none).
    pub fn summary(&self) -> String {
        let on: Vec<_> = self.flags().iter().filter(|(_, on)| *on).map(|(name, _)| *name).collect();
        if on.is_empty() { "none".to_owned() } else { on.join(", ") }
    }
}

impl fmt::Display for SceneFeatures {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.summary())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_round_trip() {
        for bits in [0, 1, 0b1_0101_0101, 0x1ff, 0x3ff, 0xfff, 0x1fff] {
            assert_eq!(SceneFeatures::from_bits(bits).to_bits(), bits);
        }
        let f = SceneFeatures { area_lights: true, conductors: true, ..Default::default() };
        assert_eq!(f.to_bits(), 17);
        assert_eq!(f.to_string(), "area_lights, conductors");
        assert_eq!(SceneFeatures::default().summary(), "none");
    }
}
