//! glTF 2.0 assets (`.gltf` with external or embedded buffers, `.glb`): meshes of every
//! triangle primitive mode through the node hierarchy, metallic-roughness materials with
//! their textures and extensions, and cameras. The `gltf` crate parses and validates the
//! JSON; buffers, accessors and images are read here, every size checked against the
//! [`Limits`] before anything is allocated.

mod accessor;
mod material;
mod sources;
mod tangents;

pub(crate) use sources::decode_image;

use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

use glam::{Affine3A, Mat4, Vec2, Vec3, Vec4};
use gltf::accessor::Dimensions;
use gltf::mesh::{Mode, Semantic};

use crate::geometry::Geometry;
use crate::limits::{Limit, Limits, read_regular_file_or};
use crate::material::Material;
use crate::punctual::{PUNCTUAL_DIRECTIONAL, PUNCTUAL_POINT, PUNCTUAL_SPOT, PunctualLight};
use crate::shorten::short_path;
use crate::texture::TextureSet;

/// Extensions ggx reads (others in `extensionsUsed` are ignored with a warning; in
/// `extensionsRequired`, refused).
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_anisotropy",
    "KHR_materials_clearcoat",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_texture_transform",
];

/// A camera found in the asset, in the asset's world space.
#[derive(Clone, Debug, PartialEq)]
pub struct GltfCamera {
    /// The camera's name (or `camera N`).
    pub name: String,
    /// Eye position.
    pub position: Vec3,
    /// Unit view direction (the node's -Z).
    pub forward: Vec3,
    /// Up (the node's +Y).
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y_degrees: f32,
    /// Width / height, when the file gives it.
    pub aspect: Option<f32>,
}

/// A loaded asset: primitives (object space), their placements, materials and cameras.
pub(crate) struct GltfAsset {
    /// Triangle primitives, each with its material (an index into `materials`).
    pub primitives: Vec<(Rc<Geometry>, usize)>,
    /// `(primitive, node-to-world)` for every node that shows a mesh.
    pub instances: Vec<(usize, Affine3A)>,
    /// Materials (`(name, material)`), texture indices already in the scene's set; the last
    /// is glTF's default material when a primitive has none.
    pub materials: Vec<(String, Material)>,
    /// Cameras, in node order.
    pub cameras: Vec<GltfCamera>,
    /// `KHR_lights_punctual` lights placed by their nodes.
    pub lights: Vec<PunctualLight>,
    /// What was ignored or approximated, one sentence each.
    pub warnings: Vec<String>,
    /// Bytes of the parsed geometry.
    pub bytes: u64,
}

impl GltfAsset {
    /// Triangles of every instance.
    pub fn triangles(&self) -> u64 {
        self.instances.iter().map(|(p, _)| self.primitives[*p].0.indices.len() as u64).sum()
    }
}

