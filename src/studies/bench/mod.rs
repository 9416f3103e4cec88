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

mod budget;
pub mod disordered;
mod empirical;
mod machine;
mod peers;
mod table;

use anyhow::{Context, Result};
use serde::Serialize;

use crate::config::{Initial, Scene};
use crate::kernel::{Kernel, KernelVisitor};
use crate::kernels;
use crate::problem::lattice::LatticeGeometry;
use crate::problem::Problem;
use crate::solver::{self, FluidState, StepsRun};
pub use budget::{check, estimated_seconds, MAX_BENCH_S};
use budget::{check_memory, steps_for};
pub use empirical::{empirical, empirical_table, EmpiricalBench, EMPIRICAL_RE};
pub use machine::{stream_gbs, Machine};
pub use peers::{
    pysph_match, pysph_match_problem, sphinxsys_match, sphinxsys_match_problem, PeerRun,
    PEER_MATCH_CFL, PYSPH_MATCH_LAYERS, SPHINXSYS_MATCH_RE,
};
pub use table::table;

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
    /// Measure the memory bandwidth (a second or two) for the roofline.
    pub bandwidth: bool,
    /// The disordered scene ([`disordered`]) instead of the ordered one.
    pub disordered: bool,
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
            bandwidth: true,
            disordered: false,
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

pub(crate) fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The bench scene for a kernel: the steady profile (7) at Re = 10, c0 = 10
/// U, the default alpha, h = d; N layers to be set. The end time plays no
/// part (a fixed number of steps is taken); it is set short so that the
/// scene's run-time bound never refuses a large N. Its CFL factor is fixed
/// at [`BENCH_CFL`], not the kernel's default, so that a step is the same
/// work in every build the bench compares (the factor sets how far the
/// disordered scene's particles move between list rebuilds).
pub fn scene(kernel: &str) -> Scene {
    Scene {
        kernel: kernel.to_string(),
        re: Some(10.0),
        p: None,
        c0: "rule10".parse().expect("a valid c0 rule"),
        initial: Initial::Steady,
        t_end: Some(1e-6),
        cfl: Some(BENCH_CFL),
        ..Scene::builtin()
    }
}

/// The bench scenes' CFL factor: the default before the default became
/// each kernel's own (docs/timestep.md), at which the bench's figures in
/// docs/performance.md were measured.
pub const BENCH_CFL: f64 = 0.5;

/// The bench scene, or its disordered form's base
/// ([`disordered::base_scene`]).
pub fn scene_for(kernel: &str, disordered: bool) -> Scene {
    if disordered {
        disordered::base_scene(kernel)
    } else {
        scene(kernel)
    }
}

/// The smallest N whose lattice holds at least `target` particles (and no
/// fewer layers than the kernel needs).
pub fn layers_for(scene: &Scene, target: usize) -> Result<u32> {
    check_memory(scene, target)?;
    let info = scene.kernel_info()?;
    let h = scene.h_over_d * scene.d;
    // A jittered scene's strip widens with N (as wide as the channel).
    let count = |n: u32| {
        let mut s = scene.clone();
        s.n_layers = n;
        match crate::problem::channel::Channel::resolve(&s, info) {
            Ok(c) if scene.jitter > 0.0 => c.lattice.n_particles(),
            _ => LatticeGeometry::new(scene.lattice, n, scene.d, h, info.support).n_particles(),
        }
    };
    // Particles grow by 2 C per layer: start from the estimate, then step.
    let per_layer =
        2 * LatticeGeometry::new(scene.lattice, 1, scene.d, h, info.support).columns as usize;
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
    /// The share of the steps' time spent in the pair passes (density and
    /// forces, timed inside the solver), and their own rate: the step's
    /// flops over that time, against the same peaks.
    pub pair_loop_share: f64,
    pub pair_loop_gflops: f64,
    pub pair_loop_fraction_of_peak_in_use: f64,
    pub pair_loop_fraction_of_peak_best: f64,
    /// The roofline: bytes the pair passes move per directed pair in the
    /// support at the least (every array once per pass), flops per such
    /// byte, and the rate the roofs allow, min(peak in use, flops/byte x
    /// measured bandwidth) for the threads used (NaN without bandwidth).
    pub bytes_per_pair: f64,
    pub flops_per_byte: f64,
    pub roofline_gflops: f64,
    /// The pair passes one by one (the last repeat's, timed inside the
    /// solver): each one's share of the steps' time, in turn the kernel
    /// pass, the density sums and the force pass.
    pub pass_share: [f64; 3],
    /// The share of the steps' time spent rebuilding the neighbour list
    /// (the last repeat's, timed inside the solver).
    pub rebuild_share: f64,
    /// The kernel pass's core-nanoseconds per pair evaluated (its wall time
    /// x the cores used / own pairs), and the kernel alone in lanes on one
    /// core with its values in the first-level cache
    /// ([`solver::kernel_alone_ns`]): a ratio near 1 is a pass bound by the
    /// kernel's own arithmetic (its square root and division per pair), not
    /// by memory.
    pub kernel_pass_ns: f64,
    pub kernel_alone_ns: f64,
    /// The force pass's core-nanoseconds per lane it runs (LANES per
    /// window, listed or not), the bound its flops per lane set at the peak
    /// in use (one core), and the share of its lanes that are listed pairs.
    pub forces_ns_per_lane: f64,
    pub forces_lane_bound_ns: f64,
    pub lane_use: f64,
    /// Where the force pass read (dW/dq)/q after the last trial: "lanes"
    /// (the window-lane table) or "pairs" (gathered from the pair table;
    /// the solver picks by cost where the list has a lane table,
    /// [`crate::solver::neighbours::NeighbourList::lane_table`]).
    pub force_g: &'static str,
    /// The f64 lanes of the vectors the kernel pass, the density sums and
    /// the force pass ran with (the instruction set each one's cost picked:
    /// the same bits with any).
    pub pass_lanes: [u32; 3],
    /// The step's core-nanoseconds per particle (its wall time x the cores
    /// used / particles), and the least the two pair passes' own arithmetic
    /// allows as the solver runs them: every own pair's kernel at the
    /// kernel-alone rate plus every force-pass lane at its flop bound, per
    /// particle (the density sums, the kick and memory left out; at the
    /// clock /proc/cpuinfo gives, which a boosting core may beat). What the
    /// step spends above it is memory, gathers and the loops' overheads;
    /// what the floor is made of is the work's form itself.
    pub core_ns_per_particle_step: f64,
    pub floor_core_ns_per_particle_step: f64,
    /// The kernel's part of that floor (the rest is the force pass's).
    pub floor_kernel_share: f64,
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
    /// The disordered scene's base per kernel (empty for the ordered one).
    pub bases: Vec<DisorderedBase>,
}

