//! Everything derived for one kernel: validation facts, then for every
//! discretisation (lattice kind, h/d) the compaction analysis, the paper's
//! claims checked, the c0 models at the configuration where the search found
//! the maximum; and the comparison with the paper's printed tables (for the
//! paper's discretisation).

use crate::c0::{self, FloatSums, ModelC0, Sums, Term};
use crate::claims;
use crate::compaction::{self, cell_area, EpsCurve, Extreme, FloatRadial, Known, Site};
use crate::exact::{bits_for_digits, decimal, Exact};
use crate::kernel::{gradient_moment, normalisation, KernelDef};
use crate::lattice::{Config, Discretisation};
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

/// Where the c0 models were derived: the configuration of maximum
/// compaction the search found.
#[derive(Clone, Debug)]
pub struct C0Configuration {
    /// `Some` when the maximum is at a symmetric configuration (exact
    /// derivation), `None` when it is elsewhere (high precision at `tau`).
    pub symmetric: Option<Config>,
    /// t / T of the configuration.
    pub tau: Known,
    /// eps0 = eps at that configuration.
    pub eps0: Known,
    /// Neighbours (self excluded) in reach there.
    pub neighbours: usize,
    /// For the reader: "t = 0.5 T (exact)" or "t = 0.0912... T and its
    /// mirror T - t ... (search, 133 bits)".
    pub label: String,
    /// At a maximum off the symmetric configurations: its mirror instant
    /// T - t, where eps is the same maximum (see `c0::stricter_mirror`).
    pub mirror: Option<Mirror>,
}

/// The mirror instant T - t of a maximum at t off the symmetric
/// configurations, and the artificial viscosity's sum at both (the only sum
/// of the balance that differs between them).
#[derive(Clone, Debug)]
pub struct Mirror {
    /// (T - t) / T.
    pub tau: Known,
    /// Av at t and at T - t.
    pub av_t: Float,
    pub av_mirror: Float,
}

/// The analysis of one kernel on one discretisation.
#[derive(Clone, Debug)]
pub struct DiscAnalysis {
    pub disc: Discretisation,
    /// Lattice facts: normalisation of W and of the gradient on this lattice.
    pub facts: Vec<Fact>,
    pub eps: EpsSummary,
    pub claims: Vec<Fact>,
    pub terms_t0: Vec<Term>,
    pub terms_half: Vec<Term>,
    pub sums_t0: Sums,
    pub sums_half: Sums,
    pub c0_config: C0Configuration,
    pub models: Vec<ModelC0>,
}

#[derive(Clone, Debug)]
pub struct Analysis {
    pub def: KernelDef,
    pub digits: usize,
    pub prec: u32,
    pub facts: Vec<Fact>,
    /// The layer count used for the claims about n and the wall.
    pub check_layers: i64,
    /// One per discretisation; the first is the paper's (triangular, h = d).
    pub discs: Vec<DiscAnalysis>,
    pub table1: Vec<Compared>,
    pub table2: Vec<Compared>,
}

impl DiscAnalysis {
    /// The models derived exactly (every model, when the maximum is at a
    /// symmetric configuration and none is degenerate).
    pub fn exact_models(&self) -> Vec<&c0::Derivation> {
        self.models
            .iter()
            .filter_map(|m| m.exact.as_ref())
            .collect()
    }
}

impl Analysis {
    /// The paper's discretisation (triangular lattice, h = d).
    pub fn paper(&self) -> &DiscAnalysis {
        &self.discs[0]
    }
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

/// Derives everything for `def` on the paper's discretisation and on each of
/// `discs` (the paper's is added first when missing; duplicates are skipped).
pub fn analyse(def: &KernelDef, discs: &[Discretisation], opts: Options) -> Analysis {
    let prec = bits_for_digits(opts.digits + 10);
    let mut all = vec![Discretisation::paper()];
    for d in discs {
        if !all.contains(d) {
            all.push(d.clone());
        }
    }
    // the discretisations are independent: derive them side by side
    let discs: Vec<DiscAnalysis> = std::thread::scope(|scope| {
        let handles: Vec<_> = all
            .iter()
            .map(|d| scope.spawn(move || analyse_disc(def, d, opts, prec)))
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .expect("a discretisation's derivation does not panic")
            })
            .collect()
    });
    let mut facts = kernel_facts(def, prec);
    // the paper's lattice facts sit among the kernel's, as they always have
    let paper = &discs[0];
    facts.splice(6..6, paper.facts.iter().cloned());
    let (table1, table2) = paper_tables(def, paper, opts.digits, prec);
    Analysis {
        def: def.clone(),
        digits: opts.digits,
        prec,
        facts,
        check_layers: opts.check_layers,
        discs,
        table1,
        table2,
    }
}

