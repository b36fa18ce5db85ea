//! What a pass did, in the form the chip's time models consume: the counters of one
//! pass (`PassStats`, counted by the units while the functional model drew it).

/// Kinds of pass, for the throughput model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
pub enum PassKind {
    ObjectDepth,
    ShadowMap,
    Objects,
    SubPlane,
    CopyToTexture,
    Plane,
    /// The glare ASIC's pass: bloom, halo and flare-line primitives added into the
    /// picture.
    Glare,
}

/// One pass's work, as counted by the units.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PassStats {
    pub kind: PassKind,
    pub light: usize,
    /// Pixels the rasteriser walked (including uncovered ones in bounding boxes).
    pub walked: u64,
    /// Fragments that reached the per-pixel units.
    pub fragments: u64,
    /// Texture lookups per fragment (for the TMU model).
    pub textures_per_fragment: u32,
    pub triangles: u64,
    /// Memory traffic the pass's units counted: texel fetches (no cache), framebuffer
    /// read-modify-write, and other bytes (copy-to-texture).
    pub texel_bytes: u64,
    pub fb_bytes: u64,
    pub other_bytes: u64,
    /// Depth-buffer tests (a 32-bit depth/stencil read each in an external z-buffer).
    pub depth_tests: u64,
}

pub fn kind_name(k: PassKind) -> &'static str {
    match k {
        PassKind::ObjectDepth => "object_depth",
        PassKind::ShadowMap => "shadow_map",
        PassKind::Objects => "objects",
        PassKind::SubPlane => "sub_planes",
        PassKind::CopyToTexture => "copy_to_texture",
        PassKind::Plane => "planes",
        PassKind::Glare => "glare",
    }
}

/// One texture a pass reads, as the texture unit and its cache see it.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct TextureWork {
    /// The sampler instance that reads it ("texture_sampler (F)", "light map", …).
    pub name: String,
    /// Texels along x, y, z (1 for unused dimensions).
    pub size: [u32; 3],
    /// Bytes one texel occupies in texture memory (its channels × texel bits, rounded up
    /// to bytes).
    pub texel_bytes: u32,
    /// Texels one lookup fetches (1 nearest, 2 linear 1D, 4 bilinear, 8 trilinear 3D):
    /// the length of each fragment's run in [`PassWork::texels`] for this texture.
    pub texels_per_lookup: u32,
}

/// What one pass of the functional model did, in the order it did it, for the clocked
/// chip: its primitives, the fragments each covered (in the functional walk's order,
/// which the clocked rasteriser regroups into 2×2 quads), and per fragment the texel
/// indices each of its samplers fetched. Recorded only when clocked timing is asked
/// for; recording never changes a pixel or a counter.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct PassWork {
    /// The pass's counters (as the roofline uses them).
    pub stats: Option<PassStats>,
    /// Framebuffer width and height in pixels (for framebuffer addresses).
    pub width: u32,
    pub height: u32,
    /// The textures the pass reads, in the order of each fragment's texel runs.
    pub textures: Vec<TextureWork>,
    /// Per primitive, in draw order: the index of its first fragment in `frag_xy` (the
    /// last primitive's fragments run to `frag_xy.len()`).
    pub prim_first_fragment: Vec<u32>,
    /// Per primitive: the pixels the rasteriser walked (covered or not).
    pub prim_walked: Vec<u32>,
    /// Per primitive: the covered fragments the depth test removed before any texture
    /// was read (they are not in `frag_xy`). The clocked chip charges them the
    /// rasteriser's walk only (with `RasterWalk::CoveredQuads`, ⌈killed ÷ pipes⌉
    /// clocks), not a depth read: a simplification, see docs/throughput.md. Empty when
    /// the pass has no depth test.
    pub prim_depth_killed: Vec<u32>,
    /// Each fragment's pixel (x, y), y down.
    pub frag_xy: Vec<[u16; 2]>,
    /// Per fragment, per texture in `textures` order, `texels_per_lookup` texel indices
    /// (x + w·(y + h·z), after the sampler's wrap or clamp), flattened.
    pub texels: Vec<u32>,
    /// Raster operations per fragment.
    pub rop: RopWork,
    /// Bytes read and written by a copy-to-texture (0 when the pass copies nothing).
    pub copy_read_bytes: u64,
    pub copy_write_bytes: u64,
    /// Present when the record holds only the fragments of a sample of the screen
    /// ([`SampleBands`]): `frag_xy` and `texels` hold the sampled fragments, while the
    /// per-primitive vectors (here and in the sample) count every primitive in full.
    pub sample: Option<SampleRecord>,
    /// The sampled mode left this pass unrecorded ([`PassSample`]): only `stats` is
    /// set, and the pass's time is scaled from the recorded passes of its kind.
    pub unrecorded: bool,
}

