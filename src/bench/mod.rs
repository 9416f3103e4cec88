//! `shearsph bench`: the solver's cost per step, per kernel and particle
//! count, on one core and on all of them; throughput in particle-steps and
//! pair evaluations per second, memory, the floating-point rate against the
//! machine's peak, and how the cost per step grows with the particle count
//! (a fitted exponent, 1 for linear).
//!
//! Each measurement takes a fixed number of steps on the steady-profile
//! scene below (not to t_end) and times the steps alone; the set-up (first
//! neighbour list, density and forces) is left out. A measurement is repeated
//! and the median kept, since the machines this runs on are noisy.

use anyhow::{bail, Context, Result};
use serde::Serialize;

use crate::config::{Initial, Scene, WallVelocity};
use crate::kernel::{Kernel, KernelVisitor};
use crate::kernels;
use crate::problem::lattice::Lattice;
use crate::problem::Problem;
use crate::solver::{self, StepsRun};

/// What to measure.
#[derive(Debug, Clone)]
pub struct Options {
    pub kernels: Vec<String>,
    /// Target particle counts (fluid and walls): each scene is the smallest
    /// channel with at least this many.
    pub particles: Vec<usize>,
    /// Steps per measurement; by default enough for `particle_steps`.
    pub steps: Option<u64>,
    /// Particle-steps per measurement when `steps` is not given.
    pub particle_steps: f64,
    /// Repeats of each measurement; the median is reported.
    pub repeats: usize,
    /// Thread counts (rayon pools) to measure with.
    pub threads: Vec<usize>,
}

impl Options {
    /// About a minute on two cores: every kernel at 1e3, 1e4 and 1e5
    /// particles, single-threaded and on all cores, three repeats of 4e6
    /// particle-steps each.
    pub fn defaults() -> Options {
        Options {
            kernels: kernels::NAMES.iter().map(|s| s.to_string()).collect(),
            particles: vec![1_000, 10_000, 100_000],
            steps: None,
            particle_steps: 4e6,
            repeats: 3,
            threads: thread_counts(),
        }
    }
}

/// 1 and every core (just 1 on a single core).
pub fn thread_counts() -> Vec<usize> {
    let all = cores();
    if all > 1 {
        vec![1, all]
    } else {
        vec![1]
    }
}

fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The bench scene for a kernel: the steady profile (7) at Re = 10, c0 = 10
/// U, the default alpha, h = d; N layers to be set. The end time plays no
/// part (a fixed number of steps is taken); it is set short so that the
/// scene's run-time bound never refuses a large N.
pub fn scene(kernel: &str) -> Scene {
    Scene {
        kernel: kernel.to_string(),
        re: Some(10.0),
        p: None,
        c0: "rule10".parse().expect("a valid c0 rule"),
        initial: Initial::Steady,
        t_end: Some(1e-6),
        ..Scene::builtin()
    }
}

/// The smallest N whose lattice holds at least `target` particles (and no
/// fewer layers than the kernel needs).
pub fn layers_for(scene: &Scene, target: usize) -> Result<u32> {
    let info = scene.kernel_info()?;
    let h = scene.h_over_d * scene.d;
    // Refused before the search, with the estimate: a count the memory
    // bound (or the lattice's u32 counts) cannot hold.
    let neighbours = crate::problem::cost::listed_neighbours(scene.d, h, info.support, scene.skin);
    let bytes = crate::problem::cost::memory_bytes(target as f64, neighbours, 0.0, 0.0);
    let max = crate::problem::cost::MAX_RUN_BYTES;
    if !(bytes <= max && (target as f64) <= crate::problem::cost::MAX_PARTICLES) {
        bail!(
            "--particles {}: the scene would take about {} of memory ({} neighbours each), over the \
             bound of {}; give fewer particles",
            crate::format::fmt_value(target as f64),
            crate::problem::cost::human_bytes(bytes),
            neighbours.round(),
            crate::problem::cost::human_bytes(max)
        );
    }
    let count = |n: u32| Lattice::new(scene.lattice, n, scene.d, h, info.support).n_particles();
    // Particles grow by 2 C per layer: start from the estimate, then step.
    let per_layer = 2 * Lattice::new(scene.lattice, 1, scene.d, h, info.support).columns as usize;
    let mut n = (target / per_layer).max(1) as u32;
    while n > 1 && count(n - 1) >= target {
        n -= 1;
    }
    while count(n) < target {
        n += 1;
    }
    // Not below the kernel's own lower bound on N (the scene's check says).
    let mut s = scene.clone();
    s.n_layers = n;
    while let Err(e) = Problem::resolve(&s, info) {
        if s.n_layers > 1_000 {
            return Err(e.with_flag("n_layers", "particles").into());
        }
        s.n_layers += 1;
    }
    Ok(s.n_layers)
}

