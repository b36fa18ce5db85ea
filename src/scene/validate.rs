//! Scene validation and loading: every field of `format.rs` is checked, and every
//! error is a [`ConfigError`] naming the field by its TOML path
//! (`lights[0].position[2]`, `objects[3].shape.radius`, `camera.fovy_deg`, …).
//!
//! Rules beyond the per-field ranges (all documented on the checks below):
//! - every coordinate and length is finite and within ±[`WORLD_MAX`] (10⁶ world
//!   units), so that downstream products such as s², far·near or |P − eye|² can neither
//!   overflow nor lose all precision;
//! - a vector that must be "non-zero" has length ≥ [`MIN_LENGTH`] (10⁻⁹): shorter
//!   vectors cannot be normalised reliably in f64 (their squared length underflows);
//! - two directions are "parallel" when the sine of the angle between them is below
//!   [`PARALLEL_SIN`] (10⁻⁶);
//! - where a rule relates two fields, the error names the second one: `camera.far`
//!   (must exceed `camera.near`), `camera.look_at` (must differ from `camera.eye`),
//!   `camera.up` (must not be parallel to the view), `objects[i].shape.tangent` (must
//!   not be parallel to the normal), `objects[i].shape.max[k]` (must exceed `min[k]`).
//!
//! Stiff but valid: ρ, κ and K each go up to 10⁶, so ρκ = 10³ (DESIGN §4) and beyond
//! are accepted; exp(−ρκ(s + t)) then underflows to 0, never NaN.

use std::ops::Range;
use std::path::{Path, PathBuf};

use rtl_model::error::{check_finite, short, ConfigError};
use serde::de::{self, Deserialize, Deserializer, MapAccess, SeqAccess, Unexpected, Visitor};
use toml::Spanned;

use super::fields;
use super::format::{Camera, Light, LightKind, LightMap, Object, Scene, ShaftsConfig, Shape};
use super::math::Vec3;

pub(crate) use super::bounds::interval;
pub use super::bounds::{
    IMAGE_MAX, INTENSITY_MAX, LIGHT_COLOR_MAX, LIGHT_MAP_FILE_MAX_BYTES, MEDIUM_MAX, MIN_LENGTH,
    PARALLEL_SIN, SCENE_FILE_MAX_BYTES, TEAPOT_SCALE_MAX, WORLD_MAX,
};
pub(crate) use super::fields::{direction, point};

