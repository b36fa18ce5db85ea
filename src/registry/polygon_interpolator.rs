//! `polygon_interpolator`: the rasteriser's incremental attribute interpolator.

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use rand::Rng;
use rtl_model::units::polygon_interpolator::PolygonInterpolator;
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "polygon_interpolator",
    summary: || UnitSummary::of(&PolygonInterpolator::geforce()),
    tables: Vec::new,
    trace,
};

/// One small triangle with four random attributes, walked for `pixels` moves.
fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = PolygonInterpolator::geforce();
    let mut ctr = Counters::default();
    let mut vert = |i: usize, x: f64, y: f64| {
        let attrs: Vec<f64> = (0..4).map(|_| rng.random_range(-4.0..4.0)).collect();
        u.vertex_from_f64(i, x, y, &attrs, &mut ctr)
            .map_err(|e| e.to_string())
    };
    let v = [vert(0, 0.5, 0.5)?, vert(1, 5.5, 1.0)?, vert(2, 1.0, 4.5)?];
    let s = u.setup_triangle(&v, &mut ctr);
    let moves: Vec<_> = s.moves().into_iter().take(pixels).collect();
    trace_unit(&u, s.state.clone(), &moves, w)
}