/// The sampled mode's passes. A frame's passes fall into kinds (a stratum: the same
/// [`PassKind`], light and textures per fragment, such as a light's 180 sub-planes);
/// of each kind's passes, numbered in draw order from 0, passes 0 and 1 and then one
/// in `every` are recorded and clocked, and the others' clocks are scaled from them in
/// proportion to their roofline time (a ratio estimator over the kind's passes).
/// `every` ≤ 1: every pass is recorded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct PassSample {
    pub every: u32,
}

impl PassSample {
    /// Every pass recorded.
    pub const ALL: PassSample = PassSample { every: 1 };

    /// Whether pass `n` of its kind (numbered from 0 in draw order) is recorded.
    pub fn records(&self, n: usize) -> bool {
        self.every <= 1 || n < 2 || n.is_multiple_of(self.every as usize)
    }
}

/// The screen sample of the sampled timing mode: units of `band_rows` pixel rows by
/// `block_cols` columns (0: the full width), unit (bx, by) numbered u = 13·by + bx and
/// sampled when u mod `every` = 0 (a diagonal spread over the screen, one unit in
/// `every`). Units of whole 8-row tile rows, several tiles wide, keep the
/// rasteriser's walk order (8 × 8 tiles in row order) and the texture caches' reuse
/// along a tile row as the full pass has them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct SampleBands {
    pub band_rows: u32,
    pub block_cols: u32,
    pub every: u32,
}

impl SampleBands {
    /// The number of the unit holding pixel (x, y).
    #[inline]
    pub fn unit(&self, x: u32, y: u32) -> u32 {
        // block_cols = 0: one block the full width.
        let bx = x.checked_div(self.block_cols).unwrap_or(0);
        (y / self.band_rows.max(1)) * 13 + bx
    }

    /// Whether pixel (x, y) is in a sampled unit.
    #[inline]
    pub fn keeps(&self, x: u32, y: u32) -> bool {
        self.unit(x, y).is_multiple_of(self.every.max(1))
    }

    /// The rank of a sampled unit among the sampled units (in unit order).
    #[inline]
    pub fn rank(&self, x: u32, y: u32) -> u32 {
        self.unit(x, y) / self.every.max(1)
    }
}

/// What a sampled record counts of every primitive, sampled or not (the scaling and
/// the per-primitive costs need it).
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct SampleRecord {
    pub bands: SampleBands,
    /// Per primitive: all its fragments (the sampled ones are in `frag_xy`).
    pub prim_fragments: Vec<u32>,
    /// Per primitive: the pixel of its first fragment in walk order (`u16::MAX` twice:
    /// no fragment). A primitive is set up in the sample when this pixel is sampled.
    pub prim_first_xy: Vec<[u16; 2]>,
    /// Per primitive: the index in `killed_xy` of its first depth-killed fragment in
    /// the sampled units (empty: their places are unknown, a record cut from a full
    /// one, and the killed fragments are shared in proportion to the visible ones).
    pub prim_first_killed: Vec<u32>,
    /// The pixels of the depth-killed fragments in the sampled units.
    pub killed_xy: Vec<[u16; 2]>,
}

impl SampleRecord {
    /// The pixels of primitive `p`'s depth-killed fragments in the sampled units.
    pub fn killed_of(&self, p: usize) -> &[[u16; 2]] {
        let end = self
            .prim_first_killed
            .get(p + 1)
            .map_or(self.killed_xy.len(), |&e| e as usize);
        &self.killed_xy[self.prim_first_killed[p] as usize..end]
    }
}

