//! The bad-inputs corpus (`tests/bad_inputs/cases.toml`, docs/inputs.md): malformed
//! and extreme scene files and command lines, each run through the real binary as a
//! user would, asserting the exit status, that stderr names the right field or
//! argument, that nothing panics, and that each case ends within 60 s (a case still
//! running then is killed, and that is a failure). The cases run on a few threads;
//! every one refuses its input before any work, so the whole corpus takes seconds.
//!
//! Also here: the memory budget (`frame::budget`) refuses a scene whose tables exceed
//! it in under 1 s with the child's peak RSS under 200 MB, both measured (wait4).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use toml::Value;

/// Each case must end within this (it is killed then, and fails).
const CASE_TIMEOUT: Duration = Duration::from_secs(60);
/// The corpus must hold at least this many cases.
const MIN_CASES: usize = 150;
/// Every class of the issue, and every pipeline's scene sections, must have cases.
const CLASSES: [&str; 5] = [
    "units-disagree",
    "truncation",
    "degenerate",
    "unbounded",
    "misleading",
];
const SECTIONS: [&str; 5] = ["shafts", "glare", "envmap", "shading", "showcase"];

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs")
}

/// One case of cases.toml (see the header of that file).
struct Case {
    name: String,
    class: String,
    section: String,
    args: Vec<String>,
    env: Vec<(String, String)>,
    exit: i32,
    names: Vec<String>,
    absent: Vec<String>,
    scene: Option<String>,
    setup: Value,
}

fn strings(v: Option<&Value>) -> Vec<String> {
    match v {
        Some(Value::String(s)) => vec![s.clone()],
        Some(Value::Array(a)) => a
            .iter()
            .map(|x| x.as_str().expect("a string").to_string())
            .collect(),
        _ => Vec::new(),
    }
}

/// A path `a.b[2].c` as segments: keys and indices.
enum Seg {
    Key(String),
    Index(usize),
}

fn segments(path: &str) -> Vec<Seg> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let mut rest = part;
        if let Some(i) = rest.find('[') {
            out.push(Seg::Key(rest[..i].to_string()));
            rest = &rest[i..];
            while let Some(r) = rest.strip_prefix('[') {
                let end = r.find(']').expect("] in path");
                out.push(Seg::Index(r[..end].parse().expect("an index")));
                rest = &r[end + 1..];
            }
        } else {
            out.push(Seg::Key(rest.to_string()));
        }
    }
    out
}

/// Set (or with `None` remove) the value at `path`, creating tables on the way.
fn set_path(root: &mut Value, path: &str, value: Option<Value>) {
    let segs = segments(path);
    let mut cur = root;
    for (i, s) in segs.iter().enumerate() {
        let last = i + 1 == segs.len();
        match s {
            Seg::Key(k) => {
                let t = cur
                    .as_table_mut()
                    .unwrap_or_else(|| panic!("{path}: not a table"));
                if last {
                    match value {
                        Some(v) => {
                            t.insert(k.clone(), v);
                        }
                        None => {
                            t.remove(k);
                        }
                    }
                    return;
                }
                cur = t
                    .entry(k.clone())
                    .or_insert_with(|| Value::Table(Default::default()));
            }
            Seg::Index(n) => {
                let a = cur
                    .as_array_mut()
                    .unwrap_or_else(|| panic!("{path}: not an array"));
                if last {
                    match value {
                        Some(v) if *n < a.len() => a[*n] = v,
                        Some(v) => a.push(v),
                        None => {
                            a.remove(*n);
                        }
                    }
                    return;
                }
                cur = &mut a[*n];
            }
        }
    }
}

/// The scene text of a case: a built-in (`base`, at a small image size unless the
/// case sets one) with `set` applied and `unset` removed, then `append` added as
/// text; or `text` as it is.
fn scene_text(c: &Value) -> Option<String> {
    if let Some(t) = c.get("text").and_then(Value::as_str) {
        return Some(t.to_string());
    }
    let base = c.get("base").and_then(Value::as_str)?;
    let text = glare_pipeline::scene::builtin::builtin_toml(base)
        .unwrap_or_else(|e| panic!("base {base}: {e}"));
    let mut v: Value = toml::from_str(&text).expect("a built-in parses");
    set_path(&mut v, "image.width", Some(Value::Integer(32)));
    set_path(&mut v, "image.height", Some(Value::Integer(24)));
    if let Some(Value::Table(sets)) = c.get("set") {
        for (k, x) in sets {
            set_path(&mut v, k, Some(x.clone()));
        }
    }
    for k in strings(c.get("unset")) {
        set_path(&mut v, &k, None);
    }
    let mut out = toml::to_string(&v).expect("serialises");
    if let Some(a) = c.get("append").and_then(Value::as_str) {
        out.push('\n');
        out.push_str(a);
    }
    Some(out)
}

