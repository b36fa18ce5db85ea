//! Per-pixel roughness from a roughness texture (issue 5's option, the thesis' proposed
//! fix of §3.5 / Fig. 17(b)): `RenderOptions::lambda_source` in
//! src/pipeline/envmap/render.rs. Small cases: the 64 × 32 pattern, an s = 16 map from
//! `quick_map`, 64 × 64 images (96 × 96 for the seam measurement).
//!
//! `cargo test --test envmap_roughness -- --nocapture` prints the comparison rows;
//! `cargo test --test envmap_roughness -- --ignored --nocapture` writes
//! out/roughness_sphere.png (per vertex | texture | intended truth | |Δ| × 8 of each).

use std::sync::OnceLock;

use glare_pipeline::pipeline::envmap::render::{
    camera, lambda_of_uv, object_geometry, object_texgen, quick_map, render_frame, render_image,
    render_interpolator, render_object_with, roughness_sampler, roughness_texels,
    texcoord_channels_cost, Image, LambdaSource, LambdaSpec, Lookup, Object, Reflection,
    RenderOptions, DEFAULT_LAMBDA_TEXTURE_SIDE, RENDER_ATTRS, RENDER_ATTRS_TEXTURE,
    TEXCOORD_CHANNELS,
};
use glare_pipeline::pipeline::envmap::roughness_comparison::{roughness_comparison, RoughnessRow};
use glare_pipeline::pipeline::envmap::voxmap::VoxelMap;
use glare_pipeline::pipeline::shafts::view::CameraView;
use glare_pipeline::scene::envmap::EnvMap;
use glare_pipeline::scene::format::ImageSize;
use rtl_model::UnitSummary;

const SIZE: (u32, u32) = (64, 64);
const S: u32 = 16;
const SIDE: u32 = 64;

fn pattern() -> &'static (EnvMap, VoxelMap) {
    static P: OnceLock<(EnvMap, VoxelMap)> = OnceLock::new();
    P.get_or_init(|| {
        let env = EnvMap::pattern(64, 32);
        let map = quick_map(&env, S).unwrap();
        (env, map)
    })
}

fn texture(side: u32) -> RenderOptions {
    RenderOptions {
        lambda_source: LambdaSource::Texture { side },
        ..RenderOptions::default()
    }
}

/// FNV-1a over the pixels and the mask.
fn fnv(img: &Image) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let bytes = img.pixels.iter().flatten().copied();
    for b in bytes.chain(img.mask.iter().map(|m| *m as u8)) {
        h ^= b as u64;
        h = h.wrapping_mul(0x100_0000_01b3);
    }
    h
}

/// The uniform-λ `Lookup::Auto` rows take the 2D path, whose texture became a cube map
/// (the `cube_map_address` unit's branch; the lat-long slice gave 0xdb7f8df03599c85f
/// and 0x52ae627bbf50ab7e): their hashes are the cube map's, printed by the failing
/// assertion when that branch replaced the slice. The other six are unchanged.
const SPHERE_CUBE: u64 = 0x3037024dafe07051;
const TEAPOT_CUBE: u64 = 0xa518f7b8ae1de83e;

/// The hashes of the per-vertex images BEFORE the option existed (commit 42c3f23,
/// printed by this file's first version): the per-vertex λ on the host-f64 reflection
/// path (the only path then; `Reflection::Unit` is the default since) must keep them.
const BEFORE: [(Object, bool, Lookup, u64); 8] = [
    (Object::Sphere, true, Lookup::Voxel3D, 0x74a6fdec1b9d09e4),
    (Object::Sphere, true, Lookup::Auto, 0x74a6fdec1b9d09e4),
    (Object::Sphere, false, Lookup::Voxel3D, 0xbfb89f482db6cee6),
    (Object::Sphere, false, Lookup::Auto, SPHERE_CUBE),
    (Object::Teapot, true, Lookup::Voxel3D, 0x69488233c0d228a8),
    (Object::Teapot, true, Lookup::Auto, 0x69488233c0d228a8),
    (Object::Teapot, false, Lookup::Voxel3D, 0x5267b068d7093bf4),
    (Object::Teapot, false, Lookup::Auto, TEAPOT_CUBE),
];

