//! The evaluation core of `optimize`: a scene and a width assignment
//! (param → value, the names `sweep` knows) in, the elaborated cost and the error
//! against the scene's f64 reference out.
//!
//! Every render goes through the path `sweep` uses: a shafts scene through
//! `pipeline::shafts::cli::render_scene`, a glare scene through `pipeline::glare::cli::render_and_predict_over`
//! against `reference_levels` (the analytic formulas over the frame's sources and line
//! draws). The reference is computed ONCE per [`Evaluator`] — for glare once per
//! framebuffer width: the glare model's luminances are framebuffer codes (A = 29 is
//! 29 codes, saturating at the largest code), so the reference, like `sweep`'s, is
//! drawn at the frame's `fb_bits`; it comes from the frame at the scene's other
//! widths (so a narrower `noise_bits` pays for moving its flare lines).
//!
//! A shafts scene has two references ([`Reference`]). `Wide` (the default) is the
//! same sample-plane frame with every bit width wide (texel, weight, coordinate and
//! framebuffer 16 bits, shadow depth 24: `attribute`'s "ideal" of each) and the
//! scene's own table sizes and sampling: it isolates what the widths cost. (With the
//! tables wide too, 1024-texel light maps and a 2048² shadow map, the defaults of
//! `fig6` at 48x32 were 6.6 levels max from it: the light map's rim and the shadow
//! edges move by a texel, which no width repairs.) `Truth`
//! is `sweep`'s ray-marched f64 reference (`reference_image`), which also holds the
//! algorithm's own error (n planes, the mesh, the sphere's tessellation): on `fig6`
//! at 96x64 the defaults are already 7.2 levels RMS from it (`sweep --scene fig6
//! --param fb_bits --values 8 --image 96x64`), so no width budget of a few levels can
//! be met against it.

use crate::frame::sweep::{FrameParam, FRAME_PARAMS};
use crate::pipeline::envmap::render::Truth;
use crate::pipeline::envmap::scene_render::{render_scene as render_env, render_scene_against};
use crate::pipeline::envmap::sweep::{envmap_row_of, envmap_scenes, ENVMAP_PARAMS};
use crate::pipeline::glare::background::from_framebuffer;
use crate::pipeline::glare::cli::{reference_levels, render_and_predict_over};
use crate::pipeline::glare::sweep::GLARE_PARAMS;
use crate::pipeline::shafts::cli::{reference_image, render_scene};
use crate::pipeline::shafts::sweep::{elaborated_gates, Param, Value, DEFAULT_TRUTH_SAMPLES};
use crate::report::image_out::Framebuffer;
use crate::report::metrics::{error_stats, ErrorStats};
use crate::scene::format::{
    Scene, DEFAULT_ACC_FRAC_BITS, DEFAULT_ACC_INT_BITS, DEFAULT_NEWTON_FRAC_BITS,
    DEFAULT_RECIP_ENTRY_BITS, DEFAULT_RECIP_INDEX_BITS,
};
use std::cell::RefCell;
use std::collections::{BTreeMap, HashMap};
use std::rc::Rc;
use std::time::Instant;

/// NAND2 equivalents of one RAM bit in the `area` objective: a 6-transistor SRAM
/// cell against the 4 transistors of a NAND2 (an assumption of this model, not a
/// figure from the seeds; docs/optimize.md).
pub const RAM_BIT_NAND2: f64 = 1.5;

/// Which pipeline's widths a scene exposes to the search.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Shafts,
    Glare,
    /// An environment-map scene (`[environment]`): `envmap::sweep`'s parameters.
    Envmap,
    /// A frame of several pipelines (`frame::sweep::is_frame_scene`): every
    /// pipeline's widths by qualified name (`shafts.texel_bits`, `glare.fb_bits`),
    /// each point rendered through the frame against its composed reference.
    Frame,
}

/// How a parameter is narrowed by one step of the search.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// One bit less (a width, or the log2 of a table's size).
    Bit,
    /// Half the size (a table side or a count).
    Halve,
}

/// The glare widths the search narrows: `sweep`'s glare names but `radial`, a
/// switch.
fn glare_search() -> Vec<&'static str> {
    GLARE_PARAMS
        .iter()
        .copied()
        .filter(|p| *p != "radial")
        .collect()
}

