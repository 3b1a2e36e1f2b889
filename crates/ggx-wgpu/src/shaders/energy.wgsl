// ggx-core's energy compensation and its other BSDFs, function by function: energy.rs,
// conductor_ms.rs (GgxConductorMs), energy_dielectric.rs, dielectric_ms.rs (GgxDielectricMs)
// and thin_dielectric.rs (ThinDielectric). Expects ggx_core.wgsl in front of it and, from the
// shader that includes it, `fn energy_table(i: u32) -> f32`: value `i` of the tables laid out
// as ggx-wgpu's `scene_upload::energy_tables()` lists them (ENERGY_* offsets below).

// energy_tables.rs N: nodes per axis of the conductor's E(mu, alpha) table.
const ENERGY_N: u32 = 48u;
// Offset of E (ENERGY_N x ENERGY_N, row j = alpha, column i = mu) and of E_AVG (ENERGY_N).
const ENERGY_E: u32 = 0u;
const ENERGY_E_AVG: u32 = 2304u;
// energy_dielectric_tables.rs dims: N_MU columns, N_ALPHA rows, N_ETA slices.
const DIELECTRIC_N_MU: u32 = 32u;
const DIELECTRIC_N_ALPHA: u32 = 32u;
const DIELECTRIC_N_ETA: u32 = 12u;
// Offsets of E_T_OUTSIDE, E_T_INSIDE, E_R (N_ETA x N_ALPHA x N_MU each) and E_R_AVG (N_ETA x N_ALPHA).
const ENERGY_E_T_OUTSIDE: u32 = 2352u;
const ENERGY_E_T_INSIDE: u32 = 14640u;
const ENERGY_E_R: u32 = 26928u;
const ENERGY_E_R_AVG: u32 = 39216u;
// Values in all the tables.
const ENERGY_TABLES_LEN: u32 = 39600u;
// DELTA_ALPHA^(1/4).
const ROOT4_DELTA_ALPHA: f32 = 0.17782794f;
// energy_dielectric.rs ETA_TABLE_MAX, Q_MAX = (ETA_TABLE_MAX - 1) / (ETA_TABLE_MAX + 1), DIELECTRIC_ALBEDO_MIN.
const ETA_TABLE_MAX: f32 = 3.0f;
const Q_MAX: f32 = 0.5f;
const DIELECTRIC_ALBEDO_MIN: f32 = 0.01f;

// ---------------------------------------------------------------------------------------------
// energy.rs
// ---------------------------------------------------------------------------------------------

struct Cell {
    i: u32,
    t: f32,
}

// x (n - 1) clamped to [0, n - 1] (NaN -> 0), split into a cell index i <= n - 2 and t in [0, 1].
fn energy_cell(x: f32, n: u32) -> Cell {
    let last = f32(n - 1u);
    let y = min_num(max_num(x * last, 0.0), last);
    let i = min(u32(y), n - 2u);
    return Cell(i, y - f32(i));
}

// a + t (b - a).
fn energy_lerp(a: f32, b: f32, t: f32) -> f32 {
    return a + t * (b - a);
}

// (alpha^(1/4) - DELTA_ALPHA^(1/4)) / (1 - DELTA_ALPHA^(1/4)), alpha clamped to [0, 1].
fn alpha_coordinate(alpha: f32) -> f32 {
    return (safe_sqrt(safe_sqrt(min_num(max_num(alpha, 0.0), 1.0))) - ROOT4_DELTA_ALPHA) * (1.0 / (1.0 - ROOT4_DELTA_ALPHA));
}

// mu^(1/4), mu clamped to [0, 1].
fn mu_coordinate(mu: f32) -> f32 {
    return safe_sqrt(safe_sqrt(min_num(max_num(mu, 0.0), 1.0)));
}

