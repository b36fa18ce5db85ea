//! `reproduce sim-speed`: the simulator's own wall time, measured in one
//! run so that ratios compare like with like on whatever machine runs it.
//!
//! - The Fig. 6(b) frame (built-in `fig6`, 720 × 480, n = 30, m = 6) bit-accurately
//!   through the units (`render_frame`, what `cargo bench --bench shafts` times),
//!   against its 180-sample f64 ray-march (`raymarch_image`, unchanged), each the best
//!   of `RUNS` runs, interleaved; the ratio is the figure of merit.
//! - The glare frames `glare-flare` and `leaves` and the environment-map built-in
//!   `env-venice_sunset-teapot` through the whole frame (`frame::run::render`, what
//!   `render --scene` runs), best of `RUNS`.
//!
//! Each frame's PNG bytes are hashed (FNV-1a) beside its time, so a speed change that
//! changed output shows at once. Written to DIR/sim_speed.csv and printed.

use crate::pipeline::shafts::frame::render_frame;
use crate::pipeline::shafts::host::prepare_scene;
use crate::pipeline::shafts::prepare::DEFAULT_EXPOSURE;
use crate::reference::raymarch::raymarch_image;
use crate::report::csv_out::write_csv;
use crate::scene::load::load_scene;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// Runs of each measurement; the best is reported (the least disturbed by anything
/// else on the machine).
pub const RUNS: usize = 3;

/// Built-ins timed through the whole frame besides Fig. 6(b).
pub const FRAMES: [&str; 2] = ["glare-flare", "leaves"];

/// One measured row.
#[derive(Clone, Debug, Serialize)]
pub struct SpeedRow {
    pub what: String,
    pub best_seconds: f64,
    pub runs: usize,
    /// FNV-1a of the frame's RGBA8 bytes (empty for the ray-march, which is f64).
    pub output_hash: String,
}

fn fnv1a(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// Best wall time of `runs` calls of `f`, and what the last call returned.
fn best_of<T>(runs: usize, mut f: impl FnMut() -> Result<T, String>) -> Result<(f64, T), String> {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..runs.max(1) {
        let t0 = Instant::now();
        let v = f()?;
        best = best.min(t0.elapsed().as_secs_f64());
        last = Some(v);
    }
    Ok((best, last.expect("at least one run")))
}

/// Measure every row; the Fig. 6(b) frame and its ray-march interleaved run by run.
pub fn measure(runs: usize) -> Result<Vec<SpeedRow>, String> {
    let scene = load_scene("fig6")?;
    let (p, geom) = prepare_scene(&scene, DEFAULT_EXPOSURE).map_err(|e| e.to_string())?;
    let (mut frame_best, mut march_best) = (f64::INFINITY, f64::INFINITY);
    let mut hash = String::new();
    for _ in 0..runs.max(1) {
        let t0 = Instant::now();
        let r = render_frame(&p).map_err(|e| e.to_string())?;
        frame_best = frame_best.min(t0.elapsed().as_secs_f64());
        hash = fnv1a(&r.fb.to_rgba8());
        let t0 = Instant::now();
        std::hint::black_box(raymarch_image(&scene, &geom, 180));
        march_best = march_best.min(t0.elapsed().as_secs_f64());
    }
    let mut rows = vec![
        SpeedRow {
            what: "fig6b_bit_accurate_frame".into(),
            best_seconds: frame_best,
            runs,
            output_hash: hash,
        },
        SpeedRow {
            what: "fig6b_raymarch_180_samples".into(),
            best_seconds: march_best,
            runs,
            output_hash: String::new(),
        },
    ];
    for name in FRAMES {
        let s = load_scene(name)?;
        let (t, frame) = best_of(runs, || {
            crate::frame::run::render(&s).map_err(|e| e.to_string())
        })?;
        rows.push(SpeedRow {
            what: name.to_string(),
            best_seconds: t,
            runs,
            output_hash: fnv1a(&frame.fb.to_rgba8()),
        });
    }
    Ok(rows)
}

/// `reproduce sim-speed --out DIR`.
pub fn sim_speed(out: &Path) -> Result<(), String> {
    let rows = measure(RUNS)?;
    println!("{:<28} {:>12}  output hash", "frame", "best (s)");
    for r in &rows {
        println!("{:<28} {:>12.3}  {}", r.what, r.best_seconds, r.output_hash);
    }
    let ratio = rows[0].best_seconds / rows[1].best_seconds;
    println!("Fig. 6(b): bit-accurate frame / 180-sample ray-march = {ratio:.2}");
    write_csv(&out.join("sim_speed.csv"), &rows)?;
    println!("wrote {}", out.join("sim_speed.csv").display());
    Ok(())
}
