//! clipper — near/far and guard-band clipping of a triangle in homogeneous clip space,
//! then the perspective divide and viewport transform into the polygon interpolator's
//! screen format.
//!
//! **Input** (one word per triangle): three vertices in clip space (x, y, z, w), each a
//! signed fixed-point word `s(clip_int_bits).(clip_frac_bits)`, and `attrs` attributes
//! in `s(attr_int_bits).(attr_frac_bits)`. Clip space is GL's: a point is in the view
//! volume when −w ≤ x, y, z ≤ w.
//!
//! **Planes.** Every vertex gets six signed distances, all exact integers of the raw
//! clip words (no rounding): near `z + w`, far `w − z`, and the guard band's four
//! edges, written in doubled screen units so the viewport transform needs no halving:
//! with `X = (x + w)·W` and `Y = (w − y)·H` (W × H the viewport, so the screen position
//! is (X/2w, Y/2w)), left `X − 2·g₀·w`, right `2·g₁·w − X`, top `Y − 2·g₀·w`, bottom
//! `2·g₁·w − Y` (g₀ ..= g₁ the guard band, `guard_min` ..= `guard_max` pixels). A
//! vertex is inside a plane when its distance is ≥ 0.
//!
//! **Trivial accept / reject.** A triangle inside every plane passes untouched (only
//! divided). A triangle whose three vertices are all outside one plane — or all
//! outside one edge of the viewport itself (X < 0, X > 2W·w, Y < 0, Y > 2H·w) — is
//! culled: it could not cover a pixel.
//!
//! **Clipping** (Sutherland–Hodgman, one plane per stage, near first): an edge from an
//! inside vertex I to an outside vertex O is cut at t = d_I / (d_I − d_O) ∈ [0, 1], a
//! rounding division to `t_frac_bits` fraction bits, always taken from the inside
//! vertex so both polygons sharing the edge cut it at the same point. The new vertex's
//! x, y, z, w are I + t·(O − I), each rounded to the clip format. Its attributes are
//! interpolated linearly in homogeneous space: at the near plane at t itself (the
//! point's own attribute along the edge, as a vertex behind the eye has no screen
//! position to interpolate from); at the far and guard-band planes (both ends have
//! w > 0) at the screen-space parameter s = t·w_O / w_new, so the attribute is the one
//! the interpolator's screen-linear walk of the unclipped triangle has at that point
//! and a clipped triangle draws the same pixels with the same attributes as the
//! unclipped one would (`attr_lerp = "screen"`; `"homogeneous"` uses t everywhere).
//! With `near_far = "near"` the far plane is not clipped (depth clamps downstream).
//!
//! **Output**: 0 vertices (culled), or a convex polygon of 3 ..= 9 vertices in the
//! interpolator's screen format `s(screen_int_bits).(subpixel_bits)`: x = X/2w, y =
//! Y/2w and the window depth (z/w + 1)/2 = (z + w)/2w in the attribute format, each
//! one rounding division (round half up); the attributes unchanged or interpolated.
//! A result outside its format saturates, counted in `saturations` (the guard band is
//! inside the screen range, so only a vertex rounded across its edge can); a clip word
//! that overflows its format in the lerp saturates, counted too.
//!
//! **Timing.** Sequenced: one distance unit (a vertex a clock), one cut engine, one
//! output divider (a division a clock). A triangle that passes untouched takes
//! 3 vertices × (x, y, depth) = 9 divisions: II = 9; latency = 1 (distances) + 1
//! (outcodes) + the divider's depth + 1 (output register). A clipped triangle holds
//! the stream for more: each cutting plane visits every vertex once, each cut edge
//! spends [`Clipper::cut_cycles`] in the cut engine, and every output vertex beyond 3
//! three more divisions. The kernel adds those clocks to `cycles` and `stalls` (the
//! next triangle waits), so all three drivers count them alike.
//!
//! **Counters** beyond the common ones are the unit's state, [`ClipStats`]: polygons
//! in, out (drawn), clipped, culled, and vertices generated.

use crate::cost::{prim, Cost};
use crate::counters::Counters;
use crate::error::{check_range, ConfigError};
use crate::unit::{Signal, Timing, Unit, Width};
use serde::{Deserialize, Serialize};

pub use super::polygon_interpolator::MAX_ATTRS;

