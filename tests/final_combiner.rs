//! final_combiner (GL_NV_register_combiners' final stage) against its f64 twin,
//! fcoc = [min(A·B + (1 − A)·C + D, 1); G], under a bound derived from the widths.
//!
//! Bound derivation (also in docs/units.md, `## final_combiner`), in output LSBs
//! (U = 2^O − 1), the twin fed the same register codes as reals c/S (S = 2^(N−1) − 1):
//! * The unsigned mappings of a register code are exact (whole codes), and so is
//!   SPARE0 + SECONDARY (a code sum, its clamp to S exact).
//! * E_TIMES_F is rounded once to the register scale: |ΔEF| ≤ e_r/S (e_r = ½ for the
//!   round-to-nearest modes, 1 for Trn/TrnZero); the invert mapping is 1-Lipschitz.
//! * The lerp A·B + (1 − A)·C + D is exact (units 1/S²); perturbing the variables,
//!   |Δ| ≤ |ΔA|·max(B_max, C_max) + |ΔB| + |ΔC| + |ΔD| (A, 1 − A ∈ [0, 1]; B, C ≥ 0),
//!   with B_max, C_max = 2 for SPARE0_PLUS_SECONDARY_COLOR under the identity without
//!   the colour-sum clamp, else 1. Only a variable reading E_TIMES_F has a Δ.
//! * min(·, 1) is 1-Lipschitz; the output is rounded once: + e_r LSB.
//!
//! So |Δ| ≤ e_r + U·(e_r/S)·k_EF, k_EF = Σ over A … D reading E_TIMES_F of its factor
//! above (+ 10⁻⁹ of f64 slack). The alpha G: e_r. At the GeForce default (N = 9,
//! O = 8, nearest) without E_TIMES_F: ½ LSB; with E·F in D: 1 LSB.

mod combiner_common;
mod common;

use combiner_common::{one, random_file, rounding_error, sext};

use glare_pipeline::reference::final_combiner as twin;
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::units::final_combiner::{
    FinalCombiner, FinalCombinerConfig, FinalInput, FinalVariable,
};
use rtl_model::units::register_combiner::{
    ComponentUsage, Mapping, Register, RegisterFile, REGISTER_COUNT,
};
use rtl_model::{Counters, Quant, Unit, UnitSummary};

const SLACK: f64 = 1e-9;

fn twin_mapping(m: Mapping) -> twin::Mapping {
    match m {
        Mapping::UnsignedInvert => twin::Mapping::UnsignedInvert,
        _ => twin::Mapping::UnsignedIdentity, // the only other one the unit accepts
    }
}

/// A register component as the twin reads it.
fn reg_value(file: &RegisterFile, r: Register, comp: usize, n: u32) -> f64 {
    if r == Register::Zero {
        0.0
    } else {
        sext(file.regs[r.index()][comp], n) as f64 / one(n)
    }
}

/// The twin's value of variable `v` on `lane` (3 = G), mapped.
fn variable(c: &FinalCombinerConfig, file: &RegisterFile, v: &FinalVariable, lane: usize) -> f64 {
    let n = c.internal_bits;
    let comp = match v.component_usage {
        ComponentUsage::Rgb => lane,
        ComponentUsage::Alpha => 3,
        ComponentUsage::Blue => 2,
    };
    let raw = match v.input {
        FinalInput::Register(r) => reg_value(file, r, comp, n),
        FinalInput::ETimesF => {
            let e = [0, 1, 2].map(|l| variable(c, file, &c.e, l));
            let f = [0, 1, 2].map(|l| variable(c, file, &c.f, l));
            twin::e_times_f(e, f)[lane]
        }
        FinalInput::Spare0PlusSecondaryColor => {
            let sp = [0, 1, 2].map(|l| reg_value(file, Register::Spare0, l, n));
            let se = [0, 1, 2].map(|l| reg_value(file, Register::SecondaryColor, l, n));
            let inv = [c.specular_add_invert_r0, c.specular_add_invert_v1];
            twin::spare0_plus_secondary_color_inverted(sp, se, inv, c.color_sum_clamp)[lane]
        }
    };
    twin::map(twin_mapping(v.mapping), raw)
}

