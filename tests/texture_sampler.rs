//! texture_sampler against its f64 twin (same integer texels, exact weights).
//!
//! Error bound, in output LSBs, derived from the widths (docs/units.md#texture_sampler):
//!
//! * Nearest: both pick texel floor(u) with the same address mode → exact, bound 0.
//! * Linear: the twin computes f(a) = Σ_corners Π_k w_k(a_k) · T_corner with
//!   w_k = (1 − a_k, a_k); the unit computes f(ã) with ã_k = fx_k / W on the SAME texels
//!   (same i0, i1 per axis: rounding fx up to W only moves weight onto i1), then rounds
//!   once, half up.
//!   - f is multilinear; ∂f/∂a_k = Σ (product of the other axes' weights) ·
//!     (T_{…1…} − T_{…0…}), a convex combination of neighbour differences, so
//!     |∂f/∂a_k| ≤ M = 2^tb − 1 everywhere in the unit cube. Moving one axis at a time
//!     from a to ã (both in [0, 1]^d) gives |f(ã) − f(a)| ≤ M · Σ_k |ã_k − a_k| ≤ d·M·δ.
//!   - δ, the per-axis weight error: the fraction of p = u − ½ has Fp = max(F, 1) bits
//!     (F = coord_frac_bits). If Fp ≤ wb it is exact: δ = 0. Otherwise round-to-nearest
//!     gives δ = 2^−(wb+1) (a tie), truncation δ = 2^−wb − 2^−Fp (all dropped bits 1).
//!   - The final (Σ + W^d/2) >> d·wb is round-half-up: error in (−½, ½].
//!
//! Total: |unit − twin| ≤ ½ + d · (2^tb − 1) · δ.  At the defaults (8, 8, 8) δ = 0 and
//! the bound is ½.
//!
//! `FilterRounding::SuccessiveLerps` (llvmpipe's): each lerp v0 + ((w·Δ + W/2) >> wb)
//! errs by at most ½ from the exact lerp of its (already rounded) inputs, and a lerp
//! of two values each within e of their exact values is within e of the exact lerp
//! (a convex combination), so after the d levels the rounding error is ≤ d · ½; the
//! weight error adds the same d · M · δ (`RoundHalfEven` has `Round`'s δ). Total:
//! |unit − twin| ≤ d/2 + d · (2^tb − 1) · δ. The 1e-9 added in the assertions is f64 evaluation slack of the
//! twin (values ≤ 65535), not a fudge.

mod common;

use glare_pipeline::reference::texture_sampler::{self as twin, TextureRef};
use proptest::prelude::*;
use rtl_model::units::texture_sampler::{
    texel_coord_from_normalized, AddressMode, Filter, FilterRounding, TextureSampler,
    TextureSamplerConfig, TextureSamplerIn, WeightRounding,
};
use rtl_model::{Counters, Unit};

/// (texel_bits, weight_bits, coord_frac_bits)
#[derive(Clone, Copy, Debug)]
struct Widths {
    texel: u32,
    weight: u32,
    frac: u32,
}

const DEFAULT: Widths = Widths {
    texel: 8,
    weight: 8,
    frac: 8,
};
const WIDE: Widths = Widths {
    texel: 12,
    weight: 12,
    frac: 16,
};
/// The brief's narrow config: F = wb, so weights are exact and only the final
/// rounding is left (large relative error: 3-bit texels).
const NARROW: Widths = Widths {
    texel: 3,
    weight: 2,
    frac: 2,
};
/// Narrow with real weight quantisation: 6 fraction bits squeezed into 2-bit weights.
const NARROW_Q: Widths = Widths {
    texel: 3,
    weight: 2,
    frac: 6,
};
/// 8-bit texels, coarse 4-bit weights from 12-bit coordinates.
const COARSE_W: Widths = Widths {
    texel: 8,
    weight: 4,
    frac: 12,
};
const ALL_WIDTHS: [Widths; 5] = [DEFAULT, WIDE, NARROW, NARROW_Q, COARSE_W];

fn bound(cfg: &TextureSamplerConfig) -> f64 {
    match cfg.filter {
        Filter::Nearest => 0.0,
        Filter::Linear => {
            let m = ((1u64 << cfg.texel_bits) - 1) as f64;
            let fp = cfg.coord_frac_bits.max(1);
            let wb = cfg.weight_bits;
            let delta = if fp <= wb {
                0.0
            } else {
                match cfg.weight_rounding {
                    WeightRounding::Round | WeightRounding::RoundHalfEven => {
                        (-(wb as f64 + 1.0)).exp2()
                    }
                    WeightRounding::Truncate => (-(wb as f64)).exp2() - (-(fp as f64)).exp2(),
                }
            };
            let rounding = match cfg.filter_rounding {
                FilterRounding::ProductWeights => 0.5,
                FilterRounding::SuccessiveLerps => 0.5 * cfg.dims as f64,
            };
            rounding + cfg.dims as f64 * m * delta
        }
    }
}

/// splitmix64: a tiny seeded generator for texture contents and coordinates.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n.max(1)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Content {
    Random,
    /// 0 / max checkerboard over x + y + z + c: the worst neighbour differences.
    Checker,
    /// Random 0 / max texels.
    RandomExtremes,
}

fn make_texels(cfg: &TextureSamplerConfig, content: Content, rng: &mut Rng) -> Vec<u32> {
    let m = (1u64 << cfg.texel_bits) - 1;
    let [w, h, d] = cfg.size;
    let ch = cfg.channels;
    let mut v = Vec::with_capacity((w * h * d * ch) as usize);
    for z in 0..d {
        for y in 0..h {
            for x in 0..w {
                for c in 0..ch {
                    v.push(match content {
                        Content::Random => rng.below(m + 1) as u32,
                        Content::Checker => {
                            if (x + y + z + c) % 2 == 1 {
                                m as u32
                            } else {
                                0
                            }
                        }
                        Content::RandomExtremes => {
                            if rng.next() & 1 == 1 {
                                m as u32
                            } else {
                                0
                            }
                        }
                    });
                }
            }
        }
    }
    v
}

fn twin_of(cfg: &TextureSamplerConfig, texels: &[u32]) -> TextureRef {
    let f = match cfg.filter {
        Filter::Nearest => twin::Filter::Nearest,
        Filter::Linear => twin::Filter::Linear,
    };
    let a = cfg.address.map(|a| match a {
        AddressMode::Clamp => twin::Address::Clamp,
        AddressMode::Wrap => twin::Address::Wrap,
    });
    TextureRef::from_codes(
        cfg.dims as usize,
        cfg.size.map(|s| s as usize),
        cfg.channels as usize,
        texels,
        f,
        a,
    )
}

