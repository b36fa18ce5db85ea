//! Gate cost model in NAND2 equivalents.
//!
//! Every primitive is first expressed as a count of the cells that Yosys' ABC maps to
//! with the pinned gate set (`synth; abc -g AND,NAND,OR,NOR,XOR,XNOR,MUX; stat`), plus
//! flip-flops, and only then weighted. So the model and Yosys are compared with one
//! and the same cell-to-NAND2 mapping, [`CELL_WEIGHTS`], stated here once.
//! RAM/ROM bits are never folded into gates; they are reported beside them.

use serde::Serialize;
use std::ops::{Add, AddAssign, Mul};

/// NAND2 equivalents of each cell kind. Conventional standard-cell area ratios
/// (a 2-input NAND = 1): NAND2/NOR2 4 transistors; AND2/OR2 a NAND/NOR plus an
/// inverter; XOR2/XNOR2/MUX2 about 2⅓ NAND2; an inverter ⅔; a D flip-flop 5⅓.
pub const CELL_WEIGHTS: CellWeights = CellWeights {
    and2: 4.0 / 3.0,
    nand2: 1.0,
    or2: 4.0 / 3.0,
    nor2: 1.0,
    xor2: 7.0 / 3.0,
    xnor2: 7.0 / 3.0,
    mux2: 7.0 / 3.0,
    not: 2.0 / 3.0,
    dff: 16.0 / 3.0,
};

/// The NAND2-equivalent area of one cell of each kind; [`CELL_WEIGHTS`] is the one set
/// the model uses.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CellWeights {
    /// 2-input AND (a NAND2 plus an inverter: 4/3).
    pub and2: f64,
    /// 2-input NAND, the unit of area (1).
    pub nand2: f64,
    /// 2-input OR (a NOR2 plus an inverter: 4/3).
    pub or2: f64,
    /// 2-input NOR (1).
    pub nor2: f64,
    /// 2-input XOR (7/3).
    pub xor2: f64,
    /// 2-input XNOR (7/3).
    pub xnor2: f64,
    /// 2-to-1 multiplexer (7/3).
    pub mux2: f64,
    /// Inverter (2/3).
    pub not: f64,
    /// D flip-flop, one register bit (16/3).
    pub dff: f64,
}

/// A bag of cells (fractional counts allowed for averaged structures).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Cells {
    /// 2-input AND cells.
    pub and2: f64,
    /// 2-input NAND cells.
    pub nand2: f64,
    /// 2-input OR cells.
    pub or2: f64,
    /// 2-input NOR cells.
    pub nor2: f64,
    /// 2-input XOR cells.
    pub xor2: f64,
    /// 2-input XNOR cells.
    pub xnor2: f64,
    /// 2-to-1 multiplexer cells.
    pub mux2: f64,
    /// Inverters.
    pub not: f64,
    /// D flip-flops (register bits).
    pub dff: f64,
}

impl Cells {
    /// NAND2 equivalents under [`CELL_WEIGHTS`].
    pub fn nand2_eq(&self) -> f64 {
        let w = CELL_WEIGHTS;
        self.and2 * w.and2
            + self.nand2 * w.nand2
            + self.or2 * w.or2
            + self.nor2 * w.nor2
            + self.xor2 * w.xor2
            + self.xnor2 * w.xnor2
            + self.mux2 * w.mux2
            + self.not * w.not
            + self.dff * w.dff
    }
}

impl Add for Cells {
    type Output = Cells;
    fn add(self, o: Cells) -> Cells {
        Cells {
            and2: self.and2 + o.and2,
            nand2: self.nand2 + o.nand2,
            or2: self.or2 + o.or2,
            nor2: self.nor2 + o.nor2,
            xor2: self.xor2 + o.xor2,
            xnor2: self.xnor2 + o.xnor2,
            mux2: self.mux2 + o.mux2,
            not: self.not + o.not,
            dff: self.dff + o.dff,
        }
    }
}

impl AddAssign for Cells {
    fn add_assign(&mut self, o: Cells) {
        *self = *self + o;
    }
}

impl Mul<f64> for Cells {
    type Output = Cells;
    fn mul(self, k: f64) -> Cells {
        Cells {
            and2: self.and2 * k,
            nand2: self.nand2 * k,
            or2: self.or2 * k,
            nor2: self.nor2 * k,
            xor2: self.xor2 * k,
            xnor2: self.xnor2 * k,
            mux2: self.mux2 * k,
            not: self.not * k,
            dff: self.dff * k,
        }
    }
}

/// The primitives every unit's cost is built from.
pub mod prim {
    use super::Cells;

    /// Half adder: sum = XOR, carry = AND.
    pub fn half_adder() -> Cells {
        Cells {
            xor2: 1.0,
            and2: 1.0,
            ..Cells::default()
        }
    }

