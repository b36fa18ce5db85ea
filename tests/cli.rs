//! The command-line front end, run as a user would.

use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
}

#[test]
fn units_json_lists_every_unit_with_the_required_fields() {
    let out = bin().args(["units", "--json"]).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let arr = v.as_array().expect("a JSON array");
    let names: Vec<&str> = arr.iter().map(|u| u["name"].as_str().unwrap()).collect();
    for want in glare_pipeline::registry::UNIT_NAMES {
        assert!(names.contains(want), "{want} missing from units --json");
    }
    for u in arr {
        for key in ["name", "latency", "ii", "gates_nand2", "ram_bits", "widths"] {
            assert!(u.get(key).is_some(), "{}: no {key}", u["name"]);
        }
        assert!(u["latency"].as_u64().unwrap() >= 1);
        assert!(u["ii"].as_u64().unwrap() >= 1);
        assert!(u["gates_nand2"].as_f64().unwrap() > 0.0);
        assert!(!u["widths"].as_array().unwrap().is_empty());
    }
}

#[test]
fn trace_writes_a_vcd_and_unknown_units_are_named() {
    let dir = std::env::temp_dir().join(format!("glare-trace-{}", std::process::id()));
    let path = dir.join("m.vcd");
    let out = bin()
        .args(["trace", "modulate", "--pixels", "5", "--out"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let vcd = std::fs::read_to_string(&path).unwrap();
    assert!(vcd.contains("$enddefinitions") && vcd.contains("in_a") && vcd.contains("out_y"));
    // 5 pixels, latency 2, II 1: (5 − 1)·1 + 2 + 1 = 7 clocks → timestamps 0 … 65 (+ drain).
    assert!(vcd.contains("#60"));

    let bad = bin().args(["trace", "nonesuch"]).output().unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("unit"));
    let zero = bin()
        .args(["trace", "modulate", "--pixels", "0"])
        .output()
        .unwrap();
    assert_eq!(zero.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&zero.stderr).contains("pixels"));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn every_unit_traces_to_a_vcd() {
    let dir = std::env::temp_dir().join(format!("glare-trace-all-{}", std::process::id()));
    for name in glare_pipeline::registry::UNIT_NAMES {
        let path = dir.join(format!("{name}.vcd"));
        let out = bin()
            .args(["trace", name, "--pixels", "3", "--out"])
            .arg(&path)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let vcd = std::fs::read_to_string(&path).unwrap();
        assert!(
            vcd.contains(&format!("$scope module {name} $end")) && vcd.contains("$enddefinitions"),
            "{name}: not a VCD of the unit"
        );
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// A malformed `ENVMAP_PATTERN_SIZE` or `GLARE_GAUSS_SEEDS` is refused with an error
/// that names the variable, before any work or file is written.
#[test]
fn bad_reproduction_knobs_name_the_variable() {
    for (var, value, name) in [
        ("ENVMAP_PATTERN_SIZE", "1024", "envmap-lambda-sweep"),
        ("ENVMAP_PATTERN_SIZE", "0x512", "envmap-table5"),
        ("ENVMAP_PATTERN_SIZE", "5000x100", "envmap-table3"),
        ("GLARE_GAUSS_SEEDS", "0", "glare-gauss-seeds"),
        ("GLARE_GAUSS_SEEDS", "many", "glare-gauss-seeds"),
        // Beyond the 3D sampler's largest cube: refused before any work.
        ("ENVMAP_TABLE3_S", "512", "envmap-table3"),
        ("ENVMAP_TABLE3_TH", "0.001,1", "envmap-table3"),
    ] {
        let dir = std::env::temp_dir().join(format!("knob-{}-{name}", std::process::id()));
        let out = bin()
            .args(["reproduce", name, "--out"])
            .arg(&dir)
            .env(var, value)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{var}={value} accepted");
        assert!(err.contains(var), "{var}={value}: {err}");
        // Refused before any work: nothing written, not even the output directory
        // (work done, not wall time, which a loaded machine stretches).
        let written = std::fs::read_dir(&dir).map_or(0, |d| d.count());
        assert_eq!(written, 0, "{var}={value}: files written");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// An unknown scene name is refused with the list of every built-in scene, the glare
/// ones included (`render --scene glare-flare` works, so the message must say so).
#[test]
fn an_unknown_scene_lists_every_built_in() {
    let out = bin()
        .args(["render", "--scene", "no-such-scene", "--out"])
        .arg(std::env::temp_dir().join(format!("unknown-scene-{}.png", std::process::id())))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    for name in glare_pipeline::scene::builtin::BUILTIN_NAMES
        .iter()
        .chain(glare_pipeline::scene::builtin_glare::GLARE_BUILTIN_NAMES)
    {
        assert!(err.contains(name), "{name} missing from: {err}");
    }
}

/// A valid but very expensive scene says so on stderr before any pixel (issue 16):
/// fig6 at n = 1000, m = 6 is 720·480·1000·7 ≈ 2.4·10⁹ sample-plane fragments, above
/// `frame::cli::LARGE_WORK_FRAGMENTS`. The render is stopped once the line is read.
#[test]
fn an_expensive_scene_prints_its_work_up_front() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    use std::sync::mpsc;
    use std::time::Duration;

    let fig6 = bin().args(["scene", "fig6"]).output().unwrap();
    assert!(fig6.status.success());
    let text = String::from_utf8(fig6.stdout)
        .unwrap()
        .replace("planes = 30", "planes = 1000");
    assert!(text.contains("planes = 1000") && text.contains("subplanes = 6"));
    let dir = std::env::temp_dir().join(format!("glare-expensive-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("expensive.toml");
    std::fs::write(&scene, text).unwrap();
    let mut child = bin()
        .args(["render", "--scene"])
        .arg(&scene)
        .arg("--out")
        .arg(dir.join("out.png"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stderr = child.stderr.take().unwrap();
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let line = rx.recv_timeout(Duration::from_secs(60));
    let _ = child.kill();
    let _ = child.wait();
    let _ = std::fs::remove_dir_all(&dir);
    let line = line.expect("no line on stderr within 60 s");
    assert!(
        line.contains("expensive scene") && line.contains("2.42e9"),
        "the first stderr line is not the work estimate: {line}"
    );
}

/// Issue 17: `sweep --param side` on an environment scene writes one row per side
/// (error against the truth, wall time, the map's memory), and refuses a side beyond
/// the sampler's largest cube or an unknown parameter before writing anything.
#[test]
fn envmap_side_sweep_writes_rows_and_names_bad_values() {
    let dir = std::env::temp_dir().join(format!("envmap-side-sweep-{}", std::process::id()));
    let run = |param: &str, values: &str| {
        bin()
            .args(["sweep", "--scene", "env-pattern-sphere", "--param", param])
            .args(["--values", values, "--image", "24x24", "--out"])
            .arg(&dir)
            .env("CI", "1")
            .output()
            .unwrap()
    };
    let out = run("side", "8,16");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("sweep_side.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 2, "{csv}");
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for (row, side) in rows.iter().zip([8u64, 16]) {
        assert_eq!(row[col("value")], side.to_string());
        assert_eq!(row[col("ram_bits")], (side * side * side * 24).to_string());
        let e: f64 = row[col("mean_abs_levels")].parse().unwrap();
        assert!(e.is_finite() && e > 0.0, "{csv}");
    }
    assert!(dir.join("sweep_side.png").is_file());
    let _ = std::fs::remove_dir_all(&dir);
    for (param, values, name) in [
        ("side", "16,512", "environment.side"),
        ("side", "24", "environment.side"),
        ("planes", "8", "param"),
    ] {
        let out = run(param, values);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{param}={values}: {err}");
        assert!(err.contains(name), "{param}={values}: {err}");
        assert!(
            !dir.join("sweep_side.csv").exists(),
            "{param}={values}: wrote a CSV"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every output is checked before the first pass: two outputs at one path are
/// refused naming both, an unwritable place names its argument, and nothing is
/// written (the refusal comes before the render, not after it).
#[test]
fn outputs_are_checked_before_any_work_and_nothing_is_written() {
    let dir = std::env::temp_dir().join(format!("cli-outputs-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let x = dir.join("x.png");
    let o = bin()
        .args(["render", "--scene", "fig6", "--out"])
        .arg(&x)
        .arg("--reference")
        .arg(dir.join("sub/../x.png"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(err.contains("out and reference"), "{err}");
    assert!(!dir.exists(), "a refused render wrote {}", dir.display());
    // An unwritable place: refused before the render, naming the argument.
    let t0 = std::time::Instant::now();
    let o = bin()
        .args([
            "render",
            "--scene",
            "fig6",
            "--out",
            "/proc/cli-outputs/x.png",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(err.contains("error: render --scene fig6: out:"), "{err}");
    assert!(err.contains("cannot write"), "{err}");
    eprintln!("refused in {:.2} s", t0.elapsed().as_secs_f64());
    // The directories of the other commands.
    for args in [
        &[
            "sweep",
            "--scene",
            "fig4",
            "--param",
            "planes",
            "--values",
            "10",
            "--image",
            "24x16",
            "--out",
            "/proc/cli-o",
        ][..],
        &[
            "attribute",
            "--scene",
            "fig6",
            "--image",
            "24x16",
            "--out",
            "/proc/cli-o",
        ],
        &[
            "optimize",
            "--scene",
            "fig6",
            "--budget",
            "max<=2",
            "--image",
            "24x16",
            "--out",
            "/proc/cli-o",
        ],
        &["reproduce", "glare-fig4", "--out", "/proc/cli-o"],
        &["tables", "--dir", "/proc/cli-o"],
        &[
            "envmap-dump",
            "--scene",
            "env-pattern-sphere",
            "--side",
            "8",
            "--out",
            "/proc/cli-o",
        ],
    ] {
        let o = bin().args(args).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?}");
        assert!(err.contains("cannot write in `/proc`"), "{args:?}: {err}");
    }
}

/// `reproduce --image` sizes the envmap reproductions' images and wins over
/// `$ENVMAP_IMAGE_SIZE`: `--image 16x16` with the variable at 24 writes the bytes the
/// variable at 16 alone writes, and not those of 24.
#[test]
fn reproduce_image_sets_the_size_and_wins_over_the_variable() {
    let dir = std::env::temp_dir().join(format!("cli-repro-image-{}", std::process::id()));
    let run = |tag: &str, flag: Option<&str>, var: &str| {
        let out = dir.join(tag);
        let _ = std::fs::remove_dir_all(&out);
        let mut c = bin();
        c.args(["reproduce", "envmap-images", "--out"])
            .arg(&out)
            .env("ENVMAP_TABLE3_S", "8")
            .env("ENVMAP_IMAGE_SIZE", var);
        if let Some(f) = flag {
            c.args(["--image", f]);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read(out.join("fig14_pattern.png")).unwrap()
    };
    let flag = run("flag", Some("16x16"), "24");
    let var16 = run("var16", None, "16");
    let var24 = run("var24", None, "24");
    assert!(
        flag == var16,
        "--image 16x16 did not give the 16-pixel images"
    );
    assert!(flag != var24, "--image lost to $ENVMAP_IMAGE_SIZE");
    let _ = std::fs::remove_dir_all(&dir);
}
