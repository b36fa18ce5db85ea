//! texture_combiner against its f64 twin (the spec's equations): every function
//! exhaustively at 8 bits where the input space allows (≤ 2²⁴ for INTERPOLATE), ≥ 10⁶
//! seeded random cases for DOT3 (2⁴⁸ inputs), both rounding modes and all three scales;
//! 4 bits exhaustively (DOT3 at 3 bits); random configs (sources, operand mappings,
//! scales) at 3, 8, 12 and 16 bits; driver agreement; config errors; the soft-float
//! against the machine's binary32.
//!
//! Bound (docs/units.md#texture_combiner): the unit rounds the exact value X / D once,
//! after the clamp to [0, N]; so |out − N·clamp(twin)| ≤ ½ LSB in both modes. In the Mesa
//! mode the one float-rounded function, ADD_SIGNED at scale 1, has an exact value
//! a0 + a1 − N/2 halfway between two codes and the float error of Mesa's three binary32
//! operations (≤ 3 · 2⁻²⁴ relative on values ≤ 2, i.e. ≤ 6 · 2⁻²⁴ · N < ½ LSB for
//! n ≤ 16) can only pick one of the two: again exactly ½ LSB. The f64 twin's own error
//! (≤ 10⁻¹² LSB) is the test's slack.

mod common;

use glare_pipeline::reference::texture_combiner as twin;
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::units::texture_combiner::{
    binary32, CombineFunction, CombineSource, CombinerRounding, OperandAlpha, OperandRgb,
    TextureCombiner, TextureCombinerConfig, TextureCombinerIn,
};
use rtl_model::Counters;

const SLACK: f64 = 1e-9;

/// The source an argument reads, as f64 values in [0, 1].
fn source(input: &TextureCombinerIn, s: CombineSource, max: f64) -> [f64; 4] {
    let c = match s {
        CombineSource::Texture => input.texture,
        CombineSource::Constant => input.constant,
        CombineSource::PrimaryColor => input.primary_color,
        CombineSource::Previous => input.previous,
    };
    c.map(|v| v as f64 / max)
}

fn function(f: CombineFunction, a: [f64; 3]) -> f64 {
    match f {
        CombineFunction::Replace => twin::replace(a[0]),
        CombineFunction::Modulate => twin::modulate(a[0], a[1]),
        CombineFunction::Add => twin::add(a[0], a[1]),
        CombineFunction::AddSigned => twin::add_signed(a[0], a[1]),
        CombineFunction::Interpolate => twin::interpolate(a[0], a[1], a[2]),
        CombineFunction::Subtract => twin::subtract(a[0], a[1]),
        CombineFunction::Dot3Rgb | CombineFunction::Dot3Rgba => unreachable!(),
    }
}

/// The twin's RGBA result, in output codes (N · value).
fn twin_codes(cfg: &TextureCombinerConfig, input: &TextureCombinerIn) -> [f64; 4] {
    let max = ((1u64 << cfg.bits) - 1) as f64;
    let rgb_arg = |i: usize, ch: usize| {
        let src = source(input, cfg.source_rgb[i], max);
        let op = cfg.operand_rgb[i];
        let alpha = matches!(op, OperandRgb::SrcAlpha | OperandRgb::OneMinusSrcAlpha);
        let inv = matches!(
            op,
            OperandRgb::OneMinusSrcColor | OperandRgb::OneMinusSrcAlpha
        );
        twin::operand(src[if alpha { 3 } else { ch }], inv)
    };
    let alpha_arg = |i: usize| {
        let src = source(input, cfg.source_alpha[i], max);
        twin::operand(
            src[3],
            cfg.operand_alpha[i] == OperandAlpha::OneMinusSrcAlpha,
        )
    };
    let (rs, als) = (cfg.rgb_scale as f64, cfg.alpha_scale as f64);
    let mut out = [0.0; 4];
    let dot = || {
        twin::dot3(
            std::array::from_fn(|ch| rgb_arg(0, ch)),
            std::array::from_fn(|ch| rgb_arg(1, ch)),
        )
    };
    for (ch, o) in out.iter_mut().enumerate().take(3) {
        *o = if cfg.combine_rgb.is_dot3() {
            twin::scale_and_clamp(dot(), rs)
        } else {
            let a = std::array::from_fn(|i| rgb_arg(i, ch));
            twin::scale_and_clamp(function(cfg.combine_rgb, a), rs)
        };
    }
    out[3] = if cfg.combine_rgb == CombineFunction::Dot3Rgba {
        twin::scale_and_clamp(dot(), als)
    } else {
        twin::scale_and_clamp(
            function(cfg.combine_alpha, std::array::from_fn(alpha_arg)),
            als,
        )
    };
    out.map(|v| v * max)
}