// E(mu, alpha): bilinear in (alpha_coordinate, mu_coordinate) on the conductor's table, in [0, 1].
fn energy_albedo(mu: f32, alpha: f32) -> f32 {
    let c = energy_cell(mu_coordinate(mu), ENERGY_N);
    let r = energy_cell(alpha_coordinate(alpha), ENERGY_N);
    let row0 = ENERGY_E + r.i * ENERGY_N + c.i;
    let row1 = row0 + ENERGY_N;
    let lo = energy_lerp(energy_table(row0), energy_table(row0 + 1u), c.t);
    let hi = energy_lerp(energy_table(row1), energy_table(row1 + 1u), c.t);
    return min_num(max_num(energy_lerp(lo, hi, r.t), 0.0), 1.0);
}

// E_avg(alpha): linear in alpha_coordinate, in [0, 1].
fn energy_average_albedo(alpha: f32) -> f32 {
    let r = energy_cell(alpha_coordinate(alpha), ENERGY_N);
    let v = energy_lerp(energy_table(ENERGY_E_AVG + r.i), energy_table(ENERGY_E_AVG + r.i + 1u), r.t);
    return min_num(max_num(v, 0.0), 1.0);
}

// sqrt((alpha_x^2 + alpha_y^2) / 2) of the clamped alphas.
fn effective_alpha(dist: TrowbridgeReitz) -> f32 {
    let a = alphas(dist);
    return safe_sqrt(0.5 * (a.x * a.x + a.y * a.y));
}

// x clamped to [0, 1], NaN -> 0.
fn unit_clamp(x: f32) -> f32 {
    return min_num(max_num(x, 0.0), 1.0);
}

// F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)) for one channel (Kulla & Conty 2017), in [0, 1].
fn ms_fresnel_channel(f_in: f32, e: f32) -> f32 {
    let f = unit_clamp(f_in);
    return unit_clamp(finite_or_zero(f * f * e / (1.0 - f * (1.0 - e))));
}

// multiple_scattering_fresnel per channel.
fn multiple_scattering_fresnel(f_avg: vec3<f32>, e_avg: f32) -> vec3<f32> {
    let e = unit_clamp(e_avg);
    return vec3(ms_fresnel_channel(f_avg.x, e), ms_fresnel_channel(f_avg.y, e), ms_fresnel_channel(f_avg.z, e));
}

// ---------------------------------------------------------------------------------------------
// conductor_ms.rs: GgxConductorMs (fields passed one by one: the conductor, F_avg, compensation)
// ---------------------------------------------------------------------------------------------

struct GgxConductorMs {
    conductor: GgxConductor,
    f_avg: vec3<f32>,
    compensation: u32,
}

// compensation != 0 and not a mirror.
fn ggx_conductor_ms_is_compensated(b: GgxConductorMs) -> bool {
    return b.compensation != 0u && !ggx_conductor_is_delta(b.conductor);
}

// F_ms of the material from the cached F_avg and E_avg(effective alpha).
fn ggx_conductor_ms_fresnel(b: GgxConductorMs) -> vec3<f32> {
    let f_avg = vec3(unit_clamp(b.f_avg.x), unit_clamp(b.f_avg.y), unit_clamp(b.f_avg.z));
    return multiple_scattering_fresnel(f_avg, energy_average_albedo(effective_alpha(b.conductor.distribution)));
}

// f_ms |wi.z| = F_ms (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)) wi.z (Kulla & Conty 2017).
fn ggx_conductor_ms_eval_ms(b: GgxConductorMs, wo_in: vec3<f32>, wi_in: vec3<f32>) -> vec3<f32> {
    let wo = normalize_or_zero(wo_in);
    let wi = normalize_or_zero(wi_in);
    if !(wo.z > 0.0 && wi.z > 0.0 && ggx_conductor_ms_is_compensated(b)) {
        return vec3(0.0);
    }
    let alpha = effective_alpha(b.conductor.distribution);
    let one_minus_avg = 1.0 - energy_average_albedo(alpha);
    if one_minus_avg < 1e-6f {
        return vec3(0.0);
    }
    let s = (1.0 - energy_albedo(wo.z, alpha)) * (1.0 - energy_albedo(wi.z, alpha)) * FRAC_1_PI / one_minus_avg;
    return ggx_conductor_ms_fresnel(b) * finite_or_zero(s * wi.z);
}

