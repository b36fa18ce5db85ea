//! Surface materials of scene objects (the models of Shinya's survey): which reflection model an object's
//! surface follows, with its parameters, and how the hardware renders its specular
//! term. An object without a material is the Lambert surface of its `color`, as in
//! every scene written before materials existed (those files load unchanged).

use rtl_model::error::ConfigError;
use serde::{Deserialize, Serialize};

use super::fields;

/// `objects[i].material`: a reflection model and its parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "snake_case", deny_unknown_fields)]
pub enum Material {
    /// Lambert: the object's `color` is the albedo.
    Lambert,
    /// Phong: k_s·cos^n of the angle between the mirror direction and the view, plus
    /// the Lambert term of `color`. `normalized` uses (n + 2)/2π.
    Phong {
        ks: f64,
        exponent: f64,
        #[serde(default)]
        normalized: bool,
    },
    /// Blinn–Phong: k_s·(n·h)^n plus Lambert.
    BlinnPhong {
        ks: f64,
        exponent: f64,
        #[serde(default)]
        normalized: bool,
    },
    /// Cook–Torrance microfacets: D·F·G / (4 cos θ_i cos θ_o). `roughness` is the
    /// Beckmann m or the GGX α; `ior` the real part of the index of refraction,
    /// `extinction` its imaginary part (0 = dielectric, > 0 = metal).
    CookTorrance {
        #[serde(default)]
        distribution: Distribution,
        roughness: f64,
        ior: f64,
        #[serde(default)]
        extinction: f64,
        #[serde(default)]
        fresnel: FresnelKind,
    },
    /// Ward's anisotropic Gaussian: ρ_s, α_x along the tangent, α_y across it.
    Ward {
        rho_s: f64,
        alpha_x: f64,
        alpha_y: f64,
    },
    /// Oren–Nayar rough diffuse, σ in degrees; `color` is the albedo.
    OrenNayar { sigma_deg: f64 },
    /// Kajiya–Kay hair along the tangent: k_s·cos^n(θ_i − θ_o) plus the sin term.
    KajiyaKay { ks: f64, exponent: f64 },
}

/// The microfacet normal distribution.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Distribution {
    #[default]
    Beckmann,
    Ggx,
}

/// The Fresnel term.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FresnelKind {
    /// The exact dielectric / conductor equations.
    #[default]
    Exact,
    /// Schlick's approximation from the normal-incidence reflectance.
    Schlick,
}

pub use super::bounds::EXPONENT_MAX;

impl Material {
    /// Check the parameters; errors name `material.<field>`.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let f = |name: &str| format!("material.{name}");
        match *self {
            Material::Lambert => Ok(()),
            Material::Phong { ks, exponent, .. } | Material::BlinnPhong { ks, exponent, .. } => {
                fields::MATERIAL_KS.real(&f("ks"), ks)?;
                fields::MATERIAL_EXPONENT.real(&f("exponent"), exponent)
            }
            Material::CookTorrance {
                roughness,
                ior,
                extinction,
                ..
            } => {
                fields::MATERIAL_ROUGHNESS.real(&f("roughness"), roughness)?;
                fields::MATERIAL_IOR.real(&f("ior"), ior)?;
                fields::MATERIAL_EXTINCTION.real(&f("extinction"), extinction)
            }
            Material::Ward {
                rho_s,
                alpha_x,
                alpha_y,
            } => {
                fields::MATERIAL_RHO_S.real(&f("rho_s"), rho_s)?;
                fields::MATERIAL_ALPHA_X.real(&f("alpha_x"), alpha_x)?;
                fields::MATERIAL_ALPHA_Y.real(&f("alpha_y"), alpha_y)
            }
            // The reference takes σ ≤ 1.5 rad (85.9°).
            Material::OrenNayar { sigma_deg } => {
                fields::MATERIAL_SIGMA_DEG.real(&f("sigma_deg"), sigma_deg)
            }
            Material::KajiyaKay { ks, exponent } => {
                fields::MATERIAL_KS.real(&f("ks"), ks)?;
                fields::MATERIAL_EXPONENT.real(&f("exponent"), exponent)
            }
        }
    }

    /// Whether the model has a specular term (a highlight the glare conditions read).
    pub fn has_specular(&self) -> bool {
        !matches!(self, Material::Lambert | Material::OrenNayar { .. })
    }

    /// A metal (complex index of refraction): Table 2's "metallic" rule applies.
    pub fn is_metal(&self) -> bool {
        matches!(self, Material::CookTorrance { extinction, .. } if *extinction > 0.0)
    }

    /// The model's name as in the scene file.
    pub fn model_name(&self) -> &'static str {
        match self {
            Material::Lambert => "lambert",
            Material::Phong { .. } => "phong",
            Material::BlinnPhong { .. } => "blinn_phong",
            Material::CookTorrance { .. } => "cook_torrance",
            Material::Ward { .. } => "ward",
            Material::OrenNayar { .. } => "oren_nayar",
            Material::KajiyaKay { .. } => "kajiya_kay",
        }
    }
}
