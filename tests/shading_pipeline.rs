//! The shading pipeline end to end: the material paths through the units against the
//! f64 references, elaboration of what a material needs, the shading → glare link,
//! and the specular banding measurement.

use glare_pipeline::frame::glare_link::prepare;
use glare_pipeline::pipeline::glare::frame::render_glare_over;
use glare_pipeline::pipeline::shading::brdfs::{catalogue, render_sphere, sphere_error};
use glare_pipeline::pipeline::shading::materials::material_path;
use glare_pipeline::pipeline::shading::path::{PathConfig, FACTORS};
use glare_pipeline::pipeline::shading::specular::{
    cube_16bit, cube_8bit, paths_at, reference_levels, score, sphere_vectors, LOOKUP_16, LOOKUP_8,
};
use glare_pipeline::pipeline::shading::sphere::SphereView;
use glare_pipeline::scene::builtin_glare::glare_builtin;
use glare_pipeline::scene::format::Scene;
use glare_pipeline::scene::material::Material;
use rtl_model::Counters;

fn view(size: u32) -> SphereView {
    SphereView {
        size,
        irradiance: std::f64::consts::PI,
        ..SphereView::default()
    }
}

#[test]
fn lambert_sphere_is_within_the_derived_bound() {
    let e = catalogue()
        .into_iter()
        .find(|e| e.label == "lambert")
        .unwrap();
    let r = render_sphere(&e, &view(96), &PathConfig::default()).unwrap();
    let st = sphere_error(&r).unwrap();
    let bound = r.path.diffuse_error_bound().unwrap();
    println!("lambert: {st:?}, bound {bound:.3}");
    assert!(st.max <= bound, "max {} > bound {bound}", st.max);
    assert!(st.n > 0);
}

#[test]
fn every_catalogue_model_renders_finite_levels_on_both_sides() {
    for e in catalogue() {
        let r = render_sphere(&e, &view(48), &PathConfig::default()).unwrap();
        let st = sphere_error(&r).unwrap();
        println!(
            "{}: {} — mean {:.2} RMS {:.2} max {:.0}",
            e.label,
            r.path.describe(),
            st.mean_abs,
            st.rms,
            st.max
        );
        assert!(
            r.reference.iter().all(|v| v.is_finite() && *v >= 0.0),
            "{}",
            e.label
        );
        assert!(
            r.hardware.iter().all(|v| (0.0..=255.0).contains(v)),
            "{}",
            e.label
        );
        // Every model lights part of the sphere on both sides.
        assert!(
            r.hardware.iter().any(|&v| v > 0.0),
            "{}: black hardware image",
            e.label
        );
        assert!(
            r.reference.iter().any(|&v| v > 0.0),
            "{}: black reference",
            e.label
        );
    }
}

#[test]
fn a_lambert_material_elaborates_no_lookup_no_factor_textures_and_no_specular_stage() {
    let cfg = PathConfig::default();
    let lambert = material_path(&Material::Lambert, [0.8; 3], &cfg).unwrap();
    let blinn = material_path(
        &Material::BlinnPhong {
            ks: 0.5,
            exponent: 32.0,
            normalized: false,
        },
        [0.8; 3],
        &cfg,
    )
    .unwrap();
    let left = |p: &glare_pipeline::pipeline::shading::path::ShadingPath| {
        p.elaboration(100)
            .into_iter()
            .filter(|e| e.left_out.is_some())
            .map(|e| e.name)
            .collect::<Vec<_>>()
    };
    let present = |p: &glare_pipeline::pipeline::shading::path::ShadingPath| {
        p.elaboration(100)
            .into_iter()
            .filter(|e| e.summary.is_some())
            .map(|e| e.name)
            .collect::<Vec<_>>()
    };
    let l = left(&lambert);
    assert!(l.iter().any(|n| n == "specular_lookup"), "{l:?}");
    assert!(l.iter().any(|n| n == FACTORS), "{l:?}");
    let p = present(&lambert);
    assert!(!p.iter().any(|n| n.contains("MODULATE specular")), "{p:?}");
    assert!(!p.iter().any(|n| n.contains("factor")), "{p:?}");
    // Blinn–Phong adds the lookup and its MODULATE stage.
    let pb = present(&blinn);
    assert!(pb.iter().any(|n| n == "specular_lookup"), "{pb:?}");
    assert!(pb.iter().any(|n| n.contains("MODULATE specular")), "{pb:?}");
    assert!(pb.len() > p.len());
    // The left-out units report the gates they saved.
    let saved: f64 = lambert
        .elaboration(100)
        .iter()
        .filter(|e| e.name == "specular_lookup")
        .map(|e| e.gates_saved)
        .sum();
    assert!(saved > 0.0);
}

