//! Ray–shape intersection for the f64 references: spheres, rectangles (`Plane`),
//! axis-aligned boxes and triangle meshes (median-split BVH), and [`SceneGeometry`],
//! the scene's objects ready for camera rays (`first_hit`) and shadow rays
//! (`occluded`).
//!
//! Conventions: a ray is `origin + t · dir` (dir need not be unit length; `t` is in
//! units of |dir|). A hit is reported only for t_min < t < t_max. `Hit::normal` is a
//! unit vector facing the ray's origin (dot(normal, dir) ≤ 0: face-forwarded, so
//! rectangles and mesh triangles are two-sided); for a mesh with vertex normals it is
//! the interpolated shading normal, face-forwarded by the geometric one.

// `!(x > 0.0)` is deliberate throughout: it is true for NaN, which must take the safe
// branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use rtl_model::error::ConfigError;

use crate::scene::format::{Light, Object, Scene, Shape};
use crate::scene::lightmap::LightMapSampler;
use crate::scene::math::{v3, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
}

impl Ray {
    pub fn at(&self, t: f64) -> Vec3 {
        self.origin + self.dir * t
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f64,
    pub point: Vec3,
    /// Unit normal facing the ray origin.
    pub normal: Vec3,
}

fn arr(a: [f64; 3]) -> Vec3 {
    v3(a[0], a[1], a[2])
}

fn face_forward(n: Vec3, dir: Vec3) -> Vec3 {
    if n.dot(dir) > 0.0 {
        -n
    } else {
        n
    }
}

fn hit(ray: &Ray, t: f64, n: Vec3) -> Hit {
    Hit {
        t,
        point: ray.at(t),
        normal: face_forward(n, ray.dir),
    }
}

/// Intersect a scene shape directly (no validation beyond NaN-safety; degenerate
/// shapes simply miss). A `Teapot` has no analytic form: it always misses here — use
/// [`Mesh`] / [`SceneGeometry`] with its triangles.
pub fn intersect(shape: &Shape, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
    match Prim::from_shape(shape).ok()? {
        Some(p) => p.intersect(ray, t_min, t_max),
        None => None,
    }
}

/// A sphere.
pub fn intersect_sphere(
    center: Vec3,
    radius: f64,
    ray: &Ray,
    t_min: f64,
    t_max: f64,
) -> Option<Hit> {
    let oc = ray.origin - center;
    let a = ray.dir.dot(ray.dir);
    if !(a > 0.0) {
        return None;
    }
    let b = oc.dot(ray.dir);
    // c = |oc|² − r², computed as (|oc| − r)(|oc| + r) for accuracy near the surface.
    let l = oc.length();
    let c = (l - radius) * (l + radius);
    // Discriminant in a form that keeps precision when the ray passes far away:
    // b² − a c = a (r² − |oc − (b/a) dir|²).
    let perp = oc - ray.dir * (b / a);
    let disc = a * (radius * radius - perp.dot(perp));
    if !(disc >= 0.0) {
        return None;
    }
    let q = -(b + b.signum() * disc.sqrt());
    let (mut t0, mut t1) = if q != 0.0 { (q / a, c / q) } else { (0.0, 0.0) };
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    for t in [t0, t1] {
        if t > t_min && t < t_max {
            let n = (ray.at(t) - center).normalized();
            return Some(hit(ray, t, n));
        }
    }
    None
}

/// A rectangle: centre c, unit normal n, unit in-plane axes a (tangent) and b = n × a,
/// half extents (ha, hb). Edges count as inside.
pub fn intersect_rect(
    c: Vec3,
    n: Vec3,
    a: Vec3,
    half: [f64; 2],
    ray: &Ray,
    t_min: f64,
    t_max: f64,
) -> Option<Hit> {
    let denom = n.dot(ray.dir);
    if denom == 0.0 || denom.is_nan() {
        return None;
    }
    let t = n.dot(c - ray.origin) / denom;
    if !(t > t_min && t < t_max) {
        return None;
    }
    let p = ray.at(t);
    let d = p - c;
    let b = n.cross(a);
    if d.dot(a).abs() <= half[0] && d.dot(b).abs() <= half[1] {
        Some(Hit {
            t,
            point: p,
            normal: face_forward(n, ray.dir),
        })
    } else {
        None
    }
}

/// An axis-aligned box by the slab test; a ray starting inside hits the exit face.
pub fn intersect_box(min: Vec3, max: Vec3, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
    let o = [ray.origin.x, ray.origin.y, ray.origin.z];
    let d = [ray.dir.x, ray.dir.y, ray.dir.z];
    let lo = [min.x, min.y, min.z];
    let hi = [max.x, max.y, max.z];
    let mut t_near = f64::NEG_INFINITY;
    let mut t_far = f64::INFINITY;
    let (mut ax_near, mut ax_far) = (0usize, 0usize);
    let (mut sg_near, mut sg_far) = (0.0, 0.0);
    for k in 0..3 {
        if d[k] == 0.0 {
            if o[k] < lo[k] || o[k] > hi[k] {
                return None;
            }
            continue;
        }
        let inv = 1.0 / d[k];
        let (mut ta, mut tb) = ((lo[k] - o[k]) * inv, (hi[k] - o[k]) * inv);
        // The entering face's outward normal points against the ray on this axis.
        let mut sa = -1.0;
        if ta > tb {
            std::mem::swap(&mut ta, &mut tb);
            sa = 1.0;
        }
        if ta > t_near {
            t_near = ta;
            ax_near = k;
            sg_near = sa;
        }
        if tb < t_far {
            t_far = tb;
            ax_far = k;
            sg_far = -sa;
        }
    }
    if !(t_near <= t_far) {
        return None;
    }
    let axis = |k: usize, s: f64| match k {
        0 => v3(s, 0.0, 0.0),
        1 => v3(0.0, s, 0.0),
        _ => v3(0.0, 0.0, s),
    };
    if t_near > t_min && t_near < t_max {
        return Some(hit(ray, t_near, axis(ax_near, sg_near)));
    }
    if t_far > t_min && t_far < t_max {
        return Some(hit(ray, t_far, axis(ax_far, sg_far)));
    }
    None
}

/// One triangle by Möller–Trumbore (no BVH): (t, barycentric b1, b2) of the hit with
/// t_min < t < t_max; edges count as inside; degenerate triangles and rays in the
/// triangle's plane miss.
pub fn intersect_triangle(
    p: &[Vec3; 3],
    ray: &Ray,
    t_min: f64,
    t_max: f64,
) -> Option<(f64, f64, f64)> {
    intersect_tri(p, ray, t_min, t_max)
}

fn intersect_tri(p: &[Vec3; 3], ray: &Ray, t_min: f64, t_max: f64) -> Option<(f64, f64, f64)> {
    let e1 = p[1] - p[0];
    let e2 = p[2] - p[0];
    let pv = ray.dir.cross(e2);
    let det = e1.dot(pv);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let tv = ray.origin - p[0];
    let b1 = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&b1) {
        return None;
    }
    let qv = tv.cross(e1);
    let b2 = ray.dir.dot(qv) * inv;
    if !(b2 >= 0.0 && b1 + b2 <= 1.0) {
        return None;
    }
    let t = e2.dot(qv) * inv;
    if t > t_min && t < t_max {
        Some((t, b1, b2))
    } else {
        None
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Aabb {
    lo: Vec3,
    hi: Vec3,
}

impl Aabb {
    fn empty() -> Self {
        let inf = f64::INFINITY;
        Aabb {
            lo: v3(inf, inf, inf),
            hi: v3(-inf, -inf, -inf),
        }
    }
    fn grow(&mut self, p: Vec3) {
        self.lo = v3(self.lo.x.min(p.x), self.lo.y.min(p.y), self.lo.z.min(p.z));
        self.hi = v3(self.hi.x.max(p.x), self.hi.y.max(p.y), self.hi.z.max(p.z));
    }
    /// Does the ray meet the box within (t_min, t_max)? `inv` = 1/dir per axis (±∞ for
    /// a zero component: then the origin must lie within that slab).
    fn hit(&self, o: Vec3, inv: [f64; 3], t_min: f64, t_max: f64) -> bool {
        let (mut t0, mut t1) = (t_min, t_max);
        let lo = [self.lo.x, self.lo.y, self.lo.z];
        let hi = [self.hi.x, self.hi.y, self.hi.z];
        let oo = [o.x, o.y, o.z];
        for k in 0..3 {
            if inv[k].is_infinite() {
                if oo[k] < lo[k] || oo[k] > hi[k] {
                    return false;
                }
                continue;
            }
            let ta = (lo[k] - oo[k]) * inv[k];
            let tb = (hi[k] - oo[k]) * inv[k];
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
        t0 <= t1
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Node {
    bounds: Aabb,
    /// Leaf: triangles `start .. start + count` of the ordered list; inner: count = 0,
    /// children at `start` and `start + 1`.
    start: u32,
    count: u32,
}

const LEAF_SIZE: usize = 4;

/// A triangle mesh with a median-split BVH (longest axis of the centroid bounds).
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    tris: Vec<[Vec3; 3]>,
    normals: Option<Vec<[Vec3; 3]>>,
    nodes: Vec<Node>,
}

impl Mesh {
    /// A mesh with flat (geometric) normals. Triangles with non-finite vertices are
    /// dropped; degenerate (zero-area) ones never hit.
    pub fn new(triangles: &[[Vec3; 3]]) -> Self {
        Self::build(triangles, None)
    }

    /// A mesh with per-vertex normals (interpolated at a hit). Lengths must agree;
    /// otherwise the normals are ignored.
    pub fn with_normals(triangles: &[[Vec3; 3]], normals: &[[Vec3; 3]]) -> Self {
        if normals.len() == triangles.len() {
            Self::build(triangles, Some(normals))
        } else {
            Self::build(triangles, None)
        }
    }

    fn build(triangles: &[[Vec3; 3]], normals: Option<&[[Vec3; 3]]>) -> Self {
        let finite = |p: &[Vec3; 3]| {
            p.iter()
                .all(|v| v.x.is_finite() && v.y.is_finite() && v.z.is_finite())
        };
        let keep: Vec<usize> = (0..triangles.len())
            .filter(|&i| finite(&triangles[i]))
            .collect();
        let mut idx = keep.clone();
        let centroid = |i: usize| {
            let p = &triangles[i];
            (p[0] + p[1] + p[2]) * (1.0 / 3.0)
        };
        let mut nodes = Vec::new();
        if !idx.is_empty() {
            nodes.push(Node {
                bounds: Aabb::empty(),
                start: 0,
                count: 0,
            });
            // Iterative build: (node index, range).
            let mut stack = vec![(0usize, 0usize, idx.len())];
            while let Some((ni, a, b)) = stack.pop() {
                let mut bounds = Aabb::empty();
                let mut cb = Aabb::empty();
                for &i in &idx[a..b] {
                    for v in &triangles[i] {
                        bounds.grow(*v);
                    }
                    cb.grow(centroid(i));
                }
                if b - a <= LEAF_SIZE {
                    nodes[ni] = Node {
                        bounds,
                        start: a as u32,
                        count: (b - a) as u32,
                    };
                    continue;
                }
                let ext = cb.hi - cb.lo;
                let axis = if ext.x >= ext.y && ext.x >= ext.z {
                    0
                } else if ext.y >= ext.z {
                    1
                } else {
                    2
                };
                let key = |i: usize| {
                    let c = centroid(i);
                    [c.x, c.y, c.z][axis]
                };
                let mid = (a + b) / 2;
                idx[a..b].select_nth_unstable_by(mid - a, |&i, &j| {
                    key(i).total_cmp(&key(j)).then(i.cmp(&j))
                });
                let left = nodes.len();
                nodes.push(Node {
                    bounds: Aabb::empty(),
                    start: 0,
                    count: 0,
                });
                nodes.push(Node {
                    bounds: Aabb::empty(),
                    start: 0,
                    count: 0,
                });
                nodes[ni] = Node {
                    bounds,
                    start: left as u32,
                    count: 0,
                };
                stack.push((left + 1, mid, b));
                stack.push((left, a, mid));
            }
        }
        Mesh {
            tris: idx.iter().map(|&i| triangles[i]).collect(),
            normals: normals.map(|n| idx.iter().map(|&i| n[i]).collect()),
            nodes,
        }
    }

    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    /// The nearest hit, or (with `any`) the first one found.
    fn trace(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        any: bool,
    ) -> Option<(f64, usize, f64, f64)> {
        if self.nodes.is_empty() {
            return None;
        }
        let inv = [1.0 / ray.dir.x, 1.0 / ray.dir.y, 1.0 / ray.dir.z];
        let mut best: Option<(f64, usize, f64, f64)> = None;
        let mut t_far = t_max;
        let mut stack = vec![0usize];
        while let Some(ni) = stack.pop() {
            let n = self.nodes[ni];
            if !n.bounds.hit(ray.origin, inv, t_min, t_far) {
                continue;
            }
            if n.count > 0 {
                for k in n.start as usize..(n.start + n.count) as usize {
                    if let Some((t, b1, b2)) = intersect_tri(&self.tris[k], ray, t_min, t_far) {
                        best = Some((t, k, b1, b2));
                        t_far = t;
                        if any {
                            return best;
                        }
                    }
                }
            } else {
                stack.push(n.start as usize + 1);
                stack.push(n.start as usize);
            }
        }
        best
    }

    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let (t, k, b1, b2) = self.trace(ray, t_min, t_max, false)?;
        let p = &self.tris[k];
        let geo = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
        let geo_ff = face_forward(geo, ray.dir);
        let normal = match &self.normals {
            Some(ns) => {
                let n = ns[k];
                let s = (n[0] * (1.0 - b1 - b2) + n[1] * b1 + n[2] * b2).normalized();
                if s.length() > 0.5 {
                    // Orient the shading normal to the side the ray sees.
                    if s.dot(geo_ff) < 0.0 {
                        -s
                    } else {
                        s
                    }
                } else {
                    geo_ff
                }
            }
            None => geo_ff,
        };
        Some(Hit {
            t,
            point: ray.at(t),
            normal,
        })
    }

    pub fn any_hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.trace(ray, t_min, t_max, true).is_some()
    }
}

/// A validated primitive.
#[derive(Clone, Debug, PartialEq)]
enum Prim {
    Sphere {
        c: Vec3,
        r: f64,
    },
    Rect {
        c: Vec3,
        n: Vec3,
        a: Vec3,
        half: [f64; 2],
    },
    Box {
        lo: Vec3,
        hi: Vec3,
    },
    Mesh(Mesh),
}

fn finite3(field: &str, a: [f64; 3]) -> Result<Vec3, ConfigError> {
    for x in a {
        rtl_model::error::check_finite(field, x)?;
    }
    Ok(arr(a))
}

impl Prim {
    /// `Ok(None)` for a teapot (needs triangles); errors name `shape.<field>`.
    fn from_shape(shape: &Shape) -> Result<Option<Prim>, ConfigError> {
        Ok(Some(match shape {
            Shape::Sphere { center, radius } => {
                let c = finite3("shape.center", *center)?;
                let r = rtl_model::error::check_finite("shape.radius", *radius)?;
                if r <= 0.0 {
                    return Err(ConfigError::out_of_range("shape.radius", r, 0.0, f64::MAX));
                }
                Prim::Sphere { c, r }
            }
            Shape::Plane {
                center,
                normal,
                tangent,
                half_size,
            } => {
                let c = finite3("shape.center", *center)?;
                let n0 = finite3("shape.normal", *normal)?;
                let t0 = finite3("shape.tangent", *tangent)?;
                let n = n0.normalized();
                if n.length() < 0.5 {
                    return Err(ConfigError::invalid("shape.normal", "is the zero vector"));
                }
                // Gram–Schmidt: the tangent's component in the plane.
                let a = (t0 - n * t0.dot(n)).normalized();
                if a.length() < 0.5 || (t0 - n * t0.dot(n)).length() < 1e-9 * t0.length() {
                    return Err(ConfigError::invalid(
                        "shape.tangent",
                        "is zero or parallel to the normal",
                    ));
                }
                for (k, h) in half_size.iter().enumerate() {
                    let f = format!("shape.half_size[{k}]");
                    rtl_model::error::check_finite(&f, *h)?;
                    if *h < 0.0 {
                        return Err(ConfigError::out_of_range(&f, *h, 0.0, f64::MAX));
                    }
                }
                Prim::Rect {
                    c,
                    n,
                    a,
                    half: *half_size,
                }
            }
            Shape::Box { min, max } => {
                let lo = finite3("shape.min", *min)?;
                let hi = finite3("shape.max", *max)?;
                if lo.x > hi.x || lo.y > hi.y || lo.z > hi.z {
                    return Err(ConfigError::invalid(
                        "shape.max",
                        "is below shape.min on some axis",
                    ));
                }
                Prim::Box { lo, hi }
            }
            Shape::Teapot { .. } => return Ok(None),
        }))
    }

    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        match self {
            Prim::Sphere { c, r } => intersect_sphere(*c, *r, ray, t_min, t_max),
            Prim::Rect { c, n, a, half } => intersect_rect(*c, *n, *a, *half, ray, t_min, t_max),
            Prim::Box { lo, hi } => intersect_box(*lo, *hi, ray, t_min, t_max),
            Prim::Mesh(m) => m.intersect(ray, t_min, t_max),
        }
    }

    fn any_hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        match self {
            Prim::Mesh(m) => m.any_hit(ray, t_min, t_max),
            _ => self.intersect(ray, t_min, t_max).is_some(),
        }
    }

