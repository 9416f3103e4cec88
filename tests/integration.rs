//! The shearsph crate's integration tests, one test binary: each file of
//! tests/ is a module of it. One binary is compiled and linked once
//! (seventeen, each linking the library, took about 30 s of a 2-core
//! machine's wall from scratch), and its tests are scheduled together
//! over the cores rather than binary after binary.

mod common;

mod bench;
mod bounds_and_signals;
mod cfl_time_step;
mod classes;
mod cli;
mod cli_kernels;
mod empirical;
mod generated_kernels;
mod input_guards;
mod particles_vtk;
mod report;
mod solver;
mod stability;
mod sweep;
mod sweep_axes;
mod viscous_normalisation;
mod viscous_time_step;

/// Every test file of tests/ is a module here: with `autotests = false`
/// cargo builds no other test binary, so a file left out would never run.
#[test]
fn every_test_file_is_a_module_here() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let here = std::fs::read_to_string(dir.join("integration.rs")).unwrap();
    let mut files = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            !path.join("main.rs").exists(),
            "tests/{name}/main.rs would be a test binary of its own, which cargo no longer \
             builds: make it a module of tests/integration.rs"
        );
        if let Some(stem) = name.strip_suffix(".rs") {
            if stem != "integration" {
                files += 1;
                assert!(
                    here.contains(&format!("\nmod {stem};\n")),
                    "tests/{name} is not a module of tests/integration.rs: add `mod {stem};` \
                     there, or its tests never run"
                );
            }
        }
    }
    assert!(files > 0, "no test files found in {}", dir.display());
}
