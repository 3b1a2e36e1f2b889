//! # ggx-wgpu
//!
//! The GPU twin of [`ggx_core`]: [`GGX_CORE_WGSL`] and [`ENERGY_WGSL`] mirror the crate
//! function by function in WGSL, and [`run_parity`] runs every mirrored function on a wgpu
//! adapter over edge-case input tables and compares the results with ggx-core on the CPU
//! (sequences bit for bit, floating-point math within a stated ULP / absolute bound).
//! [`WgpuRenderer`] is ggx-cpu's path tracer on the GPU: the same passes, sample streams and
//! integrator, so it renders the same image up to floating-point differences.
//!
//! ```no_run
//! let ctx = ggx_wgpu::GpuContext::new(Default::default())?;
//! println!("{}", ctx.describe());
//! let report = ggx_wgpu::run_parity(&ctx)?;
//! print!("{}", report.table());
//! assert!(report.passed());
//! # Ok::<(), ggx_wgpu::GpuError>(())
//! ```
#![deny(missing_docs)]

pub mod bvh_flat;
mod context;
mod gpu_scene;
mod parity;
mod renderer;
pub mod scene_upload;

pub use context::{GpuContext, GpuError, GpuOptions};
pub use ggx_render::KernelVariant;
pub use gpu_scene::path_tracer_wgsl;
pub use parity::{Bound, Contract, GroupReport, ParityReport, ProbeReport, RowReport, Witness, run_parity};
pub use renderer::{DISPATCH_PATHS, WgpuRenderer};

/// WGSL source of the ggx-core mirror: constants, structs and functions, no entry points and
/// no bindings, so it can be prepended to any shader.
pub const GGX_CORE_WGSL: &str = include_str!("shaders/ggx_core.wgsl");

/// WGSL source of ggx-core's energy compensation, compensated BSDFs and thin sheet; it expects
/// [`GGX_CORE_WGSL`] in front of it and `fn energy_table(i: u32) -> f32` from the shader that
/// includes it.
pub const ENERGY_WGSL: &str = include_str!("shaders/energy.wgsl");

/// WGSL source of the parity kernel; it expects [`GGX_CORE_WGSL`] and [`ENERGY_WGSL`] in front of
/// it, in that order, and defines energy.wgsl's `energy_table` over its binding 4.
pub const PARITY_WGSL: &str = include_str!("shaders/parity.wgsl");

