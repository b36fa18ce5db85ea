//! texture_combiner's Mesa mode against Mesa's software GL (OSMesa), bit for bit.
//!
//! libOSMesa is opened at run time (libloading) and every GL entry point comes from
//! `OSMesaGetProcAddress`. An RGBA 8-bit OSMesa context renders a 256 × 256 quad at
//! pixel-exact coordinates with three RGBA8 NEAREST textures holding Arg0, Arg1 and
//! Arg2 per texel; texture unit 2 runs the COMBINE stage under test and reads the three
//! through GL_ARB_texture_env_crossbar's TEXTURE0..TEXTURE2 sources (units 0 and 1 only
//! REPLACE), so no vertex interpolation or filtering touches an operand and every draw
//! puts 65 536 fragments (× 4 channels) through. One pass also reads CONSTANT and
//! PRIMARY_COLOR (flat shaded) instead of textures. glReadPixels reads the result, and
//! each channel must equal `TextureCombiner::combine` in `CombinerRounding::MesaFloat32`.
//!
//! Each Gallium driver runs in its own child process (the driver is chosen once per
//! process from GALLIUM_DRIVER): llvmpipe (OSMesa's default) and softpipe.
//!
//! No libOSMesa → a SKIP note on stderr and a pass (`apt-get install libosmesa6-dev`).
//! The library loads but a symbol, the context or a GL call fails → FAIL.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::units::texture_combiner::{
    CombineFunction, CombinerRounding, OperandAlpha, OperandRgb, TextureCombinerConfig,
    TextureCombinerIn,
};
use rtl_model::Counters;
use std::collections::BTreeMap;
use std::ffi::c_void;
use std::os::raw::c_int;

mod osmesa;
use osmesa::{gl, note, open_or_skip, run_child, unorm8_float, Context, GLenum, PIXELS, SIDE};

/// Where an argument of the stage under test comes from in GL.
#[derive(Clone, Copy, Debug)]
enum GlSource {
    /// TEXTUREk through the crossbar (k = 0, 1, 2).
    Texture(u32),
    /// TEXTURE_ENV_COLOR holding this colour.
    Constant([u8; 4]),
    /// The flat-shaded primary colour.
    Primary([u8; 4]),
}

/// One draw: the stage's functions, operands, scales, sources and the three textures.
struct Draw {
    label: &'static str,
    rgb: CombineFunction,
    alpha: CombineFunction,
    operand_rgb: [OperandRgb; 3],
    operand_alpha: [OperandAlpha; 3],
    rgb_scale: u32,
    alpha_scale: u32,
    sources: [GlSource; 3],
    textures: [Vec<[u8; 4]>; 3],
}

fn gl_function(f: CombineFunction) -> GLenum {
    match f {
        CombineFunction::Replace => gl::REPLACE,
        CombineFunction::Modulate => gl::MODULATE,
        CombineFunction::Add => gl::ADD,
        CombineFunction::AddSigned => gl::ADD_SIGNED,
        CombineFunction::Interpolate => gl::INTERPOLATE,
        CombineFunction::Subtract => gl::SUBTRACT,
        CombineFunction::Dot3Rgb => gl::DOT3_RGB,
        CombineFunction::Dot3Rgba => gl::DOT3_RGBA,
    }
}

fn gl_operand_rgb(o: OperandRgb) -> GLenum {
    match o {
        OperandRgb::SrcColor => gl::SRC_COLOR,
        OperandRgb::OneMinusSrcColor => gl::ONE_MINUS_SRC_COLOR,
        OperandRgb::SrcAlpha => gl::SRC_ALPHA,
        OperandRgb::OneMinusSrcAlpha => gl::ONE_MINUS_SRC_ALPHA,
    }
}

fn gl_operand_alpha(o: OperandAlpha) -> GLenum {
    match o {
        OperandAlpha::SrcAlpha => gl::SRC_ALPHA,
        OperandAlpha::OneMinusSrcAlpha => gl::ONE_MINUS_SRC_ALPHA,
    }
}

/// The fixed state of every draw: flat shading, and texture units 0 – 2 NEAREST,
/// enabled, REPLACE (unit 2's COMBINE stage is set per draw).
fn setup_stages(ctx: &Context) -> Result<(), String> {
    let g = &ctx.gl;
    // SAFETY: plain GL state calls on the current context.
    unsafe {
        (g.glShadeModel)(gl::FLAT);
        for (k, &t) in ctx.textures.iter().enumerate() {
            (g.glActiveTexture)(gl::TEXTURE0 + k as GLenum);
            (g.glBindTexture)(gl::TEXTURE_2D, t);
            (g.glTexParameteri)(gl::TEXTURE_2D, gl::TEXTURE_MIN_FILTER, gl::NEAREST as c_int);
            (g.glTexParameteri)(gl::TEXTURE_2D, gl::TEXTURE_MAG_FILTER, gl::NEAREST as c_int);
            (g.glEnable)(gl::TEXTURE_2D);
            (g.glTexEnvi)(gl::TEXTURE_ENV, gl::TEXTURE_ENV_MODE, gl::REPLACE as c_int);
        }
    }
    ctx.check("setup")
}