/// Assert the ½-LSB bound on every channel.
fn check(u: &TextureCombiner, input: &TextureCombinerIn) {
    let cfg = u.config();
    let got = u.combine(input, &mut Counters::default());
    let want = twin_codes(cfg, input);
    for ch in 0..4 {
        let err = got[ch] as f64 - want[ch];
        assert!(
            err.abs() <= 0.5 + SLACK,
            "{cfg:?}\n{input:?}\nchannel {ch}: {} want {} (err {err})",
            got[ch],
            want[ch]
        );
    }
}

fn unit(
    bits: u32,
    rgb: CombineFunction,
    alpha: CombineFunction,
    r: CombinerRounding,
    s: u32,
) -> TextureCombiner {
    let mut cfg = TextureCombinerConfig::with_functions(bits, rgb, alpha, r);
    cfg.rgb_scale = s;
    cfg.alpha_scale = s;
    cfg.build().unwrap()
}

/// Every (Arg0, Arg1) pair on every channel (the four channels carry (a, b), (b, a),
/// (N − a, b), (a, N − b) so each sees the whole space), Arg2 = `c` per channel.
fn all_pairs(bits: u32, c: [u32; 4], mut f: impl FnMut(&TextureCombinerIn)) {
    let m = (1u32 << bits) - 1;
    for a in 0..=m {
        for b in 0..=m {
            f(&TextureCombinerIn {
                texture: [a, b, m - a, a],
                constant: [b, a, b, m - b],
                primary_color: c,
                previous: [0; 4],
            });
        }
    }
}

const TWO_ARG: [CombineFunction; 5] = [
    CombineFunction::Replace,
    CombineFunction::Modulate,
    CombineFunction::Add,
    CombineFunction::AddSigned,
    CombineFunction::Subtract,
];

#[test]
fn two_argument_functions_exhaustive_at_8_and_4_bits() {
    for bits in [8u32, 4] {
        for f in TWO_ARG {
            for r in CombinerRounding::ALL {
                for s in [1, 2, 4] {
                    let u = unit(bits, f, f, r, s);
                    all_pairs(bits, [0; 4], |i| check(&u, i));
                }
            }
        }
    }
}

#[test]
fn interpolate_exhaustive_at_8_and_4_bits() {
    // All 2²⁴ (Arg0, Arg1, Arg2) triples at 8 bits: Arg2 in the primary colour, each
    // channel all (Arg0, Arg1) pairs with a quarter of Arg2; every scale, integer rounding
    // (the Mesa mode is the same integer path for INTERPOLATE — asserted below).
    let f = CombineFunction::Interpolate;
    for bits in [8u32, 4] {
        let m = (1u32 << bits) - 1;
        for s in [1, 2, 4] {
            let u = unit(bits, f, f, CombinerRounding::GeforceInteger, s);
            let mesa = unit(bits, f, f, CombinerRounding::MesaFloat32, s);
            // Channel k takes Arg2 from the k-th quarter of the codes.
            let q = (m + 1) / 4;
            for c in 0..q {
                all_pairs(bits, [c, c + q, c + 2 * q, c + 3 * q], |i| {
                    check(&u, i);
                    if s == 1 || c % 17 == 0 {
                        let mut ctr = Counters::default();
                        assert_eq!(u.combine(i, &mut ctr), mesa.combine(i, &mut ctr));
                    }
                });
            }
        }
    }
}

