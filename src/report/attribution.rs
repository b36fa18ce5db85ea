//! Error attribution by ablation: which unit, table or host approximation a
//! scene's error against its f64 reference comes from.
//!
//! The scene is rendered once as configured, then once per error source with only
//! that source made ideal (a wide width, a larger table, more planes, the better
//! scaling: each pipeline says what "ideal" means for each of its sources), then with
//! every source ideal at once. With E the squared error against the reference summed
//! over every pixel and channel:
//!
//! * `removed` = E(configured) − E(only this source ideal); `share` = removed /
//!   E(configured). A negative share means the source's ideal alone adds error (e.g.
//!   more planes at 8 bits add rounding).
//! * the interaction remainder = (E(configured) − E(all ideal)) − Σ removed: what the
//!   sources remove only together (or remove twice). When it is more than
//!   [`PAIR_THRESHOLD`] of E(configured), the three largest sources are removed in
//!   pairs and each pair's interaction (removed by the pair − the two singles) is
//!   reported.
//! * where: the bounding box of the pixels the source's ideal changes by more than one
//!   level (any channel), and the screen band (top, middle or bottom third of the rows)
//!   holding most of the squared error it removes.
//!
//! This module knows images only (levels, row-major, 3 channels); the pipelines give
//! the scenes and their renders. It imports nothing of `scene` or `pipeline`.

use crate::report::csv_out::write_csv;
use crate::report::metrics::{error_stats, ErrorStats};
use crate::report::plot::{ensure_font, FONT_FAMILY};
use crate::report::progress::progress_bar;
use plotters::prelude::*;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Remainder (as a fraction of the configured squared error) above which pairs are
/// removed to find which sources interact (the 20 %).
pub const PAIR_THRESHOLD: f64 = 0.20;
/// Sources whose share exceeds this get a difference image (the 5 %).
pub const DIFF_IMAGE_SHARE: f64 = 0.05;
/// A pixel is "changed" by a source when some channel moves by more than this many
/// levels.
pub const CHANGED_LEVELS: f64 = 1.0;
/// How many of the largest sources are removed in pairs.
pub const PAIR_SOURCES: usize = 3;

/// One error source and what "ideal" means for it.
pub struct Source<S> {
    /// Short name (CSV, bar chart, difference image file name).
    pub name: String,
    /// What the ideal is, in words with the field and value ("shafts.texel_bits 8 → 16").
    pub ideal: String,
    /// Makes the source ideal on a copy of the scene.
    pub make_ideal: Box<dyn Fn(&mut S)>,
}

/// The bound within which "all ideal" must come back to the reference.
#[derive(Clone, Debug)]
pub struct Bound {
    /// Largest mean |Δ| over every channel value, levels.
    pub mean_abs: f64,
    /// Largest fraction of channel values that may differ by more than
    /// `outlier_levels` (pixels on edges the ideal cannot reach).
    pub outlier_fraction: f64,
    pub outlier_levels: f64,
    /// Where the bound comes from, in words.
    pub why: String,
}

/// A render: the image and its f64 reference, both in levels.
pub type Rendered = (Vec<[f64; 3]>, Vec<[f64; 3]>);

/// One row of `attribution.csv`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AttributionRow {
    /// `configured`, a source's name, `all ideal`, `a + b` (a pair) or
    /// `interaction remainder`.
    pub source: String,
    pub kind: String,
    pub ideal: String,
    /// Error against the reference with only this ideal (levels).
    pub mean_levels: f64,
    pub rms_levels: f64,
    pub max_levels: f64,
    /// Squared error against the reference, summed over pixels and channels.
    pub sq_error: f64,
    /// Configured squared error − this one.
    pub removed_sq: f64,
    /// removed / configured squared error.
    pub share: f64,
    /// Pairs: removed by the pair − the two singles' removals, as a share.
    pub interaction_share: f64,
    /// Pixels the ideal changes by more than [`CHANGED_LEVELS`].
    pub changed_pixels: u64,
    /// Their bounding box `x X0–X1, y Y0–Y1` (inclusive pixel coordinates), or `none
    /// by > 1 level` when no pixel changed that much.
    pub bbox: String,
    /// `top`, `middle` or `bottom` third holding most of the removed squared error
    /// (changes of any size count here, so a band is named even when `bbox` finds no
    /// pixel changed by more than [`CHANGED_LEVELS`]).
    pub band: String,
    /// Fraction of the removed squared error in that band.
    pub band_share: f64,
}

