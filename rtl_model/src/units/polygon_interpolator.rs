//! polygon_interpolator — polygon setup plus the incremental (Pineda) walker that
//! interpolates up to 16 per-vertex attributes over triangles and quads.
//!
//! **Setup** (once per primitive, integers only): vertex positions are screen fixed point
//! `s(c).(s)` (c = `coord_int_bits` including the sign, s = `subpixel_bits`), attributes
//! are `attr_fmt`. The plane of every attribute is found exactly (i128 products) and its
//! per-pixel gradients dA/dx, dA/dy and its value at the first pixel centre are each
//! produced by ONE rounding integer division by the doubled area, landing in the
//! accumulator format `s(acc_int_bits).(acc_frac_bits)`: each is within ½ accumulator LSB.
//! The edge functions are evaluated on a half-sub-pixel grid, where vertices and pixel
//! centres are both integers, so they are exact and coverage is exact.
//!
//! **Walker / kernel** (once per pixel step): a serpentine (boustrophedon) walk over the
//! primitive's bounding box. Each input is one [`Move`]; the kernel adds the x- or
//! y-increment to the 4 edge accumulators and the K attribute accumulators (adds only,
//! no multiplies per pixel), then presents `{x, y, inside, attrs[K]}`: inside is the sign
//! test of the edge functions (top-left fill rule folded into the start values as a −1
//! bias), attrs are the accumulators rounded to `s(out_int_bits).(out_frac_bits)`
//! (unsigned if `attr_fmt` is) by `out_quant`, saturating (counted) on overflow.
//!
//! Primitives: a triangle ([`PolygonInterpolator::setup_triangle`]); a GL quad
//! (`setup_quad`) as two triangles (v0 v1 v2) and (v0 v2 v3) sharing the edge v0–v2, as
//! GL draws a mesh cell; and an affine parallelogram (`setup_parallelogram`,
//! `setup_affine_quad`) walked ONCE with 4 edge functions — the glare pipeline's
//! area-fill quads — so an axis-aligned rectangle is not walked twice (each half of a
//! split rectangle has the whole rectangle as its bounding box).
//!
//! A degenerate primitive (zero doubled area) or one whose bounding box holds no pixel
//! centre sets up cleanly as an empty primitive: no moves, and a state whose inside flag
//! is always false (GL culls zero-area triangles). Nothing divides by zero.

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_range, ConfigError};
use crate::fixed_point::{round_shift_right_i64, Format, Fx, Overflow, Quant};
use crate::unit::{Signal, Timing, Unit, Width};
use serde::{Deserialize, Serialize};

/// Most attributes a primitive carries (GeForce3 interpolates 4 texture units × (s, t,
/// r, q), 2 colours, fog and z per pixel). Only the CONFIGURED `attrs` are built and
/// costed: this bounds the config and sizes the fixed arrays, nothing more.
pub const MAX_ATTRS: usize = 16;
/// Edge accumulators in the walker (a triangle leaves the 4th idle, always inside).
pub const EDGES: usize = 4;
/// Widest attribute format (keeps every setup product within the i128 carrier).
pub const MAX_ATTR_BITS: u32 = 32;
/// Default integer bits of vertex positions (13: −4096 ..= 4095 px and sub-pixels).
pub const DEFAULT_COORD_INT_BITS: u32 = 13;

const NAME: &str = "polygon_interpolator";
const ATTR_SIGNALS: [&str; MAX_ATTRS] = [
    "attr0", "attr1", "attr2", "attr3", "attr4", "attr5", "attr6", "attr7", "attr8", "attr9",
    "attr10", "attr11", "attr12", "attr13", "attr14", "attr15",
];

/// The config as plain data (serde), turned into a validated unit by [`Self::build`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PolygonInterpolatorConfig {
    /// Attributes per primitive, 0 ..= 16 (`MAX_ATTRS`).
    pub attrs: u32,
    /// Sub-pixel bits of vertex positions, 0 ..= 8.
    pub subpixel_bits: u32,
    /// Integer bits of vertex positions and pixel counters, including the sign, 2 ..= 14
    /// (13 → −4096 ..= 4095 px).
    pub coord_int_bits: u32,
    /// Format of the vertex attributes (width 1 ..= 32).
    pub attr_fmt: Format,
    /// Integer bits of the (signed) accumulators, including the sign, 1 ..= 48.
    pub acc_int_bits: u32,
    /// Fraction bits of the accumulators, 1 ..= 40 (acc width ≤ 62).
    pub acc_frac_bits: u32,
    /// What an accumulator does when a gradient, start value or step overflows it:
    /// WRAP (counted in `overflows`; modular, so pixels whose true value fits still come
    /// out right) or a SAT mode (counted in `saturations`).
    pub acc_overflow: Overflow,
    /// Integer bits of the output attributes (including the sign when `attr_fmt` is
    /// signed), 0 ..= 40.
    pub out_int_bits: u32,
    /// Fraction bits of the output attributes, 0 ..= 40 (out width 1 ..= 48).
    pub out_frac_bits: u32,
    /// Rounding of the accumulator to the output (default RND: add half, truncate).
    pub out_quant: Quant,
    /// Triangle attributes by quantised barycentric weights instead of plane
    /// accumulators ([`Barycentric`]); None (the default): the planes.
    #[serde(default)]
    pub barycentric: Option<Barycentric>,
}

/// The NV2A's triangle attribute interpolation, read from the CC0 Gouraud captures of
/// nxdk_pgraph_tests' Specular suite (ControlFlags*, docs/conformance.md): per pixel the
/// two barycentric weights of a triangle's first and third vertices are quantised DOWN
/// to `weight_bits` fraction bits, and the attribute is
/// A = A1 + q0·(A0 − A1) + q2·(A2 − A1) (the second vertex the base), rounded once
/// into the output format by `out_quant`. No document gives this; the captures show
/// it: along a row of a quad with slope 1.79 levels/px the hardware steps by 3 and by
/// 1 (no rounding of any plane does that), and 8 weight bits with the second vertex as
/// base reproduce them (97.6 % of the pixels of the lighting-off quads, where the
/// rounded plane gives 65 %).
///
/// The weights come from the walker's exact edge functions: λ_i = E_i/(2·area2) for
/// the edge opposite vertex i, so q_i = ⌊(2^w·E_i − t)/(2·area2)⌋ with t = 1 when
/// `strict` (a weight exactly on a multiple of 2^−w takes the step below, as the
/// captures mostly show), 0 for the floor. Only triangles (and GL quads, as two
/// triangles) use it; parallelograms keep their planes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Barycentric {
    /// Fraction bits of the quantised weights, 1 ..= 16 (the NV2A: 8).
    pub weight_bits: u32,
    /// Exact multiples of 2^−w round down to the step below.
    pub strict: bool,
}

impl Default for PolygonInterpolatorConfig {
    fn default() -> Self {
        PolygonInterpolatorConfig {
            attrs: 4,
            subpixel_bits: 4,
            coord_int_bits: DEFAULT_COORD_INT_BITS,
            attr_fmt: Format {
                int_bits: 16,
                frac_bits: 16,
                signed: true,
            },
            acc_int_bits: 20,
            acc_frac_bits: 24,
            acc_overflow: Overflow::Wrap,
            out_int_bits: 16,
            out_frac_bits: 8,
            out_quant: Quant::Rnd,
            barycentric: None,
        }
    }
}

impl PolygonInterpolatorConfig {
    /// Validate; errors name the field as `polygon_interpolator.<field>`.
    pub fn build(self) -> Result<PolygonInterpolator, ConfigError> {
        let f = |s: &str| format!("{NAME}.{s}");
        check_range(&f("attrs"), self.attrs as u64, 0, MAX_ATTRS as u64)?;
        check_range(&f("subpixel_bits"), self.subpixel_bits as u64, 0, 8)?;
        check_range(&f("coord_int_bits"), self.coord_int_bits as u64, 2, 14)?;
        self.attr_fmt.validate(&f("attr_fmt"))?;
        check_range(
            &f("attr_fmt"),
            self.attr_fmt.width() as u64,
            1,
            MAX_ATTR_BITS as u64,
        )?;
        check_range(&f("acc_int_bits"), self.acc_int_bits as u64, 1, 48)?;
        check_range(&f("acc_frac_bits"), self.acc_frac_bits as u64, 1, 40)?;
        check_range(
            &f("acc_int_bits"),
            self.acc_int_bits as u64 + self.acc_frac_bits as u64,
            2,
            62,
        )?;
        check_range(&f("out_int_bits"), self.out_int_bits as u64, 0, 40)?;
        check_range(&f("out_frac_bits"), self.out_frac_bits as u64, 0, 40)?;
        check_range(
            &f("out_int_bits"),
            self.out_int_bits as u64 + self.out_frac_bits as u64,
            1,
            48,
        )?;
        if let Some(b) = self.barycentric {
            check_range(&f("barycentric.weight_bits"), b.weight_bits as u64, 1, 16)?;
        }
        if self.attr_fmt.signed && self.out_int_bits == 0 {
            return Err(ConfigError::invalid(
                &f("out_int_bits"),
                "a signed output needs at least one integer bit (the sign)",
            ));
        }
        Ok(PolygonInterpolator { cfg: self })
    }
}

/// The validated config (the unit).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PolygonInterpolator {
    cfg: PolygonInterpolatorConfig,
}

/// One walker step. `Hold` emits the current pixel (the first pixel of a walk).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Move {
    /// Stay on the current pixel and emit it (the first pixel of a walk).
    Hold,
    /// Step one pixel right (x + 1): add each edge's and attribute's x increment.
    Right,
    /// Step one pixel left (x − 1): subtract the x increments.
    Left,
    /// Step one row down (y + 1): add the y increments.
    Down,
}

impl Move {
    /// 2-bit code on the input wires.
    pub fn code(self) -> u64 {
        match self {
            Move::Hold => 0,
            Move::Right => 1,
            Move::Left => 2,
            Move::Down => 3,
        }
    }
}

/// A vertex as raw codes: `x`, `y` in the position format `s(c).(s)` (sub-pixel units),
/// `attrs[i]` in `attr_fmt` (only the first `attrs` are used). Setup masks every word to
/// its wire width (two's-complement wrap / low bits), so any value is accepted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Vertex {
    /// Screen x, a raw s(coord_int_bits).(subpixel_bits) code (sub-pixel units).
    pub x: i64,
    /// Screen y, a raw s(coord_int_bits).(subpixel_bits) code (sub-pixel units).
    pub y: i64,
    /// Attributes, raw codes in `attr_fmt`; only the first `attrs` are used.
    pub attrs: [i64; MAX_ATTRS],
}