impl Scene {
    /// Check every field; the first error found names its field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if self.shading_sphere.is_some() || self.test_scene.is_some() {
            return self.validate_fixed();
        }
        if self.camera.is_unset() {
            return Err(ConfigError::invalid("camera", MISSING_CAMERA));
        }
        fields::IMAGE_WIDTH.int("image.width", self.image.width.into())?;
        fields::IMAGE_HEIGHT.int("image.height", self.image.height.into())?;
        super::limits::check_image(self.image)?;
        validate_camera(&self.camera)?;
        fields::MEDIUM_RHO.real("medium.rho", self.medium.rho)?;
        fields::MEDIUM_KAPPA.real("medium.kappa", self.medium.kappa)?;
        fields::MEDIUM_K.real("medium.k", self.medium.k)?;
        for (i, l) in self.lights.iter().enumerate() {
            validate_light(l).map_err(|e| e.within(&format!("lights[{i}]")))?;
        }
        for (i, o) in self.objects.iter().enumerate() {
            validate_object(o).map_err(|e| e.within(&format!("objects[{i}]")))?;
        }
        validate_shafts(&self.shafts).map_err(|e| e.within("shafts"))?;
        if let Some(hw) = &self.shading_hw {
            hw.validate()?;
        }
        super::limits::check_shafts(self)?;
        if let Some(env) = &self.environment {
            env.validate()?;
            for (i, r) in env.reflectors.iter().enumerate() {
                if r.object >= self.objects.len() {
                    return Err(ConfigError::invalid(
                        &format!("environment.reflectors[{i}].object"),
                        &format!(
                            "names object {} but the scene has {} object(s)",
                            r.object,
                            self.objects.len()
                        ),
                    ));
                }
                if matches!(
                    self.objects[r.object].shape,
                    super::format::Shape::Teapot { .. }
                ) {
                    return Err(ConfigError::invalid(
                        &format!("environment.reflectors[{i}].object"),
                        "a teapot cannot reflect in a scene (the object pass ray-casts analytic shapes)",
                    ));
                }
            }
        }
        let Some(g) = &self.glare else {
            return Ok(());
        };
        g.validate()?;
        match &g.shaded_highlights {
            Some(sh) if sh.light >= self.lights.len() => Err(ConfigError::invalid(
                "glare.shaded_highlights.light",
                &format!(
                    "names light {} but the scene has {} light(s)",
                    sh.light,
                    self.lights.len()
                ),
            )),
            _ => Ok(()),
        }
    }

    /// A shading sphere or the test scene: its section checked, and nothing else in
    /// the scene but its name and seed (the first field that is set names the mix).
    fn validate_fixed(&self) -> Result<(), ConfigError> {
        let (section, what) = match (&self.test_scene, &self.shading_sphere) {
            (Some(_), Some(s)) => {
                return Err(ConfigError::invalid(
                    s.table,
                    "a scene is the foundation test scene ([test_scene]) or a shading \
                     sphere, not both",
                ))
            }
            (Some(_), None) => ("test_scene", "the foundation test scene, a fixed scene"),
            (None, Some(s)) => (s.table, "the shading units' sphere"),
            (None, None) => return Ok(()),
        };
        let blank = Scene::blank();
        // The sections of a frame first, then the settings a frame scene writes.
        let mixed = [
            ("objects", !self.objects.is_empty()),
            ("glare", self.glare.is_some()),
            ("environment", self.environment.is_some()),
            ("lights", !self.lights.is_empty()),
            ("shading_hw", self.shading_hw.is_some()),
            ("rounding", self.rounding.is_some()),
            ("camera", !self.camera.is_unset()),
            ("chip", self.chip != blank.chip),
            ("image", self.image != blank.image),
            ("medium", self.medium != blank.medium),
            ("shafts", self.shafts != blank.shafts),
        ];
        if let Some((field, _)) = mixed.iter().find(|(_, set)| *set) {
            let hint = match *field {
                "chip" | "image" if section != "test_scene" => {
                    format!(" (the sphere's is {section}.{field})")
                }
                _ => String::new(),
            };
            return Err(ConfigError::invalid(
                field,
                &format!(
                    "a scene with a [{section}] section is {what} and holds no {field}{hint}; \
                     drop one of them"
                ),
            ));
        }
        match &self.shading_sphere {
            Some(s) => s.validate(),
            None => Ok(()),
        }
    }

    /// Parse a scene from TOML text and validate it. Parse errors name the field
    /// where toml reports them (`camera.fovy_deg`, `lights[1].colour`, `scene` when
    /// no field can be told) and always carry toml's own message and the position.
    ///
    /// Relative light-map image and environment `hdr` paths are taken relative to the
    /// working directory.
    pub fn from_toml_str(s: &str) -> Result<Scene, ConfigError> {
        let scene = parse_toml(s, "")?;
        check_array_lengths(s, &scene, "")?;
        scene.validate()?;
        Ok(scene)
    }

    /// Read, parse and validate a scene file. A file that cannot be read is an error
    /// naming the path. Relative light-map image paths are resolved against the scene
    /// file's directory (the returned scene holds the resolved paths); so is a relative
    /// environment `hdr` path (the scene keeps the path as written for serialising).
    pub fn from_file(path: &Path) -> Result<Scene, ConfigError> {
        let shown = path.display().to_string();
        let bytes = check_input_file(&shown, path, "scene", SCENE_FILE_MAX_BYTES)?;
        let text = String::from_utf8(bytes).map_err(|e| {
            ConfigError::invalid(
                &shown,
                &format!(
                    "cannot read scene file: not UTF-8 text (byte {})",
                    e.utf8_error().valid_up_to()
                ),
            )
        })?;
        let what = format!("{shown}: ");
        let mut scene = parse_toml(&text, &what)?;
        check_array_lengths(&text, &scene, &what)?;
        let dir = path.parent().unwrap_or(Path::new(""));
        for l in &mut scene.lights {
            if let Some(LightMap::Image { path: p }) = &mut l.light_map {
                let pb = PathBuf::from(p.as_str());
                if !p.trim().is_empty() && pb.is_relative() {
                    *p = dir.join(pb).to_string_lossy().into_owned();
                }
            }
        }
        if let Some(hdr) = scene.environment.as_mut().and_then(|e| e.hdr.as_mut()) {
            hdr.resolve_against(dir);
        }
        scene.validate()?;
        Ok(scene)
    }
}

