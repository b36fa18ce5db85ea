//! The assumptions ledger (issue 19, docs/assumptions.md): every alternative renders
//! on a reduced image and differs from the default where it should; the new scene
//! fields parse by name, refuse a bad value naming the field, and default to the
//! model's readings (the golden test holds the defaults' bytes).

mod common;

use common::Scratch;
use glare_pipeline::frame::assumptions::{
    assumptions, render_picture, scene_named, Reduced, ALTERNATIVES, WATER_SCENE,
};
use glare_pipeline::scene::builtin::builtin_toml;
use glare_pipeline::scene::format::Scene;

const REDUCED: Reduced = Reduced {
    width: 96,
    height: 64,
    planes: 8,
    subplanes: 2,
    env_size: 24,
    env_side: 16,
};

/// Run `reproduce assumptions`' code for one assumption on reduced images: every
/// (alternative, scene) pair renders, changes the picture, and the CSV and the
/// assumption's strip are written.
fn renders_and_differs(assumption: &str) {
    let dir = Scratch::new("assumptions", &assumption.replace('.', "_"));
    let rows = assumptions(&dir, Some(REDUCED), Some(assumption)).unwrap();
    let want: usize = ALTERNATIVES
        .iter()
        .filter(|a| a.assumption == assumption)
        .map(|a| a.scenes.len())
        .sum();
    assert!(want > 0, "{assumption}: no alternative");
    assert_eq!(rows.len(), want, "one row per (alternative, scene)");
    for r in &rows {
        assert_eq!(r.assumption, assumption);
        assert!(
            r.rms_levels.is_finite() && r.max_levels.is_finite(),
            "{} on {}: non-finite difference",
            r.alternative,
            r.scene
        );
        assert!(
            r.changed_pixels > 0 && r.max_levels >= 1.0,
            "{} on {}: the alternative left the picture unchanged",
            r.alternative,
            r.scene
        );
    }
    let csv = std::fs::read_to_string(dir.join("assumptions.csv")).unwrap();
    assert_eq!(csv.lines().count(), want + 1, "header + rows");
    let png = dir.join(format!("assumptions_{}.png", assumption.replace('.', "_")));
    let img = image::open(&png).unwrap_or_else(|e| panic!("{}: {e}", png.display()));
    assert!(img.width() > REDUCED.env_size && img.height() >= REDUCED.env_size);
}

/// The assumptions tested one by one below; a new alternative needs its test.
const TESTED: &[&str] = &[
    "glare.bloom_angle_scale",
    "glare.halo_amplitude",
    "glare.halo_radius",
    "glare.bloom_range",
    "glare.water_eta",
    "envmap.exposure_rule",
    "envmap.weighting",
    "envmap.dome_pick",
    "shafts.f_scale",
    "shafts.h_cap",
    "shafts.plane_step",
];

#[test]
fn every_assumption_has_its_test() {
    let mut names: Vec<&str> = ALTERNATIVES.iter().map(|a| a.assumption).collect();
    names.dedup();
    assert_eq!(names, TESTED);
}

#[test]
fn bloom_angle_scale_renders_and_differs() {
    renders_and_differs("glare.bloom_angle_scale");
}

#[test]
fn halo_amplitude_renders_and_differs() {
    renders_and_differs("glare.halo_amplitude");
}

#[test]
fn halo_radius_renders_and_differs() {
    renders_and_differs("glare.halo_radius");
}

#[test]
fn bloom_range_renders_and_differs() {
    renders_and_differs("glare.bloom_range");
}

#[test]
fn water_eta_renders_and_differs() {
    renders_and_differs("glare.water_eta");
}

#[test]
fn exposure_rule_renders_and_differs() {
    renders_and_differs("envmap.exposure_rule");
}

#[test]
fn weighting_renders_and_differs() {
    renders_and_differs("envmap.weighting");
}

#[test]
fn dome_pick_renders_and_differs() {
    renders_and_differs("envmap.dome_pick");
}

/// The dome pick on the maps themselves (`assumptions_maps.csv`, side 16): both picks
/// are measured against the exact prefilter, and they build different maps.
#[test]
fn dome_pick_maps_differ_against_the_exact_map() {
    let rows = glare_pipeline::frame::assumptions::dome_pick_maps(16).unwrap();
    assert_eq!(rows.len(), 4, "two maps × two picks");
    for pair in rows.chunks(2) {
        let (def, alt) = (&pair[0], &pair[1]);
        assert_eq!(def.env, alt.env);
        assert!(def.dome_pick.contains("half_weight") && alt.dome_pick.contains("voxel_spacing"));
        for r in pair {
            assert!(r.mean_abs_levels.is_finite() && r.max_abs_levels >= r.mean_abs_levels);
        }
        assert!(
            (def.mean_abs_levels, def.max_abs_levels, def.changed_voxels)
                != (alt.mean_abs_levels, alt.max_abs_levels, alt.changed_voxels),
            "{}: the two picks built the same map",
            def.env
        );
    }
}

