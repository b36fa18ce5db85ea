//! f64 twin of `register_combiner`: one general combiner stage of
//! GL_NV_register_combiners as the spec writes it, on reals (section 3.8.12.2):
//! the input mappings of Table NV_register_combiners.4, the products gcc1/gcc3 and dot
//! products gcc2/gcc4 (replicated to R, G, B), the sum gcc5 or the mux gcc6 (SPARE0
//! alpha ≥ 0.5 → C·D, else A·B), and out = max(min((gcc + cbias)·cscale, 1), −1).
//! NV2A variants: the bias as a real ([`nv2a_bias`]: −128/255 at 9 bits), the mux on
//! SPARE0 alpha's low bit ([`mux_lsb_selects_cd`]), blue-to-alpha ([`blue_to_alpha`]).
//! Non-finite inputs read as 0 and finite ones are held within f64::MAX / 2, so no NaN
//! or ∞ comes out.

/// Table NV_register_combiners.4, by the spec's names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mapping {
    UnsignedIdentity,
    UnsignedInvert,
    ExpandNormal,
    ExpandNegate,
    HalfBiasNormal,
    HalfBiasNegate,
    SignedIdentity,
    SignedNegate,
}

/// The mapping function of Table NV_register_combiners.4 on one element `e`. NaN or ±∞
/// reads as 0, and |e| is held within f64::MAX / 2 (no register comes near it), so
/// EXPAND_NORMAL's 2e − 1 cannot overflow to ∞ (proptest `twin_never_nan` found
/// e = 1.25e308); every other value maps exactly as the table says.
pub fn map(m: Mapping, e: f64) -> f64 {
    let e = if e.is_finite() {
        e.clamp(-f64::MAX / 2.0, f64::MAX / 2.0)
    } else {
        0.0
    };
    match m {
        Mapping::UnsignedIdentity => e.max(0.0),
        Mapping::UnsignedInvert => 1.0 - e.clamp(0.0, 1.0), // 1 − min(max(e, 0), 1)
        Mapping::ExpandNormal => 2.0 * e.max(0.0) - 1.0,
        Mapping::ExpandNegate => -2.0 * e.max(0.0) + 1.0,
        Mapping::HalfBiasNormal => e.max(0.0) - 0.5,
        Mapping::HalfBiasNegate => -e.max(0.0) + 0.5,
        Mapping::SignedIdentity => e,
        Mapping::SignedNegate => -e,
    }
}

/// max(min(x, 1), −1) (NaN reads as 0).
pub fn clamp_signed(x: f64) -> f64 {
    if x.is_nan() {
        0.0
    } else {
        x.clamp(-1.0, 1.0)
    }
}

/// CombinerOutputNV's operation of one portion (scale and bias as reals: cscale ∈
/// {1, 2, 4, ½}, cbias ∈ {0, −½}).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutputOp {
    pub ab_dot_product: bool,
    pub cd_dot_product: bool,
    pub mux_sum: bool,
    pub scale: f64,
    pub bias: f64,
}

/// max(min((x + cbias)·cscale, 1), −1).
pub fn output(x: f64, op: &OutputOp) -> f64 {
    clamp_signed((x + op.bias) * op.scale)
}

/// The mux ("or") of gcc6/gcc4a: the right operand (C·D) when SPARE0 alpha ≥ 0.5.
pub fn mux(spare0_alpha: f64, ab: f64, cd: f64) -> f64 {
    if spare0_alpha >= 0.5 {
        cd
    } else {
        ab
    }
}

/// The NV2A's mux test (combiner control MUX_SELECT = LSB, its reset value): C·D when
/// SPARE0 alpha's register code, round(a·S) at S = `one`, is odd.
pub fn mux_lsb_selects_cd(spare0_alpha: f64, one: f64) -> bool {
    let c = if spare0_alpha.is_finite() {
        (spare0_alpha * one).round().clamp(-1e15, 1e15) as i64
    } else {
        0
    };
    c & 1 == 1
}

/// The NV2A's BIAS_BY_NEGATIVE_ONE_HALF as a real at register width N: the code
/// 2^(N−2) over S = 2^(N−1) − 1 (128/255 at N = 9), negated.
pub fn nv2a_bias(internal_bits: u32) -> f64 {
    let s = ((1u64 << (internal_bits - 1)) - 1) as f64;
    -((1u64 << (internal_bits - 2)) as f64) / s
}

/// The RGB portion on mapped variables A, B, C, D: [out1rgb, out2rgb, out3rgb].
pub fn general_rgb(v: [[f64; 3]; 4], spare0_alpha: f64, op: &OutputOp) -> [[f64; 3]; 3] {
    general_rgb_mux(v, spare0_alpha >= 0.5, op)
}

/// [`general_rgb`] with the mux's choice given (`mux_cd`: C·D), for a mux test other
/// than the spec's SPARE0 alpha ≥ 0.5 ([`mux_lsb_selects_cd`]).
pub fn general_rgb_mux(v: [[f64; 3]; 4], mux_cd: bool, op: &OutputOp) -> [[f64; 3]; 3] {
    let [a, b, c, d] = v;
    let lane = |x: [f64; 3], y: [f64; 3]| [0, 1, 2].map(|i| x[i] * y[i]);
    let dot = |x: [f64; 3], y: [f64; 3]| [x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; 3];
    let gcc_ab = if op.ab_dot_product {
        dot(a, b)
    } else {
        lane(a, b)
    }; // gcc1 / gcc2
    let gcc_cd = if op.cd_dot_product {
        dot(c, d)
    } else {
        lane(c, d)
    }; // gcc3 / gcc4
    let out3 = [0, 1, 2].map(|i| {
        if op.mux_sum {
            if mux_cd {
                gcc_cd[i]
            } else {
                gcc_ab[i]
            } // gcc6
        } else {
            gcc_ab[i] + gcc_cd[i] // gcc5
        }
    });
    [gcc_ab, gcc_cd, out3].map(|g| g.map(|x| output(x, op)))
}

/// The alpha portion on mapped variables Aa, Ba, Ca, Da: [out1a, out2a, out3a].
pub fn general_alpha(v: [f64; 4], spare0_alpha: f64, op: &OutputOp) -> [f64; 3] {
    general_alpha_mux(v, spare0_alpha >= 0.5, op)
}

/// [`general_alpha`] with the mux's choice given (`mux_cd`: C·D).
pub fn general_alpha_mux(v: [f64; 4], mux_cd: bool, op: &OutputOp) -> [f64; 3] {
    let [a, b, c, d] = v;
    let (g1, g2) = (a * b, c * d);
    let g3 = if op.mux_sum {
        if mux_cd {
            g2
        } else {
            g1
        }
    } else {
        g1 + g2
    };
    [g1, g2, g3].map(|x| output(x, op))
}

/// The NV2A's blue-to-alpha (AB_BLUE_TO_ALPHA / CD_BLUE_TO_ALPHA): the alpha an RGB
/// output gives its register, its blue.
pub fn blue_to_alpha(out_rgb: [f64; 3]) -> f64 {
    out_rgb[2]
}

/// An n-bit unorm code as a real: u / (2ⁿ − 1).
pub fn unorm(u: u32, bits: u32) -> f64 {
    u as f64 / ((1u64 << bits) - 1) as f64
}
