//! The `sweep` command: CSV and plot, the metrics' properties, errors, determinism.
//! Small images (48 × 32) and a 40-sample truth keep it fast.

mod common;

use glare_pipeline::pipeline::shafts::cli::render_scene;
use glare_pipeline::pipeline::shafts::sweep::{
    parse_values, sweep, Param, SweepOutput, Value, MAX_VALUES,
};
use glare_pipeline::report::csv_out::read_csv_column;
use glare_pipeline::scene::builtin::builtin;
use glare_pipeline::scene::format::Scene;
use std::path::Path;
use std::process::Command;

const HEADER: &str =
    "param,value,error_levels,rms_levels,predicted_hw_seconds,wall_seconds,gates_nand2";
const TRUTH: u32 = 40;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
}

fn tmp(name: &str) -> common::Scratch {
    common::Scratch::new("glare-sweep", name)
}

fn small(name: &str) -> Scene {
    let mut s = builtin(name).unwrap();
    s.image.width = 48;
    s.image.height = 32;
    s
}

fn run(scene: &Scene, param: &str, values: &str, out: &Path) -> SweepOutput {
    let p = Param::from_name(param).unwrap();
    let v = parse_values(p, values).unwrap();
    sweep(scene, p, &v, TRUTH, out).unwrap()
}

fn col(path: &Path, c: &str) -> Vec<f64> {
    read_csv_column(path, c).unwrap()
}

#[test]
fn planes_sweep_writes_the_csv_and_plot_time_rises_gates_do_not_change() {
    let out = tmp("planes");
    let r = run(&small("fig4"), "planes", "10,20,40,80", &out);
    let text = std::fs::read_to_string(&r.csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], HEADER);
    assert_eq!(lines.len(), 1 + 4, "{text}");
    for (line, v) in lines[1..].iter().zip(["10", "20", "40", "80"]) {
        assert!(line.starts_with(&format!("planes,{v},")), "{line}");
    }
    assert_eq!(r.csv, out.join("sweep_planes.csv"));
    let png = std::fs::read(out.join("sweep_planes.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");

    // Each plane is a full pass over the lit volume: the predicted time rises strictly.
    let t = col(&r.csv, "predicted_hw_seconds");
    assert!(t.windows(2).all(|w| w[1] > w[0]), "{t:?}");
    // The units do not depend on n: same elaboration, same gates.
    let g = col(&r.csv, "gates_nand2");
    assert!(g[0] > 0.0 && g.iter().all(|&x| x == g[0]), "{g:?}");
    for c in ["error_levels", "rms_levels", "wall_seconds"] {
        let v = col(&r.csv, c);
        assert!(v.iter().all(|x| x.is_finite() && *x >= 0.0), "{c}: {v:?}");
    }
    // The rows returned are the rows written.
    assert_eq!(r.rows.len(), 4);
    assert_eq!(col(&r.csv, "error_levels")[2], r.rows[2].error_levels);
    let _ = std::fs::remove_dir_all(out);
}

#[test]
fn subplanes_two_elaborate_the_j_path_and_cost_its_gates() {
    let base = small("fig4");
    let out = tmp("subplanes");
    let r = run(&base, "subplanes", "1,2", &out);
    let g = col(&r.csv, "gates_nand2");
    assert!(g[1] > g[0], "{g:?}");
    // The difference is what the m = 1 frame says leaving the J path out saved.
    let mut m1 = base.clone();
    m1.shafts.subplanes = 1;
    let (f, _, _) = render_scene(&m1).unwrap();
    let saved: f64 = f
        .elaboration
        .iter()
        .filter(|e| e.left_out.is_some() && e.name.contains("J buffer"))
        .map(|e| e.gates_saved)
        .sum();
    assert!(saved > 0.0);
    assert!(
        (g[1] - g[0] - saved).abs() < 1e-6 * g[1],
        "{g:?}, saved {saved}"
    );
    let _ = std::fs::remove_dir_all(out);
}