const NAME: &str = "clipper";
/// Planes clipped against: near, far, left, right, top, bottom.
pub const PLANES: usize = 6;
/// Most vertices a clipped triangle can have: 3 + one per plane.
pub const MAX_CLIP_VERTS: usize = 3 + PLANES;
/// Plane names, in clipping order (for the datasheet and traces).
pub const PLANE_NAMES: [&str; PLANES] = ["near", "far", "left", "right", "top", "bottom"];

/// Which depth planes are clipped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NearFar {
    /// Near and far (GL).
    Both,
    /// Near only; geometry beyond the far plane passes (its depth clamps later).
    Near,
}

/// Where a cut vertex's attributes are interpolated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AttrLerp {
    /// Near plane at t, the others at the screen parameter s = t·w_O/w_new: what the
    /// screen-linear walk of the unclipped triangle has there.
    Screen,
    /// Every plane at t (perspective-correct at the cut point).
    Homogeneous,
}

/// The config as plain data, turned into a validated unit by [`Self::build`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ClipperConfig {
    /// Attributes carried per vertex, 0 ..= 16.
    pub attrs: u32,
    /// Integer bits of the clip-space coordinates, including the sign, 2 ..= 32.
    pub clip_int_bits: u32,
    /// Fraction bits of the clip-space coordinates, 0 ..= 24.
    pub clip_frac_bits: u32,
    /// Integer bits of the attributes (signed, including the sign), 1 ..= 24.
    pub attr_int_bits: u32,
    /// Fraction bits of the attributes, 0 ..= 24.
    pub attr_frac_bits: u32,
    /// Fraction bits of the cut parameters t and s, 4 ..= 30.
    pub t_frac_bits: u32,
    /// Integer bits of the output screen position, including the sign, 2 ..= 14 (the
    /// interpolator's `coord_int_bits`).
    pub screen_int_bits: u32,
    /// Sub-pixel bits of the output screen position, 0 ..= 8 (the interpolator's).
    pub subpixel_bits: u32,
    /// Viewport width W, pixels, 1 ..= guard_max.
    pub viewport_width: u32,
    /// Viewport height H, pixels, 1 ..= guard_max.
    pub viewport_height: u32,
    /// Guard band's lowest x and y, whole pixels, ≥ the screen format's minimum, ≤ 0.
    pub guard_min: i32,
    /// Guard band's highest x and y, whole pixels, ≥ the viewport, ≤ the screen
    /// format's largest whole pixel.
    pub guard_max: i32,
    /// Which depth planes are clipped.
    pub near_far: NearFar,
    /// Where a cut vertex's attributes are interpolated.
    pub attr_lerp: AttrLerp,
}

impl Default for ClipperConfig {
    /// 8 attributes in s16.16 (the shafts pipeline's), s24.16 clip coordinates, the
    /// interpolator's s13.4 screen, a 720 × 480 viewport, the guard band the screen
    /// range's whole pixels less one on the negative side (−4095 ..= 4095: a cut vertex
    /// rounded across its edge stays inside the format), near and far clipped.
    fn default() -> Self {
        ClipperConfig {
            attrs: 8,
            clip_int_bits: 24,
            clip_frac_bits: 16,
            attr_int_bits: 16,
            attr_frac_bits: 16,
            t_frac_bits: 20,
            screen_int_bits: 13,
            subpixel_bits: 4,
            viewport_width: 720,
            viewport_height: 480,
            guard_min: -4095,
            guard_max: 4095,
            near_far: NearFar::Both,
            attr_lerp: AttrLerp::Screen,
        }
    }
}

impl ClipperConfig {
    /// Validate; errors name the field as `clipper.<field>`.
    pub fn build(self) -> Result<Clipper, ConfigError> {
        let f = |s: &str| format!("{NAME}.{s}");
        check_range(&f("attrs"), self.attrs as u64, 0, MAX_ATTRS as u64)?;
        check_range(&f("clip_int_bits"), self.clip_int_bits as u64, 2, 32)?;
        check_range(&f("clip_frac_bits"), self.clip_frac_bits as u64, 0, 24)?;
        check_range(&f("attr_int_bits"), self.attr_int_bits as u64, 1, 24)?;
        check_range(&f("attr_frac_bits"), self.attr_frac_bits as u64, 0, 24)?;
        check_range(&f("t_frac_bits"), self.t_frac_bits as u64, 4, 30)?;
        check_range(&f("screen_int_bits"), self.screen_int_bits as u64, 2, 14)?;
        check_range(&f("subpixel_bits"), self.subpixel_bits as u64, 0, 8)?;
        let smax = (1i64 << (self.screen_int_bits - 1)) - 1;
        let smin = -(1i64 << (self.screen_int_bits - 1));
        if (self.guard_max as i64) > smax || (self.guard_max as i64) < 1 {
            return Err(ConfigError::out_of_range(
                &f("guard_max"),
                self.guard_max as f64,
                1.0,
                smax as f64,
            ));
        }
        if (self.guard_min as i64) < smin || self.guard_min > 0 {
            return Err(ConfigError::out_of_range(
                &f("guard_min"),
                self.guard_min as f64,
                smin as f64,
                0.0,
            ));
        }
        check_range(
            &f("viewport_width"),
            self.viewport_width as u64,
            1,
            self.guard_max as u64,
        )?;
        check_range(
            &f("viewport_height"),
            self.viewport_height as u64,
            1,
            self.guard_max as u64,
        )?;
        Ok(Clipper { cfg: self })
    }
}

