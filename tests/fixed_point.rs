//! The runtime fixed-point core (`rtl_model::fixed_point`) against the `fixed` crate
//! and against an independent exact model.
//!
//! Requirement: "The runtime fixed-point core agrees with the `fixed` crate for every
//! format that crate can express, for add, sub, mul and conversion, in each
//! quantisation and overflow mode both support."
//!
//! The core stores widths 1..=63, so the overlap is `FixedI8/U8/I16/U16/I32/U32<Frac>`
//! with every `Frac` in 0..=W: 118 types, all instantiated by `push_types!` below.
//! What each `fixed` operation does was read from fixed-1.31.0's source:
//!
//! | `fixed` operation                               | rounding            | core                    |
//! |-------------------------------------------------|---------------------|-------------------------|
//! | `wrapping_/saturating_/checked_add`, `_sub`      | exact               | `add`/`sub`, any `Quant`, `Wrap`/`Sat` |
//! | `wrapping_/saturating_/checked_mul`              | floor (`arith.rs`: `(a·(b≪I))≫W`) | `mul` + `Trn`, `Wrap`/`Sat` |
//! | `{wrapping,saturating,checked}_from_num(fixed)`  | floor (extra fraction bits discarded) | `assign` + `Trn` |
//! | `{wrapping,saturating,checked}_from_num(f64)`    | nearest, ties even  | `Fx::from_f64` + `RndConv` |
//! | `round` / `round_ties_even` / `round_to_zero` / `floor` (+ `wrapping_`, `saturating_`, `checked_`) | to an integer in the same type | `RndInf` / `RndConv` / `TrnZero` / `Trn`, then back |
//!
//! `checked_* == None` is the core's overflow event: `Counters::overflows` (wrap) or
//! `Counters::saturations` (sat). `ceil` has no core mode (no "toward +∞"), so it is
//! not compared. Every (Quant, Overflow) pair the crate lacks — `Rnd`, `RndZero`,
//! `RndMinInf`, `SatZero`, `SatSym`, and all pairs off the table above — is compared,
//! on the same values, with [`model`], which computes exactly in sign–magnitude
//! integer arithmetic and shares no arithmetic with the core (only its data types).
//!
//! The signed all-fraction types (`FixedI8<U8>`, `FixedI16<U16>`, `FixedI32<U32>`,
//! range [−½, ½)) have `int_bits = 0`; `Format::new` refuses a signed format without
//! a sign bit, so those formats are built as struct literals here: the arithmetic
//! agrees with the crate for them too.

mod common;

use fixed::traits::Fixed;
use fixed::types::extra::*;
use fixed::{FixedI16, FixedI32, FixedI8, FixedU16, FixedU32, FixedU8};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use rtl_model::fixed_point::{
    round_shift, wrap, AssignEvents, Format, Fx, Overflow, Quant, MAX_STORED_WIDTH,
};
use rtl_model::{ConfigError, Counters};

// ---------------------------------------------------------------------------------
// The independent exact model.
// ---------------------------------------------------------------------------------

mod model {
    use super::{AssignEvents, Format, Overflow, Quant};
    use std::cmp::Ordering;

    /// `[lo, hi]` of a format, from its width alone.
    pub fn range(f: Format) -> (i128, i128) {
        let w = f.int_bits + f.frac_bits;
        if f.signed {
            (-(1i128 << (w - 1)), (1i128 << (w - 1)) - 1)
        } else {
            (0, (1i128 << w) - 1)
        }
    }

    /// The low `w` bits of a two's-complement pattern, read as a `w`-bit code.
    pub fn wrap_low(low: u128, w: u32, signed: bool) -> i128 {
        let m = low & ((1u128 << w) - 1);
        if signed && (m >> (w - 1)) & 1 == 1 {
            m as i128 - (1i128 << w)
        } else {
            m as i128
        }
    }

    fn with_sign(neg: bool, mag: u128) -> i128 {
        if neg {
            (mag as i128).wrapping_neg()
        } else {
            mag as i128
        }
    }

    /// `num / 2^s` rounded by `q`, computed on sign and magnitude: the magnitude's
    /// integer part `fl` is "toward zero", `fl + 1` is "away from zero", and each
    /// mode picks one by the sign and by the remainder against one half.
    pub fn round_pow2(num: i128, s: u32, q: Quant) -> i128 {
        if s == 0 {
            return num;
        }
        let neg = num < 0;
        let m = num.unsigned_abs();
        let (fl, rem) = if s >= 128 {
            (0u128, m)
        } else {
            (m >> s, m & ((1u128 << s) - 1))
        };
        if rem == 0 {
            return with_sign(neg, fl);
        }
        let vs_half = if s > 128 {
            Ordering::Less
        } else {
            rem.cmp(&(1u128 << (s - 1)))
        };
        let away = match q {
            Quant::Trn => neg,
            Quant::TrnZero => false,
            _ => match vs_half {
                Ordering::Less => false,
                Ordering::Greater => true,
                Ordering::Equal => match q {
                    Quant::Rnd => !neg,
                    Quant::RndZero => false,
                    Quant::RndInf => true,
                    Quant::RndMinInf => neg,
                    Quant::RndConv => fl & 1 == 1,
                    Quant::Trn | Quant::TrnZero => unreachable!(),
                },
            },
        };
        with_sign(neg, if away { fl + 1 } else { fl })
    }