/// Random DOT3 inputs: `cases` draws of all six RGB operand channels.
fn dot3_random(u: &TextureCombiner, cases: usize, seed: u64) {
    let m = (1u32 << u.config().bits) - 1;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let px = |rng: &mut ChaCha8Rng| std::array::from_fn(|_| rng.random_range(0..=m));
    for _ in 0..cases {
        let i = TextureCombinerIn {
            texture: px(&mut rng),
            constant: px(&mut rng),
            primary_color: px(&mut rng),
            previous: px(&mut rng),
        };
        check(u, &i);
    }
}

#[test]
fn dot3_a_million_random_cases_per_function_at_8_bits() {
    // 2⁴⁸ inputs: 10⁶ seeded random per function (⅓ at each scale); each case checks
    // r, g, b (and a for DOT3_RGBA). Both modes share the DOT3 path (asserted in the
    // random-config test), so the integer mode carries the million.
    for (k, f) in [CombineFunction::Dot3Rgb, CombineFunction::Dot3Rgba]
        .into_iter()
        .enumerate()
    {
        for s in [1, 2, 4] {
            let u = unit(
                8,
                f,
                CombineFunction::Replace,
                CombinerRounding::GeforceInteger,
                s,
            );
            dot3_random(&u, 1_000_000 / 3 + 1, 100 * k as u64 + s as u64);
        }
    }
}

#[test]
fn dot3_exhaustive_at_3_bits_and_the_axes_at_8() {
    // 3 bits: all 2¹⁸ (Arg0, Arg1) colour pairs.
    for f in [CombineFunction::Dot3Rgb, CombineFunction::Dot3Rgba] {
        for s in [1, 2, 4] {
            let u = unit(
                3,
                f,
                CombineFunction::Replace,
                CombinerRounding::GeforceInteger,
                s,
            );
            for k in 0..1u32 << 18 {
                let d = |j: u32| (k >> (3 * j)) & 7;
                let i = TextureCombinerIn {
                    texture: [d(0), d(1), d(2), 0],
                    constant: [d(3), d(4), d(5), 0],
                    ..Default::default()
                };
                check(&u, &i);
            }
            // 8 bits: every (Arg0r, Arg1r) with g and b at the mid codes 127 / 128.
            let u = unit(
                8,
                f,
                CombineFunction::Replace,
                CombinerRounding::GeforceInteger,
                s,
            );
            all_pairs(8, [0; 4], |i| {
                let mut i = *i;
                i.texture[1..3].copy_from_slice(&[127, 128]);
                i.constant[1..3].copy_from_slice(&[128, 127]);
                check(&u, &i);
            });
        }
    }
}

#[test]
fn integer_mode_add_signed_rounds_the_tie_up() {
    // Scale 1 at 8 bits: a + b − 127.5 → a + b − 127, clamped to [0, 255].
    let f = CombineFunction::AddSigned;
    let u = unit(8, f, f, CombinerRounding::GeforceInteger, 1);
    all_pairs(8, [0; 4], |i| {
        let got = u.combine(i, &mut Counters::default());
        let want = (i.texture[0] as i32 + i.constant[0] as i32 - 127).clamp(0, 255);
        assert_eq!(got[0], want as u32, "{i:?}");
    });
}

