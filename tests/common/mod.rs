//! Helpers shared by the unit tests.
#![allow(dead_code)]

pub mod cosim;
pub mod docs;
pub mod icarus;
pub mod shafts;
pub mod tools;

use rtl_model::cost::Cost;
use rtl_model::driver::{run_batch, run_span, run_tick};
use rtl_model::trace::VcdTrace;
use rtl_model::{Counters, Signal, Unit};

/// A cost's named part, in NAND2 equivalents (None when the cost has no such part).
pub fn cost_part(cost: &Cost, name: &str) -> Option<f64> {
    cost.breakdown
        .iter()
        .find(|(n, _)| n == name)
        .map(|&(_, g)| g)
}

/// A trace's wires as (name, width, value), for comparing with a list.
pub fn wires(signals: &[Signal]) -> Vec<(&'static str, u32, u64)> {
    signals.iter().map(|s| (s.name, s.width, s.value)).collect()
}

/// Proptest case count: ≥ 1 000 by default, more with PROPTEST_CASES.
pub fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1000)
        .max(1000)
}

/// Chunk sizes the batch path is checked at: one word, odd sizes that split runs and
/// tables at awkward places, and the whole span in one chunk.
pub const BATCH_CHUNKS: [usize; 4] = [1, 3, 7, usize::MAX];

/// Run `inputs` through the span driver, the batch path (at every chunk size of
/// [`BATCH_CHUNKS`]), the tick driver and the traced tick driver from the same start
/// state; assert identical outputs, final states and counters, and that the cycle
/// count matches the unit's timing. Returns the outputs.
pub fn assert_drivers_agree<U: Unit>(unit: &U, state: U::State, inputs: &[U::In]) -> Vec<U::Out> {
    let mut s_span = state.clone();
    let mut c_span = Counters::default();
    let out_span = run_span(unit, &mut s_span, inputs, &mut c_span);

    assert_batch_agrees(unit, &state, inputs, &out_span, &s_span, &c_span);

    let mut s_tick = state.clone();
    let mut c_tick = Counters::default();
    let out_tick = run_tick::<U, Vec<u8>>(unit, &mut s_tick, inputs, &mut c_tick, None).unwrap();
    assert_eq!(out_tick, out_span, "{}: outputs differ", unit.name());
    assert_eq!(s_tick, s_span, "{}: final states differ", unit.name());
    assert_eq!(c_tick, c_span, "{}: counters differ", unit.name());
    assert_eq!(
        c_tick.cycles,
        unit.timing().span_cycles(inputs.len() as u64),
        "{}: tick cycles differ from timing",
        unit.name()
    );
    assert_eq!(
        c_tick.stalls,
        unit.timing().span_stalls(inputs.len() as u64)
    );

    if let (Some(first), Some(out0)) = (inputs.first(), out_span.first()) {
        let mut buf: Vec<u8> = Vec::new();
        let mut tr = VcdTrace::new(
            &mut buf,
            unit.name(),
            unit.timing().latency,
            &unit.in_signals(first),
            &unit.out_signals(out0),
        )
        .unwrap();
        let mut s_tr = state;
        let mut c_tr = Counters::default();
        let out_tr = run_tick(unit, &mut s_tr, inputs, &mut c_tr, Some(&mut tr)).unwrap();
        tr.finish().unwrap();
        assert_eq!(out_tr, out_span, "{}: traced outputs differ", unit.name());
        assert_eq!(c_tr, c_span, "{}: traced counters differ", unit.name());
        let text = String::from_utf8(buf).unwrap();
        assert!(text.contains("$enddefinitions"), "VCD header missing");
    }
    out_span
}

