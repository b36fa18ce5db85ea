//! specular_lookup against its f64 twin (x^s, and the exact interpolant of the table),
//! exhaustive over the input code, under a bound derived from the widths.
//!
//! Bound derivation (also in docs/units.md, `## specular_lookup`), in output LSBs.
//! f(x) = x^s, B = 2^b − 1, N = 2^k − 1, h = 1/N (node spacing), m = magnitude bits
//! of the input (n, or n − 1 signed), x = code/(2^m − 1) the exact input value,
//! p = x·N its exact table position.
//! * Index rounding: the unit's position P/2^w obeys |P/2^w − p| ≤ E_p, with E_p = 0
//!   when m = k (C = 2^(w+m), P = x·2^w exactly) and E_p = 2^−w otherwise
//!   (|C − N·2^(w+m)/M| ≤ ½ and x ≤ M < 2^m give < ½·2^−w; the rounding of P another
//!   ½·2^−w).
//! * Table quantisation: T_j = B·f(j h) + τ_j, |τ_j| ≤ ½ (round half up).
//! * Nearest: i = round(P/2^w), so |i − p| ≤ r = ½ + E_p (r = 0 when m = k: p is an
//!   integer). f is increasing, so B·f(i h) and B·f(x) both lie in
//!   [B·f(x − r h), B·f(x + r h)] (clipped to [0, 1]):
//!   |out − B·f(x)| ≤ ½ + B·(f(x + r h) − f(x − r h)).
//! * Linear: out = round(L_T(p̂)), p̂ = P/2^w, L_T the table's interpolant with the exact
//!   weight of p̂ (the weight IS p̂'s fraction: no weight rounding). Then
//!   out − B·f(x) = [output rounding, ≤ ½] + [L_T − L_{Bf}, a convex combination of τ,
//!   ≤ ½] + B·[L_f(p̂) − f(p̂ h), the interpolation error of x^s between nodes] +
//!   B·[f(p̂ h) − f(x), the index rounding, ≤ f(x + E_p h) − f(x − E_p h)].
//!   The interpolation error on [a, a + h] at fraction φ is f''(ξ)/2 · φ(1 − φ)·h²
//!   (ξ in the interval), f'' = s(s − 1)x^(s−2), whose maximum on an interval is at an
//!   end (right for s ≥ 2, left for 1 < s < 2 — unbounded at 0; 0 for s = 1); φ(1 − φ)
//!   is 1-Lipschitz in φ, so p̂'s fraction gives ≤ φ(1 − φ) + E_p with φ that of p, and
//!   the interval is any node interval meeting [p − E_p, p + E_p]. L_f and f both lie
//!   between the interval's end values (f increasing), so the interpolation error is
//!   also ≤ f(b) − f(a): the bound takes the smaller.
//! * f64 slack: the twin's powf and a few products, relative 2^−50 of B.
//!
//! Sharp exponents: at s = 10⁴, k = b = 8 every entry but the last rounds to 0 (the
//! first non-zero entry would need j/N ≥ (1/(2B))^(1/s) = 0.99938 > 254/255): the
//! lookup is 0 for every code below 255 and 255 at 255 — right, since
//! (254/255)^10⁴·255 = 2·10⁻¹⁵. With a coarse table (k = 4) and linear filtering the
//! last interval smears the highlight into a ramp from 0 to B over x ∈ [14/15, 1]
//! (the interpolation term is then the whole f(1) − f(14/15) ≈ 1: the bound is B + 1,
//! and is reached); nearest keeps a step at x ≥ 14.5/15.

mod common;

use glare_pipeline::reference::specular_lookup::{
    exact_table, input_value, specular, specular_codes, table_interpolant,
};
use proptest::prelude::*;
use rtl_model::units::specular_lookup::{
    specular_table_entry, SpecularLookup, SpecularLookupConfig, SpecularLookupIn,
};
use rtl_model::units::texture_sampler::Filter;
use rtl_model::{Counters, Unit, UnitSummary};

fn cfg(
    k: u32,
    b: u32,
    n: u32,
    signed: bool,
    filter: Filter,
    w: u32,
    s: f64,
) -> SpecularLookupConfig {
    SpecularLookupConfig {
        table_log2: k,
        entry_bits: b,
        in_bits: n,
        signed_input: signed,
        filter,
        weight_bits: w,
        exponent: s,
    }
}

use Filter::{Linear, Nearest};

