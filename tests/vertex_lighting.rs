//! vertex_lighting against its f64 twin (the GL 1.x lighting equation), under a bound
//! derived from the float format's widths.
//!
//! Bound derivation (also in docs/units.md, `## vertex_lighting`). u = 2^−(M+1)
//! (nearest-even) or 2^−M (truncate) is the relative error of one rounding to a normal
//! value; a₀ = 2^emin (flushed) or 2^(emin−M) (kept subnormals) covers a result that
//! lands below the normal range. Every value x of the datapath is tracked as (x̂, e):
//! x̂ its exact value (f64 on the twin's inputs) and e a bound on |computed − x̂|,
//! propagated through the unit's operations IN THE UNIT'S ORDER (the evaluator
//! [`Bound`] below mirrors `VertexLighting::light` op for op):
//! * an input or loaded register is one rounding of a host value: e = its actual
//!   rounding error (≤ u|x̂| + a₀; 0 for a value the format holds exactly);
//! * a·b: e = (|â|e_b + |b̂|e_a + e_a e_b)(1 + u) + u|âb̂| + a₀ (the propagated error,
//!   then one rounding of a value within |âb̂| + propagated);
//! * a + b: e = (e_a + e_b)(1 + u) + u|â + b̂| + a₀;
//! * rsq, rcp of x ∈ [x̂ − e, x̂ + e], x̂ − e > 0: the functions are monotone and convex,
//!   so the propagated error is f(x̂ − e) − f(x̂); then one rounding (they are exactly
//!   rounded). x̂ − e ≤ 0 (a nearly zero vector) has no finite bound: such a vertex is
//!   not checked (it is a stiff case with its own test below);
//! * max(x, 0) and the final clamp to [0, 1] are 1-Lipschitz (no new error);
//! * pow(x, s) (float_format's log2 → mul → exp2): with x' ∈ [x̂ ± e_x], s' ∈ [ŝ ± e_s],
//!   the computed log2 is low by δ ∈ [0, ε_L], it and s'·L are rounded (ρ ≤
//!   (1 + u)² − 1), exp2 errs by η_exp and rounds (u): the result lies in
//!   [min x'^(s'(1±ρ))·2^(−s'ε_L(1+ρ))·(1 − η), max x'^(s'(1±ρ))·(1 + η)], the extremes
//!   at the corners (x'^a is monotone in x' and in a). The bound is the larger distance
//!   of these ends from x̂^ŝ. This is where the specular power amplifies relative
//!   error: an error ε in N·h becomes ≈ s·ε in the highlight, and ε_L becomes s·ε_L·ln 2;
//! * a branch the unit takes on a computed value (f = [N·L > 0], the spot cutoff
//!   c ≥ cos(cutoff)) is ambiguous when the threshold lies within the error interval:
//!   then the bound covers both outcomes (the full term or 0);
//! * the output: |code − 255·clamp(ĉ)| ≤ (2ⁿ − 1)·e_c + ½ (exact final rounding).
//!
//! f64 slack: the twin and the evaluator are f64 computations of ≲ 10³ operations on
//! values ≤ 10⁴: 10⁻⁹ level, added.

mod common;

use glare_pipeline::pipeline::shading::vertex_float::gl_lighting;
use glare_pipeline::reference::vertex_lighting::{
    light_vertex, light_vertex_nv2a, normalize, to_levels, GlLighting, Nv2aSwitches,
};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::float_format::{FloatFormat, Rounding, Subnormals};
use rtl_model::units::vertex_lighting::{
    Light, LightingSetup, Material, SpecularCurve, VertexLighting, VertexLightingConfig,
    VertexLightingIn,
};
use rtl_model::{Counters, Unit, UnitSummary};

type V3 = [f64; 3];

/// (exact value, bound on the computed value's distance from it).
#[derive(Clone, Copy, Debug)]
struct Val {
    v: f64,
    e: f64,
}

/// The error-bound evaluator for one format.
struct Bound {
    fmt: FloatFormat,
    u: f64,
    a0: f64,
    max: f64,
    eps_l: f64,
    eta: f64,
}

impl Bound {
    fn new(f: &FloatFormat) -> Self {
        let u = 2f64.powi(f.unit_roundoff_log2());
        Bound {
            fmt: *f,
            u,
            a0: match f.subnormals {
                Subnormals::Flush => 2f64.powi(f.emin()),
                Subnormals::Keep => 2f64.powi(f.emin() - f.mant_bits as i32),
            },
            max: f.to_f64(f.max_finite(false)),
            eps_l: f.log2_abs_error(),
            eta: (1.0 + f.exp2_rel_error()) * (1.0 + u) - 1.0,
        }
    }

    fn exact(&self, v: f64) -> Val {
        Val { v, e: 0.0 }
    }

    /// One rounding of a value computed exactly within ±prop of v.
    fn round(&self, v: f64, prop: f64) -> Val {
        let e = prop * (1.0 + self.u) + self.u * v.abs() + self.a0;
        // Saturation is not modelled by the bound: no bound past the range.
        let e = if v.abs() + e > self.max {
            f64::INFINITY
        } else {
            e
        };
        Val { v, e }
    }

    /// A host value rounded once into a register or input word: its exact error.
    fn load(&self, v: f64) -> Val {
        let mut ctr = Counters::default();
        let q = self
            .fmt
            .to_f64(self.fmt.from_f64("x", v, &mut ctr).unwrap());
        Val {
            v,
            e: (q - v).abs(),
        }
    }

    fn mul(&self, a: Val, b: Val) -> Val {
        self.round(a.v * b.v, a.v.abs() * b.e + b.v.abs() * a.e + a.e * b.e)
    }

    fn add(&self, a: Val, b: Val) -> Val {
        self.round(a.v + b.v, a.e + b.e)
    }

    fn neg(&self, a: Val) -> Val {
        Val { v: -a.v, e: a.e }
    }

    fn max0(&self, a: Val) -> Val {
        Val {
            v: a.v.max(0.0),
            e: a.e,
        }
    }

    /// f decreasing and convex on x > 0 (1/√x, 1/x): exactly rounded.
    fn convex(&self, x: Val, f: fn(f64) -> f64) -> Val {
        let lo = x.v.abs() - x.e;
        if lo <= 0.0 || !x.e.is_finite() {
            return Val {
                v: f(x.v.abs().max(f64::MIN_POSITIVE)),
                e: f64::INFINITY,
            };
        }
        let y = f(x.v.abs());
        self.round(y, f(lo) - y)
    }

    fn rsq(&self, x: Val) -> Val {
        self.convex(x, |x| 1.0 / x.sqrt())
    }

    fn rcp(&self, x: Val) -> Val {
        self.convex(x, |x| 1.0 / x)
    }

    fn dot3(&self, a: &[Val; 3], b: &[Val; 3]) -> Val {
        let s = self.add(self.mul(a[0], b[0]), self.mul(a[1], b[1]));
        self.add(s, self.mul(a[2], b[2]))
    }

    fn normalise(&self, v: &[Val; 3]) -> [Val; 3] {
        let r = self.rsq(self.dot3(v, v));
        v.map(|c| self.mul(c, r))
    }

    fn pow(&self, x: Val, s: Val) -> Val {
        if s.v == 0.0 && s.e == 0.0 {
            return self.exact(1.0);
        }
        let p = |x: f64, s: f64| if s == 0.0 { 1.0 } else { x.max(0.0).powf(s) };
        let y = p(x.v, s.v);
        if !x.e.is_finite() {
            return Val {
                v: y,
                e: f64::INFINITY,
            };
        }
        let rho = (1.0 + self.u).powi(2) - 1.0;
        let (mut hi, mut lo) = (0.0f64, f64::INFINITY);
        for xc in [(x.v - x.e).max(0.0), x.v + x.e] {
            for sc in [(s.v - s.e).max(0.0), s.v + s.e] {
                for r in [-rho, rho] {
                    let a = p(xc, sc * (1.0 + r));
                    hi = hi.max(a);
                    lo = lo.min(a);
                }
            }
        }
        let s_hi = s.v + s.e;
        let hi = hi * (1.0 + self.eta);
        let lo = lo * (-s_hi * self.eps_l * (1.0 + rho)).exp2() * (1.0 - self.eta);
        Val {
            v: y,
            e: (hi - y).max(y - lo) + self.a0,
        }
    }

