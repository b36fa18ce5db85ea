//! shadow_compare against its f64 twin (an unquantised depth map).
//!
//! Bound (docs/units.md#shadow_compare). Work in LSBs of the n-bit stored depth
//! (1 LSB = 1/(2ⁿ − 1)); k = frag_frac_bits. Host depths are quantised round to
//! nearest: the stored word s_q = s + ε_s with |ε_s| ≤ ½ (the running minimum
//! commutes with a monotone rounding, so the stored word is exactly the rounded exact
//! minimum), the fragment f_q = f + ε_f with |ε_f| ≤ ½·2⁻ᵏ, the bias b is an exact
//! integer of LSBs in both. With D = f − b − s (exact) the unit computes
//! D_q = D + ε_f − ε_s. The decisions (D ≤ 0 vs D_q ≤ 0) can differ only if
//! |D| ≤ |ε_f − ε_s| ≤ ½·(1 + 2⁻ᵏ) LSB — so every disagreement lies in that band
//! (≤ 1 LSB). The only slack is f64 rounding of the products z·(2ⁿ − 1) in the host
//! helper and in this test: ≤ 4 · 2ⁿ⁻⁵³ LSB, derived from the f64 unit roundoff on
//! values below 2ⁿ LSB.
//!
//! The same band holds for every compare function: the outcome of the one comparator
//! (less, equal, greater) of D_q can differ from that of D only if |D| ≤ |ε_f − ε_s|,
//! and each function is a fixed truth table of that outcome. On representable depths
//! (no quantisation) the unit equals the twin exactly, for every function and texel
//! format.

mod common;

use glare_pipeline::reference::shadow_compare::{
    lit as lit_ref, lit_with, texel_depth, Compare, ShadowMapRef, Texel,
};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::units::shadow_compare::{
    CompareFunc, DepthTexel, ShadowCompare, ShadowCompareConfig, ShadowIn, ShadowOut,
    MAX_DEPTH_BITS,
};
use rtl_model::{Counters, Unit, UnitSummary};

fn unit(w: u32, h: u32, n: u32, bias: u32, k: u32) -> ShadowCompare {
    unit_f(w, h, n, bias, k, CompareFunc::Lequal)
}

/// A unit with compare function `func` (unorm texels).
fn unit_f(w: u32, h: u32, n: u32, bias: u32, k: u32, func: CompareFunc) -> ShadowCompare {
    ShadowCompareConfig {
        width: w,
        height: h,
        depth_bits: n,
        bias,
        frag_frac_bits: k,
        compare: func,
        texel: DepthTexel::Unorm,
    }
    .build()
    .unwrap()
}

/// The twin's function of the unit's (matched by GL name, not by code).
fn twin_func(f: CompareFunc) -> Compare {
    let t = Compare::ALL
        .into_iter()
        .find(|c| format!("{c:?}").to_uppercase() == f.name())
        .unwrap();
    t
}

/// A unit whose bias is `bias_raw` folded into its depth range, after `writes`
/// through the kernel: the state the read-only test forms start from, and the
/// writes' counters.
fn unit_after_writes(
    (w, h, n, k): (u32, u32, u32, u32),
    bias_raw: u32,
    func: u32,
    writes: &[(i32, i32, u32)],
) -> (ShadowCompare, <ShadowCompare as Unit>::State, Counters) {
    let far = if n == 32 { u32::MAX } else { (1u32 << n) - 1 };
    let bias = (bias_raw as u64 % (far as u64 + 1)) as u32;
    let u = unit_f(w, h, n, bias, k, CompareFunc::ALL[func as usize % 8]);
    let mut st = u.fresh_state();
    let mut c = Counters::default();
    for &(x, y, d) in writes {
        u.kernel(&mut st, &ShadowIn::Write { x, y, depth: d }, &mut c);
    }
    (u, st, c)
}

/// Half-width of the disagreement band in LSBs, plus the derived f64 slack.
fn band(n: u32, k: u32) -> f64 {
    0.5 * (1.0 + (-(k as f64)).exp2()) + 4.0 * ((n as f64) - 53.0).exp2()
}

/// The three bound configs: (depth_bits, frag_frac_bits).
const BOUND_CONFIGS: [(u32, u32); 3] = [(24, 4), (16, 0), (4, 2)];

#[derive(Clone, Debug)]
enum Op {
    Clear,
    Write(i32, i32, f64),
    Test(i32, i32, f64),
}

/// Run exact ops through the unit and the twin; return (disagreements, max |D| among
/// them, in LSBs). Asserts the stored word is the quantised exact minimum and that
/// every disagreement lies in the band.
fn run_against_twin(u: &ShadowCompare, ops: &[Op]) -> (u64, f64) {
    let n = u.depth_bits();
    let k = u.frag_frac_bits();
    let lsb = u.far() as f64; // LSBs per unit depth
    let bias_units = u.bias() as f64 / lsb;
    let mut st = u.fresh_state();
    let mut twin = ShadowMapRef::new(u.width(), u.height());
    let mut ctr = Counters::default();
    let mut host = Counters::default();
    let (mut dis, mut worst) = (0u64, 0.0f64);
    for op in ops {
        match *op {
            Op::Clear => {
                u.kernel(&mut st, &ShadowIn::Clear, &mut ctr);
                twin.clear();
            }
            Op::Write(x, y, z) => {
                let depth = u.depth_word(z, &mut host).unwrap();
                u.kernel(&mut st, &ShadowIn::Write { x, y, depth }, &mut ctr);
                twin.write(x as i64, y as i64, z);
            }
            Op::Test(x, y, z) => {
                let depth = u.frag_word(z, &mut host).unwrap();
                let out = u.kernel(&mut st, &ShadowIn::Test { x, y, depth }, &mut ctr);
                let func = twin_func(u.compare());
                let want = twin.test_with(func, x as i64, y as i64, z, bias_units);
                match twin.stored(x as i64, y as i64) {
                    None => {
                        assert_eq!(out.stored, u.far());
                        if out.lit != want {
                            // The border: the far plane, the fragment clamped to it.
                            let d = (z.min(1.0) - 1.0) * lsb - u.bias() as f64;
                            assert!(d.abs() <= band(n, k), "border: |D| = {d} LSB");
                            dis += 1;
                            worst = worst.max(d.abs());
                        }
                    }
                    Some(s) => {
                        let sq = u.depth_word(s, &mut host).unwrap();
                        assert_eq!(out.stored, sq, "stored word ≠ rounded exact minimum");
                        if out.lit != want {
                            let d = (z - s) * lsb - u.bias() as f64;
                            assert!(
                                d.abs() <= band(n, k),
                                "{func:?} n={n} k={k} bias={}: frag {z} stored {s}: hw {} \
                                 twin {want}, |D| = {} LSB > band {}",
                                u.bias(),
                                out.lit,
                                d.abs(),
                                band(n, k)
                            );
                            dis += 1;
                            worst = worst.max(d.abs());
                        }
                    }
                }
            }
        }
    }
    assert_eq!(host.saturations, 0, "test depths lie in [0, 1]");
    (dis, worst)
}

