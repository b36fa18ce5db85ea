//! The clocked chip's configuration: every parameter a named field, the value of each
//! preset with its source in `presets.rs` and docs/throughput.md ("assumed" where no
//! datasheet, paper or patent gives it; those are swept, never fitted).

use serde::Serialize;

/// How a surface (a texture, the framebuffer, the depth buffer) is laid out in memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Layout {
    /// Row after row (x fastest).
    Linear,
    /// Rectangular tiles of `w` × `h` texels or pixels stored contiguously, tiles in
    /// row order.
    Tiled { w: u32, h: u32 },
    /// Morton (Z) order of x and y bits (the swizzled layout of NV1x/NV2x textures).
    Swizzled,
}

/// Which line a set-associative cache evicts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Replacement {
    Lru,
    Fifo,
}

/// A texture cache.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CacheConfig {
    /// Capacity in bytes (0: no cache, every texel a memory request).
    pub size_bytes: u32,
    /// Line size in bytes (the memory request a miss makes).
    pub line_bytes: u32,
    /// Ways (associativity); `size_bytes / line_bytes` ways is fully associative.
    pub ways: u32,
    pub replacement: Replacement,
    /// One cache shared by every texture unit of every pipe (true), or one per texture
    /// unit (false).
    pub shared: bool,
    /// Line requests a texture unit may have in flight (the prefetch depth that hides
    /// memory latency).
    pub misses_in_flight: u32,
}

/// DRAM pages and banks (optional: without them every request costs only bandwidth and
/// latency).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DramPages {
    pub page_bytes: u32,
    pub banks: u32,
    /// Extra clocks a request pays when its bank has another page open.
    pub page_miss_clocks: u32,
}

/// How the memory controller picks the next request among its clients.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Arbitration {
    /// Round robin over clients with requests waiting.
    RoundRobin,
    /// Texture misses first, then depth, then colour, then copies.
    FixedPriority,
}

/// The memory controller.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MemoryConfig {
    /// Sustained bytes per core clock (bandwidth ÷ core clock).
    pub bytes_per_clock: f64,
    /// Clocks from a read request's issue to its data.
    pub latency_clocks: u32,
    /// Requests the controller queues (over all clients).
    pub queue_depth: u32,
    pub arbitration: Arbitration,
    pub pages: Option<DramPages>,
}

/// What a pixel-pipe stage is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum StageKind {
    /// A unit that takes a fragment every `ii` clocks and hands it on `latency` clocks
    /// later.
    Plain,
    /// The texture units: lookups through the texture cache, waiting for misses.
    Texture,
}

/// One stage of a pixel pipe (between the rasteriser and the ROP), its timing from the
/// unit contract (the unit's `timing()` at the chip's configuration).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PipeStage {
    /// The unit ("polygon_interpolator", "texture_sampler", "register_combiner", …).
    pub name: String,
    pub kind: StageKind,
    pub latency: u32,
    pub ii: u32,
}

/// What the rasteriser spends its clocks on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum RasterWalk {
    /// Every pixel of the primitive's bounding box as the polygon interpolator walks
    /// it (covered or not, inside the viewport or not), `pipes` pixels per clock: the
    /// glare ASIC's interpolator (Matsuda and Ikedo's design walks the box).
    BoundingBox,
    /// Only the 2×2 quads that hold a fragment, one per clock, and the fragments the
    /// depth test removes (`pipes` per clock): a rasteriser that traverses the
    /// primitive's own quads inside the viewport, as edge-function traversal does
    /// (McCormack and McNamara, "Tiled polygon traversal using half-plane edge
    /// functions", Graphics Hardware 2000). Assumed for the GeForce presets: NVIDIA
    /// does not publish its traversal.
    CoveredQuads,
}

/// A clocked chip: the stages a pass runs through and the memory behind them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ChipConfig {
    /// "geforce256", "geforce2-gts", "geforce3", "glare-asic".
    pub name: String,
    /// Core clock in Hz.
    pub clock_hz: f64,
    /// Pixel pipes (4: one 2×2 quad per clock).
    pub pipes: u32,
    /// Texture units per pipe.
    pub tmus_per_pipe: u32,
    /// Textures one hardware pass combines (more are drawn in further passes, the
    /// partial result kept in destination alpha).
    pub textures_per_pass: u32,
    /// Triangle set-up clocks per triangle.
    pub setup_clocks_per_triangle: u32,
    /// Clocks between passes (state change, pipeline flush).
    pub pass_overhead_clocks: u32,
    /// What the rasteriser walks (its clocks per primitive).
    pub raster_walk: RasterWalk,
    /// Entries (quads) of every FIFO between two stages.
    pub fifo_depth: u32,
    /// The pixel pipe's stages in order, from the interpolator to the last combiner
    /// (the rasteriser before them and the ROP after them are the chip's own).
    pub pipe_stages: Vec<PipeStage>,
    pub texture_cache: CacheConfig,
    pub texture_layout: Layout,
    pub framebuffer_layout: Layout,
    pub memory: MemoryConfig,
}

use rtl_model::ConfigError;

fn range(field: &str, v: u64, min: u64, max: u64) -> Result<(), ConfigError> {
    if v < min || v > max {
        return Err(ConfigError::invalid(
            field,
            &format!("{v} is out of range (allowed {min} ..= {max})"),
        ));
    }
    Ok(())
}

fn pow2(field: &str, v: u64) -> Result<(), ConfigError> {
    if !v.is_power_of_two() {
        return Err(ConfigError::invalid(
            field,
            &format!("{v} is not a power of two"),
        ));
    }
    Ok(())
}

