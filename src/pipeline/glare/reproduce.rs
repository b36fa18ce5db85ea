//! The paper's glare figures (Matsuda & Ikedo, Figs. 4, 5, 7, 8) and the throughput
//! table, each as CSV and PNG in a directory.

use super::cli::{reference_levels, render_and_predict, render_and_predict_over};
use super::fluctuation::chaos_unit;
use super::frame::GlareFrame;
use super::throughput::{config_cost, peak_pixels_per_second, ThroughputRow};
use crate::report::csv_out::write_csv;
use crate::report::metrics::error_stats;
use crate::report::plot::{image_grid, line_plot, Axis, PlotSpec, Series};
use crate::report::spectrum::{loglog_slope, welch_psd};
use crate::scene::builtin_glare::{glare_elliptic, glare_flare, glare_point, leaves, street_light};
use crate::scene::format::Scene;
use image::RgbaImage;
use rtl_model::Counters;
use serde::Serialize;
use std::path::Path;

/// One rendered panel's summary row.
#[derive(Clone, Debug, Serialize)]
pub struct PanelRow {
    pub panel: String,
    pub primitives: usize,
    pub walked: u64,
    pub fragments: u64,
    pub predicted_seconds: f64,
    pub wall_seconds: f64,
    pub mean_abs: f64,
    pub rms: f64,
    pub max: f64,
}

fn rgba(f: &GlareFrame) -> RgbaImage {
    RgbaImage::from_raw(f.fb.width, f.fb.height, f.fb.to_rgba8()).unwrap_or_default()
}

/// Render one panel, save its PNG, measure it against the f64 reference.
fn panel(scene: &Scene, name: &str, out: &Path) -> Result<(GlareFrame, PanelRow), String> {
    panel_over(scene, None, name, out)
}

/// [`panel`] over a background already drawn for this scene.
fn panel_over(
    scene: &Scene,
    base: Option<&[[u32; 3]]>,
    name: &str,
    out: &Path,
) -> Result<(GlareFrame, PanelRow), String> {
    let (f, pred, wall) = render_and_predict_over(scene, base).map_err(|e| e.to_string())?;
    let path = out.join(format!("{name}.png"));
    f.fb.save_png(&path)
        .map_err(|e| format!("out: {}: {e}", path.display()))?;
    let lv = reference_levels(scene, &f).map_err(|e| e.to_string())?;
    let st = error_stats(&f.levels(), &lv).map_err(|e| e.to_string())?;
    let row = PanelRow {
        panel: name.into(),
        primitives: f.prims.len(),
        walked: pred.walked,
        fragments: pred.fragments,
        predicted_seconds: pred.seconds,
        wall_seconds: wall,
        mean_abs: st.mean_abs,
        rms: st.rms,
        max: st.max,
    };
    Ok((f, row))
}

/// A horizontal profile through each source's centre: hardware and reference, level
/// of the green channel.
#[derive(Clone, Debug, Serialize)]
struct ProfileRow {
    panel: String,
    x: u32,
    hardware: f64,
    reference: f64,
}

fn profile(scene: &Scene, f: &GlareFrame, name: &str) -> Result<Vec<ProfileRow>, String> {
    let lv = reference_levels(scene, f).map_err(|e| e.to_string())?;
    let hw = f.levels();
    let Some(s) = f.sources.first() else {
        return Ok(Vec::new());
    };
    let y = (s.center[1].floor().max(0.0) as u32).min(f.fb.height - 1);
    Ok((0..f.fb.width)
        .map(|x| {
            let i = (y * f.fb.width + x) as usize;
            ProfileRow {
                panel: name.into(),
                x,
                hardware: hw[i][1],
                reference: lv[i][1],
            }
        })
        .collect())
}

