//! f64 twin of `final_combiner`: the final combiner of GL_NV_register_combiners on
//! reals (section 3.8.12.3):
//!
//!   fcoc = [ min(A·B + (1 − A)·C + D, 1) per R, G, B ;  G ]
//!
//! with the pseudo-registers E_TIMES_F_NV = E·F and SPARE0_PLUS_SECONDARY_COLOR_NV =
//! max(0, SPARE0) + max(0, SECONDARY) (clamped to [0, 1] under COLOR_SUM_CLAMP_NV).
//! The mappings are Table 4's unsigned pair ([`map`] of the general combiner's twin).
//! Non-finite inputs read as 0, so no NaN comes out.

pub use crate::reference::register_combiner::{map, Mapping};

/// E_TIMES_F_NV on mapped E and F.
pub fn e_times_f(e: [f64; 3], f: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| finite(e[i]) * finite(f[i]))
}

/// SPARE0_PLUS_SECONDARY_COLOR_NV: both under UNSIGNED_IDENTITY, summed, clamped to
/// [0, 1] when `color_sum_clamp`.
pub fn spare0_plus_secondary_color(
    spare0: [f64; 3],
    secondary: [f64; 3],
    color_sum_clamp: bool,
) -> [f64; 3] {
    spare0_plus_secondary_color_inverted(spare0, secondary, [false, false], color_sum_clamp)
}

/// The NV2A's form: SPARE0 (`invert[0]`, SPECULAR_ADD_INVERT_R0) and SECONDARY_COLOR
/// (`invert[1]`, SPECULAR_ADD_INVERT_V1) each under UNSIGNED_INVERT instead of
/// UNSIGNED_IDENTITY when set.
pub fn spare0_plus_secondary_color_inverted(
    spare0: [f64; 3],
    secondary: [f64; 3],
    invert: [bool; 2],
    color_sum_clamp: bool,
) -> [f64; 3] {
    let m = |inv: bool| {
        if inv {
            Mapping::UnsignedInvert
        } else {
            Mapping::UnsignedIdentity
        }
    };
    [0, 1, 2].map(|i| {
        let s = map(m(invert[0]), spare0[i]) + map(m(invert[1]), secondary[i]);
        if color_sum_clamp {
            s.min(1.0)
        } else {
            s
        }
    })
}

/// fcoc's RGB on mapped A, B, C, D: min(A·B + (1 − A)·C + D, 1) per lane. Mapped
/// values are ≥ 0, so the result is in [0, 1]; values outside the mappings' range are
/// clamped into it too (no ±∞ or NaN comes out).
pub fn fcoc_rgb(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| {
        let (a, b, c, d) = (finite(a[i]), finite(b[i]), finite(c[i]), finite(d[i]));
        finite(a * b + (1.0 - a) * c + d).clamp(0.0, 1.0)
    })
}

/// A real in [0, 1] in output LSBs of an n-bit unorm: v·(2ⁿ − 1).
pub fn to_unorm_lsb(v: f64, bits: u32) -> f64 {
    finite(v) * ((1u64 << bits) - 1) as f64
}

fn finite(x: f64) -> f64 {
    if x.is_finite() {
        x
    } else {
        0.0
    }
}
