//! The report's plan: every scene it runs, each once, with the places in
//! the report it serves as typed keys (grid indices as integers, the rule
//! as a [`C0Rule`]). The report joins rows to its tables and figures by
//! these keys and the rows' grid index, never by comparing strings or
//! floats.

use std::collections::BTreeMap;

use super::config::ReportConfig;
use crate::config::{C0Rule, C0Spec};
use crate::kernel::{DiscretisationInfo, KernelInfo};
use crate::problem::c0::all_rules_on;
use crate::sweep::{pool_rows, Discretisation, HOverD, Point, PointC0, Row};

impl ReportConfig {
    /// The maps' Re (indices into maps.re) a case runs.
    fn map_res(&self, case: Case) -> Vec<usize> {
        let keep = |re: &f64| {
            (!case.perturbed || self.perturbed.re.contains(re)) && self.case_runs_at(case.disc, *re)
        };
        (0..self.maps.re.len())
            .filter(|&i| keep(&self.maps.re[i]))
            .collect()
    }

    /// Every scene of the report but the bisection's, each once, with its
    /// keys: the speed grid (the paper's discretisation, perfect start), and
    /// for each case the rules at the verdicts' Re and the maps.
    pub fn plan(&self) -> Plan {
        let infos = self.kernel_infos();
        let mut plan = Plan::default();
        // A point of the speed grid runs on its own (fixed) horizon: it is
        // one scene with the others only when both are speed points.
        let mut seen: BTreeMap<(bool, String), usize> = BTreeMap::new();
        let mut push = |kernel: usize, p: Point, role: Role| {
            let p = Point {
                index: plan.points.len(),
                ..p
            };
            let speed = matches!(role, Role::Speed { .. });
            let key = Key { kernel, role };
            match seen.get(&(speed, p.id())) {
                Some(&i) => plan.keys[i].push(key),
                None => {
                    seen.insert((speed, p.id()), plan.points.len());
                    plan.points.push(p);
                    plan.keys.push(vec![key]);
                    plan.speed.push(speed);
                }
            }
        };
        let (m, e) = (&self.maps, &self.empirical);
        for (k, &info) in infos.iter().enumerate() {
            let name = info.name;
            for (ni, &n) in self.speed.n.iter().enumerate() {
                for (ri, &re) in self.speed.re.iter().enumerate() {
                    for (ci, c) in self.speed.c0.iter().enumerate() {
                        if let Ok(spec) = c.parse::<C0Spec>() {
                            let role = Role::Speed {
                                n: ni,
                                re: ri,
                                c0: ci,
                            };
                            let c0 = PointC0::Spec(spec);
                            push(k, Point::paper(0, name, n, re, self.speed.alpha, c0), role);
                        }
                    }
                }
            }
            for case in self.cases() {
                let Some((disc, on)) = case.disc.of(info) else {
                    continue;
                };
                for seed in self.seeds(case.perturbed) {
                    let at = |re: f64, c0: PointC0| Point {
                        disc,
                        start: self.start(seed),
                        ..Point::paper(0, name, m.n, re, m.alpha, c0)
                    };
                    for (ri, &re) in e.re.iter().enumerate() {
                        for rule in case.disc.rules(info, on) {
                            let spec = PointC0::Spec(scene_spec(info, &rule));
                            let role = Role::Rule {
                                disc: case.disc,
                                seed,
                                re: ri,
                                rule,
                            };
                            push(k, at(re, spec), role);
                        }
                    }
                    for ri in self.map_res(case) {
                        for (ci, &x) in m.c0_over_u.iter().enumerate() {
                            let role = Role::Map {
                                disc: case.disc,
                                seed,
                                re: ri,
                                c0: ci,
                            };
                            push(k, at(m.re[ri], PointC0::OverU(x)), role);
                        }
                    }
                }
            }
        }
        plan
    }

    /// The points of [`ReportConfig::plan`].
    pub fn points(&self) -> Vec<Point> {
        self.plan().points
    }
}

/// A case's discretisation: its place among the config's `[[case]]`s (0:
/// the paper's) and the lattice kind and h/d it names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CaseDiscretisation {
    pub index: usize,
    pub discretisation: Discretisation,
}

impl CaseDiscretisation {
    /// The paper's: the first case, triangular, h = d.
    pub const PAPER: CaseDiscretisation = CaseDiscretisation {
        index: 0,
        discretisation: Discretisation::PAPER,
    };

    /// The kernel's discretisation of this case, as a point takes it and as
    /// generated; `None` when the kernel is not generated at it.
    pub fn of(
        self,
        info: &'static KernelInfo,
    ) -> Option<(Discretisation, &'static DiscretisationInfo)> {
        let want = self.discretisation;
        let on = info.discretisations.iter().find(|d| {
            d.lattice == want.lattice
                && d.h_over_d_exact.parse::<HOverD>().ok() == Some(want.h_over_d)
        })?;
        Some((want, on))
    }