/// Compare one sample; returns the largest |error| over the channels.
fn check(u: &TextureSampler, r: &TextureRef, input: &TextureSamplerIn, b: f64) -> f64 {
    let mut ctr = Counters::default();
    let got = u.sample(input, &mut ctr);
    let scale = (u.coord_frac_bits() as f64).exp2();
    let mut coord = [0.0; 3];
    for (c, &word) in coord.iter_mut().zip(&input.coord).take(u.dims() as usize) {
        *c = u.coord_wire(word).0 as f64 / scale;
    }
    let want = r.sample(coord);
    let mut worst = 0.0f64;
    for c in 0..4 {
        if c >= u.channels() as usize {
            assert_eq!(got[c], 0, "unused channel {c} not 0");
            continue;
        }
        let err = (got[c] as f64 - want[c]).abs();
        assert!(
            err <= b + 1e-9,
            "{:?}: coord {:?} ({coord:?}) ch {c}: unit {} twin {} err {err} > bound {b}",
            u.config(),
            input.coord,
            got[c],
            want[c]
        );
        worst = worst.max(err);
    }
    worst
}

#[allow(clippy::too_many_arguments)]
fn config(
    dims: u32,
    size: [u32; 3],
    channels: u32,
    w: Widths,
    rounding: WeightRounding,
    filter: Filter,
    address: [AddressMode; 3],
    tpc: u32,
) -> TextureSamplerConfig {
    let mut s = [1u32; 3];
    s[..dims as usize].copy_from_slice(&size[..dims as usize]);
    TextureSamplerConfig {
        dims,
        size: s,
        channels,
        texel_bits: w.texel,
        coord_int_bits: 16,
        coord_frac_bits: w.frac,
        weight_bits: w.weight,
        weight_rounding: rounding,
        filter_rounding: FilterRounding::ProductWeights,
        filter,
        address,
        texels_per_clock: tpc,
    }
}

/// A random coordinate word: mostly within a few repeats of the texture, sometimes
/// near texel centres / edges, sometimes anything the wires carry.
fn coord_word(rng: &mut Rng, size: u32, int_bits: u32, frac: u32) -> i32 {
    let one = 1i64 << frac;
    let v = match rng.below(4) {
        0 => {
            // any word of the I + F wires
            let w = int_bits + frac;
            let lo = -(1i64 << (w - 1));
            lo + rng.below(1u64 << w) as i64
        }
        1 => {
            // near a texel centre or edge (± a few LSBs)
            let t = rng.below(3 * size as u64 + 4) as i64 - size as i64 - 2;
            let half = if rng.next() & 1 == 1 { one / 2 } else { 0 };
            t * one + half + rng.below(7) as i64 - 3
        }
        _ => {
            let span = 5 * size as i64 * one + 4 * one;
            rng.below(span as u64) as i64 - 2 * size as i64 * one - 2 * one
        }
    };
    let lim = 1i64 << (int_bits + frac - 1);
    v.clamp(-lim, lim - 1) as i32
}

/// `n` inputs with coordinate words on the first `axes` axes ([`coord_word`] at the
/// config's widths), one word in 8 anything at all (wider than the wires: masked,
/// counted as overflows).
fn wire_inputs(
    rng: &mut Rng,
    cfg: &TextureSamplerConfig,
    n: usize,
    axes: usize,
) -> Vec<TextureSamplerIn> {
    let (int_bits, frac) = (cfg.coord_int_bits, cfg.coord_frac_bits);
    (0..n)
        .map(|_| {
            let mut coord = [0i32; 3];
            for (k, c) in coord.iter_mut().enumerate().take(axes) {
                *c = if rng.below(8) == 0 {
                    rng.next() as i32
                } else {
                    coord_word(rng, cfg.size[k], int_bits, frac)
                };
            }
            TextureSamplerIn { coord }
        })
        .collect()
}

/// `kernel_batch_keep` under keep masks (none, all, random, and two with whole blocks
/// of 64 lanes, the lane form's blocks, left out: every other block, and all but
/// each block's last lane): the kept outputs are the drivers' `out`, and the
/// counters are the batch kernel's on every input, whatever is skipped.
fn assert_keep_agrees(
    u: &TextureSampler,
    inputs: &[TextureSamplerIn],
    out: &[[u32; 4]],
    rng: &mut Rng,
) {
    let mut want = Counters::default();
    let mut o = Vec::new();
    u.kernel_batch(&mut (), inputs, &mut o, &mut want);
    for mode in 0..5 {
        let keep: Vec<bool> = (0..inputs.len())
            .map(|i| match mode {
                0 => false,
                1 => true,
                2 => rng.below(2) == 0,
                3 => (i / 64) % 2 == 1,
                _ => i % 64 == 63,
            })
            .collect();
        let mut got = Vec::new();
        let mut c = Counters::default();
        u.kernel_batch_keep(inputs, &keep, &mut got, &mut c);
        assert_eq!(got.len(), inputs.len());
        assert_eq!(c, want, "kernel_batch_keep counters (mode {mode})");
        for (i, k) in keep.iter().enumerate() {
            if *k {
                assert_eq!(got[i], out[i], "kept output {i} (mode {mode})");
            }
        }
        // The lane form: kept lanes get channel 0 of the drivers' output, the others
        // stay as they were; the counters are the batch kernel's on every input.
        let s: Vec<i32> = inputs.iter().map(|x| x.coord[0]).collect();
        let t: Vec<i32> = inputs.iter().map(|x| x.coord[1]).collect();
        let mut lanes = vec![u32::MAX; inputs.len()];
        let mut c = Counters::default();
        let cfg = u.config();
        let applies = cfg.channels == 1
            && cfg.dims <= 2
            && cfg.filter_rounding == FilterRounding::ProductWeights;
        assert_eq!(
            u.sample_lanes_keep(&s, &t, |i| keep[i], &mut lanes, &mut c),
            applies,
            "sample_lanes_keep applies to one-channel 1D/2D product-weight configs only"
        );
        if applies {
            assert_eq!(c, want, "sample_lanes_keep counters (mode {mode})");
            for (i, k) in keep.iter().enumerate() {
                let expect = if *k { out[i][0] } else { u32::MAX };
                assert_eq!(lanes[i], expect, "lane {i} (mode {mode})");
            }
        } else {
            assert_eq!(c, Counters::default(), "nothing counted when refused");
            assert!(
                lanes.iter().all(|&v| v == u32::MAX),
                "nothing written when refused"
            );
        }
        if !inputs.is_empty() {
            let mut short = vec![0u32; inputs.len() - 1];
            let mut c = Counters::default();
            assert!(!u.sample_lanes_keep(&s, &t, |_| true, &mut short, &mut c));
            assert_eq!(c, Counters::default());
        }
    }
}