    /// Largest coordinate magnitude (for the epsilon scale).
    fn extent(&self) -> f64 {
        let m = |v: Vec3| v.x.abs().max(v.y.abs()).max(v.z.abs());
        match self {
            Prim::Sphere { c, r } => m(*c) + r,
            Prim::Rect { c, half, .. } => m(*c) + half[0] + half[1],
            Prim::Box { lo, hi } => m(*lo).max(m(*hi)),
            Prim::Mesh(mesh) => mesh
                .nodes
                .first()
                .map(|n| m(n.bounds.lo).max(m(n.bounds.hi)))
                .unwrap_or(0.0),
        }
    }
}

/// Triangles supplied for a shape that has no analytic intersector (the teapot).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleSoup {
    pub positions: Vec<[Vec3; 3]>,
    /// Optional per-vertex normals, one triple per triangle.
    pub normals: Option<Vec<[Vec3; 3]>>,
}

impl From<Vec<[Vec3; 3]>> for TriangleSoup {
    fn from(positions: Vec<[Vec3; 3]>) -> Self {
        TriangleSoup {
            positions,
            normals: None,
        }
    }
}

/// The supplier of teapot triangles: called once per `Teapot` object with its index in
/// `objects` and its shape. `Ok(None)` is an error (`objects[i].shape`: not supplied).
pub type MeshSupplier<'a> =
    dyn FnMut(usize, &Shape) -> Result<Option<TriangleSoup>, ConfigError> + 'a;

