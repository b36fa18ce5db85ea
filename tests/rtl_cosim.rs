//! Co-simulation: every unit with Verilog (`rtl_model/verilog/units/<unit>.v`) runs
//! the model's vectors under Verilator and Icarus, bit-exact and cycle-exact, at the
//! GeForce default and a narrow configuration (docs/rtl.md).
//!
//! One Verilator build and one Icarus compile hold every unit and configuration (the
//! generated `cosim_top` instantiates each `cosim_<unit>_<config>` block; `+tag=`
//! picks the one that runs), so each simulator builds once per test run; the Verilator
//! build is reused across runs while its sources are unchanged. Vectors: exhaustive
//! where the unit's input word has ≤ 2^20 values, else `RTL_COSIM_COUNT` transactions
//! (default 100 000 under both simulators; a longer run is
//! `RTL_COSIM_COUNT=1000000 cargo test --test rtl_cosim -- --nocapture`).
//! `RTL_COSIM_ONLY=unit[,unit…]` runs only those units' sets (all of them by default),
//! e.g. `RTL_COSIM_ONLY=polygon_interpolator cargo test --test rtl_cosim`.
//!
//! A simulator that is not installed is skipped with a SKIP note on stderr; under
//! `.ci/run` (which installs both and sets `GLARE_REQUIRE_TOOLS`) it fails instead.

#[path = "common/tools.rs"]
mod tools;

use glare_pipeline::registry::rtl::{self, RtlConfig, VectorSet, RTL_UNITS};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

const SEED: u64 = 20;

fn verilog_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("rtl_model/verilog")
}

fn work_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("rtl_cosim")
}

