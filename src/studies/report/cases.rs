//! The report's cases: the `[[case]]`s of its config (each a
//! discretisation, run perfect and perturbed), their checks field by field,
//! and the cases of a config written before they were listed.

use anyhow::{bail, Result};
use serde::{Deserialize, Serialize};

use super::config::ReportConfig;
use super::plan::{Case, CaseDiscretisation};
use crate::kernel::Lattice;
use crate::sweep::{Discretisation, HOverD};

/// A config written before the cases were listed has no `[[case]]`: it
/// gets the paper's case and, unless its `[square]` gives `re = []`, the
/// default report's square one at `[square]`'s Re (`empirical_re` when it
/// has no `[square]`).
pub(super) fn fill_missing_cases(table: &mut toml::Table, empirical_re: toml::Value) {
    if table.contains_key("case") {
        return;
    }
    let square_re = match table.remove("square") {
        Some(toml::Value::Table(mut t)) => t.remove("re").unwrap_or(empirical_re),
        Some(other) => other,
        None => empirical_re,
    };
    let mut cases = vec![CaseConfig::paper()];
    if square_re.as_array().is_none_or(|a| !a.is_empty()) {
        cases.push(CaseConfig::square());
    }
    let mut cases: Vec<toml::Value> = cases
        .iter()
        .map(|c| toml::Value::try_from(c).expect("a case serialises"))
        .collect();
    if let Some(toml::Value::Table(t)) = cases.get_mut(1) {
        t.insert("re".into(), square_re);
    }
    table.insert("case".into(), toml::Value::Array(cases));
}

/// A case of the report (`[[case]]`): a discretisation, run perfect and
/// perturbed: every rule at the verdicts' Re, the stability map at `re`
/// and the empirical c0. The first is the paper's (triangular, h = d).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseConfig {
    /// Names its files (`stability_KERNEL_ID.svg`; none for the first) and
    /// its part of the page.
    pub id: String,
    pub lattice: Lattice,
    pub h_over_d: HOverD,
    /// The maps' Re its map runs at (each one of maps.re, every
    /// empirical.re among them); every maps.re when not given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub re: Option<Vec<f64>>,
    /// Its name on the page ("square lattice"); every case but the first.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
    /// Which discretisation it is, for a reader: the end of "The analysis
    /// of Tables 1 and 2 for ..."; every case but the first.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub about: Option<String>,
}

impl CaseConfig {
    /// The paper's case: triangular, h = d.
    fn paper() -> CaseConfig {
        CaseConfig {
            id: "paper".into(),
            lattice: Discretisation::PAPER.lattice,
            h_over_d: Discretisation::PAPER.h_over_d,
            re: None,
            label: None,
            about: None,
        }
    }

    /// The default report's square case, for configs from before the cases
    /// were listed.
    fn square() -> CaseConfig {
        CaseConfig {
            id: "square".into(),
            lattice: Lattice::Square,
            h_over_d: HOverD::new(13, 10).expect("13/10"),
            re: None,
            label: Some("square lattice".into()),
            about: Some(SQUARE_ABOUT.into()),
        }
    }

    pub fn discretisation(&self) -> Discretisation {
        Discretisation {
            lattice: self.lattice,
            h_over_d: self.h_over_d,
        }
    }
}

/// The default report's words for its square case.
const SQUARE_ABOUT: &str = "the discretisation the peers run: the square lattice with h = 13/10 d (SPHinXsys); a kernel not generated there has no row in this case";

