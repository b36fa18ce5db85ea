//! f64 twin of polygon_variable_generator: the exact corners and (u, v) of an area
//! quad or a flare-line rectangle (see the unit for the conventions).

/// Which primitive (mirrors the unit's kind without importing it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Area,
    Line,
}

/// Corners v0, v1, v2 as (x, y, u, v); positions in the same units as the inputs.
pub fn corners(
    kind: Kind,
    cx: f64,
    cy: f64,
    extent: f64,
    half_width: f64,
    phi: f64,
) -> [[f64; 4]; 3] {
    let (c, s) = (phi.cos(), phi.sin());
    match kind {
        Kind::Area => [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0)].map(|(sx, sy)| {
            [
                cx + sx * extent,
                cy + sy * extent,
                sx * c + sy * s,
                -sx * s + sy * c,
            ]
        }),
        Kind::Line => {
            let (lx, ly) = (extent * c, extent * s);
            let (nx, ny) = (-half_width * s, half_width * c);
            [
                [cx - nx, cy - ny, -1.0, -1.0],
                [cx + lx - nx, cy + ly - ny, 1.0, -1.0],
                [cx + lx + nx, cy + ly + ny, 1.0, 1.0],
            ]
        }
    }
}
