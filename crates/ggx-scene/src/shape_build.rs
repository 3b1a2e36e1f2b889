//! Validation of `[[shapes]]` entries and their tessellation into world-space triangles.
//!
//! Two steps, so that the triangle count of every shape is known before any is tessellated:
//! [`prepare`] validates a shape (and reads its mesh file) into a [`PreparedShape`] that
//! knows its triangle count, and [`PreparedShape::append`] tessellates it.

use std::path::Path;

use glam::{Affine3A, Mat3, Vec3};

use crate::check::{Interval, span_of};
use crate::error::{ErrorKind, SceneError, Source};
use crate::geometry::{Geometry, build_transform, cube, disk, icosphere, load_obj, rectangle};
use crate::limits::Limits;
use crate::mesh::{NO_INDEX, ShadingNormals, Triangle, TriangleMesh};
use crate::raw::{RawShape, ShapeType};
use crate::shorten::short_path;

/// Largest sphere `subdivisions` (20 * 4^7 = 327 680 triangles).
pub const MAX_SUBDIVISIONS: u32 = 7;
/// Largest disk `segments`.
pub const MAX_SEGMENTS: u32 = 4096;

/// What a validated shape tessellates into.
enum Tessellation {
    /// An icosphere of `radius` around `center`.
    Sphere { subdivisions: u32, center: Vec3, radius: f32 },
    /// The unit square.
    Rectangle,
    /// The unit cube.
    Box,
    /// The unit disk as a fan of `segments` triangles.
    Disk { segments: u32 },
    /// A mesh file, already read.
    Mesh(Geometry),
}

/// A validated shape, not yet tessellated.
pub(crate) struct PreparedShape {
    tessellation: Tessellation,
    smooth: bool,
    transform: Affine3A,
}

impl PreparedShape {
    /// The number of triangles [`Self::append`] adds, known without tessellating.
    pub fn triangles(&self) -> u64 {
        match &self.tessellation {
            Tessellation::Sphere { subdivisions, .. } => 20 * 4u64.pow(*subdivisions),
            Tessellation::Rectangle => 2,
            Tessellation::Box => 12,
            Tessellation::Disk { segments } => u64::from(*segments),
            Tessellation::Mesh(g) => g.indices.len() as u64,
        }
    }

    /// Tessellates shape `index` (its entry `raw`), transforms it to world space and appends
    /// its triangles with material `material` to `mesh`. Returns the world-space area of the
    /// appended triangles.
    pub fn append(
        self,
        src: Source<'_>,
        index: usize,
        raw: &RawShape,
        material: u32,
        mesh: &mut TriangleMesh,
    ) -> Result<f32, SceneError> {
        let mut geometry = match self.tessellation {
            Tessellation::Sphere { subdivisions, center, radius } => {
                let mut g = icosphere(subdivisions, self.smooth);
                for p in &mut g.positions {
                    *p = center + radius * *p;
                }
                g
            }
            Tessellation::Rectangle => rectangle(),
            Tessellation::Box => cube(),
            Tessellation::Disk { segments } => disk(segments),
            Tessellation::Mesh(g) => g,
        };
        if !self.smooth {
            geometry.normals = None;
        }
        append(&geometry, &self.transform, material, mesh)
            .map_err(|msg| src.error(raw.kind.span(), &format!("shapes[{index}]"), ErrorKind::Degenerate, msg))
    }
}

/// Validates shape `index` (its entry `raw`); a mesh file is resolved against `base_dir` and
/// read within `limits`.
pub(crate) fn prepare(
    src: Source<'_>,
    index: usize,
    raw: &RawShape,
    base_dir: &Path,
    limits: &Limits,
) -> Result<PreparedShape, SceneError> {
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
    let tessellation = match raw.kind.get_ref() {
        ShapeType::Sphere => {
            let center = raw.center.as_ref().map_or(Ok([0.0; 3]), |c| src.array(c, &field("center"), Interval::ANY))?;
            let radius = src.number_or(raw.radius.as_ref(), 1.0, &field("radius"), Interval::above(0.0))?;
            let subdivisions = raw
                .subdivisions
                .as_ref()
                .map_or(Ok(4), |s| src.integer(s, &field("subdivisions"), 0, MAX_SUBDIVISIONS))?;
            Tessellation::Sphere { subdivisions, center: Vec3::from(center), radius }
        }
        ShapeType::Rectangle => Tessellation::Rectangle,
        ShapeType::Box => Tessellation::Box,
        ShapeType::Disk => Tessellation::Disk {
            segments: raw.segments.as_ref().map_or(Ok(64), |s| src.integer(s, &field("segments"), 3, MAX_SEGMENTS))?,
        },
        ShapeType::Mesh => {
            let file = raw.file.as_ref().ok_or_else(|| {
                src.error(raw.kind.span(), &field("type"), ErrorKind::Conflict, "type \"mesh\" needs `file`")
            })?;
            let full = base_dir.join(file.get_ref());
            let file_error = |msg: String| src.error(file.span(), &field("file"), ErrorKind::File, msg);
            if !full.exists() {
                return Err(file_error(format!("mesh file not found: {}", short_path(&full))));
            }
            Tessellation::Mesh(load_obj(&full, limits).map_err(file_error)?)
        }
    };
    let transform = build_transform(src, raw.transform.as_ref(), &path)?;
    Ok(PreparedShape { tessellation, smooth, transform })
}

/// Transforms `g` by `m` (normals by the inverse transpose of its linear part) and appends
/// it. Returns the appended area, or why the shape does not fit in `f32`: a vertex or a
/// triangle's area (whose square the renderers compute to normalise its normal) overflows.
fn append(g: &Geometry, m: &Affine3A, material: u32, mesh: &mut TriangleMesh) -> Result<f32, &'static str> {
    let normal_matrix = Mat3::from(m.matrix3).inverse().transpose();
    let positions: Vec<Vec3> = g.positions.iter().map(|&p| m.transform_point3(p)).collect();
    if positions.iter().any(|p| !p.is_finite()) {
        return Err("the transformed shape has non-finite vertices");
    }
    let mut area = 0.0f32;
    for t in &g.indices {
        let [v0, v1, v2] = t.map(|i| positions[i as usize].to_array());
        let mut tri = Triangle { v0, material, v1, normals: NO_INDEX, v2, emitter: NO_INDEX };
        if !tri.area().is_finite() {
            return Err("the transformed shape is too large for f32: a triangle's area overflows");
        }
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
    if !area.is_finite() {
        return Err("the transformed shape is too large for f32: its total area overflows");
    }
    Ok(area)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_counts_match_the_tessellation() {
        let unit = |tessellation| PreparedShape { tessellation, smooth: true, transform: Affine3A::IDENTITY };
        for s in 0..=3 {
            let shape = unit(Tessellation::Sphere { subdivisions: s, center: Vec3::ZERO, radius: 1.0 });
            assert_eq!(shape.triangles(), icosphere(s, true).indices.len() as u64);
        }
        assert_eq!(unit(Tessellation::Rectangle).triangles(), rectangle().indices.len() as u64);
        assert_eq!(unit(Tessellation::Box).triangles(), cube().indices.len() as u64);
        assert_eq!(unit(Tessellation::Disk { segments: 7 }).triangles(), disk(7).indices.len() as u64);
        assert_eq!(unit(Tessellation::Mesh(cube())).triangles(), 12);
    }
}
