//! Report helpers: PNG plots and grids, CSV, error metrics, progress bars.

use glare_pipeline::report::csv_out::{read_csv_column, write_csv};
use glare_pipeline::report::metrics::{
    error_stats, error_stats_at, error_stats_masked, lit_mask, representative_pixels, rms_percent,
    ErrorStats,
};
use glare_pipeline::report::plot::{image_grid, line_plot, Axis, PlotSpec, Series};
use glare_pipeline::report::progress::{map_with_progress, should_hide, try_map_with_progress};
use std::path::PathBuf;

fn out_dir() -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("report_tests");
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// First two colours of the plot palette (series 0 and 1).
const C0: [u8; 3] = [0, 114, 178];
const C1: [u8; 3] = [213, 94, 0];

/// Error falls as 60/n then rises as `slope`·n; time grows linearly.
fn fig4_like(slope: f64) -> Vec<Series> {
    let ns: Vec<f64> = (1..=20).map(|k| 10.0 * k as f64).collect();
    vec![
        Series {
            label: "mean |Δ| (levels)".into(),
            points: ns.iter().map(|&n| (n, 60.0 / n + slope * n)).collect(),
            axis: Axis::Left,
        },
        Series {
            label: "time (s)".into(),
            points: ns.iter().map(|&n| (n, 0.0017 * n)).collect(),
            axis: Axis::Right,
        },
    ]
}

fn fig4_spec() -> PlotSpec {
    PlotSpec {
        title: "Error and time against sample planes".into(),
        x_label: "sample planes n".into(),
        y_left_label: "mean |Δ| (8-bit levels)".into(),
        y_right_label: Some("time (s)".into()),
        log_x: false,
        log_y: false,
        width: 800,
        height: 600,
    }
}

fn count_colour(img: &image::RgbImage, c: [u8; 3], x0: u32, x1: u32, y0: u32, y1: u32) -> usize {
    let mut n = 0;
    for y in y0..y1 {
        for x in x0..x1 {
            if img.get_pixel(x, y).0 == c {
                n += 1;
            }
        }
    }
    n
}

#[test]
fn plot_is_a_png_of_the_requested_size_and_shows_the_data() {
    let dir = out_dir();
    let (pa, pb) = (dir.join("fig4_a.png"), dir.join("fig4_b.png"));
    line_plot(&pa, &fig4_spec(), &fig4_like(0.02)).unwrap();
    line_plot(&pb, &fig4_spec(), &fig4_like(0.05)).unwrap();
    let a = image::open(&pa).unwrap().to_rgb8();
    let b = image::open(&pb).unwrap().to_rgb8();
    assert_eq!(a.dimensions(), (800, 600));
    // Plot area interior (well inside the label areas): both series are drawn there in
    // their own colours.
    let (x0, x1, y0, y1) = (150, 650, 100, 500);
    assert!(
        count_colour(&a, C0, x0, x1, y0, y1) > 300,
        "left series drawn"
    );
    assert!(
        count_colour(&a, C1, x0, x1, y0, y1) > 300,
        "right series drawn"
    );
    // Text (black glyphs) in the left and right label areas and under the x axis.
    let dark = |img: &image::RgbImage, x0, x1, y0, y1| {
        let mut n = 0;
        for y in y0..y1 {
            for x in x0..x1 {
                let p: &image::Rgb<u8> = img.get_pixel(x, y);
                if p.0.iter().all(|&v| v < 80) {
                    n += 1;
                }
            }
        }
        n
    };
    assert!(
        dark(&a, 0, 90, 100, 500) > 200,
        "left tick labels and description"
    );
    assert!(
        dark(&a, 710, 800, 100, 500) > 200,
        "right tick labels and description"
    );
    assert!(
        dark(&a, 150, 650, 540, 600) > 200,
        "x tick labels and description"
    );
    assert!(dark(&a, 100, 700, 0, 40) > 200, "title");
    // Different data → different pixels inside the plot area.
    let mut changed = 0;
    for y in y0..y1 {
        for x in x0..x1 {
            if a.get_pixel(x, y) != b.get_pixel(x, y) {
                changed += 1;
            }
        }
    }
    assert!(changed > 1000, "only {changed} pixels changed");
    // Same inputs → same bytes.
    let pc = dir.join("fig4_a_again.png");
    line_plot(&pc, &fig4_spec(), &fig4_like(0.02)).unwrap();
    assert_eq!(std::fs::read(&pa).unwrap(), std::fs::read(&pc).unwrap());
}

