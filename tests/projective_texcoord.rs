//! projective_texcoord against its f64 twin u = s/q, v = t/q.
//!
//! Bound (derivation in docs/units.md#projective_texcoord). Write Q = 2ᵖ·m with
//! m ∈ [1, 2) exact, I = recip_index_bits, E = recip_entry_bits, N = newton_frac_bits,
//! and e = |r·m − 1| the relative error of the reciprocal r ≈ 1/m.
//! * Table: m lies in [a, a + 2⁻ᴵ), the entry is 1/c + δ with c = a + 2⁻⁽ᴵ⁺¹⁾ > 1, so
//!   r·m − 1 = (m − c)/c + δ·m and e₀ ≤ 2⁻⁽ᴵ⁺¹⁾ + 2·δ_max, δ_max = 2⁻⁽ᴱ⁺¹⁾ (round to
//!   nearest), or 2⁻ᴱ when E ≤ I (then entry 0 rounds to 2ᴱ and is clamped to 2ᴱ − 1).
//! * Newton step with m truncated to u1.N (m − m_N ∈ [0, 2⁻ᴺ)), d = 2 − m_N·r rounded
//!   (|ρ₁| ≤ 2⁻⁽ᴺ⁺¹⁾), r' = r·d rounded (|ρ₂| ≤ 2⁻⁽ᴺ⁺¹⁾):
//!   1 − m·r' = e² − (1 − e)((m − m_N)·r + ρ₁) − m·ρ₂, and r ≤ (1 + e)/m, m < 2, so
//!   e' ≤ e² + (1 + e)((1 + e)·2⁻ᴺ + 2⁻⁽ᴺ⁺¹⁾) + 2⁻ᴺ.
//! * Output: s·r·2⁻ᵖ is exact, s/q = S/(m·2ᵖ), so s·r·2⁻ᵖ − s/q = (s/q)(r·m − 1); the
//!   final shift rounds to nearest: |u − s/q| ≤ |s/q|·e + ½ LSB_out. Saturation is a
//!   clamp, which is 1-Lipschitz, so |u − clamp(s/q)| obeys the same bound, and a
//!   quotient beyond a rail by more than the bound reads exactly the rail.
//! * f64 slack (derived, not a fudge): the twin's quotient and the test's difference
//!   are each rounded once in f64: 2⁻⁵²·(2|s/q| + |u|).

mod common;

use glare_pipeline::reference::projective_texcoord::{project, project_codes};
use proptest::prelude::*;
use rtl_model::units::projective_texcoord::{
    recip_rom_entry, ProjLanes, ProjectiveIn, ProjectiveOut, ProjectiveTexcoord,
    ProjectiveTexcoordConfig, SquareClass, SquareCut, SQUARE_BLOCK,
};
use rtl_model::{Counters, Unit, UnitSummary};

#[allow(clippy::too_many_arguments)]
fn cfg(
    in_int: u32,
    in_frac: u32,
    out_int: u32,
    out_frac: u32,
    index: u32,
    entry: u32,
    steps: u32,
    nfrac: u32,
) -> ProjectiveTexcoordConfig {
    ProjectiveTexcoordConfig {
        in_int_bits: in_int,
        in_frac_bits: in_frac,
        out_int_bits: out_int,
        out_frac_bits: out_frac,
        recip_index_bits: index,
        recip_entry_bits: entry,
        newton_steps: steps,
        newton_frac_bits: nfrac,
    }
}

/// The bound configs: the default, a wide one with 2 Newton steps, the narrow one
/// (I = 3, E = 6, out_frac 4, no Newton) and a narrow one with a coarse Newton step.
fn bound_configs() -> Vec<ProjectiveTexcoordConfig> {
    vec![
        ProjectiveTexcoordConfig::geforce(),
        cfg(20, 20, 16, 16, 10, 20, 2, 36),
        cfg(8, 8, 8, 4, 3, 6, 0, 8),
        cfg(6, 6, 6, 4, 3, 6, 1, 8),
    ]
}

fn p2(e: i32) -> f64 {
    (e as f64).exp2()
}

/// Derived bound on |r·m − 1|.
fn recip_bound(c: &ProjectiveTexcoordConfig) -> f64 {
    let (i, e, n) = (
        c.recip_index_bits as i32,
        c.recip_entry_bits as i32,
        c.newton_frac_bits as i32,
    );
    let delta = if e <= i { p2(-e) } else { p2(-(e + 1)) };
    let mut er = p2(-(i + 1)) + 2.0 * delta;
    for _ in 0..c.newton_steps {
        er = er * er + (1.0 + er) * ((1.0 + er) * p2(-n) + p2(-(n + 1))) + p2(-n);
    }
    er
}

/// Exact |r·m − 1| of the unit's reciprocal for Q > 0.
fn recip_error(u: &ProjectiveTexcoord, qmag: u64) -> f64 {
    let mut c = Counters::default();
    let (r, p) = u.reciprocal(qmag, &mut c);
    let fr = u.recip_frac_bits();
    // r·m − 1 = (r_raw·Q − 2^(fr+p)) / 2^(fr+p), numerator exact in i128.
    let num = r as i128 * qmag as i128 - (1i128 << (fr + p));
    (num as f64 / p2((fr + p) as i32)).abs()
}

fn sext(x: i64, w: u32) -> i64 {
    (x << (64 - w)) >> (64 - w)
}