#[test]
fn per_vertex_host_f64_path_keeps_the_images_byte_for_byte() {
    let (env, map) = pattern();
    for (object, nonuniform, lookup, want) in BEFORE {
        let lambda = if nonuniform {
            LambdaSpec::NonUniform
        } else {
            LambdaSpec::Uniform(0.5)
        };
        let opt = RenderOptions {
            lookup,
            reflection: Reflection::HostF64,
            ..RenderOptions::default()
        };
        assert_eq!(opt.lambda_source, LambdaSource::PerVertex);
        let img = render_image(env, map, object, lambda, SIZE, &opt).unwrap();
        assert_eq!(fnv(&img), want, "{object:?} {lambda:?} {lookup:?}");
        // Asking for the intended truth (which interpolates (u, v) too) changes nothing.
        let explicit = RenderOptions {
            lambda_source: LambdaSource::PerVertex,
            intended_truth: true,
            ..opt
        };
        let img2 = render_image(env, map, object, lambda, SIZE, &explicit).unwrap();
        assert_eq!(img2, img);
    }
}

#[test]
fn texgen_lambda_equals_the_vertex_lambda_at_the_vertices() {
    // The roughness texture is λ(u, v) (lambda_of_uv); at every vertex it must be the
    // per-vertex λ of object_geometry, else the two paths would render different λ
    // functions (the teapot's texgen is world x, y for that reason).
    let cam = CameraView::new(
        &camera(),
        ImageSize {
            width: 64,
            height: 64,
        },
    );
    for object in [Object::Sphere, Object::Teapot] {
        let tg = object_texgen(object, &cam);
        let geo = object_geometry(object, LambdaSpec::NonUniform, &cam).unwrap();
        let mut worst: f64 = 0.0;
        for (tri, lam) in &geo {
            for (p, want) in tri.p.iter().zip(lam) {
                let (u, v) = tg.uv(*p);
                let l = lambda_of_uv(object, LambdaSpec::NonUniform, u, v);
                let d = (l - want).abs();
                // On the sphere's seam itself (λ 0 or 1 by the sign of a rounding) the
                // two may take opposite sides.
                if object == Object::Sphere && d > 0.999 {
                    continue;
                }
                worst = worst.max(d);
            }
        }
        assert!(worst < 1e-12, "{object:?}: {worst}");
    }
}

#[test]
fn uniform_lambda_texture_matches_per_vertex_within_the_quantisation_bound() {
    let (env, map) = pattern();
    let d = map.max_neighbour_step() as f64;
    // Per axis, how far each path's texel coordinate may sit from the exact (t + 1)/2 · s:
    // HostF64 rounds it to 1/256 texel (½ LSB, two renders: 1/256); the reflection
    // unit is within its derived bound B of the exact value (0.0556 texel at s = 128
    // in docs/units.md; the bound grows with s, so it covers s = 16), two renders: 2B.
    for (reflection, handover) in [
        (Reflection::HostF64, 1.0 / 256.0),
        (Reflection::Unit, 2.0 * 0.0556),
    ] {
        let render = |object, lambda, source| {
            let opt = RenderOptions {
                lambda_source: source,
                reflection,
                ..RenderOptions::default()
            };
            render_image(env, map, object, LambdaSpec::Uniform(lambda), SIZE, &opt).unwrap()
        };
        let tex = LambdaSource::Texture { side: SIDE };
        for object in [Object::Sphere, Object::Teapot] {
            // λ = 1: the texture is all 255; a bilinear sample of a constant is the
            // constant exactly (the weights sum to W² = 2^16), so λ = 255/255 = 1.0 (and
            // the unit's u1.12 word round(255 · 4096/255) = 4096); the per-vertex
            // constant 1.0 is exact in s16.16 and its plane has zero gradients, so the
            // interpolated λ is exactly 1.0 too: the same t, the same bytes.
            let pv = render(object, 1.0, LambdaSource::PerVertex);
            let tx = render(object, 1.0, tex);
            assert_eq!(tx, pv, "{object:?} {reflection:?} λ = 1");
            // λ = 0.5: the texel is round(127.5) = 128, λ_tex = 128/255, |Δλ| = 1/510 (0.5
            // is exact in s16.16). Per axis the texel coordinate moves by ≤ s·|Δλ|/2 plus
            // the hand-over term above; the trilinear value moves by ≤ D per texel per
            // axis (D = the largest step between neighbouring voxels; the weights are
            // exact at 8 fraction bits = 8 weight bits), and the two final roundings add
            // < 1 code:  |Δout| ≤ 3·D·(s·|Δλ|/2 + hand-over) + 1.
            let dl = (128.0 / 255.0 - 0.5f64).abs();
            let bound = (3.0 * d * (S as f64 * dl / 2.0 + handover) + 1.0).floor() as u8;
            let pv = render(object, 0.5, LambdaSource::PerVertex);
            let tx = render(object, 0.5, tex);
            assert_eq!(tx.mask, pv.mask);
            let mut max = 0u8;
            let mut differ = 0;
            for k in 0..pv.pixels.len() {
                if pv.mask[k] {
                    for c in 0..3 {
                        let e = pv.pixels[k][c].abs_diff(tx.pixels[k][c]);
                        max = max.max(e);
                        differ += usize::from(e > 0);
                    }
                } else {
                    assert_eq!(pv.pixels[k], tx.pixels[k]); // the background is untouched
                }
            }
            println!(
                "{object:?} {reflection:?} λ = 0.5: texture vs per vertex max |Δ| = {max} (bound {bound}, D = {d}), {differ} channel values differ"
            );
            assert!(max <= bound, "{object:?} {reflection:?}: {max} > {bound}");
        }
    }
}