/// What [`attribute`] found.
#[derive(Clone, Debug)]
pub struct Attribution {
    pub rows: Vec<AttributionRow>,
    pub configured: ErrorStats,
    pub all_ideal: ErrorStats,
    /// Fraction of the channel values of "all ideal" off by more than the bound's
    /// outlier level.
    pub all_ideal_outliers: f64,
    pub within_bound: bool,
    /// (E(configured) − E(all ideal) − Σ removed) / E(configured).
    pub remainder_share: f64,
    pub csv: PathBuf,
    pub png: PathBuf,
    pub diff_images: Vec<PathBuf>,
}

impl Attribution {
    /// The single source removing the most squared error.
    pub fn dominant(&self) -> Option<&AttributionRow> {
        self.rows
            .iter()
            .filter(|r| r.kind == "source")
            .max_by(|a, b| a.removed_sq.total_cmp(&b.removed_sq))
    }
}

fn sq_error(img: &[[f64; 3]], truth: &[[f64; 3]]) -> f64 {
    img.iter()
        .zip(truth)
        .map(|(a, b)| (0..3).map(|c| (a[c] - b[c]).powi(2)).sum::<f64>())
        .sum()
}

/// Bounding box and band of what `img` changes against `base` (see the module notes).
fn where_in_image(
    base: &[[f64; 3]],
    img: &[[f64; 3]],
    truth: &[[f64; 3]],
    truth0: &[[f64; 3]],
    w: u32,
    h: u32,
) -> (u64, String, String, f64) {
    let mut n = 0u64;
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0u32, 0u32);
    let mut bands = [0.0f64; 3];
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let d = (0..3)
                .map(|c| (img[i][c] - base[i][c]).abs())
                .fold(0.0, f64::max);
            if d > CHANGED_LEVELS {
                n += 1;
                x0 = x0.min(x);
                y0 = y0.min(y);
                x1 = x1.max(x);
                y1 = y1.max(y);
            }
            let e0: f64 = (0..3).map(|c| (base[i][c] - truth0[i][c]).powi(2)).sum();
            let e: f64 = (0..3).map(|c| (img[i][c] - truth[i][c]).powi(2)).sum();
            bands[(y as u64 * 3 / h as u64) as usize] += e0 - e;
        }
    }
    // No pixel changed by more than CHANGED_LEVELS: the source's changes are smaller
    // (spread thin), though its band can still hold most of what it removes.
    let bbox = if n == 0 {
        format!("none by > {CHANGED_LEVELS} level")
    } else {
        format!("x {x0}–{x1}, y {y0}–{y1}")
    };
    // The band's part of what the source removes where it removes any (a band where
    // it adds error does not count against the others).
    let total: f64 = bands.iter().map(|b| b.max(0.0)).sum();
    let (k, best) = bands
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map(|(k, v)| (k, *v))
        .unwrap_or((0, 0.0));
    let (band, share) = if total > 0.0 && best > 0.0 {
        (["top", "middle", "bottom"][k].to_string(), best / total)
    } else {
        ("none".to_string(), 0.0)
    };
    (n, bbox, band, share)
}

