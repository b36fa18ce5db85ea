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
    /// was read (each read its depth, `rop.depth_read_bytes`, and went no further; they
    /// are not in `frag_xy`). Empty when the pass has no depth test.
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
