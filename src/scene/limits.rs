//! One source of limits: the unit configs that scene fields become, built here for
//! both validation and the pipelines, so that what validation accepts is exactly what
//! the units accept.
//!
//! Every scene field that ends up in a unit's config is checked by building that
//! config and calling the unit's own constructor or `validate` (never a copy of its
//! range); a unit's error is then mapped onto the scene field the user wrote
//! (`shafts.texel_bits`, not `texture_sampler.texel_bits`). The pipelines build their
//! units from the same functions ([`shafts_sampler`], [`shafts_shadow`],
//! [`shafts_interpolator`], [`lum_widths`], [`glare_noise`], [`glare_combiner`],
//! [`glare_interpolator`], [`glare_generator`]), so the two cannot drift. The audit
//! (field → unit limit → where checked) is the table in docs/inputs.md, "One source of
//! limits"; `tests/limits.rs` pins it.

use rtl_model::error::ConfigError;
use rtl_model::fixed_point::{Format, Overflow, Quant};
use rtl_model::units::blend::Blend;
use rtl_model::units::clipper::ClipperConfig;
use rtl_model::units::gaussian_noise::GaussianNoiseConfig;
use rtl_model::units::glare_combiner::GlareCombinerConfig;
use rtl_model::units::luminance_ram::{LumWidths, Radial};
use rtl_model::units::modulate::{ChainRounding, ModulateChain, ModulateMode};
use rtl_model::units::polygon_interpolator::{PolygonInterpolatorConfig, MAX_ATTRS};
use rtl_model::units::polygon_variable_generator::PolygonVariableGeneratorConfig;
use rtl_model::units::projective_texcoord::ProjectiveTexcoordConfig;
use rtl_model::units::shadow_compare::ShadowCompareConfig;
use rtl_model::units::texture_sampler::{
    FilterRounding, TextureSamplerConfig, WeightRounding, MAX_TEXELS,
};
use rtl_model::Counters;
use serde::{Deserialize, Serialize};

use super::format::{ImageSize, Scene, ShaftsConfig};
use super::glare::GlareHw;

/// Depth bits of the camera depth buffer (a shadow-compare RAM at the image's size).
pub const ZBUF_BITS: u32 = 24;
/// Attributes of the shafts pipeline's polygon interpolator.
pub const SHAFTS_ATTRS: u32 = 8;
/// Fraction bits of the shafts interpolator's outputs (s16.16, the projective inputs).
pub const SHAFTS_ATTR_FRAC: u32 = 16;
/// Largest environment voxel-map side s: the 3D texture sampler holds s³ ≤
/// [`MAX_TEXELS`] texels, and the reflection unit needs a power of two (256 at 2²⁴).
pub const ENV_MAX_SIDE: u32 = max_cube_side(MAX_TEXELS);

/// The largest power of two s with s³ ≤ `texels`.
pub const fn max_cube_side(texels: u64) -> u32 {
    let mut s: u64 = 1;
    while (2 * s) * (2 * s) * (2 * s) <= texels {
        s *= 2;
    }
    s as u32
}

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

    /// The scene's choice (the default when the scene has no `[rounding]`).
    pub fn of(scene: &Scene) -> GlRounding {
        scene.rounding.unwrap_or_default()
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

/// A unit's error with its field replaced by the scene field that drove it (the first
/// pair whose unit field matches). An error on a field not listed keeps the unit's
/// name (tests/limits.rs fails on one: every refusal must name a scene field).
pub fn onto<'a>(map: &'a [(&'a str, &'a str)]) -> impl Fn(ConfigError) -> ConfigError + 'a {
    move |e| {
        let found = map.iter().find(|(unit, _)| *unit == e.field());
        match found {
            Some((_, scene)) => e.renamed(scene),
            None => e,
        }
    }
}

// ---------------------------------------------------------------------------------
// The shafts pipeline.

/// A shafts texture sampler (F: 1D, h and light maps: 2D) at the scene's widths and
/// rounding.
pub fn shafts_sampler(scene: &Scene, dims: u32, size: [u32; 3]) -> TextureSamplerConfig {
    let s = &scene.shafts;
    GlRounding::of(scene).sampler(TextureSamplerConfig {
        dims,
        size,
        texel_bits: s.texel_bits,
        coord_frac_bits: s.coord_frac_bits,
        weight_bits: s.weight_bits,
        ..TextureSamplerConfig::geforce()
    })
}

/// Depth bias for a shadow map of `bits`: 2⁻⁸ of the window-depth range (at least 1
/// LSB). Depth reaches the compare with 16 fraction bits (the interpolator's and the
/// projective unit's outputs), and a 512² map over a 50° cone sees surfaces at grazing
/// angles change by ~1/300 of the range per texel; less bias shows as acne.
/// (Validation calls it before the unit has checked `bits`: past 40 bits the shift
/// would overflow, so it saturates; the unit then refuses the width.)
pub fn shadow_bias(bits: u32) -> u32 {
    1u32.checked_shl(bits.saturating_sub(8))
        .unwrap_or(u32::MAX)
        .max(1)
}

