//! One file per hardware unit. Each has an f64 twin in the main crate's
//! `src/reference/`, a property test in `tests/` and a datasheet in `docs/units.md`.

pub mod blend;
pub mod bloom_flare_modulator;
pub mod chaos_map;
pub mod clipper;
pub mod cube_map_address;
pub mod final_combiner;
pub mod gaussian_noise;
pub mod glare_combiner;
pub mod glare_condition;
pub mod halo_modulator;
pub mod luminance_ram;
pub mod modulate;
pub mod modulate_chain;
pub mod polygon_interpolator;
pub mod polygon_variable_generator;
pub mod projective_texcoord;
pub mod reflection_vector;
pub mod register_combiner;
pub mod shadow_compare;
pub mod specular_lookup;
pub mod texture_combiner;
// Its public items are documented separately (the file is being edited elsewhere);
// remove this allow once they are.
#[allow(missing_docs)]
pub mod texture_sampler;
pub mod vertex_lighting;

/// Whether the lane indices `idx` are first, first + 1, … (lanes on neighbouring words
/// in a rightward run; true when empty): every index checked with no early exit, so
/// the check runs in vector registers.
#[inline(always)]
pub fn rising_run(idx: &[u32]) -> bool {
    let first = idx.first().map_or(0, |&i| i as usize);
    idx.iter()
        .zip(first..)
        .fold(true, |run, (&i, j)| run & (i as usize == j))
}

/// Whether the lane indices `idx` are first, first − 1, … (a leftward run; one that
/// would pass below 0 is not), checked as [`rising_run`].
#[inline(always)]
pub(crate) fn falling_run(idx: &[u32]) -> bool {
    let first = idx.first().map_or(0, |&i| i as usize);
    idx.iter().enumerate().fold(true, |run, (j, &i)| {
        run & (i as usize == first.wrapping_sub(j))
    })
}
