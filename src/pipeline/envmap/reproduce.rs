//! `reproduce envmap-table3`: the thesis' Table 3 (voxel error of the accelerated build
//! against the exact one, per threshold th) and Table 4's table sizes and times.
//!
//! For env ∈ {pattern (512 × 256, exposure 1 = its auto exposure), st_fagans_interior
//! (auto exposure)}: the exact map at side s (timed), then for each th in [`THESIS_TH`]
//! the accelerated map and its error against the exact one. Writes
//! `DIR/table3.csv` (`env,th,mean_r,mean_g,mean_b,var_r,var_g,var_b,build_seconds,
//! table_mbytes`: mean |Δ| and variance of Δ in levels over all s³ voxels),
//! `DIR/table3_extra.csv` (entries, empty voxels, and the same errors with each
//! voxel's kept weights renormalised) and `DIR/prefilter_times.csv`.
//! The CLI uses s = 128 (the thesis); the environment variable `ENVMAP_TABLE3_S`
//! overrides it for quick runs.
//!
//! Measured (release, 2 cores shared, s = 128; mean |Δ| (r, g, b) in levels, build s,
//! table MB at 8 bytes per entry):
//!
//! | th | pattern | st_fagans_interior | MB | empty voxels |
//! |---|---|---|---|---|
//! | 0.001 | 0.25 0.27 0.27 | 0.85 0.83 0.79 | 118.7 | 0 |
//! | 0.005 | 1.31 1.33 1.33 | 0.96 0.90 0.83 | 91.0 | 744 |
//! | 0.01 | 2.85 2.85 2.85 | 1.22 1.07 0.91 | 79.1 | 3 696 |
//! | 0.05 | 15.4 15.4 15.4 | 3.58 2.82 1.88 | 51.5 | 50 088 |
//! | 0.1 | 30.7 30.7 30.7 | 6.57 5.07 3.19 | 39.6 | 138 216 |
//! | 0.25 | 70.7 70.7 70.7 | 14.5 11.2 6.85 | 23.6 | 486 048 |
//! | 0.5 | 120 120 120 | 24.4 18.8 11.4 | 11.9 | 1 061 280 |
//!
//! Exact 128³: 7.7 s (pattern), 14.7 s (st_fagans); accelerated 4–9 s per th (the
//! whole build: pyramid, domes, table, filter). The thesis: 73 h exact, 21 h table,
//! 459 → 32.7 MB; its errors fall again at th = 0.25, 0.5 (54 → 34 levels), ours keep
//! growing (empty voxels give F = 0 here; the thesis does not say what it stored).

use super::prefilter::{
    build_accelerated_both, build_exact, env_to_levels, prune_bound, voxel_error,
};
use crate::reference::envmap_prefilter::PrefilterParams;
use crate::scene::envmap::EnvMap;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// The thesis' thresholds (Table 3).
pub const THESIS_TH: [f64; 7] = [0.001, 0.005, 0.01, 0.05, 0.1, 0.25, 0.5];

/// The side used by the CLI: `ENVMAP_TABLE3_S` if set to 1 ..= 512, else 128.
pub fn cli_side() -> Result<u32, String> {
    match std::env::var("ENVMAP_TABLE3_S") {
        Ok(v) => match v.trim().parse::<u32>() {
            Ok(s) if (1..=512).contains(&s) => Ok(s),
            _ => Err(format!("ENVMAP_TABLE3_S: '{v}' is not in 1 ..= 512")),
        },
        Err(_) => Ok(128),
    }
}

/// Run Table 3 at voxel side `s` into `out` (see the module doc).
pub fn table3(out: &Path, s: u32) -> Result<(), String> {
    let e = |x: rtl_model::ConfigError| x.to_string();
    let params = PrefilterParams::thesis();
    let mut t3 =
        String::from("env,th,mean_r,mean_g,mean_b,var_r,var_g,var_b,build_seconds,table_mbytes\n");
    let mut extra = String::from(
        "env,th,entries,entries_per_voxel,empty_voxels,renorm_mean_r,renorm_mean_g,renorm_mean_b,renorm_var_r,renorm_var_g,renorm_var_b\n",
    );
    let mut times = String::from("env,s,exact_seconds,exposure,prune_bound,threads\n");
    for name in ["pattern", "st_fagans_interior"] {
        let env = EnvMap::builtin(name).map_err(e)?;
        let exposure = env.auto_exposure();
        let levels = env_to_levels(&env, exposure).map_err(e)?;
        let t0 = Instant::now();
        let exact = build_exact(&levels, s, &params).map_err(e)?;
        let exact_s = t0.elapsed().as_secs_f64();
        eprintln!("{name}: exact {s}³ in {exact_s:.1} s");
        let _ = writeln!(
            times,
            "{name},{s},{exact_s:.3},{exposure:.6e},{:.3e},{}",
            prune_bound(&levels, params.weighting()),
            rayon::current_num_threads()
        );
        for th in THESIS_TH {
            let (acc, ren, st) = build_accelerated_both(&levels, s, &params, th).map_err(e)?;
            let (mean, var) = voxel_error(&acc, &exact).ok_or("internal: side mismatch")?;
            let (rmean, rvar) = voxel_error(&ren, &exact).ok_or("internal: side mismatch")?;
            eprintln!(
                "{name} th={th}: mean |Δ| {:.3} {:.3} {:.3}, {:.1} s, {:.1} MB, {} empty",
                mean[0],
                mean[1],
                mean[2],
                st.build_seconds,
                st.mbytes(),
                st.empty_voxels
            );
            let _ = writeln!(
                t3,
                "{name},{th},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.3},{:.2}",
                mean[0],
                mean[1],
                mean[2],
                var[0],
                var[1],
                var[2],
                st.build_seconds,
                st.mbytes()
            );
            let _ = writeln!(
                extra,
                "{name},{th},{},{:.2},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4}",
                st.entries,
                st.entries as f64 / (s as f64).powi(3),
                st.empty_voxels,
                rmean[0],
                rmean[1],
                rmean[2],
                rvar[0],
                rvar[1],
                rvar[2]
            );
        }
    }
    crate::cli::write_file(&out.join("table3.csv"), t3.as_bytes())?;
    crate::cli::write_file(&out.join("table3_extra.csv"), extra.as_bytes())?;
    crate::cli::write_file(&out.join("prefilter_times.csv"), times.as_bytes())?;
    print!("{t3}");
    Ok(())
}
