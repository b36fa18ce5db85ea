//! The `Texture_shadow_comparator` suite (src/tests/texture_shadow_comparator_tests.cpp
//! in nxdk_pgraph_tests): the raw-value tests, the captures named
//! `{2,3}R{16,24}_<min>-<max>_<ref>_<func>.png` (96 of the suite's 288; the projected
//! `F`/`P` tests, whose depths come from the rasteriser's depth buffer, are not
//! described).
//!
//! What a raw-value test does (read from the test program): it fills a 640 × 480 depth
//! texture from the CPU — 16-bit words (`DEPTH_Y16_FIXED`, a Z16 surface) or 32-bit
//! words (`DEPTH_X8_Y24_FIXED`, Z24S8) — with a 15 × 15 grid of boxes 42 × 32 texels,
//! starting 5 texels in, whose values run from `min` in steps of `max / 225` (a float
//! accumulator, truncated per box to the texel type; in the 32-bit texture the grid's
//! words are stored *unshifted*, so their depth is word >> 8), and seven small boxes
//! 21 × 64 texels at (141 + 63·i, 230) holding 0, 1, ref − 1, ref, ref + 1, max − 1, max
//! (shifted left 8 in the 32-bit texture). It then draws a screen quad from y = 100 to
//! 380 whose texture coordinates run over the texture (s = x, t = (y − 100)·480/280)
//! with r = ref, the texture stage in 2D or 3D projective mode, and the final combiner
//! passing texture 0's colour: the shadow compare's texel (all ones when the compare
//! passes, zero otherwise) becomes white or black. In 2D projective mode the stage has
//! no r, and the compare reads 0 as its reference. Small marker triangles cover the
//! middle of the seven boxes; the regions avoid them.
//!
//! The model: `shadow_compare` with the test's compare function and texel format
//! (`texel` Z16 or Z24S8), bias 0, no fraction bits: each box's word is written into
//! a map of one texel per box and tested against the reference; the lit bit becomes
//! texture 0's colour, and `final_combiner` (D = TEXTURE0 RGB, G = PRIMARY alpha, the
//! rest zero) gives the pixel. Neither unit differs between the GeForce2 default and
//! the NV2A here: the test sets the compare function and format explicitly.

use super::case::{Case, Chip, Prediction, Rect, Region, Suite};
use rtl_model::units::final_combiner::{FinalCombinerConfig, FinalVariable};
use rtl_model::units::register_combiner::{ComponentUsage, Register, RegisterFile};
use rtl_model::units::shadow_compare::{CompareFunc, DepthTexel, ShadowCompareConfig, ShadowIn};
use rtl_model::{Counters, Unit};

pub const SUITE: Suite = Suite {
    name: "Texture_shadow_comparator",
    source: "src/tests/texture_shadow_comparator_tests.cpp",
    cases,
};

/// Texture and framebuffer size.
const W: u32 = 640;
const H: u32 = 480;
/// The grid: 15 × 15 boxes of 42 × 32 texels, the first column 5 texels in.
const GRID: u32 = 15;
const BOX_W: u32 = W / GRID;
const BOX_H: u32 = H / GRID;
const GRID_LEFT: u32 = (W - BOX_W * GRID) / 2;
/// The seven explicit boxes: 21 × 64 texels at x = 141 + 63·i, y = 230.
const EX_W: u32 = BOX_W / 2;
const EX_H: u32 = BOX_H * 2;
const EX_STEP: u32 = EX_W + (BOX_W - EX_W) * 2;
const EX_LEFT: u32 = W / 2 - EX_STEP * 3 + EX_W / 2;
const EX_TOP: u32 = H / 2 - EX_W / 2;
/// The quad's screen rows: texel row t is drawn at y = 100 + t·280/480.
const QUAD_TOP: u32 = 100;
const QUAD_H: u32 = 280;
/// Pixels kept clear of a patch's edges.
const INSET: u32 = 2;

/// One raw-value configuration of the test program.
struct Raw {
    texel: DepthTexel,
    min: u32,
    max: u32,
    reference: u32,
}

/// The six configurations per compare function, as the test program lists them.
const RAWS: [Raw; 6] = [
    Raw {
        texel: DepthTexel::Z16,
        min: 0,
        max: 0xFFFF,
        reference: 0x7FFF,
    },
    Raw {
        texel: DepthTexel::Z16,
        min: 0,
        max: 256,
        reference: 128,
    },
    Raw {
        texel: DepthTexel::Z16,
        min: 256,
        max: 512,
        reference: 384,
    },
    Raw {
        texel: DepthTexel::Z24S8,
        min: 0,
        max: 0xFF_FFFF,
        reference: 0x7F_FFFF,
    },
    Raw {
        texel: DepthTexel::Z24S8,
        min: 0,
        max: 256,
        reference: 128,
    },
    Raw {
        texel: DepthTexel::Z24S8,
        min: 256,
        max: 512,
        reference: 384,
    },
];

