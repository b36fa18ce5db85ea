//! projective_texcoord's vectors: (s, t, q) → (u, v, behind) with the reciprocal ROM
//! (`ProjectiveTexcoord::rom_words`) read through one `rtl_rom` port.
//!
//! Default: the GeForce unit (s16.16 in, s4.12 out, 256 × 16-bit ROM, one Newton step
//! at 20 fraction bits), 10⁵ words. Uniform 32-bit words would almost never be small
//! and s/q would nearly always saturate, so each of s, t, q is spread over magnitudes:
//! its random value's top five bits pick how many of its low bits are kept (from 1
//! LSB to the full wire, a quarter of them negated, some zero).
//! Narrow: s3.3 in, s2.7 out, an 8 × 4-bit ROM, two Newton steps at 6 fraction bits
//! (more than the mantissa's 4: m is widened, not truncated; and F_r < out_frac, so
//! the output shift is a left shift for small q): 18 input bits, exhaustive.

use super::vector_set::{collect, RomPort, RtlConfig, VectorSet};
use rtl_model::units::projective_texcoord::{ProjectiveIn, ProjectiveTexcoordConfig};

pub(super) fn projective_texcoord_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let cfg = match config {
        RtlConfig::Default => ProjectiveTexcoordConfig::geforce(),
        RtlConfig::Narrow => ProjectiveTexcoordConfig {
            in_int_bits: 3,
            in_frac_bits: 3,
            out_int_bits: 2,
            out_frac_bits: 7,
            recip_index_bits: 3,
            recip_entry_bits: 4,
            newton_steps: 2,
            newton_frac_bits: 6,
        },
    };
    let u = cfg.build().map_err(|e| e.to_string())?;
    let w = u.in_bits();
    let exhaustive = 3 * w <= super::vector_set::EXHAUSTIVE_BITS;
    let sx = move |v: u64| (v << (64 - w)) as i64 >> (64 - w);
    // A word spread over magnitudes: keep 1 + (top five bits mod w) low bits of the
    // random value (below the sign), negated when bit 0 and the top bit are set.
    let spread = move |v: u64| {
        let keep = 1 + ((v >> (w - 5)) as u32 % w);
        let mag = v & ((1u64 << keep) - 1) & ((1u64 << (w - 1)) - 1);
        if v & 1 == 1 && v >> (w - 1) == 1 {
            mag.wrapping_neg()
        } else {
            mag
        }
    };
    let make = move |v: &[u64]| {
        let (s, t, q) = if exhaustive {
            (v[0], v[1], v[2])
        } else {
            (spread(v[0]), spread(v[1]), spread(v[2]))
        };
        ProjectiveIn {
            s: sx(s),
            t: sx(t),
            q: sx(q),
        }
    };
    let params = vec![
        ("IN_BITS", w as u64),
        ("OUT_BITS", u.out_bits() as u64),
        ("OUT_FRAC_BITS", cfg.out_frac_bits as u64),
        ("RECIP_INDEX_BITS", cfg.recip_index_bits as u64),
        ("RECIP_ENTRY_BITS", cfg.recip_entry_bits as u64),
        ("NEWTON_STEPS", cfg.newton_steps as u64),
        ("NEWTON_FRAC_BITS", cfg.newton_frac_bits as u64),
    ];
    let mut v = collect(
        &u,
        (),
        config,
        ProjectiveIn::default(),
        make,
        params,
        count,
        seed,
    );
    v.roms = vec![RomPort {
        name: "recip",
        ports: 1,
        width: cfg.recip_entry_bits,
        words: u.rom_words(),
    }];
    Ok(v)
}
