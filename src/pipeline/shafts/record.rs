//! What a shafts pass did, recorded for the clocked chip ([`PassWork`]): its
//! primitives in draw order with the pixels each walked and the fragments the depth
//! test removed, its fragments in walk order, per fragment the texel indices each of
//! its samplers fetched ([`TextureSampler::footprint`]), and what the ROP does with
//! each fragment. Recording is asked for per frame
//! ([`super::frame::ShaftsFrame::record_work`]); off, nothing here runs. Recording
//! reads what the functional pass computed and never changes a pixel or a counter.
//!
//! In sampled mode ([`Rec::sampled`]) only the fragments of the sampled screen bands
//! are kept (their pixels and texels; a chunk with none computes no footprint), while
//! every primitive's walk, depth-killed and fragment counts are kept in full: the
//! record is what the sample needs, made at the cost of the sample.
//!
//! Parallel parts (mesh cells, sub-planes) record into their own [`Rec`], joined in
//! the fixed order the functional pass merges them (cell order, sub-plane order), so
//! the work is the same whatever the thread count.

use super::chunked::{ChunkBuffers, LightCtx};
use crate::chip::work::{PassWork, RopWork, SampleBands, SampleRecord, TextureWork};
use rtl_model::memory::bytes_for_bits;
use rtl_model::units::polygon_interpolator::PolyLanes;
use rtl_model::units::texture_sampler::TextureSampler;

/// Bytes of one camera depth-buffer or shadow-map access (an external 24-bit depth +
/// 8-bit stencil word, as the roofline counts a depth test and a shadow-map lookup:
/// docs/throughput.md).
pub(super) const DEPTH_BYTES: u32 = 4;

/// The primitives and fragments of a pass or of a part of one.
#[derive(Clone, Debug, Default)]
pub(super) struct Rec {
    pub prim_first: Vec<u32>,
    pub prim_walked: Vec<u32>,
    pub prim_killed: Vec<u32>,
    pub xy: Vec<[u16; 2]>,
    pub texels: Vec<u32>,
    /// Sampled mode: the bands whose fragments are kept.
    pub bands: Option<SampleBands>,
    /// Sampled mode, per primitive: all its fragments and its first fragment's pixel
    /// (`u16::MAX` twice: none).
    pub prim_all: Vec<u32>,
    pub prim_first_xy: Vec<[u16; 2]>,
    /// Sampled mode: per primitive, its first entry in `killed_xy`, the pixels of the
    /// depth-killed fragments in the sampled units.
    pub prim_first_killed: Vec<u32>,
    pub killed_xy: Vec<[u16; 2]>,
    /// Sampled mode with full-width bands: the last row asked about and whether it is
    /// sampled (fragments arrive row by row, so most asks are the row before's).
    last_row: Option<(u32, bool)>,
}

impl Rec {
    /// A record of every fragment (`None`) or of the fragments in `bands` only.
    pub fn sampled(bands: Option<SampleBands>) -> Self {
        Rec {
            bands,
            ..Rec::default()
        }
    }

    /// Start a primitive that walked `walked` pixels.
    pub fn prim(&mut self, walked: u64) {
        self.prim_first.push(self.xy.len() as u32);
        self.prim_walked.push(walked.min(u32::MAX as u64) as u32);
        self.prim_killed.push(0);
        if self.bands.is_some() {
            self.prim_all.push(0);
            self.prim_first_xy.push([u16::MAX; 2]);
            self.prim_first_killed.push(self.killed_xy.len() as u32);
        }
    }

    /// A fragment of the current primitive the depth test removed, at (x, y): its
    /// place, in sampled mode, when it falls in a sampled unit (the count is
    /// [`Self::killed`]'s).
    #[inline]
    pub fn killed_at(&mut self, x: i64, y: i64) {
        if let Some(b) = self.bands {
            if self.keeps(b, x as u32, y as u32) {
                self.killed_xy.push([x as u16, y as u16]);
            }
        }
    }

