//! `sweep` over an architecture parameter of the clocked chip (`cache_kb`,
//! `fifo_depth`, `pipes`, … — [`crate::chip::params`]): the pixels do not depend on
//! it, so the frame is drawn once, its passes' recorded work clocked on the scene's
//! chip with each value, and a row per value written: the clocked frame time, the
//! roofline's beside it, the texture caches' hit rate and bits, and the pass that
//! bounds most of the frame's clocks. Every value's chip is checked before the frame
//! is drawn; a value the chip refuses is named with its field.

use super::gpu::Gpu;
use super::run::render_swept;
use super::timing::{check, ChipName, TimingMode, TimingRequest};
use crate::chip::clock::FrameTiming;
use crate::chip::config::ChipConfig;
use crate::chip::params::{texture_cache_bits, ChipParam};
use crate::report::csv_out::write_csv;
use crate::report::plot::{line_plot, Axis, PlotSpec, Series};
use crate::report::sweep_out::parse_int_values;
use crate::scene::format::Scene;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One row of `sweep_<param>.csv` for an architecture parameter.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ChipSweepRow {
    pub param: String,
    pub value: u32,
    pub chip: String,
    /// The frame's clocked time at the chip's clock, seconds.
    pub clocked_seconds: f64,
    pub cycles: u64,
    /// The roofline's frame time for the same passes (it does not see the parameter).
    pub roofline_seconds: f64,
    /// Texture-cache hits over lookups over the frame; empty when nothing was looked up.
    pub cache_hit_rate: Option<f64>,
    /// Storage bits of the texture caches (every cache's data).
    pub cache_bits: u64,
    /// The bottleneck of the passes that take most of the frame's clocks.
    pub bottleneck: String,
    /// Its share of the frame's clocks.
    pub bottleneck_share: f64,
    /// With sampled timing: the frame cycles' relative standard error; empty when
    /// every fragment was clocked.
    pub sampling_error: Option<f64>,
}

/// The checked sweep: the scene, the parameter, its values and each value's chip.
pub struct ChipSweep {
    /// The scene as the user named it (`fig6`, a file path), for titles.
    pub label: String,
    pub scene: Scene,
    pub param: ChipParam,
    pub values: Vec<u32>,
    pub base: ChipConfig,
    pub chips: Vec<ChipConfig>,
    /// Clocked (every fragment) or sampled, on every value's chip.
    pub mode: TimingMode,
}

/// Check everything before any work: the timing clocks the chip (clocked or sampled,
/// `None`: clocked), the scene can be clocked, every value gives a chip its validation
/// accepts (an error names `--values` and the chip's field).
pub fn check_chip_sweep(
    label: &str,
    scene: Scene,
    (param, timing): (ChipParam, Option<TimingMode>),
    values: &str,
) -> Result<ChipSweep, String> {
    let mode = timing.unwrap_or(TimingMode::Clocked);
    if !mode.records() {
        return Err(format!(
            "--timing {}: an architecture sweep clocks the chip on every value: \
             clocked or sampled",
            mode.name()
        ));
    }
    let values = parse_int_values(values)?;
    let plan = super::plan::plan(&scene).map_err(|e| e.to_string())?;
    let req = TimingRequest {
        mode,
        chip: None,
        window: None,
    };
    check(&req, &plan).map_err(|e| format!("--param {}: {e}", param.name()))?;
    if super::timing::glare_only(&plan) {
        return Err(format!(
            "--param {}: a glare scene's pass runs on the glare ASIC, whose variants \
             `reproduce glare-asic-throughput` clocks; an architecture sweep takes a scene \
             whose passes run on the GPU (fig4, fig6, stage, shafts scene files)",
            param.name()
        ));
    }
    let base = ChipConfig::preset(ChipName::of_gpu(Gpu::for_scene(&scene)).name())
        .map_err(|e| e.to_string())?;
    let chips = values
        .iter()
        .map(|&v| {
            let mut c = base.clone();
            param.apply(&mut c, v);
            c.validate()
                .map_err(|e| format!("--values: {} = {v}: {e}", param.name()))?;
            Ok(c)
        })
        .collect::<Result<Vec<_>, String>>()?;
    Ok(ChipSweep {
        label: label.to_string(),
        scene,
        param,
        values,
        base,
        chips,
        mode,
    })
}

/// Draw the frame once, clock it on every value's chip, and write `DIR/sweep_<param>.csv`
/// and `.png` (each atomically). Returns the rows and the two paths.
pub fn run_chip_sweep(
    s: &ChipSweep,
    out: &Path,
) -> Result<(Vec<ChipSweepRow>, PathBuf, PathBuf), String> {
    let req = TimingRequest {
        mode: s.mode,
        chip: None,
        window: None,
    };
    let (frame, _) = render_swept(&s.scene, &req, Some(s.base.clone()), s.chips.clone(), None)
        .map_err(|e| e.to_string())?;
    let rows: Vec<ChipSweepRow> = s
        .values
        .iter()
        .zip(&s.chips)
        .zip(&frame.swept_timings)
        .map(|((&v, chip), ft)| row(s.param, v, chip, ft))
        .collect();
    std::fs::create_dir_all(out).map_err(|e| format!("out: {}: {e}", out.display()))?;
    let csv = out.join(format!("sweep_{}.csv", s.param.name()));
    let png = out.join(format!("sweep_{}.png", s.param.name()));
    write_csv(&csv, &rows)?;
    plot(&png, &s.label, s.param, &rows)?;
    Ok((rows, csv, png))
}

