//! The rows of energy.wgsl: ggx-core's `energy.rs`, `conductor_ms.rs` (`GgxConductorMs`),
//! `energy_dielectric.rs`, `dielectric_ms.rs` (`GgxDielectricMs`) and `thin_dielectric.rs`
//! (`ThinDielectric`). The GPU reads the tables from the kernel's binding 4, which holds
//! `scene_upload::energy_tables()`: the very values ggx-core interpolates.

use ggx_core::energy::{self, column_mu, row_alpha};
use ggx_core::energy_dielectric::{self as energy_dielectric, slice_eta};
use ggx_core::energy_dielectric_tables::{N_ALPHA, N_ETA, N_MU};
use ggx_core::energy_tables::N;
use ggx_core::{ALPHA_MIN, DELTA_ALPHA, GgxConductorMs, GgxDielectricMs, ThinDielectric};

use super::*;

/// Bound for the table lookups (`energy_albedo`, `energy_average_albedo`, `coat_albedo`,
/// `coat_average_albedo`): [`UNIT`], 16 ulp or 2^-20 absolute. Both sides interpolate the same
/// `f32` values operation for operation, but the GPU's row coordinate may be an ulp or two off:
/// llvmpipe (Mesa's NIR) folds `alpha_coordinate`'s `* (1 / (1 - DELTA_ALPHA^(1/4)))` and the
/// lookup's `* (N - 1)` into one multiplication by a constant, which rounds differently (the
/// GPU's cell and fraction are exactly the CPU's `(s - R) * (K * (N - 1))`). An albedo then
/// moves by the steepest step between rows times two ulps of `N - 1`, plus both sides'
/// roundings: under 2^-20 for every table (`lookup_bound_covers_two_ulps_of_the_row_coordinate`),
/// and only that absolute error means anything (next to `eta = 1` the coat's `E_R` is 1e-25,
/// where the same error is a third of the value). Measured on llvmpipe: at most 1.8e-7
/// (`energy_albedo`, `energy_average_albedo`: 6 and 4 ulp), 1.2e-7 (`coat_albedo`), 3.0e-8
/// (`coat_average_albedo`); [`FEW_OPS`] fails.
const LOOKUP: Bound = UNIT;
/// Bound for `alpha_coordinate`: `(alpha^(1/4) - DELTA_ALPHA^(1/4)) / (1 - DELTA_ALPHA^(1/4))`
/// cancels near `DELTA_ALPHA`, where only the absolute error means anything (the lookups read
/// the coordinate times `N - 1`): [`UNIT`]. Bit-identical on llvmpipe.
const COORDINATE: Bound = UNIT;
/// Bound for the compensated conductor's multiple-scattering terms (`ggx_conductor_ms_eval_ms`,
/// `_eval`, `_probability`, `_pdf` and the sample's weight and pdf): 64 ulp, four times
/// [`FORMULA`], relative with no absolute escape. They are formulas of `1 - E(mu_o)`,
/// `1 - E(mu_i)` and `1 - E_avg`, which cancel where the albedo is close to 1: a lookup off by
/// its [`LOOKUP`] error (the row coordinate's rounding) is off relative to `1 - E` by that error
/// over `1 - E`, and `1 - E` falls to 1e-5 near a mirror at normal incidence. Measured on
/// llvmpipe: 37 ulp (a sample weight), 26 (`eval_ms`), 24 (`eval`, `probability`), 17 (`pdf`),
/// 15 (the sample's pdf); [`FORMULA`] fails.
const MS_FORMULA: Bound = Bound::Ulps(64);

/// `ggx_conductor_ms_sample`'s output words: [`SAMPLE_GROUPS`] with the weight and the pdf
/// under [`MS_FORMULA`].
const MS_SAMPLE_GROUPS: [Group; 4] =
    [SAMPLE_GROUPS[0], SAMPLE_GROUPS[1], Group::float("weight", 3, MS_FORMULA), Group::float("pdf", 1, MS_FORMULA)];

/// Hostile arguments of the energy functions: NaN, infinities, negative values, signed zeros,
/// a subnormal, `1 - ulp`, 1, just above 1, 2 and huge.
const ENERGY_ODD: [f32; 14] =
    [NAN, INF, -INF, -f32::MAX, -1.0, -0.0, 0.0, 1e-40, ONE_MINUS_ULP, 1.0, 1.000_000_1, 2.0, 1e30, f32::MAX];

/// A few of [`ENERGY_ODD`], for the grids where every hostile value of one argument meets these
/// on the others.
const ENERGY_FEW_ODD: [f32; 3] = [NAN, -1.0, INF];

