//! Kernel names and shapes that used to panic, break the
//! generated tree or pass without a word. Each class has its own message.

use shearsph_codegen::analysis::{analyse, Options};
use shearsph_codegen::kernel::{
    check_emitted_names, load_dir, parse_kernel, read_kernel_file, shape_facts, KernelError,
    RESERVED_NAMES, RUST_KEYWORDS,
};
use shearsph_codegen::lattice::Discretisation;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A valid kernel (Monaghan's cubic spline) under any name.
fn cubic(name: &str) -> String {
    format!(
        "name = \"{name}\"\nreference = \"test\"\nsupport = 2\nscale = \"10/(7*pi)\"\n\
         [[w]]\nto = 1\nexpr = \"1 - 3/2*q^2 + 3/4*q^3\"\n\
         [[w]]\nto = 2\nexpr = \"(2 - q)^3/4\"\n"
    )
}

fn parse(name: &str) -> Result<shearsph_codegen::kernel::KernelDef, KernelError> {
    parse_kernel(Path::new("kernels/k.toml"), &cubic(name))
}

#[test]
fn every_rust_keyword_is_refused_as_a_name() {
    for kw in [
        "fn", "self", "type", "crate", "async", "super", "gen", "try", "dyn", "yield", "union",
    ] {
        assert!(RUST_KEYWORDS.contains(&kw), "{kw} in the list");
    }
    for kw in RUST_KEYWORDS {
        if !kw.starts_with(|c: char| c.is_ascii_lowercase()) {
            continue;
        }
        let e = parse(kw).expect_err(kw);
        assert_eq!(e.field, "name", "{e}");
        assert!(e.message.contains("is a Rust keyword"), "{kw}: {e}");
        assert!(e.fix.contains(&format!("{kw}_kernel")), "{kw}: {e}");
        assert!(e.to_string().starts_with("kernels/k.toml:1:"), "{e}");
    }
    // a keyword inside a longer name is fine
    parse("fn_cubic").expect("fn_cubic is not a keyword");
    parse("selfish").expect("selfish is not a keyword");
}

#[test]
fn names_of_the_generated_tree_are_refused() {
    for n in RESERVED_NAMES.iter().filter(|n| !RUST_KEYWORDS.contains(n)) {
        let e = parse(n).expect_err(n);
        assert_eq!(e.field, "name");
        assert!(
            e.message.contains("module or file of the generated tree"),
            "{e}"
        );
    }
    for bad in ["Monaghan", "1k", "k-2", "", "_k", "r#fn", "k\u{e9}"] {
        let e = parse(bad).expect_err(bad);
        assert!(e.message.contains("not a valid kernel name"), "{bad}: {e}");
    }
}

fn write_dir(files: &[(&str, String)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (f, src) in files {
        std::fs::write(dir.path().join(f), src).unwrap();
    }
    dir
}

#[test]
fn two_names_with_one_type_name_are_refused() {
    for (a, b) in [("k_2", "k2"), ("my_k", "my__k"), ("ab_c", "ab__c")] {
        let dir = write_dir(&[
            (&format!("{a}.toml"), cubic(a)),
            (&format!("{b}.toml"), cubic(b)),
        ]);
        let e = load_dir(dir.path()).expect_err("one type name");
        assert_eq!(e.field, "name");
        assert!(e.message.contains("gives the Rust type name"), "{e}");
        assert!(e.message.contains(a) && e.message.contains(b), "{e}");
    }
}

fn codegen() -> Command {
    Command::new(env!("CARGO_BIN_EXE_shearsph-codegen"))
}

/// `generate` over one kernel with `name`: its stderr, and whether it failed.
fn generate(name: &str) -> (bool, String, tempfile::TempDir) {
    let dir = write_dir(&[(&format!("{name}.toml"), cubic(name))]);
    let out = dir.path().join("out");
    let o = codegen()
        .arg("--kernels")
        .arg(dir.path())
        .arg("generate")
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        dir,
    )
}

#[test]
fn names_the_generated_code_uses_are_refused_before_anything_is_written() {
    // an import (KernelInfo), a prelude type the module uses (Option), the
    // registry's generic parameter (V), a registry function's parameter (visitor)
    for name in ["kernel_info", "option", "v", "visitor", "c0_model"] {
        let (ok, err, dir) = generate(name);
        assert!(!ok, "{name} accepted: {err}");
        assert!(err.contains("field `name`"), "{name}: {err}");
        assert!(
            err.contains("already used by the generated code"),
            "{name}: {err}"
        );
        assert!(err.contains(&format!("{name}.toml")), "{name}: {err}");
        assert!(!dir.path().join("out").exists(), "nothing written");
    }
    let (ok, err, _dir) = generate("cubic");
    assert!(ok, "an ordinary name is accepted: {err}");
}

#[test]
fn a_name_equal_to_another_output_file_is_refused() {
    let def = parse("extra").unwrap();
    let files = vec![
        (PathBuf::from("extra.rs"), "pub struct Extra;".to_string()),
        (PathBuf::from("registry.rs"), String::new()),
    ];
    // a generator that also writes `extra.rs` for some other purpose
    let neutral = vec![
        (
            PathBuf::from("zz_neutral_kernel_0.rs"),
            "pub struct ZzNeutralKernel0;".to_string(),
        ),
        (PathBuf::from("extra.rs"), String::new()),
        (PathBuf::from("registry.rs"), String::new()),
    ];
    let e = check_emitted_names(std::slice::from_ref(&def), &files, &neutral).unwrap_err();
    assert!(
        e.message
            .contains("name of a file the generator writes (extra.rs)"),
        "{e}"
    );
    let twice = vec![files[0].clone(), files[0].clone()];
    let e = check_emitted_names(&[def], &twice, &neutral[..1]).unwrap_err();
    assert!(e.message.contains("would write extra.rs twice"), "{e}");
}

#[test]
fn deep_nesting_is_an_error_with_file_line_and_field() {
    let deep = [
        format!("{}q{}", "(".repeat(10_000), ")".repeat(10_000)),
        format!("{}q", "-".repeat(10_000)),
        format!("{}q", "+-".repeat(5_000)),
        format!("{}4{}", "sqrt(".repeat(10_000), ")".repeat(10_000)),
    ];
    for expr in deep {
        let src = format!(
            "name = \"k\"\nreference = \"r\"\nsupport = 2\n[[w]]\nto = 2\nexpr = \"{expr}\"\n"
        );
        let e = parse_kernel(Path::new("kernels/k.toml"), &src).unwrap_err();
        assert_eq!(e.field, "w[0].expr", "{e}");
        assert_eq!(e.at.unwrap().0, 6, "line: {e}");
        assert!(e.message.contains("nested more than 100 levels"), "{e}");
        assert!(
            e.message.len() < 300,
            "the formula is not quoted whole: {e}"
        );
    }
    // shallow nesting still parses
    let ok = format!("{}q{}", "(".repeat(90), ")".repeat(90));
    shearsph_codegen::poly::parse_poly(&ok).expect("90 levels");
}

#[test]
fn each_read_failure_has_its_own_message() {
    let dir = tempfile::tempdir().unwrap();
    // not UTF-8, on line 2
    let f = dir.path().join("latin1.toml");
    std::fs::write(&f, b"name = \"k\"\ntitle = \"Gau\xdf\"\n").unwrap();
    let e = read_kernel_file(&f).unwrap_err();
    assert!(e.message.contains("is not UTF-8"), "{e}");
    assert!(e.message.contains("byte offset 23"), "{e}");
    assert!(e.message.contains("0xdf"), "{e}");
    assert_eq!(e.at, Some((2, 13)), "{e}");
    assert!(e.fix.contains("UTF-8"), "{e}");
    assert!(!e.fix.contains("permission"), "{e}");
    // a folder named like a definition
    let d = dir.path().join("folder.toml");
    std::fs::create_dir(&d).unwrap();
    let e = read_kernel_file(&d).unwrap_err();
    assert!(e.message.contains("is a folder"), "{e}");
    // missing, and a broken link as load_dir meets it
    let e = read_kernel_file(&dir.path().join("gone.toml")).unwrap_err();
    assert!(e.message.contains("does not exist"), "{e}");
    // through load_dir, the first bad file (sorted) is reported
    let e = load_dir(dir.path()).unwrap_err();
    assert!(e.message.contains("is a folder"), "{e}");
    std::fs::remove_dir(&d).unwrap();
    let e = load_dir(dir.path()).unwrap_err();
    assert!(e.message.contains("is not UTF-8"), "{e}");
    std::fs::remove_file(&f).unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::os::unix::fs::symlink(dir.path().join("nowhere"), dir.path().join("link.toml"))
            .unwrap();
        let e = load_dir(dir.path()).unwrap_err();
        assert!(
            e.message
                .contains("does not exist (or is a broken symbolic link)"),
            "{e}"
        );
        std::fs::remove_file(dir.path().join("link.toml")).unwrap();
        let p = dir.path().join("locked.toml");
        std::fs::write(&p, cubic("locked")).unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o000)).unwrap();
        if std::fs::read(&p).is_err() {
            let e = read_kernel_file(&p).unwrap_err();
            assert!(e.message.contains("permission denied"), "{e}");
            assert!(e.fix.contains("chmod"), "{e}");
        } else {
            eprintln!(
                "running as root: a mode-000 file is still readable; permission case not reachable"
            );
        }
    }
}