/// The batch path ([`run_batch`]) at every chunk size of [`BATCH_CHUNKS`] from `state`
/// gives `out`, `end` and `ctr` (what the span driver gave).
pub fn assert_batch_agrees<U: Unit>(
    unit: &U,
    state: &U::State,
    inputs: &[U::In],
    out: &[U::Out],
    end: &U::State,
    ctr: &Counters,
) {
    for chunk in BATCH_CHUNKS {
        let mut s = state.clone();
        let mut c = Counters::default();
        let o = run_batch(unit, &mut s, inputs, chunk, &mut c);
        assert_eq!(
            o,
            out,
            "{}: batch outputs differ (chunk {chunk})",
            unit.name()
        );
        assert_eq!(
            &s,
            end,
            "{}: batch final state differs (chunk {chunk})",
            unit.name()
        );
        assert_eq!(
            &c,
            ctr,
            "{}: batch counters differ (chunk {chunk})",
            unit.name()
        );
    }
}

/// A scratch directory under the system temp dir, named for this test process and
/// `name`, emptied on creation and removed when dropped (so test runs leave nothing
/// behind in /tmp). It derefs to the path and passes as a command argument.
pub struct Scratch(std::path::PathBuf);

impl Scratch {
    pub fn new(prefix: &str, name: &str) -> Self {
        let d = std::env::temp_dir().join(format!("{prefix}-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        Scratch(d)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

impl std::ops::Deref for Scratch {
    type Target = std::path::Path;
    fn deref(&self) -> &std::path::Path {
        &self.0
    }
}

impl AsRef<std::path::Path> for Scratch {
    fn as_ref(&self) -> &std::path::Path {
        &self.0
    }
}

impl AsRef<std::ffi::OsStr> for Scratch {
    fn as_ref(&self) -> &std::ffi::OsStr {
        self.0.as_os_str()
    }
}

/// The CSV's lines split into fields, the `wall_seconds` column dropped (the only one
/// two runs of a sweep differ in).
pub fn without_wall(csv: &std::path::Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(csv).unwrap_or_else(|e| panic!("{}: {e}", csv.display()));
    let lines: Vec<&str> = text.lines().collect();
    let wall = lines[0]
        .split(',')
        .position(|c| c == "wall_seconds")
        .expect("a wall_seconds column");
    lines
        .iter()
        .map(|l| {
            l.split(',')
                .enumerate()
                .filter(|(i, _)| *i != wall)
                .map(|(_, f)| f.to_string())
                .collect()
        })
        .collect()
}

/// Start `cmd`, wait (up to 300 s) until `ready()` while the child still runs, then
/// send it `kill -SIGNAL`; returns its output, which must not be a success. Fails if
/// the run ends before it could be cut (`what` names what `ready` waits for).
pub fn cut_when(
    mut cmd: std::process::Command,
    ready: impl Fn() -> bool,
    what: &str,
    signal: &str,
) -> std::process::Output {
    use std::time::{Duration, Instant};
    let mut child = cmd.spawn().unwrap();
    let t0 = Instant::now();
    loop {
        if let Some(st) = child.try_wait().unwrap() {
            panic!("the run ended ({st:?}) before it could be cut: no {what} yet");
        }
        if ready() {
            break;
        }
        assert!(
            t0.elapsed() < Duration::from_secs(300),
            "no {what} after 300 s"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    let st = std::process::Command::new("kill")
        .arg(format!("-{signal}"))
        .arg(child.id().to_string())
        .status()
        .unwrap();
    assert!(st.success(), "kill -{signal} failed");
    let o = child.wait_with_output().unwrap();
    assert!(!o.status.success(), "the cut run still exited 0");
    o
}

/// A built-in shafts scene at a test size: 64 × 48, 3 planes, 2 sub-planes, 64² shadow
/// maps (fast enough for every test that draws a whole frame).
pub fn small_shafts_scene(name: &str) -> glare_pipeline::scene::format::Scene {
    let mut s = glare_pipeline::scene::builtin::builtin(name).unwrap();
    s.image.width = 64;
    s.image.height = 48;
    s.shafts.planes = 3;
    s.shafts.subplanes = 2;
    s.shafts.shadow_resolution = 64;
    s
}
