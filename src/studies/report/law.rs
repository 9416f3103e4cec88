//! The report's section on the law of the minimal c0, from a folder that
//! `shearsph law` wrote (law.json and law_KERNEL.svg): per kernel the
//! fitted exponents with their standard errors, the paper's scaling and the
//! layers' hypothesis beside, the points not fitted, and the chart.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};
use serde_json::Value;

/// The section: its HTML (one `<section>`, figures referenced by file
/// name) and the figures to write beside the page, as (file name, SVG).
#[derive(Debug, Clone)]
pub struct LawSection {
    pub html: String,
    pub figures: Vec<(String, String)>,
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// "b +- se" cells of a fit (`law.json`'s `free`, `paper`, ...).
fn fit_text(f: &Value) -> String {
    if f.is_null() {
        return "too few points".into();
    }
    let names = f["names"].as_array().cloned().unwrap_or_default();
    let coef = f["coef"].as_array().cloned().unwrap_or_default();
    let se = f["se"].as_array().cloned().unwrap_or_default();
    let terms: Vec<String> = names
        .iter()
        .zip(coef.iter().zip(&se))
        .map(|(n, (c, s))| {
            format!(
                "{}: {:.3} &plusmn; {:.3}",
                esc(n.as_str().unwrap_or("?")),
                c.as_f64().unwrap_or(f64::NAN),
                s.as_f64().unwrap_or(f64::NAN)
            )
        })
        .collect();
    format!(
        "{}; rms residual of ln c0 {:.3} ({} dof)",
        terms.join(", "),
        f["rms"].as_f64().unwrap_or(f64::NAN),
        f["dof"].as_u64().unwrap_or(0)
    )
}

/// The law section from `dir` (a `shearsph law` output folder).
pub fn law_section(dir: &Path) -> Result<LawSection> {
    let path = dir.join("law.json");
    let text = std::fs::read_to_string(&path).with_context(|| {
        format!(
            "reading {} (run `shearsph law --out {}`)",
            path.display(),
            dir.display()
        )
    })?;
    let law: Value =
        serde_json::from_str(&text).with_context(|| format!("parsing {}", path.display()))?;
    let mut html = String::from("<section id=\"law\">\n<h2>The law of the minimal c0</h2>\n");
    let points = law["points"].as_array().map_or(0, Vec::len);
    writeln!(
        html,
        "<p>The empirical c0_min (the smallest c0 ok on the perfect lattice and on every \
         perturbed seed) at {points} points, fitted by least squares in ln c0_min / U; the \
         paper's scaling c0 &prop; U / sqrt(N Re) (alpha = 0) and the layers' hypothesis c0 \
         &prop; (2N &minus; 1) U / N<sup>2</sup> fitted for their coefficient alone. Sweep: {:.0} s.</p>",
        law["wall_s"].as_f64().unwrap_or(f64::NAN)
    )?;
    let mut figures = Vec::new();
    for kl in law["laws"].as_array().cloned().unwrap_or_default() {
        let kernel = kl["kernel"].as_str().unwrap_or("?").to_string();
        writeln!(html, "<h3>{}</h3>\n<table>", esc(&kernel))?;
        for (label, key) in [
            (
                "free: ln c0 = b0 + bN ln N + bRe ln Re (+ balpha alpha)",
                "free",
            ),
            (
                "free, alpha = 0 only (the paper: bN = bRe = &minus;1/2)",
                "free_alpha0",
            ),
            ("paper's U / sqrt(N Re), alpha = 0", "paper"),
            ("(2N &minus; 1) U / N<sup>2</sup>", "layers"),
        ] {
            writeln!(
                html,
                "<tr><th>{label}</th><td>{}</td></tr>",
                fit_text(&kl[key])
            )?;
        }
        html.push_str("</table>\n");
        let unfitted = kl["unfitted"].as_array().cloned().unwrap_or_default();
        writeln!(
            html,
            "<p>{} points fitted; {} not:</p>",
            kl["fitted"].as_u64().unwrap_or(0),
            unfitted.len()
        )?;
        if !unfitted.is_empty() {
            html.push_str("<ul>\n");
            for u in &unfitted {
                writeln!(html, "<li>{}</li>", esc(u.as_str().unwrap_or("")))?;
            }
            html.push_str("</ul>\n");
        }
        let svg_name = format!("law_{kernel}.svg");
        let svg_path = dir.join(&svg_name);
        if let Ok(svg) = std::fs::read_to_string(&svg_path) {
            writeln!(
                html,
                "<figure><img src=\"{}\" alt=\"c0_min against N for {}\"><figcaption>c0_min / U \
                 against N for each Re, every rule's c0, the fitted law.</figcaption></figure>",
                esc(&svg_name),
                esc(&kernel)
            )?;
            figures.push((svg_name, svg));
        }
    }
    html.push_str("</section>\n");
    Ok(LawSection { html, figures })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_law_folder_gives_its_section() {
        let dir = std::env::temp_dir().join(format!("shearsph-law-section-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let json = r#"{"points":[{}],"wall_s":3.0,"laws":[{"kernel":"monaghan","fitted":1,
            "unfitted":["N = 6, Re = 30, alpha = 0.1: no c0 probed was ok on every start"],
            "free":{"names":["1","ln N"],"coef":[1.0,-0.5],"se":[0.1,0.05],"rms":0.1,"dof":3},
            "free_alpha0":null,"paper":null,"layers":null}]}"#;
        std::fs::write(dir.join("law.json"), json).unwrap();
        std::fs::write(dir.join("law_monaghan.svg"), "<svg/>").unwrap();
        let s = law_section(&dir).unwrap();
        assert!(s.html.contains("ln N: -0.500 &plusmn; 0.050"), "{}", s.html);
        assert!(s.html.contains("no c0 probed was ok"));
        assert_eq!(
            s.figures,
            vec![("law_monaghan.svg".to_string(), "<svg/>".to_string())]
        );
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(law_section(&dir).is_err(), "a missing folder is an error");
    }
}
