//! Renders every scene in `scenes/` on the adapter and on ggx-cpu with the same seed, at low
//! resolution, and compares the images.
//!
//! Both sides draw the same random numbers in the same order, so a path is the same path on
//! both until float differences (transcendentals in the environment lookups, a few ulps in
//! ggx-core's formulas, ties between triangles) flip a branch: a texel, a Russian-roulette
//! decision, a shading-normal sign. Such a flip changes a whole path, so the images are not
//! bit-identical, but almost every pixel agrees to float precision. Without an adapter the
//! test skips loudly, unless `CI=true`, where a missing adapter is a failure.

use ggx_cpu::{AccelKind, RenderControl, RenderOptions, Renderer};
use ggx_film::compare;
use ggx_wgpu::{GpuContext, GpuOptions, WgpuRenderer};
use std::path::Path;

/// Per-channel relative error under which a pixel counts as equal.
const PIXEL_TOLERANCE: f64 = 1e-3;

/// Largest share of pixels over [`PIXEL_TOLERANCE`] and largest relMSE for a scene.
///
/// * Without an environment map every operation on a path is a mirrored ggx-core function
///   (within a few ulps, see the parity harness) or plain arithmetic in the same order, so
///   measured on llvmpipe the images agree to 2e-7 relative error: no pixel may exceed 1e-3
///   and relMSE must stay below 1e-12.
/// * Environment maps go through `atan2`, `acos`, `sin` and `cos`, which Vulkan lets a driver
///   compute to a few ulps (llvmpipe does not round like libm). A direction whose texel
///   index, CDF segment or Russian-roulette decision flips then follows another path;
///   measured at 32x24, 8 spp: up to 3.9% of pixels over 1e-3 (grazing, anisotropic), relMSE
///   up to 3.1e-5 (bunny: a handful of pixels, max relative error 0.13). Bounds: 8% of
///   pixels and relMSE 2e-4, a few times the measurement, far below what a sampling
///   difference gives (a wrong dimension or order changes nearly every pixel, relMSE > 1e-2).
/// * Glass: a rough refraction amplifies a sampled normal a few ulps off near grazing
///   transmission (the parity harness bounds refracted rough samples by 64 ulps,
///   `REFRACTED_UNIT`, not bit for bit), and a glass sphere is a lens that magnifies such a difference where the image behind it has an
///   edge, so a few pixels take the other side of it (measured with `cargo xtask diff` at 128
///   px, 32 spp: glass 0.41 % of pixels, relMSE 1.8e-5). Under an environment map a flipped
///   decision sends a path through another sequence of refractions (glass-bunny at 32x24:
///   0.78 % of pixels, relMSE 2.9e-4). Bounds: 2 % and 1e-4 without a map, 8 % and 1e-3 with.
fn bounds(features: &ggx_scene::SceneFeatures) -> (f64, f64) {
    match (features.env_map, features.dielectrics) {
        (true, true) => (0.08, 1e-3),
        (true, false) => (0.08, 2e-4),
        (false, true) => (0.02, 1e-4),
        (false, false) => (0.0, 1e-12),
    }
}

