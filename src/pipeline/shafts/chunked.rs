//! The shafts frame's per-fragment units chained a chunk at a time (DESIGN §2, the
//! batch path): a walk hands its fragments over in chunks of whole bounding-box rows, and the
//! depth test, the projective units, the light-map sampler and the shadow compare
//! each run their batch kernel on that chunk, in buffers reused from chunk to chunk.
//! No frame-sized list sits between two units.
//!
//! Counters stay those of the span driver: each unit keeps a [`UnitSpan`] for each
//! logical span it served before (the fragments of one sub-plane, of one plane), its
//! kernel counters summed chunk by chunk and its timing added once when the span
//! closes ((n − 1)·II + latency + 1 cycles are not a sum over chunks).

use super::units::{counters_add, Units};
use super::view::{CameraView, LightView};
use crate::pipeline::raster::{is_fragment_lane, RowBlank};
use rtl_model::driver::SpanTally;
use rtl_model::units::blend::{Blend, LanesAt};
use rtl_model::units::modulate::{Modulate, Operand};
use rtl_model::units::polygon_interpolator::{PolyLanes, PolySetup};
use rtl_model::units::projective_texcoord::{
    ProjLanes, ProjectiveIn, ProjectiveOut, ProjectiveTexcoord, SquareClass, SquareCut,
    SQUARE_BLOCK,
};
use rtl_model::units::shadow_compare::{ShadowCompare, ShadowIn, ShadowOut, ShadowState};
use rtl_model::units::texture_sampler::{TextureSampler, TextureSamplerIn};
use rtl_model::unorm::max_code;
use rtl_model::{Counters, Timing, Unit};
use std::collections::BTreeMap;
use std::ops::Range;

/// One unit's part of a logical span fed in chunks: the kernel's counters so far and
/// the inputs counted.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct UnitSpan {
    tally: SpanTally,
    ctr: Counters,
}

impl UnitSpan {
    /// Run `unit`'s batch kernel on `inputs` (outputs into `out`, cleared first).
    #[inline]
    pub fn feed<U: Unit>(
        &mut self,
        unit: &U,
        state: &mut U::State,
        inputs: &[U::In],
        out: &mut Vec<U::Out>,
    ) {
        out.clear();
        unit.kernel_batch(state, inputs, out, &mut self.ctr);
        self.tally.add(inputs.len());
    }

    /// Depth tests against a shared, read-only RAM (threads test one map at once).
    #[inline]
    pub fn feed_tests(
        &mut self,
        unit: &ShadowCompare,
        state: &ShadowState,
        inputs: &[ShadowIn],
        out: &mut Vec<ShadowOut>,
    ) {
        out.clear();
        if !unit.test_batch(state, inputs, out, &mut self.ctr) {
            // Not a plain test chunk: the kernel on a copy, as the span driver ran it.
            let mut s = state.clone();
            unit.kernel_batch(&mut s, inputs, out, &mut self.ctr);
        }
        self.tally.add(inputs.len());
    }

    /// The sampler's batch kernel where only the outputs with `keep` are used
    /// ([`TextureSampler::kernel_batch_keep`]): counted as the batch kernel on all.
    #[inline]
    pub fn feed_keep(
        &mut self,
        unit: &TextureSampler,
        inputs: &[TextureSamplerIn],
        keep: &[bool],
        out: &mut Vec<[u32; 4]>,
    ) {
        out.clear();
        unit.kernel_batch_keep(inputs, keep, out, &mut self.ctr);
        self.tally.add(inputs.len());
    }

    /// A one-channel 1D or 2D sampler on coordinate lanes `s` (and `t` for 2D):
    /// channel 0 of each output into `out` (cleared first), through
    /// [`TextureSampler::sample_lanes_keep`] (every sample kept), or else through the
    /// batch kernel on input words built in `ins` (outputs in `outs`). Counted as the
    /// batch kernel on those inputs either way.
    #[inline]
    pub fn feed_sampler_lanes(
        &mut self,
        unit: &TextureSampler,
        s: &[i32],
        t: &[i32],
        out: &mut Vec<u32>,
        ins: &mut Vec<TextureSamplerIn>,
        outs: &mut Vec<[u32; 4]>,
    ) {
        out.clear();
        out.resize(s.len(), 0);
        if unit.sample_lanes_keep(s, t, |_| true, out, &mut self.ctr) {
            self.tally.add(s.len());
            return;
        }
        ins.clear();
        ins.extend((0..s.len()).map(|i| TextureSamplerIn {
            coord: [s[i], t.get(i).copied().unwrap_or(0), 0],
        }));
        self.feed(unit, &mut (), ins, outs);
        out.clear();
        out.extend(outs.iter().map(|o| o[0]));
    }

    /// Modulates in lanes ([`Modulate::apply_lanes`]): lane i of `a` by lane i of `b`
    /// or by its one code, the products into `out` (cleared first). The modulate's
    /// batch kernel is its per-pair datapath and counts nothing (no saturation or
    /// wrap is possible), so this is the batch kernel without the input words.
    #[inline]
    pub fn feed_modulate(&mut self, unit: &Modulate, a: &[u32], b: Operand, out: &mut Vec<u32>) {
        unit.apply_lanes(a, b, out);
        self.tally.add(a.len());
    }

    /// A single-channel weighted blend in lanes, in place ([`Blend::blend_lanes_at`],
    /// prepared once by [`Blend::lanes_at`]): lane i blends `src[i]` over
    /// `dst[at[i] − offset]`, counted as the batch kernel counts those inputs.
    #[inline]
    pub fn feed_blend_lanes(
        &mut self,
        blend: &LanesAt,
        src: &[u32],
        at: (&[u32], usize),
        dst: &mut [u32],
    ) {
        blend.blend(src, at, dst, &mut self.ctr);
        self.tally.add(src.len());
    }