/// The walker's registers: pixel counters, edge accumulators and their increments,
/// attribute accumulators and their gradients (loaded by setup, per primitive).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PolyState {
    /// Current pixel (integer pixels, `coord_int_bits` wide).
    pub x: i64,
    /// Current pixel row (integer pixels, `coord_int_bits` wide).
    pub y: i64,
    /// Edge functions at the current pixel centre (units: sub-pixel × half-sub-pixel),
    /// top-left bias included: the pixel is inside iff all are ≥ 0.
    pub edge: [i64; EDGES],
    /// Change of each edge function for one pixel step in x (same units as `edge`).
    pub edge_dx: [i64; EDGES],
    /// Change of each edge function for one pixel step in y (same units as `edge`).
    pub edge_dy: [i64; EDGES],
    /// Attribute accumulators, raw in `s(acc_int).(acc_frac)`.
    pub acc: [i64; MAX_ATTRS],
    /// dA/dx of each attribute per pixel, raw in the accumulator format.
    pub grad_x: [i64; MAX_ATTRS],
    /// dA/dy of each attribute per pixel, raw in the accumulator format.
    pub grad_y: [i64; MAX_ATTRS],
    /// Barycentric mode ([`Barycentric`]), loaded by a triangle's setup: None for the
    /// planes (and always for parallelograms).
    pub bary: Option<BaryRegs>,
}

/// A triangle's registers for the barycentric mode: which edge functions give the
/// weights of the first and third vertices (and the top-left bias to add back), the
/// doubled area in edge units, and per attribute the base (second vertex) and the two
/// differences.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BaryRegs {
    /// Index of the edge function that gives the weight of the first vertex and of the
    /// third vertex (the edge opposite each).
    pub edge_of: [usize; 2],
    /// The top-left bias of those two edges, added back before the weights are taken.
    pub bias: [i64; 2],
    /// Σ of the unbiased edge functions: 2·area2 (h units × sub-pixel units).
    pub denom: i64,
    /// Per attribute, the second vertex's value (raw in `attr_fmt`): the base of the
    /// weighted sum.
    pub base: [i64; MAX_ATTRS],
    /// Per attribute, the differences A0 − A1 and A2 − A1 (raw, one bit wider than
    /// `attr_fmt`).
    pub delta: [[i64; MAX_ATTRS]; 2],
}

impl PolyState {
    /// The state of an empty primitive: never inside, nothing moves.
    pub fn empty() -> Self {
        let mut s = PolyState::default();
        s.edge[0] = -1;
        s
    }
}

/// One output word.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PolyOut {
    /// Pixel column (integer pixels).
    pub x: i64,
    /// Pixel row (integer pixels).
    pub y: i64,
    /// Whether the pixel centre is covered (every edge function ≥ 0, top-left rule).
    pub inside: bool,
    /// Raw codes in the output format (first `attrs` valid, the rest 0).
    pub attrs: [i64; MAX_ATTRS],
}

/// Output words in lanes (structure of arrays): word i is (`x[i]`, `y[i]`,
/// `inside[i]`, `attrs[a][i]` for a < the config's `attrs`). What
/// [`PolygonInterpolator::kernel_batch_lanes`] writes.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PolyLanes {
    /// Pixel columns, one per word.
    pub x: Vec<i64>,
    /// Pixel rows, one per word.
    pub y: Vec<i64>,
    /// Coverage flags, one per word.
    pub inside: Vec<bool>,
    /// One lane per attribute (only the config's first `attrs` are written, and of
    /// those not the ones in `unread`).
    pub attrs: [Vec<i64>; MAX_ATTRS],
    /// Attributes written (the config's `attrs`).
    pub k: usize,
    /// Attributes no consumer of these lanes reads (bit a for attribute a): their
    /// lanes stay empty; the kernel still computes and counts them (the same events,
    /// the same final state). Set by [`PolyLanes::clear_unread`]; 0 by
    /// [`PolyLanes::clear`].
    pub unread: u32,
    /// Only covered words are appended (`inside`): a walk whose sink keeps fragments
    /// alone skips writing the rest of each bounding-box row. The kernel still steps
    /// and counts every move (the same events, the same final state). Set by
    /// [`PolyLanes::clear_covered`]; false after [`PolyLanes::clear_unread`].
    pub covered_only: bool,
    /// Where an unread attribute's run is computed (its events counted), reused.
    spare: Vec<i64>,
}

impl PolyLanes {
    /// Words held.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True when no word is held.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Empty, ready for `k` attributes (buffers kept), every one written.
    pub fn clear(&mut self, k: usize) {
        self.clear_unread(k, 0);
    }

    /// Empty, ready for `k` attributes (buffers kept), those in the mask `unread`
    /// (bit a for attribute a) not written: lanes no consumer reads.
    pub fn clear_unread(&mut self, k: usize, unread: u32) {
        self.clear_covered(k, unread, false);
    }

    /// [`PolyLanes::clear_unread`], and whether only covered words are appended
    /// ([`PolyLanes::covered_only`]).
    pub fn clear_covered(&mut self, k: usize, unread: u32, covered_only: bool) {
        self.covered_only = covered_only;
        self.x.clear();
        self.y.clear();
        self.inside.clear();
        for l in &mut self.attrs {
            l.clear();
        }
        self.k = k;
        self.unread = unread;
    }

    /// Room for `n` more words in every lane that is written.
    pub fn reserve(&mut self, n: usize) {
        self.x.reserve(n);
        self.y.reserve(n);
        self.inside.reserve(n);
        let (k, unread) = (self.k, self.unread);
        for (a, l) in self.attrs.iter_mut().enumerate().take(k) {
            if (unread >> a) & 1 == 0 {
                l.reserve(n);
            }
        }
    }

    /// Whether attribute `a`'s lane is written.
    #[inline]
    pub fn is_read(&self, a: usize) -> bool {
        (self.unread >> a) & 1 == 0
    }

    /// Append one word (its first `k` attributes, the unread ones left out).
    pub fn push(&mut self, o: &PolyOut) {
        self.x.push(o.x);
        self.y.push(o.y);
        self.inside.push(o.inside);
        let unread = self.unread;
        let lanes = self.attrs.iter_mut().zip(&o.attrs).take(self.k);
        for (a, (l, &v)) in lanes.enumerate() {
            if (unread >> a) & 1 == 0 {
                l.push(v);
            }
        }
    }

    /// Word i as a [`PolyOut`] (attributes past `k` and unread ones 0).
    pub fn word(&self, i: usize) -> PolyOut {
        let mut attrs = [0i64; MAX_ATTRS];
        let lanes = attrs.iter_mut().zip(&self.attrs).take(self.k);
        for (a, (v, l)) in lanes.enumerate() {
            if self.is_read(a) {
                *v = l[i];
            }
        }
        PolyOut {
            x: self.x[i],
            y: self.y[i],
            inside: self.inside[i],
            attrs,
        }
    }
}

/// One attribute's codes along a stretch of a walk row
/// ([`PolygonInterpolator::attr_row`]): the accumulator is affine along it and in
/// its format at both ends, so at every pixel between, and each code is that value
/// rounded and clamped (both monotone: the codes rise or fall along the row).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AttrRow {
    /// The stretch's first and last pixel column.
    x0: i64,
    x1: i64,
    /// The accumulator at column `x0`, and its step per column.
    v0: i64,
    g: i64,
    /// The output rounding's shift (≥ 1) and mode, and the output's least and
    /// greatest code.
    shift: u32,
    quant: Quant,
    range: (i64, i64),
}

impl AttrRow {
    /// The code at pixel column `x` (within the stretch: the accumulator there is
    /// in its format, so no i64 overflow).
    #[inline]
    pub fn code(&self, x: i64) -> i64 {
        debug_assert!(
            (self.x0..=self.x1).contains(&x),
            "column {x} off the stretch"
        );
        let v = self.v0 + (x - self.x0) * self.g;
        round_acc(v, self.shift, self.quant).clamp(self.range.0, self.range.1)
    }

    /// The least and greatest code over columns `xs` (within the stretch): its
    /// ends' codes, in order.
    #[inline]
    pub fn range_over(&self, xs: std::ops::RangeInclusive<i64>) -> (i64, i64) {
        let (a, b) = (self.code(*xs.start()), self.code(*xs.end()));
        (a.min(b), a.max(b))
    }

    /// The least and greatest code over the whole stretch.
    pub fn range(&self) -> (i64, i64) {
        self.range_over(self.x0..=self.x1)
    }
}

/// Inclusive pixel bounding box of a primitive (pixels whose centres may be covered).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BBox {
    /// Leftmost pixel column.
    pub x0: i64,
    /// Top pixel row.
    pub y0: i64,
    /// Rightmost pixel column (inclusive).
    pub x1: i64,
    /// Bottom pixel row (inclusive).
    pub y1: i64,
}

impl BBox {
    /// Columns in the box, x1 − x0 + 1.
    pub fn width(&self) -> u64 {
        (self.x1 - self.x0 + 1) as u64
    }
    /// Rows in the box, y1 − y0 + 1.
    pub fn height(&self) -> u64 {
        (self.y1 - self.y0 + 1) as u64
    }
}

/// A set-up primitive: its bounding box (None if empty) and the walker's start state.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PolySetup {
    /// The pixels whose centres may be covered; `None` for an empty primitive.
    pub bbox: Option<BBox>,
    /// Edge functions used: 3 (triangle) or 4 (parallelogram); 0 if empty.
    pub edges: u32,
    /// Doubled area in sub-pixel² units (> 0), 0 if degenerate.
    pub area2: i128,
    /// The walker's registers at the first pixel: the kernel's start state for this
    /// primitive.
    pub state: PolyState,
    /// Which edges are top or left (no −1 bias in their start value).
    pub top_left: [bool; EDGES],
}

impl PolySetup {
    fn empty(area2: i128) -> Self {
        PolySetup {
            bbox: None,
            edges: 0,
            area2,
            state: PolyState::empty(),
            top_left: [true; EDGES],
        }
    }

    /// Pixels (= moves) the serpentine walk takes.
    pub fn pixels(&self) -> u64 {
        self.bbox.map_or(0, |b| b.width() * b.height())
    }

