//! `sweep --attribute` on a shading scene: the sweep's rows, each with the dominant error
//! source of its configuration from the shading attribution. Its own file because it
//! needs both the sweep and the attribution, and the attribution uses the sweep's
//! configurations.

use super::attribute::{attribute_shading, ShadingConfig};
use super::sweep::{
    check_param, shading_jobs, shading_sweep_resumable, sweep_id, Job, ShadingScene,
    ShadingSweepOptions,
};
use crate::report::shard::Shard;
use crate::report::sweep_out::parse_int_values;
use std::path::{Path, PathBuf};

/// One row of `sweep --attribute`: the sweep's row and, from
/// [`attribute_shading`] at that row's configuration, the source
/// whose ideal alone removes the most squared error and its share.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct AttributedSweepRow {
    pub param: String,
    pub value: u32,
    pub mean_abs_levels: f64,
    pub rms_levels: f64,
    pub max_levels: f64,
    pub predicted_hw_seconds: f64,
    pub wall_seconds: f64,
    pub gates_nand2: f64,
    pub ram_bits: u64,
    pub dominant_source: String,
    pub dominant_share: f64,
}

/// [`super::sweep::shading_sweep`] with each row's dominant error source (`sweep --attribute`):
/// the sweep runs as without the flag (its identity marked `attribute`, so a run
/// without the flag never resumes it), then each row's configuration is attributed
/// into `DIR/attribute_<param>_<value>/` and `DIR/sweep_<param>.csv` is rewritten
/// with the two extra columns. Only the scenes [`super::attribute`] covers: a
/// `combiner_bits` or `shading-vertex` sweep is refused naming `--attribute` before
/// anything runs.
pub fn shading_sweep_attributed(
    scene: &str,
    param: &str,
    values: &[u32],
    out: &Path,
    opts: &ShadingSweepOptions,
) -> Result<(Vec<AttributedSweepRow>, PathBuf, PathBuf), String> {
    let (param, jobs, view) = shading_jobs(scene, param, values, opts)?;
    let sc = ShadingScene::parse(scene)?;
    let configs: Vec<ShadingConfig> = jobs
        .iter()
        .map(|(_, j)| {
            let mut c = ShadingConfig::new(scene, view.size)?;
            c.view = view;
            match j {
                Job::Model(_, cfg) => c.path = *cfg,
                Job::Lookup(l) => c.lookup_path = *l,
                _ => {
                    return Err(format!(
                        "--attribute: {} {param} has no attribution (it covers the \
                         shading-<model> sweeps and shading-specular's lookup path)",
                        sc.name()
                    ))
                }
            }
            c.check()?;
            Ok(c)
        })
        .collect::<Result<_, String>>()?;
    let mut id = sweep_id(&sc, param, values, opts);
    id.settings.insert("attribute".into(), "dominant".into());
    let (rows, csv, png) = shading_sweep_resumable(scene, &id, param, values, out, opts, false)?;
    let mut v = Vec::with_capacity(rows.len());
    for (r, c) in rows.iter().zip(&configs) {
        let a = attribute_shading(c, &out.join(format!("attribute_{param}_{}", r.value)))?;
        let (name, share) = a
            .dominant()
            .map_or(("none".to_string(), 0.0), |d| (d.source.clone(), d.share));
        v.push(AttributedSweepRow {
            param: r.param.clone(),
            value: r.value,
            mean_abs_levels: r.mean_abs_levels,
            rms_levels: r.rms_levels,
            max_levels: r.max_levels,
            predicted_hw_seconds: r.predicted_hw_seconds,
            wall_seconds: r.wall_seconds,
            gates_nand2: r.gates_nand2,
            ram_bits: r.ram_bits,
            dominant_source: name,
            dominant_share: share,
        });
    }
    crate::report::csv_out::write_csv(&csv, &v)?;
    Ok((v, csv, png))
}

/// The CLI of `sweep --attribute` (arguments as [`super::sweep::shading_sweep_cli`] takes them);
/// refused, naming `--attribute`, for a scene other than `shading-*` and with
/// `--shard` or `--resume` (the attributions are not journalled).
pub fn attributed_sweep_cli(
    scene: &str,
    param: &str,
    values: &str,
    out: &Path,
    image: Option<(u32, u32)>,
    shard: Option<Shard>,
    resume: bool,
) -> Result<(), String> {
    if shard.is_some() || resume {
        return Err(
            "--attribute: not with --shard or --resume (the attributions are not journalled)"
                .into(),
        );
    }
    let sc = ShadingScene::parse(scene)?;
    check_param(&sc, param)?;
    let values = parse_int_values(values)?;
    let mut opts = ShadingSweepOptions::default();
    if let Some((w, h)) = image {
        if w != h {
            return Err(format!("--image: the sphere view is square, not {w}x{h}"));
        }
        opts.view_size = w;
    }
    let (rows, csv, png) = shading_sweep_attributed(scene, param, &values, out, &opts)?;
    println!(
        "sweep {param} on {scene} with attribution: wrote {} and {}",
        csv.display(),
        png.display()
    );
    for r in &rows {
        println!(
            "{} = {}: mean {:.3}, RMS {:.3} levels; dominant source {} ({:.1} %)",
            r.param,
            r.value,
            r.mean_abs_levels,
            r.rms_levels,
            r.dominant_source,
            r.dominant_share * 100.0
        );
    }
    Ok(())
}
