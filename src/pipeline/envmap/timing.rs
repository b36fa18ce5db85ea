//! Frame timing of the environment-map renderer (the thesis' Table 6): the
//! wall time of the bit-accurate model, and the time predicted for GeForce3-class
//! hardware from the renderer's counters ([`FrameInfo`]), in the style of the shafts'
//! throughput model (`crate::chip`, [`GpuModel::geforce3`]).
//!
//! # The model (every assumption a named constant or a `GpuModel` field)
//!
//! A frame is three passes; each takes the slower of its fill time and its memory
//! time, plus set-up and a fixed overhead per pass:
//! 1. **Clear** of the colour and depth buffers: memory only,
//!    w·h·([`FB_BYTES`] + `depth_bytes`) bytes written.
//! 2. **Object pass.** Every fragment the interpolator produced, before the depth test
//!    (no early-Z is modelled, and the draw order is unknown), is textured, depth-tested
//!    and written. That is an upper bound.
//!    - Fill: ⌈texels per fragment / (4 · TMUs)⌉ clocks per fragment, at least 1. A
//!      texture unit filters one bilinear (4-texel) sample per clock, and the 3D
//!      trilinear sample (8 texels) uses both of a pipe's units: 1 clock. The 2D slice
//!      (4 texels) also takes 1 clock. A roughness texture (per-pixel λ) adds its
//!      bilinear sample: 8 + 4 texels take 2 clocks (GeForce3 loops back for the
//!      3rd and 4th texture of a pass).
//!    - Memory: texels × [`TEXEL_BYTES`] × (1 − cache hit) for the map, roughness
//!      texels × [`ROUGHNESS_TEXEL_BYTES`] × (1 − cache hit), plus per fragment a depth
//!      read and write (2 · `depth_bytes`) and a colour write ([`FB_BYTES`]).
//!    - Set-up: triangles × `setup_clocks_per_triangle`.
//! 3. **Background** (the environment behind the object, a cube-map pass standing for
//!    the renderer's host lookup): per background pixel 1 clock, [`BACKGROUND_TEXELS`]
//!    texels (bilinear) and a colour write.
//!
//! The prediction is for the frame's GPU work only: the CPU's geometry and the
//! per-vertex λ are not included.

use serde::Serialize;

use super::render::FrameInfo;
use crate::chip::GpuModel;

/// Bytes per texel in video memory: RGB8 is stored as X8R8G8B8 on GeForce3.
pub const TEXEL_BYTES: u64 = 4;
/// Bytes per roughness texel (L8).
pub const ROUGHNESS_TEXEL_BYTES: u64 = 1;
/// Bytes per colour-buffer pixel (32-bit colour).
pub const FB_BYTES: u64 = 4;
/// Texels per background lookup (a bilinear cube-map sample).
pub const BACKGROUND_TEXELS: u64 = 4;

/// A frame's predicted time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct FramePrediction {
    pub seconds: f64,
    pub clear_seconds: f64,
    pub object_seconds: f64,
    pub background_seconds: f64,
    /// The object pass's fill and memory times (the larger one bounds it).
    pub object_fill_seconds: f64,
    pub object_memory_seconds: f64,
    /// Bytes the whole frame moves.
    pub bytes: f64,
}

impl FramePrediction {
    pub fn object_memory_bound(&self) -> bool {
        self.object_memory_seconds > self.object_fill_seconds
    }
}

/// Predict the frame `f` on `m` (see the module notes).
pub fn predict_frame(m: &GpuModel, f: &FrameInfo) -> FramePrediction {
    let pipes = m.pipes.max(1) as f64;
    let miss = (1.0 - m.texture_cache_hit).clamp(0.0, 1.0);
    let bw = m.bytes_per_second;
    let px = f.width as f64 * f.height as f64;

    let clear_bytes = px * (FB_BYTES + m.depth_bytes) as f64;
    let clear = clear_bytes / bw + m.pass_overhead_s;

    let frags = f.fragments as f64;
    let texels = f.texels_per_lookup as u64 + f.roughness_texels_per_lookup as u64;
    let clocks = texels.div_ceil(4 * m.tmus_per_pipe.max(1) as u64).max(1) as f64;
    let fill = frags * clocks / pipes / m.clock_hz;
    let obj_bytes = frags * f.texels_per_lookup as f64 * TEXEL_BYTES as f64 * miss
        + frags * f.roughness_texels_per_lookup as f64 * ROUGHNESS_TEXEL_BYTES as f64 * miss
        + frags * (2 * m.depth_bytes + FB_BYTES) as f64;
    let mem = obj_bytes / bw;
    let setup = f.triangles as f64 * m.setup_clocks_per_triangle / m.clock_hz;
    let object = fill.max(mem) + setup + m.pass_overhead_s;

    let bg = f.background_pixels as f64;
    let bg_bytes = bg * (BACKGROUND_TEXELS as f64 * TEXEL_BYTES as f64 * miss + FB_BYTES as f64);
    let background = (bg / pipes / m.clock_hz).max(bg_bytes / bw) + m.pass_overhead_s;

    FramePrediction {
        seconds: clear + object + background,
        clear_seconds: clear,
        object_seconds: object,
        background_seconds: background,
        object_fill_seconds: fill,
        object_memory_seconds: mem,
        bytes: clear_bytes + obj_bytes + bg_bytes,
    }
}

/// One row of `timing.csv`.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct TimingRow {
    pub object: String,
    pub width: u32,
    pub height: u32,
    pub fragments: u64,
    pub wall_seconds: f64,
    pub predicted_seconds_geforce3: f64,
}

impl TimingRow {
    pub const CSV_HEADER: &'static str =
        "object,width,height,fragments,wall_seconds,predicted_seconds_geforce3";

    pub fn to_csv(&self) -> String {
        format!(
            "{},{},{},{},{:.4},{:.6}",
            self.object,
            self.width,
            self.height,
            self.fragments,
            self.wall_seconds,
            self.predicted_seconds_geforce3
        )
    }
}
