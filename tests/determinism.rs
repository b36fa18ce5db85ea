//! Every built-in renders the same bytes and counters on 1 and on 2 threads, run
//! twice (issue 16, "Deterministic").
//!
//! Each built-in (`scene::load::builtin_names()` — the shafts figures, the glare
//! built-ins, the environment scenes, the showcase — and the foundation `test` scene)
//! is rendered in this process inside a rayon pool of 1 thread, twice, and of 2
//! threads, twice (`ThreadPool::install`: the pipelines run their parallel loops on
//! the current pool). The four renders must give the same framebuffer codes, the same
//! PNG bytes (encoded as the CLI's `render --out` encodes them) and the same counters
//! as JSON text.
//!
//! The scenes are reduced as in tests/golden.rs, so that the suite stays fast in the
//! test profile: 180 × 120, at most 10 planes and 2 sub-planes, environment maps at
//! s = 16 (the `env-*` scenes at 32 × 32). At full size, compare
//! `render --scene NAME --json` under `RAYON_NUM_THREADS=1` and `=2`.

use glare_pipeline::frame::run::render;
use glare_pipeline::pipeline::envmap::scene_render::render_scene;
use glare_pipeline::pipeline::test_scene;
use glare_pipeline::scene::builtin::builtin;
use glare_pipeline::scene::builtin_environment::ENVIRONMENT_BUILTIN_NAMES;
use glare_pipeline::scene::load::builtin_names;

/// One render: framebuffer codes (as words), PNG bytes, counters as JSON.
#[derive(Debug, PartialEq)]
struct Output {
    codes: Vec<u32>,
    png: Vec<u8>,
    counters: String,
}

/// PNG bytes of an 8-bit image, encoded in memory the way `image` writes a file.
fn png(width: u32, height: u32, bytes: Vec<u8>, color: image::ExtendedColorType) -> Vec<u8> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(&bytes, width, height, color)
        .unwrap();
    out
}

/// The built-in `name` at the test size, rendered as the CLI's `render` does.
fn render_builtin(name: &str) -> Output {
    if name == "test" {
        let (fb, counters) = test_scene::render().unwrap();
        return Output {
            png: png(
                fb.width,
                fb.height,
                fb.to_rgba8(),
                image::ExtendedColorType::Rgba8,
            ),
            codes: fb.data,
            counters: serde_json::to_string(&counters).unwrap(),
        };
    }
    let mut s = builtin(name).unwrap_or_else(|e| panic!("{name}: {e}"));
    if let Some(e) = s.environment.as_mut() {
        e.side = 16;
    }
    if ENVIRONMENT_BUILTIN_NAMES.contains(&name) {
        s.image.width = 32;
        s.image.height = 32;
        let f = render_scene(&s, false).unwrap_or_else(|e| panic!("{name}: {e}"));
        let img = f.image;
        let bytes: Vec<u8> = img.pixels.iter().flatten().copied().collect();
        return Output {
            png: png(img.width, img.height, bytes, image::ExtendedColorType::Rgb8),
            codes: img
                .pixels
                .iter()
                .flat_map(|p| p.map(u32::from))
                .chain(img.mask.iter().map(|&m| u32::from(m)))
                .collect(),
            counters: serde_json::to_string(&f.counters).unwrap(),
        };
    }
    s.image.width = 180;
    s.image.height = 120;
    s.shafts.planes = s.shafts.planes.min(10);
    s.shafts.subplanes = s.shafts.subplanes.min(2);
    let f = render(&s).unwrap_or_else(|e| panic!("{name}: {e}"));
    Output {
        png: png(
            f.fb.width,
            f.fb.height,
            f.fb.to_rgba8(),
            image::ExtendedColorType::Rgba8,
        ),
        counters: serde_json::to_string(&f.counters()).unwrap(),
        codes: f.fb.data,
    }
}

#[test]
fn every_built_in_renders_the_same_bytes_and_counters_on_1_and_2_threads_twice() {
    let pool = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    // Two pools of 1 thread, so that the two 1-thread runs go at once (each is still
    // alone in its pool, and a core would otherwise idle through them), then the two
    // 2-thread runs one after the other in the pool of 2.
    let (one_a, one_b, two) = (pool(1), pool(1), pool(2));
    let mut names = builtin_names();
    names.push("test");
    assert!(names.len() >= 15, "{names:?}");
    let mut bad = Vec::new();
    for name in &names {
        let (first_1, second_1) = std::thread::scope(|scope| {
            let second = scope.spawn(|| one_b.install(|| render_builtin(name)));
            let first = one_a.install(|| render_builtin(name));
            (first, second.join().unwrap())
        });
        let runs = [
            (1, 1, first_1),
            (1, 2, second_1),
            (2, 1, two.install(|| render_builtin(name))),
            (2, 2, two.install(|| render_builtin(name))),
        ];
        let (_, _, first) = &runs[0];
        assert!(
            first.codes.iter().any(|&c| c != 0),
            "{name}: a black frame proves nothing"
        );
        for (n, run, o) in &runs[1..] {
            let what = |field: &str| {
                format!("{name}: {field} on {n} threads (run {run}) differ from 1 thread (run 1)")
            };
            if o.codes != first.codes {
                bad.push(what("framebuffer codes"));
            }
            if o.png != first.png {
                bad.push(what("PNG bytes"));
            }
            if o.counters != first.counters {
                bad.push(what("counters"));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