    /// `n` lanes of [`Self::feed_blend_lanes`] whose source is 0, counted without
    /// blending ([`Blend::count_zero_lanes`]: they leave their words as they are).
    #[inline]
    pub fn feed_blend_zero_lanes(&mut self, unit: &Blend, n: usize) {
        unit.count_zero_lanes(n as u64, &mut self.ctr);
        self.tally.add(n);
    }

    /// Unweighted pixel blends in place ([`Blend::blend_pixels_in_place`]), counted
    /// as the batch kernel counts those inputs. False with nothing done (the batch
    /// kernel on input words then runs).
    #[inline]
    pub fn feed_blend_in_place(
        &mut self,
        unit: &Blend,
        n: usize,
        frag: impl Fn(usize) -> (usize, [u32; 4]),
        pixels: &mut [[u32; 4]],
    ) -> bool {
        if !unit.blend_pixels_in_place(n, frag, pixels, &mut self.ctr) {
            return false;
        }
        self.tally.add(n);
        true
    }

    /// The same span continued elsewhere (a part done on another thread).
    pub fn merge(&mut self, other: &UnitSpan) {
        self.ctr += other.ctr;
        self.tally.add(other.tally.len() as usize);
    }

    /// End the span: its counters, timing included, added under `name`.
    pub fn close(self, name: &str, t: Timing, map: &mut BTreeMap<String, Counters>) {
        let mut c = self.ctr;
        self.tally.close(t, &mut c);
        counters_add(map, name, c);
    }
}

/// The spans of H·I_l's units over one batch of fragments (one span each, as the
/// span driver ran them over the whole batch).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct HilSpans {
    proj: UnitSpan,
    light_map: UnitSpan,
    proj_depth: UnitSpan,
    shadow: UnitSpan,
}

impl HilSpans {
    pub fn merge(&mut self, o: &HilSpans) {
        self.proj.merge(&o.proj);
        self.light_map.merge(&o.light_map);
        self.proj_depth.merge(&o.proj_depth);
        self.shadow.merge(&o.shadow);
    }

    /// Close the spans of the units this light uses, under their counter names.
    pub fn close(self, ctx: &LightCtx, map: &mut BTreeMap<String, Counters>) {
        let u = ctx.units;
        if ctx.lm_tex.is_some() || ctx.sstate.is_some() {
            self.proj.close("projective_texcoord", u.proj.timing(), map);
        }
        if let Some(lm) = ctx.lm_tex {
            self.light_map
                .close("texture_sampler (light map)", lm.timing(), map);
        }
        if let (Some(sh), Some(_)) = (&u.shadow, ctx.sstate) {
            self.proj_depth
                .close("projective_texcoord (depth)", u.proj_depth.timing(), map);
            self.shadow
                .close("shadow_compare (shadow map)", sh.timing(), map);
        }
    }
}

/// Buffers of one thread's chunks, reused from chunk to chunk.
#[derive(Clone, Debug, Default)]
pub(super) struct ChunkBuffers {
    /// Whether the last [`LightCtx::h_il`] took the light-map and shadow-map pair
    /// path (its coordinates are then in `tex_s`, `tex_t` and `proj_lanes`, else in
    /// `tex_in` and `shadow_in`).
    pub(super) pair_path: bool,
    /// Whether [`LightCtx::h_il`] may give a fragment outside the light's square
    /// codes of the same classes instead of its exact ones
    /// ([`ProjectiveTexcoord::kernel_pair_lanes_in_square`]): set by a pass that
    /// records no footprint of these buffers' lookups (the timing's texel traces
    /// read every lookup's address).
    pub(super) cut_outside_square: bool,
    /// Indices (into the chunk's walked pixels) of the fragments that passed the
    /// depth test, in walk order.
    pub visible: Vec<u32>,
    /// H·I_l of each visible fragment (texel_bits unorm).
    pub hil: Vec<u32>,
    depth_in: Vec<ShadowIn>,
    depth_out: Vec<ShadowOut>,
    proj_in: Vec<ProjectiveIn>,
    proj_out: Vec<ProjectiveOut>,
    pdepth_in: Vec<ProjectiveIn>,
    pdepth_out: Vec<ProjectiveOut>,
    pub(super) tex_in: Vec<TextureSamplerIn>,
    /// Whether each light-map sample is used (in front of the light, inside its square).
    tex_keep: Vec<bool>,
    /// The light-map samples' texel-space coordinate words in lanes, and whether the
    /// shadow map lights each fragment ([`LightCtx::h_il`]'s lane form).
    pub(super) tex_s: Vec<i32>,
    pub(super) tex_t: Vec<i32>,
    lit: Vec<bool>,
    tex_out: Vec<[u32; 4]>,
    /// The light-map projective unit's outputs in lanes, and the depth unit's u
    /// ([`LightCtx::h_il`]'s shared front end).
    pub(super) proj_lanes: ProjLanes,
    pdepth_u: Vec<i32>,
    /// The H·I_l of the fragments of the blocks the square form did not decide
    /// ([`LightCtx::pair_in_square`]).
    hil_undecided: Vec<u32>,
    /// The shadow map's texel x, y and depth word of each fragment, in lanes.
    shadow_x: Vec<i32>,
    shadow_y: Vec<i32>,
    shadow_depth: Vec<u64>,
    pub(super) shadow_in: Vec<ShadowIn>,
    shadow_out: Vec<ShadowOut>,
}

/// A chunk's blank stretch ([`ChunkCut::row`]): its words, and their class.
pub(super) type RowStretch = (Range<usize>, SquareClass);

/// [`LightCtx::chunk_cut`]: the square cut of a light's pair path, the attribute
/// index of s, and the light map and shadow map it counts.
pub(super) struct ChunkCut<'a> {
    cut: SquareCut,
    base: usize,
    lm: &'a TextureSampler,
    sh: &'a ShadowCompare,
}