    /// A branch on a computed value: `cand` if the condition holds exactly, else 0;
    /// `sure_true` / `sure_false` say whether the error interval decides it.
    fn branch(&self, holds: bool, sure: bool, cand: Val) -> Val {
        match (holds, sure) {
            (true, true) => cand,
            (false, true) => self.exact(0.0),
            // Unit may take 0 or the candidate; twin takes the candidate.
            (true, false) => Val {
                v: cand.v,
                e: cand.e.max(cand.v.abs()),
            },
            // Twin takes 0; the unit may take the candidate.
            (false, false) => Val {
                v: 0.0,
                e: cand.v.abs() + cand.e,
            },
        }
    }

    fn vec_in(&self, v: V3) -> [Val; 3] {
        v.map(|c| self.load(c))
    }
}

/// The bound on |code − level| per channel (levels of the output unorm), or None
/// where the vertex is too ill-conditioned for a finite bound.
fn level_bound(cfg: &VertexLightingConfig, gl: &GlLighting, p: V3, n: V3) -> [Option<f64>; 3] {
    let b = Bound::new(&cfg.format);
    let m = &gl.state.material;
    let pv = b.vec_in(p);
    let nv = b.vec_in(n);
    let nn = if gl.normalize { b.normalise(&nv) } else { nv };
    let v = if gl.local_viewer {
        b.normalise(&pv.map(|c| b.neg(c)))
    } else {
        [b.exact(0.0), b.exact(0.0), b.exact(1.0)]
    };
    let shin = b.load(m.shininess);
    let mut acc: [Val; 3] =
        [0, 1, 2].map(|k| b.load(m.emission[k] + m.ambient[k] * gl.state.scene_ambient[k]));
    for l in &gl.state.lights {
        let (lv, att) = if l.position[3] != 0.0 {
            let w = l.position[3];
            let lp = [0, 1, 2].map(|k| b.load(l.position[k] / w));
            let vp = [0, 1, 2].map(|k| b.add(lp[k], b.neg(pv[k])));
            let d2 = b.dot3(&vp, &vp);
            let r = b.rsq(d2);
            let lv = vp.map(|c| b.mul(c, r));
            let d = b.mul(d2, r);
            let k = l.attenuation.map(|c| b.load(c));
            let den = b.add(k[0], b.mul(k[1], d));
            let den = b.add(den, b.mul(k[2], d2));
            (lv, b.rcp(den))
        } else {
            let dir = normalize([l.position[0], l.position[1], l.position[2]]);
            (b.vec_in(dir), b.exact(1.0))
        };
        let spot = if l.spot_cutoff == 180.0 {
            b.exact(1.0)
        } else {
            let sd = b.vec_in(normalize(l.spot_direction));
            let c = b.neg(b.dot3(&lv, &sd));
            let cosc = b.load(l.spot_cutoff.to_radians().cos());
            let margin = c.v - cosc.v;
            let cand = b.pow(c, b.load(l.spot_exponent));
            b.branch(margin >= 0.0, margin.abs() > c.e + cosc.e, cand)
        };
        let nl_raw = b.dot3(&nn, &lv);
        let nl = b.max0(nl_raw);
        let hv = [0, 1, 2].map(|k| b.add(lv[k], v[k]));
        let h = b.normalise(&hv);
        let nh = b.max0(b.dot3(&nn, &h));
        let cand = match cfg.specular_curve.coefficients() {
            None => b.pow(nh, shin),
            // The NV2A curve: (x + k0)·rcp(k1·x + k2), 0 unless both are positive.
            Some(k) => {
                let k = k.map(|c| b.load(c));
                let num = b.add(nh, k[0]);
                let den = b.add(b.mul(k[1], nh), k[2]);
                let q = b.mul(num, b.rcp(den));
                let holds = num.v > 0.0 && den.v > 0.0;
                let sure = num.v.abs() > num.e && den.v.abs() > den.e;
                b.branch(holds, sure, q)
            }
        };
        let spec = b.branch(nl_raw.v > 0.0, nl_raw.v.abs() > nl_raw.e, cand);
        let k = b.mul(att, spot);
        for (c, a) in acc.iter_mut().enumerate() {
            let amb = b.load(m.ambient[c] * l.ambient[c]);
            let dif = b.load(m.diffuse[c] * l.diffuse[c]);
            let spc = b.load(m.specular[c] * l.specular[c]);
            let t = b.add(amb, b.mul(nl, dif));
            let t = b.add(t, b.mul(spec, spc));
            *a = b.add(*a, b.mul(k, t));
        }
    }
    let scale = ((1u64 << cfg.color_bits) - 1) as f64;
    acc.map(|a| a.e.is_finite().then_some(scale * a.e + 0.5 + 1e-9))
}

fn fmt(e: u32, m: u32, r: Rounding, s: Subnormals) -> FloatFormat {
    FloatFormat::new(e, m)
        .unwrap()
        .with_rounding(r)
        .with_subnormals(s)
}

/// The configurations the bound is checked at (≥ 3, narrow ones included).
fn bound_configs() -> Vec<(&'static str, VertexLightingConfig)> {
    let g = VertexLightingConfig::geforce();
    let with = |f: FloatFormat, local_viewer: bool| VertexLightingConfig {
        format: f,
        local_viewer,
        ..g
    };
    vec![
        ("geforce e8m23", g),
        (
            "e8m23 local viewer, kept subnormals",
            with(fmt(8, 23, Rounding::NearestEven, Subnormals::Keep), true),
        ),
        (
            "fp16-like e5m10",
            with(fmt(5, 10, Rounding::NearestEven, Subnormals::Keep), false),
        ),
        (
            "NARROW e5m7",
            with(fmt(5, 7, Rounding::NearestEven, Subnormals::Flush), true),
        ),
        (
            "e8m12 truncating",
            with(fmt(8, 12, Rounding::Truncate, Subnormals::Flush), false),
        ),
        (
            "NARROW e6m4 (10-bit colours)",
            VertexLightingConfig {
                color_bits: 10,
                ..with(fmt(6, 4, Rounding::NearestEven, Subnormals::Flush), false)
            },
        ),
    ]
}

fn rand_colour(rng: &mut ChaCha8Rng) -> [f64; 3] {
    [(); 3].map(|_| rng.random_range(0.0..1.0))
}

fn rand_dir(rng: &mut ChaCha8Rng) -> V3 {
    loop {
        let v: V3 = [(); 3].map(|_| rng.random_range(-1.0..1.0));
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if l > 0.2 && l <= 1.0 {
            return v.map(|c| c / l);
        }
    }
}

/// A random GL state with `lights` lights (kinds, spots, attenuation all mixed).
fn random_setup(rng: &mut ChaCha8Rng, lights: usize) -> LightingSetup {
    let shininess = match rng.random_range(0..6) {
        0 => 0.0,
        1 => rng.random_range(0.0..1.0),
        2 => 128.0,
        3 => rng.random_range(1000.0..1.0e4),
        _ => rng.random_range(1.0..128.0),
    };
    let [r, g, b] = rand_colour(rng);
    let material = Material {
        emission: rand_colour(rng).map(|c| 0.2 * c),
        ambient: rand_colour(rng),
        diffuse: [r, g, b, rng.random_range(0.0..1.0)],
        specular: rand_colour(rng),
        shininess,
    };
    let lights = (0..lights)
        .map(|_| {
            let local = rng.random::<bool>();
            let position = if local {
                let p = [(); 3].map(|_| rng.random_range(-6.0..6.0));
                [p[0], p[1], p[2], 1.0]
            } else {
                let d = rand_dir(rng);
                [d[0], d[1], d[2], 0.0]
            };
            let (spot_cutoff, spot_exponent) = match rng.random_range(0..4) {
                0 => (rng.random_range(10.0..90.0), rng.random_range(0.0..128.0)),
                1 => (90.0, rng.random_range(0.0..4.0)),
                _ => (180.0, 0.0),
            };
            Light {
                position,
                ambient: rand_colour(rng).map(|c| 0.3 * c),
                diffuse: rand_colour(rng),
                specular: rand_colour(rng),
                spot_direction: rand_dir(rng),
                spot_exponent,
                spot_cutoff,
                attenuation: [
                    rng.random_range(0.5..1.5),
                    rng.random_range(0.0..0.5),
                    rng.random_range(0.0..0.2),
                ],
            }
        })
        .collect();
    LightingSetup {
        material,
        scene_ambient: rand_colour(rng).map(|c| 0.3 * c),
        lights,
    }
}

