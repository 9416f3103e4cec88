//! The grid of `shearsph sweep`: the sweep file, the `--scene` file and the
//! flags, laid over one another into a [`SweepSpec`], and where each value
//! came from ([`SweepOrigins`]) for the errors that name it.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use serde::Serialize;

use crate::sweep::{self, Origins, SweepSpec};

/// The sweep file, the `--scene` file and the grid's flags. Every flag but
/// the two files is the sweep field of its name (`--kernel` is `kernels`,
/// `--linf-bound` is `classes.linf_bound`, `--t-end` is `scene.t_end`):
/// [`GridArgs::fields`] serialises them, a flag not given left out, and
/// the sweep is the file's fields with those laid over them.
#[derive(Debug, Default, Args, Serialize)]
pub struct GridArgs {
    /// Sweep file (TOML).
    #[arg(long, value_name = "FILE")]
    #[serde(skip)]
    pub sweep: Option<PathBuf>,
    /// Kernels (default: every kernel).
    #[arg(long, value_delimiter = ',')]
    #[serde(rename = "kernels", skip_serializing_if = "Vec::is_empty")]
    pub kernel: Vec<String>,
    /// N values.
    #[arg(long, value_delimiter = ',')]
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub n: Vec<u32>,
    /// Reynolds numbers.
    #[arg(long, value_delimiter = ',')]
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub re: Vec<f64>,
    /// Artificial viscosity coefficients.
    #[arg(long, value_delimiter = ',')]
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub alpha: Vec<f64>,
    /// Sound speeds as rules ([F*]RULE, `shearsph run --help` lists every
    /// rule) or numbers.
    #[arg(long, value_delimiter = ',')]
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub c0: Vec<String>,
    /// Sound speeds as multiples of U.
    #[arg(long, value_delimiter = ',')]
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub c0_over_u: Vec<f64>,
    /// Starting lattices, by name: the help lists the kinds (`Lattice::ALL`).
    #[arg(long, value_delimiter = ',', help = lattice_help())]
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub lattice: Vec<crate::kernel::Lattice>,
    /// h/d values, numbers or exact rationals (1, 13/10; default 1); each
    /// lattice x h/d must be generated for every kernel.
    #[arg(long, value_delimiter = ',')]
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub h_over_d: Vec<crate::config::HOverD>,
    /// Jitter amplitudes of the start in d (default 0: the perfect lattice).
    #[arg(long, value_delimiter = ',')]
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub jitter: Vec<f64>,
    /// Seeds per non-zero jitter amplitude (seeds 1..=K, default 3); a
    /// perturbed point's outcome pools them (docs/stationary.md).
    #[arg(long, value_name = "K")]
    pub seeds: Option<u32>,
    /// A scene file whose fields every point starts from (the grid's win).
    #[arg(long = "scene", value_name = "FILE")]
    #[serde(skip)]
    pub scene_file: Option<PathBuf>,
    #[command(flatten)]
    pub scene: GridSceneArgs,
    #[command(flatten)]
    pub classes: GridClassArgs,
}

/// The grid's flags for fields of its `[scene]`.
#[derive(Debug, Default, Args, Serialize)]
pub struct GridSceneArgs {
    /// End time of every scene (default: the start-up's decay time).
    #[arg(long)]
    pub t_end: Option<f64>,
    /// Tolerance for the default end time.
    #[arg(long)]
    pub decay_tol: Option<f64>,
}

/// The grid's flags for fields of its `[classes]`.
#[derive(Debug, Default, Args, Serialize)]
pub struct GridClassArgs {
    /// L_inf error / U above which a run is `inaccurate` (default 0.05).
    #[arg(long)]
    pub linf_bound: Option<f64>,
    /// Compaction above the kernel's eps0 at which a run is
    /// `over-compressed` (default 0.01).
    #[arg(long)]
    pub eps_margin: Option<f64>,
}

/// `--lattice`'s help: "Starting lattices: triangular (the paper's,
/// default), square", from the list of kinds.
fn lattice_help() -> String {
    let kinds = crate::kernel::Lattice::listed(", ", |l| {
        let papers = if l.is_papers() {
            " (the paper's, default)"
        } else {
            ""
        };
        format!("{}{papers}", l.name())
    });
    format!("Starting lattices: {kinds}")
}

impl GridArgs {
    /// The flags given, as the sweep fields they set (`[scene]` and
    /// `[classes]` as tables, left out when none of theirs is given).
    pub fn fields(&self) -> toml::Table {
        let mut t = toml::Table::try_from(self).expect("grid flags are numbers and strings");
        t.retain(|_, v| !matches!(v, toml::Value::Table(sub) if sub.is_empty()));
        t
    }

