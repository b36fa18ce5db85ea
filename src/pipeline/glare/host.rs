//! The application processor's side of the glare renderer (f64): project each source
//! onto the screen, work out its outline, and turn Table 1's determinants into the
//! constants of eqs. (1)–(6) with the R1 forms of docs/glare.md.

use crate::reference::glare_model::{bloom_factor, Bloom, FlareParams, Shape2D, SourceGlare};
use crate::scene::camera::{vec3, CameraView};
use crate::scene::format::Scene;
use crate::scene::glare::{Determinants, GlareModel, GlareSection, GlareSource, SourceKind};
use crate::scene::math::Vec3;
use rtl_model::ConfigError;

/// The glare section, or an error naming `glare`.
pub fn glare_of(scene: &Scene) -> Result<&GlareSection, ConfigError> {
    scene.glare.as_ref().ok_or_else(|| {
        ConfigError::invalid(
            "glare",
            "the scene has no [glare] section (no glare sources)",
        )
    })
}

/// A source as seen on the screen, before its intensity is known (fluctuating patches
/// and highlights get theirs from the hardware).
#[derive(Clone, Debug, PartialEq)]
pub struct ScreenSource {
    pub label: String,
    pub center: [f64; 2],
    pub shape: Shape2D,
    pub px_per_deg: f64,
    /// I × area size (codes), before any fluctuation.
    pub intensity: f64,
    /// Directivity factor c_D = max(0, D̂·(eye − P₀)̂); 1 without directivity.
    pub c_dir: f64,
    pub color: [f64; 3],
    pub bloom: bool,
    pub halo: bool,
    pub flare: bool,
    /// Minor/major ratio of the outline on screen (1 for round sources).
    pub aspect: f64,
    /// R(N): the semi-minor direction on screen, radians.
    pub base_rad: f64,
    /// Which fluctuating source and patch this is, if any.
    pub patch: Option<(usize, usize)>,
    /// A highlight below the glare condition: its core only (saturating at 255), no
    /// bloom tail, halo or flare.
    pub core_only: bool,
}

/// Pixels per degree at the screen centre: the focal length in pixels × π/180.
pub fn px_per_deg(cam: &CameraView) -> f64 {
    (cam.height as f64 / 2.0) / cam.tan_half * std::f64::consts::PI / 180.0
}

fn screen(cam: &CameraView, p: Vec3, field: &str) -> Result<[f64; 2], ConfigError> {
    match cam.project(p) {
        Some((x, y, _)) if x.is_finite() && y.is_finite() => Ok([x, y]),
        _ => Err(ConfigError::invalid(
            field,
            "is behind the camera (or on its plane): a glare source must be in front of the eye",
        )),
    }
}

/// Half of the screen vector from p(P − d) to p(P + d).
fn half_vec(cam: &CameraView, p: Vec3, d: Vec3, field: &str) -> Result<[f64; 2], ConfigError> {
    let a = screen(cam, p + d, field)?;
    let b = screen(cam, p - d, field)?;
    Ok([(a[0] - b[0]) / 2.0, (a[1] - b[1]) / 2.0])
}

/// Semi-axes (a ≥ b) and the major axis' angle of the ellipse {A cos t + B sin t}
/// spanned by two conjugate semi-diameters.
pub fn ellipse_from_conjugates(a: [f64; 2], b: [f64; 2]) -> (f64, f64, f64) {
    let s00 = a[0] * a[0] + b[0] * b[0];
    let s11 = a[1] * a[1] + b[1] * b[1];
    let s01 = a[0] * a[1] + b[0] * b[1];
    let tr = s00 + s11;
    let disc = ((s00 - s11).powi(2) / 4.0 + s01 * s01).sqrt();
    let l1 = (tr / 2.0 + disc).max(0.0);
    let l2 = (tr / 2.0 - disc).max(0.0);
    let phi = 0.5 * (2.0 * s01).atan2(s00 - s11);
    (l1.sqrt(), l2.sqrt(), phi)
}

