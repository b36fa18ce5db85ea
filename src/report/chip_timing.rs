//! The clocked chip's outputs, over a frame's [`FrameTiming`]: the text tables
//! `render` prints, the `timing` object of `render --json`, the utilisation timeline
//! as a PNG and a CSV, and the chip-level signals of a window of clocks as a VCD.
//! docs/throughput.md ("The clocked chip") tells a reader what each column and field
//! means.
//!
//! Clocks in every file are the frame's: a pass starts where the one before it ended
//! (the frame runs its passes one after the other), so pass `i` starts at the sum of
//! the cycles of passes `0 .. i` ([`pass_starts`]). A pass's own records (its
//! [`Timeline`] and [`WindowTrace`]) count clocks from the pass's start; they are moved
//! to the frame's clocks here.
//!
//! A number not measured is shown as `n/a` (text) or `null` (JSON), never as 0: the
//! texture-cache hit rate of a pass that looked nothing up, a rate over a pass of zero
//! cycles, a ratio to a roofline of zero seconds.

use crate::chip::clock::{FrameTiming, NamedPassTiming, PassTiming, Timeline, WindowTrace};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;
use std::io::Write;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The clocks `--vcd-window` traces when it is not given: the frame's first 2 000.
pub const DEFAULT_VCD_WINDOW: Range<u64> = 0..2_000;

/// The longest window `--vcd-window` accepts, in clocks. Every clock of the window
/// holds the chip's signals in memory and becomes lines of the VCD; a million clocks
/// is already some hundreds of megabytes of text.
pub const MAX_VCD_WINDOW_CLOCKS: u64 = 1_000_000;

/// Where each pass starts, in clocks from the frame's start.
pub fn pass_starts(ft: &FrameTiming) -> Vec<u64> {
    let mut at = 0u64;
    ft.passes
        .iter()
        .map(|p| {
            let s = at;
            at = at.saturating_add(p.timing.cycles);
            s
        })
        .collect()
}

/// The part of a frame's window (clocks from the frame's start) that falls in a pass
/// starting at `pass_start`, in clocks from the pass's start (what `clock_pass` takes);
/// `None` when the window ends before the pass starts. The pass's end is the clock's
/// to apply (it knows the pass's length only once it has clocked it).
pub fn pass_window(frame_window: &Range<u64>, pass_start: u64) -> Option<Range<u64>> {
    (frame_window.end > pass_start && frame_window.start < frame_window.end)
        .then(|| frame_window.start.saturating_sub(pass_start)..frame_window.end - pass_start)
}

/// Parse `--vcd-window START..END`: clocks from the frame's start, START < END, at
/// most [`MAX_VCD_WINDOW_CLOCKS`] of them. Errors name the flag.
pub fn parse_vcd_window(s: &str) -> Result<Range<u64>, String> {
    let bad = |why: &str| {
        format!(
            "--vcd-window: `{s}`: {why}; give START..END in clocks from the frame's start \
             (e.g. 0..2000)"
        )
    };
    let (a, b) = s
        .trim()
        .split_once("..")
        .ok_or_else(|| bad("no `..` between START and END"))?;
    let num = |t: &str, what: &str| {
        t.trim()
            .parse::<u64>()
            .map_err(|_| bad(&format!("{what} `{t}` is not a whole number of clocks")))
    };
    let (start, end) = (num(a, "START")?, num(b, "END")?);
    if end <= start {
        return Err(bad("END must be greater than START"));
    }
    if end - start > MAX_VCD_WINDOW_CLOCKS {
        return Err(bad(&format!(
            "the window is {} clocks; at most {MAX_VCD_WINDOW_CLOCKS} are traced",
            end - start
        )));
    }
    Ok(start..end)
}

/// The files the clocked chip writes beside `render --out X.png`: `X.timeline.png`,
/// `X.timeline.csv` and `X.vcd`, and the window of clocks the VCD traces.
#[derive(Clone, Debug, PartialEq)]
pub struct ChipFiles {
    pub timeline_png: PathBuf,
    pub timeline_csv: PathBuf,
    pub vcd: PathBuf,
    /// Clocks from the frame's start ([`DEFAULT_VCD_WINDOW`] unless `--vcd-window`).
    pub vcd_window: Range<u64>,
}

impl ChipFiles {
    /// The files beside `out` (a `.png` path; the extension is replaced).
    pub fn beside(out: &Path, vcd_window: Range<u64>) -> Self {
        let with = |ext: &str| out.with_extension(ext);
        ChipFiles {
            timeline_png: with("timeline.png"),
            timeline_csv: with("timeline.csv"),
            vcd: with("vcd"),
            vcd_window,
        }
    }

    /// `render`'s check, before any work: `--vcd-window` parsed (it needs clocked or
    /// sampled timing: `clocked`), and with clocked timing the files beside `out`
    /// named. `None` when the frame is not clocked.
    pub fn for_render(
        out: &Path,
        vcd_window: Option<&str>,
        clocked: bool,
    ) -> Result<Option<Self>, String> {
        let window = vcd_window.map(parse_vcd_window).transpose()?;
        if !clocked {
            return match window {
                Some(_) => Err(
                    "--vcd-window: the VCD traces the clocked chip; ask for it with \
                     --timing clocked (or sampled)"
                        .into(),
                ),
                None => Ok(None),
            };
        }
        Ok(Some(Self::beside(
            out,
            window.unwrap_or(DEFAULT_VCD_WINDOW),
        )))
    }

    /// The paths in the order [`Self::write`] writes them.
    pub fn paths(&self) -> [&Path; 3] {
        [&self.timeline_png, &self.timeline_csv, &self.vcd]
    }

    /// Write the timeline PNG and CSV and, when a pass traced the window, the VCD.
    /// Returns a line per file for the report (a VCD not written says why).
    pub fn write(&self, ft: &FrameTiming) -> Result<Vec<String>, String> {
        let mut notes = Vec::new();
        if ft.cycles_total() == 0 {
            // Every pass kept to the roofline (or none clocked a clock): nothing to draw.
            notes.push(format!(
                "no timeline or VCD: no pass of the frame was clocked ({} passes, 0 clocks)",
                ft.passes.len()
            ));
            return Ok(notes);
        }
        write_timeline_png(ft, &self.timeline_png)?;
        notes.push(format!(
            "wrote {} (stage utilisation over the frame's clocks)",
            self.timeline_png.display()
        ));
        let rows = write_timeline_csv(ft, &self.timeline_csv)?;
        notes.push(format!(
            "wrote {} ({rows} rows: clock range, pass, stage, busy fraction)",
            self.timeline_csv.display()
        ));
        let w = &self.vcd_window;
        if ft.passes.iter().any(|p| p.timing.window.is_some()) {
            write_vcd(ft, &self.vcd)?;
            notes.push(format!(
                "wrote {} (the chip's signals over clocks {}..{} of the frame)",
                self.vcd.display(),
                w.start,
                w.end.min(ft.cycles_total())
            ));
        } else {
            notes.push(format!(
                "no VCD: no pass traced clocks {}..{} (the frame has {} clocks)",
                w.start,
                w.end,
                ft.cycles_total()
            ));
        }
        Ok(notes)
    }
}

// ---------------------------------------------------------------------------------
// Numbers as text and JSON.

/// `part / whole`, `None` when `whole` is 0 or either is not finite.
fn ratio(part: f64, whole: f64) -> Option<f64> {
    let r = part / whole;
    (whole != 0.0 && r.is_finite()).then_some(r)
}

/// Seconds of `cycles` clocks at `clock_hz` (None for a clock that is not a positive
/// finite number).
fn seconds(cycles: u64, clock_hz: f64) -> Option<f64> {
    (clock_hz.is_finite() && clock_hz > 0.0).then(|| cycles as f64 / clock_hz)
}

/// A finite number, else None.
fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

fn or_na(v: Option<f64>, f: impl Fn(f64) -> String) -> String {
    v.map_or_else(|| "n/a".to_string(), f)
}

