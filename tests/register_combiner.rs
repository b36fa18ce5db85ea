//! register_combiner (one general combiner stage of GL_NV_register_combiners) against
//! its f64 twin, the spec's real-valued equations; and the squaring chain built on it
//! (`pipeline::shading::squaring`).
//!
//! Bound derivation (also in docs/units.md, `## register_combiner`), in LSBs of the
//! register format (code c ↔ c/S, S = 2^(N−1) − 1), the twin fed the same register
//! codes as reals c/S:
//! * Select and map are exact: every Table 4 mapping of a code is a multiple of
//!   1/(2S), held in the s(N+2) half-LSB word (HALF_BIAS's −0.5 is S/2 codes).
//! * A product or dot product of exact mapped values is exact in units 1/(4S²) and is
//!   rounded ONCE to the working scale 1/(S·2^G): e_p = e_r·2^−G LSB, with e_r = ½
//!   for the round-to-nearest modes and 1 for the truncating ones (Trn, TrnZero).
//! * The sum AB + CD adds two rounded terms (2·e_p); the mux selects one (e_p; its
//!   SPARE0-alpha test c ≥ 2^(N−2) is exactly the twin's c/S ≥ 0.5 since S is odd).
//! * Bias −½ is exact in units 1/(2W); the scale multiplies the error: s·e_p (s = 1,
//!   2, 4, ½). The output rounding adds e_o = e_r, or 0 when it is exact (G = 0, no
//!   bias, scale ≠ ½: V = 2x·k is a multiple of 4).
//! * The clamp to [−1, 1] is 1-Lipschitz (both clamp).
//!
//! So |Δ| ≤ s·e_p + e_o for out1/out2 and the mux, s·2·e_p + e_o for the sum
//! (+ 10⁻⁹ for the twin's few f64 operations on values ≤ 2^24). At the GeForce default
//! (N = 9, G = 0, nearest): ½ LSB (1/510) for AB, CD and mux outputs at scale 1, 1 LSB
//! for the sum; 2 and 4 LSB at ×4.
//! Loading an I-bit unorm code u: round(u·S/U) within e_r LSB (exact when N − 1 = I).

mod combiner_common;
mod common;

use combiner_common::{one, random_file, rounding_error, sext};

use glare_pipeline::pipeline::shading::squaring::{
    power_by_squaring, specular_by_squaring, SquaringChain,
};
use glare_pipeline::reference::register_combiner as twin;
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::units::register_combiner::{
    unbound_texture, Bias, BiasConstant, ComponentUsage, FragmentInputs, Mapping, MuxSelect,
    PortionConfig, Register, RegisterCombiner, RegisterCombinerConfig, RegisterFile, Scale,
    VariableInput, REGISTER_COUNT,
};
use rtl_model::{Counters, Quant, Unit, UnitSummary};

const SLACK: f64 = 1e-9;

fn twin_mapping(m: Mapping) -> twin::Mapping {
    match m {
        Mapping::UnsignedIdentity => twin::Mapping::UnsignedIdentity,
        Mapping::UnsignedInvert => twin::Mapping::UnsignedInvert,
        Mapping::ExpandNormal => twin::Mapping::ExpandNormal,
        Mapping::ExpandNegate => twin::Mapping::ExpandNegate,
        Mapping::HalfBiasNormal => twin::Mapping::HalfBiasNormal,
        Mapping::HalfBiasNegate => twin::Mapping::HalfBiasNegate,
        Mapping::SignedIdentity => twin::Mapping::SignedIdentity,
        Mapping::SignedNegate => twin::Mapping::SignedNegate,
    }
}

/// The bounds (LSB) of out1, out2, out3 of one portion.
fn portion_bounds(c: &RegisterCombinerConfig, p: &PortionConfig) -> [f64; 3] {
    let e_r = rounding_error(c.rounding);
    let e_p = e_r / (c.guard_bits as f64).exp2();
    let exact_out = c.guard_bits == 0 && p.bias == Bias::None && p.scale != Scale::ByOneHalf;
    // HalfCode's bias is a whole number of codes: at G = 0 it adds no rounding either.
    let exact_out = exact_out
        || c.guard_bits == 0
            && p.bias == Bias::ByNegativeOneHalf
            && c.bias_constant == BiasConstant::HalfCode
            && p.scale != Scale::ByOneHalf;
    let e_o = if exact_out { 0.0 } else { e_r };
    let s = p.scale.value();
    let terms = if p.mux_sum { 1.0 } else { 2.0 };
    [s * e_p + e_o, s * e_p + e_o, s * terms * e_p + e_o]
}

/// The twin's view of a variable: the register component it reads, as a real.
fn value(file: &RegisterFile, v: &VariableInput, lane: usize, n: u32) -> f64 {
    if v.input == Register::Zero {
        return 0.0;
    }
    let comp = match v.component_usage {
        ComponentUsage::Rgb => lane,
        ComponentUsage::Alpha => 3,
        ComponentUsage::Blue => 2,
    };
    sext(file.regs[v.input.index()][comp], n) as f64 / one(n)
}

fn op(c: &RegisterCombinerConfig, p: &PortionConfig) -> twin::OutputOp {
    let bias = match (p.bias, c.bias_constant) {
        (Bias::None, _) => 0.0,
        (Bias::ByNegativeOneHalf, BiasConstant::ExactHalf) => p.bias.value(),
        (Bias::ByNegativeOneHalf, BiasConstant::HalfCode) => twin::nv2a_bias(c.internal_bits),
    };
    twin::OutputOp {
        ab_dot_product: p.ab_dot_product,
        cd_dot_product: p.cd_dot_product,
        mux_sum: p.mux_sum,
        scale: p.scale.value(),
        bias,
    }
}

/// Expected register set from the twin: per component (value in LSBs, bound).
fn expected(c: &RegisterCombinerConfig, file: &RegisterFile) -> [[(f64, f64); 4]; REGISTER_COUNT] {
    let n = c.internal_bits;
    let s = one(n);
    let mut want = file.regs.map(|r| r.map(|x| (sext(x, n) as f64, 0.0)));
    // Per-stage constants: read instead of the set's; the output passes the set's on.
    let mut read = *file;
    if let Some([c0, c1]) = c.stage_constants {
        read.set(Register::ConstantColor0, c0);
        read.set(Register::ConstantColor1, c1);
    }
    let file = &read;
    let spare0_alpha = sext(file.get(Register::Spare0)[3], n) as f64 / s;
    let mux_cd = match c.mux_select {
        MuxSelect::Msb => spare0_alpha >= 0.5,
        MuxSelect::Lsb => twin::mux_lsb_selects_cd(spare0_alpha, s),
    };
    let mapped =
        |v: &VariableInput, lane| twin::map(twin_mapping(v.mapping), value(file, v, lane, n));
    for alpha in [false, true] {
        let p = if alpha { c.alpha } else { c.rgb };
        let vars = [p.a, p.b, p.c, p.d];
        let outs: [[f64; 4]; 3] = if alpha {
            let r = twin::general_alpha_mux(vars.map(|v| mapped(&v, 3)), mux_cd, &op(c, &p));
            r.map(|x| [0.0, 0.0, 0.0, x])
        } else {
            let v = vars.map(|v| [0, 1, 2].map(|l| mapped(&v, l)));
            let r = twin::general_rgb_mux(v, mux_cd, &op(c, &p));
            r.map(|x| [x[0], x[1], x[2], 0.0])
        };
        let bounds = portion_bounds(c, &p);
        let lanes = if alpha { 3..4 } else { 0..3 };
        for (k, dst) in [p.ab_output, p.cd_output, p.sum_output].iter().enumerate() {
            if let Some(r) = dst {
                for lane in lanes.clone() {
                    want[r.index()][lane] = (outs[k][lane] * s, bounds[k]);
                }
                // NV2A blue-to-alpha: out1 / out2's blue to the register's alpha.
                let blue = [c.ab_blue_to_alpha, c.cd_blue_to_alpha];
                if !alpha && k < 2 && blue[k] {
                    let [_, _, b] = [outs[k][0], outs[k][1], outs[k][2]];
                    want[r.index()][3] = (twin::blue_to_alpha([0.0, 0.0, b]) * s, bounds[k]);
                }
            }
        }
    }
    want
}