/// How the disordered scene's base run went: the state every size tiles.
#[derive(Debug, Clone, Serialize)]
pub struct DisorderedBase {
    pub kernel: String,
    pub particles: usize,
    pub columns: u32,
    /// Time reached and steps taken (short of [`disordered::UNTIL_T`] only
    /// if it failed).
    pub t: f64,
    pub steps: u64,
    /// The RMS distance of the fluid from its starting layers' rows at the
    /// end, in d (>= 0.1: disordered).
    pub dy_rms: f64,
    /// Its 99th percentile of the compaction at the end.
    pub eps_p99: f64,
    /// The failure it ended in, if any.
    pub failure: Option<String>,
}

impl DisorderedBase {
    fn of(kernel: &str, problem: &Problem, state: &FluidState) -> DisorderedBase {
        DisorderedBase {
            kernel: kernel.to_string(),
            particles: problem.lattice.n_particles(),
            columns: state.columns,
            t: state.t,
            steps: state.steps,
            dy_rms: state.last.dy_rms,
            eps_p99: state.last.eps_p99,
            failure: state.failure.as_ref().map(|f| f.to_string()),
        }
    }
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
    /// The state to tile into `problem` ([`solver::run_steps_tiled`]),
    /// or none: the problem's own start.
    base: Option<&'a FluidState>,
    steps: u64,
}

/// The kernel alone ([`solver::kernel_alone_ns`]).
struct KernelAlone;

impl KernelVisitor for KernelAlone {
    type Output = f64;
    fn visit<K: Kernel>(self) -> f64 {
        solver::kernel_alone_ns::<K>()
    }
}

impl KernelVisitor for Steps<'_> {
    type Output = (StepsRun, f64);
    fn visit<K: Kernel>(self) -> (StepsRun, f64) {
        (
            match self.base {
                Some(base) => solver::run_steps_tiled::<K>(self.problem, base, self.steps),
                None => solver::run_steps::<K>(self.problem, self.steps),
            },
            solver::flops_per_pair(K::INFO.flops_per_pair, self.problem),
        )
    }
}

