//! One frame of the shafts pipeline (Dobashi et al.) through the bit-accurate units.
//!
//! Per frame: a depth pass of the objects into the camera's depth buffer. Per light:
//! a shadow-map pass of the occluders; the objects' colour pass (per-vertex Lambert
//! and attenuation, × light map × shadow); then n sample planes drawn as meshes whose
//! vertices carry α and (s, t), with F(α)·h(s, t) from the 1D and 2D textures,
//! modulated with H·I_l (shadow compare × projective light map) and the plane's
//! vertex colour, and added into the framebuffer. With m > 1 sub-sample planes, H·I_l
//! is instead averaged over m sub-planes per interval into a J buffer with 8-bit
//! blend weights, copied to a texture and looked up on plane i (Dobashi et al. eqs. (7)–(9)).
//!
//! Host work (vertex positions, α, s, t, light coordinates) is f64, as the
//! application processor computes it; every per-pixel step is a unit kernel.

use super::chunked::{ChunkBuffers, HilSpans, LightCtx, UnitSpan};
use super::pass_log::PassLog;
use super::planes::covers_once;
use super::record::{self, Rec};
use super::tables::{self, GTables};
use super::units::{attr_unorm, counters_add, window_depth_word, Units};
use super::view::{vec3, CameraView, LightView};
use crate::chip::work::{PassSample, SampleBands};
use crate::pipeline::raster::{draw_triangle, host_attrs, walk, Fragment, HostVertex};
use crate::report::image_out::Framebuffer;
use crate::scene::format::{HCap, Scene};
use crate::scene::limits;
use crate::scene::math::Vec3;
use rayon::prelude::*;
use rtl_model::driver::run_span;
use rtl_model::error::ConfigError;
use rtl_model::units::blend::{Blend, BlendIn};
use rtl_model::units::clipper::{ClipIn, ClipStats, Clipper};
use rtl_model::units::modulate::Operand;
use rtl_model::units::polygon_interpolator::{
    PolyLanes, PolyOut, PolygonInterpolator, Vertex, MAX_ATTRS,
};
use rtl_model::units::shadow_compare::{ShadowCompareConfig, ShadowIn, ShadowState};
use rtl_model::units::texture_sampler::{TextureSampler, TextureSamplerConfig};
use rtl_model::unorm::max_code;
use rtl_model::{Counters, Unit, UnitSummary};
use std::collections::BTreeMap;

pub use super::pass_log::WorkSink;
pub use super::prepare::{ObjectMesh, Prepared};
/// Camera depth buffer width (defined with the scene's limits: validation builds the
/// depth buffer from it).
pub use super::units::ZBUF_BITS;

pub use crate::report::elaboration::Elaborated;

pub use crate::chip::work::PassWork;
pub use crate::chip::{PassKind, PassStats};

/// The frame: framebuffer (fb_bits, RGB), counters per unit, passes, elaboration.
#[derive(Clone, Debug)]
pub struct FrameResult {
    pub fb: Framebuffer,
    pub counters: BTreeMap<String, Counters>,
    pub passes: Vec<PassStats>,
    pub elaboration: Vec<Elaborated>,
    pub tables: GTables,
    /// The clipper's polygon counts, when the scene elaborated it.
    pub clip_stats: Option<ClipStats>,
}

impl FrameResult {
    /// The image in 8-bit levels (f64, for error metrics).
    pub fn levels(&self) -> Vec<[f64; 3]> {
        self.fb.levels()
    }
}

/// One pass of a shafts frame, in the order [`passes`] lists them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum ShaftsPass {
    /// The objects into the camera's depth buffer.
    Depth,
    /// Light `light`'s occluders into its shadow map.
    ShadowMap { light: usize },
    /// The colour of the objects light `light` lights (those without a material:
    /// an object with one is shaded by the shading units, outside this pipeline).
    Objects { light: usize },
    /// Light `light`'s sample planes (and sub-planes).
    Planes { light: usize },
}

/// The passes a prepared scene needs, in order: the depth pass when there are objects;
/// per light its shadow map (occluders), its object colour (objects this pipeline
/// colours) and its sample planes (a light that shines into a scattering medium).
pub fn passes(p: &Prepared) -> Vec<ShaftsPass> {
    let has_objects = p.objects.iter().any(|o| !o.triangles.is_empty());
    let has_occluders = p
        .objects
        .iter()
        .any(|o| o.occluder && !o.triangles.is_empty());
    let coloured = p
        .objects
        .iter()
        .any(|o| o.colour_pass && !o.triangles.is_empty());
    let mut out = Vec::new();
    if has_objects {
        out.push(ShaftsPass::Depth);
    }
    for (light, l) in p.scene.lights.iter().enumerate() {
        if has_occluders {
            out.push(ShaftsPass::ShadowMap { light });
        }
        if coloured {
            out.push(ShaftsPass::Objects { light });
        }
        if l.intensity > 0.0 && scatters(&p.scene.medium) {
            out.push(ShaftsPass::Planes { light });
        }
    }
    out
}

