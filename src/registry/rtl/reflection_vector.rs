//! reflection_vector's vectors (`rtl_model/verilog/units/reflection_vector.v`): the
//! GeForce3 default (s16.16 n and e, u1.12 λ, 256 × 11-bit rsqrt ROM, one Newton step,
//! 19-bit mantissas; 10⁵ random + corners) and a narrow configuration without the Newton
//! step (s2.0 n and e, u1.2 λ, 8 × 5-bit ROM, s2.4 n̂; the 15-bit input word is
//! exhaustive, with every zero-vector case and λ codes above 1). The rsqrt ROM is read
//! through two ports (n and e are normalised in parallel).

use super::vector_set::{collect, RomPort, RtlConfig, VectorSet};
use rtl_model::units::reflection_vector::{ReflectionVectorConfig, ReflectionVectorIn};

pub(super) fn reflection_vector_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let cfg = match config {
        RtlConfig::Default => ReflectionVectorConfig::geforce3(),
        RtlConfig::Narrow => ReflectionVectorConfig {
            in_int_bits: 2,
            in_frac_bits: 0,
            lambda_bits: 2,
            rsqrt_addr_bits: 3,
            rsqrt_bits: 5,
            newton: false,
            newton_frac_bits: 4,
            norm_bits: 4,
            mant_bits: 4,
            side_log2: 2,
            coord_int_bits: 3,
            coord_frac_bits: 1,
        },
    };
    let u = cfg.build().map_err(|e| e.to_string())?;
    let w = u.in_bits();
    // Sign-extend a w-bit wire value.
    let sx = move |v: u64| ((v << (64 - w)) as i64) >> (64 - w);
    let make = move |v: &[u64]| ReflectionVectorIn {
        n: [sx(v[0]), sx(v[1]), sx(v[2])],
        e: [sx(v[3]), sx(v[4]), sx(v[5])],
        lambda: v[6] as u32,
    };
    let params = vec![
        ("IN_INT_BITS", cfg.in_int_bits as u64),
        ("IN_FRAC_BITS", cfg.in_frac_bits as u64),
        ("LAMBDA_BITS", cfg.lambda_bits as u64),
        ("RSQRT_ADDR_BITS", cfg.rsqrt_addr_bits as u64),
        ("RSQRT_BITS", cfg.rsqrt_bits as u64),
        ("NEWTON", u64::from(cfg.newton)),
        ("NEWTON_FRAC_BITS", cfg.newton_frac_bits as u64),
        ("NORM_BITS", cfg.norm_bits as u64),
        ("MANT_BITS", cfg.mant_bits as u64),
        ("SIDE_LOG2", cfg.side_log2 as u64),
        ("COORD_INT_BITS", cfg.coord_int_bits as u64),
        ("COORD_FRAC_BITS", cfg.coord_frac_bits as u64),
    ];
    let mut v = collect(&u, (), config, make(&[0; 7]), make, params, count, seed);
    v.roms = vec![RomPort {
        name: "rsqrt",
        ports: 2,
        width: cfg.rsqrt_bits,
        words: u.rom_words(),
    }];
    Ok(v)
}