/// The row of one render against the configured one.
#[allow(clippy::too_many_arguments)]
fn row(
    source: &str,
    kind: &str,
    ideal: &str,
    r: &Rendered,
    base: &Rendered,
    e0: f64,
    w: u32,
    h: u32,
) -> Result<AttributionRow, String> {
    let st = error_stats(&r.0, &r.1).map_err(|e| e.to_string())?;
    let e = sq_error(&r.0, &r.1);
    let (changed_pixels, bbox, band, band_share) =
        where_in_image(&base.0, &r.0, &r.1, &base.1, w, h);
    let removed = e0 - e;
    Ok(AttributionRow {
        source: source.to_string(),
        kind: kind.to_string(),
        ideal: ideal.to_string(),
        mean_levels: st.mean_abs,
        rms_levels: st.rms,
        max_levels: st.max,
        sq_error: e,
        removed_sq: removed,
        share: if e0 > 0.0 { removed / e0 } else { 0.0 },
        interaction_share: 0.0,
        changed_pixels,
        bbox,
        band,
        band_share,
    })
}

/// File-name form of a source name.
fn slug(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect();
    s.split('_')
        .filter(|p| !p.is_empty())
        .collect::<Vec<_>>()
        .join("_")
}

/// Run the attribution of `base` (see the module notes; `name` titles the chart) and
/// write `out/attribution.csv`,
/// `out/attribution.png` and `out/diff_<source>.png` per source above
/// [`DIFF_IMAGE_SHARE`]. Every ideal scene is built and passed to `check` before
/// anything is rendered or written; `render` gives an image and its reference.
#[allow(clippy::too_many_arguments)]
pub fn attribute<S: Clone>(
    name: &str,
    base: &S,
    (w, h): (u32, u32),
    sources: &[Source<S>],
    bound: &Bound,
    check: impl Fn(&S) -> Result<(), String>,
    render: impl Fn(&S) -> Result<Rendered, String>,
    out: &Path,
) -> Result<Attribution, String> {
    let (singles, all) = ideal_scenes(base, sources, &check)?;
    std::fs::create_dir_all(out).map_err(|e| format!("out: {}: {e}", out.display()))?;
    let Singles {
        r0,
        e0,
        mut rows,
        renders,
        ra,
    } = singles_rendered(base, (w, h), sources, &singles, &all, &render)?;
    let all = all_ideal_rows(&mut rows, &ra, &r0, e0, (w, h), bound)?;
    // Pairs of the largest sources when the remainder is large.
    if all.remainder_share.abs() > PAIR_THRESHOLD {
        pair_rows(base, sources, &render, &mut rows, &r0, e0, (w, h))?;
    }

    let csv = out.join("attribution.csv");
    write_csv(&csv, &rows)?;
    let png = out.join("attribution.png");
    let title = format!("{name} ({w}x{h}): error removed by making one source ideal");
    bar_chart(&png, &title, &rows)?;
    let mut diff_images = Vec::new();
    for (k, s) in sources.iter().enumerate() {
        if rows[k + 1].share > DIFF_IMAGE_SHARE {
            let p = out.join(format!("diff_{}.png", slug(&s.name)));
            diff_png(&p, &r0.0, &renders[k].0, w, h)?;
            diff_images.push(p);
        }
    }
    Ok(Attribution {
        rows,
        configured: error_stats(&r0.0, &r0.1).map_err(|e| e.to_string())?,
        all_ideal: all.stats,
        all_ideal_outliers: all.outliers,
        within_bound: all.within_bound,
        remainder_share: all.remainder_share,
        csv,
        png,
        diff_images,
    })
}

/// The ideal scenes, each passed to `check` (`base` first): one per source with only
/// that source ideal, and the scene with every source ideal.
fn ideal_scenes<S: Clone>(
    base: &S,
    sources: &[Source<S>],
    check: &impl Fn(&S) -> Result<(), String>,
) -> Result<(Vec<S>, S), String> {
    check(base)?;
    let singles: Vec<S> = sources
        .iter()
        .map(|s| {
            let mut v = base.clone();
            (s.make_ideal)(&mut v);
            check(&v).map_err(|e| format!("source {} ({}): {e}", s.name, s.ideal))?;
            Ok(v)
        })
        .collect::<Result<_, String>>()?;
    let mut all = base.clone();
    for s in sources {
        (s.make_ideal)(&mut all);
    }
    check(&all).map_err(|e| format!("all ideal: {e}"))?;
    Ok((singles, all))
}

