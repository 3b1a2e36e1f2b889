//! Validation of `[[shapes]]` entries and their tessellation into world-space triangles.
//!
//! Two steps, so that the triangle count of every shape is known before any is tessellated:
//! [`prepare`] validates a shape (and reads its mesh file) into a [`PreparedShape`] that
//! knows its triangle count, and [`PreparedShape::append`] tessellates it. A [`Budget`]
//! counts what the prepared shapes take (triangles, parsed meshes) against [`Limits`] and
//! parses each mesh file once, however many shapes use it.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use glam::{Affine3A, Mat3, Vec3};

use crate::check::{Interval, span_of};
use crate::error::{ErrorKind, SceneError, Source};
use crate::geometry::{Geometry, build_transform, cube, disk, icosphere, load_obj, rectangle};
use crate::gltf_asset::GltfAsset;
use crate::limits::{Limit, LimitError, Limits, ReadError, format_bytes};
use crate::memory::{BYTES_PER_TRIANGLE, triangle_bytes};
use crate::mesh::{NO_INDEX, ShadingNormals, Triangle, TriangleMesh, TriangleTangents, TriangleUvs};
use crate::punctual::PunctualLight;
use crate::raw::{RawShape, ShapeType};
use crate::shorten::short_path;
use crate::texture::TextureSet;

/// Largest sphere `subdivisions` (20 * 4^7 = 327 680 triangles).
pub const MAX_SUBDIVISIONS: u32 = 7;
/// Largest disk `segments`.
pub const MAX_SEGMENTS: u32 = 4096;

/// Most triangles a scene may have whatever [`Limits::max_triangles`] says: triangles,
/// shapes and shading normals are indexed by `u32`, and [`crate::NO_INDEX`] (`u32::MAX`)
/// must stay free.
pub(crate) const MAX_SCENE_TRIANGLES: u64 = u32::MAX as u64;

/// What the shapes prepared so far take, checked against [`Limits`] as each is prepared:
/// their triangles (against `max_triangles`, and [`BYTES_PER_TRIANGLE`] each against
/// `max_memory`) and the meshes parsed for them (their arrays, against `max_memory` too).
/// Each mesh file is read and parsed once and shared by every shape that names it.
pub(crate) struct Budget<'a> {
    limits: &'a Limits,
    /// Triangles of the shapes prepared so far.
    triangles: u64,
    /// Bytes of the parsed meshes held for them.
    mesh_bytes: u64,
    /// Parsed meshes by canonical path.
    meshes: HashMap<PathBuf, Rc<Geometry>>,
    /// Mesh files read and parsed (a file named by several shapes counts once).
    loads: usize,
    /// The textures of the glTF assets loaded so far.
    pub textures: TextureSet,
    /// glTF assets by canonical path.
    assets: HashMap<PathBuf, Rc<GltfAsset>>,
}

impl<'a> Budget<'a> {
    /// An empty budget within `limits`.
    pub fn new(limits: &'a Limits) -> Self {
        Self {
            limits,
            triangles: 0,
            mesh_bytes: 0,
            meshes: HashMap::new(),
            loads: 0,
            textures: TextureSet::default(),
            assets: HashMap::new(),
        }
    }

    /// Triangles of the shapes prepared so far.
    pub fn triangles(&self) -> u64 {
        self.triangles
    }

    /// Memory that the shapes prepared so far take: their triangles and parsed meshes.
    fn bytes(&self) -> u64 {
        triangle_bytes(self.triangles).saturating_add(self.mesh_bytes)
    }

    /// Counts `this` more triangles for shape `index` and checks the total (shapes
    /// `0..=index`) against `max_triangles` (at most [`MAX_SCENE_TRIANGLES`]) and, with the
    /// parsed meshes, against `max_memory`. The error says which limit and how much.
    pub fn add_triangles(&mut self, index: usize, this: u64) -> Result<(), String> {
        let total = self.triangles.saturating_add(this);
        triangle_limit(self.limits, index, this, total)?;
        self.triangles = total;
        let meshes = if self.mesh_bytes == 0 {
            String::new()
        } else {
            format!(" and their meshes ({})", format_bytes(self.mesh_bytes))
        };
        let what = format!(
            "{total} triangles of {} (mesh, shading normals and BVH at {BYTES_PER_TRIANGLE} B each){meshes}",
            shapes(index)
        );
        self.limits.check(Limit::Memory, what, self.bytes()).map_err(|e| e.to_string())
    }