/// The facts about the kernel itself (continuum), in the order `show` prints.
fn kernel_facts(def: &KernelDef, prec: u32) -> Vec<Fact> {
    let r = &def.support;
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
    let joints_ok = def.dw.pieces.windows(2).all(|pair| {
        pair[0].poly.eval_rational(&pair[0].to) == pair[1].poly.eval_rational(&pair[0].to)
    });
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
    facts.push(Fact {
        name: "even in q (no square root needed)".into(),
        holds: def.w.is_even() && def.dw.pieces.iter().all(|p| p.poly.is_odd()),
        detail:
            "W has only even powers of q and W' only odd ones, so W and W'/q are polynomials in q^2"
                .into(),
    });
    facts
}

/// The normalisation of W and of the gradient on one lattice (t = 0).
fn lattice_facts(disc: &Discretisation, sums_t0: &Sums, eps_t0: &Exact, prec: u32) -> Vec<Fact> {
    let area = cell_area(disc);
    let lattice_moment = &area * &sums_t0.g;
    let lattice_norm = eps_t0 + &Exact::one();
    let area_txt = if disc.is_paper() {
        "(sqrt(3)/2)".to_string()
    } else {
        format!("(dy d/h^2 = {area})")
    };
    vec![
        Fact {
            name: "gradient normalised (lattice)".into(),
            holds: lattice_moment == Exact::int(-1),
            detail: format!(
                "{area_txt} sum_j x_j^2 W'(r_j)/r_j at t = 0 = {lattice_moment} = {}",
                decimal(&lattice_moment.to_float(prec), 15)
            ),
        },
        Fact {
            name: "normalised on the lattice".into(),
            holds: lattice_norm == Exact::one(),
            detail: format!(
                "{area_txt} sum_j W(r_j) at t = 0 = {}",
                decimal(&lattice_norm.to_float(prec), 15)
            ),
        },
    ]
}