impl ChunkCut<'_> {
    /// Bounding-box row `row` of primitive `setup` as the square cut sees it: Some(the
    /// class of every fragment) where its s, t, r and q codes decide them alike
    /// ([`SquareCut::range`] of the codes' least and greatest over the row); else
    /// the row's longest first and last stretches of pixels each decided alike, with
    /// their classes. Nothing where the row's codes are not certain in closed form
    /// ([`AttrRow`]). Along a row each code rises or falls, so a stretch's codes lie
    /// between its ends' and a shorter stretch from the same end is decided where a
    /// longer one is: each stretch's end is searched from `ends` (the last row's,
    /// which moves little from row to row; updated), doubling the step until it
    /// passes the end, then by bisection. The last stretch starts after the first.
    ///
    /// [`AttrRow`]: rtl_model::units::polygon_interpolator::AttrRow
    pub fn row(
        &self,
        u: &Units,
        setup: &PolySetup,
        row: u64,
        ends: &mut [Option<i64>; 2],
    ) -> (Option<SquareClass>, [Option<RowBlank<SquareClass>>; 2]) {
        let none = (None, [None, None]);
        let Some(b) = setup.bbox else {
            return none;
        };
        let y = b.y0 + row as i64;
        let line = |a: usize| u.interp.attr_row(setup, self.base + a, b.x0..=b.x1, y);
        let (Some(s), Some(t), Some(r), Some(q)) = (line(0), line(1), line(2), line(3)) else {
            return none;
        };
        let lines = [s, t, r, q];
        let w = u.proj.in_bits();
        if let Some(class) = self.cut.range(lines.map(|l| l.range()), w) {
            return (Some(class), [None, None]);
        }
        let stretch_from = |from: i64, to: i64, end: &mut Option<i64>| {
            let at_from = lines.map(|l| l.code(from));
            // The class of the stretch from `from` to x.
            let class = |x: i64| {
                let mut ranges = [(0, 0); 4];
                for ((range, l), &c) in ranges.iter_mut().zip(&lines).zip(&at_from) {
                    let d = l.code(x);
                    *range = (c.min(d), c.max(d));
                }
                self.cut.range(ranges, w)
            };
            let found = longest_stretch(from, to, *end, class);
            *end = found.map(|(x, _)| x);
            found.map(|(x, c)| (from.min(x)..=from.max(x), c))
        };
        let first = stretch_from(b.x0, b.x1, &mut ends[0]);
        let last = stretch_from(b.x1, b.x0, &mut ends[1]);
        let after = first.as_ref().map_or(b.x0, |(xs, _)| *xs.end() + 1);
        let last = last
            .map(|(xs, c)| ((*xs.start()).max(after)..=b.x1, c))
            .filter(|(xs, _)| !xs.is_empty());
        (None, [first, last])
    }
}

/// The farthest x from `from` towards `to` (`to` itself not taken) where
/// `class(x)`, the class of the stretch from `from` to x, is Some, and that class;
/// None where the stretch of `from` alone is not. `class` must be Some on a stretch
/// wherever it is on a longer one from the same end. Searched from `guess`
/// (clamped to the stretch): outwards with a doubling step to the first x past the
/// end, then by bisection.
fn longest_stretch<C>(
    from: i64,
    to: i64,
    guess: Option<i64>,
    class: impl Fn(i64) -> Option<C>,
) -> Option<(i64, C)> {
    let dir = (to - from).signum();
    // Steps from `from` towards `to`, and back to x.
    let steps = |x: i64| (x - from) * dir;
    let (span, at) = (steps(to), |k: i64| from + k * dir);
    if span <= 0 {
        return class(from).map(|c| (from, c));
    }
    let g = guess.map_or(0, |g| steps(g).clamp(0, span - 1));
    // good: a step whose stretch is decided (with its class); bad: one whose is not,
    // or `span`.
    let (mut good, mut bad);
    if let Some(c) = class(at(g)) {
        (good, bad) = ((g, c), span);
        let mut step = 1;
        while good.0 + step < span {
            match class(at(good.0 + step)) {
                Some(c) => (good, step) = ((good.0 + step, c), step * 2),
                None => {
                    bad = good.0 + step;
                    break;
                }
            }
        }
    } else {
        bad = g;
        let mut step = 1;
        loop {
            if bad == 0 {
                return None;
            }
            let k = (bad - step).max(0);
            match class(at(k)) {
                Some(c) => {
                    good = (k, c);
                    break;
                }
                None => (bad, step) = (k, step * 2),
            }
        }
    }
    while bad - good.0 > 1 {
        let mid = good.0 + (bad - good.0) / 2;
        match class(at(mid)) {
            Some(c) => good = (mid, c),
            None => bad = mid,
        }
    }
    Some((at(good.0), good.1))
}

/// The camera depth buffer's words unpacked ([`ShadowCompare::words`]) for the
/// planes' depth tests in lanes, and each row's least and greatest word
/// ([`ShadowCompare::row_ranges`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct DepthWords<'a> {
    pub words: &'a [u32],
    pub rows: &'a [(u32, u32)],
}

/// What a light's passes read: the frame's units and depth buffer, the light's view,
/// light map and shadow map.
pub(super) struct LightCtx<'a> {
    pub li: usize,
    pub units: &'a Units,
    pub cam: &'a CameraView,
    pub lv: &'a LightView,
    pub lm_tex: Option<&'a TextureSampler>,
    pub sstate: Option<&'a ShadowState>,
    pub zstate: Option<&'a ShadowState>,
    /// The shadow map's words unpacked ([`ShadowCompare::words`] of `sstate`), when
    /// the pass has them: its tests then run in lanes.
    pub swords: Option<&'a [u32]>,
    pub light: &'a crate::scene::format::Light,
    pub tex_max: u32,
}