/// A clock rate for a reader: "200 MHz", "1.5 GHz".
fn show_clock(hz: f64) -> String {
    if !(hz.is_finite() && hz > 0.0) {
        return format!("{hz} Hz (not a clock)");
    }
    let (v, unit) = if hz >= 1e9 {
        (hz / 1e9, "GHz")
    } else if hz >= 1e6 {
        (hz / 1e6, "MHz")
    } else if hz >= 1e3 {
        (hz / 1e3, "kHz")
    } else {
        (hz, "Hz")
    };
    format!("{} {unit}", crate::report::plot::format_tick(v))
}

/// A clock period for a reader: "5 ns", "8.333 ns".
fn show_period(hz: f64) -> String {
    if !(hz.is_finite() && hz > 0.0) {
        return "n/a".into();
    }
    show_duration(1.0 / hz)
}

/// A duration for a reader: "0.5 ms", "5 ns".
fn show_duration(s: f64) -> String {
    let (v, unit) = if s >= 1.0 {
        (s, "s")
    } else if s >= 1e-3 {
        (s * 1e3, "ms")
    } else if s >= 1e-6 {
        (s * 1e6, "µs")
    } else if s >= 1e-9 {
        (s * 1e9, "ns")
    } else {
        (s * 1e12, "ps")
    };
    format!("{} {unit}", crate::report::plot::format_tick(v))
}

/// Achieved bandwidth of `bytes` over a pass: bytes per second, None over zero cycles.
fn bytes_per_second(bytes: u64, p: &PassTiming, clock_hz: f64) -> Option<f64> {
    seconds(p.cycles, clock_hz).and_then(|s| ratio(bytes as f64, s))
}

/// One stage's clocks as fractions of the pass's cycles (None over zero cycles).
fn utilisation(busy: u64, stalled: u64, starved: u64, cycles: u64) -> Option<[f64; 3]> {
    (cycles > 0).then(|| {
        let c = cycles as f64;
        [busy as f64 / c, stalled as f64 / c, starved as f64 / c]
    })
}

// ---------------------------------------------------------------------------------
// The text tables.

/// Columns right-aligned (numbers) or left-aligned (names), two spaces apart, a rule
/// under the header.
fn aligned(header: &[&str], right: &[bool], rows: &[Vec<String>]) -> String {
    let mut w: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for r in rows {
        for (i, c) in r.iter().enumerate().take(w.len()) {
            w[i] = w[i].max(c.chars().count());
        }
    }
    let line = |cells: &[String]| {
        let mut s = String::new();
        for (i, c) in cells.iter().enumerate() {
            if i > 0 {
                s.push_str("  ");
            }
            let pad = " ".repeat(w[i].saturating_sub(c.chars().count()));
            if right.get(i).copied().unwrap_or(false) {
                s.push_str(&pad);
                s.push_str(c);
            } else {
                s.push_str(c);
                s.push_str(&pad);
            }
        }
        s.trim_end().to_string() + "\n"
    };
    let head: Vec<String> = header.iter().map(|h| h.to_string()).collect();
    let mut out = line(&head);
    out.push_str(&line(&w.iter().map(|&n| "-".repeat(n)).collect::<Vec<_>>()));
    for r in rows {
        out.push_str(&line(r));
    }
    out
}

/// The widest a table line may be.
pub const MAX_TABLE_COLUMNS: usize = 100;

/// `name` cut to `max` characters with an ellipsis.
fn cut(name: &str, max: usize) -> String {
    if name.chars().count() <= max {
        name.to_string()
    } else {
        let mut s: String = name.chars().take(max.saturating_sub(1)).collect();
        s.push('…');
        s
    }
}

/// A 20-character bar of one stage's clocks: `#` busy, `=` stalled, `.` starved.
fn bar(u: [f64; 3]) -> String {
    const N: usize = 20;
    let b = (u[0] * N as f64).round() as usize;
    let s = ((u[0] + u[1]) * N as f64).round() as usize;
    let (b, s) = (b.min(N), s.clamp(b.min(N), N));
    format!(
        "{}{}{}",
        "#".repeat(b),
        "=".repeat(s - b),
        ".".repeat(N - s)
    )
}

/// A count of bytes in MB (10⁶ bytes) with three decimals.
fn megabytes(b: u64) -> String {
    format!("{:.3}", b as f64 / 1e6)
}

/// The clocked timing as text: the chip and mode; per pass its cycles, clocked and
/// roofline milliseconds and their ratio; per pass its hardware passes, texture-cache
/// hit rate, achieved bandwidth and bottleneck; each stage's busy / stalled / starved
/// share; the bytes and achieved bandwidth of each memory client; each FIFO's high
/// water. Lines are at most [`MAX_TABLE_COLUMNS`] wide (long pass names are cut in
/// the first table; the others refer to passes by their number).
pub fn print_table(ft: &FrameTiming) -> String {
    let hz = ft.clock_hz;
    let error = or_na(ft.sampling_error, |e| format!("{:.2} %", e * 100.0));
    let mode = match ft.mode.as_str() {
        "sampled" if ft.sample_band_every == Some(1) => format!(
            "sampled: the frame has too few screen bands to sample (under 64 rows): every\n\
             pass and band clocked\n\
             sampling error: frame cycles ± {error}"
        ),
        "sampled" => format!(
            "sampled: of each kind of pass, the first two and one in {} clocked, each on one\n\
             full-width band of 8 rows in {}; the other passes and bands scaled from them\n\
             sampling error: frame cycles ± {} (one standard error of the spread between\n\
             the sampled bands and passes; the sample's bias is not in it)",
            or_na(ft.sample_pass_every.map(f64::from), |k| k.to_string()),
            or_na(ft.sample_band_every.map(f64::from), |k| k.to_string()),
            error
        ),
        "clocked" => "clocked: every fragment clocked".to_string(),
        other => other.to_string(),
    };
    let mut out = format!(
        "clocked chip: {} at {} (1 clock = {})\nmode: {mode}\n",
        ft.chip,
        show_clock(hz),
        show_period(hz)
    );
    if ft.passes.is_empty() {
        out.push_str("no pass was clocked\n");
        return out;
    }
    let roofline_total: f64 = ft.passes.iter().map(|p| p.roofline_seconds).sum();
    out += &time_table(ft, roofline_total);
    out += &bounds_table(ft);
    out += &stage_table(ft);
    out += &memory_table(ft);
    out += &fifo_table(ft);
    out.push_str(&format!(
        "\nclocked frame time: {} s ({} cycles); roofline: {} s\n",
        or_na(frame_seconds(ft), |s| format!("{s:.6}")),
        ft.cycles_total(),
        or_na(finite(roofline_total), |s| format!("{s:.6}")),
    ));
    out
}

/// A table of the report under its caption, or nothing when it has no rows.
fn section(caption: &str, header: &[&str], right: &[bool], rows: &[Vec<String>]) -> String {
    if rows.is_empty() {
        return String::new();
    }
    format!("\n{caption}\n{}", aligned(header, right, rows))
}

/// The pass number on a pass's first row, blank on the rows after it.
fn first_row_index(i: usize, k: usize) -> String {
    if k == 0 {
        i.to_string()
    } else {
        String::new()
    }
}

/// Time per pass, beside the roofline, and the frame's total; the name column takes
/// what the others leave of the line.
fn time_table(ft: &FrameTiming, roofline_total: f64) -> String {
    let hz = ft.clock_hz;
    let ms = |s: Option<f64>| or_na(s, |v| format!("{:.4}", v * 1e3));
    let time_row = |idx: String, name: &str, cycles: u64, roof: f64| {
        let clocked = seconds(cycles, hz);
        vec![
            idx,
            name.to_string(),
            cycles.to_string(),
            ms(clocked),
            ms(finite(roof)),
            or_na(clocked.and_then(|c| ratio(c, roof)), |r| format!("{r:.2}")),
        ]
    };
    let mut header = vec![
        "#",
        "pass",
        "cycles",
        "clocked_ms",
        "roofline_ms",
        "clocked/roofline",
    ];
    let mut right = vec![true, false, true, true, true, true];
    let mut rows: Vec<Vec<String>> = ft
        .passes
        .iter()
        .enumerate()
        .map(|(i, p)| time_row(i.to_string(), &p.pass, p.timing.cycles, p.roofline_seconds))
        .collect();
    // Sampled mode: which passes were clocked and which scaled from which.
    if ft.mode == "sampled" {
        header.push("timed");
        right.push(false);
        for (r, p) in rows.iter_mut().zip(&ft.passes) {
            r.push(match p.scaled_from {
                Some(k) => format!("from #{k}"),
                None => "clocked".to_string(),
            });
        }
    }
    let mut frame = time_row(String::new(), "frame", ft.cycles_total(), roofline_total);
    frame.resize(header.len(), String::new());
    rows.push(frame);
    let others: usize = (0..header.len())
        .filter(|&c| c != 1)
        .map(|c| {
            rows.iter()
                .map(|r| r[c].chars().count())
                .chain([header[c].len()])
                .max()
                .unwrap_or(0)
        })
        .sum::<usize>()
        + 2 * (header.len() - 1);
    let name_room = MAX_TABLE_COLUMNS.saturating_sub(others).max(12);
    for r in &mut rows {
        r[1] = cut(&r[1], name_room);
    }
    section(
        "time per pass (clocked on the chip, and the roofline's prediction):",
        &header,
        &right,
        &rows,
    )
}

