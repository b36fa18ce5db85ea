//! The glare ASIC clocked (`src/pipeline/glare/clocked.rs`, `pipeline::glare::asic_preset`):
//! the recording of the glare pass's work (what it did equals what the units counted,
//! it changes no pixel or counter, it is the same on 1 and 2 threads), the preset's
//! fields against the units' own timing, and — once the clocked chip runs — the
//! sustained rate on the three scenes of `reproduce glare-asic-throughput` between the
//! bounds its walk and its serial set-up put on it.
//!
//! The clocked-rate tests call `crate::chip::clock::clock_pass`; while that is a
//! placeholder returning an error they fail (by design: they are not weakened to pass
//! without the engine).

use glare_pipeline::chip::config::StageKind;
use glare_pipeline::chip::work::{PassKind, PassWork};
use glare_pipeline::pipeline::glare::asic_preset::{
    glare_asic, glare_asic_for, GLARE_TABLE_WORDS_PER_CLOCK,
};
use glare_pipeline::pipeline::glare::clocked::{
    check_chip, glare_chip, glare_frame_timing, record_glare, sustained_pixels_per_second,
    table_cycles, variants, ASIC_SCENES, GLARE_PASS, PAPER_PIXELS_PER_SECOND,
};
use glare_pipeline::pipeline::glare::frame::{
    generator, interpolator, render_glare_over, render_glare_with, GlareFrame,
};
use glare_pipeline::scene::builtin_glare::glare_builtin;
use glare_pipeline::scene::format::Scene;
use glare_pipeline::scene::glare::GlareHw;
use rtl_model::Unit;
use std::collections::BTreeSet;

fn scene(name: &str) -> Scene {
    glare_builtin(name).unwrap_or_else(|| panic!("{name}: no such built-in"))
}

fn recorded(name: &str) -> (Scene, GlareFrame) {
    let s = scene(name);
    let f = record_glare(&s).unwrap_or_else(|e| panic!("{name}: {e}"));
    (s, f)
}

fn work(f: &GlareFrame) -> &PassWork {
    f.work.as_ref().expect("recorded")
}

/// The recorded work is what the units counted: fragments = Σ the primitives' covered
/// fragments = the combiner's inputs = the modulators' inputs; Σ walked = the
/// primitives' walked pixels; colour bytes × fragments = the combiner's counted
/// read-modify-write; every fragment inside the image and, within a primitive,
/// visited once.
#[test]
fn recording_equals_the_counters() {
    for &name in ASIC_SCENES {
        let (s, f) = recorded(name);
        let w = work(&f);
        let frags: u64 = f.prims.iter().map(|p| p.fragments).sum();
        let walked: u64 = f.prims.iter().map(|p| p.walked).sum();
        assert!(frags > 0, "{name}: nothing drawn");
        assert_eq!(w.fragments() as u64, frags, "{name}: fragments");
        let comb = &f.counters["glare_combiner"];
        assert_eq!(comb.pixels_in, frags, "{name}: combiner inputs");
        let modulated: u64 = ["bloom_flare_modulator", "halo_modulator"]
            .iter()
            .filter_map(|u| f.counters.get(*u))
            .map(|c| c.pixels_in)
            .sum();
        assert_eq!(modulated, frags, "{name}: modulator inputs");
        assert_eq!(w.prim_walked.len(), f.prims.len(), "{name}: primitives");
        assert_eq!(w.prim_first_fragment.len(), f.prims.len());
        let rec_walked: u64 = w.prim_walked.iter().map(|&x| x as u64).sum();
        assert_eq!(rec_walked, walked, "{name}: walked");
        assert_eq!(
            f.counters["polygon_interpolator"].pixels_in, walked,
            "{name}: the interpolator stepped over the walked pixels"
        );
        let st = w.stats.as_ref().expect("stats");
        assert_eq!(st.kind, PassKind::Glare);
        assert_eq!((st.fragments, st.walked), (frags, walked));
        assert_eq!(
            w.rop.colour_read_bytes as u64 * frags,
            comb.mem_read_bytes,
            "{name}: colour reads"
        );
        assert_eq!(
            w.rop.colour_write_bytes as u64 * frags,
            comb.mem_write_bytes,
            "{name}: colour writes"
        );
        assert_eq!((w.rop.depth_read_bytes, w.rop.depth_write_bytes), (0, 0));
        assert!(w.textures.is_empty() && w.texels.is_empty());
        assert_eq!((w.width, w.height), (s.image.width, s.image.height));
        for p in 0..f.prims.len() {
            let r = w.prim_fragments(p);
            assert_eq!(r.len() as u64, f.prims[p].fragments, "{name}: prim {p}");
            assert!(r.len() as u64 <= w.prim_walked[p] as u64);
            let mut seen = BTreeSet::new();
            for &[x, y] in &w.frag_xy[r] {
                assert!((x as u32) < w.width && (y as u32) < w.height);
                assert!(
                    seen.insert((x, y)),
                    "{name}: prim {p} visits ({x}, {y}) twice"
                );
            }
        }
    }
}

