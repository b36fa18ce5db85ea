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
/// The lane-to-word map 0, 1, …, n − 1 of the lane forms.
fn identity(n: usize) -> Vec<u32> {
    (0..n as u32).collect()
}

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
        let outs = common::assert_drivers_agree(&b, (), &inputs);
        // The drivers all run the unit's kernel: they must run it as `blend_pixel`,
        // which the other tests check against the twin.
        for (i, o) in inputs.iter().zip(outs) {
            prop_assert_eq!(o, b.blend_pixel(&i.src, &i.dst).0);
        }
    }

    #[test]
    fn out_of_range_config_is_an_error_naming_the_field(bits in prop_oneof![Just(0u32), 17u32..1000]) {
        let e = BlendConfig { bits, ..BlendConfig::default() }.build().unwrap_err();
        prop_assert_eq!(e.field(), "blend.bits");
    }
}

/// A constant of its own width only with per-term rounding (one rounding divides the
/// whole sum by one full scale): the channel's own width builds either way, another is
/// refused naming `blend.constant_bits` under `once`.
#[test]
fn constant_bits_other_than_the_channel_only_with_per_term_rounding() {
    for bits in [1u32, 5, 8, 16] {
        let cfg = |k: u32, rounding| BlendConfig {
            bits,
            constant_bits: Some(k),
            rounding,
            src_factor: BlendFactor::ConstantColor,
            ..BlendConfig::default()
        };
        for rounding in [BlendRounding::Once, BlendRounding::PerTerm] {
            assert_eq!(cfg(bits, rounding).build().unwrap().constant_bits(), bits);
        }
        for k in [1u32, 4, 12, 16].into_iter().filter(|&k| k != bits) {
            let e = cfg(k, BlendRounding::Once).build().unwrap_err();
            assert_eq!(e.field(), "blend.constant_bits", "bits {bits}, k {k}");
            assert_eq!(
                cfg(k, BlendRounding::PerTerm)
                    .build()
                    .unwrap()
                    .constant_bits(),
                k
            );
        }
    }
}

/// Per-term rounding with a constant of its own width: a CONSTANT_* factor's term is
/// divided by the constant's full scale 2ᵏ − 1, every other term by the channel's
/// 2ⁿ − 1 (n = 8, k = 4: s·K/15 rounded, plus d·255/255).
#[test]
fn per_term_divides_each_term_by_its_own_factors_full_scale() {
    let constant = [0u32, 5, 10, 15];
    let b = BlendConfig {
        bits: 8,
        constant_bits: Some(4),
        rounding: BlendRounding::PerTerm,
        src_factor: BlendFactor::ConstantColor,
        dst_factor: BlendFactor::One,
        constant,
        ..BlendConfig::default()
    }
    .build()
    .unwrap();
    for s in 0..=255u32 {
        for d in [0u32, 1, 100, 255] {
            let (out, _) = b.blend_pixel(&[s; 4], &[d; 4]);
            for c in 0..4 {
                let term = (2 * s * constant[c] + 15) / 30; // round(s·K/15), 15 odd: no ties
                assert_eq!(out[c], (term + d).min(255), "s {s} d {d} channel {c}");
            }
        }
    }
}

/// The underflow count: under `once`, each channel whose exact sum t ≠ 0 rounds to 0;
/// under `per_term`, each non-zero product that rounds to 0 (two per channel at most).
/// With M odd a value p rounds to 0 exactly when 0 < 2|p| < M. Every 3-bit pixel
/// pair, s·s ± d·d (factors SRC_COLOR, DST_COLOR), ADD and SUBTRACT.
#[test]
fn underflows_count_the_nonzero_terms_rounded_to_zero() {
    let m = 7i64;
    let to_zero = |p: i64| p != 0 && 2 * p.abs() < m;
    for eq in [BlendEquation::Add, BlendEquation::Subtract] {
        let sign = if eq == BlendEquation::Add { 1 } else { -1 };
        for rounding in [BlendRounding::Once, BlendRounding::PerTerm] {
            let b = unit(
                3,
                eq,
                BlendFactor::SrcColor,
                BlendFactor::DstColor,
                [0; 4],
                rounding,
            );
            for s in 0..8u32 {
                for d in 0..8u32 {
                    let src = [s, (s + 1) % 8, (s + 3) % 8, s];
                    let dst = [d, d, (d + 5) % 8, (d + 2) % 8];
                    let expected: u32 = (0..4)
                        .map(|c| {
                            let (ps, pd) = ((src[c] * src[c]) as i64, (dst[c] * dst[c]) as i64);
                            match rounding {
                                BlendRounding::Once => u32::from(to_zero(ps + sign * pd)),
                                BlendRounding::PerTerm => {
                                    u32::from(to_zero(ps)) + u32::from(to_zero(pd))
                                }
                            }
                        })
                        .sum();
                    let (_, _, under) = b.blend_pixel_counted(&src, &dst);
                    assert_eq!(under, expected, "{eq:?} {rounding:?} s {src:?} d {dst:?}");
                }
            }
        }
    }
}

/// A non-zero source that alignment narrows to 0 is an underflow in any equation: an
/// 8-bit source into a 4-bit blend rounds s·15/255 = s/17, so the codes 1 ..= 8 are lost
/// (ONE, ZERO: the sum itself is then 0, which alone would not count).
#[test]
fn a_source_narrowed_to_zero_counts_as_an_underflow() {
    for eq in [
        BlendEquation::Add,
        BlendEquation::Max,
        BlendEquation::AddSigned,
    ] {
        let b = BlendConfig {
            bits: 4,
            src_bits: Some(8),
            equation: eq,
            ..BlendConfig::default()
        }
        .build()
        .unwrap();
        for s in 0..=255u32 {
            let src = [s, (s + 3) % 256, (s * 7) % 256, 255 - s];
            let (_, _, under) = b.blend_pixel_counted(&src, &[0; 4]);
            let expected = src.iter().filter(|&&v| (1..=8).contains(&v)).count() as u32;
            assert_eq!(under, expected, "{eq:?} src {src:?}");
        }
    }
}

/// The default (programmable) blend at `bits` with a source of `src_bits`.
fn programmable_with_source(bits: u32, src_bits: u32) -> Blend {
    BlendConfig {
        bits,
        src_bits: Some(src_bits),
        ..BlendConfig::default()
    }
    .build()
    .unwrap()
}

/// The programmable datapath prices a narrowing aligner (round to nearest, per
/// channel) only when the source is wider than the channel; wider channels take the
/// source by wiring (bit replication) at no cost.
#[test]
fn the_programmable_datapath_prices_the_narrowing_aligner_only_when_narrowing() {
    const PART: &str = "align: narrow to bits (round to nearest)";
    for (bits, src_bits) in [(4u32, 8u32), (8, 16), (8, 8), (8, 4), (16, 1)] {
        let b = programmable_with_source(bits, src_bits);
        let has = common::cost_part(&b.cost(), PART).is_some();
        assert_eq!(has, src_bits > bits, "bits {bits}, src_bits {src_bits}");
    }
}

