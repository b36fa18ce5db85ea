//! f64 twin of `cube_map_address`: the exact cube-map mapping of OpenGL's Table 3.23
//! (ARB_texture_cube_map) on the direction d = c − s/2 of the reflection unit's
//! texel-space coordinates c = (t + 1)/2 · s.
//!
//! Faces 0 ..= 5 = +x, −x, +y, −y, +z, −z; (sc, tc) per face: +x (−d_z, −d_y),
//! −x (+d_z, −d_y), +y (+d_x, +d_z), −y (+d_x, −d_z), +z (+d_x, −d_y), −z (−d_x, −d_y);
//! (s, t) = ((sc/|ma| + 1)/2, (tc/|ma| + 1)/2) · F texels. Tie rule (the unit's): x if
//! |d_x| ≥ |d_y| and |d_x| ≥ |d_z|, else y if |d_y| ≥ |d_z|, else z. d = 0: face 0 at
//! the centre (F/2, F/2). Non-finite components read as 0, so no NaN comes out.
//!
//! [`face_direction`] is the inverse (a face texel's direction), used to build the cube
//! map's texels from the voxel map.

/// Major axis, face and (sc/|ma|, tc/|ma|) ∈ [−1, 1]² of `d`; None for d = 0.
pub fn face_and_ratios(d: [f64; 3]) -> Option<(u8, [f64; 2])> {
    let d = d.map(|c| if c.is_finite() { c } else { 0.0 });
    let m = d.map(f64::abs);
    if m == [0.0; 3] {
        return None;
    }
    let axis = if m[0] >= m[1] && m[0] >= m[2] {
        0
    } else if m[1] >= m[2] {
        1
    } else {
        2
    };
    let face = (2 * axis + usize::from(d[axis] < 0.0)) as u8;
    let [x, y, z] = d;
    let (sc, tc) = match face {
        0 => (-z, -y),
        1 => (z, -y),
        2 => (x, z),
        3 => (x, -z),
        4 => (x, -y),
        _ => (-x, -y),
    };
    let ma = m[axis];
    Some((face, [sc / ma, tc / ma]))
}

/// Face and face texel coordinates (s, t) in texels on a face of side `face_side`
/// (not clamped): ((sc/|ma| + 1)/2 · F, …); d = 0 → face 0 at (F/2, F/2).
pub fn face_st(d: [f64; 3], face_side: f64) -> (u8, [f64; 2]) {
    match face_and_ratios(d) {
        Some((f, q)) => (f, q.map(|v| (v + 1.0) * 0.5 * face_side)),
        None => (0, [0.5 * face_side; 2]),
    }
}

/// The stacked F × 6F texture's coordinates (texels): each face coordinate clamped to
/// the texel-centre range [½, F − ½] (clamp to edge), t offset by face·F.
pub fn stacked_st(face: u8, st: [f64; 2], face_side: f64) -> [f64; 2] {
    let c = |v: f64| v.clamp(0.5, face_side - 0.5);
    [c(st[0]), c(st[1]) + face as f64 * face_side]
}

/// The direction of the reflection unit's texel-space coordinates `c` (texels) for a
/// map of side `side`: d = c − s/2.
pub fn direction_of_coords(c: [f64; 3], side: f64) -> [f64; 3] {
    c.map(|v| v - 0.5 * side)
}

/// The twin on the unit's input words: raw codes with `frac_bits` fraction bits (exact
/// in f64 for ≤ 53-bit codes), map side 2^`side_log2`, face side 2^`face_log2`.
/// Returns (face, unclamped (s, t), stacked (s, t)) in texels.
pub fn cube_address_codes(
    coord: [i64; 3],
    frac_bits: u32,
    side_log2: u32,
    face_log2: u32,
) -> (u8, [f64; 2], [f64; 2]) {
    let k = (-(frac_bits as f64)).exp2();
    let d = direction_of_coords(coord.map(|x| x as f64 * k), (side_log2 as f64).exp2());
    let fs = (face_log2 as f64).exp2();
    let (face, st) = face_st(d, fs);
    (face, st, stacked_st(face, st, fs))
}

/// The unit directions through the texel centres of a cube map of face side `face`,
/// in the stacked F × 6F texture's order: face f, then row j, then column i, the centre
/// of texel (i, j) at ((i + ½)/F, (j + ½)/F).
pub fn texel_centre_directions(face: u32) -> impl Iterator<Item = [f64; 3]> {
    let ff = face as f64;
    (0..6u8).flat_map(move |f| {
        (0..face).flat_map(move |j| {
            (0..face).map(move |i| {
                let d = face_direction(f, (i as f64 + 0.5) / ff, (j as f64 + 0.5) / ff);
                let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                d.map(|c| c / l)
            })
        })
    })
}

/// The (not normalised) direction through the point (s, t) ∈ [0, 1]² of `face`
/// (faces ≥ 6 read as 5): the inverse of the table, with |ma| = 1.
pub fn face_direction(face: u8, s: f64, t: f64) -> [f64; 3] {
    let sc = 2.0 * s - 1.0;
    let tc = 2.0 * t - 1.0;
    match face {
        0 => [1.0, -tc, -sc],
        1 => [-1.0, -tc, sc],
        2 => [sc, 1.0, tc],
        3 => [sc, -1.0, -tc],
        4 => [sc, -tc, 1.0],
        _ => [-sc, -tc, -1.0],
    }
}
