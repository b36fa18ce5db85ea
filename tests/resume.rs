//! Interrupted sweeps (issue 16, "no half-written outputs, no lost work"): the real
//! binary is stopped by a real signal (SIGKILL, which no handler sees, and SIGINT)
//! once its CSV holds at least one row and before it is done; the CSV then holds
//! complete rows only, and `--resume` finishes it to the uninterrupted run's CSV,
//! plot and table (wall times aside). A shard resumes the same way and still merges
//! to the unsharded sweep. A resume over another sweep's rows is refused naming the
//! file. Small images keep each run to seconds.

mod common;

use std::path::Path;
use std::process::{Command, Output, Stdio};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
}

fn tmp(name: &str) -> common::Scratch {
    common::Scratch::new("resume", name)
}

/// fig4 at 90 × 60 with an 8-sample truth: each row takes a fraction of a second, and
/// the rows grow dearer with the planes, so the run lasts long enough to be cut.
const VALUES: &str = "10,20,30,40,50,60,70,80,90,100,110,120";
const N_VALUES: usize = 12;

fn sweep(out: &Path, extra: &[&str]) -> Command {
    sweep_at("90x60", VALUES, out, extra)
}

/// `sweep` of fig4's planes at `image` over `values` with an 8-sample truth, into `out`.
fn sweep_at(image: &str, values: &str, out: &Path, extra: &[&str]) -> Command {
    let mut c = bin();
    c.args([
        "sweep",
        "--scene",
        "fig4",
        "--image",
        image,
        "--truth-samples",
        "8",
        "--param",
        "planes",
        "--values",
        values,
        "--out",
    ])
    .arg(out)
    .args(extra)
    .stdout(Stdio::piped())
    .stderr(Stdio::piped());
    c
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

/// The data lines of a file that holds at least `min` rows after its header lines
/// (`skip`), or None while it does not (or does not exist yet).
fn rows_in(path: &Path, skip: usize) -> Option<usize> {
    let text = std::fs::read_to_string(path).ok()?;
    Some(text.lines().count().saturating_sub(skip))
}

/// Start `cmd`, wait until `path` holds at least one row past `skip` header lines
/// while the child still runs, then send it `signal`; returns the child's exit status
/// and stderr.
fn cut_short(
    cmd: Command,
    path: &Path,
    skip: usize,
    signal: &str,
) -> (std::process::ExitStatus, String) {
    let ready = || rows_in(path, skip).is_some_and(|n| n >= 1);
    let o = common::cut_when(cmd, ready, "row", signal);
    (o.status, String::from_utf8_lossy(&o.stderr).into_owned())
}

/// The CSV holds complete rows only: a header, then lines of the header's field
/// count, every line ended, each a value of the sweep in order; returns the rows.
fn complete_rows(text: &str, header_lines: usize) -> Vec<Vec<String>> {
    assert!(text.ends_with('\n'), "last line cut: {text:?}");
    let lines: Vec<&str> = text.lines().skip(header_lines - 1).collect();
    let width = lines[0].split(',').count();
    let want: Vec<&str> = VALUES.split(',').collect();
    let value = lines[0].split(',').position(|c| c == "value").unwrap();
    let rows: Vec<Vec<String>> = lines[1..]
        .iter()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), width, "row {i} is not complete: {r:?}");
        for f in r {
            assert!(!f.is_empty(), "row {i} has an empty field: {r:?}");
        }
        let _: Vec<f64> = r[value + 1..]
            .iter()
            .map(|f| f.parse().unwrap_or_else(|_| panic!("row {i}: {f:?}")))
            .collect();
        // Rows come in the order of the values (a shard: every third from K − 1).
        assert!(want.contains(&r[value].as_str()), "row {i}: {r:?}");
    }
    rows
}

/// The printed table without its first line (paths and times) and its
/// `wall_seconds` column.
fn table_without_wall(stdout: &[u8]) -> Vec<Vec<String>> {
    let text = String::from_utf8_lossy(stdout);
    let lines: Vec<&str> = text.lines().skip(1).collect();
    let wall = lines[0]
        .split_whitespace()
        .position(|c| c == "wall_seconds")
        .expect("a wall_seconds column");
    lines
        .iter()
        .filter(|l| !l.starts_with("--"))
        .map(|l| {
            l.split_whitespace()
                .enumerate()
                .filter(|(i, _)| *i != wall)
                .map(|(_, f)| f.to_string())
                .collect()
        })
        .collect()
}

