//! Scene errors of the glare section (issue 4): a malformed `[glare]` gives a clear
//! error naming the field (its TOML path, `glare.sources[0].intensity`), never a
//! panic. Scenes are TOML text through `Scene::from_toml_str`; a source's position
//! is checked against the camera when the frame is set up (`render_glare`), because
//! validation does not project.
//!
//! The last test is a proptest: one field of a valid glare scene set to a special
//! value (NaN, ±∞, negative, zero, tiny, huge, a wrong type); parsing and
//! validation never panic, an error names exactly that field, and a scene that is
//! accepted renders (96 × 64) without panic to levels in [0, 255] — or, where only
//! the hardware can tell (a highlight brighter than the glare-condition unit's u12.4
//! input), fails with an error naming a `glare.` field.

use glare_pipeline::pipeline::glare::frame::render_glare;
use glare_pipeline::scene::format::Scene;
use proptest::prelude::*;
use rtl_model::ConfigError;
use toml::Value;

/// A small valid glare scene: 96 × 64, an elliptic source with all three glare
/// components, a fluctuating circle, a metallic highlight.
const BASE: &str = r#"
name = "glare-scene-test"
seed = 3

[image]
width = 96
height = 64

[camera]
eye = [0.0, 0.0, 0.0]
look_at = [0.0, 0.0, -1.0]
up = [0.0, 1.0, 0.0]
fovy_deg = 25.0
near = 0.5
far = 100.0

[glare]
frame = 3

[glare.background]
type = "sky"
top = [0.0, 0.0, 0.05]
bottom = [0.02, 0.02, 0.05]

[glare.determinants]
ambient = 4.0
age = 30.0
mist = 0.1
glasses = true
wavelengths_nm = [650.0, 550.0, 450.0]

[glare.model]
point_theta0_deg = 0.13
point_m = 2.8
chaos_a = 0.8
chaos_z = 1.95
e_mist = 1.0

[glare.hw]
shape_log2 = 6
falloff_log2 = 8

[[glare.sources]]
kind = "elliptic"
position = [0.0, 0.0, -20.0]
a = 0.3
b = 0.1
n = [0.0, 1.0, 0.0]
intensity = 2000.0
area_size = 1.0
color = [1.0, 0.95, 0.85]

[[glare.sources]]
kind = "circle"
position = [1.0, 0.5, -20.0]
a = 0.05
intensity = 800.0
halo = false

[glare.sources.fluctuation]
patches = 3
spread = 0.5
patch_radius = 0.05

[[glare.highlights]]
material = "metallic"
position = [-1.0, -0.5, -10.0]
normal = [0.0, 0.0, 1.0]
light = [-1.0, -0.5, 0.0]
intensity = 1000.0
specular = 0.9
"#;

fn base_value() -> Value {
    toml::from_str(BASE).expect("BASE parses")
}

/// One step of a path into a TOML document.
#[derive(Clone, Copy, Debug)]
enum Step {
    Key(&'static str),
    Index(usize),
}
use Step::{Index as I, Key as K};

fn slot<'a>(v: &'a mut Value, path: &[Step]) -> &'a mut Value {
    let mut cur = v;
    for (n, s) in path.iter().enumerate() {
        let last = n + 1 == path.len();
        cur = match (*s, cur) {
            (K(k), Value::Table(t)) => {
                if last {
                    t.entry(k.to_string()).or_insert(Value::Integer(0))
                } else {
                    t.get_mut(k).unwrap_or_else(|| panic!("no key {k}"))
                }
            }
            (I(i), Value::Array(a)) => &mut a[i],
            (s, other) => panic!("step {s:?} into {other:?}"),
        };
    }
    cur
}

/// BASE with the value at `path` replaced (or added).
fn with(path: &[Step], value: Value) -> String {
    let mut v = base_value();
    *slot(&mut v, path) = value;
    toml::to_string(&v).expect("serialises")
}

