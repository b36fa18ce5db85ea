//! f64 twin of `blend`: the GL / NV2A framebuffer blend on real values, and its
//! additive datapath (the saturating weighted sum the pipelines blend with).
//!
//! Colours are RGBA values in [0, 1] (index 3 is alpha); the factors are GL's table
//! (OpenGL 1.4 § 4.1.7); MIN and MAX ignore the factors; the NV2A's signed equations
//! read the source as a two's-complement signed value of the channel width (so the
//! twin takes codes for them, see [`blend_codes`]). The result is clamped into [0, 1].
//! Inputs outside [0, 1] are clamped into it and NaN reads as 0: no output is NaN.

use rtl_model::units::blend::{BlendEquation, BlendFactor};

fn unit_interval(x: f64) -> f64 {
    if x.is_nan() {
        0.0
    } else {
        x.clamp(0.0, 1.0)
    }
}

/// The factor `f` of channel `c` (3 = alpha) for source `s`, destination `d` and
/// constant colour `k`, all in [0, 1].
pub fn factor(f: BlendFactor, c: usize, s: &[f64; 4], d: &[f64; 4], k: &[f64; 4]) -> f64 {
    match f {
        BlendFactor::Zero => 0.0,
        BlendFactor::One => 1.0,
        BlendFactor::SrcColor => s[c],
        BlendFactor::OneMinusSrcColor => 1.0 - s[c],
        BlendFactor::SrcAlpha => s[3],
        BlendFactor::OneMinusSrcAlpha => 1.0 - s[3],
        BlendFactor::DstAlpha => d[3],
        BlendFactor::OneMinusDstAlpha => 1.0 - d[3],
        BlendFactor::DstColor => d[c],
        BlendFactor::OneMinusDstColor => 1.0 - d[c],
        BlendFactor::SrcAlphaSaturate if c == 3 => 1.0,
        BlendFactor::SrcAlphaSaturate => s[3].min(1.0 - d[3]),
        BlendFactor::ConstantColor => k[c],
        BlendFactor::OneMinusConstantColor => 1.0 - k[c],
        BlendFactor::ConstantAlpha => k[3],
        BlendFactor::OneMinusConstantAlpha => 1.0 - k[3],
    }
}

/// The blend of unsigned GL equations on values in [0, 1], clamped into [0, 1].
/// For the NV2A's signed equations, `src` must already be the signed value
/// (two's-complement code / (2ⁿ − 1), in [−1, 1]): see [`blend_codes`].
pub fn blend(
    eq: BlendEquation,
    sf: BlendFactor,
    df: BlendFactor,
    src: [f64; 4],
    dst: [f64; 4],
    constant: [f64; 4],
) -> [f64; 4] {
    let signed = matches!(
        eq,
        BlendEquation::AddSigned | BlendEquation::ReverseSubtractSigned
    );
    let s = src.map(|v| {
        if signed {
            if v.is_nan() {
                0.0
            } else {
                v.clamp(-1.0, 1.0)
            }
        } else {
            unit_interval(v)
        }
    });
    let d = dst.map(unit_interval);
    let k = constant.map(unit_interval);
    std::array::from_fn(|c| {
        let v = match eq {
            BlendEquation::Add => {
                s[c] * factor(sf, c, &s, &d, &k) + d[c] * factor(df, c, &s, &d, &k)
            }
            BlendEquation::Subtract => {
                s[c] * factor(sf, c, &s, &d, &k) - d[c] * factor(df, c, &s, &d, &k)
            }
            BlendEquation::ReverseSubtract => {
                d[c] * factor(df, c, &s, &d, &k) - s[c] * factor(sf, c, &s, &d, &k)
            }
            BlendEquation::Min => s[c].min(d[c]),
            BlendEquation::Max => s[c].max(d[c]),
            BlendEquation::AddSigned => d[c] + s[c],
            BlendEquation::ReverseSubtractSigned => d[c] - s[c],
        };
        v.clamp(0.0, 1.0)
    })
}

/// The blend on n-bit codes, in LSBs, not rounded (clamped into [0, 2ⁿ − 1]).
/// Codes are masked to n bits (n clamped to 1 ..= 16); for the signed equations the
/// source code is read as two's complement.
pub fn blend_codes(
    bits: u32,
    eq: BlendEquation,
    sf: BlendFactor,
    df: BlendFactor,
    src: [u32; 4],
    dst: [u32; 4],
    constant: [u32; 4],
) -> [f64; 4] {
    let n = bits.clamp(1, 16);
    let mask = (1u32 << n) - 1;
    let m = mask as f64;
    let signed = matches!(
        eq,
        BlendEquation::AddSigned | BlendEquation::ReverseSubtractSigned
    );
    let val = |v: u32| (v & mask) as f64 / m;
    let sval = |v: u32| {
        let v = (v & mask) as i64;
        let sx = if signed && v >> (n - 1) != 0 {
            v - (1i64 << n)
        } else {
            v
        };
        sx as f64 / m
    };
    blend(eq, sf, df, src.map(sval), dst.map(val), constant.map(val)).map(|v| v * m)
}

// ---------------------------------------------------------------------------------
// The additive datapath (ADD, ONE | CONSTANT_ALPHA, ONE): the saturating weighted sum
// min(d + s·w, 1), with helpers between unorm codes and values and to accumulate
// many planes.

/// All-ones code of an n-bit unorm, as f64 (n clamped to 1 ..= 32).
pub fn unorm_max(bits: u32) -> f64 {
    ((1u64 << bits.clamp(1, 32)) - 1) as f64
}

/// The value an n-bit unorm code stands for: code / (2ⁿ − 1).
pub fn unorm_value(code: u32, bits: u32) -> f64 {
    code as f64 / unorm_max(bits)
}

/// The additive blend on values: min(dst + src·weight, 1), dst, src, weight in [0, 1].
pub fn additive(dst: f64, src: f64, weight: f64) -> f64 {
    (unit_interval(dst) + unit_interval(src) * unit_interval(weight)).min(1.0)
}

/// The ideal contribution of a source code (and weight code, if any) to an f-bit
/// framebuffer, in framebuffer LSBs (not rounded): s/(2ˢ−1) · w/(2ᵏ−1) · (2ᶠ−1).
/// `weight` is `Some((w, weight_bits))` for CONSTANT_ALPHA, `None` for ONE.
pub fn contribution_codes(
    src: u32,
    src_bits: u32,
    fb_bits: u32,
    weight: Option<(u32, u32)>,
) -> f64 {
    let w = weight.map_or(1.0, |(w, bits)| unit_interval(unorm_value(w, bits)));
    unit_interval(unorm_value(src, src_bits)) * w * unorm_max(fb_bits)
}

/// The additive blend on codes, in framebuffer LSBs (not rounded):
/// min(dst + contribution, 2ᶠ − 1) with the ideal contribution of [`contribution_codes`].
pub fn additive_codes(
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
