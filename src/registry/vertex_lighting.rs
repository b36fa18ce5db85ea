//! `vertex_lighting`: GL fixed-function lighting of a vertex in a narrow float format.

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use crate::tables::Table;
use rand::Rng;
use rtl_model::units::vertex_lighting::{
    LightingSetup, VertexLighting, VertexLightingConfig, VertexLightingIn,
};
use rtl_model::{Counters, UnitSummary};
use std::collections::BTreeMap;
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "vertex_lighting",
    summary: || UnitSummary::of(&VertexLighting::geforce()),
    tables,
    trace,
};

/// The pow unit's exp2 constants.
fn tables() -> Vec<Table> {
    let vl = VertexLighting::geforce();
    let f = vl.format();
    let k = f.pow_frac_bits();
    vec![Table {
        name: format!("vertex_lighting_exp2_{k}x{}", k + 1),
        width: k + 1,
        words: f.exp2_rom(),
        unit: "vertex_lighting".into(),
        params: BTreeMap::from([
            ("exp_bits".to_string(), f.exp_bits.to_string()),
            ("mant_bits".to_string(), f.mant_bits.to_string()),
            ("pow_frac_bits".to_string(), k.to_string()),
            (
                "generator".to_string(),
                "entry[k-1] = 2^(2^-k) in u1.K, k = 1 ..= K = M + 4: K integer square roots from 2 at K + 16 bits, rounded to K (the pow unit's exp2 constants); rtl_model/src/float_format.rs".to_string(),
            ),
        ]),
    }]
}

/// GL's default state (GL_LIGHT0, default material with a specular term), vertices on
/// a sphere of radius 1 at z = −4, normals of varying length (GL_NORMALIZE), now and
/// then a zero-length one.
fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let cfg = VertexLightingConfig::geforce();
    let mut setup = LightingSetup::default();
    setup.material.specular = [0.8; 3];
    setup.material.shininess = 32.0;
    let u = VertexLighting::new(cfg, &setup).map_err(|e| e.to_string())?;
    let mut ctr = Counters::default();
    let inputs: Vec<VertexLightingIn> = (0..pixels)
        .map(|k| {
            let n: [f64; 3] = [(); 3].map(|_| rng.random_range(-1.0..1.0));
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt().max(1e-3);
            let scale = if k % 8 == 7 {
                0.0
            } else {
                rng.random_range(0.5..2.0)
            };
            let p = [0, 1, 2].map(|i| n[i] / len + if i == 2 { -4.0 } else { 0.0 });
            u.vertex_from_f64(p, n.map(|c| c / len * scale), &mut ctr)
                .map_err(|e| e.to_string())
        })
        .collect::<Result<_, _>>()?;
    trace_unit(&u, (), &inputs, w)
}
