//! The clocked chip: a pass's recorded work ([`PassWork`]) run clock by clock through
//! the stages joined by bounded FIFOs with valid/ready back-pressure, the texture
//! caches and the memory controller. Time only: the pixels are the functional model's.

use super::config::ChipConfig;
use super::work::{PassWork, RopWork, SampleBands};
use rtl_model::ConfigError;
use serde::Serialize;
use std::collections::BTreeMap;

/// One stage's clocks over a pass: busy (did work), stalled (had work, blocked by a
/// full FIFO downstream or by memory), starved (empty upstream). busy + stalled +
/// starved = the pass's cycles.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct StageClocks {
    pub name: String,
    pub busy: u64,
    pub stalled: u64,
    pub starved: u64,
}

/// A FIFO's deepest occupancy over a pass.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FifoHighWater {
    pub name: String,
    pub depth: u32,
    pub high_water: u32,
}

/// Utilisation over time: per stage, the busy fraction of each bucket of
/// `bucket_clocks` clocks (the last bucket may be shorter).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Timeline {
    pub bucket_clocks: u64,
    pub stages: Vec<String>,
    /// `busy[s][b]`: stage s's busy fraction in bucket b, 0 ..= 1.
    pub busy: Vec<Vec<f32>>,
}

/// The chip-level signals over a window of clocks, for a VCD: each signal's value at
/// the window's start and every change after it.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct WindowTrace {
    pub start_clock: u64,
    pub end_clock: u64,
    /// (name, width in bits): `<fifo>.valid`, `<fifo>.ready`, `<fifo>.level`, …
    pub signals: Vec<(String, u32)>,
    /// (clock, signal index, value), in clock order.
    pub changes: Vec<(u64, u32, u64)>,
}

impl Timeline {
    /// Resample the timeline so that its buckets span `cycles` clocks: as many buckets
    /// as before (or fewer, when the last would be empty), each taking the busy
    /// fractions of the bucket at the same relative position.
    pub fn stretch(&mut self, cycles: u64) {
        let n = self.busy.first().map_or(0, Vec::len) as u64;
        if n == 0 || cycles == 0 {
            return;
        }
        let bucket = cycles.div_ceil(n).max(1);
        let m = cycles.div_ceil(bucket);
        for row in &mut self.busy {
            let old = std::mem::take(row);
            *row = (0..m).map(|b| old[(b * n / m) as usize]).collect();
        }
        self.bucket_clocks = bucket;
    }
}

/// A pass clocked on a chip.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct PassTiming {
    /// Clocks from the pass's first primitive to its last write (over all its hardware
    /// passes, with the pass overhead).
    pub cycles: u64,
    /// Hardware passes the pass took (⌈textures / textures per pass⌉).
    pub hardware_passes: u32,
    pub stages: Vec<StageClocks>,
    pub fifos: Vec<FifoHighWater>,
    pub cache_hits: u64,
    pub cache_misses: u64,
    /// Bytes moved by each memory client: "texture", "depth", "colour", "copy".
    pub bytes_by_client: BTreeMap<String, u64>,
    /// The stage or memory client that bounds the pass.
    pub bottleneck: String,
    pub timeline: Timeline,
    /// Present when a window was asked for and overlaps the pass.
    pub window: Option<WindowTrace>,
}

impl PassTiming {
    /// Hits ÷ lookups, `None` when the pass looked nothing up.
    pub fn cache_hit_rate(&self) -> Option<f64> {
        let n = self.cache_hits + self.cache_misses;
        (n > 0).then(|| self.cache_hits as f64 / n as f64)
    }
}

/// One pass of a frame, clocked, beside its roofline prediction.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct NamedPassTiming {
    /// The frame's pass name (as `render --plan` lists it).
    pub pass: String,
    pub timing: PassTiming,
    /// The roofline's seconds for the same pass (the cross-check).
    pub roofline_seconds: f64,
    /// In sampled mode, a pass that was not recorded: the index of the frame's pass
    /// its timing is scaled from (the recorded pass of its kind before it,
    /// [`crate::chip::work::PassSample`]). `None`: the pass was clocked.
    pub scaled_from: Option<usize>,
}

/// A frame's clocked timing.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FrameTiming {
    /// "clocked" or "sampled".
    pub mode: String,
    /// The chip preset's name.
    pub chip: String,
    pub clock_hz: f64,
    pub passes: Vec<NamedPassTiming>,
    /// In sampled mode: the estimated relative error of the frame's cycles (one
    /// standard error over the groups of sampled bands), else `None`.
    pub sampling_error: Option<f64>,
    /// In sampled mode: one screen band (full-width 8-row tile row) in this many is
    /// clocked in each clocked pass (1: every band), else `None`.
    pub sample_band_every: Option<u32>,
    /// In sampled mode: of each kind of pass, the first two and then one in this many
    /// are clocked (1: every pass; [`crate::chip::work::PassSample`]), else `None`.
    pub sample_pass_every: Option<u32>,
    /// Passes of the frame that recorded no work (not clocked: not in `passes`,
    /// not in `cycles_total`), with their roofline time.
    pub roofline_only: Vec<RooflineOnlyPass>,
}

/// A pass of a clocked frame that recorded no work, timed by the roofline alone.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RooflineOnlyPass {
    /// The frame's pass name.
    pub pass: String,
    /// Its kind (`crate::chip::kind_name`).
    pub kind: String,
    /// The roofline's seconds.
    pub seconds: f64,
    /// Why it is not clocked ("roofline (no recorded work)").
    pub why: String,
}

impl FrameTiming {
    /// Clocks over every pass.
    pub fn cycles_total(&self) -> u64 {
        self.passes.iter().map(|p| p.timing.cycles).sum()
    }

    /// The frame's clocked seconds at the chip's clock.
    pub fn clocked_seconds(&self) -> f64 {
        self.cycles_total() as f64 / self.clock_hz
    }
}

// ---------------------------------------------------------------------------------
// The engine.
//
// A pass is clocked as one or more hardware passes (its textures in groups of
// `textures_per_pass`; each group walks every primitive again and pays
// `pass_overhead_clocks` first, all stages idle). Within a hardware pass, in every
// clock, in this order (producers before consumers, so a FIFO's ready is the level at
// the start of the clock and its valid falls through, as `fifo.rs` describes):
//
// 1. memory controller (`memory.rs`): starts queued requests, counts arrived reads;
// 2. set-up: `setup_clocks_per_triangle` clocks per primitive, then hands it to the
//    rasteriser through a FIFO of `fifo_depth` primitives;
// 3. rasteriser: walks a primitive's `prim_walked` pixels at `pipes` pixels per clock
//    (`RasterWalk::BoundingBox`; with `CoveredQuads` its quads and its depth-killed
//    fragments at `pipes` per clock)
//    and emits its covered fragments as 2×2 quads, at most one quad per clock, spread
//    evenly over the walk (quad i of Q due at walk clock ⌊i·T/Q⌋, T = max(⌈walked /
//    pipes⌉, Q)). Walk order (assumed): 8×8-pixel tiles in row order, 2×2 quads in row
//    order within a tile. A full FIFO freezes the walk;
// 4. the pipe stages in order. A Plain stage accepts a quad of n fragments every
//    ⌈n / pipes⌉·II clocks and presents it (⌈n / pipes⌉ − 1)·II + latency clocks after
//    accepting it (the unit contract's span per pipe). The Texture stage is the same
//    with ⌈n / pipes⌉·⌈t / tmus_per_pipe⌉·II clocks per quad for t textures in the
//    hardware pass; on accepting a quad it looks up every texel address of its
//    fragments in the texture cache and queues a line read for each miss (at most
//    `misses_in_flight` reads outstanding before it accepts another quad), and a quad
//    leaves only when the reads it needs (its misses, or the in-flight fills it hit)
//    have arrived — up to `fifo_depth` + latency quads wait inside it (the prefetching
//    organisation of Igehy, Eldridge and Proudfoot, Graphics Hardware 1998);
// 5. ROP: accepts a quad every ⌈n / pipes⌉ clocks, queues its depth and colour reads,
//    holds up to `fifo_depth` quads until their reads arrive, then queues the depth
//    and colour writes (every fragment is assumed to pass the depth test) and retires
//    the quad;
// 6. copy engine (the last hardware pass, after the ROP retired every quad): queues
//    the copy's reads and writes in bursts of `COPY_BURST_BYTES`, one per clock.
//
// A stage's clock is *busy* when it is inside an accepted item's occupancy (II
// window), else *stalled* when it holds work it cannot advance (a full FIFO
// downstream, a full memory queue, a read not yet arrived), else *starved*. Memory is
// busy while its channel transfers. Clocks in which nothing changes are skipped: the
// engine jumps to the next clock at which a timer (an II window's end, a latency, a
// read's arrival, the channel's next free clock) fires, crediting the skipped clocks
// to each stage's current state. The pass ends at the first clock in which every
// stage and the memory are idle.
//
// Bottleneck (the rule): when the memory channel was busy in ≥ 90 % of the pass's
// clocks outside the pass overhead, "memory (<client>)" with the client that moved the
// most bytes; otherwise the stage with the most busy clocks (the earliest on a tie).
// ---------------------------------------------------------------------------------