const FILTERS: [Filter; 2] = [Filter::Nearest, Filter::Linear];
const ROUNDINGS: [WeightRounding; 2] = [WeightRounding::Round, WeightRounding::Truncate];
const CONTENTS: [Content; 3] = [Content::Random, Content::Checker, Content::RandomExtremes];

fn address_strategy() -> impl Strategy<Value = [AddressMode; 3]> {
    prop::array::uniform3(prop::sample::select(vec![
        AddressMode::Clamp,
        AddressMode::Wrap,
    ]))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    /// 1D/2D/3D × nearest/linear × clamp/wrap × five width configs (default, wide,
    /// narrow, narrow with weight quantisation, coarse weights) × both roundings, on
    /// random, checkerboard and random-extreme textures of sizes 1 ..= 9 (NPOT too).
    #[test]
    fn within_derived_bound_of_twin(
        dims in 1u32..=3,
        size in prop::array::uniform3(1u32..=9),
        channels in 1u32..=4,
        widths in prop::sample::select(ALL_WIDTHS.to_vec()),
        rounding in prop::sample::select(ROUNDINGS.to_vec()),
        filter in prop::sample::select(FILTERS.to_vec()),
        address in address_strategy(),
        content in prop::sample::select(CONTENTS.to_vec()),
        seed in any::<u64>(),
    ) {
        let cfg = config(dims, size, channels, widths, rounding, filter, address, 4);
        let mut rng = Rng(seed);
        let texels = make_texels(&cfg, content, &mut rng);
        let u = TextureSampler::new(cfg.clone(), &texels).unwrap();
        let r = twin_of(&cfg, &texels);
        let b = bound(&cfg);
        for _ in 0..24 {
            let mut coord = [0i32; 3];
            for (c, &size) in coord.iter_mut().zip(&cfg.size).take(dims as usize) {
                *c = coord_word(&mut rng, size, 16, widths.frac);
            }
            check(&u, &r, &TextureSamplerIn { coord }, b);
        }
    }

    #[test]
    fn tick_and_span_drivers_agree(
        dims in 1u32..=3,
        size in prop::array::uniform3(1u32..=6),
        channels in 1u32..=4,
        widths in prop::sample::select(ALL_WIDTHS.to_vec()),
        rounding in prop::sample::select(ROUNDINGS.to_vec()),
        filter in prop::sample::select(FILTERS.to_vec()),
        address in address_strategy(),
        tpc in 1u32..=8,
        seed in any::<u64>(),
        n in 0usize..40,
    ) {
        let cfg = config(dims, size, channels, widths, rounding, filter, address, tpc);
        let mut rng = Rng(seed);
        let texels = make_texels(&cfg, Content::Random, &mut rng);
        let u = TextureSampler::new(cfg.clone(), &texels).unwrap();
        let inputs = wire_inputs(&mut rng, &cfg, n, 3);
        let out = common::assert_drivers_agree(&u, (), &inputs);
        assert_keep_agrees(&u, &inputs, &out, &mut rng);
    }

    /// llvmpipe's datapath (successive lerps, any weight rounding incl. half-to-even)
    /// over the same space: within its derived bound of the twin, and the tick, span
    /// and batch drivers agree.
    #[test]
    fn successive_lerps_within_derived_bound_and_drivers_agree(
        dims in 1u32..=3,
        size in prop::array::uniform3(1u32..=9),
        channels in 1u32..=4,
        widths in prop::sample::select(ALL_WIDTHS.to_vec()),
        rounding in prop::sample::select(vec![
            WeightRounding::Round, WeightRounding::Truncate, WeightRounding::RoundHalfEven,
        ]),
        address in address_strategy(),
        content in prop::sample::select(CONTENTS.to_vec()),
        tpc in 1u32..=8,
        seed in any::<u64>(),
    ) {
        let mut cfg = config(dims, size, channels, widths, rounding, Filter::Linear, address, tpc);
        cfg.filter_rounding = FilterRounding::SuccessiveLerps;
        let mut rng = Rng(seed);
        let texels = make_texels(&cfg, content, &mut rng);
        let u = TextureSampler::new(cfg.clone(), &texels).unwrap();
        let r = twin_of(&cfg, &texels);
        let b = bound(&cfg);
        let inputs: Vec<TextureSamplerIn> = (0..24)
            .map(|_| {
                let mut coord = [0i32; 3];
                for (c, &size) in coord.iter_mut().zip(&cfg.size).take(dims as usize) {
                    *c = coord_word(&mut rng, size, 16, widths.frac);
                }
                TextureSamplerIn { coord }
            })
            .collect();
        for input in &inputs {
            check(&u, &r, input, b);
        }
        let out = common::assert_drivers_agree(&u, (), &inputs);
        assert_keep_agrees(&u, &inputs, &out, &mut rng);
    }

    /// The lane form over several of its blocks (64 lanes) and up to power-of-two
    /// sizes of 64, coordinate words 20 ..= 32 bits wide (the 32-bit-lane form takes
    /// up to 30 and leaves wider ones to the packed form), every weight rounding: the
    /// kept lanes are the batch kernel's channel 0, the others untouched, the
    /// counters the batch kernel's.
    #[test]
    fn lane_form_agrees_with_the_batch_kernel_over_blocks(
        dims in 1u32..=2,
        size in prop::array::uniform3(prop::sample::select(vec![1u32, 2, 3, 5, 8, 16, 33, 64])),
        widths in prop::sample::select(ALL_WIDTHS.to_vec()),
        int_bits in prop::sample::select(vec![8u32, 12, 14, 16]),
        rounding in prop::sample::select(vec![
            WeightRounding::Round, WeightRounding::Truncate, WeightRounding::RoundHalfEven,
        ]),
        filter in prop::sample::select(FILTERS.to_vec()),
        address in address_strategy(),
        seed in any::<u64>(),
        n in 0usize..200,
    ) {
        let mut cfg = config(dims, size, 1, widths, rounding, filter, address, 4);
        cfg.coord_int_bits = int_bits;
        let mut rng = Rng(seed);
        let texels = make_texels(&cfg, Content::Random, &mut rng);
        let u = TextureSampler::new(cfg.clone(), &texels).unwrap();
        let inputs = wire_inputs(&mut rng, &cfg, n, dims as usize);
        let mut out = Vec::new();
        u.kernel_batch(&mut (), &inputs, &mut out, &mut Counters::default());
        assert_keep_agrees(&u, &inputs, &out, &mut rng);
    }

    /// Random, mostly invalid configs: never a panic; an error names a
    /// `texture_sampler.` field; a valid config refuses a wrong texel count.
    #[test]
    fn random_configs_never_panic_and_errors_name_fields(
        dims in 0u32..=4,
        size in prop::array::uniform3(prop_oneof![0u32..=10, 0u32..=5000, any::<u32>()]),
        channels in 0u32..=5,
        texel_bits in 0u32..=17,
        coord_int_bits in prop_oneof![0u32..=33, any::<u32>()],
        coord_frac_bits in prop_oneof![0u32..=17, any::<u32>()],
        weight_bits in 0u32..=17,
        rounding in prop::sample::select(ROUNDINGS.to_vec()),
        filter in prop::sample::select(FILTERS.to_vec()),
        address in address_strategy(),
        tpc in 0u32..=9,
    ) {
        let cfg = TextureSamplerConfig {
            dims, size, channels, texel_bits, coord_int_bits, coord_frac_bits, weight_bits,
            weight_rounding: rounding, filter_rounding: FilterRounding::ProductWeights,
            filter, address, texels_per_clock: tpc,
        };
        const FIELDS: [&str; 9] = [
            "texture_sampler.dims", "texture_sampler.size", "texture_sampler.channels",
            "texture_sampler.texel_bits", "texture_sampler.coord_int_bits",
            "texture_sampler.coord_frac_bits", "texture_sampler.weight_bits",
            "texture_sampler.texels_per_clock", "texture_sampler.texels",
        ];
        match cfg.validate() {
            Err(e) => {
                prop_assert!(FIELDS.contains(&e.field()), "{e}");
                let e2 = TextureSampler::new(cfg.clone(), &[]).unwrap_err();
                prop_assert_eq!(e2, e);
                let mut ctr = Counters::default();
                prop_assert!(cfg.texel_coord_from_normalized(0.5, 0, &mut ctr).is_err());
            }
            Ok(()) => {
                let e = TextureSampler::new(cfg.clone(), &[]).unwrap_err();
                prop_assert_eq!(e.field(), "texture_sampler.texels");
                let n = (cfg.texel_count() * cfg.channels as u64) as usize;
                if n <= 1 << 16 {
                    let mut texels = vec![0u32; n];
                    let u = TextureSampler::new(cfg.clone(), &texels).unwrap();
                    prop_assert_eq!(u.ram_bits(), cfg.ram_bits());
                    prop_assert_eq!(u.cost().ram_bits, cfg.ram_bits());
                    let t = u.timing();
                    prop_assert!(t.latency >= 1 && t.ii >= 1);
                    prop_assert!(u.cost().gates_nand2() > 0.0);
                    texels[n - 1] = 1 << texel_bits;
                    let e = TextureSampler::new(cfg.clone(), &texels).unwrap_err();
                    prop_assert_eq!(e.field(), "texture_sampler.texels");
                }
            }
        }
    }

    /// One field made invalid in an otherwise valid config: the error names it.
    #[test]
    fn single_invalid_field_is_named(which in 0usize..9, v in any::<u32>(), dims in 1u32..=3) {
        let mut cfg = TextureSamplerConfig { dims, size: [1; 3], ..TextureSamplerConfig::geforce() };
        for k in 0..dims as usize { cfg.size[k] = 16; }
        let field = match which {
            0 => { cfg.dims = [0, 4, v.max(4)][v as usize % 3]; "dims" }
            1 => { cfg.size[v as usize % dims as usize] = 0; "size" }
            2 => { cfg.size[v as usize % dims as usize] = 4097 + v % 100_000; "size" }
            3 => { if dims == 3 { cfg.size[2] = 0 } else { cfg.size[2] = 2 + v % 100 }; "size" }
            4 => { cfg.channels = [0, 5, v.max(5)][v as usize % 3]; "channels" }
            5 => { cfg.texel_bits = [0, 17, v.max(17)][v as usize % 3]; "texel_bits" }
            6 => { cfg.coord_frac_bits = 17 + v % 1000; "coord_frac_bits" }
            7 => { cfg.weight_bits = [0, 17, v.max(17)][v as usize % 3]; "weight_bits" }
            _ => { cfg.texels_per_clock = [0, 9, v.max(9)][v as usize % 3]; "texels_per_clock" }
        };
        let e = cfg.validate().unwrap_err();
        prop_assert_eq!(e.field(), format!("texture_sampler.{field}"));
    }

    /// The host helper quantises s · size to nearest within half an LSB, or
    /// saturates (counted); NaN / ±∞ name the field.
    #[test]
    fn normalized_coordinate_helper(
        s in prop_oneof![-10.0f64..10.0, any::<f64>()],
        size in 1u32..=4096,
        frac in 0u32..=16,
    ) {
        let mut ctr = Counters::default();
        let int_bits = 16;
        match texel_coord_from_normalized(s, size, int_bits, frac, &mut ctr) {
            Err(e) => {
                prop_assert!(!s.is_finite());
                prop_assert_eq!(e.field(), "texture_sampler.coord");
            }
            Ok(word) => {
                let lsb = (-(frac as f64)).exp2();
                let u = s * size as f64;
                let got = word as f64 * lsb;
                let max = 32768.0 - lsb;
                if u > max || u < -32768.0 {
                    prop_assert_eq!(ctr.saturations, 1);
                    prop_assert!(got == max || got == -32768.0);
                } else {
                    prop_assert!((got - u).abs() <= lsb / 2.0 + 1e-12 * u.abs());
                }
            }
        }
    }
}

