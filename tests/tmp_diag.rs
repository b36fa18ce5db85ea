use glare_pipeline::chip::config::ChipConfig;
use glare_pipeline::frame::run::render_swept;
use glare_pipeline::frame::timing::{TimingMode, TimingRequest};
use glare_pipeline::scene::builtin::builtin;

#[test]
#[ignore]
fn diag() {
    let name = std::env::var("DIAG_SCENE").unwrap_or("fig6".into());
    let s = builtin(&name).unwrap();
    let req = TimingRequest {
        mode: TimingMode::Sampled,
        chip: None,
        window: None,
    };
    let (mut f, _) = render_swept(
        &s,
        &req,
        Some(ChipConfig::geforce2_gts()),
        vec![ChipConfig::geforce2_gts()],
        None,
    )
    .unwrap();
    let st = f.timing.take().unwrap();
    let full = f.swept_timings.remove(0);
    let (mut a, mut b) = (0u64, 0u64);
    for (p, q) in st.passes.iter().zip(&full.passes) {
        let (s, c) = (p.timing.cycles, q.timing.cycles);
        a += s;
        b += c;
        println!(
            "{:40} sampled {:>9} full {:>9} {:+.2} % hit {:?}/{:?} bn {} / {}",
            p.pass,
            s,
            c,
            100.0 * (s as f64 / c as f64 - 1.0),
            p.timing.cache_hit_rate(),
            q.timing.cache_hit_rate(),
            p.timing.bottleneck,
            q.timing.bottleneck
        );
    }
    println!(
        "total sampled {a} full {b} {:+.3} %  stated {:?}",
        100.0 * (a as f64 / b as f64 - 1.0),
        st.sampling_error
    );
}