#[test]
fn wide_texels_and_framebuffer_beat_four_bits() {
    let out = tmp("bits");
    // Sweep one width with the other held at 16 bits.
    let mut s = small("fig4");
    s.shafts.fb_bits = 16;
    let r = run(&s, "texel_bits", "4,16", &out);
    let rms = col(&r.csv, "rms_levels");
    assert!(rms[1] < rms[0], "texel_bits 4 vs 16: {rms:?}");
    let mut s = small("fig4");
    s.shafts.texel_bits = 16;
    let r = run(&s, "fb_bits", "4,16", &out);
    let rms = col(&r.csv, "rms_levels");
    assert!(rms[1] < rms[0], "fb_bits 4 vs 16: {rms:?}");
    // A 4-bit framebuffer has steps of 17 levels: the error is of that order.
    assert!(rms[0] > 17.0 / 12f64.sqrt() * 0.5, "{rms:?}");
    let _ = std::fs::remove_dir_all(out);
}

/// The CSV without its wall_seconds column.
fn without_wall(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let idx = HEADER.split(',').position(|c| c == "wall_seconds").unwrap();
    text.lines()
        .map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            f.remove(idx);
            f.join(",")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn the_command_is_deterministic_apart_from_wall_time() {
    let (a, b) = (tmp("det-a"), tmp("det-b"));
    for d in [&a, &b] {
        let out = bin()
            .args([
                "sweep",
                "--scene",
                "fig4",
                "--param",
                "planes",
                "--values",
                "10..30:10,5",
                "--image",
                "48x32",
                "--truth-samples",
                "40",
                "--out",
            ])
            .arg(d)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            stdout.contains("error_levels") && stdout.contains("gates_nand2"),
            "{stdout}"
        );
    }
    let (ca, cb) = (a.join("sweep_planes.csv"), b.join("sweep_planes.csv"));
    assert_eq!(without_wall(&ca), without_wall(&cb));
    // The range expands inclusively, and values keep the order given.
    assert_eq!(col(&ca, "value"), vec![10.0, 20.0, 30.0, 5.0]);
    assert!(b.join("sweep_planes.png").exists());
    let _ = std::fs::remove_dir_all(a);
    let _ = std::fs::remove_dir_all(b);
}

/// Run the command expecting failure: the message, and that nothing was written.
fn fails(args: &[&str], want: &str) {
    let out_dir = tmp("bad");
    let out = bin()
        .args(["sweep", "--truth-samples", "40"])
        .args(args)
        .arg("--out")
        .arg(&out_dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(err.contains(want), "{args:?}: wanted '{want}' in: {err}");
    assert!(!out_dir.exists(), "{args:?} wrote {}", out_dir.display());
}

#[test]
fn bad_input_names_the_field_and_writes_nothing() {
    let common = ["--scene", "fig4", "--image", "48x32"];
    let with = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut v = common.to_vec();
        v.extend_from_slice(extra);
        v
    };
    // Unknown parameter: the known ones are listed.
    fails(
        &with(&["--param", "nope", "--values", "1"]),
        "param: unknown parameter 'nope' (known: planes, subplanes, texel_bits",
    );
    // A value that is not a number, after a good one.
    fails(
        &with(&["--param", "planes", "--values", "10,abc"]),
        "values[1]: 'abc' is not a number",
    );
    // The last value out of range: nothing rendered, nothing written.
    fails(
        &with(&["--param", "texel_bits", "--values", "4,8,20"]),
        "shafts.texel_bits: 20 is out of range",
    );
    fails(
        &with(&["--param", "mesh", "--values", "15x10,0x10"]),
        "shafts.mesh[0]: 0 is out of range",
    );
    fails(
        &with(&["--param", "mesh", "--values", "15x10,3..5"]),
        "values[1]: '3..5': a range needs a numeric parameter",
    );
    fails(
        &with(&["--param", "planes", "--values", "50..10:10"]),
        "values[0]: '50..10:10': the end 10 is below the start 50",
    );
    // An image width out of range.
    fails(
        &[
            "--scene", "fig4", "--image", "0x32", "--param", "planes", "--values", "10",
        ],
        "image.width: 0 is out of range",
    );
    fails(
        &[
            "--scene",
            "nonesuch.toml",
            "--param",
            "planes",
            "--values",
            "10",
        ],
        "scene: file not found: nonesuch.toml",
    );
    fails(
        &["--scene", "test", "--param", "planes", "--values", "10"],
        "scene: the foundation test scene",
    );
}

