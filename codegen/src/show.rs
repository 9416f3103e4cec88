//! `shearsph-codegen show KERNEL`: the derivation for a person, or as JSON.

use crate::analysis::{Analysis, Compared, DiscAnalysis, Fact};
use crate::c0::{ModelC0, Term};
use crate::compaction::Known;
use crate::exact::{decimal, Exact, Ratio};
use crate::lattice::Config;
use serde_json::{json, Map, Value};
use std::fmt::Write;

fn dec(a: &Analysis, e: &Exact) -> String {
    decimal(&e.to_float(a.prec), a.digits)
}

fn dec_ratio(a: &Analysis, r: &Ratio) -> String {
    decimal(&r.to_float(a.prec), a.digits)
}

fn dec_float(a: &Analysis, x: &rug::Float) -> String {
    decimal(x, a.digits)
}

fn known_dec(a: &Analysis, k: &Known) -> String {
    let digits = match k.digits {
        Some(d) => (d as usize).min(a.digits),
        None => a.digits,
    };
    decimal(&k.value, digits)
}

fn facts_text(out: &mut String, title: &str, facts: &[Fact]) {
    let _ = writeln!(out, "\n{title}");
    for f in facts {
        let _ = writeln!(
            out,
            "  [{}] {}: {}",
            if f.holds { "yes" } else { "no " },
            f.name,
            f.detail
        );
    }
}

fn terms_text(out: &mut String, da: &DiscAnalysis, title: &str, terms: &[Term]) {
    let h = if da.disc.is_paper() {
        "h = d".to_string()
    } else {
        format!("h = {} d, F = W'(r/h)/(h^3 r)", da.disc.h)
    };
    let _ = writeln!(
        out,
        "\n{title} ({} particles, self included; lengths in d, {h})",
        terms.len()
    );
    let _ = writeln!(
        out,
        "  {:>3} {:>6} {:>6}  {:>19} {:>19}  {:>19} {:>19} {:>19}",
        "k", "x", "r^2", "W", "W'", "x^2 W'/r", "k^2 W'/r (k>0)", "2k^2x^2W'/r^3"
    );
    for t in terms {
        let d = |e: &Exact| format!("{:>19}", decimal(&e.to_float(64), 12));
        let _ = writeln!(
            out,
            "  {:>3} {:>6} {:>6}  {} {}  {} {} {}",
            t.nb.k,
            t.nb.x.to_string(),
            t.nb.r2.to_string(),
            d(&t.w),
            d(&t.dw),
            d(&t.g),
            d(&t.v),
            d(&t.av)
        );
    }
}

fn compared_text(out: &mut String, title: &str, rows: &[Compared]) {
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(out, "\n{title}");
    let _ = writeln!(
        out,
        "  {:<22} {:>10} {:>12} {:>16} {:>11}  agree?",
        "quantity", "printed", "ours rounded", "ours", "ours-print"
    );
    for r in rows {
        let _ = writeln!(
            out,
            "  {:<22} {:>10} {:>12} {:>16} {:>11}  {}",
            r.what,
            r.printed,
            r.ours_rounded,
            r.ours,
            r.difference,
            if r.matches {
                "yes"
            } else {
                "NO: the print differs from the exact value"
            }
        );
    }
}

pub fn text(a: &Analysis) -> String {
    let d = &a.def;
    let mut out = String::new();
    let _ = writeln!(out, "{} — {}", d.name, d.title);
    let _ = writeln!(out, "  file:      {}", d.file.display());
    let _ = writeln!(out, "  reference: {}", d.reference);
    let _ = writeln!(
        out,
        "  support:   R = {} h (h/d and the lattice: per discretisation, below)",
        d.support
    );
    let _ = writeln!(
        out,
        "  decimals:  {} significant digits ({} bits)",
        a.digits, a.prec
    );
    let _ = writeln!(out, "\nW pieces (q = r/h), exact:");
    for p in &d.w.pieces {
        let _ = writeln!(out, "  ({}, {}]: {}", p.from, p.to, p.poly);
    }
    let _ = writeln!(
        out,
        "W' pieces ({}):",
        if d.dw_given { "given" } else { "dW/dq" }
    );
    for p in &d.dw.pieces {
        let _ = writeln!(out, "  ({}, {}]: {}", p.from, p.to, p.poly);
    }
    facts_text(&mut out, "Validation", &a.facts);
    for da in &a.discs {
        disc_text(&mut out, a, da);
    }
    compared_text(&mut out, "Paper, Table 1 (printed) beside ours", &a.table1);
    compared_text(
        &mut out,
        "Paper, Table 2 (printed c0 = F U (sqrt(P alpha^2 + Q A) - S alpha)/N^2) beside ours, per model",
        &a.table2,
    );
    if a.table1.iter().chain(&a.table2).any(|c| !c.matches) {
        let _ = writeln!(
            out,
            "\n  Where a row says NO, the printed value differs from ours at its printed precision. Ours is computed exactly\n  (or to the stated digits) from the kernel's definition; the print is kept for reference, not used."
        );
    }
    out
}

