//! The speed table (`units --rtl-speed`, docs/rtl.md): for every unit with Verilog,
//! on the same vectors at the same configuration in the same run, the model's
//! simulated pixels per second (its batch kernel, `Unit::kernel_batch`) beside
//! Verilator's clock cycles and transactions per second, twice: in the in-memory C++
//! harness (`tb_memory.cpp`, one `--cc --exe` build per unit, vectors loaded before
//! the clock starts, only the clocked loop timed), Verilator's own speed; and in the
//! generic vector testbench (`tb_vectors.v`, one `--binary` build holding every unit,
//! two `$fscanf` per transaction).

use super::vector_set::{RtlConfig, VectorSet};
use super::{cosim_top, RTL_UNITS};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// One unit's row.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SpeedRow {
    pub unit: &'static str,
    pub config: &'static str,
    /// Transactions Verilator runs: `count`, or the set's size for a stateful unit.
    pub transactions: usize,
    /// Distinct transactions in the vector set: fewer than `transactions` where a
    /// stateless unit's exhaustive set is repeated to reach `count` (the model's rate
    /// is over one pass of the set).
    pub set_size: usize,
    /// Model: transactions (pixels) per second of the batch kernel.
    pub model_pixels_per_s: f64,
    /// Clocks the testbench runs: reset, (n − 1)·II + latency, and its tail.
    pub verilator_cycles: u64,
    /// Verilator wall time of the run less that of a one-transaction run (start-up,
    /// file opening), seconds. `None` (and the rates with it) when that difference is
    /// under [`MIN_TIMED_SECS`] (start-up noise; a short set is repeated, see
    /// [`repeat_to`], so only a very small `count` falls under it).
    pub verilator_secs: Option<f64>,
    pub verilator_cycles_per_s: Option<f64>,
    pub verilator_transactions_per_s: Option<f64>,
    /// model pixels/s ÷ Verilator transactions/s (the `$fscanf` testbench's).
    pub model_over_verilator: Option<f64>,
    /// In-memory harness (`tb_memory.cpp`, [`run_memory_harness`]): clocks of its
    /// timed loop, (n − 1)·II + latency + 3.
    pub verilator_memory_cycles: u64,
    /// Seconds of the harness's clocked loop (the fastest of [`MEMORY_PASSES`]); `None`
    /// (and the rates with it) when the clock read no time at all.
    pub verilator_memory_secs: Option<f64>,
    pub verilator_memory_cycles_per_s: Option<f64>,
    pub verilator_memory_transactions_per_s: Option<f64>,
    /// model pixels/s ÷ the in-memory harness's transactions/s.
    pub model_over_verilator_memory: Option<f64>,
    /// Seconds the harness's Verilator build of this unit took (Verilog to binary).
    pub verilator_memory_build_secs: f64,
}

/// Passes of the in-memory harness per unit, each from reset; the fastest is timed.
pub const MEMORY_PASSES: u32 = 3;

