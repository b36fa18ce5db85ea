//! Scenes: validation (every field, by its TOML path), TOML parsing and its error
//! paths, built-in scenes (valid, round trip, brightness band), tessellation.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use glare_pipeline::scene::builtin::{builtin, builtin_toml, BUILTIN_NAMES};
use glare_pipeline::scene::format::*;
use glare_pipeline::scene::math::{v3, Vec3};
use glare_pipeline::scene::teapot::*;
use proptest::prelude::*;
use proptest::sample::Index;
use rtl_model::error::ConfigError;

fn vec(a: &[f64; 3]) -> Vec3 {
    v3(a[0], a[1], a[2])
}

/// Distance along the unit ray (o, d) to the first surface (sphere, rectangle, box;
/// teapots ignored — only makes the estimate an upper bound), or ∞.
fn first_hit(scene: &Scene, o: Vec3, d: Vec3) -> f64 {
    let mut best = f64::INFINITY;
    for obj in &scene.objects {
        let t = match &obj.shape {
            Shape::Sphere { center, radius } => {
                let oc = o - vec(center);
                let b = oc.dot(d);
                let c = oc.dot(oc) - radius * radius;
                let disc = b * b - c;
                if disc < 0.0 {
                    f64::INFINITY
                } else {
                    let t = -b - disc.sqrt();
                    if t > 0.0 {
                        t
                    } else {
                        f64::INFINITY
                    }
                }
            }
            Shape::Plane {
                center,
                normal,
                tangent,
                half_size,
            } => {
                let n = vec(normal).normalized();
                let denom = n.dot(d);
                if denom.abs() < 1e-12 {
                    f64::INFINITY
                } else {
                    let t = n.dot(vec(center) - o) / denom;
                    let p = o + d * t - vec(center);
                    let tg = vec(tangent);
                    let tg = (tg - n * tg.dot(n)).normalized();
                    let b = n.cross(tg);
                    if t > 0.0 && p.dot(tg).abs() <= half_size[0] && p.dot(b).abs() <= half_size[1]
                    {
                        t
                    } else {
                        f64::INFINITY
                    }
                }
            }
            Shape::Box { min, max } => {
                let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
                let (o3, d3) = ([o.x, o.y, o.z], [d.x, d.y, d.z]);
                for k in 0..3 {
                    let inv = 1.0 / d3[k];
                    let (a, b) = ((min[k] - o3[k]) * inv, (max[k] - o3[k]) * inv);
                    t0 = t0.max(a.min(b));
                    t1 = t1.min(a.max(b));
                }
                if t0 <= t1 {
                    t0
                } else {
                    f64::INFINITY
                }
            }
            Shape::Teapot { .. } => f64::INFINITY,
        };
        best = best.min(t);
    }
    best
}

/// Light-map value at relative cone radius r (polka dots bounded by the smooth spot).
fn map_value(m: &Option<LightMap>, r: f64) -> f64 {
    match m {
        None => 1.0,
        Some(LightMap::Smooth { exponent }) => (1.0 - r * r).max(0.0).powf(*exponent),
        Some(LightMap::PolkaDots { .. }) | Some(LightMap::Image { .. }) => (1.0 - r * r).max(0.0),
    }
}

/// Upper bound (no shadows) of the shafts term I_s of SPEC A (2)–(4) per pixel, on a
/// grid of every `step`-th pixel, by midpoint ray marching with `n` samples; returns
/// the brightest value (max over colour channels).
fn peak_shafts(scene: &Scene, step: u32, n: usize) -> f64 {
    let c = &scene.camera;
    let eye = vec(&c.eye);
    let f = (vec(&c.look_at) - eye).normalized();
    let s = f.cross(vec(&c.up)).normalized();
    let u = s.cross(f);
    let (w, h) = (scene.image.width as f64, scene.image.height as f64);
    let th = (c.fovy_deg.to_radians() / 2.0).tan();
    let m = &scene.medium;
    let mut peak: f64 = 0.0;
    for py in (0..scene.image.height).step_by(step as usize) {
        for px in (0..scene.image.width).step_by(step as usize) {
            let x = (2.0 * (px as f64 + 0.5) / w - 1.0) * th * w / h;
            let y = (1.0 - 2.0 * (py as f64 + 0.5) / h) * th;
            let d = (f + s * x + u * y).normalized();
            let t_end = first_hit(scene, eye, d).min(c.far / d.dot(f));
            let t_start = c.near / d.dot(f);
            let dt = (t_end - t_start) / n as f64;
            let mut sum = [0.0f64; 3];
            for i in 0..n {
                let t = t_start + (i as f64 + 0.5) * dt;
                let p = eye + d * t;
                for l in &scene.lights {
                    let lp = vec(&l.position);
                    let to_p = p - lp;
                    let dist = to_p.length();
                    let axis = vec(&l.direction).normalized();
                    let cos_t = to_p.dot(axis) / dist;
                    let cut = l.cutoff_deg.to_radians();
                    if cos_t <= cut.cos() {
                        continue;
                    }
                    let tan_t = (1.0 - cos_t * cos_t).max(0.0).sqrt() / cos_t;
                    let il = map_value(&l.light_map, tan_t / cut.tan()) * l.intensity;
                    let cos_a = (-to_p).normalized().dot(d);
                    let half = ((1.0 + cos_a) / 2.0).max(0.0).sqrt();
                    let phase = m.k * (1.0 + 9.0 * half.powi(16));
                    let g = m.rho * phase * (-m.rho * m.kappa * (dist + t)).exp() / (dist * dist);
                    for (acc, c) in sum.iter_mut().zip(l.color) {
                        *acc += il * c * g * dt;
                    }
                }
            }
            let v = sum.iter().cloned().fold(0.0, f64::max);
            assert!(v.is_finite(), "pixel ({px}, {py}) is not finite");
            peak = peak.max(v);
        }
    }
    peak
}

// ---------------------------------------------------------------------------------
// Helpers.

/// A scratch directory for this test process.
fn scratch_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        // One fixed directory, reused by every run (files are written by atomic rename),
        // so runs do not pile up per-process directories in /tmp.
        let d = std::env::temp_dir().join("glare_scene_test");
        std::fs::create_dir_all(&d).unwrap();
        d
    })
}

/// A small existing PNG for image light maps.
fn png_path() -> String {
    let p = scratch_dir().join("map.png");
    if !p.exists() {
        let img = image::GrayImage::from_fn(4, 4, |x, y| image::Luma([(x * 60 + y * 3) as u8]));
        let tmp = scratch_dir().join(format!("map_{:?}.png", std::thread::current().id()));
        img.save(&tmp).unwrap();
        // Rename is atomic: concurrent tests never see a half-written file.
        std::fs::rename(&tmp, &p).unwrap();
    }
    p.to_string_lossy().into_owned()
}

/// A valid scene using every type: the stage (teapot, box, sphere, planes, smooth
/// and polka-dot maps) plus a point light and a spot with an image map.
fn kitchen_sink() -> Scene {
    let mut s = builtin("stage").unwrap();
    s.lights.push(Light {
        kind: LightKind::Point,
        position: [0.0, 5.0, 4.0],
        direction: [0.0, -1.0, 0.0],
        cutoff_deg: 20.0,
        intensity: 3.0,
        color: [1.0, 0.9, 0.8],
        light_map: None,
    });
    s.lights.push(Light {
        kind: LightKind::Spot,
        position: [-1.0, 8.0, 3.0],
        direction: [0.2, -1.0, -0.1],
        cutoff_deg: 12.0,
        intensity: 10.0,
        color: [1.0, 1.0, 1.0],
        light_map: Some(LightMap::Image { path: png_path() }),
    });
    s.validate().unwrap();
    s
}

fn expect_field<T: std::fmt::Debug>(r: Result<T, ConfigError>, field: &str) -> ConfigError {
    match r {
        Ok(v) => panic!("expected an error naming `{field}`, got Ok({v:?})"),
        Err(e) => {
            assert_eq!(e.field(), field, "wrong field in: {e}");
            e
        }
    }
}

// ---------------------------------------------------------------------------------
// Mutating one field.

/// A mutable field of a scene, its TOML path and invalid values for it.
enum Slot<'a> {
    F(String, &'a mut f64, Vec<f64>),
    U(String, &'a mut u32, Vec<u32>),
    S(String, &'a mut String, Vec<String>),
}

const NONFINITE: [f64; 3] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
const WORLD: f64 = 1e6;

/// Invalid values for a float field allowed in [lo, hi] (ends open when the flag is
/// false); `r` ∈ [0, 1) varies how far outside.
fn bad_f(lo: f64, lo_closed: bool, hi: f64, hi_closed: bool, r: f64) -> Vec<f64> {
    let mut v = NONFINITE.to_vec();
    let step = |x: f64| 1e-6 * x.abs().max(1.0);
    v.push(lo - step(lo) - r * 1e3 * lo.abs().max(1.0));
    v.push(hi + step(hi) + r * 1e3 * hi.abs().max(1.0));
    if !lo_closed {
        v.push(lo);
    }
    if !hi_closed {
        v.push(hi);
    }
    v
}

fn bad_u(lo: u32, hi: u32, r: f64) -> Vec<u32> {
    let mut v = vec![
        hi + 1,
        hi + 1 + (r * (u32::MAX - hi - 1) as f64) as u32,
        u32::MAX,
    ];
    if lo > 0 {
        v.push(0);
        v.push(lo - 1);
    }
    v
}

fn coord(path: String, x: &mut f64, r: f64) -> Slot<'_> {
    Slot::F(path, x, bad_f(-WORLD, true, WORLD, true, r))
}

fn coords<'a>(out: &mut Vec<Slot<'a>>, path: &str, p: &'a mut [f64; 3], r: f64) {
    for (k, x) in p.iter_mut().enumerate() {
        out.push(coord(format!("{path}[{k}]"), x, r));
    }
}

