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
pub const CHIP_PRESETS: [&str; 4] = ["geforce256", "geforce2-gts", "geforce3", "glare-asic"];

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

    /// A chip by preset name: "geforce256", "geforce2-gts", "geforce3", "glare-asic".
    pub fn preset(name: &str) -> Result<ChipConfig, ConfigError> {
        match name {
            "geforce256" => Ok(ChipConfig::geforce256()),
            "geforce2-gts" => Ok(ChipConfig::geforce2_gts()),
            "geforce3" => Ok(ChipConfig::geforce3()),
            "glare-asic" => ChipConfig::glare_asic(),
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

// ---------------------------------------------------------------------------------
// The glare ASIC (Matsuda and Ikedo): a clocked chip of its own, not a GeForce.

// The names this block uses are imported inside its functions (or written out), so
// that it merges beside the GeForce presets' own imports.

/// RAM-table words the host writes into the glare ASIC per clock: the shape RAM's four
/// banks (or the falloff and ring RAMs) in parallel, one word each. Assumed (the paper
/// shows the RAMs, not their write port); the same rate as the glare throughput
/// formula (`pipeline::glare::throughput::predict`). The tables are on chip, so these
/// writes are no memory-controller traffic: a frame's clocked timing adds them per
/// primitive beside the clocked pass (docs/glare.md, "The clocked glare ASIC").
pub const GLARE_TABLE_WORDS_PER_CLOCK: u32 = 4;

/// Bandwidth of the framebuffer memory the glare is added into, bytes/s. Assumed: the
/// paper gives no memory figure; a 128-bit DDR interface at 300 MHz (9.6 GB/s) is the
/// class of memory beside a 300 MHz graphics part of its time. At 300 MHz it moves 32
/// bytes a clock, more than the 24 the combiner's read-modify-write of 4 RGB8 pixels
/// a clock needs, so the paper's fill rate is not memory bound by assumption; the
/// `glare-asic-throughput` reproduction sweeps it below that.
pub const GLARE_MEMORY_BYTES_PER_SECOND: f64 = 9.6e9;

impl super::config::ChipConfig {
    /// Matsuda and Ikedo's glare ASIC at the default `[glare.hw]` (300 MHz, 4 pipes:
    /// the paper's 1.2 Gpixel/s). [`Self::glare_asic_for`] gives it at a scene's
    /// widths, clock and pipes.
    pub fn glare_asic() -> Result<super::config::ChipConfig, rtl_model::ConfigError> {
        Self::glare_asic_for(&crate::scene::glare::GlareHw::default())
    }

    /// The glare ASIC at a scene's `[glare.hw]`: every stage's latency and initiation
    /// interval from the unit's own `timing()` at the widths the glare pass builds it
    /// with (`scene::limits`), each field's source beside it.
    pub fn glare_asic_for(
        hw: &crate::scene::glare::GlareHw,
    ) -> Result<super::config::ChipConfig, rtl_model::ConfigError> {
        use super::config::{
            Arbitration, CacheConfig, ChipConfig, Layout, MemoryConfig, PipeStage, Replacement,
            StageKind,
        };
        use crate::scene::limits;
        use rtl_model::units::bloom_flare_modulator::BloomFlareModulatorConfig;
        use rtl_model::units::halo_modulator::HaloModulatorConfig;
        use rtl_model::Unit;
        let lw = limits::lum_widths(hw);
        let ip = limits::glare_interpolator(hw.coord_frac_bits).build()?;
        let pvg = limits::glare_generator().build()?;
        let noise = limits::glare_noise(hw).build()?;
        let comb = limits::glare_combiner(hw).build()?;
        // The modulators' timing does not depend on their table contents: built empty.
        let (shape, fall) = (vec![0.0; lw.shape_len()], vec![0.0; lw.falloff_len()]);
        let bloom = BloomFlareModulatorConfig::from_widths(lw).build(&shape, &fall)?;
        let halo = HaloModulatorConfig::from_widths(lw).build(&shape, [&fall, &fall, &fall])?;
        let (ti, tb, th, tc) = (ip.timing(), bloom.timing(), halo.timing(), comb.timing());
        let plain = |name: &str, latency: u32, ii: u32| PipeStage {
            name: name.into(),
            kind: StageKind::Plain,
            latency,
            ii,
        };
        Ok(ChipConfig {
            name: "glare-asic".into(),
            // The paper gives the rate, 1.2 Gpixel/s, not the clock or the pipes: read
            // as 4 pipes × 300 MHz at one pixel a clock (`[glare.hw] clock_mhz`,
            // `pipes`; docs/glare.md, "Throughput and gates").
            clock_hz: hw.clock_mhz * 1e6,
            pipes: hw.pipes,
            // No texture units: the modulators' RAM tables are on chip (the paper's
            // Figs. 2 and 3), read in the pipe's own stages.
            tmus_per_pipe: 0,
            // The pass reads no texture: one hardware pass whatever this is (≥ 1 so
            // ⌈textures / textures_per_pass⌉ is defined).
            textures_per_pass: 1,
            // Per primitive, the polygon-variable generator (latency) then the
            // interpolator's set-up engine (its set-up clocks), one after the other
            // (the set-up engine is a sequenced datapath). The Gaussian noise
            // generator feeds a flare line's draws to the generator ahead of it, one
            // line per II (Box–Muller: 1 clock), so it bounds the set-up only if its
            // II were the longer.
            setup_clocks_per_triangle: (pvg.timing().latency + ip.setup_cycles())
                .max(noise.timing().ii),
            // The noise generator's pipeline fills once per frame before the first
            // flare line (its latency); the paper gives no other per-pass cost (one
            // glare pass per frame, no state change inside it).
            pass_overhead_clocks: noise.timing().latency,
            // Assumed (no source): 64 quads between two stages, which also bounds the
            // quads the ROP holds while their colour reads are in flight. A designer
            // sizes that buffer to the read latency at one quad a clock (Little's law:
            // ≥ 30 quads at 30 clocks), as the GeForce presets' 64 cover their 40;
            // below the latency the pass is latency bound at depth ÷ latency quads a
            // clock. Swept by `reproduce glare-asic-throughput` (16 and 2 deep).
            // The polygon interpolator walks the primitive's bounding box, one pixel a
            // clock per pipe (the paper's design; `pipeline::glare::throughput`).
            raster_walk: super::config::RasterWalk::BoundingBox,
            fifo_depth: 64,
            pipe_stages: vec![
                plain(ip.name(), ti.latency, ti.ii),
                // Bloom/flare and halo modulators sit side by side in each pipe and a
                // fragment passes one of them (its primitive's): one stage of the
                // longer latency and II.
                plain(
                    "bloom_flare_modulator | halo_modulator",
                    tb.latency.max(th.latency),
                    tb.ii.max(th.ii),
                ),
                plain(comb.name(), tc.latency, tc.ii),
            ],
            // No texture cache (no textures): size 0; the other fields are unused.
            texture_cache: CacheConfig {
                size_bytes: 0,
                line_bytes: 64,
                ways: 1,
                replacement: Replacement::Lru,
                shared: true,
                misses_in_flight: 1,
            },
            // Unused (no textures).
            texture_layout: Layout::Linear,
            // Assumed: a scanline framebuffer (the paper does not say).
            framebuffer_layout: Layout::Linear,
            memory: MemoryConfig {
                // GLARE_MEMORY_BYTES_PER_SECOND (assumed) at the core clock.
                bytes_per_clock: GLARE_MEMORY_BYTES_PER_SECOND / (hw.clock_mhz * 1e6),
                // Assumed: 100 ns from a read's issue to its data (an SDRAM row miss
                // and the controller), 30 clocks at 300 MHz.
                latency_clocks: (100e-9 * hw.clock_mhz * 1e6).round() as u32,
                // Assumed: enough requests in flight to cover the latency at one
                // quad's read a clock (≥ 30 at 300 MHz), rounded up to a power of 2.
                queue_depth: 64,
                // One client (the combiner's colour read-modify-write): either rule.
                arbitration: Arbitration::RoundRobin,
                // Assumed: no page model (bandwidth and latency only).
                pages: None,
            },
        })
    }
}