fn load_cases() -> Vec<Case> {
    let text = std::fs::read_to_string(corpus_dir().join("cases.toml")).expect("cases.toml");
    let doc: Value = toml::from_str(&text).expect("cases.toml parses");
    let mut seen = BTreeSet::new();
    doc["case"]
        .as_array()
        .expect("[[case]] entries")
        .iter()
        .map(|c| {
            let name = c["name"].as_str().expect("name").to_string();
            assert!(seen.insert(name.clone()), "duplicate case name {name}");
            let scene = scene_text(c);
            let args = match c.get("args") {
                Some(_) => strings(c.get("args")),
                None => {
                    assert!(scene.is_some(), "{name}: no args and no scene");
                    ["render", "--scene", "{scene}", "--out", "{tmp}/out.png"]
                        .map(String::from)
                        .to_vec()
                }
            };
            let env = match c.get("env") {
                Some(Value::Table(t)) => t
                    .iter()
                    .map(|(k, v)| (k.clone(), v.as_str().expect("env value").to_string()))
                    .collect(),
                _ => Vec::new(),
            };
            let names = strings(c.get("names"));
            assert!(!names.is_empty(), "{name}: names nothing");
            Case {
                class: c["class"].as_str().expect("class").to_string(),
                section: c
                    .get("section")
                    .and_then(Value::as_str)
                    .unwrap_or("cli")
                    .to_string(),
                args,
                env,
                exit: c.get("exit").and_then(Value::as_integer).unwrap_or(2) as i32,
                names,
                absent: strings(c.get("absent")),
                scene,
                setup: c
                    .get("setup")
                    .cloned()
                    .unwrap_or(Value::Table(Default::default())),
                name,
            }
        })
        .collect()
}

/// Files a case needs beside its scene: `dir`, `fifo`, `files` (name → text),
/// `big` (name → bytes of spaces), `garbage` (non-UTF-8), `truncated_hdr`.
fn setup(c: &Case, dir: &Path) {
    let s = &c.setup;
    for d in strings(s.get("dir")) {
        std::fs::create_dir_all(dir.join(d)).unwrap();
    }
    for f in strings(s.get("fifo")) {
        let st = Command::new("mkfifo")
            .arg(dir.join(&f))
            .status()
            .expect("mkfifo");
        assert!(st.success(), "{}: mkfifo", c.name);
    }
    if let Some(Value::Table(files)) = s.get("files") {
        for (k, v) in files {
            std::fs::write(dir.join(k), v.as_str().unwrap()).unwrap();
        }
    }
    if let Some(Value::Table(big)) = s.get("big") {
        for (k, v) in big {
            let n = v.as_integer().unwrap() as usize;
            std::fs::write(dir.join(k), vec![b' '; n]).unwrap();
        }
    }
    for f in strings(s.get("garbage")) {
        std::fs::write(dir.join(f), [0xff, 0xfe, 0x00, 0x80, 0xc3, 0x28, b'\n']).unwrap();
    }
    for f in strings(s.get("truncated_hdr")) {
        // A Radiance header promising 64 × 32 flat RGBE pixels, then 40 bytes of them.
        let mut b = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 32 +X 64\n".to_vec();
        b.extend_from_slice(&[128u8; 40]);
        std::fs::write(dir.join(f), b).unwrap();
    }
}