/// Render one draw and read the framebuffer back (RGBA per pixel, row 0 at y = 0).
fn render(ctx: &Context, d: &Draw) -> Result<Vec<[u8; 4]>, String> {
    let g = &ctx.gl;
    let env = |p: GLenum, v: GLenum| unsafe { (g.glTexEnvi)(gl::TEXTURE_ENV, p, v as c_int) };
    // SAFETY: GL calls on the current context; the texture and readback buffers
    // hold SIDE × SIDE RGBA texels.
    unsafe {
        for (k, tex) in d.textures.iter().enumerate() {
            (g.glActiveTexture)(gl::TEXTURE0 + k as GLenum);
            (g.glTexImage2D)(
                gl::TEXTURE_2D,
                0,
                gl::RGBA8 as c_int,
                SIDE as c_int,
                SIDE as c_int,
                0,
                gl::RGBA,
                gl::UNSIGNED_BYTE,
                tex.as_ptr() as *const c_void,
            );
        }
        (g.glActiveTexture)(gl::TEXTURE0 + 2);
        env(gl::TEXTURE_ENV_MODE, gl::COMBINE);
        env(gl::COMBINE_RGB, gl_function(d.rgb));
        env(gl::COMBINE_ALPHA, gl_function(d.alpha));
        let mut primary = [1.0f32; 4];
        for (i, s) in d.sources.iter().enumerate() {
            let src = match *s {
                GlSource::Texture(k) => gl::TEXTURE0 + k,
                GlSource::Constant(c) => {
                    let f = c.map(unorm8_float);
                    (g.glTexEnvfv)(gl::TEXTURE_ENV, gl::TEXTURE_ENV_COLOR, f.as_ptr());
                    gl::CONSTANT
                }
                GlSource::Primary(c) => {
                    primary = c.map(unorm8_float);
                    gl::PRIMARY_COLOR
                }
            };
            env(gl::SOURCE0_RGB + i as GLenum, src);
            env(gl::SOURCE0_ALPHA + i as GLenum, src);
            env(
                gl::OPERAND0_RGB + i as GLenum,
                gl_operand_rgb(d.operand_rgb[i]),
            );
            env(
                gl::OPERAND0_ALPHA + i as GLenum,
                gl_operand_alpha(d.operand_alpha[i]),
            );
        }
        env(gl::RGB_SCALE, d.rgb_scale);
        env(gl::ALPHA_SCALE, d.alpha_scale);
        (g.glClear)(gl::COLOR_BUFFER_BIT);
        (g.glColor4f)(primary[0], primary[1], primary[2], primary[3]);
        (g.glBegin)(gl::QUADS);
        for (x, y) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            for k in 0..3 {
                (g.glMultiTexCoord2f)(gl::TEXTURE0 + k, x, y);
            }
            (g.glVertex2f)(x * SIDE as f32, y * SIDE as f32);
        }
        (g.glEnd)();
        (g.glFinish)();
    }
    ctx.check(&format!("drawing {}", d.label))?;
    ctx.read_pixels()
}

/// The unit in its Mesa mode, configured as the draw's stage: Arg0..Arg2 on the
/// texture, constant and primary-colour buses.
fn unit_config(d: &Draw) -> TextureCombinerConfig {
    let mut cfg =
        TextureCombinerConfig::with_functions(8, d.rgb, d.alpha, CombinerRounding::MesaFloat32);
    cfg.operand_rgb = d.operand_rgb;
    cfg.operand_alpha = d.operand_alpha;
    cfg.rgb_scale = d.rgb_scale;
    cfg.alpha_scale = d.alpha_scale;
    cfg
}

fn unit_input(d: &Draw, p: usize) -> TextureCombinerIn {
    let arg = |i: usize| -> [u32; 4] {
        match d.sources[i] {
            GlSource::Texture(k) => d.textures[k as usize][p],
            GlSource::Constant(c) | GlSource::Primary(c) => c,
        }
        .map(u32::from)
    };
    TextureCombinerIn {
        texture: arg(0),
        constant: arg(1),
        primary_color: arg(2),
        previous: [0; 4],
    }
}

