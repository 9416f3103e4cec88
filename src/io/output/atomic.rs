//! The write path of every output folder: [`prepare_dir`] before a run,
//! [`write_atomic`] for one file, and [`StagedSet`] for a whole set of files
//! (a run's, the report's) that must be replaced together.
//!
//! A set is written into a staging folder inside the output folder (so on
//! the same file system, whatever is mounted where, and needing no write
//! permission above it) and swapped in only when every file is complete:
//! a disk that fills, or any other error, while the set is written leaves
//! the earlier set untouched and the staging folder removed. The swap only
//! renames (it needs no space); it replaces the files the new set has, and
//! removes the files of the earlier set this tool wrote (listed in
//! [`MANIFEST`]) that the new one lacks, so no stale file of an older run
//! stays beside the new ones. Any other file in the folder, the user's, is
//! never moved or deleted. Should a rename fail midway, the renames done
//! are undone in reverse order, which restores the earlier set.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use anyhow::{bail, Context, Result};

/// The names of the files of the set last committed into a folder, one a
/// line: what a later [`StagedSet::commit`] may replace or remove.
pub const MANIFEST: &str = ".shearsph-files";

/// A per-process serial, so that two temporary names never collide.
fn serial() -> u64 {
    static SERIAL: AtomicU64 = AtomicU64::new(0);
    SERIAL.fetch_add(1, Ordering::Relaxed)
}

/// The prefix of a staging folder's name; the rest is `PID-SERIAL`.
const STAGING_PREFIX: &str = ".shearsph-staging-";