fn op_strategy(side: i32) -> impl Strategy<Value = Op> {
    prop_oneof![
        1 => Just(Op::Clear),
        7 => (-1..=side, -1..=side, 0.0f64..=1.0).prop_map(|(x, y, z)| Op::Write(x, y, z)),
        8 => (-1..=side, -1..=side, 0.0f64..=1.0).prop_map(|(x, y, z)| Op::Test(x, y, z)),
    ]
}

#[test]
fn representable_depths_are_exact_exhaustively() {
    // Depths that are codes quantise without error, so the unit must equal the twin
    // (evaluated in LSBs, exact in f64) on every (stored, frag, bias): 2^20 cases max.
    let mut cases = 0u64;
    for n in 1..=4u32 {
        for k in 0..=2u32 {
            let max = (1u32 << n) - 1;
            for bias in 0..=max {
                let u = unit(1, 1, n, bias, k);
                for s in 0..=max {
                    let mut st = u.fresh_state();
                    let mut c = Counters::default();
                    u.kernel(
                        &mut st,
                        &ShadowIn::Write {
                            x: 0,
                            y: 0,
                            depth: s,
                        },
                        &mut c,
                    );
                    for f in 0..(1u64 << (n + k)) {
                        let out = u.kernel(
                            &mut st,
                            &ShadowIn::Test {
                                x: 0,
                                y: 0,
                                depth: f,
                            },
                            &mut c,
                        );
                        let want = lit_ref(f as f64 / (1u64 << k) as f64, bias as f64, s as f64);
                        assert_eq!(out.lit, want, "n={n} k={k} bias={bias} s={s} f={f}");
                        assert_eq!(out.stored, s);
                        cases += 1;
                    }
                }
            }
        }
    }
    // 8-bit depth at the bias values a driver would set.
    for bias in [0u32, 1, 2, 255] {
        let u = unit(1, 1, 8, bias, 0);
        for s in 0..=255u32 {
            let mut st = u.fresh_state();
            let mut c = Counters::default();
            u.kernel(
                &mut st,
                &ShadowIn::Write {
                    x: 0,
                    y: 0,
                    depth: s,
                },
                &mut c,
            );
            for f in 0..=255u64 {
                let out = u.kernel(
                    &mut st,
                    &ShadowIn::Test {
                        x: 0,
                        y: 0,
                        depth: f,
                    },
                    &mut c,
                );
                assert_eq!(out.lit, lit_ref(f as f64, bias as f64, s as f64));
                cases += 1;
            }
        }
    }
    assert!(cases < 1 << 20);
}

/// Every compare function on representable depths equals the twin exactly: every
/// (stored, fragment, bias) at n ≤ 4 bits, k ≤ 2 fraction bits, in the map and on the
/// border (the far plane, the fragment clamped to it).
#[test]
fn every_function_equals_the_twin_on_representable_depths_exhaustively() {
    let mut counts = [[0u64; 2]; 8];
    for (fi, func) in CompareFunc::ALL.into_iter().enumerate() {
        let tf = twin_func(func);
        for n in 1..=4u32 {
            for k in 0..=2u32 {
                let max = (1u32 << n) - 1;
                let unit_k = (1u64 << k) as f64;
                for bias in 0..=max {
                    let u = unit_f(1, 1, n, bias, k, func);
                    let mut twin = ShadowMapRef::new(1, 1);
                    for s in 0..=max {
                        let mut st = u.fresh_state();
                        let mut c = Counters::default();
                        u.kernel(
                            &mut st,
                            &ShadowIn::Write {
                                x: 0,
                                y: 0,
                                depth: s,
                            },
                            &mut c,
                        );
                        twin.clear();
                        twin.write(0, 0, s as f64 / max as f64);
                        for f in 0..(1u64 << (n + k)) {
                            let t = |x| ShadowIn::Test { x, y: 0, depth: f };
                            let out = u.kernel(&mut st, &t(0), &mut c);
                            // In LSBs: exact in f64.
                            let want = lit_with(tf, f as f64 / unit_k, bias as f64, s as f64);
                            assert_eq!(
                                out.lit, want,
                                "{func:?} n={n} k={k} bias={bias} s={s} f={f}"
                            );
                            assert_eq!(out.stored, s);
                            counts[fi][usize::from(want)] += 1;
                            // The border (x = 1 is off the 1 × 1 map).
                            let b = u.kernel(&mut st, &t(1), &mut c);
                            let fz = f as f64 / unit_k / max as f64; // in depth units
                            let bz = bias as f64 / max as f64;
                            let bw = twin.test_with(tf, 1, 0, fz, bz);
                            let exact = lit_with(
                                tf,
                                (f as f64 / unit_k).min(max as f64),
                                bias as f64,
                                max as f64,
                            );
                            assert_eq!(
                                b.lit, exact,
                                "border {func:?} n={n} k={k} bias={bias} f={f}"
                            );
                            // The twin in depth units agrees but where f64 division rounds
                            // an equality (never for these codes at n ≤ 4: checked).
                            assert_eq!(
                                bw, exact,
                                "twin border {func:?} n={n} k={k} bias={bias} f={f}"
                            );
                        }
                    }
                }
            }
        }
    }
    // NEVER and ALWAYS are constant; every other function sees both outcomes.
    for (fi, func) in CompareFunc::ALL.into_iter().enumerate() {
        let [off, on] = counts[fi];
        match func {
            CompareFunc::Never => assert_eq!(on, 0),
            CompareFunc::Always => assert_eq!(off, 0),
            _ => assert!(off > 0 && on > 0, "{func:?}: {off} unlit, {on} lit"),
        }
    }
    // Complements: LESS/GEQUAL, EQUAL/NOTEQUAL, LEQUAL/GREATER, NEVER/ALWAYS.
    for (a, b) in [(1, 6), (2, 5), (3, 4), (0, 7)] {
        assert_eq!(counts[a][0], counts[b][1]);
        assert_eq!(counts[a][1], counts[b][0]);
    }
}

