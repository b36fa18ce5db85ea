//! The numbers the scene format's ranges are built from (the largest image, world
//! coordinate, intensity, exponent, …) and the range checks on them. The field table
//! (`fields.rs`), validation and the sections import this file; it imports none of
//! them.

use rtl_model::error::{check_finite, short, ConfigError};
use rtl_model::units::texture_sampler::{TextureSamplerConfig, MAX_TEXELS};

/// Largest image side, pixels, read from the units so that validation and the units
/// cannot drift: the shadow-compare unit's largest map side (the camera depth buffer
/// is a shadow-compare RAM at the image's size) and the largest whole pixel the
/// polygon interpolator's default vertex positions reach (a sample plane's corner
/// vertex lies at (width, height); 13 integer bits reach 4095.94). Validation also
/// builds both units at the image's size ([`super::limits::check_image`]).
pub const IMAGE_MAX: u32 = {
    use rtl_model::units::polygon_interpolator::DEFAULT_COORD_INT_BITS;
    use rtl_model::units::shadow_compare::MAX_MAP_SIDE;
    let vertex = (1u32 << (DEFAULT_COORD_INT_BITS - 1)) - 1;
    if MAX_MAP_SIDE < vertex {
        MAX_MAP_SIDE
    } else {
        vertex
    }
};
/// Largest scene file read, bytes (a scene is text: the biggest built-in is a few
/// kilobytes; this leaves room for thousands of objects).
pub const SCENE_FILE_MAX_BYTES: u64 = 16 << 20;
/// Largest light-map image file read, bytes.
pub const LIGHT_MAP_FILE_MAX_BYTES: u64 = 64 << 20;

/// Largest magnitude of any coordinate or length, world units.
pub const WORLD_MAX: f64 = 1e6;
/// Shortest vector accepted where a direction is needed.
pub const MIN_LENGTH: f64 = 1e-9;
/// Below this sine of their angle, two directions count as parallel.
pub const PARALLEL_SIN: f64 = 1e-6;
/// Largest light intensity.
pub const INTENSITY_MAX: f64 = 1e9;
/// Largest light colour component.
pub const LIGHT_COLOR_MAX: f64 = 1e3;
/// Largest ρ, κ, K.
pub const MEDIUM_MAX: f64 = 1e6;
/// Largest teapot scale (its data spans ~6.4 units, so the result stays within
/// `WORLD_MAX`).
pub const TEAPOT_SCALE_MAX: f64 = 1e5;

/// Largest specular exponent accepted (the stiff range of DESIGN §4 reaches 10⁴;
/// beyond 10⁵ cos^n underflows for every angle a texel can resolve).
pub const EXPONENT_MAX: f64 = 1e5;

/// Largest intensity (codes) accepted: 10⁹ (10⁶ is a documented stiff case).
pub const GLARE_INTENSITY_MAX: f64 = 1e9;

/// Finite and in `lo ..= hi` (an `OutOfRange` error otherwise).
pub(crate) fn closed(field: &str, x: f64, lo: f64, hi: f64) -> Result<(), ConfigError> {
    check_finite(field, x)?;
    if x < lo || x > hi {
        return Err(ConfigError::out_of_range(field, x, lo, hi));
    }
    Ok(())
}

/// Finite and in an interval with each end open or closed. Both ends closed gives
/// an `OutOfRange` error; otherwise `Invalid` with the interval written out.
pub(crate) fn interval(
    field: &str,
    x: f64,
    lo: f64,
    lo_closed: bool,
    hi: f64,
    hi_closed: bool,
) -> Result<(), ConfigError> {
    if lo_closed && hi_closed {
        return closed(field, x, lo, hi);
    }
    check_finite(field, x)?;
    let lo_ok = if lo_closed { x >= lo } else { x > lo };
    let hi_ok = if hi_closed { x <= hi } else { x < hi };
    if lo_ok && hi_ok {
        return Ok(());
    }
    let name = field.rsplit('.').next().unwrap_or(field);
    Err(ConfigError::invalid(
        field,
        &format!(
            "{} is out of range (allowed {} {} {name} {} {})",
            short(x),
            short(lo),
            if lo_closed { "≤" } else { "<" },
            if hi_closed { "≤" } else { "<" },
            short(hi),
        ),
    ))
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

/// Largest environment voxel-map side s: the 3D texture sampler holds s³ ≤
/// `MAX_TEXELS` texels, and the reflection unit needs a power of two (256 at 2²⁴).
pub const ENV_MAX_SIDE: u32 = max_cube_side(MAX_TEXELS);
/// The environment voxel map's smallest side (`environment.side`).
pub const ENV_MIN_SIDE: u32 = 2;
/// Largest `environment.exposure` (the auto exposure's own cap).
pub const ENV_MAX_EXPOSURE: f64 = 1e300;

/// The largest power of two s with s³ ≤ `texels`.
pub const fn max_cube_side(texels: u64) -> u32 {
    let mut s: u64 = 1;
    while (2 * s) * (2 * s) * (2 * s) <= texels {
        s *= 2;
    }
    s as u32
}

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
