//! `--shard k/n` and `--shard auto`: the part of a sweep's grid one job
//! runs, so n independent jobs (or a Slurm job array) cover the sweep.

/// `--shard k/n`: run only the points whose grid index is k modulo n
/// (0 <= k < n), so n independent jobs cover the sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

/// `--shard` as given: `K/N`, or `auto` (read from a Slurm job array when
/// the sweep starts, unless the folder already records its shard).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShardArg {
    Fixed(Shard),
    Auto,
}

impl std::str::FromStr for ShardArg {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s.trim() == "auto" {
            Ok(ShardArg::Auto)
        } else {
            s.parse().map(ShardArg::Fixed)
        }
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl ShardArg {
    /// The shard a sweep into a folder runs: `recorded` is the one the
    /// folder's first run wrote (`shard.toml`; `None` when it has none or
    /// starts over). A folder keeps its shard: `auto` takes the recorded
    /// one whatever the array looks like now (a task resubmitted alone,
    /// `--array=1`, reads as shard 0 of 1, the whole grid), no `--shard`
    /// resumes it, and a different `K/N` is an error. `var` reads the
    /// environment (Slurm's variables). Returns the shard and a note to
    /// print when the recorded one was kept over what `auto` read.
    pub fn resolve(
        arg: Option<ShardArg>,
        recorded: Option<Shard>,
        var: impl Fn(&str) -> Option<String>,
        folder: &str,
    ) -> Result<(Option<Shard>, Option<String>), String> {
        match (arg, recorded) {
            (None, r) => Ok((r, None)),
            (Some(ShardArg::Fixed(s)), None) => Ok((Some(s), None)),
            (Some(ShardArg::Fixed(s)), Some(r)) if s == r => Ok((Some(s), None)),
            (Some(ShardArg::Fixed(s)), Some(r)) => Err(format!(
                "--shard {s}: {folder} is shard {r} of its sweep (its shard.toml, written by its first \
                 run): give --shard {r} (or --shard auto, or none) to resume it, or --force to start it \
                 over as {s}"
            )),
            (Some(ShardArg::Auto), Some(r)) => {
                let note = match Shard::from_slurm(&var) {
                    Ok(read) if read == r => None,
                    Ok(read) => Some(format!(
                        "--shard auto: {folder} is shard {r} (its shard.toml); this Slurm task reads as \
                         {read} of its own array (a task resubmitted alone?): keeping {r}"
                    )),
                    Err(e) => Some(format!(
                        "--shard auto: {folder} is shard {r} (its shard.toml); keeping it ({e})"
                    )),
                };
                Ok((Some(r), note))
            }
            (Some(ShardArg::Auto), None) => {
                let s = Shard::from_slurm(&var)?;
                let id = var("SLURM_ARRAY_TASK_ID").unwrap_or_default();
                // A one-task array whose task is not 0 is a task resubmitted
                // alone (--array=1): read as shard 0 of 1 it would run the
                // whole grid into one shard's folder.
                if s.n == 1 && id.trim() != "0" {
                    return Err(format!(
                        "--shard auto: this array has one task, {} (SLURM_ARRAY_TASK_ID={}, \
                         SLURM_ARRAY_TASK_COUNT=1), which reads as shard 0 of 1, the whole grid; \
                         {folder} records no shard to keep. If it resubmits task K of an array of \
                         N, give --shard K/N; for the whole grid in one task, submit --array=0",
                        id.trim(),
                        id.trim()
                    ));
                }
                Ok((Some(s), None))
            }
        }
    }
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || {
            format!("bad shard {s:?}: expected K/N with 0 <= K < N, e.g. 0/4 (Slurm: $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT)")
        };
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let (k, n): (usize, usize) = (
            k.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if n == 0 || k >= n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

impl Shard {
    /// `--shard auto`: this task's shard of a Slurm job array, k = (ID - MIN)
    /// / STEP of n = COUNT, from SLURM_ARRAY_TASK_ID, _COUNT, _MIN and
    /// (optional) _STEP as `var` gives them. Every missing or malformed
    /// variable is named.
    pub fn from_slurm(var: impl Fn(&str) -> Option<String>) -> Result<Shard, String> {
        let get = |name: &str, required: bool| -> Result<Option<usize>, String> {
            match var(name) {
                None if required => Err(format!(
                    "--shard auto: {name} is not set: run inside a Slurm job array (sbatch --array=0-3), or give --shard K/N"
                )),
                None => Ok(None),
                Some(v) => v.trim().parse::<usize>().map(Some).map_err(|_| {
                    format!("--shard auto: {name}={v:?} is not a non-negative whole number")
                }),
            }
        };
        let id = get("SLURM_ARRAY_TASK_ID", true)?.unwrap_or_default();
        let count = get("SLURM_ARRAY_TASK_COUNT", true)?.unwrap_or_default();
        let min = get("SLURM_ARRAY_TASK_MIN", true)?.unwrap_or_default();
        let step = get("SLURM_ARRAY_TASK_STEP", false)?.unwrap_or(1);
        if count == 0 || step == 0 {
            return Err(format!(
                "--shard auto: SLURM_ARRAY_TASK_COUNT={count} and SLURM_ARRAY_TASK_STEP={step} must be positive"
            ));
        }
        if id < min || (id - min) % step != 0 || (id - min) / step >= count {
            return Err(format!(
                "--shard auto: task {id} is not one of {count} evenly spaced tasks from {min} by {step} \
                 (SLURM_ARRAY_TASK_ID, _MIN, _STEP, _COUNT): submit a contiguous array such as --array=0-{}",
                count - 1
            ));
        }
        Ok(Shard {
            k: (id - min) / step,
            n: count,
        })
    }

    pub fn contains(&self, index: usize) -> bool {
        index % self.n == self.k
    }

    /// How many of a grid's `points` points are this shard's.
    pub fn size_of(&self, points: usize) -> usize {
        points / self.n + usize::from(points % self.n > self.k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_auto_reads_the_slurm_array() {
        let env = |pairs: &'static [(&'static str, &'static str)]| {
            move |v: &str| {
                pairs
                    .iter()
                    .find(|(k, _)| *k == v)
                    .map(|(_, x)| x.to_string())
            }
        };
        let s = Shard::from_slurm(env(&[
            ("SLURM_ARRAY_TASK_ID", "7"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
            ("SLURM_ARRAY_TASK_MIN", "5"),
        ]))
        .unwrap();
        assert_eq!((s.k, s.n), (2, 4), "k = ID - MIN");
        let s = Shard::from_slurm(env(&[
            ("SLURM_ARRAY_TASK_ID", "4"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
        ]))
        .unwrap();
        assert_eq!((s.k, s.n), (2, 3), "--array=0-4:2");
        // each missing variable is named
        for (missing, pairs) in [
            (
                "SLURM_ARRAY_TASK_ID",
                &[
                    ("SLURM_ARRAY_TASK_COUNT", "4"),
                    ("SLURM_ARRAY_TASK_MIN", "0"),
                ][..],
            ),
            (
                "SLURM_ARRAY_TASK_COUNT",
                &[("SLURM_ARRAY_TASK_ID", "1"), ("SLURM_ARRAY_TASK_MIN", "0")][..],
            ),
            (
                "SLURM_ARRAY_TASK_MIN",
                &[
                    ("SLURM_ARRAY_TASK_ID", "1"),
                    ("SLURM_ARRAY_TASK_COUNT", "4"),
                ][..],
            ),
        ] {
            let e = Shard::from_slurm(|v: &str| {
                pairs
                    .iter()
                    .find(|(k, _)| *k == v)
                    .map(|(_, x)| x.to_string())
            })
            .unwrap_err();
            assert!(e.contains(&format!("{missing} is not set")), "{e}");
        }
        // malformed, and outside the array
        let e = Shard::from_slurm(env(&[
            ("SLURM_ARRAY_TASK_ID", "x1"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
        ]))
        .unwrap_err();
        assert!(e.contains("SLURM_ARRAY_TASK_ID=\"x1\" is not"), "{e}");
        let e = Shard::from_slurm(env(&[
            ("SLURM_ARRAY_TASK_ID", "-1"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
        ]))
        .unwrap_err();
        assert!(e.contains("SLURM_ARRAY_TASK_ID"), "{e}");
        // a list array (--array=1,5,7) is not evenly spaced
        let e = Shard::from_slurm(env(&[
            ("SLURM_ARRAY_TASK_ID", "7"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
        ]))
        .unwrap_err();
        assert!(e.contains("contiguous array such as --array=0-2"), "{e}");
        let e = Shard::from_slurm(env(&[
            ("SLURM_ARRAY_TASK_ID", "0"),
            ("SLURM_ARRAY_TASK_COUNT", "0"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
        ]))
        .unwrap_err();
        assert!(e.contains("must be positive"), "{e}");
    }

    #[test]
    fn a_folder_keeps_its_shard_and_a_lone_resubmitted_task_is_not_the_whole_grid() {
        let slurm = |id: &'static str, count: &'static str, min: &'static str| {
            move |v: &str| match v {
                "SLURM_ARRAY_TASK_ID" => Some(id.to_string()),
                "SLURM_ARRAY_TASK_COUNT" => Some(count.to_string()),
                "SLURM_ARRAY_TASK_MIN" => Some(min.to_string()),
                _ => None,
            }
        };
        let s14 = Shard { k: 1, n: 4 };
        // The first run of task 1 of --array=0-3.
        let (s, note) =
            ShardArg::resolve(Some(ShardArg::Auto), None, slurm("1", "4", "0"), "s1").unwrap();
        assert_eq!((s, note), (Some(s14), None));
        // Resubmitted alone (--array=1): the folder's shard is kept, and said.
        let (s, note) =
            ShardArg::resolve(Some(ShardArg::Auto), Some(s14), slurm("1", "1", "1"), "s1").unwrap();
        assert_eq!(s, Some(s14));
        assert!(note.unwrap().contains("reads as 0/1"));
        // ... and with no record it is refused, not run as the whole grid.
        let e =
            ShardArg::resolve(Some(ShardArg::Auto), None, slurm("1", "1", "1"), "s1").unwrap_err();
        assert!(
            e.contains("reads as shard 0 of 1") && e.contains("--shard K/N"),
            "{e}"
        );
        // --array=0 alone is the whole grid in one task.
        let (s, _) =
            ShardArg::resolve(Some(ShardArg::Auto), None, slurm("0", "1", "0"), "s0").unwrap();
        assert_eq!(s, Some(Shard { k: 0, n: 1 }));
        // No --shard resumes the recorded one; another K/N is refused.
        assert_eq!(
            ShardArg::resolve(None, Some(s14), |_: &str| None, "s1")
                .unwrap()
                .0,
            Some(s14)
        );
        let e = ShardArg::resolve(
            Some(ShardArg::Fixed(Shard { k: 2, n: 8 })),
            Some(s14),
            |_: &str| None,
            "s1",
        )
        .unwrap_err();
        assert!(e.contains("is shard 1/4") && e.contains("--force"), "{e}");
        // The points of each shard add up to the grid's.
        for n in 1..7 {
            for points in 0..20 {
                let sum: usize = (0..n).map(|k| Shard { k, n }.size_of(points)).sum();
                assert_eq!(sum, points);
                for k in 0..n {
                    let count = (0..points).filter(|&i| Shard { k, n }.contains(i)).count();
                    assert_eq!(Shard { k, n }.size_of(points), count);
                }
            }
        }
    }
}
