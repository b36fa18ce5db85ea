//! `reproduce shading-brdfs`: one sphere per reflection model, rendered through the
//! shading units ([`super::path`]) beside its f64 reference, with the ×8 difference
//! and mean / RMS / max error per model (CSV + PNG grid).

use super::materials::{material_path, MaterialBrdf};
use super::path::{PathConfig, PathCounters, ShadingPath};
use super::sphere::{SphereView, VIEW};
use crate::reference::brdf::Brdf;
use crate::report::image_out::grey_image;
use crate::report::metrics::{error_stats_masked, ErrorStats};
use crate::scene::material::{Distribution, FresnelKind, Material};
use image::RgbaImage;
use rtl_model::ConfigError;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// One sphere of the catalogue: a label, the material and the object colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CatalogueEntry {
    pub label: &'static str,
    pub material: Material,
    pub color: [f64; 3],
    /// The light's direction for this sphere (toward the light), when it is not the
    /// view's: a light behind the sphere shows the Fresnel rim.
    pub light: Option<[f64; 3]>,
}

/// The models of the shading seed, one sphere each: diffuse models with a grey
/// albedo, specular lobes alone (no Lambert term) so the lobe is what the image shows,
/// a dielectric with a dim base, and the same dielectric lit from behind, where the
/// Fresnel term brightens the rim.
pub fn catalogue() -> Vec<CatalogueEntry> {
    let none = [0.0; 3];
    let grey = [0.8; 3];
    let dielectric = Material::CookTorrance {
        distribution: Distribution::Ggx,
        roughness: 0.3,
        ior: 1.5,
        extinction: 0.0,
        fresnel: FresnelKind::Exact,
    };
    vec![
        CatalogueEntry {
            label: "lambert",
            material: Material::Lambert,
            color: grey,
            light: None,
        },
        CatalogueEntry {
            label: "oren_nayar",
            material: Material::OrenNayar { sigma_deg: 30.0 },
            color: grey,
            light: None,
        },
        CatalogueEntry {
            label: "phong",
            material: Material::Phong {
                ks: 0.6,
                exponent: 32.0,
                normalized: true,
            },
            color: none,
            light: None,
        },
        CatalogueEntry {
            label: "blinn_phong",
            material: Material::BlinnPhong {
                ks: 0.6,
                exponent: 64.0,
                normalized: true,
            },
            color: none,
            light: None,
        },
        CatalogueEntry {
            label: "cook_torrance_metal",
            material: Material::CookTorrance {
                distribution: Distribution::Beckmann,
                roughness: 0.2,
                ior: 0.27,
                extinction: 2.8,
                fresnel: FresnelKind::Exact,
            },
            color: none,
            light: None,
        },
        CatalogueEntry {
            label: "cook_torrance_dielectric",
            material: dielectric,
            color: [0.15; 3],
            light: None,
        },
        CatalogueEntry {
            label: "cook_torrance_backlit",
            material: dielectric,
            color: none,
            light: Some([-0.75, 0.25, -0.6]),
        },
        CatalogueEntry {
            label: "ward",
            material: Material::Ward {
                rho_s: 0.5,
                alpha_x: 0.3,
                alpha_y: 0.075,
            },
            color: none,
            light: None,
        },
        CatalogueEntry {
            label: "kajiya_kay",
            material: Material::KajiyaKay {
                ks: 0.5,
                exponent: 32.0,
            },
            color: none,
            light: None,
        },
    ]
}

/// One model's sphere: the hardware levels and the reference levels (grey, per pixel,
/// row-major; background 0), the coverage mask, and what it cost.
pub struct SphereRender {
    pub hardware: Vec<f64>,
    pub reference: Vec<f64>,
    pub mask: Vec<bool>,
    pub counters: PathCounters,
    pub path: ShadingPath,
    pub wall_seconds: f64,
}

/// Render one catalogue entry on the view through the units and the reference.
pub fn render_sphere(
    e: &CatalogueEntry,
    view: &SphereView,
    cfg: &PathConfig,
) -> Result<SphereRender, ConfigError> {
    render_sphere_against(e, view, cfg, sphere_reference(e, view)?)
}

/// The entry's view: `view` under the entry's own light, if it has one.
pub fn entry_view(e: &CatalogueEntry, view: &SphereView) -> SphereView {
    match e.light {
        Some(l) => SphereView {
            light: crate::scene::math::v3(l[0], l[1], l[2]).normalized(),
            ..*view
        },
        None => *view,
    }
}

/// The f64 reference levels of one catalogue entry's sphere (what [`render_sphere`]
/// compares with; it depends on no width, so a search draws it once).
pub fn sphere_reference(e: &CatalogueEntry, view: &SphereView) -> Result<Vec<f64>, ConfigError> {
    let brdf = MaterialBrdf::new(&e.material, e.color)?;
    Ok(entry_view(e, view).reference_levels(&brdf))
}

