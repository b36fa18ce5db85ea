//! Environment input: conventions, the built-in pattern, HDR loading, downsampling,
//! exposure and the 256-level conversion (src/scene/envmap.rs).

use std::f64::consts::PI;
use std::path::PathBuf;

use glare_pipeline::scene::envmap::{
    dir_to_uv, hsv_to_rgb, texel_dir, texel_solid_angle, uv_to_dir, EnvMap,
};
use glare_pipeline::scene::math::{v3, Vec3};

fn repo_envmap(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("src/scene/data/envmaps/{name}"))
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// RGB → (h in turns, s, v) for the pattern checks.
fn rgb_to_hsv(c: [f64; 3]) -> (f64, f64, f64) {
    let max = c[0].max(c[1]).max(c[2]);
    let min = c[0].min(c[1]).min(c[2]);
    let d = max - min;
    let s = if max > 0.0 { d / max } else { 0.0 };
    let h = if d == 0.0 {
        0.0
    } else if max == c[0] {
        ((c[1] - c[2]) / d).rem_euclid(6.0) / 6.0
    } else if max == c[1] {
        ((c[2] - c[0]) / d + 2.0) / 6.0
    } else {
        ((c[0] - c[1]) / d + 4.0) / 6.0
    };
    (h, s, max)
}

#[test]
fn pattern_is_a_hue_by_saturation_chart() {
    let (w, h) = (512, 256);
    let p = EnvMap::pattern(w, h);
    assert_eq!((p.width(), p.height()), (w, h));
    // Hand checks: top row fully saturated primaries/secondaries at their hues, bottom
    // row white.
    let red = p.texel(0, 0);
    assert!(
        close(red[0], 1.0, 1e-12) && red[1] < 0.02 && red[2] == 0.0,
        "{red:?}"
    );
    let green = p.texel(170, 0); // hue (170.5)/512 ≈ 0.333
    assert!(
        green[1] == 1.0 && green[0] < 0.01 && green[2] < 0.01,
        "{green:?}"
    );
    let blue = p.texel(341, 0); // hue ≈ 0.667
    assert!(
        blue[2] == 1.0 && blue[0] < 0.01 && blue[1] < 0.01,
        "{blue:?}"
    );
    let yellow = p.texel(85, 0); // hue ≈ 1/6
    assert!(
        yellow[0] > 0.99 && yellow[1] > 0.99 && yellow[2] == 0.0,
        "{yellow:?}"
    );
    assert_eq!(p.texel(123, h - 1), [1.0, 1.0, 1.0]);
    // Middle row: half saturation, same hue as its column.
    let mid = p.texel(0, 128);
    let (_, s, v) = rgb_to_hsv(mid);
    assert!(close(s, 1.0 - 128.0 / 255.0, 1e-12) && v == 1.0, "{mid:?}");
    // Everywhere: hue = (i + ½)/W, saturation = 1 − j/(H − 1), value = 1.
    for j in (0..h).step_by(17) {
        for i in (0..w).step_by(13) {
            let (hh, s, v) = rgb_to_hsv(p.texel(i, j));
            let want_s = 1.0 - j as f64 / (h - 1) as f64;
            assert!(close(v, 1.0, 1e-12), "v at ({i},{j})");
            assert!(close(s, want_s, 1e-12), "s at ({i},{j}): {s} vs {want_s}");
            if want_s > 0.0 {
                let want_h = (i as f64 + 0.5) / w as f64;
                assert!(close(hh, want_h, 1e-9), "h at ({i},{j}): {hh} vs {want_h}");
            }
        }
    }
    // The pattern is the thesis' 8-bit chart at exposure 1.
    assert_eq!(p.auto_exposure(), 1.0);
    let levels = p.to_levels(1.0).unwrap();
    assert_eq!(levels[0], [255, 1, 0]); // hue 0.5/512 turn: G = 255·6·0.5/512 ≈ 1.5 → 1
    assert_eq!(levels[(h - 1) * w], [255, 255, 255]);
    assert_eq!(EnvMap::builtin("pattern").unwrap(), p);
    // Odd sizes never panic.
    for (w, h) in [(0, 0), (1, 1), (3, 1), (7, 5)] {
        let p = EnvMap::pattern(w, h);
        assert!(p.texels().iter().flatten().all(|c| (0.0..=1.0).contains(c)));
    }
    assert_eq!(hsv_to_rgb(1.0, 1.0, 1.0), [1.0, 0.0, 0.0]);
}

