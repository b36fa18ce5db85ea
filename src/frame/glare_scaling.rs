//! `reproduce glare-scaling`: how a glare frame's cost grows with its sources. The
//! city at night of [`city_lights`] (96 × 64) with 250 … 10 000 point sources, each
//! rendered as `render --scene` renders it — the frame, the out-of-range check with
//! its sensitivity renders, the PNG — and timed in one run. Per row: seconds, seconds
//! per source and its ratio to the smallest frame's, the reduced frames the range
//! check rendered. Each count is run twice: the city as it is (sources of one kind and
//! brightness share their tables), and with every source's brightness made distinct
//! (scaled by 1 + k·10⁻⁵ for the k-th source: no two share tables). The scenes are
//! written beside (`city_N.toml`, `city_N_distinct.toml`) so any row can be rendered
//! again with `render --scene`.

use super::range::check_counted;
use super::run::render;
use crate::report::csv_out::write_csv;
use crate::scene::builtin_glare::city_lights;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// The source counts timed.
pub const SOURCE_COUNTS: [usize; 6] = [250, 500, 1000, 2000, 5000, 10_000];

/// The seed the cities are placed with.
pub const CITY_SEED: u64 = 11;

/// One timed frame.
#[derive(Clone, Debug, Serialize)]
pub struct ScalingRow {
    pub sources: usize,
    /// "shared" (the city) or "distinct" (every source's brightness its own).
    pub tables: &'static str,
    pub seconds: f64,
    pub micros_per_source: f64,
    /// Seconds per source over the first row's.
    pub per_source_ratio: f64,
    /// Out-of-range warnings the frame raised.
    pub warnings: usize,
    /// Reduced frames the range check rendered to name the driving field.
    pub range_renders: usize,
}

/// Render and time the city at each of `counts` sources, shared then distinct; rows
/// into `DIR/glare_scaling.csv`, scenes and pictures as `DIR/city_N.toml`, `city_N.png`
/// and `city_N_distinct.{toml,png}`.
pub fn glare_scaling(out: &Path, counts: &[usize]) -> Result<Vec<ScalingRow>, String> {
    std::fs::create_dir_all(out).map_err(|e| format!("out: {}: {e}", out.display()))?;
    let mut rows: Vec<ScalingRow> = Vec::new();
    for tables in ["shared", "distinct"] {
        let first = rows.len();
        for &n in counts {
            let mut scene = city_lights(n, CITY_SEED);
            let name = if tables == "shared" {
                format!("city_{n}")
            } else {
                distinct(&mut scene);
                format!("city_{n}_distinct")
            };
            let row = time_render(out, &name, &scene, tables, rows.get(first))?;
            rows.push(row);
        }
    }
    write_csv(&out.join("glare_scaling.csv"), &rows)?;
    Ok(rows)
}

/// Every source's brightness its own: the k-th scaled by 1 + k·10⁻⁵.
fn distinct(scene: &mut crate::scene::format::Scene) {
    if let Some(g) = scene.glare.as_mut() {
        for (k, s) in g.sources.iter_mut().enumerate() {
            s.intensity *= 1.0 + (k + 1) as f64 * 1e-5;
        }
    }
}

/// Write `scene` as DIR/NAME.toml, then render it as `render --scene` does (frame,
/// range check, DIR/NAME.png), timed.
fn time_render(
    out: &Path,
    name: &str,
    scene: &crate::scene::format::Scene,
    tables: &'static str,
    first: Option<&ScalingRow>,
) -> Result<ScalingRow, String> {
    let n = scene.glare.as_ref().map_or(0, |g| g.sources.len()).max(1);
    let toml = toml::to_string(scene).map_err(|e| e.to_string())?;
    let file = out.join(format!("{name}.toml"));
    std::fs::write(&file, toml).map_err(|e| format!("out: {}: {e}", file.display()))?;
    let png = out.join(format!("{name}.png"));
    let t0 = Instant::now();
    let f = render(scene).map_err(|e| e.to_string())?;
    let (warnings, range_renders) = check_counted(scene, &f);
    f.fb.save_png(&png)
        .map_err(|e| format!("out: {}: {e}", png.display()))?;
    let seconds = t0.elapsed().as_secs_f64();
    let per = seconds / n as f64;
    let first = first.map_or(per, |r| r.seconds / r.sources as f64);
    Ok(ScalingRow {
        sources: n,
        tables,
        seconds,
        micros_per_source: per * 1e6,
        per_source_ratio: per / first,
        warnings: warnings.len(),
        range_renders,
    })
}

/// The rows as a table.
pub fn table(rows: &[ScalingRow]) -> String {
    let mut s = String::from(
        "sources  tables    seconds  us_per_source  per_source_ratio  warnings  range_renders\n",
    );
    for r in rows {
        s.push_str(&format!(
            "{:>7}  {:<8}  {:>7.3}  {:>13.1}  {:>16.2}  {:>8}  {:>13}\n",
            r.sources,
            r.tables,
            r.seconds,
            r.micros_per_source,
            r.per_source_ratio,
            r.warnings,
            r.range_renders
        ));
    }
    s
}