/// A light's shadow map: `shafts.shadow_resolution`² at `shafts.shadow_depth_bits`.
pub fn shafts_shadow(s: &ShaftsConfig) -> ShadowCompareConfig {
    ShadowCompareConfig {
        width: s.shadow_resolution,
        height: s.shadow_resolution,
        depth_bits: s.shadow_depth_bits,
        bias: shadow_bias(s.shadow_depth_bits),
        frag_frac_bits: 0,
        ..ShadowCompareConfig::geforce()
    }
}

/// The camera depth buffer: a shadow-compare RAM at the image's size.
pub fn depth_buffer(image: ImageSize) -> ShadowCompareConfig {
    ShadowCompareConfig {
        width: image.width,
        height: image.height,
        depth_bits: ZBUF_BITS,
        bias: 0,
        frag_frac_bits: 0,
        ..ShadowCompareConfig::geforce()
    }
}

/// The shafts pipeline's polygon interpolator (GeForce defaults, 8 attributes, s16.16
/// outputs, accumulators `shafts.acc_int_bits`.`shafts.acc_frac_bits`); its vertex
/// positions bound the image size.
pub fn shafts_interpolator(s: &ShaftsConfig) -> PolygonInterpolatorConfig {
    PolygonInterpolatorConfig {
        attrs: SHAFTS_ATTRS,
        out_int_bits: 16,
        out_frac_bits: SHAFTS_ATTR_FRAC,
        acc_int_bits: s.acc_int_bits,
        acc_frac_bits: s.acc_frac_bits,
        ..PolygonInterpolatorConfig::default()
    }
}

/// The clipper in front of the shafts pipeline's interpolator: its attributes and
/// screen format are the interpolator's ([`shafts_interpolator`]), its viewport the
/// image, its guard band the interpolator's range of whole pixels less one on the
/// negative side (−4095 ..= 4095 at 13 integer bits): a cut vertex rounded across the
/// guard band's edge (by under a pixel) stays inside the format on both sides.
pub fn shafts_clipper(scene: &Scene) -> ClipperConfig {
    let interp = shafts_interpolator(&scene.shafts);
    let half = 1i32 << (interp.coord_int_bits - 1);
    ClipperConfig {
        attrs: interp.attrs,
        attr_int_bits: interp.attr_fmt.int_bits,
        attr_frac_bits: interp.attr_fmt.frac_bits,
        screen_int_bits: interp.coord_int_bits,
        subpixel_bits: interp.subpixel_bits,
        viewport_width: scene.image.width,
        viewport_height: scene.image.height,
        guard_min: -half + 1,
        guard_max: half - 1,
        ..ClipperConfig::default()
    }
}

/// The light-map / shadow-map projective unit: GeForce defaults with the reciprocal
/// of `shafts.recip_index_bits`, `shafts.recip_entry_bits`, `shafts.newton_frac_bits`.
pub fn shafts_projective(s: &ShaftsConfig) -> ProjectiveTexcoordConfig {
    ProjectiveTexcoordConfig {
        recip_index_bits: s.recip_index_bits,
        recip_entry_bits: s.recip_entry_bits,
        newton_frac_bits: s.newton_frac_bits,
        ..ProjectiveTexcoordConfig::geforce()
    }
}

/// The depth projection (light-space depth, 2.16 out, two Newton steps at 30 fraction
/// bits): it divides by the same q as [`shafts_projective`] and shares its ROM
/// (`shafts.recip_index_bits`, `shafts.recip_entry_bits`).
pub fn shafts_projective_depth(s: &ShaftsConfig) -> ProjectiveTexcoordConfig {
    ProjectiveTexcoordConfig {
        out_int_bits: 2,
        out_frac_bits: 16,
        newton_steps: 2,
        newton_frac_bits: 30,
        recip_index_bits: s.recip_index_bits,
        recip_entry_bits: s.recip_entry_bits,
        ..ProjectiveTexcoordConfig::geforce()
    }
}

/// Error mapping of the interpolator's and the projective units' widths onto the
/// `shafts` fields they come from.
const SHAFTS_UNIT_WIDTHS: [(&str, &str); 5] = [
    ("polygon_interpolator.acc_int_bits", "shafts.acc_int_bits"),
    ("polygon_interpolator.acc_frac_bits", "shafts.acc_frac_bits"),
    (
        "projective_texcoord.recip_index_bits",
        "shafts.recip_index_bits",
    ),
    (
        "projective_texcoord.recip_entry_bits",
        "shafts.recip_entry_bits",
    ),
    (
        "projective_texcoord.newton_frac_bits",
        "shafts.newton_frac_bits",
    ),
];