/// Run one register set; assert every component within its bound (untouched
/// components exactly equal). Returns the largest |Δ|/bound (0 where bound = 0).
fn check(u: &RegisterCombiner, file: &RegisterFile) -> f64 {
    let c = u.config();
    let out = u.kernel(&mut (), file, &mut Counters::default());
    let want = expected(&c, file);
    let mut worst: f64 = 0.0;
    for (r, (got, want)) in out.regs.iter().zip(want.iter()).enumerate() {
        for k in 0..4 {
            let (w, b) = want[k];
            let d = (got[k] as f64 - w).abs();
            assert!(
                d <= b + SLACK,
                "register {:?} comp {k}: got {} want {w} (|Δ| {d} > {b}); config {c:?}; input {file:?}",
                Register::ALL[r],
                got[k]
            );
            if b > 0.0 {
                worst = worst.max(d / b);
            }
        }
    }
    worst
}

fn widths(name: &str) -> RegisterCombinerConfig {
    let (n, g, q) = match name {
        "GeForce 9-bit" => (9, 0, Quant::Rnd),
        "wide 12-bit, 4 guard, RndConv" => (12, 4, Quant::RndConv),
        "NARROW 5-bit, TrnZero" => (5, 0, Quant::TrnZero),
        _ => (6, 2, Quant::Trn), // "6-bit, 2 guard, Trn"
    };
    RegisterCombinerConfig {
        internal_bits: n,
        guard_bits: g,
        rounding: q,
        ..RegisterCombinerConfig::geforce()
    }
}

const WIDTH_CONFIGS: [&str; 4] = [
    "GeForce 9-bit",
    "wide 12-bit, 4 guard, RndConv",
    "NARROW 5-bit, TrnZero",
    "6-bit, 2 guard, Trn",
];

fn random_variable(rng: &mut ChaCha8Rng, alpha: bool) -> VariableInput {
    let input = Register::ALL[rng.random_range(0..REGISTER_COUNT)];
    let mapping = Mapping::ALL[rng.random_range(0..8)];
    let mut usage = match (alpha, rng.random::<bool>()) {
        (false, true) => ComponentUsage::Rgb,
        (true, false) => ComponentUsage::Blue,
        _ => ComponentUsage::Alpha,
    };
    if input == Register::Fog && usage == ComponentUsage::Alpha {
        usage = if alpha {
            ComponentUsage::Blue
        } else {
            ComponentUsage::Rgb
        };
    }
    VariableInput::new(input, mapping, usage)
}

fn random_portion(rng: &mut ChaCha8Rng, alpha: bool) -> PortionConfig {
    let mut writable: Vec<Register> = Register::ALL.into_iter().filter(|r| r.writable()).collect();
    let mut out = || {
        let k = rng.random_range(0..writable.len());
        let r = writable.swap_remove(k);
        (rng.random_range(0..4) != 0).then_some(r)
    };
    let (ab, cd, sum) = (out(), out(), out());
    let scale = Scale::ALL[rng.random_range(0..4)];
    let bias = if matches!(scale, Scale::None | Scale::ByTwo) && rng.random() {
        Bias::ByNegativeOneHalf
    } else {
        Bias::None
    };
    PortionConfig {
        a: random_variable(rng, alpha),
        b: random_variable(rng, alpha),
        c: random_variable(rng, alpha),
        d: random_variable(rng, alpha),
        ab_output: ab,
        cd_output: cd,
        sum_output: sum,
        scale,
        bias,
        ab_dot_product: !alpha && rng.random(),
        cd_dot_product: !alpha && rng.random(),
        mux_sum: rng.random(),
    }
}

/// A random stage, the NV2A modes among them (bias constant, mux select, blue-to-alpha
/// where the alpha portion does not write the same register, per-stage constants).
fn random_config(rng: &mut ChaCha8Rng, base: RegisterCombinerConfig) -> RegisterCombinerConfig {
    let rgb = random_portion(rng, false);
    let alpha = random_portion(rng, true);
    let alpha_writes = [alpha.ab_output, alpha.cd_output, alpha.sum_output];
    let free = |dst: Option<Register>| dst.is_none() || !alpha_writes.contains(&dst);
    let s = ((1i64 << (base.internal_bits.clamp(3, 24) - 1)) - 1) as i32;
    let stage_constants = rng
        .random::<bool>()
        .then(|| std::array::from_fn(|_| std::array::from_fn(|_| rng.random_range(0..=s))));
    RegisterCombinerConfig {
        rgb,
        alpha,
        bias_constant: if rng.random() {
            BiasConstant::HalfCode
        } else {
            BiasConstant::ExactHalf
        },
        mux_select: if rng.random() {
            MuxSelect::Lsb
        } else {
            MuxSelect::Msb
        },
        ab_blue_to_alpha: rng.random::<bool>() && free(rgb.ab_output),
        cd_blue_to_alpha: rng.random::<bool>() && free(rgb.cd_output),
        stage_constants,
        ..base
    }
}

#[test]
fn bound_holds_on_seeded_random_stages_and_prints_the_ratio() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for name in WIDTH_CONFIGS {
        let base = widths(name);
        let mut worst: f64 = 0.0;
        for _ in 0..2_000 {
            let u = random_config(&mut rng, base).build().unwrap();
            for _ in 0..8 {
                let f = random_file(&mut rng, base.internal_bits);
                worst = worst.max(check(&u, &f));
            }
        }
        println!("{name}: worst |Δ|/bound {worst:.3}");
    }
}

/// A stage computing one variable's mapping: A = TEXTURE0 (mapping m), B = 1 (ZERO
/// inverted), A·B → SPARE1, in both portions (RGB usage / ALPHA usage).
fn mapping_stage(base: RegisterCombinerConfig, m: Mapping) -> RegisterCombiner {
    let portion = |usage| PortionConfig {
        a: VariableInput::new(Register::Texture0, m, usage),
        b: VariableInput::new(Register::Zero, Mapping::UnsignedInvert, usage),
        ab_output: Some(Register::Spare1),
        sum_output: None,
        ..PortionConfig::initial(usage)
    };
    RegisterCombinerConfig {
        rgb: portion(ComponentUsage::Rgb),
        alpha: portion(ComponentUsage::Alpha),
        ..base
    }
    .build()
    .unwrap()
}