/// Check a camera; errors name `camera.<field>`.
pub fn validate_camera(c: &Camera) -> Result<(), ConfigError> {
    let eye = point("camera.eye", &c.eye)?;
    let at = point("camera.look_at", &c.look_at)?;
    let up = direction("camera.up", &c.up)?;
    let view = at - eye;
    if view.length() < MIN_LENGTH {
        return Err(ConfigError::invalid(
            "camera.look_at",
            "coincides with camera.eye: the view direction is undefined",
        ));
    }
    if parallel(view, up) {
        return Err(ConfigError::invalid(
            "camera.up",
            "is parallel to the view direction (look_at − eye): the image's roll is undefined",
        ));
    }
    fields::CAMERA_FOVY_DEG.real("camera.fovy_deg", c.fovy_deg)?;
    fields::CAMERA_NEAR.real("camera.near", c.near)?;
    check_finite("camera.far", c.far)?;
    if c.far <= c.near {
        return Err(ConfigError::invalid(
            "camera.far",
            &format!(
                "{} must exceed camera.near = {}",
                short(c.far),
                short(c.near)
            ),
        ));
    }
    interval("camera.far", c.far, c.near, false, WORLD_MAX, true)
}

/// Field paths relative to the light (`position[0]`, `light_map.radius`).
fn validate_light(l: &Light) -> Result<(), ConfigError> {
    point("position", &l.position)?;
    match l.kind {
        LightKind::Spot => {
            direction("direction", &l.direction)?;
            fields::LIGHT_CUTOFF_DEG.real("cutoff_deg", l.cutoff_deg)?;
        }
        LightKind::Point => {
            // The cutoff is unused by a point light, but still a number. The direction
            // is used: the light's shadow map and its frame look along it, so a zero
            // direction would leave every fragment unlit (a silent black frame).
            point("direction", &l.direction)?;
            direction("direction", &l.direction).map_err(|_| {
                ConfigError::invalid(
                    "direction",
                    &format!(
                        "is (almost) the zero vector (length < {MIN_LENGTH:e}); a point light's \
                         shadow map looks along its direction, so it must not be zero"
                    ),
                )
            })?;
            check_finite("cutoff_deg", l.cutoff_deg)?;
        }
    }
    fields::LIGHT_INTENSITY.real("intensity", l.intensity)?;
    for (k, &c) in l.color.iter().enumerate() {
        fields::LIGHT_COLOR.real(&format!("color[{k}]"), c)?;
    }
    if let Some(map) = &l.light_map {
        if l.kind == LightKind::Point {
            return Err(ConfigError::invalid(
                "light_map",
                "a light map is projected over a spot's cone; a point light has none \
                 (use kind = \"spot\" or remove the light map)",
            ));
        }
        validate_light_map(map).map_err(|e| e.within("light_map"))?;
    }
    Ok(())
}