/// The `n` nodes of a table axis (`t = i / (n - 1)` mapped to the argument by `at`, as the
/// table generator places them) and a point 0.37 into every cell.
fn axis(n: usize, at: fn(f32) -> f32) -> Vec<f32> {
    let last = (n - 1) as f32;
    let nodes = (0..n).map(move |i| at(i as f32 / last));
    nodes.chain((0..n - 1).map(move |i| at((i as f32 + 0.37) / last))).collect()
}

/// Ordinary `mu` of an `n`-column table: its nodes and cells, and grazing cosines.
fn table_mus(n: usize) -> Vec<f32> {
    axis(n, column_mu).into_iter().chain([1e-7, 1e-5, 1e-3]).collect()
}

/// Ordinary alphas of an `n`-row table: its nodes and cells, `ALPHA_MIN`, both sides of
/// `DELTA_ALPHA` (below it the first row is read).
fn table_alphas(n: usize) -> Vec<f32> {
    axis(n, row_alpha).into_iter().chain([ALPHA_MIN, 5e-4, 9.99e-4, DELTA_ALPHA, 1.0001e-3]).collect()
}

/// Ordinary indices of the dielectric tables: the slices and their cells, both sides of 1 and
/// of `ETA_TABLE_MAX = 3` (beyond it the last slice is read), below 1 (clamped to 1) and large.
fn table_etas() -> Vec<f32> {
    axis(N_ETA, slice_eta).into_iter().chain([0.5, 1.0 / 1.5, 0.999_999_9, 3.0, 3.000_001, 3.5, 100.0]).collect()
}

/// `xs` followed by [`ENERGY_ODD`].
fn with_odd(xs: Vec<f32>) -> Vec<f32> {
    xs.into_iter().chain(ENERGY_ODD).collect()
}

/// Every `xs[i]` with `i % step == 0`.
fn every(xs: &[f32], step: usize) -> Vec<f32> {
    xs.iter().copied().step_by(step).collect()
}

/// The points of the grid `axes[0] x axes[1] x ...`.
fn grid(axes: &[Vec<f32>]) -> Vec<Vec<f32>> {
    axes.iter().fold(vec![Vec::new()], |points, axis| {
        points.iter().flat_map(|p| axis.iter().map(move |&x| [p.as_slice(), &[x]].concat())).collect()
    })
}

/// The grid of the ordinary values `ordinary`, then for each argument every [`ENERGY_ODD`] value
/// against [`ENERGY_FEW_ODD`] and three ordinary values of every other argument.
fn hostile_grid(ordinary: &[Vec<f32>]) -> Vec<Vec<f32>> {
    let mut points = grid(ordinary);
    for d in 0..ordinary.len() {
        let axes: Vec<Vec<f32>> = ordinary
            .iter()
            .enumerate()
            .map(|(e, xs)| {
                if e == d {
                    ENERGY_ODD.to_vec()
                } else {
                    let few = [xs[0], xs[xs.len() / 3], xs[xs.len() * 2 / 3]];
                    few.into_iter().chain(ENERGY_FEW_ODD).collect()
                }
            })
            .collect();
        points.extend(grid(&axes));
    }
    points
}

/// The case whose `a` holds `p` (up to four arguments).
fn args(p: &[f32]) -> Input {
    let mut a = [0.0; 4];
    a[..p.len()].copy_from_slice(p);
    Input { a, ..Default::default() }
}

/// The compensated conductor of a case: its conductor, `F_avg` in `c.xyz`, compensation in `m.x`.
fn ms_conductor(i: &Input, k: &GgxConductor) -> GgxConductorMs {
    GgxConductorMs { conductor: *k, f_avg: [i.c[0], i.c[1], i.c[2]], compensation: i.m[0] }
}

/// The compensated dielectric of a case: its dielectric, compensation in `m.x`.
fn ms_dielectric(i: &Input, k: &GgxDielectric) -> GgxDielectricMs {
    GgxDielectricMs { dielectric: *k, compensation: i.m[0], pad: [0; 3] }
}

/// Conductors of the `GgxConductorMs` rows: [`bsdfs_raw`] (alpha edges, every Fresnel model,
/// raw alpha fields), anisotropic lobes, and isotropic lobes at every fourth row of the tables
/// (where `E` is read at a node) and 0.7 into the cells of the rows halfway between, with the
/// Fresnel models in turn.
fn ms_bsdfs() -> Vec<GgxConductor> {
    let fresnel = fresnels();
    let rows = (0..N).step_by(2).map(|j| {
        let t = if j % 4 == 0 { j as f32 } else { j as f32 + 0.7 };
        let a = row_alpha(t / (N - 1) as f32);
        (a, a)
    });
    let extra = [(0.1, 0.4), (0.25, 1.0)].into_iter().chain(rows);
    let extra = extra.enumerate().map(|(i, (x, y))| GgxConductor {
        distribution: TrowbridgeReitz::new(x, y),
        pad: [0; 2],
        fresnel: fresnel[(i * 4) % fresnel.len()],
    });
    bsdfs_raw().into_iter().chain(extra).collect()
}