/// Run `steps` steps of `problem` on a pool of `threads`, from its start
/// or from `base` tiled into it ([`solver::run_steps_tiled`]).
pub fn measure(
    problem: &Problem,
    base: Option<&FluidState>,
    steps: u64,
    threads: usize,
) -> Result<(StepsRun, f64)> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("building the thread pool")?;
    pool.install(|| {
        kernels::with_kernel(
            &problem.scene.kernel,
            Steps {
                problem,
                base,
                steps,
            },
        )
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
    check(opts)?;
    let mut machine = Machine::detect();
    let mut rows = Vec::new();
    let mut bases = Vec::new();
    for kernel in &opts.kernels {
        let base = scene_for(kernel, opts.disordered);
        let info = base.kernel_info()?;
        // Once per kernel, on this thread, before its runs.
        let kernel_alone_ns = kernels::with_kernel(kernel, KernelAlone)
            .with_context(|| format!("unknown kernel {kernel}"))?;
        // The disordered scene's base state, once per kernel.
        let base_state = if opts.disordered {
            let problem = Problem::resolve(&base, info)?;
            progress(&format!(
                "{kernel}: the disordered base, {} particles, run to t = {}",
                problem.lattice.n_particles(),
                disordered::UNTIL_T
            ));
            let state = disordered::base(&problem)?;
            bases.push(DisorderedBase::of(kernel, &problem, &state));
            Some((state, problem))
        } else {
            None
        };
        for &target in &opts.particles {
            let problem = match &base_state {
                Some((_, base)) => disordered::tiled(base, target)?,
                None => {
                    let mut s = base.clone();
                    s.n_layers = layers_for(&s, target)?;
                    Problem::resolve(&s, info)?
                }
            };
            let s = &problem.scene;
            let particles = problem.lattice.n_particles();
            let steps = steps_for(opts, particles);
            for &threads in &opts.threads {
                progress(&format!(
                    "{kernel}: {particles} particles, {threads} thread(s), {steps} steps x {}",
                    opts.repeats
                ));
                let mut walls = Vec::with_capacity(opts.repeats);
                let mut last = None;
                for _ in 0..opts.repeats {
                    let tile = base_state.as_ref().map(|(state, _)| state);
                    let (r, flops) = measure(&problem, tile, steps, threads)?;
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
                let pair_loop_share = r.pair_loop_s / r.wall_s;
                let pair_loop_gflops = gflops / pair_loop_share;
                let bytes_per_pair = r.pass_bytes_per_step / r.pairs_per_step;
                let flops_per_byte = flops / bytes_per_pair;
                let cores_used = threads.min(machine.cores) as f64;
                let core_ns_per = |pass: usize, per_step: usize| {
                    r.pass_s[pass] * cores_used / (per_step as f64 * taken) * 1e9
                };
                let force_flops = f64::from(solver::force_flops_per_pair(&problem));
                let forces_lane_bound_ns =
                    force_flops / (machine.flops_per_cycle_in_use * machine.ghz);
                let floor_kernel = r.own_pairs as f64 * kernel_alone_ns;
                let floor_forces = r.fluid_window_lanes as f64 * forces_lane_bound_ns;
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
                    pair_loop_share,
                    pair_loop_gflops,
                    pair_loop_fraction_of_peak_in_use: pair_loop_gflops
                        / (machine.peak_gflops_in_use * share),
                    pair_loop_fraction_of_peak_best: pair_loop_gflops
                        / (machine.peak_gflops_best * share),
                    bytes_per_pair,
                    flops_per_byte,
                    // With the bandwidth, measured after every run (its
                    // arrays would count in the runs' peak memory).
                    roofline_gflops: f64::NAN,
                    pass_share: r.pass_s.map(|p| p / r.wall_s),
                    rebuild_share: r.rebuild_s / r.wall_s,
                    kernel_pass_ns: core_ns_per(0, r.own_pairs),
                    kernel_alone_ns,
                    forces_ns_per_lane: core_ns_per(2, r.fluid_window_lanes),
                    forces_lane_bound_ns,
                    lane_use: r.fluid_listed_lanes as f64 / r.fluid_window_lanes as f64,
                    force_g: r.g_form,
                    pass_lanes: r.pass_lanes,
                    core_ns_per_particle_step: per_step * cores_used / particles as f64 * 1e9,
                    floor_core_ns_per_particle_step: (floor_kernel + floor_forces)
                        / particles as f64,
                    floor_kernel_share: floor_kernel / (floor_kernel + floor_forces),
                    bytes_per_particle: r.bytes as f64 / particles as f64,
                    arrays_bytes: r.bytes,
                    vm_hwm_bytes: vm_hwm_bytes(),
                    neighbour_rebuilds: r.neighbour_rebuilds,
                    ok: r.outcome.is_ok(),
                });
            }
        }
    }
    if opts.bandwidth {
        progress("memory bandwidth (a triad over 3 x 128 MiB)");
        machine.measure_bandwidth()?;
        for row in &mut rows {
            let share = row.threads.min(machine.cores) as f64 / machine.cores as f64;
            row.roofline_gflops = (machine.peak_gflops_in_use * share)
                .min(row.flops_per_byte * machine.bandwidth(row.threads));
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
        scene: if opts.disordered {
            format!(
                "disordered: the steady profile (7) at N = {}, jittered by {} d (seed 1) on a strip \
                 as wide as the channel, run to t = {} (the base, below), then tiled along x to \
                 each particle count; Re = 10, c0 = 10 U, alpha = 0.1, h = d, skin 0.3 h",
                disordered::LAYERS,
                disordered::JITTER,
                disordered::UNTIL_T
            )
        } else {
            "steady profile (7), Re = 10, c0 = 10 U, alpha = 0.1, h = d, skin 0.3 h".to_string()
        },
        rows,
        scaling,
        bases,
    })
}
