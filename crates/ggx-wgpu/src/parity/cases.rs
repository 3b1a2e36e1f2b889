//! The parity input tables and ggx-core's expected outputs, one row per WGSL function; the rows
//! of energy.wgsl are in `energy_cases.rs`.

use bytemuck::{Pod, Zeroable};
use ggx_core::clearcoat::{clearcoat_fresnel, metal_rough_albedo_estimate};
use ggx_core::fresnel::{FresnelParams, fresnel_complex, fresnel_dielectric, fresnel_schlick};
use ggx_core::metal_rough::{clamp_ior, dielectric_f0};
use ggx_core::sequence::{self as seq, CounterRng, SampleStream, SequenceKind};
use ggx_core::{
    BsdfSample, Frame, Fresnel, GgxConductor, GgxDielectric, GltfClearcoat, GltfMetalRough, Sampling, TransportMode,
    TrowbridgeReitz, alpha, clamp_eta, math, mis, reflect, refract, warp,
};
use glam::{Vec2, Vec3};

use super::{Bound, Contract};

#[path = "energy_cases.rs"]
mod energy;

/// One case, `ParityIn` in parity.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Default, Pod, Zeroable)]
pub(super) struct Input {
    pub(super) a: [f32; 4],
    pub(super) b: [f32; 4],
    pub(super) c: [f32; 4],
    pub(super) n: [u32; 4],
    pub(super) m: [u32; 4],
}

impl Input {
    fn scalar(x: f32) -> Self {
        Input { a: [x, 0.0, 0.0, 0.0], ..Default::default() }
    }
    fn dir(a: Vec3) -> Self {
        Input { a: a.extend(0.0).to_array(), ..Default::default() }
    }
    fn pair(a: Vec3, b: Vec3) -> Self {
        Input { b: b.extend(0.0).to_array(), ..Input::dir(a) }
    }
    fn dir_u(a: Vec3, u: Vec2) -> Self {
        Input { c: [u.x, u.y, 0.0, 0.0], ..Input::dir(a) }
    }
    fn words(n: [u32; 4]) -> Self {
        Input { n, ..Default::default() }
    }
    fn va(&self) -> Vec3 {
        Vec3::new(self.a[0], self.a[1], self.a[2])
    }
    fn vb(&self) -> Vec3 {
        Vec3::new(self.b[0], self.b[1], self.b[2])
    }
    fn vc(&self) -> Vec3 {
        Vec3::new(self.c[0], self.c[1], self.c[2])
    }
    fn u(&self) -> Vec2 {
        Vec2::new(self.c[0], self.c[1])
    }
}

/// One expected output word.
#[derive(Clone, Copy)]
pub(super) enum Expect {
    /// Must match bit for bit (integers, flags, sequence floats).
    Bits(u32),
    /// Must match within its group's [`Bound`].
    Float(f32),
}

fn floats(xs: &[f32]) -> Vec<Expect> {
    xs.iter().map(|&x| Expect::Float(x)).collect()
}

fn words(xs: &[u32]) -> Vec<Expect> {
    xs.iter().map(|&x| Expect::Bits(x)).collect()
}

fn v3(v: Vec3) -> [f32; 3] {
    v.to_array()
}

/// A run of consecutive output words held to one [`Bound`] and one contract: a direction's
/// xyz, a colour's rgb, a pdf, a pair of flags.
#[derive(Clone, Copy, Debug)]
pub(super) struct Group {
    /// What the words are (`wi`, `pdf`, `valid,delta`); a group of several words names each
    /// one by its index in the log (`wi[2]`).
    pub(super) name: &'static str,
    /// How many words.
    pub(super) words: usize,
    /// The tolerance of every word of the group.
    pub(super) bound: Bound,
    /// What ggx-core promises about the words if they are floats; `None` for words compared
    /// bit for bit as integers (flags, sequences, layout).
    pub(super) contract: Option<Contract>,
    /// A separately named bound for the cases its predicate selects, instead of `bound`.
    pub(super) special: Option<Special>,
}

/// A named bound that replaces a group's own for the cases `applies` selects (given the case
/// and ggx-core's words).
#[derive(Clone, Copy, Debug)]
pub(super) struct Special {
    /// The bound's name in the log (a constant of this file).
    pub(super) name: &'static str,
    /// The tolerance in those cases.
    pub(super) bound: Bound,
    /// Which cases, in words, for the log.
    pub(super) what: &'static str,
    /// Selects the cases.
    pub(super) applies: fn(&Input, &[Expect]) -> bool,
}

impl Group {
    /// `words` floats held to `bound` and to [`Contract::Finite`].
    pub(super) const fn float(name: &'static str, words: usize, bound: Bound) -> Self {
        Group { name, words, bound, contract: Some(Contract::Finite), special: None }
    }

    /// A single float output, held to `bound` and to [`Contract::Finite`].
    pub(super) const fn value(bound: Bound) -> Self {
        Group::float("value", 1, bound)
    }

    /// `words` integer words (flags, sequence bits, layout) that must match bit for bit.
    pub(super) const fn bits(name: &'static str, words: usize) -> Self {
        Group { name, words, bound: Bound::Exact, contract: None, special: None }
    }
}

/// One function to compare: its name, the bound of each output word and cases with the CPU's
/// outputs.
pub(super) struct Spec {
    pub(super) name: &'static str,
    /// The output words, in order, in groups; they cover every expected word.
    pub(super) groups: Vec<Group>,
    pub(super) cases: Vec<Input>,
    pub(super) bsdfs: Vec<GgxConductor>,
    /// One dielectric per case (zero for the rows that do not read one).
    pub(super) dielectrics: Vec<GgxDielectric>,
    pub(super) expect: Vec<Vec<Expect>>,
    /// For outputs computed from an earlier output that the GPU may round differently: given a
    /// case, its conductor and dielectric, the GPU's words and ggx-core's, the expectation to use instead
    /// (ggx-core's values at the GPU's intermediate result), or `None` to keep ggx-core's; and
    /// the words it replaces, noted on the log lines of such cases.
    pub(super) rebase: Option<(Rebase, &'static str)>,
}

/// See [`Spec::rebase`].
pub(super) type Rebase = fn(&Input, &GgxConductor, &GgxDielectric, &[u32], &[Expect]) -> Option<Vec<Expect>>;

impl Spec {
    /// Lets the row's float words return NaN and infinities where ggx-core does
    /// ([`Contract::Ieee`]).
    fn ieee(&mut self) -> &mut Self {
        for g in self.groups.iter_mut().filter(|g| g.contract.is_some()) {
            g.contract = Some(Contract::Ieee);
        }
        self
    }