/// A vertex in front of the eye (−z) and a normal of length 0.5 ..= 2 (unit without
/// GL_NORMALIZE).
fn random_vertex(rng: &mut ChaCha8Rng, normalize_on: bool) -> (V3, V3) {
    let p = [
        rng.random_range(-2.0..2.0),
        rng.random_range(-2.0..2.0),
        rng.random_range(-6.0..-1.0),
    ];
    let n = rand_dir(rng);
    let n = if normalize_on {
        n.map(|c| c * rng.random_range(0.5..2.0))
    } else {
        n
    };
    (p, n)
}

/// Unit vs twin at one vertex; returns the largest |Δ|/bound over the channels, or
/// None when a bound was not finite (that channel unchecked).
fn check(u: &VertexLighting, gl: &GlLighting, p: V3, n: V3) -> Option<f64> {
    let cfg = u.config();
    let mut ctr = Counters::default();
    let input = u.vertex_from_f64(p, n, &mut ctr).unwrap();
    let out = u.kernel(&mut (), &input, &mut ctr);
    let want = match cfg.specular_curve.coefficients() {
        None => light_vertex(gl, p, n),
        // GL's single sum with the NV2A curve: the twin's joined primary colour.
        Some(k) => {
            let sw = Nv2aSwitches {
                normalize_directional: true,
                lighting: true,
                specular_enable: true,
                separate_specular: false,
                specular_alpha_from_vertex: false,
                specular_curve: Some(k),
            };
            light_vertex_nv2a(gl, &sw, p, n, [0.0; 4], [0.0; 4]).0
        }
    };
    let bounds = level_bound(&cfg, gl, p, n);
    let mut checked = true;
    let mut worst: f64 = 0.0;
    for c in 0..3 {
        let level = to_levels(want[c], cfg.color_bits);
        match bounds[c] {
            Some(bound) => {
                let d = (out.rgba[c] as f64 - level).abs();
                assert!(
                    d <= bound,
                    "{:?} channel {c}: code {} vs level {level} (|Δ| {d} > bound {bound}); p {p:?} n {n:?}",
                    cfg.format,
                    out.rgba[c]
                );
                worst = worst.max(d / bound);
            }
            None => checked = false,
        }
    }
    // Alpha: the diffuse alpha rounded once to the format, then to the unorm.
    let a = to_levels(want[3], cfg.color_bits);
    let scale = ((1u64 << cfg.color_bits) - 1) as f64;
    let ua = 2f64.powi(cfg.format.unit_roundoff_log2());
    assert!((out.rgba[3] as f64 - a).abs() <= 0.5 + scale * ua * want[3] + 1e-9);
    checked.then_some(worst)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    /// Every bound config, 1 ..= 8 lights of every kind, one vertex each.
    #[test]
    fn within_bound_vs_twin(ci in 0usize..6, lights in 1usize..=8, seed in any::<u64>()) {
        let (_, cfg) = bound_configs()[ci];
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let setup = random_setup(&mut rng, lights);
        let u = VertexLighting::new(cfg, &setup).unwrap();
        let gl = gl_lighting(&cfg, &setup);
        for _ in 0..4 {
            let (p, n) = random_vertex(&mut rng, cfg.normalize);
            check(&u, &gl, p, n);
        }
    }
}

/// The NV2A's SET_SPECULAR_PARAMS curve as the XDK's driver generates it for a power
/// (k0 in −0.9995 ..= 0 and k1 below it, k2 = 1 + k0 − k1: the shapes of the test
/// program's sets, Pow1 … Pow24, MechAssault …), or a random set of the same form.
fn random_curve(rng: &mut ChaCha8Rng) -> SpecularCurve {
    const SETS: [[f32; 3]; 6] = [
        [-0.803673, -2.7813, 2.97762],
        [-0.972162, -3.20637, 3.23421],
        [0.0, -0.494592, 1.49459],
        [-0.0, 0.9, 0.1],
        [-0.838916, -2.887156, 3.048239],
        [-0.421539, -1.70592, 2.28438],
    ];
    let k = if rng.random_range(0..3) == 0 {
        let k0: f32 = rng.random_range(-0.9995..0.0);
        let k1: f32 = rng.random_range(-3.6..1.0);
        [k0, k1, 1.0 + k0 - k1]
    } else {
        SETS[rng.random_range(0..SETS.len())]
    };
    SpecularCurve::nv2a([k[0], k[1], k[2], 0.0, 0.0, 0.0])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    /// The NV2A specular curve (`specular_curve`) in every bound config, 1 ..= 8
    /// lights: within the width-derived bound of the twin's `nv2a_specular` (the
    /// evaluator runs the unit's order: x + k0, k1·x + k2, rcp, ·, the sign branch).
    #[test]
    fn nv2a_curve_within_bound_vs_twin(ci in 0usize..6, lights in 1usize..=8, seed in any::<u64>()) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let cfg = VertexLightingConfig {
            specular_curve: random_curve(&mut rng),
            ..bound_configs()[ci].1
        };
        let setup = random_setup(&mut rng, lights);
        let u = VertexLighting::new(cfg, &setup).unwrap();
        let gl = gl_lighting(&cfg, &setup);
        for _ in 0..4 {
            let (p, n) = random_vertex(&mut rng, cfg.normalize);
            check(&u, &gl, p, n);
        }
    }
}

/// The curve's anchors, exact in IEEE single: 1 at x = 1 (k2 = 1 + k0 − k1), 0 at
/// and below x = −k0, 0 past the denominator's zero −k2/k1 (the NonUnitNormal
/// captures: normals of length 0.972 and 1.009 give no specular at power 125), and
/// above pow(x, 16) near the ControlFlags quads' N·h = 0.93 (the captures' +1 level).
#[test]
fn nv2a_curve_anchors() {
    let p125 = [
        -0.972162f32,
        -3.20637,
        3.23421,
        -0.945147,
        -3.14027,
        3.19512,
    ];
    let setup = |shininess: f64| {
        let mut m = shiny();
        m.shininess = shininess;
        m.specular = [1.0; 3];
        m.diffuse = [0.0, 0.0, 0.0, 1.0];
        m.ambient = [0.0; 3];
        m.emission = [0.0; 3];
        let light = Light {
            position: [0.0, 0.0, 1.0, 0.0],
            ambient: [0.0; 3],
            diffuse: [0.0; 3],
            specular: [1.0; 3],
            ..Light::default()
        };
        LightingSetup {
            scene_ambient: [0.0; 3],
            ..one_light_setup(light, m)
        }
    };
    let cfg = VertexLightingConfig {
        normalize: false,
        specular_curve: SpecularCurve::nv2a(p125),
        ..VertexLightingConfig::geforce()
    };
    let u = VertexLighting::new(cfg, &setup(0.0)).unwrap();
    // N = length·(0, 0, 1), L = V = (0, 0, 1): N·h = length.
    let at = |len: f64| run(&u, [0.0, 0.0, -7.0], [0.0, 0.0, len]).0[0];
    assert_eq!(at(1.0), 255, "f(1) = 1");
    assert_eq!(at(0.972), 0, "below −k0");
    assert!(at(0.973) > 0, "just above −k0");
    assert!(at(1.008) > 0, "below the pole");
    assert_eq!(at(1.009), 0, "past the denominator's zero");
    let pow16 = [-0.803673f32, -2.7813, 2.97762, -0.64766, -2.36199, 2.71433];
    let c16 = VertexLighting::new(
        VertexLightingConfig {
            specular_curve: SpecularCurve::nv2a(pow16),
            ..cfg
        },
        &setup(0.0),
    )
    .unwrap();
    let p16 = VertexLighting::new(VertexLightingConfig { ..cfg_power(cfg) }, &setup(16.0)).unwrap();
    let x: f64 = 0.93;
    let n = [(1.0 - x * x).sqrt(), 0.0, x];
    let (c, p) = (
        run(&c16, [0.0, 0.0, -7.0], n).0[0],
        run(&p16, [0.0, 0.0, -7.0], n).0[0],
    );
    assert!(c > p, "curve {c} above pow16 {p} at N·h = 0.93");
}

fn cfg_power(cfg: VertexLightingConfig) -> VertexLightingConfig {
    VertexLightingConfig {
        specular_curve: SpecularCurve::Power,
        ..cfg
    }
}

