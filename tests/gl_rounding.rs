//! The GL rounding modes are the user's choice (issue 16, docs/shading.md "The GL
//! oracle"): a scene's `[rounding]` reaches the units. Each built-in below is rendered
//! small through the whole frame (as `render` draws it) in each mode:
//! - no `[rounding]`, and `[rounding]` with its defaults written out, give identical
//!   bytes and counters (the default is today's datapath: tests/golden.rs);
//! - `chain = "fused"` (Mesa's llvmpipe: one rounding of the factor-texture ×
//!   constant-colour product) changes some pixel of a shaded Cook–Torrance sphere, whose
//!   factored lobe runs through the modulate chain;
//! - `filter = "successive_lerps"` with `weight = "round_half_even"` (llvmpipe's
//!   bilinear filter) changes some pixel of fig6, whose F and h tables are filtered
//!   bilinearly, and of the shaded sphere (its factor textures).
//!
//! The modes themselves are bit-exact against OSMesa in tests/modulate_mesa.rs and
//! tests/texture_sampler_mesa.rs.

use glare_pipeline::frame::run::{render, Frame};
use glare_pipeline::scene::builtin::builtin;
use glare_pipeline::scene::format::Scene;
use glare_pipeline::scene::limits::GlRounding;
use rtl_model::units::modulate::ChainRounding;
use rtl_model::units::texture_sampler::{FilterRounding, WeightRounding};

fn small(name: &str) -> Scene {
    let mut s = builtin(name).unwrap();
    s.image.width = 120;
    s.image.height = 80;
    s.shafts.planes = s.shafts.planes.min(8);
    s.shafts.subplanes = s.shafts.subplanes.min(2);
    s
}

fn with(mut s: Scene, r: Option<GlRounding>) -> Scene {
    s.rounding = r;
    // Through the scene file, as a user writes it: validation and serde see the table.
    let text = toml::to_string(&s).unwrap();
    Scene::from_toml_str(&text).unwrap()
}

/// The final picture and every counter the frame kept, as text.
fn picture(s: &Scene) -> (Vec<u32>, String) {
    let f: Frame = render(s).unwrap();
    let counters = format!(
        "{:?} {:?} {:?}",
        f.shafts.as_ref().map(|r| &r.counters),
        f.linked.as_ref().map(|l| &l.shading.counters),
        f.glare.as_ref().map(|(g, _)| &g.counters)
    );
    (f.fb.data, counters)
}

fn pixels_differing(a: &[u32], b: &[u32]) -> usize {
    a.chunks(4).zip(b.chunks(4)).filter(|(p, q)| p != q).count()
}

#[test]
fn defaults_written_out_are_todays_bytes() {
    for name in ["fig6", "shaded-metal"] {
        let base = small(name);
        let none = picture(&with(base.clone(), None));
        let explicit = picture(&with(base, Some(GlRounding::default())));
        assert_eq!(
            none, explicit,
            "{name}: the default [rounding] changed the frame"
        );
    }
}

#[test]
fn fused_chain_reaches_the_shading_units() {
    let base = small("shaded-metal");
    let (default_fb, _) = picture(&with(base.clone(), None));
    let fused = GlRounding {
        chain: ChainRounding::Fused,
        ..GlRounding::default()
    };
    let (fused_fb, _) = picture(&with(base, Some(fused)));
    let n = pixels_differing(&default_fb, &fused_fb);
    println!("shaded-metal 120 × 80: fused chain changes {n} pixels");
    assert!(n > 0, "chain = \"fused\" did not change a pixel");
}

#[test]
fn llvmpipe_filter_reaches_the_samplers() {
    let mesa_filter = GlRounding {
        filter: FilterRounding::SuccessiveLerps,
        weight: WeightRounding::RoundHalfEven,
        ..GlRounding::default()
    };
    for name in ["fig6", "shaded-metal"] {
        let base = small(name);
        let (default_fb, _) = picture(&with(base.clone(), None));
        let (mesa_fb, _) = picture(&with(base, Some(mesa_filter)));
        let n = pixels_differing(&default_fb, &mesa_fb);
        println!("{name} 120 × 80: llvmpipe filtering changes {n} pixels");
        assert!(n > 0, "{name}: llvmpipe filtering did not change a pixel");
    }
    // All three together (the preset) validate and render.
    let (fb, _) = picture(&with(
        small("shaded-metal"),
        Some(GlRounding::mesa_llvmpipe()),
    ));
    assert_eq!(fb.len(), 120 * 80 * 4);
}

#[test]
fn an_unknown_mode_names_its_field() {
    let s = small("fig6");
    let text = toml::to_string(&s).unwrap() + "\n[rounding]\nfilter = \"lerp\"\n";
    let e = Scene::from_toml_str(&text).unwrap_err();
    assert_eq!(e.field(), "rounding.filter", "{e}");
    let text = toml::to_string(&s).unwrap() + "\n[rounding]\nweight = \"nearest\"\n";
    let e = Scene::from_toml_str(&text).unwrap_err();
    assert_eq!(e.field(), "rounding.weight", "{e}");
}