/// The RGB bound in output LSBs.
fn rgb_bound(c: &FinalCombinerConfig) -> f64 {
    let e_r = rounding_error(c.rounding);
    let u = ((1u64 << c.out_bits) - 1) as f64;
    let reach = |v: &FinalVariable| -> f64 {
        if v.input == FinalInput::Spare0PlusSecondaryColor
            && v.mapping == Mapping::UnsignedIdentity
            && !c.color_sum_clamp
        {
            2.0
        } else {
            1.0
        }
    };
    let ef = |v: &FinalVariable| v.input == FinalInput::ETimesF;
    let mut k: f64 = 0.0;
    if ef(&c.a) {
        k += reach(&c.b).max(reach(&c.c));
    }
    for v in [&c.b, &c.c, &c.d] {
        if ef(v) {
            k += 1.0;
        }
    }
    e_r + u * e_r / one(c.internal_bits) * k
}

/// Run one register set; assert RGB and alpha within their bounds. Returns the largest
/// |Δ|/bound.
fn check(u: &FinalCombiner, file: &RegisterFile) -> f64 {
    let c = u.config();
    let out = u.kernel(&mut (), file, &mut Counters::default());
    // NV2A: the final combiner's own constants are read instead of the set's.
    let mut read = *file;
    if let Some([c0, c1]) = c.constants {
        read.set(Register::ConstantColor0, c0);
        read.set(Register::ConstantColor1, c1);
    }
    let file = &read;
    let var = |v: &FinalVariable, l| variable(&c, file, v, l);
    let rgb = twin::fcoc_rgb(
        [0, 1, 2].map(|l| var(&c.a, l)),
        [0, 1, 2].map(|l| var(&c.b, l)),
        [0, 1, 2].map(|l| var(&c.c, l)),
        [0, 1, 2].map(|l| var(&c.d, l)),
    );
    let want = [rgb[0], rgb[1], rgb[2], var(&c.g, 3)].map(|x| twin::to_unorm_lsb(x, c.out_bits));
    let bounds = [rgb_bound(&c); 3]
        .into_iter()
        .chain([rounding_error(c.rounding)])
        .collect::<Vec<_>>();
    let mut worst: f64 = 0.0;
    for k in 0..4 {
        let d = (out[k] as f64 - want[k]).abs();
        assert!(
            d <= bounds[k] + SLACK,
            "lane {k}: got {} want {} (|Δ| {d} > {}); config {c:?}; input {file:?}",
            out[k],
            want[k],
            bounds[k]
        );
        worst = worst.max(d / bounds[k]);
    }
    worst
}

fn widths(name: &str) -> FinalCombinerConfig {
    let (n, o, q) = match name {
        "GeForce 9-bit → 8" => (9, 8, Quant::Rnd),
        "wide 12-bit → 10, RndConv" => (12, 10, Quant::RndConv),
        "NARROW 5-bit → 4, TrnZero" => (5, 4, Quant::TrnZero),
        _ => (6, 8, Quant::Trn), // "6-bit → 8, Trn"
    };
    FinalCombinerConfig {
        internal_bits: n,
        out_bits: o,
        rounding: q,
        ..FinalCombinerConfig::geforce()
    }
}

const WIDTH_CONFIGS: [&str; 4] = [
    "GeForce 9-bit → 8",
    "wide 12-bit → 10, RndConv",
    "NARROW 5-bit → 4, TrnZero",
    "6-bit → 8, Trn",
];

fn random_variable(rng: &mut ChaCha8Rng, name: char) -> FinalVariable {
    let mapping = if rng.random() {
        Mapping::UnsignedIdentity
    } else {
        Mapping::UnsignedInvert
    };
    let special = match (name, rng.random_range(0..4)) {
        ('a' | 'b' | 'c' | 'd', 0) => Some(FinalInput::ETimesF),
        ('b' | 'c' | 'd', 1) => Some(FinalInput::Spare0PlusSecondaryColor),
        _ => None,
    };
    if let Some(input) = special {
        return FinalVariable::new(input, mapping, ComponentUsage::Rgb);
    }
    let r = Register::ALL[rng.random_range(0..REGISTER_COUNT)];
    let usage = match (name == 'g', rng.random::<bool>()) {
        (false, true) => ComponentUsage::Rgb,
        (true, true) => ComponentUsage::Blue,
        _ => ComponentUsage::Alpha,
    };
    FinalVariable::new(FinalInput::Register(r), mapping, usage)
}

