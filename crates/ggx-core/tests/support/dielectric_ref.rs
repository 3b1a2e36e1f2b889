//! An f64 rough dielectric written independently of ggx-core (no `ggx_core` import): absolute
//! indices (`1` on the `+z` side, `eta` on the `-z` side) instead of `eta'`, Walter et al.
//! 2007 eq. 21 for `f_t`, the trigonometric `D` and `Lambda`, and Fresnel in Walter's eq. 22
//! form `F = (g - c)^2 / (2 (g + c)^2) (1 + ((c (g + c) - 1) / (c (g - c) + 1))^2)`,
//! `g^2 = eta_t^2 / eta_i^2 - 1 + c^2`.

use core::f64::consts::PI;

/// An f64 vector.
pub type V = [f64; 3];

/// Dot product.
pub fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a + s b`.
pub fn add(a: V, s: f64, b: V) -> V {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

/// Unit vector (the input must be non-zero).
pub fn unit(a: V) -> V {
    let l = dot(a, a).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

/// The dielectric: alphas and the relative index of the `-z` side.
#[derive(Clone, Copy, Debug)]
pub struct RefDielectric {
    /// Width along x.
    pub ax: f64,
    /// Width along y.
    pub ay: f64,
    /// Index of the `-z` side (the `+z` side has 1).
    pub eta: f64,
}

impl RefDielectric {
    /// Walter 2007 eq. 33 (anisotropic, Heitz 2014 eq. 85), trigonometric form.
    pub fn d(&self, m: V) -> f64 {
        if m[2] <= 0.0 {
            return 0.0;
        }
        let cos2 = m[2] * m[2] / dot(m, m);
        let tan2 = (1.0 - cos2) / cos2;
        let r2 = m[0] * m[0] + m[1] * m[1];
        let (c2, s2) = if r2 > 0.0 { (m[0] * m[0] / r2, m[1] * m[1] / r2) } else { (1.0, 0.0) };
        let e = tan2 * (c2 / (self.ax * self.ax) + s2 / (self.ay * self.ay));
        1.0 / (PI * self.ax * self.ay * cos2 * cos2 * (1.0 + e) * (1.0 + e))
    }

    /// Heitz 2014 eq. 86: `(-1 + sqrt(1 + alpha(phi)^2 tan^2 theta)) / 2`.
    pub fn lambda(&self, w: V) -> f64 {
        let a2t2 = (self.ax * self.ax * w[0] * w[0] + self.ay * self.ay * w[1] * w[1]) / (w[2] * w[2]);
        (-1.0 + (1.0 + a2t2).sqrt()) / 2.0
    }

    /// Index of the medium on `w`'s side.
    pub fn index(&self, w: V) -> f64 {
        if w[2] > 0.0 { 1.0 } else { self.eta }
    }

    /// Walter 2007 eq. 22 for light on the side of index `n1` hitting a facet, `c = |cos|`,
    /// the other side of index `n2`.
    pub fn fresnel(c: f64, n1: f64, n2: f64) -> f64 {
        let g2 = (n2 / n1).powi(2) - 1.0 + c * c;
        if g2 < 0.0 {
            return 1.0;
        }
        let g = g2.sqrt();
        let a = (g - c) / (g + c);
        let b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
        0.5 * a * a * (1.0 + b * b)
    }

    /// `(half vector on +z, reflect?)`, or `None` where the side rules fail.
    pub fn half(&self, wo: V, wi: V) -> Option<(V, bool)> {
        let reflect = wo[2] * wi[2] > 0.0;
        let h = if reflect { add(wo, 1.0, wi) } else { add([0.0; 3], self.index(wo), wo) };
        let h = if reflect { h } else { add(h, self.index(wi), wi) };
        if dot(h, h) == 0.0 {
            return None;
        }
        let mut m = unit(h);
        if m[2] < 0.0 {
            m = [-m[0], -m[1], -m[2]];
        }
        if dot(wo, m) * wo[2] <= 0.0 || dot(wi, m) * wi[2] <= 0.0 {
            return None;
        }
        Some((m, reflect))
    }

    /// `f(wo, wi) |wi.z|`; Walter 2007 eq. 20 (reflection) and eq. 21 with absolute indices
    /// (transmission): `(1 - F) D G2 |wi.m| |wo.m| n^2 / (|wi.z| |wo.z| (n_o wo.m + n_i wi.m)^2)`,
    /// `n = n_o` for radiance, `n_i` for importance. Times `|wi.z|`.
    pub fn eval(&self, wo: V, wi: V, radiance: bool) -> f64 {
        let Some((m, reflect)) = self.half(wo, wi) else { return 0.0 };
        let g2 = 1.0 / (1.0 + self.lambda(wo) + self.lambda(wi));
        let (n_o, n_i) = (self.index(wo), self.index(wi));
        let f = Self::fresnel(dot(wo, m).abs(), n_o, if reflect { self.index([0.0, 0.0, -wo[2]]) } else { n_i });
        let f = if reflect {
            f * self.d(m) * g2 / (4.0 * wo[2].abs() * wi[2].abs())
        } else {
            let n = if radiance { n_o } else { n_i };
            let s = n_o * dot(wo, m) + n_i * dot(wi, m);
            (1.0 - f) * self.d(m) * g2 * (dot(wi, m) * dot(wo, m)).abs() * n * n / ((wi[2] * wo[2]).abs() * s * s)
        };
        f * wi[2].abs()
    }

    /// Density of `wi` with visible-normal (`vndf = true`) or NDF sampling:
    /// `P(lobe) p(m) dm/dwi`, `p(m) = G1(wo) |wo.m| D(m) / |wo.z|` or `D(m) m.z`.
    pub fn pdf(&self, wo: V, wi: V, vndf: bool) -> f64 {
        let Some((m, reflect)) = self.half(wo, wi) else { return 0.0 };
        let (n_o, n_i) = (self.index(wo), self.index(wi));
        let f = Self::fresnel(dot(wo, m).abs(), n_o, if reflect { self.index([0.0, 0.0, -wo[2]]) } else { n_i });
        let pm = if vndf {
            dot(wo, m).abs() * self.d(m) / ((1.0 + self.lambda(wo)) * wo[2].abs())
        } else {
            self.d(m) * m[2]
        };
        if reflect {
            f * pm / (4.0 * dot(wo, m).abs())
        } else {
            let s = n_o * dot(wo, m) + n_i * dot(wi, m);
            (1.0 - f) * pm * n_i * n_i * dot(wi, m).abs() / (s * s)
        }
    }

    /// Directional albedo `integral f |wi.z| dwi` over the sphere, as an integral over the
    /// microfacet normal: `integral D(m) |wo.m| / |wo.z| (F G2(wo, wr) + (1 - F) G2(wo, wt) s) dm`,
    /// `s = n_o^2 / n_i^2` for radiance, 1 for importance. Returns (reflection, transmission).
    /// Parameterized by stretched slopes `m ~ (ax r cos phi, ay r sin phi, 1)`,
    /// `r = t / (1 - t)`, where `D dm = r dr dphi / (pi (1 + r^2)^2 cos theta_m)`.
    pub fn albedo_integrand(&self, wo: V, t: f64, phi: f64, radiance: bool) -> (f64, f64) {
        let r = t / (1.0 - t);
        let m = unit([self.ax * r * phi.cos(), self.ay * r * phi.sin(), 1.0]);
        let d_dm = r / (PI * (1.0 + r * r).powi(2) * m[2]) / ((1.0 - t) * (1.0 - t));
        let c = dot(wo, m);
        if c * wo[2] <= 0.0 {
            return (0.0, 0.0);
        }
        let n_o = self.index(wo);
        let n_t = self.index([0.0, 0.0, -wo[2]]);
        let f = Self::fresnel(c.abs(), n_o, n_t);
        let g2 = |wi: V| 1.0 / (1.0 + self.lambda(wo) + self.lambda(wi));
        let base = d_dm * c.abs() / wo[2].abs();
        let wr = add([-wo[0], -wo[1], -wo[2]], 2.0 * c, m);
        let er = if wr[2] * wo[2] > 0.0 { f * g2(wr) * base } else { 0.0 };
        // Snell in f64: wt = -wo / e + (|c| / e - cos_t) m', m' = sign(c) m, e = n_t / n_o.
        let e = n_t / n_o;
        let sin2_t = (1.0 - c * c) / (e * e);
        let mut et = 0.0;
        if sin2_t < 1.0 {
            let cos_t = (1.0 - sin2_t).sqrt();
            let ms = if c > 0.0 { m } else { [-m[0], -m[1], -m[2]] };
            let wt = add([-wo[0] / e, -wo[1] / e, -wo[2] / e], c.abs() / e - cos_t, ms);
            if wt[2] * wo[2] < 0.0 {
                let s = if radiance { (n_o / n_t).powi(2) } else { 1.0 };
                et = (1.0 - f) * g2(wt) * base * s;
            }
        }
        (er, et)
    }
}

impl RefDielectric {
    /// Relative error bound of an f32 `eval` or `pdf` of a pair: `1e-4 + 3e-7 e^2 / c^2`,
    /// `e = max(eta, 1 / eta)`, `c = min(|wo.m|, cos_t)` with `cos_t` the facet cosine of the
    /// refracted direction (`c = 1` under total internal reflection). A small `cos_t` seen
    /// from the denser side is the critical angle, where `fresnel_dielectric` computes
    /// `cos_t^2 = 1 - sin_t^2` by cancellation (absolute error ~6e-8): `F` and `1 - F` are
    /// ill-conditioned there in any f32 code, for reflection and transmission alike.
    pub fn tolerance(&self, wo: V, wi: V) -> f64 {
        let c = match self.half(wo, wi) {
            Some((m, _)) => {
                let c_o = dot(wo, m).abs();
                let ratio = self.index(wo) / self.index([0.0, 0.0, -wo[2]]);
                let cos2_t = 1.0 - ratio * ratio * (1.0 - c_o * c_o);
                if cos2_t <= 0.0 { 1.0 } else { c_o.min(cos2_t.sqrt()) }
            }
            None => 1.0,
        };
        let e = self.eta.max(1.0 / self.eta);
        1e-4 + 3e-7 * e * e / (c * c)
    }
}