/// Tick, span and batch drivers agree with the NV2A curve (and light control).
#[test]
fn drivers_agree_with_nv2a_curve() {
    let mut rng = ChaCha8Rng::seed_from_u64(16);
    for lights in [1usize, 3] {
        let setup = random_setup(&mut rng, lights);
        for lc in [None, Some(LightControl::default())] {
            let cfg = VertexLightingConfig {
                light_control: lc,
                specular_curve: random_curve(&mut rng),
                ..VertexLightingConfig::geforce()
            };
            let u = VertexLighting::new(cfg, &setup).unwrap();
            let mut ctr = Counters::default();
            let inputs: Vec<VertexLightingIn> = (0..16)
                .map(|_| {
                    let (p, n) = random_vertex(&mut rng, true);
                    let mut i = u.vertex_from_f64(p, n, &mut ctr).unwrap();
                    i.diffuse = rand_colours(&mut rng, 8);
                    i.specular = rand_colours(&mut rng, 8);
                    i
                })
                .collect();
            common::assert_drivers_agree(&u, (), &inputs);
        }
    }
}

/// A non-finite coefficient is an error naming the field.
#[test]
fn nv2a_curve_rejects_non_finite() {
    let cfg = VertexLightingConfig {
        specular_curve: SpecularCurve::nv2a([f32::NAN, 0.0, 1.0, 0.0, 0.0, 0.0]),
        ..VertexLightingConfig::geforce()
    };
    let e = VertexLighting::new(cfg, &LightingSetup::default()).unwrap_err();
    assert_eq!(e.field(), "vertex_lighting.specular_curve.params");
}

/// Most vertices get a finite bound in every config (the check is not vacuous), and
/// the default is tight: IEEE single is within ½ level + a hair on every channel.
#[test]
fn bounds_are_finite_and_single_is_tight() {
    for (name, cfg) in bound_configs() {
        let mut rng = ChaCha8Rng::seed_from_u64(77);
        let (mut checked, mut total) = (0, 0);
        let mut worst: f64 = 0.0;
        let mut bounds: Vec<f64> = Vec::new();
        for _ in 0..200 {
            let lights = rng.random_range(1..=8);
            let setup = random_setup(&mut rng, lights);
            let u = VertexLighting::new(cfg, &setup).unwrap();
            let gl = gl_lighting(&cfg, &setup);
            let (p, n) = random_vertex(&mut rng, cfg.normalize);
            total += 1;
            if let Some(r) = check(&u, &gl, p, n) {
                checked += 1;
                worst = worst.max(r);
                let b = level_bound(&cfg, &gl, p, n);
                bounds.extend(b.into_iter().flatten());
            }
            // 0 < s < 1 makes x^s non-Lipschitz at x = 0 (a computed N·h of 10⁻⁷ where the
            // exact one clamps to 0 gives 10⁻⁷^0.1 = 0.2): the bound rightly grows there,
            // so tightness is asserted for exponents 0 or ≥ 1 (GL's practical range).
            let steep = |x: f64| x > 0.0 && x < 1.0;
            let smooth = !steep(setup.material.shininess)
                && setup.lights.iter().all(|l| !steep(l.spot_exponent));
            if smooth && cfg.format.mant_bits == 23 && cfg.format.rounding == Rounding::NearestEven
            {
                let b = level_bound(&cfg, &gl, p, n);
                for x in b.into_iter().flatten() {
                    // ½ for the output rounding plus the datapath: shininess 10⁴ amplifies
                    // ε_L (s·ε_L·ln 2 ≈ 10⁴·2.4·2⁻²⁷ ≈ 2·10⁻⁴), and s < 1 makes x^s steep
                    // near x = 0 (d/dx x^0.2 = 0.2·x^−0.8): still under a level.
                    assert!(
                        x < 1.0,
                        "{name}: bound {x} levels; {setup:?} p {p:?} n {n:?}"
                    );
                }
            }
        }
        // At M = 4 a computed N·h of 1 + 2⁻⁴ raised to s = 10⁴ leaves the range: no
        // finite bound there (the unit saturates, counted), so fewer vertices qualify.
        bounds.sort_by(f64::total_cmp);
        let q = |f: f64| bounds[((bounds.len() - 1) as f64 * f) as usize];
        println!(
            "{name}: {checked}/{total} vertices with a finite bound; bound median {:.3}, 90 % {:.3} levels; worst |Δ|/bound {worst:.3}",
            q(0.5),
            q(0.9)
        );
        let need = if cfg.format.mant_bits >= 7 { 0.9 } else { 0.5 };
        assert!(
            checked as f64 >= need * total as f64,
            "{name}: only {checked}/{total} checked"
        );
    }
}

fn one_light_setup(light: Light, material: Material) -> LightingSetup {
    LightingSetup {
        material,
        scene_ambient: [0.2; 3],
        lights: vec![light],
    }
}

fn shiny() -> Material {
    Material {
        emission: [0.0; 3],
        ambient: [0.2, 0.3, 0.4],
        diffuse: [0.6, 0.5, 0.4, 1.0],
        specular: [0.9; 3],
        shininess: 32.0,
    }
}

fn run(u: &VertexLighting, p: V3, n: V3) -> ([u32; 4], Counters) {
    let mut ctr = Counters::default();
    let i = u.vertex_from_f64(p, n, &mut ctr).unwrap();
    (u.kernel(&mut (), &i, &mut ctr).rgba, ctr)
}

/// The ambient-only colour (e + a_m·a_s + a_m·a_i, att = spot = 1) in levels.
fn ambient_only(m: &Material, l: &Light, ambient: [f64; 3]) -> [u32; 3] {
    [0, 1, 2].map(|c| {
        let v = m.emission[c] + m.ambient[c] * ambient[c] + m.ambient[c] * l.ambient[c];
        (v.clamp(0.0, 1.0) * 255.0).round() as u32
    })
}

/// Zero-length normal with GL_NORMALIZE: rsq(0) saturates (counted), N = 0, the vertex
/// gets the ambient terms only (documented); no NaN, no panic, in every format.
#[test]
fn stiff_zero_length_normal() {
    let light = Light {
        ambient: [0.1, 0.2, 0.3],
        ..Light::default()
    };
    let setup = one_light_setup(light, shiny());
    for (_, cfg) in bound_configs() {
        let u = VertexLighting::new(
            VertexLightingConfig {
                color_bits: 8,
                ..cfg
            },
            &setup,
        )
        .unwrap();
        let (rgba, ctr) = run(&u, [0.0, 0.0, -3.0], [0.0; 3]);
        assert!(ctr.saturations >= 1, "rsq(0) counted");
        let want = ambient_only(&setup.material, &light, setup.scene_ambient);
        for c in 0..3 {
            assert!(
                rgba[c].abs_diff(want[c]) <= 1,
                "{:?}: {rgba:?} vs {want:?}",
                cfg.format
            );
        }
    }
}

/// A light behind the surface (N·L < 0) and grazing light (N·L exactly 0): no diffuse,
/// f = 0 so no specular even where N·h > 0 (shininess 1: N·h ≈ 0.7 would add ~160
/// levels); ambient only. Tilting the grazing light by 10⁻³ toward N brings the
/// highlight back (the test can tell f apart).
#[test]
fn stiff_behind_and_grazing() {
    let broad = Material {
        shininess: 1.0,
        ..shiny()
    };
    let tilted = Light {
        position: [1.0, 0.0, 1.0e-3, 0.0],
        ..Light::default()
    };
    let u = VertexLighting::new(
        VertexLightingConfig::geforce(),
        &one_light_setup(tilted, broad),
    )
    .unwrap();
    let (rgba, _) = run(&u, [0.0, 0.0, -3.0], [0.0, 0.0, 1.0]);
    assert!(
        rgba[0] > 150,
        "tilted light: highlight expected, got {rgba:?}"
    );
    for dir in [[0.3, 0.2, -1.0], [1.0, 0.0, 0.0]] {
        let light = Light {
            position: [dir[0], dir[1], dir[2], 0.0],
            ambient: [0.1, 0.1, 0.1],
            ..Light::default()
        };
        let setup = one_light_setup(light, broad);
        for (_, cfg) in bound_configs() {
            let cfg = VertexLightingConfig {
                color_bits: 8,
                ..cfg
            };
            let u = VertexLighting::new(cfg, &setup).unwrap();
            let (rgba, _) = run(&u, [0.0, 0.0, -3.0], [0.0, 0.0, 1.0]);
            let want = ambient_only(&setup.material, &light, setup.scene_ambient);
            for c in 0..3 {
                assert!(
                    rgba[c].abs_diff(want[c]) <= 1,
                    "{dir:?} {:?}: {rgba:?} vs {want:?}",
                    cfg.format
                );
            }
        }
    }
}

