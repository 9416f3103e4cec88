//! Emission of `generated/`: one module per kernel and a registry, built as
//! token trees with `quote!`, printed with `prettyplease`, and written only
//! when the bytes change (`files`). `check` mode compares instead of writing.
//! The kernel's functions come from `eval`; the per-discretisation data
//! (constants, eps rows, c0 coefficients) from here, as data: eps(t, n) is
//! one generic `shearsph::kernel::eps_at_disc` over them.

mod eval;
mod files;

pub use files::{ensure, own_header_line, Changes};

use crate::analysis::{Analysis, DiscAnalysis};
use crate::c0::DEFAULT_MODEL;
use crate::compaction::{cell_area, Known};
use crate::exact::{decimal, Exact};
use crate::lattice::{max_layer_offset, row_reach, ExactLattice};
use crate::poly::parse_decimal;
use eval::{fused, lanes, piecewise, Which};
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};
use rug::{Float, Rational};
use std::path::PathBuf;

/// The command that writes `generated/`; named in every file's header.
pub const COMMAND: &str = "cargo run -p shearsph-codegen -- generate";

fn header(source: &str) -> String {
    format!("{}\n// Source: {source}\n\n", own_header_line())
}

/// An f64 literal. Every emitted number is finite: a derivation without a
/// value (no c0) is emitted as its absence, never as NaN.
fn lit(x: f64) -> Literal {
    assert!(x.is_finite(), "emitted constants are finite");
    Literal::f64_unsuffixed(x)
}

/// The Rust type name of a kernel: `monaghan` -> `Monaghan`, `my_k2` -> `MyK2`.
pub fn type_name(name: &str) -> String {
    name.split('_')
        .map(|w| {
            let mut c = w.chars();
            match c.next() {
                Some(f) => f.to_ascii_uppercase().to_string() + c.as_str(),
                None => String::new(),
            }
        })
        .collect()
}