/// Remove the staging folders in `dir` that no live process owns: left by
/// a run killed (SIGKILL, a crash, a power cut) before its set was swapped
/// in. Each is ours by its name, and its owner holds a lock on it while it
/// lives ([`StagedSet::begin`]); one whose lock is free and whose process
/// (the PID in its name) is gone is stale. Returns how many were removed.
pub fn remove_stale_staging(dir: &Path) -> usize {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    let mut removed = 0;
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name.strip_prefix(STAGING_PREFIX) else {
            continue;
        };
        let Some(pid) = rest.split('-').next().and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        let path = e.path();
        let is_dir = path.symlink_metadata().is_ok_and(|m| m.is_dir());
        // Ours (another StagedSet of this process) or a live process's:
        // left alone, even in the instant before its owner locks it.
        if !is_dir || pid == std::process::id() || Path::new(&format!("/proc/{pid}")).exists() {
            continue;
        }
        let Ok(f) = std::fs::File::open(&path) else {
            continue;
        };
        if f.try_lock().is_ok() && std::fs::remove_dir_all(&path).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// Make sure `dir` can take a run's outputs: create it, or refuse when it
/// exists with files in it and `force` is not set (stale staging folders,
/// [`remove_stale_staging`], are removed first and do not count). Call
/// before running, so a refused folder costs nothing.
pub fn prepare_dir(dir: &Path, force: bool) -> Result<()> {
    if dir.exists() {
        if !dir.is_dir() {
            bail!("output path {} exists and is not a folder", dir.display());
        }
        remove_stale_staging(dir);
        let non_empty = std::fs::read_dir(dir)
            .with_context(|| format!("reading output folder {}", dir.display()))?
            .next()
            .is_some();
        if non_empty && !force {
            bail!(
                "output folder {} already exists and is not empty; pass --force to overwrite its files, or choose \
                 another with --out",
                dir.display()
            );
        }
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("creating output folder {}", dir.display()))?;
    // Writable? A probe file of our own, created and removed now, so a
    // read-only folder is found before the run, not after it.
    let probe = dir.join(format!(".shearsph-probe-{}", std::process::id()));
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .with_context(|| {
            format!(
                "output folder {} is not writable (a test file could not be created there); \
                 fix its permissions or choose another with --out",
                dir.display()
            )
        })?;
    std::fs::remove_file(&probe).with_context(|| format!("removing {}", probe.display()))
}

/// Write `bytes` to `path` atomically: a new file beside it (same folder,
/// so the rename cannot cross file systems), renamed over the target. The
/// file gets the usual permissions (the umask's), like any other.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("out");
    let tmp = dir.join(format!(".{name}.tmp-{}-{}", std::process::id(), serial()));
    // Only a temporary file this call created is removed on an error: a
    // file that already had its name (create_new refused it) is not ours.
    let mut created = false;
    let written = (|| -> std::io::Result<()> {
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)?;
        created = true;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if written.is_err() && created {
        let _ = std::fs::remove_file(&tmp);
    }
    written.with_context(|| format!("writing {}", path.display()))
}

/// A set of output files written aside and swapped into a folder together
/// (see the module's notes). Dropped without [`StagedSet::commit`] (an
/// error on the way), it removes what it staged and the folder keeps its
/// earlier set.
#[derive(Debug)]
pub struct StagedSet {
    dir: PathBuf,
    stage: PathBuf,
    /// The staging folder, locked while this set lives: what tells a later
    /// run it is not stale.
    _lock: std::fs::File,
}

impl StagedSet {
    /// Start a set for `dir`, which must exist (see [`prepare_dir`]); stale
    /// staging folders of dead runs are removed first.
    pub fn begin(dir: &Path) -> Result<StagedSet> {
        remove_stale_staging(dir);
        let stage = dir.join(format!(
            "{STAGING_PREFIX}{}-{}",
            std::process::id(),
            serial()
        ));
        std::fs::create_dir(&stage)
            .with_context(|| format!("creating the staging folder {}", stage.display()))?;
        let lock = std::fs::File::open(&stage)
            .and_then(|f| f.try_lock().map(|()| f).map_err(std::io::Error::other))
            .with_context(|| format!("locking the staging folder {}", stage.display()));
        let lock = match lock {
            Ok(l) => l,
            Err(e) => {
                let _ = std::fs::remove_dir(&stage);
                return Err(e);
            }
        };
        Ok(StagedSet {
            dir: dir.to_path_buf(),
            stage,
            _lock: lock,
        })
    }

    /// The staging folder, for a writer of its own (the particle series):
    /// every file in it when [`StagedSet::commit`] is called is part of the
    /// set.
    pub fn path(&self) -> &Path {
        &self.stage
    }

    /// The output folder the set goes into.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Stage the file `name` (a plain file name) of the set.
    pub fn put(&self, name: &str, bytes: &[u8]) -> Result<()> {
        write_atomic(&self.stage.join(plain_name(name)?), bytes)
    }

    /// Swap the staged files into the folder: each replaces the file of the
    /// same name, the earlier set's files that are not in this one are
    /// removed, and [`MANIFEST`] lists the new set. On an error the folder
    /// is as it was. Returns the names of the set, sorted.
    pub fn commit(self) -> Result<Vec<String>> {
        let names = self.staged_names()?;
        self.put(MANIFEST, manifest_text(&names).as_bytes())?;
        let stale: Vec<String> = earlier_set(&self.dir)
            .into_iter()
            .filter(|n| names.binary_search(n).is_err())
            .collect();
        let aside = self.dir.join(format!(
            ".shearsph-replaced-{}-{}",
            std::process::id(),
            serial()
        ));
        std::fs::create_dir(&aside).with_context(|| format!("creating {}", aside.display()))?;
        let mut done: Vec<(PathBuf, PathBuf)> = Vec::new();
        let swapped = self.swap(&names, &stale, &aside, &mut done);
        if let Err(e) = swapped {
            // Undo in reverse: the earlier set back in place.
            for (from, to) in done.iter().rev() {
                let _ = std::fs::rename(to, from);
            }
            let _ = std::fs::remove_dir_all(&aside);
            return Err(e.context(format!(
                "replacing the outputs in {}; the earlier ones are kept",
                self.dir.display()
            )));
        }
        std::fs::remove_dir_all(&aside).with_context(|| {
            format!(
                "the new outputs are in {}, but the replaced ones could not be removed from {}",
                self.dir.display(),
                aside.display()
            )
        })?;
        Ok(names)
    }

    /// The staged files' names, sorted; a folder in the staging area is a
    /// bug of the writer.
    fn staged_names(&self) -> Result<Vec<String>> {
        let mut names = Vec::new();
        let entries = std::fs::read_dir(&self.stage)
            .with_context(|| format!("reading {}", self.stage.display()))?;
        for e in entries {
            let e = e.with_context(|| format!("reading {}", self.stage.display()))?;
            let name = e.file_name().to_string_lossy().into_owned();
            if !e.file_type()?.is_file() {
                bail!(
                    "{} is not a file: a set holds files only",
                    e.path().display()
                );
            }
            if name != MANIFEST {
                names.push(name);
            }
        }
        names.sort();
        Ok(names)
    }

    /// The renames of [`StagedSet::commit`], each logged in `done` as
    /// (from, to) once it happened.
    fn swap(
        &self,
        names: &[String],
        stale: &[String],
        aside: &Path,
        done: &mut Vec<(PathBuf, PathBuf)>,
    ) -> Result<()> {
        let mut rename = |from: PathBuf, to: PathBuf| -> Result<()> {
            std::fs::rename(&from, &to)
                .with_context(|| format!("moving {} to {}", from.display(), to.display()))?;
            done.push((from, to));
            Ok(())
        };
        for name in names.iter().map(String::as_str).chain([MANIFEST]) {
            let target = self.dir.join(name);
            let existing = target.symlink_metadata();
            if existing.as_ref().is_ok_and(|m| m.is_dir()) {
                bail!(
                    "{} is a folder, not a file of ours: move it, or choose another --out",
                    target.display()
                );
            }
            if existing.is_ok() {
                rename(target.clone(), aside.join(name))?;
            }
            rename(self.stage.join(name), target)?;
        }
        for name in stale {
            let old = self.dir.join(name);
            if old.symlink_metadata().is_ok_and(|m| m.is_file()) {
                rename(old, aside.join(name))?;
            }
        }
        Ok(())
    }
}

impl Drop for StagedSet {
    fn drop(&mut self) {
        // Only our own folder, and only what was staged in it (after a
        // commit, nothing but an empty folder).
        let _ = std::fs::remove_dir_all(&self.stage);
    }
}

/// `name` if it is a plain file name (no folder, not `.` or `..`).
fn plain_name(name: &str) -> Result<&str> {
    let plain = !name.is_empty()
        && name != "."
        && name != ".."
        && !name.contains('/')
        && !name.contains(std::path::MAIN_SEPARATOR);
    if !plain {
        bail!("{name:?} is not a plain file name: a set holds the files of one folder");
    }
    Ok(name)
}

fn manifest_text(names: &[String]) -> String {
    let mut text =
        String::from("# the files shearsph wrote here last; it may replace or remove them\n");
    for n in names {
        text.push_str(n);
        text.push('\n');
    }
    text
}

/// The names the folder's [`MANIFEST`] lists (none without one); lines that
/// are not plain file names are ignored.
fn earlier_set(dir: &Path) -> Vec<String> {
    let Ok(text) = std::fs::read_to_string(dir.join(MANIFEST)) else {
        return Vec::new();
    };
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .filter(|l| plain_name(l).is_ok() && *l != MANIFEST)
        .map(str::to_string)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn files(dir: &Path) -> Vec<(String, String)> {
        let mut v: Vec<(String, String)> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap())
            .filter(|e| e.file_type().unwrap().is_file())
            .map(|e| {
                (
                    e.file_name().to_string_lossy().into_owned(),
                    std::fs::read_to_string(e.path()).unwrap(),
                )
            })
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_set_replaces_its_own_files_only() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("mine.txt"), "the user's").unwrap();
        let set = StagedSet::begin(d).unwrap();
        set.put("a.csv", b"a1").unwrap();
        set.put("b.csv", b"b1").unwrap();
        assert_eq!(set.commit().unwrap(), ["a.csv", "b.csv"]);
        // The second set lacks b.csv: removed; mine.txt stays.
        let set = StagedSet::begin(d).unwrap();
        set.put("a.csv", b"a2").unwrap();
        set.put("c.csv", b"c2").unwrap();
        set.commit().unwrap();
        let got = files(d);
        let names: Vec<&str> = got.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, [MANIFEST, "a.csv", "c.csv", "mine.txt"]);
        assert_eq!(got[1].1, "a2");
        assert_eq!(got[3].1, "the user's");
        // Nothing left but the set and the user's file.
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 4);
    }

    #[test]
    fn a_dead_runs_staging_is_removed_and_a_live_ones_kept() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        // A killed run's: a PID no process has (above the kernel's limit).
        let dead = d.join(format!("{STAGING_PREFIX}4294967295-0"));
        std::fs::create_dir(&dead).unwrap();
        std::fs::write(dead.join("summary.json"), "{}").unwrap();
        // A live one (this process's own set) and the user's folder.
        let live = StagedSet::begin(d).unwrap();
        assert!(!dead.exists(), "begin removes a dead run's staging");
        std::fs::create_dir(&dead).unwrap();
        std::fs::create_dir(d.join("mine")).unwrap();
        assert_eq!(remove_stale_staging(d), 1);
        assert!(live.path().exists() && d.join("mine").exists());
        // Only stale staging in a folder: it is empty for prepare_dir.
        drop(live);
        let only = tempfile::tempdir().unwrap();
        std::fs::create_dir(only.path().join(format!("{STAGING_PREFIX}4294967295-7"))).unwrap();
        prepare_dir(only.path(), false).unwrap();
        assert_eq!(std::fs::read_dir(only.path()).unwrap().count(), 0);
    }

    #[test]
    fn a_set_dropped_uncommitted_changes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let set = StagedSet::begin(d).unwrap();
        set.put("a.csv", b"a1").unwrap();
        set.commit().unwrap();
        let before = files(d);
        {
            let set = StagedSet::begin(d).unwrap();
            set.put("a.csv", b"a2").unwrap();
            assert!(set.put("../x", b"x").is_err());
        }
        assert_eq!(files(d), before);
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 2);
    }

    /// A file that already has the temporary name write_atomic picks is not
    /// its own: the write fails and that file is left as it was.
    #[test]
    fn write_atomic_never_removes_a_file_it_did_not_create() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let next = serial() + 1;
        let pid = std::process::id();
        // Decoys for the next serials, whichever other tests take some.
        for s in next..next + 4096 {
            std::fs::write(d.join(format!(".out.csv.tmp-{pid}-{s}")), b"not ours").unwrap();
        }
        assert!(write_atomic(&d.join("out.csv"), b"new").is_err());
        assert!(!d.join("out.csv").exists());
        let decoys = std::fs::read_dir(d).unwrap().count();
        assert_eq!(decoys, 4096, "a decoy was removed");
        for e in std::fs::read_dir(d).unwrap() {
            assert_eq!(std::fs::read(e.unwrap().path()).unwrap(), b"not ours");
        }
    }
}
