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
    let sweep = check_chip_sweep("fig6", small(), (ChipParam::CacheKb, None), "1,4,16").unwrap();
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
    let e = check_chip_sweep("fig6", small(), (ChipParam::CacheLine, None), "32,3")
        .err()
        .unwrap();
    assert!(
        e.contains("--values") && e.contains("cache_line = 3"),
        "{e}"
    );
    assert!(e.contains("chip.texture_cache.line_bytes"), "{e}");
    let e = check_chip_sweep("fig6", small(), (ChipParam::FifoDepth, None), "0")
        .err()
        .unwrap();
    assert!(e.contains("chip.fifo_depth"), "{e}");
    let glare = builtin("glare-point").unwrap();
    let e = check_chip_sweep("glare-point", glare, (ChipParam::CacheKb, None), "4")
        .err()
        .unwrap();
    assert!(e.contains("--param cache_kb"), "{e}");
}

/// A sampled sweep (96 × 64: one band in 2, the first two passes of each kind and one
/// in 8): a row per value with its stated error, each row the frame `render --timing
/// sampled` times on that value's chip, and within its error of the clocked sweep.
#[test]
fn a_sampled_sweep_times_every_value_as_render_samples_it() {
    use glare_pipeline::chip::config::ChipConfig;
    use glare_pipeline::frame::run::render_timed;
    use glare_pipeline::frame::timing::{TimingMode, TimingRequest};
    let mut s = small();
    s.image.width = 96;
    s.image.height = 64;
    s.shafts.planes = 12;
    s.shafts.subplanes = 3;
    let out = std::env::temp_dir().join(format!("chip-sweep-sampled-{}", std::process::id()));
    let run = |mode| {
        let sweep =
            check_chip_sweep("fig6", s.clone(), (ChipParam::FifoDepth, mode), "4,64").unwrap();
        run_chip_sweep(&sweep, &out).unwrap().0
    };
    let sampled = run(Some(TimingMode::Sampled));
    let clocked = run(None);
    for (r, c) in sampled.iter().zip(&clocked) {
        let e = r.sampling_error.expect("a sampled row states its error");
        assert!(e > 0.0 && c.sampling_error.is_none(), "{r:?} {c:?}");
        let off = (r.cycles as f64 - c.cycles as f64).abs() / c.cycles as f64;
        assert!(off <= 3.0 * e + 0.03, "{r:?} against {c:?}");
    }
    // The value the scene's own chip has (64) times as `render --timing sampled` does.
    let req = TimingRequest {
        mode: TimingMode::Sampled,
        chip: None,
        window: None,
    };
    let (f, _) = render_timed(&s, &req, Some(ChipConfig::geforce2_gts()), None).unwrap();
    assert_eq!(ChipConfig::geforce2_gts().fifo_depth, 64);
    assert_eq!(sampled[1].cycles, f.timing.unwrap().cycles_total());
    // A roofline sweep of the chip is refused before any work.
    let e = check_chip_sweep(
        "fig6",
        s.clone(),
        (ChipParam::FifoDepth, Some(TimingMode::Roofline)),
        "4",
    )
    .err()
    .unwrap();
    assert!(
        e.contains("--timing roofline") && e.contains("sampled"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&out);
}
