//! "Say when the hardware is out of its range" (issue 16): valid but extreme scenes
//! each get a warning naming the unit, the event and the scene field that drove the
//! unit there, and the nearest value it reports, applied, silences that warning; every
//! ordinary built-in gets none.
//!
//! The scenes are built-ins at 64 pixels wide (the width `frame::range` reduces a frame
//! to for its sensitivity check, so the check runs on the very frame tested) with at
//! most 10 sample planes and 2 sub-planes, so they run fast; the shadow maps keep the
//! built-ins' size (see tests/golden.rs on why).

use glare_pipeline::frame::range::{check, check_environment, RangeWarning, REDUCED_WIDTH};
use glare_pipeline::frame::run::render;
use glare_pipeline::scene::builtin::{builtin, BUILTIN_NAMES};
use glare_pipeline::scene::builtin_environment::ENVIRONMENT_BUILTIN_NAMES;
use glare_pipeline::scene::builtin_glare::GLARE_BUILTIN_NAMES;
use glare_pipeline::scene::builtin_showcase::SHOWCASE_NAMES;
use glare_pipeline::scene::format::Scene;

/// A built-in at the test size.
fn small(name: &str) -> Scene {
    let mut s = builtin(name).unwrap_or_else(|e| panic!("{name}: {e}"));
    let h = (s.image.height as f64 * REDUCED_WIDTH as f64 / s.image.width as f64).round();
    s.image.width = REDUCED_WIDTH;
    s.image.height = h as u32;
    s.shafts.planes = s.shafts.planes.min(10);
    s.shafts.subplanes = s.shafts.subplanes.min(2);
    s
}

/// Set a field by its path as a warning names it (`lights[0].intensity`,
/// `camera.eye`), from the value's text (a number or `[x, y, z]`), through the scene's
/// own TOML form.
fn set(scene: &Scene, path: &str, value: &str) -> Scene {
    let mut v = toml::Value::try_from(scene).expect("scene to TOML");
    let mut at = &mut v;
    let parts: Vec<&str> = path.split('.').collect();
    for (n, part) in parts.iter().enumerate() {
        let (key, index) = match part.split_once('[') {
            Some((k, i)) => (k, Some(i.trim_end_matches(']').parse::<usize>().unwrap())),
            None => (*part, None),
        };
        if n + 1 == parts.len() && index.is_none() {
            // The last key may be an optional field the TOML form leaves out.
            let t = at
                .as_table_mut()
                .unwrap_or_else(|| panic!("{path}: not a table"));
            t.entry(key).or_insert(toml::Value::Float(0.0));
        }
        at = at
            .get_mut(key)
            .unwrap_or_else(|| panic!("{path}: no `{key}`"));
        if let Some(i) = index {
            at = at.get_mut(i).unwrap_or_else(|| panic!("{path}: no [{i}]"));
        }
    }
    let parsed: toml::Value = toml::from_str(&format!("x = {value}"))
        .map(|t: toml::Table| t["x"].clone())
        .unwrap_or_else(|e| panic!("{path} = {value}: {e}"));
    *at = match parsed {
        toml::Value::Integer(i) => toml::Value::Float(i as f64),
        toml::Value::Array(a) => toml::Value::Array(
            a.into_iter()
                .map(|x| match x {
                    toml::Value::Integer(i) => toml::Value::Float(i as f64),
                    x => x,
                })
                .collect(),
        ),
        x => x,
    };
    let text = toml::to_string(&v).expect("TOML text");
    Scene::from_toml_str(&text).unwrap_or_else(|e| panic!("{path} = {value}: {e}"))
}

/// The warnings of a scene: the frame's, or the environment map's for one of the
/// thesis' environment scenes (they render through their own path, whose warnings are
/// the map's).
fn warnings(scene: &Scene) -> Vec<RangeWarning> {
    if scene.environment.is_some() && scene.lights.is_empty() && scene.glare.is_none() {
        return check_environment(scene);
    }
    let f = render(scene).unwrap_or_else(|e| panic!("{}: {e}", scene.name));
    check(scene, &f)
}