/// All coordinate words of small 1D textures (power-of-two 8 and NPOT 5), every
/// filter, address mode and rounding, checkerboard and random texels.
#[test]
fn exhaustive_1d_over_all_coordinate_words() {
    let mut rng = Rng(1);
    let mut worst = Vec::new();
    for (w, int_bits) in [
        (DEFAULT, 5u32),
        (NARROW, 5),
        (NARROW_Q, 5),
        (COARSE_W, 5),
        (WIDE, 4),
    ] {
        // The 20-bit WIDE words: one size, linear, checkerboard (4 Mi samples).
        let wide = w.frac == WIDE.frac;
        let sizes: &[u32] = if wide { &[8] } else { &[8, 5] };
        let filters: &[Filter] = if wide { &[Filter::Linear] } else { &FILTERS };
        let contents: &[Content] = if wide {
            &[Content::Checker]
        } else {
            &[Content::Checker, Content::Random]
        };
        for &size in sizes {
            for &filter in filters {
                for addr in [AddressMode::Clamp, AddressMode::Wrap] {
                    for rounding in ROUNDINGS {
                        for &content in contents {
                            let mut cfg =
                                config(1, [size, 1, 1], 1, w, rounding, filter, [addr; 3], 4);
                            cfg.coord_int_bits = int_bits;
                            let texels = make_texels(&cfg, content, &mut rng);
                            let u = TextureSampler::new(cfg.clone(), &texels).unwrap();
                            let r = twin_of(&cfg, &texels);
                            let b = bound(&cfg);
                            let cw = int_bits + w.frac; // ≤ 20 bits: ≤ 2^20 words
                            let mut max_err = 0.0f64;
                            for word in -(1i64 << (cw - 1))..(1i64 << (cw - 1)) {
                                let input = TextureSamplerIn {
                                    coord: [word as i32, 0, 0],
                                };
                                max_err = max_err.max(check(&u, &r, &input, b));
                            }
                            if content == Content::Checker && size == 8 {
                                worst.push((w, filter, addr, rounding, max_err, b));
                            }
                        }
                    }
                }
            }
        }
    }
    for (w, f, a, r, e, b) in worst {
        println!("1D checker {w:?} {f:?} {a:?} {r:?}: max |err| {e:.4} (bound {b:.4})");
    }
}

