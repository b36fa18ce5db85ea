//! The frame's memory, known before anything is allocated: an estimate from the
//! validated scene of its large buffers, tables and maps, checked against a budget
//! (default: half of the machine's available memory, `MemAvailable` in
//! /proc/meminfo; `render --max-memory` sets it). Over the budget, the error lists
//! the largest items and the scene field that shrinks each (docs/inputs.md).
//!
//! The estimate is an upper bound of the same order as the real peak (each item
//! counts its working copies), not an exact figure: its job is to refuse a scene that
//! would take the machine down, in milliseconds, before any pixel.

use crate::scene::format::{LightKind, Scene, Shape};

/// One large allocation of the frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Item {
    /// What it is (e.g. "light maps").
    pub what: String,
    pub bytes: u64,
    /// The scene field(s) that set its size, and how to shrink it.
    pub shrink: String,
}

/// The frame's large allocations.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Estimate {
    pub items: Vec<Item>,
}

impl Estimate {
    pub fn total(&self) -> u64 {
        self.items.iter().map(|i| i.bytes).sum()
    }
}

/// Bytes per image pixel across the frame's per-pixel buffers: the RGBA framebuffer,
/// the camera depth buffer, the J buffer, the f64 levels and reference copies the
/// report takes (generous: 8 buffers of 8 bytes per channel-pixel would be 96).
pub const BYTES_PER_PIXEL: u64 = 128;
/// Bytes per light-map texel held by the host (one u32 per texel, plus the decoded
/// image and the sampler's upload).
pub const BYTES_PER_LIGHT_MAP_TEXEL: u64 = 12;
/// Bytes per shadow-map texel (the depth RAM and the depth pass's f64 working copy).
pub const BYTES_PER_SHADOW_TEXEL: u64 = 16;
/// Bytes per voxel of the environment map (its codes, the uploaded texture, the
/// prefilter's f64 working values).
pub const BYTES_PER_VOXEL: u64 = 64;
/// Bytes per tessellated triangle (vertices, normals, the BVH).
pub const BYTES_PER_TRIANGLE: u64 = 256;

/// The frame's large allocations for a validated scene. Sizes are computed in u64
/// with saturation, so no field can overflow them.
pub fn estimate(scene: &Scene) -> Estimate {
    let mut items = Vec::new();
    let px = u64::from(scene.image.width) * u64::from(scene.image.height);
    items.push(Item {
        what: format!(
            "image buffers ({} × {} pixels)",
            scene.image.width, scene.image.height
        ),
        bytes: px.saturating_mul(BYTES_PER_PIXEL),
        shrink: "image.width, image.height".into(),
    });
    let sh = &scene.shafts;
    let spots = scene
        .lights
        .iter()
        .filter(|l| l.kind == LightKind::Spot)
        .count() as u64;
    if spots > 0 {
        let t = u64::from(sh.light_map_texels);
        items.push(Item {
            what: format!("light maps ({spots} light(s) × {t} × {t} texels, all held at once)"),
            bytes: spots
                .saturating_mul(t * t)
                .saturating_mul(BYTES_PER_LIGHT_MAP_TEXEL),
            shrink: "shafts.light_map_texels, or fewer spot lights".into(),
        });
    }
    if !scene.lights.is_empty() && scene.objects.iter().any(|o| o.occluder) {
        let r = u64::from(sh.shadow_resolution);
        items.push(Item {
            what: format!("shadow map ({r} × {r}, one light at a time)"),
            bytes: (r * r).saturating_mul(BYTES_PER_SHADOW_TEXEL),
            shrink: "shafts.shadow_resolution".into(),
        });
    }
    let h = u64::from(sh.h_texels[0]) * u64::from(sh.h_texels[1]);
    items.push(Item {
        what: format!("h(s, t) table ({} × {})", sh.h_texels[0], sh.h_texels[1]),
        bytes: h.saturating_mul(16),
        shrink: "shafts.h_texels".into(),
    });
    let mesh = u64::from(sh.mesh[0] + 1) * u64::from(sh.mesh[1] + 1);
    items.push(Item {
        what: format!("sample-plane mesh ({} × {} cells)", sh.mesh[0], sh.mesh[1]),
        bytes: mesh.saturating_mul(256),
        shrink: "shafts.mesh".into(),
    });
    let triangles: u64 = scene
        .objects
        .iter()
        .map(|o| match o.shape {
            Shape::Teapot { subdivisions, .. } => {
                32 * 2 * u64::from(subdivisions) * u64::from(subdivisions)
            }
            Shape::Sphere { .. } => 8192,
            Shape::Plane { .. } | Shape::Box { .. } => 12,
        })
        .fold(0u64, |a, b| a.saturating_add(b));
    items.push(Item {
        what: format!(
            "object meshes ({} object(s), {triangles} triangles)",
            scene.objects.len()
        ),
        bytes: triangles.saturating_mul(BYTES_PER_TRIANGLE),
        shrink: "objects (fewer), objects[i].shape.subdivisions".into(),
    });
    if let Some(env) = &scene.environment {
        let s = u64::from(env.side);
        items.push(Item {
            what: format!("environment voxel map ({s}³ voxels)"),
            bytes: (s * s * s).saturating_mul(BYTES_PER_VOXEL),
            shrink: "environment.side".into(),
        });
    }
    Estimate { items }
}

