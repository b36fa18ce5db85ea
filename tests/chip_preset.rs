//! The chip preset (`rtl_model::chip_preset`) as scenes select it: a shading scene's
//! `[shading] chip` and a frame scene's top-level `chip`. The NV2A's modes reach the
//! units the scene elaborates, change the output where the table of
//! docs/conformance.md says the chips differ, and nowhere else.

use glare_pipeline::frame::run::render;
use glare_pipeline::pipeline::shading::scene_file::ShadingFile;
use glare_pipeline::pipeline::shading::squaring::SquaringChain;
use glare_pipeline::pipeline::shading::sweep::{
    measure_point, shading_reference, sweep_view, VERTEX_RINGS, VERTEX_SEGMENTS,
};
use glare_pipeline::pipeline::shading::vertex_float::{one_light, sphere_vertices};
use glare_pipeline::scene::builtin::builtin;
use glare_pipeline::scene::format::Scene;
use glare_pipeline::scene::print::scene_toml;
use rtl_model::chip_preset::{ChipPreset, GL_SINGLE_COLOR};
use rtl_model::units::register_combiner::{
    Bias, BiasConstant, ComponentUsage, Mapping, MuxSelect, PortionConfig, Register,
    RegisterCombinerConfig, RegisterFile, Scale, VariableInput,
};
use rtl_model::units::vertex_lighting::{VertexLighting, VertexLightingConfig};
use rtl_model::{Counters, Unit};
use std::process::Command;

fn shading_file(scene: &str, chip: Option<&str>, extra: &str) -> ShadingFile {
    let chip = chip.map_or(String::new(), |c| format!("chip = \"{c}\"\n"));
    ShadingFile::parse(&format!("[shading]\nscene = \"{scene}\"\n{chip}{extra}"))
        .unwrap_or_else(|e| panic!("{scene}: {e}"))
}

/// The squaring chain's register combiners carry the NV2A's bias constant and mux
/// select; the chain neither biases nor muxes, so its picture is the GeForce2's, and a
/// stage that does bias shows the mode is live.
#[test]
fn squaring_path_carries_the_nv2a_modes_and_keeps_its_pixels() {
    let g = SquaringChain::on_chip(9, ChipPreset::GeForce2).unwrap();
    let n = SquaringChain::on_chip(9, ChipPreset::Nv2a).unwrap();
    for stage in [n.dot_stage, n.square_stage] {
        assert_eq!(stage.config().bias_constant, BiasConstant::HalfCode);
        assert_eq!(stage.config().mux_select, MuxSelect::Lsb);
    }
    for stage in [g.dot_stage, g.square_stage] {
        assert_eq!(stage.config().bias_constant, BiasConstant::ExactHalf);
        assert_eq!(stage.config().mux_select, MuxSelect::Msb);
    }
    assert_eq!(n.final_stage.config(), g.final_stage.config());

    // The whole shading-specular squaring path, as `render --scene FILE` draws it.
    let view = sweep_view(64);
    let levels = |chip: Option<&str>| {
        let f = shading_file(
            "shading-specular",
            chip,
            "[shading.hw]\ncombiner_bits = 9\n",
        );
        let r = shading_reference(&f.point, &view).unwrap();
        (f.point, measure_point(&f.point, &view, &r).unwrap().levels)
    };
    let (pg, lg) = levels(None);
    let (pn, ln) = levels(Some("nv2a"));
    assert_eq!(pg.chip(), ChipPreset::GeForce2);
    assert_eq!(pn.chip(), ChipPreset::Nv2a);
    assert_eq!(
        pn.units_the_chip_changes(),
        vec!["register_combiner"],
        "the squaring path's units the preset sets"
    );
    assert!(lg.iter().any(|&x| x > 0.0), "the sphere is drawn");
    assert_eq!(lg, ln, "no bias and no mux: the same pixels on both chips");

    // A stage that biases: TEXTURE0 · 1 − ½ → SPARE0 on each chip's preset.
    let var = |r, m| VariableInput::new(r, m, ComponentUsage::Rgb);
    let zero = var(Register::Zero, Mapping::UnsignedIdentity);
    let biased = |chip: ChipPreset| {
        chip.register_combiner(RegisterCombinerConfig {
            rgb: PortionConfig {
                a: var(Register::Texture0, Mapping::UnsignedIdentity),
                b: var(Register::Zero, Mapping::UnsignedInvert),
                c: zero,
                d: zero,
                ab_output: Some(Register::Spare0),
                cd_output: None,
                sum_output: None,
                scale: Scale::None,
                bias: Bias::ByNegativeOneHalf,
                ab_dot_product: false,
                cd_dot_product: false,
                mux_sum: false,
            },
            alpha: PortionConfig::discard(ComponentUsage::Alpha),
            ..RegisterCombinerConfig::geforce()
        })
        .build()
        .unwrap()
    };
    let (bg, bn) = (biased(ChipPreset::GeForce2), biased(ChipPreset::Nv2a));
    let out = |u: &rtl_model::units::register_combiner::RegisterCombiner, c: u32| {
        let mut ctr = Counters::default();
        let mut f = RegisterFile::default();
        let v = u.load_unorm(c, &mut ctr);
        f.set(Register::Texture0, [v, v, v, 0]);
        u.kernel(&mut (), &f, &mut ctr).get(Register::Spare0)[0]
    };
    let differ = (0..=255u32).filter(|&c| out(&bg, c) != out(&bn, c)).count();
    assert!(
        differ > 0,
        "the NV2A's bias constant changes a biased output"
    );
}