/// The machine and the peak it is measured against.
#[derive(Debug, Clone, Serialize)]
pub struct Machine {
    pub cpu: String,
    pub cores: usize,
    /// Clock from /proc/cpuinfo (`cpu MHz`, the largest over cores); the
    /// nominal clock on a virtual machine, no turbo.
    pub ghz: f64,
    /// The vector instructions of the pair loops (chosen at run time), and
    /// the double-precision flops per cycle and core they allow: lanes x 2
    /// (two FP ports on current x86 cores), no FMA (Rust never fuses a * b +
    /// c, and the solver writes no mul_add).
    pub isa_in_use: String,
    pub flops_per_cycle_in_use: f64,
    /// cores x GHz x flops/cycle for the instruction set in use.
    pub peak_gflops_in_use: f64,
    /// The widest vector unit the CPU has (from /proc/cpuinfo flags) with
    /// FMA: lanes x 2 ports x 2 (the usual quoted peak, e.g. AVX2 FMA 16,
    /// AVX-512 FMA 32 DP flops/cycle).
    pub isa_best: &'static str,
    pub flops_per_cycle_best: f64,
    pub peak_gflops_best: f64,
}

/// (name, flops per cycle and core) of the CPU's widest unit, with FMA.
fn best_isa(avx512: bool, avx: bool, fma: bool) -> (&'static str, f64) {
    match (avx512, avx, fma) {
        (true, _, _) => ("AVX-512 + FMA (8 lanes x 2 FMA ports x 2)", 32.0),
        (false, true, true) => ("AVX2 + FMA (4 lanes x 2 FMA ports x 2)", 16.0),
        (false, true, false) => ("AVX (4 lanes x add + mul ports)", 8.0),
        _ => ("SSE2 (2 lanes x add + mul ports)", 4.0),
    }
}

impl Machine {
    pub fn detect() -> Machine {
        let info = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
        let field = |name: &str| {
            info.lines()
                .filter(|l| l.starts_with(name))
                .filter_map(|l| l.split_once(':').map(|(_, v)| v.trim().to_string()))
                .collect::<Vec<_>>()
        };
        let cpu = field("model name").into_iter().next().unwrap_or_default();
        let mhz = field("cpu MHz")
            .iter()
            .filter_map(|v| v.parse::<f64>().ok())
            .fold(0.0, f64::max);
        let ghz = if mhz > 0.0 { mhz / 1000.0 } else { f64::NAN };
        let flags = field("flags").into_iter().next().unwrap_or_default();
        let has = |f: &str| flags.split_whitespace().any(|x| x == f);
        let (name, lanes) = solver::pair_loop_isa();
        let in_use = 2.0 * f64::from(lanes);
        let isa_in_use = format!("{name} ({lanes} lanes x 2 ports, no FMA)");
        let (isa_best, best) = best_isa(has("avx512f"), has("avx"), has("fma"));
        let cores = cores();
        let peak = |f: f64| cores as f64 * ghz * f;
        Machine {
            cpu,
            cores,
            ghz,
            isa_in_use,
            flops_per_cycle_in_use: in_use,
            peak_gflops_in_use: peak(in_use),
            isa_best,
            flops_per_cycle_best: best,
            peak_gflops_best: peak(best),
        }
    }
}