/// Every field of the scene with its invalid values.
fn slots(s: &mut Scene, r: f64) -> Vec<Slot<'_>> {
    let mut v = Vec::new();
    let Scene {
        image,
        camera,
        medium,
        lights,
        objects,
        shafts,
        ..
    } = s;
    v.push(Slot::U(
        "image.width".into(),
        &mut image.width,
        bad_u(1, glare_pipeline::scene::validate::IMAGE_MAX, r),
    ));
    v.push(Slot::U(
        "image.height".into(),
        &mut image.height,
        bad_u(1, glare_pipeline::scene::validate::IMAGE_MAX, r),
    ));
    let near = camera.near;
    coords(&mut v, "camera.eye", &mut camera.eye, r);
    coords(&mut v, "camera.look_at", &mut camera.look_at, r);
    coords(&mut v, "camera.up", &mut camera.up, r);
    v.push(Slot::F(
        "camera.fovy_deg".into(),
        &mut camera.fovy_deg,
        bad_f(0.0, false, 180.0, false, r),
    ));
    let mut near_bad = bad_f(0.0, false, WORLD, true, r);
    near_bad.retain(|x| x.is_nan() || *x <= 0.0 || *x > WORLD);
    v.push(Slot::F("camera.near".into(), &mut camera.near, near_bad));
    let mut far_bad = NONFINITE.to_vec();
    far_bad.extend([near, near * r, -1.0 - r, WORLD * (1.0 + r) + 1.0]);
    v.push(Slot::F("camera.far".into(), &mut camera.far, far_bad));
    for (name, x) in [
        ("rho", &mut medium.rho),
        ("kappa", &mut medium.kappa),
        ("k", &mut medium.k),
    ] {
        v.push(Slot::F(
            format!("medium.{name}"),
            x,
            bad_f(0.0, true, 1e6, true, r),
        ));
    }
    for (i, l) in lights.iter_mut().enumerate() {
        let p = format!("lights[{i}]");
        coords(&mut v, &format!("{p}.position"), &mut l.position, r);
        coords(&mut v, &format!("{p}.direction"), &mut l.direction, r);
        let cut = match l.kind {
            LightKind::Spot => bad_f(0.0, false, 90.0, false, r),
            LightKind::Point => NONFINITE.to_vec(),
        };
        v.push(Slot::F(format!("{p}.cutoff_deg"), &mut l.cutoff_deg, cut));
        v.push(Slot::F(
            format!("{p}.intensity"),
            &mut l.intensity,
            bad_f(0.0, true, 1e9, true, r),
        ));
        for (k, c) in l.color.iter_mut().enumerate() {
            v.push(Slot::F(
                format!("{p}.color[{k}]"),
                c,
                bad_f(0.0, true, 1e3, true, r),
            ));
        }
        match &mut l.light_map {
            None => {}
            Some(LightMap::Smooth { exponent }) => v.push(Slot::F(
                format!("{p}.light_map.exponent"),
                exponent,
                bad_f(0.0, true, 64.0, true, r),
            )),
            Some(LightMap::PolkaDots { dots, radius }) => {
                v.push(Slot::U(
                    format!("{p}.light_map.dots"),
                    dots,
                    bad_u(1, 64, r),
                ));
                v.push(Slot::F(
                    format!("{p}.light_map.radius"),
                    radius,
                    bad_f(0.0, false, 0.5, true, r),
                ));
            }
            Some(LightMap::Image { path }) => v.push(Slot::S(
                format!("{p}.light_map.path"),
                path,
                vec![
                    String::new(),
                    "   ".into(),
                    format!("/nonexistent/glare/{}.png", (r * 1e6) as u32),
                ],
            )),
        }
    }
    for (i, o) in objects.iter_mut().enumerate() {
        let p = format!("objects[{i}]");
        for (k, c) in o.color.iter_mut().enumerate() {
            v.push(Slot::F(
                format!("{p}.color[{k}]"),
                c,
                bad_f(0.0, true, 1.0, true, r),
            ));
        }
        let q = format!("{p}.shape");
        match &mut o.shape {
            Shape::Sphere { center, radius } => {
                coords(&mut v, &format!("{q}.center"), center, r);
                v.push(Slot::F(
                    format!("{q}.radius"),
                    radius,
                    bad_f(0.0, false, WORLD, true, r),
                ));
            }
            Shape::Plane {
                center,
                normal,
                tangent,
                half_size,
            } => {
                coords(&mut v, &format!("{q}.center"), center, r);
                coords(&mut v, &format!("{q}.normal"), normal, r);
                coords(&mut v, &format!("{q}.tangent"), tangent, r);
                for (k, h) in half_size.iter_mut().enumerate() {
                    v.push(Slot::F(
                        format!("{q}.half_size[{k}]"),
                        h,
                        bad_f(0.0, false, WORLD, true, r),
                    ));
                }
            }
            Shape::Box { min, max } => {
                let lo = *min;
                coords(&mut v, &format!("{q}.min"), min, r);
                for (k, x) in max.iter_mut().enumerate() {
                    let mut bad = bad_f(-WORLD, true, WORLD, true, r);
                    bad.extend([lo[k], lo[k] - r * 10.0 - 1e-3]);
                    v.push(Slot::F(format!("{q}.max[{k}]"), x, bad));
                }
            }
            Shape::Teapot {
                position,
                scale,
                rotate_y_deg,
                subdivisions,
            } => {
                coords(&mut v, &format!("{q}.position"), position, r);
                v.push(Slot::F(
                    format!("{q}.scale"),
                    scale,
                    bad_f(0.0, false, 1e5, true, r),
                ));
                v.push(Slot::F(
                    format!("{q}.rotate_y_deg"),
                    rotate_y_deg,
                    NONFINITE.to_vec(),
                ));
                v.push(Slot::U(
                    format!("{q}.subdivisions"),
                    subdivisions,
                    bad_u(1, 64, r),
                ));
            }
        }
    }
    let sh = shafts;
    v.push(Slot::U(
        "shafts.planes".into(),
        &mut sh.planes,
        bad_u(1, 10_000, r),
    ));
    v.push(Slot::U(
        "shafts.subplanes".into(),
        &mut sh.subplanes,
        bad_u(1, 256, r),
    ));
    for (k, m) in sh.mesh.iter_mut().enumerate() {
        v.push(Slot::U(format!("shafts.mesh[{k}]"), m, bad_u(1, 256, r)));
    }
    v.push(Slot::U(
        "shafts.f_texels".into(),
        &mut sh.f_texels,
        bad_u(2, 4096, r),
    ));
    for (k, m) in sh.h_texels.iter_mut().enumerate() {
        v.push(Slot::U(
            format!("shafts.h_texels[{k}]"),
            m,
            bad_u(2, 4096, r),
        ));
    }
    v.push(Slot::F(
        "shafts.s_max".into(),
        &mut sh.s_max,
        bad_f(0.0, true, WORLD, true, r),
    ));
    v.push(Slot::F(
        "shafts.t_max".into(),
        &mut sh.t_max,
        bad_f(0.0, true, WORLD, true, r),
    ));
    v.push(Slot::U(
        "shafts.texel_bits".into(),
        &mut sh.texel_bits,
        bad_u(1, 16, r),
    ));
    v.push(Slot::U(
        "shafts.fb_bits".into(),
        &mut sh.fb_bits,
        bad_u(1, 16, r),
    ));
    v.push(Slot::U(
        "shafts.weight_bits".into(),
        &mut sh.weight_bits,
        bad_u(1, 16, r),
    ));
    v.push(Slot::U(
        "shafts.coord_frac_bits".into(),
        &mut sh.coord_frac_bits,
        bad_u(0, 16, r),
    ));
    v.push(Slot::U(
        "shafts.shadow_resolution".into(),
        &mut sh.shadow_resolution,
        bad_u(1, 4096, r),
    ));
    v.push(Slot::U(
        "shafts.shadow_depth_bits".into(),
        &mut sh.shadow_depth_bits,
        bad_u(1, 32, r),
    ));
    v
}

/// Set slot `i`'s `j`-th invalid value; returns its path.
fn apply_slot(s: &mut Scene, r: f64, i: &Index, j: &Index) -> String {
    let mut v = slots(s, r);
    let slot = i.get_mut(&mut v);
    match slot {
        Slot::F(p, x, bad) => {
            **x = *j.get(bad);
            p.clone()
        }
        Slot::U(p, x, bad) => {
            **x = *j.get(bad);
            p.clone()
        }
        Slot::S(p, x, bad) => {
            **x = j.get(bad).clone();
            p.clone()
        }
    }
}