/// Scale of the light's projective coordinates in the s16.16 attributes (keeps q
/// within range for lights up to ~1000 units away while keeping fraction bits).
const LIGHT_COORD_SCALE: f64 = 16.0;

impl LightCtx<'_> {
    /// (s, t, r, q) attributes of a world point.
    pub fn light_attrs(&self, p: crate::scene::math::Vec3) -> [f64; 4] {
        self.lv.strq(p).map(|v| v * LIGHT_COORD_SCALE)
    }

    /// The chunk's fragments (walked pixels that are covered and inside the
    /// `width` × `height` viewport) that pass the depth test (at window depth words,
    /// `depth(px, i)` of word i) against the camera depth buffer, as indices into
    /// `px`, into `b.visible`; all of them without objects.
    pub fn visible(
        &self,
        px: &PolyLanes,
        viewport: (u32, u32),
        depth: impl Fn(&PolyLanes, usize) -> u32,
        span: &mut UnitSpan,
        b: &mut ChunkBuffers,
    ) {
        self.visible_words(px, viewport, depth, None, span, b);
    }

    /// [`Self::visible_words`] at one depth word `zword` for every pixel (a plane
    /// parallel to the screen): with the unpacked words, the test in lanes straight
    /// from the chunk's slices, a chunk whose rows give every depth word one outcome
    /// decided at once ([`ShadowCompare::test_filter_flat_rows`]: the same kept
    /// fragments and counters), else [`Self::visible_words`].
    pub fn visible_flat(
        &self,
        px: &PolyLanes,
        viewport: (u32, u32),
        zword: u32,
        zwords: Option<DepthWords>,
        span: &mut UnitSpan,
        b: &mut ChunkBuffers,
    ) {
        if let (Some(z), Some(_), Some(dw)) = (&self.units.zbuf, self.zstate, zwords) {
            b.visible.clear();
            let lanes = (&px.x[..], &px.y[..], &px.inside[..]);
            if let Some(n) = z.test_filter_flat_rows(
                (dw.words, dw.rows),
                lanes,
                viewport,
                zword as u64,
                &mut b.visible,
                &mut span.ctr,
            ) {
                span.tally.add(n);
                return;
            }
        }
        let words = zwords.map(|dw| dw.words);
        self.visible_words(px, viewport, |_, _| zword, words, span, b);
    }

    /// [`Self::visible`] reading the depth buffer's words unpacked by
    /// [`ShadowCompare::words`] when given (`zwords`, of this light's `zstate`).
    pub fn visible_words(
        &self,
        px: &PolyLanes,
        (width, height): (u32, u32),
        depth: impl Fn(&PolyLanes, usize) -> u32,
        zwords: Option<&[u32]>,
        span: &mut UnitSpan,
        b: &mut ChunkBuffers,
    ) {
        b.visible.clear();
        let frags =
            (0..px.len() as u32).filter(|&i| is_fragment_lane(px, i as usize, width, height));
        let (Some(z), Some(zs)) = (&self.units.zbuf, self.zstate) else {
            b.visible.extend(frags);
            return;
        };
        // On the unpacked words: every walked pixel tested in one pass without a
        // branch, the lit fragments kept.
        if let Some(words) = zwords {
            let cand = |i: usize| {
                let frag = is_fragment_lane(px, i, width, height);
                (frag, px.x[i] as i32, px.y[i] as i32, depth(px, i) as u64)
            };
            if let Some(n) =
                z.test_filter_lanes(words, px.len(), cand, &mut b.visible, &mut span.ctr)
            {
                span.tally.add(n);
                return;
            }
        }
        // The fragments tested as they are found, the lit ones kept (the test batch's
        // outputs and counters without its input and output words).
        let tests = frags.map(|i| {
            let j = i as usize;
            (i, px.x[j] as i32, px.y[j] as i32, depth(px, j) as u64)
        });
        let tested = match zwords {
            Some(words) => z.test_filter_words(words, tests, &mut b.visible, &mut span.ctr),
            None => z.test_filter(zs, tests, &mut b.visible, &mut span.ctr),
        };
        if let Some(n) = tested {
            span.tally.add(n);
            return;
        }
        b.visible.clear();
        b.visible.extend(
            (0..px.len() as u32).filter(|&i| is_fragment_lane(px, i as usize, width, height)),
        );
        b.depth_in.clear();
        b.depth_in.extend(b.visible.iter().map(|&i| {
            let i = i as usize;
            ShadowIn::Test {
                x: px.x[i] as i32,
                y: px.y[i] as i32,
                depth: depth(px, i) as u64,
            }
        }));
        span.feed_tests(z, zs, &b.depth_in, &mut b.depth_out);
        let mut k = 0;
        for j in 0..b.visible.len() {
            if b.depth_out[j].lit {
                b.visible[k] = b.visible[j];
                k += 1;
            }
        }
        b.visible.truncate(k);
    }

    /// The depth-buffer test's span closed under its counter name (when there is one).
    pub fn close_visible(&self, span: UnitSpan, map: &mut BTreeMap<String, Counters>) {
        if let (Some(z), Some(_)) = (&self.units.zbuf, self.zstate) {
            span.close("shadow_compare (depth buffer)", z.timing(), map);
        }
    }

    /// H·I_l of the fragments `b.visible` of `px` (texel_bits unorm) into `b.hil`:
    /// light map through the projective unit, shadow compare at the light-space texel.
    /// `base` is the attribute index of s.
    pub fn h_il(&self, px: &PolyLanes, base: usize, spans: &mut HilSpans, b: &mut ChunkBuffers) {
        b.pair_path = self.h_il_pair(px, base, spans, b);
        if b.pair_path {
            return;
        }
        let u = self.units;
        b.hil.clear();
        let n = b.visible.len();
        let need_proj = self.lm_tex.is_some() || self.sstate.is_some();
        if need_proj {
            projective_inputs(px, &b.visible, [base, base + 1, base + 3], &mut b.proj_in);
            spans
                .proj
                .feed(&u.proj, &mut (), &b.proj_in, &mut b.proj_out);
        }
        match self.lm_tex {
            Some(lm) => self.general_light_map(lm, spans, b),
            None => b.hil.resize(n, self.tex_max),
        }
        if let (Some(sh), Some(ss)) = (&u.shadow, self.sstate) {
            self.general_shadow(px, base, sh, ss, spans, b);
        }
        if need_proj {
            // Behind the projector (q ≤ 0) nothing is lit. Outside the light's square
            // (u or v outside [0, 1]) a spot emits nothing: the light map's border
            // colour is 0 (GL_CLAMP_TO_BORDER). Clamp-to-edge alone would smear the
            // edge texels (a uniform spot's disc reaches them at the mid-edges) outward
            // over the whole half-space in front of the light. (A point light has no
            // light map and no square.)
            let one = 1i32 << u.proj.out_format().frac_bits;
            let square = self.lm_tex.is_some();
            for (o, p) in b.hil.iter_mut().zip(&b.proj_out) {
                if p.behind || (square && !((0..=one).contains(&p.u) && (0..=one).contains(&p.v))) {
                    *o = 0;
                }
            }
        }
    }

    /// [`Self::h_il`]'s light map on the general path: the light map sampled at the
    /// projective unit's outputs (`b.proj_out`), channel 0 appended to `b.hil`.
    fn general_light_map(&self, lm: &TextureSampler, spans: &mut HilSpans, b: &mut ChunkBuffers) {
        let u = self.units;
        let log2 = lm.size()[0].trailing_zeros();
        let fr = lm.coord_frac_bits();
        b.tex_in.clear();
        b.tex_in.extend(b.proj_out.iter().map(|o| TextureSamplerIn {
            coord: [
                texel_word(o.u, log2, &u.proj, fr),
                texel_word(o.v, log2, &u.proj, fr),
                0,
            ],
        }));
        // A sample outside the light's square or behind the projector is
        // replaced by 0 later: not filtered, only counted.
        let one = 1i32 << u.proj.out_format().frac_bits;
        b.tex_keep.clear();
        b.tex_keep.extend(
            b.proj_out
                .iter()
                .map(|p| !p.behind && (0..=one).contains(&p.u) && (0..=one).contains(&p.v)),
        );
        spans
            .light_map
            .feed_keep(lm, &b.tex_in, &b.tex_keep, &mut b.tex_out);
        b.hil.extend(b.tex_out.iter().map(|t| t[0]));
    }

    /// [`Self::h_il`]'s shadow compare on the general path: the depth (r, 0, q) through
    /// its projective unit, tested at the light-map unit's texel (`b.proj_out`); a
    /// fragment in shadow gets H·I_l = 0.
    fn general_shadow(
        &self,
        px: &PolyLanes,
        base: usize,
        sh: &ShadowCompare,
        ss: &ShadowState,
        spans: &mut HilSpans,
        b: &mut ChunkBuffers,
    ) {
        let u = self.units;
        // (r, 0, q): the depth through the same reciprocal (t has no wire here).
        projective_inputs(
            px,
            &b.visible,
            [base + 2, usize::MAX, base + 3],
            &mut b.pdepth_in,
        );
        spans
            .proj_depth
            .feed(&u.proj_depth, &mut (), &b.pdepth_in, &mut b.pdepth_out);
        let at = ShadowAddress::new(u, sh);
        b.shadow_in.clear();
        b.shadow_in.extend(
            b.proj_out
                .iter()
                .zip(&b.pdepth_out)
                .map(|(o, d)| ShadowIn::Test {
                    x: at.texel(o.u),
                    y: at.texel(o.v),
                    depth: at.depth_word(d.u),
                }),
        );
        spans
            .shadow
            .feed_tests(sh, ss, &b.shadow_in, &mut b.shadow_out);
        for (o, l) in b.hil.iter_mut().zip(&b.shadow_out) {
            if !l.lit {
                *o = 0;
            }
        }
    }

    /// [`Self::h_il`] with the light map and the shadow map, where the light-map and
    /// the depth projective units share their reciprocal front end
    /// ([`ProjectiveTexcoord::kernel_pair_lanes`]: the same q, each unit counted as
    /// its own batch kernel), their outputs in lanes. False with nothing done
    /// elsewhere (the general path then runs).
    fn h_il_pair(
        &self,
        px: &PolyLanes,
        base: usize,
        spans: &mut HilSpans,
        b: &mut ChunkBuffers,
    ) -> bool {
        let u = self.units;
        let (Some(lm), Some(sh), Some(ss)) = (self.lm_tex, &u.shadow, self.sstate) else {
            return false;
        };
        if base + 3 >= px.attrs.len() || !u.proj.pair_lanes_apply(&u.proj_depth) {
            return false;
        }
        let a = &px.attrs;
        b.proj_lanes.clear();
        b.pdepth_u.clear();
        let n = b.visible.len();
        let lanes: [&[i64]; 4] = [&a[base], &a[base + 1], &a[base + 2], &a[base + 3]];
        let (ctr, dctr) = (&mut spans.proj.ctr, &mut spans.proj_depth.ctr);
        let (pl, du) = (&mut b.proj_lanes, &mut b.pdepth_u);
        // Of a fragment outside the light's square only counters are read (H·I_l is
        // 0, the shadow test's outcome is not used): its codes may be replaced by
        // ones of the same classes, as long as the counters cannot tell them apart
        // (it is off the shadow map, and the light map's wrapped-coordinate count is
        // the same).
        let cut = b.cut_outside_square && self.square_cuts(lm, sh);
        let skipped = if cut {
            u.proj
                .kernel_pair_lanes_in_square(&u.proj_depth, lanes, &b.visible, pl, du, ctr, dctr)
        } else {
            u.proj
                .kernel_pair_lanes(&u.proj_depth, lanes, &b.visible, pl, du, ctr, dctr)
                .then_some(0)
        };
        spans.proj.tally.add(n);
        spans.proj_depth.tally.add(n);
        match skipped {
            Some(k) if k > 0 => self.pair_in_square(sh, ss, lm, n, spans, b),
            _ => {
                self.pair_lit(sh, ss, spans, b);
                self.pair_light_map(lm, n, spans, b);
            }
        }
        true
    }

    /// Whether the pair path may leave a fragment outside the light's square to its
    /// counters: no code of the projective unit wraps the light map's coordinate
    /// wire, and the shadow map's texels are the square (off it, off the map).
    fn square_cuts(&self, lm: &TextureSampler, sh: &ShadowCompare) -> bool {
        light_map_never_wraps(lm, &self.units.proj)
            && ShadowAddress::new(self.units, sh).is_the_square(sh, &self.units.proj)
    }

    /// The square cut of a pass that sets `cut_outside_square` and reads s, t, r
    /// and q from attributes `base..base + 4` of its walk: Some where [`Self::h_il`]
    /// takes the pair path with the square form, so that a chunk whose fragments are
    /// all of one class ([`SquareCut::range`]) may be counted without its
    /// coordinates ([`Self::h_il_class`]).
    pub fn chunk_cut(&self, base: usize) -> Option<ChunkCut<'_>> {
        let u = self.units;
        let (Some(lm), Some(sh), Some(_)) = (self.lm_tex, &u.shadow, self.sstate) else {
            return None;
        };
        let attrs = u.interp.attrs() as usize;
        if base + 3 >= attrs || !u.proj.pair_lanes_apply(&u.proj_depth) || !self.square_cuts(lm, sh)
        {
            return None;
        }
        let cut = SquareCut::of(&u.proj, &u.proj_depth)?;
        Some(ChunkCut { cut, base, lm, sh })
    }

    /// [`Self::h_il`] of a chunk whose fragments `b.visible` are all of `class`
    /// (each behind the light or outside its square, [`ChunkCut::row`]): the
    /// projective units, the shadow test and the light map counted as the pair path
    /// counts them, without running; H·I_l 0 each.
    pub fn h_il_class(
        &self,
        cc: &ChunkCut,
        class: SquareClass,
        spans: &mut HilSpans,
        b: &mut ChunkBuffers,
    ) {
        let n = b.visible.len();
        self.count_class(cc, class, n, spans);
        b.pair_path = true;
        b.hil.clear();
        b.hil.resize(n, 0);
    }

    /// [`Self::h_il`] (s at attribute `base`) of a chunk walked by the kinds of
    /// [`ChunkCut::row`] (`cut`, the chunk's class and its blank stretches): a chunk
    /// of decided rows counted ([`Self::h_il_class`]), a chunk with blank stretches
    /// run with those counted and left out ([`Self::h_il_blanks`]), another run.
    /// Returns how many visible fragments were left out of `b.visible`.
    pub fn h_il_by_kind(
        &self,
        px: &PolyLanes,
        base: usize,
        (cut, class, blanks): (Option<&ChunkCut>, Option<SquareClass>, &[RowStretch]),
        spans: &mut HilSpans,
        b: &mut ChunkBuffers,
    ) -> usize {
        match (class, cut) {
            (Some(class), Some(c)) => {
                self.h_il_class(c, class, spans, b);
                0
            }
            (None, Some(c)) if !blanks.is_empty() => self.h_il_blanks(c, px, blanks, spans, b),
            _ => {
                self.h_il(px, base, spans, b);
                0
            }
        }
    }

    /// [`Self::h_il`] of a chunk whose words in the ranges `blanks` (in order, s, t,
    /// r and q blank there: [`ChunkCut::row`]) are each of the range's class:
    /// their visible fragments counted ([`Self::count_class`]) and left out of
    /// `b.visible`, the rest run. Returns how many were left out (H·I_l 0 each).
    pub fn h_il_blanks(
        &self,
        cc: &ChunkCut,
        px: &PolyLanes,
        blanks: &[RowStretch],
        spans: &mut HilSpans,
        b: &mut ChunkBuffers,
    ) -> usize {
        // b.visible is in word order: each range's fragments are one stretch of it,
        // and the rest move to the front.
        let vis = &mut b.visible;
        let (mut kept, mut from, mut left_out) = (0, 0, 0);
        for (words, class) in blanks {
            let lo = from + vis[from..].partition_point(|&i| (i as usize) < words.start);
            let hi = lo + vis[lo..].partition_point(|&i| (i as usize) < words.end);
            vis.copy_within(from..lo, kept);
            kept += lo - from;
            if hi > lo {
                self.count_class(cc, *class, hi - lo, spans);
            }
            left_out += hi - lo;
            from = hi;
        }
        let len = vis.len();
        vis.copy_within(from..len, kept);
        vis.truncate(kept + len - from);
        self.h_il(px, cc.base, spans, b);
        left_out
    }

    /// `n` fragments of `class` ([`Self::h_il_class`]) counted: the projective
    /// units, the shadow test and the light map as the pair path counts them.
    pub fn count_class(&self, cc: &ChunkCut, class: SquareClass, n: usize, spans: &mut HilSpans) {
        let (ctr, dctr) = (&mut spans.proj.ctr, &mut spans.proj_depth.ctr);
        self.units.proj.count_pair_class(class, n as u64, ctr, dctr);
        spans.proj.tally.add(n);
        spans.proj_depth.tally.add(n);
        let behind = if class.live { 0 } else { n };
        Self::count_decided((cc.sh, cc.lm), n, behind, spans);
    }

    /// [`Self::h_il_pair`] where the square form decided some of the `n` fragments'
    /// blocks ([`ProjLanes::decided`]), perhaps all: the undecided blocks' lanes moved
    /// to the front and run through [`Self::pair_lit`] and [`Self::pair_light_map`];
    /// the decided ones counted without running ([`Self::count_decided`]), their
    /// H·I_l 0 (the counters are sums over the fragments, the same in any grouping).
    #[allow(clippy::too_many_arguments)]
    fn pair_in_square(
        &self,
        sh: &ShadowCompare,
        ss: &ShadowState,
        lm: &TextureSampler,
        n: usize,
        spans: &mut HilSpans,
        b: &mut ChunkBuffers,
    ) {
        // Block k's fragments in the visible list.
        let block = |k: usize| k * SQUARE_BLOCK..((k + 1) * SQUARE_BLOCK).min(n);
        let (pl, du) = (&mut b.proj_lanes, &mut b.pdepth_u);
        let (mut kept, mut behind) = (0, 0);
        for (k, &decided) in pl.decided.iter().enumerate() {
            let at = block(k);
            if decided {
                behind += pl.behind[at].iter().filter(|&&x| x).count();
                continue;
            }
            let len = at.len();
            pl.u.copy_within(at.clone(), kept);
            pl.v.copy_within(at.clone(), kept);
            pl.behind.copy_within(at.clone(), kept);
            du.copy_within(at, kept);
            kept += len;
        }
        Self::count_decided((sh, lm), n - kept, behind, spans);
        if kept == 0 {
            b.hil.clear();
            b.hil.resize(n, 0);
            return;
        }
        pl.u.truncate(kept);
        pl.v.truncate(kept);
        pl.behind.truncate(kept);
        du.truncate(kept);
        self.pair_lit(sh, ss, spans, b);
        self.pair_light_map(lm, kept, spans, b);
        // The undecided blocks' H·I_l back at their fragments, 0 at the others.
        std::mem::swap(&mut b.hil, &mut b.hil_undecided);
        b.hil.clear();
        b.hil.resize(n, 0);
        let undecided = (b.proj_lanes.decided.iter().enumerate()).filter(|&(_, &d)| !d);
        let mut from = 0;
        for at in undecided.map(|(k, _)| block(k)) {
            let len = at.len();
            b.hil[at].copy_from_slice(&b.hil_undecided[from..from + len]);
            from += len;
        }
    }

    /// The shadow test and the light map of `n` fragments the square form decided,
    /// `behind` of them behind the light, counted without running. Behind the light
    /// (u, v) = (0, 0), the shadow map's texel (0, 0): a read; outside the square the
    /// texel is off the map: a border lookup. A light-map sample each, none of whose
    /// coordinates wraps (the caller checked the whole code range).
    fn count_decided(
        (sh, lm): (&ShadowCompare, &TextureSampler),
        n: usize,
        behind: usize,
        spans: &mut HilSpans,
    ) {
        sh.count_tests(behind, n - behind, &mut spans.shadow.ctr);
        spans.shadow.tally.add(n);
        lm.count_samples(n as u64, &mut spans.light_map.ctr);
        spans.light_map.tally.add(n);
    }

    /// [`Self::h_il_pair`]'s shadow compare: whether the shadow map lights each
    /// fragment into `b.lit`, at the light-space texel of the projective lanes
    /// (`b.proj_lanes`), the depth (`b.pdepth_u`) through the same q.
    fn pair_lit(
        &self,
        sh: &ShadowCompare,
        ss: &ShadowState,
        spans: &mut HilSpans,
        b: &mut ChunkBuffers,
    ) {
        let at = ShadowAddress::new(self.units, sh);
        let pl = &b.proj_lanes;
        b.lit.clear();
        // Each fragment's texel and depth word, in lanes: tested on the shadow map's
        // unpacked words (the lit bits in lanes, no test words) where the pass has
        // them, else as test words.
        let (x, y, depth) = (&mut b.shadow_x, &mut b.shadow_y, &mut b.shadow_depth);
        x.clear();
        x.extend(pl.u.iter().map(|&u| at.texel(u)));
        y.clear();
        y.extend(pl.v.iter().map(|&v| at.texel(v)));
        depth.clear();
        depth.extend(b.pdepth_u.iter().map(|&d| at.depth_word(d)));
        let tested = self.swords.and_then(|words| {
            sh.test_lit_lanes(words, (x, y, depth), &mut b.lit, &mut spans.shadow.ctr)
        });
        match tested {
            Some(k) => spans.shadow.tally.add(k),
            None => {
                b.shadow_in.clear();
                b.shadow_in.extend(
                    x.iter()
                        .zip(y.iter())
                        .zip(depth.iter())
                        .map(|((&x, &y), &depth)| ShadowIn::Test { x, y, depth }),
                );
                spans
                    .shadow
                    .feed_tests(sh, ss, &b.shadow_in, &mut b.shadow_out);
                b.lit.extend(b.shadow_out.iter().map(|o| o.lit));
            }
        }
    }

    /// [`Self::h_il_pair`]'s light map: H·I_l of the `n` fragments into `b.hil`, the
    /// light map's sample at the projective lanes' texel where kept, else 0.
    fn pair_light_map(
        &self,
        lm: &TextureSampler,
        n: usize,
        spans: &mut HilSpans,
        b: &mut ChunkBuffers,
    ) {
        let u = self.units;
        let pl = &b.proj_lanes;
        let one = 1i32 << u.proj.out_format().frac_bits;
        // A sample behind the projector, outside the light's square or in shadow
        // gives H·I_l = 0 whatever its value: not filtered, only counted.
        let log2 = lm.size()[0].trailing_zeros();
        let fr = lm.coord_frac_bits();
        b.tex_s.clear();
        b.tex_s
            .extend(pl.u.iter().map(|&pu| texel_word(pu, log2, &u.proj, fr)));
        b.tex_t.clear();
        b.tex_t
            .extend(pl.v.iter().map(|&pv| texel_word(pv, log2, &u.proj, fr)));
        // Whether each sample is kept, in one pass over the lanes.
        b.tex_keep.clear();
        b.tex_keep
            .extend((pl.behind.iter().zip(&pl.u).zip(&pl.v).zip(&b.lit)).map(
                |(((&behind, &u), &v), &lit)| {
                    !behind & (0..=one).contains(&u) & (0..=one).contains(&v) & lit
                },
            ));
        let kept = &b.tex_keep;
        let keep = |i: usize| kept[i];
        // H·I_l: the light map's sample where kept, else 0.
        b.hil.clear();
        b.hil.resize(n, 0);
        if lm.sample_lanes_keep(
            &b.tex_s,
            &b.tex_t,
            keep,
            &mut b.hil,
            &mut spans.light_map.ctr,
        ) {
            spans.light_map.tally.add(n);
        } else {
            b.tex_in.clear();
            b.tex_in.extend(
                b.tex_s
                    .iter()
                    .zip(&b.tex_t)
                    .map(|(&s, &t)| TextureSamplerIn { coord: [s, t, 0] }),
            );
            spans
                .light_map
                .feed_keep(lm, &b.tex_in, &b.tex_keep, &mut b.tex_out);
            for ((o, t), &k) in b.hil.iter_mut().zip(&b.tex_out).zip(&b.tex_keep) {
                if k {
                    *o = t[0];
                }
            }
        }
    }
}

