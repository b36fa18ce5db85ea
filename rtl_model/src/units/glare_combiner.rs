//! glare_combiner — adds a modulator's RGB luminance into the framebuffer with
//! saturation: out_c = min(fb_c + lum_c, 2^fb_bits − 1).
//!
//! Widths: fb u(fb_bits) (default 8), lum u(lum_bits) (default 12); the sum is
//! u(max(fb_bits, lum_bits) + 1), clamped to u(fb_bits). One framebuffer
//! read-modify-write of the RGB pixel (3·fb_bits) per input is counted.
//! Latency 1, II 1.

use crate::cost::{prim, Cells, Cost};
use crate::counters::Counters;
use crate::error::{check_range, ConfigError};
use crate::memory::framebuffer_rmw;
use crate::unit::{Signal, Timing, Unit, Width};
use crate::unorm::max_code;
use serde::{Deserialize, Serialize};

/// Config: framebuffer channel width and luminance width.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct GlareCombinerConfig {
    /// Framebuffer channel width (1 ..= 16, default 8).
    pub fb_bits: u32,
    /// Luminance input width (1 ..= 16, default 12).
    pub lum_bits: u32,
}

impl Default for GlareCombinerConfig {
    fn default() -> Self {
        GlareCombinerConfig {
            fb_bits: 8,
            lum_bits: 12,
        }
    }
}

impl GlareCombinerConfig {
    /// Validate; errors name `glare_combiner.<field>`.
    pub fn build(&self) -> Result<GlareCombiner, ConfigError> {
        check_range("glare_combiner.fb_bits", self.fb_bits as u64, 1, 16)?;
        check_range("glare_combiner.lum_bits", self.lum_bits as u64, 1, 16)?;
        Ok(GlareCombiner { cfg: *self })
    }
}

/// The validated combiner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GlareCombiner {
    cfg: GlareCombinerConfig,
}

/// One pixel: the framebuffer RGB and the luminance RGB to add.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct CombineIn {
    /// Framebuffer RGB, codes of `fb_bits` bits (masked to the wire).
    pub fb: [u32; 3],
    /// Luminance RGB to add, codes of `lum_bits` bits (masked to the wire).
    pub lum: [u32; 3],
}

impl GlareCombiner {
    /// GeForce default: 8-bit framebuffer, 12-bit luminance.
    pub fn geforce() -> Self {
        GlareCombiner {
            cfg: GlareCombinerConfig::default(),
        }
    }

    /// The config the combiner was built from.
    pub fn config(&self) -> GlareCombinerConfig {
        self.cfg
    }

    /// The combinational datapath (no memory accounting): inputs masked to their wires.
    #[inline]
    pub fn apply(&self, input: &CombineIn, ctr: &mut Counters) -> [u32; 3] {
        let fmax = max_code(self.cfg.fb_bits);
        let lmax = max_code(self.cfg.lum_bits);
        let mut out = [0u32; 3];
        for (o, (f, l)) in out.iter_mut().zip(input.fb.iter().zip(&input.lum)) {
            // u(fb) + u(lum) → u(max(fb, lum) + 1) ≤ 17 bits.
            let s = (f & fmax) + (l & lmax);
            *o = if s > fmax {
                ctr.saturations += 1;
                fmax
            } else {
                s
            };
        }
        out
    }
}

impl Unit for GlareCombiner {
    type In = CombineIn;
    type Out = [u32; 3];
    type State = ();

    fn name(&self) -> &'static str {
        "glare_combiner"
    }

    fn kernel(&self, _: &mut (), input: &CombineIn, ctr: &mut Counters) -> [u32; 3] {
        framebuffer_rmw(ctr, 3 * self.cfg.fb_bits);
        self.apply(input, ctr)
    }

    fn timing(&self) -> Timing {
        Timing { latency: 1, ii: 1 }
    }

    fn cost(&self) -> Cost {
        let f = self.cfg.fb_bits;
        let l = self.cfg.lum_bits;
        let w = f.max(l);
        Cost::default()
            .part("3 × adders u(max(fb,lum))", prim::adder(w) * 3.0)
            .part(
                "3 × overflow detect (OR of bits above fb) + clamp OR",
                Cells {
                    or2: (3 * (w + 1 - f) + 3 * f) as f64,
                    ..Cells::default()
                },
            )
            .part("output register 3·fb", prim::register(3 * f))
    }

    fn widths(&self) -> Vec<Width> {
        vec![
            Width {
                name: "fb_bits",
                bits: self.cfg.fb_bits,
            },
            Width {
                name: "lum_bits",
                bits: self.cfg.lum_bits,
            },
        ]
    }

    fn in_signals(&self, i: &CombineIn) -> Vec<Signal> {
        let (f, l) = (self.cfg.fb_bits, self.cfg.lum_bits);
        let fm = |x: u32| (x & max_code(f)) as u64;
        let lm = |x: u32| (x & max_code(l)) as u64;
        vec![
            Signal::new("fb_r", f, fm(i.fb[0])),
            Signal::new("fb_g", f, fm(i.fb[1])),
            Signal::new("fb_b", f, fm(i.fb[2])),
            Signal::new("lum_r", l, lm(i.lum[0])),
            Signal::new("lum_g", l, lm(i.lum[1])),
            Signal::new("lum_b", l, lm(i.lum[2])),
        ]
    }

    fn out_signals(&self, o: &[u32; 3]) -> Vec<Signal> {
        let f = self.cfg.fb_bits;
        vec![
            Signal::new("r", f, o[0] as u64),
            Signal::new("g", f, o[1] as u64),
            Signal::new("b", f, o[2] as u64),
        ]
    }
}
