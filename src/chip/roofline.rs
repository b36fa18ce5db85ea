//! The roofline time model shared by every pipeline: a GeForce2-GTS / GeForce3-class
//! prediction of a pass's time from its counters (fragments, texture lookups,
//! triangles, memory bytes): max(fill, memory) + set-up per pass, with an assumed
//! texture-cache hit rate. Every assumption is a named field of [`GpuModel`] and is
//! written down in docs/throughput.md. The clocked chip is checked against it.

use super::presets::GpuModel;
use super::work::{kind_name, PassStats};
use serde::Serialize;
use std::collections::BTreeMap;

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

/// Seconds of the shafts alone (planes, sub-planes, copies) and of the objects
/// (depth, shadow maps, object passes), as the paper splits Fig. 7's time.
pub fn split_objects_shafts(p: &Prediction) -> (f64, f64) {
    let get = |k: &str| p.by_kind.get(k).copied().unwrap_or(0.0);
    (
        get("object_depth") + get("shadow_map") + get("objects"),
        get("planes") + get("sub_planes") + get("copy_to_texture"),
    )
}
