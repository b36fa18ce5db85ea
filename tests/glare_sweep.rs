//! The glare `sweep`: CSV and plot over a glare width, the error falling with the
//! table depth, errors naming the field, the CLI dispatch. Small images keep it fast.

mod common;

use glare_pipeline::pipeline::glare::sweep::{apply, glare_sweep, parse_int_values, GLARE_PARAMS};
use glare_pipeline::report::csv_out::read_csv_column;
use glare_pipeline::scene::builtin::builtin;
use glare_pipeline::scene::format::Scene;
use glare_pipeline::scene::glare::GlareHw;

use std::process::Command;

const HEADER: &str = "param,value,mean_abs_levels,rms_levels,max_levels,predicted_hw_seconds,wall_seconds,gates_nand2,ram_bits";

fn tmp(name: &str) -> common::Scratch {
    common::Scratch::new("glare-sweep", name)
}

/// The elliptic built-in at 160 × 120 (the source keeps its size in pixels).
fn small() -> Scene {
    let mut s = builtin("glare-elliptic").unwrap();
    s.image.width = 160;
    s.image.height = 120;
    s.camera.fovy_deg = 25.0 * 120.0 / 480.0;
    s
}

#[test]
fn shape_depth_sweep_writes_csv_and_plot_and_the_error_falls() {
    let out = tmp("shape");
    let (rows, csv, png) = glare_sweep(&small(), "shape_log2", &[4, 6, 8], &out, None).unwrap();
    assert_eq!(rows.len(), 3);
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().next().unwrap(), HEADER);
    assert!(png.exists() && std::fs::metadata(&png).unwrap().len() > 1000);
    let rms = read_csv_column(&csv, "rms_levels").unwrap();
    // A deeper shape RAM samples the distance field finer: the error falls, and the
    // RAM grows as (2^k + 1)².
    assert!(rms[0] > rms[1] && rms[1] > rms[2], "{rms:?}");
    assert!(rows[2].ram_bits > rows[1].ram_bits && rows[1].ram_bits > rows[0].ram_bits);
    for r in &rows {
        assert!(r.mean_abs_levels.is_finite() && r.max_levels <= 255.0);
    }
}

#[test]
fn every_param_applies_and_an_invalid_value_names_the_field() {
    for p in GLARE_PARAMS {
        let mut hw = GlareHw::default();
        apply(&mut hw, p, 9).unwrap();
        assert_ne!(hw, GlareHw::default(), "{p}");
    }
    assert!(apply(&mut GlareHw::default(), "planes", 3)
        .unwrap_err()
        .starts_with("param:"));
    let e = glare_sweep(&small(), "shape_log2", &[7, 11], &tmp("bad"), None).unwrap_err();
    assert!(e.contains("glare.hw.shape_log2") && e.contains("11"), "{e}");
    assert_eq!(parse_int_values("4..10:3, 12").unwrap(), vec![4, 7, 10, 12]);
    for bad in ["", "x", "5..3", "1..4:0", "-1"] {
        assert!(
            parse_int_values(bad).unwrap_err().starts_with("values:"),
            "{bad}"
        );
    }
}

#[test]
fn the_cli_sweeps_a_glare_scene_and_rejects_a_shafts_param() {
    let out = tmp("cli");
    let run = |param: &str| {
        Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
            .args([
                "sweep",
                "--scene",
                "glare-point",
                "--param",
                param,
                "--values",
                "6,7",
            ])
            .args(["--image", "96x64", "--out"])
            .arg(&out)
            .output()
            .unwrap()
    };
    let ok = run("falloff_log2");
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    assert!(out.join("sweep_falloff_log2.csv").exists());
    let bad = run("planes");
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("param"));
}

#[test]
fn radial_correction_sweep_cuts_the_shallow_table_error() {
    // At k = 5 the elliptic source's cone is far below a cell: the radial mode (signed
    // sdf − κ|p| entries, |p| computed) must beat the plain table; RAM bits unchanged.
    let mut s = small();
    s.glare.as_mut().unwrap().hw.shape_log2 = 5;
    let (rows, ..) = glare_sweep(&s, "radial", &[0, 1], &tmp("radial"), None).unwrap();
    println!(
        "k = 5: max off {:.1}, radial {:.1}; gates {:.0} → {:.0}",
        rows[0].max_levels, rows[1].max_levels, rows[0].gates_nand2, rows[1].gates_nand2
    );
    // Each row records the mode it ran with (0 off, 1 on).
    assert_eq!(
        rows.iter().map(|r| r.value).collect::<Vec<_>>(),
        [0, 1],
        "{rows:?}"
    );
    assert!(rows[1].max_levels < 0.6 * rows[0].max_levels, "{rows:?}");
    assert!(rows[1].mean_abs_levels <= rows[0].mean_abs_levels);
    assert_eq!(rows[0].ram_bits, rows[1].ram_bits);
    assert!(rows[1].gates_nand2 > rows[0].gates_nand2);
}
