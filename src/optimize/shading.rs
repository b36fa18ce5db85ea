//! `optimize` on the shading scenes (`shading-*`, or a shading scene file:
//! `pipeline::shading::scene_file`): the search of `search.rs` over `sweep`'s
//! shading widths, each configuration rendered through the path `sweep` uses for
//! shading (`shading::sweep::measure_point`) against the sweep's reference, drawn
//! once per run.
//!
//! **Bound.** A shading point's error is taken over output codes of a known width
//! ([`ShadingPoint::output_bits`]): each output value is a code k shown as
//! k · 255 / (2^b − 1) levels, so [`super::eval::output_bound`] of the reference at
//! that width is a sound lower bound of its mean, RMS and max error. Only
//! `shading-specular`'s lookup path has a searched width there (`lookup_bits`: the
//! lookup's entries are its output); the catalogue paths end in an 8-bit combiner
//! and the squaring chain in unorm8, whatever the widths, so their bound is one
//! constant (it prunes only a budget nothing can meet); `shading-vertex`'s
//! reference is already whole codes, so its bound is 0. The units' datasheet error
//! bounds are upper bounds and prune nothing.

use super::cli::{OptimizeArgs, SearchRun};
use super::eval::{output_bound, Metrics, Reference, Step, Target};
use super::search::{describe, Budget, Limit, Objective};
use crate::pipeline::shading::scene_file::ShadingFile;
use crate::pipeline::shading::sphere::SphereView;
use crate::pipeline::shading::sweep::{
    check_param, measure_point, params_of, shading_reference, sweep_view, ShadingPoint,
    ShadingReference, ShadingScene, SQUARING_DEFAULT_BITS,
};
use crate::report::atomic::write_bytes;
use crate::report::metrics::ErrorStats;
use std::path::PathBuf;
use std::time::Instant;

/// A shading scene, its reference (drawn once) and its view.
pub struct ShadingEvaluator {
    /// Where the search starts: the scene at the file's (or the GeForce) widths.
    pub base: ShadingPoint,
    pub view: SphereView,
    pub reference: ShadingReference,
    /// The reference values the error is taken over (for the bound).
    reference_values: Vec<[f64; 3]>,
    pub reference_seconds: f64,
}

impl ShadingEvaluator {
    /// Draw `base`'s reference on `view`.
    pub fn new(base: ShadingPoint, view: SphereView) -> Result<ShadingEvaluator, String> {
        let t0 = Instant::now();
        let reference = shading_reference(&base, &view)?;
        Ok(ShadingEvaluator {
            base,
            view,
            reference_values: reference.values(),
            reference,
            reference_seconds: t0.elapsed().as_secs_f64(),
        })
    }

    /// The base point with `values[i]` set into `params[i]` (the sweep's setters,
    /// every unit built).
    pub fn point(&self, params: &[&str], values: &[u32]) -> Result<ShadingPoint, String> {
        let mut widths = self.base.widths();
        for (p, &v) in params.iter().zip(values) {
            match widths.iter_mut().find(|(k, _)| k == p) {
                Some(w) => w.1 = v,
                None => {
                    return Err(format!(
                        "params: '{p}' is not a width of this {} configuration",
                        self.base.scene().name()
                    ))
                }
            }
        }
        ShadingPoint::new(self.base.scene(), &widths).map(|p| p.on_chip(self.base.chip()))
    }

    /// Render `point` and measure it against the run's reference.
    pub fn measure(&self, point: &ShadingPoint) -> Result<Metrics, String> {
        let m = measure_point(point, &self.view, &self.reference)?;
        Ok(Metrics {
            gates: m.gates_nand2,
            ram_bits: m.ram_bits,
            error: ErrorStats {
                mean_abs: m.mean_abs_levels,
                rms: m.rms_levels,
                max: m.max_levels,
                n: self.reference_values.len() as u64 * 3,
            },
            predicted_seconds: m.predicted_hw_seconds,
            wall_seconds: m.wall_seconds,
        })
    }
}