// (f_ss + f_ms) |wi.z|.
fn ggx_conductor_ms_eval(b: GgxConductorMs, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    return ggx_conductor_eval(b.conductor, wo, wi) + ggx_conductor_ms_eval_ms(b, wo, wi);
}

// P_ms = a_ms / (a_ss + a_ms), a_ms = mean(F_ms) (1 - E(mu_o)), a_ss = mean(F_avg) E(mu_o), at most 0.999.
fn ggx_conductor_ms_probability(b: GgxConductorMs, wo_in: vec3<f32>) -> f32 {
    let wo = normalize_or_zero(wo_in);
    if !(wo.z > 0.0) || !ggx_conductor_ms_is_compensated(b) {
        return 0.0;
    }
    let e = energy_albedo(wo.z, effective_alpha(b.conductor.distribution));
    let f_ms = ggx_conductor_ms_fresnel(b);
    let a_ms = (f_ms.x + f_ms.y + f_ms.z) * (1.0 / 3.0) * (1.0 - e);
    let a_ss = (unit_clamp(b.f_avg.x) + unit_clamp(b.f_avg.y) + unit_clamp(b.f_avg.z)) * (1.0 / 3.0) * e;
    let p = a_ms / (a_ss + a_ms);
    return min_num(max_num(finite_or_zero(p), 0.0), 0.999f);
}

// (1 - P_ms) pdf_ss + P_ms wi.z / pi.
fn ggx_conductor_ms_pdf(b: GgxConductorMs, wo: vec3<f32>, wi: vec3<f32>, sampling: u32) -> f32 {
    let pdf_ss = ggx_conductor_pdf(b.conductor, wo, wi, sampling);
    if !ggx_conductor_ms_is_compensated(b) {
        return pdf_ss;
    }
    let p = ggx_conductor_ms_probability(b, wo);
    let pdf_ms = pdf_cosine_hemisphere(normalize_or_zero(wi));
    return finite_or_zero((1.0 - p) * pdf_ss + p * pdf_ms);
}

// Cosine lobe when u_lobe < P_ms, else the conductor's sampler; weight = eval / pdf of the mixture.
fn ggx_conductor_ms_sample(b: GgxConductorMs, wo_in: vec3<f32>, u: vec2<f32>, u_lobe: f32, sampling: u32) -> BsdfSample {
    var none: BsdfSample;
    if !ggx_conductor_ms_is_compensated(b) {
        return ggx_conductor_sample(b.conductor, wo_in, u, sampling);
    }
    let wo = normalize_or_zero(wo_in);
    if !(wo.z > 0.0) {
        return none;
    }
    var wi: vec3<f32>;
    if sanitize_u(u_lobe) < ggx_conductor_ms_probability(b, wo) {
        wi = sample_cosine_hemisphere(u);
    } else {
        let s = ggx_conductor_sample(b.conductor, wo, u, sampling);
        if s.valid == 0u {
            return none;
        }
        wi = s.wi;
    }
    let pdf = ggx_conductor_ms_pdf(b, wo, wi, sampling);
    let weight = ggx_conductor_ms_eval(b, wo, wi) / pdf;
    if !(pdf > 0.0 && is_finite(pdf) && is_finite3(weight)) {
        return none;
    }
    return BsdfSample(wi, weight, pdf, 0u, 1u);
}

// ---------------------------------------------------------------------------------------------
// energy_dielectric.rs
// ---------------------------------------------------------------------------------------------

// sqrt(q / q_max), q = (eta - 1) / (eta + 1), eta clamped to [1, ETA_TABLE_MAX] (NaN -> 1).
fn eta_coordinate(eta_in: f32) -> f32 {
    let eta = min_num(max_num(eta_in, 1.0), ETA_TABLE_MAX);
    return min_num(safe_sqrt((eta - 1.0) / ((eta + 1.0) * Q_MAX)), 1.0);
}

