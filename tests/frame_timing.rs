//! `render --timing` and `--chip` through the frame: the default request is today's
//! frame (same pixels, same roofline times, no clocked timing); a chip picks the GPU
//! the roofline times; what the clocked chip cannot time is refused up front, naming
//! the flag and what is supported.

use glare_pipeline::frame::gpu::Gpu;
use glare_pipeline::frame::plan::plan;
use glare_pipeline::frame::run::{render, render_timed};
use glare_pipeline::frame::timing::{check, ChipName, TimingMode, TimingRequest};
use glare_pipeline::scene::builtin::builtin;
use glare_pipeline::scene::format::Scene;

mod common;

fn small(name: &str) -> Scene {
    common::small_shafts_scene(name)
}

#[test]
fn the_default_request_is_todays_frame() {
    let s = small("fig6");
    let a = render(&s).unwrap();
    let (b, _) = render_timed(&s, &TimingRequest::default(), None, None).unwrap();
    assert_eq!(a.fb, b.fb);
    assert!(b.timing.is_none());
    assert_eq!(a.gpu, b.gpu);
    let sec = |f: &glare_pipeline::frame::run::Frame| {
        f.times.iter().map(|t| t.seconds).collect::<Vec<_>>()
    };
    assert_eq!(sec(&a), sec(&b));
}

#[test]
fn a_chip_picks_the_gpu_the_roofline_times() {
    let s = small("fig6");
    let gts = render(&s).unwrap();
    let req = TimingRequest {
        mode: TimingMode::Roofline,
        chip: Some(ChipName::GeForce256),
        window: None,
    };
    let (g256, _) = render_timed(&s, &req, None, None).unwrap();
    assert_eq!(g256.gpu, Gpu::GeForce256);
    assert_eq!(gts.fb, g256.fb, "the chip changes the time, not the pixels");
    assert!(g256.predicted_seconds() > gts.predicted_seconds());
    assert!(g256.times.iter().all(|t| t.on == "GeForce 256"));
}

#[test]
fn what_cannot_be_clocked_is_refused_up_front() {
    let fig6 = plan(&small("fig6")).unwrap();
    let clocked = TimingRequest {
        mode: TimingMode::Clocked,
        chip: None,
        window: None,
    };
    assert!(check(&clocked, &fig6).is_ok());
    assert!(check(&TimingRequest::default(), &fig6).is_ok());
    let e = check(
        &TimingRequest {
            mode: TimingMode::Roofline,
            chip: Some(ChipName::GlareAsic),
            window: None,
        },
        &fig6,
    )
    .unwrap_err();
    assert!(
        e.contains("--chip glare-asic") && e.contains("geforce2-gts"),
        "{e}"
    );
    let glare = plan(&builtin("glare-point").unwrap()).unwrap();
    assert!(check(&TimingRequest::default(), &glare).is_ok());
    for mode in [TimingMode::Clocked, TimingMode::Sampled] {
        let e = check(
            &TimingRequest {
                mode,
                chip: None,
                window: None,
            },
            &glare,
        )
        .unwrap_err();
        assert!(e.contains(&format!("--timing {}", mode.name())), "{e}");
        assert!(e.contains("fig6") && e.contains("roofline"), "{e}");
    }
    // Clocked timing needs the chip's clocked configuration.
    assert!(render_timed(&small("fig6"), &clocked, None, None).is_err());
}

/// Clocked and sampled timing end to end on a small fig6: the same pixels as the
/// roofline frame; every pass clocked with cycles, a named bottleneck and a timeline
/// that spans its cycles (the report writes the timeline PNG/CSV, which refuse a
/// timeline that does not, and in clocked mode the VCD); the sampled frame's cycles near the full count;
/// the same cycles on 1 and 2 threads.
#[test]
fn clocked_and_sampled_frames_time_every_pass_and_change_no_pixel() {
    use glare_pipeline::chip::config::ChipConfig;
    use glare_pipeline::report::chip_timing::ChipFiles;
    let s = small("fig6");
    let base = render(&s).unwrap();
    let timed = |mode| {
        let req = TimingRequest {
            mode,
            chip: None,
            window: Some((0, 500)),
        };
        render_timed(&s, &req, Some(ChipConfig::geforce2_gts()), None)
            .unwrap()
            .0
    };
    let dir = std::env::temp_dir().join(format!("frame-timing-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut cycles = Vec::new();
    for mode in [TimingMode::Clocked, TimingMode::Sampled] {
        let f = timed(mode);
        assert_eq!(f.fb, base.fb, "{}: the clock changes no pixel", mode.name());
        let ft = f.timing.as_ref().expect("a clocked frame has its timing");
        assert!(!ft.passes.is_empty());
        for p in &ft.passes {
            assert!(p.timing.cycles > 0, "{}: {}", mode.name(), p.pass);
            assert!(!p.timing.bottleneck.is_empty(), "{}", p.pass);
        }
        let out = dir.join(format!("{}.png", mode.name()));
        let files = ChipFiles::for_render(&out, Some("0..500"), true)
            .unwrap()
            .unwrap();
        let notes = files.write(ft).unwrap();
        assert!(files.timeline_png.is_file() && files.timeline_csv.is_file());
        // Only a fully clocked pass traces its clocks (a sampled one clocks tiles).
        assert_eq!(
            files.vcd.is_file(),
            mode == TimingMode::Clocked,
            "{}: {notes:?}",
            mode.name()
        );
        cycles.push(ft.cycles_total() as f64);
    }
    // 48 rows are 6 bands of 8: too few for one band in each of the sampled mode's 4
    // groups, so the sampled frame is clocked in full (`sample_bands`) and its cycles
    // are the clocked count exactly. (The sample's accuracy on frames large enough to
    // sample is tests/chip_clock.rs's `sampled_mode_on_the_hard_kinds_of_pass`.)
    assert_eq!(
        cycles[1], cycles[0],
        "sampled {} against clocked {}",
        cycles[1], cycles[0]
    );
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let one = pool(1).install(|| timed(TimingMode::Clocked));
    let two = pool(2).install(|| timed(TimingMode::Clocked));
    assert_eq!(one.timing, two.timing, "same cycles on 1 and 2 threads");
    let _ = std::fs::remove_dir_all(&dir);
}