#[test]
fn modes_differ_only_in_add_signed_ties() {
    // Measured: how many 8-bit ADD_SIGNED ties Mesa's floats send down (the integer
    // mode sends all up). Every other function is identical in the two modes.
    let f = CombineFunction::AddSigned;
    let (g, m) = (
        unit(8, f, f, CombinerRounding::GeforceInteger, 1),
        unit(8, f, f, CombinerRounding::MesaFloat32, 1),
    );
    let mut differ = 0;
    let mut clamped = 0;
    all_pairs(8, [0; 4], |i| {
        let (mut cg, mut cm) = (Counters::default(), Counters::default());
        let (a, b) = (g.combine(i, &mut cg), m.combine(i, &mut cm));
        for ch in 0..4 {
            assert!(a[ch] == b[ch] || a[ch] == b[ch] + 1, "{i:?}");
            differ += (a[ch] != b[ch]) as u32;
        }
        // Both modes count a clamp on the exact value a + b − ½ outside [0, 1].
        assert_eq!(cm.saturations, cg.saturations, "{i:?}");
        clamped += cm.saturations;
    });
    assert!(differ > 0 && differ < 4 * 65536 / 10, "{differ}");
    assert!(clamped > 0);
    for f in TWO_ARG
        .into_iter()
        .filter(|&f| f != CombineFunction::AddSigned)
    {
        let (g, m) = (
            unit(8, f, f, CombinerRounding::GeforceInteger, 1),
            unit(8, f, f, CombinerRounding::MesaFloat32, 1),
        );
        all_pairs(8, [0; 4], |i| {
            assert_eq!(
                g.combine(i, &mut Counters::default()),
                m.combine(i, &mut Counters::default())
            );
        });
    }
}

#[test]
fn clamps_are_counted() {
    let f = CombineFunction::Add;
    let u = unit(8, f, f, CombinerRounding::GeforceInteger, 1);
    let mut ctr = Counters::default();
    let i = TextureCombinerIn {
        texture: [200, 100, 0, 255],
        constant: [100, 100, 0, 1],
        ..Default::default()
    };
    assert_eq!(u.combine(&i, &mut ctr), [255, 200, 0, 255]);
    assert_eq!(ctr.saturations, 2); // r and a; g = 200 and b = 0 are exact
    let f = CombineFunction::Subtract;
    let u = unit(8, f, f, CombinerRounding::MesaFloat32, 4);
    let mut ctr = Counters::default();
    assert_eq!(u.combine(&i, &mut ctr), [255, 0, 0, 255]);
    assert_eq!(ctr.saturations, 2); // r and a; g = 0 and b = 0 are exact
}

#[test]
fn soft_float_matches_the_machines_binary32() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    // Values of the magnitudes the datapath meets: 2⁻³⁰ ..= 2³, both signs, and zero.
    let draw = |rng: &mut ChaCha8Rng| -> f32 {
        if rng.random_range(0..50) == 0 {
            return 0.0;
        }
        let e = rng.random_range(-30..=3);
        let m: f32 = rng.random_range(1.0..2.0);
        let s = if rng.random() { -1.0 } else { 1.0 };
        s * m * 2f32.powi(e)
    };
    for _ in 0..200_000 {
        let (a, b) = (draw(&mut rng), draw(&mut rng));
        let (x, y) = (a.to_bits(), b.to_bits());
        assert_eq!(f32::from_bits(binary32::add(x, y)), a + b, "{a} + {b}");
        assert_eq!(f32::from_bits(binary32::sub(x, y)), a - b, "{a} - {b}");
        assert_eq!(f32::from_bits(binary32::mul(x, y)), a * b, "{a} * {b}");
    }
    for bits in 1..=16u32 {
        let m = (1u32 << bits) - 1;
        let r = 1.0f32 / m as f32;
        assert_eq!(binary32::reciprocal_of_max(bits), r.to_bits());
        for c in (0..=m).step_by(1 + (m as usize >> 10)) {
            assert_eq!(binary32::from_unorm(c, bits), (c as f32 * r).to_bits());
        }
        // Mesa's conversion: v·(1 − 2⁻ⁿ) + 2²³⁻ⁿ, low n bits.
        let k = m as f32 / (1u32 << bits) as f32;
        let bias = (1u32 << (23 - bits)) as f32;
        for _ in 0..5_000 {
            let v: f32 = rng.random_range(0.0..1.0);
            let want = ((v * k + bias).to_bits()) & m;
            assert_eq!(binary32::to_unorm(v.to_bits(), bits), want, "{v} at {bits}");
        }
        assert_eq!(binary32::to_unorm(1.5f32.to_bits(), bits), m);
        assert_eq!(binary32::to_unorm((-0.25f32).to_bits(), bits), 0);
    }
}