/// Per-term rounding replaces the once datapath's add, magnitude and one ÷M series per
/// channel by two ÷M series per channel (one per term, each J = ⌈(n+1)/n⌉ = 2 adders
/// of 2·max(n, k) + 1 bits, the product of the wider factor plus its rounding bit) and
/// an (n+1)-bit add of the two rounded terms.
#[test]
fn per_term_rounding_prices_a_divider_series_per_term() {
    use rtl_model::cost::prim;
    let part = |b: &Blend, name: &str| common::cost_part(&b.cost(), name);
    for (bits, k) in [(4u32, 4u32), (8, 8), (8, 12), (16, 3)] {
        let b = BlendConfig {
            bits,
            constant_bits: Some(k),
            rounding: BlendRounding::PerTerm,
            ..BlendConfig::default()
        }
        .build()
        .unwrap();
        let w = 2 * bits.max(k) + 1;
        let series = (prim::adder(w) * (2.0 * 2.0 * 4.0)).nand2_eq();
        let add = (prim::adder(bits + 1) * 4.0).nand2_eq();
        assert_eq!(
            part(&b, "÷M shift-add series, per term"),
            Some(series),
            "n {bits} k {k}"
        );
        assert_eq!(part(&b, "add/subtract terms"), Some(add), "n {bits} k {k}");
        assert_eq!(part(&b, "÷M shift-add series"), None);
    }
}

/// The VCD trace's wires: the source channels at the source's width, the framebuffer's
/// and the result's at the channel's, each its code masked to its wire.
#[test]
fn trace_signals_are_the_channels_as_wires_of_their_widths() {
    for (bits, src_bits) in [(8u32, 8u32), (4, 8), (8, 5)] {
        let b = programmable_with_source(bits, src_bits);
        let input = BlendIn {
            src: [1, 2, 0x1ff, 4],
            dst: [5, 0x10f, 7, 8],
        };
        let wires = common::wires(&b.in_signals(&input));
        let (sm, m) = ((1u64 << src_bits) - 1, (1u64 << bits) - 1);
        assert_eq!(
            wires,
            [
                ("src_r", src_bits, 1 & sm),
                ("src_g", src_bits, 2 & sm),
                ("src_b", src_bits, 0x1ff & sm),
                ("src_a", src_bits, 4 & sm),
                ("dst_r", bits, 5 & m),
                ("dst_g", bits, 0x10f & m),
                ("dst_b", bits, 7 & m),
                ("dst_a", bits, 8 & m),
            ]
        );
        let out = common::wires(&b.out_signals(&[3, 0, 9, 0x1f0]));
        assert_eq!(
            out,
            [
                ("y_r", bits, 3 & m),
                ("y_g", bits, 0),
                ("y_b", bits, 9 & m),
                ("y_a", bits, 0x1f0 & m)
            ]
        );
    }
}

/// The widths a sweep can vary: the programmable datapath lists `bits` and the pixel,
/// the source's width only where it differs, the constant's only where it differs and
/// is not the additive weight; the additive datapath its source, framebuffer and pixel
/// widths and, weighted, the weight's.
#[test]
fn widths_list_what_the_datapath_has() {
    let names =
        |b: &Blend| -> Vec<(&str, u32)> { b.widths().iter().map(|w| (w.name, w.bits)).collect() };
    let programmable = |bits, src_bits, constant_bits| {
        BlendConfig {
            bits,
            src_bits,
            constant_bits,
            rounding: BlendRounding::PerTerm,
            ..BlendConfig::default()
        }
        .build()
        .unwrap()
    };
    assert_eq!(
        names(&programmable(8, None, None)),
        [("bits", 8), ("pixel_bits", 32)]
    );
    assert_eq!(
        names(&programmable(8, Some(5), Some(8))),
        [("bits", 8), ("pixel_bits", 32), ("src_bits", 5)]
    );
    assert_eq!(
        names(&programmable(8, Some(8), Some(12))),
        [("bits", 8), ("pixel_bits", 32), ("constant_bits", 12)]
    );
    let additive = Blend::additive(6, 10, true, 4).unwrap();
    assert_eq!(
        names(&additive),
        [
            ("src_bits", 6),
            ("fb_bits", 10),
            ("pixel_bits", additive.pixel_bits()),
            ("weight_bits", 4)
        ]
    );
    let unweighted = Blend::additive(6, 10, false, 4).unwrap();
    assert_eq!(names(&unweighted).len(), 3);
}

/// The select words the Verilog reads (`EQUATION`, `SRC_FACTOR`, `DST_FACTOR` of
/// rtl_model/verilog/units/blend.v) are the codes its header lists, name by name.
#[test]
fn select_codes_are_the_ones_blend_v_lists() {
    let header: String = include_str!("../rtl_model/verilog/units/blend.v")
        .lines()
        .take_while(|l| l.starts_with("//"))
        .map(|l| l.trim_start_matches("//").trim())
        .collect::<Vec<_>>()
        .join(" ");
    let list = |after: &str| -> Vec<String> {
        let from = header.find(after).expect(after) + after.len();
        let rest = &header[from..];
        rest[..rest.find(';').unwrap()]
            .split(',')
            .map(|w| w.trim().to_string())
            .collect()
    };
    let equations = list("EQUATION 0..6 =");
    let factors = list("SRC_FACTOR / DST_FACTOR 0..14 =");
    let name = |v: serde_json::Value| v.as_str().unwrap().to_uppercase();
    assert_eq!((equations.len(), factors.len()), (7, 15));
    for e in BlendEquation::ALL {
        assert_eq!(
            equations[e.code() as usize],
            name(serde_json::to_value(e).unwrap())
        );
    }
    for f in BlendFactor::ALL {
        assert_eq!(
            factors[f.code() as usize],
            name(serde_json::to_value(f).unwrap())
        );
    }
}