/// The configurations checked exhaustively (≥ 3, narrow ones included).
fn bound_configs() -> Vec<(&'static str, SpecularLookupConfig)> {
    vec![
        ("default", SpecularLookupConfig::geforce()),
        ("default nearest", cfg(8, 8, 8, false, Nearest, 8, 32.0)),
        ("signed 9-bit", SpecularLookupConfig::geforce_signed()),
        ("NARROW k4 b4 linear", cfg(4, 4, 8, false, Linear, 8, 8.0)),
        ("NARROW k4 b4 nearest", cfg(4, 4, 8, false, Nearest, 8, 8.0)),
        ("narrow w2", cfg(5, 6, 10, false, Linear, 2, 3.5)),
        ("big table k10 b12", cfg(10, 12, 8, false, Linear, 8, 100.0)),
        ("12-bit in, k6", cfg(6, 8, 12, false, Linear, 4, 20.0)),
        ("s = 1", cfg(6, 8, 8, false, Linear, 8, 1.0)),
        ("s = 1.5 (f'' ∞ at 0)", cfg(5, 8, 8, false, Linear, 8, 1.5)),
        ("s = 1e4 default", cfg(8, 8, 8, false, Linear, 8, 1e4)),
        ("s = 1e4 k4 b4 linear", cfg(4, 4, 8, false, Linear, 8, 1e4)),
        (
            "s = 1e4 k4 b4 nearest",
            cfg(4, 4, 8, false, Nearest, 8, 1e4),
        ),
        ("wide k12 b16 n16", cfg(12, 16, 16, false, Linear, 16, 1e4)),
        (
            "wide k12 b16 n16 s64",
            cfg(12, 16, 16, false, Linear, 12, 64.0),
        ),
        (
            "signed 13-bit, k10",
            cfg(10, 10, 13, true, Nearest, 6, 500.0),
        ),
    ]
}

/// E_p: the bound on |P/2^w − p| (index units).
fn index_bound(c: &SpecularLookupConfig) -> f64 {
    if c.magnitude_bits() == c.table_log2 {
        0.0
    } else {
        (-(c.weight_bits as f64)).exp2()
    }
}

fn f_at(x: f64, s: f64) -> f64 {
    specular(x.clamp(0.0, 1.0), s)
}

/// max f'' on [a, b] ⊂ [0, 1] (∞ when 1 < s < 2 and a = 0).
fn max_second_derivative(a: f64, b: f64, s: f64) -> f64 {
    let f2 = |x: f64| {
        if s == 1.0 {
            0.0
        } else if x == 0.0 && s < 2.0 {
            f64::INFINITY
        } else {
            s * (s - 1.0) * x.powf(s - 2.0)
        }
    };
    f2(a).max(f2(b))
}

/// The derived bound on |out − B·x^s| for input value x (output LSBs).
fn bound(c: &SpecularLookupConfig, x: f64) -> f64 {
    let big_b = ((1u64 << c.entry_bits) - 1) as f64;
    let n = ((1u64 << c.table_log2) - 1) as f64;
    let h = 1.0 / n;
    let s = c.exponent;
    let ep = index_bound(c);
    let slack = big_b * 1e-12;
    match c.filter {
        Nearest => {
            let r = if ep == 0.0 { 0.0 } else { 0.5 + ep };
            0.5 + big_b * (f_at(x + r * h, s) - f_at(x - r * h, s)) + slack
        }
        Linear => {
            let p = x * n;
            let lo_node = ((p - ep).floor()).clamp(0.0, n - 1.0);
            let hi_node = ((p + ep).floor() + 1.0).clamp(1.0, n);
            let (a, b) = (lo_node * h, (hi_node * h).min(1.0));
            let phi = p - p.floor();
            let shape = (phi * (1.0 - phi) + ep).min(0.25);
            let interp =
                (0.5 * h * h * max_second_derivative(a, b, s) * shape).min(f_at(b, s) - f_at(a, s));
            let index = f_at(x + ep * h, s) - f_at(x - ep * h, s);
            1.0 + big_b * (interp + index) + slack
        }
    }
}

/// Every input word of the config, in order.
fn all_codes(c: &SpecularLookupConfig) -> Vec<i32> {
    let n = c.in_bits;
    if c.signed_input {
        (-(1i32 << (n - 1))..1i32 << (n - 1)).collect()
    } else {
        (0..1i32 << n).collect()
    }
}

