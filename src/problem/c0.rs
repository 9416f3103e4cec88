//! The sound speed c0 by any rule, from a channel (no whole problem needed),
//! and the table of every rule with the time step each implies (`shearsph
//! c0`, the report's tables).

use serde::Serialize;

use super::channel::Channel;
use super::cost::{DtLimit, Estimate};
use crate::config::{invalid, positive, C0Rule, C0Spec, Scene, SceneError};
use crate::format::fmt_value;
use crate::kernel::{DiscretisationInfo, KernelInfo};

/// c0 for a base rule (factor 1), with the rule's canonical name. A
/// derived model is the channel's discretisation's (its lattice and h/d):
/// `C0Model::c0` with A = p d N^4 / U^2 and the scale U / N^2 as the
/// generator defines them (codegen/src/c0.rs; the lattice's dy enters
/// through the coefficients, 2 dy^2 / d^2 on V, not through A). A model
/// that has no c0 on this discretisation gives NaN (its fact in
/// [`no_c0_fact`]).
pub fn by_rule(
    rule: &C0Rule,
    info: &KernelInfo,
    channel: &Channel,
    alpha: f64,
) -> Result<(f64, String), SceneError> {
    let u = channel.flow.u;
    let n = f64::from(channel.lattice.n_layers);
    let (p, d) = (channel.flow.p, channel.lattice.d);
    let disc = channel.discretisation;
    match rule {
        C0Rule::Rule10 => Ok((10.0 * u, "rule10".into())),
        C0Rule::Table2 => match &info.printed_c0 {
            Some(row) if disc.is_papers() => Ok((row.c0(u, n, p, d, alpha), "table2".into())),
            Some(_) => Err(invalid(
                "c0",
                format!(
                    "table2: the paper's Table 2 is for its discretisation (triangular, h = d), not {}; \
                     use derived or rule10",
                    disc.label()
                ),
            )),
            None => Err(invalid(
                "c0",
                format!(
                    "table2: kernel {} has no printed row in the paper's Table 2; use derived or rule10",
                    info.name
                ),
            )),
        },
        C0Rule::Derived(name) => {
            let name = name.as_deref().unwrap_or(info.c0_default);
            if let Some(model) = disc.c0_model(name) {
                return Ok((model.c0(u, n, p, d, alpha), format!("derived:{name}")));
            }
            if disc.no_c0_fact(name).is_some() {
                return Ok((f64::NAN, format!("derived:{name}")));
            }
            let known = model_names(disc);
            Err(invalid(
                "c0",
                format!(
                    "kernel {} has no c0 model {name:?}; its models: {}",
                    info.name,
                    known.join(", ")
                ),
            ))
        }
    }
}

/// Every c0 model's name on a discretisation: those with a c0, then those
/// without.
fn model_names(disc: &DiscretisationInfo) -> Vec<&'static str> {
    let with = disc.c0_models.iter().map(|m| m.name);
    with.chain(disc.no_c0.iter().map(|m| m.model)).collect()
}

/// Why a rule gives no c0 on the channel's discretisation, when the
/// generator stated it ("no c0: ...").
pub fn no_c0_fact(rule: &C0Rule, info: &KernelInfo, channel: &Channel) -> Option<&'static str> {
    match rule {
        C0Rule::Derived(name) => channel
            .discretisation
            .no_c0_fact(name.as_deref().unwrap_or(info.c0_default)),
        _ => None,
    }
}

/// All base rules for a kernel on the paper's discretisation: every derived
/// model, 10 U, and Table 2 when the paper prints a row for it.
pub fn all_rules(info: &KernelInfo) -> Vec<C0Rule> {
    all_rules_on(info, &info.discretisations[0])
}

/// All base rules for a kernel on a discretisation: every derived model
/// (with a c0 or not), 10 U, and Table 2 on the paper's discretisation when
/// the paper prints a row for the kernel.
pub fn all_rules_on(info: &KernelInfo, disc: &DiscretisationInfo) -> Vec<C0Rule> {
    let mut rules: Vec<C0Rule> = model_names(disc)
        .into_iter()
        .map(|m| C0Rule::Derived(Some(m.to_string())))
        .collect();
    rules.push(C0Rule::Rule10);
    if info.printed_c0.is_some() && disc.is_papers() {
        rules.push(C0Rule::Table2);
    }
    rules
}

/// c0 by a scene's spec (a number, or a factor times a rule) and the
/// spec's canonical name, whether or not it is a usable sound speed.
pub fn by_spec(
    spec: &C0Spec,
    info: &KernelInfo,
    channel: &Channel,
    alpha: f64,
) -> Result<(f64, String), SceneError> {
    match spec {
        C0Spec::Value(v) => Ok((*v, "value".to_string())),
        C0Spec::Rule { factor, rule } => {
            positive("c0", *factor).map_err(|_| {
                invalid(
                    "c0",
                    format!("factor {} must be positive", fmt_value(*factor)),
                )
            })?;
            let (c0, name) = by_rule(rule, info, channel, alpha)?;
            let name = if *factor == 1.0 {
                name
            } else {
                format!("{}*{name}", fmt_value(*factor))
            };
            Ok((factor * c0, name))
        }
    }
}

