//! PNG line plots and captioned image grids, drawn with plotters' bitmap backend.
//!
//! Text is drawn with `ab_glyph` from DejaVu Sans, embedded from
//! `src/report/fonts/DejaVuSans.ttf` (licence: `src/report/fonts/LICENSE-DejaVu.txt`,
//! Bitstream Vera + Arev, permissive), so no system font or fontconfig is needed and the
//! same inputs give the same bytes on every machine.
//!
//! Rules (all failures are `Err(String)` naming the output path, never a panic):
//! - no series, or a series with no points → error;
//! - a non-finite coordinate (NaN, ±∞) → error naming the series and the point index
//!   (points are never skipped silently: a NaN in a sweep is a bug upstream);
//! - on a log axis, a coordinate ≤ 0 → error naming the series and the point; data
//!   spanning more than [`MAX_LOG_DECADES`] decades on one log axis → error;
//! - on a linear axis, |coordinate| > [`MAX_ABS_LINEAR`] → error naming the point
//!   (plotters' tick search does not terminate on ranges that overflow f64);
//! - `width`/`height` outside `MIN_SIZE ..= MAX_SIZE` → error naming the field;
//! - the parent directory is created; an unwritable path → error naming it.
//!
//! `log_y` applies to both y axes (left and right). A right axis is drawn only when a
//! series uses [`Axis::Right`]; its series get " (right axis)" appended to their legend
//! label so a reader can tell the two scales apart. Each series has its own colour and
//! marker shape (circle, triangle, square, cross, cycling). The legend goes into the
//! corner of the plot area that covers the fewest data (deterministic choice).
//!
//! Known limitation: plotters 0.3.7's ab_glyph path places each glyph at its advance
//! without the glyph's left side bearing, so letter spacing is uneven by about a pixel
//! ("sampl e"); text stays legible at the default sizes (16 px ticks at 800 × 600).

use image::RgbaImage;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;
use std::sync::OnceLock;

/// DejaVu Sans 2.37 (Debian fonts-dejavu-core), embedded.
static FONT_BYTES: &[u8] = include_bytes!("fonts/DejaVuSans.ttf");

/// The family name the embedded font is registered under (plotters' default family).
pub const FONT_FAMILY: &str = "sans-serif";

/// Smallest accepted plot width and height, in pixels (drawn without error; text is
/// legible from about 480 × 360, and 800 × 600 is the intended size).
pub const MIN_SIZE: u32 = 160;
/// Largest accepted plot width and height, in pixels.
pub const MAX_SIZE: u32 = 16_384;
/// Largest |value| on a linear axis (plotters' tick search overflows beyond ~1e308).
pub const MAX_ABS_LINEAR: f64 = 1e300;
/// Most decades a log axis may span (plotters' tick search overflows beyond ~300).
pub const MAX_LOG_DECADES: f64 = 250.0;
/// Largest accepted image grid, in pixels (64 Mpx, 192 MiB as RGB).
pub const MAX_GRID_PIXELS: u64 = 1 << 26;

/// Which y axis a series is drawn against.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    Left,
    Right,
}

/// One polyline with markers.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub label: String,
    /// (x, y) in data units, drawn in the given order.
    pub points: Vec<(f64, f64)>,
    pub axis: Axis,
}

/// What to draw around the series.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotSpec {
    pub title: String,
    pub x_label: String,
    pub y_left_label: String,
    /// Description of the right axis (used only when a series is on [`Axis::Right`]).
    pub y_right_label: Option<String>,
    pub log_x: bool,
    /// Log scale on both y axes.
    pub log_y: bool,
    pub width: u32,
    pub height: u32,
}

impl PlotSpec {
    /// A linear 800 × 600 plot.
    pub fn new(title: &str, x_label: &str, y_left_label: &str) -> Self {
        PlotSpec {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_left_label: y_left_label.to_string(),
            y_right_label: None,
            log_x: false,
            log_y: false,
            width: 800,
            height: 600,
        }
    }
}

/// Register the embedded font with plotters (once per process).
pub fn ensure_font() -> Result<(), String> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FONT_FAMILY, FontStyle::Normal, FONT_BYTES)
                .map_err(|_| "embedded font DejaVuSans.ttf could not be parsed".to_string())
        })
        .clone()
}