fn count() -> usize {
    std::env::var("RTL_COSIM_COUNT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(100_000)
}

/// The units `RTL_COSIM_ONLY` names (None: every unit).
fn only() -> Option<Vec<String>> {
    std::env::var("RTL_COSIM_ONLY")
        .ok()
        .map(|s| s.split(',').map(|u| u.trim().to_string()).collect())
}

/// Whether `unit`'s sets run.
fn selected(unit: &str) -> bool {
    only().is_none_or(|o| o.iter().any(|u| u == unit))
}

fn have(tool: &str, arg: &str) -> bool {
    Command::new(tool)
        .arg(arg)
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// The Verilog sources every build reads, in order.
fn sources(blocks: &[PathBuf]) -> Vec<PathBuf> {
    let d = verilog_dir();
    let mut v = vec![d.join("tb/tb_vectors.v"), d.join("tb/rtl_rom.v")];
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    v.extend(rtl::verilog_lib_files(root));
    for e in RTL_UNITS {
        v.push(d.join(format!("units/{}.v", e.name)));
    }
    v.extend(blocks.iter().cloned());
    v
}

/// One simulator's vector sets written and its simulation built.
struct Built {
    /// The simulator's name (in messages and scratch file names).
    sim: &'static str,
    /// Where the vector sets are (one subdirectory per tag).
    dir: PathBuf,
    sets: &'static [VectorSet],
    /// Command to run a tag: program and leading arguments.
    run: Vec<String>,
}

/// Every unit's vector sets at both configurations and the Verilog blocks wiring them,
/// written once and read by both simulators (generating them is a good part of the
/// test's time in a debug build).
struct Sets {
    dir: PathBuf,
    sets: Vec<VectorSet>,
    blocks: Vec<PathBuf>,
}

static SETS: OnceLock<Sets> = OnceLock::new();

fn shared_sets() -> &'static Sets {
    SETS.get_or_init(|| {
        let dir = work_dir().join("sets");
        let (sets, blocks) = write_sets(&dir, count());
        Sets { dir, sets, blocks }
    })
}

fn write_sets(dir: &Path, n: usize) -> (Vec<VectorSet>, Vec<PathBuf>) {
    std::fs::create_dir_all(dir).unwrap();
    let mut sets = Vec::new();
    let mut blocks = Vec::new();
    if let Some(o) = only() {
        for u in &o {
            assert!(
                RTL_UNITS.iter().any(|e| e.name == u),
                "RTL_COSIM_ONLY: '{u}' is not a unit with Verilog"
            );
        }
    }
    for e in RTL_UNITS.iter().filter(|e| selected(e.name)) {
        for cfg in RtlConfig::ALL {
            let v = rtl::vectors(e.name, cfg, n, SEED).unwrap();
            let d = dir.join(v.tag());
            v.write(&d).unwrap();
            blocks.push(d.join(format!("cosim_{}.v", v.tag())));
            sets.push(v);
        }
    }
    // shadow_compare's modes beyond the two configurations (compare functions, depth
    // texel formats), each its own set.
    // polygon_interpolator's barycentric mode (weight widths, strict and floor).
    let modes = [
        rtl::shadow_compare_mode_sets(n, SEED).unwrap(),
        rtl::polygon_interpolator_mode_sets(n, SEED).unwrap(),
    ];
    for v in modes.into_iter().flatten().filter(|v| selected(v.unit)) {
        let d = dir.join(v.tag());
        v.write(&d).unwrap();
        blocks.push(d.join(format!("cosim_{}.v", v.tag())));
        sets.push(v);
    }
    // blend's additive datapath (the pipelines' blends), each its own set.
    for v in rtl::blend_mode_sets(n, SEED).unwrap() {
        let d = dir.join(v.tag());
        v.write(&d).unwrap();
        blocks.push(d.join(format!("cosim_{}.v", v.tag())));
        sets.push(v);
    }
    let tags: Vec<String> = sets.iter().map(VectorSet::tag).collect();
    let top = dir.join("cosim_top.v");
    std::fs::write(&top, rtl::cosim_top(&tags)).unwrap();
    blocks.push(top);
    (sets, blocks)
}

fn run_ok(cmd: &mut Command, what: &str) {
    let o = cmd.output().unwrap_or_else(|e| panic!("{what}: {e}"));
    assert!(
        o.status.success(),
        "{what} failed:\n{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

fn build_verilator() -> Option<Built> {
    if !have("verilator", "--version") {
        tools::skip(
            "verilator not found; the Verilator co-simulation did not run \
             (apt-get install verilator g++ make)",
        );
        return None;
    }
    let dir = work_dir().join("verilator");
    std::fs::create_dir_all(&dir).unwrap();
    let shared = shared_sets();
    let srcs = sources(&shared.blocks);
    // Rebuild only when a source changed (the vectors are read at run time).
    let stamp: String = srcs
        .iter()
        .chain(&rtl::verilog_include_files(Path::new(env!(
            "CARGO_MANIFEST_DIR"
        ))))
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    let stamp_file = dir.join("obj/sources.stamp");
    let bin = dir.join("obj/Vcosim_top");
    if !(bin.exists() && std::fs::read_to_string(&stamp_file).ok().as_deref() == Some(&stamp)) {
        let mut c = Command::new("verilator");
        c.args([
            "--binary",
            "--timing",
            "-Wno-fatal",
            "-Wno-lint",
            "-Wno-style",
            "-O1",
            "--top-module",
            "cosim_top",
            "-j",
            "2",
            "-Mdir",
        ])
        .arg(dir.join("obj"))
        .arg(rtl::verilog_include_arg(Path::new(env!(
            "CARGO_MANIFEST_DIR"
        ))))
        .args(&srcs);
        run_ok(&mut c, "verilator build");
        std::fs::write(&stamp_file, &stamp).unwrap();
    }
    Some(Built {
        sim: "verilator",
        dir: shared.dir.clone(),
        sets: &shared.sets,
        run: vec![bin.to_string_lossy().into_owned()],
    })
}

fn build_icarus() -> Option<Built> {
    if !have("iverilog", "-V") {
        tools::skip(
            "iverilog not found; the Icarus co-simulation did not run (apt-get install iverilog)",
        );
        return None;
    }
    let dir = work_dir().join("icarus");
    std::fs::create_dir_all(&dir).unwrap();
    let shared = shared_sets();
    let vvp = dir.join("cosim.vvp");
    let mut c = Command::new("iverilog");
    c.args(["-g2005", "-s", "cosim_top", "-o"])
        .arg(&vvp)
        .arg(rtl::verilog_include_arg(Path::new(env!(
            "CARGO_MANIFEST_DIR"
        ))))
        .args(sources(&shared.blocks));
    run_ok(&mut c, "iverilog compile");
    Some(Built {
        sim: "icarus",
        dir: shared.dir.clone(),
        sets: &shared.sets,
        run: vec![
            "vvp".into(),
            "-n".into(),
            vvp.to_string_lossy().into_owned(),
        ],
    })
}

static VERILATOR: OnceLock<Option<Built>> = OnceLock::new();
static ICARUS: OnceLock<Option<Built>> = OnceLock::new();

/// The summary line's numbers.
#[derive(Debug, PartialEq, Eq)]
struct Summary {
    n: usize,
    checked: usize,
    mismatches: usize,
    valid_errors: usize,
    first_bad: i64,
}

fn simulate(b: &Built, tag: &str, n: usize, expect: &Path) -> Summary {
    let stim = b.dir.join(tag).join("stimulus.hex");
    let o = Command::new(&b.run[0])
        .args(&b.run[1..])
        .arg(format!("+tag={tag}"))
        .arg(format!("+n={n}"))
        .arg(format!("+stim={}", stim.display()))
        .arg(format!("+expect={}", expect.display()))
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    let line = out
        .lines()
        .find(|l| l.starts_with("COSIM ") && l.contains(" n="))
        .unwrap_or_else(|| panic!("{tag}: no summary line in\n{out}"));
    let get = |k: &str| -> i64 {
        line.split_whitespace()
            .find_map(|w| w.strip_prefix(&format!("{k}=")))
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{tag}: no {k} in {line}"))
    };
    Summary {
        n: get("n") as usize,
        checked: get("checked") as usize,
        mismatches: get("mismatches") as usize,
        valid_errors: get("valid_errors") as usize,
        first_bad: get("first_bad"),
    }
}

/// A set's simulation cost, for ordering only: its clocks times the bits of its input
/// and output words (the slowest Icarus sets, reflection_vector's 280 bits a clock,
/// chaos_map's 10^5 transactions at II 7, come first).
fn cost(v: &VectorSet) -> u64 {
    let clocks = (v.stimulus.len() as u64).saturating_mul(v.ii.max(1) as u64);
    clocks.saturating_mul(u64::from(v.in_bits() + v.out_bits()))
}

/// Run every set, two simulations at a time, the costliest first so that no long set
/// starts last and runs alone (the sets are independent; results are printed and
/// checked in set order).
fn check_all(b: &Built) {
    let sim = b.sim;
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results: Vec<std::sync::Mutex<Option<(Summary, f64)>>> =
        b.sets.iter().map(|_| std::sync::Mutex::new(None)).collect();
    let mut order: Vec<usize> = (0..b.sets.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(cost(&b.sets[i])));
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get().min(4));
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(&i) = order.get(k) else { break };
                let v = &b.sets[i];
                let tag = v.tag();
                let t0 = std::time::Instant::now();
                let s = simulate(
                    b,
                    &tag,
                    v.stimulus.len(),
                    &b.dir.join(&tag).join("expected.hex"),
                );
                *results[i].lock().unwrap() = Some((s, t0.elapsed().as_secs_f64()));
            });
        }
    });
    let mut failed = Vec::new();
    for (v, r) in b.sets.iter().zip(results) {
        let tag = v.tag();
        let n = v.stimulus.len();
        let (s, secs) = r.into_inner().unwrap().expect("every set simulated");
        println!(
            "{sim} {tag}: {} transactions ({}), {} mismatches, {} valid errors, {secs:.1} s wall",
            s.checked,
            if v.exhaustive {
                "exhaustive"
            } else {
                "random + corners"
            },
            s.mismatches,
            s.valid_errors
        );
        if s.n != n || s.checked != n || s.mismatches != 0 || s.valid_errors != 0 {
            failed.push(format!("{tag}: {s:?}"));
        }
        assert!(v.exhaustive || n >= count());
    }
    assert!(
        failed.is_empty(),
        "{sim} mismatches:\n{}",
        failed.join("\n")
    );
}