use super::config::{RasterWalk, StageKind};
use super::fifo::Fifo;
use super::fifo::Ring;
use super::memory::{Client, Memory, CLIENT_NAMES};
use super::texture_cache::{Access, Cache, Surface, SurfaceTable};

/// Bytes of one copy-to-texture request (assumed: one 64-byte burst).
pub const COPY_BURST_BYTES: u64 = 64;
/// Memory busy fraction above which the memory names the bottleneck.
pub const MEMORY_SATURATED: f64 = 0.9;
/// Timeline buckets at most (between half this and this on a long pass).
const TIMELINE_BUCKETS: usize = 1024;

const NONE: u32 = u32::MAX;
const BUSY: u8 = 0;
const STALLED: u8 = 1;
const STARVED: u8 = 2;

/// A 2×2 quad: its fragments by lane (lane = 2·(y & 1) + (x & 1)), `NONE` where
/// uncovered.
#[derive(Clone, Copy, Debug, Default)]
struct Quad {
    frag: [u32; 4],
    n: u32,
    x: u16,
    y: u16,
}

/// The pass's quads, per primitive, in walk order.
struct Quads {
    quads: Vec<Quad>,
    /// prim_start[p] .. prim_start[p + 1]: primitive p's quads.
    prim_start: Vec<u32>,
}

fn build_quads(work: &PassWork) -> Quads {
    let w = work.width.max(1) as usize;
    let h = work.height.max(1) as usize;
    let tiles_x = w.div_ceil(8);
    let slots = tiles_x * h.div_ceil(8) * 16;
    let mut stamp = vec![u32::MAX; slots];
    let mut slot = vec![0u32; slots];
    let mut quads = Vec::with_capacity(work.fragments() / 3 + 1);
    let nprims = work.prim_first_fragment.len();
    let mut prim_start = Vec::with_capacity(nprims + 1);
    let mut scratch: Vec<Quad> = Vec::new();
    let mut keys: Vec<u64> = Vec::new();
    for p in 0..nprims {
        prim_start.push(quads.len() as u32);
        scratch.clear();
        keys.clear();
        for f in work.prim_fragments(p) {
            let [x, y] = work.frag_xy[f];
            let (x, y) = (x as usize, y as usize);
            let wi = ((y >> 3) * tiles_x + (x >> 3)) * 16 + ((y >> 1) & 3) * 4 + ((x >> 1) & 3);
            let lane = (y & 1) * 2 + (x & 1);
            let mut q = slot[wi] as usize;
            if stamp[wi] != p as u32 || scratch[q].frag[lane] != NONE {
                q = scratch.len();
                scratch.push(Quad {
                    frag: [NONE; 4],
                    n: 0,
                    x: (x & !1) as u16,
                    y: (y & !1) as u16,
                });
                keys.push(((wi as u64) << 32) | q as u64);
                stamp[wi] = p as u32;
                slot[wi] = q as u32;
            }
            scratch[q].frag[lane] = f as u32;
            scratch[q].n += 1;
        }
        keys.sort_unstable();
        quads.extend(keys.iter().map(|k| scratch[(k & 0xffff_ffff) as usize]));
    }
    prim_start.push(quads.len() as u32);
    Quads { quads, prim_start }
}

/// Busy fractions per bucket, built while clocking: buckets of 2^shift clocks, two
/// merged into one whenever the pass outgrows `TIMELINE_BUCKETS`. A bucket's busy
/// clocks are the difference of each stage's running busy count ([`Acc::counts`])
/// between the bucket's ends, so a clock costs nothing here until a bucket closes.
struct TimelineBuilder {
    shift: u32,
    /// Closed buckets, per stage: the busy clocks in each.
    busy: Vec<Vec<u64>>,
    /// Each stage's busy count when the open bucket began.
    snap: Vec<u64>,
    /// The open bucket's index and its end (the first clock after it).
    open: usize,
    end: u64,
}

impl TimelineBuilder {
    fn new(stages: usize) -> Self {
        TimelineBuilder {
            shift: 0,
            busy: vec![Vec::with_capacity(TIMELINE_BUCKETS); stages],
            snap: vec![0; stages],
            open: 0,
            end: 1,
        }
    }

    /// Close the open bucket at the stages' busy counts `counts`.
    fn close(&mut self, counts: &[[u64; 3]]) {
        for ((b, sn), c) in self.busy.iter_mut().zip(&mut self.snap).zip(counts) {
            b.push(c[BUSY as usize] - *sn);
            *sn = c[BUSY as usize];
        }
        self.open += 1;
        if self.open == TIMELINE_BUCKETS {
            for b in &mut self.busy {
                let merged: Vec<u64> = b.chunks(2).map(|c| c.iter().sum()).collect();
                *b = merged;
            }
            self.shift += 1;
            self.open /= 2;
        }
        self.end = (self.open as u64 + 1) << self.shift;
    }

    fn finish(mut self, counts: &[[u64; 3]], names: Vec<String>, cycles: u64) -> Timeline {
        if cycles == 0 {
            return Timeline {
                bucket_clocks: 1,
                stages: names,
                busy: vec![Vec::new(); self.busy.len()],
            };
        }
        if ((self.open as u64) << self.shift) < cycles {
            // The open bucket holds the pass's last clocks.
            for ((b, sn), c) in self.busy.iter_mut().zip(&self.snap).zip(counts) {
                b.push(c[BUSY as usize] - sn);
            }
        }
        let bc = 1u64 << self.shift;
        let n = cycles.div_ceil(bc) as usize;
        let busy = self
            .busy
            .iter()
            .map(|v| {
                (0..n)
                    .map(|b| {
                        let len = bc.min(cycles - b as u64 * bc);
                        v.get(b).copied().unwrap_or(0) as f32 / len as f32
                    })
                    .collect()
            })
            .collect();
        Timeline {
            bucket_clocks: bc,
            stages: names,
            busy,
        }
    }
}

/// The chip-level signals over a window of clocks.
struct WindowBuilder {
    range: std::ops::Range<u64>,
    signals: Vec<(String, u32)>,
    last: Vec<u64>,
    changes: Vec<(u64, u32, u64)>,
}

impl WindowBuilder {
    /// Record `values` as the signals' values from clock `g` (global) for `k` clocks.
    fn sample(&mut self, g: u64, k: u64, values: impl Iterator<Item = u64>) {
        if g + k <= self.range.start || g >= self.range.end {
            return;
        }
        let at = g.max(self.range.start);
        for (i, v) in values.enumerate() {
            if self.last[i] != v {
                self.last[i] = v;
                self.changes.push((at, i as u32, v));
            }
        }
    }
}

fn bits_for(v: u64) -> u32 {
    (64 - v.leading_zeros()).max(1)
}

#[derive(Clone, Copy, Debug, Default)]
struct Flight {
    ready: u64,
    quad: u32,
    need: u64,
    need2: u64,
}

struct PipeUnit {
    latency: u64,
    ii: u64,
    texture: bool,
    next_accept: u64,
    flight: Ring<Flight>,
    cap: usize,
}

/// Every texel a quad fetches in a hardware pass, in the order the texture units
/// fetch them (lane, then texture `tex`, then texel): `visit(cache, byte address)`,
/// the cache serving (lane, texture) taken from `cache_of` (precomputed per hardware
/// pass: no division per lookup).
#[inline]
fn quad_texels(
    q: &Quad,
    work: &PassWork,
    tex: &[TexInfo],
    stride: usize,
    cache_of: &[u16],
    mut visit: impl FnMut(usize, u64),
) {
    let slots = tex.len();
    for lane in 0..4 {
        let f = q.frag[lane];
        if f == NONE {
            continue;
        }
        let frag_base = f as usize * stride;
        for (slot, t) in tex.iter().enumerate() {
            let start = frag_base + t.offset;
            let cache = cache_of[lane * slots + slot] as usize;
            for &i in &work.texels[start..start + t.per_lookup] {
                visit(cache, t.surface.address(i));
            }
        }
    }
}

/// The texture cache's answer for every quad of a hardware pass, worked out before
/// the pass is clocked. With one Texture stage the cache sees the quads in their
/// order and a miss's read is numbered by its rank among the pass's misses (only
/// misses read for the texture client), so neither depends on the clock: the
/// stage then only queues each quad's misses. Same hits, misses, reads and
/// addresses as looking up at acceptance, in one tight loop.
struct LookupsAhead {
    /// need[q]: the last texture read quad q waits for (0: none).
    need: Vec<u64>,
    /// miss_end[q] .. miss_end[q + 1]: quad q's misses in `miss_addr`.
    miss_end: Vec<u32>,
    /// Each miss's line byte address, in order.
    miss_addr: Vec<u64>,
    line_bytes: u32,
}

