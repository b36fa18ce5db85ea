//! The built-in scene through every unit, against its whole-image f64 reference, and
//! its determinism.

use glare_pipeline::pipeline::test_scene::{render, HEIGHT, WIDTH};
use glare_pipeline::reference::test_scene::render_reference;

#[test]
fn render_is_deterministic() {
    let (a, ca) = render().unwrap();
    let (b, cb) = render().unwrap();
    assert_eq!(a, b);
    assert_eq!(format!("{ca:?}"), format!("{cb:?}"));
}

#[test]
fn render_matches_the_f64_reference() {
    let (fb, ctr) = render().unwrap();
    let reference = render_reference();
    let (mut n, mut sum, mut far, mut missed) = (0u64, 0.0f64, 0u64, 0u64);
    let mut lit_sum = 0.0;
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let hw = fb.pixel(x, y);
            match reference[(y * WIDTH + x) as usize] {
                None => {
                    // Uncovered pixels stay black (the floor is the only geometry).
                    if hw[..3] != [0, 0, 0] {
                        missed += 1;
                    }
                }
                Some(r) => {
                    n += 1;
                    for c in 0..3 {
                        let d = (hw[c] as f64 - r[c]).abs();
                        sum += d;
                        if d > 16.0 {
                            far += 1;
                        }
                    }
                    lit_sum += r[0];
                }
            }
        }
    }
    let mean = sum / (3 * n) as f64;
    println!("covered {n}, mean |Δ| {mean:.3} levels, channels off by > 16: {far}, coverage mismatches {missed}");
    // Coverage: the rasteriser's pixel-centre rule against the exact ray–floor test;
    // only pixels whose centre lies within the vertex quantisation of the edge differ.
    assert!(
        missed as f64 <= 0.01 * (WIDTH * HEIGHT) as f64,
        "{missed} pixels differ in coverage"
    );
    assert!(n.abs_diff(ctr.covered_pixels) as f64 <= 0.01 * n as f64);
    // The scene is lit (not a black or saturated image).
    let mean_red = lit_sum / n as f64;
    assert!(mean_red > 20.0 && mean_red < 200.0, "mean red {mean_red}");
    // Differences come from 8-bit rounding along the chain (a few levels), per-vertex
    // (Gouraud) Lambert against per-pixel, and the 128² shadow map's edges: the mean
    // stays within 2 levels and only shadow-edge pixels are far off.
    assert!(mean < 2.0, "mean |Δ| = {mean}");
    assert!(
        (far as f64) < 0.02 * (3 * n) as f64,
        "{far} channels off by > 16 levels"
    );
}
