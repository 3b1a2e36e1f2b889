//! The parity harness: every function of `ggx_core.wgsl` runs on the GPU over input tables
//! built here, and its outputs are compared with ggx-core on the CPU.

use std::fmt::{self, Write as _};
use std::sync::mpsc;

use bytemuck::Zeroable as _;
use ggx_core::GgxConductor;
use wgpu::util::DeviceExt as _;

use crate::{GGX_CORE_WGSL, GpuContext, GpuError, PARITY_WGSL};

mod cases;

use cases::{Expect, Input, NAN, Spec, specs};

/// What ggx-core promises about a function's floating-point outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Contract {
    /// NaN and infinities come out where ggx-core returns them (IEEE propagation, `+inf` for
    /// an infinite input or at a pole); the GPU must return NaN exactly where ggx-core does.
    Ieee,
    /// Every output is finite for every input, as ggx-core documents and its
    /// `tests/robustness.rs` property tests check: a NaN or infinity from either the GPU or
    /// ggx-core fails the row.
    Finite,
}

impl fmt::Display for Contract {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Contract::Ieee => "ieee",
            Contract::Finite => "finite",
        })
    }
}

/// Output words per case (`OUT_WORDS` in parity.wgsl).
const OUT_WORDS: usize = 16;
/// Cases per dispatch, which keeps every buffer at a few MiB.
const CHUNK: usize = 1 << 15;
/// `@workgroup_size` of the kernel.
const WORKGROUP: usize = 64;

/// Tolerance for floating-point outputs: a GPU value `g` matches the CPU value `c` when both
/// are NaN, or both are the same infinity, or both are finite with `ulp(g, c) <= ulps`,
/// `|g - c| <= abs` or `|g - c| < f32::MIN_POSITIVE` (Vulkan lets an adapter flush subnormals).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    /// Largest accepted distance in units in the last place.
    pub ulps: u64,
    /// Largest accepted absolute difference (for outputs that cancel).
    pub abs: f32,
}

impl Bound {
    /// Bit-identical (up to the sign of zero, the NaN payload and flushed subnormals).
    pub const EXACT: Bound = Bound { ulps: 0, abs: 0.0 };

    const fn ulps(ulps: u64) -> Bound {
        Bound { ulps, abs: 0.0 }
    }

    const fn mixed(ulps: u64, abs: f32) -> Bound {
        Bound { ulps, abs }
    }

    /// Whether `gpu` matches `cpu`.
    pub fn accepts(&self, gpu: f32, cpu: f32) -> bool {
        if gpu.is_nan() || cpu.is_nan() {
            return gpu.is_nan() && cpu.is_nan();
        }
        if gpu.is_infinite() || cpu.is_infinite() {
            return gpu == cpu;
        }
        let diff = (gpu - cpu).abs();
        ulp_distance(gpu, cpu) <= self.ulps || diff <= self.abs || diff < f32::MIN_POSITIVE
    }
}

impl fmt::Display for Bound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.ulps, self.abs) {
            (0, 0.0) => write!(f, "exact"),
            (u, 0.0) => write!(f, "{u} ulp"),
            (u, a) => write!(f, "{u} ulp|{a:.0e} abs"),
        }
    }
}

/// Distance between two non-NaN floats in units in the last place (`+0` and `-0` are equal).
fn ulp_distance(a: f32, b: f32) -> u64 {
    let key = |x: f32| {
        let bits = i64::from(x.to_bits());
        if bits & 0x8000_0000 != 0 { -(bits & 0x7fff_ffff) } else { bits }
    };
    (key(a) - key(b)).unsigned_abs()
}

