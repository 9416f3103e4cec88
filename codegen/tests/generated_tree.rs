//! generated/ is what the generator writes now; a kernel added to kernels/
//! appears in the registry and its module compiles; one bad kernel changes
//! nothing.

use shearsph_codegen::analysis::{analyse, Options};
use shearsph_codegen::kernel::load_dir;
use shearsph_codegen::{discretisation, emit};
use std::path::{Path, PathBuf};
use std::process::Command;

/// `src` compiled by rustc (`RUSTC`, else the one on the path) as the
/// 2021-edition library `name` into `out`, with `extra` arguments first.
fn rustc_lib(name: &str, src: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    Command::new(rustc)
        .args(extra)
        .args([
            "--edition",
            "2021",
            "--crate-type",
            "lib",
            "--crate-name",
            name,
            "-o",
        ])
        .arg(out)
        .arg(src)
        .output()
        .unwrap()
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn render(kernels: &Path) -> Vec<(PathBuf, String)> {
    let defs = load_dir(kernels).unwrap();
    let discs = discretisation::load(kernels).unwrap();
    let analyses: Vec<_> = defs
        .iter()
        .map(|d| analyse(d, &discs, Options::default()))
        .collect();
    emit::render(&analyses)
}

#[test]
fn generated_tree_is_fresh() {
    let files = render(&root().join("kernels"));
    let changes = emit::ensure(&root().join("generated"), &files, true).unwrap();
    let stale = changes.stale();
    assert!(
        changes.is_empty(),
        "stale generated files {stale:?}: run `{}` and commit",
        emit::COMMAND
    );
}

#[test]
fn generation_is_deterministic() {
    let a = render(&root().join("kernels"));
    let b = render(&root().join("kernels"));
    assert_eq!(a, b);
}

/// A kernel without a `[paper]` table (Wendland C2 under another name).
const EXTRA: &str = r#"
name = "extra_c2"
title = "Wendland C2 (2D), as a user would add it"
reference = "Wendland 1995; 2D normalisation 7/(4 pi) for support 2h"
support = 2
scale = "7/(4*pi)"
[[w]]
to = 2
expr = "(1 - q/2)^4 * (1 + 2*q)"
"#;

fn codegen_bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_shearsph-codegen"))
}

