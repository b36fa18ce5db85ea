//! `sweep --scene shading-<name>`: error against run time for one shading width, the
//! shading pipeline's counterpart of the glare and shafts sweeps (same CSV row shape,
//! same plot).
//!
//! Scenes:
//! - `shading-<model>`, a label of [`super::brdfs::catalogue`] (`shading-lambert`,
//!   `shading-blinn_phong`, `shading-cook_torrance_metal`, …): the model's sphere
//!   through its [`super::path::ShadingPath`] (E = π, as `reproduce shading-brdfs`)
//!   against the f64 reference. Widths: `cube_face` (every model), `lookup_log2`
//!   (Phong and Blinn–Phong, the lookup's lobes), `factor_size` and `factor_bits` (the factored
//!   lobes: every model but Lambert and Blinn–Phong). The cube's texel width and the
//!   lookup's entry width are `shading-specular`'s only: the path feeds both to 8-bit
//!   texture combiners unconverted, so only 8 bits are meaningful on it.
//! - `shading-specular`: (n·h)^32 on the sphere against 255·(n̂·ĥ)^32, as
//!   `reproduce shading-specular`. `combiner_bits` is the register combiners' internal
//!   width of the squaring path (8-bit 64² cube, DOT3 and five squarings); `cube_face`,
//!   `cube_bits`, `lookup_log2`, `lookup_bits` change the texture-shader lookup path
//!   (its defaults: a 256² cube of 16-bit texels, bilinear, DOT3 and lookup index at
//!   the cube's width, the GeForce lookup table).
//! - `shading-vertex`: the `vertex_lighting` unit on the tessellated sphere of
//!   `shading-vertex-float` (one light), against the f64 GL twin's ideal 8-bit output.
//!   Widths: `vertex_mantissa`, `vertex_exponent` of its float format.
//!
//! Every value is applied and its units built (validated) before anything runs: an
//! unknown or inapplicable `param` is an error naming `param` and listing the valid
//! ones, a bad value an error naming `values` and the unit's field.
//!
//! `predicted_hw_seconds` is the GeForce3 fill time of the shaded fragments
//! ([`crate::chip::pass_seconds`] with the textures the path
//! reads per fragment and no memory traffic: at these texel widths the pass is fill
//! bound) or, for `shading-vertex`, vertices × II at the GeForce3 clock. The widths
//! change it only through the textures a path reads (or the unit's II).

use super::brdfs::{
    catalogue, render_sphere, render_sphere_against, sphere_error, sphere_reference, CatalogueEntry,
};
use super::materials::lobe_kind;
use super::normalize_cube::{NormalizeCube, NormalizeCubeConfig};
use super::path::combiner_stage;
use super::path::PathConfig;
use super::specular::{
    cube_8bit, lookup_levels, reference_levels, sphere_vectors, squaring_levels_on, SphereVectors,
    SQUARING_BITS,
};
use super::sphere::SphereView;
use super::squaring::SquaringChain;
use super::vertex_float::{exact_levels, measure, measure_against, one_light, sphere_vertices};
use crate::chip::{pass_seconds, GpuModel, PassKind, PassStats};
use crate::report::metrics::error_stats_masked;
use crate::report::progress::try_map_with_progress;
use crate::report::resume::Journal;
use crate::report::shard::{Shard, SweepId};
use crate::report::sweep_out::{parse_int_values, shard_sweep, sweep_table, write_sweep, SweepRow};
use rtl_model::chip_preset::{ChipPreset, GL_SINGLE_COLOR};
use rtl_model::units::specular_lookup::SpecularLookupConfig;
use rtl_model::units::texture_combiner::CombineFunction;
use rtl_model::units::texture_sampler::{Filter, TextureSampler, TextureSamplerConfig};
use rtl_model::units::vertex_lighting::{VertexLighting, VertexLightingConfig};
use rtl_model::{ConfigError, Counters, UnitSummary};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Every shading width a sweep knows (each scene takes a subset: [`params_of`]).
pub const SHADING_PARAMS: &[&str] = &[
    "combiner_bits",
    "factor_size",
    "factor_bits",
    "lookup_log2",
    "lookup_bits",
    "cube_face",
    "cube_bits",
    "vertex_mantissa",
    "vertex_exponent",
];

/// The scene name prefix that selects this sweep.
pub const SCENE_PREFIX: &str = "shading-";

/// The exponent of `shading-specular`: s = 2^5 = 32 (one GeForce3 pass of squarings).
pub const SPECULAR_K: u32 = 5;

/// Rings × segments of `shading-vertex`'s sphere (as `shading-vertex-float`).
pub const VERTEX_RINGS: u32 = 48;
pub const VERTEX_SEGMENTS: u32 = 96;

/// What a `shading-*` scene renders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShadingScene {
    /// A catalogue model's sphere through its shading path.
    Model(CatalogueEntry),
    /// (n·h)^32: squaring in the register combiners, or the texture-shader lookup.
    Specular,
    /// Vertex lighting in a float format.
    Vertex,
}