/// Whether the medium scatters any light towards the eye (ρ > 0 and K > 0): without
/// it every plane adds zero and the sample-plane passes are left out.
pub fn scatters(m: &crate::scene::format::Medium) -> bool {
    m.rho > 0.0 && m.k > 0.0
}

/// Render one frame: its passes in order over one frame state.
pub fn render_frame(p: &Prepared) -> Result<FrameResult, ConfigError> {
    let mut f = ShaftsFrame::new(p, None)?;
    for pass in passes(p) {
        f.run(pass)?;
    }
    Ok(f.finish())
}

/// The shared state of one shafts frame between its passes: the configured units,
/// the framebuffer, the camera depth buffer, the current light's shadow map and
/// light map, the counters and the per-pass statistics.
pub struct ShaftsFrame<'a> {
    p: &'a Prepared,
    cam: CameraView,
    tables: GTables,
    units: Units,
    sampler_cfg: TextureSamplerConfig,
    fb: Framebuffer,
    ctr: BTreeMap<String, Counters>,
    log: PassLog,
    zstate: Option<ShadowState>,
    light: Option<LightState>,
    elaboration: Vec<Elaborated>,
    clip_stats: ClipStats,
}

/// The current light's view, light map and shadow map.
struct LightState {
    li: usize,
    lv: LightView,
    lm_tex: Option<TextureSampler>,
    sstate: Option<ShadowState>,
}

/// The h for which one plane adds full scale at the screen's corner (h_ref is at most
/// this; `shafts.h_cap`). One plane at full F, h, J and the brightest light adds
/// F_max·h_ref·I·Δt·exposure levels, Δt = Δr·t/r growing off-axis to Δr/cos of the
/// corner ray; the vertex colour S·t/r cannot exceed full scale, so h_ref is at most
/// the h for which the corner's is 255 (beyond it h clamps, counted, instead of the
/// colour).
fn h_ceiling(p: &Prepared, cam: &CameraView) -> f64 {
    let sc = &p.scene;
    let cfg = sc.shafts;
    let dr = (p.plane_range.1 - p.plane_range.0) / cfg.planes as f64;
    let corner_cos = cam.ray_dir(0.0, 0.0).dot(cam.forward).clamp(1e-6, 1.0);
    let i_max = sc
        .lights
        .iter()
        .map(|l| l.intensity * l.color.iter().cloned().fold(0.0, f64::max))
        .fold(0.0, f64::max);
    let f_ref = crate::reference::shafts_model::phase_f(p.f_alpha(), sc.medium.k);
    let denom = f_ref * i_max * dr * p.exposure / corner_cos;
    match cfg.h_cap {
        HCap::OnePlane if denom > 0.0 => 255.0 / denom,
        HCap::OnePlane => 0.0,
        // `shafts.h_cap = "none"`: h_ref = h(s_near, 0); the colour saturates.
        HCap::None => f64::INFINITY,
    }
}

/// The frame's framebuffer: `fb` when it is `w` × `h` at `bits` (what earlier passes
/// drew), an error naming `shafts.fb_bits` when it is not, or a black one.
fn frame_buffer(
    fb: Option<Framebuffer>,
    w: u32,
    h: u32,
    bits: u32,
) -> Result<Framebuffer, ConfigError> {
    match fb {
        Some(f) if (f.width, f.height, f.bits) == (w, h, bits) => Ok(f),
        Some(f) => Err(ConfigError::invalid(
            "shafts.fb_bits",
            &format!(
                "the frame's framebuffer is {} × {} at {} bits, the shafts pass needs {w} × {h} at {}",
                f.width, f.height, f.bits, bits
            ),
        )),
        None => Ok(Framebuffer::new(w, h, bits)),
    }
}

impl<'a> ShaftsFrame<'a> {
    /// Configure the units for the scene; the framebuffer starts as `fb` (what earlier
    /// passes of the frame drew, at `shafts.fb_bits`) or black.
    pub fn new(p: &'a Prepared, fb: Option<Framebuffer>) -> Result<Self, ConfigError> {
        let sc = &p.scene;
        let cfg = sc.shafts;
        let cam = CameraView::new(&sc.camera, sc.image);
        let tables = tables::build(
            &sc.medium,
            &cfg,
            p.s_max,
            p.t_max,
            p.s_near,
            p.f_alpha(),
            h_ceiling(p, &cam),
        );
        let units = Units::new(p, &tables)?;
        let fb = frame_buffer(fb, sc.image.width, sc.image.height, cfg.fb_bits)?;
        let zstate = units.zbuf.as_ref().map(|z| z.fresh_state());
        Ok(ShaftsFrame {
            p,
            cam,
            tables,
            units,
            sampler_cfg: limits::shafts_sampler(
                sc,
                2,
                [cfg.light_map_texels, cfg.light_map_texels, 1],
            ),
            fb,
            ctr: BTreeMap::new(),
            log: PassLog::new(),
            zstate,
            light: None,
            elaboration: Vec::new(),
            clip_stats: ClipStats::default(),
        })
    }

