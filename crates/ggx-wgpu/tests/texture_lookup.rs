//! The path tracer's texture lookup (`scene.wgsl`'s `texture_sample` and what it calls:
//! `texture_ref_apply`, `wrap_coord`, `neighbour`, `texel_index`, `texel`) against ggx-scene's
//! `TextureSet::sample` on the CPU: 8-bit and float textures, every wrap mode on each axis,
//! bilinear and nearest, sRGB and linear slots, transforms, and hostile coordinates (NaN,
//! infinities, huge, tiny, texel centres and edges), over the same `surface` table the renderer
//! uploads (`scene_upload::push_textures`).
//!
//! A small compute entry point appended to the path tracer's source reads one probe (a
//! `TextureRef` and `uv`, 10 words) per invocation from the start of `surface` and writes the
//! filtered RGBA and the transformed coordinates `(s, t)`. The GPU performs the CPU's
//! operations in the same order; 8-bit channels and sRGB decoding go through tables computed
//! on the CPU. Two checks:
//!
//! * The transform `s = m0 u + m1 v + m2` (`TextureRef::apply`): Vulkan lets a driver contract
//!   and reorder it into fused multiply-adds (llvmpipe evaluates `m0 u + (m1 v + m2)` in some
//!   shaders), so `(s, t)` is bounded by `4 eps (|m0 u| + |m1 v| + |m2|)` (identity
//!   transforms: exact).
//! * Everything after it (wrap, texel indices, fetch, sRGB, bilinear blend) from the GPU's own
//!   `(s, t)`: the CPU lookup of the same coordinates (an identity `TextureRef`) within
//!   [`MAX_ULP`] ulps per channel (or [`ABS_FLOOR`] absolute near zero), which allows a driver
//!   that fuses the blend; measured on llvmpipe: bit-identical. Identity-transform probes are
//!   also compared end to end under the same bound.

use bytemuck::Zeroable;
use ggx_scene::{
    NO_INDEX, TEXTURE_NEAREST, TEXTURE_WRAP_S_SHIFT, TEXTURE_WRAP_T_SHIFT, Texels, TextureRef, TextureSet,
};
use ggx_wgpu::scene_upload::{Params, push_textures};
use ggx_wgpu::{GpuContext, GpuOptions};
use glam::{Vec2, Vec4};
use std::sync::mpsc;
use wgpu::util::DeviceExt;

/// Words per probe: the `TextureRef` (8) and `uv` (2).
const PROBE_WORDS: usize = 10;

/// Largest distance in ulps between a GPU and a CPU channel, from the same `(s, t)`.
const MAX_ULP: u32 = 4;

/// Below this absolute difference two channels agree whatever their ulp distance (around 0).
const ABS_FLOOR: f32 = 1e-6;

const PROBE_WGSL: &str = "
@compute @workgroup_size(64)
fn texture_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if 2u * i + 1u >= arrayLength(&output) {
        return;
    }
    let o = 10u * i;
    let r = load_texture_ref(o);
    let uv = vec2(surface_f32(o + 8u), surface_f32(o + 9u));
    output[2u * i] = texture_sample(r, uv);
    output[2u * i + 1u] = vec4(texture_ref_apply(r, uv), 0.0, 0.0);
}
";

/// xorshift32, deterministic.
struct Rng(u32);

impl Rng {
    fn next_u32(&mut self) -> u32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        x
    }

    /// Uniform in `[lo, hi)`.
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * (self.next_u32() >> 8) as f32 / (1u32 << 24) as f32
    }
}

/// Textures of every kind, each aliased with every wrap mode pair and both filters.
fn texture_set(rng: &mut Rng) -> TextureSet {
    let mut set = TextureSet::default();
    let mut images = Vec::new();
    for (w, h) in [(5, 3), (1, 1), (1, 4), (8, 8)] {
        let texels: Vec<u32> = (0..w * h).map(|_| rng.next_u32()).collect();
        images.push(set.push(w, h, &Texels::Rgba8(texels), 0).expect("8-bit texture"));
    }
    for (w, h) in [(4, 7), (2, 1)] {
        let mut texels: Vec<[f32; 4]> =
            (0..w * h).map(|_| [rng.range(-2.0, 8.0), rng.range(0.0, 1.0), rng.range(0.0, 1e4), 1.0]).collect();
        // Non-finite texels read as zero.
        texels[0][1] = f32::NAN;
        if texels.len() > 2 {
            texels[2][3] = f32::INFINITY;
        }
        images.push(set.push(w, h, &Texels::RgbaF32(texels), 0).expect("float texture"));
    }
    for &image in &images {
        for wrap_s in 0..4u32 {
            for wrap_t in 0..4u32 {
                for nearest in [0, TEXTURE_NEAREST] {
                    let flags = wrap_s << TEXTURE_WRAP_S_SHIFT | wrap_t << TEXTURE_WRAP_T_SHIFT | nearest;
                    set.alias(image, flags).expect("alias");
                }
            }
        }
    }
    set
}

