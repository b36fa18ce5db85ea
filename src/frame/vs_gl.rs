//! `reproduce vs-gl`: the model's frame against Mesa's llvmpipe and softpipe.
//!
//! For each shafts built-in (fig4, fig6, stage) at its own size (or `--image`), the
//! scene's OpenGL 1.3 program (`render --emit-gl`, docs/gl.md) is written, built once
//! with the system C compiler against libOSMesa and run on each Gallium driver
//! (`GALLIUM_DRIVER=llvmpipe`, `softpipe`); its framebuffer is compared with the
//! model's frame in two modes:
//!
//! * `geforce`: the scene's units as they are (the GeForce-style rounding);
//! * `mesa`: the scene's `[rounding]` set to Mesa's llvmpipe choices
//!   (`GlRounding::mesa_llvmpipe`). The shafts pipeline honours its filter and weight
//!   rounding (its samplers); its modulates round per stage, as the program draws them.
//!
//! Per row: the histogram of |Δ| over every channel value (0, 1, 2, > 2 levels), the
//! mean, RMS and largest |Δ|, a difference PNG (|Δ| × 32, saturating) and the timing:
//! the model's frame (the `render` call) and the program's draw (its pass list between
//! two `glFinish`, less the time its passes read their data files; the context, the
//! textures' loading and the PNG written are outside), on the same machine in the same
//! run, and their ratio.
//!
//! The ablation (`vs_gl_ablation.csv`) reruns fig6's model in each mode with one unit
//! switched at a time (its Mesa mode, or a wider setting where it has none) and reports
//! how much of the |Δ| against llvmpipe each switch removes.
//!
//! The Lambert shading sphere (`shading-lambert`, the shading scene whose path is
//! OpenGL 1.3: `emit_gl::sphere`) is compared the same way, at its own side (or the
//! smaller of `--image`'s two): both modes (`mesa` sets the normalisation cube's filter
//! and weight rounding), its ablation (the cube's sampler, the address unit's
//! coordinate and reciprocal widths) and its difference classes (face ties, face
//! edges, the rest).

use crate::frame::emit_gl::sphere::{model_sphere, sphere_program, SphereProgram};
use crate::frame::emit_gl::vertex::vertex_program;
use crate::frame::emit_gl::{check_exportable, program_of, write_program, Export};
use crate::frame::run::{render, Frame};
use crate::pipeline::shading::path::PathConfig;
use crate::pipeline::shading::scene_file::ShadingFile;
use crate::scene::format::Scene;
use crate::scene::rounding::GlRounding;
use rtl_model::units::texture_sampler::{FilterRounding, WeightRounding};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// The scenes compared, in the table's order.
pub const SCENES: [&str; 3] = ["fig6", "fig4", "stage"];
/// The shading sphere scenes compared (those with an OpenGL 1.3 program).
pub const SPHERE_SCENES: [&str; 7] = [
    "shading-lambert",
    "shading-oren_nayar",
    "shading-cook_torrance_metal",
    "shading-cook_torrance_dielectric",
    "shading-cook_torrance_backlit",
    "shading-ward",
    "shading-kajiya_kay",
];
/// The model's modes.
pub const MODES: [&str; 2] = ["geforce", "mesa"];
/// The Gallium drivers the program runs on.
pub const DRIVERS: [&str; 2] = ["llvmpipe", "softpipe"];
/// `vs_gl.csv`'s columns.
pub const COLUMNS: &str =
    "scene,modes,driver,exact_share,within1_share,mean_abs,rms,max,model_seconds,gl_seconds,ratio";
/// `vs_gl_ablation.csv`'s columns.
pub const ABLATION_COLUMNS: &str = "scene,modes,switch,exact_share,within1_share,over1_share,mean_abs,mean_removed,over1_removed,max";
/// The difference PNG's scale: one level shows as 32.
pub const DIFF_SCALE: u32 = 32;
/// The install line named when the tools are missing.
pub const INSTALL: &str = "apt-get install gcc libosmesa6-dev";

/// |Δ| statistics of two 8-bit RGB pictures over every channel value.
#[derive(Clone, Debug, Default)]
pub struct Diff {
    /// Per channel (r, g, b), counts at |Δ| = 0, 1, 2, > 2.
    pub hist: [[u64; 4]; 3],
    pub mean_abs: f64,
    pub rms: f64,
    pub max: u32,
    pub values: u64,
}

impl Diff {
    pub fn of(model: &[u8], gl: &[u8]) -> Diff {
        let mut d = Diff::default();
        let (mut sum, mut sq) = (0u64, 0u64);
        for (i, (a, b)) in model.iter().zip(gl).enumerate() {
            let v = u32::from(a.abs_diff(*b));
            d.hist[i % 3][v.min(3) as usize] += 1;
            sum += u64::from(v);
            sq += u64::from(v * v);
            d.max = d.max.max(v);
        }
        d.values = model.len().min(gl.len()) as u64;
        let n = d.values.max(1) as f64;
        d.mean_abs = sum as f64 / n;
        d.rms = (sq as f64 / n).sqrt();
        d
    }

