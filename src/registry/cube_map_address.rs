//! `cube_map_address`: a direction's cube-map face and texel coordinates, with a
//! reciprocal ROM for the major-axis divide.

use super::unit_entry::{seeded, trace_unit, UnitEntry};
use crate::tables::Table;
use rand::Rng;
use rtl_model::units::cube_map_address::{CubeMapAddress, CubeMapAddressIn};
use rtl_model::{Counters, UnitSummary};
use std::collections::BTreeMap;
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "cube_map_address",
    summary: || UnitSummary::of(&CubeMapAddress::geforce3()),
    tables,
    trace,
};

/// The reciprocal seed ROM.
fn tables() -> Vec<Table> {
    let cube = CubeMapAddress::geforce3();
    let c = cube.config();
    vec![Table {
        name: format!(
            "cube_map_address_rcp_{}x{}",
            1u32 << c.rcp_addr_bits,
            c.rcp_bits
        ),
        width: c.rcp_bits,
        words: cube.rom_words(),
        unit: "cube_map_address".into(),
        params: BTreeMap::from([
            ("addr_bits".to_string(), c.rcp_addr_bits.to_string()),
            ("entry_bits".to_string(), c.rcp_bits.to_string()),
            (
                "generator".to_string(),
                "rcp_rom_entry(j): min(round(2^R / c), 2^R - 1), u0.R, c = 1 + (j + 1/2)/2^A the midpoint of address j's interval of the mantissa m in [1, 2) of |ma|; rtl_model/src/units/cube_map_address.rs".to_string(),
            ),
        ]),
    }]
}

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let mut rng = seeded(seed);
    let u = CubeMapAddress::geforce3();
    let c = u.config();
    // The reflection unit's words: anywhere in the map's cube [0, s]³ (texels,
    // s(16).8), the centre (a zero direction) now and then.
    let s = 1i32 << (c.side_log2 + c.in_frac_bits);
    let inputs: Vec<CubeMapAddressIn> = (0..pixels)
        .map(|k| CubeMapAddressIn {
            coord: if k % 8 == 7 {
                [s / 2; 3]
            } else {
                [(); 3].map(|_| rng.random_range(0..=s))
            },
        })
        .collect();
    trace_unit(&u, (), &inputs, w)
}