    /// Run one pass.
    pub fn run(&mut self, pass: ShaftsPass) -> Result<(), ConfigError> {
        match pass {
            ShaftsPass::Depth => self.depth_pass(),
            ShaftsPass::ShadowMap { light } => self.shadow_map_pass(light),
            ShaftsPass::Objects { light } => self.object_pass(light),
            ShaftsPass::Planes { light } => self.planes_pass(light),
        }
    }

    /// Record what each pass does from now on ([`PassWork`], for the clocked chip):
    /// `sink` gets each pass's work as it finishes, in pass order. Recording reads what
    /// the passes compute and changes no pixel and no counter; without a sink nothing
    /// is recorded.
    pub fn record_work(&mut self, sink: WorkSink) {
        self.log.record(sink);
    }

    /// [`Self::record_work`], keeping only the fragments of the screen bands `bands`
    /// (`None`: every fragment) while counting every primitive in full
    /// ([`crate::chip::work::SampleRecord`]), and recording only the passes `passes`
    /// picks of each kind (the others send their stats alone): the sampled timing
    /// mode's record.
    pub fn record_work_sampled(
        &mut self,
        sink: WorkSink,
        bands: Option<SampleBands>,
        passes: PassSample,
    ) {
        self.log.record(sink);
        self.log.bands = bands;
        self.log.pass_sample = passes;
    }

    /// The framebuffer, for a pass of another pipeline that draws into the same frame.
    pub fn framebuffer_mut(&mut self) -> &mut Framebuffer {
        &mut self.fb
    }

    /// The time-model statistics of the passes run so far (a planes pass pushes one
    /// per plane, sub-plane batch and copy).
    pub fn pass_stats(&self) -> &[PassStats] {
        &self.log.passes
    }

    /// The framebuffer, counters, passes and elaboration.
    pub fn finish(mut self) -> FrameResult {
        if self.elaboration.is_empty() && self.light.is_none() && !self.p.scene.lights.is_empty() {
            // Light 0 drew no pass: its light map still decides the elaboration.
            if self.select_light(0).is_err() {
                self.light = None;
            }
        }
        self.close_light();
        FrameResult {
            fb: self.fb,
            counters: self.ctr,
            passes: self.log.passes,
            elaboration: self.elaboration,
            tables: self.tables,
            clip_stats: self.units.clipper.map(|_| self.clip_stats),
        }
    }

    /// Camera depth pass (objects into the depth buffer).
    fn depth_pass(&mut self) -> Result<(), ConfigError> {
        let (Some(z), Some(zs)) = (&self.units.zbuf, self.zstate.as_mut()) else {
            return Ok(());
        };
        let (w, h) = (self.p.scene.image.width, self.p.scene.image.height);
        let mut c_int = Counters::default();
        let mut c_z = Counters::default();
        let mut stats = PassStats::new(PassKind::ObjectDepth, 0, 0);
        let tris: Vec<&[Vec3; 3]> = (self.p.objects.iter())
            .flat_map(|o| o.triangles.iter().map(|(tri, _)| tri))
            .collect();
        let cam = &self.cam;
        let clipper = self.units.clipper.as_ref();
        let mut rec = self.log.new_rec();
        let clip = draw_triangles(
            &self.units.interp,
            clipper,
            &tris,
            (w, h),
            |tri| project_tri(cam, tri, clipper.is_some(), |_, _| [0.0; 8]),
            |frags, c| {
                c_int += c;
                stats.triangles += 1;
                record_depth_triangle(rec.as_mut(), &frags, &c);
                let ins = depth_writes(&frags, ZBUF_BITS);
                stats.fragments += ins.len() as u64;
                run_span(z, zs, &ins, &mut c_z);
                Ok(())
            },
        )?;
        stats.walked = c_int.pixels_in;
        clip.close(clipper, &mut self.ctr, &mut self.clip_stats);
        counters_add(&mut self.ctr, "polygon_interpolator", c_int);
        counters_add(&mut self.ctr, "shadow_compare (depth buffer writes)", c_z);
        let work = rec.map(|r| r.into_work((w, h), Vec::new(), record::depth_only_rop(), false));
        self.log.push(&self.ctr, stats, work)
    }

    /// Make `li` the current light (its view and light map), closing the previous one.
    fn select_light(&mut self, li: usize) -> Result<(), ConfigError> {
        if self.light.as_ref().is_some_and(|l| l.li == li) {
            return Ok(());
        }
        self.close_light();
        let p = self.p;
        let light = &p.scene.lights[li];
        let lv = LightView::new(light, (p.s_near * 0.5).max(0.05), light_far(p, light));
        let lm_tex = match p.light_maps.get(li).cloned().flatten() {
            Some(t) => Some(
                TextureSampler::new(self.sampler_cfg.clone(), &t)
                    .map_err(|e| e.within(&format!("lights[{li}].light_map")))?,
            ),
            None => None,
        };
        let sstate = self.units.shadow.as_ref().map(|s| s.fresh_state());
        self.light = Some(LightState {
            li,
            lv,
            lm_tex,
            sstate,
        });
        Ok(())
    }

    /// After light 0's passes, record the elaboration (it reads light 0's light map).
    fn close_light(&mut self) {
        if let Some(l) = self.light.take() {
            if l.li == 0 {
                self.elaboration =
                    elaborate(&self.units, l.lm_tex.as_ref(), self.p, &self.log.passes);
            }
        }
    }

