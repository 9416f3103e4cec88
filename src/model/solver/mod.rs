//! The 2D SPH solver for plane shear (Poiseuille) flow, generic over the
//! kernel. No I/O: [`run`] takes a resolved [`Problem`] and an observer and
//! returns a [`RunResult`]; `crate::run` dispatches a scene to it by kernel
//! name, `crate::output` writes it. Imports the problem and the kernel only.
//!
//! One step (symplectic kick-drift-kick leapfrog):
//! 1. kick and drift: v += dt/2 a, x += dt v;
//! 2. rebuild the neighbour list if the displacements allow a missed pair;
//! 3. density by summation at the drifted positions, then the EOS;
//! 4. accelerations, with the velocities predicted at the step's end, then
//!    the closing kick v += dt/2 a;
//! 5. the checks for blow-up, every step.

/// Defines `$on(isa, args..)`: `$inner(args..)` compiled for the instruction
/// set `isa` (AVX-512, AVX2 or the baseline), each a `#[target_feature]`
/// copy of the same `#[inline(always)]` body, so the results are the same
/// bits on every CPU; the pair loops ([`step`]) and the list build's
/// loops in lanes ([`neighbours`]) use it. One of the two places the
/// solver meets `unsafe`: calling a target-feature function is sound
/// because [`step::Isa::detect`] found the features before any `Isa`
/// other than `Base` exists. (The other: the kernel pass views its
/// window-lane table as atomics, `density::as_atomic`, so that its tasks
/// can store into it at once.)
macro_rules! on_isa {
    (
        $(#[$attr:meta])*
        $vis:vis fn $on:ident [$($gen:tt)*] => $inner:ident [$($targs:tt)*]
        ($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)?
    ) => {
        $(#[$attr])*
        #[inline(always)]
        $vis fn $on<$($gen)*>(isa: $crate::solver::step::Isa, $($arg: $ty),*) $(-> $ret)? {
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2")]
            unsafe fn avx512<$($gen)*>($($arg: $ty),*) $(-> $ret)? {
                $inner::<$($targs)*>($($arg),*)
            }
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx2")]
            unsafe fn avx2<$($gen)*>($($arg: $ty),*) $(-> $ret)? {
                $inner::<$($targs)*>($($arg),*)
            }
            match isa {
                // SAFETY: an `Isa` other than `Base` comes only from
                // `Isa::detect`, which found the CPU features.
                #[cfg(target_arch = "x86_64")]
                $crate::solver::step::Isa::Avx512 => unsafe { avx512::<$($targs)*>($($arg),*) },
                #[cfg(target_arch = "x86_64")]
                $crate::solver::step::Isa::Avx2 => unsafe { avx2::<$($targs)*>($($arg),*) },
                $crate::solver::step::Isa::Base => $inner::<$($targs)*>($($arg),*),
            }
        }
    };
}

mod diagnostics;
mod frame;
pub mod ideal_shear;
pub mod neighbours;
mod result;
mod step;
mod steps;
pub mod tangent;
pub mod window;

use std::time::Instant;

use crate::kernel::Kernel;
use crate::problem::cost::TimeStep;
use crate::problem::Problem;
use frame::FrameBuf;
use neighbours::{Displacements, Entry, NeighbourList, Reach};
use step::{Forces, IsaPick, Params, Pick, State};

pub use diagnostics::{LayerProfile, Sample};
pub use frame::ParticleFrame;
pub use result::{
    classify, Class, DtLimitSteps, DtStats, Failure, FailureKind, Outcome, Particle, RunResult,
};
pub use steps::{disordered_state, run_steps, run_steps_tiled, FluidState, Stepper, StepsRun};
pub use window::{Regime, Window};

/// Useful floating-point operations of one step per directed pair within
/// the support, given the kernel's own count for W and (dW/dq)/q
/// (`KernelInfo::flops_per_pair`): the kernel and the distance once per
/// pair for both directions (Newton's third law: half per directed pair),
/// the density sum and the force terms per directed pair. Counted by hand
/// in `step/density.rs` and `step/forces.rs`, beside each loop; padding
/// lanes and listed pairs beyond the support are work done but not counted.
pub fn flops_per_pair(kernel_flops: u32, problem: &Problem) -> f64 {
    0.5 * f64::from(kernel_flops + step::DENSITY_DISTANCE_FLOPS)
        + f64::from(step::DENSITY_SUM_FLOPS + force_flops_per_pair(problem))
}

/// The force pass's floating-point operations per directed pair (per lane
/// it runs, listed or not).
pub fn force_flops_per_pair(problem: &Problem) -> u32 {
    let av = if problem.has_artificial_viscosity() {
        step::FORCE_PAIR_FLOPS_AV
    } else {
        step::FORCE_PAIR_FLOPS
    };
    let mirror = if problem.mirrored_walls() {
        step::FORCE_PAIR_FLOPS_MIRROR
    } else {
        0
    };
    av + mirror
}

/// Nanoseconds per evaluation of kernel `K`'s (W, (dW/dq)/q) alone on one
/// core, in lanes as the kernel pass runs it, its values in the first-level
/// cache: the kernel pass's compute roof (`shearsph bench`).
pub fn kernel_alone_ns<K: Kernel>() -> f64 {
    step::kernel_alone_ns::<K>()
}

/// The widest vector instructions the pair loops run with on this CPU
/// (detected at run time; each pair pass runs with them or, picked by its
/// cost, AVX2 under AVX-512; the results are the same bits with any): name
/// and f64 lanes.
pub fn pair_loop_isa() -> (&'static str, u32) {
    step::Isa::detect().describe()
}

/// Receives progress from a running simulation.
pub trait Observer: Send {
    /// After every step.
    fn step(&mut self, _t: f64, _steps: u64) {}
    /// At every output time (t = 0 included), and at a failure or a stop.
    fn output(&mut self, _sample: &Sample) {}
    /// Asked once per step, after it: `true` ends the run there as
    /// [`Outcome::Interrupted`], with a last sample at the time reached.
    fn should_stop(&self) -> bool {
        false
    }
    /// Whether [`Observer::particles`] is wanted: asked once, before the
    /// first output. `false` (the default) costs the run nothing.
    fn wants_particles(&self) -> bool {
        false
    }
    /// Right after every [`Observer::output`], when [`Observer::wants_particles`]:
    /// the particle field at that time (lent; copy what is to be kept).
    fn particles(&mut self, _frame: &ParticleFrame) {}
}

/// An observer that ignores everything.
pub struct Quiet;
impl Observer for Quiet {}

/// Run a resolved problem with kernel `K` on the current rayon pool.
pub fn run<K: Kernel>(problem: &Problem, observer: &mut dyn Observer) -> RunResult {
    // Drive the loop from a worker thread, so each parallel pass is a cheap
    // fork inside the pool rather than a hand-off from outside it.
    rayon::scope(|_| run_in_pool::<K>(problem, observer))
}

/// The state of a run between steps: particles, neighbour list and what
/// the last force pass saw. [`run`] drives it to t_end with outputs;
/// [`bench_steps`] takes a fixed number of steps.
struct Sim<'p> {
    problem: &'p Problem,
    s: State,
    params: Params,
    list: NeighbourList,
    /// Each lattice layer's displacement box and largest |y|, per step.
    motion: Vec<(Displacements, f64)>,
    block: usize,
    skin: f64,
    cutoff: f64,
    forces: Forces,
    max_eps: f64,
    /// Seconds spent in the pair passes so far: the kernel pass, the
    /// density sums, the force pass.
    pass_s: [f64; 3],
    /// The instruction set each of those passes runs with, picked by
    /// their cost (the same bits with any, [`IsaPick`]).
    isas: [IsaPick; 3],
    /// Where the kernel pass leaves (dW/dq)/q for the force pass, where
    /// the list has a lane table ([`step::GForm`]): picked by the two
    /// passes' cost together, its trial after the instruction sets'.
    g_pick: Pick<step::GForm>,
    /// Seconds spent rebuilding the neighbour list during the steps.
    rebuild_s: f64,
    /// Whether a rebuild first stores the fluid band by band
    /// ([`State::reorder`]): always, except where two runs are compared
    /// particle by particle by index ([`tangent`]). The first list keeps
    /// the start's order.
    reorder: bool,
    order: Vec<(u64, u64, u32)>,
    /// How many layers high the bands of a disordered fluid are
    /// ([`band_layers`]).
    band_layers: usize,
    /// The time since the last rebuild, and the Lipschitz constant of
    /// that rebuild's shear reference ([`State::shear_reference`]; 0
    /// without one: the list a run starts with, a fluid at rest, a run
    /// that keeps its start's order): the rebuild rule bounds
    /// displacements from the reference ([`Reach`]).
    since_rebuild: f64,
    shear_rate: f64,
    /// How far ahead along the reference the last rebuild listed the
    /// fluid (a time, [`list_ahead`]; 0 without a reference), and the
    /// positions it listed ([`State::ahead`]).
    ahead: f64,
    x_ahead: Vec<f64>,
    /// Whether rebuilds list the fluid ahead along its reference or where
    /// it is, picked by how long each way's lists would live
    /// ([`Listing`]).
    listing: Listing,
    /// Whether a rebuild takes a shear reference, a lattice's as a
    /// disordered fluid's: always, except in the test that measures what
    /// it saves.
    use_reference: bool,
    /// The force pass's tiles along x ([`step::FORCE_TILE`]): that, except
    /// in the test that checks they change no bit.
    force_tile: usize,
}

/// The share of its largest parting the reference's shear may reach when
/// a list is built ahead ([`list_ahead`]): of 0.5, 0.7, 0.85 and 0.95
/// measured (docs/performance.md, lists built ahead), 0.85 was the best or
/// within a few per cent of it on every scene; at 0.95 the fluid's own
/// agitation spends the little room left at the rebuild.
const AHEAD_SHARE: f64 = 0.85;

/// The pick of where the kernel pass leaves (dW/dq)/q ([`step::GForm`]):
/// the lanes until its first trial, which takes the steps after the
/// instruction sets' trial, so that its forms do not alternate in step
/// with theirs. Which is the quicker is the machine's: on the bench's
/// disordered scene the gather ran 0.86-0.94 times as fast as the lanes at
/// 1e3-1e4 particles on a 2-core Zen 4 (32 MB of last-level cache), and
/// 0.99-1.27 times as fast on a 2-core Xeon with 2 MB of second-level
/// cache a core (docs/performance.md).
fn g_pick() -> Pick<step::GForm> {
    Pick::between([step::GForm::Lanes, step::GForm::Gather], step::PICK_TRIAL)
}

/// How far ahead along the shear reference a rebuild lists the fluid: a
/// time tau. A list built on the positions the reference reaches at tau
/// (x0 + u(y0) tau, [`State::ahead`]) holds every pair within the cutoff
/// there; the rule then bounds the reference's parting from tau, Lip |t -
/// tau| ([`Reach`]), not from the rebuild, so the list lives until the
/// parting from tau has spent the slack on either side of it. The parting
/// that spends all the slack is L* = (C^2 - (Rh)^2) / (C Rh) (where
/// [`Reach::slack`] is 0, C the cutoff, Rh = C - skin); tau =
/// [`AHEAD_SHARE`] L* / Lip leaves the list at the rebuild that share of
/// it, and lets it run to (1 + share) L* / Lip where the reference alone
/// limits it. The reference is 0 at the no-slip planes, so |u| <= Lip B and
/// a particle goes at most share L* B ahead. 0 without a reference
/// (`shear_rate` 0) or a skin, and where tau overflows (a subnormal
/// `shear_rate`: u tau would be inf or NaN, 0 x inf, at the planes): that
/// list is built where the fluid is, with the rule from the rebuild.
///
/// At the rebuild such a list has only the slack left at a parting of
/// [`AHEAD_SHARE`] L*, a few hundredths of h, where a list built where the
/// fluid is has the whole skin. A fluid agitated enough to spend that
/// early lives longer listed where it is: [`Listing`] picks between the
/// two ways.
fn list_ahead(cutoff: f64, skin: f64, shear_rate: f64) -> f64 {
    let support = cutoff - skin;
    let limit = (cutoff * cutoff - support * support) / (cutoff * support);
    let tau = AHEAD_SHARE * limit / shear_rate;
    if shear_rate > 0.0 && limit > 0.0 && tau.is_finite() {
        tau
    } else {
        0.0
    }
}

/// How far the shear reference (Lipschitz constant `shear_rate`) may have
/// parted two particles, per unit of their distance in y, `since` the
/// rebuild, from where a list built `ahead` ([`list_ahead`]) listed them:
/// `shear_rate` |since - ahead| ([`Reach`]). Never 0 with a reference,
/// whose rounding the slack's margin covers; 0 without one (the rule of a
/// lattice, [`Reach::slack`]).
fn parting(shear_rate: f64, since: f64, ahead: f64) -> f64 {
    if shear_rate > 0.0 {
        (shear_rate * (since - ahead).abs()).max(f64::MIN_POSITIVE)
    } else {
        0.0
    }
}

/// Whether rebuilds list the fluid ahead along its reference
/// ([`list_ahead`]) or where it is, picked by how long each way's lists
/// would live. Either way the rule keeps every pair within R h listed
/// ([`Reach`]), so the pick misses no pair: it changes only when the
/// lists are rebuilt (and so the order of a run's sums). The other way's
/// list, had the rebuild built it, is weighed at every step by the same
/// rule on the same boxes, from its own tau (the reference's parting from
/// it, [`parting`]): where that rule has not found it stale when this
/// list goes stale, the other way would have outlived this list. After
/// [`Listing::SWITCH`] lists running that the other way would have
/// outlived, the rebuilds take it. Runs start listing ahead, which nearly
/// doubles a lattice's lists' lives; a run in which no switch happens is
/// the same, bit for bit, as with lists built ahead throughout.
///
/// Where it switches (docs/performance.md, an agitated fluid): a wide
/// strip of a disordered fluid, whose layers hold the extremes of many
/// particles' agitation, spends the few hundredths of h a list built ahead
/// has at its rebuild within a step or two (the composite kernel on 144
/// columns at Re = 10, and the bench's tiled scene of it after about 1600
/// steps); a lattice that is losing its order does so within a fraction of
/// its tau. Where a list built where the fluid is then lives less long
/// than one built ahead would have, the rebuilds go back.
#[derive(Debug, Clone, Copy)]
struct Listing {
    /// Whether rebuilds list the fluid ahead.
    ahead: bool,
    /// Whether the other way's list would have gone stale by now.
    other_stale: bool,
    /// The lists running, up to this one, that the other way's would have
    /// outlived.
    outlived: u32,
}

impl Listing {
    /// Counted over the `c0 --empirical` runs at N = 10, Re = 1 and 10,
    /// of the four kernels (390 runs, 2.0e5 lists, docs/performance.md):
    /// the other way would have outlived 8 or more lists running in 15
    /// runs, all the composite kernel's or Wendland C2's (4 or more in
    /// 30); in the bench's disordered scene at 1e3 and 1e4, 5 at most. A
    /// streak of 8 is the fluid's state, not chance, and changes the
    /// fewest runs.
    const SWITCH: u32 = 8;

    fn new() -> Self {
        Listing {
            ahead: true,
            other_stale: false,
            outlived: 0,
        }
    }

    /// Whether the other way's list is still to be weighed: until it
    /// would have gone stale.
    fn asking(&self) -> bool {
        !self.other_stale
    }

    /// A step of the list: whether the other way's would be stale now
    /// (weighed at the same step as this list, so that both stale at one
    /// step is no life outlived).
    fn observe(&mut self, stale: bool) {
        self.other_stale |= stale;
    }

    /// The list went stale: whether the other way's, `compared` at each of
    /// its steps, would have outlived it; the pick for the next list.
    fn rebuilt(&mut self, compared: bool) {
        if compared && !self.other_stale {
            self.outlived += 1;
        } else {
            self.outlived = 0;
        }
        if self.outlived >= Self::SWITCH {
            self.ahead = !self.ahead;
            self.outlived = 0;
        }
        self.other_stale = false;
    }
}

/// How many layers high the bands are that a disordered fluid is stored in
/// ([`State::reorder`]): as many as make a row of a particle's neighbours
/// fill the force pass's window of LANES consecutive indices
/// ([`neighbours::Window`]). A band k layers high holds about k particles a
/// spacing d of x, and a row of neighbours spans up to 2 cutoffs of x: k =
/// LANES d / (2 cutoff), rounded, at least 1 (2 for the cutoffs near 2.3 d
/// of R = 2 h at h = d, 1 for R = 3 h).
fn band_layers(lat: &crate::problem::lattice::LatticeGeometry, cutoff: f64) -> usize {
    let k = (neighbours::LANES as f64 * lat.d / (2.0 * cutoff)).round();
    if k >= 1.0 {
        k as usize
    } else {
        1
    }
}

/// The low edge of the bands a rebuild stores the fluid in
/// ([`State::reorder`], [`State::shear_reference`]): bands one layer
/// spacing high centred on the layers, the first on the plane y = -B.
fn bands_low(lat: &crate::problem::lattice::LatticeGeometry) -> f64 {
    -lat.b() - 0.5 * lat.dy
}

/// What one step found that may end the run.
struct StepCheck {
    max_abs_y: f64,
}

impl<'p> Sim<'p> {
    /// Particles in place, the first neighbour list, density and forces.
    fn new<K: Kernel>(problem: &'p Problem) -> Self {
        Self::with_state::<K>(problem, State::new(&problem.lattice, problem), false)
    }

    /// [`Sim::new`] from a state other than the problem's start (for
    /// [`steps::run_steps_tiled`]): its list, density and forces. A
    /// `banded` state (a disordered fluid's) is first stored in bands as
    /// a rebuild stores it ([`State::reorder`]).
    fn with_state<K: Kernel>(problem: &'p Problem, mut s: State, banded: bool) -> Self {
        let lat = problem.lattice;
        let h = lat.h;
        let params = Params::new(problem);
        let skin = problem.skin * h;
        let cutoff = K::SUPPORT2_CLOSED.sqrt() * h + skin;
        // Blocks for the rebuild rule: the lattice layers, stored in turn.
        let block = lat.columns as usize;
        let band_layers = band_layers(&lat, cutoff);
        let mut list = NeighbourList::default();
        s.wrap(lat.width);
        if banded {
            s.reorder(bands_low(&lat), lat.dy, band_layers, block, &mut Vec::new());
        }
        list.build(&s.x, &s.y, lat.width, cutoff, block);
        // Marked as the rebuild that stored it in bands marked it, for the
        // force pass ([`step::forces_in_tiles`]); after this first build,
        // so that the build's form and its measures are those of a start.
        list.set_disordered(banded);
        let max_eps = step::density::<K>(&mut s, &list, &params);
        let forces = step::forces(&mut s, &list, &params, 0.0, step::Isa::detect());
        Sim {
            problem,
            s,
            params,
            list,
            motion: Vec::with_capacity(lat.fluid_layers() as usize),
            block,
            skin,
            cutoff,
            forces,
            max_eps,
            pass_s: [0.0; 3],
            isas: std::array::from_fn(|_| IsaPick::new()),
            g_pick: g_pick(),
            rebuild_s: 0.0,
            reorder: true,
            order: Vec::new(),
            band_layers,
            since_rebuild: 0.0,
            shear_rate: 0.0,
            ahead: 0.0,
            x_ahead: Vec::new(),
            listing: Listing::new(),
            use_reference: true,
            force_tile: step::FORCE_TILE,
        }
    }

    /// The tau the other way of listing would have taken at the last
    /// rebuild ([`Listing`]): 0 for a list built ahead, [`list_ahead`]'s
    /// for one built where the fluid is; none without a reference, or
    /// where both ways are one (no tau to build ahead by).
    fn other_ahead(&self) -> Option<f64> {
        if self.shear_rate <= 0.0 {
            None
        } else if self.ahead > 0.0 {
            Some(0.0)
        } else {
            let tau = list_ahead(self.cutoff, self.skin, self.shear_rate);
            (tau > 0.0).then_some(tau)
        }
    }

    /// The time step the last forces allow.
    fn time_step(&self) -> TimeStep {
        let p = self.problem;
        TimeStep::with(
            p.dt_factors,
            p.lattice.h,
            p.c0,
            p.flow.nu,
            self.forces.v_max,
            self.forces.a_max,
        )
    }

    /// One step of length dt: kick and drift, rebuild the list if it may
    /// miss a pair, density, forces and the closing kick.
    fn advance<K: Kernel>(&mut self, dt: f64) -> StepCheck {
        let lat = &self.problem.lattice;
        self.since_rebuild += dt;
        let since = self.since_rebuild;
        let reference = (self.shear_rate > 0.0).then_some(since);
        step::kick_drift(&mut self.s, dt, reference, self.block, &mut self.motion);
        let max_abs_y = self.motion.iter().fold(0.0f64, |m, b| m.max(b.1));
        let motion = &self.motion;
        let reach = Reach {
            skin: self.skin,
            cutoff: self.cutoff,
            parting: parting(self.shear_rate, since, self.ahead),
        };
        let box_of = |b: usize| motion.get(b).map_or(Displacements::ZERO, |m| m.0);
        // The other way's list, built at the same rebuild, weighed by the
        // same rule on the same boxes from the tau it would have taken,
        // until it would have gone stale.
        let other = self.other_ahead();
        let stale = match other.filter(|_| self.listing.asking()) {
            Some(tau) => {
                let other = Reach {
                    parting: parting(self.shear_rate, since, tau),
                    ..reach
                };
                let [this, that] = self.list.stale_each(box_of, [reach, other]);
                self.listing.observe(that);
                this
            }
            None => self.list.stale(box_of, reach),
        };
        if stale {
            let start = Instant::now();
            self.listing.rebuilt(other.is_some());
            self.s.wrap(lat.width);
            self.since_rebuild = 0.0;
            self.shear_rate = 0.0;
            if self.reorder {
                // Bands one layer spacing high, centred on the lattice's
                // layers: a layer that has kept its place is one band. A
                // disordered fluid's are `band_layers` of them.
                let low = bands_low(lat);
                let moved =
                    self.s
                        .reorder(low, lat.dy, self.band_layers, self.block, &mut self.order);
                // Particles that moved in storage have left their lattice:
                // the list is built in its disordered form (the same list).
                // The rule bounds displacements from the shear of the bands
                // either way: a lattice's bands are its layers, whose shear
                // it follows as closely as a disordered fluid's.
                self.list.set_disordered(moved);
                self.shear_rate = if self.use_reference {
                    self.s.shear_reference(low, lat.dy, lat.b())
                } else {
                    self.s.u_ref.fill(0.0);
                    0.0
                };
            }
            // A fluid with a reference is listed ahead along it, while that
            // pays.
            self.ahead = if self.listing.ahead {
                list_ahead(self.cutoff, self.skin, self.shear_rate)
            } else {
                0.0
            };
            let x = if self.ahead > 0.0 {
                self.s.ahead(self.ahead, lat.width, &mut self.x_ahead);
                &self.x_ahead
            } else {
                &self.s.x
            };
            self.list
                .build(x, &self.s.y, lat.width, self.cutoff, self.block);
            self.rebuild_s += start.elapsed().as_secs_f64();
        }
        let [kernel_isa, sums_isa, forces_isa] = self.isas.each_ref().map(IsaPick::next);
        // A list without a lane table gathers, and its steps measure
        // nothing for the pick.
        let g_form = if self.list.lane_table() {
            self.g_pick.next()
        } else {
            step::GForm::Gather
        };
        if !self.list.lane_table() || !self.g_pick.trying() {
            // The other form's table holds no memory until the next trial.
            self.s.free_g_but(g_form);
        }
        let start = Instant::now();
        step::kernel_pass::<K>(&mut self.s, &self.list, &self.params, kernel_isa, g_form);
        let kernel = Instant::now();
        self.max_eps = step::density_sums::<K>(&mut self.s, &self.list, &self.params, sums_isa);
        let sums = Instant::now();
        self.forces = step::forces_in_tiles(
            &mut self.s,
            &self.list,
            &self.params,
            0.5 * dt,
            forces_isa,
            self.force_tile,
        );
        let end = Instant::now();
        for ((acc, pick), (a, b)) in self.pass_s.iter_mut().zip(&mut self.isas).zip([
            (start, kernel),
            (kernel, sums),
            (sums, end),
        ]) {
            let seconds = (b - a).as_secs_f64();
            *acc += seconds;
            pick.record(seconds);
        }
        if self.list.lane_table() {
            let seconds = (kernel - start) + (end - sums);
            self.g_pick.record(seconds.as_secs_f64());
        } else {
            self.g_pick.skip();
        }
        StepCheck { max_abs_y }
    }

    /// The failure this step ended in, if any.
    fn failure(&self, check: &StepCheck) -> Option<Failure> {
        let p = self.problem;
        let b = p.lattice.b();
        if !self.forces.finite {
            Some(Failure::NotFinite)
        } else if self.forces.v_max > p.v_limit {
            Some(Failure::Speed {
                v: self.forces.v_max,
                limit: p.v_limit,
            })
        } else if check.max_abs_y >= b {
            Some(Failure::ThroughWall {
                y: check.max_abs_y,
                b,
            })
        } else if self.max_eps > p.eps_limit {
            Some(Failure::Compaction {
                eps: self.max_eps,
                limit: p.eps_limit,
            })
        } else {
            None
        }
    }

    /// The fluid particle that triggered `failure` (see [`Particle`]): a
    /// sequential scan of the state, made only once a failure is seen.
    fn culprit(&self, failure: &Failure) -> Particle {
        let s = &self.s;
        let fluid = 0..s.n_fluid;
        let speed2 = |i: usize| s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i];
        // The first fluid particle of largest `key` (a NaN key never wins).
        let largest = |key: &dyn Fn(usize) -> f64| {
            fluid
                .clone()
                .fold(0, |best, i| if key(i) > key(best) { i } else { best })
        };
        let i = match failure {
            // The force pass's own test (which also catches a square that
            // overflows), so the particle it flagged is found; then the
            // positions and the density.
            Failure::NotFinite => fluid
                .clone()
                .find(|&i| {
                    let a2 = s.ax[i] * s.ax[i] + s.ay[i] * s.ay[i];
                    !((a2 + speed2(i)).is_finite()
                        && s.x[i].is_finite()
                        && s.y[i].is_finite()
                        && s.rho[i].is_finite())
                })
                .unwrap_or(0),
            Failure::Speed { .. } => largest(&speed2),
            Failure::ThroughWall { .. } => largest(&|i| s.y[i].abs()),
            Failure::Compaction { .. } => largest(&|i| s.rho[i]),
        };
        Particle {
            index: s.id[i] as usize,
            layer: s.layer[i],
            // In the strip: x runs on past its edges between list rebuilds.
            x: s.x[i].rem_euclid(self.problem.lattice.width),
            y: s.y[i],
            vx: s.vx[i],
            vy: s.vy[i],
        }
    }

    fn sample(&self, t: f64, steps: u64, dt: f64) -> Sample {
        diagnostics::sample(self.problem, &self.s, t, steps, dt)
    }

    /// Directed pairs (i, j) within the kernel's support now: the pair
    /// evaluations a step makes. Sequential; for benchmarks.
    fn pairs_in_support<K: Kernel>(&self) -> usize {
        let (x, y) = (&self.s.x, &self.s.y);
        let inv_h2 = self.params.inv_h2;
        (0..x.len())
            .map(|i| {
                let width = self.list.width();
                self.list
                    .of(i)
                    .iter()
                    .filter(|&&e| {
                        let j = Entry::index(e);
                        let dx = x[i] - x[j] + Entry::offset(e, width);
                        let dy = y[i] - y[j];
                        (dx * dx + dy * dy) * inv_h2 <= K::SUPPORT2_CLOSED
                    })
                    .count()
            })
            .sum()
    }

    /// Bytes the pair passes of one step move at the least: every array
    /// they read or write once (a neighbour's values gathered from cache
    /// after the first touch are not counted again). The kernel pass reads
    /// the pair table's entries and owners (4 + 4 per own pair), each
    /// pair's two window lanes (4 + 4) and x, y, and writes W (8) and
    /// (dW/dq)/q into both lanes (8 + 8); the density sum reads each padded
    /// slot's source and W (4 + 8) and writes rho, P, m/rho, P/rho^2; the
    /// force pass reads each window (its start and lanes, 8) and its
    /// lanes' (dW/dq)/q (8 a lane), the particle arrays x, y, vx, vy
    /// predicted, P, m/rho (and the wall depth), and reads and writes the
    /// fluid's rho, v and a. Steps that leave (dW/dq)/q in the pair table
    /// ([`step::GForm::Gather`], as [`Self::g_form`] says the steps after
    /// the last trial did): the kernel pass writes (dW/dq)/q
    /// once a pair (8) and reads no lanes, and the force pass reads each
    /// window's sources (4 a lane) and the pair table's (dW/dq)/q (8 a
    /// pair) instead of the lanes' values.
    fn pass_bytes(&self) -> f64 {
        let (n, nf) = (self.s.x.len() as f64, self.s.n_fluid as f64);
        let own = self.list.own_pairs() as f64;
        let padded: f64 = (0..self.s.x.len())
            .map(|i| self.list.sources_padded(i).len() as f64)
            .sum();
        let windows = self.list.window_count() as f64;
        let depth = if self.params.mirror_walls { 8.0 } else { 0.0 };
        let lane_table = self.g_form() == step::GForm::Lanes;
        let kernel = own * if lane_table { 40.0 } else { 24.0 } + 16.0 * n;
        let sum = padded * 12.0 + 4.0 * n + 32.0 * n;
        let window = size_of::<crate::solver::neighbours::Window>() as f64;
        // A window's lanes' (dW/dq)/q, or their sources and the pair table.
        let lanes = crate::solver::neighbours::LANES as f64;
        let g = if lane_table {
            windows * lanes * 8.0
        } else {
            windows * lanes * 4.0 + own * 8.0
        };
        let forces = windows * window + g + (48.0 + depth) * n + (8.0 + 32.0 + 16.0) * nf;
        kernel + sum + forces
    }

    /// Where the steps after the last trial leave (dW/dq)/q.
    fn g_form(&self) -> step::GForm {
        if self.list.lane_table() {
            self.g_pick.chosen()
        } else {
            step::GForm::Gather
        }
    }

    /// Bytes held by the particle arrays and the neighbour structure.
    fn bytes(&self) -> usize {
        self.s.bytes()
            + self.list.bytes()
            + self.motion.capacity() * size_of::<(Displacements, f64)>()
            + self.order.capacity() * size_of::<(u64, u64, u32)>()
            + self.x_ahead.capacity() * size_of::<f64>()
    }
}