/// One measurement: a kernel, a particle count, a thread count.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    pub kernel: String,
    pub target_particles: usize,
    pub particles: usize,
    pub n_fluid: usize,
    pub n_layers: u32,
    pub threads: usize,
    pub steps: u64,
    pub repeats: usize,
    /// Median over the repeats of the steps' wall time.
    pub wall_s: f64,
    /// Every repeat's wall time, in order.
    pub wall_s_all: Vec<f64>,
    pub ns_per_particle_step: f64,
    pub particle_steps_per_s: f64,
    /// Directed pairs within the support per step, and their rate: each is
    /// one evaluation of W and (dW/dq)/q with the passes' arithmetic.
    pub pairs_per_step: f64,
    pub pairs_per_s: f64,
    pub ns_per_pair: f64,
    /// Listed pairs (support + skin) per particle.
    pub listed_per_particle: f64,
    /// Useful flops per directed pair in the support: the kernel's
    /// (generator's count) and the distance, halved (each pair is evaluated
    /// once for both directions), plus the density sum and the force terms.
    pub flops_per_pair: f64,
    pub gflops: f64,
    /// gflops over the peak for the instruction set in use, and over the
    /// CPU's best (see `Machine`); for the threads used (threads/cores of it).
    pub fraction_of_peak_in_use: f64,
    pub fraction_of_peak_best: f64,
    /// Particle arrays and neighbour structure, per particle.
    pub bytes_per_particle: f64,
    pub arrays_bytes: usize,
    /// The process's peak resident memory so far (VmHWM), after this run.
    pub vm_hwm_bytes: Option<u64>,
    pub neighbour_rebuilds: u64,
    pub ok: bool,
}

/// How the cost per step grows with the particle count, per kernel and
/// thread count: time per step ~ particles^exponent (least squares on logs).
#[derive(Debug, Clone, Serialize)]
pub struct Scaling {
    pub kernel: String,
    pub threads: usize,
    pub exponent: f64,
    /// ns per particle-step at the smallest and the largest count.
    pub ns_per_particle_step_first: f64,
    pub ns_per_particle_step_last: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub machine: Machine,
    pub scene: String,
    pub rows: Vec<Row>,
    pub scaling: Vec<Scaling>,
}

/// The process's peak resident set (VmHWM), if /proc says.
pub fn vm_hwm_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

struct Steps<'a> {
    problem: &'a Problem,
    steps: u64,
}

impl KernelVisitor for Steps<'_> {
    type Output = (StepsRun, f64);
    fn visit<K: Kernel>(self) -> (StepsRun, f64) {
        (
            solver::run_steps::<K>(self.problem, self.steps),
            solver::flops_per_pair(K::INFO.flops_per_pair, self.problem),
        )
    }
}

/// Run `steps` steps of `problem` on a pool of `threads`.
pub fn measure(problem: &Problem, steps: u64, threads: usize) -> Result<(StepsRun, f64)> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("building the thread pool")?;
    pool.install(|| {
        kernels::with_kernel(&problem.scene.kernel, Steps { problem, steps })
            .with_context(|| format!("unknown kernel {}", problem.scene.kernel))
    })
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