    /// The serpentine move sequence over the bounding box: `Hold` for the top-left pixel,
    /// then right along the first row, `Down`, left along the second, … One move per
    /// pixel, so `run_span(unit, &mut setup.state.clone(), &setup.moves(), ..)` yields one
    /// output per bounding-box pixel.
    pub fn moves(&self) -> Vec<Move> {
        let Some(b) = self.bbox else {
            return Vec::new();
        };
        let (w, h) = (b.width() as usize, b.height() as usize);
        let mut m = Vec::with_capacity(w * h);
        for row in 0..h {
            m.push(if row == 0 { Move::Hold } else { Move::Down });
            let dir = if row % 2 == 0 {
                Move::Right
            } else {
                Move::Left
            };
            m.resize(m.len() + w - 1, dir);
        }
        m
    }
}

impl PolySetup {
    /// The moves of bounding-box row `row` (0 = top), appended to `out`: `moves()`
    /// a row at a time (`Hold` or `Down`, then `width − 1` steps right on even rows and
    /// left on odd ones), so a walk can be fed to the unit in row-sized chunks.
    pub fn row_moves(&self, row: u64, out: &mut Vec<Move>) {
        let Some(b) = self.bbox else {
            return;
        };
        out.push(if row == 0 { Move::Hold } else { Move::Down });
        let dir = if row & 1 == 0 {
            Move::Right
        } else {
            Move::Left
        };
        out.resize(out.len() + b.width() as usize - 1, dir);
    }

    /// [`Self::row_moves`] run-length coded: `(Hold or Down, 1)`, then `(Right or Left,
    /// width − 1)`, appended to `out` (what [`PolygonInterpolator::kernel_runs_lanes`]
    /// takes).
    pub fn row_runs(&self, row: u64, out: &mut Vec<(Move, usize)>) {
        let Some(b) = self.bbox else {
            return;
        };
        out.push((if row == 0 { Move::Hold } else { Move::Down }, 1));
        let dir = if row & 1 == 0 {
            Move::Right
        } else {
            Move::Left
        };
        out.push((dir, b.width() as usize - 1));
    }
}

/// The registers' increments of one move, as the kernel's step mux picks them: the
/// pixel counters (dx, dy), the edges and the attribute accumulators (`Hold`: none).
#[derive(Clone, Copy)]
struct Step {
    dx: i64,
    dy: i64,
    edge: [i64; EDGES],
    grad: [i64; MAX_ATTRS],
}

impl Step {
    #[inline]
    fn of(st: &PolyState, mv: Move, k: usize) -> Step {
        let mut s = Step {
            dx: 0,
            dy: 0,
            edge: [0; EDGES],
            grad: [0; MAX_ATTRS],
        };
        match mv {
            Move::Hold => {}
            Move::Right | Move::Left => {
                let sign = if mv == Move::Right { 1 } else { -1 };
                s.dx = sign;
                for (e, &d) in s.edge.iter_mut().zip(&st.edge_dx) {
                    *e = sign * d;
                }
                for (g, &d) in s.grad.iter_mut().zip(&st.grad_x).take(k) {
                    *g = sign * d;
                }
            }
            Move::Down => {
                s.dy = 1;
                s.edge = st.edge_dy;
                s.grad[..k].copy_from_slice(&st.grad_y[..k]);
            }
        }
        s
    }
}

/// The output rounding by `sh` (≥ 1) bits in mode `q` of an accumulator value
/// (|v| < 2^61): [`round_shift_right_i64`], with RND as one add and a shift and TRN
/// as a shift (the same integers: floor((v + 2^(sh−1)) / 2^sh) is floor(v / 2^sh) plus
/// one iff the dropped bits are at least half).
#[inline(always)]
fn round_acc(v: i64, sh: u32, q: Quant) -> i64 {
    match q {
        Quant::Rnd => (v + (1i64 << (sh - 1))) >> sh,
        Quant::Trn => v >> sh,
        _ => round_shift_right_i64(v, sh, q),
    }
}

/// One attribute along a closed-form run: A = a0 + j·g at step j = 1 ..= run,
/// rounded into the output format [lo, hi]; events count on the covered steps.
/// `wrap`: the accumulator's [min, max] when the run leaves it (WRAP mode): then it
/// is stepped modularly, as the kernel steps it.
struct AttrLine {
    a: usize,
    a0: i64,
    g: i64,
    lo: i64,
    hi: i64,
    inside: std::ops::Range<usize>,
    wrap: Option<(i64, i64)>,
}

impl AttrLine {
    /// Write attribute `a` of every output of the run; (saturations, underflows, and
    /// for a wrapping run its last value and wraps).
    #[inline(always)]
    fn fill(
        &self,
        outs: &mut [PolyOut],
        round: impl Fn(i64) -> i64,
    ) -> (u64, u64, Option<(i64, u64)>) {
        let a = self.a;
        let run = outs.len();
        self.fill_slots(outs.iter_mut().map(|o| &mut o.attrs[a]), run, round)
    }

    /// [`AttrLine::fill`] appending the run's values to one attribute lane: a
    /// constant written once (one `resize`; not at all unless `keep`), else the lane grown by `run` and filled
    /// as a slice (the loop the compiler vectorises; an `extend` from a counting
    /// closure did not, and kept the event counts in memory).
    #[inline(always)]
    fn extend_lane(
        &self,
        lane: &mut Vec<i64>,
        run: usize,
        keep: bool,
        round: impl Fn(i64) -> i64,
    ) -> (u64, u64, Option<(i64, u64)>) {
        if self.wrap.is_none() && self.g == 0 {
            let (c, s, u) = self.one(self.a0, &round);
            if keep {
                lane.resize(lane.len() + run, c);
            }
            let n = self.inside.len() as u64;
            return (s * n, u * n, None);
        }
        if !keep && self.wrap.is_none() {
            // Unread: its events alone, none on a quiet run.
            if self.quiet(run, &round) {
                return (0, 0, None);
            }
            return self.count_events(&round);
        }
        let base = lane.len();
        lane.resize(base + run, 0);
        self.fill_slots(lane[base..].iter_mut(), run, round)
    }

    /// [`AttrLine::extend_lane`], appending only the covered steps' values where
    /// `covered_only` (the same events and last value: they count on covered steps
    /// alone, and a wrapping accumulator is stepped over the whole run).
    #[inline(always)]
    fn extend_lane_steps(
        &self,
        lane: &mut Vec<i64>,
        run: usize,
        covered_only: bool,
        keep: bool,
        round: impl Fn(i64) -> i64,
    ) -> (u64, u64, Option<(i64, u64)>) {
        if !covered_only {
            return self.extend_lane(lane, run, keep, round);
        }
        let (start, n) = (self.inside.start, self.inside.len());
        if self.wrap.is_some() {
            // Stepped modularly from the run's start, each wrap counted: the whole run
            // computed, its covered steps kept.
            let base = lane.len();
            lane.resize(base + run, 0);
            let r = self.fill_slots(lane[base..].iter_mut(), run, round);
            lane.copy_within(base + start..base + start + n, base);
            lane.truncate(if keep { base + n } else { base });
            return r;
        }
        // Without wrapping, step j holds a0 + j·g: the covered steps are a line of
        // their own from step `start`, every one of them covered.
        let covered = AttrLine {
            a: self.a,
            a0: self.a0 + start as i64 * self.g,
            g: self.g,
            lo: self.lo,
            hi: self.hi,
            inside: 0..n,
            wrap: None,
        };
        covered.extend_lane(lane, n, keep, round)
    }

    /// Whether a run of `run` steps that does not wrap has no event to count:
    /// rounding (every mode) is monotone, so along the affine run the rounded values
    /// go from the first step's to the last's; if both are inside the output range and
    /// of one strict sign, no step saturates or rounds to 0. Then the codes are the
    /// rounded values, written with no counting (the same codes).
    #[inline(always)]
    fn quiet(&self, run: usize, round: &impl Fn(i64) -> i64) -> bool {
        if self.wrap.is_some() {
            return false; // (and a0 + run·g may not even fit 64 bits)
        }
        let (first, last) = (
            round(self.a0 + self.g),
            round(self.a0 + run as i64 * self.g),
        );
        let (lo, hi) = (first.min(last), first.max(last));
        lo >= self.lo && hi <= self.hi && (lo > 0 || hi < 0)
    }

    /// The events [`Self::fill_slots`] counts on a run that does not wrap and
    /// whose step is not 0, without writing its values: (saturations, underflows,
    /// None). Rounding (every mode) is monotone and the run affine, so the steps j
    /// (j = 0 .. run, value A = a0 + (j + 1)·g) where the rounded value lies above
    /// the output range, below it, or at 0 are each one interval of j, found by
    /// bisection within the covered steps; an underflow is a 0 whose A is not 0
    /// (at most one step has A = 0).
    fn count_events(&self, round: &impl Fn(i64) -> i64) -> (u64, u64, Option<(i64, u64)>) {
        let (from, to) = (self.inside.start as i64, self.inside.end as i64);
        let code = |j: i64| round(self.a0 + (j + 1) * self.g);
        // The steps of [from, to) where `at(code)` holds, for a predicate true on
        // the codes below some value (false above it).
        let count_below = |at: &dyn Fn(i64) -> bool| -> i64 {
            // Rising codes: the true steps are a prefix, else a suffix.
            let rising = self.g > 0;
            let (mut lo, mut hi) = (from, to);
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if at(code(mid)) == rising {
                    lo = mid + 1;
                } else {
                    hi = mid;
                }
            }
            if rising {
                lo - from
            } else {
                to - lo
            }
        };
        let n = to - from;
        let above = n - count_below(&|c| c <= self.hi);
        let below = count_below(&|c| c < self.lo);
        let zeros = count_below(&|c| c <= 0) - count_below(&|c| c < 0);
        // A step with A = 0 exactly: (j + 1)·g = −a0.
        let exact = (self.a0 % self.g == 0)
            .then(|| -self.a0 / self.g - 1)
            .is_some_and(|j| (from..to).contains(&j));
        let under = zeros - i64::from(exact);
        ((above + below) as u64, under as u64, None)
    }

    /// One accumulator value rounded and clamped into the output format: (code,
    /// saturated, underflowed).
    #[inline(always)]
    fn one(&self, v: i64, round: &impl Fn(i64) -> i64) -> (i64, u64, u64) {
        let r = round(v);
        let c = r.clamp(self.lo, self.hi);
        (c, u64::from(c != r), u64::from(r == 0 && v != 0))
    }

    /// The run's values of the attribute, in order, into `slots` (one per output of the
    /// run: a PolyOut word's attribute or a lane's entry).
    #[inline(always)]
    fn fill_slots<'s>(
        &self,
        slots: impl Iterator<Item = &'s mut i64>,
        run: usize,
        round: impl Fn(i64) -> i64,
    ) -> (u64, u64, Option<(i64, u64)>) {
        let one = |v: i64| self.one(v, &round);
        if let Some((min, max)) = self.wrap {
            let (mut sat, mut under) = (0u64, 0u64);
            // s(acc) + s(acc) → s(acc + 1), back into s(acc) modulo 2^acc (|g| ≤ 2^(acc−1),
            // so one step wraps at most once).
            let span = max - min + 1;
            let (mut v, mut wraps) = (self.a0, 0u64);
            for (j, o) in slots.enumerate() {
                v += self.g;
                if v > max {
                    v -= span;
                    wraps += 1;
                } else if v < min {
                    v += span;
                    wraps += 1;
                }
                let (c, s, u) = one(v);
                *o = c;
                let counted = u64::from(self.inside.contains(&j));
                sat += s * counted;
                under += u * counted;
            }
            return (sat, under, Some((v, wraps)));
        }
        if self.g == 0 {
            // A constant along the run: one rounding.
            let (c, s, u) = one(self.a0);
            slots.for_each(|o| *o = c);
            let n = self.inside.len() as u64;
            return (s * n, u * n, None);
        }
        // The codes written as a plain loop (the compiler vectorises it), the events
        // counted apart: none on a quiet run, else by bisection.
        let quiet = self.quiet(run, &round);
        for (j, o) in slots.enumerate() {
            // |a0 + j·g| < 2^61 along the run: no i64 overflow.
            *o = round(self.a0 + (j as i64 + 1) * self.g).clamp(self.lo, self.hi);
        }
        if quiet {
            (0, 0, None)
        } else {
            self.count_events(&round)
        }
    }
}