/// The configured render, one render per single ideal and the all-ideal render, with
/// the rows of the configured scene and of each single source.
struct Singles {
    r0: Rendered,
    /// The configured squared error.
    e0: f64,
    rows: Vec<AttributionRow>,
    /// One per source, in the sources' order.
    renders: Vec<Rendered>,
    ra: Rendered,
}

/// Render the configured scene (checked to be `w` × `h`), each single ideal (its row
/// made as it comes) and all ideal, under one progress bar.
fn singles_rendered<S>(
    base: &S,
    (w, h): (u32, u32),
    sources: &[Source<S>],
    singles: &[S],
    all: &S,
    render: &impl Fn(&S) -> Result<Rendered, String>,
) -> Result<Singles, String> {
    let bar = progress_bar(sources.len() as u64 + 2, "attribute");
    let step = |what: &str, s: &S| {
        let r = render(s).map_err(|e| format!("{what}: {e}"));
        bar.inc(1);
        r
    };
    let fail = |e: String| {
        bar.abandon();
        e
    };
    let r0 = step("configured", base).map_err(fail)?;
    if r0.0.len() != (w as usize) * (h as usize) || r0.1.len() != r0.0.len() {
        return Err(fail(format!(
            "internal: the render is {} pixels, not {w}x{h}",
            r0.0.len()
        )));
    }
    let e0 = sq_error(&r0.0, &r0.1);
    let mut rows = vec![row(
        "configured",
        "configured",
        "as the scene says",
        &r0,
        &r0,
        e0,
        w,
        h,
    )?];
    let mut renders = Vec::with_capacity(sources.len());
    for (s, v) in sources.iter().zip(singles) {
        let r = step(&s.name, v).map_err(fail)?;
        rows.push(row(&s.name, "source", &s.ideal, &r, &r0, e0, w, h)?);
        renders.push(r);
    }
    let ra = step("all ideal", all).map_err(fail)?;
    bar.finish_and_clear();
    Ok(Singles {
        r0,
        e0,
        rows,
        renders,
        ra,
    })
}

/// What the all-ideal render gives: the remainder's share, its error, its outlier
/// fraction and whether it is within the bound.
struct AllIdeal {
    remainder_share: f64,
    stats: ErrorStats,
    outliers: f64,
    within_bound: bool,
}

/// The all-ideal row (with the interaction remainder as its interaction share) and the
/// interaction remainder's row, pushed after the singles' rows.
fn all_ideal_rows(
    rows: &mut Vec<AttributionRow>,
    ra: &Rendered,
    r0: &Rendered,
    e0: f64,
    (w, h): (u32, u32),
    bound: &Bound,
) -> Result<AllIdeal, String> {
    let mut all_row = row(
        "all ideal",
        "all_ideal",
        "every source ideal at once",
        ra,
        r0,
        e0,
        w,
        h,
    )?;
    let removed_all = all_row.removed_sq;
    let sum_single: f64 = rows
        .iter()
        .filter(|r| r.kind == "source")
        .map(|r| r.removed_sq)
        .sum();
    let remainder = removed_all - sum_single;
    let remainder_share = if e0 > 0.0 { remainder / e0 } else { 0.0 };
    all_row.interaction_share = remainder_share;
    let all_stats = error_stats(&ra.0, &ra.1).map_err(|e| e.to_string())?;
    let outliers =
        ra.0.iter()
            .zip(&ra.1)
            .map(|(a, b)| {
                (0..3)
                    .filter(|&c| (a[c] - b[c]).abs() > bound.outlier_levels)
                    .count()
            })
            .sum::<usize>() as f64
            / (ra.0.len() * 3).max(1) as f64;
    let within_bound = all_stats.mean_abs <= bound.mean_abs && outliers <= bound.outlier_fraction;
    rows.push(all_row);
    rows.push(AttributionRow {
        source: "interaction remainder".into(),
        kind: "remainder".into(),
        ideal: "all ideal's removal − the sum of the single removals".into(),
        mean_levels: f64::NAN,
        rms_levels: f64::NAN,
        max_levels: f64::NAN,
        sq_error: f64::NAN,
        removed_sq: remainder,
        share: remainder_share,
        interaction_share: remainder_share,
        changed_pixels: 0,
        bbox: "none".into(),
        band: "none".into(),
        band_share: 0.0,
    });
    Ok(AllIdeal {
        remainder_share,
        stats: all_stats,
        outliers,
        within_bound,
    })
}

