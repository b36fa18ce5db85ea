//! f64 twin of `halo_modulator`: exact bilinear interpolation of the shape samples at
//! the exact (u, v), then per channel exact linear interpolation of that channel's ring
//! profile at the exact d, times the exact channel gain, saturated at the output's
//! largest code. (Shares the interpolation functions of the bloom/flare twin.)

use super::luminance_ram::{falloff, radial_distance, shape_distance};

/// (d, [lum_r, lum_g, lum_b]) in real units (d ∈ [0, 1], luminance in framebuffer
/// codes); `rings` are the R, G, B ring profiles (2ᵐ+1 samples each).
#[allow(clippy::too_many_arguments)]
pub fn halo_modulator(
    shape: &[f64],
    shape_log2: u32,
    rings: [&[f64]; 3],
    falloff_log2: u32,
    u: f64,
    v: f64,
    gain: [f64; 3],
    out_max: f64,
) -> (f64, [f64; 3]) {
    let d = shape_distance(shape, shape_log2, u, v);
    let mut lum = [0.0; 3];
    for c in 0..3 {
        lum[c] = (falloff(rings[c], falloff_log2, d) * gain[c]).min(out_max);
    }
    (d, lum)
}

/// The halo modulator in radial-correction mode (`e` signed samples, κ the loaded
/// value): d = clamp(e_interp + κ·|(u, v)|, 0, 1), then the rings as above.
#[allow(clippy::too_many_arguments)]
pub fn halo_modulator_radial(
    e: &[f64],
    shape_log2: u32,
    kappa: f64,
    rings: [&[f64]; 3],
    falloff_log2: u32,
    u: f64,
    v: f64,
    gain: [f64; 3],
    out_max: f64,
) -> (f64, [f64; 3]) {
    let d = radial_distance(e, shape_log2, kappa, u, v);
    let mut lum = [0.0; 3];
    for c in 0..3 {
        lum[c] = (falloff(rings[c], falloff_log2, d) * gain[c]).min(out_max);
    }
    (d, lum)
}

/// Ring centre for wavelength λ (nm), Matsuda and Ikedo eq. (5): θ₁ · λ / 568.
pub fn ring_radius(theta1: f64, lambda_nm: f64) -> f64 {
    theta1 * lambda_nm / 568.0
}