/// Result of one function: how far the GPU was from ggx-core.
#[derive(Clone, Debug)]
pub struct RowReport {
    /// WGSL function name (the ggx-core function it mirrors has the same name).
    pub name: &'static str,
    /// Number of input cases.
    pub cases: usize,
    /// Largest ULP distance over the floating-point outputs (`u64::MAX` for a NaN mismatch).
    pub max_ulp: u64,
    /// Largest relative error `|g - c| / |c|` over finite, non-zero CPU outputs.
    pub max_rel: f64,
    /// Largest absolute error over finite outputs.
    pub max_abs: f64,
    /// The tolerance the row is held to.
    pub bound: Bound,
    /// Whether the floating-point outputs must be finite; `None` for a row whose outputs are
    /// all compared bit for bit as words (sequences, layout).
    pub contract: Option<Contract>,
    /// Outputs outside the bound (or integer words that differ), plus, under
    /// [`Contract::Finite`], outputs that are NaN or infinite on either side.
    pub failures: usize,
    /// NaN outputs on the GPU and on the CPU.
    pub nan: (usize, usize),
    /// Infinite outputs on the GPU and on the CPU.
    pub inf: (usize, usize),
    /// The worst failing case, for the log.
    pub worst: Option<String>,
}

impl RowReport {
    /// No failure, no NaN where ggx-core has none, and under [`Contract::Finite`] no NaN or
    /// infinity at all.
    pub fn passed(&self) -> bool {
        let finite = self.nan == (0, 0) && self.inf == (0, 0);
        self.failures == 0 && self.nan.0 <= self.nan.1 && (finite || self.contract != Some(Contract::Finite))
    }
}

/// What the adapter does with special values (informational; the WGSL does not rely on the
/// builtins probed here).
#[derive(Clone, Debug)]
pub struct ProbeReport {
    /// `x != x` is true for NaN (never on naga's SPIR-V path, which emits `OpFOrdNotEqual`).
    pub nan_ne_self: bool,
    /// `!(NaN > 0)` is true.
    pub not_gt_nan: bool,
    /// The bit-pattern test `is_nan` of ggx_core.wgsl is true for NaN.
    pub is_nan_bits: bool,
    /// Builtin `max(NaN, 0)`.
    pub max_nan_zero: f32,
    /// Builtin `min(NaN, 1)`.
    pub min_nan_one: f32,
    /// Builtin `clamp(NaN, 0, 1)`.
    pub clamp_nan: f32,
    /// `1 / 0`.
    pub one_over_zero: f32,
    /// `0 / 0`.
    pub zero_over_zero: f32,
    /// `sqrt(-1)`.
    pub sqrt_minus_one: f32,
    /// A subnormal input (2^-133) times one survives.
    pub subnormal_input_kept: bool,
    /// `1e-20 * 1e-20` (subnormal) is not flushed to zero.
    pub subnormal_result_kept: bool,
    /// `a * b + c` was fused into an FMA.
    pub fma_contracted: bool,
}

impl fmt::Display for ProbeReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "adapter behaviour on special values:")?;
        writeln!(
            f,
            "  x != x for NaN: {}; !(NaN > 0): {}; bit-test is_nan(NaN): {}",
            self.nan_ne_self, self.not_gt_nan, self.is_nan_bits
        )?;
        writeln!(
            f,
            "  builtin max(NaN, 0) = {:?}, min(NaN, 1) = {:?}, clamp(NaN, 0, 1) = {:?}",
            self.max_nan_zero, self.min_nan_one, self.clamp_nan
        )?;
        writeln!(
            f,
            "  1/0 = {:?}, 0/0 = {:?}, sqrt(-1) = {:?}",
            self.one_over_zero, self.zero_over_zero, self.sqrt_minus_one
        )?;
        writeln!(
            f,
            "  subnormal input kept: {}, subnormal result kept: {}, a*b+c fused to fma: {}",
            self.subnormal_input_kept, self.subnormal_result_kept, self.fma_contracted
        )
    }
}

/// Every function's comparison, plus the adapter probe.
#[derive(Clone, Debug)]
pub struct ParityReport {
    /// The adapter the kernel ran on ([`GpuContext::describe`]).
    pub adapter: String,
    /// One row per WGSL function.
    pub rows: Vec<RowReport>,
    /// How the adapter treats special values.
    pub probe: ProbeReport,
}

impl ParityReport {
    /// True when every row passed.
    pub fn passed(&self) -> bool {
        self.rows.iter().all(RowReport::passed)
    }

