//! `render` and `units --scene` through the frame: load, plan, elaborate the chip,
//! run the passes, write the PNG, print the plan, the chip, each pipeline's counters
//! and elaboration, and the predicted time per pass.

use super::chip::{chip_table, elaborate};
use super::plan::{plan, plan_table, test_scene_plan};
use super::run::render_timed;
use super::timing::{ChipName, TimingMode, TimingRequest};
use crate::pipeline::shading::scene_file::ShadingFile;
use crate::pipeline::shafts::cli::reference_image;
use crate::report::render_json::{value, Family, PassEntry, RenderJson, Timing};
use crate::report::table::{chip_elaboration_table, counters_table, text_table};
use crate::scene::format::{Scene, SceneKind};
use crate::scene::load::load_scene;
use std::path::Path;

/// `render`'s timing flags.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct TimingArgs {
    /// How the frame's time is found: roofline (max(fill, memory) plus set-up per
    /// pass with an assumed texture-cache hit rate), clocked (each pass's work, as
    /// the frame records it, clocked through the chip's stages, FIFOs, texture caches
    /// and memory controller) or sampled (of each kind of pass the first two and one
    /// in 8 clocked, each on one full-width band of 8 rows in 8, and the rest scaled,
    /// with its estimated error). Clocked and sampled time the shafts scenes
    /// (fig4, fig6, stage and scene files without glare) on the GPU and the glare
    /// scenes (glare-point, glare-flare, leaves, …) on the glare ASIC; the roofline
    /// (for the glare pass, its throughput formula) stays printed beside them.
    #[arg(long, value_enum, value_name = "MODE", default_value_t = TimingMode::Roofline)]
    pub timing: TimingMode,
    /// The chip the frame is timed on: geforce256, geforce2-gts or geforce3 for the
    /// GPU passes (default: GeForce3 for a scene with an environment map, else the
    /// GeForce2 GTS), or glare-asic (a glare scene's glare pass, which always runs
    /// on it).
    #[arg(long, value_enum, value_name = "CHIP")]
    pub chip: Option<ChipName>,
    /// With clocked timing, the clocks of the frame (counted from its start) that
    /// the chip's signals are traced over, START..END, into OUT's .vcd beside the
    /// timeline (OUT.timeline.png and .csv); default 0..2000, at most 1 000 000
    /// clocks. GTKWave and Surfer open the VCD (docs/throughput.md).
    #[arg(long, value_name = "START..END")]
    pub vcd_window: Option<String>,
}

impl TimingArgs {
    pub fn request(&self) -> TimingRequest {
        TimingRequest {
            mode: self.timing,
            chip: self.chip,
            window: None,
        }
    }

    /// Refuse the flags for a scene family that renders outside the frame's passes
    /// (`family`: "the foundation test scene", …): clocked or sampled timing, or a chip.
    fn refuse_outside_frame(&self, family: &str) -> Result<(), String> {
        if self.timing.records() {
            return Err(super::timing::unsupported_family(self.timing, family));
        }
        match self.chip {
            Some(c) => Err(format!(
                "--chip {}: {family} is timed on its own fixed model; --chip applies to the \
                 shafts, glare and showcase scenes",
                c.name()
            )),
            None => Ok(()),
        }
    }
}

/// A plan's pass as `render --json` lists it, with its time if it has one.
pub fn pass_entry(p: &super::plan::Pass, t: Option<&super::run::PassTime>) -> PassEntry {
    PassEntry {
        name: p.name.clone(),
        pipeline: p.pipeline.to_string(),
        reads: p.reads.clone(),
        writes: p.writes.clone(),
        units: p.units.iter().map(|u| u.to_string()).collect(),
        on: t.map(|t| t.on.clone()),
        predicted_seconds: t.map(|t| t.seconds),
        wall_seconds: t.map(|t| t.wall_seconds),
    }
}