/// Mean row of the pixels of colour `c` in each column, skipping columns where they do
/// not form one compact run (markers, the legend sample) and the end markers; then the
/// number of columns used and the largest residual of a least-squares line through
/// those (column, row) pairs.
fn straightness(img: &image::RgbImage, c: [u8; 3]) -> (usize, f64) {
    let mut pts = Vec::new();
    for x in 0..img.width() {
        let rows: Vec<u32> = (0..img.height())
            .filter(|&y| img.get_pixel(x, y).0 == c)
            .collect();
        if rows.is_empty() {
            continue;
        }
        let (lo, hi) = (rows[0], rows[rows.len() - 1]);
        if hi - lo <= 4 {
            pts.push((x as f64, (lo + hi) as f64 / 2.0));
        }
    }
    // The outer edges of the end markers are centred on the end points, not on the line.
    let (first, last) = (pts[0].0, pts[pts.len() - 1].0);
    pts.retain(|p| p.0 > first + 8.0 && p.0 < last - 8.0);
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let k = sxy / sxx;
    let worst = pts
        .iter()
        .map(|p| (p.1 - (my + k * (p.0 - mx))).abs())
        .fold(0.0, f64::max);
    (pts.len(), worst)
}

#[test]
fn log_log_axes_straighten_a_power_law_and_reject_non_positive_data() {
    let dir = out_dir();
    let spectrum = vec![Series {
        label: "P(f) = f^-2".into(),
        points: (0..=8)
            .map(|k| {
                let f = 10f64.powf(k as f64 / 2.0);
                (f, 1.0 / (f * f))
            })
            .collect(),
        axis: Axis::Left,
    }];
    let mut spec = PlotSpec::new("Power spectrum", "frequency f", "power P(f)");
    spec.log_x = true;
    spec.log_y = true;
    let p = dir.join("loglog.png");
    line_plot(&p, &spec, &spectrum).unwrap();
    let img = image::open(&p).unwrap().to_rgb8();
    let (cols, worst) = straightness(&img, C0);
    assert!(cols > 300, "line found in {cols} columns");
    assert!(worst <= 2.5, "log-log power law bends by {worst} px");
    // A line that is straight on linear axes, y = 1 + x, bends on log-log axes.
    let affine = vec![Series {
        label: "1 + x".into(),
        points: (0..=8)
            .map(|k| {
                let x = 10f64.powf(k as f64 / 2.0 - 2.0);
                (x, 1.0 + x)
            })
            .collect(),
        axis: Axis::Left,
    }];
    let q = dir.join("loglog_affine.png");
    line_plot(&q, &spec, &affine).unwrap();
    let (_, worst_log) = straightness(&image::open(&q).unwrap().to_rgb8(), C0);
    assert!(
        worst_log > 30.0,
        "log-log axes bend 1 + x only {worst_log} px"
    );
    spec.log_x = false;
    spec.log_y = false;
    let q = dir.join("linlin_affine.png");
    line_plot(&q, &spec, &affine).unwrap();
    let (cols, worst_lin) = straightness(&image::open(&q).unwrap().to_rgb8(), C0);
    assert!(
        cols > 300 && worst_lin <= 2.5,
        "{cols} columns, bends {worst_lin} px"
    );

    // Non-positive values are rejected on a log axis, with the path and the point named.
    spec.log_x = true;
    spec.log_y = true;
    let mut bad = spectrum.clone();
    bad[0].points[3].1 = 0.0;
    let bad_path = dir.join("bad_log.png");
    let e = line_plot(&bad_path, &spec, &bad).unwrap_err();
    assert!(
        e.contains("bad_log.png") && e.contains("points[3]") && e.contains("log y"),
        "{e}"
    );
    let mut bad = spectrum.clone();
    bad[0].points[5].0 = -1.0;
    let e = line_plot(&bad_path, &spec, &bad).unwrap_err();
    assert!(e.contains("points[5]") && e.contains("log x"), "{e}");
    // Non-positive is fine on linear axes.
    spec.log_x = false;
    spec.log_y = false;
    line_plot(&dir.join("lin_with_zero.png"), &spec, &bad).unwrap();
    assert!(!bad_path.exists());
}

