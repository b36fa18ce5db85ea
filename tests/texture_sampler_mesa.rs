//! The bilinear sampler against Mesa's llvmpipe (OSMesa), bit for bit:
//! `TextureSampler` configured by `TextureSamplerConfig::mesa_llvmpipe` (successive
//! 8-bit lerps, half-to-even coordinate ties) must equal what llvmpipe renders for a
//! GL_LINEAR RGBA8 texture, and the default datapath's (product weights, one rounding
//! half up) difference from it is measured and printed (docs/shading.md records it).
//!
//! Each draw uploads one random RGBA8 texture (power-of-two sides, so s · 256·size is
//! exact in binary32) with GL_LINEAR and a wrap mode per axis, and puts one GL_POINT
//! on every pixel of a 256 × 256 OSMesa context (tests/osmesa) with its own texture
//! coordinate — constant over the point, so no interpolation touches it. A coordinate
//! is a random texel-space word u with 16 fraction bits, |u| < 255 texels, handed to
//! GL as the float s = u / size (exact); a quarter of them are exact ties of the
//! 8-bit weight (u·2⁸ ends in ½), an eighth have no bits below the weight. The unit
//! samples the same words (coord_frac_bits 16, weight_bits 8). 65 536 cases a draw,
//! 262 144 in all, each 4 channels.
//!
//! llvmpipe only: softpipe filters in binary32, a different datapath (its difference
//! is printed by `softpipe_difference_is_measured`, not asserted).
//! No libOSMesa → a SKIP note on stderr and a pass (`apt-get install libosmesa6-dev`).

mod osmesa;

use osmesa::{gl, note, open_or_note_skip, run_child, GLenum, Point, PIXELS};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::units::texture_sampler::{
    AddressMode, Filter, TextureSampler, TextureSamplerConfig, TextureSamplerIn,
};
use rtl_model::Counters;

const FRAC: u32 = 16;

/// The draws: (width, height, wrap s, wrap t).
const DRAWS: [(u32, u32, AddressMode, AddressMode); 4] = [
    (256, 256, AddressMode::Clamp, AddressMode::Clamp),
    (64, 64, AddressMode::Wrap, AddressMode::Wrap),
    (128, 32, AddressMode::Wrap, AddressMode::Clamp),
    (16, 256, AddressMode::Clamp, AddressMode::Wrap),
];

fn gl_wrap(a: AddressMode) -> GLenum {
    match a {
        AddressMode::Clamp => gl::CLAMP_TO_EDGE,
        AddressMode::Wrap => gl::REPEAT,
    }
}

/// A texel-space word s(16).16 on an axis of `n` texels: |u| < 255 texels, from
/// −min(n, 64) up; a quarter are exact 8-bit-weight ties, an eighth 8-bit exact.
fn coord_word(rng: &mut ChaCha8Rng, n: u32) -> i32 {
    let lo = -(n.min(64) as i32) << FRAC;
    let hi = ((2 * n).min(255) as i32) << FRAC;
    let w = rng.random_range(lo..hi);
    match rng.random_range(0..8) {
        0 | 1 => (w & !0xff) | 0x80,
        2 => w & !0xff,
        _ => w,
    }
}

#[derive(Default)]
struct Tally {
    cases: u64,
    channels: u64,
    mesa_mismatches: u64,
    default_differ: u64,
    default_max: u32,
    examples: Vec<String>,
}

#[test]
#[ignore = "run by llvmpipe_bilinear_is_bit_exact in a child process"]
fn oracle_child() {
    let Some((ctx, renderer)) = open_or_note_skip() else {
        return;
    };
    let assert_exact = renderer.starts_with("llvmpipe");
    let mut rng = ChaCha8Rng::seed_from_u64(1616);
    let mut t = Tally::default();
    for (w, h, ws, wt) in DRAWS {
        let texels: Vec<[u8; 4]> = (0..w * h).map(|_| rng.random()).collect();
        ctx.texture(
            0,
            w as usize,
            h as usize,
            &texels,
            gl::LINEAR,
            [gl_wrap(ws), gl_wrap(wt)],
        )
        .unwrap_or_else(|e| panic!("{e}"));
        ctx.env(0, gl::TEXTURE_ENV_MODE, gl::REPLACE);
        let words: Vec<[i32; 2]> = (0..PIXELS)
            .map(|_| [coord_word(&mut rng, w), coord_word(&mut rng, h)])
            .collect();
        let points: Vec<Point> = words
            .iter()
            .map(|&[u, v]| {
                // u / (size · 2¹⁶): |u| < 2²⁴, so exact in binary32.
                let s = (u as f64 / (w as f64 * 65536.0)) as f32;
                let t = (v as f64 / (h as f64 * 65536.0)) as f32;
                Point {
                    color: [1.0; 4],
                    tex: [[s, t], [0.0, 0.0]],
                }
            })
            .collect();
        let got = ctx
            .draw_points(&points, 1)
            .unwrap_or_else(|e| panic!("{e}"));
        let cfg = TextureSamplerConfig {
            channels: 4,
            coord_frac_bits: FRAC,
            address: [ws, wt, AddressMode::Clamp],
            filter: Filter::Linear,
            ..TextureSamplerConfig::geforce_2d(w, h)
        };
        let codes: Vec<u32> = texels.iter().flatten().map(|&c| c as u32).collect();
        let mesa_unit = TextureSampler::new(cfg.clone().mesa_llvmpipe(), &codes).unwrap();
        let default_unit = TextureSampler::new(cfg, &codes).unwrap();
        let mut ctr = Counters::default();
        for (g, &[u, v]) in got.iter().zip(&words) {
            let input = TextureSamplerIn { coord: [u, v, 0] };
            let m = mesa_unit.sample(&input, &mut ctr);
            let d = default_unit.sample(&input, &mut ctr);
            t.cases += 1;
            for ch in 0..4 {
                let mesa = g[ch] as u32;
                t.channels += 1;
                if m[ch] != mesa {
                    t.mesa_mismatches += 1;
                    if t.examples.len() < 8 {
                        t.examples.push(format!(
                            "{w}×{h} {ws:?}/{wt:?} u {u:#x} v {v:#x} ch {ch}: Mesa {mesa}, unit {}",
                            m[ch]
                        ));
                    }
                }
                let diff = d[ch].abs_diff(mesa);
                t.default_differ += u64::from(diff != 0);
                t.default_max = t.default_max.max(diff);
            }
        }
    }
    let mut text = format!(
        "texture_sampler bilinear vs OSMesa [{renderer}]\n\
         \x20 {} cases ({} channel results); mesa_llvmpipe: {} mismatches\n\
         \x20 default (product weights, half up): {} channels differ ({:.2} %), max |Δ| {} LSB\n",
        t.cases,
        t.channels,
        t.mesa_mismatches,
        t.default_differ,
        100.0 * t.default_differ as f64 / t.channels as f64,
        t.default_max,
    );
    for e in &t.examples {
        text += &format!("    {e}\n");
    }
    note(&text);
    assert!(t.cases >= 100_000, "too few cases: {}", t.cases);
    if assert_exact {
        assert_eq!(t.mesa_mismatches, 0, "mesa_llvmpipe differs from llvmpipe");
    }
}

#[test]
fn llvmpipe_bilinear_is_bit_exact() {
    run_child("oracle_child", "llvmpipe");
}

/// softpipe filters in binary32: its difference from both modes is printed, not
/// asserted (the child passes whatever it measures, unless GL fails).
#[test]
fn softpipe_difference_is_measured() {
    run_child("oracle_child", "softpipe");
}
