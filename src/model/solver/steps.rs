//! Steps without the run loop's outputs: one at a time ([`Stepper`], for
//! the criterion benchmarks) or a fixed number timed ([`run_steps`], for
//! `shearsph bench`), on the same [`Sim`] as [`super::run`].

use std::marker::PhantomData;
use std::time::Instant;

use serde::Serialize;

use super::step::State;
use super::{neighbours, Failure, Outcome, Sample, Sim};
use crate::kernel::Kernel;
use crate::problem::Problem;

/// One step at a time, for benchmarks (`benches/step.rs`): the set-up on
/// creation, then each [`Stepper::step`] is one full step of the solver's
/// loop (kick and drift, neighbour list when stale, density, forces), its
/// length from the limits.
pub struct Stepper<'p, K: Kernel> {
    sim: Sim<'p>,
    kernel: PhantomData<K>,
}

impl<'p, K: Kernel> Stepper<'p, K> {
    pub fn new(problem: &'p Problem) -> Self {
        Stepper {
            sim: Sim::new::<K>(problem),
            kernel: PhantomData,
        }
    }

    /// One step; returns the failure it ended in, if any.
    pub fn step(&mut self) -> Option<Failure> {
        let dt = self.sim.time_step().dt;
        let check = self.sim.advance::<K>(dt);
        self.sim.failure(&check)
    }

    /// Fluid and wall particles.
    pub fn particles(&self) -> usize {
        self.sim.s.x.len()
    }
}

/// A fixed number of steps, timed: what `shearsph bench` measures.
#[derive(Debug, Clone, Serialize)]
pub struct StepsRun {
    pub kernel: &'static str,
    pub n_fluid: usize,
    pub n_wall: usize,
    /// Steps taken (fewer than asked only if the run failed).
    pub steps: u64,
    /// Wall-clock seconds of the steps alone (set-up excluded).
    pub wall_s: f64,
    /// Directed pairs within the support per step (mean of the first and
    /// the last state): kernel evaluations W and (dW/dq)/q per step.
    pub pairs_per_step: f64,
    /// Directed pairs listed (R h + skin) at the end.
    pub listed_pairs: usize,
    pub neighbour_rebuilds: u64,
    /// Bytes of the particle arrays and the neighbour structure.
    pub bytes: usize,
    /// Wall-clock seconds of the steps spent in the pair passes (density
    /// and forces), and the bytes they move per step at the least (every
    /// array they touch once, at the end; see `Sim::pass_bytes`).
    pub pair_loop_s: f64,
    /// Those seconds pass by pass: the kernel pass (W and (dW/dq)/q of the
    /// own pairs), the density sums (W gathered per slot, the EOS), the
    /// force pass.
    pub pass_s: [f64; 3],
    /// The f64 lanes of the vectors each of those passes ran with at the
    /// end (the instruction set its cost picked, `IsaPick`).
    pub pass_lanes: [u32; 3],
    /// Wall-clock seconds of the steps spent rebuilding the neighbour list
    /// (with wrapping x into the strip).
    pub rebuild_s: f64,
    /// At the end: the pairs the kernel pass evaluates per step (each once
    /// for both directions), and the lanes the force pass runs per step
    /// (LANES per window of the fluid's, listed or not).
    pub own_pairs: usize,
    pub fluid_window_lanes: usize,
    /// Of those lanes, the listed ones.
    pub fluid_listed_lanes: usize,
    /// Where the steps after the last trial left (dW/dq)/q for the force
    /// pass: the window lanes or the pair table ([`super::step::GForm`], as its
    /// cost picked where the last list had a lane table): its name,
    /// "lanes" or "pairs".
    pub g_form: &'static str,
    pub pass_bytes_per_step: f64,
    pub outcome: Outcome,
    /// Diagnostics after the last step (against the start-up series when
    /// started from rest, the steady profile when started steady).
    pub last: Sample,
}

/// Take `steps` steps of the resolved problem with kernel `K` (each as long
/// as the limits allow), on the current rayon pool, and time them. Stops
/// early at a failure.
pub fn run_steps<K: Kernel>(problem: &Problem, steps: u64) -> StepsRun {
    rayon::scope(|_| timed::<K>(Sim::new::<K>(problem), steps))
}

/// The fluid's state at the end of a run of `problem` to `until_t`, for
/// [`run_steps_tiled`]: positions, velocities and predicted velocities, in
/// storage order, and how the run went.
#[derive(Debug, Clone)]
pub struct FluidState {
    /// The strip's columns and width.
    pub columns: u32,
    pub width: f64,
    /// Time reached and steps taken (fewer than asked if it failed).
    pub t: f64,
    pub steps: u64,
    /// The failure the run ended in, if any.
    pub failure: Option<Failure>,
    /// Diagnostics at the end: dy_rms says whether the lattice's order is
    /// gone.
    pub last: Sample,
    x: Vec<f64>,
    y: Vec<f64>,
    vx: Vec<f64>,
    vy: Vec<f64>,
    v_pred_x: Vec<f64>,
    v_pred_y: Vec<f64>,
    /// The layer each particle started in.
    layer: Vec<i32>,
    /// Whether the last rebuild stored the fluid in bands of y, its
    /// lattice's order lost ([`State::reorder`]).
    banded: bool,
}