#[test]
fn plot_errors_name_the_path_and_never_panic() {
    let dir = out_dir();
    let spec = fig4_spec();
    let p = dir.join("err.png");
    let e = line_plot(&p, &spec, &[]).unwrap_err();
    assert!(e.contains("err.png") && e.contains("no series"), "{e}");
    let empty = vec![Series {
        label: "none".into(),
        points: vec![],
        axis: Axis::Left,
    }];
    let e = line_plot(&p, &spec, &empty).unwrap_err();
    assert!(e.contains("series[0]") && e.contains("no points"), "{e}");
    for bad in [f64::NAN, f64::INFINITY] {
        let mut s = fig4_like(0.02);
        s[1].points[7].1 = bad;
        let e = line_plot(&p, &spec, &s).unwrap_err();
        assert!(
            e.contains("series[1]") && e.contains("points[7]") && e.contains("finite"),
            "{e}"
        );
    }
    let mut tiny = spec.clone();
    tiny.width = 10;
    let e = line_plot(&p, &tiny, &fig4_like(0.02)).unwrap_err();
    assert!(e.contains("spec.width"), "{e}");
    tiny.width = 160;
    tiny.height = 160;
    let small = dir.join("smallest.png");
    line_plot(&small, &tiny, &fig4_like(0.02)).unwrap();
    assert_eq!(image::image_dimensions(&small).unwrap(), (160, 160));
    // A path below a regular file cannot be created.
    let blocker = dir.join("blocker_file");
    std::fs::write(&blocker, b"x").unwrap();
    let unwritable = blocker.join("plot.png");
    let e = line_plot(&unwritable, &spec, &fig4_like(0.02)).unwrap_err();
    assert!(e.contains("blocker_file/plot.png"), "{e}");
    // Degenerate data (one point, all equal) still plots.
    let one = vec![Series {
        label: "one point".into(),
        points: vec![(3.0, 3.0)],
        axis: Axis::Right,
    }];
    line_plot(&dir.join("one_point.png"), &spec, &one).unwrap();
    // Huge magnitudes: up to 1e300 on linear axes (the padding cannot overflow) …
    let mut huge = vec![Series {
        label: "huge".into(),
        points: vec![(-1e300, -1e300), (1e300, 1e300)],
        axis: Axis::Left,
    }];
    line_plot(&dir.join("huge.png"), &spec, &huge).unwrap();
    // … beyond, an error (plotters' tick search would not terminate).
    huge[0].points[1].1 = 1.7e308;
    let e = line_plot(&p, &spec, &huge).unwrap_err();
    assert!(e.contains("points[1]") && e.contains("too large"), "{e}");
    // Log axes: at most 250 decades.
    let mut log = spec.clone();
    log.log_y = true;
    let wide = vec![Series {
        label: "wide".into(),
        points: vec![(0.0, 1e-200), (1.0, 1e100)],
        axis: Axis::Left,
    }];
    let e = line_plot(&p, &log, &wide).unwrap_err();
    assert!(e.contains("decades") && e.contains("log y"), "{e}");
    let tiny_values = vec![Series {
        label: "subnormal".into(),
        points: vec![(0.0, 5e-324), (1.0, 1e-300)],
        axis: Axis::Left,
    }];
    line_plot(&dir.join("subnormal_log.png"), &log, &tiny_values).unwrap();
}

