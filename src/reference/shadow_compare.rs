//! f64 twin of `shadow_compare`: an unquantised depth map (f64 per texel, cleared to
//! 1.0), depth-pass writes keeping the exact minimum, and the exact LEQUAL test
//! frag − bias ≤ stored. Out-of-map lookups are lit and out-of-map writes dropped,
//! as in the hardware.

/// The shadow test on depths in any one unit: lit ⇔ frag − bias ≤ stored.
/// NaN in any operand gives `false` (never a NaN output).
pub fn lit(frag: f64, bias: f64, stored: f64) -> bool {
    frag - bias <= stored
}

/// An exact depth map of `width × height` texels.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowMapRef {
    width: u32,
    height: u32,
    depth: Vec<f64>,
}

impl ShadowMapRef {
    /// A map cleared to the far plane (1.0).
    pub fn new(width: u32, height: u32) -> Self {
        ShadowMapRef {
            width,
            height,
            depth: vec![1.0; width as usize * height as usize],
        }
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    fn index(&self, x: i64, y: i64) -> Option<usize> {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            None
        } else {
            Some(y as usize * self.width as usize + x as usize)
        }
    }

    /// Every texel back to 1.0.
    pub fn clear(&mut self) {
        self.depth.fill(1.0);
    }

    /// Depth pass: keep the minimum; returns whether `z` was stored (z < old).
    /// Out of map: dropped. A NaN `z` is never stored.
    pub fn write(&mut self, x: i64, y: i64, z: f64) -> bool {
        match self.index(x, y) {
            Some(i) if z < self.depth[i] => {
                self.depth[i] = z;
                true
            }
            _ => false,
        }
    }

    /// The stored depth at (x, y), or None out of the map.
    pub fn stored(&self, x: i64, y: i64) -> Option<f64> {
        self.index(x, y).map(|i| self.depth[i])
    }

    /// Lookup pass: lit ⇔ frag − bias ≤ stored; out of map: lit.
    pub fn test(&self, x: i64, y: i64, frag: f64, bias: f64) -> bool {
        match self.stored(x, y) {
            Some(s) => lit(frag, bias, s),
            None => true,
        }
    }
}