impl Target for ShadingEvaluator {
    fn kind_name(&self) -> &'static str {
        "shading"
    }
    /// Table sides halve (the cube's faces, the factor textures); bit widths and
    /// the lookup's log2 size lose one bit.
    fn step(&self, param: &str) -> Step {
        match param {
            "cube_face" | "factor_size" => Step::Halve,
            _ => Step::Bit,
        }
    }
    fn default_value(&self, param: &str) -> Result<u32, String> {
        self.base.value(param)
    }
    fn valid(&self, params: &[&str], values: &[u32]) -> bool {
        self.point(params, values).is_ok()
    }
    fn bound_at(&self, params: &[&str], values: &[u32]) -> Result<Option<ErrorStats>, String> {
        Ok(self
            .point(params, values)
            .ok()
            .map(|p| output_bound(&self.reference_values, p.output_bits())))
    }
    fn evaluate_at(&self, params: &[&str], values: &[u32]) -> Result<Metrics, String> {
        self.measure(&self.point(params, values)?)
    }
}

/// `--params` for a shading scene: each a width of the scene (`-` read as `_`),
/// none twice, `combiner_bits` (shading-specular's squaring path) alone; errors name
/// `params`.
pub fn parse_params(sc: &ShadingScene, list: &str) -> Result<Vec<&'static str>, String> {
    let mut out: Vec<&'static str> = Vec::new();
    for item in list.split(',') {
        let p = check_param(sc, item).map_err(|_| {
            format!(
                "params: unknown parameter '{}' for this shading scene {} (known: {})",
                item.trim(),
                sc.name(),
                params_of(sc).join(", ")
            )
        })?;
        if out.contains(&p) {
            return Err(format!("params: '{p}' is given twice"));
        }
        out.push(p);
    }
    if out.len() > 1 && out.contains(&"combiner_bits") {
        return Err(format!(
            "params: combiner_bits is {}'s squaring path, the other widths its lookup \
             path; search one path at a time",
            sc.name()
        ));
    }
    Ok(out)
}

/// The options of a shading run, checked.
pub struct ShadingPlan {
    pub file: ShadingFile,
    pub budget: Budget,
    pub objective: Objective,
    pub params: Vec<&'static str>,
    pub out: PathBuf,
    pub max_evals: Option<usize>,
    pub seconds: Option<f64>,
    pub seed: u64,
}

/// Every argument checked for the shading scene `file`, each error naming its
/// argument; nothing rendered, nothing written.
pub fn check(a: &OptimizeArgs, mut file: ShadingFile) -> Result<ShadingPlan, String> {
    let sc = *file.point.scene();
    if let Some(size) = &a.image {
        let (w, h) = crate::report::image_arg::parse_image(size)?;
        if sc == ShadingScene::Vertex {
            return Err("--image: shading-vertex lights sphere vertices, it has no image".into());
        }
        if w != h {
            return Err(format!(
                "--image: the sphere view is square, not {w}x{h} (e.g. {w}x{w})"
            ));
        }
        rtl_model::error::check_range("--image", w.into(), 2, 4096).map_err(|e| e.to_string())?;
        file.image = Some(w);
    }
    if a.budget.is_empty() {
        return Err("budget: at least one --budget is needed, e.g. --budget \"max<=1\"".into());
    }
    let budget = Budget(
        a.budget
            .iter()
            .map(|b| Limit::parse(b))
            .collect::<Result<_, _>>()?,
    );
    let objective = Objective::parse(&a.objective)?;
    let params = match &a.params {
        Some(list) => parse_params(&sc, list)?,
        None => file.point.widths().into_iter().map(|(p, _)| p).collect(),
    };
    // The squaring path asked for on a point of the lookup path (the file's or the
    // defaults): start it from the GeForce combiners' width.
    if params.contains(&"combiner_bits") && file.point.value("combiner_bits").is_err() {
        file.point = ShadingPoint::new(&sc, &[("combiner_bits", SQUARING_DEFAULT_BITS)])?
            .on_chip(file.point.chip());
    }
    if let Some(p) = params.iter().find(|p| file.point.value(p).is_err()) {
        return Err(format!(
            "params: '{p}' is shading-specular's lookup path; the scene file is on its \
             squaring path (combiner_bits)"
        ));
    }
    if a.max_evals == Some(0) {
        return Err("max-evals: must be at least 1".into());
    }
    if let Some(t) = a.seconds {
        if !(t.is_finite() && t > 0.0) {
            return Err(format!("seconds: {t} is not a positive number of seconds"));
        }
    }
    if Reference::parse(&a.reference)? != Reference::Wide {
        return Err(format!(
            "reference: '{}' is for shafts scenes; a shading scene is measured against \
             its sweep's f64 reference",
            a.reference
        ));
    }
    crate::report::outputs::check_dir_out("out", &a.out)?;
    Ok(ShadingPlan {
        file,
        budget,
        objective,
        params,
        out: a.out.clone(),
        max_evals: a.max_evals,
        seconds: a.seconds,
        seed: a.seed,
    })
}