/// The literal pick is the voxel spacing of eq. (12): the dome chosen at |t| is the
/// coarsest whose vertex spacing atan 2 / n is ≤ atan(2 / (|t|·s)) — computed here from
/// eq. (12) directly, while the prefilter derives it from Λ = g(|t|) via eq. (13) — and
/// it is never finer than the model's pick.
#[test]
fn voxel_spacing_pick_follows_eq12() {
    use glare_pipeline::pipeline::envmap::prefilter::{
        dome_frequencies, env_to_levels, Accelerated, DomePick,
    };
    use glare_pipeline::reference::envmap_prefilter::PrefilterParams;
    use glare_pipeline::scene::envmap::EnvMap;
    let s = 128;
    let env = EnvMap::pattern(512, 256);
    let lv = env_to_levels(&env, 1.0).unwrap();
    let def = Accelerated::new(&lv, s, &PrefilterParams::thesis(), 0.001).unwrap();
    let alt = def.clone().with_dome_pick(DomePick::VoxelSpacing);
    let spacing = dome_frequencies(s).map(|n| 2f64.atan() / n as f64);
    let mut coarser = 0;
    for r in [0.03, 0.1, 0.2, 0.4, 0.7, 0.95] {
        let t = [r * 0.6, r * 0.8, 0.0];
        let psi = (2.0 / (r * s as f64)).atan();
        let want = (0..4).rev().find(|&k| spacing[k] <= psi).unwrap_or(0);
        assert_eq!(alt.level(t), want, "|t| = {r}: ψ_voxel = {psi}");
        assert!(alt.level(t) >= def.level(t), "|t| = {r}");
        coarser += usize::from(alt.level(t) > def.level(t));
    }
    assert!(
        coarser >= 3,
        "the literal pick is coarser on {coarser} of 6 shells"
    );
}

#[test]
fn f_scale_renders_and_differs() {
    renders_and_differs("shafts.f_scale");
}

#[test]
fn h_cap_renders_and_differs() {
    renders_and_differs("shafts.h_cap");
}

#[test]
fn plane_step_renders_and_differs() {
    renders_and_differs("shafts.plane_step");
}

/// Δt = Δr on every ray under-weights off-axis rays against Δr·t/r (t/r ≥ 1), with
/// the tables unchanged: no pixel gets brighter, and the frame's beam is dimmer
/// (fig4 at 96 × 64, 8 planes).
#[test]
fn plane_spacing_dims_the_off_axis_rays() {
    let mut s = scene_named("fig4").unwrap();
    s.image.width = 96;
    s.image.height = 64;
    s.shafts.planes = 8;
    let def = render_picture(&s).unwrap();
    s.shafts.plane_step = glare_pipeline::scene::format::PlaneStep::PlaneSpacing;
    let alt = render_picture(&s).unwrap();
    for (i, (a, d)) in alt.levels.iter().zip(&def.levels).enumerate() {
        for c in 0..3 {
            assert!(a[c] <= d[c], "pixel {i} channel {c}: {} > {}", a[c], d[c]);
        }
    }
    let sum = |p: &[[f64; 3]]| p.iter().flatten().sum::<f64>();
    assert!(
        sum(&def.levels) > sum(&alt.levels),
        "Δt = Δr·t/r ≥ Δr: {} vs {}",
        sum(&def.levels),
        sum(&alt.levels)
    );
}

/// The water reading decides whether the puddle glares: under η = 1.33 the highlight
/// becomes a glare source (it adds bloom around itself), under 1/1.33 it is only its
/// saturated core, so the default picture is brighter.
#[test]
fn water_eta_reading_decides_the_glare() {
    let mut s = scene_named(WATER_SCENE).unwrap();
    s.image.width = 96;
    s.image.height = 64;
    let def = render_picture(&s).unwrap();
    s.glare.as_mut().unwrap().model.water_eta =
        glare_pipeline::scene::glare::WaterEta::AirOverMedia;
    let alt = render_picture(&s).unwrap();
    let sum = |p: &[[f64; 3]]| p.iter().flatten().sum::<f64>();
    assert!(
        sum(&def.levels) > sum(&alt.levels),
        "η = 1.33 glares, η = 0.75 cannot: {} vs {}",
        sum(&def.levels),
        sum(&alt.levels)
    );
}

