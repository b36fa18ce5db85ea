//! `sweep … --shard K/N` and `sweep merge`: three shards run as three processes of the
//! binary and merged by a fourth give the unsharded sweep's CSV (all but the wall
//! times) and a plot, for the shafts, glare and shading sweeps; bad `--shard` forms,
//! a missing, duplicated or malformed shard and shards of two sweeps are refused,
//! naming the argument or the file, with nothing written. Small images keep it fast.

mod common;

use glare_pipeline::report::shard::Shard;
use std::path::Path;
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
}

fn tmp(name: &str) -> common::Scratch {
    common::Scratch::new("sweep-shard", name)
}

/// A shafts sweep small enough for seconds: fig4 at 90 × 60, an 8-sample truth.
const SHAFTS: &[&str] = &[
    "--scene",
    "fig4",
    "--image",
    "90x60",
    "--truth-samples",
    "8",
    "--param",
    "planes",
    "--values",
    "10,20,30,40,50",
];
const GLARE: &[&str] = &[
    "--scene",
    "glare-point",
    "--image",
    "64x48",
    "--param",
    "shape_log2",
    "--values",
    "5..8",
];
const SHADING: &[&str] = &[
    "--scene",
    "shading-specular",
    "--image",
    "32x32",
    "--param",
    "combiner_bits",
    "--values",
    "8,9,12,16",
];

fn sweep(args: &[&str], out: &Path, extra: &[&str]) -> Command {
    let mut c = bin();
    c.arg("sweep").args(args).arg("--out").arg(out).args(extra);
    c
}

/// `sweep merge --out OUT INPUTS…`.
fn merge(out: &Path, inputs: &[&Path]) -> Output {
    bin()
        .args(["sweep", "merge", "--out"])
        .arg(out)
        .args(inputs)
        .output()
        .unwrap()
}

