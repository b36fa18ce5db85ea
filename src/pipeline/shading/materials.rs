//! What a material is, on both sides: the f64 reference BRDF of a scene material
//! (`scene::material::Material` with the object's `color`), and the hardware path
//! that renders it ([`super::path::ShadingPath`]).
//!
//! A material is a Lambert term of the object's `color` plus its model's lobe, except
//! a metal (Cook–Torrance with extinction > 0), which has no diffuse term, and the
//! diffuse models (Lambert, Oren–Nayar), which are their own term. On the hardware,
//! the Lambert term is DOT3 + MODULATE, the Phong and Blinn–Phong lobes the specular
//! lookup (indexed by r·l and n·h), and every other lobe factor textures.

use super::factor::FactorTarget;
use super::path::{LobeVector, PathConfig, ShadingPath, SpecularLobe};
use crate::reference::brdf::cook_torrance::{
    CookTorrance, CookTorranceParams, Fresnel, Masking, MicrofacetDistribution,
};
use crate::reference::brdf::kajiya_kay::{KajiyaKay, KajiyaKayParams};
use crate::reference::brdf::lambert::Lambert;
use crate::reference::brdf::oren_nayar::{OrenNayar, OrenNayarForm, OrenNayarParams};
use crate::reference::brdf::phong::{BlinnPhong, Phong, PhongForm, PhongParams};
use crate::reference::brdf::ward::{Ward, WardForm, WardParams};
use crate::reference::brdf::{Brdf, BrdfParamError};
use crate::scene::material::{Distribution, FresnelKind, Material};
use crate::scene::math::Vec3;
use rtl_model::ConfigError;

/// A reference parameter error as a config error naming `material.<param>`.
fn param_error(e: BrdfParamError) -> ConfigError {
    ConfigError::invalid(&format!("material.{}", e.param), &e.to_string())
}

/// The specular lobe of a material alone (None for the diffuse models).
pub fn lobe_brdf(m: &Material) -> Result<Option<Box<dyn Brdf>>, ConfigError> {
    let phong = |ks: f64, exponent: f64, normalized: bool| PhongParams {
        k_s: ks,
        exponent,
        form: if normalized {
            PhongForm::Normalised
        } else {
            PhongForm::Classic
        },
    };
    Ok(Some(match *m {
        Material::Lambert | Material::OrenNayar { .. } => return Ok(None),
        Material::Phong {
            ks,
            exponent,
            normalized,
        } => Box::new(Phong::new(phong(ks, exponent, normalized)).map_err(param_error)?),
        Material::BlinnPhong {
            ks,
            exponent,
            normalized,
        } => Box::new(BlinnPhong::new(phong(ks, exponent, normalized)).map_err(param_error)?),
        Material::CookTorrance {
            distribution,
            roughness,
            ior,
            extinction,
            fresnel,
        } => {
            let exact = if extinction > 0.0 {
                Fresnel::Conductor {
                    eta: ior,
                    k: extinction,
                }
            } else {
                Fresnel::Dielectric { eta: ior }
            };
            Box::new(
                CookTorrance::new(CookTorranceParams {
                    distribution: match distribution {
                        Distribution::Beckmann => MicrofacetDistribution::Beckmann,
                        Distribution::Ggx => MicrofacetDistribution::Ggx,
                    },
                    alpha: roughness,
                    fresnel: match fresnel {
                        FresnelKind::Exact => exact,
                        FresnelKind::Schlick => Fresnel::schlick_from_ior(ior, extinction),
                    },
                    masking: Masking::VCavity,
                })
                .map_err(param_error)?,
            )
        }
        Material::Ward {
            rho_s,
            alpha_x,
            alpha_y,
        } => Box::new(
            Ward::new(WardParams {
                rho_s,
                alpha_x,
                alpha_y,
                form: WardForm::Original,
            })
            .map_err(param_error)?,
        ),
        Material::KajiyaKay { ks, exponent } => Box::new(
            KajiyaKay::new(KajiyaKayParams {
                k_d: 0.0,
                k_s: ks,
                exponent,
            })
            .map_err(param_error)?,
        ),
    }))
}

/// The Lambert albedo a material adds to its lobe (None for a metal, and for
/// Oren–Nayar, whose own term replaces it). Grey: the mean of `color`.
fn lambert_albedo(m: &Material, color: [f64; 3]) -> Option<[f64; 3]> {
    match m {
        _ if color == [0.0; 3] => None,
        Material::OrenNayar { .. } => None,
        m if m.is_metal() => None,
        _ => Some(color),
    }
}