    /// Shadow-map pass: light `li`'s occluders into its shadow map.
    fn shadow_map_pass(&mut self, li: usize) -> Result<(), ConfigError> {
        self.select_light(li)?;
        let p = self.p;
        let Some(ls) = self.light.as_mut() else {
            return Ok(());
        };
        let (Some(s), Some(ss)) = (&self.units.shadow, ls.sstate.as_mut()) else {
            return Ok(());
        };
        let lv = &ls.lv;
        let res = p.scene.shafts.shadow_resolution;
        let mut c_int = Counters::default();
        let mut c_s = Counters::default();
        let mut stats = PassStats::new(PassKind::ShadowMap, li, 0);
        let tris: Vec<&[Vec3; 3]> = (p.objects.iter().filter(|o| o.occluder))
            .flat_map(|o| o.triangles.iter().map(|(tri, _)| tri))
            .collect();
        let host = |tri: &&[Vec3; 3]| {
            let mut hv = [HostVertex::ORIGIN; 3];
            for k in 0..3 {
                let q = lv.strq(tri[k]);
                if q[3] <= 1e-9 {
                    return None;
                }
                let mut attrs = [0.0; MAX_ATTRS];
                attrs[0] = q[2] / q[3];
                hv[k] = HostVertex {
                    x: q[0] / q[3] * res as f64,
                    y: q[1] / q[3] * res as f64,
                    attrs,
                };
            }
            if hv.iter().any(|v| v.x.abs() > 4000.0 || v.y.abs() > 4000.0) {
                return None;
            }
            Some(HostTri::Screen(hv))
        };
        let mut rec = self.log.new_rec();
        draw_triangles(
            &self.units.interp,
            None,
            &tris,
            (res, res),
            host,
            |frags, c| {
                c_int += c;
                stats.triangles += 1;
                record_depth_triangle(rec.as_mut(), &frags, &c);
                let ins = depth_writes(&frags, s.depth_bits());
                stats.fragments += ins.len() as u64;
                run_span(s, ss, &ins, &mut c_s);
                Ok(())
            },
        )?;
        stats.walked = c_int.pixels_in;
        counters_add(&mut self.ctr, "polygon_interpolator", c_int);
        counters_add(&mut self.ctr, "shadow_compare (shadow map writes)", c_s);
        let work =
            rec.map(|r| r.into_work((res, res), Vec::new(), record::depth_only_rop(), false));
        self.log.push(&self.ctr, stats, work)
    }

    /// Object colour pass of light `li`.
    fn object_pass(&mut self, li: usize) -> Result<(), ConfigError> {
        self.select_light(li)?;
        let Some(ls) = self.light.as_ref() else {
            return Ok(());
        };
        let ctx = light_ctx(ls, &self.units, &self.cam, self.zstate.as_ref(), self.p);
        object_pass(
            &ctx,
            self.p,
            &mut self.fb,
            &mut self.ctr,
            &mut self.log,
            &mut self.clip_stats,
        )
    }

    /// Sample-plane pass of light `li`.
    fn planes_pass(&mut self, li: usize) -> Result<(), ConfigError> {
        self.select_light(li)?;
        let Some(ls) = self.light.as_ref() else {
            return Ok(());
        };
        let ctx = light_ctx(ls, &self.units, &self.cam, self.zstate.as_ref(), self.p);
        super::planes::planes_pass(
            &ctx,
            self.p,
            &self.tables,
            &mut self.fb,
            &mut self.ctr,
            &mut self.log,
        )
    }
}

fn light_ctx<'b>(
    ls: &'b LightState,
    units: &'b Units,
    cam: &'b CameraView,
    zstate: Option<&'b ShadowState>,
    p: &'b Prepared,
) -> LightCtx<'b> {
    LightCtx {
        li: ls.li,
        units,
        cam,
        lv: &ls.lv,
        lm_tex: ls.lm_tex.as_ref(),
        sstate: ls.sstate.as_ref(),
        zstate,
        swords: None,
        light: &p.scene.lights[ls.li],
        tex_max: max_code(p.scene.shafts.texel_bits),
    }
}

/// The light's far distance for the shadow map: beyond everything the planes reach.
fn light_far(p: &Prepared, _l: &crate::scene::format::Light) -> f64 {
    (p.s_max * 1.5).max(1.0)
}

/// One triangle of a depth-only pass recorded: its walked pixels and its fragments.
fn record_depth_triangle(rec: Option<&mut Rec>, frags: &[Fragment], c: &Counters) {
    if let Some(r) = rec {
        r.prim(c.pixels_in);
        for f in frags {
            r.frag(f.x as i64, f.y as i64);
        }
    }
}

/// Depth-buffer writes (keep the nearer) of fragments whose attribute 0 is the window
/// depth in s16.16: the camera's depth pass and the light's shadow-map pass.
fn depth_writes(frags: &[Fragment], bits: u32) -> Vec<ShadowIn> {
    frags
        .iter()
        .map(|f| ShadowIn::Write {
            x: f.x as i32,
            y: f.y as i32,
            depth: window_depth_word(f.attrs[0], bits),
        })
        .collect()
}