/// One discretisation's part of `show`: stencils, eps, claims, sums, c0.
fn disc_text(out: &mut String, a: &Analysis, da: &DiscAnalysis) {
    let paper = da.disc.is_paper();
    let _ = writeln!(
        out,
        "\n=== Discretisation: {}{}",
        da.disc.label(),
        if paper { " (the paper's)" } else { "" }
    );
    if !paper {
        facts_text(out, "Validation on this lattice", &da.facts);
    }
    let max_label = |c: Config| {
        if da.c0_config.symmetric == Some(c) {
            " (maximum compaction)"
        } else {
            ""
        }
    };
    terms_text(out, da, "Neighbours at t = 0", &da.terms_t0);
    terms_text(
        out,
        da,
        &format!("Neighbours at t = 0.5 T{}", max_label(Config::Half)),
        &da.terms_half,
    );
    let _ = writeln!(out, "\nCompaction eps = rho/rho0 - 1 of the centre particle (n = 0), t as a fraction of T = d N^2/U");
    let e = &da.eps;
    for (name, k) in [
        ("eps(0)", &e.t0),
        ("eps(0.5 T)", &e.half_period),
        ("max eps", &e.max),
        ("t_max / T", &e.t_max),
        ("min eps", &e.min),
        ("t_min / T", &e.t_min),
        ("mean eps", &e.mean),
    ] {
        let _ = writeln!(out, "  {:<11} = {}", name, known_dec(a, k));
        let _ = writeln!(
            out,
            "  {:<11}   {}{}",
            "",
            k.form(),
            if k.exact.is_some() {
                format!("  [{}]", k.how)
            } else {
                String::new()
            }
        );
    }
    facts_text(
        out,
        &format!(
            "The paper's claims about eps, checked (N = {} layers)",
            a.check_layers
        ),
        &da.claims,
    );
    let _ = writeln!(
        out,
        "\nLattice sums (exact; see codegen/src/c0.rs for the derivation)"
    );
    for (label, s) in [("t = 0", &da.sums_t0), ("t = 0.5 T", &da.sums_half)] {
        let _ = writeln!(out, "  {label}:");
        let _ = writeln!(out, "    G  = {}  = {}", s.g, dec(a, &s.g));
        let _ = writeln!(out, "    V  = {}  = {}", s.v, dec(a, &s.v));
        let _ = writeln!(out, "    Av = {}  = {}", s.av, dec(a, &s.av));
        let _ = writeln!(
            out,
            "    2W'(1) (nearest pair) = {}  = {}",
            s.pair,
            dec(a, &s.pair)
        );
    }
    let _ = writeln!(
        out,
        "\nc0 polynomial: a c0^2 + b alpha (U/N^2) c0 + c p d = 0;  root c0 = (U/N^2) (sqrt(P alpha^2 + Q A) - S alpha), A = p d N^4/U^2"
    );
    let cc = &da.c0_config;
    let _ = writeln!(
        out,
        "  derived at maximum compaction: {}; eps0 = {}, {} neighbour(s) in reach ({})",
        cc.label,
        known_dec(a, &cc.eps0),
        cc.neighbours,
        da.disc.label()
    );
    for m in &da.models {
        model_text(out, a, m, &cc.tau);
    }
}

fn model_text(out: &mut String, a: &Analysis, m: &ModelC0, t_max: &Known) {
    let default = if m.model.name == crate::c0::DEFAULT_MODEL {
        " (default)"
    } else {
        ""
    };
    let _ = writeln!(
        out,
        "\n  model {}{}: {}",
        m.model.name, default, m.model.description
    );
    if m.coefs.is_ok() && m.tau.value != t_max.value {
        let _ = writeln!(
            out,
            "    derived at the mirror instant t = {} T, where its S is smaller (the larger c0)",
            known_dec(a, &m.tau)
        );
    }
    match (&m.exact, &m.coefs) {
        (_, Err(fact)) => {
            let _ = writeln!(out, "    {fact}");
        }
        (Some(e), _) => {
            for (n, v) in [("a", &e.a), ("b", &e.b), ("c", &e.c)] {
                let _ = writeln!(out, "    {n} = {}\n        = {}", v, dec(a, v));
            }
            for (n, v) in [("S", &e.s), ("P", &e.p), ("Q", &e.q)] {
                let _ = writeln!(out, "    {n} = {}\n        = {}", v, dec_ratio(a, v));
            }
        }
        (None, Ok(c)) => {
            for (n, v) in [
                ("a", &c.a),
                ("b", &c.b),
                ("c", &c.c),
                ("S", &c.s),
                ("P", &c.p),
                ("Q", &c.q),
            ] {
                let _ = writeln!(
                    out,
                    "    {n} = {}  (high precision, {} bits)",
                    dec_float(a, v),
                    a.prec
                );
            }
        }
    }
}

