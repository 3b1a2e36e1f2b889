//! Prints the single-scattering directional albedo `E(mu, alpha)` of the GGX conductor with
//! `F = 1` (the energy a microfacet BRDF keeps without multiple scattering), estimated with
//! VNDF sampling and a per-pixel Owen-scrambled Sobol' stream: the table Kulla & Conty 2017
//! tabulate for energy compensation.
//!
//! `cargo run --release -p ggx-core --example albedo [samples]`

use ggx_core::{Fresnel, GgxConductor, SampleStream, Sampling, SequenceKind, Vec3};

fn main() {
    let samples: u32 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(65_536);
    let alphas = [0.05f32, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0];
    print!("{:>8}", "mu \\ a");
    for a in alphas {
        print!("{a:>8}");
    }
    println!();
    for k in 0..10 {
        let mu = 1.0 - k as f32 / 10.0;
        print!("{mu:>8.2}");
        let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
        for (j, a) in alphas.into_iter().enumerate() {
            let brdf = GgxConductor::isotropic(a, Fresnel::One);
            let mut sum = 0.0f64;
            for i in 0..samples {
                let mut stream = SampleStream::new(SequenceKind::Sobol, j as u32, k, i);
                if let Some(s) = brdf.sample(wo, stream.next_2d(), Sampling::Vndf) {
                    sum += s.weight.x as f64;
                }
            }
            print!("{:>8.4}", sum / samples as f64);
        }
        println!();
    }
}
