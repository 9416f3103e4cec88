//! The engine's runs, scheduled: every (c0, start, alpha) the answer needs
//! goes into one queue, and a fixed set of workers ([`RunQueue::workers`]: the
//! caller's rayon pool's threads, and on several cores at least one per
//! seed) takes the most urgent first, each run on its own one-thread pool. The searches ask for their probes and wait; what does
//! not depend on them (every rule's c0) is queued at the start with the
//! lowest priority, so it fills a core the searches leave idle (three seeds
//! on two cores, a probe whose seeds stop at different checkpoints, the
//! ordered search's single runs) instead of running after them. With no
//! c0 ok, the diagnosis's check (seeds at another alpha) is queued the same
//! way once its alpha is known.
//!
//! A run's result is its scene's, c0's, start's and alpha's alone (each run is
//! single-threaded and the solver is deterministic), so the order the
//! queue takes runs in, and how many run at once, change no answer: only
//! the wall time.
//!
//! Workers are plain threads, not rayon's: a rayon worker that waits on
//! another pool steals more work meanwhile, so nested pools start every
//! run at once, time-sliced on the cores (each run's wall time then says
//! nothing about its cost).

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex, MutexGuard};

use anyhow::{anyhow, bail, Result};
use indicatif::ProgressBar;

use super::trial::{pool, start_scene, starts, StartRun, Starts, Trial};
use super::Search;
use crate::config::Scene;
use crate::run::run_scene;
use crate::solver::{Observer, Outcome};

/// How urgent a run is: the queue takes the highest first, and among equals
/// the first asked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Priority {
    /// Nothing waits for it yet (a rule's c0).
    Background,
    /// The ordered search's probes, and what follows the searches.
    Ordered,
    /// The disordered search's probes: the longest chain of runs that wait
    /// on each other.
    Disordered,
}

/// A run: its c0, start (jitter, seed) and artificial viscosity alpha (the
/// scene's, or another the diagnosis checks).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Run {
    pub c0: f64,
    pub start: (f64, u32),
    pub alpha: f64,
}

type Key = (u64, u32, u64);

fn key(r: &Run) -> Key {
    (r.c0.to_bits(), r.start.1, r.alpha.to_bits())
}

enum Slot {
    Queued {
        priority: Priority,
        order: u64,
        run: Run,
    },
    Running,
    Done(Box<StartRun>),
}

#[derive(Default)]
struct State {
    slots: HashMap<Key, Slot>,
    asked: u64,
    /// No more runs are taken: the answer is complete, or gave up.
    closed: bool,
    /// The first run that went wrong (an error, or an interruption).
    error: Option<String>,
}

impl State {
    /// The most urgent queued run: the highest priority, and among equals
    /// the first asked.
    fn next(&self) -> Option<(Key, Run)> {
        self.slots
            .iter()
            .filter_map(|(k, s)| match s {
                Slot::Queued {
                    priority,
                    order,
                    run,
                } => Some(((*priority, std::cmp::Reverse(*order)), *k, *run)),
                _ => None,
            })
            .max_by_key(|&(rank, _, _)| rank)
            .map(|(_, k, run)| (k, run))
    }
}

/// Ends a run when the stop flag is set.
struct Stop<'a>(&'a AtomicBool);
impl Observer for Stop<'_> {
    fn should_stop(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// The queue of one scene's runs (see the module's doc).
pub struct RunQueue<'a> {
    scene: &'a Scene,
    search: &'a Search,
    stop: &'a AtomicBool,
    bar: &'a ProgressBar,
    state: Mutex<State>,
    changed: Condvar,
}