/// Where a fragment meets the shadow map: the projective unit's u, v (`of` fraction
/// bits, 1.0 = the map's side) shifted onto the map's texel grid, and the depth
/// unit's output (`dfrac` fraction bits) as a `dbits` depth word, clamped at its
/// full scale.
#[derive(Clone, Copy, Debug)]
struct ShadowAddress {
    shift: u32,
    dbits: u32,
    dfrac: u32,
    dmax: i64,
}

impl ShadowAddress {
    fn new(u: &Units, sh: &ShadowCompare) -> Self {
        let res = sh.width();
        let of = u.proj.out_format().frac_bits;
        let dbits = sh.depth_bits();
        ShadowAddress {
            shift: of - res.trailing_zeros().min(of),
            dbits,
            dfrac: u.proj_depth.out_format().frac_bits,
            dmax: max_code(dbits) as i64,
        }
    }

    /// Whether the shadow map's texels are the light's square, no more: a
    /// coordinate of `proj` is on the map exactly where it is in [0, 1.0).
    fn is_the_square(&self, sh: &ShadowCompare, proj: &ProjectiveTexcoord) -> bool {
        let one = 1u64 << proj.out_format().frac_bits;
        [sh.width(), sh.height()]
            .iter()
            .all(|&side| (side as u64) << self.shift == one)
    }