#[test]
fn added_kernel_appears_in_the_registry_and_compiles() {
    let tmp = tempfile::tempdir().unwrap();
    let kernels = tmp.path().join("kernels");
    std::fs::create_dir(&kernels).unwrap();
    for f in std::fs::read_dir(root().join("kernels")).unwrap() {
        let f = f.unwrap().path();
        std::fs::copy(&f, kernels.join(f.file_name().unwrap())).unwrap();
    }
    std::fs::write(kernels.join("extra_c2.toml"), EXTRA).unwrap();
    let out = tmp.path().join("generated");
    let st = codegen_bin()
        .args([
            "--kernels",
            kernels.to_str().unwrap(),
            "generate",
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let registry = std::fs::read_to_string(out.join("registry.rs")).unwrap();
    assert!(registry.contains("pub mod extra_c2"), "{registry}");
    assert!(registry.contains("\"extra_c2\" => Some(visitor.visit::<ExtraC2>())"));
    let module = std::fs::read_to_string(out.join("extra_c2.rs")).unwrap();
    syn::parse_file(&module).expect("parses");
    // compile it for real, with the solver's Kernel trait, as a library;
    // kernel.rs names the lattice kinds of `shearsph-lattice`, compiled
    // first (it depends on nothing; its serde impls stay out)
    let lattice_rlib = tmp.path().join("libshearsph_lattice.rlib");
    let st = rustc_lib(
        "shearsph_lattice",
        &root().join("lattice/src/lib.rs"),
        &lattice_rlib,
        &[],
    );
    assert!(
        st.status.success(),
        "the lattice crate compiles alone:\n{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let lib = tmp.path().join("lib.rs");
    std::fs::write(
        &lib,
        format!(
            "#[path = {:?}] pub mod kernel;\n#[allow(clippy::all)] pub mod kernels {{ include!({:?}); }}\n\
             pub fn w() -> f64 {{ use kernel::Kernel; kernels::ExtraC2::w(1.0) }}\n",
            root().join("src/model/kernel.rs"),
            out.join("registry.rs")
        ),
    )
    .unwrap();
    let extern_lattice = format!("shearsph_lattice={}", lattice_rlib.display());
    // no warning at all: a module without a paper row imports nothing it does not use
    let st = rustc_lib(
        "gen_check",
        &lib,
        &tmp.path().join("libgen_check.rlib"),
        &["--extern", &extern_lattice, "-D", "warnings"],
    );
    assert!(
        st.status.success(),
        "the emitted code compiles:\n{}",
        String::from_utf8_lossy(&st.stderr)
    );
}

#[test]
fn check_fails_after_a_kernel_is_edited_and_bad_kernels_change_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let kernels = tmp.path().join("kernels");
    std::fs::create_dir(&kernels).unwrap();
    std::fs::copy(
        root().join("kernels/monaghan.toml"),
        kernels.join("monaghan.toml"),
    )
    .unwrap();
    let out = tmp.path().join("generated");
    let run = |args: &[&str]| {
        codegen_bin()
            .args(["--kernels", kernels.to_str().unwrap()])
            .args(args)
            .args(["--out", out.to_str().unwrap()])
            .output()
            .unwrap()
    };
    assert!(run(&["generate"]).status.success());
    assert!(run(&["check"]).status.success());
    // edit: a different title changes the emitted docs
    let src = std::fs::read_to_string(kernels.join("monaghan.toml")).unwrap();
    std::fs::write(
        kernels.join("monaghan.toml"),
        src.replace("Monaghan cubic spline (R = 2)", "Cubic"),
    )
    .unwrap();
    let st = run(&["check"]);
    assert!(!st.status.success());
    let msg = String::from_utf8_lossy(&st.stderr);
    assert!(
        msg.contains("monaghan.rs") && msg.contains("generate"),
        "{msg}"
    );
    // a bad kernel beside it: generate fails and writes nothing
    let before = std::fs::read_to_string(out.join("monaghan.rs")).unwrap();
    std::fs::write(
        kernels.join("zz_bad.toml"),
        "name = \"zz\"\nreference = \"x\"\nsupport = 1\n[[w]]\nto = 1\nexpr = \"1 - q\"\n",
    )
    .unwrap();
    let st = run(&["generate"]);
    assert!(!st.status.success());
    assert!(String::from_utf8_lossy(&st.stderr).contains("zz_bad.toml"));
    assert_eq!(
        std::fs::read_to_string(out.join("monaghan.rs")).unwrap(),
        before
    );
    assert!(!out.join("zz.rs").exists());
}

/// `generate --out DIR` into a folder of the user's own
/// files removes none of them, overwrites none of them, and says so; a file
/// it generated earlier for a kernel since deleted is removed, and named as
/// removed, not as written.
#[test]
fn generate_never_removes_or_overwrites_files_it_did_not_write() {
    let tmp = tempfile::tempdir().unwrap();
    let kernels = tmp.path().join("kernels");
    std::fs::create_dir(&kernels).unwrap();
    for k in ["monaghan", "composite"] {
        std::fs::copy(
            root().join(format!("kernels/{k}.toml")),
            kernels.join(format!("{k}.toml")),
        )
        .unwrap();
    }
    let out = tmp.path().join("src");
    std::fs::create_dir(&out).unwrap();
    let user_files = [
        ("lib.rs", "pub mod a;\n"),
        ("main.rs", "fn main() {}\n"),
        // mentions the header, but not as its first line
        (
            "notes.rs",
            "// see `cargo run -p shearsph-codegen -- generate`\n",
        ),
        ("README.md", "mine\n"),
    ];
    for (f, body) in user_files {
        std::fs::write(out.join(f), body).unwrap();
    }
    let run = |args: &[&str]| {
        codegen_bin()
            .args(["--kernels", kernels.to_str().unwrap()])
            .args(args)
            .args(["--out", out.to_str().unwrap()])
            .output()
            .unwrap()
    };
    let st = run(&["generate"]);
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let log = String::from_utf8_lossy(&st.stderr).to_string();
    for (f, body) in user_files {
        assert_eq!(std::fs::read_to_string(out.join(f)).unwrap(), body, "{f}");
        if f.ends_with(".rs") {
            assert!(
                log.contains(&format!("left {} alone", out.join(f).display())),
                "{log}"
            );
            assert!(!log.contains(&format!("wrote {}", out.join(f).display())));
        }
    }
    assert!(out.join("monaghan.rs").exists() && out.join("registry.rs").exists());

    // delete a kernel: its generated module is removed, and logged as removed
    std::fs::remove_file(kernels.join("composite.toml")).unwrap();
    let st = run(&["generate"]);
    assert!(st.status.success());
    let log = String::from_utf8_lossy(&st.stderr).to_string();
    assert!(!out.join("composite.rs").exists());
    let composite = out.join("composite.rs").display().to_string();
    assert!(log.contains(&format!("removed {composite}")), "{log}");
    assert!(!log.contains(&format!("wrote {composite}")), "{log}");
    for (f, body) in user_files {
        assert_eq!(std::fs::read_to_string(out.join(f)).unwrap(), body, "{f}");
    }

    // a hand-written file where a generated one would go is not overwritten
    std::fs::write(out.join("monaghan.rs"), "// mine\n").unwrap();
    let st = run(&["generate"]);
    assert!(!st.status.success());
    let msg = String::from_utf8_lossy(&st.stderr).to_string();
    assert!(
        msg.contains("monaghan.rs") && msg.contains("refusing to overwrite"),
        "{msg}"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("monaghan.rs")).unwrap(),
        "// mine\n"
    );
    // and check reports the same folder as stale without touching it
    let st = run(&["check"]);
    assert!(!st.status.success());
    assert_eq!(
        std::fs::read_to_string(out.join("lib.rs")).unwrap(),
        "pub mod a;\n"
    );
}