    /// The rows that failed.
    pub fn failures(&self) -> impl Iterator<Item = &RowReport> {
        self.rows.iter().filter(|r| !r.passed())
    }

    /// The report as a text table, one row per function, then the adapter probe and the
    /// worst case of every failing row.
    pub fn table(&self) -> String {
        let mut s = format!("parity of ggx_core.wgsl against ggx-core on {}\n", self.adapter);
        let _ = writeln!(
            s,
            "{:<26} {:>7} {:>8} {:>11} {:>11} {:<17} {:<8} {:>9} {:>9}  result",
            "function", "cases", "max ulp", "max rel", "max abs", "bound", "contract", "nan g/c", "inf g/c"
        );
        for r in &self.rows {
            let ulp = if r.max_ulp == u64::MAX { "inf".to_string() } else { r.max_ulp.to_string() };
            let _ = writeln!(
                s,
                "{:<26} {:>7} {:>8} {:>11.2e} {:>11.2e} {:<17} {:<8} {:>9} {:>9}  {}",
                r.name,
                r.cases,
                ulp,
                r.max_rel,
                r.max_abs,
                r.bound.to_string(),
                r.contract.map_or("bits".to_string(), |c| c.to_string()),
                format!("{}/{}", r.nan.0, r.nan.1),
                format!("{}/{}", r.inf.0, r.inf.1),
                if r.passed() { "pass" } else { "FAIL" }
            );
        }
        let passed = self.rows.iter().filter(|r| r.passed()).count();
        let _ = writeln!(s, "{passed}/{} functions within bounds", self.rows.len());
        let _ = write!(s, "{}", self.probe);
        for r in self.failures() {
            let _ =
                writeln!(s, "{} failed {} outputs; worst: {}", r.name, r.failures, r.worst.as_deref().unwrap_or("-"));
        }
        s
    }
}

/// The id of `case F_<NAME>` in parity.wgsl.
fn func_id(name: &str) -> Option<u32> {
    let key = format!("const F_{}: u32 = ", name.to_uppercase());
    let rest = &PARITY_WGSL[PARITY_WGSL.find(&key)? + key.len()..];
    rest[..rest.find('u')?].parse().ok()
}

// ---------------------------------------------------------------------------------------------
// Running and comparing
// ---------------------------------------------------------------------------------------------

/// The shader module and layouts shared by every function's pipeline.
struct Kernel<'a> {
    ctx: &'a GpuContext,
    module: wgpu::ShaderModule,
    bind_group_layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
}

/// Runs `f` inside a validation error scope and turns a captured error into [`GpuError::Wgpu`].
pub(crate) fn checked<T>(device: &wgpu::Device, f: impl FnOnce() -> T) -> Result<T, GpuError> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let value = f();
    match pollster::block_on(scope.pop()) {
        Some(e) => Err(GpuError::Wgpu(e.to_string())),
        None => Ok(value),
    }
}