/// Least-squares slope of log y against log x.
pub fn fitted_exponent(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|&(x, y)| (x.ln(), y.ln())).unzip();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Run every measurement; `progress` hears about each as it starts.
pub fn run(opts: &Options, mut progress: impl FnMut(&str)) -> Result<Report> {
    if opts.repeats == 0 {
        bail!("--repeats must be at least 1");
    }
    if opts.threads.contains(&0) {
        bail!("--threads must be at least 1");
    }
    if opts.steps == Some(0) {
        bail!("--steps must be at least 1: a measurement of no steps has no throughput");
    }
    let machine = Machine::detect();
    let mut rows = Vec::new();
    for kernel in &opts.kernels {
        let base = scene(kernel);
        let info = base.kernel_info()?;
        for &target in &opts.particles {
            let mut s = base.clone();
            s.n_layers = layers_for(&s, target)?;
            let problem = Problem::resolve(&s, info)?;
            let particles = problem.lattice.n_particles();
            let steps = opts.steps.unwrap_or_else(|| {
                ((opts.particle_steps / particles as f64).ceil() as u64).max(10)
            });
            for &threads in &opts.threads {
                progress(&format!(
                    "{kernel}: {particles} particles, {threads} thread(s), {steps} steps x {}",
                    opts.repeats
                ));
                let mut walls = Vec::with_capacity(opts.repeats);
                let mut last = None;
                for _ in 0..opts.repeats {
                    let (r, flops) = measure(&problem, steps, threads)?;
                    walls.push(r.wall_s);
                    last = Some((r, flops));
                }
                let (r, flops) = last.expect("at least one repeat");
                let wall = median(&walls);
                let taken = r.steps.max(1) as f64;
                let per_step = wall / taken;
                let pairs_per_s = r.pairs_per_step / per_step;
                let gflops = pairs_per_s * flops * 1e-9;
                let share = threads.min(machine.cores) as f64 / machine.cores as f64;
                rows.push(Row {
                    kernel: kernel.clone(),
                    target_particles: target,
                    particles,
                    n_fluid: r.n_fluid,
                    n_layers: s.n_layers,
                    threads,
                    steps: r.steps,
                    repeats: opts.repeats,
                    wall_s: wall,
                    wall_s_all: walls,
                    ns_per_particle_step: per_step / particles as f64 * 1e9,
                    particle_steps_per_s: particles as f64 / per_step,
                    pairs_per_step: r.pairs_per_step,
                    pairs_per_s,
                    ns_per_pair: 1e9 / pairs_per_s,
                    listed_per_particle: r.listed_pairs as f64 / particles as f64,
                    flops_per_pair: flops,
                    gflops,
                    fraction_of_peak_in_use: gflops / (machine.peak_gflops_in_use * share),
                    fraction_of_peak_best: gflops / (machine.peak_gflops_best * share),
                    bytes_per_particle: r.bytes as f64 / particles as f64,
                    arrays_bytes: r.bytes,
                    vm_hwm_bytes: vm_hwm_bytes(),
                    neighbour_rebuilds: r.neighbour_rebuilds,
                    ok: r.outcome.is_ok(),
                });
            }
        }
    }
    let mut scaling = Vec::new();
    for kernel in &opts.kernels {
        for &threads in &opts.threads {
            let mut pts: Vec<&Row> = rows
                .iter()
                .filter(|r| &r.kernel == kernel && r.threads == threads)
                .collect();
            pts.sort_by_key(|r| r.particles);
            if pts.len() < 2 || pts[0].particles == pts[pts.len() - 1].particles {
                continue;
            }
            let xy: Vec<(f64, f64)> = pts
                .iter()
                .map(|r| (r.particles as f64, r.wall_s / r.steps.max(1) as f64))
                .collect();
            scaling.push(Scaling {
                kernel: kernel.clone(),
                threads,
                exponent: fitted_exponent(&xy),
                ns_per_particle_step_first: pts[0].ns_per_particle_step,
                ns_per_particle_step_last: pts[pts.len() - 1].ns_per_particle_step,
            });
        }
    }
    Ok(Report {
        machine,
        scene: "steady profile (7), Re = 10, c0 = 10 U, alpha = 0.1, h = d, skin 0.3 h".to_string(),
        rows,
        scaling,
    })
}