/// What the ROP does with each fragment of a pass.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct RopWork {
    /// Bytes of depth/stencil read per fragment (0: no depth test).
    pub depth_read_bytes: u32,
    /// Bytes of depth written per fragment that passes (0: no depth write).
    pub depth_write_bytes: u32,
    /// Colour bytes read per fragment (blending reads the destination; 0: no read).
    pub colour_read_bytes: u32,
    /// Colour bytes written per fragment.
    pub colour_write_bytes: u32,
}

impl PassWork {
    /// Fragments recorded.
    pub fn fragments(&self) -> usize {
        self.frag_xy.len()
    }

    /// Texel indices one fragment carries (the sum over textures).
    pub fn texels_per_fragment(&self) -> usize {
        self.textures
            .iter()
            .map(|t| t.texels_per_lookup as usize)
            .sum()
    }

    /// Fragments the depth test removed (see `prim_depth_killed`).
    pub fn depth_killed(&self) -> u64 {
        self.prim_depth_killed.iter().map(|&k| k as u64).sum()
    }

    /// Bytes the recorded vectors hold (their capacities): what recording costs in
    /// memory while the pass is clocked.
    pub fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        self.prim_first_fragment.capacity() * size_of::<u32>()
            + self.prim_walked.capacity() * size_of::<u32>()
            + self.prim_depth_killed.capacity() * size_of::<u32>()
            + self.frag_xy.capacity() * size_of::<[u16; 2]>()
            + self.texels.capacity() * size_of::<u32>()
            + self.textures.capacity() * size_of::<TextureWork>()
            + self.sample.as_ref().map_or(0, |s| {
                s.prim_fragments.capacity() * size_of::<u32>()
                    + s.prim_first_xy.capacity() * size_of::<[u16; 2]>()
                    + s.prim_first_killed.capacity() * size_of::<u32>()
                    + s.killed_xy.capacity() * size_of::<[u16; 2]>()
            })
    }

    /// The record of a sample of this (full) record: the fragments in `bands`' sampled
    /// rows, every primitive's counts kept (what the recorder in sampled mode makes).
    /// A record that is already sampled is returned as it is.
    pub fn sampled(&self, bands: SampleBands) -> PassWork {
        if self.sample.is_some() {
            return self.clone();
        }
        let per = self.texels_per_fragment();
        let nprims = self.prim_first_fragment.len();
        let mut s = SampleRecord {
            bands,
            prim_fragments: Vec::with_capacity(nprims),
            prim_first_xy: Vec::with_capacity(nprims),
            prim_first_killed: Vec::new(),
            killed_xy: Vec::new(),
        };
        let mut out = PassWork {
            stats: self.stats.clone(),
            textures: self.textures.clone(),
            prim_walked: self.prim_walked.clone(),
            prim_depth_killed: self.prim_depth_killed.clone(),
            prim_first_fragment: Vec::with_capacity(nprims),
            ..PassWork::default()
        };
        for p in 0..nprims {
            let r = self.prim_fragments(p);
            out.prim_first_fragment.push(out.frag_xy.len() as u32);
            s.prim_fragments.push(r.len() as u32);
            s.prim_first_xy
                .push(r.clone().next().map_or([u16::MAX; 2], |f| self.frag_xy[f]));
            for f in r.filter(|&f| {
                let [x, y] = self.frag_xy[f];
                bands.keeps(x as u32, y as u32)
            }) {
                out.frag_xy.push(self.frag_xy[f]);
                out.texels
                    .extend_from_slice(&self.texels[f * per..(f + 1) * per]);
            }
        }
        out.sample = Some(s);
        PassWork {
            width: self.width,
            height: self.height,
            rop: self.rop,
            copy_read_bytes: self.copy_read_bytes,
            copy_write_bytes: self.copy_write_bytes,
            ..out
        }
    }

    /// Every fragment of the pass, sampled or not.
    pub fn all_fragments(&self) -> u64 {
        match &self.sample {
            Some(s) => s.prim_fragments.iter().map(|&n| n as u64).sum(),
            None => self.frag_xy.len() as u64,
        }
    }

    /// The fragments of primitive `p` (a range into `frag_xy`).
    pub fn prim_fragments(&self, p: usize) -> std::ops::Range<usize> {
        let start = self.prim_first_fragment[p] as usize;
        let end = self
            .prim_first_fragment
            .get(p + 1)
            .map_or(self.frag_xy.len(), |&e| e as usize);
        start..end
    }
}