    /// Counts over all channels at |Δ| = 0, 1, 2, > 2.
    pub fn total(&self) -> [u64; 4] {
        [0, 1, 2, 3].map(|k| self.hist.iter().map(|h| h[k]).sum())
    }

    fn share(&self, k: &[usize]) -> f64 {
        let t = self.total();
        k.iter().map(|&i| t[i]).sum::<u64>() as f64 / self.values.max(1) as f64
    }

    pub fn exact_share(&self) -> f64 {
        self.share(&[0])
    }

    pub fn within1_share(&self) -> f64 {
        self.share(&[0, 1])
    }

    pub fn over1_share(&self) -> f64 {
        self.share(&[2, 3])
    }

    /// The histogram as CSV: one row per channel and one for all.
    pub fn histogram_csv(&self) -> String {
        let mut s = String::from("channel,abs_0,abs_1,abs_2,abs_over_2\n");
        for (name, h) in ["r", "g", "b"].iter().zip(&self.hist) {
            let _ = writeln!(s, "{name},{},{},{},{}", h[0], h[1], h[2], h[3]);
        }
        let t = self.total();
        let _ = writeln!(s, "all,{},{},{},{}", t[0], t[1], t[2], t[3]);
        s
    }
}

/// One row of `vs_gl.csv`.
#[derive(Clone, Debug)]
pub struct Row {
    pub scene: String,
    pub modes: String,
    pub driver: String,
    pub diff: Diff,
    pub model_seconds: f64,
    pub gl_seconds: f64,
}

/// One row of `vs_gl_ablation.csv`.
#[derive(Clone, Debug)]
pub struct AblationRow {
    pub scene: String,
    pub modes: String,
    pub switch: String,
    pub diff: Diff,
    /// Mean |Δ| and share off by more than one level that the switch removes from its
    /// mode's (negative: it adds).
    pub mean_removed: f64,
    pub over1_removed: f64,
}

impl AblationRow {
    /// The row of a switch whose picture differs from GL's by `d`, against its mode's
    /// base difference `d0`.
    fn against(name: &str, mode: &str, label: &str, d0: &Diff, d: Diff) -> AblationRow {
        AblationRow {
            scene: name.into(),
            modes: mode.into(),
            switch: label.into(),
            mean_removed: d0.mean_abs - d.mean_abs,
            over1_removed: d0.over1_share() - d.over1_share(),
            diff: d,
        }
    }
}

/// What is missing to build and run the GL programs (a C compiler, libOSMesa), with the
/// install line; `None` when a probe program builds.
pub fn missing_tools() -> Option<String> {
    let cc = Command::new("cc").arg("--version").output();
    if !cc.map(|o| o.status.success()).unwrap_or(false) {
        return Some(format!(
            "no C compiler (`cc`) found; it builds the scenes' GL programs against libOSMesa ({INSTALL})"
        ));
    }
    let dir = std::env::temp_dir().join(format!("glare_vs_gl_probe_{}", std::process::id()));
    let ok = (|| -> Option<bool> {
        std::fs::create_dir_all(&dir).ok()?;
        let src = dir.join("probe.c");
        std::fs::write(
            &src,
            "#include <GL/osmesa.h>\nint main(void) { return OSMesaGetCurrentContext() != 0; }\n",
        )
        .ok()?;
        let o = Command::new("cc")
            .arg(&src)
            .arg("-o")
            .arg(dir.join("probe"))
            .args(["-lOSMesa", "-lm"])
            .output()
            .ok()?;
        Some(o.status.success())
    })()
    .unwrap_or(false);
    let _ = std::fs::remove_dir_all(&dir);
    if ok {
        None
    } else {
        Some(format!(
            "libOSMesa (GL/osmesa.h and -lOSMesa) not found: `cc` cannot build a program against it ({INSTALL})"
        ))
    }
}

/// `scene` in a mode: `geforce` (the default rounding) or `mesa` (llvmpipe's).
pub fn in_mode(scene: &Scene, mode: &str) -> Scene {
    let mut s = scene.clone();
    s.rounding = Some(if mode == "mesa" {
        GlRounding::mesa_llvmpipe()
    } else {
        GlRounding::default()
    });
    s
}

/// Times the model's frame and llvmpipe's draw are each measured in the shafts
/// scenes' rows; the median is reported. One run of either moves by a fifth or more
/// on a shared machine.
const TIMING_RUNS: usize = 3;

/// `run` (its seconds and picture) done `runs` times (at least once): the first
/// run's picture and the median seconds; every run's picture must be the first's,
/// else the error names `what`.
fn repeat_timed<T: PartialEq>(
    runs: usize,
    what: &str,
    mut run: impl FnMut() -> Result<(f64, T), String>,
) -> Result<(f64, T), String> {
    let (first, picture) = run()?;
    let mut secs = vec![first];
    for _ in 1..runs {
        let (t, again) = run()?;
        if again != picture {
            return Err(format!("{what} differs between two runs"));
        }
        secs.push(t);
    }
    secs.sort_by(f64::total_cmp);
    Ok((secs[secs.len() / 2], picture))
}

