//! The normalisation cube map path (`cube_map_address` → 2D `texture_sampler` on the
//! F × 6F RGB texture of normalised directions) against the exact normalisation of
//! the input words' direction, under the bounds derived from F, b and the address
//! unit's widths (`pipeline::shading::normalize_cube` module notes; docs/shading.md).
//!
//! The bounds, in short (h = 2/F, B = 2^b − 1, δ the address unit's coordinate bound):
//! nearest: angle ≤ √2(½ + δ)h + asin(√3/B), component ≤ ½ + (B/2)·√2(½ + δ)h codes;
//! bilinear: angle ≤ asin(h²/4 + √2·Δ·h + 2√3/B), component ≤ 1 + (B/2)(h²/4 + √2·Δ·h),
//! with Δ = δ inside a face and ½ + δ within ½ + δ texel of a face edge.

mod common;

use glare_pipeline::pipeline::shading::normalize_cube::{
    angle_between, decode, measure, normalize_f64, random_vector, NormalizeCube,
    NormalizeCubeConfig, NormalizeCubeCounters,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rtl_model::units::cube_map_address::{CubeMapAddressConfig, CubeMapAddressIn};
use rtl_model::units::texture_sampler::Filter;
use rtl_model::Counters;

fn norm(d: [f64; 3]) -> [f64; 3] {
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    d.map(|c| c / l)
}

/// Check one word: angle and every component within the bound of its region.
fn check(cube: &NormalizeCube, w: &CubeMapAddressIn) -> (f64, f64) {
    let c = cube.config();
    let big_b = ((1u64 << c.texel_bits) - 1) as f64;
    let d = cube.word_direction(w);
    let mut ctr = NormalizeCubeCounters::default();
    let out = cube.normalize(w, &mut ctr);
    let b = cube.bounds();
    let edge = cube.in_edge_band(d);
    let (ab, cb) = if edge {
        (b.angle_edge, b.component_edge)
    } else {
        (b.angle_interior, b.component_interior)
    };
    let n = norm(d);
    let a = angle_between(decode(out, c.texel_bits), n);
    assert!(
        a <= ab + 1e-12,
        "{c:?}: d {d:?}: angle {a} > bound {ab} (edge {edge})"
    );
    let mut worst_c: f64 = 0.0;
    for k in 0..3 {
        let e = (out[k] as f64 - (n[k] + 1.0) * 0.5 * big_b).abs();
        assert!(
            e <= cb + 1e-9,
            "{c:?}: d {d:?}: component {k} off by {e} > {cb}"
        );
        worst_c = worst_c.max(e / cb);
    }
    assert_eq!(ctr.address.table_reads, 1);
    assert_eq!(ctr.address.underflows, 0);
    (a / ab, worst_c)
}

fn configs() -> Vec<NormalizeCubeConfig> {
    let mut v = Vec::new();
    for (f, b) in [(16, 8), (32, 8), (64, 8), (4, 4), (8, 6), (128, 16)] {
        for filter in [Filter::Nearest, Filter::Linear] {
            v.push(NormalizeCubeConfig::with(f, b, filter));
        }
    }
    // A narrower address unit (no Newton step, a small reciprocal table).
    v.push(NormalizeCubeConfig {
        address: CubeMapAddressConfig {
            newton: false,
            rcp_addr_bits: 5,
            rcp_bits: 7,
            ..CubeMapAddressConfig::geforce3()
        },
        ..NormalizeCubeConfig::with(32, 8, Filter::Linear)
    });
    v
}

/// Random directions and lengths (log-uniform down to 2^−12), every config.
#[test]
fn random_vectors_within_the_derived_bounds() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for c in configs() {
        let cube = c.build().unwrap();
        let (mut wa, mut wc) = (0f64, 0f64);
        let mut n = 0;
        while n < 4000 {
            let w = cube
                .vector_words(random_vector(&mut rng), &mut Counters::default())
                .unwrap();
            if cube.word_direction(&w) == [0.0; 3] {
                continue;
            }
            let (a, cc) = check(&cube, &w);
            wa = wa.max(a);
            wc = wc.max(cc);
            n += 1;
        }
        println!(
            "F {} b {} {:?}: worst angle/bound {wa:.2}, worst component/bound {wc:.2}",
            c.face_side, c.texel_bits, c.filter
        );
    }
}

