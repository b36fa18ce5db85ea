//! The clocked chip's outputs (src/report/chip_timing.rs) on synthetic frame timings:
//! the JSON's fields against the struct, `n/a` where nothing was measured, the table's
//! width, the timeline PNG and CSV, the VCD parsed back with the `vcd` crate and
//! compared clock by clock with the window traces, and the refusals (bad windows,
//! inconsistent records) naming what is wrong.

// The contract types' literals end in `..Default::default()`, so a field added to them
// later (small additive fields are allowed) leaves this file compiling.
#![allow(clippy::needless_update)]

use glare_pipeline::chip::clock::{
    FifoHighWater, FrameTiming, NamedPassTiming, PassTiming, StageClocks, Timeline, WindowTrace,
};
use glare_pipeline::report::chip_timing::{
    self as ct, parse_vcd_window, pass_starts, pass_window, ChipFiles, DEFAULT_VCD_WINDOW,
    MAX_TABLE_COLUMNS, MAX_VCD_WINDOW_CLOCKS, TIMELINE_WIDTH,
};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A small deterministic generator (no dependence on `rand`'s streams).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }
}

const STAGES: [&str; 5] = [
    "rasteriser",
    "polygon_interpolator",
    "texture_sampler",
    "texture_combiner",
    "rop",
];

/// A pass of `cycles` clocks with `stages` (busy/stalled/starved splitting the clocks
/// in a pattern), a timeline of `bucket` clocks, and the given cache hits and misses
/// and bytes.
fn pass(
    name: &str,
    cycles: u64,
    stages: &[&str],
    bucket: u64,
    (hits, misses): (u64, u64),
    bytes: &[(&str, u64)],
    seed: u64,
) -> NamedPassTiming {
    let mut g = Lcg(seed);
    let st: Vec<StageClocks> = stages
        .iter()
        .map(|s| {
            let busy = g.next() % (cycles + 1);
            let stalled = g.next() % (cycles - busy + 1);
            StageClocks {
                name: s.to_string(),
                busy,
                stalled,
                starved: cycles - busy - stalled,
            }
        })
        .collect();
    let n = cycles.div_ceil(bucket) as usize;
    let busy: Vec<Vec<f32>> = stages
        .iter()
        .enumerate()
        .map(|(k, _)| {
            (0..n)
                .map(|b| {
                    // Stage 0 busy every clock in the first half: a dark stretch.
                    if k == 0 && b < n / 2 {
                        1.0
                    } else {
                        (g.next() % 1001) as f32 / 1000.0
                    }
                })
                .collect()
        })
        .collect();
    NamedPassTiming {
        pass: name.to_string(),
        timing: PassTiming {
            cycles,
            hardware_passes: 1 + (seed % 2) as u32,
            stages: st,
            fifos: stages
                .windows(2)
                .map(|w| FifoHighWater {
                    name: format!("{}_to_{}", w[0], w[1]),
                    depth: 16,
                    high_water: (g.next() % 17) as u32,
                })
                .collect(),
            cache_hits: hits,
            cache_misses: misses,
            bytes_by_client: bytes.iter().map(|(c, b)| (c.to_string(), *b)).collect(),
            bottleneck: "memory: texture".into(),
            timeline: Timeline {
                bucket_clocks: bucket,
                stages: stages.iter().map(|s| s.to_string()).collect(),
                busy,
            },
            window: None,
            ..Default::default()
        },
        roofline_seconds: cycles as f64 / 200e6 * 0.8,
        ..Default::default()
    }
}

/// A window trace over `range` (pass clocks): valid, ready and level of two FIFOs and
/// the memory queue's level, with changes at random clocks (values fitting the width),
/// the opening values at the window's start.
fn trace(range: std::ops::Range<u64>, seed: u64) -> WindowTrace {
    let signals: Vec<(String, u32)> = vec![
        ("raster_to_interp.valid".into(), 1),
        ("raster_to_interp.ready".into(), 1),
        ("raster_to_interp.level".into(), 5),
        ("tex_to_comb.valid".into(), 1),
        ("tex_to_comb.level".into(), 5),
        ("memory.queue_level".into(), 7),
    ];
    let mut g = Lcg(seed);
    let mut changes = Vec::new();
    for (s, (_, w)) in signals.iter().enumerate() {
        changes.push((range.start, s as u32, g.next() % (1 << w)));
    }
    for c in range.start + 1..range.end {
        for (s, (_, w)) in signals.iter().enumerate() {
            if g.next().is_multiple_of(5) {
                changes.push((c, s as u32, g.next() % (1 << w)));
            }
        }
    }
    WindowTrace {
        start_clock: range.start,
        end_clock: range.end,
        signals,
        changes,
        ..Default::default()
    }
}