/// A run that goes in closed form: the output shift, the registers' last values,
/// which accumulators wrap, the formats' ranges and the covered interval of the run.
struct RunPlan {
    shift: u32,
    x_end: i64,
    y_end: i64,
    edge_end: [i64; EDGES],
    acc_end: [i64; MAX_ATTRS],
    wraps: [bool; MAX_ATTRS],
    acc_range: (i64, i64),
    out_range: (i64, i64),
    inside: std::ops::Range<usize>,
}

impl RunPlan {
    /// Attribute `a`'s line along the run.
    #[inline]
    fn line(&self, st: &PolyState, a: usize, step: &Step) -> AttrLine {
        AttrLine {
            a,
            a0: st.acc[a],
            g: step.grad[a],
            lo: self.out_range.0,
            hi: self.out_range.1,
            inside: self.inside.clone(),
            wrap: self.wraps[a].then_some(self.acc_range),
        }
    }

    /// Attribute `a`'s events counted (and a wrapping accumulator's last value kept).
    #[inline]
    fn count(
        &mut self,
        a: usize,
        sat: u64,
        under: u64,
        wrapped: Option<(i64, u64)>,
        ctr: &mut Counters,
    ) {
        ctr.saturations += sat;
        ctr.underflows += under;
        if let Some((end, n)) = wrapped {
            self.acc_end[a] = end;
            ctr.overflows += n;
        }
    }

    /// The registers at the run's end.
    #[inline]
    fn finish(&self, st: &mut PolyState, k: usize) {
        st.x = self.x_end;
        st.y = self.y_end;
        st.edge = self.edge_end;
        st.acc[..k].copy_from_slice(&self.acc_end[..k]);
    }
}

/// floor(a / b) for b > 0.
fn floor_div(a: i64, b: i64) -> i64 {
    a.div_euclid(b)
}

/// round(num · 2^k / den) to nearest, ties toward +∞, for den > 0: a rounding integer
/// division (the setup divider). The power of two goes to the numerator or the divisor.
fn div_round_pow2(num: i128, k: i32, den: i128) -> i128 {
    let (n, d) = if k >= 0 {
        (num << k, den)
    } else {
        (num, den << (-k))
    };
    // floor((2n + d) / 2d)
    (2 * n + d).div_euclid(2 * d)
}

/// Sign-extend the low `w` bits of `v` (two's-complement wrap to a w-bit register).
#[inline]
fn wrap_signed(v: i64, w: u32) -> i64 {
    let sh = 64 - w;
    (v << sh) >> sh
}

impl PolygonInterpolator {
    /// Validated constructor (see [`PolygonInterpolatorConfig`] for ranges).
    pub fn new(cfg: PolygonInterpolatorConfig) -> Result<Self, ConfigError> {
        cfg.build()
    }

    /// GeForce-era defaults: 4 attributes s16.16, 4 sub-pixel bits, ±4096 px,
    /// accumulators s20.24 (WRAP), outputs s16.8 rounded RND.
    pub fn geforce() -> Self {
        PolygonInterpolator {
            cfg: PolygonInterpolatorConfig::default(),
        }
    }

    /// The config the unit was built from.
    pub fn config(&self) -> PolygonInterpolatorConfig {
        self.cfg
    }
    /// Attributes per primitive, 0 ..= 16.
    pub fn attrs(&self) -> u32 {
        self.cfg.attrs
    }
    /// Sub-pixel bits of vertex positions, 0 ..= 8.
    pub fn subpixel_bits(&self) -> u32 {
        self.cfg.subpixel_bits
    }
    /// Integer bits of vertex positions and pixel counters, including the sign, 2 ..= 14.
    pub fn coord_int_bits(&self) -> u32 {
        self.cfg.coord_int_bits
    }
    /// Format of the vertex attributes (width 1 ..= 32).
    pub fn attr_fmt(&self) -> Format {
        self.cfg.attr_fmt
    }
    /// Integer bits of the signed accumulators, including the sign, 1 ..= 48.
    pub fn acc_int_bits(&self) -> u32 {
        self.cfg.acc_int_bits
    }
    /// Fraction bits of the accumulators, 1 ..= 40.
    pub fn acc_frac_bits(&self) -> u32 {
        self.cfg.acc_frac_bits
    }
    /// What an accumulator does on overflow: WRAP (counted in `overflows`) or a SAT mode
    /// (counted in `saturations`).
    pub fn acc_overflow(&self) -> Overflow {
        self.cfg.acc_overflow
    }
    /// Integer bits of the output attributes (including the sign when `attr_fmt` is
    /// signed), 0 ..= 40.
    pub fn out_int_bits(&self) -> u32 {
        self.cfg.out_int_bits
    }
    /// Fraction bits of the output attributes, 0 ..= 40.
    pub fn out_frac_bits(&self) -> u32 {
        self.cfg.out_frac_bits
    }
    /// Rounding of an accumulator to the output format.
    pub fn out_quant(&self) -> Quant {
        self.cfg.out_quant
    }

    /// Vertex position format s(c).(s).
    pub fn pos_fmt(&self) -> Format {
        Format {
            int_bits: self.cfg.coord_int_bits,
            frac_bits: self.cfg.subpixel_bits,
            signed: true,
        }
    }

    /// Accumulator format s(acc_int).(acc_frac).
    pub fn acc_fmt(&self) -> Format {
        Format {
            int_bits: self.cfg.acc_int_bits,
            frac_bits: self.cfg.acc_frac_bits,
            signed: true,
        }
    }

    /// Output format (signed iff `attr_fmt` is).
    pub fn out_fmt(&self) -> Format {
        Format {
            int_bits: self.cfg.out_int_bits,
            frac_bits: self.cfg.out_frac_bits,
            signed: self.cfg.attr_fmt.signed,
        }
    }

    /// The output rounding's right shift, acc_frac − out_frac, where it is at least 1
    /// (the closed forms round by a shift); None elsewhere.
    fn out_shift(&self) -> Option<u32> {
        let shift = self.cfg.acc_frac_bits as i32 - self.cfg.out_frac_bits as i32;
        (shift > 0).then_some(shift as u32)
    }

    /// The output format's least and greatest raw code.
    fn out_range(&self) -> (i64, i64) {
        let of = self.out_fmt();
        (of.min_raw() as i64, of.max_raw() as i64)
    }

    /// The least and the greatest code of attribute `a` over the pixels `xs` × `ys`
    /// of primitive `s`, as its walk writes them, where that is certain in closed
    /// form; None elsewhere. Certain where the accumulator is affine in the pixel
    /// (no barycentric weights) and stays in its format: at every corner of the
    /// rectangle A + (x − x₀)·dA/dx + (y − y₀)·dA/dy (exact, in 128 bits) lies
    /// strictly above the format's minimum and at most its maximum, and so does every
    /// pixel's (an affine function's extremes on a rectangle lie at its corners), so
    /// no step wraps or saturates and each pixel's accumulator is that value. The
    /// output rounding (shift ≥ 1) and clamp are monotone: the codes' extremes are
    /// the corners' codes. (Whether a pixel is covered plays no part.)
    pub fn attr_code_range(
        &self,
        s: &PolySetup,
        a: usize,
        xs: std::ops::RangeInclusive<i64>,
        ys: std::ops::RangeInclusive<i64>,
    ) -> Option<(i64, i64)> {
        let top = self.attr_row(s, a, xs.clone(), *ys.start())?.range();
        let bottom = self.attr_row(s, a, xs, *ys.end())?.range();
        Some((top.0.min(bottom.0), top.1.max(bottom.1)))
    }

    /// Attribute `a`'s codes along the pixels `xs` of row `y` of primitive `s`, as
    /// its walk writes them, where they are certain in closed form
    /// ([`Self::attr_code_range`]'s conditions, at the row's two ends); None
    /// elsewhere.
    pub fn attr_row(
        &self,
        s: &PolySetup,
        a: usize,
        xs: std::ops::RangeInclusive<i64>,
        y: i64,
    ) -> Option<AttrRow> {
        let st = &s.state;
        let shift = self.out_shift()?;
        if st.bary.is_some() || a >= self.cfg.attrs as usize || xs.is_empty() {
            return None;
        }
        let acc = self.acc_fmt();
        let at = |x: i64| {
            let v = st.acc[a] as i128
                + (x - st.x) as i128 * st.grad_x[a] as i128
                + (y - st.y) as i128 * st.grad_y[a] as i128;
            (v > acc.min_raw() && v <= acc.max_raw()).then_some(v as i64)
        };
        let (x0, x1) = (*xs.start(), *xs.end());
        let (v0, _) = (at(x0)?, at(x1)?);
        Some(AttrRow {
            x0,
            x1,
            v0,
            g: st.grad_x[a],
            shift,
            quant: self.cfg.out_quant,
            range: self.out_range(),
        })
    }

