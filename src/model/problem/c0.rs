//! The sound speed c0 by any rule, from a channel (no whole problem needed),
//! and the table of every rule with the time step each implies (`shearsph
//! c0`, the report's tables).

use serde::Serialize;

use super::channel::Channel;
use super::cost::{DtLimit, Estimate};
use crate::config::{
    entry_of, invalid, positive, C0Rule, C0Spec, RuleFlow, RuleKind, Scene, SceneError,
    DEFAULT_TECHNICAL_EPS0, RULES,
};
use crate::format::fmt_value;
use crate::kernel::{DiscretisationInfo, KernelInfo};

pub use crate::config::MORRIS_DELTA;

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
    let name = rule.to_string();
    // A code's rule: its registry entry's formula of the flow.
    if let RuleKind::Code { c0, .. } = entry_of(rule).kind {
        let flow = RuleFlow {
            u,
            p,
            nu: channel.flow.nu,
            b: channel.flow.b,
        };
        return Ok((c0(&flow), name));
    }
    match rule {
        C0Rule::Code(e) => Err(invalid(
            "c0",
            format!("rule {} is a code's rule without a formula", e.syntax),
        )),
        // the solver's answer: the layers above resolve it by running the
        // bisection first (`crate::empirical::resolve_empirical`)
        C0Rule::Empirical => Err(invalid(
            "c0",
            "empirical is the solver's answer for the scene: `shearsph run` and `shearsph c0 \
             --empirical` find it by running the bisection first; here give a number or another \
             rule (`shearsph c0` lists them)",
        )),
        C0Rule::DerivedEps(eps) => {
            let eps_t = eps.unwrap_or(DEFAULT_TECHNICAL_EPS0);
            let name = match eps {
                None => "derived-eps".to_string(),
                Some(e) => format!("derived-eps:{e}"),
            };
            // the default model on the scene's discretisation; none there
            // (the generator's "no c0" fact), or a maximum compaction that is
            // not positive, gives no c0
            let eps0 = disc.eps.max.value;
            let Some(model) = disc.c0_model(info.c0_default).filter(|_| eps0 > 0.0) else {
                return Ok((f64::NAN, name));
            };
            // a = eps0 K: the kinematic eps0 (the true maximum of the
            // lattice's compaction) replaced by eps_t scales a by k; b and
            // c are kept (they carry eps0 only as 1 + eps0, a change of a
            // few per cent at most). S = b/(2a), P = S^2 (or its own value),
            // Q = -c/a then scale as 1/k, 1/k^2, 1/k.
            let k = eps_t / eps0;
            let root = crate::kernel::c0_root(
                model.p.value / (k * k),
                model.q.value / k,
                model.s.value / k,
                u,
                n,
                p,
                d,
                alpha,
            );
            Ok((u / (n * n) * root, name))
        }
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
        C0Rule::DerivedEps(_) => channel.discretisation.no_c0_fact(info.c0_default),
        _ => None,
    }
}

