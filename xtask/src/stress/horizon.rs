//! Share of samples lost below the horizon (`sample` returns `None`) at grazing views, per
//! microfacet technique, to compare with published figures: Heitz & d'Eon 2014's
//! slope-space visible-normal sampler sent 61 of N samples below the horizon at 86 degrees
//! where NDF sampling sent 371.

use super::grid;
use super::table;
use ggx_core::{CounterRng, Fresnel, GgxConductor, Sampling};
use rayon::prelude::*;

/// Isotropic alphas measured.
pub const ALPHAS: [f32; 2] = [0.3, 1.0];
/// View angles measured, degrees from the normal.
pub const ANGLES_DEG: [f64; 2] = [86.0, 89.0];
/// The 2014 reference: samples lost at 86 degrees, slope-space VNDF and NDF.
pub const REFERENCE_86: (u32, u32) = (61, 371);
/// Samples per parallel task.
const CHUNK: u64 = 1 << 16;

/// One measured cell: technique, alpha, angle and the share lost.
#[derive(Clone, Copy, Debug)]
pub struct Loss {
    /// Technique.
    pub sampling: Sampling,
    /// Isotropic alpha.
    pub alpha: f32,
    /// View angle, degrees.
    pub angle_deg: f64,
    /// Samples that returned `None`.
    pub lost: u64,
    /// Samples drawn.
    pub samples: u64,
}

impl Loss {
    /// Lost share in percent.
    pub fn percent(&self) -> f64 {
        100.0 * self.lost as f64 / self.samples.max(1) as f64
    }
}

/// Every technique of [`Sampling::MICROFACET`] at every alpha and angle, `samples` random
/// points each (azimuth 0, `Fresnel::One`), on rayon's global pool.
pub fn measure(samples: u64) -> Vec<Loss> {
    let mut cells = Vec::new();
    for sampling in Sampling::MICROFACET {
        for alpha in ALPHAS {
            for angle_deg in ANGLES_DEG {
                cells.push(Loss { sampling, alpha, angle_deg, lost: 0, samples });
            }
        }
    }
    let chunks = samples.div_ceil(CHUNK);
    let lost: Vec<u64> = (0..cells.len() as u64 * chunks)
        .into_par_iter()
        .fold(
            || vec![0u64; cells.len()],
            |mut acc, task| {
                let (cell, chunk) = ((task / chunks) as usize, task % chunks);
                let c = &cells[cell];
                let brdf = GgxConductor::isotropic(c.alpha, Fresnel::One);
                let wo = grid::view(c.angle_deg.to_radians().cos() as f32, 0.0);
                let mut rng = CounterRng::new(0x686f_7a6e ^ cell as u32, chunk as u32);
                let n = CHUNK.min(samples - chunk * CHUNK);
                acc[cell] += (0..n).filter(|_| brdf.sample(wo, rng.next_vec2(), c.sampling).is_none()).count() as u64;
                acc
            },
        )
        .reduce(|| vec![0u64; cells.len()], |a, b| a.iter().zip(&b).map(|(x, y)| x + y).collect());
    cells.iter().zip(lost).map(|(c, lost)| Loss { lost, ..*c }).collect()
}

/// The table of lost shares (one row per technique) and the comparison with 2014.
pub fn report(losses: &[Loss]) -> String {
    let mut header = vec!["lost below horizon".to_string()];
    for alpha in ALPHAS {
        for angle in ANGLES_DEG {
            header.push(format!("a={alpha} {angle}deg"));
        }
    }
    let rows: Vec<Vec<String>> = Sampling::MICROFACET
        .iter()
        .map(|&s| {
            let mut row = vec![s.name().to_string()];
            row.extend(losses.iter().filter(|l| l.sampling == s).map(|l| format!("{:.3}%", l.percent())));
            row
        })
        .collect();
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let mut out = table::render(&header, &rows);
    let at = |s: Sampling, alpha: f32| {
        losses.iter().find(|l| l.sampling == s && l.alpha == alpha && l.angle_deg == 86.0).map_or(0.0, Loss::percent)
    };
    let (vndf, ndf) = REFERENCE_86;
    out += &format!(
        "samples per cell: {}. 2014 slope-space VNDF at 86 deg: {vndf} lost vs {ndf} for NDF (ratio {:.3}).\n",
        losses.first().map_or(0, |l| l.samples),
        vndf as f64 / ndf as f64
    );
    for alpha in ALPHAS {
        let ndf = at(Sampling::Ndf, alpha);
        let ratios: Vec<String> = [Sampling::Vndf, Sampling::SphericalCaps, Sampling::Bounded]
            .iter()
            .map(|&s| format!("{} {:.3}", s.name(), at(s, alpha) / ndf))
            .collect();
        out += &format!("ours at 86 deg, a={alpha}, lost relative to ndf: {}\n", ratios.join(", "));
    }
    out
}