struct TexInfo {
    surface: SurfaceTable,
    offset: usize,
    per_lookup: usize,
}

/// Everything one clocked pass accumulates over its hardware passes (and, in sampled
/// mode, over its groups of sampled bands).
struct Acc {
    counts: Vec<[u64; 3]>,
    timeline: TimelineBuilder,
    window: Option<WindowBuilder>,
    /// Global clock at which the next hardware pass starts.
    offset: u64,
    overhead: u64,
    fifo_high: Vec<usize>,
    hits: u64,
    misses: u64,
    bytes: [u64; 4],
    mem_busy: u64,
    /// The fill and drain of every hardware pass so far ([`Engine::edges`]), summed;
    /// `None` when not asked for (only the sampled mode scales around them, and
    /// keeping each stage's busy span costs a loop over the stages every clock).
    edges: Option<u64>,
}

impl Acc {
    /// Credit clocks g .. g + k (global) to each stage's class `cls[s]`, closing the
    /// timeline's buckets the clocks pass the end of.
    #[inline]
    fn credit(&mut self, cls: &[u8], mut g: u64, mut k: u64) {
        while g + k > self.timeline.end {
            let end = self.timeline.end;
            if g < end {
                let part = end - g;
                for (c, &s) in self.counts.iter_mut().zip(cls) {
                    c[s as usize] += part;
                }
                g += part;
                k -= part;
            }
            self.timeline.close(&self.counts);
        }
        for (c, &s) in self.counts.iter_mut().zip(cls) {
            c[s as usize] += k;
        }
    }
}

struct Engine<'a> {
    chip: &'a ChipConfig,
    work: &'a PassWork,
    quads: &'a Quads,
    tex: Vec<TexInfo>,
    stride: usize,
    colour: Surface,
    depth: Surface,
    caches: Vec<Cache>,
    mem: Memory,
    fifo_sr: Fifo<u32>,
    fifos: Vec<Fifo<u32>>,
    pipes: Vec<PipeUnit>,
    rop_flight: Ring<Flight>,
    rop_next_accept: u64,
    rop_retired: usize,
    // set-up
    next_prim: usize,
    setup_hold: Option<u32>,
    setup_until: u64,
    // rasteriser
    r_active: bool,
    r_quad: usize,
    r_start: usize,
    r_end: usize,
    r_total: u64,
    r_base: u64,
    /// The walk clock at which quad `r_quad` is due, ⌊i·T/Q⌋ (kept, not divided out
    /// every clock).
    r_due: u64,
    /// Clocks a quad of n fragments occupies a stage per II, ⌈n / pipes⌉ (at least 1),
    /// by n.
    lanes_of: [u64; 5],
    /// Texture issue rounds per fragment in this hardware pass, ⌈t / tmus_per_pipe⌉.
    tex_rounds: u64,
    // copy
    copy_read_left: u64,
    copy_write_left: u64,
    copy_toggle: bool,
    // this hardware pass's textures
    group: std::ops::Range<usize>,
    cls: Vec<u8>,
    /// Texel fetches made without a cache (each a memory read).
    uncached: u64,
    /// cache_of[lane · group length + slot]: the cache that serves texture slot `slot`
    /// of lane `lane` in this hardware pass.
    cache_of: Vec<u16>,
    /// This hardware pass's lookups, when worked out ahead ([`LookupsAhead`]).
    ahead: Option<LookupsAhead>,
    /// The clock at which the ROP retired its first quad in this hardware pass
    /// (`u64::MAX`: none yet).
    first_retire: u64,
    /// Per stage (the memory channel last), in this hardware pass ([`BusySpan`]).
    busy: Vec<BusySpan>,
}

/// One stage's busy clocks in a hardware pass: how many, how many before the ROP
/// retired its first quad, and the clock after its last busy one.
#[derive(Clone, Copy, Debug, Default)]
struct BusySpan {
    clocks: u64,
    before_first_retire: u64,
    end: u64,
}

impl<'a> Engine<'a> {
    fn n_stages(&self) -> usize {
        self.pipes.len() + 5
    }

    fn rop_index(&self) -> usize {
        2 + self.pipes.len()
    }

    fn step_setup(&mut self, t: u64) -> bool {
        let mut prog = false;
        let s = self.chip.setup_clocks_per_triangle as u64;
        let n = self.work.prim_first_fragment.len();
        loop {
            if let Some(p) = self.setup_hold {
                if t < self.setup_until {
                    self.cls[0] = BUSY;
                    return prog;
                }
                if self.fifo_sr.push(p) {
                    self.setup_hold = None;
                    prog = true;
                } else {
                    self.cls[0] = STALLED;
                    return prog;
                }
            }
            if self.next_prim < n {
                self.setup_hold = Some(self.next_prim as u32);
                self.next_prim += 1;
                self.setup_until = t + s;
                prog = true;
            } else {
                self.cls[0] = STARVED;
                return prog;
            }
        }
    }

    fn step_raster(&mut self, t: u64) -> bool {
        let mut prog = false;
        let pipes = self.chip.pipes as u64;
        loop {
            if self.r_active {
                let pos = t - self.r_base;
                if self.r_quad < self.r_end && self.r_due <= pos {
                    if self.fifos[0].push(self.r_quad as u32) {
                        self.r_quad += 1;
                        self.r_due = self.raster_due();
                        prog = true;
                    } else {
                        self.r_base += 1;
                        self.cls[1] = STALLED;
                        return prog;
                    }
                }
                if pos + 1 >= self.r_total && self.r_quad == self.r_end {
                    self.r_active = false;
                    prog = true;
                }
                self.cls[1] = BUSY;
                return prog;
            }
            let Some(p) = self.fifo_sr.pop() else {
                self.cls[1] = STARVED;
                return prog;
            };
            let p = p as usize;
            prog = true;
            self.r_start = self.quads.prim_start[p] as usize;
            self.r_end = self.quads.prim_start[p + 1] as usize;
            self.r_quad = self.r_start;
            self.r_due = 0;
            let nq = (self.r_end - self.r_start) as u64;
            self.r_total = match self.chip.raster_walk {
                RasterWalk::BoundingBox => {
                    (self.work.prim_walked[p] as u64).div_ceil(pipes).max(nq)
                }
                RasterWalk::CoveredQuads => {
                    let killed = self.work.prim_depth_killed.get(p).copied().unwrap_or(0);
                    nq + u64::from(killed).div_ceil(pipes)
                }
            };
            if self.r_total > 0 {
                self.r_active = true;
                self.r_base = t;
            }
        }
    }

    /// The walk clock at which quad `r_quad` of the primitive is due (quad i of Q at
    /// ⌊i·T/Q⌋); any value once every quad is out.
    fn raster_due(&self) -> u64 {
        if self.r_quad >= self.r_end {
            return 0;
        }
        let i = (self.r_quad - self.r_start) as u64;
        let nq = (self.r_end - self.r_start) as u64;
        i * self.r_total / nq
    }

    /// Look up a quad's texels for this hardware pass's textures; returns the last
    /// texture read it needs.
    fn lookup(&mut self, qi: u32) -> u64 {
        if let Some(pre) = &self.ahead {
            // Worked out before the clock: queue the quad's misses, in order.
            let (a, b) = (pre.miss_end[qi as usize], pre.miss_end[qi as usize + 1]);
            for &addr in &pre.miss_addr[a as usize..b as usize] {
                self.mem
                    .enqueue(Client::Texture, pre.line_bytes, addr, true);
            }
            return pre.need[qi as usize];
        }
        let q = self.quads.quads[qi as usize];
        if self.caches.is_empty() {
            return self.lookup_uncached(&q);
        }
        let mut need = 0;
        // The number the next texture read gets; it grows by one per miss queued.
        let mut next = self.mem.next_read(Client::Texture);
        let (caches, mem) = (&mut self.caches, &mut self.mem);
        let tex = &self.tex[self.group.clone()];
        quad_texels(
            &q,
            self.work,
            tex,
            self.stride,
            &self.cache_of,
            |c, address| {
                let cache = &mut caches[c];
                let line = cache.line_of(address);
                match cache.access(line, next) {
                    Access::Hit { fill } => need = need.max(fill),
                    Access::Miss => {
                        let lb = cache.line_bytes();
                        need = mem.enqueue(Client::Texture, lb, line * lb as u64, true);
                        next = need + 1;
                    }
                }
            },
        );
        need
    }