impl ShadingScene {
    /// `shading-<model>`, `shading-specular` or `shading-vertex`; anything else is an
    /// error naming `scene` and listing the valid names.
    pub fn parse(name: &str) -> Result<ShadingScene, String> {
        let rest = name.strip_prefix(SCENE_PREFIX).unwrap_or("");
        match rest {
            "specular" => return Ok(ShadingScene::Specular),
            "vertex" => return Ok(ShadingScene::Vertex),
            _ => {}
        }
        catalogue()
            .into_iter()
            .find(|e| e.label == rest)
            .map(ShadingScene::Model)
            .ok_or_else(|| {
                let names = scene_names();
                let refs: Vec<&str> = names.iter().map(String::as_str).collect();
                let hint = crate::scene::load::did_you_mean(name, &refs, "");
                let hint = if hint.is_empty() {
                    String::new()
                } else {
                    format!("; {hint}")
                };
                format!(
                    "scene: unknown shading scene '{name}'{hint} (known: {})",
                    names.join(", ")
                )
            })
    }

    /// The scene's name on the command line.
    pub fn name(&self) -> String {
        match self {
            ShadingScene::Model(e) => format!("{SCENE_PREFIX}{}", e.label),
            ShadingScene::Specular => format!("{SCENE_PREFIX}specular"),
            ShadingScene::Vertex => format!("{SCENE_PREFIX}vertex"),
        }
    }
}

/// Every `shading-*` scene name.
pub fn scene_names() -> Vec<String> {
    let mut v: Vec<String> = catalogue()
        .iter()
        .map(|e| format!("{SCENE_PREFIX}{}", e.label))
        .collect();
    v.push(format!("{SCENE_PREFIX}specular"));
    v.push(format!("{SCENE_PREFIX}vertex"));
    v
}

/// The widths that reach a scene's result.
pub fn params_of(scene: &ShadingScene) -> &'static [&'static str] {
    match scene {
        ShadingScene::Model(e) => match lobe_kind(&e.material) {
            "none" => &["cube_face"],
            // Not `lookup_bits` (nor `cube_bits`): the path hands the lookup's entries
            // (and the cube's texels) to 8-bit texture combiners as they are, so only
            // 8 bits render correctly there; `shading-specular` sweeps both.
            "lookup" => &["cube_face", "lookup_log2"],
            _ => &["cube_face", "factor_size", "factor_bits"],
        },
        ShadingScene::Specular => &[
            "combiner_bits",
            "cube_face",
            "cube_bits",
            "lookup_log2",
            "lookup_bits",
        ],
        ShadingScene::Vertex => &["vertex_mantissa", "vertex_exponent"],
    }
}

/// The param's canonical name (`-` accepted for `_`) if the scene takes it; an
/// unknown name or one for another scene is an error naming `param` with the valid
/// ones.
pub fn check_param(scene: &ShadingScene, param: &str) -> Result<&'static str, String> {
    let norm = param.trim().replace('-', "_");
    let valid = params_of(scene);
    if let Some(p) = valid.iter().find(|p| **p == norm) {
        return Ok(p);
    }
    let why = if SHADING_PARAMS.contains(&norm.as_str()) {
        format!("'{param}' does not apply to {}", scene.name())
    } else {
        format!("unknown shading width '{param}'")
    };
    Err(format!(
        "param: {why} (valid for {}: {})",
        scene.name(),
        valid.join(", ")
    ))
}

/// The texture-shader lookup path of `shading-specular`: the cube the vectors come
/// from (its texel width is the DOT3's and the lookup index's) and the lookup table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LookupPathConfig {
    pub cube: NormalizeCubeConfig,
    pub lookup: SpecularLookupConfig,
}

impl Default for LookupPathConfig {
    /// `reproduce shading-specular`'s 16-bit path: 256² faces of 16-bit texels,
    /// bilinear; the GeForce lookup (256 entries of 8 bits, interpolated).
    fn default() -> Self {
        LookupPathConfig {
            cube: NormalizeCubeConfig::with(256, 16, Filter::Linear),
            lookup: SpecularLookupConfig::geforce(),
        }
    }
}

/// One configuration of a sweep, the value applied.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Job {
    Model(CatalogueEntry, PathConfig),
    /// The register combiners' internal width, and the chip whose modes they take.
    Squaring(u32, ChipPreset),
    Lookup(LookupPathConfig),
    Vertex(VertexLightingConfig),
}

/// The config of `scene` with `param` (a name [`check_param`] accepted) set to `v`.
fn job(scene: &ShadingScene, param: &str, v: u32) -> Job {
    let mut j = base_job(scene, param == "combiner_bits");
    set(&mut j, param, v);
    j
}