/// Run `problem` with kernel `K` from its start to `until_t`, on the
/// current rayon pool (a jittered start run into its disordered state:
/// `bench --disordered`); stops early at a failure.
pub fn disordered_state<K: Kernel>(problem: &Problem, until_t: f64) -> FluidState {
    rayon::scope(|_| {
        let mut sim = Sim::new::<K>(problem);
        let (mut t, mut steps, mut dt, mut failure) = (0.0, 0, 0.0, None);
        while t < until_t && failure.is_none() {
            dt = sim.time_step().dt;
            let check = sim.advance::<K>(dt);
            t += dt;
            steps += 1;
            failure = sim.failure(&check);
        }
        let nf = sim.s.n_fluid;
        let fluid = |v: &[f64]| v[..nf].to_vec();
        FluidState {
            columns: problem.lattice.columns,
            width: problem.lattice.width,
            t,
            steps,
            failure,
            last: sim.sample(t, steps, dt),
            x: fluid(&sim.s.x),
            y: fluid(&sim.s.y),
            vx: fluid(&sim.s.vx),
            vy: fluid(&sim.s.vy),
            v_pred_x: fluid(&sim.s.v_pred_x),
            v_pred_y: fluid(&sim.s.v_pred_y),
            layer: sim.s.layer[..nf].to_vec(),
            banded: sim.list.disordered(),
        }
    })
}

/// `base` tiled along x into `problem` (its scene on a strip a whole
/// number of `base`'s strips wide: the same layers, kernel and flow), and
/// `steps` steps of it timed, on the current rayon pool. The base is
/// stored in blocks of C particles (its lattice layers, or the bands of y
/// of its last rebuild, [`State::reorder`]); copy m of the base's particle
/// (block b, place c) is the tiled state's particle (block b, place
/// m C + c), moved by m times the base strip's width: every copy is the
/// base's state, so every size has the base's neighbours per particle,
/// the same scatter of their indices (copies of one block are stored
/// together, as the lattice stores a layer; a base stored in bands of y
/// is stored in bands again, as a rebuild of the tiled fluid stores it)
/// and the same rebuilds per step. The walls are the tiled lattice's own,
/// which are the base's repeated.
///
/// Panics if `problem`'s lattice is not `base`'s tiled.
pub fn run_steps_tiled<K: Kernel>(problem: &Problem, base: &FluidState, steps: u64) -> StepsRun {
    let lat = problem.lattice;
    let (c, n) = (base.columns as usize, lat.columns as usize);
    assert!(
        n.is_multiple_of(c) && base.x.len().is_multiple_of(c),
        "{n} columns are not whole copies of {c}"
    );
    let (copies, layers) = (n / c, base.x.len() / c);
    assert_eq!(layers * n, lat.n_fluid(), "the base's fluid layers");
    let mut s = State::new(&lat, problem);
    for layer in 0..layers {
        for m in 0..copies {
            for col in 0..c {
                let (i, k) = (layer * c + col, layer * n + m * c + col);
                s.x[k] = base.x[i] + m as f64 * base.width;
                s.y[k] = base.y[i];
                s.vx[k] = base.vx[i];
                s.vy[k] = base.vy[i];
                s.v_pred_x[k] = base.v_pred_x[i];
                s.v_pred_y[k] = base.v_pred_y[i];
                s.layer[k] = base.layer[i];
            }
        }
    }
    rayon::scope(|_| timed::<K>(Sim::with_state::<K>(problem, s, base.banded), steps))
}

