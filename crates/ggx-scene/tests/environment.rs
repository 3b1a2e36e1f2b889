//! Environment maps: the importance-sampling pdf integrates to one, agrees with the sampled
//! pdf, passes a chi-square test (each for the full and the MIS-compensated distribution),
//! MIS with the compensated distribution stays unbiased, and `.hdr` / `.exr` files load
//! texel-exactly.

use std::borrow::Cow;
use std::f32::consts::PI;
use std::path::Path;

use ggx_scene::{
    EnvMap, Environment, IntegratorSettings, LightStrategy, direction_to_uv, luminance, parse_scene, sky, studio,
    uv_to_direction,
};
use glam::{Quat, Vec2, Vec3};

/// A small deterministic generator (64-bit LCG, top 24 bits) for reproducible tests.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn vec2(&mut self) -> Vec2 {
        Vec2::new(self.next(), self.next())
    }
}

/// A 32 x 16 map of random texels spanning three orders of magnitude, some black.
fn random_map(rotation_degrees: f32) -> EnvMap {
    let mut rng = Lcg(7);
    let texels = (0..32 * 16)
        .map(|i| {
            if i % 7 == 3 {
                return [0.0, 0.0, 0.0, 1.0];
            }
            let s = 10f32.powf(3.0 * rng.next() - 1.0);
            [s * rng.next(), s * rng.next(), s * rng.next(), 1.0]
        })
        .collect();
    EnvMap::new(32, 16, texels, 2.0, rotation_degrees).unwrap()
}

/// [`random_map`] with its full and its MIS-compensated sampling distribution.
fn both_maps(rotation_degrees: f32) -> [EnvMap; 2] {
    let map = random_map(rotation_degrees);
    let compensated = map.mis_compensated().expect("a random map has texels above its mean");
    [map, compensated]
}

/// Map-space texel of a world direction.
fn cell(map: &EnvMap, world: Vec3) -> (usize, usize) {
    let uv = direction_to_uv(Quat::from_rotation_y(-map.rotation()) * world);
    let col = ((uv.x * map.width as f32) as usize).min(map.width as usize - 1);
    let row = ((uv.y * map.height as f32) as usize).min(map.height as usize - 1);
    (col, row)
}

#[test]
fn pdf_integrates_to_one() {
    for map in [0.0, 40.0].into_iter().flat_map(both_maps) {
        let rotation = map.rotation();
        // Midpoint rule over (u, v) with d(omega) = 2 pi^2 sin(pi v) du dv.
        let (nu, nv) = (1024, 512);
        let mut sum = 0.0f64;
        for j in 0..nv {
            let v = (j as f32 + 0.5) / nv as f32;
            for i in 0..nu {
                let d = uv_to_direction(Vec2::new((i as f32 + 0.5) / nu as f32, v));
                sum += f64::from(map.pdf(d) * 2.0 * PI * PI * (PI * v).sin());
            }
        }
        let integral = sum / f64::from(nu * nv);
        assert!((integral - 1.0).abs() < 2e-3, "rotation {rotation}: {integral}");
    }
}

#[test]
fn sampled_pdf_matches_pdf() {
    for map in [0.0, 40.0].into_iter().flat_map(both_maps) {
        let mut rng = Lcg(11);
        let n = 100_000;
        let mut mismatches = 0;
        for _ in 0..n {
            let u = rng.vec2();
            let (d, pdf) = map.sample(u);
            // The light sample's radiance is the sampled texel's: `sample`'s cell, not the
            // one found again from the direction.
            let [col, row] = map.distribution.sample(u).2.map(|i| i as usize);
            assert_eq!(map.sample_with_radiance(u), (d, pdf, map.texel(col, row)));
            if map.texel(col, row) != map.radiance(d) {
                mismatches += 1;
            }
            assert!((d.length() - 1.0).abs() < 1e-4);
            assert!(pdf > 0.0 && pdf.is_finite());
            assert!(map.radiance(d) != Vec3::ZERO, "sampled a black texel");
            // The escaped-path lookup: the texel this test finds on its own, and pdf()'s density.
            let (col, row) = cell(&map, d);
            assert_eq!(map.radiance_and_pdf(d), (map.texel(col, row), map.pdf(d)));
            assert_eq!(map.radiance_and_pdf(d).0, map.radiance(d));
            if (map.pdf(d) - pdf).abs() > 1e-3 * pdf {
                mismatches += 1;
            }
        }
        // Only directions within float rounding of a texel border may disagree (in pdf or
        // in radiance).
        assert!(mismatches < n / 1000, "{mismatches} mismatches");
    }
}

