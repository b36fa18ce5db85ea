//! The sample-plane pass of one light (Dobashi et al. eqs. (5)–(9)): per interval i, the m
//! sub-planes' H·I_l averaged into the J buffer and copied to a texture (m > 1), then
//! plane i drawn as a cols × rows mesh whose fragments take F(α)·h(s, t), J, the
//! plane scale and the light colour through the modulate unit into the framebuffer.
//!
//! Fragments go through the units a chunk of walk rows at a time ([`super::chunked`]); the
//! spans and the merge order are those of the span driver, so the bytes and counters
//! do not depend on the chunking or the thread count.

use super::chunked::{ChunkBuffers, DepthWords, HilSpans, LightCtx, UnitSpan};
use super::pass_log::PassLog;
use super::prepare::Prepared;
use super::record::{self, Rec};
use super::tables::{self, GTables};
use super::units::{attr_unorm, counters_add, unit_depth_word, ATTR_FRAC, ZBUF_BITS};
use super::view::vec3;
use crate::chip::work::{PassWork, SampleBands};
use crate::chip::{PassKind, PassStats};
use crate::pipeline::raster::{
    host_attrs, quantise, walk_rows_lanes, walk_rows_lanes_blank, HostVertex, WalkBuffers,
};
use crate::report::image_out::Framebuffer;
use crate::scene::format::{PlaneStep, ShaftsConfig};
use crate::scene::math::Vec3;
use rayon::prelude::*;
use rtl_model::error::ConfigError;
use rtl_model::units::blend::{Blend, BlendIn};
use rtl_model::units::modulate::Operand;
use rtl_model::units::polygon_interpolator::{PolyLanes, PolySetup};
use rtl_model::units::rising_run;
use rtl_model::units::texture_sampler::{
    AddressMode, Filter, TextureSampler, TextureSamplerConfig, TextureSamplerIn,
};
use rtl_model::unorm::max_code;
use rtl_model::{Counters, Unit};
use std::collections::BTreeMap;
use std::sync::Mutex;

/// Sub-planes whose H·I_l is computed in parallel at a time (memory: one full-screen
/// fragment list each). Fixed, so the work split never depends on the thread count.
const SUBPLANE_BATCH: usize = 4;

/// One sub-plane's visible fragments as the J buffer's blend takes them, the
/// counters of the units that made them and, when recording, what the sub-plane did.
struct SubPlaneHil {
    /// The blended fragments' pixels (y·w + x), in walk order.
    pix: Vec<u32>,
    /// Their H·I_l.
    hil: Vec<u32>,
    /// Visible fragments left out of the lists: whole blocks of them whose H·I_l is
    /// 0 (outside the light's square, behind it or in shadow), which the blend
    /// counts and leaves as they are ([`Blend::count_zero_lanes`]).
    zero: usize,
    /// The rows of `pix` never go up.
    rows_in_order: bool,
    counters: BTreeMap<String, Counters>,
    rec: Option<Rec>,
}

/// Full-screen word lists (the sub-planes' pixel and H·I_l lists, the J buffer) handed
/// back once an interval's J buffer is made and reused by the next interval's: fresh
/// ones each time would have their pages faulted in on first write and unmapped
/// again on drop, on every sub-plane. What a list held is never read (each is
/// cleared or zeroed when taken), so the bytes do not depend on which list is reused.
#[derive(Default)]
struct WordPool(Mutex<Vec<Vec<u32>>>);

impl WordPool {
    /// An empty list with room for `len` words.
    fn take(&self, len: usize) -> Vec<u32> {
        let mut v = self
            .0
            .lock()
            .ok()
            .and_then(|mut p| p.pop())
            .unwrap_or_default();
        v.clear();
        v.reserve(len);
        v
    }

    /// `len` zero words.
    fn zeroed(&self, len: usize) -> Vec<u32> {
        let mut v = self.take(len);
        v.resize(len, 0);
        v
    }

    fn give(&self, v: Vec<u32>) {
        if let Ok(mut p) = self.0.lock() {
            p.push(v);
        }
    }
}

/// A plane fragment's framebuffer position and colour (texel_bits unorm).
#[derive(Clone, Copy, Debug)]
struct PlaneFrag {
    x: u32,
    y: u32,
    rgb: [u32; 3],
}

/// The spans of one plane's units; a mesh cell's part merges into the plane's.
#[derive(Clone, Copy, Debug, Default)]
struct PlaneSpans {
    interp: Counters,
    zbuf: UnitSpan,
    f: UnitSpan,
    h: UnitSpan,
    j: UnitSpan,
    hil: HilSpans,
    /// The four modulates J·S, ·F, ·colour, ·h: four spans, as four span-driver calls.
    modulate: [UnitSpan; 4],
}

impl PlaneSpans {
    fn merge(&mut self, o: &PlaneSpans) {
        self.interp += o.interp;
        self.zbuf.merge(&o.zbuf);
        self.f.merge(&o.f);
        self.h.merge(&o.h);
        self.j.merge(&o.j);
        self.hil.merge(&o.hil);
        for (a, b) in self.modulate.iter_mut().zip(&o.modulate) {
            a.merge(b);
        }
    }

    /// End the plane's spans: each unit's counters, timing included, under its name
    /// (J from the J texture when there is one, else H·I_l's units).
    fn close(
        self,
        ctx: &LightCtx,
        jtex: Option<&TextureSampler>,
        ctr: &mut BTreeMap<String, Counters>,
    ) {
        let u = ctx.units;
        counters_add(ctr, "polygon_interpolator", self.interp);
        ctx.close_visible(self.zbuf, ctr);
        self.f.close("texture_sampler (F)", u.f_tex.timing(), ctr);
        self.h.close("texture_sampler (h)", u.h_tex.timing(), ctr);
        match jtex {
            Some(t) => self.j.close("texture_sampler (J)", t.timing(), ctr),
            None => self.hil.close(ctx, ctr),
        }
        for s in self.modulate {
            s.close("modulate", u.modulate.timing(), ctr);
        }
    }
}

