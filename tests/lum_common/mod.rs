//! Shared by tests/bloom_flare_modulator.rs and tests/halo_modulator.rs: width
//! configs, random tables (smooth and rough) and the width-derived error bound.
#![allow(dead_code)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::units::luminance_ram::{LumWidths, Radial};

/// Width configs the property tests run: defaults, a wide one, two narrow ones
/// (one with truncated shape weights, one with k > F+1 and m > sb).
pub fn configs() -> Vec<LumWidths> {
    vec![
        LumWidths::default(),
        LumWidths {
            coord_frac_bits: 14,
            shape_log2: 5,
            shape_bits: 16,
            falloff_log2: 10,
            falloff_bits: 20,
            weight_bits: 12,
            gain_int_bits: 16,
            gain_frac_bits: 16,
            out_bits: 16,
            radial: Radial::default(),
        },
        // Narrow: 3-bit entries, 2-bit weights truncating a 7-bit cell fraction.
        LumWidths {
            coord_frac_bits: 8,
            shape_log2: 2,
            shape_bits: 3,
            falloff_log2: 2,
            falloff_bits: 3,
            weight_bits: 2,
            gain_int_bits: 3,
            gain_frac_bits: 1,
            out_bits: 4,
            radial: Radial::default(),
        },
        // Narrow the other way: coordinates coarser than the grid, m > sb, 1-bit weights.
        LumWidths {
            coord_frac_bits: 2,
            shape_log2: 6,
            shape_bits: 6,
            falloff_log2: 12,
            falloff_bits: 8,
            weight_bits: 1,
            gain_int_bits: 0,
            gain_frac_bits: 4,
            out_bits: 1,
            radial: Radial::default(),
        },
    ]
}

/// A random shape table: kind 0 = rotated ellipse distance (smooth, clamped to 1),
/// 1 = uniform random samples (rough), 2 = capsule/"eggplant" distance with exact
/// 0/1 plateaus, 3 = a random 0/1 checkerboard (maximal neighbour jumps).
pub fn shape_table(w: &LumWidths, kind: u32, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let side = w.shape_side();
    let n = (side - 1) as f64;
    let coord = |i: usize| -1.0 + 2.0 * i as f64 / n;
    let a: f64 = rng.random_range(0.2..1.5);
    let b: f64 = rng.random_range(0.2..1.5);
    let th: f64 = rng.random_range(0.0..std::f64::consts::PI);
    let (c, s) = (th.cos(), th.sin());
    let mut t = Vec::with_capacity(side * side);
    for j in 0..side {
        for i in 0..side {
            let (u, v) = (coord(i), coord(j));
            let x = match kind % 4 {
                0 => {
                    let (p, q) = (c * u + s * v, -s * u + c * v);
                    ((p / a).powi(2) + (q / b).powi(2)).sqrt()
                }
                1 => rng.random_range(0.0..=1.0),
                2 => {
                    // Capsule along a rotated axis, fatter at one end ("eggplant").
                    let (p, q) = (c * u + s * v, -s * u + c * v);
                    let pc = p.clamp(-0.5, 0.5);
                    let r = 0.2 + 0.2 * (pc + 0.5) * a;
                    (((p - pc).powi(2) + q.powi(2)).sqrt() / r - 0.5).max(0.0)
                }
                _ => f64::from(rng.random_bool(0.5)),
            };
            t.push(x.clamp(0.0, 1.0));
        }
    }
    t
}

/// A random falloff profile: kind 0 = (1 − d)^γ, 1 = uniform random, 2 = a Vos-like
/// 1/(d + d₀)^m normalised, 3 = a Gaussian ring (halo).
pub fn falloff_table(w: &LumWidths, kind: u32, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x9e37_79b9_7f4a_7c15);
    let len = w.falloff_len();
    let n = (len - 1) as f64;
    let g: f64 = rng.random_range(0.5..4.0);
    let d0: f64 = rng.random_range(0.01..0.3);
    let r1: f64 = rng.random_range(0.2..0.8);
    let al: f64 = rng.random_range(0.03..0.3);
    (0..len)
        .map(|j| {
            let d = j as f64 / n;
            let x: f64 = match kind % 4 {
                0 => (1.0 - d).powf(g),
                1 => rng.random_range(0.0..=1.0),
                2 => (d0 / (d + d0)).powf(g),
                _ => (-((d - r1) / al).powi(2)).exp(),
            };
            x.clamp(0.0, 1.0)
        })
        .collect()
}