impl ReportConfig {
    /// The cases, field by field: the paper's first, each id a distinct
    /// name for files and the page, each discretisation distinct and
    /// generated for some kernel, each `re` list the maps', a label and an
    /// about for every case but the first.
    pub(super) fn check_cases(&self) -> Result<()> {
        let Some(first) = self.case.first() else {
            bail!("no [[case]]: give the paper's first ([[case]] id = \"paper\", lattice = \"triangular\", h_over_d = 1)");
        };
        if first.discretisation() != Discretisation::PAPER {
            bail!(
                "case[0] (id = {:?}) is lattice = {:?}, h_over_d = {:?}: the first case is the paper's discretisation (lattice = \"triangular\", h_over_d = 1), whose tables, Figure 4 and first screen the report gives; put it first",
                first.id,
                first.lattice.name(),
                first.h_over_d.to_string()
            );
        }
        for (i, c) in self.case.iter().enumerate() {
            let ok = |ch: char| ch.is_ascii_lowercase() || ch.is_ascii_digit() || ch == '_';
            if c.id.is_empty() || !c.id.chars().all(ok) {
                bail!("case[{i}].id = {:?}: give a name of a-z, 0-9 and _ (it names the case's files and its part of the page)", c.id);
            }
            if let Some(j) = self.case[..i].iter().position(|o| o.id == c.id) {
                bail!(
                    "case[{i}].id = {:?} is case[{j}]'s too: give each case its own id",
                    c.id
                );
            }
            if let Some(j) = self.case[..i]
                .iter()
                .position(|o| o.discretisation() == c.discretisation())
            {
                bail!(
                    "case[{i}] (id = {:?}) is case[{j}]'s discretisation (lattice = {:?}, h_over_d = {:?}): give each case its own",
                    c.id,
                    c.lattice.name(),
                    c.h_over_d.to_string()
                );
            }
            let disc = CaseDiscretisation {
                index: i,
                discretisation: c.discretisation(),
            };
            if self
                .kernel_infos()
                .iter()
                .all(|info| disc.of(info).is_none())
            {
                bail!(
                    "case[{i}] (id = {:?}): no kernel reported is generated at lattice = {:?}, h_over_d = {:?}: add it to kernels/discretisations.toml and run `cargo run -p shearsph-codegen -- generate`",
                    c.id,
                    c.lattice.name(),
                    c.h_over_d.to_string()
                );
            }
            if let Some(re) = &c.re {
                if re.is_empty() {
                    bail!("case[{i}].re = [] runs no map: leave re out (every maps.re) or remove the case");
                }
                self.check_re_list(&format!("case[{i}].re"), re)?;
            }
            if i > 0 {
                for (field, v) in [("label", &c.label), ("about", &c.about)] {
                    if v.as_deref().is_none_or(str::is_empty) {
                        bail!("case[{i}].{field} is missing: every case but the first needs a label (its name on the page, \"square lattice\") and an about (which discretisation it is, for a reader)");
                    }
                }
            }
        }
        Ok(())
    }

    /// The cases the report runs: each `[[case]]`'s discretisation
    /// perfect and perturbed, the paper's first.
    pub fn cases(&self) -> Vec<Case> {
        (0..self.case.len())
            .flat_map(|index| {
                let disc = CaseDiscretisation {
                    index,
                    discretisation: self.case[index].discretisation(),
                };
                [false, true].map(|perturbed| Case { disc, perturbed })
            })
            .collect()
    }

    /// Whether case `disc`'s map runs at `re`.
    pub fn case_runs_at(&self, disc: CaseDiscretisation, re: f64) -> bool {
        self.case[disc.index]
            .re
            .as_ref()
            .is_none_or(|list| list.contains(&re))
    }

    /// The suffix of a case's files, from its parts: none for the paper's
    /// perfect case, `_perturbed`, `_ID` for another case, `_ID_perturbed`.
    pub fn file_suffix(&self, case: Case) -> String {
        let id = match case.disc.index {
            0 => String::new(),
            i => format!("_{}", self.case[i].id),
        };
        let start = if case.perturbed { "_perturbed" } else { "" };
        format!("{id}{start}")
    }

