//! Textured materials at a shading point: the glTF metallic-roughness parameters read from
//! their textures, the normal map's perturbed normal and the textured emission. The CPU
//! kernels call these; `path_tracer.wgsl` mirrors them function by function.

use ggx_core::{GltfMetalRough, Sampling};
use ggx_scene::{MetalRough, TextureSet, TriangleTangents, TriangleUvs};
use glam::{Vec2, Vec3};

use crate::bsdf::Bsdf;

/// The metallic-roughness BRDF of `m` at texture coordinates `uv`: each factor times its
/// texture (glTF 2.0 spec 3.9.2: base colour RGB, roughness G, metallic B), `alpha =
/// roughness^2`; with anisotropy, `alpha_x = mix(alpha, 1, strength^2)` along the shading
/// frame's tangent (`KHR_materials_anisotropy`; the caller turns the frame).
#[inline]
pub fn metal_rough_at(m: &MetalRough, textures: &TextureSet, uv: Vec2) -> GltfMetalRough {
    let mut base = m.base_color;
    if m.base_color_texture.is_some() {
        base *= textures.sample(&m.base_color_texture, uv).truncate();
    }
    let mut metallic = m.metallic;
    if m.metallic_texture.is_some() {
        metallic *= textures.sample_channel(&m.metallic_texture, uv);
    }
    let mut roughness = m.roughness;
    if m.roughness_texture.is_some() {
        roughness *= textures.sample_channel(&m.roughness_texture, uv);
    }
    let alpha = roughness * roughness;
    // KHR_materials_anisotropy: alpha_t = mix(alpha, 1, strength^2) along the direction.
    let s2 = m.anisotropy * m.anisotropy;
    let alpha_t = alpha + (1.0 - alpha) * s2;
    GltfMetalRough::new(base, metallic, alpha_t, alpha, m.ior, m.specular_color, m.specular)
}

/// [`metal_rough_at`] as a ggx-render [`Bsdf`], under `m`'s clear coat when it has one
/// ([`Bsdf::metal_rough`]).
#[inline]
pub fn metal_rough_bsdf(m: &MetalRough, textures: &TextureSet, uv: Vec2, sampling: Sampling) -> Bsdf {
    Bsdf::metal_rough(metal_rough_at(m, textures, uv), m.clearcoat, m.clearcoat_roughness, sampling)
}

/// The normal map's tangent-space normal at `uv`: `normalize((2 rgb - 1) (scale, scale, 1))`
/// (glTF 2.0 spec 3.9.3), `None` without a normal map or when the texel decodes to zero.
#[inline]
pub fn normal_map_at(m: &MetalRough, textures: &TextureSet, uv: Vec2) -> Option<Vec3> {
    if !m.normal_texture.is_some() {
        return None;
    }
    let t = textures.sample(&m.normal_texture, uv).truncate() * 2.0 - Vec3::ONE;
    let n = (t * Vec3::new(m.normal_scale, m.normal_scale, 1.0)).normalize_or_zero();
    if n == Vec3::ZERO { None } else { Some(n) }
}

/// Emitted radiance of `m` at `uv`: the factor times the sRGB emission texture.
#[inline]
pub fn emission_at(m: &MetalRough, textures: &TextureSet, uv: Vec2) -> Vec3 {
    if m.emission_texture.is_some() {
        m.emission * textures.sample(&m.emission_texture, uv).truncate()
    } else {
        m.emission
    }
}

/// The tangent at barycentrics `(b1, b2)` and the bitangent's sign `w` (`B = w (n x T)`): the
/// mesh's tangent (glTF's TANGENT), interpolated, or `dp/du` of the triangle with the sign
/// that makes `B` follow `-dp/dv` (glTF's `v` runs down the image, a normal map's +Y up).
/// `None` when the coordinates are degenerate. Not yet orthogonal to any normal.
#[inline]
pub fn tangent_at(
    n: Vec3,
    vertices: [Vec3; 3],
    uvs: &TriangleUvs,
    tangents: Option<&TriangleTangents>,
    b1: f32,
    b2: f32,
) -> Option<(Vec3, f32)> {
    match tangents.filter(|t| t.tangents[0][3] != 0.0) {
        Some(tg) => {
            let v = |i: usize| Vec3::new(tg.tangents[i][0], tg.tangents[i][1], tg.tangents[i][2]);
            let t = (1.0 - b1 - b2) * v(0) + b1 * v(1) + b2 * v(2);
            Some((t, if tg.tangents[0][3] < 0.0 { -1.0 } else { 1.0 }))
        }
        None => {
            let (dp1, dp2) = (vertices[1] - vertices[0], vertices[2] - vertices[0]);
            let (d1, d2) = (uvs.at(1) - uvs.at(0), uvs.at(2) - uvs.at(0));
            let det = d1.x * d2.y - d2.x * d1.y;
            if !(det.abs() > 1e-20) {
                return None;
            }
            let dpdu = (dp1 * d2.y - dp2 * d1.y) / det;
            let dpdv = (dp2 * d1.x - dp1 * d2.x) / det;
            let w = if n.cross(dpdu).dot(-dpdv) < 0.0 { -1.0 } else { 1.0 };
            Some((dpdu, w))
        }
    }
}

