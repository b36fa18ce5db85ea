//! What the shafts passes record for the clocked chip (`PassWork`): recording changes
//! no pixel, counter or pass statistic; each pass's record agrees with its counters
//! (fragments, walked pixels, primitives, texel bytes, framebuffer and depth bytes,
//! copy bytes); the record is the same on one and two threads.

use glare_pipeline::chip::work::{PassSample, PassWork, SampleBands};
use glare_pipeline::chip::{kind_name, PassKind};
use glare_pipeline::pipeline::shafts::frame::{passes, FrameResult, ShaftsFrame};
use glare_pipeline::pipeline::shafts::host::prepare_scene;
use glare_pipeline::pipeline::shafts::prepare::DEFAULT_EXPOSURE;
use glare_pipeline::scene::builtin::builtin;
use glare_pipeline::scene::format::Scene;
use std::cell::RefCell;
use std::collections::BTreeSet;
use std::rc::Rc;

fn small(name: &str, planes: u32, subplanes: u32) -> Scene {
    let mut s = builtin(name).unwrap();
    s.image.width = 96;
    s.image.height = 64;
    s.shafts.planes = planes;
    s.shafts.subplanes = subplanes;
    s.shafts.shadow_resolution = 128;
    s
}

/// The frame rendered pass by pass, recording its work when `record`.
fn frame(s: &Scene, record: bool) -> (FrameResult, Vec<PassWork>) {
    frame_sampled(s, record, None)
}

/// [`frame`], recording only the fragments of `bands` when given.
fn frame_sampled(
    s: &Scene,
    record: bool,
    bands: Option<SampleBands>,
) -> (FrameResult, Vec<PassWork>) {
    let (p, _) = prepare_scene(s, DEFAULT_EXPOSURE).unwrap();
    let works = Rc::new(RefCell::new(Vec::new()));
    let mut f = ShaftsFrame::new(&p, None).unwrap();
    if record {
        let w = Rc::clone(&works);
        f.record_work_sampled(
            Box::new(move |pw| {
                w.borrow_mut().push(pw);
                Ok(())
            }),
            bands,
            PassSample::ALL,
        );
    }
    for pass in passes(&p) {
        f.run(pass).unwrap();
    }
    let r = f.finish();
    drop(p);
    let works = std::mem::take(&mut *works.borrow_mut());
    (r, works)
}

