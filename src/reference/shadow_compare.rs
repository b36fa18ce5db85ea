//! f64 twin of `shadow_compare`: an unquantised depth map (f64 per texel, cleared to
//! 1.0), depth-pass writes keeping the exact minimum, and the exact test
//! (frag − bias) OP stored under one of the eight compare functions (LEQUAL by
//! default). Out-of-map lookups compare the fragment, clamped to the far plane,
//! against the far plane (1.0); out-of-map writes are dropped, as in the hardware.
//! Depth texels (16-bit words, 32-bit words with the depth in the high 24 bits) are
//! read as the exact fraction of the far plane their depth code stands for.

/// A depth compare function, by its GL name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Compare {
    Never,
    Less,
    Equal,
    Lequal,
    Greater,
    Notequal,
    Gequal,
    Always,
}

impl Compare {
    /// All eight, in GL's order (GL_NEVER … GL_ALWAYS).
    pub const ALL: [Compare; 8] = [
        Compare::Never,
        Compare::Less,
        Compare::Equal,
        Compare::Lequal,
        Compare::Greater,
        Compare::Notequal,
        Compare::Gequal,
        Compare::Always,
    ];

    /// a OP b on exact values. A NaN operand gives `false` (never a NaN output).
    pub fn eval(self, a: f64, b: f64) -> bool {
        if a.is_nan() || b.is_nan() {
            return false;
        }
        match self {
            Compare::Never => false,
            Compare::Less => a < b,
            Compare::Equal => a == b,
            Compare::Lequal => a <= b,
            Compare::Greater => a > b,
            Compare::Notequal => a != b,
            Compare::Gequal => a >= b,
            Compare::Always => true,
        }
    }
}

/// How a depth texel word is read (the twin of the unit's `texel` field).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Texel {
    /// The word is an n-bit unorm depth code.
    Unorm(u32),
    /// A 16-bit unorm depth.
    Z16,
    /// A 32-bit word: a 24-bit unorm depth above an 8-bit stencil.
    Z24S8,
}

/// The depth in [0, 1] a texel word stands for: its depth code over the far-plane
/// code 2ⁿ − 1 (bits of the word above the format are ignored).
pub fn texel_depth(format: Texel, word: u32) -> f64 {
    let (code, n) = match format {
        Texel::Unorm(n) => (word as u64 & ((1u64 << n.min(32)) - 1), n.min(32)),
        Texel::Z16 => (word as u64 & 0xffff, 16),
        Texel::Z24S8 => ((word >> 8) as u64, 24),
    };
    code as f64 / ((1u64 << n) - 1) as f64
}

/// The shadow test on depths in any one unit: lit ⇔ frag − bias ≤ stored.
/// NaN in any operand gives `false` (never a NaN output).
pub fn lit(frag: f64, bias: f64, stored: f64) -> bool {
    lit_with(Compare::Lequal, frag, bias, stored)
}

/// The shadow test under `func`: lit ⇔ (frag − bias) OP stored.
pub fn lit_with(func: Compare, frag: f64, bias: f64, stored: f64) -> bool {
    func.eval(frag - bias, stored)
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
        self.test_with(Compare::Lequal, x, y, frag, bias)
    }

    /// Lookup pass under `func`: lit ⇔ (frag − bias) OP stored; out of map,
    /// (min(frag, 1) − bias) OP 1 (the border is the far plane).
    pub fn test_with(&self, func: Compare, x: i64, y: i64, frag: f64, bias: f64) -> bool {
        match self.stored(x, y) {
            Some(s) => lit_with(func, frag, bias, s),
            None => lit_with(func, frag.min(1.0), bias, 1.0),
        }
    }
}