    /// Width of an edge accumulator: 2c + 2s + 4 (derivation at `setup_poly`).
    pub fn edge_bits(&self) -> u32 {
        2 * self.cfg.coord_int_bits + 2 * self.cfg.subpixel_bits + 4
    }

    /// Value of an output code.
    pub fn out_to_f64(&self, raw: i64) -> f64 {
        raw as f64 * (-(self.cfg.out_frac_bits as f64)).exp2()
    }

    /// Clocks the setup engine spends on one primitive (an estimate of the sequenced
    /// datapath costed under "setup:"): 2 clocks for the deltas and area, 4 for the edges
    /// (one per clock), 3·K divider issues (dA/dx, dA/dy, start per attribute) and ⌈QW/4⌉
    /// clocks of divider pipeline fill (QW = acc width + 2 quotient rows, 4 per stage). Not counted by the drivers; a walker fed
    /// primitives of fewer pixels than this would wait on setup.
    pub fn setup_cycles(&self) -> u32 {
        let qw = self.cfg.acc_int_bits + self.cfg.acc_frac_bits + 2;
        2 + EDGES as u32 + 3 * self.cfg.attrs + qw.div_ceil(4)
    }

    // ---------------------------------------------------------------- host helpers

    /// Quantise an f64 vertex (pixels, attribute values) into raw codes. Positions round
    /// to nearest-even onto the sub-pixel grid; NaN/±∞ or a position outside the
    /// coordinate range is an error naming `polygon_interpolator.vertices[i].x` / `.y`.
    /// Attributes round to nearest-even into `attr_fmt` and saturate (counted in
    /// `ctr.saturations`) if out of range; NaN/±∞ names `…vertices[i].attrs[j]`; a
    /// count other than `attrs` names `…vertices[i].attrs`.
    pub fn vertex_from_f64(
        &self,
        index: usize,
        x: f64,
        y: f64,
        attrs: &[f64],
        ctr: &mut Counters,
    ) -> Result<Vertex, ConfigError> {
        let pos = self.pos_fmt();
        let mut v = Vertex::default();
        for (name, val, slot) in [("x", x, &mut v.x), ("y", y, &mut v.y)] {
            // Field names are formatted only for an error (this runs per vertex).
            let field = || format!("{NAME}.vertices[{index}].{name}");
            if !val.is_finite() {
                return Err(ConfigError::not_finite(&field(), val));
            }
            let mut local = Counters::default();
            let q = Fx::from_f64(val, pos, Quant::RndConv, Overflow::Sat, NAME, &mut local)?;
            if local.saturations > 0 {
                let lsb = pos.lsb();
                return Err(ConfigError::out_of_range(
                    &field(),
                    val,
                    pos.min_raw() as f64 * lsb,
                    pos.max_raw() as f64 * lsb,
                ));
            }
            *slot = q.raw as i64;
        }
        let k = self.cfg.attrs as usize;
        if attrs.len() != k {
            return Err(ConfigError::invalid(
                &format!("{NAME}.vertices[{index}].attrs"),
                &format!(
                    "{} attributes given, the unit is configured for {k}",
                    attrs.len()
                ),
            ));
        }
        for (j, &a) in attrs.iter().enumerate() {
            if !a.is_finite() {
                let field = format!("{NAME}.vertices[{index}].attrs[{j}]");
                return Err(ConfigError::not_finite(&field, a));
            }
            let q = Fx::from_f64(
                a,
                self.cfg.attr_fmt,
                Quant::RndConv,
                Overflow::Sat,
                NAME,
                ctr,
            )?;
            v.attrs[j] = q.raw as i64;
        }
        Ok(v)
    }

    /// The vertex as the hardware sees it (masked to the wires), in f64: (x px, y px,
    /// attribute values). For feeding the f64 twin the same quantised data.
    pub fn vertex_to_f64(&self, v: &Vertex) -> (f64, f64, Vec<f64>) {
        let m = self.mask(v);
        let sl = self.pos_fmt().lsb();
        let al = self.cfg.attr_fmt.lsb();
        let a = m.attrs[..self.cfg.attrs as usize]
            .iter()
            .map(|&r| r as f64 * al)
            .collect();
        (m.x as f64 * sl, m.y as f64 * sl, a)
    }

    /// Mask a vertex's words to their wire widths.
    fn mask(&self, v: &Vertex) -> Vertex {
        let pw = self.pos_fmt().width();
        let af = self.cfg.attr_fmt;
        let mut m = Vertex {
            x: wrap_signed(v.x, pw),
            y: wrap_signed(v.y, pw),
            attrs: [0; MAX_ATTRS],
        };
        for i in 0..self.cfg.attrs as usize {
            m.attrs[i] = if af.signed {
                wrap_signed(v.attrs[i], af.width())
            } else {
                v.attrs[i] & ((1i64 << af.width()) - 1)
            };
        }
        m
    }

    // ---------------------------------------------------------------- setup

    /// Plane numerators of every attribute through (v0, v1, v2), exact:
    /// A(X, Y) = A0 + (Nx·(X − X0) + Ny·(Y − Y0)) / area2, positions in sub-pixel units.
    fn plane(&self, v: &[Vertex; 3]) -> (i128, [i128; MAX_ATTRS], [i128; MAX_ATTRS]) {
        // Positions s(c+s) → deltas s(c+s+1) =: D bits.
        let (dx1, dy1) = ((v[1].x - v[0].x) as i128, (v[1].y - v[0].y) as i128);
        let (dx2, dy2) = ((v[2].x - v[0].x) as i128, (v[2].y - v[0].y) as i128);
        // D × D → 2D, difference → 2D + 1 bits (≤ 47 at c + s = 22).
        let area2 = dx1 * dy2 - dy1 * dx2;
        let mut nx = [0i128; MAX_ATTRS];
        let mut ny = [0i128; MAX_ATTRS];
        for i in 0..self.cfg.attrs as usize {
            // Attribute deltas: attr width + 1 (≤ 33) bits.
            let da1 = (v[1].attrs[i] - v[0].attrs[i]) as i128;
            let da2 = (v[2].attrs[i] - v[0].attrs[i]) as i128;
            // (attr+1) × D → attr + D + 1, difference → attr + D + 2 bits (≤ 57).
            nx[i] = da1 * dy2 - da2 * dy1;
            ny[i] = dx1 * da2 - dx2 * da1;
        }
        (area2, nx, ny)
    }

    /// Triangle setup. Zero area → an empty primitive (no pixels).
    pub fn setup_triangle(&self, v: &[Vertex; 3], ctr: &mut Counters) -> PolySetup {
        let v = [self.mask(&v[0]), self.mask(&v[1]), self.mask(&v[2])];
        let (area2, mut nx, mut ny) = self.plane(&v);
        if area2 == 0 {
            return PolySetup::empty(0);
        }
        let p = |u: &Vertex| [u.x, u.y];
        let mut setup = if area2 > 0 {
            self.setup_poly(&[p(&v[0]), p(&v[1]), p(&v[2])], &v[0], area2, &nx, &ny, ctr)
        } else {
            // Reverse the winding so that the interior is on the positive side of every
            // edge; the plane numerators change sign with the area.
            nx.iter_mut().chain(ny.iter_mut()).for_each(|n| *n = -*n);
            self.setup_poly(
                &[p(&v[0]), p(&v[2]), p(&v[1])],
                &v[0],
                -area2,
                &nx,
                &ny,
                ctr,
            )
        };
        if self.cfg.barycentric.is_some() && setup.bbox.is_some() {
            // Edge i runs from cyc[i] to cyc[i + 1]: the edge opposite v0 is edge 1
            // either way; opposite v2, edge 0 (cyc = v0 v1 v2) or 2 (v0 v2 v1).
            let edge_of = [1, if area2 > 0 { 0 } else { 2 }];
            let bias = edge_of.map(|e| self.unbiased_edge(&setup, e) - setup.state.edge[e]);
            let mut regs = BaryRegs {
                edge_of,
                bias,
                denom: (2 * area2.abs()) as i64,
                ..BaryRegs::default()
            };
            for i in 0..self.cfg.attrs as usize {
                // attr + 1 bits each.
                regs.base[i] = v[1].attrs[i];
                regs.delta[0][i] = v[0].attrs[i] - v[1].attrs[i];
                regs.delta[1][i] = v[2].attrs[i] - v[1].attrs[i];
            }
            setup.state.bary = Some(regs);
        }
        setup
    }

    /// The barycentric mode's output stage ([`Barycentric`]): the two weights from the
    /// edge functions (bias added back), quantised down to w bits, then per attribute
    /// base·2^w + q0·Δ0 + q2·Δ2 rounded once by `out_quant` into the output format
    /// (saturating, events counted only for covered pixels).
    fn barycentric_out(
        &self,
        b: &BaryRegs,
        cfg: Barycentric,
        edge: &[i64; EDGES],
        inside: bool,
        out: &mut PolyOut,
        ctr: &mut Counters,
    ) {
        let w = cfg.weight_bits;
        let t = i128::from(cfg.strict);
        let den = i128::from(b.denom.max(1));
        // s(edge) · 2^w − t → edge + w + 1 bits; ÷ the doubled area (a w + 1-bit
        // quotient once clamped to 0 ..= 2^w: pixels outside give weights outside).
        let q = [0, 1].map(|j| {
            let e = i128::from(edge[b.edge_of[j]] + b.bias[j]);
            ((e << w) - t).div_euclid(den).clamp(0, 1i128 << w)
        });
        let af = self.cfg.attr_fmt;
        // base·2^w + two (attr + 1) × (w + 1) products → attr + w + 3 bits.
        let wide = Format {
            int_bits: af.int_bits + 3,
            frac_bits: af.frac_bits + w,
            signed: true,
        };
        let of = self.out_fmt();
        for i in 0..self.cfg.attrs as usize {
            let raw = (i128::from(b.base[i]) << w)
                + q[0] * i128::from(b.delta[0][i])
                + q[1] * i128::from(b.delta[1][i]);
            let (v, ev) =
                Fx { raw, fmt: wide }.assign_events(of, self.cfg.out_quant, Overflow::Sat);
            if inside {
                ctr.saturations += u64::from(ev.saturated);
                ctr.underflows += u64::from(ev.underflowed);
            }
            out.attrs[i] = v.raw as i64;
        }
    }