#[test]
fn image_grid_lays_out_captioned_panels() {
    let dir = out_dir();
    let solid = |c: [u8; 4]| image::RgbaImage::from_pixel(96, 64, image::Rgba(c));
    let (r, g, b) = (
        solid([255, 0, 0, 255]),
        solid([0, 255, 0, 255]),
        solid([0, 0, 255, 255]),
    );
    let p = dir.join("triptych.png");
    image_grid(&p, &[("original", &r), ("+ bloom", &g), ("+ halo", &b)], 3).unwrap();
    let img = image::open(&p).unwrap().to_rgb8();
    let count = |c: [u8; 3]| img.pixels().filter(|px| px.0 == c).count();
    // Each panel is copied whole (captions are black text on white, no overlap).
    assert_eq!(count([255, 0, 0]), 96 * 64);
    assert_eq!(count([0, 255, 0]), 96 * 64);
    assert_eq!(count([0, 0, 255]), 96 * 64);
    // Side by side: one row, three columns, wider than high.
    assert!(
        img.width() >= 3 * 96 && img.height() < 2 * 64 + 64,
        "{:?}",
        img.dimensions()
    );
    // Captions: dark pixels below the panels.
    let dark = img
        .enumerate_pixels()
        .filter(|(_, y, px)| *y > 64 && px.0.iter().all(|&v| v < 100))
        .count();
    assert!(dark > 100, "captions drawn ({dark} dark pixels)");
    // Two columns → two rows.
    let p2 = dir.join("grid_2col.png");
    image_grid(&p2, &[("a", &r), ("b", &g), ("c", &b)], 2).unwrap();
    let img2 = image::open(&p2).unwrap().to_rgb8();
    assert!(img2.height() > 2 * 64 && img2.width() < 3 * 96);
    // Transparency composites over white.
    let clear = solid([0, 0, 0, 0]);
    let p3 = dir.join("grid_clear.png");
    image_grid(&p3, &[("", &clear)], 1).unwrap();
    let img3 = image::open(&p3).unwrap().to_rgb8();
    assert!(img3.pixels().all(|px| px.0 == [255, 255, 255]));
    // Errors.
    let e = image_grid(&p, &[], 3).unwrap_err();
    assert!(e.contains("triptych.png") && e.contains("no images"), "{e}");
    let e = image_grid(&p, &[("x", &r)], 0).unwrap_err();
    assert!(e.contains("columns"), "{e}");
    let empty = image::RgbaImage::new(0, 0);
    let e = image_grid(&p, &[("x", &r), ("nothing", &empty)], 2).unwrap_err();
    assert!(e.contains("images[1]"), "{e}");
}

#[derive(serde::Serialize)]
struct Row {
    n: u32,
    error: f64,
    time_s: f64,
}

#[test]
fn csv_round_trips_floats_exactly() {
    let dir = out_dir().join("nested/csv");
    let _ = std::fs::remove_dir_all(&dir);
    let p = dir.join("sweep.csv");
    let values = [
        0.1 + 0.2,
        1.0 / 3.0,
        std::f64::consts::PI,
        1e-300,
        -2.5e-320, // subnormal
        f64::MAX,
        0.0,
        -0.0,
        123456789.0123456,
    ];
    let rows: Vec<Row> = values
        .iter()
        .enumerate()
        .map(|(i, &v)| Row {
            n: 10 * i as u32,
            error: v,
            time_s: v * 0.5,
        })
        .collect();
    write_csv(&p, &rows).unwrap();
    let text = std::fs::read_to_string(&p).unwrap();
    assert_eq!(text.lines().next(), Some("n,error,time_s"));
    let back = read_csv_column(&p, "error").unwrap();
    assert_eq!(back.len(), values.len());
    for (a, b) in values.iter().zip(&back) {
        assert_eq!(a.to_bits(), b.to_bits(), "{a} read back as {b}");
    }
    let ns = read_csv_column(&p, "n").unwrap();
    assert_eq!(
        ns,
        (0..values.len())
            .map(|i| 10.0 * i as f64)
            .collect::<Vec<_>>()
    );
    let e = read_csv_column(&p, "missing").unwrap_err();
    assert!(e.contains("sweep.csv") && e.contains("\"missing\""), "{e}");
    let e = read_csv_column(&dir.join("absent.csv"), "n").unwrap_err();
    assert!(e.contains("absent.csv"), "{e}");
    // Zero rows: an empty file.
    let p0 = dir.join("empty.csv");
    write_csv::<Row>(&p0, &[]).unwrap();
    assert_eq!(std::fs::read_to_string(&p0).unwrap(), "");
}