/// `uses_factors` is what the datapath does: under MIN, MAX and the two signed
/// equations no factor pair changes any output (every 3-bit pixel pair, every factor
/// pair); under ADD, SUBTRACT and REVERSE_SUBTRACT some does.
#[test]
fn only_the_equations_that_use_factors_depend_on_them() {
    let bits = 3;
    let pixels: Vec<[u32; 4]> = (0..8u32).map(|v| [v, 7 - v, v / 2, (v * 5) % 8]).collect();
    for eq in BlendEquation::ALL {
        let reference = unit(
            bits,
            eq,
            BlendFactor::One,
            BlendFactor::Zero,
            [3; 4],
            BlendRounding::Once,
        );
        let mut depends = false;
        for sf in BlendFactor::ALL {
            for df in BlendFactor::ALL {
                let b = unit(bits, eq, sf, df, [3; 4], BlendRounding::Once);
                for s in &pixels {
                    for d in &pixels {
                        depends |= b.blend_pixel(s, d).0 != reference.blend_pixel(s, d).0;
                    }
                }
            }
        }
        assert_eq!(depends, eq.uses_factors(), "{eq:?}");
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
// The additive datapath equals the retired `additive_blend` unit bit for bit. Until it
// was retired the test compared the two units directly; the oracle below is that
// unit's definition (its module documentation, kernel, counters and cost), written
// here independently of `blend`'s code: the weight's rounding by exact integer
// division rather than the unit's shift-add series, alignment by `unorm`.

use rtl_model::cost::{prim, Cost};
use rtl_model::units::blend::BlendDatapath;
use rtl_model::unorm::{max_code, narrow, widen};

/// The retired unit: a u(s) source into a u(f) framebuffer, RGBA, optionally weighted
/// by a unorm w of k bits.
#[derive(Clone, Copy, Debug)]
struct AdditiveBlendOracle {
    s: u32,
    f: u32,
    weighted: bool,
    k: u32,
}

impl AdditiveBlendOracle {
    /// What it added for a source: align (replicate or round to nearest), then
    /// round(a·w / (2ᵏ − 1)) when weighted.
    fn contribution(&self, src: u32, w: u32) -> u32 {
        let v = src & max_code(self.s);
        let a = if self.f >= self.s {
            widen(v, self.s, self.f)
        } else {
            narrow(v, self.s, self.f)
        };
        if !self.weighted {
            return a;
        }
        let m = max_code(self.k) as u64;
        let p = a as u64 * (w & max_code(self.k)) as u64;
        ((2 * p + m) / (2 * m)) as u32
    }

    /// One pixel: outputs, and the counters one kernel call adds.
    fn pixel(&self, src: [u32; 4], dst: [u32; 4], w: u32, ctr: &mut Counters) -> [u32; 4] {
        let max = max_code(self.f);
        let bytes = bytes_for_bits(4 * self.f);
        ctr.mem_read_bytes += bytes;
        ctr.mem_write_bytes += bytes;
        std::array::from_fn(|c| {
            let q = self.contribution(src[c], w);
            let sum = (dst[c] & max) + q;
            ctr.saturations += u64::from(sum > max);
            let on =
                src[c] & max_code(self.s) != 0 && (!self.weighted || w & max_code(self.k) != 0);
            ctr.underflows += u64::from(on && q == 0);
            sum.min(max)
        })
    }

    /// Its cost: input, stage 1, 2 and 3 registers, the narrowing (when f < s), the
    /// weight multiplier and rounding (when weighted) and four saturating adders.
    fn cost(&self) -> Cost {
        let (s, f, k) = (self.s, self.f, self.k);
        let wbits = if self.weighted { k } else { 0 };
        let mut c = Cost::default()
            .part(
                "input registers (src, weight)",
                prim::register(4 * s + wbits),
            )
            .part(
                "stage 1 registers (contribution, fb read data)",
                prim::register(8 * f),
            )
            .part("stage 2 register (saturated sum)", prim::register(4 * f))
            .part("stage 3 register (write data)", prim::register(4 * f));
        if f < s {
            let per =
                prim::subtractor(s + f) + prim::half_adder() * (f + 1) as f64 + prim::adder(s + f);
            c = c.part("align: narrow to fb_bits (round to nearest)", per * 4.0);
        }
        if self.weighted {
            c = c
                .part("weight multiplier fb×weight", prim::multiplier(f, k) * 4.0)
                .part(
                    "weight rounding: + 2^(k-1)",
                    prim::half_adder() * ((f + 1) as f64 * 4.0),
                )
                .part(
                    "weight rounding: ÷(2^k−1) shift-add series",
                    prim::adder(f + k) * (f.div_ceil(k) as f64 * 4.0),
                );
        }
        c.part("saturating adder fb_bits", prim::saturating_adder(f) * 4.0)
    }
}

/// A unit's cost (cells, RAM bits, named parts) as JSON, to compare two costs.
fn cost_json(c: &Cost) -> String {
    serde_json::to_string(c).unwrap()
}

/// The oracle and the `blend` additive datapath, the same configuration, at weight `w`.
fn both(s: u32, f: u32, weighted: bool, k: u32, w: u32) -> (AdditiveBlendOracle, Blend) {
    let a = AdditiveBlendOracle { s, f, weighted, k };
    let b = Blend::additive(s, f, weighted, k).unwrap().with_weight(w);
    (a, b)
}

/// The oracle over inputs, with the span driver's cycle and pixel counts added.
fn oracle_span(
    a: &AdditiveBlendOracle,
    b: &Blend,
    ins: &[BlendIn],
    w: u32,
) -> (Vec<[u32; 4]>, Counters) {
    let mut c = Counters::default();
    let out = ins
        .iter()
        .map(|x| a.pixel(x.src, x.dst, w, &mut c))
        .collect();
    let mut tally = rtl_model::driver::SpanTally::new();
    tally.add(ins.len());
    tally.close(b.timing(), &mut c);
    (out, c)
}

/// Every source, destination (channel 0; the other channels varied with them) and
/// weight at every width triple where the channel's input space is ≤ 2²⁰ (s, f ≤ 6,
/// k ≤ 4 and 8): the kernel's outputs and counters, the batch kernel's, the lane and
/// pixel forms', the cost and the latency.
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
                    assert_eq!(
                        cost_json(&a.cost()),
                        cost_json(&b.cost()),
                        "cost s{s} f{f} k{k}"
                    );
                    assert_eq!(b.timing(), rtl_model::Timing { latency: 3, ii: 1 });
                    let (sm, fm) = (max_code(s), max_code(f));
                    let mut ins = Vec::new();
                    for sv in 0..=sm {
                        for dv in 0..=fm {
                            let src = [sv, (sv * 7 + 3) & sm, sm - sv, (sv ^ 1) & sm];
                            let dst = [dv, fm - dv, (dv * 5 + 1) & fm, 0];
                            ins.push(BlendIn { src, dst });
                        }
                    }
                    let (oa, ca) = oracle_span(&a, &b, &ins, w);
                    let mut cb = Counters::default();
                    let ob = rtl_model::driver::run_span(&b, &mut (), &ins, &mut cb);
                    assert_eq!(oa, ob, "kernel s{s} f{f} k{k} w{w}");
                    assert_eq!(ca, cb, "kernel counters s{s} f{f} k{k} w{w}");
                    let mut cb = Counters::default();
                    let ob = rtl_model::driver::run_batch(&b, &mut (), &ins, 37, &mut cb);
                    assert_eq!(oa, ob, "batch s{s} f{f} k{k} w{w}");
                    assert_eq!(ca, cb, "batch counters s{s} f{f} k{k} w{w}");
                    // The lane form (J buffer): channel 0 of [src, 0, 0, 0] over [dst, 0, 0, 0].
                    let lanes: Vec<BlendIn> = ins
                        .iter()
                        .map(|x| BlendIn {
                            src: [x.src[0], 0, 0, 0],
                            dst: [x.dst[0], 0, 0, 0],
                        })
                        .collect();
                    let (la, mut lca) = oracle_span(&a, &b, &lanes, w);
                    let src: Vec<u32> = ins.iter().map(|x| x.src[0]).collect();
                    let mut db: Vec<u32> = ins.iter().map(|x| x.dst[0]).collect();
                    let mut lcb = Counters::default();
                    b.blend_lanes_at(&src, (&identity(src.len()), 0), &mut db, &mut lcb);
                    let la0: Vec<u32> = la.iter().map(|o| o[0]).collect();
                    assert_eq!(la0, db, "lanes s{s} f{f} k{k} w{w}");
                    lca.cycles = 0;
                    lca.pixels_in = 0;
                    lca.pixels_out = 0;
                    assert_eq!(lca, lcb, "lanes counters s{s} f{f} k{k} w{w}");
                    // The pixel form (framebuffer, unweighted only).
                    let n = ins.len();
                    let mut pb: Vec<[u32; 4]> = ins.iter().map(|x| x.dst).collect();
                    let mut pcb = Counters::default();
                    let done = b.blend_pixels_in_place(n, |i| (i, ins[i].src), &mut pb, &mut pcb);
                    assert_eq!(done, !weighted);
                    if done {
                        let mut ca0 = ca;
                        (ca0.cycles, ca0.pixels_in, ca0.pixels_out) = (0, 0, 0);
                        assert_eq!((&oa, ca0), (&pb, pcb), "pixels s{s} f{f}");
                    }
                    compared += n as u64;
                }
            }
        }
    }
    assert!(compared > 100_000, "{compared} pixels compared");
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
            let mut db = dst0.clone();
            let mut cb = Counters::default();
            b.blend_lanes_at(&src, (&identity(src.len()), 0), &mut db, &mut cb);
            let mut ca = Counters::default();
            for i in 0..src.len() {
                let o = a.pixel([src[i], 0, 0, 0], [dst0[i], 0, 0, 0], w, &mut ca);
                assert_eq!(
                    o[0], db[i],
                    "w{w} weighted {weighted}: {} + {}",
                    src[i], dst0[i]
                );
            }
            assert_eq!(ca, cb, "w{w} weighted {weighted}");
            if [0, 1, 128, 254, 255].contains(&w) {
                let ins: Vec<BlendIn> = (0..src.len())
                    .map(|i| BlendIn {
                        src: [src[i], dst0[i], 255 - src[i], src[i] ^ 0x5a],
                        dst: [dst0[i], src[i], 255 - dst0[i], 0],
                    })
                    .collect();
                let (oa, ca) = oracle_span(&a, &b, &ins, w);
                let mut cb = Counters::default();
                let ob = rtl_model::driver::run_span(&b, &mut (), &ins, &mut cb);
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
        let oa = a.pixel(src, dst, w & max_code(k), &mut ca);
        let ob = b.kernel(&mut (), &BlendIn { src, dst }, &mut cb);
        prop_assert_eq!(oa, ob);
        prop_assert_eq!(ca, cb);
        prop_assert_eq!(cost_json(&a.cost()), cost_json(&b.cost()));
    }
}

