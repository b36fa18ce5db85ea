//! Golden hashes of every built-in scene: restructuring and speed work never change
//! output, so the framebuffer codes and the counters of each built-in, rendered through
//! the same library functions the CLI's `render` uses, must hash to the constants below.
//!
//! The scenes are shrunk so the file stays fast ([`shrink`]: 180 × 120, at most 10
//! planes and 2 sub-planes; the foundation `test` scene at its fixed
//! size; the environment maps at s = 16, 32 × 32; the shading spheres at 48 × 48). A change that only shows at full size
//! is not caught here: render the built-ins with `render --scene NAME --json` before and
//! after and compare the PNG bytes and counters.
//!
//! Each row hashes (FNV-1a 64, [`fnv1a`]) the frame's width, height, bits and every
//! channel code (u32, little endian), and separately the counters as serde_json text.
//!
//! **Regenerating.** `cargo test --test golden -- --ignored --nocapture
//! print_golden_tables` prints each table (`("name", image, counters),`) and asserts
//! nothing; it is a separate, ignored test, so printing never turns a check into a
//! pass. Paste its output over the constants. A deliberate output change is its own commit
//! that updates these constants and says why the output changed; a restructuring or
//! speed commit never touches them.
//!
//! Thread-count independence (same bytes on 1 or N threads) is asserted elsewhere:
//! tests/shafts_pipeline.rs (fig6), tests/glare_pipeline.rs (glare-flare,
//! street-light), tests/envmap_reproduce.rs and tests/envmap_build.rs.

use glare_pipeline::frame::run::render;
use glare_pipeline::pipeline::envmap::prefilter::{build_accelerated, env_to_levels};
use glare_pipeline::pipeline::envmap::render::{render_frame, LambdaSpec, Object, RenderOptions};
use glare_pipeline::pipeline::envmap::reproduce::TABLE5_TH;
use glare_pipeline::pipeline::envmap::scene_render::render_scene;
use glare_pipeline::pipeline::shading::scene_file::{ShadingFile, DEFAULT_IMAGE};
use glare_pipeline::pipeline::shading::sweep::{
    measure_point, scene_names, shading_reference, sweep_view,
};
use glare_pipeline::pipeline::test_scene;
use glare_pipeline::reference::envmap_prefilter::PrefilterParams;
use glare_pipeline::report::image_out::Framebuffer;
use glare_pipeline::scene::builtin::{builtin, BUILTIN_NAMES};
use glare_pipeline::scene::builtin_environment::ENVIRONMENT_BUILTIN_NAMES;
use glare_pipeline::scene::builtin_glare::GLARE_BUILTIN_NAMES;
use glare_pipeline::scene::builtin_showcase::SHOWCASE_NAMES;
use glare_pipeline::scene::envmap::{EnvMap, BUILTIN_NAMES as ENV_NAMES};
use glare_pipeline::scene::format::Scene;

/// (scene, framebuffer hash, counters hash). Generated at 5e9bf33; every row of a scene
/// that existed at 63f8b50 is the same when the same code runs there (release profile),
/// and at full size the CLI's PNG bytes and JSON (but wall times) were identical
/// between the two commits.
const SHAFTS: &[(&str, u64, u64)] = &[
    ("fig4", 0x5546a9d3bd5cd32e, 0x6917a7eb1072e4ee),
    ("fig6", 0xaae7ee25f803e728, 0xc706b6f1dfbc9db8),
    ("stage", 0x115bed6625c57ef5, 0x8a727cd987a6f254),
];

/// The foundation test scene (`render --scene test`).
const TEST_SCENE: &[(&str, u64, u64)] = &[("test", 0xb01fdea48830eebd, 0x357ff2d2f177dfd6)];

/// The glare built-ins; `shaded-*` run the shading pass first (src/frame/glare_link.rs)
/// and hash its counters with the glare frame's. The counters are the frame's, as the
/// CLI prints them: street-light's shafts background counts in its image only.
const GLARE: &[(&str, u64, u64)] = &[
    ("glare-point", 0xf3f3acf1941c8491, 0xfe24b6f4155f816f),
    ("glare-elliptic", 0xfb4520dfc3302e43, 0xb8646d5abb7f22ad),
    ("glare-flare", 0xbfd3fa89b41f711e, 0xe13f839fdf8f7ff2),
    ("street-light", 0x068ed26f4a75639e, 0xd5e7261dc949380b),
    ("leaves", 0xeef24bfd1be33234, 0xa0d7c3f2bea76d5b),
    ("shaded-metal", 0x2e0bc6ab797ea759, 0x32192010504420e7),
    ("shaded-dielectric", 0x7b79bd6edf4eb0e3, 0xb71c02156c6cc980),
];