    /// Compares the row's later words with ggx-core's at the GPU's intermediate result where
    /// the two differ (see [`Spec::rebase`]).
    fn rebase(&mut self, rebase: Rebase, note: &'static str) -> &mut Self {
        self.rebase = Some((rebase, note));
        self
    }
}

#[derive(Default)]
struct Specs(Vec<Spec>);

impl Specs {
    /// Adds a row whose output words are `groups`: `cpu` gives ggx-core's outputs for each case.
    fn row<I, F>(&mut self, name: &'static str, groups: &[Group], cases: I, cpu: F) -> &mut Spec
    where
        I: IntoIterator<Item = (Input, GgxConductor)>,
        F: Fn(&Input, &GgxConductor) -> Vec<Expect>,
    {
        let (cases, bsdfs): (Vec<Input>, Vec<GgxConductor>) = cases.into_iter().unzip();
        let expect = cases.iter().zip(&bsdfs).map(|(i, k)| cpu(i, k)).collect();
        let dielectrics = vec![GgxDielectric::zeroed(); cases.len()];
        self.0.push(Spec { name, groups: groups.to_vec(), cases, bsdfs, dielectrics, expect, rebase: None });
        self.0.last_mut().expect("just pushed")
    }

    /// Adds a row whose cases carry a dielectric (and a zero conductor): `cpu` gives ggx-core's
    /// outputs for each case.
    fn dielectric_row<I, F>(&mut self, name: &'static str, groups: &[Group], cases: I, cpu: F) -> &mut Spec
    where
        I: IntoIterator<Item = (Input, GgxDielectric)>,
        F: Fn(&Input, &GgxDielectric) -> Vec<Expect>,
    {
        let (cases, dielectrics): (Vec<Input>, Vec<GgxDielectric>) = cases.into_iter().unzip();
        let expect = cases.iter().zip(&dielectrics).map(|(i, k)| cpu(i, k)).collect();
        let bsdfs = vec![GgxConductor::zeroed(); cases.len()];
        self.0.push(Spec { name, groups: groups.to_vec(), cases, bsdfs, dielectrics, expect, rebase: None });
        self.0.last_mut().expect("just pushed")
    }
}

// ---------------------------------------------------------------------------------------------
// Input tables
// ---------------------------------------------------------------------------------------------

pub(super) const NAN: f32 = f32::NAN;
pub(super) const INF: f32 = f32::INFINITY;
/// `1 - 2^-24` (0x3f7fffff), the largest u a sampler accepts.
const ONE_MINUS_ULP: f32 = math::ONE_MINUS_EPSILON;

/// Special scalars: NaN, infinities, signed zeros, subnormals, the smallest normal, tiny,
/// unit-interval edges, large.
const SPECIALS: [f32; 22] = [
    NAN,
    INF,
    -INF,
    -1.0,
    -1e-30,
    -1e-45,
    -0.0,
    0.0,
    1e-40,
    f32::MIN_POSITIVE,
    1e-30,
    1e-7,
    0.25,
    0.5,
    ONE_MINUS_ULP,
    1.0,
    1.000_000_1,
    1.5,
    3.0,
    1e30,
    f32::MAX,
    -f32::MAX,
];

fn scalars() -> Vec<f32> {
    let sweep = (-80..=80).flat_map(|e| {
        let x = 1.37 * 2f32.powf(e as f32 * 0.5);
        [x, -x]
    });
    SPECIALS.into_iter().chain(sweep).collect()
}

/// Cosines from normal incidence down to 1e-7, exactly grazing and below the horizon.
const COS: [f64; 19] = [
    1.0,
    0.999_999_94,
    0.999_995,
    0.99,
    0.9,
    0.7,
    0.5,
    0.3,
    0.1,
    1e-2,
    1e-3,
    1e-4,
    1e-5,
    1e-6,
    1e-7,
    0.0,
    -1e-7,
    -0.3,
    -1.0,
];
const COS_FEW: [f64; 9] = [1.0, 0.9, 0.5, 0.1, 1e-3, 1e-5, 1e-7, 0.0, -0.5];
const PHI: [f64; 6] = [0.0, 0.7, std::f64::consts::FRAC_PI_2, 2.3, std::f64::consts::PI, -1.2];

/// Unit vector at `cos theta`, `phi`, rounded from f64.
fn spherical(cos: f64, phi: f64) -> Vec3 {
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    Vec3::new((sin * phi.cos()) as f32, (sin * phi.sin()) as f32, cos as f32)
}

/// Zero, NaN and infinite components, non-unit vectors, vectors whose squared length
/// underflows or overflows, and vectors just inside and outside normalize_or_zero's
/// idempotence band.
fn odd_directions() -> Vec<Vec3> {
    let v = Vec3::new(0.6, 0.0, 0.8);
    vec![
        Vec3::ZERO,
        Vec3::new(NAN, 0.0, 1.0),
        Vec3::new(0.0, 0.0, NAN),
        Vec3::new(INF, 0.0, 1.0),
        Vec3::new(0.0, 0.0, INF),
        Vec3::new(0.0, -INF, 1.0),
        Vec3::new(0.3, -0.4, 1.2),
        Vec3::new(-2.0, 1.0, 0.5),
        Vec3::new(1e-20, 0.0, 1e-20),
        Vec3::new(1e20, 0.0, 1e20),
        v * (1.0 + 0.9e-6),
        v * (1.0 + 1.5e-6),
        v * (1.0 + 3e-6),
    ]
}

fn directions() -> Vec<Vec3> {
    let grid = COS.iter().flat_map(|&c| PHI.iter().map(move |&p| spherical(c, p)));
    grid.chain(odd_directions()).collect()
}

fn few_directions() -> Vec<Vec3> {
    let grid = COS_FEW.iter().flat_map(|&c| [0.0, 2.3, -1.2].map(|p| spherical(c, p)));
    grid.chain(odd_directions().into_iter().take(8).skip(1).step_by(2)).chain([Vec3::ZERO]).collect()
}

/// Outgoing directions for the samplers.
fn wo_directions() -> Vec<Vec3> {
    let cos = [1.0, 0.999_999_94, 0.999_995, 0.9, 0.5, 0.1, 1e-3, 1e-5, 1e-7, 0.0, -0.5];
    let grid = cos.into_iter().flat_map(|c| [0.0, 2.3].map(|p| spherical(c, p)));
    grid.chain([
        Vec3::new(NAN, 0.0, 1.0),
        Vec3::new(0.0, 0.0, INF),
        Vec3::new(0.3, -0.4, 1.2),
        Vec3::new(1e-20, 0.0, 1e-20),
    ])
    .collect()
}

const U: [f32; 8] = [0.0, 1e-7, 0.13, 0.25, 0.5, 0.77, 0.999, ONE_MINUS_ULP];
const U_ODD: [(f32, f32); 10] = [
    (NAN, 0.3),
    (0.3, NAN),
    (INF, 0.3),
    (0.3, -INF),
    (-0.5, 0.3),
    (0.3, 1.0),
    (1.0, 1.0),
    (2.0, 0.6),
    (0.6, 2.0),
    (NAN, NAN),
];

/// Random numbers for the samplers: a grid including 0 and 1 - ulp, plus NaN, infinities,
/// negative values, 1 and above.
fn us(grid: &[f32]) -> Vec<Vec2> {
    let grid = grid.iter().flat_map(|&x| grid.iter().map(move |&y| Vec2::new(x, y)));
    grid.chain(U_ODD.map(|(x, y)| Vec2::new(x, y))).collect()
}

/// Raw alpha pairs (the constructor clamps them): zero and NaN (-> ALPHA_MIN), 1e-4 .. 1e-3 and
/// both sides of DELTA_ALPHA, rough, above one, anisotropic up to 1:100.
const ALPHAS: [(f32, f32); 18] = [
    (0.0, 0.0),
    (1e-4, 1e-4),
    (3e-4, 3e-4),
    (9.99e-4, 9.99e-4),
    (1e-3, 1e-3),
    (0.01, 0.01),
    (0.1, 0.1),
    (0.3, 0.3),
    (0.7, 0.7),
    (1.0, 1.0),
    (1.5, 1.5),
    (NAN, NAN),
    (0.01, 1.0),
    (1.0, 0.01),
    (1e-4, 1e-2),
    (3e-3, 0.3),
    (0.5, 0.005),
    (0.05, 0.2),
];

/// Field values that bypass the constructor (`Pod` bytes): ggx-core and the WGSL read them
/// through `alphas()`, the constructor's clamp.
const RAW_ALPHAS: [(f32, f32); 8] =
    [(NAN, 0.3), (-0.5, 0.2), (0.0, 0.5), (2.0, 3.0), (INF, -INF), (1e-40, 0.3), (0.3, f32::MAX), (-0.3, -0.3)];

/// Raw alpha fields for the conductor rows: [`RAW_ALPHAS`] without `(inf, -inf)`, which reads
/// as `(1, 1e-4)`: a 1:10^4 anisotropy (beyond the 1:100 the rows are sized for) where one
/// `sample` pdf of 127 is 19 ulp from ggx-core, exactly as for `TrowbridgeReitz::new(1.0, 1e-4)`.
const RAW_CONDUCTOR_ALPHAS: [(f32, f32); 7] =
    [(NAN, 0.3), (-0.5, 0.2), (0.0, 0.5), (2.0, 3.0), (1e-40, 0.3), (0.3, f32::MAX), (-0.3, -0.3)];

fn raw_dists() -> impl Iterator<Item = TrowbridgeReitz> {
    RAW_ALPHAS.into_iter().map(|(alpha_x, alpha_y)| TrowbridgeReitz { alpha_x, alpha_y })
}

fn dists() -> Vec<TrowbridgeReitz> {
    ALPHAS.iter().map(|&(x, y)| TrowbridgeReitz::new(x, y)).chain(raw_dists()).collect()
}

fn with_dist(distribution: TrowbridgeReitz) -> GgxConductor {
    GgxConductor { distribution, ..GgxConductor::zeroed() }
}

/// Every Fresnel kind, physical and degenerate parameters, and an unknown kind.
fn fresnels() -> Vec<FresnelParams> {
    let gold = Fresnel::Conductor { eta: Vec3::new(0.143, 0.374, 1.442), k: Vec3::new(3.983, 2.385, 1.603) };
    let odd_conductor = Fresnel::Conductor { eta: Vec3::new(0.0, 1.0, NAN), k: Vec3::new(0.0, 0.0, 1.0) };
    let unknown = FresnelParams { kind: 7, ..Fresnel::Schlick { f0: Vec3::splat(0.5) }.into() };
    [
        Fresnel::One,
        Fresnel::Schlick { f0: Vec3::splat(0.04) },
        Fresnel::SchlickF90 { f0: Vec3::new(1.0, 0.78, 0.34), f90: Vec3::new(1.0, 0.95, 0.9) },
        gold,
        odd_conductor,
        Fresnel::Dielectric { eta: 1.5 },
        Fresnel::Dielectric { eta: 1.0 / 1.5 },
        Fresnel::Dielectric { eta: NAN },
    ]
    .into_iter()
    .map(FresnelParams::from)
    .chain([unknown])
    .collect()
}

/// BRDFs for the conductor rows: the alpha edge cases with Fresnel models in turn, and every
/// Fresnel model at alpha 0.3.
fn bsdfs() -> Vec<GgxConductor> {
    let alphas = [
        (0.0, 0.0),
        (5e-4, 5e-4),
        (1e-3, 1e-3),
        (0.01, 0.01),
        (0.3, 0.3),
        (1.0, 1.0),
        (0.01, 1.0),
        (0.5, 0.005),
        (1e-4, 1e-2),
    ];
    let fresnel = fresnels();
    let edge = alphas.iter().enumerate().map(|(i, &(x, y))| (x, y, fresnel[i % fresnel.len()]));
    let models = fresnel.iter().map(|&f| (0.3, 0.3, f));
    edge.chain(models)
        .map(|(x, y, fresnel)| GgxConductor { distribution: TrowbridgeReitz::new(x, y), pad: [0; 2], fresnel })
        .collect()
}

/// [`bsdfs`] plus conductors whose alpha fields bypass the constructor.
fn bsdfs_raw() -> Vec<GgxConductor> {
    let fresnel = fresnels();
    let raw = RAW_CONDUCTOR_ALPHAS.into_iter().enumerate().map(|(i, (alpha_x, alpha_y))| GgxConductor {
        distribution: TrowbridgeReitz { alpha_x, alpha_y },
        pad: [0; 2],
        fresnel: fresnel[(i + 3) % fresnel.len()],
    });
    bsdfs().into_iter().chain(raw).collect()
}

/// Cosines for the Fresnel formulas: both sides of zero, grazing, one and beyond, NaN, infinities.
const FRESNEL_COS: [f32; 21] = [
    -1.0,
    -0.7,
    -0.2,
    -1e-7,
    -0.0,
    0.0,
    1e-7,
    1e-3,
    0.1,
    0.3,
    0.5,
    0.7,
    0.9,
    0.999,
    ONE_MINUS_ULP,
    1.0,
    1.0001,
    2.0,
    NAN,
    INF,
    -INF,
];

/// Sampling techniques: every discriminant and an unknown one (read as VNDF).
const SAMPLINGS: [u32; 7] = [0, 1, 2, 3, 4, 5, 9];

/// Edge words and pseudo-random words (SplitMix32-style, independent of the hashes under test).
fn u32s(count: u32) -> Vec<u32> {
    let edges = [0, 1, 2, 3, 255, 256, 0x7fff_ffff, 0x8000_0000, 0xdead_beef, u32::MAX - 1, u32::MAX];
    let random = (0..count).map(|i| {
        let mut z = i.wrapping_mul(0x9e37_79b9).wrapping_add(0x6a09_e667);
        z = (z ^ (z >> 16)).wrapping_mul(0x85eb_ca6b);
        z = (z ^ (z >> 13)).wrapping_mul(0xc2b2_ae35);
        z ^ (z >> 16)
    });
    edges.into_iter().chain(random).collect()
}

fn none() -> GgxConductor {
    GgxConductor::zeroed()
}

/// Relative IORs of the dielectric rows: glass seen from both sides, water, diamond and an
/// index-matched interface.
const ETAS: [f32; 5] = [1.5, 1.0 / 1.5, 1.33, 2.4, 1.0];

/// Raw `eta` fields (ggx-core and the WGSL read them through `clamp_eta`): zero, negative,
/// NaN, infinities, subnormal, both clamp edges and beyond them, huge.
const ODD_ETAS: [f32; 13] = [0.0, -0.0, -1.0, NAN, INF, -INF, 1e-40, 1e-3, 1e-2, 100.0, 1e3, 1e30, f32::MAX];

/// Dielectrics: every [`ETAS`] value at the delta alpha 1e-4, at `DELTA_ALPHA`, rough,
/// fully rough and anisotropic; every [`ODD_ETAS`] field at alpha 0.3 and four at 1e-4 (the
/// smooth interface); alpha edges with the etas in turn; raw alpha fields
/// ([`RAW_CONDUCTOR_ALPHAS`]) with the etas in turn.
fn dielectrics() -> Vec<GgxDielectric> {
    let main = [(1e-4, 1e-4), (1e-3, 1e-3), (0.01, 0.01), (0.3, 0.3), (1.0, 1.0), (0.05, 0.5)]
        .into_iter()
        .flat_map(|(x, y)| ETAS.map(|eta| GgxDielectric::new(x, y, eta)));
    let odd = ODD_ETAS.into_iter().map(|eta| GgxDielectric { eta, ..GgxDielectric::isotropic(0.3, 1.5) });
    let odd_smooth =
        [NAN, 0.0, -1.0, 1e30].into_iter().map(|eta| GgxDielectric { eta, ..GgxDielectric::isotropic(1e-4, 1.5) });
    let edges = [(0.0, 0.0), (9.99e-4, 9.99e-4), (0.01, 1.0), (0.5, 0.005), (1e-4, 1e-2)]
        .into_iter()
        .enumerate()
        .map(|(i, (x, y))| GgxDielectric::new(x, y, ETAS[i % ETAS.len()]));
    let raw = RAW_CONDUCTOR_ALPHAS.into_iter().enumerate().map(|(i, (alpha_x, alpha_y))| GgxDielectric {
        distribution: TrowbridgeReitz { alpha_x, alpha_y },
        eta: ETAS[(i + 2) % ETAS.len()],
        pad: 0,
    });
    main.chain(odd).chain(odd_smooth).chain(edges).chain(raw).collect()
}

/// Cosine of the critical angle on the denser side of an interface with relative IOR `e`.
fn critical_cos(e: f64) -> f64 {
    let e = e.max(1.0 / e);
    (1.0 - 1.0 / (e * e)).sqrt()
}

/// Cosines of the dielectric directions: both sides down to grazing, 0, and both sides of the
/// critical angles of eta 1.5 and 2.4 (on both sides of the interface).
fn dielectric_cos() -> Vec<f64> {
    let mut cos = vec![1.0, 0.9, 0.5, 0.1, 1e-3, 1e-7, 0.0, -1e-7, -1e-3, -0.3, -0.7, -1.0];
    for e in [1.5, 2.4] {
        let c = critical_cos(e);
        cos.extend([c - 1e-4, c + 1e-4, -(c - 1e-4), -(c + 1e-4)]);
    }
    cos
}

/// Directions of the dielectric pairs: [`dielectric_cos`] at azimuths 0 and pi (so that pairs
/// include mirror pairs, whose half vector is the normal), plus zero, NaN and non-unit vectors.
fn dielectric_directions() -> Vec<Vec3> {
    let grid = dielectric_cos().into_iter().flat_map(|c| [0.0, std::f64::consts::PI].map(|p| spherical(c, p)));
    grid.chain([Vec3::ZERO, Vec3::new(NAN, 0.0, 1.0), Vec3::new(0.3, -0.4, -1.2)]).collect()
}

/// Pairs around the critical angle of each IOR `e` (1.5, 1.33, 2.4, from the denser side,
/// which is `-z` for `e > 1` and `+z` for `1 / e`): `wo` at cosines `c + delta`, and `wi` its
/// mirror image (half vector = the normal: `F(wo.z)`, total internal reflection beyond `c`) and
/// its refraction (computed in f64, grazing near `c`); each with the dielectrics of that IOR.
fn critical_pairs() -> Vec<(Vec3, Vec3, GgxDielectric)> {
    let mut out = Vec::new();
    for e in [1.5f64, 1.33, 2.4] {
        let c = critical_cos(e);
        for (eta, side) in [(e as f32, -1.0), ((1.0 / e) as f32, 1.0)] {
            for delta in [-1e-3, -1e-5, -1e-6, 0.0, 1e-6, 1e-5, 1e-3] {
                let cos_i = c + delta;
                let wo = spherical(side * cos_i, 0.7);
                let mirror = spherical(side * cos_i, 0.7 + std::f64::consts::PI);
                let sin_t = e * (1.0 - cos_i * cos_i).max(0.0).sqrt();
                let mut wis = vec![mirror];
                if sin_t < 1.0 {
                    wis.push(spherical(-side * (1.0 - sin_t * sin_t).sqrt(), 0.7 + std::f64::consts::PI));
                }
                for wi in wis {
                    for alpha in [0.01, 0.3, 1.0] {
                        out.push((wo, wi, GgxDielectric::isotropic(alpha, eta)));
                    }
                }
            }
        }
    }
    out
}

/// Sampling techniques of a dielectric pair case: NDF, one visible-normal technique (VNDF,
/// spherical caps, bounded, unknown in turn) and one refused one (cosine, uniform in turn).
fn dielectric_samplings(j: usize) -> [u32; 3] {
    [0, [1, 2, 3, 9][j % 4], [4, 5][j % 2]]
}

/// `u_lobe` values of the dielectric sample row, used in turn (11 values, so that with the
/// two transport modes in turn every combination occurs every 22 cases): 0, small, middle,
/// `1 - ulp`, 1 and beyond, negative, NaN and infinity.
const U_LOBES: [f32; 11] = [0.0, 0.02, 0.1, 0.5, 0.9, ONE_MINUS_ULP, 1.0, 2.0, -0.5, NAN, INF];

fn mode(m: u32) -> TransportMode {
    TransportMode::from_u32(m)
}

/// A glTF material in the conductor slot of a case (parity.wgsl `metal_rough` unpacks it):
/// the distribution as is, `base_color` and `metallic` in `fresnel.a`, `f0` and
/// `specular_weight` in `fresnel.b`, `p_specular` in `fresnel.eta`, `pad` in `fresnel.kind`.
pub(super) fn pack_metal_rough(m: &GltfMetalRough) -> GgxConductor {
    let ([r, g, b], [x, y, z]) = (m.base_color, m.f0);
    let fresnel = FresnelParams {
        kind: m.pad,
        eta: m.p_specular,
        pad: [0; 2],
        a: [r, g, b, m.metallic],
        b: [x, y, z, m.specular_weight],
    };
    GgxConductor { distribution: m.distribution, pad: [0; 2], fresnel }
}

/// The inverse of [`pack_metal_rough`].
pub(super) fn unpack_metal_rough(k: &GgxConductor) -> GltfMetalRough {
    let (a, b) = (k.fresnel.a, k.fresnel.b);
    GltfMetalRough {
        base_color: [a[0], a[1], a[2]],
        metallic: a[3],
        f0: [b[0], b[1], b[2]],
        specular_weight: b[3],
        distribution: k.distribution,
        p_specular: k.fresnel.eta,
        pad: k.fresnel.kind,
    }
}

/// `(ior, specular_color, specular_weight)` of the glTF rows: the defaults, `KHR_materials_ior`'s
/// 0 (f0 = 1 times the colour), an index-matched 1, diamond with a colour above one, no
/// specular lobe, and a colour that saturates `f0` at 1.
fn gltf_extensions() -> [(f32, Vec3, f32); 6] {
    [
        (1.5, Vec3::ONE, 1.0),
        (0.0, Vec3::new(1.0, 0.8, 0.6), 0.5),
        (2.4, Vec3::new(1.0, 0.5, 2.0), 0.7),
        (1.0, Vec3::ONE, 1.0),
        (1.5, Vec3::ONE, 0.0),
        (1.33, Vec3::new(30.0, 1.0, 0.2), 1.0),
    ]
}

/// glTF materials: every alpha edge of the conductor rows (mirrors, `DELTA_ALPHA`, rough,
/// anisotropic) three times, with base colours, metallic values and [`gltf_extensions`] in turn;
/// a lone diffuse lobe (`p_s = 0`), lone specular lobes (`p_s = 1`, rough and mirror); and
/// fields that bypass the constructor: NaN, infinite, negative and above-one values, a
/// `p_specular` outside `[0, 1]` and a subnormal one over a mirror, raw alphas, a non-zero pad.
pub(super) fn metal_roughs() -> Vec<GltfMetalRough> {
    let alphas = [
        (0.0, 0.0),
        (5e-4, 5e-4),
        (1e-3, 1e-3),
        (0.01, 0.01),
        (0.09, 0.09),
        (0.3, 0.3),
        (1.0, 1.0),
        (0.01, 1.0),
        (0.5, 0.005),
        (1e-4, 1e-2),
    ];
    let bases = [Vec3::new(0.8, 0.5, 0.2), Vec3::ONE, Vec3::ZERO, Vec3::new(0.02, 0.9, 0.4)];
    let metallics = [0.0, 0.5, 1.0, 0.2];
    let ext = gltf_extensions();
    let constructed = alphas.iter().enumerate().flat_map(|(i, &(ax, ay))| {
        (0..3).map(move |j| {
            let (ior, color, weight) = ext[(i + 2 * j) % ext.len()];
            GltfMetalRough::new(bases[(i + j) % 4], metallics[(i + 3 * j) % 4], ax, ay, ior, color, weight)
        })
    });
    let lone = [
        GltfMetalRough::new(Vec3::ONE, 0.0, 0.3, 0.3, 1.5, Vec3::ONE, 0.0),
        GltfMetalRough::core(Vec3::new(0.9, 0.6, 0.3), 1.0, 0.3),
        GltfMetalRough::core(Vec3::new(0.9, 0.6, 0.3), 1.0, 0.0),
    ];
    let raw = |base: [f32; 3], metallic, f0: [f32; 3], specular_weight, (alpha_x, alpha_y), p_specular, pad| {
        let distribution = TrowbridgeReitz { alpha_x, alpha_y };
        GltfMetalRough { base_color: base, metallic, f0, specular_weight, distribution, p_specular, pad }
    };
    let raw = [
        raw([NAN, -1.0, 2.0], NAN, [INF, -1.0, 0.5], 2.0, (0.3, 0.3), NAN, 0),
        raw([0.5, 0.5, 0.5], -1.0, [NAN, 0.04, 0.04], 0.5, (NAN, 0.3), -0.5, 0),
        raw([INF, 0.2, -INF], 0.5, [0.04; 3], NAN, (2.0, 3.0), 2.0, 0xdead_beef),
        raw([0.8, 0.5, 0.2], 0.3, [0.04; 3], 1.0, (0.0, 0.0), 1e-45, 0),
        raw([0.8, 0.5, 0.2], 0.3, [0.04; 3], 1.0, (-0.3, -0.3), 0.5, 0),
        raw([1e-40, 0.5, 1.0], f32::MAX, [1.0; 3], -0.0, (1e-40, 0.3), ONE_MINUS_ULP, 0),
    ];
    constructed.chain(lone).chain(raw).collect()
}

/// [`sample_at_gpu_wi`] for `gltf_metal_rough_sample` (the material unpacked from the case's
/// conductor): ggx-core's `pdf` and `eval / pdf` at the GPU's `wi`.
fn metal_rough_sample_at_gpu_wi(
    i: &Input,
    k: &GgxConductor,
    _: &GgxDielectric,
    got: &[u32],
    cpu: &[Expect],
) -> Option<Vec<Expect>> {
    let wi = differing_gpu_wi(got, cpu)?;
    let (wo, m) = (i.va(), unpack_metal_rough(k));
    let pdf = m.pdf(wo, wi, Sampling::from_u32(i.n[0]));
    Some(rebased(cpu, m.eval(wo, wi) / pdf, pdf))
}

/// A `GltfMetalRough`'s output words (`put_metal_rough` in parity.wgsl): the copied and clamped
/// fields exactly, `f0` (a division and three products) to [`FORMULA`], `p_specular` (a ratio
/// of sums whose diffuse term cancels where `specular_weight f_avg(max(f0))` nears one; in
/// `[0, 1]`) to [`UNIT`].
const METAL_ROUGH_GROUPS: [Group; 7] = [
    Group::float("base_color", 3, Bound::Exact),
    Group::float("metallic", 1, Bound::Exact),
    Group::float("f0", 3, FORMULA),
    Group::float("specular_weight", 1, Bound::Exact),
    Group::float("alpha", 2, Bound::Exact),
    Group::float("p_specular", 1, UNIT),
    Group::bits("pad", 1),
];

/// The words of a `GltfMetalRough` for [`METAL_ROUGH_GROUPS`].
fn metal_rough_words(m: &GltfMetalRough) -> Vec<Expect> {
    let d = m.distribution;
    let mut e = floats(
        &[m.base_color.as_slice(), &[m.metallic], &m.f0, &[m.specular_weight, d.alpha_x, d.alpha_y, m.p_specular]]
            .concat(),
    );
    e.extend(words(&[m.pad]));
    e
}

/// A clearcoat in the conductor slot of a case (parity.wgsl `clearcoat` unpacks it): the base as
/// [`pack_metal_rough`] packs it, the coat's alphas (bits) in `pad`, `weight` and `base_albedo`
/// (bits) in `fresnel.pad`, the four words the base leaves free.
pub(super) fn pack_clearcoat(c: &GltfClearcoat) -> GgxConductor {
    let mut k = pack_metal_rough(&c.base);
    k.pad = [c.coat.alpha_x.to_bits(), c.coat.alpha_y.to_bits()];
    k.fresnel.pad = [c.weight.to_bits(), c.base_albedo.to_bits()];
    k
}

/// The inverse of [`pack_clearcoat`].
pub(super) fn unpack_clearcoat(k: &GgxConductor) -> GltfClearcoat {
    GltfClearcoat {
        base: unpack_metal_rough(k),
        coat: TrowbridgeReitz { alpha_x: f32::from_bits(k.pad[0]), alpha_y: f32::from_bits(k.pad[1]) },
        weight: f32::from_bits(k.fresnel.pad[0]),
        base_albedo: f32::from_bits(k.fresnel.pad[1]),
    }
}

/// Clearcoats: every base of [`metal_roughs`] (every alpha edge, lone lobes, raw fields) under a
/// coat weight (none, thin, half, full) and a coat alpha (mirrors, both sides of `DELTA_ALPHA`,
/// rough) in turn; and fields that bypass the constructor: NaN, infinite, negative, signed-zero
/// and above-one weights and base albedos, raw coat alphas, a coat over a black base (`p_c` at
/// its maximum). No subnormal weight: an adapter may flush it to 0, which takes the other branch.
pub(super) fn clearcoats() -> Vec<GltfClearcoat> {
    let weights = [1.0, 0.5, 0.0, 0.25, 1e-3];
    let coat_alphas = [0.01, 0.0, 0.3, 1e-3, 1.0, 5e-4, 0.09];
    let constructed = metal_roughs()
        .into_iter()
        .enumerate()
        .map(move |(i, m)| GltfClearcoat::new(m, weights[i % weights.len()], coat_alphas[i % coat_alphas.len()]));
    let base = GltfMetalRough::core(Vec3::new(0.8, 0.5, 0.2), 0.3, 0.2);
    let black = GltfMetalRough::new(Vec3::ZERO, 0.0, 0.3, 0.3, 1.5, Vec3::ONE, 0.0);
    let mirror = GltfMetalRough::core(Vec3::new(0.9, 0.6, 0.3), 0.5, 0.0);
    let raw = |base, weight, (alpha_x, alpha_y), base_albedo| GltfClearcoat {
        base,
        coat: TrowbridgeReitz { alpha_x, alpha_y },
        weight,
        base_albedo,
    };
    let raw = [
        raw(base, NAN, (0.1, 0.1), 0.5),
        raw(base, INF, (0.1, 0.1), 0.5),
        raw(base, -1.0, (0.1, 0.1), 0.5),
        raw(base, -0.0, (0.3, 0.3), 0.5),
        raw(base, 2.0, (0.1, 0.1), NAN),
        raw(base, 0.7, (NAN, 0.3), -1.0),
        raw(base, 0.7, (-0.3, -0.3), 2.0),
        raw(base, ONE_MINUS_ULP, (2.0, 1e-40), 1e-45),
        raw(black, 1.0, (0.2, 0.2), 0.0),
        raw(black, 1e-30, (0.2, 0.2), 0.0),
        raw(black, 0.5, (0.0, 0.0), INF),
        raw(mirror, 0.8, (0.0, 0.0), 0.6),
        raw(mirror, 0.8, (0.2, 0.2), -INF),
    ];
    constructed.chain(raw).collect()
}

/// [`sample_at_gpu_wi`] for `gltf_clearcoat_sample` (the clearcoat unpacked from the case's
/// conductor): ggx-core's `pdf` and `eval / pdf` at the GPU's `wi`.
fn clearcoat_sample_at_gpu_wi(
    i: &Input,
    k: &GgxConductor,
    _: &GgxDielectric,
    got: &[u32],
    cpu: &[Expect],
) -> Option<Vec<Expect>> {
    let wi = differing_gpu_wi(got, cpu)?;
    let (wo, c) = (i.va(), unpack_clearcoat(k));
    let pdf = c.pdf(wo, wi, Sampling::from_u32(i.n[0]));
    Some(rebased(cpu, c.eval(wo, wi) / pdf, pdf))
}

/// A `GltfClearcoat`'s 16 output words (`put_clearcoat` in parity.wgsl): the base, the coat's
/// alphas and the weight copied or clamped (exactly), `base_albedo` (sums of products whose
/// `1 - sw F_avg` may cancel; in `[0, 1]`) to [`UNIT`].
const CLEARCOAT_GROUPS: [Group; 5] = [
    Group::float("base", 11, Bound::Exact),
    Group::bits("base.pad", 1),
    Group::float("coat", 2, Bound::Exact),
    Group::float("weight", 1, Bound::Exact),
    Group::float("base_albedo", 1, UNIT),
];

/// The words of a `GltfClearcoat` for [`CLEARCOAT_GROUPS`].
fn clearcoat_words(c: &GltfClearcoat) -> Vec<Expect> {
    let mut e = metal_rough_words(&c.base);
    e.extend(floats(&[c.coat.alpha_x, c.coat.alpha_y, c.weight, c.base_albedo]));
    e
}

// ---------------------------------------------------------------------------------------------
// The rows
// ---------------------------------------------------------------------------------------------

/// The words of `ggx_conductor_sample`'s output for ggx-core's `sample`.
fn sample_words(sample: Option<ggx_core::BsdfSample>) -> Vec<Expect> {
    let b = sample.unwrap_or(ggx_core::BsdfSample { wi: Vec3::ZERO, weight: Vec3::ZERO, pdf: 0.0, is_delta: false });
    let mut e = words(&[sample.is_some() as u32, b.is_delta as u32]);
    e.extend(floats(&[b.wi.x, b.wi.y, b.wi.z, b.weight.x, b.weight.y, b.weight.z, b.pdf]));
    e
}

/// ggx-core's weight and pdf at the direction the GPU returned, where it differs from
/// ggx-core's own sample: `pdf(wo, wi, sampling)` and `eval(wo, wi) / pdf`, the same formulas
/// up to a few roundings. The GPU's `wi` comes out of reflect and normalize at grazing angles
/// and may be a few ulp (up to 128 ulp in a small component, within `UNIT`) from ggx-core's;
/// the weight and pdf of that direction legitimately differ from those of ggx-core's
/// direction, by far more than their own rounding where the Fresnel term cancels (a conductor
/// channel with `eta = 1, k = 0`: 0 against 1e-11). The direction words keep ggx-core's own
/// `wi` as reference; a GPU `wi` outside `UNIT` fails the `wi` group.
fn sample_at_gpu_wi(
    i: &Input,
    k: &GgxConductor,
    _: &GgxDielectric,
    got: &[u32],
    cpu: &[Expect],
) -> Option<Vec<Expect>> {
    let wi = differing_gpu_wi(got, cpu)?;
    let wo = i.va();
    let pdf = k.pdf(wo, wi, Sampling::from_u32(i.n[0]));
    Some(rebased(cpu, k.eval(wo, wi) / pdf, pdf))
}

/// The GPU's `wi` of a sample row (words: valid, delta, wi, weight, pdf) where it differs from
/// ggx-core's in a sample both call valid and non-delta; `None` where nothing is rebased.
fn differing_gpu_wi(got: &[u32], cpu: &[Expect]) -> Option<Vec3> {
    let same_wi = (2..5).all(|w| matches!(cpu[w], Expect::Float(c) if c.to_bits() == got[w]));
    if same_wi || !matches!((cpu[0], cpu[1]), (Expect::Bits(1), Expect::Bits(0))) || got[..2] != [1, 0] {
        return None;
    }
    Some(Vec3::new(f32::from_bits(got[2]), f32::from_bits(got[3]), f32::from_bits(got[4])))
}

/// ggx-core's expected words with the weight and pdf replaced by those at the GPU's `wi`.
fn rebased(cpu: &[Expect], weight: Vec3, pdf: f32) -> Vec<Expect> {
    let mut e = cpu[..5].to_vec();
    e.extend(floats(&[weight.x, weight.y, weight.z, pdf]));
    e
}

/// [`sample_at_gpu_wi`] for `ggx_dielectric_sample`: where the GPU's `wi` differs from
/// ggx-core's in a valid, non-delta sample of both, ggx-core's `pdf(wo, wi, sampling, mode)`
/// and `eval(wo, wi, mode) / pdf` at the GPU's `wi` (the sample's weight `G2 / G1` or
/// `G2 |wo.wm| / (|wo.z| wm.z)`, times `1 / eta'^2`, equals `eval / pdf` to a few roundings).
/// A delta sample's weight and pdf do not depend on `wi` and are never rebased.
fn dielectric_sample_at_gpu_wi(
    i: &Input,
    _: &GgxConductor,
    k: &GgxDielectric,
    got: &[u32],
    cpu: &[Expect],
) -> Option<Vec<Expect>> {
    let wi = differing_gpu_wi(got, cpu)?;
    let (wo, m) = (i.va(), mode(i.n[1]));
    let pdf = k.pdf(wo, wi, Sampling::from_u32(i.n[0]), m);
    Some(rebased(cpu, k.eval(wo, wi, m) / pdf, pdf))
}

/// Bound for outputs that are a few correctly rounded operations on the CPU and may be a few
/// operations of Vulkan precision (division and sqrt within 2.5-3 ulp) with FMA contraction on
/// the GPU.
const FEW_OPS: Bound = Bound::Ulps(4);
/// Bound for longer formulas (ratios of sums of products).
const FORMULA: Bound = Bound::Ulps(16);
/// Bound for unit vectors and values in [-1, 1] whose components cancel (cross products,
/// `1 - p1^2 - p2^2`, half vectors at grazing angles): 16 ulp, or 2^-20 (8 ulp of one).
const UNIT: Bound = Bound::UlpsOrAbs(16, 1.0 / 1_048_576.0);
/// Bound for `ggx_conductor_sample`'s weight: relative, with no absolute escape (a weight of
/// 1e-14 is held to as many digits as a weight of 1): [`FORMULA`]'s 16 ulp, like `eval`, so
/// that adapters with FMA contraction or 2.5-ulp division pass too. Measured on llvmpipe over
/// the 159 250 cases: at most 6 ulp (`eval / pdf` for cosine and uniform sampling, `F * scale`
/// for the microfacet techniques, against ggx-core at the GPU's `wi` where the two directions
/// differ, see [`sample_at_gpu_wi`]); the old unit-vector bound let any weight below 1e-6
/// through (max rel 0.437).
const SAMPLE_WEIGHT: Bound = FORMULA;
/// Bound for `ggx_conductor_sample`'s pdf: 16 ulp like the `ggx_conductor_pdf` row, with no
/// absolute escape; bit-identical to ggx-core on llvmpipe in every case (at the GPU's `wi`
/// where it differs).
const SAMPLE_PDF: Bound = FORMULA;

/// Bound for the refracted directions of `ggx_dielectric_sample` (valid, non-delta samples whose
/// `wi` crossed the surface): four times [`UNIT`] (64 ulp or 2^-18). The microfacet samplers'
/// `wm` may be a couple of ulp from ggx-core's (`sample_wm_ndf` measures 2 on llvmpipe, within
/// `UNIT`), and `refract` amplifies an error in the normal by `~ cos_i / (eta'^2 cos_t)`, which grows
/// without bound towards grazing transmission: from inside eta 2.4 at `sin_t = 0.91` one ulp of
/// `wm.z` moves `wi.z` by 12 ulp (GPU 0.72910917 = ggx-core's `refract` of its `wm` two ulps off in
/// x and z, exactly). The same operations in the same order on both sides (the rows `refract`,
/// `ggx_dielectric_eval` and `ggx_dielectric_pdf` are bit-identical); reflected and delta samples
/// keep [`UNIT`].
const REFRACTED_UNIT: Bound = Bound::UlpsOrAbs(64, 4.0 / 1_048_576.0);

/// True for a valid, non-delta `ggx_dielectric_sample` output of ggx-core whose `wi` lies on the
/// other side of `wo` (transmission).
fn is_refracted_sample(i: &Input, cpu: &[Expect]) -> bool {
    let z = |e: Expect| if let Expect::Float(x) = e { x } else { 0.0 };
    matches!((cpu[0], cpu[1]), (Expect::Bits(1), Expect::Bits(0))) && i.a[2] * z(cpu[4]) < 0.0
}

/// `ggx_dielectric_sample`'s output words: [`SAMPLE_GROUPS`], the direction under
/// [`REFRACTED_UNIT`] where the sample was refracted.
pub(super) const DIELECTRIC_SAMPLE_GROUPS: [Group; 4] = [
    SAMPLE_GROUPS[0],
    Group {
        special: Some(Special {
            name: "REFRACTED_UNIT",
            bound: REFRACTED_UNIT,
            what: "refracted microfacet samples",
            applies: is_refracted_sample,
        }),
        ..SAMPLE_GROUPS[1]
    },
    SAMPLE_GROUPS[2],
    SAMPLE_GROUPS[3],
];

/// `ggx_conductor_sample`'s output words (`put_*` in parity.wgsl): flags, the direction, the
/// weight and the pdf, each with its own bound.
pub(super) const SAMPLE_GROUPS: [Group; 4] = [
    Group::bits("valid,delta", 2),
    Group::float("wi", 3, UNIT),
    Group::float("weight", 3, SAMPLE_WEIGHT),
    Group::float("pdf", 1, SAMPLE_PDF),
];

pub(super) fn specs() -> Vec<Spec> {
    let mut s = Specs::default();
    let scalar_cases = || scalars().into_iter().map(|x| (Input::scalar(x), none()));

    // math.rs
    // Every row is held to Contract::Finite (ggx-core documents finite outputs and its
    // tests/contract.rs checks them) except the three marked `ieee()`: safe_sqrt(+inf) and
    // pdf_cosine_hemisphere at w.z = +inf are +inf, and lambda is +inf at grazing.
    s.row("safe_sqrt", &[Group::value(FEW_OPS)], scalar_cases(), |i, _| floats(&[math::safe_sqrt(i.a[0])])).ieee();
    s.row("finite_or_zero", &[Group::value(Bound::Exact)], scalar_cases(), |i, _| {
        floats(&[math::finite_or_zero(i.a[0])])
    });
    s.row("sanitize_u", &[Group::value(Bound::Exact)], scalar_cases(), |i, _| floats(&[math::sanitize_u(i.a[0])]));
    let pairs = || {
        let xs = SPECIALS;
        xs.into_iter().flat_map(move |x| {
            xs.into_iter().map(move |y| (Input { a: [x, y, 0.0, 0.0], ..Default::default() }, none()))
        })
    };
    s.row("sanitize_u2", &[Group::float("u", 2, Bound::Exact)], pairs(), |i, _| {
        let u = math::sanitize_u2(Vec2::new(i.a[0], i.a[1]));
        floats(&[u.x, u.y])
    });
    s.row(
        "normalize_or_zero",
        &[Group::float("xyz", 3, UNIT)],
        directions()
            .into_iter()
            .map(|d| (Input::dir(d * 1.7), none()))
            .chain(directions().into_iter().map(|d| (Input::dir(d), none()))),
        |i, _| floats(&v3(math::normalize_or_zero(i.va()))),
    );
    // [0, 1] (what the samplers pass), then negative u, large u up to and past 2^23 (where
    // every f32 is an integer), and every special scalar (NaN, infinities, -0, subnormals, MAX).
    let sincos_u = (0..=4096)
        .map(|k| k as f32 / 4096.0)
        .chain([ONE_MINUS_ULP, 0.125 - 1e-8, 0.125 + 1e-8, 0.375, 0.625, 0.875, 1.3, 2.0])
        .chain((1..=1024).map(|k| k as f32 / -1024.0 - 0.3))
        .chain([-ONE_MINUS_ULP, -1e-30, -0.125 - 1e-8, -1.0, -2.5, 1e-30 - 1.0])
        .chain((0..=46).flat_map(|e| {
            let x = 1.37 * 2f32.powi(e - 23);
            [x, -x, x + 0.3, -(x + 0.3)]
        }))
        .chain([8_388_607.5, -8_388_607.5, 8_388_608.0, 8_388_609.0, 4_194_303.5, 16_777_218.0, 123_456.79])
        .chain(scalars());
    s.row(
        "sincos_2pi",
        &[Group::float("sin", 1, UNIT), Group::float("cos", 1, UNIT)],
        sincos_u.map(|u| (Input::scalar(u), none())),
        |i, _| {
            let (sin, cos) = math::sincos_2pi(i.a[0]);
            floats(&[sin, cos])
        },
    );

    // alpha.rs
    s.row("clamp_alpha", &[Group::value(Bound::Exact)], scalar_cases(), |i, _| floats(&[alpha::clamp_alpha(i.a[0])]));
    s.row("roughness_to_alpha", &[Group::value(Bound::Exact)], scalar_cases(), |i, _| {
        floats(&[alpha::roughness_to_alpha(i.a[0])])
    });
    s.row("alpha_to_roughness", &[Group::value(FEW_OPS)], scalar_cases(), |i, _| {
        floats(&[alpha::alpha_to_roughness(i.a[0])])
    });

    // distribution/ (formulas.rs)
    let alpha_pairs =
        scalars().into_iter().step_by(3).flat_map(|x| scalars().into_iter().step_by(5).map(move |y| (x, y)));
    s.row(
        "trowbridge_reitz_new",
        &[Group::float("alpha", 2, Bound::Exact), Group::bits("isotropic,smooth", 2)],
        alpha_pairs.map(|(x, y)| (Input { a: [x, y, 0.0, 0.0], ..Default::default() }, none())),
        |i, _| {
            let t = TrowbridgeReitz::new(i.a[0], i.a[1]);
            let mut e = floats(&[t.alpha_x, t.alpha_y]);
            e.extend(words(&[t.is_isotropic() as u32, t.is_effectively_smooth() as u32]));
            e
        },
    );
    let dist_dir =
        || dists().into_iter().flat_map(|t| directions().into_iter().map(move |w| (Input::dir(w), with_dist(t))));
    let dist_pair = || {
        dists().into_iter().flat_map(|t| {
            few_directions()
                .into_iter()
                .flat_map(move |a| few_directions().into_iter().map(move |b| (Input::pair(a, b), with_dist(t))))
        })
    };
    s.row("d", &[Group::value(FORMULA)], dist_dir(), |i, k| floats(&[k.distribution.d(i.va())]));
    s.row("lambda", &[Group::value(FORMULA)], dist_dir(), |i, k| floats(&[k.distribution.lambda(i.va())])).ieee();
    s.row("g1", &[Group::value(FORMULA)], dist_dir(), |i, k| floats(&[k.distribution.g1(i.va())]));
    s.row("g2", &[Group::value(FORMULA)], dist_pair(), |i, k| floats(&[k.distribution.g2(i.va(), i.vb())]));
    s.row("g2_separable", &[Group::value(FORMULA)], dist_pair(), |i, k| {
        floats(&[k.distribution.g2_separable(i.va(), i.vb())])
    });
    s.row("d_visible", &[Group::value(FORMULA)], dist_pair(), |i, k| {
        floats(&[k.distribution.d_visible(i.va(), i.vb())])
    });

    // Samplers and their densities.
    let dist_u = || {
        dists().into_iter().flat_map(|t| us(&U).into_iter().map(move |u| (Input::dir_u(Vec3::ZERO, u), with_dist(t))))
    };
    let dist_wo_u = || {
        dists().into_iter().flat_map(|t| {
            wo_directions()
                .into_iter()
                .flat_map(move |wo| us(&U).into_iter().map(move |u| (Input::dir_u(wo, u), with_dist(t))))
        })
    };
    s.row("sample_wm_ndf", &[Group::float("wm", 3, UNIT)], dist_u(), |i, k| {
        floats(&v3(k.distribution.sample_wm_ndf(i.u())))
    });
    s.row("pdf_wm_ndf", &[Group::value(FORMULA)], dist_dir(), |i, k| floats(&[k.distribution.pdf_wm_ndf(i.va())]));
    s.row("sample_wm_vndf", &[Group::float("wm", 3, UNIT)], dist_wo_u(), |i, k| {
        floats(&v3(k.distribution.sample_wm_vndf(i.va(), i.u())))
    });
    s.row("sample_wm_spherical_caps", &[Group::float("wm", 3, UNIT)], dist_wo_u(), |i, k| {
        floats(&v3(k.distribution.sample_wm_spherical_caps(i.va(), i.u())))
    });
    s.row("bounded_k", &[Group::value(FORMULA)], dist_dir(), |i, k| floats(&[k.distribution.bounded_k(i.va())]));
    s.row("sample_wm_bounded", &[Group::float("wm", 3, UNIT)], dist_wo_u(), |i, k| {
        floats(&v3(k.distribution.sample_wm_bounded(i.va(), i.u())))
    });
    s.row("pdf_wi_bounded", &[Group::value(FORMULA)], dist_pair(), |i, k| {
        floats(&[k.distribution.pdf_wi_bounded(i.va(), i.vb())])
    });

    // warp.rs
    let u_cases = || us(&U).into_iter().map(|u| (Input::dir_u(Vec3::ZERO, u), none()));
    let dir_cases = || directions().into_iter().map(|w| (Input::dir(w), none()));
    s.row("sample_cosine_hemisphere", &[Group::float("wi", 3, UNIT)], u_cases(), |i, _| {
        floats(&v3(warp::sample_cosine_hemisphere(i.u())))
    });
    s.row("pdf_cosine_hemisphere", &[Group::value(FEW_OPS)], dir_cases(), |i, _| {
        floats(&[warp::pdf_cosine_hemisphere(i.va())])
    })
    .ieee();
    s.row("sample_uniform_hemisphere", &[Group::float("wi", 3, UNIT)], u_cases(), |i, _| {
        floats(&v3(warp::sample_uniform_hemisphere(i.u())))
    });
    s.row("pdf_uniform_hemisphere", &[Group::value(Bound::Exact)], dir_cases(), |i, _| {
        floats(&[warp::pdf_uniform_hemisphere(i.va())])
    });

    // fresnel/
    let colours = [
        (Vec3::splat(0.04), Vec3::ONE),
        (Vec3::new(1.0, 0.78, 0.34), Vec3::new(1.0, 0.95, 0.9)),
        (Vec3::ZERO, Vec3::ZERO),
        (Vec3::new(NAN, -1.0, 2.0), Vec3::new(1.0, INF, 0.5)),
        // f90 - f0 overflows to +inf from finite parameters (times m^5 = 0 at cos >= 1: NaN).
        (Vec3::new(-f32::MAX, 0.5, -INF), Vec3::new(f32::MAX, -f32::MAX, INF)),
    ];
    let schlick = FRESNEL_COS
        .into_iter()
        .flat_map(|c| colours.map(move |(f0, f90)| (Input { c: [c, 0.0, 0.0, 0.0], ..Input::pair(f0, f90) }, none())));
    s.row("fresnel_schlick", &[Group::float("rgb", 3, FEW_OPS)], schlick, |i, _| {
        floats(&v3(fresnel_schlick(i.c[0], i.va(), i.vb())))
    });
    let etas = [1.5, 1.0 / 1.5, 1.0, 1.33, 2.4, 1e-3, 1e3, 0.0, -1.0, NAN, INF];
    let dielectric = FRESNEL_COS
        .into_iter()
        .flat_map(|c| etas.map(move |eta| (Input { c: [c, eta, 0.0, 0.0], ..Default::default() }, none())));
    s.row("fresnel_dielectric", &[Group::value(FORMULA)], dielectric, |i, _| {
        floats(&[fresnel_dielectric(i.c[0], i.c[1])])
    });
    let iors = [
        (0.143, 3.983),
        (0.2, 3.9),
        (1.5, 0.0),
        (0.0, 0.0),
        (0.0, 1.0),
        (1.0, 0.0),
        (2.9, 3.0),
        (NAN, 1.0),
        (1.0, NAN),
        (INF, 1.0),
        // Unphysical: the denominator vanishes (infinite or huge; 1 where not finite).
        (-1.0, 0.0),
    ];
    let complex = FRESNEL_COS
        .into_iter()
        .flat_map(|c| iors.map(move |(eta, k)| (Input { c: [c, eta, k, 0.0], ..Default::default() }, none())));
    s.row("fresnel_complex", &[Group::value(FORMULA)], complex, |i, _| {
        floats(&[fresnel_complex(i.c[0], i.c[1], i.c[2])])
    });
    let params = FRESNEL_COS.into_iter().flat_map(|c| {
        fresnels().into_iter().map(move |fresnel| {
            (Input { c: [c, 0.0, 0.0, 0.0], ..Default::default() }, GgxConductor { fresnel, ..none() })
        })
    });
    s.row("fresnel_params_eval", &[Group::float("rgb", 3, FORMULA)], params, |i, k| {
        floats(&v3(k.fresnel.eval(i.c[0])))
    });

    // conductor/ (mod.rs, formulas.rs)
    let pair_bsdf = || {
        bsdfs_raw().into_iter().flat_map(|k| {
            few_directions().into_iter().flat_map(move |a| few_directions().into_iter().map(move |b| (a, b, k)))
        })
    };
    s.row(
        "ggx_conductor_eval",
        &[Group::float("rgb", 3, FORMULA)],
        pair_bsdf().map(|(a, b, k)| (Input::pair(a, b), k)),
        |i, k| floats(&v3(k.eval(i.va(), i.vb()))),
    );
    let pdf_cases =
        pair_bsdf().flat_map(|(a, b, k)| SAMPLINGS.map(|t| (Input { n: [t, 0, 0, 0], ..Input::pair(a, b) }, k)));
    s.row("ggx_conductor_pdf", &[Group::value(FORMULA)], pdf_cases, |i, k| {
        floats(&[k.pdf(i.va(), i.vb(), Sampling::from_u32(i.n[0]))])
    });
    let few_u = us(&[0.0, 0.25, 0.5, 0.77, ONE_MINUS_ULP]);
    let sample_cases = bsdfs_raw().into_iter().flat_map(|k| {
        let few_u = few_u.clone();
        wo_directions().into_iter().flat_map(move |wo| {
            let few_u = few_u.clone();
            SAMPLINGS.into_iter().flat_map(move |t| {
                few_u.clone().into_iter().map(move |u| (Input { n: [t, 0, 0, 0], ..Input::dir_u(wo, u) }, k))
            })
        })
    });
    s.row("ggx_conductor_sample", &SAMPLE_GROUPS, sample_cases, |i, k| {
        sample_words(k.sample(i.va(), i.u(), Sampling::from_u32(i.n[0])))
    })
    .rebase(sample_at_gpu_wi, "weight, pdf: cpu at the gpu's wi");

    // dielectric.rs
    let eta_cases = scalars().into_iter().chain(ODD_ETAS).chain(ETAS).map(|x| (Input::scalar(x), none()));
    s.row("clamp_eta", &[Group::value(Bound::Exact)], eta_cases, |i, _| floats(&[clamp_eta(i.a[0])]));
    let normals = [Vec3::Z, -Vec3::Z, spherical(0.8, 1.0), spherical(-0.6, 2.0), Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO];
    let refract_etas: Vec<f32> = ETAS.into_iter().chain(ODD_ETAS).collect();
    let refract_cases = directions()
        .into_iter()
        .chain(dielectric_directions())
        .flat_map(|w| {
            let etas = refract_etas.clone();
            normals.into_iter().flat_map(move |n| etas.clone().into_iter().map(move |eta| (w, n, eta)))
        })
        .chain(critical_pairs().into_iter().map(|(wo, _, k)| (wo, Vec3::Z, k.eta)))
        .map(|(w, n, eta)| (Input { c: [eta, 0.0, 0.0, 0.0], ..Input::pair(w, n) }, none()));
    s.row("refract", &[Group::bits("valid", 1), Group::float("wt", 3, UNIT)], refract_cases, |i, _| {
        let r = refract(i.va(), i.vb(), i.c[0]);
        let mut e = words(&[r.is_some() as u32]);
        e.extend(floats(&v3(r.unwrap_or(Vec3::ZERO))));
        e
    });
    let dielectric_pairs = || {
        let dirs = dielectric_directions();
        dielectrics()
            .into_iter()
            .flat_map(move |k| {
                let dirs = dirs.clone();
                dirs.clone().into_iter().flat_map(move |a| dirs.clone().into_iter().map(move |b| (a, b, k)))
            })
            .chain(critical_pairs())
    };
    let eval_cases =
        dielectric_pairs().flat_map(|(a, b, k)| [0, 1].map(|m| (Input { n: [0, m, 0, 0], ..Input::pair(a, b) }, k)));
    s.dielectric_row("ggx_dielectric_eval", &[Group::float("rgb", 3, FORMULA)], eval_cases, |i, k| {
        floats(&v3(k.eval(i.va(), i.vb(), mode(i.n[1]))))
    });
    let pdf_cases = dielectric_pairs().enumerate().flat_map(|(j, (a, b, k))| {
        dielectric_samplings(j).map(|t| (Input { n: [t, (j % 2) as u32, 0, 0], ..Input::pair(a, b) }, k))
    });
    s.dielectric_row("ggx_dielectric_pdf", &[Group::value(FORMULA)], pdf_cases, |i, k| {
        floats(&[k.pdf(i.va(), i.vb(), Sampling::from_u32(i.n[0]), mode(i.n[1]))])
    });
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
    let sample_cases = dielectrics().into_iter().flat_map(|k| {
        let (sample_wo, sample_u) = (sample_wo.clone(), sample_u.clone());
        sample_wo.into_iter().flat_map(move |wo| {
            let sample_u = sample_u.clone();
            SAMPLINGS.into_iter().flat_map(move |t| {
                // Cosine and uniform are refused whatever u is: one u each.
                let us = if t == 4 || t == 5 { sample_u[..1].to_vec() } else { sample_u.clone() };
                us.into_iter().enumerate().map(move |(j, u)| {
                    let c = [u.x, u.y, U_LOBES[j % U_LOBES.len()], 0.0];
                    (Input { c, n: [t, (j % 2) as u32, 0, 0], ..Input::dir(wo) }, k)
                })
            })
        })
    });
    s.dielectric_row("ggx_dielectric_sample", &DIELECTRIC_SAMPLE_GROUPS, sample_cases, |i, k| {
        sample_words(k.sample(i.va(), i.u(), i.c[2], Sampling::from_u32(i.n[0]), mode(i.n[1])))
    })
    .rebase(dielectric_sample_at_gpu_wi, "weight, pdf: cpu at the gpu's wi");

    // mis.rs
    let pdfs = [0.0, -1.0, NAN, INF, -INF, f32::MAX, f32::MIN_POSITIVE, 1e-30, 0.5, 1.0, 3.0, 1e30];
    // Counts 0, NaN and +inf against densities +inf and 0: the products 0 inf that ggx-core
    // sanitizes to 0 instead of NaN.
    let counts = [1.0, 2.0, 0.0, 0.5, NAN, INF, f32::MAX];
    let mis_cases = || {
        counts.into_iter().flat_map(move |nf| {
            pdfs.into_iter().flat_map(move |f| {
                counts.into_iter().flat_map(move |ng| {
                    pdfs.into_iter().map(move |g| (Input { c: [nf, f, ng, g], ..Default::default() }, none()))
                })
            })
        })
    };
    s.row("balance_heuristic", &[Group::value(FEW_OPS)], mis_cases(), |i, _| {
        floats(&[mis::balance_heuristic(i.c[0], i.c[1], i.c[2], i.c[3])])
    });
    s.row("power_heuristic", &[Group::value(FEW_OPS)], mis_cases(), |i, _| {
        floats(&[mis::power_heuristic(i.c[0], i.c[1], i.c[2], i.c[3])])
    });

    // frame.rs
    s.row(
        "frame_from_z",
        &[Group::float("x", 3, UNIT), Group::float("y", 3, UNIT), Group::float("z", 3, UNIT)],
        dir_cases().chain([(Input::dir(Vec3::new(1e-20, -1e-20, -1.0)), none())]),
        |i, _| {
            let f = Frame::from_z(i.va());
            floats(&[f.x.to_array(), f.y.to_array(), f.z.to_array()].concat())
        },
    );
    // Vectors with NaN and infinite components (in few_directions) and finite ones whose
    // image overflows.
    let frame_vectors =
        || few_directions().into_iter().chain([Vec3::splat(f32::MAX), Vec3::new(1e38, -3e38, 2e38), Vec3::splat(NAN)]);
    let frame_cases = || {
        few_directions().into_iter().flat_map(move |n| {
            let f = Frame::from_z(n);
            frame_vectors().map(move |v| {
                let input = Input {
                    a: f.x.extend(v.x).to_array(),
                    b: f.y.extend(v.y).to_array(),
                    c: f.z.extend(v.z).to_array(),
                    ..Default::default()
                };
                (input, none())
            })
        })
    };
    fn frame(i: &Input) -> Frame {
        Frame { x: i.va(), y: i.vb(), z: i.vc() }
    }
    fn v(i: &Input) -> Vec3 {
        Vec3::new(i.a[3], i.b[3], i.c[3])
    }
    s.row("frame_to_local", &[Group::float("xyz", 3, UNIT)], frame_cases(), |i, _| {
        floats(&v3(frame(i).to_local(v(i))))
    });
    s.row("frame_to_world", &[Group::float("xyz", 3, UNIT)], frame_cases(), |i, _| {
        floats(&v3(frame(i).to_world(v(i))))
    });
    let reflect_cases =
        few_directions().into_iter().flat_map(|a| directions().into_iter().map(move |b| (Input::pair(a, b), none())));
    s.row("reflect", &[Group::float("xyz", 3, UNIT)], reflect_cases, |i, _| floats(&v3(reflect(i.va(), i.vb()))));

    // sequence/: bit-identical.
    let w = u32s(4000);
    let w2 = || u32s(60).into_iter().flat_map(|a| u32s(60).into_iter().map(move |b| (a, b)));
    let word_cases = |ns: Vec<[u32; 4]>| ns.into_iter().map(|n| (Input::words(n), none()));
    s.row("hash_u32", &[Group::bits("word", 1)], word_cases(w.iter().map(|&x| [x, 0, 0, 0]).collect()), |i, _| {
        words(&[seq::hash_u32(i.n[0])])
    });
    s.row("hash_combine", &[Group::bits("word", 1)], word_cases(w2().map(|(a, b)| [a, b, 0, 0]).collect()), |i, _| {
        words(&[seq::hash_combine(i.n[0], i.n[1])])
    });
    s.row(
        "u32_to_unit_f32",
        &[Group::bits("word", 1)],
        word_cases(w.iter().map(|&x| [x, 0, 0, 0]).collect()),
        |i, _| words(&[seq::u32_to_unit_f32(i.n[0]).to_bits()]),
    );
    s.row(
        "counter_rng_new",
        &[Group::bits("key", 1), Group::bits("counter", 1)],
        word_cases(w2().map(|(a, b)| [a, b, 0, 0]).collect()),
        |i, _| {
            let r = CounterRng::new(i.n[0], i.n[1]);
            words(&[r.key, r.counter])
        },
    );
    let rng_cases = || {
        word_cases(
            u32s(30)
                .into_iter()
                .flat_map(|key| u32s(30).into_iter().map(move |c| [key, c, c ^ 0x5555_5555, 0]))
                .collect(),
        )
    };
    s.row("counter_rng_get_u32", &[Group::bits("word", 1)], rng_cases(), |i, _| {
        words(&[CounterRng { key: i.n[0], counter: i.n[1] }.get_u32(i.n[2])])
    });
    s.row("counter_rng_next_u32", &[Group::bits("x,y", 2), Group::bits("counter", 1)], rng_cases(), |i, _| {
        let mut r = CounterRng { key: i.n[0], counter: i.n[1] };
        let (x, y) = (r.next_u32(), r.next_u32());
        words(&[x, y, r.counter])
    });
    s.row("counter_rng_next_f32", &[Group::bits("x", 1), Group::bits("counter", 1)], rng_cases(), |i, _| {
        let mut r = CounterRng { key: i.n[0], counter: i.n[1] };
        words(&[r.next_f32().to_bits(), r.counter])
    });
    s.row("counter_rng_next_vec2", &[Group::bits("xy", 2), Group::bits("counter", 1)], rng_cases(), |i, _| {
        let mut r = CounterRng { key: i.n[0], counter: i.n[1] };
        let v = r.next_vec2();
        words(&[v.x.to_bits(), v.y.to_bits(), r.counter])
    });
    s.row("counter_rng_advance", &[Group::bits("counter", 1), Group::bits("next_u32", 1)], rng_cases(), |i, _| {
        let mut r = CounterRng { key: i.n[0], counter: i.n[1] };
        r.advance(i.n[2]);
        words(&[r.counter, r.next_u32()])
    });
    let dims = [0, 1, 2, 3, 4, 5, 6, 7, 8, 13, 0x8000_0001, u32::MAX];
    let sobol_cases = (0..1024).chain(u32s(500)).flat_map(|i| dims.map(|d| [i, d, 0, 0])).collect();
    s.row("sobol", &[Group::bits("word", 1)], word_cases(sobol_cases), |i, _| words(&[seq::sobol(i.n[0], i.n[1])]));
    s.row("owen_scramble", &[Group::bits("word", 1)], word_cases(w2().map(|(a, b)| [a, b, 0, 0]).collect()), |i, _| {
        words(&[seq::owen_scramble(i.n[0], i.n[1])])
    });
    s.row(
        "shuffle_index_reversed",
        &[Group::bits("word", 1)],
        word_cases(w2().map(|(a, b)| [a, b, 0, 0]).collect()),
        |i, _| words(&[seq::shuffle_index_reversed(i.n[0], i.n[1])]),
    );
    let shuffled_cases =
        u32s(40).into_iter().flat_map(|r| u32s(6).into_iter().flat_map(move |g| dims.map(|d| [r, g, d, 0])));
    s.row("sobol_owen_shuffled", &[Group::bits("word", 1)], word_cases(shuffled_cases.collect()), |i, _| {
        words(&[seq::sobol_owen_shuffled(i.n[0], i.n[1], i.n[2])])
    });
    let owen_cases = || {
        let seeds = [0, 7, 0xdead_beef, u32::MAX];
        word_cases(
            (0..256)
                .chain(u32s(200))
                .flat_map(|i| dims.into_iter().flat_map(move |d| seeds.map(|s| [i, d, s, 0])))
                .collect(),
        )
    };
    s.row("sobol_owen_u32", &[Group::bits("word", 1)], owen_cases(), |i, _| {
        words(&[seq::sobol_owen_u32(i.n[0], i.n[1], i.n[2])])
    });
    s.row("sobol_owen", &[Group::bits("word", 1)], owen_cases(), |i, _| {
        words(&[seq::sobol_owen(i.n[0], i.n[1], i.n[2]).to_bits()])
    });
    let new_cases = [0, 1].into_iter().flat_map(|kind| {
        u32s(12).into_iter().flat_map(move |seed| u32s(12).into_iter().map(move |p| [kind, seed, p, p ^ seed]))
    });
    s.row("sample_stream_new", &[Group::bits("fields", 4)], word_cases(new_cases.collect()), |i, _| {
        let st = SampleStream::new(SequenceKind::from_u32(i.n[0]), i.n[1], i.n[2], i.n[3]);
        words(&[st.kind, st.seed, st.sample_index, st.dimension])
    });
    let stream_cases = || {
        let dims = [0, 1, 2, 3, 4, 5, 6, 7, 9, u32::MAX - 2, u32::MAX - 1, u32::MAX];
        let streams = [0, 1, 7].into_iter().flat_map(|kind| {
            u32s(8).into_iter().flat_map(move |seed| u32s(8).into_iter().map(move |sample| (kind, seed, sample)))
        });
        let cases = streams.flat_map(move |(kind, seed, sample)| {
            dims.map(|d| Input { n: [kind, seed, sample, d], m: [d ^ 1, 0, 0, 0], ..Default::default() })
        });
        cases.map(|i| (i, none())).collect::<Vec<_>>()
    };
    fn stream(i: &Input) -> SampleStream {
        SampleStream { kind: i.n[0], seed: i.n[1], sample_index: i.n[2], dimension: i.n[3] }
    }
    s.row("sample_stream_get_u32", &[Group::bits("word", 1)], stream_cases(), |i, _| {
        words(&[stream(i).get_u32(i.m[0])])
    });
    s.row("sample_stream_next_1d", &[Group::bits("x,y", 2), Group::bits("dimension", 1)], stream_cases(), |i, _| {
        let mut st = stream(i);
        let (x, y) = (st.next_1d(), st.next_1d());
        words(&[x.to_bits(), y.to_bits(), st.dimension])
    });
    s.row("sample_stream_next_2d", &[Group::bits("p,q", 4), Group::bits("dimension", 1)], stream_cases(), |i, _| {
        let mut st = stream(i);
        let (p, q) = (st.next_2d(), st.next_2d());
        words(&[p.x.to_bits(), p.y.to_bits(), q.x.to_bits(), q.y.to_bits(), st.dimension])
    });

    // Layout: every word of the uploaded GgxConductor read back field by field.
    let mut odd = bsdfs();
    odd.push(GgxConductor { pad: [0xdead_beef, 0x0bad_cafe], ..odd[3] });
    s.row(
        "ggx_conductor_layout",
        &[Group::bits("alpha", 2), Group::bits("pad", 2), Group::bits("fresnel", 12)],
        odd.into_iter().map(|k| (Input::default(), k)),
        |_, k| words(bytemuck::cast_slice::<GgxConductor, u32>(std::slice::from_ref(k))),
    );
    // Layout: every word of the uploaded GgxDielectric read back field by field.
    let mut odd = dielectrics();
    odd.push(GgxDielectric { pad: 0xdead_beef, ..odd[3] });
    s.dielectric_row(
        "ggx_dielectric_layout",
        &[Group::bits("alpha", 2), Group::bits("eta", 1), Group::bits("pad", 1)],
        odd.into_iter().map(|k| (Input::default(), k)),
        |_, k| words(bytemuck::cast_slice::<GgxDielectric, u32>(std::slice::from_ref(k))),
    );
    // BsdfSample::mis_pdf: every scalar as the pdf of a delta and of a non-delta sample.
    let mis_pdf_cases = scalars().into_iter().flat_map(|x| {
        [0, 1].map(|delta| (Input { a: [x, 0.0, 0.0, 0.0], n: [delta, 0, 0, 0], ..Default::default() }, none()))
    });
    s.row("bsdf_sample_mis_pdf", &[Group::value(Bound::Exact)], mis_pdf_cases, |i, _| {
        let sample = BsdfSample { wi: Vec3::ZERO, weight: Vec3::ZERO, pdf: i.a[0], is_delta: i.n[0] != 0 };
        floats(&[sample.mis_pdf()])
    })
    .ieee();

    // metal_rough.rs
    let ior_cases = scalars().into_iter().chain(ODD_ETAS).chain([0.0, -0.0, 1.0, 1.5, 1.33, 2.4]);
    s.row("clamp_ior", &[Group::value(Bound::Exact)], ior_cases.map(|x| (Input::scalar(x), none())), |i, _| {
        floats(&[clamp_ior(i.a[0])])
    });
    let colours = [
        Vec3::ONE,
        Vec3::new(1.0, 0.5, 2.0),
        Vec3::ZERO,
        Vec3::new(NAN, INF, -1.0),
        Vec3::new(1e30, -0.0, 1e-40),
        Vec3::new(30.0, f32::MAX, -INF),
    ];
    let f0_cases = ETAS.into_iter().chain(ODD_ETAS).chain([0.0, 1.33, 3.0]).flat_map(|ior| {
        colours.map(|c| (Input { a: [ior, 0.0, 0.0, 0.0], b: c.extend(0.0).to_array(), ..Default::default() }, none()))
    });
    s.row("dielectric_f0", &[Group::float("rgb", 3, FORMULA)], f0_cases, |i, _| {
        floats(&v3(dielectric_f0(i.a[0], i.vb())))
    });
    // Arguments in turn (coprime list lengths): ordinary, edge and hostile values of each.
    let new_bases = [
        Vec3::new(0.8, 0.5, 0.2),
        Vec3::ONE,
        Vec3::ZERO,
        Vec3::new(NAN, INF, -INF),
        Vec3::new(-1.0, 2.0, 1e-40),
        Vec3::new(0.02, 0.9, ONE_MINUS_ULP),
        Vec3::new(f32::MAX, 0.5, 1e-7),
    ];
    let new_scalars = [0.0, 0.5, 1.0, 0.2, NAN, INF, -INF, -1.0, 2.0, 1e-40, ONE_MINUS_ULP];
    let new_iors = [1.5, 0.0, -0.0, 1.0, 2.4, 1.33, NAN, INF, -1.0, 0.5, 1e30, 3.0, 1e-40];
    let new_cases = (0..4000usize).map(|n| {
        let base = new_bases[n % new_bases.len()];
        let metallic = new_scalars[(n / 7) % new_scalars.len()];
        let (ax, ay) = ALPHAS[(n / 3) % ALPHAS.len()];
        let ior = new_iors[(n / 5) % new_iors.len()];
        let colour = colours[(n / 11) % colours.len()];
        let weight = new_scalars[(n / 13 + 3) % new_scalars.len()];
        let input = Input {
            a: base.extend(metallic).to_array(),
            b: [ax, ay, ior, weight],
            c: colour.extend(0.0).to_array(),
            ..Default::default()
        };
        (input, none())
    });
    s.row("gltf_metal_rough_new", &METAL_ROUGH_GROUPS, new_cases, |i, _| {
        metal_rough_words(&GltfMetalRough::new(i.va(), i.a[3], i.b[0], i.b[1], i.b[2], i.vc(), i.b[3]))
    });
    let core_cases = new_bases.into_iter().flat_map(|base| {
        new_scalars.into_iter().flat_map(move |metallic| {
            [0.0, 5e-4, 1e-3, 0.09, 1.0, NAN, 2.0].map(|alpha| {
                (Input { a: base.extend(metallic).to_array(), b: [alpha, 0.0, 0.0, 0.0], ..Default::default() }, none())
            })
        })
    });
    s.row("gltf_metal_rough_core", &METAL_ROUGH_GROUPS, core_cases, |i, _| {
        metal_rough_words(&GltfMetalRough::core(i.va(), i.a[3], i.b[0]))
    });
    let materials = || metal_roughs().into_iter().map(|m| pack_metal_rough(&m));
    s.row(
        "gltf_metal_rough_is_delta",
        &[Group::bits("delta", 1)],
        materials().map(|k| (Input::default(), k)),
        |_, k| words(&[unpack_metal_rough(k).is_delta() as u32]),
    );
    s.row(
        "gltf_metal_rough_specular",
        &[Group::bits("alpha", 2), Group::bits("pad", 2), Group::bits("fresnel", 12)],
        materials().map(|k| (Input::default(), k)),
        |_, k| words(bytemuck::cast_slice::<GgxConductor, u32>(&[unpack_metal_rough(k).specular()])),
    );
    s.row(
        "gltf_metal_rough_specular_probability",
        &[Group::value(Bound::Exact)],
        materials().map(|k| (Input::default(), k)),
        |_, k| floats(&[unpack_metal_rough(k).specular_probability()]),
    );
    let cos_cases =
        || materials().flat_map(|k| FRESNEL_COS.map(|c| (Input { c: [c, 0.0, 0.0, 0.0], ..Default::default() }, k)));
    s.row("gltf_metal_rough_specular_fresnel", &[Group::float("rgb", 3, FORMULA)], cos_cases(), |i, k| {
        floats(&v3(unpack_metal_rough(k).specular_fresnel(i.c[0])))
    });
    // 1 - specular_weight max(fr_d) cancels where fr_d nears one: absolute in [0, 1].
    s.row("gltf_metal_rough_diffuse_weight", &[Group::value(UNIT)], cos_cases(), |i, k| {
        floats(&[unpack_metal_rough(k).diffuse_weight(i.c[0])])
    });
    let metal_rough_pairs = || {
        materials().flat_map(|k| {
            few_directions().into_iter().flat_map(move |a| few_directions().into_iter().map(move |b| (a, b, k)))
        })
    };
    s.row(
        "gltf_metal_rough_eval",
        &[Group::float("rgb", 3, FORMULA)],
        metal_rough_pairs().map(|(a, b, k)| (Input::pair(a, b), k)),
        |i, k| floats(&v3(unpack_metal_rough(k).eval(i.va(), i.vb()))),
    );
    let pdf_cases = metal_rough_pairs()
        .flat_map(|(a, b, k)| SAMPLINGS.map(|t| (Input { n: [t, 0, 0, 0], ..Input::pair(a, b) }, k)));
    s.row("gltf_metal_rough_pdf", &[Group::value(FORMULA)], pdf_cases, |i, k| {
        floats(&[unpack_metal_rough(k).pdf(i.va(), i.vb(), Sampling::from_u32(i.n[0]))])
    });
    let few_u = us(&[0.0, 0.25, 0.5, 0.77, ONE_MINUS_ULP]);
    let sample_cases = materials().flat_map(|k| {
        let few_u = few_u.clone();
        wo_directions().into_iter().flat_map(move |wo| {
            let few_u = few_u.clone();
            SAMPLINGS.into_iter().flat_map(move |t| {
                few_u.clone().into_iter().enumerate().map(move |(j, u)| {
                    let c = [u.x, u.y, U_LOBES[j % U_LOBES.len()], 0.0];
                    (Input { c, n: [t, 0, 0, 0], ..Input::dir(wo) }, k)
                })
            })
        })
    });
    s.row("gltf_metal_rough_sample", &SAMPLE_GROUPS, sample_cases, |i, k| {
        sample_words(unpack_metal_rough(k).sample(i.va(), i.u(), i.c[2], Sampling::from_u32(i.n[0])))
    })
    .rebase(metal_rough_sample_at_gpu_wi, "weight, pdf: cpu at the gpu's wi");

    // clearcoat.rs
    let fresnel_cases = scalars().into_iter().chain(FRESNEL_COS).map(|x| (Input::scalar(x), none()));
    s.row("clearcoat_fresnel", &[Group::value(FEW_OPS)], fresnel_cases, |i, _| floats(&[clearcoat_fresnel(i.a[0])]));
    // 1 - sw F_avg(max f0) cancels where sw F_avg nears one: absolute in [0, 1].
    s.row(
        "metal_rough_albedo_estimate",
        &[Group::value(UNIT)],
        metal_roughs().into_iter().map(|m| (Input::default(), pack_metal_rough(&m))),
        |_, k| floats(&[metal_rough_albedo_estimate(&unpack_metal_rough(k))]),
    );
    // Bases with finite fields only (the row copies them to its output), every weight and alpha edge.
    let finite_bases = metal_roughs().into_iter().filter(|m| {
        let d = m.distribution;
        [m.base_color, m.f0]
            .concat()
            .into_iter()
            .chain([m.metallic, m.specular_weight, d.alpha_x, d.alpha_y, m.p_specular])
            .all(f32::is_finite)
    });
    let new_weights = [0.0, 0.5, 1.0, 0.25, NAN, INF, -INF, -1.0, 2.0, 1e-30, ONE_MINUS_ULP, -0.0];
    let new_alphas = [0.0, 5e-4, 1e-3, 0.01, 0.3, 1.0, NAN, 2.0, -1.0, INF];
    let new_cases = finite_bases.flat_map(|m| {
        new_weights.into_iter().flat_map(move |w| {
            new_alphas.map(|a| (Input { a: [w, a, 0.0, 0.0], ..Default::default() }, pack_metal_rough(&m)))
        })
    });
    s.row("gltf_clearcoat_new", &CLEARCOAT_GROUPS, new_cases, |i, k| {
        clearcoat_words(&GltfClearcoat::new(unpack_metal_rough(k), i.a[0], i.a[1]))
    });
    let coats = || clearcoats().into_iter().map(|c| pack_clearcoat(&c));
    s.row(
        "gltf_clearcoat_coat_weight",
        &[Group::value(Bound::Exact)],
        coats().map(|k| (Input::default(), k)),
        |_, k| floats(&[unpack_clearcoat(k).coat_weight()]),
    );
    s.row(
        "gltf_clearcoat_coat_is_delta",
        &[Group::bits("delta", 1)],
        coats().map(|k| (Input::default(), k)),
        |_, k| words(&[unpack_clearcoat(k).coat_is_delta() as u32]),
    );
    s.row(
        "gltf_clearcoat_coat_lobe",
        &[Group::bits("alpha", 2), Group::bits("pad", 2), Group::bits("fresnel", 12)],
        coats().map(|k| (Input::default(), k)),
        |_, k| words(bytemuck::cast_slice::<GgxConductor, u32>(&[unpack_clearcoat(k).coat_lobe()])),
    );
    let cos_cases =
        || coats().flat_map(|k| FRESNEL_COS.map(|c| (Input { c: [c, 0.0, 0.0, 0.0], ..Default::default() }, k)));
    s.row("gltf_clearcoat_coat_mix", &[Group::value(FORMULA)], cos_cases(), |i, k| {
        floats(&[unpack_clearcoat(k).coat_mix(i.c[0])])
    });
    // A polynomial of |cos| (in [0, 1], no cancellation: relative).
    s.row("gltf_clearcoat_base_mix", &[Group::value(FORMULA)], cos_cases(), |i, k| {
        floats(&[unpack_clearcoat(k).base_mix(i.c[0])])
    });
    // A ratio of sums, clamped to [0.05, 0.95]: absolute in [0, 1].
    s.row("gltf_clearcoat_coat_probability", &[Group::value(UNIT)], cos_cases(), |i, k| {
        floats(&[unpack_clearcoat(k).coat_probability(i.c[0])])
    });
    let clearcoat_pairs = || {
        coats().flat_map(|k| {
            few_directions().into_iter().flat_map(move |a| few_directions().into_iter().map(move |b| (a, b, k)))
        })
    };
    s.row(
        "gltf_clearcoat_eval",
        &[Group::float("rgb", 3, FORMULA)],
        clearcoat_pairs().map(|(a, b, k)| (Input::pair(a, b), k)),
        |i, k| floats(&v3(unpack_clearcoat(k).eval(i.va(), i.vb()))),
    );
    let pdf_cases =
        clearcoat_pairs().flat_map(|(a, b, k)| SAMPLINGS.map(|t| (Input { n: [t, 0, 0, 0], ..Input::pair(a, b) }, k)));
    s.row("gltf_clearcoat_pdf", &[Group::value(FORMULA)], pdf_cases, |i, k| {
        floats(&[unpack_clearcoat(k).pdf(i.va(), i.vb(), Sampling::from_u32(i.n[0]))])
    });
    // Not the base with the raw p_specular = 1 - 2^-24: every u_lobe >= 1 - 2^-24 (sanitize_u)
    // rescales to (1 - 2^-24 - p_c) / (1 - p_c), within an ulp of it, so the base's lobe would
    // depend on the last bit of a division, which Vulkan leaves to 2.5 ulp (gltf_metal_rough_sample
    // has the raw field in its own rows, where u_lobe is compared as given).
    let few_u = us(&[0.0, 0.25, 0.5, 0.77, ONE_MINUS_ULP]);
    let sample_coats = coats().filter(|k| unpack_clearcoat(k).base.p_specular != ONE_MINUS_ULP);
    let sample_cases = sample_coats.flat_map(|k| {
        let few_u = few_u.clone();
        wo_directions().into_iter().flat_map(move |wo| {
            let few_u = few_u.clone();
            SAMPLINGS.into_iter().flat_map(move |t| {
                few_u.clone().into_iter().enumerate().map(move |(j, u)| {
                    let c = [u.x, u.y, U_LOBES[j % U_LOBES.len()], 0.0];
                    (Input { c, n: [t, 0, 0, 0], ..Input::dir(wo) }, k)
                })
            })
        })
    });
    s.row("gltf_clearcoat_sample", &SAMPLE_GROUPS, sample_cases, |i, k| {
        sample_words(unpack_clearcoat(k).sample(i.va(), i.u(), i.c[2], Sampling::from_u32(i.n[0])))
    })
    .rebase(clearcoat_sample_at_gpu_wi, "weight, pdf: cpu at the gpu's wi");

    // energy.wgsl
    energy::energy_specs(&mut s);
    s.0
}
