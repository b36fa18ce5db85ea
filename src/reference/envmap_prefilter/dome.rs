//! Geodesic domes: class-I, frequency-n subdivision of the icosahedron, projected
//! centrally onto the unit sphere (each face's planar grid point (i·A + j·B + k·C)/n,
//! i + j + k = n, normalised). 10n² + 2 vertices, 20n² spherical triangles.
//!
//! Shared vertices are merged exactly: a grid point is keyed by its integer
//! barycentric weights on the icosahedron's corner indices (zero weights dropped,
//! corners in increasing order), so a point on an edge or a corner gets the same key
//! from every face that holds it — no float hashing.
//!
//! Per-vertex solid angle Ω(ω): one third of the area of every incident spherical
//! triangle (the triangle's area is its spherical excess, Van Oosterom–Strackee:
//! tan(E/2) = |a·(b×c)| / (1 + a·b + b·c + c·a)). The triangles tile the sphere,
//! so the Ω sum to 4π up to rounding (|Σ − 4π| < 1e-9 tested). Central projection is
//! not equal-area: Ω max/min is 2.09 / 2.24 / 2.32 / 2.35 at n = 9 / 18 / 36 / 72
//! (1.59 … 1.94 without the 12 five-valent corners, which get 5 triangles, not 6).
//! Build time at n = 72: ≈ 7 ms (test profile).

use rtl_model::error::ConfigError;
use std::collections::HashMap;

use super::equirect::Equirect;

/// The thesis' four domes (Table 2): 51 842, 12 962, 3 242, 812 vertices, paired
/// with the pyramid levels 512×256, 256×128, 128×64, 64×32.
pub const THESIS_DOME_FREQUENCIES: [u32; 4] = [72, 36, 18, 9];

/// Largest accepted frequency (10n² + 2 ≈ 4·10⁷ vertices at 2048).
pub const MAX_DOME_FREQUENCY: u32 = 2048;

/// A geodesic dome: unit vertex directions and their solid angles.
#[derive(Clone, Debug, PartialEq)]
pub struct Dome {
    frequency: u32,
    dirs: Vec<[f64; 3]>,
    solid_angles: Vec<f64>,
}

/// Key of a grid point: (corner, weight) pairs with weight > 0, corners increasing,
/// padded with (u32::MAX, 0).
type Key = [(u32, u32); 3];

