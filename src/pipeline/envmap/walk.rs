//! The envmap renderer's raster walk and depth test: every triangle of the object is
//! set up and walked by the ONE `polygon_interpolator` (`pipeline::raster`), and the
//! nearest fragment per pixel wins an integer compare of the interpolated window-depth
//! codes (standing for the depth buffer). See [`super::render`]'s module notes, steps
//! 1–3.

use rayon::prelude::*;
use rtl_model::error::ConfigError;
use rtl_model::units::polygon_interpolator::PolygonInterpolator;
use rtl_model::Counters;

use super::interpolator::RENDER_ATTRS;
use super::roughness::TexGen;
use crate::pipeline::raster::{
    host_attrs, is_fragment, quantise, walk_rows_raw, HostVertex, WalkBuffers,
};
use crate::scene::camera::CameraView;
use crate::scene::teapot::Triangle;

/// Triangles per rayon task: each task walks its triangles in order into its own
/// fragment list; the depth test then runs over the lists in triangle order.
const TRIS_PER_TASK: usize = 32;

/// A covered pixel that may be visible: its index y·w + x and the interpolator's raw
/// s16.16 codes of n (3), e (3), λ, z, and (u, v) (the render's attributes 8, 9, the
/// measurement walk's, or zeros).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Frag {
    pub k: u32,
    pub attrs: [i64; RENDER_ATTRS as usize],
    pub uv: [i64; 2],
}

/// What the walk leaves for shading: the visible fragment of every covered pixel, in
/// pixel order.
pub(super) struct Walk {
    pub visible: Vec<Frag>,
    pub triangles: usize,
    /// Fragments the interpolator produced, before the depth test.
    pub fragments: u64,
    /// The interpolator's counters (the measurement walk's are not counted).
    pub counters: Counters,
}

/// How [`walk`] draws: the camera, the texgen of (u, v), the render's interpolator,
/// the measurement walk's (or None), whether (u, v) are the render's attributes 8 and
/// 9, and the viewport `w` × `h`.
#[derive(Clone, Copy)]
pub(super) struct WalkSetup<'a> {
    pub cam: &'a CameraView,
    pub texgen: &'a TexGen,
    pub interp: &'a PolygonInterpolator,
    pub uv_probe: Option<&'a PolygonInterpolator>,
    pub uv_from_render: bool,
    pub w: u32,
    pub h: u32,
}

/// One task's triangles walked: their fragments in walk order and their counts.
struct Part {
    frags: Vec<Frag>,
    triangles: usize,
    counters: Counters,
}

/// Walk `geo` (triangles with per-vertex λ) as `how` says (its fields named below). Each vertex
/// carries n (flipped for triangles seen from their back), e = eye − p, λ, the window
/// depth and the texgen (u, v). With `uv_probe` (per-vertex λ with the intended-λ
/// truth) a second, uncounted walk of the 10-attribute interpolator gives the (u, v)
/// codes; it must cover the same pixels, else an error naming
/// "envmap_render.texcoord". `uv_from_render`: (u, v) are the render's own attributes
/// 8 and 9 (the roughness-texture path).
///
/// Triangles are walked in parallel (rayon, [`TRIS_PER_TASK`] a task; the unit is
/// stateless between primitives, each primitive one span with its own counters); the
/// depth test runs over the fragments in triangle and walk order, so the image and the
/// counters are those of one sequential walk on any thread count.
pub(super) fn walk(geo: &[(Triangle, [f64; 3])], how: &WalkSetup<'_>) -> Result<Walk, ConfigError> {
    let (w, h) = (how.w, how.h);
    let parts: Vec<Result<Part, ConfigError>> = geo
        .par_chunks(TRIS_PER_TASK)
        .map(|tris| walk_part(tris, how))
        .collect();
    let mut c_int = Counters::default();
    let mut triangles = 0;
    let mut done = Vec::with_capacity(parts.len());
    for p in parts {
        let p = p?;
        c_int += p.counters;
        triangles += p.triangles;
        done.push(p.frags);
    }
    // The depth test in triangle order: (task, index) of each pixel's nearest fragment;
    // an integer compare on the s16.16 window-depth code (less wins, the first of equal
    // depths stays).
    const NONE: (u32, u32) = (u32::MAX, u32::MAX);
    let n_px = w as usize * h as usize;
    let mut zbuf: Vec<i64> = vec![i64::MAX; n_px];
    let mut nearest: Vec<(u32, u32)> = vec![NONE; n_px];
    let mut fragments = 0u64;
    for (t, frags) in done.iter().enumerate() {
        fragments += frags.len() as u64;
        for (i, f) in frags.iter().enumerate() {
            let k = f.k as usize;
            if f.attrs[7] < zbuf[k] {
                zbuf[k] = f.attrs[7];
                nearest[k] = (t as u32, i as u32);
            }
        }
    }
    let visible = nearest
        .iter()
        .filter(|&&n| n != NONE)
        .map(|&(t, i)| done[t as usize][i as usize])
        .collect();
    Ok(Walk {
        visible,
        triangles,
        fragments,
        counters: c_int,
    })
}