/// A 3D trilinear (and nearest) sample over a fine grid of a 5 × 4 × 3 texture, clamp
/// and wrap, checkerboard and random, at the default and narrow-quantised widths.
#[test]
fn trilinear_5x4x3_on_a_grid() {
    let mut rng = Rng(3);
    for w in [DEFAULT, NARROW_Q, WIDE] {
        for filter in FILTERS {
            for addr in [AddressMode::Clamp, AddressMode::Wrap] {
                for content in [Content::Checker, Content::Random] {
                    let cfg = config(
                        3,
                        [5, 4, 3],
                        2,
                        w,
                        WeightRounding::Truncate,
                        filter,
                        [addr; 3],
                        4,
                    );
                    let texels = make_texels(&cfg, content, &mut rng);
                    let u = TextureSampler::new(cfg.clone(), &texels).unwrap();
                    let r = twin_of(&cfg, &texels);
                    let b = bound(&cfg);
                    // steps of 1/8 texel (plus an odd LSB offset) from −1.5 to size + 1.5
                    let step = 1i64 << (w.frac - 3);
                    let one = 1i64 << w.frac;
                    let axis = |s: u32| {
                        let lo = -3 * one / 2;
                        let hi = s as i64 * one + 3 * one / 2;
                        (0..)
                            .map(move |i| lo + i * step + (i % 3))
                            .take_while(move |&v| v < hi)
                    };
                    let mut max_err = 0.0f64;
                    for z in axis(3) {
                        for y in axis(4) {
                            for x in axis(5) {
                                let input = TextureSamplerIn {
                                    coord: [x as i32, y as i32, z as i32],
                                };
                                max_err = max_err.max(check(&u, &r, &input, b));
                            }
                        }
                    }
                    if filter == Filter::Nearest {
                        assert_eq!(max_err, 0.0);
                    }
                }
            }
        }
    }
}

/// Nearest is exact: the output is the stored texel at floor(u) after addressing.
#[test]
fn nearest_returns_stored_texels() {
    let cfg = TextureSamplerConfig {
        filter: Filter::Nearest,
        address: [AddressMode::Wrap, AddressMode::Clamp, AddressMode::Clamp],
        ..TextureSamplerConfig::geforce_2d(4, 3)
    };
    let texels: Vec<u32> = (0..12).map(|i| i * 20).collect();
    let u = TextureSampler::new(cfg, &texels).unwrap();
    let mut ctr = Counters::default();
    let at = |x: f64, y: f64, ctr: &mut Counters| {
        u.sample(
            &TextureSamplerIn {
                coord: [(x * 256.0) as i32, (y * 256.0) as i32, 0],
            },
            ctr,
        )[0]
    };
    assert_eq!(at(0.0, 0.0, &mut ctr), 0);
    assert_eq!(at(3.99, 2.5, &mut ctr), 11 * 20);
    assert_eq!(at(4.0, 2.5, &mut ctr), 8 * 20); // wraps in x
    assert_eq!(at(-0.01, 7.0, &mut ctr), 11 * 20); // wraps to x = 3, clamps y = 2
    assert_eq!(at(1.5, -9.0, &mut ctr), 20); // clamps y = 0
    assert_eq!(u.texel(3, 2, 0, 0), 220);
    assert_eq!(ctr.table_reads, 5);
    assert_eq!(ctr.mem_read_bytes, 5);
}

/// Bilinear at texel centres reproduces texels; half-way is the mean, rounded half up.
#[test]
fn bilinear_centres_and_midpoints() {
    let cfg = TextureSamplerConfig::geforce_2d(2, 2);
    let u = TextureSampler::new(cfg, &[0, 255, 100, 51]).unwrap();
    let mut ctr = Counters::default();
    let s = |x: i32, y: i32, ctr: &mut Counters| {
        u.sample(&TextureSamplerIn { coord: [x, y, 0] }, ctr)[0]
    };
    assert_eq!(s(128, 128, &mut ctr), 0);
    assert_eq!(s(384, 128, &mut ctr), 255);
    assert_eq!(s(128, 384, &mut ctr), 100);
    assert_eq!(s(384, 384, &mut ctr), 51);
    assert_eq!(s(256, 128, &mut ctr), 128); // 127.5 rounds up
    assert_eq!(s(256, 256, &mut ctr), 102); // (0 + 255 + 100 + 51)/4 = 101.5 → 102
    assert_eq!(ctr.table_reads, 6 * 4);
}

/// Words wider than the I + F wires are masked (sign-extended) and counted.
#[test]
fn wide_words_are_masked_and_counted() {
    let cfg = TextureSamplerConfig {
        address: [AddressMode::Wrap; 3],
        ..TextureSamplerConfig::geforce_2d(8, 8)
    };
    let texels: Vec<u32> = (0..64).map(|i| (i * 37 % 256) as u32).collect();
    let u = TextureSampler::new(cfg, &texels).unwrap();
    let mut rng = Rng(7);
    for _ in 0..1000 {
        let a = (rng.next() as i32) >> 8; // fits 24 bits
        let b = (rng.next() as i32) >> 8;
        let mut c0 = Counters::default();
        let want = u.sample(&TextureSamplerIn { coord: [a, b, 0] }, &mut c0);
        assert_eq!(c0.overflows, 0);
        let k = (rng.below(100) as i32 - 50) << 24;
        let mut c1 = Counters::default();
        let got = u.sample(
            &TextureSamplerIn {
                coord: [a.wrapping_add(k), b, 0],
            },
            &mut c1,
        );
        assert_eq!(got, want);
        assert_eq!(c1.overflows, u64::from(k != 0));
    }
    // Extreme words never panic.
    for w in [i32::MIN, i32::MAX, -1, 0] {
        let mut c = Counters::default();
        u.sample(&TextureSamplerIn { coord: [w, w, w] }, &mut c);
    }
}

