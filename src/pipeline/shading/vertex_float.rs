//! `shading-vertex-float`: how narrow can the vertex-lighting float go? The
//! `vertex_lighting` unit lights the vertices of a tessellated sphere at every
//! mantissa width M = 4 ..= 23 (exponent 8, and exponent 5 as fp16-like formats), with
//! one light and with eight, against its f64 twin (the GL 1.x equation); the error is
//! counted in 8-bit levels against the twin's ideal 8-bit output round(255·clamp(c)).

use crate::reference::vertex_lighting::{
    light_vertex, light_vertex_nv2a, GlLighting, Nv2aSwitches,
};
use crate::report::csv_out::write_csv;
use crate::report::metrics::error_stats;
use crate::report::plot::{line_plot, Axis, PlotSpec, Series};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use rtl_model::units::vertex_lighting::{
    Light, LightingSetup, Material, VertexLighting, VertexLightingConfig,
};
use rtl_model::{Counters, Unit, UnitSummary};
use serde::Serialize;
use std::path::Path;

/// The twin's view of a unit config and its loaded lighting state.
pub fn gl_lighting(cfg: &VertexLightingConfig, s: &LightingSetup) -> GlLighting {
    GlLighting {
        state: s.clone(),
        normalize: cfg.normalize,
        local_viewer: cfg.local_viewer,
    }
}

/// Sphere centre in eye space and radius.
pub const SPHERE_CENTRE: [f64; 3] = [0.0, 0.0, -4.0];
pub const SPHERE_RADIUS: f64 = 1.0;

/// A latitude/longitude tessellation of the sphere: `rings` × `segments` vertices
/// (poles excluded), as (eye-space position, unit normal).
pub fn sphere_vertices(rings: u32, segments: u32) -> Vec<([f64; 3], [f64; 3])> {
    let mut out = Vec::with_capacity((rings * segments) as usize);
    for i in 0..rings {
        let theta = std::f64::consts::PI * (i as f64 + 0.5) / rings as f64;
        for j in 0..segments {
            let phi = 2.0 * std::f64::consts::PI * j as f64 / segments as f64;
            let n = [
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            ];
            let p = [0, 1, 2].map(|k| SPHERE_CENTRE[k] + SPHERE_RADIUS * n[k]);
            out.push((p, n));
        }
    }
    out
}

/// A polished material (shininess 32), the study's surface.
pub fn study_material() -> Material {
    Material {
        emission: [0.02, 0.02, 0.02],
        ambient: [0.25, 0.2, 0.15],
        diffuse: [0.7, 0.5, 0.35, 1.0],
        specular: [0.8, 0.8, 0.8],
        shininess: 32.0,
    }
}

/// One white directional light from the upper left, in front.
pub fn one_light() -> LightingSetup {
    LightingSetup {
        material: study_material(),
        scene_ambient: [0.2; 3],
        lights: vec![Light {
            position: [-0.45, 0.55, 0.70, 0.0],
            ..Light::default()
        }],
    }
}

/// Eight lights (seeded): directional, local with attenuation, spots with cutoffs
/// 20 ..= 70° and exponents 0 ..= 64; colours scaled so the sum stays mostly in range.
pub fn eight_lights(seed: u64) -> LightingSetup {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut col = |s: f64| [(); 3].map(|_| s * rng.random_range(0.3..1.0));
    let colours: Vec<_> = (0..8).map(|_| (col(0.05), col(0.35), col(0.5))).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed);
    let lights = colours
        .into_iter()
        .enumerate()
        .map(|(i, (ambient, diffuse, specular))| {
            let dir = [
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(0.2..1.0),
            ];
            match i % 3 {
                0 => Light {
                    position: [dir[0], dir[1], dir[2], 0.0],
                    ambient,
                    diffuse,
                    specular,
                    ..Light::default()
                },
                1 => Light {
                    position: [3.0 * dir[0], 3.0 * dir[1], -4.0 + 3.0 * dir[2], 1.0],
                    ambient,
                    diffuse,
                    specular,
                    attenuation: [0.5, 0.2, 0.05],
                    ..Light::default()
                },
                _ => {
                    let pos = [2.5 * dir[0], 2.5 * dir[1], -4.0 + 2.5 * dir[2]];
                    let to_centre = [0, 1, 2].map(|k| SPHERE_CENTRE[k] - pos[k]);
                    Light {
                        position: [pos[0], pos[1], pos[2], 1.0],
                        ambient,
                        diffuse,
                        specular,
                        spot_direction: to_centre,
                        spot_cutoff: rng.random_range(20.0..70.0),
                        spot_exponent: rng.random_range(0.0..64.0),
                        attenuation: [1.0, 0.05, 0.01],
                    }
                }
            }
        })
        .collect();
    LightingSetup {
        material: study_material(),
        scene_ambient: [0.1; 3],
        lights,
    }
}