#[test]
fn chi_square_of_sampled_texels() {
    for map in both_maps(40.0) {
        chi_square(&map);
    }
}

fn chi_square(map: &EnvMap) {
    let (w, h) = (map.width as usize, map.height as usize);
    let n = 200_000;
    let mut counts = vec![0u32; w * h];
    let mut rng = Lcg(3);
    for _ in 0..n {
        let (d, _) = map.sample(rng.vec2());
        let (col, row) = cell(map, d);
        counts[row * w + col] += 1;
    }
    // Expected counts n * P(cell), P(cell) = cell pdf * cell area in [0, 1)^2; cells with
    // fewer than 5 expected samples are pooled.
    let (mut chi2, mut dof, mut pooled_obs, mut pooled_exp) = (0.0f64, 0usize, 0.0f64, 0.0f64);
    for row in 0..h {
        for col in 0..w {
            let expected = f64::from(n) * f64::from(map.distribution.cell_pdf(col, row)) / (w * h) as f64;
            let observed = f64::from(counts[row * w + col]);
            if expected < 5.0 {
                pooled_obs += observed;
                pooled_exp += expected;
            } else {
                chi2 += (observed - expected).powi(2) / expected;
                dof += 1;
            }
        }
    }
    if pooled_exp > 0.0 {
        chi2 += (pooled_obs - pooled_exp).powi(2) / pooled_exp.max(1.0);
        dof += 1;
    }
    // Mean dof - 1, standard deviation sqrt(2 dof): allow six standard deviations.
    let limit = dof as f64 + 6.0 * (2.0 * dof as f64).sqrt();
    assert!(chi2 < limit, "chi2 {chi2} over {dof} cells (limit {limit})");
}

#[test]
fn importance_sampled_integral_matches_exact() {
    let map = random_map(0.0);
    // Exact: sum of texel luminance times texel solid angle 2 pi / w (cos t0 - cos t1).
    let (w, h) = (map.width as usize, map.height as usize);
    let mut exact = 0.0f64;
    for row in 0..h {
        let (t0, t1) = (PI * row as f32 / h as f32, PI * (row + 1) as f32 / h as f32);
        let solid_angle = 2.0 * PI / w as f32 * (t0.cos() - t1.cos());
        for col in 0..w {
            exact += f64::from(luminance(map.texel(col, row)) * solid_angle);
        }
    }
    let mut rng = Lcg(5);
    let n = 200_000;
    let estimate: f64 = (0..n)
        .map(|_| {
            let (d, pdf) = map.sample(rng.vec2());
            f64::from(luminance(map.radiance(d)) / pdf)
        })
        .sum::<f64>()
        / f64::from(n);
    assert!((estimate / exact - 1.0).abs() < 0.01, "estimate {estimate}, exact {exact}");
}

#[test]
fn nearest_texel_lookup_and_rotation() {
    let map = random_map(90.0);
    for (row, col) in [(0, 0), (5, 17), (15, 31)] {
        let uv = Vec2::new((col as f32 + 0.5) / 32.0, (row as f32 + 0.5) / 16.0);
        let world = Quat::from_rotation_y(map.rotation()) * uv_to_direction(uv);
        assert_eq!(map.radiance(world), map.texel(col, row));
        let t = map.texels[row * 32 + col];
        assert_eq!(map.texel(col, row), 2.0 * Vec3::new(t[0], t[1], t[2]));
        assert_eq!(t[3], map.distribution.cell_pdf(col, row));
    }
}

