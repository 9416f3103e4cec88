//! `--shard k/n` and `--shard auto`: the part of a sweep's grid one job
//! runs, so n independent jobs (or a Slurm job array) cover the sweep.

/// `--shard k/n`: run only the points whose grid index is k modulo n
/// (0 <= k < n), so n independent jobs cover the sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s.trim() == "auto" {
            return Shard::from_slurm(|v| std::env::var(v).ok());
        }
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
}