// ---------------------------------------------------------------------------------
// The additive datapath against its f64 twin (`reference::blend::additive_codes`):
// exhaustive where a channel's input space is ≤ 2²⁰, property tests at 8→8, 8→16,
// 8→10, 8→12 and a narrow 3→2, weighted and unweighted, plus random configs;
// thousands of blended planes.
//
// Error bound, in framebuffer LSBs (f = bits, s = src_bits, k = constant_bits,
// M_x = 2ˣ − 1). The twin's value is min(d + c, M_f) with the ideal contribution
// c = s/M_s · w/M_w · M_f (w/M_w = 1 unweighted); the unit's is min(d + q, M_f).
// min(·, M_f) is 1-Lipschitz and the add is exact, so |unit − twin| ≤ |q − c|:
//
// * alignment a = align(s): e_align = 0 if f is a multiple of s (replication is then
//   exactly s·M_f/M_s), < 1 if f > s (replication = ⌊2ᶠ·s/M_s⌋ for s < M_s, so
//   a − s·M_f/M_s = s/M_s − frac(2ᶠ·s/M_s) ∈ (−1, 1); exact at s = M_s), ≤ ½ if
//   f < s (round to nearest);
// * weight rounding q = round(a·w/M_w): e_round = ½ (k ≥ 2; ties cannot occur since
//   M_w is odd) or 0 (k = 1: w ∈ {0, 1}, exact); unweighted 0;
// * |q − c| ≤ |q − a·w/M_w| + (w/M_w)·|a − s·M_f/M_s| ≤ e_round + (w/M_w)·e_align.
//
// Saturation is exact on both sides (both clamp at M_f). Over k planes of equal
// contribution the same Lipschitz argument gives |unit − twin| ≤ k·(e_round + (w/M_w)·e_align).
// The only slack in the assertions is 1e-9 LSB for the f64 twin's own rounding.

mod additive {
    use super::common;
    use glare_pipeline::reference::blend::{
        accumulate_planes, additive, additive_codes, contribution_codes, unorm_value,
    };
    use proptest::prelude::*;
    use rtl_model::memory::bytes_for_bits;
    use rtl_model::units::blend::{round_div_mersenne, Blend, BlendIn, CONTRIBUTION_LUT_BITS};
    use rtl_model::unorm::{max_code, narrow};
    use rtl_model::{Counters, Unit, UnitSummary};

    const SLACK: f64 = 1e-9;

    fn blend(src_bits: u32, fb_bits: u32, weighted: bool, weight_bits: u32) -> Blend {
        Blend::additive(src_bits, fb_bits, weighted, weight_bits).unwrap()
    }

    /// Alignment error bound in fb LSBs (see the section header).
    fn e_align(b: &Blend) -> f64 {
        let (s, f) = (b.src_bits(), b.bits());
        if f % s == 0 {
            0.0
        } else if f > s {
            1.0
        } else {
            0.5
        }
    }

    /// Weight rounding error bound in fb LSBs.
    fn e_round(b: &Blend) -> f64 {
        if b.weighted() && b.constant_bits() >= 2 {
            0.5
        } else {
            0.0
        }
    }

    /// The per-add bound e_round + (w/M_w)·e_align, fb LSBs.
    fn bound(b: &Blend, w: u32) -> f64 {
        let wfrac = if b.weighted() {
            unorm_value(w & b.constant_max(), b.constant_bits())
        } else {
            1.0
        };
        e_round(b) + wfrac * e_align(b)
    }

    fn twin_weight(b: &Blend, w: u32) -> Option<(u32, u32)> {
        b.weighted()
            .then_some((w & b.constant_max(), b.constant_bits()))
    }

    /// Check one channel against the twin (and the contribution alone against the ideal).
    fn check(b: &Blend, src: u32, dst: u32, w: u32) {
        let bw = b.with_weight(w);
        let (got, sat, _) = bw.add_channel(src, dst);
        let q = bw.contribution(src);
        let tw = twin_weight(b, w);
        let want = additive_codes(src, dst, b.src_bits(), b.bits(), tw);
        let ideal_c = contribution_codes(src, b.src_bits(), b.bits(), tw);
        let lim = bound(b, w) + SLACK;
        let cfg = b.config();
        assert!(
            (got as f64 - want).abs() <= lim,
            "{cfg:?}: src {src} dst {dst} w {w} → {got}, twin {want}, bound {lim}"
        );
        assert!(
            (q as f64 - ideal_c).abs() <= lim,
            "{cfg:?}: contribution of src {src} w {w} = {q}, ideal {ideal_c}, bound {lim}"
        );
        // Exact integer semantics: min(d + q, M_f), clamp flagged iff d + q > M_f.
        let d = dst & b.max();
        assert_eq!(got, (d + q).min(b.max()));
        assert_eq!(sat, d + q > b.max());
    }

    #[test]
    fn default_is_min_s_plus_d_for_all_65536_pairs() {
        let b = blend(8, 8, false, 8);
        for s in 0..=255u32 {
            for d in 0..=255u32 {
                let (got, sat, under) = b.add_channel(s, d);
                assert_eq!(got, (s + d).min(255), "{s}+{d}");
                assert_eq!(sat, s + d > 255);
                assert!(!under);
            }
        }
    }

    #[test]
    fn within_bound_exhaustively_where_space_is_at_most_2_pow_20() {
        // (src, fb, weighted, weight_bits): every (src, dst[, w]) combination.
        let full = [
            (8, 8, false, 8),  // 2^16
            (8, 10, false, 8), // 2^18
            (8, 12, false, 8), // 2^20
            (3, 2, false, 8),  // 2^5
            (3, 2, true, 8),   // 2^13
            (4, 4, true, 4),   // 2^12
            (5, 7, true, 8),   // 2^20
            (6, 3, true, 11),  // 2^20
            (2, 16, true, 2),  // 2^20
            (16, 4, false, 8), // 2^20
            (3, 12, true, 5),  // 2^20
        ];
        for (s, f, wtd, k) in full {
            let b = blend(s, f, wtd, k);
            let ws = if wtd { max_code(k) } else { 0 };
            for src in 0..=max_code(s) {
                for dst in 0..=max_code(f) {
                    for w in 0..=ws {
                        check(&b, src, dst, w);
                    }
                }
            }
        }
        // Larger spaces: every (src, w), dst at the interesting points.
        for (s, f, wtd, k) in [
            (8, 8, true, 8),
            (8, 16, false, 8),
            (8, 16, true, 8),
            (8, 10, true, 8),
        ] {
            let b = blend(s, f, wtd, k);
            let m = b.max();
            let ws = if wtd { max_code(k) } else { 0 };
            for src in 0..=max_code(s) {
                for w in 0..=ws {
                    for dst in [0, 1, m / 2, m - 300.min(m), m - 1, m] {
                        check(&b, src, dst, w);
                    }
                }
            }
        }
    }

