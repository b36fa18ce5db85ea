//! The frame's error against its f64 references, per pass and in total, and
//! `reproduce frame-elaboration`: the `night-street` showcase and four reduced variants,
//! one row each.
//!
//! # How the error is formed
//! Each pass is compared with its own f64 reference, given the same inputs the
//! hardware pass had:
//! - **objects** (shading units, environment reflections): the pass's 8-bit result
//!   against, per light, k_l · 255 · π · R · cos θ_i of the material's reference BRDF
//!   (`objects::reference_levels`, per channel albedo) plus the reflector's Phong
//!   environment truth × reflectance × transmittance, on the pixels it coloured;
//! - **shafts** (depth, shadow maps, Lambert objects, sample planes): the shafts
//!   framebuffer less what the object pass wrote, against the ray-marched reference
//!   (`reference::raymarch`, 180 samples per ray) of the scene with the object pass's
//!   objects black (there it holds the in-scatter and attenuation alone), on every
//!   pixel;
//! - **glare**: the glare frame against the analytic glare formulas over the same
//!   picture (`glare::cli::reference_levels`), on every pixel.
//!
//! The frame's reference is the ray march plus the object pass's reference plus the
//! glare's analytic contribution (clamped to [0, 255]). Per pixel the hardware frame
//! is the object pass's result plus the shafts passes' contribution, glared; so
//! |hw − ref| ≤ |objects error| + |shafts error| + |glare error| (the glare adds the
//! same contribution to both pictures, and clamping is 1-Lipschitz). Averaged over the
//! whole frame (a pass contributes 0 where it draws nothing), the total's mean |Δ| is
//! at most the sum of the passes' means over the frame: that sum is the bound the
//! report checks (`mean_abs_frame` ≤ `bound`).

use super::chip::{elaborate, Feature};
use super::gpu::Gpu;
use super::run::{render_on, Frame};
use crate::pipeline::glare::cli::reference_levels;
use crate::pipeline::shafts::cli::reference_image;
use crate::report::image_out::levels_png;
use crate::scene::format::Scene;
use serde::Serialize;
use std::path::Path;

/// One pass's (or the total's) error, in 8-bit levels.
#[derive(Clone, Debug, Serialize)]
pub struct PassError {
    pub pass: String,
    pub reference: String,
    /// Pixels compared.
    pub pixels: usize,
    /// Mean |Δ| over the compared pixels, and over every pixel of the frame (0 where
    /// not compared): the second is what the total's bound sums.
    pub mean_abs: f64,
    pub mean_abs_frame: f64,
    pub rms: f64,
    pub max: f64,
}

/// Per-pass and total errors of a frame.
#[derive(Clone, Debug, Serialize)]
pub struct FrameError {
    pub passes: Vec<PassError>,
    pub total: PassError,
    /// Σ of the passes' `mean_abs_frame`: the bound on the total's `mean_abs_frame`.
    pub bound: f64,
}

fn stats(pass: &str, reference: &str, a: &[[f64; 3]], b: &[[f64; 3]], mask: &[bool]) -> PassError {
    let (mut sum, mut sq, mut max, mut n) = (0.0f64, 0.0f64, 0.0f64, 0usize);
    for ((x, y), &m) in a.iter().zip(b).zip(mask) {
        if !m {
            continue;
        }
        n += 1;
        for c in 0..3 {
            let d = (x[c] - y[c]).abs();
            sum += d;
            sq += d * d;
            max = max.max(d);
        }
    }
    let all = (a.len() * 3).max(1) as f64;
    let k = (n * 3).max(1) as f64;
    PassError {
        pass: pass.into(),
        reference: reference.into(),
        pixels: n,
        mean_abs: sum / k,
        mean_abs_frame: sum / all,
        rms: (sq / k).sqrt(),
        max,
    }
}

/// The frame's error (module notes); `reference` also writes the total reference PNG.
pub fn frame_error(
    scene: &Scene,
    f: &Frame,
    reference: Option<&Path>,
) -> Result<FrameError, String> {
    let (e, ref_total) = frame_error_and_reference(scene, f)?;
    if let Some(path) = reference {
        let (w, h) = (scene.image.width, scene.image.height);
        levels_png(&ref_total, w, h, path).map_err(|e| e.replacen("out:", "reference:", 1))?;
    }
    Ok(e)
}

