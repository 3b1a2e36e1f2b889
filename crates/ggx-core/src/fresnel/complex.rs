//! Just enough complex arithmetic for the conductor Fresnel equations, over any [`Lanes`]
//! (one `f32`, or the three RGB channels at once).

use crate::lanes::Lanes;

/// `re + i im`.
#[derive(Clone, Copy)]
pub(crate) struct Complex<L> {
    pub re: L,
    pub im: L,
}

impl<L: Lanes> Complex<L> {
    pub fn new(re: L, im: L) -> Self {
        Self { re, im }
    }
    pub fn real(re: L) -> Self {
        Self { re, im: L::splat(0.0) }
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
        let scale = L::splat(1.0) / (o.re * o.re + o.im * o.im);
        Self::new((self.re * o.re + self.im * o.im) * scale, (self.im * o.re - self.re * o.im) * scale)
    }
    /// `|z|^2`.
    pub fn norm(self) -> L {
        self.re * self.re + self.im * self.im
    }
    /// Principal square root: `t1 = sqrt((|z| + |re|) / 2)`, `t2 = im / (2 t1)` (Press et al. 5.4);
    /// `0` where `|z|` is 0, and `(|t2|, t1 sign(im))` where `re < 0`.
    #[inline(always)]
    pub fn sqrt(self) -> Self {
        let n = self.norm().sqrt();
        let t1 = (L::splat(0.5) * (n + self.re.abs())).sqrt();
        let t2 = L::splat(0.5) * self.im / t1;
        let zero = n.eq(L::splat(0.0));
        let right = self.re.ge(L::splat(0.0));
        let (re, im) = (L::select(right, t1, t2.abs()), L::select(right, t2, t1.copysign(self.im)));
        Self::new(L::select(zero, L::splat(0.0), re), L::select(zero, L::splat(0.0), im))
    }
}