    #[test]
    fn alignment_within_bound_for_every_width_pair_and_code() {
        for s in 1..=16u32 {
            for f in 1..=16u32 {
                let b = blend(s, f, false, 8);
                let lim = e_align(&b) + SLACK;
                for src in 0..=max_code(s) {
                    let q = b.contribution(src) as f64;
                    let ideal = contribution_codes(src, s, f, None);
                    assert!(
                        (q - ideal).abs() <= lim,
                        "{s}→{f}: {src} → {q}, ideal {ideal}"
                    );
                    if f > s && f % s != 0 {
                        assert!((q - ideal).abs() < 1.0, "replication error must be < 1 LSB");
                    }
                }
                assert_eq!(b.contribution(max_code(s)), max_code(f), "1.0 stays 1.0");
                assert_eq!(b.contribution(0), 0);
            }
        }
    }

    #[test]
    fn weighted_at_full_weight_equals_unweighted_for_every_width_and_code() {
        for s in 1..=16u32 {
            for f in 1..=16u32 {
                let plain = blend(s, f, false, 8);
                for k in [1u32, 2, 8, 16] {
                    let wtd = blend(s, f, true, k).with_weight(max_code(k));
                    for src in 0..=max_code(s) {
                        assert_eq!(
                            wtd.contribution(src),
                            plain.contribution(src),
                            "{s}→{f}, k {k}: src {src}"
                        );
                    }
                    let m = max_code(f);
                    for (src, dst) in [(0, 0), (max_code(s), m), (1, m), (max_code(s) / 2, m / 2)] {
                        assert_eq!(wtd.add_channel(src, dst), plain.add_channel(src, dst));
                    }
                }
            }
        }
    }

    #[test]
    fn round_div_mersenne_is_round_to_nearest() {
        let exact = |x: u64, k: u32| {
            let m = max_code(k) as u64;
            (2 * x + m) / (2 * m)
        };
        for k in 1..=16u32 {
            for q in 1..=16u32 {
                let top = max_code(q) as u64 * max_code(k) as u64;
                if q + k <= 16 {
                    for x in 0..=top {
                        assert_eq!(
                            round_div_mersenne(x, k, q),
                            exact(x, k),
                            "k {k} q {q} x {x}"
                        );
                    }
                } else {
                    // Ends, and every rounding boundary near multiples of M_k at both ends.
                    let m = max_code(k) as u64;
                    let mut xs: Vec<u64> = (0..2000u64.min(top + 1)).collect();
                    xs.extend(top.saturating_sub(2000)..=top);
                    for n in (0..2000u64).chain(top / m - 2000.min(top / m)..=top / m) {
                        for d in [0, m / 2, m / 2 + 1, m.saturating_sub(1)] {
                            xs.push((n * m + d).min(top));
                        }
                    }
                    for x in xs {
                        assert_eq!(
                            round_div_mersenne(x, k, q),
                            exact(x, k),
                            "k {k} q {q} x {x}"
                        );
                    }
                }
            }
        }
    }

    /// Beyond its precondition (x ≥ 2^(q+k)) `round_div_mersenne` is documented to give
    /// the same shift-add formula, with no panic and saturated to u64: the 64-bit fast
    /// path must not be taken there (its t and sum would wrap).
    #[test]
    fn round_div_mersenne_beyond_its_precondition_is_the_formula() {
        for k in 1..=16u32 {
            for q in 1..=16u32 {
                let terms = q.div_ceil(k) + 1;
                let formula = |x: u64| {
                    let t = x as u128 + (1u128 << (k - 1));
                    let acc: u128 = (0..terms).map(|j| t << (j * k)).sum();
                    u64::try_from(acc >> (terms * k)).unwrap_or(u64::MAX)
                };
                let beyond = [
                    1u64 << (q + k),
                    (1 << (q + k)) + 12_345,
                    1 << 63,
                    u64::MAX >> 1,
                    u64::MAX,
                ];
                for x in beyond {
                    assert_eq!(round_div_mersenne(x, k, q), formula(x), "k {k} q {q} x {x}");
                }
            }
        }
    }

    #[test]
    fn narrow_equals_the_costed_shift_add_form() {
        // The cost of narrowing is priced as (v·M_f) then the J = 1 round_div_mersenne
        // series; prove that is the function unorm::narrow computes.
        for s in 2..=16u32 {
            for f in 1..s {
                for v in 0..=max_code(s) {
                    let via = round_div_mersenne(v as u64 * max_code(f) as u64, s, f) as u32;
                    assert_eq!(via, narrow(v, s, f), "{s}→{f}: {v}");
                }
            }
        }
    }

    /// Blend `planes` equal fragments into a pixel that starts at 0, one kernel call each.
    fn run_planes(b: &Blend, src: u32, planes: u64) -> ([u32; 4], Counters) {
        let mut ctr = Counters::default();
        let mut dst = [0u32; 4];
        for _ in 0..planes {
            let input = BlendIn { src: [src; 4], dst };
            dst = b.kernel(&mut (), &input, &mut ctr);
        }
        (dst, ctr)
    }

    #[test]
    fn thousands_of_planes_saturate_and_count_exactly() {
        // Weight 1/6 as the shafts quantise it: round-half-even of 255/6 = 42.5.
        let w6 = (255.0f64 / 6.0).round_ties_even() as u32;
        // (src, fb, weighted, weight_bits, src code, weight code)
        let cases = [
            (8, 8, false, 8, 1, 0),    // 255 adds fit, 4 745 clamp
            (8, 8, false, 8, 5, 0),    // 51·5 = 255 exactly: the 51st add does not clamp
            (8, 16, false, 8, 3, 0),   // 771·85 = 65 535 exactly
            (8, 12, false, 8, 1, 0),   // q = 16 (replication 0x010 + 0x001>>4)
            (8, 10, false, 8, 200, 0), // q = 803
            (3, 2, false, 8, 1, 0),    // q = round(3/7) = 0: every plane underflows
            (3, 2, false, 8, 2, 0),    // q = round(6/7) = 1
            (8, 8, true, 8, 200, w6),  // q = round(200·42/255) = 33
            (8, 8, true, 8, 1, w6),    // q = round(42/255) = 0: lost in 8 bits
            (8, 16, true, 8, 1, w6),   // q = round(257·42/255) = 42: kept in 16 bits
            (8, 16, true, 16, 255, 1), // q = round(65535/65535) = 1
        ];
        let planes = 5000u64;
        for (s, f, wtd, k, src, w) in cases {
            let b = blend(s, f, wtd, k).with_weight(w);
            let m = b.max() as u64;
            let q = b.contribution(src) as u64;
            let (out, ctr) = run_planes(&b, src, planes);
            // Integers: min(k·q, M) and the number of adds i with i·q > M.
            let want = (planes * q).min(m) as u32;
            // (q = 0 never clamps: no add exceeds M.)
            let clamps = m.checked_div(q).map_or(0, |fit| planes - planes.min(fit));
            assert_eq!(out, [want; 4], "{:?} src {src} w {w}", b.config());
            assert_eq!(ctr.saturations, 4 * clamps, "{:?}", b.config());
            let nonzero = src != 0 && (!wtd || w != 0);
            let underflows = if q == 0 && nonzero { 4 * planes } else { 0 };
            assert_eq!(ctr.underflows, underflows);
            let px = bytes_for_bits(b.pixel_bits());
            assert_eq!(
                (ctr.mem_read_bytes, ctr.mem_write_bytes),
                (planes * px, planes * px)
            );
            // The twin, given the contribution the unit adds, predicts both exactly
            // (codes are integers, exact in f64).
            let (tv, tclamps) = accumulate_planes(0.0, q as f64, planes, m as f64);
            assert_eq!((tv, tclamps), (want as f64, clamps), "{:?}", b.config());
            // Against the ideal contribution: |unit − twin| ≤ planes · per-add bound.
            let ideal = contribution_codes(src, s, f, twin_weight(&b, w));
            let (iv, _) = accumulate_planes(0.0, ideal, planes, m as f64);
            let lim = planes as f64 * bound(&b, w) + SLACK * planes as f64;
            assert!(
                (want as f64 - iv).abs() <= lim,
                "{:?}: {want} vs {iv}",
                b.config()
            );
        }
    }