/// `steps` steps of `sim`, timed.
fn timed<K: Kernel>(mut sim: Sim, steps: u64) -> StepsRun {
    let pairs_first = sim.pairs_in_support::<K>();
    let rebuilds_first = sim.list.rebuilds;
    sim.pass_s = [0.0; 3];
    sim.rebuild_s = 0.0;
    let mut t = 0.0;
    let mut taken = 0;
    let mut dt = 0.0;
    let mut outcome = Outcome::Ok;
    let start = Instant::now();
    while taken < steps {
        dt = sim.time_step().dt;
        let check = sim.advance::<K>(dt);
        t += dt;
        taken += 1;
        if let Some(failure) = sim.failure(&check) {
            outcome = Outcome::Failed {
                particle: sim.culprit(&failure),
                failure,
                t,
                step: taken,
            };
            break;
        }
    }
    let wall_s = start.elapsed().as_secs_f64();
    let pairs_last = sim.pairs_in_support::<K>();
    StepsRun {
        kernel: K::NAME,
        n_fluid: sim.s.n_fluid,
        n_wall: sim.s.x.len() - sim.s.n_fluid,
        steps: taken,
        wall_s,
        pairs_per_step: 0.5 * (pairs_first + pairs_last) as f64,
        listed_pairs: sim.list.pairs(),
        neighbour_rebuilds: sim.list.rebuilds - rebuilds_first,
        bytes: sim.bytes(),
        pair_loop_s: sim.pass_s.iter().sum(),
        pass_s: sim.pass_s,
        pass_lanes: sim.isas.each_ref().map(|p| p.chosen().describe().1),
        rebuild_s: sim.rebuild_s,
        own_pairs: sim.list.own_pairs(),
        fluid_window_lanes: (0..sim.s.n_fluid)
            .map(|i| sim.list.windows(i).len())
            .sum::<usize>()
            * neighbours::LANES,
        fluid_listed_lanes: (0..sim.s.n_fluid)
            .flat_map(|i| sim.list.windows(i))
            .map(|w| w.mask().count_ones() as usize)
            .sum(),
        g_form: sim.g_form().name(),
        pass_bytes_per_step: sim.pass_bytes(),
        outcome,
        last: sim.sample(t, taken, dt),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Scene;
    use crate::kernels::Monaghan;

    /// A state tiled three times is three copies of it: three times the
    /// fluid and the listed pairs (the same geometry repeated), the same
    /// statistics of the layers and the compaction (its mean and largest;
    /// a percentile interpolates between other neighbours in a set three
    /// times as large).
    #[test]
    fn a_tiled_state_is_copies_of_its_base() {
        let mut scene = Scene {
            kernel: "monaghan".into(),
            n_layers: 6,
            re: Some(10.0),
            p: None,
            jitter: 0.05,
            jitter_seed: 1,
            ..Scene::builtin()
        };
        let base = Problem::resolve(&scene, Monaghan::INFO).expect("the base");
        let state = disordered_state::<Monaghan>(&base, 30.0);
        assert!(state.failure.is_none() && state.t >= 30.0);
        scene.columns = Some(3 * base.lattice.columns);
        let tiled = Problem::resolve(&scene, Monaghan::INFO).expect("tiled");
        let one = run_steps_tiled::<Monaghan>(&base, &state, 0);
        let three = run_steps_tiled::<Monaghan>(&tiled, &state, 0);
        assert_eq!(three.n_fluid, 3 * one.n_fluid);
        assert_eq!(three.listed_pairs, 3 * one.listed_pairs);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * a.abs().max(b.abs());
        assert!(
            close(one.last.dy_rms, state.last.dy_rms),
            "the base's own state"
        );
        assert!(close(three.last.dy_rms, one.last.dy_rms));
        assert!(close(three.last.mean_eps, one.last.mean_eps));
        assert!(close(three.last.max_eps, one.last.max_eps));
    }
}

#[cfg(test)]
mod reorder_tests {
    use super::*;
    use crate::config::{Initial, Scene};
    use crate::kernel::Lattice;
    use crate::kernels::Composite;
    use crate::problem::lattice::LatticeGeometry;
    use crate::solver::neighbours::{Entry, LANE_TABLE_MAX_BYTES};
    use crate::solver::step::{every_isa, GForm, Isa, IsaPick, Pick};

    /// The composite kernel on the square lattice at h = d, from rest:
    /// its lattice disorders by t = 11, so the rebuilds after that store
    /// the fluid again band by band ([`State::reorder`]).
    fn disordering() -> Problem {
        let scene = Scene {
            kernel: "composite".into(),
            n_layers: 8,
            re: Some(10.0),
            alpha: 0.0,
            lattice: Lattice::Square,
            h_over_d: 1.0,
            c0: "rule10".parse().expect("a rule"),
            initial: Initial::Rest,
            eps_limit: 0.5,
            ..Scene::builtin()
        };
        Problem::resolve(&scene, Composite::INFO).expect("the scene")
    }

    /// The lattice of [`disordering`] and its start, with what a reorder
    /// of it takes: the blocks' size (its columns) and the bands' low
    /// edge ([`super::super::bands_low`]).
    fn start() -> (LatticeGeometry, State, usize, f64) {
        let problem = disordering();
        let lat = problem.lattice;
        let s = State::new(&lat, &problem);
        (lat, s, lat.columns as usize, super::super::bands_low(&lat))
    }

    /// The fluid's state and ids after `until_t`, on `threads` threads.
    fn state_after(problem: &Problem, until_t: f64, threads: usize) -> (Vec<f64>, Vec<u32>) {
        state_after_with(problem, until_t, threads, None, None, None)
    }

    /// [`state_after`] with lists of at most `lane_table_max` bytes of
    /// window-lane table ([`NeighbourList::lane_table`]), the first list
    /// included, with every pair pass on the instruction set `isa`, and
    /// (dW/dq)/q left in `form`, instead of the ones picked by cost.
    fn state_after_with(
        problem: &Problem,
        until_t: f64,
        threads: usize,
        lane_table_max: Option<usize>,
        isa: Option<Isa>,
        form: Option<GForm>,
    ) -> (Vec<f64>, Vec<u32>) {
        let set_up = |sim: &mut Sim| {
            if let Some(bytes) = lane_table_max {
                let (lat, s) = (problem.lattice, &sim.s);
                sim.list.set_lane_table_max(bytes);
                sim.list.build(&s.x, &s.y, lat.width, sim.cutoff, sim.block);
                assert_eq!(sim.list.lane_table(), bytes > 0);
            }
            if let Some(isa) = isa {
                sim.isas = std::array::from_fn(|_| IsaPick::fixed(isa));
            }
            if let Some(form) = form {
                sim.g_pick = Pick::fixed(form);
            }
        };
        run_until(problem, until_t, threads, set_up, |sim| {
            let nf = sim.s.n_fluid;
            let s = &sim.s;
            let values = [&s.x, &s.y, &s.vx, &s.vy, &s.rho]
                .iter()
                .flat_map(|v| v[..nf].iter().copied())
                .collect();
            (values, s.id.clone())
        })
    }

    /// `problem` run to `until_t` on `threads` threads, failing none of
    /// its steps, `set_up` applied to its start, and what `read` takes
    /// from its end.
    fn run_until<R: Send>(
        problem: &Problem,
        until_t: f64,
        threads: usize,
        set_up: impl Fn(&mut Sim) + Sync,
        read: impl Fn(&Sim) -> R + Sync,
    ) -> R {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a pool");
        pool.install(|| {
            rayon::scope(|_| {
                let mut sim = Sim::new::<Composite>(problem);
                set_up(&mut sim);
                let mut t = 0.0;
                while t < until_t {
                    let dt = sim.time_step().dt;
                    let check = sim.advance::<Composite>(dt);
                    assert!(sim.failure(&check).is_none(), "no failure");
                    t += dt;
                }
                read(&sim)
            })
        })
    }

    /// Once the lattice is lost the fluid is stored in another order, and
    /// the run is the same bits on one thread and two.
    #[test]
    fn a_reordered_run_does_not_depend_on_the_thread_count() {
        let problem = disordering();
        let (one, ids) = state_after(&problem, 40.0, 1);
        let (two, ids_two) = state_after(&problem, 40.0, 2);
        let moved = ids.iter().enumerate().filter(|&(i, &id)| id as usize != i);
        assert!(moved.count() > 0, "the fluid was reordered by t = 40");
        assert_eq!(ids, ids_two);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&one), bits(&two));
    }

    /// Where the kernel pass leaves (dW/dq)/q ([`GForm`]) changes no bit:
    /// the force pass gathers each window's from the pair table or loads
    /// it from the window-lane table, the same values in the same lanes. A
    /// disordering run, with its rebuilds and reorders, is the same bits
    /// with the lanes throughout, the gather throughout, lists without a
    /// lane table, and the form picked by cost, whose trial switches form
    /// step by step within one list.
    #[test]
    fn where_the_kernel_pass_leaves_its_gradients_changes_no_bit() {
        let problem = disordering();
        let picked = state_after(&problem, 40.0, 1);
        for form in [GForm::Lanes, GForm::Gather] {
            let fixed = state_after_with(&problem, 40.0, 1, None, None, Some(form));
            assert_eq!(fixed, picked, "{form:?}");
        }
        let without = state_after_with(&problem, 40.0, 1, Some(0), None, None);
        assert_eq!(without, picked);
        // The default: a lane table for this small strip.
        let lanes = state_after_with(&problem, 40.0, 1, Some(LANE_TABLE_MAX_BYTES), None, None);
        assert_eq!(lanes, picked);
    }

    /// The force pass's tiles ([`super::super::step::FORCE_TILE`]) order
    /// its tasks, not its sums: a disordering run on a strip of 48 columns
    /// visited in tiles of 8 particles of a layer (6 tiles across, so the
    /// tasks run far from storage order) is the same bits as the run in
    /// storage order, on one thread and two.
    #[test]
    fn the_force_pass_in_tiles_is_the_same_bits() {
        let problem = Problem::resolve(
            &Scene {
                columns: Some(48),
                ..disordering().scene
            },
            Composite::INFO,
        )
        .expect("the scene");
        let run = |threads: usize, force_tile: usize| {
            let set_up = |sim: &mut Sim| sim.force_tile = force_tile;
            run_until(&problem, 40.0, threads, set_up, |sim| {
                assert!(sim.list.disordered(), "the fluid was reordered");
                let s = &sim.s;
                // The tiles' order is not storage order: some task's
                // first particle is in an earlier tile than the task
                // before it's.
                let chunk = super::super::step::CHUNK;
                let tile = |c: usize| (s.x[c * chunk] / (sim.list.width() / 6.0)).floor();
                let tasks = s.n_fluid.div_ceil(chunk);
                assert!((1..tasks).any(|c| tile(c) < tile(c - 1)));
                let values: Vec<u64> = [&s.x, &s.y, &s.vx, &s.vy, &s.ax, &s.ay, &s.rho]
                    .iter()
                    .flat_map(|v| v.iter().map(|x| x.to_bits()))
                    .collect();
                (values, s.n_fluid, sim.forces.v_max.to_bits())
            })
        };
        assert_eq!(problem.lattice.columns / 8, 6, "6 tiles of 8 in a layer");
        let plain = run(1, usize::MAX);
        assert!(
            plain.1 > 5 * super::super::step::CHUNK,
            "tasks: {}",
            plain.1
        );
        assert_eq!(run(1, 8), plain);
        assert_eq!(run(2, 8), plain);
    }

    /// The pair passes' instruction sets change no bit: a disordered run
    /// with every pass on each set this CPU runs is the run with the sets
    /// picked by cost ([`IsaPick`]), in either of the kernel pass's forms
    /// of (dW/dq)/q ([`GForm`]).
    #[test]
    fn a_run_does_not_depend_on_the_passes_instruction_sets() {
        let problem = disordering();
        for form in [GForm::Lanes, GForm::Gather] {
            let picked = state_after_with(&problem, 40.0, 1, None, None, Some(form));
            for isa in every_isa() {
                let fixed = state_after_with(&problem, 40.0, 1, None, Some(isa), Some(form));
                assert_eq!(fixed, picked, "{isa:?}, {form:?}");
            }
        }
    }

    /// The pairs within R h of each other that `sim`'s list lacks, by
    /// testing every pair through every image (x runs on past the strip's
    /// edges between rebuilds: a listed pair keeps its image).
    fn missed_pairs(sim: &Sim) -> usize {
        let (x, y) = (&sim.s.x, &sim.s.y);
        let reach2 = (sim.cutoff - sim.skin).powi(2);
        let width = sim.list.width();
        (0..x.len())
            .map(|i| {
                let listed = sim.list.of(i);
                let mut missed = 0;
                for j in 0..x.len() {
                    for shift in -1i8..=1 {
                        if i == j && shift == 0 {
                            continue;
                        }
                        let dx = x[i] - x[j] + f64::from(shift) * width;
                        let dy = y[i] - y[j];
                        if dx * dx + dy * dy <= reach2 && !listed.contains(&Entry::pack(j, shift)) {
                            missed += 1;
                        }
                    }
                }
                missed
            })
            .sum()
    }

    /// A list built ahead along the reference ([`super::super::list_ahead`])
    /// misses no pair the rule lets it keep: for pairs beyond the cutoff
    /// where they were listed (the positions the reference reaches at tau),
    /// the reference moving them toward each other by at most Lip |b| |t -
    /// tau| at every t before the rule's slack runs out, and the rest
    /// moving them by at most that slack, none comes within R h. At the
    /// rebuild (t = 0) the list has room (the slack is positive), at tau it
    /// has the whole skin less the margin, and it runs out past tau.
    #[test]
    fn a_list_built_ahead_misses_no_pair_its_rule_keeps() {
        use super::super::{list_ahead, parting, Reach};
        let (skin, cutoff, rate) = (0.3, 2.3, 0.4);
        let reach_h = cutoff - skin;
        let tau = list_ahead(cutoff, skin, rate);
        let slack = |t: f64| {
            Reach {
                skin,
                cutoff,
                parting: parting(rate, t, tau),
            }
            .slack()
        };
        assert!(tau > 0.0 && slack(0.0) > 0.0, "room at the rebuild");
        assert!((slack(tau) - skin).abs() < 1e-8, "the skin at tau");
        // Where the reference alone spends the slack: past tau.
        let mut end = tau;
        while slack(end) > 0.0 {
            end += 1e-3 * tau;
        }
        assert!(
            end > 1.5 * tau,
            "the list lives past tau: {end} against {tau}"
        );
        assert_eq!(list_ahead(cutoff, skin, 0.0), 0.0, "no reference");
        let tiny = f64::MIN_POSITIVE / 1024.0;
        assert_eq!(list_ahead(cutoff, skin, tiny), 0.0, "tau would overflow");
        assert_eq!(parting(0.0, 1.0, 0.0), 0.0, "the lattice's rule");
        let mut uniform = neighbours::tests::uniform(0x2545_f491_4f6c_dd1d);
        for _ in 0..100_000 {
            let t = end * uniform();
            // Where it was listed: beyond the cutoff, at any angle.
            let (r0, theta) = (cutoff * (1.0 + 1e-6 + 0.2 * uniform()), uniform() * 6.3);
            let (a, b) = (r0 * theta.cos(), r0 * theta.sin());
            // The reference's speed difference, at most Lip |b|, either
            // way, for t - tau from there; then the rest, at most the
            // slack, in any direction.
            let du = rate * b.abs() * (2.0 * uniform() - 1.0);
            let (rest, phi) = (slack(t).max(0.0) * uniform(), uniform() * 6.3);
            let (x, y) = (a + du * (t - tau) + rest * phi.cos(), b + rest * phi.sin());
            assert!(x.hypot(y) > reach_h, "t = {t}: reached {}", x.hypot(y));
        }
    }

    /// The pick between listing ahead and where the fluid is
    /// ([`super::super::Listing`]) switches after SWITCH lists running that
    /// the other way would have outlived, not before; a list the other way
    /// would not have outlived (its rule stale first, or at the same step),
    /// or one with nothing to compare (no reference), starts the count
    /// again; and it switches back the same way.
    #[test]
    fn the_listing_switches_after_lists_running_the_other_way_outlived() {
        use super::super::Listing;
        let mut pick = Listing::new();
        assert!(pick.ahead, "a run starts listing ahead");
        // A list the other way's rule found stale at its second step: it
        // would have gone stale, and is not asked again until the next
        // list.
        let outlived_not = |pick: &mut Listing| {
            pick.observe(false);
            pick.observe(true);
            assert!(!pick.asking(), "asked until stale");
            pick.rebuilt(true);
            assert!(pick.asking(), "asked again for the next list");
        };
        let outlived = |pick: &mut Listing| {
            pick.observe(false);
            pick.observe(false);
            pick.rebuilt(true);
        };
        for _ in 0..Listing::SWITCH - 1 {
            outlived(&mut pick);
        }
        outlived_not(&mut pick);
        assert!(pick.ahead, "a list not outlived starts the count again");
        for _ in 0..Listing::SWITCH - 1 {
            outlived(&mut pick);
        }
        pick.rebuilt(false);
        assert!(pick.ahead, "a list with nothing compared starts it again");
        for _ in 0..Listing::SWITCH - 1 {
            outlived(&mut pick);
            assert!(pick.ahead, "not before SWITCH lists running");
        }
        outlived(&mut pick);
        assert!(!pick.ahead, "switched to listing where the fluid is");
        for _ in 0..Listing::SWITCH {
            outlived(&mut pick);
        }
        assert!(pick.ahead, "and back");
    }

    /// The positions ahead along the reference lie in the strip; a fluid
    /// particle whose position ahead wrapped moved by the strip's width
    /// with its x0, so that its position ahead is its position plus u tau
    /// (as the list's images need); the walls stay.
    #[test]
    fn positions_ahead_wrap_with_their_particles() {
        let (lat, mut s, _, _) = start();
        let (nf, width) = (s.n_fluid, lat.width);
        s.wrap(width);
        // Speeds of both signs, up to a tenth of the strip in tau = 1.
        for i in 0..nf {
            s.u_ref[i] = 0.1 * width * ((i as f64) * 0.618).sin();
        }
        let before = s.x.clone();
        let mut ahead = Vec::new();
        s.ahead(1.0, width, &mut ahead);
        let mut moved = 0;
        for i in 0..s.x.len() {
            assert!((0.0..width).contains(&ahead[i]), "{i} in the strip");
            if i >= nf {
                assert_eq!((s.x[i], ahead[i]), (before[i], before[i]), "a wall stays");
                continue;
            }
            let turns = (before[i] - s.x[i]) / width;
            assert!(
                turns == 0.0 || turns.abs() == 1.0,
                "{i} moved {turns} widths"
            );
            moved += usize::from(turns != 0.0);
            assert_eq!(s.x0[i], s.x[i], "x0 with it");
            let off = ahead[i] - s.x[i] - s.u_ref[i];
            assert!(off.abs() < 1e-12 * width, "{i}: {off}");
        }
        assert!(moved > 0 && moved < nf, "some wrapped: {moved}");
    }

    /// Monaghan's kernel at N = 6, Re = 10, jittered by `jitter` d, run
    /// to t = 100 with the shear reference taken at each rebuild or not:
    /// at every step every pair within R h is listed; at every rebuild the
    /// reference's speeds part no two particles (the walls' 0 included)
    /// faster than its Lipschitz constant says. Returns the rebuilds (the
    /// list the run starts with not counted), how many of them took a
    /// reference, and how many of those found the lattice in its order
    /// (its list built in the lattice's form).
    fn on_the_shear_reference(jitter: f64, reference: bool) -> (u64, usize, usize) {
        use crate::kernels::Monaghan;
        let scene = Scene {
            kernel: "monaghan".into(),
            n_layers: 6,
            re: Some(10.0),
            c0: "rule10".parse().expect("a rule"),
            jitter,
            jitter_seed: 1,
            eps_limit: 0.5,
            ..Scene::builtin()
        };
        let problem = Problem::resolve(&scene, Monaghan::INFO).expect("the scene");
        let b = problem.lattice.b();
        rayon::scope(|_| {
            let mut sim = Sim::new::<Monaghan>(&problem);
            sim.use_reference = reference;
            let (mut t, mut referenced, mut ordered) = (0.0, 0, 0);
            let first = sim.list.rebuilds;
            let mut before = first;
            while t < 100.0 {
                let dt = sim.time_step().dt;
                let check = sim.advance::<Monaghan>(dt);
                assert!(sim.failure(&check).is_none(), "no failure");
                t += dt;
                if sim.list.rebuilds > before {
                    before = sim.list.rebuilds;
                    let (s, rate) = (&sim.s, sim.shear_rate);
                    referenced += usize::from(rate > 0.0);
                    ordered += usize::from(rate > 0.0 && !sim.list.disordered());
                    // Each fluid particle against every other and
                    // against a wall at either plane (u = 0).
                    let walls = [(-b, 0.0), (b, 0.0)];
                    let fluid = s.y0.iter().copied().zip(s.u_ref.iter().copied());
                    let all: Vec<(f64, f64)> = fluid.chain(walls).collect();
                    for &(ya, ua) in &all {
                        for &(yb, ub) in &all {
                            let bound = rate * (ya - yb).abs() * (1.0 + 1e-12) + 1e-15;
                            assert!((ua - ub).abs() <= bound, "parted faster at t = {t}");
                        }
                    }
                }
                assert_eq!(missed_pairs(&sim), 0, "a pair missed at t = {t}");
            }
            (sim.list.rebuilds - first, referenced, ordered)
        })
    }

    /// A disordered fluid's list lives on the shear of its bands
    /// ([`State::shear_reference`], [`crate::solver::neighbours::Reach`]),
    /// built ahead along it ([`super::super::list_ahead`]): jittered by
    /// 0.3 d, the fluid disorders by t = 60; it misses no pair
    /// ([`on_the_shear_reference`]) and is rebuilt less often than when
    /// the rule bounds the displacements themselves (no reference taken,
    /// the list built where the fluid is).
    #[test]
    fn a_list_on_the_shear_reference_misses_no_pair_and_lives_longer() {
        let (with, referenced, _) = on_the_shear_reference(0.3, true);
        let (without, _, _) = on_the_shear_reference(0.3, false);
        assert!(referenced > 20, "the disordered lists had a reference");
        assert!(with < without, "{with} rebuilds against {without}");
    }

    /// A lattice that keeps its order lists on the shear of its layers as
    /// a disordered fluid does on its bands': the perfect lattice, from
    /// rest to t = 100, takes the reference at every rebuild and keeps its
    /// order at each, misses no pair, and is rebuilt less often than
    /// without the reference.
    #[test]
    fn a_lattice_that_keeps_its_order_lists_on_its_shear_reference_too() {
        let (with, referenced, ordered) = on_the_shear_reference(0.0, true);
        let (without, _, _) = on_the_shear_reference(0.0, false);
        assert!(with > 20, "{with} rebuilds");
        assert_eq!(referenced as u64, with, "every rebuild took a reference");
        assert_eq!(ordered, referenced, "the lattice kept its order");
        assert!(with < without, "{with} rebuilds against {without}");
    }

    /// The composite kernel (R = h) at N = 6, Re = 10, c0 = 10 U, jittered
    /// by 0.05 d on a strip of 48 columns, run to t = 400: the rebuilds
    /// after the list made at the start, and whether rebuilds still list
    /// the fluid ahead along its reference at the end. `keep_ahead` lists
    /// it ahead at every rebuild, as without the pick between the ways
    /// ([`super::super::Listing`]). Every 16th step, no pair within R h is
    /// missed.
    fn wide_agitated_strip(keep_ahead: bool) -> (u64, bool) {
        let scene = Scene {
            kernel: "composite".into(),
            n_layers: 6,
            re: Some(10.0),
            c0: "rule10".parse().expect("a rule"),
            jitter: 0.05,
            jitter_seed: 1,
            columns: Some(48),
            ..Scene::builtin()
        };
        let problem = Problem::resolve(&scene, Composite::INFO).expect("the scene");
        rayon::scope(|_| {
            let mut sim = Sim::new::<Composite>(&problem);
            let first = sim.list.rebuilds;
            let (mut t, mut step) = (0.0, 0u64);
            while t < 400.0 {
                let dt = sim.time_step().dt;
                let check = sim.advance::<Composite>(dt);
                assert!(sim.failure(&check).is_none(), "no failure");
                if keep_ahead {
                    // No list outlived: the pick never switches.
                    sim.listing.outlived = 0;
                }
                t += dt;
                step += 1;
                if step % 16 == 0 {
                    assert_eq!(missed_pairs(&sim), 0, "a pair missed at t = {t}");
                }
            }
            (sim.list.rebuilds - first, sim.listing.ahead)
        })
    }

    /// A wide strip's layers hold the extremes of many particles'
    /// agitation, which spend within a step or two the slack a list built
    /// ahead leaves at its rebuild: listed ahead to the end, this strip
    /// rebuilds at about half its steps. Where lists built where the fluid
    /// is would have outlived those, the run takes them: it misses no pair
    /// and rebuilds less than half as often.
    #[test]
    fn a_fluid_too_agitated_for_lists_built_ahead_is_listed_where_it_is() {
        let (with, ahead) = wide_agitated_strip(false);
        let (without, _) = wide_agitated_strip(true);
        assert!(!ahead, "the pick lists where the fluid is at the end");
        assert!(2 * with < without, "{with} rebuilds against {without}");
    }

    /// Reordering moves every particle's values together, keeps each id
    /// once, and leaves a lattice whose layers are only rotated (sheared
    /// past the strip's edge) where it is.
    #[test]
    fn a_reorder_moves_whole_particles_and_leaves_a_rotated_lattice() {
        let (lat, mut s, c, low) = start();
        let nf = s.n_fluid;
        let mut order = Vec::new();
        // Every layer shifted by half its width: each is rotated.
        for i in 0..nf {
            s.x[i] += 0.5 * lat.width;
        }
        s.wrap(lat.width);
        let before = s.x.clone();
        for layers in [1, 2] {
            assert!(
                !s.reorder(low, lat.dy, layers, c, &mut order),
                "rotations stay"
            );
            assert_eq!(s.x, before);
        }
        // Two particles of layer 0 swapped in x: now it moves.
        for i in 0..nf {
            s.rho[i] = f64::from(s.id[i]);
        }
        s.x.swap(0, 1);
        assert!(s.reorder(low, lat.dy, 1, c, &mut order), "an order lost");
        let mut seen = vec![false; nf];
        for i in 0..nf {
            let id = s.id[i] as usize;
            assert!(!seen[id], "each id once");
            seen[id] = true;
            assert_eq!(s.rho[i], id as f64, "rho moved with its particle");
        }
        // Band by band, by x within a band.
        let band = |s: &State, i: usize| ((s.y[i] - low) / lat.dy) as i64;
        for i in 1..nf {
            assert!(
                (band(&s, i - 1), s.x[i - 1]) <= (band(&s, i), s.x[i]),
                "sorted at {i}"
            );
        }
        assert_eq!(&s.x0[..nf], &s.x[..nf], "the rebuild's reference moved too");
        // The middle particle of the first layer moved into the second's
        // band: the fluid is stored in bands of two layers, by x within a
        // band.
        s.y[1] += lat.dy;
        assert!(s.reorder(low, lat.dy, 2, c, &mut order), "an order lost");
        let wide = |s: &State, i: usize| ((s.y[i] - low) / (2.0 * lat.dy)) as i64;
        for i in 1..nf {
            assert!(
                (wide(&s, i - 1), s.x[i - 1]) <= (wide(&s, i), s.x[i]),
                "sorted in bands of two layers at {i}"
            );
        }
        assert!(
            (1..c).any(|i| band(&s, i) != band(&s, 0)),
            "a block holds two layers"
        );
        // Stored so, it is not taken for a lattice, and sorts the same.
        let stored = s.x.clone();
        assert!(s.reorder(low, lat.dy, 2, c, &mut order));
        assert_eq!(s.x, stored);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]
        /// A reorder keeps the storage exactly where sorting by one
        /// layer's bands finds every block a rotated band (the decision
        /// before the sort could be skipped), whatever the bands a moved
        /// fluid is stored in: the same decisions, so every run that keeps
        /// its lattice keeps its bits. Particles shifted along x and moved
        /// by up to 0.75 d and 0.75 layer spacings, kept or not.
        #[test]
        fn a_reorder_keeps_exactly_the_orders_the_sort_keeps(
            scale in 0.0f64..1.5,
            shift in 0.0f64..1.0,
            layers in 1usize..4,
            offsets in proptest::collection::vec((-0.5f64..0.5, -0.5f64..0.5), 16),
        ) {
            let (lat, mut s, c, low) = start();
            let nf = s.n_fluid;
            for i in 0..nf {
                let (ox, oy) = offsets[i % offsets.len()];
                s.x[i] += shift * lat.width + scale * ox * lat.d;
                s.y[i] += scale * oy * lat.dy;
            }
            s.wrap(lat.width);
            let mut sorted: Vec<(u64, u64, u32)> = (0..nf)
                .map(|i| {
                    let b = ((s.y[i] - low) / lat.dy).max(0.0) as u64;
                    (b, s.x[i].to_bits(), i as u32)
                })
                .collect();
            sorted.sort_unstable_by_key(|&(b, x, i)| (b, x, s.id[i as usize]));
            let kept = crate::solver::step::blocks_rotated(&sorted, c);
            let before = s.x.clone();
            let mut order = Vec::new();
            proptest::prop_assert_eq!(s.reorder(low, lat.dy, layers, c, &mut order), !kept);
            if kept {
                proptest::prop_assert_eq!(&s.x, &before);
            }
        }
    }

    /// A block whose bands descend once can still be a rotated band: the
    /// first layer's first particle moved into the second layer's band,
    /// left of all of it, is stored first and sorts last. The sort keeps
    /// that storage, and so does the reorder, which skips the sort only
    /// for blocks whose bands descend more than once.
    #[test]
    fn a_block_rotated_across_a_band_edge_stays() {
        let (lat, mut s, c, low) = start();
        assert!(s.x[1] < s.x[2], "a layer is stored by x");
        let left = s.x[c..2 * c].iter().fold(f64::INFINITY, |m, &x| m.min(x));
        s.x[0] = 0.5 * left;
        s.y[0] += lat.dy;
        let band = |y: f64| ((y - low) / lat.dy) as i64;
        assert_eq!(band(s.y[0]), band(s.y[c]), "in the second layer's band");
        let before = s.x.clone();
        for layers in [1, 2, 3] {
            assert!(!s.reorder(low, lat.dy, layers, c, &mut Vec::new()));
            assert_eq!(s.x, before);
        }
    }

    /// A disordered fluid's bands are as many layers high as fill a window
    /// with a row of neighbours ([`super::super::band_layers`]).
    #[test]
    fn bands_are_as_high_as_fill_a_window() {
        let lat = disordering().lattice;
        let layers = |cutoff: f64| super::super::band_layers(&lat, cutoff * lat.d);
        // R = 2 h and 3 h at h = d with the skin 0.3 h; R = h.
        assert_eq!(layers(2.3), 2);
        assert_eq!(layers(3.3), 1);
        assert_eq!(layers(1.3), 3);
        // A cutoff so wide that less than a layer would fill the window,
        // or not a number: one layer.
        assert_eq!(layers(100.0), 1);
        assert_eq!(layers(f64::NAN), 1);
    }
}