/// Invalid combinations of fields (a relation broken, a vector zero); each returns
/// the path the error must name, or `None` if it does not apply to this scene.
fn relations(s: &mut Scene, which: usize, r: f64) -> Option<String> {
    let spot = s.lights.iter().position(|l| l.kind == LightKind::Spot)?;
    let point = s.lights.iter().position(|l| l.kind == LightKind::Point);
    let plane = s
        .objects
        .iter()
        .position(|o| matches!(o.shape, Shape::Plane { .. }));
    match which {
        0 => {
            s.camera.look_at = s.camera.eye;
            Some("camera.look_at".into())
        }
        1 => {
            let c = &s.camera;
            let k = 0.5 + 3.0 * r;
            s.camera.up =
                [0, 1, 2].map(|i| (c.look_at[i] - c.eye[i]) * if r < 0.5 { k } else { -k });
            Some("camera.up".into())
        }
        2 => {
            s.camera.up = [0.0; 3];
            Some("camera.up".into())
        }
        3 => {
            s.lights[spot].direction = [0.0, -1e-12 * r, 0.0];
            Some(format!("lights[{spot}].direction"))
        }
        4 => {
            let i = point?;
            s.lights[i].light_map = Some(LightMap::Smooth { exponent: 1.0 });
            Some(format!("lights[{i}].light_map"))
        }
        5..=7 => {
            let i = plane?;
            let Shape::Plane {
                normal, tangent, ..
            } = &mut s.objects[i].shape
            else {
                unreachable!()
            };
            match which {
                5 => {
                    *normal = [0.0; 3];
                    Some(format!("objects[{i}].shape.normal"))
                }
                6 => {
                    *tangent = [0.0; 3];
                    Some(format!("objects[{i}].shape.tangent"))
                }
                _ => {
                    *tangent = normal.map(|x| x * (-3.0 + 2.0 * r));
                    Some(format!("objects[{i}].shape.tangent"))
                }
            }
        }
        _ => None,
    }
}
const RELATIONS: usize = 8;

#[test]
fn kitchen_sink_and_builtins_are_valid() {
    kitchen_sink().validate().unwrap();
    for name in BUILTIN_NAMES {
        let s = builtin(name).unwrap();
        s.validate().unwrap();
        assert_eq!((s.image.width, s.image.height), (720, 480), "{name}");
    }
    assert!(BUILTIN_NAMES.len() >= 3);
    expect_field(builtin("nope"), "scene");
    expect_field(builtin_toml("nope"), "scene");
}

/// Every slot and every invalid value, exhaustively (the proptest below samples more
/// values and the relations).
#[test]
fn every_field_every_bad_value_is_named() {
    let base = kitchen_sink();
    let mut probe = base.clone();
    let n = slots(&mut probe, 0.5).len();
    assert!(n > 150, "only {n} slots");
    let mut checked = 0;
    for i in 0..n {
        let mut probe = base.clone();
        let nbad = match &slots(&mut probe, 0.5)[i] {
            Slot::F(_, _, b) => b.len(),
            Slot::U(_, _, b) => b.len(),
            Slot::S(_, _, b) => b.len(),
        };
        for j in 0..nbad {
            let mut s = base.clone();
            let mut v = slots(&mut s, 0.5);
            let path = match &mut v[i] {
                Slot::F(p, x, b) => {
                    **x = b[j];
                    p.clone()
                }
                Slot::U(p, x, b) => {
                    **x = b[j];
                    p.clone()
                }
                Slot::S(p, x, b) => {
                    **x = b[j].clone();
                    p.clone()
                }
            };
            drop(v);
            expect_field(s.validate(), &path);
            checked += 1;
        }
    }
    for w in 0..RELATIONS {
        let mut s = base.clone();
        let path = relations(&mut s, w, 0.3).expect("the kitchen sink has every kind");
        expect_field(s.validate(), &path);
    }
    println!("{checked} single-field mutations checked");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// One field of a valid scene made invalid (NaN, ±∞, negative, zero, out of
    /// range, or a broken relation): validate() names exactly that field.
    #[test]
    fn one_bad_field_is_named(which in 0usize..10, i in any::<Index>(), j in any::<Index>(), r in 0.0f64..1.0) {
        let mut s = kitchen_sink();
        let path = if which == 0 {
            relations(&mut s, i.index(RELATIONS), r).unwrap()
        } else {
            apply_slot(&mut s, r, &i, &j)
        };
        let e = s.validate().expect_err(&path);
        prop_assert_eq!(e.field(), path.as_str(), "{}", e);
    }

    /// Random edits of a builtin's TOML never panic; an error names a non-empty field
    /// and carries toml's message.
    #[test]
    fn toml_edits_never_panic(name in 0usize..3, pos in any::<Index>(), edit in 0usize..6, junk in "[a-z0-9=\\[\\]\". -]{0,4}") {
        let text = builtin_toml(BUILTIN_NAMES[name]).unwrap();
        let mut at = pos.index(text.len() + 1);
        while !text.is_char_boundary(at) {
            at -= 1;
        }
        let end = (at + edit).min(text.len());
        let end = (end..=text.len()).find(|&e| text.is_char_boundary(e)).unwrap();
        let edited = format!("{}{}{}", &text[..at], junk, &text[end..]);
        match Scene::from_toml_str(&edited) {
            Ok(s) => prop_assert!(s.validate().is_ok()),
            Err(e) => {
                prop_assert!(!e.field().is_empty());
                prop_assert!(!e.to_string().is_empty());
            }
        }
    }
}

/// Valid extremes are accepted: the documented stiff medium, inclusive bounds, the
/// largest and smallest values of every range.
#[test]
fn valid_extremes_are_accepted() {
    let mut s = kitchen_sink();
    s.medium = Medium {
        rho: 100.0,
        kappa: 10.0,
        k: 1e6,
    }; // ρκ = 10³
    s.camera.fovy_deg = 179.9;
    s.camera.near = 1e-6;
    s.camera.far = 1e6;
    s.image = ImageSize {
        width: 1,
        height: glare_pipeline::scene::validate::IMAGE_MAX,
    };
    s.lights[0].cutoff_deg = 89.99;
    s.lights[0].intensity = 1e9;
    s.lights[0].color = [0.0, 1e3, 0.5];
    s.lights[0].light_map = Some(LightMap::Smooth { exponent: 64.0 });
    s.lights[1].light_map = Some(LightMap::PolkaDots {
        dots: 64,
        radius: 0.5,
    });
    s.lights[2].light_map = Some(LightMap::Smooth { exponent: 0.0 });
    s.lights[3].light_map = Some(LightMap::PolkaDots {
        dots: 1,
        radius: 1e-9,
    });
    s.objects[0].color = [0.0, 1.0, 1.0];
    s.shafts = ShaftsConfig {
        planes: 10_000,
        subplanes: 256,
        mesh: [1, 256],
        f_texels: 2,
        h_texels: [4096, 2],
        s_max: 1e6,
        t_max: 0.0,
        texel_bits: 16,
        fb_bits: 1,
        weight_bits: 16,
        coord_frac_bits: 0,
        shadow_resolution: 4096,
        shadow_depth_bits: 32,
        f_scale: glare_pipeline::scene::format::FScale::LitVolume,
        h_cap: glare_pipeline::scene::format::HCap::OnePlane,
        plane_step: glare_pipeline::scene::format::PlaneStep::AlongRay,
        light_map_texels: 4096,
        ..ShaftsConfig::default()
    };
    s.validate().unwrap();
    s.medium = Medium {
        rho: 0.0,
        kappa: 0.0,
        k: 0.0,
    };
    s.validate().unwrap();
}

// ---------------------------------------------------------------------------------
// TOML.

#[test]
fn builtin_toml_round_trips() {
    for name in BUILTIN_NAMES {
        let text = builtin_toml(name).unwrap();
        assert!(text.starts_with('#'), "a comment names the builtin");
        assert_eq!(
            Scene::from_toml_str(&text).unwrap(),
            builtin(name).unwrap(),
            "{name}"
        );
    }
    let s = kitchen_sink();
    let text = toml::to_string_pretty(&s).unwrap();
    assert_eq!(Scene::from_toml_str(&text).unwrap(), s);
}

#[test]
fn a_minimal_file_takes_the_defaults() {
    let s = Scene::from_toml_str("[camera]\neye = [0, 1, 5]\nlook_at = [0, 1, 0]\n").unwrap();
    assert_eq!(s.image, ImageSize::default());
    assert_eq!(s.shafts, ShaftsConfig::default());
    assert_eq!(s.camera.fovy_deg, 45.0);
    assert!(s.lights.is_empty() && s.objects.is_empty());
}