fn run_in_pool<K: Kernel>(problem: &Problem, observer: &mut dyn Observer) -> RunResult {
    let start = Instant::now();
    let mut sim = Sim::new::<K>(problem);
    let mean_neighbours = sim.list.pairs() as f64 / sim.s.x.len() as f64;
    let mut max_eps_run = sim.max_eps;
    let mut dt_stats = DtStats::new(&sim.time_step());

    let mut frames = observer.wants_particles().then(FrameBuf::default);
    let mut samples = Vec::new();
    let mut observe =
        |sim: &Sim, sample: Sample, observer: &mut dyn Observer, samples: &mut Vec<Sample>| {
            observer.output(&sample);
            if let Some(buf) = frames.as_mut() {
                observer.particles(&buf.frame(&sim.s, sim.problem, sample.t));
            }
            samples.push(sample);
        };
    observe(
        &sim,
        sim.sample(0.0, 0, dt_stats.last),
        observer,
        &mut samples,
    );

    let t_end = problem.t_end;
    let mut t = 0.0;
    let mut steps = 0u64;
    let mut outputs_done = 0u64;
    // Output k (from 0) at (k + 1) intervals; the last one at t_end exactly,
    // also when t_end is a multiple of the interval up to round-off.
    let next_output = |k: u64| {
        let t = (k + 1) as f64 * problem.output_interval;
        if t >= t_end * (1.0 - 1e-9) {
            t_end
        } else {
            t
        }
    };
    let mut outcome = Outcome::Ok;
    while t < t_end {
        let ts = sim.time_step();
        let target = next_output(outputs_done);
        let landing = t + ts.dt >= target;
        let dt = if landing { target - t } else { ts.dt };
        if !landing {
            dt_stats.record(&ts);
        }

        let check = sim.advance::<K>(dt);
        max_eps_run = max_eps_run.max(sim.max_eps);
        t = if landing { target } else { t + dt };
        steps += 1;
        observer.step(t, steps);

        if let Some(failure) = sim.failure(&check) {
            observe(&sim, sim.sample(t, steps, dt), observer, &mut samples);
            outcome = Outcome::Failed {
                particle: sim.culprit(&failure),
                failure,
                t,
                step: steps,
            };
            break;
        }
        if landing {
            outputs_done += 1;
            observe(
                &sim,
                sim.sample(t, steps, dt_stats.last),
                observer,
                &mut samples,
            );
            // A stationary horizon ends at the first checkpoint whose
            // window is stationary.
            if problem.horizon.may_stop_at(t) {
                let (from, to) = problem.horizon.window(t);
                if window::window(&samples, from, to, problem.flow.u).stationary {
                    break;
                }
            }
        }
        if observer.should_stop() {
            // The last sample at the time reached, unless this step took it.
            if !landing {
                observe(
                    &sim,
                    sim.sample(t, steps, dt_stats.last),
                    observer,
                    &mut samples,
                );
            }
            outcome = Outcome::Interrupted { t, step: steps };
            break;
        }
    }

    let (from, to) = problem.horizon.window(t);
    RunResult {
        window: window::window(&samples, from, to, problem.flow.u),
        t_disorder: window::t_disorder(&samples),
        problem: problem.clone(),
        kernel: K::NAME,
        n_fluid: sim.s.n_fluid,
        n_wall: sim.s.x.len() - sim.s.n_fluid,
        steps,
        t,
        dt: dt_stats,
        outcome,
        samples,
        max_eps_run,
        neighbour_rebuilds: sim.list.rebuilds,
        mean_neighbours,
        wall_s: start.elapsed().as_secs_f64(),
    }
}