/// Widest config: 16-bit texels, 16-bit weights, 3D: the u64 accumulator must not
/// overflow (debug overflow checks are on in the test profile) and stays in bound.
#[test]
fn widest_3d_config_fits_the_accumulator() {
    let cfg = TextureSamplerConfig {
        texel_bits: 16,
        weight_bits: 16,
        coord_frac_bits: 16,
        ..TextureSamplerConfig::geforce_3d(3, 3, 3)
    };
    let texels = vec![65535u32; 27];
    let u = TextureSampler::new(cfg.clone(), &texels).unwrap();
    let r = twin_of(&cfg, &texels);
    let mut rng = Rng(11);
    for _ in 0..2000 {
        let coord = [0, 1, 2].map(|_| coord_word(&mut rng, 3, 16, 16));
        check(&u, &r, &TextureSamplerIn { coord }, bound(&cfg));
        let mut c = Counters::default();
        assert_eq!(u.sample(&TextureSamplerIn { coord }, &mut c)[0], 65535);
    }
}

#[test]
fn counters_timing_and_ram_bits() {
    let cases = [
        (TextureSamplerConfig::geforce_1d(256), 2u64, 4u32, 1u32),
        (TextureSamplerConfig::geforce_2d(256, 256), 4, 4, 1),
        (TextureSamplerConfig::geforce_3d(16, 16, 16), 8, 5, 2),
        (
            TextureSamplerConfig {
                texels_per_clock: 1,
                ..TextureSamplerConfig::geforce_3d(16, 16, 16)
            },
            8,
            11,
            8,
        ),
        (
            TextureSamplerConfig {
                filter: Filter::Nearest,
                channels: 4,
                texel_bits: 5,
                ..TextureSamplerConfig::geforce_2d(16, 8)
            },
            1,
            2,
            1,
        ),
    ];
    for (cfg, reads, latency, ii) in cases {
        let n = (cfg.texel_count() * cfg.channels as u64) as usize;
        let u = TextureSampler::new(cfg.clone(), &vec![1; n]).unwrap();
        assert_eq!(u.timing().latency, latency, "{cfg:?}");
        assert_eq!(u.timing().ii, ii, "{cfg:?}");
        assert_eq!(
            u.ram_bits(),
            cfg.texel_count() * cfg.channels as u64 * cfg.texel_bits as u64
        );
        assert_eq!(u.cost().ram_bits, u.ram_bits());
        let mut ctr = Counters::default();
        u.sample(&TextureSamplerIn::default(), &mut ctr);
        assert_eq!(ctr.table_reads, reads);
        let bytes = (cfg.texel_bits * cfg.channels).div_ceil(8) as u64;
        assert_eq!(ctr.mem_read_bytes, reads * bytes);
        assert_eq!(ctr.saturations + ctr.overflows + ctr.underflows, 0);
    }
}

#[test]
fn zero_size_and_bad_texels_name_their_fields() {
    let cfg = TextureSamplerConfig::geforce_2d(0, 16);
    assert_eq!(
        TextureSampler::new(cfg, &[]).unwrap_err().field(),
        "texture_sampler.size"
    );
    let cfg = TextureSamplerConfig::geforce_1d(4);
    let e = TextureSampler::new(cfg.clone(), &[1, 2, 3]).unwrap_err();
    assert_eq!(e.field(), "texture_sampler.texels");
    let e = TextureSampler::new(cfg.clone(), &[1, 2, 3, 256]).unwrap_err();
    assert_eq!(e.field(), "texture_sampler.texels");
    // The first code too wide is named, not a full-scale one before it.
    let e = TextureSampler::new(cfg.clone(), &[255, 256, 300, 3]).unwrap_err();
    assert!(
        e.to_string()
            .contains("code 256 at index 1 does not fit 8 bits"),
        "{e}"
    );
    let mut u = TextureSampler::new(cfg, &[1, 2, 3, 255]).unwrap();
    assert!(u.load(&[9; 5]).is_err());
    assert_eq!(u.texel(3, 0, 0, 0), 255, "a failed load keeps the RAM");
    u.load(&[9; 4]).unwrap();
    assert_eq!(u.texel(3, 0, 0, 0), 9);
    // A texture larger than the coordinate's integer range is refused.
    let cfg = TextureSamplerConfig {
        coord_int_bits: 8,
        ..TextureSamplerConfig::geforce_1d(256)
    };
    assert_eq!(
        cfg.validate().unwrap_err().field(),
        "texture_sampler.coord_int_bits"
    );
    // 2^24 texels at most.
    let cfg = TextureSamplerConfig::geforce_3d(4096, 4096, 2);
    assert_eq!(cfg.validate().unwrap_err().field(), "texture_sampler.size");
}

#[test]
fn nan_and_infinite_normalized_coordinates_are_errors() {
    let cfg = TextureSamplerConfig::geforce_2d(64, 32);
    let mut ctr = Counters::default();
    for s in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let e = cfg.texel_coord_from_normalized(s, 1, &mut ctr).unwrap_err();
        assert_eq!(e.field(), "texture_sampler.coord");
        let e = cfg
            .input_from_normalized([0.5, s, 0.0], &mut ctr)
            .unwrap_err();
        assert_eq!(e.field(), "texture_sampler.coord");
    }
    assert!(cfg.texel_coord_from_normalized(0.5, 2, &mut ctr).is_err());
    assert_eq!(
        cfg.texel_coord_from_normalized(0.5, 1, &mut ctr).unwrap(),
        16 << 8
    );
    // End to end against the twin's normalised lookup.
    let texels: Vec<u32> = (0..64 * 32).map(|i| (i * 7 % 256) as u32).collect();
    let u = TextureSampler::new(cfg.clone(), &texels).unwrap();
    let r = twin_of(&cfg, &texels);
    let mut rng = Rng(5);
    for _ in 0..1000 {
        let s = [0, 1, 2].map(|_| rng.below(3000) as f64 / 1000.0 - 1.0);
        let input = cfg.input_from_normalized(s, &mut ctr).unwrap();
        let got = u.sample(&input, &mut ctr)[0] as f64;
        // The coordinate's own rounding (½ LSB of 2^−8 texel) moves the ideal value by
        // at most 2 · 255 · 2^−9 (d · M · δ with δ = 2^−9), plus the ½ LSB output rounding.
        let want = r.sample_normalized(s)[0];
        assert!((got - want).abs() <= 0.5 + 2.0 * 255.0 / 512.0 + 1e-9);
    }
}