    /// Assign the exact value `num · 2^(lshift − dst.frac_bits)` — i.e. `num` scaled so
    /// that shifting it left by `lshift` (right when negative) gives `dst` codes — to
    /// `dst` with modes `q`, `o`. Returns the code and the events.
    pub fn assign_scaled(
        num: i128,
        lshift: i64,
        dst: Format,
        q: Quant,
        o: Overflow,
    ) -> (i128, AssignEvents) {
        let (lo, hi) = range(dst);
        let w = dst.int_bits + dst.frac_bits;
        // `v`: the rounded code if it fits an i128; `low`: the code mod 2^128.
        let (v, low): (Option<i128>, u128) = if lshift >= 0 {
            let d = lshift as u32;
            let v = if num == 0 {
                Some(0)
            } else if d < 127 {
                num.checked_mul(1i128 << d)
            } else {
                None
            };
            let low = if d >= 128 { 0 } else { (num as u128) << d };
            (v, low)
        } else {
            let s = u32::try_from(-lshift).unwrap_or(u32::MAX);
            let r = round_pow2(num, s, q);
            (Some(r), r as u128)
        };
        let neg = num < 0;
        let mut ev = AssignEvents {
            underflowed: num != 0 && v == Some(0),
            ..AssignEvents::default()
        };
        let fits = |l: i128| matches!(v, Some(x) if x >= l && x <= hi);
        let raw = match o {
            Overflow::Wrap => {
                if fits(lo) {
                    v.unwrap()
                } else {
                    ev.wrapped = true;
                    wrap_low(low, w, dst.signed)
                }
            }
            Overflow::Sat => {
                if fits(lo) {
                    v.unwrap()
                } else {
                    ev.saturated = true;
                    if neg {
                        lo
                    } else {
                        hi
                    }
                }
            }
            Overflow::SatZero => {
                if fits(lo) {
                    v.unwrap()
                } else {
                    ev.saturated = true;
                    0
                }
            }
            Overflow::SatSym => {
                let sym_lo = if dst.signed { -hi } else { lo };
                if fits(sym_lo) {
                    v.unwrap()
                } else {
                    ev.saturated = true;
                    if neg {
                        sym_lo
                    } else {
                        hi
                    }
                }
            }
        };
        (raw, ev)
    }

    /// Assign the exact value `num · 2^−src_frac` to `dst`.
    pub fn assign(
        num: i128,
        src_frac: u32,
        dst: Format,
        q: Quant,
        o: Overflow,
    ) -> (i128, AssignEvents) {
        assign_scaled(num, dst.frac_bits as i64 - src_frac as i64, dst, q, o)
    }

    /// A finite f64 as `mant · 2^exp` (exact), from its bit pattern.
    pub fn f64_parts(x: f64) -> (i128, i64) {
        let b = x.to_bits();
        let e = ((b >> 52) & 0x7ff) as i64;
        let f = (b & ((1u64 << 52) - 1)) as i128;
        let (m, e2) = if e == 0 {
            (f, -1074)
        } else {
            (f | (1i128 << 52), e - 1075)
        };
        (if x < 0.0 { -m } else { m }, e2)
    }

    /// Quantise the exact value of a finite f64 into `dst`.
    pub fn from_f64(x: f64, dst: Format, q: Quant, o: Overflow) -> (i128, AssignEvents) {
        let (m, e) = f64_parts(x);
        assign_scaled(m, e + dst.frac_bits as i64, dst, q, o)
    }
}

// ---------------------------------------------------------------------------------
// Comparing the core with the model and with expected `fixed` results.
// ---------------------------------------------------------------------------------

fn counted(ev: AssignEvents) -> (u64, u64, u64) {
    (
        u64::from(ev.saturated),
        u64::from(ev.wrapped),
        u64::from(ev.underflowed),
    )
}

fn ctr_triple(c: &Counters) -> (u64, u64, u64) {
    (c.saturations, c.overflows, c.underflows)
}

/// `x` has exactly the value `num · 2^−frac`.
fn same_value(x: Fx, num: i128, frac: u32) -> bool {
    let f = x.fmt.frac_bits.max(frac);
    let a = x.raw.checked_mul(1i128 << (f - x.fmt.frac_bits));
    let b = num.checked_mul(1i128 << (f - frac));
    a.is_some() && a == b
}

/// The core's `assign` of `x` (whose exact value is `num · 2^−frac`) to `dst` equals
/// the model in value, format, events and counters, for every quantisation and
/// overflow mode.
fn check_all_modes(
    x: Fx,
    num: i128,
    frac: u32,
    dst: Format,
    what: &str,
) -> Result<(), TestCaseError> {
    prop_assert!(
        same_value(x, num, frac),
        "{what}: {x:?} is not {num}·2^-{frac}"
    );
    for q in Quant::ALL {
        for o in Overflow::ALL {
            let (want, want_ev) = model::assign(num, frac, dst, q, o);
            let mut c = Counters::default();
            let got = x.assign(dst, q, o, &mut c);
            let (got2, ev) = x.assign_events(dst, q, o);
            prop_assert_eq!(got, got2);
            prop_assert_eq!(
                (got.raw, got.fmt),
                (want, dst),
                "{} {:?} → {} {:?} {:?}",
                what,
                x,
                dst,
                q,
                o
            );
            prop_assert_eq!(
                ev,
                want_ev,
                "{} events {:?} → {} {:?} {:?}",
                what,
                x,
                dst,
                q,
                o
            );
            prop_assert_eq!(ctr_triple(&c), counted(want_ev), "{} counters", what);
        }
    }
    Ok(())
}

