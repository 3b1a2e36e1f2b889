//! Generators of small valid `.exr`, `.hdr` and OBJ files, and the byte-level and
//! header-field mutations that `readers_fuzz.rs` applies to them.

use proptest::prelude::*;
use proptest::sample::Index;

/// A small deterministic generator (64-bit LCG, top 24 bits).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// One mutation of a file's bytes; positions are fractions of the current length.
#[derive(Clone, Debug)]
pub enum Mutation {
    /// Flip one bit.
    Flip(Index, u8),
    /// Cut the file at a position.
    Truncate(Index),
    /// Copy a run of the file to another place in it (overwriting).
    Splice(Index, Index, usize),
    /// Insert a run of the file at another place.
    Duplicate(Index, Index, usize),
    /// Overwrite four bytes with a little-endian `i32` (sizes, counts, windows).
    SetI32(Index, i32),
    /// Overwrite eight bytes with a little-endian `u64` (offset-table entries).
    SetU64(Index, u64),
}

/// Interesting `i32` values: boundaries of the limits and of integer types.
fn interesting_i32() -> impl Strategy<Value = i32> {
    prop_oneof![
        Just(0),
        Just(1),
        Just(-1),
        Just(i32::MAX),
        Just(i32::MIN),
        Just(16384),
        Just(100_000),
        Just(1 << 24),
        any::<i32>()
    ]
}

/// Any [`Mutation`].
pub fn mutation() -> impl Strategy<Value = Mutation> {
    let u64s = prop_oneof![Just(0u64), Just(u64::MAX), Just(1 << 40), 0u64..4096, any::<u64>()];
    prop_oneof![
        (any::<Index>(), 0u8..8).prop_map(|(i, b)| Mutation::Flip(i, b)),
        any::<Index>().prop_map(Mutation::Truncate),
        (any::<Index>(), any::<Index>(), 1usize..64).prop_map(|(a, b, n)| Mutation::Splice(a, b, n)),
        (any::<Index>(), any::<Index>(), 1usize..64).prop_map(|(a, b, n)| Mutation::Duplicate(a, b, n)),
        (any::<Index>(), interesting_i32()).prop_map(|(i, v)| Mutation::SetI32(i, v)),
        (any::<Index>(), u64s).prop_map(|(i, v)| Mutation::SetU64(i, v)),
    ]
}

/// Overwrites `bytes[at..]` with `value`, as far as it fits.
fn overwrite(bytes: &mut [u8], at: usize, value: &[u8]) {
    let end = (at + value.len()).min(bytes.len());
    if at < end {
        bytes[at..end].copy_from_slice(&value[..end - at]);
    }
}

/// Applies `mutations` in order.
pub fn mutate(bytes: &mut Vec<u8>, mutations: &[Mutation]) {
    for m in mutations {
        if bytes.is_empty() {
            return;
        }
        let n = bytes.len();
        match m {
            Mutation::Flip(i, bit) => bytes[i.index(n)] ^= 1 << bit,
            Mutation::Truncate(i) => bytes.truncate(i.index(n)),
            Mutation::Splice(from, to, len) => {
                let from = from.index(n);
                let run = bytes[from..(from + len).min(n)].to_vec();
                overwrite(bytes, to.index(n), &run);
            }
            Mutation::Duplicate(from, to, len) => {
                let from = from.index(n);
                let run = bytes[from..(from + len).min(n)].to_vec();
                let to = to.index(n);
                bytes.splice(to..to, run);
            }
            Mutation::SetI32(i, v) => overwrite(bytes, i.index(n), &v.to_le_bytes()),
            Mutation::SetU64(i, v) => overwrite(bytes, i.index(n), &v.to_le_bytes()),
        }
    }
}

/// Compressions the generated EXR files use (index 0..6).
fn compression(index: usize) -> exr::compression::Compression {
    use exr::compression::Compression::*;
    [Uncompressed, RLE, ZIP1, ZIP16, PIZ, PXR24][index % 6]
}

/// A valid `w x h` OpenEXR file with `layers` RGBA `f32` layers (several layers make a
/// multi-part file with `chunkCount` attributes), scan lines or 4x4 tiles. `None` if the
/// `exr` crate cannot write that combination.
pub fn exr_bytes(w: usize, h: usize, compression_index: usize, tiled: bool, layers: usize) -> Option<Vec<u8>> {
    use exr::prelude::*;
    let encoding = Encoding {
        compression: compression(compression_index),
        blocks: if tiled { Blocks::Tiles(Vec2(4, 4)) } else { Blocks::ScanLines },
        line_order: LineOrder::Increasing,
    };
    let layer = |i: usize| {
        let pixels = move |p: Vec2<usize>| (p.x() as f32 + 0.5, p.y() as f32, i as f32 * 0.25, 1.0f32);
        Layer::new(
            Vec2(w, h),
            LayerAttributes::named(format!("layer{i}").as_str()),
            encoding,
            SpecificChannels::rgba(pixels),
        )
    };
    let image = Image::from_layers(
        ImageAttributes::new(IntegerBounds::from_dimensions(Vec2(w, h))),
        (0..layers).map(layer).collect::<Vec<_>>(),
    );
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write().to_buffered(&mut bytes).ok()?;
    Some(bytes.into_inner())
}