impl<'a> Kernel<'a> {
    fn new(ctx: &'a GpuContext) -> Result<Self, GpuError> {
        let device = ctx.device();
        checked(device, || {
            let source = format!("{GGX_CORE_WGSL}\n{PARITY_WGSL}");
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("ggx parity"),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
            let storage = |binding, read_only| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            };
            let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("ggx parity"),
                entries: &[storage(0, true), storage(1, true), storage(2, false)],
            });
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("ggx parity"),
                bind_group_layouts: &[Some(&bind_group_layout)],
                immediate_size: 0,
            });
            Kernel { ctx, module, bind_group_layout, pipeline_layout }
        })
    }

    /// The pipeline specialised to one function through the `FUNC` override constant.
    fn pipeline(&self, func: u32) -> Result<wgpu::ComputePipeline, GpuError> {
        checked(self.ctx.device(), || {
            self.ctx.device().create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("ggx parity"),
                layout: Some(&self.pipeline_layout),
                module: &self.module,
                entry_point: Some("main"),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &[("FUNC", f64::from(func))],
                    ..Default::default()
                },
                cache: None,
            })
        })
    }

    /// Runs function `func` over the cases, `CHUNK` at a time; returns `OUT_WORDS` words per case.
    fn run(&self, func: u32, cases: &[Input], bsdfs: &[GgxConductor]) -> Result<Vec<u32>, GpuError> {
        let pipeline = self.pipeline(func)?;
        let mut out = Vec::with_capacity(cases.len() * OUT_WORDS);
        for (inputs, bsdfs) in cases.chunks(CHUNK).zip(bsdfs.chunks(CHUNK)) {
            out.extend(self.dispatch(&pipeline, inputs, bsdfs)?);
        }
        Ok(out)
    }

    fn dispatch(
        &self,
        pipeline: &wgpu::ComputePipeline,
        inputs: &[Input],
        bsdfs: &[GgxConductor],
    ) -> Result<Vec<u32>, GpuError> {
        let device = self.ctx.device();
        let size = (inputs.len() * OUT_WORDS * 4) as u64;
        let readback = checked(device, || {
            let buffer = |label, contents: &[u8]| {
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage: wgpu::BufferUsages::STORAGE,
                })
            };
            let input_buffer = buffer("parity inputs", bytemuck::cast_slice(inputs));
            let bsdf_buffer = buffer("parity bsdfs", bytemuck::cast_slice(bsdfs));
            let output = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("parity outputs"),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let readback = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("parity readback"),
                size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ggx parity"),
                layout: &self.bind_group_layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: input_buffer.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: bsdf_buffer.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 2, resource: output.as_entire_binding() },
                ],
            });
            let mut encoder =
                device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("ggx parity") });
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("ggx parity"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &bind_group, &[]);
                pass.dispatch_workgroups(inputs.len().div_ceil(WORKGROUP) as u32, 1, 1);
            }
            encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, size);
            self.ctx.queue().submit([encoder.finish()]);
            readback
        })?;
        let (tx, rx) = mpsc::channel();
        readback.slice(..).map_async(wgpu::MapMode::Read, move |result| {
            let _ = tx.send(result);
        });
        device.poll(wgpu::PollType::wait_indefinitely())?;
        rx.recv().map_err(|e| GpuError::Wgpu(e.to_string()))??;
        let view = readback.slice(..).get_mapped_range().map_err(|e| GpuError::Wgpu(e.to_string()))?;
        let words = bytemuck::cast_slice::<u8, u32>(&view).to_vec();
        drop(view);
        readback.unmap();
        Ok(words)
    }
}

/// Whether the GPU word `got` matches the expectation.
fn word_ok(bound: Bound, expect: Expect, got: u32) -> bool {
    match expect {
        Expect::Bits(c) => got == c,
        Expect::Float(c) => bound.accepts(f32::from_bits(got), c),
    }
}

/// Whether a float word is finite on both sides (bit words always are).
fn finite_word(expect: Expect, got: u32) -> bool {
    match expect {
        Expect::Bits(_) => true,
        Expect::Float(c) => c.is_finite() && f32::from_bits(got).is_finite(),
    }
}