/// Check one input against the twin under the derived bound; returns the number of
/// coordinates that must have saturated and the number at a rail.
fn check(u: &ProjectiveTexcoord, inp: ProjectiveIn) -> (u64, u64) {
    let c = u.config();
    let w = u.in_bits();
    let mut ctr = Counters::default();
    let out = u.kernel(&mut (), &inp, &mut ctr);
    let (s, t, q) = (sext(inp.s, w), sext(inp.t, w), sext(inp.q, w));
    let want = project_codes(s, t, q, c.in_frac_bits);
    if want.behind {
        assert_eq!(
            out,
            ProjectiveOut {
                u: 0,
                v: 0,
                behind: true
            }
        );
        assert_eq!(ctr.underflows, 1);
        assert_eq!(ctr.table_reads + ctr.saturations, 0);
        return (0, 0);
    }
    assert!(!out.behind);
    assert_eq!(ctr.table_reads, 1);
    let er = recip_bound(&c);
    let lsb = p2(-(c.out_frac_bits as i32));
    let f = u.out_format();
    let (lo, hi) = (f.min_raw() as f64 * lsb, f.max_raw() as f64 * lsb);
    let (mut must, mut rail) = (0, 0);
    for (raw, x) in [(out.u, want.u), (out.v, want.v)] {
        let got = u.out_value(raw);
        let bound = x.abs() * er + 0.5 * lsb + p2(-52) * (2.0 * x.abs() + got.abs());
        let err = (got - x.clamp(lo, hi)).abs();
        assert!(
            err <= bound,
            "{c:?}: s,t,q = {s},{t},{q}: got {got}, want {x} (err {err:e} > bound {bound:e})"
        );
        // Beyond a rail by more than the bound: exactly the rail (the clamp).
        if x.abs() * (1.0 - er) > hi.max(-lo) + lsb {
            assert_eq!(got, if x > 0.0 { hi } else { lo });
            must += 1;
        }
        rail += u64::from(got == hi || got == lo);
    }
    assert!(ctr.saturations >= must && ctr.saturations <= rail);
    (must, rail)
}

/// Raw codes spread over all magnitudes (exponent uniform), both signs.
fn code(w: u32) -> impl Strategy<Value = i64> {
    (any::<u64>(), 0u32..64, any::<bool>()).prop_map(move |(x, sh, neg)| {
        let m = (x >> sh) as i64 & ((1i64 << (w - 1)) - 1);
        if neg {
            -m
        } else {
            m
        }
    })
}

#[test]
fn exhaustive_narrow_configs_within_bound() {
    // W = 6 bits: all 2^18 (s, t, q) for each config.
    for c in [cfg(4, 2, 4, 4, 3, 6, 0, 8), cfg(3, 3, 5, 4, 2, 4, 1, 6)] {
        let u = c.build().unwrap();
        let mut sat = 0;
        for q in -32i64..32 {
            for s in -32i64..32 {
                for t in -32i64..32 {
                    sat += check(&u, ProjectiveIn { s, t, q }).0;
                }
            }
        }
        assert!(sat > 0, "the narrow exhaustive run must reach the rails");
    }
}

#[test]
fn reciprocal_error_within_derived_bound_exhaustively() {
    // Every Q of a 20-bit input wire (2^19 magnitudes) for narrow and default tables.
    for c in [
        cfg(10, 10, 8, 4, 3, 6, 0, 8),
        cfg(10, 10, 8, 4, 3, 6, 1, 8),
        cfg(10, 10, 8, 4, 3, 6, 2, 12),
        cfg(10, 10, 4, 12, 8, 16, 0, 20),
        cfg(10, 10, 4, 12, 8, 16, 1, 20),
        cfg(10, 10, 4, 12, 4, 4, 0, 20), // E ≤ I: clamped entry 0
        cfg(10, 10, 4, 12, 1, 1, 2, 30), // the coarsest table
    ] {
        let u = c.build().unwrap();
        let b = recip_bound(&c);
        let mut worst = 0.0f64;
        for qm in 1u64..(1 << 19) {
            let e = recip_error(&u, qm);
            assert!(e <= b, "{c:?}: Q = {qm}: |r·m − 1| = {e:e} > {b:e}");
            worst = worst.max(e);
        }
        println!(
            "I={} E={} steps={} N={}: max |r·m − 1| = {worst:.3e} (bound {b:.3e}, ratio {:.2})",
            c.recip_index_bits,
            c.recip_entry_bits,
            c.newton_steps,
            c.newton_frac_bits,
            worst / b
        );
    }
}

#[test]
fn rom_is_an_integer_function_of_the_config() {
    for (i, e) in [(8u32, 16u32), (3, 6), (1, 1), (12, 24), (4, 4), (10, 20)] {
        let u = cfg(16, 16, 4, 12, i, e, 0, 20).build().unwrap();
        let words = u.rom_words();
        assert_eq!(words.len(), 1 << i);
        assert_eq!(u.rom_bits(), (1u64 << i) * e as u64);
        let p = u.rom_params();
        assert_eq!((p.depth, p.width), (1u64 << i, e));
        for (idx, &wd) in words.iter().enumerate() {
            // Independent integer rounding: quotient, then round half up on the remainder.
            let num = 1u128 << (e + i + 1);
            let den = (1u128 << (i + 1)) + 2 * idx as u128 + 1;
            let (qt, rem) = (num / den, num % den);
            let want = (qt + u128::from(2 * rem >= den)).min((1u128 << e) - 1) as u64;
            assert_eq!(wd, want, "I={i} E={e} entry {idx}");
            assert_eq!(wd, recip_rom_entry(idx as u64, i, e));
            // Within δ_max of 1/c (f64 check of the rounding).
            let cmid = 1.0 + (idx as f64 + 0.5) / p2(i as i32);
            let dmax = if e <= i {
                p2(-(e as i32))
            } else {
                p2(-(e as i32) - 1)
            };
            assert!((wd as f64 / p2(e as i32) - 1.0 / cmid).abs() <= dmax);
        }
    }
    // Golden entries of the default ROM.
    let w = ProjectiveTexcoord::geforce().rom_words();
    assert_eq!((w[0], w[128], w[255]), (65408, 43634, 32800));
}

