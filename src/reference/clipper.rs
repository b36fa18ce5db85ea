//! f64 twin of `clipper`: Sutherland–Hodgman against the same planes (near, far, the
//! guard band's four edges) in homogeneous clip space, then the perspective divide and
//! viewport transform, all in f64 with no rounding. The cut parameter is
//! t = d_I / (d_I − d_O) from the inside vertex; attributes are interpolated at t on
//! the near plane and at the screen parameter s = t·w_O / w_new on the others (or at
//! t everywhere for `homogeneous`), as the unit does.

/// A clip-space vertex: (x, y, z, w) and attributes.
#[derive(Clone, Debug, PartialEq)]
pub struct ClipVertexF {
    pub c: [f64; 4],
    pub attrs: Vec<f64>,
}

/// A screen vertex: position in pixels (y down), window depth in [0, 1], attributes.
#[derive(Clone, Debug, PartialEq)]
pub struct ScreenVertexF {
    pub x: f64,
    pub y: f64,
    pub depth: f64,
    pub attrs: Vec<f64>,
}

/// The planes and viewport of a clipper.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipSetup {
    pub width: f64,
    pub height: f64,
    pub guard_min: f64,
    pub guard_max: f64,
    /// Whether the far plane is clipped.
    pub far: bool,
    /// Attributes at the screen parameter on the non-near planes.
    pub screen_attrs: bool,
}

impl ClipSetup {
    /// Signed distances to near, far, left, right, top, bottom (≥ 0 inside).
    pub fn distances(&self, c: &[f64; 4]) -> [f64; 6] {
        let [x, y, z, w] = *c;
        let sx = (x + w) * self.width;
        let sy = (w - y) * self.height;
        [
            z + w,
            w - z,
            sx - 2.0 * self.guard_min * w,
            2.0 * self.guard_max * w - sx,
            sy - 2.0 * self.guard_min * w,
            2.0 * self.guard_max * w - sy,
        ]
    }

    fn active(&self, p: usize) -> bool {
        p != 1 || self.far
    }

    /// Whether every vertex is outside one plane, or (all in front of the eye) outside
    /// one edge of the viewport: the triangle is culled.
    pub fn culled(&self, tri: &[ClipVertexF; 3]) -> bool {
        let d: Vec<[f64; 6]> = tri.iter().map(|v| self.distances(&v.c)).collect();
        if (0..6).any(|p| self.active(p) && d.iter().all(|d| d[p] < 0.0)) {
            return true;
        }
        if tri.iter().any(|v| v.c[3] <= 0.0) {
            return false;
        }
        let view = |v: &ClipVertexF| {
            let [x, y, _, w] = v.c;
            let (sx, sy) = ((x + w) * self.width, (w - y) * self.height);
            [
                sx < 0.0,
                sx > 2.0 * self.width * w,
                sy < 0.0,
                sy > 2.0 * self.height * w,
            ]
        };
        let o: Vec<[bool; 4]> = tri.iter().map(view).collect();
        (0..4).any(|e| o.iter().all(|o| o[e]))
    }

    /// The clipped polygon in clip space (empty when culled or nothing is left).
    pub fn clip_polygon(&self, tri: &[ClipVertexF; 3]) -> Vec<ClipVertexF> {
        if self.culled(tri) {
            return Vec::new();
        }
        let mut poly: Vec<ClipVertexF> = tri.to_vec();
        for p in 0..6 {
            if !self.active(p) || poly.is_empty() {
                continue;
            }
            poly = self.clip_stage(&poly, p);
        }
        poly
    }

    /// One stage of [`ClipSetup::clip_polygon`]: `poly` clipped by plane `p` alone
    /// (Sutherland–Hodgman); unchanged when wholly inside, empty when less than a
    /// triangle is left.
    pub fn clip_stage(&self, poly: &[ClipVertexF], p: usize) -> Vec<ClipVertexF> {
        let d: Vec<f64> = poly.iter().map(|v| self.distances(&v.c)[p]).collect();
        if d.iter().all(|&x| x >= 0.0) {
            return poly.to_vec();
        }
        let n = poly.len();
        let mut next = Vec::with_capacity(n + 1);
        for a in 0..n {
            let b = (a + 1) % n;
            if d[a] >= 0.0 {
                next.push(poly[a].clone());
            }
            if (d[a] >= 0.0) != (d[b] >= 0.0) {
                let (i, o, di, d_o) = if d[a] >= 0.0 {
                    (&poly[a], &poly[b], d[a], d[b])
                } else {
                    (&poly[b], &poly[a], d[b], d[a])
                };
                next.push(self.cut(i, o, di, d_o, p));
            }
        }
        if next.len() < 3 {
            Vec::new()
        } else {
            next
        }
    }

    fn cut(&self, i: &ClipVertexF, o: &ClipVertexF, di: f64, d_o: f64, p: usize) -> ClipVertexF {
        let t = (di / (di - d_o)).clamp(0.0, 1.0);
        let c: [f64; 4] = std::array::from_fn(|k| i.c[k] + t * (o.c[k] - i.c[k]));
        let a_t = if p == 0 || !self.screen_attrs || c[3] <= 0.0 {
            t
        } else {
            (t * o.c[3] / c[3]).clamp(0.0, 1.0)
        };
        let attrs = (i.attrs.iter().zip(&o.attrs))
            .map(|(a, b)| a + a_t * (b - a))
            .collect();
        ClipVertexF { c, attrs }
    }

    /// Perspective divide and viewport transform of a clip-space vertex (w > 0).
    pub fn to_screen(&self, v: &ClipVertexF) -> ScreenVertexF {
        let [x, y, z, w] = v.c;
        ScreenVertexF {
            x: (x + w) * self.width / (2.0 * w),
            y: (w - y) * self.height / (2.0 * w),
            depth: (z + w) / (2.0 * w),
            attrs: v.attrs.clone(),
        }
    }

    /// The whole clipper: the clipped polygon on the screen (empty when culled).
    pub fn clip(&self, tri: &[ClipVertexF; 3]) -> Vec<ScreenVertexF> {
        let poly = self.clip_polygon(tri);
        if poly.iter().any(|v| v.c[3] <= 0.0) {
            return Vec::new();
        }
        poly.iter().map(|v| self.to_screen(v)).collect()
    }
}
