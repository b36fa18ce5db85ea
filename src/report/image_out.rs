//! Framebuffers to PNG.

use image::{ImageBuffer, Rgba};
use std::path::Path;

/// An RGBA framebuffer of n-bit channels (n ≤ 16), row-major, top row first.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Framebuffer {
    pub width: u32,
    pub height: u32,
    pub bits: u32,
    /// width · height · 4 channel codes.
    pub data: Vec<u32>,
}

impl Framebuffer {
    pub fn new(width: u32, height: u32, bits: u32) -> Self {
        Framebuffer {
            width,
            height,
            bits,
            data: vec![0; (width * height * 4) as usize],
        }
    }

    pub fn pixel(&self, x: u32, y: u32) -> [u32; 4] {
        let i = ((y * self.width + x) * 4) as usize;
        [
            self.data[i],
            self.data[i + 1],
            self.data[i + 2],
            self.data[i + 3],
        ]
    }

    pub fn set(&mut self, x: u32, y: u32, v: [u32; 4]) {
        let i = ((y * self.width + x) * 4) as usize;
        self.data[i..i + 4].copy_from_slice(&v);
    }

    /// 8-bit RGBA bytes (wider channels rounded to nearest; alpha forced opaque).
    /// The image in 8-bit levels (f64, for error metrics): each RGB code × 255 / full scale.
    pub fn levels(&self) -> Vec<[f64; 3]> {
        let max = rtl_model::unorm::max_code(self.bits) as f64;
        self.data
            .chunks(4)
            .map(|p| [0, 1, 2].map(|c| p[c] as f64 * 255.0 / max))
            .collect()
    }

    pub fn to_rgba8(&self) -> Vec<u8> {
        let max = (1u64 << self.bits) - 1;
        self.data
            .chunks(4)
            .flat_map(|p| {
                let c = |v: u32| ((v as u64 * 255 * 2 + max) / (2 * max)) as u8;
                [c(p[0]), c(p[1]), c(p[2]), 255]
            })
            .collect()
    }

    /// Write as an 8-bit RGBA PNG (atomically: the old file or the whole new one).
    pub fn save_png(&self, path: &Path) -> Result<(), image::ImageError> {
        let img: ImageBuffer<Rgba<u8>, Vec<u8>> =
            ImageBuffer::from_raw(self.width, self.height, self.to_rgba8())
                .expect("buffer size matches");
        // Atomically (`report::atomic`); the temporary file keeps the `.png` the
        // encoder is picked by.
        let mut failed = None;
        crate::report::atomic::write_atomically(path, |tmp| {
            img.save(tmp).map_err(|e| {
                let shown = e.to_string();
                failed = Some(e);
                shown
            })
        })
        .map_err(|e| failed.unwrap_or_else(|| image::ImageError::IoError(std::io::Error::other(e))))
    }
}

/// A grey RGBA image of `size` × `size` levels (row-major; rounded, clamped to
/// 0 ..= 255).
pub fn grey_image(levels: &[f64], size: u32) -> image::RgbaImage {
    image::RgbaImage::from_fn(size, size, |x, y| {
        let v = levels[(y * size + x) as usize].round().clamp(0.0, 255.0) as u8;
        image::Rgba([v, v, v, 255])
    })
}

/// 8-bit PNG of an image in levels.
pub fn levels_png(levels: &[[f64; 3]], width: u32, height: u32, path: &Path) -> Result<(), String> {
    let mut fb = Framebuffer::new(width, height, 8);
    for (i, l) in levels.iter().enumerate() {
        let q = l.map(|v| v.round().clamp(0.0, 255.0) as u32);
        fb.data[i * 4..i * 4 + 4].copy_from_slice(&[q[0], q[1], q[2], 255]);
    }
    fb.save_png(path)
        .map_err(|e| format!("out: {}: {e}", path.display()))
}

/// Write a file atomically (`report::atomic`), creating its directory; a failure names
/// the path.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<(), String> {
    crate::report::atomic::write_bytes(path, bytes).map_err(|e| format!("out: {e}"))
}

/// Check, before any work, that `path` can take a PNG (`report::outputs`): not a
/// directory (say so), a file name ending in `.png`, a parent that is not a file, a
/// place that takes a new file. Errors name `arg` (`out`, `reference`), so a bad
/// `--reference` is never blamed on `--out`.
pub fn check_png_path(arg: &str, path: &Path) -> Result<(), String> {
    crate::report::outputs::check_outputs(&[crate::report::outputs::Output::png(arg, path)])
}