/// The constructor writes each texel's `w`, the cell's sampling density, over whatever the
/// caller passed (here NaN and a wrong value): the lookups' pdf never depends on it.
#[test]
fn texel_w_is_the_cell_density() {
    let map = random_map(0.0);
    for w in [f32::NAN, 7.0] {
        let texels = map.texels.iter().map(|&[r, g, b, _]| [r, g, b, w]).collect();
        assert_eq!(EnvMap::new(32, 16, texels, 2.0, 0.0).unwrap(), map);
    }
    for map in both_maps(0.0) {
        for (i, t) in map.texels.iter().enumerate() {
            assert_eq!(t[3], map.distribution.cell_pdf(i % 32, i / 32));
        }
    }
}

/// Karlik et al. 2019: the compensated weights are `max(L - mean, 0) sin(theta)`, the mean
/// taken over solid angle; radiance, scale and rotation are the map's own.
#[test]
fn compensated_distribution_keeps_what_stands_above_the_mean() {
    let map = random_map(30.0);
    let c = map.mis_compensated().unwrap();
    assert_eq!((c.width, c.height, c.scale, c.rotation()), (map.width, map.height, map.scale, map.rotation()));
    let (w, h) = (map.width as usize, map.height as usize);
    let sin_theta = |row: usize| (std::f64::consts::PI * (row as f64 + 0.5) / h as f64).sin();
    let lum = |col: usize, row: usize| f64::from(luminance(map.texel(col, row)) / map.scale);
    let (mut sum, mut solid_angle) = (0.0, 0.0);
    for row in 0..h {
        for col in 0..w {
            sum += lum(col, row) * sin_theta(row);
            solid_angle += sin_theta(row);
        }
    }
    let mean = sum / solid_angle;
    let (mut zero, mut ratio) = (0, None::<f64>);
    for row in 0..h {
        for col in 0..w {
            assert_eq!(c.texel(col, row), map.texel(col, row));
            let pdf = f64::from(c.distribution.cell_pdf(col, row));
            let weight = (lum(col, row) - mean).max(0.0) * sin_theta(row);
            if weight <= 1e-6 * mean {
                assert_eq!(pdf, 0.0, "texel ({col}, {row}) at or below the mean");
                zero += 1;
                continue;
            }
            let r = *ratio.get_or_insert(pdf / weight);
            assert!((pdf / weight / r - 1.0).abs() < 1e-4, "texel ({col}, {row}): {} vs {r}", pdf / weight);
        }
    }
    assert!(zero > w * h / 4 && zero < w * h, "{zero} of {} texels left to BSDF sampling", w * h);
}

/// A map without a texel above its mean has nothing left to sample, and so has a constant
/// environment: under MIS they are left to BSDF sampling. Without MIS, or without
/// compensation, the environment is sampled as it is.
#[test]
fn uniform_environments_are_left_to_bsdf_sampling() {
    let uniform = EnvMap::new(8, 4, vec![[0.3, 0.5, 0.7, 0.0]; 32], 1.5, 10.0).unwrap();
    assert!(uniform.mis_compensated().is_none());
    let map = random_map(0.0);
    let settings = |light_strategy, mis_compensation| IntegratorSettings {
        light_strategy,
        mis_compensation,
        ..Default::default()
    };
    for env in [Environment::Map(uniform), Environment::Constant(Vec3::ONE), Environment::Map(map.clone())] {
        let full = env.clone();
        let is_random = env == Environment::Map(map.clone());
        let (e, sampled) = env.for_integrator(&settings(LightStrategy::Mis, true));
        assert_eq!(sampled, is_random);
        assert_eq!(*e == full, !is_random, "only the random map's distribution changes");
        // Only a compensated map is a new value: the others are the scene's own, not copies.
        assert_eq!(matches!(e, Cow::Owned(_)), is_random);
        for (strategy, compensation, sampled) in
            [(LightStrategy::Mis, false, true), (LightStrategy::Nee, true, true), (LightStrategy::Bsdf, true, false)]
        {
            let (e, s) = env.for_integrator(&settings(strategy, compensation));
            assert!(matches!(e, Cow::Borrowed(b) if *b == full) && s == sampled, "{strategy:?} {compensation}");
        }
    }
}