    /// Full adder: two XORs for the sum, three NAND2 for the carry (majority).
    pub fn full_adder() -> Cells {
        Cells {
            xor2: 2.0,
            nand2: 3.0,
            ..Cells::default()
        }
    }

    /// n-bit ripple-carry adder with carry out: one half adder, n−1 full adders.
    pub fn adder(n: u32) -> Cells {
        if n == 0 {
            return Cells::default();
        }
        half_adder() + full_adder() * (n - 1) as f64
    }

    /// n-bit subtractor a − b: an adder with b inverted and carry in = 1.
    pub fn subtractor(n: u32) -> Cells {
        full_adder() * n as f64
            + Cells {
                not: n as f64,
                ..Cells::default()
            }
    }

    /// n-bit unsigned adder that clamps to all-ones on carry out: adder + n OR.
    pub fn saturating_adder(n: u32) -> Cells {
        adder(n)
            + Cells {
                or2: n as f64,
                ..Cells::default()
            }
    }

    /// n-bit magnitude comparator (a < b): the borrow chain of a subtractor with no
    /// difference bits. Per bit: an inverter (ā), an XNOR2 (ā ⊕ b = a ⊙ b, the
    /// propagate) and a 3-NAND2 majority for the borrow,
    /// NAND(NAND(ā, b), NAND(a ⊙ b, borrow in)): 6 NAND2 eq. a bit. The full
    /// adder's carry gets its XOR from the sum; a comparator has no sum, so the XNOR
    /// is counted here (without it a 3-input majority needs ≥ 4 two-input gates).
    /// Against Yosys (`cmp16.v`, `cmp32.v`): 96.0 vs 112.67 (−14.8 %) at 16 bits,
    /// 192.0 vs 227.33 (−15.5 %) at 32 (tests/gate_calibration.rs).
    pub fn comparator(n: u32) -> Cells {
        Cells {
            not: n as f64,
            xnor2: n as f64,
            nand2: 3.0 * n as f64,
            ..Cells::default()
        }
    }

    /// n × m unsigned array multiplier: n·m AND partial products, n(m−2) full adders
    /// and n half adders in the carry-save array and final ripple (n = m: n² AND,
    /// n(n−2) FA, n HA).
    pub fn multiplier(n: u32, m: u32) -> Cells {
        if n == 0 || m == 0 {
            return Cells::default();
        }
        let (n, m) = (n.max(m) as f64, n.min(m) as f64);
        Cells {
            and2: n * m,
            ..Cells::default()
        } + full_adder() * (n * (m - 2.0)).max(0.0)
            + half_adder() * n
    }

    /// Non-zero digits of `c` in its non-adjacent form (canonical signed digits,
    /// digits in {−1, 0, 1}, no two adjacent non-zero): the fewest shifted terms
    /// whose sum or difference is c (248 = 2^8 − 2^3: 2; 2^12 − 1: 2; 85: 4).
    pub fn naf_digits(c: u64) -> u32 {
        naf_digits_u128(c as u128)
    }

    /// [`naf_digits`] of a constant wider than 64 bits (chaos_map's 1/(1 − a) at F > 30).
    pub fn naf_digits_u128(mut c: u128) -> u32 {
        let mut d = 0;
        while c != 0 {
            if c & 1 == 1 {
                // digit +1 when c ≡ 1 (mod 4), −1 when c ≡ 3 (the carry clears the run)
                if c & 3 == 1 {
                    c -= 1;
                } else {
                    c += 1;
                }
                d += 1;
            }
            c >>= 1;
        }
        d
    }

    /// x × C for an n-bit unsigned x and a constant C: shift-adds over C's d non-zero
    /// signed digits ([`naf_digits`]), d − 1 adders/subtractors, each taken as an
    /// (n+1)-bit [`subtractor`] (the bits below each term's shift pass through as
    /// wires; where two terms overlap the cells are full adders, above the shorter
    /// one an incrementer, about n + 1 cells a term, counted all as full adders, the
    /// subtractor's inverters covering the −1 digits). A power of two (d = 1) is
    /// wiring; C = 0 is constant 0. This is the design a constant multiplier is built
    /// as by hand; Yosys (the pinned script) does not recode C to signed digits but
    /// sums C's binary ones (measured alone, `assign y = x * C`: 9 bits × 248 = 195
    /// NAND2 where this counts 83; 12 bits × 4095 = 801 against 108), so where C has
    /// runs of ones Yosys' count of such a multiplier is larger (docs/units.md,
    /// specular_lookup).
    pub fn constant_multiplier(n: u32, c: u64) -> Cells {
        constant_multiplier_u128(n, c as u128)
    }