/// Buffers of one mesh cell's chunks besides the H·I_l ones.
#[derive(Default)]
struct PlaneBuffers {
    chunk: ChunkBuffers,
    f_in: Vec<TextureSamplerIn>,
    f_out: Vec<[u32; 4]>,
    h_in: Vec<TextureSamplerIn>,
    h_out: Vec<[u32; 4]>,
    j_in: Vec<TextureSamplerIn>,
    j_out: Vec<[u32; 4]>,
    m_a: Vec<u32>,
    m_b: Vec<u32>,
    /// The vertex colour's code and the three channels' products, in lanes.
    m_s: Vec<u32>,
    m_rgb: [Vec<u32>; 3],
    /// The samplers' coordinate words and outputs in lanes (F: s; h: s, t; J: x, y).
    f_s: Vec<i32>,
    f_o: Vec<u32>,
    h_s: Vec<i32>,
    h_t: Vec<i32>,
    h_o: Vec<u32>,
    j_s: Vec<i32>,
    j_t: Vec<i32>,
    /// When recording: the chunk's footprints of F, h, and J or the light map and the
    /// shadow map.
    fp: [Vec<u32>; 4],
}

/// What every fragment of plane i shares.
struct PlaneCtx<'a> {
    ctx: &'a LightCtx<'a>,
    /// The camera depth buffer's words and row ranges ([`DepthWords`]).
    zwords: Option<DepthWords<'a>>,
    jtex: Option<&'a TextureSampler>,
    zword: u32,
    color_codes: [u32; 3],
    coord_shift: u32,
    /// Record the plane's work ([`Rec`]).
    record: bool,
    /// Recording in sampled mode: the bands whose fragments are kept.
    bands: Option<SampleBands>,
}

/// The n sample planes (and their sub-planes when m > 1): per interval i, its
/// sub-planes into the J buffer and the J buffer copied to the J texture (m > 1),
/// then plane i.
pub(super) fn planes_pass(
    ctx: &LightCtx,
    p: &Prepared,
    tables: &GTables,
    fb: &mut Framebuffer,
    ctr: &mut BTreeMap<String, Counters>,
    log: &mut PassLog,
) -> Result<(), ConfigError> {
    let cfg = p.scene.shafts;
    let n = cfg.planes as usize;
    // What sub-plane k of the light's sub-planes (k = i·m + j: interval i's j-th)
    // records: nothing, or every fragment or the sampled bands'.
    let sub_record = log.recorder();
    let m = cfg.subplanes as usize;
    let (r0, r1) = p.plane_range;
    let dr = (r1 - r0) / n as f64;
    let mut jtex: Option<TextureSampler> = None;
    let (zwords, swords) = unpacked_words(ctx);
    let zwords = (zwords.as_ref()).map(|(words, rows)| DepthWords { words, rows });
    let ctx = &LightCtx {
        swords: swords.as_deref(),
        ..*ctx
    };

    // Interval i's sub-planes' H·I_l (independent of the framebuffer and the J
    // buffer): interval i + 1's are computed beside plane i's blend into the
    // framebuffer, then merged and blended in order as before.
    let pool = WordPool::default();
    let hil_of = |i: usize| {
        subplanes_hil(
            ctx,
            p,
            (zwords, &pool),
            r0 + (i as f64 + 0.5) * dr,
            dr,
            |j| sub_record(i * m + j),
        )
    };
    let mut pending = None;
    // The planes' fragment list and blend buffers, reused from plane to plane.
    let (mut frags, mut scratch) = (Vec::new(), BlendScratch::default());
    for i in 0..n {
        let r = r0 + (i as f64 + 0.5) * dr;
        // Sub-sample planes: J_i = (1/m) Σ H·I_l into the J buffer, copied to a texture.
        if m > 1 {
            let hils = pending.take().unwrap_or_else(|| hil_of(i));
            let jbuf = subplanes_into_j(ctx, p, hils, &pool, ctr, log)?;
            copy_to_j_texture(ctx, p, &jbuf, &mut jtex, ctr, log, i)?;
            pool.give(jbuf);
        }
        let next = m > 1 && i + 1 < n;
        pending = plane(
            ctx,
            p,
            zwords,
            tables,
            (i, r, dr),
            jtex.as_ref().filter(|_| m > 1),
            fb,
            (&mut frags, &mut scratch),
            ctr,
            log,
            || next.then(|| hil_of(i + 1)),
        )?;
        // One step of `render`'s bar per plane (nothing when no bar is installed).
        crate::report::progress::frame_step(1);
    }
    Ok(())
}

/// The camera depth buffer's words with each row's least and greatest word, and the
/// shadow map's words, unpacked once for every plane's and sub-plane's tests in
/// lanes: both are read-only during the planes pass. `None` for a buffer the light's
/// passes do not have.
#[allow(clippy::type_complexity)]
fn unpacked_words(ctx: &LightCtx) -> (Option<(Vec<u32>, Vec<(u32, u32)>)>, Option<Vec<u32>>) {
    let zwords = match (&ctx.units.zbuf, ctx.zstate) {
        (Some(z), Some(zs)) => z.words(zs).map(|words| {
            let rows = z.row_ranges(&words);
            (words, rows)
        }),
        _ => None,
    };
    let swords = match (&ctx.units.shadow, ctx.sstate) {
        (Some(sh), Some(ss)) => sh.words(ss),
        _ => None,
    };
    (zwords, swords)
}

/// The J buffer copied to the J texture: read the J buffer and write the texture (a
/// copy pass of memory traffic only), the texture made at the first copy and loaded
/// at each next one. `i`: the copy's number among the light's copies (whether it
/// records, [`PassLog::records`]).
fn copy_to_j_texture(
    ctx: &LightCtx,
    p: &Prepared,
    jbuf: &[u32],
    jtex: &mut Option<TextureSampler>,
    ctr: &mut BTreeMap<String, Counters>,
    log: &mut PassLog,
    i: usize,
) -> Result<(), ConfigError> {
    let cfg = p.scene.shafts;
    let (w, h) = (p.scene.image.width, p.scene.image.height);
    let mut st = PassStats::new(PassKind::CopyToTexture, ctx.li, 0);
    let bytes = (w * h) as u64 * rtl_model::memory::bytes_for_bits(cfg.texel_bits);
    st.other_bytes = 2 * bytes;
    let work = log.records(i).then(|| PassWork {
        width: w,
        height: h,
        copy_read_bytes: bytes,
        copy_write_bytes: bytes,
        ..PassWork::default()
    });
    log.push(ctr, st, work)?;
    match jtex.as_mut() {
        Some(t) => t.load(jbuf)?,
        None => {
            // A w × h texture of texel_bits, sampled at pixel centres (nearest).
            *jtex = Some(TextureSampler::new(
                TextureSamplerConfig {
                    dims: 2,
                    size: [w, h, 1],
                    texel_bits: cfg.texel_bits,
                    coord_int_bits: 16,
                    filter: Filter::Nearest,
                    address: [AddressMode::Clamp; 3],
                    ..TextureSamplerConfig::geforce()
                },
                jbuf,
            )?)
        }
    }
    Ok(())
}