/// The pairs of the [`PAIR_SOURCES`] sources removing the most (by |removed|), each
/// rendered with both ideal; its interaction share is what the pair removes beyond
/// the two singles (`rows[1..]` are the singles, in the sources' order).
fn pair_rows<S: Clone>(
    base: &S,
    sources: &[Source<S>],
    render: &impl Fn(&S) -> Result<Rendered, String>,
    rows: &mut Vec<AttributionRow>,
    r0: &Rendered,
    e0: f64,
    (w, h): (u32, u32),
) -> Result<(), String> {
    let mut order: Vec<usize> = (0..sources.len()).collect();
    order.sort_by(|&a, &b| {
        rows[b + 1]
            .removed_sq
            .abs()
            .total_cmp(&rows[a + 1].removed_sq.abs())
    });
    order.truncate(PAIR_SOURCES);
    let pairs: Vec<(usize, usize)> = order
        .iter()
        .enumerate()
        .flat_map(|(k, &a)| order[k + 1..].iter().map(move |&b| (a, b)))
        .collect();
    let bar = progress_bar(pairs.len() as u64, "attribute pairs");
    for (a, b) in pairs {
        let mut v = base.clone();
        (sources[a].make_ideal)(&mut v);
        (sources[b].make_ideal)(&mut v);
        let name = format!("{} + {}", sources[a].name, sources[b].name);
        let r = render(&v).map_err(|e| {
            bar.abandon();
            format!("{name}: {e}")
        })?;
        bar.inc(1);
        let mut pr = row(
            &name,
            "pair",
            &format!("{}; {}", sources[a].ideal, sources[b].ideal),
            &r,
            r0,
            e0,
            w,
            h,
        )?;
        pr.interaction_share = if e0 > 0.0 {
            (pr.removed_sq - rows[a + 1].removed_sq - rows[b + 1].removed_sq) / e0
        } else {
            0.0
        };
        rows.push(pr);
    }
    bar.finish_and_clear();
    Ok(())
}

/// What the ideal changes: red where the ideal image is brighter than the configured
/// one (the hardware is too dark there), blue where it is darker; the largest change
/// (over the channels' mean) is full scale, over a dim grey copy of the configured
/// image so that the change can be placed in the frame.
pub fn diff_png(
    path: &Path,
    base: &[[f64; 3]],
    ideal: &[[f64; 3]],
    w: u32,
    h: u32,
) -> Result<(), String> {
    let d: Vec<f64> = base
        .iter()
        .zip(ideal)
        .map(|(a, b)| (0..3).map(|c| b[c] - a[c]).sum::<f64>() / 3.0)
        .collect();
    let m = d.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1.0);
    let img = image::RgbImage::from_fn(w, h, |x, y| {
        let i = (y * w + x) as usize;
        let g = ((base[i][0] + base[i][1] + base[i][2]) / 3.0 * 0.25).clamp(0.0, 63.0);
        let v = (d[i].abs() / m * 255.0).clamp(0.0, 255.0);
        let (r, b) = if d[i] > 0.0 {
            (v.max(g), g)
        } else {
            (g, v.max(g))
        };
        image::Rgb([r as u8, g as u8, b as u8])
    });
    crate::report::atomic::write_atomically(path, |tmp| {
        img.save_with_format(tmp, image::ImageFormat::Png)
            .map_err(|e| format!("out: {}: {e}", path.display()))
    })
}

