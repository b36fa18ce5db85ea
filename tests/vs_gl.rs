//! `reproduce vs-gl --image 96x64`: the model's frames of fig6, fig4 and stage, and the
//! shading spheres with an OpenGL 1.3 form (64 × 64, the smaller side), against their
//! OpenGL programs on Mesa's llvmpipe and softpipe (OSMesa). It must write vs_gl.csv
//! with exactly its columns, a row per scene × mode × driver, a difference PNG and a
//! histogram CSV per row, fig6's and the spheres' ablation and classes, and the fig6
//! and fig4 rows of the model's Mesa-matching mode on llvmpipe must be within one
//! level on at least [`WITHIN_ONE_MIN`] of the channel values, the spheres' bit-exact
//! on at least [`SPHERE_EXACT_MIN`].
//!
//! Measured at 96 × 64 (llvmpipe, Mesa 22.3.6): fig6 mesa 99.647 % within one level,
//! fig4 mesa 99.609 % (docs/results.md, "Against real GL"). The margin: 0.5 % below the
//! lower of the two, so 99.1 %; the fused modulate chain the program first drew
//! (docs/gl.md: 96.3 % on fig6) fails it. The shading spheres at 64 × 64, mesa mode:
//! Lambert 99.634 % exact, the Cook–Torrance dielectric 99.951 %, the five other
//! factored spheres 100 % (geforce: 86.2 % … 99.2 %, the samplers' product-weight
//! filter); the vertex-lighting sphere's colours 100 % (one mode); the bound 99.0 %.
//!
//! Without `cc` or libOSMesa the test prints a SKIP note on stderr and passes; under
//! `.ci/run` (`GLARE_REQUIRE_TOOLS`) it fails naming the install line.

#[path = "common/tools.rs"]
mod tools;

use std::path::{Path, PathBuf};
use std::process::Command;

/// Smallest share of channel values within one level of llvmpipe's, for the
/// Mesa-matching mode at 96 × 64 (measured, less a margin: module notes).
const WITHIN_ONE_MIN: f64 = 0.991;
/// Smallest bit-exact share of a shading sphere's Mesa-matching mode on llvmpipe at
/// 64 × 64 (measured ≥ 99.634 %, less a margin; the GeForce modes, 86.2 % … 98.8 %,
/// fail it, but for Ward's 99.194 %).
const SPHERE_EXACT_MIN: f64 = 0.99;
/// The vertex-lighting sphere: its vertex colours as a 96 × 48 picture, one mode.
const VERTEX_SCENE: (&str, (u32, u32)) = ("shading-vertex", (96, 48));
/// The scenes in both modes, and the size of their pictures at `--image 96x64`.
const SCENES: [(&str, (u32, u32)); 10] = [
    ("fig6", (96, 64)),
    ("fig4", (96, 64)),
    ("stage", (96, 64)),
    ("shading-lambert", (64, 64)),
    ("shading-oren_nayar", (64, 64)),
    ("shading-cook_torrance_metal", (64, 64)),
    ("shading-cook_torrance_dielectric", (64, 64)),
    ("shading-cook_torrance_backlit", (64, 64)),
    ("shading-ward", (64, 64)),
    ("shading-kajiya_kay", (64, 64)),
];