/// A scene's defaults: the GeForce path of a catalogue model, `shading-specular`'s
/// lookup path (its squaring path with `squaring`, at [`SQUARING_DEFAULT_BITS`]), the
/// e8m23 vertex lighting.
fn base_job(scene: &ShadingScene, squaring: bool) -> Job {
    match scene {
        ShadingScene::Model(e) => Job::Model(*e, PathConfig::default()),
        ShadingScene::Specular if squaring => {
            Job::Squaring(SQUARING_DEFAULT_BITS, ChipPreset::GeForce2)
        }
        ShadingScene::Specular => Job::Lookup(LookupPathConfig::default()),
        ShadingScene::Vertex => Job::Vertex(VertexLightingConfig::geforce()),
    }
}

/// `param` (a name [`check_param`] accepted for the job's scene) set to `v`: the
/// sweep's setter of every width.
fn set(j: &mut Job, param: &str, v: u32) {
    match j {
        Job::Model(_, c) => match param {
            "cube_face" => c.cube.face_side = v,
            "lookup_log2" => c.lookup.table_log2 = v,
            "lookup_bits" => c.lookup.entry_bits = v,
            "factor_size" => c.factor_resolution = v,
            _ => c.factor_bits = v,
        },
        Job::Squaring(bits, _) => *bits = v,
        Job::Lookup(c) => match param {
            "cube_face" => c.cube.face_side = v,
            "cube_bits" => c.cube.texel_bits = v,
            "lookup_log2" => c.lookup.table_log2 = v,
            _ => c.lookup.entry_bits = v,
        },
        Job::Vertex(c) => {
            *c = match param {
                "vertex_mantissa" => c.with_format(c.format.exp_bits, v),
                _ => c.with_format(v, c.format.mant_bits),
            }
        }
    }
}

/// The value of `param` in `j` (the inverse of [`set`]); None for a width the job's
/// path does not have.
fn get(j: &Job, param: &str) -> Option<u32> {
    Some(match (j, param) {
        (Job::Model(_, c), "cube_face") => c.cube.face_side,
        (Job::Model(_, c), "lookup_log2") => c.lookup.table_log2,
        (Job::Model(_, c), "lookup_bits") => c.lookup.entry_bits,
        (Job::Model(_, c), "factor_size") => c.factor_resolution,
        (Job::Model(_, c), "factor_bits") => c.factor_bits,
        (Job::Squaring(bits, _), "combiner_bits") => *bits,
        (Job::Lookup(c), "cube_face") => c.cube.face_side,
        (Job::Lookup(c), "cube_bits") => c.cube.texel_bits,
        (Job::Lookup(c), "lookup_log2") => c.lookup.table_log2,
        (Job::Lookup(c), "lookup_bits") => c.lookup.entry_bits,
        (Job::Vertex(c), "vertex_mantissa") => c.format.mant_bits,
        (Job::Vertex(c), "vertex_exponent") => c.format.exp_bits,
        _ => return None,
    })
}

/// Build every unit the job elaborates, without rendering: a bad width is an error
/// naming its field.
fn validate(j: &Job) -> Result<(), ConfigError> {
    match j {
        Job::Model(_, c) => {
            c.cube.build()?;
            c.lookup.build()?;
            // The factor textures' samplers at this size and texel width.
            let s = c.factor_resolution;
            let cfg = TextureSamplerConfig {
                texel_bits: c.factor_bits,
                ..TextureSamplerConfig::geforce_2d(s, s)
            };
            TextureSampler::new(cfg, &vec![0; (s as usize).saturating_mul(s as usize)])
                .map_err(|e| e.within("shading.factor"))?;
        }
        Job::Squaring(bits, chip) => {
            SquaringChain::on_chip(*bits, *chip)?;
        }
        Job::Lookup(c) => {
            c.cube.build()?;
            combiner_stage(c.cube.texel_bits, CombineFunction::Dot3Rgb, 1)?;
            SpecularLookupConfig {
                in_bits: c.cube.texel_bits,
                ..c.lookup
            }
            .build()?;
        }
        Job::Vertex(c) => {
            VertexLighting::new(*c, &one_light())?;
        }
    }
    Ok(())
}

/// One row of `sweep_<param>.csv`: the glare sweep's row (param, value, mean / RMS /
/// max levels, predicted and wall seconds, gates, RAM bits).
pub type ShadingSweepRow = SweepRow;

/// What one job measured.
struct Measured {
    mean: f64,
    rms: f64,
    max: f64,
    predicted: f64,
    wall: f64,
    gates: f64,
    ram: u64,
}

/// GeForce3 fill time of `fragments` reading `textures` textures each (no memory
/// traffic, triangles or overhead counted beyond one pass).
fn fill_seconds(fragments: u64, textures: u32) -> f64 {
    let p = PassStats {
        kind: PassKind::Objects,
        light: 0,
        walked: fragments,
        fragments,
        textures_per_fragment: textures,
        triangles: 0,
        texel_bytes: 0,
        fb_bytes: 0,
        other_bytes: 0,
        depth_tests: 0,
    };
    pass_seconds(&GpuModel::geforce3(), &p).0
}

/// Sum of gates and RAM bits.
fn total(units: &[UnitSummary]) -> (f64, u64) {
    units
        .iter()
        .fold((0.0, 0), |(g, b), s| (g + s.gates_nand2, b + s.ram_bits))
}