    /// Every quad's lookup in this hardware pass, before the clock ([`LookupsAhead`]).
    fn lookups_ahead(&mut self) -> LookupsAhead {
        let n = self.quads.quads.len();
        let line_bytes = self.caches[0].line_bytes();
        let mut ahead = LookupsAhead {
            need: Vec::with_capacity(n),
            miss_end: Vec::with_capacity(n + 1),
            miss_addr: Vec::new(),
            line_bytes,
        };
        ahead.miss_end.push(0);
        // Reads are numbered from 1 in each hardware pass, and only misses read.
        let mut next = 1u64;
        let (work, tex, stride) = (self.work, &self.tex[self.group.clone()], self.stride);
        let caches = &mut self.caches;
        for q in &self.quads.quads {
            let mut need = 0;
            quad_texels(q, work, tex, stride, &self.cache_of, |c, address| {
                let cache = &mut caches[c];
                let line = cache.line_of(address);
                match cache.access(line, next) {
                    Access::Hit { fill } => need = need.max(fill),
                    Access::Miss => {
                        ahead.miss_addr.push(line * line_bytes as u64);
                        need = next;
                        next += 1;
                    }
                }
            });
            ahead.need.push(need);
            ahead.miss_end.push(ahead.miss_addr.len() as u32);
        }
        ahead
    }

    /// `lookup` without a cache: every texel fetch is a memory read.
    fn lookup_uncached(&mut self, q: &Quad) -> u64 {
        let mut need = 0;
        for lane in 0..4 {
            let f = q.frag[lane];
            if f == NONE {
                continue;
            }
            let frag_base = f as usize * self.stride;
            for j in self.group.clone() {
                let tex = &self.tex[j];
                let start = frag_base + tex.offset;
                let texels = &self.work.texels[start..start + tex.per_lookup];
                self.uncached += texels.len() as u64;
                for &i in texels {
                    let a = tex.surface.address(i);
                    need = self.mem.enqueue(
                        Client::Texture,
                        tex.surface.surface().elem_bytes,
                        a,
                        true,
                    );
                }
            }
        }
        need
    }

    fn step_pipe(&mut self, i: usize, t: u64) -> bool {
        let mut prog = false;
        let (mut blocked, mut waiting) = (false, false);
        {
            let st = &mut self.pipes[i];
            if let Some(f) = st.flight.front().copied() {
                if f.ready <= t {
                    if st.texture && self.mem.reads_done(Client::Texture) < f.need {
                        waiting = true;
                    } else if self.fifos[i + 1].push(f.quad) {
                        st.flight.pop_front();
                        prog = true;
                    } else {
                        blocked = true;
                    }
                }
            }
        }
        let st = &self.pipes[i];
        let mut refused = false;
        if !blocked && t >= st.next_accept && self.fifos[i].valid() {
            let can = st.flight.len() < st.cap
                && (!st.texture
                    || (self.mem.reads_outstanding(Client::Texture)
                        < self.chip.texture_cache.misses_in_flight as u64
                        && self.mem.has_room()));
            if can {
                let q = self.fifos[i].pop().unwrap_or(0);
                let quad = self.quads.quads[q as usize];
                let lanes = self.lanes_of[quad.n as usize];
                let (texture, ii, latency) = (st.texture, st.ii, st.latency);
                let (occ, need) = if texture {
                    (lanes * self.tex_rounds * ii, self.lookup(q))
                } else {
                    (lanes * ii, 0)
                };
                let st = &mut self.pipes[i];
                st.flight.push_back(Flight {
                    ready: t + occ - ii + latency,
                    quad: q,
                    need,
                    need2: 0,
                });
                st.next_accept = t + occ;
                prog = true;
            } else {
                refused = true;
            }
        }
        let st = &self.pipes[i];
        let head_waits = st.texture
            && st
                .flight
                .front()
                .is_some_and(|f| f.ready <= t && self.mem.reads_done(Client::Texture) < f.need);
        self.cls[2 + i] = if t < st.next_accept {
            BUSY
        } else if blocked || refused || waiting || head_waits {
            STALLED
        } else {
            STARVED
        };
        prog
    }

    fn step_rop(&mut self, t: u64) -> bool {
        let mut prog = false;
        let k = self.pipes.len();
        let rop = self.work.rop;
        let cap = self.chip.fifo_depth as usize;
        let mut refused = false;
        if t >= self.rop_next_accept && self.fifos[k].valid() {
            if self.rop_flight.len() < cap && self.mem.has_room() {
                let q = self.fifos[k].pop().unwrap_or(0);
                let quad = self.quads.quads[q as usize];
                let n = quad.n;
                let (x, y) = (quad.x as u32, quad.y as u32);
                let need = if rop.depth_read_bytes > 0 {
                    let a = self.depth.address_xyz(x, y, 0);
                    self.mem
                        .enqueue(Client::Depth, n * rop.depth_read_bytes, a, true)
                } else {
                    0
                };
                let need2 = if rop.colour_read_bytes > 0 {
                    let a = self.colour.address_xyz(x, y, 0);
                    self.mem
                        .enqueue(Client::Colour, n * rop.colour_read_bytes, a, true)
                } else {
                    0
                };
                self.rop_flight.push_back(Flight {
                    ready: t,
                    quad: q,
                    need,
                    need2,
                });
                self.rop_next_accept = t + self.lanes_of[n as usize];
                prog = true;
            } else {
                refused = true;
            }
        }
        let mut blocked = false;
        let mut waiting = false;
        if let Some(f) = self.rop_flight.front().copied() {
            if self.mem.reads_done(Client::Depth) >= f.need
                && self.mem.reads_done(Client::Colour) >= f.need2
            {
                let writes = rop.depth_write_bytes > 0 || rop.colour_write_bytes > 0;
                if writes && !self.mem.has_room() {
                    blocked = true;
                } else {
                    let quad = self.quads.quads[f.quad as usize];
                    let (x, y) = (quad.x as u32, quad.y as u32);
                    if rop.depth_write_bytes > 0 {
                        let a = self.depth.address_xyz(x, y, 0);
                        self.mem
                            .enqueue(Client::Depth, quad.n * rop.depth_write_bytes, a, false);
                    }
                    if rop.colour_write_bytes > 0 {
                        let a = self.colour.address_xyz(x, y, 0);
                        self.mem
                            .enqueue(Client::Colour, quad.n * rop.colour_write_bytes, a, false);
                    }
                    self.rop_flight.pop_front();
                    self.rop_retired += 1;
                    if self.first_retire == u64::MAX {
                        self.first_retire = t;
                        for b in &mut self.busy {
                            b.before_first_retire = b.clocks;
                        }
                    }
                    prog = true;
                }
            } else {
                waiting = true;
            }
        }
        let ri = self.rop_index();
        self.cls[ri] = if t < self.rop_next_accept {
            BUSY
        } else if blocked || refused || waiting {
            STALLED
        } else {
            STARVED
        };
        prog
    }

    fn drawing_done(&self) -> bool {
        self.rop_retired == self.quads.quads.len()
            && self.next_prim == self.work.prim_first_fragment.len()
            && self.setup_hold.is_none()
            && !self.r_active
            && !self.fifo_sr.valid()
    }

    fn step_copy(&mut self, t: u64) -> bool {
        let ci = self.rop_index() + 1;
        let _ = t;
        if self.copy_read_left + self.copy_write_left == 0 || !self.drawing_done() {
            self.cls[ci] = STARVED;
            return false;
        }
        if !self.mem.has_room() {
            self.cls[ci] = STALLED;
            return false;
        }
        let read = if self.copy_read_left == 0 {
            false
        } else if self.copy_write_left == 0 {
            true
        } else {
            self.copy_toggle = !self.copy_toggle;
            self.copy_toggle
        };
        let left = if read {
            &mut self.copy_read_left
        } else {
            &mut self.copy_write_left
        };
        let b = (*left).min(COPY_BURST_BYTES);
        *left -= b;
        self.mem.enqueue(Client::Copy, b as u32, 0, read);
        self.cls[ci] = BUSY;
        true
    }

    fn clock(&mut self, t: u64) -> bool {
        let mut prog = self.mem.tick(t);
        prog |= self.step_setup(t);
        prog |= self.step_raster(t);
        for i in 0..self.pipes.len() {
            prog |= self.step_pipe(i, t);
        }
        prog |= self.step_rop(t);
        prog |= self.step_copy(t);
        let mi = self.n_stages() - 1;
        self.cls[mi] = if self.mem.busy(t) { BUSY } else { STARVED };
        prog
    }

    fn all_done(&self, t: u64) -> bool {
        self.drawing_done()
            && self.copy_read_left + self.copy_write_left == 0
            && self.mem.idle(t)
            && self.fifos.iter().all(|f| !f.valid())
            && self.pipes.iter().all(|p| p.flight.is_empty())
            && self.rop_flight.is_empty()
    }

    /// The next clock after `t` at which some timer fires.
    fn next_event(&self, t: u64) -> Option<u64> {
        let mut next = u64::MAX;
        let mut at = |c: u64| {
            if c > t {
                next = next.min(c);
            }
        };
        if self.setup_hold.is_some() {
            at(self.setup_until);
        }
        if self.r_active && self.cls[1] == BUSY {
            if self.r_quad < self.r_end {
                at(self.r_base + self.r_due);
            }
            at(self.r_base + self.r_total - 1);
        }
        for p in &self.pipes {
            at(p.next_accept);
            if let Some(f) = p.flight.front() {
                at(f.ready);
            }
        }
        at(self.rop_next_accept);
        if let Some(m) = self.mem.next_event(t) {
            at(m);
        }
        (next != u64::MAX).then_some(next)
    }

