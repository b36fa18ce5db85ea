//! One frame through every pipeline: the showcase's plan, its chip against the
//! reduced variants', every pipeline's visible contribution, the error bound, and
//! thread-count independence (a reduced `night-street`).

use glare_pipeline::frame::chip::{elaborate, Chip, Feature};
use glare_pipeline::frame::plan::{plan, Step};
use glare_pipeline::frame::reproduce::{frame_error, variants};
use glare_pipeline::frame::run::render;
use glare_pipeline::pipeline::shafts::frame::ShaftsPass;
use glare_pipeline::scene::builtin_showcase::night_street;
use glare_pipeline::scene::format::Scene;
use std::collections::BTreeSet;

mod common;

/// Each pass's documented bound: (pass name prefix, mean |Δ|, RMS) in 8-bit levels on the
/// pass's own pixels (docs/frame.md "What each pass is held to").
const PASS_BOUNDS: [(&str, f64, f64); 3] = [
    ("shafts", 4.0, 22.0),
    ("objects", 0.5, 3.0),
    ("glare", 1.0, 2.5),
];

/// night-street at a test size: 144 × 96, 8 planes, 2 sub-planes, 128² shadow maps,
/// the environment map at s = 16.
fn small() -> Scene {
    let mut s = night_street();
    s.image.width = 144;
    s.image.height = 96;
    s.shafts.planes = 8;
    s.shafts.subplanes = 2;
    s.shafts.shadow_resolution = 128;
    if let Some(e) = s.environment.as_mut() {
        e.side = 16;
    }
    s
}

fn present(c: &Chip) -> BTreeSet<&'static str> {
    c.present().map(|u| u.instance).collect()
}

#[test]
fn showcase_plan_has_every_pass() {
    let s = night_street();
    let p = plan(&s).unwrap();
    let steps: Vec<Step> = p.passes.iter().map(|p| p.step).collect();
    assert_eq!(steps[0], Step::Shafts(ShaftsPass::Depth));
    assert_eq!(
        steps[1],
        Step::ShadedObjects,
        "the object pass follows the depth pass"
    );
    for light in 0..2 {
        for sp in [
            ShaftsPass::ShadowMap { light },
            ShaftsPass::Objects { light },
            ShaftsPass::Planes { light },
        ] {
            assert!(steps.contains(&Step::Shafts(sp)), "{sp:?}");
        }
    }
    assert_eq!(
        *steps.last().unwrap(),
        Step::Glare,
        "glare is the last pass"
    );
}

/// Each reduced variant elaborates strictly fewer units and gates than the showcase,
/// and what it leaves out beyond the showcase is exactly the units of the features it
/// lacks, each with that feature's reason.
#[test]
fn each_variant_leaves_out_exactly_its_features_units() {
    let base = night_street();
    let vs = variants(&base);
    let full = elaborate(&vs[0].scene);
    assert!(vs[0].missing.is_empty());
    let full_present = present(&full);
    for v in &vs[1..] {
        let chip = elaborate(&v.scene);
        let mine = present(&chip);
        assert!(mine.is_subset(&full_present), "{}", v.name);
        assert!(
            mine.len() < full_present.len(),
            "{}: not fewer units",
            v.name
        );
        assert!(chip.gates() < full.gates(), "{}: not fewer gates", v.name);
        let dropped: BTreeSet<&str> = full_present.difference(&mine).copied().collect();
        // A glare unit that highlights also need (the halo and the flare lines'
        // noise: a highlight that passes the conditions gets both) goes with them.
        let for_highlights = |instance: &str| {
            v.missing.contains(&Feature::Highlights)
                && chip.units.iter().any(|u| {
                    u.instance == instance
                        && u.left_out
                            .is_some_and(|w| w.ends_with("no highlight to test"))
                })
        };
        let expected: BTreeSet<&str> = full
            .present()
            .filter(|u| v.missing.contains(&u.feature) || for_highlights(u.instance))
            .map(|u| u.instance)
            .collect();
        assert!(!expected.is_empty(), "{}: the feature had units", v.name);
        assert_eq!(dropped, expected, "{}", v.name);
        for u in chip
            .left_out()
            .filter(|u| expected.contains(u.instance) && v.missing.contains(&u.feature))
        {
            assert_eq!(
                u.left_out,
                Some(u.feature.absent_because()),
                "{}: {}",
                v.name,
                u.instance
            );
        }
    }
}

