//! A sweep's folder: `sweep.toml` (the sweep, which identifies it),
//! `results.jsonl` (one JSON row per finished point, appended and fsynced as
//! each finishes) and `results.csv` (the same rows in grid order, rewritten
//! atomically when a sweep ends or stops). A crash can cut only the last
//! JSON line short; such a line is ignored, and dropped when the sweep
//! resumes.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::fs::{File, OpenOptions};
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{bail, Context, Result};

use super::{Row, Shard, SweepSpec};
use crate::output::{prepare_dir, write_atomic};

pub const SPEC_FILE: &str = "sweep.toml";
pub const JSONL_FILE: &str = "results.jsonl";
pub const CSV_FILE: &str = "results.csv";
/// The shard a shard's folder holds (`--shard k/n`), written by its first
/// run: a resubmitted task keeps it, a merge names what is missing.
pub const SHARD_FILE: &str = "shard.toml";

/// The rows of a JSON-lines file, skipping a last line without its newline
/// (cut short by a crash). A missing file has no rows.
pub fn read_rows(path: &Path) -> Result<Vec<Row>> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(e).with_context(|| format!("reading {}", path.display())),
    };
    let complete = match text.rfind('\n') {
        Some(end) => &text[..=end],
        None => "",
    };
    complete
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, line)| {
            Row::from_json(line).with_context(|| {
                format!(
                    "{} line {}: not a sweep row; the file was edited or is from another version \
                     (remove the line, or restart the sweep with --force)",
                    path.display(),
                    i + 1
                )
            })
        })
        .collect()
}

/// Appends rows to `results.jsonl`, one line each, fsynced.
pub struct Appender {
    file: Mutex<File>,
    path: PathBuf,
}

impl Appender {
    /// Open the folder's row file for appending, first dropping a last line
    /// cut short by a crash.
    pub fn open(dir: &Path) -> Result<Appender> {
        let path = dir.join(JSONL_FILE);
        if let Ok(bytes) = std::fs::read(&path) {
            let keep = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
            if keep < bytes.len() {
                write_atomic(&path, &bytes[..keep])?;
            }
        }
        let file = OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
            .with_context(|| format!("opening {}", path.display()))?;
        Ok(Appender {
            file: Mutex::new(file),
            path,
        })
    }

    pub fn append(&self, row: &Row) -> Result<()> {
        let mut line = serde_json::to_string(row).expect("a row serialises");
        line.push('\n');
        let mut f = self.file.lock().unwrap();
        f.write_all(line.as_bytes())
            .and_then(|()| f.sync_data())
            .with_context(|| format!("appending to {}", self.path.display()))
    }
}

