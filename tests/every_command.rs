//! Every command × every built-in scene, through the real binary at a small `--image`:
//! `render`, `sweep`, `attribute`, `optimize`, `units --scene` and `scene` each either
//! succeed with measured values that are not zero where they apply (gates, predicted
//! time, the error of an 8-bit render against its f64 reference), or refuse before any
//! work, with exit status 2, a message that names the command and the scene, and no
//! output file created. Which pairs refuse is fixed below ([`REFUSED`]), each with
//! what the scene lacks, so a command that starts refusing a scene fails here.
//!
//! The runs go two at a time (the machine's cores); the whole matrix takes minutes,
//! most of it in the environment-map and showcase attributions.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;

/// The (command, scene) pairs that refuse, and the words the refusal must hold.
const REFUSED: &[(&str, &str, &str)] = &[
    ("sweep", "test", "no sample planes to sweep"),
    ("attribute", "test", "no error sources"),
    ("optimize", "test", "not a scene optimize can search"),
    ("units", "test", "fixed units"),
    ("attribute", "shading-vertex", "no image"),
];

/// Every built-in name a command takes: the scenes, `test`, the shading scenes.
fn builtins() -> Vec<String> {
    let mut v: Vec<String> = glare_pipeline::scene::load::builtin_names()
        .iter()
        .map(|s| s.to_string())
        .collect();
    v.push("test".into());
    v.extend(glare_pipeline::pipeline::shading::sweep::scene_names());
    v
}

/// The `--image` a scene takes in a quick run, None for a scene without one.
fn image(scene: &str) -> Option<&'static str> {
    match scene {
        "test" | "shading-vertex" => None,
        s if s.starts_with("shading-") => Some("24x24"),
        s if s.starts_with("env-") => Some("40x32"),
        _ => Some("48x32"),
    }
}

/// A param and two values `sweep` takes on the scene.
fn sweep_param(scene: &str) -> (String, &'static str) {
    use glare_pipeline::pipeline::shading::sweep::{params_of, ShadingScene};
    if scene.starts_with("shading-") {
        let p = params_of(&ShadingScene::parse(scene).unwrap())[0];
        let values = match p {
            "cube_face" => "16,32",
            "vertex_mantissa" => "10,12",
            "combiner_bits" => "8,9",
            other => panic!("no values for {other}"),
        };
        return (p.to_string(), values);
    }
    if scene.starts_with("env-") {
        return ("side".into(), "8,16");
    }
    if scene == "test" {
        return ("fb_bits".into(), "6,8");
    }
    let s = glare_pipeline::scene::load::load_scene(scene).unwrap();
    if glare_pipeline::frame::sweep::is_frame_scene(&s).unwrap() {
        let glare = s.glare.is_some();
        return (
            if glare {
                "glare.fb_bits"
            } else {
                "shafts.fb_bits"
            }
            .into(),
            "6,8",
        );
    }
    ("fb_bits".into(), "6,8")
}

/// One run: its arguments and the outputs it would write.
struct Run {
    command: &'static str,
    scene: String,
    args: Vec<String>,
    outputs: Vec<PathBuf>,
}

fn runs(scene: &str, dir: &Path) -> Vec<Run> {
    let d = dir.join(scene);
    let img = |v: &mut Vec<String>| {
        if let Some(i) = image(scene) {
            v.extend(["--image".to_string(), i.to_string()]);
        }
    };
    let s = |x: &[&str]| x.iter().map(|a| a.to_string()).collect::<Vec<_>>();
    let mut out = Vec::new();
    let png = d.join("render.png");
    let mut a = s(&["render", "--scene", scene, "--json", "--out"]);
    a.push(png.display().to_string());
    img(&mut a);
    out.push(Run {
        command: "render",
        scene: scene.into(),
        args: a,
        outputs: vec![png],
    });
    let (param, values) = sweep_param(scene);
    let sw = d.join("sweep");
    let mut a = s(&[
        "sweep", "--scene", scene, "--param", &param, "--values", values,
    ]);
    a.extend(["--out".into(), sw.display().to_string()]);
    img(&mut a);
    out.push(Run {
        command: "sweep",
        scene: scene.into(),
        args: a,
        outputs: vec![sw],
    });
    let at = d.join("attribute");
    let mut a = s(&["attribute", "--scene", scene, "--out"]);
    a.push(at.display().to_string());
    img(&mut a);
    out.push(Run {
        command: "attribute",
        scene: scene.into(),
        args: a,
        outputs: vec![at],
    });
    let op = d.join("optimize");
    let mut a = s(&[
        "optimize",
        "--scene",
        scene,
        "--budget",
        "max<=255",
        "--max-evals",
        "2",
    ]);
    a.extend(["--out".into(), op.display().to_string()]);
    img(&mut a);
    out.push(Run {
        command: "optimize",
        scene: scene.into(),
        args: a,
        outputs: vec![op],
    });
    out.push(Run {
        command: "units",
        scene: scene.into(),
        args: s(&["units", "--scene", scene]),
        outputs: vec![],
    });
    out.push(Run {
        command: "scene",
        scene: scene.into(),
        args: s(&["scene", scene]),
        outputs: vec![],
    });
    out
}