/// The frame's error (module notes) and its composed f64 reference in 8-bit levels
/// (row-major RGB): what `sweep` and `attribute` compare a frame scene against.
pub fn frame_error_and_reference(
    scene: &Scene,
    f: &Frame,
) -> Result<(FrameError, Vec<[f64; 3]>), String> {
    let (w, h) = (scene.image.width, scene.image.height);
    let n = (w * h) as usize;
    let all = vec![true; n];
    let mut passes = Vec::new();
    let mut ref_backdrop: Vec<[f64; 3]> = f.fb.levels();
    if let Some(sh) = &f.shafts {
        let truth = shafts_truth(scene, f)?;
        let mut shafts_hw = sh.levels();
        ref_backdrop = truth.clone();
        if let Some(o) = &f.shaded {
            let (obj_hw, mask, obj_ref) = object_pass_levels(scene, f, sh.fb.bits, o)?;
            passes.push(stats(
                "objects (shading units, environment reflections)",
                "BRDF references per channel, Phong environment truth",
                &obj_hw,
                &obj_ref,
                &mask,
            ));
            // The shafts passes' own contribution: the framebuffer less what the object
            // pass wrote.
            for ((s, o), m) in shafts_hw.iter_mut().zip(&obj_hw).zip(&mask) {
                if *m {
                    for c in 0..3 {
                        s[c] -= o[c];
                    }
                }
            }
            ref_backdrop = truth
                .iter()
                .zip(&obj_ref)
                .map(|(t, o)| [0, 1, 2].map(|c| t[c] + o[c]))
                .collect();
        }
        passes.insert(
            0,
            stats(
                "shafts (depth, shadow maps, Lambert objects, sample planes)",
                "ray march, 180 samples per ray",
                &shafts_hw,
                &truth,
                &all,
            ),
        );
    }
    let mut ref_total = ref_backdrop.clone();
    if let Some((g, _)) = &f.glare {
        let gs = g_scene(scene, f);
        let lv = reference_levels(&gs, g).map_err(|e| e.to_string())?;
        passes.push(stats(
            "glare",
            "analytic glare over the same picture",
            &g.levels(),
            &lv,
            &all,
        ));
        add_glare_reference(&mut ref_total, &lv, g, f.shafts.is_some());
    }
    let total = stats(
        "frame",
        "composed f64 reference",
        &f.fb.levels(),
        &ref_total,
        &all,
    );
    let bound = passes.iter().map(|p| p.mean_abs_frame).sum();
    Ok((
        FrameError {
            passes,
            total,
            bound,
        },
        ref_total,
    ))
}

/// The shafts passes' truth: the ray march with the object pass's objects black (their
/// pixels then hold the in-scatter and attenuation alone, to which the object pass's
/// reference adds their colour).
fn shafts_truth(scene: &Scene, f: &Frame) -> Result<Vec<[f64; 3]>, String> {
    let mut s = scene.clone();
    s.glare = None;
    if let Some(o) = &f.shaded {
        for (i, obj) in s.objects.iter_mut().enumerate() {
            if scene.shaded_object(i) && o.objects.contains(&Some(i)) {
                obj.color = [0.0; 3];
            }
        }
    }
    Ok(reference_image(&s, 180)?.0)
}

/// The object pass's levels in the framebuffer, the pixels it wrote, its reference.
type ObjectPassLevels = (Vec<[f64; 3]>, Vec<bool>, Vec<[f64; 3]>);

/// The object pass's output in framebuffer levels (as written into a `fb_bits`
/// framebuffer), the mask of the pixels it wrote, and its reference (0 elsewhere).
fn object_pass_levels(
    scene: &Scene,
    f: &Frame,
    fb_bits: u32,
    o: &super::objects::ShadedObjects,
) -> Result<ObjectPassLevels, String> {
    let p = f.plan.prepared.as_ref().ok_or("frame: no shafts set-up")?;
    let refl = super::reflection::reflections_with(scene, true).map_err(|e| e.to_string())?;
    let obj_ref =
        super::objects::reference_levels(scene, p, &o.objects, &refl).map_err(|e| e.to_string())?;
    let max = rtl_model::unorm::max_code(fb_bits);
    let obj_hw: Vec<[f64; 3]> = o
        .levels
        .iter()
        .map(|l| {
            l.map_or([0.0; 3], |v| {
                v.map(|c| {
                    rtl_model::unorm::narrow(rtl_model::unorm::widen(c, 8, 16), 16, fb_bits) as f64
                        * 255.0
                        / max as f64
                })
            })
        })
        .collect();
    let mask: Vec<bool> = o.levels.iter().map(|l| l.is_some()).collect();
    let obj_ref_dense: Vec<[f64; 3]> = obj_ref.iter().map(|r| r.unwrap_or([0.0; 3])).collect();
    Ok((obj_hw, mask, obj_ref_dense))
}