impl<'a> RunQueue<'a> {
    pub fn new(
        scene: &'a Scene,
        search: &'a Search,
        stop: &'a AtomicBool,
        bar: &'a ProgressBar,
    ) -> Self {
        RunQueue {
            scene,
            search,
            stop,
            bar,
            state: Mutex::new(State::default()),
            changed: Condvar::new(),
        }
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        // A worker that panicked poisons the lock; its state is still whole
        // (every change is one assignment), and the panic reaches the
        // caller through the thread scope.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The runs `which` makes at each of `c0s`.
    pub fn runs_of(&self, c0s: &[f64], which: Starts) -> Vec<Run> {
        self.runs_at(self.scene.alpha, c0s, which)
    }

    /// The same at the artificial viscosity `alpha`.
    pub fn runs_at(&self, alpha: f64, c0s: &[f64], which: Starts) -> Vec<Run> {
        let mut out: Vec<Run> = Vec::new();
        for &c0 in c0s {
            for start in starts(self.search, which) {
                let run = Run { c0, start, alpha };
                if !out.iter().any(|r| key(r) == key(&run)) {
                    out.push(run);
                }
            }
        }
        out
    }

    /// Queue `runs` at `priority`; a run already queued lower is raised,
    /// one running or done is left as it is. Returns how many were new (the
    /// progress bar's length grows by as many; each run made ticks it).
    pub fn ask(&self, runs: &[Run], priority: Priority) -> usize {
        let mut st = self.lock();
        let mut new = 0;
        for run in runs {
            let order = st.asked;
            match st.slots.get_mut(&key(run)) {
                Some(Slot::Queued { priority: p, .. }) => *p = (*p).max(priority),
                Some(_) => {}
                None => {
                    st.slots.insert(
                        key(run),
                        Slot::Queued {
                            priority,
                            order,
                            run: *run,
                        },
                    );
                    st.asked += 1;
                    new += 1;
                }
            }
        }
        drop(st);
        self.changed.notify_all();
        self.bar.inc_length(new as u64);
        new
    }

    /// Queue `runs` at `priority` and wait until every one is done; the
    /// first run that went wrong is the error.
    pub fn wait(&self, runs: &[Run], priority: Priority) -> Result<()> {
        self.ask(runs, priority);
        let mut st = self.lock();
        loop {
            if let Some(e) = &st.error {
                bail!("{e}");
            }
            if runs
                .iter()
                .all(|r| matches!(st.slots.get(&key(r)), Some(Slot::Done(_))))
            {
                return Ok(());
            }
            if st.closed {
                return Err(anyhow!("the run queue closed before its runs were made"));
            }
            st = self.changed.wait(st).unwrap_or_else(|e| e.into_inner());
        }
    }

    /// The trials at `c0s` with the starts `which`, made now at `priority`
    /// (a trial also carries the other starts where they were made before).
    pub fn trials(&self, c0s: &[f64], which: Starts, priority: Priority) -> Result<Vec<Trial>> {
        self.wait(&self.runs_of(c0s, which), priority)?;
        self.collect(c0s)
    }

    pub fn trial(&self, c0: f64, which: Starts, priority: Priority) -> Result<Trial> {
        Ok(self.trials(&[c0], which, priority)?.remove(0))
    }

    /// The trials at `c0s` from the runs made so far (none run now).
    pub fn collect(&self, c0s: &[f64]) -> Result<Vec<Trial>> {
        self.collect_at(self.scene.alpha, c0s)
    }

    /// The same at the artificial viscosity `alpha`.
    pub fn collect_at(&self, alpha: f64, c0s: &[f64]) -> Result<Vec<Trial>> {
        let scene = self.scene;
        let info = scene.kernel_info()?;
        let rules = scene.classes();
        let bound = rules.eps_bound(scene.discretisation(info)?);
        let st = self.lock();
        let get = |c0: f64, seed: u32| match st.slots.get(&(c0.to_bits(), seed, alpha.to_bits())) {
            Some(Slot::Done(r)) => Some((**r).clone()),
            _ => None,
        };
        Ok(c0s
            .iter()
            .map(|&c0| {
                let seeds: Option<Vec<StartRun>> =
                    (1..=self.search.seeds).map(|s| get(c0, s)).collect();
                Trial {
                    c0,
                    c0_over_u: c0 / scene.u,
                    perfect: get(c0, 0),
                    pooled: seeds.as_ref().map(|s| pool(s, &rules, bound)),
                    seeds: seeds.unwrap_or_default(),
                }
            })
            .collect())
    }

    /// Take no more runs; the workers end once their current run is made.
    pub fn close(&self) {
        self.lock().closed = true;
        self.changed.notify_all();
    }

    /// Runs made.
    pub fn made(&self) -> usize {
        self.lock()
            .slots
            .values()
            .filter(|s| matches!(s, Slot::Done(_)))
            .count()
    }

    /// A worker: take the most urgent queued run, make it, until closed.
    pub fn work(&self) {
        let pool = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
            Ok(p) => p,
            Err(e) => {
                self.fail(format!("building a thread pool: {e}"));
                return;
            }
        };
        loop {
            let run = {
                let mut st = self.lock();
                loop {
                    if st.closed || st.error.is_some() {
                        return;
                    }
                    let next = st.next();
                    if let Some((k, run)) = next {
                        st.slots.insert(k, Slot::Running);
                        break run;
                    }
                    st = self.changed.wait(st).unwrap_or_else(|e| e.into_inner());
                }
            };
            // A run that panics is the answer's error, not a worker gone
            // with its run never done (the searches would wait on it).
            let made =
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| self.make(&pool, run)));
            match made {
                Ok(Ok(r)) => {
                    self.lock().slots.insert(key(&run), Slot::Done(Box::new(r)));
                    self.bar.inc(1);
                }
                Ok(Err(e)) => self.fail(format!("{e:#}")),
                Err(p) => {
                    let why = p
                        .downcast_ref::<&str>()
                        .map(|s| s.to_string())
                        .or_else(|| p.downcast_ref::<String>().cloned())
                        .unwrap_or_else(|| "a panic".into());
                    self.fail(format!(
                        "the run at c0 = {} (seed {}) panicked: {why}",
                        run.c0, run.start.1
                    ));
                }
            }
            self.changed.notify_all();
        }
    }

    fn fail(&self, e: String) {
        self.lock().error.get_or_insert(e);
        self.changed.notify_all();
    }

    fn make(&self, pool: &rayon::ThreadPool, run: Run) -> Result<StartRun> {
        let mut s = start_scene(self.scene, run.c0, run.start);
        s.alpha = run.alpha;
        let r = pool.install(|| run_scene(&s, &mut Stop(self.stop)))?;
        if matches!(r.outcome, Outcome::Interrupted { .. }) {
            bail!("interrupted");
        }
        Ok(StartRun::of(&r, &self.scene.classes()))
    }

    /// Workers for this queue: as many as the caller's rayon pool has
    /// threads (the report gives each scene one), and on several cores at
    /// least one per seed: a probe's seeds then share the cores (three
    /// seeds on two cores end together after 1.5 runs' time, not after two
    /// runs one after the other), which shortens the chain of probes the
    /// search waits on; the cores' total work is the same.
    pub fn workers(search: &Search) -> usize {
        let threads = rayon::current_num_threads().max(1);
        if threads > 1 {
            threads.max(search.seeds as usize)
        } else {
            1
        }
    }
}