/// Largest |difference| between neighbouring samples of a (2ᵏ+1)² grid, along u (x)
/// and along v (y).
pub fn shape_lipschitz(w: &LumWidths, t: &[f64]) -> (f64, f64) {
    let side = w.shape_side();
    let (mut lx, mut ly) = (0f64, 0f64);
    for j in 0..side {
        for i in 0..side {
            if i + 1 < side {
                lx = lx.max((t[j * side + i + 1] - t[j * side + i]).abs());
            }
            if j + 1 < side {
                ly = ly.max((t[(j + 1) * side + i] - t[j * side + i]).abs());
            }
        }
    }
    (lx, ly)
}

/// Largest |difference| between neighbouring falloff samples (per cell).
pub fn falloff_lipschitz(t: &[f64]) -> f64 {
    t.windows(2)
        .map(|p| (p[1] - p[0]).abs())
        .fold(0.0, f64::max)
}

/// Error bound on d (in d units, i.e. fraction of full scale), derived from the widths
/// and the loaded table (see docs/units.md § bloom_flare_modulator):
///   E_d = ½ LSB_s (entry rounding; bilinear is a convex combination)
///       + ½ LSB_s (rounding the interpolated d to sb bits)
///       + (L_x + L_y) · δw (shape weight truncation, δw < one weight LSB)
/// LSB_s = 1/(2^sb − 1). With s = F + 1 − k fraction bits of the cell position, the
/// weight keeps wb of them: δw = (2^(s−wb) − 1)/2^s if s > wb, else 0 (exact).
pub fn bound_d(w: &LumWidths, shape: &[f64]) -> f64 {
    let lsb_s = 1.0 / ((1u64 << w.shape_bits) - 1) as f64;
    let s = w.coord_frac_bits as i32 + 1 - w.shape_log2 as i32;
    let wb = w.weight_bits as i32;
    let dw = if s > wb {
        (2f64.powi(s - wb) - 1.0) / 2f64.powi(s)
    } else {
        0.0
    };
    let (lx, ly) = shape_lipschitz(w, shape);
    lsb_s + (lx + ly) * dw
}

/// Error bound on p (fraction of full scale) given the d bound:
///   E_p = ½ LSB_f (entry rounding) + ½ LSB_f (rounding the lerp to fb bits)
///       + L_f · 2^−wb (the d code replicated to m + wb address bits: ≤ 1 address LSB)
///       + L_f · 2^m · E_d (the profile's slope per unit d times the d error)
/// LSB_f = 1/(2^fb − 1), L_f = largest neighbour difference of the loaded profile.
pub fn bound_p(w: &LumWidths, falloff: &[f64], e_d: f64) -> f64 {
    let lsb_f = 1.0 / ((1u64 << w.falloff_bits) - 1) as f64;
    let lf = falloff_lipschitz(falloff);
    lsb_f + lf * (2f64.powi(-(w.weight_bits as i32)) + (1u64 << w.falloff_log2) as f64 * e_d)
}

/// Error bound on one luminance channel, in output LSBs:
///   E_lum = G · (E_p + 2^−R) + ½
/// G = gain value, 2^−R the unorm → binary replication of p to R = fb + gi bits, ½ the
/// final rounding. Saturation at the top code is 1-Lipschitz and adds nothing.
pub fn bound_lum(w: &LumWidths, e_p: f64, gain_code: u32) -> f64 {
    let g = gain_code as f64 / 2f64.powi(w.gain_frac_bits as i32);
    g * (e_p + 2f64.powi(-(w.p_rep_bits() as i32))) + 0.5
}

pub fn gain_value(w: &LumWidths, code: u32) -> f64 {
    code as f64 / 2f64.powi(w.gain_frac_bits as i32)
}

pub fn coord_value(w: &LumWidths, code: i32) -> f64 {
    code as f64 / 2f64.powi(w.coord_frac_bits as i32)
}

/// Coordinate code range on the wire: s2.F → [−2^(F+1), 2^(F+1)).
pub fn coord_range(w: &LumWidths) -> (i32, i32) {
    let h = 1i32 << (w.coord_frac_bits + 1);
    (-h, h - 1)
}

pub fn out_max(w: &LumWidths) -> f64 {
    ((1u64 << w.out_bits) - 1) as f64
}

/// Random pixel inputs: positions over the whole wire range (so |u| ≥ 1 and the clamp
/// region are hit), often inside [−1, 1]; gains random, sometimes the largest code.
pub fn random_points(w: &LumWidths, seed: u64, n: usize) -> Vec<(i32, i32, [u32; 3])> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5151);
    let (lo, hi) = coord_range(w);
    let one = 1i32 << w.coord_frac_bits;
    let gmax = w.gain_max();
    let c = |rng: &mut ChaCha8Rng| {
        if rng.random_bool(0.7) {
            rng.random_range(-one..=one)
        } else {
            rng.random_range(lo..=hi)
        }
    };
    (0..n)
        .map(|_| {
            let u = c(&mut rng);
            let v = c(&mut rng);
            let mut g = [0u32; 3];
            for x in g.iter_mut() {
                *x = if rng.random_bool(0.2) {
                    gmax
                } else {
                    rng.random_range(0..=gmax)
                };
            }
            (u, v, g)
        })
        .collect()
}