    /// The mesh at `path` for shape `index`: parsed before for another shape, or read and
    /// parsed now within what the shapes before it leave of `max_triangles` and
    /// `max_memory`, then counted against `max_memory`.
    fn mesh(&mut self, index: usize, path: &Path) -> Result<Rc<Geometry>, MeshError> {
        let key = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        if let Some(g) = self.meshes.get(&key) {
            return Ok(Rc::clone(g));
        }
        let used = self.bytes();
        let left = self.left(used);
        self.loads += 1;
        let geometry = load_obj(path, &left).map_err(|e| match e {
            ReadError::Io(message) => MeshError::File(message),
            ReadError::Limit(e) => MeshError::Limit(self.over_limit(index, used, e)),
        })?;
        self.mesh_bytes = self.mesh_bytes.saturating_add(geometry.heap_bytes());
        let geometry = Rc::new(geometry);
        self.meshes.insert(key, Rc::clone(&geometry));
        Ok(geometry)
    }

    /// What the shapes prepared so far (`used` bytes) leave of `max_triangles` (at most
    /// [`MAX_SCENE_TRIANGLES`]) and `max_memory`, for the next file to load within.
    fn left(&self, used: u64) -> Limits {
        Limits {
            max_triangles: self.limits.max_triangles.min(MAX_SCENE_TRIANGLES).saturating_sub(self.triangles),
            max_memory: self.limits.max_memory.saturating_sub(used),
            ..*self.limits
        }
    }

    /// The glTF asset at `path`: loaded before for another shape, or loaded now within what
    /// the shapes before it leave of `max_triangles` and `max_memory` (its textures join
    /// [`Self::textures`]), then counted against `max_memory`.
    fn gltf(&mut self, path: &Path) -> Result<Rc<GltfAsset>, MeshError> {
        let key = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        if let Some(a) = self.assets.get(&key) {
            return Ok(Rc::clone(a));
        }
        let left = self.left(self.bytes());
        self.loads += 1;
        let textures_before = self.textures.bytes();
        let asset = crate::gltf_asset::load(path, &left, &mut self.textures)
            .map_err(|e| if e.contains("(max_") { MeshError::Limit(e) } else { MeshError::File(e) })?;
        self.mesh_bytes =
            self.mesh_bytes.saturating_add(asset.bytes).saturating_add(self.textures.bytes() - textures_before);
        let asset = Rc::new(asset);
        self.assets.insert(key, Rc::clone(&asset));
        Ok(asset)
    }

    /// `e`, a mesh of shape `index` over what the shapes before it (`used` bytes) left of a
    /// limit, as the message for the whole limit.
    fn over_limit(&self, index: usize, used: u64, e: LimitError) -> String {
        match e.limit {
            Limit::Triangles => {
                triangle_limit(self.limits, index, e.needed, self.triangles.saturating_add(e.needed)).err()
            }
            Limit::Memory if used > 0 => {
                let what =
                    format!("{}, after the {} of {},", e.what, format_bytes(used), shapes(index.saturating_sub(1)));
                let needed = used.saturating_add(e.needed);
                self.limits.check(Limit::Memory, what, needed).err().map(|e| e.to_string())
            }
            _ => None,
        }
        .unwrap_or_else(|| e.to_string())
    }
}

/// `shape 0` or `shapes 0 to {index}`.
fn shapes(index: usize) -> String {
    if index == 0 { "shape 0".to_owned() } else { format!("shapes 0 to {index}") }
}

/// Checks `total` triangles of shapes `0..=index` (`this` of them in shape `index`) against
/// `limits.max_triangles` and [`MAX_SCENE_TRIANGLES`].
fn triangle_limit(limits: &Limits, index: usize, this: u64, total: u64) -> Result<(), String> {
    let what = format!("the triangles of {} (this one: {this})", shapes(index));
    if total > MAX_SCENE_TRIANGLES && total <= limits.max_triangles {
        return Err(format!(
            "{what} needs {total}, over {MAX_SCENE_TRIANGLES} (2^32 - 1), the most triangles a scene can have \
             whatever max_triangles says (they are indexed by u32)"
        ));
    }
    limits.check(Limit::Triangles, what, total).map_err(|e| e.to_string())
}