/// Cut a sweep with `signal`, check what it left, resume it, and compare with an
/// uninterrupted run: CSV (but wall), plot (the shafts plot draws no wall time) and
/// table (but wall).
fn killed_then_resumed_matches_uninterrupted(name: &str, signal: &str) {
    let whole = tmp(&format!("{name}-whole"));
    let w = ok(sweep(&whole, &[]).output().unwrap(), "uninterrupted sweep");

    let cut = tmp(&format!("{name}-cut"));
    let csv = cut.join("sweep_planes.csv");
    let (status, err) = cut_short(sweep(&cut, &[]), &csv, 1, signal);
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows = complete_rows(&text, 1);
    assert!(
        !rows.is_empty() && rows.len() < N_VALUES,
        "{} rows after the cut",
        rows.len()
    );
    // SIGINT and SIGTERM are caught: the run stops after the row it was computing is
    // saved, says how far it got and how to go on, and exits 128 + the signal
    // (SIGKILL cannot be caught: no message, killed by the signal).
    let caught = match signal {
        "INT" => Some(130),
        "TERM" => Some(143),
        _ => None,
    };
    assert_eq!(status.code(), caught, "{err}");
    let said = format!(
        "interrupted after {} of {N_VALUES} rows; rerun the same command with --resume to continue",
        rows.len()
    );
    assert_eq!(err.contains(&said), caught.is_some(), "{err}");
    // The rows left are the uninterrupted run's first rows (but wall).
    let full = common::without_wall(&whole.join("sweep_planes.csv"));
    assert_eq!(
        &common::without_wall(&csv)[..],
        &full[..=rows.len()],
        "the rows kept differ from the uninterrupted run's"
    );
    // No plot yet: the sweep did not finish.
    assert!(!cut.join("sweep_planes.png").exists());

    let r = ok(
        sweep(&cut, &["--resume"]).output().unwrap(),
        "resumed sweep",
    );
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        err.contains(&format!("resume: {} rows", rows.len())),
        "{err}"
    );
    assert_eq!(common::without_wall(&csv), full, "resumed CSV differs");
    // The rows kept are kept as they were, wall time included.
    let after = std::fs::read_to_string(&csv).unwrap();
    for l in text.lines() {
        assert!(after.contains(l), "row {l:?} was rewritten");
    }
    let (a, b) = (
        std::fs::read(whole.join("sweep_planes.png")).unwrap(),
        std::fs::read(cut.join("sweep_planes.png")).unwrap(),
    );
    assert!(a == b, "resumed plot differs from the uninterrupted one");
    assert_eq!(table_without_wall(&r.stdout), table_without_wall(&w.stdout));
    // Nothing left behind but the outputs and the record.
    let mut names: Vec<String> = std::fs::read_dir(&*cut)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "sweep_planes.csv",
            "sweep_planes.png",
            "sweep_planes.resume.json"
        ]
    );
}

#[test]
fn a_sweep_killed_with_sigkill_keeps_complete_rows_and_resumes_to_the_same_bytes() {
    killed_then_resumed_matches_uninterrupted("kill", "KILL");
}

#[test]
fn a_sweep_stopped_with_sigint_keeps_complete_rows_and_resumes_to_the_same_bytes() {
    killed_then_resumed_matches_uninterrupted("int", "INT");
}

#[test]
fn a_sweep_stopped_with_sigterm_keeps_complete_rows_and_resumes_to_the_same_bytes() {
    killed_then_resumed_matches_uninterrupted("term", "TERM");
}

