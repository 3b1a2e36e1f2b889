//! `ggx info`: what a scene contains, its settings, and how long each BVH takes to build.

use std::fmt::Write as _;
use std::io::Write as _;

use anyhow::{Context, Result};
use clap::ValueEnum;
use ggx_cpu::Renderer;
use ggx_scene::{
    BsdfStrategy, CameraPath, Environment, IntegratorSettings, Interpolation, LightStrategy, Limit, Limits, Material,
    SamplerKind, Scene,
};

use crate::args::{AccelArg, InfoArgs};
use crate::{accel, memory};

/// Runs `ggx info`: the description, the memory estimate and the limits are printed before
/// the BVHs are built, and the build is refused when the estimate is over `--max-memory`.
pub fn run(args: &InfoArgs) -> Result<()> {
    let limits = args.limits.limits();
    let scene = crate::scene_load::load(&args.scene, &limits, &args.gltf)?;
    let mut text = describe(&scene);
    let _ = writeln!(text, "{:<13}{}", "memory:", memory::estimate(&scene));
    let _ = writeln!(text, "{:<13}{}", "limits:", describe_limits(&limits));
    let mut stdout = std::io::stdout().lock();
    stdout.write_all(text.as_bytes()).and_then(|()| stdout.flush()).context("cannot write to stdout")?;
    memory::check(&scene, &limits)?;
    let mut text = String::new();
    let times: Vec<String> = AccelArg::value_variants()
        .iter()
        .map(|&a| {
            let renderer = Renderer::new(&scene, accel::kind(a));
            format!("{} {}", accel::name(a), accel::format_build_time(renderer.build_time()))
        })
        .collect();
    let _ = writeln!(text, "bvh build:  {}", times.join(", "));
    stdout.write_all(text.as_bytes()).context("cannot write to stdout")
}

/// Every limit with the flag that changes it, e.g. `scene file 64.0 MiB (--max-scene-bytes)`.
fn describe_limits(limits: &Limits) -> String {
    let parts = [
        ("scene file", Limit::SceneBytes),
        ("mesh file", Limit::MeshBytes),
        ("map pixels", Limit::MapPixels),
        ("triangles", Limit::Triangles),
        ("memory", Limit::Memory),
    ];
    let parts: Vec<String> =
        parts.iter().map(|&(name, l)| format!("{name} {} ({})", l.format(limits.get(l)), l.flag())).collect();
    parts.join(", ")
}

/// Everything but the BVH build times, one `key: value` line each.
fn describe(scene: &Scene) -> String {
    let stats = scene.stats();
    let mut s = String::new();
    // Writing to a String cannot fail.
    let mut line = |key: &str, value: String| {
        let _ = writeln!(s, "{:<13}{value}", format!("{key}:"));
    };
    line("scene", scene.source.display().to_string());
    line("shapes", stats.shapes.to_string());
    line("triangles", format!("{} ({} with shading normals)", stats.triangles, stats.smooth_triangles));
    let materials: Vec<String> =
        scene.material_names.iter().zip(&scene.materials).map(|(n, m)| format!("{n} ({})", material_kind(m))).collect();
    line("materials", format!("{}: {}", stats.materials, materials.join(", ")));
    line(
        "lights",
        format!("{} ({} emitting triangles, area {})", stats.lights, stats.emitters, fixed(stats.light_area, 4)),
    );
    line("environment", environment(scene.environment.as_ref(), &scene.integrator));
    line("features", scene.features.summary());
    let i = &scene.integrator;
    line(
        "integrator",
        format!(
            "{} spp, time budget {}, max depth {}, russian roulette {}, seed {}, energy compensation {}",
            i.spp,
            i.time_budget.map_or("none".to_owned(), |t| format!("{t} s")),
            i.max_depth,
            if i.russian_roulette == 0 { "off".to_owned() } else { format!("from depth {}", i.russian_roulette) },
            i.seed,
            match i.energy_compensation {
                Some(true) => "on",
                Some(false) => "off",
                None => "per material",
            },
        ),
    );
    line(
        "sampling",
        format!(
            "sampler {}, bsdf sampling {}, light strategy {}",
            sampler_name(i.sampler),
            bsdf_name(i.bsdf_sampling),
            light_name(i.light_strategy)
        ),
    );
    let c = &scene.camera;
    line(
        "camera",
        format!(
            "{}x{}, fov_y {}°, position {}, forward {}",
            c.resolution[0],
            c.resolution[1],
            c.fov_y_degrees,
            vec3(c.position.to_array()),
            vec3(c.forward.to_array())
        ),
    );
    line("animation", animation(scene.camera_path.as_ref()));
    s
}

/// `none (still camera)`, or the keys, fps, frames, duration and interpolation of the path,
/// e.g. `17 keys, 24 fps, 49 frames (0..=48), 2 s, smooth`.
fn animation(path: Option<&CameraPath>) -> String {
    let Some(p) = path else { return "none (still camera)".to_owned() };
    let frames = p.frame_count();
    let keys = if p.keys().len() == 1 { "1 key".to_owned() } else { format!("{} keys", p.keys().len()) };
    format!(
        "{keys}, {} fps, {frames} frames (0..={}), {} s, {}",
        p.fps(),
        frames.saturating_sub(1),
        p.duration(),
        interpolation_name(p.interpolation())
    )
}

fn vec3([x, y, z]: [f32; 3]) -> String {
    format!("[{}, {}, {}]", fixed(x, 3), fixed(y, 3), fixed(z, 3))
}

