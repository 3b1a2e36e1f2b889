//! glTF accessors read by hand, every size and offset checked with `u64` arithmetic before a
//! byte is read or an element allocated (the `gltf` crate's own reader underflows on
//! `count = 0` and asserts on mismatched types, so it is never called on user data).

use gltf::accessor::{DataType, Dimensions};

/// Size in bytes of one component.
fn component_size(t: DataType) -> u64 {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

/// Components per element.
fn dimensions(d: Dimensions) -> u64 {
    match d {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 | Dimensions::Mat2 => 4,
        Dimensions::Mat3 => 9,
        Dimensions::Mat4 => 16,
    }
}

/// Component `k` of the little-endian element at `bytes`, normalized as glTF defines it for
/// normalized integers (`u8 / 255`, `max(i8 / 127, -1)`, ...), as is for floats and, when
/// `normalized` is false, plain integers.
fn component(bytes: &[u8], t: DataType, normalized: bool) -> f32 {
    let b = |i: usize| bytes.get(i).copied().unwrap_or(0);
    match t {
        DataType::F32 => f32::from_le_bytes([b(0), b(1), b(2), b(3)]),
        DataType::U8 => f32::from(b(0)) / if normalized { 255.0 } else { 1.0 },
        DataType::I8 => {
            let v = f32::from(b(0) as i8);
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        DataType::U16 => f32::from(u16::from_le_bytes([b(0), b(1)])) / if normalized { 65535.0 } else { 1.0 },
        DataType::I16 => {
            let v = f32::from(i16::from_le_bytes([b(0), b(1)]));
            if normalized { (v / 32767.0).max(-1.0) } else { v }
        }
        DataType::U32 => u32::from_le_bytes([b(0), b(1), b(2), b(3)]) as f32,
    }
}

/// An integer component (indices).
fn integer(bytes: &[u8], t: DataType) -> Option<u32> {
    let b = |i: usize| bytes.get(i).copied().unwrap_or(0);
    match t {
        DataType::U8 => Some(u32::from(b(0))),
        DataType::U16 => Some(u32::from(u16::from_le_bytes([b(0), b(1)]))),
        DataType::U32 => Some(u32::from_le_bytes([b(0), b(1), b(2), b(3)])),
        _ => None,
    }
}

/// The bytes of `count` elements of `element` bytes each, `stride` apart, from `offset` of
/// the buffer view `view`: checked against the view's and the buffer's lengths.
fn strided<'b>(
    view: &gltf::buffer::View<'_>,
    offset: u64,
    count: u64,
    element: u64,
    buffers: &'b [Vec<u8>],
) -> Result<(&'b [u8], u64), String> {
    let stride = view.stride().map_or(element, |s| s as u64);
    if stride < element {
        return Err(format!(
            "bufferViews[{}].byteStride {stride} is smaller than an element ({element} bytes)",
            view.index()
        ));
    }
    let buffer = buffers
        .get(view.buffer().index())
        .ok_or_else(|| format!("bufferViews[{}]: buffer {} is missing", view.index(), view.buffer().index()))?;
    let view_start = view.offset() as u64;
    let view_end =
        view_start.checked_add(view.length() as u64).filter(|&e| e <= buffer.len() as u64).ok_or_else(|| {
            format!(
                "bufferViews[{}] (bytes {view_start}..+{}) lies outside buffer {} ({} bytes)",
                view.index(),
                view.length(),
                view.buffer().index(),
                buffer.len()
            )
        })?;
    let needed = count
        .checked_sub(1)
        .and_then(|n| n.checked_mul(stride))
        .and_then(|n| n.checked_add(element))
        .and_then(|n| n.checked_add(offset))
        .filter(|&n| n <= view_end - view_start)
        .ok_or_else(|| {
            format!(
                "{count} elements of {element} bytes every {stride} from byte {offset} do not fit in bufferViews[{}] \
                 ({} bytes)",
                view.index(),
                view.length()
            )
        })?;
    let start = (view_start + offset) as usize;
    let end = (view_start + needed) as usize;
    Ok((&buffer[start..end], stride))
}

/// Checks `count` elements against `max` before anything is allocated.
fn check_count(count: u64, max: u64) -> Result<(), String> {
    if count == 0 {
        return Err("count is 0 (glTF requires at least 1)".to_owned());
    }
    if count > max {
        return Err(format!("count {count} is over the {max} elements the limits allow"));
    }
    Ok(())
}

/// Allocates `n` zeroed values without aborting.
fn zeroed<T: Copy + Default>(n: u64) -> Result<Vec<T>, String> {
    let n = usize::try_from(n).map_err(|_| format!("{n} values do not fit in memory"))?;
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| format!("cannot allocate {n} values"))?;
    v.resize(n, T::default());
    Ok(v)
}