/// Exhaustive check of one config against x^s and against the table's exact
/// interpolant; returns (worst |Δ| vs x^s, worst |Δ|/bound).
fn check_config(c: &SpecularLookupConfig) -> (f64, f64) {
    let u = c.build().unwrap();
    let big_b = ((1u64 << c.entry_bits) - 1) as f64;
    let n = ((1u64 << c.table_log2) - 1) as f64;
    let ep = index_bound(c);
    let table: Vec<f64> = u.table_words().iter().map(|&v| v as f64).collect();
    let linear = c.filter == Linear;
    let (mut worst, mut worst_ratio) = (0.0f64, 0.0f64);
    for code in all_codes(c) {
        let mut ctr = Counters::default();
        let out = u.kernel(&mut (), &SpecularLookupIn { code }, &mut ctr);
        assert!(out as f64 <= big_b, "{c:?}: code {code} → {out}");
        let x = input_value(code as i64, c.in_bits, c.signed_input);
        let want = specular_codes(x, c.entry_bits, c.exponent);
        let err = (out as f64 - want).abs();
        let bd = bound(c, x);
        assert!(
            err <= bd,
            "{c:?}: code {code} (x {x}): out {out}, x^s·B {want}, |Δ| {err} > bound {bd}"
        );
        worst = worst.max(err);
        worst_ratio = worst_ratio.max(err / bd);
        // Against the table's own exact interpolant at the exact position.
        let p = x * n;
        if linear {
            let i = p.floor() as usize;
            let lo = i.saturating_sub(1);
            let hi = (i + 2).min(table.len() - 1);
            let slope = (lo..hi)
                .map(|j| (table[j + 1] - table[j]).abs())
                .fold(0.0, f64::max);
            let d = (out as f64 - table_interpolant(&table, p, true)).abs();
            assert!(
                d <= 0.5 + ep * slope + 1e-9,
                "{c:?}: code {code}: |out − L_T(p)| {d}"
            );
        } else {
            let near: Vec<f64> = [p - ep, p, p + ep]
                .iter()
                .map(|&q| table_interpolant(&table, q, false))
                .collect();
            assert!(
                near.contains(&(out as f64)),
                "{c:?}: code {code}: {out} not a nearest entry {near:?}"
            );
        }
        // Counters: one or two reads; a negative signed word is one clamp.
        assert_eq!(ctr.table_reads, if linear { 2 } else { 1 });
        assert_eq!(ctr.saturations, u64::from(c.signed_input && code < 0));
        assert_eq!(ctr.overflows, 0);
    }
    (worst, worst_ratio)
}

#[test]
fn exhaustive_within_the_derived_bound() {
    for (name, c) in bound_configs() {
        let (worst, ratio) = check_config(&c);
        println!(
            "{name}: worst |Δ| {worst:.3} LSB, worst/bound {ratio:.2}, table bits {}",
            c.build().unwrap().rom_bits()
        );
    }
}

/// The table is the host's formula, and the twin's exact table rounds to it.
#[test]
fn table_is_the_rounded_power() {
    for (_, c) in bound_configs() {
        let u = c.build().unwrap();
        let exact = exact_table(c.table_log2, c.entry_bits, c.exponent);
        for (j, (&t, &e)) in u.table_words().iter().zip(&exact).enumerate() {
            assert!((t as f64 - e).abs() <= 0.5 + 1e-9, "{c:?}: entry {j}");
            assert_eq!(
                t,
                specular_table_entry(j as u64, c.table_log2, c.entry_bits, c.exponent)
            );
        }
        assert_eq!(u.table_words()[0], 0);
        assert_eq!(*u.table_words().last().unwrap(), (1u64 << c.entry_bits) - 1);
    }
}

/// s = 10⁴: the documented behaviour (module notes).
#[test]
fn sharp_exponent_is_a_single_code_highlight() {
    let c = cfg(8, 8, 8, false, Linear, 8, 1e4);
    let u = c.build().unwrap();
    let t = u.table_words();
    assert!(t[..255].iter().all(|&v| v == 0));
    assert_eq!(t[255], 255);
    assert_eq!(u.table_underflows(), 254);
    for code in 0..256 {
        let mut ctr = Counters::default();
        let out = u.lookup(code, &mut ctr);
        assert_eq!(out, if code == 255 { 255 } else { 0 });
        assert_eq!(ctr.underflows, 0);
    }
    // Coarse and linear: a ramp over the last interval, reaching the bound B + 1.
    let c4 = cfg(4, 4, 8, false, Linear, 8, 1e4);
    let u4 = c4.build().unwrap();
    let out = |code: i32| u4.lookup(code, &mut Counters::default());
    assert_eq!(out(238), 0); // 238/255 = 14/15: the node before the last
    assert_eq!(out(255), 15);
    assert!((239..255).all(|c| out(c) <= out(c + 1)));
    assert!(out(247) >= 7);
    // Nearest: a step at x = 14.5/15.
    let n4 = cfg(4, 4, 8, false, Nearest, 8, 1e4).build().unwrap();
    let step = (0..256)
        .find(|&c| n4.lookup(c, &mut Counters::default()) > 0)
        .unwrap();
    assert_eq!(step, 247); // 247/255·15 = 14.53 ≥ 14.5
}