/// Compares the GPU's words with the CPU's expectations.
fn compare(spec: &Spec, gpu: &[u32]) -> RowReport {
    let mut r = RowReport {
        name: spec.name,
        cases: spec.cases.len(),
        max_ulp: 0,
        max_rel: 0.0,
        max_abs: 0.0,
        bound: spec.bound,
        contract: spec.expect.iter().flatten().any(|e| matches!(e, Expect::Float(_))).then_some(spec.contract),
        failures: 0,
        nan: (0, 0),
        inf: (0, 0),
        worst: None,
    };
    let mut worst_ulp = 0;
    for (case, (expect, got)) in spec.expect.iter().zip(gpu.chunks(OUT_WORDS)).enumerate() {
        let mut failed = Vec::new();
        let (mut max_ulp, mut max_rel, mut max_abs) = (0, 0.0f64, 0.0f64);
        for (k, (&e, &g)) in expect.iter().zip(got).enumerate() {
            let ulp = match e {
                Expect::Bits(c) => u64::from(g != c) * u64::MAX,
                Expect::Float(c) => {
                    let gf = f32::from_bits(g);
                    r.nan.0 += gf.is_nan() as usize;
                    r.nan.1 += c.is_nan() as usize;
                    r.inf.0 += gf.is_infinite() as usize;
                    r.inf.1 += c.is_infinite() as usize;
                    if gf.is_finite() && c.is_finite() {
                        let abs = (f64::from(gf) - f64::from(c)).abs();
                        max_abs = max_abs.max(abs);
                        if c != 0.0 {
                            max_rel = max_rel.max(abs / f64::from(c).abs());
                        }
                    }
                    if gf.is_nan() != c.is_nan() {
                        u64::MAX
                    } else if gf.is_nan() {
                        0
                    } else {
                        ulp_distance(gf, c)
                    }
                }
            };
            max_ulp = max_ulp.max(ulp);
            if !word_ok(spec.bound, e, g) {
                failed.push((k, ulp));
            } else if spec.contract == Contract::Finite && !finite_word(e, g) {
                // Equal on both sides, but the contract excludes NaN and infinity.
                failed.push((k, u64::MAX));
            }
        }
        r.max_ulp = r.max_ulp.max(max_ulp);
        r.max_rel = r.max_rel.max(max_rel);
        r.max_abs = r.max_abs.max(max_abs);
        if failed.is_empty() {
            continue;
        }
        r.failures += failed.len();
        let &(k, ulp) = failed.iter().max_by_key(|(_, ulp)| *ulp).expect("not empty");
        if r.worst.is_none() || ulp > worst_ulp {
            worst_ulp = ulp;
            let (i, t) = (&spec.cases[case], &spec.bsdfs[case]);
            let expected = match expect[k] {
                Expect::Bits(c) => format!("{c:#010x}"),
                Expect::Float(c) => format!("{c:e} ({:#010x})", c.to_bits()),
            };
            let contract = if word_ok(spec.bound, expect[k], got[k]) { " (not finite)" } else { "" };
            r.worst = Some(format!(
                "case {case} word {k}: got {:e} ({:#010x}), expected {expected}{contract}; input a={:?} b={:?} c={:?} n={:?} m={:?}, alpha=({:e}, {:e}), fresnel kind {}",
                f32::from_bits(got[k]),
                got[k],
                i.a,
                i.b,
                i.c,
                i.n,
                i.m,
                t.distribution.alpha_x,
                t.distribution.alpha_y,
                t.fresnel.kind
            ));
        }
    }
    r
}

fn probe(kernel: &Kernel) -> Result<ProbeReport, GpuError> {
    let one_p = 1.0 + 1.0 / 4096.0;
    let input = Input {
        a: [NAN, 1.0, 0.0, -1.0],
        b: [f32::from_bits(1 << 13), 1e-20, one_p, -(1.0 + 1.0 / 2048.0)],
        ..Default::default()
    };
    let id = func_id("probe").expect("parity.wgsl defines F_PROBE");
    let w = kernel.run(id, &[input], &[GgxConductor::zeroed()])?;
    let f = |k: usize| f32::from_bits(w[k]);
    Ok(ProbeReport {
        nan_ne_self: w[0] == 1,
        not_gt_nan: w[1] == 1,
        max_nan_zero: f(2),
        min_nan_one: f(3),
        clamp_nan: f(4),
        one_over_zero: f(5),
        zero_over_zero: f(6),
        subnormal_input_kept: w[7] == 1 << 13,
        subnormal_result_kept: f(8) != 0.0,
        fma_contracted: f(9) != 0.0,
        sqrt_minus_one: f(10),
        is_nan_bits: w[11] == 1,
    })
}