/// A random final combiner, the NV2A modes among them (add-invert flags, own
/// constants).
fn random_config(rng: &mut ChaCha8Rng, base: FinalCombinerConfig) -> FinalCombinerConfig {
    let s = ((1i64 << (base.internal_bits.clamp(3, 24) - 1)) - 1) as i32;
    let constants = rng
        .random::<bool>()
        .then(|| std::array::from_fn(|_| std::array::from_fn(|_| rng.random_range(0..=s))));
    FinalCombinerConfig {
        specular_add_invert_r0: rng.random(),
        specular_add_invert_v1: rng.random(),
        constants,
        color_sum_clamp: rng.random(),
        a: random_variable(rng, 'a'),
        b: random_variable(rng, 'b'),
        c: random_variable(rng, 'c'),
        d: random_variable(rng, 'd'),
        e: random_variable(rng, 'e'),
        f: random_variable(rng, 'f'),
        g: random_variable(rng, 'g'),
        ..base
    }
}

#[test]
fn bound_holds_on_seeded_random_configs_and_prints_the_ratio() {
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    for name in WIDTH_CONFIGS {
        let base = widths(name);
        let mut worst: f64 = 0.0;
        for _ in 0..4_000 {
            let u = random_config(&mut rng, base).build().unwrap();
            for _ in 0..8 {
                worst = worst.max(check(&u, &random_file(&mut rng, base.internal_bits)));
            }
        }
        println!("{name}: worst |Δ|/bound {worst:.3}");
    }
}

/// The lerp exhaustively at 5 bits: every A, B, C code on the wires (32³) under every
/// mapping triple (8), D = ZERO, 4-bit output.
#[test]
fn lerp_exhaustive_at_5_bits() {
    let base = widths("NARROW 5-bit → 4, TrnZero");
    let s = one(5) as i32;
    let maps = [Mapping::UnsignedIdentity, Mapping::UnsignedInvert];
    let reg = |r, m| FinalVariable::new(FinalInput::Register(r), m, ComponentUsage::Rgb);
    let mut worst: f64 = 0.0;
    for ma in maps {
        for mb in maps {
            for mc in maps {
                let u = FinalCombinerConfig {
                    a: reg(Register::Texture0, ma),
                    b: reg(Register::Texture1, mb),
                    c: reg(Register::Texture2, mc),
                    d: reg(Register::Zero, Mapping::UnsignedIdentity),
                    ..base
                }
                .build()
                .unwrap();
                for a in -s - 1..=s {
                    for b in -s - 1..=s {
                        for c0 in (-s - 1..=s).step_by(3) {
                            let mut f = RegisterFile::default();
                            f.set(Register::Texture0, [a; 4]);
                            f.set(Register::Texture1, [b; 4]);
                            f.set(
                                Register::Texture2,
                                [c0, (c0 + 1).min(s), (c0 + 2).min(s), 0],
                            );
                            worst = worst.max(check(&u, &f));
                        }
                    }
                }
            }
        }
    }
    println!("5-bit lerp exhaustive: worst |Δ|/bound {worst:.3}");
}

