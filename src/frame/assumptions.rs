//! `reproduce assumptions`: every constant the papers leave open or state
//! differently that has a selectable alternative in the scene file is rendered both
//! ways on the built-ins it affects; a CSV row per (assumption, alternative, scene)
//! gives the difference from the scene as it is (RMS, max and mean |Δ| in 8-bit
//! levels, and the pixels that changed), and a PNG strip per assumption shows, per
//! scene, the default picture, each alternative's and its |Δ| × [`DIFF_GAIN`].
//! The ledger itself, with the figures this writes, is docs/assumptions.md.
//! `envmap.dome_pick` changes the voxel map itself, so it is also measured on the maps
//! ([`dome_pick_maps`]: `assumptions_maps.csv`, each pick against the exact prefilter).
//!
//! The full run renders the built-ins at their own sizes (the CLI); [`Reduced`]
//! shrinks them for the tests (tests/assumptions.rs).

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;

use super::plan::environment_scene;
use super::run::render;
use crate::pipeline::envmap::prefilter::{
    build_accelerated_picked, build_exact, env_to_levels, voxel_error, DomePick,
};
use crate::pipeline::envmap::scene_render::render_scene;
use crate::reference::envmap_prefilter::PrefilterParams;
use crate::report::metrics::error_stats;
use crate::scene::builtin::builtin;
use crate::scene::environment::{EnvDomePick, EnvWeighting, ExposureRule, THESIS_THRESHOLD};
use crate::scene::envmap::EnvMap;
use crate::scene::format::{FScale, HCap, PlaneStep, Scene};
use crate::scene::glare::{
    BloomRange, HaloAmplitude, HaloRadius, Highlight, HighlightMaterial, WaterEta,
};

/// |Δ| is drawn × this in the strips (a 32-level difference is full white).
pub const DIFF_GAIN: f64 = 8.0;

/// The one scene that is not a built-in: `glare-point` with a water highlight — the
/// lamp seen in a puddle 10 m ahead (incidence 78.7°, mirror direction at the eye), so
/// that Table 2's water row can fire (no built-in has a water highlight).
pub const WATER_SCENE: &str = "glare-point+water";

/// One alternative of one assumption: the scene field(s) it sets.
pub struct Alternative {
    /// The assumption's name (its ledger row in docs/assumptions.md).
    pub assumption: &'static str,
    /// The alternative as written in the scene file.
    pub alternative: &'static str,
    /// The built-ins (or [`WATER_SCENE`]) it is rendered on.
    pub scenes: &'static [&'static str],
    /// Set the alternative on a scene.
    pub apply: fn(&mut Scene),
}

fn glare_model(s: &mut Scene) -> &mut crate::scene::glare::GlareModel {
    &mut s.glare.as_mut().expect("a glare scene").model
}

fn env(s: &mut Scene) -> &mut crate::scene::environment::EnvironmentSection {
    s.environment.as_mut().expect("an environment scene")
}