/// The CSV's columns: each one's name and its field of a row, in order.
type Column = (&'static str, fn(&Row) -> String);

const COLUMNS: &[Column] = &[
    ("index", |r| r.index.to_string()),
    ("id", |r| r.id.clone()),
    ("kernel", |r| r.kernel.clone()),
    ("n", |r| r.n.to_string()),
    ("re", |r| num(r.re)),
    ("alpha", |r| num(r.alpha)),
    ("lattice", |r| r.lattice.name().to_string()),
    ("h_over_d", |r| r.h_over_d.to_string()),
    ("jitter", |r| num(r.jitter)),
    ("seed", |r| r.seed.to_string()),
    ("c0_spec", |r| r.c0_spec.clone()),
    ("c0_rule", |r| r.c0_rule.clone()),
    ("c0", |r| num(r.c0)),
    ("c0_over_u", |r| num(r.c0_over_u)),
    ("class", |r| r.class.to_string()),
    ("failure_kind", |r| {
        r.failure_kind
            .map(|k| k.name())
            .unwrap_or_default()
            .to_string()
    }),
    ("failure_reason", |r| {
        r.failure_reason.clone().unwrap_or_default()
    }),
    ("linf", |r| num(r.linf)),
    ("linf_max", |r| num(r.linf_max)),
    ("l2", |r| num(r.l2)),
    ("max_eps", |r| num(r.max_eps)),
    ("eps_bound", |r| num(r.eps_bound)),
    // relative to U, as the column always was
    ("rms_v", |r| num(r.rms_v / r.u)),
    ("steps", |r| r.steps.to_string()),
    ("dt_limit_dominant", |r| {
        r.dt_limit_dominant
            .map(|l| l.name())
            .unwrap_or_default()
            .to_string()
    }),
    ("dt", |r| num(r.dt)),
    ("particles", |r| r.particles.to_string()),
    ("particle_steps", |r| num(r.particle_steps)),
    ("t_end", |r| num(r.t_end)),
    ("t", |r| num(r.t)),
    ("wall_s", |r| num(r.wall_s)),
    ("horizon", |r| r.horizon.to_string()),
    ("window_from", |r| num(r.window_from)),
    ("window_to", |r| num(r.window_to)),
    ("stationary", |r| r.stationary.to_string()),
    ("regime", |r| r.regime.to_string()),
    ("eps_stat", |r| num(r.eps_stat)),
    ("eps_max_mean", |r| num(r.eps_max_mean)),
    ("linf_stat", |r| num(r.linf_stat)),
    ("rms_v_stat", |r| num(r.rms_v_stat / r.u)),
    ("dy_rms", |r| num(r.dy_rms)),
    ("t_disorder", |r| r.t_disorder.map_or(String::new(), num)),
];

/// A number as the CSV writes it (NaN as `NaN`).
fn num(v: f64) -> String {
    v.to_string()
}

/// One CSV field, quoted when it holds a comma, a quote or a line break.
pub fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The rows as CSV (header first; NaN written `NaN`).
pub fn rows_csv(rows: &[Row]) -> String {
    let names: Vec<&str> = COLUMNS.iter().map(|c| c.0).collect();
    let mut out = names.join(",");
    out.push('\n');
    for r in rows {
        let line: Vec<String> = COLUMNS.iter().map(|c| csv_field(&c.1(r))).collect();
        let _ = writeln!(out, "{}", line.join(","));
    }
    out
}

/// The rows whose id is a point of `spec`'s grid, each given that point's
/// position [`Row::at`] (not stored: the id is).
pub fn on_grid(spec: &SweepSpec, rows: Vec<Row>) -> Vec<Row> {
    let at: std::collections::BTreeMap<String, crate::sweep::GridPosition> =
        spec.points().iter().map(|p| (p.id(), p.at)).collect();
    rows.into_iter()
        .filter_map(|mut r| {
            r.at = *at.get(&r.id)?;
            Some(r)
        })
        .collect()
}

/// Rows in grid order, one per id (the first of duplicates).
pub fn canonical(mut rows: Vec<Row>) -> Vec<Row> {
    let mut seen = BTreeSet::new();
    rows.retain(|r| seen.insert(r.id.clone()));
    rows.sort_by_key(|r| r.index);
    rows
}

pub fn write_csv(dir: &Path, rows: &[Row]) -> Result<()> {
    write_atomic(&dir.join(CSV_FILE), rows_csv(rows).as_bytes())
}

fn read_spec(dir: &Path) -> Result<Option<SweepSpec>> {
    let path = dir.join(SPEC_FILE);
    match std::fs::read_to_string(&path) {
        Ok(text) => Ok(Some(SweepSpec::from_toml(
            &text,
            &path.display().to_string(),
        )?)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e).with_context(|| format!("reading {}", path.display())),
    }
}

/// The shard `dir` records (its [`SHARD_FILE`]), if any.
pub fn read_shard(dir: &Path) -> Result<Option<Shard>> {
    let path = dir.join(SHARD_FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(e).with_context(|| format!("reading {}", path.display())),
    };
    #[derive(serde::Deserialize)]
    struct Record {
        k: usize,
        n: usize,
    }
    let r: Record = toml::from_str(&text).map_err(|e| {
        anyhow::anyhow!(
            "{}: {} (it records the folder's shard as k = K, n = N; remove it, or start over with --force)",
            path.display(),
            e.message().trim()
        )
    })?;
    if r.n == 0 || r.k >= r.n {
        bail!(
            "{}: k = {}, n = {} is not a shard (0 <= k < n); remove it, or start over with --force",
            path.display(),
            r.k,
            r.n
        );
    }
    Ok(Some(Shard { k: r.k, n: r.n }))
}

/// Record `shard` as `dir`'s (none: the whole grid, the record removed).
pub fn write_shard(dir: &Path, shard: Option<Shard>) -> Result<()> {
    let path = dir.join(SHARD_FILE);
    match shard {
        Some(s) => write_atomic(
            &path,
            format!(
                "# this folder is shard k of n of its sweep (--shard {s}): a resubmitted task keeps it\nk = {}\nn = {}\n",
                s.k, s.n
            )
            .as_bytes(),
        ),
        None => match std::fs::remove_file(&path) {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
            Err(e) => Err(e).with_context(|| format!("removing {}", path.display())),
        },
    }
}

/// Lock the sweep folder `dir` (created if missing) for this process: a
/// second sweep into it refuses instead of duplicating rows or mixing
/// files. The lock is the folder's own (flock on its descriptor), so no file
/// is added; it ends when the returned handle drops or the process ends,
/// however it ends.
///
/// A lock found held is tried again for up to [`LOCK_GRACE`] before the
/// refusal. A child process this one spawns shares its open descriptors
/// from the fork to the exec, so a lock dropped in that moment is still
/// held, by the child, for a few microseconds; a sweep that holds it
/// keeps it for far longer than the grace.
pub fn lock(dir: &Path) -> Result<std::fs::File> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("creating sweep folder {}", dir.display()))?;
    let f = std::fs::File::open(dir)
        .with_context(|| format!("opening sweep folder {}", dir.display()))?;
    let start = std::time::Instant::now();
    loop {
        match f.try_lock() {
            Ok(()) => return Ok(f),
            Err(std::fs::TryLockError::WouldBlock) if start.elapsed() < LOCK_GRACE => {
                std::thread::sleep(std::time::Duration::from_millis(10));
            }
            Err(std::fs::TryLockError::WouldBlock) => bail!(
                "sweep folder {} is in use by another sweep (locked): wait for it to finish, or choose another --out",
                dir.display()
            ),
            Err(std::fs::TryLockError::Error(e)) => {
                return Err(e).with_context(|| format!("locking sweep folder {}", dir.display()));
            }
        }
    }
}