/// What bounds each pass: its start, hardware passes, cache, bandwidth, bottleneck.
fn bounds_table(ft: &FrameTiming) -> String {
    let starts = pass_starts(ft);
    let rows: Vec<Vec<String>> = ft
        .passes
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let t = &p.timing;
            let total: u64 = t.bytes_by_client.values().sum();
            vec![
                i.to_string(),
                starts[i].to_string(),
                t.hardware_passes.to_string(),
                or_na(t.cache_hit_rate(), |r| format!("{:.1}", r * 100.0)),
                (t.cache_hits + t.cache_misses).to_string(),
                or_na(bytes_per_second(total, t, ft.clock_hz), |b| {
                    format!("{:.2}", b / 1e9)
                }),
                cut(&t.bottleneck, 36),
            ]
        })
        .collect();
    section(
        "per pass (tex_hit_%: hits over lookups of the texture caches; GB/s: all memory clients):",
        &[
            "#",
            "start_clock",
            "hw_passes",
            "tex_hit_%",
            "tex_lookups",
            "GB/s",
            "bottleneck",
        ],
        &[true, true, true, true, true, true, false],
        &rows,
    )
}

/// Each stage's busy, stalled and starved share of its pass, with a bar.
fn stage_table(ft: &FrameTiming) -> String {
    let mut rows = Vec::new();
    for (i, p) in ft.passes.iter().enumerate() {
        for (k, s) in p.timing.stages.iter().enumerate() {
            let u = utilisation(s.busy, s.stalled, s.starved, p.timing.cycles);
            let pct = |j: usize| or_na(u.map(|u| u[j]), |v| format!("{:.1}", v * 100.0));
            rows.push(vec![
                first_row_index(i, k),
                cut(&s.name, 28),
                pct(0),
                pct(1),
                pct(2),
                u.map_or_else(|| "n/a".into(), bar),
            ]);
        }
    }
    section(
        "stage utilisation (% of the pass's clocks; bar: # busy, = stalled, . starved):",
        &["#", "stage", "busy_%", "stalled_%", "starved_%", "bar"],
        &[true, false, true, true, true, false],
        &rows,
    )
}

/// The bytes each memory client moved per pass (clients of 0 bytes left out).
fn memory_table(ft: &FrameTiming) -> String {
    let mut rows = Vec::new();
    for (i, p) in ft.passes.iter().enumerate() {
        let t = &p.timing;
        let total: u64 = t.bytes_by_client.values().sum();
        let moved = t.bytes_by_client.iter().filter(|(_, &b)| b > 0);
        for (k, (client, &b)) in moved.enumerate() {
            rows.push(vec![
                first_row_index(i, k),
                cut(client, 20),
                b.to_string(),
                megabytes(b),
                or_na(bytes_per_second(b, t, ft.clock_hz), |v| {
                    format!("{:.3}", v / 1e9)
                }),
                or_na(ratio(b as f64, total as f64), |v| {
                    format!("{:.1}", v * 100.0)
                }),
            ]);
        }
    }
    section(
        "memory traffic by client (MB = 10^6 bytes; GB/s over the pass; clients of 0 bytes \
         left out):",
        &["#", "client", "bytes", "MB", "GB/s", "share_%"],
        &[true, false, true, true, true, true],
        &rows,
    )
}

/// Each FIFO's deepest occupancy against its depth.
fn fifo_table(ft: &FrameTiming) -> String {
    let mut rows = Vec::new();
    for (i, p) in ft.passes.iter().enumerate() {
        for (k, f) in p.timing.fifos.iter().enumerate() {
            let reached = f.depth > 0 && f.high_water >= f.depth;
            rows.push(vec![
                first_row_index(i, k),
                cut(&f.name, 40),
                f.high_water.to_string(),
                f.depth.to_string(),
                if reached {
                    "full".into()
                } else {
                    String::new()
                },
            ]);
        }
    }
    section(
        "FIFO high water (deepest occupancy over the pass, in entries):",
        &["#", "fifo", "high_water", "depth", "reached"],
        &[true, false, true, true, false],
        &rows,
    )
}

/// [`FrameTiming::clocked_seconds`] where the clock is a clock (else None).
fn frame_seconds(ft: &FrameTiming) -> Option<f64> {
    seconds(ft.cycles_total(), ft.clock_hz)
}

// ---------------------------------------------------------------------------------
// JSON.

/// The clocked timing as one JSON object (the `timing` object of `render --json` with
/// clocked or sampled timing; docs/throughput.md lists the fields). `null` where a
/// number was not measured; `sampling_error` only in sampled mode.
pub fn json(ft: &FrameTiming) -> Value {
    let hz = ft.clock_hz;
    let starts = pass_starts(ft);
    let passes: Vec<Value> = ft
        .passes
        .iter()
        .enumerate()
        .map(|(i, p)| pass_json(p, starts[i], hz))
        .collect();
    let roofline_total: f64 = ft.passes.iter().map(|p| p.roofline_seconds).sum();
    let mut m = Map::new();
    m.insert("mode".into(), json!(ft.mode));
    m.insert("chip".into(), json!(ft.chip));
    m.insert("clock_hz".into(), json!(finite(hz)));
    m.insert("cycles_total".into(), json!(ft.cycles_total()));
    m.insert("clocked_seconds".into(), json!(frame_seconds(ft)));
    m.insert("roofline_seconds".into(), json!(finite(roofline_total)));
    if ft.mode == "sampled" {
        m.insert(
            "sampling_error".into(),
            json!(ft.sampling_error.and_then(finite)),
        );
        m.insert("sample_band_every".into(), json!(ft.sample_band_every));
        m.insert("sample_pass_every".into(), json!(ft.sample_pass_every));
    }
    m.insert("passes".into(), Value::Array(passes));
    Value::Object(m)
}

fn pass_json(p: &NamedPassTiming, start: u64, hz: f64) -> Value {
    let t = &p.timing;
    let clocked = seconds(t.cycles, hz);
    let stages: Vec<Value> = t
        .stages
        .iter()
        .map(|s| {
            let u = utilisation(s.busy, s.stalled, s.starved, t.cycles);
            json!({
                "stage": s.name,
                "busy_clocks": s.busy,
                "stalled_clocks": s.stalled,
                "starved_clocks": s.starved,
                "busy": u.map(|u| u[0]),
                "stalled": u.map(|u| u[1]),
                "starved": u.map(|u| u[2]),
            })
        })
        .collect();
    let achieved: BTreeMap<&String, Option<f64>> = t
        .bytes_by_client
        .iter()
        .map(|(c, &b)| (c, bytes_per_second(b, t, hz)))
        .collect();
    let fifos: Vec<Value> = t
        .fifos
        .iter()
        .map(|f| json!({"fifo": f.name, "depth": f.depth, "high_water": f.high_water}))
        .collect();
    json!({
        "pass": p.pass,
        "start_clock": start,
        "cycles": t.cycles,
        "hardware_passes": t.hardware_passes,
        "clocked_seconds": clocked,
        "roofline_seconds": finite(p.roofline_seconds),
        "clocked_over_roofline": clocked.and_then(|c| ratio(c, p.roofline_seconds)),
        "cache_hits": t.cache_hits,
        "cache_misses": t.cache_misses,
        "cache_hit_rate": t.cache_hit_rate(),
        "bytes_by_client": t.bytes_by_client,
        "bytes_per_second_by_client": achieved,
        "stage_utilisation": stages,
        "fifo_high_water": fifos,
        "bottleneck": t.bottleneck,
        "scaled_from": p.scaled_from,
    })
}