/// One clip-space vertex (raw words).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClipVertex {
    /// Clip-space x, a raw s(clip_int_bits).(clip_frac_bits) code.
    pub x: i64,
    /// Clip-space y, a raw s(clip_int_bits).(clip_frac_bits) code.
    pub y: i64,
    /// Clip-space z, a raw s(clip_int_bits).(clip_frac_bits) code.
    pub z: i64,
    /// Clip-space w, a raw s(clip_int_bits).(clip_frac_bits) code.
    pub w: i64,
    /// Attributes, raw s(attr_int_bits).(attr_frac_bits) codes; the first `attrs` are used.
    pub attrs: [i64; MAX_ATTRS],
}

/// One input word: a triangle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClipIn {
    /// The triangle's three vertices.
    pub v: [ClipVertex; 3],
}

/// One output vertex: screen position (interpolator format), window depth and
/// attributes (attribute format).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ScreenVertex {
    /// Screen x = X/2w, a raw s(screen_int_bits).(subpixel_bits) code.
    pub x: i64,
    /// Screen y = Y/2w, a raw s(screen_int_bits).(subpixel_bits) code.
    pub y: i64,
    /// Window depth (z + w)/2w, a raw code in the attribute format.
    pub depth: i64,
    /// Attributes in the attribute format, unchanged or interpolated at a cut; the first
    /// `attrs` are used.
    pub attrs: [i64; MAX_ATTRS],
}

/// One output word: the clipped polygon (`n` = 0 when culled).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClipOut {
    /// Vertices of the polygon, 0 (culled) or 3 ..= 9.
    pub n: u32,
    /// Whether a plane cut it (false: untouched or culled).
    pub clipped: bool,
    /// The polygon's vertices; only the first `n` are meaningful (see
    /// [`ClipOut::vertices`]).
    pub v: [ScreenVertex; MAX_CLIP_VERTS],
}

impl ClipOut {
    /// The polygon's `n` vertices, in order around the polygon.
    pub fn vertices(&self) -> &[ScreenVertex] {
        &self.v[..self.n as usize]
    }
}

/// The clipper's own counters (its state: summed over a stream).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct ClipStats {
    /// Triangles received.
    pub polygons_in: u64,
    /// Polygons handed on (not culled).
    pub polygons_out: u64,
    /// Polygons a plane cut.
    pub polygons_clipped: u64,
    /// Polygons culled (wholly outside, or nothing left after clipping).
    pub polygons_culled: u64,
    /// Vertices made by cutting edges.
    pub vertices_generated: u64,
}

impl std::ops::AddAssign for ClipStats {
    fn add_assign(&mut self, o: ClipStats) {
        self.polygons_in += o.polygons_in;
        self.polygons_out += o.polygons_out;
        self.polygons_clipped += o.polygons_clipped;
        self.polygons_culled += o.polygons_culled;
        self.vertices_generated += o.vertices_generated;
    }
}

/// A vertex inside the clip stages: clip words, attributes and its plane distances.
#[derive(Clone, Copy, Debug, Default)]
struct Work {
    c: [i64; 4],
    attrs: [i64; MAX_ATTRS],
}

/// The validated clipper.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Clipper {
    cfg: ClipperConfig,
}

/// Round-half-up integer division n / d (d > 0).
#[inline]
fn div_round(n: i128, d: i128) -> i128 {
    debug_assert!(d > 0);
    (2 * n + d).div_euclid(2 * d)
}