    /// Edge `e`'s function at the setup's first pixel without the top-left bias (the
    /// bias is −1 on edges that are not top or left).
    fn unbiased_edge(&self, setup: &PolySetup, e: usize) -> i64 {
        setup.state.edge[e] + i64::from(!setup.top_left[e])
    }

    /// GL quad setup: two triangles (v0 v1 v2) and (v0 v2 v3) sharing the edge v0–v2,
    /// each with its own attribute plane. The top-left rule gives every pixel on the
    /// shared edge to exactly one of them. Walk both (two primitives).
    pub fn setup_quad(&self, v: &[Vertex; 4], ctr: &mut Counters) -> [PolySetup; 2] {
        [
            self.setup_triangle(&[v[0], v[1], v[2]], ctr),
            self.setup_triangle(&[v[0], v[2], v[3]], ctr),
        ]
    }

    /// Affine parallelogram v0 v1 v2 v3 with v3 = v0 + v2 − v1 implied (and attributes
    /// affine: A3 = A0 + A2 − A1), walked once with 4 edge functions. An implied v3 outside
    /// the coordinate range is an error naming `polygon_interpolator.vertices[3].x` / `.y`.
    pub fn setup_parallelogram(
        &self,
        v: &[Vertex; 3],
        ctr: &mut Counters,
    ) -> Result<PolySetup, ConfigError> {
        let v = [self.mask(&v[0]), self.mask(&v[1]), self.mask(&v[2])];
        let pos = self.pos_fmt();
        let v3 = [v[0].x + v[2].x - v[1].x, v[0].y + v[2].y - v[1].y];
        for (name, c) in [("x", v3[0]), ("y", v3[1])] {
            if (c as i128) < pos.min_raw() || (c as i128) > pos.max_raw() {
                let lsb = pos.lsb();
                return Err(ConfigError::out_of_range(
                    &format!("{NAME}.vertices[3].{name}"),
                    c as f64 * lsb,
                    pos.min_raw() as f64 * lsb,
                    pos.max_raw() as f64 * lsb,
                ));
            }
        }
        let (area2, mut nx, mut ny) = self.plane(&v);
        if area2 == 0 {
            return Ok(PolySetup::empty(0));
        }
        let p = |u: &Vertex| [u.x, u.y];
        Ok(if area2 > 0 {
            self.setup_poly(
                &[p(&v[0]), p(&v[1]), p(&v[2]), v3],
                &v[0],
                area2,
                &nx,
                &ny,
                ctr,
            )
        } else {
            nx.iter_mut().chain(ny.iter_mut()).for_each(|n| *n = -*n);
            self.setup_poly(
                &[p(&v[0]), v3, p(&v[2]), p(&v[1])],
                &v[0],
                -area2,
                &nx,
                &ny,
                ctr,
            )
        })
    }

    /// A 4-vertex quad that must be an affine parallelogram: v0 + v2 = v1 + v3 exactly in
    /// position and in every attribute (after masking), else an error naming the first
    /// inconsistent field of vertex 3 (`…vertices[3].x`, `.y`, `.attrs[j]`).
    pub fn setup_affine_quad(
        &self,
        v: &[Vertex; 4],
        ctr: &mut Counters,
    ) -> Result<PolySetup, ConfigError> {
        let m: Vec<Vertex> = v.iter().map(|u| self.mask(u)).collect();
        let why = "not an affine parallelogram: v0 + v2 must equal v1 + v3";
        if m[0].x + m[2].x != m[1].x + m[3].x {
            return Err(ConfigError::invalid(&format!("{NAME}.vertices[3].x"), why));
        }
        if m[0].y + m[2].y != m[1].y + m[3].y {
            return Err(ConfigError::invalid(&format!("{NAME}.vertices[3].y"), why));
        }
        for j in 0..self.cfg.attrs as usize {
            if m[0].attrs[j] + m[2].attrs[j] != m[1].attrs[j] + m[3].attrs[j] {
                return Err(ConfigError::invalid(
                    &format!("{NAME}.vertices[3].attrs[{j}]"),
                    why,
                ));
            }
        }
        self.setup_parallelogram(&[m[0], m[1], m[2]], ctr)
    }

    /// Common setup of a convex polygon `cyc` (3 or 4 vertices, positive winding:
    /// interior on the positive side of each edge) with attribute plane through `v0`.
    ///
    /// Grids: sub-pixel units u = 2^-s px (vertices), half units h = u/2 (pixel centres
    /// x·2^(s+1) + 2^s are integers in h even at s = 0). Edge a→b at p:
    /// E = (bx−ax)(py_h − 2ay) − (by−ay)(px_h − 2ax), exact. Widths: bx−ax is s(c+s+1)
    /// with |·| < 2^(c+s); |p_h − 2a| < 2^(c+s+1) for p in the coordinate range; each
    /// product < 2^(2c+2s+1), the difference (and the −1 bias) < 2^(2c+2s+2) + 1, which
    /// a signed 2c+2s+4-bit register holds with a bit to spare.
    fn setup_poly(
        &self,
        cyc: &[[i64; 2]],
        v0: &Vertex,
        area2: i128,
        nx: &[i128; MAX_ATTRS],
        ny: &[i128; MAX_ATTRS],
        ctr: &mut Counters,
    ) -> PolySetup {
        let s = self.cfg.subpixel_bits;
        let (mut xmin, mut xmax, mut ymin, mut ymax) = (i64::MAX, i64::MIN, i64::MAX, i64::MIN);
        for q in cyc {
            xmin = xmin.min(q[0]);
            xmax = xmax.max(q[0]);
            ymin = ymin.min(q[1]);
            ymax = ymax.max(q[1]);
        }
        // Pixels whose centres lie in [min, max]: centre_h(x) = x·2^(s+1) + 2^s.
        let step = 1i64 << (s + 1);
        let half = 1i64 << s;
        let x0 = -floor_div(-(2 * xmin - half), step); // ceil
        let x1 = floor_div(2 * xmax - half, step);
        let y0 = -floor_div(-(2 * ymin - half), step);
        let y1 = floor_div(2 * ymax - half, step);
        if x0 > x1 || y0 > y1 {
            return PolySetup::empty(area2);
        }
        let px_h = x0 * step + half; // s(c+s+1) in h units
        let py_h = y0 * step + half;

        let mut st = PolyState {
            x: x0,
            y: y0,
            ..PolyState::default()
        };
        let n = cyc.len();
        let mut tl = [true; EDGES];
        for i in 0..n {
            let (a, b) = (cyc[i], cyc[(i + 1) % n]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]); // s(c+s+1)
                                                       // s(c+s+1) × s(c+s+2) → s(2c+2s+3); difference → s(2c+2s+4).
            let e = dx * (py_h - 2 * a[1]) - dy * (px_h - 2 * a[0]);
            // Top-left rule (y down, interior on the positive side): a top edge is
            // horizontal with the interior below (dy = 0, dx > 0); a left edge has the
            // interior to its right (dy < 0). Pixels exactly on other edges are outside:
            // E > 0 ⇔ E − 1 ≥ 0 on integers, so the bias makes inside a sign test.
            let top_left = (dy == 0 && dx > 0) || dy < 0;
            st.edge[i] = e - i64::from(!top_left);
            tl[i] = top_left;
            st.edge_dx[i] = -dy * step; // one pixel right: Δp_h = 2^(s+1)
            st.edge_dy[i] = dx * step;
        }
        // An unused 4th edge stays 0 with zero increments: always ≥ 0.