/// Every alternative, in ledger order.
pub const ALTERNATIVES: &[Alternative] = &[
    Alternative {
        assumption: "glare.bloom_angle_scale",
        alternative: "bloom_angle_scale_deg = 1.0",
        scenes: &["glare-elliptic", "street-light"],
        apply: |s| glare_model(s).bloom_w_deg = 1.0,
    },
    Alternative {
        assumption: "glare.halo_amplitude",
        alternative: "halo_amplitude = \"ambient_x10\"",
        scenes: &["street-light", "shaded-metal"],
        apply: |s| glare_model(s).halo_amplitude = HaloAmplitude::AmbientX10,
    },
    Alternative {
        assumption: "glare.halo_radius",
        alternative: "halo_radius = \"spencer\"",
        scenes: &["street-light", "shaded-metal"],
        apply: |s| glare_model(s).halo_radius = HaloRadius::Spencer,
    },
    Alternative {
        assumption: "glare.bloom_range",
        alternative: "bloom_range = \"eq1_8deg\"",
        scenes: &["glare-point", "glare-elliptic", "street-light"],
        apply: |s| glare_model(s).bloom_range = BloomRange::Eq1EightDeg,
    },
    Alternative {
        assumption: "glare.water_eta",
        alternative: "water_eta = \"air_over_media\"",
        scenes: &[WATER_SCENE],
        apply: |s| glare_model(s).water_eta = WaterEta::AirOverMedia,
    },
    Alternative {
        assumption: "envmap.exposure_rule",
        alternative: "exposure_rule = \"p99_texels\"",
        scenes: &["env-venice_sunset-sphere", "env-st_fagans_interior-sphere"],
        apply: |s| env(s).exposure_rule = ExposureRule::P99Texels,
    },
    Alternative {
        assumption: "envmap.exposure_rule",
        alternative: "exposure_rule = \"max\"",
        scenes: &["env-venice_sunset-sphere", "env-st_fagans_interior-sphere"],
        apply: |s| env(s).exposure_rule = ExposureRule::Max,
    },
    Alternative {
        assumption: "envmap.weighting",
        alternative: "weighting = \"uniform\"",
        scenes: &["env-pattern-sphere", "env-venice_sunset-sphere"],
        apply: |s| env(s).weighting = EnvWeighting::Uniform,
    },
    Alternative {
        assumption: "envmap.dome_pick",
        alternative: "dome_pick = \"voxel_spacing\"",
        scenes: &["env-pattern-sphere", "env-st_fagans_interior-sphere"],
        apply: |s| env(s).dome_pick = EnvDomePick::VoxelSpacing,
    },
    Alternative {
        assumption: "shafts.f_scale",
        alternative: "f_scale = \"lit_volume\"",
        scenes: &["fig4", "fig6"],
        apply: |s| s.shafts.f_scale = FScale::LitVolume,
    },
    Alternative {
        assumption: "shafts.h_cap",
        alternative: "h_cap = \"none\"",
        scenes: &["fig4", "fig6"],
        apply: |s| s.shafts.h_cap = HCap::None,
    },
    Alternative {
        assumption: "shafts.plane_step",
        alternative: "plane_step = \"plane_spacing\"",
        scenes: &["fig4", "fig6"],
        apply: |s| s.shafts.plane_step = PlaneStep::PlaneSpacing,
    },
];

/// The built-in `name`, or [`WATER_SCENE`].
pub fn scene_named(name: &str) -> Result<Scene, String> {
    if name == WATER_SCENE {
        let mut s = builtin("glare-point").map_err(|e| e.to_string())?;
        let g = s.glare.as_mut().expect("glare-point has glare");
        // The lamp at (0, 0, −20) mirrored in a level puddle at (0, −2, −10): the
        // mirror direction of the light points at the eye (cos α = 1), the incidence
        // angle is atan(10/2) = 78.7° (past water's critical angle 48.8° at η = 1.33).
        g.highlights.push(Highlight {
            material: HighlightMaterial::Water,
            position: [0.0, -2.0, -10.0],
            normal: [0.0, 1.0, 0.0],
            light: [0.0, 0.0, -20.0],
            intensity: 2000.0,
            specular: 1.0,
            eta: 1.33,
            radius: 0.05,
        });
        s.name = format!("{WATER_SCENE}: the point source reflected in water");
        return Ok(s);
    }
    builtin(name).map_err(|e| e.to_string())
}

/// Sizes for a quick run (tests): every scene at `width` × `height` (environment
/// scenes at `env_size`² with a map of side `env_side`), at most `planes` sample
/// planes and `subplanes` sub-planes.
#[derive(Clone, Copy, Debug)]
pub struct Reduced {
    pub width: u32,
    pub height: u32,
    pub planes: u32,
    pub subplanes: u32,
    pub env_size: u32,
    pub env_side: u32,
}