#[test]
fn verilator_runs_every_unit_bit_and_cycle_exact() {
    if let Some(b) = VERILATOR.get_or_init(build_verilator) {
        check_all(b);
    }
}

#[test]
fn icarus_runs_every_unit_bit_and_cycle_exact() {
    if let Some(b) = ICARUS.get_or_init(build_icarus) {
        check_all(b);
    }
}

/// Flip one bit of one expected word: both simulators report exactly that transaction.
fn corrupted_vector_is_caught(b: &Built) {
    if !selected("modulate") {
        eprintln!(
            "SKIP: RTL_COSIM_ONLY leaves out modulate: the corrupted-vector check did not run"
        );
        return;
    }
    let tag = "modulate_default";
    let dir = b.dir.join(tag);
    let text = std::fs::read_to_string(dir.join("expected.hex")).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let k = 12_345;
    let w = u64::from_str_radix(&lines[k], 16).unwrap() ^ 1;
    lines[k] = format!("{w:02x}");
    let bad = dir.join(format!("expected_corrupted_{}.hex", b.sim));
    std::fs::write(&bad, lines.join("\n") + "\n").unwrap();
    let s = simulate(b, tag, lines.len(), &bad);
    assert_eq!(s.mismatches, 1, "{s:?}");
    assert_eq!(s.first_bad, k as i64, "{s:?}");
    assert_eq!(s.valid_errors, 0, "{s:?}");
}