fn compared_json(rows: &[Compared]) -> Value {
    Value::Array(
        rows.iter()
            .map(|r| {
                json!({"quantity": r.what, "printed": r.printed, "ours_rounded": r.ours_rounded,
                       "ours": r.ours, "difference": r.difference, "matches": r.matches})
            })
            .collect(),
    )
}

fn facts_json(facts: &[Fact]) -> Value {
    Value::Array(
        facts
            .iter()
            .map(|f| json!({"name": f.name, "holds": f.holds, "detail": f.detail}))
            .collect(),
    )
}

/// One discretisation's derivation as JSON.
fn disc_json(a: &Analysis, da: &DiscAnalysis) -> Value {
    let e = &da.eps;
    let known = |k: &Known| json!({"value": known_dec(a, k), "exact": k.exact.as_ref().map(|x| x.to_string()), "digits": k.digits, "how": k.how});
    let mut models = Map::new();
    let mut no_c0 = Map::new();
    for m in &da.models {
        let c = match &m.coefs {
            Ok(c) => c,
            Err(fact) => {
                no_c0.insert(m.model.name.to_string(), json!(fact));
                continue;
            }
        };
        let exact = m.exact.as_ref().map(|e| {
            json!({"S": e.s.to_string(), "P": e.p.to_string(), "Q": e.q.to_string(),
                   "a": e.a.to_string(), "b": e.b.to_string(), "c": e.c.to_string()})
        });
        models.insert(
            m.model.name.to_string(),
            json!({
                "S": dec_float(a, &c.s), "P": dec_float(a, &c.p), "Q": dec_float(a, &c.q),
                "a": dec_float(a, &c.a), "b": dec_float(a, &c.b), "c": dec_float(a, &c.c),
                "exact": exact,
                "time_over_T": known_dec(a, &m.tau),
                "description": m.model.description,
            }),
        );
    }
    let cc = &da.c0_config;
    json!({
        "lattice": da.disc.lattice.name(),
        "h_over_d": da.disc.h.to_string(),
        "label": da.disc.label(),
        "eps": {
            "t0": known_dec(a, &e.t0),
            "half_period": known_dec(a, &e.half_period),
            "max": known_dec(a, &e.max),
            "t_max": known_dec(a, &e.t_max),
            "min": known_dec(a, &e.min),
            "t_min": known_dec(a, &e.t_min),
            "mean": known_dec(a, &e.mean),
            "detail": {
                "t0": known(&e.t0), "half_period": known(&e.half_period), "max": known(&e.max),
                "t_max": known(&e.t_max), "min": known(&e.min), "t_min": known(&e.t_min), "mean": known(&e.mean),
            },
        },
        "c0": {
            "default": crate::c0::DEFAULT_MODEL,
            "models": models,
            "no_c0": no_c0,
            "configuration": {
                "time_over_T": known_dec(a, &cc.tau),
                "time_exact": cc.tau.exact.as_ref().map(|x| x.to_string()),
                "symmetric": cc.symmetric.map(|c| c.label()),
                "eps0": known_dec(a, &cc.eps0),
                "neighbours": cc.neighbours,
                "mirror": cc.mirror.as_ref().map(|m| json!({
                    "time_over_T": known_dec(a, &m.tau),
                    "av_at_t": dec_float(a, &m.av_t),
                    "av_at_mirror": dec_float(a, &m.av_mirror),
                })),
                "label": cc.label,
                "discretisation": da.disc.label(),
            },
        },
        "validation": facts_json(&da.facts),
        "claims": facts_json(&da.claims),
    })
}

pub fn json(a: &Analysis) -> Value {
    let d = &a.def;
    let paper = disc_json(a, a.paper());
    json!({
        "kernel": d.name,
        "title": d.title,
        "reference": d.reference,
        "support": d.support.to_string(),
        "digits": a.digits,
        "discretisation": paper["label"],
        "eps": paper["eps"],
        "c0": paper["c0"],
        "validation": facts_json(&a.facts),
        "claims": paper["claims"],
        "check_layers": a.check_layers,
        "discretisations": a.discs.iter().map(|da| disc_json(a, da)).collect::<Vec<_>>(),
        "paper": {"table1": compared_json(&a.table1), "table2": compared_json(&a.table2)},
    })
}
