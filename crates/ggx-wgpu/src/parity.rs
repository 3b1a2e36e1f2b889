//! The parity harness: every function of `ggx_core.wgsl` and `energy.wgsl` that mirrors a
//! ggx-core function runs on the GPU over input tables built here, and its outputs are compared
//! with ggx-core on the CPU word by word, each group of output words (a direction, a colour, a
//! pdf, flags) under its own [`Bound`] and [`Contract`]. The kernel reads energy.wgsl's tables
//! from a binding that holds [`crate::scene_upload::energy_tables`], the data ggx-core reads.

use std::fmt::{self, Write as _};
use std::ops::Range;
use std::sync::mpsc;

use bytemuck::Zeroable as _;
use ggx_core::{GgxConductor, GgxDielectric};
use wgpu::util::DeviceExt as _;

use crate::{ENERGY_WGSL, GGX_CORE_WGSL, GpuContext, GpuError, PARITY_WGSL};

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

/// Tolerance for one output word. Integer words (flags, sequences, layout) are always held to
/// [`Bound::Exact`]: the same bits. A float word `g` from the GPU matches ggx-core's `c` when
/// both are NaN, or both are the same infinity, or both are finite and within the bound, or
/// `|g - c| < f32::MIN_POSITIVE` (Vulkan lets an adapter flush subnormals).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bound {
    /// Bit-identical (up to the sign of zero, the NaN payload and flushed subnormals).
    Exact,
    /// At most this many units in the last place apart: a relative bound (one ulp is 2^-24 to
    /// 2^-23 of the value) with no absolute escape, for values of any magnitude.
    Ulps(u64),
    /// At most `.0` ulps apart or at most `.1` apart: for unit vectors and values in [-1, 1]
    /// whose small components come out of a cancellation, where only the absolute error is
    /// meaningful.
    UlpsOrAbs(u64, f32),
}

impl Bound {
    /// Whether the float `gpu` matches ggx-core's `cpu`.
    pub fn accepts(&self, gpu: f32, cpu: f32) -> bool {
        if gpu.is_nan() || cpu.is_nan() {
            return gpu.is_nan() && cpu.is_nan();
        }
        if gpu.is_infinite() || cpu.is_infinite() {
            return gpu == cpu;
        }
        let diff = (gpu - cpu).abs();
        let ulps = ulp_distance(gpu, cpu);
        diff < f32::MIN_POSITIVE
            || match *self {
                Bound::Exact => ulps == 0,
                Bound::Ulps(n) => ulps <= n,
                Bound::UlpsOrAbs(n, abs) => ulps <= n || diff <= abs,
            }
    }
}

impl fmt::Display for Bound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Bound::Exact => write!(f, "exact"),
            Bound::Ulps(n) => write!(f, "{n} ulp"),
            Bound::UlpsOrAbs(n, abs) => write!(f, "{n} ulp|{abs:.0e} abs"),
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

/// A case behind a maximum or a failure, for the log.
#[derive(Clone, Debug, PartialEq)]
pub struct Witness {
    /// Index of the case in the row's input table.
    pub case: usize,
    /// Index of the output word.
    pub word: usize,
    /// The word's name, the inputs and every output word of the case on both sides.
    pub text: String,
}

/// How far one group of output words of a function (a direction, a colour, a pdf, flags) was
/// from ggx-core, against its own bound.
#[derive(Clone, Debug)]
pub struct GroupReport {
    /// The words' name (`wi`, `pdf`, `value`).
    pub name: &'static str,
    /// Which output words.
    pub words: Range<usize>,
    /// The tolerance the words are held to.
    pub bound: Bound,
    /// A separately named bound for the cases its predicate selects (`ggx_dielectric_sample`'s
    /// refracted directions): its name, its bound, what it is for and how many cases it covered.
    pub special: Option<(&'static str, Bound, &'static str, usize)>,
    /// What ggx-core promises about the words; `None` for words compared bit for bit as
    /// integers (flags, sequences, layout).
    pub contract: Option<Contract>,
    /// Largest ULP distance (`u64::MAX` for a NaN mismatch or an integer word that differs).
    pub max_ulp: u64,
    /// Largest relative error `|g - c| / |c|` over finite, non-zero CPU values.
    pub max_rel: f64,
    /// Largest absolute error over finite values.
    pub max_abs: f64,
    /// The cases behind `max_ulp`, `max_rel` and `max_abs` (`None` while the maximum is 0).
    pub at_max: [Option<Witness>; 3],
    /// Words outside the bound (or integer words that differ), plus, under
    /// [`Contract::Finite`], words that are NaN or infinite on either side.
    pub failures: usize,
    /// The worst failing word (largest ULP distance).
    pub worst: Option<Witness>,
    /// NaN words on the GPU and on the CPU.
    pub nan: (usize, usize),
    /// Infinite words on the GPU and on the CPU.
    pub inf: (usize, usize),
}

impl GroupReport {
    fn new(name: &'static str, words: Range<usize>, bound: Bound, contract: Option<Contract>) -> Self {
        GroupReport {
            name,
            words,
            bound,
            special: None,
            contract,
            max_ulp: 0,
            max_rel: 0.0,
            max_abs: 0.0,
            at_max: [None, None, None],
            failures: 0,
            worst: None,
            nan: (0, 0),
            inf: (0, 0),
        }
    }

    /// No failure, no NaN where ggx-core has none, and under [`Contract::Finite`] no NaN or
    /// infinity at all.
    pub fn passed(&self) -> bool {
        let finite = self.nan == (0, 0) && self.inf == (0, 0);
        self.failures == 0 && self.nan.0 <= self.nan.1 && (finite || self.contract != Some(Contract::Finite))
    }
}

