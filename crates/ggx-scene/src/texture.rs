//! Image textures: every texture of a scene in one flat `u32` table ([`TextureSet`], uploaded
//! to the GPU as it is), references from material slots ([`TextureRef`]: texture, channel,
//! sRGB decoding, UV transform), and the lookup both renderers perform ([`TextureSet::sample`]:
//! wrap, bilinear or nearest filter, sRGB to linear after the fetch and before the filter).
//!
//! 8-bit images stay 8-bit (one packed RGBA `u32` per texel); 16-bit and float images
//! (PNG 16, HDR, EXR) are kept as four `f32` per texel. The first [`SRGB_LUT_WORDS`] words of
//! the table are the sRGB decoding table, so the GPU decodes with the same numbers.

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec4};

use crate::mesh::NO_INDEX;

/// Words at the start of [`TextureSet::words`] that hold the sRGB-to-linear table (256 `f32`).
pub const SRGB_LUT_WORDS: u32 = 256;
/// [`TextureInfo::flags`]: four `f32` words per texel (else one packed RGBA8 word).
pub const TEXTURE_FLOAT: u32 = 1;
/// [`TextureInfo::flags`]: nearest-texel filter (else bilinear).
pub const TEXTURE_NEAREST: u32 = 2;
/// [`TextureInfo::flags`]: shift of the 2-bit S wrap mode ([`Wrap`]).
pub const TEXTURE_WRAP_S_SHIFT: u32 = 2;
/// [`TextureInfo::flags`]: shift of the 2-bit T wrap mode ([`Wrap`]).
pub const TEXTURE_WRAP_T_SHIFT: u32 = 4;
/// [`TextureRef::flags`]: decode R, G, B from sRGB (colour data; alpha and data stay linear).
pub const REF_SRGB: u32 = 1;
/// [`TextureRef::flags`]: shift of the 2-bit channel a scalar slot reads (0 R, 1 G, 2 B, 3 A).
pub const REF_CHANNEL_SHIFT: u32 = 1;

/// Texture coordinate wrap modes (glTF samplers, OpenGL's names).
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Wrap {
    /// `fract(s)`: the texture tiles.
    #[default]
    Repeat = 0,
    /// `clamp(s, 0, 1)`: the edge texels extend.
    ClampToEdge = 1,
    /// The texture tiles, every other copy mirrored.
    MirroredRepeat = 2,
}

impl Wrap {
    /// The mode of a 2-bit field (3 reads as [`Wrap::Repeat`]).
    pub fn from_bits(bits: u32) -> Wrap {
        match bits & 3 {
            1 => Wrap::ClampToEdge,
            2 => Wrap::MirroredRepeat,
            _ => Wrap::Repeat,
        }
    }
}

/// One texture of a [`TextureSet`], 16 bytes (WGSL `TextureInfo`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct TextureInfo {
    /// First word of the texels in [`TextureSet::words`].
    pub offset: u32,
    /// Width in texels, >= 1.
    pub width: u32,
    /// Height in texels, >= 1.
    pub height: u32,
    /// [`TEXTURE_FLOAT`], [`TEXTURE_NEAREST`] and the wrap modes.
    pub flags: u32,
}

/// A material slot's texture: which texture, which channel, sRGB or linear, and the
/// `KHR_texture_transform` of its coordinates, 32 bytes (WGSL `TextureRef`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct TextureRef {
    /// Index into [`TextureSet::infos`], [`NO_INDEX`] for none.
    pub texture: u32,
    /// [`REF_SRGB`] and the channel ([`REF_CHANNEL_SHIFT`]).
    pub flags: u32,
    /// Row-major 2x3 affine map of `(u, v, 1)`: `s = m0 u + m1 v + m2`, `t = m3 u + m4 v + m5`.
    pub transform: [f32; 6],
}

impl TextureRef {
    /// The identity transform.
    pub const IDENTITY: [f32; 6] = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    /// No texture.
    pub const NONE: TextureRef = TextureRef { texture: NO_INDEX, flags: 0, transform: Self::IDENTITY };

