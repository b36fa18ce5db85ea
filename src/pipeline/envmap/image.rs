//! The render's 8-bit RGB [`Image`] with the object's coverage, and the [`ErrorStats`] of
//! rendered − truth over the object's pixels.

use std::path::Path;

use rtl_model::error::ConfigError;

/// An 8-bit RGB image with the object's coverage.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    /// Row-major, y down.
    pub pixels: Vec<[u8; 3]>,
    /// True where the object is (the pixels the statistics use).
    pub mask: Vec<bool>,
}

impl Image {
    pub(super) fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Image {
            width,
            height,
            pixels: vec![[0; 3]; n],
            mask: vec![false; n],
        }
    }

    pub fn get(&self, x: u32, y: u32) -> [u8; 3] {
        self.pixels[(y * self.width + x) as usize]
    }

    pub fn covered(&self, x: u32, y: u32) -> bool {
        self.mask[(y * self.width + x) as usize]
    }

    /// Object pixels.
    pub fn coverage(&self) -> usize {
        self.mask.iter().filter(|m| **m).count()
    }

    /// Write as an 8-bit RGB PNG (errors name "envmap_render.path").
    pub fn write_png(&self, path: impl AsRef<Path>) -> Result<(), ConfigError> {
        let path = path.as_ref();
        let buf: Vec<u8> = self.pixels.iter().flatten().copied().collect();
        // Atomically (`report::atomic`): the temporary file keeps the `.png`.
        crate::report::atomic::write_atomically(path, |tmp| {
            image::save_buffer(
                tmp,
                &buf,
                self.width,
                self.height,
                image::ExtendedColorType::Rgb8,
            )
            .map_err(|e| e.to_string())
        })
        .map_err(|e| {
            ConfigError::invalid(
                "envmap_render.path",
                &format!("`{}`: cannot write PNG: {e}", path.display()),
            )
        })
    }

    /// |a − b| × `gain` (clamped) on the object pixels of `self`, black elsewhere: a
    /// difference image for looking at.
    pub fn diff(&self, other: &Image, gain: f64) -> Image {
        let mut d = Image::new(self.width, self.height);
        for k in 0..self.pixels.len().min(other.pixels.len()) {
            if self.mask[k] {
                d.mask[k] = true;
                for c in 0..3 {
                    let v = (self.pixels[k][c] as f64 - other.pixels[k][c] as f64).abs() * gain;
                    d.pixels[k][c] = v.clamp(0.0, 255.0).round() as u8;
                }
            }
        }
        d
    }

    /// Images side by side (heights must match; shorter ones are padded black).
    pub fn hstack(images: &[&Image]) -> Image {
        let w: u32 = images.iter().map(|i| i.width).sum();
        let h = images.iter().map(|i| i.height).max().unwrap_or(0);
        let mut out = Image::new(w.max(1), h.max(1));
        let mut x0 = 0;
        for im in images {
            for y in 0..im.height {
                for x in 0..im.width {
                    let k = (y * out.width + x0 + x) as usize;
                    out.pixels[k] = im.get(x, y);
                    out.mask[k] = im.covered(x, y);
                }
            }
            x0 += im.width;
        }
        out
    }
}

/// Error statistics of Δ = rendered − truth over the object's pixels (8-bit levels).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ErrorStats {
    pub pixels: usize,
    /// Mean of |Δ| per channel.
    pub mean: [f64; 3],
    /// Population variance of |Δ| per channel.
    pub var: [f64; 3],
    /// Mean of Δ (signed) per channel.
    pub mean_signed: [f64; 3],
    /// Largest |Δ| per channel.
    pub max: [f64; 3],
}

impl ErrorStats {
    /// Statistics of `img` − `truth` over `img`'s object pixels (all zero if none).
    pub fn of(img: &Image, truth: &Image) -> ErrorStats {
        Self::of_masked(img, truth, &img.mask)
    }

    /// Statistics of `img` − `truth` over the pixels where `mask` is true (all zero if
    /// none; a short mask leaves the rest out).
    pub fn of_masked(img: &Image, truth: &Image, mask: &[bool]) -> ErrorStats {
        let mut s = ErrorStats::default();
        let mut sum = [0.0; 3];
        let mut sum2 = [0.0; 3];
        let mut sums = [0.0; 3];
        let n = img.pixels.len().min(truth.pixels.len());
        for (k, _) in mask.iter().take(n).enumerate().filter(|(_, m)| **m) {
            s.pixels += 1;
            for c in 0..3 {
                let d = img.pixels[k][c] as f64 - truth.pixels[k][c] as f64;
                sum[c] += d.abs();
                sum2[c] += d * d;
                sums[c] += d;
                s.max[c] = s.max[c].max(d.abs());
            }
        }
        if s.pixels > 0 {
            let n = s.pixels as f64;
            for c in 0..3 {
                s.mean[c] = sum[c] / n;
                s.var[c] = (sum2[c] / n - s.mean[c] * s.mean[c]).max(0.0);
                s.mean_signed[c] = sums[c] / n;
            }
        }
        s
    }

    pub fn is_finite(&self) -> bool {
        self.mean
            .iter()
            .chain(&self.var)
            .chain(&self.mean_signed)
            .chain(&self.max)
            .all(|v| v.is_finite())
    }
}