/// The attribute index of the light's s in a plane's and a sub-plane's walk: s, t,
/// r and q are attributes 4..=7 (a sub-plane's 0..=3 are the constant 0).
const LIGHT_ATTRS: usize = 4;

/// Interval [r − Δr/2, r + Δr/2]'s m sub-planes' H·I_l, in sub-plane order: each
/// independent of the J buffer and the framebuffer, so computed in parallel, each
/// with its own counters, to be merged and blended in sub-plane order by
/// [`subplanes_into_j`] (the same spans, counters and bytes as one after the other,
/// whatever the thread count).
fn subplanes_hil(
    ctx: &LightCtx,
    p: &Prepared,
    (zwords, pool): (Option<DepthWords>, &WordPool),
    r: f64,
    dr: f64,
    recording: impl Fn(usize) -> Option<Option<SampleBands>> + Sync,
) -> Vec<Result<SubPlaneHil, ConfigError>> {
    let m = p.scene.shafts.subplanes as usize;
    let all: Vec<usize> = (0..m).collect();
    let mut out = Vec::with_capacity(m);
    for batch in all.chunks(SUBPLANE_BATCH) {
        out.par_extend(batch.par_iter().map(|&j| {
            // Sub-plane j at the middle of the interval's j-th m-th.
            let uj = r - dr / 2.0 + (j as f64 + 0.5) * dr / m as f64;
            subplane_hil(ctx, p, (zwords, pool), uj, recording(j))
        }));
    }
    out
}

/// The sub-plane at eye distance `uj`: a full-screen parallelogram walked, its pixels
/// depth-tested at the sub-plane's window depth, and the visible ones' H·I_l, with
/// the counters of the units that made them (and, when `recording`, its record).
fn subplane_hil(
    ctx: &LightCtx,
    p: &Prepared,
    (zwords, pool): (Option<DepthWords>, &WordPool),
    uj: f64,
    recording: Option<Option<SampleBands>>,
) -> Result<SubPlaneHil, ConfigError> {
    let u = ctx.units;
    let (w, h) = (p.scene.image.width, p.scene.image.height);
    let mut local = BTreeMap::new();
    let mut c_int = Counters::default();
    let setup = subplane_setup(ctx, (w, h), uj, &mut c_int)?;
    let zsub = ctx
        .cam
        .project(ctx.cam.point_at(w as f64 * 0.5, h as f64 * 0.5, uj))
        .map_or(1.0, |v| v.2);
    let zw = unit_depth_word(zsub, ZBUF_BITS);
    let (mut zspan, mut spans) = (UnitSpan::default(), HilSpans::default());
    let mut b = ChunkBuffers::default();
    // At most one fragment per pixel: no growing (and copying) on the way.
    let (mut pix, mut hil) = (pool.take((w * h) as usize), pool.take((w * h) as usize));
    // Attributes 0..=3 are the constant 0 (no plane attributes here): no one
    // reads their lanes (the depth is `zw`, H·I_l reads s, t, r, q).
    let mut wb = WalkBuffers::unread((1 << LIGHT_ATTRS) - 1);
    let (mut rows_in_order, mut last_y) = (true, 0i64);
    let mut zero = 0;
    let mut rec = recording.map(|bands| subplane_rec(ctx, bands, (w, h)));
    b.cut_outside_square = rec.is_none();
    let depth_tested = u.zbuf.is_some() && ctx.zstate.is_some();
    let (mut lm, mut sm) = (Vec::new(), Vec::new());
    // A row whose fragments are all of one class of the light's square cut (all
    // behind the light, or all outside its square alike) is walked with s, t, r, q
    // unread and counted without them (the unit's counters are the same); in
    // another row, its first and last stretches of one class each are walked with
    // them blank and counted alike.
    let cut = (b.cut_outside_square)
        .then(|| ctx.chunk_cut(LIGHT_ATTRS))
        .flatten();
    let light = 0b1111 << LIGHT_ATTRS;
    // The last row's stretch ends, where the next row's are looked for.
    let mut ends = [None, None];
    let row_kind = |row: u64| {
        let Some(c) = cut.as_ref() else {
            return (0, None, [None, None]);
        };
        match c.row(u, &setup, row, &mut ends) {
            (Some(class), _) => (light, Some(class), [None, None]),
            (None, blanks) => (0, None, blanks),
        }
    };
    walk_rows_lanes_blank(
        &u.interp,
        &setup,
        &mut c_int,
        &mut wb,
        light,
        row_kind,
        |px, class, blanks| {
            ctx.visible_flat(px, (w, h), zw, zwords, &mut zspan, &mut b);
            let kind = (cut.as_ref(), class, blanks);
            let blanked = ctx.h_il_by_kind(px, LIGHT_ATTRS, kind, &mut spans, &mut b);
            if let Some(r) = rec.as_mut() {
                let kept = record::chunk_fragments(r, px, &b.visible, (w, h), depth_tested);
                if !kept.is_none() {
                    ctx.hil_footprint(&b, &mut lm, &mut sm);
                    let runs = ctx.hil_runs(&lm, &sm);
                    record::interleave_kept(&runs, b.visible.len(), &kept, &mut r.texels);
                }
            }
            // The rows never go up when the walked rows never do (then neither do the
            // visible fragments' among them).
            rows_in_order &=
                px.y.first().is_none_or(|&y| y >= last_y) && px.y.windows(2).all(|r| r[0] <= r[1]);
            last_y = px.y.last().copied().unwrap_or(last_y);
            // A decided row's H·I_l is all 0, and so is a blank stretch's: their
            // fragments left out.
            zero += blanked
                + match class {
                    Some(_) => b.visible.len(),
                    None => push_fragments(px, (&b.visible, &b.hil), w, (&mut pix, &mut hil)),
                };
        },
    );
    counters_add(&mut local, "polygon_interpolator", c_int);
    ctx.close_visible(zspan, &mut local);
    spans.close(ctx, &mut local);
    Ok(SubPlaneHil {
        pix,
        hil,
        zero,
        rows_in_order,
        counters: local,
        rec,
    })
}

