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
/// together, as the lattice stores a layer) and the same rebuilds per
/// step. The walls are the tiled lattice's own, which are the base's
/// repeated.
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
    rayon::scope(|_| timed::<K>(Sim::with_state::<K>(problem, s), steps))
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
