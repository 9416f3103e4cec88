//! Guards on a kernel's name: not a Rust keyword, not a name the generated
//! tree already uses, and no collision with anything the generator emits.

use super::{KernelDef, KernelError};
use std::path::{Path, PathBuf};

/// Every Rust keyword, strict, reserved and edition-dependent (2015 to 2024):
/// a kernel's name becomes a module and, capitalised, a type, so none of
/// these can be one (`self`, `super`, `crate` and `Self` cannot even be raw
/// identifiers, so `r#name` is no way out).
pub const RUST_KEYWORDS: &[&str] = &[
    // strict
    "as",
    "break",
    "const",
    "continue",
    "crate",
    "else",
    "enum",
    "extern",
    "false",
    "fn",
    "for",
    "if",
    "impl",
    "in",
    "let",
    "loop",
    "match",
    "mod",
    "move",
    "mut",
    "pub",
    "ref",
    "return",
    "self",
    "static",
    "struct",
    "super",
    "trait",
    "true",
    "type",
    "unsafe",
    "use",
    "where",
    "while",
    "async",
    "await",
    "dyn",
    // reserved
    "abstract",
    "become",
    "box",
    "do",
    "final",
    "macro",
    "override",
    "priv",
    "typeof",
    "unsized",
    "virtual",
    "yield",
    "try",
    "gen",
    // weak, kept out so that the module name never reads as syntax
    "union",
    "raw",
    "safe",
    "macro_rules",
];

/// Names the generated tree or the crates that include it already use for
/// a module or file: a kernel with one of these names would shadow or
/// include it (a kernel `registry` makes `registry.rs` include itself).
/// Names of further output files are checked against the rendered tree by
/// [`check_emitted_names`].
pub const RESERVED_NAMES: &[&str] = &["registry", "kernel", "kernels", "mod", "lib", "main"];

/// Why a kernel name cannot be used, or `None` when it can.
pub fn name_problem(name: &str) -> Option<(String, String)> {
    let valid_name = name.chars().next().is_some_and(|c| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    if !valid_name {
        return Some((
            format!("`{name}` is not a valid kernel name"),
            "use lowercase letters, digits and _, starting with a letter (it names a Rust module)"
                .into(),
        ));
    }
    if RUST_KEYWORDS.contains(&name) {
        return Some((
            format!("`{name}` is a Rust keyword, and a kernel's name becomes a Rust module"),
            format!("choose another name, e.g. `{name}_kernel`"),
        ));
    }
    if RESERVED_NAMES.contains(&name) {
        return Some((
            format!(
                "`{name}` is the name of a module or file of the generated tree or of the crate that includes it ({})",
                RESERVED_NAMES.join(", ")
            ),
            format!("choose another name, e.g. `{name}_kernel`"),
        ));
    }
    None
}

/// The identifiers in Rust source (doc strings and literals excluded).
pub fn identifiers(src: &str) -> std::collections::BTreeSet<String> {
    fn walk(ts: proc_macro2::TokenStream, out: &mut std::collections::BTreeSet<String>) {
        for t in ts {
            match t {
                proc_macro2::TokenTree::Ident(i) => {
                    out.insert(i.to_string());
                }
                proc_macro2::TokenTree::Group(g) => walk(g.stream(), out),
                _ => {}
            }
        }
    }
    let mut out = std::collections::BTreeSet::new();
    if let Ok(ts) = src.parse::<proc_macro2::TokenStream>() {
        walk(ts, &mut out);
    }
    out
}

/// The stand-in name of kernel `i` in the neutral rendering that
/// [`check_emitted_names`] compares with.
pub fn neutral_name(i: usize) -> String {
    format!("{NEUTRAL_PREFIX}{i}")
}

const NEUTRAL_PREFIX: &str = "zz_neutral_kernel_";

/// Checks that no kernel's module name, type name or file collides with
/// anything else the generator writes. `files` is the rendered tree;
/// `neutral` is the same tree rendered with kernel `i` renamed to
/// [`neutral_name`]`(i)`: every identifier and file stem in it belongs to the
/// generator itself (imports, prelude names, functions, generic
/// parameters, further output files), so a kernel named like one of them
/// would shadow it. This holds for whatever files and items a future
/// generator adds, without a list to keep in step.
pub fn check_emitted_names(
    defs: &[KernelDef],
    files: &[(PathBuf, String)],
    neutral: &[(PathBuf, String)],
) -> Result<(), KernelError> {
    let name_err = |d: &KernelDef, message: String| KernelError {
        file: d.file.clone(),
        field: "name".into(),
        at: None,
        message,
        fix: format!(
            "choose another name, e.g. `{}_kernel`, and rename the file to match",
            d.name
        ),
    };
    let mut seen: std::collections::BTreeMap<&Path, usize> = Default::default();
    for (p, _) in files {
        *seen.entry(p.as_path()).or_default() += 1;
    }
    if let Some((p, _)) = seen.iter().find(|(_, n)| **n > 1) {
        let owner = defs
            .iter()
            .find(|d| {
                p.file_stem()
                    .and_then(|s| s.to_str())
                    .is_some_and(|s| s == d.name)
            })
            .unwrap_or(&defs[0]);
        return Err(name_err(
            owner,
            format!(
                "the generator would write {} twice: two kernels' outputs share a file name",
                p.display()
            ),
        ));
    }
    // a kernel's own files are included inside its module, so its module name
    // can only collide in the shared files (the registry); its type name
    // enters every file of its own
    let mut idents = std::collections::BTreeSet::new();
    let mut shared_idents = std::collections::BTreeSet::new();
    let mut stems = std::collections::BTreeSet::new();
    for (p, src) in neutral {
        let stem = p.file_stem().and_then(|s| s.to_str()).unwrap_or("");
        let ids = identifiers(src);
        if !stem.starts_with(NEUTRAL_PREFIX) {
            shared_idents.extend(ids.iter().cloned());
        }
        idents.extend(ids);
        stems.insert(stem.to_string());
    }
    for d in defs {
        if stems.contains(&d.name) {
            return Err(name_err(
                d,
                format!(
                    "`{}` is the name of a file the generator writes ({}.rs): the kernel's module would collide with it",
                    d.name, d.name
                ),
            ));
        }
        let ty = crate::emit::type_name(&d.name);
        for (what, id, used) in [("module", &d.name, &shared_idents), ("type", &ty, &idents)] {
            if used.contains(id) {
                return Err(name_err(
                    d,
                    format!(
                        "the kernel's {what} name `{id}` is already used by the generated code (an import, a prelude name, a function or a parameter), which it would shadow"
                    ),
                ));
            }
        }
    }
    Ok(())
}
