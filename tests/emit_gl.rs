//! `render --emit-gl DIR`: the shafts built-ins (fig6, fig4, stage) at 96 × 64, the
//! Lambert and a factored shading sphere at 64 × 64 (their own bounds:
//! [`SPHERE_LIMITS`]), the test scene and the vertex-lighting sphere at their own
//! sizes, written
//! as GL 1.3 C programs, compiled with `cc … -lOSMesa -lm` and run on Mesa's llvmpipe
//! (`GALLIUM_DRIVER=llvmpipe`). Each must exit 0 and write a framebuffer.png of its size
//! that is not blank and agrees loosely with the model's model.png written beside it:
//! mean |Δ| over the channel values below [`MEAN_LIMIT`] and at least
//! [`WITHIN_ONE_MIN`] of them within one level (the histogram of |Δ| 0 / 1 / 2 / > 2 is
//! printed). Measured at 96 × 64 on llvmpipe (Mesa 22.3): mean |Δ| 0.060 (fig6), 0.042
//! (fig4), 0.119 (stage); within one level 99.66 %, 99.64 %, 99.38 %. What is left is
//! the bilinear filters' and the interpolators' rounding, the shadow map's depth
//! precision (a few pixels on the sphere's terminator differ by tens of levels) and
//! the pixels on shared triangle edges; a pass drawn wrong or left out moves whole
//! regions by tens of levels (the fig6 program without its planes pass: mean |Δ| 24.6
//! levels), and the modulates fused into one rounding (one draw per plane, as the
//! program first drew them) gave a mean of 0.198 and 96.3 % within one level on fig6.
//!
//! Without `cc` or libOSMesa the test prints a SKIP note on stderr and passes; under
//! `.ci/run` (`GLARE_REQUIRE_TOOLS`) it fails naming the install line.

#[path = "common/tools.rs"]
mod tools;

use std::path::{Path, PathBuf};
use std::process::Command;

/// Largest mean |Δ| (8-bit levels over every channel value) accepted: about 1.5× the
/// largest measured (stage, 0.119); the fused chain's 0.198 on fig6 fails it.
const MEAN_LIMIT: f64 = 0.18;
/// Smallest fraction of channel values within one level accepted (measured ≥ 99.38 %;
/// the fused chain's 96.3 % fails it).
const WITHIN_ONE_MIN: f64 = 0.985;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("emit_gl_{name}"));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn rgb(path: &Path) -> (u32, u32, Vec<u8>) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8();
    (img.width(), img.height(), img.into_raw())
}

/// Emit, build and run a shafts `scene` at 96 × 64; compare with model.png.
fn emit_build_run(scene: &str) {
    emit_build_run_at(scene, (96, 64), (MEAN_LIMIT, WITHIN_ONE_MIN));
}

/// Emit, build and run `scene` at `size`; compare with model.png: the mean |Δ| below
/// `limits.0`, at least `limits.1` of the channel values within one level.
fn emit_build_run_at(scene: &str, size: (u32, u32), limits: (f64, f64)) {
    emit_build_run_sized(scene, Some(size), size, limits);
}