/// Why [`Budget::mesh`] did not give a mesh.
enum MeshError {
    /// The file is missing, unreadable or invalid.
    File(String),
    /// The mesh is over a limit.
    Limit(String),
}

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
    /// A mesh file, already read (and shared by the shapes that name it).
    Mesh(Rc<Geometry>),
    /// A glTF asset: its primitives placed by their nodes, each with the asset's material
    /// `material_base + slot` (or the shape's own material).
    Gltf(Rc<GltfAsset>),
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
            Tessellation::Gltf(a) => a.triangles(),
        }
    }

    /// The punctual lights of a `gltf` shape, placed by the shape's transform (none when a
    /// transformed one is not finite).
    pub fn punctual_lights(&self) -> Vec<PunctualLight> {
        let Some(asset) = self.gltf() else { return Vec::new() };
        let t = self.transform;
        asset
            .lights
            .iter()
            .map(|l| PunctualLight {
                position: t.transform_point3(Vec3::from(l.position)).to_array(),
                direction: t.transform_vector3(Vec3::from(l.direction)).normalize_or_zero().to_array(),
                ..*l
            })
            .filter(|l| Vec3::from(l.position).is_finite() && Vec3::from(l.direction).is_finite())
            .collect()
    }

    /// The glTF asset of a `gltf` shape.
    pub fn gltf(&self) -> Option<&GltfAsset> {
        match &self.tessellation {
            Tessellation::Gltf(a) => Some(a),
            _ => None,
        }
    }

    /// Tessellates shape `index` (its entry `raw`), transforms it to world space and appends
    /// its triangles with material `material` to `mesh` (a glTF asset's primitives: material
    /// `material + slot`, or `material` for all when `one_material`). Returns the world-space
    /// area of the appended triangles.
    pub fn append(
        self,
        src: Source<'_>,
        index: usize,
        raw: &RawShape,
        (material, one_material): (u32, bool),
        textured: &dyn Fn(u32) -> bool,
        mesh: &mut TriangleMesh,
    ) -> Result<f32, SceneError> {
        if let Tessellation::Gltf(asset) = &self.tessellation {
            let mut area = 0.0f32;
            for (p, node) in &asset.instances {
                let (g, slot) = &asset.primitives[*p];
                let m = if one_material { material } else { material + *slot as u32 };
                let t = self.transform * *node;
                area += append(g, g.normals.as_deref(), textured(m), &t, m, mesh).map_err(|msg| {
                    src.error(raw.kind.span(), &format!("shapes[{index}]"), ErrorKind::Degenerate, msg)
                })?;
            }
            return Ok(area);
        }
        let generated = match &self.tessellation {
            &Tessellation::Sphere { subdivisions, center, radius } => {
                let mut g = icosphere(subdivisions, self.smooth);
                for p in &mut g.positions {
                    *p = center + radius * *p;
                }
                g
            }
            Tessellation::Rectangle => rectangle(),
            Tessellation::Box => cube(),
            &Tessellation::Disk { segments } => disk(segments),
            Tessellation::Mesh(g) => {
                return self.append_geometry(g, src, index, raw, (material, textured(material)), mesh);
            }
            Tessellation::Gltf(_) => return Ok(0.0),
        };
        self.append_geometry(&generated, src, index, raw, (material, textured(material)), mesh)
    }

    /// Appends `geometry` (without its normals unless the shape is smooth) transformed.
    fn append_geometry(
        &self,
        geometry: &Geometry,
        src: Source<'_>,
        index: usize,
        raw: &RawShape,
        (material, uvs): (u32, bool),
        mesh: &mut TriangleMesh,
    ) -> Result<f32, SceneError> {
        let normals = if self.smooth { geometry.normals.as_deref() } else { None };
        append(geometry, normals, uvs, &self.transform, material, mesh)
            .map_err(|msg| src.error(raw.kind.span(), &format!("shapes[{index}]"), ErrorKind::Degenerate, msg))
    }
}

/// Validates shape `index` (its entry `raw`); a mesh file is resolved against `base_dir` and
/// read, once per file, within what `budget` leaves (see [`Budget`]).
pub(crate) fn prepare(
    src: Source<'_>,
    index: usize,
    raw: &RawShape,
    base_dir: &Path,
    budget: &mut Budget<'_>,
) -> Result<PreparedShape, SceneError> {
    let path = format!("shapes[{index}]");
    let field = |key: &str| format!("{path}.{key}");
    let (type_name, allowed): (_, &[&str]) = match raw.kind.get_ref() {
        ShapeType::Sphere => ("sphere", &["center", "radius", "subdivisions", "smooth"]),
        ShapeType::Rectangle => ("rectangle", &[]),
        ShapeType::Box => ("box", &[]),
        ShapeType::Disk => ("disk", &["segments"]),
        ShapeType::Mesh => ("mesh", &["file", "smooth"]),
        ShapeType::Gltf => ("gltf", &["file"]),
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
            Tessellation::Mesh(budget.mesh(index, &full).map_err(|e| match e {
                MeshError::File(msg) => file_error(msg),
                MeshError::Limit(msg) => src.error(file.span(), &field("file"), ErrorKind::Limit, msg),
            })?)
        }
        ShapeType::Gltf => {
            let file = raw.file.as_ref().ok_or_else(|| {
                src.error(raw.kind.span(), &field("type"), ErrorKind::Conflict, "type \"gltf\" needs `file`")
            })?;
            let full = base_dir.join(file.get_ref());
            let file_error = |kind, msg: String| src.error(file.span(), &field("file"), kind, msg);
            if !full.exists() {
                return Err(file_error(ErrorKind::File, format!("glTF file not found: {}", short_path(&full))));
            }
            Tessellation::Gltf(budget.gltf(&full).map_err(|e| match e {
                MeshError::File(msg) => file_error(ErrorKind::File, msg),
                MeshError::Limit(msg) => file_error(ErrorKind::Limit, msg),
            })?)
        }
    };
    let transform = build_transform(src, raw.transform.as_ref(), &path)?;
    Ok(PreparedShape { tessellation, smooth, transform })
}