#[test]
fn behind_and_extreme_inputs() {
    let u = ProjectiveTexcoord::geforce();
    let mut c = Counters::default();
    let max = (1i64 << 31) - 1;
    for q in [0, -1, -max - 1, -65536] {
        let o = u.kernel(&mut (), &ProjectiveIn { s: max, t: -max, q }, &mut c);
        assert_eq!(
            o,
            ProjectiveOut {
                u: 0,
                v: 0,
                behind: true
            }
        );
    }
    assert_eq!((c.underflows, c.table_reads, c.saturations), (4, 0, 0));
    // q = 1 LSB, s = ±max: both coordinates clamp to the rails, counted.
    let mut c = Counters::default();
    let o = u.kernel(
        &mut (),
        &ProjectiveIn {
            s: max,
            t: -max - 1,
            q: 1,
        },
        &mut c,
    );
    assert_eq!((o.u, o.v), (i16::MAX as i32, i16::MIN as i32));
    assert_eq!(c.saturations, 2);
    // q = max, s = 1 LSB: the quotient (2^-31) rounds to 0 and is not a saturation.
    let mut c = Counters::default();
    let o = u.kernel(
        &mut (),
        &ProjectiveIn {
            s: 1,
            t: -1,
            q: max,
        },
        &mut c,
    );
    assert_eq!((o.u, o.v, o.behind), (0, 0, false));
    assert_eq!(c.saturations, 0);
    // Exact quotients: u = 0.75, v = −0.5 at q = 3.
    let mut c = Counters::default();
    let inp = u.quantise_in(2.25, -1.5, 3.0, &mut c).unwrap();
    let o = u.kernel(&mut (), &inp, &mut c);
    assert_eq!((u.out_value(o.u), u.out_value(o.v)), (0.75, -0.5));
    // The twin never returns NaN.
    let r = project(f64::NAN, 1.0, f64::NAN);
    assert!(r.behind && r.u == 0.0);
    let r = project(f64::NAN, 1.0, 2.0);
    assert!(!r.behind && r.u == 0.0 && r.v == 0.5);
}

#[test]
fn nan_and_infinite_host_inputs_name_the_field() {
    let u = ProjectiveTexcoord::geforce();
    let mut c = Counters::default();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let e = |s, t, q| {
            u.quantise_in(s, t, q, &mut Counters::default())
                .unwrap_err()
                .field()
                .to_string()
        };
        assert_eq!(e(bad, 0.0, 1.0), "projective_texcoord.s");
        assert_eq!(e(0.0, bad, 1.0), "projective_texcoord.t");
        assert_eq!(e(0.0, 0.0, bad), "projective_texcoord.q");
    }
    // Out of the s16.16 range: saturated and counted.
    let i = u.quantise_in(1e9, -1e9, 0.5, &mut c).unwrap();
    assert_eq!((i.s, i.t, i.q), ((1 << 31) - 1, -(1 << 31), 32768));
    assert_eq!(c.saturations, 2);
}

#[test]
fn datasheet_numbers_at_defaults() {
    let u = ProjectiveTexcoord::geforce();
    let s = UnitSummary::of(&u);
    println!(
        "projective_texcoord defaults: latency {} II {} gates {:.1} NAND2 rom_bits {} recip bound {:.3e}",
        s.latency,
        s.ii,
        s.gates_nand2,
        s.ram_bits,
        recip_bound(&u.config())
    );
    for (part, g) in &s.breakdown {
        println!("  {part}: {g:.1}");
    }
    for c in bound_configs() {
        let u = c.build().unwrap();
        let s = UnitSummary::of(&u);
        println!(
            "  config {c:?}: latency {} gates {:.1} rom_bits {} e_r {:.3e}",
            s.latency,
            s.gates_nand2,
            s.ram_bits,
            recip_bound(&c)
        );
    }
    assert_eq!((s.latency, s.ii), (6, 1));
    assert_eq!(s.ram_bits, 256 * 16);
}

/// A config field drawn from valid and invalid values.
fn field(lo: u32, hi: u32) -> impl Strategy<Value = u32> {
    prop_oneof![
        4 => lo..=hi,
        1 => Just(lo.wrapping_sub(1)),
        1 => hi..=hi + 3,
        1 => any::<u32>(),
    ]
}

fn random_valid_config() -> impl Strategy<Value = ProjectiveTexcoordConfig> {
    (
        (1u32..=24, 0u32..=24, 1u32..=16, 0u32..=16),
        (1u32..=12, 1u32..=24, 0u32..=2, 1u32..=40),
    )
        .prop_map(|((a, b, c, d), (e, f, g, h))| cfg(a, b, c, d, e, f, g, h))
}

/// Two units built from `a` and `b`, `b` taking `a`'s front end (input width, ROM
/// index and entry bits): a pair the pair form may take.
fn sharing_front_end(
    a: ProjectiveTexcoordConfig,
    b: ProjectiveTexcoordConfig,
) -> (ProjectiveTexcoord, ProjectiveTexcoord) {
    let b = ProjectiveTexcoordConfig {
        in_int_bits: a.in_int_bits,
        in_frac_bits: a.in_frac_bits,
        recip_index_bits: a.recip_index_bits,
        recip_entry_bits: a.recip_entry_bits,
        ..b
    };
    (a.build().unwrap(), b.build().unwrap())
}

/// The shafts frame's depth unit (r/q): s2.16 out, two Newton steps at N = 30.
fn shafts_depth() -> ProjectiveTexcoordConfig {
    ProjectiveTexcoordConfig {
        out_int_bits: 2,
        out_frac_bits: 16,
        newton_steps: 2,
        newton_frac_bits: 30,
        ..ProjectiveTexcoordConfig::geforce()
    }
}