/// Stiff inputs: back-facing (negative signed words), the extremes, words wider than
/// the wires — each a documented result and count, never a panic.
#[test]
fn back_facing_extremes_and_wide_words() {
    let u = SpecularLookup::new(SpecularLookupConfig::geforce_signed()).unwrap();
    let mut ctr = Counters::default();
    assert_eq!(u.lookup(-256, &mut ctr), 0);
    assert_eq!(u.lookup(-1, &mut ctr), 0);
    assert_eq!(ctr.saturations, 2);
    assert_eq!(u.lookup(255, &mut ctr), 255);
    assert_eq!(u.lookup(0, &mut ctr), 0);
    // 300 does not fit 9 signed wires: it wraps to 300 − 512 = −212 → 0, counted.
    let mut ctr = Counters::default();
    assert_eq!(u.lookup(300, &mut ctr), 0);
    assert_eq!((ctr.overflows, ctr.saturations), (1, 1));
    // Unsigned: the low 8 wires of 256 + 255.
    let d = SpecularLookup::geforce();
    let mut ctr = Counters::default();
    assert_eq!(d.lookup(511, &mut ctr), 255);
    assert_eq!(ctr.overflows, 1);
    assert_eq!(d.lookup(i32::MIN, &mut Counters::default()), 0);
}

/// A non-zero interpolant rounded to 0 is an underflow.
#[test]
fn lerp_rounding_to_zero_counts_an_underflow() {
    let c = cfg(2, 4, 8, false, Linear, 8, 1.0);
    let mut u = c.build().unwrap();
    u.load_table(&[0, 1, 2, 15]).unwrap();
    let mut ctr = Counters::default();
    // code 30: p = 30·3/255 = 0.353 → 0 + 1·0.353 rounds to 0.
    assert_eq!(u.lookup(30, &mut ctr), 0);
    assert_eq!(ctr.underflows, 1);
    let mut ctr = Counters::default();
    assert_eq!(u.lookup(60, &mut ctr), 1); // 0.706 → 1
    assert_eq!(ctr.underflows, 0);
}

#[test]
fn defaults_summary_and_costs() {
    let u = SpecularLookup::geforce();
    let s = UnitSummary::of(&u);
    println!(
        "specular_lookup defaults: latency {}, II {}, {:.0} NAND2, {} ROM bits",
        s.latency, s.ii, s.gates_nand2, s.ram_bits
    );
    for (p, g) in &s.breakdown {
        println!("  {p}: {g:.0}");
    }
    assert_eq!((s.latency, s.ii), (4, 1));
    assert_eq!(s.ram_bits, 256 * 8);
    let near = cfg(8, 8, 8, false, Nearest, 8, 32.0).build().unwrap();
    assert_eq!(near.timing().latency, 2);
    for (name, c) in bound_configs() {
        let a = UnitSummary::of(&c.build().unwrap());
        println!(
            "  {name}: {:.0} NAND2, {} ROM bits, latency {}",
            a.gates_nand2, a.ram_bits, a.latency
        );
    }
    // Default: m = k, so no position multiplier; a 10-bit input pays for one.
    assert!(u.position_is_exact());
    let ten = cfg(8, 8, 10, false, Linear, 8, 32.0).build().unwrap();
    assert!(!ten.position_is_exact());
    assert!(UnitSummary::of(&ten).gates_nand2 > s.gates_nand2);
}