#[test]
fn verilator_catches_a_corrupted_expected_vector() {
    if let Some(b) = VERILATOR.get_or_init(build_verilator) {
        corrupted_vector_is_caught(b);
    }
}

#[test]
fn icarus_catches_a_corrupted_expected_vector() {
    if let Some(b) = ICARUS.get_or_init(build_icarus) {
        corrupted_vector_is_caught(b);
    }
}

#[test]
fn vectors_are_exhaustive_for_small_input_words_and_seeded_otherwise() {
    // modulate at 8 bits: 2^16 input words, every one written.
    let v = rtl::vectors("modulate", RtlConfig::Default, 5, 1).unwrap();
    assert!(v.exhaustive);
    assert_eq!(v.stimulus.len(), 1 << 16);
    assert_eq!(v.stimulus[0x1234], "1234");
    // round(0x12 * 0x34 / 255) = round(936 / 255) = 4.
    assert_eq!(v.expected[0x1234], "04");
    // glare_combiner at its default: 60 input bits, `count` seeded transactions.
    let a = rtl::vectors("glare_combiner", RtlConfig::Default, 1000, 7).unwrap();
    let b = rtl::vectors("glare_combiner", RtlConfig::Default, 1000, 7).unwrap();
    let c = rtl::vectors("glare_combiner", RtlConfig::Default, 1000, 8).unwrap();
    assert!(!a.exhaustive);
    assert_eq!(a.stimulus.len(), 1000);
    assert_eq!(a.stimulus, b.stimulus);
    assert_ne!(a.stimulus, c.stimulus);
    assert_eq!(a.in_bits(), 3 * 8 + 3 * 12);
    assert_eq!(a.stimulus[0].len(), 15);
}

/// The barycentric sets drive the mode: triangles of both windings (q2's edge 0 or 2)
/// with and without each top-left bias, and parallelograms (mode off) among them; the
/// strict and floor sets' expected words differ (exact multiples of 2^-w occur).
#[test]
fn barycentric_sets_cover_both_windings_biases_and_strictness() {
    let sets = rtl::polygon_interpolator_mode_sets(20_000, SEED).unwrap();
    assert!(sets.len() >= 8);
    for v in &sets {
        let ctl = v.roms.iter().find(|r| r.name == "bary_ctl").unwrap();
        let seen = |m: u64, want: u64| ctl.words.iter().any(|&w| w & m == want);
        let tag = v.tag();
        assert!(
            seen(0b1100, 0b1000) && seen(0b1100, 0b1100),
            "{tag}: a winding missing"
        );
        assert!(
            seen(0b1001, 0b1000) && seen(0b1001, 0b1001),
            "{tag}: bias0 0/1"
        );
        assert!(
            seen(0b1010, 0b1000) && seen(0b1010, 0b1010),
            "{tag}: bias2 0/1"
        );
        assert!(v.params.contains(&("BARY", 1)), "{tag}");
    }
    let by = |t: &str| sets.iter().find(|v| v.tag() == t).unwrap();
    let strict = by("polygon_interpolator_narrow_bary_w1_strict");
    let cfg = rtl_model::units::polygon_interpolator::Barycentric {
        weight_bits: 1,
        strict: false,
    };
    assert!(strict.params.contains(&("STRICT", 1)));
    // The same primitives with the floor: some outputs move.
    let floor =
        rtl::polygon_interpolator_mode_vectors(cfg, RtlConfig::Narrow, 20_000, SEED).unwrap();
    assert!(floor.params.contains(&("STRICT", 0)));
    assert_eq!(floor.stimulus.len(), strict.stimulus.len());
    assert_ne!(floor.expected, strict.expected);
}