/// Lights every vertex of shading-vertex's sphere; the colour codes per vertex.
fn vertex_codes(cfg: VertexLightingConfig) -> Vec<[u32; 4]> {
    let u = VertexLighting::new(cfg, &one_light()).unwrap();
    let mut ctr = Counters::default();
    sphere_vertices(VERTEX_RINGS, VERTEX_SEGMENTS)
        .iter()
        .map(|&(p, n)| {
            let v = u.vertex_from_f64(p, n, &mut ctr).unwrap();
            u.kernel(&mut (), &v, &mut ctr).rgba
        })
        .collect()
}

/// shading-vertex on the NV2A: the directional light's vector is used as written
/// (|L| = 0.9975 here), which changes lit vertices only; with that one mode put back,
/// the NV2A's two-colour datapath under GL's single-colour switches gives the GeForce2's
/// codes exactly.
#[test]
fn vertex_lighting_on_the_nv2a_changes_lit_vertices_only() {
    let base = VertexLightingConfig::geforce();
    let g = ChipPreset::GeForce2.vertex_lighting(base, GL_SINGLE_COLOR);
    let n = ChipPreset::Nv2a.vertex_lighting(base, GL_SINGLE_COLOR);
    assert!(!n.normalize_directional && n.light_control.is_some());
    let (cg, cn) = (vertex_codes(g), vertex_codes(n));
    let light = one_light().lights[0].position;
    let len = (light[0] * light[0] + light[1] * light[1] + light[2] * light[2]).sqrt();
    assert!(
        (len - 1.0).abs() > 1e-3,
        "the scene's light is not unit length"
    );
    let verts = sphere_vertices(VERTEX_RINGS, VERTEX_SEGMENTS);
    let mut changed = 0;
    for ((a, b), (_, nrm)) in cg.iter().zip(&cn).zip(&verts) {
        if a != b {
            changed += 1;
            let nl = nrm[0] * light[0] + nrm[1] * light[1] + nrm[2] * light[2];
            assert!(nl > 0.0, "an unlit vertex changed: {a:?} → {b:?}");
            for k in 0..3 {
                assert!(a[k].abs_diff(b[k]) <= 1, "{a:?} → {b:?}");
            }
        }
    }
    println!(
        "shading-vertex: {changed} of {} vertices change on the NV2A",
        verts.len()
    );
    assert!(
        changed > 0,
        "the NV2A's directional load changes some vertex"
    );
    let n_normalised = VertexLightingConfig {
        normalize_directional: true,
        ..n
    };
    assert_eq!(
        vertex_codes(n_normalised),
        cg,
        "only the directional load differs"
    );

    // Through the scene file: the chip reaches the unit, and the error is taken
    // against the twin in the same modes (the NV2A's two-colour path).
    let f = shading_file("shading-vertex", Some("nv2a"), "");
    assert_eq!(f.point.units_the_chip_changes(), vec!["vertex_lighting"]);
    let view = sweep_view(16);
    let r = shading_reference(&f.point, &view).unwrap();
    let m = measure_point(&f.point, &view, &r).unwrap();
    assert!(
        m.max_levels <= 1.0,
        "against the NV2A twin: {}",
        m.max_levels
    );
    let fg = shading_file("shading-vertex", None, "");
    let rg = shading_reference(&fg.point, &view).unwrap();
    assert_ne!(r, rg, "the twin follows the chip's modes");
}