/// The image size against the units it sizes: the camera depth buffer (shadow-compare
/// map side) and the interpolator's vertex range (a sample plane's corner vertex lies
/// at (width, height)). Errors name `image.width` / `image.height`.
pub fn check_image(image: ImageSize) -> Result<(), ConfigError> {
    let map = onto(&[
        ("shadow_compare.width", "image.width"),
        ("shadow_compare.height", "image.height"),
        ("polygon_interpolator.vertices[0].x", "image.width"),
        ("polygon_interpolator.vertices[0].y", "image.height"),
    ]);
    depth_buffer(image).build().map_err(&map)?;
    // The accumulator widths do not bound the vertex range: the defaults' here.
    let interp = shafts_interpolator(&ShaftsConfig::default())
        .build()
        .map_err(&map)?;
    let attrs = [0.0; MAX_ATTRS];
    let mut ctr = Counters::default();
    interp
        .vertex_from_f64(
            0,
            image.width as f64,
            image.height as f64,
            &attrs[..SHAFTS_ATTRS as usize],
            &mut ctr,
        )
        .map_err(&map)?;
    Ok(())
}

/// Every unit the shafts fields configure, built as the shafts frame builds them:
/// the F, h and light-map samplers, the modulate, the blend and the J blend, the shadow
/// map. Errors name `shafts.<field>` (and `rounding.<field>`).
pub fn check_shafts(scene: &Scene) -> Result<(), ConfigError> {
    let s = &scene.shafts;
    let sampler = |size_field: &'static str| {
        [
            ("texture_sampler.size", size_field),
            ("texture_sampler.coord_int_bits", size_field),
            ("texture_sampler.texel_bits", "shafts.texel_bits"),
            ("texture_sampler.coord_frac_bits", "shafts.coord_frac_bits"),
            ("texture_sampler.weight_bits", "shafts.weight_bits"),
        ]
    };
    shafts_sampler(scene, 1, [s.f_texels, 1, 1])
        .validate()
        .map_err(onto(&sampler("shafts.f_texels")))?;
    shafts_sampler(scene, 2, [s.h_texels[0], s.h_texels[1], 1])
        .validate()
        .map_err(onto(&sampler("shafts.h_texels")))?;
    shafts_sampler(scene, 2, [s.light_map_texels, s.light_map_texels, 1])
        .validate()
        .map_err(onto(&sampler("shafts.light_map_texels")))?;
    let tex = [
        ("modulate.bits", "shafts.texel_bits"),
        ("blend.src_bits", "shafts.texel_bits"),
        ("blend.bits", "shafts.fb_bits"),
        ("blend.constant_bits", "shafts.weight_bits"),
    ];
    rtl_model::units::modulate::Modulate::new(s.texel_bits, ModulateMode::Exact)
        .map_err(onto(&tex))?;
    Blend::additive(s.texel_bits, s.fb_bits, false, s.weight_bits).map_err(onto(&tex))?;
    // The J buffer: texel-wide, weighted by 1/m.
    let j = [
        ("blend.src_bits", "shafts.texel_bits"),
        ("blend.bits", "shafts.texel_bits"),
        ("blend.constant_bits", "shafts.weight_bits"),
    ];
    Blend::additive(s.texel_bits, s.texel_bits, true, s.weight_bits).map_err(onto(&j))?;
    shafts_shadow(s).build().map_err(onto(&[
        ("shadow_compare.width", "shafts.shadow_resolution"),
        ("shadow_compare.height", "shafts.shadow_resolution"),
        ("shadow_compare.depth_bits", "shafts.shadow_depth_bits"),
        ("shadow_compare.bias", "shafts.shadow_depth_bits"),
    ]))?;
    let widths = onto(&SHAFTS_UNIT_WIDTHS);
    shafts_interpolator(s).build().map_err(&widths)?;
    shafts_projective(s).build().map_err(&widths)?;
    shafts_projective_depth(s).build().map_err(&widths)?;
    Ok(())
}

// ---------------------------------------------------------------------------------
// The glare pipeline.

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

// ---------------------------------------------------------------------------------
// The environment-map pipeline.

/// The environment's 3D voxel-map texture (s × s × s, RGB, 8-bit texels as the
/// render uploads it) and the reflection unit's side: errors name `side` (put
/// `environment.` before it).
pub fn check_env_side(side: u32) -> Result<(), ConfigError> {
    TextureSamplerConfig {
        channels: 3,
        ..TextureSamplerConfig::geforce_3d(side, side, side)
    }
    .validate()
    .map_err(onto(&[
        ("texture_sampler.size", "side"),
        ("texture_sampler.coord_int_bits", "side"),
    ]))
}
