//! Shared support code for the integration tests: a chi-square
//! goodness-of-fit test for direction samplers ([`chi2`]) and the adaptive
//! quadrature it uses ([`quadrature`]).
//!
//! Use it from a test file with `mod support;` and `use support::chi2::*;`.
#![allow(dead_code)]

pub mod albedo;
pub mod chi2;
pub mod dielectric_ref;
pub mod quadrature;
