//! `render --json` has one shape for every scene family: every built-in is rendered
//! through the CLI binary at a small `--image` and its output checked against
//! docs/render.schema.json (with a validator of the schema subset the file uses:
//! type, required, properties, additionalProperties, items, enum; itself tested to
//! fail on what it must refuse), and against what the run did: the outputs it names
//! exist, the family's own sub-object is the only one present, `error` appears only
//! with `--reference`, and `image` is the size asked for.

use glare_pipeline::pipeline::shading::sweep::scene_names;
use glare_pipeline::scene::builtin::BUILTIN_NAMES;
use glare_pipeline::scene::builtin_environment::ENVIRONMENT_BUILTIN_NAMES;
use glare_pipeline::scene::builtin_glare::GLARE_BUILTIN_NAMES;
use glare_pipeline::scene::builtin_showcase::SHOWCASE_NAMES;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

// ------------------------------------------------------------- the validator

/// The JSON type names a value matches ("integer" also matches "number").
fn is_type(v: &Value, t: &str) -> bool {
    match t {
        "object" => v.is_object(),
        "array" => v.is_array(),
        "string" => v.is_string(),
        "boolean" => v.is_boolean(),
        "null" => v.is_null(),
        "number" => v.is_number(),
        "integer" => v.is_u64() || v.is_i64(),
        other => panic!("schema: unknown type '{other}'"),
    }
}

/// Every violation of `schema` by `v` at `at` (a JSON pointer), appended to `errs`.
/// Keywords outside the subset are refused, so the schema cannot say more than is
/// checked.
fn validate(schema: &Value, v: &Value, at: &str, errs: &mut Vec<String>) {
    let s = schema.as_object().expect("a schema is an object");
    for k in s.keys() {
        assert!(
            [
                "$schema",
                "title",
                "description",
                "type",
                "required",
                "properties",
                "additionalProperties",
                "items",
                "enum"
            ]
            .contains(&k.as_str()),
            "schema at {at}: keyword '{k}' is outside the subset this validator checks"
        );
    }
    if let Some(t) = s.get("type") {
        let types: Vec<&str> = match t {
            Value::String(one) => vec![one.as_str()],
            Value::Array(many) => many.iter().map(|x| x.as_str().unwrap()).collect(),
            _ => panic!("schema at {at}: bad type"),
        };
        if !types.iter().any(|t| is_type(v, t)) {
            errs.push(format!("{at}: {v} is not of type {types:?}"));
            return;
        }
    }
    if let Some(Value::Array(allowed)) = s.get("enum") {
        if !allowed.contains(v) {
            errs.push(format!("{at}: {v} is not one of {allowed:?}"));
        }
    }
    if let Value::Object(obj) = v {
        if let Some(Value::Array(req)) = s.get("required") {
            for r in req {
                let r = r.as_str().unwrap();
                if !obj.contains_key(r) {
                    errs.push(format!("{at}: missing required '{r}'"));
                }
            }
        }
        let props = s.get("properties").and_then(Value::as_object);
        for (k, x) in obj {
            let here = format!("{at}/{k}");
            match props.and_then(|p| p.get(k)) {
                Some(sub) => validate(sub, x, &here, errs),
                None => match s.get("additionalProperties") {
                    Some(Value::Bool(false)) => {
                        errs.push(format!("{at}: '{k}' is not allowed here"))
                    }
                    Some(sub @ Value::Object(_)) => validate(sub, x, &here, errs),
                    _ => {}
                },
            }
        }
    }
    if let (Value::Array(items), Some(sub)) = (v, s.get("items")) {
        for (i, x) in items.iter().enumerate() {
            validate(sub, x, &format!("{at}/{i}"), errs);
        }
    }
}

fn schema() -> Value {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/render.schema.json");
    serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap()
}

fn violations(v: &Value) -> Vec<String> {
    let mut errs = Vec::new();
    validate(&schema(), v, "", &mut errs);
    errs
}

/// The smallest object the schema accepts, to break one field at a time.
fn minimal() -> Value {
    serde_json::json!({
        "schema_version": 1,
        "scene": "x",
        "family": "test",
        "image": { "width": 4, "height": 3 },
        "outputs": { "image": "a.png", "reference": null },
        "passes": [],
        "chip": null,
        "counters": { "p": { "u": {
            "cycles": 1, "pixels_in": 1, "pixels_out": 1, "stalls": 0, "table_reads": 0,
            "mem_read_bytes": 0, "mem_write_bytes": 0, "saturations": 0, "overflows": 0,
            "underflows": 0
        } } },
        "timing": { "predicted_seconds": 0.5, "gpu": null, "cycles": 7, "clock_mhz": 200.0,
                    "wall_seconds": 0.1 },
        "warnings": [],
        "test": { "covered_pixels": 3 }
    })
}