/// The walked lanes `visible` with H·I_l `hil` (one per visible lane) appended to
/// a sub-plane's lists, in blocks of 16: a block's pixel indices y·w + x to `pix`
/// and its H·I_l to `hil_out`. A block whose H·I_l is all 0 (most of a sub-plane
/// lies outside the light's square) is left out: its lanes would blend 0 into J,
/// which changes no word. Returns how many lanes were left out, for the blend to
/// count. A block of lanes on neighbouring words (a stretch of a walk row where
/// every pixel is visible) is read as slices, so it runs as vectors; other blocks
/// lane by lane.
fn push_fragments(
    px: &PolyLanes,
    (visible, hil): (&[u32], &[u32]),
    w: u32,
    (pix, hil_out): (&mut Vec<u32>, &mut Vec<u32>),
) -> usize {
    const BLOCK: usize = 16;
    assert_eq!(visible.len(), hil.len(), "one H·I_l per visible lane");
    let lanes = px.x.len().min(px.y.len());
    let (x, y) = (&px.x[..lanes], &px.y[..lanes]);
    let at = |(&x, &y): (&i64, &i64)| y as u32 * w + x as u32;
    let mut zero = 0;
    for (block, h) in visible.chunks(BLOCK).zip(hil.chunks(BLOCK)) {
        if h.iter().fold(0, |any, &v| any | v) == 0 {
            zero += block.len();
            continue;
        }
        hil_out.extend_from_slice(h);
        let first = block[0] as usize;
        if rising_run(block) && first + block.len() <= lanes {
            let run = first..first + block.len();
            pix.extend(x[run.clone()].iter().zip(&y[run]).map(at));
        } else {
            // Clamped to the lanes (visible lanes always lie in them): no bounds check.
            let last = lanes.saturating_sub(1);
            pix.extend(block.iter().map(|&i| {
                let i = (i as usize).min(last);
                at((&x[i], &y[i]))
            }));
        }
    }
    zero
}

/// The sub-plane at eye distance `uj` set up as one full-screen parallelogram: its
/// light coordinates are affine (the sub-plane is parallel to the screen), so one walk
/// covers the `w` × `h` screen. Only attributes 4..=7 (s, t, r, q) carry values.
fn subplane_setup(
    ctx: &LightCtx,
    (w, h): (u32, u32),
    uj: f64,
    c_int: &mut Counters,
) -> Result<PolySetup, ConfigError> {
    let u = ctx.units;
    let corners = [(0.0, 0.0), (w as f64, 0.0), (w as f64, h as f64)];
    let hv = corners.map(|(x, y)| {
        let pt = ctx.cam.point_at(x, y, uj);
        let la = ctx.light_attrs(pt);
        HostVertex {
            x,
            y,
            attrs: host_attrs([0.0, 0.0, 0.0, 0.0, la[0], la[1], la[2], la[3]]),
        }
    });
    let q = quantise(&u.interp, &hv, c_int)?;
    u.interp.setup_parallelogram(&q, c_int)
}

/// A sub-plane's record, started: one primitive (the parallelogram) walking the whole
/// `w` × `h` screen, room reserved for at most one fragment per pixel (of the sampled
/// units, about one pixel in `every`) and its H·I_l texels.
fn subplane_rec(ctx: &LightCtx, bands: Option<SampleBands>, (w, h): (u32, u32)) -> Rec {
    let mut r = Rec::sampled(bands);
    let px = ((w * h) / bands.map_or(1, |b| b.every.max(1))) as usize;
    r.xy.reserve(px);
    r.texels
        .reserve(px * ctx.hil_runs(&[], &[]).iter().map(|r| r.1).sum::<usize>());
    r.prim((w * h) as u64);
    r
}

/// An interval's sub-planes' H·I_l ([`subplanes_hil`]) merged in sub-plane order and
/// blended with their weights into a zeroed J buffer (one PassStats per sub-plane),
/// their lists handed back to `pool`. Returns the J buffer.
fn subplanes_into_j(
    ctx: &LightCtx,
    p: &Prepared,
    hils: Vec<Result<SubPlaneHil, ConfigError>>,
    pool: &WordPool,
    ctr: &mut BTreeMap<String, Counters>,
    log: &mut PassLog,
) -> Result<Vec<u32>, ConfigError> {
    let u = ctx.units;
    let sc = &p.scene;
    let cfg = sc.shafts;
    let (w, h) = (sc.image.width, sc.image.height);
    let m = cfg.subplanes as usize;
    let mut jbuf = pool.zeroed((w * h) as usize);
    for (j, res) in hils.into_iter().enumerate() {
        let SubPlaneHil {
            pix,
            hil,
            zero,
            rows_in_order,
            counters,
            rec,
        } = res?;
        for (k, c) in counters {
            counters_add(ctr, &k, c);
        }
        // Sub-plane j's blend weight: the driver splits full scale W into m parts
        // ⌊(j+1)W/m⌋ − ⌊jW/m⌋ (each round(W/m) or one off), so the weights sum to
        // exactly W and J of a fully lit interval is full scale; a single
        // round(W/m) would make ΣJ m·round(W/m)/W (258/255 at m = 6, 250/255 at
        // m = 25).
        let wmax = max_code(cfg.weight_bits) as u64;
        let weight = (((j as u64 + 1) * wmax / m as u64) - (j as u64 * wmax / m as u64)) as u32;
        let fragments = (&pix[..], &hil[..], zero);
        let span = blend_j(&u.j_blend, &mut jbuf, w, fragments, rows_in_order, weight);
        span.close("additive_blend (J buffer)", u.j_blend.timing(), ctr);
        let mut st = PassStats::new(
            PassKind::SubPlane,
            ctx.li,
            u32::from(ctx.lm_tex.is_some()) + u32::from(ctx.sstate.is_some()),
        );
        st.triangles = 1;
        st.walked = (w * h) as u64;
        st.fragments = (pix.len() + zero) as u64;
        pool.give(pix);
        pool.give(hil);
        let work = rec.map(|r| {
            let depth_tested = u.zbuf.is_some() && ctx.zstate.is_some();
            // The J buffer: an RGBA target at texel_bits per channel.
            let rop = record::blend_rop(cfg.texel_bits, depth_tested);
            r.into_work((w, h), ctx.hil_textures(), rop, depth_tested)
        });
        log.push(ctr, st, work)?;
    }
    Ok(jbuf)
}

/// Rows of the J buffer one thread blends at a time.
const J_BAND_ROWS: usize = 16;

