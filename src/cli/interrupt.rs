//! Ctrl-C for every command that runs scenes: a stop flag the first press
//! sets, a second press that quits at once, and the exit status they give.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use anyhow::{Context, Result};

/// Exit status of a command stopped by Ctrl-C (SIGINT) after keeping what it
/// had (a sweep its finished rows, a run its outputs so far): 128 + 2, what
/// a shell reports for a process that SIGINT ended.
pub const EXIT_INTERRUPTED: u8 = 130;

/// A stop flag set by Ctrl-C (SIGINT): the first press stops cleanly, a
/// second quits at once (rows already written are kept either way).
pub fn stop_on_ctrl_c() -> Result<Arc<AtomicBool>> {
    stop_on_ctrl_c_saying("stopping the running scenes; finished rows are kept")
}

/// [`stop_on_ctrl_c`] for any command: the first press prints
/// `interrupted: {what} (Ctrl-C again quits at once)`. One per process.
pub fn stop_on_ctrl_c_saying(what: &'static str) -> Result<Arc<AtomicBool>> {
    let stop = Arc::new(AtomicBool::new(false));
    let flag = stop.clone();
    ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            eprintln!("\ninterrupted again: quitting now");
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
        eprintln!("\ninterrupted: {what} (Ctrl-C again quits at once)");
    })
    .context("installing the Ctrl-C handler")?;
    Ok(stop)
}