    /// Texture `texture`, reading `channel` (0..=3) for scalars, sRGB-decoded when `srgb`.
    pub fn new(texture: u32, channel: u32, srgb: bool) -> TextureRef {
        TextureRef { texture, flags: u32::from(srgb) | ((channel & 3) << REF_CHANNEL_SHIFT), ..Self::NONE }
    }

    /// True when a texture is set.
    pub fn is_some(&self) -> bool {
        self.texture != NO_INDEX
    }

    /// The channel a scalar slot reads (0 R, 1 G, 2 B, 3 A).
    pub fn channel(&self) -> usize {
        ((self.flags >> REF_CHANNEL_SHIFT) & 3) as usize
    }

    /// `KHR_texture_transform`: `T(offset) R(rotation) S(scale)` applied to `(u, v)`, the
    /// extension's GLSL (`s = cos u sx - sin v sy + ox`, `t = sin u sx + cos v sy + oy`).
    pub fn with_transform(mut self, offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> TextureRef {
        let (s, c) = rotation.sin_cos();
        self.transform =
            [c * scale[0], -s * scale[1], offset[0], s * scale[0], c * scale[1], offset[1]].map(finite_or_zero);
        self
    }

    /// The transformed coordinates `(s, t)` of `uv`.
    #[inline]
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let m = self.transform;
        Vec2::new(m[0] * uv.x + m[1] * uv.y + m[2], m[3] * uv.x + m[4] * uv.y + m[5])
    }
}

fn finite_or_zero(x: f32) -> f32 {
    if x.is_finite() { x } else { 0.0 }
}

/// sRGB electro-optical transfer function (IEC 61966-2-1): `c / 12.92` below 0.04045, else
/// `((c + 0.055) / 1.055)^2.4`, for an 8-bit code `i`, computed in `f64`.
pub fn srgb_to_linear(i: u8) -> f32 {
    let c = f64::from(i) / 255.0;
    (if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }) as f32
}

/// Every texture of a scene: the infos and one word table (sRGB table first, then texels).
#[derive(Clone, Debug, PartialEq)]
pub struct TextureSet {
    /// One entry per texture.
    pub infos: Vec<TextureInfo>,
    /// [`SRGB_LUT_WORDS`] `f32` bit patterns, then every texture's texels.
    pub words: Vec<u32>,
}

impl Default for TextureSet {
    fn default() -> Self {
        Self { infos: Vec::new(), words: (0..=255u8).map(|i| srgb_to_linear(i).to_bits()).collect() }
    }
}

/// Decoded texels of one image, before they join a [`TextureSet`].
#[derive(Clone, Debug, PartialEq)]
pub enum Texels {
    /// Packed RGBA8 (`r | g << 8 | b << 16 | a << 24`), row-major from the top row.
    Rgba8(Vec<u32>),
    /// RGBA `f32`, row-major from the top row.
    RgbaF32(Vec<[f32; 4]>),
}

impl Texels {
    /// Number of texels.
    pub fn len(&self) -> usize {
        match self {
            Texels::Rgba8(t) => t.len(),
            Texels::RgbaF32(t) => t.len(),
        }
    }

    /// True when there are no texels.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Words the texels take in a [`TextureSet`].
    pub fn words(&self) -> u64 {
        match self {
            Texels::Rgba8(t) => t.len() as u64,
            Texels::RgbaF32(t) => 4 * t.len() as u64,
        }
    }
}

impl TextureSet {
    /// True when there is no texture.
    pub fn is_empty(&self) -> bool {
        self.infos.is_empty()
    }

    /// Bytes the table holds.
    pub fn bytes(&self) -> u64 {
        (self.words.len() as u64 * 4).saturating_add(self.infos.len() as u64 * 16)
    }