    /// The flags given, by their fields' dotted names (`n`,
    /// `classes.linf_bound`, `scene.t_end`).
    pub fn given(&self) -> Vec<String> {
        let mut names = Vec::new();
        for (key, value) in self.fields() {
            match value {
                toml::Value::Table(sub) => {
                    names.extend(sub.keys().map(|k| format!("{key}.{k}")));
                }
                _ => names.push(key),
            }
        }
        names
    }

    fn has_grid(&self) -> bool {
        self.sweep.is_some() || self.scene_file.is_some() || !self.fields().is_empty()
    }

    /// Where each of the grid's values came from: the flags given, the
    /// sweep file's fields, the `--scene` file's.
    pub fn origins(&self) -> Result<SweepOrigins> {
        let read = |path: &Path, what: &str| -> Result<toml::Table> {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("reading {what} {}", path.display()))?;
            text.parse().map_err(|e: toml::de::Error| {
                anyhow::anyhow!("{what} {}: {}", path.display(), e.message().trim())
            })
        };
        Ok(SweepOrigins {
            flags: self.given(),
            file: match &self.sweep {
                Some(p) => Some((p.clone(), read(p, "sweep file")?)),
                None => None,
            },
            scene_file: match &self.scene_file {
                Some(p) => Some((p.clone(), read(p, "scene file")?)),
                None => None,
            },
        })
    }

    /// The sweep the flags and files give, or `None` for "the folder's
    /// own": the sweep file's fields, its `[scene]` overlaid by the
    /// `--scene` file, then the flags' fields (a `--c0` or `--c0-over-u`
    /// replaces both of the file's c0 lists).
    pub fn spec(&self) -> Result<Option<SweepSpec>> {
        if !self.has_grid() {
            return Ok(None);
        }
        let origins = self.origins()?;
        let mut table = match &origins.file {
            Some((path, table)) => {
                // The file's own errors, by its name, before any flag is
                // laid over it.
                let text = std::fs::read_to_string(path)
                    .with_context(|| format!("reading sweep file {}", path.display()))?;
                SweepSpec::from_toml(&text, &format!("sweep file {}", path.display()))?;
                table.clone()
            }
            None => toml::Table::new(),
        };
        let flags = self.fields();
        if flags.contains_key("c0") || flags.contains_key("c0_over_u") {
            table.remove("c0");
            table.remove("c0_over_u");
        }
        if let Some((_, scene)) = &origins.scene_file {
            crate::config::overlay(sub_table(&mut table, "scene"), scene.clone());
        }
        for (key, value) in flags {
            match value {
                toml::Value::Table(sub) => sub_table(&mut table, &key).extend(sub),
                value => {
                    table.insert(key, value);
                }
            }
        }
        let spec: SweepSpec = toml::Value::Table(table)
            .try_into()
            .map_err(|e: toml::de::Error| anyhow::anyhow!("sweep: {}", e.message().trim()))?;
        Ok(Some(spec.resolved_as(&origins)?))
    }
}

/// The table `key` of `table` (made empty when missing; a sweep file whose
/// `key` is not a table was refused before).
fn sub_table<'a>(table: &'a mut toml::Table, key: &str) -> &'a mut toml::Table {
    let entry = table
        .entry(key)
        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
    if !entry.is_table() {
        *entry = toml::Value::Table(toml::Table::new());
    }
    entry.as_table_mut().expect("a table")
}

/// Where a sweep's values came from: the grid's fields given as flags, the
/// sweep file's and the `--scene` file's tables (see [`Origins`]).
#[derive(Debug, Default)]
pub struct SweepOrigins {
    /// Grid fields (`n`, `classes.linf_bound`, `scene.t_end`) set by a flag.
    flags: Vec<String>,
    file: Option<(PathBuf, toml::Table)>,
    scene_file: Option<(PathBuf, toml::Table)>,
}

impl SweepOrigins {
    fn flag(&self, field: &str) -> bool {
        self.flags.iter().any(|f| f == field)
    }

    /// Whether the sweep file has `field` (`n`, `classes.linf_bound`,
    /// `scene.gamma`).
    fn in_file(&self, field: &str) -> Option<&Path> {
        let (path, table) = self.file.as_ref()?;
        let mut t = table;
        let mut parts = field.split('.').peekable();
        while let Some(part) = parts.next() {
            let v = t.get(part)?;
            if parts.peek().is_none() {
                return Some(path);
            }
            t = v.as_table()?;
        }
        None
    }
}

impl Origins for SweepOrigins {
    fn grid(&self, field: &str) -> String {
        let flag = sweep::grid_flag(field);
        if self.flag(field) {
            format!("flag --{flag}")
        } else if let Some(path) = self.in_file(field) {
            format!("sweep file {}, field `{field}`", path.display())
        } else {
            format!("sweep field `{field}`, by default (flag --{flag})")
        }
    }

