//! polygon_variable_generator — the glare renderer's setup of area-fill quads (M. Matsuda
//! and T. Ikedo, "A Realtime Renderer for Glare Effect Based upon Empirical Approach",
//! Fig. 1): from a source's (or flare line's) centre, extent, width and angle it makes
//! the three vertices of the parallelogram the polygon interpolator walks, with the
//! two attributes (u, v) — the pixel's position in the primitive's own normalised
//! frame — at each vertex.
//!
//! Two kinds of primitive:
//! - **Area** (bloom, halo): the screen-aligned square of half-side R around the centre
//!   (so the walker can scissor it to the viewport); the frame's rotation φ goes into
//!   the corner attributes, u = sx·cos φ + sy·sin φ, v = −sx·sin φ + sy·cos φ for the
//!   corner (sx, sy) ∈ {±1}², so u, v = the offset rotated by −φ, over R.
//! - **Line** (flare line): the rectangle from the centre along direction φ, length L,
//!   half-width w: u = −1 at the centre … +1 at the tip, v = ±1 at the sides.
//!
//! Widths: positions are the interpolator's `s(c).(s)` codes (c = `coord_int_bits`,
//! s = `subpixel_bits`); the angle is u(`angle_bits`) turns; cos and sin come from a
//! quarter-wave ROM of 2^k + 1 entries (k = `trig_log2`) of unorm `trig_bits`, indexed
//! by the top k bits of the angle within its quadrant (the rest truncated); attributes
//! are s2.(`attr_frac_bits`). Offsets: u(c+s) × u(trig_bits) → u(c+s+trig_bits),
//! rounded back by `trig_bits`. Corners beyond the coordinate range saturate (counted).

use crate::cost::{prim, Cost};
use crate::counters::Counters;
use crate::error::{check_range, ConfigError};
use crate::unit::{Signal, Timing, Unit, Width};
use serde::{Deserialize, Serialize};

const NAME: &str = "polygon_variable_generator";

/// Config as plain data; [`Self::build`] validates it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PolygonVariableGeneratorConfig {
    /// Integer bits of positions including the sign, 2 ..= 14 (as the interpolator).
    pub coord_int_bits: u32,
    /// Sub-pixel bits of positions, 0 ..= 8 (as the interpolator).
    pub subpixel_bits: u32,
    /// Angle width in turns, 3 ..= 16.
    pub angle_bits: u32,
    /// Quarter-wave ROM depth 2^k, 1 ..= 14.
    pub trig_log2: u32,
    /// ROM entry width (unorm, full scale = 1.0), 2 ..= 16.
    pub trig_bits: u32,
    /// Fraction bits of the s2.f attributes, 1 ..= 30.
    pub attr_frac_bits: u32,
}

impl Default for PolygonVariableGeneratorConfig {
    fn default() -> Self {
        PolygonVariableGeneratorConfig {
            coord_int_bits: 14,
            subpixel_bits: 4,
            angle_bits: 12,
            trig_log2: 10,
            trig_bits: 16,
            attr_frac_bits: 14,
        }
    }
}

impl PolygonVariableGeneratorConfig {
    /// Validate and build the quarter-wave ROM; errors name
    /// `polygon_variable_generator.<field>`.
    pub fn build(self) -> Result<PolygonVariableGenerator, ConfigError> {
        let f = |s: &str| format!("{NAME}.{s}");
        check_range(&f("coord_int_bits"), self.coord_int_bits.into(), 2, 14)?;
        check_range(&f("subpixel_bits"), self.subpixel_bits.into(), 0, 8)?;
        check_range(&f("angle_bits"), self.angle_bits.into(), 3, 16)?;
        check_range(&f("trig_log2"), self.trig_log2.into(), 1, 14)?;
        check_range(&f("trig_bits"), self.trig_bits.into(), 2, 16)?;
        check_range(&f("attr_frac_bits"), self.attr_frac_bits.into(), 1, 30)?;
        // The ROM: cos over the first quadrant, sampled at j·(π/2)/2^k, rounded.
        let n = 1usize << self.trig_log2;
        let full = ((1u64 << self.trig_bits) - 1) as f64;
        let rom = (0..=n)
            .map(|j| {
                let a = j as f64 / n as f64 * std::f64::consts::FRAC_PI_2;
                (a.cos() * full).round() as u32
            })
            .collect();
        Ok(PolygonVariableGenerator { cfg: self, rom })
    }
}