/// `scene` warns about `unit`'s `event`, driven by `field`; the nearest value applied
/// silences that unit's event.
fn assert_warns(scene: &Scene, unit: &str, event: &str, field: &str) {
    let ws = warnings(scene);
    for w in &ws {
        eprintln!("{w}");
    }
    let w = ws
        .iter()
        .find(|w| w.unit == unit && w.event == event)
        .unwrap_or_else(|| panic!("no `{unit}` {event} warning in {ws:#?}"));
    assert_eq!(w.field, field, "{w:#?}");
    assert!(w.share > w.threshold, "{w:#?}");
    let nearest = w
        .nearest
        .as_ref()
        .unwrap_or_else(|| panic!("no nearest value: {w:#?}"));
    assert_ne!(nearest, &w.value, "{w:#?}");
    let fixed = set(scene, field, nearest);
    let again = warnings(&fixed);
    assert!(
        !again.iter().any(|x| x.unit == unit && x.event == event),
        "{field} = {nearest} still warns: {again:#?}"
    );
}

#[test]
fn light_intensity_far_beyond_the_tables_saturates_the_blend() {
    let s = set(&small("fig6"), "lights[0].intensity", "1e6");
    assert_warns(&s, "additive_blend", "saturations", "lights[0].intensity");
}

#[test]
fn spot_cutoff_near_90_degrees_saturates_the_blend() {
    let s = set(&small("fig6"), "lights[0].cutoff_deg", "89.9");
    assert_warns(&s, "additive_blend", "saturations", "lights[0].cutoff_deg");
}

#[test]
fn near_far_ratio_of_1e9_loses_the_depth_buffers_resolution() {
    let s = set(&small("fig6"), "camera.near", "1e-8");
    let s = set(&s, "camera.far", "10");
    assert_warns(
        &s,
        "shadow_compare (depth buffer)",
        "depth resolution",
        "camera.near",
    );
}

#[test]
fn tiny_near_plane_in_the_four_light_stage_loses_depth_resolution() {
    let s = set(&small("stage"), "camera.near", "1e-7");
    assert_warns(
        &s,
        "shadow_compare (depth buffer)",
        "depth resolution",
        "camera.near",
    );
}

#[test]
fn camera_at_the_lights_position_saturates_the_blend() {
    let s = set(&small("fig6"), "camera.look_at", "[0, 0, 0.01]");
    let s = set(&s, "camera.eye", "[0, 9.5, 0]");
    assert_warns(&s, "additive_blend", "saturations", "camera.eye");
}

#[test]
fn tiny_light_distance_range_clamps_the_h_table() {
    let s = set(&small("fig6"), "shafts.s_max", "0.5");
    assert_warns(&s, "texture_sampler (h)", "table range", "shafts.s_max");
}

#[test]
fn tiny_eye_distance_range_clamps_the_h_table() {
    let s = set(&small("fig6"), "shafts.t_max", "0.5");
    assert_warns(&s, "texture_sampler (h)", "table range", "shafts.t_max");
}

/// In a frame of several lights, one far brighter than the rest sets the scale; the
/// others' colours round to zero in the interpolator, and the bright one is named.
#[test]
fn one_of_several_lights_far_too_bright_is_the_one_named() {
    let s = small("stage");
    assert!(s.lights.len() >= 3);
    let s = set(&s, "lights[1].intensity", "1e7");
    assert_warns(
        &s,
        "polygon_interpolator",
        "underflows",
        "lights[1].intensity",
    );
}

#[test]
fn dim_light_underflows_the_interpolated_light_colour() {
    let s = set(&small("fig6"), "lights[0].intensity", "0.01");
    assert_warns(
        &s,
        "polygon_interpolator",
        "underflows",
        "lights[0].intensity",
    );
}

#[test]
fn glare_source_far_too_bright_saturates_the_bloom_modulator() {
    let s = set(&small("glare-point"), "glare.sources[0].intensity", "3e7");
    assert_warns(
        &s,
        "bloom_flare_modulator",
        "saturations",
        "glare.sources[0].intensity",
    );
}

#[test]
fn glare_source_far_too_bright_saturates_the_combiner() {
    let s = set(&small("glare-flare"), "glare.sources[0].intensity", "3e7");
    assert_warns(
        &s,
        "glare_combiner",
        "saturations",
        "glare.sources[0].intensity",
    );
}

