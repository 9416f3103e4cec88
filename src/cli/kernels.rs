//! `shearsph kernels`: every generated kernel with its support, its
//! compaction eps (t = 0, 0.5 T, true extremes and where, mean) and its c0
//! coefficients, from the generated constants (no rug here).

use std::process::ExitCode;

use anyhow::Result;
use clap::Args;
use serde_json::{json, Value};

use crate::kernel::{Derived, KernelInfo};
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

/// One kernel as JSON.
pub fn kernel_json(k: &KernelInfo) -> Value {
    let e = &k.eps;
    let models: serde_json::Map<String, Value> = k
        .c0_models
        .iter()
        .map(|m| {
            (
                m.name.to_string(),
                json!({"S": m.s.value, "P": m.p.value, "Q": m.q.value,
                       "a": m.a.value, "b": m.b.value, "c": m.c.value,
                       "positive_root": m.q.value > 0.0 || m.s.value < 0.0,
                       "description": m.description}),
            )
        })
        .collect();
    json!({
        "kernel": k.name,
        "title": k.title,
        "reference": k.reference,
        "support": k.support,
        "eps": {
            "t0": derived(&e.t0), "half_period": derived(&e.half_period),
            "max": derived(&e.max), "t_max": derived(&e.t_max),
            "min": derived(&e.min), "t_min": derived(&e.t_min), "mean": derived(&e.mean),
        },
        "c0": {"default": k.c0_default, "models": models},
        "printed_c0": k.printed_c0.map(|p| json!({"eps0": p.eps0, "factor": p.factor, "S": p.s, "P": p.p, "Q": p.q})),
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
        "{:<12} {:>5} {:>12} {:>12} {:>12} {:>8} {:>12} {:>8} {:>12}",
        "kernel",
        "R",
        "eps(0)",
        "eps(0.5T)",
        "max eps",
        "t_max/T",
        "min eps",
        "t_min/T",
        "mean eps"
    );
    for k in KERNELS {
        let e = &k.eps;
        println!(
            "{:<12} {:>5} {:>12.4e} {:>12.4e} {:>12.4e} {:>8.4} {:>12.4e} {:>8.4} {:>12.4e}",
            k.name,
            k.support_exact,
            e.t0.value,
            e.half_period.value,
            e.max.value,
            e.t_max.value,
            e.min.value,
            e.t_min.value,
            e.mean.value
        );
    }
    println!("\nc0 = (U/N^2) (sqrt(P alpha^2 + Q A) - S alpha), A = p d N^4 / U^2");
    println!(
        "{:<12} {:<10} {:>14} {:>14} {:>14}  note",
        "kernel", "model", "S", "P", "Q"
    );
    for k in KERNELS {
        for m in k.c0_models {
            let default = m.name == k.c0_default;
            if !default && !args.models {
                continue;
            }
            let note = if m.q.value <= 0.0 && m.s.value >= 0.0 {
                "no positive root (Q <= 0)"
            } else if default {
                "default"
            } else {
                ""
            };
            println!(
                "{:<12} {:<10} {:>14.6} {:>14.6} {:>14.6}  {note}",
                k.name, m.name, m.s.value, m.p.value, m.q.value
            );
        }
        if let Some(p) = k.printed_c0 {
            println!(
                "{:<12} {:<10} {:>14.6} {:>14.6} {:>14.6}  the paper's Table 2 (F = {}), for comparison",
                k.name,
                "printed",
                p.factor * p.s,
                p.factor * p.factor * p.p,
                p.factor * p.factor * p.q,
                p.factor
            );
        }
    }
    if !args.models {
        println!(
            "(--models lists every model; shearsph-codegen show KERNEL gives the exact forms)"
        );
    }
    Ok(ExitCode::SUCCESS)
}