/// One discretisation: stencils, eps, claims, c0 at the true maximum.
fn analyse_disc(def: &KernelDef, disc: &Discretisation, opts: Options, prec: u32) -> DiscAnalysis {
    let r = &def.support;
    let terms_t0 = c0::terms(&def.w, &def.dw, r, disc, Config::T0);
    let terms_half = c0::terms(&def.w, &def.dw, r, disc, Config::Half);
    let sums_t0 = c0::sums(&terms_t0);
    let sums_half = c0::sums(&terms_half);
    let eps_t0 = compaction::eps_exact(&def.w, r, disc, Config::T0);
    let eps_half = compaction::eps_exact(&def.w, r, disc, Config::Half);
    let facts = lattice_facts(disc, &sums_t0, &eps_t0, prec);
    let fr = FloatRadial::new(&def.w, prec);
    let curve = EpsCurve::new(&fr, r, disc, Site::CENTRE);
    let (mut mx, mut mn) = compaction::extremes(&curve);
    // eps(t) = eps(T - t) for the centre particle (the configuration at
    // T - t is the one at t mirrored in x): state the earlier of the two,
    // whichever the search returned
    for e in [&mut mx, &mut mn] {
        let mirror = Float::with_val(prec, 1u32 - &e.tau);
        if mirror < e.tau {
            e.tau = mirror;
        }
    }
    let t0_known = Known::exact(eps_t0.clone(), prec, "exact lattice sum");
    let half_known = Known::exact(eps_half.clone(), prec, "exact lattice sum");
    let at_max = recognise_any(&mx, &t0_known, &half_known, prec);
    let at_min = recognise_any(&mn, &t0_known, &half_known, prec);
    let (max, t_max) = at_max
        .clone()
        .map(|(_, v, t)| (v, t))
        .unwrap_or_else(|| searched(&mx, prec));
    let (min, t_min) = at_min
        .map(|(_, v, t)| (v, t))
        .unwrap_or_else(|| searched(&mn, prec));
    let mean = compaction::mean(&def.w, r, disc, Site::CENTRE, prec);
    let eps = EpsSummary {
        t0: t0_known,
        half_period: half_known,
        max,
        t_max,
        min,
        t_min,
        mean,
    };
    let claims = claims::claims(def, disc, &eps, opts.check_layers);

    // c0 from the configuration where the search found the maximum
    let symmetric = at_max.map(|(c, _, _)| c);
    let (c0_config, models) = match symmetric {
        Some(c) => {
            let (eps0, s1, terms) = match c {
                Config::T0 => (&eps_t0, &sums_t0, &terms_t0),
                Config::Half => (&eps_half, &sums_half, &terms_half),
            };
            let neighbours = terms.iter().filter(|t| !t.nb.is_self()).count();
            let at = c0::AtMax {
                eps0: Ok(eps0),
                sums: Ok(s1),
                neighbours,
                config: Some(c),
                tau: &eps.t_max,
            };
            let models = c0::derive_all(&at, &sums_t0, disc, prec);
            let config = C0Configuration {
                symmetric: Some(c),
                tau: eps.t_max.clone(),
                eps0: eps.max.clone(),
                neighbours,
                label: format!(
                    "{} (exact: the maximum the search found is attained there)",
                    c.label()
                ),
                mirror: None,
            };
            (config, models)
        }
        None => {
            // the maximum at t (t < T/2) and at its mirror T - t
            let frdw = FloatRadial::new(&def.dw, prec);
            let sums_at = |tau: &Float| {
                let nbs: Vec<_> = curve
                    .neighbours(tau)
                    .into_iter()
                    .filter(|n| !n.2.is_zero())
                    .collect();
                (FloatSums::at(&frdw, &nbs, disc, prec), nbs.len())
            };
            let tau_m = Float::with_val(prec, 1u32 - &mx.tau);
            let (s_t, n_t) = sums_at(&mx.tau);
            let (s_m, _) = sums_at(&tau_m);
            let mirror = Mirror {
                tau: Known {
                    value: tau_m.clone(),
                    how: "T - t: the mirror of the search's maximum".into(),
                    ..eps.t_max.clone()
                },
                av_t: s_t.av.clone(),
                av_mirror: s_m.av.clone(),
            };
            let derive = |s: &FloatSums, tau: &Known| {
                let at = c0::AtMax {
                    eps0: Err(&mx.value),
                    sums: Err(s),
                    neighbours: n_t,
                    config: None,
                    tau,
                };
                c0::derive_all(&at, &sums_t0, disc, prec)
            };
            let models = derive(&s_t, &eps.t_max)
                .into_iter()
                .zip(derive(&s_m, &mirror.tau))
                .map(|(at_t, at_m)| c0::stricter_mirror(at_t, at_m))
                .collect();
            let config = C0Configuration {
                symmetric: None,
                tau: eps.t_max.clone(),
                eps0: eps.max.clone(),
                neighbours: n_t,
                label: format!(
                    "t = {} T and its mirror T - t = {} T (where the search found the maximum; not a \
                     symmetric configuration: sums evaluated at {prec} bits). The configuration at T - t \
                     is the one at t mirrored in x: eps0, G, V and the pair's sum are the same there, \
                     the artificial viscosity's Av is not (Av = {} at t, {} at T - t: it sums the \
                     approaching pairs, x > 0, which the mirror exchanges with receding ones), so each \
                     -av model is derived at the one where its S is smaller, which gives it the larger \
                     c0 at every Re and alpha",
                    decimal(&mx.tau, 20),
                    decimal(&tau_m, 20),
                    decimal(&mirror.av_t, 12),
                    decimal(&mirror.av_mirror, 12),
                ),
                mirror: Some(mirror),
            };
            (config, models)
        }
    };
    DiscAnalysis {
        disc: disc.clone(),
        facts,
        eps,
        claims,
        terms_t0,
        terms_half,
        sums_t0,
        sums_half,
        c0_config,
        models,
    }
}

