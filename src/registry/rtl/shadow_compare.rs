//! shadow_compare's vectors: a stream of clears, depth-pass writes and lookup tests
//! through the unit's depth RAM (its state, carried from the cleared reset state), the
//! RAM outside the Verilog module as a read/write port (`RamPort`).
//!
//! The input word (op 2, x 16, y 16, depth n + k bits) is too wide to enumerate, so
//! the random field values are mapped to a stream that exercises the RAM: a clear for
//! 1 in 64 words, coordinates in four modes (a 4-texel window at the map's origin, one
//! at its far edge, anywhere in the map or one past it, or the raw s16 wire, which is
//! mostly outside), depths in four (small codes, codes just below the far plane, or
//! the raw wire twice), so writes and tests keep meeting the same texels and depth
//! comparisons land on the bias edge.

use super::vector_set::{collect, RamPort, RtlConfig, VectorSet};
use rtl_model::units::shadow_compare::{CompareFunc, DepthTexel, ShadowCompareConfig, ShadowIn};

/// A coordinate on an axis of `side` texels from a 16-bit random value.
fn coord(v: u64, side: u32) -> i32 {
    let side = side as i64;
    let c = match v >> 14 {
        0 => (v & 3) as i64,
        1 => side - 1 - (v & 3) as i64,
        2 => (v & 0x3fff) as i64 % (side + 1),
        _ => v as u16 as i16 as i64,
    };
    c as i32
}

pub(super) fn shadow_compare_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    vectors_at(base(config), config, count, seed)
}

/// The configuration's shadow_compare config.
fn base(config: RtlConfig) -> ShadowCompareConfig {
    match config {
        RtlConfig::Default => ShadowCompareConfig::geforce(),
        // 15 texels on a non-power-of-two row (the address multiplier), 3-bit depths
        // with one fraction bit: compares meet the bias edge all the time.
        RtlConfig::Narrow => ShadowCompareConfig {
            width: 5,
            height: 3,
            depth_bits: 3,
            bias: 1,
            frag_frac_bits: 1,
            ..ShadowCompareConfig::geforce()
        },
    }
}

/// The modes beyond the two configurations, each a set tagged
/// `shadow_compare_narrow_<mode>`: the seven compare functions other than LEQUAL on the
/// narrow map, and the texel formats on it at their depth widths (Z16 with 2 fraction
/// bits, so the depth port is the fragment's 18 bits; Z24S8 with 0 and 8, the port the
/// 32-bit texel word and the 32-bit fragment).
pub fn shadow_compare_mode_sets(count: usize, seed: u64) -> Result<Vec<VectorSet>, String> {
    let narrow = base(RtlConfig::Narrow);
    let mut modes: Vec<(String, ShadowCompareConfig)> = CompareFunc::ALL
        .into_iter()
        .filter(|&f| f != CompareFunc::Lequal)
        .map(|f| {
            let cfg = ShadowCompareConfig {
                compare: f,
                ..narrow
            };
            (f.name().to_lowercase(), cfg)
        })
        .collect();
    for (name, texel, n, k, bias, f) in [
        ("z16_equal", DepthTexel::Z16, 16, 2, 0, CompareFunc::Equal),
        ("z16_lequal", DepthTexel::Z16, 16, 0, 3, CompareFunc::Lequal),
        (
            "z24s8_equal",
            DepthTexel::Z24S8,
            24,
            0,
            0,
            CompareFunc::Equal,
        ),
        (
            "z24s8_gequal",
            DepthTexel::Z24S8,
            24,
            8,
            2,
            CompareFunc::Gequal,
        ),
    ] {
        let cfg = ShadowCompareConfig {
            depth_bits: n,
            frag_frac_bits: k,
            bias,
            compare: f,
            texel,
            ..narrow
        };
        modes.push((name.to_string(), cfg));
    }
    modes
        .into_iter()
        .map(|(name, cfg)| {
            let mut v = vectors_at(cfg, RtlConfig::Narrow, count, seed)?;
            v.variant = Some(name);
            Ok(v)
        })
        .collect()
}

fn vectors_at(
    cfg: ShadowCompareConfig,
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let u = cfg.build().map_err(|e| e.to_string())?;
    let fw = u.frag_bits();
    let fmax = (1u64 << fw) - 1;
    let shift = cfg.texel.shift();
    let (w, h) = (cfg.width, cfg.height);
    let make = move |v: &[u64]| {
        let raw = v[3] & fmax;
        let depth = if fw < 6 {
            raw
        } else {
            match raw >> (fw - 2) {
                0 => raw & 15,
                1 => fmax - (raw & 15),
                _ => raw,
            }
        };
        let (x, y) = (coord(v[1], w), coord(v[2], h));
        match v[0] {
            0 if v[2] & 15 == 0 => ShadowIn::Clear,
            // A texel word: the depth code (its low n bits) above the low bits of
            // the random word (a Z24S8 texel's stencil byte).
            1 => ShadowIn::Write {
                x,
                y,
                depth: (((depth as u32) << shift) | (v[3] as u32 & ((1 << shift) - 1))),
            },
            _ => ShadowIn::Test { x, y, depth },
        }
    };
    let params = vec![
        ("WIDTH", w as u64),
        ("HEIGHT", h as u64),
        ("DEPTH_BITS", cfg.depth_bits as u64),
        ("BIAS", cfg.bias as u64),
        ("FRAG_FRAC_BITS", cfg.frag_frac_bits as u64),
        ("ADDR_BITS", u.addr_bits() as u64),
        ("COMPARE", cfg.compare.code() as u64),
        ("TEXEL_SHIFT", shift as u64),
        ("IN_BITS", u.in_depth_bits() as u64),
    ];
    let probe = ShadowIn::Test {
        x: 0,
        y: 0,
        depth: 0,
    };
    let state = u.fresh_state();
    let mut v = collect(&u, state, config, probe, make, params, count, seed);
    v.rams = vec![RamPort {
        name: "ram",
        width: cfg.depth_bits,
        depth: w as u64 * h as u64,
        clear_value: u.far() as u64,
    }];
    Ok(v)
}
