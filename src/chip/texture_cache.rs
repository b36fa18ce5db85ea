//! The texture cache and the address mapping of surfaces.
//!
//! - [`Surface`] maps a texel (or pixel) index to a byte address under a [`Layout`]:
//!   linear rows, rectangular tiles, or Morton (Z-order) swizzling.
//! - [`Cache`] is a set-associative cache of lines (LRU or FIFO replacement) keyed by
//!   line address. Each line remembers the memory read that fills it, so a lookup that
//!   hits a line still in flight waits for the same read (the fill-on-miss
//!   organisation of Igehy, Eldridge and Proudfoot, "Prefetching in a texture cache
//!   architecture", Graphics Hardware 1998).
//!
//! Every texel fetch is one cache access (a bilinear lookup is four), so the hit rate
//! compares with the roofline's assumed fraction of texel bytes absorbed.

use super::config::{CacheConfig, Layout, Replacement};

/// A surface in memory: its base address, dimensions, bytes per element and layout.
#[derive(Clone, Copy, Debug)]
pub struct Surface {
    pub base: u64,
    pub size: [u32; 3],
    pub elem_bytes: u32,
    pub layout: Layout,
    /// log2 of the power-of-two padded width and height (for the swizzled layout).
    pow2_bits: [u32; 2],
    /// Elements per z slice in memory (padded for swizzled and tiled layouts).
    slice: u64,
    /// Tiles per row (tiled layout).
    tiles_x: u64,
    /// log2 of the width and height when both are powers of two (index → x, y, z by
    /// shifts), else `None` (by division).
    shifts: Option<(u32, u32)>,
}

fn ceil_log2(v: u32) -> u32 {
    if v <= 1 {
        0
    } else {
        32 - (v - 1).leading_zeros()
    }
}

/// Spread the low 16 bits of `v` to the even bit positions.
#[inline(always)]
fn spread(v: u32) -> u64 {
    let mut x = v as u64 & 0xffff;
    x = (x | (x << 8)) & 0x00ff_00ff;
    x = (x | (x << 4)) & 0x0f0f_0f0f;
    x = (x | (x << 2)) & 0x3333_3333;
    x = (x | (x << 1)) & 0x5555_5555;
    x
}

/// Morton index of (x, y) in a 2^bx × 2^by rectangle: the low min(bx, by) bits of x
/// and y interleaved (x in the even bits), the remaining high bits of the longer axis
/// above them.
#[inline(always)]
pub fn morton(x: u32, y: u32, bx: u32, by: u32) -> u64 {
    let m = bx.min(by);
    let mask = (1u32 << m) - 1;
    let low = spread(x & mask) | (spread(y & mask) << 1);
    let high = if bx > by {
        (x >> m) as u64
    } else {
        (y >> m) as u64
    };
    low | (high << (2 * m))
}

impl Surface {
    pub fn new(base: u64, size: [u32; 3], elem_bytes: u32, layout: Layout) -> Self {
        let (w, h) = (size[0].max(1), size[1].max(1));
        let pow2_bits = [ceil_log2(w), ceil_log2(h)];
        let (slice, tiles_x) = match layout {
            Layout::Linear => (w as u64 * h as u64, 1),
            Layout::Tiled { w: tw, h: th } => {
                let tx = w.div_ceil(tw.max(1)) as u64;
                let ty = h.div_ceil(th.max(1)) as u64;
                (tx * ty * tw as u64 * th as u64, tx)
            }
            Layout::Swizzled => (1u64 << (pow2_bits[0] + pow2_bits[1]), 1),
        };
        Surface {
            base,
            size: [w, h, size[2].max(1)],
            elem_bytes: elem_bytes.max(1),
            layout,
            pow2_bits,
            slice,
            tiles_x,
            shifts: (w.is_power_of_two() && h.is_power_of_two())
                .then(|| (w.trailing_zeros(), h.trailing_zeros())),
        }
    }

    /// Bytes the surface occupies.
    pub fn bytes(&self) -> u64 {
        self.slice * self.size[2] as u64 * self.elem_bytes as u64
    }