/// The report as a text table.
pub fn table(r: &Report) -> String {
    let m = &r.machine;
    let mut out = String::new();
    out.push_str(&format!(
        "machine: {} | {} cores at {:.2} GHz (/proc/cpuinfo)\n",
        m.cpu, m.cores, m.ghz
    ));
    out.push_str(&format!(
        "peak = cores x GHz x DP flops/cycle/core. In use (pair loops): {}: {} -> {:.1} GFLOP/s; \
         the CPU's best, {}: {} -> {:.1} GFLOP/s\n",
        m.isa_in_use,
        m.flops_per_cycle_in_use,
        m.peak_gflops_in_use,
        m.isa_best,
        m.flops_per_cycle_best,
        m.peak_gflops_best
    ));
    out.push_str(&format!("scene: {}\n\n", r.scene));
    out.push_str(&format!(
        "{:<10} {:>8} {:>3} {:>6} {:>9} {:>12} {:>12} {:>7} {:>8} {:>6} {:>6} {:>7} {:>6} {:>8} {:>4}\n",
        "kernel",
        "particles",
        "thr",
        "steps",
        "s/step",
        "p-steps/s",
        "pairs/s",
        "ns/pair",
        "ns/p-step",
        "GF/s",
        "%peak",
        "%best",
        "B/part",
        "HWM MiB",
        "ok"
    ));
    for row in &r.rows {
        out.push_str(&format!(
            "{:<10} {:>8} {:>3} {:>6} {:>9.3e} {:>12.4e} {:>12.4e} {:>7.2} {:>8.1} {:>6.2} {:>6.1} {:>7.2} {:>6.0} {:>8.1} {:>4}\n",
            row.kernel,
            row.particles,
            row.threads,
            row.steps,
            row.wall_s / row.steps.max(1) as f64,
            row.particle_steps_per_s,
            row.pairs_per_s,
            row.ns_per_pair,
            row.ns_per_particle_step,
            row.gflops,
            100.0 * row.fraction_of_peak_in_use,
            100.0 * row.fraction_of_peak_best,
            row.bytes_per_particle,
            row.vm_hwm_bytes.map_or(f64::NAN, |b| b as f64 / (1 << 20) as f64),
            if row.ok { "ok" } else { "FAIL" },
        ));
    }
    if !r.scaling.is_empty() {
        out.push_str("\ncost per step ~ particles^k (least squares over the counts above):\n");
        for s in &r.scaling {
            out.push_str(&format!(
                "  {:<10} {} thread(s): k = {:.3}; ns per particle-step {:.1} -> {:.1}\n",
                s.kernel,
                s.threads,
                s.exponent,
                s.ns_per_particle_step_first,
                s.ns_per_particle_step_last
            ));
        }
    }
    out
}

/// shearsph on the scene matched to PySPH's stock example
/// `pysph.examples.poiseuille` (see bench/peers/): one run of fixed steps.
#[derive(Debug, Clone, Serialize)]
pub struct PeerRun {
    pub code: String,
    /// The walls' velocity in the viscous term (`zero`: the paper's walls).
    pub wall_velocity: WallVelocity,
    /// Layers in the half-width (PySPH: 30 is the matched resolution).
    pub layers: u32,
    /// The discretisation ("square, h = 1 d").
    pub discretisation: String,
    /// U B / nu and c0 / U of the scene.
    pub re: f64,
    pub c0_over_u: f64,
    pub particles: usize,
    pub n_fluid: usize,
    pub n_wall: usize,
    pub steps: u64,
    pub threads: usize,
    /// Wall-clock seconds of the steps alone.
    pub wall_s: f64,
    pub particle_steps_per_s: f64,
    pub t: f64,
    /// t in units of B^2 / nu (B the half-width): the physical time that
    /// both codes reach after the same number of steps.
    pub tau: f64,
    /// max over layers of |mean u - start-up series| / U at t.
    pub linf_rel_err: f64,
}