/// The environment maps (`reproduce envmap-images`' path): the accelerated map
/// (th = [`TABLE5_TH`]) at s = 16, the sphere at uniform λ = 0.5 (the 2D-slice lookup)
/// and the teapot at non-uniform λ (the 3D lookup), 32 × 32; `name/object`.
const ENVMAP: &[(&str, u64, u64)] = &[
    ("pattern/sphere", 0x9844d3f97cd90652, 0x00d54ff19806f492),
    ("pattern/teapot", 0x44cf5a75aa7e223a, 0xf22ec05d77ecaaec),
    (
        "venice_sunset/sphere",
        0x4db412f9fc7670b7,
        0x00d54ff19806f492,
    ),
    (
        "venice_sunset/teapot",
        0xa8e8ed00507b97e6,
        0xf22ec05d77ecaaec,
    ),
    (
        "st_fagans_interior/sphere",
        0xd1cc0ad179078c8c,
        0x00d54ff19806f492,
    ),
    (
        "st_fagans_interior/teapot",
        0xa96404dd478f77c5,
        0xf22ec05d77ecaaec,
    ),
];

/// The scenes added with the frame (generated at their first commit).
/// The shading spheres, generated when this table was added: the bytes of the
/// normalisation cube's path were then those of the commit before it (its sampler's
/// rounding became a `[rounding]` choice whose default is the sampler's own;
/// `render --scene shading-lambert` wrote the same PNG before and after).
const SHADING: &[(&str, u64, u64)] = &[
    ("shading-lambert", 0x77839615577ae943, 0x3753bc9b471dcc74),
    ("shading-oren_nayar", 0x4ad31e9ddb82661d, 0xbb6522e1a6dcded1),
    ("shading-phong", 0x49107ac589791659, 0x90a085e456f475a4),
    (
        "shading-blinn_phong",
        0x791506a5e93b9c3d,
        0xe29e16fb06e81263,
    ),
    (
        "shading-cook_torrance_metal",
        0xd15adaea6b6e99ef,
        0x2945fc4f74cd49bc,
    ),
    (
        "shading-cook_torrance_dielectric",
        0xb255d4b489ac5abd,
        0xfbb03e55ebf2898e,
    ),
    (
        "shading-cook_torrance_backlit",
        0xae057a7622c8f025,
        0xaa19f7d7d04d7ba5,
    ),
    ("shading-ward", 0x1602df0af80eadbe, 0x34261c3f671198ad),
    ("shading-kajiya_kay", 0x5e073a8762b414af, 0xc39f628dec30a05e),
    ("shading-specular", 0xc4dbb46fb90841e6, 0x3af8c43540ac818a),
    ("shading-vertex", 0xcbf29ce484222325, 0x035015bbcd9dfb99),
];

const SCENES: &[(&str, u64, u64)] = &[
    ("night-street", 0xca9425c8530c22ce, 0x30c3580b303f1642),
    ("env-pattern-sphere", 0x7b283435ad3c106c, 0xecf54cd750656eec),
    ("env-pattern-teapot", 0x36fc709730bb3ee2, 0x0f6c3481fa83653e),
    (
        "env-venice_sunset-sphere",
        0xb0f2746d6dca88a3,
        0xecf54cd750656eec,
    ),
    (
        "env-venice_sunset-teapot",
        0xf9c2ecda882e1e50,
        0x0f6c3481fa83653e,
    ),
    (
        "env-st_fagans_interior-sphere",
        0x383f7be597a713d0,
        0xecf54cd750656eec,
    ),
    (
        "env-st_fagans_interior-teapot",
        0xec1ffc716ff03f15,
        0x0f6c3481fa83653e,
    ),
];

/// FNV-1a, 64 bit: enough to notice a changed byte, no dependency.
fn fnv1a(bytes: impl IntoIterator<Item = u8>) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