    /// The page's figure id of a case's stability maps (`stability` and
    /// the file suffix).
    pub fn figure_id(&self, case: Case) -> String {
        format!("stability{}", self.file_suffix(case))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::plan::Role;
    use crate::report::QUICK_CONFIG;

    /// The quick config with its `[[case]]`s cut out.
    fn without_cases(text: &str) -> String {
        let start = text.find("[[case]]").expect("cases");
        let end = start + text[start..].find("[figure4]").expect("figure4");
        format!("{}{}", &text[..start], &text[end..])
    }

    /// A config from before `[perturbed]` and the cases parses, with the
    /// default report's choices; one with the old `[square]` gets its Re.
    #[test]
    fn a_config_without_the_lattice_sections_gets_the_defaults() {
        let start = QUICK_CONFIG.find("[perturbed]").expect("perturbed");
        let end = start + QUICK_CONFIG[start..].find("\n[").expect("next");
        let old = without_cases(&format!(
            "{}{}",
            &QUICK_CONFIG[..start],
            &QUICK_CONFIG[end..]
        ));
        assert!(!old.contains("[perturbed]") && !old.contains("[[case]]"));
        let c = ReportConfig::parse(&old, "old.toml").expect("an old config parses");
        let q = ReportConfig::quick();
        assert_eq!((c.perturbed.jitter, c.perturbed.seeds), (0.05, 3));
        assert_eq!(c.perturbed.re, q.maps.re);
        assert_eq!(c.case.len(), 2);
        assert_eq!(c.case[1].re.as_ref(), Some(&q.empirical.re));
        assert_eq!(c.cases(), q.cases());
        assert_eq!(
            (c.case[1].label.as_deref(), c.case[1].about.as_deref()),
            (q.case[1].label.as_deref(), q.case[1].about.as_deref())
        );
        // The old `[square]` is kept: `re = []` runs no square case.
        let none = format!("{old}\n[square]\nre = []\n");
        let c = ReportConfig::parse(&none, "mine.toml").unwrap();
        assert_eq!(c.case.len(), 1);
        let mine = format!("{old}\n[square]\nre = [1.0, 10.0]\n");
        let c = ReportConfig::parse(&mine, "mine.toml").unwrap();
        assert_eq!(c.case[1].re, Some(vec![1.0, 10.0]));
    }

    /// The paper's case alone runs no other lattice; a case's `re` must be
    /// the maps' and cover empirical.re, as perturbed.re must.
    #[test]
    fn the_paper_case_alone_runs_no_other_lattice() {
        let mut c = ReportConfig::quick();
        c.case.truncate(1);
        c.check().expect("the paper's case alone is valid");
        let plan = c.plan();
        assert!(plan.keys.iter().flatten().all(|k| match k.role {
            Role::Rule { disc, .. } | Role::Map { disc, .. } => disc == CaseDiscretisation::PAPER,
            Role::Speed { .. } => true,
        }));
        let only = |re: f64| vec![re];
        let missing = *c.empirical.re.last().expect("the quick config has one");
        let other = *c.maps.re.iter().find(|&&r| r != missing).expect("two Re");
        for field in ["case[1].re", "perturbed.re"] {
            let mut bad = ReportConfig::quick();
            if field == "case[1].re" {
                bad.case[1].re = Some(only(other));
            } else {
                bad.perturbed.re = only(other);
            }
            let err = bad.check().expect_err(field).to_string();
            assert!(err.contains(field) && err.contains("lacks"), "{err}");
        }
    }

    /// Every field of a case is checked, the error naming it and the fix.
    #[test]
    fn the_cases_are_checked_field_by_field() {
        let bad = |edit: &dyn Fn(&mut Vec<CaseConfig>), field: &str, fix: &str| {
            let mut c = ReportConfig::quick();
            edit(&mut c.case);
            let err = c.check().expect_err(field).to_string();
            assert!(err.contains(field) && err.contains(fix), "{field}: {err}");
        };
        bad(&|c| c.clear(), "[[case]]", "paper");
        bad(&|c| c.swap(0, 1), "case[0]", "put it first");
        bad(&|c| c[1].id = "Sq uare".into(), "case[1].id", "a-z");
        bad(&|c| c[1].id = "paper".into(), "case[1].id", "its own id");
        bad(
            &|c| (c[1].lattice, c[1].h_over_d) = (Lattice::Triangular, HOverD::ONE),
            "case[1]",
            "give each case its own",
        );
        bad(
            &|c| c[1].h_over_d = HOverD::new(3, 2).unwrap(),
            "case[1]",
            "kernels/discretisations.toml",
        );
        bad(&|c| c[1].re = Some(vec![]), "case[1].re", "remove the case");
        bad(&|c| c[1].re = Some(vec![7.0]), "case[1].re", "maps.re");
        bad(
            &|c| c[1].label = None,
            "case[1].label",
            "its name on the page",
        );
        bad(
            &|c| c[1].about = None,
            "case[1].about",
            "which discretisation",
        );
        // A case is a config edit: a third one runs on its discretisation.
        let mut c = ReportConfig::quick();
        c.case.push(CaseConfig {
            id: "square_h1".into(),
            h_over_d: HOverD::ONE,
            ..c.case[1].clone()
        });
        c.check().expect("a third case");
        let third = c.cases()[4];
        assert_eq!(c.file_suffix(third), "_square_h1");
        let on = |info| third.disc.of(info).map(|(_, on)| on.label());
        assert_eq!(on(c.kernel_infos()[0]).as_deref(), Some("square, h = 1 d"));
        assert!(c.plan().keys.iter().flatten().any(|k| matches!(
            k.role,
            Role::Map { disc, .. } if disc == third.disc
        )));
    }
}