    /// The rules run at the verdicts' Re: every rule, on any
    /// discretisation (`table2`, the paper's printed row, on the paper's
    /// only: [`all_rules_on`]).
    fn rules(self, info: &KernelInfo, on: &DiscretisationInfo) -> Vec<C0Rule> {
        all_rules_on(info, on)
    }
}

/// A case of the report: a discretisation and a start (perfect, or
/// perturbed: the worst over the seeds).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Case {
    pub disc: CaseDiscretisation,
    pub perturbed: bool,
}

impl Case {
    /// The paper's discretisation from the perfect lattice: the report's
    /// first case, and its tables' and Figure 4's.
    pub const PAPER: Case = Case {
        disc: CaseDiscretisation::PAPER,
        perturbed: false,
    };
    /// The paper's discretisation, perturbed: the first screen's second.
    pub const PAPER_PERTURBED: Case = Case {
        disc: CaseDiscretisation::PAPER,
        perturbed: true,
    };

    /// "perfect" or "perturbed".
    pub fn start_name(self) -> &'static str {
        if self.perturbed {
            "perturbed"
        } else {
            "perfect"
        }
    }
}

/// A verdict rule in scene syntax: the default model as `derived`.
fn scene_spec(info: &KernelInfo, rule: &C0Rule) -> C0Spec {
    let rule = match rule {
        C0Rule::Derived(Some(m)) if m == info.c0_default => C0Rule::Derived(None),
        r => r.clone(),
    };
    C0Spec::Rule { factor: 1.0, rule }
}

/// Which part of the report a scene serves, by indices into the config's
/// lists.
#[derive(Debug, Clone, PartialEq)]
pub enum Role {
    /// The speed grid: `speed.n[n]`, `speed.re[re]`, `speed.c0[c0]`.
    Speed { n: usize, re: usize, c0: usize },
    /// A rule at `empirical.re[re]` (N = maps.n, alpha = maps.alpha), its
    /// derived model named (the default one too), on `disc` from start
    /// `seed` (0: the perfect lattice).
    Rule {
        disc: CaseDiscretisation,
        seed: u32,
        re: usize,
        rule: C0Rule,
    },
    /// The stability map: `maps.re[re]`, `maps.c0_over_u[c0]`.
    Map {
        disc: CaseDiscretisation,
        seed: u32,
        re: usize,
        c0: usize,
    },
}

/// A scene's place in the report: the kernel (an index into
/// [`ReportConfig::kernel_infos`]) and its role.
#[derive(Debug, Clone, PartialEq)]
pub struct Key {
    pub kernel: usize,
    pub role: Role,
}

/// The report's scenes and, for each (by its grid index), every place it
/// serves.
#[derive(Debug, Default)]
pub struct Plan {
    pub points: Vec<Point>,
    pub keys: Vec<Vec<Key>>,
    /// Whether each point is the speed grid's (run on its fixed horizon,
    /// [`ReportConfig::base`]).
    pub speed: Vec<bool>,
}

impl Plan {
    /// The rows (in their order) with a key `want` takes.
    pub fn rows<'a>(&self, rows: &'a [Row], want: impl Fn(&Key) -> bool) -> Vec<&'a Row> {
        rows.iter()
            .filter(|r| {
                self.keys
                    .get(r.index)
                    .is_some_and(|ks| ks.iter().any(&want))
            })
            .collect()
    }

    /// Kernel `kernel`'s stability-map rows of case `case` at `maps.re[re]`,
    /// or at every Re, over its seeds: one row per map point, its seeds
    /// pooled (the perfect start's own row), in grid order.
    pub fn map_rows(&self, rows: &[Row], kernel: usize, case: Case, re: Option<usize>) -> Vec<Row> {
        let mut groups: BTreeMap<(usize, usize), Vec<&Row>> = BTreeMap::new();
        for r in rows {
            for key in self.keys.get(r.index).into_iter().flatten() {
                if let Role::Map {
                    disc,
                    seed,
                    re: ri,
                    c0,
                } = key.role
                {
                    let wanted = key.kernel == kernel
                        && disc == case.disc
                        && (seed > 0) == case.perturbed
                        && re.is_none_or(|x| x == ri);
                    if wanted {
                        groups.entry((ri, c0)).or_default().push(r);
                    }
                }
            }
        }
        let mut out: Vec<Row> = groups.into_values().map(|g| pool_rows(&g)).collect();
        out.sort_by_key(|r| r.index);
        out
    }

    /// The row (the seeds pooled) of kernel `kernel`'s rule `rule` at
    /// `empirical.re[re]` in case `case`.
    pub fn rule_row(
        &self,
        rows: &[Row],
        kernel: usize,
        case: Case,
        re: usize,
        rule: &C0Rule,
    ) -> Option<Row> {
        let seeds = self.rows(rows, |k| {
            k.kernel == kernel
                && matches!(&k.role, Role::Rule { disc, seed, re: r, rule: x }
                    if *disc == case.disc && (*seed > 0) == case.perturbed && *r == re && x == rule)
        });
        (!seeds.is_empty()).then(|| pool_rows(&seeds))
    }
}