/// The shafts widths searched when `--params` is not given: the bit widths. The
/// table sizes (f_texels, light_map_texels, shadow_resolution) and the sampling
/// counts (planes, subplanes) are the algorithm's sampling, kept as the scene has
/// them in the `Wide` reference too; `--params` can still name them.
const SHAFTS_DEFAULT: &[&str] = &[
    "texel_bits",
    "fb_bits",
    "weight_bits",
    "coord_frac_bits",
    "shadow_depth_bits",
];

impl Kind {
    /// The kind of a scene: glare with a `[glare]` section, environment map with an
    /// `[environment]` section (and no `[glare]`, as `environment_scene` reads it),
    /// else shafts. The shading scenes (`shading-*`, not `Scene`s) are refused by the
    /// CLI before this.
    pub fn of(scene: &Scene) -> Kind {
        if crate::frame::sweep::is_frame_scene(scene).unwrap_or(false) {
            Kind::Frame
        } else if scene.glare.is_some() {
            Kind::Glare
        } else if scene.environment.is_some() {
            Kind::Envmap
        } else {
            Kind::Shafts
        }
    }

    /// The parameters searched when `--params` is not given.
    pub fn default_params(self) -> Vec<&'static str> {
        match self {
            Kind::Shafts => SHAFTS_DEFAULT.to_vec(),
            Kind::Glare => glare_search(),
            Kind::Envmap => ENVMAP_PARAMS.to_vec(),
            Kind::Frame => {
                // Each pipeline's own defaults, qualified.
                let mut v: Vec<&'static str> = SHAFTS_DEFAULT
                    .iter()
                    .map(|f| ("shafts", *f))
                    .chain(glare_search().into_iter().map(|f| ("glare", f)))
                    .chain([
                        ("shading", "factor_bits"),
                        ("shading", "cube_face"),
                        ("environment", "side"),
                    ])
                    .map(|(pipeline, field)| FrameParam { pipeline, field }.qualified_static())
                    .collect();
                v.retain(|q| !q.is_empty());
                v
            }
        }
    }

    /// Every parameter the search can narrow for this kind.
    pub fn known(self) -> Vec<&'static str> {
        match self {
            Kind::Shafts => Param::ALL
                .into_iter()
                .filter(|p| !p.is_pair())
                .map(Param::name)
                .collect(),
            Kind::Glare => glare_search(),
            Kind::Envmap => ENVMAP_PARAMS.to_vec(),
            Kind::Frame => FRAME_PARAMS
                .iter()
                .filter(|(_, f, _)| *f != "radial")
                .map(|(_, _, q)| *q)
                .collect(),
        }
    }

    /// [`Kind::default_params`] for `scene`: a frame scene's narrowed to the
    /// pipelines its frame runs.
    pub fn default_params_for(self, scene: &Scene) -> Vec<&'static str> {
        let mut v = self.default_params();
        if self == Kind::Frame {
            let present = crate::frame::plan::frame_pipelines(scene).unwrap_or_default();
            v.retain(|q| {
                FrameParam::of_qualified(q).is_some_and(|p| present.contains(&p.pipeline))
            });
        }
        v
    }

    /// `--params` for `scene`: a frame scene's names resolved as `sweep` resolves
    /// them (`shafts.texel_bits`, or a field only one of its pipelines has), the
    /// others checked by [`Kind::parse_params`]; errors name `params`.
    pub fn parse_params_for(self, scene: &Scene, list: &str) -> Result<Vec<&'static str>, String> {
        if self != Kind::Frame {
            return self.parse_params(list);
        }
        let mut out: Vec<&'static str> = Vec::new();
        for item in list.split(',') {
            let p = crate::frame::sweep::resolve_param(scene, item)
                .map_err(|e| e.replacen("param:", "params:", 1))?;
            let q = p.qualified_static();
            if q.ends_with(".radial") {
                return Err("params: glare.radial is a switch, not a width to narrow".into());
            }
            if out.contains(&q) {
                return Err(format!("params: '{q}' is given twice"));
            }
            out.push(q);
        }
        Ok(out)
    }

    /// How `param` narrows.
    pub fn step(self, param: &str) -> Step {
        match (self, param) {
            (Kind::Shafts, "f_texels" | "light_map_texels" | "shadow_resolution")
            | (Kind::Shafts, "planes" | "subplanes") => Step::Halve,
            // The voxel map's side is a power of two (`environment.side`).
            (Kind::Envmap, _) => Step::Halve,
            (Kind::Frame, q) => match FrameParam::of_qualified(q) {
                Some(p) if p.pipeline == "environment" => Step::Halve,
                Some(p) if matches!(p.field, "cube_face" | "factor_size") => Step::Halve,
                Some(p) if p.pipeline == "shafts" => Kind::Shafts.step(p.field),
                _ => Step::Bit,
            },
            _ => Step::Bit,
        }
    }

    /// `--params` checked against this kind: each name known (`-` read as `_`), none
    /// twice; errors name `params`.
    pub fn parse_params(self, list: &str) -> Result<Vec<&'static str>, String> {
        let known = self.known();
        let mut out: Vec<&'static str> = Vec::new();
        for item in list.split(',') {
            let norm = item.trim().replace('-', "_");
            let p = known.iter().find(|k| **k == norm).ok_or_else(|| {
                format!(
                    "params: unknown parameter '{}' for this {} scene (known: {})",
                    item.trim(),
                    self.name(),
                    known.join(", ")
                )
            })?;
            if out.contains(p) {
                return Err(format!("params: '{p}' is given twice"));
            }
            out.push(p);
        }
        Ok(out)
    }

    pub fn name(self) -> &'static str {
        match self {
            Kind::Shafts => "shafts",
            Kind::Glare => "glare",
            Kind::Envmap => "environment-map",
            Kind::Frame => "frame",
        }
    }

    /// The value of `param` in `scene`.
    pub fn get(self, scene: &Scene, param: &str) -> Result<u32, String> {
        match self {
            Kind::Shafts => match Param::from_name(param)? {
                Param::Mesh | Param::HTexels => Err(format!("params: '{param}' is a pair (AxB)")),
                p => Ok(p.get(&scene.shafts)),
            },
            Kind::Glare => {
                let g = &scene.glare.as_ref().ok_or("scene: no [glare] section")?.hw;
                crate::pipeline::glare::sweep::get(g, param)
            }
            Kind::Envmap => {
                let e = scene
                    .environment
                    .as_ref()
                    .ok_or("scene: no [environment] section")?;
                match param {
                    "side" => Ok(e.side),
                    _ => Err(format!(
                        "params: unknown environment-map parameter '{param}'"
                    )),
                }
            }
            Kind::Frame => FrameParam::of_qualified(param)
                .ok_or_else(|| format!("params: unknown frame parameter '{param}'"))?
                .get(scene),
        }
    }

    /// `base` with `values[i]` set into `params[i]` (through `sweep`'s own setters),
    /// validated: an invalid point is an error naming the field.
    pub fn apply(self, base: &Scene, params: &[&str], values: &[u32]) -> Result<Scene, String> {
        let mut s = base.clone();
        for (p, &v) in params.iter().zip(values) {
            match self {
                Kind::Shafts => Param::from_name(p)?.apply(&mut s.shafts, Value::One(v))?,
                Kind::Glare => {
                    let g = s.glare.as_mut().ok_or("scene: no [glare] section")?;
                    crate::pipeline::glare::sweep::apply(&mut g.hw, p, v)?;
                }
                // `sweep`'s own setter (validates the scene, naming `environment.side`).
                Kind::Envmap => s = envmap_scenes(&s, p, &[v])?.remove(0),
                Kind::Frame => FrameParam::of_qualified(p)
                    .ok_or_else(|| format!("params: unknown frame parameter '{p}'"))?
                    .apply(&mut s, v)?,
            }
        }
        s.validate().map_err(|e| e.to_string())?;
        Ok(s)
    }

    /// The output (framebuffer) width of a scene, for the bound of [`output_bound`];
    /// None when the pipeline's error is not measured on such codes against a
    /// reference the evaluator holds (environment maps: `envmap_row` measures the
    /// object's pixels against the Phong truth inside the render), so no bound.
    pub fn fb_bits(self, scene: &Scene) -> Option<u32> {
        match self {
            Kind::Shafts => Some(scene.shafts.fb_bits),
            Kind::Glare => Some(scene.glare.as_ref().map_or(8, |g| g.hw.fb_bits)),
            // The frame's reference follows its picture (the glare over it): no
            // bound from one reference, so nothing is pruned.
            Kind::Envmap | Kind::Frame => None,
        }
    }
}