/// FNV-1a 64 over a pass's whole record.
fn hash(works: &[PassWork]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let mut eat = |v: u64| {
        for b in v.to_le_bytes() {
            h = (h ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
    };
    for w in works {
        eat(w.width as u64);
        eat(w.height as u64);
        eat(w.textures.len() as u64);
        for t in &w.textures {
            eat(t.size[0] as u64 | (t.size[1] as u64) << 16 | (t.size[2] as u64) << 32);
            eat(t.texel_bytes as u64 | (t.texels_per_lookup as u64) << 32);
        }
        for v in [&w.prim_first_fragment, &w.prim_walked, &w.prim_depth_killed] {
            eat(v.len() as u64);
            v.iter().for_each(|&x| eat(x as u64));
        }
        eat(w.frag_xy.len() as u64);
        w.frag_xy
            .iter()
            .for_each(|p| eat(p[0] as u64 | (p[1] as u64) << 16));
        eat(w.texels.len() as u64);
        w.texels.iter().for_each(|&x| eat(x as u64));
        let r = w.rop;
        eat(r.depth_read_bytes as u64 | (r.depth_write_bytes as u64) << 32);
        eat(r.colour_read_bytes as u64 | (r.colour_write_bytes as u64) << 32);
        eat(w.copy_read_bytes);
        eat(w.copy_write_bytes);
    }
    h
}

/// Every pass's record agrees with its counters.
fn check_consistent(name: &str, works: &[PassWork]) -> BTreeSet<PassKind> {
    let mut kinds = BTreeSet::new();
    for (i, w) in works.iter().enumerate() {
        let st = w.stats.as_ref().expect("stats");
        let at = format!("{name} pass {i} ({})", kind_name(st.kind));
        kinds.insert(st.kind);
        assert_eq!(w.fragments() as u64, st.fragments, "{at}: fragments");
        let walked: u64 = w.prim_walked.iter().map(|&x| x as u64).sum();
        assert_eq!(walked, st.walked, "{at}: walked");
        assert_eq!(w.prim_walked.len() as u64, st.triangles, "{at}: primitives");
        assert_eq!(w.prim_first_fragment.len(), w.prim_walked.len(), "{at}");
        // Primitives' fragments are in draw order, each within its walk.
        for p in 0..w.prim_first_fragment.len() {
            let r = w.prim_fragments(p);
            assert!(r.start <= r.end, "{at}: primitive {p} order");
            let killed = w.prim_depth_killed.get(p).copied().unwrap_or(0) as usize;
            assert!(r.len() + killed <= w.prim_walked[p] as usize, "{at}: {p}");
        }
        for xy in &w.frag_xy {
            assert!(
                (xy[0] as u32) < w.width && (xy[1] as u32) < w.height,
                "{at}"
            );
        }
        // Texels: one run per texture per fragment, indices inside the texture, bytes
        // as the samplers counted them.
        assert_eq!(
            w.texels.len(),
            w.fragments() * w.texels_per_fragment(),
            "{at}: texel runs"
        );
        let mut off = 0;
        for f in 0..w.fragments() {
            for t in &w.textures {
                let n = t.size.iter().product::<u32>();
                for k in 0..t.texels_per_lookup as usize {
                    assert!(w.texels[off + k] < n, "{at}: fragment {f} {}", t.name);
                }
                off += t.texels_per_lookup as usize;
            }
        }
        let per_frag: u64 = w
            .textures
            .iter()
            .map(|t| t.texels_per_lookup as u64 * t.texel_bytes as u64)
            .sum();
        assert_eq!(
            per_frag * w.fragments() as u64,
            st.texel_bytes,
            "{at}: texel bytes"
        );
        // The ROP: colour bytes as the blend counted them; depth reads of every
        // tested fragment, those the depth test removed included.
        let rop = w.rop;
        let n = w.fragments() as u64;
        match st.kind {
            PassKind::ObjectDepth | PassKind::ShadowMap => {
                assert!(
                    rop.depth_write_bytes > 0 && rop.colour_write_bytes == 0,
                    "{at}"
                );
                assert!(w.prim_depth_killed.is_empty(), "{at}");
            }
            PassKind::CopyToTexture => {
                assert_eq!(
                    w.copy_read_bytes + w.copy_write_bytes,
                    st.other_bytes,
                    "{at}"
                );
                assert_eq!(n, 0, "{at}");
            }
            _ => {
                assert_eq!(
                    n * (rop.colour_read_bytes + rop.colour_write_bytes) as u64,
                    st.fb_bytes,
                    "{at}: framebuffer bytes"
                );
                assert_eq!(
                    (n + w.depth_killed()) * rop.depth_read_bytes as u64,
                    4 * st.depth_tests,
                    "{at}: depth bytes"
                );
                assert_eq!(w.prim_depth_killed.is_empty(), st.depth_tests == 0, "{at}");
            }
        }
        if st.kind != PassKind::CopyToTexture {
            assert_eq!(w.copy_read_bytes + w.copy_write_bytes, 0, "{at}");
        }
    }
    kinds
}

#[test]
fn recording_changes_nothing_and_agrees_with_the_counters() {
    let mut kinds = BTreeSet::new();
    // fig6: depth, shadow map, objects, sub-planes (m = 3), copies, planes; fig4: m = 1
    // (the light map and shadow map on the planes); stage: several lights. Without a
    // record the passes skip the projective work of fragments outside the light's
    // square; a shadow map of 96 texels (not a power of two) is more than the square.
    for (name, n, m, res) in [
        ("fig6", 4, 3, 128),
        ("fig4", 4, 1, 128),
        ("fig6", 4, 3, 96),
        ("stage", 3, 2, 128),
    ] {
        let mut s = small(name, n, m);
        s.shafts.shadow_resolution = res;
        let (plain, none) = frame(&s, false);
        assert!(none.is_empty());
        let (rec, works) = frame(&s, true);
        assert_eq!(plain.fb, rec.fb, "{name}: pixels");
        assert_eq!(plain.counters, rec.counters, "{name}: counters");
        assert_eq!(
            format!("{:?}", plain.passes),
            format!("{:?}", rec.passes),
            "{name}: pass statistics"
        );
        assert_eq!(works.len(), rec.passes.len(), "{name}: one record per pass");
        for (w, st) in works.iter().zip(&rec.passes) {
            assert_eq!(
                format!("{:?}", w.stats.as_ref().unwrap()),
                format!("{st:?}")
            );
        }
        kinds.extend(check_consistent(name, &works));
        let texels: usize = works.iter().map(|w| w.texels.len()).sum();
        assert!(texels > 0, "{name}: texels recorded");
    }
    let all = [
        PassKind::ObjectDepth,
        PassKind::ShadowMap,
        PassKind::Objects,
        PassKind::SubPlane,
        PassKind::CopyToTexture,
        PassKind::Plane,
    ];
    for k in all {
        assert!(kinds.contains(&k), "no {} pass recorded", kind_name(k));
    }
}

#[test]
fn same_record_on_one_and_two_threads() {
    // m = 5: the sub-planes run in batches of 4 (one full, one partial).
    let s = small("fig6", 3, 5);
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let (_, a) = pool(1).install(|| frame(&s, true));
    let (_, b) = pool(2).install(|| frame(&s, true));
    assert!(!a.is_empty());
    assert_eq!(hash(&a), hash(&b));
    let s4 = small("fig4", 3, 1);
    let (_, a) = pool(1).install(|| frame(&s4, true));
    let (_, b) = pool(2).install(|| frame(&s4, true));
    assert_eq!(hash(&a), hash(&b));
}

/// The recorder in sampled mode keeps only the fragments of the sampled units (and
/// computes no footprint for the others) while counting every primitive in full: its
/// record is exactly the full record cut to the sample ([`PassWork::sampled`]), it
/// holds about one fragment in `every`, and the pixels do not change.
#[test]
fn the_sampled_recorder_records_only_the_sample() {
    let mut s = small("fig6", 4, 3);
    (s.image.width, s.image.height) = (256, 128);
    let bands = SampleBands {
        band_rows: 8,
        block_cols: 0,
        every: 4,
    };
    let (full_frame, full) = frame(&s, true);
    let (sampled_frame, sampled) = frame_sampled(&s, true, Some(bands));
    assert_eq!(full_frame.fb, sampled_frame.fb, "pixels");
    assert_eq!(full_frame.counters, sampled_frame.counters, "counters");
    assert_eq!(full.len(), sampled.len());
    let (mut kept, mut all, mut bytes_full, mut bytes_sampled) = (0, 0, 0, 0);
    for (f, w) in full.iter().zip(&sampled) {
        let cut = f.sampled(bands);
        let kind = kind_name(f.stats.as_ref().unwrap().kind);
        let Some(b) = w.sample.as_ref() else {
            // A copy to texture records no primitive nor fragment: nothing to sample.
            assert_eq!((w.fragments(), w.prim_walked.len()), (0, 0), "{kind}");
            continue;
        };
        assert_eq!(
            hash(std::slice::from_ref(&cut)),
            hash(std::slice::from_ref(w)),
            "{kind}"
        );
        let a = cut.sample.as_ref().unwrap();
        assert_eq!(a.prim_fragments, b.prim_fragments, "{kind}");
        assert_eq!(a.prim_first_xy, b.prim_first_xy, "{kind}");
        // The recorder also places the depth-killed fragments of the sampled rows (a
        // full record does not know them): as many as the pass killed there at most.
        assert!(b.killed_xy.len() as u64 <= w.depth_killed(), "{kind}");
        assert!(b
            .killed_xy
            .iter()
            .all(|p| bands.keeps(p[0] as u32, p[1] as u32)));
        assert_eq!(w.all_fragments(), f.fragments() as u64, "{kind}");
        assert!(w
            .frag_xy
            .iter()
            .all(|p| bands.keeps(p[0] as u32, p[1] as u32)));
        kept += w.fragments();
        all += f.fragments();
        bytes_full += f.heap_bytes();
        bytes_sampled += w.heap_bytes();
    }
    // One band in 4 sampled: about a quarter of the fragments (the scene's fragments
    // are not spread evenly over the bands: between an eighth and a half).
    assert!(all > 0);
    assert!(
        kept * 8 >= all && kept * 2 <= all,
        "{kept} of {all} fragments kept"
    );
    assert!(
        bytes_sampled * 2 < bytes_full,
        "record {bytes_sampled} bytes against {bytes_full}"
    );
}

/// Per pass kind: the largest record (bytes), the passes, the fragments.
type PerKind = std::collections::BTreeMap<&'static str, (usize, usize, u64)>;

/// The record's cost on the full-size fig6 (720 × 480, 30 planes, m = 6): wall time of
/// the frame without and with recording (each record dropped as it arrives, as the
/// clocked frame drops it after clocking), and the largest record per pass kind.
/// Prints, asserts only that the record is complete. `cargo test --release --test
/// shafts_pass_work -- --ignored --nocapture record_cost_on_fig6`.
#[test]
#[ignore]
fn record_cost_on_fig6() {
    use std::collections::BTreeMap;
    use std::time::Instant;
    let s = builtin("fig6").unwrap();
    let (p, _) = prepare_scene(&s, DEFAULT_EXPOSURE).unwrap();
    let run = |record: bool| {
        let peak: Rc<RefCell<PerKind>> = Rc::default();
        let t = Instant::now();
        let mut f = ShaftsFrame::new(&p, None).unwrap();
        if record {
            let pk = Rc::clone(&peak);
            f.record_work(Box::new(move |w| {
                let st = w.stats.as_ref().unwrap();
                let mut m = pk.borrow_mut();
                let e = m.entry(kind_name(st.kind)).or_default();
                e.0 = e.0.max(w.heap_bytes());
                e.1 += 1;
                e.2 += w.fragments() as u64;
                Ok(())
            }));
        }
        for pass in passes(&p) {
            f.run(pass).unwrap();
        }
        let r = f.finish();
        let secs = t.elapsed().as_secs_f64();
        let peak = peak.borrow().clone();
        (r, secs, peak)
    };
    // Alternate, twice each, so a warm cache favours neither.
    let mut off = Vec::new();
    let mut on = Vec::new();
    let mut kinds = BTreeMap::new();
    for _ in 0..2 {
        off.push(run(false).1);
        let (r, secs, peak) = run(true);
        on.push(secs);
        assert_eq!(peak.values().map(|v| v.1).sum::<usize>(), r.passes.len());
        kinds = peak;
    }
    println!("fig6 wall seconds without recording: {off:?}, with: {on:?}");
    for (k, (bytes, n, frags)) in &kinds {
        println!(
            "{k}: {n} passes, largest record {:.2} MB, {:.0} fragments per pass",
            *bytes as f64 / 1e6,
            *frags as f64 / *n as f64
        );
    }
}
