//! The units of one shafts frame, configured from the scene, and the word conversions
//! the passes share (s16.16 attributes and window depths → unorm codes and depth
//! words). Below the passes: the frame, the planes and the chunked path use it, and it
//! uses none of them.

use super::prepare::Prepared;
use super::tables::{self, GTables};
use crate::scene::limits;
use rtl_model::error::ConfigError;
use rtl_model::units::blend::Blend;
use rtl_model::units::clipper::Clipper;
use rtl_model::units::modulate::Modulate;
use rtl_model::units::polygon_interpolator::PolygonInterpolator;
use rtl_model::units::projective_texcoord::ProjectiveTexcoord;
use rtl_model::units::shadow_compare::ShadowCompare;
use rtl_model::units::texture_sampler::TextureSampler;
use rtl_model::unorm::max_code;
use rtl_model::Counters;
use std::collections::BTreeMap;

/// Camera depth buffer width (defined with the scene's limits: validation builds the
/// depth buffer from it).
pub use crate::scene::limits::ZBUF_BITS;
/// Fraction bits of the interpolator's outputs (s16.16, the projective inputs).
pub(super) const ATTR_FRAC: u32 = crate::scene::limits::SHAFTS_ATTR_FRAC;

/// The units of one frame, configured from the scene.
pub(super) struct Units {
    pub(super) interp: PolygonInterpolator,
    pub(super) f_tex: TextureSampler,
    pub(super) h_tex: TextureSampler,
    pub(super) modulate: Modulate,
    pub(super) blend: Blend,
    pub(super) proj: ProjectiveTexcoord,
    pub(super) proj_depth: ProjectiveTexcoord,
    pub(super) zbuf: Option<ShadowCompare>,
    pub(super) shadow: Option<ShadowCompare>,
    pub(super) j_blend: Blend,
    /// The clipper in front of the interpolator for the camera's object passes, when
    /// the scene's objects can leave its planes ([`crate::scene::clip::clip_needed`]).
    pub(super) clipper: Option<Clipper>,
}

impl Units {
    /// The frame's units configured from the scene (`tables`: the F and h textures'
    /// contents). The unit configs come from the scene's limits module, which
    /// validation builds too (one source of limits); errors name the scene's fields.
    pub(super) fn new(p: &Prepared, tables: &GTables) -> Result<Self, ConfigError> {
        let sc = &p.scene;
        let cfg = sc.shafts;
        let tex_bits = cfg.texel_bits;
        let interp = limits::shafts_interpolator(&cfg).build()?;
        let sampler_cfg = |dims: u32, size: [u32; 3]| limits::shafts_sampler(sc, dims, size);
        let f_tex = TextureSampler::new(sampler_cfg(1, [cfg.f_texels, 1, 1]), &tables.f_texels)
            .map_err(|e| e.within("shafts.f_texels"))?;
        let h_tex = TextureSampler::new(
            sampler_cfg(2, [cfg.h_texels[0], cfg.h_texels[1], 1]),
            &tables.h_texels,
        )
        .map_err(|e| e.within("shafts.h_texels"))?;
        let has_objects = p.objects.iter().any(|o| !o.triangles.is_empty());
        let has_occluders = p
            .objects
            .iter()
            .any(|o| o.occluder && !o.triangles.is_empty());
        Ok(Units {
            interp,
            f_tex,
            h_tex,
            modulate: Modulate::new(tex_bits, rtl_model::units::modulate::ModulateMode::Exact)?,
            blend: Blend::additive(tex_bits, cfg.fb_bits, false, cfg.weight_bits)?,
            proj: limits::shafts_projective(&cfg).build()?,
            proj_depth: limits::shafts_projective_depth(&cfg).build()?,
            zbuf: if has_objects {
                Some(limits::depth_buffer(sc.image).build()?)
            } else {
                None
            },
            shadow: if has_occluders {
                Some(limits::shafts_shadow(&cfg).build().map_err(limits::onto(&[
                    ("shadow_compare.width", "shafts.shadow_resolution"),
                    ("shadow_compare.height", "shafts.shadow_resolution"),
                    ("shadow_compare.depth_bits", "shafts.shadow_depth_bits"),
                ]))?)
            } else {
                None
            },
            // The J buffer lives in the RGBA framebuffer, as on the real part (its traffic counts 4 channels).
            j_blend: Blend::additive(tex_bits, tex_bits, true, cfg.weight_bits)?,
            clipper: if has_objects && crate::scene::clip::clip_needed(sc).is_some() {
                Some(limits::shafts_clipper(sc).build()?)
            } else {
                None
            },
        })
    }
}

/// Add `c` to the counters filed under unit `name`.
pub(super) fn counters_add(map: &mut BTreeMap<String, Counters>, name: &str, c: Counters) {
    *map.entry(name.to_string()).or_default() += c;
}

/// A window depth in s16.16 raw → an unsigned depth word of `bits`.
pub(super) fn window_depth_word(raw: i64, bits: u32) -> u32 {
    let max = max_code(bits) as i64;
    let v = if bits >= ATTR_FRAC {
        raw << (bits - ATTR_FRAC)
    } else {
        raw >> (ATTR_FRAC - bits)
    };
    v.clamp(0, max) as u32
}

/// An s16.16 attribute in [0, 1] → a unorm code of full scale `max` (round half up,
/// clamped): the interpolated vertex colour entering the combiner.
pub(super) fn attr_unorm(raw: i64, max: u32) -> u32 {
    let max = max as i64;
    ((raw * max + (1 << (ATTR_FRAC - 1))) >> ATTR_FRAC).clamp(0, max) as u32
}

/// A window depth in [0, 1] → a depth word.
pub(super) fn unit_depth_word(z: f64, bits: u32) -> u32 {
    tables::unorm_from_unit(z, bits)
}