/// The core gives `want_raw` for `x → dst` under `(q, o)` (o is Wrap or Sat) and counts
/// one overflow event exactly when the `fixed` crate's `checked_*` said `None`.
fn expect_fixed(
    x: Fx,
    dst: Format,
    q: Quant,
    o: Overflow,
    want_raw: i128,
    want_overflow: bool,
    what: &str,
) -> Result<(), TestCaseError> {
    let mut c = Counters::default();
    let got = x.assign(dst, q, o, &mut c);
    prop_assert_eq!(
        got.raw,
        want_raw,
        "{}: core {:?} → {} {:?} {:?} differs from fixed",
        what,
        x,
        dst,
        q,
        o
    );
    let (sat, wrapped) = match o {
        Overflow::Wrap => (0, u64::from(want_overflow)),
        _ => (u64::from(want_overflow), 0),
    };
    prop_assert_eq!(
        (c.saturations, c.overflows),
        (sat, wrapped),
        "{}: {:?} → {} {:?} {:?} events",
        what,
        x,
        dst,
        q,
        o
    );
    Ok(())
}

// ---------------------------------------------------------------------------------
// Random inputs, biased toward the codes where rounding and overflow decide.
// ---------------------------------------------------------------------------------

/// A raw code, realised per format: any bit pattern, or an edge (0, min, max, ±½, ±1,
/// max/2) plus a small offset, wrapped to the format's width.
#[derive(Clone, Copy, Debug)]
enum Word {
    Any(u64),
    Edge(u8, i8),
}

fn word() -> impl Strategy<Value = Word> {
    prop_oneof![
        3 => any::<u64>().prop_map(Word::Any),
        2 => (0u8..7, -2i8..=2).prop_map(|(k, d)| Word::Edge(k, d)),
    ]
}

/// The code `w` stands for in a format of `bits` bits (≥ the format's width to reach
/// beyond its range), `frac` fraction bits.
fn realize_bits(w: Word, bits: u32, frac: u32, signed: bool) -> i128 {
    let lo = if signed { -(1i128 << (bits - 1)) } else { 0 };
    let hi = if signed {
        (1i128 << (bits - 1)) - 1
    } else {
        (1i128 << bits) - 1
    };
    let one = 1i128 << frac;
    let base = match w {
        Word::Any(u) => u as i128,
        Word::Edge(k, d) => {
            let b = match k {
                0 => 0,
                1 => lo,
                2 => hi,
                3 => one >> 1,
                4 => -(one >> 1),
                5 => one,
                _ => -one,
            };
            b + d as i128
        }
    };
    model::wrap_low(base as u128, bits, signed)
}

fn realize(w: Word, f: Format) -> i128 {
    realize_bits(w, f.int_bits + f.frac_bits, f.frac_bits, f.signed)
}

/// An f64 input: any finite bit pattern, or a code of the format (or up to 2 bits
/// beyond it) plus a fraction of an LSB: 0, ½ (a tie), ¼, ¾ or k/2¹⁶.
#[derive(Clone, Copy, Debug)]
enum FGen {
    Bits(u64),
    Grid(Word, u8, u16),
}

fn fgen() -> impl Strategy<Value = FGen> {
    prop_oneof![
        1 => any::<u64>().prop_map(FGen::Bits),
        3 => (word(), 0u8..5, any::<u16>()).prop_map(|(w, t, k)| FGen::Grid(w, t, k)),
    ]
}

fn realize_f64(g: FGen, f: Format) -> f64 {
    match g {
        FGen::Bits(u) => {
            let x = f64::from_bits(u);
            if x.is_finite() {
                x
            } else {
                // Keep the sign and mantissa, use the largest finite exponent.
                f64::from_bits(u & !(1u64 << 52))
            }
        }
        FGen::Grid(w, t, k) => {
            let code = realize_bits(w, f.int_bits + f.frac_bits + 2, f.frac_bits, f.signed);
            let sixteenths: i128 = match t {
                0 => 0,
                1 => 1 << 15,
                2 => 1 << 14,
                3 => 3 << 14,
                _ => k as i128,
            };
            // For the `fixed` types |code| < 2³⁴, so code·2¹⁶ + k < 2⁵⁰ is exact in an
            // f64; wider stored formats get the nearest f64 (the model reads it exactly).
            let n = (code << 16) + sixteenths;
            n as f64 * (-((f.frac_bits + 16) as f64)).exp2()
        }
    }
}

// ---------------------------------------------------------------------------------
// The `fixed` types: one table entry per type.
// ---------------------------------------------------------------------------------

type Check = Result<(), TestCaseError>;

/// What the `fixed` crate gives for one operation, as raw codes.
#[derive(Clone, Copy, Debug, PartialEq)]
struct CrateOp {
    wrapping: i128,
    saturating: i128,
    checked: Option<i128>,
    /// The plain operation (`+`, `*`, `round()`, `from_num`…), called only when the
    /// result fits: it panics on overflow with debug assertions.
    plain: Option<i128>,
}

/// One `fixed` type. Only the `crate_*` functions are generic (one instance per type,
/// and 118 × 8 × 2 for conversions), so they stay small; all checking is shared.
struct Ty {
    name: String,
    fmt: Format,
    add_sub: fn(i128, i128) -> [CrateOp; 2],
    mul: fn(i128, i128) -> CrateOp,
    /// round, round_ties_even, floor; and round_to_zero.
    round: fn(i128) -> ([CrateOp; 3], i128),
    from_f64: fn(f64) -> CrateOp,
    /// Conversions to and from the partner type `k`, via `conv_with_rep`.
    conv: fn(&Ty, usize, Word, Word) -> Check,
}

