//! texture_sampler's vectors: 2D bilinear, one channel, four texel ports (II 1), on
//! a seeded random texture (every texel matters, unlike a smooth image) that the
//! testbench reads through four `rtl_rom` ports.
//!
//! Default: the GeForce sampler (256 × 256, 8-bit texels, s16.8 coordinates, 8-bit
//! weights, product weights rounded once, clamp to edge), 10⁵ coordinates: seven in
//! eight of the random ones fall within a texel of the texture (the rest are the raw
//! s16.8 wire, mostly clamped), so filtering sees real texel neighbourhoods.
//! Narrow: a 5 × 3 texture (a non-power-of-two row, the address multiplier), 3-bit
//! texels, s4.3 coordinates, 2-bit weights (the fraction is rounded), repeat along s
//! (the floored remainder) and clamp along t, in Mesa llvmpipe's mode (successive
//! lerps, half-to-even weights): 14 input bits, exhaustive.

use super::super::unit_entry::seeded;
use super::vector_set::{collect, RomPort, RtlConfig, VectorSet};
use rand::Rng;
use rtl_model::units::texture_sampler::{
    AddressMode, FilterRounding, TextureSampler, TextureSamplerConfig, TextureSamplerIn,
    WeightRounding,
};

fn weight_rounding_code(r: WeightRounding) -> u64 {
    match r {
        WeightRounding::Round => 0,
        WeightRounding::Truncate => 1,
        WeightRounding::RoundHalfEven => 2,
    }
}

fn address_code(m: AddressMode) -> u64 {
    match m {
        AddressMode::Clamp => 0,
        AddressMode::Wrap => 1,
    }
}

pub(super) fn texture_sampler_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let cfg = match config {
        RtlConfig::Default => TextureSamplerConfig::geforce(),
        RtlConfig::Narrow => TextureSamplerConfig {
            size: [5, 3, 1],
            texel_bits: 3,
            coord_int_bits: 4,
            coord_frac_bits: 3,
            weight_bits: 2,
            address: [AddressMode::Wrap, AddressMode::Clamp, AddressMode::Clamp],
            ..TextureSamplerConfig::geforce()
        }
        .mesa_llvmpipe(),
    };
    let mut rng = seeded(seed ^ 0x7e7e1);
    let max = (1u32 << cfg.texel_bits) - 1;
    let texels: Vec<u32> = (0..cfg.texel_count())
        .map(|_| rng.random_range(0..=max))
        .collect();
    let u = TextureSampler::new(cfg.clone(), &texels).map_err(|e| e.to_string())?;
    let cw = u.coord_bits();
    let f = cfg.coord_frac_bits;
    let remap = 2 * cw > super::vector_set::EXHAUSTIVE_BITS;
    // A coordinate from a cw-bit random value: the raw wire (sign-extended), or, for
    // wide words, mostly within a texel of an axis of `size` texels.
    let coord = move |v: u64, size: u32| -> i32 {
        let raw = ((v << (64 - cw)) as i64 >> (64 - cw)) as i32;
        if !remap || v >> (cw - 3) == 7 {
            raw
        } else {
            let span = (size as u64 + 2) << f;
            ((v % span) as i64 - (1i64 << f)) as i32
        }
    };
    let [w, h, _] = cfg.size;
    let make = move |v: &[u64]| TextureSamplerIn {
        coord: [coord(v[0], w), coord(v[1], h), 0],
    };
    let rom = RomPort {
        name: "texels",
        ports: 4,
        width: cfg.texel_bits,
        words: texels.iter().map(|&t| t as u64).collect(),
    };
    let params = vec![
        ("SIZE_W", w as u64),
        ("SIZE_H", h as u64),
        ("TEXEL_BITS", cfg.texel_bits as u64),
        ("COORD_INT_BITS", cfg.coord_int_bits as u64),
        ("COORD_FRAC_BITS", f as u64),
        ("WEIGHT_BITS", cfg.weight_bits as u64),
        ("WEIGHT_ROUNDING", weight_rounding_code(cfg.weight_rounding)),
        (
            "FILTER_ROUNDING",
            u64::from(cfg.filter_rounding == FilterRounding::SuccessiveLerps),
        ),
        ("ADDR_S", address_code(cfg.address[0])),
        ("ADDR_T", address_code(cfg.address[1])),
        ("ADDR_BITS", rom.addr_bits() as u64),
    ];
    let mut v = collect(
        &u,
        (),
        config,
        TextureSamplerIn::default(),
        make,
        params,
        count,
        seed,
    );
    v.roms = vec![rom];
    Ok(v)
}
