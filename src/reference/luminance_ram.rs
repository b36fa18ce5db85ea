//! f64 twin of `luminance_ram`, the datapath both luminance modulators share: exact
//! bilinear interpolation of the shape samples, exact linear interpolation of a
//! falloff (or ring) profile, and the gain with saturation.

/// Exact bilinear interpolation of a (2ᵏ+1)² row-major shape grid over [−1, 1]² at
/// (u, v), each clamped to [−1, 1].
pub fn shape_distance(shape: &[f64], shape_log2: u32, u: f64, v: f64) -> f64 {
    let n = 1usize << shape_log2;
    let side = n + 1;
    let cell = |x: f64| {
        let p = (x.clamp(-1.0, 1.0) + 1.0) * (n as f64) / 2.0; // position in cells
        let i = (p.floor() as usize).min(n - 1);
        (i, p - i as f64)
    };
    let (i, tx) = cell(u);
    let (j, ty) = cell(v);
    let s = |i: usize, j: usize| shape[j * side + i];
    let r0 = s(i, j) + (s(i + 1, j) - s(i, j)) * tx;
    let r1 = s(i, j + 1) + (s(i + 1, j + 1) - s(i, j + 1)) * tx;
    r0 + (r1 - r0) * ty
}

/// Exact linear interpolation of a 2ᵐ+1-sample profile over [0, 1] at d ∈ [0, 1].
pub fn falloff(profile: &[f64], falloff_log2: u32, d: f64) -> f64 {
    let n = 1usize << falloff_log2;
    let p = d.clamp(0.0, 1.0) * n as f64;
    let j = (p.floor() as usize).min(n - 1);
    let t = p - j as f64;
    profile[j] + (profile[j + 1] - profile[j]) * t
}

/// p · gain per channel, saturated at `out_max`.
pub fn apply_gain(p: f64, gain: [f64; 3], out_max: f64) -> [f64; 3] {
    gain.map(|g| (p * g).min(out_max))
}

/// Radial-correction mode: d = clamp(e_interp(u, v) + κ·|(u, v)|, 0, 1), e the signed
/// shape samples (sdf_n − κ·|(u, v)| at the grid points), u and v clamped to [−1, 1]
/// for both the lookup and the radius.
pub fn radial_distance(e: &[f64], shape_log2: u32, kappa: f64, u: f64, v: f64) -> f64 {
    let (uc, vc) = (u.clamp(-1.0, 1.0), v.clamp(-1.0, 1.0));
    let d = shape_distance(e, shape_log2, uc, vc) + kappa * uc.hypot(vc);
    if d.is_nan() {
        0.0
    } else {
        d.clamp(0.0, 1.0)
    }
}
