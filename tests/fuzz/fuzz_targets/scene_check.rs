//! Fuzz target: any bytes as a scene file, through parse → validate → elaborate.
//! A refusal is fine (it must name a field: a `ConfigError` always does); a panic,
//! an abort, a hang or an out-of-memory is a bug libFuzzer reports.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // Scene files are UTF-8 text: `Scene::from_file` refuses anything else before
    // parsing, so only text reaches the parser.
    if let Ok(text) = std::str::from_utf8(data) {
        if let Err(e) = glare_pipeline::frame::check::check_scene_text(text) {
            assert!(!e.field().is_empty(), "a refusal that names no field: {e}");
        }
    }
});