impl Reduced {
    fn apply(&self, s: &mut Scene) {
        if let Some(e) = s.environment.as_mut() {
            e.side = self.env_side;
            s.image.width = self.env_size;
            s.image.height = self.env_size;
        } else {
            s.image.width = self.width;
            s.image.height = self.height;
        }
        s.shafts.planes = s.shafts.planes.min(self.planes);
        s.shafts.subplanes = s.shafts.subplanes.min(self.subplanes);
    }
}

/// A rendered picture in 8-bit levels.
#[derive(Clone, Debug, PartialEq)]
pub struct Picture {
    pub width: u32,
    pub height: u32,
    pub levels: Vec<[f64; 3]>,
}

/// Render a scene as `render --scene` does (the environment scenes through their own
/// renderer), in levels.
pub fn render_picture(scene: &Scene) -> Result<Picture, String> {
    let (width, height) = (scene.image.width, scene.image.height);
    let levels = if environment_scene(scene) {
        let f = render_scene(scene, false).map_err(|e| e.to_string())?;
        f.image.pixels.iter().map(|p| p.map(f64::from)).collect()
    } else {
        render(scene).map_err(|e| e.to_string())?.fb.levels()
    };
    Ok(Picture {
        width,
        height,
        levels,
    })
}

/// One CSV row.
#[derive(Clone, Debug, Serialize)]
pub struct AssumptionRow {
    pub assumption: String,
    pub alternative: String,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    /// Difference of the alternative's picture from the scene as it is, 8-bit levels
    /// over every channel of every pixel.
    pub rms_levels: f64,
    pub max_levels: f64,
    pub mean_abs_levels: f64,
    /// Pixels where any channel differs.
    pub changed_pixels: u64,
}

/// The pictures of one assumption's strip: per scene, the default and each
/// alternative's.
type StripRows = BTreeMap<String, (Picture, Vec<Picture>)>;

/// Render every alternative (at the built-ins' sizes, or `reduced`), write
/// `out/assumptions.csv` and `out/assumptions_<assumption>.png`, and return the rows.
/// `only` keeps the alternatives whose assumption starts with it (None: all).
pub fn assumptions(
    out: &Path,
    reduced: Option<Reduced>,
    only: Option<&str>,
) -> Result<Vec<AssumptionRow>, String> {
    let mut defaults: BTreeMap<&str, Picture> = BTreeMap::new();
    let mut rows = Vec::new();
    let mut strips: BTreeMap<&str, StripRows> = BTreeMap::new();
    for alt in ALTERNATIVES
        .iter()
        .filter(|a| only.is_none_or(|o| a.assumption.starts_with(o)))
    {
        for &name in alt.scenes {
            let mut base = scene_named(name)?;
            if let Some(r) = reduced {
                r.apply(&mut base);
            }
            if !defaults.contains_key(name) {
                let p = render_picture(&base).map_err(|e| format!("{name}: {e}"))?;
                defaults.insert(name, p);
            }
            let mut s = base.clone();
            (alt.apply)(&mut s);
            if s == base {
                return Err(format!(
                    "{}: `{}` is already {name}'s setting (list another scene)",
                    alt.assumption, alt.alternative
                ));
            }
            s.validate()
                .map_err(|e| format!("{name} with {}: {e}", alt.alternative))?;
            let p =
                render_picture(&s).map_err(|e| format!("{name} with {}: {e}", alt.alternative))?;
            let d = &defaults[name];
            let st = error_stats(&p.levels, &d.levels).map_err(|e| e.to_string())?;
            let changed = p
                .levels
                .iter()
                .zip(&d.levels)
                .filter(|(a, b)| a != b)
                .count() as u64;
            rows.push(AssumptionRow {
                assumption: alt.assumption.to_string(),
                alternative: alt.alternative.to_string(),
                scene: name.to_string(),
                width: p.width,
                height: p.height,
                rms_levels: st.rms,
                max_levels: st.max,
                mean_abs_levels: st.mean_abs,
                changed_pixels: changed,
            });
            strips
                .entry(alt.assumption)
                .or_default()
                .entry(name.to_string())
                .or_insert_with(|| (d.clone(), Vec::new()))
                .1
                .push(p);
        }
    }
    crate::report::csv_out::write_csv(&out.join("assumptions.csv"), &rows)?;
    if only.is_none_or(|o| "envmap.dome_pick".starts_with(o)) {
        let side = reduced.map_or(crate::scene::environment::DEFAULT_SIDE, |r| r.env_side);
        let maps = dome_pick_maps(side)?;
        crate::report::csv_out::write_csv(&out.join("assumptions_maps.csv"), &maps)?;
        print!("{}", maps_table(&maps));
    }
    for (assumption, scenes) in &strips {
        let path = out.join(format!("assumptions_{}.png", assumption.replace('.', "_")));
        write_strip(&path, scenes)?;
    }
    Ok(rows)
}