/// E_TIMES_F exhaustively at 9 bits (every E, F code on the wires: 2^18) into D and,
/// with the invert mapping, into A; SPARE0_PLUS_SECONDARY_COLOR exhaustively (2^18)
/// with and without the colour-sum clamp.
#[test]
fn pseudo_registers_exhaustive_at_9_bits() {
    let base = FinalCombinerConfig::geforce();
    let s = one(9) as i32;
    let reg = |r, m| FinalVariable::new(FinalInput::Register(r), m, ComponentUsage::Rgb);
    let zero = reg(Register::Zero, Mapping::UnsignedIdentity);
    let ef_d = FinalCombinerConfig {
        a: zero,
        b: zero,
        c: reg(Register::Texture1, Mapping::UnsignedIdentity),
        d: FinalVariable::new(
            FinalInput::ETimesF,
            Mapping::UnsignedIdentity,
            ComponentUsage::Rgb,
        ),
        e: reg(Register::Texture0, Mapping::UnsignedIdentity),
        f: reg(Register::Texture1, Mapping::UnsignedInvert),
        ..base
    };
    let ef_a = FinalCombinerConfig {
        a: FinalVariable::new(
            FinalInput::ETimesF,
            Mapping::UnsignedInvert,
            ComponentUsage::Rgb,
        ),
        b: FinalVariable::new(
            FinalInput::Spare0PlusSecondaryColor,
            Mapping::UnsignedIdentity,
            ComponentUsage::Rgb,
        ),
        ..ef_d
    };
    for cfg in [ef_d, ef_a] {
        let u = cfg.build().unwrap();
        for e in -s - 1..=s {
            for f in (-s - 1..=s).step_by(3) {
                let mut file = RegisterFile::default();
                file.set(Register::Texture0, [e; 4]);
                file.set(Register::Texture1, [f, (f + 1).min(s), (f + 2).min(s), 0]);
                file.set(Register::Spare0, [s, e, -e, 0]);
                file.set(Register::SecondaryColor, [f, s, e, 0]);
                check(&u, &file);
            }
        }
    }
    for csc in [false, true] {
        let u = FinalCombinerConfig {
            color_sum_clamp: csc,
            a: reg(Register::Zero, Mapping::UnsignedInvert), // 1
            b: FinalVariable::new(
                FinalInput::Spare0PlusSecondaryColor,
                Mapping::UnsignedIdentity,
                ComponentUsage::Rgb,
            ),
            ..base
        }
        .build()
        .unwrap();
        for sp in -s - 1..=s {
            for se in (-s - 1..=s).step_by(3) {
                let mut file = RegisterFile::default();
                file.set(Register::Spare0, [sp; 4]);
                file.set(
                    Register::SecondaryColor,
                    [se, (se + 1).min(s), (se + 2).min(s), 0],
                );
                check(&u, &file);
                // Exact: at N = 9, O = 8 a code is its output level; the sum clamps at 1.
                let out = u.kernel(&mut (), &file, &mut Counters::default());
                let want = (sp.max(0) + se.max(0)).min(s) as u32;
                assert_eq!(out[0], want, "csc {csc}: {sp} + {se}");
            }
        }
    }
}

/// Stiff: everything at +1 with SPARE0 + SECONDARY = 2 in B and D (the spec's [0, 4]
/// range) saturates each RGB lane once (3); with the colour-sum clamp the sums clamp
/// first (3 more, one per lane) and A·B + D = 2 still clamps (3).
#[test]
fn stiff_all_max_and_the_color_sum_range() {
    let s = one(9) as i32;
    let all_max = RegisterFile {
        regs: [[s; 4]; REGISTER_COUNT],
    };
    let sum = FinalVariable::new(
        FinalInput::Spare0PlusSecondaryColor,
        Mapping::UnsignedIdentity,
        ComponentUsage::Rgb,
    );
    for (csc, sats) in [(false, 3), (true, 3 + 3)] {
        let u = FinalCombinerConfig {
            color_sum_clamp: csc,
            a: FinalVariable::register(Register::PrimaryColor, ComponentUsage::Rgb),
            b: sum,
            d: sum,
            ..FinalCombinerConfig::geforce()
        }
        .build()
        .unwrap();
        let mut ctr = Counters::default();
        let out = u.kernel(&mut (), &all_max, &mut ctr);
        assert_eq!(out, [255; 4]);
        assert_eq!(ctr.saturations, sats, "csc {csc}");
        check(&u, &all_max);
    }
    // All registers at −1 (and the wire's −1.0039): unsigned mappings read 0; the
    // default (colour sum, fog) gives black with alpha 0 and no clamp.
    for v in [-s, -s - 1] {
        let f = RegisterFile {
            regs: [[v; 4]; REGISTER_COUNT],
        };
        let mut ctr = Counters::default();
        let out = FinalCombiner::geforce().kernel(&mut (), &f, &mut ctr);
        assert_eq!(out, [0; 4]);
        assert_eq!(ctr.saturations, 0);
    }
}