fn fmt_of<F: Fixed>() -> Format {
    // ap_fixed<W, I>: a signed type's integer bits include the sign bit, as in `fixed`.
    Format {
        int_bits: F::INT_NBITS,
        frac_bits: F::FRAC_NBITS,
        signed: F::IS_SIGNED,
    }
}

/// `FixedI16<U3>` for s13.3.
fn label(f: Format) -> String {
    let s = if f.signed { "I" } else { "U" };
    format!("Fixed{s}{}<U{}>", f.width(), f.frac_bits)
}

fn from_raw<F: Fixed>(raw: i128) -> F {
    F::from_bits(
        <F::Bits as TryFrom<i128>>::try_from(raw)
            .ok()
            .expect("code in range"),
    )
}

fn raw_of<F: Fixed>(x: F) -> i128 {
    <F::Bits as TryInto<i128>>::try_into(x.to_bits())
        .ok()
        .expect("bits fit i128")
}

fn ty<F: Fixed>() -> Ty {
    Ty {
        name: label(fmt_of::<F>()),
        fmt: fmt_of::<F>(),
        add_sub: crate_add_sub::<F>,
        mul: crate_mul::<F>,
        round: crate_round::<F>,
        from_f64: crate_from_f64::<F>,
        conv: conv_with_rep::<F>,
    }
}

macro_rules! push_types {
    ($v:ident, $T:ident; $($U:ident)*) => { $( $v.push(ty::<$T<$U>>()); )* };
}

#[allow(clippy::vec_init_then_push)]
fn types() -> Vec<Ty> {
    let mut v = Vec::new();
    push_types!(v, FixedI8; U0 U1 U2 U3 U4 U5 U6 U7 U8);
    push_types!(v, FixedU8; U0 U1 U2 U3 U4 U5 U6 U7 U8);
    push_types!(v, FixedI16; U0 U1 U2 U3 U4 U5 U6 U7 U8 U9 U10 U11 U12 U13 U14 U15 U16);
    push_types!(v, FixedU16; U0 U1 U2 U3 U4 U5 U6 U7 U8 U9 U10 U11 U12 U13 U14 U15 U16);
    push_types!(v, FixedI32; U0 U1 U2 U3 U4 U5 U6 U7 U8 U9 U10 U11 U12 U13 U14 U15 U16
        U17 U18 U19 U20 U21 U22 U23 U24 U25 U26 U27 U28 U29 U30 U31 U32);
    push_types!(v, FixedU32; U0 U1 U2 U3 U4 U5 U6 U7 U8 U9 U10 U11 U12 U13 U14 U15 U16
        U17 U18 U19 U20 U21 U22 U23 U24 U25 U26 U27 U28 U29 U30 U31 U32);
    v
}

const N_TYPES: usize = 2 * (9 + 17 + 33);

fn crate_op<F: Fixed>(w: F, s: F, c: Option<F>, plain: impl FnOnce() -> F) -> CrateOp {
    CrateOp {
        wrapping: raw_of(w),
        saturating: raw_of(s),
        checked: c.map(raw_of),
        plain: c.map(|_| raw_of(plain())),
    }
}

fn crate_add_sub<F: Fixed>(a: i128, b: i128) -> [CrateOp; 2] {
    let (a, b) = (from_raw::<F>(a), from_raw::<F>(b));
    [
        crate_op(
            a.wrapping_add(b),
            a.saturating_add(b),
            a.checked_add(b),
            || a + b,
        ),
        crate_op(
            a.wrapping_sub(b),
            a.saturating_sub(b),
            a.checked_sub(b),
            || a - b,
        ),
    ]
}

fn crate_mul<F: Fixed>(a: i128, b: i128) -> CrateOp {
    let (a, b) = (from_raw::<F>(a), from_raw::<F>(b));
    crate_op(
        a.wrapping_mul(b),
        a.saturating_mul(b),
        a.checked_mul(b),
        || a * b,
    )
}

fn crate_round<F: Fixed>(a: i128) -> ([CrateOp; 3], i128) {
    let a = from_raw::<F>(a);
    (
        [
            crate_op(
                a.wrapping_round(),
                a.saturating_round(),
                a.checked_round(),
                || a.round(),
            ),
            crate_op(
                a.wrapping_round_ties_even(),
                a.saturating_round_ties_even(),
                a.checked_round_ties_even(),
                || a.round_ties_even(),
            ),
            crate_op(
                a.wrapping_floor(),
                a.saturating_floor(),
                a.checked_floor(),
                || a.floor(),
            ),
        ],
        raw_of(a.round_to_zero()),
    )
}

fn crate_from_f64<F: Fixed>(x: f64) -> CrateOp {
    crate_op(
        F::wrapping_from_num(x),
        F::saturating_from_num(x),
        F::checked_from_num(x),
        || F::from_num(x),
    )
}

/// The core gives the crate's codes for `x → dst` with `q`: `wrapping` under Wrap,
/// `saturating` under Sat, one event exactly when `checked` is None, and `plain`
/// equals `checked`.
fn expect_crate(x: Fx, dst: Format, q: Quant, c: CrateOp, what: &str) -> Check {
    let over = c.checked.is_none();
    expect_fixed(x, dst, q, Overflow::Wrap, c.wrapping, over, what)?;
    expect_fixed(x, dst, q, Overflow::Sat, c.saturating, over, what)?;
    prop_assert_eq!(c.plain, c.checked, "{}: plain", what);
    if let Some(v) = c.checked {
        prop_assert_eq!(v, c.wrapping, "{}: checked", what);
    }
    Ok(())
}

