//! Drawing primitives through the polygon interpolator: set-up, the serpentine walk
//! (span driver), and the viewport scissor. Walked pixels outside the primitive or
//! the viewport still cost the walker its clocks (counted); only covered pixels
//! inside the viewport come out as fragments.

use std::cell::RefCell;
use std::ops::{Range, RangeInclusive};

use rtl_model::driver::SpanTally;
use rtl_model::error::ConfigError;
use rtl_model::units::polygon_interpolator::{
    Move, PolyLanes, PolyOut, PolySetup, PolygonInterpolator, Vertex, MAX_ATTRS,
};
use rtl_model::{Counters, Unit};

/// A covered pixel and its interpolated attributes (raw output codes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fragment {
    pub x: u32,
    pub y: u32,
    pub attrs: [i64; MAX_ATTRS],
}

/// A vertex as the host computes it: screen position in pixels (y down) and attributes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HostVertex {
    pub x: f64,
    pub y: f64,
    pub attrs: [f64; MAX_ATTRS],
}

impl HostVertex {
    /// At the origin with every attribute zero: what a triangle's vertices start as
    /// before the host fills them in.
    pub const ORIGIN: HostVertex = HostVertex {
        x: 0.0,
        y: 0.0,
        attrs: [0.0; MAX_ATTRS],
    };
}

/// Host attributes for a vertex: the `N` given, then zeros up to `MAX_ATTRS` (a unit
/// configured for k ≤ N attributes reads the first k). `N > MAX_ATTRS` does not compile.
pub fn host_attrs<const N: usize>(a: [f64; N]) -> [f64; MAX_ATTRS] {
    const { assert!(N <= MAX_ATTRS) };
    let mut out = [0.0; MAX_ATTRS];
    out[..N].copy_from_slice(&a);
    out
}

/// Quantise host vertices into the interpolator's vertex words (errors name the field).
pub fn quantise<const N: usize>(
    u: &PolygonInterpolator,
    v: &[HostVertex; N],
    ctr: &mut Counters,
) -> Result<[Vertex; N], ConfigError> {
    let k = u.attrs() as usize;
    let mut out = [Vertex::default(); N];
    for (i, hv) in v.iter().enumerate() {
        out[i] = u.vertex_from_f64(i, hv.x, hv.y, &hv.attrs[..k], ctr)?;
    }
    Ok(out)
}

/// Buffers of a walk fed to the interpolator in chunks of whole bounding-box rows, reused
/// from row to row and primitive to primitive (no allocation per fragment).
#[derive(Clone, Debug, Default)]
pub struct WalkBuffers {
    moves: Vec<Move>,
    runs: Vec<(Move, usize)>,
    /// Each run's blank attributes ([`walk_rows_lanes_blank`]).
    blanks: Vec<u32>,
    outs: Vec<PolyOut>,
    frags: Vec<Fragment>,
    lanes: PolyLanes,
    /// Attributes whose lanes [`walk_rows_lanes`] leaves unwritten (bit a for
    /// attribute a; [`PolyLanes::clear_unread`]).
    unread: u32,
    /// Whether [`walk_rows_lanes`] appends covered words alone
    /// ([`PolyLanes::covered_only`]).
    covered_only: bool,
}

impl WalkBuffers {
    /// Buffers for a walk whose sink reads none of the attributes in the mask
    /// `unread` (bit a for attribute a): [`walk_rows_lanes`] leaves their lanes empty
    /// (still computed and counted by the interpolator).
    pub fn unread(unread: u32) -> Self {
        WalkBuffers {
            unread,
            ..WalkBuffers::default()
        }
    }

    /// [`WalkBuffers::unread`] for a sink that reads covered words alone:
    /// [`walk_rows_lanes`] leaves out the rest of each row ([`PolyLanes::covered_only`]).
    pub fn covered(unread: u32) -> Self {
        WalkBuffers {
            covered_only: true,
            ..WalkBuffers::unread(unread)
        }
    }
}

/// Moves of the walk fed to the interpolator at a time (whole bounding-box rows).
pub const WALK_CHUNK_MOVES: usize = 2048;

/// Walk one set-up primitive through the interpolator's batch kernel in chunks of
/// whole bounding-box rows (at least [`WALK_CHUNK_MOVES`] moves, or the rest), handing
/// each chunk's raw outputs (every walked pixel, covered or not, inside the viewport
/// or not) to `sink` in walk order. The counters are those
/// of one span over the whole walk, as [`walk`] counts them.
pub fn walk_rows_raw(
    u: &PolygonInterpolator,
    s: &PolySetup,
    ctr: &mut Counters,
    buf: &mut WalkBuffers,
    mut sink: impl FnMut(&[PolyOut]),
) {
    let mut st = s.state.clone();
    let mut tally = SpanTally::new();
    let rows = s.bbox.map_or(0, |b| b.height());
    buf.moves.clear();
    for row in 0..rows {
        s.row_moves(row, &mut buf.moves);
        // Whole rows, at least WALK_CHUNK_MOVES a chunk (small primitives in one):
        // the per-chunk work of every unit downstream is paid per chunk.
        if buf.moves.len() >= WALK_CHUNK_MOVES || row + 1 == rows {
            buf.outs.clear();
            u.kernel_batch(&mut st, &buf.moves, &mut buf.outs, ctr);
            tally.add(buf.moves.len());
            sink(&buf.outs);
            buf.moves.clear();
        }
    }
    tally.close(u.timing(), ctr);
}