    /// A projective coordinate → the shadow map's texel index.
    fn texel(&self, c: i32) -> i32 {
        c >> self.shift
    }

    /// The depth unit's output (negative: 0) → the shadow map's depth word.
    fn depth_word(&self, d: i32) -> u64 {
        let dv = d.max(0) as i64;
        let word = if self.dbits >= self.dfrac {
            dv << (self.dbits - self.dfrac)
        } else {
            dv >> (self.dfrac - self.dbits)
        };
        word.min(self.dmax) as u64
    }
}

/// The projective unit's (s, t, q) words of the fragments `visible` of `px`, from
/// attributes `idx` (`usize::MAX`: a wire held at 0), into `out`.
fn projective_inputs(
    px: &PolyLanes,
    visible: &[u32],
    idx: [usize; 3],
    out: &mut Vec<ProjectiveIn>,
) {
    // The t wire held at 0 reads a zero attribute (the depth's (r, 0, q)).
    let [si, ti, qi] = idx;
    let (s, q) = (&px.attrs[si], &px.attrs[qi]);
    out.clear();
    match px.attrs.get(ti) {
        Some(t) => out.extend(visible.iter().map(|&i| {
            let i = i as usize;
            ProjectiveIn {
                s: s[i],
                t: t[i],
                q: q[i],
            }
        })),
        None => out.extend(visible.iter().map(|&i| {
            let i = i as usize;
            ProjectiveIn {
                s: s[i],
                t: 0,
                q: q[i],
            }
        })),
    }
}

/// Whether no code of the projective unit's output range wraps the light map's
/// coordinate wire as [`texel_word`] (the range's ends do not, and the wire's range
/// is an interval around 0).
fn light_map_never_wraps(lm: &TextureSampler, proj: &ProjectiveTexcoord) -> bool {
    let (log2, fr) = (lm.size()[0].trailing_zeros(), lm.coord_frac_bits());
    let f = proj.out_format();
    [f.min_raw(), f.max_raw()]
        .iter()
        .all(|&c| !lm.coord_wire(texel_word(c as i32, log2, proj, fr)).1)
}

/// Normalised projective s4.12 → the sampler's texel-space word for a 2^log2 texture.
pub(super) fn texel_word(
    raw: i32,
    log2_size: u32,
    proj: &ProjectiveTexcoord,
    sampler_frac: u32,
) -> i32 {
    let shift = log2_size as i32 + sampler_frac as i32 - proj.out_format().frac_bits as i32;
    if shift >= 0 {
        raw << shift
    } else {
        raw >> -shift
    }
}
