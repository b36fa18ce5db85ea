//! The speed table (`units --rtl-speed`, docs/rtl.md): for every unit with Verilog,
//! on the same vectors at the same configuration in the same run, the model's
//! simulated pixels per second (its batch kernel, `Unit::kernel_batch`) beside
//! Verilator's clock cycles and transactions per second (the generic vector
//! testbench, `tb_vectors.v`, one `--binary` build holding every unit).

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
    /// model pixels/s ÷ Verilator transactions/s.
    pub model_over_verilator: Option<f64>,
}

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