/// [`emit_build_run_at`] with `--image` given (`image`) or not (the scene's own size,
/// `size`).
fn emit_build_run_sized(
    scene: &str,
    image: Option<(u32, u32)>,
    size: (u32, u32),
    limits: (f64, f64),
) {
    let (mean_limit, within_one_min) = limits;
    let image_args = match image {
        Some((w, h)) => vec!["--image".to_string(), format!("{w}x{h}")],
        None => Vec::new(),
    };
    let image = format!("{}x{}", size.0, size.1);
    if !tools::osmesa_toolchain(&scratch("probe")) {
        tools::skip(&format!(
            "cc or libOSMesa not found; the {scene} GL program was not built \
             (apt-get install gcc libosmesa6-dev)"
        ));
        return;
    }
    let dir = scratch(scene);
    let out = bin()
        .args(["render", "--scene", scene])
        .args(&image_args)
        .arg("--emit-gl")
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "emit {scene}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    for f in ["scene.c", "build.sh", "model.png"] {
        assert!(dir.join(f).is_file(), "{scene}: no {f}");
    }
    let build = Command::new("sh")
        .arg(dir.join("build.sh"))
        .output()
        .unwrap();
    assert!(
        build.status.success(),
        "{scene}: build.sh failed:\n{}",
        String::from_utf8_lossy(&build.stderr)
    );
    let run = Command::new(dir.join("scene"))
        .current_dir(&dir)
        .env("GALLIUM_DRIVER", "llvmpipe")
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{scene}: the program failed:\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let (w, h, gl) = rgb(&dir.join("framebuffer.png"));
    assert_eq!((w, h), size, "{scene}: framebuffer size");
    let (mw, mh, model) = rgb(&dir.join("model.png"));
    assert_eq!((mw, mh), size, "{scene}: model.png size");
    let lit = gl.iter().filter(|&&v| v > 8).count();
    assert!(
        lit > gl.len() / 20,
        "{scene}: the GL framebuffer is (nearly) blank: {lit} of {} channel values above 8",
        gl.len()
    );
    let mut hist = [0usize; 4];
    let mut sum = 0u64;
    for (a, b) in gl.iter().zip(&model) {
        let d = a.abs_diff(*b) as usize;
        sum += d as u64;
        hist[d.min(3)] += 1;
    }
    let n = gl.len() as f64;
    let mean = sum as f64 / n;
    let within_one = (hist[0] + hist[1]) as f64 / n;
    eprintln!(
        "{scene} {image}, model vs llvmpipe: mean |d| {mean:.3}; |d| 0/1/2/>2: {:.4} {:.4} {:.4} {:.4}",
        hist[0] as f64 / n,
        hist[1] as f64 / n,
        hist[2] as f64 / n,
        hist[3] as f64 / n
    );
    assert!(
        mean < mean_limit,
        "{scene}: mean |d| {mean:.3} ≥ {mean_limit}"
    );
    assert!(
        within_one >= within_one_min,
        "{scene}: only {:.2} % of channel values within one level",
        within_one * 100.0
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn fig6_runs_on_llvmpipe_and_agrees_with_the_model() {
    emit_build_run("fig6");
}

#[test]
fn fig4_runs_on_llvmpipe_and_agrees_with_the_model() {
    emit_build_run("fig4");
}

#[test]
fn stage_runs_on_llvmpipe_and_agrees_with_the_model() {
    emit_build_run("stage");
}

/// The Lambert sphere's bounds: its model.png is the GeForce mode, whose normalisation
/// cube filters with product weights where llvmpipe lerps (`reproduce vs-gl` holds the
/// Mesa mode to bit-exactness). Measured at 64 × 64 on llvmpipe (Mesa 22.3.6): mean
/// |Δ| 0.168, 97.19 % within one level; the bounds about 1.5× the mean and 0.7 % below
/// the share. A stage left out moves the sphere by tens of levels.
const SPHERE_LIMITS: (f64, f64) = (0.25, 0.965);

#[test]
fn the_lambert_sphere_runs_on_llvmpipe_and_agrees_with_the_model() {
    emit_build_run_at("shading-lambert", (64, 64), SPHERE_LIMITS);
}

/// A factored lobe over the Lambert term (the Cook–Torrance dielectric: both terms,
/// the factor textures, the constant colour, the scale, the saturating add). Measured
/// at 64 × 64: mean |Δ| 0.040, 99.78 % within one level; the Lambert sphere's bounds
/// hold it with room.
#[test]
fn a_factored_sphere_runs_on_llvmpipe_and_agrees_with_the_model() {
    emit_build_run_at("shading-cook_torrance_dielectric", (64, 64), SPHERE_LIMITS);
}

/// The foundation test scene at its fixed 320 × 240. Measured on llvmpipe (Mesa
/// 22.3.6): mean |Δ| 0.119, 98.76 % within one level (the filters' and the Lambert
/// term's rounding, the checker's cell seams, the shadow's edge at GL's 24-bit depth
/// against the model's 16); the bounds about 1.5× the mean and 0.76 % below the share.
/// Without its spot pass the picture is off by tens of levels over the spot.
const TEST_SCENE_LIMITS: (f64, f64) = (0.18, 0.98);

#[test]
fn the_foundation_test_scene_runs_on_llvmpipe_and_agrees_with_the_model() {
    emit_build_run_sized("test", None, (320, 240), TEST_SCENE_LIMITS);
}

/// The vertex-lighting sphere's colours (lit by GL's fixed-function lighting, read back
/// in feedback mode) as a 96 × 48 picture: measured bit-exact on llvmpipe (Mesa 22.3.6);
/// the bounds allow a level on a few vertices (a rounding tie in float32).
#[test]
fn the_vertex_lighting_sphere_runs_on_llvmpipe_and_agrees_with_the_model() {
    emit_build_run_sized("shading-vertex", None, (96, 48), (0.01, 0.999));
}

#[test]
fn shading_scenes_with_no_gl_program_are_refused_with_why() {
    for (scene, why) in [
        ("shading-blinn_phong", "dependent texture read"),
        ("shading-specular", "NV_register_combiners"),
        ("shading-phong", "dependent texture read"),
    ] {
        let dir = scratch(scene);
        let out = bin()
            .args(["render", "--scene", scene, "--emit-gl"])
            .arg(&dir)
            .output()
            .unwrap();
        assert!(!out.status.success(), "{scene} was exported");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(why), "{scene}: {err}");
        assert!(!dir.join("scene.c").exists(), "{scene}: nothing written");
    }
}