    /// The hardware pass's fill and drain, ending at clock `end`, on its busiest
    /// resource (a stage or the memory channel): the clocks it sat idle before the
    /// ROP retired the first quad, and after its own last busy clock. In between it
    /// works at its steady rate, on work that grows with the fragments; the fill and
    /// the drain are paid once per pass (the sampled mode does not scale them).
    ///
    /// Why not the clocks before the first retire and after the last: a memory-bound
    /// pass moves the first quads' reads before any quad retires, work every sampled
    /// stream would then leave out (about 2 % of tests/chip_clock's Fig. 6(b)-sized
    /// plane at one band in 8). The two ends are measured on the same resource: the
    /// pipe's latency that a rasteriser-bound fill no longer holds (the rasteriser is
    /// busy while the first quads cross the pipe) is in its drain (idle while the last
    /// ones do). 0 when no quad retired (a copy).
    fn edges(&self, end: u64) -> u64 {
        if self.first_retire == u64::MAX {
            return 0;
        }
        // The first of equals in stage order (the memory channel last).
        let b = self
            .busy
            .iter()
            .rev()
            .max_by_key(|b| b.clocks)
            .copied()
            .unwrap_or_default();
        (self.first_retire - b.before_first_retire.min(self.first_retire))
            + end.saturating_sub(b.end)
    }

    fn signal_values(&self) -> impl Iterator<Item = u64> + '_ {
        std::iter::once(&self.fifo_sr)
            .chain(self.fifos.iter())
            .flat_map(|f| [f.valid() as u64, f.ready() as u64, f.level() as u64])
            .chain(std::iter::once(self.mem.queued() as u64))
    }

    fn record(&mut self, acc: &mut Acc, t: u64, k: u64) {
        if acc.edges.is_some() && k > 0 {
            for (b, &c) in self.busy.iter_mut().zip(&self.cls) {
                if c == BUSY {
                    b.clocks += k;
                    b.end = t + k;
                }
            }
        }
        let g = acc.offset + t;
        acc.credit(&self.cls, g, k);
        if let Some(w) = acc.window.as_mut() {
            w.sample(g, k, self.signal_values());
        }
    }

    /// Clock one hardware pass (textures `group`; the copy on the last). Returns its
    /// clocks (without the overhead).
    fn run_hw_pass(
        &mut self,
        acc: &mut Acc,
        group: std::ops::Range<usize>,
        last: bool,
    ) -> Result<u64, ConfigError> {
        self.group = group;
        let (pipes, tmus) = (self.chip.pipes as usize, self.chip.tmus_per_pipe as usize);
        // A chip without TMUs has no Texture stage (validated): no rounds to count.
        self.tex_rounds = if tmus == 0 {
            1
        } else {
            (self.group.len() as u64).div_ceil(tmus as u64).max(1)
        };
        let shared = self.chip.texture_cache.shared;
        let slots = self.group.len();
        self.cache_of = (0..4 * slots)
            .map(|k| {
                let (lane, slot) = (k / slots.max(1), k % slots.max(1));
                if shared {
                    0
                } else {
                    ((lane % pipes) * tmus + slot % tmus) as u16
                }
            })
            .collect();
        self.mem.restart();
        for c in &mut self.caches {
            c.flush();
        }
        let texture_stages = self.pipes.iter().filter(|p| p.texture).count();
        self.ahead = None;
        if texture_stages == 1 && !self.caches.is_empty() {
            self.ahead = Some(self.lookups_ahead());
        }
        self.fifo_sr.clear();
        for f in &mut self.fifos {
            f.clear();
        }
        for p in &mut self.pipes {
            p.next_accept = 0;
            p.flight.clear();
        }
        self.rop_flight.clear();
        self.rop_next_accept = 0;
        self.rop_retired = 0;
        self.next_prim = 0;
        self.setup_hold = None;
        self.setup_until = 0;
        self.r_active = false;
        self.first_retire = u64::MAX;
        self.busy.fill(BusySpan::default());
        (self.copy_read_left, self.copy_write_left) = if last {
            (self.work.copy_read_bytes, self.work.copy_write_bytes)
        } else {
            (0, 0)
        };
        let mut t = 0u64;
        loop {
            let prog = self.clock(t);
            if !prog && self.all_done(t) {
                break;
            }
            self.record(acc, t, 1);
            if prog {
                t += 1;
                continue;
            }
            let Some(next) = self.next_event(t) else {
                return Err(ConfigError::invalid(
                    "chip",
                    "the clocked chip stopped with work left (no stage can advance)",
                ));
            };
            self.record(acc, t + 1, next - t - 1);
            t = next;
        }
        for (h, f) in acc
            .fifo_high
            .iter_mut()
            .zip(std::iter::once(&self.fifo_sr).chain(self.fifos.iter()))
        {
            *h = (*h).max(f.high_water());
        }
        if let Some(e) = acc.edges.as_mut() {
            *e += self.edges(t);
        }
        Ok(t)
    }
}

/// Check that a pass's recorded work is consistent (every length and index), so the
/// engine never indexes out of range. Errors name the field (`pass_work.texels`).
pub fn validate_work(work: &PassWork) -> Result<(), ConfigError> {
    validate_textures(work)?;
    validate_rop(&work.rop)?;
    validate_fragments(work)?;
    validate_sample(work)
}

/// [`validate_work`]'s textures: lookups of 1 ..= 64 texels, no empty dimension,
/// texels of 1 ..= 64 bytes.
fn validate_textures(work: &PassWork) -> Result<(), ConfigError> {
    for (j, t) in work.textures.iter().enumerate() {
        if t.texels_per_lookup == 0 || t.texels_per_lookup > 64 {
            return Err(ConfigError::invalid(
                &format!("pass_work.textures[{j}].texels_per_lookup"),
                &format!("{} is not in 1 ..= 64", t.texels_per_lookup),
            ));
        }
        if t.size.contains(&0) {
            return Err(ConfigError::invalid(
                &format!("pass_work.textures[{j}].size"),
                "every dimension must be at least 1",
            ));
        }
        if t.texel_bytes == 0 || t.texel_bytes > 64 {
            return Err(ConfigError::invalid(
                &format!("pass_work.textures[{j}].texel_bytes"),
                &format!("{} is not in 1 ..= 64", t.texel_bytes),
            ));
        }
    }
    Ok(())
}

/// [`validate_work`]'s raster operations: at most 1024 bytes of each per fragment.
fn validate_rop(r: &RopWork) -> Result<(), ConfigError> {
    for (field, v) in [
        ("depth_read_bytes", r.depth_read_bytes),
        ("depth_write_bytes", r.depth_write_bytes),
        ("colour_read_bytes", r.colour_read_bytes),
        ("colour_write_bytes", r.colour_write_bytes),
    ] {
        if v > 1024 {
            return Err(ConfigError::invalid(
                &format!("pass_work.rop.{field}"),
                &format!("{v} bytes per fragment is not in 0 ..= 1024"),
            ));
        }
    }
    Ok(())
}

/// [`validate_work`]'s fragments: their texel indices, the primitives that hold them
/// in order, their pixels inside the framebuffer, counts that fit 32 bits.
fn validate_fragments(work: &PassWork) -> Result<(), ConfigError> {
    let n = work.fragments();
    let per = work.texels_per_fragment();
    if work.texels.len() as u64 != n as u64 * per as u64 {
        return Err(ConfigError::invalid(
            "pass_work.texels",
            &format!(
                "{} texel indices for {n} fragments × {per} texels per fragment (expected {})",
                work.texels.len(),
                n as u64 * per as u64
            ),
        ));
    }
    if work.prim_first_fragment.len() != work.prim_walked.len() {
        return Err(ConfigError::invalid(
            "pass_work.prim_walked",
            &format!(
                "{} entries for {} primitives",
                work.prim_walked.len(),
                work.prim_first_fragment.len()
            ),
        ));
    }
    if n > 0 && work.prim_first_fragment.first() != Some(&0) {
        return Err(ConfigError::invalid(
            "pass_work.prim_first_fragment",
            "the first primitive must start at fragment 0 (every fragment belongs to a primitive)",
        ));
    }
    let mut prev = 0u32;
    for &s in &work.prim_first_fragment {
        if s < prev || s as usize > n {
            return Err(ConfigError::invalid(
                "pass_work.prim_first_fragment",
                &format!("{s} is not in order within 0 ..= {n}"),
            ));
        }
        prev = s;
    }
    if n > 0 && (work.width == 0 || work.height == 0) {
        return Err(ConfigError::invalid(
            "pass_work.width",
            "a pass with fragments needs a framebuffer of at least 1 × 1",
        ));
    }
    if let Some(bad) = work
        .frag_xy
        .iter()
        .find(|p| p[0] as u32 >= work.width || p[1] as u32 >= work.height)
    {
        return Err(ConfigError::invalid(
            "pass_work.frag_xy",
            &format!(
                "pixel ({}, {}) is outside the {} × {} framebuffer",
                bad[0], bad[1], work.width, work.height
            ),
        ));
    }
    if work.prim_first_fragment.len() >= u32::MAX as usize || n >= u32::MAX as usize {
        return Err(ConfigError::invalid(
            "pass_work.frag_xy",
            "more than 2^32 − 1 fragments or primitives in one pass",
        ));
    }
    Ok(())
}