/// MIS of the compensated map with cosine-weighted hemisphere sampling (what a diffuse
/// BSDF does) estimates the irradiance `E = int L cos` without bias, where the compensated
/// density alone is zero over most of the sphere, and with less variance than MIS with the
/// full distribution.
#[test]
fn mis_with_the_compensated_map_is_unbiased() {
    let map = random_map(25.0);
    let n_up = Vec3::new(0.3, 0.8, -0.2).normalize();
    let tangent = n_up.cross(Vec3::X).normalize();
    let to_world = |l: Vec3| tangent * l.x + n_up.cross(tangent) * l.y + n_up * l.z;
    // Exact: midpoint rule over the sphere in map (u, v), each point's nearest texel.
    let (nu, nv) = (1024, 512);
    let mut exact = 0.0f64;
    for j in 0..nv {
        let v = (j as f32 + 0.5) / nv as f32;
        for i in 0..nu {
            let d = Quat::from_rotation_y(map.rotation()) * uv_to_direction(Vec2::new((i as f32 + 0.5) / nu as f32, v));
            let cos = d.dot(n_up).max(0.0);
            exact += f64::from(luminance(map.radiance(d)) * cos * 2.0 * PI * PI * (PI * v).sin());
        }
    }
    exact /= f64::from(nu * nv);
    let power = |a: f32, b: f32| a * a / (a * a + b * b);
    let mut errors = vec![];
    for m in both_maps(25.0) {
        let mut rng = Lcg(9);
        let n = 200_000;
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let mut f = 0.0f32;
            // Light sample.
            let (d, pdf) = m.sample(rng.vec2());
            let cos = d.dot(n_up);
            if pdf > 0.0 && cos > 0.0 {
                let pdf_bsdf = cos / PI;
                f += luminance(m.radiance(d)) * cos / pdf * power(pdf, pdf_bsdf);
            }
            // Cosine-weighted sample.
            let u = rng.vec2();
            let r = u.x.sqrt();
            let (s, c) = (2.0 * PI * u.y).sin_cos();
            let local = Vec3::new(r * c, r * s, (1.0 - u.x).max(0.0).sqrt());
            let d = to_world(local);
            let pdf_bsdf = local.z / PI;
            if pdf_bsdf > 0.0 {
                f += luminance(m.radiance(d)) * local.z / pdf_bsdf * power(pdf_bsdf, m.pdf(d));
            }
            sum += f64::from(f);
            sum2 += f64::from(f) * f64::from(f);
        }
        let mean = sum / f64::from(n);
        let std_error = ((sum2 / f64::from(n) - mean * mean) / f64::from(n)).sqrt();
        assert!((mean - exact).abs() < 4.0 * std_error + 1e-4 * exact, "{mean} vs {exact} (se {std_error})");
        errors.push(std_error);
    }
    println!("standard error: full {:.3e}, compensated {:.3e}", errors[0], errors[1]);
    assert!(errors[1] < errors[0], "compensation should lower the variance: {errors:?}");
}

