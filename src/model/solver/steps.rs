//! Steps without the run loop's outputs: one at a time ([`Stepper`], for
//! the criterion benchmarks) or a fixed number timed ([`run_steps`], for
//! `shearsph bench`), on the same [`Sim`] as [`super::run`].

use std::marker::PhantomData;
use std::time::Instant;

use serde::Serialize;

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
    run_steps_after::<K>(problem, 0, steps)
}

/// [`run_steps`] after `warm` untimed steps (a jittered start's flow
/// brought into its disordered state first: `bench --disordered`).
pub fn run_steps_after<K: Kernel>(problem: &Problem, warm: u64, steps: u64) -> StepsRun {
    rayon::scope(|_| run_steps_here::<K>(problem, warm, steps))
}

fn run_steps_here<K: Kernel>(problem: &Problem, warm: u64, steps: u64) -> StepsRun {
    let mut sim = Sim::new::<K>(problem);
    for _ in 0..warm {
        let dt = sim.time_step().dt;
        let check = sim.advance::<K>(dt);
        if sim.failure(&check).is_some() {
            break;
        }
    }
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
