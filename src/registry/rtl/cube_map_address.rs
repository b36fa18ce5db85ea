//! cube_map_address's vectors (`rtl_model/verilog/units/cube_map_address.v`): the
//! GeForce3 default (s16.8 words of a 128³ map, 64 × 8-bit reciprocal ROM, one Newton
//! step, 256-texel faces; 10⁵ random + corners) and a narrow configuration without the
//! Newton step (s4.2 words of a 4³ map, 4 × 4-bit ROM, 4-texel faces, s4.1 out; the
//! 18-bit input word is exhaustive). The reciprocal ROM is a read port.

use super::vector_set::{collect, RomPort, RtlConfig, VectorSet};
use rtl_model::units::cube_map_address::{CubeMapAddressConfig, CubeMapAddressIn};

pub(super) fn cube_map_address_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let cfg = match config {
        RtlConfig::Default => CubeMapAddressConfig::geforce3(),
        RtlConfig::Narrow => CubeMapAddressConfig {
            in_int_bits: 4,
            in_frac_bits: 2,
            side_log2: 2,
            rcp_addr_bits: 2,
            rcp_bits: 4,
            newton: false,
            newton_frac_bits: 4,
            face_log2: 2,
            coord_int_bits: 4,
            coord_frac_bits: 1,
        },
    };
    let u = cfg.build().map_err(|e| e.to_string())?;
    let w = u.in_bits();
    // Sign-extend a w-bit wire value.
    let sx = move |v: u64| (((v as u32) << (32 - w)) as i32) >> (32 - w);
    let make = move |v: &[u64]| CubeMapAddressIn {
        coord: [sx(v[0]), sx(v[1]), sx(v[2])],
    };
    let params = vec![
        ("IN_INT_BITS", cfg.in_int_bits as u64),
        ("IN_FRAC_BITS", cfg.in_frac_bits as u64),
        ("SIDE_LOG2", cfg.side_log2 as u64),
        ("RCP_ADDR_BITS", cfg.rcp_addr_bits as u64),
        ("RCP_BITS", cfg.rcp_bits as u64),
        ("NEWTON", u64::from(cfg.newton)),
        ("NEWTON_FRAC_BITS", cfg.newton_frac_bits as u64),
        ("FACE_LOG2", cfg.face_log2 as u64),
        ("COORD_INT_BITS", cfg.coord_int_bits as u64),
        ("COORD_FRAC_BITS", cfg.coord_frac_bits as u64),
    ];
    let mut v = collect(&u, (), config, make(&[0; 3]), make, params, count, seed);
    v.roms = vec![RomPort {
        name: "rcp",
        ports: 1,
        width: cfg.rcp_bits,
        words: u.rom_words(),
    }];
    Ok(v)
}
