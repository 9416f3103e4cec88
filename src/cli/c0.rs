//! `shearsph c0`: the sound speed for a kernel and a scene by every rule side
//! by side (each derived model, 10 U, the paper's printed Table 2 row), with
//! the time step each implies and the limit that binds it.

use std::process::ExitCode;

use anyhow::Result;
use clap::Args;

use super::SceneArgs;
use crate::problem::c0::table;

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

pub fn main(args: C0Args) -> Result<ExitCode> {
    let t = table(&args.scene.load()?)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&t)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "kernel {} on the {} lattice, h = {} d (the derived rules are this discretisation's)",
        t.kernel,
        t.lattice.name(),
        t.h_over_d
    );
    println!(
        "N = {}, Re = {:.6}, U = {}, p = {:.6e}, nu = {:.6e}, alpha = {}, A = p d N^4 / U^2 = {:.6}",
        t.n_layers, t.re, t.u, t.p, t.nu, t.alpha, t.a
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
            None => match r.no_c0 {
                Some(fact) => println!("{:<24} {:>12}   {fact}", r.rule, "none"),
                None => println!(
                    "{:<24} {:>12.6}   no positive sound speed for this scene",
                    r.rule, r.c0
                ),
            },
        }
    }
    if let Some(e) = &t.scene_c0_error {
        println!("the scene's own c0 ({}) does not resolve: {e}", t.scene_c0);
    }
    Ok(ExitCode::SUCCESS)
}