/// One sub-plane's H·I_l (`hil` at pixels `pix`, y·w + x, and `zero` lanes of 0 left
/// out of the lists) blended with `weight` into the J buffer: one span of the
/// J-buffer blend. A parallelogram's walk covers each
/// pixel once and goes down the rows, so bands of rows are disjoint runs of `pix`,
/// blended in parallel, each in place (each reads what the span driver read; the
/// counters are sums, the same in any order). `rows_in_order`: the rows of `pix` never
/// go up (found by the walk, on its thread; else the whole buffer in one part).
fn blend_j(
    u: &Blend,
    jbuf: &mut [u32],
    w: u32,
    (pix, hil, zero): (&[u32], &[u32], usize),
    rows_in_order: bool,
    weight: u32,
) -> UnitSpan {
    let band = J_BAND_ROWS * w as usize;
    // The plane's weight is the blend's constant alpha (CONSTANT_ALPHA, ONE), set per draw.
    let u = &u.with_weight(weight);
    // In lanes, each J value read, blended and written back in place
    // (`blend_lanes_at`: the batch kernel on [H·I_l, 0, 0, 0] over [J, 0, 0, 0]; the
    // walk covers each pixel once, so each reads J as the span driver read it). Its
    // contribution table built once for every band.
    let lanes = u.lanes_at();
    let blend = |base: usize, jb: &mut [u32], pix: &[u32], hil: &[u32]| {
        let mut span = UnitSpan::default();
        span.feed_blend_lanes(&lanes, hil, (pix, base), jb);
        span
    };
    let mut span = if rows_in_order {
        blend_bands(jbuf, band, (pix, hil), blend)
    } else {
        blend(0, jbuf, pix, hil)
    };
    span.feed_blend_zero_lanes(u, zero);
    span
}

/// [`blend_j`]'s lists blended band by band (`band` words of J each) in parallel:
/// each band takes the run of `pix` that falls in it (the rows never go up) and
/// `blend(base, band's words, pix, hil)` returns its span; the spans merged.
fn blend_bands(
    jbuf: &mut [u32],
    band: usize,
    (pix, hil): (&[u32], &[u32]),
    blend: impl Fn(usize, &mut [u32], &[u32], &[u32]) -> UnitSpan + Sync,
) -> UnitSpan {
    let parts: Vec<UnitSpan> = jbuf
        .par_chunks_mut(band)
        .enumerate()
        .map(|(b, jb)| {
            let base = b * band;
            let lo = pix.partition_point(|&p| (p as usize) < base);
            let hi = pix.partition_point(|&p| (p as usize) < base + jb.len());
            blend(base, jb, &pix[lo..hi], &hil[lo..hi])
        })
        .collect();
    let mut span = UnitSpan::default();
    for p in &parts {
        span.merge(p);
    }
    span
}

/// Fragments per blend chunk.
const BLEND_CHUNK: usize = 4096;

/// Plane i at eye distance r: a cols × rows mesh whose vertices carry α, s, t, light
/// coordinates and the vertex colour S·Δt/Δr (= S·t/r: Δt grows off-axis); each cell
/// drawn and shaded in parallel, then blended in cell order. `beside` (work that
/// neither reads nor writes the framebuffer) runs on the pool beside the blend; its
/// result is returned.
#[allow(clippy::too_many_arguments)]
fn plane<T: Send>(
    ctx: &LightCtx,
    p: &Prepared,
    zwords: Option<DepthWords>,
    tables: &GTables,
    (i, r, dr): (usize, f64, f64),
    jtex: Option<&TextureSampler>,
    fb: &mut Framebuffer,
    (frags, scratch): (&mut Vec<PlaneFrag>, &mut BlendScratch),
    ctr: &mut BTreeMap<String, Counters>,
    log: &mut PassLog,
    beside: impl FnOnce() -> T + Send,
) -> Result<T, ConfigError> {
    let u = ctx.units;
    let sc = &p.scene;
    let cfg = sc.shafts;
    let (w, h) = (sc.image.width, sc.image.height);
    let (color_codes, intensity) = light_color_codes(ctx.light, ctx.tex_max);
    let mesh = PlaneMesh::new(ctx, p, tables, r, dr, intensity);
    // The plane is parallel to the screen: one window depth for all its fragments,
    // that of the screen's centre.
    let plane_z = ctx
        .cam
        .project(ctx.cam.point_at(w as f64 * 0.5, h as f64 * 0.5, r))
        .map_or(1.0, |v| v.2);
    let pc = PlaneCtx {
        ctx,
        zwords,
        jtex,
        zword: unit_depth_word(plane_z, ZBUF_BITS),
        color_codes,
        coord_shift: ATTR_FRAC - cfg.coord_frac_bits,
        record: log.records(i),
        bands: log.bands,
    };
    let drawn = draw_cells(&pc, &mesh, (w, h));
    let (cell_frags, spans, rec) = join_cells(&pc, drawn)?;
    let walked = spans.interp.pixels_in;
    spans.close(ctx, jtex, ctr);
    // The cells' fragments joined in cell order on the pool, beside `beside`, not
    // between two parallel sections.
    let blend = || {
        frags.clear();
        for f in &cell_frags {
            frags.extend_from_slice(f);
        }
        blend_plane(&u.blend, fb, frags, ctr, scratch)
    };
    let ((), t) = rayon::join(blend, beside);
    let mut st = PassStats::new(PassKind::Plane, ctx.li, plane_textures(ctx, &cfg));
    st.triangles = 2 * (cfg.mesh[0] * cfg.mesh[1]) as u64;
    st.walked = walked;
    st.fragments = frags.len() as u64;
    let work = rec.map(|r| plane_work(ctx, &cfg, jtex, r, (w, h)));
    log.push(ctr, st, work)?;
    Ok(t)
}

/// Plane i's mesh as the host computes its vertices (f64): the plane's eye distance,
/// the light's position, the per-plane scale S and the tables' ranges.
struct PlaneMesh<'a> {
    ctx: &'a LightCtx<'a>,
    tables: &'a GTables,
    /// The framebuffer's width and height (the mesh spans the screen).
    viewport: (u32, u32),
    /// Cells across and down (`shafts.mesh`).
    cells: [u32; 2],
    /// Eye distance of the plane.
    r: f64,
    lpos: Vec3,
    /// Per-plane scale S (fraction of full scale).
    s_plane: f64,
    plane_step: PlaneStep,
    /// The F table's texels and the h table's texels across and down, as f64.
    nf: f64,
    hw: f64,
    hh: f64,
}

