//! The glare hardware: its widths (`[glare.hw]`, [`GlareHw`]) and the unit configs
//! they become, built here for both validation and the glare pipeline (the "one source
//! of limits" of `limits.rs`, which re-exports them). Below the glare section, the
//! scene format and `limits.rs`, which import it; it imports none of them.

use super::bounds::onto;
use rtl_model::error::ConfigError;
use rtl_model::fixed_point::{Format, Overflow, Quant};
use rtl_model::units::gaussian_noise::GaussianNoiseConfig;
use rtl_model::units::glare_combiner::GlareCombinerConfig;
use rtl_model::units::luminance_ram::{LumWidths, Radial};
use rtl_model::units::polygon_interpolator::PolygonInterpolatorConfig;
use rtl_model::units::polygon_variable_generator::PolygonVariableGeneratorConfig;
use serde::{Deserialize, Serialize};

/// The glare hardware's widths (a sweep changes them).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GlareHw {
    /// Shape RAM: 2^k cells per side; entry width.
    pub shape_log2: u32,
    pub shape_bits: u32,
    /// Falloff RAM: 2^m cells; entry width.
    pub falloff_log2: u32,
    pub falloff_bits: u32,
    /// Interpolation weight bits in both RAMs.
    pub weight_bits: u32,
    /// Fraction bits of the interpolated (u, v) (the interpolator's output).
    pub coord_frac_bits: u32,
    /// Gaussian noise generator: uniform bits used.
    pub noise_bits: u32,
    /// Framebuffer bits per channel.
    pub fb_bits: u32,
    /// Clock (MHz) and parallel pixel pipes, for the throughput model.
    pub clock_mhz: f64,
    pub pipes: u32,
    /// Radial correction in the luminance modulators' shape RAM (default false):
    /// signed entries sdf/d_max − κ·|(u, v)|, |(u, v)| computed by the datapath.
    pub radial: bool,
}

impl Default for GlareHw {
    fn default() -> Self {
        GlareHw {
            shape_log2: 7,
            shape_bits: 16,
            falloff_log2: 8,
            falloff_bits: 16,
            weight_bits: 8,
            coord_frac_bits: 14,
            noise_bits: 32,
            fb_bits: 8,
            clock_mhz: 300.0,
            pipes: 4,
            radial: false,
        }
    }
}

/// The luminance modulators' widths from `glare.hw`.
pub fn lum_widths(hw: &GlareHw) -> LumWidths {
    LumWidths {
        coord_frac_bits: hw.coord_frac_bits,
        shape_log2: hw.shape_log2,
        shape_bits: hw.shape_bits,
        falloff_log2: hw.falloff_log2,
        falloff_bits: hw.falloff_bits,
        weight_bits: hw.weight_bits,
        radial: Radial {
            on: hw.radial,
            entry_int_bits: Radial::default()
                .entry_int_bits
                .min(hw.shape_bits.saturating_sub(1)),
            ..Radial::default()
        },
        ..LumWidths::default()
    }
}

/// Sub-pixel bits of glare positions (interpolator and generator agree).
pub const GLARE_SUBPIXEL_BITS: u32 = 4;
/// Integer bits of glare positions, with the sign: ±8192 px.
pub const GLARE_COORD_INT_BITS: u32 = 14;
/// Fraction bits of the s2.f attributes the generator hands the interpolator.
pub const GLARE_ATTR_FRAC_BITS: u32 = 14;

/// The glare interpolator: two attributes (u, v), s2.14 in, s2.f out
/// (f = `glare.hw.coord_frac_bits`).
pub fn glare_interpolator(coord_frac_bits: u32) -> PolygonInterpolatorConfig {
    PolygonInterpolatorConfig {
        attrs: 2,
        subpixel_bits: GLARE_SUBPIXEL_BITS,
        coord_int_bits: GLARE_COORD_INT_BITS,
        attr_fmt: Format {
            int_bits: 2,
            frac_bits: GLARE_ATTR_FRAC_BITS,
            signed: true,
        },
        acc_int_bits: 4,
        acc_frac_bits: 24,
        acc_overflow: Overflow::Wrap,
        out_int_bits: 2,
        out_frac_bits: coord_frac_bits,
        out_quant: Quant::Rnd,
        barycentric: None,
    }
}

/// The glare primitives' polygon-variable generator (positions and attributes as the
/// interpolator takes them).
pub fn glare_generator() -> PolygonVariableGeneratorConfig {
    PolygonVariableGeneratorConfig {
        coord_int_bits: GLARE_COORD_INT_BITS,
        subpixel_bits: GLARE_SUBPIXEL_BITS,
        attr_frac_bits: GLARE_ATTR_FRAC_BITS,
        ..PolygonVariableGeneratorConfig::default()
    }
}

/// The flare lines' Gaussian noise generator at `glare.hw.noise_bits`.
pub fn glare_noise(hw: &GlareHw) -> GaussianNoiseConfig {
    GaussianNoiseConfig {
        uniform_bits: hw.noise_bits,
        ..GaussianNoiseConfig::geforce()
    }
}

/// The glare combiner at `glare.hw.fb_bits` and the modulators' luminance width.
pub fn glare_combiner(hw: &GlareHw) -> GlareCombinerConfig {
    GlareCombinerConfig {
        fb_bits: hw.fb_bits,
        lum_bits: lum_widths(hw).out_bits,
    }
}

/// Every unit `glare.hw` configures: the luminance RAM widths (bloom, halo and flare
/// modulators), the noise generator, the combiner. Errors name `hw.<field>` (put
/// `glare.` before them with [`ConfigError::within`]).
pub fn check_glare(hw: &GlareHw) -> Result<(), ConfigError> {
    let lum = [
        "coord_frac_bits",
        "shape_log2",
        "shape_bits",
        "falloff_log2",
        "falloff_bits",
        "weight_bits",
    ]
    .map(|f| (format!("luminance_ram.{f}"), format!("hw.{f}")));
    let lum: Vec<(&str, &str)> = lum.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
    lum_widths(hw)
        .validate("luminance_ram")
        .map_err(onto(&lum))?;
    glare_noise(hw)
        .build()
        .map_err(onto(&[("gaussian_noise.uniform_bits", "hw.noise_bits")]))?;
    glare_combiner(hw)
        .build()
        .map_err(onto(&[("glare_combiner.fb_bits", "hw.fb_bits")]))?;
    Ok(())
}
