//! SIGINT and SIGTERM during a run that saves its rows as it goes (a sweep, a shard,
//! a reproduction with a [`crate::report::resume::Journal`]): the signal only raises a
//! flag; the run stops after the row it is computing has been saved, says how far it
//! got and how to continue, and exits with 128 + the signal's number (130 for SIGINT,
//! 143 for SIGTERM), as a shell reports a process the signal ended. The file on disk is
//! then whole (each row is saved by an atomic rename: `report::atomic`).
//!
//! The handlers are installed only once a journal exists ([`arm`]); before that, and in
//! every other command (`render`), the signals keep their default action. A second
//! signal of either kind while the first is waiting for its row ends the process at
//! once, with the same status (the rows saved so far are still whole).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Once;

/// The signal number that asked the run to stop, 0 while none has.
static SIGNAL: AtomicUsize = AtomicUsize::new(0);
/// Raised with the first signal: a second one then ends the process at once.
static RAISED: AtomicBool = AtomicBool::new(false);
static ARM: Once = Once::new();

/// Install the handlers (once per process; later calls do nothing). Failure to
/// install them (not expected on Unix) leaves the default action, which still keeps
/// every saved row whole.
pub fn arm() {
    ARM.call_once(|| {
        use signal_hook::consts::{SIGINT, SIGTERM};
        for sig in [SIGINT, SIGTERM] {
            // The second signal exits at once (the check sees RAISED set by the first);
            // the first only records which signal it was.
            let code = 128 + sig;
            let _ = signal_hook::flag::register_conditional_shutdown(sig, code, &RAISED);
            let _ = signal_hook::flag::register_usize(sig, &SIGNAL, sig as usize);
            let _ = signal_hook::flag::register(sig, &RAISED);
        }
    });
}

/// The signal that asked to stop, if one has.
pub fn requested() -> Option<i32> {
    match SIGNAL.load(Ordering::SeqCst) {
        0 => None,
        s => Some(s as i32),
    }
}

/// The exit status for a run stopped by signal `sig`: 128 + its number.
pub fn exit_status(sig: i32) -> i32 {
    128 + sig
}

/// The message printed when a run stops after `done` of `total` rows saved in `file`.
pub fn message(done: usize, total: usize, file: &std::path::Path) -> String {
    format!(
        "interrupted after {done} of {total} rows; rerun the same command with --resume to continue\n\
         (the rows are saved in {})",
        file.display()
    )
}

/// Called after a row has been saved: if a signal asked to stop, print
/// [`message`] on stderr and exit with [`exit_status`].
pub fn stop_if_requested(done: usize, total: usize, file: &std::path::Path) {
    if let Some(sig) = requested() {
        eprintln!("\n{}", message(done, total, file));
        std::process::exit(exit_status(sig));
    }
}

/// After the last row, in the work a run does once its rows are saved (its range
/// warnings): if a signal asked to stop, exit with [`exit_status`] at once; every row
/// is already on file, so the message is not needed and `--resume` has nothing left.
pub fn exit_if_requested() {
    if let Some(sig) = requested() {
        std::process::exit(exit_status(sig));
    }
}