/// Walk one task's triangles in order (see [`walk`]).
fn walk_part(tris: &[(Triangle, [f64; 3])], how: &WalkSetup<'_>) -> Result<Part, ConfigError> {
    let WalkSetup {
        cam,
        texgen,
        interp,
        uv_probe,
        uv_from_render,
        w,
        h,
    } = *how;
    let mut part = Part {
        frags: Vec::new(),
        triangles: 0,
        counters: Counters::default(),
    };
    let mut buf = WalkBuffers::default();
    let mut probe: Vec<(u32, [i64; 2])> = Vec::new();
    for (tri, lam) in tris {
        let mut hv = [HostVertex {
            x: 0.0,
            y: 0.0,
            attrs: host_attrs([]),
        }; 3];
        let mut ok = true;
        // Two-sided lighting (GL's LIGHT_MODEL_TWO_SIDE): a triangle seen from its back
        // (the teapot is an open sheet: the inside of the rim and spout shows) gets its
        // normals flipped. Per primitive, host side (the facing is the sign of the
        // screen-space area the setup computes anyway).
        let face = (tri.p[1] - tri.p[0]).cross(tri.p[2] - tri.p[0]);
        let flip = if face.dot(cam.eye - tri.p[0]) < 0.0 {
            -1.0
        } else {
            1.0
        };
        for k in 0..3 {
            let Some((sx, sy, sz)) = cam.project(tri.p[k]) else {
                ok = false;
                break;
            };
            let n = tri.n[k] * flip;
            let e = cam.eye - tri.p[k];
            let (u, v) = texgen.uv(tri.p[k]);
            // An 8-attribute interpolator reads the first 8 (u, v unused).
            hv[k] = HostVertex {
                x: sx,
                y: sy,
                attrs: host_attrs([n.x, n.y, n.z, e.x, e.y, e.z, lam[k], sz, u, v]),
            };
        }
        if !ok {
            continue;
        }
        part.triangles += 1;
        let first = part.frags.len();
        draw(interp, &hv, w, h, &mut part.counters, &mut buf, |k, a| {
            part.frags.push(Frag {
                k,
                attrs: std::array::from_fn(|i| a[i]),
                uv: if uv_from_render { [a[8], a[9]] } else { [0; 2] },
            });
        })?;
        if let Some(p) = uv_probe {
            probe.clear();
            draw(p, &hv, w, h, &mut Counters::default(), &mut buf, |k, a| {
                probe.push((k, [a[8], a[9]]));
            })?;
            let mine = &mut part.frags[first..];
            if probe.len() != mine.len() || probe.iter().zip(&*mine).any(|(g, f)| g.0 != f.k) {
                return Err(ConfigError::invalid(
                    "envmap_render.texcoord",
                    "the (u, v) measurement walk covered other pixels than the render",
                ));
            }
            for (f, g) in mine.iter_mut().zip(&probe) {
                f.uv = g.1;
            }
        }
    }
    Ok(part)
}

/// One triangle through `u` (`pipeline::raster::draw_triangle` on the batch path):
/// quantise, set up, walk in chunks of whole bounding-box rows through `buf`
/// ([`walk_rows_raw`]: the primitive's walk one span); `sink` gets the pixel index
/// y·w + x and the raw codes of each fragment ([`is_fragment`]: covered, inside the
/// `w` × `h` viewport), in walk order.
fn draw(
    u: &PolygonInterpolator,
    hv: &[HostVertex; 3],
    w: u32,
    h: u32,
    ctr: &mut Counters,
    buf: &mut WalkBuffers,
    mut sink: impl FnMut(u32, &[i64]),
) -> Result<(), ConfigError> {
    let q = quantise(u, hv, ctr)?;
    let s = u.setup_triangle(&q, ctr);
    walk_rows_raw(u, &s, ctr, buf, |outs| {
        for f in outs.iter().filter(|f| is_fragment(f, w, h)) {
            sink(f.y as u32 * w + f.x as u32, &f.attrs);
        }
    });
    Ok(())
}