/// The capture's suffix for a compare function.
fn func_tag(f: CompareFunc) -> &'static str {
    match f {
        CompareFunc::Never => "N",
        CompareFunc::Less => "LT",
        CompareFunc::Equal => "EQ",
        CompareFunc::Lequal => "LE",
        CompareFunc::Greater => "GT",
        CompareFunc::Notequal => "NE",
        CompareFunc::Gequal => "GE",
        CompareFunc::Always => "A",
    }
}

fn texel_tag(t: DepthTexel) -> &'static str {
    match t {
        DepthTexel::Z16 => "Z16",
        DepthTexel::Z24S8 => "Z24S8",
        DepthTexel::Unorm => "unorm",
    }
}

/// A box of texels: its rectangle in the texture and its texel word.
struct TexBox {
    name: String,
    texels: Rect,
    word: u32,
}

/// The grid's values as the test program computes them: a 32-bit float accumulator
/// from `min` in steps of `max / 225`, truncated per box (row-major).
fn grid_values(min: u32, max: u32) -> Vec<u32> {
    let inc = max as f32 / (GRID * GRID) as f32;
    let mut v = min as f32;
    let mut out = Vec::with_capacity((GRID * GRID) as usize);
    for _ in 0..GRID * GRID {
        out.push(v as u32);
        v += inc;
    }
    out
}

/// The explicit boxes' rectangles in texels.
fn explicit_rect(i: u32) -> Rect {
    Rect::new(EX_LEFT + EX_STEP * i, EX_TOP, EX_W, EX_H)
}

fn overlaps(a: Rect, b: Rect) -> bool {
    a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h
}

/// Every box of a configuration whose face can be compared: the grid's boxes (those
/// the explicit boxes cut into keep their part above or below the explicit band when
/// it is at least 16 texels tall; the others are left out) and the seven explicit
/// boxes (their strip above the marker triangle).
fn boxes(raw: &Raw) -> Vec<TexBox> {
    let shift = raw.texel.shift();
    let values = grid_values(raw.min, raw.max);
    let band = Rect::new(EX_LEFT, EX_TOP, EX_STEP * 6 + EX_W, EX_H);
    let mut out = Vec::new();
    for j in 0..GRID {
        for i in 0..GRID {
            let r = Rect::new(GRID_LEFT + BOX_W * i, BOX_H * j, BOX_W, BOX_H);
            let r = if overlaps(r, band) && (0..7).any(|e| overlaps(r, explicit_rect(e))) {
                let above = band.y.saturating_sub(r.y);
                let below = (r.y + r.h).saturating_sub(band.y + band.h);
                if above.max(below) < 16 {
                    continue;
                }
                if above >= below {
                    Rect::new(r.x, r.y, r.w, above)
                } else {
                    Rect::new(r.x, band.y + band.h, r.w, below)
                }
            } else {
                r
            };
            out.push(TexBox {
                name: format!("grid/{i},{j}"),
                texels: r,
                word: values[(j * GRID + i) as usize],
            });
        }
    }
    let r = raw.reference;
    let mask = if shift > 0 { u32::MAX } else { 0xFFFF };
    let names = ["0", "1", "ref-1", "ref", "ref+1", "max-1", "max"];
    for (i, v) in [0, 1, r - 1, r, r + 1, raw.max - 1, raw.max]
        .into_iter()
        .enumerate()
    {
        let e = explicit_rect(i as u32);
        // The marker triangle is drawn at screen rows 246 ..= 262 (the layout's
        // numbers taken as screen pixels): keep the box's strips above it (texel
        // rows 230 .. 248, screen rows 235 ..= 244) and below it (texel rows
        // 281 .. 294, screen rows 264 ..= 271).
        for (part, y0, y1) in [("above", e.y, 248), ("below", 281, e.y + e.h)] {
            out.push(TexBox {
                name: format!("box/{}/{part}", names[i]),
                texels: Rect::new(e.x, y0, e.w, y1 - y0),
                word: (v & mask) << shift,
            });
        }
    }
    out
}

/// The screen rectangle a texel rectangle covers (pixel centres whose texel lies in
/// it), inset by [`INSET`]; None when nothing is left.
fn screen_rect(t: Rect) -> Option<Rect> {
    // Texel row of screen row y: floor((y + ½ − 100)·480/280).
    let row = |y: u32| ((2 * y + 1) as i64 - 2 * QUAD_TOP as i64) * H as i64 / (2 * QUAD_H as i64);
    let ys: Vec<u32> = (QUAD_TOP..QUAD_TOP + QUAD_H)
        .filter(|&y| {
            let r = row(y);
            r >= t.y as i64 && r < (t.y + t.h) as i64
        })
        .collect();
    let (&y0, &y1) = (ys.first()?, ys.last()?);
    let r = Rect::new(t.x, y0, t.w, y1 - y0 + 1).inset(INSET);
    (r.w > 0 && r.h > 0).then_some(r)
}