/// Every mapping of every code on the wires (≤ 2^12 per config), each width config:
/// within the bound, and EXACT (= the mapped code) for the six mappings whose result is
/// a whole code at G = 0 and nearest rounding … or any rounding: a whole code is
/// never rounded.
#[test]
fn per_operand_mapping_sweep_is_exhaustive() {
    for name in WIDTH_CONFIGS {
        let base = widths(name);
        let n = base.internal_bits;
        let s = one(n) as i64;
        for m in Mapping::ALL {
            let u = mapping_stage(base, m);
            for r in -s - 1..=s {
                let mut f = RegisterFile::default();
                f.set(Register::Texture0, [r as i32; 4]);
                check(&u, &f);
                let got = u.kernel(&mut (), &f, &mut Counters::default());
                let half = m.apply_half_lsb(r, s);
                if half % 2 == 0 {
                    let code = (half / 2).clamp(-s, s) as i32;
                    assert_eq!(got.get(Register::Spare1), [code; 4], "{name} {m:?} {r}");
                }
            }
        }
    }
}

/// Every pair of codes × every pair of mappings × every valid scale/bias at 5 bits
/// (32 × 32 × 64 × 6 = 393 216 stages), A·B → SPARE0 and C·D → SPARE1 with the sum to
/// TEXTURE3, so products, the sum and scale/bias are all swept.
#[test]
fn products_sum_and_scale_exhaustive_at_5_bits() {
    let base = widths("NARROW 5-bit, TrnZero");
    let s = one(5) as i32;
    let scale_bias = [
        (Scale::None, Bias::None),
        (Scale::ByTwo, Bias::None),
        (Scale::ByFour, Bias::None),
        (Scale::ByOneHalf, Bias::None),
        (Scale::None, Bias::ByNegativeOneHalf),
        (Scale::ByTwo, Bias::ByNegativeOneHalf),
    ];
    let mut worst: f64 = 0.0;
    for ma in Mapping::ALL {
        for mb in Mapping::ALL {
            for (scale, bias) in scale_bias {
                let rgb = PortionConfig {
                    a: VariableInput::new(Register::Texture0, ma, ComponentUsage::Rgb),
                    b: VariableInput::new(Register::Texture1, mb, ComponentUsage::Rgb),
                    c: VariableInput::new(Register::Texture1, ma, ComponentUsage::Rgb),
                    d: VariableInput::new(Register::Texture0, mb, ComponentUsage::Rgb),
                    ab_output: Some(Register::Spare0),
                    cd_output: Some(Register::Spare1),
                    sum_output: Some(Register::Texture3),
                    scale,
                    bias,
                    ..PortionConfig::initial(ComponentUsage::Rgb)
                };
                let u = RegisterCombinerConfig { rgb, ..base }.build().unwrap();
                for a in -s - 1..=s {
                    // Three lanes carry three values of b per stage.
                    for b0 in (-s - 1..=s).step_by(3) {
                        let b = [b0, (b0 + 1).min(s), (b0 + 2).min(s)];
                        let mut f = RegisterFile::default();
                        f.set(Register::Texture0, [a, a, a, 0]);
                        f.set(Register::Texture1, [b[0], b[1], b[2], 0]);
                        worst = worst.max(check(&u, &f));
                    }
                }
            }
        }
    }
    println!("5-bit exhaustive: worst |Δ|/bound {worst:.3}");
}

/// Dot products exhaustively at 5 bits over A = (a, a, a) and B = (b0, b1, b2) with
/// b1 = b0 ± 1 … — the three lane products are summed then rounded once.
#[test]
fn dot_products_exhaustive_at_5_bits() {
    let s = one(5) as i32;
    for name in ["NARROW 5-bit, TrnZero", "6-bit, 2 guard, Trn"] {
        let base = RegisterCombinerConfig {
            internal_bits: 5,
            ..widths(name)
        };
        for m in [
            Mapping::ExpandNormal,
            Mapping::SignedIdentity,
            Mapping::HalfBiasNegate,
        ] {
            let rgb = PortionConfig {
                a: VariableInput::new(Register::Texture0, m, ComponentUsage::Rgb),
                b: VariableInput::new(Register::Texture1, m, ComponentUsage::Rgb),
                c: VariableInput::new(Register::Texture0, m, ComponentUsage::Rgb),
                d: VariableInput::new(Register::Texture0, m, ComponentUsage::Rgb),
                ab_output: Some(Register::Spare0),
                cd_output: Some(Register::Spare1),
                sum_output: Some(Register::Texture2),
                ab_dot_product: true,
                cd_dot_product: true,
                ..PortionConfig::initial(ComponentUsage::Rgb)
            };
            let u = RegisterCombinerConfig { rgb, ..base }.build().unwrap();
            for a0 in -s - 1..=s {
                for b0 in -s - 1..=s {
                    for b1 in -s - 1..=s {
                        let mut f = RegisterFile::default();
                        f.set(Register::Texture0, [a0, -a0.max(-s), s, 0]);
                        f.set(Register::Texture1, [b0, b1, (b0 ^ b1) & s, 0]);
                        check(&u, &f);
                    }
                }
            }
        }
    }
}

/// The mux: SPARE0 alpha ≥ 0.5 selects C·D, else A·B; at every SPARE0 alpha code
/// (both sides of c = 2^(N−2), the 0.5 threshold), at 9 and 5 bits.
#[test]
fn mux_threshold_is_spare0_alpha_at_least_one_half() {
    for n in [9u32, 5] {
        let s = one(n) as i32;
        let rgb = PortionConfig {
            a: VariableInput::new(
                Register::Texture0,
                Mapping::SignedIdentity,
                ComponentUsage::Rgb,
            ),
            b: VariableInput::new(Register::Zero, Mapping::UnsignedInvert, ComponentUsage::Rgb),
            c: VariableInput::new(
                Register::Texture1,
                Mapping::SignedIdentity,
                ComponentUsage::Rgb,
            ),
            d: VariableInput::new(Register::Zero, Mapping::UnsignedInvert, ComponentUsage::Rgb),
            mux_sum: true,
            sum_output: Some(Register::Spare1),
            ..PortionConfig::initial(ComponentUsage::Rgb)
        };
        let u = RegisterCombinerConfig {
            internal_bits: n,
            rgb,
            ..RegisterCombinerConfig::geforce()
        }
        .build()
        .unwrap();
        for alpha in -s - 1..=s {
            let mut f = RegisterFile::default();
            f.set(Register::Texture0, [3, 3, 3, 0]);
            f.set(Register::Texture1, [-5, -5, -5, 0]);
            f.set(Register::Spare0, [0, 0, 0, alpha]);
            let out = u.kernel(&mut (), &f, &mut Counters::default());
            let want = if alpha as f64 / s as f64 >= 0.5 {
                -5
            } else {
                3
            };
            assert_eq!(out.get(Register::Spare1)[0], want, "N {n}, alpha {alpha}");
            check(&u, &f);
        }
    }
}