/// The cube's two units.
fn cube_units(c: &NormalizeCube) -> [UnitSummary; 2] {
    [
        UnitSummary::of(c.address_unit()),
        UnitSummary::of(c.sampler()),
    ]
}

/// A `shading-specular` path's row: its levels against 255·(n̂·ĥ)^32 over the covered
/// pixels, the gates and RAM of `units`, the fill time at `textures` per fragment.
fn specular_measured(
    vectors: &SphereVectors,
    hw: &[f64],
    wall: f64,
    units: &[UnitSummary],
    textures: u32,
    reference: Option<&[f64]>,
) -> Result<Measured, ConfigError> {
    let owned;
    let reference = match reference {
        Some(r) => r,
        None => {
            owned = reference_levels(vectors, (1u32 << SPECULAR_K) as f64);
            &owned
        }
    };
    let mask: Vec<bool> = vectors.iter().map(|v| v.is_some()).collect();
    let rgb = |v: &[f64]| v.iter().map(|&x| [x; 3]).collect::<Vec<_>>();
    let st = error_stats_masked(&rgb(hw), &rgb(reference), &mask)?;
    let (gates, ram) = total(units);
    Ok(Measured {
        mean: st.mean_abs,
        rms: st.rms,
        max: st.max,
        predicted: fill_seconds(st.n / 3, textures),
        wall,
        gates,
        ram,
    })
}

fn run(j: &Job, view: &SphereView) -> Result<Measured, ConfigError> {
    run_with(j, view, None).map(|(m, _)| m)
}

/// [`run`], against a reference drawn before when `reference` is given (else drawn
/// here, as the sweep does); also the hardware's levels per pixel of the view (none
/// for `shading-vertex`).
fn run_with(
    j: &Job,
    view: &SphereView,
    reference: Option<&ShadingReference>,
) -> Result<(Measured, Vec<f64>), ConfigError> {
    match j {
        Job::Model(e, cfg) => run_model(e, cfg, view, reference),
        Job::Squaring(bits, chip) => run_squaring(*bits, *chip, view, reference),
        Job::Lookup(c) => run_lookup(c, view, reference),
        Job::Vertex(c) => run_vertex(*c, reference),
    }
}

/// A reference drawn for another kind of scene than the job's.
fn reference_mismatch() -> ConfigError {
    ConfigError::invalid(
        "shading reference",
        "drawn for another kind of shading scene",
    )
}

/// The reference image's levels (None: no reference given); a vertex reference is a
/// mismatch.
fn given_levels(r: Option<&ShadingReference>) -> Result<Option<Vec<f64>>, ConfigError> {
    match r {
        None => Ok(None),
        Some(ShadingReference::Image { levels, .. }) => Ok(Some(levels.clone())),
        Some(ShadingReference::Vertex(_)) => Err(reference_mismatch()),
    }
}

/// [`run_with`] of a model's sphere through its shading path.
fn run_model(
    e: &CatalogueEntry,
    cfg: &PathConfig,
    view: &SphereView,
    reference: Option<&ShadingReference>,
) -> Result<(Measured, Vec<f64>), ConfigError> {
    // The units' shading of the sphere (render_sphere's clock: the host's
    // factorisation and the reference are not in it).
    let r = match given_levels(reference)? {
        Some(levels) => render_sphere_against(e, view, cfg, levels)?,
        None => render_sphere(e, view, cfg)?,
    };
    let wall = r.wall_seconds;
    let st = sphere_error(&r)?;
    let fragments = st.n / 3;
    let elab = r.path.elaboration(fragments);
    let used: Vec<UnitSummary> = elab.iter().filter_map(|u| u.summary.clone()).collect();
    let (gates, ram) = total(&used);
    // Textures per fragment: the cube for n and l, and for h with the lookup;
    // the lookup's 1D table; one per factor texture.
    let lookup = elab
        .iter()
        .any(|u| u.summary.is_some() && u.name == "specular_lookup");
    let factors = elab
        .iter()
        .filter(|u| u.summary.is_some() && u.name.starts_with("texture_sampler (factor"))
        .count() as u32;
    let textures = 2 + 2 * u32::from(lookup) + factors;
    let m = Measured {
        mean: st.mean_abs,
        rms: st.rms,
        max: st.max,
        predicted: fill_seconds(fragments, textures),
        wall,
        gates,
        ram,
    };
    Ok((m, r.hardware))
}

/// [`run_with`] of the specular term by squaring in the register combiners (`bits`
/// wide, `chip`'s modes).
fn run_squaring(
    bits: u32,
    chip: ChipPreset,
    view: &SphereView,
    reference: Option<&ShadingReference>,
) -> Result<(Measured, Vec<f64>), ConfigError> {
    let cube = cube_8bit()?;
    let chain = SquaringChain::on_chip(bits, chip)?;
    let t0 = Instant::now();
    let v8 = sphere_vectors(view, &cube)?;
    let mut ctr = Counters::default();
    let hw = squaring_levels_on(&v8, SPECULAR_K, &chain, &mut ctr);
    let wall = t0.elapsed().as_secs_f64();
    // The cube, the dot-product stage, k squaring stages and the final combiner.
    let mut units = cube_units(&cube).to_vec();
    units.push(UnitSummary::of(&chain.dot_stage));
    units.extend((0..SPECULAR_K).map(|_| UnitSummary::of(&chain.square_stage)));
    units.push(UnitSummary::of(&chain.final_stage));
    // Textures: a normal map and the cube for h.
    let r = given_levels(reference)?;
    let m = specular_measured(&v8, &hw, wall, &units, 2, r.as_deref())?;
    Ok((m, hw))
}