    /// The byte address of element (x, y, z).
    #[inline(always)]
    pub fn address_xyz(&self, x: u32, y: u32, z: u32) -> u64 {
        let w = self.size[0];
        let elem = match self.layout {
            Layout::Linear => x as u64 + w as u64 * y as u64,
            Layout::Tiled { w: tw, h: th } => {
                let tile = (y / th) as u64 * self.tiles_x + (x / tw) as u64;
                tile * (tw as u64 * th as u64) + ((y % th) * tw + x % tw) as u64
            }
            Layout::Swizzled => morton(x, y, self.pow2_bits[0], self.pow2_bits[1]),
        };
        self.base + (z as u64 * self.slice + elem) * self.elem_bytes as u64
    }

    /// The byte address of element index `i` = x + w·(y + h·z).
    #[inline(always)]
    pub fn address(&self, i: u32) -> u64 {
        if let Layout::Linear = self.layout {
            return self.base + i as u64 * self.elem_bytes as u64;
        }
        if let Some((sw, sh)) = self.shifts {
            let x = i & ((1 << sw) - 1);
            let r = i >> sw;
            return self.address_xyz(x, r & ((1 << sh) - 1), r >> sh);
        }
        let (w, h) = (self.size[0], self.size[1]);
        let x = i % w;
        let r = i / w;
        self.address_xyz(x, r % h, r / h)
    }
}

/// Exact division of a 32-bit index by a fixed divisor by one multiply: the quotient
/// is the high half of i · ⌈2^64 / d⌉ (exact for every i < 2^32 and d < 2^32: the
/// rounding error of the reciprocal, below d ÷ 2^64 per unit of i, stays under 1 ÷ d),
/// for the texel index → (x, y, z) split of a texture whose sides are not powers of two.
#[derive(Clone, Copy, Debug)]
struct Divisor {
    d: u32,
    magic: u64,
}

impl Divisor {
    fn new(d: u32) -> Self {
        let d = d.max(1);
        let magic = if d == 1 { 0 } else { u64::MAX / d as u64 + 1 };
        Divisor { d, magic }
    }

    /// (i ÷ d, i mod d).
    #[inline(always)]
    fn div_rem(&self, i: u32) -> (u32, u32) {
        if self.d == 1 {
            return (i, 0);
        }
        let q = ((i as u128 * self.magic as u128) >> 64) as u32;
        (q, i - q * self.d)
    }
}

/// A [`Surface`]'s index → byte address mapping with the layout folded into two
/// tables, one per axis (every layout's element offset is a sum of a part that depends
/// on x alone and one on y alone: Morton interleaves x's and y's bits into disjoint
/// positions, tiles add a column and a row term), so a texel's address is two loads
/// and two adds instead of a bit-spreading swizzle per texel. Gives exactly
/// [`Surface::address`] (tests/chip_clock.rs checks every layout).
#[derive(Clone, Debug)]
pub struct SurfaceTable {
    surface: Surface,
    /// Byte offset of column x and of row y from the slice's start.
    col: Vec<u64>,
    row: Vec<u64>,
    /// Bytes per z slice.
    slice_bytes: u64,
    w: Divisor,
    h: Divisor,
}

impl SurfaceTable {
    pub fn new(surface: Surface) -> Self {
        let [w, h, _] = surface.size;
        let base = surface.base;
        let (col, row) = match surface.layout {
            // Linear needs no table (the index is the element).
            Layout::Linear => (Vec::new(), Vec::new()),
            _ => (
                (0..w)
                    .map(|x| surface.address_xyz(x, 0, 0) - base)
                    .collect(),
                (0..h)
                    .map(|y| surface.address_xyz(0, y, 0) - base)
                    .collect(),
            ),
        };
        SurfaceTable {
            surface,
            col,
            row,
            slice_bytes: surface.slice * surface.elem_bytes as u64,
            w: Divisor::new(w),
            h: Divisor::new(h),
        }
    }

    pub fn surface(&self) -> &Surface {
        &self.surface
    }

