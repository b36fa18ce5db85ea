//! Helpers shared by the register-combiner tests (`register_combiner`,
//! `final_combiner`): the register format's numbers and random register sets.
#![allow(dead_code)]

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rtl_model::units::register_combiner::RegisterFile;
use rtl_model::Quant;

/// One rounding's error bound in units of its LSB: ½ for the round-to-nearest modes,
/// 1 for the truncating ones.
pub fn rounding_error(q: Quant) -> f64 {
    match q {
        Quant::Trn | Quant::TrnZero => 1.0,
        _ => 0.5,
    }
}

/// S = 2^(N−1) − 1, the register code of 1.0.
pub fn one(n: u32) -> f64 {
    ((1i64 << (n - 1)) - 1) as f64
}

/// A register word as its N wires read it.
pub fn sext(x: i32, n: u32) -> i64 {
    let sh = 64 - n;
    ((x as i64) << sh) >> sh
}

/// A random register set: anywhere on the N wires, or (one in four) at a stiff code:
/// ±S, 0, 1, the wire's −S−1, the mux threshold 2^(N−2) and one below it.
pub fn random_file(rng: &mut ChaCha8Rng, n: u32) -> RegisterFile {
    let s = one(n) as i32;
    let special = [s, -s, 0, 1, -s - 1, 1 << (n - 2), (1 << (n - 2)) - 1];
    let mut f = RegisterFile::default();
    for r in f.regs.iter_mut().flatten() {
        *r = if rng.random_range(0..4) == 0 {
            special[rng.random_range(0..special.len())]
        } else {
            rng.random_range(-s - 1..=s)
        };
    }
    f
}