/// Triangles drawn at a time in parallel: fixed, so the split never depends on the
/// thread count, and it bounds the fragments held at once.
const DRAW_BATCH: usize = 256;

/// One triangle drawn: its fragments, its interpolator counters and (through the
/// clipper) the clipper's counters, or the error.
type DrawnTriangle = Result<(Vec<Fragment>, Counters, Option<ClipTally>), ConfigError>;

/// A triangle as the host hands it to the rasteriser: on the screen, or (through the
/// clipper) in clip space.
#[derive(Clone, Copy, Debug)]
enum HostTri {
    Screen([HostVertex; 3]),
    Clip([ClipHost; 3]),
}

/// A clip-space vertex (x, y, z, w) and its host attributes.
#[derive(Clone, Copy, Debug)]
struct ClipHost {
    c: [f64; 4],
    attrs: [f64; MAX_ATTRS],
}

/// The clipper's counters over a pass: its unit counters (kernel events and the
/// clocks a clipped triangle holds the stream), its polygon counts, the triangles fed.
#[derive(Clone, Copy, Debug, Default)]
struct ClipTally {
    ctr: Counters,
    stats: ClipStats,
    n: u64,
}

impl std::ops::AddAssign for ClipTally {
    fn add_assign(&mut self, o: ClipTally) {
        self.ctr += o.ctr;
        self.stats += o.stats;
        self.n += o.n;
    }
}

impl ClipTally {
    /// End the pass's span through the clipper: its timing counters (one stream of
    /// `n` triangles) added, the counters filed under "clipper" and the polygon counts
    /// into `stats`. Nothing when the frame has no clipper.
    fn close(
        mut self,
        clipper: Option<&Clipper>,
        ctr: &mut BTreeMap<String, Counters>,
        stats: &mut ClipStats,
    ) {
        if let Some(cl) = clipper {
            rtl_model::driver::add_span_counters(cl.timing(), self.n, &mut self.ctr);
            counters_add(ctr, "clipper", self.ctr);
            *stats += self.stats;
        }
    }
}

/// A clip-space triangle through the clipper, its polygon fanned into triangles
/// (v0, vᵢ, vᵢ₊₁) for the interpolator, each set up and walked; the window depth the
/// clipper computes is attribute 0.
fn draw_clipped(
    u: &PolygonInterpolator,
    cl: &Clipper,
    v: &[ClipHost; 3],
    w: u32,
    h: u32,
    ctr: &mut Counters,
) -> Result<(Vec<Fragment>, ClipTally), ConfigError> {
    let k = u.attrs() as usize;
    let mut t = ClipTally {
        n: 1,
        ..ClipTally::default()
    };
    let mut input = ClipIn::default();
    for (i, hv) in v.iter().enumerate() {
        input.v[i] = cl.vertex_from_f64(i, hv.c, &hv.attrs[..k], &mut t.ctr)?;
    }
    let out = cl.kernel(&mut t.stats, &input, &mut t.ctr);
    let verts: Vec<Vertex> = out
        .vertices()
        .iter()
        .map(|s| {
            let mut attrs = s.attrs;
            attrs[0] = s.depth;
            Vertex {
                x: s.x,
                y: s.y,
                attrs,
            }
        })
        .collect();
    let mut frags = Vec::new();
    for i in 1..verts.len().saturating_sub(1) {
        let s = u.setup_triangle(&[verts[0], verts[i], verts[i + 1]], ctr);
        walk(u, &s, w, h, ctr, &mut frags);
    }
    Ok((frags, t))
}

/// Each item's triangle (`host`: its host vertices, None when it is skipped) drawn by
/// [`draw_triangle`] on its own, a batch of items in parallel; `sink` gets each drawn
/// triangle's fragments and interpolator counters in item order. The counters are
/// sums, so their total is the one drawing into one set gives, and the first error
/// in item order is returned after the triangles before it were sunk, as drawing
/// one after the other did.
fn draw_triangles<T: Sync>(
    u: &PolygonInterpolator,
    clipper: Option<&Clipper>,
    items: &[T],
    (w, h): (u32, u32),
    host: impl Fn(&T) -> Option<HostTri> + Sync,
    mut sink: impl FnMut(Vec<Fragment>, Counters) -> Result<(), ConfigError>,
) -> Result<ClipTally, ConfigError> {
    let mut clip = ClipTally::default();
    for batch in items.chunks(DRAW_BATCH) {
        let drawn: Vec<Option<DrawnTriangle>> = batch
            .par_iter()
            .map(|item| {
                let mut c = Counters::default();
                Some(match (host(item)?, clipper) {
                    (HostTri::Screen(hv), _) => {
                        draw_triangle(u, &hv, w, h, &mut c).map(|f| (f, c, None))
                    }
                    (HostTri::Clip(cv), Some(cl)) => {
                        draw_clipped(u, cl, &cv, w, h, &mut c).map(|(f, t)| (f, c, Some(t)))
                    }
                    // Clip-space triangles come only from a frame with a clipper.
                    (HostTri::Clip(_), None) => return None,
                })
            })
            .collect();
        for d in drawn.into_iter().flatten() {
            let (frags, c, t) = d?;
            if let Some(t) = t {
                clip += t;
            }
            sink(frags, c)?;
        }
    }
    Ok(clip)
}