#[test]
fn every_scene_matches_the_cpu_render() {
    let ctx = match GpuContext::new(GpuOptions::default()) {
        Ok(ctx) => ctx,
        Err(e) if e.is_no_adapter() && std::env::var("CI").as_deref() != Ok("true") => {
            eprintln!("\n*** SKIPPING the GPU render parity test: {e}\n*** (set CI=true to make this a failure)\n");
            return;
        }
        Err(e) => panic!("no GPU context: {e}"),
    };
    eprintln!("adapter: {}", ctx.describe());
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .expect("scenes/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    names.sort();
    let mut failures = Vec::new();
    for path in &names {
        let name = path.file_name().unwrap_or_default().to_string_lossy().into_owned();
        let mut scene = ggx_scene::load_scene(path).expect("scene loads");
        scene.camera.resolution = [32, 24];
        scene.integrator.spp = 8;
        scene.integrator.time_budget = None;
        let options = RenderOptions::default();
        let cpu =
            Renderer::new(&scene, AccelKind::Bvh2).render(&options, &RenderControl::default()).expect("cpu render");
        let gpu = WgpuRenderer::new(&scene, &ctx)
            .and_then(|r| r.render(&options, &RenderControl::default()))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((gpu.spp, gpu.kernel), (cpu.spp, cpu.kernel), "{name}");
        let m = compare(&gpu.film.mean(), &cpu.film.mean(), PIXEL_TOLERANCE).expect("same size");
        let (max_over, max_rel_mse) = bounds(&scene.features);
        println!("{name:<24} rays gpu {} cpu {}: {m}", gpu.rays, cpu.rays);
        if m.over_tolerance > max_over || m.rel_mse > max_rel_mse {
            failures.push(format!("{name}: {m}"));
        }
    }
    assert!(failures.is_empty(), "GPU renders differ from the CPU:\n{}", failures.join("\n"));
}

/// A context, or `None` (test skipped loudly) where no adapter exists outside CI.
fn context_or_skip(what: &str) -> Option<GpuContext> {
    match GpuContext::new(GpuOptions::default()) {
        Ok(ctx) => Some(ctx),
        Err(e) if e.is_no_adapter() && std::env::var("CI").as_deref() != Ok("true") => {
            eprintln!("\n*** SKIPPING {what}: {e}\n*** (set CI=true to make this a failure)\n");
            None
        }
        Err(e) => panic!("no GPU context: {e}"),
    }
}

/// A scene without shapes: the BVH is the one-node placeholder, which the traversal must
/// recognise before reading a child (it used to hit the placeholder's box and read past the
/// node array, 80x slower). Only the environment is seen, one camera ray per sample.
#[test]
fn an_empty_scene_traces_one_ray_per_sample_and_sees_the_environment() {
    let Some(ctx) = context_or_skip("the empty-scene test") else { return };
    let text = "[camera]\nposition = [0, 0, 0.5]\nlook_at = [0, 0, 0]\nresolution = [24, 16]\n\
                [integrator]\nspp = 4\n[environment]\ntype = \"constant\"\nradiance = [0.25, 0.5, 1.0]\n";
    let scene = ggx_scene::parse_scene(text, "empty.toml", Path::new(".")).expect("scene");
    let gpu = WgpuRenderer::new(&scene, &ctx)
        .and_then(|r| r.render(&RenderOptions::default(), &RenderControl::default()))
        .expect("gpu render");
    let cpu = Renderer::new(&scene, AccelKind::Bvh2).render(&RenderOptions::default(), &RenderControl::default());
    let cpu = cpu.expect("cpu render");
    assert_eq!((gpu.rays, cpu.rays), (24 * 16 * 4, 24 * 16 * 4));
    let env = ggx_film::Vec3::new(0.25, 0.5, 1.0);
    assert!(gpu.film.mean().iter().all(|p| *p == env), "every pixel sees the environment");
}

/// A buffer larger than the device allows is refused by name before anything is uploaded,
/// not reported as a raw wgpu validation error.
#[test]
fn an_image_too_large_for_the_device_is_a_clear_error() {
    let Some(ctx) = context_or_skip("the buffer-limit test") else { return };
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut scene = ggx_scene::load_scene(&dir.join("furnace.toml")).expect("scene loads");
    scene.camera.resolution = [16384, 16384];
    let err = WgpuRenderer::new(&scene, &ctx).err().expect("a 4 GiB image buffer is refused");
    assert!(matches!(err, ggx_wgpu::GpuError::TooLarge { what: "image", .. }), "{err}");
    assert!(err.to_string().contains("--backend cpu"), "{err}");
}

/// The generic kernel returns the specialized kernel's image bit for bit, and the cancel flag,
/// checked between dispatches, stops the render after the pass in which it was set.
#[test]
fn generic_kernel_cancel_and_progress() {
    let ctx = match GpuContext::new(GpuOptions::default()) {
        Ok(ctx) => ctx,
        Err(e) if e.is_no_adapter() && std::env::var("CI").as_deref() != Ok("true") => {
            eprintln!("\n*** SKIPPING the GPU renderer test: {e}\n*** (set CI=true to make this a failure)\n");
            return;
        }
        Err(e) => panic!("no GPU context: {e}"),
    };
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell.toml");
    let mut scene = ggx_scene::load_scene(&path).expect("scene loads");
    scene.camera.resolution = [16, 12];
    scene.integrator.spp = 4;
    let renderer = WgpuRenderer::new(&scene, &ctx).expect("upload");
    let control = RenderControl::default();
    let specialized = renderer.render(&RenderOptions::default(), &control).expect("render");
    let generic =
        renderer.render(&RenderOptions { specialize: false, ..Default::default() }, &control).expect("render");
    assert_eq!(generic.kernel, ggx_wgpu::KernelVariant::ALL.name());
    assert_ne!(specialized.kernel, generic.kernel);
    let bits = |r: &ggx_cpu::RenderResult| {
        r.film.mean().iter().flat_map(|v| v.to_array()).map(f32::to_bits).collect::<Vec<_>>()
    };
    assert_eq!(bits(&specialized), bits(&generic));

    // Dispatches of at most 100 paths: 6 rows of 16 pixels at 1 spp, 3 rows at 2 spp.
    let split = WgpuRenderer::new(&scene, &ctx).expect("upload").with_dispatch_paths(100);
    assert_eq!(bits(&split.render(&RenderOptions::default(), &control).expect("render")), bits(&specialized));

    let cancel = std::sync::atomic::AtomicBool::new(false);
    let passes = std::sync::Mutex::new(Vec::new());
    let progress = |p: ggx_cpu::Progress| {
        if p.pass_end {
            passes.lock().unwrap().push(p.spp_done);
            cancel.store(true, std::sync::atomic::Ordering::Relaxed);
        }
    };
    let control = RenderControl { cancel: Some(&cancel), progress: Some(&progress), pass_film: None };
    let cut = renderer.render(&RenderOptions::default(), &control).expect("render");
    assert_eq!((cut.spp, cut.interrupted), (1, true));
    assert_eq!(*passes.lock().unwrap(), [1]);

    // Cancelled after the first dispatch of a pass: its finished rows are kept.
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let progress = |_: ggx_cpu::Progress| cancel.store(true, std::sync::atomic::Ordering::Relaxed);
    let control = RenderControl { cancel: Some(&cancel), progress: Some(&progress), pass_film: None };
    let cut = split.render(&RenderOptions::default(), &control).expect("render");
    let counts: Vec<u32> = cut.film.pixels().iter().map(|p| p.samples).collect();
    assert_eq!((cut.spp, cut.interrupted), (0, true));
    assert_eq!(&counts[..6 * 16], &[1; 96][..], "the first dispatch's 6 rows");
    assert!(counts[6 * 16..].iter().all(|&n| n == 0));
    assert_eq!(&cut.film.pixels()[..96], &specialized_first_pass(&renderer)[..96]);
}

/// The film of samples `[0, 1)` of every pixel.
fn specialized_first_pass(renderer: &WgpuRenderer<'_>) -> Vec<ggx_film::SampleSum> {
    let options = RenderOptions { samples: Some([0, 1]), ..Default::default() };
    renderer.render(&options, &RenderControl::default()).expect("render").film.pixels().to_vec()
}

/// Sample ranges split at pass boundaries merge into the single render bit for bit (a GPU pass
/// sums its samples in `f32`, so the same passes give the same sums); a film is continued on
/// the GPU to the same bits; a pixel window renders only its pixels.
#[test]
fn ranges_windows_and_resumes_on_the_gpu() {
    let ctx = match GpuContext::new(GpuOptions::default()) {
        Ok(ctx) => ctx,
        Err(e) if e.is_no_adapter() && std::env::var("CI").as_deref() != Ok("true") => {
            eprintln!("\n*** SKIPPING the GPU range test: {e}\n*** (set CI=true to make this a failure)\n");
            return;
        }
        Err(e) => panic!("no GPU context: {e}"),
    };
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/three-spheres.toml");
    let mut scene = ggx_scene::load_scene(&path).expect("scene loads");
    scene.camera.resolution = [20, 14];
    scene.integrator.spp = 48;
    let renderer = WgpuRenderer::new(&scene, &ctx).expect("upload").with_dispatch_paths(500);
    let control = RenderControl::default();
    let range = |samples: [u32; 2], window: Option<[u32; 4]>| {
        let options = RenderOptions { samples: Some(samples), window, ..Default::default() };
        renderer.render(&options, &control).expect("render").film
    };
    let whole = range([0, 48], None);
    for splits in [[0, 16, 48], [0, 32, 48], [0, 8, 48]] {
        let mut merged = range([splits[0], splits[1]], None);
        merged.merge(&range([splits[1], splits[2]], None)).unwrap();
        assert_eq!(merged, whole, "{splits:?}");
    }
    let mut windows = range([0, 48], Some([0, 0, 20, 5]));
    assert!(windows.pixels()[5 * 20..].iter().all(|p| p.samples == 0));
    windows.merge(&range([0, 48], Some([0, 5, 20, 14]))).unwrap();
    assert_eq!(windows, whole);
    // Continue the first 16 samples to 48.
    let options = RenderOptions { samples: Some([0, 48]), ..Default::default() };
    let resumed = renderer.render_film(&options, &control, range([0, 16], None)).expect("render");
    assert_eq!(resumed.film, whole);
    assert_eq!(resumed.camera_samples, 32 * 20 * 14);
    // A film whose rows hold different counts in one row cannot be continued on the GPU.
    let mut ragged = range([0, 16], None);
    ragged.pixels_mut()[3] = ggx_film::SampleSum::default();
    let err = renderer.render_film(&options, &control, ragged).err().expect("refused").to_string();
    assert!(err.contains("the GPU continues only films whose window rows are uniform"), "{err}");
}

/// A glTF scene built for the textured path: every metal-rough feature the GPU mirrors, in one
/// image (written to a temporary directory: the glTF, its `.bin` and its PNGs).
///
/// * floor: sRGB 8-bit base colour (repeat, bilinear, coordinates from -1 to 2), a
///   `metallicRoughnessTexture` (roughness G, metallic B; mirrored S, clamped T) and a normal
///   map (scale 0.7) without `TANGENT` (the loader's MikkTSpace tangents);
/// * back wall: a 16-bit base colour (float texels; nearest, mirrored repeat) under a
///   `KHR_texture_transform`, the normal map with mesh tangents (`TANGENT`, `w = -1`);
/// * textured sphere: base colour (nearest, clamp to edge) and normal map on a curved mesh
///   whose poles have degenerate coordinates;
/// * lamp: emission factor 6 (`KHR_materials_emissive_strength`) times an sRGB emission
///   texture, which both emits (hit and next-event estimation) and reflects;
/// * anisotropic metal-rough (`KHR_materials_anisotropy`): the gold sphere (strength 0.7, rotation
///   0.6, MikkTSpace tangents) and the back wall (strength 0.5, rotation -1.1, its `TANGENT`s,
///   under its normal map);
/// * an untextured metal-rough sphere: a half-metallic mirror lobe (roughness 0.02: a delta
///   specular sample over a diffuse base) under a mirror clear coat (`KHR_materials_clearcoat`,
///   factor 1, roughness 0: a delta coat sample);
/// * clear coat on a textured material: the textured sphere (factor 0.8, roughness 0.3), its
///   coat rebuilt over the textured base at each hit;
/// * `KHR_lights_punctual`: a point light with a range, a spot light whose cone edge crosses
///   the floor and a directional light from behind the back wall, all at tilted nodes, and a
///   point light inside the textured sphere (dark unless the sphere is glass);
/// * a constant environment.
mod textured_scene {
    use std::path::Path;

    /// PNG (RGBA, 8 or 16 bits per channel, stored deflate blocks) of `pixel(x, y)`, channel
    /// values in `0..=255` or `0..=65535`.
    pub fn png(width: u32, height: u32, sixteen: bool, pixel: impl Fn(u32, u32) -> [u16; 4]) -> Vec<u8> {
        let mut raw = Vec::new();
        for y in 0..height {
            raw.push(0u8);
            for x in 0..width {
                for c in pixel(x, y) {
                    if sixteen {
                        raw.extend_from_slice(&c.to_be_bytes());
                    } else {
                        raw.push(c as u8);
                    }
                }
            }
        }
        let mut zlib = vec![0x78, 0x01];
        let blocks: Vec<&[u8]> = raw.chunks(65535).collect();
        for (i, block) in blocks.iter().enumerate() {
            zlib.push(u8::from(i + 1 == blocks.len()));
            let len = block.len() as u16;
            zlib.extend_from_slice(&len.to_le_bytes());
            zlib.extend_from_slice(&(!len).to_le_bytes());
            zlib.extend_from_slice(block);
        }
        let (mut a, mut b) = (1u32, 0u32);
        for &byte in &raw {
            a = (a + u32::from(byte)) % 65521;
            b = (b + a) % 65521;
        }
        zlib.extend_from_slice(&((b << 16) | a).to_be_bytes());
        let mut ihdr = Vec::new();
        ihdr.extend_from_slice(&width.to_be_bytes());
        ihdr.extend_from_slice(&height.to_be_bytes());
        ihdr.extend_from_slice(&[if sixteen { 16 } else { 8 }, 6, 0, 0, 0]);
        let mut out = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
        for (kind, data) in [(b"IHDR", ihdr), (b"IDAT", zlib), (b"IEND", Vec::new())] {
            out.extend_from_slice(&(data.len() as u32).to_be_bytes());
            let start = out.len();
            out.extend_from_slice(kind);
            out.extend_from_slice(&data);
            let crc = crc32(&out[start..]);
            out.extend_from_slice(&crc.to_be_bytes());
        }
        out
    }

    fn crc32(bytes: &[u8]) -> u32 {
        let mut crc = !0u32;
        for &byte in bytes {
            crc ^= u32::from(byte);
            for _ in 0..8 {
                crc = if crc & 1 != 0 { (crc >> 1) ^ 0xedb8_8320 } else { crc >> 1 };
            }
        }
        !crc
    }

    /// One triangle primitive.
    #[derive(Default)]
    struct Prim {
        positions: Vec<[f32; 3]>,
        normals: Vec<[f32; 3]>,
        uvs: Vec<[f32; 2]>,
        tangents: Vec<[f32; 4]>,
        indices: Vec<u32>,
    }

    /// A `nu x nv` grid from `origin` along `du` (first) and `dv`, facing `du x dv`, with
    /// coordinates `uv(i / nu, j / nv)` and, when given, one tangent for every vertex.
    fn grid(
        origin: [f32; 3],
        du: [f32; 3],
        dv: [f32; 3],
        (nu, nv): (u32, u32),
        uv: impl Fn(f32, f32) -> [f32; 2],
        tangent: Option<[f32; 4]>,
    ) -> Prim {
        let n = cross(du, dv);
        let len = dot(n, n).sqrt();
        let normal = n.map(|c| c / len);
        let mut p = Prim::default();
        for j in 0..=nv {
            for i in 0..=nu {
                let (a, b) = (i as f32 / nu as f32, j as f32 / nv as f32);
                p.positions.push([0, 1, 2].map(|k| origin[k] + a * du[k] + b * dv[k]));
                p.normals.push(normal);
                p.uvs.push(uv(a, b));
                p.tangents.extend(tangent);
            }
        }
        let at = |i: u32, j: u32| j * (nu + 1) + i;
        for j in 0..nv {
            for i in 0..nu {
                p.indices.extend([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        p
    }

    /// A UV sphere (`lat x lon` quads) with outward normals and coordinates `(2 lon, lat)`.
    fn sphere(center: [f32; 3], radius: f32, lat: u32, lon: u32) -> Prim {
        let mut p = Prim::default();
        for i in 0..=lat {
            for j in 0..=lon {
                let theta = std::f32::consts::PI * i as f32 / lat as f32;
                let phi = std::f32::consts::TAU * j as f32 / lon as f32;
                let n = [theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()];
                p.positions.push([0, 1, 2].map(|k| center[k] + radius * n[k]));
                p.normals.push(n);
                p.uvs.push([2.0 * j as f32 / lon as f32, i as f32 / lat as f32]);
            }
        }
        let at = |i: u32, j: u32| i * (lon + 1) + j;
        for i in 0..lat {
            for j in 0..lon {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                if i > 0 {
                    p.indices.extend([a, d, c]);
                }
                if i + 1 < lat {
                    p.indices.extend([a, c, b]);
                }
            }
        }
        p
    }

    fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    }

    fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    /// The binary buffer with its bufferViews and accessors (JSON).
    #[derive(Default)]
    struct Buffers {
        bin: Vec<u8>,
        views: Vec<String>,
        accessors: Vec<String>,
    }

    impl Buffers {
        /// Appends `bytes` as one bufferView and an accessor of `count` elements over it;
        /// returns the accessor's index.
        fn accessor(
            &mut self,
            bytes: &[u8],
            count: usize,
            kind: &str,
            component: u32,
            bounds: Option<([f32; 3], [f32; 3])>,
        ) -> usize {
            let (offset, length) = (self.bin.len(), bytes.len());
            self.views.push(format!(r#"{{"buffer": 0, "byteOffset": {offset}, "byteLength": {length}}}"#));
            self.bin.extend_from_slice(bytes);
            let bounds = bounds.map_or(String::new(), |(lo, hi)| format!(r#", "min": {lo:?}, "max": {hi:?}"#));
            let view = self.views.len() - 1;
            self.accessors.push(format!(
                r#"{{"bufferView": {view}, "componentType": {component}, "count": {count}, "type": "{kind}"{bounds}}}"#
            ));
            self.accessors.len() - 1
        }
    }

    fn f32_bytes<const N: usize>(v: &[[f32; N]]) -> Vec<u8> {
        v.iter().flatten().flat_map(|x| x.to_le_bytes()).collect()
    }

    /// Writes the scene (`textured.toml` + `textured.gltf` and its resources) into `dir`, with
    /// `integrator` as the TOML's `[integrator]` table and, when `material` is given, every
    /// primitive in the TOML material it defines (`[materials.override]`); returns the TOML's
    /// path.
    pub fn write(dir: &Path, integrator: &str, material: Option<&str>) -> std::path::PathBuf {
        std::fs::create_dir_all(dir).expect("temporary directory");
        let write = |name: &str, bytes: &[u8]| std::fs::write(dir.join(name), bytes).expect("write");
        // Images: 0 floor colour (sRGB checker), 1 metallic-roughness, 2 normal map (bumps),
        // 3 wall colour (16-bit), 4 emission, 5 sphere colour.
        write(
            "colour.png",
            &png(8, 8, false, |x, y| {
                if (x / 2 + y / 2) % 2 == 0 {
                    [200, 60 + 20 * x as u16, 40, 255]
                } else {
                    [30, 90, 160 + 10 * y as u16, 255]
                }
            }),
        );
        write("mr.png", &png(4, 4, false, |x, y| [0, 40 + 60 * x as u16, 255 - 80 * y as u16, 255]));
        write(
            "normal.png",
            &png(8, 8, false, |x, y| {
                let dx = ((x as f32 * 0.8).sin() * 90.0) as i32;
                let dy = ((y as f32 * 1.1).cos() * 90.0) as i32;
                [(128 + dx) as u16, (128 + dy) as u16, 220, 255]
            }),
        );
        write(
            "wall.png",
            &png(6, 5, true, |x, y| {
                [9000 + 9000 * x as u16, 52000 - 7000 * y as u16, 20000 + 3000 * (x + y) as u16, 65535]
            }),
        );
        write(
            "emission.png",
            &png(4, 4, false, |x, y| if (x + y) % 2 == 0 { [255, 230, 180, 255] } else { [120, 160, 255, 255] }),
        );
        write("tiles.png", &png(3, 3, false, |x, y| [60 * x as u16 + 40, 200 - 50 * y as u16, 120, 255]));

        let floor = grid(
            [-2.0, 0.0, -2.0],
            [0.0, 0.0, 4.0],
            [4.0, 0.0, 0.0],
            (4, 4),
            |a, b| [3.0 * a - 1.0, 3.0 * b - 1.0],
            None,
        );
        let wall = grid(
            [-2.0, 0.0, -1.5],
            [4.0, 0.0, 0.0],
            [0.0, 2.5, 0.0],
            (3, 3),
            |a, b| [a, 1.0 - b],
            Some([1.0, 0.0, 0.0, -1.0]),
        );
        let lamp = grid([-0.6, 2.4, -0.4], [1.2, 0.0, 0.0], [0.0, 0.0, 1.2], (2, 2), |a, b| [a, b], None);
        // (primitive, material): 0 floor, 1 wall, 2 gold, 3 lamp, 4 gloss, 5 tiles.
        let prims = [
            (floor, 0),
            (wall, 1),
            (sphere([0.75, 0.45, 0.1], 0.45, 8, 12), 2),
            (lamp, 3),
            (sphere([0.0, 0.3, 0.9], 0.3, 6, 10), 4),
            (sphere([-0.75, 0.5, 0.0], 0.5, 10, 14), 5),
        ];
        let (mut buffers, mut meshes) = (Buffers::default(), Vec::new());
        for (p, material) in &prims {
            let n = p.positions.len();
            let mut lo = [f32::INFINITY; 3];
            let mut hi = [f32::NEG_INFINITY; 3];
            for q in &p.positions {
                for k in 0..3 {
                    (lo[k], hi[k]) = (lo[k].min(q[k]), hi[k].max(q[k]));
                }
            }
            let pos = buffers.accessor(&f32_bytes(&p.positions), n, "VEC3", 5126, Some((lo, hi)));
            let nor = buffers.accessor(&f32_bytes(&p.normals), n, "VEC3", 5126, None);
            let uv = buffers.accessor(&f32_bytes(&p.uvs), n, "VEC2", 5126, None);
            let tangent = if p.tangents.is_empty() {
                String::new()
            } else {
                format!(r#", "TANGENT": {}"#, buffers.accessor(&f32_bytes(&p.tangents), n, "VEC4", 5126, None))
            };
            let index_bytes: Vec<u8> = p.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
            let idx = buffers.accessor(&index_bytes, p.indices.len(), "SCALAR", 5125, None);
            meshes.push(format!(
                r#"{{"primitives": [{{"attributes": {{"POSITION": {pos}, "NORMAL": {nor}, "TEXCOORD_0": {uv}{tangent}}}, "indices": {idx}, "material": {material}}}]}}"#
            ));
        }
        let Buffers { bin, views, accessors } = buffers;
        write("textured.bin", &bin);
        let mut nodes: Vec<String> = (0..meshes.len()).map(|i| format!(r#"{{"mesh": {i}}}"#)).collect();
        // Punctual lights 0 point, 1 spot, 2 directional, 3 point inside the textured sphere: each
        // node's -Z turned toward `toward`.
        let lights = [
            ([1.4f32, 1.5, 1.1], [0.2f32, -1.0, -0.5]),
            ([0.3, 2.0, 1.3], [-0.25, -1.0, -0.6]),
            ([0.0; 3], [-0.3, -0.8, 0.35]),
            ([-0.7, 0.55, 0.1], [0.0, 0.0, -1.0]),
        ];
        for (i, (at, toward)) in lights.iter().enumerate() {
            let q = glam::Quat::from_rotation_arc(glam::Vec3::NEG_Z, glam::Vec3::from(*toward).normalize()).to_array();
            nodes.push(format!(
                r#"{{"translation": {at:?}, "rotation": {q:?}, "extensions": {{"KHR_lights_punctual": {{"light": {i}}}}}}}"#
            ));
        }
        let node_list: Vec<String> = (0..nodes.len()).map(|i| i.to_string()).collect();
        let gltf = format!(
            r#"{{
  "asset": {{"version": "2.0"}},
  "extensionsUsed": ["KHR_texture_transform", "KHR_materials_emissive_strength", "KHR_materials_anisotropy", "KHR_lights_punctual", "KHR_materials_clearcoat"],
  "extensions": {{"KHR_lights_punctual": {{"lights": [
    {{"type": "point", "color": [1.0, 0.8, 0.6], "intensity": 3.0, "range": 4.0}},
    {{"type": "spot", "color": [0.6, 0.8, 1.0], "intensity": 6.0, "spot": {{"innerConeAngle": 0.25, "outerConeAngle": 0.5}}}},
    {{"type": "directional", "color": [1.0, 0.95, 0.9], "intensity": 1.5}},
    {{"type": "point", "color": [1.0, 0.6, 0.3], "intensity": 0.8}}
  ]}}}},
  "scene": 0,
  "scenes": [{{"nodes": [{nodes_list}]}}],
  "nodes": [{nodes}],
  "meshes": [{meshes}],
  "buffers": [{{"uri": "textured.bin", "byteLength": {bin_len}}}],
  "bufferViews": [{views}],
  "accessors": [{accessors}],
  "images": [{{"uri": "colour.png"}}, {{"uri": "mr.png"}}, {{"uri": "normal.png"}}, {{"uri": "wall.png"}}, {{"uri": "emission.png"}}, {{"uri": "tiles.png"}}],
  "samplers": [
    {{"magFilter": 9729, "wrapS": 10497, "wrapT": 10497}},
    {{"magFilter": 9729, "wrapS": 33648, "wrapT": 33071}},
    {{"magFilter": 9728, "wrapS": 33648, "wrapT": 33648}},
    {{"magFilter": 9728, "wrapS": 33071, "wrapT": 33071}}
  ],
  "textures": [
    {{"source": 0, "sampler": 0}},
    {{"source": 1, "sampler": 1}},
    {{"source": 2, "sampler": 0}},
    {{"source": 3, "sampler": 2}},
    {{"source": 4, "sampler": 0}},
    {{"source": 5, "sampler": 3}}
  ],
  "materials": [
    {{"name": "floor", "pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}}, "metallicRoughnessTexture": {{"index": 1}}}}, "normalTexture": {{"index": 2, "scale": 0.7}}}},
    {{"name": "wall", "pbrMetallicRoughness": {{"baseColorFactor": [0.9, 0.8, 0.7, 1], "baseColorTexture": {{"index": 3, "extensions": {{"KHR_texture_transform": {{"offset": [0.1, -0.2], "rotation": 0.4, "scale": [1.7, 1.3]}}}}}}, "metallicFactor": 0.0, "roughnessFactor": 0.55}}, "normalTexture": {{"index": 2}}, "extensions": {{"KHR_materials_anisotropy": {{"anisotropyStrength": 0.5, "anisotropyRotation": -1.1}}}}}},
    {{"name": "gold", "pbrMetallicRoughness": {{"baseColorFactor": [1.0, 0.77, 0.34, 1], "metallicFactor": 1.0, "roughnessFactor": 0.35}}, "extensions": {{"KHR_materials_anisotropy": {{"anisotropyStrength": 0.7, "anisotropyRotation": 0.6}}}}}},
    {{"name": "lamp", "pbrMetallicRoughness": {{"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0.0, "roughnessFactor": 0.8}}, "emissiveFactor": [1, 1, 1], "emissiveTexture": {{"index": 4}}, "extensions": {{"KHR_materials_emissive_strength": {{"emissiveStrength": 6}}}}}},
    {{"name": "gloss", "pbrMetallicRoughness": {{"baseColorFactor": [0.2, 0.5, 0.8, 1], "metallicFactor": 0.5, "roughnessFactor": 0.02}}, "extensions": {{"KHR_materials_clearcoat": {{"clearcoatFactor": 1.0}}}}}},
    {{"name": "tiles", "pbrMetallicRoughness": {{"baseColorTexture": {{"index": 5}}, "metallicRoughnessTexture": {{"index": 1}}, "metallicFactor": 0.6, "roughnessFactor": 0.9}}, "normalTexture": {{"index": 2, "scale": 1.3}}, "extensions": {{"KHR_materials_clearcoat": {{"clearcoatFactor": 0.8, "clearcoatRoughnessFactor": 0.3}}}}}}
  ]
}}"#,
            nodes_list = node_list.join(", "),
            nodes = nodes.join(", "),
            meshes = meshes.join(",\n    "),
            bin_len = bin.len(),
            views = views.join(",\n    "),
            accessors = accessors.join(",\n    "),
        );
        write("textured.gltf", gltf.as_bytes());
        let (materials, assign) = match material {
            Some(m) => (format!("[materials.override]\n{m}\n"), "material = \"override\"\n"),
            None => (String::new(), ""),
        };
        let toml = format!(
            "[camera]\nposition = [0, 1.6, 4.2]\nlook_at = [0, 0.6, 0]\nfov_y = 45\nresolution = [32, 24]\n\
             [integrator]\n{integrator}\n\
             [environment]\ntype = \"constant\"\nradiance = [0.1, 0.12, 0.15]\n{materials}\
             [[shapes]]\ntype = \"gltf\"\nfile = \"textured.gltf\"\n{assign}"
        );
        write("textured.toml", toml.as_bytes());
        dir.join("textured.toml")
    }
}

/// The textured metal-rough scene of [`textured_scene`] (sRGB and 16-bit base colours, a
/// metallic-roughness texture, normal maps with the file's and with MikkTSpace tangents, textured emission,
/// anisotropic, clear-coated and untextured metal-rough materials, every wrap mode, nearest and bilinear,
/// point, spot and directional lights beside the area light and the environment) renders on
/// the GPU as on the CPU, under two integrator settings (MIS, NEE alone), within the bounds of
/// a scene without an environment map; so does its geometry under one untextured clear-coated
/// metal-rough material, and under one absorbing rough glass (a point light inside the closed sphere: shadow
/// rays through the medium; the directional light behind the open wall, on its inside: reached
/// through an infinite medium in the channel that does not absorb), each in a specialized
/// kernel without `TEXTURES` whose only scene lights are the punctual ones (`AREA` on, no
/// emitter), the glass within the bounds of dielectrics.
#[test]
fn a_textured_metal_rough_scene_matches_the_cpu_render() {
    let Some(ctx) = context_or_skip("the textured scene test") else { return };
    let dir = std::env::temp_dir().join(format!("ggx-wgpu-textured-{}", std::process::id()));
    let plain = "type = \"metal-rough\"\nbase_color = [0.8, 0.5, 0.3]\nmetallic = 0.4\nroughness = 0.3\n\
                 clearcoat = 0.6\nclearcoat_roughness = 0.2";
    let glass = "type = \"dielectric\"\nior = 1.4\nroughness = 0.7\nabsorption = [0.8, 0.3, 0.0]";
    let settings = [
        ("spp = 8\nmax_depth = 6\nrussian_roulette = 3", None),
        (
            "spp = 8\nmax_depth = 4\nsampler = \"independent\"\nbsdf_sampling = \"spherical-caps\"\nlight_strategy = \"nee\"",
            None,
        ),
        ("spp = 8\nmax_depth = 6\nrussian_roulette = 3", Some(plain)),
        ("spp = 8\nmax_depth = 6\nrussian_roulette = 3", Some(glass)),
    ];
    let mut failures = Vec::new();
    for (i, (integrator, material)) in settings.iter().enumerate() {
        let path = textured_scene::write(&dir, integrator, *material);
        let scene = ggx_scene::load_scene(&path).unwrap_or_else(|e| panic!("textured scene: {e}"));
        let f = scene.features;
        let textured = material.is_none();
        let dielectric = *material == Some(glass);
        assert!(f.metal_rough != dielectric && f.dielectrics == dielectric, "{f:?}");
        assert!(f.textures == textured && f.area_lights == textured, "{f:?}");
        assert!(f.punctual_lights && scene.punctual_lights.len() == 4, "{f:?}");
        if textured {
            assert!(scene.textures.infos.len() >= 6 && !scene.mesh.uvs.is_empty() && !scene.mesh.tangents.is_empty());
            let anisotropic = scene
                .materials
                .iter()
                .filter(|m| matches!(m, ggx_scene::Material::MetalRough(r) if r.anisotropy > 0.0));
            assert_eq!(anisotropic.count(), 2);
            let coated =
                |m: &&ggx_scene::Material| matches!(m, ggx_scene::Material::MetalRough(r) if r.clearcoat > 0.0);
            assert_eq!(scene.materials.iter().filter(coated).count(), 2);
        }
        let options = RenderOptions::default();
        let cpu =
            Renderer::new(&scene, AccelKind::Bvh2).render(&options, &RenderControl::default()).expect("cpu render");
        let gpu = WgpuRenderer::new(&scene, &ctx)
            .and_then(|r| r.render(&options, &RenderControl::default()))
            .unwrap_or_else(|e| panic!("textured scene: {e}"));
        assert_eq!((gpu.spp, gpu.kernel), (cpu.spp, cpu.kernel));
        let kernel = match (textured, dielectric) {
            (true, _) => ggx_wgpu::KernelVariant::ALL.name(),
            (false, false) => "area+env",
            (false, true) => "area+env+dielectric",
        };
        assert_eq!(gpu.kernel, kernel);
        let mean = cpu.film.mean();
        assert!(mean.iter().all(|p| p.is_finite()) && mean.iter().any(|p| p.max_element() > 0.05), "a lit image");
        let m = compare(&gpu.film.mean(), &mean, PIXEL_TOLERANCE).expect("same size");
        let (max_over, max_rel_mse) = bounds(&scene.features);
        println!("textured scene, settings {i}: rays gpu {} cpu {}: {m}", gpu.rays, cpu.rays);
        if m.over_tolerance > max_over || m.rel_mse > max_rel_mse {
            failures.push(format!("settings {i}: {m}"));
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(failures.is_empty(), "GPU renders of the textured scene differ from the CPU:\n{}", failures.join("\n"));
}