/// Coordinates worth probing for a `w x h` texture, then random ones.
fn coordinates(rng: &mut Rng, w: u32, h: u32) -> Vec<Vec2> {
    let mut uvs = vec![
        Vec2::ZERO,
        Vec2::ONE,
        Vec2::splat(-0.0),
        Vec2::new(0.5 / w as f32, 0.5 / h as f32),
        Vec2::new(1.0 / w as f32, 1.0 / h as f32),
        Vec2::new(1.0 - 0.5 / w as f32, 1.0 + 0.5 / h as f32),
        Vec2::new(f32::NAN, 0.3),
        Vec2::new(0.3, f32::INFINITY),
        Vec2::new(f32::NEG_INFINITY, f32::NAN),
        Vec2::new(1e30, -1e30),
        Vec2::new(-1e-30, f32::MIN_POSITIVE),
        Vec2::new(1.0 - f32::EPSILON / 2.0, -1.0 + f32::EPSILON / 2.0),
        Vec2::new(2.0, -3.0),
        Vec2::new(1.5, 2.5),
    ];
    uvs.extend((0..40).map(|_| Vec2::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0))));
    uvs.extend((0..8).map(|_| Vec2::new(rng.range(-1e4, 1e4), rng.range(0.0, 1.0))));
    uvs
}

/// The probes: every texture with random slots (channel, sRGB, transform) at its coordinates,
/// plus a missing and an out-of-range texture.
fn probes(set: &TextureSet, rng: &mut Rng) -> Vec<(TextureRef, Vec2)> {
    let mut out = Vec::new();
    for (t, info) in set.infos.iter().enumerate() {
        for uv in coordinates(rng, info.width, info.height) {
            let mut r = TextureRef::new(t as u32, rng.next_u32() & 3, rng.next_u32() & 1 == 1);
            match rng.next_u32() % 4 {
                0 => {}
                1 => r = r.with_transform([rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)], 0.0, [1.0, 1.0]),
                _ => {
                    let offset = [rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)];
                    let scale = [rng.range(-3.0, 3.0), rng.range(0.1, 5.0)];
                    r = r.with_transform(offset, rng.range(-4.0, 4.0), scale);
                }
            }
            out.push((r, uv));
        }
    }
    out.push((TextureRef::NONE, Vec2::new(0.25, 0.5)));
    out.push((TextureRef::new(set.infos.len() as u32 + 5, 0, true), Vec2::new(0.25, 0.5)));
    assert_eq!(out[out.len() - 2].0.texture, NO_INDEX);
    out
}

/// Runs the probes on the GPU: RGBA and `(s, t, 0, 0)` per probe.
fn run_on_gpu(ctx: &GpuContext, set: &TextureSet, probes: &[(TextureRef, Vec2)]) -> Vec<(Vec4, Vec2)> {
    let device = ctx.device();
    let mut surface: Vec<u32> = Vec::new();
    for (r, uv) in probes {
        surface.extend_from_slice(bytemuck::cast_slice(&[*r]));
        surface.extend([uv.x.to_bits(), uv.y.to_bits()]);
    }
    assert_eq!(surface.len(), PROBE_WORDS * probes.len());
    let mut params = Params::zeroed();
    push_textures(&mut surface, set, &mut params);
    let source = format!("{}\n{PROBE_WGSL}", ggx_wgpu::path_tracer_wgsl());
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("texture probe"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("texture probe"),
        layout: None,
        module: &module,
        entry_point: Some("texture_probe"),
        compilation_options: Default::default(),
        cache: None,
    });
    let init = |label, contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
    };
    let params_buffer = init("probe params", bytemuck::bytes_of(&params), wgpu::BufferUsages::STORAGE);
    let surface_buffer = init("probe surface", bytemuck::cast_slice(&surface), wgpu::BufferUsages::STORAGE);
    let size = (probes.len() * 32) as u64;
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe output"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("texture probe"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: params_buffer.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 6, resource: output.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 7, resource: surface_buffer.as_entire_binding() },
        ],
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("texture probe") });
    {
        let mut pass = encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("texture probe"), timestamp_writes: None });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(probes.len().div_ceil(64) as u32, 1, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, size);
    ctx.queue().submit([encoder.finish()]);
    let (tx, rx) = mpsc::channel();
    readback.slice(..).map_async(wgpu::MapMode::Read, move |result| {
        let _ = tx.send(result);
    });
    device.poll(wgpu::PollType::wait_indefinitely()).expect("poll");
    rx.recv().expect("map callback").expect("map");
    let view = readback.slice(..).get_mapped_range().expect("mapped range");
    let values = bytemuck::cast_slice::<u8, [[f32; 4]; 2]>(&view)
        .iter()
        .map(|[rgba, st]| (Vec4::from_array(*rgba), Vec2::new(st[0], st[1])))
        .collect();
    drop(view);
    readback.unmap();
    values
}