/// Every (a, b) pair: Arg0 = [a, b, 255 − a, a], Arg1 = [b, a, b, 255 − b] at texel
/// (a, b), so each channel sees all 65 536 pairs.
fn pair_textures(arg2: Vec<[u8; 4]>) -> [Vec<[u8; 4]>; 3] {
    let mut t0 = vec![[0u8; 4]; PIXELS];
    let mut t1 = vec![[0u8; 4]; PIXELS];
    for y in 0..SIDE {
        for x in 0..SIDE {
            let (a, b) = (x as u8, y as u8);
            t0[y * SIDE + x] = [a, b, 255 - a, a];
            t1[y * SIDE + x] = [b, a, b, 255 - b];
        }
    }
    [t0, t1, arg2]
}

fn random_texture(rng: &mut ChaCha8Rng) -> Vec<[u8; 4]> {
    (0..PIXELS).map(|_| rng.random()).collect()
}

const CROSSBAR: [GlSource; 3] = [
    GlSource::Texture(0),
    GlSource::Texture(1),
    GlSource::Texture(2),
];

fn draw(label: &'static str, f: CombineFunction, scale: u32, textures: [Vec<[u8; 4]>; 3]) -> Draw {
    Draw {
        label,
        rgb: f,
        alpha: if f.is_dot3() {
            CombineFunction::Modulate
        } else {
            f
        },
        operand_rgb: [OperandRgb::SrcColor; 3],
        operand_alpha: [OperandAlpha::SrcAlpha; 3],
        rgb_scale: scale,
        alpha_scale: scale,
        sources: CROSSBAR,
        textures,
    }
}

/// The draws: every 8-bit pair for the two-argument functions at every scale; every
/// ADD_SIGNED operand mapping; every INTERPOLATE triple at scale 1; ≥ 10⁶ random DOT3
/// cases; CONSTANT and PRIMARY_COLOR sources; random whole configurations.
fn draws(rng: &mut ChaCha8Rng, interpolate_stride: usize) -> Vec<Draw> {
    let mut v = Vec::new();
    let two = [
        ("REPLACE", CombineFunction::Replace),
        ("MODULATE", CombineFunction::Modulate),
        ("ADD", CombineFunction::Add),
        ("ADD_SIGNED", CombineFunction::AddSigned),
        ("SUBTRACT", CombineFunction::Subtract),
    ];
    for (label, f) in two {
        for s in [1, 2, 4] {
            v.push(draw(label, f, s, pair_textures(random_texture(rng))));
        }
    }
    for o0 in OperandRgb::ALL {
        for o1 in OperandRgb::ALL {
            let mut d = draw(
                "ADD_SIGNED",
                CombineFunction::AddSigned,
                1,
                pair_textures(random_texture(rng)),
            );
            d.operand_rgb = [o0, o1, OperandRgb::SrcColor];
            let alpha = |o: OperandRgb| match o {
                OperandRgb::SrcColor | OperandRgb::SrcAlpha => OperandAlpha::SrcAlpha,
                _ => OperandAlpha::OneMinusSrcAlpha,
            };
            d.operand_alpha = [alpha(o0), alpha(o1), OperandAlpha::SrcAlpha];
            v.push(d);
        }
    }
    // INTERPOLATE: channel k's Arg2 runs over codes 64k .. 64k + 63 in 64 draws, so
    // every (Arg0, Arg1, Arg2) triple goes through once; `interpolate_stride` 8 (the
    // slower softpipe) takes every 8th draw, 2²¹ triples.
    for c in (0..64u8).step_by(interpolate_stride) {
        let arg2 = vec![[c, c + 64, c + 128, c + 192]; PIXELS];
        v.push(draw(
            "INTERPOLATE",
            CombineFunction::Interpolate,
            1,
            pair_textures(arg2),
        ));
    }
    for s in [2, 4] {
        for _ in 0..2 {
            let t = [
                random_texture(rng),
                random_texture(rng),
                random_texture(rng),
            ];
            v.push(draw("INTERPOLATE", CombineFunction::Interpolate, s, t));
        }
    }
    for (label, f) in [
        ("DOT3_RGB", CombineFunction::Dot3Rgb),
        ("DOT3_RGBA", CombineFunction::Dot3Rgba),
    ] {
        let per_scale = if f == CombineFunction::Dot3Rgb { 6 } else { 1 };
        for s in [1, 2, 4] {
            for _ in 0..per_scale {
                let t = [
                    random_texture(rng),
                    random_texture(rng),
                    random_texture(rng),
                ];
                let mut d = draw(label, f, s, t);
                d.alpha_scale = [4, 1, 2][s.trailing_zeros() as usize];
                v.push(d);
            }
        }
    }
    for (label, f) in [
        ("ADD_SIGNED", CombineFunction::AddSigned),
        ("MODULATE", CombineFunction::Modulate),
        ("INTERPOLATE", CombineFunction::Interpolate),
    ] {
        for _ in 0..4 {
            let mut d = draw(label, f, 1, pair_textures(random_texture(rng)));
            d.sources = [
                GlSource::Texture(0),
                GlSource::Constant(rng.random()),
                GlSource::Primary(rng.random()),
            ];
            v.push(d);
        }
    }
    for _ in 0..16 {
        let rgb = CombineFunction::ALL[rng.random_range(0..8)];
        let alpha = CombineFunction::ALPHA[rng.random_range(0..6)];
        let t = [
            random_texture(rng),
            random_texture(rng),
            random_texture(rng),
        ];
        let mut d = draw("random configuration", rgb, 1, t);
        d.alpha = alpha;
        d.operand_rgb = std::array::from_fn(|_| OperandRgb::ALL[rng.random_range(0..4)]);
        d.operand_alpha = std::array::from_fn(|_| OperandAlpha::ALL[rng.random_range(0..2)]);
        d.rgb_scale = [1, 2, 4][rng.random_range(0..3)];
        d.alpha_scale = [1, 2, 4][rng.random_range(0..3)];
        v.push(d);
    }
    v
}