#[test]
fn toml_errors_name_the_field() {
    let t = builtin_toml("stage").unwrap();
    let cases: Vec<(String, &str, &str)> = vec![
        // Unknown fields, at every level.
        (format!("colour = 1\n{t}"), "colour", "unknown field"),
        (
            t.replace("fovy_deg = 40.0", "fovy = 40.0"),
            "camera.fovy",
            "unknown field",
        ),
        (
            t.replacen("cutoff_deg", "cutof_deg", 1),
            "lights[0].cutof_deg",
            "unknown field",
        ),
        (
            t.replace("radius = 0.9", "radiu = 0.9"),
            "objects[2].shape.radiu",
            "unknown field",
        ),
        (
            t.replace("planes = 30", "planes = 30\nplanez = 3"),
            "shafts.planez",
            "unknown field",
        ),
        // Wrong types.
        (
            t.replace("fovy_deg = 40.0", "fovy_deg = \"wide\""),
            "camera.fovy_deg",
            "invalid type",
        ),
        (
            t.replace("radius = 0.9", "radius = \"big\""),
            "objects[2].shape.radius",
            "invalid type",
        ),
        (
            t.replace("dots = 5", "dots = 5.5"),
            "lights[1].light_map.dots",
            "invalid type",
        ),
        (
            t.replace("subdivisions = 8", "subdivisions = -8"),
            "objects[0].shape.subdivisions",
            "invalid value",
        ),
        (
            t.replace("planes = 30", "planes = -30"),
            "shafts.planes",
            "invalid value",
        ),
        (
            t.replacen("color = [", "color = [true, ", 1),
            "lights[0].color[0]",
            "invalid type",
        ),
        (
            t.replace("width = 720", "width = 7.5"),
            "image.width",
            "invalid type",
        ),
        (
            t.replace("mesh = [", "mesh = [\"a\", "),
            "shafts.mesh[0]",
            "invalid type",
        ),
        // Unknown variants, missing fields.
        (
            t.replace("type = \"sphere\"", "type = \"cone\""),
            "objects[2].shape.type",
            "unknown variant",
        ),
        (
            t.replacen("kind = \"spot\"", "kind = \"cone\"", 1),
            "lights[0].kind",
            "unknown variant",
        ),
        ("name = \"x\"\n".to_string(), "camera", "missing field"),
        (
            t.replacen("position = [", "positio = [", 1),
            "lights[0].positio",
            "unknown field",
        ),
        (
            "[camera]\neye = [0, 1, 5]\n".to_string(),
            "camera.look_at",
            "missing field",
        ),
        // Syntax errors: the key on the line.
        (
            t.replace("fovy_deg = 40.0", "fovy_deg = = 40.0"),
            "camera.fovy_deg",
            "TOML line",
        ),
    ];
    for (text, field, msg) in cases {
        let e = expect_field(Scene::from_toml_str(&text), field);
        let shown = e.to_string();
        assert!(shown.contains(msg), "`{shown}` lacks `{msg}`");
        assert!(shown.contains("TOML line"), "`{shown}` lacks the position");
    }
    // Values that parse but do not validate name the field too.
    let e = expect_field(
        Scene::from_toml_str(&t.replace("radius = 0.9", "radius = 0.0")),
        "objects[2].shape.radius",
    );
    assert!(e.to_string().contains("0 < radius"), "{e}");
    expect_field(
        Scene::from_toml_str(&t.replace("fovy_deg = 40.0", "fovy_deg = nan")),
        "camera.fovy_deg",
    );
    expect_field(
        Scene::from_toml_str(&t.replace("planes = 30", "planes = 0")),
        "shafts.planes",
    );
}

#[test]
fn from_file_reads_resolves_and_names_the_path() {
    // A missing file names the path.
    let missing = scratch_dir().join("does_not_exist.toml");
    let e = expect_field(Scene::from_file(&missing), &missing.display().to_string());
    assert!(e.to_string().contains("cannot read"), "{e}");

    // A builtin written out reads back.
    let f = scratch_dir().join("fig6.toml");
    std::fs::write(&f, builtin_toml("fig6").unwrap()).unwrap();
    assert_eq!(Scene::from_file(&f).unwrap(), builtin("fig6").unwrap());

    // A relative light-map path is resolved against the scene file's directory …
    let sub = scratch_dir().join("sub");
    std::fs::create_dir_all(&sub).unwrap();
    std::fs::copy(png_path(), sub.join("dots.png")).unwrap();
    let mut s = builtin("fig4").unwrap();
    s.lights[0].light_map = Some(LightMap::Image {
        path: "dots.png".into(),
    });
    let text = toml::to_string_pretty(&s).unwrap();
    let f = sub.join("scene.toml");
    std::fs::write(&f, &text).unwrap();
    let read = Scene::from_file(&f).unwrap();
    assert_eq!(
        read.lights[0].light_map,
        Some(LightMap::Image {
            path: sub.join("dots.png").to_string_lossy().into_owned()
        })
    );
    // … but from a string it is relative to the working directory (not found here).
    let e = expect_field(Scene::from_toml_str(&text), "lights[0].light_map.path");
    assert!(e.to_string().contains("not found"), "{e}");

    // Parse errors in a file name the field and the file.
    std::fs::write(&f, text.replace("cutoff_deg", "cutoff")).unwrap();
    let e = expect_field(Scene::from_file(&f), "lights[0].cutoff");
    assert!(e.to_string().contains("scene.toml"), "{e}");
}

// ---------------------------------------------------------------------------------
// Built-in scenes: brightness.

/// The bright end of every builtin's shafts (no shadows: an upper bound) lies in
/// 0.3 … 0.6 of full scale, and each light alone reaches at least 0.3: visible,
/// not saturating (see builtin.rs). Figs. 4 and 6 are the exception by design: their
/// beams saturate next to the light (peak 1 … 4× full scale, see `builtin::fig4`). A
/// finer grid and march agree within 5 %.
#[test]
fn builtin_shafts_are_visible_but_do_not_saturate() {
    for bright in ["fig4", "fig6"] {
        let s = builtin(bright).unwrap();
        let p = peak_shafts(&s, 8, 300);
        assert!((1.0..=4.0).contains(&p), "{bright}: peak {p}");
    }
    for name in BUILTIN_NAMES
        .iter()
        .filter(|n| !["fig4", "fig6"].contains(n))
    {
        let s = builtin(name).unwrap();
        let peak = peak_shafts(&s, 8, 300);
        assert!((0.3..=0.6).contains(&peak), "{name}: peak {peak}");
        for (i, l) in s.lights.iter().enumerate() {
            let mut one = s.clone();
            one.lights = vec![l.clone()];
            let p = peak_shafts(&one, 12, 200);
            assert!((0.3..=0.6).contains(&p), "{name} light {i}: peak {p}");
        }
    }
    let s = builtin("fig6").unwrap();
    let (coarse, fine) = (peak_shafts(&s, 8, 300), peak_shafts(&s, 3, 1000));
    assert!((coarse - fine).abs() < 0.05 * fine, "{coarse} vs {fine}");
}

/// The scenes are what they say: fig4 has no objects; fig6 has a sphere inside the
/// light's cone above a floor; the stage has 5 spots (≥ 2 polka-dot maps), a teapot,
/// a box, a sphere, and every light is above the frame (its apex is not drawn).
#[test]
fn builtins_have_their_content() {
    let f4 = builtin("fig4").unwrap();
    assert!(f4.objects.is_empty() && f4.lights.len() == 1);
    let f6 = builtin("fig6").unwrap();
    let l = &f6.lights[0];
    let Shape::Sphere { center, radius } = f6.objects[0].shape else {
        panic!()
    };
    let to_c = vec(&center) - vec(&l.position);
    let angle = to_c
        .normalized()
        .dot(vec(&l.direction).normalized())
        .acos()
        .to_degrees();
    let half = (radius / to_c.length()).asin().to_degrees();
    assert!(
        angle + half < l.cutoff_deg,
        "the sphere's shadow lies inside the cone"
    );
    assert!(matches!(f6.objects[1].shape, Shape::Plane { .. }));
    let st = builtin("stage").unwrap();
    assert_eq!(st.lights.len(), 5);
    let dots = st
        .lights
        .iter()
        .filter(|l| matches!(l.light_map, Some(LightMap::PolkaDots { .. })))
        .count();
    assert!(dots >= 2);
    let kinds: Vec<&str> = st
        .objects
        .iter()
        .map(|o| match o.shape {
            Shape::Teapot { .. } => "teapot",
            Shape::Box { .. } => "box",
            Shape::Sphere { .. } => "sphere",
            Shape::Plane { .. } => "plane",
        })
        .collect();
    for k in ["teapot", "box", "sphere", "plane"] {
        assert!(kinds.contains(&k), "stage lacks a {k}");
    }
    let dirs: Vec<Vec3> = st
        .lights
        .iter()
        .map(|l| vec(&l.direction).normalized())
        .collect();
    for a in 0..5 {
        for b in a + 1..5 {
            assert!(
                dirs[a].dot(dirs[b]) < 0.9999,
                "lights {a} and {b} point the same way"
            );
        }
    }
    for s in [f4, f6, st] {
        let c = &s.camera;
        let eye = vec(&c.eye);
        let f = (vec(&c.look_at) - eye).normalized();
        let side = f.cross(vec(&c.up)).normalized();
        let up = side.cross(f);
        for l in &s.lights {
            let d = vec(&l.position) - eye;
            let slope = d.dot(up) / d.dot(f);
            assert!(
                slope > (c.fovy_deg.to_radians() / 2.0).tan(),
                "{}: a light is in the frame",
                s.name
            );
        }
    }
}

// ---------------------------------------------------------------------------------
// Tessellation.

fn assert_unit_finite(tris: &[Triangle]) {
    for t in tris {
        for k in 0..3 {
            let (p, n) = (t.p[k], t.n[k]);
            assert!(
                p.x.is_finite() && p.y.is_finite() && p.z.is_finite(),
                "{t:?}"
            );
            assert!((n.length() - 1.0).abs() < 1e-12, "normal not unit: {t:?}");
        }
    }
}

/// (b − a) × (c − a): the winding's normal, length twice the area.
fn geometric(t: &Triangle) -> Vec3 {
    (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0])
}

/// Σ area·n over a closed surface is 0; Σ (p·n)·area / 3 is its volume.
fn closed_surface_sums(tris: &[Triangle]) -> (Vec3, f64) {
    let mut flux = Vec3::default();
    let mut vol = 0.0;
    for t in tris {
        let g = geometric(t);
        flux = flux + g * 0.5;
        vol += t.p[0].dot(g) / 6.0;
    }
    (flux, vol)
}