/// What one simulated configuration costs and how far it is from the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metrics {
    /// Gates (NAND2 equivalents) of the units the frame elaborated, at these widths.
    pub gates: f64,
    pub ram_bits: u64,
    /// Error against the reference, 8-bit levels, over every channel of the image.
    pub error: ErrorStats,
    /// Predicted hardware time (GeForce2 GTS for shafts, the glare ASIC for glare).
    pub predicted_seconds: f64,
    /// Wall time of the simulation.
    pub wall_seconds: f64,
}

impl Metrics {
    /// A sweep row's measurements (the environment-map and frame kinds measure
    /// through `sweep`'s own row).
    pub fn of_row(r: &crate::report::sweep_out::SweepRow) -> Metrics {
        Metrics {
            gates: r.gates_nand2,
            ram_bits: r.ram_bits,
            error: ErrorStats {
                mean_abs: r.mean_abs_levels,
                rms: r.rms_levels,
                max: r.max_levels,
                n: 0,
            },
            predicted_seconds: r.predicted_hw_seconds,
            wall_seconds: r.wall_seconds,
        }
    }
}

/// What a shafts scene's error is measured against (module notes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reference {
    Wide,
    Truth,
}

impl Reference {
    pub fn parse(text: &str) -> Result<Reference, String> {
        match text.trim() {
            "wide" => Ok(Reference::Wide),
            "truth" => Ok(Reference::Truth),
            other => Err(format!(
                "reference: unknown reference '{other}' (known: wide, truth)"
            )),
        }
    }
}