impl Clipper {
    /// The config the clipper was built from.
    pub fn config(&self) -> &ClipperConfig {
        &self.cfg
    }

    /// Default config ([`ClipperConfig::default`]).
    pub fn geforce() -> Self {
        ClipperConfig::default()
            .build()
            .expect("default clipper config")
    }

    /// Attributes carried per vertex, 0 ..= 16.
    pub fn attrs(&self) -> u32 {
        self.cfg.attrs
    }

    fn clip_width(&self) -> u32 {
        self.cfg.clip_int_bits + self.cfg.clip_frac_bits
    }

    fn attr_width(&self) -> u32 {
        self.cfg.attr_int_bits + self.cfg.attr_frac_bits
    }

    fn screen_width(&self) -> u32 {
        self.cfg.screen_int_bits + self.cfg.subpixel_bits
    }

    /// Width of a plane distance: a clip word times the viewport (12 bits at 4095) plus
    /// the guard term and a carry: clip width + screen_int_bits + 2.
    pub fn distance_bits(&self) -> u32 {
        self.clip_width() + self.cfg.screen_int_bits + 2
    }

    /// Quotient bits of the output divider (screen position and depth).
    fn out_quotient_bits(&self) -> u32 {
        self.screen_width().max(self.attr_width())
    }

    /// Pipeline depth of a divider giving `q` quotient bits, 4 rows a stage.
    fn div_stages(q: u32) -> u32 {
        q.div_ceil(4)
    }

    /// Clocks the shared cut engine spends on one edge: its t divider (t_frac_bits + 1
    /// quotient bits, 4 rows a clock), for `attr_lerp = "screen"` the s divider after
    /// it, then one multiply-add a clock over the 4 clip words and the attributes.
    pub fn cut_cycles(&self) -> u32 {
        let t = Self::div_stages(self.cfg.t_frac_bits + 1);
        let div = match self.cfg.attr_lerp {
            AttrLerp::Screen => 2 * t,
            AttrLerp::Homogeneous => t,
        };
        div + 4 + self.cfg.attrs
    }

    /// Output divisions a vertex needs (x, y, depth), one a clock.
    pub const DIVS_PER_VERTEX: u32 = 3;

    fn clip_range(&self) -> (i64, i64) {
        let w = self.clip_width();
        (-(1i64 << (w - 1)), (1i64 << (w - 1)) - 1)
    }

    fn attr_range(&self) -> (i64, i64) {
        let w = self.attr_width();
        (-(1i64 << (w - 1)), (1i64 << (w - 1)) - 1)
    }

    /// Clip-space value of a raw clip word.
    pub fn clip_lsb(&self) -> f64 {
        (-(self.cfg.clip_frac_bits as f64)).exp2()
    }

    /// Value of one attribute (and depth) LSB.
    pub fn attr_lsb(&self) -> f64 {
        (-(self.cfg.attr_frac_bits as f64)).exp2()
    }

    /// Value of one screen LSB, pixels.
    pub fn screen_lsb(&self) -> f64 {
        (-(self.cfg.subpixel_bits as f64)).exp2()
    }

    /// Quantise an f64 clip-space vertex and its attributes (round half to even),
    /// saturating out-of-range words (counted in `ctr.saturations`). A non-finite value
    /// is an error naming `clipper.vertices[index].<field>`.
    pub fn vertex_from_f64(
        &self,
        index: usize,
        clip: [f64; 4],
        attrs: &[f64],
        ctr: &mut Counters,
    ) -> Result<ClipVertex, ConfigError> {
        let q = |name: &str, v: f64, frac: u32, (lo, hi): (i64, i64), ctr: &mut Counters| {
            if !v.is_finite() {
                return Err(ConfigError::not_finite(
                    &format!("{NAME}.vertices[{index}].{name}"),
                    v,
                ));
            }
            let r = (v * (frac as f64).exp2()).round_ties_even();
            if r < lo as f64 || r > hi as f64 {
                ctr.saturations += 1;
            }
            Ok((r.clamp(lo as f64, hi as f64)) as i64)
        };
        let cf = self.cfg.clip_frac_bits;
        let cr = self.clip_range();
        let mut v = ClipVertex {
            x: q("x", clip[0], cf, cr, ctr)?,
            y: q("y", clip[1], cf, cr, ctr)?,
            z: q("z", clip[2], cf, cr, ctr)?,
            w: q("w", clip[3], cf, cr, ctr)?,
            attrs: [0; MAX_ATTRS],
        };
        let k = self.cfg.attrs as usize;
        for (j, &a) in attrs.iter().take(k).enumerate() {
            v.attrs[j] = q("attrs", a, self.cfg.attr_frac_bits, self.attr_range(), ctr)?;
        }
        Ok(v)
    }

