//! The glare ASIC (Matsuda and Ikedo) as a clocked chip of its own, not a GeForce: its
//! preset built from a glare scene's `[glare.hw]` (the units' timing at the widths the
//! glare pass builds them with). Here, beside the glare pass, because it reads the
//! scene's glare section; the chip's model (`crate::chip`) imports no scene.

use crate::chip::config::ChipConfig;

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

/// Matsuda and Ikedo's glare ASIC at the default `[glare.hw]` (300 MHz, 4 pipes:
/// the paper's 1.2 Gpixel/s). [`glare_asic_for`] gives it at a scene's
/// widths, clock and pipes.
pub fn glare_asic() -> Result<ChipConfig, rtl_model::ConfigError> {
    glare_asic_for(&crate::scene::glare::GlareHw::default())
}

/// The glare ASIC at a scene's `[glare.hw]`: every stage's latency and initiation
/// interval from the unit's own `timing()` at the widths the glare pass builds it
/// with (`scene::limits`), each field's source beside it.
pub fn glare_asic_for(
    hw: &crate::scene::glare::GlareHw,
) -> Result<ChipConfig, rtl_model::ConfigError> {
    use crate::chip::config::{CacheConfig, Layout, PipeStage, Replacement, StageKind};
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
        raster_walk: crate::chip::config::RasterWalk::BoundingBox,
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
        memory: glare_memory(hw.clock_mhz),
    })
}

/// The glare ASIC's framebuffer memory at a core clock of `clock_mhz`.
fn glare_memory(clock_mhz: f64) -> crate::chip::config::MemoryConfig {
    use crate::chip::config::{Arbitration, MemoryConfig};
    MemoryConfig {
        // GLARE_MEMORY_BYTES_PER_SECOND (assumed) at the core clock.
        bytes_per_clock: GLARE_MEMORY_BYTES_PER_SECOND / (clock_mhz * 1e6),
        // Assumed: 100 ns from a read's issue to its data (an SDRAM row miss
        // and the controller), 30 clocks at 300 MHz.
        latency_clocks: (100e-9 * clock_mhz * 1e6).round() as u32,
        // Assumed: enough requests in flight to cover the latency at one
        // quad's read a clock (≥ 30 at 300 MHz), rounded up to a power of 2.
        queue_depth: 64,
        // One client (the combiner's colour read-modify-write): either rule.
        arbitration: Arbitration::RoundRobin,
        // Assumed: no page model (bandwidth and latency only).
        pages: None,
    }
}
