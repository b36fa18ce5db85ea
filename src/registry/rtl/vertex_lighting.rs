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
//!   two pows, their exponents 4.5 and 32.5 non-integers so exp2's floor acts) is
//!   on the path;
//! * narrow: E 4, M 6, truncation, 12-bit colours (every bit of a sum ≥ 2^−5),
//!   no GL_NORMALIZE, a local viewer, a directional light without a spot.
//!
//! Both are GL's single colour. The NV2A modes (`normalize_directional` off, and
//! `light_control` with its four switches: LIGHT_CONTROL, LIGHTING, SPECULAR_ENABLE,
//! SEPARATE_SPECULAR, SPEC_ALPHA_FROM_VERTEX, the vertex colours in, the secondary
//! colour out; `specular_curve`: SPECULAR_CURVE and CURVE_K0 … CURVE_K2) are
//! [`vertex_lighting_mode_sets`], run by tests/rtl_vertex_lighting.rs.
//!
//! The input word is six format words (192 bits default, 66 narrow), so 10⁵ vertices
//! (`count`), shaped from the seeded raw words: one in eight is the raw wire (with
//! the corners of the first eighth: ±0, the reserved exponent, max finite…), one in
//! eight has a zero-length normal (±0 or a flushed subnormal), one in eight sits
//! exactly at the light's position register (for the default's local light d² = 0:
//! rsq saturates, L = 0, the spot is 0), the rest have coordinates of magnitude
//! 2^−4 ..= 4 and normal components 2^−3 ..= 2 (exponents spread, random signs), so N·L ≤ 0,
//! the spot cone's edge, specular highlights and the [0, 1] clamps all occur.
//!
//! Before all of these come the **fault corners** ([`fault_corners`]): vertices on
//! which a wrong rounding in a rarely deciding position reaches the output. Each is
//! found by running [`light_with`], the kernel's datapath for one light, once as the
//! model computes it and once with one hand mutation of the Verilog applied to every
//! RSQ, RCP or exp2 — RSQ's or RCP's remainder dropped from the sticky bit (the
//! quotient rounded as if exact), or exp2's ⌊t·2^K⌋ of a negative t truncated toward
//! zero instead of floored — and keeping the vertex when the output words differ.
//! A test checks `light_with` without a fault against the kernel. They replace the
//! first vertices of the stream, so the count is unchanged.

use super::super::unit_entry::seeded;
use super::vector_set::{collect, RtlConfig, VectorSet, VerilogParams};
use crate::conformance::specular::POW16_PARAMS;
use rand::Rng;
use rtl_model::units::vertex_lighting::{
    Light, LightControl, LightingSetup, SpecularCurve, VertexLighting, VertexLightingConfig,
    VertexLightingIn,
};
use rtl_model::{Counters, FloatFormat, Fp, Rounding, Subnormals};
use std::cell::Cell;

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
        ("LIGHT_CONTROL", u64::from(cfg.light_control.is_some())),
    ];
    if let Some(lc) = cfg.light_control {
        p.extend([
            ("LIGHTING", u64::from(lc.lighting)),
            ("SPECULAR_ENABLE", u64::from(lc.specular_enable)),
            ("SEPARATE_SPECULAR", u64::from(lc.separate_specular)),
            (
                "SPEC_ALPHA_FROM_VERTEX",
                u64::from(lc.specular_alpha_from_vertex),
            ),
        ]);
    }
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
    // The NV2A specular curve: only when set, so the pow sets' parameters are as before.
    if let Some(k) = u.curve_registers() {
        p.push(("SPECULAR_CURVE", 1));
        p.extend(names3(["CURVE_K0", "CURVE_K1", "CURVE_K2"], k));
    }
    Ok(p)
}

/// Fault corners searched for per fault, shaped vertices tried at most, and the
/// redraws of a vertex's normal low bits (see [`fault_corners`]).
const CORNERS_PER_FAULT: usize = 16;
const CORNER_TRIES: usize = 40_000;
const SWEEP: usize = 64;