fn validate_light_map(m: &LightMap) -> Result<(), ConfigError> {
    match m {
        LightMap::Smooth { exponent } => fields::LIGHT_MAP_EXPONENT.real("exponent", *exponent),
        LightMap::PolkaDots { dots, radius } => {
            fields::LIGHT_MAP_DOTS.int("dots", (*dots).into())?;
            fields::LIGHT_MAP_RADIUS.real("radius", *radius)
        }
        LightMap::Image { path } => {
            if path.trim().is_empty() {
                return Err(ConfigError::invalid("path", "the image path is empty"));
            }
            check_input_file("path", Path::new(path), "image", LIGHT_MAP_FILE_MAX_BYTES).map(|_| ())
        }
    }
}

/// Field paths relative to the object (`shape.radius`, `color[1]`).
fn validate_object(o: &Object) -> Result<(), ConfigError> {
    validate_shape(&o.shape)?;
    for (k, &c) in o.color.iter().enumerate() {
        fields::OBJECT_COLOR.real(&format!("color[{k}]"), c)?;
    }
    if let Some(m) = &o.material {
        m.validate()?;
    }
    Ok(())
}

/// Check a shape's fields; errors name `shape.<field>` (prefix the object with
/// [`ConfigError::within`]). Used by the tessellators too, so that they never see an
/// invalid shape.
pub fn validate_shape(s: &Shape) -> Result<(), ConfigError> {
    match s {
        Shape::Sphere { center, radius } => {
            point("shape.center", center)?;
            fields::SHAPE_RADIUS.real("shape.radius", *radius)
        }
        Shape::Plane {
            center,
            normal,
            tangent,
            half_size,
        } => {
            point("shape.center", center)?;
            let n = direction("shape.normal", normal)?;
            let t = direction("shape.tangent", tangent)?;
            if parallel(n, t) {
                return Err(ConfigError::invalid(
                    "shape.tangent",
                    "is parallel to shape.normal: the rectangle's in-plane axes are undefined",
                ));
            }
            for (k, &h) in half_size.iter().enumerate() {
                fields::SHAPE_HALF_SIZE.real(&format!("shape.half_size[{k}]"), h)?;
            }
            Ok(())
        }
        Shape::Box { min, max } => {
            point("shape.min", min)?;
            point("shape.max", max)?;
            for k in 0..3 {
                if max[k] <= min[k] {
                    return Err(ConfigError::invalid(
                        &format!("shape.max[{k}]"),
                        &format!(
                            "{} must exceed shape.min[{k}] = {} (a box must have a volume)",
                            short(max[k]),
                            short(min[k])
                        ),
                    ));
                }
            }
            Ok(())
        }
        Shape::Teapot {
            position,
            scale,
            rotate_y_deg,
            subdivisions,
        } => {
            point("shape.position", position)?;
            fields::SHAPE_SCALE.real("shape.scale", *scale)?;
            check_finite("shape.rotate_y_deg", *rotate_y_deg)?;
            fields::SHAPE_SUBDIVISIONS.int("shape.subdivisions", (*subdivisions).into())
        }
    }
}

/// Field paths relative to `shafts`.
fn validate_shafts(s: &ShaftsConfig) -> Result<(), ConfigError> {
    fields::SHAFTS_PLANES.int("planes", s.planes.into())?;
    fields::SHAFTS_SUBPLANES.int("subplanes", s.subplanes.into())?;
    for (k, &m) in s.mesh.iter().enumerate() {
        fields::SHAFTS_MESH.int(&format!("mesh[{k}]"), m.into())?;
    }
    // Table sizes: at least 2 texels (the tables' own rule: a lerp needs two ends), at
    // most the sampler's axis (its own constant). The widths, the texel product and the
    // shadow map are checked by building the units ([`super::limits::check_shafts`]).
    fields::SHAFTS_F_TEXELS.int("f_texels", s.f_texels.into())?;
    for (k, &h) in s.h_texels.iter().enumerate() {
        fields::SHAFTS_H_TEXELS.int(&format!("h_texels[{k}]"), h.into())?;
    }
    fields::SHAFTS_S_MAX.real("s_max", s.s_max)?;
    fields::SHAFTS_T_MAX.real("t_max", s.t_max)?;
    // A power of two (the table's range says so).
    fields::SHAFTS_LIGHT_MAP_TEXELS.int("light_map_texels", s.light_map_texels.into())
}

