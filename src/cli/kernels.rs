//! `shearsph kernels`: every generated kernel x discretisation (lattice
//! kind, h/d) with its support, its compaction eps (t = 0, 0.5 T, true
//! extremes and where, mean) and its c0 coefficients or the stated "no c0"
//! fact, from the generated constants (no rug here).

use std::process::ExitCode;

use anyhow::Result;
use clap::Args;
use serde_json::{json, Value};

use crate::kernel::{C0Model, Derived, DiscretisationInfo, EpsInfo, KernelInfo};
use crate::kernels::KERNELS;

#[derive(Debug, Args)]
pub struct KernelsArgs {
    /// Machine-readable output.
    #[arg(long)]
    pub json: bool,
    /// Also list every c0 model's S, P, Q (the default model is always shown).
    #[arg(long)]
    pub models: bool,
}

fn derived(d: &Derived) -> Value {
    json!({"value": d.value, "exact": d.exact, "is_exact": d.is_exact})
}

fn eps_json(e: &EpsInfo) -> Value {
    json!({
        "t0": derived(&e.t0), "half_period": derived(&e.half_period),
        "max": derived(&e.max), "t_max": derived(&e.t_max),
        "min": derived(&e.min), "t_min": derived(&e.t_min), "mean": derived(&e.mean),
    })
}

fn models_json(models: &[C0Model]) -> serde_json::Map<String, Value> {
    models
        .iter()
        .map(|m| {
            (
                m.name.to_string(),
                json!({"S": m.s.value, "P": m.p.value, "Q": m.q.value,
                       "a": m.a.value, "b": m.b.value, "c": m.c.value,
                       "t": derived(&m.t),
                       "positive_root": has_positive_root(m),
                       "description": m.description}),
            )
        })
        .collect()
}

/// Whether c0 = (U/N^2)(sqrt(P alpha^2 + Q A) - S alpha) is positive for
/// some scene: Q > 0, or S < 0.
fn has_positive_root(m: &C0Model) -> bool {
    m.q.value > 0.0 || m.s.value < 0.0
}

/// One discretisation of a kernel as JSON.
pub fn discretisation_json(d: &DiscretisationInfo) -> Value {
    let no_c0: serde_json::Map<String, Value> = d
        .no_c0
        .iter()
        .map(|m| (m.model.to_string(), Value::from(m.fact)))
        .collect();
    let c = &d.c0_configuration;
    json!({
        "lattice": d.lattice.name(),
        "h_over_d": d.h_over_d,
        "h_over_d_exact": d.h_over_d_exact,
        "label": d.label(),
        "dy": d.dy,
        "eps": eps_json(&d.eps),
        "c0": {
            "configuration": {"t": derived(&c.t), "eps0": derived(&c.eps0),
                              "symmetric": c.symmetric, "label": c.label},
            "models": models_json(d.c0_models),
            "no_c0": no_c0,
        },
    })
}

/// One kernel as JSON: the paper's discretisation's fields at the top, and
/// every discretisation in `discretisations`.
pub fn kernel_json(k: &KernelInfo) -> Value {
    json!({
        "kernel": k.name,
        "title": k.title,
        "reference": k.reference,
        "support": k.support,
        "eps": eps_json(&k.eps),
        "c0": {"default": k.c0_default, "models": models_json(k.c0_models)},
        "printed_c0": k.printed_c0.map(|p| json!({"eps0": p.eps0, "factor": p.factor, "S": p.s, "P": p.p, "Q": p.q})),
        "discretisations": k.discretisations.iter().map(discretisation_json).collect::<Vec<_>>(),
        "flops_per_pair": k.flops_per_pair,
    })
}

pub fn main(args: KernelsArgs) -> Result<ExitCode> {
    if args.json {
        let all: Vec<Value> = KERNELS.iter().map(|k| kernel_json(k)).collect();
        println!("{}", serde_json::to_string_pretty(&all)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "{:<12} {:>5} {:<10} {:>5} {:>12} {:>12} {:>12} {:>8} {:>12} {:>8} {:>12}",
        "kernel",
        "R",
        "lattice",
        "h/d",
        "eps(0)",
        "eps(0.5T)",
        "max eps",
        "t_max/T",
        "min eps",
        "t_min/T",
        "mean eps"
    );
    for k in KERNELS {
        for d in k.discretisations {
            let e = &d.eps;
            println!(
                "{:<12} {:>5} {:<10} {:>5} {:>12.4e} {:>12.4e} {:>12.4e} {:>8.4} {:>12.4e} {:>8.4} {:>12.4e}",
                k.name,
                k.support_exact,
                d.lattice.name(),
                d.h_over_d_exact,
                e.t0.value,
                e.half_period.value,
                e.max.value,
                e.t_max.value,
                e.min.value,
                e.t_min.value,
                e.mean.value
            );
        }
    }
    println!(
        "\nc0 = (U/N^2) (sqrt(P alpha^2 + Q A) - S alpha), A = p d N^4 / U^2, derived at maximum compaction (t_c0/T)"
    );
    println!(
        "{:<12} {:<10} {:>5} {:<10} {:>8} {:>14} {:>14} {:>14}  note",
        "kernel", "lattice", "h/d", "model", "t_c0/T", "S", "P", "Q"
    );
    for k in KERNELS {
        for d in k.discretisations {
            for m in d.c0_models {
                // where this model was derived (an -av model may take the
                // mirror instant T - t of a maximum off the symmetric ones)
                let t_c0 = m.t.value;
                let default = m.name == k.c0_default;
                if !default && !args.models {
                    continue;
                }
                let note = if !has_positive_root(m) {
                    "no positive root (Q <= 0)"
                } else if default {
                    "default"
                } else {
                    ""
                };
                println!(
                    "{:<12} {:<10} {:>5} {:<10} {:>8.4} {:>14.6} {:>14.6} {:>14.6}  {note}",
                    k.name,
                    d.lattice.name(),
                    d.h_over_d_exact,
                    m.name,
                    t_c0,
                    m.s.value,
                    m.p.value,
                    m.q.value
                );
            }
            for m in d.no_c0 {
                if m.model != k.c0_default && !args.models {
                    continue;
                }
                println!(
                    "{:<12} {:<10} {:>5} {:<10} {:>8} {:>14} {:>14} {:>14}  {}",
                    k.name,
                    d.lattice.name(),
                    d.h_over_d_exact,
                    m.model,
                    "-",
                    "-",
                    "-",
                    "-",
                    m.fact
                );
            }
            if let (Some(p), true) = (k.printed_c0, d.is_papers()) {
                println!(
                    "{:<12} {:<10} {:>5} {:<10} {:>8} {:>14.6} {:>14.6} {:>14.6}  the paper's Table 2 (F = {}), for comparison",
                    k.name,
                    d.lattice.name(),
                    d.h_over_d_exact,
                    "printed",
                    "0.5",
                    p.factor * p.s,
                    p.factor * p.factor * p.p,
                    p.factor * p.factor * p.q,
                    p.factor
                );
            }
        }
    }
    if !args.models {
        println!(
            "(--models lists every model; shearsph-codegen show KERNEL gives the exact forms)"
        );
    }
    Ok(ExitCode::SUCCESS)
}