    /// The six plane distances of clip words c = (x, y, z, w), exact (i128).
    fn distances(&self, c: &[i64; 4]) -> [i128; PLANES] {
        let [x, y, z, w] = c.map(|v| v as i128);
        let (vw, vh) = (
            self.cfg.viewport_width as i128,
            self.cfg.viewport_height as i128,
        );
        let (g0, g1) = (self.cfg.guard_min as i128, self.cfg.guard_max as i128);
        let sx = (x + w) * vw; // s(cw+1) × u(12) → s(cw+13): X = 2w·screen x
        let sy = (w - y) * vh; // Y = 2w·screen y
        [
            z + w,           // near
            w - z,           // far
            sx - 2 * g0 * w, // left
            2 * g1 * w - sx, // right
            sy - 2 * g0 * w, // top
            2 * g1 * w - sy, // bottom
        ]
    }

    /// Whether the vertex is outside one edge of the viewport (bits: left, right, top,
    /// bottom) — for the trivial reject of a triangle the guard band holds but the
    /// view does not see.
    fn view_outcode(&self, c: &[i64; 4]) -> u32 {
        let [x, y, _, w] = c.map(|v| v as i128);
        let (vw, vh) = (
            self.cfg.viewport_width as i128,
            self.cfg.viewport_height as i128,
        );
        let sx = (x + w) * vw;
        let sy = (w - y) * vh;
        u32::from(sx < 0)
            | u32::from(sx > 2 * vw * w) << 1
            | u32::from(sy < 0) << 2
            | u32::from(sy > 2 * vh * w) << 3
    }

    fn plane_active(&self, p: usize) -> bool {
        !(p == 1 && self.cfg.near_far == NearFar::Near)
    }

    /// Bit p set when the clip-space vertex c = (x, y, z, w) (raw words) is outside
    /// plane p ([`PLANE_NAMES`] order; the far bit never with `near_far = "near"`).
    pub fn outcode(&self, c: &[i64; 4]) -> u32 {
        let d = self.distances(c);
        (0..PLANES)
            .filter(|&p| self.plane_active(p) && d[p] < 0)
            .fold(0, |m, p| m | 1 << p)
    }

    /// The vertex cut on edge I → O at plane `p` (I inside, O outside).
    fn cut(&self, i: &Work, o: &Work, di: i128, d_o: i128, p: usize, ctr: &mut Counters) -> Work {
        let tf = self.cfg.t_frac_bits;
        let one = 1i128 << tf;
        // t = d_I / (d_I − d_O) ∈ [0, 1]: u(dist) << tf / u(dist+1) → u(tf+1).
        let t = div_round(di << tf, di - d_o).clamp(0, one);
        let (lo, hi) = self.clip_range();
        let mut c = [0i64; 4];
        for (k, ck) in c.iter_mut().enumerate() {
            // s(cw+1) × u(tf+1) → s(cw+tf+2), rounded back to the clip format.
            let delta = o.c[k] as i128 - i.c[k] as i128; // s(cw+1)
            let v = i.c[k] as i128 + div_round(delta * t, one);
            if v < lo as i128 || v > hi as i128 {
                ctr.saturations += 1;
            }
            *ck = v.clamp(lo as i128, hi as i128) as i64;
        }
        // The attributes' parameter: t at the near plane, else s = t·w_O/w_new.
        let a_t = if p == 0 || self.cfg.attr_lerp == AttrLerp::Homogeneous || c[3] <= 0 {
            t
        } else {
            // u(tf+1) × s(cw) / s(cw) → u(tf+1)
            div_round(t * o.c[3] as i128, c[3] as i128).clamp(0, one)
        };
        let mut attrs = [0i64; MAX_ATTRS];
        let (alo, ahi) = self.attr_range();
        for j in 0..self.cfg.attrs as usize {
            let delta = o.attrs[j] as i128 - i.attrs[j] as i128; // s(aw+1)
            let v = i.attrs[j] as i128 + div_round(delta * a_t, one); // s(aw+tf+2) → s(aw)
            attrs[j] = v.clamp(alo as i128, ahi as i128) as i64;
        }
        Work { c, attrs }
    }