/// Default budget: this share of `MemAvailable`.
pub const DEFAULT_SHARE: f64 = 0.5;
/// The budget when /proc/meminfo cannot be read.
pub const FALLBACK_BUDGET: u64 = 4 << 30;

/// `MemAvailable` of /proc/meminfo, bytes (None where there is none).
pub fn mem_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb.saturating_mul(1024))
}

/// The default budget: [`DEFAULT_SHARE`] of `MemAvailable`, else
/// [`FALLBACK_BUDGET`].
pub fn default_budget() -> u64 {
    mem_available().map_or(FALLBACK_BUDGET, |b| (b as f64 * DEFAULT_SHARE) as u64)
}

/// A byte count as the CLI takes it: a whole number with an optional binary suffix
/// K, M, G or T (`512M`, `2G`, `1073741824`). Errors name `--max-memory`.
pub fn parse_bytes(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let bad = || {
        format!(
            "'{text}' is not a size: a whole number of bytes with an optional suffix K, M, G or T (e.g. 512M, 2G)"
        )
    };
    let (digits, shift) = match t.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => {
            let shift = match c.to_ascii_uppercase() {
                'K' => 10,
                'M' => 20,
                'G' => 30,
                'T' => 40,
                _ => return Err(bad()),
            };
            (&t[..i], shift)
        }
        _ => (t, 0),
    };
    if digits.starts_with('-') {
        return Err(format!(
            "'{text}' is negative; a size of at least 1 byte is needed"
        ));
    }
    let n: u64 = digits.trim().parse().map_err(|_| bad())?;
    if n == 0 {
        return Err(format!(
            "'{text}' is zero; a size of at least 1 byte is needed"
        ));
    }
    n.checked_mul(1u64 << shift)
        .ok_or_else(|| format!("'{text}' is more than {} bytes", u64::MAX))
}

/// A byte count for a message: `1.5 GiB`, `300.0 MiB`, `512 B`.
pub fn human(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut x = bytes as f64;
    let mut u = 0;
    while x >= 1024.0 && u + 1 < UNITS.len() {
        x /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{bytes} B")
    } else {
        format!("{x:.1} {}", UNITS[u])
    }
}

/// Refuse a scene whose estimate exceeds `budget` bytes, listing the largest items
/// (largest first) with the fields that shrink them. `budget_from` says where the
/// budget came from (for the message).
pub fn check(scene: &Scene, budget: u64, budget_from: &str) -> Result<Estimate, String> {
    check_estimate(estimate(scene), budget, budget_from)
}

/// [`check`] for an estimate already made (a shading scene's: [`shading_estimate`]).
pub fn check_estimate(e: Estimate, budget: u64, budget_from: &str) -> Result<Estimate, String> {
    if e.total() <= budget {
        return Ok(e);
    }
    Err(refusal(&e, budget, budget_from))
}

