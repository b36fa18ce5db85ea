//! The shading `sweep`: CSV and plot over a shading width, the error falling where the
//! width is the error's source, `param` / `values` errors before any work, the CLI
//! dispatch of `shading-*` scenes. A 48² sphere keeps it fast.

mod common;

use glare_pipeline::pipeline::shading::sweep::{
    check_param, params_of, scene_names, shading_sweep, ShadingScene, ShadingSweepOptions,
    SHADING_PARAMS,
};
use glare_pipeline::report::csv_out::read_csv_column;
use std::process::Command;

const HEADER: &str = "param,value,mean_abs_levels,rms_levels,max_levels,predicted_hw_seconds,wall_seconds,gates_nand2,ram_bits";

const SMALL: ShadingSweepOptions = ShadingSweepOptions { view_size: 48 };

fn tmp(name: &str) -> common::Scratch {
    common::Scratch::new("shading-sweep", name)
}

#[test]
fn cube_bits_sweep_writes_csv_and_plot_and_the_error_falls() {
    let out = tmp("cube-bits");
    let (rows, csv, png) =
        shading_sweep("shading-specular", "cube_bits", &[4, 6, 8], &out, &SMALL).unwrap();
    assert_eq!(rows.len(), 3);
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().next().unwrap(), HEADER);
    assert_eq!(text.lines().count(), 4);
    assert!(png.exists() && std::fs::metadata(&png).unwrap().len() > 1000);
    let rms = read_csv_column(&csv, "rms_levels").unwrap();
    let mean = read_csv_column(&csv, "mean_abs_levels").unwrap();
    // The lookup path's n·h is formed from b-bit cube texels, so its error is the
    // vectors' quantisation: at 64² measured RMS 33.9 → 22.3 → 4.1 for b = 4, 6, 8
    // (each step well over 1.5×), so a strict fall holds with room.
    assert!(rms[0] > rms[1] && rms[1] > rms[2], "{rms:?}");
    assert!(mean[0] > mean[1] && mean[1] > mean[2], "{mean:?}");
    // Texel RAM 6F²·3·b grows with b.
    assert!(rows[2].ram_bits > rows[1].ram_bits && rows[1].ram_bits > rows[0].ram_bits);
    for r in &rows {
        assert_eq!(r.param, "cube_bits");
        assert!(r.max_levels <= 255.0 && r.gates_nand2 > 0.0 && r.predicted_hw_seconds > 0.0);
    }
    assert_eq!(rows.iter().map(|r| r.value).collect::<Vec<_>>(), [4, 6, 8]);
}

#[test]
fn factor_bits_and_combiner_bits_cut_the_error_where_they_are_its_source() {
    // Oren–Nayar's factor textures: at 64², RMS 30.8 (2 bits) → 23.3 (8 bits), mean
    // 23.5 → 16.6; at 2 bits the texels' quantisation dominates, at 8 the SVD's rank.
    // (Not every model falls: classic Phong's mean rises from 2 to 8 bits — its
    // rank error dominates — so only the Oren–Nayar fall is asserted.)
    let out = tmp("factor-bits");
    let (rows, ..) =
        shading_sweep("shading-oren_nayar", "factor_bits", &[2, 8], &out, &SMALL).unwrap();
    assert!(rows[1].rms_levels < rows[0].rms_levels, "{rows:?}");
    assert!(rows[1].ram_bits > rows[0].ram_bits && rows[1].gates_nand2 > rows[0].gates_nand2);
    // Squaring at 8 internal bits against the GeForce's 9: at 64² RMS 9.3 → 4.4.
    let (rows, ..) =
        shading_sweep("shading-specular", "combiner_bits", &[8, 9], &out, &SMALL).unwrap();
    assert!(rows[1].rms_levels < rows[0].rms_levels, "{rows:?}");
    assert!(rows[1].gates_nand2 > rows[0].gates_nand2);
    // The vertex float: 8 → 16 mantissa bits, max 12 → ≤ 1 level on the sphere.
    let (rows, ..) =
        shading_sweep("shading-vertex", "vertex_mantissa", &[8, 16], &out, &SMALL).unwrap();
    assert!(rows[1].max_levels < rows[0].max_levels, "{rows:?}");
    assert!(
        rows[1].mean_abs_levels <= rows[0].mean_abs_levels,
        "{rows:?}"
    );
}

#[test]
fn params_are_checked_per_scene_before_any_work() {
    let lambert = ShadingScene::parse("shading-lambert").unwrap();
    // Unknown: names `param` and lists the scene's valid ones.
    let e = check_param(&lambert, "nope").unwrap_err();
    assert!(e.starts_with("param:") && e.contains("cube_face"), "{e}");
    // Another scene's width: refused, naming `param`.
    let out = tmp("refused");
    let e = shading_sweep("shading-lambert", "vertex_mantissa", &[8], &out, &SMALL).unwrap_err();
    assert!(
        e.starts_with("param:") && e.contains("does not apply"),
        "{e}"
    );
    let e = shading_sweep("shading-vertex", "factor_bits", &[8], &out, &SMALL).unwrap_err();
    assert!(
        e.starts_with("param:") && e.contains("vertex_mantissa"),
        "{e}"
    );
    // A bad value names `values` and the unit's field, before anything is written.
    let e = shading_sweep("shading-blinn_phong", "cube_face", &[32, 48], &out, &SMALL).unwrap_err();
    assert!(
        e.starts_with("values:") && e.contains("normalize_cube.face_side"),
        "{e}"
    );
    let e = shading_sweep("shading-specular", "lookup_bits", &[8, 40], &out, &SMALL).unwrap_err();
    assert!(e.starts_with("values:") && e.contains("entry_bits"), "{e}");
    // The lookup's entry width is not a width of the Blinn–Phong path (its 8-bit
    // MODULATE reads the entries as they are).
    let e = shading_sweep("shading-blinn_phong", "lookup_bits", &[8], &out, &SMALL).unwrap_err();
    assert!(e.starts_with("param:"), "{e}");
    assert!(!out.exists());
    // An unknown scene names `scene`; every scene's params are known widths and every
    // width applies to some scene.
    assert!(ShadingScene::parse("shading-nope")
        .unwrap_err()
        .starts_with("scene:"));
    let mut used = std::collections::BTreeSet::new();
    for name in scene_names() {
        let s = ShadingScene::parse(&name).unwrap();
        assert_eq!(s.name(), name);
        for p in params_of(&s) {
            assert!(SHADING_PARAMS.contains(p), "{p}");
            used.insert(*p);
        }
    }
    assert_eq!(used.len(), SHADING_PARAMS.len());
}

#[test]
fn the_cli_sweeps_a_shading_scene_and_rejects_a_foreign_param() {
    let out = tmp("cli");
    let run = |scene: &str, param: &str| {
        Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
            .args(["sweep", "--scene", scene, "--param", param])
            .args(["--values", "5,8", "--out"])
            .arg(&out)
            .output()
            .unwrap()
    };
    let ok = run("shading-vertex", "vertex_exponent");
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    assert!(out.join("sweep_vertex_exponent.csv").exists());
    let bad = run("shading-lambert", "combiner_bits");
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("param"));
}
