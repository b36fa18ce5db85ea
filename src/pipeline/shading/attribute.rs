//! `attribute --scene shading-<name>` (`report::attribution`): the shading
//! pipeline's error sources, each an elaborated unit's width or table size set to the
//! widest its config takes.
//!
//! Renders go through the functions `sweep --scene shading-*` uses: a catalogue
//! model's sphere through [`render_sphere`] (its [`PathConfig`]) against the f64
//! BRDF's levels; `shading-specular`'s texture-shader lookup path through
//! [`sphere_vectors`] and [`lookup_levels`] against 255·(n̂·ĥ)^32 (the sweep's
//! `cube_*` / `lookup_*` rows). Pixels off the sphere are 0 in both. "Ideal" for each
//! source (a source is listed only where the scene's path elaborates its unit, as
//! `params_of` says):
//!
//! | scene | source | configured → ideal |
//! |---|---|---|
//! | every model | normalisation cube resolution | `cube.face_side` 64 → 512 |
//! | Phong, Blinn–Phong | specular lookup table size | `lookup.table_log2` 8 → 12 |
//! | Phong, Blinn–Phong | specular lookup weight | `lookup.weight_bits` 8 → 16 |
//! | factored lobes | BRDF factor-texture resolution | `factor_resolution` 64 → 256 |
//! | factored lobes | factor texel bits | `factor_bits` 8 → 16 |
//! | factored lobes | combiner chain rounding | `rounding.chain` per_stage → fused |
//! | shading-specular | cube resolution | `cube.face_side` 256 → 512 |
//! | shading-specular | lookup table size | `lookup.table_log2` 8 → 12 |
//! | shading-specular | lookup weight | `lookup.weight_bits` 8 → 16 |
//! | shading-specular | lookup entries (output rounding) | `lookup.entry_bits` 8 → 16 (the level is entry·255/(2^bits − 1), no longer whole) |
//!
//! Not sources: the models' cube texel and lookup entry widths (the path hands both
//! to 8-bit texture combiners unconverted, so only 8 bits render correctly: the
//! sweep's own rule), `shading-specular`'s cube texels (16 bits, already the widest),
//! and the models' output rounding: the combiners write whole 8-bit levels, which is
//! the frame buffer, so it stays in the bound below. The factorisation of a factored
//! lobe (rank-1 SVD) is the method, not a width: no config removes it, so for those
//! models "all ideal" is reported but not expected to meet the bound. `shading-vertex`
//! has no image (it lights sphere vertices) and is refused, naming `scene`.

use super::brdfs::{render_sphere, CatalogueEntry};
use super::materials::{lobe_kind, material_path};
use super::path::PathConfig;
use super::specular::{lookup_levels, reference_levels, sphere_vectors};
use super::sphere::SphereView;
use super::sweep::{LookupPathConfig, ShadingScene, SPECULAR_K};
use crate::report::attribution::{attribute, Attribution, Bound, Rendered, Source};
use rtl_model::units::modulate::ChainRounding;
use rtl_model::Counters;
use std::path::Path;

/// What one shading render is: the scene, the sphere view and every unit's config.
#[derive(Clone, Debug)]
pub struct ShadingConfig {
    pub scene: ShadingScene,
    pub view: SphereView,
    /// A catalogue model's path (unused by `shading-specular`).
    pub path: PathConfig,
    /// `shading-specular`'s lookup path (unused by the models).
    pub lookup_path: LookupPathConfig,
}

impl ShadingConfig {
    /// The scene as the sweep renders it at its defaults, on a `size`² view (E = π).
    pub fn new(scene: &str, size: u32) -> Result<ShadingConfig, String> {
        let sc = ShadingScene::parse(scene)?;
        if sc == ShadingScene::Vertex {
            return Err(format!(
                "scene: '{scene}' lights sphere vertices and has no image to attribute \
                 (attribute covers shading-<model> and shading-specular)"
            ));
        }
        rtl_model::error::check_range("image", size.into(), 2, 4096).map_err(|e| e.to_string())?;
        Ok(ShadingConfig {
            scene: sc,
            view: SphereView {
                size,
                irradiance: std::f64::consts::PI,
                ..SphereView::default()
            },
            path: PathConfig::default(),
            lookup_path: LookupPathConfig::default(),
        })
    }

