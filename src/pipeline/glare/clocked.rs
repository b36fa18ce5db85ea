//! The glare ASIC clocked: the glare pass records what it did (its primitives, their
//! walked pixels and covered fragments, the combiner's read-modify-write per fragment:
//! a [`PassWork`]) and the clocked chip (`crate::chip::clock::clock_pass`) runs it on
//! the glare ASIC's preset ([`glare_asic_for`]). The host's RAM-table
//! writes between primitives are on-chip writes at
//! [`GLARE_TABLE_WORDS_PER_CLOCK`] words a clock, added beside the clocked pass as a
//! pass of their own (they are no memory traffic, and the pipe cannot modulate a
//! primitive before its tables are loaded).
//!
//! `reproduce glare-asic-throughput` ([`asic_throughput`]) reports the sustained rate,
//! covered fragments ÷ clocked seconds, on `glare-flare`, `street-light` and `leaves`
//! against the paper's 1.2 Gpixel/s, with the bottleneck the clock names, and the
//! assumed parameters of the preset swept.

use super::asic_preset::{glare_asic_for, GLARE_TABLE_WORDS_PER_CLOCK};
use super::cli::setup_and_drain;
use super::frame::{render_glare_with, GlareFrame};
use super::host::glare_of;
use super::throughput::{predict, GlarePrediction};
use crate::chip::clock::{clock_pass, FrameTiming, NamedPassTiming, PassTiming, StageClocks};
use crate::chip::config::ChipConfig;
use crate::chip::work::PassWork;
use crate::report::csv_out::write_csv;
use crate::scene::format::Scene;
use rtl_model::ConfigError;
use serde::Serialize;
use std::path::Path;

/// The name of the glare pass (as `render --plan` lists it).
pub const GLARE_PASS: &str = "glare";
/// The pass that stands for the host's RAM-table writes.
pub const TABLES_PASS: &str = "glare RAM tables (host writes)";
/// The paper's fill rate: 1.2 × 10⁹ pixels/s.
pub const PAPER_PIXELS_PER_SECOND: f64 = 1.2e9;

/// The glare ASIC at the scene's `[glare.hw]` (widths, clock, pipes).
pub fn glare_chip(scene: &Scene) -> Result<ChipConfig, ConfigError> {
    glare_asic_for(&glare_of(scene)?.hw)
}

/// The glare pass of `scene`, rendered with its work recorded. What the pass does does
/// not depend on the picture beneath it (the primitives come from the sources and the
/// highlights; every covered fragment is added, saturating or not), so it is drawn
/// over a black picture: a scene whose background the frame's shafts passes draw
/// (`street-light`) needs no shafts frame for its timing.
pub fn record_glare(scene: &Scene) -> Result<GlareFrame, ConfigError> {
    let n = (scene.image.width as usize) * (scene.image.height as usize);
    render_glare_with(scene, Some(&vec![[0u32; 3]; n]), true)
}

/// Clocks the host's RAM-table writes take: per primitive ⌈words ÷ words per clock⌉.
pub fn table_cycles(f: &GlareFrame) -> u64 {
    f.prims
        .iter()
        .map(|p| p.table_words.div_ceil(GLARE_TABLE_WORDS_PER_CLOCK as u64))
        .sum()
}

/// The glare throughput formula at the chip's clock and pipes (per primitive: set-up,
/// walk over the pipes, drain; plus the table writes): the cross-check printed beside
/// the clocked time.
pub fn formula(
    f: &GlareFrame,
    scene: &Scene,
    chip: &ChipConfig,
) -> Result<GlarePrediction, ConfigError> {
    let g = glare_of(scene)?;
    let (setup, drain) = setup_and_drain(f, g.hw.coord_frac_bits)?;
    Ok(predict(f, chip.clock_hz / 1e6, chip.pipes, setup, drain))
}

/// Refuse a chip that is not the glare ASIC: the glare pass runs on its own units.
pub fn check_chip(chip: &ChipConfig) -> Result<(), ConfigError> {
    if chip.name != "glare-asic" {
        return Err(ConfigError::invalid(
            "chip",
            &format!(
                "the glare pass runs on the glare ASIC (glare-asic), not on {}",
                chip.name
            ),
        ));
    }
    Ok(())
}

