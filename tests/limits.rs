//! One source of limits (issue 16): for every scene field that ends up in a unit's
//! config, validation (`frame::check::check_scene_text`, the path every scene takes
//! before its first pixel) accepts a value exactly when the pipeline's own code builds
//! its units from it without error, and every refusal names the scene field as the
//! user wrote it (`shafts.texel_bits`, `glare.hw.noise_bits`), never a unit's internal
//! name (`texture_sampler.texel_bits`).
//!
//! The oracle is the pipeline itself, on the scene NOT validated: the shafts frame of a
//! small fig6 (prepared by `prepare_scene_unchecked`, rendered by `render_frame`: every
//! unit the frame uses is built, every vertex quantised), the glare frame of a small
//! point source with bloom, halo and flare (`render_glare`). A panic of the pipeline on
//! a value validation refuses counts as a refusal (it can never be reached by a user);
//! on a value validation accepts, it fails the test. Values are drawn on both sides of
//! each unit's range (proptest); table sizes and map sides at their boundaries.

use glare_pipeline::frame::check::check_scene_text;
use glare_pipeline::pipeline::glare::frame::render_glare;
use glare_pipeline::pipeline::shafts::frame::render_frame;
use glare_pipeline::pipeline::shafts::host::prepare_scene_unchecked;
use glare_pipeline::pipeline::shafts::prepare::DEFAULT_EXPOSURE;
use glare_pipeline::scene::builtin::builtin;
use glare_pipeline::scene::format::Scene;
use glare_pipeline::scene::limits::ENV_MAX_SIDE;
use glare_pipeline::scene::validate::IMAGE_MAX;
use proptest::prelude::*;
use rtl_model::units::shadow_compare::{MAX_DEPTH_BITS, MAX_MAP_SIDE};
use rtl_model::units::texture_sampler::MAX_SIZE;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// fig6 made small: every shafts unit is still built (the sphere and floor occlude, so
/// the depth buffer and shadow map exist; m = 2 builds the J path).
fn small_shafts() -> Scene {
    let mut s = builtin("fig6").unwrap();
    s.image.width = 24;
    s.image.height = 16;
    s.shafts.planes = 2;
    s.shafts.subplanes = 2;
    s.shafts.mesh = [2, 2];
    s.shafts.f_texels = 16;
    s.shafts.h_texels = [16, 16];
    s.shafts.shadow_resolution = 16;
    s.shafts.light_map_texels = 16;
    s
}

/// A point source with bloom, halo and flare lines over a black background, small.
fn small_glare() -> Scene {
    let mut s = builtin("glare-point").unwrap();
    s.image.width = 32;
    s.image.height = 24;
    let g = s.glare.as_mut().unwrap();
    g.sources[0].halo = true;
    g.sources[0].flare = true;
    s
}

/// Validation's verdict, on the scene's TOML text (as a user's file would be read).
fn validation(s: &Scene) -> Result<(), String> {
    let text = toml::to_string(s).expect("a scene serialises");
    check_scene_text(&text)
        .map(|_| ())
        .map_err(|e| e.field().to_string())
}

/// The units' verdict: the pipeline's code on the unvalidated scene.
fn shafts_units(s: &Scene) -> bool {
    let run = || -> Result<(), rtl_model::ConfigError> {
        let (p, _) = prepare_scene_unchecked(s, DEFAULT_EXPOSURE)?;
        render_frame(&p).map(|_| ())
    };
    matches!(catch_unwind(AssertUnwindSafe(run)), Ok(Ok(())))
}

fn glare_units(s: &Scene) -> bool {
    let run = || render_glare(s).map(|_| ());
    matches!(catch_unwind(AssertUnwindSafe(run)), Ok(Ok(())))
}

/// The property: accepted ⇔ built; a refusal names `field`.
fn agree(s: &Scene, field: &str, units: bool, value: u32) {
    match validation(s) {
        Ok(()) => assert!(
            units,
            "{field} = {value}: validation accepts it, the units refuse it (or panic)"
        ),
        Err(named) => {
            assert!(
                !units,
                "{field} = {value}: validation refuses it (naming {named}), the units build"
            );
            assert_eq!(named, field, "{field} = {value}: the refusal names {named}");
        }
    }
}

