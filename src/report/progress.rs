//! Progress bars on stderr for long sweeps, silent in CI and in pipes.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;

/// Whether a bar should be hidden, given the value of the `CI` environment variable
/// and whether stderr is a terminal. Hidden unless stderr is a terminal, and hidden
/// whenever `CI` is set to anything but "", "0" or "false" (any case): GitHub Actions,
/// GitLab and most CI services set `CI=true`.
pub fn should_hide(ci: Option<&str>, stderr_is_terminal: bool) -> bool {
    let ci = ci.is_some_and(|v| {
        let v = v.trim();
        !(v.is_empty() || v == "0" || v.eq_ignore_ascii_case("false"))
    });
    ci || !stderr_is_terminal
}

/// A bar of `len` steps labelled `what`, drawn on stderr; hidden (but still counting,
/// so `position()` works) when [`should_hide`] says so for this process.
pub fn progress_bar(len: u64, what: &str) -> ProgressBar {
    let ci = std::env::var("CI").ok();
    if should_hide(ci.as_deref(), std::io::stderr().is_terminal()) {
        return ProgressBar::hidden().with_message(what.to_string());
    }
    let style = ProgressStyle::with_template(
        "{msg:>12} [{bar:40.cyan/blue}] {pos}/{len} {elapsed_precise} (eta {eta})",
    )
    .map(|s| s.progress_chars("=> "))
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    ProgressBar::new(len)
        .with_style(style)
        .with_message(what.to_string())
}

/// `f` applied to each item in order, with a bar advancing once per item; the bar is
/// cleared at the end. Results are in item order.
pub fn map_with_progress<T, R>(items: &[T], what: &str, mut f: impl FnMut(&T) -> R) -> Vec<R> {
    let bar = progress_bar(items.len() as u64, what);
    let out = items
        .iter()
        .map(|it| {
            let r = f(it);
            bar.inc(1);
            r
        })
        .collect();
    bar.finish_and_clear();
    out
}

/// As [`map_with_progress`], stopping at the first error (the bar is abandoned where it
/// stopped, so the step that failed stays visible on a terminal).
pub fn try_map_with_progress<T, R, E>(
    items: &[T],
    what: &str,
    mut f: impl FnMut(&T) -> Result<R, E>,
) -> Result<Vec<R>, E> {
    let bar = progress_bar(items.len() as u64, what);
    let mut out = Vec::with_capacity(items.len());
    for it in items {
        match f(it) {
            Ok(r) => out.push(r),
            Err(e) => {
                bar.abandon();
                return Err(e);
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(out)
}

thread_local! {
    /// The bar of the frame this thread is rendering (`render`), if one is installed.
    static FRAME_BAR: std::cell::RefCell<Option<ProgressBar>> = const { std::cell::RefCell::new(None) };
}

/// Whether `render` shows its frame's bar for `work` (its sample-plane fragments),
/// given `GLARE_PROGRESS`: `always` shows it whatever the work, `never` hides it,
/// anything else (or unset) shows it above [`FRAME_BAR_WORK`]. On a terminal outside
/// CI only ([`should_hide`] still applies).
pub fn frame_bar_wanted(work: f64, setting: Option<&str>) -> bool {
    match setting.map(str::trim) {
        Some(s) if s.eq_ignore_ascii_case("always") => true,
        Some(s) if s.eq_ignore_ascii_case("never") => false,
        _ => work > FRAME_BAR_WORK,
    }
}

/// Sample-plane fragments above which `render` draws a bar (a few seconds of frame).
pub const FRAME_BAR_WORK: f64 = 2e8;

/// A frame's bar, installed for this thread while it lives: the frame's passes call
/// [`frame_step`] (a sample plane, a pass), and the bar is cleared when it is dropped.
pub struct FrameProgress {
    bar: ProgressBar,
}

impl FrameProgress {
    /// Install a bar of `len` steps for this thread's frame; drawn (per
    /// [`progress_bar`]'s rules) when `shown`, else hidden but counting.
    pub fn install(len: u64, what: &str, shown: bool) -> FrameProgress {
        let bar = if shown {
            progress_bar(len, what)
        } else {
            ProgressBar::hidden().with_message(what.to_string())
        };
        bar.set_length(len);
        FRAME_BAR.with(|b| *b.borrow_mut() = Some(bar.clone()));
        FrameProgress { bar }
    }

    /// Steps done so far.
    pub fn position(&self) -> u64 {
        self.bar.position()
    }

    /// Steps in all.
    pub fn length(&self) -> u64 {
        self.bar.length().unwrap_or(0)
    }
}

impl Drop for FrameProgress {
    fn drop(&mut self) {
        FRAME_BAR.with(|b| *b.borrow_mut() = None);
        self.bar.finish_and_clear();
    }
}

/// Advance this thread's frame bar by `n` steps (nothing when none is installed).
/// Called once per sample plane or pass, never per fragment.
pub fn frame_step(n: u64) {
    FRAME_BAR.with(|b| {
        if let Some(bar) = b.borrow().as_ref() {
            bar.inc(n);
        }
    });
}