/// Colour-blind-friendly palette (Okabe–Ito, without yellow which is too pale on white).
const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),   // blue
    RGBColor(213, 94, 0),    // vermilion
    RGBColor(0, 158, 115),   // bluish green
    RGBColor(204, 121, 167), // reddish purple
    RGBColor(86, 180, 233),  // sky blue
    RGBColor(230, 159, 0),   // orange
    RGBColor(0, 0, 0),       // black
];

/// Tick label: at most 4 significant digits, no trailing zeros, exponent form outside
/// [1e-3, 1e5).
pub fn format_tick(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 {
            "0".to_string()
        } else {
            format!("{v}")
        };
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{v:.2e}");
        // "1.50e6" → "1.5e6", "1.00e-5" → "1e-5"
        let (mant, exp) = s.split_once('e').unwrap_or((&s, "0"));
        let mant = trim_zeros(mant);
        return format!("{mant}e{exp}");
    }
    let decimals = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
    trim_zeros(&format!("{v:.decimals$}"))
}

fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

/// A number for an error message: plain when short, exponent form when huge or tiny.
fn show(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

fn err_at(path: &Path, what: impl std::fmt::Display) -> String {
    format!("{}: {what}", path.display())
}

/// Data range of one axis, padded for drawing.
#[derive(Clone, Copy, Debug)]
struct AxisRange {
    lo: f64,
    hi: f64,
    log: bool,
}

impl AxisRange {
    fn from_values(values: impl Iterator<Item = f64>, log: bool) -> Option<Self> {
        let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in values {
            min = min.min(v);
            max = max.max(v);
        }
        if min > max {
            return None;
        }
        let (lo, hi) = if log {
            if min == max {
                (min / 2.0, max * 2.0)
            } else {
                // 5 % of the decades on each side.
                let pad = (max / min).powf(0.05);
                (min / pad, max * pad)
            }
        } else if min == max {
            let d = (min.abs() * 0.1).max(1.0);
            (min - d, max + d)
        } else {
            let pad = max * 0.05 - min * 0.05;
            (min - pad, max + pad)
        };
        // Padding may leave f64 at the extremes of the range: fall back to the data.
        let lo = if lo.is_finite() && lo > 0.0 || (!log && lo.is_finite()) {
            lo
        } else {
            min
        };
        let hi = if hi.is_finite() { hi } else { max };
        Some(AxisRange { lo, hi, log })
    }

    /// Position of `v` in [0, 1] along the axis.
    fn unit(&self, v: f64) -> f64 {
        if self.log {
            (v.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }
}

fn check_series(path: &Path, spec: &PlotSpec, series: &[Series]) -> Result<(), String> {
    if series.is_empty() {
        return Err(err_at(path, "series: nothing to plot (no series)"));
    }
    for (field, v) in [("spec.width", spec.width), ("spec.height", spec.height)] {
        if !(MIN_SIZE..=MAX_SIZE).contains(&v) {
            return Err(err_at(
                path,
                format!("{field}: {v} is out of range (allowed {MIN_SIZE} ..= {MAX_SIZE})"),
            ));
        }
    }
    for (si, s) in series.iter().enumerate() {
        if s.points.is_empty() {
            return Err(err_at(
                path,
                format!("series[{si}] \"{}\": no points", s.label),
            ));
        }
        for (pi, &(x, y)) in s.points.iter().enumerate() {
            let at = || {
                format!(
                    "series[{si}] \"{}\".points[{pi}] = ({}, {})",
                    s.label,
                    show(x),
                    show(y)
                )
            };
            if !x.is_finite() || !y.is_finite() {
                return Err(err_at(path, format!("{}: not a finite number", at())));
            }
            if spec.log_x && x <= 0.0 {
                return Err(err_at(
                    path,
                    format!("{}: x must be > 0 on a log x axis", at()),
                ));
            }
            if spec.log_y && y <= 0.0 {
                return Err(err_at(
                    path,
                    format!("{}: y must be > 0 on a log y axis", at()),
                ));
            }
            for (v, log, name) in [(x, spec.log_x, "x"), (y, spec.log_y, "y")] {
                if !log && v.abs() > MAX_ABS_LINEAR {
                    return Err(err_at(
                        path,
                        format!(
                            "{}: |{name}| exceeds {MAX_ABS_LINEAR:e}, too large for a linear axis",
                            at()
                        ),
                    ));
                }
            }
        }
    }
    // Log axes: the decades spanned by each drawn axis (x over all series; y per side).
    let span = |vals: &mut dyn Iterator<Item = f64>| {
        let (lo, hi) = vals.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v.log10()), hi.max(v.log10()))
        });
        hi - lo
    };
    for (log, name, axis) in [(spec.log_x, "x", 0), (spec.log_y, "y", 1)] {
        if !log {
            continue;
        }
        for side in [Axis::Left, Axis::Right] {
            let d = span(
                &mut series
                    .iter()
                    .filter(|s| axis == 0 || s.axis == side)
                    .flat_map(|s| {
                        s.points
                            .iter()
                            .map(move |p| if axis == 0 { p.0 } else { p.1 })
                    }),
            );
            if d > MAX_LOG_DECADES {
                return Err(err_at(
                    path,
                    format!(
                        "series: the data span {d:.0} decades on the log {name} axis \
                         (limit {MAX_LOG_DECADES})"
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Sizes in pixels, scaled with the image.
#[derive(Clone, Copy)]
struct Sizes {
    title: f64,
    desc: f64,
    tick: f64,
    legend: f64,
    line: u32,
    marker: i32,
    y_area: u32,
    x_area: u32,
    margin: u32,
}

impl Sizes {
    fn for_size(w: u32, h: u32) -> Self {
        let s = (w.min(h) as f64 / 600.0).clamp(0.5, 4.0);
        Sizes {
            title: 26.0 * s,
            desc: 20.0 * s,
            tick: 16.0 * s,
            legend: 16.0 * s,
            line: (2.0 * s).round().max(1.0) as u32,
            marker: (4.5 * s).round().max(2.0) as i32,
            y_area: (90.0 * s) as u32,
            x_area: (60.0 * s) as u32,
            margin: (14.0 * s) as u32,
        }
    }
}

/// Write a line plot of `series` as an RGB PNG of `spec.width × spec.height`.
pub fn line_plot(path: &Path, spec: &PlotSpec, series: &[Series]) -> Result<(), String> {
    points_plot(path, spec, series, &[])
}

/// [`line_plot`] where series `i` is drawn as markers only unless `joined[i]` (a
/// series past the end of `joined` is joined): scatter plots such as `optimize`'s
/// front.
pub fn points_plot(
    path: &Path,
    spec: &PlotSpec,
    series: &[Series],
    joined: &[bool],
) -> Result<(), String> {
    check_series(path, spec, series)?;
    ensure_font().map_err(|e| err_at(path, e))?;
    let xr = AxisRange::from_values(
        series.iter().flat_map(|s| s.points.iter().map(|p| p.0)),
        spec.log_x,
    );
    let yl = AxisRange::from_values(
        series
            .iter()
            .filter(|s| s.axis == Axis::Left)
            .flat_map(|s| s.points.iter().map(|p| p.1)),
        spec.log_y,
    );
    let yr = AxisRange::from_values(
        series
            .iter()
            .filter(|s| s.axis == Axis::Right)
            .flat_map(|s| s.points.iter().map(|p| p.1)),
        spec.log_y,
    );
    let xr = xr.ok_or_else(|| err_at(path, "series: no points"))?;
    // Only right-axis series: the left axis mirrors the right one.
    let yl_range = yl.or(yr).ok_or_else(|| err_at(path, "series: no points"))?;
    let (w, h) = (spec.width, spec.height);
    let mut buf = vec![255u8; w as usize * h as usize * 3];
    {
        let ctx = Ctx {
            spec,
            series,
            joined,
            xr,
            yl: yl_range,
            yr,
            m: Sizes::for_size(w, h),
        };
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        let draw = |x: AxisRange, y: AxisRange| -> Result<(), String> {
            match (x.log, y.log) {
                (false, false) => ctx.draw(&root, x.lo..x.hi, y.lo..y.hi, yr.map(|r| r.lo..r.hi)),
                (true, false) => ctx.draw(
                    &root,
                    (x.lo..x.hi).log_scale(),
                    y.lo..y.hi,
                    yr.map(|r| r.lo..r.hi),
                ),
                (false, true) => ctx.draw(
                    &root,
                    x.lo..x.hi,
                    (y.lo..y.hi).log_scale(),
                    yr.map(|r| (r.lo..r.hi).log_scale()),
                ),
                (true, true) => ctx.draw(
                    &root,
                    (x.lo..x.hi).log_scale(),
                    (y.lo..y.hi).log_scale(),
                    yr.map(|r| (r.lo..r.hi).log_scale()),
                ),
            }
        };
        draw(xr, yl_range).map_err(|e| err_at(path, e))?;
        root.present().map_err(|e| err_at(path, e))?;
    }
    save_rgb(path, w, h, buf)
}

/// The plot as PNG, atomically (`report::atomic`).
fn save_rgb(path: &Path, w: u32, h: u32, buf: Vec<u8>) -> Result<(), String> {
    let img = image::RgbImage::from_raw(w, h, buf)
        .ok_or_else(|| err_at(path, "internal: buffer size does not match the image"))?;
    crate::report::atomic::write_atomically(path, |tmp| {
        img.save_with_format(tmp, image::ImageFormat::Png)
            .map_err(|e| err_at(path, format!("cannot write PNG: {e}")))
    })
}

struct Ctx<'a> {
    spec: &'a PlotSpec,
    series: &'a [Series],
    /// Whether series i is a polyline (absent: yes).
    joined: &'a [bool],
    xr: AxisRange,
    yl: AxisRange,
    yr: Option<AxisRange>,
    m: Sizes,
}

#[derive(Clone, Copy)]
enum Marker {
    Circle,
    Triangle,
    Square,
    Cross,
}

impl Marker {
    fn of(i: usize) -> Self {
        [
            Marker::Circle,
            Marker::Triangle,
            Marker::Square,
            Marker::Cross,
        ][i % 4]
    }
}

/// A marker's outline as a polygon in pixel offsets around its centre (`size` =
/// half-width in pixels). One element type for every shape keeps the drawing code
/// monomorphic.
fn marker_polygon(shape: Marker, size: i32) -> Vec<(i32, i32)> {
    let r = size as f64;
    let pt = |a: f64, rad: f64| {
        (
            (rad * a.cos()).round() as i32,
            (rad * a.sin()).round() as i32,
        )
    };
    use std::f64::consts::PI;
    match shape {
        Marker::Circle => (0..20).map(|k| pt(2.0 * PI * k as f64 / 20.0, r)).collect(),
        // Pointing up (pixel y grows downwards).
        Marker::Triangle => (0..3)
            .map(|k| pt(-PI / 2.0 + 2.0 * PI * k as f64 / 3.0, r * 1.3))
            .collect(),
        Marker::Square => {
            let s = (r * 0.85).round() as i32;
            vec![(-s, -s), (s, -s), (s, s), (-s, s)]
        }
        // A plus sign of half-length s and half-thickness t, turned by 45°.
        Marker::Cross => {
            let (s, t) = (r * 1.15, (r * 0.3).max(0.8));
            let plus = [
                (t, s),
                (t, t),
                (s, t),
                (s, -t),
                (t, -t),
                (t, -s),
                (-t, -s),
                (-t, -t),
                (-s, -t),
                (-s, t),
                (-t, t),
                (-t, s),
            ];
            let h = std::f64::consts::FRAC_1_SQRT_2;
            plus.iter()
                .map(|&(x, y)| (((x - y) * h).round() as i32, ((x + y) * h).round() as i32))
                .collect()
        }
    }
}

impl Ctx<'_> {
    fn legend_label(&self, s: &Series) -> String {
        if s.axis == Axis::Right && self.yr.is_some() {
            format!("{} (right axis)", s.label)
        } else {
            s.label.clone()
        }
    }

    /// The corner of the plot area (in unit coordinates, y up) covering the fewest
    /// samples of the polylines. Ties prefer upper right, upper left, lower right,
    /// lower left.
    fn legend_corner(&self) -> SeriesLabelPosition {
        let n = self.series.len() as f64;
        let bw = 0.42;
        let bh = (0.075 * n + 0.04).min(0.9);
        let corners = [
            (SeriesLabelPosition::UpperRight, 1.0 - bw, 1.0 - bh),
            (SeriesLabelPosition::UpperLeft, 0.0, 1.0 - bh),
            (SeriesLabelPosition::LowerRight, 1.0 - bw, 0.0),
            (SeriesLabelPosition::LowerLeft, 0.0, 0.0),
        ];
        let mut counts = [0usize; 4];
        for s in self.series {
            let yax = match (s.axis, self.yr) {
                (Axis::Right, Some(r)) => r,
                _ => self.yl,
            };
            let to_unit = |p: (f64, f64)| (self.xr.unit(p.0), yax.unit(p.1));
            let mut samples: Vec<(f64, f64)> = s.points.iter().map(|&p| to_unit(p)).collect();
            for w in s.points.windows(2) {
                let (a, b) = (to_unit(w[0]), to_unit(w[1]));
                for k in 1..16 {
                    let t = k as f64 / 16.0;
                    samples.push((a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t));
                }
            }
            for (u, v) in samples {
                for (ci, &(_, x0, y0)) in corners.iter().enumerate() {
                    if u >= x0 && u <= x0 + bw && v >= y0 && v <= y0 + bh {
                        counts[ci] += 1;
                    }
                }
            }
        }
        let best = (0..4).min_by_key(|&i| (counts[i], i)).unwrap_or(0);
        corners[best].0.clone()
    }

    /// The chart's frame on a white `root`: the title, the margins and the label areas
    /// (with a `right` axis its label area, else a wider right margin).
    fn frame<'a, 'b, DB: DrawingBackend>(
        &self,
        root: &'a DrawingArea<DB, plotters::coord::Shift>,
        right: bool,
    ) -> Result<ChartBuilder<'a, 'b, DB>, String> {
        let m = self.m;
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(e)?;
        let mut builder = ChartBuilder::on(root);
        builder
            .caption(&self.spec.title, (FONT_FAMILY, m.title))
            .margin(m.margin)
            .x_label_area_size(m.x_area)
            .y_label_area_size(m.y_area);
        if right {
            builder.right_y_label_area_size(m.y_area);
        } else {
            builder.margin_right(m.margin * 2);
        }
        Ok(builder)
    }

    fn draw<DB, XC, YC>(
        &self,
        root: &DrawingArea<DB, plotters::coord::Shift>,
        x: XC,
        y: YC,
        y2: Option<YC>,
    ) -> Result<(), String>
    where
        DB: DrawingBackend,
        XC: AsRangedCoord<Value = f64> + Clone,
        YC: AsRangedCoord<Value = f64> + Clone,
        XC::CoordDescType: ValueFormatter<f64>,
        YC::CoordDescType: ValueFormatter<f64>,
    {
        let m = self.m;
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        let right = y2.is_some();
        let mut builder = self.frame(root, right)?;
        let chart = builder
            .build_cartesian_2d(x.clone(), y.clone())
            .map_err(e)?;
        let mut chart = chart.set_secondary_coord(x, y2.unwrap_or(y));
        let fmt = |v: &f64| format_tick(*v);
        let tick_font = (FONT_FAMILY, m.tick).into_font();
        let desc_font = (FONT_FAMILY, m.desc).into_font();
        chart
            .configure_mesh()
            .x_desc(&self.spec.x_label)
            .y_desc(&self.spec.y_left_label)
            .x_label_formatter(&fmt)
            .y_label_formatter(&fmt)
            .x_labels(8)
            .y_labels(8)
            .label_style(tick_font.clone())
            .axis_desc_style(desc_font.clone())
            .bold_line_style(RGBColor(215, 215, 215))
            .light_line_style(RGBColor(240, 240, 240))
            .axis_style(ShapeStyle::from(&BLACK).stroke_width(1))
            .draw()
            .map_err(e)?;
        if right {
            let desc = self.spec.y_right_label.clone().unwrap_or_default();
            chart
                .configure_secondary_axes()
                .y_desc(desc)
                .y_label_formatter(&fmt)
                .y_labels(8)
                .label_style(tick_font)
                .axis_desc_style(desc_font)
                .axis_style(ShapeStyle::from(&BLACK).stroke_width(1))
                .draw()
                .map_err(e)?;
        }
        for (i, s) in self.series.iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            let style = ShapeStyle::from(&color).stroke_width(m.line);
            let shape = Marker::of(i);
            let pts = s.points.clone();
            let poly = marker_polygon(shape, m.marker);
            let fill = color.filled();
            let marks = pts
                .iter()
                .map(|&p| EmptyElement::at(p) + Polygon::new(poly.clone(), fill));
            let line = self.joined.get(i).copied().unwrap_or(true);
            let anno = if s.axis == Axis::Right && right {
                if line {
                    chart
                        .draw_secondary_series(LineSeries::new(pts.clone(), style))
                        .map_err(e)?;
                }
                chart.draw_secondary_series(marks).map_err(e)?
            } else {
                if line {
                    chart
                        .draw_series(LineSeries::new(pts.clone(), style))
                        .map_err(e)?;
                }
                chart.draw_series(marks).map_err(e)?
            };
            let seg = (m.legend * 1.6) as i32;
            let legend_poly: Vec<(i32, i32)> =
                poly.iter().map(|&(dx, dy)| (dx + seg / 2, dy)).collect();
            anno.label(self.legend_label(s)).legend(move |(lx, ly)| {
                EmptyElement::at((lx, ly))
                    + PathElement::new(vec![(0, 0), (seg, 0)], style)
                    + Polygon::new(legend_poly.clone(), fill)
            });
        }
        chart
            .configure_series_labels()
            .position(self.legend_corner())
            .margin((m.margin as f64 * 0.8) as i32)
            .label_font((FONT_FAMILY, m.legend))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(120, 120, 120))
            .draw()
            .map_err(e)?;
        Ok(())
    }
}

/// Lay `images` out in a grid of `columns` columns (row by row), each panel centred in
/// its cell with its caption underneath, on a white background; write as RGB PNG.
///
/// Transparent pixels are composited over white. Captions too wide for a cell are drawn
/// smaller (down to 10 px). Errors: no images, `columns == 0`, an empty image, a grid
/// larger than [`MAX_GRID_PIXELS`], an unwritable path.
pub fn image_grid(
    path: &Path,
    images: &[(&str, &RgbaImage)],
    columns: usize,
) -> Result<(), String> {
    if images.is_empty() {
        return Err(err_at(path, "images: nothing to lay out (no images)"));
    }
    if columns == 0 {
        return Err(err_at(path, "columns: must be at least 1"));
    }
    for (i, (cap, img)) in images.iter().enumerate() {
        if img.width() == 0 || img.height() == 0 {
            return Err(err_at(
                path,
                format!(
                    "images[{i}] \"{cap}\": empty image ({}×{})",
                    img.width(),
                    img.height()
                ),
            ));
        }
    }
    ensure_font().map_err(|e| err_at(path, e))?;
    let columns = columns.min(images.len());
    let rows = images.len().div_ceil(columns);
    let cell_w = images.iter().map(|(_, i)| i.width()).max().unwrap_or(1) as u64;
    let cell_h = images.iter().map(|(_, i)| i.height()).max().unwrap_or(1) as u64;
    let caption_px = (cell_w as f64 / 16.0).clamp(14.0, 32.0);
    let gap = (caption_px * 0.6).round() as u64;
    let cap_h = (caption_px * 1.6).round() as u64;
    let w = columns as u64 * (cell_w + gap) + gap;
    let h = rows as u64 * (cell_h + cap_h + gap) + gap;
    if w > MAX_SIZE as u64 * 2 || h > MAX_SIZE as u64 * 2 || w * h > MAX_GRID_PIXELS {
        return Err(err_at(
            path,
            format!("images: the grid would be {w}×{h} pixels (limit {MAX_GRID_PIXELS} pixels)"),
        ));
    }
    let (w, h) = (w as u32, h as u32);
    let mut buf = vec![255u8; w as usize * h as usize * 3];
    let origin = |i: usize| {
        let (c, r) = ((i % columns) as u64, (i / columns) as u64);
        (gap + c * (cell_w + gap), gap + r * (cell_h + cap_h + gap))
    };
    for (i, (_, img)) in images.iter().enumerate() {
        let (ox, oy) = origin(i);
        let ox = ox + (cell_w - img.width() as u64) / 2;
        let oy = oy + (cell_h - img.height() as u64) / 2;
        for (x, y, p) in img.enumerate_pixels() {
            let a = p[3] as u32;
            let o = ((oy + y as u64) * w as u64 + ox + x as u64) as usize * 3;
            for k in 0..3 {
                // Over white, rounded: (c·a + 255·(255 − a) + 127) / 255.
                buf[o + k] = ((p[k] as u32 * a + 255 * (255 - a) + 127) / 255) as u8;
            }
        }
    }
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        for (i, (cap, _)) in images.iter().enumerate() {
            let (ox, oy) = origin(i);
            let mut size = caption_px;
            loop {
                let font = (FONT_FAMILY, size).into_font();
                let (tw, _) = root
                    .estimate_text_size(cap, &TextStyle::from(font))
                    .map_err(|e| err_at(path, e))?;
                if tw as u64 <= cell_w + gap / 2 || size <= 10.0 {
                    break;
                }
                size -= 1.0;
            }
            let style = TextStyle::from((FONT_FAMILY, size).into_font())
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Center));
            let cx = (ox + cell_w / 2) as i32;
            let cy = (oy + cell_h + cap_h / 2) as i32;
            root.draw_text(cap, &style, (cx, cy))
                .map_err(|e| err_at(path, e))?;
        }
        root.present().map_err(|e| err_at(path, e))?;
    }
    save_rgb(path, w, h, buf)
}