    /// Divide and map a clip-space vertex to the screen (w > 0).
    fn screen_vertex(&self, v: &Work, ctr: &mut Counters) -> ScreenVertex {
        let [x, y, z, w] = v.c.map(|c| c as i128);
        let (vw, vh) = (
            self.cfg.viewport_width as i128,
            self.cfg.viewport_height as i128,
        );
        let sub = self.cfg.subpixel_bits;
        let sw = self.screen_width();
        let (smin, smax) = (-(1i128 << (sw - 1)), (1i128 << (sw - 1)) - 1);
        let (amin, amax) = self.attr_range();
        let mut sat = |v: i128, lo: i128, hi: i128| {
            if v < lo || v > hi {
                ctr.saturations += 1;
            }
            v.clamp(lo, hi) as i64
        };
        // X·2^sub / 2w: s(dist) << sub / s(cw) → s(screen).
        let sx = sat(div_round(((x + w) * vw) << sub, 2 * w), smin, smax);
        let sy = sat(div_round(((w - y) * vh) << sub, 2 * w), smin, smax);
        // (z + w)·2^af / 2w → the attribute format.
        let depth = sat(
            div_round((z + w) << self.cfg.attr_frac_bits, 2 * w),
            amin as i128,
            amax as i128,
        );
        ScreenVertex {
            x: sx,
            y: sy,
            depth,
            attrs: v.attrs,
        }
    }

    /// The whole datapath on one triangle; `stats` gathers the unit's counters and the
    /// returned clocks are those the triangle holds the stream beyond the pass-through.
    pub fn clip(
        &self,
        input: &ClipIn,
        stats: &mut ClipStats,
        ctr: &mut Counters,
    ) -> (ClipOut, u64) {
        stats.polygons_in += 1;
        let mut out = ClipOut::default();
        let codes = input.v.map(|v| self.outcode(&[v.x, v.y, v.z, v.w]));
        let views = input.v.map(|v| self.view_outcode(&[v.x, v.y, v.z, v.w]));
        let any_w_le0 = input.v.iter().any(|v| v.w <= 0);
        // Culled: all three outside one plane, or (all in front of the eye) outside one
        // edge of the view.
        if codes[0] & codes[1] & codes[2] != 0 || !any_w_le0 && views[0] & views[1] & views[2] != 0
        {
            stats.polygons_culled += 1;
            return (out, 0);
        }
        let mut poly = [Work::default(); MAX_CLIP_VERTS];
        let mut n = 3usize;
        for (k, v) in input.v.iter().enumerate() {
            poly[k] = Work {
                c: [v.x, v.y, v.z, v.w],
                attrs: v.attrs,
            };
        }
        let mut extra = 0u64;
        if codes[0] | codes[1] | codes[2] != 0 {
            out.clipped = true;
            stats.polygons_clipped += 1;
            let mut next = [Work::default(); MAX_CLIP_VERTS];
            for p in 0..PLANES {
                if !self.plane_active(p) || n == 0 {
                    continue;
                }
                let d: Vec<i128> = poly[..n].iter().map(|v| self.distances(&v.c)[p]).collect();
                if d.iter().all(|&x| x >= 0) {
                    continue;
                }
                let mut m = 0usize;
                let mut cuts = 0u64;
                for a in 0..n {
                    let b = (a + 1) % n;
                    let (ia, ib) = (d[a] >= 0, d[b] >= 0);
                    if ia {
                        if m < MAX_CLIP_VERTS {
                            next[m] = poly[a];
                        }
                        m += 1;
                    }
                    if ia != ib {
                        let cut = if ia {
                            self.cut(&poly[a], &poly[b], d[a], d[b], p, ctr)
                        } else {
                            self.cut(&poly[b], &poly[a], d[b], d[a], p, ctr)
                        };
                        if m < MAX_CLIP_VERTS {
                            next[m] = cut;
                        }
                        m += 1;
                        cuts += 1;
                        stats.vertices_generated += 1;
                    }
                }
                if m > MAX_CLIP_VERTS {
                    // A convex polygon gains at most one vertex a plane; only rounding
                    // could do otherwise. Counted, never silent.
                    ctr.overflows += 1;
                    m = MAX_CLIP_VERTS;
                }
                // The stage visits each vertex once and runs the engine per cut.
                extra += n as u64 + cuts * self.cut_cycles() as u64;
                poly = next;
                n = if m < 3 { 0 } else { m };
            }
        }
        if n < 3 || poly[..n].iter().any(|v| v.c[3] <= 0) {
            if n >= 3 {
                // Only a degenerate polygon keeps a w ≤ 0 vertex past the near plane.
                ctr.underflows += 1;
            }
            stats.polygons_culled += 1;
            return (out, extra);
        }
        for (k, v) in poly[..n].iter().enumerate() {
            out.v[k] = self.screen_vertex(v, ctr);
        }
        out.n = n as u32;
        stats.polygons_out += 1;
        extra += n.saturating_sub(3) as u64 * Self::DIVS_PER_VERTEX as u64;
        (out, extra)
    }
}