#[test]
fn vector_errors_name_the_argument() {
    let e = rtl::vectors("modulate", RtlConfig::Default, 0, 1).unwrap_err();
    assert!(e.starts_with("count:"), "{e}");
    let e = rtl::vectors("no_such_unit", RtlConfig::Default, 10, 1).unwrap_err();
    assert!(e.starts_with("unit:"), "{e}");
    let e = RtlConfig::parse("wide").unwrap_err();
    assert!(e.starts_with("config:"), "{e}");
}

#[test]
fn pack_hex_puts_the_first_field_in_the_top_bits() {
    use rtl_model::Signal;
    let s = [
        Signal::new("a", 3, 0b101),
        Signal::new("b", 70, (1 << 63) | 1),
        Signal::new("c", 1, 1),
    ];
    // 74 bits → 19 digits: 101 · 0…(6 zeros) 1 (bit 63) 0…0 1 · 1.
    let want = (0b101u128 << 71) | (((1u128 << 63) | 1) << 1) | 1;
    assert_eq!(rtl::pack_hex(&s), format!("{want:019x}"));
}

#[test]
fn trace_vectors_cli_writes_the_files_and_names_bad_arguments() {
    let exe = env!("CARGO_BIN_EXE_glare-pipeline");
    let dir = work_dir().join("cli");
    let _ = std::fs::remove_dir_all(&dir);
    let o = Command::new(exe)
        .args(["trace", "glare_combiner", "--vectors"])
        .arg(&dir)
        .args(["--count", "300", "--seed", "5"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stim = std::fs::read_to_string(dir.join("stimulus.hex")).unwrap();
    let exp = std::fs::read_to_string(dir.join("expected.hex")).unwrap();
    assert_eq!(stim.lines().count(), 300);
    assert_eq!(exp.lines().count(), 300);
    let want = rtl::vectors("glare_combiner", RtlConfig::Default, 300, 5).unwrap();
    assert_eq!(stim.lines().collect::<Vec<_>>(), want.stimulus);
    let header = std::fs::read_to_string(dir.join("header.txt")).unwrap();
    assert!(header.contains("latency 1\n"), "{header}");
    assert!(dir.join("cosim_glare_combiner_default.v").exists());
    for (args, field) in [
        (vec!["--config", "wide"], "config:"),
        (vec!["--count", "0"], "count:"),
    ] {
        let o = Command::new(exe)
            .args(["trace", "modulate", "--vectors"])
            .arg(&dir)
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            !o.status.success() && err.contains(field),
            "{args:?}: {err}"
        );
    }
    let o = Command::new(exe)
        .args(["trace", "polygon_variable_generator", "--vectors"])
        .arg(&dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("unit:"), "{err}");
}

/// Cycle-exactness is checked, not just values: the same modulate vectors with the
/// testbench told a latency one clock longer than the Verilog's. The unit's first
/// output then arrives on a clock where none is expected, and its last is missing on
/// the clock the testbench expects it: two valid errors (Icarus: a one-block compile
/// is quick).
#[test]
fn icarus_catches_a_wrong_latency() {
    if !have("iverilog", "-V") {
        tools::skip(
            "iverilog not found; the wrong-latency check did not run (apt-get install iverilog)",
        );
        return;
    }
    let root = work_dir().join("wrong_latency");
    let mut v = rtl::vectors("modulate", RtlConfig::Narrow, 1, SEED).unwrap();
    v.latency += 1;
    let dir = root.join(v.tag());
    v.write(&dir).unwrap();
    let top = root.join("cosim_top.v");
    std::fs::write(&top, rtl::cosim_top(&[v.tag()])).unwrap();
    let d = verilog_dir();
    let vvp = root.join("cosim.vvp");
    run_ok(
        Command::new("iverilog")
            .args(["-g2005", "-s", "cosim_top", "-o"])
            .arg(&vvp)
            .arg(d.join("tb/tb_vectors.v"))
            .arg(d.join("units/modulate.v"))
            .arg(dir.join(format!("cosim_{}.v", v.tag())))
            .arg(&top),
        "iverilog compile",
    );
    let b = Built {
        sim: "icarus",
        dir: root.clone(),
        sets: &[],
        run: vec![
            "vvp".into(),
            "-n".into(),
            vvp.to_string_lossy().into_owned(),
        ],
    };
    let n = v.stimulus.len();
    let s = simulate(&b, &v.tag(), n, &dir.join("expected.hex"));
    assert_eq!(s.checked, n, "{s:?}");
    assert_eq!(s.valid_errors, 2, "{s:?}");
    // Every other output is compared against its predecessor's expected word.
    assert!(s.mismatches > 0, "{s:?}");
}

/// Flip `mask` in the hex digit `digit` (0: the least significant) of line `k` of
/// `file`.
fn flip_hex_digit(file: &Path, k: usize, digit: usize, mask: u32) {
    let text = std::fs::read_to_string(file).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut chars: Vec<char> = lines[k].chars().collect();
    let i = chars.len() - 1 - digit;
    let d = chars[i].to_digit(16).unwrap() ^ mask;
    chars[i] = char::from_digit(d, 16).unwrap();
    lines[k] = chars.into_iter().collect();
    std::fs::write(file, lines.join("\n") + "\n").unwrap();
}

/// The in-memory Verilator harness of `units --rtl-speed` (rtl_model/verilog/tb/
/// tb_memory.cpp, one build per unit): on a narrow word (modulate, 8 bits in, 4 out)
/// and on words wider than 64 bits (cube_map_address, 72 bits in, 100 out, Verilator's
/// `VlWide`, with a ROM) it checks every word with 0 mismatches and times its loop;
/// the same binary told a latency one clock longer reports two valid errors, and an
/// expected word with one bit flipped (the wide one in its top 32-bit word) is caught
/// at that transaction and fails the run.
#[test]
fn verilator_in_memory_harness_is_exact_timed_and_catches_a_corrupted_word() {
    use glare_pipeline::registry::rtl::speed;
    if !have("verilator", "--version") {
        tools::skip(
            "verilator not found; the in-memory harness test did not run \
             (apt-get install verilator g++ make)",
        );
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = work_dir().join("memory");
    let _ = std::fs::remove_dir_all(&dir);
    // (unit, config, transactions, corrupted transaction, hex digit, bit mask)
    let cases = [
        ("modulate", RtlConfig::Narrow, 20_000, 12_345, 0, 1),
        ("cube_map_address", RtlConfig::Default, 5_000, 4_321, 24, 1),
    ];
    for (unit, config, count, k, digit, mask) in cases {
        let v = speed::repeat_to(rtl::vectors(unit, config, count, SEED).unwrap(), count);
        assert_eq!(v.stimulus.len(), count, "{unit}");
        let bin = speed::build_memory_harness(root, &dir, &v).unwrap();
        let r = speed::run_memory_harness(&bin, &dir, &v, 2).unwrap();
        eprintln!(
            "{}: {r:?}, {:.3e} transactions/s",
            v.tag(),
            count as f64 / r.secs
        );
        assert!(r.clean(), "{r:?}");
        assert_eq!((r.n, r.checked), (count as u64, count as u64), "{r:?}");
        let cycles = (count as u64 - 1) * u64::from(v.ii) + u64::from(v.latency) + 3;
        assert_eq!(r.cycles, cycles, "{r:?}");
        assert!(r.secs > 0.0 && r.secs < 60.0, "{r:?}");

        // The latency is checked, not only the words.
        let mut late = v.clone();
        late.latency += 1;
        let r = speed::run_memory_harness(&bin, &dir, &late, 1).unwrap();
        assert_eq!(r.valid_errors, 2, "{r:?}");
        assert!(!r.clean(), "{r:?}");

        let expected = dir.join(v.tag()).join("expected.hex");
        flip_hex_digit(&expected, k, digit, mask);
        let r = speed::run_memory_harness(&bin, &dir, &v, 1).unwrap();
        assert_eq!(r.mismatches, 1, "{r:?}");
        assert_eq!(r.first_bad, Some(k as u64), "{r:?}");
        assert_eq!(r.valid_errors, 0, "{r:?}");
        assert!(!r.clean(), "{r:?}");
    }
}
