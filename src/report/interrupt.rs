//! SIGINT and SIGTERM during a run that saves its rows as it goes (a sweep, a shard,
//! a reproduction with a [`crate::report::resume::Journal`]): the signal only raises a
//! flag; the run stops after the row it is computing has been saved, says how far it
//! got and how to continue, and exits with 128 + the signal's number (130 for SIGINT,
//! 143 for SIGTERM), as a shell reports a process the signal ended. The file on disk is
//! then whole (each row is saved by an atomic rename: `report::atomic`).
//!
//! The handlers are installed only once a journal exists ([`arm`]); before that, and in
//! every other command (`render`), the signals keep their default action. A second
//! signal of either kind while the first is waiting for its row ends the process
//! without waiting for the row, with the same status and the same "rerun with
//! --resume" line, counting the rows saved so far (which are whole): each save
//! records its line with [`saved`], and a watcher thread prints the last one.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, Once};

/// The signal number that asked the run to stop, 0 while none has.
static SIGNAL: AtomicUsize = AtomicUsize::new(0);
/// Signals received so far (SIGINT and SIGTERM together).
static COUNT: AtomicUsize = AtomicUsize::new(0);
static ARM: Once = Once::new();
/// The line to print if the run ends now: what is saved and how to continue
/// (None before the first save).
static SAVED: Mutex<Option<String>> = Mutex::new(None);
/// Held by whoever prints the last line and exits, so that it is printed once.
static EXITING: Mutex<()> = Mutex::new(());

/// How often the watcher looks for a second signal.
const WATCH: std::time::Duration = std::time::Duration::from_millis(20);

/// Install the handlers (once per process; later calls do nothing). Failure to
/// install them (not expected on Unix) leaves the default action, which still keeps
/// every saved row whole.
pub fn arm() {
    ARM.call_once(|| {
        use signal_hook::consts::{SIGINT, SIGTERM};
        for sig in [SIGINT, SIGTERM] {
            // SAFETY: the handler only stores to and adds to atomics, which is
            // async-signal-safe; it allocates nothing and takes no lock.
            let _ = unsafe {
                signal_hook::low_level::register(sig, move || {
                    SIGNAL.store(sig as usize, Ordering::SeqCst);
                    COUNT.fetch_add(1, Ordering::SeqCst);
                })
            };
        }
        // The second signal: print the saved line and exit, without waiting for the
        // row being computed.
        let _ = std::thread::Builder::new()
            .name("second-signal".into())
            .spawn(|| loop {
                std::thread::sleep(WATCH);
                if COUNT.load(Ordering::SeqCst) >= 2 {
                    let sig = requested().unwrap_or(signal_hook::consts::SIGINT);
                    let line = SAVED.lock().map(|s| s.clone()).unwrap_or(None);
                    exit_with(sig, line.as_deref());
                }
            });
    });
}

/// Record the line a run stopped now prints: called after each save of a run that
/// can resume (a message such as [`message`]'s).
pub fn saved(line: String) {
    if let Ok(mut s) = SAVED.lock() {
        *s = Some(line);
    }
}

/// Print `line` (if any) on stderr and exit with [`exit_status`], once per process.
pub fn exit_with(sig: i32, line: Option<&str>) -> ! {
    let _once = EXITING.lock();
    if let Some(l) = line {
        eprintln!("\n{l}");
    }
    std::process::exit(exit_status(sig));
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
    let line = message(done, total, file);
    if let Some(sig) = requested() {
        exit_with(sig, Some(&line));
    }
    saved(line);
}

/// After the last row, in the work a run does once its rows are saved (its range
/// warnings): if a signal asked to stop, exit with [`exit_status`] at once; every row
/// is already on file, so the message is not needed and `--resume` has nothing left.
pub fn exit_if_requested() {
    if let Some(sig) = requested() {
        exit_with(sig, None);
    }
}