/// [`run_with`] of the specular term by the lookup table.
fn run_lookup(
    c: &LookupPathConfig,
    view: &SphereView,
    reference: Option<&ShadingReference>,
) -> Result<(Measured, Vec<f64>), ConfigError> {
    let cube = c.cube.build()?;
    let bits = c.cube.texel_bits;
    let s = (1u32 << SPECULAR_K) as f64;
    let t0 = Instant::now();
    let v = sphere_vectors(view, &cube)?;
    let mut ctr = Counters::default();
    let hw = lookup_levels(&v, bits, s, c.lookup, &mut ctr)?;
    let wall = t0.elapsed().as_secs_f64();
    let dot3 = combiner_stage(bits, CombineFunction::Dot3Rgb, 1)?;
    let lut = SpecularLookupConfig {
        exponent: s,
        in_bits: bits,
        ..c.lookup
    }
    .build()?;
    let mut units = cube_units(&cube).to_vec();
    units.push(UnitSummary::of(&dot3));
    units.push(UnitSummary::of(&lut));
    // Textures: the normal map, the cube for h, the lookup's 1D texture.
    let r = given_levels(reference)?;
    let m = specular_measured(&v, &hw, wall, &units, 3, r.as_deref())?;
    Ok((m, hw))
}

/// [`run_with`] of vertex lighting (one light, the sphere's vertices).
fn run_vertex(
    c: VertexLightingConfig,
    reference: Option<&ShadingReference>,
) -> Result<(Measured, Vec<f64>), ConfigError> {
    let setup = one_light();
    let verts = sphere_vertices(VERTEX_RINGS, VERTEX_SEGMENTS);
    let t0 = Instant::now();
    let row = match reference {
        None => measure(c, &setup, &verts),
        Some(ShadingReference::Vertex(exact)) => measure_against(c, &setup, &verts, exact),
        Some(ShadingReference::Image { .. }) => return Err(reference_mismatch()),
    }
    .map_err(|e| ConfigError::invalid("vertex_lighting", &e))?;
    let wall = t0.elapsed().as_secs_f64();
    let s = UnitSummary::of(&VertexLighting::new(c, &setup)?);
    let clock = GpuModel::geforce3().clock_hz;
    let m = Measured {
        mean: row.mean_levels,
        rms: row.rms_levels,
        max: row.max_levels,
        predicted: verts.len() as f64 * s.ii as f64 / clock,
        wall,
        gates: s.gates_nand2,
        ram: s.ram_bits,
    };
    Ok((m, Vec::new()))
}

/// Sweep options: the sphere view's side in pixels (the `shading-brdfs` 256 by
/// default; `shading-vertex` does not use it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingSweepOptions {
    pub view_size: u32,
}

impl Default for ShadingSweepOptions {
    fn default() -> Self {
        ShadingSweepOptions { view_size: 256 }
    }
}

/// The rows of the values `only` picks (every value without a shard), with their
/// value indices, of the sweep of `param` over `values` on the `shading-*` scene
/// `scene`. The scene, the param and every value are checked (units built) before
/// anything renders.
pub fn shading_rows(
    scene: &str,
    param: &str,
    values: &[u32],
    opts: &ShadingSweepOptions,
    only: Option<Shard>,
    journal: &mut Journal<ShadingSweepRow>,
) -> Result<(), String> {
    let (param, jobs, view) = shading_jobs(scene, param, values, opts)?;
    let todo = journal.pending(&jobs, only);
    try_map_with_progress(&todo, &format!("sweep {param}"), |&(i, (v, j))| {
        let m = run(j, &view).map_err(|e| format!("values: {param} = {v}: {e}"))?;
        journal.record(
            i,
            ShadingSweepRow {
                param: param.to_string(),
                value: *v,
                mean_abs_levels: m.mean,
                rms_levels: m.rms,
                max_levels: m.max,
                predicted_hw_seconds: m.predicted,
                wall_seconds: m.wall,
                gates_nand2: m.gates,
                ram_bits: m.ram,
            },
        )
    })?;
    Ok(())
}