/// Loading I-bit unorm codes: exact at N − 1 = I (the GeForce 8 → 9 bits), within e_r
/// LSB otherwise, exhaustively.
#[test]
fn unorm_load_is_exact_at_geforce_widths_and_bounded_otherwise() {
    let u = RegisterCombiner::geforce();
    for c in 0..=255u32 {
        assert_eq!(u.load_unorm(c, &mut Counters::default()), c as i32);
    }
    for name in WIDTH_CONFIGS {
        let cfg = widths(name);
        let u = cfg.build().unwrap();
        let s = one(cfg.internal_bits);
        let e = rounding_error(cfg.rounding);
        for c in 0..=255u32 {
            let want = twin::unorm(c, 8) * s;
            let got = u.load_unorm(c, &mut Counters::default()) as f64;
            assert!(
                (got - want).abs() <= e + SLACK,
                "{name}: {c} → {got} vs {want}"
            );
        }
    }
    // The fragment load: Table 1's registers, SPARE0 alpha = texture 0 alpha.
    let f = FragmentInputs {
        primary_color: [1, 2, 3, 4],
        secondary_color: [5, 6, 7, 8],
        texture: [
            [9, 10, 11, 12],
            [13, 14, 15, 16],
            [17, 18, 19, 20],
            [21, 22, 23, 24],
        ],
        constant_color0: [25, 26, 27, 28],
        constant_color1: [29, 30, 31, 32],
        fog: [33, 34, 35, 255],
    };
    let file = u.load_fragment(&f, &mut Counters::default());
    assert_eq!(file.get(Register::Spare0), [0, 0, 0, 12]);
    assert_eq!(file.get(Register::Texture3), [21, 22, 23, 24]);
    assert_eq!(file.get(Register::Fog), [33, 34, 35, 255]);
    assert_eq!(file.get(Register::Zero), [0; 4]);
}

/// Stiff cases, each with its documented result and saturation count.
#[test]
fn stiff_all_max_dot_of_extreme_vectors_and_scale_by_four() {
    let u0 = RegisterCombiner::geforce();
    let s = u0.one() as i32;
    let v = |r, m| VariableInput::new(r, m, ComponentUsage::Rgb);
    // 1. Dot of two extreme expand-normal vectors: (1,1,1)·(1,1,1) = 3 → 1 on R, G, B
    //    (3 clamps), and (1,1,1)·(−1,−1,−1) = −3 → −1 (3 clamps).
    let rgb = PortionConfig {
        a: v(Register::Texture0, Mapping::ExpandNormal),
        b: v(Register::Texture1, Mapping::ExpandNormal),
        ab_output: Some(Register::Spare0),
        sum_output: None,
        ab_dot_product: true,
        ..PortionConfig::initial(ComponentUsage::Rgb)
    };
    let u = RegisterCombinerConfig {
        rgb,
        alpha: PortionConfig::discard(ComponentUsage::Alpha),
        ..RegisterCombinerConfig::geforce()
    }
    .build()
    .unwrap();
    for (t1, want) in [(255, s), (0, -s)] {
        let mut f = RegisterFile::default();
        f.set(Register::Texture0, [255, 255, 255, 0]);
        f.set(Register::Texture1, [t1, t1, t1, 0]);
        let mut ctr = Counters::default();
        let out = u.kernel(&mut (), &f, &mut ctr);
        assert_eq!(out.get(Register::Spare0), [want, want, want, 0]);
        assert_eq!(ctr.saturations, 3);
        check(&u, &f);
    }
    // 2. All registers at +1 through the initial state with scale ×4 and the sum
    //    A·B + C·D (C = D = 1 too): 2·4 = 8 → 1, one clamp per RGBA output (4).
    let all_max = RegisterFile {
        regs: [[s; 4]; REGISTER_COUNT],
    };
    let mut cfg = RegisterCombinerConfig::geforce();
    for p in [&mut cfg.rgb, &mut cfg.alpha] {
        p.scale = Scale::ByFour;
        p.c = VariableInput {
            input: Register::PrimaryColor,
            ..p.c
        };
        p.d = VariableInput {
            input: Register::PrimaryColor,
            ..p.d
        };
    }
    let u = cfg.build().unwrap();
    let mut ctr = Counters::default();
    let out = u.kernel(&mut (), &all_max, &mut ctr);
    assert_eq!(out.get(Register::Spare0), [s; 4]);
    assert_eq!(ctr.saturations, 4);
    check(&u, &all_max);
    // 3. Scale ×4 on a product just over ¼: saturates (counted); just under: does not.
    let mut cfg = RegisterCombinerConfig::geforce();
    cfg.rgb.scale = Scale::ByFour;
    cfg.alpha = PortionConfig::discard(ComponentUsage::Alpha);
    let u = cfg.build().unwrap();
    let quarter = (s + 3) / 4; // 64 at N = 9: 64/255 > ¼
    for (p, sat) in [(quarter, 3), (quarter - 1, 0)] {
        let mut f = RegisterFile::default();
        f.set(Register::PrimaryColor, [p, p, p, 0]);
        let mut ctr = Counters::default();
        let out = u.kernel(&mut (), &f, &mut ctr);
        assert_eq!(ctr.saturations, sat, "p = {p}");
        assert_eq!(out.get(Register::Spare0)[0], (4 * p).min(s));
        check(&u, &f);
    }
    // 4. The most negative wire code −S−1 under SIGNED_NEGATE is S+1 → clamps to S.
    let mut cfg = RegisterCombinerConfig::geforce();
    cfg.rgb.a.mapping = Mapping::SignedNegate;
    let u = cfg.build().unwrap();
    let mut f = RegisterFile::default();
    f.set(Register::PrimaryColor, [-s - 1; 4]);
    let mut ctr = Counters::default();
    let out = u.kernel(&mut (), &f, &mut ctr);
    assert_eq!(out.get(Register::Spare0)[0], s);
    assert_eq!(ctr.saturations, 3); // R, G, B (the alpha portion reads UNSIGNED_IDENTITY → 0)
}