/// The scene's objects, ready for ray queries, plus (when built with
/// [`SceneGeometry::for_scene`]) the scene's light maps, loaded.
///
/// Wiring the teapot (its tessellator lives in `scene::teapot`):
///
/// ```ignore
/// let geom = SceneGeometry::for_scene(&scene, &mut |_i, shape| match shape {
///     Shape::Teapot { position, scale, rotate_y_deg, subdivisions } => {
///         let tris = tessellate_teapot(*position, *scale, *rotate_y_deg, *subdivisions)?;
///         Ok(Some(TriangleSoup {
///             positions: tris.iter().map(|t| t.p).collect(),
///             normals: Some(tris.iter().map(|t| t.n).collect()),
///         }))
///     }
///     _ => Ok(None),
/// })?;
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SceneGeometry {
    prims: Vec<Prim>,
    occluder: Vec<bool>,
    light_maps: Vec<LightMapSampler>,
    /// Absolute epsilon (world units) for self-intersection avoidance.
    eps: f64,
}

impl SceneGeometry {
    /// Geometry of `objects` (no light maps). Errors name `objects[i].shape.<field>`.
    pub fn new(objects: &[Object], supply: &mut MeshSupplier<'_>) -> Result<Self, ConfigError> {
        let mut prims = Vec::with_capacity(objects.len());
        let mut occluder = Vec::with_capacity(objects.len());
        for (i, o) in objects.iter().enumerate() {
            let within = |e: ConfigError| e.within(&format!("objects[{i}]"));
            let prim = match Prim::from_shape(&o.shape).map_err(within)? {
                Some(p) => p,
                None => {
                    let soup = supply(i, &o.shape)?.ok_or_else(|| {
                        ConfigError::invalid(
                            &format!("objects[{i}].shape"),
                            "teapot triangles were not supplied",
                        )
                    })?;
                    Prim::Mesh(match &soup.normals {
                        Some(n) => Mesh::with_normals(&soup.positions, n),
                        None => Mesh::new(&soup.positions),
                    })
                }
            };
            prims.push(prim);
            occluder.push(o.occluder);
        }
        let scale = prims.iter().map(Prim::extent).fold(1.0, f64::max);
        Ok(SceneGeometry {
            prims,
            occluder,
            light_maps: Vec::new(),
            eps: 1e-9 * scale,
        })
    }

