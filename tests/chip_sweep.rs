//! `sweep --param <architecture parameter>`: one frame, clocked on every value's chip.
//! The rows follow the values, the cache bits follow the cache size, the pixels never
//! depend on the parameter, a value the chip refuses is named before any work.

use glare_pipeline::chip::params::ChipParam;
use glare_pipeline::frame::chip_sweep::{check_chip_sweep, run_chip_sweep};
use glare_pipeline::scene::builtin::builtin;
use glare_pipeline::scene::format::Scene;

mod common;

fn small() -> Scene {
    common::small_shafts_scene("fig6")
}

#[test]
fn a_cache_sweep_clocks_one_frame_on_every_value() {
    let sweep = check_chip_sweep("fig6", small(), ChipParam::CacheKb, "1,4,16").unwrap();
    let out = std::env::temp_dir().join(format!("chip-sweep-{}", std::process::id()));
    let (rows, csv, png) = run_chip_sweep(&sweep, &out).unwrap();
    assert_eq!(rows.iter().map(|r| r.value).collect::<Vec<_>>(), [1, 4, 16]);
    assert!(csv.is_file() && png.is_file());
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().count(), 4, "header and a row per value");
    for w in rows.windows(2) {
        assert_eq!(
            w[1].cache_bits,
            w[0].cache_bits * (w[1].value / w[0].value) as u64
        );
    }
    for r in &rows {
        assert!(r.cycles > 0 && r.clocked_seconds > 0.0, "{r:?}");
        let hit = r.cache_hit_rate.expect("fig6 looks textures up");
        assert!((0.0..=1.0).contains(&hit), "{r:?}");
        assert!(!r.bottleneck.is_empty());
        // The roofline does not see the cache: the same for every value.
        assert_eq!(r.roofline_seconds, rows[0].roofline_seconds);
    }
    // A larger cache never hits less on the same addresses: the presets' LRU caches
    // keep their ways and line and double their sets, and an address that hits in the
    // smaller cache hits in the larger (its set sees a subset of the same accesses).
    assert!(rows[2].cache_hit_rate >= rows[0].cache_hit_rate, "{rows:?}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_value_the_chip_refuses_is_named_before_any_work() {
    let e = check_chip_sweep("fig6", small(), ChipParam::CacheLine, "32,3")
        .err()
        .unwrap();
    assert!(
        e.contains("--values") && e.contains("cache_line = 3"),
        "{e}"
    );
    assert!(e.contains("chip.texture_cache.line_bytes"), "{e}");
    let e = check_chip_sweep("fig6", small(), ChipParam::FifoDepth, "0")
        .err()
        .unwrap();
    assert!(e.contains("chip.fifo_depth"), "{e}");
    let glare = builtin("glare-point").unwrap();
    let e = check_chip_sweep("glare-point", glare, ChipParam::CacheKb, "4")
        .err()
        .unwrap();
    assert!(e.contains("--param cache_kb"), "{e}");
}