/// Transforms `g` by `m` (`normals`, `g`'s or none, by the inverse transpose of its linear
/// part; its texture coordinates and tangents when `uvs`, for a textured material) and appends it, transforming each triangle's vertices as it goes (no transformed
/// copy of the mesh is kept). Returns the appended area, or why the shape does not fit in
/// `f32`: a vertex or a triangle's area (whose square the renderers compute to normalise its
/// normal) overflows.
fn append(
    g: &Geometry,
    normals: Option<&[Vec3]>,
    uvs: bool,
    m: &Affine3A,
    material: u32,
    mesh: &mut TriangleMesh,
) -> Result<f32, &'static str> {
    let normal_matrix = Mat3::from(m.matrix3).inverse().transpose();
    if g.positions.iter().any(|&p| !m.transform_point3(p).is_finite()) {
        return Err("the transformed shape has non-finite vertices");
    }
    let mut area = 0.0f32;
    for t in &g.indices {
        let [v0, v1, v2] = t.map(|i| m.transform_point3(g.positions[i as usize]).to_array());
        let mut tri = Triangle { v0, material, v1, normals: NO_INDEX, v2, emitter: NO_INDEX };
        if !tri.area().is_finite() {
            return Err("the transformed shape is too large for f32: a triangle's area overflows");
        }
        let uvs = g.uvs.as_deref().filter(|_| uvs).map(|uv| TriangleUvs::new(t.map(|i| uv[i as usize])));
        let mut n = normals.map(|normals| t.map(|i| (normal_matrix * normals[i as usize]).normalize_or_zero()));
        if n.is_some_and(|n| n.contains(&Vec3::ZERO)) {
            n = None;
        }
        // Textured triangles keep a record for their coordinates: the flat normal if need be.
        let n = n.or_else(|| uvs.map(|_| [tri.geometric_normal(); 3]));
        if let Some(n) = n {
            let tangents = g.tangents.as_deref().filter(|_| uvs.is_some()).map(|tg| {
                TriangleTangents::new(t.map(|i| {
                    let v = tg[i as usize];
                    let d = m.matrix3 * v.truncate();
                    let d = d.normalize_or_zero();
                    d.extend(if v.w < 0.0 { -1.0 } else { 1.0 })
                }))
            });
            tri.normals = mesh
                .push_attributes(ShadingNormals::new(n), uvs, tangents)
                .ok_or("the scene has more shading normals than u32 indexes")?;
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
        assert_eq!(unit(Tessellation::Mesh(Rc::new(cube()))).triangles(), 12);
    }

    #[test]
    fn each_mesh_file_is_parsed_once() {
        let dir = std::env::temp_dir().join(format!("ggx-shape-build-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("t.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        let limits = Limits::default();
        let mut budget = Budget::new(&limits);
        let first = budget.mesh(0, &dir.join("t.obj")).unwrap_or_else(|_| panic!("cannot load"));
        // The same file by another path: parsed once, shared, counted once.
        let same = budget.mesh(1, &dir.join(".").join("t.obj")).unwrap_or_else(|_| panic!("cannot load"));
        assert!(Rc::ptr_eq(&first, &same));
        assert_eq!((budget.loads, budget.mesh_bytes), (1, first.heap_bytes()));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn triangles_are_limited_to_u32_whatever_max_triangles_says() {
        let limits = Limits { max_triangles: u64::MAX, max_memory: u64::MAX, ..Limits::default() };
        let mut budget = Budget::new(&limits);
        budget.add_triangles(0, MAX_SCENE_TRIANGLES).unwrap();
        let msg = budget.add_triangles(1, 1).unwrap_err();
        assert!(
            msg.starts_with("the triangles of shapes 0 to 1 (this one: 1) needs 4294967296, over 4294967295"),
            "{msg}"
        );
        // Under a smaller max_triangles, the usual limit message.
        let limits = Limits { max_triangles: 10, ..limits };
        let msg = Budget::new(&limits).add_triangles(0, 11).unwrap_err();
        assert!(msg.contains("needs 11, over the limit of 10 (max_triangles"), "{msg}");
    }
}