    /// Whether pixel (x, y) is in a sampled unit of `b` ([`SampleBands::keeps`]),
    /// remembered per row when the bands span the full width.
    #[inline]
    fn keeps(&mut self, b: SampleBands, x: u32, y: u32) -> bool {
        if b.block_cols != 0 {
            return b.keeps(x, y);
        }
        match self.last_row {
            Some((row, kept)) if row == y => kept,
            _ => {
                let kept = b.keeps(x, y);
                self.last_row = Some((y, kept));
                kept
            }
        }
    }

    /// Add `walked` pixels to the current primitive (a walk fed in parts).
    pub fn walked(&mut self, walked: u64) {
        if let Some(w) = self.prim_walked.last_mut() {
            *w = (*w as u64 + walked).min(u32::MAX as u64) as u32;
        }
    }

    /// Fragments of the current primitive the depth test removed.
    pub fn killed(&mut self, n: usize) {
        if let Some(k) = self.prim_killed.last_mut() {
            *k += n as u32;
        }
    }

    /// A fragment of the current primitive; whether it is kept (always, unless
    /// sampling and outside the sampled bands).
    #[inline]
    pub fn frag(&mut self, x: i64, y: i64) -> bool {
        if let Some(b) = self.bands {
            self.count_fragments(1, (x, y));
            if !self.keeps(b, x as u32, y as u32) {
                return false;
            }
        }
        self.xy.push([x as u16, y as u16]);
        true
    }

    /// `n` fragments of the current primitive (sampled mode), the first at `first`:
    /// its count of every fragment, and its first fragment's place if it had none.
    #[inline]
    fn count_fragments(&mut self, n: usize, first: (i64, i64)) {
        if let Some(all) = self.prim_all.last_mut() {
            if *all == 0 {
                if let Some(r) = self.prim_first_xy.last_mut() {
                    *r = [first.0 as u16, first.1 as u16];
                }
            }
            *all += n as u32;
        }
    }

    /// Room for `parts` appended after what this one holds.
    pub fn reserve_for<'x>(&mut self, parts: impl Iterator<Item = &'x Rec> + Clone) {
        let sum = |f: fn(&Rec) -> usize| parts.clone().map(f).sum::<usize>();
        self.prim_first.reserve(sum(|r| r.prim_first.len()));
        self.prim_walked.reserve(sum(|r| r.prim_walked.len()));
        self.prim_killed.reserve(sum(|r| r.prim_killed.len()));
        self.xy.reserve(sum(|r| r.xy.len()));
        self.texels.reserve(sum(|r| r.texels.len()));
        self.prim_all.reserve(sum(|r| r.prim_all.len()));
        self.prim_first_killed
            .reserve(sum(|r| r.prim_first_killed.len()));
        self.killed_xy.reserve(sum(|r| r.killed_xy.len()));
        self.prim_first_xy.reserve(sum(|r| r.prim_first_xy.len()));
    }

    /// `other` after this one (its primitives and fragments follow).
    pub fn append(&mut self, other: Rec) {
        let base = self.xy.len() as u32;
        self.prim_first
            .extend(other.prim_first.iter().map(|&f| f + base));
        self.prim_walked.extend(other.prim_walked);
        self.prim_killed.extend(other.prim_killed);
        self.xy.extend(other.xy);
        self.texels.extend(other.texels);
        self.prim_all.extend(other.prim_all);
        let kbase = self.killed_xy.len() as u32;
        self.prim_first_killed
            .extend(other.prim_first_killed.iter().map(|&k| k + kbase));
        self.killed_xy.extend(other.killed_xy);
        self.prim_first_xy.extend(other.prim_first_xy);
    }

    /// The pass's work (its stats are filled in when it is pushed).
    pub fn into_work(
        self,
        (width, height): (u32, u32),
        textures: Vec<TextureWork>,
        rop: RopWork,
        depth_tested: bool,
    ) -> PassWork {
        PassWork {
            stats: None,
            width,
            height,
            textures,
            prim_first_fragment: self.prim_first,
            prim_walked: self.prim_walked,
            prim_depth_killed: if depth_tested {
                self.prim_killed
            } else {
                Vec::new()
            },
            frag_xy: self.xy,
            texels: self.texels,
            rop,
            copy_read_bytes: 0,
            copy_write_bytes: 0,
            sample: self.bands.map(|bands| SampleRecord {
                bands,
                prim_fragments: self.prim_all,
                prim_first_xy: self.prim_first_xy,
                prim_first_killed: if depth_tested {
                    self.prim_first_killed
                } else {
                    Vec::new()
                },
                killed_xy: self.killed_xy,
            }),
            unrecorded: false,
        }
    }
}