/// `render --scene NAME [--plan]`. Before any work: the output paths are checked
/// (writable, distinct; errors name `out` or `reference`: `report::outputs`), the
/// scene is loaded, `image` (`--image WIDTHxHEIGHT`) replaces its image size, it is
/// validated, and its memory estimate is checked against `max_memory` (bytes; `None`
/// = the default budget, half of `MemAvailable`: `frame::budget`), a shading scene's
/// too (`budget::shading_estimate`: its sphere view). `json`: one object of the shape
/// `report::render_json` prints for every family (docs/json.md). `vcd_window`
/// (`--vcd-window START..END`): the clocks the clocked chip's VCD traces
/// (`report::chip_timing`); with clocked timing the timeline PNG and CSV and the VCD
/// are written beside `out` and checked with it.
#[allow(clippy::too_many_arguments)]
pub fn render_cli(
    name: &str,
    out: &Path,
    json: bool,
    reference: Option<&Path>,
    plan_only: bool,
    max_memory: Option<u64>,
    image: Option<&str>,
    timing: &TimingArgs,
) -> Result<(), String> {
    use crate::report::outputs::{check_outputs, Output};
    let size = image
        .map(crate::report::image_arg::parse_image)
        .transpose()?;
    let chip_files = crate::report::chip_timing::ChipFiles::for_render(
        out,
        timing.vcd_window.as_deref(),
        timing.timing.records(),
    )?;
    if !plan_only {
        let mut outs = vec![Output::png("out", out)];
        if let Some(r) = reference {
            outs.push(Output::png("reference", r));
        }
        if let Some(f) = &chip_files {
            outs.push(Output::png("out (timeline PNG)", &f.timeline_png));
            outs.push(Output::file("out (timeline CSV)", &f.timeline_csv));
            outs.push(Output::file("out (VCD)", &f.vcd));
        }
        check_outputs(&outs)?;
    }
    let out = RenderOut {
        out,
        json,
        reference,
        plan_only,
        chip_files,
    };
    // One resolver for every kind of scene; what the scene holds picks the path.
    let mut scene = load_scene(name)?;
    match render_path(&scene) {
        RenderPath::TestScene => {
            timing.refuse_outside_frame("the foundation test scene")?;
            return render_test_scene(size, &out);
        }
        RenderPath::ShadingSphere => {
            // The shading sweep's path, at the section's widths.
            let f = ShadingFile::from_scene(&scene)?;
            timing.refuse_outside_frame("a shading scene")?;
            return render_shading_scene(name, f, image, max_memory, &out);
        }
        RenderPath::Environment | RenderPath::Frame => {}
    }
    if let Some((w, h)) = size {
        scene.image.width = w;
        scene.image.height = h;
        scene
            .validate()
            .map_err(|e| format!("--image {w}x{h}: {e}"))?;
    }
    if super::plan::environment_scene(&scene) {
        timing.refuse_outside_frame("an environment-map scene")?;
    }
    // Clocked timing's chip resolved, and what the frame cannot clock refused, before
    // any work (the default roofline needs neither).
    let mut req = timing.request();
    req.window = out
        .chip_files
        .as_ref()
        .map(|f| (f.vcd_window.start, f.vcd_window.end));
    let chip_config = if req == TimingRequest::default() {
        None
    } else {
        let p = plan(&scene).map_err(|e| e.to_string())?;
        super::timing::check(&req, &p)?;
        match req.mode.records() {
            true => Some(super::timing::frame_chip(&req, &scene, &p)?),
            false => None,
        }
    };
    if !plan_only {
        let (budget, from) = super::budget::resolve(max_memory);
        super::budget::check(&scene, budget, &from)?;
        work_note(&scene);
    }
    let chip = elaborate(&scene);
    if super::plan::environment_scene(&scene) && !plan_only {
        // The thesis' environment scenes keep their own report (map build, truth).
        return render_environment_scene(&scene, &chip, &out);
    }
    if plan_only {
        return print_plan(&scene, &chip, json);
    }
    render_frame(&scene, &out, &req, chip_config)
}

/// The path `render` takes, by what the scene holds (never by its name).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RenderPath {
    /// The foundation test scene's renderer (`pipeline::test_scene`).
    TestScene,
    /// The shading units' sphere through the shading sweep's path.
    ShadingSphere,
    /// An environment-map scene of the thesis: its own report (map build, truth).
    Environment,
    /// The frame's passes.
    Frame,
}