// ---------------------------------------------------------------------------------
// Checks.

/// Read a file the user named, refusing early what cannot be the kind of file
/// wanted: a missing path, a directory ("is a directory"), a device, pipe or socket
/// (which could be endless: refused from its metadata, before any read), or a file
/// larger than `cap` bytes. At most `cap + 1` bytes are read whatever the file does
/// while it is read. Errors name `field`.
pub fn check_input_file(
    field: &str,
    path: &Path,
    kind: &str,
    cap: u64,
) -> Result<Vec<u8>, ConfigError> {
    use std::io::Read;
    let shown = path.display();
    let fail = |why: String| ConfigError::invalid(field, &why);
    let meta = std::fs::metadata(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => {
            fail(format!("cannot read {kind} file `{shown}`: not found"))
        }
        _ => fail(format!("cannot read {kind} file `{shown}`: {e}")),
    })?;
    if meta.is_dir() {
        return Err(fail(format!(
            "`{shown}` is a directory; {} {kind} file is needed",
            article(kind)
        )));
    }
    if !meta.is_file() {
        return Err(fail(format!(
            "`{shown}` is not a regular file (a device, pipe or socket); {} {kind} file is needed",
            article(kind)
        )));
    }
    let too_big = |n: u64| {
        fail(format!(
            "{kind} file `{shown}` is {n} bytes, more than the {cap} bytes allowed"
        ))
    };
    if meta.len() > cap {
        return Err(too_big(meta.len()));
    }
    let file = std::fs::File::open(path)
        .map_err(|e| fail(format!("cannot read {kind} file `{shown}`: {e}")))?;
    let mut bytes = Vec::new();
    file.take(cap + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| fail(format!("cannot read {kind} file `{shown}`: {e}")))?;
    if bytes.len() as u64 > cap {
        return Err(too_big(bytes.len() as u64));
    }
    Ok(bytes)
}

fn article(word: &str) -> &'static str {
    if word.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    }
}

/// Strict arrays: serde fills a fixed-length array (`[f64; 3]`) from the first
/// elements of a longer TOML array and drops the rest. Every array of the text is
/// compared with the array the parsed scene holds at the same path (its serialised
/// form); a longer one is an error naming the field, the length given and the length
/// expected. (A shorter one is already refused by serde: "invalid length".)
fn check_array_lengths(text: &str, scene: &Scene, what: &str) -> Result<(), ConfigError> {
    let Ok(given) = toml::from_str::<toml::Value>(text) else {
        return Ok(());
    };
    let Ok(parsed) = toml::Value::try_from(scene) else {
        return Ok(());
    };
    compare_lengths("", &given, &parsed, what)
}

fn compare_lengths(
    path: &str,
    given: &toml::Value,
    parsed: &toml::Value,
    what: &str,
) -> Result<(), ConfigError> {
    use toml::Value;
    match (given, parsed) {
        (Value::Table(g), Value::Table(p)) => {
            for (k, gv) in g {
                if let Some(pv) = p.get(k) {
                    compare_lengths(&join(path, k), gv, pv, what)?;
                }
            }
            Ok(())
        }
        (Value::Array(g), Value::Array(p)) => {
            if g.len() > p.len() {
                return Err(ConfigError::invalid(
                    path,
                    &format!(
                        "{what}has {} elements, expected {} (the extra elements would be dropped)",
                        g.len(),
                        p.len()
                    ),
                ));
            }
            for (i, (gv, pv)) in g.iter().zip(p).enumerate() {
                compare_lengths(&format!("{path}[{i}]"), gv, pv, what)?;
            }
            Ok(())
        }
        _ => Ok(()),
    }
}