/// The clocked timing of a recorded glare frame: the glare pass clocked, then the
/// host's table writes. `Err` if the frame was drawn without recording, the chip is
/// not the glare ASIC or the clock refuses the work.
pub fn frame_timing(
    f: &GlareFrame,
    scene: &Scene,
    chip: &ChipConfig,
) -> Result<FrameTiming, ConfigError> {
    check_chip(chip)?;
    let work: &PassWork = f.work.as_ref().ok_or_else(|| {
        ConfigError::invalid(
            "timing",
            "the glare frame was drawn without recording its work (render_glare_with(.., true))",
        )
    })?;
    let pred = formula(f, scene, chip)?;
    let pass = clock_pass(chip, work, None)?;
    let mut passes = vec![NamedPassTiming {
        pass: GLARE_PASS.into(),
        timing: pass,
        roofline_seconds: pred.walk_cycles as f64 / chip.clock_hz,
        scaled_from: None,
    }];
    passes.extend(tables_pass(f, &pred, chip));
    Ok(FrameTiming {
        mode: "clocked".into(),
        chip: chip.name.clone(),
        clock_hz: chip.clock_hz,
        passes,
        sampling_error: None,
        sample_band_every: None,
        sample_pass_every: None,
        roofline_only: Vec::new(),
    })
}

/// The host's RAM-table writes as a pass after the glare pass (`None`: no words
/// written), beside the formula's `pred` for them.
pub fn tables_pass(
    f: &GlareFrame,
    pred: &GlarePrediction,
    chip: &ChipConfig,
) -> Option<NamedPassTiming> {
    let tables = table_cycles(f);
    (tables > 0).then(|| NamedPassTiming {
        pass: TABLES_PASS.into(),
        timing: tables_timing(tables),
        roofline_seconds: pred.table_cycles as f64 / chip.clock_hz,
        scaled_from: None,
    })
}

/// The table writes as a pass: the host's write port busy every clock.
fn tables_timing(cycles: u64) -> PassTiming {
    PassTiming {
        cycles,
        hardware_passes: 1,
        stages: vec![StageClocks {
            name: "host table writes".into(),
            busy: cycles,
            stalled: 0,
            starved: 0,
        }],
        bottleneck: "host table writes".into(),
        ..PassTiming::default()
    }
}

/// Record and clock a glare scene's frame on `chip` (the glare ASIC: [`glare_chip`]
/// gives it at the scene's configuration).
pub fn glare_frame_timing(scene: &Scene, chip: &ChipConfig) -> Result<FrameTiming, ConfigError> {
    check_chip(chip)?;
    let f = record_glare(scene)?;
    frame_timing(&f, scene, chip)
}

/// Covered fragments ÷ clocked seconds; `None` when the frame took no time.
pub fn sustained_pixels_per_second(fragments: u64, t: &FrameTiming) -> Option<f64> {
    let s = t.clocked_seconds();
    (s > 0.0).then(|| fragments as f64 / s)
}

/// One row of `glare_asic_throughput.csv`: a scene on one variant of the preset.
/// Clocked columns are empty when the clocked chip could not run.
#[derive(Clone, Debug, Serialize)]
pub struct AsicRow {
    pub scene: String,
    /// "preset", or which assumed parameter the row changes.
    pub variant: String,
    pub clock_mhz: f64,
    pub pipes: u32,
    pub memory_bytes_per_clock: f64,
    pub memory_latency_clocks: u32,
    pub fifo_depth: u32,
    pub primitives: usize,
    pub walked: u64,
    pub fragments: u64,
    /// Peak: clock × pipes.
    pub peak_pixels_per_second: f64,
    /// The throughput formula's cycles (set-up + walk + drain per primitive, tables).
    pub formula_cycles: u64,
    pub formula_pixels_per_second: f64,
    /// The clocked glare pass's cycles.
    pub clocked_pass_cycles: Option<u64>,
    /// The host's table writes, clocks.
    pub table_cycles: u64,
    pub clocked_seconds: Option<f64>,
    pub sustained_pixels_per_second: Option<f64>,
    /// Sustained ÷ the paper's 1.2 × 10⁹ pixels/s.
    pub of_paper: Option<f64>,
    pub bottleneck: Option<String>,
}

/// The scenes `glare-asic-throughput` clocks.
pub const ASIC_SCENES: &[&str] = &["glare-flare", "street-light", "leaves"];

/// The preset and its assumed parameters changed one at a time: (name, chip).
pub fn variants(preset: &ChipConfig) -> Vec<(String, ChipConfig)> {
    let mut v = vec![("preset".to_string(), preset.clone())];
    let need = 2.0 * preset.pipes as f64 * 3.0; // RGB8 read + write per pipe per clock
    for (name, bpc) in [
        (format!("memory {need:.0} B/clock (the peak's need)"), need),
        (format!("memory {:.0} B/clock", need / 2.0), need / 2.0),
    ] {
        let mut c = preset.clone();
        c.memory.bytes_per_clock = bpc;
        v.push((name, c));
    }
    let mut c = preset.clone();
    c.memory.latency_clocks *= 3;
    v.push((
        format!("memory latency {} clocks", c.memory.latency_clocks),
        c,
    ));
    for depth in [16, 2] {
        let mut c = preset.clone();
        c.fifo_depth = depth;
        v.push((format!("FIFOs {depth} deep"), c));
    }
    v
}

