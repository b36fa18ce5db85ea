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

// ---------------------------------------------------------------------------------
// The clocked chip's presets. Every value carries its source: NVIDIA's published
// figures and the GpuModel above (docs/throughput.md, docs/references.md), the
// extension specifications, the unit contract (a unit's `timing()` at its GeForce
// default configuration in rtl_model), or "assumed" — no datasheet, paper or patent
// gives it; the value is picked from the literature named beside it and is swept,
// never fitted to the timings the chip should predict.
// ---------------------------------------------------------------------------------

use super::config::{
    Arbitration, CacheConfig, ChipConfig, Layout, MemoryConfig, PipeStage, RasterWalk, Replacement,
    StageKind,
};
use rtl_model::units::final_combiner::FinalCombiner;
use rtl_model::units::polygon_interpolator::PolygonInterpolator;
use rtl_model::units::register_combiner::RegisterCombiner;
use rtl_model::units::texture_sampler::{TextureSampler, TextureSamplerConfig};
use rtl_model::{ConfigError, Timing, Unit};

/// The preset names `ChipConfig::preset` accepts.
pub const CHIP_PRESETS: [&str; 3] = ["geforce256", "geforce2-gts", "geforce3"];

fn stage(name: &str, kind: StageKind, t: Timing) -> PipeStage {
    PipeStage {
        name: name.to_string(),
        kind,
        latency: t.latency,
        ii: t.ii,
    }
}

/// The NV1x/NV2x pixel pipe: interpolator, texture units, `general` general combiner
/// stages chained, the final combiner — each stage's latency and II the unit's own
/// `timing()` at its GeForce default (the `general` stages chained in one pipelined
/// block: latency general × the stage's latency, II the stage's).
fn nv_pipe_stages(general: u32) -> Vec<PipeStage> {
    let interp = PolygonInterpolator::geforce().timing();
    // A 2 × 2 texture with the GeForce defaults (bilinear, 4 texels per clock): the
    // timing does not depend on the texture's size.
    let sampler = TextureSampler::new(TextureSamplerConfig::geforce_2d(2, 2), &[0; 4])
        .map(|s| s.timing())
        .unwrap_or(Timing { latency: 4, ii: 1 });
    let rc = RegisterCombiner::geforce().timing();
    let fc = FinalCombiner::geforce().timing();
    vec![
        stage("polygon_interpolator", StageKind::Plain, interp),
        stage("texture_sampler", StageKind::Texture, sampler),
        stage(
            "register_combiner",
            StageKind::Plain,
            Timing {
                latency: rc.latency * general,
                ii: rc.ii,
            },
        ),
        stage("final_combiner", StageKind::Plain, fc),
    ]
}

impl ChipConfig {
    /// GeForce2 GTS (NV15), the card of Dobashi et al.'s timings.
    pub fn geforce2_gts() -> Self {
        let m = GpuModel::geforce2_gts();
        ChipConfig {
            name: "geforce2-gts".to_string(),
            // 200 MHz: NVIDIA's published figures (GpuModel::geforce2_gts).
            clock_hz: m.clock_hz,
            // 4 pixel pipelines: NVIDIA's published figures.
            pipes: m.pipes,
            // 2 texture units per pipe: NVIDIA's published figures.
            tmus_per_pipe: m.tmus_per_pipe,
            // 2 textures per pass: GL_NV_register_combiners on NV1x combines two
            // textures (MAX_TEXTURE_UNITS_ARB 2).
            textures_per_pass: m.textures_per_pass,
            // 8 clocks per triangle: the roofline's figure (about 25 M triangles/s),
            // docs/throughput.md.
            setup_clocks_per_triangle: m.setup_clocks_per_triangle as u32,
            // 10 µs per pass at 200 MHz: the roofline's assumed figure.
            pass_overhead_clocks: (m.pass_overhead_s * m.clock_hz).round() as u32,
            // assumed: 64 quads between stages (and waiting in the texture unit and
            // the ROP): enough to cover the assumed memory latency (40 clocks) and a
            // full request queue (16) at one quad per clock, as Igehy et al. size
            // their prefetch FIFO to the latency.
            // assumed: the rasteriser walks the primitive's own quads inside the viewport
            // (edge-function traversal; McCormack and McNamara, Graphics Hardware 2000),
            // not the polygon interpolator's bounding box.
            raster_walk: RasterWalk::CoveredQuads,
            fifo_depth: 64,
            // The unit contract at GeForce defaults; 2 general combiners
            // (MAX_GENERAL_COMBINERS_NV on NV1x, GL_NV_register_combiners).
            pipe_stages: nv_pipe_stages(2),
            texture_cache: geforce_texture_cache(),
            // assumed: NV textures are stored swizzled (Morton order), as the open
            // drivers upload them; no NVIDIA document states the layout.
            texture_layout: Layout::Swizzled,
            // assumed: a linear colour and depth buffer.
            framebuffer_layout: Layout::Linear,
            memory: MemoryConfig {
                // 5.3 GB/s ÷ 200 MHz = 26.5 bytes per clock: NVIDIA's published figures.
                bytes_per_clock: m.bytes_per_second / m.clock_hz,
                ..geforce_memory()
            },
        }
    }