#[derive(Default)]
struct Tally {
    cases: u64,
    mismatches: u64,
    examples: Vec<String>,
}

enum Outcome {
    Skipped(String),
    Ran(String, BTreeMap<&'static str, Tally>),
}

/// Run every draw under the current process's driver.
fn run_oracle() -> Result<Outcome, String> {
    // No libOSMesa, or a libOSMesa built without the requested driver (it falls back
    // to another): a skip of this driver, not a failure (the other child still runs).
    let (ctx, renderer) = match open_or_skip() {
        Ok(c) => c,
        Err(why) => return Ok(Outcome::Skipped(why)),
    };
    setup_stages(&ctx)?;
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    // softpipe interprets each fragment (≈ 2.5× llvmpipe's time): a sample of the
    // exhaustive INTERPOLATE sweep keeps the test file within its time budget.
    let stride = if renderer.starts_with("softpipe") {
        8
    } else {
        1
    };
    let mut tallies: BTreeMap<&'static str, Tally> = BTreeMap::new();
    for d in draws(&mut rng, stride) {
        let got = render(&ctx, &d)?;
        let unit = unit_config(&d).build().map_err(|e| e.to_string())?;
        let t = tallies.entry(d.label).or_default();
        let mut ctr = Counters::default();
        for (p, g) in got.iter().enumerate() {
            let input = unit_input(&d, p);
            let want = unit.combine(&input, &mut ctr);
            for ch in 0..4 {
                t.cases += 1;
                if want[ch] != g[ch] as u32 {
                    t.mismatches += 1;
                    if t.examples.len() < 5 {
                        t.examples.push(format!(
                            "rgb {:?} alpha {:?} ops {:?}/{:?} scales {}/{} ch {ch}: {input:?} → Mesa {} unit {}",
                            d.rgb, d.alpha, d.operand_rgb, d.operand_alpha, d.rgb_scale, d.alpha_scale, g[ch], want[ch]
                        ));
                    }
                }
            }
        }
    }
    Ok(Outcome::Ran(renderer, tallies))
}

#[test]
#[ignore = "run by llvmpipe_is_bit_exact / softpipe_is_bit_exact in a child process"]
fn oracle_child() {
    match run_oracle() {
        Err(e) => panic!("OSMesa oracle failed: {e}"),
        Ok(Outcome::Skipped(why)) => osmesa::tools::skip(&why),
        Ok(Outcome::Ran(renderer, tallies)) => {
            let mut text = format!("texture_combiner vs OSMesa [{renderer}]\n");
            let mut total = 0;
            for (label, t) in &tallies {
                text += &format!(
                    "  {label:<22} {:>10} channel results, {} mismatches\n",
                    t.cases, t.mismatches
                );
                for e in &t.examples {
                    text += &format!("      {e}\n");
                }
                total += t.mismatches;
            }
            note(&text);
            assert_eq!(total, 0, "the unit's Mesa mode differs from OSMesa");
        }
    }
}

#[test]
fn llvmpipe_is_bit_exact() {
    run_child("oracle_child", "llvmpipe");
}

#[test]
fn softpipe_is_bit_exact() {
    run_child("oracle_child", "softpipe");
}