// Trilinear lookup of the N_ETA x N_ALPHA x N_MU table at `base` in (eta, alpha, mu) coordinates.
fn energy_trilinear(base: u32, mu: f32, alpha: f32, eta: f32) -> f32 {
    let c = energy_cell(mu_coordinate(mu), DIELECTRIC_N_MU);
    let r = energy_cell(alpha_coordinate(alpha), DIELECTRIC_N_ALPHA);
    let k = energy_cell(eta_coordinate(eta), DIELECTRIC_N_ETA);
    var planes: array<f32, 2>;
    for (var dk = 0u; dk < 2u; dk++) {
        let row0 = base + ((k.i + dk) * DIELECTRIC_N_ALPHA + r.i) * DIELECTRIC_N_MU + c.i;
        let row1 = row0 + DIELECTRIC_N_MU;
        let lo = energy_lerp(energy_table(row0), energy_table(row0 + 1u), c.t);
        let hi = energy_lerp(energy_table(row1), energy_table(row1 + 1u), c.t);
        planes[dk] = energy_lerp(lo, hi, r.t);
    }
    return energy_lerp(planes[0], planes[1], k.t);
}

// E_T from one side: the inside table at index eta when `inside`, else the outside one; in [DIELECTRIC_ALBEDO_MIN, 1].
fn dielectric_albedo_side(mu: f32, alpha: f32, eta: f32, inside: bool) -> f32 {
    let base = select(ENERGY_E_T_OUTSIDE, ENERGY_E_T_INSIDE, inside);
    return min_num(max_num(energy_trilinear(base, mu, alpha, eta), DIELECTRIC_ALBEDO_MIN), 1.0);
}

// E_R(mu, alpha, eta): the coat's reflection albedo, in [0, 1].
fn coat_albedo(mu: f32, alpha: f32, eta: f32) -> f32 {
    return unit_clamp(energy_trilinear(ENERGY_E_R, mu, alpha, eta));
}

// E_R_avg(alpha, eta): bilinear on E_R_AVG, in [0, 1].
fn coat_average_albedo(alpha: f32, eta: f32) -> f32 {
    let r = energy_cell(alpha_coordinate(alpha), DIELECTRIC_N_ALPHA);
    let k = energy_cell(eta_coordinate(eta), DIELECTRIC_N_ETA);
    let row0 = ENERGY_E_R_AVG + k.i * DIELECTRIC_N_ALPHA + r.i;
    let row1 = row0 + DIELECTRIC_N_ALPHA;
    let lo = energy_lerp(energy_table(row0), energy_table(row0 + 1u), r.t);
    let hi = energy_lerp(energy_table(row1), energy_table(row1 + 1u), r.t);
    return unit_clamp(energy_lerp(lo, hi, k.t));
}

// (1 - E_R(mu_o)) (1 - E_R(mu_i)) / (1 - E_R_avg) (Kulla & Conty 2017's albedo coupling); 0 where 1 - E_R_avg < 1e-6.
fn plastic_base_weight(mu_o: f32, mu_i: f32, alpha: f32, eta: f32) -> f32 {
    let one_minus_avg = 1.0 - coat_average_albedo(alpha, eta);
    if !(one_minus_avg >= 1e-6f) {
        return 0.0;
    }
    let w = (1.0 - coat_albedo(mu_o, alpha, eta)) * (1.0 - coat_albedo(mu_i, alpha, eta)) / one_minus_avg;
    return max_num(finite_or_zero(w), 0.0);
}

// ---------------------------------------------------------------------------------------------
// dielectric_ms.rs: GgxDielectricMs
// ---------------------------------------------------------------------------------------------

struct GgxDielectricMs {
    dielectric: GgxDielectric,
    compensation: u32,
    pad: array<u32, 3>,
}

// compensation != 0 and a rough interface.
fn ggx_dielectric_ms_is_compensated(b: GgxDielectricMs) -> bool {
    return b.compensation != 0u && !ggx_dielectric_is_delta(b.dielectric);
}