#[test]
fn solid_angles_sum_to_four_pi() {
    for (w, h) in [(1, 1), (3, 2), (64, 32), (512, 256), (1000, 7)] {
        let sum: f64 = (0..h).map(|j| texel_solid_angle(j, w, h) * w as f64).sum();
        assert!(close(sum, 4.0 * PI, 1e-12), "{w}×{h}: {sum}");
        assert!((0..h).all(|j| texel_solid_angle(j, w, h) > 0.0));
    }
}

#[test]
fn direction_conventions_and_round_trip() {
    let (w, h) = (64, 32);
    for j in 0..h {
        for i in 0..w {
            let d = texel_dir(i, j, w, h);
            assert!(close(d.length(), 1.0, 1e-12));
            let (u, v) = dir_to_uv(d);
            assert!(
                close(u, (i as f64 + 0.5) / w as f64, 1e-12),
                "u at ({i},{j})"
            );
            assert!(
                close(v, (j as f64 + 0.5) / h as f64, 1e-12),
                "v at ({i},{j})"
            );
        }
    }
    // The axes: φ = 0 along −z, increasing towards +x; θ from +y.
    let axes: [(Vec3, f64, f64); 5] = [
        (v3(0.0, 0.0, -1.0), 0.0, 0.5),
        (v3(1.0, 0.0, 0.0), 0.25, 0.5),
        (v3(0.0, 0.0, 1.0), 0.5, 0.5),
        (v3(-1.0, 0.0, 0.0), 0.75, 0.5),
        (v3(0.0, 2.0, 0.0), 0.0, 0.0),
    ];
    for (d, u, v) in axes {
        let (gu, gv) = dir_to_uv(d);
        assert!(
            close(gu, u, 1e-12) && close(gv, v, 1e-12),
            "{d:?}: {gu} {gv}"
        );
    }
    assert!(close(dir_to_uv(v3(0.0, -1.0, 0.0)).1, 1.0, 1e-15));
    // uv → dir → uv on a grid of non-pole points, and degenerate input.
    for a in 0..50 {
        for b in 1..50 {
            let (u, v) = (a as f64 / 50.0, b as f64 / 50.0);
            let (u2, v2) = dir_to_uv(uv_to_dir(u, v));
            assert!(close(u2, u, 1e-12) && close(v2, v, 1e-12), "{u} {v}");
        }
    }
    assert_eq!(dir_to_uv(v3(0.0, 0.0, 0.0)), (0.0, 0.0));
    assert_eq!(dir_to_uv(v3(f64::NAN, 0.0, 1.0)), (0.0, 0.0));
}

#[test]
fn bilinear_lookup_wraps_and_clamps() {
    let (w, h) = (8, 4);
    let texels = (0..w * h)
        .map(|k| [(k % w) as f64, (k / w) as f64, 1.0])
        .collect();
    let env = EnvMap::new(w, h, texels).unwrap();
    // At texel centres: the texel.
    for j in 0..h {
        for i in 0..w {
            let got = env.lookup(env.texel_dir(i, j));
            let want = env.texel(i, j);
            for c in 0..3 {
                assert!(close(got[c], want[c], 1e-9), "({i},{j}) {got:?} {want:?}");
            }
        }
    }
    // At u = 0 (between column W−1 and column 0): the average, i.e. wrapping.
    let got = env.lookup_uv(0.0, 1.5 / h as f64);
    assert!(close(got[0], (w as f64 - 1.0) / 2.0, 1e-12), "{got:?}");
    // Above row 0's centre and below row H−1's: clamped to the row.
    assert!(close(env.lookup_uv(0.5 / w as f64, 0.0)[1], 0.0, 1e-12));
    assert!(close(env.lookup(v3(0.0, -1.0, 0.0))[1], 3.0, 1e-12));
    // Halfway between two rows.
    assert!(close(env.lookup_uv(0.5 / w as f64, 0.5)[1], 1.5, 1e-12));
    // Never NaN.
    let x = env.lookup_uv(f64::NAN, f64::INFINITY);
    assert!(x.iter().all(|c| c.is_finite()));
}