/// Fig. 4: a point source and an elliptic source with bloom.
pub fn fig4(out: &Path) -> Result<(), String> {
    let (sp, se) = (glare_point(), glare_elliptic());
    let (fp, rp) = panel(&sp, "fig4_point", out)?;
    let (fe, re) = panel(&se, "fig4_elliptic", out)?;
    write_csv(&out.join("fig4.csv"), &[rp, re])?;
    let mut prof = profile(&sp, &fp, "point")?;
    prof.extend(profile(&se, &fe, "elliptic")?);
    write_csv(&out.join("fig4_profile.csv"), &prof)?;
    image_grid(
        &out.join("fig4.png"),
        &[
            ("point source", &rgba(&fp)),
            ("elliptic source", &rgba(&fe)),
        ],
        2,
    )?;
    let series = |panel: &str, hw: bool| Series {
        label: format!("{panel} {}", if hw { "hardware" } else { "f64 reference" }),
        points: prof
            .iter()
            .filter(|r| r.panel == panel)
            .map(|r| (r.x as f64, if hw { r.hardware } else { r.reference }))
            .collect(),
        axis: Axis::Left,
    };
    line_plot(
        &out.join("fig4_profile.png"),
        &PlotSpec::new(
            "Fig. 4: bloom profile through the source (green channel)",
            "x (pixels)",
            "level",
        ),
        &[
            series("point", true),
            series("point", false),
            series("elliptic", true),
            series("elliptic", false),
        ],
    )
}

#[derive(Clone, Debug, Serialize)]
struct LineRow {
    line: usize,
    distribution: usize,
    angle_deg: f64,
    length_px: f64,
    width_px: f64,
    intensity: f64,
}

/// Fig. 5: flare lines from an elliptic source.
pub fn fig5(out: &Path) -> Result<(), String> {
    let s = glare_flare();
    let (f, row) = panel(&s, "fig5", out)?;
    write_csv(&out.join("fig5.csv"), &[row])?;
    let rows: Vec<LineRow> = f
        .lines
        .iter()
        .flatten()
        .enumerate()
        .map(|(k, l)| LineRow {
            line: k,
            distribution: k % 2,
            angle_deg: l.angle.to_degrees().rem_euclid(360.0),
            length_px: l.length_px,
            width_px: l.width_px,
            intensity: l.intensity,
        })
        .collect();
    write_csv(&out.join("fig5_lines.csv"), &rows)?;
    // The f64 reference with its own rand_distr draws (same R1 outputs, different
    // random lines): the distribution, not the particular lines, is what must agree.
    let g = s.glare.as_ref().ok_or("scene: glare-flare has no glare")?;
    let float_lines: Vec<Vec<crate::reference::glare_model::FlareLine>> = f
        .sources
        .iter()
        .enumerate()
        .map(|(i, src)| {
            src.flare.as_ref().map_or(Vec::new(), |fp| {
                fp.lines(
                    &crate::reference::glare_model::float_draws(fp.num, s.seed ^ i as u64),
                    src.px_per_deg,
                )
            })
        })
        .collect();
    let max = rtl_model::unorm::max_code(g.hw.fb_bits) as f64;
    let base: Vec<[f64; 3]> = f.base.iter().map(|p| p.map(|v| v as f64)).collect();
    let img = crate::reference::glare_model::reference_image(
        s.image.width,
        s.image.height,
        &base,
        &f.sources,
        &float_lines,
        &g.determinants,
        &g.model,
        max,
    );
    let lv: Vec<[f64; 3]> = img.iter().map(|p| p.map(|v| v * 255.0 / max)).collect();
    crate::report::image_out::levels_png(
        &lv,
        s.image.width,
        s.image.height,
        &out.join("fig5_reference_float_draws.png"),
    )
}