#[test]
fn extreme_inputs_never_panic() {
    // Codes above N are masked to n wires; all-zero and all-ones sources.
    for r in CombinerRounding::ALL {
        for f in CombineFunction::ALL {
            let alpha = if f.is_dot3() { CombineFunction::Add } else { f };
            for bits in [1u32, 8, 16] {
                for s in [1, 4] {
                    let u = unit(bits, f, alpha, r, s);
                    for v in [0u32, u32::MAX, (1 << bits) - 1] {
                        let i = TextureCombinerIn {
                            texture: [v; 4],
                            constant: [v; 4],
                            primary_color: [v; 4],
                            previous: [v; 4],
                        };
                        let out = u.combine(&i, &mut Counters::default());
                        assert!(out.iter().all(|&c| c < 1 << bits));
                        if v < 1 << bits {
                            check(&u, &i);
                        }
                    }
                }
            }
        }
    }
}

fn any_config(bits: u32) -> impl Strategy<Value = TextureCombinerConfig> {
    let src = prop::sample::select(CombineSource::ALL.to_vec());
    let op_rgb = prop::sample::select(OperandRgb::ALL.to_vec());
    let op_a = prop::sample::select(OperandAlpha::ALL.to_vec());
    let scale = prop::sample::select(vec![1u32, 2, 4]);
    (
        prop::sample::select(CombineFunction::ALL.to_vec()),
        prop::sample::select(CombineFunction::ALPHA.to_vec()),
        [src.clone(), src.clone(), src.clone()],
        [op_rgb.clone(), op_rgb.clone(), op_rgb],
        [src.clone(), src.clone(), src],
        [op_a.clone(), op_a.clone(), op_a],
        (scale.clone(), scale),
        prop::sample::select(CombinerRounding::ALL.to_vec()),
    )
        .prop_map(
            move |(
                rgb,
                alpha,
                source_rgb,
                operand_rgb,
                source_alpha,
                operand_alpha,
                (rs, als),
                rounding,
            )| {
                TextureCombinerConfig {
                    bits,
                    combine_rgb: rgb,
                    combine_alpha: alpha,
                    source_rgb,
                    operand_rgb,
                    source_alpha,
                    operand_alpha,
                    rgb_scale: rs,
                    alpha_scale: als,
                    rounding,
                }
            },
        )
}

fn any_input(bits: u32) -> impl Strategy<Value = TextureCombinerIn> {
    let m = (1u32 << bits) - 1;
    let px = prop::array::uniform4(0..=m);
    (px.clone(), px.clone(), px.clone(), px).prop_map(|(t, c, p, v)| TextureCombinerIn {
        texture: t,
        constant: c,
        primary_color: p,
        previous: v,
    })
}