fn print_rows(rows: &[RoughnessRow]) {
    println!("{}", RoughnessRow::CSV_HEADER);
    for r in rows {
        println!("{}", r.to_csv());
    }
}

#[test]
fn texture_lambda_is_closer_to_the_intended_truth_at_the_sphere_seam() {
    let (env, map) = pattern();
    let size = (96, 96);
    let rows =
        roughness_comparison(env, map, Object::Sphere, size, DEFAULT_LAMBDA_TEXTURE_SIDE).unwrap();
    print_rows(&rows);
    let (pv, tx) = (&rows[0], &rows[1]);
    assert_eq!(pv.lambda_source, "per_vertex");
    assert_eq!(tx.lambda_source, "texture_256");
    assert_eq!(pv.pixels, tx.pixels);
    assert_eq!(pv.seam_pixels, tx.seam_pixels);
    assert!(pv.seam_pixels > 20, "seam band: {} pixels", pv.seam_pixels);
    // Measured (s = 16, 96 × 96, 256² texture): see docs/envmap.md. The margins are
    // asserted well inside the measured values.
    // 1. The λ itself: per vertex smears 0 → 1 across whole triangles at the seam; the
    //    texture's λ is off by at most its bilinear ramp (one texel, < 1 pixel here)
    //    and 1/510 elsewhere.
    println!(
        "seam |Δλ| mean: per vertex {:.4}, texture {:.4}; whole sphere {:.5} vs {:.5}",
        pv.seam_lambda_mean, tx.seam_lambda_mean, pv.lambda_mean, tx.lambda_mean
    );
    assert!(tx.seam_lambda_mean * 50.0 < pv.seam_lambda_mean);
    assert!(tx.seam_lambda_max * 50.0 < pv.seam_lambda_max);
    assert!(tx.lambda_mean * 5.0 < pv.lambda_mean);
    // 2. The image: the seam error drops, down to the map's own floor there (the
    //    error against the truth at the λ the render used: λ → 0 reads the coarse
    //    centre of an s = 16 map), which no λ source removes.
    println!(
        "seam mean |Δ| (RGB mean): per vertex {:.3}, texture {:.3}; floor {:.3} / {:.3}",
        pv.seam_mean_rgb(),
        tx.seam_mean_rgb(),
        pv.seam_own_mean_rgb(),
        tx.seam_own_mean_rgb()
    );
    assert!(
        tx.seam_mean_rgb() < 0.9 * pv.seam_mean_rgb(),
        "seam: texture {} vs per vertex {}",
        tx.seam_mean_rgb(),
        pv.seam_mean_rgb()
    );
    // The excess over the floor is what the λ source adds.
    let excess = |r: &RoughnessRow| r.seam_mean_rgb() - r.seam_own_mean_rgb();
    println!(
        "seam excess over the floor: per vertex {:.3}, texture {:.3}",
        excess(pv),
        excess(tx)
    );
    assert!(
        tx.mean_rgb() < pv.mean_rgb(),
        "whole sphere: texture {} vs per vertex {}",
        tx.mean_rgb(),
        pv.mean_rgb()
    );

    // The teapot has no λ jump: no seam band; both sources stay close to the truth.
    let rows = roughness_comparison(env, map, Object::Teapot, SIZE, SIDE).unwrap();
    print_rows(&rows);
    assert_eq!(rows[0].seam_pixels, 0);
    assert!(rows.iter().all(|r| r.mean.iter().all(|m| m.is_finite())));
}