    /// Geometry of a scene without teapots (a teapot is an error naming its field).
    pub fn without_meshes(objects: &[Object]) -> Result<Self, ConfigError> {
        Self::new(objects, &mut |_, _| Ok(None))
    }

    /// Geometry of `scene.objects` and the scene's light maps (images loaded; errors
    /// name `lights[i].light_map.<field>`).
    pub fn for_scene(scene: &Scene, supply: &mut MeshSupplier<'_>) -> Result<Self, ConfigError> {
        let g = Self::new(&scene.objects, supply)?;
        g.with_lights(&scene.lights)
    }

    /// Load the light maps of `lights` (replacing any loaded before).
    pub fn with_lights(mut self, lights: &[Light]) -> Result<Self, ConfigError> {
        self.light_maps = lights
            .iter()
            .enumerate()
            .map(|(i, l)| LightMapSampler::for_light(l, i))
            .collect::<Result<_, _>>()?;
        let scale = lights
            .iter()
            .flat_map(|l| l.position)
            .map(f64::abs)
            .filter(|x| x.is_finite())
            .fold(self.eps / 1e-9, f64::max);
        self.eps = 1e-9 * scale;
        Ok(self)
    }

    /// The loaded map of light `i`; `Uniform` if none was loaded (geometry built with
    /// [`SceneGeometry::new`] only, or an index past the lights).
    pub fn light_map(&self, i: usize) -> &LightMapSampler {
        static UNIFORM: LightMapSampler = LightMapSampler::Uniform;
        self.light_maps.get(i).unwrap_or(&UNIFORM)
    }

