//! The architecture parameters `sweep` and `optimize` name: each reads back the value it
//! was given on every GeForce preset, changes only its own field (and, for the clock,
//! keeps the memory's bytes per second), and an unknown name is `None`.

use glare_pipeline::chip::config::ChipConfig;
use glare_pipeline::chip::params::{texture_cache_bits, ChipParam, CHIP_PARAMS};

fn presets() -> Vec<ChipConfig> {
    vec![
        ChipConfig::geforce256(),
        ChipConfig::geforce2_gts(),
        ChipConfig::geforce3(),
    ]
}

#[test]
fn every_param_reads_back_what_it_was_given() {
    for base in presets() {
        for p in CHIP_PARAMS {
            for v in [1u32, 2, 7, 64, 300] {
                let mut c = base.clone();
                p.apply(&mut c, v);
                assert_eq!(p.get(&c), v, "{} {}", base.name, p.name());
                for q in CHIP_PARAMS.into_iter().filter(|&q| q != p) {
                    assert_eq!(
                        q.get(&c),
                        q.get(&base),
                        "{} = {v} moved {} on {}",
                        p.name(),
                        q.name(),
                        base.name
                    );
                }
            }
        }
    }
}

#[test]
fn a_new_clock_keeps_the_memory_bandwidth() {
    let base = ChipConfig::geforce2_gts();
    let before = ChipParam::BandwidthMbs.get(&base);
    let mut c = base.clone();
    ChipParam::ClockMhz.apply(&mut c, 100);
    assert_eq!(ChipParam::BandwidthMbs.get(&c), before);
    assert!((c.memory.bytes_per_clock - 2.0 * base.memory.bytes_per_clock).abs() < 1e-9);
}

#[test]
fn names_round_trip_and_unknown_names_are_none() {
    for p in CHIP_PARAMS {
        assert_eq!(ChipParam::from_name(p.name()), Some(p));
        assert_eq!(ChipParam::from_name(&p.name().replace('_', "-")), Some(p));
    }
    assert_eq!(ChipParam::from_name("planes"), None);
    assert!(ChipParam::names().contains("cache_kb"));
}

#[test]
fn cache_bits_count_every_cache() {
    let mut c = ChipConfig::geforce2_gts();
    c.texture_cache.size_bytes = 4096;
    c.texture_cache.shared = false;
    assert_eq!(
        texture_cache_bits(&c),
        u64::from(c.pipes * c.tmus_per_pipe) * 4096 * 8
    );
    c.texture_cache.shared = true;
    assert_eq!(texture_cache_bits(&c), 4096 * 8);
}