// 1 / E_T(|wo.z|, effective alpha, eta'_o) (Turquin 2019), the table of the denser side read at max(eta, 1 / eta).
fn ggx_dielectric_ms_compensation_scale(b: GgxDielectricMs, wo_in: vec3<f32>) -> f32 {
    if !ggx_dielectric_ms_is_compensated(b) {
        return 1.0;
    }
    let wo = normalize_or_zero(wo_in);
    let eta = ggx_dielectric_eta(b.dielectric);
    var index = eta;
    var denser = !(wo.z > 0.0);
    if eta < 1.0 {
        index = 1.0 / eta;
        denser = wo.z > 0.0;
    }
    return 1.0 / dielectric_albedo_side(abs(wo.z), effective_alpha(b.dielectric.distribution), index, denser);
}

// f_ss |wi.z| / E_T(wo).
fn ggx_dielectric_ms_eval(b: GgxDielectricMs, wo: vec3<f32>, wi: vec3<f32>, mode: u32) -> vec3<f32> {
    let f = ggx_dielectric_eval(b.dielectric, wo, wi, mode);
    if !ggx_dielectric_ms_is_compensated(b) {
        return f;
    }
    return finite_or_zero3_each(f * ggx_dielectric_ms_compensation_scale(b, wo));
}

// The dielectric's pdf: the scale does not move samples.
fn ggx_dielectric_ms_pdf(b: GgxDielectricMs, wo: vec3<f32>, wi: vec3<f32>, sampling: u32, mode: u32) -> f32 {
    return ggx_dielectric_pdf(b.dielectric, wo, wi, sampling, mode);
}

// The dielectric's sample with a rough sample's weight times the scale.
fn ggx_dielectric_ms_sample(b: GgxDielectricMs, wo: vec3<f32>, u: vec2<f32>, u_lobe: f32, sampling: u32, mode: u32) -> BsdfSample {
    var none: BsdfSample;
    var s = ggx_dielectric_sample(b.dielectric, wo, u, u_lobe, sampling, mode);
    if s.valid != 0u && ggx_dielectric_ms_is_compensated(b) && s.is_delta == 0u {
        s.weight *= ggx_dielectric_ms_compensation_scale(b, wo);
        if !is_finite3(s.weight) {
            return none;
        }
    }
    return s;
}

// Vec3::new(finite_or_zero(x), finite_or_zero(y), finite_or_zero(z)).
fn finite_or_zero3_each(v: vec3<f32>) -> vec3<f32> {
    return vec3(finite_or_zero(v.x), finite_or_zero(v.y), finite_or_zero(v.z));
}

// ---------------------------------------------------------------------------------------------
// thin_dielectric.rs: ThinDielectric
// ---------------------------------------------------------------------------------------------

// R' = R + T^2 R / (1 - R^2), R = F(|cos|, eta), T = 1 - R (pbrt-v4 ThinDielectricBxDF).
fn thin_dielectric_reflectance(eta: f32, cos_theta: f32) -> f32 {
    let r = fresnel_dielectric(abs(cos_theta), clamp_eta(eta));
    if !(r < 1.0) {
        return 1.0;
    }
    let t = 1.0 - r;
    return min_num(max_num(r + t * t * r / (1.0 - r * r), 0.0), 1.0);
}

// Mirror with probability R' (by u_lobe), else -wo; weight 1, pdf the lobe's probability.
fn thin_dielectric_sample(eta: f32, wo_in: vec3<f32>, u_lobe: f32) -> BsdfSample {
    var none: BsdfSample;
    let wo = normalize_or_zero(wo_in);
    if !(wo.z != 0.0) {
        return none;
    }
    let r = thin_dielectric_reflectance(eta, wo.z);
    var wi = -wo;
    var pdf = 1.0 - r;
    if sanitize_u(u_lobe) < r {
        wi = vec3(-wo.x, -wo.y, wo.z);
        pdf = r;
    }
    if !(pdf > 0.0) {
        return none;
    }
    return BsdfSample(wi, vec3(1.0), pdf, 1u, 1u);
}