const COLUMNS: [&str; 11] = [
    "scene",
    "modes",
    "driver",
    "exact_share",
    "within1_share",
    "mean_abs",
    "rms",
    "max",
    "model_seconds",
    "gl_seconds",
    "ratio",
];

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("vs_gl_{name}"));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn vs_gl_writes_its_table_pngs_and_histograms_and_the_mesa_mode_agrees() {
    if !tools::osmesa_toolchain(&scratch("probe")) {
        tools::skip(
            "cc or libOSMesa not found; reproduce vs-gl was not run \
             (apt-get install gcc libosmesa6-dev)",
        );
        return;
    }
    let out = scratch("run");
    // `--out` relative to the working directory, as a user types it: each GL program
    // runs in its own directory, which must not change what the path names.
    let o = bin()
        .current_dir(env!("CARGO_TARGET_TMPDIR"))
        .args(["reproduce", "vs-gl", "--image", "96x64", "--out"])
        .arg(out.file_name().unwrap())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "reproduce vs-gl failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    eprintln!("{stdout}");
    let csv = std::fs::read_to_string(out.join("vs_gl.csv")).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(head, COLUMNS, "vs_gl.csv's columns");
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(
        rows.len(),
        SCENES.len() * 2 * 2 + 2,
        "a row per scene × mode × driver (`shading-vertex`: one mode, its float format is GL's float32)"
    );
    let num = |r: &[&str], c: &str| -> f64 {
        let i = COLUMNS.iter().position(|&x| x == c).unwrap();
        r[i].parse()
            .unwrap_or_else(|e| panic!("{c} = '{}': {e}", r[i]))
    };
    for r in &rows {
        assert_eq!(r.len(), COLUMNS.len(), "{r:?}");
        let stem = format!("{}_{}_{}", r[0], r[1], r[2]);
        for f in [format!("{stem}.diff.png"), format!("{stem}.hist.csv")] {
            assert!(out.join(&f).is_file(), "no {f}");
        }
        let img = image::open(out.join(format!("{stem}.diff.png")))
            .unwrap()
            .to_rgb8();
        let (_, (w, h)) = SCENES
            .iter()
            .chain(&[VERTEX_SCENE])
            .find(|s| s.0 == r[0])
            .expect("a known scene");
        assert_eq!(img.dimensions(), (*w, *h), "{stem}: difference PNG size");
        // The histogram's counts cover every channel value of the picture.
        let hist = std::fs::read_to_string(out.join(format!("{stem}.hist.csv"))).unwrap();
        let all: u64 = hist
            .lines()
            .find(|l| l.starts_with("all,"))
            .unwrap()
            .split(',')
            .skip(1)
            .map(|v| v.parse::<u64>().unwrap())
            .sum();
        assert_eq!(all, u64::from(w * h * 3), "{stem}: histogram total");
        let (exact, within) = (num(r, "exact_share"), num(r, "within1_share"));
        assert!(
            (0.0..=1.0).contains(&exact) && exact <= within && within <= 1.0,
            "{r:?}"
        );
        assert!(
            num(r, "model_seconds") > 0.0 && num(r, "gl_seconds") > 0.0,
            "{r:?}"
        );
        let ratio = num(r, "model_seconds") / num(r, "gl_seconds");
        assert!(
            (num(r, "ratio") - ratio).abs() <= 0.01 * ratio + 0.01,
            "{r:?}: ratio"
        );
        if r[1] == "mesa" && r[2] == "llvmpipe" && (r[0] == "fig6" || r[0] == "fig4") {
            assert!(
                within >= WITHIN_ONE_MIN,
                "{}: {:.3} % within one level of llvmpipe (< {:.1} %)",
                r[0],
                100.0 * within,
                100.0 * WITHIN_ONE_MIN
            );
        }
        let mesa_or_vertex = r[1] == "mesa" || r[0] == VERTEX_SCENE.0;
        if mesa_or_vertex && r[2] == "llvmpipe" && r[0].starts_with("shading-") {
            assert!(
                exact >= SPHERE_EXACT_MIN,
                "{}: {:.3} % bit-exact with llvmpipe (< {:.1} %)",
                r[0],
                100.0 * exact,
                100.0 * SPHERE_EXACT_MIN
            );
        }
    }
    // fig6's and the sphere's ablation: a baseline and the switches for each mode.
    let abl = std::fs::read_to_string(out.join("vs_gl_ablation.csv")).unwrap();
    for mode in ["geforce", "mesa"] {
        assert!(
            abl.lines()
                .any(|l| l.starts_with(&format!("shading-lambert,{mode},"))
                    && l.contains("successive_lerps")),
            "{abl}"
        );
        assert!(
            abl.lines()
                .any(|l| l.starts_with(&format!("fig6,{mode},\"none\""))),
            "{abl}"
        );
        assert!(
            abl.lines().any(|l| l.starts_with(&format!("fig6,{mode},"))
                && l.contains("shadow_depth_bits")),
            "{abl}"
        );
    }
    let classes = std::fs::read_to_string(out.join("vs_gl_classes.csv")).unwrap();
    for (scene, mode) in ["fig6", "shading-lambert"]
        .iter()
        .flat_map(|s| ["geforce", "mesa"].map(|m| (*s, m)))
    {
        // The classes split the whole picture and the whole |Δ|.
        let (mut values, mut of_total) = (0.0, 0.0);
        for l in classes
            .lines()
            .filter(|l| l.starts_with(&format!("{scene},{mode},")))
        {
            let f: Vec<f64> = l
                .rsplit(',')
                .take(4)
                .map(|v| v.parse::<f64>().unwrap())
                .collect();
            // Reversed: of_total_abs, over1_share, abs1_share, values_share.
            of_total += f[0];
            values += f[3];
        }
        assert!(
            (values - 1.0).abs() < 1e-5,
            "{scene} {mode}: classes cover {values}"
        );
        assert!(
            (of_total - 1.0).abs() < 1e-5,
            "{scene} {mode}: classes hold {of_total} of |Δ|"
        );
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn vs_gl_refuses_a_bad_image_size_before_any_work() {
    let out = scratch("bad");
    let o = bin()
        .args(["reproduce", "vs-gl", "--image", "96by64", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--image"), "{err}");
    assert!(!out.exists(), "nothing written");
}