/// Shininess 1 ..= 128 (GL's range) and up to the model's 10⁴: within the bound at the
/// default and the narrow format, looking straight into the highlight and off it.
#[test]
fn stiff_shininess_range() {
    for s in [1.0, 2.0, 8.0, 32.0, 128.0, 1000.0, 1.0e4] {
        let m = Material {
            shininess: s,
            ..shiny()
        };
        let light = Light {
            position: [0.2, 0.1, 1.0, 0.0],
            ..Light::default()
        };
        let setup = one_light_setup(light, m);
        for (_, cfg) in bound_configs() {
            let u = VertexLighting::new(cfg, &setup).unwrap();
            let gl = gl_lighting(&cfg, &setup);
            for n in [
                [0.1, 0.05, 1.0],
                [0.1, 0.06, 1.0],
                [0.3, -0.2, 1.0],
                [0.0, 0.0, 1.0],
            ] {
                let n = if cfg.normalize { n } else { normalize(n) };
                check(&u, &gl, [0.0, 0.0, -3.0], n);
            }
        }
    }
}

/// Huge attenuation: the light vanishes (att → 0, underflow at narrow formats is fine);
/// zero attenuation (k = 0, 0, 0): rcp(0) saturates (counted) and every channel with a
/// positive term clamps to white, as the twin (att = f64::MAX).
#[test]
fn stiff_attenuation_extremes() {
    let base = Light {
        position: [1.0, 1.0, 0.0, 1.0],
        ..Light::default()
    };
    for (_, cfg) in bound_configs() {
        let cfg = VertexLightingConfig {
            color_bits: 8,
            ..cfg
        };
        let huge = one_light_setup(
            Light {
                attenuation: [1.0e4, 1.0e4, 1.0e4],
                ..base
            },
            shiny(),
        );
        let u = VertexLighting::new(cfg, &huge).unwrap();
        let (rgba, _) = run(&u, [0.0, 0.0, -3.0], [0.0, 0.0, 1.0]);
        let m = shiny();
        let want = [0, 1, 2].map(|c| (m.ambient[c] * 0.2 * 255.0).round() as u32);
        for c in 0..3 {
            assert!(rgba[c].abs_diff(want[c]) <= 1, "{:?}: {rgba:?}", cfg.format);
        }
        let zero = one_light_setup(
            Light {
                attenuation: [0.0; 3],
                ..base
            },
            shiny(),
        );
        let u = VertexLighting::new(cfg, &zero).unwrap();
        let (rgba, ctr) = run(&u, [0.0, 0.0, -3.0], [0.0, 0.0, 1.0]);
        assert_eq!(rgba, [255, 255, 255, 255]);
        assert!(ctr.saturations >= 1);
        let gl = gl_lighting(&cfg, &zero);
        let t = light_vertex(&gl, [0.0, 0.0, -3.0], [0.0, 0.0, 1.0]);
        assert!(t.iter().all(|x| !x.is_nan()) && t[..3].iter().all(|&x| x >= 1.0));
        // A light exactly at the vertex: L = 0, d = 0, att = 1/k_c; no NaN.
        let (rgba, _) = run(
            &VertexLighting::new(cfg, &one_light_setup(base, shiny())).unwrap(),
            [1.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        );
        let twin = light_vertex(
            &gl_lighting(&cfg, &one_light_setup(base, shiny())),
            [1.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        );
        for c in 0..3 {
            assert!(rgba[c].abs_diff((twin[c].clamp(0.0, 1.0) * 255.0).round() as u32) <= 1);
        }
    }
}

/// Spot cutoff 180 (no spot) against 90 (a half-space): a vertex behind the spot
/// direction is lit with 180 and only ambient-free of the light's terms with 90.
#[test]
fn stiff_spot_cutoff_180_vs_90() {
    let spot = |cutoff: f64| Light {
        position: [0.0, 0.0, 0.0, 1.0],
        spot_direction: [0.0, 0.0, -1.0],
        spot_cutoff: cutoff,
        spot_exponent: 2.0,
        ..Light::default()
    };
    for (_, cfg) in bound_configs() {
        let cfg = VertexLightingConfig {
            color_bits: 8,
            ..cfg
        };
        for cutoff in [180.0, 90.0] {
            let setup = one_light_setup(spot(cutoff), shiny());
            let u = VertexLighting::new(cfg, &setup).unwrap();
            let gl = gl_lighting(&cfg, &setup);
            // In front of the spot (z < 0) and behind it (z > 0), facing the light.
            for (p, n) in [
                ([0.5, 0.0, -3.0], [0.0, 0.0, 1.0]),
                ([0.5, 0.0, 3.0], [0.0, 0.0, -1.0]),
            ] {
                check(&u, &gl, p, n);
                let (rgba, _) = run(&u, p, n);
                if cutoff == 90.0 && p[2] > 0.0 {
                    let m = shiny();
                    let want = [0, 1, 2].map(|c| (m.ambient[c] * 0.2 * 255.0).round() as u32);
                    for c in 0..3 {
                        assert!(rgba[c].abs_diff(want[c]) <= 1, "{rgba:?} vs {want:?}");
                    }
                }
            }
        }
    }
}

/// Tick and span drivers agree (outputs, counters, cycles = the timing), 0, 1 and 8 lights.
#[test]
fn drivers_agree() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for lights in [0, 1, 8] {
        let setup = random_setup(&mut rng, lights);
        for (_, cfg) in bound_configs().into_iter().take(4) {
            let u = VertexLighting::new(cfg, &setup).unwrap();
            let mut ctr = Counters::default();
            let inputs: Vec<VertexLightingIn> = (0..24)
                .map(|_| {
                    let (p, n) = random_vertex(&mut rng, cfg.normalize);
                    u.vertex_from_f64(p, n, &mut ctr).unwrap()
                })
                .collect();
            common::assert_drivers_agree(&u, (), &inputs);
        }
    }
}

/// Invalid configs and inputs are errors naming the field, never a panic.
#[test]
fn config_errors_name_the_field() {
    let g = VertexLightingConfig::geforce();
    let ok = LightingSetup::default();
    let err = |cfg: VertexLightingConfig, s: &LightingSetup| {
        VertexLighting::new(cfg, s).unwrap_err().field().to_string()
    };
    assert_eq!(
        err(g.with_format(8, 0), &ok),
        "vertex_lighting.format.mant_bits"
    );
    assert_eq!(
        err(g.with_format(12, 10), &ok),
        "vertex_lighting.format.exp_bits"
    );
    assert_eq!(
        err(
            VertexLightingConfig {
                color_bits: 17,
                ..g
            },
            &ok
        ),
        "vertex_lighting.color_bits"
    );
    let with_light = |l: Light| LightingSetup {
        lights: vec![Light::default(), l],
        ..LightingSetup::default()
    };
    assert_eq!(
        err(
            g,
            &LightingSetup {
                lights: vec![Light::default(); 9],
                ..ok.clone()
            }
        ),
        "vertex_lighting.lights"
    );
    assert_eq!(
        err(
            g,
            &with_light(Light {
                diffuse: [f64::NAN, 0.0, 0.0],
                ..Light::default()
            })
        ),
        "vertex_lighting.lights[1].diffuse"
    );
    assert_eq!(
        err(
            g,
            &with_light(Light {
                specular: [-0.5, 0.0, 0.0],
                ..Light::default()
            })
        ),
        "vertex_lighting.lights[1].specular"
    );
    assert_eq!(
        err(
            g,
            &with_light(Light {
                spot_cutoff: 120.0,
                ..Light::default()
            })
        ),
        "vertex_lighting.lights[1].spot_cutoff"
    );
    assert_eq!(
        err(
            g,
            &with_light(Light {
                spot_exponent: 2.0e4,
                spot_cutoff: 45.0,
                ..Light::default()
            })
        ),
        "vertex_lighting.lights[1].spot_exponent"
    );
    assert_eq!(
        err(
            g,
            &with_light(Light {
                spot_direction: [0.0; 3],
                spot_cutoff: 45.0,
                ..Light::default()
            })
        ),
        "vertex_lighting.lights[1].spot_direction"
    );
    assert_eq!(
        err(
            g,
            &with_light(Light {
                position: [0.0; 4],
                ..Light::default()
            })
        ),
        "vertex_lighting.lights[1].position"
    );
    assert_eq!(
        err(
            g,
            &with_light(Light {
                attenuation: [1.0, f64::INFINITY, 0.0],
                ..Light::default()
            })
        ),
        "vertex_lighting.lights[1].attenuation"
    );
    let bad_shine = LightingSetup {
        material: Material {
            shininess: 1.0e5,
            ..Material::default()
        },
        ..ok.clone()
    };
    assert_eq!(err(g, &bad_shine), "vertex_lighting.material.shininess");
    let u = VertexLighting::geforce();
    let mut ctr = Counters::default();
    assert_eq!(
        u.vertex_from_f64([0.0, f64::NAN, 0.0], [0.0; 3], &mut ctr)
            .unwrap_err()
            .field(),
        "vertex_lighting.position"
    );
    assert_eq!(
        u.vertex_from_f64([0.0; 3], [f64::INFINITY, 0.0, 0.0], &mut ctr)
            .unwrap_err()
            .field(),
        "vertex_lighting.normal"
    );
}

/// The summary is well formed and the calibration holds: one light, GL_NORMALIZE,
/// infinite viewer → II 8 (15 M vertices/s at 120 MHz).
#[test]
fn summary_and_calibration() {
    let u = VertexLighting::geforce();
    let s = UnitSummary::of(&u);
    assert_eq!(s.name, "vertex_lighting");
    assert_eq!(s.ii, 8);
    assert!(s.gates_nand2 > 0.0 && s.ram_bits > 0);
    assert!(s
        .widths
        .iter()
        .any(|w| w.name == "mant_bits" && w.bits == 23));
}

// ------------------------------------------------------------------ NV2A modes

use rtl_model::units::vertex_lighting::LightControl;

fn with_control(cfg: VertexLightingConfig, lc: LightControl) -> VertexLightingConfig {
    VertexLightingConfig {
        light_control: Some(lc),
        ..cfg
    }
}

fn all_controls() -> Vec<LightControl> {
    let mut v = Vec::new();
    for bits in 0u32..16 {
        v.push(LightControl {
            lighting: bits & 1 != 0,
            specular_enable: bits & 2 != 0,
            separate_specular: bits & 4 != 0,
            specular_alpha_from_vertex: bits & 8 != 0,
        });
    }
    v
}

fn rand_colours(rng: &mut ChaCha8Rng, bits: u32) -> [u32; 4] {
    let max = (1u32 << bits) - 1;
    std::array::from_fn(|_| rng.random_range(0..=max))
}

fn run2(u: &VertexLighting, i: &VertexLightingIn) -> ([u32; 4], [u32; 4]) {
    let mut ctr = Counters::default();
    let o = u.kernel(&mut (), i, &mut ctr);
    (o.rgba, o.secondary)
}

/// The switches' routing, exact for every combination: lighting off passes the vertex
/// colours through; specular disabled gives (0, 0, 0, max); the secondary alpha is the
/// vertex's specular alpha only with `specular_alpha_from_vertex`; the default (no light
/// control) leaves the secondary colour zero.
#[test]
fn light_control_routing_is_exact() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for bits in [1u32, 5, 8, 12] {
        let max = (1u32 << bits) - 1;
        let setup = random_setup(&mut rng, 2);
        let base = VertexLightingConfig {
            color_bits: bits,
            ..VertexLightingConfig::geforce()
        };
        let gl = VertexLighting::new(base, &setup).unwrap();
        for lc in all_controls() {
            let u = VertexLighting::new(with_control(base, lc), &setup).unwrap();
            for _ in 0..200 {
                let (p, n) = random_vertex(&mut rng, true);
                let mut ctr = Counters::default();
                let mut i = u.vertex_from_f64(p, n, &mut ctr).unwrap();
                i.diffuse = rand_colours(&mut rng, bits);
                i.specular = rand_colours(&mut rng, bits);
                let (pri, sec) = run2(&u, &i);
                let (gl_pri, gl_sec) = run2(&gl, &i);
                assert_eq!(gl_sec, [0; 4], "no light control: no secondary colour");
                if !lc.lighting {
                    assert_eq!(pri, i.diffuse, "{lc:?}: diffuse passes through");
                }
                if !lc.specular_enable {
                    assert_eq!(sec, [0, 0, 0, max], "{lc:?}: specular disabled");
                } else {
                    let a = if lc.specular_alpha_from_vertex {
                        i.specular[3]
                    } else {
                        max
                    };
                    assert_eq!(sec[3], a, "{lc:?}: secondary alpha");
                    if !lc.lighting || !lc.separate_specular {
                        assert_eq!(sec[..3], i.specular[..3], "{lc:?}: specular passes");
                    }
                }
                if lc.lighting {
                    assert_eq!(pri[3], gl_pri[3], "{lc:?}: primary alpha = material's");
                }
            }
        }
    }
}