fn layout(field: &str, l: &Layout) -> Result<(), ConfigError> {
    if let Layout::Tiled { w, h } = l {
        range(&format!("{field}.w"), *w as u64, 1, 4096)?;
        pow2(&format!("{field}.w"), *w as u64)?;
        range(&format!("{field}.h"), *h as u64, 1, 4096)?;
        pow2(&format!("{field}.h"), *h as u64)?;
    }
    Ok(())
}

impl ChipConfig {
    /// Check every field; the error names the first bad one (`chip.texture_cache.line_bytes`).
    pub fn validate(&self) -> Result<(), ConfigError> {
        if !(self.clock_hz.is_finite() && self.clock_hz > 0.0) {
            return Err(ConfigError::invalid(
                "chip.clock_hz",
                &format!("{} is not a positive finite frequency", self.clock_hz),
            ));
        }
        range("chip.pipes", self.pipes as u64, 1, 64)?;
        // 0: a chip without texture units (the glare ASIC: its tables are on chip).
        range("chip.tmus_per_pipe", self.tmus_per_pipe as u64, 0, 16)?;
        range(
            "chip.textures_per_pass",
            self.textures_per_pass as u64,
            1,
            64,
        )?;
        range(
            "chip.setup_clocks_per_triangle",
            self.setup_clocks_per_triangle as u64,
            0,
            1 << 20,
        )?;
        range(
            "chip.pass_overhead_clocks",
            self.pass_overhead_clocks as u64,
            0,
            1 << 30,
        )?;
        range("chip.fifo_depth", self.fifo_depth as u64, 1, 1 << 16)?;
        self.validate_stages()?;
        self.texture_cache.validate()?;
        layout("chip.texture_layout", &self.texture_layout)?;
        layout("chip.framebuffer_layout", &self.framebuffer_layout)?;
        self.memory.validate()
    }

    /// The pipe's stages: named, latency and II in range, at most one Texture stage and
    /// texture units for it.
    fn validate_stages(&self) -> Result<(), ConfigError> {
        let mut textures = 0;
        for (i, s) in self.pipe_stages.iter().enumerate() {
            let f = format!("chip.pipe_stages[{i}]");
            if s.name.trim().is_empty() {
                return Err(ConfigError::invalid(&format!("{f}.name"), "is empty"));
            }
            range(&format!("{f}.latency"), s.latency as u64, 1, 1 << 16)?;
            range(&format!("{f}.ii"), s.ii as u64, 1, 1 << 16)?;
            textures += (s.kind == StageKind::Texture) as u32;
        }
        if textures == 1 && self.tmus_per_pipe == 0 {
            return Err(ConfigError::invalid(
                "chip.tmus_per_pipe",
                "is 0 but the pipe has a Texture stage (give it at least one texture unit)",
            ));
        }
        if textures > 1 {
            return Err(ConfigError::invalid(
                "chip.pipe_stages",
                &format!(
                    "{textures} Texture stages; the chip has one (its units are tmus_per_pipe)"
                ),
            ));
        }
        Ok(())
    }
}

impl CacheConfig {
    /// Line, prefetch depth, and (a cache at all) whole lines in a power-of-two number
    /// of sets; errors name the `chip.texture_cache` field.
    fn validate(&self) -> Result<(), ConfigError> {
        let c = self;
        range(
            "chip.texture_cache.line_bytes",
            c.line_bytes as u64,
            4,
            4096,
        )?;
        pow2("chip.texture_cache.line_bytes", c.line_bytes as u64)?;
        range(
            "chip.texture_cache.misses_in_flight",
            c.misses_in_flight as u64,
            1,
            1 << 16,
        )?;
        if c.size_bytes > 0 {
            range(
                "chip.texture_cache.size_bytes",
                c.size_bytes as u64,
                c.line_bytes as u64,
                1 << 30,
            )?;
            let lines = c.size_bytes / c.line_bytes;
            if lines * c.line_bytes != c.size_bytes {
                return Err(ConfigError::invalid(
                    "chip.texture_cache.size_bytes",
                    &format!(
                        "{} is not a whole number of {}-byte lines",
                        c.size_bytes, c.line_bytes
                    ),
                ));
            }
            range("chip.texture_cache.ways", c.ways as u64, 1, lines as u64)?;
            if !lines.is_multiple_of(c.ways) || !(lines / c.ways).is_power_of_two() {
                return Err(ConfigError::invalid(
                    "chip.texture_cache.ways",
                    &format!(
                        "{} lines in {} ways do not make a power-of-two number of sets",
                        lines, c.ways
                    ),
                ));
            }
        }
        Ok(())
    }
}

impl MemoryConfig {
    /// Bandwidth, latency, queue and DRAM pages in range; errors name the
    /// `chip.memory` field.
    fn validate(&self) -> Result<(), ConfigError> {
        let m = self;
        if !(m.bytes_per_clock.is_finite() && (1e-3..=1e12).contains(&m.bytes_per_clock)) {
            return Err(ConfigError::invalid(
                "chip.memory.bytes_per_clock",
                &format!(
                    "{} is not a finite number in 0.001 ..= 1e12",
                    m.bytes_per_clock
                ),
            ));
        }
        range(
            "chip.memory.latency_clocks",
            m.latency_clocks as u64,
            0,
            1 << 20,
        )?;
        range("chip.memory.queue_depth", m.queue_depth as u64, 1, 1 << 16)?;
        if let Some(p) = &m.pages {
            range(
                "chip.memory.pages.page_bytes",
                p.page_bytes as u64,
                64,
                1 << 24,
            )?;
            pow2("chip.memory.pages.page_bytes", p.page_bytes as u64)?;
            range("chip.memory.pages.banks", p.banks as u64, 1, 256)?;
            range(
                "chip.memory.pages.page_miss_clocks",
                p.page_miss_clocks as u64,
                0,
                1 << 16,
            )?;
        }
        Ok(())
    }
}