/// Default latency / II / gates / RAM bits, printed for the datasheet
/// (`cargo test --test texture_sampler datasheet -- --nocapture`).
#[test]
fn datasheet_numbers() {
    let cfgs = [
        (
            "2D 256x256 L8 bilinear (geforce)",
            TextureSamplerConfig::geforce(),
        ),
        ("1D 256 L8 linear", TextureSamplerConfig::geforce_1d(256)),
        (
            "2D 256x256 L8 nearest",
            TextureSamplerConfig {
                filter: Filter::Nearest,
                ..TextureSamplerConfig::geforce()
            },
        ),
        (
            "2D 256x256 RGBA8 bilinear",
            TextureSamplerConfig {
                channels: 4,
                ..TextureSamplerConfig::geforce()
            },
        ),
        (
            "3D 64^3 L8 trilinear",
            TextureSamplerConfig::geforce_3d(64, 64, 64),
        ),
        (
            "3D 128^3 RGBA8 trilinear (thesis voxels)",
            TextureSamplerConfig {
                channels: 4,
                ..TextureSamplerConfig::geforce_3d(128, 128, 128)
            },
        ),
    ];
    for (name, cfg) in cfgs {
        let n = (cfg.texel_count() * cfg.channels as u64) as usize;
        let u = TextureSampler::new(cfg.clone(), &vec![0; n]).unwrap();
        let t = u.timing();
        let c = u.cost();
        println!(
            "{name}: latency {} II {} gates {:.0} NAND2 RAM bits {} bound {}",
            t.latency,
            t.ii,
            c.gates_nand2(),
            c.ram_bits,
            bound(&cfg)
        );
        for (part, g) in &c.breakdown {
            println!("    {part}: {g:.1}");
        }
    }
}

/// The texel address (z·h + y)·w + x costs a multiplier only for a factor that is not
/// a power of two: ·w when w is not (2D and 3D), z·h when h is not (3D). A power-of-two
/// w with any height is a concatenation (the cube map's F × 6F texture), so it costs the
/// same as the power-of-two texture of the same width and address width.
#[test]
fn address_cost_follows_the_power_of_two_factors() {
    let parts = |cfg: TextureSamplerConfig| -> Vec<String> {
        let n = cfg.size.iter().product::<u32>() as usize * cfg.channels as usize;
        let u = TextureSampler::new(cfg, &vec![0; n]).unwrap();
        u.cost()
            .breakdown
            .iter()
            .filter(|(p, _)| p.starts_with("address"))
            .map(|(p, _)| p.clone())
            .collect()
    };
    // 2D: w = 16 (power of two), 6·16 rows: free; w = 24: the row multiplier and adders.
    assert!(parts(TextureSamplerConfig::geforce_2d(16, 96)).is_empty());
    assert_eq!(
        parts(TextureSamplerConfig::geforce_2d(24, 16)),
        ["address: row base ·w", "address: base + index adders"]
    );
    // 3D: only h not a power of two → the plane multiplier; only w → the row one.
    assert_eq!(
        parts(TextureSamplerConfig::geforce_3d(16, 12, 16)),
        ["address: plane base z·h", "address: base + index adders"]
    );
    assert_eq!(
        parts(TextureSamplerConfig::geforce_3d(12, 16, 16)),
        ["address: row base ·w", "address: base + index adders"]
    );
    assert!(parts(TextureSamplerConfig::geforce_3d(16, 16, 12)).is_empty());
    // 16 × 96 (F × 6F at F = 16) costs what 16 × 128 does: the same width, 7-bit row
    // indices and 11-bit addresses. The cube map pays no address arithmetic.
    let g = |cfg: TextureSamplerConfig| {
        let n = cfg.size.iter().product::<u32>() as usize;
        TextureSampler::new(cfg, &vec![0; n])
            .unwrap()
            .cost()
            .gates_nand2()
    };
    assert_eq!(
        g(TextureSamplerConfig::geforce_2d(16, 96)),
        g(TextureSamplerConfig::geforce_2d(16, 128))
    );
}

#[test]
fn half_to_even_weight_ties_and_successive_lerps_by_hand() {
    // 1D, 4 texels, 9 fraction bits reduced to 8-bit weights: a fraction of p ending
    // in exactly half a weight LSB goes to the even weight (RoundHalfEven), up
    // (Round). Texels 0, 255: the output is the lerp of the weight alone.
    let base = TextureSamplerConfig {
        coord_frac_bits: 9,
        ..TextureSamplerConfig::geforce_1d(4)
    };
    let texels = [0, 255, 0, 255];
    let even = TextureSampler::new(base.clone().mesa_llvmpipe(), &texels).unwrap();
    let up = TextureSampler::new(base, &texels).unwrap();
    let mut ctr = Counters::default();
    // u = 1.5 + k/512: p = 1 + k/512, fraction k/512 = (k/2)/256 → weight k/2.
    for (k, w_even, w_up) in [(1, 0, 1), (3, 2, 2), (5, 2, 3), (7, 4, 4), (255, 128, 128)] {
        let word = (3 << 8) + k; // 1.5 · 2⁹ + k
        let coord = [word, 0, 0];
        // lerp(w; 255, 0) = 255 + ((−255·w + 128) >> 8)
        let want_even = 255 + ((-255 * w_even + 128) >> 8);
        assert_eq!(
            even.sample(&TextureSamplerIn { coord }, &mut ctr)[0] as i64,
            want_even,
            "k {k}"
        );
        // product weights: (255·(256 − w) + 128) >> 8
        let want_up = (255 * (256 - w_up) + 128) >> 8;
        assert_eq!(
            up.sample(&TextureSamplerIn { coord }, &mut ctr)[0] as i64,
            want_up,
            "k {k}"
        );
    }
    // A 2D successive lerp rounds each row before the t lerp: texels [[0, 1], [1, 0]]
    // at the centre (weights ½, ½): rows 0 + ((128 + 128) >> 8) = 1 and
    // 1 + ((−128 + 128) >> 8) = 1, then 1.
    let cfg2 = TextureSamplerConfig {
        filter_rounding: FilterRounding::SuccessiveLerps,
        ..TextureSamplerConfig::geforce_2d(2, 2)
    };
    let lerps = TextureSampler::new(cfg2, &[0, 1, 1, 0]).unwrap();
    let centre = TextureSamplerIn {
        coord: [256, 256, 0],
    };
    assert_eq!(lerps.sample(&centre, &mut ctr)[0], 1);
    // s = 0.5 + ¼ texel: w_s = 64; rows: 0 + ((64 + 128) >> 8) = 0 and
    // 1 + ((−64 + 128) >> 8) = 1; t weight 128: 0 + ((128 + 128) >> 8) = 1.
    let quarter = TextureSamplerIn {
        coord: [128 + 64, 256, 0],
    };
    assert_eq!(lerps.sample(&quarter, &mut ctr)[0], 1);
}

/// Every address-mode triple.
fn all_address_modes() -> Vec<[AddressMode; 3]> {
    let m = [AddressMode::Clamp, AddressMode::Wrap];
    let mut v = Vec::new();
    for a in m {
        for b in m {
            for c in m {
                v.push([a, b, c]);
            }
        }
    }
    v
}