/// `scene` with every shafts bit width wide (never narrower than it is), its table
/// sizes and sampling unchanged: the `Wide` reference's configuration.
pub fn wide_shafts(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    let c = &mut s.shafts;
    c.texel_bits = c.texel_bits.max(16);
    c.fb_bits = c.fb_bits.max(16);
    c.weight_bits = c.weight_bits.max(16);
    c.coord_frac_bits = c.coord_frac_bits.max(16);
    c.shadow_depth_bits = c.shadow_depth_bits.max(24);
    // The interpolator's accumulators and the projective reciprocal: never narrower
    // than the GeForce defaults (s20.24, a 2^8 × 16-bit ROM, 20-bit Newton step), which
    // are already wider than the s16.16 / 4.12 outputs they feed; so the reference of
    // a scene at the defaults is the one it had before these were searchable.
    c.acc_int_bits = c.acc_int_bits.max(DEFAULT_ACC_INT_BITS);
    c.acc_frac_bits = c.acc_frac_bits.max(DEFAULT_ACC_FRAC_BITS);
    c.recip_index_bits = c.recip_index_bits.max(DEFAULT_RECIP_INDEX_BITS);
    c.recip_entry_bits = c.recip_entry_bits.max(DEFAULT_RECIP_ENTRY_BITS);
    c.newton_frac_bits = c.newton_frac_bits.max(DEFAULT_NEWTON_FRAC_BITS);
    s
}

/// A scene, its reference (computed once) and what every render of it needs.
pub struct Evaluator {
    pub kind: Kind,
    pub base: Scene,
    pub reference: Vec<[f64; 3]>,
    /// Wall time of the reference.
    pub reference_seconds: f64,
    /// A glare scene's shafts background, drawn once (it does not depend on the glare
    /// widths).
    backdrop: Option<Framebuffer>,
    /// A glare scene's references by framebuffer width (the base's is `reference`).
    by_fb: RefCell<BTreeMap<u32, Rc<Vec<[f64; 3]>>>>,
    /// An environment-map scene's Phong truths, by the scene (as TOML) they were drawn
    /// for: the truth depends on the map's side s (Λ = g(λ·|r|, s, I)), so one per
    /// side searched, drawn the first time that scene is rendered and reused after
    /// (the verification's fresh render of `best.toml`).
    truths: RefCell<HashMap<String, Rc<Truth>>>,
}

