//! f64 twin of `glare_combiner`: the real sum of framebuffer value and luminance,
//! clipped at the framebuffer's largest value (both in framebuffer codes).

/// min(fb + lum, fb_max) per channel.
pub fn glare_combiner(fb: [f64; 3], lum: [f64; 3], fb_max: f64) -> [f64; 3] {
    [0, 1, 2].map(|c| (fb[c] + lum[c]).min(fb_max))
}