    /// Appends a `width x height` image with `flags` (filter and wrap; [`TEXTURE_FLOAT`] is
    /// set from the texels) and returns its index. `None` when the sizes disagree or the
    /// table would pass `u32::MAX` words.
    pub fn push(&mut self, width: u32, height: u32, texels: &Texels, flags: u32) -> Option<u32> {
        if width == 0 || height == 0 || texels.len() as u64 != u64::from(width) * u64::from(height) {
            return None;
        }
        let offset = u32::try_from(self.words.len()).ok()?;
        let end = u64::from(offset) + texels.words();
        if end > u64::from(u32::MAX) {
            return None;
        }
        let flags = flags & !TEXTURE_FLOAT;
        let flags = match texels {
            Texels::Rgba8(t) => {
                self.words.extend_from_slice(t);
                flags
            }
            Texels::RgbaF32(t) => {
                self.words.extend(t.iter().flat_map(|p| p.map(f32::to_bits)));
                flags | TEXTURE_FLOAT
            }
        };
        let index = u32::try_from(self.infos.len()).ok()?;
        self.infos.push(TextureInfo { offset, width, height, flags });
        Some(index)
    }

    /// A texture sharing the texels of `texture` with other `flags` (another sampler).
    pub fn alias(&mut self, texture: u32, flags: u32) -> Option<u32> {
        let info = *self.infos.get(texture as usize)?;
        let index = u32::try_from(self.infos.len()).ok()?;
        self.infos.push(TextureInfo { flags: (info.flags & TEXTURE_FLOAT) | (flags & !TEXTURE_FLOAT), ..info });
        Some(index)
    }

    /// Texel `(x, y)` of `info` (in range) in linear RGBA: 8-bit channels `/ 255`, R, G, B
    /// through the sRGB table when `srgb`.
    #[inline]
    fn texel(&self, info: &TextureInfo, x: u32, y: u32, srgb: bool) -> Vec4 {
        let i = u64::from(y) * u64::from(info.width) + u64::from(x);
        let word = |k: u64| self.words.get((u64::from(info.offset) + k) as usize).copied().unwrap_or(0);
        if info.flags & TEXTURE_FLOAT != 0 {
            let v = Vec4::new(
                f32::from_bits(word(4 * i)),
                f32::from_bits(word(4 * i + 1)),
                f32::from_bits(word(4 * i + 2)),
                f32::from_bits(word(4 * i + 3)),
            );
            return if v.is_finite() { v } else { Vec4::ZERO };
        }
        let w = word(i);
        let c = |shift: u32| (w >> shift) & 255;
        let lin = |b: u32| {
            if srgb { f32::from_bits(self.words.get(b as usize).copied().unwrap_or(0)) } else { b as f32 / 255.0 }
        };
        Vec4::new(lin(c(0)), lin(c(8)), lin(c(16)), c(24) as f32 / 255.0)
    }