    fn scene(&self, field: &str) -> String {
        if self.flag(&format!("scene.{field}")) {
            format!("flag --{}", field.replace('_', "-"))
        } else if let Some((path, _)) = self
            .scene_file
            .as_ref()
            .filter(|(_, t)| t.contains_key(field))
        {
            format!("scene file {} (--scene), field `{field}`", path.display())
        } else if let Some(path) = self.in_file(&format!("scene.{field}")) {
            format!("sweep file {}, field `scene.{field}`", path.display())
        } else {
            format!("the base scene's `{field}`, by default")
        }
    }

    fn scene_table(&self) -> String {
        match (&self.file, &self.scene_file) {
            (_, Some((p, _))) => format!("the base scene (scene file {}, --scene)", p.display()),
            (Some((p, _)), None) => format!("sweep file {}, table [scene]", p.display()),
            _ => "the base scene".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::{CommandFactory, Parser};

    use super::GridArgs;
    use crate::kernel::Lattice;

    #[derive(Parser)]
    #[command(allow_negative_numbers = true)]
    struct Cli {
        #[command(flatten)]
        grid: GridArgs,
    }

    /// Every grid flag given lands in the sweep field of its name, laid over
    /// the sweep file's and the `--scene` file's; the errors name each field
    /// by that flag again (`sweep::grid_flag`); a flag not given is left out.
    #[test]
    fn every_grid_flag_is_the_sweep_field_of_its_name() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("scene.toml");
        std::fs::write(&scene, "u = 2.0\ndecay_tol = 0.5\n").unwrap();
        let file = dir.path().join("sweep.toml");
        std::fs::write(
            &file,
            "n = [6]\nc0_over_u = [3.0]\n[classes]\neps_margin = 0.5\n",
        )
        .unwrap();
        let (scene, file) = (scene.to_str().unwrap(), file.to_str().unwrap());
        let all = Cli::parse_from([
            "x",
            "--sweep",
            file,
            "--kernel",
            "monaghan",
            "--n",
            "8,12",
            "--re",
            "3",
            "--alpha",
            "0.05",
            "--c0",
            "rule10",
            "--c0-over-u",
            "4",
            "--lattice",
            "square",
            "--h-over-d",
            "13/10",
            "--jitter",
            "0.01",
            "--seeds",
            "2",
            "--scene",
            scene,
            "--t-end",
            "3",
            "--decay-tol",
            "0.02",
            "--linf-bound",
            "0.1",
            "--eps-margin",
            "0.02",
        ])
        .grid;
        let mut given = all.given();
        given.sort();
        assert_eq!(
            given,
            [
                "alpha",
                "c0",
                "c0_over_u",
                "classes.eps_margin",
                "classes.linf_bound",
                "h_over_d",
                "jitter",
                "kernels",
                "lattice",
                "n",
                "re",
                "scene.decay_tol",
                "scene.t_end",
                "seeds"
            ]
        );
        let cli = Cli::command();
        for field in &given {
            let flag = match field.strip_prefix("scene.") {
                Some(f) => f.replace('_', "-"),
                None => crate::sweep::grid_flag(field),
            };
            assert!(
                cli.get_arguments().any(|a| a.get_long() == Some(&flag)),
                "{field}: no flag --{flag}"
            );
        }
        let s = all.spec().unwrap().expect("a grid");
        assert_eq!(s.kernels, ["monaghan"]);
        assert_eq!(
            (s.n.as_slice(), s.re.as_slice()),
            (&[8, 12][..], &[3.0][..])
        );
        assert_eq!(
            (s.alpha.as_slice(), s.jitter.as_slice()),
            (&[0.05][..], &[0.01][..])
        );
        assert_eq!(
            (s.c0.as_slice(), s.c0_over_u.as_slice()),
            (&["rule10".to_string()][..], &[4.0][..])
        );
        assert_eq!(s.lattice, [Lattice::Square]);
        assert_eq!(s.h_over_d[0].to_string(), "13/10");
        assert_eq!(s.seeds, 2);
        assert_eq!((s.classes.linf_bound, s.classes.eps_margin), (0.1, 0.02));
        assert_eq!(s.scene["u"].as_float(), Some(2.0));
        assert_eq!(s.scene["t_end"].as_float(), Some(3.0));
        assert_eq!(s.scene["decay_tol"].as_float(), Some(0.02));

        // The file's fields stand where no flag is given; a c0 flag
        // replaces both of its c0 lists.
        let some = Cli::parse_from(["x", "--sweep", file, "--c0", "rule10"]).grid;
        let s = some.spec().unwrap().expect("a grid");
        assert_eq!((s.n.as_slice(), s.c0_over_u.len()), (&[6][..], 0));
        assert_eq!(s.classes.eps_margin, 0.5);

        let none = Cli::parse_from(["x"]).grid;
        assert!(none.fields().is_empty());
        assert!(none.spec().unwrap().is_none());
    }
}