fn small_linked(name: &str) -> Scene {
    let mut s = glare_builtin(name).unwrap();
    s.image.width = 240;
    s.image.height = 160;
    s
}

#[test]
fn a_metal_cook_torrance_highlight_becomes_a_glare_source_and_a_rough_dielectric_does_not() {
    for (name, glares) in [("shaded-metal", true), ("shaded-dielectric", false)] {
        let s = small_linked(name);
        let linked = prepare(&s)
            .unwrap()
            .expect("the scene asks for shaded highlights");
        // No highlight is written by hand: the one the glare conditions see is the shader's.
        assert!(s.glare.as_ref().unwrap().highlights.is_empty());
        assert_eq!(
            linked.shading.highlights.len(),
            1,
            "{name}: the sphere's highlight"
        );
        let h = &linked.shading.highlights[0];
        assert_eq!(h.object, 0, "{name}");
        let f = render_glare_over(&linked.scene, Some(&linked.base)).unwrap();
        let label = f.labels.iter().find(|l| l.contains("highlights")).unwrap();
        println!(
            "{name}: specular level {} (I_s {:.3}) → {label}",
            h.specular, h.highlight.specular
        );
        assert_eq!(label.contains("(glare)"), glares, "{name}: {label}");
        assert_eq!(label.contains("saturates only"), !glares, "{name}: {label}");
    }
}

#[test]
fn a_scene_without_shaded_highlights_is_not_touched() {
    let s = glare_builtin("glare-point").unwrap();
    assert!(prepare(&s).unwrap().is_none());
}

#[test]
fn materials_are_optional_in_scene_files_and_bad_parameters_name_the_field() {
    // Old scene files have no `material`: they load, and serialise without one.
    let fig6 = glare_pipeline::scene::builtin::builtin_toml("fig6").unwrap();
    assert!(!fig6.contains("material"));
    let mut s = glare_builtin("shaded-metal").unwrap();
    s.validate().unwrap();
    s.objects[0].material = Some(Material::CookTorrance {
        distribution: Default::default(),
        roughness: 0.0,
        ior: 1.5,
        extinction: 0.0,
        fresnel: Default::default(),
    });
    let e = s.validate().unwrap_err();
    assert_eq!(e.field(), "objects[0].material.roughness", "{e}");
    let mut s = glare_builtin("shaded-metal").unwrap();
    s.glare
        .as_mut()
        .unwrap()
        .shaded_highlights
        .as_mut()
        .unwrap()
        .light = 3;
    let e = s.validate().unwrap_err();
    assert_eq!(e.field(), "glare.shaded_highlights.light", "{e}");
    // A TOML round trip keeps the material.
    let text = toml::to_string(&glare_builtin("shaded-metal").unwrap()).unwrap();
    assert!(text.contains("model = \"cook_torrance\""), "{text}");
    let back = Scene::from_toml_str(&text).unwrap();
    assert_eq!(
        back.objects[0].material,
        glare_builtin("shaded-metal").unwrap().objects[0].material
    );
}

#[test]
fn squaring_in_9_bit_combiners_bands_and_the_lookup_at_texture_shader_precision_does_not() {
    let v = view(128);
    let v8 = sphere_vectors(&v, &cube_8bit().unwrap()).unwrap();
    let v16 = sphere_vectors(&v, &cube_16bit().unwrap()).unwrap();
    let mask: Vec<bool> = v8.iter().map(|x| x.is_some()).collect();
    let mut ctr = Counters::default();
    let (k, s) = (5u32, 32u32);
    let reference = reference_levels(&v8, s as f64);
    let paths = paths_at(k, &v8, &v16, &mut ctr).unwrap();
    let row = |label: &str| {
        let levels = &paths.iter().find(|(l, _)| l == label).unwrap().1;
        score(label, s, levels, &reference, &mask, v.size).unwrap()
    };
    let (sq, lut8, lut16) = (row("squaring 9-bit"), row(LOOKUP_8), row(LOOKUP_16));
    println!("{sq:?}\n{lut8:?}\n{lut16:?}");
    // The squaring's highlight has fewer levels and bigger jumps than the lookup's.
    assert!(
        sq.distinct_levels < lut16.distinct_levels,
        "{sq:?} {lut16:?}"
    );
    assert!(sq.max_step > lut16.max_step, "{sq:?} {lut16:?}");
    assert!(lut16.rms < sq.rms, "{sq:?} {lut16:?}");
    // An 8-bit n·h bands through the lookup too: the levels come from n·h's width.
    assert!(
        lut8.distinct_levels < lut16.distinct_levels,
        "{lut8:?} {lut16:?}"
    );
}

