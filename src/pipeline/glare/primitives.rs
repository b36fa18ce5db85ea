//! One primitive through the glare datapath: the generator's variables, the
//! interpolator's set-up and walk (scissored to the viewport and fitted to the
//! coordinate range), then a modulator and the combiner into the framebuffer.

use super::tables::AreaPrim;
use crate::report::image_out::Framebuffer;
use crate::scene::glare::GlareSection;
use rtl_model::driver::{run_span, SpanTally};
use rtl_model::units::glare_combiner::{CombineIn, GlareCombiner};
use rtl_model::units::luminance_ram::{LumIn, LumOut, LumWidths};
use rtl_model::units::polygon_interpolator::{
    Move, PolyOut, PolySetup, PolygonInterpolator, Vertex, MAX_ATTRS,
};
use rtl_model::units::polygon_variable_generator::{PolygonVariableGenerator, PrimKind, PvgIn};
use rtl_model::{ConfigError, Counters, Unit};
use std::collections::BTreeMap;

pub(crate) fn add(map: &mut BTreeMap<String, Counters>, name: &str, c: Counters) {
    *map.entry(name.to_string()).or_default() += c;
}

/// Sub-pixel bits of glare positions (interpolator and generator agree).
pub const SUBPIXEL_BITS: u32 = crate::scene::limits::GLARE_SUBPIXEL_BITS;
/// Integer bits of glare positions, with the sign: ±8192 px.
pub const COORD_INT_BITS: u32 = crate::scene::limits::GLARE_COORD_INT_BITS;
/// Fraction bits of the s2.f attributes the generator hands the interpolator.
pub const ATTR_FRAC_BITS: u32 = crate::scene::limits::GLARE_ATTR_FRAC_BITS;

/// The modulators' widths from the scene (built where validation builds them:
/// `scene::limits`).
pub fn lum_widths(g: &GlareSection) -> LumWidths {
    crate::scene::limits::lum_widths(&g.hw)
}

/// The glare interpolator: two attributes (u, v), s2.14 in, s2.f out
/// ([`crate::scene::limits::glare_interpolator`]).
pub fn interpolator(coord_frac_bits: u32) -> Result<PolygonInterpolator, ConfigError> {
    crate::scene::limits::glare_interpolator(coord_frac_bits).build()
}

/// The polygon-variable generator ([`crate::scene::limits::glare_generator`]).
pub fn generator() -> Result<PolygonVariableGenerator, ConfigError> {
    crate::scene::limits::glare_generator().build()
}

/// Move a set-up primitive's walk to the part of its bounding box inside the
/// viewport: the setup engine starts the walker at the clipped corner, its edge and
/// attribute accumulators advanced by Δx·d/dx + Δy·d/dy (multiply-adds, the same
/// values the walk would reach, accumulators wrapping to their width).
pub fn scissor(u: &PolygonInterpolator, s: &PolySetup, width: u32, height: u32) -> PolySetup {
    let Some(b) = s.bbox else {
        return s.clone();
    };
    let (x0, y0) = (b.x0.max(0), b.y0.max(0));
    let (x1, y1) = (b.x1.min(width as i64 - 1), b.y1.min(height as i64 - 1));
    let mut out = s.clone();
    if x0 > x1 || y0 > y1 {
        out.bbox = None;
        return out;
    }
    let (dx, dy) = (x0 - b.x0, y0 - b.y0);
    let st = &mut out.state;
    for i in 0..st.edge.len() {
        st.edge[i] += dx * st.edge_dx[i] + dy * st.edge_dy[i];
    }
    let w = u.acc_int_bits() + u.acc_frac_bits();
    let sh = 64 - w;
    for i in 0..u.attrs() as usize {
        let v = st.acc[i]
            .wrapping_add(dx.wrapping_mul(st.grad_x[i]))
            .wrapping_add(dy.wrapping_mul(st.grad_y[i]));
        st.acc[i] = (v << sh) >> sh;
    }
    st.x = x0;
    st.y = y0;
    out.bbox = Some(rtl_model::units::polygon_interpolator::BBox { x0, y0, x1, y1 });
    out
}

/// Largest |coordinate| (pixels) the host lets a quad corner reach: the position
/// format's range ±2^(COORD_INT_BITS−1), less a pixel for rounding.
pub const COORD_LIMIT_PX: f64 = ((1u64 << (COORD_INT_BITS - 1)) - 1) as f64;

/// An area primitive whose quad fits the coordinate range: the half-side shrunk to
/// COORD_LIMIT_PX − |centre| (0 when the centre itself is out of range, an empty
/// quad). Its RAM tables are computed over the shrunk frame, so the walked part keeps
/// the primitive's true (u, v) → distance mapping; what is cut off lies outside the
/// coordinate range (off screen).
pub fn fit_area(a: &AreaPrim) -> AreaPrim {
    let room = COORD_LIMIT_PX - a.center[0].abs().max(a.center[1].abs());
    AreaPrim {
        half_px: a.half_px.min(room).max(0.0),
        ..a.clone()
    }
}

/// Longest flare line and widest line (pixels) the host sends.
pub const LINE_MAX_PX: f64 = 4000.0;