/// Very short vectors: words a few LSBs from the centre, every direction they can
/// encode, are normalised within the bound (of the words' direction); against the
/// f64 vector before quantisation the words' own rounding adds asin(√3/2·2^−Fi/|d|).
#[test]
fn very_short_vectors() {
    for filter in [Filter::Nearest, Filter::Linear] {
        let cube = NormalizeCubeConfig::with(64, 8, filter).build().unwrap();
        let a = cube.config().address;
        let centre = 1i32 << (a.side_log2 + a.in_frac_bits - 1);
        for x in -3..=3 {
            for y in -3..=3 {
                for z in -3..=3 {
                    let w = CubeMapAddressIn {
                        coord: [centre + x, centre + y, centre + z],
                    };
                    if (x, y, z) != (0, 0, 0) {
                        check(&cube, &w);
                    }
                }
            }
        }
        // v of length 10⁻³ (d = 0.064 texel = 16 LSB): against the unquantised vector.
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let lsb = (-(a.in_frac_bits as f64)).exp2();
        let bits = cube.config().texel_bits;
        for _ in 0..2000 {
            let v = norm(random_vector(&mut rng)).map(|c| c * 1e-3);
            let w = cube.vector_words(v, &mut Counters::default()).unwrap();
            let d = cube.word_direction(&w);
            let dl = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if dl == 0.0 {
                continue;
            }
            let b = cube.bounds();
            let quant = (3f64.sqrt() / 2.0 * lsb / dl).min(1.0).asin();
            let out = cube.normalize(&w, &mut NormalizeCubeCounters::default());
            let ang = angle_between(decode(out, bits), v);
            assert!(ang <= b.angle_edge.max(b.angle_interior) + quant + 1e-12);
        }
    }
}

/// A zero-length vector: +x, flagged and counted, no panic, no NaN; the f64 path
/// gives +x too.
#[test]
fn zero_vector_reads_plus_x() {
    for filter in [Filter::Nearest, Filter::Linear] {
        for f in [2, 16, 64] {
            let cube = NormalizeCubeConfig::with(f, 8, filter).build().unwrap();
            let w = cube
                .vector_words([0.0; 3], &mut Counters::default())
                .unwrap();
            assert_eq!(cube.word_direction(&w), [0.0; 3]);
            let mut ctr = NormalizeCubeCounters::default();
            let out = cube.normalize(&w, &mut ctr);
            assert_eq!(ctr.address.underflows, 1);
            let v = decode(out, 8);
            assert!(v.iter().all(|c| c.is_finite()));
            let a = angle_between(v, [1.0, 0.0, 0.0]);
            // Face 0's centre: the four centre texels are √2/2 texel off its axis.
            let b = cube.bounds();
            assert!(a <= b.angle_edge.max(b.angle_interior), "F {f}: {a}");
            // +x dominates (F = 2 nearest: the texel (1, ½, ½)/|·|, x = 0.816).
            assert!(v[0] > 0.8, "F {f}: {v:?}");
        }
    }
    assert_eq!(normalize_f64([0.0; 3], 8), [255, 128, 128]);
    assert_eq!(normalize_f64([f64::NAN, 1.0, 0.0], 8), [255, 128, 128]);
}

/// The f64 path: exact normalisation, then ½-LSB rounding per component.
#[test]
fn f64_path_rounds_the_exact_normal() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for bits in [4, 8, 16] {
        let big_b = ((1u64 << bits) - 1) as f64;
        for _ in 0..2000 {
            let d = random_vector(&mut rng);
            let n = norm(d);
            let c = normalize_f64(d, bits);
            for k in 0..3 {
                assert!((c[k] as f64 - (n[k] + 1.0) * 0.5 * big_b).abs() <= 0.5 + 1e-9);
            }
            let a = angle_between(decode(c, bits), n);
            assert!(a <= (3f64.sqrt() / big_b).asin());
        }
    }
}