/// Fig. 7: a street light — the original, with bloom, with bloom and halo, over
/// `backdrop`, the street light's picture as the frame's shafts passes drew it.
pub fn fig7(out: &Path, backdrop: &crate::report::image_out::Framebuffer) -> Result<(), String> {
    let base = street_light();
    let fb_bits = base
        .glare
        .as_ref()
        .map(|g| g.hw.fb_bits)
        .unwrap_or_default();
    let picture = super::background::from_framebuffer(backdrop, fb_bits);
    // The original keeps the lamp's own disc (its core, B = 0: no veil).
    let variant = |veil: bool, halo: bool| {
        let mut s = base.clone();
        if let Some(g) = s.glare.as_mut() {
            if !veil {
                g.model.bloom_k = 0.0;
            }
            for src in &mut g.sources {
                src.halo = halo;
            }
        }
        s
    };
    // The three panels share one background (the shafts pipeline's frame).
    let (f0, r0) = panel_over(&variant(false, false), Some(&picture), "fig7_original", out)?;
    let (f1, r1) = panel_over(&variant(true, false), Some(&picture), "fig7_bloom", out)?;
    let (f2, r2) = panel_over(&variant(true, true), Some(&picture), "fig7_bloom_halo", out)?;
    write_csv(&out.join("fig7.csv"), &[r0, r1, r2])?;
    image_grid(
        &out.join("fig7.png"),
        &[
            ("original", &rgba(&f0)),
            ("+ bloom", &rgba(&f1)),
            ("+ halo", &rgba(&f2)),
        ],
        3,
    )
}

#[derive(Clone, Debug, Serialize)]
struct TraceRow {
    t: usize,
    i_p: f64,
}

#[derive(Clone, Debug, Serialize)]
struct SlopeRow {
    z: f64,
    a: f64,
    patches: u32,
    steps: usize,
    f_lo: f64,
    f_hi: f64,
    slope: f64,
    theory: f64,
}

/// The theoretical log-log slope of the intermittent map's spectrum: −(2z − 3)/(z − 1)
/// for 3/2 < z < 2 (flat, 0, below 3/2).
pub fn theory_slope(z: f64) -> f64 {
    if z <= 1.5 {
        0.0
    } else {
        -(2.0 * z - 3.0) / (z - 1.0)
    }
}

/// Steps of the Fig. 8 trace and the frames drawn from it.
pub const FIG8_STEPS: usize = 1 << 20;
pub const FIG8_FRAMES: [u32; 4] = [0, 40, 80, 120];

/// Fig. 8: sunlight through leaves — frames, the intensity trace I_p(t), its power
/// spectrum and slope.
pub fn fig8(out: &Path) -> Result<(), String> {
    let base = leaves();
    let mut frames = Vec::new();
    let mut rows = Vec::new();
    for &t in &FIG8_FRAMES {
        let mut s = base.clone();
        if let Some(g) = s.glare.as_mut() {
            g.frame = t;
        }
        let (f, r) = panel(&s, &format!("fig8_frame_{t:03}"), out)?;
        frames.push((format!("t = {t}"), rgba(&f)));
        rows.push(r);
    }
    write_csv(&out.join("fig8.csv"), &rows)?;
    let refs: Vec<(&str, &RgbaImage)> = frames.iter().map(|(c, i)| (c.as_str(), i)).collect();
    image_grid(&out.join("fig8.png"), &refs, 2)?;

    // The trace: I_p(t) of the source's patches through the chaos-map unit.
    let g = base.glare.as_ref().ok_or("scene: leaves has no glare")?;
    let patches = g.sources[0].fluctuation.map_or(1, |f| f.patches);
    let trace = fig8_trace(out, &base, g, patches)?;
    let (freq, power) = welch_psd(&trace, 16);
    let (f_lo, f_hi) = (1e-4, 1e-2);
    let (slope, _) =
        loglog_slope(&freq, &power, f_lo, f_hi, 8).ok_or("spectrum: too few bins for a slope")?;
    let theory = theory_slope(g.model.chaos_z);
    write_csv(
        &out.join("fig8_slope.csv"),
        &[SlopeRow {
            z: g.model.chaos_z,
            a: g.model.chaos_a,
            patches,
            steps: FIG8_STEPS,
            f_lo,
            f_hi,
            slope,
            theory,
        }],
    )?;
    fig8_spectrum(out, g, &freq, &power, (f_lo, f_hi), (slope, theory))?;
    println!("fig8: log-log slope {slope:.3} over [{f_lo}, {f_hi}] cycles/step; theory {theory:.3} for z = {}", g.model.chaos_z);
    Ok(())
}

