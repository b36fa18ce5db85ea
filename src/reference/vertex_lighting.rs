//! f64 twin of `vertex_lighting`: the OpenGL 1.x lighting equation (GL 1.x spec
//! §2.13.1, "Lighting"), for the front face, in eye space:
//!
//! c = e_cm + a_cm·a_cs + Σ_i att_i·spot_i·(a_cm·a_cli + (n ⊙ VP̂_pli)·d_cm·d_cli
//!     + f_i·(n ⊙ ĥ_i)^s_rm·s_cm·s_cli),
//!
//! with u ⊙ v = max(u·v, 0); f_i = 1 if n ⊙ VP̂_pli ≠ 0, else 0;
//! att_i = 1/(k_0i + k_1i‖VP_pli‖ + k_2i‖VP_pli‖²) if P_pli's w ≠ 0, else 1
//! (attenuation only for local lights); spot_i = (P̂_pliV ⊙ ŝ_dli)^s_rli if
//! c_rli ≠ 180 and P̂_pliV·ŝ_dli ≥ cos(c_rli), 0 if c_rli ≠ 180 and below, 1 if
//! c_rli = 180; ĥ_i = normalize(VP̂_pli + VP̂_e) for a local viewer, normalize(VP̂_pli +
//! (0, 0, 1)) for an infinite one. The alpha is the material's diffuse alpha.
//!
//! The unit's conventions for degenerate vectors, mirrored here so that no NaN comes
//! out: normalize(0) = 0 (a zero-length normal with GL_NORMALIZE, a light at the
//! vertex, L = −V, a local viewer at the vertex); a zero attenuation denominator gives
//! att = f64::MAX (the unit saturates to its largest finite value). Directional light
//! and spot directions are normalised (the unit does it at load; `light_vertex_nv2a`
//! can keep the directional vector as given, the NV2A mode). Colours are
//! non-negative (the unit refuses negative ones), so no ∞ − ∞ can arise.

use rtl_model::lighting_state::{Light, LightingSetup};

/// The lighting state and the two switches the equation depends on.
#[derive(Clone, Debug, PartialEq)]
pub struct GlLighting {
    /// Material, scene ambient and lights (GL's state, `rtl_model::lighting_state`).
    pub state: LightingSetup,
    /// GL_NORMALIZE.
    pub normalize: bool,
    /// GL_LIGHT_MODEL_LOCAL_VIEWER.
    pub local_viewer: bool,
}

type V3 = [f64; 3];

pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// v/‖v‖, or 0 for a zero (or non-finite-length) vector.
pub fn normalize(v: V3) -> V3 {
    let l = dot(v, v).sqrt();
    if l > 0.0 && l.is_finite() {
        v.map(|c| c / l)
    } else {
        [0.0; 3]
    }
}

/// One light's factors at a vertex (for error studies).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightTerms {
    /// Unit vector toward the light.
    pub l: V3,
    pub att: f64,
    pub spot: f64,
    /// n·L before the max.
    pub n_dot_l: f64,
    /// max(n·ĥ, 0) (0 when f = 0).
    pub n_dot_h: f64,
    /// (n ⊙ ĥ)^s_rm · f.
    pub specular: f64,
}

/// The per-light factors of light `l` at eye-space position `p` with normal `n`
/// (already normalised if GL_NORMALIZE applies).
pub fn light_terms(s: &GlLighting, l: &Light, p: V3, n: V3) -> LightTerms {
    light_terms_dir(s, l, p, n, true, None)
}

/// The NV2A's specular curve of x = max(N·h, 0) with its coefficients (k0, k1, k2)
/// (`vertex_lighting`'s `SpecularCurve::Nv2aParams`): (x + k0)/(k1·x + k2), 0 unless
/// the numerator and the denominator are both positive.
pub fn nv2a_specular(x: f64, k: [f64; 3]) -> f64 {
    let num = x + k[0];
    let den = k[1] * x + k[2];
    if num > 0.0 && den > 0.0 {
        num / den
    } else {
        0.0
    }
}

/// [`light_terms`] with the directional vector normalised (GL) or used as given
/// (`normalize_directional` false: the NV2A's register as the host wrote it).
fn light_terms_dir(
    s: &GlLighting,
    l: &Light,
    p: V3,
    n: V3,
    normalize_directional: bool,
    curve: Option<[f64; 3]>,
) -> LightTerms {
    let local = l.position[3] != 0.0;
    let (lv, att) = if local {
        let w = l.position[3];
        let vp = [0, 1, 2].map(|k| l.position[k] / w - p[k]);
        let d2 = dot(vp, vp);
        let d = d2.sqrt();
        let den = l.attenuation[0] + l.attenuation[1] * d + l.attenuation[2] * d2;
        let att = if den > 0.0 { 1.0 / den } else { f64::MAX };
        (normalize(vp), att.min(f64::MAX))
    } else {
        let d = [l.position[0], l.position[1], l.position[2]];
        (
            if normalize_directional {
                normalize(d)
            } else {
                d
            },
            1.0,
        )
    };
    let spot = if l.spot_cutoff == 180.0 {
        1.0
    } else {
        let c = -dot(lv, normalize(l.spot_direction));
        if c >= l.spot_cutoff.to_radians().cos() {
            pow0(c.max(0.0), l.spot_exponent)
        } else {
            0.0
        }
    };
    let n_dot_l = dot(n, lv);
    let (n_dot_h, specular) = if n_dot_l > 0.0 {
        let v = if s.local_viewer {
            normalize(p.map(|c| -c))
        } else {
            [0.0, 0.0, 1.0]
        };
        let h = normalize([0, 1, 2].map(|k| lv[k] + v[k]));
        let nh = dot(n, h).max(0.0);
        let f = match curve {
            None => pow0(nh, s.state.material.shininess),
            Some(k) => nv2a_specular(nh, k),
        };
        (nh, f)
    } else {
        (0.0, 0.0)
    };
    LightTerms {
        l: lv,
        att,
        spot,
        n_dot_l,
        n_dot_h,
        specular,
    }
}