    /// Filtered linear RGBA of `r` at mesh coordinates `uv`: transform, wrap, then bilinear
    /// (texel centres at half-integers) or nearest. No texture or NaN coordinates: the
    /// lookup still returns finite values (zero for a missing texture).
    pub fn sample(&self, r: &TextureRef, uv: Vec2) -> Vec4 {
        let Some(info) = self.infos.get(r.texture as usize) else { return Vec4::ZERO };
        let st = r.apply(uv);
        let srgb = r.flags & REF_SRGB != 0;
        let s = wrap_coord(st.x, Wrap::from_bits(info.flags >> TEXTURE_WRAP_S_SHIFT));
        let t = wrap_coord(st.y, Wrap::from_bits(info.flags >> TEXTURE_WRAP_T_SHIFT));
        let (w, h) = (info.width, info.height);
        if info.flags & TEXTURE_NEAREST != 0 {
            let x = texel_index(s * w as f32, w);
            let y = texel_index(t * h as f32, h);
            return self.texel(info, x, y, srgb);
        }
        let x = s * w as f32 - 0.5;
        let y = t * h as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let wrap_s = Wrap::from_bits(info.flags >> TEXTURE_WRAP_S_SHIFT);
        let wrap_t = Wrap::from_bits(info.flags >> TEXTURE_WRAP_T_SHIFT);
        let (xa, xb) = (neighbour(x0, w, wrap_s), neighbour(x0 + 1.0, w, wrap_s));
        let (ya, yb) = (neighbour(y0, h, wrap_t), neighbour(y0 + 1.0, h, wrap_t));
        let top = self.texel(info, xa, ya, srgb) * (1.0 - fx) + self.texel(info, xb, ya, srgb) * fx;
        let bottom = self.texel(info, xa, yb, srgb) * (1.0 - fx) + self.texel(info, xb, yb, srgb) * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// One channel of [`Self::sample`] (the slot's [`TextureRef::channel`]).
    pub fn sample_channel(&self, r: &TextureRef, uv: Vec2) -> f32 {
        self.sample(r, uv)[r.channel()]
    }
}

/// A coordinate reduced to one period of the wrap mode: `[0, 1)` for repeat, `[0, 1]` for
/// clamp, `[0, 1]` mirrored for mirrored repeat; NaN and infinities become 0.
#[inline]
pub fn wrap_coord(s: f32, wrap: Wrap) -> f32 {
    let s = if s.is_finite() { s } else { 0.0 };
    match wrap {
        Wrap::Repeat => s - s.floor(),
        Wrap::ClampToEdge => s.max(0.0).min(1.0),
        Wrap::MirroredRepeat => {
            let p = s * 0.5;
            let f = 2.0 * (p - p.floor());
            if f > 1.0 { 2.0 - f } else { f }
        }
    }
}

/// Integer texel of a coordinate already in `[0, n]`: `floor`, at most `n - 1`.
#[inline]
fn texel_index(x: f32, n: u32) -> u32 {
    (x.max(0.0) as u32).min(n - 1)
}

/// The texel a bilinear tap at `i` (within one texel of `[0, n)`) reads: wrapped around for
/// repeat, reflected for mirrored repeat, clamped for clamp-to-edge.
#[inline]
fn neighbour(i: f32, n: u32, wrap: Wrap) -> u32 {
    let nf = n as f32;
    let j = match wrap {
        Wrap::Repeat if i < 0.0 => i + nf,
        Wrap::Repeat if i >= nf => i - nf,
        Wrap::MirroredRepeat if i < 0.0 => -1.0 - i,
        Wrap::MirroredRepeat if i >= nf => 2.0 * nf - 1.0 - i,
        _ => i,
    };
    texel_index(j, n)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgba(r: u8, g: u8, b: u8, a: u8) -> u32 {
        u32::from(r) | u32::from(g) << 8 | u32::from(b) << 16 | u32::from(a) << 24
    }

    #[test]
    fn srgb_table_matches_the_standard() {
        assert_eq!(srgb_to_linear(0), 0.0);
        assert_eq!(srgb_to_linear(255), 1.0);
        assert!((srgb_to_linear(128) - 0.215_861).abs() < 1e-6);
        assert!((srgb_to_linear(10) - 10.0 / 255.0 / 12.92).abs() < 1e-7);
        assert_eq!(TextureSet::default().words.len(), SRGB_LUT_WORDS as usize);
    }

    #[test]
    fn bilinear_interpolates_between_texel_centres_and_wraps() {
        let mut set = TextureSet::default();
        let t = set.push(2, 1, &Texels::Rgba8(vec![rgba(0, 0, 0, 255), rgba(255, 255, 255, 255)]), 0).unwrap();
        let r = TextureRef::new(t, 0, false);
        // Texel centres at s = 0.25 and 0.75.
        assert_eq!(set.sample(&r, Vec2::new(0.25, 0.5)).x, 0.0);
        assert_eq!(set.sample(&r, Vec2::new(0.75, 0.5)).x, 1.0);
        assert!((set.sample(&r, Vec2::new(0.5, 0.5)).x - 0.5).abs() < 1e-6);
        // Repeat: s = 0 is halfway between the last and first texel.
        assert!((set.sample(&r, Vec2::new(0.0, 0.5)).x - 0.5).abs() < 1e-6);
        assert!((set.sample(&r, Vec2::new(3.0, 0.5)).x - 0.5).abs() < 1e-6);
        // Clamp: the edge texel extends.
        let c = set.alias(t, (Wrap::ClampToEdge as u32) << TEXTURE_WRAP_S_SHIFT).unwrap();
        let rc = TextureRef::new(c, 0, false);
        assert_eq!(set.sample(&rc, Vec2::new(0.0, 0.5)).x, 0.0);
        assert_eq!(set.sample(&rc, Vec2::new(-7.0, 0.5)).x, 0.0);
        assert_eq!(set.sample(&rc, Vec2::new(9.0, 0.5)).x, 1.0);
        // Mirrored repeat: s in [1, 2] reads the texture backwards.
        let m = set.alias(t, (Wrap::MirroredRepeat as u32) << TEXTURE_WRAP_S_SHIFT).unwrap();
        let rm = TextureRef::new(m, 0, false);
        assert_eq!(set.sample(&rm, Vec2::new(1.25, 0.5)).x, 1.0);
        assert_eq!(set.sample(&rm, Vec2::new(1.75, 0.5)).x, 0.0);
        // Nearest.
        let n = set.alias(t, TEXTURE_NEAREST).unwrap();
        assert_eq!(set.sample(&TextureRef::new(n, 0, false), Vec2::new(0.49, 0.5)).x, 0.0);
        assert_eq!(set.sample(&TextureRef::new(n, 0, false), Vec2::new(0.51, 0.5)).x, 1.0);
    }

    #[test]
    fn srgb_decodes_colour_but_not_alpha_and_filters_in_linear() {
        let mut set = TextureSet::default();
        let t = set.push(1, 1, &Texels::Rgba8(vec![rgba(128, 128, 128, 128)]), 0).unwrap();
        let v = set.sample(&TextureRef::new(t, 0, true), Vec2::ZERO);
        assert_eq!(v.x, srgb_to_linear(128));
        assert_eq!(v.w, 128.0 / 255.0);
        let lin = set.sample(&TextureRef::new(t, 1, false), Vec2::ZERO);
        assert_eq!(lin.y, 128.0 / 255.0);
        assert_eq!(set.sample_channel(&TextureRef::new(t, 3, true), Vec2::ZERO), 128.0 / 255.0);
    }

    #[test]
    fn float_textures_and_hostile_coordinates() {
        let mut set = TextureSet::default();
        let t = set.push(1, 2, &Texels::RgbaF32(vec![[2.0, 0.5, 0.0, 1.0], [f32::NAN, 1.0, 1.0, 1.0]]), 0).unwrap();
        let r = TextureRef::new(t, 0, true);
        assert_eq!(set.sample(&r, Vec2::new(0.5, 0.25)).x, 2.0, "float texels are never sRGB-decoded");
        for uv in [Vec2::NAN, Vec2::INFINITY, Vec2::new(-1e30, 1e30), Vec2::new(f32::MIN_POSITIVE, -0.0)] {
            assert!(set.sample(&r, uv).is_finite(), "{uv}");
        }
        assert_eq!(set.sample(&TextureRef::NONE, Vec2::ZERO), Vec4::ZERO);
        assert_eq!(set.push(2, 2, &Texels::Rgba8(vec![0; 3]), 0), None, "size mismatch");
    }

    #[test]
    fn texture_transform_follows_khr_texture_transform() {
        // Rotation by 90 degrees: (u, v) = (1, 0) goes to (0, 1) before the offset (the
        // extension's column-major `mat3(cos, sin, 0, -sin, cos, 0, 0, 0, 1)`).
        let r = TextureRef::NONE.with_transform([0.5, 0.25], std::f32::consts::FRAC_PI_2, [2.0, 3.0]);
        let st = r.apply(Vec2::new(1.0, 0.0));
        assert!((st - Vec2::new(0.5, 0.25 + 2.0)).length() < 1e-6, "{st}");
        let st = r.apply(Vec2::new(0.0, 1.0));
        assert!((st - Vec2::new(0.5 - 3.0, 0.25)).length() < 1e-6, "{st}");
    }
}