#[test]
fn constant_environment_samples_uniformly() {
    let env = Environment::Constant(Vec3::ONE);
    let mut rng = Lcg(1);
    let mut mean = Vec3::ZERO;
    for _ in 0..10_000 {
        let (d, pdf) = env.sample(rng.vec2());
        assert!((d.length() - 1.0).abs() < 1e-5 && pdf == env.pdf(d) && env.radiance(d) == Vec3::ONE);
        mean += d / 10_000.0;
    }
    assert!(mean.length() < 0.05, "{mean}");
    assert!((env.pdf(Vec3::Y) * 4.0 * PI - 1.0).abs() < 1e-6);
}

#[test]
fn procedural_maps_are_valid() {
    for texels in [sky(64, 32), studio(64, 32)] {
        assert_eq!(texels.len(), 64 * 32);
        assert!(texels.iter().all(|t| t.iter().all(|c| c.is_finite() && *c >= 0.0)));
        let max = texels.iter().map(|t| t[1]).fold(0.0, f32::max);
        let min = texels.iter().map(|t| t[1]).fold(f32::MAX, f32::min);
        assert!(max > 5.0 && min > 0.0, "{min} {max}");
    }
    // The sky's sun (35 degrees up, azimuth 60 degrees) is the brightest texel.
    let map = EnvMap::new(512, 256, sky(512, 256), 1.0, 0.0).unwrap();
    let sun = Vec3::new(
        35f32.to_radians().cos() * 60f32.to_radians().cos(),
        35f32.to_radians().sin(),
        35f32.to_radians().cos() * 60f32.to_radians().sin(),
    );
    assert!(luminance(map.radiance(sun)) > 100.0);
    assert!(luminance(map.radiance(-Vec3::Y)) < 0.2);
}

fn scene_with_map(dir: &Path, file: &str) -> EnvMap {
    let text = format!(
        "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n\n[environment]\ntype = \"map\"\nfile = \"{file}\"\n"
    );
    match parse_scene(&text, "map.toml", dir).unwrap_or_else(|e| panic!("{e}")).environment {
        Some(Environment::Map(m)) => m,
        other => panic!("{other:?}"),
    }
}

fn test_pixel(x: usize, y: usize) -> [f32; 3] {
    [0.25 + x as f32, 0.5 * (y + 1) as f32, 4.0 / (x + y + 1) as f32]
}

#[test]
fn exr_and_hdr_files_load_texel_exact() {
    use image::ImageEncoder;
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("env_maps");
    std::fs::create_dir_all(&dir).unwrap();
    let (w, h) = (8usize, 4usize);
    exr::prelude::write_rgba_file(dir.join("test.exr"), w, h, |x, y| {
        let [r, g, b] = test_pixel(x, y);
        (r, g, b, 1.0f32)
    })
    .unwrap();
    let pixels: Vec<f32> = (0..w * h).flat_map(|i| test_pixel(i % w, i / w)).collect();
    let file = std::io::BufWriter::new(std::fs::File::create(dir.join("test.hdr")).unwrap());
    image::codecs::hdr::HdrEncoder::new(file)
        .write_image(bytemuck::cast_slice(&pixels), w as u32, h as u32, image::ExtendedColorType::Rgb32F)
        .unwrap();
    for (file, tolerance) in [("test.exr", 0.0), ("test.hdr", 0.01)] {
        let map = scene_with_map(&dir, file);
        assert_eq!((map.width, map.height), (8, 4));
        for y in 0..h {
            for x in 0..w {
                let expected = Vec3::from(test_pixel(x, y));
                let got = map.texel(x, y);
                assert!(
                    (got - expected).abs().max_element() <= tolerance * expected.max_element(),
                    "{file} ({x}, {y}): {got} vs {expected}"
                );
            }
        }
    }
}

/// The random maps (unrotated and rotated, full and MIS-compensated) and a constant
/// environment, for the batched lookups' tests.
fn batch_test_environments() -> impl Iterator<Item = Environment> {
    [0.0, 40.0]
        .into_iter()
        .flat_map(both_maps)
        .map(Environment::Map)
        .chain([Environment::Constant(Vec3::new(0.5, 1.0, 2.0))])
}