/// The glare's analytic contribution added to the backdrop's reference `total` (over a
/// shafts picture: the glare reference `lv` less the base it was drawn over; alone: `lv`).
fn add_glare_reference(
    total: &mut [[f64; 3]],
    lv: &[[f64; 3]],
    g: &crate::pipeline::glare::frame::GlareFrame,
    over_shafts: bool,
) {
    let max = rtl_model::unorm::max_code(g.fb.bits) as f64;
    for ((t, r), b) in total.iter_mut().zip(lv).zip(&g.base) {
        for c in 0..3 {
            if over_shafts {
                let contrib = r[c] - b[c] as f64 * 255.0 / max;
                t[c] = (t[c] + contrib).clamp(0.0, 255.0);
            } else {
                t[c] = r[c];
            }
        }
    }
}

/// The scene the glare pass rendered (with the highlights the shading found).
fn g_scene(scene: &Scene, f: &Frame) -> Scene {
    let mut s = match &f.linked {
        Some(l) => l.scene.clone(),
        None => scene.clone(),
    };
    if let (Some(sh), Some(g)) = (&f.shaded, s.glare.as_mut()) {
        g.highlights
            .extend(sh.highlights.iter().map(|h| h.highlight));
    }
    s
}

/// The errors as a table.
pub fn error_table(e: &FrameError) -> String {
    let rows: Vec<Vec<String>> = e
        .passes
        .iter()
        .chain(std::iter::once(&e.total))
        .map(|p| {
            vec![
                p.pass.clone(),
                p.reference.clone(),
                p.pixels.to_string(),
                format!("{:.3}", p.mean_abs),
                format!("{:.3}", p.mean_abs_frame),
                format!("{:.3}", p.rms),
                format!("{:.1}", p.max),
            ]
        })
        .collect();
    let mut s = crate::report::table::text_table(
        &[
            "pass",
            "reference",
            "pixels",
            "mean_abs_levels",
            "mean_abs_frame_levels",
            "rms_levels",
            "max_levels",
        ],
        &rows,
    );
    s.push_str(&format!(
        "total mean |Δ| over the frame {:.3} ≤ Σ per-pass {:.3}: {}\n",
        e.total.mean_abs_frame,
        e.bound,
        if e.total.mean_abs_frame <= e.bound + 1e-9 {
            "holds"
        } else {
            "VIOLATED"
        }
    ));
    s
}

/// Render a scene on `gpu` and its error (for the reproduction).
pub fn render_with_error(scene: &Scene, gpu: Gpu) -> Result<(Frame, FrameError), String> {
    let f = render_on(scene, gpu).map_err(|e| e.to_string())?;
    let e = frame_error(scene, &f, None)?;
    Ok((f, e))
}

/// A reduced variant of the showcase: its name, the scene, and the features it lacks.
pub struct Variant {
    pub name: &'static str,
    pub scene: Scene,
    pub missing: Vec<Feature>,
}

/// The showcase (`night-street`) and its four reduced variants: no fog, no glare, no
/// environment map, Lambert only.
pub fn variants(base: &Scene) -> Vec<Variant> {
    let mut no_fog = base.clone();
    no_fog.medium.rho = 0.0;
    let mut no_glare = base.clone();
    no_glare.glare = None;
    let mut no_env = base.clone();
    no_env.environment = None;
    let mut lambert = base.clone();
    for o in &mut lambert.objects {
        o.material = None;
    }
    let named = |mut s: Scene, tag: &str| {
        s.name = format!("{} [{tag}]", base.name);
        s
    };
    vec![
        Variant {
            name: "showcase",
            scene: base.clone(),
            missing: vec![],
        },
        Variant {
            name: "no fog",
            scene: named(no_fog, "no fog"),
            missing: vec![Feature::Fog],
        },
        Variant {
            name: "no glare",
            scene: named(no_glare, "no glare"),
            // The highlights feed only the glare conditions.
            missing: vec![Feature::Glare, Feature::Highlights],
        },
        Variant {
            name: "no environment map",
            scene: named(no_env, "no environment map"),
            missing: vec![Feature::Environment],
        },
        Variant {
            name: "Lambert only",
            scene: named(lambert, "Lambert only"),
            // Without a specular material no highlight reaches the glare conditions.
            missing: vec![Feature::Shading, Feature::Highlights],
        },
    ]
}