/// A shard cut short (SIGINT) is refused by `sweep merge` as incomplete; `--resume` finishes
/// it, and the merge of the three shards is the unsharded sweep (but wall).
#[test]
fn a_killed_shard_resumes_and_merges_to_the_unsharded_sweep() {
    let whole = tmp("shard-whole");
    ok(sweep(&whole, &[]).output().unwrap(), "unsharded sweep");
    let shards = tmp("shard-parts");
    for k in [1, 3] {
        ok(
            sweep(&shards, &["--shard", &format!("{k}/3")])
                .output()
                .unwrap(),
            "shard",
        );
    }
    let file = shards.join("sweep_planes.shard-2-of-3.csv");
    // Two header lines: the shard's record and the columns.
    let (status, err) = cut_short(sweep(&shards, &["--shard", "2/3"]), &file, 2, "INT");
    assert_eq!(status.code(), Some(130), "{err}");
    let text = std::fs::read_to_string(&file).unwrap();
    let rows = complete_rows(&text, 2);
    assert!(!rows.is_empty() && rows.len() < 4, "{} rows", rows.len());
    // A shard counts the rows of its own share (4 of the 12 values).
    assert!(
        err.contains(&format!(
            "interrupted after {} of 4 rows; rerun the same command with --resume",
            rows.len()
        )),
        "{err}"
    );

    let merged = tmp("shard-merged");
    let m = bin()
        .args(["sweep", "merge", "--out"])
        .arg(&*merged)
        .arg(&*shards)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&m.stderr);
    assert_eq!(m.status.code(), Some(2), "{err}");
    assert!(
        err.contains("incomplete") && err.contains("shard-2-of-3") && err.contains("--resume"),
        "{err}"
    );

    ok(
        sweep(&shards, &["--shard", "2/3", "--resume"])
            .output()
            .unwrap(),
        "resumed shard",
    );
    let m = bin()
        .args(["sweep", "merge", "--out"])
        .arg(&*merged)
        .arg(&*shards)
        .output()
        .unwrap();
    ok(m, "merge");
    assert_eq!(
        common::without_wall(&merged.join("sweep_planes.csv")),
        common::without_wall(&whole.join("sweep_planes.csv"))
    );
    assert!(
        std::fs::read(merged.join("sweep_planes.png")).unwrap()
            == std::fs::read(whole.join("sweep_planes.png")).unwrap()
    );
}

/// `--resume` over rows of another sweep (other values, another image size), over a
/// CSV with no record, or over a row edited by hand is refused naming the file, and
/// leaves the file as it was; with nothing to resume from, it starts the sweep.
#[test]
fn resume_refuses_another_sweeps_rows_naming_the_file() {
    let out = tmp("refuse");
    let small = |extra: &[&str]| {
        let mut c = bin();
        c.args([
            "sweep",
            "--scene",
            "fig4",
            "--image",
            "48x32",
            "--truth-samples",
            "4",
            "--param",
            "planes",
            "--out",
        ])
        .arg(&*out)
        .args(extra);
        c.output().unwrap()
    };
    // Nothing there yet: --resume starts the sweep.
    ok(small(&["--values", "10,20", "--resume"]), "first run");
    let csv = out.join("sweep_planes.csv");
    let before = std::fs::read(&csv).unwrap();
    let refused = |o: Output, names: &[&str]| {
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains("cannot resume"), "{err}");
        for n in names {
            assert!(err.contains(n), "does not name {n:?}: {err}");
        }
        assert!(!err.contains("panicked"), "{err}");
    };
    refused(
        small(&["--values", "10,30", "--resume"]),
        &["sweep_planes.csv", "values"],
    );
    let mut c = bin();
    c.args([
        "sweep",
        "--scene",
        "fig4",
        "--image",
        "40x32",
        "--truth-samples",
        "4",
        "--param",
        "planes",
        "--values",
        "10,20",
        "--resume",
        "--out",
    ])
    .arg(&*out);
    refused(c.output().unwrap(), &["sweep_planes.csv", "image"]);
    assert_eq!(std::fs::read(&csv).unwrap(), before, "a refusal wrote");

    // A value edited by hand.
    let text = String::from_utf8(before.clone()).unwrap();
    let edited = text.replacen("planes,20,", "planes,20,9", 1);
    assert_ne!(edited, text);
    std::fs::write(&csv, &edited).unwrap();
    refused(
        small(&["--values", "10,20", "--resume"]),
        &["sweep_planes.csv", "line 3"],
    );
    // No record beside the CSV.
    std::fs::write(&csv, &before).unwrap();
    std::fs::remove_file(out.join("sweep_planes.resume.json")).unwrap();
    refused(
        small(&["--values", "10,20", "--resume"]),
        &["sweep_planes.csv", "sweep_planes.resume.json"],
    );
    // Without --resume the sweep starts over.
    ok(small(&["--values", "10,30"]), "a new sweep");
    let rows = complete_rows(&std::fs::read_to_string(&csv).unwrap(), 1);
    assert_eq!(rows.len(), 2);
    assert_eq!(rows[1][1], "30");
}