/// A Lambert-only scene without glare, fog or environment keeps the bare object
/// path: no combiner stage, no sampler beyond the light map's.
#[test]
fn a_plain_scene_elaborates_the_plain_chip() {
    let s = glare_pipeline::scene::builtin::builtin("fig6").unwrap();
    let chip = elaborate(&s);
    for u in chip.present() {
        assert!(
            matches!(
                u.feature,
                Feature::Objects | Feature::Shadows | Feature::LightMaps | Feature::Fog
            ),
            "{}",
            u.instance
        );
    }
    assert!(chip.present().all(|u| u.unit != "texture_combiner"));
}

/// Every pipeline visibly changes the showcase frame: removing fog, glare, the
/// environment map or the materials changes pixels; the total error stays within the
/// sum of the per-pass errors.
#[test]
fn every_pipeline_contributes_and_the_error_is_bounded() {
    let base = small();
    let full = render(&base).unwrap();
    let e = frame_error(&base, &full, None).unwrap();
    assert!(e.total.mean_abs_frame <= e.bound + 1e-9, "{e:?}");
    assert_eq!(
        e.passes.len(),
        3,
        "shafts, objects and glare are compared: {e:?}"
    );
    // Each pass against its own figure (docs/frame.md "What each pass is held to"),
    // stated before the run, not against the passes' observed sum.
    let held = common::docs::section("frame.md", "### What each pass is held to");
    for p in &e.passes {
        let (prefix, mean, rms) = PASS_BOUNDS
            .iter()
            .copied()
            .find(|(name, _, _)| p.pass.starts_with(name))
            .unwrap_or_else(|| panic!("no documented bound for pass {}", p.pass));
        let row = format!("| {prefix} |");
        common::docs::assert_quotes(&held, &row, "docs/frame.md's bounds table");
        let row_text = held.split(&row).nth(1).unwrap_or_default();
        let cells: Vec<&str> = row_text.split('|').map(str::trim).collect();
        let number = |i: usize| cells.get(i).and_then(|c| c.parse::<f64>().ok());
        assert_eq!(
            (number(1), number(2)),
            (Some(mean), Some(rms)),
            "docs/frame.md quotes {prefix}'s bounds: {row_text}"
        );
        eprintln!(
            "{}: mean {:.2}, RMS {:.1} levels (held to {mean}, {rms})",
            p.pass, p.mean_abs, p.rms
        );
        assert!(
            p.mean_abs <= mean && p.rms <= rms,
            "{}: mean {:.3} (≤ {mean}), RMS {:.3} (≤ {rms})",
            p.pass,
            p.mean_abs,
            p.rms
        );
    }
    for v in variants(&base).into_iter().skip(1) {
        let f = render(&v.scene).unwrap();
        let differing =
            f.fb.data
                .iter()
                .zip(&full.fb.data)
                .filter(|(a, b)| a != b)
                .count();
        assert!(
            differing > 20,
            "{}: only {differing} channel codes differ",
            v.name
        );
    }
    let shaded = full.shaded.as_ref().unwrap();
    assert!(
        !shaded.highlights.is_empty(),
        "the shading units found highlights"
    );
}

#[test]
fn same_bytes_on_one_and_two_threads() {
    let s = small();
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let one = pool(1).install(|| render(&s).unwrap());
    let two = pool(2).install(|| render(&s).unwrap());
    assert_eq!(one.fb, two.fb);
    assert_eq!(
        serde_json::to_string(&one.counters()).unwrap(),
        serde_json::to_string(&two.counters()).unwrap()
    );
}