#[test]
fn teapot_patches_parse_and_turn_y_up() {
    let p = teapot_patches().unwrap();
    assert_eq!(p.len(), 32);
    // The first control point of the data, (1.4, 0.0, 2.4), is (1.4, 2.4, −0.0) Y up.
    assert_eq!(p[0][0][0], v3(1.4, 2.4, -0.0));
    let e = expect_field(parse_bpt("2\n3 3\n1 2 3\n"), "teapot.bpt line 3");
    assert!(e.to_string().contains("ends inside patch 0"), "{e}");
    let bad =
        include_str!("../src/scene/data/teapot.bpt").replacen("1.4 -0.784 2.4", "1.4 x 2.4", 1);
    let e = expect_field(parse_bpt(&bad), "teapot.bpt line 4");
    assert!(e.to_string().contains("1.4 x 2.4"), "{e}");
    expect_field(parse_bpt("1\n3 4\n"), "teapot.bpt line 2");
    expect_field(parse_bpt("nan"), "teapot.bpt line 1");
    expect_field(parse_bpt(""), "teapot.bpt line 1");
    let extra = format!(
        "{}\n1 2 3\n",
        include_str!("../src/scene/data/teapot.bpt").trim_end()
    );
    expect_field(parse_bpt(&extra), "teapot.bpt line 546");
}