#[test]
fn config_errors_name_the_field() {
    let base = SpecularLookupConfig::geforce();
    let cases: Vec<(SpecularLookupConfig, &str)> = vec![
        (
            SpecularLookupConfig {
                table_log2: 0,
                ..base
            },
            "table_log2",
        ),
        (
            SpecularLookupConfig {
                table_log2: 13,
                ..base
            },
            "table_log2",
        ),
        (
            SpecularLookupConfig {
                entry_bits: 0,
                ..base
            },
            "entry_bits",
        ),
        (
            SpecularLookupConfig {
                entry_bits: 17,
                ..base
            },
            "entry_bits",
        ),
        (SpecularLookupConfig { in_bits: 0, ..base }, "in_bits"),
        (
            SpecularLookupConfig {
                in_bits: 17,
                ..base
            },
            "in_bits",
        ),
        (
            SpecularLookupConfig {
                in_bits: 1,
                signed_input: true,
                ..base
            },
            "in_bits",
        ),
        (
            SpecularLookupConfig {
                weight_bits: 0,
                ..base
            },
            "weight_bits",
        ),
        (
            SpecularLookupConfig {
                weight_bits: 17,
                ..base
            },
            "weight_bits",
        ),
        (
            SpecularLookupConfig {
                exponent: 0.5,
                ..base
            },
            "exponent",
        ),
        (
            SpecularLookupConfig {
                exponent: 2e4,
                ..base
            },
            "exponent",
        ),
        (
            SpecularLookupConfig {
                exponent: f64::NAN,
                ..base
            },
            "exponent",
        ),
        (
            SpecularLookupConfig {
                exponent: f64::INFINITY,
                ..base
            },
            "exponent",
        ),
    ];
    for (c, field) in cases {
        let e = c.build().unwrap_err();
        assert_eq!(e.field(), format!("specular_lookup.{field}"), "{c:?}");
    }
    let mut u = SpecularLookup::geforce();
    let before = u.table_words();
    assert_eq!(
        u.load_table(&[0; 10]).unwrap_err().field(),
        "specular_lookup.table"
    );
    assert_eq!(
        u.load_table(&[256; 256]).unwrap_err().field(),
        "specular_lookup.table"
    );
    assert_eq!(u.table_words(), before);
}

fn valid_cfg() -> impl Strategy<Value = SpecularLookupConfig> {
    (
        1u32..=12,
        1u32..=16,
        (any::<bool>(), 1u32..=16),
        any::<bool>(),
        1u32..=16,
        1.0f64..=1e4,
    )
        .prop_map(|(k, b, (signed, n), lin, w, s)| SpecularLookupConfig {
            table_log2: k,
            entry_bits: b,
            in_bits: n + u32::from(signed),
            signed_input: signed,
            filter: if lin { Linear } else { Nearest },
            weight_bits: w,
            exponent: s,
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn tick_and_span_drivers_agree(
        c in valid_cfg(),
        codes in prop::collection::vec(any::<i32>(), 0..24),
    ) {
        let u = c.build().unwrap();
        let inputs: Vec<SpecularLookupIn> =
            codes.iter().map(|&code| SpecularLookupIn { code }).collect();
        common::assert_drivers_agree(&u, (), &inputs);
    }

    /// Random valid configs and in-range words: within the derived bound.
    #[test]
    fn random_configs_within_bound(c in valid_cfg(), r in any::<u32>()) {
        let u = c.build().unwrap();
        let n = c.in_bits;
        let code = if c.signed_input {
            (r as i64 % (1i64 << n) - (1i64 << (n - 1))) as i32
        } else {
            (r as u64 % (1u64 << n)) as i32
        };
        let out = u.lookup(code, &mut Counters::default());
        let x = input_value(code as i64, n, c.signed_input);
        let err = (out as f64 - specular_codes(x, c.entry_bits, c.exponent)).abs();
        prop_assert!(err <= bound(&c, x), "{c:?} code {code}: {out}, |Δ| {err}");
    }

    #[test]
    fn random_configs_never_panic_and_errors_name_the_field(
        k in 0u32..40, b in 0u32..40, n in 0u32..40, signed in any::<bool>(),
        lin in any::<bool>(), w in 0u32..40,
        s in prop_oneof![any::<f64>(), -10.0f64..2e4], code in any::<i32>(),
    ) {
        let c = SpecularLookupConfig {
            table_log2: k, entry_bits: b, in_bits: n, signed_input: signed,
            filter: if lin { Linear } else { Nearest }, weight_bits: w, exponent: s,
        };
        match c.build() {
            Ok(u) => {
                let inp = SpecularLookupIn { code };
                let o = u.kernel(&mut (), &inp, &mut Counters::default());
                prop_assert!(o < 1 << b);
                let _ = u.cost();
                let _ = u.in_signals(&inp);
                let _ = u.out_signals(&o);
            }
            Err(e) => prop_assert!(
                e.field().starts_with("specular_lookup."),
                "field {}",
                e.field()
            ),
        }
    }

    #[test]
    fn twin_never_nan(x in any::<f64>(), s in any::<f64>(), p in any::<f64>(), lin in any::<bool>()) {
        let v = specular(x, s);
        prop_assert!((0.0..=1.0).contains(&v), "{v}");
        let t = exact_table(3, 8, 7.0);
        prop_assert!(table_interpolant(&t, p, lin).is_finite());
        prop_assert_eq!(table_interpolant(&[], p, lin), 0.0);
    }
}