#[test]
fn values_parse_lists_ranges_and_pairs() {
    let one = |v: &[u32]| v.iter().map(|&x| Value::One(x)).collect::<Vec<_>>();
    assert_eq!(
        parse_values(Param::Planes, "10..50:10").unwrap(),
        one(&[10, 20, 30, 40, 50])
    );
    assert_eq!(
        parse_values(Param::Planes, " 1, 5..7 ,12..20:5").unwrap(),
        one(&[1, 5, 6, 7, 12, 17])
    );
    assert_eq!(
        parse_values(Param::Mesh, "15x10, 30X20").unwrap(),
        vec![Value::Pair(15, 10), Value::Pair(30, 20)]
    );
    assert_eq!(Value::Pair(15, 10).to_string(), "15x10");
    assert_eq!(
        Param::from_name("texel-bits").unwrap(),
        Param::from_name("texel_bits").unwrap()
    );
    for p in Param::ALL {
        assert_eq!(Param::from_name(p.name()).unwrap(), p);
    }
    let err = |p, s| parse_values(p, s).unwrap_err();
    assert!(err(Param::Planes, "").starts_with("values:"));
    assert!(err(Param::Planes, "10..20:0").contains("step must be at least 1"));
    assert!(err(Param::Planes, "1,-3").starts_with("values[1]:"));
    assert!(err(Param::Mesh, "15").starts_with("values[0]:"));
    assert!(err(Param::Planes, "15x10").starts_with("values[0]:"));
    assert!(err(Param::Planes, "99999999999").starts_with("values[0]:"));
    // The count is checked before the range is expanded.
    assert!(err(Param::Planes, "0..4294967295:1").contains(&MAX_VALUES.to_string()));
    assert_eq!(
        parse_values(Param::Planes, &format!("1..{MAX_VALUES}"))
            .unwrap()
            .len(),
        MAX_VALUES
    );
    assert!(err(Param::Planes, &format!("1..{MAX_VALUES},7")).contains("values"));
}

/// Range warnings after a sweep (issue 16): fig6 with a near/far ratio of 10⁹ loses
/// the depth buffer's resolution at every point; the warning is printed once, naming
/// the unit, the field and every point where it fired. The same sweep of the ordinary
/// fig6 prints none.
#[test]
fn a_sweep_out_of_range_warns_once_naming_its_points() {
    let out = tmp("warns");
    let toml = glare_pipeline::scene::builtin::builtin_toml("fig6").unwrap();
    assert!(toml.contains("near = 0.5") && toml.contains("far = 40.0"));
    let extreme = out.join("near.toml");
    std::fs::create_dir_all(&*out).unwrap();
    std::fs::write(
        &extreme,
        toml.replace("near = 0.5", "near = 1e-8")
            .replace("far = 40.0", "far = 10.0"),
    )
    .unwrap();
    let sweep_of = |scene: &str, dir: &str| {
        let o = bin()
            .args(["sweep", "--scene", scene, "--image", "48x32"])
            .args([
                "--truth-samples",
                "4",
                "--param",
                "planes",
                "--values",
                "4,8",
            ])
            .arg("--out")
            .arg(out.join(dir))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{err}");
        err
    };
    let err = sweep_of(&extreme.to_string_lossy(), "extreme");
    let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("warning:")).collect();
    assert_eq!(lines.len(), 1, "one distinct warning: {err}");
    let w = lines[0];
    for want in [
        "shadow_compare (depth buffer)",
        "depth resolution",
        "camera.near = 1e-8",
        "at planes = 4",
        "planes = 8",
    ] {
        assert!(w.contains(want), "{want:?} missing: {w}");
    }
    let err = sweep_of("fig6", "ordinary");
    assert!(!err.contains("warning:"), "{err}");
}
