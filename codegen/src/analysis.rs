//! Everything derived for one kernel: validation facts, the compaction
//! analysis, the paper's claims checked, the c0 models, and the comparison
//! with the paper's printed tables.

use crate::c0::{self, Derivation, Sums, Term, MODELS};
use crate::compaction::{self, cell_area, EpsCurve, FloatRadial, Known, Site};
use crate::exact::{bits_for_digits, decimal, Exact};
use crate::kernel::{gradient_moment, normalisation, KernelDef};
use crate::lattice::{max_layer_offset, Config};
use crate::poly::parse_decimal;
use rug::{Float, Rational};

/// A statement about a kernel, and whether it holds.
#[derive(Clone, Debug)]
pub struct Fact {
    pub name: String,
    pub holds: bool,
    pub detail: String,
}

/// Section 4's numbers for the centre particle (n = 0).
#[derive(Clone, Debug)]
pub struct EpsSummary {
    pub t0: Known,
    pub half_period: Known,
    pub max: Known,
    pub t_max: Known,
    pub min: Known,
    pub t_min: Known,
    pub mean: Known,
}

/// One printed number beside ours.
#[derive(Clone, Debug)]
pub struct Compared {
    pub what: String,
    pub printed: String,
    /// Ours, rounded to the printed number of decimals.
    pub ours_rounded: String,
    pub ours: String,
    pub matches: bool,
    /// ours - printed
    pub difference: String,
}

#[derive(Clone, Debug)]
pub struct Analysis {
    pub def: KernelDef,
    pub digits: usize,
    pub prec: u32,
    pub facts: Vec<Fact>,
    pub eps: EpsSummary,
    /// The layer count used for the claims about n and the wall.
    pub check_layers: i64,
    pub claims: Vec<Fact>,
    pub terms_t0: Vec<Term>,
    pub terms_half: Vec<Term>,
    pub sums_t0: Sums,
    pub sums_half: Sums,
    pub models: Vec<Derivation>,
    pub table1: Vec<Compared>,
    pub table2: Vec<Compared>,
}

/// Options of an analysis.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Decimal digits of the reported decimals.
    pub digits: usize,
    /// N for the claims about layers n and the wall.
    pub check_layers: i64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            digits: 30,
            check_layers: 10,
        }
    }
}

fn compare(what: &str, printed: &str, ours: &Float, digits: usize) -> Compared {
    let p = parse_decimal(printed.trim_start_matches('-')).map(|x| {
        if printed.starts_with('-') {
            -x
        } else {
            x
        }
    });
    let decimals = printed.split_once('.').map(|(_, f)| f.len()).unwrap_or(0);
    let scale = Float::with_val(ours.prec(), 10u32).pow(decimals as u32);
    use rug::ops::Pow;
    let scaled = Float::with_val(ours.prec(), ours * &scale).round();
    let ours_int = scaled.to_integer().unwrap();
    let ours_rounded = Rational::from((ours_int, rug::Integer::from(10u32).pow(decimals as u32)));
    let matches = p.as_ref() == Some(&ours_rounded);
    let diff = p
        .as_ref()
        .map(|p| decimal(&Float::with_val(ours.prec(), ours - p), 3))
        .unwrap_or_else(|| "unreadable print".into());
    let rounded_str = {
        let f = Float::with_val(ours.prec(), &ours_rounded);
        format!("{:.*}", decimals, f.to_f64())
    };
    Compared {
        what: what.into(),
        printed: printed.into(),
        ours_rounded: rounded_str,
        ours: decimal(ours, digits.min(12)),
        matches,
        difference: diff,
    }
}

/// The curve's amplitude (max - min) and mean for a site, at `prec` bits.
fn amplitude(fr: &FloatRadial, def: &KernelDef, site: Site) -> (f64, f64, f64) {
    let curve = EpsCurve::new(fr, &def.support, site);
    let (mx, mn) = compaction::extremes(&curve);
    (
        Float::with_val(mx.value.prec(), &mx.value - &mn.value).to_f64(),
        mx.value.to_f64(),
        mx.tau.to_f64(),
    )
}

