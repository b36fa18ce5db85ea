//! The vector writers of the state-carrying RTL units (issue 20): gaussian_noise and
//! chaos_map (a stream of bare requests from the reset state) and polygon_interpolator
//! (primitives' start states through ports, `{load, move}` input words). The
//! co-simulation itself is tests/rtl_cosim.rs; this checks that the vectors exercise
//! what they claim.

use glare_pipeline::registry::rtl::{self, RtlConfig};

fn words(v: &[String]) -> Vec<u128> {
    v.iter()
        .map(|w| u128::from_str_radix(w, 16).unwrap())
        .collect()
}

fn param(v: &rtl::VectorSet, name: &str) -> u64 {
    v.params.iter().find(|(k, _)| *k == name).unwrap().1
}

#[test]
fn gaussian_noise_vectors_are_a_standard_normal_stream_from_reset() {
    let n = 20_000;
    let v = rtl::vectors("gaussian_noise", RtlConfig::Default, n, 3).unwrap();
    assert_eq!(v.stimulus.len(), n);
    assert!(!v.exhaustive);
    assert!(
        v.stimulus.iter().all(|w| w == "1"),
        "every transaction is a request"
    );
    assert_eq!((v.latency, v.ii), (9, 1));
    // x, y: s3.12 each, x in the top 16 bits.
    let sx = |w: u128| ((w as u16) as i16) as f64 / 4096.0;
    let mut xs = Vec::new();
    for w in words(&v.expected) {
        xs.push(sx(w >> 16));
        xs.push(sx(w));
    }
    let m = xs.iter().sum::<f64>() / xs.len() as f64;
    let var = xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / xs.len() as f64;
    // 40 000 samples: the mean's standard error is 0.005, the variance's 0.007.
    assert!(m.abs() < 0.03, "mean {m}");
    assert!((var - 1.0).abs() < 0.05, "variance {var}");
    // Another seed is another reset state, hence another stream.
    let w = rtl::vectors("gaussian_noise", RtlConfig::Default, 100, 4).unwrap();
    assert_ne!(w.expected, v.expected[..100].to_vec());
    assert_eq!(param(&w, "SEED"), 4);
}

#[test]
fn chaos_map_vectors_move_and_the_narrow_set_uses_the_naive_escape() {
    let v = rtl::vectors("chaos_map", RtlConfig::Default, 5_000, 1).unwrap();
    assert_eq!((v.latency, v.ii), (4 + 7, 7));
    assert_eq!(param(&v, "ESCAPE"), 1);
    let mut d = words(&v.expected);
    d.sort_unstable();
    d.dedup();
    assert!(d.len() > 500, "{} distinct outputs", d.len());
    let n = rtl::vectors("chaos_map", RtlConfig::Narrow, 100, 1).unwrap();
    assert_eq!(param(&n, "ESCAPE"), 0);
    assert_eq!((n.latency, n.ii), (2 + 7, 7));
    // a = 0.8 as u0.8 (round(a·2^8)) reaches the Verilog.
    assert_eq!(param(&n, "A"), (0.8f64 * 256.0).round() as u64);
}

#[test]
fn polygon_interpolator_vectors_load_one_start_state_per_primitive() {
    for cfg in RtlConfig::ALL {
        let v = rtl::vectors("polygon_interpolator", cfg, 20_000, 9).unwrap();
        assert_eq!(v.stimulus.len(), 20_000);
        let ins: Vec<u64> = v
            .stimulus
            .iter()
            .map(|w| u64::from_str_radix(w, 16).unwrap())
            .collect();
        // A load is the first move of a walk: Hold (code 0); Hold only there.
        assert!(ins.iter().all(|&w| (w >> 2 == 1) == (w & 3 == 0)));
        assert_eq!(ins[0], 0b100);
        let loads = ins.iter().filter(|&&w| w >> 2 == 1).count();
        assert!(loads > 100, "{cfg:?}: {loads} primitives");
        // Every table holds 2^PRIM_BITS > loads primitives' entries.
        let pb = param(&v, "PRIM_BITS");
        assert!(1usize << pb > loads);
        for r in &v.roms {
            assert_eq!(r.words.len() % (1 << pb), 0, "{}", r.name);
        }
        // Both inside and outside pixels are presented (the inside flag sits above
        // the four attributes).
        let ow = param(&v, "OUT_INT_BITS") + param(&v, "OUT_FRAC_BITS");
        let inside = words(&v.expected)
            .iter()
            .filter(|&&w| (w >> (4 * ow)) & 1 == 1)
            .count();
        let f = inside as f64 / v.expected.len() as f64;
        assert!((0.1..0.9).contains(&f), "{cfg:?}: inside fraction {f}");
    }
}