fn fact<'a>(
    facts: &'a [shearsph_codegen::analysis::Fact],
    name: &str,
) -> &'a shearsph_codegen::analysis::Fact {
    facts.iter().find(|f| f.name == name).unwrap()
}

fn kernel(support: &str, scale: &str, expr: &str) -> shearsph_codegen::kernel::KernelDef {
    let src = format!(
        "name = \"k\"\nreference = \"r\"\nsupport = {support}\nscale = \"{scale}\"\n[[w]]\nto = {support}\nexpr = \"{expr}\"\n"
    );
    parse_kernel(Path::new("k.toml"), &src).expect("valid")
}

#[test]
fn negative_w_is_located_exactly_or_to_1e_12() {
    // 12/pi (1 - q^2)(1/2 - q^2): normalised, negative for q in (1/sqrt 2, 1)
    let def = kernel("1", "12/pi", "(1 - q^2)*(1/2 - q^2)");
    let f = shape_facts(&def);
    let neg = fact(&f, "W >= 0 on [0, R]");
    assert!(!neg.holds);
    assert!(
        neg.detail.contains("W < 0 for q in (0.707106781187, 1)"),
        "{}",
        neg.detail
    );
    assert!(fact(&f, "gradient vanishes at the origin").holds);
    // -24/pi (1 - q^2)(1/4 - q^2): negative on (0, 1/2), the root exact
    let def = kernel("1", "-24/pi", "(1 - q^2)*(1/4 - q^2)");
    let neg = shape_facts(&def).remove(0);
    assert!(
        neg.detail.contains("W < 0 for q in (0, 1/2)"),
        "{}",
        neg.detail
    );
    assert!(neg.detail.contains("exact"), "{}", neg.detail);
}

