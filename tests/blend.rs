//! blend against its f64 twin and against the hardware's one-rounding formula.
//!
//! Error bound, in LSBs of the n-bit channel (M = 2ⁿ − 1). The twin's value is
//! clamp(eq(s·f_s, d·f_d), 0, M) on the same codes, unrounded. The unit's:
//! * `Once`: clamp(round(t / M)) with t = s·f_s ± d·f_d exact in integers; the
//!   factors are codes of the same n bits as the twin's (exact), so the only error is
//!   the one rounding, ≤ ½ LSB, and the clamp is 1-Lipschitz: |unit − twin| ≤ ½.
//! * `PerTerm`: each term rounded (≤ ½ each), then ±: |unit − twin| ≤ 1.
//! * MIN, MAX and the two signed equations: no rounding at all, exact (0).
//!
//! The only slack is 1e-9 LSB for the twin's own f64 rounding.

mod common;

use glare_pipeline::reference::blend::blend_codes;
use proptest::prelude::*;
use rtl_model::memory::bytes_for_bits;
use rtl_model::units::blend::{
    Blend, BlendConfig, BlendEquation, BlendFactor, BlendIn, BlendRounding,
};
use rtl_model::{Counters, Unit};

const SLACK: f64 = 1e-9;

fn unit(
    bits: u32,
    equation: BlendEquation,
    src_factor: BlendFactor,
    dst_factor: BlendFactor,
    constant: [u32; 4],
    rounding: BlendRounding,
) -> Blend {
    BlendConfig {
        bits,
        equation,
        src_factor,
        dst_factor,
        constant,
        rounding,
        ..BlendConfig::default()
    }
    .build()
    .unwrap()
}

fn bound(b: &Blend) -> f64 {
    let c = b.config();
    if !c.equation.uses_factors() {
        0.0
    } else {
        match c.rounding {
            BlendRounding::Once => 0.5,
            BlendRounding::PerTerm => 1.0,
        }
    }
}

fn check(b: &Blend, src: [u32; 4], dst: [u32; 4]) {
    let c = b.config();
    let (got, _) = b.blend_pixel(&src, &dst);
    let want = blend_codes(
        c.bits,
        c.equation,
        c.src_factor,
        c.dst_factor,
        src,
        dst,
        c.constant,
    );
    let lim = bound(b) + SLACK;
    for ch in 0..4 {
        assert!(
            (got[ch] as f64 - want[ch]).abs() <= lim,
            "{c:?}: src {src:?} dst {dst:?} ch {ch} → {}, twin {}, bound {lim}",
            got[ch],
            want[ch]
        );
        assert!(got[ch] <= b.max());
    }
}

/// The 8-bit factor codes GL's table gives, computed independently of the unit.
fn factor8(f: BlendFactor, c: usize, s: &[u32; 4], d: &[u32; 4], k: &[u32; 4]) -> i64 {
    let v = match f {
        BlendFactor::Zero => 0,
        BlendFactor::One => 255,
        BlendFactor::SrcColor => s[c],
        BlendFactor::OneMinusSrcColor => 255 - s[c],
        BlendFactor::SrcAlpha => s[3],
        BlendFactor::OneMinusSrcAlpha => 255 - s[3],
        BlendFactor::DstAlpha => d[3],
        BlendFactor::OneMinusDstAlpha => 255 - d[3],
        BlendFactor::DstColor => d[c],
        BlendFactor::OneMinusDstColor => 255 - d[c],
        BlendFactor::SrcAlphaSaturate => {
            if c == 3 {
                255
            } else {
                s[3].min(255 - d[3])
            }
        }
        BlendFactor::ConstantColor => k[c],
        BlendFactor::OneMinusConstantColor => 255 - k[c],
        BlendFactor::ConstantAlpha => k[3],
        BlendFactor::OneMinusConstantAlpha => 255 - k[3],
    };
    v as i64
}

/// round(x / 255) for a signed x (255 is odd: never a tie), by f64 division.
fn round255(x: i64) -> i64 {
    (x as f64 / 255.0).round() as i64
}