/// The checks of a sampled record: a count per primitive, at least as many fragments
/// per primitive as it holds, and only fragments of sampled bands.
fn validate_sample(work: &PassWork) -> Result<(), ConfigError> {
    let Some(s) = &work.sample else {
        return Ok(());
    };
    let b = s.bands;
    if b.band_rows == 0 || b.every == 0 {
        return Err(ConfigError::invalid(
            "pass_work.sample.bands",
            "band_rows and every must be at least 1",
        ));
    }
    let nprims = work.prim_first_fragment.len();
    for (field, len) in [
        ("prim_fragments", s.prim_fragments.len()),
        ("prim_first_xy", s.prim_first_xy.len()),
    ] {
        if len != nprims {
            return Err(ConfigError::invalid(
                &format!("pass_work.sample.{field}"),
                &format!("{len} entries for {nprims} primitives"),
            ));
        }
    }
    if let Some(p) =
        (0..nprims).find(|&p| work.prim_fragments(p).len() > s.prim_fragments[p] as usize)
    {
        return Err(ConfigError::invalid(
            "pass_work.sample.prim_fragments",
            &format!("primitive {p} holds more sampled fragments than it has"),
        ));
    }
    let k = &s.prim_first_killed;
    if !k.is_empty()
        && (k.len() != nprims
            || k.windows(2).any(|w| w[0] > w[1])
            || k.last().is_some_and(|&l| l as usize > s.killed_xy.len()))
    {
        return Err(ConfigError::invalid(
            "pass_work.sample.prim_first_killed",
            "one entry per primitive, in order, within killed_xy",
        ));
    }
    if let Some(f) = (work.frag_xy.iter())
        .chain(&s.killed_xy)
        .find(|f| !b.keeps(f[0] as u32, f[1] as u32))
    {
        return Err(ConfigError::invalid(
            "pass_work.frag_xy",
            &format!("pixel ({}, {}) is outside the sampled bands", f[0], f[1]),
        ));
    }
    Ok(())
}

/// The stage names of a chip, in report order.
pub fn stage_names(chip: &ChipConfig) -> Vec<String> {
    let mut v = vec!["setup".to_string(), "raster".to_string()];
    v.extend(chip.pipe_stages.iter().map(|s| s.name.clone()));
    v.extend(["rop", "copy", "memory"].map(String::from));
    v
}

/// The FIFO names of a chip (`<producer>_to_<consumer>`), in order.
pub fn fifo_names(chip: &ChipConfig) -> Vec<String> {
    let mut chain = vec!["raster".to_string()];
    chain.extend(chip.pipe_stages.iter().map(|s| s.name.clone()));
    chain.push("rop".to_string());
    let mut v = vec!["setup_to_raster".to_string()];
    v.extend(chain.windows(2).map(|w| format!("{}_to_{}", w[0], w[1])));
    v
}

fn hw_groups(chip: &ChipConfig, work: &PassWork) -> Vec<std::ops::Range<usize>> {
    let n = work.textures.len();
    let tpp = chip.textures_per_pass.max(1) as usize;
    if n == 0 {
        // One hardware pass that reads no texture.
        return std::iter::once(0..0).collect();
    }
    (0..n.div_ceil(tpp))
        .map(|g| g * tpp..((g + 1) * tpp).min(n))
        .collect()
}

fn new_acc(chip: &ChipConfig, window: Option<std::ops::Range<u64>>) -> Acc {
    let names = stage_names(chip);
    let fifos = fifo_names(chip);
    let window = window.map(|range| {
        let mut signals = Vec::new();
        for f in &fifos {
            let d = chip.fifo_depth as u64;
            signals.push((format!("{f}.valid"), 1));
            signals.push((format!("{f}.ready"), 1));
            signals.push((format!("{f}.level"), bits_for(d)));
        }
        signals.push((
            "memory.queue".to_string(),
            bits_for(chip.memory.queue_depth as u64),
        ));
        let n = signals.len();
        WindowBuilder {
            range,
            signals,
            last: vec![u64::MAX; n],
            changes: Vec::new(),
        }
    });
    Acc {
        counts: vec![[0; 3]; names.len()],
        timeline: TimelineBuilder::new(names.len()),
        window,
        offset: 0,
        overhead: 0,
        fifo_high: vec![0; fifos.len()],
        hits: 0,
        misses: 0,
        bytes: [0; 4],
        mem_busy: 0,
        edges: None,
    }
}

/// The engine for `work` on `chip`, before its first hardware pass: the surfaces laid
/// out in memory (colour, depth, then each texture, on 1 MiB boundaries), the caches,
/// the memory controller, the FIFOs and the pipe stages.
fn new_engine<'a>(chip: &'a ChipConfig, work: &'a PassWork, quads: &'a Quads) -> Engine<'a> {
    let colour = Surface::new(0, [work.width, work.height, 1], 4, chip.framebuffer_layout);
    let align = |v: u64| (v + (1 << 20) - 1) & !((1 << 20) - 1);
    let depth = Surface::new(
        align(colour.bytes()),
        [work.width, work.height, 1],
        4,
        chip.framebuffer_layout,
    );
    let mut base = align(depth.base + depth.bytes());
    let mut tex = Vec::with_capacity(work.textures.len());
    let mut offset = 0;
    for t in &work.textures {
        let surface = Surface::new(base, t.size, t.texel_bytes, chip.texture_layout);
        base = align(base + surface.bytes());
        tex.push(TexInfo {
            surface: SurfaceTable::new(surface),
            offset,
            per_lookup: t.texels_per_lookup as usize,
        });
        offset += t.texels_per_lookup as usize;
    }
    let cc = &chip.texture_cache;
    let n_caches = if cc.size_bytes == 0 {
        0
    } else if cc.shared {
        1
    } else {
        (chip.pipes * chip.tmus_per_pipe) as usize
    };
    let depth_fifo = chip.fifo_depth as usize;
    let pipes = chip
        .pipe_stages
        .iter()
        .map(|s| {
            let texture = s.kind == StageKind::Texture;
            let cap = if texture {
                depth_fifo + s.latency as usize
            } else {
                (s.latency as usize).div_ceil(s.ii as usize) + 1
            };
            PipeUnit {
                latency: s.latency as u64,
                ii: s.ii as u64,
                texture,
                next_accept: 0,
                flight: Ring::with_capacity(cap),
                cap,
            }
        })
        .collect::<Vec<_>>();
    let n_stages = pipes.len() + 5;
    Engine {
        chip,
        work,
        quads,
        tex,
        stride: offset,
        colour,
        depth,
        caches: (0..n_caches).map(|_| Cache::new(cc)).collect(),
        mem: Memory::new(&chip.memory),
        fifo_sr: Fifo::new(depth_fifo),
        fifos: (0..=chip.pipe_stages.len())
            .map(|_| Fifo::new(depth_fifo))
            .collect(),
        pipes,
        rop_flight: Ring::with_capacity(depth_fifo),
        rop_next_accept: 0,
        rop_retired: 0,
        next_prim: 0,
        setup_hold: None,
        setup_until: 0,
        r_active: false,
        r_quad: 0,
        r_start: 0,
        r_end: 0,
        r_total: 0,
        r_base: 0,
        r_due: 0,
        lanes_of: [0, 1, 2, 3, 4].map(|n: u64| n.div_ceil(chip.pipes as u64).max(1)),
        tex_rounds: 1,
        copy_read_left: 0,
        copy_write_left: 0,
        copy_toggle: false,
        group: 0..0,
        cls: vec![STARVED; n_stages],
        uncached: 0,
        cache_of: Vec::new(),
        ahead: None,
        first_retire: u64::MAX,
        busy: vec![BusySpan::default(); n_stages],
    }
}

/// Clock `work` on `chip` into `acc` (its clocks appended after `acc.offset`).
fn run_pass(chip: &ChipConfig, work: &PassWork, acc: &mut Acc) -> Result<u32, ConfigError> {
    let quads = build_quads(work);
    let mut e = new_engine(chip, work, &quads);
    let n_stages = e.n_stages();
    let groups = hw_groups(chip, work);
    let overhead = chip.pass_overhead_clocks as u64;
    let last = groups.len() - 1;
    for (g, group) in groups.iter().enumerate() {
        // The pass overhead: every stage idle.
        if overhead > 0 {
            e.cls.fill(STARVED);
            e.fifo_sr.clear();
            for f in &mut e.fifos {
                f.clear();
            }
            e.record(acc, 0, overhead);
            acc.offset += overhead;
            acc.overhead += overhead;
        }
        let clocks = e.run_hw_pass(acc, group.clone(), g == last)?;
        acc.offset += clocks;
    }
    acc.mem_busy = acc.counts[n_stages - 1][BUSY as usize];
    for c in &e.caches {
        acc.hits += c.hits;
        acc.misses += c.misses;
    }
    // No cache: every texel fetch is a memory request (a miss).
    acc.misses += e.uncached;
    for (b, m) in acc.bytes.iter_mut().zip(e.mem.bytes) {
        *b += m;
    }
    Ok(groups.len() as u32)
}

