//! `clipper`: near/far and guard-band clipping before the polygon interpolator.

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use rand::Rng;
use rtl_model::units::clipper::{ClipIn, ClipStats, Clipper};
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "clipper",
    summary: || UnitSummary::of(&Clipper::geforce()),
    tables: Vec::new,
    trace,
};

/// `pixels` random triangles in clip space (w in 0.5 ..= 4, x/w and y/w up to ±12, so
/// some pass, some are cut by the guard band or the near plane, some are culled).
fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = Clipper::geforce();
    let mut ctr = Counters::default();
    let mut inputs = Vec::with_capacity(pixels);
    for _ in 0..pixels {
        let mut tri = ClipIn::default();
        for (k, v) in tri.v.iter_mut().enumerate() {
            let ww: f64 = rng.random_range(0.5..4.0);
            let c = [
                rng.random_range(-12.0..12.0) * ww,
                rng.random_range(-12.0..12.0) * ww,
                rng.random_range(-1.5..1.0) * ww,
                ww,
            ];
            let attrs: Vec<f64> = (0..u.attrs()).map(|_| rng.random_range(0.0..1.0)).collect();
            *v = u
                .vertex_from_f64(k, c, &attrs, &mut ctr)
                .map_err(|e| e.to_string())?;
        }
        inputs.push(tri);
    }
    trace_unit(&u, ClipStats::default(), &inputs, w)
}
