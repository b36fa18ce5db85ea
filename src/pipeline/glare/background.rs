//! The picture the glare is added to (fb codes): black, a sky gradient, a leaf
//! canopy, or the picture earlier passes of the frame drew (the scene's lights and
//! objects through the light-shafts pipeline), handed over as a framebuffer.

use super::host::glare_of;
use crate::report::image_out::Framebuffer;
use crate::scene::format::Scene;
use crate::scene::glare::Background;
use rand::{Rng, SeedableRng};
use rtl_model::{ConfigError, Counters};
use std::collections::BTreeMap;

fn code(v: f64, max: u32) -> u32 {
    (v.clamp(0.0, 1.0) * max as f64).round() as u32
}

/// The background in framebuffer codes (RGB), row-major.
pub fn base_image(
    scene: &Scene,
    _ctr: &mut BTreeMap<String, Counters>,
) -> Result<Vec<[u32; 3]>, ConfigError> {
    let g = glare_of(scene)?;
    let (w, h) = (scene.image.width, scene.image.height);
    let max = rtl_model::unorm::max_code(g.hw.fb_bits);
    let n = (w * h) as usize;
    Ok(match &g.background {
        Background::Black => vec![[0; 3]; n],
        // The gradient is a function of the row alone: one code triple per row.
        Background::Sky { top, bottom } => (0..h)
            .flat_map(|y| {
                let t = y as f64 / (h.max(2) - 1) as f64;
                let rgb = [0, 1, 2].map(|c| code(top[c] * (1.0 - t) + bottom[c] * t, max));
                std::iter::repeat_n(rgb, w as usize)
            })
            .collect(),
        Background::Canopy { leaves, sky, leaf } => {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(scene.seed ^ 0x1eaf);
            let discs: Vec<(f64, f64, f64, f64)> = (0..*leaves)
                .map(|_| {
                    (
                        rng.random::<f64>() * w as f64,
                        rng.random::<f64>() * h as f64,
                        (0.02 + 0.05 * rng.random::<f64>()) * h as f64,
                        0.6 + 0.4 * rng.random::<f64>(),
                    )
                })
                .collect();
            // Each pixel shows the last disc covering its centre, else the sky:
            // painting the discs in order over the sky leaves the same picture. A
            // disc is tested only on the pixels of its bounding box (a pixel further
            // than a pixel outside it cannot pass the same covering test).
            let sky_code = [0, 1, 2].map(|c| code(sky[c], max));
            let mut img = vec![sky_code; n];
            for d in &discs {
                let span = |c: f64, len: u32| {
                    let lo = (c - d.2 - 1.0).floor().max(0.0) as u32;
                    let hi = ((c + d.2 + 1.0).ceil().max(0.0) as u32).min(len);
                    lo..hi
                };
                let leaf_code = [0, 1, 2].map(|c| code(leaf[c] * d.3, max));
                for py in span(d.1, h) {
                    for px in span(d.0, w) {
                        let (x, y) = (px as f64 + 0.5, py as f64 + 0.5);
                        if (x - d.0).powi(2) + (y - d.1).powi(2) <= d.2 * d.2 {
                            img[(py * w + px) as usize] = leaf_code;
                        }
                    }
                }
            }
            img
        }
        Background::Shafts => {
            // Drawn by the frame's shafts passes, which hand it over (`from_framebuffer`).
            return Err(ConfigError::invalid(
                "glare.background",
                "\"shafts\" is drawn by the frame's shafts passes: render the scene through the frame (`render`), which hands the glare pass its picture",
            ));
        }
    })
}

/// A framebuffer the frame's earlier passes drew (any bit depth), as the glare
/// pass's background at `fb_bits`: each channel widened to 16 bits and narrowed to the
/// glare framebuffer's width, as the hardware would copy it.
pub fn from_framebuffer(fb: &Framebuffer, fb_bits: u32) -> Vec<[u32; 3]> {
    let from = fb.bits;
    fb.data
        .chunks(4)
        .map(|p| {
            [0, 1, 2].map(|c| {
                rtl_model::unorm::narrow(rtl_model::unorm::widen(p[c], from, 16), 16, fb_bits)
            })
        })
        .collect()
}
