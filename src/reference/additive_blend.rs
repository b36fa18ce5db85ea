//! f64 twin of `additive_blend`: the saturating weighted sum min(d + s·w, 1) on values
//! in [0, 1], with helpers to go between unorm codes and values and to accumulate many
//! planes. Inputs outside [0, 1] are clamped into it and NaN reads as 0, so no output
//! is ever NaN.

/// A value clamped into [0, 1]; NaN reads as 0.
fn unit_interval(x: f64) -> f64 {
    if x.is_nan() {
        0.0
    } else {
        x.clamp(0.0, 1.0)
    }
}

/// All-ones code of an n-bit unorm, as f64 (n clamped to 1 ..= 32).
pub fn unorm_max(bits: u32) -> f64 {
    ((1u64 << bits.clamp(1, 32)) - 1) as f64
}

/// The value an n-bit unorm code stands for: code / (2ⁿ − 1).
pub fn unorm_value(code: u32, bits: u32) -> f64 {
    code as f64 / unorm_max(bits)
}

/// The blend on values: min(dst + src·weight, 1), dst, src, weight in [0, 1].
pub fn additive_blend(dst: f64, src: f64, weight: f64) -> f64 {
    (unit_interval(dst) + unit_interval(src) * unit_interval(weight)).min(1.0)
}

/// The ideal contribution of a source code (and weight code, if any) to an f-bit
/// framebuffer, in framebuffer LSBs (not rounded): s/(2ˢ−1) · w/(2ᵏ−1) · (2ᶠ−1).
/// `weight` is `Some((w, weight_bits))` for the weighted path, `None` for GL_ONE.
pub fn contribution_codes(
    src: u32,
    src_bits: u32,
    fb_bits: u32,
    weight: Option<(u32, u32)>,
) -> f64 {
    let w = weight.map_or(1.0, |(w, bits)| unit_interval(unorm_value(w, bits)));
    unit_interval(unorm_value(src, src_bits)) * w * unorm_max(fb_bits)
}

/// The blend on codes, in framebuffer LSBs (not rounded):
/// min(dst + contribution, 2ᶠ − 1) with the ideal contribution of [`contribution_codes`].
pub fn additive_blend_codes(
    src: u32,
    dst: u32,
    src_bits: u32,
    fb_bits: u32,
    weight: Option<(u32, u32)>,
) -> f64 {
    let max = unorm_max(fb_bits);
    let d = (dst as f64).min(max);
    (d + contribution_codes(src, src_bits, fb_bits, weight)).min(max)
}

/// Accumulate `planes` equal contributions into a starting value, saturating at
/// `full_scale` (1.0 for values, 2ᶠ − 1 for framebuffer LSBs): d ← min(d + c, full_scale).
/// Returns the final value and how many of the adds clamped (d + c > full_scale).
/// Negative, NaN or infinite arguments are treated as 0 (full_scale as 1).
pub fn accumulate_planes(
    start: f64,
    contribution: f64,
    planes: u64,
    full_scale: f64,
) -> (f64, u64) {
    let finite_pos = |x: f64| if x.is_finite() && x > 0.0 { x } else { 0.0 };
    let top = if full_scale.is_finite() && full_scale > 0.0 {
        full_scale
    } else {
        1.0
    };
    let c = finite_pos(contribution);
    let mut d = finite_pos(start).min(top);
    let mut clamps = 0u64;
    for i in 0..planes {
        if d + c > top {
            if d == top {
                // Saturated: every remaining add (c > 0) clamps too.
                clamps += planes - i;
                break;
            }
            clamps += 1;
            d = top;
        } else {
            d += c;
        }
    }
    (d, clamps)
}
