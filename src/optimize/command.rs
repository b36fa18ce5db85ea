//! The `optimize` command: it chooses the driver (a shading scene's widths, the
//! clocked chip's parameters, or a scene's widths) and runs it. The drivers share
//! `cli.rs` (arguments, the search run, its outputs) and import nothing of this file.

use super::chip;
use super::cli::{best_toml, check_on, OptimizeArgs, SearchRun};
use super::eval::Evaluator;
use super::search::describe;
use super::shading;
use crate::pipeline::shading::scene_file::ShadingFile;
use crate::report::atomic::write_bytes;
use crate::scene::format::{Scene, SceneKind};

/// The path `optimize` takes, by what the scene holds and which parameters are named.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OptimizePath {
    /// The foundation test scene: nothing to search (refused).
    Refused,
    /// A shading sphere's widths (`shading.rs`).
    ShadingWidths,
    /// The clocked chip's parameters within a time budget (`chip.rs`).
    Chip,
    /// A scene's unit widths (`search.rs` over `eval.rs`).
    SceneWidths,
}

/// [`OptimizePath`] of a loaded scene and `--params`.
pub fn optimize_path(scene: &Scene, params: Option<&str>) -> OptimizePath {
    match scene.kind() {
        SceneKind::Test => OptimizePath::Refused,
        SceneKind::ShadingSphere(_) => OptimizePath::ShadingWidths,
        SceneKind::Frame if params.is_some_and(chip::names_chip_params) => OptimizePath::Chip,
        SceneKind::Frame => OptimizePath::SceneWidths,
    }
}

/// The command: a shading scene, the clocked chip's parameters, or a scene's widths.
pub fn optimize_cli(a: &OptimizeArgs) -> Result<(), String> {
    let scene = crate::scene::load::load_scene(&a.scene)?;
    let path = optimize_path(&scene, a.params.as_deref());
    if let (Some(t), false) = (a.timing, path == OptimizePath::Chip) {
        return Err(format!(
            "--timing {}: only a search of the chip's architecture (--params pipes, tmus, \
             fifo_depth, cache_kb, …, on a scene the chip clocks) times the chip",
            t.name()
        ));
    }
    let plan = match path {
        OptimizePath::Refused => {
            return Err(format!(
                "scene: '{}' is not a scene optimize can search (it covers shafts scenes: \
                 fig4, fig6, stage; glare scenes: glare-point, glare-elliptic, …; \
                 environment-map scenes: env-pattern-sphere, …; shading scenes: \
                 shading-<model>, shading-specular, shading-vertex; TOML files of these)",
                a.scene
            ))
        }
        // A shading scene (`shading-*` or a `[shading_sphere]` or `[shading]` file).
        OptimizePath::ShadingWidths => {
            return shading::optimize_shading_cli(a, ShadingFile::from_scene(&scene)?)
        }
        // Parameters of the clocked chip: an architecture search within a time budget.
        OptimizePath::Chip => return chip::optimize_chip_on(a, scene),
        OptimizePath::SceneWidths => check_on(a, scene)?,
    };
    std::fs::create_dir_all(&plan.out).map_err(|e| format!("out: {}: {e}", plan.out.display()))?;
    let t0 = std::time::Instant::now();
    let ev = Evaluator::new(&plan.scene, plan.reference)?;
    eprintln!(
        "optimize {} ({}x{}, {} scene): reference in {:.1} s; budget {}; objective {}; params {}",
        plan.scene_arg,
        plan.scene.image.width,
        plan.scene.image.height,
        ev.kind.name(),
        ev.reference_seconds,
        plan.budget.describe(),
        plan.objective.name(),
        plan.params.join(",")
    );
    let title = format!(
        "optimize {} ({}x{}): {} within {}",
        plan.scene.short_name(),
        plan.scene.image.width,
        plan.scene.image.height,
        plan.objective.name(),
        plan.budget.describe()
    );
    let run = SearchRun {
        label: &plan.scene_arg,
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
    let Some(best) = o.best_scene(&ev) else {
        return Err(run.no_best(&o));
    };
    let best = best?;
    let bi = o.best.unwrap_or(0);
    let header = format!(
        "# optimize --scene {} --objective {} --budget \"{}\" ({}x{}): {}",
        plan.scene_arg,
        plan.objective.name(),
        plan.budget.describe(),
        plan.scene.image.width,
        plan.scene.image.height,
        describe(&o.params, &o.points[bi].values)
    );
    let toml_path = plan.out.join("best.toml");
    write_bytes(&toml_path, best_toml(&best, &header)?.as_bytes())?;
    // Verification: the written file read back and rendered afresh.
    let again = Scene::from_file(&toml_path).map_err(|e| format!("best.toml: {e}"))?;
    let m = ev.evaluate(&again)?;
    run.verified(&o, bi, &toml_path, &m)
}