#[test]
fn downsample_box_filter_preserves_the_integral() {
    let env = EnvMap::pattern(64, 32);
    let small = env.downsample(4).unwrap();
    assert_eq!((small.width(), small.height()), (16, 8));
    let (a, b) = (env.mean(), small.mean());
    for c in 0..3 {
        assert!(close(a[c], b[c], 1e-12), "{a:?} {b:?}");
    }
    let k = EnvMap::constant(32, 16, [0.25, 2.0, 7.0]).unwrap();
    for t in k.downsample(2).unwrap().texels() {
        for (c, want) in t.iter().zip([0.25, 2.0, 7.0]) {
            assert!(close(*c, want, 1e-12));
        }
    }
    assert!(env.downsample(1).unwrap() == env);
    for bad in [0, 3, 64, 5] {
        let e = env.downsample(bad).unwrap_err();
        assert_eq!(e.field(), "envmap.downsample_factor");
    }
}

#[test]
fn constructor_refuses_bad_texels_and_sizes() {
    let e = EnvMap::new(2, 1, vec![[0.0; 3]]).unwrap_err();
    assert_eq!(e.field(), "envmap.texels");
    let e = EnvMap::new(2, 1, vec![[0.0; 3], [1.0, f64::NAN, 0.0]]).unwrap_err();
    assert_eq!(e.field(), "envmap.texels[1]");
    let e = EnvMap::new(2, 1, vec![[f64::INFINITY, 0.0, 0.0], [0.0; 3]]).unwrap_err();
    assert_eq!(e.field(), "envmap.texels[0]");
    let e = EnvMap::new(2, 1, vec![[0.0; 3], [0.0, 0.0, -1e-3]]).unwrap_err();
    assert_eq!(e.field(), "envmap.texels[1]");
    assert_eq!(
        EnvMap::new(0, 1, vec![]).unwrap_err().field(),
        "envmap.width"
    );
    assert_eq!(
        EnvMap::new(1, 0, vec![]).unwrap_err().field(),
        "envmap.height"
    );
    assert_eq!(
        EnvMap::constant(1 << 20, 1, [0.0; 3]).unwrap_err().field(),
        "envmap.width"
    );
    assert_eq!(EnvMap::builtin("nope").unwrap_err().field(), "envmap.name");
}

#[test]
fn levels_and_exposure() {
    let env = EnvMap::new(
        4,
        1,
        vec![[0.0; 3], [0.5, 1.0, 2.0], [1e-3, 0.25, 1e100], [0.1; 3]],
    )
    .unwrap();
    let l = env.to_levels(1.0).unwrap();
    assert_eq!(l, vec![[0; 3], [128, 255, 255], [0, 64, 255], [26; 3]]);
    let l2 = env.to_levels(0.5).unwrap();
    assert_eq!(l2[1], [64, 128, 255]);
    let m = env.to_level_map(1.0).unwrap();
    assert_eq!(m.texels()[1], [128.0, 255.0, 255.0]);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(env.to_levels(bad).unwrap_err().field(), "envmap.exposure");
    }
    // All-black map: exposure 1; tiny values: large but finite.
    assert_eq!(
        EnvMap::constant(4, 2, [0.0; 3]).unwrap().auto_exposure(),
        1.0
    );
    let tiny = EnvMap::constant(4, 2, [1e-310; 3]).unwrap().auto_exposure();
    assert!(tiny.is_finite() && tiny > 0.0);
    // A sun at 1e5 × the mean: the P99 exposure ignores it and clips only the sun.
    let mut env = EnvMap::pattern(64, 32).into_texels();
    for t in env.iter_mut() {
        *t = t.map(|c| 0.5 * c);
    }
    env[10 * 64 + 20] = [5e4; 3];
    let env = EnvMap::new(64, 32, env).unwrap();
    let e = env.auto_exposure();
    assert!(close(e, 2.0, 1e-12), "{e}");
    let l = env.to_levels(e).unwrap();
    assert_eq!(l[10 * 64 + 20], [255; 3]);
    assert_eq!(l[31 * 64], [255; 3]);
}