/// The 3-bit code is GL's order (GL_NEVER 0x200 … GL_ALWAYS 0x207, less 0x200) and a
/// truth table over (less, equal, greater).
#[test]
fn function_codes_are_truth_tables() {
    for (i, f) in CompareFunc::ALL.into_iter().enumerate() {
        assert_eq!(f.code(), i as u32);
        assert_eq!(CompareFunc::from_code(i as u32), Some(f));
        assert_eq!(f.eval(0, 1), i & 1 == 1, "{f:?} less");
        assert_eq!(f.eval(1, 1), i & 2 == 2, "{f:?} equal");
        assert_eq!(f.eval(2, 1), i & 4 == 4, "{f:?} greater");
    }
    assert_eq!(CompareFunc::from_code(8), None);
    assert_eq!(CompareFunc::default(), CompareFunc::Lequal);
    assert_eq!(DepthTexel::default(), DepthTexel::Unorm);
}

/// A texel format's unit, 2 × 1 texels, LEQUAL unless given.
fn texel_unit(texel: DepthTexel, func: CompareFunc) -> ShadowCompare {
    ShadowCompareConfig {
        width: 2,
        height: 1,
        depth_bits: texel.required_depth_bits().unwrap(),
        bias: 0,
        frag_frac_bits: 0,
        compare: func,
        texel,
    }
    .build()
    .unwrap()
}

/// Load one texel word through a depth-pass write after a clear and return the
/// stored depth code; check it against the twin's depth of the word.
fn load_texel(u: &ShadowCompare, word: u32, twin: Texel) -> u32 {
    let mut st = u.fresh_state();
    let mut c = Counters::default();
    u.kernel(&mut st, &ShadowIn::Clear, &mut c);
    let o = u.kernel(
        &mut st,
        &ShadowIn::Write {
            x: 1,
            y: 0,
            depth: word,
        },
        &mut c,
    );
    let z = texel_depth(twin, word);
    assert_eq!(
        o.stored as f64,
        (z * u.far() as f64).round(),
        "{:?} word {word:#x}",
        u.texel()
    );
    o.stored
}

/// Z16: every 16-bit word is its own depth code (bits above 16 ignored); the
/// compare is at texel precision: a fragment word equal to the texel is EQUAL, one
/// LSB either side LESS or GREATER.
#[test]
fn z16_texels_are_their_word_exhaustively() {
    let eq = texel_unit(DepthTexel::Z16, CompareFunc::Equal);
    for w in 0..=0xffffu32 {
        assert_eq!(load_texel(&eq, w, Texel::Z16), w);
        assert_eq!(load_texel(&eq, w | 0xabcd_0000, Texel::Z16), w);
    }
    let mut st = eq.fresh_state();
    let mut c = Counters::default();
    for w in [0u32, 1, 0x7ffe, 0x7fff, 0x8000, 0xfffe] {
        eq.kernel(&mut st, &ShadowIn::Clear, &mut c);
        eq.kernel(
            &mut st,
            &ShadowIn::Write {
                x: 0,
                y: 0,
                depth: w,
            },
            &mut c,
        );
        for (f, want) in [(w as u64, true), (w as u64 + 1, false)] {
            let o = eq.kernel(
                &mut st,
                &ShadowIn::Test {
                    x: 0,
                    y: 0,
                    depth: f,
                },
                &mut c,
            );
            assert_eq!(o.lit, want, "word {w:#x} frag {f:#x}");
        }
    }
}

/// Z24S8: a 32-bit word's depth is word >> 8 whatever the stencil byte, over every
/// 24-bit depth code in steps (and its neighbours) and every stencil byte at a few
/// codes; the compare is at 24-bit texel precision.
#[test]
fn z24s8_texels_are_the_word_shifted_right_8() {
    let eq = texel_unit(DepthTexel::Z24S8, CompareFunc::Equal);
    let codes: Vec<u32> = (0..1u32 << 24)
        .step_by(4099)
        .chain([1, 0x7f_fffe, 0x7f_ffff, 0x80_0000, 0xff_fffe, 0xff_ffff])
        .collect();
    for &d in &codes {
        assert_eq!(load_texel(&eq, d << 8, Texel::Z24S8), d);
        assert_eq!(load_texel(&eq, (d << 8) | 0xff, Texel::Z24S8), d);
    }
    for s in 0..=0xffu32 {
        for d in [0u32, 0x80, 0x7f_ffff, 0xff_fffe] {
            assert_eq!(load_texel(&eq, (d << 8) | s, Texel::Z24S8), d);
            let mut st = eq.fresh_state();
            let mut c = Counters::default();
            eq.kernel(
                &mut st,
                &ShadowIn::Write {
                    x: 0,
                    y: 0,
                    depth: (d << 8) | s,
                },
                &mut c,
            );
            let t = |f: u64, st: &mut _, c: &mut Counters| {
                eq.kernel(
                    st,
                    &ShadowIn::Test {
                        x: 0,
                        y: 0,
                        depth: f,
                    },
                    c,
                )
                .lit
            };
            assert!(t(d as u64, &mut st, &mut c), "depth {d:#x} stencil {s:#x}");
            assert!(!t(d as u64 + 1, &mut st, &mut c));
        }
    }
    // A format fixes the depth width; the error names the field.
    for (texel, n) in [(DepthTexel::Z24S8, 16), (DepthTexel::Z16, 24)] {
        let cfg = ShadowCompareConfig {
            depth_bits: n,
            texel,
            ..ShadowCompareConfig::geforce()
        };
        assert_eq!(cfg.build().unwrap_err().field(), "shadow_compare.texel");
    }
}