/// The rows of one scene: recorded once, clocked on every variant. The first clock
/// error (the clocked chip absent or refusing) is returned beside the rows, whose
/// clocked columns are then empty.
pub fn scene_rows(name: &str, scene: &Scene) -> Result<(Vec<AsicRow>, Option<String>), String> {
    let e = |e: ConfigError| format!("{name}: {e}");
    let f = record_glare(scene).map_err(e)?;
    let preset = glare_chip(scene).map_err(e)?;
    let fragments: u64 = f.prims.iter().map(|p| p.fragments).sum();
    let walked: u64 = f.prims.iter().map(|p| p.walked).sum();
    let mut first_err = None;
    let mut rows = Vec::new();
    for (variant, chip) in variants(&preset) {
        let pred = formula(&f, scene, &chip).map_err(e)?;
        let t = match frame_timing(&f, scene, &chip) {
            Ok(t) => Some(t),
            Err(err) => {
                first_err.get_or_insert_with(|| err.to_string());
                None
            }
        };
        let glare = t
            .as_ref()
            .and_then(|t| t.passes.iter().find(|p| p.pass == GLARE_PASS));
        let sustained = t
            .as_ref()
            .and_then(|t| sustained_pixels_per_second(fragments, t));
        rows.push(AsicRow {
            scene: name.into(),
            variant,
            clock_mhz: chip.clock_hz / 1e6,
            pipes: chip.pipes,
            memory_bytes_per_clock: chip.memory.bytes_per_clock,
            memory_latency_clocks: chip.memory.latency_clocks,
            fifo_depth: chip.fifo_depth,
            primitives: f.prims.len(),
            walked,
            fragments,
            peak_pixels_per_second: chip.clock_hz * chip.pipes as f64,
            formula_cycles: pred.cycles,
            formula_pixels_per_second: pred.fragments_per_second,
            clocked_pass_cycles: glare.map(|p| p.timing.cycles),
            table_cycles: table_cycles(&f),
            clocked_seconds: t.as_ref().map(|t| t.clocked_seconds()),
            sustained_pixels_per_second: sustained,
            of_paper: sustained.map(|s| s / PAPER_PIXELS_PER_SECOND),
            bottleneck: glare.map(|p| p.timing.bottleneck.clone()),
        });
    }
    Ok((rows, first_err))
}

/// The table `glare-asic-throughput` prints: one line per row, "n/a" where the clocked
/// chip did not run.
pub fn table(rows: &[AsicRow]) -> String {
    let na = || "n/a".to_string();
    let mut s = format!(
        "{:<13} {:<36} {:>9} {:>9} {:>11} {:>11} {:>12} {:>12} {:>7}  bottleneck\n",
        "scene",
        "variant",
        "fragments",
        "walked",
        "formula/s",
        "formula cyc",
        "clocked cyc",
        "sustained/s",
        "of 1.2G"
    );
    for r in rows {
        let cyc = r
            .clocked_pass_cycles
            .map(|c| (c + r.table_cycles).to_string())
            .unwrap_or_else(na);
        let sus = r
            .sustained_pixels_per_second
            .map(|v| format!("{v:.3e}"))
            .unwrap_or_else(na);
        let of = r
            .of_paper
            .map(|v| format!("{:.0} %", 100.0 * v))
            .unwrap_or_else(na);
        s += &format!(
            "{:<13} {:<36} {:>9} {:>9} {:>11.3e} {:>11} {:>12} {:>12} {:>7}  {}\n",
            r.scene,
            r.variant,
            r.fragments,
            r.walked,
            r.formula_pixels_per_second,
            r.formula_cycles,
            cyc,
            sus,
            of,
            r.bottleneck.clone().unwrap_or_else(na)
        );
    }
    s
}

/// `reproduce glare-asic-throughput`: `glare_asic_throughput.csv` in `out` and the
/// table; the clocked chip's error, if it could not run, printed once (the formula's
/// columns are still written).
pub fn asic_throughput(out: &Path) -> Result<Vec<AsicRow>, String> {
    let mut rows = Vec::new();
    let mut err = None;
    for &name in ASIC_SCENES {
        let scene = crate::scene::load::load_scene(name)?;
        let (r, e) = scene_rows(name, &scene)?;
        rows.extend(r);
        if err.is_none() {
            err = e;
        }
    }
    write_csv(&out.join("glare_asic_throughput.csv"), &rows)?;
    print!("{}", table(&rows));
    if let Some(e) = err {
        println!("clocked columns n/a: {e}");
    }
    Ok(rows)
}
