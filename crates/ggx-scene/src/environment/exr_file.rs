//! `.exr` environment maps via the `exr` crate: the headers are read and checked against
//! [`Limits`] first, then the first layer with R, G and B channels is decoded, one block at
//! a time, checking every chunk.

use std::fs::File;
use std::io::{BufReader, Seek as _, SeekFrom};

use exr::block::UncompressedBlock;
use exr::block::reader::ChunksReader as _;
use exr::math::Vec2;
use exr::meta::BlockDescription;
use exr::meta::MetaData;
use exr::meta::attribute::SampleType;
use exr::meta::header::Header;
use exr::prelude::f16;

use super::load::{Texels, alloc_texels, check_size};
use crate::limits::Limits;

/// Copies of one block that decoding holds at once: the compressed bytes, the decompressed
/// bytes, the decompressor's scratch buffer and one more for the codecs that reorder.
const BLOCK_COPIES: u64 = 4;

/// Bytes per offset-table entry (`u64`), one entry per chunk of every layer.
const OFFSET_BYTES: u64 = 8;

/// Reads the first layer with `R`, `G` and `B` channels of the OpenEXR `file`.
///
/// Before any pixel is allocated, the headers are read on their own and refused when the
/// layer is larger than [`crate::MAX_MAP_SIZE`] per side or `limits.max_map_pixels`, when
/// any layer is deep, or when the texels, the sampling tables, the offset tables of every
/// layer and the largest block of any layer need more than `limits.max_memory`.
pub(super) fn read_exr(file: File, limits: &Limits) -> Result<Texels, String> {
    let mut reader = BufReader::new(file);
    let meta = MetaData::read_from_buffered(&mut reader, false).map_err(|e| format!("invalid OpenEXR header: {e}"))?;
    let (layer, width, height, pixels) = check_headers(&meta.headers, limits)?;
    reader.seek(SeekFrom::Start(0)).map_err(|e| format!("cannot read: {e}"))?;
    decode(reader, layer, width, height, pixels)
}

/// Checks the headers against `limits`; returns the index of the layer that will be read,
/// its size and its pixel count.
fn check_headers(headers: &[Header], limits: &Limits) -> Result<(usize, u32, u32, usize), String> {
    if headers.iter().any(|h| h.deep) {
        return Err("deep OpenEXR data is not supported".into());
    }
    let is_rgb = |h: &&Header| ["R", "G", "B"].iter().all(|name| h.channels.list.iter().any(|c| c.name.eq(name)));
    let index = headers.iter().position(|h| is_rgb(&h)).ok_or("no layer with R, G and B channels")?;
    let layer = &headers[index];
    let too_big = || "the OpenEXR block or offset tables are too large to count".to_string();
    let mut largest_block = 0u64;
    let mut chunks = 0u64;
    for h in headers {
        largest_block = largest_block.max(block_bytes(h).ok_or_else(too_big)?);
        chunks = chunks.checked_add(h.chunk_count as u64).ok_or_else(too_big)?;
    }
    let transient = largest_block
        .checked_mul(BLOCK_COPIES)
        .and_then(|b| b.checked_add(chunks.checked_mul(OFFSET_BYTES)?))
        .ok_or_else(too_big)?;
    let size = layer.layer_size;
    let (width, height, pixels) = check_size(size.width() as u64, size.height() as u64, transient, limits)?;
    Ok((index, width, height, pixels))
}

/// Uncompressed bytes of the largest block of `header`: a tile, or the scan lines that are
/// compressed together; `None` on overflow.
fn block_bytes(header: &Header) -> Option<u64> {
    let pixels = match header.blocks {
        BlockDescription::Tiles(t) => (t.tile_size.width() as u64).checked_mul(t.tile_size.height() as u64)?,
        BlockDescription::ScanLines => {
            (header.compression.scan_lines_per_block() as u64).checked_mul(header.layer_size.width() as u64)?
        }
    };
    pixels.checked_mul(header.channels.bytes_per_pixel as u64)
}

