//! The SMALL, TEST-ONLY voxel map builder: [`quick_map`] (exact prefilter over at most
//! 64 × 32 texels, one voxel at a time). The full 128³ builder is `envmap::prefilter`'s.

use rtl_model::error::ConfigError;

use super::voxmap::VoxelMap;
use crate::reference::envmap_prefilter::{
    prefilter_voxel_exact, Equirect, PrefilterParams, Samples, Weighting, THESIS_LEVELS,
};
use crate::scene::envmap::EnvMap;

/// Largest environment (texels) [`quick_map`] prefilters exactly; larger maps are
/// box-filtered down to ≤ 64 × 32 first (solid-angle weighted).
pub const QUICK_MAP_MAX_TEXELS: usize = 64 * 32;

/// SMALL / TEST map builder: the exact prefilter (eqs. 8–9, Λ = g(|t|) at s and I = 256,
/// solid-angle weighting) of every voxel of an s³ map, over `env`'s levels at
/// [`EnvMap::auto_exposure`], 8-bit voxels. Environments above
/// [`QUICK_MAP_MAX_TEXELS`] are first box-filtered (solid-angle weighted) by the
/// smallest factor that brings them to ≤ 64 × 32 (it must divide both sides, else an
/// error naming "envmap_render.env"). Cost ≈ s³ × texels weight evaluations: s = 16 on
/// 64 × 32 ≈ 8·10⁶. Not the thesis' builder (that is `envmap::prefilter`).
pub fn quick_map(env: &EnvMap, s: u32) -> Result<VoxelMap, ConfigError> {
    quick_map_with(env, s, env.auto_exposure())
}

/// [`quick_map`] at an explicit exposure ("envmap.exposure").
pub fn quick_map_with(env: &EnvMap, s: u32, exposure: f64) -> Result<VoxelMap, ConfigError> {
    let mut map = VoxelMap::new(s, 8)?;
    let small = shrink(env)?;
    let levels = small.to_level_map(exposure)?;
    let eq = Equirect::from_slice(levels.width(), levels.height(), levels.texels())?;
    let samples = Samples::from_equirect(&eq);
    let params = PrefilterParams::new(s as f64, THESIS_LEVELS, Weighting::SolidAngle)?;
    for z in 0..s {
        for y in 0..s {
            for x in 0..s {
                let t = map.voxel_t(x, y, z);
                let v = prefilter_voxel_exact(t, &samples, &params);
                map.set_levels(x, y, z, v.map(|c| c / 255.0));
            }
        }
    }
    Ok(map)
}

fn shrink(env: &EnvMap) -> Result<EnvMap, ConfigError> {
    if env.width() * env.height() <= QUICK_MAP_MAX_TEXELS {
        return Ok(env.clone());
    }
    let f = (1..=env.width())
        .find(|&f| {
            env.width() / f * f == env.width()
                && env.height() / f * f == env.height()
                && (env.width() / f) * (env.height() / f) <= QUICK_MAP_MAX_TEXELS
        })
        .ok_or_else(|| {
            ConfigError::invalid(
                "envmap_render.env",
                &format!(
                    "{} × {} cannot be box-filtered to ≤ {QUICK_MAP_MAX_TEXELS} texels",
                    env.width(),
                    env.height()
                ),
            )
        })?;
    env.downsample(f)
}