/// BASE with the value at `path` given as TOML text (for values `toml::Value` cannot
/// hold, e.g. integers beyond i64, or to keep the exact spelling).
fn with_text(path: &[Step], text: &str) -> String {
    // A unique marker string, replaced by the raw text after serialising.
    let marker = "@@VALUE@@";
    with(path, Value::String(marker.into())).replace(&format!("\"{marker}\""), text)
}

fn err_of(text: &str) -> ConfigError {
    match Scene::from_toml_str(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

/// The scene is rejected with an error naming `field` (and the message shows it).
fn assert_names(text: &str, field: &str) {
    let e = err_of(text);
    assert_eq!(e.field(), field, "error: {e}");
    assert!(
        e.to_string().contains(field),
        "message lacks the field: {e}"
    );
}

fn f(x: f64) -> Value {
    Value::Float(x)
}

// ---------------------------------------------------------------- the base itself

#[test]
fn base_scene_is_valid_and_renders() {
    let s = Scene::from_toml_str(BASE).unwrap();
    let fr = render_glare(&s).unwrap();
    assert_eq!(fr.fb.width, 96);
    assert!(fr.sources.len() >= 5, "1 + 3 patches + 1 highlight");
}

// ---------------------------------------------------------------- the issue's list

/// NaN, ±∞, negative and too-large intensities name `glare.sources[0].intensity`.
#[test]
fn bad_intensity_names_the_field() {
    let path = [K("glare"), K("sources"), I(0), K("intensity")];
    for x in [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        -1.0,
        -1e-300,
        2e9,
    ] {
        assert_names(&with(&path, f(x)), "glare.sources[0].intensity");
    }
    // 0 and 10⁹ are the ends of the accepted range.
    for x in [0.0, 1e9] {
        Scene::from_toml_str(&with(&path, f(x))).unwrap();
    }
    // The second source and the highlight are named by their own index.
    assert_names(
        &with(
            &[K("glare"), K("sources"), I(1), K("intensity")],
            f(f64::NAN),
        ),
        "glare.sources[1].intensity",
    );
    assert_names(
        &with(
            &[K("glare"), K("highlights"), I(0), K("intensity")],
            f(-5.0),
        ),
        "glare.highlights[0].intensity",
    );
}

/// b > a (semi-minor longer than semi-major) names `glare.sources[0].b`; b = a is a
/// circle and accepted.
#[test]
fn semi_minor_longer_than_semi_major() {
    let e = err_of(&with(&[K("glare"), K("sources"), I(0), K("b")], f(0.31)));
    assert_eq!(e.field(), "glare.sources[0].b");
    assert!(e.to_string().contains("semi-major"), "{e}");
    Scene::from_toml_str(&with(&[K("glare"), K("sources"), I(0), K("b")], f(0.3))).unwrap();
}

/// An unknown source kind is a TOML parse error naming the field, with toml's own
/// message (the accepted variants) and the position.
#[test]
fn unknown_source_kind_is_a_parse_error_naming_the_field() {
    let e = err_of(&with(
        &[K("glare"), K("sources"), I(0), K("kind")],
        Value::String("triangle".into()),
    ));
    assert_eq!(e.field(), "glare.sources[0].kind", "{e}");
    let msg = e.to_string();
    assert!(
        msg.contains("triangle") && msg.contains("elliptic"),
        "{msg}"
    );
    assert!(msg.contains("TOML line"), "{msg}");
    // An unknown highlight material likewise.
    let e = err_of(&with(
        &[K("glare"), K("highlights"), I(0), K("material")],
        Value::String("glass".into()),
    ));
    assert_eq!(e.field(), "glare.highlights[0].material", "{e}");
}

/// A source behind the camera (or on the eye's plane) is valid TOML but cannot be
/// projected: setting up the frame fails with an error naming
/// `glare.sources[0].position`; for a polygon vertex, `…vertices[k]`; for a
/// highlight, `glare.highlights[0].position`. Never a panic.
#[test]
fn source_behind_the_camera_names_the_position() {
    for p in [[0.0, 0.0, 20.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1e-13]] {
        let text = with(
            &[K("glare"), K("sources"), I(0), K("position")],
            Value::try_from(p).unwrap(),
        );
        let s = Scene::from_toml_str(&text).unwrap();
        let e = render_glare(&s).unwrap_err();
        assert_eq!(e.field(), "glare.sources[0].position", "{e}");
        assert!(e.to_string().contains("behind the camera"), "{e}");
    }
    // A polygon whose second vertex is behind the eye.
    let mut v = base_value();
    {
        let src = slot(&mut v, &[K("glare"), K("sources"), I(0)]);
        let t = src.as_table_mut().unwrap();
        t.insert("kind".into(), Value::String("polygon".into()));
        t.insert(
            "vertices".into(),
            Value::try_from(vec![[0.5, 0.0, -20.0], [0.0, 0.5, 5.0]]).unwrap(),
        );
    }
    let s = Scene::from_toml_str(&toml::to_string(&v).unwrap()).unwrap();
    let e = render_glare(&s).unwrap_err();
    assert_eq!(e.field(), "glare.sources[0].vertices[1]", "{e}");
    // A highlight behind the eye.
    let text = with(
        &[K("glare"), K("highlights"), I(0), K("position")],
        Value::try_from([0.0, 0.0, 3.0]).unwrap(),
    );
    let s = Scene::from_toml_str(&text).unwrap();
    let e = render_glare(&s).unwrap_err();
    assert_eq!(e.field(), "glare.highlights[0].position", "{e}");
}

/// Hardware widths out of range name `glare.hw.<field>`: shape_log2 ∈ 1 ..= 10,
/// so 0 and 11 fail; a negative or fractional width is a parse error naming it.
#[test]
fn hw_widths_out_of_range() {
    let p = [K("glare"), K("hw"), K("shape_log2")];
    for x in [0, 11, 64] {
        assert_names(&with(&p, Value::Integer(x)), "glare.hw.shape_log2");
    }
    for x in [1, 10] {
        Scene::from_toml_str(&with(&p, Value::Integer(x))).unwrap();
    }
    assert_names(&with(&p, Value::Integer(-1)), "glare.hw.shape_log2");
    assert_names(&with(&p, f(6.5)), "glare.hw.shape_log2");
    for (k, bad) in [
        ("shape_bits", 17),
        ("falloff_log2", 13),
        ("falloff_bits", 0),
        ("weight_bits", 13),
        ("coord_frac_bits", 1),
        ("noise_bits", 7),
        ("fb_bits", 17),
        ("pipes", 0),
    ] {
        assert_names(
            &with(&[K("glare"), K("hw"), K(k)], Value::Integer(bad)),
            &format!("glare.hw.{k}"),
        );
    }
    for x in [0.0, -300.0, f64::NAN, 2e5] {
        assert_names(
            &with(&[K("glare"), K("hw"), K("clock_mhz")], f(x)),
            "glare.hw.clock_mhz",
        );
    }
}

/// The chaos map's z and a lie in open intervals: z = 1 and z = 2, a = 0 and a = 1
/// are rejected naming `glare.model.chaos_z` / `chaos_a`; 1.0001, 1.9999 and a
/// near 0 or 1 are accepted.
#[test]
fn chaos_parameters_open_intervals() {
    let z = [K("glare"), K("model"), K("chaos_z")];
    for x in [1.0, 2.0, 0.5, 2.5, f64::NAN] {
        assert_names(&with(&z, f(x)), "glare.model.chaos_z");
    }
    for x in [1.0001, 1.9999] {
        Scene::from_toml_str(&with(&z, f(x))).unwrap();
    }
    let a = [K("glare"), K("model"), K("chaos_a")];
    for x in [0.0, 1.0, -0.1, f64::INFINITY] {
        assert_names(&with(&a, f(x)), "glare.model.chaos_a");
    }
    for x in [1e-9, 0.999_999] {
        Scene::from_toml_str(&with(&a, f(x))).unwrap();
    }
}

/// An R1 exponent below 0 would flip Table 1's sign: every `e_*` < 0 (and > 8) is
/// rejected naming it.
#[test]
fn negative_exponents_rejected() {
    for k in [
        "e_intensity",
        "e_glasses",
        "e_size",
        "e_ambient",
        "e_mist",
        "e_directivity",
        "e_shape",
    ] {
        for x in [-0.5, -1e-12, 8.5, f64::NAN] {
            assert_names(
                &with(&[K("glare"), K("model"), K(k)], f(x)),
                &format!("glare.model.{k}"),
            );
        }
        Scene::from_toml_str(&with(&[K("glare"), K("model"), K(k)], f(0.0))).unwrap();
    }
}

/// The frame number: above 10⁷ is rejected naming `glare.frame`; beyond u32, or
/// negative, is a parse error naming it.
#[test]
fn frame_huge() {
    let p = [K("glare"), K("frame")];
    assert_names(&with(&p, Value::Integer(10_000_001)), "glare.frame");
    assert_names(&with(&p, Value::Integer(5_000_000_000)), "glare.frame");
    assert_names(&with(&p, Value::Integer(-1)), "glare.frame");
    assert_names(&with_text(&p, "1e300"), "glare.frame");
    Scene::from_toml_str(&with(&p, Value::Integer(10_000_000))).unwrap();
}

/// Other malformed fields: each names its path.
#[test]
fn other_fields_named() {
    let cases: Vec<(Vec<Step>, Value, &str)> = vec![
        (
            vec![K("glare"), K("sources"), I(0), K("area_size")],
            f(1.5),
            "glare.sources[0].area_size",
        ),
        (
            vec![K("glare"), K("sources"), I(0), K("color")],
            Value::try_from([1.0, 2.0, 0.0]).unwrap(),
            "glare.sources[0].color[1]",
        ),
        (
            vec![K("glare"), K("sources"), I(0), K("directivity")],
            Value::try_from([0.0, 0.0, 0.0]).unwrap(),
            "glare.sources[0].directivity",
        ),
        (
            vec![K("glare"), K("sources"), I(0), K("n")],
            Value::try_from([0.0, f64::NAN, 0.0]).unwrap(),
            "glare.sources[0].n[1]",
        ),
        (
            vec![K("glare"), K("sources"), I(0), K("a")],
            f(-0.1),
            "glare.sources[0].a",
        ),
        (
            vec![K("glare"), K("sources"), I(0), K("position")],
            Value::try_from([0.0, 0.0, -2e6]).unwrap(),
            "glare.sources[0].position[2]",
        ),
        (
            vec![
                K("glare"),
                K("sources"),
                I(1),
                K("fluctuation"),
                K("patches"),
            ],
            Value::Integer(0),
            "glare.sources[1].fluctuation.patches",
        ),
        (
            vec![
                K("glare"),
                K("sources"),
                I(1),
                K("fluctuation"),
                K("patches"),
            ],
            Value::Integer(65),
            "glare.sources[1].fluctuation.patches",
        ),
        (
            vec![
                K("glare"),
                K("sources"),
                I(1),
                K("fluctuation"),
                K("spread"),
            ],
            f(f64::NAN),
            "glare.sources[1].fluctuation.spread",
        ),
        (
            vec![K("glare"), K("highlights"), I(0), K("eta")],
            f(0.0),
            "glare.highlights[0].eta",
        ),
        (
            vec![K("glare"), K("highlights"), I(0), K("normal")],
            Value::try_from([0.0, 0.0, 0.0]).unwrap(),
            "glare.highlights[0].normal",
        ),
        (
            vec![K("glare"), K("highlights"), I(0), K("specular")],
            f(1.01),
            "glare.highlights[0].specular",
        ),
        (
            vec![K("glare"), K("determinants"), K("ambient")],
            f(-1.0),
            "glare.determinants.ambient",
        ),
        (
            vec![K("glare"), K("determinants"), K("age")],
            f(121.0),
            "glare.determinants.age",
        ),
        (
            vec![K("glare"), K("determinants"), K("mist")],
            f(f64::NAN),
            "glare.determinants.mist",
        ),
        (
            vec![K("glare"), K("determinants"), K("wavelengths_nm")],
            Value::try_from([650.0, 200.0, 450.0]).unwrap(),
            "glare.determinants.wavelengths_nm[1]",
        ),
        (
            vec![K("glare"), K("determinants"), K("glasses")],
            Value::String("yes".into()),
            "glare.determinants.glasses",
        ),
        (
            vec![K("glare"), K("model"), K("point_theta0_deg")],
            f(0.0),
            "glare.model.point_theta0_deg",
        ),
        (
            vec![K("glare"), K("model"), K("point_m")],
            f(8.5),
            "glare.model.point_m",
        ),
        (
            vec![K("glare"), K("model"), K("bloom_m")],
            f(0.4),
            "glare.model.bloom_m",
        ),
        (
            vec![K("glare"), K("model"), K("halo_alpha_deg")],
            f(0.0),
            "glare.model.halo_alpha_deg",
        ),
        (
            vec![K("glare"), K("model"), K("contrast")],
            f(0.0),
            "glare.model.contrast",
        ),
        (
            vec![K("glare"), K("model"), K("glasses_flare")],
            f(0.5),
            "glare.model.glasses_flare",
        ),
        (
            vec![K("glare"), K("model"), K("flare_max_lines")],
            Value::Integer(1025),
            "glare.model.flare_max_lines",
        ),
        (
            vec![K("glare"), K("background"), K("top")],
            Value::try_from([0.0, 2.0, 0.0]).unwrap(),
            "glare.background.top[1]",
        ),
    ];
    for (path, value, field) in cases {
        assert_names(&with(&path, value), field);
    }
}

/// A polygon needs 2 ..= 64 vertices besides `position`.
#[test]
fn polygon_vertex_count() {
    let mut v = base_value();
    {
        let t = slot(&mut v, &[K("glare"), K("sources"), I(0)])
            .as_table_mut()
            .unwrap();
        t.insert("kind".into(), Value::String("polygon".into()));
        t.insert(
            "vertices".into(),
            Value::try_from(vec![[0.5, 0.0, -20.0]]).unwrap(),
        );
    }
    assert_names(&toml::to_string(&v).unwrap(), "glare.sources[0].vertices");
}

/// Unknown keys are parse errors naming them (deny_unknown_fields), and an unknown
/// background type names `glare.background.type`.
#[test]
fn unknown_keys_named() {
    let e = err_of(&with(&[K("glare"), K("model"), K("e_mistt")], f(1.0)));
    assert!(e.field().starts_with("glare.model"), "{e}");
    assert!(e.to_string().contains("e_mistt"), "{e}");
    let e = err_of(&with(
        &[K("glare"), K("sources"), I(0), K("radius")],
        f(1.0),
    ));
    assert!(e.field().starts_with("glare.sources[0]"), "{e}");
    assert!(e.to_string().contains("radius"), "{e}");
    let e = err_of(&with(
        &[K("glare"), K("background"), K("type")],
        Value::String("stars".into()),
    ));
    assert!(e.field().starts_with("glare.background"), "{e}");
    assert!(e.to_string().contains("stars"), "{e}");
}

/// A highlight brighter than the glare-condition unit's u12.4 intensity input
/// (> 4095.9375 codes) passes validation (which allows 10⁹) but the frame set-up
/// rejects it, naming `glare.highlights[0].glare_condition.intensity`; so does an
/// ambient beyond u12.4 when there are highlights. A documented limit, not a panic.
#[test]
fn highlight_beyond_the_condition_units_range() {
    let text = with(
        &[K("glare"), K("highlights"), I(0), K("intensity")],
        f(5000.0),
    );
    let s = Scene::from_toml_str(&text).unwrap();
    let e = render_glare(&s).unwrap_err();
    assert_eq!(
        e.field(),
        "glare.highlights[0].glare_condition.intensity",
        "{e}"
    );
    let text = with(&[K("glare"), K("determinants"), K("ambient")], f(5000.0));
    let s = Scene::from_toml_str(&text).unwrap();
    let e = render_glare(&s).unwrap_err();
    assert_eq!(
        e.field(),
        "glare.highlights[0].glare_condition.ambient",
        "{e}"
    );
    // 4095 is accepted.
    let text = with(
        &[K("glare"), K("highlights"), I(0), K("intensity")],
        f(4095.0),
    );
    render_glare(&Scene::from_toml_str(&text).unwrap()).unwrap();
}

// ---------------------------------------------------------------- proptest

/// Every field the proptest perturbs: its path, its full name, and whether it holds
/// an integer.
fn fields() -> Vec<(Vec<Step>, &'static str, bool)> {
    let src = |k: &'static str| vec![K("glare"), K("sources"), I(0), K(k)];
    let model = |k: &'static str| vec![K("glare"), K("model"), K(k)];
    let hw = |k: &'static str| vec![K("glare"), K("hw"), K(k)];
    let det = |k: &'static str| vec![K("glare"), K("determinants"), K(k)];
    let hl = |k: &'static str| vec![K("glare"), K("highlights"), I(0), K(k)];
    vec![
        (src("intensity"), "glare.sources[0].intensity", false),
        (src("a"), "glare.sources[0].a", false),
        (src("b"), "glare.sources[0].b", false),
        (src("area_size"), "glare.sources[0].area_size", false),
        (
            vec![K("glare"), K("sources"), I(1), K("a")],
            "glare.sources[1].a",
            false,
        ),
        (
            vec![
                K("glare"),
                K("sources"),
                I(1),
                K("fluctuation"),
                K("spread"),
            ],
            "glare.sources[1].fluctuation.spread",
            false,
        ),
        (
            vec![
                K("glare"),
                K("sources"),
                I(1),
                K("fluctuation"),
                K("patch_radius"),
            ],
            "glare.sources[1].fluctuation.patch_radius",
            false,
        ),
        (det("ambient"), "glare.determinants.ambient", false),
        (det("age"), "glare.determinants.age", false),
        (det("mist"), "glare.determinants.mist", false),
        (hl("intensity"), "glare.highlights[0].intensity", false),
        (hl("specular"), "glare.highlights[0].specular", false),
        (hl("eta"), "glare.highlights[0].eta", false),
        (hl("radius"), "glare.highlights[0].radius", false),
        (
            model("point_theta0_deg"),
            "glare.model.point_theta0_deg",
            false,
        ),
        (model("point_m"), "glare.model.point_m", false),
        (model("point_a"), "glare.model.point_a", false),
        (model("bloom_n"), "glare.model.bloom_n", false),
        (model("bloom_m"), "glare.model.bloom_m", false),
        (model("bloom_w_deg"), "glare.model.bloom_w_deg", false),
        (
            model("bloom_theta1_deg"),
            "glare.model.bloom_theta1_deg",
            false,
        ),
        (model("bloom_k"), "glare.model.bloom_k", false),
        (model("halo_k"), "glare.model.halo_k", false),
        (
            model("halo_radius_deg"),
            "glare.model.halo_radius_deg",
            false,
        ),
        (model("halo_alpha_deg"), "glare.model.halo_alpha_deg", false),
        (model("flare_num_k"), "glare.model.flare_num_k", false),
        (
            model("flare_len_k_deg"),
            "glare.model.flare_len_k_deg",
            false,
        ),
        (
            model("flare_width_k_deg"),
            "glare.model.flare_width_k_deg",
            false,
        ),
        (
            model("flare_intensity_k"),
            "glare.model.flare_intensity_k",
            false,
        ),
        (
            model("flare_spread_rad"),
            "glare.model.flare_spread_rad",
            false,
        ),
        (model("e_intensity"), "glare.model.e_intensity", false),
        (model("e_size"), "glare.model.e_size", false),
        (model("e_mist"), "glare.model.e_mist", false),
        (model("size_ref_deg"), "glare.model.size_ref_deg", false),
        (model("contrast"), "glare.model.contrast", false),
        (model("chaos_a"), "glare.model.chaos_a", false),
        (model("chaos_z"), "glare.model.chaos_z", false),
        (
            model("flare_max_lines"),
            "glare.model.flare_max_lines",
            true,
        ),
        (hw("shape_log2"), "glare.hw.shape_log2", true),
        (hw("shape_bits"), "glare.hw.shape_bits", true),
        (hw("falloff_log2"), "glare.hw.falloff_log2", true),
        (hw("falloff_bits"), "glare.hw.falloff_bits", true),
        (hw("weight_bits"), "glare.hw.weight_bits", true),
        (hw("coord_frac_bits"), "glare.hw.coord_frac_bits", true),
        (hw("noise_bits"), "glare.hw.noise_bits", true),
        (hw("fb_bits"), "glare.hw.fb_bits", true),
        (hw("pipes"), "glare.hw.pipes", true),
        (hw("clock_mhz"), "glare.hw.clock_mhz", false),
        (vec![K("glare"), K("frame")], "glare.frame", true),
    ]
}

const SPECIAL_F: &[f64] = &[
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    -1.0,
    -1e-300,
    0.0,
    1e-300,
    1e-9,
    0.5,
    1.0,
    1.5,
    2.0,
    7.9,
    100.0,
    1e6,
    1e12,
];

const SPECIAL_I: &[i64] = &[-1, 0, 1, 2, 5, 8, 12, 16, 17, 33, 64, 1000, 1 << 40];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]

    /// One field of the base scene set to a special value (a float, or an integer
    /// where the field is an integer, or the wrong type): never a panic; an error
    /// names exactly that field; an accepted scene renders to levels in [0, 255].
    #[test]
    fn one_bad_field_never_panics(
        fi in 0usize..49,
        vi in 0usize..SPECIAL_F.len(),
        ii in 0usize..SPECIAL_I.len(),
        wrong_type in prop::bool::weighted(0.1),
    ) {
        let fields = fields();
        let (path, name, int) = &fields[fi % fields.len()];
        let value = if wrong_type {
            Value::String("x".into())
        } else if *int {
            Value::Integer(SPECIAL_I[ii])
        } else {
            Value::Float(SPECIAL_F[vi])
        };
        let text = with(path, value.clone());
        let got = std::panic::catch_unwind(|| Scene::from_toml_str(&text));
        prop_assert!(got.is_ok(), "from_toml_str panicked on {name} = {value}");
        match got.unwrap() {
            Err(e) => {
                // A rule relating two fields names the second one (validate.rs): a
                // semi-major axis shrunk below b is reported at b.
                let ok = e.field() == *name
                    || (*name == "glare.sources[0].a" && e.field() == "glare.sources[0].b");
                prop_assert!(ok, "{} = {}: {}", name, value, e);
            }
            Ok(scene) => {
                // The frame number only matters with fluctuation; keep big ones quick.
                let mut scene = scene;
                if let Some(g) = scene.glare.as_mut() {
                    g.frame = g.frame.min(1000);
                }
                let r = std::panic::catch_unwind(|| render_glare(&scene));
                prop_assert!(r.is_ok(), "render panicked on {name} = {value}");
                match r.unwrap() {
                    Err(e) => prop_assert!(
                        e.field().starts_with("glare."),
                        "{} = {}: render error without a glare field: {}", name, value, e
                    ),
                    Ok(fr) => {
                        for p in fr.levels() {
                            for v in p {
                                prop_assert!((0.0..=255.0).contains(&v), "{name} = {value}: level {v}");
                            }
                        }
                    }
                }
            }
        }
    }
}