/// Bytes per lit sphere vertex of `shading-vertex` (position and normal in f64, the
/// exact and the hardware colours, generous as [`BYTES_PER_PIXEL`] is).
pub const BYTES_PER_VERTEX: u64 = 128;

/// The large allocations of `render --scene` on a shading scene (`shading-*`, or a
/// file with a `[shading_sphere]` section or its `[shading]` alias): the sphere view's
/// image buffers (`image` × `image` pixels; the section's `image` shrinks them), or for `shading-vertex`
/// (`image` None: no image) its fixed sphere of lit vertices.
pub fn shading_estimate(image: Option<u32>) -> Estimate {
    use crate::pipeline::shading::sweep::{VERTEX_RINGS, VERTEX_SEGMENTS};
    let item = match image {
        Some(side) => {
            let s = u64::from(side);
            Item {
                what: format!("image buffers ({side} × {side} pixels)"),
                bytes: (s * s).saturating_mul(BYTES_PER_PIXEL),
                shrink:
                    "shading_sphere.image (shading.image in the [shading] alias form; default 256)"
                        .into(),
            }
        }
        None => {
            let n = u64::from(VERTEX_RINGS) * u64::from(VERTEX_SEGMENTS);
            Item {
                what: format!("sphere vertices ({n}, lit one by one)"),
                bytes: n.saturating_mul(BYTES_PER_VERTEX),
                shrink: "nothing: shading-vertex's sphere is fixed".into(),
            }
        }
    };
    Estimate { items: vec![item] }
}

/// The refusal of an estimate over `budget`: the total, the budget and where it came
/// from, and the four largest items with the fields that shrink them.
fn refusal(e: &Estimate, budget: u64, budget_from: &str) -> String {
    let mut items = e.items.clone();
    items.sort_by_key(|i| std::cmp::Reverse(i.bytes));
    let list: Vec<String> = items
        .iter()
        .take(4)
        .filter(|i| i.bytes > 0)
        .map(|i| format!("  {} — {} (shrink: {})", human(i.bytes), i.what, i.shrink))
        .collect();
    format!(
        "max-memory: the scene needs about {} but the budget is {} ({budget_from}); nothing was allocated. Largest:\n{}\nShrink those fields, or raise the budget with --max-memory SIZE (e.g. 8G).",
        human(e.total()),
        human(budget),
        list.join("\n")
    )
}

/// The budget `--max-memory` gives (`None`: the default, [`default_budget`]) and
/// where it came from, for [`check`]'s message.
pub fn resolve(max_memory: Option<u64>) -> (u64, String) {
    match max_memory {
        Some(b) => (b, "--max-memory".to_string()),
        None => (
            default_budget(),
            "default: half of MemAvailable".to_string(),
        ),
    }
}

/// [`check`] for a run of several frames (the points of a sweep, the scenes of a
/// reproduction), before the first one runs: the largest point is checked, and a
/// refusal names it (`label`, e.g. `light_map_texels = 4096`) after [`check`]'s text.
pub fn check_largest(
    points: &[(String, Scene)],
    budget: u64,
    budget_from: &str,
) -> Result<(), String> {
    let Some((label, scene)) = points.iter().max_by_key(|(_, s)| estimate(s).total()) else {
        return Ok(());
    };
    check(scene, budget, budget_from)
        .map(|_| ())
        .map_err(|e| format!("{e}\n(the largest point of this run: {label})"))
}

/// [`check`] for frames that are not a [`Scene`] (the shading sweeps' sphere views):
/// the items given.
pub fn check_items(
    items: Vec<Item>,
    label: &str,
    budget: u64,
    budget_from: &str,
) -> Result<(), String> {
    let e = Estimate { items };
    if e.total() <= budget {
        return Ok(());
    }
    Err(format!(
        "{}\n(the largest point of this run: {label})",
        refusal(&e, budget, budget_from)
    ))
}