// ---------------------------------------------------------------------------------
// The timeline: checks, CSV and PNG.

/// One bucket of a pass's timeline on the frame's clocks (or several merged:
/// [`timeline_csv_merge`]).
struct Bucket<'a> {
    pass: usize,
    stage: &'a str,
    start: u64,
    end: u64,
    busy: f32,
}

/// A pass's timeline checked against its pass: one row of buckets per stage, each
/// fraction in 0 ..= 1, the buckets within the pass's cycles. Errors name the pass.
fn check_timeline(i: usize, p: &NamedPassTiming) -> Result<(), String> {
    let tl: &Timeline = &p.timing.timeline;
    let at = |what: String| format!("timing.passes[{i}] ({}): timeline: {what}", p.pass);
    if tl.busy.len() != tl.stages.len() {
        return Err(at(format!(
            "{} stages but {} rows of busy fractions",
            tl.stages.len(),
            tl.busy.len()
        )));
    }
    let n = tl.busy.first().map_or(0, Vec::len);
    if n == 0 {
        return Ok(());
    }
    if tl.bucket_clocks == 0 {
        return Err(at("bucket_clocks is 0".into()));
    }
    for (s, row) in tl.busy.iter().enumerate() {
        if row.len() != n {
            return Err(at(format!(
                "stage {} has {} buckets, stage {} has {n}",
                tl.stages[s],
                row.len(),
                tl.stages[0]
            )));
        }
        if let Some((b, v)) = row
            .iter()
            .enumerate()
            .find(|(_, v)| !(0.0..=1.0).contains(*v))
        {
            return Err(at(format!(
                "stage {} bucket {b}: busy fraction {v} is outside 0 ..= 1",
                tl.stages[s]
            )));
        }
    }
    let want = p.timing.cycles.div_ceil(tl.bucket_clocks);
    if n as u64 != want {
        return Err(at(format!(
            "{n} buckets of {} clocks for the pass's {} cycles (it takes {want})",
            tl.bucket_clocks, p.timing.cycles
        )));
    }
    Ok(())
}

/// Every pass's timeline checked ([`check_timeline`]), and where each pass starts on
/// the frame's clocks.
fn checked_starts(ft: &FrameTiming) -> Result<Vec<u64>, String> {
    for (i, p) in ft.passes.iter().enumerate() {
        check_timeline(i, p)?;
    }
    Ok(pass_starts(ft))
}

/// Every bucket of every pass on the frame's clocks, pass by pass, stage by stage
/// (`starts` from [`checked_starts`]), each pass's buckets merged `merge[pass]` at a
/// time (1: as they are). An iterator: a clocked frame of a few hundred passes has
/// over a million buckets, which the CSV and the image take one by one.
fn buckets<'a>(
    ft: &'a FrameTiming,
    starts: &'a [u64],
    merge: &'a [u64],
) -> impl Iterator<Item = Bucket<'a>> + 'a {
    ft.passes.iter().enumerate().flat_map(move |(i, p)| {
        let tl = &p.timing.timeline;
        let end = starts[i].saturating_add(p.timing.cycles);
        let k = merge[i].max(1);
        let span = k.saturating_mul(tl.bucket_clocks);
        tl.busy.iter().enumerate().flat_map(move |(s, row)| {
            (0..row.len())
                .step_by(k as usize)
                .enumerate()
                .map(move |(j, b0)| {
                    let lo = starts[i].saturating_add(j as u64 * span);
                    Bucket {
                        pass: i,
                        stage: &tl.stages[s],
                        start: lo,
                        end: lo.saturating_add(span).min(end),
                        busy: merged_row(row, b0, k as usize, tl.bucket_clocks, p.timing.cycles),
                    }
                })
        })
    })
}

/// The timeline CSV's columns.
const TIMELINE_COLUMNS: [&str; 6] = [
    "clock_start",
    "clock_end",
    "pass_index",
    "pass",
    "stage",
    "busy_fraction",
];

/// The most rows per stage the timeline CSV spends on a frame (about three times the
/// timeline image's width) before it merges buckets.
pub const TIMELINE_CSV_BUCKETS: u64 = 4096;

/// How many of each pass's buckets one CSV row merges: 1 (every bucket its own row)
/// when the frame has at most [`TIMELINE_CSV_BUCKETS`] buckets per stage, else enough
/// that a row spans at least the frame's clocks / [`TIMELINE_CSV_BUCKETS`].
pub fn timeline_csv_merge(ft: &FrameTiming) -> Vec<u64> {
    let buckets: u64 = ft
        .passes
        .iter()
        .map(|p| p.timing.timeline.busy.first().map_or(0, Vec::len) as u64)
        .sum();
    let row_clocks = ft.cycles_total().div_ceil(TIMELINE_CSV_BUCKETS);
    ft.passes
        .iter()
        .map(|p| {
            if buckets <= TIMELINE_CSV_BUCKETS {
                1
            } else {
                row_clocks
                    .div_ceil(p.timing.timeline.bucket_clocks.max(1))
                    .max(1)
            }
        })
        .collect()
}

/// One CSV row of a pass's stage: its buckets `b0 .. b0 + k` (fewer at the pass's end)
/// merged, the busy fraction their clock-weighted mean (the bucket's own value when it
/// is one).
fn merged_row(row: &[f32], b0: usize, k: usize, bucket_clocks: u64, cycles: u64) -> f32 {
    let end = (b0 + k).min(row.len());
    if end - b0 == 1 {
        return row[b0];
    }
    let (mut busy, mut clocks) = (0f64, 0f64);
    for (b, &v) in row.iter().enumerate().take(end).skip(b0) {
        let len = bucket_clocks.min(cycles - b as u64 * bucket_clocks) as f64;
        busy += v as f64 * len;
        clocks += len;
    }
    (busy / clocks) as f32
}

/// The timeline as CSV: one row per pass, stage and bucket — `clock_start`,
/// `clock_end` (frame clocks, end exclusive), `pass_index`, `pass`, `stage`,
/// `busy_fraction` (0 ..= 1, the shortest decimal that reads back to the same `f32`).
/// A frame of more than [`TIMELINE_CSV_BUCKETS`] buckets per stage has each pass's
/// buckets merged ([`timeline_csv_merge`]), so the file holds at most about that many
/// rows per stage plus one per pass. Returns the number of rows. The rows are written
/// field by field as they are made, and the file is replaced atomically when all are
/// written.
pub fn write_timeline_csv(ft: &FrameTiming, path: &Path) -> Result<usize, String> {
    let starts = checked_starts(ft).map_err(|e| format!("{}: {e}", path.display()))?;
    let merge = timeline_csv_merge(ft);
    let mut n = 0usize;
    crate::report::atomic::write_with(path, |w| {
        let mut out = csv::Writer::from_writer(w);
        out.write_record(TIMELINE_COLUMNS)?;
        let (mut int, mut float) = (itoa::Buffer::new(), ryu::Buffer::new());
        for b in buckets(ft, &starts, &merge) {
            out.write_field(int.format(b.start))?;
            out.write_field(int.format(b.end))?;
            out.write_field(int.format(b.pass))?;
            out.write_field(&ft.passes[b.pass].pass)?;
            out.write_field(b.stage)?;
            out.write_field(float.format(b.busy))?;
            out.write_record(None::<&[u8]>)?;
            n += 1;
        }
        out.flush()
    })?;
    Ok(n)
}