fn hash_words(words: impl IntoIterator<Item = u32>) -> u64 {
    fnv1a(words.into_iter().flat_map(u32::to_le_bytes))
}

fn hash_fb(fb: &Framebuffer) -> u64 {
    hash_words(
        [fb.width, fb.height, fb.bits]
            .into_iter()
            .chain(fb.data.iter().copied()),
    )
}

fn hash_json<T: serde::Serialize>(v: &T) -> u64 {
    fnv1a(serde_json::to_string(v).unwrap().into_bytes())
}

/// The built-in at a test size (see the module doc).
fn shrink(name: &str) -> Scene {
    let mut s = builtin(name).unwrap_or_else(|e| panic!("{name}: {e}"));
    s.image.width = 180;
    s.image.height = 120;
    s.shafts.planes = s.shafts.planes.min(10);
    s.shafts.subplanes = s.shafts.subplanes.min(2);
    // The shadow maps stay at the built-ins' 512²: at 128² or 256² street-light's
    // shadow pass draws a triangle that the ±4000-pixel guard in shafts::frame skips at
    // 512², and its walk takes 10–30× the whole frame.
    s
}

type Row = (String, u64, u64);

/// The rows as Rust constants, to paste over a table after a deliberate change.
fn print_table(table: &str, rows: &[Row]) {
    println!("const {table}: &[(&str, u64, u64)] = &[");
    for (n, i, c) in rows {
        println!("    (\"{n}\", {i:#018x}, {c:#018x}),");
    }
    println!("];");
}

/// Assert the rows against `want`, listing every mismatch at once.
fn check(table: &str, rows: &[Row], want: &[(&str, u64, u64)]) {
    let got: Vec<(&str, u64, u64)> = rows.iter().map(|(n, i, c)| (n.as_str(), *i, *c)).collect();
    let mut bad = Vec::new();
    for w in want {
        match got.iter().find(|g| g.0 == w.0) {
            None => bad.push(format!("{}: not rendered", w.0)),
            Some(g) if g != w => bad.push(format!(
                "{}: image {:#018x} (golden {:#018x}), counters {:#018x} (golden {:#018x})",
                g.0, g.1, w.1, g.2, w.2
            )),
            Some(_) => {}
        }
    }
    for g in &got {
        if !want.iter().any(|w| w.0 == g.0) {
            bad.push(format!("{}: no golden (a new built-in? add its row)", g.0));
        }
    }
    assert!(
        bad.is_empty(),
        "{table}: output changed (regenerate only for a deliberate change, see the module doc):\n{}",
        bad.join("\n")
    );
}

fn shafts_rows() -> Vec<Row> {
    BUILTIN_NAMES
        .iter()
        .map(|&name| {
            // Through the frame, as the CLI's `render` draws it.
            let f = render(&shrink(name)).unwrap();
            let r = f.shafts.as_ref().unwrap();
            assert_eq!(f.fb, r.fb, "{name}: the frame is the shafts picture");
            (name.to_string(), hash_fb(&f.fb), hash_json(&r.counters))
        })
        .collect()
}

fn test_scene_rows() -> Vec<Row> {
    let (fb, counters) = test_scene::render().unwrap();
    vec![("test".to_string(), hash_fb(&fb), hash_json(&counters))]
}

fn glare_rows() -> Vec<Row> {
    GLARE_BUILTIN_NAMES
        .iter()
        .map(|&name| {
            let s = shrink(name);
            // Through the frame, as the CLI's `render` draws it: a scene with shaded
            // highlights is shaded first, then glared over the shaded picture; the
            // street light's picture is drawn by its shafts passes.
            let fr = render(&s).unwrap();
            let (f, _) = fr.glare.as_ref().unwrap();
            let shading = fr.linked.as_ref().map(|l| l.shading.counters.clone());
            let counters = hash_json(&(&f.counters, &shading));
            (name.to_string(), hash_fb(&f.fb), counters)
        })
        .collect()
}