/// [`RenderPath`] of a loaded scene.
pub fn render_path(scene: &Scene) -> RenderPath {
    match scene.kind() {
        SceneKind::Test => RenderPath::TestScene,
        SceneKind::ShadingSphere(_) => RenderPath::ShadingSphere,
        SceneKind::Frame if super::plan::environment_scene(scene) => RenderPath::Environment,
        SceneKind::Frame => RenderPath::Frame,
    }
}

/// Where and how `render` reports: the PNG, JSON or text, the reference PNG, and
/// whether only the plan is asked for.
struct RenderOut<'a> {
    out: &'a Path,
    json: bool,
    reference: Option<&'a Path>,
    plan_only: bool,
    /// The clocked chip's files and the VCD's window (None: the frame is not
    /// clocked). The frame's clock takes the window per pass through
    /// `report::chip_timing::pass_window`.
    chip_files: Option<crate::report::chip_timing::ChipFiles>,
}

/// `render` of the foundation test scene (fixed size: `--image` is refused).
fn render_test_scene(size: Option<(u32, u32)>, o: &RenderOut) -> Result<(), String> {
    let (out, json, reference, plan_only) = (o.out, o.json, o.reference, o.plan_only);
    if let Some((w, h)) = size {
        return Err(format!(
            "--image: the foundation test scene has a fixed size ({}x{}); --image {w}x{h} cannot change it",
            crate::scene::test_scene::WIDTH,
            crate::scene::test_scene::HEIGHT
        ));
    }
    if !json {
        print!("pass plan:\n{}", plan_table(&test_scene_plan()));
    }
    let passes: Vec<PassEntry> = test_scene_plan()
        .passes
        .iter()
        .map(|p| pass_entry(p, None))
        .collect();
    if plan_only {
        if json {
            let mut r = RenderJson::new("test", Family::Test).image(
                crate::scene::test_scene::WIDTH,
                crate::scene::test_scene::HEIGHT,
            );
            r.passes = passes;
            r.print()?;
        }
        return Ok(());
    }
    crate::pipeline::test_scene::render_cli(out, json, reference, passes)
}

/// `render` of a shading scene at `image` (a square side) or its own size.
fn render_shading_scene(
    name: &str,
    mut f: ShadingFile,
    image: Option<&str>,
    max_memory: Option<u64>,
    o: &RenderOut,
) -> Result<(), String> {
    let (out, json, reference, plan_only) = (o.out, o.json, o.reference, o.plan_only);
    if let Some(img) = image {
        if f.image.is_none() {
            return Err(format!(
                "--image: {name} lights sphere vertices; it has no image to size"
            ));
        }
        let side = crate::report::image_arg::square_side(img)?;
        rtl_model::error::check_range("--image", side.into(), 2, 4096)
            .map_err(|e| e.to_string())?;
        f.image = Some(side);
    }
    if !plan_only {
        let (budget, from) = super::budget::resolve(max_memory);
        let e = super::budget::shading_estimate(f.image);
        super::budget::check_estimate(e, budget, &from)?;
    }
    crate::pipeline::shading::scene_file::render_cli(&f, out, json, reference, plan_only)
}

