//! The shading → glare link: a glare scene with `[glare.shaded_highlights]` has its
//! objects shaded by the shading units first; the highlights they find join the
//! scene's written ones at the glare conditions, and the shaded objects become the
//! picture the glare is added to. Both pipelines stay unaware of each other: this
//! module, beside them, passes one's output to the other.

use crate::pipeline::glare::background::base_image;
use crate::pipeline::shading::scene_pass::{shade_scene, SceneShading};
use crate::scene::format::Scene;
use rtl_model::ConfigError;
use std::collections::BTreeMap;

/// A glare scene prepared from its shading pass.
pub struct Linked {
    /// The scene with the found highlights appended to `glare.highlights`.
    pub scene: Scene,
    /// The glare background with the shaded objects drawn over it (fb codes, RGB).
    pub base: Vec<[u32; 3]>,
    pub shading: SceneShading,
}

/// None when the scene asks for no shaded highlights (then nothing changes).
pub fn prepare(scene: &Scene) -> Result<Option<Linked>, ConfigError> {
    let Some(g) = &scene.glare else {
        return Ok(None);
    };
    let Some(sh) = g.shaded_highlights else {
        return Ok(None);
    };
    let shading = shade_scene(scene, sh.light, sh.intensity, sh.radius)?;
    let mut base = base_image(scene, &mut BTreeMap::new())?;
    let max = rtl_model::unorm::max_code(g.hw.fb_bits) as u64;
    for (b, p) in base.iter_mut().zip(&shading.pixels) {
        if let Some(rgb) = p {
            // u8 level → fb code, rounded: (v · max · 2 + 255) / 510.
            *b = rgb.map(|v| ((v as u64 * max * 2 + 255) / 510) as u32);
        }
    }
    let mut linked = scene.clone();
    if let Some(lg) = linked.glare.as_mut() {
        lg.highlights
            .extend(shading.highlights.iter().map(|h| h.highlight));
    }
    Ok(Some(Linked {
        scene: linked,
        base,
        shading,
    }))
}

/// What the shading pass did, as text: the highlights it found and its units.
pub fn summary(l: &Linked) -> String {
    let mut s = format!(
        "shading pass: {} fragments shaded; {} highlight(s) found by the shading units\n",
        l.shading.fragments,
        l.shading.highlights.len()
    );
    for h in &l.shading.highlights {
        s.push_str(&format!(
            "  objects[{}]: brightest specular fragment at pixel ({}, {}), level {} → I_s = {:.3}\n",
            h.object, h.pixel[0], h.pixel[1], h.specular, h.highlight.specular
        ));
    }
    s.push_str(&crate::report::table::counters_table(&l.shading.counters));
    s.push_str("\nshading elaboration:\n");
    s.push_str(&crate::report::table::elaboration_table(
        &l.shading.elaboration,
    ));
    s.push('\n');
    s
}