/// Project one scene source (`field` names it, e.g. `glare.sources[2]`).
pub fn screen_source(
    cam: &CameraView,
    s: &GlareSource,
    field: &str,
) -> Result<ScreenSource, ConfigError> {
    let p0 = vec3(s.position);
    let center = screen(cam, p0, &format!("{field}.position"))?;
    let to_eye = (cam.eye - p0).normalized();
    let c_dir = match s.directivity {
        Some(d) => vec3(d).normalized().dot(to_eye).max(0.0),
        None => 1.0,
    };
    let (center, shape, aspect, base_rad) = screen_shape(cam, s, field, center, to_eye)?;
    Ok(ScreenSource {
        label: field.to_string(),
        center,
        shape,
        px_per_deg: px_per_deg(cam),
        intensity: s.intensity * s.area_size,
        c_dir,
        color: s.color,
        bloom: s.bloom,
        halo: s.halo,
        flare: s.flare,
        aspect,
        base_rad,
        patch: None,
        core_only: false,
    })
}

/// A source's outline on the screen: (its centre, its shape about the centre, the
/// aspect b/a, the angle its streaks start from). A polygon's centre is its points'
/// mean (the position and the vertices).
fn screen_shape(
    cam: &CameraView,
    s: &GlareSource,
    field: &str,
    center: [f64; 2],
    to_eye: Vec3,
) -> Result<([f64; 2], Shape2D, f64, f64), ConfigError> {
    let p0 = vec3(s.position);
    let (m, n) = plane_axes(s, to_eye);
    let depth = cam.depth_of(p0).max(1e-12);
    let f_px = px_per_deg(cam) * 180.0 / std::f64::consts::PI;
    Ok(match s.kind {
        SourceKind::Point => (center, Shape2D::Point, 1.0, 0.0),
        SourceKind::Circle => (
            center,
            Shape2D::Circle {
                r: f_px * s.a / depth,
            },
            1.0,
            0.0,
        ),
        SourceKind::Elliptic => {
            let av = half_vec(cam, p0, m * s.a, &format!("{field}.a"))?;
            let bv = half_vec(cam, p0, n * s.b, &format!("{field}.b"))?;
            let (a, b, phi) = ellipse_from_conjugates(av, bv);
            let aspect = if a > 0.0 { b / a } else { 1.0 };
            (
                center,
                Shape2D::Ellipse { a, b, phi },
                aspect,
                phi + std::f64::consts::FRAC_PI_2,
            )
        }
        SourceKind::Cylindrical => {
            let av = half_vec(cam, p0, m * s.a, &format!("{field}.a"))?;
            let h = (av[0] * av[0] + av[1] * av[1]).sqrt();
            let r = f_px * s.b / depth;
            let phi = av[1].atan2(av[0]);
            let aspect = if h + r > 0.0 { r / (h + r) } else { 1.0 };
            (
                center,
                Shape2D::Capsule { h, r, phi },
                aspect,
                phi + std::f64::consts::FRAC_PI_2,
            )
        }
        SourceKind::Polygon => {
            let mut pts = vec![center];
            for (k, v) in s.vertices.iter().enumerate() {
                pts.push(screen(cam, vec3(*v), &format!("{field}.vertices[{k}]"))?);
            }
            let n = pts.len() as f64;
            let c = [
                pts.iter().map(|p| p[0]).sum::<f64>() / n,
                pts.iter().map(|p| p[1]).sum::<f64>() / n,
            ];
            let rel = pts.iter().map(|p| [p[0] - c[0], p[1] - c[1]]).collect();
            (c, Shape2D::Polygon { pts: rel }, 1.0, 0.0)
        }
    })
}

/// The axes (M, N) of the plane an extended source lies in: the plane faces D (or the
/// eye, without D); N is the scene's N in that plane (any direction in it when N is
/// parallel to D), M = normal × N.
fn plane_axes(s: &GlareSource, to_eye: Vec3) -> (Vec3, Vec3) {
    let normal = s.directivity.map_or(to_eye, |d| vec3(d).normalized());
    let n_raw = vec3(s.n);
    let n = (n_raw - normal * n_raw.dot(normal)).normalized();
    let n = if n.length().is_finite() && n.length() > 0.5 {
        n
    } else {
        let t = if normal.y.abs() < 0.9 {
            vec3([0.0, 1.0, 0.0])
        } else {
            vec3([1.0, 0.0, 0.0])
        };
        (t - normal * t.dot(normal)).normalized()
    };
    (normal.cross(n), n)
}