/// `render` of an environment-map scene of the thesis: its own report (map build,
/// truth), in the one JSON shape.
fn render_environment_scene(
    scene: &crate::scene::format::Scene,
    chip: &super::chip::Chip,
    o: &RenderOut,
) -> Result<(), String> {
    let (out, json, reference) = (o.out, o.json, o.reference);
    // The thesis' environment scenes keep their own report (map build, truth).
    let p = plan(scene).map_err(|e| e.to_string())?;
    if !json {
        print!(
            "pass plan:\n{}\nchip (from the scene, before any pass runs; gates at the registry's default widths):\n{}\n",
            plan_table(&p),
            chip_table(chip)
        );
    }
    let warnings = super::range::check_environment(scene);
    super::range::print(&warnings);
    let w = serde_json::to_value(&warnings).map_err(|e| e.to_string())?;
    use crate::pipeline::envmap::scene_render as sr;
    let f = sr::render_and_write(scene, out, reference)?;
    if !json {
        return sr::print_text(scene, &f, out, reference);
    }
    let passes = p.passes.iter().map(|ps| pass_entry(ps, None)).collect();
    let mut r = RenderJson::new(&scene.name, Family::Environment)
        .image(f.frame.width, f.frame.height)
        .outputs(Some(out), f.truth.as_ref().and(reference))
        .family_details(serde_json::json!({
            "map": f.map,
            "frame": f.frame,
            "prediction": f.prediction,
        }));
    r.passes = passes;
    r.chip = super::chip::elaborated_json(&f.frame.elaboration.units, scene.chip);
    r.counters.insert("envmap".into(), value(&f.counters)?);
    r.timing = Timing {
        predicted_seconds: Some(f.prediction.seconds),
        gpu: Some("GeForce3".into()),
        cycles: None,
        clock_mhz: None,
        wall_seconds: Some(f.render_seconds),
    };
    r.error = match (&f.truth, reference) {
        (Some(t), Some(_)) => Some(serde_json::json!({
            "against": "Phong truth",
            "cos_phi": t.cos_phi,
            "simplified": t.simplified,
        })),
        _ => None,
    };
    r.warnings = w;
    r.print()
}

/// `render --plan`: the pass plan and the chip before any pass runs.
fn print_plan(
    scene: &crate::scene::format::Scene,
    chip: &super::chip::Chip,
    json: bool,
) -> Result<(), String> {
    let p = plan(scene).map_err(|e| e.to_string())?;
    if json {
        // The render's object with nothing rendered: no outputs, counters or
        // times, no family sub-object.
        let family = if super::plan::environment_scene(scene) {
            Family::Environment
        } else {
            Family::Frame
        };
        let mut r =
            RenderJson::new(&scene.name, family).image(scene.image.width, scene.image.height);
        r.passes = p.passes.iter().map(|ps| pass_entry(ps, None)).collect();
        r.chip = super::chip::defaults_json(chip);
        r.print()?;
    } else {
        print!(
            "pass plan:\n{}\nchip (from the scene, before any pass runs; gates at the registry's default widths, `render` reports them at the scene's):\n{}",
            plan_table(&p),
            chip_table(chip)
        );
    }
    Ok(())
}

/// `render` of a frame: run the passes, write the PNG (and the reference), report.
fn render_frame(
    scene: &crate::scene::format::Scene,
    o: &RenderOut,
    req: &TimingRequest,
    chip: Option<crate::chip::config::ChipConfig>,
) -> Result<(), String> {
    let (out, reference) = (o.out, o.reference);
    let setting = std::env::var("GLARE_PROGRESS").ok();
    let shown = crate::report::progress::frame_bar_wanted(work(scene), setting.as_deref());
    let (f, _) = render_timed(scene, req, chip, Some(shown)).map_err(|e| e.to_string())?;
    let warnings = super::range::check(scene, &f);
    f.fb.save_png(out)
        .map_err(|e| format!("out: {}: {e}", out.display()))?;
    // The clocked chip's timeline (PNG, CSV) and VCD beside the picture.
    let chip_notes = match (&f.timing, &o.chip_files) {
        (Some(ft), Some(files)) => files.write(ft)?,
        _ => Vec::new(),
    };
    let error = match reference {
        Some(path) => Some(super::reproduce::frame_error(scene, &f, Some(path))?),
        None => None,
    };
    let elaboration = f.elaboration();
    if o.json {
        return print_frame_json(scene, &f, &elaboration, error.as_ref(), &warnings, o);
    }
    print_frame_text(scene, &f, &elaboration, error.as_ref(), &warnings, out)?;
    for n in chip_notes {
        println!("{n}");
    }
    Ok(())
}