/// PySPH's example, in shearsph's terms: the quintic spline (shearsph's
/// `morris`, R = 3 h), h / B = 1/30 (dx = h = 1/60 across Ly = 1 = 2 B, the
/// example's square lattice with hdx = 1), Re = Vmax Ly / nu = 0.0125, i.e.
/// U B / nu = 0.00625, c0 = 10 U, no artificial viscosity (TVF has none),
/// from rest. The time step is then bound by the viscous limit
/// 0.125 h^2 / nu in both codes, so equal steps reach equal t nu / B^2.
/// N = 30 layers in the half-width on the square lattice, h = d, and a strip
/// 26 columns wide: 1690 particles with the walls, against PySPH's 1680
/// (24 x 60 fluid, 2 x 5 x 24 wall).
///
/// `layers` other than [`PYSPH_MATCH_LAYERS`] gives the same flow at another
/// resolution (h = d, so h / B = 1 / N), on the narrowest strip: for the
/// time shearsph takes to reach PySPH's accuracy.
pub fn pysph_match_problem(wall_velocity: WallVelocity, layers: u32) -> Result<Problem> {
    let n_layers = layers;
    let scene = Scene {
        kernel: "morris".into(),
        n_layers,
        lattice: crate::kernel::Lattice::Square,
        h_over_d: 1.0,
        re: Some(0.00625),
        p: None,
        c0: "rule10".parse().expect("a valid c0 rule"),
        alpha: 0.0,
        initial: Initial::Rest,
        wall_velocity,
        t_end: Some(1e-6),
        ..Scene::builtin()
    };
    let mut problem = Problem::resolve(&scene, scene.kernel_info()?)
        .map_err(|e| e.with_flag("n_layers", "layers"))?;
    if layers == PYSPH_MATCH_LAYERS {
        // A wider strip than the kernel needs, to match the particle count:
        // the flow does not depend on x.
        let lat = &mut problem.lattice;
        lat.columns = 26;
        lat.width = f64::from(lat.columns) * lat.d;
    }
    Ok(problem)
}

/// Layers in the half-width of the scene matched to PySPH's resolution.
pub const PYSPH_MATCH_LAYERS: u32 = 30;

/// `steps` steps of the matched scene, or with `layers` other than 35 the
/// steps that reach the same t nu / B^2 (the viscous limit binds: steps
/// scale as layers^2). Layers other than 30 keep h = d.
pub fn pysph_match(
    steps: u64,
    threads: usize,
    wall_velocity: WallVelocity,
    layers: u32,
) -> Result<PeerRun> {
    let problem = pysph_match_problem(wall_velocity, layers)?;
    let scale = (f64::from(layers) / f64::from(PYSPH_MATCH_LAYERS)).powi(2);
    let steps = ((steps as f64 * scale).round() as u64).max(1);
    let (r, _) = measure(&problem, steps, threads)?;
    let particles = r.n_fluid + r.n_wall;
    let flow = &problem.flow;
    Ok(PeerRun {
        code: "shearsph (morris = quintic spline)".into(),
        wall_velocity,
        layers,
        discretisation: problem.discretisation.label(),
        re: problem.re,
        c0_over_u: problem.c0 / flow.u,
        particles,
        n_fluid: r.n_fluid,
        n_wall: r.n_wall,
        steps: r.steps,
        threads,
        wall_s: r.wall_s,
        particle_steps_per_s: particles as f64 * r.steps as f64 / r.wall_s,
        t: r.last.t,
        tau: r.last.t * flow.nu / (flow.b * flow.b),
        linf_rel_err: r.last.linf_rel_err,
    })
}