/// One strip: a row per scene — default, then per alternative its picture and
/// |Δ| × [`DIFF_GAIN`] (grey); rows padded to the widest, 4-pixel gaps.
fn write_strip(path: &Path, scenes: &StripRows) -> Result<(), String> {
    const GAP: u32 = 4;
    let row_width = |(d, alts): &(Picture, Vec<Picture>)| {
        d.width + alts.iter().map(|p| 2 * (p.width + GAP)).sum::<u32>()
    };
    let width = scenes.values().map(row_width).max().unwrap_or(1).max(1);
    let height = scenes
        .values()
        .map(|(d, _)| d.height + GAP)
        .sum::<u32>()
        .max(1);
    let mut img = image::RgbaImage::from_pixel(width, height, image::Rgba([40, 40, 40, 255]));
    let mut put = |x0: u32, y0: u32, p: &Picture, f: &dyn Fn(usize) -> [f64; 3]| {
        for y in 0..p.height {
            for x in 0..p.width {
                let v = f((y * p.width + x) as usize).map(|c| c.round().clamp(0.0, 255.0) as u8);
                img.put_pixel(x0 + x, y0 + y, image::Rgba([v[0], v[1], v[2], 255]));
            }
        }
    };
    let mut y0 = 0;
    for (d, alts) in scenes.values() {
        put(0, y0, d, &|i| d.levels[i]);
        let mut x0 = d.width + GAP;
        for p in alts {
            put(x0, y0, p, &|i| p.levels[i]);
            x0 += p.width + GAP;
            put(x0, y0, p, &|i| {
                let m = (0..3)
                    .map(|c| (p.levels[i][c] - d.levels[i][c]).abs())
                    .fold(0.0, f64::max);
                [m * DIFF_GAIN; 3]
            });
            x0 += p.width + GAP;
        }
        y0 += d.height + GAP;
    }
    crate::report::atomic::write_atomically(path, |tmp| {
        img.save(tmp)
            .map_err(|e| format!("{}: {e}", path.display()))
    })
    .map_err(|e| format!("out: {e}"))
}

/// The rows as a terminal table.
pub fn table(rows: &[AssumptionRow]) -> String {
    let mut s = format!(
        "{:<24} {:<34} {:<30} {:>8} {:>8} {:>8} {:>8}\n",
        "assumption", "alternative", "scene", "rms", "max", "mean|Δ|", "changed"
    );
    for r in rows {
        s += &format!(
            "{:<24} {:<34} {:<30} {:>8.3} {:>8.0} {:>8.3} {:>8}\n",
            r.assumption,
            r.alternative,
            r.scene,
            r.rms_levels,
            r.max_levels,
            r.mean_abs_levels,
            r.changed_pixels
        );
    }
    s
}

/// The maps on which `envmap.dome_pick` is measured (the thesis' two: its pattern and
/// a photo; as `reproduce envmap-table3`).
pub const DOME_PICK_MAPS: [&str; 2] = ["pattern", "st_fagans_interior"];