/// The footprint is the set of texels the kernel reads, in its order, and its length
/// is the kernel's `table_reads`: on random inputs at every width, dimension, filter,
/// filter rounding and address mode, (1) the footprint's length per lookup is the
/// filter's texel count and its sum over a span the batch and word kernels'
/// `table_reads`; (2) the kernel's output is the footprint's texels under their
/// weights (the product-weight datapath rounded once; nearest: the one texel) on a
/// random texture; (3) on a one-hot texture (one texel at full scale, the rest 0)
/// the output is the weight the footprint gives that texel, for every texel, so each
/// corner with a weight is the texel the kernel read; (4) the lane form gives the
/// per-lookup footprints in lane order.
#[test]
fn footprint_is_what_the_kernel_reads() {
    let mut rng = Rng(0x7e17_f007);
    let sizes: [[u32; 3]; 3] = [[5, 3, 2], [4, 8, 2], [7, 1, 3]];
    let mut lookups = 0u64;
    for w in ALL_WIDTHS {
        for dims in 1..=3u32 {
            for filter in FILTERS {
                for fr in [
                    FilterRounding::ProductWeights,
                    FilterRounding::SuccessiveLerps,
                ] {
                    for address in all_address_modes() {
                        for size in sizes {
                            let mut cfg =
                                config(dims, size, 1, w, WeightRounding::Round, filter, address, 4);
                            cfg.filter_rounding = fr;
                            let texels = make_texels(&cfg, Content::Random, &mut rng);
                            let u = TextureSampler::new(cfg.clone(), &texels).unwrap();
                            let inputs: Vec<TextureSamplerIn> = (0..24)
                                .map(|_| TextureSamplerIn {
                                    coord: std::array::from_fn(|k| {
                                        coord_word(&mut rng, cfg.size[k], 16, w.frac)
                                    }),
                                })
                                .collect();
                            lookups += inputs.len() as u64;
                            footprint_checks(&u, &cfg, &texels, &inputs);
                        }
                    }
                }
            }
        }
    }
    assert!(lookups > 10_000, "{lookups} lookups checked");
}

fn footprint_checks(
    u: &TextureSampler,
    cfg: &TextureSamplerConfig,
    texels: &[u32],
    inputs: &[TextureSamplerIn],
) {
    let n_tex = cfg.texels_per_sample() as usize;
    let mut all = Vec::new();
    for x in inputs {
        let before = all.len();
        u.footprint(x, &mut all);
        assert_eq!(all.len() - before, n_tex, "{cfg:?}: texels per lookup");
        let c = u.corners(x);
        assert_eq!(c.texels(), &all[before..]);
        let count = cfg.size.iter().product::<u32>();
        assert!(c.texels().iter().all(|&t| t < count), "index in range");
    }
    // (1) table_reads of the batch and of the word kernel.
    let (mut cb, mut cw) = (Counters::default(), Counters::default());
    let mut out = Vec::new();
    u.kernel_batch(&mut (), inputs, &mut out, &mut cb);
    for x in inputs {
        u.kernel(&mut (), x, &mut cw);
    }
    assert_eq!(
        cb.table_reads,
        all.len() as u64,
        "{cfg:?}: batch table_reads"
    );
    assert_eq!(
        cw.table_reads,
        all.len() as u64,
        "{cfg:?}: word table_reads"
    );
    let d = cfg.dims;
    let shift = d * cfg.weight_bits;
    let full = (1u64 << cfg.texel_bits) - 1;
    for (x, o) in inputs.iter().zip(&out) {
        let c = u.corners(x);
        // (2) the output from the footprint's texels and weights.
        if cfg.filter == Filter::Nearest {
            assert_eq!(o[0], texels[c.texel[0] as usize], "{cfg:?}: nearest texel");
        } else if cfg.filter_rounding == FilterRounding::ProductWeights {
            let acc: u64 = (0..c.len as usize)
                .map(|k| texels[c.texel[k] as usize] as u64 * c.weight[k])
                .sum();
            assert_eq!(
                o[0] as u64,
                (acc + (1u64 << (shift - 1))) >> shift,
                "{cfg:?}: {x:?}"
            );
            assert_eq!(c.weight[..c.len as usize].iter().sum::<u64>(), 1 << shift);
        }
    }
    // (3) one-hot textures: every texel with a weight in the footprint is read.
    if cfg.filter == Filter::Linear && cfg.filter_rounding == FilterRounding::ProductWeights {
        let count = texels.len();
        for hot in 0..count {
            let mut t = vec![0u32; count];
            t[hot] = full as u32;
            let uh = TextureSampler::new(cfg.clone(), &t).unwrap();
            for x in inputs.iter().take(6) {
                let c = uh.corners(x);
                let wsum: u64 = (0..c.len as usize)
                    .filter(|&k| c.texel[k] as usize == hot)
                    .map(|k| c.weight[k])
                    .sum();
                let want = (full * wsum + (1u64 << (shift - 1))) >> shift;
                let got = uh.sample(x, &mut Counters::default())[0] as u64;
                assert_eq!(got, want, "{cfg:?}: one-hot texel {hot} at {x:?}");
            }
        }
    }
    // (4) the lane form.
    let s: Vec<i32> = inputs.iter().map(|x| x.coord[0]).collect();
    let t: Vec<i32> = inputs.iter().map(|x| x.coord[1]).collect();
    let r: Vec<i32> = inputs.iter().map(|x| x.coord[2]).collect();
    let mut lanes = Vec::new();
    let (tl, rl): (&[i32], &[i32]) = match d {
        1 => (&[], &[]),
        2 => (&t, &[]),
        _ => (&t, &r),
    };
    u.footprint_lanes(&s, tl, rl, &mut lanes);
    assert_eq!(lanes, all, "{cfg:?}: lane form");
}

proptest! {
    /// The texel RAM as `load` packs it: every texel at bit i·texel_bits, LSB first, as
    /// a `store_le` per texel writes it, at every width the unit takes (1 ..= 16 bits):
    /// those that divide the 64-bit word (whole texels per word) and those that
    /// straddle words; each texel reads back.
    #[test]
    fn load_packs_each_texel_as_a_store_le_writes_it(
        (tb, codes) in (1u32..=16).prop_flat_map(|tb| {
            (Just(tb), proptest::collection::vec(0..=(1u32 << tb) - 1, 1..150))
        })
    ) {
        use bitvec::prelude::*;
        let cfg = TextureSamplerConfig {
            texel_bits: tb,
            ..TextureSamplerConfig::geforce_1d(codes.len() as u32)
        };
        let u = TextureSampler::new(cfg, &codes).unwrap();
        let tbu = tb as usize;
        let mut want = bitvec![u64, Lsb0; 0; codes.len() * tbu];
        for (i, &v) in codes.iter().enumerate() {
            want[i * tbu..(i + 1) * tbu].store_le(v);
        }
        prop_assert_eq!(u.ram(), want.as_bitslice());
        for (i, &v) in codes.iter().enumerate() {
            prop_assert_eq!(u.texel(i as u32, 0, 0, 0), v);
        }
    }
}