/// Per fragment, the texture runs in order: run k of fragment i is
/// `runs[k].0[i·len_k .. (i+1)·len_k]` with `len_k = runs[k].1`; appended to `out`.
pub(super) fn interleave(runs: &[(&[u32], usize)], n: usize, out: &mut Vec<u32>) {
    out.reserve(n * runs.iter().map(|r| r.1).sum::<usize>());
    for i in 0..n {
        for &(t, len) in runs {
            out.extend_from_slice(&t[i * len..(i + 1) * len]);
        }
    }
}

/// [`interleave`] of the fragments `kept` (positions among the `n`) only: all of them
/// for [`Kept::All`], none for [`Kept::None`].
pub(super) fn interleave_kept(runs: &[(&[u32], usize)], n: usize, kept: &Kept, out: &mut Vec<u32>) {
    match kept {
        Kept::All => interleave(runs, n, out),
        Kept::None => {}
        Kept::Some(sel) => {
            for &i in sel {
                let i = i as usize;
                for &(t, len) in runs {
                    out.extend_from_slice(&t[i * len..(i + 1) * len]);
                }
            }
        }
    }
}

/// Which of a chunk's fragments a record kept: all (recording everything, or the
/// chunk inside the sampled bands), none (the chunk outside them: no footprint is
/// computed), or the positions of those kept.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) enum Kept {
    All,
    None,
    Some(Vec<u32>),
}

impl Kept {
    /// Whether no fragment was kept (the footprints need not be computed).
    pub fn is_none(&self) -> bool {
        *self == Kept::None
    }
}

/// A sampler as the clocked chip's texture unit sees it.
pub(super) fn texture(name: &str, t: &TextureSampler) -> TextureWork {
    TextureWork {
        name: name.to_string(),
        size: t.size(),
        texel_bytes: bytes_for_bits(t.texel_bits() * t.channels()) as u32,
        texels_per_lookup: t.config().texels_per_sample(),
    }
}

/// The shadow map as a texture: one depth word per lookup.
pub(super) fn shadow_texture(res: u32) -> TextureWork {
    TextureWork {
        name: "shadow_compare (shadow map)".to_string(),
        size: [res, res, 1],
        texel_bytes: DEPTH_BYTES,
        texels_per_lookup: 1,
    }
}

/// ROP work of a pass blending into an RGBA target of `channel_bits` per channel
/// (read-modify-write, as the blend unit counts it), with a depth test or not.
pub(super) fn blend_rop(channel_bits: u32, depth_tested: bool) -> RopWork {
    let px = bytes_for_bits(4 * channel_bits) as u32;
    RopWork {
        depth_read_bytes: if depth_tested { DEPTH_BYTES } else { 0 },
        depth_write_bytes: 0,
        colour_read_bytes: px,
        colour_write_bytes: px,
    }
}

/// ROP work of a depth-only pass (the camera depth pass, a shadow-map pass): the
/// depth unit's keep-the-nearer test and write of each fragment, no colour.
pub(super) fn depth_only_rop() -> RopWork {
    RopWork {
        depth_read_bytes: DEPTH_BYTES,
        depth_write_bytes: DEPTH_BYTES,
        colour_read_bytes: 0,
        colour_write_bytes: 0,
    }
}