/// [`render_sphere`] against a reference drawn before ([`sphere_reference`] of the
/// same entry and view).
pub fn render_sphere_against(
    e: &CatalogueEntry,
    view: &SphereView,
    cfg: &PathConfig,
    reference: Vec<f64>,
) -> Result<SphereRender, ConfigError> {
    let view = &entry_view(e, view);
    let path = material_path(&e.material, e.color, cfg)?;
    let t0 = Instant::now();
    let mut counters = PathCounters::new();
    let mut hardware = Vec::with_capacity(reference.len());
    let mut mask = Vec::with_capacity(reference.len());
    for p in view.pixels() {
        match p {
            Some(p) => {
                let s = path.shade(&p.frame, view.light, VIEW, &mut counters)?;
                hardware.push(s.rgb[0] as f64);
                mask.push(true);
            }
            None => {
                hardware.push(0.0);
                mask.push(false);
            }
        }
    }
    path.close_counters(&mut counters);
    Ok(SphereRender {
        hardware,
        reference,
        mask,
        counters,
        path,
        wall_seconds: t0.elapsed().as_secs_f64(),
    })
}

/// Mean / RMS / max |Δ| over the covered pixels, in 8-bit levels.
pub fn sphere_error(r: &SphereRender) -> Result<ErrorStats, ConfigError> {
    let rgb = |v: &[f64]| v.iter().map(|&x| [x; 3]).collect::<Vec<_>>();
    error_stats_masked(&rgb(&r.hardware), &rgb(&r.reference), &r.mask)
}

/// The view of `shading-brdfs` (and of `shading-factorization`): the default 256²
/// sphere under E = π, so a white Lambert surface lit head-on is full scale.
pub fn brdfs_view() -> SphereView {
    SphereView {
        irradiance: std::f64::consts::PI,
        ..SphereView::default()
    }
}

/// One CSV row.
#[derive(Clone, Debug, Serialize)]
pub struct BrdfRow {
    pub model: String,
    pub reference: String,
    pub hardware_path: String,
    pub mean_abs: f64,
    pub rms: f64,
    pub max: f64,
    pub pixels: u64,
    pub gates_nand2: f64,
    pub ram_bits: u64,
    pub wall_seconds: f64,
}

/// Run the catalogue on the default view (256², E = π) and path; write
/// `shading_brdfs.csv` and `shading_brdfs.png` (per model: hardware, reference,
/// |Δ| × 8) into `out`.
pub fn shading_brdfs(out: &Path) -> Result<Vec<BrdfRow>, String> {
    let view = brdfs_view();
    let cfg = PathConfig::default();
    std::fs::create_dir_all(out).map_err(|e| format!("out: {}: {e}", out.display()))?;
    let mut rows = Vec::new();
    let mut panels: Vec<(String, RgbaImage)> = Vec::new();
    for e in catalogue() {
        let r = render_sphere(&e, &view, &cfg).map_err(|err| format!("{}: {err}", e.label))?;
        let st = sphere_error(&r).map_err(|err| err.to_string())?;
        let elab = r.path.elaboration(st.n / 3);
        let present = elab.iter().filter_map(|u| u.summary.as_ref());
        let (gates, ram) = present.fold((0.0, 0), |(g, b), s| (g + s.gates_nand2, b + s.ram_bits));
        let diff: Vec<f64> = r
            .hardware
            .iter()
            .zip(&r.reference)
            .map(|(h, f)| (h - f).abs() * 8.0)
            .collect();
        panels.push((
            format!("{} (units)", e.label),
            grey_image(&r.hardware, view.size),
        ));
        panels.push((
            format!("{} (f64)", e.label),
            grey_image(&r.reference, view.size),
        ));
        panels.push((format!("{} |Δ|×8", e.label), grey_image(&diff, view.size)));
        rows.push(BrdfRow {
            model: e.label.to_string(),
            reference: MaterialBrdf::new(&e.material, e.color)
                .map_err(|err| err.to_string())?
                .name(),
            hardware_path: r.path.describe(),
            mean_abs: st.mean_abs,
            rms: st.rms,
            max: st.max,
            pixels: st.n / 3,
            gates_nand2: gates,
            ram_bits: ram,
            wall_seconds: r.wall_seconds,
        });
    }
    crate::report::csv_out::write_csv(&out.join("shading_brdfs.csv"), &rows)?;
    let refs: Vec<(&str, &RgbaImage)> = panels.iter().map(|(c, i)| (c.as_str(), i)).collect();
    crate::report::plot::image_grid(&out.join("shading_brdfs.png"), &refs, 6)?;
    Ok(rows)
}

/// The rows as a terminal table.
pub fn table(rows: &[BrdfRow]) -> String {
    let body: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.model.clone(),
                r.hardware_path.clone(),
                format!("{:.2}", r.mean_abs),
                format!("{:.2}", r.rms),
                format!("{:.0}", r.max),
                format!("{:.0}", r.gates_nand2),
                r.ram_bits.to_string(),
            ]
        })
        .collect();
    crate::report::table::text_table(
        &[
            "model",
            "hardware path",
            "mean |Δ|",
            "RMS",
            "max",
            "gates",
            "RAM bits",
        ],
        &body,
    )
}

/// The lobe `shading-factorization` factorises: the catalogue's Cook–Torrance metal,
/// so its error is measured on the same sphere and model as `shading-brdfs`.
pub fn factorization_brdf() -> Result<Box<dyn Brdf>, ConfigError> {
    let e = catalogue()
        .into_iter()
        .find(|e| e.label == "cook_torrance_metal")
        .expect("the catalogue has the metal");
    super::materials::lobe_brdf(&e.material)?
        .ok_or_else(|| ConfigError::invalid("material", "the metal has a lobe"))
}
