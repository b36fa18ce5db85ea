//! The golden model over DPI-C (docs/rtl.md, section 4): the Rust model, built as a
//! C library (`cargo build -p glare_dpi --features dpi`), is the scoreboard of a
//! SystemVerilog testbench (`rtl_model/verilog/dpi/tb_dpi.sv`) that drives seeded
//! random transactions into each unit's Verilog under Verilator and compares every
//! output on the clock it appears. ≥ 10⁴ transactions per unit and configuration
//! (`RTL_DPI_COUNT`, default 10 000). A second run with the model's output corrupted
//! on one transaction (`GLARE_DPI_CORRUPT=k`, read by the library) must be caught on
//! exactly that transaction.
//!
//! Without `verilator`, `g++` or `make` (Verilator's `--binary` build) the test prints a SKIP note on
//! stderr and passes; under `.ci/run` (`GLARE_REQUIRE_TOOLS`) it fails
//! (`.ci/run` installs them).

#[path = "common/tools.rs"]
mod tools;

use glare_pipeline::registry::rtl::dpi::{write_dpi_blocks, DPI_UNITS};
use glare_pipeline::registry::rtl::RTL_UNITS;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn count() -> usize {
    std::env::var("RTL_DPI_COUNT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10_000)
}

fn have(tool: &str, arg: &str) -> bool {
    Command::new(tool)
        .arg(arg)
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

fn run_ok(cmd: &mut Command, what: &str) -> String {
    let o = cmd.output().unwrap_or_else(|e| panic!("{what}: {e}"));
    assert!(
        o.status.success(),
        "{what} failed:\n{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The C library, built by cargo into this target directory (a no-op when it is up to
/// date), with the features `cargo test --workspace` resolved: a test build of the
/// whole workspace that selects only glare_dpi's `header` test, so its dependencies
/// (serde, fixed, rtl_model, …) are the ones the suite already compiled and only
/// glare_dpi itself builds again, with `dpi` (`cargo build -p glare_dpi --features
/// dpi` resolves features for that package alone and compiled those dependencies a
/// second time: 49 s user on a clean target).
fn build_library() -> PathBuf {
    run_ok(
        Command::new(env!("CARGO"))
            .args([
                "test",
                "-q",
                "--workspace",
                "--no-run",
                "--features",
                "glare_dpi/dpi",
                "--test",
                "header",
            ])
            .current_dir(root()),
        "cargo test --workspace --no-run --features glare_dpi/dpi --test header",
    );
    let target = std::env::var("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| root().join("target"));
    // A test build leaves the library in deps/ (a cdylib's name has no hash there, so
    // a later build of glare_dpi without `dpi` would overwrite it: Verilator's link then
    // fails on the missing DPI symbols, never a silent pass).
    let lib = target.join("debug/deps/libglare_dpi.so");
    assert!(lib.exists(), "{} missing after the build", lib.display());
    lib
}

/// The Verilator simulation of every DPI unit at both configurations (rebuilt when a
/// source changes): the binary.
fn build_sim(dir: &Path, lib: &Path) -> PathBuf {
    let (_, blocks) = write_dpi_blocks(dir).unwrap();
    let v = root().join("rtl_model/verilog");
    let mut srcs = vec![
        v.join("dpi/glare_dpi_pkg.sv"),
        v.join("dpi/tb_dpi.sv"),
        v.join("dpi/dpi_rom.sv"),
        // rtl_ram: a unit's RAM outside it is the same module as in the co-simulation.
        v.join("tb/rtl_rom.v"),
    ];
    srcs.extend(glare_pipeline::registry::rtl::verilog_lib_files(&root()));
    for e in DPI_UNITS {
        srcs.push(v.join(format!("units/{}.v", e.name)));
    }
    srcs.extend(blocks);
    let stamp: String = srcs
        .iter()
        .chain(&glare_pipeline::registry::rtl::verilog_include_files(
            &root(),
        ))
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    let stamp_file = dir.join("obj/sources.stamp");
    let bin = dir.join("obj/Vdpi_top");
    if !(bin.exists() && std::fs::read_to_string(&stamp_file).ok().as_deref() == Some(&stamp)) {
        let libdir = lib.parent().unwrap().display().to_string();
        let mut c = Command::new("verilator");
        c.args([
            "--binary",
            "--timing",
            "-Wno-fatal",
            "-Wno-lint",
            "-Wno-style",
            "-O1",
            "--top-module",
            "dpi_top",
            "-j",
            "2",
            "-LDFLAGS",
        ])
        .arg(format!("-L{libdir} -lglare_dpi -Wl,-rpath,{libdir}"))
        .arg("-Mdir")
        .arg(dir.join("obj"))
        .arg(glare_pipeline::registry::rtl::verilog_include_arg(&root()))
        .args(&srcs);
        run_ok(&mut c, "verilator build");
        std::fs::write(&stamp_file, &stamp).unwrap();
    }
    bin
}

/// The summary line's fields of one run.
fn summary(out: &str, tag: &str) -> std::collections::BTreeMap<String, i64> {
    let line = out
        .lines()
        .find(|l| l.starts_with(&format!("DPI tag={tag} n=")))
        .unwrap_or_else(|| panic!("no summary line for {tag}:\n{out}"));
    line.split_whitespace()
        .filter_map(|kv| kv.split_once('='))
        .filter_map(|(k, v)| v.parse().ok().map(|v| (k.to_string(), v)))
        .collect()
}

#[test]
fn dpi_units_have_verilog() {
    for e in DPI_UNITS {
        assert!(
            RTL_UNITS.iter().any(|r| r.name == e.name),
            "{} has no vector writer",
            e.name
        );
        assert!(!(e.spec)(glare_pipeline::registry::rtl::RtlConfig::Default).is_empty());
    }
    // The three units issue 20 names all have Verilog and a DPI entry.
    for u in ["modulate", "bloom_flare_modulator", "texture_sampler"] {
        assert!(RTL_UNITS.iter().any(|r| r.name == u), "{u}: no Verilog");
        assert!(DPI_UNITS.iter().any(|e| e.name == u), "{u}: no DPI entry");
    }
}

#[test]
fn verilator_runs_the_model_as_scoreboard() {
    if !have("verilator", "--version") || !have("g++", "--version") || !have("make", "--version") {
        tools::skip(
            "verilator, g++ or make not found; the DPI-C testbench did not run \
             (apt-get install verilator g++ make)",
        );
        return;
    }
    let lib = build_library();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("rtl_dpi");
    let bin = build_sim(&dir, &lib);
    let n = count();
    let mut runs = 0;
    for e in DPI_UNITS {
        for c in glare_pipeline::registry::rtl::RtlConfig::ALL {
            let tag = format!("{}_{}", e.name, c.name());
            let out = run_ok(
                Command::new(&bin)
                    .arg(format!("+tag={tag}"))
                    .arg(format!("+n={n}"))
                    .arg("+seed=20")
                    .env_remove("GLARE_DPI_CORRUPT"),
                &tag,
            );
            println!(
                "{}",
                out.lines().find(|l| l.starts_with("DPI")).unwrap_or("")
            );
            let s = summary(&out, &tag);
            assert_eq!(s["n"], n as i64, "{out}");
            assert_eq!(s["checked"], n as i64, "{out}");
            assert_eq!(s["mismatches"], 0, "{out}");
            assert_eq!(s["valid_errors"], 0, "{out}");
            assert_eq!(s["first_bad"], -1, "{out}");
            assert!(!out.contains("error="), "{out}");
            runs += 1;
        }
    }
    assert_eq!(runs, 2 * DPI_UNITS.len());

    // The model's output corrupted on transaction k: caught there, and only there.
    for (tag, k) in [
        ("modulate_default", 4321),
        ("bloom_flare_modulator_narrow", 77),
        ("texture_sampler_default", 999),
    ] {
        let out = run_ok(
            Command::new(&bin)
                .arg(format!("+tag={tag}"))
                .arg(format!("+n={n}"))
                .arg("+seed=20")
                .env("GLARE_DPI_CORRUPT", k.to_string()),
            tag,
        );
        let s = summary(&out, tag);
        assert_eq!(s["mismatches"], 1, "{out}");
        assert_eq!(s["first_bad"], k, "{out}");
        assert_eq!(s["valid_errors"], 0, "{out}");
        assert!(out.contains(&format!("mismatch k={k} ")), "{out}");
    }
}