/// The frames of a sweep of `param` over `values` on `scene` (with `--image`
/// applied), each with its label (`planes = 20`): what the memory check and the range
/// warnings look at. None for a shading sphere (sphere views, no frame) and for the
/// test scene (the sweep refuses it). Errors in the param or values are the sweep's
/// own (the same checks it makes next).
pub fn sweep_points(
    scene: &Scene,
    param: &str,
    values: &str,
    image: Option<&str>,
) -> Result<Option<Vec<(String, Scene)>>, String> {
    use crate::pipeline::shafts::sweep as sh;
    if scene.kind() != crate::scene::format::SceneKind::Frame {
        return Ok(None);
    }
    let mut base = scene.clone();
    if let Some(img) = image {
        let (w, h) = sh::parse_image(img)?;
        base.image.width = w;
        base.image.height = h;
    }
    // An environment scene sweeps its own parameters (`side`), as `sweep` dispatches it.
    if super::sweep::environment_sweep(&base) {
        let vs = crate::report::sweep_out::parse_int_values(values)?;
        let scenes = crate::pipeline::envmap::sweep::envmap_scenes(&base, param, &vs)?;
        return Ok(Some(
            vs.iter()
                .map(|v| format!("{param} = {v}"))
                .zip(scenes)
                .collect(),
        ));
    }
    if super::sweep::is_frame_scene(&base)? {
        let p = super::sweep::resolve_param(&base, param)?;
        let vs = crate::report::sweep_out::parse_int_values(values)?;
        let scenes = super::sweep::frame_scenes(&base, &p, &vs)?;
        return Ok(Some(
            vs.iter()
                .map(|v| format!("{} = {v}", p.qualified()))
                .zip(scenes)
                .collect(),
        ));
    }
    Ok(Some(if base.glare.is_some() {
        let vs = crate::report::sweep_out::parse_int_values(values)?;
        let scenes = crate::pipeline::glare::sweep::glare_scenes(&base, param, &vs)?;
        vs.iter()
            .map(|v| format!("{param} = {v}"))
            .zip(scenes)
            .collect()
    } else {
        let p = sh::Param::from_name(param)?;
        let vs = sh::parse_values(p, values)?;
        let scenes = sh::sweep_scenes(&base, p, &vs)?;
        vs.iter()
            .map(|v| format!("{} = {v}", p.name()))
            .zip(scenes)
            .collect()
    }))
}

/// `sweep`'s memory check of a shading sphere's sweep, before the first point runs:
/// its sphere view's buffers (`side` × `side`).
pub fn check_shading_sweep(side: u32, max_memory: Option<u64>) -> Result<(), String> {
    let (budget, from) = resolve(max_memory);
    let side = u64::from(side);
    let item = Item {
        what: format!("image buffers ({side} × {side} pixels)"),
        bytes: (side * side).saturating_mul(BYTES_PER_PIXEL),
        shrink: "--image".into(),
    };
    check_items(vec![item], &format!("--image {side}x{side}"), budget, &from)
}

/// `sweep`'s memory check, before the first point runs: the largest of its
/// [`sweep_points`] against the budget.
pub fn check_sweep(
    scene: &Scene,
    param: &str,
    values: &str,
    image: Option<&str>,
    max_memory: Option<u64>,
) -> Result<(), String> {
    let (budget, from) = resolve(max_memory);
    match sweep_points(scene, param, values, image)? {
        Some(points) => check_largest(&points, budget, &from),
        None => Ok(()),
    }
}