/// The timeline's lanes: every pass's stages merged in pipeline order (a stage first
/// seen in a later pass goes after the stage it follows there).
fn lane_order(ft: &FrameTiming) -> Vec<&str> {
    let mut lanes: Vec<&str> = Vec::new();
    for p in &ft.passes {
        let stages = &p.timing.timeline.stages;
        for (j, s) in stages.iter().enumerate() {
            if lanes.contains(&s.as_str()) {
                continue;
            }
            let at = match j.checked_sub(1) {
                None => 0,
                Some(prev) => lanes
                    .iter()
                    .position(|l| *l == stages[prev])
                    .map_or(lanes.len(), |k| k + 1),
            };
            lanes.insert(at, s);
        }
    }
    lanes
}

/// The timeline image's width in pixels.
pub const TIMELINE_WIDTH: u32 = 1400;

/// Busy fraction → colour: near-white (idle) through blue to dark navy (busy every
/// clock), a sequential scale that stays readable in grey.
fn busy_colour(v: f64) -> [u8; 3] {
    const STOPS: [(f64, [f64; 3]); 5] = [
        (0.0, [247.0, 251.0, 255.0]),
        (0.25, [198.0, 219.0, 239.0]),
        (0.5, [107.0, 174.0, 214.0]),
        (0.75, [33.0, 113.0, 181.0]),
        (1.0, [8.0, 38.0, 96.0]),
    ];
    let v = v.clamp(0.0, 1.0);
    for w in STOPS.windows(2) {
        let ((a, ca), (b, cb)) = (w[0], w[1]);
        if v <= b {
            let t = (v - a) / (b - a);
            return std::array::from_fn(|k| (ca[k] + (cb[k] - ca[k]) * t).round() as u8);
        }
    }
    [8, 38, 96]
}

/// Grey with diagonal stripes: a stage the pass does not have.
fn absent_colour(x: u32, y: u32) -> [u8; 3] {
    if (x + y) % 8 < 2 {
        [190, 190, 190]
    } else {
        [232, 232, 232]
    }
}

/// The pass bands' two alternating shades.
const BAND: [[u8; 3]; 2] = [[236, 226, 206], [214, 228, 214]];

struct Canvas {
    w: u32,
    h: u32,
    buf: Vec<u8>,
}

impl Canvas {
    fn put(&mut self, x: u32, y: u32, c: [u8; 3]) {
        if x < self.w && y < self.h {
            let o = (y as usize * self.w as usize + x as usize) * 3;
            self.buf[o..o + 3].copy_from_slice(&c);
        }
    }

    fn rect(&mut self, x0: u32, y0: u32, x1: u32, y1: u32, c: [u8; 3]) {
        for y in y0..y1 {
            for x in x0..x1 {
                self.put(x, y, c);
            }
        }
    }
}

/// Nice tick spacing for `span` clocks over about `n` ticks (1, 2 or 5 × 10^k).
fn tick_step(span: f64, n: f64) -> f64 {
    let raw = (span / n).max(1.0);
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * p)
}

/// Where everything of the timeline PNG goes (pixels), from the frame and its lanes.
struct TimelineLayout {
    w: u32,
    h: u32,
    left: u32,
    plot_w: u32,
    title_h: u32,
    band_h: u32,
    lane_h: u32,
    lanes_top: u32,
    lanes_bottom: u32,
    bar_y: u32,
    bar_w: u32,
    key_y: u32,
    key_line: u32,
    /// Key columns and rows, and the passes the key lists (the rest are counted).
    key_cols: usize,
    key_rows: u32,
    listed: usize,
    /// The frame's clocks.
    total: u64,
}

impl TimelineLayout {
    fn new(ft: &FrameTiming, lanes: &[&str], total: u64) -> Self {
        let w = TIMELINE_WIDTH;
        let left = 24 + 9 * lanes.iter().map(|s| s.chars().count()).max().unwrap_or(8) as u32;
        let left = left.clamp(120, 420);
        let right = 30u32;
        let (title_h, band_h, lane_h) = (44u32, 26u32, 30u32);
        let lanes_top = title_h + band_h;
        let lanes_h = lane_h * lanes.len().max(1) as u32;
        let (axis_h, bar_h, key_line) = (56u32, 44u32, 20u32);
        // The key: one column up to 12 passes, two up to 48, then three; at most
        // KEY_ROWS rows, the rest counted on a last line (the CSV lists every pass).
        const KEY_ROWS: usize = 40;
        let n_passes = ft.passes.len();
        let key_cols = match n_passes {
            0..=12 => 1,
            13..=48 => 2,
            _ => 3,
        };
        let key_rows = n_passes.div_ceil(key_cols).min(KEY_ROWS);
        let listed = (key_rows * key_cols).min(n_passes);
        let more_line = u32::from(listed < n_passes);
        let key_rows = key_rows as u32;
        let h =
            lanes_top + lanes_h + axis_h + bar_h + 16 + key_line * (key_rows + 1 + more_line) + 12;
        let lanes_bottom = lanes_top + lanes_h;
        let bar_y = lanes_bottom + axis_h;
        TimelineLayout {
            w,
            h,
            left,
            plot_w: w - left - right,
            title_h,
            band_h,
            lane_h,
            lanes_top,
            lanes_bottom,
            bar_y,
            bar_w: 300,
            key_y: bar_y + bar_h + 16,
            key_line,
            key_cols,
            key_rows,
            listed,
            total,
        }
    }

    /// The x pixel of a frame clock.
    fn x_of(&self, clock: f64) -> f64 {
        self.left as f64 + clock / self.total as f64 * self.plot_w as f64
    }

    /// Pass `i`'s left and right x (floating).
    fn pass_span(&self, ft: &FrameTiming, starts: &[u64], i: usize) -> (f64, f64) {
        let s = starts[i] as f64;
        (
            self.x_of(s),
            self.x_of(s + ft.passes[i].timing.cycles as f64),
        )
    }
}

/// The timeline as a PNG, [`TIMELINE_WIDTH`] pixels wide: a lane per stage (the
/// stages of every pass, in the order they first appear), each pixel column coloured
/// by the stage's busy fraction over the clocks it covers (the buckets' fractions
/// weighted by their overlap); grey stripes where the pass has no such stage. The
/// passes are bands along the top with their numbers (and names where they fit),
/// their boundaries drawn through the lanes; a key under the axis lists every pass
/// with its clocks and share of the frame; a colour bar gives the scale.
pub fn write_timeline_png(ft: &FrameTiming, path: &Path) -> Result<(), String> {
    let e = |x: String| format!("{}: {x}", path.display());
    crate::report::plot::ensure_font().map_err(e)?;
    let starts = checked_starts(ft).map_err(e)?;
    let total = ft.cycles_total();
    if total == 0 {
        return Err(e("timing: the frame has no clocks to draw".into()));
    }
    let lanes = lane_order(ft);
    let lay = TimelineLayout::new(ft, &lanes, total);
    let mut cv = Canvas {
        w: lay.w,
        h: lay.h,
        buf: vec![255u8; lay.w as usize * lay.h as usize * 3],
    };
    paint_pass_bands(&mut cv, ft, &starts, &lay);
    // The image from every bucket as it is (merged by none).
    let whole = vec![1; ft.passes.len()];
    paint_lanes(&mut cv, buckets(ft, &starts, &whole), &lanes, &lay);
    paint_frame_and_boundaries(&mut cv, ft, &starts, &lay);
    let step = tick_step(total as f64, 8.0);
    let ticks = paint_ticks(&mut cv, step, &lay);
    paint_colour_bar(&mut cv, &lay);
    {
        let root = BitMapBackend::with_buffer(&mut cv.buf, (lay.w, lay.h)).into_drawing_area();
        let de = |x: DrawingAreaErrorKind<_>| e(x.to_string());
        label_lanes_and_passes(&root, ft, &starts, &lanes, &lay).map_err(de)?;
        label_axis_and_bar(&root, ft, &ticks, step, &lay).map_err(de)?;
        draw_key(&root, ft, &starts, &lay).map_err(de)?;
        root.present().map_err(de)?;
    }
    let img = image::RgbImage::from_raw(lay.w, lay.h, cv.buf)
        .ok_or_else(|| e("internal: buffer size does not match the image".into()))?;
    crate::report::atomic::write_atomically(path, |tmp| {
        img.save_with_format(tmp, image::ImageFormat::Png)
            .map_err(|x| e(format!("cannot write PNG: {x}")))
    })
}