/// Recording changes no pixel and no counter, and is absent unless asked for.
#[test]
fn recording_changes_nothing() {
    for name in ["glare-flare", "leaves"] {
        let s = scene(name);
        let plain = render_glare_over(&s, None).unwrap();
        let rec = render_glare_with(&s, None, true).unwrap();
        assert!(plain.work.is_none(), "{name}: recorded unasked");
        assert!(rec.work.is_some());
        assert_eq!(plain.fb.data, rec.fb.data, "{name}: pixels");
        assert_eq!(plain.counters, rec.counters, "{name}: counters");
        assert_eq!(plain.prims, rec.prims, "{name}: primitives");
    }
}

/// The work does not depend on the picture beneath the glare: the same over the
/// scene's own background and over black (which is what `record_glare` draws over).
#[test]
fn work_does_not_depend_on_the_background() {
    let s = scene("leaves");
    let own = render_glare_with(&s, None, true).unwrap();
    let black = record_glare(&s).unwrap();
    let j = |f: &GlareFrame| serde_json::to_string(work(f)).unwrap();
    assert_eq!(j(&own), j(&black));
}

/// Same work on 1 and 2 threads (the flare lines walk beside the areas).
#[test]
fn recording_is_deterministic_across_threads() {
    for name in ["glare-flare", "leaves"] {
        let s = scene(name);
        let at = |n: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap();
            pool.install(|| serde_json::to_string(work(&record_glare(&s).unwrap())).unwrap())
        };
        let one = at(1);
        assert_eq!(one, at(2), "{name}");
        assert_eq!(one, at(2), "{name}: again");
    }
}

/// The preset's fields: the paper's 4 pipes × 300 MHz = 1.2 Gpixel/s, no texture
/// units, no cache, and every stage's latency and II, the set-up clocks and the pass
/// overhead from the units' own timing at the default widths.
#[test]
fn preset_fields_come_from_the_units() {
    let c = glare_asic().unwrap();
    assert_eq!(c.name, "glare-asic");
    assert_eq!(c.clock_hz * c.pipes as f64, PAPER_PIXELS_PER_SECOND);
    assert_eq!((c.tmus_per_pipe, c.texture_cache.size_bytes), (0, 0));
    let hw = GlareHw::default();
    let ip = interpolator(hw.coord_frac_bits).unwrap();
    let setup = generator().unwrap().timing().latency + ip.setup_cycles();
    assert_eq!(c.setup_clocks_per_triangle, setup);
    let noise = glare_pipeline::scene::limits::glare_noise(&hw)
        .build()
        .unwrap();
    assert_eq!(c.pass_overhead_clocks, noise.timing().latency);
    let names: Vec<&str> = c.pipe_stages.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "polygon_interpolator",
            "bloom_flare_modulator | halo_modulator",
            "glare_combiner"
        ]
    );
    assert!(c.pipe_stages.iter().all(|s| s.kind == StageKind::Plain));
    assert_eq!(
        (c.pipe_stages[0].latency, c.pipe_stages[0].ii),
        (ip.timing().latency, ip.timing().ii)
    );
    let lw = glare_pipeline::scene::limits::lum_widths(&hw);
    assert_eq!(c.pipe_stages[1].latency, lw.latency());
    let comb = glare_pipeline::scene::limits::glare_combiner(&hw)
        .build()
        .unwrap();
    assert_eq!(c.pipe_stages[2].latency, comb.timing().latency);
    // With radial correction the modulators' square root lengthens their stage.
    let radial = glare_asic_for(&GlareHw { radial: true, ..hw }).unwrap();
    assert!(radial.pipe_stages[1].latency > c.pipe_stages[1].latency);
    // A scene's clock and pipes carry over.
    let mut s = scene("glare-flare");
    s.glare.as_mut().unwrap().hw.pipes = 2;
    s.glare.as_mut().unwrap().hw.clock_mhz = 600.0;
    let c2 = glare_chip(&s).unwrap();
    assert_eq!((c2.pipes, c2.clock_hz), (2, 600e6));
    // The variants change one assumed field each.
    let v = variants(&c);
    assert_eq!(v[0].1, c);
    assert!(v[1..].iter().all(|(_, x)| *x != c));
}

/// The glare pass refuses a GeForce, naming the chip, before any work.
#[test]
fn a_geforce_is_refused() {
    let mut c = glare_asic().unwrap();
    c.name = "geforce3".into();
    let e = check_chip(&c).unwrap_err().to_string();
    assert!(e.contains("chip") && e.contains("geforce3"), "{e}");
    let e = glare_frame_timing(&scene("glare-point"), &c)
        .unwrap_err()
        .to_string();
    assert!(e.contains("glare-asic"), "{e}");
}