/// Separate specular splits GL's single sum exactly: the primary equals the GL path
/// with the material's specular zeroed, the secondary equals the GL path with
/// emission, ambient and diffuse zeroed (the same operations in the same order, the
/// zero terms adding exactly), so both inherit the GL path's width-derived bound
/// against the twin (`within_bound_vs_twin`). Specular disabled or not separate: the
/// primary is the one sum, identical between the two (the switch only routes).
#[test]
fn separate_specular_splits_the_gl_sum_exactly() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let split = LightControl::default();
    for (name, cfg) in bound_configs() {
        for lights in [1usize, 3, 8] {
            let setup = random_setup(&mut rng, lights);
            let mut no_spec = setup.clone();
            no_spec.material.specular = [0.0; 3];
            let mut spec_only = setup.clone();
            spec_only.material.emission = [0.0; 3];
            spec_only.material.ambient = [0.0; 3];
            spec_only.material.diffuse = [0.0, 0.0, 0.0, setup.material.diffuse[3]];
            let u = VertexLighting::new(with_control(cfg, split), &setup).unwrap();
            let joined = |specular_enable| LightControl {
                specular_enable,
                separate_specular: false,
                ..split
            };
            let j_on = VertexLighting::new(with_control(cfg, joined(true)), &setup).unwrap();
            let j_off = VertexLighting::new(with_control(cfg, joined(false)), &setup).unwrap();
            let gl_d = VertexLighting::new(cfg, &no_spec).unwrap();
            let gl_s = VertexLighting::new(cfg, &spec_only).unwrap();
            for _ in 0..50 {
                let (p, n) = random_vertex(&mut rng, cfg.normalize);
                let mut ctr = Counters::default();
                let i = u.vertex_from_f64(p, n, &mut ctr).unwrap();
                let (pri, sec) = run2(&u, &i);
                assert_eq!(pri, run2(&gl_d, &i).0, "{name}: primary");
                assert_eq!(sec[..3], run2(&gl_s, &i).0[..3], "{name}: secondary");
                assert_eq!(run2(&j_on, &i).0, run2(&j_off, &i).0, "{name}: joined");
            }
        }
    }
}

/// A directional light kept as written (`normalize_directional` off) scales N·L by its
/// length: L = 2·d̂ with diffuse colour c gives exactly what d̂ with 2c gives (a power
/// of two scales every product exactly), specular off.
#[test]
fn unnormalised_direction_scales_n_dot_l_exactly() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let cfg = VertexLightingConfig {
        normalize_directional: false,
        ..VertexLightingConfig::geforce()
    };
    for _ in 0..20 {
        let mut m = shiny();
        m.specular = [0.0; 3];
        let c = [0.1, 0.2, 0.3].map(|x: f64| x * rng.random_range(0.5..1.5));
        let light = |w: f64, d: [f64; 3]| Light {
            position: [0.0, 0.0, w, 0.0],
            diffuse: d,
            ..Light::default()
        };
        let long = VertexLighting::new(cfg, &one_light_setup(light(2.0, c), m)).unwrap();
        let unit =
            VertexLighting::new(cfg, &one_light_setup(light(1.0, c.map(|x| 2.0 * x)), m)).unwrap();
        let normalised = VertexLighting::new(
            VertexLightingConfig::geforce(),
            &one_light_setup(light(2.0, c), m),
        )
        .unwrap();
        let plain = VertexLighting::new(cfg, &one_light_setup(light(1.0, c), m)).unwrap();
        for _ in 0..50 {
            let (p, n) = random_vertex(&mut rng, true);
            assert_eq!(run(&long, p, n).0, run(&unit, p, n).0);
            // GL's normalisation at load: the length-2 vector acts as the unit one.
            assert_eq!(run(&normalised, p, n).0, run(&plain, p, n).0);
        }
    }
}

