//! The bounds of every count a command takes, in one place: seeds, threads,
//! scenes at once, grid points, repeats, output frames. Each says why
//! (memory, threads, time), and each is checked before any work, so that a
//! count of 1e9 is an error in milliseconds, not an hour of allocation or a
//! machine of threads that no signal can stop. The sizes a scene sets
//! (particles, samples kept, run time) have their own estimates in
//! `crate::problem::cost`; the lists a grid takes are [`distinct`].

use std::fmt::Debug;

/// A count outside its bounds, with the name it was given by (a flag, a
/// file's field) and why the bound is there.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{name} = {value}: {reason}")]
pub struct CountError {
    pub name: String,
    pub value: u64,
    pub reason: String,
}

/// The range of one count and why it has its ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Count {
    pub min: u64,
    pub max: u64,
    /// Why not fewer than `min` (e.g. "0 seeds give a jittered start no run").
    pub why_min: &'static str,
    /// Why not more than `max` (memory, threads, time).
    pub why_max: &'static str,
}

impl Count {
    /// Ok when `min <= value <= max`, else the error naming `name` (as the
    /// user gave it: `--seeds`, `sweep file grid.toml: seeds`), the bound
    /// and why.
    pub fn check(&self, name: &str, value: u64) -> Result<(), CountError> {
        let reason = if value < self.min {
            format!("give at least {} ({})", self.min, self.why_min)
        } else if value > self.max {
            format!(
                "above the bound of {} ({}); give at most {}",
                self.max, self.why_max, self.max
            )
        } else {
            return Ok(());
        };
        Err(CountError {
            name: name.to_string(),
            value,
            reason,
        })
    }

    /// [`Count::check`] for a `usize` count.
    pub fn check_usize(&self, name: &str, value: usize) -> Result<(), CountError> {
        self.check(name, u64::try_from(value).unwrap_or(u64::MAX))
    }
}

/// Seeds of a jittered start: at most 1,000, since each seed is one more
/// run of every c0 (a sweep: of every point), and the seeds' pooled window
/// statistics agree to a few per cent with 3 on a strip as wide as the
/// channel (docs/stationary.md).
pub const SEEDS: Count = Count {
    min: 1,
    max: 1_000,
    why_min: "a jittered start needs at least one seed",
    why_max: "each seed is one more run of every point, and 3 seeds' pooled statistics agree to a few per cent",
};

/// The cores this process may use (its affinity and cgroup quota).
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Threads of one process (scenes at once x threads per scene, a bench's
/// pool): at most 8 per core. More only take turns on the cores, each
/// with its stack (2 MiB for a rayon worker), and a machine of threads
/// takes minutes to start and to stop on a signal.
pub fn threads() -> Count {
    Count {
        min: 1,
        max: 8 * cores() as u64,
        why_min: "no thread runs nothing",
        why_max: "8 per core of this machine's; more only take turns on the cores, and each has its stack",
    }
}

/// Points of a sweep's grid: at most 1,000,000. Each is a row of about
/// 1.2 kB in `results.jsonl` and as much in memory when `results.csv` is
/// rewritten (1.2 GB at the bound), and at least one run.
pub const POINTS: Count = Count {
    min: 1,
    max: 1_000_000,
    why_min: "a grid with no point runs nothing",
    why_max: "each point is a row of about 1.2 kB in results.jsonl and in memory, 1.2 GB at the bound; split a larger grid into sweeps",
};

/// Repeats of a bench measurement: at most 100 (the median of 100 is as
/// good as the machine's noise allows; the time bound counts them too).
pub const REPEATS: Count = Count {
    min: 1,
    max: 100,
    why_min: "a measurement needs one run",
    why_max: "the median of 100 repeats is as steady as the machine allows",
};

/// Ok unless a value is given twice: a repeated value would run (and
/// count, and fit) one point twice. `name` is how the user gave the list.
pub fn distinct<T: PartialEq + Debug>(name: &str, values: &[T]) -> Result<(), DuplicateError> {
    for (i, a) in values.iter().enumerate() {
        if values[..i].contains(a) {
            return Err(DuplicateError {
                name: name.to_string(),
                value: format!("{a:?}"),
            });
        }
    }
    Ok(())
}

/// A list that gives one value twice.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{name} gives {value} twice: give each value once")]
pub struct DuplicateError {
    pub name: String,
    pub value: String,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_count_names_its_bound_and_why() {
        assert!(SEEDS.check("--seeds", 3).is_ok());
        let e = SEEDS.check("--seeds", 1_000_000_000).unwrap_err();
        assert_eq!(e.name, "--seeds");
        let e = e.to_string();
        assert!(
            e.starts_with("--seeds = 1000000000: above the bound of 1000"),
            "{e}"
        );
        assert!(e.contains("give at most 1000"), "{e}");
        let e = SEEDS.check("--seeds", 0).unwrap_err().to_string();
        assert!(e.contains("give at least 1"), "{e}");
        let e = distinct("--n", &[10, 12, 10]).unwrap_err().to_string();
        assert_eq!(e, "--n gives 10 twice: give each value once");
        assert!(threads().max >= 8);
    }
}