/// The numbers of a CSV column whose name starts with `prefix`.
fn column(csv: &Path, prefix: &str) -> Result<Vec<f64>, String> {
    let text = std::fs::read_to_string(csv).map_err(|e| format!("{}: {e}", csv.display()))?;
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let head: Vec<&str> = lines.next().ok_or("an empty CSV")?.split(',').collect();
    let i = head
        .iter()
        .position(|c| c.starts_with(prefix))
        .ok_or_else(|| format!("{}: no column {prefix} in {head:?}", csv.display()))?;
    Ok(lines
        .map(|l| {
            l.split(',')
                .nth(i)
                .and_then(|x| x.parse().ok())
                .unwrap_or(f64::NAN)
        })
        .collect())
}

/// A measured value that is there and not zero (NaN is not).
fn positive(x: f64) -> bool {
    x > 0.0
}

/// The one CSV a sweep writes into `dir`.
fn sweep_csv(dir: &Path) -> Result<PathBuf, String> {
    std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "csv"))
        .ok_or_else(|| format!("no CSV in {}", dir.display()))
}

/// Any number under `key` anywhere in `v` that is > 0.
fn some_positive(v: &serde_json::Value, key: &str) -> bool {
    match v {
        serde_json::Value::Object(m) => m.iter().any(|(k, x)| {
            (k == key && x.as_f64().is_some_and(|n| n > 0.0)) || some_positive(x, key)
        }),
        serde_json::Value::Array(a) => a.iter().any(|x| some_positive(x, key)),
        _ => false,
    }
}

/// What is wrong with a successful run's measurements, if anything.
fn check_success(r: &Run, stdout: &str) -> Result<(), String> {
    match r.command {
        "render" => {
            let v: serde_json::Value =
                serde_json::from_str(stdout).map_err(|e| format!("not JSON: {e}"))?;
            // A shading scene's render measures its path as a whole (gates, error),
            // not per unit; every other family counts each unit's cycles.
            if v["family"] == "shading" {
                if !v["shading"]["gates_nand2"].as_f64().is_some_and(positive) {
                    return Err(format!("shading gates {}", v["shading"]["gates_nand2"]));
                }
            } else if !some_positive(&v["counters"], "cycles") {
                return Err("no unit counted a cycle".into());
            }
            if !v["timing"]["predicted_seconds"]
                .as_f64()
                .is_some_and(|t| t > 0.0)
            {
                return Err(format!(
                    "predicted_seconds {}",
                    v["timing"]["predicted_seconds"]
                ));
            }
            if image(&r.scene).is_some() && !r.outputs[0].is_file() {
                return Err("no PNG written".into());
            }
        }
        "sweep" => {
            let csv = sweep_csv(&r.outputs[0])?;
            for c in ["gates_nand2", "predicted_hw_seconds"] {
                let v = column(&csv, c)?;
                if v.len() != 2 || !v.iter().all(|x| positive(*x)) {
                    return Err(format!("{c} {v:?}"));
                }
            }
            // An 8-bit render is never exactly its f64 reference at both values: the
            // max (or, for the shafts sweep, the representative pixels' error).
            let err = column(&csv, "max").or_else(|_| column(&csv, "error_levels"))?;
            if !err.iter().any(|x| positive(*x)) {
                return Err(format!("error {err:?}"));
            }
        }
        "attribute" => {
            let csv = r.outputs[0].join("attribution.csv");
            let max = column(&csv, "max")?;
            if !max.first().is_some_and(|m| *m > 0.0) {
                return Err(format!("configured max error {max:?}"));
            }
        }
        "optimize" => {
            let d = stdout
                .lines()
                .find(|l| l.trim_start().starts_with("defaults:"))
                .ok_or("no defaults line")?;
            let gates: f64 = d
                .split(" gates ")
                .nth(1)
                .and_then(|t| t.split_whitespace().next())
                .and_then(|t| t.parse().ok())
                .ok_or(format!("no gates in {d}"))?;
            if !positive(gates) {
                return Err(d.to_string());
            }
        }
        "units" => {
            let gates = stdout
                .split(" NAND2 gates")
                .next()
                .and_then(|t| t.split_whitespace().last())
                .and_then(|t| t.parse::<f64>().ok())
                .ok_or("no NAND2 gates total")?;
            if !positive(gates) {
                return Err(format!("{gates} gates"));
            }
        }
        "scene" => {
            stdout
                .parse::<toml::Table>()
                .map_err(|e| format!("not TOML: {e}"))?;
        }
        _ => unreachable!(),
    }
    Ok(())
}

