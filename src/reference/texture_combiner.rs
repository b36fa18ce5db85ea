//! f64 twin of `texture_combiner`: the COMBINE functions of GL_ARB_texture_env_combine
//! and GL_ARB_texture_env_dot3 (OpenGL 1.3 §3.8.13, Table 3.20) on real values in
//! [0, 1], exactly as the spec writes them, then the scale and the clamp to [0, 1].
//! Arguments arrive already selected (SOURCEi_*) and mapped (OPERANDi_*, see
//! [`operand`]). Non-finite values read as 0, so no NaN comes out.

fn finite(x: f64) -> f64 {
    if x.is_finite() {
        x
    } else {
        0.0
    }
}

/// OPERANDi mapping: SRC_COLOR / SRC_ALPHA give the value, ONE_MINUS_* give 1 − it.
pub fn operand(value: f64, one_minus: bool) -> f64 {
    if one_minus {
        1.0 - value
    } else {
        value
    }
}

/// REPLACE: Arg0.
pub fn replace(arg0: f64) -> f64 {
    arg0
}

/// MODULATE: Arg0 · Arg1.
pub fn modulate(arg0: f64, arg1: f64) -> f64 {
    arg0 * arg1
}

/// ADD: Arg0 + Arg1.
pub fn add(arg0: f64, arg1: f64) -> f64 {
    arg0 + arg1
}

/// ADD_SIGNED: Arg0 + Arg1 − 0.5.
pub fn add_signed(arg0: f64, arg1: f64) -> f64 {
    arg0 + arg1 - 0.5
}

/// INTERPOLATE: Arg0 · Arg2 + Arg1 · (1 − Arg2).
pub fn interpolate(arg0: f64, arg1: f64, arg2: f64) -> f64 {
    arg0 * arg2 + arg1 * (1.0 - arg2)
}

/// SUBTRACT: Arg0 − Arg1.
pub fn subtract(arg0: f64, arg1: f64) -> f64 {
    arg0 - arg1
}

/// DOT3_RGB / DOT3_RGBA: 4·((Arg0r − 0.5)(Arg1r − 0.5) + (Arg0g − 0.5)(Arg1g − 0.5)
/// + (Arg0b − 0.5)(Arg1b − 0.5)), the scalar placed into r, g, b (and a for DOT3_RGBA).
pub fn dot3(arg0: [f64; 3], arg1: [f64; 3]) -> f64 {
    4.0 * (0..3)
        .map(|c| (arg0[c] - 0.5) * (arg1[c] - 0.5))
        .sum::<f64>()
}

/// RGB_SCALE / ALPHA_SCALE, then the clamp to [0, 1].
pub fn scale_and_clamp(value: f64, scale: f64) -> f64 {
    (finite(value) * finite(scale)).clamp(0.0, 1.0)
}