/// `(F_avg, compensation)` of a conductor's cases: `GgxConductorMs::new`'s (`F_avg` =
/// `fresnel.average()`) with the lobe on, off and on by another non-zero word; then raw `F_avg`
/// words the reads clamp (NaN, negative, above 1, infinite), black, white and coloured.
fn ms_variants(k: &GgxConductor) -> [([f32; 3], u32); 8] {
    let f = k.fresnel.average().to_array();
    [
        (f, 1),
        (f, 0),
        (f, 0xdead_beef),
        ([NAN, -1.0, 2.0], 1),
        ([0.0; 3], 1),
        ([1.0; 3], 1),
        ([INF, ONE_MINUS_ULP, -INF], 1),
        ([0.9, 0.5, 0.1], 1),
    ]
}

/// `input` with `F_avg` and the compensation word of `variant`.
fn with_variant(input: Input, (f, compensation): ([f32; 3], u32)) -> Input {
    Input { c: [f[0], f[1], f[2], 0.0], m: [compensation, 0, 0, 0], ..input }
}

/// Compensation words of the dielectric cases, used in turn: on, off, on by another word.
const COMPENSATIONS: [u32; 5] = [1, 1, 0, 1, 0xdead_beef];

/// Dielectrics of the `GgxDielectricMs` rows: [`dielectrics`] and indices at and beyond the
/// tables' `ETA_TABLE_MAX = 3` from both sides, close to 1, and across the roughness rows.
fn ms_dielectrics() -> Vec<GgxDielectric> {
    let extra = [
        (0.3, 3.0),
        (0.3, 1.0 / 3.0),
        (0.3, 3.5),
        (0.3, 1.0 / 3.5),
        (0.05, 1.05),
        (0.05, 1.0 / 1.05),
        (0.7, 2.9),
        (1.0, 1.0 / 2.9),
        (2e-3, 1.2),
        (0.15, 100.0),
    ];
    dielectrics().into_iter().chain(extra.map(|(a, eta)| GgxDielectric::isotropic(a, eta))).collect()
}

/// Indices of the thin sheet (read through `clamp_eta`): [`ETAS`], [`ODD_ETAS`], beyond the
/// tables' 3, below 1, close to 1 and below `ETA_MIN`.
fn thin_etas() -> Vec<f32> {
    ETAS.into_iter().chain(ODD_ETAS).chain([3.5, 0.2, 1.05, 1.0 / 1.05, 1e-4]).collect()
}

/// ggx-core's weight and pdf of `GgxConductorMs::sample` at the GPU's `wi` where it differs
/// from ggx-core's ([`sample_at_gpu_wi`]): with the lobe on, `pdf(wo, wi)` and `eval(wo, wi) /
/// pdf` at the normalized `wo`, exactly what `sample` computes for its own `wi`; with it off,
/// the conductor's sample and [`sample_at_gpu_wi`].
fn conductor_ms_sample_at_gpu_wi(
    i: &Input,
    k: &GgxConductor,
    g: &GgxDielectric,
    got: &[u32],
    cpu: &[Expect],
) -> Option<Vec<Expect>> {
    let b = ms_conductor(i, k);
    if !b.is_compensated() {
        return sample_at_gpu_wi(i, k, g, got, cpu);
    }
    let wi = differing_gpu_wi(got, cpu)?;
    let wo = math::normalize_or_zero(i.va());
    let pdf = b.pdf(wo, wi, Sampling::from_u32(i.n[0]));
    Some(rebased(cpu, b.eval(wo, wi) / pdf, pdf))
}

/// [`dielectric_sample_at_gpu_wi`] for `GgxDielectricMs::sample`: its `pdf` and `eval / pdf`
/// (the dielectric's times the compensation scale) at the GPU's `wi`.
fn dielectric_ms_sample_at_gpu_wi(
    i: &Input,
    _: &GgxConductor,
    k: &GgxDielectric,
    got: &[u32],
    cpu: &[Expect],
) -> Option<Vec<Expect>> {
    let wi = differing_gpu_wi(got, cpu)?;
    let (b, wo, m) = (ms_dielectric(i, k), i.va(), mode(i.n[1]));
    let pdf = b.pdf(wo, wi, Sampling::from_u32(i.n[0]), m);
    Some(rebased(cpu, b.eval(wo, wi, m) / pdf, pdf))
}