/// One row: a format and a light count.
#[derive(Clone, Debug, Serialize)]
pub struct VertexFloatRow {
    pub exp_bits: u32,
    pub mant_bits: u32,
    pub lights: usize,
    pub vertices: usize,
    /// |code − round(255·clamp(c_f64))|, over vertices × RGB.
    pub mean_levels: f64,
    pub rms_levels: f64,
    pub max_levels: f64,
    /// Largest |code − 255·clamp(c_f64)| (the unrounded twin: includes the ½ level of
    /// the final rounding).
    pub max_vs_exact_levels: f64,
    pub saturations: u64,
    pub underflows: u64,
    pub ii: u32,
    pub gates_nand2: f64,
}

/// Light every vertex at one format; the row.
pub fn measure(
    cfg: VertexLightingConfig,
    setup: &LightingSetup,
    verts: &[([f64; 3], [f64; 3])],
) -> Result<VertexFloatRow, String> {
    measure_against(cfg, setup, verts, &exact_levels(&cfg, setup, verts))
}

/// The GL twin's exact colour of every vertex, clamp(c) · (2^color_bits − 1): the
/// reference [`measure`] compares with. It depends on the colour width, the lighting
/// state, the normalise / local-viewer switches and the NV2A modes (`light_control`,
/// `normalize_directional`: then the twin's NV2A path, its primary colour), not on the
/// float format, so a search over the format draws it once.
pub fn exact_levels(
    cfg: &VertexLightingConfig,
    setup: &LightingSetup,
    verts: &[([f64; 3], [f64; 3])],
) -> Vec<[f64; 3]> {
    let gl = gl_lighting(cfg, setup);
    let scale = ((1u64 << cfg.color_bits) - 1) as f64;
    verts
        .iter()
        .map(|&(p, n)| {
            let c = match cfg.light_control {
                None => light_vertex(&gl, p, n),
                // The NV2A's modes (the chip preset): the twin's two-colour path with the
                // unit's switches and directional-light load; the vertices carry no
                // colours of their own, and the primary colour is the one compared.
                Some(lc) => {
                    let sw = Nv2aSwitches {
                        normalize_directional: cfg.normalize_directional,
                        lighting: lc.lighting,
                        specular_enable: lc.specular_enable,
                        separate_specular: lc.separate_specular,
                        specular_alpha_from_vertex: lc.specular_alpha_from_vertex,
                        specular_curve: cfg.specular_curve.coefficients(),
                    };
                    light_vertex_nv2a(&gl, &sw, p, n, [0.0; 4], [0.0; 4]).0
                }
            };
            [0, 1, 2].map(|k| c[k].clamp(0.0, 1.0) * scale)
        })
        .collect()
}

/// Light every vertex through the unit: the unit, each vertex's RGB codes and the
/// counters.
pub fn light_codes(
    cfg: VertexLightingConfig,
    setup: &LightingSetup,
    verts: &[([f64; 3], [f64; 3])],
) -> Result<(VertexLighting, Vec<[u32; 3]>, Counters), String> {
    let u = VertexLighting::new(cfg, setup).map_err(|e| e.to_string())?;
    let mut ctr = Counters::default();
    let mut codes = Vec::with_capacity(verts.len());
    for &(p, n) in verts {
        let input = u
            .vertex_from_f64(p, n, &mut ctr)
            .map_err(|e| e.to_string())?;
        let out = u.kernel(&mut (), &input, &mut ctr);
        codes.push([out.rgba[0], out.rgba[1], out.rgba[2]]);
    }
    Ok((u, codes, ctr))
}

/// [`measure`] against exact colours drawn before ([`exact_levels`] of the same
/// colour width, setup and vertices).
pub fn measure_against(
    cfg: VertexLightingConfig,
    setup: &LightingSetup,
    verts: &[([f64; 3], [f64; 3])],
    exact_all: &[[f64; 3]],
) -> Result<VertexFloatRow, String> {
    if exact_all.len() != verts.len() {
        return Err(format!(
            "vertex reference: {} colours for {} vertices",
            exact_all.len(),
            verts.len()
        ));
    }
    let (u, codes, ctr) = light_codes(cfg, setup, verts)?;
    let (mut got, mut ideal) = (Vec::new(), Vec::new());
    let mut max_exact: f64 = 0.0;
    for (rgb, &exact) in codes.iter().zip(exact_all) {
        let code = rgb.map(f64::from);
        for k in 0..3 {
            max_exact = max_exact.max((code[k] - exact[k]).abs());
        }
        got.push(code);
        ideal.push(exact.map(f64::round));
    }
    let st = error_stats(&got, &ideal).map_err(|e| e.to_string())?;
    let s = UnitSummary::of(&u);
    Ok(VertexFloatRow {
        exp_bits: cfg.format.exp_bits,
        mant_bits: cfg.format.mant_bits,
        lights: setup.lights.len(),
        vertices: verts.len(),
        mean_levels: st.mean_abs,
        rms_levels: st.rms,
        max_levels: st.max,
        max_vs_exact_levels: max_exact,
        saturations: ctr.saturations,
        underflows: ctr.underflows,
        ii: s.ii,
        gates_nand2: s.gates_nand2,
    })
}