/// Both non-zero; true when the sine of their angle is below `PARALLEL_SIN`.
fn parallel(a: Vec3, b: Vec3) -> bool {
    a.normalized().cross(b.normalized()).length() < PARALLEL_SIN
}

// ---------------------------------------------------------------------------------
// TOML parse errors → field paths.

/// Parse without validating; errors are mapped to field paths. `what` prefixes the
/// reason (e.g. the file name).
fn parse_toml(s: &str, what: &str) -> Result<Scene, ConfigError> {
    let scene = parse_serde(s, what)?;
    // A scene of lights and objects needs its camera (serde reads a missing one as
    // unset, for the shading sphere and the test scene): said as toml says a
    // missing field, at the document's start.
    if scene.camera.is_unset() && scene.shading_sphere.is_none() && scene.test_scene.is_none() {
        return Err(ConfigError::invalid(
            "camera",
            &format!("{what}{MISSING_CAMERA} (TOML line 1, column 1)"),
        ));
    }
    Ok(scene)
}

/// The error of a scene of lights and objects without a camera.
const MISSING_CAMERA: &str = "missing field `camera`: a scene of lights and objects needs a \
     [camera] table (eye, look_at); only a [shading_sphere] or [test_scene] scene has none";

fn parse_serde(s: &str, what: &str) -> Result<Scene, ConfigError> {
    toml::from_str::<Scene>(s).map_err(|e| {
        let msg = e
            .message()
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect::<Vec<_>>()
            .join("; ");
        let msg = with_suggestion(msg);
        let located = e.span().map(|sp| match locate_field(s, sp.clone(), &msg) {
            Some(found) => found,
            None => (text_field(s, sp.start), sp.start),
        });
        let field = located
            .as_ref()
            .and_then(|(f, _)| f.clone())
            .or_else(|| message_field(&msg))
            .unwrap_or_else(|| "scene".to_string());
        let at = match located {
            Some((_, pos)) => {
                let (line, col) = line_col(s, pos);
                format!(" (TOML line {line}, column {col})")
            }
            None => String::new(),
        };
        ConfigError::invalid(&field, &format!("{what}{msg}{at}"))
    })
}

/// An "unknown field `x`, expected one of `a`, `b`" (or unknown variant) message with
/// the nearest valid name appended: "; did you mean `b`?".
fn with_suggestion(msg: String) -> String {
    if !(msg.starts_with("unknown field") || msg.starts_with("unknown variant")) {
        return msg;
    }
    let quoted: Vec<&str> = msg.split('`').skip(1).step_by(2).collect();
    let Some((typo, valid)) = quoted.split_first() else {
        return msg;
    };
    let hint = super::load::did_you_mean(typo, valid, "`");
    if hint.is_empty() {
        msg
    } else {
        format!("{msg}; {hint}")
    }
}

/// 1-based line and column (in characters) of a byte offset.
fn line_col(s: &str, pos: usize) -> (usize, usize) {
    let pos = pos.min(s.len());
    let pos = (0..=pos)
        .rev()
        .find(|&p| s.is_char_boundary(p))
        .unwrap_or(0);
    let before = &s[..pos];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
    (line, col)
}

/// The name in a serde message "missing field `x`" / "unknown field `x`", for a
/// top-level error without a span.
fn message_field(msg: &str) -> Option<String> {
    backticked_after(msg, "missing field ").or_else(|| backticked_after(msg, "unknown field "))
}