/// [`model_frame`] rendered [`TIMING_RUNS`] times, with the median time (the first
/// run's frame kept).
fn model_frame_timed(scene: &Scene, name: &str) -> Result<(Frame, Vec<u8>, f64), String> {
    let mut first = None;
    let (secs, rgb) = repeat_timed(TIMING_RUNS, &format!("{name}: the model's frame"), || {
        let (f, rgb, t) = model_frame(scene)?;
        first.get_or_insert(f);
        Ok((t, rgb))
    })?;
    let f = first.ok_or_else(|| format!("{name}: no frame rendered"))?;
    Ok((f, rgb, secs))
}

/// [`run_program`] run [`TIMING_RUNS`] times on llvmpipe (once on softpipe, whose
/// draw takes seconds and is not the speed compared), with the median draw time.
fn run_program_timed(dir: &Path, driver: &str, png: &Path) -> Result<(f64, Vec<u8>), String> {
    let runs = if driver == "llvmpipe" { TIMING_RUNS } else { 1 };
    let what = format!(
        "{}: the GL program's framebuffer on {driver}",
        dir.display()
    );
    repeat_timed(runs, &what, || run_program(dir, driver, png))
}

/// The model's frame, timed (the `render` call), and its 8-bit RGB.
fn model_frame(scene: &Scene) -> Result<(Frame, Vec<u8>, f64), String> {
    let t0 = Instant::now();
    let f = render(scene).map_err(|e| e.to_string())?;
    let secs = t0.elapsed().as_secs_f64();
    let rgb = rgb_of_rgba(&f.fb.to_rgba8());
    Ok((f, rgb, secs))
}

fn rgb_of_rgba(rgba: &[u8]) -> Vec<u8> {
    rgba.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect()
}