/// The initial state is OpenGL's colour sum and fog: with the fog factor 1 (FOG alpha
/// = 1), fcoc = SPARE0 + SECONDARY (clamped to 1), alpha = SPARE0 alpha; with factor 0
/// the fog colour.
#[test]
fn initial_state_is_the_gl_color_sum_and_fog() {
    let u = FinalCombiner::geforce();
    let mut f = RegisterFile::default();
    f.set(Register::Spare0, [100, 200, 30, 77]);
    f.set(Register::SecondaryColor, [50, 100, 0, 9]);
    f.set(Register::Fog, [11, 22, 33, 255]);
    assert_eq!(
        u.kernel(&mut (), &f, &mut Counters::default()),
        [150, 255, 30, 77]
    );
    f.set(Register::Fog, [11, 22, 33, 0]);
    assert_eq!(
        u.kernel(&mut (), &f, &mut Counters::default()),
        [11, 22, 33, 77]
    );
}

#[test]
fn config_errors_name_the_field() {
    let g = FinalCombinerConfig::geforce();
    let err = |c: FinalCombinerConfig| c.build().unwrap_err().field().to_string();
    assert_eq!(
        err(FinalCombinerConfig {
            internal_bits: 25,
            ..g
        }),
        "final_combiner.internal_bits"
    );
    assert_eq!(
        err(FinalCombinerConfig { out_bits: 0, ..g }),
        "final_combiner.out_bits"
    );
    let mut c = g;
    c.c.mapping = Mapping::ExpandNormal;
    assert_eq!(err(c), "final_combiner.c.mapping");
    let mut c = g;
    c.d.component_usage = ComponentUsage::Blue;
    assert_eq!(err(c), "final_combiner.d.component_usage");
    let mut c = g;
    c.g.component_usage = ComponentUsage::Rgb;
    assert_eq!(err(c), "final_combiner.g.component_usage");
    let mut c = g;
    c.e.input = FinalInput::ETimesF;
    assert_eq!(err(c), "final_combiner.e.input");
    let mut c = g;
    c.a.input = FinalInput::Spare0PlusSecondaryColor;
    c.a.component_usage = ComponentUsage::Rgb;
    assert_eq!(err(c), "final_combiner.a.input");
    let mut c = g;
    c.b.component_usage = ComponentUsage::Alpha; // B is SPARE0_PLUS_SECONDARY_COLOR
    assert_eq!(err(c), "final_combiner.b.component_usage");
    let c = FinalCombinerConfig {
        constants: Some([[0; 4], [0, 0, 256, 0]]),
        ..g
    };
    assert_eq!(err(c), "final_combiner.constants");
}

/// NV2A SPARE0_PLUS_SECONDARY_COLOR with the add-invert flags: (S − R0) + V1,
/// R0 + (S − V1), (S − R0) + (S − V1), exactly, for every pair of codes at 9 and 5
/// bits (at 9 bits R0 = 191, V1 = 0 inverted gives 64: the Flags capture), with the
/// clamp to S under COLOR_SUM_CLAMP; the final combiner's own constants read instead
/// of the set's (E·F of C0 = 255, C1 = 127 gives 127: the SpecialInputs capture).
#[test]
fn nv2a_add_invert_flags_and_own_constants() {
    for n in [9u32, 5] {
        let s = one(n) as i64;
        let u_max = 255i64.min((1 << (n - 1)) - 1);
        for (ir, iv) in [(true, false), (false, true), (true, true), (false, false)] {
            for clamp in [false, true] {
                let c = FinalCombinerConfig {
                    internal_bits: n,
                    out_bits: n - 1,
                    a: FinalVariable::new(
                        FinalInput::Register(Register::Zero),
                        Mapping::UnsignedInvert,
                        ComponentUsage::Rgb,
                    ),
                    b: FinalVariable::new(
                        FinalInput::Spare0PlusSecondaryColor,
                        Mapping::UnsignedIdentity,
                        ComponentUsage::Rgb,
                    ),
                    c: FinalVariable::register(Register::Zero, ComponentUsage::Rgb),
                    color_sum_clamp: clamp,
                    specular_add_invert_r0: ir,
                    specular_add_invert_v1: iv,
                    ..FinalCombinerConfig::geforce()
                };
                let u = c.build().unwrap();
                for r0 in 0..=s.min(u_max) {
                    for v1 in (0..=s).step_by(if n == 9 { 7 } else { 1 }) {
                        let mut f = RegisterFile::default();
                        f.set(Register::Spare0, [r0 as i32; 4]);
                        f.set(Register::SecondaryColor, [v1 as i32; 4]);
                        let out = u.kernel(&mut (), &f, &mut Counters::default());
                        let t = |x: i64, inv: bool| if inv { s - x } else { x };
                        let want = (t(r0, ir) + t(v1, iv)).min(s); // min(·, 1) of fcoc either way
                        assert_eq!(out[0] as i64, want, "N {n} r0 {r0} v1 {v1} inv {ir} {iv}");
                        check(&u, &f);
                    }
                }
            }
        }
    }
    let c = FinalCombinerConfig {
        a: FinalVariable::register(Register::Zero, ComponentUsage::Rgb),
        b: FinalVariable::register(Register::Zero, ComponentUsage::Rgb),
        c: FinalVariable::register(Register::Zero, ComponentUsage::Rgb),
        d: FinalVariable::new(
            FinalInput::ETimesF,
            Mapping::UnsignedIdentity,
            ComponentUsage::Rgb,
        ),
        e: FinalVariable::register(Register::ConstantColor0, ComponentUsage::Rgb),
        f: FinalVariable::register(Register::ConstantColor1, ComponentUsage::Rgb),
        constants: Some([[255, 191, 127, 255], [127; 4]]),
        ..FinalCombinerConfig::geforce()
    };
    let u = c.build().unwrap();
    let mut f = RegisterFile::default();
    f.set(Register::ConstantColor0, [1; 4]);
    let out = u.kernel(&mut (), &f, &mut Counters::default());
    assert_eq!(&out[..3], &[127, 95, 63]);
    check(&u, &f);
}

