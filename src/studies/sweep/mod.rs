//! Many scenes in parallel: a grid of points (kernels x discretisation x N x
//! Re x alpha x start x c0), each run once, classified by its scene's bounds,
//! and kept as one row (the point's key and the run's summary). `shearsph
//! sweep` and the report both run their scenes through here.
//!
//! - A point is keyed by a stable id (`monaghan/n=10/re=30/alpha=0.1/c0=rule10`),
//!   so a finished point is never rerun: a sweep resumes where it stopped.
//! - Scenes run side by side, one per worker, each inside its own rayon pool
//!   (one thread unless asked otherwise); the longest (estimated) start first.
//! - A stop flag (Ctrl-C in the CLI) ends the sweep cleanly: no new point
//!   starts, running ones end at their next step as interrupted (the
//!   solver's `Observer::should_stop`; their rows are not written, so a
//!   resume reruns them) and every finished row is kept.
//!
//! Storage (see [`store`]): `results.jsonl` gets one JSON row per finished
//! point, appended and fsynced as it finishes (a line cut short by a crash is
//! ignored and dropped on resume); `results.csv` is rewritten atomically from
//! it when the sweep ends or stops.

pub mod axes;
mod check;
mod grid;
mod row;
mod shard;
pub mod store;

pub use crate::config::ClassRules;
pub use crate::solver::{classify, Class};
pub use axes::{Discretisation, GridPosition, HOverD, Start};
pub use check::check_points;
pub use grid::{grid_flag, label_scene, Origins, Point, PointC0, SweepSpec, Unlabelled};
pub use row::{pool_over_seeds, pool_rows, OverSeeds, Row};
pub use shard::{Shard, ShardArg};

use std::collections::BTreeSet;
use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

use anyhow::{Context, Result};
use indicatif::ProgressBar;

use crate::config::{C0Spec, Scene, SceneError};
use crate::kernel::KernelInfo;
use crate::particles::series::{write_picture, ParticleOutput};
use crate::problem::c0;
use crate::problem::channel::Channel;
use crate::problem::cost::Estimate;
use crate::problem::Problem;
use crate::solver::{self, FailureKind, Observer};

/// Hands the stop flag to a running scene, which ends at the next step as
/// [`solver::Outcome::Interrupted`]; [`run_point`] then drops it whole.
struct StopWatch<'a> {
    stop: &'a AtomicBool,
}

impl Observer for StopWatch<'_> {
    fn should_stop(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

/// Where a sweep writes particle snapshots: every `every`-th output time of
/// each point into `root/`[`Point::particle_dir`] (`sweep --particles-every K`).
#[derive(Debug, Clone, Copy)]
pub struct ParticleDump<'a> {
    pub root: &'a Path,
    pub every: u64,
}

impl Point {
    /// The point's folder of particle snapshots under a sweep's: its id as
    /// a path (`monaghan/n=10/re=1/alpha=0.1/c0=derived`), any character
    /// but letters, digits and `=._-` as `_`.
    pub fn particle_dir(&self) -> PathBuf {
        self.id()
            .split('/')
            .map(|part| {
                part.chars()
                    .map(|c| {
                        if c.is_ascii_alphanumeric() || "=._-".contains(c) {
                            c
                        } else {
                            '_'
                        }
                    })
                    .collect::<String>()
            })
            .collect()
    }
}