#[test]
fn config_errors_name_the_field() {
    let g = RegisterCombinerConfig::geforce();
    let err = |c: RegisterCombinerConfig| c.build().unwrap_err().field().to_string();
    assert_eq!(
        err(RegisterCombinerConfig {
            internal_bits: 2,
            ..g
        }),
        "register_combiner.internal_bits"
    );
    assert_eq!(
        err(RegisterCombinerConfig { input_bits: 0, ..g }),
        "register_combiner.input_bits"
    );
    assert_eq!(
        err(RegisterCombinerConfig {
            guard_bits: 17,
            ..g
        }),
        "register_combiner.guard_bits"
    );
    let mut c = g;
    c.alpha.b.component_usage = ComponentUsage::Rgb;
    assert_eq!(err(c), "register_combiner.alpha.b.component_usage");
    let mut c = g;
    c.rgb.c.component_usage = ComponentUsage::Blue;
    assert_eq!(err(c), "register_combiner.rgb.c.component_usage");
    let mut c = g;
    c.rgb.d = VariableInput::new(
        Register::Fog,
        Mapping::UnsignedIdentity,
        ComponentUsage::Alpha,
    );
    assert_eq!(err(c), "register_combiner.rgb.d.component_usage");
    let mut c = g;
    c.alpha.cd_dot_product = true;
    assert_eq!(err(c), "register_combiner.alpha.cd_dot_product");
    for scale in [Scale::ByFour, Scale::ByOneHalf] {
        let mut c = g;
        c.rgb.scale = scale;
        c.rgb.bias = Bias::ByNegativeOneHalf;
        assert_eq!(err(c), "register_combiner.rgb.bias");
    }
    let mut c = g;
    c.rgb.ab_output = Some(Register::ConstantColor1);
    assert_eq!(err(c), "register_combiner.rgb.ab_output");
    let mut c = g;
    c.alpha.cd_output = Some(Register::Spare0); // sum_output is SPARE0 too
    assert_eq!(err(c), "register_combiner.alpha.sum_output");
    // Two DISCARDs are legal.
    let mut c = g;
    c.rgb.sum_output = None;
    assert!(c.build().is_ok());
    // NV2A: blue-to-alpha into a register whose alpha the alpha portion also writes.
    let mut c = g;
    c.rgb.ab_output = Some(Register::Spare1);
    c.alpha.ab_output = Some(Register::Spare1);
    c.ab_blue_to_alpha = true;
    assert_eq!(err(c), "register_combiner.ab_blue_to_alpha");
    c.ab_blue_to_alpha = false;
    assert!(c.build().is_ok());
    // Per-stage constants outside the register codes 0 ..= S.
    for bad in [-1, 256] {
        let c = RegisterCombinerConfig {
            stage_constants: Some([[0, 0, 0, bad], [0; 4]]),
            ..g
        };
        assert_eq!(err(c), "register_combiner.stage_constants");
    }
}

/// The final combiner takes only the two unsigned mappings (NV_register_combiners,
/// FinalCombinerInputNV: UNSIGNED_IDENTITY_NV or UNSIGNED_INVERT_NV); `is_unsigned` is
/// the test it applies, and it maps every code into 0 ..= 2S half-LSBs.
#[test]
fn only_the_two_unsigned_mappings_are_unsigned() {
    let unsigned: Vec<Mapping> = Mapping::ALL
        .into_iter()
        .filter(|m| m.is_unsigned())
        .collect();
    assert_eq!(
        unsigned,
        [Mapping::UnsignedIdentity, Mapping::UnsignedInvert]
    );
    let s = one(9) as i64;
    for m in Mapping::ALL {
        let range: Vec<i64> = (-s..=s).map(|r| m.apply_half_lsb(r, s)).collect();
        let within = range.iter().all(|&v| (0..=2 * s).contains(&v));
        assert_eq!(within, m.is_unsigned(), "{m:?}");
    }
}

/// The trace signals (VCD) of a register file: one N-bit wire per register component,
/// named `<register>_<component>` in Table 1 order, a negative code as its N-bit two's
/// complement.
#[test]
fn trace_signals_are_the_register_codes_as_n_bit_wires() {
    let u = RegisterCombiner::geforce();
    let n = u.config().internal_bits;
    let mut file = RegisterFile::default();
    for (i, reg) in file.regs.iter_mut().enumerate() {
        for (c, v) in reg.iter_mut().enumerate() {
            *v = (i * 4 + c) as i32 - 20; // −20 ..= 27: negatives included
        }
    }
    for signals in [u.in_signals(&file), u.out_signals(&file)] {
        assert_eq!(signals.len(), 4 * REGISTER_COUNT);
        for (k, sig) in signals.iter().enumerate() {
            let code = k as i64 - 20;
            assert_eq!(sig.width, n, "{}", sig.name);
            assert_eq!(sig.value, code.rem_euclid(1 << n) as u64, "{}", sig.name);
            assert!(sig.value < 1 << n);
        }
        assert_eq!(signals[0].name, "zero_r");
        assert_eq!(signals[19].name, "pri_a");
        assert_eq!(signals[4 * REGISTER_COUNT - 1].name, "tex3_a");
    }
}

/// The underflow counter of a load: a non-zero unorm code loaded as register code 0 (at
/// N = 3, S = 3: every u < U/6 at 8 bits), and nothing else.
#[test]
fn a_load_counts_each_nonzero_code_rounded_to_zero() {
    let u = RegisterCombinerConfig {
        internal_bits: 3,
        ..RegisterCombinerConfig::geforce()
    }
    .build()
    .unwrap();
    let big_u = (1u32 << u.config().input_bits) - 1;
    let mut ctr = Counters::default();
    let mut zeros = 0;
    for code in 0..=big_u {
        let c = u.load_unorm(code, &mut ctr);
        zeros += u64::from(c == 0 && code != 0);
    }
    assert!(zeros > 0, "N = 3 must round the smallest codes to 0");
    assert_eq!(ctr.underflows, zeros);
    assert_eq!(u.load_unorm(0, &mut ctr), 0);
    assert_eq!(ctr.underflows, zeros, "0 loaded as 0 is no underflow");
}

/// The underflow counter of a product: code 1 × code 1 is 1/S² of a unit, below half a
/// working LSB (1/S at G = 0), so AB rounds to 0 on every lane and counts; code S × S
/// (1.0 × 1.0) and the zero CD product do not.
#[test]
fn a_product_rounded_to_zero_counts_once_per_lane() {
    let portion = |usage| PortionConfig {
        a: VariableInput::new(Register::Texture0, Mapping::UnsignedIdentity, usage),
        b: VariableInput::new(Register::Texture0, Mapping::UnsignedIdentity, usage),
        ab_output: Some(Register::Spare1),
        ..PortionConfig::initial(usage)
    };
    let u = RegisterCombinerConfig {
        rgb: portion(ComponentUsage::Rgb),
        alpha: portion(ComponentUsage::Alpha),
        ..RegisterCombinerConfig::geforce()
    }
    .build()
    .unwrap();
    assert_eq!(u.config().guard_bits, 0);
    let s = u.one() as i32;
    for (code, underflows) in [(1, 4), (s, 0)] {
        let mut file = RegisterFile::default();
        file.set(Register::Texture0, [code; 4]);
        let mut ctr = Counters::default();
        let out = u.kernel(&mut (), &file, &mut ctr);
        let want = if code == 1 { 0 } else { s };
        assert_eq!(out.get(Register::Spare1), [want; 4], "code {code}");
        assert_eq!(ctr.underflows, underflows, "code {code}");
        assert_eq!(
            ctr.saturations, 0,
            "code {code}: S is in range, not clamped"
        );
    }
}