/// The orthonormal tangent frame `(T, B)` around the unit normal `n` from [`tangent_at`]'s
/// tangent `t` and sign `w`: `T` is `t` made orthogonal to `n`, `B = w (n x T)`.
#[inline]
pub fn tangent_frame(n: Vec3, t: Vec3, w: f32) -> Option<(Vec3, Vec3)> {
    let t = (t - n * n.dot(t)).normalize_or_zero();
    if t == Vec3::ZERO || !t.is_finite() {
        return None;
    }
    Some((t, n.cross(t) * w))
}

/// `n` bent by the tangent-space normal `nt`: `normalize(nt.x T + nt.y B + nt.z n)` in the
/// [`tangent_frame`] of [`tangent_at`]; `n` unchanged when no tangent can be found.
#[inline]
pub fn perturb_normal(
    n: Vec3,
    nt: Vec3,
    vertices: [Vec3; 3],
    uvs: &TriangleUvs,
    tangents: Option<&TriangleTangents>,
    b1: f32,
    b2: f32,
) -> Vec3 {
    let Some((t, w)) = tangent_at(n, vertices, uvs, tangents, b1, b2) else { return n };
    let Some((t, b)) = tangent_frame(n, t, w) else { return n };
    let bent = (t * nt.x + b * nt.y + n * nt.z).normalize_or_zero();
    if bent == Vec3::ZERO || !bent.is_finite() { n } else { bent }
}

/// `KHR_materials_anisotropy`'s direction: the tangent frame's `T` turned by `rotation`
/// radians toward `B` (`cos r T + sin r B`), the GGX `alpha_x` axis.
#[inline]
pub fn anisotropy_direction(t: Vec3, b: Vec3, rotation: f32) -> Vec3 {
    let (s, c) = rotation.sin_cos();
    (t * c + b * s).normalize_or_zero()
}

#[cfg(test)]
mod tests {
    use super::*;
    use ggx_scene::{Texels, TextureRef};

