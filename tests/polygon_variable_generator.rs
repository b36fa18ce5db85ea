//! polygon_variable_generator against its f64 twin, with a bound from its widths.

mod common;

use glare_pipeline::reference::polygon_variable_generator::{corners, Kind};
use proptest::prelude::*;
use rtl_model::units::polygon_variable_generator::{
    PolygonVariableGenerator, PolygonVariableGeneratorConfig, PrimKind, PvgIn,
};
use rtl_model::Counters;

/// |cos/sin code / 2^tb − exact| for any angle code: the angle's truncation to the
/// ROM's index (2π·2^−(k+2) when k < angle_bits − 2, else 0), the entry's rounding
/// (½·2^−tb), and reading full scale 2^tb − 1 as 2^tb (2^−tb).
fn trig_err(c: &PolygonVariableGeneratorConfig) -> f64 {
    let trunc = if c.trig_log2 < c.angle_bits - 2 {
        std::f64::consts::TAU * (-((c.trig_log2 + 2) as f64)).exp2()
    } else {
        0.0
    };
    trunc + 1.5 * (-(c.trig_bits as f64)).exp2()
}

fn configs() -> Vec<PolygonVariableGeneratorConfig> {
    let d = PolygonVariableGeneratorConfig::default();
    vec![
        d,
        PolygonVariableGeneratorConfig {
            angle_bits: 16,
            trig_log2: 12,
            trig_bits: 14,
            attr_frac_bits: 12,
            ..d
        },
        // Narrow: 3-bit ROM index, 6-bit entries, 8-bit angles, 2 sub-pixel bits.
        PolygonVariableGeneratorConfig {
            coord_int_bits: 12,
            subpixel_bits: 2,
            angle_bits: 8,
            trig_log2: 3,
            trig_bits: 6,
            attr_frac_bits: 8,
        },
    ]
}

