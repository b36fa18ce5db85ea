//! f64 twin of `glare_condition` (Matsuda and Ikedo, Table 2), on real values:
//! metallic I_ps = I·I_s·cos²α, water I_ps = I·cos α (cos α < 0 → no highlight, both
//! materials); contrast_ok = I_ps ≥ T·I_a; water also needs total internal reflection
//! 1 − η²(1 − cos²θ) < 0; the highlight value saturates at `out_max`.

/// Surface material (the twin's own copy: it does not import the unit).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Material {
    Metallic,
    Water,
}

/// The twin's decision, with the unsaturated I_ps and the TIR margin for tests.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConditionTwin {
    pub glare: bool,
    pub tir: bool,
    /// min(I_ps, out_max).
    pub i_ps: f64,
    pub contrast_ok: bool,
    /// I_ps before saturation.
    pub i_ps_raw: f64,
    /// 1 − η²(1 − cos²θ) (TIR when < 0).
    pub tir_margin: f64,
}

/// Evaluate the glare condition on real values (intensities in framebuffer codes,
/// I_s ∈ [0, 1], cosines ∈ [−1, 1]).
#[allow(clippy::too_many_arguments)]
pub fn glare_condition(
    material: Material,
    intensity: f64,
    specular: f64,
    cos_alpha: f64,
    cos_theta: f64,
    ambient: f64,
    eta: f64,
    threshold: f64,
    out_max: f64,
) -> ConditionTwin {
    let a = cos_alpha.max(0.0);
    let i_ps_raw = match material {
        Material::Metallic => intensity * specular * a * a,
        Material::Water => intensity * a,
    };
    let contrast_ok = i_ps_raw >= threshold * ambient;
    let tir_margin = 1.0 - eta * eta * (1.0 - cos_theta * cos_theta);
    let tir = material == Material::Water && tir_margin < 0.0;
    ConditionTwin {
        glare: contrast_ok && (material == Material::Metallic || tir),
        tir,
        i_ps: i_ps_raw.min(out_max),
        contrast_ok,
        i_ps_raw,
        tir_margin,
    }
}