/// Three passes: a depth pass with no texture lookups (hit rate n/a), a long sample
/// plane pass with a long name and lookups, and a copy with no texture stage. Pass 0
/// traced over its clocks 0..1200 (all of it), pass 1 over its first 800 clocks.
fn frame(mode: &str) -> FrameTiming {
    let mut p0 = pass(
        "depth",
        1_200,
        &["rasteriser", "polygon_interpolator", "rop"],
        10,
        (0, 0),
        &[("depth", 9_600)],
        1,
    );
    let mut p1 = pass(
        "sample planes, light 0 (n = 30, m = 6) with a name long enough to be cut",
        50_000,
        &STAGES,
        100,
        (90_000, 10_000),
        &[
            ("texture", 320_000),
            ("depth", 400_000),
            ("colour", 800_000),
        ],
        2,
    );
    let p2 = pass(
        "copy to texture",
        3_000,
        &["rasteriser", "rop"],
        30,
        (0, 0),
        &[("copy", 12_000)],
        3,
    );
    p0.timing.window = Some(trace(0..1_200, 11));
    p1.timing.window = Some(trace(0..800, 12));
    FrameTiming {
        mode: mode.into(),
        chip: "geforce2-gts".into(),
        clock_hz: 200e6,
        passes: vec![p0, p1, p2],
        sampling_error: (mode == "sampled").then_some(0.0123),
        ..Default::default()
    }
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("chip_report_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

#[test]
fn json_fields_are_present_and_match_the_struct() {
    let ft = frame("clocked");
    let v = ct::json(&ft);
    assert_eq!(v["mode"], "clocked");
    assert_eq!(v["chip"], "geforce2-gts");
    assert_eq!(v["cycles_total"], 54_200);
    assert_eq!(v["cycles_total"].as_u64().unwrap(), ft.cycles_total());
    let secs = v["clocked_seconds"].as_f64().unwrap();
    assert_eq!(secs, ft.clocked_seconds());
    assert!((secs - 54_200.0 / 200e6).abs() < 1e-15);
    assert!(
        v.get("sampling_error").is_none(),
        "no sampling_error when every fragment is clocked"
    );
    let passes = v["passes"].as_array().unwrap();
    assert_eq!(passes.len(), 3);
    let starts = pass_starts(&ft);
    assert_eq!(starts, vec![0, 1_200, 51_200]);
    for (i, (j, p)) in passes.iter().zip(&ft.passes).enumerate() {
        let t = &p.timing;
        assert_eq!(j["pass"], p.pass.as_str());
        assert_eq!(j["cycles"].as_u64().unwrap(), t.cycles);
        assert_eq!(j["start_clock"].as_u64().unwrap(), starts[i]);
        assert_eq!(j["bottleneck"], t.bottleneck.as_str());
        assert_eq!(j["roofline_seconds"].as_f64().unwrap(), p.roofline_seconds);
        assert_eq!(
            j["hardware_passes"].as_u64().unwrap(),
            u64::from(t.hardware_passes)
        );
        match t.cache_hit_rate() {
            Some(r) => assert_eq!(j["cache_hit_rate"].as_f64().unwrap(), r),
            None => assert!(j["cache_hit_rate"].is_null(), "pass {i}: no lookups → null"),
        }
        let bytes: BTreeMap<String, u64> =
            serde_json::from_value(j["bytes_by_client"].clone()).unwrap();
        assert_eq!(bytes, t.bytes_by_client);
        for (c, b) in &t.bytes_by_client {
            let bps = j["bytes_per_second_by_client"][c].as_f64().unwrap();
            let want = *b as f64 / (t.cycles as f64 / ft.clock_hz);
            assert!((bps - want).abs() <= 1e-9 * want, "{c}: {bps} vs {want}");
        }
        let su = j["stage_utilisation"].as_array().unwrap();
        assert_eq!(su.len(), t.stages.len());
        for (u, s) in su.iter().zip(&t.stages) {
            assert_eq!(u["stage"], s.name.as_str());
            assert_eq!(u["busy_clocks"].as_u64().unwrap(), s.busy);
            let sum: f64 = ["busy", "stalled", "starved"]
                .iter()
                .map(|k| u[*k].as_f64().unwrap())
                .sum();
            assert!((sum - 1.0).abs() < 1e-12, "fractions add to 1: {sum}");
            assert_eq!(u["busy"].as_f64().unwrap(), s.busy as f64 / t.cycles as f64);
        }
        assert_eq!(
            j["fifo_high_water"].as_array().unwrap().len(),
            t.fifos.len()
        );
    }
    // The hit rate of the pass with lookups: 90 000 of 100 000.
    assert_eq!(passes[1]["cache_hit_rate"].as_f64().unwrap(), 0.9);
}

#[test]
fn sampled_mode_carries_its_error_and_the_table_says_so() {
    let ft = frame("sampled");
    let v = ct::json(&ft);
    assert_eq!(v["sampling_error"].as_f64().unwrap(), 0.0123);
    let t = ct::print_table(&ft);
    assert!(t.contains("sampled"), "{t}");
    assert!(t.contains("± 1.23 %"), "{t}");
    // Sampled with no error estimate: null and n/a, never 0.
    let mut ft = ft;
    ft.sampling_error = None;
    assert!(ct::json(&ft)["sampling_error"].is_null());
    assert!(ct::print_table(&ft).contains("± n/a"));
    // The sample's rates: unknown (n/a), a sample, or a frame too small to sample.
    assert!(ct::print_table(&ft).contains("one in n/a"));
    for (every, says) in [
        (8, ["one in 8 clocked", "band of 8 rows in 8"]),
        (1, ["too few screen bands", "every"]),
    ] {
        (ft.sample_band_every, ft.sample_pass_every) = (Some(every), Some(every));
        let t = ct::print_table(&ft);
        assert!(says.iter().all(|s| t.contains(s)), "{t}");
        assert!(t.lines().all(|l| l.chars().count() <= 100), "{t}");
        assert_eq!(
            ct::json(&ft)["sample_pass_every"].as_u64(),
            Some(every as u64)
        );
    }
}

#[test]
fn unmeasured_numbers_are_na_never_zero() {
    let mut ft = frame("clocked");
    // A pass of zero clocks and a roofline of zero seconds.
    ft.passes.push(NamedPassTiming {
        pass: "empty".into(),
        timing: PassTiming {
            cycles: 0,
            stages: vec![StageClocks {
                name: "rop".into(),
                ..Default::default()
            }],
            bytes_by_client: [("colour".to_string(), 0u64)].into_iter().collect(),
            ..Default::default()
        },
        roofline_seconds: 0.0,
        ..Default::default()
    });
    let t = ct::print_table(&ft);
    for l in t.lines() {
        assert!(
            l.chars().count() <= MAX_TABLE_COLUMNS,
            "line of {} columns: {l}",
            l.chars().count()
        );
    }
    // The per-pass table: pass 0 (no lookups) and pass 3 have n/a as hit rate.
    let section: Vec<&str> = t
        .split("\n\n")
        .find(|s| s.starts_with("per pass"))
        .unwrap()
        .lines()
        .collect();
    let header: Vec<&str> = section[1].split_whitespace().collect();
    let col = header.iter().position(|h| *h == "tex_hit_%").unwrap();
    let row = |i: usize| -> Vec<&str> {
        section
            .iter()
            .skip(3)
            .map(|l| l.split_whitespace().collect::<Vec<_>>())
            .find(|c| c[0] == i.to_string())
            .unwrap()
    };
    assert_eq!(row(0)[col], "n/a");
    assert_eq!(row(1)[col], "90.0");
    assert_eq!(row(2)[col], "n/a");
    assert_eq!(row(3)[col], "n/a");
    // GB/s over zero clocks, utilisation over zero clocks, ratio to a zero roofline.
    let gbs = header.iter().position(|h| *h == "GB/s").unwrap();
    assert_eq!(row(3)[gbs], "n/a");
    let time: Vec<&str> = t
        .split("\n\n")
        .find(|s| s.starts_with("time per pass"))
        .unwrap()
        .lines()
        .collect();
    let empty = time.iter().find(|l| l.contains("empty")).unwrap();
    assert!(empty.trim_end().ends_with("n/a"), "{empty}");
    let stages = t
        .split("\n\n")
        .find(|s| s.starts_with("stage utilisation"))
        .unwrap();
    let last = stages.lines().last().unwrap();
    assert!(last.contains("n/a"), "{last}");
    // A client of 0 bytes has no line in the memory table (the JSON keeps it).
    let memory = t
        .split("\n\n")
        .find(|s| s.starts_with("memory traffic"))
        .unwrap();
    assert!(memory.lines().any(|l| l.starts_with("2  copy")), "{memory}");
    assert!(!memory.lines().any(|l| l.starts_with("3 ")), "{memory}");
    // A long pass name is cut to fit, never wraps the line.
    assert!(t.contains('…'));
    // JSON: nulls for the same.
    let v = ct::json(&ft);
    let p = &v["passes"][3];
    assert!(p["cache_hit_rate"].is_null());
    assert!(p["clocked_over_roofline"].is_null());
    assert!(p["stage_utilisation"][0]["busy"].is_null());
    assert!(p["bytes_per_second_by_client"]["colour"].is_null());
    assert_eq!(p["clocked_seconds"].as_f64().unwrap(), 0.0);
}

#[test]
fn the_table_lists_every_pass_stage_client_and_fifo() {
    let ft = frame("clocked");
    let t = ct::print_table(&ft);
    for p in &ft.passes {
        for s in &p.timing.stages {
            assert!(t.contains(&s.name), "stage {}", s.name);
        }
        for c in p.timing.bytes_by_client.keys() {
            assert!(t.contains(c.as_str()));
        }
        for f in &p.timing.fifos {
            assert!(t.contains(&f.name));
        }
    }
    if let Ok(d) = std::env::var("CHIP_REPORT_KEEP") {
        std::fs::write(PathBuf::from(d).join("table.txt"), &t).unwrap();
    }
    assert!(
        t.contains("geforce2-gts at 200 MHz (1 clock = 5 ns)"),
        "{t}"
    );
    assert!(t.contains("54200"));
    // The frame line: the clocked total over the roofline's.
    let roof: f64 = ft.passes.iter().map(|p| p.roofline_seconds).sum();
    let want = format!("{:.2}", ft.clocked_seconds() / roof);
    let frame_row = t.lines().find(|l| l.contains("frame  ")).unwrap();
    assert!(
        frame_row.trim_end().ends_with(&want),
        "{frame_row} vs {want}"
    );
}

#[test]
fn timeline_csv_has_a_row_per_pass_stage_and_bucket() {
    let ft = frame("clocked");
    let path = tmp("t.timeline.csv");
    let n = ct::write_timeline_csv(&ft, &path).unwrap();
    let want: usize = ft
        .passes
        .iter()
        .map(|p| p.timing.timeline.stages.len() * p.timing.timeline.busy[0].len())
        .sum();
    assert_eq!(n, want);
    // 3 stages × 120 + 5 × 500 + 2 × 100
    assert_eq!(n, 3 * 120 + 5 * 500 + 2 * 100);
    let mut r = csv::Reader::from_path(&path).unwrap();
    let h: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(
        h,
        [
            "clock_start",
            "clock_end",
            "pass_index",
            "pass",
            "stage",
            "busy_fraction"
        ]
    );
    let starts = pass_starts(&ft);
    let mut rows = 0;
    for rec in r.records() {
        let rec = rec.unwrap();
        let (a, b): (u64, u64) = (rec[0].parse().unwrap(), rec[1].parse().unwrap());
        let i: usize = rec[2].parse().unwrap();
        let p = &ft.passes[i];
        assert_eq!(&rec[3], p.pass.as_str());
        assert!(a < b && a >= starts[i] && b <= starts[i] + p.timing.cycles);
        let tl = &p.timing.timeline;
        let s = tl.stages.iter().position(|s| s == &rec[4]).unwrap();
        let bucket = ((a - starts[i]) / tl.bucket_clocks) as usize;
        let v: f32 = rec[5].parse().unwrap();
        assert_eq!(v, tl.busy[s][bucket]);
        rows += 1;
    }
    assert_eq!(rows, n);
}

#[test]
fn timeline_png_decodes_at_its_size_with_busy_and_absent_lanes() {
    let ft = frame("clocked");
    let path = tmp("t.timeline.png");
    ct::write_timeline_png(&ft, &path).unwrap();
    let img = image::open(&path).unwrap().to_rgb8();
    assert_eq!(img.width(), TIMELINE_WIDTH);
    assert!(
        img.height() > 300 && img.height() < 1000,
        "{}",
        img.height()
    );
    let count = |c: [u8; 3]| img.pixels().filter(|p| p.0 == c).count();
    // The rasteriser is busy every clock through half of each pass: the darkest
    // colour shows; stages a pass lacks show the grey stripes.
    assert!(count([8, 38, 96]) > 1_000, "{}", count([8, 38, 96]));
    assert!(count([190, 190, 190]) > 100);
    // Pass boundaries in red.
    assert!(count([200, 40, 40]) > 100);
    // Kept for a look: CHIP_REPORT_KEEP=dir copies it there.
    if let Ok(d) = std::env::var("CHIP_REPORT_KEEP") {
        std::fs::copy(&path, PathBuf::from(d).join("timeline.png")).unwrap();
    }
}

#[test]
fn inconsistent_timelines_are_refused_naming_the_pass() {
    let mut ft = frame("clocked");
    ft.passes[1].timing.timeline.busy[2][7] = 1.5;
    let e = ct::write_timeline_csv(&ft, &tmp("bad.csv")).unwrap_err();
    assert!(e.contains("timing.passes[1]") && e.contains("1.5"), "{e}");
    let mut ft = frame("clocked");
    ft.passes[0].timing.timeline.busy[1].pop();
    let e = ct::write_timeline_png(&ft, &tmp("bad.png")).unwrap_err();
    assert!(
        e.contains("timing.passes[0]") && e.contains("buckets"),
        "{e}"
    );
    let mut ft = frame("clocked");
    // 100 buckets of 30 clocks cover the pass's 3 000; of 100 or of 10 they do not.
    for b in [100, 10] {
        ft.passes[2].timing.timeline.bucket_clocks = b;
        let e = ct::write_timeline_csv(&ft, &tmp("bad2.csv")).unwrap_err();
        assert!(
            e.contains("timing.passes[2]") && e.contains("it takes"),
            "{e}"
        );
    }
    ft.passes[2].timing.timeline.bucket_clocks = 30;
    assert!(ct::write_timeline_csv(&ft, &tmp("good2.csv")).is_ok());
}

/// Every traced signal's value at every frame clock of its pass's window, from the
/// WindowTrace (the value of the last change at or before the clock).
fn expected(ft: &FrameTiming) -> BTreeMap<(String, u64), u64> {
    let starts = pass_starts(ft);
    let mut out = BTreeMap::new();
    for (i, p) in ft.passes.iter().enumerate() {
        let Some(tr) = &p.timing.window else { continue };
        let end = tr.end_clock.min(p.timing.cycles);
        let mut cur: Vec<Option<u64>> = vec![None; tr.signals.len()];
        let mut ch = tr.changes.iter().peekable();
        for c in tr.start_clock..end {
            while let Some(&&(cc, s, v)) = ch.peek() {
                if cc > c {
                    break;
                }
                cur[s as usize] = Some(v);
                ch.next();
            }
            for (s, (name, _)) in tr.signals.iter().enumerate() {
                if let Some(v) = cur[s] {
                    out.insert((name.clone(), starts[i] + c), v);
                }
            }
        }
    }
    out
}

#[test]
fn vcd_round_trips_through_a_parser() {
    let ft = frame("clocked");
    let path = tmp("t.vcd");
    ct::write_vcd(&ft, &path).unwrap();
    if let Ok(d) = std::env::var("CHIP_REPORT_KEEP") {
        std::fs::copy(&path, PathBuf::from(d).join("frame.vcd")).unwrap();
    }
    let text = std::fs::read(&path).unwrap();
    let mut p = vcd::Parser::new(&text[..]);
    let header = p.parse_header().unwrap();
    assert_eq!(header.timescale, Some((1, vcd::TimescaleUnit::PS)));
    let ps = 5_000u64; // 200 MHz
                       // Declarations: chip.clk, chip.pass, one scope per FIFO, memory.queue_level.
    let chip = header
        .items
        .iter()
        .find_map(|i| match i {
            vcd::ScopeItem::Scope(s) if s.identifier == "chip" => Some(s),
            _ => None,
        })
        .expect("scope chip");
    let mut ids: BTreeMap<vcd::IdCode, (String, u32)> = BTreeMap::new();
    let mut scopes = Vec::new();
    for item in &chip.items {
        match item {
            vcd::ScopeItem::Var(v) => {
                ids.insert(v.code, (v.reference.clone(), v.size));
            }
            vcd::ScopeItem::Scope(s) => {
                scopes.push(s.identifier.clone());
                for it in &s.items {
                    if let vcd::ScopeItem::Var(v) = it {
                        ids.insert(
                            v.code,
                            (format!("{}.{}", s.identifier, v.reference), v.size),
                        );
                    }
                }
            }
            _ => {}
        }
    }
    assert_eq!(scopes, ["raster_to_interp", "tex_to_comb", "memory"]);
    // Widths as declared in the traces.
    let tr0 = ft.passes[0].timing.window.as_ref().unwrap();
    for (name, width) in &tr0.signals {
        let got = ids.values().find(|(n, _)| n == name).expect(name);
        assert_eq!(got.1, *width, "{name}");
    }
    assert!(ids.values().any(|(n, w)| n == "clk" && *w == 1));
    assert!(ids.values().any(|(n, _)| n == "pass"));
    // Replay: the value of every signal at every clock's rising edge.
    let mut now = 0u64;
    let mut cur: BTreeMap<String, Option<u64>> = BTreeMap::new();
    let mut got: BTreeMap<(String, u64), u64> = BTreeMap::new();
    let mut pass_at: BTreeMap<u64, String> = BTreeMap::new();
    let mut edges = 0u64;
    let mut record = |now: u64, cur: &BTreeMap<String, Option<u64>>| {
        for (n, v) in cur {
            if let Some(v) = v {
                got.insert((n.clone(), now / ps), *v);
            }
        }
    };
    let mut rising = false;
    for cmd in p {
        match cmd.unwrap() {
            vcd::Command::Timestamp(t) => {
                if rising {
                    record(now, &cur);
                }
                rising = false;
                assert!(t >= now, "time goes forward");
                now = t;
            }
            vcd::Command::ChangeScalar(id, v) => {
                let name = &ids[&id].0;
                if name == "clk" {
                    if v == vcd::Value::V1 {
                        assert_eq!(now % ps, 0, "rising edge at a whole clock");
                        rising = true;
                        edges += 1;
                    } else {
                        assert_eq!(now % ps, ps / 2);
                    }
                    continue;
                }
                let v = match v {
                    vcd::Value::V0 => Some(0),
                    vcd::Value::V1 => Some(1),
                    _ => None,
                };
                cur.insert(name.clone(), v);
            }
            vcd::Command::ChangeVector(id, v) => {
                let (name, width) = &ids[&id];
                assert_eq!(v.len(), *width as usize, "{name}");
                let mut x = Some(0u64);
                for b in v.iter() {
                    x = match (x, b) {
                        (Some(x), vcd::Value::V0) => Some(x << 1),
                        (Some(x), vcd::Value::V1) => Some(x << 1 | 1),
                        _ => None,
                    };
                }
                cur.insert(name.clone(), x);
            }
            vcd::Command::ChangeString(_, s) => {
                pass_at.insert(now / ps, s);
            }
            _ => {}
        }
    }
    if rising {
        record(now, &cur);
    }
    // Pass 0 traced 1 200 clocks, pass 1 (starting at 1 200) 800.
    assert_eq!(edges, 1_200 + 800);
    assert_eq!(
        pass_at,
        [
            (0, "depth".to_string()),
            (1_200, ct_name(&ft.passes[1].pass))
        ]
        .into_iter()
        .collect()
    );
    let want = expected(&ft);
    assert_eq!(want.len(), 1_200 * 6 + 800 * 6);
    assert_eq!(got, want);
}

fn ct_name(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join("_")
}

#[test]
fn a_trace_past_its_pass_is_clipped_and_bad_traces_are_refused() {
    // A window longer than the pass: clipped at the pass's end, time still forward.
    let mut ft = frame("clocked");
    ft.passes[0].timing.window = Some(trace(1_000..5_000, 3));
    let mut bytes = Vec::new();
    ct::vcd_bytes(&ft, &mut bytes).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    assert!(text.contains(&format!("#{}", 1_000 * 5_000)));
    // Pass 1's window starts at its first clock, the frame's 1 200.
    assert!(text.contains("#6000000\n"));
    let mut ft = frame("clocked");
    let tr = ft.passes[1].timing.window.as_mut().unwrap();
    tr.changes.swap(10, 400);
    let e = ct::vcd_bytes(&ft, Vec::new()).unwrap_err();
    assert!(
        e.contains("timing.passes[1]") && e.contains("clock order"),
        "{e}"
    );
    // Through the file: the error names the path, and no file is left.
    let path = tmp("refused.vcd");
    let e = ct::write_vcd(&ft, &path).unwrap_err();
    assert!(
        e.contains("refused.vcd") && e.contains("clock order"),
        "{e}"
    );
    assert!(!path.exists());
    let mut ft = frame("clocked");
    let tr = ft.passes[0].timing.window.as_mut().unwrap();
    tr.changes[0].2 = 2; // a 1-bit valid set to 2
    let e = ct::vcd_bytes(&ft, Vec::new()).unwrap_err();
    assert!(
        e.contains("raster_to_interp.valid") && e.contains("1 bits"),
        "{e}"
    );
    let mut ft = frame("clocked");
    ft.passes[0].timing.window.as_mut().unwrap().signals[2].1 = 0;
    let e = ct::vcd_bytes(&ft, Vec::new()).unwrap_err();
    assert!(e.contains("width 0"), "{e}");
    let mut ft = frame("clocked");
    ft.passes[1].timing.window.as_mut().unwrap().signals[2].1 = 6;
    let e = ct::vcd_bytes(&ft, Vec::new()).unwrap_err();
    assert!(
        e.contains("raster_to_interp.level") && e.contains("earlier pass"),
        "{e}"
    );
    let mut ft = frame("clocked");
    ft.clock_hz = 0.0;
    let e = ct::vcd_bytes(&ft, Vec::new()).unwrap_err();
    assert!(e.contains("timing.clock_hz"), "{e}");
}

#[test]
fn a_clock_that_does_not_divide_a_picosecond_is_rounded_and_said() {
    let mut ft = frame("clocked");
    ft.clock_hz = 120e6; // 8 333.3 ps
    assert_eq!(ct::vcd_clock_ps(120e6).unwrap(), 8_333);
    let mut bytes = Vec::new();
    ct::vcd_bytes(&ft, &mut bytes).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    assert!(text.contains("one clock = 8333 ps"), "{}", &text[..300]);
    assert!(text.contains("rounded to a whole ps"));
    assert!(text.contains(&format!("#{}\n", 8_333 * 1_199)));
}

#[test]
fn vcd_windows_parse_and_bad_ones_name_the_flag() {
    assert_eq!(parse_vcd_window("0..2000").unwrap(), 0..2000);
    assert_eq!(parse_vcd_window(" 10 .. 20 ").unwrap(), 10..20);
    for bad in [
        "",
        "5",
        "5..3",
        "4..4",
        "a..9",
        "1..x",
        "-1..5",
        "0..99999999999",
    ] {
        let e = parse_vcd_window(bad).unwrap_err();
        assert!(e.starts_with("--vcd-window:"), "{bad}: {e}");
    }
    let e = parse_vcd_window(&format!("0..{}", MAX_VCD_WINDOW_CLOCKS + 1)).unwrap_err();
    assert!(e.contains("at most"), "{e}");
    assert!(parse_vcd_window(&format!("7..{}", MAX_VCD_WINDOW_CLOCKS + 7)).is_ok());
}

#[test]
fn files_beside_out_and_the_window_per_pass() {
    let out = std::path::Path::new("dir/frame.png");
    let f = ChipFiles::for_render(out, None, true).unwrap().unwrap();
    assert_eq!(f.timeline_png, PathBuf::from("dir/frame.timeline.png"));
    assert_eq!(f.timeline_csv, PathBuf::from("dir/frame.timeline.csv"));
    assert_eq!(f.vcd, PathBuf::from("dir/frame.vcd"));
    assert_eq!(f.vcd_window, DEFAULT_VCD_WINDOW);
    let f = ChipFiles::for_render(out, Some("100..300"), true)
        .unwrap()
        .unwrap();
    assert_eq!(f.vcd_window, 100..300);
    assert_eq!(ChipFiles::for_render(out, None, false).unwrap(), None);
    let e = ChipFiles::for_render(out, Some("0..10"), false).unwrap_err();
    assert!(e.contains("--vcd-window") && e.contains("--timing"), "{e}");
    let e = ChipFiles::for_render(out, Some("10..0"), true).unwrap_err();
    assert!(e.contains("--vcd-window"), "{e}");
    // A frame window over passes starting at 0, 1 200, 51 200.
    let w = 1_000..1_500;
    assert_eq!(pass_window(&w, 0), Some(1_000..1_500));
    assert_eq!(pass_window(&w, 1_200), Some(0..300));
    assert_eq!(pass_window(&w, 51_200), None);
    assert_eq!(pass_window(&w, 1_500), None);
}

#[test]
fn chip_files_write_all_three_and_say_when_no_pass_traced() {
    let ft = frame("clocked");
    let f = ChipFiles::beside(&tmp("all.png"), 0..2_000);
    let notes = f.write(&ft).unwrap();
    assert_eq!(notes.len(), 3);
    // The traced clocks, cut at the frame's end (54 200 clocks).
    let f2 = ChipFiles::beside(&tmp("cut.png"), 50_000..60_000);
    let mut ft2 = frame("clocked");
    ft2.passes[0].timing.window = None;
    ft2.passes[1].timing.window = None;
    ft2.passes[2].timing.window = Some(trace(0..3_000, 5));
    let n2 = f2.write(&ft2).unwrap();
    assert!(
        n2[2].ends_with("clocks 50000..54200 of the frame)"),
        "{}",
        n2[2]
    );
    for p in f.paths() {
        assert!(p.exists(), "{}", p.display());
    }
    let mut ft = frame("clocked");
    for p in &mut ft.passes {
        p.timing.window = None;
    }
    let f = ChipFiles::beside(&tmp("none.png"), 60_000..61_000);
    let notes = f.write(&ft).unwrap();
    assert!(notes[2].starts_with("no VCD"), "{}", notes[2]);
    assert!(!f.vcd.exists());
}

#[test]
fn the_table_stays_within_its_width_on_long_names_and_big_numbers() {
    let long = "x".repeat(150);
    let mut ft = frame("sampled");
    ft.clock_hz = 1.0; // a frame of days: wide millisecond cells
    for p in &mut ft.passes {
        p.pass = format!("{} {long}", p.pass);
        p.timing.cycles *= 1_000_000_000;
        p.timing.bottleneck = long.clone();
        for s in &mut p.timing.stages {
            s.name = format!("{}{long}", s.name);
        }
        for f in &mut p.timing.fifos {
            f.name = format!("{}{long}", f.name);
        }
        let b: BTreeMap<String, u64> = p
            .timing
            .bytes_by_client
            .iter()
            .map(|(c, b)| (format!("{c}{long}"), b * 1_000_000_000))
            .collect();
        p.timing.bytes_by_client = b;
    }
    let t = ct::print_table(&ft);
    let widest = t.lines().map(|l| l.chars().count()).max().unwrap();
    assert!(widest <= MAX_TABLE_COLUMNS, "{widest} columns:\n{t}");
    // Every pass still has its row, its number and the start of its name.
    for (i, p) in ft.passes.iter().enumerate() {
        let head: String = p.pass.chars().take(5).collect();
        assert!(
            t.lines().any(|l| l.starts_with(&format!("{i}  {head}"))),
            "pass {i}"
        );
    }
}

#[test]
fn a_frame_of_many_passes_draws_a_bounded_key() {
    // 300 short passes: the key lists 120 in three columns and counts the rest; the
    // image stays a few hundred pixels high.
    let base = frame("clocked").passes[0].clone();
    let ft = FrameTiming {
        mode: "clocked".into(),
        chip: "geforce2-gts".into(),
        clock_hz: 200e6,
        passes: (0..300)
            .map(|i| {
                let mut p = base.clone();
                p.pass = format!("shadow map, light {i}");
                p.timing.window = None;
                p
            })
            .collect(),
        ..Default::default()
    };
    let path = tmp("many.timeline.png");
    ct::write_timeline_png(&ft, &path).unwrap();
    let img = image::open(&path).unwrap().to_rgb8();
    assert_eq!(img.width(), TIMELINE_WIDTH);
    assert!(img.height() < 1400, "{}", img.height());
    if let Ok(d) = std::env::var("CHIP_REPORT_KEEP") {
        std::fs::copy(&path, PathBuf::from(d).join("many.png")).unwrap();
    }
    let csv = tmp("many.timeline.csv");
    let rows = ct::write_timeline_csv(&ft, &csv).unwrap();
    // 300 × 120 buckets per stage are more than the CSV's 4096: each pass's buckets
    // merged k at a time, k = ⌈⌈300 · 1200 / 4096⌉ / 10⌉ = ⌈88 / 10⌉ = 9, so 14 rows
    // per pass and stage (13 of 9 buckets, the last of 3).
    assert_eq!(ct::TIMELINE_CSV_BUCKETS, 4096);
    assert_eq!(ct::timeline_csv_merge(&ft), vec![9; 300]);
    assert_eq!(rows, 300 * 3 * 14);
    // Each pass's rows per stage tile its clocks, and each holds the clock-weighted
    // mean of its buckets (here all of 10 clocks: the plain mean).
    let mut r = csv::Reader::from_path(&csv).unwrap();
    let starts = pass_starts(&ft);
    let mut next: std::collections::HashMap<(usize, String), (u64, usize)> = Default::default();
    for rec in r.records() {
        let rec = rec.unwrap();
        let (a, b): (u64, u64) = (rec[0].parse().unwrap(), rec[1].parse().unwrap());
        let i: usize = rec[2].parse().unwrap();
        let tl = &ft.passes[i].timing.timeline;
        let s = tl.stages.iter().position(|s| s == &rec[4]).unwrap();
        let (at, j) = next
            .entry((i, rec[4].to_string()))
            .or_insert((starts[i], 0));
        assert_eq!(a, *at, "pass {i} stage {s} row {j}");
        let bs = &tl.busy[s][*j * 9..(*j * 9 + 9).min(120)];
        assert_eq!(b - a, 10 * bs.len() as u64);
        let mean = bs.iter().map(|&v| v as f64).sum::<f64>() / bs.len() as f64;
        let v: f64 = rec[5].parse().unwrap();
        assert!(
            (v - mean).abs() < 1e-6,
            "pass {i} stage {s} row {j}: {v} vs {mean}"
        );
        (*at, *j) = (b, *j + 1);
    }
    for ((i, _), (at, j)) in next {
        assert_eq!((at, j), (starts[i] + 1_200, 14), "pass {i}");
    }
}

#[test]
fn a_frame_with_no_clocked_pass_writes_nothing_and_says_so() {
    let ft = FrameTiming {
        mode: "clocked".into(),
        chip: "geforce2-gts".into(),
        clock_hz: 200e6,
        ..Default::default()
    };
    let f = ChipFiles::beside(&tmp("empty.png"), DEFAULT_VCD_WINDOW);
    let notes = f.write(&ft).unwrap();
    assert_eq!(notes.len(), 1);
    assert!(
        notes[0].contains("no pass of the frame was clocked"),
        "{}",
        notes[0]
    );
    for p in f.paths() {
        assert!(!p.exists(), "{}", p.display());
    }
    assert!(ct::print_table(&ft).contains("no pass was clocked"));
    assert_eq!(ct::json(&ft)["cycles_total"], 0);
    // A trace at clocks no VCD time can hold is refused, not wrapped.
    let mut ft = frame("clocked");
    ft.passes[0].timing.cycles = u64::MAX / 1_000;
    let e = ct::vcd_bytes(&ft, Vec::new()).unwrap_err();
    assert!(e.contains("2^64 ps"), "{e}");
}