#[test]
fn texture_path_counts_and_elaborates_the_roughness_sampler() {
    let (env, map) = pattern();
    let (_, _, st) = render_object_with(
        env,
        map,
        Object::Sphere,
        LambdaSpec::NonUniform,
        SIZE,
        &texture(SIDE),
    )
    .unwrap();
    let shaded = st.frame.shaded;
    let c = &st.counters["texture_sampler (roughness)"];
    assert_eq!(c.table_reads, 4 * shaded, "bilinear: 4 texels per pixel");
    assert_eq!(c.mem_read_bytes, 4 * shaded, "8-bit texels");
    // ONE interpolator carries (u, v): no second unit's counters.
    assert!(!st.counters.contains_key("polygon_interpolator (texcoord)"));
    assert_eq!(
        st.counters
            .keys()
            .filter(|k| k.contains("interpolator"))
            .count(),
        1
    );
    assert_eq!(st.frame.roughness_texels_per_lookup, 4);
    assert_eq!(st.frame.texels_per_lookup, 8);
    let e = &st.frame.elaboration;
    assert_eq!(e.roughness_texture_bytes, (SIDE * SIDE) as u64);
    let u = e
        .units
        .iter()
        .find(|u| u.name == "texture_sampler (roughness)")
        .expect("listed");
    let sum = u.summary.as_ref().expect("elaborated");
    assert!(u.left_out.is_none());
    assert_eq!(sum.ram_bits, (SIDE * SIDE * 8) as u64);
    assert!(sum.gates_nand2 > 0.0);
    println!(
        "roughness sampler ({SIDE}²): {:.0} gates, {} RAM bits, latency {}, II {}",
        sum.gates_nand2, sum.ram_bits, sum.latency, sum.ii
    );
    for u in &e.units {
        if let Some(s) = &u.summary {
            println!(
                "  {}: {:.0} gates, {} RAM bits",
                u.name, s.gates_nand2, s.ram_bits
            );
        }
    }

    // At the default side (what roughness_comparison uses).
    let rs = roughness_sampler(
        Object::Sphere,
        LambdaSpec::NonUniform,
        DEFAULT_LAMBDA_TEXTURE_SIDE,
    )
    .unwrap();
    let sum = UnitSummary::of(&rs);
    assert_eq!(sum.ram_bits, 256 * 256 * 8);
    println!(
        "roughness sampler (256²): {:.0} gates, {} RAM bits, latency {}, II {}",
        sum.gates_nand2, sum.ram_bits, sum.latency, sum.ii
    );

    // The texture coordinate is 2 more attribute channels of the one interpolator
    // (10 attributes, not 8): the elaboration lists their cost as the increment.
    let gates = |attrs| UnitSummary::of(&render_interpolator(attrs).unwrap()).gates_nand2;
    let (g8, g10) = (gates(RENDER_ATTRS), gates(RENDER_ATTRS_TEXTURE));
    assert_eq!((RENDER_ATTRS, RENDER_ATTRS_TEXTURE), (8, 10));
    assert!(g10 > g8);
    let row = e
        .units
        .iter()
        .find(|u| u.name == TEXCOORD_CHANNELS)
        .expect("the (u, v) channels are listed");
    assert!(row.left_out.is_none());
    let inc = row.summary.as_ref().expect("costed");
    assert_eq!(inc.gates_nand2, g10 - g8);
    assert_eq!(inc.ram_bits, 0);
    let parts: f64 = inc.breakdown.iter().map(|(_, g)| g).sum();
    assert!((parts - inc.gates_nand2).abs() < 1e-6 * g10);
    assert!(inc.breakdown.iter().all(|(n, _)| !n.starts_with("setup:")));
    assert_eq!(
        inc.gates_nand2,
        texcoord_channels_cost().unwrap().gates_nand2
    );
    // No whole second interpolator any more.
    assert!(!e.units.iter().any(|u| u.name != TEXCOORD_CHANNELS
        && u.summary
            .as_ref()
            .is_some_and(|s| s.name == "polygon_interpolator")));
    println!(
        "polygon_interpolator gates: 8 attrs {g8:.0}, 10 attrs {g10:.0}; (u, v) channels {:.0}",
        g10 - g8
    );
    for (part, g) in &inc.breakdown {
        println!("  {part}: {g:.0}");
    }
    let walked = st.counters["polygon_interpolator"].pixels_in;

    // Per vertex: neither listed nor counted, and no roughness bytes.
    let (_, _, st) = render_object_with(
        env,
        map,
        Object::Sphere,
        LambdaSpec::NonUniform,
        SIZE,
        &Default::default(),
    )
    .unwrap();
    assert!(!st.counters.contains_key("texture_sampler (roughness)"));
    assert!(!st.counters.contains_key("polygon_interpolator (texcoord)"));
    // The same walk (8 attributes here, 10 with the texture): the same pixels.
    assert_eq!(st.counters["polygon_interpolator"].pixels_in, walked);
    let e = &st.frame.elaboration;
    assert!(e.units.iter().all(|u| !u.name.contains("roughness")));
    assert!(e.units.iter().all(|u| u.name != TEXCOORD_CHANNELS));
    assert_eq!(e.roughness_texture_bytes, 0);
    assert_eq!(st.frame.roughness_texels_per_lookup, 0);
    assert!(st.intended.is_none());

    // With a texture the uniform-λ Auto lookup stays on the 3D map.
    let opt = RenderOptions {
        lookup: Lookup::Auto,
        ..texture(SIDE)
    };
    let (_, f) = render_frame(
        env,
        map,
        Object::Teapot,
        LambdaSpec::Uniform(0.5),
        SIZE,
        &opt,
    )
    .unwrap();
    assert!(!f.elaboration.slice_2d);
}