/// The `SOBOL_DIRECTIONS` constant of [`GGX_CORE_WGSL`] as generated from
/// [`ggx_core::sequence::SOBOL_DIRECTIONS`]; a test checks that the shader contains exactly this.
pub fn sobol_directions_wgsl() -> String {
    let mut s = String::from("const SOBOL_DIRECTIONS: array<array<u32, 32>, 4> = array<array<u32, 32>, 4>(\n");
    for dim in &ggx_core::sequence::SOBOL_DIRECTIONS {
        s.push_str("    array<u32, 32>(\n");
        for row in dim.chunks(8) {
            let words: Vec<String> = row.iter().map(|w| format!("{w:#010x}u")).collect();
            s.push_str(&format!("        {},\n", words.join(", ")));
        }
        s.push_str("    ),\n");
    }
    s.push_str(");\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(source: &str) -> naga::Module {
        naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)))
    }

    fn validate(module: &naga::Module) {
        let mut validator = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), Default::default());
        if let Err(e) = validator.validate(module) {
            panic!("{:?}", e.into_inner());
        }
    }

    #[test]
    fn sobol_table_matches_ggx_core() {
        let expected = sobol_directions_wgsl();
        assert!(GGX_CORE_WGSL.contains(&expected), "ggx_core.wgsl must contain exactly:\n{expected}");
    }

    #[test]
    fn shaders_parse_and_validate() {
        validate(&parse(GGX_CORE_WGSL));
        // The parity kernel: GGX_CORE_WGSL, ENERGY_WGSL, PARITY_WGSL, whole and as each row's
        // pipeline compiles it (one arm of its switch).
        let parity = crate::parity::parity_source();
        assert!(parity.starts_with(GGX_CORE_WGSL) && parity.contains(ENERGY_WGSL) && parity.ends_with(PARITY_WGSL));
        validate(&parse(&parity));
        for (name, source) in crate::parity::kernel_sources() {
            assert!(source.starts_with(GGX_CORE_WGSL) && source.contains(ENERGY_WGSL), "{name}");
            validate(&parse(&source));
        }
        validate(&parse(&path_tracer_wgsl()));
    }

    /// Size of a WGSL struct and the offsets of its members, by name.
    fn wgsl_layout(module: &naga::Module, name: &str) -> (u32, Vec<(String, u32)>) {
        let ty = module.types.iter().find(|(_, t)| t.name.as_deref() == Some(name)).expect(name).1;
        match &ty.inner {
            naga::TypeInner::Struct { members, span } => {
                (*span, members.iter().map(|m| (m.name.clone().unwrap(), m.offset)).collect())
            }
            _ => panic!("{name} is not a struct"),
        }
    }

    macro_rules! assert_layout {
        ($module:expr, $ty:ty, $($field:ident),+) => {{
            let (size, members) = wgsl_layout($module, stringify!($ty));
            assert_eq!(size as usize, size_of::<$ty>(), "size of {}", stringify!($ty));
            let rust = [$((stringify!($field).to_string(), core::mem::offset_of!($ty, $field) as u32)),+];
            assert_eq!(members, rust, "members of {}", stringify!($ty));
        }};
    }

    #[test]
    fn struct_layouts_match_the_rust_pod_structs() {
        use ggx_core::{CounterRng, FresnelParams, GgxConductor, GgxDielectric, SampleStream, TrowbridgeReitz};
        let module = parse(GGX_CORE_WGSL);
        assert_layout!(&module, TrowbridgeReitz, alpha_x, alpha_y);
        assert_layout!(&module, FresnelParams, kind, eta, pad, a, b);
        assert_layout!(&module, GgxConductor, distribution, pad, fresnel);
        assert_layout!(&module, GgxDielectric, distribution, eta, pad);
        assert_layout!(&module, CounterRng, key, counter);
        assert_layout!(&module, SampleStream, kind, seed, sample_index, dimension);
        assert_eq!(size_of::<FresnelParams>(), 48);
        assert_eq!(size_of::<GgxConductor>(), 64);
        assert_eq!(size_of::<GgxDielectric>(), 16);
    }

    #[test]
    fn path_tracer_layouts_match_the_rust_pod_structs() {
        use crate::bvh_flat::BvhNode;
        use crate::scene_upload::{MaterialRecord, Params};
        use ggx_core::{GgxConductorMs, GgxDielectricMs, GltfMetalRough};
        use ggx_scene::{Emitter, PunctualLight, ShadingNormals, TextureInfo, Triangle};
        let module = parse(&path_tracer_wgsl());
        assert_layout!(&module, BvhNode, min, prim_count, max, first_index);
        assert_layout!(&module, Triangle, v0, material, v1, normals, v2, emitter);
        assert_layout!(&module, ShadingNormals, normals);
        assert_layout!(&module, Emitter, triangle, light, area, pmf);
        let (size, members) = wgsl_layout(&module, "Material");
        assert_eq!(size as usize, size_of::<MaterialRecord>());
        let rust = [
            ("conductor", core::mem::offset_of!(MaterialRecord, conductor)),
            ("albedo", core::mem::offset_of!(MaterialRecord, albedo)),
            ("kind", core::mem::offset_of!(MaterialRecord, kind)),
            ("emission", core::mem::offset_of!(MaterialRecord, emission)),
            ("ior", core::mem::offset_of!(MaterialRecord, ior)),
            ("extra", core::mem::offset_of!(MaterialRecord, extra)),
            ("sampling", core::mem::offset_of!(MaterialRecord, sampling)),
            ("compensation", core::mem::offset_of!(MaterialRecord, compensation)),
            ("surface", core::mem::offset_of!(MaterialRecord, surface)),
            ("specular_weight", core::mem::offset_of!(MaterialRecord, specular_weight)),
            ("p_specular", core::mem::offset_of!(MaterialRecord, p_specular)),
        ]
        .map(|(n, o)| (n.to_string(), o as u32));
        assert_eq!(members, rust, "members of Material");
        assert_layout!(
            &module,
            Params,
            cam_position,
            tan_half_fov,
            cam_forward,
            aspect,
            cam_right,
            width_f,
            cam_up,
            height_f,
            env_radiance,
            env_scale,
            env_to_map,
            env_to_world,
            width,
            height,
            y0,
            rows,
            s0,
            s1,
            sequence,
            seed,
            light_strategy,
            max_depth,
            roulette_depth,
            draw_lobe,
            emitter_count,
            env_kind,
            env_width,
            env_height,
            light_cdf,
            env_func,
            env_conditional_cdf,
            env_marginal_cdf,
            env_texels,
            env_marginal_integral,
            energy_tables,
            uvs,
            uv_count,
            tangents,
            tangent_count,
            texture_infos,
            texture_count,
            texture_unorm,
            texture_words,
            punctual_lights,
            punctual_count,
            emitters,
            env_light,
            pad3
        );
        assert_eq!(size_of::<Params>(), 256);
        assert_eq!(size_of::<MaterialRecord>(), 128);
        assert_eq!(size_of::<crate::scene_upload::MetalRoughRecord>(), 60 * 4);
        assert_layout!(
            &module,
            PunctualLight,
            position,
            kind,
            direction,
            range,
            intensity,
            spot_scale,
            spot_offset,
            pad
        );
        assert_layout!(&module, TextureInfo, offset, width, height, flags);
        assert_layout!(
            &module,
            GltfMetalRough,
            base_color,
            metallic,
            f0,
            specular_weight,
            distribution,
            p_specular,
            pad
        );
        assert_layout!(&module, GgxConductorMs, conductor, f_avg, compensation);
        assert_layout!(&module, GgxDielectricMs, dielectric, compensation, pad);
    }

    /// `path_tracer.wgsl`'s `MR_*` word offsets are those of [`MetalRoughRecord`]'s fields.
    ///
    /// [`MetalRoughRecord`]: crate::scene_upload::MetalRoughRecord
    #[test]
    fn metal_rough_record_offsets_match_the_shader() {
        use crate::scene_upload::MetalRoughRecord;
        let source = include_str!("shaders/path_tracer.wgsl");
        let constant = |name: &str| -> usize {
            let key = format!("const {name}: u32 = ");
            let rest = &source[source.find(&key).unwrap_or_else(|| panic!("{key}")) + key.len()..];
            rest[..rest.find('u').unwrap()].parse().unwrap()
        };
        macro_rules! check {
            ($($name:literal => $field:ident),+ $(,)?) => {$(
                assert_eq!(constant($name) * 4, core::mem::offset_of!(MetalRoughRecord, $field), $name);
            )+};
        }
        check!(
            "MR_BASE_COLOR" => base_color,
            "MR_METALLIC" => metallic,
            "MR_EMISSION" => emission,
            "MR_ROUGHNESS" => roughness,
            "MR_SPECULAR_COLOR" => specular_color,
            "MR_SPECULAR" => specular,
            "MR_IOR" => ior,
            "MR_NORMAL_SCALE" => normal_scale,
            "MR_ANISOTROPY" => anisotropy,
            "MR_ANISOTROPY_COS_SIN" => anisotropy_cos_sin,
            "MR_BASE_COLOR_TEXTURE" => base_color_texture,
            "MR_METALLIC_TEXTURE" => metallic_texture,
            "MR_ROUGHNESS_TEXTURE" => roughness_texture,
            "MR_NORMAL_TEXTURE" => normal_texture,
            "MR_EMISSION_TEXTURE" => emission_texture,
        );
        assert_eq!(size_of::<ggx_scene::TextureRef>(), 32, "load_texture_ref reads 8 words");
        assert_eq!(size_of::<ggx_scene::PunctualLight>(), 16 * 4, "load_punctual reads 16 words");
    }

    /// `energy.wgsl`'s table offsets and dims are those of the tables the upload appends.
    #[test]
    fn energy_table_offsets_match_the_upload() {
        use ggx_core::energy_dielectric::{coat_albedo_table, dielectric_albedo_outside_table};
        let constant = |name: &str| -> usize {
            let key = format!("const {name}: u32 = ");
            let rest = &ENERGY_WGSL[ENERGY_WGSL.find(&key).unwrap_or_else(|| panic!("{key}")) + key.len()..];
            rest[..rest.find('u').unwrap()].parse().unwrap()
        };
        let tables = crate::scene_upload::energy_tables();
        let mut offsets = vec![0];
        for t in &tables {
            offsets.push(offsets.last().unwrap() + t.len());
        }
        let names =
            ["ENERGY_E", "ENERGY_E_AVG", "ENERGY_E_T_OUTSIDE", "ENERGY_E_T_INSIDE", "ENERGY_E_R", "ENERGY_E_R_AVG"];
        for (name, offset) in names.iter().zip(&offsets) {
            assert_eq!(constant(name), *offset, "{name}");
        }
        assert_eq!(constant("ENERGY_TABLES_LEN"), offsets[6]);
        assert_eq!(constant("ENERGY_N"), ggx_core::energy_tables::N);
        let [n_eta, n_alpha, n_mu] = dielectric_albedo_outside_table().1;
        assert_eq!(coat_albedo_table().1, [n_eta, n_alpha, n_mu]);
        assert_eq!(
            [constant("DIELECTRIC_N_ETA"), constant("DIELECTRIC_N_ALPHA"), constant("DIELECTRIC_N_MU")],
            [n_eta, n_alpha, n_mu]
        );
    }
}
