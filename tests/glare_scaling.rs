//! `reproduce glare-scaling`, small: the city at night at two source counts. What
//! grows with the sources is the frame's own work; the out-of-range check renders the
//! same number of reduced frames at both counts (it used to render one per source).

use glare_pipeline::frame::glare_scaling::{glare_scaling, CITY_SEED};
use glare_pipeline::scene::builtin_glare::city_lights;
use glare_pipeline::scene::format::Scene;

#[test]
fn the_city_scales_and_its_range_check_does_not_grow_with_the_sources() {
    let dir = std::env::temp_dir().join(format!("glare_scaling_{}", std::process::id()));
    let rows = glare_scaling(&dir, &[40, 400]).unwrap();
    assert_eq!(rows.len(), 4);
    let counts: Vec<(usize, &str)> = rows.iter().map(|r| (r.sources, r.tables)).collect();
    assert_eq!(
        counts,
        [
            (40, "shared"),
            (400, "shared"),
            (40, "distinct"),
            (400, "distinct")
        ]
    );
    assert_eq!(rows[2].per_source_ratio, 1.0);
    assert!(rows
        .iter()
        .all(|r| r.seconds > 0.0 && r.micros_per_source > 0.0));
    assert_eq!(rows[0].per_source_ratio, 1.0);
    for pair in [&rows[0..2], &rows[2..4]] {
        assert_eq!(
            pair[0].range_renders, pair[1].range_renders,
            "reduced frames rendered by the range check: {rows:?}"
        );
    }
    // Both frames warn (the bloom modulator saturates on more than 1 % of the faint
    // sources' fragments), so the check does run its reduced frames.
    assert!(
        rows.iter().all(|r| r.warnings > 0 && r.range_renders > 0),
        "{rows:?}"
    );
    assert!(
        rows.iter().all(|r| r.range_renders <= 5 + 10 + 10),
        "{rows:?}"
    );
    // The CSV has a row per count; each written scene loads back as the city.
    let csv = std::fs::read_to_string(dir.join("glare_scaling.csv")).unwrap();
    assert_eq!(csv.lines().count(), 5, "{csv}");
    for n in [40, 400] {
        let text = std::fs::read_to_string(dir.join(format!("city_{n}.toml"))).unwrap();
        let s = Scene::from_toml_str(&text).unwrap();
        assert_eq!(s, city_lights(n, CITY_SEED));
        assert_eq!(s.glare.as_ref().unwrap().sources.len(), n);
        assert!(dir.join(format!("city_{n}.png")).is_file());
        let text = std::fs::read_to_string(dir.join(format!("city_{n}_distinct.toml"))).unwrap();
        let d = Scene::from_toml_str(&text).unwrap();
        let mut kinds: Vec<u64> = d
            .glare
            .as_ref()
            .unwrap()
            .sources
            .iter()
            .map(|s| s.intensity.to_bits())
            .collect();
        kinds.sort_unstable();
        kinds.dedup();
        assert_eq!(kinds.len(), n, "every distinct source its own brightness");
    }
    std::fs::remove_dir_all(&dir).ok();
}