/// `render`'s progress bar (issue 16): with a (hidden) bar the frame is the same bytes
/// and counters as without, and the bar reached its length: one step per sample plane
/// of each light's planes pass and one per other pass, counted here from the plan.
#[test]
fn the_progress_bar_reaches_its_length_and_changes_nothing() {
    use glare_pipeline::frame::run::render_with_progress;
    let s = small();
    let p = plan(&s).unwrap();
    let planes_passes = p
        .passes
        .iter()
        .filter(|p| matches!(p.step, Step::Shafts(ShaftsPass::Planes { .. })))
        .count() as u64;
    assert!(planes_passes >= 1, "night-street has lights in a medium");
    let want = planes_passes * u64::from(s.shafts.planes) + (p.passes.len() as u64 - planes_passes);
    let plain = render(&s).unwrap();
    let (f, (pos, len)) = render_with_progress(&s, false).unwrap();
    assert_eq!(
        len, want,
        "steps: {planes_passes} planes passes of {} planes + the other passes",
        s.shafts.planes
    );
    assert_eq!(pos, len, "the bar stopped short of its length");
    assert_eq!(f.fb, plain.fb);
    assert_eq!(
        serde_json::to_string(&f.counters()).unwrap(),
        serde_json::to_string(&plain.counters()).unwrap()
    );
}

/// The registry unit a counters or elaboration row names: the chip's unit of the
/// instance the row starts with (`frame::chip::INSTANCES`), else the first registry
/// unit it names: `objects[0]:
/// cube_map_address (normalisation cube)` → `cube_map_address`, `objects[0]: factor
/// textures (texture_sampler × modulate)` → `texture_sampler`.
fn unit_of(row: &str) -> String {
    let names: Vec<String> = glare_pipeline::registry::summaries()
        .iter()
        .map(|s| s.name.to_string())
        .collect();
    let r = row.split_once(": ").map_or(row, |(_, r)| r);
    // An instance the chip's own table names (`additive_blend (J buffer)` is `blend`'s
    // additive datapath): the longest instance name the row starts with, as a whole word.
    let instance = glare_pipeline::frame::chip::INSTANCES
        .iter()
        .filter(|(i, _, _)| {
            r.strip_prefix(i)
                .is_some_and(|rest| !rest.starts_with(|c: char| c.is_alphanumeric() || c == '_'))
        })
        .max_by_key(|(i, _, _)| i.len());
    if let Some((_, unit, _)) = instance {
        return unit.to_string();
    }
    r.split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .find(|t| names.iter().any(|n| n == t))
        .unwrap_or_else(|| panic!("{row}: names no registry unit"))
        .to_string()
}

/// One chip report: for every built-in drawn through the frame (small), each unit
/// whose counters show work is present in the chip elaborated before the passes run,
/// and the chip `render` reports after them (the frame's elaboration) never lists a
/// unit that ran as left out.
#[test]
fn units_that_ran_are_never_left_out() {
    use glare_pipeline::scene::load::{builtin_names, load_scene};
    let mut checked = 0;
    for name in builtin_names() {
        let mut s = load_scene(name).unwrap();
        if glare_pipeline::frame::plan::environment_scene(&s) {
            continue;
        }
        s.image.width = 96;
        s.image.height = 64;
        s.shafts.planes = s.shafts.planes.min(4);
        s.shafts.subplanes = s.shafts.subplanes.min(2);
        if let Some(e) = s.environment.as_mut() {
            e.side = 16;
        }
        let chip = elaborate(&s);
        let f = render(&s).unwrap_or_else(|e| panic!("{name}: {e}"));
        let elaboration = f.elaboration();
        for (pipeline, counters) in f.counters() {
            for (row, c) in counters {
                if c.pixels_in == 0 {
                    continue;
                }
                let unit = unit_of(&row);
                assert!(
                    chip.present().any(|u| u.unit == unit.as_str()),
                    "{name}: {pipeline} ran {row} ({} pixels) but the chip has no {unit} present",
                    c.pixels_in
                );
                let named_left_out = elaboration
                    .iter()
                    .filter(|e| e.left_out.is_some())
                    .any(|e| e.name == row);
                assert!(
                    !named_left_out,
                    "{name}: {row} ran {} pixels but the chip says it was left out",
                    c.pixels_in
                );
            }
        }
        checked += 1;
    }
    assert!(checked >= 10, "only {checked} built-ins checked");
}

/// An environment-map scene's chip has the interpolator its pass runs.
#[test]
fn environment_scene_chip_has_its_interpolator() {
    let s = glare_pipeline::scene::load::load_scene("env-pattern-teapot").unwrap();
    let chip = elaborate(&s);
    for unit in [
        "polygon_interpolator",
        "reflection_vector",
        "texture_sampler",
    ] {
        assert!(chip.present().any(|u| u.unit == unit), "{unit}");
    }
}