/// [`by_spec`], refusing a c0 that is not a positive number.
pub fn resolve(
    spec: &C0Spec,
    info: &KernelInfo,
    channel: &Channel,
    alpha: f64,
) -> Result<(f64, String), SceneError> {
    let (c0, rule) = by_spec(spec, info, channel, alpha)?;
    if c0 > 0.0 && c0.is_finite() {
        Ok((c0, rule))
    } else if let Some(fact) = match spec {
        C0Spec::Rule { rule, .. } => no_c0_fact(rule, info, channel),
        C0Spec::Value(_) => None,
    } {
        Err(invalid(
            "c0",
            format!(
                "{spec} has no c0 for kernel {} on {}: {fact}; give a number or another rule \
                 (`shearsph c0` lists them)",
                info.name,
                channel.discretisation.label()
            ),
        ))
    } else {
        Err(invalid(
            "c0",
            format!(
                "{spec} gives c0 = {} for this scene, which is not a positive sound speed (a derived \
                 model without a positive root, or a non-positive number); give a positive number or \
                 another rule (`shearsph c0` lists them)",
                fmt_value(c0)
            ),
        ))
    }
}

/// One rule's sound speed and what it costs.
#[derive(Debug, Clone, Serialize)]
pub struct C0Row {
    /// Rule in scene syntax (`derived:MODEL`, `rule10`, `table2`), or the
    /// scene's own c0 when it is not one of those.
    pub rule: String,
    /// NaN (null in JSON) or not positive when the rule gives no sound speed
    /// for this scene (a derived model without a positive root).
    pub c0: f64,
    pub c0_over_u: f64,
    /// The time step with |v|max = U and |a|max = p (the body force), the
    /// limit that binds, each limit, and the steps to t_end at that dt; none
    /// when c0 is not a positive number.
    pub cost: Option<Cost>,
    /// The generator's fact when a derived model has no c0 on the scene's
    /// discretisation ("no c0: ...").
    #[serde(skip_serializing_if = "Option::is_none")]
    pub no_c0: Option<&'static str>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Cost {
    pub dt: f64,
    pub dt_limit: DtLimit,
    pub dt_cfl: f64,
    pub dt_viscous: f64,
    pub dt_force: f64,
    pub steps: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct C0Table {
    pub kernel: String,
    /// The discretisation the derived rules are for: its lattice, h/d
    /// (exact, "13/10") and label ("square, h = 13/10 d").
    pub lattice: crate::kernel::Lattice,
    pub h_over_d: String,
    pub discretisation: String,
    pub n_layers: u32,
    pub re: f64,
    pub u: f64,
    pub p: f64,
    pub nu: f64,
    pub d: f64,
    pub h: f64,
    pub alpha: f64,
    /// A = p d N^4 / U^2, the paper's parameter of Table 2.
    pub a: f64,
    pub t_end: f64,
    /// The scene's own c0 spec, and the error it gives if it cannot resolve.
    pub scene_c0: String,
    pub scene_c0_error: Option<String>,
    pub rows: Vec<C0Row>,
}

/// The c0 table for a scene: every base rule, and the scene's own c0 when
/// it is none of them. Everything but c0 must be valid; the scene's own c0
/// is reported beside when it does not resolve.
pub fn table(scene: &Scene) -> Result<C0Table, SceneError> {
    let info = scene.kernel_info()?;
    super::check_fields(scene)?;
    let channel = Channel::resolve(scene, info)?;
    let t_end = channel.t_end(scene)?;
    let row = |rule: String, c0: f64, no_c0: Option<&'static str>| {
        let est = Estimate::new(&channel, c0, t_end);
        let ts = est.time_step;
        C0Row {
            rule,
            c0,
            c0_over_u: c0 / channel.flow.u,
            cost: (c0 > 0.0 && c0.is_finite()).then_some(Cost {
                dt: ts.dt,
                dt_limit: ts.limit,
                dt_cfl: ts.cfl,
                dt_viscous: ts.viscous,
                dt_force: ts.force,
                steps: est.steps,
            }),
            no_c0,
        }
    };
    let mut rows = Vec::new();
    let disc = channel.discretisation;
    for rule in all_rules_on(info, disc) {
        let (c0, name) = by_rule(&rule, info, &channel, scene.alpha)?;
        rows.push(row(name, c0, no_c0_fact(&rule, info, &channel)));
    }
    let mut scene_c0_error = None;
    match super::Problem::resolve(scene, info) {
        Ok(p) if !rows.iter().any(|r| r.rule == p.c0_rule) => {
            rows.push(row(p.c0_rule.clone(), p.c0, None))
        }
        Ok(_) => {}
        Err(e) => scene_c0_error = Some(e.to_string()),
    }
    Ok(C0Table {
        kernel: info.name.to_string(),
        lattice: disc.lattice,
        h_over_d: disc.h_over_d_exact.to_string(),
        discretisation: disc.label(),
        n_layers: scene.n_layers,
        re: channel.re,
        u: channel.flow.u,
        p: channel.flow.p,
        nu: channel.flow.nu,
        d: channel.lattice.d,
        h: channel.lattice.h,
        alpha: scene.alpha,
        a: channel.a_param(),
        t_end,
        scene_c0: scene.c0.to_string(),
        scene_c0_error,
        rows,
    })
}