/// Project a world triangle with per-vertex attributes. Without the clipper (`clip`
/// false: the scene's objects stay inside its planes, [`crate::scene::clip`]) onto
/// the screen, `None` if any vertex is behind the eye (skipped, counted by the
/// caller's triangle count only); attrs[0] is replaced by the window depth. With it,
/// in clip space, for the clipper to cut and divide.
fn project_tri(
    cam: &CameraView,
    tri: &[Vec3; 3],
    clip: bool,
    attrs: impl Fn(usize, Vec3) -> [f64; 8],
) -> Option<HostTri> {
    if clip {
        let v = std::array::from_fn(|k| ClipHost {
            c: cam.view_proj.apply(tri[k]),
            attrs: host_attrs(attrs(k, tri[k])),
        });
        return Some(HostTri::Clip(v));
    }
    let mut hv = [HostVertex::ORIGIN; 3];
    for k in 0..3 {
        let (x, y, z) = cam.project(tri[k])?;
        if x.abs() > 8000.0 || y.abs() > 8000.0 {
            return None;
        }
        let mut a = host_attrs(attrs(k, tri[k]));
        a[0] = z;
        hv[k] = HostVertex { x, y, attrs: a };
    }
    Some(HostTri::Screen(hv))
}

/// The object fragments' colours (`rgb`, one lane per channel) at their pixels `at`
/// (x, y) added into the framebuffer. Triangles of one object may cover a pixel
/// twice: then every destination is read before any is written, as the span driver
/// ran it; where no pixel has two fragments (checked), in place, each fragment
/// reading its pixel as the span driver read it (alpha stays 0, as in the planes'
/// blend).
fn blend_into(
    u: &Blend,
    fb: &mut Framebuffer,
    at: &[(u32, u32)],
    rgb: &[Vec<u32>; 3],
    ctr: &mut BTreeMap<String, Counters>,
) {
    let w = fb.width as usize;
    let index = |&(x, y): &(u32, u32)| y as usize * w + x as usize;
    let colour = |i: usize| [rgb[0][i], rgb[1][i], rgb[2][i], 0];
    if covers_once(fb, at.iter().map(index), &mut Vec::new()) {
        let (pixels, _) = fb.data.as_chunks_mut::<4>();
        let mut span = UnitSpan::default();
        if span.feed_blend_in_place(u, at.len(), |i| (index(&at[i]), colour(i)), pixels) {
            span.close("additive_blend", u.timing(), ctr);
            return;
        }
    }
    let ins: Vec<BlendIn> = at
        .iter()
        .enumerate()
        .map(|(i, &(x, y))| BlendIn {
            src: colour(i),
            dst: fb.pixel(x, y),
        })
        .collect();
    let mut c = Counters::default();
    let out = run_span(u, &mut (), &ins, &mut c);
    counters_add(ctr, "additive_blend", c);
    for (&(x, y), o) in at.iter().zip(out) {
        fb.set(x, y, [o[0], o[1], o[2], 0]);
    }
}

/// The objects lit by this light: per-vertex colour (albedo · Lambert · I/s² ·
/// exp(−ρκ(s + T)) as a fraction of full scale) × light map × shadow, depth-tested.
fn object_pass(
    ctx: &LightCtx,
    p: &Prepared,
    fb: &mut Framebuffer,
    ctr: &mut BTreeMap<String, Counters>,
    log: &mut PassLog,
    clip_stats: &mut ClipStats,
) -> Result<(), ConfigError> {
    let u = ctx.units;
    let sc = &p.scene;
    let (w, h) = (sc.image.width, sc.image.height);
    let clipper = u.clipper.as_ref();
    let mut stats = PassStats::new(
        PassKind::Objects,
        ctx.li,
        1 + u32::from(ctx.lm_tex.is_some()) + u32::from(ctx.sstate.is_some()),
    );
    let mut c_int = Counters::default();
    // Every drawn triangle's walked fragments in lanes of the interpolator's
    // attributes (every one inside), in draw order, for the chunked units.
    let mut lanes = PolyLanes::default();
    lanes.clear(u.interp.attrs() as usize);
    let tris: Vec<(&ObjectMesh, &[Vec3; 3], &[Vec3; 3])> = (p.objects.iter())
        .flat_map(|o| o.triangles.iter().map(move |(tri, nrm)| (o, tri, nrm)))
        .collect();
    let host = |&(o, tri, nrm): &(&ObjectMesh, &[Vec3; 3], &[Vec3; 3])| {
        let attrs = |k: usize, pt: Vec3| object_vertex_attrs(ctx, p, o.color, nrm[k], pt);
        project_tri(ctx.cam, tri, clipper.is_some(), attrs)
    };
    // When recording: each drawn triangle's first fragment in `lanes` and its walked
    // pixels.
    let recording = log.recording();
    let mut prims: Vec<(usize, u64)> = Vec::new();
    let clip = draw_triangles(&u.interp, clipper, &tris, (w, h), host, |frags, c| {
        c_int += c;
        stats.triangles += 1;
        if recording {
            prims.push((lanes.len(), c.pixels_in));
        }
        lanes.reserve(frags.len());
        for f in &frags {
            lanes.push(&PolyOut {
                x: f.x as i64,
                y: f.y as i64,
                inside: true,
                attrs: f.attrs,
            });
        }
        Ok(())
    })?;
    stats.walked = c_int.pixels_in;
    clip.close(clipper, ctr, clip_stats);
    counters_add(ctr, "polygon_interpolator", c_int);
    // The object pass in one chunk (fig6: 125 390 walked fragments).
    let mut b = ChunkBuffers::default();
    let mut zspan = UnitSpan::default();
    ctx.visible(
        &lanes,
        (w, h),
        |l, i| window_depth_word(l.attrs[0][i], ZBUF_BITS),
        &mut zspan,
        &mut b,
    );
    ctx.close_visible(zspan, ctr);
    stats.fragments = b.visible.len() as u64;
    let mut spans = HilSpans::default();
    b.cut_outside_square = !recording;
    ctx.h_il(&lanes, 4, &mut spans, &mut b);
    spans.close(ctx, ctr);
    object_colour(ctx, &lanes, &b.visible, &b.hil, fb, ctr);
    let work = recording.then(|| object_work(ctx, log.bands, &prims, &lanes, &b, sc, (w, h)));
    log.push(ctr, stats, work)
}

