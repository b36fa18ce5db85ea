//! vertex_lighting's vectors (`rtl_model/verilog/units/vertex_lighting.v`).
//!
//! The Verilog implements ONE light (local or directional, with or without a spot
//! cone), GL_NORMALIZE on or off, an infinite or local viewer, nearest-even or
//! truncating rounding, subnormals flushed; the loaded registers are module
//! parameters. [`verilog_params`] refuses anything else (no light or several, kept
//! subnormals, M < 2), naming the field.
//!
//! * default: GeForce 256's datapath (IEEE single 8/23, nearest-even, GL_NORMALIZE,
//!   infinite viewer) with 16-bit colours instead of 8 (at 8 bits the output hides
//!   almost every one-ulp difference inside the float datapath: a hand mutation
//!   dropping the adder's sticky bit went unseen in 2·10⁴ vertices), a local spot
//!   light with attenuation and a specular material: every special (RSQ ×3, RCP,
//!   two pows) is on the path;
//! * narrow: E 4, M 6, truncation, 12-bit colours (every bit of a sum ≥ 2^−5),
//!   no GL_NORMALIZE, a local viewer, a directional light without a spot.
//!
//! The input word is six format words (192 bits default, 66 narrow), so 10⁵ vertices
//! (`count`), shaped from the seeded raw words: one in eight is the raw wire (with
//! the corners of the first eighth: ±0, the reserved exponent, max finite…), one in
//! eight has a zero-length normal (±0 or a flushed subnormal), one in eight sits
//! exactly at the light's position register (for the default's local light d² = 0:
//! rsq saturates, L = 0, the spot is 0), the rest have coordinates of magnitude
//! 2^−4 ..= 4 and normal components 2^−3 ..= 2 (exponents spread, random signs), so N·L ≤ 0,
//! the spot cone's edge, specular highlights and the [0, 1] clamps all occur.

use super::{collect, RtlConfig, VectorSet, VerilogParams};
use rtl_model::units::vertex_lighting::{
    Light, LightingSetup, VertexLighting, VertexLightingConfig, VertexLightingIn,
};
use rtl_model::{Fp, Rounding, Subnormals};