/// The accessor's elements as `f32` components (`dims` per element, which must match),
/// sparse substitutions applied, at most `max` elements.
pub(crate) fn read_floats(
    acc: &gltf::Accessor<'_>,
    dims: &[Dimensions],
    buffers: &[Vec<u8>],
    max: u64,
) -> Result<Vec<f32>, String> {
    let at = |e: String| format!("accessors[{}]: {e}", acc.index());
    if !dims.contains(&acc.dimensions()) {
        return Err(at(format!("type {:?} where {:?} is expected", acc.dimensions(), dims)));
    }
    let n = dimensions(acc.dimensions());
    let t = acc.data_type();
    if t == DataType::U32 {
        return Err(at("UNSIGNED_INT components are only allowed for indices".to_owned()));
    }
    let normalized = acc.normalized() || t == DataType::F32;
    if !normalized {
        return Err(at(format!("{t:?} components must be normalized for this attribute")));
    }
    let count = acc.count() as u64;
    check_count(count, max).map_err(at)?;
    let csize = component_size(t);
    let element = n * csize;
    let mut out: Vec<f32> = zeroed(count * n).map_err(at)?;
    if let Some(view) = acc.view() {
        let (bytes, stride) = strided(&view, acc.offset() as u64, count, element, buffers).map_err(at)?;
        for (i, slot) in out.chunks_exact_mut(n as usize).enumerate() {
            let e = &bytes[(i as u64 * stride) as usize..];
            for (k, c) in slot.iter_mut().enumerate() {
                *c = component(&e[(k as u64 * csize) as usize..], t, normalized);
            }
        }
    }
    if let Some(sparse) = acc.sparse() {
        let scount = sparse.count() as u64;
        check_count(scount, count).map_err(|e| at(format!("sparse {e}")))?;
        let it = sparse.indices();
        let itype = match it.index_type() {
            gltf::accessor::sparse::IndexType::U8 => DataType::U8,
            gltf::accessor::sparse::IndexType::U16 => DataType::U16,
            gltf::accessor::sparse::IndexType::U32 => DataType::U32,
        };
        let isize = component_size(itype);
        let (ibytes, istride) = strided(&it.view(), it.offset() as u64, scount, isize, buffers)
            .map_err(|e| at(format!("sparse indices: {e}")))?;
        let values = sparse.values();
        let (vbytes, vstride) = strided(&values.view(), values.offset() as u64, scount, element, buffers)
            .map_err(|e| at(format!("sparse values: {e}")))?;
        for s in 0..scount {
            let index = integer(&ibytes[(s * istride) as usize..], itype).unwrap_or(u32::MAX);
            if u64::from(index) >= count {
                return Err(at(format!("sparse index {index} is out of range (count {count})")));
            }
            let e = &vbytes[(s * vstride) as usize..];
            for k in 0..n {
                out[(u64::from(index) * n + k) as usize] = component(&e[(k * csize) as usize..], t, normalized);
            }
        }
    }
    if out.iter().any(|c| !c.is_finite()) {
        return Err(at("a component is NaN or infinite".to_owned()));
    }
    Ok(out)
}

/// An index accessor (`SCALAR` of `u8`, `u16` or `u32`), every index below `vertices`.
pub(crate) fn read_indices(
    acc: &gltf::Accessor<'_>,
    buffers: &[Vec<u8>],
    vertices: u64,
    max: u64,
) -> Result<Vec<u32>, String> {
    let at = |e: String| format!("accessors[{}] (indices): {e}", acc.index());
    let t = acc.data_type();
    if acc.dimensions() != Dimensions::Scalar || !matches!(t, DataType::U8 | DataType::U16 | DataType::U32) {
        return Err(at(format!("must be SCALAR unsigned integers, got {:?} {t:?}", acc.dimensions())));
    }
    if acc.sparse().is_some() {
        return Err(at("sparse index accessors are not supported".to_owned()));
    }
    let count = acc.count() as u64;
    check_count(count, max).map_err(at)?;
    let size = component_size(t);
    let view = acc.view().ok_or_else(|| at("has no bufferView".to_owned()))?;
    let (bytes, stride) = strided(&view, acc.offset() as u64, count, size, buffers).map_err(at)?;
    let mut out: Vec<u32> = zeroed(count).map_err(at)?;
    for (i, slot) in out.iter_mut().enumerate() {
        let v = integer(&bytes[(i as u64 * stride) as usize..], t).unwrap_or(u32::MAX);
        if u64::from(v) >= vertices {
            return Err(at(format!("index {v} at position {i} is out of range ({vertices} vertices)")));
        }
        *slot = v;
    }
    Ok(out)
}