/// The whole reference BRDF of a material on an object of `color` (grey: the mean of
/// the colour channels, as the scalar reference images are).
pub struct MaterialBrdf {
    pub lambert: Option<Lambert>,
    pub lobe: Option<Box<dyn Brdf>>,
    pub oren_nayar: Option<OrenNayar>,
}

impl MaterialBrdf {
    pub fn new(m: &Material, color: [f64; 3]) -> Result<Self, ConfigError> {
        let grey = (color[0] + color[1] + color[2]) / 3.0;
        let oren_nayar = match *m {
            Material::OrenNayar { sigma_deg } => Some(
                OrenNayar::new(OrenNayarParams {
                    rho: grey,
                    sigma: sigma_deg.to_radians(),
                    form: OrenNayarForm::Full,
                })
                .map_err(param_error)?,
            ),
            _ => None,
        };
        Ok(MaterialBrdf {
            lambert: lambert_albedo(m, color)
                .map(|c| Lambert::new((c[0] + c[1] + c[2]) / 3.0).map_err(param_error))
                .transpose()?,
            lobe: lobe_brdf(m)?,
            oren_nayar,
        })
    }
}

impl Brdf for MaterialBrdf {
    fn name(&self) -> String {
        let mut parts = Vec::new();
        if let Some(l) = &self.lambert {
            parts.push(l.name());
        }
        if let Some(o) = &self.oren_nayar {
            parts.push(o.name());
        }
        if let Some(l) = &self.lobe {
            parts.push(l.name());
        }
        parts.join("+")
    }
    fn eval(&self, wi: Vec3, wo: Vec3) -> f64 {
        self.lambert.as_ref().map_or(0.0, |l| l.eval(wi, wo))
            // The full Oren–Nayar fit dips below zero near grazing for rough, dark
            // surfaces (σ ≳ 0.8, ρ ≲ 0.5, Δφ near π); a radiance cannot, and the
            // hardware's unorm factor textures cannot hold it: clamped at 0.
            + self.oren_nayar.as_ref().map_or(0.0, |o| o.eval(wi, wo).max(0.0))
            + self.lobe.as_ref().map_or(0.0, |l| l.eval(wi, wo))
    }
}

/// Which specular datapath [`material_path`] gives a material: `"none"` (Lambert),
/// `"lookup"` (Phong, Blinn–Phong) or `"factored"` (every other model).
pub fn lobe_kind(m: &Material) -> &'static str {
    match m {
        Material::Lambert => "none",
        Material::Phong { .. } | Material::BlinnPhong { .. } => "lookup",
        _ => "factored",
    }
}

/// The hardware path of a material on an object of `color`.
pub fn material_path(
    m: &Material,
    color: [f64; 3],
    cfg: &PathConfig,
) -> Result<ShadingPath, ConfigError> {
    // k_s times the form's normalisation (1 for the classic form).
    let lookup = |ks: f64, exponent: f64, normalized: bool, norm: fn(f64) -> f64, vector| {
        SpecularLobe::Lookup {
            k: ks * if normalized { norm(exponent) } else { 1.0 },
            exponent,
            vector,
        }
    };
    let lobe = match *m {
        Material::BlinnPhong {
            ks,
            exponent,
            normalized,
        } => lookup(
            ks,
            exponent,
            normalized,
            BlinnPhong::normalisation,
            LobeVector::Half,
        ),
        Material::Phong {
            ks,
            exponent,
            normalized,
        } => lookup(
            ks,
            exponent,
            normalized,
            Phong::normalisation,
            LobeVector::Mirror,
        ),
        Material::OrenNayar { .. } => match MaterialBrdf::new(m, color)?.oren_nayar {
            Some(o) => SpecularLobe::Factored(Box::new(o), cfg.factor_method, FactorTarget::Brdf),
            None => SpecularLobe::None,
        },
        _ => match lobe_brdf(m)? {
            Some(b) => SpecularLobe::Factored(b, cfg.factor_method, FactorTarget::BrdfCosine),
            None => SpecularLobe::None,
        },
    };
    ShadingPath::new(lambert_albedo(m, color), lobe, cfg)
}