#[test]
fn bad_texture_side_is_an_error_naming_the_field() {
    let (env, map) = pattern();
    for side in [0, 4097, u32::MAX] {
        let e = render_image(
            env,
            map,
            Object::Sphere,
            LambdaSpec::NonUniform,
            SIZE,
            &texture(side),
        )
        .unwrap_err();
        assert_eq!(e.field(), "envmap_render.lambda_texture", "side {side}");
        let e = roughness_texels(Object::Teapot, LambdaSpec::NonUniform, side).unwrap_err();
        assert_eq!(e.field(), "envmap_render.lambda_texture");
    }
    // The smallest texture works: one texel, λ = round(255 · λ(½, ½)) / 255 everywhere.
    let img = render_image(
        env,
        map,
        Object::Teapot,
        LambdaSpec::NonUniform,
        SIZE,
        &texture(1),
    )
    .unwrap();
    assert!(img.coverage() > 0);
    let t = roughness_texels(Object::Teapot, LambdaSpec::NonUniform, 1).unwrap();
    assert_eq!(t, vec![(255.0f64 * (0.2 + 0.7 * 0.5)).round() as u32]);
}

#[test]
fn texture_path_is_deterministic() {
    let (env, map) = pattern();
    let opt = RenderOptions {
        intended_truth: true,
        ..texture(SIDE)
    };
    let a =
        render_object_with(env, map, Object::Sphere, LambdaSpec::NonUniform, SIZE, &opt).unwrap();
    let b =
        render_object_with(env, map, Object::Sphere, LambdaSpec::NonUniform, SIZE, &opt).unwrap();
    assert_eq!(a.0, b.0);
    assert_eq!(a.1, b.1);
    assert_eq!(a.2, b.2);
    assert!(a.1.intended.is_some());
    let i = a.2.intended.unwrap();
    assert!(i.all.is_finite() && i.seam.is_finite());
}

/// Look at it: out/roughness_sphere.png, 256 × 256 panels: per vertex | texture |
/// intended truth, and below |Δ| × 8 against the intended truth.
#[test]
#[ignore]
fn write_roughness_png() {
    let (env, map) = pattern();
    let size = (256, 256);
    print_rows(
        &roughness_comparison(env, map, Object::Sphere, size, DEFAULT_LAMBDA_TEXTURE_SIDE).unwrap(),
    );
    let mut imgs = Vec::new();
    let mut truth = None;
    for source in [
        LambdaSource::PerVertex,
        LambdaSource::Texture {
            side: DEFAULT_LAMBDA_TEXTURE_SIDE,
        },
    ] {
        let opt = RenderOptions {
            lambda_source: source,
            intended_truth: true,
            ..RenderOptions::default()
        };
        let (img, t, st) =
            render_object_with(env, map, Object::Sphere, LambdaSpec::NonUniform, size, &opt)
                .unwrap();
        assert!(st.intended.is_some());
        truth = t.intended;
        imgs.push(img);
    }
    let truth = truth.unwrap();
    let top = Image::hstack(&[&imgs[0], &imgs[1], &truth]);
    let d0 = imgs[0].diff(&truth, 8.0);
    let d1 = imgs[1].diff(&truth, 8.0);
    let bottom = Image::hstack(&[&d0, &d1, &truth.diff(&truth, 8.0)]);
    std::fs::create_dir_all("out").unwrap();
    top.write_png("out/roughness_sphere.png").unwrap();
    bottom.write_png("out/roughness_sphere_diff.png").unwrap();
}
