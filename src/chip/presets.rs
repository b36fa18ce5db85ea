//! The GPUs a frame's time is predicted for: every figure a named field with its source
//! (docs/throughput.md).

use serde::Serialize;

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
