//! Criterion benchmarks of ggx-core: ns per call of the scalar functions and samples per
//! second of the batch API, on 1024 precomputed inputs per iteration (so nothing is
//! constant-folded). Run with `cargo bench -p ggx-core`; criterion reports time per
//! element (`thrpt` in elements/s), one core.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use ggx_core::batch::{self, Vec3Slices, Vec3SlicesMut};
use ggx_core::{
    Fresnel, GgxConductor, GgxConductorMs, GgxDielectric, GgxDielectricMs, Sampling, TransportMode, TrowbridgeReitz,
    Vec2, Vec3, energy, energy_dielectric, warp,
};
use rand_core::{Rng, SeedableRng};
use std::hint::black_box;

const N: usize = 1024;

struct Inputs {
    wo: Vec<Vec3>,
    wi: Vec<Vec3>,
    wm: Vec<Vec3>,
    u: Vec<Vec2>,
}

fn inputs() -> Inputs {
    let mut rng = rand_pcg::Pcg32::seed_from_u64(7);
    let mut u2 = || Vec2::new(rng.next_u32() as f32 / 4294967296.0, rng.next_u32() as f32 / 4294967296.0);
    let mut v = Inputs { wo: vec![], wi: vec![], wm: vec![], u: vec![] };
    for _ in 0..N {
        v.wo.push(warp::sample_cosine_hemisphere(u2()));
        v.wi.push(warp::sample_cosine_hemisphere(u2()));
        v.wm.push(warp::sample_cosine_hemisphere(u2()));
        v.u.push(u2());
    }
    v
}

fn scalar(c: &mut Criterion) {
    let v = inputs();
    let brdf = GgxConductor::isotropic(0.3, Fresnel::One);
    let aniso = GgxConductor::new(0.1, 0.4, Fresnel::One);
    let d = brdf.distribution;
    let mut g = c.benchmark_group("scalar");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("D", |b| b.iter(|| v.wm.iter().map(|&m| d.d(black_box(m))).sum::<f32>()));
    g.bench_function("G2", |b| b.iter(|| v.wo.iter().zip(&v.wi).map(|(&o, &i)| d.g2(black_box(o), i)).sum::<f32>()));
    g.bench_function("eval", |b| {
        b.iter(|| v.wo.iter().zip(&v.wi).map(|(&o, &i)| brdf.eval(black_box(o), i).x).sum::<f32>())
    });
    g.bench_function("eval_anisotropic", |b| {
        b.iter(|| v.wo.iter().zip(&v.wi).map(|(&o, &i)| aniso.eval(black_box(o), i).x).sum::<f32>())
    });
    g.bench_function("pdf_vndf", |b| {
        b.iter(|| v.wo.iter().zip(&v.wi).map(|(&o, &i)| brdf.pdf(black_box(o), i, Sampling::Vndf)).sum::<f32>())
    });
    for s in Sampling::ALL {
        g.bench_function(format!("sample_{}", s.name()), |b| {
            b.iter(|| {
                v.wo.iter()
                    .zip(&v.u)
                    .map(|(&o, &u)| brdf.sample(black_box(o), u, s).map_or(0.0, |s| s.weight.x))
                    .sum::<f32>()
            })
        });
    }
    g.bench_function("sample_wm_vndf", |b| {
        b.iter(|| v.wo.iter().zip(&v.u).map(|(&o, &u)| d.sample_wm_vndf(black_box(o), u).z).sum::<f32>())
    });
    g.bench_function("sample_wm_spherical_caps", |b| {
        b.iter(|| v.wo.iter().zip(&v.u).map(|(&o, &u)| d.sample_wm_spherical_caps(black_box(o), u).z).sum::<f32>())
    });
    g.finish();
}

/// `batch::sample_vndf`'s signature.
type SampleFn = fn(&TrowbridgeReitz, Vec3Slices, &[f32], &[f32], Sampling, Vec3SlicesMut, &mut [f32]) -> usize;
/// `batch::eval`'s signature.
type EvalFn = fn(&GgxConductor, Vec3Slices, Vec3Slices, Vec3SlicesMut);
/// `batch::sample`'s signature.
type SampleWeightedFn =
    fn(&GgxConductor, Vec3Slices, &[f32], &[f32], Sampling, Vec3SlicesMut, Vec3SlicesMut, &mut [f32]) -> usize;
/// `batch::pdf`'s signature.
type PdfFn = fn(&GgxConductor, Vec3Slices, Vec3Slices, &mut [f32]);
/// `batch::d`'s signature.
type DFn = fn(&TrowbridgeReitz, Vec3Slices, &mut [f32]);

