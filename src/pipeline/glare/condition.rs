//! Specular highlights through the glare-condition unit (Table 2): a highlight whose
//! contrast against the ambient reaches the threshold (and, on water, is totally
//! internally reflected) becomes a glare source; below it, only its core is drawn,
//! saturating at 255.

use super::host::{px_per_deg, ScreenSource};
use crate::reference::glare_model::Shape2D;
use crate::scene::camera::{vec3, CameraView};
use crate::scene::format::Scene;
use crate::scene::glare::{Highlight, HighlightMaterial};
use rtl_model::driver::run_span;
use rtl_model::units::glare_condition::{GlareCondition, GlareConditionConfig, Material};
use rtl_model::{ConfigError, Counters, Unit, UnitSummary};
use std::collections::BTreeMap;

/// The shader's cosines at a highlight: cos α between the mirror direction of the
/// light and the view, and cos θ of the incidence (for the TIR test).
pub fn cosines(h: &Highlight, eye: crate::scene::math::Vec3) -> (f64, f64) {
    let p = vec3(h.position);
    let n = vec3(h.normal).normalized();
    let l = (vec3(h.light) - p).normalized();
    let v = (eye - p).normalized();
    let r = n * (2.0 * n.dot(l)) - l;
    (r.dot(v), n.dot(l).abs())
}

/// The highlight sources with their intensities, and (elaborated?, summary).
pub fn highlight_sources(
    scene: &Scene,
    ctr: &mut BTreeMap<String, Counters>,
) -> Result<(Vec<(ScreenSource, f64)>, super::fluctuation::Elab), ConfigError> {
    let g = super::host::glare_of(scene)?;
    if g.highlights.is_empty() {
        return Ok((
            Vec::new(),
            (false, Some(UnitSummary::of(&GlareCondition::geforce()))),
        ));
    }
    let cam = CameraView::new(&scene.camera, scene.image);
    let ppd = px_per_deg(&cam);
    let mut out = Vec::new();
    let mut unit = None;
    for (i, h) in g.highlights.iter().enumerate() {
        let field = format!("glare.highlights[{i}]");
        let eta = match h.material {
            HighlightMaterial::Water => g.model.water_eta_for(h.eta),
            HighlightMaterial::Metallic => h.eta,
        };
        let u = GlareConditionConfig {
            eta,
            threshold: g.model.contrast.round().clamp(0.0, 65535.0) as u32,
            ..GlareConditionConfig::default()
        }
        .build()
        .map_err(|e| e.within(&field))?;
        let (cos_a, cos_t) = cosines(h, cam.eye);
        let material = match h.material {
            HighlightMaterial::Metallic => Material::Metallic,
            HighlightMaterial::Water => Material::Water,
        };
        let input = u
            .input_from_f64(
                material,
                h.intensity,
                h.specular,
                cos_a,
                cos_t,
                g.determinants.ambient,
            )
            .map_err(|e| e.within(&field))?;
        let mut c = Counters::default();
        let o = run_span(&u, &mut (), &[input], &mut c)[0];
        *ctr.entry(u.name().to_string()).or_default() += c;
        let Some((x, y, _)) = cam.project(vec3(h.position)) else {
            return Err(ConfigError::invalid(
                &format!("{field}.position"),
                "is behind the camera",
            ));
        };
        let depth = cam.depth_of(vec3(h.position)).max(1e-12);
        let r = ppd * 180.0 / std::f64::consts::PI * h.radius / depth;
        let frac = (1u64 << u.config().frac_bits) as f64;
        let intensity = if o.glare {
            u.i_ps_code(&input) as f64 / frac
        } else {
            o.i_ps as f64
        };
        out.push((
            ScreenSource {
                label: format!(
                    "{field} ({})",
                    if o.glare { "glare" } else { "saturates only" }
                ),
                center: [x, y],
                shape: Shape2D::Circle { r },
                px_per_deg: ppd,
                intensity,
                c_dir: 1.0,
                color: [1.0, 1.0, 1.0],
                bloom: true,
                halo: o.glare,
                flare: o.glare,
                aspect: 1.0,
                base_rad: 0.0,
                patch: None,
                core_only: !o.glare,
            },
            intensity,
        ));
        unit.get_or_insert_with(|| UnitSummary::of(&u));
    }
    Ok((out, (true, unit)))
}