pub fn analyse(def: &KernelDef, opts: Options) -> Analysis {
    let prec = bits_for_digits(opts.digits + 10);
    let r = &def.support;
    let area = cell_area();

    // --- validation facts (the unusable cases were errors at parse time)
    let mut facts = Vec::new();
    let norm = normalisation(&def.w);
    facts.push(Fact {
        name: "normalised".into(),
        holds: norm == Exact::one(),
        detail: format!("2 pi int_0^R W q dq = {norm} (exact)"),
    });
    facts.push(Fact {
        name: "continuous, W(R) = 0".into(),
        holds: true,
        detail: format!("{} piece(s), joints checked exactly", def.w.pieces.len()),
    });
    let derivative = def.w.derivative();
    let is_derivative = derivative == def.dw;
    facts.push(Fact {
        name: "gradient is dW/dq".into(),
        holds: is_derivative,
        detail: if def.dw_given {
            if is_derivative {
                "the given gradient equals dW/dq exactly".into()
            } else {
                "the given gradient is NOT dW/dq; the SPH sums (12), (14), (31) use the given one, the density (11) uses W".into()
            }
        } else {
            "no separate gradient given: dW/dq is used".into()
        },
    });
    let dw_r = def.dw.pieces.last().unwrap().poly.eval_rational(r);
    facts.push(Fact {
        name: "gradient vanishes at R".into(),
        holds: dw_r.is_zero(),
        detail: format!(
            "W'(R) = {dw_r}; with a closed support, neighbours at exactly q = R feel it"
        ),
    });
    let mut joints_ok = true;
    for pair in def.dw.pieces.windows(2) {
        if pair[0].poly.eval_rational(&pair[0].to) != pair[1].poly.eval_rational(&pair[0].to) {
            joints_ok = false;
        }
    }
    facts.push(Fact {
        name: "gradient continuous at the joints".into(),
        holds: joints_ok,
        detail: format!("{} joint(s) checked exactly", def.dw.pieces.len() - 1),
    });
    let moment = gradient_moment(&def.dw);
    facts.push(Fact {
        name: "gradient normalised (continuum)".into(),
        holds: moment == Exact::int(-1),
        detail: format!(
            "pi int_0^R W' q^2 dq = {moment} = {} (-1 for the derivative of a normalised kernel)",
            decimal(&moment.to_float(prec), 15)
        ),
    });
    facts.extend(crate::kernel::shape_facts(def));
    let terms_t0 = c0::terms(&def.w, &def.dw, r, Config::T0);
    let terms_half = c0::terms(&def.w, &def.dw, r, Config::Half);
    let sums_t0 = c0::sums(&terms_t0);
    let sums_half = c0::sums(&terms_half);
    let lattice_moment = &area * &sums_t0.g;
    facts.push(Fact {
        name: "gradient normalised (lattice)".into(),
        holds: lattice_moment == Exact::int(-1),
        detail: format!(
            "(sqrt(3)/2) sum_j x_j^2 W'(r_j)/r_j at t = 0 = {lattice_moment} = {}",
            decimal(&lattice_moment.to_float(prec), 15)
        ),
    });
    let eps_t0 = compaction::eps_exact(&def.w, r, Config::T0);
    let lattice_norm = &eps_t0 + &Exact::one();
    facts.push(Fact {
        name: "normalised on the lattice".into(),
        holds: lattice_norm == Exact::one(),
        detail: format!(
            "(sqrt(3)/2) sum_j W(r_j) at t = 0 = {}",
            decimal(&lattice_norm.to_float(prec), 15)
        ),
    });
    facts.push(Fact {
        name: "even in q (no square root needed)".into(),
        holds: def.w.is_even() && def.dw.pieces.iter().all(|p| p.poly.is_odd()),
        detail:
            "W has only even powers of q and W' only odd ones, so W and W'/q are polynomials in q^2"
                .into(),
    });

    // --- compaction for the centre particle
    let eps_half = compaction::eps_exact(&def.w, r, Config::Half);
    let fr = FloatRadial::new(&def.w, prec);
    let curve = EpsCurve::new(&fr, r, Site::CENTRE);
    let (mx, mn) = compaction::extremes(&curve);
    let t0_known = Known::exact(eps_t0.clone(), prec, "exact lattice sum");
    let half_known = Known::exact(eps_half.clone(), prec, "exact lattice sum");
    // The search's result is recognised as the exact configuration when it
    // lands there (to half the working precision in tau, all of it in eps).
    let recognise = |e: &compaction::Extreme,
                     at: &Rational,
                     exact: &Known|
     -> Option<(Known, Known)> {
        let tau_err = Float::with_val(prec, &e.tau - at).abs();
        let val_err = Float::with_val(prec, &e.value - &exact.value).abs();
        let tau_tol = Float::with_val(prec, Float::i_exp(1, -((prec / 3) as i32)));
        let val_tol = Float::with_val(prec, Float::i_exp(1, -((prec * 2 / 3) as i32)));
        (tau_err < tau_tol && val_err < val_tol).then(|| {
            (
                Known {
                    how: format!("search (golden section, {prec} bits) confirmed to land on the exact configuration"),
                    ..exact.clone()
                },
                Known::exact(Exact::rational(at.clone()), prec, "exact"),
            )
        })
    };
    let searched = |e: &compaction::Extreme| -> (Known, Known) {
        let digits = (prec as f64 * std::f64::consts::LOG10_2 / 2.0).floor() as u32 - 3;
        (
            Known {
                value: e.value.clone(),
                exact: None,
                digits: Some(digits),
                how: format!("golden-section search at {prec} bits"),
            },
            Known {
                value: e.tau.clone(),
                exact: None,
                digits: Some(digits / 2),
                how: "location of the search's extreme".into(),
            },
        )
    };
    let half = Rational::from((1, 2));
    let zero = Rational::new();
    let (max, t_max) = recognise(&mx, &half, &half_known).unwrap_or_else(|| searched(&mx));
    let (min, t_min) = recognise(&mn, &zero, &t0_known)
        .or_else(|| {
            recognise(&mn, &Rational::from(1), &t0_known)
                .map(|(v, _)| (v, Known::exact(Exact::zero(), prec, "exact")))
        })
        .unwrap_or_else(|| searched(&mn));
    let mean = compaction::mean(&def.w, r, Site::CENTRE, prec);

    // --- the paper's claims, checked
    let nl = opts.check_layers;
    let kmax = max_layer_offset(r);
    let rr = r.to_f64().ceil() as i64;
    let check_prec = 128;
    let frc = FloatRadial::new(&def.w, check_prec);
    let mut claims = Vec::new();
    let t_max_is_half = t_max.exact.as_ref() == Some(&Exact::rational(half.clone()));
    claims.push(Fact {
        name: "maximum of eps at exactly 0.5 T (n = 0)".into(),
        holds: t_max_is_half,
        detail: format!(
            "search finds the maximum at t = {} T",
            decimal(&t_max.value, 20)
        ),
    });
    let (amp0, _, _) = amplitude(&frc, def, Site::CENTRE);
    let mut amp_bad = Vec::new();
    let mut amps = Vec::new();
    for n in 1..=(nl - rr) {
        let (a, _, _) = amplitude(
            &frc,
            def,
            Site {
                n,
                n_layers: Some(nl),
            },
        );
        amps.push(format!("n={n}: {:.6e}", a));
        if ((a - amp0) / amp0).abs() > 1e-9 {
            amp_bad.push(n);
        }
    }
    claims.push(Fact {
        name: format!("amplitude of eps independent of n (0 <= n <= N - R, N = {nl})"),
        holds: amp_bad.is_empty(),
        detail: format!(
            "amplitude at n=0: {:.6e}; {}{}",
            amp0,
            amps.join(", "),
            if amp_bad.is_empty() {
                String::new()
            } else {
                format!("; differs (relative 1e-9) at n = {amp_bad:?}")
            }
        ),
    });
    let mut mean_bad = Vec::new();
    let mut means = Vec::new();
    let mean1 = compaction::mean(
        &def.w,
        r,
        Site {
            n: nl - rr,
            n_layers: Some(nl),
        },
        check_prec,
    );
    for n in 1..=(nl - rr) {
        let m = compaction::mean(
            &def.w,
            r,
            Site {
                n,
                n_layers: Some(nl),
            },
            check_prec,
        );
        means.push(format!("n={n}: {}", decimal(&m.value, 8)));
        let d = Float::with_val(check_prec, &m.value - &mean1.value)
            .abs()
            .to_f64();
        if d > 1e-20 {
            mean_bad.push(n);
        }
    }
    claims.push(Fact {
        name: format!("mean of eps the same for 0 < n <= N - R (N = {nl})"),
        holds: mean_bad.is_empty(),
        detail: format!(
            "{}{}",
            means.join(", "),
            if mean_bad.is_empty() {
                String::new()
            } else {
                format!(
                    "; differs at n = {mean_bad:?}: there the mirror layer -n (at rest relative to the particle) is within reach of 2 n (sqrt(3)/2) <= R"
                )
            }
        ),
    });
    let (amp_wall, _, _) = amplitude(
        &frc,
        def,
        Site {
            n: nl - 1,
            n_layers: Some(nl),
        },
    );
    let drops = amp_wall < amp0 * (1.0 - 1e-9);
    claims.push(Fact {
        name: format!(
            "amplitude drops near the wall (n = N - 1 = {}) when R > 1",
            nl - 1
        ),
        holds: if kmax > 1 { drops } else { !drops },
        detail: format!(
            "amplitude at n = N - 1: {:.6e}, at n = 0: {:.6e} (ratio {:.4})",
            amp_wall,
            amp0,
            amp_wall / amp0
        ),
    });

    // --- c0
    let models: Vec<Derivation> = MODELS
        .iter()
        .map(|m| c0::derive(*m, &eps_half, &sums_t0, &sums_half))
        .collect();

    // --- paper
    let mut table1 = Vec::new();
    let mut table2 = Vec::new();
    if let Some(p) = &def.paper {
        table1.push(compare(
            "eps(0T)",
            &p.table1.t0,
            &t0_known.value,
            opts.digits,
        ));
        table1.push(compare(
            "eps(0.5T)",
            &p.table1.half_period,
            &half_known.value,
            opts.digits,
        ));
        table1.push(compare(
            "mean eps",
            &p.table1.mean,
            &mean.value,
            opts.digits,
        ));
        if let Some(t2) = &p.table2 {
            table2.push(compare("eps0", &t2.eps0, &half_known.value, opts.digits));
            let f = parse_decimal(&t2.factor).expect("printed factor is a number");
            let f = Float::with_val(prec, &f);
            for d in &models {
                let s = Float::with_val(prec, d.s.to_float(prec) / &f);
                let pp = Float::with_val(
                    prec,
                    d.p.to_float(prec) / Float::with_val(prec, f.square_ref()),
                );
                let q = Float::with_val(
                    prec,
                    d.q.to_float(prec) / Float::with_val(prec, f.square_ref()),
                );
                table2.push(compare(
                    &format!("S/F [{}]", d.model.name),
                    &t2.s,
                    &s,
                    opts.digits,
                ));
                table2.push(compare(
                    &format!("P/F^2 [{}]", d.model.name),
                    &t2.p,
                    &pp,
                    opts.digits,
                ));
                table2.push(compare(
                    &format!("Q/F^2 [{}]", d.model.name),
                    &t2.q,
                    &q,
                    opts.digits,
                ));
            }
        }
    }

    Analysis {
        def: def.clone(),
        digits: opts.digits,
        prec,
        facts,
        eps: EpsSummary {
            t0: t0_known,
            half_period: half_known,
            max,
            t_max,
            min,
            t_min,
            mean,
        },
        check_layers: nl,
        claims,
        terms_t0,
        terms_half,
        sums_t0,
        sums_half,
        models,
        table1,
        table2,
    }
}