/// The passes' bands along the top, alternating colours.
fn paint_pass_bands(cv: &mut Canvas, ft: &FrameTiming, starts: &[u64], lay: &TimelineLayout) {
    for i in 0..ft.passes.len() {
        let (a, b) = lay.pass_span(ft, starts, i);
        let (a, b) = (
            a.round() as u32,
            (b.round() as u32).max(a.round() as u32 + 1),
        );
        cv.rect(
            a,
            lay.title_h,
            b.min(lay.left + lay.plot_w),
            lay.title_h + lay.band_h - 2,
            BAND[i % 2],
        );
    }
}

/// Per pixel column and stage, the overlap-weighted busy fraction; a column the stage
/// covers for under a tenth of its clocks reads as absent rather than as a fraction of
/// almost nothing.
fn paint_lanes<'a>(
    cv: &mut Canvas,
    all: impl Iterator<Item = Bucket<'a>>,
    lanes: &[&str],
    lay: &TimelineLayout,
) {
    let plot_w = lay.plot_w as usize;
    let mut sum = vec![vec![0f64; plot_w]; lanes.len()];
    let mut cover = vec![vec![0f64; plot_w]; lanes.len()];
    let px_clocks = lay.total as f64 / lay.plot_w as f64;
    for b in all {
        let Some(l) = lanes.iter().position(|s| *s == b.stage) else {
            continue;
        };
        let (lo, hi) = (b.start as f64, b.end as f64);
        let c0 = ((lo / px_clocks).floor() as usize).min(plot_w - 1);
        let c1 = ((hi / px_clocks).ceil() as usize).min(plot_w);
        for c in c0..c1 {
            let (cl, ch) = (c as f64 * px_clocks, (c + 1) as f64 * px_clocks);
            let ov = hi.min(ch) - lo.max(cl);
            if ov > 0.0 {
                sum[l][c] += ov * b.busy as f64;
                cover[l][c] += ov;
            }
        }
    }
    for l in 0..lanes.len() {
        let y0 = lay.lanes_top + l as u32 * lay.lane_h;
        for c in 0..lay.plot_w {
            let cov = cover[l][c as usize];
            for y in y0 + 2..y0 + lay.lane_h - 2 {
                let col = if cov > 0.1 * px_clocks {
                    busy_colour(sum[l][c as usize] / cov)
                } else {
                    absent_colour(lay.left + c, y)
                };
                cv.put(lay.left + c, y, col);
            }
        }
    }
}

/// The frame around the lanes and the pass boundaries. A boundary crosses the lanes
/// where the passes on both sides are at least 8 pixels wide; between narrower ones it
/// stays in the band, so many short passes do not hide the lanes.
fn paint_frame_and_boundaries(
    cv: &mut Canvas,
    ft: &FrameTiming,
    starts: &[u64],
    lay: &TimelineLayout,
) {
    let (left, right, top, bottom) = (
        lay.left,
        lay.left + lay.plot_w,
        lay.lanes_top,
        lay.lanes_bottom,
    );
    cv.rect(left - 1, top, left, bottom, DARK);
    cv.rect(right, top, right + 1, bottom, DARK);
    cv.rect(left - 1, bottom, right + 1, bottom + 1, DARK);
    let px = |i: usize| lay.x_of(ft.passes[i].timing.cycles as f64) - left as f64;
    for (i, &s) in starts.iter().enumerate().skip(1) {
        let x = lay.x_of(s as f64).round() as u32;
        let through = px(i - 1) >= 8.0 && px(i) >= 8.0;
        let end = if through {
            bottom
        } else {
            lay.title_h + lay.band_h - 2
        };
        cv.rect(x, lay.title_h, x + 1, end, [200, 40, 40]);
    }
}

/// Tick marks every `step` clocks under the lanes; returns the ticks' clocks.
fn paint_ticks(cv: &mut Canvas, step: f64, lay: &TimelineLayout) -> Vec<f64> {
    let mut ticks = Vec::new();
    let mut t = 0.0;
    while t <= lay.total as f64 + 0.5 {
        ticks.push(t);
        let x = lay.x_of(t).round() as u32;
        cv.rect(x, lay.lanes_bottom, x + 1, lay.lanes_bottom + 6, DARK);
        t += step;
    }
    ticks
}

/// The colour bar (busy fraction 0 … 1) and the "stage not in the pass" swatch.
fn paint_colour_bar(cv: &mut Canvas, lay: &TimelineLayout) {
    let (bar_x, bar_y, bar_w) = (lay.left, lay.bar_y, lay.bar_w);
    for x in 0..bar_w {
        let c = busy_colour(x as f64 / (bar_w - 1) as f64);
        cv.rect(bar_x + x, bar_y, bar_x + x + 1, bar_y + 14, c);
    }
    let swatch = bar_x + bar_w + 150;
    cv.rect(swatch, bar_y, swatch + 30, bar_y + 14, [0; 3]);
    for x in 0..30 {
        for y in 0..14 {
            cv.put(swatch + x, bar_y + y, absent_colour(swatch + x, bar_y + y));
        }
    }
}

/// Dark grey of the frame and the ticks.
const DARK: [u8; 3] = [40, 40, 40];

/// The timeline's text in the font's `px` size, anchored at (`hp`, `vp`).
fn timeline_text(px: f64, hp: HPos, vp: VPos) -> TextStyle<'static> {
    TextStyle::from((crate::report::plot::FONT_FAMILY, px).into_font())
        .color(&BLACK)
        .pos(Pos::new(hp, vp))
}

/// Text sizes: title, labels, small print.
const TITLE_PX: f64 = 22.0;
const TEXT_PX: f64 = 15.0;
const SMALL_PX: f64 = 13.0;

type Root<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;
type DrawResult =
    Result<(), DrawingAreaErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>>;

/// The title, the lanes' names and the passes' labels in their bands ("3 name" where
/// it fits, else "3", else none).
fn label_lanes_and_passes(
    root: &Root<'_>,
    ft: &FrameTiming,
    starts: &[u64],
    lanes: &[&str],
    lay: &TimelineLayout,
) -> DrawResult {
    let title = format!(
        "Stage utilisation over the frame: {} at {}, {} ({} clocks)",
        ft.chip,
        show_clock(ft.clock_hz),
        ft.mode,
        lay.total
    );
    let name_x = (lay.left - 10) as i32;
    root.draw_text(
        &title,
        &timeline_text(TITLE_PX, HPos::Left, VPos::Center),
        (lay.left as i32, (lay.title_h / 2) as i32),
    )?;
    let right = timeline_text(TEXT_PX, HPos::Right, VPos::Center);
    root.draw_text(
        "pass",
        &right,
        (name_x, (lay.title_h + lay.band_h / 2) as i32),
    )?;
    for (l, s) in lanes.iter().enumerate() {
        let y = lay.lanes_top + l as u32 * lay.lane_h + lay.lane_h / 2;
        root.draw_text(s, &right, (name_x, y as i32))?;
    }
    let ts = timeline_text(SMALL_PX, HPos::Left, VPos::Center);
    for (i, p) in ft.passes.iter().enumerate() {
        let (a, b) = lay.pass_span(ft, starts, i);
        let room = (b - a - 6.0).max(0.0);
        let full = format!("{i} {}", p.pass);
        let fits = |s: &str| {
            root.estimate_text_size(s, &ts)
                .map(|(tw, _)| f64::from(tw) <= room)
                .unwrap_or(false)
        };
        let label = if fits(&full) {
            Some(full)
        } else if fits(&i.to_string()) {
            Some(i.to_string())
        } else {
            None
        };
        if let Some(label) = label {
            let y = (lay.title_h + lay.band_h / 2 - 1) as i32;
            root.draw_text(&label, &ts, ((a + 3.0) as i32, y))?;
        }
    }
    Ok(())
}