fn envmap_rows() -> Vec<Row> {
    let opt = RenderOptions::default();
    let mut rows = Vec::new();
    for name in ENV_NAMES {
        let env = EnvMap::builtin(name).unwrap();
        let levels = env_to_levels(&env, env.auto_exposure()).unwrap();
        let (map, _) =
            build_accelerated(&levels, 16, &PrefilterParams::thesis(), TABLE5_TH).unwrap();
        for (object, lambda) in [
            (Object::Sphere, LambdaSpec::Uniform(0.5)),
            (Object::Teapot, LambdaSpec::NonUniform),
        ] {
            let (img, info) = render_frame(&env, &map, object, lambda, (32, 32), &opt).unwrap();
            let pixels = img.pixels.iter().flatten().copied();
            let mask = img.mask.iter().map(|&m| m as u8);
            let image = fnv1a(
                [img.width, img.height]
                    .into_iter()
                    .flat_map(u32::to_le_bytes)
                    .chain(pixels)
                    .chain(mask),
            );
            rows.push((format!("{name}/{}", object.name()), image, hash_json(&info)));
        }
    }
    rows
}

#[test]
fn shafts_builtins() {
    check("SHAFTS", &shafts_rows(), SHAFTS);
}

#[test]
fn foundation_test_scene() {
    check("TEST_SCENE", &test_scene_rows(), TEST_SCENE);
}

#[test]
fn glare_builtins() {
    check("GLARE", &glare_rows(), GLARE);
}

/// The showcase (through the frame: every pipeline; shrunk as [`shrink`], its
/// environment map at s = 16) and the environment scenes (`env-*`, through
/// `render --scene`'s path, 32 × 32 at s = 16).
fn scene_rows() -> Vec<Row> {
    let mut rows = Vec::new();
    for &name in SHOWCASE_NAMES {
        let mut s = shrink(name);
        if let Some(e) = s.environment.as_mut() {
            e.side = 16;
        }
        let f = render(&s).unwrap();
        rows.push((name.to_string(), hash_fb(&f.fb), hash_json(&f.counters())));
    }
    for &name in ENVIRONMENT_BUILTIN_NAMES {
        let mut s = builtin(name).unwrap();
        s.image.width = 32;
        s.image.height = 32;
        if let Some(e) = s.environment.as_mut() {
            e.side = 16;
        }
        let f = render_scene(&s, false).unwrap();
        let img = f.image;
        let words = [img.width, img.height]
            .into_iter()
            .chain(img.pixels.iter().flat_map(|p| p.map(u32::from)))
            .chain(img.mask.iter().map(|&m| u32::from(m)));
        rows.push((name.to_string(), hash_words(words), hash_json(&f.counters)));
    }
    rows
}

#[test]
fn scene_builtins() {
    check("SCENES", &scene_rows(), SCENES);
}

/// The shading spheres (`render --scene shading-*`, through its path at 48 × 48): the
/// levels `render` writes, and the report's error, gates, RAM bits and predicted time
/// (`shading-vertex`: its lit vertices' report, no image).
fn shading_rows() -> Vec<Row> {
    scene_names()
        .iter()
        .map(|name| {
            let mut f = ShadingFile::builtin(name).unwrap();
            f.image = f.image.map(|_| 48);
            let view = sweep_view(f.image.unwrap_or(DEFAULT_IMAGE));
            let r = shading_reference(&f.point, &view).unwrap();
            let m = measure_point(&f.point, &view, &r).unwrap();
            let words = m.levels.iter().map(|&l| l.round() as u32);
            let report = (
                m.mean_abs_levels,
                m.rms_levels,
                m.max_levels,
                m.gates_nand2,
                m.ram_bits,
                m.predicted_hw_seconds,
            );
            (name.clone(), hash_words(words), hash_json(&report))
        })
        .collect()
}

#[test]
fn shading_builtins() {
    check("SHADING", &shading_rows(), SHADING);
}

#[test]
fn envmap_builtins() {
    check("ENVMAP", &envmap_rows(), ENVMAP);
}

/// Prints every table for regenerating the constants (see the module doc); ignored, so
/// it runs only when asked for, and it asserts nothing.
#[test]
#[ignore = "prints the golden tables for a deliberate output change"]
fn print_golden_tables() {
    print_table("SHAFTS", &shafts_rows());
    print_table("TEST_SCENE", &test_scene_rows());
    print_table("GLARE", &glare_rows());
    print_table("SCENES", &scene_rows());
    print_table("ENVMAP", &envmap_rows());
    print_table("SHADING", &shading_rows());
}