/// A value's row from its chip's frame timing.
fn row(param: ChipParam, value: u32, chip: &ChipConfig, ft: &FrameTiming) -> ChipSweepRow {
    let (hits, lookups) = ft.passes.iter().fold((0, 0), |(h, n), p| {
        (
            h + p.timing.cache_hits,
            n + p.timing.cache_hits + p.timing.cache_misses,
        )
    });
    // Clocks per bottleneck over the passes; the largest names the frame's.
    let mut by: BTreeMap<&str, u64> = BTreeMap::new();
    for p in &ft.passes {
        *by.entry(p.timing.bottleneck.as_str()).or_default() += p.timing.cycles;
    }
    let cycles = ft.cycles_total();
    let (bottleneck, clocks) = by
        .into_iter()
        .max_by_key(|&(name, c)| (c, std::cmp::Reverse(name)))
        .unwrap_or(("none", 0));
    ChipSweepRow {
        param: param.name().to_string(),
        value,
        chip: chip.name.clone(),
        clocked_seconds: ft.clocked_seconds(),
        cycles,
        roofline_seconds: ft.passes.iter().map(|p| p.roofline_seconds).sum(),
        cache_hit_rate: (lookups > 0).then(|| hits as f64 / lookups as f64),
        cache_bits: texture_cache_bits(chip),
        bottleneck: bottleneck.to_string(),
        bottleneck_share: if cycles > 0 {
            clocks as f64 / cycles as f64
        } else {
            0.0
        },
        sampling_error: ft.sampling_error,
    }
}

/// The plot: clocked and roofline frame time against the value; the hit rate on the
/// right axis.
fn plot(png: &Path, scene: &str, param: ChipParam, rows: &[ChipSweepRow]) -> Result<(), String> {
    let mut spec = PlotSpec::new(
        &format!("{scene}: frame time against {}", param.name()),
        param.name(),
        "predicted frame time (s)",
    );
    spec.y_right_label = Some("texture-cache hit rate".into());
    let pts = |f: &dyn Fn(&ChipSweepRow) -> Option<f64>| {
        rows.iter()
            .filter_map(|r| f(r).map(|y| (r.value as f64, y)))
            .collect::<Vec<_>>()
    };
    let mut series = vec![
        Series {
            label: "clocked".into(),
            points: pts(&|r| Some(r.clocked_seconds)),
            axis: Axis::Left,
        },
        Series {
            label: "roofline".into(),
            points: pts(&|r| Some(r.roofline_seconds)),
            axis: Axis::Left,
        },
    ];
    let hits = pts(&|r| r.cache_hit_rate);
    if !hits.is_empty() {
        series.push(Series {
            label: "hit rate".into(),
            points: hits,
            axis: Axis::Right,
        });
    }
    line_plot(png, &spec, &series)
}

/// The rows as a table for the terminal.
pub fn table(rows: &[ChipSweepRow]) -> String {
    // Sampled rows carry their stated error (± one standard error, in %).
    let sampled = rows.iter().any(|r| r.sampling_error.is_some());
    let mut out = format!(
        "{:>10}  {:>12}  {}{:>12}  {:>9}  {:>10}  {}\n",
        rows.first().map_or("value", |r| r.param.as_str()),
        "clocked_s",
        if sampled { "  error_%  " } else { "" },
        "roofline_s",
        "hit_%",
        "cache_bits",
        "bottleneck (share of clocks)"
    );
    for r in rows {
        let hit = r
            .cache_hit_rate
            .map_or("n/a".to_string(), |h| format!("{:.2}", 100.0 * h));
        let error = match (sampled, r.sampling_error) {
            (false, _) => String::new(),
            (true, Some(e)) => format!("  {:>7.2}  ", 100.0 * e),
            (true, None) => format!("  {:>7}  ", "n/a"),
        };
        out += &format!(
            "{:>10}  {:>12.6}  {error}{:>12.6}  {:>9}  {:>10}  {} ({:.0} %)\n",
            r.value,
            r.clocked_seconds,
            r.roofline_seconds,
            hit,
            r.cache_bits,
            r.bottleneck,
            100.0 * r.bottleneck_share
        );
    }
    out
}

/// `sweep --param <architecture parameter>` on `scene` (loaded from `scene_name`):
/// every argument checked before the frame is drawn (the image size, the memory budget, every value's chip, the
/// output directory); `--shard`, `--resume` and `--attribute` are refused (the frame
/// is drawn once for all values, so there is nothing to split or resume).
// The command line's options, one argument each.
#[allow(clippy::too_many_arguments)]
pub fn chip_sweep_cli(
    scene_name: &str,
    mut scene: Scene,
    (param, timing): (ChipParam, Option<TimingMode>),
    values: &str,
    out: &Path,
    image: Option<&str>,
    max_memory: Option<u64>,
    split: (bool, bool, bool),
) -> Result<(), String> {
    let (shard, resume, attribute) = split;
    for (given, flag) in [
        (shard, "--shard"),
        (resume, "--resume"),
        (attribute, "--attribute"),
    ] {
        if given {
            return Err(format!(
                "{flag}: an architecture sweep (--param {}) draws the frame once and clocks \
                 it on every value; it has no {flag}",
                param.name()
            ));
        }
    }
    crate::scene::load::apply_image_checked(&mut scene, image)?;
    let sweep = check_chip_sweep(scene_name, scene, (param, timing), values)?;
    let (budget, from) = super::budget::resolve(max_memory);
    super::budget::check(&sweep.scene, budget, &from)?;
    crate::report::outputs::check_dir_out("out", out)?;
    let (rows, csv, png) = run_chip_sweep(&sweep, out)?;
    println!(
        "sweep {} on {scene_name} ({} {}, {} values): wrote {} and {}",
        param.name(),
        sweep.base.name,
        sweep.mode.name(),
        rows.len(),
        csv.display(),
        png.display()
    );
    print!("{}", table(&rows));
    Ok(())
}
