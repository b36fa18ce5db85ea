//! The GPU time model shared by every pipeline: what a pass did (`PassStats`, counted by
//! the units) and a GeForce2-GTS / GeForce3-class prediction of its time from those
//! counters (fragments, texture lookups, triangles, memory bytes). Every assumption is a
//! named field here and is written down in docs/throughput.md. It lives beside the
//! frame, not inside one pipeline (the shafts pipeline re-exports it as
//! `shafts::throughput`).

use serde::Serialize;
use std::collections::BTreeMap;

/// Kinds of pass, for the throughput model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
pub enum PassKind {
    ObjectDepth,
    ShadowMap,
    Objects,
    SubPlane,
    CopyToTexture,
    Plane,
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

/// The hardware being predicted.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GpuModel {
    /// Core clock (GeForce2 GTS: 200 MHz).
    pub clock_hz: f64,
    /// Pixel pipelines (4).
    pub pipes: u32,
    /// Texture units per pipe (GeForce2 GTS: 2): a pass with t textures takes
    /// ⌈t / TMUs⌉ clocks per fragment.
    pub tmus_per_pipe: u32,
    /// Textures one hardware pass can combine (NV1x register combiners: 2): a fragment
    /// needing T textures is drawn in ⌈T/2⌉ hardware passes (the intermediate product
    /// kept in the framebuffer's destination alpha), each paying fill, framebuffer,
    /// depth, set-up and overhead.
    pub textures_per_pass: u32,
    /// Memory bandwidth, bytes/s (5.3 GB/s).
    pub bytes_per_second: f64,
    /// Fraction of texel fetch bytes the texture cache absorbs.
    pub texture_cache_hit: f64,
    /// Bytes per depth test in an external 32-bit depth/stencil buffer.
    pub depth_bytes: u64,
    /// Triangle set-up clocks per triangle.
    pub setup_clocks_per_triangle: f64,
    /// Fixed cost per pass (state change, pipeline flush), seconds.
    pub pass_overhead_s: f64,
}

impl GpuModel {
    /// GeForce2 GTS defaults (NVIDIA's published figures; docs/throughput.md).
    pub fn geforce2_gts() -> Self {
        GpuModel {
            clock_hz: 200e6,
            pipes: 4,
            tmus_per_pipe: 2,
            textures_per_pass: 2,
            bytes_per_second: 5.3e9,
            texture_cache_hit: 0.75,
            depth_bytes: 4,
            setup_clocks_per_triangle: 8.0,
            pass_overhead_s: 10e-6,
        }
    }
}

impl GpuModel {
    /// GeForce 256 (DDR), the paper's second card (0.19 s for Fig. 6(b) against the
    /// GTS's 0.17 s): 120 MHz, 4 pipes with one texture unit each (a second texture in
    /// the same pass loops back: two clocks), 4.8 GB/s; the rest as the GTS.
    pub fn geforce256() -> Self {
        GpuModel {
            clock_hz: 120e6,
            tmus_per_pipe: 1,
            bytes_per_second: 4.8e9,
            ..GpuModel::geforce2_gts()
        }
    }
}

impl GpuModel {
    /// GeForce3 (Okumura's thesis' card): 200 MHz, 4 pipes × 2
    /// texture units, 3D textures, 4 textures per pass, about 7.36 GB/s (230 MHz DDR on
    /// a 128-bit bus); the cache, depth, set-up and overhead as the GTS.
    pub fn geforce3() -> Self {
        GpuModel {
            clock_hz: 200e6,
            pipes: 4,
            tmus_per_pipe: 2,
            textures_per_pass: 4,
            bytes_per_second: 7.36e9,
            ..GpuModel::geforce2_gts()
        }
    }
}

/// Predicted time, per pass kind and in total.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Prediction {
    pub seconds: f64,
    /// Seconds by pass kind.
    pub by_kind: BTreeMap<String, f64>,
    /// Hardware passes bounded by memory rather than by the pipes.
    pub memory_bound_passes: u64,
    /// Hardware passes (a model pass needing more textures than one pass combines
    /// counts ⌈T/2⌉).
    pub passes: u64,
}

/// Hardware passes a pass of the model needs: ⌈T / textures per pass⌉, at least 1.
pub fn hardware_passes(m: &GpuModel, p: &PassStats) -> u32 {
    p.textures_per_fragment
        .div_ceil(m.textures_per_pass.max(1))
        .max(1)
}

/// Pipe clocks per fragment over all hardware passes: each pass takes its textures
/// (full passes of `textures_per_pass`, the remainder in the last) ⌈t / TMUs⌉ clocks,
/// at least one.
fn clocks_per_fragment(m: &GpuModel, p: &PassStats) -> u32 {
    let (tpp, tmus) = (m.textures_per_pass.max(1), m.tmus_per_pipe.max(1));
    let mut left = p.textures_per_fragment;
    let mut clocks = 0;
    for _ in 0..hardware_passes(m, p) {
        let t = left.min(tpp);
        left -= t;
        clocks += t.div_ceil(tmus).max(1);
    }
    clocks
}

/// Seconds of one pass of the model: the slower of the pipes (clocks per fragment
/// over its hardware passes) and the memory, plus set-up and overhead. Texel bytes are paid
/// once (each texture is fetched in one of the hardware passes); framebuffer and depth
/// traffic, fill, set-up and overhead once per hardware pass. Returns the seconds,
/// whether memory bounds it, and the number of hardware passes.
pub fn pass_seconds(m: &GpuModel, p: &PassStats) -> (f64, bool, u32) {
    let hw = hardware_passes(m, p);
    let k = hw as f64;
    let fill = p.fragments as f64 * clocks_per_fragment(m, p) as f64 / m.pipes as f64 / m.clock_hz;
    let bytes = p.texel_bytes as f64 * (1.0 - m.texture_cache_hit)
        + k * p.fb_bytes as f64
        + p.other_bytes as f64
        + k * (p.depth_tests * m.depth_bytes) as f64;
    let mem = bytes / m.bytes_per_second;
    let setup = k * p.triangles as f64 * m.setup_clocks_per_triangle / m.clock_hz;
    (
        fill.max(mem) + setup + k * m.pass_overhead_s,
        mem > fill,
        hw,
    )
}

/// Predict a frame.
pub fn predict(m: &GpuModel, passes: &[PassStats]) -> Prediction {
    let mut out = Prediction::default();
    for p in passes {
        let (s, mem_bound, hw) = pass_seconds(m, p);
        out.seconds += s;
        *out.by_kind
            .entry(kind_name(p.kind).to_string())
            .or_default() += s;
        out.memory_bound_passes += u64::from(mem_bound) * hw as u64;
        out.passes += hw as u64;
    }
    out
}

pub fn kind_name(k: PassKind) -> &'static str {
    match k {
        PassKind::ObjectDepth => "object_depth",
        PassKind::ShadowMap => "shadow_map",
        PassKind::Objects => "objects",
        PassKind::SubPlane => "sub_planes",
        PassKind::CopyToTexture => "copy_to_texture",
        PassKind::Plane => "planes",
    }
}

/// Seconds of the shafts alone (planes, sub-planes, copies) and of the objects
/// (depth, shadow maps, object passes), as the paper splits Fig. 7's time.
pub fn split_objects_shafts(p: &Prediction) -> (f64, f64) {
    let get = |k: &str| p.by_kind.get(k).copied().unwrap_or(0.0);
    (
        get("object_depth") + get("shadow_map") + get("objects"),
        get("planes") + get("sub_planes") + get("copy_to_texture"),
    )
}