#[test]
fn writes_keep_the_minimum_exhaustively_at_4_bits() {
    let u = unit(2, 1, 4, 0, 0);
    for a in 0..16u32 {
        for b in 0..16u32 {
            let mut st = u.fresh_state();
            let mut c = Counters::default();
            let w = |st: &mut _, d, c: &mut Counters| {
                u.kernel(
                    st,
                    &ShadowIn::Write {
                        x: 1,
                        y: 0,
                        depth: d,
                    },
                    c,
                )
            };
            let oa = w(&mut st, a, &mut c);
            let ob = w(&mut st, b, &mut c);
            assert_eq!(oa.written, a < 15);
            assert_eq!(ob.written, b < a.min(15));
            assert_eq!(ob.stored, a.min(b));
            // The neighbour texel is untouched (still the far plane).
            let t = u.kernel(
                &mut st,
                &ShadowIn::Test {
                    x: 0,
                    y: 0,
                    depth: 15,
                },
                &mut c,
            );
            assert_eq!(t.stored, 15);
            assert_eq!(c.table_reads, 3);
        }
    }
}

#[test]
fn narrow_4_bit_disagrees_often_and_only_in_the_band() {
    // Deterministic: shows the band matters at 4 bits and is not loose.
    let mut rng = ChaCha8Rng::seed_from_u64(0x5ad0);
    for k in [0u32, 2] {
        let u = unit(4, 4, 4, 1, k);
        let ops: Vec<Op> = (0..40_000)
            .map(|_| {
                let (x, y, z) = (rng.random_range(0..4), rng.random_range(0..4), rng.random());
                match rng.random_range(0..32) {
                    0 => Op::Clear,
                    1..=12 => Op::Write(x, y, z),
                    _ => Op::Test(x, y, z),
                }
            })
            .collect();
        let (dis, worst) = run_against_twin(&u, &ops);
        println!(
            "4-bit k={k}: {dis} disagreements, max |D| {worst:.4} LSB (band {:.4})",
            band(4, k)
        );
        assert!(
            dis > 100,
            "expected many disagreements at 4 bits, got {dis}"
        );
        assert!(
            worst > 0.75 * band(4, k),
            "band looser than observed: {worst}"
        );
    }
}

#[test]
fn out_of_map_is_lit_counted_and_writes_are_dropped() {
    let u = unit(3, 2, 8, 0, 0);
    let coords = [
        (-1, 0),
        (0, -1),
        (3, 0),
        (0, 2),
        (i32::MIN, 0),
        (0, i32::MAX),
        (4096, 1),
        (70_000, 1),
        (-70_000, -1),
    ];
    let mut st = u.fresh_state();
    let before = st.clone();
    let mut c = Counters::default();
    for (x, y) in coords {
        let o = u.kernel(&mut st, &ShadowIn::Write { x, y, depth: 0 }, &mut c);
        assert!(!o.written);
        let o = u.kernel(&mut st, &ShadowIn::Test { x, y, depth: 255 }, &mut c);
        assert!(o.lit && o.stored == 255);
    }
    assert_eq!(st, before);
    assert_eq!(c.saturations, 2 * coords.len() as u64);
    assert_eq!(c.table_reads, 0);
}

#[test]
fn wrong_size_state_is_replaced_not_a_panic() {
    let u = unit(4, 4, 8, 0, 0);
    let mut st = unit(2, 2, 3, 0, 0).fresh_state();
    let mut c = Counters::default();
    let o = u.kernel(
        &mut st,
        &ShadowIn::Test {
            x: 3,
            y: 3,
            depth: 9,
        },
        &mut c,
    );
    assert!(o.lit && o.stored == 255);
    assert_eq!(st, u.fresh_state());
}

#[test]
fn nan_and_infinite_host_inputs_name_the_field() {
    let u = ShadowCompare::geforce();
    let mut c = Counters::default();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(
            u.depth_word(bad, &mut c).unwrap_err().field(),
            "shadow_compare.depth"
        );
        assert_eq!(
            u.frag_word(bad, &mut c).unwrap_err().field(),
            "shadow_compare.frag_depth"
        );
        assert_eq!(
            ShadowCompare::bias_lsb_from_f64(24, bad)
                .unwrap_err()
                .field(),
            "shadow_compare.bias"
        );
    }
    for bad in [-1e-3, 1.5] {
        assert_eq!(
            ShadowCompare::bias_lsb_from_f64(24, bad)
                .unwrap_err()
                .field(),
            "shadow_compare.bias"
        );
    }
    assert_eq!(
        ShadowCompare::bias_lsb_from_f64(0, 0.1)
            .unwrap_err()
            .field(),
        "shadow_compare.depth_bits"
    );
    assert_eq!(
        ShadowCompare::bias_lsb_from_f64(24, 2.0 / 16_777_215.0),
        Ok(2)
    );
    // Out-of-[0, 1] depths clamp and count.
    assert_eq!(u.depth_word(-0.5, &mut c), Ok(0));
    assert_eq!(u.frag_word(2.0, &mut c), Ok((1 << 24) - 1));
    assert_eq!(c.saturations, 2);
    assert_eq!(c.overflows + c.underflows, 0);
}