impl<'a> PlaneMesh<'a> {
    fn new(
        ctx: &'a LightCtx<'a>,
        p: &Prepared,
        tables: &'a GTables,
        r: f64,
        dr: f64,
        intensity: f64,
    ) -> Self {
        let sc = &p.scene;
        let cfg = sc.shafts;
        let [hw, hh] = cfg.h_texels.map(|v| v as f64);
        PlaneMesh {
            ctx,
            tables,
            viewport: (sc.image.width, sc.image.height),
            cells: cfg.mesh,
            r,
            lpos: vec3(ctx.light.position),
            // S = F_max · h_ref · I · Δr · exposure / 255.
            s_plane: tables.f_max * tables.h_ref * intensity * dr * p.exposure / 255.0,
            plane_step: cfg.plane_step,
            nf: cfg.f_texels as f64,
            hw,
            hh,
        }
    }

    /// Mesh vertex (k, l): its screen position and attributes α, s, t (in texels of
    /// the F and h tables), the vertex colour and the light coordinates.
    fn vertex(&self, k: u32, l: u32) -> HostVertex {
        let (ctx, tables, r) = (self.ctx, self.tables, self.r);
        let ((w, h), [cols, rows]) = (self.viewport, self.cells);
        let (x, y) = (
            k as f64 * w as f64 / cols as f64,
            l as f64 * h as f64 / rows as f64,
        );
        let pt = ctx.cam.point_at(x, y, r);
        let t = (pt - ctx.cam.eye).length();
        let to_l = self.lpos - pt;
        let s = to_l.length();
        let view = (pt - ctx.cam.eye).normalized();
        let cos_a = if s > 0.0 {
            (to_l * (1.0 / s)).dot(view).clamp(-1.0, 1.0)
        } else {
            1.0
        };
        let alpha = cos_a.acos();
        let la = ctx.light_attrs(pt);
        HostVertex {
            x,
            y,
            attrs: host_attrs([
                alpha / std::f64::consts::PI * self.nf,
                s / tables.s_max * self.hw,
                t / tables.t_max * self.hh,
                match self.plane_step {
                    PlaneStep::AlongRay => self.s_plane * t / r,
                    // `shafts.plane_step = "plane_spacing"`: Δt = Δr on every ray.
                    PlaneStep::PlaneSpacing => self.s_plane,
                },
                la[0],
                la[1],
                la[2],
                la[3],
            ]),
        }
    }
}

/// Every mesh cell of the plane drawn and shaded ([`cell`]) in parallel, in cell
/// order (row by row).
fn draw_cells(
    pc: &PlaneCtx,
    mesh: &PlaneMesh,
    (w, h): (u32, u32),
) -> Vec<Result<DrawnCell, ConfigError>> {
    let [cols, rows] = mesh.cells;
    let cells: Vec<(u32, u32)> = (0..rows)
        .flat_map(|l| (0..cols).map(move |k| (k, l)))
        .collect();
    // With sub-planes J comes from the J texture: no one reads the light attributes.
    // The depth test, the shading and the record read covered words alone.
    let unread = if pc.jtex.is_some() { 0xf0 } else { 0 };
    // Each worker's scratch buffers reused from cell to cell (every one is cleared
    // before it is read, as from chunk to chunk within a cell).
    let scratch = || (PlaneBuffers::default(), WalkBuffers::covered(unread));
    cells
        .par_iter()
        .map_init(scratch, |(b, wb), &(k, l)| {
            let q = [
                mesh.vertex(k, l),
                mesh.vertex(k + 1, l),
                mesh.vertex(k + 1, l + 1),
                mesh.vertex(k, l + 1),
            ];
            cell(pc, &q, (w, h), (b, wb))
        })
        .collect()
}

/// The drawn cells joined in cell order (the order their fragments blend in): each
/// cell's fragments, the plane's spans, and when recording the cells' records joined
/// into one. The first cell's error in cell order is returned.
#[allow(clippy::type_complexity)]
fn join_cells(
    pc: &PlaneCtx,
    drawn: Vec<Result<DrawnCell, ConfigError>>,
) -> Result<(Vec<Vec<PlaneFrag>>, PlaneSpans, Option<Rec>), ConfigError> {
    let mut spans = PlaneSpans::default();
    let mut cell_frags = Vec::with_capacity(drawn.len());
    let mut rec = pc.record.then(|| {
        // Sized once for every cell's record (no growing and copying on the way).
        let mut all = Rec::sampled(pc.bands);
        let cells = drawn.iter().filter_map(|d| d.as_ref().ok()?.2.as_ref());
        all.reserve_for(cells);
        all
    });
    for d in drawn {
        let (f, s, r) = d?;
        cell_frags.push(f);
        spans.merge(&s);
        if let (Some(all), Some(r)) = (rec.as_mut(), r) {
            all.append(r);
        }
    }
    Ok((cell_frags, spans, rec))
}

/// Textures a plane fragment reads: F and h, then J (m > 1) or the light map and the
/// shadow map it has (m = 1).
fn plane_textures(ctx: &LightCtx, cfg: &ShaftsConfig) -> u32 {
    let m = cfg.subplanes as usize;
    2 + if m > 1 {
        1
    } else {
        u32::from(ctx.lm_tex.is_some()) + u32::from(ctx.sstate.is_some())
    }
}

/// A plane's record as the clocked chip's work: its textures (F, h, then J or H·I_l's)
/// and the framebuffer's ROP.
fn plane_work(
    ctx: &LightCtx,
    cfg: &ShaftsConfig,
    jtex: Option<&TextureSampler>,
    r: Rec,
    (w, h): (u32, u32),
) -> PassWork {
    let u = ctx.units;
    let depth_tested = u.zbuf.is_some() && ctx.zstate.is_some();
    let mut tex = vec![
        record::texture("texture_sampler (F)", &u.f_tex),
        record::texture("texture_sampler (h)", &u.h_tex),
    ];
    match jtex {
        Some(t) => tex.push(record::texture("texture_sampler (J)", t)),
        None => tex.extend(ctx.hil_textures()),
    }
    r.into_work(
        (w, h),
        tex,
        record::blend_rop(cfg.fb_bits, depth_tested),
        depth_tested,
    )
}