#[test]
fn teapot_bounding_box_counts_and_normals() {
    for s in [1u32, 2, 5, 8, 16] {
        let tris = tessellate_teapot([0.0; 3], 1.0, 0.0, s).unwrap();
        let s = s as usize;
        // 32 patches × 2s² triangles, less one collapsed triangle per quad on the
        // pole edge of the 4 lid-knob and the 4 bottom patches; at s = 1 the two
        // spout-tip patches, whose four corners are collinear, also vanish.
        let spout_tip = if s == 1 { 4 } else { 0 };
        assert_eq!(tris.len(), 64 * s * s - 8 * s - spout_tip, "s = {s}");
        assert_unit_finite(&tris);
        // The winding agrees with the normals everywhere once the tessellation
        // follows the rim's and the spout tip's curl (s ≥ 3; at s = 1, 2 a flat quad
        // spans the curl).
        for t in tris.iter().filter(|_| s >= 3) {
            let g = geometric(t);
            assert!(
                g.dot(t.n[0] + t.n[1] + t.n[2]) > 0.0,
                "winding against normals: {t:?}"
            );
        }
    }
    // Every vertex normal agrees with its triangle's winding from s = 6 on, better and
    // better as s grows (the worst is at the spout tip's sharp curl).
    let worst = |s: u32| {
        tessellate_teapot([0.0; 3], 1.0, 0.0, s)
            .unwrap()
            .iter()
            .map(|t| {
                (0..3)
                    .map(|k| geometric(t).normalized().dot(t.n[k]))
                    .fold(1.0, f64::min)
            })
            .fold(1.0, f64::min)
    };
    let (w6, w16, w32) = (worst(6), worst(16), worst(32));
    assert!(0.0 < w6 && w6 < w16 && w16 < w32, "{w6} {w16} {w32}");
    let tris = tessellate_teapot([0.0; 3], 1.0, 0.0, 16).unwrap();
    let (mut lo, mut hi) = (v3(1e9, 1e9, 1e9), v3(-1e9, -1e9, -1e9));
    for p in tris.iter().flat_map(|t| t.p) {
        lo = v3(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
        hi = v3(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
    }
    // The data's surface: x ∈ [−3, 3.434] (handle to spout tip), height 0 … 3.15,
    // depth ±2 (the body's widest ring). Corners are exact; the spout tip is an
    // interior maximum sampled at 1/16 steps.
    let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol;
    assert!(
        close(lo.x, -3.0, 1e-12) && close(hi.x, 3.434, 5e-3),
        "x {lo:?} {hi:?}"
    );
    assert!(
        close(lo.y, 0.0, 1e-12) && close(hi.y, 3.15, 1e-12),
        "y {lo:?} {hi:?}"
    );
    assert!(
        close(lo.z, -2.0, 1e-12) && close(hi.z, 2.0, 1e-12),
        "z {lo:?} {hi:?}"
    );
}

#[test]
fn teapot_normals_point_outwards_and_poles_are_smooth() {
    let p = teapot_patches().unwrap();
    for (i, patch) in p.iter().enumerate() {
        for a in 0..=20 {
            for b in 0..=20 {
                let (q, n) = patch_point_normal(patch, a as f64 / 20.0, b as f64 / 20.0);
                assert!((n.length() - 1.0).abs() < 1e-12, "patch {i}");
                let radial = v3(q.x, 0.0, q.z);
                match i {
                    // The body: away from the axis.
                    4..=11 => assert!(n.dot(radial) > 0.0, "body patch {i} at {a},{b}: {n:?}"),
                    // The lid: upwards and outwards; its rim (u = 1) is vertical.
                    24..=27 => {
                        assert!(n.dot(radial) >= 0.0, "lid patch {i}: {n:?}");
                        assert!(
                            n.y > 0.0 || (a == 20 && n.y.abs() < 1e-12),
                            "lid patch {i}: {n:?}"
                        );
                    }
                    // The bottom: downwards and outwards; its rim (u = 1) is vertical.
                    28..=31 => {
                        assert!(n.dot(radial) >= 0.0, "bottom patch {i}: {n:?}");
                        assert!(
                            n.y < 0.0 || (a == 20 && n.y.abs() < 1e-12),
                            "bottom patch {i}: {n:?}"
                        );
                    }
                    _ => {}
                }
            }
        }
    }
    // At the poles the derivative ∂/∂v vanishes; the normal is the axis.
    for (i, patch) in p.iter().enumerate().take(24).skip(20) {
        for b in 0..=8 {
            let (q, n) = patch_point_normal(patch, 0.0, b as f64 / 8.0);
            assert!(
                (q.y - 3.15).abs() < 1e-12 && n.y > 0.9999,
                "lid pole {i}: {n:?}"
            );
        }
    }
    for (i, patch) in p.iter().enumerate().skip(28) {
        for b in 0..=8 {
            let (q, n) = patch_point_normal(patch, 0.0, b as f64 / 8.0);
            assert!(q.y.abs() < 1e-12 && n.y < -0.9999, "bottom pole {i}: {n:?}");
        }
    }
}

#[test]
fn teapot_transform_is_scale_rotate_move() {
    let base = tessellate_teapot([0.0; 3], 1.0, 0.0, 4).unwrap();
    let moved = tessellate_teapot([1.0, -2.0, 3.0], 0.5, 90.0, 4).unwrap();
    assert_eq!(base.len(), moved.len());
    for (a, b) in base.iter().zip(&moved) {
        for k in 0..3 {
            // Rotating +90° about y takes (x, y, z) to (z, y, −x).
            let p = a.p[k];
            let want = v3(0.5 * p.z + 1.0, 0.5 * p.y - 2.0, -0.5 * p.x + 3.0);
            assert!((b.p[k] - want).length() < 1e-12);
            let n = a.n[k];
            assert!((b.n[k] - v3(n.z, n.y, -n.x)).length() < 1e-12);
        }
    }
    expect_field(tessellate_teapot([0.0; 3], 0.0, 0.0, 4), "shape.scale");
    expect_field(
        tessellate_teapot([0.0; 3], 1.0, f64::NAN, 4),
        "shape.rotate_y_deg",
    );
    expect_field(
        tessellate_teapot([0.0; 3], 1.0, 0.0, 0),
        "shape.subdivisions",
    );
    expect_field(
        tessellate_teapot([f64::INFINITY, 0.0, 0.0], 1.0, 0.0, 4),
        "shape.position[0]",
    );
}

#[test]
fn sphere_and_box_are_closed_and_outward() {
    let c = v3(1.0, -2.0, 0.5);
    let sphere = Shape::Sphere {
        center: [1.0, -2.0, 0.5],
        radius: 1.5,
    };
    let tris = shape_triangles(&sphere).unwrap();
    assert_eq!(
        tris.len(),
        (2 * SPHERE_SEGMENTS * (SPHERE_RINGS - 1)) as usize
    );
    assert_unit_finite(&tris);
    for t in &tris {
        for k in 0..3 {
            assert!((t.p[k] - c).length() - 1.5 < 1e-12, "vertex on the sphere");
            assert!(t.n[k].dot(t.p[k] - c) > 0.0, "outward");
            assert!(
                (t.n[k] - (t.p[k] - c) * (1.0 / 1.5)).length() < 1e-12,
                "radial"
            );
        }
        assert!(
            geometric(t).dot(t.p[0] + t.p[1] + t.p[2] - c * 3.0) > 0.0,
            "ccw from outside"
        );
    }
    let (flux, vol) = closed_surface_sums(&tris);
    assert!(flux.length() < 1e-12, "closed: {flux:?}");
    // An inscribed polyhedron: a little less than 4/3·π·r³ (within 2 % at 32 × 16).
    let exact = 4.0 / 3.0 * std::f64::consts::PI * 1.5f64.powi(3);
    assert!(vol < exact && vol > 0.98 * exact, "volume {vol} vs {exact}");

    let bx = Shape::Box {
        min: [-1.0, 0.0, 2.0],
        max: [2.0, 0.5, 4.0],
    };
    let tris = shape_triangles(&bx).unwrap();
    assert_eq!(tris.len(), 12);
    assert_unit_finite(&tris);
    let centre = v3(0.5, 0.25, 3.0);
    for t in &tris {
        let g = geometric(t);
        for k in 0..3 {
            assert!(t.n[k].dot(t.p[k] - centre) > 0.0, "outward");
            assert!(
                (g.normalized() - t.n[k]).length() < 1e-12,
                "face normal = winding"
            );
            for (x, lo, hi) in [
                (t.p[k].x, -1.0, 2.0),
                (t.p[k].y, 0.0, 0.5),
                (t.p[k].z, 2.0, 4.0),
            ] {
                assert!(x == lo || x == hi, "corner");
            }
        }
    }
    let (flux, vol) = closed_surface_sums(&tris);
    assert!(flux.length() < 1e-12);
    assert!((vol - 3.0 * 0.5 * 2.0).abs() < 1e-12, "volume {vol}");

    // Segments and rings are configurable; too few is an error naming them.
    assert_eq!(sphere_triangles([0.0; 3], 1.0, 3, 2).unwrap().len(), 6);
    expect_field(sphere_triangles([0.0; 3], 1.0, 2, 8), "segments");
    expect_field(sphere_triangles([0.0; 3], 1.0, 8, 1), "rings");
    expect_field(sphere_triangles([0.0; 3], 0.0, 8, 8), "shape.radius");
}

#[test]
fn plane_is_two_triangles_on_the_normal_side() {
    // A tilted plane with a tangent not perpendicular to its normal.
    let n = v3(0.0, 1.0, 1.0).normalized();
    let shape = Shape::Plane {
        center: [1.0, 2.0, 3.0],
        normal: [0.0, 2.0, 2.0],
        tangent: [1.0, 1.0, 0.0],
        half_size: [2.0, 0.5],
    };
    let tris = shape_triangles(&shape).unwrap();
    assert_eq!(tris.len(), 2);
    assert_unit_finite(&tris);
    let c = v3(1.0, 2.0, 3.0);
    let mut area = 0.0;
    for t in &tris {
        let g = geometric(t);
        area += g.length() / 2.0;
        assert!(
            (g.normalized() - n).length() < 1e-12,
            "ccw seen from the normal side"
        );
        for k in 0..3 {
            assert!((t.n[k] - n).length() < 1e-12);
            assert!((t.p[k] - c).dot(n).abs() < 1e-12, "in the plane");
        }
    }
    assert!((area - 4.0 * 2.0 * 0.5).abs() < 1e-12, "area {area}");
    let parallel = Shape::Plane {
        center: [0.0; 3],
        normal: [0.0, 1.0, 0.0],
        tangent: [0.0, -3.0, 0.0],
        half_size: [1.0, 1.0],
    };
    expect_field(shape_triangles(&parallel), "shape.tangent");
}

#[test]
fn every_builtin_object_tessellates() {
    for name in BUILTIN_NAMES {
        for (i, o) in builtin(name).unwrap().objects.iter().enumerate() {
            let tris = shape_triangles(&o.shape).unwrap_or_else(|e| panic!("{name} {i}: {e}"));
            assert!(!tris.is_empty());
            assert_unit_finite(&tris);
        }
    }
}

// ---------------------------------------------------------------------------------
// The field table (src/scene/fields.rs) against the serde format, docs/scenes.md,
// `scene NAME` for every name, did-you-mean.

use glare_pipeline::scene::fields::{self, Ty, FIELDS};
use glare_pipeline::scene::load::{self, every_scene_name, load_scene, SHADING_NAMES};
use std::collections::BTreeSet;

/// A scene text that sets every optional section and every variant's fields (not
/// validated: it is for the serde format only). `background` picks the glare
/// background's variant.
fn maximal_text(background: &str) -> String {
    format!(
        r#"name = "maximal"
seed = 3
chip = "nv2a"
[image]
width = 64
height = 48
[camera]
eye = [0.0, 1.0, 5.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fovy_deg = 40.0
near = 0.5
far = 40.0
[medium]
rho = 0.1
kappa = 0.5
k = 1.0
[[lights]]
kind = "spot"
position = [0.0, 5.0, 0.0]
direction = [0.0, -1.0, 0.0]
cutoff_deg = 30.0
intensity = 2.0
color = [1.0, 0.5, 0.5]
light_map = {{ type = "smooth", exponent = 2.0 }}
[[lights]]
position = [0.0, 5.0, 0.0]
light_map = {{ type = "polka_dots", dots = 4, radius = 0.2 }}
[[lights]]
position = [0.0, 5.0, 0.0]
light_map = {{ type = "image", path = "map.png" }}
[[lights]]
kind = "point"
position = [1.0, 5.0, 0.0]
[[objects]]
shape = {{ type = "sphere", center = [0.0, 0.0, 0.0], radius = 1.0 }}
material = {{ model = "lambert" }}
[[objects]]
shape = {{ type = "plane", center = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0], tangent = [1.0, 0.0, 0.0], half_size = [1.0, 1.0] }}
material = {{ model = "phong", ks = 0.5, exponent = 10.0, normalized = true }}
[[objects]]
shape = {{ type = "box", min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0] }}
material = {{ model = "blinn_phong", ks = 0.5, exponent = 10.0 }}
[[objects]]
shape = {{ type = "teapot", position = [0.0, 0.0, 0.0], scale = 1.0, rotate_y_deg = 10.0, subdivisions = 4 }}
material = {{ model = "cook_torrance", distribution = "ggx", roughness = 0.3, ior = 1.5, extinction = 1.0, fresnel = "schlick" }}
[[objects]]
shape = {{ type = "sphere", center = [0.0, 0.0, 0.0], radius = 1.0 }}
material = {{ model = "ward", rho_s = 0.2, alpha_x = 0.1, alpha_y = 0.2 }}
[[objects]]
shape = {{ type = "sphere", center = [0.0, 0.0, 0.0], radius = 1.0 }}
material = {{ model = "oren_nayar", sigma_deg = 20.0 }}
[[objects]]
shape = {{ type = "sphere", center = [0.0, 0.0, 0.0], radius = 1.0 }}
material = {{ model = "kajiya_kay", ks = 0.3, exponent = 8.0 }}
occluder = false
color = [0.5, 0.5, 0.5]
[shafts]
acc_int_bits = 21
acc_frac_bits = 23
recip_index_bits = 9
recip_entry_bits = 15
newton_frac_bits = 21
plane_step = "plane_spacing"
[rounding]
chain = "fused"
filter = "successive_lerps"
weight = "truncate"
[shading_hw]
cube_face = 32
lookup_log2 = 7
factor_size = 48
factor_bits = 7
[glare]
background = {background}
frame = 3
[[glare.sources]]
kind = "polygon"
position = [0.0, 2.0, 0.0]
a = 0.5
b = 0.2
n = [0.0, 0.0, 1.0]
vertices = [[1.0, 2.0, 0.0], [0.0, 3.0, 0.0]]
intensity = 500.0
area_size = 0.5
directivity = [0.0, 0.0, 1.0]
color = [1.0, 1.0, 0.5]
bloom = false
halo = false
flare = false
fluctuation = {{ patches = 4, spread = 0.5, patch_radius = 0.1 }}
[[glare.highlights]]
material = "water"
position = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
light = [0.0, 5.0, 0.0]
intensity = 100.0
specular = 0.5
eta = 1.2
radius = 0.05
[glare.shaded_highlights]
light = 0
intensity = 100.0
radius = 0.05
[environment]
map = "pattern"
hdr = "x.hdr"
exposure = 1.0
exposure_rule = "max"
weighting = "uniform"
dome_pick = "voxel_spacing"
side = 64
object = "sphere"
lambda = 0.5
lookup = "auto"
background = "black"
reflectors = [{{ object = 0, lambda = 0.5, reflectance = 0.5 }}]
prefilter = {{ type = "accelerated", threshold = 0.01 }}
"#
    )
}

/// The maximal scenes, one per glare background variant, as the serde format reads
/// them.
fn maximal_scenes() -> Vec<Scene> {
    [
        r#"{ type = "sky", top = [0.1, 0.1, 0.2], bottom = [0.0, 0.0, 0.0] }"#,
        r#"{ type = "canopy", leaves = 10, sky = [0.5, 0.5, 0.9], leaf = [0.1, 0.2, 0.1] }"#,
        r#"{ type = "black" }"#,
        r#"{ type = "shafts" }"#,
    ]
    .iter()
    .enumerate()
    .map(|(i, b)| {
        // The other prefilters' tags too (their fields are the accelerated one's).
        let prefilter = ["accelerated", "accelerated", "exact", "auto"][i];
        let text = maximal_text(b).replace(
            r#"prefilter = { type = "accelerated", threshold = 0.01 }"#,
            &format!(
                "prefilter = {{ type = \"{prefilter}\"{} }}",
                if prefilter == "accelerated" {
                    ", threshold = 0.01"
                } else {
                    ""
                }
            ),
        );
        toml::from_str::<Scene>(&text).unwrap()
    })
    .collect()
}

/// Every key path of a TOML value: `camera`, `camera.eye`, `lights`,
/// `lights[].light_map.type`, …
fn key_paths(prefix: &str, v: &toml::Value, out: &mut BTreeSet<String>) {
    let toml::Value::Table(t) = v else { return };
    for (k, x) in t {
        let p = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        out.insert(p.clone());
        match x {
            toml::Value::Table(_) => key_paths(&p, x, out),
            toml::Value::Array(a) if !a.is_empty() && a.iter().all(|e| e.is_table()) => {
                for e in a {
                    key_paths(&format!("{p}[]"), e, out);
                }
            }
            _ => {}
        }
    }
}

/// Every string value of a TOML value with its generic path.
fn string_values(prefix: &str, v: &toml::Value, out: &mut BTreeSet<(String, String)>) {
    let toml::Value::Table(t) = v else { return };
    for (k, x) in t {
        let p = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match x {
            toml::Value::String(s) => {
                out.insert((p, s.clone()));
            }
            toml::Value::Table(_) => string_values(&p, x, out),
            toml::Value::Array(a) => {
                for e in a {
                    string_values(&format!("{p}[]"), e, out);
                }
            }
            _ => {}
        }
    }
}

/// A concrete path (keys and array indices) to the first place a generic path
/// (`lights[].light_map.dots`) exists in `v`.
fn locate(v: &toml::Value, parts: &[&str]) -> Option<Vec<(String, Option<usize>)>> {
    let Some((part, rest)) = parts.split_first() else {
        return Some(Vec::new());
    };
    let (key, array) = match part.strip_suffix("[]") {
        Some(k) => (k, true),
        None => (*part, false),
    };
    let x = v.get(key)?;
    if !array {
        let mut tail = locate(x, rest)?;
        tail.insert(0, (key.to_string(), None));
        return Some(tail);
    }
    let a = x.as_array()?;
    a.iter().enumerate().find_map(|(i, e)| {
        let mut tail = locate(e, rest)?;
        tail.insert(0, (key.to_string(), Some(i)));
        Some(tail)
    })
}

/// The value at a generic path (the first place it exists).
fn value_at<'a>(v: &'a toml::Value, path: &str) -> Option<&'a toml::Value> {
    let parts: Vec<&str> = path.split('.').collect();
    let steps = locate(v, &parts)?;
    let mut cur = v;
    for (k, i) in steps {
        cur = cur.get(k.as_str())?;
        if let Some(i) = i {
            cur = cur.get(i)?;
        }
    }
    Some(cur)
}