/// `thin_dielectric_sample`'s output words: flags; `wi`, the mirror of the normalized `wo` or
/// its opposite, under [`UNIT`] like `normalize_or_zero`; the weight, exactly 1; the pdf, `R'`
/// or `1 - R'` with `R'` a [`FORMULA`] of `fresnel_dielectric`: `1 - R'` cancels towards
/// grazing incidence (`R' -> 1`), so it inherits `R'`'s absolute error (16 ulp of a value
/// near 1 = 2^-20): [`UNIT`].
const THIN_SAMPLE_GROUPS: [Group; 4] = [
    Group::bits("valid,delta", 2),
    Group::float("wi", 3, UNIT),
    Group::float("weight", 3, Bound::Exact),
    Group::float("pdf", 1, UNIT),
];

pub(super) fn energy_specs(s: &mut Specs) {
    // energy.rs
    let scalar = |xs: Vec<f32>| xs.into_iter().map(|x| (Input::scalar(x), none())).collect::<Vec<_>>();
    let coordinates = |xs: Vec<f32>| scalar(scalars().into_iter().chain(xs).collect());
    let all_alphas = || table_alphas(N).into_iter().chain(table_alphas(N_ALPHA)).collect::<Vec<_>>();
    let all_mus = || table_mus(N).into_iter().chain(table_mus(N_MU)).collect::<Vec<_>>();
    s.row("alpha_coordinate", &[Group::value(COORDINATE)], coordinates(all_alphas()), |i, _| {
        floats(&[energy::alpha_coordinate(i.a[0])])
    });
    s.row("mu_coordinate", &[Group::value(FEW_OPS)], coordinates(all_mus()), |i, _| {
        floats(&[energy::mu_coordinate(i.a[0])])
    });
    let albedo_cases = grid(&[with_odd(table_mus(N)), with_odd(table_alphas(N))]);
    s.row("energy_albedo", &[Group::value(LOOKUP)], albedo_cases.iter().map(|p| (args(p), none())), |i, _| {
        floats(&[energy::albedo(i.a[0], i.a[1])])
    });
    s.row("energy_average_albedo", &[Group::value(LOOKUP)], scalar(with_odd(all_alphas())), |i, _| {
        floats(&[energy::average_albedo(i.a[0])])
    });
    // Raw alpha fields (NaN, infinite, negative, huge: read through `alphas()`), the
    // constructor's alphas and pairs of the tables' rows, anisotropic up to 1:1000.
    let raw = SPECIALS.into_iter().flat_map(|x| SPECIALS.map(|y| TrowbridgeReitz { alpha_x: x, alpha_y: y }));
    let rows = every(&table_alphas(N), 6);
    let row_pairs = rows.iter().flat_map(|&x| rows.iter().map(move |&y| TrowbridgeReitz::new(x, y)));
    let effective = dists().into_iter().chain(raw).chain(row_pairs).map(|t| (Input::default(), with_dist(t)));
    s.row("effective_alpha", &[Group::value(FEW_OPS)], effective, |_, k| {
        floats(&[energy::effective_alpha(&k.distribution)])
    });
    // Each F_avg value with two others in the other channels, against E_avg from hostile to
    // every tabulated average; and every Fresnel model's own F_avg.
    let f = [NAN, INF, -INF, -1.0, -0.0, 0.0, 1e-7, 0.04, 0.3, 0.5, 0.9, ONE_MINUS_ULP, 1.0, 1.5];
    let e_avgs: Vec<f32> = with_odd(ggx_core::energy_tables::E_AVG.into_iter().step_by(3).chain([1e-7, 0.5]).collect());
    let f_avgs = (0..f.len())
        .map(|i| Vec3::new(f[i], f[(i + 3) % f.len()], f[(i + 7) % f.len()]))
        .chain(fresnels().into_iter().map(|p| p.average()));
    let ms_fresnel_cases: Vec<(Input, GgxConductor)> = f_avgs
        .flat_map(|fa| e_avgs.iter().map(move |&e| (Input { b: [e, 0.0, 0.0, 0.0], ..Input::dir(fa) }, none())))
        .collect();
    s.row("multiple_scattering_fresnel", &[Group::float("rgb", 3, FORMULA)], ms_fresnel_cases, |i, _| {
        floats(&v3(energy::multiple_scattering_fresnel(i.va(), i.b[0])))
    });

    // conductor_ms.rs
    let variant_cases = || {
        ms_bsdfs()
            .into_iter()
            .chain(dists().into_iter().map(|t| GgxConductor { distribution: t, ..bsdfs()[3] }))
            .flat_map(|k| ms_variants(&k).map(|v| (with_variant(Input::default(), v), k)))
    };
    s.row("ggx_conductor_ms_is_compensated", &[Group::bits("on", 1)], variant_cases(), |i, k| {
        words(&[ms_conductor(i, k).is_compensated() as u32])
    });
    s.row("ggx_conductor_ms_fresnel", &[Group::float("rgb", 3, FORMULA)], variant_cases(), |i, k| {
        floats(&v3(ms_conductor(i, k).ms_fresnel()))
    });
    let probability_cases = ms_bsdfs().into_iter().flat_map(|k| {
        ms_variants(&k)
            .into_iter()
            .flat_map(move |v| directions().into_iter().map(move |wo| (with_variant(Input::dir(wo), v), k)))
    });
    s.row("ggx_conductor_ms_probability", &[Group::value(MS_FORMULA)], probability_cases, |i, k| {
        floats(&[ms_conductor(i, k).ms_probability(i.va())])
    });
    // Every pair with GgxConductorMs::new's lobe, and with one other variant in turn.
    let ms_pairs = || {
        ms_bsdfs().into_iter().flat_map(|k| {
            let dirs = few_directions();
            let pairs = dirs.clone().into_iter().flat_map(move |a| dirs.clone().into_iter().map(move |b| (a, b)));
            pairs.enumerate().flat_map(move |(j, (a, b))| {
                let v = ms_variants(&k);
                [(0, v[0]), (1, v[1 + j % 7])].map(|(n, v)| (n, j, with_variant(Input::pair(a, b), v), k))
            })
        })
    };
    s.row(
        "ggx_conductor_ms_eval_ms",
        &[Group::float("rgb", 3, MS_FORMULA)],
        ms_pairs().map(|(_, _, i, k)| (i, k)),
        |i, k| floats(&v3(ms_conductor(i, k).eval_ms(i.va(), i.vb()))),
    );
    s.row(
        "ggx_conductor_ms_eval",
        &[Group::float("rgb", 3, MS_FORMULA)],
        ms_pairs().map(|(_, _, i, k)| (i, k)),
        |i, k| floats(&v3(ms_conductor(i, k).eval(i.va(), i.vb()))),
    );
    let pdf_cases = ms_pairs().map(|(n, j, i, k)| {
        let t = SAMPLINGS[(j + 3 * n) % SAMPLINGS.len()];
        (Input { n: [t, 0, 0, 0], ..i }, k)
    });
    s.row("ggx_conductor_ms_pdf", &[Group::value(MS_FORMULA)], pdf_cases, |i, k| {
        floats(&[ms_conductor(i, k).pdf(i.va(), i.vb(), Sampling::from_u32(i.n[0]))])
    });
    // The conductor sample row's cases (u in b.xy here), with u_lobe and the variant in turn.
    let few_u = us(&[0.0, 0.25, 0.5, 0.77, ONE_MINUS_ULP]);
    let sample_cases = ms_bsdfs()
        .into_iter()
        .flat_map(|k| {
            let few_u = few_u.clone();
            wo_directions().into_iter().flat_map(move |wo| {
                let few_u = few_u.clone();
                SAMPLINGS.into_iter().flat_map(move |t| few_u.clone().into_iter().map(move |u| (wo, t, u, k)))
            })
        })
        .enumerate()
        .map(|(j, (wo, t, u, k))| {
            let input = Input { b: [u.x, u.y, U_LOBES[j % U_LOBES.len()], 0.0], n: [t, 0, 0, 0], ..Input::dir(wo) };
            (with_variant(input, ms_variants(&k)[j % 8]), k)
        });
    s.row("ggx_conductor_ms_sample", &MS_SAMPLE_GROUPS, sample_cases, |i, k| {
        let u = Vec2::new(i.b[0], i.b[1]);
        sample_words(ms_conductor(i, k).sample(i.va(), u, i.b[2], Sampling::from_u32(i.n[0])))
    })
    .rebase(conductor_ms_sample_at_gpu_wi, "weight, pdf: cpu at the gpu's wi");

    // energy_dielectric.rs
    s.row("eta_coordinate", &[Group::value(FEW_OPS)], coordinates(table_etas()), |i, _| {
        floats(&[energy_dielectric::eta_coordinate(i.a[0])])
    });
    let (mus, alphas, etas) = (table_mus(N_MU), table_alphas(N_ALPHA), table_etas());
    let coat_cases = hostile_grid(&[mus.clone(), alphas.clone(), etas.clone()]);
    s.row("coat_albedo", &[Group::value(LOOKUP)], coat_cases.iter().map(|p| (args(p), none())), |i, _| {
        floats(&[energy_dielectric::coat_albedo(i.a[0], i.a[1], i.a[2])])
    });
    let average_cases = grid(&[with_odd(alphas.clone()), with_odd(etas.clone())]);
    s.row("coat_average_albedo", &[Group::value(LOOKUP)], average_cases.iter().map(|p| (args(p), none())), |i, _| {
        floats(&[energy_dielectric::coat_average_albedo(i.a[0], i.a[1])])
    });
    // A ratio of three lookups, 1 - E_R_avg >= 0.72 and 1 - E_R >= 0.03 (grazing views of
    // eta 3): FORMULA. Measured on llvmpipe: 7 ulp.
    let plastic_cases = hostile_grid(&[every(&mus, 4), every(&mus, 5), every(&alphas, 4), every(&etas, 2)]);
    s.row("plastic_base_weight", &[Group::value(FORMULA)], plastic_cases.iter().map(|p| (args(p), none())), |i, _| {
        floats(&[energy_dielectric::plastic_base_weight(i.a[0], i.a[1], i.a[2], i.a[3])])
    });

    // dielectric_ms.rs
    let on_off = ms_dielectrics()
        .into_iter()
        .flat_map(|k| [1, 0, 0xdead_beef].map(|c| (Input { m: [c, 0, 0, 0], ..Default::default() }, k)));
    s.dielectric_row("ggx_dielectric_ms_is_compensated", &[Group::bits("on", 1)], on_off, |i, k| {
        words(&[ms_dielectric(i, k).is_compensated() as u32])
    });
    // Views from both sides at every column of the tables, and the dielectric directions.
    let columns = (0..N_MU).flat_map(|i| {
        let mu = f64::from(column_mu(i as f32 / (N_MU - 1) as f32));
        [spherical(mu, 0.7), spherical(-mu, 2.3)]
    });
    let scale_wo: Vec<Vec3> = dielectric_directions()
        .into_iter()
        .chain(columns)
        .chain([Vec3::new(0.0, 0.0, INF), Vec3::new(0.0, 0.0, -INF), Vec3::new(0.0, 0.0, -0.0)])
        .collect();
    // Also every row of the tables (where E_T is read at a node) with glass, diamond and the
    // tables' last slice from both sides.
    let node_dielectrics = (0..N_ALPHA).flat_map(|j| {
        let alpha = row_alpha(j as f32 / (N_ALPHA - 1) as f32);
        [1.5, 1.0 / 1.5, 2.4, 1.0 / 2.4, 3.0, 1.0 / 3.0].map(|eta| GgxDielectric::isotropic(alpha, eta))
    });
    let scale_cases =
        ms_dielectrics().into_iter().chain(node_dielectrics).flat_map(|k| {
            scale_wo.clone().into_iter().enumerate().map(move |(j, wo)| {
                (Input { m: [COMPENSATIONS[j % COMPENSATIONS.len()], 0, 0, 0], ..Input::dir(wo) }, k)
            })
        });
    // 1 / E_T, E_T >= 0.019: the lookup's error relative to E_T, plus a division: FORMULA.
    // Measured on llvmpipe: 4 ulp.
    s.dielectric_row("ggx_dielectric_ms_compensation_scale", &[Group::value(FORMULA)], scale_cases, |i, k| {
        floats(&[ms_dielectric(i, k).compensation_scale(i.va())])
    });
    // The dielectric pairs once each: the mode, the compensation word and the technique in turn.
    let ms_pairs = || {
        let dirs = dielectric_directions();
        ms_dielectrics()
            .into_iter()
            .flat_map(move |k| {
                let dirs = dirs.clone();
                dirs.clone().into_iter().flat_map(move |a| dirs.clone().into_iter().map(move |b| (a, b, k)))
            })
            .chain(critical_pairs())
            .enumerate()
            .map(|(j, (a, b, k))| {
                let t = dielectric_samplings(j)[(j / 2) % 3];
                let c = COMPENSATIONS[(j / 2) % COMPENSATIONS.len()];
                (Input { n: [t, (j % 2) as u32, 0, 0], m: [c, 0, 0, 0], ..Input::pair(a, b) }, k)
            })
    };
    // The dielectric's eval (FORMULA, bit-identical on llvmpipe) times the scale: FORMULA.
    // Measured on llvmpipe: 4 ulp; the pdf is the dielectric's, bit-identical.
    s.dielectric_row("ggx_dielectric_ms_eval", &[Group::float("rgb", 3, FORMULA)], ms_pairs(), |i, k| {
        floats(&v3(ms_dielectric(i, k).eval(i.va(), i.vb(), mode(i.n[1]))))
    });
    s.dielectric_row("ggx_dielectric_ms_pdf", &[Group::value(FORMULA)], ms_pairs(), |i, k| {
        floats(&[ms_dielectric(i, k).pdf(i.va(), i.vb(), Sampling::from_u32(i.n[0]), mode(i.n[1]))])
    });
    // ggx_dielectric_sample's cases over the MS dielectrics, with the compensation word in turn.
    let sample_wo: Vec<Vec3> = dielectric_cos()
        .into_iter()
        .map(|c| spherical(c, 2.3))
        .chain([
            Vec3::new(NAN, 0.0, 1.0),
            Vec3::new(0.0, 0.0, -INF),
            Vec3::new(0.3, -0.4, -1.2),
            Vec3::new(1e-20, 0.0, 1e-20),
        ])
        .collect();
    let sample_u = us(&[0.0, 0.5, 0.77, ONE_MINUS_ULP]);
    let sample_cases = ms_dielectrics()
        .into_iter()
        .flat_map(|k| {
            let (sample_wo, sample_u) = (sample_wo.clone(), sample_u.clone());
            sample_wo.into_iter().flat_map(move |wo| {
                let sample_u = sample_u.clone();
                SAMPLINGS.into_iter().flat_map(move |t| {
                    // Cosine and uniform are refused whatever u is: one u each.
                    let us = if t == 4 || t == 5 { sample_u[..1].to_vec() } else { sample_u.clone() };
                    us.into_iter().map(move |u| (wo, t, u, k))
                })
            })
        })
        .enumerate()
        .map(|(j, (wo, t, u, k))| {
            let c = [u.x, u.y, U_LOBES[j % U_LOBES.len()], 0.0];
            let m = [COMPENSATIONS[(j / 2) % COMPENSATIONS.len()], 0, 0, 0];
            (Input { c, n: [t, (j % 2) as u32, 0, 0], m, ..Input::dir(wo) }, k)
        });
    // The dielectric's sample, its weight times the scale: DIELECTRIC_SAMPLE_GROUPS. Measured on
    // llvmpipe: weight 4 ulp, pdf bit-identical.
    s.dielectric_row("ggx_dielectric_ms_sample", &DIELECTRIC_SAMPLE_GROUPS, sample_cases, |i, k| {
        sample_words(ms_dielectric(i, k).sample(i.va(), i.u(), i.c[2], Sampling::from_u32(i.n[0]), mode(i.n[1])))
    })
    .rebase(dielectric_ms_sample_at_gpu_wi, "weight, pdf: cpu at the gpu's wi");

    // thin_dielectric.rs
    let cosines: Vec<f32> =
        FRESNEL_COS.into_iter().chain((0..=64).flat_map(|k| [k as f32 / 64.0, -(k as f32) / 64.0])).collect();
    let reflectance_cases = thin_etas().into_iter().flat_map(|eta| {
        cosines.clone().into_iter().map(move |c| (Input { c: [c, eta, 0.0, 0.0], ..Default::default() }, none()))
    });
    s.row("thin_dielectric_reflectance", &[Group::value(FORMULA)], reflectance_cases, |i, _| {
        floats(&[ThinDielectric { eta: i.c[1], pad: 0 }.reflectance(i.c[0])])
    });
    let thin_wo: Vec<Vec3> = directions().into_iter().chain(dielectric_directions()).collect();
    let thin_cases = thin_etas().into_iter().flat_map(|eta| {
        thin_wo
            .clone()
            .into_iter()
            .flat_map(move |wo| U_LOBES.map(|u_lobe| (Input { c: [0.0, eta, u_lobe, 0.0], ..Input::dir(wo) }, none())))
    });
    s.row("thin_dielectric_sample", &THIN_SAMPLE_GROUPS, thin_cases, |i, _| {
        sample_words(ThinDielectric { eta: i.c[1], pad: 0 }.sample(i.va(), i.c[2]))
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ENERGY_WGSL;

    /// The helpers of energy.wgsl that mirror no public ggx-core function (so have no row), each
    /// with what covers it.
    const ENERGY_HELPERS: [(&str, &str); 7] = [
        ("energy_cell", "energy.rs `cell` (private): every lookup row"),
        ("energy_lerp", "energy.rs `lerp` (private): every lookup row"),
        ("unit_clamp", "conductor_ms.rs `unit` (private): the ggx_conductor_ms rows"),
        ("ms_fresnel_channel", "the closure of multiple_scattering_fresnel: its row"),
        ("energy_trilinear", "energy_dielectric.rs `trilinear` (private): coat_albedo"),
        (
            "dielectric_albedo_side",
            "energy_dielectric.rs `dielectric_albedo_side` (pub(crate)): ggx_dielectric_ms_compensation_scale",
        ),
        ("finite_or_zero3_each", "GgxDielectricMs::eval's per-channel finite_or_zero: ggx_dielectric_ms_eval"),
    ];

    /// The names of energy.wgsl's functions.
    fn wgsl_functions() -> Vec<&'static str> {
        ENERGY_WGSL
            .lines()
            .filter_map(|l| l.strip_prefix("fn "))
            .map(|l| &l[..l.find('(').expect("fn name(")])
            .collect()
    }

    #[test]
    fn every_energy_function_with_a_ggx_core_twin_has_a_row() {
        let functions = wgsl_functions();
        assert!(functions.len() > 20, "{functions:?}");
        let rows: Vec<&str> = specs().iter().map(|s| s.name).collect();
        for f in &functions {
            let helper = ENERGY_HELPERS.iter().any(|(h, _)| h == f);
            assert!(rows.contains(f) != helper, "{f}: a row, or a helper without one");
        }
        for (h, _) in ENERGY_HELPERS {
            assert!(functions.contains(&h), "{h} is a function of energy.wgsl");
        }
    }

    /// [`LOOKUP`]'s derivation, table by table: two ulps of the row coordinate (at most
    /// `N - 1`) times the steepest step between adjacent rows, plus both sides' roundings (a
    /// value of at most 1 rounded twice per level of interpolation), within its absolute bound.
    #[test]
    fn lookup_bound_covers_two_ulps_of_the_row_coordinate() {
        use ggx_core::energy_dielectric_tables::{E_R, E_R_AVG};
        use ggx_core::energy_tables::{E, E_AVG};
        let Bound::UlpsOrAbs(_, abs) = LOOKUP else { panic!("LOOKUP has an absolute bound") };
        let ulp = |x: f32| f32::from_bits(x.to_bits() + 1) - x;
        // Steepest step between adjacent rows of each slice (rows listed as slices of values).
        let steepest = |slices: Vec<Vec<&[f32]>>| {
            let steps = slices.into_iter().flat_map(|rows| {
                let pairs: Vec<(&[f32], &[f32])> = rows.windows(2).map(|w| (w[0], w[1])).collect();
                pairs.into_iter().flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (y - x).abs()))
            });
            steps.fold(0.0f32, f32::max)
        };
        let e = steepest(vec![E.iter().map(|r| r.as_slice()).collect()]);
        let e_avg = steepest(vec![E_AVG.iter().map(std::slice::from_ref).collect()]);
        let e_r = steepest(E_R.iter().map(|k| k.iter().map(|r| r.as_slice()).collect()).collect());
        let e_r_avg = steepest(E_R_AVG.iter().map(|k| k.iter().map(std::slice::from_ref).collect()).collect());
        for (table, step, rows, levels) in
            [("E", e, N, 2.0), ("E_AVG", e_avg, N, 1.0), ("E_R", e_r, N_ALPHA, 3.0), ("E_R_AVG", e_r_avg, N_ALPHA, 2.0)]
        {
            let error = 2.0 * ulp((rows - 1) as f32) * step + 2.0 * levels * f32::EPSILON / 2.0;
            assert!(step > 0.0 && error <= abs, "{table}: {error:e} above {abs:e} (steepest step {step})");
        }
    }

    #[test]
    fn the_ms_rows_turn_compensation_off_and_on() {
        for spec in specs().iter().filter(|s| s.name.contains("_ms_")) {
            let words: Vec<u32> = spec.cases.iter().map(|i| i.m[0]).collect();
            assert!(words.contains(&0) && words.contains(&1), "{}", spec.name);
            assert!(words.iter().any(|&w| w > 1), "{}: another non-zero word", spec.name);
        }
    }

    #[test]
    fn the_lookup_rows_meet_hostile_arguments() {
        let rows = [
            ("alpha_coordinate", 1),
            ("mu_coordinate", 1),
            ("eta_coordinate", 1),
            ("energy_albedo", 2),
            ("energy_average_albedo", 1),
            ("coat_albedo", 3),
            ("coat_average_albedo", 2),
            ("plastic_base_weight", 4),
        ];
        let hostile = [NAN, INF, -INF, -1.0, 0.0, ONE_MINUS_ULP, 1.0, f32::MAX];
        let specs = specs();
        for (name, arguments) in rows {
            let spec = specs.iter().find(|s| s.name == name).expect(name);
            for d in 0..arguments {
                for x in hostile {
                    let found = spec.cases.iter().any(|i| i.a[d].to_bits() == x.to_bits());
                    assert!(found, "{name}: argument {d} never {x}");
                }
            }
        }
    }
}
