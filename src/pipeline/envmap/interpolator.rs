//! The render's one polygon interpolator: n, e, λ, z ([`RENDER_ATTRS`]) and, with a
//! roughness texture, also (u, v) ([`RENDER_ATTRS_TEXTURE`]); what those 2 channels cost
//! ([`texcoord_channels_cost`]). See [`super::roughness`]'s module notes.

use rtl_model::error::ConfigError;
use rtl_model::units::polygon_interpolator::{PolygonInterpolator, PolygonInterpolatorConfig};
use rtl_model::UnitSummary;

/// Fraction bits of the interpolator's attribute outputs (s16.16).
pub(super) const ATTR_FRAC: u32 = 16;
/// Attributes the render's interpolator carries with per-vertex λ: n (3), e (3), λ, z.
pub const RENDER_ATTRS: u32 = 8;
/// With [`LambdaSource::Texture`](super::roughness::LambdaSource::Texture): the same 8
/// plus the texture coordinate (u, v), in the same interpolator.
pub const RENDER_ATTRS_TEXTURE: u32 = RENDER_ATTRS + 2;

/// The render's polygon interpolator carrying `attrs` attributes (GeForce defaults:
/// s16.16 attributes, s20.24 accumulators; outputs s16.16).
pub fn render_interpolator(attrs: u32) -> Result<PolygonInterpolator, ConfigError> {
    PolygonInterpolatorConfig {
        attrs,
        out_int_bits: 16,
        out_frac_bits: ATTR_FRAC,
        ..PolygonInterpolatorConfig::default()
    }
    .build()
}

/// The elaboration report's row for (u, v) with
/// [`LambdaSource::Texture`](super::roughness::LambdaSource::Texture): the
/// interpolator's 2 more attribute channels, summary from [`texcoord_channels_cost`].
pub const TEXCOORD_CHANNELS: &str = "polygon_interpolator +2 attributes (u, v): 10, not 8";

/// What carrying (u, v) costs the render's interpolator: gates, RAM bits and the
/// breakdown are the INCREMENT, the [`RENDER_ATTRS_TEXTURE`]-attribute config's minus
/// the [`RENDER_ATTRS`]-attribute config's (only the parts that grow are kept: two more
/// attribute accumulators, output rounders and output register bits; the sequenced
/// set-up datapath is shared, it takes 3 more clocks per attribute); latency, II and
/// widths are the 10-attribute unit's (the same latency and II as with 8).
pub fn texcoord_channels_cost() -> Result<UnitSummary, ConfigError> {
    let with = UnitSummary::of(&render_interpolator(RENDER_ATTRS_TEXTURE)?);
    let without = UnitSummary::of(&render_interpolator(RENDER_ATTRS)?);
    let breakdown = with
        .breakdown
        .iter()
        .zip(&without.breakdown)
        .map(|((n1, g1), (n0, g0))| {
            let name = if n1 == n0 {
                format!("{n1}: {RENDER_ATTRS_TEXTURE} − {RENDER_ATTRS} attributes")
            } else {
                format!("{n1} − {n0}")
            };
            (name, g1 - g0)
        })
        .filter(|(_, d)| *d != 0.0)
        .collect();
    Ok(UnitSummary {
        gates_nand2: with.gates_nand2 - without.gates_nand2,
        ram_bits: with.ram_bits - without.ram_bits,
        breakdown,
        ..with
    })
}