/// [`walk_rows_raw`] with each chunk's outputs in lanes
/// ([`PolygonInterpolator::kernel_runs_lanes`] on each row's moves run-length coded,
/// [`PolySetup::row_runs`]): the same words in the same chunks, the same counters.
pub fn walk_rows_lanes(
    u: &PolygonInterpolator,
    s: &PolySetup,
    ctr: &mut Counters,
    buf: &mut WalkBuffers,
    mut sink: impl FnMut(&PolyLanes),
) {
    walk_rows_lanes_by(u, s, ctr, buf, |_| (0, ()), |l, ()| sink(l));
}

/// [`walk_rows_lanes`] with the rows sorted into kinds: `kind(row)` (the row's index
/// in the bounding box) gives the row's kind and the attributes its sink does not
/// read (a mask, added to the buffers' own: their lanes are left empty, still
/// computed and counted). A chunk holds rows of one kind (it ends early where the
/// kind changes), handed to `sink` with its kind. The counters are the same as
/// [`walk_rows_lanes`]'s (they are sums over the moves, in any chunking).
pub fn walk_rows_lanes_by<K: Copy + PartialEq>(
    u: &PolygonInterpolator,
    s: &PolySetup,
    ctr: &mut Counters,
    buf: &mut WalkBuffers,
    mut kind: impl FnMut(u64) -> (u32, K),
    mut sink: impl FnMut(&PolyLanes, K),
) {
    let kind = |row| {
        let (unread, k) = kind(row);
        (unread, k, [None, None])
    };
    walk_rows_lanes_blank(u, s, ctr, buf, 0, kind, |l, k, _: &[(Range<usize>, ())]| {
        sink(l, k)
    });
}

/// A stretch of a walk row (pixel columns, inclusive) whose blank attributes its
/// sink does not read, with what the sink is told of it.
pub type RowBlank<P> = (RangeInclusive<i64>, P);

/// [`walk_rows_lanes_by`] where `kind(row)` also gives up to two stretches of the
/// row (disjoint) whose attributes in the mask `blank` the sink does not read: their
/// words hold 0 in those lanes, computed and counted all the same
/// ([`PolygonInterpolator::kernel_runs_lanes_blank`]; the lanes stay in step with
/// the words). The sink gets each chunk's stretches as ranges of its words, in
/// order. Every word is appended (not [`WalkBuffers::covered`]). The counters are
/// [`walk_rows_lanes`]'s.
pub fn walk_rows_lanes_blank<K: Copy + PartialEq, P: Copy>(
    u: &PolygonInterpolator,
    s: &PolySetup,
    ctr: &mut Counters,
    buf: &mut WalkBuffers,
    blank: u32,
    mut kind: impl FnMut(u64) -> (u32, K, [Option<RowBlank<P>>; 2]),
    mut sink: impl FnMut(&PolyLanes, K, &[(Range<usize>, P)]),
) {
    let mut st = s.state.clone();
    let mut tally = SpanTally::new();
    let Some(b) = s.bbox else {
        tally.close(u.timing(), ctr);
        return;
    };
    let (rows, width) = (b.height(), b.width() as usize);
    buf.runs.clear();
    buf.blanks.clear();
    let mut stretches = Vec::new();
    let (mut moves, mut row) = (0, 0);
    let mut this = (rows > 0).then(|| kind(0));
    while let Some((unread, k, row_blanks)) = this {
        s.row_runs(row, &mut buf.runs);
        buf.blanks.resize(buf.runs.len(), 0);
        if row_blanks.iter().any(Option::is_some) {
            assert!(
                !buf.covered_only,
                "blank stretches need every word appended"
            );
            // The row's word i lies at column x0 + i walking right (even rows), at
            // x1 − i walking left.
            let rightward = row & 1 == 0;
            let mut words = row_blanks.map(|rb| {
                rb.map(|(xs, p)| {
                    let (xa, xb) = ((*xs.start()).max(b.x0), (*xs.end()).min(b.x1));
                    let (i, j) = if rightward {
                        (xa - b.x0, xb - b.x0)
                    } else {
                        (b.x1 - xb, b.x1 - xa)
                    };
                    (i as usize..(j + 1) as usize, p)
                })
            });
            words.sort_by_key(|w| w.as_ref().map(|(r, _)| r.start));
            let at = buf.runs.len() - 2;
            split_row_runs(&mut buf.runs, &mut buf.blanks, at, width, &words, blank);
            stretches.extend(
                words
                    .into_iter()
                    .flatten()
                    .filter(|(r, _)| !r.is_empty())
                    .map(|(r, p)| (moves + r.start..moves + r.end, p)),
            );
        }
        moves += width;
        let next = (row + 1 < rows).then(|| kind(row + 1));
        if moves >= WALK_CHUNK_MOVES || next.as_ref().is_none_or(|n| (n.0, n.1) != (unread, k)) {
            buf.lanes
                .clear_covered(u.attrs() as usize, buf.unread | unread, buf.covered_only);
            u.kernel_runs_lanes_blank(&mut st, &buf.runs, &buf.blanks, &mut buf.lanes, ctr);
            tally.add(moves);
            sink(&buf.lanes, k, &stretches);
            buf.runs.clear();
            buf.blanks.clear();
            stretches.clear();
            moves = 0;
        }
        (this, row) = (next, row + 1);
    }
    tally.close(u.timing(), ctr);
}