/// An object vertex's host attributes for light `ctx`: 0 (the depth's place), the
/// vertex colour albedo · Lambert · I/s² · exp(−ρκ(s + T)) · exposure as a fraction of
/// full scale (clamped at 1) per channel, and the light coordinates.
fn object_vertex_attrs(
    ctx: &LightCtx,
    p: &Prepared,
    color: [f64; 3],
    normal: Vec3,
    pt: Vec3,
) -> [f64; 8] {
    let medium = p.scene.medium;
    let to_l = vec3(ctx.light.position) - pt;
    let s2 = to_l.dot(to_l).max(1e-12);
    let lambert = normal.dot(to_l.normalized()).max(0.0);
    let tt = (pt - ctx.cam.eye).length();
    let atten = (-medium.rho * medium.kappa * (s2.sqrt() + tt)).exp();
    let light_scale = ctx.light.intensity * lambert * atten / s2 * p.exposure / 255.0;
    let la = ctx.light_attrs(pt);
    [
        0.0,
        (color[0] * light_scale * ctx.light.color[0]).min(1.0),
        (color[1] * light_scale * ctx.light.color[1]).min(1.0),
        (color[2] * light_scale * ctx.light.color[2]).min(1.0),
        la[0],
        la[1],
        la[2],
        la[3],
    ]
}

/// The visible fragments' colour (`visible`: indices into `lanes`): each channel of the
/// vertex colour (attributes 1..=3, unorm texel codes) modulated by H·I_l (`hil`, one
/// per visible fragment), added into the framebuffer.
fn object_colour(
    ctx: &LightCtx,
    lanes: &PolyLanes,
    visible: &[u32],
    hil: &[u32],
    fb: &mut Framebuffer,
    ctr: &mut BTreeMap<String, Counters>,
) {
    let u = ctx.units;
    // Each channel of the vertex colour by H·I_l, one channel at a time in lanes (one
    // span of 3 × fragments modulates, as the pairs were).
    let mut span = UnitSpan::default();
    let mut rgb: [Vec<u32>; 3] = Default::default();
    let mut col = Vec::with_capacity(visible.len());
    for (c, ch) in rgb.iter_mut().enumerate() {
        let attr = &lanes.attrs[1 + c];
        col.clear();
        col.extend(
            visible
                .iter()
                .map(|&i| attr_unorm(attr[i as usize], ctx.tex_max)),
        );
        span.feed_modulate(&u.modulate, &col, Operand::Lanes(hil), ch);
    }
    span.close("modulate", u.modulate.timing(), ctr);
    let at: Vec<(u32, u32)> = visible
        .iter()
        .map(|&i| (lanes.x[i as usize] as u32, lanes.y[i as usize] as u32))
        .collect();
    blend_into(&u.blend, fb, &at, &rgb, ctr);
}

