//! `render --timing` and `--chip` through the frame: the default request is today's
//! frame (same pixels, same roofline times, no clocked timing); a chip picks the GPU
//! the roofline times; what the clocked chip cannot time is refused up front, naming
//! the flag and what is supported.

use glare_pipeline::frame::plan::plan;
use glare_pipeline::frame::run::{render, render_timed, Gpu};
use glare_pipeline::frame::timing::{check, ChipName, TimingMode, TimingRequest};
use glare_pipeline::scene::builtin::builtin;
use glare_pipeline::scene::format::Scene;

fn small(name: &str) -> Scene {
    let mut s = builtin(name).unwrap();
    s.image.width = 64;
    s.image.height = 48;
    s.shafts.planes = 3;
    s.shafts.subplanes = 2;
    s.shafts.shadow_resolution = 64;
    s
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