/// SPHinXsys's stock `test_2d_poiseuille_flow` in shearsph's terms (see
/// bench/peers/sphinxsys_poiseuille.sh, whose header fixes it): Wendland C2
/// (`wendland_c2`), the square lattice with h = 13/10 d, B = N d,
/// U B / nu = 7.5, c0 = 10 U, no artificial viscosity (SPHinXsys's Riemann
/// solvers have none), no-slip walls (`mirrored`), from rest, to
/// t nu / B^2 = `tau`, on a strip of `columns` columns (default: the
/// narrowest the kernel allows).
pub fn sphinxsys_match_problem(layers: u32, tau: f64, columns: Option<u32>) -> Result<Problem> {
    if !(tau > 0.0 && tau.is_finite()) {
        bail!("--tau {tau} must be a positive number (t nu / B^2)");
    }
    let scene = Scene {
        kernel: "wendland_c2".into(),
        n_layers: layers,
        lattice: crate::kernel::Lattice::Square,
        h_over_d: 1.3,
        re: Some(SPHINXSYS_MATCH_RE),
        p: None,
        c0: "rule10".parse().expect("a valid c0 rule"),
        alpha: 0.0,
        initial: Initial::Rest,
        wall_velocity: WallVelocity::Mirrored,
        t_end: Some(1.0),
        ..Scene::builtin()
    };
    let info = scene.kernel_info()?;
    let mut probe = Problem::resolve(&scene, info)?;
    let b = probe.flow.b;
    let t_end = tau * b * b / probe.flow.nu;
    let scene = Scene {
        t_end: Some(t_end),
        ..scene
    };
    probe = Problem::resolve(&scene, info)?;
    if let Some(c) = columns {
        let lat = &mut probe.lattice;
        if c < lat.columns {
            bail!(
                "--columns {c} is narrower than kernel {} needs at h = {} d (at least {} columns)",
                info.name,
                scene.h_over_d,
                lat.columns
            );
        }
        // A wider strip than the kernel needs: the flow does not depend on x.
        lat.columns = c;
        lat.width = f64::from(c) * lat.d;
    }
    Ok(probe)
}

/// U B / nu of the SPHinXsys-matched scene: the stock case's Re = 10 on the
/// mean speed and the full width.
pub const SPHINXSYS_MATCH_RE: f64 = 7.5;

/// One run of the SPHinXsys-matched scene to t nu / B^2 = `tau`. The solver
/// runs whole steps whose dt follows the flow (c0 = 10 U: the CFL limit
/// 0.25 h / (c0 + |v|max) binds, up to 10 % longer than at |v| = U), so a
/// first run at the starting estimate's step count measures the mean dt and
/// the timed run takes the steps that reach t_end at it.
pub fn sphinxsys_match(
    layers: u32,
    tau: f64,
    threads: usize,
    columns: Option<u32>,
) -> Result<PeerRun> {
    let problem = sphinxsys_match_problem(layers, tau, columns)?;
    let est = crate::problem::cost::Estimate::new(&problem.channel(), problem.c0, problem.t_end);
    let first = (est.steps as u64).max(1);
    let (probe, _) = measure(&problem, first, threads)?;
    let steps = ((first as f64 * problem.t_end / probe.last.t).round() as u64).max(1);
    let (r, _) = measure(&problem, steps, threads)?;
    let particles = r.n_fluid + r.n_wall;
    let flow = &problem.flow;
    Ok(PeerRun {
        code: "shearsph (wendland_c2 = Wendland C2)".into(),
        wall_velocity: problem.wall_velocity,
        layers,
        discretisation: problem.discretisation.label(),
        re: problem.re,
        c0_over_u: problem.c0 / flow.u,
        particles,
        n_fluid: r.n_fluid,
        n_wall: r.n_wall,
        steps: r.steps,
        threads,
        wall_s: r.wall_s,
        particle_steps_per_s: particles as f64 * r.steps as f64 / r.wall_s,
        t: r.last.t,
        tau: r.last.t * flow.nu / (flow.b * flow.b),
        linf_rel_err: r.last.linf_rel_err,
    })
}
