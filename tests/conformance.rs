//! The hardware-capture comparison (docs/conformance.md): the machinery on a synthetic
//! capture, and every suite against its committed expected values, whose figures
//! must be the ones docs/conformance.md states.

use glare_pipeline::conformance::run::{run_suite, SuiteReport};
use glare_pipeline::conformance::store::{extract, parse, Capture};
use glare_pipeline::conformance::{suites, Case, Chip, Prediction, Rect, Region, Suite};
use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("conformance-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("results/Synthetic")).unwrap();
    d
}

/// A 16 × 8 capture: left half (10, 20, 30), right half a gradient in red.
fn synthetic_capture(dir: &std::path::Path) {
    let img = image::RgbImage::from_fn(16, 8, |x, _| {
        if x < 8 {
            image::Rgb([10, 20, 30])
        } else {
            image::Rgb([x as u8 * 10, 0, 0])
        }
    });
    img.save(dir.join("results/Synthetic/a.png")).unwrap();
}

fn synthetic_cases(_chip: Chip) -> Vec<Case> {
    let grad: Vec<[u8; 3]> = (0..2)
        .flat_map(|_| (9..13).map(|x| [x as u8 * 10, 0, 0]))
        .collect();
    vec![Case {
        image: "a.png".into(),
        regions: vec![
            Region {
                name: "flat".into(),
                feature: "flat patch".into(),
                rect: Rect::new(1, 1, 6, 6),
                predicted: Prediction::Flat([10, 20, 30]),
            },
            Region {
                name: "gradient".into(),
                feature: "gradient".into(),
                rect: Rect::new(9, 3, 4, 2),
                predicted: Prediction::PerPixel(grad),
            },
            Region {
                name: "off".into(),
                feature: "one level off".into(),
                rect: Rect::new(2, 2, 2, 1),
                predicted: Prediction::Flat([10, 21, 30]),
            },
            Region {
                name: "wrong".into(),
                feature: "wrong".into(),
                rect: Rect::new(3, 6, 1, 1),
                predicted: Prediction::Flat([12, 20, 30]),
            },
        ],
    }]
}

const SYNTHETIC: Suite = Suite {
    name: "Synthetic",
    source: "none",
    cases: synthetic_cases,
};

#[test]
fn extract_and_run_count_exact_off_by_one_and_worse() {
    let dir = tmp("synthetic");
    synthetic_capture(&dir);
    let cases = synthetic_cases(Chip::Nv2a);
    let text = extract(&SYNTHETIC, &cases, &dir).unwrap();
    let exp = parse(&text).unwrap();
    // The flat patch is one run; the committed pixels are the capture's.
    assert!(text.contains("flat 1 1 6 6 0a141e*36"), "{text}");
    let cap = Capture::load(&dir.join("results/Synthetic/a.png")).unwrap();
    for r in &exp.images["a.png"] {
        assert_eq!(r.pixels, cap.region(r.rect, &r.name).unwrap());
    }
    let diff_dir = dir.join("diff");
    let rep = run_suite(&SYNTHETIC, Chip::Nv2a, Some(&dir), Some(&diff_dir), false).unwrap();
    assert_eq!(rep.images, 1);
    assert_eq!(rep.tally.regions, 4);
    assert_eq!(rep.tally.compared, 36 + 8 + 2 + 1);
    assert_eq!(rep.tally.exact, 36 + 8);
    assert_eq!(rep.tally.off1, 2);
    assert_eq!(rep.tally.worse, 1);
    assert_eq!(rep.tally.max_levels, 2);
    // One image: the calibration half (even positions of the sorted names) holds it.
    assert_eq!(rep.calibration_half, rep.tally);
    assert_eq!(rep.validation_half.compared, 0);
    let classes: Vec<&str> = rep
        .mismatch_classes
        .iter()
        .map(|f| f.feature.as_str())
        .collect();
    assert_eq!(classes, ["wrong", "one level off"]);
    let w = rep.worst.as_ref().unwrap();
    assert_eq!((w.region.as_str(), w.max_levels), ("wrong", 2));
    // One difference image (hardware | model | difference), three captures wide.
    assert_eq!(rep.difference_images.len(), 1);
    let d = image::open(&rep.difference_images[0]).unwrap();
    assert_eq!((d.width(), d.height()), (48, 8));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_capture_smaller_than_a_region_is_refused_naming_it() {
    let dir = tmp("small");
    synthetic_capture(&dir);
    let bad = |_chip: Chip| {
        vec![Case {
            image: "a.png".into(),
            regions: vec![Region {
                name: "past_the_edge".into(),
                feature: "x".into(),
                rect: Rect::new(10, 0, 8, 1),
                predicted: Prediction::Flat([0; 3]),
            }],
        }]
    };
    let suite = Suite {
        name: "Synthetic",
        source: "none",
        cases: bad,
    };
    let e = extract(&suite, &bad(Chip::Nv2a), &dir).unwrap_err();
    assert!(e.contains("past_the_edge") && e.contains("16x8"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

fn committed_reports() -> Vec<SuiteReport> {
    suites()
        .iter()
        .map(|s| {
            run_suite(s, Chip::Nv2a, None, None, false)
                .unwrap_or_else(|e| panic!("{}: {e}", s.name))
        })
        .collect()
}

#[test]
fn every_described_case_is_in_the_committed_tables() {
    for r in committed_reports() {
        // run_suite refuses a case or region the table lacks; here, every region counted.
        if r.images > 0 {
            assert!(r.tally.compared > 0, "{}: no pixels compared", r.suite);
            assert_eq!(
                r.tally.compared,
                r.tally.exact + r.tally.off1 + r.tally.worse,
                "{}",
                r.suite
            );
        }
    }
}
