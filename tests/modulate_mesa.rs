//! The two-texture modulate chain against Mesa's software GL (OSMesa), bit for bit:
//! `ModulateChain` in `ChainRounding::Fused` must equal what Mesa renders for
//! primary colour × texture 0 × texture 1, and the default `PerStage` chain's
//! difference from Mesa is measured and printed (docs/shading.md records it).
//!
//! Each draw puts one GL_POINT on every pixel of a 256 × 256 RGBA8 OSMesa context
//! (tests/osmesa): its colour is a random 8-bit RGBA colour handed to GL as
//! fl(c · fl(1/255)) (the float Mesa's texture fetch makes of a code), its texture
//! coordinates are the centre of texel (x, y) of two random 256 × 256 RGBA8 NEAREST
//! textures. Texture units 0 and 1 MODULATE (GL_MODULATE, and in one draw COMBINE
//! MODULATE of TEXTURE and PREVIOUS), so every channel of every pixel is one random
//! (colour, texel 0, texel 1) triple: 262 144 triples a draw, 786 432 in all.
//!
//! Each Gallium driver runs in its own child process: llvmpipe and softpipe.
//! No libOSMesa → a SKIP note on stderr and a pass (`apt-get install libosmesa6-dev`).

mod osmesa;

use osmesa::{gl, note, open_or_note_skip, run_child, unorm8_float, Point, PIXELS, SIDE};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::units::modulate::{ChainRounding, ModulateChain, ModulateMode};

#[derive(Default)]
struct Tally {
    triples: u64,
    fused_mismatches: u64,
    per_stage_differ: u64,
    per_stage_max: u32,
    /// round(a·b·c / 255²) in exact integers, once: not Mesa's float.
    exact_once_differ: u64,
    examples: Vec<String>,
}

/// One draw: MODULATE chain under GL_MODULATE (`combine` false) or COMBINE.
fn run_draw(
    ctx: &osmesa::Context,
    rng: &mut ChaCha8Rng,
    combine: bool,
    t: &mut Tally,
) -> Result<(), String> {
    let tex: [Vec<[u8; 4]>; 2] =
        std::array::from_fn(|_| (0..PIXELS).map(|_| rng.random()).collect());
    for (k, texels) in tex.iter().enumerate() {
        ctx.texture(
            k as u32,
            SIDE,
            SIDE,
            texels,
            gl::NEAREST,
            [gl::CLAMP_TO_EDGE; 2],
        )?;
        if combine {
            ctx.env(k as u32, gl::TEXTURE_ENV_MODE, gl::COMBINE);
            ctx.env(k as u32, gl::COMBINE_RGB, gl::MODULATE);
            ctx.env(k as u32, gl::COMBINE_ALPHA, gl::MODULATE);
            // SOURCE0 = TEXTURE, SOURCE1 = PREVIOUS (the primary colour at unit 0).
            ctx.env(k as u32, gl::SOURCE0_RGB, gl::TEXTURE);
            ctx.env(k as u32, gl::SOURCE0_ALPHA, gl::TEXTURE);
            ctx.env(k as u32, gl::SOURCE0_RGB + 1, gl::PREVIOUS);
            ctx.env(k as u32, gl::SOURCE0_ALPHA + 1, gl::PREVIOUS);
        } else {
            ctx.env(k as u32, gl::TEXTURE_ENV_MODE, gl::MODULATE);
        }
    }
    let colors: Vec<[u8; 4]> = (0..PIXELS).map(|_| rng.random()).collect();
    let points: Vec<Point> = (0..PIXELS)
        .map(|p| {
            let (x, y) = ((p % SIDE) as f32 + 0.5, (p / SIDE) as f32 + 0.5);
            let st = [x / SIDE as f32, y / SIDE as f32]; // texel (x, y)'s centre, exact
            Point {
                color: colors[p].map(unorm8_float),
                tex: [st, st],
            }
        })
        .collect();
    let got = ctx.draw_points(&points, 2)?;
    let fused = ModulateChain::new(8, ModulateMode::Exact, ChainRounding::Fused)
        .map_err(|e| e.to_string())?;
    let per_stage = ModulateChain::geforce();
    for (p, g) in got.iter().enumerate() {
        for ch in 0..4 {
            let ops = [
                colors[p][ch] as u32,
                tex[0][p][ch] as u32,
                tex[1][p][ch] as u32,
            ];
            let mesa = g[ch] as u32;
            t.triples += 1;
            let want = fused.apply(&ops);
            if want != mesa {
                t.fused_mismatches += 1;
                if t.examples.len() < 5 {
                    t.examples
                        .push(format!("{ops:?} ch {ch}: Mesa {mesa}, fused {want}"));
                }
            }
            let d = per_stage.apply(&ops).abs_diff(mesa);
            t.per_stage_differ += u64::from(d != 0);
            t.per_stage_max = t.per_stage_max.max(d);
            let x = ops.iter().map(|&c| c as u64).product::<u64>(); // u24
            let once = ((2 * x + 65025) / (2 * 65025)) as u32; // no ties: 65025 is odd
            t.exact_once_differ += u64::from(once != mesa);
        }
    }
    Ok(())
}

#[test]
#[ignore = "run by llvmpipe_* / softpipe_* in a child process"]
fn oracle_child() {
    let Some((ctx, renderer)) = open_or_note_skip() else {
        return;
    };
    let mut rng = ChaCha8Rng::seed_from_u64(16);
    let mut t = Tally::default();
    for combine in [false, true, false] {
        run_draw(&ctx, &mut rng, combine, &mut t).unwrap_or_else(|e| panic!("{e}"));
    }
    let share = |n: u64| 100.0 * n as f64 / t.triples as f64;
    let mut text = format!(
        "modulate chain (colour × texture 0 × texture 1) vs OSMesa [{renderer}]\n\
         \x20 {} triples; fused: {} mismatches\n\
         \x20 per_stage (default): {} differ ({:.2} %), max |Δ| {} LSB\n\
         \x20 exact integer single rounding: {} differ ({:.4} %)\n",
        t.triples,
        t.fused_mismatches,
        t.per_stage_differ,
        share(t.per_stage_differ),
        t.per_stage_max,
        t.exact_once_differ,
        share(t.exact_once_differ),
    );
    for e in &t.examples {
        text += &format!("    {e}\n");
    }
    note(&text);
    assert!(t.triples >= 400_000, "too few triples: {}", t.triples);
    assert_eq!(t.fused_mismatches, 0, "the fused chain differs from OSMesa");
}

#[test]
fn llvmpipe_fused_chain_is_bit_exact() {
    run_child("oracle_child", "llvmpipe");
}

#[test]
fn softpipe_fused_chain_is_bit_exact() {
    run_child("oracle_child", "softpipe");
}
