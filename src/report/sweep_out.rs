//! The sweep report shared by every pipeline's `sweep`: the values parser, one row per
//! value (error against the f64 reference, predicted and wall time, gates, RAM bits),
//! the CSV and plot writer and the terminal table.

use crate::report::csv_out::write_csv;
use crate::report::plot::{line_plot, Axis, PlotSpec, Series};
use crate::report::shard::{finish_shard, Shard, ShardSet, SweepId};
use crate::report::table::text_table;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Most values one sweep takes (the shafts sweep's limit too).
pub const MAX_VALUES: usize = 1000;

/// `10,20,30` or ranges `4..10:2` (inclusive), non-negative integers; errors name
/// `values`. A range's length is checked before it is expanded.
pub fn parse_int_values(text: &str) -> Result<Vec<u32>, String> {
    let mut out = Vec::new();
    for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let bad = || format!("values: '{item}' is not an integer or a range start..end:step");
        if let Some((a, rest)) = item.split_once("..") {
            let (b, step) = rest.split_once(':').unwrap_or((rest, "1"));
            let (a, b, step): (u32, u32, u32) = (
                a.trim().parse().map_err(|_| bad())?,
                b.trim().parse().map_err(|_| bad())?,
                step.trim().parse().map_err(|_| bad())?,
            );
            if step == 0 || b < a {
                return Err(bad());
            }
            // Count before expanding: a range of billions is refused, not allocated.
            let count = ((b - a) / step) as usize + 1;
            if out.len() + count > MAX_VALUES {
                return Err(format!(
                    "values: '{item}' gives {count} values; a sweep has at most {MAX_VALUES}"
                ));
            }
            out.extend((a..=b).step_by(step as usize));
        } else {
            if out.len() + 1 > MAX_VALUES {
                return Err(format!("values: more than {MAX_VALUES} values"));
            }
            out.push(item.parse().map_err(|_| bad())?);
        }
    }
    if out.is_empty() {
        return Err("values: no values given".into());
    }
    Ok(out)
}

/// One row of `sweep_<param>.csv` (read back from shard files by `sweep merge`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepRow {
    pub param: String,
    pub value: u32,
    pub mean_abs_levels: f64,
    pub rms_levels: f64,
    pub max_levels: f64,
    pub predicted_hw_seconds: f64,
    pub wall_seconds: f64,
    pub gates_nand2: f64,
    pub ram_bits: u64,
}

/// Write `DIR/sweep_<param>.csv` (the rows) and `DIR/sweep_<param>.png` (mean and RMS
/// error on the left axis, the wall time on the right, against the value); every
/// sweep with this row shape (glare, shading) writes its outputs here, each file
/// atomically.
pub fn write_sweep(
    rows: &[SweepRow],
    title: &str,
    param: &str,
    out: &Path,
) -> Result<(PathBuf, PathBuf), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("out: {}: {e}", out.display()))?;
    let csv = out.join(format!("sweep_{param}.csv"));
    let png = out.join(format!("sweep_{param}.png"));
    write_csv(&csv, rows)?;
    let mut spec = PlotSpec::new(title, param, "error against the f64 reference (levels)");
    spec.y_right_label = Some("wall time of the simulation (s)".into());
    let pts = |f: &dyn Fn(&SweepRow) -> f64| {
        rows.iter()
            .map(|r| (r.value as f64, f(r)))
            .collect::<Vec<_>>()
    };
    line_plot(
        &png,
        &spec,
        &[
            Series {
                label: "mean |Δ|".into(),
                points: pts(&|r| r.mean_abs_levels),
                axis: Axis::Left,
            },
            Series {
                label: "RMS".into(),
                points: pts(&|r| r.rms_levels),
                axis: Axis::Left,
            },
            Series {
                label: "wall time".into(),
                points: pts(&|r| r.wall_seconds),
                axis: Axis::Right,
            },
        ],
    )?;
    Ok((csv, png))
}

/// The rows as a terminal table, headed by the param's name; the columns are named as
/// in the CSV.
pub fn sweep_table(param: &str, rows: &[SweepRow]) -> String {
    let table: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.value.to_string(),
                format!("{:.3}", r.mean_abs_levels),
                format!("{:.3}", r.rms_levels),
                format!("{:.1}", r.max_levels),
                format!("{:.6}", r.predicted_hw_seconds),
                format!("{:.3}", r.wall_seconds),
                format!("{:.0}", r.gates_nand2),
                r.ram_bits.to_string(),
            ]
        })
        .collect();
    text_table(
        &[
            param,
            "mean_abs_levels",
            "rms_levels",
            "max_levels",
            "predicted_hw_seconds",
            "wall_seconds",
            "gates_nand2",
            "ram_bits",
        ],
        &table,
    )
}

/// `sweep merge` of a glare or shading sweep: the shards' rows written as the
/// unsharded sweep writes them (CSV, plot, table on stdout).
pub fn merge_sweep(set: &ShardSet, out: &Path) -> Result<(), String> {
    let rows: Vec<SweepRow> = set.rows()?;
    let (csv, png) = write_sweep(&rows, &set.id.title, &set.id.param, out)?;
    println!("{}", set.merged(&csv, &png));
    print!("{}", sweep_table(&set.id.param, &rows));
    Ok(())
}

/// A glare or shading shard run's end: the shard file, the line saying so, the table
/// of its rows.
pub fn shard_sweep(
    out: &Path,
    id: &SweepId,
    shard: Shard,
    rows: &[(usize, SweepRow)],
) -> Result<(), String> {
    println!("{}", finish_shard(out, id, shard, rows)?);
    let rows: Vec<SweepRow> = rows.iter().map(|(_, r)| r.clone()).collect();
    print!("{}", sweep_table(&id.param, &rows));
    Ok(())
}

/// A sweep of [`SweepRow`]s run as the command line asks: with `shard`, only its share
/// of the values into its shard file (the line and table printed; returns None);
/// without, every value into `out/sweep_<id.param>.csv`, continuing with `resume` from
/// the rows an interrupted run left, then the CSV and plot written (returns the rows
/// and the two paths). `rows` renders the values a journal lacks (those of `shard`).
pub fn run_sweep(
    out: &Path,
    id: &SweepId,
    shard: Option<Shard>,
    resume: bool,
    mut rows: impl FnMut(
        Option<Shard>,
        &mut crate::report::resume::Journal<SweepRow>,
    ) -> Result<(), String>,
) -> Result<Option<(Vec<SweepRow>, PathBuf, PathBuf)>, String> {
    use crate::report::resume::Journal;
    if let Some(shard) = shard {
        let mut journal = Journal::shard(out, id, shard, resume)?;
        rows(Some(shard), &mut journal)?;
        shard_sweep(out, id, shard, &journal.into_rows())?;
        return Ok(None);
    }
    let csv = out.join(format!("sweep_{}.csv", id.param));
    let mut journal = Journal::plain(&csv, id, resume, |r: &SweepRow| r.value.to_string())?;
    rows(None, &mut journal)?;
    let done: Vec<SweepRow> = journal.into_rows().into_iter().map(|(_, r)| r).collect();
    let (csv, png) = write_sweep(&done, &id.title, &id.param, out)?;
    Ok(Some((done, csv, png)))
}