/// Every case of the suite, predicted in `chip`'s modes (the same for both).
pub fn cases(_chip: Chip) -> Vec<Case> {
    let fc = FinalCombinerConfig {
        d: FinalVariable::register(Register::Texture0, ComponentUsage::Rgb),
        g: FinalVariable::register(Register::PrimaryColor, ComponentUsage::Alpha),
        a: FinalVariable::register(Register::Zero, ComponentUsage::Rgb),
        b: FinalVariable::register(Register::Zero, ComponentUsage::Rgb),
        c: FinalVariable::register(Register::Zero, ComponentUsage::Rgb),
        ..FinalCombinerConfig::geforce()
    }
    .build()
    .expect("the final combiner's pass-through config is valid");
    // The quad's diffuse colour 0xFF2277FF, in register units.
    let one = fc.one() as i32;
    let diffuse = [0x22, 0x77, 0xFF, 0xFF].map(|c: i32| (c * one + 127) / 255);
    let mut cases = Vec::new();
    for raw in &RAWS {
        let list = boxes(raw);
        for func in CompareFunc::ALL {
            let unit = ShadowCompareConfig {
                width: list.len() as u32,
                height: 1,
                depth_bits: raw.texel.required_depth_bits().expect("a sized format"),
                bias: 0,
                frag_frac_bits: 0,
                compare: func,
                texel: raw.texel,
            }
            .build()
            .expect("the suite's shadow_compare config is valid");
            let mut st = unit.fresh_state();
            let mut ctr = Counters::default();
            for (x, b) in list.iter().enumerate() {
                let w = ShadowIn::Write {
                    x: x as i32,
                    y: 0,
                    depth: b.word,
                };
                unit.kernel(&mut st, &w, &mut ctr);
            }
            for mode in [2u32, 3] {
                // 2D projective: no r coordinate, the compare's reference reads 0.
                let reference = if mode == 3 { raw.reference } else { 0 };
                let image = format!(
                    "{mode}R{}_{:X}-{:X}_{:X}_{}.png",
                    if raw.texel == DepthTexel::Z16 { 16 } else { 24 },
                    raw.min,
                    raw.max,
                    raw.reference,
                    func_tag(func)
                );
                let feature = format!("shadow compare {} {}", func.name(), texel_tag(raw.texel));
                let mut regions = Vec::new();
                for (x, b) in list.iter().enumerate() {
                    let Some(rect) = screen_rect(b.texels) else {
                        continue;
                    };
                    let t = ShadowIn::Test {
                        x: x as i32,
                        y: 0,
                        depth: reference as u64,
                    };
                    let lit = unit.kernel(&mut st, &t, &mut ctr).lit;
                    // The compare's texel: all ones or zero, in register units.
                    let tex = if lit { one } else { 0 };
                    let mut file = RegisterFile::default();
                    file.set(Register::Texture0, [tex; 4]);
                    file.set(Register::PrimaryColor, diffuse);
                    let px = fc.combine(&file, &mut ctr);
                    regions.push(Region {
                        name: format!("{}/{}", b.name, if lit { "lit" } else { "unlit" }),
                        feature: feature.clone(),
                        rect,
                        predicted: Prediction::Flat([px[0] as u8, px[1] as u8, px[2] as u8]),
                    });
                }
                cases.push(Case { image, regions });
            }
        }
    }
    cases
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_matches_the_test_program() {
        assert_eq!((BOX_W, BOX_H, GRID_LEFT), (42, 32, 5));
        assert_eq!(
            (EX_W, EX_H, EX_STEP, EX_LEFT, EX_TOP),
            (21, 64, 63, 141, 230)
        );
        let c = cases(Chip::Nv2a);
        assert_eq!(c.len(), 96);
        let mut names: Vec<&str> = c.iter().map(|c| c.image.as_str()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), 96);
        assert!(names.contains(&"3R24_0-FFFFFF_7FFFFF_EQ.png"));
        // Regions lie inside the quad and never overlap within an image.
        for case in &c {
            for (i, a) in case.regions.iter().enumerate() {
                assert!(a.rect.y >= QUAD_TOP && a.rect.y + a.rect.h <= QUAD_TOP + QUAD_H);
                for b in &case.regions[i + 1..] {
                    assert!(
                        !overlaps(a.rect, b.rect),
                        "{} {} {}",
                        case.image,
                        a.name,
                        b.name
                    );
                }
            }
        }
    }
}