#[test]
fn datasheet_numbers_at_defaults() {
    let u = ShadowCompare::geforce();
    let s = UnitSummary::of(&u);
    println!(
        "shadow_compare defaults: latency {} II {} gates {:.1} NAND2 ram_bits {}",
        s.latency, s.ii, s.gates_nand2, s.ram_bits
    );
    for (part, g) in &s.breakdown {
        println!("  {part}: {g:.1}");
    }
    assert_eq!((s.latency, s.ii), (2, 1));
    assert_eq!(s.ram_bits, 512 * 512 * 24);
    // Any other compare function adds its part (the same for all seven); a texel
    // format widens only the stage-1 depth register (Z24S8: 32 bits, not 24).
    let with = |compare, texel| {
        let cfg = ShadowCompareConfig {
            compare,
            texel,
            ..ShadowCompareConfig::geforce()
        };
        UnitSummary::of(&cfg.build().unwrap()).gates_nand2
    };
    let extra: Vec<f64> = CompareFunc::ALL
        .into_iter()
        .map(|f| with(f, DepthTexel::Unorm) - s.gates_nand2)
        .collect();
    println!("  another compare function: +{:.1}", extra[0]);
    assert_eq!(extra[3], 0.0);
    for (i, e) in extra.iter().enumerate() {
        assert!(i == 3 || (*e > 0.0 && *e == extra[0]), "{i}: {e}");
    }
    let z24 = with(CompareFunc::Lequal, DepthTexel::Z24S8) - s.gates_nand2;
    println!("  Z24S8 texels: +{z24:.1}");
    assert!(z24 > 0.0);
}