/// The canonical param, each value's job (every one checked: units built) and the
/// sphere view: all a sweep needs before anything renders.
type Jobs = (&'static str, Vec<(u32, Job)>, SphereView);

/// [`Jobs`] of a sweep.
pub(super) fn shading_jobs(
    scene: &str,
    param: &str,
    values: &[u32],
    opts: &ShadingSweepOptions,
) -> Result<Jobs, String> {
    let sc = ShadingScene::parse(scene)?;
    let param = check_param(&sc, param)?;
    if values.is_empty() {
        return Err("values: no values given".into());
    }
    rtl_model::error::check_range("image", opts.view_size.into(), 2, 4096)
        .map_err(|e| e.to_string())?;
    let jobs: Vec<(u32, Job)> = values.iter().map(|&v| (v, job(&sc, param, v))).collect();
    for (v, j) in &jobs {
        validate(j).map_err(|e| format!("values: {param} = {v}: {e}"))?;
    }
    Ok((param, jobs, sweep_view(opts.view_size)))
}

/// The sphere view of a shading sweep: `size`² pixels, E = π (as `reproduce
/// shading-brdfs`).
pub fn sweep_view(size: u32) -> SphereView {
    SphereView {
        size,
        irradiance: std::f64::consts::PI,
        ..SphereView::default()
    }
}

/// The plot's title.
fn title(sc: &ShadingScene, param: &str) -> String {
    format!("{}: error and run time against {param}", sc.name())
}

/// Run the sweep (see [`shading_rows`]) and write `DIR/sweep_<param>.csv` and `.png`.
pub fn shading_sweep(
    scene: &str,
    param: &str,
    values: &[u32],
    out: &Path,
    opts: &ShadingSweepOptions,
) -> Result<(Vec<ShadingSweepRow>, PathBuf, PathBuf), String> {
    let sc = ShadingScene::parse(scene)?;
    let param = check_param(&sc, param)?;
    let id = sweep_id(&sc, param, values, opts);
    shading_sweep_resumable(scene, &id, param, values, out, opts, false)
}

/// What makes two runs or the shards of a shading sweep one sweep: the scenes are
/// built in, so the name, the param, the values and the view's size (none for
/// shading-vertex, which has no image) are the whole sweep.
pub(super) fn sweep_id(
    sc: &ShadingScene,
    param: &str,
    values: &[u32],
    opts: &ShadingSweepOptions,
) -> SweepId {
    let mut settings = std::collections::BTreeMap::new();
    if *sc != ShadingScene::Vertex {
        settings.insert("image".to_string(), opts.view_size.to_string());
    }
    SweepId {
        kind: "shading".into(),
        scene: sc.name(),
        param: param.into(),
        values: values.iter().map(u32::to_string).collect(),
        settings,
        title: title(sc, param),
    }
}

/// [`shading_sweep`] as sweep `id`, continuing (with `resume`) from the rows an
/// earlier run of it left; the CSV is rewritten as each row finishes.
pub(super) fn shading_sweep_resumable(
    scene: &str,
    id: &SweepId,
    param: &str,
    values: &[u32],
    out: &Path,
    opts: &ShadingSweepOptions,
    resume: bool,
) -> Result<(Vec<ShadingSweepRow>, PathBuf, PathBuf), String> {
    // Every value is checked before the journal removes an old CSV.
    shading_jobs(scene, param, values, opts)?;
    let csv = out.join(format!("sweep_{param}.csv"));
    let mut journal = Journal::plain(&csv, id, resume, |r: &ShadingSweepRow| r.value.to_string())?;
    shading_rows(scene, param, values, opts, None, &mut journal)?;
    let rows: Vec<ShadingSweepRow> = journal.into_rows().into_iter().map(|(_, r)| r).collect();
    let (csv, png) = write_sweep(&rows, &id.title, param, out)?;
    Ok((rows, csv, png))
}

/// The CLI: `values` as `parse_int_values` reads them, `image` (width, height as
/// `--image WxH` gave them; square) the sphere view's size; prints what was written
/// and the rows.
pub fn shading_sweep_cli(
    scene: &str,
    param: &str,
    values: &str,
    out: &Path,
    image: Option<(u32, u32)>,
    shard: Option<Shard>,
    resume: bool,
) -> Result<(), String> {
    let sc = ShadingScene::parse(scene)?;
    let canonical = check_param(&sc, param)?;
    let values = parse_int_values(values)?;
    let mut opts = ShadingSweepOptions::default();
    if let Some((w, h)) = image {
        if sc == ShadingScene::Vertex {
            return Err("--image: shading-vertex lights sphere vertices, it has no image".into());
        }
        if w != h {
            return Err(format!("--image: the sphere view is square, not {w}x{h}"));
        }
        opts.view_size = w;
    }
    let id = sweep_id(&sc, canonical, &values, &opts);
    if let Some(shard) = shard {
        shading_jobs(scene, param, &values, &opts)?;
        let mut journal = Journal::shard(out, &id, shard, resume)?;
        shading_rows(scene, param, &values, &opts, Some(shard), &mut journal)?;
        return shard_sweep(out, &id, shard, &journal.into_rows());
    }
    let (rows, csv, png) =
        shading_sweep_resumable(scene, &id, canonical, &values, out, &opts, resume)?;
    println!(
        "sweep {} on {scene}: wrote {} and {}",
        rows.first().map_or(param, |r| r.param.as_str()),
        csv.display(),
        png.display()
    );
    print!(
        "{}",
        sweep_table(rows.first().map_or(param, |r| r.param.as_str()), &rows)
    );
    Ok(())
}

// ------------------------------------------------------------ joint points (optimize)

/// The register combiners' internal width of `shading-specular`'s squaring path when
/// no `combiner_bits` is given: 9 bits, the GeForce 256/2's (the first of
/// `reproduce shading-specular`'s [`SQUARING_BITS`]).
pub const SQUARING_DEFAULT_BITS: u32 = SQUARING_BITS[0];

/// One configuration of a shading scene with several widths set at once (`optimize`,
/// a shading scene file): the sweep's configuration at the scene's defaults, each
/// width set through the sweep's own setter, every unit built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingPoint {
    scene: ShadingScene,
    job: Job,
    chip: ChipPreset,
}

