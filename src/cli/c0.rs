//! `shearsph c0`: the sound speed for a kernel and a scene by every rule side
//! by side (each derived model, 10 U, the paper's printed Table 2 row), with
//! the time step each implies and the limit that binds it.

use std::process::ExitCode;

use anyhow::Result;
use clap::Args;
use serde::Serialize;

use super::SceneArgs;
use crate::scene::{all_rules, c0_by_rule, C0Spec, Problem, Scene};
use crate::solver::{DtLimit, TimeStep};

/// c0 by every rule for a scene, and the time step each implies.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true, args_override_self = true)]
pub struct C0Args {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Print the table as JSON on stdout.
    #[arg(long)]
    pub json: bool,
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

/// The c0 table for a scene.
pub fn table(scene: &Scene) -> Result<C0Table> {
    let info = scene.kernel_info()?;
    // Everything but c0 must be valid; the scene's own c0 is reported beside.
    let base = Problem::new(
        &Scene {
            c0: "rule10".parse::<C0Spec>().expect("valid rule"),
            ..scene.clone()
        },
        info,
    )?;
    let row = |rule: String, c0: f64| {
        let ts = TimeStep::new(base.lattice.h, c0, base.flow.nu, base.flow.u, base.flow.p);
        C0Row {
            rule,
            c0,
            c0_over_u: c0 / base.flow.u,
            cost: (c0 > 0.0 && c0.is_finite()).then(|| Cost {
                dt: ts.dt,
                dt_limit: ts.limit,
                dt_cfl: ts.cfl,
                dt_viscous: ts.viscous,
                dt_force: ts.force,
                steps: (base.t_end / ts.dt).ceil(),
            }),
        }
    };
    let mut rows = Vec::new();
    for rule in all_rules(info) {
        let (c0, name) = c0_by_rule(&rule, info, scene, &base.flow)?;
        rows.push(row(name, c0));
    }
    let mut scene_c0_error = None;
    match Problem::new(scene, info) {
        Ok(p) if !rows.iter().any(|r| r.rule == p.c0_rule) => {
            rows.push(row(p.c0_rule.clone(), p.c0))
        }
        Ok(_) => {}
        Err(e) => scene_c0_error = Some(e.to_string()),
    }
    let n = f64::from(scene.n_layers);
    Ok(C0Table {
        kernel: info.name.to_string(),
        n_layers: scene.n_layers,
        re: base.re,
        u: base.flow.u,
        p: base.flow.p,
        nu: base.flow.nu,
        d: base.lattice.d,
        h: base.lattice.h,
        alpha: scene.alpha,
        a: base.flow.p * base.lattice.d * n.powi(4) / (base.flow.u * base.flow.u),
        t_end: base.t_end,
        scene_c0: scene.c0.to_string(),
        scene_c0_error,
        rows,
    })
}

pub fn main(args: C0Args) -> Result<ExitCode> {
    let t = table(&args.scene.load()?)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&t)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "kernel {}, N = {}, Re = {:.6}, U = {}, p = {:.6e}, nu = {:.6e}, alpha = {}, A = p d N^4 / U^2 = {:.6}",
        t.kernel, t.n_layers, t.re, t.u, t.p, t.nu, t.alpha, t.a
    );
    println!(
        "time steps with |v|max = U and |a|max = p; steps to t_end = {:.6}",
        t.t_end
    );
    println!(
        "{:<24} {:>12} {:>10} {:>12} {:>8} {:>12} {:>12} {:>10}",
        "rule", "c0", "c0/U", "dt", "limit", "dt_cfl", "dt_viscous", "steps"
    );
    for r in &t.rows {
        match &r.cost {
            Some(c) => println!(
                "{:<24} {:>12.6} {:>10.4} {:>12.4e} {:>8} {:>12.4e} {:>12.4e} {:>10}",
                r.rule,
                r.c0,
                r.c0_over_u,
                c.dt,
                c.dt_limit.name(),
                c.dt_cfl,
                c.dt_viscous,
                c.steps
            ),
            None => println!(
                "{:<24} {:>12.6}   no positive sound speed for this scene",
                r.rule, r.c0
            ),
        }
    }
    if let Some(e) = &t.scene_c0_error {
        println!("the scene's own c0 ({}) does not resolve: {e}", t.scene_c0);
    }
    Ok(ExitCode::SUCCESS)
}
