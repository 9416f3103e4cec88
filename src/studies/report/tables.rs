//! The paper's Tables 1 and 2 beside ours (from the generated
//! `KernelInfo`), and the c0 comparison per kernel: every rule's sound speed
//! at the report's scenes, the time step and cost it implies, and what its
//! run gave.

use std::fmt::Write as _;

use anyhow::Result;
use serde::Serialize;

use super::config::ReportConfig;
use super::plan::{Case, Plan};
use crate::config::C0Rule;
use crate::kernel::{Derived, KernelInfo};
use crate::problem::c0::{all_rules_on, table as c0_table};
use crate::problem::cost::DtLimit;
use crate::sweep::store::csv_field;
use crate::sweep::{Class, Discretisation, Point, PointC0, Row};

/// Decimal places of a printed number (`"0.029873"` has 6).
fn decimals(printed: &str) -> u32 {
    printed.trim().split_once('.').map_or(0, |(_, frac)| {
        frac.chars().take_while(char::is_ascii_digit).count() as u32
    })
}

/// Whether `ours` rounds to the printed value: |ours - printed| at most half
/// a unit of the printed last place, times `scale` (a printed factor).
pub fn agrees_at_printed_precision(ours: f64, printed: &str, scale: f64) -> Option<bool> {
    let p: f64 = printed.trim().parse().ok()?;
    let half_unit = 0.5 * 10f64.powi(-(decimals(printed) as i32)) * scale.abs();
    Some((ours - p * scale).abs() <= half_unit * (1.0 + 1e-9))
}

/// One cell of Table 1: a quantity, ours (value and exact form) and the print.
#[derive(Debug, Clone, Serialize)]
pub struct EpsCompare {
    pub quantity: &'static str,
    pub ours: f64,
    pub exact: &'static str,
    pub is_exact: bool,
    pub printed: Option<String>,
    /// Ours rounded to the printed places equals the print.
    pub agrees: Option<bool>,
}

pub fn table1(info: &KernelInfo) -> Vec<EpsCompare> {
    let p = info.printed_eps;
    let cell = |quantity: &'static str, d: &Derived, printed: Option<&'static str>| EpsCompare {
        quantity,
        ours: d.value,
        exact: d.exact,
        is_exact: d.is_exact,
        printed: printed.map(str::to_string),
        agrees: printed.and_then(|s| agrees_at_printed_precision(d.value, s, 1.0)),
    };
    vec![
        cell("eps(0T)", &info.eps.t0, p.map(|p| p.t0)),
        cell("eps(0.5T)", &info.eps.half_period, p.map(|p| p.half_period)),
        cell("mean eps", &info.eps.mean, p.map(|p| p.mean)),
    ]
}

pub fn table1_csv(t: &[(String, Vec<EpsCompare>)]) -> String {
    let mut out = String::from(
        "kernel,quantity,ours,exact_form,ours_is_exact,printed,agrees_at_printed_precision\n",
    );
    for (k, cells) in t {
        for c in cells {
            let _ = writeln!(
                out,
                "{},{},{},{},{},{},{}",
                csv_field(k),
                c.quantity,
                c.ours,
                csv_field(c.exact),
                c.is_exact,
                c.printed.clone().unwrap_or_default(),
                c.agrees.map_or(String::new(), |a| a.to_string())
            );
        }
    }
    out
}

/// One derived model's coefficients, as c0 = (U/N^2)(sqrt(P a^2 + Q A) - S a).
#[derive(Debug, Clone, Serialize)]
pub struct ModelCoefs {
    pub model: String,
    pub default: bool,
    pub s: f64,
    pub p: f64,
    pub q: f64,
    /// P - S^2: zero for the root of one quadratic.
    pub p_minus_s2: f64,
    /// Q <= 0 with S >= 0: no positive c0 at any alpha.
    pub no_positive_root: bool,
    /// Each coefficient against the print (scaled by the printed F), at the
    /// printed precision.
    pub s_agrees: Option<bool>,
    pub p_agrees: Option<bool>,
    pub q_agrees: Option<bool>,
}