/// `a.kernel_pair_lanes(b, …)` on the lanes [s, t, r, q] at every other index: where
/// the pair form applies, each unit's outputs are those the three drivers give it on
/// its own inputs ((s, t, q) and (r, 0, q)) and its counters the kernel's on them;
/// elsewhere nothing is done.
fn pair_agrees(a: &ProjectiveTexcoord, b: &ProjectiveTexcoord, [s, t, r, q]: [&[i64]; 4]) {
    let idx: Vec<u32> = (0..s.len() as u32).step_by(2).collect();
    let ins = |x: &[i64], y: Option<&[i64]>| -> Vec<ProjectiveIn> {
        idx.iter()
            .map(|&i| {
                let i = i as usize;
                ProjectiveIn {
                    s: x[i],
                    t: y.map_or(0, |y| y[i]),
                    q: q[i],
                }
            })
            .collect()
    };
    let (ins_a, ins_b) = (ins(s, Some(t)), ins(r, None));
    let (mut lanes, mut bu) = (ProjLanes::default(), Vec::new());
    let (mut ca, mut cb) = (Counters::default(), Counters::default());
    let done = a.kernel_pair_lanes(b, [s, t, r, q], &idx, &mut lanes, &mut bu, &mut ca, &mut cb);
    assert_eq!(done, a.pair_lanes_apply(b));
    if !done {
        assert!(lanes.is_empty() && bu.is_empty());
        return;
    }
    let out_a = common::assert_drivers_agree(a, (), &ins_a);
    let out_b = common::assert_drivers_agree(b, (), &ins_b);
    let got_a: Vec<ProjectiveOut> = (0..idx.len())
        .map(|j| ProjectiveOut {
            u: lanes.u[j],
            v: lanes.v[j],
            behind: lanes.behind[j],
        })
        .collect();
    assert_eq!(got_a, out_a);
    assert_eq!(bu, out_b.iter().map(|o| o.u).collect::<Vec<_>>());
    let kernel_ctr = |u: &ProjectiveTexcoord, ins: &[ProjectiveIn]| {
        let mut c = Counters::default();
        for x in ins {
            u.kernel(&mut (), x, &mut c);
        }
        c
    };
    assert_eq!(ca, kernel_ctr(a, &ins_a));
    assert_eq!(cb, kernel_ctr(b, &ins_b));
}