/// Result of one function: how far each group of its output words was from ggx-core.
#[derive(Clone, Debug)]
pub struct RowReport {
    /// WGSL function name (the ggx-core function it mirrors has the same name).
    pub name: &'static str,
    /// Number of input cases.
    pub cases: usize,
    /// One report per group of output words, in word order.
    pub groups: Vec<GroupReport>,
    /// Cases whose later words were compared with ggx-core's at the GPU's intermediate result
    /// (`ggx_conductor_sample`, `ggx_dielectric_sample`: weight and pdf at the GPU's `wi` where
    /// it differs from ggx-core's).
    pub rebased: usize,
    /// Which words a rebased case compares with ggx-core at the GPU's intermediate result.
    pub rebase_note: Option<&'static str>,
}

impl RowReport {
    /// Every group passed.
    pub fn passed(&self) -> bool {
        self.groups.iter().all(GroupReport::passed)
    }

    /// Words outside their bound or contract, over every group.
    pub fn failures(&self) -> usize {
        self.groups.iter().map(|g| g.failures).sum()
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

    /// The report as a text table: one line per group of output words (the function's name on
    /// the first), and under each function the case behind every non-zero maximum (`ulp`,
    /// `rel`, `abs`: inputs, the GPU's and ggx-core's outputs); then the adapter probe and
    /// the worst case of every failing group.
    pub fn table(&self) -> String {
        let mut s = format!("parity of ggx_core.wgsl and energy.wgsl against ggx-core on {}\n", self.adapter);
        let _ = writeln!(
            s,
            "{:<36} {:>7} {:<16} {:>10} {:>9} {:>9} {:<16} {:<8} {:>7} {:>7}  result",
            "function", "cases", "words", "max ulp", "max rel", "max abs", "bound", "contract", "nan g/c", "inf g/c"
        );
        for r in &self.rows {
            for (i, g) in r.groups.iter().enumerate() {
                let (name, cases) = if i == 0 { (r.name, r.cases.to_string()) } else { ("", String::new()) };
                let ulp = if g.max_ulp == u64::MAX { "inf".to_string() } else { g.max_ulp.to_string() };
                let (bound, contract) = match g.contract {
                    Some(c) => (g.bound.to_string(), c.to_string()),
                    None => ("exact".to_string(), "bits".to_string()),
                };
                let _ = writeln!(
                    s,
                    "{name:<36} {cases:>7} {:<16} {ulp:>10} {:>9.2e} {:>9.2e} {bound:<16} {contract:<8} {:>7} {:>7}  {}",
                    g.name,
                    g.max_rel,
                    g.max_abs,
                    format!("{}/{}", g.nan.0, g.nan.1),
                    format!("{}/{}", g.inf.0, g.inf.1),
                    if g.passed() { "pass" } else { "FAIL" }
                );
            }
            if r.rebased > 0 {
                let what = r.rebase_note.unwrap_or("-");
                let _ = writeln!(s, "    {} cases rebased ({what})", r.rebased);
            }
            for g in &r.groups {
                if let Some((name, bound, what, cases)) = g.special {
                    let _ = writeln!(s, "    {} under {name} ({bound}) in {cases} cases: {what}", g.name);
                }
            }
            for g in &r.groups {
                // One line per distinct case: the maxima it is behind.
                let mut lines: Vec<(Vec<&str>, &Witness)> = Vec::new();
                for (what, w) in ["ulp", "rel", "abs"].into_iter().zip(&g.at_max) {
                    let Some(w) = w else { continue };
                    match lines.iter_mut().find(|(_, x)| x.case == w.case && x.word == w.word) {
                        Some((whats, _)) => whats.push(what),
                        None => lines.push((vec![what], w)),
                    }
                }
                for (whats, w) in lines {
                    let _ = writeln!(s, "    max {}: {}", whats.join(","), w.text);
                }
            }
        }
        let passed = self.rows.iter().filter(|r| r.passed()).count();
        let _ = writeln!(s, "{passed}/{} functions within bounds", self.rows.len());
        let _ = write!(s, "{}", self.probe);
        for r in self.failures() {
            for g in r.groups.iter().filter(|g| !g.passed()) {
                let worst = g.worst.as_ref().map_or("-", |w| w.text.as_str());
                let _ = writeln!(s, "{} {} failed {} words; worst: {worst}", r.name, g.name, g.failures);
            }
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

/// The kernel's WGSL with every arm: [`GGX_CORE_WGSL`], [`ENERGY_WGSL`] and [`PARITY_WGSL`], in
/// that order. Each pipeline compiles it with one arm left ([`row_source`]); a test validates
/// both.
#[cfg(test)]
pub(crate) fn parity_source() -> String {
    format!("{GGX_CORE_WGSL}\n{ENERGY_WGSL}\n{PARITY_WGSL}")
}

/// What every pipeline compiles: the [`row_source`] of each function of parity.wgsl (each
/// `const F_<NAME>`), by name.
#[cfg(test)]
pub(crate) fn kernel_sources() -> Vec<(String, String)> {
    let names = PARITY_WGSL.lines().filter_map(|l| Some(l.strip_prefix("const F_")?.split(':').next()?.to_lowercase()));
    names.map(|n| (n.clone(), row_source(&n).unwrap_or_else(|| panic!("no case F_{}", n.to_uppercase())))).collect()
}

/// What the pipeline of function `name` compiles: [`GGX_CORE_WGSL`], [`ENERGY_WGSL`] and
/// [`PARITY_WGSL`] with only the arms `case F_<NAME>` and `default` left in the kernel's
/// `switch FUNC` (and the comments between arms dropped). A driver inlines every arm's call
/// graph before it folds the switch on the pipeline constant: with all arms llvmpipe spent
/// about 0.7 s on each row's pipeline (a minute for the table), with one about 10 ms. `None`
/// when parity.wgsl has no such arm.
fn row_source(name: &str) -> Option<String> {
    let arm = format!("        case F_{}: {{", name.to_uppercase());
    let mut kept = String::new();
    let (mut in_switch, mut keep, mut found) = (false, true, false);
    for line in PARITY_WGSL.lines() {
        if line == "    switch FUNC {" {
            in_switch = true;
        } else if in_switch && line == "    }" {
            in_switch = false;
            keep = true;
        } else if in_switch && line.starts_with("        ") && !line.starts_with("         ") {
            // An arm's first or last line, or a comment between arms.
            if line.starts_with("        case ") || line.starts_with("        default") {
                keep = line == arm || line == "        default: {";
                found |= line == arm;
            } else if line != "        }" {
                continue;
            }
        }
        if keep {
            kept.push_str(line);
            kept.push('\n');
        }
    }
    found.then(|| format!("{GGX_CORE_WGSL}\n{ENERGY_WGSL}\n{kept}"))
}

/// ggx-core's energy-compensation tables concatenated in the order energy.wgsl reads them
/// (binding 4, `energy_table` in parity.wgsl).
fn energy_values() -> Vec<f32> {
    crate::scene_upload::energy_tables().concat()
}

/// The layouts and the energy tables shared by every function's pipeline.
struct Kernel<'a> {
    ctx: &'a GpuContext,
    bind_group_layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    /// [`energy_values`], uploaded once.
    energy: wgpu::Buffer,
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
                entries: &[storage(0, true), storage(1, true), storage(2, false), storage(3, true), storage(4, true)],
            });
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("ggx parity"),
                bind_group_layouts: &[Some(&bind_group_layout)],
                immediate_size: 0,
            });
            let energy = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("parity energy tables"),
                contents: bytemuck::cast_slice(&energy_values()),
                usage: wgpu::BufferUsages::STORAGE,
            });
            Kernel { ctx, bind_group_layout, pipeline_layout, energy }
        })
    }

    /// The pipeline of function `name`: [`row_source`], specialised through the `FUNC`
    /// override constant.
    fn pipeline(&self, name: &str) -> Result<wgpu::ComputePipeline, GpuError> {
        let func = func_id(name).unwrap_or_else(|| panic!("no F_{} in parity.wgsl", name.to_uppercase()));
        let source = row_source(name).unwrap_or_else(|| panic!("no case F_{} in parity.wgsl", name.to_uppercase()));
        let device = self.ctx.device();
        checked(device, || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("ggx parity"),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("ggx parity"),
                layout: Some(&self.pipeline_layout),
                module: &module,
                entry_point: Some("main"),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &[("FUNC", f64::from(func))],
                    ..Default::default()
                },
                cache: None,
            })
        })
    }

    /// Runs function `name` over the cases (each with its conductor and its dielectric),
    /// `CHUNK` at a time; returns `OUT_WORDS` words per case.
    fn run(
        &self,
        name: &str,
        cases: &[Input],
        bsdfs: &[GgxConductor],
        dielectrics: &[GgxDielectric],
    ) -> Result<Vec<u32>, GpuError> {
        let pipeline = self.pipeline(name)?;
        let mut out = Vec::with_capacity(cases.len() * OUT_WORDS);
        let chunks = cases.chunks(CHUNK).zip(bsdfs.chunks(CHUNK)).zip(dielectrics.chunks(CHUNK));
        for ((inputs, bsdfs), dielectrics) in chunks {
            out.extend(self.dispatch(&pipeline, inputs, bsdfs, dielectrics)?);
        }
        Ok(out)
    }

    fn dispatch(
        &self,
        pipeline: &wgpu::ComputePipeline,
        inputs: &[Input],
        bsdfs: &[GgxConductor],
        dielectrics: &[GgxDielectric],
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
            let dielectric_buffer = buffer("parity dielectrics", bytemuck::cast_slice(dielectrics));
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
                    wgpu::BindGroupEntry { binding: 3, resource: dielectric_buffer.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 4, resource: self.energy.as_entire_binding() },
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

/// How one GPU word compares with ggx-core's.
#[derive(Clone, Copy, Debug, PartialEq)]
struct WordCheck {
    /// ULP distance (`u64::MAX` for a NaN on one side only or an integer word that differs).
    ulp: u64,
    /// Absolute error, when both sides are finite floats.
    abs: Option<f64>,
    /// Relative error, when both sides are finite floats and ggx-core's is not zero.
    rel: Option<f64>,
    /// Within the bound (integer words: the same bits).
    within: bool,
    /// Both sides finite (integer words always are).
    finite: bool,
}

/// Compares the GPU word `got` with the expectation under `bound`.
fn check_word(bound: Bound, expect: Expect, got: u32) -> WordCheck {
    match expect {
        Expect::Bits(c) => {
            WordCheck { ulp: u64::from(got != c) * u64::MAX, abs: None, rel: None, within: got == c, finite: true }
        }
        Expect::Float(c) => {
            let g = f32::from_bits(got);
            let both_finite = g.is_finite() && c.is_finite();
            let abs = both_finite.then(|| (f64::from(g) - f64::from(c)).abs());
            let ulp = match (g.is_nan(), c.is_nan()) {
                (true, true) => 0,
                (false, false) => ulp_distance(g, c),
                _ => u64::MAX,
            };
            WordCheck {
                ulp,
                abs,
                rel: abs.filter(|_| c != 0.0).map(|a| a / f64::from(c).abs()),
                within: bound.accepts(g, c),
                finite: both_finite,
            }
        }
    }
}

/// The name of output word `k` in its group (`pdf`, `wi[2]`).
fn word_name(spec: &Spec, k: usize) -> String {
    let mut start = 0;
    for g in &spec.groups {
        if k < start + g.words {
            return if g.words == 1 { g.name.to_string() } else { format!("{}[{}]", g.name, k - start) };
        }
        start += g.words;
    }
    format!("word {k}")
}

/// A word for the log: floats in Rust's shortest round-trip form, integers in decimal up to
/// 2^16 and in hex above.
fn show_word(e: Expect, got: Option<u32>) -> String {
    match (e, got) {
        (Expect::Float(c), None) => format!("{c:?}"),
        (Expect::Float(_), Some(g)) => format!("{:?}", f32::from_bits(g)),
        (Expect::Bits(c), g) => {
            let w = g.unwrap_or(c);
            if w < 1 << 16 { w.to_string() } else { format!("{w:#010x}") }
        }
    }
}

/// The log line of case `case`, word `k`: the word, the non-zero inputs, then every output word
/// on the GPU and in ggx-core.
fn witness(spec: &Spec, case: usize, k: usize, got: &[u32], expect: &[Expect], note: &str) -> Witness {
    let (i, t, g) = (&spec.cases[case], &spec.bsdfs[case], &spec.dielectrics[case]);
    let mut inputs = Vec::new();
    for (name, v) in [("a", i.a), ("b", i.b), ("c", i.c)] {
        if v.iter().any(|x| x.to_bits() != 0) {
            inputs.push(format!("{name}={v:?}"));
        }
    }
    for (name, v) in [("n", i.n), ("m", i.m)] {
        if v.iter().any(|&x| x != 0) {
            inputs.push(format!("{name}={v:?}"));
        }
    }
    if bytemuck::bytes_of(t).iter().any(|&b| b != 0) {
        let d = t.distribution;
        inputs.push(format!("alpha=({:?}, {:?}) fresnel kind {}", d.alpha_x, d.alpha_y, t.fresnel.kind));
    }
    if bytemuck::bytes_of(g).iter().any(|&b| b != 0) {
        let d = g.distribution;
        inputs.push(format!("dielectric alpha=({:?}, {:?}) eta={:?}", d.alpha_x, d.alpha_y, g.eta));
    }
    let list =
        |f: &dyn Fn(usize, Expect) -> String| expect.iter().enumerate().map(|(k, &e)| f(k, e)).collect::<Vec<_>>();
    let gpu = list(&|k, e| show_word(e, Some(got[k])));
    let cpu = list(&|_, e| show_word(e, None));
    Witness {
        case,
        word: k,
        text: format!(
            "{} case {case}{note}: in {}; gpu [{}] cpu [{}]",
            word_name(spec, k),
            if inputs.is_empty() { "-".to_string() } else { inputs.join(" ") },
            gpu.join(", "),
            cpu.join(", ")
        ),
    }
}

/// Compares the GPU's words with the CPU's expectations, word by word under each group's bound.
fn compare(spec: &Spec, gpu: &[u32]) -> RowReport {
    let mut start = 0;
    let mut groups: Vec<GroupReport> = spec
        .groups
        .iter()
        .map(|g| {
            start += g.words;
            let mut report = GroupReport::new(g.name, start - g.words..start, g.bound, g.contract);
            report.special = g.special.map(|sp| (sp.name, sp.bound, sp.what, 0));
            report
        })
        .collect();
    // (case, word) behind each maximum and the worst failure, turned into log lines at the end.
    let mut at = vec![[None::<(usize, usize)>; 4]; groups.len()];
    let mut worst_ulp = vec![0; groups.len()];
    let mut rebased = 0;
    for (case, (expect, got)) in spec.expect.iter().zip(gpu.chunks(OUT_WORDS)).enumerate() {
        let alt = expected(spec, case, got);
        rebased += alt.is_some() as usize;
        let expect = alt.as_deref().unwrap_or(expect);
        for (j, g) in groups.iter_mut().enumerate() {
            let bound = case_bound(spec, j, case, expect);
            if let (true, Some(sp)) = (bound.1, g.special.as_mut()) {
                sp.3 += 1;
            }
            for k in g.words.clone() {
                let (e, w) = (expect[k], got[k]);
                let c = check_word(bound.0, e, w);
                if let Expect::Float(cpu) = e {
                    let gf = f32::from_bits(w);
                    g.nan.0 += gf.is_nan() as usize;
                    g.nan.1 += cpu.is_nan() as usize;
                    g.inf.0 += gf.is_infinite() as usize;
                    g.inf.1 += cpu.is_infinite() as usize;
                }
                if c.ulp > g.max_ulp {
                    g.max_ulp = c.ulp;
                    at[j][0] = Some((case, k));
                }
                if let Some(rel) = c.rel.filter(|&r| r > g.max_rel) {
                    g.max_rel = rel;
                    at[j][1] = Some((case, k));
                }
                if let Some(abs) = c.abs.filter(|&a| a > g.max_abs) {
                    g.max_abs = abs;
                    at[j][2] = Some((case, k));
                }
                // Under the finite contract a NaN or infinity fails even where both sides agree.
                let failed = !c.within || (g.contract == Some(Contract::Finite) && !c.finite);
                if failed {
                    g.failures += 1;
                    let ulp = if c.within { u64::MAX } else { c.ulp };
                    if at[j][3].is_none() || ulp > worst_ulp[j] {
                        worst_ulp[j] = ulp;
                        at[j][3] = Some((case, k));
                    }
                }
            }
        }
    }
    for (j, (g, at)) in groups.iter_mut().zip(at).enumerate() {
        let log = |(case, k): (usize, usize)| {
            let got = &gpu[case * OUT_WORDS..][..OUT_WORDS];
            let alt = expected(spec, case, got);
            let expect = alt.as_deref().unwrap_or(&spec.expect[case]);
            let (bound, special) = case_bound(spec, j, case, expect);
            let not_finite = matches!(expect[k], Expect::Float(_)) && check_word(bound, expect[k], got[k]).within;
            let mut note = String::new();
            if let (Some(_), Some((_, what))) = (&alt, spec.rebase) {
                let _ = write!(note, " ({what})");
            }
            if let (true, Some(sp)) = (special, g.special) {
                let _ = write!(note, " (under {})", sp.0);
            }
            if not_finite && at[3] == Some((case, k)) {
                note.push_str(" (not finite)");
            }
            witness(spec, case, k, got, expect, &note)
        };
        g.at_max = [at[0].map(log), at[1].map(log), at[2].map(log)];
        g.worst = at[3].map(log);
    }
    RowReport { name: spec.name, cases: spec.cases.len(), groups, rebased, rebase_note: spec.rebase.map(|r| r.1) }
}

/// The bound of group `group` in case `case`: the group's special bound where its predicate
/// selects the case (and `true`), else the group's own bound.
fn case_bound(spec: &Spec, group: usize, case: usize, expect: &[Expect]) -> (Bound, bool) {
    let g = &spec.groups[group];
    match g.special {
        Some(sp) if (sp.applies)(&spec.cases[case], expect) => (sp.bound, true),
        _ => (g.bound, false),
    }
}

/// ggx-core's words at the GPU's intermediate result for case `case`, where the row rebases
/// and the GPU's intermediate result differs ([`Spec::rebase`]).
fn expected(spec: &Spec, case: usize, got: &[u32]) -> Option<Vec<Expect>> {
    spec.rebase
        .and_then(|(f, _)| f(&spec.cases[case], &spec.bsdfs[case], &spec.dielectrics[case], got, &spec.expect[case]))
}

fn probe(kernel: &Kernel) -> Result<ProbeReport, GpuError> {
    let one_p = 1.0 + 1.0 / 4096.0;
    let input = Input {
        a: [NAN, 1.0, 0.0, -1.0],
        b: [f32::from_bits(1 << 13), 1e-20, one_p, -(1.0 + 1.0 / 2048.0)],
        ..Default::default()
    };
    let w = kernel.run("probe", &[input], &[GgxConductor::zeroed()], &[GgxDielectric::zeroed()])?;
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

/// Runs every function of `ggx_core.wgsl` and `energy.wgsl` on the context's adapter over the
/// CPU-built input tables and compares with ggx-core. Errors are GPU failures (shader
/// compilation, device loss); mismatches are reported in the [`ParityReport`].
pub fn run_parity(ctx: &GpuContext) -> Result<ParityReport, GpuError> {
    let kernel = Kernel::new(ctx)?;
    let rows = specs()
        .iter()
        .map(|spec| Ok(compare(spec, &kernel.run(spec.name, &spec.cases, &spec.bsdfs, &spec.dielectrics)?)))
        .collect::<Result<Vec<_>, GpuError>>()?;
    Ok(ParityReport { adapter: ctx.describe(), rows, probe: probe(&kernel)? })
}

#[cfg(test)]
mod tests {
    use super::cases::{Group, INF, SAMPLE_GROUPS};
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
    fn each_pipeline_compiles_one_arm_of_the_switch() {
        let sources = kernel_sources();
        assert_eq!(sources.len(), PARITY_WGSL.matches("\n        case F_").count(), "a source per arm");
        let prefix = format!("{GGX_CORE_WGSL}\n{ENERGY_WGSL}\n");
        let all: Vec<&str> = PARITY_WGSL.lines().collect();
        for (name, source) in &sources {
            let parity = source.strip_prefix(&prefix).expect("ggx_core.wgsl and energy.wgsl in front");
            let arms: Vec<&str> = parity.lines().filter(|l| l.trim_start().starts_with("case F_")).collect();
            assert_eq!(arms, [format!("        case F_{}: {{", name.to_uppercase())], "{name}");
            assert!(parity.contains("\n        default: {\n"), "{name}");
            // The kept lines are parity.wgsl's, in order: whole arms are left out, nothing else.
            let mut rest = all.iter();
            for line in parity.lines() {
                assert!(rest.any(|l| *l == line), "{name}: {line:?} out of order or not in parity.wgsl");
            }
            let (kept, total) = (parity.lines().count(), all.len());
            let left_out = total - kept;
            let arm_lines = |n: &str| {
                let start = all.iter().position(|l| *l == format!("        case F_{}: {{", n.to_uppercase())).unwrap();
                all[start..].iter().position(|l| *l == "        }").unwrap() + 1
            };
            let other_arms: usize = sources.iter().filter(|(n, _)| n != name).map(|(n, _)| arm_lines(n)).sum();
            let comments = all.iter().filter(|l| l.starts_with("        //")).count();
            assert_eq!(left_out, other_arms + comments, "{name}: the other arms and the comments between them");
        }
        assert_eq!(row_source("no_such_function"), None);
        let sample = row_source("ggx_conductor_ms_sample").unwrap();
        assert!(
            sample
                .contains("put_sample(ggx_conductor_ms_sample(conductor_ms(p, bsdf), p.a.xyz, p.b.xy, p.b.z, p.n.x));")
        );
        assert!(!sample.contains("put_sample(ggx_conductor_sample("));
    }

    #[test]
    fn groups_cover_every_word_with_its_kind() {
        for spec in &specs() {
            let words: usize = spec.groups.iter().map(|g| g.words).sum();
            let kinds: Vec<bool> = spec.groups.iter().flat_map(|g| vec![g.contract.is_none(); g.words]).collect();
            for expect in &spec.expect {
                assert_eq!(expect.len(), words, "{}: groups cover every output word", spec.name);
                for (k, (e, &bits)) in expect.iter().zip(&kinds).enumerate() {
                    assert_eq!(
                        matches!(e, Expect::Bits(_)),
                        bits,
                        "{} word {k}: integer words in bits groups",
                        spec.name
                    );
                }
            }
        }
    }

    /// A one-case row with the given groups, ggx-core's words `cpu` and no rebase.
    fn one_case(groups: &[Group], cpu: Vec<Expect>) -> Spec {
        Spec {
            name: "test",
            groups: groups.to_vec(),
            cases: vec![Input::default()],
            bsdfs: vec![GgxConductor::zeroed()],
            dielectrics: vec![GgxDielectric::zeroed()],
            expect: vec![cpu],
            rebase: None,
        }
    }

    fn padded(words: &[u32]) -> Vec<u32> {
        words.iter().copied().chain(std::iter::repeat(0)).take(OUT_WORDS).collect()
    }

    #[test]
    fn finite_contract_rejects_nan_and_inf_on_either_side() {
        let spec = |contract, cpu: f32| {
            let value = Group { contract: Some(contract), ..Group::value(Bound::Exact) };
            one_case(&[value, Group::bits("flag", 1)], vec![Expect::Float(cpu), Expect::Bits(7)])
        };
        let gpu = |x: f32| padded(&[x.to_bits(), 7]);
        for x in [NAN, INF, -INF] {
            // Both sides agree: fine for an IEEE row, a broken promise for a finite one.
            let ieee = compare(&spec(Contract::Ieee, x), &gpu(x));
            assert!(ieee.passed() && ieee.failures() == 0, "{x}");
            let finite = compare(&spec(Contract::Finite, x), &gpu(x));
            assert!(!finite.passed() && finite.failures() == 1, "{x}");
            let worst = finite.groups[0].worst.as_ref().map(|w| w.text.as_str());
            assert!(worst.unwrap().contains("(not finite)"), "{worst:?}");
            assert!(finite.groups[1].passed(), "the flag group has no float contract");
            // Only the GPU leaves the contract.
            assert!(!compare(&spec(Contract::Finite, 0.0), &gpu(x)).passed(), "{x}");
        }
        let ok = compare(&spec(Contract::Finite, 0.5), &gpu(0.5));
        assert!(ok.passed() && ok.groups[0].contract == Some(Contract::Finite));
        let bits = compare(&one_case(&[Group::bits("word", 1)], vec![Expect::Bits(NAN.to_bits())]), &gpu(NAN));
        assert!(bits.passed() && bits.groups[0].contract.is_none(), "bit rows carry no float contract");
        let flag = compare(&spec(Contract::Finite, 0.5), &padded(&[0.5f32.to_bits(), 8]));
        assert!(!flag.passed() && flag.groups[1].max_ulp == u64::MAX, "an integer word that differs fails");
    }

    /// ggx-core's `ggx_conductor_sample` words: valid, not delta, `wi`, `weight`, `pdf`.
    fn sample_expect(wi: [f32; 3], weight: [f32; 3], pdf: f32) -> Vec<Expect> {
        let floats = wi.into_iter().chain(weight).chain([pdf]).map(Expect::Float);
        [Expect::Bits(1), Expect::Bits(0)].into_iter().chain(floats).collect()
    }

    fn sample_gpu(wi: [f32; 3], weight: [f32; 3], pdf: f32) -> Vec<u32> {
        let floats = wi.into_iter().chain(weight).chain([pdf]).map(f32::to_bits);
        padded(&[1, 0].into_iter().chain(floats).collect::<Vec<_>>())
    }

    #[test]
    fn sample_pdf_and_weight_have_no_absolute_escape() {
        // The old rule: every float word of the row under the unit-vector bound.
        let old = [Group::bits("valid,delta", 2), Group::float("all", 7, Bound::UlpsOrAbs(16, 1.0 / 1_048_576.0))];
        let wi = [0.6, 0.0, 0.8];
        let (weight, pdf) = ([0.25, 0.5, 1e-8], 5e-7f32);
        let cpu = sample_expect(wi, weight, pdf);

        // A pdf below 1e-6 off by 1e-3 relative.
        let gpu = sample_gpu(wi, weight, pdf * 1.001);
        assert!(compare(&one_case(&old, cpu.clone()), &gpu).passed(), "the old rule let it through");
        let new = compare(&one_case(&SAMPLE_GROUPS, cpu.clone()), &gpu);
        assert!(!new.passed() && new.failures() == 1);
        let pdf_group = new.groups.iter().find(|g| g.name == "pdf").unwrap();
        assert_eq!(pdf_group.failures, 1);
        assert!(pdf_group.worst.as_ref().unwrap().text.starts_with("pdf case 0"), "{:?}", pdf_group.worst);
        assert!((pdf_group.max_rel - 1e-3).abs() < 1e-5, "{}", pdf_group.max_rel);

        // A weight of 1e-8 off by 1e-3 relative.
        let gpu = sample_gpu(wi, [0.25, 0.5, 1e-8 * 1.001], pdf);
        assert!(compare(&one_case(&old, cpu.clone()), &gpu).passed(), "the old rule let it through");
        let new = compare(&one_case(&SAMPLE_GROUPS, cpu.clone()), &gpu);
        assert!(!new.passed() && new.groups[2].failures == 1, "weight[2] fails");
        assert!(new.groups[2].worst.as_ref().unwrap().text.starts_with("weight[2] case 0"));

        // The direction keeps the unit-vector bound: 4e-7 absolute on a component passes.
        let gpu = sample_gpu([0.6, 4e-7, 0.8], weight, pdf);
        assert!(compare(&one_case(&SAMPLE_GROUPS, cpu.clone()), &gpu).passed());
        // Sixteen ulp on a weight pass, seventeen fail; likewise the pdf.
        let ulps = |x: f32, n: u32| f32::from_bits(x.to_bits() + n);
        let gpu = sample_gpu(wi, [0.25, ulps(0.5, 16), 1e-8], ulps(pdf, 16));
        assert!(compare(&one_case(&SAMPLE_GROUPS, cpu.clone()), &gpu).passed());
        let gpu = sample_gpu(wi, [0.25, ulps(0.5, 17), 1e-8], pdf);
        assert!(!compare(&one_case(&SAMPLE_GROUPS, cpu.clone()), &gpu).passed());
        let gpu = sample_gpu(wi, weight, ulps(pdf, 17));
        assert!(!compare(&one_case(&SAMPLE_GROUPS, cpu), &gpu).passed());
    }

    #[test]
    fn sample_rebases_weight_and_pdf_on_the_gpu_direction() {
        let spec = specs().into_iter().find(|s| s.name == "ggx_conductor_sample").unwrap();
        let (f, _) = spec.rebase.unwrap();
        // A valid, non-delta sample at a grazing view.
        let case = (0..spec.cases.len())
            .find(|&c| {
                let e = &spec.expect[c];
                matches!((e[0], e[1]), (Expect::Bits(1), Expect::Bits(0)))
                    && spec.cases[c].a[2] == 1e-3
                    && spec.cases[c].n[0] == 1
            })
            .unwrap();
        let (i, k, cpu) = (&spec.cases[case], &spec.bsdfs[case], &spec.expect[case]);
        let word = |e: Expect| match e {
            Expect::Float(x) => x.to_bits(),
            Expect::Bits(w) => w,
        };
        let same: Vec<u32> = padded(&cpu.iter().map(|&e| word(e)).collect::<Vec<_>>());
        let g = &spec.dielectrics[case];
        assert!(f(i, k, g, &same, cpu).is_none(), "the same direction keeps ggx-core's own words");
        // The GPU's wi one ulp away in x: weight and pdf of that direction, wi unchanged.
        let mut moved = same.clone();
        moved[2] += 1;
        let alt = f(i, k, g, &moved, cpu).expect("rebased");
        let wi = glam::Vec3::new(f32::from_bits(moved[2]), f32::from_bits(moved[3]), f32::from_bits(moved[4]));
        let wo = glam::Vec3::new(i.a[0], i.a[1], i.a[2]);
        let pdf = k.pdf(wo, wi, ggx_core::Sampling::from_u32(i.n[0]));
        assert!(matches!(alt[8], Expect::Float(p) if p == pdf), "pdf at the gpu's wi");
        assert!(matches!(alt[2], Expect::Float(x) if x.to_bits() == same[2]), "wi keeps ggx-core's reference");
        // The row's comparison uses it, and says so in the log.
        let one = Spec {
            cases: vec![*i],
            bsdfs: vec![*k],
            dielectrics: vec![*g],
            expect: vec![cpu.clone()],
            ..specs().into_iter().find(|s| s.name == "ggx_conductor_sample").unwrap()
        };
        let mut gpu: Vec<u32> = alt.iter().map(|&e| word(e)).collect();
        gpu[2] = moved[2];
        let r = compare(&one, &padded(&gpu));
        assert!(r.passed() && r.rebased == 1, "{}", r.groups.iter().map(|g| g.failures).sum::<usize>());
        let w = r.groups[1].at_max[0].as_ref().expect("wi is one ulp away");
        assert!(w.text.contains("(weight, pdf: cpu at the gpu's wi)"), "{}", w.text);
    }

    #[test]
    fn the_table_logs_the_case_behind_every_maximum() {
        let spec = one_case(&[Group::float("xyz", 3, Bound::Ulps(4))], [0.5f32, 0.25, 2.0].map(Expect::Float).to_vec());
        let gpu = padded(&[0.5f32.to_bits(), 0.25f32.to_bits() + 2, 2.0f32.to_bits()]);
        let row = compare(&spec, &gpu);
        assert!(row.passed());
        let g = &row.groups[0];
        assert_eq!(g.max_ulp, 2);
        for w in &g.at_max {
            assert_eq!(w.as_ref().map(|w| (w.case, w.word)), Some((0, 1)));
        }
        let report = ParityReport {
            adapter: "test".into(),
            rows: vec![row],
            probe: ProbeReport {
                nan_ne_self: false,
                not_gt_nan: true,
                is_nan_bits: true,
                max_nan_zero: 0.0,
                min_nan_one: 1.0,
                clamp_nan: 0.0,
                one_over_zero: INF,
                zero_over_zero: NAN,
                sqrt_minus_one: NAN,
                subnormal_input_kept: true,
                subnormal_result_kept: true,
                fma_contracted: false,
            },
        };
        let table = report.table();
        assert!(
            table.contains("    max ulp,rel,abs: xyz[1] case 0: in -; gpu [0.5, 0.25000006, 2.0] cpu [0.5, 0.25, 2.0]"),
            "{table}"
        );
    }

    /// `GltfMetalRough` in ggx_core.wgsl has the Rust struct's size and member offsets (its
    /// `[f32; 3]` fields are `vec3<f32>` with the next `f32` in the fourth lane), and the
    /// parity rows' packing of it into a conductor (parity.wgsl `metal_rough`) loses nothing.
    #[test]
    fn gltf_metal_rough_layout_and_packing() {
        use ggx_core::GltfMetalRough;
        let module = naga::front::wgsl::parse_str(crate::GGX_CORE_WGSL).expect("ggx_core.wgsl parses");
        let ty = module.types.iter().find(|(_, t)| t.name.as_deref() == Some("GltfMetalRough")).expect("struct").1;
        let naga::TypeInner::Struct { members, span } = &ty.inner else { panic!("GltfMetalRough is a struct") };
        let wgsl: Vec<(String, u32)> = members.iter().map(|m| (m.name.clone().unwrap(), m.offset)).collect();
        let rust = [
            ("base_color", std::mem::offset_of!(GltfMetalRough, base_color)),
            ("metallic", std::mem::offset_of!(GltfMetalRough, metallic)),
            ("f0", std::mem::offset_of!(GltfMetalRough, f0)),
            ("specular_weight", std::mem::offset_of!(GltfMetalRough, specular_weight)),
            ("distribution", std::mem::offset_of!(GltfMetalRough, distribution)),
            ("p_specular", std::mem::offset_of!(GltfMetalRough, p_specular)),
            ("pad", std::mem::offset_of!(GltfMetalRough, pad)),
        ]
        .map(|(n, o)| (n.to_string(), o as u32));
        assert_eq!(wgsl, rust);
        assert_eq!(*span as usize, size_of::<GltfMetalRough>());
        assert_eq!(size_of::<GltfMetalRough>(), 48);
        for m in cases::metal_roughs() {
            let back = cases::unpack_metal_rough(&cases::pack_metal_rough(&m));
            assert_eq!(bytemuck::bytes_of(&back), bytemuck::bytes_of(&m));
        }
    }

    /// `GltfClearcoat` in ggx_core.wgsl has the Rust struct's size and member offsets (the base
    /// a `GltfMetalRough` at 0, 16-aligned in WGSL as well), and the parity rows' packing of it into
    /// a conductor (parity.wgsl `clearcoat`) loses nothing.
    #[test]
    fn gltf_clearcoat_layout_and_packing() {
        use ggx_core::GltfClearcoat;
        let module = naga::front::wgsl::parse_str(crate::GGX_CORE_WGSL).expect("ggx_core.wgsl parses");
        let ty = module.types.iter().find(|(_, t)| t.name.as_deref() == Some("GltfClearcoat")).expect("struct").1;
        let naga::TypeInner::Struct { members, span } = &ty.inner else { panic!("GltfClearcoat is a struct") };
        let wgsl: Vec<(String, u32)> = members.iter().map(|m| (m.name.clone().unwrap(), m.offset)).collect();
        let rust = [
            ("base", std::mem::offset_of!(GltfClearcoat, base)),
            ("coat", std::mem::offset_of!(GltfClearcoat, coat)),
            ("weight", std::mem::offset_of!(GltfClearcoat, weight)),
            ("base_albedo", std::mem::offset_of!(GltfClearcoat, base_albedo)),
        ]
        .map(|(n, o)| (n.to_string(), o as u32));
        assert_eq!(wgsl, rust);
        assert_eq!(*span as usize, size_of::<GltfClearcoat>());
        assert_eq!(size_of::<GltfClearcoat>(), 64);
        for c in cases::clearcoats() {
            let back = cases::unpack_clearcoat(&cases::pack_clearcoat(&c));
            assert_eq!(bytemuck::bytes_of(&back), bytemuck::bytes_of(&c));
        }
    }

    #[test]
    fn ulp_distance_and_bounds() {
        assert_eq!(ulp_distance(1.0, 1.0), 0);
        assert_eq!(ulp_distance(0.0, -0.0), 0);
        assert_eq!(ulp_distance(1.0, f32::from_bits(1.0f32.to_bits() + 3)), 3);
        assert_eq!(ulp_distance(f32::from_bits(1), -f32::from_bits(1)), 2);
        assert!(Bound::Exact.accepts(NAN, NAN));
        assert!(!Bound::Ulps(100).accepts(NAN, 1.0));
        assert!(!Bound::Ulps(100).accepts(f32::MAX, INF));
        assert!(Bound::UlpsOrAbs(0, 1e-6).accepts(1e-7, 0.0));
        assert!(!Bound::Ulps(1000).accepts(1e-7, 0.0), "no absolute escape");
        assert!(!Bound::Ulps(4).accepts(1.0, 1.001));
        assert!(Bound::Exact.accepts(0.0, 1e-40), "flushed subnormal");
        assert!(!Bound::Exact.accepts(0.0, f32::MIN_POSITIVE));
        assert!(Bound::Exact.accepts(-0.0, 0.0));
        assert_eq!(Bound::UlpsOrAbs(16, 1.0 / 1_048_576.0).to_string(), "16 ulp|1e-6 abs");
    }
}