/// A rendered frame's `render --json` object.
fn print_frame_json(
    scene: &crate::scene::format::Scene,
    f: &super::run::Frame,
    elaboration: &[crate::report::elaboration::Elaborated],
    error: Option<&super::reproduce::FrameError>,
    warnings: &[super::range::RangeWarning],
    o: &RenderOut,
) -> Result<(), String> {
    let (out, reference) = (o.out, o.reference);
    let mut passes: Vec<PassEntry> = Vec::new();
    let mut times: Vec<Option<&super::run::PassTime>> = f.times.iter().map(Some).collect();
    for ps in &f.plan.passes {
        let t = times
            .iter_mut()
            .find(|t| t.is_some_and(|t| t.pass == ps.name))
            .and_then(Option::take);
        passes.push(pass_entry(ps, t));
    }
    // A timed pass the plan does not list (none today): kept, with what is known.
    for t in times.into_iter().flatten() {
        passes.push(PassEntry {
            name: t.pass.clone(),
            pipeline: String::new(),
            reads: Vec::new(),
            writes: Vec::new(),
            units: Vec::new(),
            on: Some(t.on.clone()),
            predicted_seconds: Some(t.seconds),
            wall_seconds: Some(t.wall_seconds),
        });
    }
    let mut r = RenderJson::new(&scene.name, Family::Frame)
        .image(scene.image.width, scene.image.height)
        .outputs(Some(out), reference)
        .family_details(match &f.timing {
            None => serde_json::json!({
                "glare_link": f.linked.as_ref().map(crate::frame::glare_link::summary),
            }),
            Some(ft) => serde_json::json!({
                "glare_link": f.linked.as_ref().map(crate::frame::glare_link::summary),
                "chip_timing": crate::report::chip_timing::json(ft),
            }),
        });
    r.passes = passes;
    r.chip = super::chip::elaborated_json(elaboration, scene.chip);
    for (pipeline, c) in f.counters() {
        r.counters.insert(pipeline, value(&c)?);
    }
    r.timing = Timing {
        predicted_seconds: Some(f.predicted_seconds()),
        gpu: Some(f.gpu.name().to_string()),
        // The clocked chip's cycles and clock, when it timed the frame.
        cycles: f.timing.as_ref().map(|t| t.cycles_total()),
        clock_mhz: f.timing.as_ref().map(|t| t.clock_hz / 1e6),
        wall_seconds: Some(f.wall_seconds),
    };
    r.error = error.map(value).transpose()?;
    r.warnings = value(&warnings)?;
    super::range::print(warnings);
    r.print()
}

/// A rendered frame's text report.
fn print_frame_text(
    scene: &crate::scene::format::Scene,
    f: &super::run::Frame,
    elaboration: &[crate::report::elaboration::Elaborated],
    error: Option<&super::reproduce::FrameError>,
    warnings: &[super::range::RangeWarning],
    out: &Path,
) -> Result<(), String> {
    println!(
        "{} ({}x{}): wrote {} in {:.2} s of simulation",
        scene.name,
        scene.image.width,
        scene.image.height,
        out.display(),
        f.wall_seconds
    );
    print!("\npass plan:\n{}", plan_table(&f.plan));
    for (pipeline, c) in f.counters() {
        print!("\n{pipeline} counters:\n{}", counters_table(&c));
    }
    print!(
        "\nchip (the units each pass elaborated, at the scene's widths):\n{}",
        chip_elaboration_table(elaboration)
    );
    let present: Vec<&str> = elaboration
        .iter()
        .filter_map(|u| u.summary.as_ref().map(|s| s.name))
        .collect();
    println!("{}", super::chip::preset_line(scene.chip, &present));
    if let Some(c) = f.shafts.as_ref().and_then(|s| s.clip_stats) {
        println!(
            "\nclipper: {} polygons in, {} out, {} clipped, {} culled, {} vertices generated",
            c.polygons_in,
            c.polygons_out,
            c.polygons_clipped,
            c.polygons_culled,
            c.vertices_generated
        );
    }
    if let Some(l) = &f.linked {
        print!("\n{}", crate::frame::glare_link::summary(l));
    }
    let rows: Vec<Vec<String>> = f
        .times
        .iter()
        .map(|t| {
            vec![
                t.pass.clone(),
                t.on.clone(),
                format!("{:.6}", t.seconds),
                format!("{:.2}", t.wall_seconds),
            ]
        })
        .collect();
    print!(
        "\npredicted time per pass:\n{}",
        text_table(&["pass", "on", "seconds", "simulation_wall_s"], &rows)
    );
    println!("predicted frame time: {:.6} s", f.predicted_seconds());
    if let Some(ft) = &f.timing {
        print!("\n{}", crate::report::chip_timing::print_table(ft));
        for p in &ft.roofline_only {
            println!("{} ({}): {:.6} s, {}", p.pass, p.kind, p.seconds, p.why);
        }
    }
    if let Some(e) = error {
        print!("\n{}", super::reproduce::error_table(e));
    }
    super::range::print(warnings);
    Ok(())
}

