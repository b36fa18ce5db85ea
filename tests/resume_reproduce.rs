//! Interrupted reproductions (issue 16: "a sweep or reproduction interrupted keeps the
//! rows it finished, and `--resume` continues from them"): the real binary runs a long
//! reproduction at a reduced size (its environment variables), is stopped by a real
//! signal once its journal (`DIR/<name>.resume.jsonl`, `report::items`) holds a
//! finished item, and `--resume` then writes the uninterrupted run's bytes (wall-time
//! columns aside). A journal of other settings is refused naming the setting.

mod common;

use std::path::Path;
use std::process::{Command, Output, Stdio};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
}

fn tmp(name: &str) -> common::Scratch {
    common::Scratch::new("resume-reproduce", name)
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

/// `reproduce NAME --out OUT [extra]` with the environment `env`.
fn reproduce(name: &str, out: &Path, env: &[(&str, &str)], extra: &[&str]) -> Command {
    let mut c = bin();
    c.args(["reproduce", name, "--out"])
        .arg(out)
        .args(extra)
        .envs(env.iter().copied())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    c
}

/// Run `cmd` to its end on a thread of its own: the uninterrupted run goes on beside
/// the one that is cut short (their directories are apart), so that the two cores are
/// busy while the test waits for a journal item.
fn beside(mut cmd: Command) -> std::thread::JoinHandle<Output> {
    std::thread::spawn(move || cmd.output().unwrap())
}

/// Items in a journal (its lines after the record), None while it does not exist.
fn items_in(journal: &Path) -> Option<usize> {
    let text = std::fs::read_to_string(journal).ok()?;
    Some(text.lines().count().saturating_sub(1))
}

/// Start `cmd`, wait until `journal` holds an item while the child still runs, send
/// it `kill -SIGNAL`; returns its exit status and stderr.
fn cut_short(cmd: Command, journal: &Path, signal: &str) -> (Option<i32>, String) {
    let ready = || items_in(journal).is_some_and(|n| n >= 1);
    let o = common::cut_when(cmd, ready, "journal item", signal);
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// The number in "interrupted after K of N items" and N.
fn kept(err: &str) -> (usize, usize) {
    let at = err
        .find("interrupted after ")
        .unwrap_or_else(|| panic!("no interruption note: {err}"));
    let words: Vec<&str> = err[at..].split_whitespace().collect();
    (words[2].parse().unwrap(), words[4].parse().unwrap())
}

/// glare-gauss-seeds at 40 seeds (80 items, a journal saved every 64 items or every
/// second): SIGINT, then --resume gives the uninterrupted run's CSVs, plot and
/// printed table byte for byte (no wall-time column here).
#[test]
fn gauss_seeds_stopped_with_sigint_resumes_to_the_same_bytes() {
    let env = [("GLARE_GAUSS_SEEDS", "40")];
    let name = "glare-gauss-seeds";
    let whole = tmp("gauss-whole");
    let whole_run = beside(reproduce(name, &whole, &env, &[]));
    let cut = tmp("gauss-cut");
    let journal = cut.join("glare-gauss-seeds.resume.jsonl");
    let (code, err) = cut_short(reproduce(name, &cut, &env, &[]), &journal, "INT");
    assert_eq!(code, Some(130), "{err}");
    let (k, n) = kept(&err);
    assert_eq!(n, 80, "{err}");
    assert!(k >= 1 && k < n, "{err}");
    assert!(err.contains("--resume"), "{err}");
    // Every finished item is on file (SIGINT saves the batch), and no output yet.
    assert_eq!(items_in(&journal), Some(k));
    assert!(!cut.join("gauss_seeds.csv").exists());
    let w = ok(whole_run.join().unwrap(), "uninterrupted run");

    let r = ok(
        reproduce(name, &cut, &env, &["--resume"]).output().unwrap(),
        "resumed run",
    );
    let rerr = String::from_utf8_lossy(&r.stderr);
    assert!(
        rerr.contains(&format!("resume: {k} of 80 items of reproduce {name}")),
        "{rerr}"
    );
    for f in [
        "gauss_seeds.csv",
        "gauss_seeds_summary.csv",
        "gauss_seeds_4sigma.png",
    ] {
        let (a, b) = (
            std::fs::read(whole.join(f)).unwrap(),
            std::fs::read(cut.join(f)).unwrap(),
        );
        assert!(a == b, "{f}: the resumed run's bytes differ");
    }
    // The printed summary, but its last line (the directory and the wall time).
    let table = |o: &Output| {
        let t = String::from_utf8_lossy(&o.stdout).into_owned();
        let lines: Vec<String> = t.lines().map(str::to_string).collect();
        assert!(lines
            .last()
            .unwrap()
            .starts_with("glare-gauss-seeds: wrote "));
        lines[..lines.len() - 1].to_vec()
    };
    assert_eq!(table(&r), table(&w), "printed table differs");
    assert_eq!(items_in(&journal), Some(80));
}

/// The CSV without the named wall-time columns.
fn without(path: &Path, wall: &[&str]) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let keep: Vec<usize> = (0..head.len())
        .filter(|&i| !wall.contains(&head[i]))
        .collect();
    std::iter::once(head.join(","))
        .chain(lines.map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            keep.iter().map(|&i| f[i]).collect::<Vec<_>>().join(",")
        }))
        .collect()
}

