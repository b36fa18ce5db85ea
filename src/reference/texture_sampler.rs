//! f64 twin of `texture_sampler`: the ideal GL texture lookup on the same integer
//! texels (as f64 codes), with exact real-valued filter weights and no output
//! rounding. So the unit differs from it only by weight quantisation and the final
//! rounding.
//!
//! Conventions (the same as the unit, stated independently of it):
//! * coordinates are in texel space: u = s · size (normalised s, t, r times the size);
//! * nearest: i = floor(u);
//! * linear: p = u − ½, i0 = floor(p), a = p − i0 ∈ [0, 1), i1 = i0 + 1, weights
//!   (1 − a, a) per axis, multiplied across axes (bilinear / trilinear);
//! * clamp to edge: clamp(i, 0, size − 1); repeat: i mod size (floored).
//!
//! Never NaN: a non-finite coordinate is read as 0, huge ones are limited to ±2^40
//! texels (far beyond any repeat that matters), missing texels read as 0.

/// Filter of the twin.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    Nearest,
    Linear,
}

/// Address mode of one axis of the twin.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Address {
    Clamp,
    Wrap,
}

/// A texture held as f64 codes, sampled ideally.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureRef {
    dims: usize,
    size: [usize; 3],
    channels: usize,
    /// Texel (x, y, z) channel c at ((z·h + y)·w + x)·channels + c.
    texels: Vec<f64>,
    filter: Filter,
    address: [Address; 3],
}

impl TextureRef {
    /// `dims` is clamped to 1 ..= 3, `channels` to 1 ..= 4, sizes of unused axes are
    /// taken as 1 and zero sizes as 1 (the twin never fails; the unit validates).
    pub fn new(
        dims: usize,
        size: [usize; 3],
        channels: usize,
        texels: Vec<f64>,
        filter: Filter,
        address: [Address; 3],
    ) -> Self {
        let dims = dims.clamp(1, 3);
        let mut s = [1usize; 3];
        for k in 0..dims {
            s[k] = size[k].max(1);
        }
        TextureRef {
            dims,
            size: s,
            channels: channels.clamp(1, 4),
            texels,
            filter,
            address,
        }
    }

    /// From integer codes.
    pub fn from_codes(
        dims: usize,
        size: [usize; 3],
        channels: usize,
        codes: &[u32],
        filter: Filter,
        address: [Address; 3],
    ) -> Self {
        let texels = codes.iter().map(|&c| c as f64).collect();
        Self::new(dims, size, channels, texels, filter, address)
    }

    pub fn size(&self) -> [usize; 3] {
        self.size
    }

    /// Stored code of texel (x, y, z), channel c (0 when absent).
    pub fn texel(&self, x: usize, y: usize, z: usize, c: usize) -> f64 {
        let [w, h, _] = self.size;
        let i = ((z * h + y) * w + x) * self.channels + c;
        self.texels.get(i).copied().unwrap_or(0.0)
    }

    fn address(&self, k: usize, i: i64) -> usize {
        let n = self.size[k] as i64;
        match self.address[k] {
            Address::Clamp => i.clamp(0, n - 1) as usize,
            Address::Wrap => i.rem_euclid(n) as usize,
        }
    }

    /// Sample at texel-space coordinates `u` (unused axes ignored); returns the
    /// filtered codes per channel (unused channels 0).
    #[allow(clippy::needless_range_loop)] // per-axis loops over parallel arrays
    pub fn sample(&self, u: [f64; 3]) -> [f64; 4] {
        let lim = 2f64.powi(40);
        let mut uu = [0.0f64; 3];
        for k in 0..self.dims {
            uu[k] = if u[k].is_finite() {
                u[k].clamp(-lim, lim)
            } else {
                0.0
            };
        }
        let mut out = [0.0f64; 4];
        match self.filter {
            Filter::Nearest => {
                let mut idx = [0usize; 3];
                for k in 0..self.dims {
                    idx[k] = self.address(k, uu[k].floor() as i64);
                }
                for (c, o) in out.iter_mut().enumerate().take(self.channels) {
                    *o = self.texel(idx[0], idx[1], idx[2], c);
                }
            }
            Filter::Linear => {
                let mut i01 = [[0usize; 2]; 3];
                let mut w01 = [[1.0f64, 0.0]; 3];
                for k in 0..self.dims {
                    let p = uu[k] - 0.5;
                    let i0 = p.floor();
                    let a = p - i0;
                    w01[k] = [1.0 - a, a];
                    let i0 = i0 as i64;
                    i01[k] = [self.address(k, i0), self.address(k, i0 + 1)];
                }
                for corner in 0..(1usize << self.dims) {
                    let mut idx = [0usize; 3];
                    let mut w = 1.0;
                    for k in 0..self.dims {
                        let b = (corner >> k) & 1;
                        idx[k] = i01[k][b];
                        w *= w01[k][b];
                    }
                    for (c, o) in out.iter_mut().enumerate().take(self.channels) {
                        *o += w * self.texel(idx[0], idx[1], idx[2], c);
                    }
                }
            }
        }
        out
    }

    /// Sample at normalised coordinates (s, t, r): u = s · size per axis.
    pub fn sample_normalized(&self, s: [f64; 3]) -> [f64; 4] {
        let mut u = [0.0; 3];
        for k in 0..self.dims {
            u[k] = texel_coord(s[k], self.size[k]);
        }
        self.sample(u)
    }
}

/// Texel-space coordinate of normalised `s` on an axis of `size` texels.
pub fn texel_coord(s: f64, size: usize) -> f64 {
    s * size as f64
}