/// A config field drawn from valid and invalid values.
fn field(valid_max: u32) -> impl Strategy<Value = u32> {
    prop_oneof![
        3 => 0..=valid_max,
        1 => Just(0u32),
        1 => valid_max..=valid_max.saturating_add(100),
        1 => any::<u32>(),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn disagreements_lie_in_the_quantisation_band_at_24_16_and_narrow_4_bits(
        which in 0usize..3,
        bias in 0u32..=4,
        func in 0usize..8,
        ops in prop::collection::vec(op_strategy(4), 1..64),
    ) {
        let (n, k) = BOUND_CONFIGS[which];
        let u = unit_f(4, 4, n, bias, k, CompareFunc::ALL[func]);
        run_against_twin(&u, &ops);
    }

    #[test]
    fn depth_words_round_trip(n in 1u32..=MAX_DEPTH_BITS, code in any::<u32>(), k in 0u32..=8) {
        let u = unit(1, 1, n, 0, k);
        let d = code & u.far();
        let mut c = Counters::default();
        let z = d as f64 / u.far() as f64;
        prop_assert_eq!(u.depth_word(z, &mut c).unwrap(), d);
        prop_assert_eq!(u.frag_word(z, &mut c).unwrap(), (d as u64) << k);
        prop_assert_eq!(c.saturations, 0);
    }

    #[test]
    fn tick_and_span_drivers_agree(
        w in 1u32..=8, h in 1u32..=8, n in 1u32..=MAX_DEPTH_BITS, k in 0u32..=8,
        bias_raw in any::<u32>(), func in 0usize..8, texel in 0usize..3,
        raw in prop::collection::vec((0u8..8, -2i32..10, -2i32..10, any::<u64>()), 0..40),
    ) {
        // A texel format fixes the depth width.
        let texel = [DepthTexel::Unorm, DepthTexel::Z16, DepthTexel::Z24S8][texel];
        let n = texel.required_depth_bits().unwrap_or(n);
        let far = if n == 32 { u32::MAX } else { (1u32 << n) - 1 };
        let bias = (bias_raw as u64 % (far as u64 + 1)) as u32;
        let u = ShadowCompareConfig {
            width: w,
            height: h,
            depth_bits: n,
            bias,
            frag_frac_bits: k,
            compare: CompareFunc::ALL[func],
            texel,
        }
        .build()
        .unwrap();
        // Unmasked depth words: the unit masks them to its wires.
        let inputs: Vec<ShadowIn> = raw
            .iter()
            .map(|&(op, x, y, d)| match op {
                0 => ShadowIn::Clear,
                1..=3 => ShadowIn::Write { x, y, depth: d as u32 },
                _ => ShadowIn::Test { x, y, depth: d },
            })
            .collect();
        let out: Vec<ShadowOut> = common::assert_drivers_agree(&u, u.fresh_state(), &inputs);
        prop_assert_eq!(out.len(), inputs.len());
    }

    /// The read-only test forms (`test_batch`, `test_filter`, and `test_filter_words`
    /// on the unpacked words) against the kernel's Test word by word, on a RAM filled
    /// by random writes: the same lit bits (kept indices), the same counters, any
    /// coordinate word (out-of-map and beyond the s16 wires included).
    #[test]
    fn read_only_test_forms_agree_with_the_kernel(
        w in 1u32..=9, h in 1u32..=9, n in 1u32..=MAX_DEPTH_BITS, k in 0u32..=8,
        bias_raw in any::<u32>(), func in 0u32..8,
        writes in prop::collection::vec((0i32..9, 0i32..9, any::<u32>()), 0..60),
        tests in prop::collection::vec(
            (prop_oneof![-3i32..12, any::<i32>()], prop_oneof![-3i32..12, any::<i32>()], any::<u64>()),
            0..80,
        ),
    ) {
        let (u, st, _) = unit_after_writes((w, h, n, k), bias_raw, func, &writes);
        let ins: Vec<ShadowIn> =
            tests.iter().map(|&(x, y, depth)| ShadowIn::Test { x, y, depth }).collect();
        let (mut s_k, mut c_k) = (st.clone(), Counters::default());
        let want: Vec<ShadowOut> = ins.iter().map(|i| u.kernel(&mut s_k, i, &mut c_k)).collect();
        let lit: Vec<u32> = (0..want.len() as u32).filter(|&i| want[i as usize].lit).collect();

        let (mut out, mut c_b) = (Vec::new(), Counters::default());
        prop_assert!(u.test_batch(&st, &ins, &mut out, &mut c_b));
        prop_assert_eq!(&out, &want);
        prop_assert_eq!(c_b, c_k);

        let cands = || tests.iter().enumerate().map(|(i, &(x, y, d))| (i as u32, x, y, d));
        let (mut kept, mut c_f) = (Vec::new(), Counters::default());
        prop_assert_eq!(u.test_filter(&st, cands(), &mut kept, &mut c_f), Some(tests.len()));
        prop_assert_eq!(&kept, &lit);
        prop_assert_eq!(c_f, c_k);

        let words = u.words(&st).unwrap();
        prop_assert_eq!(words.len(), (w * h) as usize);
        let (mut kept, mut c_w) = (Vec::new(), Counters::default());
        prop_assert_eq!(u.test_filter_words(&words, cands(), &mut kept, &mut c_w), Some(tests.len()));
        prop_assert_eq!(&kept, &lit);
        prop_assert_eq!(c_w, c_k);

        // In lanes: every other test a candidate (the others masked off).
        let cand = |i: usize| {
            let (x, y, d) = tests[i];
            (i & 1 == 0, x, y, d)
        };
        let ins2: Vec<ShadowIn> = ins.iter().step_by(2).copied().collect();
        let (mut s_2, mut c_2) = (st.clone(), Counters::default());
        let lit2: Vec<u32> = ins2
            .iter()
            .enumerate()
            .filter(|(_, i)| u.kernel(&mut s_2, i, &mut c_2).lit)
            .map(|(j, _)| 2 * j as u32)
            .collect();
        let (mut kept, mut c_l) = (vec![99], Counters::default());
        prop_assert_eq!(u.test_filter_lanes(&words, tests.len(), cand, &mut kept, &mut c_l), Some(ins2.len()));
        prop_assert_eq!(kept[0], 99);
        prop_assert_eq!(&kept[1..], &lit2[..]);
        prop_assert_eq!(c_l, c_2);
        let all = |i: usize| {
            let (x, y, d) = tests[i];
            (true, x, y, d)
        };
        let (mut kept, mut c_l) = (Vec::new(), Counters::default());
        prop_assert_eq!(u.test_filter_lanes(&words, tests.len(), all, &mut kept, &mut c_l), Some(tests.len()));
        prop_assert_eq!(&kept, &lit);
        prop_assert_eq!(c_l, c_k);
        prop_assert_eq!(u.test_filter_lanes(&words[1..], tests.len(), all, &mut kept, &mut c_l), None);

        // The lit bits in lanes, appended after what the vector holds.
        let tx: Vec<i32> = tests.iter().map(|t| t.0).collect();
        let ty: Vec<i32> = tests.iter().map(|t| t.1).collect();
        let td: Vec<u64> = tests.iter().map(|t| t.2).collect();
        let test = (&tx[..], &ty[..], &td[..]);
        let (mut bits, mut c_b) = (vec![false], Counters::default());
        prop_assert_eq!(u.test_lit_lanes(&words, test, &mut bits, &mut c_b), Some(tests.len()));
        prop_assert!(!bits[0]);
        let want_bits: Vec<bool> = want.iter().map(|o| o.lit).collect();
        prop_assert_eq!(&bits[1..], &want_bits[..]);
        prop_assert_eq!(c_b, c_k);
        let (mut bits, mut c_b) = (Vec::new(), Counters::default());
        prop_assert_eq!(u.test_lit_lanes(&words[1..], test, &mut bits, &mut c_b), None);
        if !tests.is_empty() {
            prop_assert_eq!(u.test_lit_lanes(&words, (&tx[1..], &ty[..], &td[..]), &mut bits, &mut c_b), None);
        }
        prop_assert!(bits.is_empty());
        prop_assert_eq!(c_b, Counters::default());

        // A state or word list of another size: nothing done.
        let other = unit_f(w + 1, h, n, u.bias(), k, u.compare()).fresh_state();
        prop_assert_eq!(u.test_filter(&other, cands(), &mut kept, &mut c_f), None);
        prop_assert!(u.words(&other).is_none());
        prop_assert_eq!(u.test_filter_words(&words[1..], cands(), &mut kept, &mut c_w), None);
    }

    #[test]
    fn random_configs_never_panic_and_errors_name_the_field(
        width in field(4096), height in field(4096), depth_bits in field(32),
        bias in any::<u32>(), frag_frac_bits in field(8), func in 0usize..8, texel in 0usize..3,
    ) {
        let texel = [DepthTexel::Unorm, DepthTexel::Z16, DepthTexel::Z24S8][texel];
        let compare = CompareFunc::ALL[func];
        let cfg = ShadowCompareConfig { width, height, depth_bits, bias, frag_frac_bits, compare, texel };
        let far = if (1..=31).contains(&depth_bits) { (1u64 << depth_bits) - 1 } else { u32::MAX as u64 };
        let first_bad = if !(1..=4096).contains(&width) {
            Some("shadow_compare.width")
        } else if !(1..=4096).contains(&height) {
            Some("shadow_compare.height")
        } else if !(1..=32).contains(&depth_bits) {
            Some("shadow_compare.depth_bits")
        } else if bias as u64 > far {
            Some("shadow_compare.bias")
        } else if frag_frac_bits > 8 {
            Some("shadow_compare.frag_frac_bits")
        } else if texel.required_depth_bits().is_some_and(|b| b != depth_bits) {
            Some("shadow_compare.texel")
        } else {
            None
        };
        match (cfg.build(), first_bad) {
            (Ok(u), None) => {
                // Cost and widths of any valid config are finite and positive.
                let c = u.cost();
                prop_assert!(c.gates_nand2().is_finite() && c.gates_nand2() > 0.0);
                prop_assert_eq!(c.ram_bits, width as u64 * height as u64 * depth_bits as u64);
            }
            (Err(e), Some(f)) => prop_assert_eq!(e.field(), f),
            (r, f) => prop_assert!(false, "{:?} vs expected {:?}", r.map(|_| ()), f),
        }
    }
}

/// `address` (one unsigned compare per axis) is the s16-clamped map test: every
/// coordinate word from −2¹⁶ to 2¹⁶ and the i32 extremes, at the largest map side
/// and small ones.
#[test]
fn address_is_the_clamped_wire_test() {
    let clamped = |u: &ShadowCompare, x: i32, y: i32| {
        let lim = 1i32 << 15;
        let (x, y) = (x.clamp(-lim, lim - 1), y.clamp(-lim, lim - 1));
        (x >= 0 && y >= 0 && x < u.width() as i32 && y < u.height() as i32)
            .then(|| y as usize * u.width() as usize + x as usize)
    };
    for (w, h) in [(1, 1), (3, 5), (4096, 4096)] {
        let u = unit(w, h, 8, 0, 0);
        let words = (-(1i32 << 16)..=(1 << 16)).chain([i32::MIN, i32::MAX, i32::MIN + 1]);
        for v in words {
            for o in [0, 2, -1, 4095, 4096] {
                assert_eq!(u.address(v, o), clamped(&u, v, o), "({v}, {o}) on {w}×{h}");
                assert_eq!(u.address(o, v), clamped(&u, o, v), "({o}, {v}) on {w}×{h}");
            }
        }
    }
}

/// `test_filter_flat` on lanes (x, y, inside) at one depth, against the kernel's
/// Test on the candidates (covered lanes inside the viewport) in lane order, run on
/// a copy of `st` (a test never changes it), and against `test_filter_lanes` on the
/// same candidates: the same kept indices (appended), counters and count; and so
/// `test_filter_flat_rows` on the map's uniform rows.
#[allow(clippy::too_many_arguments)]
fn flat_agrees(
    u: &ShadowCompare,
    st: &rtl_model::units::shadow_compare::ShadowState,
    words: &[u32],
    x: &[i64],
    y: &[i64],
    inside: &[bool],
    viewport: (u32, u32),
    depth: u64,
) {
    let (vw, vh) = (viewport.0 as i64, viewport.1 as i64);
    let is_cand = |i: usize| inside[i] && x[i] >= 0 && y[i] >= 0 && x[i] < vw && y[i] < vh;
    let (mut s_k, mut c_k) = (st.clone(), Counters::default());
    let mut want = vec![7u32];
    let mut n = 0;
    for i in (0..x.len()).filter(|&i| is_cand(i)) {
        n += 1;
        let t = ShadowIn::Test {
            x: x[i] as i32,
            y: y[i] as i32,
            depth,
        };
        if u.kernel(&mut s_k, &t, &mut c_k).lit {
            want.push(i as u32);
        }
    }
    let (mut kept, mut c_f) = (vec![7u32], Counters::default());
    assert_eq!(
        u.test_filter_flat(words, (x, y, inside), viewport, depth, &mut kept, &mut c_f),
        Some(n),
        "test_filter_flat: candidate count"
    );
    assert_eq!(
        kept, want,
        "test_filter_flat: kept lanes differ from the kernel's"
    );
    assert_eq!(
        c_f, c_k,
        "test_filter_flat: counters differ from the kernel's"
    );
    let cand = |i: usize| (is_cand(i), x[i] as i32, y[i] as i32, depth);
    let (mut kept_l, mut c_l) = (vec![7u32], Counters::default());
    assert_eq!(
        u.test_filter_lanes(words, x.len(), cand, &mut kept_l, &mut c_l),
        Some(n)
    );
    assert_eq!(
        kept_l, kept,
        "test_filter_flat and test_filter_lanes differ"
    );
    assert_eq!(c_l, c_f);
    let rows = u.row_ranges(words);
    let (mut kept_r, mut c_r) = (vec![7u32], Counters::default());
    let lanes = (x, y, inside);
    assert_eq!(
        u.test_filter_flat_rows(
            (words, &rows),
            lanes,
            viewport,
            depth,
            &mut kept_r,
            &mut c_r
        ),
        Some(n),
        "test_filter_flat_rows: candidate count"
    );
    assert_eq!(kept_r, want, "test_filter_flat_rows: kept lanes");
    assert_eq!(c_r, c_k, "test_filter_flat_rows: counters");
    // Words of another size, or lanes of different lengths: nothing done.
    let (mut none, mut c_n) = (Vec::new(), Counters::default());
    assert_eq!(
        u.test_filter_flat(
            &words[1..],
            (x, y, inside),
            viewport,
            depth,
            &mut none,
            &mut c_n
        ),
        None
    );
    if !x.is_empty() {
        assert_eq!(
            u.test_filter_flat(
                words,
                (x, &y[1..], inside),
                viewport,
                depth,
                &mut none,
                &mut c_n
            ),
            None
        );
    }
    assert!(none.is_empty());
    assert_eq!(c_n, Counters::default());
}

/// A RAM of `u` filled by writes of every third depth code from `seed`.
fn filled(u: &ShadowCompare, seed: u32) -> rtl_model::units::shadow_compare::ShadowState {
    let mut st = u.fresh_state();
    let mut c = Counters::default();
    let far = ((1u64 << u.depth_bits()) - 1) as u32;
    let mut v = seed;
    for y in 0..4 {
        for x in 0..4 {
            v = v.wrapping_mul(2_654_435_761).wrapping_add(0x9e37);
            if !v.is_multiple_of(5) {
                let depth = v % (far + 1);
                u.kernel(&mut st, &ShadowIn::Write { x, y, depth }, &mut c);
            }
        }
    }
    st
}

/// Exhaustive at narrow widths: a 3 × 3 map of 2-bit words, every bias, fraction
/// width 0 ..= 2 and fragment depth word (and some beyond the wires), over lanes
/// that cover −1 ..= 4 on both axes, covered and not, against viewports smaller,
/// equal and larger than the map.
#[test]
fn flat_test_form_agrees_exhaustively_at_2_bits() {
    let (mut x, mut y, mut inside) = (Vec::new(), Vec::new(), Vec::new());
    for yy in -1i64..=4 {
        for xx in -1i64..=4 {
            for ins in [true, false] {
                x.push(xx);
                y.push(yy);
                inside.push(ins);
            }
        }
    }
    for func in CompareFunc::ALL {
        for k in 0..=2 {
            for bias in 0..=3 {
                let u = unit_f(3, 3, 2, bias, k, func);
                let st = filled(&u, bias * 7 + k);
                let words = u.words(&st).unwrap();
                for depth in (0..1u64 << (2 + k)).chain([1u64 << 40, u64::MAX]) {
                    for viewport in [(2, 3), (3, 3), (5, 4), (0, 0)] {
                        flat_agrees(&u, &st, &words, &x, &y, &inside, viewport, depth);
                    }
                }
            }
        }
    }
}

/// `test_filter_flat` on a walk that goes back and forth along rows (as the polygon
/// interpolator walks a full-screen parallelogram), rows 21 wide so that groups of 8
/// lanes start at every offset and straddle rows, the walk reaching one pixel off
/// the map on every side, some lanes not covered: the runs of 8 lanes along one row
/// (read as one block of words, forward or reversed) and the rest give the kernel's
/// kept lanes and counters, for every function and at depths below, inside and
/// above the map's words.
#[test]
fn flat_test_form_agrees_on_a_back_and_forth_walk() {
    let (w, h) = (19u32, 5u32);
    let (mut x, mut y, mut inside) = (Vec::new(), Vec::new(), Vec::new());
    for yy in -1i64..=h as i64 {
        let row: Vec<i64> = (-1i64..=w as i64).collect();
        let row: Vec<i64> = if yy.rem_euclid(2) == 0 {
            row
        } else {
            row.into_iter().rev().collect()
        };
        for xx in row {
            x.push(xx);
            y.push(yy);
            inside.push((xx * 7 + yy * 3).rem_euclid(23) != 0);
        }
    }
    for func in CompareFunc::ALL {
        let u = unit_f(w, h, 8, 1, 2, func);
        let mut st = u.fresh_state();
        let mut c = Counters::default();
        let mut v = 12345u32;
        for yy in 0..h as i32 {
            for xx in 0..w as i32 {
                v = v.wrapping_mul(2_654_435_761).wrapping_add(0x9e37);
                let depth = v % 256;
                u.kernel(
                    &mut st,
                    &ShadowIn::Write {
                        x: xx,
                        y: yy,
                        depth,
                    },
                    &mut c,
                );
            }
        }
        let words = u.words(&st).unwrap();
        for depth in [0u64, 1, 300, 517, 1023, 1 << 20] {
            for viewport in [(w, h), (w - 4, h), (w + 3, h + 2)] {
                flat_agrees(&u, &st, &words, &x, &y, &inside, viewport, depth);
            }
        }
    }
}

/// `row_ranges`: each row's least and greatest word.
#[test]
fn row_ranges_are_each_rows_least_and_greatest_word() {
    let u = unit(3, 4, 8, 0, 0);
    let words = [5, 5, 5, 5, 6, 4, 0, 0, 0, 7, 9, 7];
    assert_eq!(u.row_ranges(&words), [(5, 5), (4, 6), (0, 0), (7, 9)]);
}

/// `is_monotone`: the functions whose lit stored words are a run at one end of
/// their range, checked on every stored word around a fragment depth.
#[test]
fn monotone_functions_change_outcome_at_most_once() {
    for func in CompareFunc::ALL {
        let outcomes: Vec<bool> = (0..5).map(|stored| func.eval(2, stored)).collect();
        let changes = outcomes.windows(2).filter(|w| w[0] != w[1]).count();
        assert_eq!(func.is_monotone(), changes <= 1, "{func:?}: {outcomes:?}");
    }
}

/// `test_filter_flat_rows` where it decides at once: lanes walked along rows that
/// each hold one word or several (all or some of them covered, inside the viewport
/// or not), at depths below, at, between and above those words, for every function:
/// the kernel's kept lanes and counters, whether every row gives one outcome (decided
/// at once) or the rows give two, or a row of several words gives two (lane by
/// lane).
#[test]
fn flat_rows_form_agrees_on_rows_decided_at_once() {
    let (w, h) = (13u32, 6u32);
    // Rows 0 and 1 hold 100, row 2 mixed, rows 3 and 4 hold 40, row 5 holds 100.
    let word_at = |x: i32, y: i32| match y {
        0 | 1 | 5 => 100,
        2 => 30 + 10 * (x as u32 % 3),
        _ => 40,
    };
    for func in CompareFunc::ALL {
        let u = unit_f(w, h, 8, 0, 0, func);
        let mut st = u.fresh_state();
        let mut c = Counters::default();
        for yy in 0..h as i32 {
            for xx in 0..w as i32 {
                let t = ShadowIn::Write {
                    x: xx,
                    y: yy,
                    depth: word_at(xx, yy),
                };
                u.kernel(&mut st, &t, &mut c);
            }
        }
        let words = u.words(&st).unwrap();
        for (y0, y1) in [
            (0, 1),
            (3, 4),
            (0, 0),
            (4, 5),
            (2, 2),
            (1, 2),
            (1, 3),
            (0, 5),
        ] {
            let (mut x, mut y) = (Vec::new(), Vec::new());
            for yy in y0..=y1 {
                for xx in 0..w as i64 {
                    // Back and forth, as the interpolator walks.
                    x.push(if yy % 2 == 0 { xx } else { w as i64 - 1 - xx });
                    y.push(yy);
                }
            }
            let all = vec![true; x.len()];
            let some: Vec<bool> = (0..x.len()).map(|i| i % 5 != 2).collect();
            for depth in [0u64, 29, 30, 35, 39, 40, 41, 45, 50, 51, 99, 100, 101, 255] {
                for viewport in [(w, h), (w - 1, h), (w + 2, h + 1)] {
                    for inside in [&all, &some] {
                        flat_agrees(&u, &st, &words, &x, &y, inside, viewport, depth);
                    }
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]
    /// Random configs, RAM contents, viewports, depths and lanes (coordinates off the
    /// map and beyond the s16 wires included).
    #[test]
    fn flat_test_form_agrees_with_the_kernel(
        w in 1u32..=9, h in 1u32..=9, n in 1u32..=MAX_DEPTH_BITS, k in 0u32..=8,
        bias_raw in any::<u32>(), func in 0u32..8, depth in any::<u64>(),
        vw in 0u32..=12, vh in 0u32..=12,
        writes in prop::collection::vec((0i32..9, 0i32..9, any::<u32>()), 0..60),
        lanes in prop::collection::vec(
            (prop_oneof![-3i64..12, any::<i64>()], prop_oneof![-3i64..12, any::<i64>()], any::<bool>()),
            0..80,
        ),
    ) {
        let (u, st, _) = unit_after_writes((w, h, n, k), bias_raw, func, &writes);
        let words = u.words(&st).unwrap();
        let x: Vec<i64> = lanes.iter().map(|l| l.0).collect();
        let y: Vec<i64> = lanes.iter().map(|l| l.1).collect();
        let inside: Vec<bool> = lanes.iter().map(|l| l.2).collect();
        flat_agrees(&u, &st, &words, &x, &y, &inside, (vw, vh), depth);
    }
}