/// Run a command with a timeout; (exit code, stdout, stderr, wall). A command still
/// running at the timeout is killed and reported as `None`.
fn run_with_timeout(
    mut cmd: Command,
    dir: &Path,
    timeout: Duration,
) -> (Option<i32>, String, String, Duration) {
    let (out_path, err_path) = (dir.join("stdout.txt"), dir.join("stderr.txt"));
    cmd.stdin(Stdio::null())
        .stdout(std::fs::File::create(&out_path).unwrap())
        .stderr(std::fs::File::create(&err_path).unwrap());
    let t0 = Instant::now();
    let mut child = cmd.spawn().expect("spawn the binary");
    let code = loop {
        if let Some(st) = child.try_wait().unwrap() {
            break st.code();
        }
        if t0.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let wall = t0.elapsed();
    let read =
        |p: &Path| String::from_utf8_lossy(&std::fs::read(p).unwrap_or_default()).into_owned();
    (code, read(&out_path), read(&err_path), wall)
}

fn run_case(c: &Case, root: &Path) -> Result<Duration, String> {
    let dir = root.join(&c.name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    setup(c, &dir);
    let scene_path = dir.join("scene.toml");
    if let Some(text) = &c.scene {
        std::fs::write(&scene_path, text).unwrap();
    }
    let fill = |a: &str| {
        a.replace("{scene}", &scene_path.to_string_lossy())
            .replace("{tmp}", &dir.to_string_lossy())
    };
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_glare-pipeline"));
    cmd.current_dir(&dir).args(c.args.iter().map(|a| fill(a)));
    for (k, v) in &c.env {
        cmd.env(k, fill(v));
    }
    let (code, _out, err, wall) = run_with_timeout(cmd, &dir, CASE_TIMEOUT);
    let fail = |why: String| {
        Err(format!(
            "{} ({}): {why}\n  stderr: {}",
            c.name,
            c.class,
            err.trim()
        ))
    };
    match code {
        None => return fail(format!("still running after {CASE_TIMEOUT:?}: killed")),
        Some(x) if x != c.exit => return fail(format!("exit status {x}, expected {}", c.exit)),
        _ => {}
    }
    if err.contains("panicked") || err.contains("RUST_BACKTRACE") {
        return fail("panicked".into());
    }
    for n in &c.names {
        if !err.contains(n.as_str()) {
            return fail(format!("the message does not name `{n}`"));
        }
    }
    for n in &c.absent {
        if err.contains(n.as_str()) {
            return fail(format!("the message contains `{n}`, which it must not"));
        }
    }
    // A number is never printed with dozens of digits.
    let longest_digits = err
        .split(|ch: char| !ch.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0);
    if longest_digits > 24 {
        return fail(format!(
            "a number of {longest_digits} digits in the message"
        ));
    }
    let _ = std::fs::remove_dir_all(&dir);
    Ok(wall)
}

#[test]
fn every_bad_input_is_refused_naming_its_field() {
    let cases = load_cases();
    assert!(
        cases.len() >= MIN_CASES,
        "{} cases, at least {MIN_CASES} wanted",
        cases.len()
    );
    for class in CLASSES {
        assert!(
            cases.iter().any(|c| c.class == class),
            "no case of class {class}"
        );
    }
    for section in SECTIONS {
        assert!(
            cases.iter().any(|c| c.section == section),
            "no case for the {section} scene sections"
        );
    }
    let root = std::env::temp_dir().join(format!("bad-inputs-{}", std::process::id()));
    let next = AtomicUsize::new(0);
    let failures = Mutex::new(Vec::new());
    let slowest = Mutex::new((Duration::ZERO, String::new()));
    std::thread::scope(|s| {
        for _ in 0..4 {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                let Some(c) = cases.get(i) else { break };
                match run_case(c, &root) {
                    Ok(wall) => {
                        let mut sl = slowest.lock().unwrap();
                        if wall > sl.0 {
                            *sl = (wall, c.name.clone());
                        }
                    }
                    Err(e) => failures.lock().unwrap().push(e),
                }
            });
        }
    });
    let _ = std::fs::remove_dir_all(&root);
    let failures = failures.into_inner().unwrap();
    let (wall, name) = slowest.into_inner().unwrap();
    println!(
        "{} cases, {} failed; slowest {name} {:.2} s",
        cases.len(),
        failures.len(),
        wall.as_secs_f64()
    );
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

/// docs/inputs.md quotes the corpus size ("`tests/bad_inputs/cases.toml` holds N
/// cases"); the figure must be the corpus's own count, so a case added or removed
/// without the doc fails here (it said 249 when the file held 279).
#[test]
fn docs_inputs_quotes_the_corpus_size() {
    let doc = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/inputs.md"))
        .expect("docs/inputs.md");
    // The sentence with a number ("… holds the user-level cases" is another).
    let lead = "`tests/bad_inputs/cases.toml` holds ";
    let quoted: usize = doc
        .match_indices(lead)
        .find_map(|(at, _)| {
            let rest = &doc[at + lead.len()..];
            rest.split_whitespace().next()?.parse().ok()
        })
        .expect("docs/inputs.md quotes the corpus size after its name");
    assert_eq!(
        quoted,
        load_cases().len(),
        "docs/inputs.md quotes {quoted} cases; cases.toml holds the other number"
    );
}

// ---------------------------------------------------------------------------------
// The memory budget: refused fast and small.

/// `struct rusage` of Linux (x86_64 and aarch64 alike: two timevals, then 14 longs,
/// of which `ru_maxrss`, in KiB, is the first).
#[cfg(target_os = "linux")]
#[repr(C)]
#[derive(Default)]
struct Rusage {
    utime: [i64; 2],
    stime: [i64; 2],
    maxrss: i64,
    rest: [i64; 13],
}

#[cfg(target_os = "linux")]
extern "C" {
    fn wait4(pid: i32, status: *mut i32, options: i32, rusage: *mut Rusage) -> i32;
}

/// Run the binary; (exit code, the child's own CPU time (user + system), its peak RSS
/// in bytes, stderr), measured by wait4 on that child alone. Killed after 60 s of wall
/// time (then code `None`).
#[cfg(target_os = "linux")]
// The child is reaped by wait4 (which clippy does not know), or killed and waited.
#[allow(clippy::zombie_processes)]
fn run_measured(args: &[&str], dir: &Path) -> (Option<i32>, Duration, u64, String) {
    const WNOHANG: i32 = 1;
    let err_path = dir.join("stderr.txt");
    let t0 = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&err_path).unwrap())
        .spawn()
        .unwrap();
    let pid = child.id() as i32;
    let mut status = 0i32;
    let mut ru = Rusage::default();
    let code = loop {
        // SAFETY: wait4 on our own child with valid pointers to locals.
        let r = unsafe { wait4(pid, &mut status, WNOHANG, &mut ru) };
        if r == pid {
            // WIFEXITED: low 7 bits zero; the code is the next byte.
            break ((status & 0x7f) == 0).then_some((status >> 8) & 0xff);
        }
        assert!(r == 0, "wait4 failed");
        if t0.elapsed() > CASE_TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return (None, t0.elapsed(), 0, String::new());
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let cpu =
        |tv: [i64; 2]| Duration::from_secs(tv[0] as u64) + Duration::from_micros(tv[1] as u64);
    let err = std::fs::read_to_string(&err_path).unwrap_or_default();
    (
        code,
        cpu(ru.utime) + cpu(ru.stime),
        ru.maxrss as u64 * 1024,
        err,
    )
}

