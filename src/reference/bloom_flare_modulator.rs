//! f64 twin of `bloom_flare_modulator`: the same algorithm at infinite precision —
//! exact bilinear interpolation of the (unquantised) shape samples at the exact
//! (u, v), exact linear interpolation of the falloff samples at that exact d, times
//! the exact gain, saturated at the output's largest code.

pub use super::luminance_ram::{apply_gain, falloff, radial_distance, shape_distance};

/// The whole modulator: (d, [lum_r, lum_g, lum_b]) in real units (d ∈ [0, 1],
/// luminance in framebuffer codes).
#[allow(clippy::too_many_arguments)]
pub fn bloom_flare_modulator(
    shape: &[f64],
    shape_log2: u32,
    profile: &[f64],
    falloff_log2: u32,
    u: f64,
    v: f64,
    gain: [f64; 3],
    out_max: f64,
) -> (f64, [f64; 3]) {
    let d = shape_distance(shape, shape_log2, u, v);
    let p = falloff(profile, falloff_log2, d);
    (d, apply_gain(p, gain, out_max))
}

/// The modulator in radial-correction mode: `e` the signed shape samples, `kappa` the
/// loaded κ value; d = clamp(e_interp + κ·|(u, v)|, 0, 1), then as above.
#[allow(clippy::too_many_arguments)]
pub fn bloom_flare_modulator_radial(
    e: &[f64],
    shape_log2: u32,
    kappa: f64,
    profile: &[f64],
    falloff_log2: u32,
    u: f64,
    v: f64,
    gain: [f64; 3],
    out_max: f64,
) -> (f64, [f64; 3]) {
    let d = radial_distance(e, shape_log2, kappa, u, v);
    let p = falloff(profile, falloff_log2, d);
    (d, apply_gain(p, gain, out_max))
}