/// One way to break the minimal object.
type Breaker = Box<dyn Fn(&mut Value)>;

#[test]
fn the_validator_accepts_the_minimal_object_and_refuses_each_kind_of_fault() {
    assert_eq!(violations(&minimal()), Vec::<String>::new());
    let broken: Vec<(&str, Breaker)> = vec![
        (
            "missing required",
            Box::new(|v| {
                v.as_object_mut().unwrap().remove("timing");
            }),
        ),
        ("type", Box::new(|v| v["schema_version"] = "1".into())),
        ("enum", Box::new(|v| v["schema_version"] = 2.into())),
        ("enum", Box::new(|v| v["family"] = "glare".into())),
        ("integer", Box::new(|v| v["image"]["width"] = 4.5.into())),
        (
            "additional top-level",
            Box::new(|v| v["predicted_seconds"] = 1.0.into()),
        ),
        (
            "additional nested",
            Box::new(|v| v["outputs"]["png"] = "a.png".into()),
        ),
        (
            "additionalProperties schema",
            Box::new(|v| v["counters"]["p"]["u"]["cycles"] = (-1.5).into()),
        ),
        (
            "items",
            Box::new(|v| {
                v["passes"] = serde_json::json!([{ "name": "p" }]);
            }),
        ),
        (
            "null where not allowed",
            Box::new(|v| v["scene"] = Value::Null),
        ),
    ];
    for (what, f) in broken {
        let mut v = minimal();
        f(&mut v);
        assert!(!violations(&v).is_empty(), "{what}: accepted {v}");
    }
}