/// Width configs with radial correction on: defaults, a wide one, two narrow ones
/// (3-bit radius, 4-bit κ, 1 entry integer bit; and 2-bit radius, κ u0.3, ei = 0 with
/// coordinates coarser than the grid).
pub fn radial_configs() -> Vec<LumWidths> {
    let on = |w: LumWidths, rf, ki, kf, ei| LumWidths {
        radial: Radial {
            on: true,
            radius_frac_bits: rf,
            kappa_int_bits: ki,
            kappa_frac_bits: kf,
            entry_int_bits: ei,
        },
        ..w
    };
    let c = configs();
    vec![
        on(c[0], 16, 4, 12, 1),
        on(c[1], 16, 8, 16, 4),
        on(
            LumWidths {
                shape_bits: 4,
                ..c[2]
            },
            3,
            2,
            2,
            1,
        ),
        on(c[3], 2, 0, 3, 0),
    ]
}

/// A random κ code for a radial config (often the largest, sometimes 0).
pub fn random_kappa(w: &LumWidths, seed: u64) -> u32 {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x004b_4150_5041);
    match rng.random_range(0..4) {
        0 => w.kappa_max(),
        1 => 0,
        _ => rng.random_range(0..=w.kappa_max()),
    }
}

/// A random signed radial table e for κ (value): kind 0 = a rotated ellipse's signed
/// distance (scaled) minus κ·|(u, v)| (the host's table for a small source, clamped
/// to the entry range), 1 = uniform random over the entry range (rough), 2 = a
/// constant (a cone: e exact at any depth), 3 = a checkerboard of the range ends.
pub fn radial_table(w: &LumWidths, kind: u32, seed: u64, kappa: f64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x7261_6469_616c);
    let (lo, hi) = w.entry_range();
    let side = w.shape_side();
    let n = (side - 1) as f64;
    let coord = |i: usize| -1.0 + 2.0 * i as f64 / n;
    let a: f64 = rng.random_range(0.01..0.5);
    let b: f64 = rng.random_range(0.01..0.5);
    let th: f64 = rng.random_range(0.0..std::f64::consts::PI);
    let scale: f64 = rng.random_range(0.5..3.0);
    let cst: f64 = rng.random_range(lo..=hi);
    let shape = glare_pipeline::reference::glare_model::Shape2D::Ellipse { a, b, phi: th };
    let mut t = Vec::with_capacity(side * side);
    for j in 0..side {
        for i in 0..side {
            let (u, v) = (coord(i), coord(j));
            let x = match kind % 4 {
                0 => scale * shape.signed_distance(u, v) - kappa * u.hypot(v),
                1 => rng.random_range(lo..=hi),
                2 => cst,
                _ => {
                    if (i + j) % 2 == 0 {
                        lo
                    } else {
                        hi
                    }
                }
            };
            t.push(x.clamp(lo, hi));
        }
    }
    t
}

/// Error bound on d in radial mode (d units), derived from the widths, the table and κ
/// (see docs/units.md § bloom_flare_modulator, radial correction):
///   E_d = ½·2^−fe (signed entry rounding, fe = sb − 1 − ei; bilinear is convex)
///       + (L_x + L_y)·δw (weight truncation, as in [`bound_d`], L of the e table)
///       + κ·2^−rf (the square root is an exact floor of |(u, v)| to rf fraction bits,
///         times κ; the product and the sum are exact)
///       + ½ LSB_s (rounding the clamped sum to the unorm sb-bit d code)
/// The clamp to [0, 1] is 1-Lipschitz and adds nothing.
pub fn bound_d_radial(w: &LumWidths, e: &[f64], kappa: f64) -> f64 {
    let lsb_s = 1.0 / ((1u64 << w.shape_bits) - 1) as f64;
    let s = w.coord_frac_bits as i32 + 1 - w.shape_log2 as i32;
    let wb = w.weight_bits as i32;
    let dw = if s > wb {
        (2f64.powi(s - wb) - 1.0) / 2f64.powi(s)
    } else {
        0.0
    };
    let (lx, ly) = shape_lipschitz(w, e);
    0.5 * 2f64.powi(-(w.entry_frac_bits() as i32))
        + (lx + ly) * dw
        + kappa * 2f64.powi(-(w.radial.radius_frac_bits as i32))
        + 0.5 * lsb_s
}