/// envmap-table3 at side 16 on a 64 × 32 pattern over eight thresholds: SIGTERM, then
/// --resume gives the uninterrupted run's tables but for the build times.
#[test]
fn envmap_table3_stopped_with_sigterm_resumes_to_the_same_tables() {
    let env = [
        ("ENVMAP_TABLE3_S", "16"),
        ("ENVMAP_PATTERN_SIZE", "64x32"),
        (
            "ENVMAP_TABLE3_TH",
            "0.001,0.005,0.01,0.02,0.05,0.1,0.25,0.5",
        ),
    ];
    let name = "envmap-table3";
    let whole = tmp("table3-whole");
    let whole_run = beside(reproduce(name, &whole, &env, &[]));
    let cut = tmp("table3-cut");
    let journal = cut.join("envmap-table3.resume.jsonl");
    let (code, err) = cut_short(reproduce(name, &cut, &env, &[]), &journal, "TERM");
    assert_eq!(code, Some(143), "{err}");
    let (k, n) = kept(&err);
    assert_eq!(n, 18, "{err}");
    assert!(k >= 1 && k < n, "{err}");
    assert_eq!(items_in(&journal), Some(k));
    assert!(!cut.join("table3.csv").exists());
    ok(whole_run.join().unwrap(), "uninterrupted run");
    ok(
        reproduce(name, &cut, &env, &["--resume"]).output().unwrap(),
        "resumed run",
    );
    for (f, wall) in [
        ("table3.csv", &["build_seconds"][..]),
        ("table3_extra.csv", &[][..]),
        ("prefilter_times.csv", &["exact_seconds"][..]),
    ] {
        assert_eq!(
            without(&cut.join(f), wall),
            without(&whole.join(f), wall),
            "{f}: the resumed run's rows differ"
        );
    }
}

/// A journal of other settings is refused, naming the file, the setting and both
/// values, and is left as it was; without --resume the run starts over.
#[test]
fn a_journal_of_other_settings_is_refused_naming_the_setting() {
    let name = "glare-gauss-seeds";
    let out = tmp("refuse");
    ok(
        reproduce(name, &out, &[("GLARE_GAUSS_SEEDS", "2")], &[])
            .output()
            .unwrap(),
        "first run",
    );
    let journal = out.join("glare-gauss-seeds.resume.jsonl");
    let before = std::fs::read(&journal).unwrap();
    let o = reproduce(name, &out, &[("GLARE_GAUSS_SEEDS", "3")], &["--resume"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("glare-gauss-seeds.resume.jsonl: cannot resume")
            && err.contains("GLARE_GAUSS_SEEDS \"2\" vs \"3\""),
        "{err}"
    );
    assert_eq!(std::fs::read(&journal).unwrap(), before);
    // --resume of the same settings after a complete run computes nothing new.
    let r = ok(
        reproduce(name, &out, &[("GLARE_GAUSS_SEEDS", "2")], &["--resume"])
            .output()
            .unwrap(),
        "resume of a complete run",
    );
    assert!(
        String::from_utf8_lossy(&r.stderr).contains("resume: 4 of 4 items"),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    ok(
        reproduce(name, &out, &[("GLARE_GAUSS_SEEDS", "3")], &[])
            .output()
            .unwrap(),
        "a new run",
    );
    assert_eq!(items_in(&journal), Some(6));
}

/// frame-elaboration at 32 × 24 (the library call; the CLI's size is fixed): a run
/// whose journal lost its last three variants (as a run stopped after two would have
/// left it) resumes to the uninterrupted run's CSV (wall time aside), grid and frame
/// images; the grid's kept panels are read back from their PNGs.
#[test]
fn frame_elaboration_resumes_to_the_same_images_and_rows() {
    use glare_pipeline::frame::reproduce::frame_elaboration_resumable as run;
    let size = Some((32, 24));
    let whole = tmp("elab-whole");
    std::fs::create_dir_all(&*whole).unwrap();
    run(&whole, size, false).unwrap();
    let cut = tmp("elab-cut");
    std::fs::create_dir_all(&*cut).unwrap();
    let journal_of_whole = whole.join("frame-elaboration.resume.jsonl");
    std::fs::copy(
        &journal_of_whole,
        cut.join("frame-elaboration.resume.jsonl"),
    )
    .unwrap();
    let journal = cut.join("frame-elaboration.resume.jsonl");
    let text = std::fs::read_to_string(&journal).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 6, "a record and five variants");
    // Keep the record and the first two variants (the journal is in key order; which
    // two does not matter); remove every output.
    std::fs::write(&journal, format!("{}\n", lines[..3].join("\n"))).unwrap();
    for e in std::fs::read_dir(&*cut).unwrap() {
        let p = e.unwrap().path();
        if p != journal {
            std::fs::remove_file(p).unwrap();
        }
    }
    // The two kept variants' PNGs come back only through a render: put the whole
    // run's in place, as the interrupted run had written them.
    for l in &lines[1..3] {
        let key = l.split('"').nth(3).unwrap();
        let f = format!("frame_{}.png", key.replace(' ', "_").to_lowercase());
        std::fs::copy(whole.join(&f), cut.join(&f)).unwrap();
    }
    run(&cut, size, true).unwrap();
    let wall = ["simulation_wall_seconds"];
    assert_eq!(
        without(&cut.join("frame_elaboration.csv"), &wall),
        without(&whole.join("frame_elaboration.csv"), &wall)
    );
    let mut names = 0;
    for e in std::fs::read_dir(&*whole).unwrap() {
        let n = e.unwrap().file_name().to_string_lossy().into_owned();
        if n.ends_with(".png") {
            names += 1;
            assert!(
                std::fs::read(whole.join(&n)).unwrap() == std::fs::read(cut.join(&n)).unwrap(),
                "{n} differs"
            );
        }
    }
    assert_eq!(names, 6, "five frames and the grid");
}