fn finish(chip: &ChipConfig, acc: Acc, hardware_passes: u32) -> PassTiming {
    let names = stage_names(chip);
    let cycles = acc.offset;
    let stages: Vec<StageClocks> = names
        .iter()
        .zip(&acc.counts)
        .map(|(n, c)| StageClocks {
            name: n.clone(),
            busy: c[0],
            stalled: c[1],
            starved: c[2],
        })
        .collect();
    let fifos = fifo_names(chip)
        .into_iter()
        .zip(&acc.fifo_high)
        .map(|(name, &h)| FifoHighWater {
            name,
            depth: chip.fifo_depth,
            high_water: h as u32,
        })
        .collect();
    let bytes_by_client: BTreeMap<String, u64> = CLIENT_NAMES
        .iter()
        .zip(acc.bytes)
        .map(|(n, b)| (n.to_string(), b))
        .collect();
    let bottleneck = bottleneck(&stages, &acc.bytes, cycles - acc.overhead.min(cycles));
    let window = acc.window.and_then(|w| {
        (w.range.start < cycles).then(|| WindowTrace {
            start_clock: w.range.start,
            end_clock: w.range.end.min(cycles),
            signals: w.signals,
            changes: w.changes,
        })
    });
    PassTiming {
        cycles,
        hardware_passes,
        stages,
        fifos,
        cache_hits: acc.hits,
        cache_misses: acc.misses,
        bytes_by_client,
        bottleneck,
        timeline: acc.timeline.finish(&acc.counts, names, cycles),
        window,
    }
}

/// The bottleneck rule (module comment): memory when its channel was busy in ≥ 90 % of
/// the working clocks (named by the client that moved the most bytes), else the stage
/// with the most busy clocks ("none" when no stage was busy).
fn bottleneck(stages: &[StageClocks], bytes: &[u64; 4], working: u64) -> String {
    let mem = stages.last().map_or(0, |s| s.busy);
    if working > 0 && mem as f64 >= MEMORY_SATURATED * working as f64 {
        let mut best = 0;
        for c in 1..4 {
            if bytes[c] > bytes[best] {
                best = c;
            }
        }
        return format!("memory ({})", CLIENT_NAMES[best]);
    }
    let mut best: Option<&StageClocks> = None;
    for s in &stages[..stages.len().saturating_sub(1)] {
        if best.is_none_or(|b| s.busy > b.busy) {
            best = Some(s);
        }
    }
    match best {
        Some(s) if s.busy > 0 => s.name.clone(),
        // Nothing was busy (a pass with no work but its overhead).
        _ => "none".to_string(),
    }
}

/// Clock one pass's work on a chip. `window` (clocks relative to the pass's start)
/// asks for the chip-level signals over that range. The chip and the work are checked
/// first; an error names the field at fault.
pub fn clock_pass(
    chip: &ChipConfig,
    work: &PassWork,
    window: Option<std::ops::Range<u64>>,
) -> Result<PassTiming, ConfigError> {
    chip.validate()?;
    validate_work(work)?;
    check_stages(chip, work)?;
    let mut acc = new_acc(chip, window);
    let hw = run_pass(chip, work, &mut acc)?;
    Ok(finish(chip, acc, hw))
}

fn check_stages(chip: &ChipConfig, work: &PassWork) -> Result<(), ConfigError> {
    if !work.textures.is_empty()
        && !chip
            .pipe_stages
            .iter()
            .any(|s| s.kind == StageKind::Texture)
    {
        return Err(ConfigError::invalid(
            "chip.pipe_stages",
            "the pass reads textures but the chip has no Texture stage",
        ));
    }
    Ok(())
}

/// Pixel rows of one unit of the sampled mode: one 8-row tile row of the walk.
pub const SAMPLE_BAND_ROWS: u32 = 8;
/// Pixel columns of one unit of the sampled mode (0: the full width).
pub const SAMPLE_BLOCK_COLS: u32 = 0;
/// Groups the sampled bands are dealt into (band k of the sample to group k mod 4),
/// each clocked as a stream of its own: the spread between the groups is the error
/// estimate (batch means).
pub const SAMPLE_GROUPS: usize = 4;

/// Sampled mode: clock the fragments of a deterministic sample of full-width screen
/// bands exactly and scale to the whole pass.
///
/// Band b (rows [8b, 8b + 8)) is sampled when b mod `every` = 0 (a record made in
/// sampled mode carries its own bands and holds only their fragments; a full record
/// is cut to them first, [`PassWork::sampled`]). The sampled bands are dealt round
/// robin, top to bottom, into 4 groups, each clocked as one stream (no pass overhead):
/// every primitive in draw order with its fragments in the group's bands, its walk and
/// depth-killed fragments in proportion to the fragments kept. A primitive is set up
/// in the group whose band holds its first fragment; its pieces in other groups ride
/// along with the primitive before them (one set-up per primitive, as in the full
/// pass). A primitive without fragments (it walks a bounding box and covers nothing)
/// goes, whole, to one in `every` of them by its rank among such primitives.
///
/// Scaling: a group's clocks c_g less its fill and drain a_g (the clocks its busiest
/// resource sat idle before the first quad retired and after its own last busy clock,
/// paid once by the full pass) are set against a per-primitive proxy x_g, Σ (set-up +
/// (walk + fragments) ÷ pipes) over its pieces; the pass's clocks are R·X + ā +
/// hardware passes × overhead, R = Σ(c_g − a_g) / Σx_g (a ratio estimator) and X the
/// proxy over every primitive.
/// The relative standard error returned is that of R from the spread between the
/// groups, √(Σ(c_g − a_g − R·x_g)² / (G(G − 1))) / (x̄·R). Counters (stage clocks,
/// bytes, cache hits and misses) are scaled the same way; the timeline shows the
/// groups back to back. `every` ≤ 1 or a pass without fragments is clocked in full
/// (error 0); a sample with work in fewer than two groups states an error of 1 (its
/// spread is unknown).
pub fn clock_pass_sampled(
    chip: &ChipConfig,
    work: &PassWork,
    every: u32,
) -> Result<(PassTiming, f64), ConfigError> {
    chip.validate()?;
    validate_work(work)?;
    check_stages(chip, work)?;
    let full = |chip: &ChipConfig| -> Result<(PassTiming, f64), ConfigError> {
        let mut acc = new_acc(chip, None);
        let hw = run_pass(chip, work, &mut acc)?;
        Ok((finish(chip, acc, hw), 0.0))
    };
    // Nothing to sample (a copy, primitives without fragments: the record is whole).
    if work.all_fragments() == 0 || (work.sample.is_none() && every <= 1) {
        return full(chip);
    }
    let cut;
    let work = match &work.sample {
        Some(_) => work,
        None => {
            cut = work.sampled(SampleBands {
                band_rows: SAMPLE_BAND_ROWS,
                block_cols: SAMPLE_BLOCK_COLS,
                every,
            });
            &cut
        }
    };
    let mut inner = chip.clone();
    inner.pass_overhead_clocks = 0;
    let streams = sample_streams(chip, work);
    let x_total = proxy_total(chip, work);
    let mut acc = new_acc(&inner, None);
    acc.edges = Some(0);
    let mut cx = Vec::with_capacity(streams.len());
    let mut edges = Vec::with_capacity(streams.len());
    let mut hw = hw_groups(chip, work).len() as u32;
    for (mut gw, x) in streams.into_iter().filter(|s| s.1 > 0.0) {
        // The copy's bytes shared by the groups in proportion to their proxy (scaled
        // back with the rest by X / Σx_g).
        gw.copy_read_bytes = (work.copy_read_bytes as f64 * x / x_total) as u64;
        gw.copy_write_bytes = (work.copy_write_bytes as f64 * x / x_total) as u64;
        let (before, e0) = (acc.offset, acc.edges.unwrap_or(0));
        hw = run_pass(&inner, &gw, &mut acc)?;
        let a = acc.edges.unwrap_or(0) - e0;
        cx.push(((acc.offset - before).saturating_sub(a) as f64, x));
        edges.push(a as f64);
    }
    let overhead = hw as u64 * chip.pass_overhead_clocks as u64;
    if cx.is_empty() {
        // Nothing of the pass fell in the sample: the proxy alone (a lower bound).
        let t = finish(&inner, acc, hw);
        return Ok((scale_sampled(t, x_total.round() as u64, overhead, 0.0), 1.0));
    }
    let (r, rse) = ratio_estimate(&cx);
    let x_sum: f64 = cx.iter().map(|c| c.1).sum();
    let a_mean = edges.iter().sum::<f64>() / edges.len() as f64;
    let t = finish(&inner, acc, hw);
    let work_clocks = (r * x_total + a_mean).round() as u64;
    let rse = if cx.len() < 2 { 1.0 } else { rse };
    Ok((
        scale_sampled(t, work_clocks, overhead, x_total / x_sum),
        rse,
    ))
}