/// Run one point on the current thread (and rayon pool); with `particles`
/// its particle snapshots and picture too (a write error is printed and
/// costs the snapshots, not the row). `None` when the stop flag ended it
/// before it finished.
pub fn run_point(
    point: &Point,
    base: &toml::Table,
    rules: &ClassRules,
    stop: &AtomicBool,
    particles: Option<ParticleDump>,
) -> Option<Row> {
    if stop.load(Ordering::Relaxed) {
        return None;
    }
    let scene = match point.scene_classed(base, rules) {
        Ok(s) => s,
        Err(e) => {
            return Some(Row::not_run(
                point,
                FailureKind::Scene,
                e.to_string(),
                f64::NAN,
                String::new(),
            ))
        }
    };
    let info = match scene.kernel_info() {
        Ok(i) => i,
        Err(e) => {
            return Some(Row::not_run(
                point,
                FailureKind::Scene,
                e.to_string(),
                f64::NAN,
                String::new(),
            ))
        }
    };
    if let Err(e) = Problem::resolve(&scene, info) {
        let (c0, rule) = c0_of(&scene, info);
        let kind = match &e {
            SceneError::Invalid { field: "c0", .. } => FailureKind::NoC0,
            _ => FailureKind::Scene,
        };
        let reason = if kind == FailureKind::NoC0 && !rule.is_empty() {
            if c0.is_nan() {
                format!("{rule}: no positive root for this scene (P alpha^2 + Q A < 0)")
            } else {
                format!("{rule} gives c0 = {c0:.6}: no positive root for this scene")
            }
        } else {
            e.to_string()
        };
        let mut row = Row::not_run(point, kind, reason, c0, rule);
        row.c0_over_u = c0 / scene.u;
        return Some(row);
    }
    let mut watch = StopWatch { stop };
    let dump_dir = particles.map(|d| (d.root.join(point.particle_dir()), d.every));
    // A panic in the solver is a bug, but it costs one row, not the sweep.
    let result = panic::catch_unwind(AssertUnwindSafe(|| match &dump_dir {
        None => crate::run::run_scene(&scene, &mut watch),
        Some((dir, every)) => {
            let written =
                std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()));
            let mut observer = ParticleOutput::new(&mut watch, dir, Some(*every));
            let r = crate::run::run_scene(&scene, &mut observer);
            if let Ok(r) = &r {
                let pictured =
                    written
                        .and_then(|_| observer.finish())
                        .and_then(|last| match last {
                            Some(last) => write_picture(dir, &last, r),
                            None => Ok(()),
                        });
                if let Err(e) = pictured {
                    eprintln!("warning: particle snapshots of {}: {e:#}", point.id());
                }
            }
            r
        }
    }));
    match result {
        // Stopped before the end: no row, so a resumed sweep reruns it.
        Ok(Ok(r)) if matches!(r.outcome, solver::Outcome::Interrupted { .. }) => None,
        Ok(Ok(r)) => Some(Row::from_run(point, &r)),
        Ok(Err(e)) => Some(Row::not_run(
            point,
            FailureKind::Scene,
            e.to_string(),
            f64::NAN,
            String::new(),
        )),
        Err(payload) => {
            let msg = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown".into());
            Some(Row::not_run(
                point,
                FailureKind::Panic,
                format!("the solver panicked: {msg}"),
                f64::NAN,
                String::new(),
            ))
        }
    }
}

/// The c0 a scene's spec gives (for the record when it is not positive).
fn c0_of(scene: &Scene, info: &'static KernelInfo) -> (f64, String) {
    let fallback = || match &scene.c0 {
        C0Spec::Value(v) => (*v, "value".to_string()),
        C0Spec::Rule { rule, .. } => (f64::NAN, rule.to_string()),
    };
    let Ok(channel) = Channel::resolve(scene, info) else {
        return fallback();
    };
    c0::by_spec(&scene.c0, info, &channel, scene.alpha).unwrap_or_else(|_| fallback())
}

/// Estimated work of a point (particles x steps at the starting time step),
/// to start the longest first. Zero when the point will not run.
pub fn estimated_cost(point: &Point, base: &toml::Table) -> f64 {
    let Ok(scene) = point.scene(base) else {
        return 0.0;
    };
    let Ok(info) = scene.kernel_info() else {
        return 0.0;
    };
    let Ok(p) = Problem::resolve(&scene, info) else {
        return 0.0;
    };
    let channel = p.channel();
    Estimate::new(&channel, p.c0, p.t_end).particle_steps(&channel)
}

/// How to run many scenes.
#[derive(Debug, Clone, Copy)]
pub struct Parallel {
    /// Scenes at once.
    pub jobs: usize,
    /// Threads inside each scene (1: each scene single-threaded).
    pub threads_per_scene: usize,
}

impl Parallel {
    /// One scene per core, each single-threaded.
    pub fn per_core() -> Parallel {
        Parallel::new(None, 1)
    }

    /// `jobs` scenes at once (default: cores / threads_per_scene, at least 1).
    pub fn new(jobs: Option<usize>, threads_per_scene: usize) -> Parallel {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let threads_per_scene = threads_per_scene.max(1);
        Parallel {
            jobs: jobs.unwrap_or(cores / threads_per_scene).max(1),
            threads_per_scene,
        }
    }