type Set = fn(&mut Scene, u32);

/// The shafts widths: [scene field, largest value drawn, setter]. Values are drawn
/// from 0 to two past the unit's range (16 for the unorm widths, weights and
/// fraction bits; `MAX_DEPTH_BITS` for the depth): far beyond it the pipeline, which
/// trusts validation, would be asked for tables of 2^width entries.
const SHAFTS_WIDTHS: [(&str, u32, Set); 5] = [
    ("shafts.texel_bits", 18, |s, v| s.shafts.texel_bits = v),
    ("shafts.fb_bits", 18, |s, v| s.shafts.fb_bits = v),
    ("shafts.weight_bits", 18, |s, v| s.shafts.weight_bits = v),
    ("shafts.coord_frac_bits", 18, |s, v| {
        s.shafts.coord_frac_bits = v
    }),
    ("shafts.shadow_depth_bits", MAX_DEPTH_BITS + 2, |s, v| {
        s.shafts.shadow_depth_bits = v
    }),
];

/// The glare widths, drawn from 0 to past the luminance RAM's, the noise generator's
/// and the combiner's ranges (the log2 sizes only one past: the tables are 2^k).
const GLARE_WIDTHS: [(&str, u32, Set); 8] = [
    ("glare.hw.shape_log2", 11, |s, v| {
        s.glare.as_mut().unwrap().hw.shape_log2 = v
    }),
    ("glare.hw.shape_bits", 18, |s, v| {
        s.glare.as_mut().unwrap().hw.shape_bits = v
    }),
    ("glare.hw.falloff_log2", 13, |s, v| {
        s.glare.as_mut().unwrap().hw.falloff_log2 = v
    }),
    ("glare.hw.falloff_bits", 22, |s, v| {
        s.glare.as_mut().unwrap().hw.falloff_bits = v
    }),
    ("glare.hw.weight_bits", 14, |s, v| {
        s.glare.as_mut().unwrap().hw.weight_bits = v
    }),
    ("glare.hw.coord_frac_bits", 18, |s, v| {
        s.glare.as_mut().unwrap().hw.coord_frac_bits = v
    }),
    ("glare.hw.noise_bits", 34, |s, v| {
        s.glare.as_mut().unwrap().hw.noise_bits = v
    }),
    ("glare.hw.fb_bits", 18, |s, v| {
        s.glare.as_mut().unwrap().hw.fb_bits = v
    }),
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    /// Shafts widths on both sides of every unit's range (1 ..= 16 for the unorm
    /// widths, 0 ..= 16 fraction bits, 1 ..= 32 depth bits).
    #[test]
    fn shafts_widths_agree(k in 0..SHAFTS_WIDTHS.len(), x in 0.0f64..1.0) {
        let (field, top, set) = SHAFTS_WIDTHS[k];
        let v = (x * (top + 1) as f64) as u32;
        let mut s = small_shafts();
        set(&mut s, v);
        agree(&s, field, shafts_units(&s), v);
    }

    /// Glare widths on both sides of the luminance RAM's, the noise generator's and
    /// the combiner's ranges (which end at 10, 12, 16, 20 and 32).
    #[test]
    fn glare_widths_agree(k in 0..GLARE_WIDTHS.len(), x in 0.0f64..1.0) {
        let (field, top, set) = GLARE_WIDTHS[k];
        let v = (x * (top + 1) as f64) as u32;
        let mut s = small_glare();
        set(&mut s, v);
        agree(&s, field, glare_units(&s), v);
    }
}