impl Evaluator {
    /// Validate `base` and compute its reference (`reference` matters for shafts
    /// scenes only).
    pub fn new(base: &Scene, reference: Reference) -> Result<Evaluator, String> {
        base.validate().map_err(|e| e.to_string())?;
        let kind = Kind::of(base);
        let t0 = Instant::now();
        let (reference, backdrop) = match kind {
            Kind::Shafts => match reference {
                Reference::Truth => (reference_image(base, DEFAULT_TRUTH_SAMPLES)?.0, None),
                Reference::Wide => {
                    let wide = wide_shafts(base);
                    wide.validate()
                        .map_err(|e| format!("{e} (the wide reference of the scene)"))?;
                    (render_scene(&wide)?.0.levels(), None)
                }
            },
            // The environment map's truth (Phong, with the cos φ test) depends on the
            // map's side, which is searched: drawn by `evaluate`, once per scene.
            // A frame's composed reference is drawn with each render (`evaluate`).
            Kind::Envmap | Kind::Frame => (Vec::new(), None),
            Kind::Glare => {
                let backdrop = if crate::frame::plan::shafts_backdrop(base) {
                    Some(crate::frame::run::shafts_backdrop(base).map_err(|e| e.to_string())?)
                } else {
                    None
                };
                let bg = glare_background(base, backdrop.as_ref());
                let (f, _, _) =
                    render_and_predict_over(base, bg.as_deref()).map_err(|e| e.to_string())?;
                (
                    reference_levels(base, &f).map_err(|e| e.to_string())?,
                    backdrop,
                )
            }
        };
        let by_fb = RefCell::new(BTreeMap::from([(
            kind.fb_bits(base).unwrap_or(0),
            Rc::new(reference.clone()),
        )]));
        Ok(Evaluator {
            kind,
            base: base.clone(),
            reference,
            reference_seconds: t0.elapsed().as_secs_f64(),
            backdrop,
            by_fb,
            truths: RefCell::new(HashMap::new()),
        })
    }

    /// The reference `scene` is measured against: the one reference of a shafts
    /// scene; for glare, the reference at `scene`'s framebuffer width (drawn from the
    /// base scene at that width the first time it is asked for).
    pub fn reference_for(&self, scene: &Scene) -> Result<Rc<Vec<[f64; 3]>>, String> {
        let fb = self.kind.fb_bits(scene).unwrap_or(0);
        if self.kind != Kind::Glare {
            return Ok(Rc::new(self.reference.clone()));
        }
        if let Some(r) = self.by_fb.borrow().get(&fb) {
            return Ok(r.clone());
        }
        let mut at = self.base.clone();
        if let Some(g) = at.glare.as_mut() {
            g.hw.fb_bits = fb;
        }
        at.validate().map_err(|e| e.to_string())?;
        let bg = glare_background(&at, self.backdrop.as_ref());
        let (f, _, _) = render_and_predict_over(&at, bg.as_deref()).map_err(|e| e.to_string())?;
        let r = Rc::new(reference_levels(&at, &f).map_err(|e| e.to_string())?);
        self.by_fb.borrow_mut().insert(fb, r.clone());
        Ok(r)
    }

    /// Render `scene` (the base with other widths) and measure it.
    pub fn evaluate(&self, scene: &Scene) -> Result<Metrics, String> {
        match self.kind {
            Kind::Shafts => {
                let (r, pred, wall) = render_scene(scene)?;
                let reference = self.reference_for(scene)?;
                let error = error_stats(&r.levels(), &reference).map_err(|e| e.to_string())?;
                Ok(Metrics {
                    gates: elaborated_gates(&r),
                    ram_bits: r
                        .elaboration
                        .iter()
                        .filter_map(|e| e.summary.as_ref())
                        .map(|s| s.ram_bits)
                        .sum(),
                    error,
                    predicted_seconds: pred.seconds,
                    wall_seconds: wall,
                })
            }
            Kind::Glare => {
                let bg = glare_background(scene, self.backdrop.as_ref());
                let (f, pred, wall) =
                    render_and_predict_over(scene, bg.as_deref()).map_err(|e| e.to_string())?;
                let reference = self.reference_for(scene)?;
                let error = error_stats(&f.levels(), &reference).map_err(|e| e.to_string())?;
                Ok(Metrics {
                    gates: f.units.iter().map(|u| u.gates_nand2).sum(),
                    ram_bits: f.units.iter().map(|u| u.ram_bits).sum(),
                    error,
                    predicted_seconds: pred.seconds,
                    wall_seconds: wall,
                })
            }
            Kind::Frame => {
                let r = crate::frame::sweep::frame_row(scene, None)?;
                Ok(Metrics::of_row(&r))
            }
            Kind::Envmap => {
                // `sweep`'s row: the render against the Phong truth (cos φ test), the
                // truth drawn the first time this scene is rendered.
                let key = toml::to_string(scene)
                    .map_err(|e| format!("scene: cannot write it as TOML: {e}"))?;
                let known = self.truths.borrow().get(&key).cloned();
                let f = match &known {
                    Some(t) => render_scene_against(scene, t),
                    None => render_env(scene, true),
                }
                .map_err(|e| e.to_string())?;
                if known.is_none() {
                    if let Some(t) = &f.truth {
                        self.truths
                            .borrow_mut()
                            .insert(key, Rc::new(t.truth.clone()));
                    }
                }
                let r = envmap_row_of(&f, "side")?;
                Ok(Metrics::of_row(&r))
            }
        }
    }