/// Fragments above which `render` says up front, on stderr, how much work it is.
pub const LARGE_WORK_FRAGMENTS: f64 = 2e9;

/// A line on stderr before an expensive render: the estimated sample-plane fragments
/// (pixels × planes × (1 + sub-planes) × lights) and memory.
fn work_note(scene: &crate::scene::format::Scene) {
    let fragments = work(scene);
    if fragments > LARGE_WORK_FRAGMENTS {
        eprintln!(
            "note: an expensive scene: about {fragments:.2e} sample-plane fragments and {} of buffers and tables; this may take minutes",
            super::budget::human(super::budget::estimate(scene).total())
        );
    }
}

/// A scene's estimated sample-plane fragments: pixels × planes × (1 + sub-planes) ×
/// lights (what [`work_note`] prints and what decides `render`'s progress bar).
fn work(scene: &crate::scene::format::Scene) -> f64 {
    let px = f64::from(scene.image.width) * f64::from(scene.image.height);
    let s = &scene.shafts;
    let lights = scene.lights.len().max(1) as f64;
    px * f64::from(s.planes) * (1.0 + f64::from(s.subplanes)) * lights
}

/// `units --scene NAME`: the chip the scene elaborates.
pub fn units_scene_cli(name: &str, json: bool) -> Result<(), String> {
    let scene = load_scene(name)?;
    if scene.kind() == SceneKind::Test {
        return Err(
            "scene: the foundation test scene has fixed units (`render --scene test --plan`)"
                .into(),
        );
    }
    // A shading scene's chip is its path's units at its widths.
    if render_path(&scene) == RenderPath::ShadingSphere {
        let f = ShadingFile::from_scene(&scene)?;
        let (gates, ram_bits) = crate::pipeline::shading::sweep::point_cost(&f.point)?;
        let widths: std::collections::BTreeMap<_, _> = f.point.widths().into_iter().collect();
        if json {
            let v = serde_json::json!({
                "scene": f.point.scene().name(),
                "widths": widths,
                "chip_preset": f.point.chip().name(),
                "gates_nand2": gates,
                "ram_bits": ram_bits,
            });
            println!(
                "{}",
                serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
            );
        } else {
            let w: Vec<String> = widths.iter().map(|(k, v)| format!("{k}={v}")).collect();
            println!(
                "shading scene {}: {}
chip: the shading path's units at these widths, {gates:.0} NAND2 gates, {ram_bits} RAM/ROM bits",
                f.point.scene().name(),
                w.join(" ")
            );
            println!(
                "{}",
                crate::pipeline::shading::scene_file::chip_line(&f.point)
            );
        }
        return Ok(());
    }
    let chip = elaborate(&scene);
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&super::chip::defaults_json(&chip))
                .map_err(|e| e.to_string())?
        );
    } else {
        print!("{}", chip_table(&chip));
    }
    Ok(())
}

/// The ray-marched reference of a shafts scene (re-exported for the reproductions).
pub fn shafts_reference(
    scene: &crate::scene::format::Scene,
    samples: u32,
) -> Result<Vec<[f64; 3]>, String> {
    Ok(reference_image(scene, samples)?.0)
}