/// Whether a flare line's rectangle (from `center` along `angle`, `length` long,
/// `half_width` to each side) lies inside the coordinate range with a pixel to
/// spare. The generator saturates each corner on its own, so a line reaching out of
/// range would come out skewed (or its fourth corner overflow the interpolator);
/// the host culls it instead. Its rectangle is at most √2·4000 px across, so on an
/// image of up to 2534 px a side a culled line never reaches the screen.
pub fn line_fits(center: [f64; 2], angle: f64, length: f64, half_width: f64) -> bool {
    let (c, s) = (angle.cos(), angle.sin());
    let lim = COORD_LIMIT_PX - 1.0;
    [(0.0, -1.0), (0.0, 1.0), (1.0, -1.0), (1.0, 1.0)]
        .iter()
        .all(|&(along, side)| {
            let x = center[0] + along * length * c - side * half_width * s;
            let y = center[1] + along * length * s + side * half_width * c;
            x.abs() <= lim && y.abs() <= lim
        })
}

/// Position code of a pixel coordinate (round to nearest sub-pixel).
pub(crate) fn pos_code(x: f64) -> i64 {
    (x * (1u64 << SUBPIXEL_BITS) as f64).round() as i64
}

/// A covered fragment: x, y and the (u, v) codes.
pub type Frag = (u32, u32, i32, i32);

/// Walker moves per chunk (a row is cut into chunks of at most this many, narrow rows
/// are gathered up to it), so a chunk's interpolator outputs (152-byte words, 38 KiB)
/// stay in the L1 cache between the walk and the filter.
const CHUNK_MOVES: usize = 256;

/// The buffers one frame's primitives reuse: a chunk of walker moves and of each
/// unit's inputs and outputs. Owned by the frame and cleared per chunk, so drawing a
/// primitive allocates nothing once they have grown to a chunk.
#[derive(Default)]
pub(crate) struct DrawBuffers {
    pub walk_bufs: WalkBuffers,
    pub comb_in: Vec<CombineIn>,
    pub comb_out: Vec<[u32; 3]>,
}

/// The walk's and the modulator's chunk buffers ([`walk_prim`]).
#[derive(Default)]
pub(crate) struct WalkBuffers {
    moves: Vec<Move>,
    walk: Vec<PolyOut>,
    /// Framebuffer pixel index of each covered fragment of the chunk.
    pix: Vec<usize>,
    lum_in: Vec<LumIn>,
    lum: Vec<LumOut>,
}

/// What one primitive's walk did: pixels stepped over (after the scissor) and covered
/// fragments inside the viewport.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Drawn {
    pub walked: u64,
    pub fragments: u64,
}

/// One primitive through the datapath: the generator's variables, the interpolator's
/// set-up (scissored), then its walk chunk by chunk, each chunk's covered fragments
/// through the modulator `m` and the combiner into `fb`. The units are chained per
/// chunk (no primitive-long buffer); each unit's span is the whole primitive, so its
/// timing counters are added once at the end ([`SpanTally`]) and equal one
/// `run_span` over the primitive. Every unit's counter entry is made even when the
/// walk is empty. With `record`, the covered fragments' framebuffer pixel indices are
/// appended to it in walk order (for the clocked chip; nothing else changes).
#[allow(clippy::too_many_arguments)]
pub(crate) fn draw_prim<U>(
    pvg: &PolygonVariableGenerator,
    ip: &PolygonInterpolator,
    input: PvgIn,
    m: &U,
    comb: &GlareCombiner,
    gain: [u32; 3],
    fb: &mut Framebuffer,
    buf: &mut DrawBuffers,
    ctr: &mut BTreeMap<String, Counters>,
    mut record: Option<&mut Vec<u32>>,
) -> Result<Drawn, ConfigError>
where
    U: Unit<In = LumIn, Out = LumOut, State = ()> + ?Sized,
{
    let (mut c_comb, mut t_comb) = (Counters::default(), SpanTally::new());
    let (fw, fh) = (fb.width, fb.height);
    let DrawBuffers {
        walk_bufs,
        comb_in,
        comb_out,
    } = buf;
    let d = walk_prim(
        pvg,
        ip,
        input,
        m,
        gain,
        fw,
        fh,
        walk_bufs,
        ctr,
        |pix, lum| {
            if let Some(r) = record.as_deref_mut() {
                r.extend(pix.iter().map(|&i| i as u32));
            }
            combine(
                comb,
                pix,
                lum,
                fb,
                comb_in,
                comb_out,
                &mut c_comb,
                &mut t_comb,
            )
        },
    )?;
    t_comb.close(comb.timing(), &mut c_comb);
    add(ctr, comb.name(), c_comb);
    Ok(d)
}

