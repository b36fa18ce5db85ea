//! `sweep`, `attribute` and `optimize` on frame scenes (several pipelines in one
//! frame): each measures the whole frame against its composed reference, names its
//! params by pipeline, and attributes every pipeline's sources.

use glare_pipeline::frame::sweep::{pipeline_param_names, resolve_param, FRAME_PARAMS};
use glare_pipeline::scene::load::load_scene;
use std::path::Path;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
}

fn temp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("frame_tools_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// The CSV's rows as (column → value) maps.
fn csv_rows(path: &Path) -> Vec<std::collections::BTreeMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let head: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    lines
        .map(|l| {
            head.iter()
                .cloned()
                .zip(l.split(',').map(str::to_string))
                .collect()
        })
        .collect()
}

#[test]
fn frame_params_are_every_pipelines_params() {
    let table: Vec<String> = FRAME_PARAMS.iter().map(|(_, _, q)| q.to_string()).collect();
    assert_eq!(table, pipeline_param_names());
    for (p, f, q) in FRAME_PARAMS {
        assert_eq!(format!("{p}.{f}"), *q);
    }
}

#[test]
fn a_name_two_pipelines_share_is_refused_naming_both() {
    let s = load_scene("street-light").unwrap();
    let e = resolve_param(&s, "fb_bits").unwrap_err();
    assert!(e.starts_with("param:"), "{e}");
    assert!(
        e.contains("shafts.fb_bits") && e.contains("glare.fb_bits"),
        "{e}"
    );
    assert_eq!(
        resolve_param(&s, "planes").unwrap().qualified(),
        "shafts.planes"
    );
    assert_eq!(
        resolve_param(&s, "glare.hw.fb_bits").unwrap().qualified(),
        "glare.fb_bits"
    );
    let e = resolve_param(&s, "plane").unwrap_err();
    assert!(e.contains("did you mean shafts.planes?"), "{e}");
    // Through the CLI: refused before anything is written.
    let out = temp("ambiguous");
    let o = bin()
        .args([
            "sweep",
            "--scene",
            "street-light",
            "--param",
            "fb_bits",
            "--values",
            "6,8",
        ])
        .args(["--image", "48x32", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("glare.fb_bits"));
    assert!(!out.exists(), "the refused sweep created {}", out.display());
}

/// `sweep --scene shaded-metal --param fb_bits` measured the glare pass alone without
/// the shading pass that finds its highlight, and printed 0 error and 0 gates.
#[test]
fn sweep_on_a_shaded_glare_scene_measures_the_frame() {
    let out = temp("sweep");
    let o = bin()
        .args([
            "sweep",
            "--scene",
            "shaded-metal",
            "--param",
            "fb_bits",
            "--values",
            "4,8",
        ])
        .args(["--image", "64x48", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = csv_rows(&out.join("sweep_glare.fb_bits.csv"));
    assert_eq!(rows.len(), 2);
    let num = |r: &std::collections::BTreeMap<String, String>, k: &str| -> f64 {
        r.iter()
            .find(|(c, _)| c.starts_with(k))
            .unwrap_or_else(|| panic!("no column {k} in {r:?}"))
            .1
            .parse()
            .unwrap()
    };
    for r in &rows {
        for k in ["mean_abs", "rms", "max", "predicted", "gates", "ram_bits"] {
            assert!(num(r, k) > 0.0, "{k} = 0 in {r:?}");
        }
    }
    assert!(
        num(&rows[0], "mean_abs") > num(&rows[1], "mean_abs"),
        "a 4-bit framebuffer is not worse than 8 bits: {rows:?}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// The attribution of a frame scene lists sources of every pipeline its frame runs.
#[test]
fn frame_attribution_has_every_pipelines_sources() {
    use glare_pipeline::frame::attribute::sources;
    let night = load_scene("night-street").unwrap();
    let names: Vec<String> = sources(&night)
        .unwrap()
        .into_iter()
        .map(|s| s.name)
        .collect();
    for p in ["shafts: ", "shading: ", "environment: ", "glare: "] {
        assert!(
            names.iter().any(|n| n.starts_with(p)),
            "no {p}source in {names:?}"
        );
    }
    assert!(names.iter().any(|n| n == "shafts: table scaling (h cap)"));
    // A small run: shaded-metal's error is the frame's, attributed to its shading
    // and glare sources.
    let out = temp("attribute");
    let o = bin()
        .args([
            "attribute",
            "--scene",
            "shaded-metal",
            "--image",
            "48x32",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = csv_rows(&out.join("attribution.csv"));
    let source = |r: &std::collections::BTreeMap<String, String>| {
        r.iter()
            .find(|(c, _)| c.as_str() == "source")
            .map(|(_, v)| v.clone())
            .unwrap()
    };
    let configured = rows.iter().find(|r| source(r) == "configured").unwrap();
    let mean: f64 = configured
        .iter()
        .find(|(c, _)| c.starts_with("mean"))
        .unwrap()
        .1
        .parse()
        .unwrap();
    assert!(mean > 0.0, "configured error 0: {configured:?}");
    for p in ["shading: ", "glare: "] {
        assert!(rows.iter().any(|r| source(r).starts_with(p)), "no {p}row");
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// `optimize` on a frame scene searches every pipeline's widths and measures them.
#[test]
fn optimize_on_a_frame_scene_measures_gates_and_error() {
    let out = temp("optimize");
    let o = bin()
        .args([
            "optimize",
            "--scene",
            "shaded-metal",
            "--budget",
            "max<=255",
        ])
        .args(["--max-evals", "2", "--size", "48x32", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    let defaults = text
        .lines()
        .find(|l| l.trim_start().starts_with("defaults:"))
        .unwrap();
    assert!(
        defaults.contains("glare.fb_bits=8") && defaults.contains("shading."),
        "{defaults}"
    );
    let gates: f64 = defaults
        .split("gates ")
        .nth(1)
        .and_then(|t| t.split_whitespace().next())
        .unwrap()
        .parse()
        .unwrap();
    assert!(gates > 0.0, "{defaults}");
    let _ = std::fs::remove_dir_all(&out);
}