/// Decodes layer `layer` (`width x height`, `pixels` texels) from `reader` (at the start of
/// the file), one block at a time. The `exr` crate's image reader trusts the layer index and
/// level that each chunk states (a mutated file panics its debug assertions, or mixes in
/// another layer's blocks), so blocks are read here and each chunk is checked: it must
/// belong to `layer` and to its full-resolution level, and every line must lie inside the
/// texels and hold as many bytes as its samples need.
fn decode(reader: BufReader<File>, layer: usize, width: u32, height: u32, pixels: usize) -> Result<Texels, String> {
    let invalid = |e: exr::error::Error| format!("invalid OpenEXR file: {e}");
    let chunks = exr::block::read(reader, false).map_err(invalid)?;
    let header = chunks.headers().get(layer).ok_or("the OpenEXR headers changed while reading")?.clone();
    if (header.layer_size.width(), header.layer_size.height()) != (width as usize, height as usize) {
        return Err("the OpenEXR headers changed while reading".into());
    }
    let rgb = ["R", "G", "B"].map(|name| header.channels.list.iter().position(|c| c.name.eq(name)));
    let [Some(r), Some(g), Some(b)] = rgb else { return Err("the OpenEXR headers changed while reading".into()) };
    if [r, g, b].iter().any(|&c| header.channels.list[c].sampling != Vec2(1, 1)) {
        return Err("subsampled R, G or B channels are not supported".into());
    }
    let chunks = chunks
        .filter_chunks(false, |_, tile, block| block.layer == layer && tile.level_index == Vec2(0, 0))
        .map_err(invalid)?;
    let meta = chunks.meta_data().clone();
    let mut texels = alloc_texels(pixels, [0.0, 0.0, 0.0, 1.0])?;
    for chunk in chunks {
        let chunk = chunk.map_err(invalid)?;
        if chunk.layer_index != layer {
            return Err(format!(
                "invalid OpenEXR file: a chunk of part {} is listed in part {layer}",
                chunk.layer_index
            ));
        }
        let block = UncompressedBlock::decompress_chunk(chunk, &meta, false).map_err(invalid)?;
        if block.index.level != Vec2(0, 0) {
            return Err("invalid OpenEXR file: a chunk of a smaller mip level is listed in the full level".into());
        }
        for line in block.lines(&header.channels) {
            let Some(component) = [r, g, b].iter().position(|&c| c == line.location.channel) else { continue };
            let sample_type = header.channels.list[line.location.channel].sample_type;
            let (x, y) = (line.location.position.x(), line.location.position.y());
            let start = y.checked_mul(width as usize).and_then(|i| i.checked_add(x));
            let row = start.and_then(|s| texels.get_mut(s..s.checked_add(line.location.sample_count)?));
            let row = row.ok_or("invalid OpenEXR file: a block lies outside the data window")?;
            read_line(sample_type, line.value, row, component)?;
        }
    }
    Ok((width, height, texels))
}

/// Writes the samples of one line of one channel, `bytes` in native byte order as the
/// `exr` crate leaves them after decompression, into `component` of `row`.
fn read_line(sample_type: SampleType, bytes: &[u8], row: &mut [[f32; 4]], component: usize) -> Result<(), String> {
    let size = match sample_type {
        SampleType::F16 => 2,
        SampleType::F32 | SampleType::U32 => 4,
    };
    if bytes.len() != row.len() * size {
        return Err("invalid OpenEXR file: a line holds the wrong number of bytes".into());
    }
    for (texel, sample) in row.iter_mut().zip(bytes.chunks_exact(size)) {
        texel[component] = match sample_type {
            SampleType::F16 => f16::from_bits(u16::from_ne_bytes([sample[0], sample[1]])).to_f32(),
            SampleType::F32 => f32::from_ne_bytes([sample[0], sample[1], sample[2], sample[3]]),
            SampleType::U32 => u32::from_ne_bytes([sample[0], sample[1], sample[2], sample[3]]) as f32,
        };
    }
    Ok(())
}