#[test]
fn a_cusp_at_the_origin_is_reported() {
    // the cone 3/pi (1 - q): W'(0) = -3/pi
    let def = kernel("1", "3/pi", "1 - q");
    let f = shape_facts(&def);
    let cusp = fact(&f, "gradient vanishes at the origin");
    assert!(!cusp.holds);
    assert!(cusp.detail.contains("W'(0) = -3/pi"), "{}", cusp.detail);
    assert!(fact(&f, "W >= 0 on [0, R]").holds);
}

#[test]
fn shipped_kernels_are_nonnegative_and_smooth_at_the_origin() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../kernels");
    let defs = load_dir(&dir).unwrap();
    for d in &defs {
        let f = shape_facts(d);
        assert!(fact(&f, "W >= 0 on [0, R]").holds, "{}: {:?}", d.name, f);
        // the facts reach the analysis (and so `show`)
        let a = analyse(
            d,
            &[Discretisation::paper()],
            Options {
                digits: 10,
                check_layers: 6,
            },
        );
        assert!(a.facts.iter().any(|x| x.name == "W >= 0 on [0, R]"));
        let origin = fact(&a.facts, "gradient vanishes at the origin");
        eprintln!("{}: {}", d.name, origin.detail);
    }
}

/// `generate` into a folder too small for its files fails, leaves no
/// temporary file (`.NAME.PID-N.tmp`), and changes nothing that was there. Needs a tiny tmpfs
/// (root in a container that may mount); says so and returns otherwise.
#[test]
fn generate_on_a_full_disk_leaves_no_temporary_files() {
    let mnt = tempfile::tempdir().unwrap();
    let ok = Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=8k", "tmpfs"])
        .arg(mnt.path())
        .status()
        .is_ok_and(|s| s.success());
    if !ok {
        eprintln!("cannot mount a tiny tmpfs here (not root?): full-disk case not run");
        return;
    }
    let kernels = Path::new(env!("CARGO_MANIFEST_DIR")).join("../kernels");
    let o = codegen()
        .arg("--kernels")
        .arg(&kernels)
        .arg("generate")
        .arg("--out")
        .arg(mnt.path())
        .output()
        .unwrap();
    let left: Vec<String> = std::fs::read_dir(mnt.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let _ = Command::new("umount").arg(mnt.path()).status();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "a full disk is an error: {err}");
    assert!(err.contains("No space left on device"), "{err}");
    assert!(
        left.iter().all(|f| !f.ends_with(".tmp")),
        "temporary files left: {left:?}"
    );
}