/// The constants of eqs. (1)–(6) for a source of effective intensity `ie` (codes).
pub fn source_glare(s: &ScreenSource, ie: f64, det: &Determinants, p: &GlareModel) -> SourceGlare {
    let ie = ie.max(0.0);
    let fb = bloom_factor(det, p, s.c_dir);
    if s.core_only {
        return SourceGlare {
            center: s.center,
            shape: s.shape.clone(),
            px_per_deg: s.px_per_deg,
            color: s.color,
            bloom: (ie > 0.0).then_some(Bloom::Extended { a: ie, b: 0.0 }),
            halo: None,
            flare: None,
        };
    }
    let bloom = if s.bloom && ie > 0.0 {
        Some(match s.shape {
            Shape2D::Point => Bloom::Point {
                a: p.point_k * ie * fb * p.point_a,
                theta0: p.point_theta0_deg,
                m: p.point_m,
            },
            _ => Bloom::Extended {
                a: ie,
                b: p.bloom_k * ie * fb,
            },
        })
    } else {
        None
    };
    // C = halo_k·I_e, or 10·E₁ under `halo_amplitude = "ambient_x10"`.
    let c_halo = p.halo_amplitude_for(ie, det.ambient);
    let halo = (s.halo && ie > 0.0 && c_halo > 0.0).then_some(c_halo);
    let size_deg = s.shape.extent() / s.px_per_deg;
    let size = 1.0 + size_deg / p.size_ref_deg;
    let ie_e = ie.powf(p.e_intensity);
    let g = if det.glasses {
        p.glasses_flare.powf(p.e_glasses)
    } else {
        1.0
    };
    let amb = (1.0 + det.ambient).powf(-p.e_ambient);
    let mist = (1.0 + det.mist).powf(-p.e_mist);
    let cd = s.c_dir.clamp(0.0, 1.0).powf(p.e_directivity);
    let num = (p.flare_num_k * ie_e * g * size.powf(-p.e_size) * amb * mist * cd)
        .round()
        .clamp(0.0, p.flare_max_lines as f64) as u32;
    // No light, no lines: ie^e_intensity is 0^0 = 1 at e_intensity = 0, so num alone
    // would draw (invisible) lines for a dark source.
    let flare = (s.flare && ie > 0.0 && num > 0).then(|| FlareParams {
        num,
        len_deg: p.flare_len_k_deg * ie_e * g * amb,
        width_deg: p.flare_width_k_deg * ie_e * size.powf(p.e_size),
        intensity: p.flare_intensity_k * ie * mist * cd,
        spread_rad: p.flare_spread_rad * s.aspect.clamp(0.0, 1.0).powf(p.e_shape),
        base_rad: s.base_rad,
    });
    SourceGlare {
        center: s.center,
        shape: s.shape.clone(),
        px_per_deg: s.px_per_deg,
        color: s.color,
        bloom,
        halo,
        flare,
    }
}

/// Every source of the scene on the screen; fluctuating sources become their patches
/// (scattered with the scene's seed), in order.
pub fn screen_sources(scene: &Scene) -> Result<Vec<ScreenSource>, ConfigError> {
    let Some(g) = &scene.glare else {
        return Ok(Vec::new());
    };
    let cam = CameraView::new(&scene.camera, scene.image);
    let mut out = Vec::new();
    for (i, s) in g.sources.iter().enumerate() {
        let field = format!("glare.sources[{i}]");
        match s.fluctuation {
            None => out.push(screen_source(&cam, s, &field)?),
            Some(f) => {
                use rand::{Rng, SeedableRng};
                let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(scene.seed ^ (i as u64 + 1));
                let right = cam.right;
                let up = cam.up;
                for k in 0..f.patches as usize {
                    let (r, t) = (
                        f.spread * rng.random::<f64>().sqrt(),
                        rng.random::<f64>() * std::f64::consts::TAU,
                    );
                    let p = vec3(s.position) + right * (r * t.cos()) + up * (r * t.sin());
                    let patch = GlareSource {
                        kind: SourceKind::Circle,
                        position: [p.x, p.y, p.z],
                        a: f.patch_radius,
                        fluctuation: None,
                        ..s.clone()
                    };
                    let mut ss = screen_source(&cam, &patch, &format!("{field}.fluctuation"))?;
                    ss.label = format!("{field} patch {k}");
                    ss.patch = Some((i, k));
                    out.push(ss);
                }
            }
        }
    }
    Ok(out)
}