/// The twin's two colours: separate specular splits `light_vertex` (primary +
/// secondary = GL's sum, f64 to 1e-12); lighting off and specular disabled route the
/// vertex colours as the unit does.
#[test]
fn twin_light_control_matches_gl_sum() {
    let mut rng = ChaCha8Rng::seed_from_u64(14);
    for lights in [1usize, 4] {
        let setup = random_setup(&mut rng, lights);
        let gl = GlLighting {
            state: setup,
            normalize: true,
            local_viewer: false,
        };
        for _ in 0..100 {
            let (p, n) = random_vertex(&mut rng, true);
            let dv = [0.1, 0.2, 0.3, 0.4];
            let sv = [0.5, 0.6, 0.7, 0.8];
            let sw = |lighting, specular_enable, separate_specular| Nv2aSwitches {
                normalize_directional: true,
                lighting,
                specular_enable,
                separate_specular,
                specular_alpha_from_vertex: true,
                specular_curve: None,
            };
            let whole = light_vertex(&gl, p, n);
            let (pri, sec) = light_vertex_nv2a(&gl, &sw(true, true, true), p, n, dv, sv);
            for c in 0..3 {
                assert!((pri[c] + sec[c] - whole[c]).abs() <= 1e-12 * (1.0 + whole[c].abs()));
            }
            assert_eq!(sec[3], sv[3]);
            let (pri, sec) = light_vertex_nv2a(&gl, &sw(true, false, true), p, n, dv, sv);
            for c in 0..3 {
                assert!((pri[c] - whole[c]).abs() <= 1e-12 * (1.0 + whole[c].abs()));
            }
            assert_eq!(sec, [0.0, 0.0, 0.0, 1.0]);
            let (pri, sec) = light_vertex_nv2a(&gl, &sw(false, true, false), p, n, dv, sv);
            assert_eq!(pri, dv);
            assert_eq!(sec, sv);
        }
    }
}

/// Tick, span and batch drivers agree with light control on (colours in the input).
#[test]
fn drivers_agree_with_light_control() {
    let mut rng = ChaCha8Rng::seed_from_u64(15);
    let setup = random_setup(&mut rng, 2);
    for lc in all_controls() {
        let cfg = with_control(VertexLightingConfig::geforce(), lc);
        let u = VertexLighting::new(cfg, &setup).unwrap();
        let mut ctr = Counters::default();
        let inputs: Vec<VertexLightingIn> = (0..16)
            .map(|_| {
                let (p, n) = random_vertex(&mut rng, true);
                let mut i = u.vertex_from_f64(p, n, &mut ctr).unwrap();
                i.diffuse = rand_colours(&mut rng, 8);
                i.specular = rand_colours(&mut rng, 8);
                i
            })
            .collect();
        common::assert_drivers_agree(&u, (), &inputs);
    }
}

/// Light control's cost is its own part and nothing else: 0 without it; with it the
/// total grows by exactly that part, which holds the secondary colour's converters (as
/// many as the primary's: both sums are converted in the same clock), so it exceeds
/// the primary's conversion part by the registers and muxes, at every colour width.
#[test]
fn light_control_cost_is_its_own_part_with_the_secondary_converters() {
    const PART: &str =
        "light control (vertex colours, specular sum, secondary colour and its conversion, routing)";
    let part = |u: &VertexLighting, name: &str| {
        common::cost_part(&u.cost(), name).unwrap_or_else(|| panic!("no part {name}"))
    };
    let setup = LightingSetup::default();
    for bits in [1, 5, 8, 16] {
        for (e, m) in [(8, 23), (5, 10), (4, 6)] {
            let gl_cfg = VertexLightingConfig {
                color_bits: bits,
                ..VertexLightingConfig::geforce().with_format(e, m)
            };
            let gl = VertexLighting::new(gl_cfg, &setup).unwrap();
            let lc =
                VertexLighting::new(with_control(gl_cfg, LightControl::default()), &setup).unwrap();
            assert_eq!(part(&gl, PART), 0.0);
            let extra = lc.cost().gates_nand2() - gl.cost().gates_nand2();
            assert!((extra - part(&lc, PART)).abs() < 1e-6, "{bits} e{e}m{m}");
            let conv = part(&gl, "unorm conversion (3 × significand × (2^n − 1), round)");
            // Registers: 8 + 4 colours in and out and 3 words; muxes 4 + 8 colours.
            let w = 1 + e + m;
            let regs = rtl_model::cost::prim::register(12 * bits + 3 * w).nand2_eq();
            let muxes = rtl_model::cost::prim::mux(12 * bits).nand2_eq();
            assert!(
                (part(&lc, PART) - (conv + regs + muxes)).abs() < 1e-6,
                "{bits} e{e}m{m}: {} against {conv} + {regs} + {muxes}",
                part(&lc, PART)
            );
        }
    }
}

/// The NV2A curve's cost is its own part: 0 under pow; with the curve the total grows by
/// exactly that part, its three coefficient registers k0, k1, k2 of one word each
/// (the adds, multiplies and RCP run on the shared lanes), at every format.
#[test]
fn the_nv2a_curve_costs_its_three_coefficient_registers() {
    const PART: &str = "NV2A specular curve coefficients (k0, k1, k2)";
    let part = |u: &VertexLighting| {
        common::cost_part(&u.cost(), PART).unwrap_or_else(|| panic!("no part {PART}"))
    };
    let setup = LightingSetup::default();
    for (e, m) in [(8, 23), (5, 10), (4, 6)] {
        let pow_cfg = VertexLightingConfig::geforce().with_format(e, m);
        let curve_cfg = VertexLightingConfig {
            specular_curve: SpecularCurve::nv2a([-0.5, 0.5, 0.0, 0.0, 0.0, 0.0]),
            ..pow_cfg
        };
        let pow = VertexLighting::new(pow_cfg, &setup).unwrap();
        let curve = VertexLighting::new(curve_cfg, &setup).unwrap();
        assert_eq!(part(&pow), 0.0, "e{e}m{m}");
        let w = 1 + e + m;
        let regs = rtl_model::cost::prim::register(3 * w).nand2_eq();
        assert!(
            (part(&curve) - regs).abs() < 1e-9,
            "e{e}m{m}: {} against {regs}",
            part(&curve)
        );
        let extra = curve.cost().gates_nand2() - pow.cost().gates_nand2();
        assert!((extra - regs).abs() < 1e-6, "e{e}m{m}");
    }
}

/// The VCD trace's wires: P and N as words of the format in; with light control also the
/// vertex's diffuse and specular colours in and the secondary colour out, as colour
/// codes; the lit colour out.
#[test]
fn trace_signals_are_the_vertex_words_and_the_colour_codes() {
    use rtl_model::float_format::Fp;
    use rtl_model::units::vertex_lighting::VertexLightingOut;
    let setup = LightingSetup::default();
    let input = VertexLightingIn {
        position: [Fp(1), Fp(2), Fp(3)],
        normal: [Fp(4), Fp(5), Fp(6)],
        diffuse: [7, 8, 9, 10],
        specular: [11, 12, 13, 14],
    };
    let out = VertexLightingOut {
        rgba: [21, 22, 23, 24],
        secondary: [25, 26, 27, 28],
    };
    for (e, m, bits) in [(8, 23, 8), (5, 10, 5)] {
        let cfg = VertexLightingConfig {
            color_bits: bits,
            ..VertexLightingConfig::geforce().with_format(e, m)
        };
        let w = 1 + e + m;
        let vertex: Vec<_> = ["px", "py", "pz", "nx", "ny", "nz"]
            .into_iter()
            .zip(1..)
            .map(|(n, v)| (n, w, v))
            .collect();
        let colours = |names: [&'static str; 4], first: u64| {
            names
                .into_iter()
                .zip(first..)
                .map(move |(n, v)| (n, bits, v))
        };
        let gl = VertexLighting::new(cfg, &setup).unwrap();
        assert_eq!(common::wires(&gl.in_signals(&input)), vertex);
        assert_eq!(
            common::wires(&gl.out_signals(&out)),
            colours(["r", "g", "b", "a"], 21).collect::<Vec<_>>()
        );
        let lc = VertexLighting::new(with_control(cfg, LightControl::default()), &setup).unwrap();
        let lc_in: Vec<_> = vertex
            .iter()
            .copied()
            .chain(colours(["dr", "dg", "db", "da"], 7))
            .chain(colours(["sr", "sg", "sb", "sa"], 11))
            .collect();
        assert_eq!(common::wires(&lc.in_signals(&input)), lc_in);
        let lc_out: Vec<_> = colours(["r", "g", "b", "a"], 21)
            .chain(colours(["r2", "g2", "b2", "a2"], 25))
            .collect();
        assert_eq!(common::wires(&lc.out_signals(&out)), lc_out);
    }
}