    /// [`constant_multiplier`] by a constant wider than 64 bits.
    pub fn constant_multiplier_u128(n: u32, c: u128) -> Cells {
        let d = naf_digits_u128(c);
        if n == 0 || d <= 1 {
            return Cells::default();
        }
        subtractor(n + 1) * (d - 1) as f64
    }

    /// n-bit 2:1 multiplexer.
    pub fn mux(n: u32) -> Cells {
        Cells {
            mux2: n as f64,
            ..Cells::default()
        }
    }

    /// n-bit k:1 multiplexer as a tree of k−1 2:1 muxes per bit.
    pub fn mux_k(n: u32, k: u32) -> Cells {
        mux(n) * (k.saturating_sub(1)) as f64
    }

    /// n-bit register (D flip-flops).
    pub fn register(n: u32) -> Cells {
        Cells {
            dff: n as f64,
            ..Cells::default()
        }
    }

    /// n-bit logarithmic barrel shifter over `stages` shift stages.
    pub fn shifter(n: u32, stages: u32) -> Cells {
        mux(n) * stages as f64
    }

    /// n-bit leading-zero counter: about n mux-equivalent cells (priority tree).
    pub fn leading_zero_counter(n: u32) -> Cells {
        Cells {
            or2: n as f64,
            mux2: n as f64 / 2.0,
            ..Cells::default()
        }
    }

    /// n-bit restoring divider producing q quotient bits: q subtract-and-select rows.
    pub fn divider(n: u32, q: u32) -> Cells {
        (subtractor(n) + mux(n)) * q as f64
    }
}

/// A unit's cost: gates (NAND2 equivalents, from cells) and storage bits apart.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Cost {
    /// Logic and pipeline registers.
    pub cells: Cells,
    /// RAM/ROM bits the unit holds (tables, texel memory), reported separately.
    pub ram_bits: u64,
    /// Named parts, for datasheets: (part, NAND2 equivalents).
    pub breakdown: Vec<(String, f64)>,
}

impl Cost {
    /// Logic and register area in NAND2 equivalents, the cells weighed by [`CELL_WEIGHTS`];
    /// RAM/ROM bits are not included (see [`Cost::ram_bits`]).
    pub fn gates_nand2(&self) -> f64 {
        self.cells.nand2_eq()
    }

    /// Add a named part.
    pub fn part(mut self, name: &str, cells: Cells) -> Self {
        self.cells += cells;
        self.breakdown.push((name.to_string(), cells.nand2_eq()));
        self
    }

    /// Add `bits` of RAM/ROM storage to the cost (reported beside the gates, never
    /// folded into them).
    pub fn with_ram_bits(mut self, bits: u64) -> Self {
        self.ram_bits += bits;
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn naf_digits_are_the_fewest_signed_terms() {
        // No two adjacent ones: the binary digits are already the NAF.
        for c in [0u64, 1, 5, 0b1010_0101, 0b1001_0001_0101] {
            assert_eq!(prim::naf_digits(c), c.count_ones(), "c = {c}");
        }
        // A run of ones 2^a − 1 (a ≥ 2) is 2^a − 2^0: two digits, shifted anywhere.
        for a in 2..40 {
            for s in [0u32, 3, 9] {
                assert_eq!(
                    prim::naf_digits(((1u64 << a) - 1) << s),
                    2,
                    "a = {a}, s = {s}"
                );
            }
        }
        // 248 = 2^8 − 2^3; 219 = 2^8 − 2^5 − 2^2 − 2^0 (binary 1101_1011: six ones).
        assert_eq!(prim::naf_digits(248), 2);
        assert_eq!(prim::naf_digits(219), 4);
        // Beyond 64 bits: a run of 100 ones is two digits; 5·2^96 + 5·2^4 is four.
        assert_eq!(prim::naf_digits_u128((1u128 << 100) - 1), 2);
        assert_eq!(prim::naf_digits_u128((5u128 << 96) | (5 << 4)), 4);
    }

    #[test]
    fn constant_multiplier_is_wiring_for_a_power_of_two() {
        for s in 0..30 {
            assert_eq!(prim::constant_multiplier(9, 1u64 << s).nand2_eq(), 0.0);
        }
        assert_eq!(prim::constant_multiplier(9, 0).nand2_eq(), 0.0);
        // d digits: d − 1 (n+1)-bit subtractors, below the general n × bits(C) array.
        let c = prim::constant_multiplier(9, 248).nand2_eq();
        assert_eq!(c, prim::subtractor(10).nand2_eq());
        assert!(c < prim::multiplier(9, 8).nand2_eq());
    }

    #[test]
    fn adder_sizes_grow_linearly() {
        let a8 = prim::adder(8).nand2_eq();
        let a16 = prim::adder(16).nand2_eq();
        assert!(a16 > 1.9 * a8 && a16 < 2.1 * a8);
    }
}