/// The printed row, in the same form (F folded in: S = F S', P = F^2 P',
/// Q = F^2 Q').
#[derive(Debug, Clone, Serialize)]
pub struct PrintedRow {
    pub eps0: f64,
    pub factor: f64,
    pub s: f64,
    pub p: f64,
    pub q: f64,
    pub p_minus_s2: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct Table2Row {
    pub kernel: String,
    pub eps0_ours: f64,
    pub eps0_exact: &'static str,
    pub eps0_agrees: Option<bool>,
    pub printed: Option<PrintedRow>,
    pub models: Vec<ModelCoefs>,
}

pub fn table2(info: &KernelInfo) -> Table2Row {
    let pr = info.printed_c0;
    // The printed f64 keeps the printed digits in its shortest form.
    let agree = |ours: f64, printed: f64, scale: f64| {
        agrees_at_printed_precision(ours, &printed.to_string(), scale)
    };
    let models = info
        .c0_models
        .iter()
        .map(|m| ModelCoefs {
            model: m.name.to_string(),
            default: m.name == info.c0_default,
            s: m.s.value,
            p: m.p.value,
            q: m.q.value,
            p_minus_s2: m.p.value - m.s.value * m.s.value,
            no_positive_root: m.q.value <= 0.0 && m.s.value >= 0.0,
            s_agrees: pr.and_then(|r| agree(m.s.value, r.s, r.factor)),
            p_agrees: pr.and_then(|r| agree(m.p.value, r.p, r.factor * r.factor)),
            q_agrees: pr.and_then(|r| agree(m.q.value, r.q, r.factor * r.factor)),
        })
        .collect();
    Table2Row {
        kernel: info.name.to_string(),
        eps0_ours: info.eps.half_period.value,
        eps0_exact: info.eps.half_period.exact,
        eps0_agrees: pr.and_then(|r| agree(info.eps.half_period.value, r.eps0, 1.0)),
        printed: pr.map(|r| PrintedRow {
            eps0: r.eps0,
            factor: r.factor,
            s: r.factor * r.s,
            p: r.factor * r.factor * r.p,
            q: r.factor * r.factor * r.q,
            p_minus_s2: r.factor * r.factor * (r.p - r.s * r.s),
        }),
        models,
    }
}

pub fn table2_csv(t: &[Table2Row]) -> String {
    let mut out = String::from(
        "kernel,source,model,eps0,S,P,Q,P_minus_S2,no_positive_root,eps0_agrees,S_agrees,P_agrees,Q_agrees\n",
    );
    let b = |v: Option<bool>| v.map_or(String::new(), |a| a.to_string());
    for r in t {
        if let Some(p) = &r.printed {
            let _ = writeln!(
                out,
                "{},printed,,{},{},{},{},{},{},,,,",
                csv_field(&r.kernel),
                p.eps0,
                p.s,
                p.p,
                p.q,
                p.p_minus_s2,
                p.q <= 0.0
            );
        }
        for m in &r.models {
            let _ = writeln!(
                out,
                "{},ours,{}{},{},{},{},{},{},{},{},{},{},{}",
                csv_field(&r.kernel),
                m.model,
                if m.default { " (default)" } else { "" },
                r.eps0_ours,
                m.s,
                m.p,
                m.q,
                m.p_minus_s2,
                m.no_positive_root,
                b(r.eps0_agrees),
                b(m.s_agrees),
                b(m.p_agrees),
                b(m.q_agrees)
            );
        }
    }
    out
}

/// One rule for one kernel at one scene: c0, the time step it implies, the
/// cost estimate, and the measured run.
#[derive(Debug, Clone)]
pub struct C0Compare {
    pub kernel: String,
    /// The keys: the kernel's index in [`ReportConfig::kernel_infos`], the Re's in
    /// `empirical.re`, and the rule (a derived one with its model named).
    pub kernel_index: usize,
    pub re_index: usize,
    pub rule: C0Rule,
    /// The discretisation and start of the run; perturbed: the worst of
    /// its seeds' runs.
    pub case: Case,
    pub disc: Discretisation,
    pub discretisation: String,
    pub n: u32,
    pub re: f64,
    pub alpha: f64,
    pub default_model: bool,
    pub c0_over_u: f64,
    pub dt: f64,
    pub dt_limit: Option<DtLimit>,
    /// Steps to t_end at that dt, and particles x steps.
    pub steps_est: f64,
    pub particle_steps_est: f64,
    /// The run (None when the rule gives no positive c0).
    pub class: Option<Class>,
    pub reason: Option<String>,
    /// The run's judged statistics (the seeds pooled when perturbed).
    pub linf_stat: f64,
    pub eps_stat: f64,
    pub wall_s: f64,
    pub steps: u64,
    /// The limit that bound most of the run's steps.
    pub run_dt_limit_dominant: Option<DtLimit>,
}

/// Every rule at every verdict Re for every kernel, in each case.
pub fn c0_compare(
    config: &ReportConfig,
    plan: &Plan,
    infos: &[&'static KernelInfo],
    rows: &[Row],
) -> Result<Vec<C0Compare>> {
    let mut out = Vec::new();
    for case in config.cases() {
        for (ki, &info) in infos.iter().enumerate() {
            for ri in 0..config.empirical.re.len() {
                out.extend(compare_at(config, plan, rows, (ki, info), case, ri)?);
            }
        }
    }
    Ok(out)
}

/// Every rule of kernel `ki` at `empirical.re[ri]` in case `case` (none
/// when the kernel has no discretisation for it).
fn compare_at(
    config: &ReportConfig,
    plan: &Plan,
    rows: &[Row],
    (ki, info): (usize, &'static KernelInfo),
    case: Case,
    ri: usize,
) -> Result<Vec<C0Compare>> {
    let Some((disc, on)) = case.disc.of(info) else {
        return Ok(Vec::new());
    };
    let (m, re) = (&config.maps, config.empirical.re[ri]);
    let c0 = PointC0::Spec("rule10".parse().expect("a rule"));
    let point = Point {
        disc,
        ..Point::paper(0, info.name, m.n, re, m.alpha, c0)
    };
    let scene = point.scene(&config.scene)?;
    let table = c0_table(&scene)?;
    let particles = crate::problem::lattice::LatticeGeometry::new(
        scene.lattice,
        scene.n_layers,
        scene.d,
        scene.h_over_d * scene.d,
        info.support,
    )
    .n_particles() as f64;
    // The table's rows are its discretisation's rules, in order.
    let mut out = Vec::new();
    for (rule, t) in all_rules_on(info, on).into_iter().zip(&table.rows) {
        let run = plan.rule_row(rows, ki, case, ri, &rule);
        let ran = run.as_ref().filter(|r| r.steps > 0);
        let cost = t.cost.as_ref();
        out.push(C0Compare {
            kernel: info.name.to_string(),
            kernel_index: ki,
            re_index: ri,
            case,
            disc,
            discretisation: on.label(),
            n: m.n,
            re,
            alpha: m.alpha,
            default_model: rule == C0Rule::Derived(Some(info.c0_default.to_string())),
            rule,
            c0_over_u: t.c0_over_u,
            dt: cost.map_or(f64::NAN, |c| c.dt),
            dt_limit: cost.map(|c| c.dt_limit),
            steps_est: cost.map_or(f64::NAN, |c| c.steps),
            particle_steps_est: cost.map_or(f64::NAN, |c| c.steps * particles),
            class: run.as_ref().map(|r| r.class),
            reason: run.as_ref().map(super::empirical::row_reason),
            linf_stat: ran.map_or(f64::NAN, |r| r.linf_stat),
            eps_stat: ran.map_or(f64::NAN, |r| r.eps_stat),
            wall_s: ran.map_or(f64::NAN, |r| r.wall_s),
            steps: ran.map_or(0, |r| r.steps),
            run_dt_limit_dominant: ran.and_then(|r| r.dt_limit_dominant),
        });
    }
    Ok(out)
}

pub fn c0_compare_csv(list: &[C0Compare]) -> String {
    let mut out = String::from(
        "kernel,n,re,alpha,rule,default_model,c0_over_u,dt,dt_limit,steps_est,particle_steps_est,class,reason,linf_stat,eps_stat,wall_s,steps,run_dt_limit_dominant,lattice,h_over_d,start\n",
    );
    for c in list {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            csv_field(&c.kernel),
            c.n,
            c.re,
            c.alpha,
            csv_field(&c.rule.to_string()),
            c.default_model,
            c.c0_over_u,
            c.dt,
            c.dt_limit.map_or("", DtLimit::name),
            c.steps_est,
            c.particle_steps_est,
            c.class.map_or(String::new(), |k| k.to_string()),
            csv_field(&c.reason.clone().unwrap_or_default()),
            c.linf_stat,
            c.eps_stat,
            c.wall_s,
            c.steps,
            c.run_dt_limit_dominant.map_or("", DtLimit::name),
            c.disc.lattice.name(),
            c.disc.h_over_d,
            c.case.start_name()
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn printed_precision() {
        assert_eq!(decimals("0.029873"), 6);
        assert_eq!(decimals("12"), 0);
        assert_eq!(
            agrees_at_printed_precision(0.0297834, "0.029873", 1.0),
            Some(false)
        );
        assert_eq!(
            agrees_at_printed_precision(-0.00073992, "-0.000740", 1.0),
            Some(true)
        );
        // 10 x 2.15 printed: 21.5 +- 0.05
        assert_eq!(agrees_at_printed_precision(21.54, "2.15", 10.0), Some(true));
        assert_eq!(
            agrees_at_printed_precision(21.56, "2.15", 10.0),
            Some(false)
        );
    }
}