fn run(cmd: &mut Command, what: &str) -> Result<String, String> {
    let o = cmd
        .output()
        .map_err(|e| format!("rtl-speed: cannot run {what}: {e}"))?;
    if !o.status.success() {
        return Err(format!(
            "rtl-speed: {what} failed:\n{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    Ok(String::from_utf8_lossy(&o.stdout).into_owned())
}

/// Build the Verilator binary of `sets` under `dir` (sources from `root`).
pub fn build_verilator(root: &Path, dir: &Path, sets: &[VectorSet]) -> Result<PathBuf, String> {
    let v = root.join("rtl_model/verilog");
    let mut srcs = vec![v.join("tb/tb_vectors.v"), v.join("tb/rtl_rom.v")];
    srcs.extend(super::verilog_lib_files(root));
    for e in RTL_UNITS {
        srcs.push(v.join(format!("units/{}.v", e.name)));
    }
    for s in sets {
        let d = dir.join(s.tag());
        s.write(&d)?;
        srcs.push(d.join(format!("cosim_{}.v", s.tag())));
    }
    let tags: Vec<String> = sets.iter().map(VectorSet::tag).collect();
    let top = dir.join("cosim_top.v");
    std::fs::write(&top, cosim_top(&tags)).map_err(|e| format!("rtl-speed: {e}"))?;
    srcs.push(top);
    let mut c = Command::new("verilator");
    c.args([
        "--binary",
        "--timing",
        "-Wno-fatal",
        "-Wno-lint",
        "-Wno-style",
        "-O3",
        "--top-module",
        "cosim_top",
        "-j",
        "2",
        "-Mdir",
    ])
    .arg(dir.join("obj"))
    .arg(super::verilog_include_arg(root))
    .args(&srcs);
    run(
        &mut c,
        "verilator (is it installed? apt-get install verilator g++ make)",
    )?;
    Ok(dir.join("obj/Vcosim_top"))
}

/// Build the in-memory Verilator harness of `set` under `dir/<tag>/` (the set's files,
/// the port module [`VectorSet::memory_top`] in `vlmem_<tag>.v`, the build in
/// `memory_obj/`): `rtl_model/verilog/tb/tb_memory.cpp` over the unit's Verilog,
/// `verilator --cc --exe --build -O3 --x-assign fast --x-initial fast -j 2`, its C++
/// compiled at `OPT_FAST=-O3`. Returns the binary.
pub fn build_memory_harness(root: &Path, dir: &Path, set: &VectorSet) -> Result<PathBuf, String> {
    let v = root.join("rtl_model/verilog");
    let tag = set.tag();
    let d = dir.join(&tag);
    set.write(&d)?;
    let abs = std::fs::canonicalize(&d).map_err(|e| format!("rtl-speed: {e}"))?;
    let top = abs.join(format!("vlmem_{tag}.v"));
    std::fs::write(&top, set.memory_top(&abs)).map_err(|e| format!("rtl-speed: {e}"))?;
    let mut srcs = vec![v.join("tb/rtl_rom.v")];
    srcs.extend(super::verilog_lib_files(root));
    for e in RTL_UNITS {
        srcs.push(v.join(format!("units/{}.v", e.name)));
    }
    srcs.push(top);
    let obj = abs.join("memory_obj");
    let mut c = Command::new("verilator");
    c.args([
        "--cc",
        "--exe",
        "--build",
        "-O3",
        "--x-assign",
        "fast",
        "--x-initial",
        "fast",
        "-Wno-fatal",
        "-Wno-lint",
        "-Wno-style",
        "--prefix",
        "Vtop",
        "--top-module",
    ])
    .arg(format!("vlmem_{tag}"))
    // The C++ of the fast path at -O3 too (Verilator's makefile default is -Os).
    .args(["-MAKEFLAGS", "OPT_FAST=-O3", "-j", "2", "-Mdir"])
    .arg(&obj)
    .arg(super::verilog_include_arg(root))
    .args(&srcs)
    .arg(v.join("tb/tb_memory.cpp"));
    run(
        &mut c,
        "verilator (is it installed? apt-get install verilator g++ make)",
    )?;
    Ok(obj.join("Vtop"))
}

/// The summary of one in-memory harness run ([`run_memory_harness`]).
#[derive(Clone, Debug, PartialEq)]
pub struct MemoryRun {
    pub n: u64,
    /// Clocks of the timed loop: (n − 1)·II + latency + 3 (reset is before it).
    pub cycles: u64,
    /// Expected words compared (n on a complete run).
    pub checked: u64,
    pub mismatches: u64,
    /// Clocks where out_valid was not what the latency says.
    pub valid_errors: u64,
    /// The first transaction that failed, if any.
    pub first_bad: Option<u64>,
    /// Seconds of the clocked loop (the fastest pass): no file I/O, no start-up.
    pub secs: f64,
}

impl MemoryRun {
    /// Every word checked, no mismatch and no valid error.
    pub fn clean(&self) -> bool {
        self.checked == self.n && self.mismatches == 0 && self.valid_errors == 0
    }

    /// Parse the harness's `VLMEM n=… secs=…` line.
    pub fn parse(line: &str) -> Option<MemoryRun> {
        let field = |k: &str| {
            line.split_whitespace()
                .find_map(|t| t.strip_prefix(k)?.strip_prefix('='))
        };
        let int = |k: &str| field(k)?.parse::<u64>().ok();
        let first_bad = field("first_bad")?.parse::<i64>().ok()?;
        Some(MemoryRun {
            n: int("n")?,
            cycles: int("cycles")?,
            checked: int("checked")?,
            mismatches: int("mismatches")?,
            valid_errors: int("valid_errors")?,
            first_bad: u64::try_from(first_bad).ok(),
            secs: field("secs")?.parse().ok()?,
        })
        .filter(|_| line.starts_with("VLMEM "))
    }
}

/// Run the in-memory harness `bin` (from [`build_memory_harness`]) on `set`'s files
/// under `dir/<tag>/`, `passes` times from reset (the fastest loop's time). The
/// summary whatever the outcome (the harness exits 1 on a mismatch); an error only
/// when it prints none.
pub fn run_memory_harness(
    bin: &Path,
    dir: &Path,
    set: &VectorSet,
    passes: u32,
) -> Result<MemoryRun, String> {
    let d = dir.join(set.tag());
    let o = Command::new(bin)
        .arg(format!("stim={}", d.join("stimulus.hex").display()))
        .arg(format!("expect={}", d.join("expected.hex").display()))
        .arg(format!("n={}", set.stimulus.len()))
        .arg(format!("lat={}", set.latency))
        .arg(format!("ii={}", set.ii))
        .arg(format!("in_w={}", set.in_bits()))
        .arg(format!("out_w={}", set.out_bits()))
        .arg(format!("passes={passes}"))
        .output()
        .map_err(|e| format!("rtl-speed: cannot run {}: {e}", bin.display()))?;
    let out = String::from_utf8_lossy(&o.stdout);
    out.lines().find_map(MemoryRun::parse).ok_or_else(|| {
        format!(
            "rtl-speed: {}: the in-memory harness printed no summary:\n{out}{}",
            set.tag(),
            String::from_utf8_lossy(&o.stderr)
        )
    })
}

/// Seconds of one run of `tag` over `n` transactions, and its summary line.
fn time_run(bin: &Path, dir: &Path, tag: &str, n: usize) -> Result<(f64, String), String> {
    let d = dir.join(tag);
    let t = Instant::now();
    let out = run(
        Command::new(bin)
            .arg(format!("+tag={tag}"))
            .arg(format!("+n={n}"))
            .arg(format!("+stim={}", d.join("stimulus.hex").display()))
            .arg(format!("+expect={}", d.join("expected.hex").display())),
        tag,
    )?;
    let secs = t.elapsed().as_secs_f64();
    let line = out
        .lines()
        .find(|l| l.starts_with(&format!("COSIM tag={tag} n=")))
        .ok_or_else(|| format!("rtl-speed: {tag}: no summary line:\n{out}"))?
        .to_string();
    if !line.contains(" mismatches=0 valid_errors=0 ") {
        return Err(format!(
            "rtl-speed: {tag}: the RTL disagrees with the model: {line}"
        ));
    }
    Ok((secs, line))
}

/// The shortest Verilator run (less its start-up) that gets a rate.
pub const MIN_TIMED_SECS: f64 = 0.05;

/// `s` with its transactions repeated in order up to `count`, when it is an
/// exhaustive set of a stateless unit shorter than that (each expected word depends
/// on its own input word only); any other set as it is.
pub fn repeat_to(mut s: VectorSet, count: usize) -> VectorSet {
    let n = s.stimulus.len();
    if s.exhaustive && s.stateless && n > 0 && n < count {
        s.stimulus = s.stimulus.iter().cycle().take(count).cloned().collect();
        s.expected = s.expected.iter().cycle().take(count).cloned().collect();
    }
    s
}

/// The speed table at `config`: `count` transactions per unit (a stateless unit's
/// shorter exhaustive set repeated to `count`, [`repeat_to`]; a stateful unit's set
/// is `count` long already), vectors from `seed`, work files under `dir`.
pub fn rtl_speed(
    root: &Path,
    dir: &Path,
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<Vec<SpeedRow>, String> {
    let mut sets = Vec::new();
    let mut sizes = Vec::new();
    for e in RTL_UNITS {
        let s = super::vectors(e.name, config, count, seed)?;
        sizes.push(s.stimulus.len());
        sets.push(repeat_to(s, count));
    }
    eprintln!(
        "units --rtl-speed: building the Verilator binary of {} units …",
        sets.len()
    );
    let bin = build_verilator(root, dir, &sets)?;
    let mut rows = Vec::new();
    for (s, &set_size) in sets.iter().zip(&sizes) {
        let n = s.stimulus.len();
        let tag = s.tag();
        let (t1, _) = time_run(&bin, dir, &tag, 1)?;
        let (tn, _) = time_run(&bin, dir, &tag, n)?;
        let secs = tn - t1;
        let timed = (secs >= MIN_TIMED_SECS).then_some(secs);
        let cycles = 2 + (n as u64 - 1) * s.ii as u64 + s.latency as u64 + 3;
        let model = set_size as f64 / s.model_batch_secs.max(1e-12);
        let vtx = timed.map(|t| n as f64 / t);
        eprintln!("units --rtl-speed: {tag}: {n} transactions, Verilator {secs:.3} s");
        let started = Instant::now();
        let mem_bin = build_memory_harness(root, dir, s)?;
        let build_secs = started.elapsed().as_secs_f64();
        let m = run_memory_harness(&mem_bin, dir, s, MEMORY_PASSES)?;
        if !m.clean() {
            return Err(format!(
                "rtl-speed: {tag}: the RTL disagrees with the model in the in-memory harness: \
                 {} of {} checked, {} mismatches, {} valid errors, first at transaction {}",
                m.checked,
                m.n,
                m.mismatches,
                m.valid_errors,
                m.first_bad.map_or("-".into(), |k| k.to_string())
            ));
        }
        let mem_timed = (m.secs > 0.0).then_some(m.secs);
        let mtx = mem_timed.map(|t| n as f64 / t);
        eprintln!(
            "units --rtl-speed: {tag}: in memory {:.4} s (build {build_secs:.0} s)",
            m.secs
        );
        rows.push(SpeedRow {
            unit: s.unit,
            config: config.name(),
            transactions: n,
            set_size,
            model_pixels_per_s: model,
            verilator_cycles: cycles,
            verilator_secs: timed,
            verilator_cycles_per_s: timed.map(|t| cycles as f64 / t),
            verilator_transactions_per_s: vtx,
            model_over_verilator: vtx.map(|v| model / v),
            verilator_memory_cycles: m.cycles,
            verilator_memory_secs: mem_timed,
            verilator_memory_cycles_per_s: mem_timed.map(|t| m.cycles as f64 / t),
            verilator_memory_transactions_per_s: mtx,
            model_over_verilator_memory: mtx.map(|v| model / v),
            verilator_memory_build_secs: build_secs,
        });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_stateless_exhaustive_sets_repeat() {
        let d = RtlConfig::Default;
        let s = super::super::vectors("specular_lookup", d, 10, 1).unwrap();
        assert!(s.exhaustive && s.stateless);
        let n = s.stimulus.len();
        let r = repeat_to(s.clone(), 2 * n + 3);
        assert_eq!(r.stimulus.len(), 2 * n + 3);
        assert_eq!(r.expected.len(), 2 * n + 3);
        assert_eq!(r.stimulus[n..2 * n], s.stimulus[..]);
        assert_eq!(r.expected[2 * n..], s.expected[..3]);
        // A set at least `count` long, a stateful unit's, or a seeded one: as it is.
        assert_eq!(repeat_to(s.clone(), n).stimulus.len(), n);
        let sc = super::super::vectors("shadow_compare", RtlConfig::Narrow, 50, 1).unwrap();
        assert!(!sc.stateless);
        let g = super::super::vectors("gaussian_noise", d, 50, 1).unwrap();
        assert!(!g.stateless);
        let mut fake = g.clone();
        fake.exhaustive = true;
        assert_eq!(repeat_to(fake, 500).stimulus.len(), 50);
        let m = super::super::vectors("glare_combiner", d, 50, 1).unwrap();
        assert!(m.stateless && !m.exhaustive);
        assert_eq!(repeat_to(m, 500).stimulus.len(), 50);
    }
}