    /// Build every unit the render elaborates (a bad width is an error naming it).
    pub fn check(&self) -> Result<(), String> {
        let e = |x: rtl_model::ConfigError| x.to_string();
        match self.scene {
            ShadingScene::Model(m) => {
                material_path(&m.material, m.color, &self.path).map_err(e)?;
            }
            _ => {
                let c = &self.lookup_path;
                c.cube.build().map_err(e)?;
                rtl_model::units::specular_lookup::SpecularLookupConfig {
                    in_bits: c.cube.texel_bits,
                    ..c.lookup
                }
                .build()
                .map_err(e)?;
            }
        }
        Ok(())
    }
}

fn source(
    name: &str,
    ideal: String,
    f: impl Fn(&mut ShadingConfig) + 'static,
) -> Source<ShadingConfig> {
    Source {
        name: name.into(),
        ideal,
        make_ideal: Box::new(f),
    }
}

/// The sources of a shading scene (module notes).
pub fn sources(base: &ShadingConfig) -> Vec<Source<ShadingConfig>> {
    let mut v = Vec::new();
    match base.scene {
        ShadingScene::Model(CatalogueEntry { material, .. }) => {
            let p = &base.path;
            v.push(source(
                "normalisation cube resolution",
                format!("cube.face_side {} → 512", p.cube.face_side),
                |s| s.path.cube.face_side = 512,
            ));
            match lobe_kind(&material) {
                "none" => {}
                "lookup" => {
                    v.push(source(
                        "specular lookup table size",
                        format!("lookup.table_log2 {} → 12", p.lookup.table_log2),
                        |s| s.path.lookup.table_log2 = 12,
                    ));
                    v.push(source(
                        "specular lookup weight",
                        format!("lookup.weight_bits {} → 16", p.lookup.weight_bits),
                        |s| s.path.lookup.weight_bits = 16,
                    ));
                }
                _ => {
                    v.push(source(
                        "factor texture resolution",
                        format!("factor_resolution {} → 256", p.factor_resolution),
                        |s| s.path.factor_resolution = 256,
                    ));
                    v.push(source(
                        "factor texel bits",
                        format!("factor_bits {} → 16", p.factor_bits),
                        |s| s.path.factor_bits = 16,
                    ));
                    v.push(source(
                        "combiner chain rounding",
                        format!("rounding.chain {:?} → Fused", p.rounding.chain),
                        |s| s.path.rounding.chain = ChainRounding::Fused,
                    ));
                }
            }
        }
        _ => {
            let c = &base.lookup_path;
            v.push(source(
                "normalisation cube resolution",
                format!("cube.face_side {} → 512", c.cube.face_side),
                |s| s.lookup_path.cube.face_side = 512,
            ));
            v.push(source(
                "specular lookup table size",
                format!("lookup.table_log2 {} → 12", c.lookup.table_log2),
                |s| s.lookup_path.lookup.table_log2 = 12,
            ));
            v.push(source(
                "specular lookup weight",
                format!("lookup.weight_bits {} → 16", c.lookup.weight_bits),
                |s| s.lookup_path.lookup.weight_bits = 16,
            ));
            v.push(source(
                "lookup entries (output rounding)",
                format!("lookup.entry_bits {} → 16", c.lookup.entry_bits),
                |s| s.lookup_path.lookup.entry_bits = 16,
            ));
        }
    }
    v
}

/// The bound of "all ideal" (lookup lobes, Lambert and shading-specular): the
/// output is whole 8-bit levels (≤ 0.5 level) after 8-bit DOT3 and MODULATE stages
/// (≤ 0.5 level each before the lobe's slope): the mean |Δ| over the image (off-sphere
/// pixels count, both 0) is held to 0.5 level and at most 1 % of the values (the
/// sphere's outline and the highlight's steepest ring, where one code of n·h moves the
/// lobe by several levels) may be off by more than 2 levels.
pub fn bound() -> Bound {
    Bound {
        mean_abs: 0.5,
        outlier_fraction: 0.01,
        outlier_levels: 2.0,
        why: "mean |Δ| ≤ 0.5 level (8-bit output and stage rounding); ≤ 1 % of the values off by > 2 levels (outline, highlight ring)"
            .into(),
    }
}