/// How long [`lock`] tries a held lock again before it refuses.
pub const LOCK_GRACE: std::time::Duration = std::time::Duration::from_millis(500);

/// Open a sweep folder. With a `spec`: start it there (an existing folder
/// must hold the same sweep, whose finished rows are kept, unless `force`
/// starts over). Without: resume the sweep the folder holds. Returns the
/// sweep and its finished rows.
pub fn open(dir: &Path, spec: Option<SweepSpec>, force: bool) -> Result<(SweepSpec, Vec<Row>)> {
    let stored = if dir.is_dir() { read_spec(dir)? } else { None };
    match (stored, spec) {
        (Some(stored), spec) if !force => {
            if let Some(spec) = spec {
                if spec != stored {
                    bail!(
                        "{} holds a different sweep ({}); resume it with the same grid (or with no grid \
                         flags), choose another --out, or pass --force to start over",
                        dir.display(),
                        dir.join(SPEC_FILE).display()
                    );
                }
            }
            let rows = grid_rows(&stored, read_rows(&dir.join(JSONL_FILE))?, dir);
            Ok((stored, canonical(rows)))
        }
        (stored, spec) => {
            let spec = match (spec, stored) {
                (Some(s), _) => s,
                (None, Some(s)) => s,
                (None, None) => SweepSpec::default().resolved()?,
            };
            prepare_dir(dir, force)?;
            for f in [JSONL_FILE, CSV_FILE] {
                let p = dir.join(f);
                if p.exists() {
                    std::fs::remove_file(&p)
                        .with_context(|| format!("removing {}", p.display()))?;
                }
            }
            write_atomic(&dir.join(SPEC_FILE), spec.to_toml().as_bytes())?;
            Ok((spec, Vec::new()))
        }
    }
}

/// The rows of `dir`'s results that are points of `spec`'s grid; any other
/// is skipped, with a warning.
fn grid_rows(spec: &SweepSpec, rows: Vec<Row>, dir: &Path) -> Vec<Row> {
    let total = rows.len();
    let rows = on_grid(spec, rows);
    if rows.len() < total {
        eprintln!(
            "warning: {} row(s) of {} have an id that is not a point of this sweep's grid: \
             skipped (not counted, not written to {CSV_FILE})",
            total - rows.len(),
            dir.join(JSONL_FILE).display()
        );
    }
    rows
}