/// A scene whose light maps alone need ~800 GB (4000 spots × 4096² texels) is refused
/// under the default budget (half of MemAvailable), and a small scene and a sweep whose
/// largest point is too large under an explicit `--max-memory`: each in under 1 s of its
/// own CPU time with a peak RSS under 200 MB (both generous: the refusal takes
/// milliseconds and ~10 MB; CPU time, unlike wall time, does not grow when other
/// processes load the machine), and the message lists what is large and the field to
/// shrink.
#[cfg(target_os = "linux")]
#[test]
fn a_scene_over_the_memory_budget_is_refused_before_allocating() {
    let dir = std::env::temp_dir().join(format!("budget-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut text = String::from(
        "[image]\nwidth = 64\nheight = 48\n[camera]\neye = [0.0, 3.0, 13.0]\nlook_at = [0.0, 3.0, 0.0]\n\
         [shafts]\nlight_map_texels = 4096\nshadow_resolution = 4096\n",
    );
    for i in 0..4000 {
        text.push_str(&format!(
            "[[lights]]\nposition = [{}.0, 9.5, 0.0]\ndirection = [0.0, -1.0, 0.0]\n",
            i % 50
        ));
    }
    let huge = dir.join("huge.toml");
    std::fs::write(&huge, text).unwrap();
    let out = dir.join("out.png");
    let (huge_s, out_s) = (huge.to_string_lossy(), out.to_string_lossy());
    let one_light = glare_pipeline::scene::builtin::builtin_toml("fig6")
        .unwrap()
        .replace("light_map_texels = 256", "light_map_texels = 4096");
    let small = dir.join("fig6-4096.toml");
    std::fs::write(&small, one_light).unwrap();
    let small_s = small.to_string_lossy();
    let sweep_dir = dir.join("sweep");
    let sweep_s = sweep_dir.to_string_lossy();
    let runs: [(&str, Vec<&str>); 3] = [
        // A sweep: its largest point (the last value) is checked before the first
        // runs; nothing is written, not even the output directory.
        (
            "sweep fig6 light_map_texels 64,4096, --max-memory 64M",
            vec![
                "sweep",
                "--scene",
                "fig6",
                "--param",
                "light_map_texels",
                "--values",
                "64,4096",
                "--out",
                &sweep_s,
                "--max-memory",
                "64M",
            ],
        ),
        (
            "4000 lights, default budget",
            vec!["render", "--scene", &huge_s, "--out", &out_s],
        ),
        (
            "fig6 with 4096² light map, --max-memory 64M",
            vec![
                "render",
                "--scene",
                &small_s,
                "--out",
                &out_s,
                "--max-memory",
                "64M",
            ],
        ),
    ];
    for (what, args) in &runs {
        let (code, cpu, rss, err) = run_measured(args, &dir);
        println!(
            "{what}: exit {code:?}, {:.3} s of CPU, peak RSS {:.1} MB",
            cpu.as_secs_f64(),
            rss as f64 / 1e6
        );
        assert_eq!(code, Some(2), "{what}: {err}");
        assert!(err.contains("max-memory"), "{what}: {err}");
        assert!(err.contains("shafts.light_map_texels"), "{what}: {err}");
        assert!(!err.contains("panicked"), "{what}: {err}");
        // Work done, not time taken: refused before the frame's buffers, tables or
        // maps were allocated (the smallest of them, fig6's 4096² light map, is 16 MiB;
        // parsing the 4000-light scene peaks near 22 MB). The CPU time is printed.
        assert!(rss < 48_000_000, "{what}: peak RSS {rss} bytes");
        assert!(!out.exists(), "{what}: an image was written");
        assert!(
            !sweep_dir.exists(),
            "{what}: the sweep wrote into its --out"
        );
    }
    // The sweep's refusal names the point that is too large.
    let (_, _, _, err) = run_measured(runs[0].1.as_slice(), &dir);
    assert!(err.contains("light_map_texels = 4096"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A shading scene honours the budget as the other pipelines' scenes do: under a
/// budget smaller than its sphere view's buffers (`frame::budget::shading_estimate`)
/// `render` refuses it naming `--max-memory` and the field that shrinks the view
/// (`shading.image`), and writes nothing; the same scene file under the default
/// budget (and under a budget that holds it) renders and writes its PNG.
#[test]
fn a_shading_scene_honours_the_memory_budget() {
    use glare_pipeline::frame::budget::{shading_estimate, BYTES_PER_PIXEL};
    let bin = env!("CARGO_BIN_EXE_glare-pipeline");
    let dir = std::env::temp_dir().join(format!("budget-shading-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("small.toml");
    std::fs::write(
        &file,
        "[shading]\nscene = \"shading-blinn_phong\"\nimage = 16\n",
    )
    .unwrap();
    let out = dir.join("out.png");
    let need = shading_estimate(Some(16)).total();
    assert_eq!(need, 16 * 16 * BYTES_PER_PIXEL);
    let render = |budget: Option<String>| {
        let mut c = Command::new(bin);
        c.arg("render")
            .arg("--scene")
            .arg(&file)
            .arg("--out")
            .arg(&out);
        if let Some(b) = budget {
            c.args(["--max-memory", &b]);
        }
        c.output().unwrap()
    };
    // One byte short of the view's estimate: refused, nothing written.
    let o = render(Some((need - 1).to_string()));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--max-memory"), "{err}");
    assert!(err.contains("shading.image"), "{err}");
    assert!(err.contains("16 × 16"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.exists(), "a refused render wrote {}", out.display());
    // Exactly the estimate, and the default budget: rendered.
    for budget in [Some(need.to_string()), None] {
        let o = render(budget.clone());
        assert!(
            o.status.success(),
            "budget {budget:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(out.is_file(), "budget {budget:?}: no PNG");
        std::fs::remove_file(&out).unwrap();
    }
    let _ = std::fs::remove_dir_all(&dir);
}