/// x^s with 0^0 = 1 (C's pow).
fn pow0(x: f64, s: f64) -> f64 {
    if s == 0.0 {
        1.0
    } else {
        x.powf(s)
    }
}

/// The lit colour (r, g, b unclamped; alpha = the diffuse alpha) of a vertex at
/// eye-space `p` with normal `n`.
pub fn light_vertex(s: &GlLighting, p: V3, n: V3) -> [f64; 4] {
    let m = &s.state.material;
    let n = if s.normalize { normalize(n) } else { n };
    let mut c = [0, 1, 2].map(|k| m.emission[k] + m.ambient[k] * s.state.scene_ambient[k]);
    for l in &s.state.lights {
        let t = light_terms(s, l, p, n);
        let k = t.att * t.spot;
        for (ch, cv) in c.iter_mut().enumerate() {
            let term = m.ambient[ch] * l.ambient[ch]
                + t.n_dot_l.max(0.0) * m.diffuse[ch] * l.diffuse[ch]
                + t.specular * m.specular[ch] * l.specular[ch];
            *cv += k * term;
        }
    }
    [c[0], c[1], c[2], m.diffuse[3]]
}

/// A colour as an n-bit level, GL's clamp to [0, 1] then ×(2ⁿ − 1) (not rounded).
pub fn to_levels(c: f64, bits: u32) -> f64 {
    c.clamp(0.0, 1.0) * ((1u64 << bits) - 1) as f64
}

/// The NV2A's switches the unit's `light_control` and `normalize_directional` modes
/// model (SET_LIGHTING_ENABLE, SET_SPECULAR_ENABLE, SET_LIGHT_CONTROL's
/// SEPARATE_SPECULAR and ALPHA_FROM_MATERIAL_SPECULAR).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nv2aSwitches {
    pub normalize_directional: bool,
    pub lighting: bool,
    pub specular_enable: bool,
    pub separate_specular: bool,
    pub specular_alpha_from_vertex: bool,
    /// The specular curve's (k0, k1, k2) ([`nv2a_specular`]); None: pow(x, shininess).
    pub specular_curve: Option<[f64; 3]>,
}

/// The NV2A's two colours of a vertex (primary, secondary), RGB unclamped, from its
/// eye-space `p`, normal `n` and vertex colours (`diffuse`, `specular`, RGBA in
/// [0, 1]): lighting off passes the vertex colours through; lit, the specular sum
/// Σ att·spot·spec·s_m·s_l is the secondary RGB when specular is enabled and separate,
/// otherwise it joins the primary and the secondary RGB is the vertex's specular.
/// Specular disabled: secondary (0, 0, 0, 1); else its alpha is the vertex's specular
/// alpha with `specular_alpha_from_vertex`, 1 without.
pub fn light_vertex_nv2a(
    s: &GlLighting,
    sw: &Nv2aSwitches,
    p: V3,
    n: V3,
    diffuse: [f64; 4],
    specular: [f64; 4],
) -> ([f64; 4], [f64; 4]) {
    let mut secondary = [specular[0], specular[1], specular[2], 1.0];
    let primary = if !sw.lighting {
        diffuse
    } else {
        let m = &s.state.material;
        let n = if s.normalize { normalize(n) } else { n };
        let mut d = [0, 1, 2].map(|k| m.emission[k] + m.ambient[k] * s.state.scene_ambient[k]);
        let mut sp = [0.0; 3];
        for l in &s.state.lights {
            let t = light_terms_dir(s, l, p, n, sw.normalize_directional, sw.specular_curve);
            let k = t.att * t.spot;
            for ch in 0..3 {
                d[ch] += k
                    * (m.ambient[ch] * l.ambient[ch]
                        + t.n_dot_l.max(0.0) * m.diffuse[ch] * l.diffuse[ch]);
                sp[ch] += k * t.specular * m.specular[ch] * l.specular[ch];
            }
        }
        if sw.specular_enable && sw.separate_specular {
            secondary[..3].copy_from_slice(&sp);
        } else {
            for ch in 0..3 {
                d[ch] += sp[ch];
            }
        }
        [d[0], d[1], d[2], m.diffuse[3]]
    };
    if !sw.specular_enable {
        secondary = [0.0, 0.0, 0.0, 1.0];
    } else if sw.specular_alpha_from_vertex {
        secondary[3] = specular[3];
    }
    (primary, secondary)
}