/// Only the reproductions that save rows as they go take --resume; the refusal says
/// why: a fast one finishes in seconds, a long one of a single frame has no item to
/// keep.
#[test]
fn reproduce_resume_is_refused_where_nothing_resumes() {
    let out = tmp("reproduce");
    for (name, why) in [
        ("glare-fig4", "finishes in seconds"),
        ("shafts-stage", "one frame and one row"),
    ] {
        let o = bin()
            .args(["reproduce", name, "--resume", "--out"])
            .arg(&*out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(
            err.contains("resume") && err.contains(name) && err.contains(why),
            "{err}"
        );
        assert!(!out.exists(), "files written");
    }
}

/// The atomic writer: a write that fails leaves the old file and no temporary file;
/// one that succeeds replaces it whole.
#[test]
fn a_failed_write_leaves_the_old_file_and_no_temporary() {
    use glare_pipeline::report::atomic::{write_atomically, write_bytes};
    let dir = tmp("atomic");
    let f = dir.join("a.csv");
    write_bytes(&f, b"old\n").unwrap();
    let e = write_atomically(&f, |p| {
        std::fs::write(p, b"half").unwrap();
        Err("disk full".into())
    })
    .unwrap_err();
    assert_eq!(e, "disk full");
    assert_eq!(std::fs::read(&f).unwrap(), b"old\n");
    write_bytes(&f, b"new\n").unwrap();
    assert_eq!(std::fs::read(&f).unwrap(), b"new\n");
    let names: Vec<String> = std::fs::read_dir(&*dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["a.csv"]);
}

/// `--resume`'s clean-up: another process's temporary files of the file are removed,
/// this process's and other files' are not.
#[test]
fn stale_temporary_files_of_a_killed_run_are_removed() {
    use glare_pipeline::report::atomic::remove_stale_partials;
    let dir = tmp("stale");
    std::fs::create_dir_all(&*dir).unwrap();
    let f = dir.join("sweep_planes.csv");
    let mine = format!(".sweep_planes.{}-3.partial.csv", std::process::id());
    for n in [
        ".sweep_planes.999999999-0.partial.csv",
        ".sweep_planes.999999998-7.partial.csv",
        mine.as_str(),
        ".sweep_mesh.999999999-0.partial.csv",
        ".sweep_planes.x-0.partial.csv",
        "sweep_planes.csv",
    ] {
        std::fs::write(dir.join(n), b"x").unwrap();
    }
    assert_eq!(remove_stale_partials(&f), 2);
    let mut names: Vec<String> = std::fs::read_dir(&*dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let mut want = vec![
        ".sweep_mesh.999999999-0.partial.csv".to_string(),
        ".sweep_planes.x-0.partial.csv".to_string(),
        mine,
        "sweep_planes.csv".to_string(),
    ];
    want.sort();
    assert_eq!(names, want);
}

/// Ctrl-C twice: the second SIGINT, sent 30 ms after the first while the row the
/// first one waits for is still being computed (after a cheap first row, rows of
/// about a second each), ends the run at once, but still with the saved/resume line
/// (counting the rows on file, which are whole) and status 130; `--resume` then
/// finishes the rows. (Before, the second signal ended the run without a word.)
#[test]
fn a_sweep_interrupted_twice_still_says_what_it_saved_and_resumes() {
    use std::time::{Duration, Instant};
    const VALUES: &str = "10,150,160,170";
    let sweep = |out: &Path, extra: &[&str]| sweep_at("160x120", VALUES, out, extra);
    let cut = tmp("int-twice");
    let csv = cut.join("sweep_planes.csv");
    let mut child = sweep(&cut, &[]).spawn().unwrap();
    let t0 = Instant::now();
    while rows_in(&csv, 1).unwrap_or(0) < 1 {
        assert!(child.try_wait().unwrap().is_none(), "ended before a row");
        assert!(
            t0.elapsed() < Duration::from_secs(300),
            "no row after 300 s"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    for _ in 0..2 {
        let st = Command::new("kill")
            .arg("-INT")
            .arg(child.id().to_string())
            .status()
            .unwrap();
        assert!(st.success());
        std::thread::sleep(Duration::from_millis(30));
    }
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.ends_with('\n'), "last line cut: {text:?}");
    let rows = text.lines().count() - 1;
    assert!((1..4).contains(&rows), "{rows} rows");
    let said = format!(
        "interrupted after {rows} of 4 rows; rerun the same command with --resume to continue"
    );
    assert!(err.contains(&said), "{err}");
    assert_eq!(err.matches("interrupted after").count(), 1, "{err}");
    let r = ok(
        sweep(&cut, &["--resume"]).output().unwrap(),
        "resumed sweep",
    );
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains(&format!("resume: {rows} rows")), "{err}");
    let resumed = std::fs::read_to_string(&csv).unwrap();
    let values: Vec<String> = resumed
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().to_string())
        .collect();
    assert_eq!(values.join(","), VALUES, "{resumed}");
}