/// The bilinear bound uses max |∂²n/∂u²| ≤ 1 on a face: check it on a grid (the
/// closed form |n_uu|² = [9u²(1+v²)² + (1+v²)(2u²−1−v²)²]/(1+u²+v²)⁵).
#[test]
fn second_derivative_of_the_face_field_is_at_most_one() {
    let mut worst: f64 = 0.0;
    for i in 0..=200 {
        for j in 0..=200 {
            let (u, v) = (i as f64 / 100.0 - 1.0, j as f64 / 100.0 - 1.0);
            let r2 = 1.0 + u * u + v * v;
            let a = 9.0 * u * u * (1.0 + v * v).powi(2);
            let b = (1.0 + v * v) * (2.0 * u * u - 1.0 - v * v).powi(2);
            let k = ((a + b) / r2.powi(5)).sqrt();
            // Against a central difference of n(u, v) = (u, v, 1)/r.
            let h = 1e-4;
            let n = |u: f64| norm([u, v, 1.0]);
            let (p, c, m) = (n(u + h), n(u), n(u - h));
            let fd = (0..3)
                .map(|q| ((p[q] - 2.0 * c[q] + m[q]) / (h * h)).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!((fd - k).abs() < 1e-5, "({u}, {v}): {fd} vs {k}");
            worst = worst.max(k);
        }
    }
    assert!(worst <= 1.0 + 1e-12, "{worst}");
}

/// The span driver path gives the same codes as the kernels, and counts.
#[test]
fn span_path_matches_kernels_and_counts() {
    let cube = NormalizeCube::new(NormalizeCubeConfig::geforce()).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let inputs: Vec<CubeMapAddressIn> = (0..300)
        .map(|_| {
            cube.vector_words(random_vector(&mut rng), &mut Counters::default())
                .unwrap()
        })
        .collect();
    let (outs, ctr) = cube.normalize_span(&inputs);
    let mut kc = NormalizeCubeCounters::default();
    for (w, o) in inputs.iter().zip(&outs) {
        assert_eq!(cube.normalize(w, &mut kc), *o);
    }
    assert_eq!(ctr.address.table_reads, kc.address.table_reads);
    assert_eq!(ctr.sampler.mem_read_bytes, kc.sampler.mem_read_bytes);
    assert_eq!(ctr.sampler.pixels_out, 300);
    assert!(ctr.address.cycles > 300 && ctr.sampler.cycles > 300);
    assert_eq!(cube.texture_bits(), 6 * 64 * 64 * 3 * 8);
}

/// The error table's rows at the small sizes stay within their bounds and the
/// interior error falls with F (the CLI writes F up to 256).
#[test]
fn error_table_rows_fall_with_face_side() {
    let mut last = f64::INFINITY;
    for f in [16, 32, 64] {
        let r = measure(NormalizeCubeConfig::with(f, 16, Filter::Linear), 3000, 1).unwrap();
        assert!(r.max_angle_interior_deg <= r.bound_angle_interior_deg);
        assert!(r.max_angle_deg <= r.bound_angle_edge_deg);
        assert!(r.max_angle_interior_deg < last);
        last = r.max_angle_interior_deg;
    }
}

#[test]
fn config_errors_name_the_field() {
    let base = NormalizeCubeConfig::geforce();
    for (c, field) in [
        (
            NormalizeCubeConfig {
                face_side: 1,
                ..base
            },
            "normalize_cube.face_side",
        ),
        (
            NormalizeCubeConfig {
                face_side: 48,
                ..base
            },
            "normalize_cube.face_side",
        ),
        (
            NormalizeCubeConfig {
                face_side: 1024,
                ..base
            },
            "normalize_cube.face_side",
        ),
        (
            NormalizeCubeConfig {
                texel_bits: 0,
                ..base
            },
            "normalize_cube.texel_bits",
        ),
        (
            NormalizeCubeConfig {
                texel_bits: 17,
                ..base
            },
            "normalize_cube.texel_bits",
        ),
        (
            NormalizeCubeConfig {
                address: CubeMapAddressConfig {
                    rcp_bits: 1,
                    ..base.address
                },
                ..base
            },
            "normalize_cube.address.cube_map_address.rcp_bits",
        ),
    ] {
        assert_eq!(c.build().unwrap_err().field(), field, "{c:?}");
    }
    let cube = base.build().unwrap();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let e = cube
            .vector_words([0.5, bad, 0.0], &mut Counters::default())
            .unwrap_err();
        assert_eq!(e.field(), "normalize_cube.vector");
    }
    // Huge vectors saturate the words (counted), never panic.
    let mut ctr = Counters::default();
    let w = cube.vector_words([1e300, -1e300, 3.0], &mut ctr).unwrap();
    assert!(ctr.saturations >= 2);
    let _ = cube.normalize(&w, &mut NormalizeCubeCounters::default());
}