impl ShadingPoint {
    /// `scene` at its defaults with `widths` set. A name the scene does not take is
    /// an error naming `param` ([`check_param`]); a value a unit refuses is an error
    /// `NAME = VALUE: <the unit's field and limits>`. On `shading-specular`,
    /// `combiner_bits` (the squaring path) does not mix with the lookup path's widths.
    pub fn new(scene: &ShadingScene, widths: &[(&str, u32)]) -> Result<ShadingPoint, String> {
        let names: Vec<&'static str> = widths
            .iter()
            .map(|(p, _)| check_param(scene, p))
            .collect::<Result<_, _>>()?;
        let squaring = names.contains(&"combiner_bits");
        if let Some(other) = names.iter().find(|p| squaring && **p != "combiner_bits") {
            return Err(format!(
                "param: combiner_bits is {}'s squaring path and '{other}' its lookup \
                 path; a configuration is one path",
                scene.name()
            ));
        }
        let mut job = base_job(scene, squaring);
        // Set one width at a time, every unit built after each: an error names the
        // width that made the configuration invalid.
        for (p, (_, v)) in names.iter().zip(widths) {
            set(&mut job, p, *v);
            validate(&job).map_err(|e| format!("{p} = {v}: {e}"))?;
        }
        validate(&job).map_err(|e| e.to_string())?;
        Ok(ShadingPoint {
            scene: *scene,
            job,
            chip: ChipPreset::GeForce2,
        })
    }

    /// The same widths in `chip`'s modes (the chip preset): `shading-specular`'s
    /// squaring path takes its register and final combiner modes, `shading-vertex` its
    /// vertex-lighting modes (with an OpenGL program's light-control state,
    /// [`GL_SINGLE_COLOR`]); the catalogue models' and the lookup path's units (the
    /// normalisation cube, texture combiners, specular lookup, factor textures) have
    /// no mode that differs between the two chips.
    pub fn on_chip(self, chip: ChipPreset) -> ShadingPoint {
        let job = match self.job {
            Job::Squaring(bits, _) => Job::Squaring(bits, chip),
            Job::Vertex(c) => Job::Vertex(chip.vertex_lighting(c, GL_SINGLE_COLOR)),
            other => other,
        };
        ShadingPoint { job, chip, ..self }
    }

    /// A catalogue model's entry and path configuration (None for `shading-specular`
    /// and `shading-vertex`).
    pub fn model(&self) -> Option<(CatalogueEntry, PathConfig)> {
        match self.job {
            Job::Model(e, c) => Some((e, c)),
            _ => None,
        }
    }

    /// A catalogue model's point with its path configuration changed by `change`
    /// (the same point for `shading-specular` and `shading-vertex`), every unit built
    /// again: an error names the field a change made invalid.
    pub fn with_path(self, change: impl FnOnce(&mut PathConfig)) -> Result<ShadingPoint, String> {
        let mut p = self;
        if let Job::Model(_, c) = &mut p.job {
            change(c);
        }
        validate(&p.job).map_err(|e| e.to_string())?;
        Ok(p)
    }

    /// `shading-vertex`'s vertex-lighting configuration (None for the other scenes).
    pub fn vertex_config(&self) -> Option<VertexLightingConfig> {
        match self.job {
            Job::Vertex(c) => Some(c),
            _ => None,
        }
    }

    /// The chip preset the point's units follow.
    pub fn chip(&self) -> ChipPreset {
        self.chip
    }