/// `x` with `decimals` digits after the point, without the sign of a value that rounds to
/// zero (`-0.0000` reads as a bug; -1e-8 and -0.0 print as `0.000`).
fn fixed(x: f32, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_owned(),
        _ => s,
    }
}

/// The environment, and how light samples take it ([`Environment::for_integrator`]).
fn environment(env: Option<&Environment>, settings: &IntegratorSettings) -> String {
    let Some(env) = env else { return "none".to_owned() };
    let kind = match env {
        Environment::Constant(l) => format!("constant {}", vec3(l.to_array())),
        Environment::Map(m) => format!("map {}x{}", m.width, m.height),
    };
    let compensated = settings.compensates_mis();
    let (lit, sampled) = env.for_integrator(settings);
    match (&*lit, sampled) {
        (Environment::Map(m), true) if compensated => {
            let sampled = m.distribution.func.iter().filter(|&&f| f > 0.0).count();
            let percent = 100.0 * sampled as f64 / m.distribution.func.len().max(1) as f64;
            format!("{kind}, light samples from the {percent:.1} % of texels above its mean (MIS compensation)")
        }
        (_, false) if compensated => format!("{kind}, left to BSDF sampling (MIS compensation)"),
        _ => kind,
    }
}

fn material_kind(m: &Material) -> &'static str {
    match m {
        Material::Diffuse { .. } => "diffuse",
        Material::Conductor { .. } if m.is_anisotropic() => "anisotropic conductor",
        Material::Conductor { .. } => "conductor",
        Material::Plastic { .. } => "plastic",
        Material::Dielectric { thin: true, .. } => "thin dielectric",
        Material::Dielectric { .. } if m.is_anisotropic() => "anisotropic dielectric",
        Material::Dielectric { .. } => "dielectric",
        Material::Emissive { .. } => "emissive",
        Material::MetalRough(r) => match (r.is_textured() || r.has_emission_texture(), r.clearcoat > 0.0) {
            (true, true) => "glTF metal-rough, textured, clear-coated",
            (true, false) => "glTF metal-rough, textured",
            (false, true) => "glTF metal-rough, clear-coated",
            (false, false) => "glTF metal-rough",
        },
    }
}

fn sampler_name(s: SamplerKind) -> &'static str {
    match s {
        SamplerKind::Independent => "independent",
        SamplerKind::Sobol => "sobol",
    }
}

fn bsdf_name(b: BsdfStrategy) -> &'static str {
    match b {
        BsdfStrategy::Cosine => "cosine",
        BsdfStrategy::Ndf => "ndf",
        BsdfStrategy::Vndf => "vndf",
        BsdfStrategy::SphericalCaps => "spherical-caps",
        BsdfStrategy::Bounded => "bounded",
    }
}

fn interpolation_name(i: Interpolation) -> &'static str {
    match i {
        Interpolation::Linear => "linear",
        Interpolation::Smooth => "smooth",
    }
}

fn light_name(l: LightStrategy) -> &'static str {
    match l {
        LightStrategy::Bsdf => "bsdf",
        LightStrategy::Nee => "nee",
        LightStrategy::Mis => "mis",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn describes_a_scene() {
        let text = "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nresolution = [64, 32]\n\
                    [materials.w]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\
                    [[shapes]]\ntype = \"rectangle\"\nmaterial = \"w\"\n";
        let scene = ggx_scene::parse_scene(text, "t.toml", std::path::Path::new(".")).unwrap();
        let d = describe(&scene);
        assert!(d.contains("triangles:   2 (0 with shading normals)"), "{d}");
        assert!(d.contains("materials:   1: w (diffuse)"), "{d}");
        assert!(d.contains("camera:      64x32, fov_y 40°"), "{d}");
        assert!(d.contains("sampler sobol, bsdf sampling vndf, light strategy mis"), "{d}");
        assert!(d.contains("energy compensation per material"), "{d}");
        // The camera looks down -z from +z: forward is (0, 0, -1), printed without -0.000.
        assert!(d.contains("forward [0.000, 0.000, -1.000]"), "{d}");
        assert!(!d.contains("-0.0"), "{d}");
        assert!(d.contains("animation:   none (still camera)"), "{d}");
    }

    #[test]
    fn describes_an_animation() {
        let text = "[camera]\nfps = 12\ninterpolation = \"smooth\"\n\
                    [[camera.keys]]\ntime = 0\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n\
                    [[camera.keys]]\ntime = 2.5\nposition = [5, 0, 0]\nlook_at = [0, 0, 0]\n";
        let scene = ggx_scene::parse_scene(text, "t.toml", std::path::Path::new(".")).unwrap();
        let d = describe(&scene);
        assert!(d.contains("animation:   2 keys, 12 fps, 31 frames (0..=30), 2.5 s, smooth"), "{d}");
        assert!(d.contains("position [0.000, 0.000, 5.000]"), "frame 0 is described: {d}");
    }

    #[test]
    fn values_that_round_to_zero_lose_their_sign() {
        assert_eq!(fixed(-0.0, 4), "0.0000");
        assert_eq!(fixed(-1e-8, 3), "0.000");
        assert_eq!(fixed(-0.0004, 3), "0.000");
        assert_eq!(fixed(-0.0006, 3), "-0.001");
        assert_eq!(fixed(2.5, 1), "2.5");
        assert_eq!(fixed(-2.0, 0), "-2");
        assert_eq!(vec3([-0.0, 1e-9, -1e-9]), "[0.000, 0.000, 0.000]");
    }
}