/// The pair form exhaustively at narrow widths (W = 6): every (s, q) with t and r
/// running over the wire too, at pairs that differ in outputs and Newton steps.
#[test]
fn pair_lane_form_exhaustive_at_narrow_widths() {
    let pairs = [
        (cfg(4, 2, 4, 4, 3, 6, 0, 8), cfg(3, 3, 2, 6, 3, 6, 2, 9)),
        (cfg(3, 3, 5, 4, 2, 4, 1, 6), cfg(3, 3, 1, 3, 2, 4, 0, 5)),
    ];
    let (mut s, mut t, mut r, mut q) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for qq in -32i64..32 {
        for ss in -32i64..32 {
            s.push(ss);
            t.push((ss * 7 + qq) % 32);
            r.push(-ss ^ qq);
            q.push(qq);
        }
    }
    for (a, b) in pairs {
        let (a, b) = (a.build().unwrap(), b.build().unwrap());
        assert!(a.pair_lanes_apply(&b), "{a:?} {b:?}");
        pair_agrees(&a, &b, [&s, &t, &r, &q]);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn within_derived_bound_at_default_wide_and_narrow(
        which in 0usize..4,
        s in code(48), t in code(48), q in code(48),
    ) {
        let c = bound_configs()[which];
        let u = c.build().unwrap();
        let w = u.in_bits();
        // Bring the codes into the W-bit wire keeping their spread of magnitudes.
        let fit = |x: i64| x >> (48 - w);
        check(&u, ProjectiveIn { s: fit(s), t: fit(t), q: fit(q) });
    }

    #[test]
    fn within_derived_bound_for_random_valid_configs(
        c in random_valid_config(),
        s in code(48), t in code(48), q in code(48),
    ) {
        let u = c.build().unwrap();
        let w = u.in_bits();
        let fit = |x: i64| x >> (48 - w);
        check(&u, ProjectiveIn { s: fit(s), t: fit(t), q: fit(q) });
    }

    #[test]
    fn tick_and_span_drivers_agree(
        c in random_valid_config(),
        raw in prop::collection::vec((any::<i64>(), any::<i64>(), any::<i64>()), 0..40),
    ) {
        let u = c.build().unwrap();
        // Unmasked words: the unit sign-extends them from its W-bit wires.
        let inputs: Vec<ProjectiveIn> =
            raw.iter().map(|&(s, t, q)| ProjectiveIn { s, t, q }).collect();
        common::assert_drivers_agree(&u, (), &inputs);
    }

    /// The batch kernel's lane form (64-input blocks, used when the 64-bit carriers fit
    /// and F_r > out_frac) at the two configs the shafts frame runs: the light map's
    /// (GeForce defaults, one Newton step) and the depth's (s2.16 out, two steps at
    /// N = 30). Runs longer than a block, q mostly in front of the projector, s and t
    /// over the whole wire (many saturate): identical to the span and tick drivers.
    #[test]
    fn lane_form_agrees_with_the_drivers_at_the_shafts_configs(
        depth in any::<bool>(),
        raw in prop::collection::vec((any::<i32>(), any::<i32>(), -4096i64..(1i64 << 31)), 0..300),
    ) {
        let c = if depth {
            shafts_depth()
        } else {
            ProjectiveTexcoordConfig::geforce()
        };
        let u = c.build().unwrap();
        let inputs: Vec<ProjectiveIn> = raw
            .iter()
            .map(|&(s, t, q)| ProjectiveIn { s: s as i64, t: t as i64, q })
            .collect();
        common::assert_drivers_agree(&u, (), &inputs);
    }

    /// The shared front end of two units dividing by the same q
    /// (`kernel_pair_lanes`, the shafts frame's light map and depth): each unit's
    /// outputs are those the three drivers give it on its own inputs, (s, t, q) and
    /// (r, 0, q) at the chosen indices (some at random, or all), and its counters the
    /// kernel's on them.
    #[test]
    fn pair_lane_form_agrees_with_each_unit_through_the_drivers(
        raw in prop::collection::vec(
            (any::<i32>(), any::<i32>(), any::<i32>(), -4096i64..(1i64 << 31), any::<bool>()),
            0..300,
        ),
        every_index in any::<bool>(),
    ) {
        let a = ProjectiveTexcoordConfig::geforce().build().unwrap();
        let b = shafts_depth().build().unwrap();
        prop_assert!(a.pair_lanes_apply(&b));
        let lane = |k: usize| raw.iter().map(|x| [x.0 as i64, x.1 as i64, x.2 as i64, x.3][k]).collect::<Vec<i64>>();
        let (s, t, r, q) = (lane(0), lane(1), lane(2), lane(3));
        // The chosen indices, or every one (blocks of consecutive indices, read as
        // slices of the lanes).
        let idx: Vec<u32> = (0..raw.len() as u32).filter(|&i| every_index || raw[i as usize].4).collect();
        let ins_a: Vec<ProjectiveIn> = idx.iter().map(|&i| {
            let i = i as usize;
            ProjectiveIn { s: s[i], t: t[i], q: q[i] }
        }).collect();
        let ins_b: Vec<ProjectiveIn> = idx.iter().map(|&i| {
            let i = i as usize;
            ProjectiveIn { s: r[i], t: 0, q: q[i] }
        }).collect();
        let out_a = common::assert_drivers_agree(&a, (), &ins_a);
        let out_b = common::assert_drivers_agree(&b, (), &ins_b);
        let kernel_ctr = |u: &ProjectiveTexcoord, ins: &[ProjectiveIn]| {
            let mut c = Counters::default();
            for x in ins {
                u.kernel(&mut (), x, &mut c);
            }
            c
        };
        let (mut lanes, mut bu) = (ProjLanes::default(), vec![7i32]);
        let (mut ca, mut cb) = (Counters::default(), Counters::default());
        prop_assert!(a.kernel_pair_lanes(&b, [&s, &t, &r, &q], &idx, &mut lanes, &mut bu, &mut ca, &mut cb));
        prop_assert_eq!(lanes.len(), idx.len());
        let got_a: Vec<ProjectiveOut> = (0..idx.len())
            .map(|j| ProjectiveOut { u: lanes.u[j], v: lanes.v[j], behind: lanes.behind[j] })
            .collect();
        prop_assert_eq!(got_a, out_a);
        // Appended after what the vector held.
        prop_assert_eq!(bu[0], 7);
        prop_assert_eq!(&bu[1..], &out_b.iter().map(|o| o.u).collect::<Vec<_>>()[..]);
        prop_assert!(out_b.iter().all(|o| o.v == 0));
        prop_assert_eq!(ca, kernel_ctr(&a, &ins_a));
        prop_assert_eq!(cb, kernel_ctr(&b, &ins_b));
        // Another ROM: not a pair; nothing done.
        let c = ProjectiveTexcoordConfig { recip_index_bits: 7, ..ProjectiveTexcoordConfig::geforce() }
            .build()
            .unwrap();
        let mut none = ProjLanes::default();
        let mut nu = Vec::new();
        prop_assert!(!a.kernel_pair_lanes(&c, [&s, &t, &r, &q], &idx, &mut none, &mut nu, &mut ca, &mut cb));
        prop_assert!(none.is_empty() && nu.is_empty());
    }

    /// The pair form at random pairs of configs that share the front end (W, I, E)
    /// and differ in everything else (outputs, Newton steps and width: the 32-bit
    /// multiplies where W ≤ 32 and N ≤ 30, the 64-bit ones elsewhere), on unmasked
    /// words: each unit's outputs and counters are its own drivers' and kernel's.
    #[test]
    fn pair_lane_form_agrees_at_random_configs(
        a in random_valid_config(),
        b in random_valid_config(),
        raw in prop::collection::vec((any::<i64>(), any::<i64>(), any::<i64>(), any::<i64>()), 0..150),
        wide_q in any::<bool>(),
    ) {
        let (a, b) = sharing_front_end(a, b);
        let w = a.in_bits();
        // q mostly in front of the projector unless `wide_q` (any word).
        let q: Vec<i64> = raw.iter().map(|x| if wide_q { x.3 } else { (x.3 & ((1i64 << (w - 1)) - 1)) >> (x.3 as u64 % 64).min(w as u64 - 1) }).collect();
        pair_agrees(&a, &b, [&raw.iter().map(|x| x.0).collect::<Vec<_>>(), &raw.iter().map(|x| x.1).collect::<Vec<_>>(), &raw.iter().map(|x| x.2).collect::<Vec<_>>(), &q]);
    }

    #[test]
    fn random_configs_never_panic_and_errors_name_the_field(
        a in field(1, 24), b in field(0, 24), c in field(1, 16), d in field(0, 16),
        e in field(1, 12), f in field(1, 24), g in field(0, 2), h in field(1, 40),
    ) {
        let conf = cfg(a, b, c, d, e, f, g, h);
        let checks = [
            ("in_int_bits", a, 1, 24),
            ("in_frac_bits", b, 0, 24),
            ("out_int_bits", c, 1, 16),
            ("out_frac_bits", d, 0, 16),
            ("recip_index_bits", e, 1, 12),
            ("recip_entry_bits", f, 1, 24),
            ("newton_steps", g, 0, 2),
            ("newton_frac_bits", h, 1, 40),
        ];
        let first_bad = checks
            .iter()
            .find(|(_, v, lo, hi)| v < lo || v > hi)
            .map(|(n, ..)| format!("projective_texcoord.{n}"));
        match (conf.build(), first_bad) {
            (Ok(u), None) => {
                let k = u.cost();
                prop_assert!(k.gates_nand2().is_finite() && k.gates_nand2() > 0.0);
                prop_assert_eq!(k.ram_bits, (1u64 << e) * f as u64);
                prop_assert_eq!(u.timing().latency, 4 + 2 * g);
                // The extremes of the input range run without panic.
                let w = u.in_bits();
                let mx = (1i64 << (w - 1)) - 1;
                for (s, q) in [(mx, 1), (-mx - 1, 1), (1, mx), (0, 0), (mx, -1)] {
                    u.kernel(&mut (), &ProjectiveIn { s, t: s, q }, &mut Counters::default());
                }
            }
            (Err(err), Some(fld)) => prop_assert_eq!(err.field(), fld.as_str()),
            (r, fld) => prop_assert!(false, "{:?} vs expected {:?}", r.map(|_| ()), fld),
        }
    }
}

/// `a.kernel_pair_lanes_in_square(b, …)` against the exact pair form on the same
/// lanes (every index): the same counters for both units, the same behind flags, and
/// wherever a code differs, the lane is in front of the projector and outside the
/// unit square on the same side in both (some coordinate below 0 in both, or above
/// 1.0 in both), each coordinate's clamp exactly the kernel's, and no given code
/// larger in magnitude than the exact one. Returns the square form's run.
fn square_form_agrees(
    a: &ProjectiveTexcoord,
    b: &ProjectiveTexcoord,
    lanes: [&[i64]; 4],
) -> SquareRun {
    let idx: Vec<u32> = (0..lanes[0].len() as u32).collect();
    let (mut exact, mut cut) = (ProjLanes::default(), ProjLanes::default());
    let (mut eu, mut cu) = (Vec::new(), Vec::new());
    let (mut ea, mut eb, mut ca, mut cb) = Default::default();
    let done = a.kernel_pair_lanes(b, lanes, &idx, &mut exact, &mut eu, &mut ea, &mut eb);
    let cut_done =
        a.kernel_pair_lanes_in_square(b, lanes, &idx, &mut cut, &mut cu, &mut ca, &mut cb);
    assert_eq!(done, cut_done.is_some());
    let mut run = SquareRun {
        skipped: cut_done,
        differ: 0,
        ctr: ca,
        depth_ctr: cb,
        lanes: ProjLanes::default(),
        depth: Vec::new(),
    };
    if !done {
        assert!(cut.is_empty() && cu.is_empty());
        return run;
    }
    assert_eq!((ea, eb), (ca, cb), "counters");
    assert_eq!(exact.behind, cut.behind);
    let one = 1i32 << a.config().out_frac_bits;
    // One flag per block of SQUARE_BLOCK inputs; the decided blocks hold the skipped
    // inputs, each behind the projector or outside the square in the exact form.
    let n = idx.len();
    assert!(exact.decided.is_empty(), "the exact form decides no block");
    let blocks = if SquareCut::of(a, b).is_some() {
        n.div_ceil(SQUARE_BLOCK)
    } else {
        0 // no cut: nothing decided, no flag
    };
    assert_eq!(
        cut.decided.len(),
        blocks,
        "a flag per block where the cut applies"
    );
    let mut in_decided = 0;
    for (k, _) in cut.decided.iter().enumerate().filter(|(_, &d)| d) {
        for j in k * SQUARE_BLOCK..((k + 1) * SQUARE_BLOCK).min(n) {
            let outside = [exact.u[j], exact.v[j]]
                .iter()
                .any(|c| !(0..=one).contains(c));
            assert!(
                exact.behind[j] || outside,
                "lane {j} of a decided block in the square"
            );
            in_decided += 1;
        }
    }
    assert_eq!(
        Some(in_decided),
        cut_done,
        "the decided blocks' inputs are the skipped ones"
    );
    let clamps = |u: &ProjectiveTexcoord| {
        let f = u.out_format();
        [f.min_raw() as i32, f.max_raw() as i32]
    };
    let (ca_, cb_) = (clamps(a), clamps(b));
    let mut differ = 0;
    for j in 0..idx.len() {
        let (e, c) = ([exact.u[j], exact.v[j]], [cut.u[j], cut.v[j]]);
        if e == c && eu[j] == cu[j] {
            continue;
        }
        differ += 1;
        assert!(!exact.behind[j], "lane {j} behind the projector changed");
        let same_side = (0..2).any(|k| (e[k] < 0 && c[k] < 0) || (e[k] > one && c[k] > one));
        assert!(
            same_side,
            "lane {j}: exact {e:?}, given {c:?}: not outside on one side"
        );
        for k in 0..2 {
            assert_eq!(ca_.contains(&e[k]), ca_.contains(&c[k]), "lane {j} clamp");
            assert!(!ca_.contains(&e[k]) || e[k] == c[k], "lane {j} clamp code");
            assert!(
                c[k].abs() <= e[k].abs(),
                "lane {j}: |{}| > |{}|",
                c[k],
                e[k]
            );
        }
        assert_eq!(
            cb_.contains(&eu[j]),
            cb_.contains(&cu[j]),
            "lane {j} depth clamp"
        );
        assert!(
            !cb_.contains(&eu[j]) || eu[j] == cu[j],
            "lane {j} depth clamp code"
        );
        assert!(cu[j].abs() <= eu[j].abs(), "lane {j} depth magnitude");
    }
    run.differ = differ;
    (run.lanes, run.depth) = (cut, cu);
    run
}

/// [`square_form_agrees`]'s run of the square form: what it returned, the lanes
/// whose codes differ from the exact form's, its counters and outputs.
struct SquareRun {
    skipped: Option<usize>,
    differ: usize,
    ctr: Counters,
    depth_ctr: Counters,
    lanes: ProjLanes,
    depth: Vec<i32>,
}

/// The pair a square-form property runs on: the shafts frame's (where the cut
/// applies) when `frame_pair`, else `a` and `b`; `b` taking `a`'s front end.
fn cut_pair(
    a: ProjectiveTexcoordConfig,
    b: ProjectiveTexcoordConfig,
    frame_pair: bool,
) -> (ProjectiveTexcoord, ProjectiveTexcoord) {
    if frame_pair {
        sharing_front_end(ProjectiveTexcoordConfig::geforce(), shafts_depth())
    } else {
        sharing_front_end(a, b)
    }
}

/// A plane-like block's q on `w`-bit input words: 2^e, at most half the largest
/// word, negative behind the projector.
fn block_q(e: i64, front: bool, w: u32) -> i64 {
    let top = (1i64 << (w - 1)) - 1;
    let q = (1i64 << e.min(w as i64 - 2).max(0)).min(top / 2);
    if front {
        q
    } else {
        -q
    }
}

/// Blocks of 64 lanes from a plane's view of the light, as the shafts frame's light
/// map and depth see them: per block a q and s/q, t/q, r/q ratios (as multiples of
/// 1/16) with a small spread across the block.
fn plane_blocks(blocks: &[(i64, [i64; 3], i64)]) -> [Vec<i64>; 4] {
    let mut l: [Vec<i64>; 4] = Default::default();
    for &(q, ratios, spread) in blocks {
        for j in 0..64i64 {
            let qj = q + j * spread;
            for (lane, x) in l.iter_mut().zip(ratios) {
                lane.push((x * qj) / 16 + j * spread);
            }
            l[3].push(qj);
        }
    }
    l
}

#[test]
fn the_square_form_gives_class_codes_to_a_block_far_outside_and_exact_ones_elsewhere() {
    let (a, b) = (
        ProjectiveTexcoord::geforce(),
        shafts_depth().build().unwrap(),
    );
    let q = 1i64 << 24;
    // Block 0: s/q = −1 (u far below 0), t/q = ½, r/q = ½. Block 1: s/q = ½ (inside
    // the square). Block 2: s/q = 12 (u saturates), t/q = −12 (v saturates), r/q = 3
    // (the depth saturates). Block 3: behind the projector.
    let lanes = plane_blocks(&[
        (q, [-16, 8, 8], 3),
        (q, [8, 8, 8], 3),
        (q, [192, -192, 48], 3),
        (-q, [8, 8, 8], 3),
    ]);
    let lanes = [&lanes[0][..], &lanes[1][..], &lanes[2][..], &lanes[3][..]];
    let run = square_form_agrees(&a, &b, lanes);
    let (cut, cu, ca, cb) = (&run.lanes, &run.depth, run.ctr, run.depth_ctr);
    // Blocks 0, 2 and 3 are skipped; block 1 is not.
    assert_eq!(run.skipped, Some(192));
    // Block 0 takes −1 for u, 0 for v and the depth; the others are exact (block 1 is
    // inside, block 2 is all clamps, block 3 is behind: their codes are the kernel's).
    assert!(cut.u[..64].iter().all(|&u| u == -1));
    assert!(cut.v[..64].iter().chain(&cu[..64]).all(|&c| c == 0));
    assert_eq!(run.differ, 64);
    assert!(cut.u[128..192].iter().all(|&u| u == i16::MAX as i32));
    assert!(cut.v[128..192].iter().all(|&v| v == i16::MIN as i32));
    assert_eq!(ca.saturations, 128);
    assert_eq!(cb.saturations, 64);
    assert_eq!((ca.underflows, cb.underflows), (64, 64));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    /// The bound the square form rests on: wherever `recip_error_bound` gives ε, the
    /// reciprocal of any q is within it (|1 − m·r| ≤ ε, m = q·2⁻ᵖ), at random configs
    /// and words.
    #[test]
    fn the_reciprocal_is_within_its_derived_bound(
        conf in random_valid_config(),
        words in prop::collection::vec(any::<u64>(), 1..200),
    ) {
        let u = conf.build().unwrap();
        let Some(eps) = u.recip_error_bound() else { return Ok(()); };
        prop_assert!(eps <= 1.0 / 16.0);
        let w = u.in_bits();
        for x in words {
            let qmag = (x & ((1u64 << (w - 1)) - 1)) >> (x % 61).min(w.saturating_sub(2) as u64);
            if qmag == 0 {
                continue;
            }
            let mut c = Counters::default();
            let (r, p) = u.reciprocal(qmag, &mut c);
            let m = qmag as f64 / (p as f64).exp2();
            let r = r as f64 / (u.recip_frac_bits() as f64).exp2();
            prop_assert!((1.0 - m * r).abs() <= eps, "q {} m {} r {} eps {}", qmag, m, r, eps);
            prop_assert_eq!(c.saturations, 0);
        }
    }

    /// The square form against the exact pair form at random configs sharing the
    /// front end and on plane-like blocks (far outside, inside, near the edges,
    /// saturating, behind): see `square_form_agrees`.
    #[test]
    fn the_square_form_agrees_with_the_exact_pair_form(
        a in random_valid_config(),
        b in random_valid_config(),
        blocks in prop::collection::vec(
            (0i64..31, prop::array::uniform3(-400i64..400), 0i64..64, any::<bool>()),
            1..6,
        ),
        frame_pair in any::<bool>(),
    ) {
        // Half the cases on the shafts frame's pair, where the cut applies.
        let (a, b) = cut_pair(a, b, frame_pair);
        let w = a.in_bits();
        let blocks: Vec<(i64, [i64; 3], i64)> = blocks
            .iter()
            .map(|&(e, x, spread, front)| (block_q(e, front, w), x, spread))
            .collect();
        // Words past the input width wrap on the wire as the kernel wraps them.
        let lanes = plane_blocks(&blocks);
        square_form_agrees(&a, &b, [&lanes[0], &lanes[1], &lanes[2], &lanes[3]]);
    }
}

/// `cut.range(ranges, w)` against the exact pair form on inputs in the ranges (their
/// corners and `inner`, each coordinate taken within its range): where it gives a
/// class, both units' counters are `count_pair_class` of that class, and every input
/// is behind the projector (all, or none, as the class says) or outside the unit
/// square. Returns the class.
fn range_class_holds(
    a: &ProjectiveTexcoord,
    b: &ProjectiveTexcoord,
    ranges: [(i64, i64); 4],
    inner: &[[u64; 4]],
) -> Option<SquareClass> {
    let cut = SquareCut::of(a, b)?;
    let class = cut.range(ranges, a.in_bits())?;
    let mut lanes: [Vec<i64>; 4] = Default::default();
    let pick = |k: usize, x: u64| {
        let (lo, hi) = ranges[k];
        lo + (x % (hi - lo + 1) as u64) as i64
    };
    for c in 0..16u64 {
        for (k, lane) in lanes.iter_mut().enumerate() {
            let (lo, hi) = ranges[k];
            lane.push(if (c >> k) & 1 == 0 { lo } else { hi });
        }
    }
    for x in inner {
        for (k, lane) in lanes.iter_mut().enumerate() {
            lane.push(pick(k, x[k]));
        }
    }
    let n = lanes[0].len();
    let idx: Vec<u32> = (0..n as u32).collect();
    let (mut out, mut du) = (ProjLanes::default(), Vec::new());
    let (mut ca, mut cb) = (Counters::default(), Counters::default());
    let l = [&lanes[0][..], &lanes[1][..], &lanes[2][..], &lanes[3][..]];
    assert!(a.kernel_pair_lanes(b, l, &idx, &mut out, &mut du, &mut ca, &mut cb));
    let (mut wa, mut wb) = (Counters::default(), Counters::default());
    a.count_pair_class(class, n as u64, &mut wa, &mut wb);
    assert_eq!((ca, cb), (wa, wb), "counters of class {class:?}");
    let one = 1i32 << a.config().out_frac_bits;
    for j in 0..n {
        assert_eq!(out.behind[j], !class.live, "input {j} of class {class:?}");
        let outside = [out.u[j], out.v[j]].iter().any(|c| !(0..=one).contains(c));
        assert!(out.behind[j] || outside, "input {j} in the square");
    }
    Some(class)
}

/// `SquareCut::range` on the shafts frame's pair: ranges far below the square, far
/// outside it with every coordinate saturating, and behind the projector are each
/// one class; ranges reaching into the square, straddling the projector's plane,
/// between certain and uncertain saturation, or leaving the input words are not.
#[test]
fn a_range_of_inputs_is_one_class_only_where_every_input_is() {
    let (a, b) = (
        ProjectiveTexcoord::geforce(),
        shafts_depth().build().unwrap(),
    );
    let q = 1i64 << 24;
    let inner: Vec<[u64; 4]> = (0..64u64)
        .map(|i| [i * 7919, i * 104_729, i * 1_299_709, i * 15_485_863])
        .collect();
    let class = |r: [(i64, i64); 4]| range_class_holds(&a, &b, r, &inner);
    // s/q about −1 (u below 0), t/q and r/q about ½.
    let below = [
        (-q - 99, -q + 99),
        (q / 2, q / 2 + 99),
        (q / 2, q / 2 + 99),
        (q, q + 99),
    ];
    let live = |sats, depth_sats| SquareClass {
        live: true,
        sats,
        depth_sats,
    };
    assert_eq!(class(below), Some(live(0, 0)));
    // s/q = 12, t/q = −12, r/q = 3: every coordinate saturates.
    let far = [
        (12 * q, 12 * q + 99),
        (-12 * q - 99, -12 * q),
        (3 * q, 3 * q + 99),
        (q, q + 99),
    ];
    assert_eq!(class(far), Some(live(2, 1)));
    let behind = [(-q, q), (-q, q), (-q, q), (-q, 0)];
    assert_eq!(class(behind), Some(SquareClass::BEHIND));
    // Reaching into the square (s/q from −1 to ½).
    let into = [(-q, q / 2), (q / 2, q / 2), (q / 2, q / 2), (q, q)];
    assert_eq!(class(into), None);
    // q from −1 to +1: some behind, some in front.
    let straddle = [(-q, -q), (q / 2, q / 2), (q / 2, q / 2), (-q, q)];
    assert_eq!(class(straddle), None);
    // u certainly below 0, but its saturation not certain for all (s/q from −1 to −12).
    let unsure = [(-12 * q, -q), (q / 2, q / 2), (q / 2, q / 2), (q, q)];
    assert_eq!(class(unsure), None);
    // s a little below 0 while q runs from 8 to 2^30: s/q reaches −2/2^30, not
    // certainly below 0 (u's code is then 0).
    let shallow = [(-2, -2), (4, 4), (4, 4), (8, 1 << 30)];
    assert_eq!(class(shallow), None);
    // A range past the input words (read sign-extended, not in order): q past the
    // largest word is negative on the wire, behind the projector.
    let top = (1i64 << (a.in_bits() - 1)) - 1;
    let wrapped = [(-top, -top + 9), (0, 0), (0, 0), (top - 5, top + 5)];
    assert_eq!(class(wrapped), None);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    /// `SquareCut::range` at random ranges (about q·x/16 for ratios x, spreads up to
    /// 2^e) on the shafts frame's pair and on random pairs sharing the front end:
    /// wherever it gives a class, every input in the ranges is of it
    /// (`range_class_holds`).
    #[test]
    fn a_range_class_holds_for_every_input_in_the_ranges(
        a in random_valid_config(),
        b in random_valid_config(),
        e in 0i64..31,
        ratios in prop::array::uniform3(-400i64..400),
        spread in prop::array::uniform4(0u32..40),
        front in any::<bool>(),
        frame_pair in any::<bool>(),
        inner in prop::collection::vec(prop::array::uniform4(any::<u64>()), 16),
    ) {
        let (a, b) = cut_pair(a, b, frame_pair);
        let w = a.in_bits();
        let top = (1i64 << (w - 1)) - 1;
        let q = block_q(e, front, w);
        let range = |x: i64, s: u32| {
            let d = ((1i64 << s.min(w.saturating_sub(2))).min(top / 4) - 1).max(0);
            (x.clamp(-top, top - d), x.clamp(-top, top - d) + d)
        };
        let [xs, xt, xr] = ratios.map(|x| x * q / 16);
        let ranges = [
            range(xs, spread[0]),
            range(xt, spread[1]),
            range(xr, spread[2]),
            range(q, spread[3]),
        ];
        range_class_holds(&a, &b, ranges, &inner);
    }
}
