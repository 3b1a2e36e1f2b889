//! Just enough complex arithmetic in f32 for the conductor Fresnel equations.

use crate::math::sqrt;

/// `re + i im`.
#[derive(Clone, Copy)]
pub(crate) struct Complex {
    pub re: f32,
    pub im: f32,
}

impl Complex {
    pub fn new(re: f32, im: f32) -> Self {
        Self { re, im }
    }
    pub fn real(re: f32) -> Self {
        Self { re, im: 0.0 }
    }
    pub fn add(self, o: Self) -> Self {
        Self::new(self.re + o.re, self.im + o.im)
    }
    pub fn sub(self, o: Self) -> Self {
        Self::new(self.re - o.re, self.im - o.im)
    }
    pub fn mul(self, o: Self) -> Self {
        Self::new(self.re * o.re - self.im * o.im, self.re * o.im + self.im * o.re)
    }
    /// `a / b = a conj(b) / |b|^2`.
    pub fn div(self, o: Self) -> Self {
        let scale = 1.0 / (o.re * o.re + o.im * o.im);
        Self::new((self.re * o.re + self.im * o.im) * scale, (self.im * o.re - self.re * o.im) * scale)
    }
    /// `|z|^2`.
    pub fn norm(self) -> f32 {
        self.re * self.re + self.im * self.im
    }
    /// Principal square root: `t1 = sqrt((|z| + |re|) / 2)`, `t2 = im / (2 t1)` (Press et al. 5.4).
    pub fn sqrt(self) -> Self {
        let n = sqrt(self.norm());
        if n == 0.0 {
            return Self::real(0.0);
        }
        let t1 = sqrt(0.5 * (n + self.re.abs()));
        let t2 = 0.5 * self.im / t1;
        if self.re >= 0.0 { Self::new(t1, t2) } else { Self::new(t2.abs(), t1.copysign(self.im)) }
    }
}