/// The validated unit, holding its quarter-wave ROM.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PolygonVariableGenerator {
    cfg: PolygonVariableGeneratorConfig,
    rom: Vec<u32>,
}

/// What to set up.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PrimKind {
    /// Bloom or halo: the screen-aligned square of half-side R around the centre, the
    /// rotation φ carried in the corners' (u, v).
    Area,
    /// Flare line: the rectangle from the centre along φ, length L and half-width w;
    /// u = −1 at the centre … +1 at the tip, v = ±1 at the sides.
    Line,
}

/// One primitive's variables, raw codes: centre in the position format, `extent`
/// (R or L) and `half_width` in sub-pixel units (unsigned, masked to c + s bits),
/// `angle` in u(angle_bits) turns.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PvgIn {
    /// Area (bloom, halo) or line (flare line).
    pub kind: PrimKind,
    /// Centre x, a raw s(coord_int_bits).(subpixel_bits) code.
    pub cx: i64,
    /// Centre y, a raw s(coord_int_bits).(subpixel_bits) code.
    pub cy: i64,
    /// R (area: half-side of the square) or L (line: length), in sub-pixel units.
    pub extent: u64,
    /// Half-width w of a line, in sub-pixel units (unused for an area).
    pub half_width: u64,
    /// The rotation φ in turns, a u(angle_bits) code (2^angle_bits = one turn).
    pub angle: u32,
}

/// A vertex: position codes and the (u, v) attribute codes (s2.f).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PvgVertex {
    /// Screen x, a raw s(coord_int_bits).(subpixel_bits) code (saturated, counted).
    pub x: i64,
    /// Screen y, a raw s(coord_int_bits).(subpixel_bits) code (saturated, counted).
    pub y: i64,
    /// Attribute u, the first coordinate of the pixel's position in the primitive's
    /// normalised frame (line: −1 at the centre … +1 at the tip), a raw code with
    /// `attr_frac_bits` fraction bits.
    pub u: i64,
    /// Attribute v, the second coordinate in the primitive's frame (line: ±1 at the
    /// sides), a raw code with `attr_frac_bits` fraction bits.
    pub v: i64,
}

/// Parallelogram v0 v1 v2 (v3 = v0 + v2 − v1).
pub type PvgOut = [PvgVertex; 3];

impl PolygonVariableGenerator {
    /// Validate and build the unit; the same as [`PolygonVariableGeneratorConfig::build`].
    pub fn new(cfg: PolygonVariableGeneratorConfig) -> Result<Self, ConfigError> {
        cfg.build()
    }

    /// Defaults: 14.4 positions (as the glare interpolator), 12-bit angles, exact
    /// 1025-entry × 16-bit quarter-wave ROM, s2.14 attributes.
    pub fn geforce() -> Self {
        PolygonVariableGeneratorConfig::default()
            .build()
            .expect("defaults are valid")
    }

    /// The config the unit was built from.
    pub fn config(&self) -> PolygonVariableGeneratorConfig {
        self.cfg
    }

    /// The quarter-wave ROM, entry order (2^k + 1 words of `trig_bits`):
    /// `entry[j]` = round(cos(j/2^k · π/2) · (2^trig_bits − 1)), for `$readmemh` images.
    pub fn rom_words(&self) -> Vec<u64> {
        self.rom.iter().map(|&w| u64::from(w)).collect()
    }

    /// Largest position code (one sign bit, c − 1 integer bits, s fraction bits).
    fn pos_max(&self) -> i64 {
        (1i64 << (self.cfg.coord_int_bits + self.cfg.subpixel_bits - 1)) - 1
    }

    /// An angle in radians → its u(angle_bits) code, round to nearest, wrapped to one
    /// turn; NaN/∞ is an error naming `angle`.
    pub fn angle_code(&self, radians: f64) -> Result<u32, ConfigError> {
        crate::error::check_finite(&format!("{NAME}.angle"), radians)?;
        let turns = (radians / std::f64::consts::TAU).rem_euclid(1.0);
        let n = 1u64 << self.cfg.angle_bits;
        Ok(((turns * n as f64).round() as u64 % n) as u32)
    }