impl LightCtx<'_> {
    /// The textures H·I_l reads (the light map, the shadow map), in the order
    /// [`Self::hil_footprint`] appends them.
    pub fn hil_textures(&self) -> Vec<TextureWork> {
        let mut v = Vec::new();
        if let Some(lm) = self.lm_tex {
            v.push(texture("texture_sampler (light map)", lm));
        }
        if let (Some(sh), Some(_)) = (&self.units.shadow, self.sstate) {
            v.push(shadow_texture(sh.width()));
        }
        v
    }

    /// The runs of [`Self::hil_footprint`]'s texels for [`interleave`], in
    /// [`Self::hil_textures`] order.
    pub fn hil_runs<'x>(&self, lm: &'x [u32], sm: &'x [u32]) -> Vec<(&'x [u32], usize)> {
        let mut v = Vec::new();
        if let Some(t) = self.lm_tex {
            v.push((lm, t.config().texels_per_sample() as usize));
        }
        if let (Some(_), Some(_)) = (&self.units.shadow, self.sstate) {
            v.push((sm, 1));
        }
        v
    }

    /// The texels H·I_l fetched for the fragments `b.visible` of the last
    /// [`Self::h_il`] on `b`: the light map's footprints into `lm`, the shadow map's
    /// texel per fragment into `sm` (a lookup outside the map, which reads no RAM,
    /// recorded at the nearest edge texel: the roofline counts every lookup's bytes).
    pub fn hil_footprint(&self, b: &ChunkBuffers, lm: &mut Vec<u32>, sm: &mut Vec<u32>) {
        lm.clear();
        sm.clear();
        let u = self.units;
        if let Some(t) = self.lm_tex {
            if b.pair_path {
                t.footprint_lanes(&b.tex_s, &b.tex_t, &[], lm);
            } else {
                for x in &b.tex_in {
                    t.footprint(x, lm);
                }
            }
        }
        if let (Some(sh), Some(_)) = (&u.shadow, self.sstate) {
            let res = sh.width() as i32;
            let at = |x: i32, y: i32| (y.clamp(0, res - 1) * res + x.clamp(0, res - 1)) as u32;
            if b.pair_path {
                let of = u.proj.out_format().frac_bits;
                let shift = of - sh.width().trailing_zeros().min(of);
                let pl = &b.proj_lanes;
                sm.extend(
                    pl.u.iter()
                        .zip(&pl.v)
                        .map(|(&pu, &pv)| at(pu >> shift, pv >> shift)),
                );
            } else {
                use rtl_model::units::shadow_compare::ShadowIn;
                sm.extend(b.shadow_in.iter().map(|s| match *s {
                    ShadowIn::Test { x, y, .. } => at(x, y),
                    _ => 0,
                }));
            }
        }
    }
}

/// The fragments `visible` of a chunk `px` into `rec` (their pixels), with the
/// fragments the depth test removed: the chunk's candidates (covered, inside the
/// `viewport`) less the visible ones, when `depth_tested`.
/// Returns which of them were kept ([`Kept`]).
pub(super) fn chunk_fragments(
    rec: &mut Rec,
    px: &PolyLanes,
    visible: &[u32],
    viewport: (u32, u32),
    depth_tested: bool,
) -> Kept {
    let before = rec.xy.len();
    let mut sel = Vec::new();
    let xy = |i: u32| (px.x[i as usize], px.y[i as usize]);
    match rec.bands {
        // Every fragment counted at once ([`Rec::frag`] one by one), the sampled rows'
        // kept.
        Some(b) if !visible.is_empty() => {
            rec.count_fragments(visible.len(), xy(visible[0]));
            for (k, &i) in visible.iter().enumerate() {
                let (x, y) = xy(i);
                if rec.keeps(b, x as u32, y as u32) {
                    rec.xy.push([x as u16, y as u16]);
                    sel.push(k as u32);
                }
            }
        }
        Some(_) => {}
        None => rec.xy.extend(visible.iter().map(|&i| {
            let (x, y) = xy(i);
            [x as u16, y as u16]
        })),
    }
    if depth_tested {
        let is_frag =
            |i: usize| crate::pipeline::raster::is_fragment_lane(px, i, viewport.0, viewport.1);
        let cand = (0..px.len()).filter(|&i| is_frag(i)).count();
        rec.killed(cand - visible.len());
        if rec.bands.is_some() && cand > visible.len() {
            // The killed fragments' places: the candidates not visible (`visible`
            // holds lane indices in increasing order).
            let mut v = visible.iter().peekable();
            for i in (0..px.len()).filter(|&i| is_frag(i)) {
                if v.peek().is_some_and(|&&j| j as usize == i) {
                    v.next();
                } else {
                    rec.killed_at(px.x[i], px.y[i]);
                }
            }
        }
    }
    let kept = rec.xy.len() - before;
    if kept == visible.len() {
        Kept::All
    } else if kept == 0 {
        Kept::None
    } else {
        Kept::Some(sel)
    }
}