#[test]
fn every_command_measures_every_builtin_or_refuses_up_front() {
    let dir = std::env::temp_dir().join(format!("every_command_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let all: Vec<Run> = builtins().iter().flat_map(|s| runs(s, &dir)).collect();
    let queue = Mutex::new(all.iter().collect::<Vec<_>>());
    let failures = Mutex::new(Vec::<String>::new());
    let refused = Mutex::new(BTreeMap::<(String, String), String>::new());
    std::thread::scope(|t| {
        for _ in 0..2 {
            t.spawn(|| loop {
                let Some(r) = queue.lock().unwrap().pop() else {
                    break;
                };
                let t0 = std::time::Instant::now();
                let o = Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
                    .args(&r.args)
                    .env("GLARE_PROGRESS", "never")
                    .output()
                    .unwrap();
                let secs = t0.elapsed().as_secs_f64();
                if secs > 30.0 {
                    eprintln!("slow: {secs:.0} s: {}", r.args.join(" "));
                }
                let (out, err) = (
                    String::from_utf8_lossy(&o.stdout),
                    String::from_utf8_lossy(&o.stderr),
                );
                let what = r.args.join(" ");
                let verdict = if o.status.success() {
                    check_success(r, &out)
                } else if o.status.code() != Some(2) || err.contains("panicked") {
                    Err(format!("exit {:?}: {err}", o.status.code()))
                } else {
                    refused
                        .lock()
                        .unwrap()
                        .insert((r.command.into(), r.scene.clone()), err.to_string());
                    let named = format!("{} --scene {}", r.command, r.scene);
                    let scene_cmd = format!("scene {}", r.scene);
                    match r.outputs.iter().find(|p| p.exists()) {
                        Some(p) => Err(format!("refused but created {}: {err}", p.display())),
                        None if !(err.contains(&named) || err.contains(&scene_cmd)) => {
                            Err(format!("the refusal does not name {named}: {err}"))
                        }
                        None => Ok(()),
                    }
                };
                if let Err(e) = verdict {
                    failures.lock().unwrap().push(format!("{what}: {e}"));
                }
            });
        }
    });
    let mut failures = failures.into_inner().unwrap();
    let refused = refused.into_inner().unwrap();
    for ((cmd, scene), err) in &refused {
        match REFUSED.iter().find(|(c, s, _)| c == cmd && s == scene) {
            Some((_, _, why)) if err.contains(why) => {}
            Some((_, _, why)) => {
                failures.push(format!("{cmd} {scene}: refusal lacks '{why}': {err}"))
            }
            None => failures.push(format!("{cmd} {scene}: refused: {err}")),
        }
    }
    for (c, s, _) in REFUSED {
        if !refused.contains_key(&(c.to_string(), s.to_string())) {
            failures.push(format!("{c} {s}: expected a refusal, it ran"));
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