/// The narrowest mantissa (of the swept ones) from which on every wider one keeps
/// max ≤ `max_levels` and mean ≤ `mean_levels`.
pub fn narrowest(
    rows: &[VertexFloatRow],
    exp_bits: u32,
    lights: usize,
    max_levels: f64,
    mean_levels: f64,
) -> Option<u32> {
    let mut sel: Vec<&VertexFloatRow> = rows
        .iter()
        .filter(|r| r.exp_bits == exp_bits && r.lights == lights)
        .collect();
    sel.sort_by_key(|r| r.mant_bits);
    let mut best = None;
    for r in sel.iter().rev() {
        if r.max_levels <= max_levels && r.mean_levels <= mean_levels {
            best = Some(r.mant_bits);
        } else {
            break;
        }
    }
    best
}

/// A column of a row, for plotting.
type RowStat = fn(&VertexFloatRow) -> f64;

/// Exponent widths and mantissa range of the sweep.
pub const EXPONENTS: [u32; 2] = [8, 5];
pub const MANTISSAS: std::ops::RangeInclusive<u32> = 4..=23;

/// Run the study: `DIR/vertex_float.csv` (one row per exponent, mantissa and light
/// count) and `DIR/vertex_float.png` (max and mean error against M).
pub fn reproduce(out: &Path) -> Result<Vec<VertexFloatRow>, String> {
    let verts = sphere_vertices(48, 96);
    let setups = [one_light(), eight_lights(13)];
    let jobs: Vec<(u32, u32, usize)> = EXPONENTS
        .iter()
        .flat_map(|&e| MANTISSAS.flat_map(move |m| [(e, m, 0usize), (e, m, 1usize)]))
        .collect();
    let rows: Vec<VertexFloatRow> = jobs
        .par_iter()
        .map(|&(e, m, s)| {
            measure(
                VertexLightingConfig::geforce().with_format(e, m),
                &setups[s],
                &verts,
            )
        })
        .collect::<Result<_, _>>()?;
    write_csv(&out.join("vertex_float.csv"), &rows)?;
    // Log y: a zero error is drawn at the floor 1/64 level (said in the axis label).
    let floor = 1.0 / 64.0;
    let mut series = Vec::new();
    for &e in &EXPONENTS {
        for lights in [1usize, 8] {
            let sel: Vec<&VertexFloatRow> = rows
                .iter()
                .filter(|r| r.exp_bits == e && r.lights == lights)
                .collect();
            let plural = if lights > 1 { "s" } else { "" };
            let stats: [(&str, RowStat); 2] =
                [("max", |r| r.max_levels), ("mean", |r| r.mean_levels)];
            for (what, stat) in stats {
                series.push(Series {
                    label: format!("{what}, e{e}, {lights} light{plural}"),
                    points: sel
                        .iter()
                        .map(|r| (r.mant_bits as f64, stat(r).max(floor)))
                        .collect(),
                    axis: Axis::Left,
                });
            }
        }
    }
    let mut spec = PlotSpec::new(
        &format!(
            "vertex lighting vs f64 GL twin, {} sphere vertices",
            verts.len()
        ),
        "mantissa bits M",
        "error, 8-bit levels (0 drawn at 1/64)",
    );
    spec.log_y = true;
    line_plot(&out.join("vertex_float.png"), &spec, &series)?;
    println!("exp_bits,mant_bits,lights,mean_levels,rms_levels,max_levels,max_vs_exact,saturations,underflows");
    for r in &rows {
        println!(
            "{},{},{},{:.4},{:.4},{:.1},{:.3},{},{}",
            r.exp_bits,
            r.mant_bits,
            r.lights,
            r.mean_levels,
            r.rms_levels,
            r.max_levels,
            r.max_vs_exact_levels,
            r.saturations,
            r.underflows
        );
    }
    for &e in &EXPONENTS {
        for lights in [1usize, 8] {
            match narrowest(&rows, e, lights, 1.0, 0.5) {
                Some(m) => println!(
                    "narrowest mantissa, e{e}, {lights} light(s): M = {m} (max ≤ 1 level, mean ≤ 0.5)"
                ),
                None => println!("e{e}, {lights} light(s): no swept M keeps max ≤ 1 level"),
            }
        }
    }
    Ok(rows)
}