    /// Run `f` over `items` on `jobs` workers, each with its own rayon pool
    /// of `threads_per_scene` threads, taking items in order. `done` is called
    /// on the worker as each item finishes. An item whose `f` gives `None`
    /// (stopped) stops that worker. Results in item order.
    pub fn map<T, R, F, D>(
        &self,
        items: &[T],
        stop: &AtomicBool,
        f: F,
        done: D,
    ) -> Result<Vec<Option<R>>>
    where
        T: Sync,
        R: Send,
        F: Fn(&T) -> Option<R> + Sync,
        D: Fn(usize, &R) + Sync,
    {
        let next = AtomicUsize::new(0);
        let results: Mutex<Vec<Option<R>>> = Mutex::new((0..items.len()).map(|_| None).collect());
        let workers = self.jobs.min(items.len()).max(1);
        let errors: Mutex<Vec<anyhow::Error>> = Mutex::new(Vec::new());
        std::thread::scope(|scope| {
            for _ in 0..workers {
                scope.spawn(|| {
                    let pool = match rayon::ThreadPoolBuilder::new()
                        .num_threads(self.threads_per_scene)
                        .build()
                    {
                        Ok(p) => p,
                        Err(e) => {
                            errors
                                .lock()
                                .unwrap()
                                .push(anyhow::anyhow!("building a thread pool: {e}"));
                            return;
                        }
                    };
                    loop {
                        if stop.load(Ordering::Relaxed) {
                            return;
                        }
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= items.len() {
                            return;
                        }
                        match pool.install(|| f(&items[i])) {
                            Some(r) => {
                                done(i, &r);
                                results.lock().unwrap()[i] = Some(r);
                            }
                            None => return,
                        }
                    }
                });
            }
        });
        if let Some(e) = errors.into_inner().unwrap().pop() {
            return Err(e);
        }
        Ok(results.into_inner().unwrap())
    }
}

/// Run `points` (longest first), with each point's particle snapshots when
/// `particles`. `on_row` sees each row as it finishes (on a worker thread).
/// Returns the new rows, in grid order, and whether the stop flag cut the
/// run short.
pub fn run_points(
    points: &[Point],
    base: &toml::Table,
    rules: &ClassRules,
    par: Parallel,
    stop: &AtomicBool,
    on_row: &(dyn Fn(&Row) + Sync),
    particles: Option<ParticleDump>,
) -> Result<(Vec<Row>, bool)> {
    // Stopped while scheduling: nothing has started (a large grid takes
    // a moment to cost).
    let mut todo: Vec<(f64, &Point)> = Vec::with_capacity(points.len());
    for p in points {
        if stop.load(Ordering::Relaxed) {
            return Ok((Vec::new(), true));
        }
        todo.push((estimated_cost(p, base), p));
    }
    todo.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.index.cmp(&b.1.index)));
    let todo: Vec<&Point> = todo.into_iter().map(|t| t.1).collect();
    let results = par.map(
        &todo,
        stop,
        |p| run_point(p, base, rules, stop, particles),
        |_, row| on_row(row),
    )?;
    let finished = results.iter().filter(|r| r.is_some()).count();
    let mut rows: Vec<Row> = results.into_iter().flatten().collect();
    rows.sort_by_key(|r| r.index);
    Ok((rows, finished < todo.len()))
}

/// What a sweep run did.
#[derive(Debug)]
pub struct SweepRun {
    pub spec: SweepSpec,
    /// Every finished row in the folder, this run's and earlier ones', in
    /// grid order.
    pub rows: Vec<Row>,
    /// The shard this run ran (given, or the folder's own).
    pub shard: Option<Shard>,
    /// Points of this shard: finished now, finished before, still to run.
    pub ran: usize,
    pub already: usize,
    pub remaining: usize,
    /// The stop flag cut this run short.
    pub interrupted: bool,
}

/// A sweep to run or resume: its folder; its grid (None: the folder's own,
/// see [`store::open`] for `spec` and `force`); its shard, as given (`auto`
/// read from Slurm unless the folder records its shard, see
/// [`ShardArg::resolve`]; None: the folder's, or every point); how it runs
/// in parallel; each point's particle snapshots (every K-th output time) and
/// picture under `dir/particles/`; and where the grid's values came from,
/// for its errors (None: named as the sweep's fields).
pub struct SweepRequest<'a> {
    pub dir: &'a Path,
    pub spec: Option<SweepSpec>,
    pub force: bool,
    pub shard: Option<ShardArg>,
    pub par: Parallel,
    pub particles_every: Option<u64>,
    pub origins: Option<&'a dyn Origins>,
}

impl<'a> SweepRequest<'a> {
    /// The sweep of `spec` in `dir`: resumed (not forced), every point of
    /// it (no shard), one scene per core, no snapshots.
    pub fn new(dir: &'a Path, spec: Option<SweepSpec>) -> Self {
        SweepRequest {
            dir,
            spec,
            force: false,
            shard: None,
            par: Parallel::per_core(),
            particles_every: None,
            origins: None,
        }
    }
}