/// Light colour as texel codes (normalised by its largest component, which goes
/// into the intensity).
fn light_color_codes(l: &crate::scene::format::Light, tex_max: u32) -> ([u32; 3], f64) {
    let m = l.color.iter().cloned().fold(0.0, f64::max);
    if m <= 0.0 {
        return ([0; 3], 0.0);
    }
    (
        l.color
            .map(|c| tables::unorm_from_unit(c / m, tex_max.trailing_ones())),
        l.intensity * m,
    )
}

/// One mesh cell drawn: its shaded fragments, its units' spans and, when recording,
/// what it did.
type DrawnCell = (Vec<PlaneFrag>, PlaneSpans, Option<Rec>);

/// One mesh cell (a GL quad: two triangles) walked, depth-tested and shaded, on the
/// worker's scratch buffers `b` and `wb`.
fn cell(
    pc: &PlaneCtx,
    q: &[HostVertex; 4],
    (w, h): (u32, u32),
    (b, wb): (&mut PlaneBuffers, &mut WalkBuffers),
) -> Result<DrawnCell, ConfigError> {
    let u = pc.ctx.units;
    let mut spans = PlaneSpans::default();
    let mut out = Vec::new();
    let mut c_int = Counters::default();
    let qv = quantise(&u.interp, q, &mut c_int)?;
    let mut rec = pc.record.then(|| Rec::sampled(pc.bands));
    // A triangle's walked pixels: the interpolator's pixels since the previous one
    // (the first takes the quad's set-up's).
    let mut walked_before = 0;
    for s in u.interp.setup_quad(&qv, &mut c_int) {
        if let Some(r) = rec.as_mut() {
            r.prim(0);
        }
        walk_rows_lanes(&u.interp, &s, &mut c_int, wb, |px| {
            shade_chunk(pc, px, (w, h), &mut spans, b, &mut out, rec.as_mut())
        });
        if let Some(r) = rec.as_mut() {
            r.walked(c_int.pixels_in - walked_before);
            walked_before = c_int.pixels_in;
        }
    }
    spans.interp = c_int;
    Ok((out, spans, rec))
}

/// One chunk of a plane's walk: its fragments depth-tested, F(α), h(s, t) and J
/// sampled in lanes, recorded when recording, and their product
/// ([`modulate_chain`]) into `out`.
fn shade_chunk(
    pc: &PlaneCtx,
    px: &PolyLanes,
    viewport: (u32, u32),
    sp: &mut PlaneSpans,
    b: &mut PlaneBuffers,
    out: &mut Vec<PlaneFrag>,
    rec: Option<&mut Rec>,
) {
    pc.ctx.visible_flat(
        px,
        viewport,
        pc.zword,
        pc.zwords,
        &mut sp.zbuf,
        &mut b.chunk,
    );
    sample_f_h(pc, px, sp, b);
    sample_j(pc, px, sp, b);
    if let Some(r) = rec {
        record_chunk(pc, px, viewport, b, r);
    }
    modulate_chain(pc, px, sp, b, out);
}

/// F(α) and h(s, t) of the chunk's visible fragments in lanes: coordinate words
/// (attributes 0, 1 and 2 shifted to `coord_frac_bits`) in `b.f_s`, `b.h_s`,
/// `b.h_t`, one code per fragment out in `b.f_o`, `b.h_o`.
fn sample_f_h(pc: &PlaneCtx, px: &PolyLanes, sp: &mut PlaneSpans, b: &mut PlaneBuffers) {
    let u = pc.ctx.units;
    let vis = &b.chunk.visible;
    let sh = pc.coord_shift;
    let [alpha, hs, ht] = [&px.attrs[0], &px.attrs[1], &px.attrs[2]];
    b.f_s.clear();
    b.f_s
        .extend(vis.iter().map(|&i| (alpha[i as usize] >> sh) as i32));
    b.h_s.clear();
    b.h_s
        .extend(vis.iter().map(|&i| (hs[i as usize] >> sh) as i32));
    b.h_t.clear();
    b.h_t
        .extend(vis.iter().map(|&i| (ht[i as usize] >> sh) as i32));
    sp.f.feed_sampler_lanes(&u.f_tex, &b.f_s, &[], &mut b.f_o, &mut b.f_in, &mut b.f_out);
    sp.h.feed_sampler_lanes(
        &u.h_tex,
        &b.h_s,
        &b.h_t,
        &mut b.h_o,
        &mut b.h_in,
        &mut b.h_out,
    );
}

/// J of the chunk's visible fragments into `b.m_a`: the sub-plane average from the J
/// texture at the pixel centres (m > 1) or H·I_l on the plane itself (m = 1).
fn sample_j(pc: &PlaneCtx, px: &PolyLanes, sp: &mut PlaneSpans, b: &mut PlaneBuffers) {
    let vis = &b.chunk.visible;
    match pc.jtex {
        Some(t) => {
            let fr = t.coord_frac_bits();
            let centre = |c: i64| ((c as i32) << fr) + (1 << fr >> 1);
            b.j_s.clear();
            b.j_s.extend(vis.iter().map(|&i| centre(px.x[i as usize])));
            b.j_t.clear();
            b.j_t.extend(vis.iter().map(|&i| centre(px.y[i as usize])));
            sp.j.feed_sampler_lanes(t, &b.j_s, &b.j_t, &mut b.m_a, &mut b.j_in, &mut b.j_out);
        }
        None => {
            b.chunk.cut_outside_square = !pc.record;
            pc.ctx.h_il(px, LIGHT_ATTRS, &mut sp.hil, &mut b.chunk);
            b.m_a.clear();
            b.m_a.extend_from_slice(&b.chunk.hil);
        }
    }
}