    /// The byte address of element index `i` = x + w·(y + h·z), as
    /// [`Surface::address`] gives it.
    #[inline(always)]
    pub fn address(&self, i: u32) -> u64 {
        let s = &self.surface;
        if let Layout::Linear = s.layout {
            return s.base + i as u64 * s.elem_bytes as u64;
        }
        let (x, y, z) = if let Some((sw, sh)) = s.shifts {
            let r = i >> sw;
            (i & ((1 << sw) - 1), r & ((1 << sh) - 1), r >> sh)
        } else {
            let (r, x) = self.w.div_rem(i);
            let (z, y) = self.h.div_rem(r);
            (x, y, z)
        };
        // x < w and y < h by construction: the indexing cannot fail.
        s.base + z as u64 * self.slice_bytes + self.col[x as usize] + self.row[y as usize]
    }
}

/// Result of one cache access.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// The line is present; `fill` is the memory read that filled it (the access waits
    /// until that read has arrived).
    Hit { fill: u64 },
    /// The line was absent and is now allocated; the caller issues the read and the line
    /// records `fill`.
    Miss,
}

/// A set-associative cache of `line_bytes` lines.
#[derive(Clone, Debug)]
pub struct Cache {
    line_shift: u32,
    sets_mask: u64,
    ways: usize,
    replacement: Replacement,
    /// tags[set·ways + way]: line address, u64::MAX empty.
    tags: Vec<u64>,
    /// Recency (LRU) or insertion (FIFO) stamp; 0 for an empty way.
    stamps: Vec<u64>,
    /// The memory read that fills each way.
    fills: Vec<u64>,
    stamp: u64,
    /// The last line accessed (it is its set's most recent: a hit on it changes
    /// nothing), its way slot.
    last_line: u64,
    last_slot: usize,
    pub hits: u64,
    pub misses: u64,
}

impl Cache {
    /// A cache as configured; `size_bytes` must be a power-of-two number of sets times
    /// ways times line bytes (validated by `ChipConfig::validate`).
    pub fn new(cfg: &CacheConfig) -> Self {
        let lines = (cfg.size_bytes / cfg.line_bytes.max(1)).max(1) as usize;
        let ways = (cfg.ways.max(1) as usize).min(lines);
        let sets = (lines / ways).max(1);
        Cache {
            line_shift: cfg.line_bytes.max(1).trailing_zeros(),
            sets_mask: sets as u64 - 1,
            ways,
            replacement: cfg.replacement,
            tags: vec![u64::MAX; sets * ways],
            stamps: vec![0; sets * ways],
            fills: vec![0; sets * ways],
            stamp: 0,
            last_line: u64::MAX,
            last_slot: 0,
            hits: 0,
            misses: 0,
        }
    }

    /// The line address of a byte address.
    #[inline]
    pub fn line_of(&self, addr: u64) -> u64 {
        addr >> self.line_shift
    }

    /// Bytes per line.
    pub fn line_bytes(&self) -> u32 {
        1 << self.line_shift
    }

    /// Access line `line`; on a miss the victim way is replaced and records `fill`
    /// (the read the caller issues).
    #[inline]
    pub fn access(&mut self, line: u64, fill: u64) -> Access {
        if line == self.last_line {
            self.hits += 1;
            return Access::Hit {
                fill: self.fills[self.last_slot],
            };
        }
        let set = (line & self.sets_mask) as usize;
        let base = set * self.ways;
        let ways = &mut self.tags[base..base + self.ways];
        self.stamp += 1;
        if let Some(w) = ways.iter().position(|&t| t == line) {
            let slot = base + w;
            if self.replacement == Replacement::Lru {
                self.stamps[slot] = self.stamp;
            }
            self.hits += 1;
            self.last_line = line;
            self.last_slot = slot;
            return Access::Hit {
                fill: self.fills[slot],
            };
        }
        // Victim: an empty way (stamp 0) or the oldest stamp; the lowest way on ties.
        let stamps = &self.stamps[base..base + self.ways];
        let mut victim = 0;
        for (w, &s) in stamps.iter().enumerate() {
            if s < stamps[victim] {
                victim = w;
            }
        }
        let slot = base + victim;
        self.tags[slot] = line;
        self.stamps[slot] = self.stamp;
        self.fills[slot] = fill;
        self.misses += 1;
        self.last_line = line;
        self.last_slot = slot;
        Access::Miss
    }

    /// Empty every line (counters kept).
    pub fn flush(&mut self) {
        self.tags.fill(u64::MAX);
        self.stamps.fill(0);
        self.last_line = u64::MAX;
    }
}