impl Unit for Clipper {
    type In = ClipIn;
    type Out = ClipOut;
    type State = ClipStats;

    fn name(&self) -> &'static str {
        NAME
    }

    /// One triangle; the clocks it holds the stream beyond the pass-through II go to
    /// `cycles` and `stalls`.
    fn kernel(&self, state: &mut ClipStats, input: &ClipIn, ctr: &mut Counters) -> ClipOut {
        let (out, extra) = self.clip(input, state, ctr);
        ctr.cycles += extra;
        ctr.stalls += extra;
        out
    }

    fn timing(&self) -> Timing {
        // Distances, outcodes, the output divider's rows, the output register; one
        // division a clock: 3 vertices × (x, y, depth).
        Timing {
            latency: 1 + 1 + Self::div_stages(self.out_quotient_bits()) + 1,
            ii: 3 * Self::DIVS_PER_VERTEX,
        }
    }

    fn cost(&self) -> Cost {
        let cw = self.clip_width();
        let aw = self.attr_width();
        let db = self.distance_bits();
        let si = self.cfg.screen_int_bits;
        let tf = self.cfg.t_frac_bits;
        let k = self.cfg.attrs;
        let vbits = 4 * cw + k * aw; // one vertex word
        let g = |v: i32| (2 * v.unsigned_abs()) as u64;
        // One vertex a clock: x + w, w − y, z + w, w − z; X = W·(x + w), Y = H·(w − y);
        // the guard terms 2g·w (constants of the config) and the view terms 2W·w, 2H·w;
        // 8 subtractions whose signs are the outcodes.
        let distance = prim::adder(cw + 1) * 4.0
            + prim::multiplier(cw + 1, si) * 2.0
            + prim::multiplier(cw, si + 1) * 2.0
            + prim::constant_multiplier(cw, g(self.cfg.guard_min))
            + prim::constant_multiplier(cw, g(self.cfg.guard_max))
            + prim::subtractor(db) * 8.0;
        let s_div = match self.cfg.attr_lerp {
            AttrLerp::Screen => prim::divider(cw + tf + 1, tf + 1),
            AttrLerp::Homogeneous => Default::default(),
        };
        let lerp_bits = cw.max(aw) + 1;
        let q = self.out_quotient_bits();
        Cost::default()
            .part("plane distances and outcodes", distance)
            .part(
                "cut engine: t divider, s divider, one multiply-add a clock",
                prim::divider(db, tf + 1)
                    + s_div
                    + prim::multiplier(lerp_bits, tf + 1)
                    + prim::adder(lerp_bits),
            )
            .part(
                "plane sequencer: vertex registers (previous, first, out) and muxes",
                prim::register(vbits + 2 * db) * 3.0 + prim::mux(vbits) * 2.0,
            )
            .part(
                "output divider (x, y, depth, one a clock)",
                prim::divider(db + self.cfg.subpixel_bits, q),
            )
            .part(
                "output register",
                prim::register(2 * self.screen_width() + aw * (k + 1)),
            )
            // Two polygon buffers (the stage's input and output), 9 vertices each.
            .with_ram_bits(2 * MAX_CLIP_VERTS as u64 * vbits as u64)
    }

    fn widths(&self) -> Vec<Width> {
        vec![
            Width {
                name: "attrs",
                bits: self.cfg.attrs,
            },
            Width {
                name: "clip_int_bits",
                bits: self.cfg.clip_int_bits,
            },
            Width {
                name: "clip_frac_bits",
                bits: self.cfg.clip_frac_bits,
            },
            Width {
                name: "attr_int_bits",
                bits: self.cfg.attr_int_bits,
            },
            Width {
                name: "attr_frac_bits",
                bits: self.cfg.attr_frac_bits,
            },
            Width {
                name: "t_frac_bits",
                bits: self.cfg.t_frac_bits,
            },
            Width {
                name: "screen_int_bits",
                bits: self.cfg.screen_int_bits,
            },
            Width {
                name: "subpixel_bits",
                bits: self.cfg.subpixel_bits,
            },
            Width {
                name: "distance_bits",
                bits: self.distance_bits(),
            },
        ]
    }

    fn in_signals(&self, i: &ClipIn) -> Vec<Signal> {
        const N: [[&str; 4]; 3] = [
            ["v0_x", "v0_y", "v0_z", "v0_w"],
            ["v1_x", "v1_y", "v1_z", "v1_w"],
            ["v2_x", "v2_y", "v2_z", "v2_w"],
        ];
        let cw = self.clip_width();
        let mask = |v: i64| (v as u64) & (u64::MAX >> (64 - cw));
        let mut s = Vec::new();
        for (k, v) in i.v.iter().enumerate() {
            for (j, c) in [v.x, v.y, v.z, v.w].into_iter().enumerate() {
                s.push(Signal::new(N[k][j], cw, mask(c)));
            }
        }
        s
    }

    fn out_signals(&self, o: &ClipOut) -> Vec<Signal> {
        const N: [[&str; 2]; MAX_CLIP_VERTS] = [
            ["o0_x", "o0_y"],
            ["o1_x", "o1_y"],
            ["o2_x", "o2_y"],
            ["o3_x", "o3_y"],
            ["o4_x", "o4_y"],
            ["o5_x", "o5_y"],
            ["o6_x", "o6_y"],
            ["o7_x", "o7_y"],
            ["o8_x", "o8_y"],
        ];
        let sw = self.screen_width();
        let mask = |v: i64| (v as u64) & (u64::MAX >> (64 - sw));
        let mut s = vec![
            Signal::new("n", 4, o.n as u64),
            Signal::new("clipped", 1, o.clipped as u64),
        ];
        for (k, v) in o.v.iter().enumerate() {
            s.push(Signal::new(N[k][0], sw, mask(v.x)));
            s.push(Signal::new(N[k][1], sw, mask(v.y)));
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64, w: f64) -> ClipVertex {
        let c = Clipper::geforce();
        c.vertex_from_f64(0, [x, y, z, w], &[], &mut Counters::default())
            .unwrap()
    }

    #[test]
    fn inside_passes_untouched_and_outside_is_culled() {
        let c = Clipper::geforce();
        let mut st = ClipStats::default();
        let mut ctr = Counters::default();
        let tri = ClipIn {
            v: [
                v(-0.5, -0.5, 0.0, 1.0),
                v(0.5, -0.5, 0.0, 1.0),
                v(0.0, 0.5, 0.0, 1.0),
            ],
        };
        let (o, extra) = c.clip(&tri, &mut st, &mut ctr);
        assert_eq!((o.n, o.clipped, extra), (3, false, 0));
        // x = 0.5·w → screen (0.5·0.5 + 0.5)·720 = 540 px.
        assert_eq!(o.v[1].x, 540 * 16);
        let behind = ClipIn {
            v: [
                v(0.0, 0.0, -2.0, 1.0),
                v(0.1, 0.0, -3.0, 1.0),
                v(0.0, 0.1, -2.5, 1.0),
            ],
        };
        let (o, _) = c.clip(&behind, &mut st, &mut ctr);
        assert_eq!(o.n, 0);
        assert_eq!(
            (st.polygons_in, st.polygons_out, st.polygons_culled),
            (2, 1, 1)
        );
    }

    #[test]
    fn a_triangle_past_the_guard_band_is_cut_inside_it() {
        let c = Clipper::geforce();
        let mut st = ClipStats::default();
        let mut ctr = Counters::default();
        // x/w = 20: screen x = 10.5·720 = 7560 px, beyond 4095.
        let tri = ClipIn {
            v: [
                v(0.0, 0.0, 0.0, 1.0),
                v(20.0, 0.0, 0.0, 1.0),
                v(0.0, 0.5, 0.0, 1.0),
            ],
        };
        let (o, extra) = c.clip(&tri, &mut st, &mut ctr);
        assert!(o.clipped && o.n == 4, "{o:?}");
        assert!(extra > 0);
        assert!(o
            .vertices()
            .iter()
            .all(|p| p.x <= 4095 * 16 && p.x >= -4096 * 16));
        assert_eq!(st.vertices_generated, 2);
        assert_eq!(ctr.saturations, 0);
    }
}