#[test]
fn environment_exposure_far_too_high_clamps_the_map() {
    let s = set(&small("env-pattern-sphere"), "environment.exposure", "100");
    assert_warns(
        &s,
        "texture_sampler (environment)",
        "table range",
        "environment.exposure",
    );
}

#[test]
fn environment_exposure_far_too_low_rounds_the_map_to_zero() {
    let s = set(&small("env-pattern-sphere"), "environment.exposure", "1e-4");
    assert_warns(
        &s,
        "texture_sampler (environment)",
        "underflows",
        "environment.exposure",
    );
}

#[test]
fn warnings_name_field_value_and_nearest_in_their_text() {
    let s = set(&small("fig6"), "lights[0].intensity", "1e6");
    let ws = warnings(&s);
    let line = ws
        .iter()
        .find(|w| w.unit == "additive_blend")
        .expect("a blend warning")
        .to_string();
    for part in [
        "warning:",
        "`additive_blend`",
        "saturations",
        "lights[0].intensity = 1000000",
        "nearest value that fits",
    ] {
        assert!(line.contains(part), "`{part}` missing from: {line}");
    }
}

#[test]
fn every_ordinary_builtin_warns_of_nothing() {
    let names = BUILTIN_NAMES
        .iter()
        .chain(GLARE_BUILTIN_NAMES)
        .chain(SHOWCASE_NAMES)
        .chain(ENVIRONMENT_BUILTIN_NAMES);
    let mut loud = Vec::new();
    let mut checked = 0;
    for name in names {
        let s = small(name);
        let ws = warnings(&s);
        checked += 1;
        if !ws.is_empty() {
            loud.push((name.to_string(), ws));
        }
    }
    assert!(checked >= 17, "only {checked} built-ins");
    assert!(loud.is_empty(), "ordinary built-ins warned: {loud:#?}");
}

/// Many sources that saturate the bloom modulator together, none alone: the check names every
/// source's intensity scaled by one factor, with a factor that fits, and renders a
/// bounded number of reduced frames however many sources there are (one per source
/// before, the whole check quadratic in the sources).
#[test]
fn many_glare_sources_together_are_named_as_one_scale_in_bounded_renders() {
    // 60 copies of glare-point's source on a grid around the centre, each a sixtieth
    // as bright, so that only their sum saturates.
    let mut s = small("glare-point");
    let g = s.glare.as_mut().unwrap();
    let one = g.sources[0].clone();
    g.sources = (0..60)
        .map(|i| {
            let mut c = one.clone();
            c.position[0] += 0.1 * (i % 10) as f64 - 0.45;
            c.position[1] += 0.1 * (i / 10) as f64 - 0.25;
            c.intensity = one.intensity / 60.0;
            c
        })
        .collect();
    let f = render(&s).unwrap();
    let (warnings, renders) = glare_pipeline::frame::range::check_counted(&s, &f);
    let w = warnings
        .iter()
        .find(|w| w.unit == "bloom_flare_modulator")
        .unwrap_or_else(|| panic!("no bloom modulator warning: {warnings:?}"));
    assert_eq!(w.field, "glare.sources[*].intensity", "{w}");
    let nearest = w.nearest.as_deref().unwrap_or_else(|| panic!("{w}"));
    assert!(
        nearest.starts_with('×') && nearest.contains("all 60 sources"),
        "{w}"
    );
    // Four single sources, the scale at its ordinary value, ten bisection steps and a
    // few snapping steps for this rule; at most five renders for each other rule.
    assert!(
        renders <= 4 + 1 + 10 + 10 + 5 * (warnings.len() - 1),
        "{renders} renders: {warnings:?}"
    );
    // The factor found fits: the reduced scene scaled by it is silent on the modulator.
    let x: f64 = nearest[nearest.char_indices().nth(1).unwrap().0..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let mut fitted = s.clone();
    for src in &mut fitted.glare.as_mut().unwrap().sources {
        src.intensity *= x;
    }
    let reduced = glare_pipeline::frame::range::reduced(&fitted);
    let g = render(&reduced).unwrap();
    let c = &g.counters()["glare"]["bloom_flare_modulator"];
    assert!(
        (c.saturations as f64) <= 0.01 * c.pixels_in as f64,
        "×{x}: {c:?}"
    );
}