/// All base rules for a kernel on the scene's discretisation: every derived model, the derivation with the
/// technical eps0, the codes' rules (10 U, Morris 1997, GPUSPH,
/// DualSPHysics, TrixiParticles.jl), and Table 2 when the paper prints a row
/// for it.
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
    rules.push(C0Rule::DerivedEps(None));
    rules.extend(
        RULES
            .iter()
            .filter(|e| matches!(e.kind, RuleKind::Code { .. }))
            .map(|e| C0Rule::Code(e)),
    );
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
    } else if c0.is_nan() {
        Err(invalid(
            "c0",
            format!(
                "{spec} has no positive root for this scene (P alpha^2 + Q A < 0 in the derived \
                 c0 = (U/N^2)(sqrt(P alpha^2 + Q A) - S alpha), or for derived-eps a maximum \
                 compaction that is not positive), so it is not a positive sound speed; give a positive number or another rule (`shearsph c0` lists them)"
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
    /// The time step's factors in use (the scene's `cfl` and
    /// `viscous_dt`), and the largest at which the kernel's pressure and
    /// viscous terms are stable on the perfect lattice
    /// ([`super::acoustic_stable_factor`], [`super::viscous_stable_factor`],
    /// docs/timestep.md).
    pub cfl: f64,
    pub cfl_stable: f64,
    pub viscous_dt: f64,
    pub viscous_dt_stable: f64,
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
        cfl: channel.dt_factors.cfl,
        cfl_stable: super::acoustic_stable_factor(
            info,
            &channel.lattice,
            super::Eos::of_scene(scene),
        ),
        viscous_dt: channel.dt_factors.viscous,
        viscous_dt_stable: super::viscous_stable_factor(
            info,
            &channel.lattice,
            scene.viscous_normalisation,
        ),
        rows,
    })
}

#[cfg(test)]
mod tests {
    //! Each rule against a hand calculation from its source, for the
    //! built-in scene (Monaghan's kernel, N = 10, U = 1, d = 1, h = d) at
    //! Re = 1, where every branch of the max()s is not the trivial one.
    use super::*;

    /// The scene's numbers by hand: the triangular lattice's layer spacing
    /// dy = (sqrt 3 / 2) d, B = N dy, p = 2 U^2 / (Re B), nu = U B / Re.
    const N: f64 = 10.0;
    const U: f64 = 1.0;
    const RE: f64 = 1.0;
    fn b() -> f64 {
        N * (3f64.sqrt() / 2.0) * 1.0
    }
    fn p() -> f64 {
        2.0 * U * U / (RE * b())
    }
    fn nu() -> f64 {
        U * b() / RE
    }

    fn c0_of(rule: &str) -> f64 {
        let mut scene = Scene::builtin();
        scene.n_layers = 10;
        scene.re = Some(RE);
        scene.p = None;
        let info = scene.kernel_info().unwrap();
        let channel = Channel::resolve(&scene, info).unwrap();
        assert!((channel.flow.b - b()).abs() < 1e-12, "B = N dy");
        let spec: C0Spec = rule.parse().unwrap();
        by_spec(&spec, info, &channel, scene.alpha).unwrap().0
    }

    fn close(a: f64, b: f64) {
        assert!((a - b).abs() <= 1e-12 * b.abs(), "{a} != {b}");
    }

    #[test]
    fn empirical_is_refused_here_with_where_it_is_found() {
        let mut scene = Scene::builtin();
        scene.c0 = "empirical".parse().unwrap();
        let info = scene.kernel_info().unwrap();
        let channel = Channel::resolve(&scene, info).unwrap();
        let err = by_spec(&scene.c0, info, &channel, scene.alpha)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("`c0`") && err.contains("c0 --empirical"),
            "{err}"
        );
    }

    #[test]
    fn rule10_is_ten_u() {
        // Monaghan (1994): c0 = 10 U_max.
        close(c0_of("rule10"), 10.0 * U);
    }

    #[test]
    fn trixi_is_a_hundred_u() {
        // TrixiParticles.jl poiseuille_flow_2d.jl: sound_speed = 100 U_max.
        close(c0_of("trixi"), 100.0 * U);
    }

    #[test]
    fn morris1997_takes_the_largest_of_three_terms() {
        // Morris, Fox and Zhu (1997) 2.2: c^2 = max(U^2/delta,
        // nu U/(L delta), F L/delta), delta = 0.01, L = 2 B.
        // Here: 100, 8.66/0.1732 = 50, 0.2309 x 17.32 / 0.01 = 400.
        let (delta, l) = (0.01, 2.0 * b());
        let terms = [U * U / delta, nu() * U / (l * delta), p() * l / delta];
        close(terms[2], 400.0);
        close(c0_of("morris1997"), 400f64.sqrt());
    }

    #[test]
    fn gpusph_is_twenty_times_the_hydrostatic_speed() {
        // GPUSPH Poiseuille.cu: hydrostatic_vel = sqrt(2 driving_force lz),
        // c0 = 20 fmax(hydrostatic_vel, max_vel); lz = 2 B.
        // sqrt(2 x 0.2309 x 17.32) = sqrt(8) > U.
        let hydrostatic = (2.0 * p() * 2.0 * b()).sqrt();
        close(hydrostatic, 8f64.sqrt());
        close(c0_of("gpusph"), 20.0 * 8f64.sqrt());
    }

    #[test]
    fn dualsphysics_is_coefsound_times_the_speed_of_the_system() {
        // DualSPHysics: speedsound = coefsound x speedsystem, coefsound = 20,
        // speedsystem = sqrt(|g| hswl), g = p, hswl = 2 B: sqrt(4) = 2.
        close((p() * 2.0 * b()).sqrt(), 2.0);
        close(c0_of("dualsphysics"), 20.0 * 2.0);
    }

    #[test]
    fn derived_eps_is_the_balance_with_the_technical_eps0() {
        // The paper's balance a c0^2 + b alpha (U/N^2) c0 + c p d = 0 with
        // a = eps0 K: eps0 -> eps_t scales a by eps_t/eps0, b and c kept.
        let info = Scene::builtin().kernel_info().unwrap();
        let m = info.default_c0_model();
        let (alpha, d) = (Scene::builtin().alpha, 1.0);
        for (spec, eps_t) in [("derived-eps", 0.01), ("derived-eps:0.03", 0.03)] {
            let a = m.a.value * eps_t / info.eps.max.value;
            let (bb, cc) = (m.b.value * alpha * U / (N * N), m.c.value * p() * d);
            // The positive root of the quadratic (a < 0 < c for this kernel).
            let disc = (bb * bb - 4.0 * a * cc).sqrt();
            let root = ((-bb + disc) / (2.0 * a)).max((-bb - disc) / (2.0 * a));
            let got = c0_of(spec);
            assert!((got - root).abs() <= 1e-9 * root, "{spec}: {got} != {root}");
        }
        // eps_t = eps0 is the derived model itself.
        let same = format!("derived-eps:{}", info.eps.max.value);
        assert!((c0_of(&same) - c0_of("derived")).abs() <= 1e-12 * c0_of("derived"));
    }
}