/// The combiner on one chunk of a primitive's fragments (framebuffer pixel indices
/// and their luminance): reads the pixels, adds with saturation, writes them back. A
/// walk visits each pixel once, so reading a chunk's pixels before writing any is the
/// primitive's read-modify-write. The chunk's inputs join the primitive's `tally`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn combine(
    comb: &GlareCombiner,
    pix: &[usize],
    lum: &[LumOut],
    fb: &mut Framebuffer,
    comb_in: &mut Vec<CombineIn>,
    comb_out: &mut Vec<[u32; 3]>,
    ctr: &mut Counters,
    tally: &mut SpanTally,
) {
    comb_in.clear();
    comb_in.extend(pix.iter().zip(lum).map(|(&i, l)| CombineIn {
        fb: [fb.data[4 * i], fb.data[4 * i + 1], fb.data[4 * i + 2]],
        lum: l.lum,
    }));
    comb_out.clear();
    comb.kernel_batch(&mut (), comb_in, comb_out, ctr);
    tally.add(comb_in.len());
    for (&i, o) in pix.iter().zip(comb_out.iter()) {
        fb.data[4 * i..4 * i + 3].copy_from_slice(o);
    }
}

/// The front of [`draw_prim`]: generator, set-up and walk, and the modulator, chunk
/// by chunk, each chunk's covered fragments (framebuffer pixel index, luminance) handed
/// to `sink` in walk order. The generator's, interpolator's and modulator's counters
/// (one span each over the primitive) go to `ctr`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn walk_prim<U>(
    pvg: &PolygonVariableGenerator,
    ip: &PolygonInterpolator,
    input: PvgIn,
    m: &U,
    gain: [u32; 3],
    width: u32,
    height: u32,
    buf: &mut WalkBuffers,
    ctr: &mut BTreeMap<String, Counters>,
    mut sink: impl FnMut(&[usize], &[LumOut]),
) -> Result<Drawn, ConfigError>
where
    U: Unit<In = LumIn, Out = LumOut, State = ()> + ?Sized,
{
    let mut c_pvg = Counters::default();
    let v = run_span(pvg, &mut (), &[input], &mut c_pvg)[0];
    add(ctr, pvg.name(), c_pvg);
    let mut c_ip = Counters::default();
    let verts = v.map(|p| {
        let mut attrs = [0i64; MAX_ATTRS];
        attrs[0] = p.u;
        attrs[1] = p.v;
        Vertex {
            x: p.x,
            y: p.y,
            attrs,
        }
    });
    let setup = ip.setup_parallelogram(&verts, &mut c_ip)?;
    let setup = scissor(ip, &setup, width, height);
    let mut st = setup.state.clone();
    let mut c_m = Counters::default();
    let (mut t_ip, mut t_m) = (SpanTally::new(), SpanTally::new());
    let (w, h) = (width as i64, height as i64);
    let WalkBuffers {
        moves,
        walk,
        pix,
        lum_in,
        lum,
    } = buf;
    if let Some(b) = setup.bbox {
        let bw = b.width() as usize;
        let rows = b.height() as usize;
        let mut row = 0;
        while row < rows {
            // The serpentine walk of `PolySetup::moves`, whole rows at a time.
            moves.clear();
            while row < rows && (moves.is_empty() || moves.len() + bw <= CHUNK_MOVES) {
                setup.row_moves(row as u64, moves);
                row += 1;
            }
            for part in moves.chunks(CHUNK_MOVES) {
                walk.clear();
                ip.kernel_batch(&mut st, part, walk, &mut c_ip);
                t_ip.add(part.len());
                // Covered fragments inside the viewport, in walk order.
                pix.clear();
                lum_in.clear();
                for f in walk.iter() {
                    if f.inside && f.x >= 0 && f.y >= 0 && f.x < w && f.y < h {
                        pix.push((f.y * w + f.x) as usize);
                        lum_in.push(LumIn {
                            u: f.attrs[0] as i32,
                            v: f.attrs[1] as i32,
                            gain,
                        });
                    }
                }
                if pix.is_empty() {
                    continue;
                }
                lum.clear();
                m.kernel_batch(&mut (), lum_in, lum, &mut c_m);
                t_m.add(lum_in.len());
                sink(pix, lum);
            }
        }
    }
    let fragments = t_m.len();
    t_ip.close(ip.timing(), &mut c_ip);
    t_m.close(m.timing(), &mut c_m);
    add(ctr, ip.name(), c_ip);
    add(ctr, m.name(), c_m);
    Ok(Drawn {
        walked: setup.pixels(),
        fragments,
    })
}

/// The area primitive's generator input (the quad fitted to the coordinate range).
pub(crate) fn area_input(
    a: &AreaPrim,
    pvg: &PolygonVariableGenerator,
) -> Result<PvgIn, ConfigError> {
    let half = fit_area(a).half_px;
    Ok(PvgIn {
        kind: PrimKind::Area,
        cx: pos_code(a.center[0]),
        cy: pos_code(a.center[1]),
        extent: pos_code(half) as u64,
        half_width: 0,
        angle: pvg.angle_code(a.phi)?,
    })
}

/// Gains (u12.4 codes) of luminance `l` times the source colour.
pub(crate) fn gains(
    w: &LumWidths,
    l: f64,
    color: [f64; 3],
    field: &str,
) -> Result<[u32; 3], ConfigError> {
    let max = w.gain_max() as f64 / (1u64 << w.gain_frac_bits) as f64;
    w.gain_from_f64(field, color.map(|c| (l * c).clamp(0.0, max)))
}