fn check_hdr(env: &EnvMap, name: &str) {
    assert_eq!((env.width(), env.height()), (512, 256), "{name}");
    assert!(env
        .texels()
        .iter()
        .flatten()
        .all(|c| c.is_finite() && *c >= 0.0));
    let zero = env
        .texels()
        .iter()
        .filter(|t| t.iter().all(|c| *c == 0.0))
        .count();
    let mean = env.mean();
    let max = env.texels().iter().flatten().fold(0.0f64, |a, &b| a.max(b));
    let e = env.auto_exposure();
    let l = env.to_levels(e).unwrap();
    let clipped = l.iter().filter(|t| t.contains(&255)).count();
    let mean_level: f64 = l
        .iter()
        .map(|t| t.iter().map(|&c| c as f64).sum::<f64>() / 3.0)
        .sum::<f64>()
        / l.len() as f64;
    println!(
        "{name}: mean {mean:.4?}, max {max:.1}, black texels {zero}, auto exposure {e:.4}, \
         texels with a 255 channel {clipped} ({:.2} %), mean level {mean_level:.1}",
        100.0 * clipped as f64 / l.len() as f64
    );
    assert!(mean.iter().all(|c| *c > 0.0));
    assert!(e.is_finite() && e > 0.0);
}

#[test]
fn hdr_repo_copies_load() {
    for (file, builtin) in [
        ("venice_sunset_512.hdr", "venice_sunset"),
        ("st_fagans_interior_512.hdr", "st_fagans_interior"),
    ] {
        let from_file = EnvMap::load_hdr(repo_envmap(file)).unwrap();
        check_hdr(&from_file, file);
        assert_eq!(EnvMap::builtin(builtin).unwrap(), from_file);
    }
}

#[test]
fn hdr_errors_name_the_path() {
    let missing = repo_envmap("no_such_map.hdr");
    let e = EnvMap::load_hdr(&missing).unwrap_err();
    assert_eq!(e.field(), "envmap.path");
    assert!(e.to_string().contains("no_such_map.hdr"), "{e}");

    let dir = std::env::temp_dir().join(format!("envmap_input_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases: [(&str, &[u8]); 4] = [
        ("garbage.hdr", b"this is not an HDR file\n\x00\x01\x02"),
        ("empty.hdr", b""),
        (
            "truncated.hdr",
            b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 256 +X 512\n\x02\x02",
        ),
        ("png.hdr", b"\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR"),
    ];
    for (name, bytes) in cases {
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        let e = EnvMap::load_hdr(&p).unwrap_err();
        assert_eq!(e.field(), "envmap.path", "{name}");
        assert!(e.to_string().contains(name), "{name}: {e}");
        println!("{name}: {e}");
    }
    // A round trip through the encoder keeps the size and the values within RGBE's 1 %.
    let env = EnvMap::pattern(32, 16);
    let p = dir.join("pattern.hdr");
    env.write_hdr(&p).unwrap();
    let back = EnvMap::load_hdr(&p).unwrap();
    assert_eq!((back.width(), back.height()), (32, 16));
    for (a, b) in env.texels().iter().zip(back.texels()) {
        for c in 0..3 {
            assert!(close(a[c], b[c], 0.01), "{a:?} {b:?}");
        }
    }
    let e = env.write_hdr(dir.join("no_dir/x.hdr")).unwrap_err();
    assert_eq!(e.field(), "envmap.path");
    std::fs::remove_dir_all(&dir).ok();
}

/// Regenerate the repo copies from the 1024 × 512 originals (needs /work/shared):
/// `cargo test --test envmap_input -- --ignored regenerate`.
#[test]
#[ignore]
fn regenerate_repo_envmaps() {
    for name in ["venice_sunset", "st_fagans_interior"] {
        let src = format!("/work/shared/data/envmaps/{name}_1k.hdr");
        let env = EnvMap::load_hdr(&src).unwrap();
        assert_eq!((env.width(), env.height()), (1024, 512));
        let small = env.downsample(2).unwrap();
        let dst = repo_envmap(&format!("{name}_512.hdr"));
        small.write_hdr(&dst).unwrap();
        let max = |e: &EnvMap| e.texels().iter().flatten().fold(0.0f64, |a, &b| a.max(b));
        println!(
            "{src} (mean {:.4?}, max {:.1}) → {} (mean {:.4?}, max {:.1})",
            env.mean(),
            max(&env),
            dst.display(),
            small.mean(),
            max(&small)
        );
    }
}