fn config_and_inputs(
    n: usize,
) -> impl Strategy<Value = (TextureCombinerConfig, Vec<TextureCombinerIn>)> {
    prop::sample::select(vec![3u32, 8, 12, 16]).prop_flat_map(move |bits| {
        (
            any_config(bits),
            prop::collection::vec(any_input(bits), 1..n),
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn random_configs_within_half_lsb_at_3_8_12_16_bits((cfg, inputs) in config_and_inputs(32)) {
        let u = cfg.build().unwrap();
        let mut other = cfg;
        other.rounding = match cfg.rounding {
            CombinerRounding::GeforceInteger => CombinerRounding::MesaFloat32,
            CombinerRounding::MesaFloat32 => CombinerRounding::GeforceInteger,
        };
        let other = other.build().unwrap();
        for i in &inputs {
            check(&u, i);
            // The modes differ only where ADD_SIGNED runs at scale 1.
            let adds1 = |f: CombineFunction, s: u32| f == CombineFunction::AddSigned && s == 1;
            if !adds1(cfg.combine_rgb, cfg.rgb_scale) && !adds1(cfg.combine_alpha, cfg.alpha_scale) {
                prop_assert_eq!(u.combine(i, &mut Counters::default()), other.combine(i, &mut Counters::default()));
            }
        }
    }

    #[test]
    fn tick_and_span_drivers_agree((cfg, inputs) in config_and_inputs(40)) {
        let u = cfg.build().unwrap();
        let outs = common::assert_drivers_agree(&u, (), &inputs);
        // The drivers all run the unit's kernel: they must run it as `combine`, which
        // the other tests check against the twin.
        for (i, o) in inputs.iter().zip(outs) {
            prop_assert_eq!(o, u.combine(i, &mut Counters::default()));
        }
    }

    #[test]
    fn out_of_range_width_is_an_error_naming_the_field(bits in prop_oneof![Just(0u32), 17u32..1000]) {
        let mut cfg = TextureCombinerConfig::geforce();
        cfg.bits = bits;
        let e = cfg.build().unwrap_err();
        prop_assert_eq!(e.field(), "texture_combiner.bits");
    }

    #[test]
    fn a_scale_other_than_1_2_4_is_an_error_naming_the_field(s in any::<u32>().prop_filter("not a GL scale", |s| ![1, 2, 4].contains(s)), alpha in any::<bool>()) {
        let mut cfg = TextureCombinerConfig::geforce();
        if alpha { cfg.alpha_scale = s } else { cfg.rgb_scale = s }
        let field = if alpha { "texture_combiner.alpha_scale" } else { "texture_combiner.rgb_scale" };
        let e = cfg.build().unwrap_err();
        prop_assert_eq!(e.field(), field);
    }
}

#[test]
fn dot3_as_the_alpha_function_is_an_error_naming_the_field() {
    for f in [CombineFunction::Dot3Rgb, CombineFunction::Dot3Rgba] {
        let mut cfg = TextureCombinerConfig::geforce();
        cfg.combine_alpha = f;
        assert_eq!(
            TextureCombiner::new(cfg).unwrap_err().field(),
            "texture_combiner.combine_alpha"
        );
    }
}

#[test]
fn the_single_rounding_is_exact_for_every_x_up_to_n_squared() {
    // round(X / N) by t = X + 2ⁿ⁻¹, (t + (t >> n)) >> n, for every 0 ≤ X ≤ N² at n ≤ 12;
    // D = 2 rounds half up; D = 1 passes X; outside [0, N·D] clamps (counted).
    for bits in 1..=12u32 {
        let u = unit(
            bits,
            CombineFunction::Add,
            CombineFunction::Add,
            CombinerRounding::GeforceInteger,
            1,
        );
        let n = (1i64 << bits) - 1;
        let mut ctr = Counters::default();
        for x in 0..=n * n {
            assert_eq!(
                u.clamp_round((x, n), &mut ctr) as i64,
                (2 * x + n) / (2 * n),
                "{bits} bits: {x}"
            );
        }
        for x in 0..=2 * n {
            assert_eq!(u.clamp_round((x, 2), &mut ctr) as i64, (x + 1) / 2);
            assert_eq!(u.clamp_round((x.min(n), 1), &mut ctr) as i64, x.min(n));
        }
        assert_eq!(ctr.saturations, 0);
        assert_eq!(u.clamp_round((-1, n), &mut ctr), 0);
        assert_eq!(u.clamp_round((n * n + 1, n), &mut ctr) as i64, n);
        assert_eq!(u.clamp_round((2 * n + 1, 2), &mut ctr) as i64, n);
        assert_eq!(ctr.saturations, 3);
    }
}

/// The VCD trace's wires: the four sources' sixteen channels in, RGBA out, each an
/// n-bit wire carrying its code.
#[test]
fn trace_signals_are_the_sources_and_the_result_as_n_bit_wires() {
    use rtl_model::Unit;
    for bits in [3u32, 8, 16] {
        let u = unit(
            bits,
            CombineFunction::Modulate,
            CombineFunction::Modulate,
            CombinerRounding::GeforceInteger,
            1,
        );
        let m = (1u32 << bits) - 1;
        let code = |k: u32| (k * 37 + 5) & m;
        let input = TextureCombinerIn {
            texture: [0, 1, 2, 3].map(code),
            constant: [4, 5, 6, 7].map(code),
            primary_color: [8, 9, 10, 11].map(code),
            previous: [12, 13, 14, 15].map(code),
        };
        let ins = u.in_signals(&input);
        assert_eq!(ins.len(), 16);
        for (k, sig) in ins.iter().enumerate() {
            assert_eq!(sig.width, bits, "{}", sig.name);
            assert_eq!(sig.value, code(k as u32) as u64, "{}", sig.name);
        }
        let names: Vec<&str> = ins.iter().map(|s| s.name).collect();
        assert_eq!(
            [names[0], names[5], names[10], names[15]],
            ["texture_r", "constant_g", "primary_b", "previous_a"]
        );
        let outs = u.out_signals(&[code(1), code(2), code(3), code(4)]);
        assert_eq!(
            common::wires(&outs),
            [
                ("r", bits, 1),
                ("g", bits, 2),
                ("b", bits, 3),
                ("a", bits, 4)
            ]
            .map(|(n, w, k)| (n, w, code(k) as u64))
        );
    }
}

/// The Mesa mode's cost is the GeForce mode's plus one part, the binary32 ADD_SIGNED
/// path of the four channels, which holds three 32-bit registers per channel (its
/// third pipeline stage): 384 flip-flops more, and one more cycle of latency.
#[test]
fn the_mesa_mode_adds_the_binary32_path_and_its_stage() {
    use rtl_model::Unit;
    for bits in [3u32, 8, 16] {
        let [geforce, mesa] = [
            CombinerRounding::GeforceInteger,
            CombinerRounding::MesaFloat32,
        ]
        .map(|r| unit(bits, CombineFunction::AddSigned, CombineFunction::Add, r, 1));
        let (g, m) = (geforce.cost(), mesa.cost());
        assert_eq!(
            m.breakdown[..g.breakdown.len()],
            g.breakdown[..],
            "bits {bits}"
        );
        assert_eq!(m.breakdown.len(), g.breakdown.len() + 1);
        assert_eq!(
            m.breakdown.last().unwrap().0,
            "binary32 ADD_SIGNED path, ×4"
        );
        assert_eq!(m.cells.dff - g.cells.dff, 4.0 * 3.0 * 32.0, "bits {bits}");
        assert_eq!((geforce.timing().latency, mesa.timing().latency), (2, 3));
    }
}

/// 1/N rounded to binary32 never hangs on its sticky bit: for N = 2ⁿ − 1 the bits
/// rounded away from 2⁸¹/N are never exactly one half, so `reciprocal_of_max`'s result
/// is the same with the sticky bit 0 or 1 at every width (why cargo-mutants' four
/// mutants of that bit are equivalent, docs/testing.md), and equals the machine's
/// correctly rounded 1.0f32 / N.
#[test]
fn the_sticky_bit_of_one_over_n_never_decides_its_rounding() {
    for bits in 1..=16u32 {
        let m = ((1u32 << bits) - 1) as u128;
        let q = (1u128 << 80) / m;
        let [clear, set] = [0, 1].map(|sticky| binary32::round(false, (q << 1) | sticky, -81));
        assert_eq!(clear, set, "bits {bits}");
        assert_eq!(binary32::reciprocal_of_max(bits), clear, "bits {bits}");
        assert_eq!(clear, (1.0f32 / m as f32).to_bits(), "bits {bits}");
    }
}