/// The batched escaped-path lookup is the single one, bit for bit, for any number of
/// directions (more than one batch, a partial batch, none), hostile directions included, and
/// fills only as many results as it has directions or room for.
#[test]
fn batched_lookups_are_the_single_lookups() {
    let mut rng = Lcg(23);
    let mut directions: Vec<Vec3> = (0..37).map(|_| ggx_scene::uniform_sphere(rng.vec2())).collect();
    directions.extend([Vec3::ZERO, Vec3::NAN, Vec3::INFINITY, Vec3::NEG_Y, Vec3::Y, Vec3::new(3.0, -4.0, 0.5)]);
    for env in batch_test_environments() {
        let want: Vec<(Vec3, f32)> = directions.iter().map(|&d| env.radiance_and_pdf(d)).collect();
        let bits = |v: &[(Vec3, f32)]| {
            v.iter().map(|(l, p)| (l.to_array().map(f32::to_bits), p.to_bits())).collect::<Vec<_>>()
        };
        for n in [0, 1, 16, 17, directions.len()] {
            let sentinel = (Vec3::splat(-1.0), -1.0);
            let mut out = vec![sentinel; directions.len() + 3];
            env.radiance_and_pdf_batch(&directions[..n], &mut out);
            assert_eq!(bits(&out[..n]), bits(&want[..n]), "{n} directions");
            assert!(out[n..].iter().all(|&o| o == sentinel), "wrote past {n} directions");
        }
        // Less room than directions: the first results only.
        let mut out = vec![(Vec3::ZERO, 0.0); 5];
        env.radiance_and_pdf_batch(&directions, &mut out);
        assert_eq!(bits(&out), bits(&want[..5]));
    }
}

/// The batched light samples are the single ones, bit for bit: the map's (its distribution's
/// cells by `sample_cells`, equal to `sample`'s) and the constant environment's, hostile `u`
/// included, over several batches and a partial one; nothing is written past the samples.
#[test]
fn batched_light_samples_are_the_single_samples() {
    let mut rng = Lcg(29);
    let mut us: Vec<Vec2> = (0..40).map(|_| rng.vec2()).collect();
    us.extend([Vec2::NAN, Vec2::ZERO, Vec2::ONE, Vec2::new(-1.0, 2.0), Vec2::splat(f32::INFINITY)]);
    let bits = |v: &[(Vec3, f32, Vec3)]| {
        v.iter()
            .map(|(d, p, l)| (d.to_array().map(f32::to_bits), p.to_bits(), l.to_array().map(f32::to_bits)))
            .collect::<Vec<_>>()
    };
    for map in [0.0, 40.0].into_iter().flat_map(both_maps) {
        let mut cells = vec![(Vec2::ZERO, [0u32; 2]); us.len()];
        map.distribution.sample_cells(&us, &mut cells);
        for (&u, &cell) in us.iter().zip(&cells) {
            let (p, _, c) = map.distribution.sample(u);
            assert_eq!(cell, map.distribution.sample_cell(u));
            assert_eq!((p.to_array().map(f32::to_bits), c), (cell.0.to_array().map(f32::to_bits), cell.1), "{u}");
        }
    }
    for env in batch_test_environments() {
        let want: Vec<(Vec3, f32, Vec3)> = us.iter().map(|&u| env.sample_with_radiance(u)).collect();
        for n in [0, 1, 16, 33, us.len()] {
            let sentinel = (Vec3::splat(-1.0), -1.0, Vec3::splat(-1.0));
            let mut out = vec![sentinel; us.len() + 2];
            env.sample_with_radiance_batch(&us[..n], &mut out);
            assert_eq!(bits(&out[..n]), bits(&want[..n]), "{n} samples");
            assert!(out[n..].iter().all(|&o| o == sentinel), "wrote past {n} samples");
        }
    }
}
