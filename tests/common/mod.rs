//! What the integration tests share: the binary under test and its output
//! as text. tests/integration.rs declares it, and each test file that
//! needs it takes it with `use crate::common;`.
#![allow(dead_code)]

use std::process::{Command, Output};

/// The `shearsph` binary of this build, to be given arguments.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_shearsph"))
}

/// `shearsph ARGS`, run to its end.
pub fn shearsph(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub mod brute;