/// Loads the glTF (`.gltf` or `.glb`) at `path` within `limits` (`max_mesh_bytes` for the
/// file and each resource, `max_triangles` and `max_memory` for what it holds); its textures
/// are appended to `textures`. Errors and warnings start with the file.
pub(crate) fn load(path: &Path, limits: &Limits, textures: &mut TextureSet) -> Result<GltfAsset, String> {
    let shown = short_path(path);
    let file = |e: String| format!("{shown}: {e}");
    let bytes = read_regular_file_or(path, "glTF file", Limit::MeshBytes, limits).map_err(|e| file(e.to_string()))?;
    // The gltf crate subtracts the header size from the GLB's declared length unchecked.
    if let Some(len) = bytes.strip_prefix(b"glTF").and_then(|b| b.get(4..8)) {
        let len = u32::from_le_bytes([len[0], len[1], len[2], len[3]]);
        if len < 12 {
            return Err(file(format!("invalid GLB: declared length {len} is smaller than its 12-byte header")));
        }
    }
    // gltf-json's validation indexes the POSITION accessor before it checks the index
    // (gltf-json 1.4.1, mesh.rs): check that reference first.
    let unchecked =
        gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| file(format!("invalid glTF: {e}")))?;
    let accessors = unchecked.accessors().len();
    for (m, mesh) in unchecked.document.as_json().meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let position = prim.attributes.get(&gltf::json::validation::Checked::Valid(Semantic::Positions));
            if let Some(i) = position.filter(|i| i.value() >= accessors) {
                let at = format!("meshes[{m}].primitives[{p}].attributes.POSITION");
                return Err(file(format!(
                    "invalid glTF: {at}: accessor {} does not exist ({accessors} accessors)",
                    i.value()
                )));
            }
        }
    }
    // extensionsRequired: checked here against what ggx reads (the error names the extension),
    // then left out of gltf-json's validation, which refuses those it has no feature for
    // (KHR_materials_anisotropy, KHR_materials_clearcoat) although ggx reads them.
    let gltf::Gltf { document, blob } = unchecked;
    let mut json = document.into_json();
    for ext in std::mem::take(&mut json.extensions_required) {
        if !SUPPORTED_EXTENSIONS.contains(&ext.as_str()) {
            return Err(file(format!(
                "extensionsRequired: {ext} is not supported (ggx reads {})",
                SUPPORTED_EXTENSIONS.join(", ")
            )));
        }
    }
    let document = gltf::Document::from_json(json).map_err(|e| {
        file(match e {
            gltf::Error::Validation(problems) => {
                let shown: Vec<String> = problems.iter().take(4).map(|(path, e)| format!("{path}: {e}")).collect();
                let more = problems.len().saturating_sub(4);
                let more = if more > 0 { format!(" (and {more} more)") } else { String::new() };
                format!("invalid glTF: {}{more}", shown.join("; "))
            }
            other => format!("invalid glTF: {other}"),
        })
    })?;
    let gltf = gltf::Gltf { document, blob };
    let base_dir = path.parent().unwrap_or(Path::new("."));
    let mut warnings = Vec::new();
    let ignored: Vec<_> = gltf.extensions_used().filter(|e| !SUPPORTED_EXTENSIONS.contains(e)).collect();
    if !ignored.is_empty() {
        warnings.push(file(format!("ignores the extensions {}", ignored.join(", "))));
    }
    // Buffers: the GLB chunk or URIs, each at least its declared length.
    let mut memory = limits.max_memory;
    let mut buffers = Vec::new();
    for b in gltf.buffers() {
        let data = match b.source() {
            gltf::buffer::Source::Bin => {
                gltf.blob.clone().ok_or_else(|| file(format!("buffers[{}]: no GLB binary chunk", b.index())))?
            }
            gltf::buffer::Source::Uri(uri) => sources::read_uri(uri, base_dir, limits, limits.max_mesh_bytes)
                .map_err(|e| file(format!("buffers[{}]: {e}", b.index())))?,
        };
        if (data.len() as u64) < b.length() as u64 {
            return Err(file(format!(
                "buffers[{}]: {} bytes where byteLength is {}",
                b.index(),
                data.len(),
                b.length()
            )));
        }
        memory = memory.saturating_sub(data.len() as u64);
        buffers.push(data);
    }
    // Primitives: object-space geometry once per mesh primitive.
    let max_elements = limits.max_triangles.saturating_mul(3).min(memory / 16);
    let mut primitives = Vec::new();
    let mut primitive_index: HashMap<(usize, usize), usize> = HashMap::new();
    let mut material_slots: HashMap<Option<usize>, usize> = HashMap::new();
    let mut slot_materials: Vec<gltf::Material> = Vec::new();
    let mut bytes_used = 0u64;
    for mesh in gltf.meshes() {
        for prim in mesh.primitives() {
            let at = format!("meshes[{}].primitives[{}]", mesh.index(), prim.index());
            let mut notes = Vec::new();
            let read =
                read_primitive(&prim, &buffers, max_elements, &mut notes).map_err(|e| file(format!("{at}: {e}")))?;
            for note in notes.into_iter().map(&file) {
                if !warnings.contains(&note) {
                    warnings.push(note);
                }
            }
            let Some(g) = read else { continue };
            bytes_used = bytes_used.saturating_add(g.heap_bytes());
            if bytes_used > memory {
                let msg = format!(
                    "the meshes need more than the {} the memory limit leaves (max_memory)",
                    crate::format_bytes(memory)
                );
                return Err(file(msg));
            }
            let n = material_slots.len();
            let slot = *material_slots.entry(prim.material().index()).or_insert(n);
            if slot == slot_materials.len() {
                slot_materials.push(prim.material());
            }
            primitive_index.insert((mesh.index(), prim.index()), primitives.len());
            primitives.push((Rc::new(g), slot));
        }
    }
    // Materials, in slot order, with their textures (a primitive without one gets glTF's
    // default material, which `Primitive::material` returns with no index).
    let mut images = material::ImageCache::default();
    let mut materials = Vec::new();
    for m in &slot_materials {
        let index = m.index();
        let name = match (index, m.name()) {
            (Some(_), Some(n)) => n.to_owned(),
            (Some(i), None) => format!("material {i}"),
            (None, _) => "default".to_owned(),
        };
        let sources = material::Sources {
            root: gltf.document.as_json(),
            buffers: &buffers,
            base_dir,
            limits,
            memory: memory.saturating_sub(bytes_used),
        };
        let converted = material::convert(m, &sources, textures, &mut images, &mut warnings)
            .map_err(|e| file(format!("materials[{}]: {e}", index.map_or("default".to_owned(), |i| i.to_string()))))?;
        materials.push((name, converted));
    }
    if images.occlusion {
        warnings.push(file("occlusion textures are ignored (a path tracer computes occlusion)".to_owned()));
    }
    // Nodes: the default scene (or the first, or every root node), walked without recursion.
    let roots: Vec<gltf::Node> = match gltf.default_scene().or_else(|| gltf.scenes().next()) {
        Some(s) => s.nodes().collect(),
        None => {
            let children: std::collections::HashSet<usize> =
                gltf.nodes().flat_map(|n| n.children().map(|c| c.index())).collect();
            gltf.nodes().filter(|n| !children.contains(&n.index())).collect()
        }
    };
    let mut instances = Vec::new();
    let mut cameras = Vec::new();
    let mut lights = Vec::new();
    let mut visited = vec![false; gltf.nodes().len()];
    let mut stack: Vec<(gltf::Node, Mat4)> = roots.into_iter().map(|n| (n, Mat4::IDENTITY)).collect();
    while let Some((node, parent)) = stack.pop() {
        if std::mem::replace(&mut visited[node.index()], true) {
            return Err(file(format!(
                "nodes[{}] appears twice in the hierarchy (a node has one parent)",
                node.index()
            )));
        }
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        let world = parent * local;
        if !world.is_finite() {
            return Err(file(format!("nodes[{}]: the transform is not finite", node.index())));
        }
        if let Some(mesh) = node.mesh() {
            let affine = Affine3A::from_mat4(world);
            for prim in mesh.primitives() {
                if let Some(&p) = primitive_index.get(&(mesh.index(), prim.index())) {
                    instances.push((p, affine));
                }
            }
        }
        if let Some(cam) = node.camera() {
            match cam.projection() {
                gltf::camera::Projection::Perspective(p) => {
                    let position = world.transform_point3(Vec3::ZERO);
                    let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
                    let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
                    let fov = p.yfov().to_degrees();
                    if forward != Vec3::ZERO && up != Vec3::ZERO && fov > 0.0 && fov < 180.0 {
                        let name = cam.name().map_or_else(|| format!("camera {}", cam.index()), str::to_owned);
                        cameras.push(GltfCamera {
                            name,
                            position,
                            forward,
                            up,
                            fov_y_degrees: fov,
                            aspect: p.aspect_ratio(),
                        });
                    } else {
                        warnings.push(file(format!(
                            "cameras[{}] is degenerate (zero axis or field of view {fov}): skipped",
                            cam.index()
                        )));
                    }
                }
                gltf::camera::Projection::Orthographic(_) => {
                    warnings.push(file(format!(
                        "cameras[{}] is orthographic: skipped (ggx renders perspective cameras)",
                        cam.index()
                    )));
                }
            }
        }
        if let Some(light) = node.light() {
            match punctual(&light, world) {
                Some(l) => lights.push(l),
                None => warnings.push(file(format!(
                    "nodes[{}]: light {} is degenerate: skipped",
                    node.index(),
                    light.index()
                ))),
            }
        }
        for child in node.children() {
            stack.push((child, world));
        }
    }
    // Node order for cameras and instances (the stack visits siblings in reverse).
    instances.sort_by_key(|(p, _)| *p);
    let asset = GltfAsset { primitives, instances, materials, cameras, lights, warnings, bytes: bytes_used };
    if asset.triangles() > limits.max_triangles {
        return Err(file(format!(
            "{} triangles, over the limit of {} (max_triangles)",
            asset.triangles(),
            limits.max_triangles
        )));
    }
    Ok(asset)
}

