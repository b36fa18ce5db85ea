//! `attribute --scene S` for an environment-map scene (`report::attribution`): the
//! voxel map's error sources.
//!
//! Renders go through the path `sweep --param side` uses ([`render_scene`] with the
//! truth). The reference is the truth of eq. (3), without the cos φ test: what the
//! voxel map stores (the thesis drops the test on purpose, eqs. (3)–(5); it is a
//! choice of the method, not of the hardware, so it is not a source here and is left
//! out of the comparison). Pixels off the object are the truth's own (no error).
//! "Ideal" for each source:
//!
//! | source | configured → ideal |
//! |---|---|
//! | voxel map resolution | `environment.side` s → 2s (at most 256; the truth's Λ = g(|t|) follows s, so the reference is the one at the render's s) |
//! | prefilter (domes, weight table) | `environment.prefilter` → exact (every voxel summed over every texel) |

use super::scene_render::render_scene;
use crate::report::attribution::{attribute, Attribution, Bound, Rendered, Source};
use crate::scene::environment::{Prefilter, MAX_SIDE};
use crate::scene::format::Scene;
use std::path::Path;

/// The sources of an environment scene (module notes).
pub fn sources(base: &Scene) -> Vec<Source<Scene>> {
    let Some(env) = base.environment.as_ref() else {
        return Vec::new();
    };
    let side = env.side;
    let to = (side * 2).min(MAX_SIDE).max(side);
    vec![
        Source {
            name: "voxel map resolution".into(),
            ideal: format!("environment.side {side} → {to}"),
            make_ideal: Box::new(move |s| {
                if let Some(e) = s.environment.as_mut() {
                    e.side = to
                }
            }),
        },
        Source {
            name: "prefilter (domes, weight table)".into(),
            ideal: format!("environment.prefilter {:?} → exact", env.prefilter),
            make_ideal: Box::new(|s| {
                if let Some(e) = s.environment.as_mut() {
                    e.prefilter = Prefilter::Exact
                }
            }),
        },
    ]
}

/// The bound of "all ideal": both images are 8-bit (the truth rounded to whole levels,
/// the render through 8-bit texels and trilinear weights): a mean |Δ| of at most 1
/// level (two roundings of ≤ 0.5), at most 1 % of the values off by more than 2
/// (the object's outline, where a pixel's coverage differs).
pub fn bound() -> Bound {
    Bound {
        mean_abs: 1.0,
        outlier_fraction: 0.01,
        outlier_levels: 2.0,
        why: "mean |Δ| ≤ 1 level (two 8-bit roundings); ≤ 1 % of the values off by > 2 levels"
            .into(),
    }
}

fn render(s: &Scene) -> Result<Rendered, String> {
    let f = render_scene(s, true).map_err(|e| e.to_string())?;
    let t = f
        .truth
        .as_ref()
        .ok_or("internal: the render made no truth")?;
    let truth = &t.truth.simplified;
    let lv = |p: [u8; 3]| p.map(f64::from);
    let img = f
        .image
        .pixels
        .iter()
        .zip(&f.image.mask)
        .zip(&truth.pixels)
        .map(|((p, &m), q)| if m { lv(*p) } else { lv(*q) })
        .collect();
    Ok((img, truth.pixels.iter().map(|q| lv(*q)).collect()))
}

/// Attribute the error of the environment scene `scene` into `out`.
pub fn attribute_envmap(scene: &Scene, out: &Path) -> Result<Attribution, String> {
    let (w, h) = (scene.image.width, scene.image.height);
    attribute(
        scene.short_name().trim(),
        scene,
        (w, h),
        &sources(scene),
        &bound(),
        |s| s.validate().map_err(|e| e.to_string()),
        render,
        out,
    )
}