#[test]
fn error_stats_on_hand_computed_arrays() {
    let a = [[0.0, 0.0, 0.0], [10.0, 20.0, 30.0]];
    let b = [[1.0, 2.0, 3.0], [10.0, 16.0, 30.0]];
    // |Δ| = 1, 2, 3, 0, 4, 0: sum 10, squares 30, max 4, n 6.
    let s = error_stats(&a, &b).unwrap();
    assert_eq!(
        s,
        ErrorStats {
            mean_abs: 10.0 / 6.0,
            rms: 5f64.sqrt(),
            max: 4.0,
            n: 6
        }
    );
    // Symmetric.
    assert_eq!(error_stats(&b, &a).unwrap(), s);
    // Only the second pixel: |Δ| = 0, 4, 0.
    let second = ErrorStats {
        mean_abs: 4.0 / 3.0,
        rms: (16.0f64 / 3.0).sqrt(),
        max: 4.0,
        n: 3,
    };
    assert_eq!(error_stats_masked(&a, &b, &[false, true]).unwrap(), second);
    assert_eq!(error_stats_at(&a, &b, 2, &[(1, 0)]).unwrap(), second);
    assert_eq!(error_stats_at(&a, &b, 1, &[(0, 1)]).unwrap(), second);
    assert_eq!(
        error_stats_masked(&a, &b, &[false, false]).unwrap(),
        ErrorStats::EMPTY
    );
    assert_eq!(error_stats(&[], &[]).unwrap(), ErrorStats::EMPTY);
    // rms_percent: 255 levels = 100 %.
    let r = ErrorStats {
        mean_abs: 0.0,
        rms: 25.5,
        max: 0.0,
        n: 1,
    };
    assert!((rms_percent(&r) - 10.0).abs() < 1e-12);
    // Huge values: finite, scaled sums; overflowing differences: ∞, never NaN.
    let s = error_stats(&[[1e200, 0.0, 0.0]], &[[-1e200, 0.0, 0.0]]).unwrap();
    assert_eq!(s.max, 2e200);
    assert!((s.mean_abs / (2e200 / 3.0) - 1.0).abs() < 1e-12);
    assert!((s.rms / (2e200 / 3f64.sqrt()) - 1.0).abs() < 1e-12);
    let s = error_stats(&[[1.7e308, 0.0, 0.0]], &[[-1.7e308, 0.0, 0.0]]).unwrap();
    assert!(s.max.is_infinite() && s.rms.is_infinite() && s.mean_abs.is_infinite());
}

#[test]
fn metric_input_errors_name_the_argument() {
    let a = [[0.0; 3]; 4];
    let b = [[0.0; 3]; 3];
    assert_eq!(error_stats(&a, &b).unwrap_err().field(), "b");
    assert_eq!(
        error_stats_masked(&a, &b, &[true; 4]).unwrap_err().field(),
        "b"
    );
    assert_eq!(
        error_stats_masked(&a, &a, &[true; 3]).unwrap_err().field(),
        "mask"
    );
    assert_eq!(error_stats_at(&a, &b, 2, &[]).unwrap_err().field(), "b");
    assert_eq!(error_stats_at(&a, &a, 0, &[]).unwrap_err().field(), "width");
    assert_eq!(error_stats_at(&a, &a, 3, &[]).unwrap_err().field(), "width");
    assert_eq!(
        error_stats_at(&a, &a, 2, &[(0, 0), (2, 0)])
            .unwrap_err()
            .field(),
        "pixels[1]"
    );
    assert_eq!(
        error_stats_at(&a, &a, 2, &[(1, 2)]).unwrap_err().field(),
        "pixels[0]"
    );
    let mut c = a;
    c[1][2] = f64::NAN;
    assert_eq!(error_stats(&a, &c).unwrap_err().field(), "b[1][2]");
    assert_eq!(error_stats(&c, &a).unwrap_err().field(), "a[1][2]");
    // A NaN outside the mask / the listed pixels is not looked at.
    assert!(error_stats_masked(&a, &c, &[true, false, true, true]).is_ok());
    assert_eq!(
        representative_pixels(&a, 3, 2, 10, 0).unwrap_err().field(),
        "reference"
    );
}