/// A `KHR_lights_punctual` light at its node's `world` transform (position: the origin;
/// direction: -Z), `None` when a value is not finite or the direction degenerate.
fn punctual(light: &gltf::khr_lights_punctual::Light<'_>, world: Mat4) -> Option<PunctualLight> {
    use gltf::khr_lights_punctual::Kind;
    let intensity = Vec3::from(light.color()).max(Vec3::ZERO) * light.intensity().max(0.0);
    let position = world.transform_point3(Vec3::ZERO);
    let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
    let range = light.range().filter(|r| r.is_finite() && *r > 0.0).unwrap_or(0.0);
    let (kind, spot_scale, spot_offset) = match light.kind() {
        Kind::Point => (PUNCTUAL_POINT, 0.0, 0.0),
        Kind::Directional => (PUNCTUAL_DIRECTIONAL, 0.0, 0.0),
        Kind::Spot { inner_cone_angle, outer_cone_angle } => {
            let (ci, co) = (inner_cone_angle.cos(), outer_cone_angle.cos());
            let scale = 1.0 / (ci - co).max(1e-3);
            (PUNCTUAL_SPOT, scale, -co * scale)
        }
    };
    let l = PunctualLight {
        position: position.to_array(),
        kind,
        direction: direction.to_array(),
        range,
        intensity: intensity.to_array(),
        spot_scale,
        spot_offset,
        pad: [0; 3],
    };
    let finite = position.is_finite() && intensity.is_finite() && spot_scale.is_finite() && spot_offset.is_finite();
    (finite && (kind == PUNCTUAL_POINT || direction != Vec3::ZERO)).then_some(l)
}

