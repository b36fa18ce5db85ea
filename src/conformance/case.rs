//! What a conformance suite is made of: a [`Suite`] of [`Case`]s (one capture each),
//! each with its compared [`Region`]s and the model's [`Prediction`] there. The suites
//! (`blend.rs`, `combiner.rs`, …) and the runner (`run.rs`) import this file; it
//! imports none of them.

/// A rectangle of a capture, in pixels (x right, y down from the top-left corner).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    pub x: u32,
    pub y: u32,
    pub w: u32,
    pub h: u32,
}

impl Rect {
    pub const fn new(x: u32, y: u32, w: u32, h: u32) -> Rect {
        Rect { x, y, w, h }
    }

    /// The rectangle shrunk by `m` pixels on every side (patch edges are rasterisation
    /// and filtering territory, not the unit under test).
    pub const fn inset(self, m: u32) -> Rect {
        Rect {
            x: self.x + m,
            y: self.y + m,
            w: self.w.saturating_sub(2 * m),
            h: self.h.saturating_sub(2 * m),
        }
    }

    pub fn pixels(&self) -> usize {
        self.w as usize * self.h as usize
    }
}

/// What the model predicts inside a region: RGB, 8 bits per channel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Prediction {
    /// One colour for every pixel of the region.
    Flat([u8; 3]),
    /// One colour per pixel, row-major over the region (w · h entries).
    PerPixel(Vec<[u8; 3]>),
}

impl Prediction {
    /// The predicted colour of the region's pixel `i` (row-major).
    pub fn at(&self, i: usize) -> [u8; 3] {
        match self {
            Prediction::Flat(c) => *c,
            Prediction::PerPixel(v) => v[i],
        }
    }
}

/// One compared region of a capture.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Region {
    /// Unique within its image ("bias/rgb", "SUB/dst_checker_dark").
    pub name: String,
    /// The feature the region exercises: mismatches are reported grouped by it
    /// ("combiner bias", "blend SUB", "shadow compare LEQUAL").
    pub feature: String,
    pub rect: Rect,
    pub predicted: Prediction,
}

/// One hardware test: one capture and its regions.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Case {
    /// The capture's file name inside the suite's folder ("CombinerOps.png").
    pub image: String,
    pub regions: Vec<Region>,
}

/// Which chip's behaviour the units follow where the GeForce2 (NV15) default and the
/// NV2A differ: the one mapping from a chip to its units' modes
/// ([`rtl_model::chip_preset`]), which a scene's `chip` field selects too.
pub use rtl_model::chip_preset::ChipPreset as Chip;

/// A hardware test suite: a folder of captures and the cases that describe them.
pub struct Suite {
    /// The folder under `results/` in the captures' repository ("Combiner").
    pub name: &'static str,
    /// The test program's source in nxdk_pgraph_tests the cases were read from.
    pub source: &'static str,
    /// Every case of the suite, predicted with the units in the given chip's modes.
    pub cases: fn(Chip) -> Vec<Case>,
}