/// The object pass's record: per drawn triangle (`prims`: its first fragment in `px`
/// and its walked pixels) its visible fragments (`b.visible`, indices into `px` in
/// walk order) and, depth-tested, those the test killed; the kept fragments' H·I_l
/// texels.
fn object_work(
    ctx: &LightCtx,
    bands: Option<SampleBands>,
    prims: &[(usize, u64)],
    px: &PolyLanes,
    b: &ChunkBuffers,
    sc: &Scene,
    (w, h): (u32, u32),
) -> PassWork {
    let depth_tested = ctx.units.zbuf.is_some() && ctx.zstate.is_some();
    let mut rec = Rec::sampled(bands);
    // The visible fragments (indices into `px`, in walk order) per triangle, and the
    // positions among them of those the record keeps.
    let mut vis = b.visible.iter().enumerate().peekable();
    let mut sel = Vec::new();
    for (k, &(first, walked)) in prims.iter().enumerate() {
        let end = prims.get(k + 1).map_or(px.len(), |p| p.0);
        rec.prim(walked);
        let mut visible = 0;
        for c in first..end {
            let (x, y) = (px.x[c], px.y[c]);
            match vis.peek() {
                Some(&(j, &i)) if i as usize == c => {
                    if rec.frag(x, y) {
                        sel.push(j as u32);
                    }
                    visible += 1;
                    vis.next();
                }
                _ if depth_tested => rec.killed_at(x, y),
                _ => {}
            }
        }
        if depth_tested {
            rec.killed((end - first) - visible);
        }
    }
    let kept = if sel.len() == b.visible.len() {
        record::Kept::All
    } else {
        record::Kept::Some(sel)
    };
    let (mut lm, mut sm) = (Vec::new(), Vec::new());
    ctx.hil_footprint(b, &mut lm, &mut sm);
    let tex = ctx.hil_textures();
    let runs = ctx.hil_runs(&lm, &sm);
    record::interleave_kept(&runs, b.visible.len(), &kept, &mut rec.texels);
    let rop = record::blend_rop(sc.shafts.fb_bits, depth_tested);
    rec.into_work((w, h), tex, rop, depth_tested)
}

impl Elaborated {
    fn present(name: &str, summary: UnitSummary) -> Self {
        Elaborated {
            name: name.to_string(),
            summary: Some(summary),
            left_out: None,
            gates_saved: 0.0,
            cycles_saved: 0,
        }
    }

    fn left_out(name: &str, why: &str, gates_saved: f64, cycles_saved: u64) -> Self {
        Elaborated {
            name: name.to_string(),
            summary: None,
            left_out: Some(why.to_string()),
            gates_saved,
            cycles_saved,
        }
    }
}

/// What the frame elaborated and what it left out (with the gates the unit would
/// have cost and the plane fragments it would have processed).
fn elaborate(
    units: &Units,
    lm: Option<&TextureSampler>,
    p: &Prepared,
    passes: &[PassStats],
) -> Vec<Elaborated> {
    let plane_frags: u64 = passes
        .iter()
        .filter(|s| s.kind == PassKind::Plane)
        .map(|s| s.fragments)
        .sum();
    let mut out: Vec<Elaborated> = [
        ("polygon_interpolator", UnitSummary::of(&units.interp)),
        ("texture_sampler (F)", UnitSummary::of(&units.f_tex)),
        ("texture_sampler (h)", UnitSummary::of(&units.h_tex)),
        ("modulate", UnitSummary::of(&units.modulate)),
        ("additive_blend", UnitSummary::of(&units.blend)),
    ]
    .into_iter()
    .map(|(name, s)| Elaborated::present(name, s))
    .collect();
    // The clipper only when the scene needs it (the chip lists it left out otherwise).
    if let Some(cl) = &units.clipper {
        out.insert(0, Elaborated::present("clipper", UnitSummary::of(cl)));
    }
    let cfg = &p.scene.shafts;
    let would_shadow = ShadowCompareConfig {
        width: cfg.shadow_resolution,
        height: cfg.shadow_resolution,
        depth_bits: cfg.shadow_depth_bits,
        bias: 1,
        frag_frac_bits: 0,
        ..ShadowCompareConfig::geforce()
    }
    .build()
    .map_or(0.0, |s| s.cost().gates_nand2());
    out.push(match &units.shadow {
        Some(s) => Elaborated::present("shadow_compare (shadow map)", UnitSummary::of(s)),
        None => Elaborated::left_out(
            "shadow_compare (shadow map)",
            "no occluders in the scene",
            would_shadow,
            plane_frags,
        ),
    });
    out.push(match lm {
        Some(t) => Elaborated::present("texture_sampler (light map)", UnitSummary::of(t)),
        None => Elaborated::left_out(
            "texture_sampler (light map)",
            "light 0 has no light map",
            UnitSummary::of(&units.h_tex).gates_nand2,
            plane_frags,
        ),
    });
    out.push(if lm.is_some() || units.shadow.is_some() {
        Elaborated::present("projective_texcoord", UnitSummary::of(&units.proj))
    } else {
        Elaborated::left_out(
            "projective_texcoord",
            "no light map and no shadow map",
            units.proj.cost().gates_nand2(),
            plane_frags,
        )
    });
    out.push(match &units.zbuf {
        Some(z) => Elaborated::present("shadow_compare (depth buffer)", UnitSummary::of(z)),
        None => Elaborated::left_out(
            "shadow_compare (depth buffer)",
            "no objects in the scene",
            0.0,
            plane_frags,
        ),
    });
    out.push(if cfg.subplanes > 1 {
        Elaborated::present("additive_blend (J buffer)", UnitSummary::of(&units.j_blend))
    } else {
        Elaborated::left_out(
            "additive_blend (J buffer) + texture_sampler (J)",
            "m = 1: no sub-plane path",
            units.j_blend.cost().gates_nand2(),
            0,
        )
    });
    out
}