fn batched(c: &mut Criterion) {
    let v = inputs();
    let brdf = GgxConductor::isotropic(0.3, Fresnel::One);
    let split = |w: &[Vec3]| -> [Vec<f32>; 3] {
        [w.iter().map(|v| v.x).collect(), w.iter().map(|v| v.y).collect(), w.iter().map(|v| v.z).collect()]
    };
    let [ox, oy, oz] = split(&v.wo);
    let [ix, iy, iz] = split(&v.wi);
    let [mx, my, mz] = split(&v.wm);
    let u0: Vec<f32> = v.u.iter().map(|u| u.x).collect();
    let u1: Vec<f32> = v.u.iter().map(|u| u.y).collect();
    let (mut rx, mut ry, mut rz, mut pdf) = (vec![0.0; N], vec![0.0; N], vec![0.0; N], vec![0.0; N]);
    let (mut wx, mut wy, mut wz) = (vec![0.0; N], vec![0.0; N], vec![0.0; N]);
    let mut g = c.benchmark_group("batch");
    g.throughput(Throughput::Elements(N as u64));
    // The dispatched loops (the CPU's widest ISA) beside the same loops at the baseline ISA;
    // the spherical caps, and Heitz's sampler (`_heitz`).
    let caps = Sampling::SphericalCaps;
    let samplers = [
        ("sample_vndf", batch::sample_vndf as SampleFn, caps),
        ("sample_vndf_portable", batch::sample_vndf_portable, caps),
        ("sample_vndf_heitz", batch::sample_vndf, Sampling::Vndf),
    ];
    for (name, f, sampling) in samplers {
        g.bench_function(name, |b| {
            b.iter(|| {
                f(
                    &brdf.distribution,
                    Vec3Slices { x: black_box(&ox), y: &oy, z: &oz },
                    &u0,
                    &u1,
                    sampling,
                    Vec3SlicesMut { x: &mut rx, y: &mut ry, z: &mut rz },
                    &mut pdf,
                )
            })
        });
    }
    for (name, f) in [("eval", batch::eval as EvalFn), ("eval_portable", batch::eval_portable)] {
        g.bench_function(name, |b| {
            b.iter(|| {
                f(
                    &brdf,
                    Vec3Slices { x: black_box(&ox), y: &oy, z: &oz },
                    Vec3Slices { x: &ix, y: &iy, z: &iz },
                    Vec3SlicesMut { x: &mut rx, y: &mut ry, z: &mut rz },
                )
            })
        });
    }
    let samplers = [
        ("sample", batch::sample as SampleWeightedFn, caps),
        ("sample_portable", batch::sample_portable, caps),
        ("sample_heitz", batch::sample, Sampling::Vndf),
    ];
    for (name, f, sampling) in samplers {
        g.bench_function(name, |b| {
            b.iter(|| {
                f(
                    &brdf,
                    Vec3Slices { x: black_box(&ox), y: &oy, z: &oz },
                    &u0,
                    &u1,
                    sampling,
                    Vec3SlicesMut { x: &mut rx, y: &mut ry, z: &mut rz },
                    Vec3SlicesMut { x: &mut wx, y: &mut wy, z: &mut wz },
                    &mut pdf,
                )
            })
        });
    }
    for (name, f) in [("pdf", batch::pdf as PdfFn), ("pdf_portable", batch::pdf_portable)] {
        g.bench_function(name, |b| {
            b.iter(|| {
                f(
                    &brdf,
                    Vec3Slices { x: black_box(&ox), y: &oy, z: &oz },
                    Vec3Slices { x: &ix, y: &iy, z: &iz },
                    &mut pdf,
                )
            })
        });
    }
    for (name, f) in [("D", batch::d as DFn), ("D_portable", batch::d_portable)] {
        g.bench_function(name, |b| {
            b.iter(|| f(&brdf.distribution, Vec3Slices { x: black_box(&mx), y: &my, z: &mz }, &mut pdf))
        });
    }
    g.finish();
}

/// Energy compensation: `GgxConductorMs::eval` against `GgxConductor::eval` (same lobe, a
/// complex-IOR Fresnel) and the table lookup `energy::albedo` alone (mu, alpha from the inputs).
fn energy_compensation(c: &mut Criterion) {
    let v = inputs();
    let fresnel = Fresnel::Conductor { eta: Vec3::new(0.2, 0.92, 1.1), k: Vec3::new(3.9, 2.45, 2.2) };
    let brdf = GgxConductor::isotropic(0.3, fresnel);
    let ms = GgxConductorMs::new(brdf);
    let mut g = c.benchmark_group("energy");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("conductor_eval", |b| {
        b.iter(|| v.wo.iter().zip(&v.wi).map(|(&o, &i)| brdf.eval(black_box(o), i).x).sum::<f32>())
    });
    g.bench_function("conductor_ms_eval", |b| {
        b.iter(|| v.wo.iter().zip(&v.wi).map(|(&o, &i)| ms.eval(black_box(o), i).x).sum::<f32>())
    });
    g.bench_function("albedo", |b| {
        b.iter(|| v.wo.iter().zip(&v.u).map(|(&o, &u)| energy::albedo(black_box(o.z), u.x)).sum::<f32>())
    });
    g.finish();
}