/// add and sub: wrapping ↔ Wrap, saturating ↔ Sat, checked None ↔ the event; the
/// result needs no rounding, so every Quant mode must give the same code.
fn check_add_sub(t: &Ty, wa: Word, wb: Word) -> Check {
    let (a, b) = (realize(wa, t.fmt), realize(wb, t.fmt));
    let (xa, xb) = (Fx::from_raw(a, t.fmt), Fx::from_raw(b, t.fmt));
    let [c_add, c_sub] = (t.add_sub)(a, b);
    for (op, exact, num, c) in [
        ("add", xa.add(xb), a + b, c_add),
        ("sub", xa.sub(xb), a - b, c_sub),
    ] {
        let what = format!("{} {op} {a} {b}", t.name);
        let (lo, hi) = model::range(exact.fmt);
        prop_assert!(
            exact.raw >= lo && exact.raw <= hi,
            "{what}: {exact:?} not full precision"
        );
        for q in Quant::ALL {
            expect_crate(exact, t.fmt, q, c, &what)?;
        }
        if let Some(v) = c.checked {
            prop_assert_eq!(v, num, "{}: checked", what);
        }
        check_all_modes(exact, num, t.fmt.frac_bits, t.fmt, &what)?;
    }
    Ok(())
}

/// mul: the crate floors the double-width product (Trn); wrapping ↔ Wrap,
/// saturating ↔ Sat, checked None ↔ the event.
fn check_mul(t: &Ty, wa: Word, wb: Word) -> Check {
    let (a, b) = (realize(wa, t.fmt), realize(wb, t.fmt));
    let exact = Fx::from_raw(a, t.fmt).mul(Fx::from_raw(b, t.fmt));
    let what = format!("{} mul {a} {b}", t.name);
    expect_crate(exact, t.fmt, Quant::Trn, (t.mul)(a, b), &what)?;
    check_all_modes(exact, a * b, 2 * t.fmt.frac_bits, t.fmt, &what)
}

/// Rounding to an integer of the same type: the core rounds into a wide integer format
/// (it never overflows there) and assigns that back with Wrap or Sat.
fn check_round(t: &Ty, wa: Word) -> Check {
    let a = realize(wa, t.fmt);
    let x = Fx::from_raw(a, t.fmt);
    let what = format!("{} round {a}", t.name);
    let int = Format {
        int_bits: t.fmt.width() + 1,
        frac_bits: 0,
        signed: true,
    };
    let to_int = |q: Quant| -> Result<Fx, TestCaseError> {
        let mut c = Counters::default();
        let n = x.assign(int, q, Overflow::Wrap, &mut c);
        prop_assert_eq!((c.saturations, c.overflows), (0, 0), "{}: to int", what);
        Ok(n)
    };
    let (ops, to_zero) = (t.round)(a);
    let names = [
        (Quant::RndInf, "round"),
        (Quant::RndConv, "round_ties_even"),
        (Quant::Trn, "floor"),
    ];
    for ((q, name), c) in names.into_iter().zip(ops) {
        expect_crate(to_int(q)?, t.fmt, Quant::Trn, c, &format!("{what} {name}"))?;
    }
    // round_to_zero never overflows.
    let n = to_int(Quant::TrnZero)?;
    expect_fixed(n, t.fmt, Quant::Trn, Overflow::Wrap, to_zero, false, &what)?;
    // Every mode to an integer and back, against the model.
    for q in Quant::ALL {
        let n = to_int(q)?;
        let (want, _) = model::assign(a, t.fmt.frac_bits, int, q, Overflow::Wrap);
        prop_assert_eq!(n.raw, want, "{} {:?}", what, q);
        check_all_modes(n, want, 0, t.fmt, &what)?;
    }
    Ok(())
}

/// f64 → fixed: the crate rounds to nearest, ties to even (RndConv).
fn check_from_f64(t: &Ty, g: FGen) -> Check {
    let x = realize_f64(g, t.fmt);
    let what = format!("{} from_f64 {x:e} ({g:?})", t.name);
    let c = (t.from_f64)(x);
    let over = c.checked.is_none();
    for (o, want) in [(Overflow::Wrap, c.wrapping), (Overflow::Sat, c.saturating)] {
        let mut ctr = Counters::default();
        let got = Fx::from_f64(x, t.fmt, Quant::RndConv, o, "x", &mut ctr).unwrap();
        prop_assert_eq!((got.raw, got.fmt), (want, t.fmt), "{}: {:?}", what, o);
        let ev = u64::from(over);
        let want_ctr = if o == Overflow::Wrap {
            (0, ev)
        } else {
            (ev, 0)
        };
        prop_assert_eq!(
            (ctr.saturations, ctr.overflows),
            want_ctr,
            "{}: {:?} events",
            what,
            o
        );
    }
    prop_assert_eq!(c.plain, c.checked, "{}: from_num", what);
    for q in Quant::ALL {
        for o in Overflow::ALL {
            let (want, want_ev) = model::from_f64(x, t.fmt, q, o);
            let mut ctr = Counters::default();
            let got = Fx::from_f64(x, t.fmt, q, o, "x", &mut ctr).unwrap();
            prop_assert_eq!(got.raw, want, "{}: {:?} {:?} vs model", what, q, o);
            prop_assert_eq!(
                ctr_triple(&ctr),
                counted(want_ev),
                "{}: {:?} {:?} counters",
                what,
                q,
                o
            );
        }
    }
    Ok(())
}