    #[test]
    fn twin_on_values_agrees_with_codes_and_never_nans() {
        assert_eq!(additive(0.75, 0.5, 1.0), 1.0);
        assert_eq!(additive(0.25, 0.5, 0.5), 0.5);
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0, 2.0] {
            assert!(!additive(x, x, x).is_nan());
            let (v, _) = accumulate_planes(x, x, 10, x);
            assert!(!v.is_nan());
        }
        let v = additive(unorm_value(100, 8), unorm_value(50, 8), 1.0) * 255.0;
        assert!((v - additive_codes(50, 100, 8, 8, None)).abs() < 1e-9);
    }

    #[test]
    fn only_the_additive_path_is_costed() {
        let plain = blend(8, 8, false, 8);
        let wtd = blend(8, 8, true, 8);
        let has = |b: &Blend, what: &str| b.cost().breakdown.iter().any(|(n, _)| n.contains(what));
        assert!(!has(&plain, "multiplier"));
        assert!(has(&wtd, "multiplier"));
        assert!(wtd.cost().gates_nand2() > plain.cost().gates_nand2());
        assert_eq!(plain.cost().ram_bits, 0);
        // No factor muxes, equations or clamp below 0: well under the programmable
        // datapath at the same width.
        let full = Blend::geforce();
        for b in [&plain, &wtd] {
            assert!(!has(b, "factor mux") && !has(b, "min/max") && !has(b, "signed"));
            assert!(b.cost().gates_nand2() < 0.5 * full.cost().gates_nand2());
        }
        assert!(has(&full, "factor mux"));
    }

    /// Datasheet numbers: `cargo test --test blend -- --nocapture datasheet`.
    #[test]
    fn datasheet_numbers() {
        let cfgs = [
            ("additive 8→8 RGBA, unweighted", blend(8, 8, false, 8)),
            ("additive 8→8 RGBA, weighted k = 8", blend(8, 8, true, 8)),
            ("additive 8→16 RGBA, unweighted", blend(8, 16, false, 8)),
            ("additive 8→16 RGBA, weighted k = 8", blend(8, 16, true, 8)),
            (
                "additive narrow 3→2 RGBA, unweighted",
                blend(3, 2, false, 8),
            ),
            ("programmable 8-bit (the default)", Blend::geforce()),
        ];
        for (name, b) in cfgs {
            let u = UnitSummary::of(&b);
            println!(
                "blend [{name}]: latency {} II {} gates {:.1} NAND2, RAM {} bits",
                u.latency, u.ii, u.gates_nand2, u.ram_bits
            );
            for (part, g) in &u.breakdown {
                println!("    {part}: {g:.1}");
            }
        }
    }

    fn config_field() -> impl Strategy<Value = u32> {
        prop_oneof![1u32..=16, Just(0u32), 17u32..100, any::<u32>()]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(common::cases()))]

        #[test]
        fn within_bound_at_named_configs(
            cfg in prop::sample::select(vec![(8u32, 8u32), (8, 16), (8, 10), (8, 12), (3, 2)]),
            weighted in any::<bool>(),
            k in prop::sample::select(vec![8u32, 1, 5, 16]),
            src in any::<u32>(), dst in any::<u32>(), w in any::<u32>(),
        ) {
            let b = blend(cfg.0, cfg.1, weighted, k);
            check(&b, src & max_code(cfg.0), dst & max_code(cfg.1), w & max_code(k));
        }

        #[test]
        fn within_bound_at_random_configs(
            s in 1u32..=16, f in 1u32..=16, k in 1u32..=16, weighted in any::<bool>(),
            src in any::<u32>(), dst in any::<u32>(), w in any::<u32>(),
        ) {
            let b = blend(s, f, weighted, k);
            check(&b, src & max_code(s), dst & max_code(f), w & max_code(k));
        }

        #[test]
        fn round_div_mersenne_random(k in 1u32..=16, q in 1u32..=16, x in any::<u64>()) {
            let m = max_code(k) as u64;
            let x = x % (max_code(q) as u64 * m + 1);
            prop_assert_eq!(round_div_mersenne(x, k, q), (2 * x + m) / (2 * m));
        }

        #[test]
        fn raw_words_never_panic_and_stay_in_range(
            s in 1u32..=16, f in 1u32..=16, k in 1u32..=16, weighted in any::<bool>(),
            src in any::<[u32; 4]>(), dst in any::<[u32; 4]>(), weight in any::<u32>(),
        ) {
            let b = blend(s, f, weighted, k).with_weight(weight);
            let mut ctr = Counters::default();
            let out = b.kernel(&mut (), &BlendIn { src, dst }, &mut ctr);
            for (c, &o) in out.iter().enumerate() {
                prop_assert!(o <= b.max());
                prop_assert_eq!(o, b.add_channel(src[c], dst[c]).0);
            }
            prop_assert!(ctr.saturations <= 4);
            prop_assert_eq!(ctr.mem_read_bytes, bytes_for_bits(4 * f));
            prop_assert_eq!(ctr.mem_write_bytes, bytes_for_bits(4 * f));
            // Signals are masked to their widths.
            for sig in b.in_signals(&BlendIn { src, dst }).iter().chain(b.out_signals(&out).iter()) {
                prop_assert!(sig.value < (1u64 << sig.width));
            }
        }

        #[test]
        fn tick_and_span_drivers_agree(
            s in 1u32..=16, f in 1u32..=16, k in 1u32..=16, weighted in any::<bool>(),
            weight in any::<u32>(),
            words in prop::collection::vec((any::<[u32; 4]>(), any::<[u32; 4]>()), 0..40),
        ) {
            let b = blend(s, f, weighted, k).with_weight(weight);
            let inputs: Vec<BlendIn> = words
                .iter()
                .map(|&(src, dst)| BlendIn {
                    src: src.map(|x| x & max_code(s)),
                    dst: dst.map(|x| x & max_code(f)),
                })
                .collect();
            common::assert_drivers_agree(&b, (), &inputs);
        }

        #[test]
        fn random_configs_never_panic_and_errors_name_the_field(
            src_bits in config_field(), fb_bits in config_field(),
            weighted in any::<bool>(), weight_bits in config_field(),
        ) {
            let ok_bits = |x: u32| (1..=16).contains(&x);
            let bad: Vec<&str> = [
                ("blend.src_bits", ok_bits(src_bits)),
                ("blend.bits", ok_bits(fb_bits)),
                ("blend.constant_bits", ok_bits(weight_bits)),
            ]
            .iter()
            .filter(|(_, ok)| !ok)
            .map(|(n, _)| *n)
            .collect();
            match Blend::additive(src_bits, fb_bits, weighted, weight_bits) {
                Ok(b) => {
                    prop_assert!(bad.is_empty());
                    prop_assert_eq!(
                        (b.src_bits(), b.bits(), b.weighted(), b.constant_bits()),
                        (src_bits, fb_bits, weighted, weight_bits)
                    );
                }
                Err(e) => {
                    prop_assert!(bad.contains(&e.field()), "{} not in {:?}", e.field(), bad);
                }
            }
        }
    }

    #[test]
    fn bounds_are_nearly_attained() {
        // The derived bounds are not loose: the worst observed error comes close to them.
        for (s, f, wtd, k) in [
            (8, 10, false, 8),
            (8, 12, false, 8),
            (3, 2, false, 8),
            (8, 8, true, 8),
            (3, 2, true, 8),
            (5, 7, true, 8),
        ] {
            let b = blend(s, f, wtd, k);
            let ws = if wtd { max_code(k) } else { 0 };
            let mut worst = 0.0f64;
            let mut worst_ratio = 0.0f64;
            for src in 0..=max_code(s) {
                for w in 0..=ws {
                    let q = b.with_weight(w).contribution(src) as f64;
                    let e = (q - contribution_codes(src, s, f, twin_weight(&b, w))).abs();
                    worst = worst.max(e);
                    worst_ratio = worst_ratio.max(e / bound(&b, w).max(1e-300));
                }
            }
            println!(
                "{s}→{f} weighted {wtd} k {k}: worst {worst:.4} LSB, worst/bound {worst_ratio:.4}"
            );
            assert!(worst_ratio <= 1.0 + 1e-9);
            assert!(
                worst_ratio > 0.7,
                "bound for {s}→{f} looks loose: {worst_ratio}"
            );
        }
    }

    #[test]
    fn the_additive_datapath_has_latency_3_and_refuses_other_states() {
        assert_eq!(
            blend(8, 8, false, 8).timing(),
            rtl_model::Timing { latency: 3, ii: 1 }
        );
        use rtl_model::units::blend::{BlendConfig, BlendDatapath, BlendEquation, BlendFactor};
        for (eq, sf, df) in [
            (BlendEquation::Subtract, BlendFactor::One, BlendFactor::One),
            (BlendEquation::Add, BlendFactor::SrcAlpha, BlendFactor::One),
            (BlendEquation::Add, BlendFactor::One, BlendFactor::Zero),
        ] {
            let e = BlendConfig {
                equation: eq,
                src_factor: sf,
                dst_factor: df,
                datapath: BlendDatapath::Additive,
                ..BlendConfig::default()
            }
            .build()
            .unwrap_err();
            assert_eq!(e.field(), "blend.datapath");
        }
    }

    /// The batch path (its contribution table) against the span driver on every source,
    /// destination and weight of 4-bit words, weighted and not, narrowing and widening
    /// (2¹² inputs each: exhaustive), at several chunk sizes.
    #[test]
    fn batch_path_agrees_exhaustively_at_4_bits() {
        let inputs: Vec<BlendIn> = (0..1u32 << 8)
            .map(|i| BlendIn {
                src: [i & 15, (i >> 4) & 15, 15 - (i & 15), 0],
                dst: [(i >> 4) & 15, i & 15, 0, 15],
            })
            .collect();
        for (src, fb) in [(4u32, 4u32), (4, 3), (3, 4)] {
            for weighted in [false, true] {
                for w in 0..16 {
                    let b = blend(src, fb, weighted, 4).with_weight(w);
                    let mut c = Counters::default();
                    let span = rtl_model::driver::run_span(&b, &mut (), &inputs, &mut c);
                    common::assert_batch_agrees(&b, &(), &inputs, &span, &(), &c);
                }
            }
        }
    }

    /// `blend_lanes_at` (the J buffer's single-channel lane form, lane i on word i) against the span driver
    /// on the inputs it stands for, `[src, 0, 0, 0]` over `[dst, 0, 0, 0]`: channel 0's
    /// outputs, and the counters once the span's timing is added.
    fn lanes_agree_with_span(b: &Blend, src: &[u32], dst: &[u32]) {
        let inputs: Vec<BlendIn> = src
            .iter()
            .zip(dst)
            .map(|(&s, &d)| BlendIn {
                src: [s, 0, 0, 0],
                dst: [d, 0, 0, 0],
            })
            .collect();
        let mut c_span = Counters::default();
        let out = rtl_model::driver::run_span(b, &mut (), &inputs, &mut c_span);
        let mut lanes = dst.to_vec();
        let mut c = Counters::default();
        b.blend_lanes_at(src, (&super::identity(src.len()), 0), &mut lanes, &mut c);
        let mut tally = rtl_model::driver::SpanTally::new();
        tally.add(src.len());
        tally.close(b.timing(), &mut c);
        let ch0: Vec<u32> = out.iter().map(|o| o[0]).collect();
        assert_eq!(
            lanes, ch0,
            "blend_lanes_at outputs differ from the span driver's"
        );
        assert_eq!(
            c, c_span,
            "blend_lanes_at counters differ from the span driver's"
        );
        // The same lanes on the words in reverse, past an offset of 5: the same
        // outputs, reversed, and the same counters.
        let n = src.len();
        let at: Vec<u32> = (0..n as u32).map(|i| 5 + (n as u32 - 1 - i)).collect();
        let mut rev: Vec<u32> = dst.iter().rev().copied().collect();
        let mut c_rev = Counters::default();
        b.blend_lanes_at(src, (&at, 5), &mut rev, &mut c_rev);
        rev.reverse();
        assert_eq!(rev, lanes, "blend_lanes_at through a reversed map");
        tally.close(b.timing(), &mut c_rev);
        assert_eq!(
            c_rev, c_span,
            "blend_lanes_at counters through a reversed map"
        );
        // The lanes on a walk's words: rows of 13, rightward and leftward in turn,
        // every fifth word skipped (runs broken at odd places, and blocks of the
        // lane form's runs mixed with scattered lanes): each lane's output is its
        // word's, the counters the same.
        let walk: Vec<u32> = (0..)
            .flat_map(|r: u32| {
                let row =
                    (0..13).map(move |c| r * 13 + if r.is_multiple_of(2) { c } else { 12 - c });
                row.filter(|&p| p % 5 != 4)
            })
            .take(n)
            .collect();
        let words = walk.iter().max().map_or(0, |&m| m as usize + 1);
        let mut walked = vec![0u32; words];
        for (&p, &d) in walk.iter().zip(dst) {
            walked[p as usize] = d;
        }
        let mut c_walk = Counters::default();
        b.blend_lanes_at(src, (&walk, 0), &mut walked, &mut c_walk);
        for (i, &p) in walk.iter().enumerate() {
            assert_eq!(
                walked[p as usize], lanes[i],
                "lane {i} on word {p} of a walk"
            );
        }
        tally.close(b.timing(), &mut c_walk);
        assert_eq!(c_walk, c_span, "blend_lanes_at counters on a walk's words");
        // Lanes 2k and 2k + 1 on word k: the second reads what the first wrote.
        let at: Vec<u32> = (0..n as u32).map(|i| i / 2).collect();
        let mut shared: Vec<u32> = dst.iter().step_by(2).copied().collect();
        b.blend_lanes_at(src, (&at, 0), &mut shared, &mut Counters::default());
        for (k, &v) in shared.iter().enumerate() {
            let mut want = dst[2 * k];
            for &s in src.iter().skip(2 * k).take(2) {
                let one = [BlendIn {
                    src: [s, 0, 0, 0],
                    dst: [want, 0, 0, 0],
                }];
                want =
                    rtl_model::driver::run_span(b, &mut (), &one, &mut Counters::default())[0][0];
            }
            assert_eq!(v, want, "word {k}: the lanes one after the other");
        }
        // Lanes whose source is 0 (whole blocks the J buffer's caller leaves out and
        // counts with `count_zero_lanes`): every word at most full scale is written
        // back as it was, and the counters are what `count_zero_lanes` counts.
        let zeros = vec![0u32; n];
        let words: Vec<u32> = dst.iter().map(|&d| d.min(b.max())).collect();
        let mut blended = words.clone();
        let (mut c_blend, mut c_count) = (Counters::default(), Counters::default());
        b.blend_lanes_at(&zeros, (&super::identity(n), 0), &mut blended, &mut c_blend);
        b.count_zero_lanes(n as u64, &mut c_count);
        assert_eq!(blended, words, "a source of 0 leaves its word as it was");
        assert_eq!(
            c_blend, c_count,
            "count_zero_lanes counts what the blend counts"
        );
        // The prepared form blends as the one-call form does.
        let mut prepared = dst.to_vec();
        let mut c_prepared = Counters::default();
        b.lanes_at().blend(
            src,
            (&super::identity(n), 0),
            &mut prepared,
            &mut c_prepared,
        );
        let mut once = dst.to_vec();
        let mut c_once = Counters::default();
        b.blend_lanes_at(src, (&super::identity(n), 0), &mut once, &mut c_once);
        assert_eq!((prepared, c_prepared), (once, c_once), "lanes_at().blend");
    }

    /// Exhaustive at 4-bit words: every source, destination and weight, weighted and
    /// not, narrowing, equal and widening.
    #[test]
    fn lane_form_agrees_with_the_span_driver_exhaustively_at_4_bits() {
        let src: Vec<u32> = (0..256u32).map(|i| i & 15).collect();
        let dst: Vec<u32> = (0..256u32).map(|i| i >> 4).collect();
        for (s, f) in [(4u32, 4u32), (4, 3), (3, 4)] {
            for weighted in [false, true] {
                for w in 0..16 {
                    lanes_agree_with_span(&blend(s, f, weighted, 4).with_weight(w), &src, &dst);
                }
            }
        }
    }

    /// `blend_pixels_in_place` (the framebuffer's unweighted form) against the span
    /// driver on the inputs it stands for, lane i on its own pixel i: the outputs, and
    /// the counters once the span's timing is added; a weighted blend or a source
    /// wider than the table is refused with nothing done. Then the lanes again in
    /// reverse onto one pixel each pair: a read-modify-write per lane, in lane order.
    fn pixels_agree_with_span(b: &Blend, src: &[[u32; 4]], dst: &[[u32; 4]]) {
        let mut out = dst.to_vec();
        let mut c = Counters::default();
        let done = b.blend_pixels_in_place(src.len(), |i| (i, src[i]), &mut out, &mut c);
        if b.weighted() || b.src_bits() > CONTRIBUTION_LUT_BITS {
            assert!(
                !done,
                "blend_pixels_in_place ran on a config it does not serve"
            );
            assert_eq!(out, dst);
            assert_eq!(c, Counters::default());
            return;
        }
        assert!(done, "blend_pixels_in_place refused an unweighted config");
        // Lanes 2k and 2k + 1 on pixel k: the second reads what the first wrote.
        let mut shared: Vec<[u32; 4]> = dst.iter().step_by(2).copied().collect();
        let mut c_shared = Counters::default();
        assert!(b.blend_pixels_in_place(
            src.len(),
            |i| (i / 2, src[i]),
            &mut shared,
            &mut c_shared
        ));
        for (k, px) in shared.iter().enumerate() {
            let mut want = dst[2 * k];
            for s in src.iter().skip(2 * k).take(2) {
                let one = [BlendIn { src: *s, dst: want }];
                want = rtl_model::driver::run_span(b, &mut (), &one, &mut Counters::default())[0];
            }
            assert_eq!(*px, want, "pixel {k}: the lanes one after the other");
        }
        let inputs: Vec<BlendIn> = src
            .iter()
            .zip(dst)
            .map(|(&s, &d)| BlendIn { src: s, dst: d })
            .collect();
        let mut c_span = Counters::default();
        let want = rtl_model::driver::run_span(b, &mut (), &inputs, &mut c_span);
        let mut tally = rtl_model::driver::SpanTally::new();
        tally.add(src.len());
        tally.close(b.timing(), &mut c);
        assert_eq!(
            out, want,
            "blend_pixels_in_place outputs differ from the span driver's"
        );
        assert_eq!(
            c, c_span,
            "blend_pixels_in_place counters differ from the span driver's"
        );
    }

    /// Exhaustive at 4-bit words: every source and destination code on every channel
    /// (2⁸ pairs, rotated across the channels), narrowing, equal and widening; weighted
    /// configs refused.
    #[test]
    fn pixel_form_agrees_with_the_span_driver_exhaustively_at_4_bits() {
        let src: Vec<[u32; 4]> = (0..256u32)
            .map(|i| [i & 15, i >> 4, 15 - (i & 15), (i * 7) & 15])
            .collect();
        let dst: Vec<[u32; 4]> = (0..256u32)
            .map(|i| [i >> 4, i & 15, (i * 3) & 15, 15 - (i >> 4)])
            .collect();
        for (s, f) in [(4u32, 4u32), (4, 3), (3, 4)] {
            for weighted in [false, true] {
                pixels_agree_with_span(&blend(s, f, weighted, 4), &src, &dst);
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(500))]
        /// Random configs (sources past the table's width too), words and weights.
        #[test]
        fn lane_form_agrees_with_the_span_driver(
            s in 1u32..=16, f in 1u32..=16, k in 1u32..=16, weighted in any::<bool>(),
            weight in any::<u32>(),
            words in prop::collection::vec((any::<u32>(), any::<u32>()), 0..60),
        ) {
            let b = blend(s, f, weighted, k).with_weight(weight);
            let src: Vec<u32> = words.iter().map(|w| w.0 & max_code(s)).collect();
            let dst: Vec<u32> = words.iter().map(|w| w.1 & max_code(f)).collect();
            lanes_agree_with_span(&b, &src, &dst);
        }

        /// Random configs (sources past the table's width too) and raw words (bits
        /// above the wires included).
        #[test]
        fn pixel_form_agrees_with_the_span_driver(
            s in 1u32..=16, f in 1u32..=16, k in 1u32..=16, weighted in any::<bool>(),
            words in prop::collection::vec((any::<[u32; 4]>(), any::<[u32; 4]>()), 0..60),
        ) {
            let b = blend(s, f, weighted, k);
            let src: Vec<[u32; 4]> = words.iter().map(|w| w.0).collect();
            let dst: Vec<[u32; 4]> = words.iter().map(|w| w.1).collect();
            pixels_agree_with_span(&b, &src, &dst);
        }
    }
}