/// Dielectric energy compensation: `GgxDielectricMs::eval` against `GgxDielectric::eval` (glass,
/// alpha 0.3, every other `wi` flipped below the surface so that half the pairs transmit) and
/// the trilinear lookup `energy_dielectric::dielectric_albedo` alone.
fn dielectric_energy_compensation(c: &mut Criterion) {
    let v = inputs();
    let wi: Vec<Vec3> =
        v.wi.iter().enumerate().map(|(i, &w)| if i % 2 == 1 { Vec3::new(w.x, w.y, -w.z) } else { w }).collect();
    let dielectric = GgxDielectric::isotropic(0.3, 1.5);
    let ms = GgxDielectricMs::new(dielectric);
    let mode = TransportMode::Radiance;
    let mut g = c.benchmark_group("dielectric_energy");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("dielectric_eval", |b| {
        b.iter(|| v.wo.iter().zip(&wi).map(|(&o, &i)| dielectric.eval(black_box(o), i, mode).x).sum::<f32>())
    });
    g.bench_function("dielectric_ms_eval", |b| {
        b.iter(|| v.wo.iter().zip(&wi).map(|(&o, &i)| ms.eval(black_box(o), i, mode).x).sum::<f32>())
    });
    g.bench_function("dielectric_albedo", |b| {
        b.iter(|| {
            v.wo.iter()
                .zip(&v.u)
                .map(|(&o, &u)| energy_dielectric::dielectric_albedo(black_box(o.z), u.x, 1.5))
                .sum::<f32>()
        })
    });
    g.finish();
}

/// Light sampling with MIS needs `f` and the BSDF's density of one pair: `eval` then `pdf`
/// (two half vectors, two `D`), against `eval_pdf` (one), for the peer scenes' gold conductor
/// (complex Fresnel) and the dielectric (half of the pairs transmit).
fn eval_and_pdf(c: &mut Criterion) {
    let v = inputs();
    let wi_t: Vec<Vec3> =
        v.wi.iter().enumerate().map(|(i, &w)| if i % 2 == 1 { Vec3::new(w.x, w.y, -w.z) } else { w }).collect();
    let gold = Fresnel::Conductor { eta: Vec3::new(0.143, 0.374, 1.442), k: Vec3::new(3.983, 2.385, 1.603) };
    let conductor = GgxConductor::isotropic(0.2, gold);
    let dielectric = GgxDielectric::isotropic(0.3, 1.5);
    let (s, mode) = (Sampling::Vndf, TransportMode::Radiance);
    let mut g = c.benchmark_group("eval_pdf");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("conductor_eval_then_pdf", |b| {
        b.iter(|| {
            v.wo.iter()
                .zip(&v.wi)
                .map(|(&o, &i)| conductor.eval(black_box(o), i).x + conductor.pdf(o, i, s))
                .sum::<f32>()
        })
    });
    g.bench_function("conductor_eval_pdf", |b| {
        b.iter(|| {
            v.wo.iter()
                .zip(&v.wi)
                .map(|(&o, &i)| {
                    let (f, pdf) = conductor.eval_pdf(black_box(o), i, s);
                    f.x + pdf
                })
                .sum::<f32>()
        })
    });
    g.bench_function("dielectric_eval_then_pdf", |b| {
        b.iter(|| {
            v.wo.iter()
                .zip(&wi_t)
                .map(|(&o, &i)| dielectric.eval(black_box(o), i, mode).x + dielectric.pdf(o, i, s, mode))
                .sum::<f32>()
        })
    });
    g.bench_function("dielectric_eval_pdf", |b| {
        b.iter(|| {
            v.wo.iter()
                .zip(&wi_t)
                .map(|(&o, &i)| {
                    let (f, pdf) = dielectric.eval_pdf(black_box(o), i, s, mode);
                    f.x + pdf
                })
                .sum::<f32>()
        })
    });
    g.finish();
}

criterion_group!(benches, scalar, batched, energy_compensation, dielectric_energy_compensation, eval_and_pdf);
criterion_main!(benches);