/// What the `fixed` crate gives for one S → D conversion.
fn crate_conv<S: Fixed, D: Fixed>(raw: i128) -> (CrateOp, (i128, bool)) {
    let src = from_raw::<S>(raw);
    let (ov, flag) = D::overflowing_from_num(src);
    (
        crate_op(
            D::wrapping_from_num(src),
            D::saturating_from_num(src),
            D::checked_from_num(src),
            || D::from_num(src),
        ),
        (raw_of(ov), flag),
    )
}

/// Fixed → fixed: the crate discards extra fraction bits (Trn);
/// wrapping_from_num ↔ Wrap, saturating_from_num ↔ Sat, checked None ↔ the event.
fn check_conv(sf: Format, df: Format, raw: i128, (c, ov): (CrateOp, (i128, bool))) -> Check {
    let x = Fx::from_raw(raw, sf);
    let what = format!("{} {raw} → {}", label(sf), label(df));
    expect_crate(x, df, Quant::Trn, c, &what)?;
    prop_assert_eq!(
        ov,
        (c.wrapping, c.checked.is_none()),
        "{}: overflowing",
        what
    );
    check_all_modes(x, raw, sf.frac_bits, df, &what)
}

/// The partner types every type converts to and from (widths 8/16/32, signed and
/// unsigned, no / some / all fraction bits).
const N_REPS: usize = 8;

fn conv_with_rep<T: Fixed>(t: &Ty, k: usize, wt: Word, wr: Word) -> Check {
    macro_rules! reps {
        ($($i:literal => $R:ty),*) => {
            match k {
                $($i => {
                    let rf = fmt_of::<$R>();
                    let a = realize(wt, t.fmt);
                    check_conv(t.fmt, rf, a, crate_conv::<T, $R>(a))?;
                    let b = realize(wr, rf);
                    check_conv(rf, t.fmt, b, crate_conv::<$R, T>(b))?;
                })*
                _ => unreachable!(),
            }
        };
    }
    reps!(
        0 => FixedI8<U3>,
        1 => FixedU8<U8>,
        2 => FixedI16<U16>,
        3 => FixedU16<U0>,
        4 => FixedI16<U9>,
        5 => FixedI32<U0>,
        6 => FixedU32<U27>,
        7 => FixedI32<U31>
    );
    Ok(())
}

fn config() -> ProptestConfig {
    ProptestConfig::with_cases(common::cases())
}

