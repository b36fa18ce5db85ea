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