/// Header attributes that [`set_attribute_word`] mutates.
pub const MUTATED_EXR_FIELDS: &[&str] =
    &["dataWindow", "displayWindow", "channels", "compression", "tiles", "chunkCount", "lineOrder", "type"];

/// Offsets of the values of every header attribute called `name` (one per part).
pub fn attribute_values(bytes: &[u8], name: &str) -> Vec<usize> {
    let key = [name.as_bytes(), b"\0"].concat();
    let mut found = Vec::new();
    let mut start = 0;
    while let Some(p) = bytes[start..].windows(key.len()).position(|w| w == key) {
        let at = start + p + key.len();
        if let Some(type_len) = bytes[at..].iter().position(|&b| b == 0) {
            // Skip the type name, its NUL and the i32 value size.
            found.push(at + type_len + 1 + 4);
        }
        start = at;
    }
    found
}

/// Writes little-endian `values` at `at` (as far as they fit).
pub fn write_i32s(bytes: &mut [u8], at: usize, values: &[i32]) {
    for (k, v) in values.iter().enumerate() {
        overwrite(bytes, at + 4 * k, &v.to_le_bytes());
    }
}

/// Sets the value of every attribute `name` to `values`; `false` if there is none.
pub fn set_attribute_i32s(bytes: &mut [u8], name: &str, values: &[i32]) -> bool {
    let at = attribute_values(bytes, name);
    for &a in &at {
        write_i32s(bytes, a, values);
    }
    !at.is_empty()
}

/// Overwrites 32-bit word `word` of the value of the first attribute `name` (if any) with
/// `value`; single bytes (`compression`, `lineOrder`) take its low byte.
pub fn set_attribute_word(bytes: &mut [u8], name: &str, word: usize, value: i32) {
    if let Some(&at) = attribute_values(bytes, name).first() {
        if matches!(name, "compression" | "lineOrder") {
            overwrite(bytes, at, &[value as u8]);
        } else {
            overwrite(bytes, at + 4 * word, &value.to_le_bytes());
        }
    }
}

/// A valid `w x h` Radiance HDR file written by `image` (run-length encoded from a width of
/// 8) with texels spanning several orders of magnitude.
pub fn hdr_bytes(w: u32, h: u32, seed: u32) -> Vec<u8> {
    use image::ImageEncoder as _;
    let mut rng = Lcg(u64::from(seed));
    let pixels: Vec<f32> = (0..w * h * 3).map(|_| 10f32.powf(6.0 * rng.next() - 3.0) * rng.next()).collect();
    let mut bytes = Vec::new();
    image::codecs::hdr::HdrEncoder::new(&mut bytes)
        .write_image(bytemuck::cast_slice(&pixels), w, h, image::ExtendedColorType::Rgb32F)
        .unwrap();
    bytes
}

/// `bytes` with the dimension line (the one after the first blank line) replaced by `line`.
pub fn replace_dimension_line(bytes: &[u8], line: &str) -> Vec<u8> {
    let Some(blank) = bytes.windows(2).position(|w| w == b"\n\n").map(|p| p + 2) else { return bytes.to_vec() };
    let Some(end) = bytes[blank..].iter().position(|&b| b == b'\n').map(|p| blank + p) else { return bytes.to_vec() };
    [&bytes[..blank], line.as_bytes(), &bytes[end..]].concat()
}

/// A `w x h` Radiance HDR file of one RGBE colour, run-length encoded by hand (a few bytes
/// per scan line), for maps too large to build in memory first. `w` in `8..32768`.
pub fn rle_hdr(w: u32, h: u32, rgbe: [u8; 4]) -> Vec<u8> {
    let mut bytes = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n").into_bytes();
    let mut line = vec![2, 2, (w >> 8) as u8, (w & 0xff) as u8];
    for c in rgbe {
        let mut left = w;
        while left > 0 {
            let run = left.min(127);
            line.extend([128 + run as u8, c]);
            left -= run;
        }
    }
    for _ in 0..h {
        bytes.extend_from_slice(&line);
    }
    bytes
}

/// OBJ text: an `n`-gon fan of `n` vertices with normals, a quad and a triangle, then the
/// index `edits` (each sets one index of the face lines to a value).
pub fn obj_text(n: usize, seed: u32, edits: &[(Index, i64)]) -> String {
    let mut rng = Lcg(u64::from(seed));
    let mut text = String::from("o fuzz\n");
    for _ in 0..n {
        text.push_str(&format!("v {} {} {}\nvn 0 0 1\n", rng.next(), rng.next(), rng.next() - 0.5));
    }
    let mut faces: Vec<Vec<i64>> = vec![(1..=n as i64).collect(), vec![1, 2, 3, 4], vec![-1, -2, -3]];
    let total: usize = faces.iter().map(Vec::len).sum();
    for (index, value) in edits {
        let mut k = index.index(total);
        for f in &mut faces {
            if k < f.len() {
                f[k] = *value;
                break;
            }
            k -= f.len();
        }
    }
    for f in faces {
        let ids: Vec<String> = f.iter().map(|i| format!("{i}//{i}")).collect();
        text.push_str(&format!("f {}\n", ids.join(" ")));
    }
    text
}
