//! `texture_sampler`: the 1D/2D/3D nearest/linear texture unit. Its tables are the
//! built-in test scene's textures (the default instance holds a zero texture).

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use crate::pipeline::test_scene;
use crate::tables::Table;
use rand::Rng;
use rtl_model::units::texture_sampler::{TextureSampler, TextureSamplerConfig, TextureSamplerIn};
use rtl_model::{Counters, UnitSummary};
use std::collections::BTreeMap;
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "texture_sampler",
    summary: || UnitSummary::of(&default_sampler()),
    tables,
    trace,
};

/// The default texture sampler (2D 256 × 256 luminance), holding a zero texture.
fn default_sampler() -> TextureSampler {
    let cfg = TextureSamplerConfig::geforce();
    let texels = vec![0u32; cfg.texel_count() as usize];
    TextureSampler::new(cfg, &texels).expect("the GeForce default sampler config is valid")
}

/// The built-in test scene's checker and light-map textures.
fn tables() -> Vec<Table> {
    let scene_param = |what: &str| {
        BTreeMap::from([
            (
                "scene".to_string(),
                "built-in test scene (render)".to_string(),
            ),
            ("generator".to_string(), what.to_string()),
        ])
    };
    vec![
        Table {
            name: "test_scene_checker_rgba8_64x64".into(),
            width: 8,
            words: test_scene::checker_texels()
                .into_iter()
                .map(u64::from)
                .collect(),
            unit: "texture_sampler".into(),
            params: scene_param(
                "8x8-texel squares (235,228,210) / (70,96,140), alpha 255; texel (x,y) channel c at ((y*64+x)*4+c)",
            ),
        },
        Table {
            name: "test_scene_lightmap_l8_64x64".into(),
            width: 8,
            words: test_scene::lightmap_texels()
                .into_iter()
                .map(u64::from)
                .collect(),
            unit: "texture_sampler".into(),
            params: scene_param(
                "spot disc: 255 inside r=0.3, linear in r^2 to 0 at r=0.45 (map units)",
            ),
        },
    ]
}

/// A 16 × 16 random texture, read at random coordinates.
fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let cfg = TextureSamplerConfig::geforce_2d(16, 16);
    let texels: Vec<u32> = (0..256).map(|_| rng.random_range(0..=255)).collect();
    let u = TextureSampler::new(cfg, &texels).map_err(|e| e.to_string())?;
    let inputs: Vec<TextureSamplerIn> = (0..pixels)
        .map(|_| TextureSamplerIn {
            coord: [
                rng.random_range(0..16 << 8),
                rng.random_range(0..16 << 8),
                0,
            ],
        })
        .collect();
    trace_unit(&u, (), &inputs, w)
}