/// Table sizes and map sides at the ends of their ranges (a render at 4096 texels per
/// axis is cheap for the 1D and 2D tables; the largest shadow map is built but a render
/// over it would take a debug build minutes, so it is rendered at a small image).
#[test]
fn shafts_sizes_agree() {
    let sizes = [
        0,
        1,
        2,
        3,
        MAX_SIZE - 1,
        MAX_SIZE,
        MAX_SIZE + 1,
        2 * MAX_SIZE,
    ];
    let cases: [(&str, Set); 3] = [
        ("shafts.f_texels", |s, v| s.shafts.f_texels = v),
        ("shafts.h_texels[0]", |s, v| s.shafts.h_texels[0] = v),
        ("shafts.h_texels[1]", |s, v| s.shafts.h_texels[1] = v),
    ];
    for (field, set) in cases {
        for v in sizes {
            let mut s = small_shafts();
            set(&mut s, v);
            if v < 2 {
                // The scene's own rule (a table lerps between two texels at least);
                // a one-texel sampler is valid to the unit.
                assert_eq!(validation(&s), Err(field.to_string()), "{field} = {v}");
            } else {
                agree(&s, field, shafts_units(&s), v);
            }
        }
    }
    for v in [0, 1, 2, MAX_MAP_SIDE + 1, 2 * MAX_MAP_SIDE] {
        let mut s = small_shafts();
        s.shafts.shadow_resolution = v;
        agree(&s, "shafts.shadow_resolution", shafts_units(&s), v);
    }
    // The largest map side validates, and the pipeline builds the shadow map unit.
    let mut s = small_shafts();
    s.shafts.shadow_resolution = MAX_MAP_SIDE;
    assert_eq!(validation(&s), Ok(()));
    // The light map: a power of two up to the sampler's axis.
    for (v, ok) in [(1, false), (2, true), (3, false), (MAX_SIZE * 2, false)] {
        let mut s = small_shafts();
        s.shafts.light_map_texels = v;
        match validation(&s) {
            Ok(()) => assert!(ok, "light_map_texels = {v} accepted"),
            Err(f) => {
                assert!(!ok, "light_map_texels = {v} refused");
                assert_eq!(f, "shafts.light_map_texels");
            }
        }
        if ok {
            assert!(
                shafts_units(&s),
                "light_map_texels = {v}: the units refuse it"
            );
        }
    }
}

/// The image side against the depth buffer and the interpolator's vertex range: the
/// largest accepted side renders (a sample plane's corner vertex at the image's
/// corner), one more is refused naming the image field. Before the limits were tied,
/// 4096 was accepted and failed at render time in `polygon_interpolator.vertices[1].x`.
/// The scene is fig4 (planes only): at a 1 × 4095 aspect an object's triangles project
/// thousands of pixels off screen, beyond the interpolator whatever the image size
/// (docs/inputs.md, "One source of limits").
#[test]
fn image_sides_agree() {
    let small_fig4 = || {
        let mut s = builtin("fig4").unwrap();
        s.shafts.planes = 2;
        s.shafts.subplanes = 2;
        s.shafts.mesh = [2, 2];
        s.shafts.f_texels = 16;
        s.shafts.h_texels = [16, 16];
        s.shafts.light_map_texels = 16;
        s
    };
    for v in [
        1,
        2,
        IMAGE_MAX - 1,
        IMAGE_MAX,
        IMAGE_MAX + 1,
        MAX_MAP_SIDE + 1,
    ] {
        let mut s = small_fig4();
        s.image.width = v;
        s.image.height = 1;
        agree(&s, "image.width", shafts_units(&s), v);
        let mut s = small_fig4();
        s.image.width = 1;
        s.image.height = v;
        agree(&s, "image.height", shafts_units(&s), v);
    }
}

/// The environment's voxel-map side: the 3D texture sampler's texel count bounds it.
#[test]
fn environment_side_is_the_3d_samplers() {
    use rtl_model::units::texture_sampler::{TextureSamplerConfig, MAX_TEXELS};
    let ok = |side: u32| {
        TextureSamplerConfig {
            channels: 3,
            ..TextureSamplerConfig::geforce_3d(side, side, side)
        }
        .validate()
        .is_ok()
    };
    assert!(ok(ENV_MAX_SIDE) && !ok(2 * ENV_MAX_SIDE));
    assert!((ENV_MAX_SIDE as u64).pow(3) <= MAX_TEXELS);
    let base = builtin("env-pattern-sphere").unwrap();
    for (side, accepted) in [(ENV_MAX_SIDE, true), (2 * ENV_MAX_SIDE, false)] {
        let mut s = base.clone();
        s.environment.as_mut().unwrap().side = side;
        match validation(&s) {
            Ok(()) => assert!(accepted, "side {side} accepted"),
            Err(f) => {
                assert!(!accepted, "side {side} refused");
                assert_eq!(f, "environment.side");
            }
        }
    }
}