/// Run (or resume) the sweep `req` asks. Under the folder's lock, before
/// anything runs: the shard is settled (and recorded in the folder), and
/// every point of it checked ([`check_points`]; a new grid before the
/// folder is written). Only the points of the shard run; finished points
/// are skipped. `bar` counts the points of this run; `watch` sees each row
/// once it is stored.
pub fn run_sweep(
    req: SweepRequest<'_>,
    stop: &AtomicBool,
    bar: &ProgressBar,
    watch: &(dyn Fn(&Row) + Sync),
) -> Result<SweepRun> {
    // A sweep refused before it wrote anything leaves no folder behind:
    // the one the lock created (empty, ours) is removed again.
    let dir = req.dir;
    let created = !dir.exists();
    let r = sweep_in(req, stop, bar, watch);
    if r.is_err() && created {
        let empty = std::fs::read_dir(dir).is_ok_and(|mut d| d.next().is_none());
        if empty {
            let _ = std::fs::remove_dir(dir);
        }
    }
    r
}

fn sweep_in(
    req: SweepRequest<'_>,
    stop: &AtomicBool,
    bar: &ProgressBar,
    watch: &(dyn Fn(&Row) + Sync),
) -> Result<SweepRun> {
    let SweepRequest {
        dir,
        spec,
        force,
        shard,
        par,
        particles_every,
        origins,
    } = req;
    let particles_root = dir.join("particles");
    let origins = origins.unwrap_or(&Unlabelled);
    // One sweep per folder at a time: the lock is held until this returns.
    let _lock = store::lock(dir)?;
    // A start over forgets the folder's shard.
    let recorded = if force || !dir.join(store::SPEC_FILE).exists() {
        None
    } else {
        store::read_shard(dir)?
    };
    let (shard, note) = ShardArg::resolve(
        shard,
        recorded,
        |v| std::env::var(v).ok(),
        &dir.display().to_string(),
    )
    .map_err(anyhow::Error::msg)?;
    if let Some(note) = note {
        eprintln!("{note}");
    }
    let in_shard = |p: &Point| shard.is_none_or(|s| s.contains(p.index));
    // A new grid is checked whole before the folder is written.
    if let Some(spec) = &spec {
        let points = spec.points();
        let mine: Vec<&Point> = points.iter().filter(|p| in_shard(p)).collect();
        check_points(&mine, &spec.scene, &spec.classes, origins, stop)?;
    }
    let checked = spec.is_some();
    let (spec, done) = store::open(dir, spec, force)?;
    // A start over (`--force`) records the shard it runs, or none.
    if force || recorded != shard {
        store::write_shard(dir, shard)?;
    }
    let done_ids: BTreeSet<String> = done.iter().map(|r| r.id.clone()).collect();
    let (already, todo): (Vec<Point>, Vec<Point>) = spec
        .points()
        .into_iter()
        .filter(|p| in_shard(p))
        .partition(|p| done_ids.contains(&p.id()));
    if !checked {
        let todo: Vec<&Point> = todo.iter().collect();
        check_points(&todo, &spec.scene, &spec.classes, origins, stop)?;
    }
    bar.set_length(todo.len() as u64);
    let appender = store::Appender::open(dir)?;
    let append_error: Mutex<Option<anyhow::Error>> = Mutex::new(None);
    let counts = Mutex::new([0usize; 4]);
    let on_row = |row: &Row| {
        if let Err(e) = appender.append(row) {
            append_error.lock().unwrap().get_or_insert(e);
            stop.store(true, Ordering::Relaxed);
        }
        let mut c = counts.lock().unwrap();
        if let Some(n) = c.get_mut(row.class as usize) {
            *n += 1;
        }
        bar.set_message(format!(
            "ok {} inaccurate {} over-compressed {} failed {}",
            c[0], c[1], c[2], c[3]
        ));
        bar.inc(1);
        watch(row);
    };
    let (new_rows, interrupted) = run_points(
        &todo,
        &spec.scene,
        &spec.classes,
        par,
        stop,
        &on_row,
        particles_every.map(|every| ParticleDump {
            root: &particles_root,
            every,
        }),
    )?;
    if let Some(e) = append_error.into_inner().unwrap() {
        return Err(e);
    }
    let ran = new_rows.len();
    let mut rows = done;
    rows.extend(new_rows);
    let rows = store::canonical(rows);
    store::write_csv(dir, &rows)?;
    Ok(SweepRun {
        spec,
        rows,
        shard,
        ran,
        already: already.len(),
        remaining: todo.len() - ran,
        interrupted,
    })
}

#[cfg(test)]
mod tests;