/// Distance in ulps between two finite floats of any sign (`u32::MAX` when one is not finite).
fn ulps(a: f32, b: f32) -> u32 {
    if !a.is_finite() || !b.is_finite() {
        return if a.to_bits() == b.to_bits() { 0 } else { u32::MAX };
    }
    let key = |x: f32| {
        let bits = x.to_bits() as i64;
        if bits & 0x8000_0000 != 0 { -(bits & 0x7fff_ffff) } else { bits }
    };
    (key(a) - key(b)).unsigned_abs().min(u64::from(u32::MAX)) as u32
}

#[test]
fn the_wgsl_texture_lookup_matches_texture_set_sample() {
    let ctx = match GpuContext::new(GpuOptions::default()) {
        Ok(ctx) => ctx,
        Err(e) if e.is_no_adapter() && std::env::var("CI").as_deref() != Ok("true") => {
            eprintln!("\n*** SKIPPING the texture lookup test: {e}\n*** (set CI=true to make this a failure)\n");
            return;
        }
        Err(e) => panic!("no GPU context: {e}"),
    };
    let mut rng = Rng(0x9e37_79b9);
    let set = texture_set(&mut rng);
    let probes = probes(&set, &mut rng);
    let gpu = run_on_gpu(&ctx, &set, &probes);
    assert_eq!(gpu.len(), probes.len());
    let close = |got: Vec4, want: Vec4| {
        (0..4).all(|c| ulps(got[c], want[c]) <= MAX_ULP || (got[c] - want[c]).abs() <= ABS_FLOOR)
    };
    let (mut exact, mut worst, mut st_worst, mut failures) = (0usize, (0u32, 0usize), 0f32, Vec::new());
    for (i, ((r, uv), (got, st))) in probes.iter().zip(&gpu).enumerate() {
        let info = set.infos.get(r.texture as usize);
        // The transform, within its bound (relative to the terms' magnitude).
        let want_st = r.apply(*uv);
        let m = r.transform;
        for (k, (g, w)) in [(st.x, want_st.x), (st.y, want_st.y)].into_iter().enumerate() {
            let terms = (m[3 * k] * uv.x).abs() + (m[3 * k + 1] * uv.y).abs() + m[3 * k + 2].abs();
            let ok = if w.is_finite() { (g - w).abs() <= 4.0 * f32::EPSILON * terms } else { !g.is_finite() };
            if terms.is_finite() && terms > 0.0 {
                st_worst = st_worst.max((g - w).abs() / (f32::EPSILON * terms));
            }
            if !ok || (r.transform == TextureRef::IDENTITY && w.is_finite() && g.to_bits() != w.to_bits()) {
                failures.push(format!("probe {i}: {r:?} uv {uv}: gpu (s, t) {st} cpu {want_st}"));
            }
        }
        // The lookup from the GPU's coordinates (non-finite ones wrap to 0 on both sides).
        let finite_or_zero = |x: f32| if x.is_finite() { x } else { 0.0 };
        let same_st = Vec2::new(finite_or_zero(st.x), finite_or_zero(st.y));
        let want = set.sample(&TextureRef { transform: TextureRef::IDENTITY, ..*r }, same_st);
        assert!(want.is_finite(), "the CPU lookup is finite");
        let d = (0..4).map(|c| ulps(got[c], want[c])).max().unwrap_or(0);
        exact += usize::from(got.to_array().map(f32::to_bits) == want.to_array().map(f32::to_bits));
        if d > worst.0 {
            worst = (d, i);
        }
        if !close(*got, want) {
            failures.push(format!("probe {i}: {r:?} info {info:?} (s, t) {st}: gpu {got} cpu {want}"));
        }
        // End to end where the transform is exact.
        let end_to_end = set.sample(r, *uv);
        if r.transform == TextureRef::IDENTITY && !close(*got, end_to_end) {
            failures.push(format!("probe {i}: {r:?} info {info:?} uv {uv}: gpu {got} cpu {end_to_end}"));
        }
    }
    println!(
        "{} probes on {}: transform within {st_worst:.2} eps x terms; lookup {exact} bit-identical, max {} ulp \
         (probe {}); {} failures",
        probes.len(),
        ctx.describe(),
        worst.0,
        worst.1,
        failures.len()
    );
    assert!(
        failures.is_empty(),
        "{} lookups differ:\n{}",
        failures.len(),
        failures[..failures.len().min(20)].join("\n")
    );
}