    /// (cos, sin) of an angle code as signed codes of full scale 2^trig_bits − 1.
    /// The quadrant is the top 2 bits; the ROM index the next k bits (truncated).
    pub fn cos_sin(&self, angle: u32) -> (i64, i64) {
        let ab = self.cfg.angle_bits;
        let a = angle as u64 & ((1u64 << ab) - 1);
        let quadrant = a >> (ab - 2);
        let within = a & ((1u64 << (ab - 2)) - 1); // u(ab − 2)
        let k = self.cfg.trig_log2;
        let idx = if ab - 2 >= k {
            (within >> (ab - 2 - k)) as usize
        } else {
            (within << (k - (ab - 2))) as usize
        };
        let n = 1usize << k;
        let c = self.rom[idx] as i64; // cos(θ) for θ in the quadrant
        let s = self.rom[n - idx] as i64; // sin(θ) = cos(π/2 − θ)
        match quadrant {
            0 => (c, s),
            1 => (-s, c),
            2 => (-c, -s),
            _ => (s, -c),
        }
    }

    /// round(x · t / (2^trig_bits − 1))… implemented as the hardware does it: the ROM's
    /// full scale is treated as 2^trig_bits (a shift), x·t + half >> trig_bits.
    fn scale(&self, x: i64, t: i64) -> i64 {
        let tb = self.cfg.trig_bits;
        let p = x as i128 * t as i128; // s(c+s+1) × s(trig+1) → s(c+s+trig+2)
        ((p + (1i128 << (tb - 1))) >> tb) as i64
    }

    /// A trig code as an s2.f attribute code.
    fn attr(&self, t: i64) -> i64 {
        let (tb, f) = (self.cfg.trig_bits as i32, self.cfg.attr_frac_bits as i32);
        if f >= tb {
            t << (f - tb)
        } else {
            let sh = tb - f;
            (t + (1 << (sh - 1))) >> sh
        }
    }

    fn clamp_pos(&self, p: i64, ctr: &mut Counters) -> i64 {
        let m = self.pos_max();
        if p > m {
            ctr.saturations += 1;
            m
        } else if p < -m - 1 {
            ctr.saturations += 1;
            -m - 1
        } else {
            p
        }
    }
}

impl Unit for PolygonVariableGenerator {
    type In = PvgIn;
    type Out = PvgOut;
    type State = ();