    /// The units of the point's path the chip preset changes (registry names; empty
    /// when none of them differs between the chips, or at the GeForce2 preset).
    pub fn units_the_chip_changes(&self) -> Vec<&'static str> {
        let units: &[&'static str] = match self.job {
            Job::Squaring(..) => &["register_combiner", "final_combiner"],
            Job::Vertex(_) => &["vertex_lighting"],
            Job::Model(..) | Job::Lookup(_) => &[],
        };
        units
            .iter()
            .copied()
            .filter(|u| self.chip.changes(u))
            .collect()
    }

    pub fn scene(&self) -> &ShadingScene {
        &self.scene
    }

    /// The value of `param` at this point; an error naming `param` for a width
    /// this point's path does not have.
    pub fn value(&self, param: &str) -> Result<u32, String> {
        get(&self.job, param).ok_or_else(|| {
            format!(
                "param: '{param}' is not a width of this {} configuration",
                self.scene.name()
            )
        })
    }

    /// Every width of this point's path, in [`params_of`]'s order.
    pub fn widths(&self) -> Vec<(&'static str, u32)> {
        params_of(&self.scene)
            .iter()
            .filter_map(|p| get(&self.job, p).map(|v| (*p, v)))
            .collect()
    }

    /// The width of the codes the error is measured on: each output value is a
    /// code k shown as k · 255 / (2^bits − 1) levels. The catalogue paths end in an
    /// 8-bit combiner, the squaring chain in unorm8, the lookup path in the lookup's
    /// entries (`lookup_bits`), vertex lighting in its colour width.
    pub fn output_bits(&self) -> u32 {
        match &self.job {
            Job::Model(..) | Job::Squaring(..) => 8,
            Job::Lookup(c) => c.lookup.entry_bits,
            Job::Vertex(c) => c.color_bits,
        }
    }
}

/// What a shading point's error is measured against: the sweep's reference, which
/// depends on no searched width, so it is drawn once.
#[derive(Clone, Debug, PartialEq)]
pub enum ShadingReference {
    /// Levels per pixel of the view (row-major, grey, background 0) and the covered
    /// pixels (the error is over these).
    Image { levels: Vec<f64>, mask: Vec<bool> },
    /// The GL twin's exact colour per vertex (`vertex_float::exact_levels`).
    Vertex(Vec<[f64; 3]>),
}

impl ShadingReference {
    /// The reference values the error is taken over, as RGB: the covered pixels,
    /// or the vertices' ideal codes (the exact colour rounded, as `measure`
    /// compares).
    pub fn values(&self) -> Vec<[f64; 3]> {
        match self {
            ShadingReference::Image { levels, mask } => levels
                .iter()
                .zip(mask)
                .filter(|(_, m)| **m)
                .map(|(&x, _)| [x; 3])
                .collect(),
            ShadingReference::Vertex(v) => v.iter().map(|c| c.map(f64::round)).collect(),
        }
    }
}

/// The reference of `point`'s scene on `view` (the sweep's: the catalogue model's
/// f64 sphere, 255·(n̂·ĥ)^32, the GL twin's vertex colours at the point's colour
/// width).
pub fn shading_reference(
    point: &ShadingPoint,
    view: &SphereView,
) -> Result<ShadingReference, String> {
    let e = |e: ConfigError| e.to_string();
    Ok(match &point.job {
        Job::Model(entry, _) => ShadingReference::Image {
            levels: sphere_reference(entry, view).map_err(e)?,
            mask: view.pixels().iter().map(Option::is_some).collect(),
        },
        Job::Squaring(..) | Job::Lookup(_) => {
            // The reference reads the exact n̂·ĥ, not the cube's vectors.
            let v = sphere_vectors(view, &cube_8bit().map_err(e)?).map_err(e)?;
            ShadingReference::Image {
                levels: reference_levels(&v, (1u32 << SPECULAR_K) as f64),
                mask: v.iter().map(Option::is_some).collect(),
            }
        }
        Job::Vertex(c) => ShadingReference::Vertex(exact_levels(
            c,
            &one_light(),
            &sphere_vertices(VERTEX_RINGS, VERTEX_SEGMENTS),
        )),
    })
}

/// What one shading point measured (the sweep's row) and the hardware's levels.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadingMeasure {
    pub mean_abs_levels: f64,
    pub rms_levels: f64,
    pub max_levels: f64,
    pub predicted_hw_seconds: f64,
    pub wall_seconds: f64,
    pub gates_nand2: f64,
    pub ram_bits: u64,
    /// Grey levels per pixel of the view (row-major; background 0); empty for
    /// `shading-vertex`, which has no image.
    pub levels: Vec<f64>,
}

/// The gates and RAM bits `point`'s path elaborates at its widths (from a render of a
/// small view: the units elaborated do not depend on the view's size); what
/// `units --scene shading-*` prints.
pub fn point_cost(point: &ShadingPoint) -> Result<(f64, u64), String> {
    let (m, _) = run_with(&point.job, &sweep_view(16), None).map_err(|e| e.to_string())?;
    Ok((m.gates, m.ram))
}

/// Render `point` on `view` through the sweep's path and measure it against
/// `reference` (its [`shading_reference`] on the same view).
pub fn measure_point(
    point: &ShadingPoint,
    view: &SphereView,
    reference: &ShadingReference,
) -> Result<ShadingMeasure, String> {
    let (m, levels) = run_with(&point.job, view, Some(reference)).map_err(|e| e.to_string())?;
    Ok(ShadingMeasure {
        mean_abs_levels: m.mean,
        rms_levels: m.rms,
        max_levels: m.max,
        predicted_hw_seconds: m.predicted,
        wall_seconds: m.wall,
        gates_nand2: m.gates,
        ram_bits: m.ram,
        levels,
    })
}
