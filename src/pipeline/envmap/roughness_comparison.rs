//! The roughness comparison: the thesis' proposed fix (λ from a texture,
//! [`super::roughness`]) measured against λ per vertex, both against the intended-λ
//! truth. It renders through [`super::render`], above it and the roughness file both.

use rtl_model::error::ConfigError;

use super::image::Image;
use super::objects::{LambdaSpec, Object};
use super::render::{render_object_with, RenderOptions};
#[cfg(doc)]
use super::roughness::IntendedErrors;
use super::roughness::LambdaSource;
#[cfg(doc)]
use super::truth::Truth;
use super::voxmap::VoxelMap;
use crate::scene::envmap::EnvMap;

/// One row of the roughness comparison: a λ source's errors against the intended-λ
/// truth ([`Truth::intended`], eq. 3, 8-bit levels).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RoughnessRow {
    pub object: String,
    /// [`LambdaSource::label`].
    pub lambda_source: String,
    /// Object pixels.
    pub pixels: usize,
    /// Mean and largest |Δ| per channel over the object.
    pub mean: [f64; 3],
    pub max: [f64; 3],
    /// The same over the seam band ([`IntendedErrors::seam`]; 0 pixels for the teapot).
    pub seam_pixels: usize,
    pub seam_mean: [f64; 3],
    pub seam_max: [f64; 3],
    /// Mean |Δ| over the seam band against the truth with the render's own λ (the
    /// map's floor there, [`IntendedErrors::seam_own`]).
    pub seam_own_mean: [f64; 3],
    /// Mean and largest |λ used − λ intended| over the object and the seam band.
    pub lambda_mean: f64,
    pub lambda_max: f64,
    pub seam_lambda_mean: f64,
    pub seam_lambda_max: f64,
}

impl RoughnessRow {
    pub const CSV_HEADER: &'static str = "object,lambda_source,pixels,mean_r,mean_g,mean_b,max_r,max_g,max_b,seam_pixels,seam_mean_r,seam_mean_g,seam_mean_b,seam_max_r,seam_max_g,seam_max_b,seam_own_mean_r,seam_own_mean_g,seam_own_mean_b,lambda_mean,lambda_max,seam_lambda_mean,seam_lambda_max";

    pub fn to_csv(&self) -> String {
        let f = |v: [f64; 3]| format!("{:.4},{:.4},{:.4}", v[0], v[1], v[2]);
        format!(
            "{},{},{},{},{},{},{},{},{},{:.5},{:.5},{:.5},{:.5}",
            self.object,
            self.lambda_source,
            self.pixels,
            f(self.mean),
            f(self.max),
            self.seam_pixels,
            f(self.seam_mean),
            f(self.seam_max),
            f(self.seam_own_mean),
            self.lambda_mean,
            self.lambda_max,
            self.seam_lambda_mean,
            self.seam_lambda_max
        )
    }

    /// Mean of the three channels' mean |Δ| (over the object, and over the seam band).
    pub fn mean_rgb(&self) -> f64 {
        self.mean.iter().sum::<f64>() / 3.0
    }
    pub fn seam_mean_rgb(&self) -> f64 {
        self.seam_mean.iter().sum::<f64>() / 3.0
    }
    pub fn seam_own_mean_rgb(&self) -> f64 {
        self.seam_own_mean.iter().sum::<f64>() / 3.0
    }
}

/// The thesis' proposed fix measured: `object` with the non-uniform λ at
/// `size`, rendered with λ per vertex and with a `side` × `side` roughness texture,
/// each against the intended-λ truth (the same truth image for both: it depends only
/// on the geometry and the interpolated n, r, (u, v)). Rows in that order. Errors as
/// [`render_object_with`] and "envmap_render.lambda_texture".
pub fn roughness_comparison(
    env: &EnvMap,
    map: &VoxelMap,
    object: Object,
    size: (u32, u32),
    side: u32,
) -> Result<Vec<RoughnessRow>, ConfigError> {
    Ok(roughness_comparison_images(env, map, object, size, side)?.rows)
}

/// [`roughness_comparison`] with the images it made, for looking at.
pub struct RoughnessComparison {
    pub rows: Vec<RoughnessRow>,
    /// The renders: λ per vertex, λ from the texture.
    pub images: [Image; 2],
    /// The intended-λ truth (black where the object is not).
    pub truth: Image,
}

/// [`roughness_comparison`], keeping the two renders and the intended-λ truth.
pub fn roughness_comparison_images(
    env: &EnvMap,
    map: &VoxelMap,
    object: Object,
    size: (u32, u32),
    side: u32,
) -> Result<RoughnessComparison, ConfigError> {
    let run = |source: LambdaSource| {
        let opt = RenderOptions {
            lambda_source: source,
            intended_truth: true,
            ..RenderOptions::default()
        };
        // Each source gets its own truths: the intended one is the same image for both,
        // but `seam_own` needs the truth with the λ this render used.
        let (img, t, st) =
            render_object_with(env, map, object, LambdaSpec::NonUniform, size, &opt)?;
        let i = st.intended.unwrap_or_default();
        let row = RoughnessRow {
            object: object.name().to_string(),
            lambda_source: source.label(),
            pixels: i.all.pixels,
            mean: i.all.mean,
            max: i.all.max,
            seam_pixels: i.seam.pixels,
            seam_mean: i.seam.mean,
            seam_max: i.seam.max,
            seam_own_mean: i.seam_own.mean,
            lambda_mean: i.lambda_all.mean,
            lambda_max: i.lambda_all.max,
            seam_lambda_mean: i.lambda_seam.mean,
            seam_lambda_max: i.lambda_seam.max,
        };
        Ok::<_, ConfigError>((row, img, t.intended))
    };
    let (r0, a, _) = run(LambdaSource::PerVertex)?;
    let (r1, b, truth) = run(LambdaSource::Texture { side })?;
    // `intended_truth: true` always makes it.
    let truth = truth.ok_or_else(|| {
        ConfigError::invalid("envmap_render.truth", "the render made no intended-λ truth")
    })?;
    Ok(RoughnessComparison {
        rows: vec![r0, r1],
        images: [a, b],
        truth,
    })
}