/// 64 × 48: a disc of radius 15 at (40, 22) at 100 levels, a faint band (0.5 levels,
/// below the 1-level floor) and a dim patch at 1.5 levels (below 2 % of the peak).
fn disc_reference() -> (Vec<[f64; 3]>, impl Fn(u32, u32) -> bool) {
    let (w, h) = (64u32, 48u32);
    let inside = |x: u32, y: u32| {
        let (dx, dy) = (x as f64 - 40.0, y as f64 - 22.0);
        dx * dx + dy * dy <= 15.0 * 15.0
    };
    let mut img = vec![[0.0; 3]; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            img[i] = if inside(x, y) {
                [100.0, 80.0, 60.0]
            } else if x < 10 {
                [0.5, 0.5, 0.5]
            } else if y > 40 && x < 20 {
                [1.5, 0.0, 0.0]
            } else {
                [0.0; 3]
            };
        }
    }
    (img, inside)
}

#[test]
fn representative_pixels_are_deterministic_spread_and_lit() {
    let (img, inside) = disc_reference();
    let lit = lit_mask(&img).unwrap();
    let lit_count = lit.iter().filter(|&&l| l).count();
    let disc_count = (0..48u32)
        .flat_map(|y| (0..64u32).map(move |x| (x, y)))
        .filter(|&(x, y)| inside(x, y))
        .count();
    assert_eq!(lit_count, disc_count, "lit region is exactly the disc");

    let p = representative_pixels(&img, 64, 48, 10, 7).unwrap();
    assert_eq!(p.len(), 10);
    assert_eq!(p, representative_pixels(&img, 64, 48, 10, 7).unwrap());
    assert!(p.iter().all(|&(x, y)| inside(x, y)), "{p:?}");
    let mut uniq = p.clone();
    uniq.sort();
    uniq.dedup();
    assert_eq!(uniq.len(), 10, "distinct");
    // Raster order, one per stratum: spread over the disc's rows 7 ..= 37.
    assert!(p.windows(2).all(|w| (w[0].1, w[0].0) < (w[1].1, w[1].0)));
    assert!(p[0].1 <= 12 && p[9].1 >= 32, "{p:?}");
    // Other seeds choose other pixels (each stratum has ~70 candidates).
    let others: Vec<_> = (0..4)
        .map(|s| representative_pixels(&img, 64, 48, 10, 100 + s).unwrap())
        .collect();
    assert!(others.iter().any(|o| *o != p));
    // The metric at those pixels: a uniform 2-level error gives mean 2, n 30.
    let shifted: Vec<[f64; 3]> = img.iter().map(|c| c.map(|v| v + 2.0)).collect();
    let s = error_stats_at(&img, &shifted, 64, &p).unwrap();
    assert_eq!((s.mean_abs, s.rms, s.max, s.n), (2.0, 2.0, 2.0, 30));

    // Fewer lit pixels than asked for: all of them.
    let mut few = vec![[0.0; 3]; 64 * 48];
    few[5] = [9.0, 0.0, 0.0];
    few[64 * 47 + 63] = [0.0, 0.0, 9.0];
    assert_eq!(
        representative_pixels(&few, 64, 48, 10, 1).unwrap(),
        vec![(5, 0), (63, 47)]
    );
    // Nothing lit: an error, not an empty list.
    let dark = vec![[0.9; 3]; 64 * 48];
    assert_eq!(
        representative_pixels(&dark, 64, 48, 10, 1)
            .unwrap_err()
            .field(),
        "reference"
    );
    assert!(representative_pixels(&img, 64, 48, 0, 1)
        .unwrap()
        .is_empty());
}

#[test]
fn progress_is_hidden_in_ci_and_pipes_and_keeps_order() {
    assert!(should_hide(Some("true"), true));
    assert!(should_hide(Some("1"), true));
    assert!(should_hide(None, false));
    assert!(!should_hide(None, true));
    assert!(!should_hide(Some("false"), true));
    assert!(!should_hide(Some("0"), true));
    assert!(!should_hide(Some(""), true));
    let items = [3, 1, 4, 1, 5];
    assert_eq!(
        map_with_progress(&items, "square", |&x| x * x),
        vec![9, 1, 16, 1, 25]
    );
    let mut calls = 0;
    let r: Result<Vec<i32>, String> = try_map_with_progress(&items, "check", |&x| {
        calls += 1;
        if x == 4 {
            Err(format!("item {x}"))
        } else {
            Ok(x)
        }
    });
    assert_eq!(r, Err("item 4".to_string()));
    assert_eq!(calls, 3, "stops at the first error");
}
