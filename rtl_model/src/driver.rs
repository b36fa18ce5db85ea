//! Three drivers over the same arithmetic.
//!
//! * [`run_tick`] clocks the unit's pipeline registers one cycle at a time: inputs are
//!   accepted every II clocks, results travel through `latency` stage registers, and
//!   cycles and stalls are counted as they happen (and can be traced to VCD).
//! * [`run_span`] runs the kernel over a whole span in a tight loop and adds the same
//!   counters arithmetically from [`crate::unit::Timing`].
//! * [`run_batch`] (the batch path) feeds the span to [`Unit::kernel_batch`] a chunk at
//!   a time and adds the span's timing counters once, through a [`SpanTally`]: a
//!   pipeline that chains units chunk by chunk keeps one tally per unit and logical
//!   span, so its counters equal one `run_span` over the whole span.
//!
//! Tests prove all three give identical outputs, final states and counters.

use crate::counters::Counters;
use crate::trace::VcdTrace;
use crate::unit::Unit;
use std::collections::VecDeque;
use std::io::Write;

/// Run `inputs` through `unit` a span at a time; counters added arithmetically.
pub fn run_span<U: Unit>(
    unit: &U,
    state: &mut U::State,
    inputs: &[U::In],
    ctr: &mut Counters,
) -> Vec<U::Out> {
    let mut out = Vec::with_capacity(inputs.len());
    for x in inputs {
        out.push(unit.kernel(state, x, ctr));
    }
    add_span_counters(unit.timing(), inputs.len() as u64, ctr);
    out
}

/// The counters a span of `n` inputs adds by the unit's timing: pixels in and out,
/// (n − 1)·II + latency + 1 cycles and (n − 1)·(II − 1) stalls.
pub fn add_span_counters(t: crate::unit::Timing, n: u64, ctr: &mut Counters) {
    ctr.pixels_in += n;
    ctr.pixels_out += n;
    ctr.cycles += t.span_cycles(n);
    ctr.stalls += t.span_stalls(n);
}

/// The length of one logical span fed to a unit in chunks. Cycles of a span are not a
/// sum over its chunks ((n − 1)·II + latency + 1 is affine in n), so a chunked driver
/// counts inputs here and adds the span's timing once, at [`SpanTally::close`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SpanTally {
    n: u64,
}

impl SpanTally {
    /// An empty span: no inputs counted yet.
    pub fn new() -> Self {
        SpanTally { n: 0 }
    }

    /// `n` more inputs of this span went through the unit.
    #[inline]
    pub fn add(&mut self, n: usize) {
        self.n += n as u64;
    }

    /// Inputs counted so far.
    pub fn len(&self) -> u64 {
        self.n
    }

    /// True when no input has been counted for this span yet.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// End the span: add its timing counters (as [`run_span`] does for one call).
    pub fn close(self, t: crate::unit::Timing, ctr: &mut Counters) {
        add_span_counters(t, self.n, ctr);
    }
}

/// The batch path over one span: [`Unit::kernel_batch`] on chunks of at most `chunk`
/// inputs (≥ 1), outputs in order, the span's timing counters added once. Same
/// outputs, state and counters as [`run_span`] for every chunk size.
pub fn run_batch<U: Unit>(
    unit: &U,
    state: &mut U::State,
    inputs: &[U::In],
    chunk: usize,
    ctr: &mut Counters,
) -> Vec<U::Out> {
    let mut out = Vec::with_capacity(inputs.len());
    let mut tally = SpanTally::new();
    for c in inputs.chunks(chunk.max(1)) {
        unit.kernel_batch(state, c, &mut out, ctr);
        tally.add(c.len());
    }
    tally.close(unit.timing(), ctr);
    out
}

/// Run `inputs` through `unit` one clock at a time; optionally trace every clock.
pub fn run_tick<U: Unit, W: Write>(
    unit: &U,
    state: &mut U::State,
    inputs: &[U::In],
    ctr: &mut Counters,
    mut trace: Option<&mut VcdTrace<W>>,
) -> std::io::Result<Vec<U::Out>> {
    let t = unit.timing();
    let latency = t.latency.max(1) as usize;
    let ii = t.ii.max(1) as u64;
    // Stage registers: index 0 is the first stage, the back is the output register.
    let mut pipe: VecDeque<Option<U::Out>> = VecDeque::from(vec![None; latency]);
    let mut out = Vec::with_capacity(inputs.len());
    let mut next = 0usize;
    let mut next_accept: u64 = 0;
    let mut cycle: u64 = 0;
    loop {
        // The output register presents what was accepted `latency` clocks ago.
        let presented = pipe.back().cloned().flatten();
        let accept = next < inputs.len() && cycle >= next_accept;
        let stalled = next < inputs.len() && !accept;
        if let Some(tr) = trace.as_deref_mut() {
            let in_sig = if accept {
                unit.in_signals(&inputs[next])
            } else {
                Vec::new()
            };
            let out_sig = presented
                .as_ref()
                .map(|o| unit.out_signals(o))
                .unwrap_or_default();
            let valid: Vec<bool> = pipe.iter().map(Option::is_some).collect();
            tr.clock(
                cycle,
                accept,
                stalled,
                &in_sig,
                &valid,
                presented.is_some(),
                &out_sig,
            )?;
        }
        if let Some(o) = presented {
            out.push(o);
            ctr.pixels_out += 1;
        }
        pipe.pop_back();
        if accept {
            let o = unit.kernel(state, &inputs[next], ctr);
            pipe.push_front(Some(o));
            ctr.pixels_in += 1;
            next += 1;
            next_accept = cycle + ii;
        } else {
            pipe.push_front(None);
            if stalled {
                ctr.stalls += 1;
            }
        }
        cycle += 1;
        if next == inputs.len() && pipe.iter().all(Option::is_none) {
            if inputs.is_empty() {
                cycle = 0;
            } else if let Some(tr) = trace.as_deref_mut() {
                // Show the drained pipeline on one last clock.
                let valid = vec![false; latency];
                tr.clock(cycle, false, false, &[], &valid, false, &[])?;
            }
            break;
        }
    }
    // Clocks 0 ..= the one presenting the last output (matches Timing::span_cycles).
    ctr.cycles += cycle;
    Ok(out)
}