/// Runs every function of `ggx_core.wgsl` on the context's adapter over the CPU-built input
/// tables and compares with ggx-core. Errors are GPU failures (shader compilation, device
/// loss); mismatches are reported in the [`ParityReport`].
pub fn run_parity(ctx: &GpuContext) -> Result<ParityReport, GpuError> {
    let kernel = Kernel::new(ctx)?;
    let rows = specs()
        .iter()
        .map(|spec| {
            let id = func_id(spec.name).expect("every row has a `case F_<NAME>` in parity.wgsl");
            Ok(compare(spec, &kernel.run(id, &spec.cases, &spec.bsdfs)?))
        })
        .collect::<Result<Vec<_>, GpuError>>()?;
    Ok(ParityReport { adapter: ctx.describe(), rows, probe: probe(&kernel)? })
}

#[cfg(test)]
mod tests {
    use super::cases::INF;
    use super::*;

    #[test]
    fn every_row_has_a_kernel_case() {
        let specs = specs();
        for spec in &specs {
            let id = func_id(spec.name).unwrap_or_else(|| panic!("no F_{} in parity.wgsl", spec.name.to_uppercase()));
            assert!(spec.expect.iter().all(|e| e.len() <= OUT_WORDS), "{}", spec.name);
            assert!(!spec.cases.is_empty(), "{} (id {id}) has no cases", spec.name);
        }
        let mut ids: Vec<u32> = specs.iter().map(|s| func_id(s.name).unwrap()).collect();
        ids.sort_unstable();
        ids.dedup();
        assert_eq!(ids.len(), specs.len(), "ids are unique");
    }

    #[test]
    fn finite_contract_rejects_nan_and_inf_on_either_side() {
        let spec = |contract, cpu: f32| Spec {
            name: "test",
            bound: Bound::EXACT,
            contract,
            cases: vec![Input::default()],
            bsdfs: vec![GgxConductor::zeroed()],
            expect: vec![vec![Expect::Float(cpu), Expect::Bits(7)]],
        };
        let gpu = |x: f32| [x.to_bits(), 7].into_iter().chain([0; OUT_WORDS - 2]).collect::<Vec<u32>>();
        for x in [NAN, INF, -INF] {
            // Both sides agree: fine for an IEEE row, a broken promise for a finite one.
            let ieee = compare(&spec(Contract::Ieee, x), &gpu(x));
            assert!(ieee.passed() && ieee.failures == 0, "{x}");
            let finite = compare(&spec(Contract::Finite, x), &gpu(x));
            assert!(!finite.passed() && finite.failures == 1, "{x}");
            assert!(finite.worst.as_deref().unwrap().contains("(not finite)"), "{:?}", finite.worst);
            // Only the GPU leaves the contract.
            assert!(!compare(&spec(Contract::Finite, 0.0), &gpu(x)).passed(), "{x}");
        }
        let ok = compare(&spec(Contract::Finite, 0.5), &gpu(0.5));
        assert!(ok.passed() && ok.contract == Some(Contract::Finite));
        let bits = Spec { expect: vec![vec![Expect::Bits(NAN.to_bits())]], ..spec(Contract::Finite, 0.0) };
        let bits = compare(&bits, &gpu(NAN));
        assert!(bits.passed() && bits.contract.is_none(), "bit rows carry no float contract");
    }

    #[test]
    fn ulp_distance_and_bounds() {
        assert_eq!(ulp_distance(1.0, 1.0), 0);
        assert_eq!(ulp_distance(0.0, -0.0), 0);
        assert_eq!(ulp_distance(1.0, f32::from_bits(1.0f32.to_bits() + 3)), 3);
        assert_eq!(ulp_distance(f32::from_bits(1), -f32::from_bits(1)), 2);
        assert!(Bound::EXACT.accepts(NAN, NAN));
        assert!(!Bound::ulps(100).accepts(NAN, 1.0));
        assert!(!Bound::ulps(100).accepts(f32::MAX, INF));
        assert!(Bound::mixed(0, 1e-6).accepts(1e-7, 0.0));
        assert!(!Bound::ulps(4).accepts(1.0, 1.001));
        assert!(Bound::EXACT.accepts(0.0, 1e-40), "flushed subnormal");
        assert!(!Bound::EXACT.accepts(0.0, f32::MIN_POSITIVE));
    }
}