/// One primitive by hand. `glare-point` draws one bloom quad covering 720 × 352 =
/// 253 440 pixels (walked = covered) and loads 16 898 table words. On the preset
/// (4 pipes, set-up 23 clocks = generator 3 + interpolator set-up 20, stages 2 + 6 + 1
/// clocks, memory 32 B/clock at 30 clocks' latency, 6 B of RGB8 read-modify-write per
/// fragment):
/// - set-up 23, then the walk ⌈253 440 / 4⌉ = 63 360 clocks, then the drain: the
///   last quad through the stages (2 + 6 + 1) and its colour read (30 clocks) and
///   write, about 40 clocks; plus the pass overhead 9 (the noise generator's fill):
///   the clocked pass ≈ 23 + 63 360 + ~40 + 9 ≈ 63 432 clocks (the formula's
///   `prim_cycles` gives 23 + 63 360 + 7 = 63 390);
/// - memory: 253 440 × 6 B ÷ 32 B/clock = 47 520 clocks < 63 360, so the walk, not
///   memory, bounds it;
/// - tables: ⌈16 898 / 4⌉ = 4 225 clocks beside it;
/// - sustained ≈ 253 440 ÷ ((63 432 + 4 225) / 300 MHz) ≈ 1.12 × 10⁹ pixels/s.
///
/// Asserted: the pass lies between the walk with set-up and that plus a drain bound
/// (the stages, two memory latencies, the FIFOs and the overhead), and the tables
/// are their own ⌈words / 4⌉ clocks.
#[test]
fn one_primitive_by_hand() {
    let s = scene("glare-point");
    let chip = glare_chip(&s).unwrap();
    let f = record_glare(&s).unwrap();
    assert_eq!(f.prims.len(), 1);
    let p = &f.prims[0];
    let t = glare_frame_timing(&s, &chip).unwrap_or_else(|e| panic!("clocked chip: {e}"));
    let pass = &t
        .passes
        .iter()
        .find(|p| p.pass == GLARE_PASS)
        .unwrap()
        .timing;
    let walk = chip.setup_clocks_per_triangle as u64 + p.walked.div_ceil(chip.pipes as u64);
    let stages: u64 = chip.pipe_stages.iter().map(|s| s.latency as u64).sum();
    let drain = stages
        + 2 * chip.memory.latency_clocks as u64
        + 2 * chip.fifo_depth as u64
        + chip.pass_overhead_clocks as u64
        + 8;
    assert!(
        pass.cycles >= walk && pass.cycles <= walk + drain,
        "{} clocks, expected {walk} ..= {}",
        pass.cycles,
        walk + drain
    );
    assert_eq!(
        t.cycles_total() - pass.cycles,
        p.table_words.div_ceil(GLARE_TABLE_WORDS_PER_CLOCK as u64)
    );
}

/// The sustained rate on the three scenes: positive, at most the peak (clock × pipes,
/// the paper's 1.2 Gpixel/s), and the clocked pass between the walker's bound
/// (Σ ⌈walked / pipes⌉: one quad of pixels a clock) and the serial bound (each
/// primitive's set-up, walk and a drain one after the other, as the formula adds
/// them, with a drain as in [`one_primitive_by_hand`]); a bottleneck named.
#[test]
fn sustained_rate_on_the_glare_scenes() {
    for &name in ASIC_SCENES {
        let (s, f) = recorded(name);
        let chip = glare_chip(&s).unwrap();
        let t =
            glare_frame_timing(&s, &chip).unwrap_or_else(|e| panic!("{name}: clocked chip: {e}"));
        let pass = &t
            .passes
            .iter()
            .find(|p| p.pass == GLARE_PASS)
            .unwrap()
            .timing;
        let frags: u64 = f.prims.iter().map(|p| p.fragments).sum();
        let pipes = chip.pipes as u64;
        let walker: u64 = f.prims.iter().map(|p| p.walked.div_ceil(pipes)).sum();
        let stages: u64 = chip.pipe_stages.iter().map(|s| s.latency as u64).sum();
        let drain = stages + 2 * chip.memory.latency_clocks as u64 + 2 * chip.fifo_depth as u64 + 8;
        let serial: u64 = f
            .prims
            .iter()
            .map(|p| chip.setup_clocks_per_triangle as u64 + p.walked.div_ceil(pipes) + drain)
            .sum::<u64>()
            + chip.pass_overhead_clocks as u64;
        assert!(
            pass.cycles >= walker && pass.cycles <= serial,
            "{name}: {} clocks outside {walker} ..= {serial}",
            pass.cycles
        );
        assert_eq!(t.cycles_total(), pass.cycles + table_cycles(&f), "{name}");
        let rate = sustained_pixels_per_second(frags, &t).unwrap();
        assert!(
            rate > 0.0 && rate <= chip.clock_hz * chip.pipes as f64,
            "{name}: {rate:.3e} pixels/s"
        );
        assert!(!pass.bottleneck.is_empty(), "{name}: no bottleneck named");
    }
}