/// A walk row's two runs (its first move, then `width − 1` along the row) at
/// `runs[at..]` split at the stretches `words` (ranges of the row's words, disjoint,
/// in order; empty ones none), those with the blank mask `blank` in `blanks`.
fn split_row_runs<P>(
    runs: &mut Vec<(Move, usize)>,
    blanks: &mut Vec<u32>,
    at: usize,
    width: usize,
    words: &[Option<(Range<usize>, P)>],
    blank: u32,
) {
    let (first, along) = (runs[at].0, runs[at + 1].0);
    runs.truncate(at);
    blanks.truncate(at);
    // Words a..b with mask m: word 0 is the first move, the rest moves along.
    let mut push = |a: usize, b: usize, m: u32| {
        if a == 0 {
            runs.push((first, 1));
            blanks.push(m);
        }
        let along_from = a.max(1);
        if b > along_from {
            runs.push((along, b - along_from));
            blanks.push(m);
        }
    };
    let mut from = 0;
    for (r, _) in words.iter().flatten().filter(|(r, _)| !r.is_empty()) {
        assert!(
            r.start >= from && r.end <= width,
            "stretches disjoint and in the row"
        );
        if r.start > from {
            push(from, r.start, 0);
        }
        push(r.start, r.end, blank);
        from = r.end;
    }
    if from < width {
        push(from, width, 0);
    }
}

/// Whether lane word `i` is a fragment ([`is_fragment`]).
#[inline]
pub fn is_fragment_lane(l: &PolyLanes, i: usize, width: u32, height: u32) -> bool {
    let (x, y) = (l.x[i], l.y[i]);
    l.inside[i] && x >= 0 && y >= 0 && x < width as i64 && y < height as i64
}

/// Whether a walked pixel is a fragment: covered, and inside the viewport.
#[inline]
pub fn is_fragment(f: &PolyOut, width: u32, height: u32) -> bool {
    f.inside && f.x >= 0 && f.y >= 0 && f.x < width as i64 && f.y < height as i64
}

/// [`walk_rows_lanes`] keeping each chunk's fragments (covered pixels inside the
/// `width` × `height` viewport), handed to `sink` when a chunk has any.
pub fn walk_rows(
    u: &PolygonInterpolator,
    s: &PolySetup,
    width: u32,
    height: u32,
    ctr: &mut Counters,
    buf: &mut WalkBuffers,
    mut sink: impl FnMut(&[Fragment]),
) {
    let mut frags = std::mem::take(&mut buf.frags);
    // Only fragments are kept: the uncovered part of each row is stepped and counted
    // but not written out.
    let covered_only = std::mem::replace(&mut buf.covered_only, true);
    walk_rows_lanes(u, s, ctr, buf, |l| {
        frags.clear();
        for i in (0..l.len()).filter(|&i| is_fragment_lane(l, i, width, height)) {
            let mut attrs = [0i64; MAX_ATTRS];
            for (a, lane) in attrs.iter_mut().zip(&l.attrs[..l.k]) {
                *a = lane[i];
            }
            frags.push(Fragment {
                x: l.x[i] as u32,
                y: l.y[i] as u32,
                attrs,
            });
        }
        if !frags.is_empty() {
            sink(&frags);
        }
    });
    buf.covered_only = covered_only;
    buf.frags = frags;
}

thread_local! {
    /// [`walk`]'s buffers, kept by each thread from one primitive to the next (a
    /// pass draws thousands of small triangles; each walk clears them first).
    static WALK_BUFFERS: RefCell<WalkBuffers> = RefCell::new(WalkBuffers::default());
}

/// Walk one set-up primitive; keep covered pixels inside a `width` × `height` viewport.
pub fn walk(
    u: &PolygonInterpolator,
    s: &PolySetup,
    width: u32,
    height: u32,
    ctr: &mut Counters,
    out: &mut Vec<Fragment>,
) {
    WALK_BUFFERS.with_borrow_mut(|buf| {
        walk_rows(u, s, width, height, ctr, buf, |f| out.extend_from_slice(f))
    });
}

/// Draw a triangle.
pub fn draw_triangle(
    u: &PolygonInterpolator,
    v: &[HostVertex; 3],
    width: u32,
    height: u32,
    ctr: &mut Counters,
) -> Result<Vec<Fragment>, ConfigError> {
    let q = quantise(u, v, ctr)?;
    let mut out = Vec::new();
    let s = u.setup_triangle(&q, ctr);
    walk(u, &s, width, height, ctr, &mut out);
    Ok(out)
}