#[test]
fn defaults_summary() {
    let u = FinalCombiner::geforce();
    let s = UnitSummary::of(&u);
    println!(
        "final_combiner defaults: latency {}, II {}, {:.0} NAND2, {} RAM bits",
        s.latency, s.ii, s.gates_nand2, s.ram_bits
    );
    for (p, g) in &s.breakdown {
        println!("  {p}: {g:.0}");
    }
    assert_eq!((s.latency, s.ii, s.ram_bits), (3, 1, 0));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn within_bound_vs_twin(ci in 0usize..4, seed in any::<u64>()) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let base = widths(WIDTH_CONFIGS[ci]);
        let u = random_config(&mut rng, base).build().unwrap();
        check(&u, &random_file(&mut rng, base.internal_bits));
    }

    #[test]
    fn tick_and_span_drivers_agree(
        n in 3u32..=24, o in 1u32..=16, q in 0usize..7, seed in any::<u64>(), len in 0usize..12,
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let base = FinalCombinerConfig {
            internal_bits: n,
            out_bits: o,
            rounding: Quant::ALL[q],
            ..FinalCombinerConfig::geforce()
        };
        let u = random_config(&mut rng, base).build().unwrap();
        let inputs: Vec<RegisterFile> = (0..len).map(|_| random_file(&mut rng, n)).collect();
        common::assert_drivers_agree(&u, (), &inputs);
    }

    #[test]
    fn random_configs_never_panic_and_errors_name_the_field(
        n in 0u32..40, o in 0u32..40, seed in any::<u64>(), m in 0usize..8, usage in 0usize..3,
        words in prop::collection::vec(any::<i32>(), 48),
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut c = random_config(&mut rng, FinalCombinerConfig {
            internal_bits: n, out_bits: o, ..FinalCombinerConfig::geforce()
        });
        c.e.mapping = Mapping::ALL[m];
        c.f.component_usage = [ComponentUsage::Rgb, ComponentUsage::Alpha, ComponentUsage::Blue][usage];
        match c.build() {
            Ok(u) => {
                let mut f = RegisterFile::default();
                for (r, w) in f.regs.iter_mut().flatten().zip(&words) {
                    *r = *w;
                }
                let out = u.kernel(&mut (), &f, &mut Counters::default());
                prop_assert!(out.iter().all(|&x| x <= u.out_max()));
                let _ = u.cost();
            }
            Err(e) => prop_assert!(e.field().starts_with("final_combiner."), "{}", e.field()),
        }
    }

    #[test]
    fn twin_never_nan(x in [any::<f64>(), any::<f64>(), any::<f64>()], csc in any::<bool>()) {
        let s = twin::spare0_plus_secondary_color(x, x, csc);
        let ef = twin::e_times_f(x, s);
        let o = twin::fcoc_rgb(x, s, ef, x);
        prop_assert!(o.iter().all(|v| twin::to_unorm_lsb(*v, 8).is_finite()));
    }
}
