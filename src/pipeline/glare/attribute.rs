//! `attribute --scene S` for a glare scene (`report::attribution`): the
//! glare renderer's error sources, each a `[glare.hw]` width or RAM size set wide.
//!
//! Renders go through the path `sweep` uses ([`render_and_predict_over`] through the
//! units, [`reference_levels`]: the analytic formulas per pixel over the frame's own
//! background, sources and line draws). "Ideal" for each source:
//!
//! | source | configured → ideal |
//! |---|---|
//! | shape RAM resolution | `shape_log2` k → min(k + 3, 10) (8× the cells per side) |
//! | falloff RAM resolution | `falloff_log2` → 12 |
//! | falloff RAM entries | `falloff_bits` → 20 |
//! | weight_bits | → 12 |
//! | coord_frac_bits | → 16 (the RAM address fraction) |
//! | fb_bits (output rounding) | 8 → 16 (the glare combiner's framebuffer) |
//!
//! Each is the widest the unit takes (`luminance_ram`, `glare_combiner` limits), not the
//! mathematical limit; the shape RAM's entries are 16 bits by default, already its
//! widest, so they are not a source.
//!
//! The Gaussian noise of the flare lines is part of the scene (the reference draws the
//! same lines), so it is not an error source.

use super::background::from_framebuffer;
use super::cli::{reference_levels, render_and_predict_over};
use crate::report::attribution::{attribute, Attribution, Bound, Source};
use crate::report::image_out::Framebuffer;
use crate::scene::format::Scene;
use crate::scene::glare::GlareHw;
use std::path::Path;

fn hw_of(s: &mut Scene) -> Option<&mut GlareHw> {
    s.glare.as_mut().map(|g| &mut g.hw)
}

/// The sources of a glare scene (module notes).
pub fn sources(base: &Scene) -> Vec<Source<Scene>> {
    let c = base.glare.as_ref().map(|g| g.hw).unwrap_or_default();
    let mut v: Vec<Source<Scene>> = Vec::new();
    let mut add = |name: &str, field: &str, from: u32, to: u32, set: fn(&mut GlareHw, u32)| {
        let to = to.max(from);
        v.push(Source {
            name: name.to_string(),
            ideal: format!("glare.hw.{field} {from} → {to}"),
            make_ideal: Box::new(move |s| {
                if let Some(h) = hw_of(s) {
                    set(h, to)
                }
            }),
        })
    };
    // The widest each field takes (the luminance RAM's and combiner's own limits).
    add(
        "shape RAM resolution",
        "shape_log2",
        c.shape_log2,
        (c.shape_log2 + 3).min(10),
        |h, v| h.shape_log2 = v,
    );
    add(
        "falloff RAM resolution",
        "falloff_log2",
        c.falloff_log2,
        12,
        |h, v| h.falloff_log2 = v,
    );
    add(
        "falloff RAM entries",
        "falloff_bits",
        c.falloff_bits,
        20,
        |h, v| h.falloff_bits = v,
    );
    add("weight_bits", "weight_bits", c.weight_bits, 12, |h, v| {
        h.weight_bits = v
    });
    add(
        "coord_frac_bits",
        "coord_frac_bits",
        c.coord_frac_bits,
        16,
        |h, v| h.coord_frac_bits = v,
    );
    add(
        "fb_bits (output rounding)",
        "fb_bits",
        c.fb_bits,
        16,
        |h, v| h.fb_bits = v,
    );
    v
}

/// The bound of "all ideal": the 16-bit framebuffer read as 8-bit levels rounds by at
/// most 1/257 level, the tables at their widest leave a sampling
/// error well under a level; the mean |Δ| is held to 0.5 level and at most 1 % of the
/// values (source rims and flare-line edges, where one more cell moves a pixel's value
/// by the profile's slope) may be off by more than 2 levels.
pub fn bound() -> Bound {
    Bound {
        mean_abs: 0.5,
        outlier_fraction: 0.01,
        outlier_levels: 2.0,
        why: "mean |Δ| ≤ 0.5 level; ≤ 1 % of the values off by > 2 levels (rims, line edges)"
            .into(),
    }
}

/// Attribute the error of the glare scene `scene` into `out`; `backdrop` is what the
/// frame's earlier passes drew (a shafts background), as `sweep` takes it.
pub fn attribute_glare(
    scene: &Scene,
    backdrop: Option<&Framebuffer>,
    out: &Path,
) -> Result<Attribution, String> {
    let (w, h) = (scene.image.width, scene.image.height);
    if scene.glare.is_none() {
        return Err("scene: it has no [glare] section".into());
    }
    attribute(
        scene.short_name().trim(),
        scene,
        (w, h),
        &sources(scene),
        &bound(),
        |s| s.validate().map_err(|e| e.to_string()),
        |s| {
            let base = backdrop
                .map(|fb| from_framebuffer(fb, s.glare.as_ref().map_or(8, |g| g.hw.fb_bits)));
            let (f, _, _) =
                render_and_predict_over(s, base.as_deref()).map_err(|e| e.to_string())?;
            let lv = reference_levels(s, &f).map_err(|e| e.to_string())?;
            Ok((f.levels(), lv))
        },
        out,
    )
}