/// The Verilog's parameters for `u`, or why the Verilog does not implement it.
pub(super) fn verilog_params(u: &VertexLighting) -> Result<VerilogParams, String> {
    let cfg = u.config();
    let fmt = cfg.format;
    if u.light_count() != 1 {
        return Err(format!(
            "vertex_lighting.lights: the Verilog implements exactly one light ({} given)",
            u.light_count()
        ));
    }
    if fmt.subnormals != Subnormals::Flush {
        return Err(
            "vertex_lighting.format.subnormals: the Verilog flushes subnormals only".into(),
        );
    }
    if fmt.mant_bits < 2 {
        return Err(format!(
            "vertex_lighting.format.mant_bits: the Verilog needs at least 2 ({} given)",
            fmt.mant_bits
        ));
    }
    let l = &u.light_registers()[0];
    let (base, shininess, alpha) = u.material_registers();
    let spot = l.spot;
    let w = |x: Fp| x.0;
    let mut p: VerilogParams = vec![
        ("EXP_BITS", fmt.exp_bits as u64),
        ("MANT_BITS", fmt.mant_bits as u64),
        (
            "ROUNDING",
            match fmt.rounding {
                Rounding::NearestEven => 0,
                Rounding::Truncate => 1,
            },
        ),
        ("COLOR_BITS", cfg.color_bits as u64),
        ("NORMALIZE", u64::from(cfg.normalize)),
        ("LOCAL_VIEWER", u64::from(cfg.local_viewer)),
        ("LOCAL", u64::from(l.local)),
        ("SPOT", u64::from(spot.is_some())),
    ];
    let names3 = |a: [&'static str; 3], v: [Fp; 3]| a.into_iter().zip(v.map(w));
    p.extend(names3(["LIGHT_X", "LIGHT_Y", "LIGHT_Z"], l.vector));
    p.extend(names3(["ATT_C", "ATT_L", "ATT_Q"], l.attenuation));
    let (sdir, scos, sexp) = match spot {
        Some(s) => (s.direction, s.cos_cutoff, s.exponent),
        None => ([Fp(0); 3], Fp(0), Fp(0)),
    };
    p.extend(names3(["SPOT_X", "SPOT_Y", "SPOT_Z"], sdir));
    p.push(("SPOT_COS", w(scos)));
    p.push(("SPOT_EXP", w(sexp)));
    p.extend(names3(["AMB_R", "AMB_G", "AMB_B"], l.ambient));
    p.extend(names3(["DIF_R", "DIF_G", "DIF_B"], l.diffuse));
    p.extend(names3(["SPE_R", "SPE_G", "SPE_B"], l.specular));
    p.extend(names3(["BASE_R", "BASE_G", "BASE_B"], base));
    p.push(("SHININESS", w(shininess)));
    p.push(("ALPHA", alpha as u64));
    Ok(p)
}

/// The unit at `config` (see the module docs).
fn unit_of(config: RtlConfig) -> Result<VertexLighting, String> {
    let mut setup = LightingSetup::default();
    let (cfg, light) = match config {
        RtlConfig::Default => {
            setup.material.emission = [0.05, 0.0, 0.02];
            setup.material.specular = [0.8; 3];
            setup.material.shininess = 32.0;
            // Above and in front of the origin, the cone aimed at it: most shaped
            // vertices (|P| components 2^-4 ..= 4) fall inside.
            let light = Light {
                position: [0.5, 1.0, 2.0, 1.0],
                ambient: [0.1, 0.1, 0.1],
                diffuse: [0.9, 0.8, 0.7],
                specular: [1.0; 3],
                spot_direction: [-0.5, -1.0, -2.0],
                spot_exponent: 4.0,
                spot_cutoff: 75.0,
                attenuation: [1.0, 0.05, 0.02],
            };
            // 16-bit colours: the unorm shows 16 of the sum's 24 bits (GeForce's 8
            // hide almost every one-ulp difference of the float datapath).
            let cfg = VertexLightingConfig {
                color_bits: 16,
                ..VertexLightingConfig::geforce()
            };
            (cfg, light)
        }
        RtlConfig::Narrow => {
            setup.material.specular = [0.5; 3];
            setup.material.shininess = 8.0;
            // Directional (the default's light is local): each of LOCAL, SPOT,
            // NORMALIZE, LOCAL_VIEWER and ROUNDING takes both values across the two.
            let light = Light {
                position: [0.3, 0.8, 0.5, 0.0],
                ambient: [0.25, 0.25, 0.25],
                diffuse: [1.0, 0.75, 0.5],
                ..Light::default()
            };
            let mut cfg = VertexLightingConfig::geforce().with_format(4, 6);
            cfg.format.rounding = Rounding::Truncate;
            cfg.color_bits = 12; // every bit of a sum ≥ 2^-5 is visible
            cfg.normalize = false;
            cfg.local_viewer = true;
            (cfg, light)
        }
    };
    setup.lights = vec![light];
    VertexLighting::new(cfg, &setup).map_err(|e| e.to_string())
}

pub(super) fn vertex_lighting_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let u = unit_of(config)?;
    let params = verilog_params(&u)?;
    let fmt = u.format();
    let (e_bits, m) = (fmt.exp_bits, fmt.mant_bits);
    let bias = fmt.bias() as u64;
    let sign_mask = 1u64 << (e_bits + m);
    let mant_mask = (1u64 << m) - 1;
    // A word with the raw sign and mantissa and an exponent in bias + lo ..= bias + lo + 7.
    let shaped = move |v: u64, lo: i64| {
        let e = (bias as i64 + lo + ((v >> m) & 7) as i64) as u64;
        (v & (sign_mask | mant_mask)) | (e << m)
    };
    let light = u.light_registers()[0].vector;
    let make = move |v: &[u64]| {
        // A selector from all six words (the shaping below reads their low bits).
        let h = v.iter().fold(0xcbf2_9ce4_8422_2325u64, |a, &x| {
            (a ^ x).wrapping_mul(0x0000_0100_0000_01b3)
        });
        let sel = h >> 61;
        let mut w: [u64; 6] = std::array::from_fn(|i| v[i]);
        if sel != 0 {
            for (i, x) in w.iter_mut().enumerate() {
                // Exponents bias + lo ..= bias + lo + 7, those above bias + top
                // folded down by 4: |P| components 2^-4 ..= 4, |n| components
                // 2^-3 ..= 2 (the narrow config does not normalise n).
                let (lo, top) = if i < 3 { (-4, 1) } else { (-3, 0) };
                *x = shaped(*x, lo);
                let e = (*x >> m) & ((1 << e_bits) - 1);
                if e > bias + top {
                    *x -= 4 << m;
                }
            }
        }
        if sel == 1 {
            // A zero-length normal: ±0 or a subnormal (flushed), both read as zero.
            for x in &mut w[3..] {
                *x &= sign_mask | mant_mask;
            }
        }
        if sel == 2 {
            // The vertex at the light (a local light's position; d² = 0).
            for (x, l) in w.iter_mut().zip(light) {
                *x = l.0;
            }
        }
        VertexLightingIn {
            position: [Fp(w[0]), Fp(w[1]), Fp(w[2])],
            normal: [Fp(w[3]), Fp(w[4]), Fp(w[5])],
        }
    };
    Ok(collect(
        &u,
        (),
        config,
        VertexLightingIn::default(),
        make,
        params,
        count,
        seed,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_what_the_verilog_does_not_build() {
        let cfg = VertexLightingConfig::geforce();
        let two = LightingSetup {
            lights: vec![Light::default(); 2],
            ..LightingSetup::default()
        };
        let u = VertexLighting::new(cfg, &two).unwrap();
        let e = verilog_params(&u).unwrap_err();
        assert!(e.contains("vertex_lighting.lights"), "{e}");
        let mut keep = cfg;
        keep.format.subnormals = Subnormals::Keep;
        let u = VertexLighting::new(keep, &LightingSetup::default()).unwrap();
        let e = verilog_params(&u).unwrap_err();
        assert!(e.contains("subnormals"), "{e}");
        let u = VertexLighting::new(cfg.with_format(5, 1), &LightingSetup::default()).unwrap();
        let e = verilog_params(&u).unwrap_err();
        assert!(e.contains("mant_bits"), "{e}");
        // Both built-in configurations pass.
        for c in RtlConfig::ALL {
            assert!(verilog_params(&unit_of(c).unwrap()).is_ok());
        }
    }
}