/// Combine the rows of shard folders of one sweep into `out`: every folder
/// must hold the same `sweep.toml`; a point finished in several keeps its
/// first row. Unless `partial`, every point of the grid must be finished
/// in some folder: a merge of an incomplete set is an error naming what is
/// missing (each shard folder's count, the shards not given), before `out`
/// is touched. `out` is locked like a sweep's folder while it is written.
/// Returns the sweep and the merged rows, in grid order.
pub fn merge(
    dirs: &[PathBuf],
    out: &Path,
    force: bool,
    partial: bool,
) -> Result<(SweepSpec, Vec<Row>)> {
    let Some(first) = dirs.first() else {
        bail!("merge needs at least one sweep folder");
    };
    let spec = read_spec(first)?
        .with_context(|| format!("{} is not a sweep folder (no {SPEC_FILE})", first.display()))?;
    let mut rows = Vec::new();
    for dir in dirs {
        let own = read_spec(dir)?
            .with_context(|| format!("{} is not a sweep folder (no {SPEC_FILE})", dir.display()))?;
        if own != spec {
            bail!(
                "{} holds a different sweep from {} (their {SPEC_FILE} differ): only shards of one sweep merge",
                dir.display(),
                first.display()
            );
        }
        rows.extend(grid_rows(&spec, read_rows(&dir.join(JSONL_FILE))?, dir));
    }
    let rows = canonical(rows);
    let total = spec.points().len();
    if rows.len() < total && !partial {
        bail!(
            "the folders hold {} of the grid's {total} points: {}; merge when every shard has \
             finished (resume a shard with the same command), or pass --partial to merge what there is",
            rows.len(),
            missing(dirs, &spec, total)?
        );
    }
    // One writer per folder: a sweep (or another merge) into `out` holds
    // its lock, and this waits for none.
    let _lock = lock(out)?;
    prepare_dir(out, force)?;
    write_atomic(&out.join(SPEC_FILE), spec.to_toml().as_bytes())?;
    let mut jsonl = String::new();
    for r in &rows {
        jsonl.push_str(&serde_json::to_string(r).expect("a row serialises"));
        jsonl.push('\n');
    }
    write_atomic(&out.join(JSONL_FILE), jsonl.as_bytes())?;
    write_csv(out, &rows)?;
    Ok((spec, rows))
}

/// What a merge of `dirs` lacks, in words: each shard folder's finished
/// points against its shard's, and the shards of the array not given.
fn missing(dirs: &[PathBuf], spec: &SweepSpec, total: usize) -> Result<String> {
    let ids: std::collections::BTreeMap<String, usize> =
        spec.points().iter().map(|p| (p.id(), p.index)).collect();
    let mut parts = Vec::new();
    let mut seen: Vec<Shard> = Vec::new();
    for dir in dirs {
        let done: BTreeSet<usize> = read_rows(&dir.join(JSONL_FILE))?
            .iter()
            .filter_map(|r| ids.get(&r.id).copied())
            .collect();
        match read_shard(dir)? {
            Some(s) => {
                seen.push(s);
                let own = s.size_of(total);
                let have = done.iter().filter(|&&i| s.contains(i)).count();
                if have < own {
                    parts.push(format!(
                        "{} (shard {s}) has {have} of its {own}",
                        dir.display()
                    ));
                }
            }
            None => parts.push(format!(
                "{} (no shard recorded) has {} points",
                dir.display(),
                done.len()
            )),
        }
    }
    if let Some(n) = seen.first().map(|s| s.n) {
        if seen.iter().all(|s| s.n == n) {
            let absent: Vec<String> = (0..n)
                .filter(|k| !seen.iter().any(|s| s.k == *k))
                .map(|k| format!("{k}/{n}"))
                .collect();
            if !absent.is_empty() {
                parts.push(format!(
                    "no folder given for shard{} {}",
                    if absent.len() > 1 { "s" } else { "" },
                    absent.join(", ")
                ));
            }
        }
    }
    Ok(parts.join("; "))
}
