//! [`SceneTables`] uploaded: storage buffers, the bind group, and one compute pipeline per
//! kernel variant (`AREA`, `ENV`, `PLASTIC`, `DIELECTRIC`, `TEXTURES` override constants, ggx-render's
//! [`KernelVariant`]), built on first use.

use crate::context::{GpuContext, GpuError};
use crate::parity::checked;
use crate::scene_upload::{Params, SceneTables, non_empty};
use ggx_render::KernelVariant;
use std::collections::HashMap;
use std::sync::Mutex;
use wgpu::util::DeviceExt;

/// WGSL source of the path tracer: [`crate::GGX_CORE_WGSL`], [`crate::ENERGY_WGSL`],
/// `scene.wgsl` and `path_tracer.wgsl`.
pub fn path_tracer_wgsl() -> String {
    format!(
        "{}\n{}\n{}\n{}",
        crate::GGX_CORE_WGSL,
        crate::ENERGY_WGSL,
        include_str!("shaders/scene.wgsl"),
        include_str!("shaders/path_tracer.wgsl")
    )
}

/// Fails with [`GpuError::TooLarge`] when a buffer of `sizes` (what, bytes) exceeds what the
/// device can allocate or bind as one storage buffer: said before anything is uploaded, in
/// place of a validation error from inside wgpu.
fn check_buffer_sizes(ctx: &GpuContext, sizes: &[(&'static str, u64)]) -> Result<(), GpuError> {
    let limits = ctx.device().limits();
    let limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
    match sizes.iter().find(|(_, bytes)| *bytes > limit) {
        Some(&(what, bytes)) => Err(GpuError::TooLarge { what, bytes, limit }),
        None => Ok(()),
    }
}

/// The uploaded scene.
pub struct GpuScene {
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    pipelines: Mutex<HashMap<KernelVariant, wgpu::ComputePipeline>>,
    /// The bind group over all buffers.
    pub bind_group: wgpu::BindGroup,
    /// The per-dispatch [`crate::scene_upload::Params`] (read-only storage).
    pub params: wgpu::Buffer,
    /// Per-pixel `vec4<f32>`: radiance sum, rays (bits).
    pub output: wgpu::Buffer,
    /// Mappable copy of `output`.
    pub readback: wgpu::Buffer,
    /// Bytes of `output`.
    pub output_size: u64,
}

impl GpuScene {
    /// Uploads `tables`; the shader module is compiled here, pipelines on first use.
    pub fn new(ctx: &GpuContext, tables: &SceneTables) -> Result<GpuScene, GpuError> {
        let device = ctx.device();
        let pixels = u64::from(tables.params.width) * u64::from(tables.params.height);
        let output_size = pixels * 16;
        let (nodes, triangles) = (tables.nodes(), tables.triangles());
        let (normals, materials) = (non_empty(&tables.normals), non_empty(&tables.materials));
        let table = non_empty(&tables.table);
        let surface = non_empty(&tables.surface);
        let sizes = [
            ("BVH nodes", size_of_val(nodes.as_slice()) as u64),
            ("triangles", size_of_val(triangles.as_slice()) as u64),
            ("shading normals", size_of_val(normals.as_slice()) as u64),
            ("materials", size_of_val(materials.as_slice()) as u64),
            ("light and environment tables", size_of_val(table.as_slice()) as u64),
            ("emitters, textures, texture coordinates and punctual lights", size_of_val(surface.as_slice()) as u64),
            ("image", output_size),
        ];
        check_buffer_sizes(ctx, &sizes)?;
        // Offsets into `surface` are u32 words.
        if surface.len() as u64 > u64::from(u32::MAX) {
            let bytes = size_of_val(surface.as_slice()) as u64;
            return Err(GpuError::TooLarge {
                what: "emitters, textures, texture coordinates and punctual lights",
                bytes,
                limit: 4 * u64::from(u32::MAX),
            });
        }
        checked(device, || {
            let source = path_tracer_wgsl();
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("ggx path tracer"),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
            let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
                count: None,
            };
            let storage = |binding| entry(binding, wgpu::BufferBindingType::Storage { read_only: true });
            let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("ggx path tracer"),
                entries: &[
                    storage(0),
                    storage(1),
                    storage(2),
                    storage(3),
                    storage(4),
                    storage(5),
                    entry(6, wgpu::BufferBindingType::Storage { read_only: false }),
                    storage(7),
                ],
            });
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("ggx path tracer"),
                bind_group_layouts: &[Some(&bind_group_layout)],
                immediate_size: 0,
            });
            let init = |label, contents: &[u8]| {
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage: wgpu::BufferUsages::STORAGE,
                })
            };
            let nodes = init("bvh nodes", bytemuck::cast_slice(&nodes));
            let triangles = init("triangles", bytemuck::cast_slice(&triangles));
            let normals = init("shading normals", bytemuck::cast_slice(&normals));
            let materials = init("materials", bytemuck::cast_slice(&materials));
            let table = init("tables", bytemuck::cast_slice(&table));
            let surface = init("surface", bytemuck::cast_slice(&surface));
            let params = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("params"),
                size: size_of::<Params>() as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let buffer = |label, usage| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: output_size,
                    usage,
                    mapped_at_creation: false,
                })
            };
            let output = buffer("radiance sums", wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC);
            let readback = buffer("radiance readback", wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST);
            let buffers = [&params, &nodes, &triangles, &normals, &materials, &table, &output, &surface];
            let entries: Vec<wgpu::BindGroupEntry> = buffers
                .iter()
                .enumerate()
                .map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32, resource: b.as_entire_binding() })
                .collect();
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ggx path tracer"),
                layout: &bind_group_layout,
                entries: &entries,
            });
            GpuScene {
                module,
                layout,
                pipelines: Mutex::new(HashMap::new()),
                bind_group,
                params,
                output,
                readback,
                output_size,
            }
        })
    }

    /// The pipeline of `variant`, compiled on first use and cached.
    pub fn pipeline(&self, ctx: &GpuContext, variant: KernelVariant) -> Result<wgpu::ComputePipeline, GpuError> {
        let mut cache = self.pipelines.lock().map_err(|e| GpuError::Wgpu(e.to_string()))?;
        if let Some(p) = cache.get(&variant) {
            return Ok(p.clone());
        }
        let constants = [
            ("AREA", f64::from(u8::from(variant.area))),
            ("ENV", f64::from(u8::from(variant.env))),
            ("PLASTIC", f64::from(u8::from(variant.plastic))),
            ("DIELECTRIC", f64::from(u8::from(variant.dielectric))),
            ("TEXTURES", f64::from(u8::from(variant.textures))),
        ];
        let pipeline = checked(ctx.device(), || {
            ctx.device().create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(variant.name()),
                layout: Some(&self.layout),
                module: &self.module,
                entry_point: Some("render"),
                compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
                cache: None,
            })
        })?;
        cache.insert(variant, pipeline.clone());
        Ok(pipeline)
    }
}