/// The unit at `config` (see the module docs).
fn unit_of(config: RtlConfig) -> Result<VertexLighting, String> {
    let (cfg, setup) = setup_of(config);
    VertexLighting::new(cfg, &setup).map_err(|e| e.to_string())
}

/// The config and loaded state of `config`'s unit (see the module docs).
fn setup_of(config: RtlConfig) -> (VertexLightingConfig, LightingSetup) {
    let mut setup = LightingSetup::default();
    let (cfg, light) = match config {
        RtlConfig::Default => {
            setup.material.emission = [0.05, 0.0, 0.02];
            setup.material.specular = [0.8; 3];
            setup.material.shininess = 32.5;
            // Above and in front of the origin, the cone aimed at it: most shaped
            // vertices (|P| components 2^-4 ..= 4) fall inside.
            let light = Light {
                position: [0.5, 1.0, 2.0, 1.0],
                ambient: [0.1, 0.1, 0.1],
                diffuse: [0.9, 0.8, 0.7],
                specular: [1.0; 3],
                spot_direction: [-0.5, -1.0, -2.0],
                spot_exponent: 4.5,
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
    (cfg, setup)
}

/// A hand mutation of the Verilog the fault corners are chosen to expose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Fault {
    None,
    /// RSQ's remainders dropped from the sticky bit.
    RsqSticky,
    /// RCP's remainder dropped from the sticky bit.
    RcpSticky,
    /// exp2's fixed-point t of a negative t truncated toward zero, not floored.
    Exp2Floor,
}

const FAULTS: [Fault; 3] = [Fault::RsqSticky, Fault::RcpSticky, Fault::Exp2Floor];

/// The kernel's float operations, with one fault applied to RSQ, RCP or exp2.
struct Datapath {
    f: FloatFormat,
    fault: Fault,
    ctr: Counters,
    /// The fault changed an RSQ, RCP or exp2 result.
    changed: bool,
}

impl Datapath {
    /// (sig, lsb) of a non-zero word: sig·2^lsb, sig in [2^M, 2^(M+1)).
    fn parts(&self, x: Fp) -> (u128, i32) {
        let f = &self.f;
        let (_, e, mant) = f.fields(x);
        let e = e.min((1 << f.exp_bits) - 2) as i32;
        let m = f.mant_bits;
        ((1u128 << m) | mant as u128, e - f.bias() - m as i32)
    }

    /// (−1)^neg · q · 2^lsb rounded once with no sticky bit (exact in f64 here).
    fn round(&mut self, neg: bool, q: u128, lsb: i32) -> Fp {
        let v = q as f64 * 2f64.powi(lsb);
        let v = if neg { -v } else { v };
        self.f
            .from_f64("vertex_lighting", v, &mut self.ctr)
            .unwrap_or(Fp(0))
    }

    fn rsq(&mut self, x: Fp) -> Fp {
        if self.fault != Fault::RsqSticky || self.f.is_zero(x) {
            return self.f.rsq(x, &mut self.ctr);
        }
        // The model's ⌊√⌊2^(2P)/sig⌋⌋, rounded as if exact.
        let m = self.f.mant_bits;
        let (sig, lsb) = self.parts(x);
        let (sig, lsb) = if lsb % 2 != 0 {
            (sig << 1, lsb - 1)
        } else {
            (sig, lsb)
        };
        let two_p = 3 * m + 8 + (m % 2);
        let r = ((1u128 << two_p) / sig).isqrt();
        let y = self.round(false, r, -(two_p as i32 / 2) - lsb / 2);
        self.changed |= y != self.f.rsq(x, &mut self.ctr);
        y
    }

    fn rcp(&mut self, x: Fp) -> Fp {
        if self.fault != Fault::RcpSticky || self.f.is_zero(x) {
            return self.f.rcp(x, &mut self.ctr);
        }
        let k = 2 * self.f.mant_bits + 4;
        let (sig, lsb) = self.parts(x);
        let neg = self.f.is_neg(x);
        let y = self.round(neg, (1u128 << k) / sig, -(k as i32) - lsb);
        self.changed |= y != self.f.rcp(x, &mut self.ctr);
        y
    }

    /// The model's pow: log2 (K squarings) → mul → exp2.
    fn pow(&mut self, x: Fp, s: Fp) -> Fp {
        let f = self.f;
        if f.is_zero(s) {
            return f.one();
        }
        if !f.lt(Fp(0), x) {
            return Fp(0);
        }
        let (m, k) = (f.mant_bits, f.pow_frac_bits());
        let (sig, lsb) = self.parts(x);
        let mut y = sig << (k - m);
        let mut frac: i128 = 0;
        for _ in 0..k {
            let z = y * y;
            frac <<= 1;
            if z >> (2 * k + 1) != 0 {
                frac |= 1;
                y = z >> (k + 1);
            } else {
                y = z >> k;
            }
        }
        let l_fix = ((lsb as i128 + m as i128) << k) + frac;
        let l = self.round(l_fix < 0, l_fix.unsigned_abs(), -(k as i32));
        let t = f.mul(s, l, &mut self.ctr);
        if self.fault == Fault::Exp2Floor && f.is_neg(t) && !f.is_zero(t) {
            // ⌊|t|·2^K⌋ (exact in f64): the mutation's t·2^K of a negative t.
            let mag = (-f.to_f64(t) * 2f64.powi(k as i32)).floor();
            let tt = self.round(true, mag as u128, -(k as i32));
            let y = f.exp2(tt, &mut self.ctr);
            self.changed |= y != f.exp2(t, &mut self.ctr);
            return y;
        }
        f.exp2(t, &mut self.ctr)
    }

    fn dot3(&mut self, a: &[Fp; 3], b: &[Fp; 3]) -> Fp {
        let (f, c) = (self.f, &mut self.ctr);
        let t0 = f.mul(a[0], b[0], c);
        let t1 = f.mul(a[1], b[1], c);
        let s = f.add(t0, t1, c);
        let t2 = f.mul(a[2], b[2], c);
        f.add(s, t2, c)
    }

    fn normalise(&mut self, v: &[Fp; 3]) -> [Fp; 3] {
        let d = self.dot3(v, v);
        let r = self.rsq(d);
        v.map(|c| self.f.mul(c, r, &mut self.ctr))
    }
}

/// [`light_with`]'s result.
struct Lit {
    rgb: [u32; 3],
    /// The fault changed an RSQ, RCP or exp2 result (whether or not `rgb` shows it).
    changed: bool,
    /// The normalised half vector, when the specular term is computed.
    h: Option<[Fp; 3]>,
}

/// The kernel's colour words for `input` (one light, `VertexLighting::light`'s order
/// of operations) with `fault` applied.
fn light_with(u: &VertexLighting, input: &VertexLightingIn, fault: Fault) -> Lit {
    let cfg = u.config();
    let f = cfg.format;
    let mut dp = Datapath {
        f,
        fault,
        ctr: Counters::default(),
        changed: false,
    };
    let p = &input.position;
    let n = if cfg.normalize {
        dp.normalise(&input.normal)
    } else {
        input.normal
    };
    let v = if cfg.local_viewer {
        dp.normalise(&p.map(|c| f.neg(c)))
    } else {
        [Fp(0), Fp(0), f.one()]
    };
    let (base, shininess, _) = u.material_registers();
    let l = &u.light_registers()[0];
    let (lv, att) = if l.local {
        let vp = [0, 1, 2].map(|k| f.sub(l.vector[k], p[k], &mut dp.ctr));
        let d2 = dp.dot3(&vp, &vp);
        let r = dp.rsq(d2);
        let lv = vp.map(|c| f.mul(c, r, &mut dp.ctr));
        let d = f.mul(d2, r, &mut dp.ctr);
        let [kc, kl, kq] = l.attenuation;
        let t = f.mul(kl, d, &mut dp.ctr);
        let den = f.add(kc, t, &mut dp.ctr);
        let t = f.mul(kq, d2, &mut dp.ctr);
        let den = f.add(den, t, &mut dp.ctr);
        (lv, dp.rcp(den))
    } else {
        (l.vector, f.one())
    };
    let spot = match &l.spot {
        None => f.one(),
        Some(s) => {
            let c = f.neg(dp.dot3(&lv, &s.direction));
            if f.lt(c, s.cos_cutoff) {
                Fp(0)
            } else {
                dp.pow(c, s.exponent)
            }
        }
    };
    let nl_raw = dp.dot3(&n, &lv);
    let nl = f.max0(nl_raw);
    let mut half = None;
    let spec = if f.lt(Fp(0), nl_raw) {
        let hv = [0, 1, 2].map(|k| f.add(lv[k], v[k], &mut dp.ctr));
        let h = dp.normalise(&hv);
        half = Some(h);
        let nh = f.max0(dp.dot3(&n, &h));
        dp.pow(nh, shininess)
    } else {
        Fp(0)
    };
    let c = &mut dp.ctr;
    let k = f.mul(att, spot, c);
    let rgb = [0, 1, 2].map(|i| {
        let t = f.mul(nl, l.diffuse[i], c);
        let t = f.add(l.ambient[i], t, c);
        let s = f.mul(spec, l.specular[i], c);
        let t = f.add(t, s, c);
        let kt = f.mul(k, t, c);
        f.to_unorm(f.add(base[i], kt, c), cfg.color_bits, c)
    });
    Lit {
        rgb,
        changed: dp.changed,
        h: half,
    }
}

/// Up to `per_fault` vertices for each of [`FAULTS`] on which it changes the output,
/// from at most `tries` shaped vertices (a fault that cannot act at this
/// configuration, e.g. a sticky bit under truncation, finds none). A 1-ulp change
/// inside the float datapath reaches a colour word only when the sum sits near a
/// rounding point of the unorm, so: every other vertex has its normal aimed at the
/// half vector (N·H ≈ 1, pow's t a small negative non-integer: exp2's floor acts)
/// and every fourth is on the spot light's axis (the spot's pow likewise),
/// and a vertex on which the fault changes an RSQ, RCP or exp2 result but not the
/// output is tried again with the normal's low mantissa bits redrawn (the sum moves
/// by a few of its ulps), up to [`SWEEP`] times.
fn fault_corners(
    u: &VertexLighting,
    make: &impl Fn(&[u64]) -> VertexLightingIn,
    per_fault: usize,
    tries: usize,
    seed: u64,
) -> Vec<VertexLightingIn> {
    let fmt = u.format();
    let w = fmt.width();
    let low = (1u64 << (fmt.mant_bits / 2).min(10)) - 1;
    let aim = (1u64 << fmt.mant_bits.saturating_sub(5)) - 1;
    let mut rng = seeded(seed ^ 0x5f1c_ad0e_7a11_c0de);
    let l = u.light_registers()[0];
    let mut ctr = Counters::default();
    let mut found = [0usize; FAULTS.len()];
    let mut out = Vec::new();
    for t in 0..tries {
        if found.iter().all(|&n| n >= per_fault) {
            break;
        }
        let raw: Vec<u64> = (0..6).map(|_| rng.random_range(0..1u64 << w)).collect();
        let mut x = make(&raw);
        if let (2, Some(s), true) = (t % 4, &l.spot, l.local) {
            // On the spot cone's axis (c ≈ 1: the spot's pow has t a small negative
            // non-integer), a distance 2^-2 ..= 4 from the light.
            let tau = 2f64.powf(rng.random_range(-2.0..2.0));
            for (k, c) in x.position.iter_mut().enumerate() {
                let p = fmt.to_f64(l.vector[k]) + tau * fmt.to_f64(s.direction[k]);
                *c = fmt.from_f64("position", p, &mut ctr).unwrap_or(Fp(0));
            }
        } else if t % 2 == 1 {
            // Four times as far out (a local light's attenuation keeps the sum below
            // the clamp), N = H with its low mantissa bits redrawn: N·H just below 1.
            for c in &mut x.position {
                let (_, e, _) = fmt.fields(*c);
                if e != 0 && e + 3 < (1 << fmt.exp_bits) {
                    *c = Fp(c.0 + (2 << fmt.mant_bits));
                }
            }
            let Some(h) = light_with(u, &x, Fault::None).h else {
                continue;
            };
            for (c, h) in x.normal.iter_mut().zip(h) {
                *c = Fp((h.0 & !aim) | rng.random_range(0..=aim));
            }
        }
        for (n, &fault) in found.iter_mut().zip(&FAULTS) {
            if *n >= per_fault {
                continue;
            }
            let lit = light_with(u, &x, fault);
            let mut hit = (lit.rgb != light_with(u, &x, Fault::None).rgb).then_some(x);
            if hit.is_none() && lit.changed {
                hit = (0..SWEEP).find_map(|_| {
                    let mut y = x;
                    for c in &mut y.normal {
                        *c = Fp((c.0 & !low) | rng.random_range(0..=low));
                    }
                    let a = light_with(u, &y, fault).rgb;
                    (a != light_with(u, &y, Fault::None).rgb).then_some(y)
                });
            }
            if let Some(y) = hit {
                *n += 1;
                out.push(y);
                break;
            }
        }
    }
    out
}

/// The shaped vertex of six seeded raw words (see the module docs).
fn shaper(u: &VertexLighting) -> impl Fn(&[u64]) -> VertexLightingIn {
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
    move |v: &[u64]| {
        // A selector from all six words (the shaping below reads their low bits).
        let h = v[..6].iter().fold(0xcbf2_9ce4_8422_2325u64, |a, &x| {
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
        // With light control, the vertex's diffuse and specular colours: the words
        // after the six as drawn (their corners 0, 1, the midpoint ± 0, max − 1, max).
        let colour = |k: usize| std::array::from_fn(|c| v.get(k + c).map_or(0, |&x| x as u32));
        VertexLightingIn {
            position: [Fp(w[0]), Fp(w[1]), Fp(w[2])],
            normal: [Fp(w[3]), Fp(w[4]), Fp(w[5])],
            diffuse: colour(6),
            specular: colour(10),
        }
    }
}

pub(super) fn vertex_lighting_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let u = unit_of(config)?;
    let params = verilog_params(&u)?;
    let make = shaper(&u);
    // The fault corners first, in place of the stream's first vertices (`collect`
    // calls `make` once per vertex, in order).
    let corners = fault_corners(
        &u,
        &make,
        (count / 64).min(CORNERS_PER_FAULT),
        CORNER_TRIES,
        seed,
    );
    let next = Cell::new(0usize);
    let make = |v: &[u64]| {
        let i = next.get();
        next.set(i + 1);
        corners.get(i).copied().unwrap_or_else(|| make(v))
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

/// Every set of the light-control switches, in a fixed order: lighting,
/// specular_enable, separate_specular and specular_alpha_from_vertex are bits 3, 2, 1
/// and 0 of the index.
pub fn light_controls() -> [LightControl; 16] {
    std::array::from_fn(|m| LightControl {
        lighting: m & 8 != 0,
        specular_enable: m & 4 != 0,
        separate_specular: m & 2 != 0,
        specular_alpha_from_vertex: m & 1 != 0,
    })
}

/// The narrow mode sets' directional light: (0.6, 0.9, 0.5), length ≈ 1.19, so
/// `normalize_directional` changes its registers (none of its components is exact at
/// M = 6).
const NARROW_MODE_DIRECTION: [f64; 4] = [0.6, 0.9, 0.5, 0.0];

/// The mode sets' light specular colour: unequal channels, so the separate specular
/// colour's channels differ (the configurations' lights are grey: a swap of two
/// secondary channels would pass them).
const MODE_SPECULAR: [f64; 3] = [1.0, 0.7, 0.4];

/// SET_SPECULAR_PARAMS for power 125 as nxdk_pgraph_tests' Specular suite writes them
/// (`NonUnitNormal`): the numerator's zero −k0 = 0.972162 and the denominator's
/// −k2/k1 = 1.00868 bracket x = 1, so an x past either gives no specular.
pub const POW125_PARAMS: [f32; 6] = [-0.972162, -3.20637, 3.23421, -0.945147, -3.14027, 3.19512];

/// The specular-curve mode sets: (configuration, curve name, its words, light control).
/// Narrow (no GL_NORMALIZE: x = N·h runs past 1, so both of the power-125 curve's
/// zeros are inside its range) and the default's widths (x ≤ 1: the numerator's zero
/// inside), each curve with GL's colour and with light control (separate, or joined
/// to the primary). The narrow "Pow 16" set has an infinite viewer (no normalise at
/// all): there the curve's 2 adds take II from 8 to 9 (⌈33/4⌉; pow's is ⌈31/4⌉ = 8), so
/// the testbench's cycle check sees whether the Verilog counts them.
fn curve_modes() -> [(RtlConfig, &'static str, [f32; 6], Option<LightControl>); 6] {
    let lc = |separate_specular, specular_alpha_from_vertex| {
        Some(LightControl {
            separate_specular,
            specular_alpha_from_vertex,
            ..LightControl::default()
        })
    };
    [
        (RtlConfig::Narrow, "curve125", POW125_PARAMS, None),
        (RtlConfig::Narrow, "curve125", POW125_PARAMS, lc(true, true)),
        (RtlConfig::Narrow, "curve16", POW16_PARAMS, lc(true, false)),
        (RtlConfig::Default, "curve16", POW16_PARAMS, None),
        (RtlConfig::Default, "curve16", POW16_PARAMS, lc(true, true)),
        (
            RtlConfig::Default,
            "curve125",
            POW125_PARAMS,
            lc(false, true),
        ),
    ]
}

/// A light-control set's name: `lit`, `spec`, `sep`, `valpha` (the four switches) 0 or 1.
fn light_control_name(lc: &LightControl) -> String {
    format!(
        "lit{}_spec{}_sep{}_valpha{}",
        u8::from(lc.lighting),
        u8::from(lc.specular_enable),
        u8::from(lc.separate_specular),
        u8::from(lc.specular_alpha_from_vertex)
    )
}

/// The NV2A modes (`normalize_directional`, `light_control`) beyond the two
/// configurations, each a set of `count` vertices tagged
/// `vertex_lighting_<config>_<mode>`:
/// * narrow (E 4, M 6, truncate, 12-bit colours, no GL_NORMALIZE, a local viewer) with
///   a directional light of length ≈ 1.19 (`NARROW_MODE_DIRECTION`), specular colour
///   `MODE_SPECULAR` as in every mode set: the direction
///   normalised at load (`nd1`) or as written (`nd0`), each with GL's single colour
///   (`gl`) and with every light-control switch set ([`light_controls`]): 34 sets;
/// * default (IEEE single, nearest-even, GL_NORMALIZE, 16-bit colours) with its local
///   spot light, so k = att·spot scales both sums: every switch set, 16 sets;
/// * the NV2A specular curve (`specular_curve`, `curve_modes`): the ControlFlags
///   tests' "Pow 16" words ([`POW16_PARAMS`]) and the power-125 words
///   (`POW125_PARAMS`), at narrow (the light as the `nd1` sets') and the default,
///   with GL's colour and with light control: 6 sets, tagged
///   `…_curve16_…` / `…_curve125_…`.
///
/// The vertices are shaped as the configurations' (the module docs) with no fault
/// corners, from `seed` in every set (so the sets of one configuration with the same
/// input word, e.g. nd0 and nd1 of one switch set, see the same vertices); the vertex's diffuse and specular colours are the drawn words as they
/// are, the first eighth from the corners 0, 1, the midpoint ± 0, max − 1 and max.
pub fn vertex_lighting_mode_sets(count: usize, seed: u64) -> Result<Vec<VectorSet>, String> {
    let mut modes = Vec::new();
    for nd in [false, true] {
        let lcs = std::iter::once(None).chain(light_controls().map(Some));
        for lc in lcs {
            let (mut cfg, mut setup) = setup_of(RtlConfig::Narrow);
            cfg.normalize_directional = nd;
            cfg.light_control = lc;
            setup.lights[0].position = NARROW_MODE_DIRECTION;
            setup.lights[0].specular = MODE_SPECULAR;
            let name = lc.as_ref().map_or("gl".into(), light_control_name);
            modes.push((
                RtlConfig::Narrow,
                format!("nd{}_{name}", u8::from(nd)),
                cfg,
                setup,
            ));
        }
    }
    for lc in light_controls() {
        let (mut cfg, mut setup) = setup_of(RtlConfig::Default);
        cfg.light_control = Some(lc);
        setup.lights[0].specular = MODE_SPECULAR;
        modes.push((RtlConfig::Default, light_control_name(&lc), cfg, setup));
    }
    for (config, curve, words, lc) in curve_modes() {
        let (mut cfg, mut setup) = setup_of(config);
        cfg.light_control = lc;
        cfg.specular_curve = SpecularCurve::nv2a(words);
        setup.lights[0].specular = MODE_SPECULAR;
        let mut name = format!(
            "{curve}_{}",
            lc.as_ref().map_or("gl".into(), light_control_name)
        );
        if config == RtlConfig::Narrow {
            setup.lights[0].position = NARROW_MODE_DIRECTION;
            let viewer = if curve == "curve16" {
                cfg.local_viewer = false;
                "_iv"
            } else {
                ""
            };
            name = format!("nd1{viewer}_{name}");
        }
        modes.push((config, name, cfg, setup));
    }
    // One seed for all: the sets of one configuration and input width (every light-
    // control set of a configuration, nd0 and nd1 alike) see the same vertices.
    modes
        .into_iter()
        .map(|(config, name, cfg, setup)| {
            let u = VertexLighting::new(cfg, &setup).map_err(|e| e.to_string())?;
            let params = verilog_params(&u)?;
            let probe = VertexLightingIn::default();
            let make = shaper(&u);
            let mut v = collect(&u, (), config, probe, make, params, count, seed);
            v.variant = Some(name);
            Ok(v)
        })
        .collect()
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

    /// `light_with` without a fault is the kernel; the fault corners come first and
    /// each changes the output under its fault.
    #[test]
    fn fault_corners_lead_and_the_datapath_copy_is_the_kernel() {
        use rtl_model::Unit;
        for c in RtlConfig::ALL {
            let u = unit_of(c).unwrap();
            let make = shaper(&u);
            let corners = fault_corners(&u, &make, 4, 20_000, 3);
            let mut rng = seeded(9);
            let mut ctr = Counters::default();
            let shaped = (0..3000).map(|_| {
                let raw: Vec<u64> = (0..6).map(|_| rng.random_range(0..1u64 << 20)).collect();
                make(&raw)
            });
            for x in corners.iter().copied().chain(shaped) {
                let y = u.kernel(&mut (), &x, &mut ctr);
                assert_eq!(
                    light_with(&u, &x, Fault::None).rgb,
                    y.rgba[..3],
                    "{c:?} {x:?}"
                );
            }
            for x in &corners {
                let good = light_with(&u, x, Fault::None).rgb;
                assert!(FAULTS.iter().any(|&f| light_with(&u, x, f).rgb != good));
            }
            let set = vertex_lighting_vectors(c, 1000, 3).unwrap();
            assert_eq!(set.stimulus.len(), 1000);
            for (k, x) in fault_corners(&u, &make, 1000 / 64, CORNER_TRIES, 3)
                .iter()
                .enumerate()
            {
                assert_eq!(
                    set.stimulus[k],
                    super::super::vector_set::pack_hex(&u.in_signals(x))
                );
            }
        }
        // Every fault is found at the default (nearest-even, a local spot light) with
        // tests/rtl_cosim.rs's seed.
        let u = unit_of(RtlConfig::Default).unwrap();
        let corners = fault_corners(&u, &shaper(&u), CORNERS_PER_FAULT, CORNER_TRIES, 20);
        for f in FAULTS {
            let n = corners
                .iter()
                .filter(|x| light_with(&u, x, f).rgb != light_with(&u, x, Fault::None).rgb)
                .count();
            assert!(n > 0, "{f:?}: no corner");
        }
    }
}