/// Set or remove the value at a generic path (the first place it exists).
fn set_at(v: &mut toml::Value, path: &str, value: Option<toml::Value>) {
    let parts: Vec<&str> = path.split('.').collect();
    let steps = locate(v, &parts).expect("the path exists");
    let n = steps.len();
    let mut cur = v;
    for (j, (k, i)) in steps.into_iter().enumerate() {
        if j + 1 == n {
            let t = cur.as_table_mut().expect("a table");
            match value {
                Some(x) => {
                    t.insert(k, x);
                }
                None => {
                    t.remove(&k);
                }
            }
            return;
        }
        cur = cur.get_mut(k.as_str()).expect("a key");
        if let Some(i) = i {
            cur = cur.get_mut(i).expect("an element");
        }
    }
}

/// The scenes whose serialised forms are searched for key paths: every built-in and
/// the maximal scenes.
fn format_scenes() -> Vec<Scene> {
    let mut v: Vec<Scene> = load::builtin_names()
        .into_iter()
        .map(|n| builtin(n).unwrap())
        .collect();
    v.extend(maximal_scenes());
    // The shading sphere with every field of its section (each width set: the serde
    // format holds any of them; which a scene takes is validation's), and the test
    // scene.
    let mut sphere = load_scene("shading-specular").unwrap();
    let sec = sphere.shading_sphere.as_mut().unwrap();
    sec.image = Some(64);
    sec.chip = rtl_model::chip_preset::ChipPreset::parse("chip", "nv2a").unwrap();
    sec.hw = glare_pipeline::pipeline::shading::sweep::SHADING_PARAMS
        .iter()
        .map(|p| (p.to_string(), 8))
        .collect();
    v.push(sphere);
    v.push(Scene::test_scene());
    v
}

#[test]
fn field_table_matches_the_serde_format() {
    let mut found = BTreeSet::new();
    for s in format_scenes() {
        let v = toml::Value::try_from(&s).unwrap();
        // What serialises deserialises to the same scene: the keys are the format's.
        let back: Scene = toml::from_str(&toml::to_string(&s).unwrap()).unwrap();
        assert_eq!(back, s, "{}", s.name);
        key_paths("", &v, &mut found);
    }
    let table: BTreeSet<String> = FIELDS.iter().map(|f| f.path.to_string()).collect();
    assert_eq!(table.len(), FIELDS.len(), "a path is listed twice");
    let missing: Vec<_> = found.difference(&table).collect();
    assert!(
        missing.is_empty(),
        "key paths of the scene format missing from src/scene/fields.rs: {missing:?}"
    );
    let stale: Vec<_> = table.difference(&found).collect();
    assert!(
        stale.is_empty(),
        "src/scene/fields.rs lists paths the scene format does not have: {stale:?}"
    );
}

#[test]
fn every_table_entry_deserializes_with_its_default_and_choices() {
    let bases: Vec<toml::Value> = format_scenes()
        .iter()
        .map(|s| toml::Value::try_from(s).unwrap())
        .collect();
    let parse = |text: &str| {
        text.parse::<toml::Table>()
            .map(toml::Value::Table)
            .unwrap_or_else(|e| panic!("{text}: {e}"))
    };
    let mut strings = BTreeSet::new();
    for b in &bases {
        string_values("", b, &mut strings);
    }
    let mut checked_defaults = 0;
    for f in FIELDS {
        let base = bases
            .iter()
            .find(|b| value_at(b, f.path).is_some())
            .unwrap_or_else(|| panic!("{}: in no scene", f.path));
        // Each choice of a choice field is accepted at that path; a choice not listed
        // is refused.
        let choices: &[&str] = match f.ty {
            Ty::Choice(c) | Ty::RealOr(c) => c,
            _ => &[],
        };
        let tag = (f.path.ends_with(".type") || f.path.ends_with(".model"))
            && fields::field(f.path.rsplit_once('.').unwrap().0)
                .is_some_and(|p| p.ty == Ty::Tagged);
        for c in choices {
            if tag {
                // A variant tag: some scene of the format holds each variant (its
                // fields differ, so the tag alone cannot be swapped).
                assert!(
                    strings.contains(&(f.path.to_string(), c.to_string())),
                    "{} = \"{c}\": in no scene",
                    f.path
                );
                continue;
            }
            let mut v = base.clone();
            set_at(&mut v, f.path, Some(toml::Value::String(c.to_string())));
            let text = toml::to_string(&v).unwrap();
            if let Err(e) = toml::from_str::<Scene>(&text) {
                panic!("{} = \"{c}\" is refused: {e}", f.path);
            }
        }
        // `environment.map` is a string to serde; validation refuses a name not
        // listed (checked below).
        if !choices.is_empty() && !tag && f.path != "environment.map" {
            let mut v = base.clone();
            set_at(&mut v, f.path, Some(toml::Value::String("no_such".into())));
            assert!(
                toml::from_str::<Scene>(&toml::to_string(&v).unwrap()).is_err(),
                "{} accepts a choice the table does not list",
                f.path
            );
        }
        // The default: the field left out reads back as the table says (a field
        // written only when it differs from its default reads back absent).
        match f.default {
            "required" | "" => {}
            "none" => {
                let mut v = base.clone();
                set_at(&mut v, f.path, None);
                let s: Scene = toml::from_str(&toml::to_string(&v).unwrap())
                    .unwrap_or_else(|e| panic!("{} left out: {e}", f.path));
                let again = toml::Value::try_from(&s).unwrap();
                assert!(value_at(&again, f.path).is_none(), "{}: not none", f.path);
                checked_defaults += 1;
            }
            d => {
                let want = parse(&format!("v = {d}"))["v"].clone();
                let mut v = base.clone();
                set_at(&mut v, f.path, None);
                let s: Scene = toml::from_str(&toml::to_string(&v).unwrap())
                    .unwrap_or_else(|e| panic!("{} left out: {e}", f.path));
                let again = toml::Value::try_from(&s).unwrap();
                if let Some(got) = value_at(&again, f.path) {
                    assert_eq!(got, &want, "{}: the default", f.path);
                    checked_defaults += 1;
                }
            }
        }
    }
    assert!(
        checked_defaults > 100,
        "only {checked_defaults} defaults checked"
    );
    let mut s = builtin("env-pattern-sphere").unwrap();
    s.environment.as_mut().unwrap().map = Some("no_such".into());
    expect_field(s.validate(), "environment.map");
}

#[test]
fn validation_ranges_are_the_tables() {
    use fields::Range;
    // A field at each end of its range is accepted, just outside is refused, naming
    // the field: the ranges validation checks are the table's.
    let base = builtin("glare-flare").unwrap();
    type Setter = fn(&mut Scene, f64);
    let cases: Vec<(fields::Field, Setter)> = vec![
        (fields::MEDIUM_RHO, |s, x| s.medium.rho = x),
        (fields::CAMERA_FOVY_DEG, |s, x| s.camera.fovy_deg = x),
        (fields::LIGHT_INTENSITY, |s, x| s.lights[0].intensity = x),
        (fields::SHAFTS_PLANES, |s, x| s.shafts.planes = x as u32),
        (fields::SHAFTS_S_MAX, |s, x| s.shafts.s_max = x),
        (fields::IMAGE_WIDTH, |s, x| s.image.width = x as u32),
        (fields::GLARE_AGE, |s, x| {
            s.glare.as_mut().unwrap().determinants.age = x
        }),
        (fields::CHAOS_Z, |s, x| {
            s.glare.as_mut().unwrap().model.chaos_z = x
        }),
        (fields::HW_PIPES, |s, x| {
            s.glare.as_mut().unwrap().hw.pipes = x as u32
        }),
    ];
    let mut s0 = base.clone();
    if s0.lights.is_empty() {
        s0.lights.push(kitchen_sink().lights[0].clone());
    }
    for (f, set) in cases {
        let (lo, lo_in, hi, hi_in, step) = match f.range {
            Range::Real {
                lo,
                lo_closed,
                hi,
                hi_closed,
            } => (lo, lo_closed, hi, hi_closed, (hi - lo) * 1e-6),
            Range::Int { lo, hi } => (lo as f64, true, hi as f64, true, 1.0),
            other => panic!("{}: {other:?}", f.path),
        };
        let check = |x: f64, ok: bool| {
            let mut s = s0.clone();
            set(&mut s, x);
            let r = s.validate();
            assert_eq!(r.is_ok(), ok, "{} = {x}: {r:?}", f.path);
            if let Err(e) = r {
                assert!(
                    e.field().ends_with(f.path.rsplit('.').next().unwrap()),
                    "{e}"
                );
            }
        };
        let inside = |x: f64, closed: bool, dir: f64| if closed { x } else { x + dir * step };
        check(inside(lo, lo_in, 1.0), true);
        check(inside(hi, hi_in, -1.0), true);
        if lo > 0.0 || !matches!(f.range, Range::Int { .. }) {
            check(if lo_in { lo - step } else { lo }, false);
        }
        check(if hi_in { hi + step } else { hi }, false);
    }
}