/// The built-in scenes `reproduce NAME` renders, each with its label, at the sizes its
/// environment variables set (`ENVMAP_TABLE3_S`, `ENVMAP_IMAGE_SIZE`) and with its
/// `--values` (shafts-fig4: planes at 8- and 16-bit texels; shafts-fig5: sub-planes).
/// None for the shading reproductions (sphere views, no scene) and unknown names.
pub fn reproduction_points(
    name: &str,
    values: Option<&[u32]>,
) -> Result<Option<Vec<(String, Scene)>>, String> {
    use crate::scene::load::load_scene;
    let scenes: Vec<&str> = match name {
        "shafts-fig4" => {
            let base = load_scene("fig4")?;
            let default: Vec<u32> = (1..=20).map(|k| 10 * k).collect();
            let mut points = Vec::new();
            for bits in [8, 16] {
                for &n in values.unwrap_or(&default) {
                    let mut s = base.clone();
                    s.shafts.planes = n;
                    s.shafts.texel_bits = bits;
                    s.shafts.fb_bits = bits;
                    points.push((format!("planes = {n} ({bits}-bit texels)"), s));
                }
            }
            return Ok(Some(points));
        }
        "shafts-fig5" => {
            let base = load_scene("fig6")?;
            let default: Vec<u32> = (1..=25).collect();
            let points = values
                .unwrap_or(&default)
                .iter()
                .map(|&m| {
                    let mut s = base.clone();
                    s.shafts.subplanes = m;
                    (format!("subplanes = {m}"), s)
                })
                .collect();
            return Ok(Some(points));
        }
        "assumptions" => return assumption_points().map(Some),
        "shafts-vs-raymarch" => vec!["fig6"],
        "shafts-stage" => vec!["stage"],
        "glare-fig4" | "glare-fig5" | "glare-fig7" | "glare-fig8" | "glare-throughput"
        | "glare-gauss-seeds" => vec![
            "glare-point",
            "glare-elliptic",
            "glare-flare",
            "street-light",
            "leaves",
        ],
        "glare-asic-throughput" => crate::pipeline::glare::clocked::ASIC_SCENES.to_vec(),
        "frame-elaboration" => vec!["night-street"],
        "sim-speed" => vec!["fig6", "night-street"],
        "vs-gl" => crate::frame::vs_gl::SCENES.to_vec(),
        n if n.starts_with("envmap-") => vec![
            "env-pattern-teapot",
            "env-venice_sunset-teapot",
            "env-st_fagans_interior-teapot",
        ],
        _ => return Ok(None),
    };
    let mut points = Vec::new();
    for s in scenes {
        let mut scene = load_scene(s)?;
        if name.starts_with("envmap-") {
            let run = crate::pipeline::envmap::reproduce::RenderRun::cli()?;
            let size = if name == "envmap-timing" {
                (640, 480)
            } else {
                (run.size, run.size)
            };
            (scene.image.width, scene.image.height) = size;
            if let Some(env) = scene.environment.as_mut() {
                env.side = run.s;
            }
        }
        let label = match &scene.environment {
            Some(env) if name.starts_with("envmap-") => format!(
                "{name}: scene {s}, side {} ($ENVMAP_TABLE3_S), image {} × {} ($ENVMAP_IMAGE_SIZE)",
                env.side, scene.image.width, scene.image.height
            ),
            _ => format!("{name}: scene {s}"),
        };
        points.push((label, scene));
    }
    Ok(Some(points))
}

/// The scenes `reproduce assumptions` renders: every alternative of the ledger on each
/// of its built-ins, and each built-in as it is.
fn assumption_points() -> Result<Vec<(String, Scene)>, String> {
    use super::assumptions::{scene_named, ALTERNATIVES};
    let mut points = Vec::new();
    for alt in ALTERNATIVES {
        for &name in alt.scenes {
            let base = scene_named(name)?;
            let mut s = base.clone();
            (alt.apply)(&mut s);
            // Each built-in once, however many alternatives it carries.
            if !points.iter().any(|(label, _)| label == name) {
                points.push((name.to_string(), base));
            }
            points.push((format!("{name} with {}", alt.alternative), s));
        }
    }
    Ok(points)
}

/// `reproduce NAME`'s memory check, before any work: the largest of its
/// [`reproduction_points`] against the budget. The shading reproductions render
/// fixed sphere views (256 × 256 at most) and are counted as such.
pub fn check_reproduction(
    name: &str,
    values: Option<&[u32]>,
    max_memory: Option<u64>,
) -> Result<(), String> {
    let (budget, from) = resolve(max_memory);
    if name.starts_with("shading-") {
        let item = Item {
            what: "image buffers (256 × 256 pixels)".into(),
            bytes: 256 * 256 * BYTES_PER_PIXEL,
            shrink: "nothing: the shading reproductions' views are fixed".into(),
        };
        return check_items(vec![item], name, budget, &from);
    }
    match reproduction_points(name, values)? {
        Some(points) => check_largest(&points, budget, &from),
        None => Ok(()),
    }
}