#[test]
fn a_scene_with_no_gl_pass_is_refused_naming_the_pass() {
    let dir = scratch("glare");
    let out = bin()
        .args(["render", "--scene", "glare-point", "--emit-gl"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("glare") && err.contains("no OpenGL"), "{err}");
    assert!(!dir.join("scene.c").exists(), "nothing written");
}

#[test]
fn an_unwritable_dir_is_refused_before_any_work() {
    let d = scratch("file");
    std::fs::create_dir_all(&d).unwrap();
    let file = d.join("a_file");
    std::fs::write(&file, b"x").unwrap();
    let out = bin()
        .args(["render", "--scene", "fig6", "--emit-gl"])
        .arg(&file)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("emit-gl"), "{err}");
}

#[test]
fn a_scene_the_gl_program_cannot_draw_is_refused_naming_the_field() {
    let d = scratch("bits");
    std::fs::create_dir_all(&d).unwrap();
    let toml = bin().args(["scene", "fig4"]).output().unwrap();
    let text = String::from_utf8(toml.stdout)
        .unwrap()
        .replace("texel_bits = 8", "texel_bits = 10");
    let scene = d.join("fig4_10bit.toml");
    std::fs::write(&scene, text).unwrap();
    let out = bin()
        .args(["render", "--scene"])
        .arg(&scene)
        .args(["--image", "48x32", "--emit-gl"])
        .arg(d.join("out"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("shafts.texel_bits"), "{err}");
    assert!(!d.join("out").join("scene.c").exists());
}

#[test]
fn a_mixed_scene_exports_its_gl_passes_and_lists_the_rest() {
    let dir = scratch("night_street");
    let out = bin()
        .args([
            "render",
            "--scene",
            "night-street",
            "--image",
            "96x64",
            "--emit-gl",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let c = std::fs::read_to_string(dir.join("scene.c")).unwrap();
    let header = &c[..c.find("*/").unwrap()];
    for pass in ["glare", "objects (shading units"] {
        assert!(
            err.lines()
                .any(|l| l.contains("not exported") && l.contains(pass)),
            "stderr does not list {pass}: {err}"
        );
        assert!(header.contains(pass), "the header does not list {pass}");
    }
    // The shafts passes are exported, each a function called from main.
    for f in ["pass_depth();", "pass_planes_0();", "pass_planes_1();"] {
        assert!(c.contains(f), "main does not call {f}");
    }
    assert!(dir.join("model.png").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}