/// Stiff and extreme inputs through the material paths (issue 13's list): grazing
/// light and view (cos exactly 0), a light behind the surface, roughness toward 0 and
/// at 1, exponents 1 and 10⁴, anisotropy 100:1, a zero-length interpolated normal.
/// Documented behaviour: every output is a level in 0 ..= 255 (never a panic or a
/// NaN); a light behind the horizon gives exactly 0 (DOT3 clamps n·l at 0 and counts
/// a saturation; the factor path's self-shadowing flag zeroes the constant colour);
/// a light exactly on the horizon gives 0 on the factor path and, on the DOT3 path, at
/// most the Lambert term's derived bound (the expand-normal encoding has no exact 0:
/// 127.5 rounds to 128, so n·l reads a few codes above 0); a zero-length normal reads
/// as +x, the normalisation cube's documented result for a zero vector (one
/// `underflows` in the address unit).
#[test]
fn stiff_inputs_through_the_material_paths_give_levels_and_zero_below_the_horizon() {
    use glare_pipeline::reference::brdf::ShadingFrame;
    use glare_pipeline::scene::material::Distribution;
    use glare_pipeline::scene::math::v3;
    let cfg = PathConfig::default();
    let materials = [
        Material::Lambert,
        Material::BlinnPhong {
            ks: 1.0,
            exponent: 1.0,
            normalized: true,
        },
        Material::BlinnPhong {
            ks: 1.0,
            exponent: 1e4,
            normalized: true,
        },
        Material::CookTorrance {
            distribution: Distribution::Beckmann,
            roughness: 1e-3,
            ior: 0.27,
            extinction: 2.8,
            fresnel: Default::default(),
        },
        Material::CookTorrance {
            distribution: Distribution::Ggx,
            roughness: 1.0,
            ior: 1.5,
            extinction: 0.0,
            fresnel: Default::default(),
        },
        Material::Ward {
            rho_s: 0.5,
            alpha_x: 0.5,
            alpha_y: 0.005,
        },
        Material::OrenNayar { sigma_deg: 85.0 },
        Material::KajiyaKay {
            ks: 1.0,
            exponent: 1e4,
        },
    ];
    let n = v3(0.0, 0.0, 1.0);
    let frame = ShadingFrame::new(n, v3(1.0, 0.0, 0.0));
    let up = v3(0.0, 0.0, 1.0);
    let grazing = v3(1.0, 0.0, 0.0);
    let behind = v3(0.3, 0.2, -0.93).normalized();
    for m in materials {
        let path = material_path(&m, [0.8; 3], &cfg).unwrap();
        let mut ctr = Default::default();
        // Light behind: black.
        let s = path.shade(&frame, behind, up, &mut ctr).unwrap();
        assert_eq!(s.rgb, [0, 0, 0], "{m:?}: light behind");
        assert_eq!(s.specular, 0, "{m:?}: light behind");
        // Light exactly at the horizon: at most the diffuse bound.
        let s = path.shade(&frame, grazing, up, &mut ctr).unwrap();
        let bound = path.diffuse_error_bound().unwrap_or(0.0);
        let lambert_only = matches!(m, Material::Lambert);
        if lambert_only {
            assert!(
                s.rgb.iter().all(|&c| c as f64 <= bound),
                "{m:?}: {s:?} > {bound}"
            );
        } else {
            assert!(s.rgb.iter().all(|&c| c <= 255), "{m:?}");
        }
        // View exactly at the horizon, light overhead: a level, never NaN.
        let s = path.shade(&frame, up, grazing, &mut ctr).unwrap();
        assert!(s.rgb.iter().all(|&c| c <= 255), "{m:?}");
        // Head-on: lit.
        let s = path.shade(&frame, up, up, &mut ctr).unwrap();
        assert!(s.rgb.iter().all(|&c| c <= 255), "{m:?}");
        // A zero-length interpolated normal: a level, no panic.
        let zero = ShadingFrame::new(v3(0.0, 0.0, 0.0), v3(1.0, 0.0, 0.0));
        let s = path.shade(&zero, up, up, &mut ctr).unwrap();
        assert!(s.rgb.iter().all(|&c| c <= 255), "{m:?}");
    }
}