// ------------------------------------------------------------- the renders

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("render-json-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `render --json` of `scene` with `args`, its object, checked against the schema and
/// the run.
fn render(scene: &str, args: &[&str], dir: &Path, reference: bool) -> Value {
    let out = dir.join(format!("{scene}.png"));
    let refp = dir.join(format!("{scene}.ref.png"));
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_glare-pipeline"));
    cmd.args(["render", "--json", "--scene", scene])
        .args(args)
        .arg("--out")
        .arg(&out);
    if reference {
        cmd.arg("--reference").arg(&refp);
    }
    let o = cmd.output().unwrap();
    assert!(
        o.status.success(),
        "{scene}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: Value = serde_json::from_slice(&o.stdout)
        .unwrap_or_else(|e| panic!("{scene}: not one JSON object ({e})"));
    let errs = violations(&v);
    assert!(errs.is_empty(), "{scene}: {errs:#?}");
    // The scene's own name, which for a built-in begins with the name given.
    assert!(
        v["scene"].as_str().unwrap().starts_with(scene),
        "{scene}: {}",
        v["scene"]
    );
    // The family's own sub-object, and no other family's.
    let family = v["family"].as_str().unwrap();
    for f in ["frame", "environment", "shading", "test"] {
        assert_eq!(v.get(f).is_some(), f == family, "{scene}: sub-object {f}");
    }
    // The outputs it names are the files written.
    if let Some(p) = v["outputs"]["image"].as_str() {
        assert_eq!(Path::new(p), out);
        assert!(out.is_file(), "{scene}: {p} not written");
    }
    if let Some(p) = v["outputs"]["reference"].as_str() {
        assert_eq!(Path::new(p), refp);
        assert!(refp.is_file(), "{scene}: {p} not written");
    }
    assert_eq!(v.get("error").is_some(), reference, "{scene}: error");
    assert!(v["timing"]["wall_seconds"].as_f64().unwrap() >= 0.0);
    v
}

fn assert_size(v: &Value, w: u64, h: u64) {
    assert_eq!(v["image"]["width"].as_u64(), Some(w), "{}", v["scene"]);
    assert_eq!(v["image"]["height"].as_u64(), Some(h), "{}", v["scene"]);
    let png = v["outputs"]["image"].as_str().unwrap();
    let img = image::open(png).unwrap();
    assert_eq!((img.width() as u64, img.height() as u64), (w, h), "{png}");
}

#[test]
fn every_frame_scene_renders_to_the_schema_at_the_size_asked() {
    let dir = scratch("frame");
    let names = BUILTIN_NAMES
        .iter()
        .chain(GLARE_BUILTIN_NAMES)
        .chain(SHOWCASE_NAMES);
    for name in names {
        let v = render(name, &["--image", "64x48"], &dir, false);
        assert_eq!(v["family"], "frame", "{name}");
        assert_size(&v, 64, 48);
        assert!(!v["passes"].as_array().unwrap().is_empty(), "{name}");
        assert!(v["chip"]["units"].is_array(), "{name}");
        assert!(v["timing"]["predicted_seconds"].as_f64().unwrap() > 0.0);
    }
    // With --reference: the error, and the reference PNG named and written.
    let v = render("glare-point", &["--image", "48x32"], &dir, true);
    assert!(v["error"].is_object());
    assert_size(&v, 48, 32);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_environment_scene_renders_to_the_schema_at_the_size_asked() {
    let dir = scratch("env");
    for name in ENVIRONMENT_BUILTIN_NAMES {
        let v = render(name, &["--image", "40x32"], &dir, false);
        assert_eq!(v["family"], "environment", "{name}");
        assert_size(&v, 40, 32);
        assert!(v["counters"]["envmap"].is_object(), "{name}");
    }
    let v = render("env-pattern-sphere", &["--image", "32x24"], &dir, true);
    assert!(v["error"]["cos_phi"].is_object(), "{v}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_shading_scene_and_the_test_scene_render_to_the_schema() {
    let dir = scratch("shading");
    for name in scene_names() {
        if name == "shading-vertex" {
            let v = render(&name, &[], &dir, false);
            assert!(v["image"].is_null() && v["outputs"]["image"].is_null());
            continue;
        }
        let v = render(&name, &["--image", "24x24"], &dir, false);
        assert_eq!(v["family"], "shading", "{name}");
        assert_size(&v, 24, 24);
        assert!(v["shading"]["error_levels"]["rms_levels"]
            .as_f64()
            .is_some());
    }
    let v = render("shading-lambert", &["--image", "16x16"], &dir, true);
    assert_eq!(v["error"], v["shading"]["error_levels"]);
    let t = render("test", &[], &dir, true);
    assert_eq!(t["family"], "test");
    assert!(t["timing"]["cycles"].as_u64().unwrap() > 0);
    assert!(t["counters"]["test scene"].as_object().unwrap().len() >= 2);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `render --plan --json` prints the same shape with nothing rendered: no outputs
/// (and no file written), no counters, no times, no family sub-object.
#[test]
fn the_plan_has_the_same_shape_with_nothing_rendered() {
    let dir = scratch("plan");
    for (scene, family) in [
        ("fig6", "frame"),
        ("night-street", "frame"),
        ("env-pattern-sphere", "environment"),
        ("shading-lambert", "shading"),
        ("test", "test"),
    ] {
        let out = dir.join("x.png");
        let o = Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
            .args(["render", "--plan", "--json", "--scene", scene, "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: Value = serde_json::from_slice(&o.stdout).unwrap();
        let errs = violations(&v);
        assert!(errs.is_empty(), "{scene}: {errs:#?}");
        assert_eq!(v["family"], family);
        assert!(v.get(family).is_none(), "{scene}: a sub-object with --plan");
        assert!(v["outputs"]["image"].is_null() && v["timing"]["wall_seconds"].is_null());
        assert_eq!(v["counters"], serde_json::json!({}));
        assert!(!out.exists(), "{scene}: --plan wrote {}", out.display());
        if family != "shading" {
            assert!(!v["passes"].as_array().unwrap().is_empty(), "{scene}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `render --json --timing clocked|sampled` keeps the one shape: the frame's
/// `chip_timing` (docs/throughput.md's fields) against the schema, on a shafts scene
/// large enough to sample (96 × 64) and on a glare scene (its glare ASIC).
#[test]
fn timed_frames_render_to_the_schema() {
    let dir = scratch("timed");
    for (scene, mode) in [
        ("fig6", "sampled"),
        ("fig6", "clocked"),
        ("glare-point", "clocked"),
    ] {
        let v = render(scene, &["--image", "96x64", "--timing", mode], &dir, false);
        let t = &v["frame"]["chip_timing"];
        assert_eq!(t["mode"], mode, "{scene}");
        let passes = t["passes"].as_array().unwrap();
        assert!(!passes.is_empty(), "{scene} {mode}");
        // Sampled: some passes scaled, each from an earlier clocked one.
        let scaled: Vec<(usize, u64)> = passes
            .iter()
            .enumerate()
            .filter_map(|(i, p)| p["scaled_from"].as_u64().map(|k| (i, k)))
            .collect();
        assert_eq!(
            !scaled.is_empty(),
            mode == "sampled" && scene == "fig6",
            "{scene} {mode}"
        );
        for (i, k) in scaled {
            assert!((k as usize) < i && passes[k as usize]["scaled_from"].is_null());
        }
        if scene == "glare-point" {
            assert_eq!(t["chip"], "glare-asic");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