/// A frame scene at `chip = "nv2a"`: no unit a frame elaborates differs between the
/// chips, so the picture is the GeForce2's; the scene text keeps the field.
#[test]
fn a_frame_scene_on_the_nv2a_renders_the_same_and_keeps_its_chip() {
    let mut s = builtin("shaded-metal").unwrap();
    s.image.width = 48;
    s.image.height = 32;
    let mut n = s.clone();
    n.chip = ChipPreset::Nv2a;
    let (fg, fn_) = (render(&s).unwrap(), render(&n).unwrap());
    assert_eq!(fg.fb, fn_.fb, "same pixels");
    let names: Vec<String> = fg
        .elaboration()
        .into_iter()
        .filter(|u| u.summary.is_some())
        .map(|u| u.name)
        .collect();
    assert!(
        names.iter().any(|n| n.contains("texture_combiner")),
        "the shading units ran: {names:?}"
    );

    let text = scene_toml(&n, "").unwrap();
    assert!(text.contains("chip = \"nv2a\""), "{text}");
    let back: Scene = toml::from_str(&text).unwrap();
    assert_eq!(back, n);
    assert!(!scene_toml(&s, "").unwrap().contains("chip ="));
}

/// The reports say which preset the scene uses (text and JSON), and a bad name is
/// refused naming the field.
#[test]
fn reports_name_the_preset_and_bad_names_are_refused() {
    let dir = std::env::temp_dir().join(format!("chip_preset_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |args: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
            .args(args)
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stdout).to_string(),
            String::from_utf8_lossy(&o.stderr).to_string(),
        )
    };
    let vertex = dir.join("vertex.toml");
    std::fs::write(
        &vertex,
        "[shading]\nscene = \"shading-vertex\"\nchip = \"nv2a\"\n",
    )
    .unwrap();
    let (code, out, err) = run(&["render", "--scene", vertex.to_str().unwrap(), "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    let details = &j["shading"];
    assert_eq!(details["chip_preset"], "nv2a", "{out}");
    assert_eq!(details["units_the_chip_changes"][0], "vertex_lighting");
    let (_, text, _) = run(&["render", "--scene", vertex.to_str().unwrap()]);
    assert!(
        text.contains("chip preset: nv2a (vertex_lighting.normalize_directional = false"),
        "{text}"
    );

    let mut s = builtin("shaded-metal").unwrap();
    s.chip = ChipPreset::Nv2a;
    let frame = dir.join("frame.toml");
    std::fs::write(&frame, scene_toml(&s, "").unwrap()).unwrap();
    let (code, out, err) = run(&["render", "--scene", frame.to_str().unwrap(), "--plan"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        out.contains("chip preset: nv2a (no unit of this frame"),
        "{out}"
    );
    let (_, out, _) = run(&[
        "render",
        "--scene",
        frame.to_str().unwrap(),
        "--plan",
        "--json",
    ]);
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["chip"]["preset"], "nv2a", "{out}");

    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        scene_toml(&s, "")
            .unwrap()
            .replace("chip = \"nv2a\"", "chip = \"nv20\""),
    )
    .unwrap();
    let (code, _, err) = run(&["render", "--scene", bad.to_str().unwrap(), "--plan"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("chip") && err.contains("nv2a"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