impl Dome {
    /// Frequency n ∈ 1 ..= 2048 (field `envmap_prefilter.dome_frequency`).
    pub fn new(frequency: u32) -> Result<Self, ConfigError> {
        rtl_model::error::check_range(
            "envmap_prefilter.dome_frequency",
            frequency as u64,
            1,
            MAX_DOME_FREQUENCY as u64,
        )?;
        let n = frequency;
        let (corners, faces) = icosahedron();
        let expected = 10 * (n as usize) * (n as usize) + 2;
        let mut index: HashMap<Key, u32> = HashMap::with_capacity(expected);
        let mut dirs: Vec<[f64; 3]> = Vec::with_capacity(expected);
        let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(20 * (n as usize) * (n as usize));
        let mut grid: Vec<u32> = Vec::new();

        for face in &faces {
            let [a, b, c] = *face; // corner indices, a < b < c
            let (pa, pb, pc) = (
                corners[a as usize],
                corners[b as usize],
                corners[c as usize],
            );
            // grid[(i, j)] for i + j ≤ n, row i of length n + 1 − i.
            grid.clear();
            for i in 0..=n {
                for j in 0..=(n - i) {
                    let k = n - i - j;
                    let mut key: Key = [(u32::MAX, 0); 3];
                    let mut m = 0;
                    for (corner, weight) in [(a, i), (b, j), (c, k)] {
                        if weight > 0 {
                            key[m] = (corner, weight);
                            m += 1;
                        }
                    }
                    let id = *index.entry(key).or_insert_with(|| {
                        let (fi, fj, fk) = (i as f64, j as f64, k as f64);
                        let p = [
                            fi * pa[0] + fj * pb[0] + fk * pc[0],
                            fi * pa[1] + fj * pb[1] + fk * pc[1],
                            fi * pa[2] + fj * pb[2] + fk * pc[2],
                        ];
                        dirs.push(normalise(p));
                        (dirs.len() - 1) as u32
                    });
                    grid.push(id);
                }
            }
            let row_start = |i: u32| -> usize {
                // Σ_{r<i} (n + 1 − r)
                (i * (n + 1) - i * (i.saturating_sub(1)) / 2) as usize
            };
            let at = |i: u32, j: u32| grid[row_start(i) + j as usize];
            for i in 0..n {
                for j in 0..(n - i) {
                    triangles.push([at(i, j), at(i + 1, j), at(i, j + 1)]);
                    if i + j + 1 < n {
                        triangles.push([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
                    }
                }
            }
        }

        let mut solid_angles = vec![0.0; dirs.len()];
        for t in &triangles {
            let e = spherical_triangle_area(
                dirs[t[0] as usize],
                dirs[t[1] as usize],
                dirs[t[2] as usize],
            );
            for &v in t {
                solid_angles[v as usize] += e / 3.0;
            }
        }
        Ok(Dome {
            frequency,
            dirs,
            solid_angles,
        })
    }

    pub fn frequency(&self) -> u32 {
        self.frequency
    }
    /// Unit vertex directions.
    pub fn dirs(&self) -> &[[f64; 3]] {
        &self.dirs
    }
    /// Per-vertex solid angles (sum 4π).
    pub fn solid_angles(&self) -> &[f64] {
        &self.solid_angles
    }
    pub fn len(&self) -> usize {
        self.dirs.len()
    }
    pub fn is_empty(&self) -> bool {
        self.dirs.is_empty()
    }

    /// Radiance at each vertex: bilinear lookup in `map` at the vertex direction.
    pub fn resample(&self, map: &Equirect) -> Vec<[f64; 3]> {
        self.dirs.iter().map(|&d| map.sample_bilinear(d)).collect()
    }
}

/// Vertex count of a class-I frequency-n dome: 10n² + 2.
pub fn dome_vertex_count(frequency: u32) -> u64 {
    10 * (frequency as u64) * (frequency as u64) + 2
}

/// Area (spherical excess) of the spherical triangle with unit corners a, b, c.
pub fn spherical_triangle_area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let cross = [
        b[1] * c[2] - b[2] * c[1],
        b[2] * c[0] - b[0] * c[2],
        b[0] * c[1] - b[1] * c[0],
    ];
    let triple = (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]).abs();
    let denom = 1.0 + dot(a, b) + dot(b, c) + dot(c, a);
    2.0 * triple.atan2(denom)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalise(p: [f64; 3]) -> [f64; 3] {
    let l = dot(p, p).sqrt();
    [p[0] / l, p[1] / l, p[2] / l]
}

/// The icosahedron: 12 corners (0, ±1, ±φ) and cyclic permutations (not normalised,
/// edge length 2) and its 20 faces, found as the vertex triples at mutual distance 2,
/// each with corner indices increasing.
fn icosahedron() -> ([[f64; 3]; 12], Vec<[u32; 3]>) {
    let p = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v = [[0.0; 3]; 12];
    let mut k = 0;
    for s1 in [-1.0, 1.0] {
        for s2 in [-1.0, 1.0] {
            v[k] = [0.0, s1, s2 * p];
            v[k + 1] = [s1, s2 * p, 0.0];
            v[k + 2] = [s2 * p, 0.0, s1];
            k += 3;
        }
    }
    let edge = |a: usize, b: usize| {
        let d = [v[a][0] - v[b][0], v[a][1] - v[b][1], v[a][2] - v[b][2]];
        (dot(d, d) - 4.0).abs() < 1e-9
    };
    let mut faces = Vec::with_capacity(20);
    for a in 0..12 {
        for b in a + 1..12 {
            for c in b + 1..12 {
                if edge(a, b) && edge(b, c) && edge(a, c) {
                    faces.push([a as u32, b as u32, c as u32]);
                }
            }
        }
    }
    debug_assert_eq!(faces.len(), 20);
    (v, faces)
}