        let fa = self.cfg.attr_fmt.frac_bits as i32;
        let facc = self.cfg.acc_frac_bits as i32;
        let acc = self.acc_fmt();
        let (ox, oy) = (px_h - 2 * v0.x, py_h - 2 * v0.y); // s(c+s+2), h units
        for i in 0..self.cfg.attrs as usize {
            // dA/dx per pixel in accumulator LSBs: Nx·2^s/area2 · 2^(facc−fa).
            // Nx ≤ 57 bits, × 2^(s+facc−fa) ≤ 2^48 → ≤ 105 bits.
            let gx = div_round_pow2(nx[i], s as i32 + facc - fa, area2);
            let gy = div_round_pow2(ny[i], s as i32 + facc - fa, area2);
            // Start at the first pixel centre, over the doubled area (h units):
            // A0·2·area2 (32 + 48 bits) + Nx·ox + Ny·oy (57 + 24 bits each) → ≤ 82 bits,
            // × 2^(facc−fa) ≤ 2^40 → ≤ 122 bits; the rounding doubles it once: ≤ 123.
            let num = v0.attrs[i] as i128 * 2 * area2 + nx[i] * ox as i128 + ny[i] * oy as i128;
            let a0 = div_round_pow2(num, facc - fa, 2 * area2);
            // A non-zero gradient or start that rounds to 0 accumulator LSB is an underflow.
            ctr.underflows += u64::from(gx == 0 && nx[i] != 0)
                + u64::from(gy == 0 && ny[i] != 0)
                + u64::from(a0 == 0 && num != 0);
            st.grad_x[i] = self.fit_acc(gx, acc, ctr);
            st.grad_y[i] = self.fit_acc(gy, acc, ctr);
            st.acc[i] = self.fit_acc(a0, acc, ctr);
        }
        PolySetup {
            bbox: Some(BBox { x0, y0, x1, y1 }),
            edges: n as u32,
            area2,
            state: st,
            top_left: tl,
        }
    }

    /// `run` moves `mv` in closed form, outputs appended; false (nothing done) if a
    /// register might wrap or saturate on the way, or the output rounding is a left
    /// shift (its 64-bit form could overflow).
    fn run_in_closed_form(
        &self,
        st: &mut PolyState,
        mv: Move,
        run: usize,
        out: &mut Vec<PolyOut>,
        ctr: &mut Counters,
    ) -> bool {
        if st.bary.is_some() {
            return false; // the weights' quantisation is not affine along a run
        }
        let k = self.cfg.attrs as usize;
        let step = Step::of(st, mv, k);
        let Some(mut plan) = self.run_plan(st, &step, run) else {
            return false;
        };
        let base = out.len();
        out.resize(
            base + run,
            PolyOut {
                x: 0,
                y: 0,
                inside: false,
                attrs: [0; MAX_ATTRS],
            },
        );
        let outs = &mut out[base..];
        for (j, o) in outs.iter_mut().enumerate() {
            o.x = st.x + step.dx * (j as i64 + 1);
            o.y = st.y + step.dy * (j as i64 + 1);
        }
        for o in &mut outs[plan.inside.clone()] {
            o.inside = true;
        }
        // Output rounding s(acc) → out format, saturating; events only where inside.
        // The rounding mode is matched once per run, so each loop has its own form.
        let sh = plan.shift;
        for a in 0..k {
            let line = plan.line(st, a, &step);
            let (sat, under, wrapped) = match self.cfg.out_quant {
                Quant::Trn => line.fill(outs, |v| round_acc(v, sh, Quant::Trn)),
                Quant::TrnZero => line.fill(outs, |v| round_acc(v, sh, Quant::TrnZero)),
                Quant::Rnd => line.fill(outs, |v| round_acc(v, sh, Quant::Rnd)),
                Quant::RndZero => line.fill(outs, |v| round_acc(v, sh, Quant::RndZero)),
                Quant::RndInf => line.fill(outs, |v| round_acc(v, sh, Quant::RndInf)),
                Quant::RndMinInf => line.fill(outs, |v| round_acc(v, sh, Quant::RndMinInf)),
                Quant::RndConv => line.fill(outs, |v| round_acc(v, sh, Quant::RndConv)),
            };
            plan.count(a, sat, under, wrapped, ctr);
        }
        plan.finish(st, k);
        true
    }

    /// [`Unit::kernel_batch`] with its outputs appended to lanes (`out.k` must be
    /// the config's `attrs`, as [`PolyLanes::clear`] sets it): the same words, final
    /// state and counters; closed-form runs write each attribute's lane in one loop.
    pub fn kernel_batch_lanes(
        &self,
        st: &mut PolyState,
        moves: &[Move],
        out: &mut PolyLanes,
        ctr: &mut Counters,
    ) {
        let mut i = 0;
        while i < moves.len() {
            let mv = moves[i];
            let run = moves[i..].iter().take_while(|&&m| m == mv).count();
            self.kernel_runs_lanes(st, &[(mv, run)], out, ctr);
            i += run;
        }
    }

    /// [`Self::kernel_batch_lanes`] on run-length coded moves: `(m, n)` is `n` moves
    /// `m` (n = 0 is none). The same words, final state and counters as the moves
    /// written out, however a run of one move is split into entries
    /// ([`PolySetup::row_runs`] codes a walk row as two). Each run goes in closed
    /// form where no register can wrap or saturate on the way (every kind of move: a
    /// step is affine in the run), else one kernel call per move. Where
    /// [`PolyLanes::covered_only`], only the covered words are appended.
    pub fn kernel_runs_lanes(
        &self,
        st: &mut PolyState,
        runs: &[(Move, usize)],
        out: &mut PolyLanes,
        ctr: &mut Counters,
    ) {
        self.kernel_runs_lanes_blank(st, runs, &[], out, ctr);
    }

    /// [`Self::kernel_runs_lanes`] where run i leaves the attributes in the mask
    /// `blank[i]` (bit a for attribute a; none past the slice's end) blank: its
    /// words are appended with 0 in those lanes, which no consumer reads there (the
    /// lanes stay in step with the words). They are still computed and counted, as
    /// an unread attribute's are: the same counters and final state. A run that does
    /// not go in closed form writes its values.
    pub fn kernel_runs_lanes_blank(
        &self,
        st: &mut PolyState,
        runs: &[(Move, usize)],
        blank: &[u32],
        out: &mut PolyLanes,
        ctr: &mut Counters,
    ) {
        assert_eq!(
            out.k, self.cfg.attrs as usize,
            "PolyLanes cleared for another attrs"
        );
        for (i, &(mv, run)) in runs.iter().enumerate() {
            let blank = blank.get(i).copied().unwrap_or(0);
            if run > 0 && !self.run_in_closed_form_lanes(st, mv, run, blank, out, ctr) {
                for _ in 0..run {
                    let o = self.kernel(st, &mv, ctr);
                    if o.inside || !out.covered_only {
                        out.push(&o);
                    }
                }
            }
        }
    }

    /// [`Self::run_in_closed_form`] appending to lanes, each entry written once.
    fn run_in_closed_form_lanes(
        &self,
        st: &mut PolyState,
        mv: Move,
        run: usize,
        blank: u32,
        out: &mut PolyLanes,
        ctr: &mut Counters,
    ) -> bool {
        if st.bary.is_some() {
            return false; // the weights' quantisation is not affine along a run
        }
        let k = self.cfg.attrs as usize;
        let step = Step::of(st, mv, k);
        let Some(mut plan) = self.run_plan(st, &step, run) else {
            return false;
        };
        let base = out.len();
        let covered_only = out.covered_only;
        // The steps appended (j = 1 ..= run, the run's index j − 1): all, or the
        // covered ones alone.
        let steps = if covered_only {
            plan.inside.clone()
        } else {
            0..run
        };
        let (x0, y0, dx, dy) = (st.x, st.y, step.dx, step.dy);
        for (lane, c0, d) in [(&mut out.x, x0, dx), (&mut out.y, y0, dy)] {
            if d == 0 {
                lane.resize(base + steps.len(), c0);
            } else {
                lane.extend((steps.start as i64 + 1..=steps.end as i64).map(|j| c0 + d * j));
            }
        }
        if covered_only {
            out.inside.resize(base + steps.len(), true);
        } else {
            out.inside.resize(base + plan.inside.start, false);
            out.inside.resize(base + plan.inside.end, true);
            out.inside.resize(base + run, false);
        }
        let sh = plan.shift;
        for a in 0..k {
            let line = plan.line(st, a, &step);
            // An unread attribute is computed into the spare lane (a constant one not
            // at all), its events counted all the same; so is a blank one, whose lane
            // then takes a 0 per word appended.
            let read = out.is_read(a);
            let keep = read && (blank >> a) & 1 == 0;
            if read && !keep {
                let at = out.attrs[a].len();
                out.attrs[a].resize(at + steps.len(), 0);
            }
            let lane = if keep {
                &mut out.attrs[a]
            } else {
                out.spare.clear();
                &mut out.spare
            };
            // One loop per rounding mode, the mode a constant inside it.
            macro_rules! extend_rounded {
                ($($q:ident),*) => {
                    match self.cfg.out_quant {
                        $(Quant::$q => line.extend_lane_steps(lane, run, covered_only, keep, |v| {
                            round_acc(v, sh, Quant::$q)
                        }),)*
                    }
                };
            }
            let (sat, under, wrapped) =
                extend_rounded!(Trn, TrnZero, Rnd, RndZero, RndInf, RndMinInf, RndConv);
            plan.count(a, sat, under, wrapped, ctr);
        }
        plan.finish(st, k);
        true
    }

    /// Whether `run` moves of `step` can go in closed form (see
    /// [`Self::run_in_closed_form`]), and if so the registers' last values and the
    /// covered interval of the run.
    fn run_plan(&self, st: &PolyState, step: &Step, run: usize) -> Option<RunPlan> {
        let k = self.cfg.attrs as usize;
        let shift = self.out_shift()?;
        let steps = run as i64;
        // Pixel counters (c bits): the last values must fit.
        let cw = self.cfg.coord_int_bits;
        let (x_end, y_end) = (st.x + steps * step.dx, st.y + steps * step.dy);
        if wrap_signed(x_end, cw) != x_end || wrap_signed(y_end, cw) != y_end {
            return None;
        }
        // Edges (ew bits): the last values must fit.
        let ew = self.edge_bits();
        // (An i64 overflow on the way is a value no ≤ 62-bit register holds.)
        let affine = |a: i64, d: i64| d.checked_mul(steps).and_then(|p| p.checked_add(a));
        let mut edge_end = [0i64; EDGES];
        for ((end_e, &e0), &d) in edge_end.iter_mut().zip(&st.edge).zip(&step.edge) {
            match affine(e0, d) {
                Some(end) if wrap_signed(end, ew) == end => *end_e = end,
                _ => return None,
            }
        }
        // Accumulators (≤ 62 bits): the last value strictly above the format's minimum
        // (fit_acc sends the minimum through the overflow mode) and at most its maximum,
        // for the affine closed form. One whose last value leaves this: under WRAP it is
        // stepped modularly below (each wrap counted, as the kernel counts it); under
        // a SAT mode the run goes to the per-step kernel.
        let acc = self.acc_fmt();
        let (acc_min, acc_max) = (acc.min_raw() as i64, acc.max_raw() as i64);
        let mut acc_end = [0i64; MAX_ATTRS];
        let mut wraps = [false; MAX_ATTRS];
        for a in 0..k {
            match affine(st.acc[a], step.grad[a]) {
                Some(end) if end > acc_min && end <= acc_max => acc_end[a] = end,
                _ if self.cfg.acc_overflow == Overflow::Wrap => wraps[a] = true,
                _ => return None,
            }
        }
        // Each edge is affine along the run, E + j·D (j = 1 ..= run), so the pixels
        // inside all edges are one interval of j: intersect each edge's half-line. An
        // edge inside at both ends of the run bounds nothing (no division).
        let (mut j_lo, mut j_hi) = (1i64, steps);
        for ((&e0, &d), &end) in st.edge.iter().zip(&step.edge).zip(&edge_end) {
            if d > 0 {
                if e0 + d < 0 {
                    j_lo = j_lo.max((-e0).div_euclid(d) + i64::from((-e0).rem_euclid(d) != 0));
                }
            } else if d < 0 {
                if end < 0 {
                    j_hi = j_hi.min(e0.div_euclid(-d));
                }
            } else if e0 < 0 {
                j_hi = 0;
            }
        }
        let inside = if j_lo <= j_hi {
            (j_lo - 1) as usize..j_hi as usize
        } else {
            0..0
        };
        Some(RunPlan {
            shift,
            x_end,
            y_end,
            edge_end,
            acc_end,
            wraps,
            acc_range: (acc_min, acc_max),
            out_range: self.out_range(),
            inside,
        })
    }

    /// Put an integer number of accumulator LSBs into the accumulator by `acc_overflow`
    /// (counted: WRAP in `overflows`, SAT modes in `saturations`).
    #[inline]
    fn fit_acc(&self, raw: i128, acc: Format, ctr: &mut Counters) -> i64 {
        if raw > acc.min_raw() && raw <= acc.max_raw() {
            return raw as i64;
        }
        let wide = Format {
            int_bits: 127 - acc.frac_bits,
            frac_bits: acc.frac_bits,
            signed: true,
        };
        Fx { raw, fmt: wide }
            .assign(acc, Quant::Trn, self.cfg.acc_overflow, ctr)
            .raw as i64
    }
}

impl Unit for PolygonInterpolator {
    type In = Move;
    type Out = PolyOut;
    type State = PolyState;

