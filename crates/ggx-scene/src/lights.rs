//! Area lights: the emissive shapes, their triangles, and the distribution over emissive
//! triangles used for next-event estimation.

use std::f32::consts::PI;

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::distribution::Distribution1D;
use crate::material::luminance;
use crate::mesh::TriangleMesh;

/// One emissive shape: a contiguous range of [`TriangleMesh::triangles`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaLight {
    /// Index of the shape in the scene file's `[[shapes]]`.
    pub shape: u32,
    /// First triangle of the shape.
    pub first_triangle: u32,
    /// Number of triangles.
    pub triangle_count: u32,
    /// Index into [`crate::Scene::materials`].
    pub material: u32,
    /// Emitted radiance.
    pub radiance: Vec3,
    /// Total surface area (world space).
    pub area: f32,
}

impl AreaLight {
    /// Luminance of the emitted power of a one-sided Lambertian emitter, `pi * L * A`.
    pub fn power(&self) -> f32 {
        PI * luminance(self.radiance) * self.area
    }
}

/// One emissive triangle with non-zero area (16 bytes, GPU-uploadable).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Emitter {
    /// Index into [`TriangleMesh::triangles`].
    pub triangle: u32,
    /// Index into [`AreaLights::lights`].
    pub light: u32,
    /// Triangle area.
    pub area: f32,
    /// Probability of choosing this emitter (same as [`AreaLights::pmf`]).
    pub pmf: f32,
}

/// All area lights and the power distribution over their triangles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AreaLights {
    /// The emissive shapes.
    pub lights: Vec<AreaLight>,
    /// The emissive triangles with non-zero area.
    pub emitters: Vec<Emitter>,
    /// Distribution over `emitters` with weights `area * luminance(radiance)`, i.e.
    /// proportional to emitted power.
    pub distribution: Distribution1D,
}

impl AreaLights {
    /// Collects the emitters of `lights`, links each triangle to its emitter
    /// ([`crate::Triangle::emitter`]) and builds the power distribution.
    pub fn new(lights: Vec<AreaLight>, mesh: &mut TriangleMesh) -> Self {
        let mut emitters = Vec::new();
        let mut weights = Vec::new();
        for (l, light) in lights.iter().enumerate() {
            let range = light.first_triangle as usize..(light.first_triangle + light.triangle_count) as usize;
            for (t, tri) in mesh.triangles.iter_mut().enumerate().take(range.end).skip(range.start) {
                let area = tri.area();
                if area > 0.0 {
                    tri.emitter = emitters.len() as u32;
                    emitters.push(Emitter { triangle: t as u32, light: l as u32, area, pmf: 0.0 });
                    weights.push(area * luminance(light.radiance));
                }
            }
        }
        let distribution = Distribution1D::new(&weights);
        for (i, e) in emitters.iter_mut().enumerate() {
            e.pmf = distribution.pmf(i);
        }
        Self { lights, emitters, distribution }
    }

    /// `true` when the scene has no area lights.
    pub fn is_empty(&self) -> bool {
        self.emitters.is_empty()
    }

    /// Picks an emitter proportionally to power. Returns `(emitter index, pmf, u remapped to
    /// [0, 1))`, or `None` when there are no lights.
    #[inline]
    pub fn sample(&self, u: f32) -> Option<(usize, f32, f32)> {
        self.distribution.sample_discrete(u)
    }

    /// Probability of picking emitter `i`.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        self.distribution.pmf(i)
    }

    /// Area density of sampling a point on emitter `i` uniformly after picking it:
    /// `pmf / area`.
    #[inline]
    pub fn pdf_area(&self, i: usize) -> f32 {
        self.emitters.get(i).map_or(0.0, |e| self.pmf(i) / e.area)
    }

    /// Total emitting area.
    pub fn total_area(&self) -> f32 {
        self.lights.iter().map(|l| l.area).sum()
    }
}
