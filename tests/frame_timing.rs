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

/// A pool of `n` threads (to check that a frame's timing does not depend on them).
fn pool(n: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .unwrap()
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
    // A glare scene's one pass is clocked on the glare ASIC; a frame of GPU passes and
    // a glare pass (two chips) is refused, and so is a glare scene on a GPU.
    let glare = plan(&builtin("glare-point").unwrap()).unwrap();
    let both = plan(&builtin("street-light").unwrap()).unwrap();
    assert!(check(&TimingRequest::default(), &glare).is_ok());
    for mode in [TimingMode::Clocked, TimingMode::Sampled] {
        let req = |chip| TimingRequest {
            mode,
            chip,
            window: None,
        };
        assert!(check(&req(None), &glare).is_ok());
        assert!(check(&req(Some(ChipName::GlareAsic)), &glare).is_ok());
        let e = check(&req(Some(ChipName::GeForce3)), &glare).unwrap_err();
        assert!(
            e.contains("--chip geforce3") && e.contains("glare-asic"),
            "{e}"
        );
        let e = check(&req(None), &both).unwrap_err();
        assert!(e.contains(&format!("--timing {}", mode.name())), "{e}");
        assert!(e.contains("glare ASIC") && e.contains("roofline"), "{e}");
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
    let one = pool(1).install(|| timed(TimingMode::Clocked));
    let two = pool(2).install(|| timed(TimingMode::Clocked));
    assert_eq!(one.timing, two.timing, "same cycles on 1 and 2 threads");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The sampled mode's passes: of each kind, passes 0 and 1 and then one in `every`.
#[test]
fn the_sampled_mode_records_the_first_two_passes_of_a_kind_and_one_in_every() {
    use glare_pipeline::chip::work::PassSample;
    let picked = |every| {
        (0..20)
            .filter(|&n| PassSample { every }.records(n))
            .collect::<Vec<_>>()
    };
    assert_eq!(picked(8), vec![0, 1, 8, 16]);
    assert_eq!(picked(3), vec![0, 1, 3, 6, 9, 12, 15, 18]);
    assert_eq!(picked(1), (0..20).collect::<Vec<_>>());
    assert_eq!(picked(0), (0..20).collect::<Vec<_>>());
}

/// The ratio estimate over a kind's passes, by hand: R = Σc / Σx, the variance
/// N²(1 − n/N)/n · Σ(c − R·x)²/(n − 1) plus the recorded passes' own, carried by
/// X / Σx.
#[test]
fn a_kind_of_pass_is_estimated_by_its_ratio_to_the_roofline() {
    use glare_pipeline::frame::strata::kind_estimate;
    // Proportional passes: exact, no spread.
    let e = kind_estimate(&[(100.0, 1.0, 0.0), (200.0, 2.0, 0.0)], &[3.0]);
    assert_eq!(e.clocks_per_proxy, 100.0);
    assert_eq!(e.variance, 0.0);
    // R = 600 / 5 = 120; residuals −20, 60, −40: s² = 5600 / 2 = 2800; N = 4, n = 3:
    // 16 · (1/4) / 3 · 2800 = 3733.3…; own variances 9 each, carried by (5 + 3) / 5.
    let rec = [(100.0, 1.0, 9.0), (300.0, 2.0, 9.0), (200.0, 2.0, 9.0)];
    let e = kind_estimate(&rec, &[3.0]);
    assert_eq!(e.clocks_per_proxy, 120.0);
    let want = 16.0 * 0.25 / 3.0 * 2800.0 + 8.0 / 5.0 * 27.0;
    assert!((e.variance - want).abs() < 1e-9, "{} vs {want}", e.variance);
    // Every pass recorded: only their own variances.
    let e = kind_estimate(&rec, &[]);
    assert!((e.variance - 27.0).abs() < 1e-12, "{}", e.variance);
    // One recorded, one not: the spread is unknown, the unrecorded part ± 100 %.
    let e = kind_estimate(&[(100.0, 1.0, 0.0)], &[2.0]);
    assert_eq!(e.variance, 200.0 * 200.0);
}

/// Sampled timing on a frame large enough to sample (96 × 64: 8 bands, one in 2
/// clocked; 12 planes of 3 sub-planes: 12 of a kind, passes 0, 1, 8 clocked): the same
/// pixels; every pass not clocked is scaled from an earlier clocked pass of its kind;
/// the frame's cycles near the full count; the same timing on 1 and 2 threads.
#[test]
fn sampled_timing_clocks_some_passes_of_each_kind_and_scales_the_rest() {
    use glare_pipeline::chip::config::ChipConfig;
    let mut s = small("fig6");
    s.image.width = 96;
    s.image.height = 64;
    s.shafts.planes = 12;
    s.shafts.subplanes = 3;
    let base = render(&s).unwrap();
    let timed = |mode| {
        let req = TimingRequest {
            mode,
            chip: None,
            window: None,
        };
        render_timed(&s, &req, Some(ChipConfig::geforce2_gts()), None)
            .unwrap()
            .0
    };
    let sampled = timed(TimingMode::Sampled);
    let clocked = timed(TimingMode::Clocked);
    assert_eq!(sampled.fb, base.fb, "the sample changes no pixel");
    let st = sampled.timing.as_ref().unwrap();
    let ct = clocked.timing.as_ref().unwrap();
    assert_eq!(st.passes.len(), ct.passes.len());
    assert_eq!(
        (st.sample_band_every, st.sample_pass_every),
        (Some(2), Some(8))
    );
    assert_eq!((ct.sample_band_every, ct.sample_pass_every), (None, None));
    // 3 single passes, then per plane 3 sub-planes, a copy and the plane: the kinds
    // are sub-planes (36), copies (12) and planes (12).
    let kind = |i: usize| {
        if i < 3 {
            i
        } else {
            3 + (i - 3) % 5 / 3 + (i - 3) % 5 / 4
        }
    };
    let mut scaled = 0;
    for (i, p) in st.passes.iter().enumerate() {
        assert!(p.timing.cycles > 0, "pass {i}");
        assert!(ct.passes[i].scaled_from.is_none());
        if let Some(k) = p.scaled_from {
            scaled += 1;
            assert!(k < i && st.passes[k].scaled_from.is_none(), "{i} from {k}");
            assert_eq!(kind(k), kind(i), "{i} from {k}");
            assert_eq!(p.timing.stages.len(), st.passes[k].timing.stages.len());
        }
    }
    // Clocked: sub-planes 0, 1, 8, 16, 24, 32; copies and planes 0, 1, 8; the rest
    // scaled.
    assert_eq!(scaled, (36 - 6) + 2 * (12 - 3));
    let (a, b) = (st.cycles_total() as f64, ct.cycles_total() as f64);
    let stated = st.sampling_error.expect("a sampled frame states its error");
    assert!(stated > 0.0 && stated < 0.1, "{stated}");
    assert!(
        (a - b).abs() / b <= 3.0 * stated + 0.03,
        "sampled {a} against clocked {b} (stated ± {stated})"
    );
    let one = pool(1).install(|| timed(TimingMode::Sampled));
    assert_eq!(
        one.timing.as_ref(),
        Some(st),
        "same sampled timing on 1 and 2 threads"
    );
}

/// A glare scene's clocked frame: its glare pass and the host's table writes on the
/// glare ASIC at the scene's widths, the same cycles `reproduce glare-asic-throughput`
/// clocks (`glare_frame_timing`), the same pixels as the roofline frame; sampled, one
/// band in 8 of the pass, within its stated error of them.
#[test]
fn a_glare_scene_is_clocked_on_the_glare_asic() {
    use glare_pipeline::pipeline::glare::clocked::{glare_chip, glare_frame_timing};
    let mut s = builtin("glare-flare").unwrap();
    s.image.width = 180;
    s.image.height = 120;
    let chip = glare_chip(&s).unwrap();
    let want = glare_frame_timing(&s, &chip).unwrap();
    let base = render(&s).unwrap();
    for mode in [TimingMode::Clocked, TimingMode::Sampled] {
        let req = TimingRequest {
            mode,
            chip: None,
            window: None,
        };
        let (f, _) = render_timed(&s, &req, Some(chip.clone()), None).unwrap();
        assert_eq!(f.fb, base.fb, "{}: the clock changes no pixel", mode.name());
        let ft = f.timing.unwrap();
        assert_eq!(ft.chip, "glare-asic");
        let names: Vec<&str> = ft.passes.iter().map(|p| p.pass.as_str()).collect();
        assert_eq!(names, ["glare", "glare RAM tables (host writes)"]);
        if mode == TimingMode::Clocked {
            assert_eq!(ft.passes, want.passes);
        } else {
            let (a, b) = (ft.cycles_total() as f64, want.cycles_total() as f64);
            let e = ft.sampling_error.unwrap();
            assert!((a - b).abs() / b <= 3.0 * e + 0.03, "{a} against {b} ± {e}");
        }
    }
}