#[test]
fn the_table_holds_every_8_16_32_bit_type() {
    let t = types();
    assert_eq!(t.len(), N_TYPES);
    for w in [8u32, 16, 32] {
        for signed in [false, true] {
            for frac in 0..=w {
                let f = Format {
                    int_bits: w - frac,
                    frac_bits: frac,
                    signed,
                };
                assert_eq!(t.iter().filter(|x| x.fmt == f).count(), 1, "{f}");
                // Format::new accepts exactly those with a sign bit (or unsigned).
                assert_eq!(
                    Format::new(w - frac, frac, signed).is_ok(),
                    !signed || frac < w
                );
            }
        }
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn add_sub_agree_with_fixed(words in prop::collection::vec((word(), word()), N_TYPES)) {
        for (t, (a, b)) in types().iter().zip(words) {
            check_add_sub(t, a, b)?;
        }
    }

    #[test]
    fn mul_agrees_with_fixed(words in prop::collection::vec((word(), word()), N_TYPES)) {
        for (t, (a, b)) in types().iter().zip(words) {
            check_mul(t, a, b)?;
        }
    }

    #[test]
    fn rounding_to_integer_agrees_with_fixed(words in prop::collection::vec(word(), N_TYPES)) {
        for (t, a) in types().iter().zip(words) {
            check_round(t, a)?;
        }
    }

    #[test]
    fn f64_conversion_agrees_with_fixed(gens in prop::collection::vec(fgen(), N_TYPES)) {
        for (t, g) in types().iter().zip(gens) {
            check_from_f64(t, g)?;
        }
    }

    #[test]
    fn fixed_to_fixed_conversion_agrees_with_fixed(
        words in prop::collection::vec((0..N_REPS, word(), word()), N_TYPES)
    ) {
        for (t, (k, a, b)) in types().iter().zip(words) {
            (t.conv)(t, k, a, b)?;
        }
    }
}

// ---------------------------------------------------------------------------------
// Beyond the `fixed` crate: any stored formats, mixed operands, all modes.
// ---------------------------------------------------------------------------------

/// Any storable format: width 1..=63, a signed one with its sign bit.
fn stored_format() -> impl Strategy<Value = Format> {
    (1u32..=MAX_STORED_WIDTH, any::<bool>(), any::<u32>()).prop_map(|(w, signed, r)| {
        let min_int = u32::from(signed);
        let int_bits = min_int + r % (w + 1 - min_int);
        Format::new(int_bits, w - int_bits, signed).unwrap()
    })
}

/// Two operands in random stored formats, an operation (0 = none, add, sub, mul) and a
/// random stored destination.
fn op_strategy() -> impl Strategy<Value = (Format, Word, Format, Word, u8, Format)> {
    (
        stored_format(),
        word(),
        stored_format(),
        word(),
        0u8..4,
        stored_format(),
    )
}

proptest! {
    #![proptest_config(config())]

    /// Full-precision add/sub/mul of mixed stored formats are exact, and assigning
    /// them (or a plain value) to any stored format matches the model in every mode.
    #[test]
    fn mixed_formats_match_the_exact_model((fa, wa, fb, wb, op, dst) in op_strategy()) {
        let (a, b) = (realize(wa, fa), realize(wb, fb));
        let (xa, xb) = (Fx::from_raw(a, fa), Fx::from_raw(b, fb));
        let f = fa.frac_bits.max(fb.frac_bits);
        let (sa, sb) = (a << (f - fa.frac_bits), b << (f - fb.frac_bits));
        let (x, num, frac, name) = match op {
            0 => (xa, a, fa.frac_bits, "id"),
            1 => (xa.add(xb), sa + sb, f, "add"),
            2 => (xa.sub(xb), sa - sb, f, "sub"),
            _ => (xa.mul(xb), a * b, fa.frac_bits + fb.frac_bits, "mul"),
        };
        let what = format!("{name} {a}:{fa} {b}:{fb} → {dst}");
        // Full precision: the value is exact and fits the result format.
        let (lo, hi) = model::range(x.fmt);
        prop_assert!(x.fmt.width() <= 127, "{}: {}", what, x.fmt);
        prop_assert!(x.raw >= lo && x.raw <= hi, "{}: {:?} overflows its format", what, x);
        if name == "sub" {
            prop_assert!(x.fmt.signed);
        }
        check_all_modes(x, num, frac, dst, &what)?;
    }

    /// `round_shift` over its whole domain (any i128, shifts −140..=140).
    #[test]
    fn round_shift_matches_the_model(
        raw in prop_oneof![
            any::<i128>(),
            (0u32..127, -2i128..=2, any::<bool>()).prop_map(|(k, d, n)| {
                let v = (1i128 << k) + d;
                if n { -v } else { v }
            }),
            Just(i128::MIN),
            Just(i128::MAX),
        ],
        shift in -140i32..=140,
    ) {
        for q in Quant::ALL {
            let got = round_shift(raw, shift, q);
            let want = if shift > 0 {
                model::round_pow2(raw, shift as u32, q)
            } else {
                // Exact left shift; a carrier overflow saturates the carrier.
                let s = (-shift) as u32;
                let exact = if raw == 0 { Some(0) } else if s < 127 { raw.checked_mul(1i128 << s) } else { None };
                exact.unwrap_or(if raw < 0 { -i128::MAX } else { i128::MAX })
            };
            prop_assert_eq!(got, want, "round_shift({}, {}, {:?})", raw, shift, q);
        }
    }

    /// `wrap` keeps the low bits, sign-extended.
    #[test]
    fn wrap_matches_the_model(raw in any::<i128>(), f in stored_format()) {
        prop_assert_eq!(wrap(raw, f), model::wrap_low(raw as u128, f.width(), f.signed));
    }

    /// f64 → any stored format, every mode, against the model (huge, tiny, subnormal
    /// and on-grid values).
    #[test]
    fn from_f64_matches_the_model(g in fgen(), f in stored_format()) {
        let x = realize_f64(g, f);
        for q in Quant::ALL {
            for o in Overflow::ALL {
                let (want, ev) = model::from_f64(x, f, q, o);
                let mut c = Counters::default();
                let got = Fx::from_f64(x, f, q, o, "x", &mut c).unwrap();
                prop_assert_eq!(got.raw, want, "{:e} → {} {:?} {:?}", x, f, q, o);
                prop_assert_eq!(ctr_triple(&c), counted(ev), "{:e} → {} {:?} {:?}", x, f, q, o);
            }
        }
    }

    /// Random (often invalid) formats: never a panic; Ok exactly when storable;
    /// errors name the field.
    #[test]
    fn format_new_validates(int_bits in prop_oneof![0u32..70, any::<u32>()],
                            frac_bits in prop_oneof![0u32..70, any::<u32>()],
                            signed in any::<bool>()) {
        let w = int_bits as u64 + frac_bits as u64;
        let ok = (1..=63).contains(&w) && !(signed && int_bits == 0);
        match Format::new(int_bits, frac_bits, signed) {
            Ok(f) => {
                prop_assert!(ok);
                prop_assert_eq!((f.int_bits, f.frac_bits, f.signed), (int_bits, frac_bits, signed));
            }
            Err(e) => {
                prop_assert!(!ok);
                prop_assert_eq!(e.field(), "format");
            }
        }
        let f = Format { int_bits, frac_bits, signed };
        match f.validate("unit.x_format") {
            Ok(()) => prop_assert!(ok),
            Err(e) => { prop_assert!(!ok); prop_assert_eq!(e.field(), "unit.x_format"); }
        }
    }
}

// ---------------------------------------------------------------------------------
// Fixed cases.
// ---------------------------------------------------------------------------------

#[test]
fn format_new_rejects_zero_wide_signed_without_sign_bit() {
    let e = Format::new(0, 0, false).unwrap_err();
    assert!(
        matches!(e, ConfigError::OutOfRange { ref field, value, .. } if field == "format" && value == 0.0),
        "{e:?}"
    );
    let e = Format::new(40, 24, false).unwrap_err();
    assert!(
        matches!(e, ConfigError::OutOfRange { ref field, value, .. } if field == "format" && value == 64.0),
        "{e:?}"
    );
    let e = Format::new(0, 8, true).unwrap_err();
    assert!(
        matches!(e, ConfigError::Invalid { ref field, .. } if field == "format"),
        "{e:?}"
    );
    assert!(Format::new(u32::MAX, u32::MAX, true).is_err());
    assert!(Format::new(0, 63, false).is_ok());
    assert!(Format::new(1, 62, true).is_ok());
    assert!(Format::uint(0).is_err() && Format::ufrac(64).is_err());
    let e = Format {
        int_bits: 0,
        frac_bits: 0,
        signed: true,
    }
    .validate("texture_sampler.texel_format")
    .unwrap_err();
    assert_eq!(e.field(), "texture_sampler.texel_format");
    assert!(e.to_string().starts_with("texture_sampler.texel_format:"));
}

#[test]
fn from_f64_rejects_nan_and_infinities_naming_the_field() {
    let f = Format::new(4, 4, true).unwrap();
    for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -f64::NAN] {
        let mut c = Counters::default();
        let e =
            Fx::from_f64(x, f, Quant::RndConv, Overflow::Sat, "glare.bias", &mut c).unwrap_err();
        assert!(
            matches!(e, ConfigError::NotFinite { ref field, .. } if field == "glare.bias"),
            "{e:?}"
        );
        assert_eq!(
            c,
            Counters::default(),
            "nothing counted for a refused input"
        );
        let e = Fx::exact_from_f64(x, "glare.bias").unwrap_err();
        assert_eq!(e.field(), "glare.bias");
        // The fixed crate refuses them too (checked → None).
        assert!(fixed::types::I4F4::checked_from_num(x).is_none());
    }
}