/// One row of `assumptions_maps.csv`: an accelerated map (th = 0.001, the map's auto
/// exposure) built with one dome pick, against the exact prefilter of the same map.
#[derive(Clone, Debug, Serialize)]
pub struct MapRow {
    pub assumption: String,
    /// `dome_pick = "…"` as written in the scene file (the default included).
    pub dome_pick: String,
    pub env: String,
    pub side: u32,
    /// Mean |Δ| over every voxel and channel, in levels (8-bit codes).
    pub mean_abs_levels: f64,
    /// Largest |Δ| of any voxel channel, in levels.
    pub max_abs_levels: f64,
    /// Voxels where any channel differs from the exact map.
    pub changed_voxels: u64,
    /// Wall time of the accelerated build (pyramid, domes, table, filter), seconds.
    pub build_seconds: f64,
    /// Its weight table, MB at 8 bytes per entry.
    pub table_mbytes: f64,
    /// Wall time of the exact build it is compared with, seconds.
    pub exact_seconds: f64,
}

/// `envmap.dome_pick` on the voxel maps themselves: for each of [`DOME_PICK_MAPS`] at
/// side `side`, the exact map, then the accelerated map under each dome pick and its
/// difference from the exact one (the thesis' Table 3 measure, plus the max).
pub fn dome_pick_maps(side: u32) -> Result<Vec<MapRow>, String> {
    let e = |x: rtl_model::ConfigError| x.to_string();
    let params = PrefilterParams::thesis();
    let mut rows = Vec::new();
    for name in DOME_PICK_MAPS {
        let env = EnvMap::builtin(name).map_err(e)?;
        let levels = env_to_levels(&env, env.auto_exposure()).map_err(e)?;
        let t0 = std::time::Instant::now();
        let exact = build_exact(&levels, side, &params).map_err(e)?;
        let exact_seconds = t0.elapsed().as_secs_f64();
        for (pick, written) in [
            (DomePick::HalfWeight, "dome_pick = \"half_weight\""),
            (DomePick::VoxelSpacing, "dome_pick = \"voxel_spacing\""),
        ] {
            let (acc, st) =
                build_accelerated_picked(&levels, side, &params, THESIS_THRESHOLD, pick)
                    .map_err(e)?;
            let (mean, _) = voxel_error(&acc, &exact).ok_or("internal: side mismatch")?;
            let mut max = 0u32;
            let mut changed = 0u64;
            for (a, b) in acc.data().iter().zip(exact.data()) {
                let d = (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0);
                max = max.max(d);
                changed += u64::from(d > 0);
            }
            rows.push(MapRow {
                assumption: "envmap.dome_pick".to_string(),
                dome_pick: written.to_string(),
                env: name.to_string(),
                side,
                mean_abs_levels: mean.iter().sum::<f64>() / 3.0,
                max_abs_levels: f64::from(max),
                changed_voxels: changed,
                build_seconds: st.build_seconds,
                table_mbytes: st.mbytes(),
                exact_seconds,
            });
        }
    }
    Ok(rows)
}

/// The map rows as a terminal table.
pub fn maps_table(rows: &[MapRow]) -> String {
    let mut s = format!(
        "{:<30} {:<20} {:>5} {:>9} {:>6} {:>10} {:>9} {:>9} {:>9}\n",
        "dome_pick", "env", "side", "mean|Δ|", "max", "changed", "build s", "table MB", "exact s"
    );
    for r in rows {
        s += &format!(
            "{:<30} {:<20} {:>5} {:>9.3} {:>6.0} {:>10} {:>9.2} {:>9.1} {:>9.2}\n",
            r.dome_pick,
            r.env,
            r.side,
            r.mean_abs_levels,
            r.max_abs_levels,
            r.changed_voxels,
            r.build_seconds,
            r.table_mbytes,
            r.exact_seconds
        );
    }
    s
}