/// The proxy of a piece of a primitive: set-up + walk ÷ pipes + fragments ÷ pipes.
/// A sum, not a maximum, so that a primitive's pieces add up to the primitive (a
/// maximum would count a set-up-bound primitive's walk again in every piece set up
/// elsewhere).
fn proxy(chip: &ChipConfig, setup: bool, walked: u64, killed: u64, frags: u64) -> f64 {
    let pipes = chip.pipes.max(1) as u64;
    let walk = match chip.raster_walk {
        RasterWalk::BoundingBox => walked,
        RasterWalk::CoveredQuads => frags + killed,
    };
    let s = if setup {
        chip.setup_clocks_per_triangle as u64
    } else {
        0
    };
    s as f64 + (walk + frags) as f64 / pipes as f64
}

/// The proxy over every primitive of a sampled record (each set up once).
fn proxy_total(chip: &ChipConfig, work: &PassWork) -> f64 {
    let Some(s) = &work.sample else {
        return 0.0;
    };
    (0..work.prim_walked.len())
        .map(|p| {
            let killed = work.prim_depth_killed.get(p).copied().unwrap_or(0) as u64;
            let frags = s.prim_fragments[p] as u64;
            proxy(chip, true, work.prim_walked[p] as u64, killed, frags)
        })
        .sum()
}

/// A primitive's share `kept / total` of `v`, rounded (all of it when it has no
/// fragments).
fn share(v: u32, kept: u32, total: u32) -> u32 {
    if total == 0 {
        return v;
    }
    ((v as u64 * kept as u64 + total as u64 / 2) / total as u64) as u32
}

/// A piece of a primitive into a group's stream: `walk` pixels walked and `killed`
/// depth-killed fragments (`None`: the pass has no depth test). Set up here, or the
/// group's first piece, it starts a primitive; else it is part of the walk of the
/// primitive before it (a primitive set up in another group).
fn add_piece(gw: &mut PassWork, set_up: bool, walk: u32, killed: Option<u32>) {
    if set_up || gw.prim_walked.is_empty() {
        gw.prim_first_fragment.push(gw.frag_xy.len() as u32);
        gw.prim_walked.push(walk);
        gw.prim_depth_killed.extend(killed);
    } else {
        *gw.prim_walked.last_mut().unwrap_or(&mut 0) += walk;
        if let (Some(k), Some(more)) = (gw.prim_depth_killed.last_mut(), killed) {
            *k += more;
        }
    }
}

/// The sampled record's groups as streams of their own, each with its proxy
/// ([`clock_pass_sampled`] describes the deal).
fn sample_streams(chip: &ChipConfig, work: &PassWork) -> Vec<(PassWork, f64)> {
    let Some(s) = &work.sample else {
        return Vec::new();
    };
    let bands = s.bands;
    let every = bands.every.max(1);
    // The group of a sampled pixel's unit.
    let group_of = |[x, y]: [u16; 2]| (bands.rank(x as u32, y as u32) as usize) % SAMPLE_GROUPS;
    let per = work.texels_per_fragment();
    let mut out: Vec<(PassWork, f64)> = (0..SAMPLE_GROUPS)
        .map(|_| {
            let w = PassWork {
                width: work.width,
                height: work.height,
                textures: work.textures.clone(),
                rop: work.rop,
                ..PassWork::default()
            };
            (w, 0.0)
        })
        .collect();
    let depth_tested = !work.prim_depth_killed.is_empty();
    // Whether the killed fragments' places are known (a record made in sampled mode).
    let known = depth_tested && !s.prim_first_killed.is_empty();
    let mut zero_rank = 0u32;
    let mut frag_group: Vec<u8> = Vec::new();
    for p in 0..work.prim_first_fragment.len() {
        let r = work.prim_fragments(p);
        let total = s.prim_fragments[p];
        let killed = work.prim_depth_killed.get(p).copied().unwrap_or(0);
        // The group that sets the primitive up, if any: where its first visible
        // fragment is, else (none visible) one in `every` by rank.
        let home = if total > 0 {
            let [x, y] = s.prim_first_xy[p];
            bands.keeps(x as u32, y as u32).then(|| group_of([x, y]))
        } else {
            let z = zero_rank;
            zero_rank += 1;
            z.is_multiple_of(every)
                .then(|| ((z / every) as usize) % SAMPLE_GROUPS)
        };
        frag_group.clear();
        frag_group.extend(r.clone().map(|f| group_of(work.frag_xy[f]) as u8));
        let mut count = [0u32; SAMPLE_GROUPS];
        for &g in &frag_group {
            count[g as usize] += 1;
        }
        let mut kcount = [0u32; SAMPLE_GROUPS];
        if known {
            for &xy in s.killed_of(p) {
                kcount[group_of(xy)] += 1;
            }
        }
        // The candidates (visible and killed) whose places the record knows.
        let located = total + if known { killed } else { 0 };
        for (g, (gw, x)) in out.iter_mut().enumerate() {
            let set_up = home == Some(g);
            let here = count[g] + kcount[g];
            if !set_up && here == 0 {
                continue;
            }
            let (walk, kill) = if located == 0 {
                // Nothing placed: the primitive whole, in its one group.
                (work.prim_walked[p], killed)
            } else if known {
                (share(work.prim_walked[p], here, located), kcount[g])
            } else {
                let k = share(killed, count[g], total);
                (share(work.prim_walked[p], count[g], total), k)
            };
            *x += proxy(chip, set_up, walk as u64, kill as u64, count[g] as u64);
            add_piece(gw, set_up, walk, depth_tested.then_some(kill));
        }
        for (f, &g) in r.zip(&frag_group) {
            let gw = &mut out[g as usize].0;
            gw.frag_xy.push(work.frag_xy[f]);
            gw.texels
                .extend_from_slice(&work.texels[f * per..(f + 1) * per]);
        }
    }
    out
}

/// The ratio estimate of clocks per fragment over the groups' (clocks, fragments), and
/// its relative standard error from the spread between the groups.
fn ratio_estimate(cn: &[(f64, f64)]) -> (f64, f64) {
    let c_sum: f64 = cn.iter().map(|c| c.0).sum();
    let n_sum: f64 = cn.iter().map(|c| c.1).sum();
    let r = c_sum / n_sum;
    let gk = cn.len() as f64;
    let var: f64 = cn.iter().map(|&(c, m)| (c - r * m).powi(2)).sum::<f64>() / (gk * (gk - 1.0));
    let rse = if r > 0.0 {
        var.sqrt() / (n_sum / gk * r)
    } else {
        0.0
    };
    (r, rse)
}

/// A pass's timing scaled to `cycles` (another pass of its kind, estimated from it):
/// stage clocks in proportion, counts and bytes by `f`, the bottleneck named again.
pub fn scale_timing(t: PassTiming, cycles: u64, f: f64) -> PassTiming {
    scale_sampled(t, cycles, 0, f)
}

/// The sampled groups' timing scaled to the whole pass: `work_clocks` of estimated work
/// plus `overhead`; stage clocks scaled to the work, counts and bytes by `f` (all
/// fragments over the sampled ones); the bottleneck named again on the scaled figures.
fn scale_sampled(mut t: PassTiming, work_clocks: u64, overhead: u64, f: f64) -> PassTiming {
    let cycles = work_clocks + overhead;
    let s = if t.cycles > 0 {
        work_clocks as f64 / t.cycles as f64
    } else {
        0.0
    };
    for st in &mut t.stages {
        st.busy = (st.busy as f64 * s).round() as u64;
        st.stalled = (st.stalled as f64 * s).round() as u64;
        st.starved = cycles.saturating_sub(st.busy + st.stalled);
        if st.busy + st.stalled > cycles {
            st.stalled = cycles - st.busy.min(cycles);
            st.busy = st.busy.min(cycles);
        }
    }
    let scale = |v: u64| (v as f64 * f).round() as u64;
    t.cache_hits = scale(t.cache_hits);
    t.cache_misses = scale(t.cache_misses);
    for v in t.bytes_by_client.values_mut() {
        *v = scale(*v);
    }
    let bytes: Vec<u64> = CLIENT_NAMES
        .iter()
        .map(|c| t.bytes_by_client.get(*c).copied().unwrap_or(0))
        .collect();
    t.bottleneck = bottleneck(
        &t.stages,
        &[bytes[0], bytes[1], bytes[2], bytes[3]],
        work_clocks,
    );
    t.cycles = cycles;
    t
}