    fn name(&self) -> &'static str {
        NAME
    }

    fn kernel(&self, st: &mut PolyState, mv: &Move, ctr: &mut Counters) -> PolyOut {
        let k = self.cfg.attrs as usize;
        let cw = self.cfg.coord_int_bits;
        let ew = self.edge_bits();
        let acc = self.acc_fmt();
        // Stage 1: one add per accumulator. The step mux picks +dx, −dx (XOR + carry in)
        // or +dy; Hold disables the register.
        let (dxy, sign): (bool, i64) = match mv {
            Move::Hold => (false, 0),
            Move::Right => (false, 1),
            Move::Left => (false, -1),
            Move::Down => (true, 1),
        };
        if sign != 0 {
            // Pixel counters: c bits, ±1.
            let (nx, ny) = if dxy {
                (st.x, st.y + 1)
            } else {
                (st.x + sign, st.y)
            };
            let (wx, wy) = (wrap_signed(nx, cw), wrap_signed(ny, cw));
            ctr.overflows += u64::from(wx != nx) + u64::from(wy != ny);
            st.x = wx;
            st.y = wy;
            for e in 0..EDGES {
                let inc = if dxy {
                    st.edge_dy[e]
                } else {
                    sign * st.edge_dx[e]
                };
                // s(ew) + s(ew) → s(ew+1) ≤ 49 bits; wrap to ew (counted).
                let sum = st.edge[e] + inc;
                let w = wrap_signed(sum, ew);
                ctr.overflows += u64::from(w != sum);
                st.edge[e] = w;
            }
            for i in 0..k {
                let inc = if dxy {
                    st.grad_y[i]
                } else {
                    sign * st.grad_x[i]
                };
                // s(acc) + s(acc) → s(acc+1) ≤ 63 bits; back to s(acc) by acc_overflow.
                let sum = st.acc[i] as i128 + inc as i128;
                st.acc[i] = self.fit_acc(sum, acc, ctr);
            }
        }
        // Stage 2: inside = no edge sign bit set; round s(acc) → output format (RND:
        // + half LSB, truncate), saturate. Output events count only for covered pixels
        // (the counter enables are gated by inside).
        let inside = st.edge.iter().all(|&e| e >= 0);
        let mut out = PolyOut {
            x: st.x,
            y: st.y,
            inside,
            attrs: [0; MAX_ATTRS],
        };
        let of = self.out_fmt();
        if let (Some(b), Some(cfg)) = (&st.bary, self.cfg.barycentric) {
            self.barycentric_out(b, cfg, &st.edge, inside, &mut out, ctr);
            return out;
        }
        for i in 0..k {
            let (v, ev) = Fx {
                raw: st.acc[i] as i128,
                fmt: acc,
            }
            .assign_events(of, self.cfg.out_quant, Overflow::Sat);
            if inside {
                ctr.saturations += u64::from(ev.saturated);
                ctr.underflows += u64::from(ev.underflowed);
            }
            out.attrs[i] = v.raw as i64;
        }
        out
    }

    /// Runs of one move are evaluated in closed form where the run can neither wrap
    /// nor saturate any register: every register is affine along the run (A + k·g;
    /// a `Down` run steps by the y-increments, a `Hold` run by none), so if its last
    /// value lies strictly inside its format (and the pixel counters' and edges' last
    /// values inside theirs) no step of the run fits, wraps or counts anything, and
    /// each step's value is A + k·g exactly. Runs that might overflow go through the
    /// per-step kernel, and so does every move of the barycentric mode (its output is
    /// not affine along a run).
    fn kernel_batch(
        &self,
        st: &mut PolyState,
        moves: &[Move],
        out: &mut Vec<PolyOut>,
        ctr: &mut Counters,
    ) {
        let mut i = 0;
        while i < moves.len() {
            let mv = moves[i];
            let run = moves[i..].iter().take_while(|&&m| m == mv).count();
            if !self.run_in_closed_form(st, mv, run, out, ctr) {
                for m in &moves[i..i + run] {
                    out.push(self.kernel(st, m, ctr));
                }
            }
            i += run;
        }
    }

    fn timing(&self) -> Timing {
        // Stage 1: the accumulator adders (the accumulators are the stage register);
        // stage 2: edge sign test, output rounding/saturation, output register.
        Timing { latency: 2, ii: 1 }
    }

    fn cost(&self) -> Cost {
        let c = self.cfg.coord_int_bits;
        let s = self.cfg.subpixel_bits;
        let k = self.cfg.attrs;
        let ew = self.edge_bits();
        let aw = self.cfg.acc_int_bits + self.cfg.acc_frac_bits;
        let ow = self.cfg.out_int_bits + self.cfg.out_frac_bits;
        let attr_w = self.cfg.attr_fmt.width();
        // One incremental accumulator of width w: adder, accumulator register, the dx and
        // dy increment registers, the dx/dy step mux, XOR for −dx, hold (enable) mux.
        let accumulator = |w: u32| {
            prim::adder(w)
                + prim::register(w)
                + prim::register(2 * w)
                + prim::mux(w)
                + Cells {
                    xor2: w as f64,
                    ..Cells::default()
                }
                + prim::mux(w)
        };
        // Output rounding of one attribute: add half over the kept bits, then clamp: an
        // all-ones/all-zeros detector over the dropped integer bits and a clamp mux.
        let kept = self.cfg.acc_int_bits + self.cfg.acc_frac_bits.min(self.cfg.out_frac_bits) + 1;
        let excess = self.cfg.acc_int_bits.saturating_sub(self.cfg.out_int_bits) + 1;
        let round_sat = prim::adder(kept)
            + Cells {
                or2: 2.0 * excess as f64,
                ..Cells::default()
            }
            + prim::mux(ow);

        // Setup engine (per primitive), sequenced: D = c+s+1 delta bits.
        let d = c + s + 1;
        let area_w = 2 * d + 1;
        let ad = attr_w + 1;
        let nw = ad + d + 1;
        let fa = self.cfg.attr_fmt.frac_bits;
        let facc = self.cfg.acc_frac_bits;
        let divisor_w = area_w + 1 + fa.saturating_sub(facc);
        let qw = aw + 2;
        let start_w = nw + d + 1 + 2; // Nx·Δx (1 b wider than A0·2area) and 2 adds' carries

        Cost::default()
            .part(
                "pixel counters x, y (±1)",
                (prim::adder(c) + prim::register(c)) * 2.0,
            )
            .part(
                &format!("{EDGES} edge accumulators ({ew} b)"),
                accumulator(ew) * EDGES as f64,
            )
            .part(
                &format!("{k} attribute accumulators ({aw} b)"),
                accumulator(aw) * k as f64,
            )
            .part(
                "move decode + inside (edge sign bits)",
                Cells {
                    and2: 4.0 + (EDGES - 1) as f64,
                    not: 4.0,
                    ..Cells::default()
                },
            )
            .part("output rounding + saturation", round_sat * k as f64)
            .part("output register", prim::register(2 * c + 1 + k * ow))
            .part(
                "setup: vertex deltas (8 × D-bit subtractors)",
                prim::subtractor(d) * 8.0,
            )
            .part(
                "setup: area (2 multipliers D×D, subtractor)",
                prim::multiplier(d, d) * 2.0 + prim::subtractor(area_w),
            )
            .part(
                "setup: edge start values (2 multipliers D×(D+1), subtractor; 1 edge/clock)",
                prim::multiplier(d, d + 1) * 2.0 + prim::subtractor(2 * d + 2),
            )
            .part(
                "setup: plane numerators (2 multipliers (attr+1)×D, subtractor)",
                prim::multiplier(ad, d) * 2.0 + prim::subtractor(nw),
            )
            .part(
                "setup: start numerator (A0×2area, Nx×Δx, Ny×Δy, 2 adders)",
                prim::multiplier(attr_w, area_w + 1)
                    + prim::multiplier(nw, d + 1) * 2.0
                    + prim::adder(start_w) * 2.0,
            )
            .part(
                &format!("setup: rounding divider ({divisor_w}-b divisor, {qw} quotient bits)"),
                prim::divider(divisor_w + 1, qw) + prim::adder(divisor_w + 1),
            )
            .part(
                "setup: operand registers (area, Nx, Ny, start numerator)",
                prim::register(area_w + 2 * nw + start_w),
            )
            .part(
                "barycentric weights: 2 dividers (edge/area, w + 1 quotient bits), per attribute 2 multipliers (w+1)×(attr+1), 2 adders, base and delta registers",
                match self.cfg.barycentric {
                    None => Cells::default(),
                    Some(b) => {
                        let w = b.weight_bits;
                        let wide = attr_w + w + 3;
                        prim::divider(ew + 1, w + 1) * 2.0
                            + (prim::multiplier(w + 1, ad) * 2.0
                                + prim::adder(wide) * 2.0
                                + prim::register(attr_w + 2 * ad))
                                * k as f64
                    }
                },
            )
    }

    fn widths(&self) -> Vec<Width> {
        let w = |name, bits| Width { name, bits };
        vec![
            w("attrs", self.cfg.attrs),
            w("subpixel_bits", self.cfg.subpixel_bits),
            w("coord_int_bits", self.cfg.coord_int_bits),
            w("attr_bits", self.cfg.attr_fmt.width()),
            w("attr_frac_bits", self.cfg.attr_fmt.frac_bits),
            w("acc_int_bits", self.cfg.acc_int_bits),
            w("acc_frac_bits", self.cfg.acc_frac_bits),
            w("edge_bits", self.edge_bits()),
            w("out_int_bits", self.cfg.out_int_bits),
            w("out_frac_bits", self.cfg.out_frac_bits),
        ]
    }

    fn in_signals(&self, mv: &Move) -> Vec<Signal> {
        vec![Signal::new("move", 2, mv.code())]
    }

    fn out_signals(&self, o: &PolyOut) -> Vec<Signal> {
        let c = self.cfg.coord_int_bits;
        let ow = self.cfg.out_int_bits + self.cfg.out_frac_bits;
        let m = |v: i64, w: u32| (v as u64) & (u64::MAX >> (64 - w));
        let mut v = vec![
            Signal::new("x", c, m(o.x, c)),
            Signal::new("y", c, m(o.y, c)),
            Signal::new("inside", 1, u64::from(o.inside)),
        ];
        let k = self.cfg.attrs as usize;
        for (name, &a) in ATTR_SIGNALS.iter().zip(&o.attrs).take(k) {
            v.push(Signal::new(name, ow, m(a, ow)));
        }
        v
    }
}