/// Fig. 8's trace: `FIG8_STEPS` steps of I_p(t) through the chaos-map unit (I_p / I);
/// its first 4096 steps written as `fig8_trace.csv` and `.png`.
fn fig8_trace(
    out: &Path,
    base: &Scene,
    g: &crate::scene::glare::GlareSection,
    patches: u32,
) -> Result<Vec<f64>, String> {
    let (u, mut st) = chaos_unit(base, 0, patches).map_err(|e| e.to_string())?;
    let mut c = Counters::default();
    let codes = u.run_trace(&mut st, FIG8_STEPS, &mut c);
    let scale = ((1u64 << u.config().out_bits) - 1) as f64;
    let trace: Vec<f64> = codes.iter().map(|&v| v as f64 / scale).collect();
    let head: Vec<TraceRow> = trace
        .iter()
        .take(4096)
        .enumerate()
        .map(|(t, &i_p)| TraceRow { t, i_p })
        .collect();
    write_csv(&out.join("fig8_trace.csv"), &head)?;
    line_plot(
        &out.join("fig8_trace.png"),
        &PlotSpec::new(
            "Fig. 8: I_p(t) = I·(1/n)·ΣS_i(t), first 4096 steps",
            "t (steps)",
            "I_p / I",
        ),
        &[Series {
            label: format!(
                "{patches} patches, a = {}, z = {}",
                g.model.chaos_a, g.model.chaos_z
            ),
            points: head.iter().map(|r| (r.t as f64, r.i_p)).collect(),
            axis: Axis::Left,
        }],
    )?;
    Ok(trace)
}

/// Fig. 8's spectrum: `fig8_spectrum.csv` and its log-log plot with the theory's slope
/// from the first bin at or above `f_lo`.
fn fig8_spectrum(
    out: &Path,
    g: &crate::scene::glare::GlareSection,
    freq: &[f64],
    power: &[f64],
    (f_lo, f_hi): (f64, f64),
    (slope, theory): (f64, f64),
) -> Result<(), String> {
    #[derive(Serialize)]
    struct SpecRow {
        f: f64,
        power: f64,
    }
    let spec: Vec<SpecRow> = freq
        .iter()
        .zip(power)
        .map(|(&f, &p)| SpecRow { f, power: p })
        .collect();
    write_csv(&out.join("fig8_spectrum.csv"), &spec)?;
    let p0 = power
        .iter()
        .zip(freq)
        .find(|(_, &f)| f >= f_lo)
        .map_or(1.0, |(p, _)| *p);
    let mut spec_plot = PlotSpec::new(
        &format!("Fig. 8: spectrum of I_p, slope {slope:.2} (theory {theory:.2})"),
        "frequency (cycles/step)",
        "power",
    );
    spec_plot.log_x = true;
    spec_plot.log_y = true;
    line_plot(
        &out.join("fig8_spectrum.png"),
        &spec_plot,
        &[
            Series {
                label: "Welch spectrum of the chaos-map trace".into(),
                points: freq
                    .iter()
                    .zip(power)
                    .filter(|(_, p)| **p > 0.0)
                    .map(|(&f, &p)| (f, p))
                    .collect(),
                axis: Axis::Left,
            },
            Series {
                label: format!("slope {theory:.3} (theory, z = {})", g.model.chaos_z),
                points: vec![(f_lo, p0), (f_hi, p0 * (f_hi / f_lo).powf(theory))],
                axis: Axis::Left,
            },
        ],
    )?;
    Ok(())
}

