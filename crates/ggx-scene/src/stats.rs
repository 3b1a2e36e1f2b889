//! [`SceneStats`]: counts for `ggx info`.

use std::fmt;

/// Sizes of a loaded scene.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneStats {
    /// Shapes in the file.
    pub shapes: usize,
    /// Triangles after tessellation.
    pub triangles: usize,
    /// Triangles with shading normals.
    pub smooth_triangles: usize,
    /// Defined materials.
    pub materials: usize,
    /// Emissive shapes.
    pub lights: usize,
    /// Emissive triangles with non-zero area.
    pub emitters: usize,
    /// Total emitting area.
    pub light_area: f32,
    /// Environment map `[width, height]`, if any.
    pub env_map: Option<[u32; 2]>,
}

impl fmt::Display for SceneStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "shapes:    {}", self.shapes)?;
        writeln!(f, "triangles: {} ({} with shading normals)", self.triangles, self.smooth_triangles)?;
        writeln!(f, "materials: {}", self.materials)?;
        writeln!(f, "lights:    {} ({} triangles, area {:.4})", self.lights, self.emitters, self.light_area)?;
        match self.env_map {
            Some([w, h]) => write!(f, "env map:   {w}x{h}"),
            None => write!(f, "env map:   none"),
        }
    }
}