    pub fn light_maps(&self) -> &[LightMapSampler] {
        &self.light_maps
    }

    /// The absolute epsilon used by [`SceneGeometry::occluded`] (1e-9 × the scene's
    /// coordinate scale).
    pub fn epsilon(&self) -> f64 {
        self.eps
    }

    pub fn len(&self) -> usize {
        self.prims.len()
    }

    pub fn is_empty(&self) -> bool {
        self.prims.is_empty()
    }

    /// The nearest surface of any object (occluder or not) with 0 < t < t_max:
    /// (object index, hit).
    pub fn first_hit(&self, ray: &Ray, t_max: f64) -> Option<(usize, Hit)> {
        self.first_hit_range(ray, 0.0, t_max)
    }

    /// The nearest hit with t_min < t < t_max.
    pub fn first_hit_range(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<(usize, Hit)> {
        let mut best: Option<(usize, Hit)> = None;
        let mut far = t_max;
        for (i, p) in self.prims.iter().enumerate() {
            if let Some(h) = p.intersect(ray, t_min, far) {
                far = h.t;
                best = Some((i, h));
            }
        }
        best
    }

    /// Is any occluder object strictly between `from` and `to`? Hits within
    /// [`epsilon`](Self::epsilon) of either end are ignored, so a point on a surface
    /// does not shadow itself (and a light on a surface is not hidden by it); a point
    /// on the far side of a closed occluder is shadowed by the occluder's other wall.
    /// `from == to` is never occluded.
    pub fn occluded(&self, from: Vec3, to: Vec3) -> bool {
        let d = to - from;
        let len = d.length();
        if !(len > 2.0 * self.eps) || !len.is_finite() {
            return false;
        }
        let ray = Ray {
            origin: from,
            dir: d * (1.0 / len),
        };
        let (t0, t1) = (self.eps, len - self.eps);
        self.prims
            .iter()
            .zip(&self.occluder)
            .any(|(p, &occ)| occ && p.any_hit(&ray, t0, t1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: [f64; 3], d: [f64; 3]) -> Ray {
        Ray {
            origin: arr(o),
            dir: arr(d),
        }
    }

    #[test]
    fn sphere_hits_and_inside() {
        let s = Shape::Sphere {
            center: [0.0, 0.0, -5.0],
            radius: 1.0,
        };
        let h = intersect(&s, &ray([0.0; 3], [0.0, 0.0, -1.0]), 0.0, 100.0).unwrap();
        assert!((h.t - 4.0).abs() < 1e-14);
        assert_eq!(h.normal, v3(0.0, 0.0, 1.0));
        // From the centre: the exit at t = 1, normal facing back to the origin.
        let h = intersect(&s, &ray([0.0, 0.0, -5.0], [0.0, 1.0, 0.0]), 0.0, 100.0).unwrap();
        assert!((h.t - 1.0).abs() < 1e-14);
        assert_eq!(h.normal, v3(0.0, -1.0, 0.0));
        assert!(intersect(&s, &ray([0.0, 1.0001, 0.0], [0.0, 0.0, -1.0]), 0.0, 100.0).is_none());
    }

    #[test]
    fn rect_and_box() {
        let p = Shape::Plane {
            center: [0.0, 0.0, 0.0],
            normal: [0.0, 1.0, 0.0],
            tangent: [1.0, 0.0, 0.0],
            half_size: [2.0, 1.0],
        };
        // normal × tangent = y × x = −z: the second half size (1) is along z.
        assert!(intersect(&p, &ray([1.9, 1.0, 0.9], [0.0, -1.0, 0.0]), 0.0, 10.0).is_some());
        assert!(intersect(&p, &ray([1.9, 1.0, 1.1], [0.0, -1.0, 0.0]), 0.0, 10.0).is_none());
        let h = intersect(&p, &ray([0.0, -1.0, 0.0], [0.0, 1.0, 0.0]), 0.0, 10.0).unwrap();
        assert_eq!(h.normal, v3(0.0, -1.0, 0.0));
        let b = Shape::Box {
            min: [-1.0, -1.0, -1.0],
            max: [1.0, 1.0, 1.0],
        };
        let h = intersect(&b, &ray([5.0, 0.5, 0.0], [-1.0, 0.0, 0.0]), 0.0, 10.0).unwrap();
        assert_eq!((h.t, h.normal), (4.0, v3(1.0, 0.0, 0.0)));
        let h = intersect(&b, &ray([0.0, 0.0, 0.0], [0.0, 0.0, 2.0]), 0.0, 10.0).unwrap();
        assert_eq!((h.t, h.normal), (0.5, v3(0.0, 0.0, -1.0)));
        assert!(intersect(&b, &ray([5.0, 1.5, 0.0], [-1.0, 0.0, 0.0]), 0.0, 10.0).is_none());
    }
}