/// The output's counters (step 6, truncating): a non-zero value scaled by ½ to below one
/// code counts an underflow, exactly ±S is no saturation, ±2S (±1.0 × 1.0 scaled by 2)
/// is one per lane, clamped to ±S.
#[test]
fn the_output_counts_underflows_and_saturations_per_lane() {
    let portion = |usage, mapping, scale| PortionConfig {
        a: VariableInput::new(Register::Texture0, mapping, usage),
        b: VariableInput::new(Register::Zero, Mapping::UnsignedInvert, usage),
        ab_output: Some(Register::Spare1),
        sum_output: None,
        scale,
        ..PortionConfig::initial(usage)
    };
    let s = one(9) as i32;
    let cases = [
        // (mapping of A, scale, code, output, underflows, saturations)
        (Mapping::UnsignedIdentity, Scale::ByOneHalf, 1, 0, 4, 0),
        (Mapping::UnsignedIdentity, Scale::ByOneHalf, 2, 1, 0, 0),
        (Mapping::UnsignedIdentity, Scale::None, s, s, 0, 0),
        (Mapping::UnsignedIdentity, Scale::ByTwo, s, s, 0, 4),
        (Mapping::SignedNegate, Scale::None, s, -s, 0, 0),
        (Mapping::SignedNegate, Scale::ByTwo, s, -s, 0, 4),
    ];
    for (mapping, scale, code, want, underflows, saturations) in cases {
        let u = RegisterCombinerConfig {
            rgb: portion(ComponentUsage::Rgb, mapping, scale),
            alpha: portion(ComponentUsage::Alpha, mapping, scale),
            rounding: Quant::Trn,
            ..RegisterCombinerConfig::geforce()
        }
        .build()
        .unwrap();
        assert_eq!((u.config().internal_bits, u.config().guard_bits), (9, 0));
        let mut file = RegisterFile::default();
        file.set(Register::Texture0, [code; 4]);
        let mut ctr = Counters::default();
        let out = u.kernel(&mut (), &file, &mut ctr);
        let case = format!("{mapping:?} {scale:?} × code {code}");
        assert_eq!(out.get(Register::Spare1), [want; 4], "{case}");
        assert_eq!(ctr.underflows, underflows, "{case}");
        assert_eq!(ctr.saturations, saturations, "{case}");
    }
}

/// What the NV2A options add to the stage's cost, in cells: per-stage constants are two
/// RGBA registers (8 × N flip-flops); blue-to-alpha a 2:1 select on each of the 8
/// writable registers' alphas (8 × N 2:1 muxes). Nothing else changes. At the default
/// widths the whole cost is pinned by the datasheet (tests/datasheet.rs); these parts
/// are absent there.
#[test]
fn the_nv2a_options_cost_their_registers_and_selects() {
    for n in [5u32, 9, 12] {
        let base = RegisterCombinerConfig {
            internal_bits: n,
            ..RegisterCombinerConfig::geforce()
        };
        let cells = |c: RegisterCombinerConfig| c.build().unwrap().cost().cells;
        let plain = cells(base);
        let constants = cells(RegisterCombinerConfig {
            stage_constants: Some([[0; 4]; 2]),
            ..base
        });
        let mut with_blue = base;
        with_blue.rgb.ab_output = Some(Register::Spare1);
        with_blue.ab_blue_to_alpha = true;
        let mut without_blue = with_blue;
        without_blue.ab_blue_to_alpha = false;
        let (blue, no_blue) = (cells(with_blue), cells(without_blue));
        let n = n as f64;
        assert_eq!(constants.dff - plain.dff, 8.0 * n, "N = {n}");
        assert_eq!(blue.mux2 - no_blue.mux2, 8.0 * n, "N = {n}");
        let rest =
            |a: rtl_model::cost::Cells| [a.and2, a.nand2, a.or2, a.nor2, a.xor2, a.xnor2, a.not];
        assert_eq!(rest(constants), rest(plain), "N = {n}");
        assert_eq!(constants.mux2, plain.mux2, "N = {n}");
        assert_eq!(rest(blue), rest(no_blue), "N = {n}");
        assert_eq!(blue.dff, no_blue.dff, "N = {n}");
    }
}

/// The NV2A's −½ is 2^(N−2) codes: BIAS of x is x − 2^(N−2) and SHIFT_LEFT_1_BIAS is
/// 2(x − 2^(N−2)), clamped, EXACTLY (no rounding at G = 0) for every code x, at every
/// width 3 ..= 12 (at N = 9: 1.0 → 127 and 254, the CombinerOps capture). ExactHalf
/// gives x − S/2 rounded, one code more at x = S.
#[test]
fn nv2a_bias_is_the_half_code_exactly_at_every_width() {
    for n in 3u32..=12 {
        let s = one(n) as i64;
        let h = 1i64 << (n - 2);
        for (scale, k) in [(Scale::None, 1i64), (Scale::ByTwo, 2)] {
            let stage = |bias_constant| {
                let rgb = PortionConfig {
                    a: VariableInput::new(
                        Register::Texture0,
                        Mapping::SignedIdentity,
                        ComponentUsage::Rgb,
                    ),
                    b: VariableInput::new(
                        Register::Zero,
                        Mapping::UnsignedInvert,
                        ComponentUsage::Rgb,
                    ),
                    sum_output: Some(Register::Spare1),
                    scale,
                    bias: Bias::ByNegativeOneHalf,
                    ..PortionConfig::initial(ComponentUsage::Rgb)
                };
                RegisterCombinerConfig {
                    internal_bits: n,
                    rgb,
                    bias_constant,
                    ..RegisterCombinerConfig::geforce()
                }
                .build()
                .unwrap()
            };
            let (nv2a, spec) = (
                stage(BiasConstant::HalfCode),
                stage(BiasConstant::ExactHalf),
            );
            for x in -s..=s {
                let mut f = RegisterFile::default();
                f.set(Register::Texture0, [x as i32; 4]);
                let mut ctr = Counters::default();
                let got = nv2a.kernel(&mut (), &f, &mut ctr).get(Register::Spare1)[0] as i64;
                assert_eq!(got, (k * (x - h)).clamp(-s, s), "N {n}, ×{k}, x {x}");
                check(&nv2a, &f);
                check(&spec, &f);
            }
            let mut f = RegisterFile::default();
            f.set(Register::Texture0, [s as i32; 4]);
            let top = |u: &RegisterCombiner| {
                u.kernel(&mut (), &f, &mut Counters::default())
                    .get(Register::Spare1)[0] as i64
            };
            assert_eq!(
                top(&spec) - top(&nv2a),
                1,
                "N {n}, ×{k}: ExactHalf rounds up"
            );
        }
    }
}

/// NV2A mux select LSB: C·D exactly when SPARE0 alpha's code is odd (0x82 → A·B,
/// 0x81 → C·D, the Mux capture), at every code of 9 and 5 bits; MSB is the spec's.
#[test]
fn mux_lsb_selects_on_spare0_alphas_low_bit() {
    for n in [9u32, 5] {
        let s = one(n) as i32;
        let rgb = PortionConfig {
            a: VariableInput::new(
                Register::Texture0,
                Mapping::SignedIdentity,
                ComponentUsage::Rgb,
            ),
            b: VariableInput::new(Register::Zero, Mapping::UnsignedInvert, ComponentUsage::Rgb),
            c: VariableInput::new(
                Register::Texture1,
                Mapping::SignedIdentity,
                ComponentUsage::Rgb,
            ),
            d: VariableInput::new(Register::Zero, Mapping::UnsignedInvert, ComponentUsage::Rgb),
            mux_sum: true,
            sum_output: Some(Register::Spare1),
            ..PortionConfig::initial(ComponentUsage::Rgb)
        };
        let u = RegisterCombinerConfig {
            internal_bits: n,
            rgb,
            mux_select: MuxSelect::Lsb,
            ..RegisterCombinerConfig::geforce()
        }
        .build()
        .unwrap();
        for alpha in -s - 1..=s {
            let mut f = RegisterFile::default();
            f.set(Register::Texture0, [3, 3, 3, 0]);
            f.set(Register::Texture1, [-5, -5, -5, 0]);
            f.set(Register::Spare0, [0, 0, 0, alpha]);
            let out = u.kernel(&mut (), &f, &mut Counters::default());
            let want = if alpha & 1 == 1 { -5 } else { 3 };
            assert_eq!(out.get(Register::Spare1)[0], want, "N {n}, alpha {alpha}");
            check(&u, &f);
        }
    }
}

