//! `attribute --scene S` (issue 18): the error budget by ablation on a reduced fig6,
//! and the command's refusals of bad arguments (each naming the argument, before any
//! file is written).

use glare_pipeline::pipeline::shading::attribute::{attribute_shading, ShadingConfig};
use glare_pipeline::pipeline::shafts::attribute::{attribute_shafts, bound, load_with_image};
use std::path::PathBuf;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("attribute-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// fig6 at 120 × 80: the h table's scaling/cap is the largest source and what it
/// removes sits in the top band (next to the light); all ideal comes back to the
/// reference within the bound of `shafts::attribute::bound`; the interaction remainder
/// is a row of the CSV. (Release: 10 s user time; the all-ideal frame has 120 planes.)
#[test]
fn fig6_names_the_h_scaling_in_the_top_band_and_all_ideal_is_within_bound() {
    let scene = load_with_image("fig6", Some("120x80")).unwrap();
    let out = scratch("fig6");
    let a = attribute_shafts(&scene, &out).unwrap();
    let d = a.dominant().unwrap();
    assert_eq!(d.source, "table scaling (h cap)", "{:#?}", a.rows);
    assert!(
        d.share > 0.5,
        "h scaling removes {:.3} of the squared error",
        d.share
    );
    assert_eq!(d.band, "top");
    // Every other source removes less than a fifth of what it removes.
    for r in a
        .rows
        .iter()
        .filter(|r| r.kind == "source" && r.source != d.source)
    {
        assert!(
            r.removed_sq < 0.2 * d.removed_sq,
            "{} removes {}",
            r.source,
            r.removed_sq
        );
    }
    let b = bound();
    assert!(
        a.configured.mean_abs > b.mean_abs,
        "configured is outside the bound"
    );
    assert!(
        a.within_bound
            && a.all_ideal.mean_abs <= b.mean_abs
            && a.all_ideal_outliers <= b.outlier_fraction,
        "all ideal: mean {} outliers {}",
        a.all_ideal.mean_abs,
        a.all_ideal_outliers
    );
    let rem = a.rows.iter().find(|r| r.kind == "remainder").unwrap();
    assert!(rem.share.is_finite());
    assert_eq!(rem.share, a.remainder_share);
    // The files: the CSV has every row, the chart and the h scaling's difference image.
    let csv = std::fs::read_to_string(&a.csv).unwrap();
    assert_eq!(csv.lines().count(), a.rows.len() + 1);
    assert!(csv.contains("interaction remainder"));
    assert!(a.png.is_file());
    assert!(a
        .diff_images
        .iter()
        .any(|p| p.ends_with("diff_table_scaling_h_cap.png")));
    let _ = std::fs::remove_dir_all(&out);
}

/// shading-specular (the texture-shader lookup path) on a 64² view: the lookup's
/// 8-bit entries (the output rounding) are the largest source, and all ideal comes
/// back to 255·(n̂·ĥ)^32 within `shading::attribute::bound`, below the configured
/// error. shading-lambert: the normalisation cube is its only source, and all ideal is
/// within the bound too. (Release: about 1 s each.)
#[test]
fn shading_scenes_name_a_dominant_source_and_all_ideal_is_within_bound() {
    let b = glare_pipeline::pipeline::shading::attribute::bound();
    let c = ShadingConfig::new("shading-specular", 64).unwrap();
    let out = scratch("shading-specular");
    let a = attribute_shading(&c, &out).unwrap();
    let d = a.dominant().unwrap();
    assert_eq!(
        d.source, "lookup entries (output rounding)",
        "{:#?}",
        a.rows
    );
    assert!(d.share > 0.5, "{} removes {:.3}", d.source, d.share);
    assert!(
        a.within_bound
            && a.all_ideal.mean_abs <= b.mean_abs
            && a.all_ideal_outliers <= b.outlier_fraction,
        "all ideal: mean {} outliers {}",
        a.all_ideal.mean_abs,
        a.all_ideal_outliers
    );
    assert!(a.all_ideal.rms < a.configured.rms);
    let csv = std::fs::read_to_string(&a.csv).unwrap();
    assert_eq!(csv.lines().count(), a.rows.len() + 1);
    assert!(csv.contains("interaction remainder"));
    assert!(a.png.is_file());
    assert!(a
        .diff_images
        .iter()
        .any(|p| p.ends_with("diff_lookup_entries_output_rounding.png")));
    let _ = std::fs::remove_dir_all(&out);

    let c = ShadingConfig::new("shading-lambert", 64).unwrap();
    let out = scratch("shading-lambert");
    let a = attribute_shading(&c, &out).unwrap();
    assert_eq!(
        a.dominant().unwrap().source,
        "normalisation cube resolution",
        "{:#?}",
        a.rows
    );
    assert!(a.dominant().unwrap().share > 0.0);
    assert!(
        a.within_bound,
        "all ideal: mean {} outliers {}",
        a.all_ideal.mean_abs, a.all_ideal_outliers
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// `sweep --attribute` on a tiny shading-specular sweep (32² view, two values): the
/// CSV gains dominant_source and dominant_share, a 16-entry table's dominant source
/// is the table size; without the flag the same sweep's CSV has the plain columns
/// and the same error columns.
#[test]
fn sweep_attribute_adds_the_dominant_source_columns() {
    use glare_pipeline::pipeline::shading::attributed_sweep::shading_sweep_attributed;
    use glare_pipeline::pipeline::shading::sweep::{shading_sweep, ShadingSweepOptions};
    let opts = ShadingSweepOptions { view_size: 32 };
    let out = scratch("sweep-attr");
    let (rows, csv, _) =
        shading_sweep_attributed("shading-specular", "lookup_log2", &[4, 8], &out, &opts).unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    let header = text.lines().next().unwrap();
    assert!(
        header.ends_with(",dominant_source,dominant_share"),
        "{header}"
    );
    assert_eq!(text.lines().count(), 3);
    assert_eq!(rows[0].dominant_source, "specular lookup table size");
    assert!(rows[0].dominant_share > 0.5 && rows[0].dominant_share <= 1.0);
    assert!(out
        .join("attribute_lookup_log2_4/attribution.csv")
        .is_file());
    let plain = scratch("sweep-plain");
    let (prow, pcsv, _) =
        shading_sweep("shading-specular", "lookup_log2", &[4, 8], &plain, &opts).unwrap();
    let ptext = std::fs::read_to_string(&pcsv).unwrap();
    assert!(!ptext.contains("dominant_source"));
    for (a, p) in rows.iter().zip(&prow) {
        assert_eq!((a.value, a.rms_levels), (p.value, p.rms_levels));
    }
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(&plain);
}

fn refused(args: &[&str], names: &str) {
    let o = bin().arg("attribute").args(args).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{args:?} was accepted");
    assert!(
        err.contains(names),
        "{args:?}: '{err}' does not name {names}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_arguments_are_refused_naming_them_before_any_work() {
    let out = scratch("bad");
    let o = out.to_str().unwrap();
    refused(&["--scene", "no-such-scene", "--out", o], "scene");
    refused(&["--scene", "shading-vertex", "--out", o], "scene");
    refused(&["--scene", "shading-nope", "--out", o], "scene");
    refused(
        &["--scene", "shading-lambert", "--image", "64x32", "--out", o],
        "image",
    );
    refused(&["--scene", "test", "--out", o], "scene");
    refused(&["--scene", "fig6", "--image", "12x", "--out", o], "image");
    refused(&["--scene", "fig6", "--image", "wide", "--out", o], "image");
    refused(
        &["--scene", "fig6", "--image", "0x80", "--out", o],
        "image.width",
    );
    refused(
        &["--scene", "fig6", "--image", "120x100000", "--out", o],
        "image.height",
    );
    refused(&["--out", o], "--scene");
    assert!(!out.exists(), "a refused run wrote {}", out.display());
    // An output path that is a file.
    let file = std::env::temp_dir().join(format!("attribute-test-{}-file", std::process::id()));
    std::fs::write(&file, b"x").unwrap();
    refused(
        &[
            "--scene",
            "fig6",
            "--image",
            "120x80",
            "--out",
            file.to_str().unwrap(),
        ],
        "out",
    );
    let _ = std::fs::remove_file(&file);
}
