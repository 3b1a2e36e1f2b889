//! Validation helpers: finite numbers, ranges, keys that must or must not be present.
//! Each returns a located [`SceneError`] that points at the offending value.

use std::fmt;

use toml::Spanned;

use crate::error::{ErrorKind, SceneError, Source};

/// An allowed range of a number, shown in messages (`in [0, 1]`, `> 0`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Interval {
    lo: f32,
    lo_open: bool,
    hi: f32,
    hi_open: bool,
}

impl Interval {
    /// `[lo, hi]`.
    pub const fn closed(lo: f32, hi: f32) -> Self {
        Self { lo, lo_open: false, hi, hi_open: false }
    }
    /// `(lo, hi)`.
    pub const fn open(lo: f32, hi: f32) -> Self {
        Self { lo, lo_open: true, hi, hi_open: true }
    }
    /// `(lo, hi]`.
    pub const fn open_closed(lo: f32, hi: f32) -> Self {
        Self { lo, lo_open: true, hi, hi_open: false }
    }
    /// `[lo, inf)`.
    pub const fn at_least(lo: f32) -> Self {
        Self { lo, lo_open: false, hi: f32::INFINITY, hi_open: true }
    }
    /// `(lo, inf)`.
    pub const fn above(lo: f32) -> Self {
        Self { lo, lo_open: true, hi: f32::INFINITY, hi_open: true }
    }
    /// Any finite number.
    pub const ANY: Self = Self::open(f32::NEG_INFINITY, f32::INFINITY);

    fn contains(self, x: f32) -> bool {
        let lo_ok = if self.lo_open { x > self.lo } else { x >= self.lo };
        let hi_ok = if self.hi_open { x < self.hi } else { x <= self.hi };
        lo_ok && hi_ok
    }
}

impl fmt::Display for Interval {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.hi.is_infinite() {
            write!(f, "{} {}", if self.lo_open { ">" } else { ">=" }, self.lo)
        } else {
            let (l, r) = (if self.lo_open { '(' } else { '[' }, if self.hi_open { ')' } else { ']' });
            write!(f, "in {l}{}, {}{r}", self.lo, self.hi)
        }
    }
}

impl Source<'_> {
    /// A finite number inside `range`, as `f32`.
    pub fn number(&self, v: &Spanned<f64>, field: &str, range: Interval) -> Result<f32, SceneError> {
        self.components(v.span(), &[*v.get_ref()], field, range)?;
        Ok(*v.get_ref() as f32)
    }

    /// An optional number, `default` when absent.
    pub fn number_or(
        &self,
        v: Option<&Spanned<f64>>,
        default: f32,
        field: &str,
        range: Interval,
    ) -> Result<f32, SceneError> {
        v.map_or(Ok(default), |v| self.number(v, field, range))
    }

    /// An array of finite numbers, each inside `range`, as `f32`.
    pub fn array<const N: usize>(
        &self,
        v: &Spanned<[f64; N]>,
        field: &str,
        range: Interval,
    ) -> Result<[f32; N], SceneError> {
        self.components(v.span(), v.get_ref(), field, range)?;
        Ok(v.get_ref().map(|x| x as f32))
    }

    /// Checks every component of a value at `span` before it is converted to `f32`: NaN and
    /// infinities are [`ErrorKind::NonFinite`]; a magnitude over `f32::MAX` (which `f32`
    /// would round to infinity) and a value outside `range` are [`ErrorKind::OutOfRange`].
    /// The range is checked on the `f32` value, the one the renderer uses; messages show the
    /// value as written.
    pub fn components(
        &self,
        span: std::ops::Range<usize>,
        values: &[f64],
        field: &str,
        range: Interval,
    ) -> Result<(), SceneError> {
        let which = |i: usize| if values.len() > 1 { format!(" (component {i})") } else { String::new() };
        for (i, &x) in values.iter().enumerate() {
            if !x.is_finite() {
                let msg = format!("must be a finite number, got {x}{}", which(i));
                return Err(self.error(span, field, ErrorKind::NonFinite, msg));
            }
            if x.abs() > f64::from(f32::MAX) {
                let msg = format!("is too large for f32 (max {:.1e}), got {x:e}{}", f32::MAX, which(i));
                return Err(self.error(span, field, ErrorKind::OutOfRange, msg));
            }
            if !range.contains(x as f32) {
                let msg = format!("must be {range}, got {}{}", show(x), which(i));
                return Err(self.error(span, field, ErrorKind::OutOfRange, msg));
            }
        }
        Ok(())
    }

    /// An integer inside `lo..=hi`.
    pub fn integer(&self, v: &Spanned<u32>, field: &str, lo: u32, hi: u32) -> Result<u32, SceneError> {
        let x = *v.get_ref();
        if (lo..=hi).contains(&x) {
            Ok(x)
        } else {
            let msg = format!("must be in [{lo}, {hi}], got {x}");
            Err(self.error(v.span(), field, ErrorKind::OutOfRange, msg))
        }
    }

    /// Rejects keys that do not apply to the chosen `type` (`present` pairs a key name with its
    /// value's span, when given).
    pub fn only_keys(
        &self,
        parent: &str,
        type_name: &str,
        present: &[(&str, Option<std::ops::Range<usize>>)],
        allowed: &[&str],
    ) -> Result<(), SceneError> {
        for (key, span) in present {
            if let Some(span) = span
                && !allowed.contains(key)
            {
                let msg = format!("does not apply to type \"{type_name}\" (allowed: {})", allowed.join(", "));
                return Err(self.error(span.clone(), &format!("{parent}.{key}"), ErrorKind::Conflict, msg));
            }
        }
        Ok(())
    }
}

/// `x` as written in messages: plain for ordinary magnitudes, in scientific notation for
/// very large or very small ones (`1e300`, not 301 digits).
pub(crate) fn show(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && !(1e-6..1e16).contains(&a) { format!("{x:e}") } else { format!("{x}") }
}

/// The span of an optional spanned value.
pub(crate) fn span_of<T>(v: &Option<Spanned<T>>) -> Option<std::ops::Range<usize>> {
    v.as_ref().map(Spanned::span)
}