/// The search's extreme recognised as one of the exact symmetric
/// configurations when it lands there (to a third of the working precision
/// in tau, two thirds in eps): t = 0 (or T), or t = 0.5 T; or, when the
/// curve is flat at its extreme (the search stops anywhere on a plateau),
/// when a symmetric configuration attains the extreme value (to two thirds
/// of the working precision): it is then an extreme too, and exact.
fn recognise_any(
    e: &Extreme,
    t0: &Known,
    half: &Known,
    prec: u32,
) -> Option<(Config, Known, Known)> {
    let tau_tol = Float::with_val(prec, Float::i_exp(1, -((prec / 3) as i32)));
    let val_tol = Float::with_val(prec, Float::i_exp(1, -((prec * 2 / 3) as i32)));
    let candidates = [
        (
            Config::Half,
            Rational::from((1, 2)),
            half,
            Rational::from((1, 2)),
        ),
        (Config::T0, Rational::new(), t0, Rational::new()),
        (Config::T0, Rational::from(1), t0, Rational::new()),
    ];
    let lands = |at: &Rational, exact: &Known| {
        let tau_err = Float::with_val(prec, &e.tau - at).abs();
        let val_err = Float::with_val(prec, &e.value - &exact.value).abs();
        (tau_err < tau_tol, val_err < val_tol)
    };
    let landed = candidates
        .iter()
        .any(|(_, at, exact, _)| lands(at, exact) == (true, true));
    candidates.into_iter().find_map(|(c, at, exact, report)| {
        let (near, equal) = lands(&at, exact);
        (equal && (near || !landed)).then(|| {
            (
                c,
                Known {
                    how: format!("search (golden section, {prec} bits) confirmed to land on the exact configuration"),
                    ..exact.clone()
                },
                Known::exact(Exact::rational(report), prec, "exact"),
            )
        })
    })
}

/// An extreme known from the search only, with its stated digits.
fn searched(e: &Extreme, prec: u32) -> (Known, Known) {
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
}

/// The paper's Tables 1 and 2 beside ours (paper's discretisation only).
fn paper_tables(
    def: &KernelDef,
    paper: &DiscAnalysis,
    digits: usize,
    prec: u32,
) -> (Vec<Compared>, Vec<Compared>) {
    let mut table1 = Vec::new();
    let mut table2 = Vec::new();
    let Some(p) = &def.paper else {
        return (table1, table2);
    };
    let e = &paper.eps;
    table1.push(compare("eps(0T)", &p.table1.t0, &e.t0.value, digits));
    table1.push(compare(
        "eps(0.5T)",
        &p.table1.half_period,
        &e.half_period.value,
        digits,
    ));
    table1.push(compare("mean eps", &p.table1.mean, &e.mean.value, digits));
    if let Some(t2) = &p.table2 {
        table2.push(compare(
            "eps0",
            &t2.eps0,
            &paper.c0_config.eps0.value,
            digits,
        ));
        let f = parse_decimal(&t2.factor).expect("printed factor is a number");
        let f = Float::with_val(prec, &f);
        let f2 = Float::with_val(prec, f.square_ref());
        for m in &paper.models {
            let Ok(d) = &m.coefs else { continue };
            let name = m.model.name;
            let s = Float::with_val(prec, &d.s / &f);
            let pp = Float::with_val(prec, &d.p / &f2);
            let q = Float::with_val(prec, &d.q / &f2);
            table2.push(compare(&format!("S/F [{name}]"), &t2.s, &s, digits));
            table2.push(compare(&format!("P/F^2 [{name}]"), &t2.p, &pp, digits));
            table2.push(compare(&format!("Q/F^2 [{name}]"), &t2.q, &q, digits));
        }
    }
    (table1, table2)
}