/// The per-fragment product J · S · F · colour · h of one chunk, one 8-bit modulate at
/// a time, largest factors first: each modulate rounds to a whole code, so an
/// intermediate that has shrunk to a few codes carries a large relative error (a 1
/// stays 1 under any factor ≥ 128/255). J (≤ full scale in the light), the plane
/// scale S·t/r (near full scale by the choice of h_ref) and F (near full scale by the
/// choice of F_ref) keep the product large; h, which spans the 1/s² range and is a
/// few codes far from the light, comes last, so only the final rounding acts on the
/// small value (docs/shafts.md).
fn modulate_chain(
    pc: &PlaneCtx,
    px: &PolyLanes,
    sp: &mut PlaneSpans,
    b: &mut PlaneBuffers,
    out: &mut Vec<PlaneFrag>,
) {
    let ctx = pc.ctx;
    let vis = &b.chunk.visible;
    let md = &ctx.units.modulate;
    let (s_attr, tex_max) = (&px.attrs[3], ctx.tex_max);
    // The vertex colour S·t/r of each fragment as a code.
    b.m_s.clear();
    b.m_s
        .extend(vis.iter().map(|&i| attr_unorm(s_attr[i as usize], tex_max)));
    // J · S, then · F
    sp.modulate[0].feed_modulate(md, &b.m_a, Operand::Lanes(&b.m_s), &mut b.m_b);
    sp.modulate[1].feed_modulate(md, &b.m_b, Operand::Lanes(&b.f_o), &mut b.m_a);
    // · colour, then · h: one channel at a time (each modulate is the same datapath
    // on the same pair, in any order).
    for (c, &cc) in pc.color_codes.iter().enumerate() {
        let ch = &mut b.m_rgb[c];
        sp.modulate[2].feed_modulate(md, &b.m_a, Operand::Constant(cc), &mut b.m_b);
        sp.modulate[3].feed_modulate(md, &b.m_b, Operand::Lanes(&b.h_o), ch);
    }
    let [r, g, bl] = &b.m_rgb;
    out.extend(
        vis.iter()
            .zip(r.iter().zip(g).zip(bl))
            .map(|(&i, ((&r, &g), &bl))| {
                let i = i as usize;
                PlaneFrag {
                    x: px.x[i] as u32,
                    y: px.y[i] as u32,
                    rgb: [r, g, bl],
                }
            }),
    );
}

/// A plane chunk's fragments recorded with their texel runs: F, h, then J (m > 1) or
/// the light map and the shadow map (m = 1), each sampled on `b`'s coordinate lanes.
fn record_chunk(
    pc: &PlaneCtx,
    px: &PolyLanes,
    viewport: (u32, u32),
    b: &mut PlaneBuffers,
    r: &mut Rec,
) {
    let ctx = pc.ctx;
    let u = ctx.units;
    let depth_tested = u.zbuf.is_some() && ctx.zstate.is_some();
    let vis = &b.chunk.visible;
    let kept = record::chunk_fragments(r, px, vis, viewport, depth_tested);
    if kept.is_none() {
        // No fragment of the chunk in the sampled bands: no footprint to compute.
        return;
    }
    let [f, hh, j, s] = &mut b.fp;
    f.clear();
    u.f_tex.footprint_lanes(&b.f_s, &[], &[], f);
    hh.clear();
    u.h_tex.footprint_lanes(&b.h_s, &b.h_t, &[], hh);
    let mut runs: Vec<(&[u32], usize)> = vec![
        (f, u.f_tex.config().texels_per_sample() as usize),
        (hh, u.h_tex.config().texels_per_sample() as usize),
    ];
    match pc.jtex {
        Some(t) => {
            j.clear();
            t.footprint_lanes(&b.j_s, &b.j_t, &[], j);
            runs.push((j, t.config().texels_per_sample() as usize));
        }
        None => {
            ctx.hil_footprint(&b.chunk, j, s);
            runs.extend(ctx.hil_runs(j, s));
        }
    }
    record::interleave_kept(&runs, vis.len(), &kept, &mut r.texels);
}

/// The blend's inputs of `chunk`: each fragment's colour over its framebuffer pixel.
fn blend_inputs(fb: &Framebuffer, chunk: &[PlaneFrag], ins: &mut Vec<BlendIn>) {
    ins.clear();
    ins.extend(chunk.iter().map(|f| BlendIn {
        src: [f.rgb[0], f.rgb[1], f.rgb[2], 0],
        dst: fb.pixel(f.x, f.y),
    }));
}

/// Buffers of the framebuffer blend, reused from plane to plane: the pixels seen
/// ([`covers_once`]).
#[derive(Default)]
struct BlendScratch {
    seen: Vec<u64>,
}

/// Whether no two of the pixel indices `pixels` (y·w + x) of the `fb`-sized
/// framebuffer are the same (`seen` is the bitmap, cleared first).
pub(super) fn covers_once(
    fb: &Framebuffer,
    mut pixels: impl Iterator<Item = usize>,
    seen: &mut Vec<u64>,
) -> bool {
    seen.clear();
    seen.resize(((fb.width * fb.height) as usize).div_ceil(64), 0);
    pixels.all(|i| {
        let (word, bit) = (&mut seen[i / 64], 1u64 << (i % 64));
        let fresh = *word & bit == 0;
        *word |= bit;
        fresh
    })
}

/// The plane's fragments added into the framebuffer (one span). When no pixel has two
/// fragments (checked; a mesh covers each pixel once), each fragment is blended in
/// place: it reads its pixel as the span driver read it, since no earlier fragment
/// wrote there. Alpha stays 0: the frame's framebuffer starts black, every pass
/// writes alpha 0, and a source alpha of 0 adds 0. Otherwise a chunk at a time
/// through the batch kernel, each written back with alpha 0.
fn blend_plane(
    u: &Blend,
    fb: &mut Framebuffer,
    frags: &[PlaneFrag],
    ctr: &mut BTreeMap<String, Counters>,
    scratch: &mut BlendScratch,
) {
    let w = fb.width as usize;
    let at = |f: &PlaneFrag| f.y as usize * w + f.x as usize;
    if covers_once(fb, frags.iter().map(at), &mut scratch.seen) {
        // Each fragment read-modify-writes its own pixel: in place, in one pass.
        let (pixels, _) = fb.data.as_chunks_mut::<4>();
        let frag = |i: usize| {
            let f = &frags[i];
            let [r, g, b] = f.rgb;
            (at(f), [r, g, b, 0])
        };
        let mut span = UnitSpan::default();
        if span.feed_blend_in_place(u, frags.len(), frag, pixels) {
            span.close("additive_blend", u.timing(), ctr);
            return;
        }
    }
    let mut span = UnitSpan::default();
    let mut ins = Vec::with_capacity(BLEND_CHUNK);
    let mut outs = Vec::with_capacity(BLEND_CHUNK);
    for chunk in frags.chunks(BLEND_CHUNK) {
        blend_inputs(fb, chunk, &mut ins);
        span.feed(u, &mut (), &ins, &mut outs);
        for (f, o) in chunk.iter().zip(&outs) {
            fb.set(f.x, f.y, [o[0], o[1], o[2], 0]);
        }
    }
    span.close("additive_blend", u.timing(), ctr);
}
