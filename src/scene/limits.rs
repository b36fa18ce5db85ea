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
use rtl_model::units::blend::Blend;
use rtl_model::units::clipper::ClipperConfig;
use rtl_model::units::modulate::ModulateMode;
use rtl_model::units::polygon_interpolator::{PolygonInterpolatorConfig, MAX_ATTRS};
use rtl_model::units::projective_texcoord::ProjectiveTexcoordConfig;
use rtl_model::units::shadow_compare::ShadowCompareConfig;
use rtl_model::units::texture_sampler::TextureSamplerConfig;
use rtl_model::Counters;

pub use super::bounds::{check_env_side, max_cube_side, onto, ENV_MAX_SIDE};
use super::format::{ImageSize, Scene, ShaftsConfig};
pub use super::glare_hw::{
    check_glare, glare_combiner, glare_generator, glare_interpolator, glare_noise, lum_widths,
    GlareHw, GLARE_ATTR_FRAC_BITS, GLARE_COORD_INT_BITS, GLARE_SUBPIXEL_BITS,
};

/// Depth bits of the camera depth buffer (a shadow-compare RAM at the image's size).
pub const ZBUF_BITS: u32 = 24;
/// Attributes of the shafts pipeline's polygon interpolator.
pub const SHAFTS_ATTRS: u32 = 8;
/// Fraction bits of the shafts interpolator's outputs (s16.16, the projective inputs).
pub const SHAFTS_ATTR_FRAC: u32 = 16;

pub use super::rounding::GlRounding;

/// The scene's rounding: here, above the scene format, while the type is below it.
impl GlRounding {
    /// The scene's choice (the default when the scene has no `[rounding]`).
    pub fn of(scene: &Scene) -> GlRounding {
        scene.rounding.unwrap_or_default()
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

// The environment-map pipeline's limits (`ENV_MAX_SIDE`, `check_env_side`) are in
// `bounds.rs`, below the environment section that checks them; re-exported above.