/// `optimize` on a shading scene: as `command::optimize_cli` does for a `Scene` (progress
/// bar, `pareto.csv` after every point, `pareto.png`), then `best.toml` in the
/// shading file form, read back and rendered afresh.
pub fn optimize_shading_cli(a: &OptimizeArgs, file: ShadingFile) -> Result<(), String> {
    let plan = check(a, file)?;
    let name = plan.file.point.scene().name();
    let size_text = plan
        .file
        .image
        .map_or("vertices".to_string(), |s| format!("{s}x{s}"));
    std::fs::create_dir_all(&plan.out).map_err(|e| format!("out: {}: {e}", plan.out.display()))?;
    let t0 = Instant::now();
    let view = sweep_view(
        plan.file
            .image
            .unwrap_or(crate::pipeline::shading::scene_file::DEFAULT_IMAGE),
    );
    let ev = ShadingEvaluator::new(plan.file.point, view)?;
    eprintln!(
        "optimize {} ({size_text}, shading scene {name}): reference in {:.1} s; budget {}; \
         objective {}; params {}",
        a.scene,
        ev.reference_seconds,
        plan.budget.describe(),
        plan.objective.name(),
        plan.params.join(",")
    );
    let title = format!(
        "optimize {name} ({size_text}): {} within {}",
        plan.objective.name(),
        plan.budget.describe()
    );
    let run = SearchRun {
        label: &a.scene,
        title: &title,
        params: &plan.params,
        budget: &plan.budget,
        objective: plan.objective,
        max_evals: plan.max_evals,
        seconds: plan.seconds,
        seed: plan.seed,
        out: &plan.out,
        started: t0,
    };
    let o = run.run(&ev)?;
    let Some(bi) = o.best else {
        return Err(run.no_best(&o));
    };
    let best = ShadingFile {
        point: ev.point(&o.params, &o.points[bi].values)?,
        image: plan.file.image,
    };
    let header = format!(
        "# optimize --scene {} --objective {} --budget \"{}\" ({size_text}): {}",
        a.scene,
        plan.objective.name(),
        plan.budget.describe(),
        describe(&o.params, &o.points[bi].values)
    );
    let toml_path = plan.out.join("best.toml");
    write_bytes(&toml_path, best.to_toml(&header)?.as_bytes())?;
    // Verification: the written file read back and rendered afresh.
    let again = crate::scene::load::load_scene(&toml_path.display().to_string())
        .and_then(|s| ShadingFile::from_scene(&s))
        .map_err(|e| format!("best.toml: {e}"))?;
    let m = ev.measure(&again.point)?;
    run.verified(&o, bi, &toml_path, &m)
}
