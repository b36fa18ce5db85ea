//! What the two glare modulators (`bloom_flare_modulator`, `halo_modulator`) share in
//! the registry, as they share `rtl_model::units::luminance_ram`: the parameters of
//! their shape and falloff tables and the random inputs of their traces.

use super::unit_entry::params;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rtl_model::units::luminance_ram::{LumIn, LumWidths};
use std::collections::BTreeMap;

/// A shape table's parameters: its widths, then `extra`.
pub fn shape_params(w: &LumWidths, extra: &[(&str, String)]) -> BTreeMap<String, String> {
    let mut p = params(&[
        ("shape_log2", w.shape_log2.to_string()),
        ("shape_bits", w.shape_bits.to_string()),
    ]);
    p.extend(params(extra));
    p
}

/// A falloff (or ring) table's parameters: its widths, then `extra`.
pub fn falloff_params(w: &LumWidths, extra: &[(&str, String)]) -> BTreeMap<String, String> {
    let mut p = params(&[
        ("falloff_log2", w.falloff_log2.to_string()),
        ("falloff_bits", w.falloff_bits.to_string()),
    ]);
    p.extend(params(extra));
    p
}

/// `pixels` random modulator inputs: (u, v) over ±1.25 (the clamp region included),
/// gains up to 255 codes.
pub fn random_inputs(rng: &mut ChaCha8Rng, pixels: usize) -> Vec<LumIn> {
    let lw = LumWidths::default();
    let one = 1i32 << lw.coord_frac_bits;
    let lim = one + one / 4;
    let gmax = 255u32 << lw.gain_frac_bits;
    (0..pixels)
        .map(|_| LumIn {
            u: rng.random_range(-lim..=lim),
            v: rng.random_range(-lim..=lim),
            gain: std::array::from_fn(|_| rng.random_range(0..=gmax)),
        })
        .collect()
}