/// Blue-to-alpha writes out1's / out2's blue (after scale, bias and clamp) to its
/// register's alpha; per-stage constants are read instead of the set's and the set's
/// pass on; the unbound texture is (0, 0, 0, 1).
#[test]
fn blue_to_alpha_and_stage_constants() {
    let n = 9;
    let rgb = PortionConfig {
        a: VariableInput::new(
            Register::ConstantColor0,
            Mapping::UnsignedIdentity,
            ComponentUsage::Rgb,
        ),
        b: VariableInput::new(Register::Zero, Mapping::UnsignedInvert, ComponentUsage::Rgb),
        c: VariableInput::new(
            Register::ConstantColor1,
            Mapping::UnsignedIdentity,
            ComponentUsage::Rgb,
        ),
        d: VariableInput::new(Register::Zero, Mapping::UnsignedInvert, ComponentUsage::Rgb),
        ab_output: Some(Register::Spare0),
        cd_output: Some(Register::Spare1),
        sum_output: None,
        scale: Scale::ByTwo,
        ..PortionConfig::initial(ComponentUsage::Rgb)
    };
    let c = RegisterCombinerConfig {
        internal_bits: n,
        rgb,
        alpha: PortionConfig::discard(ComponentUsage::Alpha),
        ab_blue_to_alpha: true,
        cd_blue_to_alpha: true,
        stage_constants: Some([[10, 20, 30, 40], [50, 60, 200, 70]]),
        ..RegisterCombinerConfig::geforce()
    };
    let u = c.build().unwrap();
    let mut f = RegisterFile::default();
    f.set(Register::ConstantColor0, [1, 1, 1, 1]);
    f.set(Register::Spare0, [0, 0, 0, 99]);
    f.set(Register::Spare1, [0, 0, 0, 98]);
    let out = u.kernel(&mut (), &f, &mut Counters::default());
    assert_eq!(out.get(Register::Spare0), [20, 40, 60, 60]);
    assert_eq!(out.get(Register::Spare1), [100, 120, 255, 255]);
    assert_eq!(out.get(Register::ConstantColor0), [1, 1, 1, 1]);
    check(&u, &f);
    let off = RegisterCombinerConfig {
        ab_blue_to_alpha: false,
        cd_blue_to_alpha: false,
        ..c
    };
    let out = off
        .build()
        .unwrap()
        .kernel(&mut (), &f, &mut Counters::default());
    assert_eq!(
        (out.get(Register::Spare0)[3], out.get(Register::Spare1)[3]),
        (99, 98)
    );
    assert_eq!(unbound_texture(8), [0, 0, 0, 255]);
    assert_eq!(unbound_texture(5), [0, 0, 0, 31]);
}

#[test]
fn defaults_summary() {
    let u = RegisterCombiner::geforce();
    let s = UnitSummary::of(&u);
    println!(
        "register_combiner defaults: latency {}, II {}, {:.0} NAND2, {} RAM bits",
        s.latency, s.ii, s.gates_nand2, s.ram_bits
    );
    for (p, g) in &s.breakdown {
        println!("  {p}: {g:.0}");
    }
    for n in [5, 6, 9, 12, 16] {
        let c = RegisterCombinerConfig {
            internal_bits: n,
            ..RegisterCombinerConfig::geforce()
        };
        println!(
            "  N = {n}: {:.0} NAND2",
            UnitSummary::of(&c.build().unwrap()).gates_nand2
        );
    }
    assert_eq!((s.latency, s.ii, s.ram_bits), (3, 1, 0));
    // The initial state passes PRIMARY_COLOR × 1 to SPARE0 exactly.
    let mut f = RegisterFile::default();
    f.set(Register::PrimaryColor, [10, -20, 255, 128]);
    let out = u.kernel(&mut (), &f, &mut Counters::default());
    assert_eq!(out.get(Register::Spare0), [10, 0, 255, 128]);
}

// ---- the squaring chain (pipeline::shading::squaring) ----

/// The chain is exactly its units' kernels run in sequence.
#[test]
fn squaring_is_exactly_the_chained_kernels() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for n in [9u32, 6, 12] {
        let chain = SquaringChain::new(n).unwrap();
        for _ in 0..500 {
            let nv: [u8; 3] = [(); 3].map(|_| rng.random());
            let hv: [u8; 3] = [(); 3].map(|_| rng.random());
            let k = rng.random_range(0..8u32);
            // By hand: load, dot stage, k squaring stages, final combiner.
            let mut ctr = Counters::default();
            let mut f = RegisterFile::default();
            let ld = |v: [u8; 3], ctr: &mut Counters| {
                let c = v.map(|x| chain.dot_stage.load_unorm(x as u32, ctr));
                [c[0], c[1], c[2], 0]
            };
            f.set(Register::Texture0, ld(nv, &mut ctr));
            f.set(Register::Texture1, ld(hv, &mut ctr));
            let f = chain.dot_stage.kernel(&mut (), &f, &mut ctr);
            let mut g = RegisterFile::default();
            g.set(Register::Spare0, f.get(Register::Spare0));
            g.regs[Register::Spare0.index()][3] = 0;
            for _ in 0..k {
                g = chain.square_stage.kernel(&mut (), &g, &mut ctr);
            }
            let want = chain.final_stage.kernel(&mut (), &g, &mut ctr)[0] as u8;
            assert_eq!(chain.specular(nv, hv, k, &mut Counters::default()), want);
            assert_eq!(specular_by_squaring(n, nv, hv, k).unwrap(), want);
            let d = chain.n_dot_h(nv, hv, &mut Counters::default());
            assert_eq!(power_by_squaring(n, d, k).unwrap(), want);
        }
    }
    assert_eq!(
        specular_by_squaring(2, [0; 3], [0; 3], 1)
            .unwrap_err()
            .field(),
        "register_combiner.internal_bits"
    );
    assert_eq!(
        power_by_squaring(9, 0, 17).unwrap_err().field(),
        "squaring.k"
    );
}

/// Distinct unorm8 outputs of (c/S)^(2^k) over every n·h code c ∈ [0, S].
fn levels(n: u32, k: u32) -> usize {
    let chain = SquaringChain::new(n).unwrap();
    let s = chain.one();
    let mut seen = std::collections::BTreeSet::new();
    let mut ctr = Counters::default();
    for c in 0..=s {
        seen.insert(chain.power_from_code(c, k, &mut ctr));
    }
    seen.len()
}