fn check(
    cfg: PolygonVariableGeneratorConfig,
    kind: PrimKind,
    cx: i64,
    cy: i64,
    ext: u64,
    hw: u64,
    angle: u32,
) {
    let u = cfg.build().unwrap();
    let mut ctr = Counters::default();
    let angle = angle & ((1 << cfg.angle_bits) - 1);
    let got = rtl_model::Unit::kernel(
        &u,
        &mut (),
        &PvgIn {
            kind,
            cx,
            cy,
            extent: ext,
            half_width: hw,
            angle,
        },
        &mut ctr,
    );
    assert_eq!(ctr.saturations, 0, "inputs are chosen in range");
    let phi = angle as f64 / (1u64 << cfg.angle_bits) as f64 * std::f64::consts::TAU;
    let k = if kind == PrimKind::Area {
        Kind::Area
    } else {
        Kind::Line
    };
    let want = corners(k, cx as f64, cy as f64, ext as f64, hw as f64, phi);
    let d = trig_err(&cfg);
    let af = (cfg.attr_frac_bits as f64).exp2();
    for (g, w) in got.iter().zip(want) {
        // Positions (sub-pixel units): area corners are exact; a line corner adds two
        // rounded products, each within extent·δ + ½.
        let pos_bound = match kind {
            PrimKind::Area => 0.0,
            PrimKind::Line => (ext + hw) as f64 * d + 1.0,
        };
        assert!(
            (g.x as f64 - w[0]).abs() <= pos_bound + 1e-9,
            "x {} vs {} (bound {pos_bound})",
            g.x,
            w[0]
        );
        assert!(
            (g.y as f64 - w[1]).abs() <= pos_bound + 1e-9,
            "y {} vs {} (bound {pos_bound})",
            g.y,
            w[1]
        );
        // Attributes (s2.f codes): area = sum of two trig codes, each within δ·2^f and
        // a rounding of ½ when f < trig_bits; a line's are exactly ±1.
        let attr_bound = match kind {
            PrimKind::Area => {
                2.0 * (d * af
                    + if cfg.attr_frac_bits < cfg.trig_bits {
                        0.5
                    } else {
                        0.0
                    })
            }
            PrimKind::Line => 0.0,
        };
        assert!(
            (g.u as f64 - w[2] * af).abs() <= attr_bound + 1e-9,
            "u {} vs {}",
            g.u,
            w[2] * af
        );
        assert!(
            (g.v as f64 - w[3] * af).abs() <= attr_bound + 1e-9,
            "v {} vs {}",
            g.v,
            w[3] * af
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn within_width_bound_in_three_configs(
        which in 0usize..3,
        line in any::<bool>(),
        fx in -0.3f64..0.3, fy in -0.3f64..0.3, fe in 0.0f64..0.2, fw in 0.0f64..0.05,
        angle in any::<u32>(),
    ) {
        let cfg = configs()[which];
        let m = (1i64 << (cfg.coord_int_bits + cfg.subpixel_bits - 1)) as f64;
        let kind = if line { PrimKind::Line } else { PrimKind::Area };
        check(cfg, kind, (fx * m) as i64, (fy * m) as i64, (fe * m) as u64, (fw * m) as u64, angle);
    }

    #[test]
    fn tick_and_span_drivers_agree(
        which in 0usize..3,
        words in prop::collection::vec((any::<bool>(), any::<i64>(), any::<i64>(), any::<u64>(), any::<u64>(), any::<u32>()), 0..20),
    ) {
        let u = configs()[which].build().unwrap();
        let inputs: Vec<PvgIn> = words.iter().map(|&(l, cx, cy, e, w, a)| PvgIn {
            kind: if l { PrimKind::Line } else { PrimKind::Area },
            cx, cy, extent: e, half_width: w, angle: a,
        }).collect();
        common::assert_drivers_agree(&u, (), &inputs);
    }

    #[test]
    fn bad_configs_are_errors_naming_the_field(
        c in 0u32..20, s in 0u32..12, a in 0u32..20, k in 0u32..16, t in 0u32..20, f in 0u32..34,
    ) {
        let cfg = PolygonVariableGeneratorConfig { coord_int_bits: c, subpixel_bits: s, angle_bits: a, trig_log2: k, trig_bits: t, attr_frac_bits: f };
        if let Err(e) = cfg.build() {
            prop_assert!(e.field().starts_with("polygon_variable_generator."), "{}", e.field());
        }
    }
}

#[test]
fn every_angle_code_is_within_bound_at_8_bits() {
    for cfg in configs() {
        let m = 1i64 << (cfg.coord_int_bits + cfg.subpixel_bits - 3);
        for a in 0..(1u32 << cfg.angle_bits.min(10)) {
            let a = a << (cfg.angle_bits - cfg.angle_bits.min(10));
            check(cfg, PrimKind::Area, 100, -200, (m / 2) as u64, 0, a);
            check(
                cfg,
                PrimKind::Line,
                -300,
                50,
                (m / 2) as u64,
                (m / 64) as u64,
                a,
            );
        }
    }
}

#[test]
fn corners_beyond_the_range_saturate_and_are_counted() {
    let u = PolygonVariableGenerator::geforce();
    let mut ctr = Counters::default();
    let m = (1i64 << 17) - 1;
    let out = rtl_model::Unit::kernel(
        &u,
        &mut (),
        &PvgIn {
            kind: PrimKind::Area,
            cx: m - 10,
            cy: 0,
            extent: 1000,
            half_width: 0,
            angle: 0,
        },
        &mut ctr,
    );
    assert_eq!(out[1].x, m);
    assert!(ctr.saturations >= 2);
}

#[test]
fn nan_angle_is_an_error_naming_the_field() {
    let u = PolygonVariableGenerator::geforce();
    assert_eq!(
        u.angle_code(f64::NAN).unwrap_err().field(),
        "polygon_variable_generator.angle"
    );
    assert_eq!(u.angle_code(std::f64::consts::PI).unwrap(), 2048);
    assert_eq!(u.angle_code(-std::f64::consts::FRAC_PI_2).unwrap(), 3072);
}
