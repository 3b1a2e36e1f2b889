//! Validation of `[[shapes]]` entries and their tessellation into world-space triangles.

use std::path::Path;

use glam::{Affine3A, Mat3, Vec3};

use crate::check::{Interval, span_of};
use crate::error::{ErrorKind, SceneError, Source};
use crate::geometry::{Geometry, build_transform, cube, disk, icosphere, load_obj, rectangle};
use crate::mesh::{NO_INDEX, ShadingNormals, Triangle, TriangleMesh};
use crate::raw::{RawShape, ShapeType};

/// Largest sphere `subdivisions` (20 * 4^7 = 327 680 triangles).
pub const MAX_SUBDIVISIONS: u32 = 7;
/// Largest disk `segments`.
pub const MAX_SEGMENTS: u32 = 4096;

/// Validates shape `index`, tessellates it and appends its triangles (with material
/// `material`) to `mesh`. Returns the world-space area of the appended triangles.
pub(crate) fn add_shape(
    src: Source<'_>,
    index: usize,
    raw: &RawShape,
    material: u32,
    base_dir: &Path,
    mesh: &mut TriangleMesh,
) -> Result<f32, SceneError> {
    let path = format!("shapes[{index}]");
    let field = |key: &str| format!("{path}.{key}");
    let (type_name, allowed): (_, &[&str]) = match raw.kind.get_ref() {
        ShapeType::Sphere => ("sphere", &["center", "radius", "subdivisions", "smooth"]),
        ShapeType::Rectangle => ("rectangle", &[]),
        ShapeType::Box => ("box", &[]),
        ShapeType::Disk => ("disk", &["segments"]),
        ShapeType::Mesh => ("mesh", &["file", "smooth"]),
    };
    let present = [
        ("center", span_of(&raw.center)),
        ("radius", span_of(&raw.radius)),
        ("subdivisions", span_of(&raw.subdivisions)),
        ("smooth", span_of(&raw.smooth)),
        ("segments", span_of(&raw.segments)),
        ("file", span_of(&raw.file)),
    ];
    src.only_keys(&path, type_name, &present, allowed)?;
    let smooth = raw.smooth.as_ref().is_none_or(|s| *s.get_ref());
    let mut geometry = match raw.kind.get_ref() {
        ShapeType::Sphere => {
            let center = raw.center.as_ref().map_or(Ok([0.0; 3]), |c| src.array(c, &field("center"), Interval::ANY))?;
            let radius = src.number_or(raw.radius.as_ref(), 1.0, &field("radius"), Interval::above(0.0))?;
            let subdivisions = raw
                .subdivisions
                .as_ref()
                .map_or(Ok(4), |s| src.integer(s, &field("subdivisions"), 0, MAX_SUBDIVISIONS))?;
            let mut g = icosphere(subdivisions, smooth);
            for p in &mut g.positions {
                *p = Vec3::from(center) + radius * *p;
            }
            g
        }
        ShapeType::Rectangle => rectangle(),
        ShapeType::Box => cube(),
        ShapeType::Disk => {
            disk(raw.segments.as_ref().map_or(Ok(64), |s| src.integer(s, &field("segments"), 3, MAX_SEGMENTS))?)
        }
        ShapeType::Mesh => {
            let file = raw.file.as_ref().ok_or_else(|| {
                src.error(raw.kind.span(), &field("type"), ErrorKind::Conflict, "type \"mesh\" needs `file`")
            })?;
            let full = base_dir.join(file.get_ref());
            let file_error = |msg: String| src.error(file.span(), &field("file"), ErrorKind::File, msg);
            if !full.is_file() {
                return Err(file_error(format!("mesh file not found: {}", full.display())));
            }
            load_obj(&full).map_err(file_error)?
        }
    };
    if !smooth {
        geometry.normals = None;
    }
    let transform = build_transform(src, raw.transform.as_ref(), &path)?;
    append(&geometry, &transform, material, mesh).ok_or_else(|| {
        let msg = "the transformed shape has non-finite vertices";
        src.error(raw.kind.span(), &path, ErrorKind::Degenerate, msg)
    })
}

/// Transforms `g` by `m` (normals by the inverse transpose of its linear part) and appends
/// it. Returns the appended area, or `None` if a vertex is not finite.
fn append(g: &Geometry, m: &Affine3A, material: u32, mesh: &mut TriangleMesh) -> Option<f32> {
    let normal_matrix = Mat3::from(m.matrix3).inverse().transpose();
    let positions: Vec<Vec3> = g.positions.iter().map(|&p| m.transform_point3(p)).collect();
    if positions.iter().any(|p| !p.is_finite()) {
        return None;
    }
    let mut area = 0.0;
    for t in &g.indices {
        let [v0, v1, v2] = t.map(|i| positions[i as usize].to_array());
        let mut tri = Triangle { v0, material, v1, normals: NO_INDEX, v2, emitter: NO_INDEX };
        if let Some(normals) = &g.normals {
            let n = t.map(|i| (normal_matrix * normals[i as usize]).normalize_or_zero());
            if n.iter().all(|n| *n != Vec3::ZERO) {
                tri.normals = mesh.shading_normals.len() as u32;
                mesh.shading_normals.push(ShadingNormals::new(n));
            }
        }
        area += tri.area();
        mesh.triangles.push(tri);
    }
    Some(area)
}