    /// How many environment-map truths this evaluator has drawn (one per distinct
    /// scene rendered; 0 for other kinds).
    pub fn truths_drawn(&self) -> usize {
        self.truths.borrow().len()
    }

    /// The sound lower bound of [`output_bound`] for `scene`'s output width; for a
    /// kind without one (environment maps) the trivial bound 0, which prunes nothing.
    pub fn bound(&self, scene: &Scene) -> Result<ErrorStats, String> {
        match self.kind.fb_bits(scene) {
            Some(fb) => Ok(output_bound(&self.reference_for(scene)?, fb)),
            None => Ok(ErrorStats::EMPTY),
        }
    }
}

/// A glare scene's background at its framebuffer width, as `sweep` draws it.
fn glare_background(scene: &Scene, backdrop: Option<&Framebuffer>) -> Option<Vec<[u32; 3]>> {
    backdrop.map(|fb| from_framebuffer(fb, scene.glare.as_ref().map_or(8, |g| g.hw.fb_bits)))
}

/// A guaranteed lower bound on the error of ANY image whose values are codes of an
/// `fb_bits`-bit framebuffer shown in 8-bit levels (code · 255 / (2^fb_bits − 1),
/// `Framebuffer::levels`): each value can at best be the level nearest its reference
/// value, so |image − reference| ≥ that distance value by value, and the mean, RMS and
/// max of the distances bound the image's mean, RMS and max from below. It follows
/// from the reference and the width alone, before anything is simulated.
pub fn output_bound(reference: &[[f64; 3]], fb_bits: u32) -> ErrorStats {
    let max_code = rtl_model::unorm::max_code(fb_bits) as f64;
    let step = 255.0 / max_code;
    let (mut sum, mut sq, mut max) = (0.0f64, 0.0f64, 0.0f64);
    for x in reference.iter().flatten() {
        let code = (x / step).round().clamp(0.0, max_code);
        let d = (x - code * step).abs();
        sum += d;
        sq += d * d;
        max = max.max(d);
    }
    let n = reference.len() as u64 * 3;
    if n == 0 {
        return ErrorStats::EMPTY;
    }
    ErrorStats {
        mean_abs: sum / n as f64,
        rms: (sq / n as f64).sqrt(),
        max,
        n,
    }
}

/// What the search (`search.rs`) needs of what it searches, whatever its kind: a
/// `Scene` through an [`Evaluator`], or a shading scene (`super::shading`). A
/// configuration is the values of the searched parameters.
pub trait Target {
    /// The kind's name, for messages.
    fn kind_name(&self) -> &'static str;
    /// How `param` narrows.
    fn step(&self, param: &str) -> Step;
    /// The default (GeForce) value of `param`, where the search starts.
    fn default_value(&self, param: &str) -> Result<u32, String>;
    /// Whether `values` is a configuration the units accept.
    fn valid(&self, params: &[&str], values: &[u32]) -> bool;
    /// The sound lower bound of the configuration's error, before any simulation;
    /// None for a configuration the units refuse.
    fn bound_at(&self, params: &[&str], values: &[u32]) -> Result<Option<ErrorStats>, String>;
    /// Simulate the configuration and measure it.
    fn evaluate_at(&self, params: &[&str], values: &[u32]) -> Result<Metrics, String>;
}

impl Target for Evaluator {
    fn kind_name(&self) -> &'static str {
        self.kind.name()
    }
    fn step(&self, param: &str) -> Step {
        self.kind.step(param)
    }
    fn default_value(&self, param: &str) -> Result<u32, String> {
        self.kind.get(&self.base, param)
    }
    fn valid(&self, params: &[&str], values: &[u32]) -> bool {
        self.kind.apply(&self.base, params, values).is_ok()
    }
    fn bound_at(&self, params: &[&str], values: &[u32]) -> Result<Option<ErrorStats>, String> {
        match self.kind.apply(&self.base, params, values) {
            Ok(scene) => self.bound(&scene).map(Some),
            Err(_) => Ok(None),
        }
    }
    fn evaluate_at(&self, params: &[&str], values: &[u32]) -> Result<Metrics, String> {
        self.evaluate(&self.kind.apply(&self.base, params, values)?)
    }
}