/// One render and its reference, grey levels as RGB.
pub fn render(c: &ShadingConfig) -> Result<Rendered, String> {
    let rgb = |v: &[f64]| v.iter().map(|&x| [x; 3]).collect::<Vec<_>>();
    match c.scene {
        ShadingScene::Model(m) => {
            let r = render_sphere(&m, &c.view, &c.path).map_err(|e| e.to_string())?;
            Ok((rgb(&r.hardware), rgb(&r.reference)))
        }
        _ => {
            let l = &c.lookup_path;
            let cube = l.cube.build().map_err(|e| e.to_string())?;
            let v = sphere_vectors(&c.view, &cube).map_err(|e| e.to_string())?;
            let s = (1u32 << SPECULAR_K) as f64;
            let mut ctr = Counters::default();
            let hw = lookup_levels(&v, l.cube.texel_bits, s, l.lookup, &mut ctr)
                .map_err(|e| e.to_string())?;
            Ok((rgb(&hw), rgb(&reference_levels(&v, s))))
        }
    }
}

/// Attribute the error of the shading scene `c` into `out`.
pub fn attribute_shading(c: &ShadingConfig, out: &Path) -> Result<Attribution, String> {
    let n = c.view.size;
    attribute(
        &c.scene.name(),
        c,
        (n, n),
        &sources(c),
        &bound(),
        ShadingConfig::check,
        render,
        out,
    )
}

/// The CLI's config: `scene` a `shading-*` name, `image` (as `--image WxH` gave it)
/// the square sphere view's side (default 256, the sweep's); every unit built.
pub fn config_for_cli(scene: &str, image: Option<(u32, u32)>) -> Result<ShadingConfig, String> {
    let size = match image {
        Some((w, h)) if w != h => {
            return Err(format!("--image: the sphere view is square, not {w}x{h}"))
        }
        Some((w, _)) => w,
        None => super::sweep::ShadingSweepOptions::default().view_size,
    };
    let c = ShadingConfig::new(scene, size)?;
    c.check()?;
    Ok(c)
}

/// The shading units' sources in a frame scene (`[shading_hw]`; `frame::attribute`):
/// the normalisation cube's face side for every material, the specular lookup's size
/// where a Phong or Blinn–Phong material runs it, the factor textures' side and texel
/// bits where a factored material does; each set to the widest this module's sphere
/// attribution uses.
pub fn scene_sources(
    base: &crate::scene::format::Scene,
) -> Vec<Source<crate::scene::format::Scene>> {
    use crate::scene::shading_hw::ShadingHw;
    let hw = base.shading_hw.unwrap_or_default();
    let kinds: Vec<&str> = base
        .objects
        .iter()
        .filter_map(|o| o.material.as_ref().map(lobe_kind))
        .collect();
    let mut v: Vec<Source<crate::scene::format::Scene>> = Vec::new();
    let mut add = |name: &str, field: &str, from: u32, to: u32, set: fn(&mut ShadingHw, u32)| {
        let to = to.max(from);
        v.push(Source {
            name: name.into(),
            ideal: format!("shading_hw.{field} {from} → {to}"),
            make_ideal: Box::new(move |s| {
                set(s.shading_hw.get_or_insert_with(Default::default), to)
            }),
        })
    };
    if kinds.is_empty() {
        return v;
    }
    add(
        "normalisation cube resolution",
        "cube_face",
        hw.cube_face,
        512,
        |h, x| h.cube_face = x,
    );
    if kinds.contains(&"lookup") {
        add(
            "specular lookup table size",
            "lookup_log2",
            hw.lookup_log2,
            12,
            |h, x| h.lookup_log2 = x,
        );
    }
    if kinds.contains(&"factored") {
        add(
            "factor texture resolution",
            "factor_size",
            hw.factor_size,
            256,
            |h, x| h.factor_size = x,
        );
        add(
            "factor texel bits",
            "factor_bits",
            hw.factor_bits,
            16,
            |h, x| h.factor_bits = x,
        );
    }
    v
}