/// The ticks' clocks, the axis caption and the colour bar's labels.
fn label_axis_and_bar(
    root: &Root<'_>,
    ft: &FrameTiming,
    ticks: &[f64],
    step: f64,
    lay: &TimelineLayout,
) -> DrawResult {
    for &t in ticks {
        root.draw_text(
            &crate::report::plot::format_tick(t),
            &timeline_text(SMALL_PX, HPos::Center, VPos::Top),
            (lay.x_of(t).round() as i32, (lay.lanes_bottom + 8) as i32),
        )?;
    }
    root.draw_text(
        &format!(
            "frame clock (1 clock = {}, {} clocks = {}; red lines: pass boundaries)",
            show_period(ft.clock_hz),
            crate::report::plot::format_tick(step),
            seconds(step as u64, ft.clock_hz).map_or("n/a".into(), show_duration)
        ),
        &timeline_text(TEXT_PX, HPos::Center, VPos::Top),
        (
            (lay.left + lay.plot_w / 2) as i32,
            (lay.lanes_bottom + 30) as i32,
        ),
    )?;
    let (bar_x, bar_y, bar_w) = (lay.left, lay.bar_y, lay.bar_w);
    for (s, x, hp) in [
        ("0", bar_x, HPos::Left),
        ("0.5", bar_x + bar_w / 2, HPos::Center),
        ("1", bar_x + bar_w, HPos::Right),
    ] {
        let style = timeline_text(SMALL_PX, hp, VPos::Top);
        root.draw_text(s, &style, (x as i32, (bar_y + 17) as i32))?;
    }
    let beside = timeline_text(TEXT_PX, HPos::Left, VPos::Center);
    let y = (bar_y + 7) as i32;
    root.draw_text("busy fraction", &beside, ((bar_x + bar_w + 12) as i32, y))?;
    root.draw_text(
        "stage not in the pass",
        &beside,
        ((bar_x + bar_w + 188) as i32, y),
    )
}

/// The key under the colour bar: every pass listed, its clocks and share.
fn draw_key(root: &Root<'_>, ft: &FrameTiming, starts: &[u64], lay: &TimelineLayout) -> DrawResult {
    let small = timeline_text(SMALL_PX, HPos::Left, VPos::Center);
    root.draw_text(
        "passes:",
        &timeline_text(TEXT_PX, HPos::Left, VPos::Center),
        (lay.left as i32, lay.key_y as i32),
    )?;
    let col_w = lay.plot_w / lay.key_cols as u32;
    for (i, p) in ft.passes.iter().enumerate().take(lay.listed) {
        let (col, row) = (i / lay.key_rows as usize, i % lay.key_rows as usize);
        let share = p.timing.cycles as f64 / lay.total as f64 * 100.0;
        let line = if lay.key_cols < 3 {
            format!(
                "{i}  {} — {} clocks from {} ({share:.1} %)",
                cut(&p.pass, 70 / lay.key_cols),
                p.timing.cycles,
                starts[i],
            )
        } else {
            format!(
                "{i}  {} — {} clocks ({share:.1} %)",
                cut(&p.pass, 22),
                p.timing.cycles,
            )
        };
        let at = (
            (lay.left + col as u32 * col_w) as i32,
            (lay.key_y + lay.key_line * (row as u32 + 1)) as i32,
        );
        root.draw_text(&line, &small, at)?;
    }
    let n_passes = ft.passes.len();
    if lay.listed < n_passes {
        root.draw_text(
            &format!(
                "… and {} more passes (the timeline CSV lists every pass)",
                n_passes - lay.listed
            ),
            &small,
            (
                lay.left as i32,
                (lay.key_y + lay.key_line * (lay.key_rows + 1)) as i32,
            ),
        )?;
    }
    Ok(())
}

// ---------------------------------------------------------------------------------
// The VCD.

/// One clock in the VCD's time unit (picoseconds): the chip's period rounded to a
/// whole picosecond (exact for clocks that divide 10¹² Hz, such as 200 MHz → 5 000).
/// Errors for a clock that is not a positive finite number or is above 1 THz.
pub fn vcd_clock_ps(clock_hz: f64) -> Result<u64, String> {
    if !(clock_hz.is_finite() && clock_hz > 0.0) {
        return Err(format!(
            "timing.clock_hz: {clock_hz} is not a clock (a positive number of Hz)"
        ));
    }
    let ps = (1e12 / clock_hz).round();
    if ps < 2.0 {
        return Err(format!(
            "timing.clock_hz: {clock_hz} Hz is above what a VCD in picoseconds can show \
             (500 GHz)"
        ));
    }
    Ok(ps as u64)
}

/// A VCD name: no white space (the format separates by it).
fn vcd_name(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join("_")
}

/// A declared signal: its scope path, wire name and width.
struct Declared {
    scope: Vec<String>,
    wire: String,
    width: u32,
}

/// Declarations nested by scope.
#[derive(Default)]
struct ScopeTree {
    wires: Vec<usize>,
    children: BTreeMap<String, ScopeTree>,
    order: Vec<String>,
}

impl ScopeTree {
    fn insert(&mut self, path: &[String], sig: usize) {
        match path.split_first() {
            None => self.wires.push(sig),
            Some((head, rest)) => {
                if !self.children.contains_key(head) {
                    self.order.push(head.clone());
                }
                self.children
                    .entry(head.clone())
                    .or_default()
                    .insert(rest, sig);
            }
        }
    }

    fn write<W: Write>(
        &self,
        w: &mut vcd::Writer<W>,
        decl: &[Declared],
        ids: &mut [Option<vcd::IdCode>],
    ) -> std::io::Result<()> {
        for &s in &self.wires {
            ids[s] = Some(w.add_wire(decl[s].width, &decl[s].wire)?);
        }
        for name in &self.order {
            w.add_module(name)?;
            self.children[name].write(w, decl, ids)?;
            w.upscope()?;
        }
        Ok(())
    }
}

/// The passes' [`WindowTrace`]s as one VCD on the frame's clocks. Time unit 1 ps, one
/// clock = [`vcd_clock_ps`] (the chip's period); scope `chip` holds `clk` (rising at
/// each clock), `pass` (a string: the pass running) and a scope per FIFO or other
/// block: a signal "a.b.level" is wire `level` in scope `chip.a.b`. Signals a pass
/// does not trace are `x` while it runs. Errors (naming the pass and signal): a width
/// outside 1 ..= 64, a value wider than its signal, a signal index out of range,
/// changes out of clock order, one name with two widths.
pub fn write_vcd(ft: &FrameTiming, path: &Path) -> Result<(), String> {
    // Streamed to the file (a long window is large); every check comes before the
    // first byte, and a failure leaves no file.
    crate::report::atomic::write_with(path, |w| vcd_bytes(ft, w).map_err(std::io::Error::other))
}

/// [`write_vcd`] into a writer.
pub fn vcd_bytes<W: Write>(ft: &FrameTiming, out: W) -> Result<(), String> {
    let ps = vcd_clock_ps(ft.clock_hz)?;
    let starts = pass_starts(ft);
    let traced: Vec<(usize, &WindowTrace)> = ft
        .passes
        .iter()
        .enumerate()
        .filter_map(|(i, p)| p.timing.window.as_ref().map(|w| (i, w)))
        .collect();
    let (decl, maps) = declare_signals(ft, &traced)?;
    let (lo, hi) = traced
        .iter()
        .map(|&(i, tr)| {
            let end = tr.end_clock.min(ft.passes[i].timing.cycles);
            (
                starts[i].saturating_add(tr.start_clock),
                starts[i].saturating_add(end),
            )
        })
        .fold((u64::MAX, 0), |(a, b), (c, d)| (a.min(c), b.max(d)));
    // Every timestamp, half clocks included, must fit the VCD's 64-bit time.
    if hi.checked_mul(ps).and_then(|t| t.checked_add(ps)).is_none() {
        return Err(format!(
            "timing: clock {hi} of the frame is beyond what a VCD in picoseconds can \
             time (2^64 ps); trace an earlier window"
        ));
    }
    let io = |e: std::io::Error| e.to_string();
    let mut w = vcd::Writer::new(out);
    let ids = vcd_header(&mut w, ft, ps, (lo, hi), &decl).map_err(io)?;
    let mut state = VcdState {
        value: vec![None; decl.len()],
        declared_x: false,
    };
    for (t, &(i, tr)) in traced.iter().enumerate() {
        let at = VcdPass {
            ft,
            pass: i,
            start: starts[i],
            trace: tr,
            map: &maps[t],
            ps,
        };
        vcd_window(&mut w, &at, &decl, &ids, &mut state).map_err(io)?;
    }
    if hi > lo {
        w.timestamp(hi * ps).map_err(io)?;
    }
    w.flush().map_err(io)
}