/// Horizontal bars: each source's share of the configured squared error (%), the
/// interaction remainder and the pairs' interactions.
fn bar_chart(path: &Path, title: &str, rows: &[AttributionRow]) -> Result<(), String> {
    ensure_font().map_err(|e| format!("{}: {e}", path.display()))?;
    let bars: Vec<(String, f64)> = rows
        .iter()
        .filter(|r| matches!(r.kind.as_str(), "source" | "remainder" | "pair"))
        .map(|r| {
            let v = if r.kind == "pair" {
                r.interaction_share
            } else {
                r.share
            };
            let label = if r.kind == "pair" {
                format!("{} (interaction)", r.source)
            } else {
                r.source.clone()
            };
            (label, v * 100.0)
        })
        .filter(|(_, v)| v.is_finite())
        .collect();
    let (w, h) = (1000u32, (140 + 34 * bars.len() as u32).max(300));
    let lo = bars.iter().map(|b| b.1).fold(0.0f64, f64::min).min(0.0) - 2.0;
    let hi = bars.iter().map(|b| b.1).fold(0.0f64, f64::max).max(0.0) + 8.0;
    let n = bars.len().max(1);
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        let e = |x: String| format!("{}: {x}", path.display());
        let mut chart = ChartBuilder::on(&root)
            .caption(title, (FONT_FAMILY, 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(330)
            .build_cartesian_2d(lo..hi, 0.0..n as f64)
            .map_err(|x| e(x.to_string()))?;
        let labels: Vec<String> = bars.iter().map(|b| b.0.clone()).collect();
        chart
            .configure_mesh()
            .disable_y_mesh()
            .y_labels(n * 2 + 1)
            .y_label_formatter(&|y| {
                let k = (n as f64 - y - 0.5).round();
                if (y.fract() - 0.5).abs() < 1e-6 && k >= 0.0 && (k as usize) < n {
                    labels[k as usize].chars().take(44).collect()
                } else {
                    String::new()
                }
            })
            .x_desc("share of the configured squared error removed (%)")
            .label_style((FONT_FAMILY, 14))
            .draw()
            .map_err(|x| e(x.to_string()))?;
        chart
            .draw_series(bars.iter().enumerate().map(|(k, (_, v))| {
                let top = n as f64 - k as f64 - 0.15;
                let bottom = n as f64 - k as f64 - 0.85;
                let colour = if *v >= 0.0 {
                    RGBColor(0, 114, 178)
                } else {
                    RGBColor(213, 94, 0)
                };
                Rectangle::new([(0.0, bottom), (*v, top)], colour.filled())
            }))
            .map_err(|x| e(x.to_string()))?;
        chart
            .draw_series(bars.iter().enumerate().map(|(k, (_, v))| {
                Text::new(
                    format!("{v:.1} %"),
                    (v.max(0.0) + 0.5, n as f64 - k as f64 - 0.35),
                    (FONT_FAMILY, 13),
                )
            }))
            .map_err(|x| e(x.to_string()))?;
        root.present().map_err(|x| e(x.to_string()))?;
    }
    let img = image::RgbImage::from_raw(w, h, buf)
        .ok_or_else(|| format!("{}: internal: buffer size", path.display()))?;
    crate::report::atomic::write_atomically(path, |tmp| {
        img.save_with_format(tmp, image::ImageFormat::Png)
            .map_err(|x| format!("out: {}: {x}", path.display()))
    })
}

/// The rows as a terminal table.
pub fn table(rows: &[AttributionRow]) -> String {
    let body: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            let f = |v: f64| {
                if v.is_finite() {
                    format!("{v:.3}")
                } else {
                    "-".into()
                }
            };
            vec![
                r.source.clone(),
                f(r.mean_levels),
                f(r.rms_levels),
                f(r.max_levels),
                format!("{:.1}", r.share * 100.0),
                if r.kind == "pair" {
                    format!("{:.1}", r.interaction_share * 100.0)
                } else {
                    String::new()
                },
                r.bbox.clone(),
                if r.band == "none" {
                    "none".into()
                } else {
                    format!("{} ({:.0} %)", r.band, r.band_share * 100.0)
                },
            ]
        })
        .collect();
    crate::report::table::text_table(
        &[
            "source",
            "mean_levels",
            "rms_levels",
            "max_levels",
            "share_%",
            "interact_%",
            "bbox",
            "band",
        ],
        &body,
    )
}
