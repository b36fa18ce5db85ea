//! `envmap-dump` (issue 19): a prefiltered map written out and read back is the same
//! map bit for bit; the sidecar carries the exposure; broken dumps are refused naming
//! the file.

mod common;

use common::Scratch;
use glare_pipeline::pipeline::envmap::dump::{dump_scene, read_dump, SIDECAR_FILE, VOLUME_FILE};
use glare_pipeline::pipeline::envmap::scene_render::build_map;
use glare_pipeline::scene::builtin::builtin;

#[test]
fn dumped_32_cubed_map_reads_back_bit_for_bit() {
    let dir = Scratch::new("envmap-dump", "venice32");
    let scene = builtin("env-venice_sunset-sphere").unwrap();
    let (written, car) = dump_scene(&scene, Some(32), &dir).unwrap();
    assert_eq!(written.side(), 32);
    // The in-memory map, built again the way `render` builds it.
    let mut section = scene.environment.clone().unwrap();
    section.side = 32;
    let env = section.load().unwrap();
    let (in_memory, build) = build_map(&section, &env).unwrap();
    assert_eq!(written, in_memory, "the dumped map is the render's map");
    let (back, car_back) = read_dump(&dir).unwrap();
    assert_eq!(back, in_memory, "read back bit for bit");
    assert_eq!(back.data(), in_memory.data());
    assert_eq!(car_back, car);
    assert_eq!(car.exposure.to_bits(), build.exposure.to_bits());
    assert_eq!(car.slices.len(), 32);
    for s in &car.slices {
        let img = image::open(dir.join(s)).unwrap();
        assert_eq!((img.width(), img.height()), (32, 32));
    }
    let raw = std::fs::metadata(dir.join(VOLUME_FILE)).unwrap().len();
    assert_eq!(raw, 32 * 32 * 32 * 3 * 2);
}

#[test]
fn broken_dumps_are_refused_naming_the_file() {
    let dir = Scratch::new("envmap-dump", "broken");
    let scene = builtin("env-pattern-sphere").unwrap();
    dump_scene(&scene, Some(8), &dir).unwrap();
    let vol = dir.join(VOLUME_FILE);
    let mut raw = std::fs::read(&vol).unwrap();
    raw.pop();
    std::fs::write(&vol, &raw).unwrap();
    let e = read_dump(&dir).unwrap_err();
    assert!(e.contains(VOLUME_FILE) && e.contains("bytes"), "{e}");
    std::fs::remove_file(dir.join(SIDECAR_FILE)).unwrap();
    let e = read_dump(&dir).unwrap_err();
    assert!(e.contains(SIDECAR_FILE), "{e}");
    // A scene without an environment has no map.
    let e = dump_scene(&builtin("fig4").unwrap(), None, &dir).unwrap_err();
    assert!(e.starts_with("scene:"), "{e}");
    let e = dump_scene(&scene, Some(12), &dir).unwrap_err();
    assert!(e.contains("side"), "{e}");
}
