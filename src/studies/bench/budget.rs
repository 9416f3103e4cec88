//! The bench's budget: its estimated time on one core and the checks of
//! its options against their bounds, before anything runs.

use anyhow::{bail, Result};

use super::disordered::{base_scene, MIN_STEPS, UNTIL_T};
use super::{scene, scene_for, Options};
use crate::config::Scene;

/// The longest a bench may take by [`estimated_seconds`]: an hour on one
/// core, a scene's own default bound (`max_run_s`).
pub const MAX_BENCH_S: f64 = 3600.0;

/// Steps per measurement of a scene of `particles` particles: `--steps`,
/// or enough for the particle-steps asked, at least 10 (the disordered
/// scene's at least [`MIN_STEPS`]).
pub(super) fn steps_for(opts: &Options, particles: usize) -> u64 {
    let least = if opts.disordered { MIN_STEPS } else { 10 };
    opts.steps
        .unwrap_or_else(|| ((opts.particle_steps / particles as f64).ceil() as u64).max(least))
}

/// The estimated seconds of every measurement of `opts` on one core
/// (kernels x particle counts x thread counts x repeats, each steps x
/// particles x neighbours x 2 passes at [`crate::problem::cost::EST_S_PER_PAIR_PASS`],
/// as a scene's run-time guard counts it: it errs long).
pub fn estimated_seconds(opts: &Options) -> Result<f64> {
    let mut total = 0.0;
    for kernel in &opts.kernels {
        let neighbours = listed_of(&scene(kernel))?;
        if opts.disordered {
            total += base_seconds(kernel)?;
        }
        for &target in &opts.particles {
            // The scene holds at least `target` particles: counted as that
            // (its few more change the estimate by a layer's worth).
            let steps = steps_for(opts, target) as f64;
            total += steps
                * target as f64
                * neighbours
                * 2.0
                * crate::problem::cost::EST_S_PER_PAIR_PASS
                * (opts.threads.len() * opts.repeats) as f64;
        }
    }
    Ok(total)
}

/// The estimated seconds of the disordered scene's base run of a kernel
/// (once per kernel, to [`UNTIL_T`]), as a scene's run-time guard counts it.
fn base_seconds(kernel: &str) -> Result<f64> {
    let base = base_scene(kernel);
    let info = base.kernel_info()?;
    let channel = crate::problem::channel::Channel::resolve(&base, info)?;
    let c0 = crate::problem::Problem::resolve(&base, info)?.c0;
    Ok(
        crate::problem::cost::Estimate::new(&channel, c0, UNTIL_T).seconds(
            &channel,
            info.support,
            base.skin,
        ),
    )
}

/// Every count of `opts` within its bound, before any work: at least one
/// of each, thread counts within [`bounds::threads`], repeats within
/// [`bounds::REPEATS`], no kernel, particle count or thread count given
/// twice, and the whole bench estimated within [`MAX_BENCH_S`].
pub fn check(opts: &Options) -> Result<()> {
    use crate::config::bounds;
    if opts.steps == Some(0) {
        bail!("--steps must be at least 1: a measurement of no steps has no throughput");
    }
    if opts.repeats == 0 {
        bail!("--repeats must be at least 1");
    }
    if opts.threads.contains(&0) {
        bail!("--threads must be at least 1");
    }
    bounds::REPEATS.check_usize("--repeats", opts.repeats)?;
    let threads = bounds::threads();
    for &t in &opts.threads {
        threads.check_usize("--threads", t)?;
    }
    bounds::distinct("--kernels", &opts.kernels)?;
    bounds::distinct("--particles", &opts.particles)?;
    bounds::distinct("--threads", &opts.threads)?;
    // Each scene within the memory bound, then the whole within the time's.
    for kernel in &opts.kernels {
        for &target in &opts.particles {
            check_memory(&scene_for(kernel, opts.disordered), target)?;
            if opts.disordered {
                check_tiles(kernel, target)?;
            }
        }
    }
    let est = estimated_seconds(opts)?;
    if est.is_nan() || est > MAX_BENCH_S {
        let what = match opts.steps {
            Some(s) => format!("--steps {s}"),
            None => "the bench's measurements".to_string(),
        };
        bail!(
            "{what}: the bench would take about {} on one core ({} kernel(s) x {} particle count(s) x \
             {} thread count(s) x {} repeat(s), each steps x particles x neighbours at {} ns per pair \
             and pass), over the bound of {}; give fewer --steps (default: about {:.0e} particle-steps \
             a measurement), --particles, --threads or --repeats",
            crate::problem::cost::human_seconds(est),
            opts.kernels.len(),
            opts.particles.len(),
            opts.threads.len(),
            opts.repeats,
            crate::problem::cost::EST_S_PER_PAIR_PASS * 1e9,
            crate::problem::cost::human_seconds(MAX_BENCH_S),
            opts.particle_steps
        );
    }
    Ok(())
}

/// The disordered scene of `target` particles within the strip's bound on
/// its columns, before the base runs: it is the base tiled, so its columns
/// grow with the particle count.
fn check_tiles(kernel: &str, target: usize) -> Result<()> {
    use crate::problem::channel::{Channel, MAX_COLUMNS};
    let base = base_scene(kernel);
    let lattice = Channel::resolve(&base, base.kernel_info()?)?.lattice;
    let per_copy = lattice.n_particles();
    let copies = target.div_ceil(per_copy).max(1);
    if copies as u64 * u64::from(lattice.columns) > u64::from(MAX_COLUMNS) {
        let most = u64::from(MAX_COLUMNS / lattice.columns) * per_copy as u64;
        bail!(
            "--particles {} with --disordered: the disordered scene of kernel {kernel} is its base ({per_copy} \
             particles on {} columns) tiled {copies} times, over the strip's bound of {MAX_COLUMNS} columns \
             (at most {most} particles); give fewer particles",
            crate::format::fmt_value(target as f64),
            lattice.columns
        );
    }
    Ok(())
}

/// A scene of `target` particles within the memory a run may take,
/// refused before the search for its N, with the estimate: a count the
/// memory bound (or the lattice's u32 counts) cannot hold.
pub(super) fn check_memory(scene: &Scene, target: usize) -> Result<()> {
    let neighbours = listed_of(scene)?;
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
    Ok(())
}

/// A bench scene's listed neighbours per particle (its lattice, h and skin).
fn listed_of(scene: &Scene) -> Result<f64> {
    let info = scene.kernel_info()?;
    Ok(crate::problem::cost::listed_neighbours(
        scene.lattice,
        scene.d,
        scene.h_over_d * scene.d,
        info.support,
        scene.skin,
    ))
}