#[test]
fn ties_and_events_by_hand() {
    // s4.4 = FixedI8<U4>: ties at ±2.5, ±0.03125 (half an LSB).
    let f = Format::new(4, 4, true).unwrap();
    let mut c = Counters::default();
    let q = |x: f64, q: Quant, c: &mut Counters| {
        Fx::from_f64(x, f, q, Overflow::Sat, "x", c).unwrap().raw
    };
    assert_eq!(q(2.5 / 16.0, Quant::RndConv, &mut c), 2);
    assert_eq!(q(3.5 / 16.0, Quant::RndConv, &mut c), 4);
    assert_eq!(q(-2.5 / 16.0, Quant::RndInf, &mut c), -3);
    assert_eq!(q(-2.5 / 16.0, Quant::Rnd, &mut c), -2);
    assert_eq!(q(-2.5 / 16.0, Quant::RndMinInf, &mut c), -3);
    assert_eq!(q(-2.5 / 16.0, Quant::RndZero, &mut c), -2);
    assert_eq!(c, Counters::default());
    // Underflow: a non-zero value rounded to zero is counted.
    assert_eq!(q(0.4 / 16.0, Quant::RndConv, &mut c), 0);
    assert_eq!(c.underflows, 1);
    // Saturation at both ends, and SAT_SYM's symmetric minimum.
    assert_eq!(q(100.0, Quant::Trn, &mut c), 127);
    assert_eq!(q(-100.0, Quant::Trn, &mut c), -128);
    assert_eq!(c.saturations, 2);
    let m = Fx::from_f64(-8.0, f, Quant::Trn, Overflow::SatSym, "x", &mut c).unwrap();
    assert_eq!((m.raw, c.saturations), (-127, 3));
    // Wrap counts an overflow.
    let w = Fx::from_f64(8.0, f, Quant::Trn, Overflow::Wrap, "x", &mut c).unwrap();
    assert_eq!((w.raw, c.overflows), (-128, 1));
    // The same through the fixed crate.
    use fixed::types::I4F4;
    assert_eq!(I4F4::from_num(2.5 / 16.0).to_bits(), 2);
    assert_eq!(I4F4::saturating_from_num(100.0).to_bits(), 127);
    assert_eq!(I4F4::wrapping_from_num(8.0).to_bits(), -128);
}

#[test]
fn huge_values_wrap_like_the_fixed_crate() {
    // |x|·2^frac beyond the i128 carrier: the wrapped code is still the low bits.
    use fixed::types::{I16F16, U32F32};
    for x in [
        2f64.powi(100) + 2f64.powi(60),
        -(2f64.powi(110)),
        3.0 * 2f64.powi(96),
        1e300,
    ] {
        let mut c = Counters::default();
        let f = fmt_of::<U32F32>();
        let got = Fx::from_f64(x, f, Quant::RndConv, Overflow::Wrap, "x", &mut c).unwrap();
        assert_eq!(got.raw, raw_of(U32F32::wrapping_from_num(x)), "{x:e}");
        assert_eq!(c.overflows, 1);
        let f = fmt_of::<I16F16>();
        let got = Fx::from_f64(x, f, Quant::RndConv, Overflow::Wrap, "x", &mut c).unwrap();
        assert_eq!(got.raw, raw_of(I16F16::wrapping_from_num(x)), "{x:e}");
    }
    // A 126-bit product assigned to a format with more fraction bits.
    let s = Format::new(63, 0, true).unwrap();
    let p = Fx::from_raw(s.max_raw(), s).mul(Fx::from_raw(s.max_raw(), s));
    let dst = Format::new(1, 62, true).unwrap();
    let (v, ev) = p.assign_events(dst, Quant::Trn, Overflow::Wrap);
    let (want, _) = model::assign(p.raw, 0, dst, Quant::Trn, Overflow::Wrap);
    assert_eq!(v.raw, want);
    assert!(ev.wrapped);
}