    fn quad_uvs() -> TriangleUvs {
        // A triangle in the xy plane facing +z: u along +x, v down the image (along -y).
        TriangleUvs::new([Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 0.0)])
    }

    const TRI: [Vec3; 3] = [Vec3::ZERO, Vec3::X, Vec3::Y];

    #[test]
    fn flat_normal_map_changes_nothing_and_green_tilts_toward_image_up() {
        let n = Vec3::Z;
        assert_eq!(perturb_normal(n, Vec3::Z, TRI, &quad_uvs(), None, 0.2, 0.2), n);
        // +Y in the map is up in the image: +y in the world here.
        let bent = perturb_normal(n, Vec3::new(0.0, 0.6, 0.8), TRI, &quad_uvs(), None, 0.2, 0.2);
        assert!((bent - Vec3::new(0.0, 0.6, 0.8)).length() < 1e-6, "{bent}");
        let bent = perturb_normal(n, Vec3::new(0.6, 0.0, 0.8), TRI, &quad_uvs(), None, 0.2, 0.2);
        assert!((bent - Vec3::new(0.6, 0.0, 0.8)).length() < 1e-6, "{bent}");
        // Mirrored u: +x in the map now points to -x, +y still up.
        let mirrored = TriangleUvs::new([Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0), Vec2::new(1.0, 0.0)]);
        let bent = perturb_normal(n, Vec3::new(0.6, 0.0, 0.8), TRI, &mirrored, None, 0.2, 0.2);
        assert!((bent - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-6, "{bent}");
        let bent = perturb_normal(n, Vec3::new(0.0, 0.6, 0.8), TRI, &mirrored, None, 0.2, 0.2);
        assert!((bent - Vec3::new(0.0, 0.6, 0.8)).length() < 1e-6, "{bent}");
        // The mesh's tangents win: T = +y, w = -1 -> B = -(z x y) = +x.
        let tg = TriangleTangents::new([glam::Vec4::new(0.0, 1.0, 0.0, -1.0); 3]);
        let bent = perturb_normal(n, Vec3::new(0.0, 0.6, 0.8), TRI, &quad_uvs(), Some(&tg), 0.2, 0.2);
        assert!((bent - Vec3::new(0.6, 0.0, 0.8)).length() < 1e-6, "{bent}");
        // Degenerate coordinates: unchanged.
        let flat = TriangleUvs::new([Vec2::ZERO; 3]);
        assert_eq!(perturb_normal(n, Vec3::new(0.6, 0.0, 0.8), TRI, &flat, None, 0.2, 0.2), n);
    }

    #[test]
    fn anisotropy_turns_the_tangent_and_widens_alpha_along_it() {
        let d = anisotropy_direction(Vec3::X, Vec3::Y, std::f32::consts::FRAC_PI_2);
        assert!((d - Vec3::Y).length() < 1e-6, "{d}");
        let m = MetalRough { roughness: 0.5, anisotropy: 0.5, ..MetalRough::default() };
        let b = metal_rough_at(&m, &TextureSet::default(), Vec2::ZERO);
        // alpha = 0.25; alpha_t = 0.25 + 0.75 * 0.25.
        assert_eq!(b, GltfMetalRough::new(Vec3::ONE, 1.0, 0.4375, 0.25, 1.5, Vec3::ONE, 1.0));
    }

    #[test]
    fn factors_multiply_textures_channel_by_channel() {
        let mut set = TextureSet::default();
        // R 255, G 128 (roughness), B 64 (metallic), A 255.
        let t = set.push(1, 1, &Texels::Rgba8(vec![0xff40_80ff]), 0).unwrap();
        let m = MetalRough {
            base_color: Vec3::new(0.5, 1.0, 1.0),
            base_color_texture: TextureRef::new(t, 0, true),
            metallic: 0.5,
            metallic_texture: TextureRef::new(t, 2, false),
            roughness: 1.0,
            roughness_texture: TextureRef::new(t, 1, false),
            ..MetalRough::default()
        };
        let b = metal_rough_at(&m, &set, Vec2::ZERO);
        let r = 128.0f32 / 255.0;
        let expected = GltfMetalRough::new(
            Vec3::new(0.5, ggx_scene::srgb_to_linear(128), ggx_scene::srgb_to_linear(64)),
            0.5 * 64.0 / 255.0,
            r * r,
            r * r,
            1.5,
            Vec3::ONE,
            1.0,
        );
        assert_eq!(b, expected);
        assert_eq!(normal_map_at(&m, &set, Vec2::ZERO), None);
        assert_eq!(emission_at(&MetalRough { emission: Vec3::ONE, ..m }, &set, Vec2::ZERO), Vec3::ONE);
    }

    #[test]
    fn a_clear_coat_goes_over_the_textured_base_with_alpha_roughness_squared() {
        let mut set = TextureSet::default();
        let t = set.push(1, 1, &Texels::Rgba8(vec![0xff40_80ff]), 0).unwrap();
        let m = MetalRough {
            base_color_texture: TextureRef::new(t, 0, true),
            clearcoat: 0.75,
            clearcoat_roughness: 0.5,
            ..MetalRough::default()
        };
        let base = metal_rough_at(&m, &set, Vec2::ZERO);
        let Bsdf::Clearcoat { brdf, sampling } = metal_rough_bsdf(&m, &set, Vec2::ZERO, Sampling::Bounded) else {
            panic!("a coated material is a Bsdf::Clearcoat");
        };
        assert_eq!((brdf, sampling), (ggx_core::GltfClearcoat::new(base, 0.75, 0.25), Sampling::Bounded));
        // The untextured path builds the same BSDF.
        let untextured = ggx_scene::Material::MetalRough(MetalRough { base_color_texture: TextureRef::NONE, ..m });
        let Bsdf::Clearcoat { brdf: plain, .. } = Bsdf::new(&untextured, ggx_scene::BsdfStrategy::Vndf) else {
            panic!("a coated material is a Bsdf::Clearcoat");
        };
        let white = GltfMetalRough::new(Vec3::ONE, 1.0, 1.0, 1.0, 1.5, Vec3::ONE, 1.0);
        assert_eq!(plain, ggx_core::GltfClearcoat::new(white, 0.75, 0.25));
        // No coat: the metal-rough BSDF itself.
        let bare = MetalRough { clearcoat: 0.0, ..m };
        assert!(
            matches!(metal_rough_bsdf(&bare, &set, Vec2::ZERO, Sampling::Vndf), Bsdf::MetalRough { brdf, .. } if brdf == base)
        );
    }
}