/// The fields by name in a scene file, and the built-ins unchanged by default.
#[test]
fn fields_parse_by_name_and_default_to_the_model() {
    let base = builtin_toml("street-light").unwrap();
    // The defaults are written out by `scene` and read back unchanged.
    for f in [
        "halo_amplitude = \"intensity\"",
        "halo_radius = \"diameter_half\"",
        "bloom_range = \"cutoff_14\"",
        "water_eta = \"media_over_air\"",
        "h_cap = \"one_plane\"",
    ] {
        assert!(base.contains(f), "`scene street-light` lacks {f}");
    }
    let set = |from: &str, to: &str| -> Scene {
        assert!(base.contains(from), "{from}");
        Scene::from_toml_str(&base.replacen(from, to, 1)).unwrap()
    };
    let s = set(
        "halo_amplitude = \"intensity\"",
        "halo_amplitude = \"ambient_x10\"",
    );
    let m = s.glare.as_ref().unwrap().model;
    assert_eq!(m.halo_amplitude_for(1000.0, 4.0), 40.0);
    let s = set(
        "halo_radius = \"diameter_half\"",
        "halo_radius = \"spencer\"",
    );
    assert_eq!(s.glare.as_ref().unwrap().model.halo_ring_radius_deg(), 3.0);
    let s = set("bloom_range = \"cutoff_14\"", "bloom_range = \"eq1_8deg\"");
    assert_eq!(s.glare.as_ref().unwrap().model.bloom_range.limit_deg(), 8.0);
    let s = set(
        "water_eta = \"media_over_air\"",
        "water_eta = \"air_over_media\"",
    );
    assert!((s.glare.as_ref().unwrap().model.water_eta_for(1.33) - 0.75188).abs() < 1e-4);
    let s = set("bloom_w_deg = 0.3", "bloom_angle_scale_deg = 1.0");
    assert_eq!(s.glare.as_ref().unwrap().model.bloom_w_deg, 1.0);
    let s = set("h_cap = \"one_plane\"", "h_cap = \"none\"");
    assert_eq!(s.shafts.h_cap, glare_pipeline::scene::format::HCap::None);
    // plane_step is written only when not the default (the built-ins' files and sweep
    // identities are unchanged).
    assert!(!base.contains("plane_step"));
    let s = set(
        "h_cap = \"one_plane\"",
        "h_cap = \"one_plane\"\nplane_step = \"plane_spacing\"",
    );
    assert_eq!(
        s.shafts.plane_step,
        glare_pipeline::scene::format::PlaneStep::PlaneSpacing
    );
}

/// A bad value is refused naming its field.
#[test]
fn bad_values_name_their_field() {
    let base = builtin_toml("street-light").unwrap();
    for (from, to, field) in [
        (
            "halo_amplitude = \"intensity\"",
            "halo_amplitude = \"ambient_x20\"",
            "glare.model.halo_amplitude",
        ),
        (
            "halo_radius = \"diameter_half\"",
            "halo_radius = \"diameter\"",
            "glare.model.halo_radius",
        ),
        (
            "bloom_range = \"cutoff_14\"",
            "bloom_range = 8",
            "glare.model.bloom_range",
        ),
        (
            "water_eta = \"media_over_air\"",
            "water_eta = \"1/media\"",
            "glare.model.water_eta",
        ),
        ("h_cap = \"one_plane\"", "h_cap = \"half\"", "shafts.h_cap"),
        (
            "h_cap = \"one_plane\"",
            "h_cap = \"one_plane\"\nplane_step = \"ray\"",
            "shafts.plane_step",
        ),
    ] {
        let e = Scene::from_toml_str(&base.replacen(from, to, 1)).unwrap_err();
        assert_eq!(e.field(), field, "{to}: {e}");
    }
    let env = builtin_toml("env-venice_sunset-sphere").unwrap();
    let e = Scene::from_toml_str(&env.replacen(
        "[environment]\n",
        "[environment]\nexposure_rule = \"p98\"\n",
        1,
    ))
    .unwrap_err();
    assert_eq!(e.field(), "environment.exposure_rule", "{e}");
    let e = Scene::from_toml_str(&env.replacen(
        "[environment]\n",
        "[environment]\nweighting = \"area\"\n",
        1,
    ))
    .unwrap_err();
    assert_eq!(e.field(), "environment.weighting", "{e}");
    let e = Scene::from_toml_str(&env.replacen(
        "[environment]\n",
        "[environment]\ndome_pick = \"coarse\"\n",
        1,
    ))
    .unwrap_err();
    assert_eq!(e.field(), "environment.dome_pick", "{e}");
    // The pick is the accelerated build's: with the exact prefilter it is refused.
    let exact = env.replacen(
        "[environment]\n",
        "[environment]\ndome_pick = \"voxel_spacing\"\n",
        1,
    );
    assert!(
        Scene::from_toml_str(&exact).is_ok(),
        "the built-in is accelerated"
    );
    let accelerated = "type = \"accelerated\"\nthreshold = 0.001";
    assert!(exact.contains(accelerated));
    let e = Scene::from_toml_str(&exact.replace(accelerated, "type = \"exact\"")).unwrap_err();
    assert_eq!(e.field(), "environment.dome_pick", "{e}");
    // An explicit exposure leaves no rule to apply: both at once is refused.
    let e = Scene::from_toml_str(&env.replacen(
        "[environment]\n",
        "[environment]\nexposure = 0.5\nexposure_rule = \"max\"\n",
        1,
    ))
    .unwrap_err();
    assert_eq!(e.field(), "environment.exposure_rule", "{e}");
}

/// The ledger names every assumption that has an alternative here.
#[test]
fn ledger_lists_every_alternative() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/assumptions.md"))
        .unwrap();
    for a in ALTERNATIVES {
        assert!(
            doc.contains(a.assumption) && doc.contains(a.alternative),
            "docs/assumptions.md lacks {} / {}",
            a.assumption,
            a.alternative
        );
    }
}