/// The 8-bit defaults equal clamp(round((s·f_s ± d·f_d)/255)) — the one rounding the
/// NV2A captures show — for every equation and factor pair over a grid of codes.
#[test]
fn default_8_bit_is_one_rounding_of_the_weighted_sum_over_a_grid() {
    let grid: Vec<u32> = (0..=255).step_by(17).chain([1, 127, 128, 254]).collect();
    let k = [0x55, 0x10, 0xee, 0x80];
    for eq in [
        BlendEquation::Add,
        BlendEquation::Subtract,
        BlendEquation::ReverseSubtract,
    ] {
        for sf in BlendFactor::ALL {
            for df in BlendFactor::ALL {
                let b = unit(8, eq, sf, df, k, BlendRounding::Once);
                for &s in &grid {
                    for &d in &grid {
                        for &(sa, da) in &[(s, d), (255 - d, s), (0, 255)] {
                            let src = [s, d, 255 - s, sa];
                            let dst = [d, s, 255 - d, da];
                            let (got, _) = b.blend_pixel(&src, &dst);
                            for c in 0..4 {
                                let ps = src[c] as i64 * factor8(sf, c, &src, &dst, &k);
                                let pd = dst[c] as i64 * factor8(df, c, &src, &dst, &k);
                                let t = match eq {
                                    BlendEquation::Add => ps + pd,
                                    BlendEquation::Subtract => ps - pd,
                                    _ => pd - ps,
                                };
                                let want = round255(t).clamp(0, 255) as u32;
                                assert_eq!(
                                    got[c], want,
                                    "{eq:?} {sf:?} {df:?} {src:?} {dst:?} ch {c}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}

/// MIN, MAX and the signed equations at 8 bits, every (s, d) pair: exact formulas.
#[test]
fn min_max_and_signed_equations_exhaustively_at_8_bits() {
    for eq in [
        BlendEquation::Min,
        BlendEquation::Max,
        BlendEquation::AddSigned,
        BlendEquation::ReverseSubtractSigned,
    ] {
        // Factors are ignored: a factor pair that would zero everything changes nothing.
        let b = unit(
            8,
            eq,
            BlendFactor::Zero,
            BlendFactor::Zero,
            [0; 4],
            BlendRounding::Once,
        );
        for s in 0..=255u32 {
            for d in 0..=255u32 {
                let (got, sat) = b.blend_pixel(&[s; 4], &[d; 4]);
                let sx = s as i64 - if s >= 128 { 256 } else { 0 };
                let raw = match eq {
                    BlendEquation::Min => s.min(d) as i64,
                    BlendEquation::Max => s.max(d) as i64,
                    BlendEquation::AddSigned => d as i64 + sx,
                    _ => d as i64 - sx,
                };
                assert_eq!(got, [raw.clamp(0, 255) as u32; 4], "{eq:?} s {s} d {d}");
                assert_eq!(sat, if (0..=255).contains(&raw) { 0 } else { 4 });
            }
        }
    }
}

/// Every equation, factor pair and rounding within its bound against the twin,
/// exhaustively over (s, d) of one channel at 3 bits (alpha varied too).
#[test]
fn within_bound_of_the_twin_exhaustively_at_3_bits() {
    let k = [5, 2, 7, 3];
    for eq in BlendEquation::ALL {
        for sf in BlendFactor::ALL {
            for df in BlendFactor::ALL {
                for r in [BlendRounding::Once, BlendRounding::PerTerm] {
                    let b = unit(3, eq, sf, df, k, r);
                    for s in 0..8u32 {
                        for d in 0..8u32 {
                            for a in [0u32, 3, 7] {
                                check(&b, [s, d, 7 - s, a], [d, s, a, 7 - a]);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// `PerTerm` is the modulate-then-add path: at 8 bits, ADD with (SRC_ALPHA,
/// ONE_MINUS_SRC_ALPHA) differs from the one rounding by exactly one LSB on some
/// pixels, and never by more.
#[test]
fn per_term_rounding_is_off_by_at_most_one_from_once() {
    let once = Blend::with(
        BlendEquation::Add,
        BlendFactor::SrcAlpha,
        BlendFactor::OneMinusSrcAlpha,
    );
    let per = unit(
        8,
        BlendEquation::Add,
        BlendFactor::SrcAlpha,
        BlendFactor::OneMinusSrcAlpha,
        [0; 4],
        BlendRounding::PerTerm,
    );
    let (mut off, mut n) = (0u32, 0u32);
    for s in (0..=255u32).step_by(3) {
        for d in (0..=255u32).step_by(5) {
            for a in [0x22u32, 0x7f, 0xdd] {
                let (x, _) = once.blend_pixel(&[s, s, s, a], &[d; 4]);
                let (y, _) = per.blend_pixel(&[s, s, s, a], &[d; 4]);
                let diff = (x[0] as i64 - y[0] as i64).abs();
                assert!(diff <= 1);
                off += u32::from(diff == 1);
                n += 1;
            }
        }
    }
    assert!(off > 0 && off < n, "{off} of {n}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn within_bound_of_the_twin_at_random_widths(
        bits in 1u32..=16,
        eq in prop::sample::select(BlendEquation::ALL.to_vec()),
        sf in prop::sample::select(BlendFactor::ALL.to_vec()),
        df in prop::sample::select(BlendFactor::ALL.to_vec()),
        r in prop::sample::select(vec![BlendRounding::Once, BlendRounding::PerTerm]),
        k in any::<[u32; 4]>(),
        src in any::<[u32; 4]>(),
        dst in any::<[u32; 4]>(),
    ) {
        let m = (1u32 << bits) - 1;
        let b = unit(bits, eq, sf, df, k.map(|v| v & m), r);
        check(&b, src, dst);
    }

    #[test]
    fn tick_span_and_batch_drivers_agree(
        bits in 1u32..=16,
        eq in prop::sample::select(BlendEquation::ALL.to_vec()),
        sf in prop::sample::select(BlendFactor::ALL.to_vec()),
        df in prop::sample::select(BlendFactor::ALL.to_vec()),
        px in prop::collection::vec((any::<[u32; 4]>(), any::<[u32; 4]>()), 0..40),
    ) {
        let m = (1u32 << bits) - 1;
        let b = unit(bits, eq, sf, df, [m / 3; 4], BlendRounding::Once);
        let inputs: Vec<BlendIn> = px.iter().map(|&(s, d)| BlendIn { src: s, dst: d }).collect();
        common::assert_drivers_agree(&b, (), &inputs);
    }

    #[test]
    fn out_of_range_config_is_an_error_naming_the_field(bits in prop_oneof![Just(0u32), 17u32..1000]) {
        let e = BlendConfig { bits, ..BlendConfig::default() }.build().unwrap_err();
        prop_assert_eq!(e.field(), "blend.bits");
    }
}

#[test]
fn constant_wider_than_the_channel_is_an_error_naming_it() {
    let e = BlendConfig {
        bits: 4,
        constant: [0, 0, 16, 0],
        ..BlendConfig::default()
    }
    .build()
    .unwrap_err();
    assert_eq!(e.field(), "blend.constant[2]");
}

/// Counters: one read-modify-write of 4·n bits per pixel each way, and one saturation
/// per clamped channel (counted independently here from the twin's unclamped sign).
#[test]
fn counters_count_traffic_and_clamps() {
    let b = Blend::with(BlendEquation::Add, BlendFactor::One, BlendFactor::One);
    let inputs = vec![
        BlendIn {
            src: [200, 10, 0, 255],
            dst: [100, 10, 0, 1],
        },
        BlendIn {
            src: [1, 2, 3, 4],
            dst: [5, 6, 7, 8],
        },
    ];
    let mut c = Counters::default();
    let out = rtl_model::driver::run_span(&b, &mut (), &inputs, &mut c);
    assert_eq!(out, vec![[255, 20, 0, 255], [6, 8, 10, 12]]);
    assert_eq!(c.saturations, 2);
    assert_eq!(c.mem_read_bytes, 2 * bytes_for_bits(32));
    assert_eq!(c.mem_write_bytes, 2 * bytes_for_bits(32));
    let sub = Blend::with(BlendEquation::Subtract, BlendFactor::One, BlendFactor::One);
    let mut c = Counters::default();
    let out = rtl_model::driver::run_span(&sub, &mut (), &inputs, &mut c);
    assert_eq!(out, vec![[100, 0, 0, 254], [0, 0, 0, 0]]);
    // 1−5, 2−6, 3−7, 4−8 clamp; 10−10 and 0−0 are exactly 0 (no clamp).
    assert_eq!(c.saturations, 4);
}

/// Batch and span agree on every (s, d) pair of one channel at 8 bits for the
/// classic alpha blend (exhaustive 2¹⁶ pixels), at several chunk sizes.
#[test]
fn batch_path_agrees_exhaustively_at_8_bits() {
    let b = Blend::with(
        BlendEquation::Add,
        BlendFactor::SrcAlpha,
        BlendFactor::OneMinusSrcAlpha,
    );
    let inputs: Vec<BlendIn> = (0..65536u32)
        .map(|i| BlendIn {
            src: [i >> 8, i & 255, 255 - (i >> 8), i & 255],
            dst: [i & 255, i >> 8, 0, 255],
        })
        .collect();
    let mut c = Counters::default();
    let span = rtl_model::driver::run_span(&b, &mut (), &inputs, &mut c);
    common::assert_batch_agrees(&b, &(), &inputs, &span, &(), &c);
    assert!(b.timing().latency >= 1 && b.cost().gates_nand2() > 0.0);
}

// ---------------------------------------------------------------------------------
// The additive datapath against additive_blend, bit for bit.

use rtl_model::units::additive_blend::{AdditiveBlend, AdditiveBlendIn};
use rtl_model::units::blend::BlendDatapath;
use rtl_model::unorm::max_code;

/// A unit's cost (cells, RAM bits, named parts) as JSON, to compare two units'.
fn cost_json(u: &impl Unit) -> String {
    serde_json::to_string(&u.cost()).unwrap()
}

/// Both units, the same configuration: `additive_blend` (src, fb, weighted, k) and the
/// `blend` additive datapath, at weight `w`.
fn both(s: u32, f: u32, weighted: bool, k: u32, w: u32) -> (AdditiveBlend, Blend) {
    let a = AdditiveBlend::new(s, f, 4, weighted, k).unwrap();
    let b = Blend::additive(s, f, weighted, k).unwrap().with_weight(w);
    (a, b)
}

/// Every source, destination (channel 0; the other channels varied with them) and
/// weight at every width triple where the channel's input space is ≤ 2²⁰ (s, f ≤ 6,
/// k ≤ 4 and 8): the kernel's outputs and counters, the batch kernel's, the lane and
/// pixel forms', and the cost, timing and widths.
#[test]
fn additive_datapath_equals_additive_blend_bit_for_bit_exhaustively() {
    let mut compared = 0u64;
    for s in 1..=6u32 {
        for f in 1..=6u32 {
            for (weighted, k) in [(false, 8), (true, 1), (true, 2), (true, 4), (true, 8)] {
                let ws: Vec<u32> = if weighted {
                    (0..=max_code(k)).collect()
                } else {
                    vec![0]
                };
                for &w in &ws {
                    let (a, b) = both(s, f, weighted, k, w);
                    assert_eq!(cost_json(&a), cost_json(&b), "cost s{s} f{f} k{k}");
                    assert_eq!(a.timing(), b.timing());
                    assert_eq!(a.widths(), b.widths());
                    let (sm, fm) = (max_code(s), max_code(f));
                    let mut ins_a = Vec::new();
                    let mut ins_b = Vec::new();
                    for sv in 0..=sm {
                        for dv in 0..=fm {
                            let src = [sv, (sv * 7 + 3) & sm, sm - sv, (sv ^ 1) & sm];
                            let dst = [dv, fm - dv, (dv * 5 + 1) & fm, 0];
                            ins_a.push(AdditiveBlendIn {
                                src,
                                dst,
                                weight: w,
                            });
                            ins_b.push(BlendIn { src, dst });
                        }
                    }
                    let (mut ca, mut cb) = (Counters::default(), Counters::default());
                    let oa = rtl_model::driver::run_span(&a, &mut (), &ins_a, &mut ca);
                    let ob = rtl_model::driver::run_span(&b, &mut (), &ins_b, &mut cb);
                    assert_eq!(oa, ob, "kernel s{s} f{f} k{k} w{w}");
                    assert_eq!(ca, cb, "kernel counters s{s} f{f} k{k} w{w}");
                    let (mut ca, mut cb) = (Counters::default(), Counters::default());
                    let oa = rtl_model::driver::run_batch(&a, &mut (), &ins_a, 37, &mut ca);
                    let ob = rtl_model::driver::run_batch(&b, &mut (), &ins_b, 37, &mut cb);
                    assert_eq!(oa, ob, "batch s{s} f{f} k{k} w{w}");
                    assert_eq!(ca, cb, "batch counters s{s} f{f} k{k} w{w}");
                    // The lane form (J buffer) and the pixel form (framebuffer).
                    let src: Vec<u32> = ins_a.iter().map(|x| x.src[0]).collect();
                    let mut da: Vec<u32> = ins_a.iter().map(|x| x.dst[0]).collect();
                    let mut db = da.clone();
                    let (mut ca, mut cb) = (Counters::default(), Counters::default());
                    a.blend_lanes(&src, &mut da, w, &mut ca);
                    b.blend_lanes(&src, &mut db, &mut cb);
                    assert_eq!(da, db, "lanes s{s} f{f} k{k} w{w}");
                    assert_eq!(ca, cb, "lanes counters s{s} f{f} k{k} w{w}");
                    let n = ins_a.len();
                    let (mut pa, mut pb) = (vec![[0u32; 4]; n], vec![[0u32; 4]; n]);
                    let (mut ca, mut cb) = (Counters::default(), Counters::default());
                    let ra = a.blend_pixels(|i| ins_a[i].src, |i| ins_a[i].dst, &mut pa, &mut ca);
                    let rb = b.blend_pixels(|i| ins_b[i].src, |i| ins_b[i].dst, &mut pb, &mut cb);
                    assert_eq!((ra, &pa, ca), (rb, &pb, cb), "pixels s{s} f{f} k{k}");
                    compared += n as u64;
                }
            }
        }
    }
    assert!(compared > 1_000_000, "{compared} pixels compared");
}

/// The hardware's widths, 8-bit source, framebuffer and weight: every source,
/// destination and weight (2²⁴ channel inputs) through the lane form, and every
/// source and destination through the kernel at the weights 0, 1, 128, 254 and 255.
#[test]
fn additive_datapath_equals_additive_blend_at_8_bits_for_all_inputs() {
    let src: Vec<u32> = (0..1u32 << 16).map(|i| i >> 8).collect();
    let dst0: Vec<u32> = (0..1u32 << 16).map(|i| i & 255).collect();
    for weighted in [false, true] {
        for w in 0..=255u32 {
            let (a, b) = both(8, 8, weighted, 8, w);
            let (mut da, mut db) = (dst0.clone(), dst0.clone());
            let (mut ca, mut cb) = (Counters::default(), Counters::default());
            a.blend_lanes(&src, &mut da, w, &mut ca);
            b.blend_lanes(&src, &mut db, &mut cb);
            assert!(da == db && ca == cb, "w{w} weighted {weighted}");
            if [0, 1, 128, 254, 255].contains(&w) {
                let ins_a: Vec<AdditiveBlendIn> = (0..src.len())
                    .map(|i| AdditiveBlendIn {
                        src: [src[i], dst0[i], 255 - src[i], src[i] ^ 0x5a],
                        dst: [dst0[i], src[i], 255 - dst0[i], 0],
                        weight: w,
                    })
                    .collect();
                let ins_b: Vec<BlendIn> = ins_a
                    .iter()
                    .map(|x| BlendIn {
                        src: x.src,
                        dst: x.dst,
                    })
                    .collect();
                let (mut ca, mut cb) = (Counters::default(), Counters::default());
                let oa = rtl_model::driver::run_span(&a, &mut (), &ins_a, &mut ca);
                let ob = rtl_model::driver::run_span(&b, &mut (), &ins_b, &mut cb);
                assert!(oa == ob && ca == cb, "kernel w{w} weighted {weighted}");
            }
        }
    }
    assert_eq!(
        Blend::additive(8, 8, false, 8).unwrap().datapath(),
        BlendDatapath::Additive
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    /// Random widths up to 16 bits (where exhaustion is impossible): the same outputs
    /// and counters, and the same cost.
    #[test]
    fn additive_datapath_equals_additive_blend_at_random_widths(
        s in 1u32..=16, f in 1u32..=16, k in 1u32..=16, weighted in any::<bool>(),
        w in any::<u32>(), src in any::<[u32; 4]>(), dst in any::<[u32; 4]>(),
    ) {
        let (a, b) = both(s, f, weighted, k, w & max_code(k));
        let mut ca = Counters::default();
        let mut cb = Counters::default();
        let oa = a.kernel(&mut (), &AdditiveBlendIn { src, dst, weight: w }, &mut ca);
        let ob = b.kernel(&mut (), &BlendIn { src, dst }, &mut cb);
        prop_assert_eq!(oa, ob);
        prop_assert_eq!(ca, cb);
        prop_assert_eq!(cost_json(&a), cost_json(&b));
    }
}