/// Build the program in `dir` (its build.sh).
fn build(dir: &Path) -> Result<(), String> {
    let o = Command::new("sh")
        .arg(dir.join("build.sh"))
        .output()
        .map_err(|e| format!("sh {}: {e}", dir.join("build.sh").display()))?;
    if !o.status.success() {
        return Err(format!(
            "building {} failed:\n{}",
            dir.display(),
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    Ok(())
}

/// Run the program in `dir` on `driver`, writing `png`: its draw seconds and its RGB.
fn run_program(dir: &Path, driver: &str, png: &Path) -> Result<(f64, Vec<u8>), String> {
    run_program_with(dir, driver, png, &[])
}

/// [`run_program`] with more environment variables set.
fn run_program_with(
    dir: &Path,
    driver: &str,
    png: &Path,
    env: &[(&str, &str)],
) -> Result<(f64, Vec<u8>), String> {
    let o = Command::new(dir.join("scene"))
        .arg(png)
        .current_dir(dir)
        .env("GALLIUM_DRIVER", driver)
        .envs(env.iter().copied())
        .output()
        .map_err(|e| format!("{}: {e}", dir.join("scene").display()))?;
    let out = String::from_utf8_lossy(&o.stdout);
    if !o.status.success() {
        return Err(format!(
            "{} on {driver} failed:\n{}{}",
            dir.join("scene").display(),
            out,
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    let field = |k: &str| {
        out.lines()
            .find_map(|l| l.strip_prefix(k))
            .map(str::trim)
            .map(String::from)
    };
    let renderer = field("renderer=").unwrap_or_default();
    if !renderer.to_lowercase().contains(driver) {
        return Err(format!(
            "GALLIUM_DRIVER={driver} gave the renderer '{renderer}': this libOSMesa has no {driver}"
        ));
    }
    let secs: f64 = field("draw_seconds=")
        .and_then(|v| v.parse().ok())
        .ok_or_else(|| format!("the program printed no draw_seconds line:\n{out}"))?;
    let img = image::open(png)
        .map_err(|e| format!("{}: {e}", png.display()))?
        .to_rgb8();
    Ok((secs, img.into_raw()))
}

/// The difference picture: |Δ| × [`DIFF_SCALE`] per channel, saturating.
fn diff_png(model: &[u8], gl: &[u8], w: u32, h: u32, path: &Path) -> Result<(), String> {
    let px: Vec<u8> = model
        .iter()
        .zip(gl)
        .map(|(a, b)| (u32::from(a.abs_diff(*b)) * DIFF_SCALE).min(255) as u8)
        .collect();
    image::RgbImage::from_raw(w, h, px)
        .ok_or_else(|| format!("{}: size", path.display()))?
        .save(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// The scene at the run's size, checked for export.
fn load(name: &str, size: Option<(u32, u32)>) -> Result<(Scene, Vec<Export>), String> {
    let mut s = crate::scene::load::load_scene(name)?;
    if let Some((w, h)) = size {
        s.image.width = w;
        s.image.height = h;
    }
    let exports = check_exportable(&s).map_err(|e| format!("{name}: {e}"))?;
    Ok((s, exports))
}

/// The switches of the ablation on a scene in `mode`: name and how to apply it. Each
/// is a unit's Mesa mode (where the model has one and the mode does not already use
/// it) or a wider setting of a unit that has no Mesa mode.
#[allow(clippy::type_complexity)]
pub fn switches(mode: &str) -> Vec<(String, Box<dyn Fn(&mut Scene)>)> {
    let mut v: Vec<(String, Box<dyn Fn(&mut Scene)>)> = Vec::new();
    if mode != "mesa" {
        v.push((
            "texture sampler: filter successive_lerps (Mesa)".into(),
            Box::new(|s: &mut Scene| {
                let mut r = s.rounding.unwrap_or_default();
                r.filter = FilterRounding::SuccessiveLerps;
                s.rounding = Some(r);
            }),
        ));
        v.push((
            "texture sampler: weight round_half_even (Mesa)".into(),
            Box::new(|s: &mut Scene| {
                let mut r = s.rounding.unwrap_or_default();
                r.weight = WeightRounding::RoundHalfEven;
                s.rounding = Some(r);
            }),
        ));
    }
    v.push((
        "polygon interpolator: coord_frac_bits 8 → 16".into(),
        Box::new(|s: &mut Scene| s.shafts.coord_frac_bits = s.shafts.coord_frac_bits.max(16)),
    ));
    v.push((
        "polygon interpolator: acc_frac_bits 24 → 40".into(),
        Box::new(|s: &mut Scene| s.shafts.acc_frac_bits = s.shafts.acc_frac_bits.max(40)),
    ));
    v.push((
        "projective texcoord: reciprocal 8 → 12 index bits, 16 → 24 entry bits, Newton 20 → 40 bits".into(),
        Box::new(|s: &mut Scene| {
            s.shafts.recip_index_bits = s.shafts.recip_index_bits.max(12);
            s.shafts.recip_entry_bits = s.shafts.recip_entry_bits.max(24);
            s.shafts.newton_frac_bits = s.shafts.newton_frac_bits.max(40);
        }),
    ));
    v.push((
        "texture sampler: weight_bits 8 → 16".into(),
        Box::new(|s: &mut Scene| s.shafts.weight_bits = s.shafts.weight_bits.max(16)),
    ));
    v.push((
        SHADOW_RES_SWITCH.into(),
        Box::new(|s: &mut Scene| s.shafts.shadow_resolution = s.shafts.shadow_resolution.max(2048)),
    ));
    v.push((
        "shadow compare: shadow_depth_bits 8 → 24 (GL's depth texture)".into(),
        Box::new(|s: &mut Scene| s.shafts.shadow_depth_bits = s.shafts.shadow_depth_bits.max(24)),
    ));
    v
}

/// The ablation row with every switch but the shadow map's resolution.
pub const ALL_SWITCHES: &str = "all of the above but the 2048² shadow map";

/// The switch that moves the shadow's edge: its pixels are the "shadow edge" class.
pub const SHADOW_RES_SWITCH: &str = "shadow map: shadow_resolution 512 → 2048";

/// One difference class of fig6 in a mode (`vs_gl_classes.csv`): which channel values
/// it holds and its share of the differences.
#[derive(Clone, Debug)]
pub struct ClassRow {
    pub scene: String,
    pub modes: String,
    pub class: String,
    /// Channel values in the class, of the picture's.
    pub values_share: f64,
    /// Of all channel values: those in the class off by exactly 1, and by more.
    pub abs1_share: f64,
    pub over1_share: f64,
    /// The class's part of the picture's total |Δ|.
    pub of_total_abs: f64,
}

/// `vs_gl_classes.csv`'s columns.
pub const CLASS_COLUMNS: &str =
    "scene,modes,class,values_share,abs1_share,over1_share,of_total_abs";

/// The class names, in order: each pixel is in the first that holds it.
pub const CLASSES: [&str; 3] = [
    "shadow edge (pixels the model's picture changes on when its shadow map is 2048², dilated by one)",
    "other edges (a 4-neighbour differs by more than 8 levels in the model's picture: silhouettes, the cone's edge)",
    "smooth (the rest: the rounding of interpolated colours and coordinates and of the filters)",
];

/// Split the differences between `model` and `gl` into [`CLASSES`] (`shadow`: the
/// model's picture with the shadow map at 2048²).
pub fn classes(
    name: &str,
    mode: &str,
    (w, h): (u32, u32),
    model: &[u8],
    gl: &[u8],
    shadow: &[u8],
) -> Vec<ClassRow> {
    let (w, h) = (w as usize, h as usize);
    let px = |v: &[u8], i: usize| [v[3 * i], v[3 * i + 1], v[3 * i + 2]];
    let far = |a: [u8; 3], b: [u8; 3], t: u8| (0..3).any(|c| a[c].abs_diff(b[c]) > t);
    let mut moved = vec![false; w * h];
    for (i, m) in moved.iter_mut().enumerate() {
        *m = far(px(model, i), px(shadow, i), 1);
    }
    let mut class = vec![2usize; w * h];
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let near = |f: &dyn Fn(usize) -> bool| {
                (y.saturating_sub(1)..=(y + 1).min(h - 1))
                    .any(|yy| (x.saturating_sub(1)..=(x + 1).min(w - 1)).any(|xx| f(yy * w + xx)))
            };
            if near(&|j| moved[j]) {
                class[i] = 0;
                continue;
            }
            let me = px(model, i);
            let edge = [(0i64, 1i64), (0, -1), (1, 0), (-1, 0)]
                .iter()
                .any(|&(dx, dy)| {
                    let (xx, yy) = (x as i64 + dx, y as i64 + dy);
                    xx >= 0
                        && yy >= 0
                        && (xx as usize) < w
                        && (yy as usize) < h
                        && far(me, px(model, yy as usize * w + xx as usize), 8)
                });
            if edge {
                class[i] = 1;
            }
        }
    }
    class_rows(name, mode, &CLASSES, &class, model, gl)
}

/// The rows of `vs_gl_classes.csv` for one picture: pixel i is in class `class[i]` of
/// `labels`; shares of every channel value, and of the picture's total |Δ|.
fn class_rows(
    name: &str,
    mode: &str,
    labels: &[&str],
    class: &[usize],
    model: &[u8],
    gl: &[u8],
) -> Vec<ClassRow> {
    let n = (class.len() * 3).max(1) as f64;
    let total: u64 = model
        .iter()
        .zip(gl)
        .map(|(a, b)| u64::from(a.abs_diff(*b)))
        .sum();
    (0..labels.len())
        .map(|k| {
            let (mut vals, mut one, mut over, mut sum) = (0u64, 0u64, 0u64, 0u64);
            for i in (0..class.len()).filter(|&i| class[i] == k) {
                for c in 0..3 {
                    let d = model[3 * i + c].abs_diff(gl[3 * i + c]);
                    vals += 1;
                    one += u64::from(d == 1);
                    over += u64::from(d > 1);
                    sum += u64::from(d);
                }
            }
            ClassRow {
                scene: name.into(),
                modes: mode.into(),
                class: labels[k].into(),
                values_share: vals as f64 / n,
                abs1_share: one as f64 / n,
                over1_share: over as f64 / n,
                of_total_abs: if total == 0 {
                    0.0
                } else {
                    sum as f64 / total as f64
                },
            }
        })
        .collect()
}

/// `vs_gl_classes.csv`'s text (class names are quoted: they hold commas).
pub fn classes_csv(rows: &[ClassRow]) -> String {
    let mut s = format!("{CLASS_COLUMNS}\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},\"{}\",{:.6},{:.6},{:.6},{:.6}",
            r.scene, r.modes, r.class, r.values_share, r.abs1_share, r.over1_share, r.of_total_abs
        );
    }
    s
}

/// Where a row's comparison sits: the run's directory, the scene, the mode, the
/// driver and the picture's size.
struct RowAt<'a> {
    out: &'a Path,
    name: &'a str,
    mode: &'a str,
    driver: &'a str,
    size: (u32, u32),
}

/// One row of `vs_gl.csv`: the model's picture against the driver's, its difference
/// PNG and histogram written; `seconds` the model's and the GL draw's.
fn compare_row(at: &RowAt, model: &[u8], gl: &[u8], seconds: (f64, f64)) -> Result<Row, String> {
    let diff = Diff::of(model, gl);
    let stem = row_stem(at.out, at.name, at.mode, at.driver);
    diff_png(
        model,
        gl,
        at.size.0,
        at.size.1,
        &stem.with_extension("diff.png"),
    )?;
    write(&stem.with_extension("hist.csv"), &diff.histogram_csv())?;
    Ok(Row {
        scene: at.name.to_string(),
        modes: at.mode.to_string(),
        driver: at.driver.to_string(),
        diff,
        model_seconds: seconds.0,
        gl_seconds: seconds.1,
    })
}

/// Where the run writes a row's files.
fn row_stem(out: &Path, scene: &str, mode: &str, driver: &str) -> PathBuf {
    out.join(format!("{scene}_{mode}_{driver}"))
}

/// What `reproduce vs-gl` measured: the rows, fig6's ablation and its classes.
pub type VsGl = (Vec<Row>, Vec<AblationRow>, Vec<ClassRow>);

/// `reproduce vs-gl` into `out`, at `size` (each scene's own without): the rows, and
/// fig6's ablation rows.
pub fn vs_gl(out: &Path, size: Option<(u32, u32)>) -> Result<VsGl, String> {
    if let Some(why) = missing_tools() {
        return Err(why);
    }
    // Every scene checked before any work.
    let mut loaded = Vec::new();
    for name in SCENES {
        loaded.push((name, load(name, size)?));
    }
    std::fs::create_dir_all(out).map_err(|e| format!("out: {}: {e}", out.display()))?;
    // Absolute: each program runs in its own directory, so a relative `out` would name
    // the program and its PNG from the wrong place.
    let out = &out
        .canonicalize()
        .map_err(|e| format!("out: {}: {e}", out.display()))?;
    let mut rows = Vec::new();
    let mut ablation = Vec::new();
    let mut class_rows = Vec::new();
    for (name, (scene, exports)) in &loaded {
        let (w, h) = (scene.image.width, scene.image.height);
        let dir = out.join(format!("gl_{name}"));
        // The model in each mode; the program of the first (built once: the program's
        // data do not depend on the mode's rounding, checked here).
        let mut models = Vec::new();
        let mut first_program = None;
        for mode in MODES {
            let s = in_mode(scene, mode);
            let (f, rgb, secs) = model_frame_timed(&s, name)?;
            match &first_program {
                None => {
                    let p = write_program(&f, exports, &dir)?;
                    first_program = Some(p.files);
                }
                Some(files) => {
                    if program_of(&f, exports)?.files != *files {
                        return Err(format!(
                            "{name}: the GL program's data differ between the modes"
                        ));
                    }
                }
            }
            models.push((mode, s, rgb, secs));
        }
        build(&dir)?;
        let mut gl_llvmpipe = None;
        for driver in DRIVERS {
            let png = out.join(format!("gl_{name}_{driver}.png"));
            let (gl_secs, gl) = run_program_timed(&dir, driver, &png)?;
            for (mode, _, model, model_secs) in &models {
                let at = RowAt {
                    out,
                    name,
                    mode,
                    driver,
                    size: (w, h),
                };
                rows.push(compare_row(&at, model, &gl, (*model_secs, gl_secs))?);
            }
            if driver == "llvmpipe" {
                gl_llvmpipe = Some(gl);
            }
        }
        if *name == "fig6" {
            let gl = gl_llvmpipe.ok_or("no llvmpipe frame")?;
            for (mode, s, model, _) in &models {
                let (a, c) = ablate(name, mode, s, model, &gl)?;
                ablation.extend(a);
                class_rows.extend(c);
            }
        }
    }
    for name in SPHERE_SCENES {
        let (r, a, c) = sphere_rows(name, out, size)?;
        rows.extend(r);
        ablation.extend(a);
        class_rows.extend(c);
    }
    rows.extend(vertex_rows(out)?);
    write(&out.join("vs_gl.csv"), &csv(&rows))?;
    write(&out.join("vs_gl_ablation.csv"), &ablation_csv(&ablation))?;
    write(&out.join("vs_gl_classes.csv"), &classes_csv(&class_rows))?;
    Ok((rows, ablation, class_rows))
}

/// The shading path in a mode: `geforce` (the default rounding) or `mesa`
/// (llvmpipe's filter and weight rounding in the normalisation cube's and the factor
/// textures' samplers; the factor chain stays rounded per stage, as the program draws
/// it).
fn sphere_in_mode(f: &ShadingFile, mode: &str) -> Result<ShadingFile, String> {
    let rounding = if mode == "mesa" {
        GlRounding {
            chain: GlRounding::default().chain,
            ..GlRounding::mesa_llvmpipe()
        }
    } else {
        GlRounding::default()
    };
    Ok(ShadingFile {
        point: f.point.with_path(|c| c.rounding = rounding)?,
        ..*f
    })
}

/// The sphere's unit switches of the ablation: the samplers (the normalisation
/// cube's, the factor textures') in their Mesa rounding, and the cube address unit's
/// coordinates and reciprocal wider.
type PathSwitch = (&'static str, fn(&mut PathConfig));
const SPHERE_SWITCHES: [PathSwitch; 4] = [
    (
        "samplers (cube, factors): filter successive_lerps (Mesa)",
        |c| c.rounding.filter = FilterRounding::SuccessiveLerps,
    ),
    (
        "samplers (cube, factors): weight round_half_even (Mesa)",
        |c| c.rounding.weight = WeightRounding::RoundHalfEven,
    ),
    ("cube map address: coord_frac_bits 8 → 16", |c| {
        c.cube.address.coord_frac_bits = 16
    }),
    (
        "cube map address: reciprocal 6 → 12 address bits, 8 → 24 entry bits",
        |c| {
            c.cube.address.rcp_addr_bits = 12;
            c.cube.address.rcp_bits = 24;
        },
    ),
];

/// The model's sphere in 8-bit RGB (grey levels in all three channels).
fn sphere_rgb(levels: &[f64]) -> Vec<u8> {
    levels
        .iter()
        .flat_map(|&x| [x.round().clamp(0.0, 255.0) as u8; 3])
        .collect()
}

/// A shading sphere scene's rows: its program run on each driver against the model's
/// sphere in each mode (at the scene's own side, or the smaller of `size`'s two), and
/// its ablation against llvmpipe.
fn sphere_rows(name: &str, out: &Path, size: Option<(u32, u32)>) -> Result<VsGl, String> {
    let scene = crate::scene::load::load_scene(name)?;
    let mut base = ShadingFile::from_scene(&scene)?;
    if let Some((w, h)) = size {
        base.image = Some(w.min(h));
    }
    // The program (its data do not depend on the mode's rounding) and the classes
    // once; the model's sphere in each mode.
    let dir = out.join(format!("gl_{name}"));
    let program = sphere_program(&base)?;
    program.write(&dir)?;
    let class = sphere_classes(&program);
    let side = program.side;
    let mut models = Vec::new();
    for mode in MODES {
        let f = sphere_in_mode(&base, mode)?;
        let (_, r) = model_sphere(&f)?;
        models.push((mode, f, sphere_rgb(&r.hardware), r.wall_seconds));
    }
    build(&dir)?;
    let (mut rows, mut ablation, mut class_rows_out) = (Vec::new(), Vec::new(), Vec::new());
    for driver in DRIVERS {
        let png = out.join(format!("gl_{name}_{driver}.png"));
        let (gl_secs, gl) = run_program(&dir, driver, &png)?;
        for (mode, f, model, model_secs) in &models {
            let at = RowAt {
                out,
                name,
                mode,
                driver,
                size: (side, side),
            };
            let row = compare_row(&at, model, &gl, (*model_secs, gl_secs))?;
            if driver == "llvmpipe" {
                ablation.extend(sphere_ablation(name, mode, f, &row.diff, &gl)?);
                class_rows_out.extend(class_rows(name, mode, &SPHERE_CLASSES, &class, model, &gl));
            }
            rows.push(row);
        }
    }
    Ok((rows, ablation, class_rows_out))
}

/// `shading-vertex`'s rows: the vertices lit by GL's fixed-function lighting against
/// the model's vertex_lighting unit (its e8m23 floats; it has no Mesa mode), as a
/// rings × segments picture of vertex colours. On softpipe the program runs with
/// `DRAW_USE_LLVM=0`: Mesa 22.3's LLVM vertex path crashes compiling softpipe's
/// fixed-function lighting in feedback mode (llvmpipe's does not).
fn vertex_rows(out: &Path) -> Result<Vec<Row>, String> {
    let name = "shading-vertex";
    let scene = crate::scene::load::load_scene(name)?;
    let f = ShadingFile::from_scene(&scene)?;
    let p = vertex_program(&f)?;
    let dir = out.join(format!("gl_{name}"));
    p.write(&dir)?;
    build(&dir)?;
    let model = rgb_of_rgba(&p.model.to_rgba8());
    let mut rows = Vec::new();
    for driver in DRIVERS {
        let png = out.join(format!("gl_{name}_{driver}.png"));
        let env: &[(&str, &str)] = if driver == "softpipe" {
            &[("DRAW_USE_LLVM", "0")]
        } else {
            &[]
        };
        let (gl_secs, gl) = run_program_with(&dir, driver, &png, env)?;
        let at = RowAt {
            out,
            name,
            mode: "geforce",
            driver,
            size: (p.model.width, p.model.height),
        };
        rows.push(compare_row(&at, &model, &gl, (p.model_seconds, gl_secs))?);
    }
    Ok(rows)
}

/// Where a sphere's differences can sit, by the normal's cube-map lookup.
pub const SPHERE_CLASSES: [&str; 3] = [
    "face tie (the normal's two largest components equal in magnitude: which face is read is left to the implementation)",
    "face edge (the normal's lookup within one texel of its face's edge, where the filter clamps)",
    "rest (the cube faces' interiors, the factored lobe, the background)",
];

/// Each pixel's class of [`SPHERE_CLASSES`]; every pixel is in the rest when the
/// sphere has no Lambert term (no cube lookup).
fn sphere_classes(p: &SphereProgram) -> Vec<usize> {
    let side = p.side as usize;
    let mut class = vec![2; side * side];
    let Some(face) = p.face else {
        return class;
    };
    let f = f64::from(face);
    for ([x, y], d) in &p.normals {
        let mut m = d.map(f64::abs);
        m.sort_by(f64::total_cmp);
        let (_, st) = crate::reference::cube_map_address::face_st(*d, f);
        let edge = st.iter().any(|&v| v < 1.0 || v > f - 1.0);
        class[*y as usize * side + *x as usize] = if m[1] == m[2] {
            0
        } else if edge {
            1
        } else {
            2
        };
    }
    class
}

/// The sphere's ablation in one mode against llvmpipe's picture `gl`: each switch
/// alone, then all of them.
fn sphere_ablation(
    name: &str,
    mode: &str,
    f: &ShadingFile,
    d0: &Diff,
    gl: &[u8],
) -> Result<Vec<AblationRow>, String> {
    let row = |label: &str, d: Diff| AblationRow::against(name, mode, label, d0, d);
    let mut rows = vec![row("none", d0.clone())];
    let mut all = *f;
    for (label, apply) in SPHERE_SWITCHES {
        let one = ShadingFile {
            point: f.point.with_path(apply)?,
            ..*f
        };
        all.point = all.point.with_path(apply)?;
        let (_, r) = model_sphere(&one)?;
        rows.push(row(label, Diff::of(&sphere_rgb(&r.hardware), gl)));
    }
    let (_, r) = model_sphere(&all)?;
    rows.push(row(
        "all of the above",
        Diff::of(&sphere_rgb(&r.hardware), gl),
    ));
    Ok(rows)
}

/// fig6's ablation in one mode against llvmpipe's frame `gl`.
fn ablate(
    name: &str,
    mode: &str,
    base: &Scene,
    model: &[u8],
    gl: &[u8],
) -> Result<(Vec<AblationRow>, Vec<ClassRow>), String> {
    let d0 = Diff::of(model, gl);
    let mut rows = vec![AblationRow::against(name, mode, "none", &d0, d0.clone())];
    let sw = switches(mode);
    let mut all = base.clone();
    let mut shadow = None;
    for (label, apply) in &sw {
        let mut s = base.clone();
        apply(&mut s);
        // The 2048² shadow map is the shadow edge's probe, not a match: GL's is the
        // scene's size, as the model's.
        if label != SHADOW_RES_SWITCH {
            apply(&mut all);
        }
        let (row, rgb) = switched(name, mode, label, &s, &d0, gl)?;
        rows.push(row);
        if label == SHADOW_RES_SWITCH {
            shadow = Some(rgb);
        }
    }
    rows.push(switched(name, mode, ALL_SWITCHES, &all, &d0, gl)?.0);
    let shadow = shadow.ok_or("no shadow-map switch")?;
    let size = (base.image.width, base.image.height);
    Ok((rows, classes(name, mode, size, model, gl, &shadow)))
}

fn switched(
    name: &str,
    mode: &str,
    label: &str,
    s: &Scene,
    d0: &Diff,
    gl: &[u8],
) -> Result<(AblationRow, Vec<u8>), String> {
    s.validate().map_err(|e| format!("ablation {label}: {e}"))?;
    let (_, rgb, _) = model_frame(s)?;
    let d = Diff::of(&rgb, gl);
    Ok((AblationRow::against(name, mode, label, d0, d), rgb))
}

fn write(path: &Path, text: &str) -> Result<(), String> {
    crate::report::image_out::write_file(path, text.as_bytes())
}

/// `vs_gl.csv`'s text.
pub fn csv(rows: &[Row]) -> String {
    let mut s = format!("{COLUMNS}\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{:.6},{:.6},{:.6},{:.6},{},{:.6},{:.6},{:.2}",
            r.scene,
            r.modes,
            r.driver,
            r.diff.exact_share(),
            r.diff.within1_share(),
            r.diff.mean_abs,
            r.diff.rms,
            r.diff.max,
            r.model_seconds,
            r.gl_seconds,
            r.model_seconds / r.gl_seconds
        );
    }
    s
}

/// `vs_gl_ablation.csv`'s text (switch names are quoted: they hold commas).
pub fn ablation_csv(rows: &[AblationRow]) -> String {
    let mut s = format!("{ABLATION_COLUMNS}\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},\"{}\",{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{}",
            r.scene,
            r.modes,
            r.switch,
            r.diff.exact_share(),
            r.diff.within1_share(),
            r.diff.over1_share(),
            r.diff.mean_abs,
            r.mean_removed,
            r.over1_removed,
            r.diff.max
        );
    }
    s
}

/// The printed tables.
pub fn table(rows: &[Row], ablation: &[AblationRow]) -> String {
    let mut s = String::from(
        "scene            modes    driver    exact %  within 1 %  mean |Δ|   rms    max  model s   GL draw s  ratio\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{:<16} {:<8} {:<9} {:>7.3} {:>11.3} {:>9.4} {:>6.3} {:>5} {:>8.3} {:>11.4} {:>6.2}",
            r.scene,
            r.modes,
            r.driver,
            100.0 * r.diff.exact_share(),
            100.0 * r.diff.within1_share(),
            r.diff.mean_abs,
            r.diff.rms,
            r.diff.max,
            r.model_seconds,
            r.gl_seconds,
            r.model_seconds / r.gl_seconds
        );
    }
    if !ablation.is_empty() {
        let _ = writeln!(
            s,
            "\nablation against llvmpipe (one switch at a time on the mode's model):\nscene            modes    switch                                                   exact %  > 1 %   mean |Δ|  removed (mean, > 1 share)"
        );
        for r in ablation {
            let _ = writeln!(
                s,
                "{:<16} {:<8} {:<56} {:>7.3} {:>6.3} {:>9.4}  {:+.4}, {:+.4} %",
                r.scene,
                r.modes,
                r.switch,
                100.0 * r.diff.exact_share(),
                100.0 * r.diff.over1_share(),
                r.diff.mean_abs,
                r.mean_removed,
                100.0 * r.over1_removed
            );
        }
    }
    s
}

/// `reproduce vs-gl [--image WxH]`.
pub fn vs_gl_cli(out: &Path, image: Option<&str>) -> Result<(), String> {
    let size = image
        .map(crate::report::image_arg::parse_image)
        .transpose()?;
    let (rows, ablation, class_rows) = vs_gl(out, size)?;
    print!("{}", table(&rows, &ablation));
    println!("\nthe differences against llvmpipe by where they sit (shares of every channel value):\nscene            modes    |Δ| = 1 %  > 1 %   of the total |Δ|  class");
    for c in &class_rows {
        println!(
            "{:<16} {:<8} {:>9.3} {:>6.3} {:>15.1} %  {}",
            c.scene,
            c.modes,
            100.0 * c.abs1_share,
            100.0 * c.over1_share,
            100.0 * c.of_total_abs,
            c.class
        );
    }
    Ok(())
}