    /// GeForce 256 (NV10, DDR): 120 MHz, 4 pipes × 1 texture unit, 4.8 GB/s
    /// (GpuModel::geforce256); the rest as the GeForce2 GTS.
    pub fn geforce256() -> Self {
        let m = GpuModel::geforce256();
        let gts = ChipConfig::geforce2_gts();
        ChipConfig {
            name: "geforce256".to_string(),
            // 120 MHz: NVIDIA's published figures.
            clock_hz: m.clock_hz,
            // 1 texture unit per pipe (a second texture loops back): NVIDIA's
            // published figures.
            tmus_per_pipe: m.tmus_per_pipe,
            // 10 µs per pass at 120 MHz (assumed, as the GTS).
            pass_overhead_clocks: (m.pass_overhead_s * m.clock_hz).round() as u32,
            memory: MemoryConfig {
                // 4.8 GB/s ÷ 120 MHz = 40 bytes per clock: NVIDIA's published figures.
                bytes_per_clock: m.bytes_per_second / m.clock_hz,
                ..gts.memory
            },
            ..gts
        }
    }

    /// GeForce3 (NV20), the card of Okumura's thesis: 200 MHz, 4 pipes × 2 texture
    /// units, 4 textures per pass, 7.36 GB/s (GpuModel::geforce3), 8 general
    /// combiners.
    pub fn geforce3() -> Self {
        let m = GpuModel::geforce3();
        let gts = ChipConfig::geforce2_gts();
        ChipConfig {
            name: "geforce3".to_string(),
            // 200 MHz: NVIDIA's published figures.
            clock_hz: m.clock_hz,
            pipes: m.pipes,
            tmus_per_pipe: m.tmus_per_pipe,
            // 4 textures per pass (MAX_TEXTURE_UNITS_ARB 4 on NV20).
            textures_per_pass: m.textures_per_pass,
            pass_overhead_clocks: (m.pass_overhead_s * m.clock_hz).round() as u32,
            // 8 general combiners (MAX_GENERAL_COMBINERS_NV on NV20,
            // GL_NV_register_combiners2).
            pipe_stages: nv_pipe_stages(8),
            memory: MemoryConfig {
                // 7.36 GB/s ÷ 200 MHz = 36.8 bytes per clock (230 MHz DDR on a
                // 128-bit bus).
                bytes_per_clock: m.bytes_per_second / m.clock_hz,
                ..gts.memory
            },
            ..gts
        }
    }

    /// A GPU by preset name: "geforce256", "geforce2-gts", "geforce3" (the glare ASIC is
    /// built from a glare scene: `pipeline::glare::asic_preset`).
    pub fn preset(name: &str) -> Result<ChipConfig, ConfigError> {
        match name {
            "geforce256" => Ok(ChipConfig::geforce256()),
            "geforce2-gts" => Ok(ChipConfig::geforce2_gts()),
            "geforce3" => Ok(ChipConfig::geforce3()),
            "glare-asic" => Err(ConfigError::invalid(
                "chip",
                "the glare ASIC is built from a glare scene's [glare.hw] widths, clock and pipes \
                 (pipeline::glare::asic_preset), not from a name",
            )),
            other => Err(ConfigError::invalid(
                "chip",
                &format!(
                    "unknown chip preset '{other}' (allowed: {})",
                    CHIP_PRESETS.join(", ")
                ),
            )),
        }
    }
}

/// The texture cache of the NV presets. No size, line or associativity is published
/// for these chips: every field is assumed, from Hakura and Gupta, "The design and
/// analysis of a cache architecture for texture mapping" (ISCA 1997: 16–32 KB,
/// 2-way set-associative caches with 32–128-byte lines over blocked texture layouts
/// reach their working sets) and Igehy, Eldridge and Proudfoot, "Prefetching in a
/// texture cache architecture" (Graphics Hardware 1998: misses issued ahead while
/// fragments wait in a FIFO deep enough to cover the memory latency).
fn geforce_texture_cache() -> CacheConfig {
    CacheConfig {
        // assumed (Hakura and Gupta's range): 16 KiB.
        size_bytes: 16 * 1024,
        // assumed: 64-byte lines (a 4 × 4 block of 32-bit texels in Morton order).
        line_bytes: 64,
        // assumed (Hakura and Gupta): 2-way set-associative, LRU.
        ways: 2,
        replacement: Replacement::Lru,
        // assumed: one cache shared by the texture units.
        shared: true,
        // assumed (Igehy et al.'s prefetch depth covers the latency): 16 lines.
        misses_in_flight: 16,
    }
}

/// The memory controller of the NV presets (bandwidth set per chip).
fn geforce_memory() -> MemoryConfig {
    MemoryConfig {
        bytes_per_clock: 26.5,
        // assumed: 40 core clocks (200 ns at 200 MHz) from request to data.
        latency_clocks: 40,
        // assumed: 16 requests queued.
        queue_depth: 16,
        // assumed: round robin among texture, depth, colour and copy.
        arbitration: Arbitration::RoundRobin,
        // assumed: no DRAM page model (bandwidth and latency only); swept with pages.
        pages: None,
    }
}