/// The union of every trace's signals by name (first-seen order) and, per trace, its
/// signals' indices into it; each trace checked: widths 1 ..= 64, one width per name,
/// changes in clock order naming its signals with values that fit.
fn declare_signals(
    ft: &FrameTiming,
    traced: &[(usize, &WindowTrace)],
) -> Result<(Vec<Declared>, Vec<Vec<usize>>), String> {
    let mut decl: Vec<Declared> = Vec::new();
    let mut by_name: BTreeMap<String, usize> = BTreeMap::new();
    let mut maps = Vec::new();
    for &(i, tr) in traced {
        let at =
            |what: String| format!("timing.passes[{i}] ({}): window: {what}", ft.passes[i].pass);
        let mut map = Vec::new();
        for (name, width) in &tr.signals {
            if !(1..=64).contains(width) {
                return Err(at(format!(
                    "signal {name}: width {width} is outside 1 ..= 64"
                )));
            }
            let name = vcd_name(name);
            let k = match by_name.get(&name) {
                Some(&k) if decl[k].width != *width => {
                    return Err(at(format!(
                        "signal {name} is {width} bits wide here and {} in an earlier pass",
                        decl[k].width
                    )));
                }
                Some(&k) => k,
                None => {
                    let mut parts: Vec<String> = name.split('.').map(String::from).collect();
                    let wire = parts.pop().unwrap_or_default();
                    decl.push(Declared {
                        scope: parts,
                        wire,
                        width: *width,
                    });
                    by_name.insert(name, decl.len() - 1);
                    decl.len() - 1
                }
            };
            map.push(k);
        }
        check_changes(tr, &map, &decl).map_err(at)?;
        maps.push(map);
    }
    Ok((decl, maps))
}

/// A trace's changes: in clock order, signal indices in range, values that fit.
fn check_changes(tr: &WindowTrace, map: &[usize], decl: &[Declared]) -> Result<(), String> {
    let mut last = 0u64;
    for (n, &(c, s, v)) in tr.changes.iter().enumerate() {
        let Some(&k) = map.get(s as usize) else {
            return Err(format!(
                "change {n}: signal index {s} (the window has {} signals)",
                map.len()
            ));
        };
        if c < last {
            return Err(format!(
                "change {n}: clock {c} comes after clock {last} (changes must be in clock order)"
            ));
        }
        last = c;
        let width = decl[k].width;
        if width < 64 && v >> width != 0 {
            return Err(format!(
                "change {n}: value {v} does not fit signal {}'s {width} bits",
                tr.signals[s as usize].0
            ));
        }
    }
    Ok(())
}

/// The VCD's comment, time unit and declarations: `chip` with `clk`, `pass` and the
/// signals' scopes. Returns the clock's, the pass name's and every signal's id.
fn vcd_header<W: Write>(
    w: &mut vcd::Writer<W>,
    ft: &FrameTiming,
    ps: u64,
    (lo, hi): (u64, u64),
    decl: &[Declared],
) -> std::io::Result<VcdIds> {
    w.comment(&format!(
        " glare-pipeline clocked chip: {} at {}, {} timing; one clock = {ps} ps \
         (the chip's period{}); clocks {lo}..{hi} of the frame, the clock k at {ps}·k ps ",
        ft.chip,
        show_clock(ft.clock_hz),
        ft.mode,
        if (1e12 / ft.clock_hz - ps as f64).abs() > 1e-9 {
            format!(" {} rounded to a whole ps", show_period(ft.clock_hz))
        } else {
            String::new()
        }
    ))?;
    w.timescale(1, vcd::TimescaleUnit::PS)?;
    w.add_module("chip")?;
    let clk = w.add_wire(1, "clk")?;
    let pass = w.add_var(vcd::VarType::String, 1, "pass", None)?;
    let mut tree = ScopeTree::default();
    for (k, d) in decl.iter().enumerate() {
        tree.insert(&d.scope, k);
    }
    let mut ids: Vec<Option<vcd::IdCode>> = vec![None; decl.len()];
    tree.write(w, decl, &mut ids)?;
    let signals = ids.into_iter().map(|i| i.expect("declared")).collect();
    w.upscope()?;
    w.enddefinitions()?;
    Ok(VcdIds { clk, pass, signals })
}

/// The VCD's ids: the clock, the pass name, every declared signal.
struct VcdIds {
    clk: vcd::IdCode,
    pass: vcd::IdCode,
    signals: Vec<vcd::IdCode>,
}

/// The values written so far (None: x) and whether every signal has been written once.
struct VcdState {
    value: Vec<Option<u64>>,
    declared_x: bool,
}

/// One traced pass: its index, first frame clock, trace and the trace's signals'
/// indices into the declarations; `ps` the clock's period in the VCD's unit.
struct VcdPass<'a> {
    ft: &'a FrameTiming,
    pass: usize,
    start: u64,
    trace: &'a WindowTrace,
    map: &'a [usize],
    ps: u64,
}

/// Signal `k` set to `v` (None: x), as a scalar or a vector of its width.
fn vcd_set<W: Write>(
    w: &mut vcd::Writer<W>,
    decl: &[Declared],
    ids: &VcdIds,
    k: usize,
    v: Option<u64>,
) -> std::io::Result<()> {
    let width = decl[k].width;
    if width == 1 {
        return w.change_scalar(
            ids.signals[k],
            match v {
                None => vcd::Value::X,
                Some(0) => vcd::Value::V0,
                Some(_) => vcd::Value::V1,
            },
        );
    }
    let bits: Vec<vcd::Value> = (0..width)
        .rev()
        .map(|b| match v {
            None => vcd::Value::X,
            Some(v) if (v >> b) & 1 == 1 => vcd::Value::V1,
            Some(_) => vcd::Value::V0,
        })
        .collect();
    w.change_vector(ids.signals[k], bits)
}

/// One pass's window, clock by clock on the frame's clocks: the clock's edges, at the
/// window's start the pass's name and every signal's opening value (x for signals the
/// pass does not trace), then each change as it happens.
fn vcd_window<W: Write>(
    w: &mut vcd::Writer<W>,
    p: &VcdPass<'_>,
    decl: &[Declared],
    ids: &VcdIds,
    st: &mut VcdState,
) -> std::io::Result<()> {
    let (tr, map, ps) = (p.trace, p.map, p.ps);
    let end = tr.end_clock.min(p.ft.passes[p.pass].timing.cycles);
    if tr.start_clock >= end {
        return Ok(());
    }
    let mut ch = tr.changes.iter().peekable();
    // Changes before the window's start set the value the window opens with.
    let mut opening: Vec<Option<u64>> = vec![None; decl.len()];
    while let Some(&&(c, s, v)) = ch.peek() {
        if c > tr.start_clock {
            break;
        }
        opening[map[s as usize]] = Some(v);
        ch.next();
    }
    for c in tr.start_clock..end {
        let at = (p.start + c) * ps;
        w.timestamp(at)?;
        w.change_scalar(ids.clk, vcd::Value::V1)?;
        if c == tr.start_clock {
            w.change_string(ids.pass, &vcd_name(&p.ft.passes[p.pass].pass))?;
            for (k, &open) in opening.iter().enumerate() {
                let v = if map.contains(&k) { open } else { None };
                if v != st.value[k] || !st.declared_x {
                    vcd_set(w, decl, ids, k, v)?;
                    st.value[k] = v;
                }
            }
            st.declared_x = true;
        }
        while let Some(&&(cc, s, v)) = ch.peek() {
            if cc != c {
                break;
            }
            let k = map[s as usize];
            if st.value[k] != Some(v) {
                vcd_set(w, decl, ids, k, Some(v))?;
                st.value[k] = Some(v);
            }
            ch.next();
        }
        w.timestamp(at + ps / 2)?;
        w.change_scalar(ids.clk, vcd::Value::V0)?;
    }
    Ok(())
}