    fn name(&self) -> &'static str {
        NAME
    }

    fn kernel(&self, _: &mut (), i: &PvgIn, ctr: &mut Counters) -> PvgOut {
        let w = self.cfg.coord_int_bits + self.cfg.subpixel_bits;
        let mask = (1u64 << w) - 1;
        let (ext, hw) = ((i.extent & mask) as i64, (i.half_width & mask) as i64);
        let (cx, cy) = (self.clamp_pos(i.cx, ctr), self.clamp_pos(i.cy, ctr));
        let (c, s) = self.cos_sin(i.angle);
        ctr.table_reads += 2;
        let one = 1i64 << (self.cfg.attr_frac_bits);
        let mut out = [PvgVertex::default(); 3];
        match i.kind {
            PrimKind::Area => {
                let (ac, as_) = (self.attr(c), self.attr(s));
                for (k, (sx, sy)) in [(-1i64, -1i64), (1, -1), (1, 1)].into_iter().enumerate() {
                    out[k] = PvgVertex {
                        x: self.clamp_pos(cx + sx * ext, ctr),
                        y: self.clamp_pos(cy + sy * ext, ctr),
                        u: sx * ac + sy * as_, // s2.f + s2.f → s3.f, |u| ≤ √2
                        v: -sx * as_ + sy * ac,
                    };
                }
            }
            PrimKind::Line => {
                let (lx, ly) = (self.scale(ext, c), self.scale(ext, s)); // L·d
                let (nx, ny) = (self.scale(hw, -s), self.scale(hw, c)); // w·n
                let pts = [
                    (cx - nx, cy - ny, -one, -one),
                    (cx + lx - nx, cy + ly - ny, one, -one),
                    (cx + lx + nx, cy + ly + ny, one, one),
                ];
                for (k, (x, y, u, v)) in pts.into_iter().enumerate() {
                    out[k] = PvgVertex {
                        x: self.clamp_pos(x, ctr),
                        y: self.clamp_pos(y, ctr),
                        u,
                        v,
                    };
                }
            }
        }
        out
    }

    fn timing(&self) -> Timing {
        // 1: ROM read; 2: the four offset multipliers; 3: corner adders and clamps.
        Timing { latency: 3, ii: 1 }
    }

    fn cost(&self) -> Cost {
        let w = self.cfg.coord_int_bits + self.cfg.subpixel_bits;
        let tb = self.cfg.trig_bits;
        let f = self.cfg.attr_frac_bits;
        let k = self.cfg.trig_log2;
        Cost::default()
            .part(
                "quadrant fold (index complement, sign muxes)",
                prim::adder(k) + prim::mux(2 * (tb + 1)),
            )
            .part(
                "offset multipliers 4 × (c+s)×trig",
                prim::multiplier(w, tb) * 4.0,
            )
            .part("corner adders 6 × (c+s+1)", prim::adder(w + 1) * 6.0)
            .part("attribute adders 2 × (f+3)", prim::adder(f + 3) * 2.0)
            .part(
                "position clamps 6",
                (prim::comparator(w + 1) + prim::mux(w)) * 6.0,
            )
            .part(
                "input registers",
                prim::register(4 * w + self.cfg.angle_bits + 1),
            )
            .part(
                "pipeline registers",
                prim::register(2 * (tb + 1) + 4 * (w + tb)),
            )
            .part(
                "output registers",
                prim::register(3 * (2 * w + 2 * (f + 2))),
            )
            .with_ram_bits(((1u64 << k) + 1) * tb as u64)
    }

    fn widths(&self) -> Vec<Width> {
        vec![
            Width {
                name: "coord_int_bits",
                bits: self.cfg.coord_int_bits,
            },
            Width {
                name: "subpixel_bits",
                bits: self.cfg.subpixel_bits,
            },
            Width {
                name: "angle_bits",
                bits: self.cfg.angle_bits,
            },
            Width {
                name: "trig_log2",
                bits: self.cfg.trig_log2,
            },
            Width {
                name: "trig_bits",
                bits: self.cfg.trig_bits,
            },
            Width {
                name: "attr_frac_bits",
                bits: self.cfg.attr_frac_bits,
            },
        ]
    }

    fn in_signals(&self, i: &PvgIn) -> Vec<Signal> {
        let w = self.cfg.coord_int_bits + self.cfg.subpixel_bits;
        let m = (1u64 << w) - 1;
        vec![
            Signal::new("line", 1, u64::from(i.kind == PrimKind::Line)),
            Signal::new("cx", w, i.cx as u64 & m),
            Signal::new("cy", w, i.cy as u64 & m),
            Signal::new("extent", w, i.extent & m),
            Signal::new("half_width", w, i.half_width & m),
            Signal::new("angle", self.cfg.angle_bits, i.angle as u64),
        ]
    }

    fn out_signals(&self, o: &PvgOut) -> Vec<Signal> {
        let w = self.cfg.coord_int_bits + self.cfg.subpixel_bits;
        let m = (1u64 << w) - 1;
        let fa = self.cfg.attr_frac_bits + 3;
        let ma = (1u64 << fa) - 1;
        const N: [[&str; 4]; 3] = [
            ["v0_x", "v0_y", "v0_u", "v0_v"],
            ["v1_x", "v1_y", "v1_u", "v1_v"],
            ["v2_x", "v2_y", "v2_u", "v2_v"],
        ];
        o.iter()
            .zip(N)
            .flat_map(|(v, n)| {
                [
                    Signal::new(n[0], w, v.x as u64 & m),
                    Signal::new(n[1], w, v.y as u64 & m),
                    Signal::new(n[2], fa, v.u as u64 & ma),
                    Signal::new(n[3], fa, v.v as u64 & ma),
                ]
            })
            .collect()
    }
}