/// One primitive as object-space geometry; `None` (with a warning) for points and lines.
fn read_primitive(
    prim: &gltf::Primitive<'_>,
    buffers: &[Vec<u8>],
    max: u64,
    warnings: &mut Vec<String>,
) -> Result<Option<Geometry>, String> {
    let mode = prim.mode();
    if matches!(mode, Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip) {
        warnings.push(format!("a {mode:?} primitive is skipped (ggx renders surfaces)"));
        return Ok(None);
    }
    if prim.get(&Semantic::Colors(0)).is_some() {
        warnings.push("COLOR_0 vertex colours are ignored (the base colour factor and texture are used)".to_owned());
    }
    if prim.morph_targets().len() > 0 {
        warnings.push("morph targets are ignored (the base shape is rendered)".to_owned());
    }
    let pos = prim.get(&Semantic::Positions).ok_or("no POSITION attribute")?;
    let positions =
        accessor::read_floats(&pos, &[Dimensions::Vec3], buffers, max).map_err(|e| format!("POSITION: {e}"))?;
    let vertices = positions.len() as u64 / 3;
    let attribute = |s: Semantic, dims: &[Dimensions], name: &str| -> Result<Option<Vec<f32>>, String> {
        let Some(a) = prim.get(&s) else { return Ok(None) };
        let v = accessor::read_floats(&a, dims, buffers, max).map_err(|e| format!("{name}: {e}"))?;
        let n = v.len() as u64 / dims_of(a.dimensions());
        if n != vertices {
            return Err(format!("{name} has {n} elements, POSITION {vertices}"));
        }
        Ok(Some(v))
    };
    let normals = attribute(Semantic::Normals, &[Dimensions::Vec3], "NORMAL")?;
    let uvs = attribute(Semantic::TexCoords(0), &[Dimensions::Vec2], "TEXCOORD_0")?;
    let tangents = attribute(Semantic::Tangents, &[Dimensions::Vec4], "TANGENT")?;
    let list: Vec<u32> = match prim.indices() {
        Some(acc) => accessor::read_indices(&acc, buffers, vertices, max)?,
        None => (0..u32::try_from(vertices).map_err(|_| "too many vertices")?).collect(),
    };
    let indices = triangles(mode, &list);
    // A normal map or anisotropy needs tangents: MikkTSpace when the file gives none.
    let material = prim.material();
    let needs_tangents = material.normal_texture().is_some()
        || material.extensions().is_some_and(|e| e.contains_key("KHR_materials_anisotropy"));
    let g = Geometry {
        positions: positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect(),
        normals: normals.map(|n| n.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2]).normalize_or_zero()).collect()),
        uvs: uvs.map(|n| n.chunks_exact(2).map(|p| Vec2::new(p[0], p[1])).collect()),
        tangents: tangents.map(|n| n.chunks_exact(4).map(|p| Vec4::new(p[0], p[1], p[2], p[3])).collect()),
        indices,
    };
    Ok(Some(if needs_tangents { tangents::with_mikktspace_tangents(g) } else { g }))
}

fn dims_of(d: Dimensions) -> u64 {
    match d {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        _ => 4,
    }
}

/// Triangles of a primitive's index list: lists as they are, strips and fans converted
/// (glTF 2.0 spec 3.7.2.1; strips alternate winding), degenerate triangles dropped.
fn triangles(mode: Mode, list: &[u32]) -> Vec<[u32; 3]> {
    let tris: Vec<[u32; 3]> = match mode {
        Mode::TriangleStrip => (2..list.len())
            .map(|i| if i % 2 == 0 { [list[i - 2], list[i - 1], list[i]] } else { [list[i - 1], list[i - 2], list[i]] })
            .collect(),
        Mode::TriangleFan => (2..list.len()).map(|i| [list[i - 1], list[i], list[0]]).collect(),
        _ => list.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
    };
    tris.into_iter().filter(|[a, b, c]| a != b && b != c && a != c).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_become_lists() {
        assert_eq!(triangles(Mode::Triangles, &[0, 1, 2, 3, 4]), vec![[0, 1, 2]]);
        assert_eq!(triangles(Mode::TriangleStrip, &[0, 1, 2, 3]), vec![[0, 1, 2], [2, 1, 3]]);
        assert_eq!(triangles(Mode::TriangleFan, &[0, 1, 2, 3]), vec![[1, 2, 0], [2, 3, 0]]);
        assert_eq!(triangles(Mode::Triangles, &[0, 0, 1]), Vec::<[u32; 3]>::new());
    }
}
