//! `[rounding]`: the type of the scene's choice where GL leaves the rounding to the
//! implementation ([`GlRounding`]; `limits.rs` re-exports it and reads a scene's
//! choice, `GlRounding::of`). Below the scene format, which holds one.

use super::bounds::onto;
use rtl_model::error::ConfigError;
use rtl_model::units::modulate::{ChainRounding, ModulateChain, ModulateMode};
use rtl_model::units::texture_sampler::{FilterRounding, TextureSamplerConfig, WeightRounding};
use serde::{Deserialize, Serialize};

/// `[rounding]`: where GL leaves the rounding to the implementation, which choice the
/// units make (docs/shading.md, "The GL oracle"). The defaults are the GeForce-style
/// datapath; `chain = "fused"`, `filter = "successive_lerps"`, `weight =
/// "round_half_even"` together are Mesa's llvmpipe (bit-exact against OSMesa:
/// tests/modulate_mesa.rs, tests/texture_sampler_mesa.rs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GlRounding {
    /// A chain of MODULATE stages (the shading pipeline's factor textures × constant
    /// colour): `per_stage` (default, an 8-bit register between stages) or `fused`.
    pub chain: ChainRounding,
    /// Bilinear filtering (shafts F, h and light-map textures; shading factor
    /// textures): `product_weights` (default) or `successive_lerps`.
    pub filter: FilterRounding,
    /// Sub-texel fraction → filter weight: `round` (default, ties up),
    /// `round_half_even` or `truncate`.
    pub weight: WeightRounding,
}

impl Default for GlRounding {
    fn default() -> Self {
        GlRounding {
            chain: ChainRounding::PerStage,
            filter: FilterRounding::ProductWeights,
            weight: WeightRounding::Round,
        }
    }
}

impl GlRounding {
    /// Mesa's llvmpipe in all three places.
    pub fn mesa_llvmpipe() -> Self {
        GlRounding {
            chain: ChainRounding::Fused,
            filter: FilterRounding::SuccessiveLerps,
            weight: WeightRounding::RoundHalfEven,
        }
    }

    /// `cfg` with this choice of filter and weight rounding.
    pub fn sampler(&self, cfg: TextureSamplerConfig) -> TextureSamplerConfig {
        TextureSamplerConfig {
            filter_rounding: self.filter,
            weight_rounding: self.weight,
            ..cfg
        }
    }

    /// The modulate chain of `bits`-bit exact stages with this chain rounding (errors
    /// name `rounding.chain`, or `modulate.bits`: the width is the pipeline's).
    pub fn chain(&self, bits: u32) -> Result<ModulateChain, ConfigError> {
        ModulateChain::new(bits, ModulateMode::Exact, self.chain)
            .map_err(onto(&[("modulate.chain_rounding", "rounding.chain")]))
    }
}