fn ok(o: Output, what: &str) -> Output {
    assert!(
        o.status.success(),
        "{what}: {:?}\nstdout: {}\nstderr: {}",
        o.status,
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

/// Exit status 2 (an argument error) and stderr naming `names`; returns stderr.
fn refused(o: Output, names: &[&str]) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "stderr: {err}");
    for n in names {
        assert!(err.contains(n), "stderr does not name {n:?}: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
    err
}

/// Run `args` unsharded, and as N = 3 shards in three processes at once, merge them
/// in a fourth: the same CSV but for the wall times, the same row order, and a plot
/// (the same bytes when `same_plot`: the shafts plot draws no wall time).
fn sharded_matches_unsharded(name: &str, args: &[&str], param: &str, same_plot: bool) {
    let whole = tmp(&format!("{name}-whole"));
    ok(
        sweep(args, &whole, &[]).output().unwrap(),
        "unsharded sweep",
    );
    let shards = tmp(&format!("{name}-shards"));
    let children: Vec<_> = (1..=3)
        .map(|k| {
            sweep(args, &shards, &["--shard", &format!("{k}/3")])
                .stdout(std::process::Stdio::piped())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    for (k, c) in children.into_iter().enumerate() {
        ok(c.wait_with_output().unwrap(), &format!("shard {}/3", k + 1));
        let f = shards.join(format!("sweep_{param}.shard-{}-of-3.csv", k + 1));
        assert!(f.is_file(), "{} missing", f.display());
    }
    // Nothing but the shard files: a shard writes no CSV or plot of the sweep.
    assert!(!shards.join(format!("sweep_{param}.csv")).exists());
    let merged = tmp(&format!("{name}-merged"));
    let o = ok(merge(&merged, &[&shards]), "merge");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("merged 3 shards"), "{stdout}");

    let csv = format!("sweep_{param}.csv");
    let (a, b) = (
        common::without_wall(&whole.join(&csv)),
        common::without_wall(&merged.join(&csv)),
    );
    assert!(a.len() > 3, "{a:?}");
    assert_eq!(a, b, "merged CSV differs from the unsharded one");
    let png = std::fs::read(merged.join(format!("sweep_{param}.png"))).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    if same_plot {
        let whole_png = std::fs::read(whole.join(format!("sweep_{param}.png"))).unwrap();
        assert!(
            png == whole_png,
            "merged plot differs from the unsharded one"
        );
    }
    // No temporary file is left beside the outputs.
    let names: Vec<String> = std::fs::read_dir(&*merged)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn shafts_sweep_in_three_processes_merges_to_the_unsharded_csv() {
    sharded_matches_unsharded("shafts", SHAFTS, "planes", true);
}

#[test]
fn glare_sweep_in_three_processes_merges_to_the_unsharded_csv() {
    sharded_matches_unsharded("glare", GLARE, "shape_log2", false);
}

#[test]
fn shading_sweep_in_three_processes_merges_to_the_unsharded_csv() {
    sharded_matches_unsharded("shading", SHADING, "combiner_bits", false);
}

#[test]
fn shards_take_every_nth_value_and_parse_strictly() {
    let s = Shard::parse("2/3").unwrap();
    assert_eq!((s.k, s.n), (2, 3));
    assert_eq!(s.indices(8), [1, 4, 7]);
    assert_eq!(Shard::parse("3/3").unwrap().indices(2), Vec::<usize>::new());
    assert_eq!(Shard::parse("1/1").unwrap().indices(3), [0, 1, 2]);
    // Every index in exactly one shard.
    for n in 1..=7 {
        let mut all: Vec<usize> = (1..=n).flat_map(|k| Shard { k, n }.indices(20)).collect();
        all.sort();
        assert_eq!(all, (0..20).collect::<Vec<_>>(), "n = {n}");
    }
    for bad in [
        "0/3", "4/3", "3", "a/b", "1/0", "", "/", "1/", "+1/3", " 1/3", "1/3 ", "-1/3", "1/1001",
        "1.0/3",
    ] {
        let e = Shard::parse(bad).unwrap_err();
        assert!(e.contains("--shard takes K/N"), "{bad:?}: {e}");
    }
}

#[test]
fn bad_shard_forms_are_refused_naming_the_argument_before_any_work() {
    let out = tmp("bad-forms");
    for bad in ["0/3", "4/3", "3", "a/b", "1/0", "2/3/4", ""] {
        let err = refused(
            sweep(GLARE, &out, &["--shard", bad]).output().unwrap(),
            &["--shard"],
        );
        assert!(err.contains("K/N"), "{bad:?}: {err}");
        assert!(!out.exists(), "{bad:?} wrote {}", out.display());
    }
}

#[test]
fn merge_refuses_a_missing_shard_naming_it_and_writes_nothing() {
    let shards = tmp("missing");
    for k in [1, 3] {
        ok(
            sweep(GLARE, &shards, &["--shard", &format!("{k}/3")])
                .output()
                .unwrap(),
            "shard",
        );
    }
    let out = tmp("missing-out");
    refused(
        merge(&out, &[&shards]),
        &["missing shard", "sweep_shape_log2.shard-2-of-3.csv"],
    );
    assert!(!out.exists());
}

#[test]
fn merge_refuses_shards_of_two_sweeps_a_duplicate_and_a_malformed_file() {
    let a = tmp("mix-a");
    let b = tmp("mix-b");
    // Shard 1/2 of values 5..8 and shard 2/2 of values 5..7: two sweeps.
    ok(
        sweep(GLARE, &a, &["--shard", "1/2"]).output().unwrap(),
        "shard 1/2",
    );
    let mut other: Vec<&str> = GLARE.to_vec();
    *other.last_mut().unwrap() = "5..7";
    ok(
        sweep(&other, &b, &["--shard", "2/2"]).output().unwrap(),
        "shard 2/2",
    );
    let out = tmp("mix-out");
    let merge = |inputs: &[&Path]| merge(&out, inputs);
    let b2 = b.join("sweep_shape_log2.shard-2-of-2.csv");
    let err = refused(
        merge(&[&a, &b]),
        &[&b2.display().to_string(), "another sweep", "values"],
    );
    assert!(err.contains("5,6,7"), "{err}");

    // Another param (its own file name) in the same directory.
    let c = tmp("mix-c");
    let mut param: Vec<&str> = GLARE.to_vec();
    param[5] = "shape_bits";
    *param.last_mut().unwrap() = "6,7,8,9";
    ok(
        sweep(&param, &c, &["--shard", "2/2"]).output().unwrap(),
        "other param",
    );
    let c2 = c.join("sweep_shape_bits.shard-2-of-2.csv");
    refused(merge(&[&a, &c2]), &[&c2.display().to_string(), "param"]);

    // Another N.
    let d = tmp("mix-d");
    ok(
        sweep(GLARE, &d, &["--shard", "2/3"]).output().unwrap(),
        "N = 3",
    );
    refused(merge(&[&a, &d]), &["N = 3"]);

    // The same shard twice (a copy in another directory).
    let dup = tmp("dup");
    std::fs::create_dir_all(&*dup).unwrap();
    let a1 = a.join("sweep_shape_log2.shard-1-of-2.csv");
    std::fs::copy(&a1, dup.join("sweep_shape_log2.shard-1-of-2.csv")).unwrap();
    refused(merge(&[&a, &dup]), &["duplicate shard 1/2"]);

    // Malformed: not a shard, a cut row, a row of another shard.
    let bad = tmp("bad");
    std::fs::create_dir_all(&*bad).unwrap();
    let f = bad.join("sweep_shape_log2.shard-1-of-2.csv");
    let text = std::fs::read_to_string(&a1).unwrap();
    let fname = f.display().to_string();
    for (broken, why) in [
        ("param,value\n1,2\n".to_string(), "not a sweep shard file"),
        (
            text.lines()
                .take(text.lines().count() - 1)
                .collect::<Vec<_>>()
                .join("\n"),
            "incomplete",
        ),
        (text.replacen("\n0,", "\n1,", 1), "not shard 1/2's"),
        (text.replacen("\"k\":1", "\"k\":\"one\"", 1), "malformed"),
    ] {
        std::fs::write(&f, broken).unwrap();
        refused(merge(&[&f]), &[&fname, why]);
    }
    // A field that is not a number reads as no row of the sweep.
    std::fs::write(&f, text.replacen(",shape_log2,5,", ",shape_log2,five,", 1)).unwrap();
    refused(merge(&[&f]), &[&fname]);
    assert!(!out.exists(), "a refused merge wrote {}", out.display());
}

#[test]
fn merge_of_an_empty_directory_or_no_such_path_names_it() {
    let empty = tmp("empty");
    std::fs::create_dir_all(&*empty).unwrap();
    refused(
        bin()
            .args(["sweep", "merge"])
            .arg(&*empty)
            .output()
            .unwrap(),
        &[&empty.display().to_string(), "no sweep shard files"],
    );
    let none = empty.join("nope");
    refused(
        bin().args(["sweep", "merge"]).arg(&none).output().unwrap(),
        &[&none.display().to_string()],
    );
}

#[test]
fn more_shards_than_values_leave_some_empty_and_still_merge() {
    let shards = tmp("sparse");
    let mut args: Vec<&str> = GLARE.to_vec();
    *args.last_mut().unwrap() = "5,6";
    for k in 1..=3 {
        ok(
            sweep(&args, &shards, &["--shard", &format!("{k}/3")])
                .output()
                .unwrap(),
            "shard",
        );
    }
    let out = tmp("sparse-out");
    ok(merge(&out, &[&shards]), "merge");
    let rows = common::without_wall(&out.join("sweep_shape_log2.csv"));
    assert_eq!(rows.len(), 3);
    assert_eq!(rows[1][..2], ["shape_log2", "5"]);
    assert_eq!(rows[2][..2], ["shape_log2", "6"]);
}