/// The banding, counted: distinct unorm8 outputs of k squarings over every n·h code
/// c ∈ [0, S] at 9 bits, against a count derived from the precision.
///
/// Derivation: stage j rounds x_j² to the register format, at most ½ LSB (½/S) up, so
/// x_j ≤ h_j with h_0 = c/S, h_{j+1} = min(h_j², 1) + ½/S (interval arithmetic on the
/// upper end). The last stage's code is round(x_{k−1}²·S), 0 when x_{k−1}²·S < ½, and
/// a zero code gives output 0, so only codes with h_{k−1}(c)²·S ≥ ½ can give a
/// non-zero level: levels ≤ 1 + #{c : h_{k−1}(c)² ≥ ½/S}.
/// Measured (deterministic, pinned): 192, 131, 87, 56, 35, 21 levels for k = 1 … 6;
/// an exact power of the same 9-bit codes rounded once to 8 bits (a lookup indexed by
/// the same n·h) gives 192, 136, 90, 57, 35, 21.
#[test]
fn squaring_at_9_bits_bands_into_few_levels() {
    let s = one(9);
    let mut measured = Vec::new();
    println!("k, exponent, levels, bound, codes with (c/S)^(2^k) >= 1/510, exact-power levels");
    for k in 1..=6u32 {
        let e = (2f64).powi(k as i32);
        let got = levels(9, k);
        let count = |t: f64| (0..=255).filter(|&c| (c as f64 / s).powf(e) >= t).count();
        let upper = |c: i32| (1..k).fold(c as f64 / s, |h, _| (h * h).min(1.0) + 0.5 / s);
        let bound = 1 + (0..=255).filter(|&c| upper(c).powi(2) >= 0.5 / s).count();
        let exact: std::collections::BTreeSet<i64> = (0..=255)
            .map(|c| ((c as f64 / s).powf(e) * 255.0 + 0.5).floor() as i64)
            .collect();
        println!(
            "{k}, {e}, {got}, {bound}, {}, {}",
            count(0.5 / 255.0),
            exact.len()
        );
        assert!(got <= bound, "k {k}: {got} levels > derived bound {bound}");
        measured.push((got, bound));
    }
    // Visibly few at k = 4, 5 (exponents 16, 32): the derived bounds are 86 and 48 of
    // the 256 output levels.
    assert_eq!((measured[3].1, measured[4].1), (86, 48));
    let measured: Vec<usize> = measured.iter().map(|m| m.0).collect();
    assert_eq!(measured, [192, 131, 87, 56, 35, 21]);
    // Other widths, for the record (the n·h codes 0 … S, so wider registers also carry
    // a finer n·h): levels for k = 1 … 6.
    for n in [6u32, 8, 10, 12, 16] {
        let l: Vec<usize> = (1..=6).map(|k| levels(n, k)).collect();
        println!("N = {n}: levels {l:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn within_bound_vs_twin(ci in 0usize..4, seed in any::<u64>()) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let base = widths(WIDTH_CONFIGS[ci]);
        let u = random_config(&mut rng, base).build().unwrap();
        let f = random_file(&mut rng, base.internal_bits);
        check(&u, &f);
    }

    #[test]
    fn tick_and_span_drivers_agree(
        n in 3u32..=24, g in 0u32..=16, q in 0usize..7, seed in any::<u64>(), len in 0usize..12,
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let base = RegisterCombinerConfig {
            internal_bits: n,
            guard_bits: g,
            rounding: Quant::ALL[q],
            ..RegisterCombinerConfig::geforce()
        };
        let u = random_config(&mut rng, base).build().unwrap();
        let inputs: Vec<RegisterFile> = (0..len).map(|_| random_file(&mut rng, n)).collect();
        common::assert_drivers_agree(&u, (), &inputs);
    }

    #[test]
    fn random_configs_never_panic_and_errors_name_the_field(
        n in 0u32..40, i in 0u32..40, g in 0u32..40, seed in any::<u64>(),
        bad_usage in any::<bool>(), words in prop::collection::vec(any::<i32>(), 48),
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut c = random_config(&mut rng, RegisterCombinerConfig {
            internal_bits: n, input_bits: i, guard_bits: g, ..RegisterCombinerConfig::geforce()
        });
        if bad_usage {
            c.alpha.a.component_usage = ComponentUsage::Rgb;
        }
        match c.build() {
            Ok(u) => {
                let mut f = RegisterFile::default();
                for (r, w) in f.regs.iter_mut().flatten().zip(&words) {
                    *r = *w;
                }
                let _ = u.kernel(&mut (), &f, &mut Counters::default());
                let _ = u.load_unorm(words[0] as u32, &mut Counters::default());
                let _ = u.cost();
            }
            Err(e) => prop_assert!(e.field().starts_with("register_combiner."), "{}", e.field()),
        }
    }

    #[test]
    fn twin_never_nan(e in any::<f64>(), m in 0usize..8, x in any::<f64>()) {
        let tm = [
            twin::Mapping::UnsignedIdentity, twin::Mapping::UnsignedInvert,
            twin::Mapping::ExpandNormal, twin::Mapping::ExpandNegate,
            twin::Mapping::HalfBiasNormal, twin::Mapping::HalfBiasNegate,
            twin::Mapping::SignedIdentity, twin::Mapping::SignedNegate,
        ][m];
        let v = twin::map(tm, e);
        prop_assert!(v.is_finite());
        let op = twin::OutputOp { ab_dot_product: true, cd_dot_product: false, mux_sum: false, scale: 4.0, bias: -0.5 };
        let r = twin::general_rgb([[v; 3], [x; 3], [v; 3], [x; 3]], x, &op);
        prop_assert!(r.iter().flatten().all(|y| y.is_finite()));
    }
}

/// `fixed_point::round_div` (the units' divide by S and 4S): equal to `round_shift`
/// for powers of two and to the exact rational rounding for odd divisors, every mode.
#[test]
fn round_div_matches_round_shift_and_exact_rounding() {
    use rtl_model::fixed_point::{round_div, round_shift};
    for q in Quant::ALL {
        for num in -600i128..=600 {
            for k in 0..6 {
                assert_eq!(
                    round_div(num, 1 << k, q),
                    round_shift(num, k, q),
                    "{q:?} {num} {k}"
                );
            }
            for den in [3i128, 7, 15, 31, 255, 1020] {
                let got = round_div(num, den, q);
                let (fl, rem) = (num.div_euclid(den), num.rem_euclid(den));
                let neg = num < 0;
                let want = if rem == 0 {
                    fl
                } else {
                    let up = match q {
                        Quant::Trn => false,
                        Quant::TrnZero => neg,
                        _ if 2 * rem != den => 2 * rem > den,
                        Quant::Rnd => true,
                        Quant::RndZero => neg,
                        Quant::RndInf => !neg,
                        Quant::RndMinInf => false,
                        Quant::RndConv => fl % 2 != 0,
                    };
                    fl + i128::from(up)
                };
                assert_eq!(got, want, "{q:?} {num}/{den}");
            }
        }
    }
}

/// The case proptest found: EXPAND_NORMAL of a finite e near f64::MAX overflowed to ∞.
#[test]
fn twin_mapping_of_a_huge_finite_element_stays_finite() {
    for m in [twin::Mapping::ExpandNormal, twin::Mapping::ExpandNegate] {
        for e in [1.25e308, f64::MAX, -f64::MAX] {
            assert!(twin::map(m, e).is_finite(), "{m:?} {e}");
        }
    }
}