/// One row of `frame-elaboration`.
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
pub struct ElaborationRow {
    pub variant: String,
    pub units_present: usize,
    pub gates_nand2: f64,
    pub ram_bits: u64,
    pub left_out: String,
    pub gpu: String,
    pub predicted_seconds: f64,
    pub simulation_wall_seconds: f64,
    /// Mean |Δ| over the compared pixels, and over every pixel of the frame (the
    /// measure `error_bound` bounds).
    pub error_mean_abs: f64,
    pub error_mean_abs_frame: f64,
    pub error_rms: f64,
    pub error_max: f64,
    /// Σ of the per-pass mean |Δ| over the frame (the total's bound).
    pub error_bound: f64,
}

/// `reproduce frame-elaboration`: one row per variant (CSV), the five frames as a
/// PNG strip, and the rows as a table on stdout. `size` overrides the image size.
pub fn frame_elaboration(
    out: &Path,
    size: Option<(u32, u32)>,
) -> Result<Vec<ElaborationRow>, String> {
    frame_elaboration_resumable(out, size, false)
}

/// [`frame_elaboration`], saving each variant's row (its PNG written first) as it
/// finishes to `DIR/frame-elaboration.resume.jsonl`; with `resume`, the variants of an
/// interrupted run of the same size are kept (their images read back from their PNGs,
/// which hold the framebuffer's RGBA bytes exactly) and only the others rendered
/// (`report::items`).
pub fn frame_elaboration_resumable(
    out: &Path,
    size: Option<(u32, u32)>,
    resume: bool,
) -> Result<Vec<ElaborationRow>, String> {
    let mut base = crate::scene::builtin_showcase::night_street();
    if let Some((w, h)) = size {
        base.image.width = w;
        base.image.height = h;
    }
    let mut rows = Vec::new();
    let mut images = Vec::new();
    // Every variant on the showcase's GPU, so the times compare.
    let gpu = Gpu::for_scene(&base);
    let all = variants(&base);
    let journal = crate::report::items::ItemJournal::<ElaborationRow>::open(
        out,
        "frame-elaboration",
        &[(
            "image",
            format!("{}x{}", base.image.width, base.image.height),
        )],
        all.len(),
        resume,
    )?;
    for v in all {
        let png = out.join(format!(
            "frame_{}.png",
            v.name.replace(' ', "_").to_lowercase()
        ));
        let row = journal.item(v.name, || {
            let chip = elaborate(&v.scene);
            let (f, e) = render_with_error(&v.scene, gpu)?;
            f.fb.save_png(&png)
                .map_err(|err| format!("out: {}: {err}", png.display()))?;
            let left: Vec<&str> = chip.left_out().map(|u| u.instance).collect();
            Ok(ElaborationRow {
                variant: v.name.to_string(),
                units_present: chip.present().count(),
                gates_nand2: chip.gates(),
                ram_bits: chip.ram_bits(),
                left_out: left.join("; "),
                gpu: f.gpu.name().to_string(),
                predicted_seconds: f.predicted_seconds(),
                simulation_wall_seconds: f.wall_seconds,
                error_mean_abs: e.total.mean_abs,
                error_mean_abs_frame: e.total.mean_abs_frame,
                error_rms: e.total.rms,
                error_max: e.total.max,
                error_bound: e.bound,
            })
        })?;
        rows.push(row);
        let rgba = image::open(&png)
            .map_err(|err| format!("out: {}: {err}", png.display()))?
            .to_rgba8();
        images.push((v.name, rgba));
    }
    journal.finish()?;
    crate::report::csv_out::write_csv(&out.join("frame_elaboration.csv"), &rows)?;
    let refs: Vec<(&str, &image::RgbaImage)> = images.iter().map(|(n, i)| (*n, i)).collect();
    crate::report::plot::image_grid(&out.join("frame_elaboration.png"), &refs, 5)?;
    Ok(rows)
}

/// The rows as a table.
pub fn elaboration_rows_table(rows: &[ElaborationRow]) -> String {
    let t: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.variant.clone(),
                r.units_present.to_string(),
                format!("{:.0}", r.gates_nand2),
                r.ram_bits.to_string(),
                format!("{} {:.4}", r.gpu, r.predicted_seconds),
                format!("{:.1}", r.simulation_wall_seconds),
                format!(
                    "{:.3} / {:.3} / {:.1}",
                    r.error_mean_abs, r.error_rms, r.error_max
                ),
                format!("{:.3} ≤ {:.3}", r.error_mean_abs_frame, r.error_bound),
            ]
        })
        .collect();
    crate::report::table::text_table(
        &[
            "variant",
            "units",
            "gates_nand2",
            "ram_bits",
            "predicted_s",
            "sim_wall_s",
            "error mean/rms/max (compared px)",
            "frame mean ≤ Σ passes",
        ],
        &t,
    )
}