fn derived(k: &Known) -> TokenStream {
    let v = lit(k.value.to_f64());
    let (s, exact) = match &k.exact {
        Some(e) => (e.to_string(), true),
        None => (decimal(&k.value, k.digits.unwrap_or(30) as usize), false),
    };
    quote!(Derived { value: #v, exact: #s, is_exact: #exact })
}

fn derived_exact(value: f64, form: String) -> TokenStream {
    let v = lit(value);
    quote!(Derived { value: #v, exact: #form, is_exact: true })
}

/// A high-precision value that has no exact form, with its digits.
fn derived_float(x: &Float, digits: usize) -> TokenStream {
    let v = lit(x.to_f64());
    let s = format!("{} ({digits} significant digits)", decimal(x, digits));
    quote!(Derived { value: #v, exact: #s, is_exact: false })
}

/// One `#[doc]` attribute per line, so prettyplease prints `///` comments.
fn doc(s: &str) -> TokenStream {
    let lines = s.lines().map(|l| quote!(#[doc = #l]));
    quote!(#(#lines)*)
}

/// The c0 models of one discretisation: those with a c0, and the facts of
/// those without.
fn c0_tokens(da: &DiscAnalysis, digits: usize) -> (Vec<TokenStream>, Vec<TokenStream>) {
    let mut models = Vec::new();
    let mut none = Vec::new();
    for m in &da.models {
        let mname = m.model.name;
        let desc = m.model.description;
        let coefs = match &m.coefs {
            Ok(c) => c,
            Err(fact) => {
                none.push(quote!(NoC0 { model: #mname, fact: #fact }));
                continue;
            }
        };
        let [av, bv, cv, sv, pv, qv] = match &m.exact {
            Some(e) => [
                derived_exact(e.a.to_f64(), e.a.to_string()),
                derived_exact(e.b.to_f64(), e.b.to_string()),
                derived_exact(e.c.to_f64(), e.c.to_string()),
                derived_exact(e.s.to_f64(), e.s.to_string()),
                derived_exact(e.p.to_f64(), e.p.to_string()),
                derived_exact(e.q.to_f64(), e.q.to_string()),
            ],
            None => [&coefs.a, &coefs.b, &coefs.c, &coefs.s, &coefs.p, &coefs.q]
                .map(|x| derived_float(x, digits)),
        };
        let t = derived(&m.tau);
        models.push(quote!(C0Model { name: #mname, description: #desc, t: #t, a: #av, b: #bv, c: #cv, s: #sv, p: #pv, q: #qv }));
    }
    (models, none)
}

/// What the generic `eps_at` needs of one discretisation, as data: the
/// lattice, the rows in reach and the particles of each.
fn eps_lattice_tokens(a: &Analysis, da: &DiscAnalysis, lattice: &TokenStream) -> TokenStream {
    let disc = &da.disc;
    let layers = max_layer_offset(disc, &a.def.support) as i32;
    let dy2 = lit(disc.lattice.dy2().to_f64());
    let reach = row_reach(disc, &a.def.support) as i32;
    let inv_h2 = lit((Rational::from(1) / disc.h2()).to_f64());
    let area = lit(cell_area(disc).to_f64());
    quote!(EpsLattice { lattice: #lattice, layers: #layers, dy2: #dy2, reach: #reach, inv_h2: #inv_h2, area: #area })
}

/// One discretisation's `DiscretisationInfo`, entry `index` of the kernel's:
/// data, and the one generic `eps_at_disc` for its eps(t, n).
fn disc_tokens(
    a: &Analysis,
    da: &DiscAnalysis,
    ty: &proc_macro2::Ident,
    index: usize,
) -> TokenStream {
    let disc = &da.disc;
    let variant = format_ident!("{}", disc.lattice.variant_name());
    let lattice = quote!(Lattice::#variant);
    let h = lit(disc.h.to_f64());
    let h_exact = disc.h.to_string();
    let dy = lit(Exact::sqrt_rational(&disc.lattice.dy2()).to_f64());
    let e = &da.eps;
    let [t0, half, max, t_max, min, t_min, mean] = [
        &e.t0,
        &e.half_period,
        &e.max,
        &e.t_max,
        &e.min,
        &e.t_min,
        &e.mean,
    ]
    .map(derived);
    let cc = &da.c0_config;
    let (ct, ce) = (derived(&cc.tau), derived(&cc.eps0));
    let symmetric = cc.symmetric.is_some();
    let label = &cc.label;
    let (models, none) = c0_tokens(da, a.digits);
    let lat = eps_lattice_tokens(a, da, &lattice);
    quote! {
        DiscretisationInfo {
            lattice: #lattice,
            h_over_d: #h,
            h_over_d_exact: #h_exact,
            dy: #dy,
            eps: EpsInfo { t0: #t0, half_period: #half, max: #max, t_max: #t_max, min: #min, t_min: #t_min, mean: #mean },
            c0_configuration: C0Configuration { t: #ct, eps0: #ce, symmetric: #symmetric, label: #label },
            c0_models: &[#(#models),*],
            no_c0: &[#(#none),*],
            eps_lattice: #lat,
            eps_at: eps_at_disc::<#ty, #index>,
        }
    }
}

/// `impl Kernel for Type`: the kernel's functions.
fn kernel_impl(a: &Analysis, ty: &proc_macro2::Ident) -> (TokenStream, u32) {
    let d = &a.def;
    let name = &d.name;
    let support2_closed = lit(Rational::from(&d.support * &d.support).to_f64() * (1.0 + 1e-9));
    let (w_body, _) = piecewise(&d.w, Which::W);
    // the solver evaluates W and (dW/dq)/q of a pair together, in lanes
    let (pair_body, flops) = lanes(&d.w, &d.dw).unwrap_or_else(|| fused(&d.w, &d.dw));
    let pieces = |r: &crate::kernel::Radial| {
        r.pieces
            .iter()
            .map(|p| format!(" - ({}, {}]: {}\n", p.from, p.to, p.poly))
            .collect::<String>()
    };
    let doc_w = doc(&format!(
        " W(q), q^2 = `q2`, units h^-2. Pieces (exact):\n{}",
        pieces(&d.w)
    ));
    let doc_pair = doc(&format!(
        " (W, (dW/dq)/q) of a pair, units h^-2 and h^-4, as the solver's pair loops take it. dW/dq ({}), pieces (exact):\n{}",
        if d.dw_given {
            "given separately"
        } else {
            "derivative of W"
        },
        pieces(&d.dw)
    ));
    let tokens = quote! {
        impl Kernel for #ty {
            const NAME: &'static str = #name;
            const SUPPORT2_CLOSED: f64 = #support2_closed;
            const INFO: &'static KernelInfo = &INFO;

            #doc_w
            #[inline(always)]
            fn w(q2: f64) -> f64 { #w_body }

            #doc_pair
            #[inline(always)]
            fn w_dw_over_q_lanes(q2: f64) -> (f64, f64) { #pair_body }
        }
    };
    (tokens, flops)
}

/// The paper's printed rows, when the kernel has a `[paper]` table.
fn printed_tokens(a: &Analysis) -> (TokenStream, TokenStream) {
    let d = &a.def;
    let printed = match d.paper.as_ref().and_then(|p| p.table2.as_ref()) {
        Some(t) => {
            let f = |s: &str| lit(parse_decimal(s).map(|q| q.to_f64()).unwrap_or(f64::NAN));
            let (e0, fa, s, p, q) = (f(&t.eps0), f(&t.factor), f(&t.s), f(&t.p), f(&t.q));
            quote!(Some(PrintedC0 { eps0: #e0, factor: #fa, s: #s, p: #p, q: #q }))
        }
        None => quote!(None),
    };
    let printed_eps = match d.paper.as_ref() {
        Some(p) => {
            let (t0, h, m) = (&p.table1.t0, &p.table1.half_period, &p.table1.mean);
            quote!(Some(PrintedEps { t0: #t0, half_period: #h, mean: #m }))
        }
        None => quote!(None),
    };
    (printed, printed_eps)
}

/// The module for one kernel.
pub fn kernel_module(a: &Analysis) -> String {
    let d = &a.def;
    let ty = format_ident!("{}", type_name(&d.name));
    let (name, title, reference) = (&d.name, &d.title, &d.reference);
    let support = lit(d.support.to_f64());
    let support_exact = d.support.to_string();
    let (kernel_impl, flops) = kernel_impl(a, &ty);
    let (printed, printed_eps) = printed_tokens(a);
    let infos = a
        .discs
        .iter()
        .enumerate()
        .map(|(i, da)| disc_tokens(a, da, &ty, i));
    let n_discs = a.discs.len();
    let mut uses = vec![
        quote!(eps_at_disc),
        quote!(C0Configuration),
        quote!(C0Model),
        quote!(Derived),
        quote!(DiscretisationInfo),
        quote!(EpsInfo),
        quote!(EpsLattice),
        quote!(Kernel),
        quote!(KernelInfo),
        quote!(Lattice),
    ];
    if a.discs
        .iter()
        .any(|da| da.models.iter().any(|m| m.coefs.is_err()))
    {
        uses.push(quote!(NoC0));
    }
    if d.paper.as_ref().is_some_and(|p| p.table2.is_some()) {
        uses.push(quote!(PrintedC0));
    }
    if d.paper.is_some() {
        uses.push(quote!(PrintedEps));
    }
    let doc_struct = doc(&format!(" {title}.\n\n Reference: {reference}.\n\n Support R = {support_exact} h. Generated from `kernels/{name}.toml`."));
    let default_model = DEFAULT_MODEL;
    let tokens = quote! {
        use crate::kernel::{#(#uses),*};

        #doc_struct
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        pub struct #ty;

        #kernel_impl

        /// The derivation on every discretisation of `kernels/discretisations.toml`, the paper's first.
        pub const DISCRETISATIONS: [DiscretisationInfo; #n_discs] = [#(#infos),*];

        /// Everything the derivation found; see `shearsph-codegen show`. The
        /// top-level fields are the paper's discretisation (triangular, h = d).
        pub const INFO: KernelInfo = KernelInfo {
            name: #name,
            title: #title,
            reference: #reference,
            support: #support,
            support_exact: #support_exact,
            eps: DISCRETISATIONS[0].eps,
            c0_default: #default_model,
            c0_models: DISCRETISATIONS[0].c0_models,
            printed_c0: #printed,
            eps_at: DISCRETISATIONS[0].eps_at,
            printed_eps: #printed_eps,
            discretisations: &DISCRETISATIONS,
            flops_per_pair: #flops,
        };
    };
    format_file(tokens, &format!("kernels/{}.toml", name))
}

fn format_file(tokens: TokenStream, source: &str) -> String {
    let file: syn::File = syn::parse2(tokens).expect("emitted tokens parse as a file");
    header(source) + &prettyplease::unparse(&file)
}

/// The registry of every kernel.
pub fn registry(analyses: &[Analysis]) -> String {
    let mods = analyses.iter().map(|a| {
        let m = format_ident!("{}", a.def.name);
        let file = format!("{}.rs", a.def.name);
        let ty = format_ident!("{}", type_name(&a.def.name));
        let d = doc(&format!(" {}", a.def.title));
        quote! {
            #d
            pub mod #m { include!(#file); }
            pub use #m::#ty;
        }
    });
    let infos = analyses.iter().map(|a| {
        let m = format_ident!("{}", a.def.name);
        quote!(&#m::INFO)
    });
    let arms = analyses.iter().map(|a| {
        let name = &a.def.name;
        let ty = format_ident!("{}", type_name(&a.def.name));
        quote!(#name => Some(visitor.visit::<#ty>()))
    });
    let names = analyses.iter().map(|a| a.def.name.as_str());
    let tokens = quote! {
        use crate::kernel::{KernelInfo, KernelVisitor};

        #(#mods)*

        /// Every kernel, in file-name order.
        pub const KERNELS: &[&KernelInfo] = &[#(#infos),*];

        /// Every kernel's name, in file-name order.
        pub const NAMES: &[&str] = &[#(#names),*];

        /// The kernel called `name`.
        pub fn kernel_info(name: &str) -> Option<&'static KernelInfo> {
            KERNELS.iter().copied().find(|k| k.name == name)
        }

        /// Runs `visitor` with the kernel called `name` as its type parameter.
        pub fn with_kernel<V: KernelVisitor>(name: &str, visitor: V) -> Option<V::Output> {
            match name {
                #(#arms,)*
                _ => None,
            }
        }
    };
    format_file(tokens, "kernels/*.toml")
}

/// Every file of `generated/`, path relative to the output folder.
pub fn render(analyses: &[Analysis]) -> Vec<(PathBuf, String)> {
    let mut out: Vec<(PathBuf, String)> = analyses
        .iter()
        .map(|a| {
            (
                PathBuf::from(format!("{}.rs", a.def.name)),
                kernel_module(a),
            )
        })
        .collect();
    out.push((PathBuf::from("registry.rs"), registry(analyses)));
    out
}