// ------------------------------------------------- the host's load, register by register

/// The registers the host loads read back as its values rounded into the format: one
/// register set per enabled light (a directional light's vector normalised, a local
/// light's position divided by w), the material's e_m + a_m·a_s, shininess and alpha.
#[test]
fn loaded_registers_are_the_host_values_rounded() {
    let cfg = VertexLightingConfig::geforce();
    let fmt = cfg.format;
    let w = |x: f64| fmt.from_f64("test", x, &mut Counters::default()).unwrap();
    let mut setup = LightingSetup {
        lights: vec![
            Light {
                position: [0.0, 0.0, 2.0, 0.0],
                ..Light::default()
            },
            Light {
                position: [1.0, 2.0, 3.0, 2.0],
                ..Light::default()
            },
            Light {
                position: [0.0, 3.0, 4.0, 0.0],
                ..Light::default()
            },
        ],
        ..LightingSetup::default()
    };
    setup.material.emission = [0.1, 0.2, 0.3];
    setup.material.ambient = [0.5, 0.25, 1.0];
    setup.material.diffuse[3] = 0.5;
    setup.material.shininess = 12.0;
    setup.scene_ambient = [0.4, 0.4, 0.4];
    let vl = VertexLighting::new(cfg, &setup).unwrap();
    assert_eq!(vl.light_count(), 3);
    let regs = vl.light_registers();
    assert_eq!(regs.len(), 3);
    assert!(!regs[0].local && regs[1].local && !regs[2].local);
    assert_eq!(regs[0].vector, [w(0.0), w(0.0), w(1.0)]);
    assert_eq!(regs[1].vector, [w(0.5), w(1.0), w(1.5)]);
    assert_eq!(regs[2].vector, [w(0.0), w(0.6), w(0.8)]);
    let (base, shininess, alpha) = vl.material_registers();
    let m = &setup.material;
    assert_eq!(
        base,
        [0, 1, 2].map(|c| w(m.emission[c] + m.ambient[c] * setup.scene_ambient[c]))
    );
    assert_eq!(shininess, w(12.0));
    assert_eq!(
        alpha,
        fmt.to_unorm(w(0.5), cfg.color_bits, &mut Counters::default())
    );
    // No light: none loaded.
    setup.lights.clear();
    assert_eq!(VertexLighting::new(cfg, &setup).unwrap().light_count(), 0);
}

/// A light's direction that is no direction (zero, or too long for f64) is refused
/// naming the field, not loaded as NaN or zero.
#[test]
fn a_zero_or_overflowing_light_vector_is_refused() {
    for (position, spot) in [
        ([0.0, 0.0, 0.0, 0.0], [0.0, 0.0, -1.0]),
        ([1e200, 1e200, 0.0, 0.0], [0.0, 0.0, -1.0]),
        ([0.0, 0.0, 1.0, 1.0], [0.0, 0.0, 0.0]),
        ([0.0, 0.0, 1.0, 1.0], [1e200, 0.0, 1e200]),
    ] {
        for normalize_directional in [true, false] {
            let cfg = VertexLightingConfig {
                normalize_directional,
                ..VertexLightingConfig::geforce()
            };
            let setup = LightingSetup {
                lights: vec![Light {
                    position,
                    spot_direction: spot,
                    spot_cutoff: 30.0,
                    ..Light::default()
                }],
                ..LightingSetup::default()
            };
            let e = VertexLighting::new(cfg, &setup)
                .expect_err(&format!("{position:?} {spot:?} loaded"))
                .to_string();
            let field = if spot == [0.0, 0.0, -1.0] {
                "lights[0].position"
            } else {
                "lights[0].spot_direction"
            };
            assert!(e.contains(field) && e.contains("non-zero finite"), "{e}");
        }
    }
}

/// A config written before `normalize_directional` existed (the key absent) reads back
/// with it on, GL's behaviour.
#[test]
fn a_config_without_normalize_directional_normalises() {
    let mut v = serde_json::to_value(VertexLightingConfig {
        normalize_directional: false,
        ..VertexLightingConfig::geforce()
    })
    .unwrap();
    v.as_object_mut().unwrap().remove("normalize_directional");
    let cfg: VertexLightingConfig = serde_json::from_value(v).unwrap();
    assert!(cfg.normalize_directional);
}

/// The NV2A curve's k0, k1, k2 are loaded one rounding each (the pow curve loads none),
/// and a host value the format cannot hold is counted at the load.
#[test]
fn curve_registers_and_load_counters_are_what_the_host_loaded() {
    let curve = SpecularCurve::nv2a([-0.972162, 0.5, 0.75, 0.0, 0.0, 0.0]);
    let cfg = VertexLightingConfig {
        specular_curve: curve,
        ..VertexLightingConfig::geforce()
    };
    let w = |x: f64| {
        cfg.format
            .from_f64("test", x, &mut Counters::default())
            .unwrap()
    };
    let vl = VertexLighting::new(cfg, &LightingSetup::default()).unwrap();
    let k = curve.coefficients().unwrap();
    assert_eq!(vl.curve_registers(), Some(k.map(w)));
    assert_eq!(
        vl.load_counters(),
        Counters::default(),
        "nothing rounded out of range"
    );
    let pow = VertexLighting::new(VertexLightingConfig::geforce(), &LightingSetup::default());
    assert_eq!(pow.unwrap().curve_registers(), None);
    // e5m4 holds at most 2^16·(2 − 2^−4): an emission of 10⁹ saturates at the load.
    let narrow = VertexLightingConfig::geforce().with_format(5, 4);
    let mut setup = LightingSetup::default();
    setup.material.emission = [1e9, 0.0, 0.0];
    let vl = VertexLighting::new(narrow, &setup).unwrap();
    assert!(
        vl.load_counters().saturations >= 1,
        "{:?}",
        vl.load_counters()
    );
}

/// Issues per vertex follow the documented schedule (docs/units.md, vertex_lighting):
/// per light 36 multiplies, 28 adds, 7 special-function ops; GL_NORMALIZE and a local
/// viewer 6, 2, 1 each; two colours 3 more multiplies per light and 3 adds; the NV2A
/// curve 1 more multiply and 2 more adds per light and one fewer special op. II is
/// the busiest resource's share (6 multipliers, 4 adders, 1 special unit).
#[test]
fn issues_and_ii_follow_the_documented_schedule() {
    for n in [0usize, 1, 3] {
        for (normalize, local_viewer) in [(false, false), (true, false), (true, true)] {
            for two_colours in [false, true] {
                for nv2a in [false, true] {
                    let cfg = VertexLightingConfig {
                        normalize,
                        local_viewer,
                        light_control: two_colours.then(LightControl::default),
                        specular_curve: if nv2a {
                            SpecularCurve::nv2a([-0.5, 0.5, 0.75, 0.0, 0.0, 0.0])
                        } else {
                            SpecularCurve::Power
                        },
                        ..VertexLightingConfig::geforce()
                    };
                    let setup = LightingSetup {
                        lights: vec![Light::default(); n],
                        ..LightingSetup::default()
                    };
                    let vl = VertexLighting::new(cfg, &setup).unwrap();
                    let (n, k) = (n as u32, normalize as u32 + local_viewer as u32);
                    let (lc, c) = (two_colours as u32, nv2a as u32);
                    let i = vl.issues();
                    let what = format!("{n} lights, k {k}, two colours {lc}, nv2a {c}");
                    assert_eq!(i.muls, 36 * n + 6 * k + 3 * n * lc + n * c, "{what}");
                    assert_eq!(i.adds, 28 * n + 2 * k + 3 * lc + 2 * n * c, "{what}");
                    assert_eq!(i.specials, 7 * n + k - n * c, "{what}");
                    let ii = i
                        .muls
                        .div_ceil(6)
                        .max(i.adds.div_ceil(4))
                        .max(i.specials)
                        .max(1);
                    assert_eq!(vl.timing().ii, ii, "{what}");
                    assert_eq!(vl.timing().latency, ii + 6, "{what}");
                }
            }
        }
    }
}