#[test]
fn docs_scenes_md_is_generated_from_the_table() {
    let want = glare_pipeline::frame::scene_text::reference_text().unwrap();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scenes.md");
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "docs/scenes.md differs from what the generator writes: run \
         `glare-pipeline scene --reference docs/scenes.md`"
    );
    // Every field is in it with its unit and range.
    for f in FIELDS {
        // A top-level section is a heading, everything else a row.
        let shown = [
            format!("| `{}` | {} | {} |", f.path, f.ty.text(), f.unit),
            format!("## `[{}]`", f.path),
            format!("## `[[{}]]`", f.path),
        ];
        assert!(
            shown.iter().any(|t| want.contains(t.as_str())),
            "{}",
            f.path
        );
    }
    // A width whose range a unit decides shows that range in numbers: the values
    // validation accepts, one interval, refused just outside.
    for f in FIELDS {
        if f.ty == Ty::Int
            && matches!(f.range, fields::Range::Unit(_))
            && (f.path.starts_with("shafts.") || f.path.starts_with("glare.hw."))
        {
            let (lo, hi) = glare_pipeline::scene::fields_reference::probe_int(f.path)
                .unwrap_or_else(|| panic!("{}: no interval found", f.path));
            assert!(lo <= hi && hi < 1 << 20, "{}", f.path);
            assert!(
                want.contains(&format!("{lo} ..= {hi} (unit)")),
                "{}",
                f.path
            );
        }
    }
}

/// The body of a printed scene after its header comment lines.
fn body(text: &str) -> &str {
    let start = text.find("\n\n").map_or(0, |i| i + 2);
    &text[start..]
}

#[test]
fn scene_name_prints_compact_toml_that_loads_back_for_every_builtin() {
    use glare_pipeline::frame::scene_text::scene_text;
    use glare_pipeline::pipeline::shading::scene_file::ShadingFile;
    use glare_pipeline::scene::print::scene_toml;
    // The shading names this layer lists are the shading pipeline's.
    assert_eq!(
        SHADING_NAMES.to_vec(),
        glare_pipeline::pipeline::shading::sweep::scene_names()
    );
    for name in every_scene_name() {
        let text = scene_text(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(text.starts_with("# "), "{name}: a comment says what it is");
        // Compact: every line is a comment, a header, blank or `key = value` (no
        // vector element on a line of its own).
        for line in text.lines() {
            let t = line.trim();
            assert!(
                t.is_empty() || t.starts_with('#') || t.starts_with('[') || t.contains(" = "),
                "{name}: line `{line}`"
            );
        }
        if name == load::TEST_NAME {
            assert_eq!(
                glare_pipeline::scene::test_scene::parse_file(&text),
                Ok(true)
            );
            continue;
        }
        if SHADING_NAMES.contains(&name) {
            let f = ShadingFile::parse(&text).unwrap();
            let built = ShadingFile::builtin(name).unwrap();
            assert_eq!(f, built, "{name}");
            assert_eq!(f.to_toml("").unwrap(), built.to_toml("").unwrap());
            continue;
        }
        let loaded = Scene::from_toml_str(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        let want = builtin(name).unwrap();
        assert_eq!(loaded, want, "{name}");
        // Printing the loaded scene again gives the same text, byte for byte.
        let again = scene_toml(&loaded, "").unwrap();
        assert_eq!(
            again,
            body(&text),
            "{name}: the round trip is not byte-stable"
        );
        let lines = text.lines().count();
        let pretty = toml::to_string_pretty(&want).unwrap().lines().count();
        assert!(
            lines < pretty,
            "{name}: {lines} lines, pretty TOML {pretty}"
        );
        // Each section has a comment line above its header.
        let ls: Vec<&str> = text.lines().collect();
        for (i, l) in ls.iter().enumerate() {
            if l.starts_with('[') && !l.contains('=') {
                let header = l.trim_matches(['[', ']']);
                let first = !ls[..i].iter().any(|p| p.trim_matches(['[', ']']) == header);
                if first {
                    assert!(ls[i - 1].starts_with("# "), "{name}: no comment above {l}");
                }
            }
        }
    }
}

#[test]
fn scene_files_render_the_same_bytes_as_the_builtins() {
    use glare_pipeline::frame::scene_text::scene_text;
    use glare_pipeline::pipeline::shading::scene_file::{render_cli, ShadingFile};
    use glare_pipeline::scene::print::scene_toml;
    let dir = scratch_dir().join(format!("render_{:?}", std::thread::current().id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A shafts scene and a glare scene at a small image: the built-in against its
    // printed file read back from disk.
    for name in ["fig6", "glare-point"] {
        let mut s = builtin(name).unwrap();
        s.image = ImageSize {
            width: 48,
            height: 32,
        };
        let file = dir.join(format!("{name}.toml"));
        std::fs::write(&file, scene_toml(&s, "# test\n\n").unwrap()).unwrap();
        let loaded = Scene::from_file(&file).unwrap();
        assert_eq!(loaded, s);
        let a = dir.join(format!("{name}_builtin.png"));
        let b = dir.join(format!("{name}_file.png"));
        glare_pipeline::frame::run::render(&s)
            .unwrap()
            .fb
            .save_png(&a)
            .unwrap();
        glare_pipeline::frame::run::render(&loaded)
            .unwrap()
            .fb
            .save_png(&b)
            .unwrap();
        let (pa, pb) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
        assert!(pa.len() > 100);
        assert_eq!(pa, pb, "{name}: the file renders other bytes");
    }
    // A shading scene at a small view: `scene NAME`'s form with the view shrunk.
    let text = scene_text("shading-phong")
        .unwrap()
        .replace("image = 256", "image = 24");
    let f = ShadingFile::parse(&text).unwrap();
    let mut built = ShadingFile::builtin("shading-phong").unwrap();
    built.image = Some(24);
    assert_eq!(f, built);
    let (a, b) = (
        dir.join("shading_builtin.png"),
        dir.join("shading_file.png"),
    );
    render_cli(&built, &a, true, None, false).unwrap();
    render_cli(&f, &b, true, None, false).unwrap();
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
}

#[test]
fn misspelt_names_and_missing_files_are_told_apart() {
    let e = load_scene("fig7").unwrap_err();
    assert!(e.contains("did you mean fig4 or fig6?"), "{e}");
    let e = load_scene("glare-pont").unwrap_err();
    assert!(e.contains("did you mean glare-point?"), "{e}");
    let e = load_scene("env-pattern").unwrap_err();
    assert!(
        e.contains("did you mean env-pattern-sphere or env-pattern-teapot?"),
        "{e}"
    );
    let e = load_scene("shading-phogn").unwrap_err();
    assert!(e.contains("did you mean shading-phong?"), "{e}");
    let e = load_scene("zzzzzzzz").unwrap_err();
    assert!(!e.contains("did you mean"), "{e}");
    for missing in ["./nope.toml", "dir/scene", "nope.toml"] {
        let e = load_scene(missing).unwrap_err();
        assert_eq!(e, format!("scene: file not found: {missing}"));
    }
    // `test` and the shading scenes are scenes of other kinds: the one resolver takes
    // them, a tool of lights and objects says what they are.
    assert!(load_scene("test").unwrap().test_scene.is_some());
    assert!(load_scene("shading-phong")
        .unwrap()
        .shading_sphere
        .is_some());
    assert!(load::load_frame_scene("test")
        .unwrap_err()
        .contains("foundation test scene"));
    assert!(load::load_frame_scene("shading-phong")
        .unwrap_err()
        .contains("shading scene"));
}

#[test]
fn a_misspelt_key_names_its_path_and_the_nearest_key() {
    let t = builtin_toml("fig6").unwrap();
    let cases = [
        ("fovy_deg = 40.0", "fvo = 40.0", "camera.fvo", "`fovy_deg`"),
        (
            "cutoff_deg",
            "cutof_deg",
            "lights[0].cutof_deg",
            "`cutoff_deg`",
        ),
        ("planes = 30", "plnaes = 30", "shafts.plnaes", "`planes`"),
        (
            "type = \"sphere\"",
            "type = \"spehre\"",
            "objects[0].shape.type",
            "`sphere`",
        ),
    ];
    for (from, to, field, hint) in cases {
        assert!(t.contains(from), "{from}");
        let e = Scene::from_toml_str(&t.replacen(from, to, 1)).unwrap_err();
        assert_eq!(e.field(), field, "{e}");
        assert!(
            e.to_string().contains(&format!("did you mean {hint}?")),
            "{e}"
        );
    }
}