fn backticked_after(msg: &str, prefix: &str) -> Option<String> {
    let rest = msg.strip_prefix(prefix)?.strip_prefix('`')?;
    let end = rest.find('`')?;
    Some(rest[..end].to_string())
}

/// A TOML document as a tree of spans, for mapping an error's byte span to a path.
enum Node {
    Table(Vec<(Spanned<String>, Spanned<Node>)>),
    Array(Vec<Spanned<Node>>),
    /// A scalar, described as serde's `Unexpected` describes it in an error message
    /// (e.g. string "x", or integer 3 in backticks).
    Leaf(String),
}

impl<'de> Deserialize<'de> for Node {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(NodeVisitor)
    }
}

struct NodeVisitor;

impl<'de> Visitor<'de> for NodeVisitor {
    type Value = Node;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("any TOML value")
    }
    fn visit_bool<E: de::Error>(self, v: bool) -> Result<Node, E> {
        Ok(Node::Leaf(Unexpected::Bool(v).to_string()))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Node, E> {
        Ok(Node::Leaf(Unexpected::Signed(v).to_string()))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Node, E> {
        Ok(Node::Leaf(Unexpected::Unsigned(v).to_string()))
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Node, E> {
        Ok(Node::Leaf(Unexpected::Float(v).to_string()))
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<Node, E> {
        Ok(Node::Leaf(Unexpected::Str(v).to_string()))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut m: A) -> Result<Node, A::Error> {
        let mut entries = Vec::new();
        while let Some(e) = m.next_entry::<Spanned<String>, Spanned<Node>>()? {
            entries.push(e);
        }
        Ok(Node::Table(entries))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut s: A) -> Result<Node, A::Error> {
        let mut items = Vec::new();
        while let Some(e) = s.next_element::<Spanned<Node>>()? {
            items.push(e);
        }
        Ok(Node::Array(items))
    }
}

/// One place in the tree: its path, its span, and the node (`None` for a key).
struct Site<'a> {
    path: String,
    span: Range<usize>,
    node: Option<&'a Node>,
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

fn collect<'a>(path: &str, node: &'a Spanned<Node>, out: &mut Vec<Site<'a>>) {
    out.push(Site {
        path: path.to_string(),
        span: node.span(),
        node: Some(node.get_ref()),
    });
    match node.get_ref() {
        Node::Table(entries) => {
            for (k, v) in entries {
                let p = join(path, k.get_ref());
                out.push(Site {
                    path: p.clone(),
                    span: k.span(),
                    node: None,
                });
                collect(&p, v, out);
            }
        }
        Node::Array(items) => {
            for (i, v) in items.iter().enumerate() {
                collect(&format!("{path}[{i}]"), v, out);
            }
        }
        Node::Leaf(_) => {}
    }
}

/// The field an error at byte span `sp` is about: the smallest site enclosing the
/// span, refined with the message when that site is a table (missing / unknown
/// field, unknown `type` variant, a wrong value found by its description inside an
/// internally tagged table, whose errors toml can only place on the whole table).
/// Returns the path (when found) and the byte offset to report (the refined field's
/// own position where it was found by its value).
fn locate_field(text: &str, sp: Range<usize>, msg: &str) -> Option<(Option<String>, usize)> {
    let root: Spanned<Node> = toml::from_str(text).ok()?;
    let mut sites = Vec::new();
    collect("", &root, &mut sites);
    let site = sites
        .iter()
        .filter(|s| s.span.start <= sp.start && sp.end <= s.span.end)
        .min_by_key(|s| (s.span.end - s.span.start, usize::MAX - s.path.len()))?;
    let mut path = site.path.clone();
    let mut pos = sp.start;
    if let Some(node @ (Node::Table(_) | Node::Array(_))) = site.node {
        if let Some(f) = message_field(msg) {
            path = join(&path, &f);
        } else if msg.starts_with("unknown variant") {
            if let Node::Table(entries) = node {
                if entries.iter().any(|(k, _)| k.get_ref() == "type") {
                    path = join(&path, "type");
                }
            }
        } else if let Some(n) = msg
            .strip_prefix("invalid length ")
            .and_then(|r| r.split(|c: char| !c.is_ascii_digit()).next())
            .and_then(|d| d.parse::<usize>().ok())
        {
            // An array of the wrong length inside an internally tagged table (a shape,
            // a background), which toml can only place on the whole table: the one
            // array under it with that many elements.
            let matches: Vec<&Site> = sites
                .iter()
                .filter(|s| {
                    s.path.len() > site.path.len()
                        && s.path.starts_with(site.path.as_str())
                        && matches!(s.node, Some(Node::Array(a)) if a.len() == n)
                })
                .collect();
            if matches.len() == 1 {
                path = matches[0].path.clone();
                pos = matches[0].span.start;
            }
        } else if let Some(what) = msg
            .strip_prefix("invalid type: ")
            .or_else(|| msg.strip_prefix("invalid value: "))
            .and_then(|r| r.split(", expected").next())
        {
            let under = |p: &str| {
                site.path.is_empty()
                    || p.strip_prefix(site.path.as_str())
                        .is_some_and(|r| r.starts_with('.') || r.starts_with('['))
            };
            let matches: Vec<&Site> = sites
                .iter()
                .filter(|s| under(&s.path) && matches!(s.node, Some(Node::Leaf(d)) if d == what))
                .collect();
            if matches.len() == 1 {
                path = matches[0].path.clone();
                pos = matches[0].span.start;
            }
        }
    }
    if path != site.path && pos == sp.start {
        if let Some(key) = sites.iter().find(|s| s.path == path && s.node.is_none()) {
            pos = key.span.start;
        }
    }
    Some(((!path.is_empty()).then_some(path), pos))
}

/// For a syntax error (no tree to search): the key assigned on the error's line, or
/// on the nearest line above it, inside the table of the last header before it
/// (`[[lights]]` headers counted for the index). A heuristic; `None` at top level
/// without a key.
fn text_field(text: &str, pos: usize) -> Option<String> {
    let pos = (0..=pos.min(text.len()))
        .rev()
        .find(|&p| text.is_char_boundary(p))
        .unwrap_or(0);
    let line_end = text[pos..].find('\n').map_or(text.len(), |e| pos + e);
    let mut arrays: Vec<(String, usize)> = Vec::new();
    let mut table = String::new();
    let mut key: Option<String> = None;
    let is_key = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.';
    for line in text[..line_end].lines() {
        let l = line.trim();
        if let Some(h) = l.strip_prefix("[[").and_then(|r| r.split("]]").next()) {
            let h = h.trim().to_string();
            match arrays.iter_mut().find(|(n, _)| *n == h) {
                Some((_, c)) => *c += 1,
                None => arrays.push((h.clone(), 1)),
            }
            table = indexed(&h, &arrays);
            key = None;
        } else if let Some(h) = l.strip_prefix('[').and_then(|r| r.split(']').next()) {
            table = indexed(h.trim(), &arrays);
            key = None;
        } else if let Some((k, _)) = l.split_once('=') {
            let k = k.trim();
            if !k.is_empty() && k.chars().all(is_key) {
                key = Some(k.to_string());
            }
        }
    }
    let path = match key {
        Some(k) => join(&table, &k),
        None => table,
    };
    (!path.is_empty()).then_some(path)
}

/// A dotted table name with the current index of each array-of-tables prefix.
fn indexed(name: &str, arrays: &[(String, usize)]) -> String {
    let mut out = String::new();
    let mut prefix = String::new();
    for part in name.split('.') {
        prefix = join(&prefix, part.trim());
        out = join(&out, part.trim());
        if let Some((_, c)) = arrays.iter().find(|(n, _)| *n == prefix) {
            out = format!("{out}[{}]", c - 1);
        }
    }
    out
}
