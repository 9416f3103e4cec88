//! Signals for every command: one handler for SIGINT (Ctrl-C), SIGTERM and
//! SIGHUP, installed before any work ([`install`], from `main`), and one
//! behaviour and exit status for all of them.
//!
//! - While a command has nothing to keep (parsing, checking its input, a
//!   `c0` table or bisection, a bench, whose figures are printed at the
//!   end), a signal ends it at once with exit status 130.
//! - Once it has something to keep (a run's outputs, a sweep's rows, the
//!   law's points, the report's files), the command asks for a stop flag
//!   ([`stop_flag`]): the first signal sets it and the command stops at its
//!   next step, writes what it computed and exits 130. A second signal (or
//!   any later one: `timeout` delivers its signal twice, to the process and
//!   to its group) never quits before that is written: it only says so.
//!
//! 130 is 128 + SIGINT, what a shell reports for a process Ctrl-C ended;
//! SIGTERM and SIGHUP give the same status, so a script tells an
//! interrupted command from a failed one by one code.

use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::sync::{Mutex, OnceLock};

use anyhow::{Context, Result};

/// Exit status of a command stopped by a signal (SIGINT, SIGTERM, SIGHUP),
/// whatever it kept: 128 + 2, what a shell reports for a process SIGINT
/// ended.
pub const EXIT_INTERRUPTED: u8 = 130;

/// Nothing to keep yet: a signal quits at once.
const QUIT: u8 = 0;
/// Something to keep: a signal sets the stop flag.
const STOP: u8 = 1;

struct State {
    mode: AtomicU8,
    /// The process-wide stop every run watches ([`crate::run::stop_all`]).
    stop: &'static AtomicBool,
    /// What the first signal says in stop mode.
    what: Mutex<&'static str>,
}

fn state() -> &'static State {
    static STATE: OnceLock<State> = OnceLock::new();
    STATE.get_or_init(|| State {
        mode: AtomicU8::new(QUIT),
        stop: crate::run::stop_all(),
        what: Mutex::new("stopping"),
    })
}

/// What a signal does now (run on the handler's thread).
fn on_signal() {
    let s = state();
    if s.mode.load(Ordering::SeqCst) == QUIT {
        eprintln!("\ninterrupted: nothing was kept (exit {EXIT_INTERRUPTED})");
        std::process::exit(i32::from(EXIT_INTERRUPTED));
    }
    if s.stop.swap(true, Ordering::SeqCst) {
        eprintln!(
            "\ninterrupted again: already stopping; what was computed is being written first"
        );
    } else {
        let what = *s.what.lock().unwrap_or_else(|e| e.into_inner());
        eprintln!("\ninterrupted: {what}");
    }
}

/// Install the one handler of the process (once; later calls do nothing).
/// Until a command asks for [`stop_flag`], a signal quits at once with
/// [`EXIT_INTERRUPTED`].
pub fn install() -> Result<()> {
    static INSTALLED: OnceLock<std::result::Result<(), String>> = OnceLock::new();
    INSTALLED
        .get_or_init(|| {
            state();
            ctrlc::set_handler(on_signal).map_err(|e| e.to_string())
        })
        .clone()
        .map_err(anyhow::Error::msg)
        .context("installing the signal handler (SIGINT, SIGTERM, SIGHUP)")
}

/// From now on a signal stops the command cleanly: it sets the returned
/// flag, the process-wide [`crate::run::stop_all`] that every run watches
/// (the first signal prints `interrupted: {what}`), and the command keeps
/// what it computed; no later signal quits before that is written.
pub fn stop_flag(what: &'static str) -> Result<&'static AtomicBool> {
    install()?;
    let s = state();
    *s.what.lock().unwrap_or_else(|e| e.into_inner()) = what;
    s.mode.store(STOP, Ordering::SeqCst);
    Ok(s.stop)
}

/// [`stop_flag`] for a command that runs scenes: finished rows are kept.
pub fn stop_on_ctrl_c() -> Result<&'static AtomicBool> {
    stop_flag("stopping the running scenes; finished rows are kept")
}