/// Run `f` with `queue`'s workers going, then close it (whatever `f`
/// returns: the workers end after their current run).
pub fn with_workers<T>(queue: &RunQueue<'_>, f: impl FnOnce() -> T) -> T {
    /// Closes the queue however `f` ends (a panic too: the workers must
    /// end for the scope to).
    struct Closer<'q, 'a>(&'q RunQueue<'a>);
    impl Drop for Closer<'_, '_> {
        fn drop(&mut self) {
            self.0.close();
        }
    }
    let workers = RunQueue::workers(queue.search);
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| queue.work());
        }
        let _closer = Closer(queue);
        f()
    })
}

/// The trials of `scene` at `c0s` with the starts `which`, made now by a
/// queue of their own (for a question outside an answer).
pub fn trials(
    scene: &Scene,
    search: &Search,
    c0s: &[f64],
    which: Starts,
    stop: &AtomicBool,
    bar: &ProgressBar,
) -> Result<Vec<Trial>> {
    let q = RunQueue::new(scene, search, stop, bar);
    with_workers(&q, || q.trials(c0s, which, Priority::Disordered))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The queue takes the highest priority first, among equals the first
    /// asked; asking again raises a queued run, never lowers it.
    #[test]
    fn the_most_urgent_run_goes_first() {
        let scene = Scene::builtin();
        let search = Search::default();
        let stop = AtomicBool::new(false);
        let bar = ProgressBar::hidden();
        let q = RunQueue::new(&scene, &search, &stop, &bar);
        let rule = q.runs_of(&[100.0], Starts::Both);
        assert_eq!(rule.len(), 4, "the perfect lattice and three seeds");
        assert_eq!(q.ask(&rule, Priority::Background), 4);
        assert_eq!(
            q.ask(&q.runs_of(&[10.0], Starts::Perfect), Priority::Ordered),
            1
        );
        assert_eq!(
            q.ask(&q.runs_of(&[3.0], Starts::Seeds), Priority::Disordered),
            3
        );
        let take = |q: &RunQueue| {
            let mut st = q.lock();
            let (k, run) = st.next().expect("a queued run");
            st.slots.insert(k, Slot::Running);
            run
        };
        let run = |c0, start| Run {
            c0,
            start,
            alpha: scene.alpha,
        };
        for seed in 1..=3 {
            assert_eq!(take(&q), run(3.0, (search.amplitude, seed)));
        }
        assert_eq!(take(&q), run(10.0, (0.0, 0)));
        // A rule's seed the search now needs jumps the queue; asked again
        // lower, it stays where it is; the running ones are not queued again.
        assert_eq!(q.ask(&[rule[2]], Priority::Disordered), 0);
        assert_eq!(q.ask(&[rule[2]], Priority::Background), 0);
        assert_eq!(
            q.ask(&q.runs_of(&[3.0], Starts::Seeds), Priority::Disordered),
            0
        );
        assert_eq!(take(&q), rule[2]);
        for r in [rule[0], rule[1], rule[3]] {
            assert_eq!(take(&q), r);
        }
        assert!(q.lock().next().is_none());
    }
}