/// The glare-throughput table: configurations of clock and pipes, their fill rate,
/// gates and RAM bits (per-pipe units replicated; generator and noise shared).
pub fn throughput_table() -> Result<Vec<ThroughputRow>, String> {
    Ok(throughput_parts()?.0)
}

/// One unit of the throughput configurations (`throughput_units.csv`).
#[derive(Clone, Debug, Serialize)]
pub struct UnitRow {
    pub unit: String,
    pub role: String,
    pub gates_nand2: f64,
    pub ram_bits: u64,
    pub latency: u32,
    pub ii: u32,
}

/// The configurations and the units they are built from.
pub fn throughput_parts() -> Result<(Vec<ThroughputRow>, Vec<UnitRow>), String> {
    // Per-pipe and shared units at the defaults, from a frame that elaborates them all.
    let mut s = glare_flare();
    if let Some(g) = s.glare.as_mut() {
        g.sources[0].halo = true;
    }
    let (f, _, _) = render_and_predict(&s).map_err(|e| e.to_string())?;
    let per_pipe: Vec<_> = f
        .units
        .iter()
        .filter(|u| {
            matches!(
                u.name,
                "polygon_interpolator"
                    | "bloom_flare_modulator"
                    | "halo_modulator"
                    | "glare_combiner"
            )
        })
        .cloned()
        .collect();
    let shared: Vec<_> = f
        .units
        .iter()
        .filter(|u| matches!(u.name, "polygon_variable_generator" | "gaussian_noise"))
        .cloned()
        .collect();
    let configs: [(&str, f64, u32); 6] = [
        ("1 pipe at the GeForce2 GTS clock", 200.0, 1),
        ("4 pipes at the GeForce2 GTS clock", 200.0, 4),
        ("4 pipes, 300 MHz", 300.0, 4),
        ("6 pipes, 200 MHz", 200.0, 6),
        ("8 pipes, 150 MHz", 150.0, 8),
        ("2 pipes, 600 MHz", 600.0, 2),
    ];
    let units: Vec<UnitRow> = per_pipe
        .iter()
        .map(|u| (u, "per pipe"))
        .chain(shared.iter().map(|u| (u, "shared")))
        .map(|(u, role)| UnitRow {
            unit: u.name.into(),
            role: role.into(),
            gates_nand2: u.gates_nand2,
            ram_bits: u.ram_bits,
            latency: u.latency,
            ii: u.ii,
        })
        .collect();
    let rows = configs
        .iter()
        .map(|&(name, clock, pipes)| {
            let (gates, ram) = config_cost(&per_pipe, &shared, pipes);
            ThroughputRow {
                config: name.into(),
                clock_mhz: clock,
                pipes,
                pixels_per_second: peak_pixels_per_second(clock, pipes),
                gates_nand2: gates,
                ram_bits: ram,
            }
        })
        .collect();
    Ok((rows, units))
}

pub fn throughput(out: &Path) -> Result<(), String> {
    let (rows, units) = throughput_parts()?;
    write_csv(&out.join("throughput.csv"), &rows)?;
    write_csv(&out.join("throughput_units.csv"), &units)?;
    for u in &units {
        println!(
            "{:<28} {:<8} {:>8.0} gates {:>8} RAM bits, latency {}, II {}",
            u.unit, u.role, u.gates_nand2, u.ram_bits, u.latency, u.ii
        );
    }
    let modulators: f64 = units
        .iter()
        .filter(|u| u.unit.ends_with("modulator"))
        .map(|u| u.gates_nand2)
        .sum();
    println!("luminance modulators (bloom/flare + halo) per pipe: {modulators:.0} gates (the paper: about 80 k)");
    for r in &rows {
        println!(
            "{:<36} {:>6.0} MHz × {} pipes: {:.3e} pixels/s, {:.0} gates, {} RAM bits",
            r.config, r.clock_mhz, r.pipes, r.pixels_per_second, r.gates_nand2, r.ram_bits
        );
    }
    Ok(())
}
