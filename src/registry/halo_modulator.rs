//! `halo_modulator`: a halo primitive's luminance from its shape RAM and three ring
//! RAMs (one per wavelength).

use super::luminance_ram::{falloff_params, random_inputs};
use super::unit_entry::{rom, seeded, trace_unit, UnitEntry};
use crate::pipeline::glare::tables::{halo_prim, ring_samples, shape_samples};
use crate::reference::glare_model::{Shape2D, SourceGlare};
use crate::scene::glare::{Determinants, GlareModel};
use crate::tables::Table;
use rtl_model::units::halo_modulator::{HaloModulator, HaloModulatorConfig};
use rtl_model::units::luminance_ram::LumWidths;
use rtl_model::{Counters, UnitSummary};
use std::io::Write;

pub const ENTRY: UnitEntry = UnitEntry {
    name: "halo_modulator",
    summary: || UnitSummary::of(&default_halo()),
    tables,
    trace,
};

/// Pixels per degree of the representative halo source (a point source; the ring
/// tables do not depend on it, only its shape table's quad margin does).
const HALO_PX_PER_DEG: f64 = 20.0;

/// The representative halo: a point source of the default glare model and
/// determinants (λ = 650, 550, 450 nm). Returns θ_max (degrees) and the shape and
/// R, G, B ring samples the host writes, as the frame computes them.
fn default_halo_tables(w: &LumWidths) -> (f64, Vec<f64>, [Vec<f64>; 3]) {
    let model = GlareModel::default();
    let det = Determinants::default();
    let src = SourceGlare {
        center: [0.0, 0.0],
        shape: Shape2D::Point,
        px_per_deg: HALO_PX_PER_DEG,
        color: [1.0; 3],
        bloom: None,
        halo: Some(1.0),
        flare: None,
    };
    let (a, theta_max) = halo_prim(&src, &det, &model);
    let shape = shape_samples(&src.shape, &a, w.shape_log2);
    let rings = det
        .wavelengths_nm
        .map(|l| ring_samples(l, theta_max, &model, w.falloff_log2));
    (theta_max, shape, rings)
}

/// The default halo modulator holding the representative halo's tables.
pub fn default_halo() -> HaloModulator {
    let w = LumWidths::default();
    let (_, shape, r) = default_halo_tables(&w);
    HaloModulatorConfig::from_widths(w)
        .build(&shape, [&r[0], &r[1], &r[2]])
        .expect("the default modulator widths and the halo tables are valid")
}

/// The three ring RAMs of the default model. The halo shape RAM depends on each
/// source's outline and size and is written by the host per primitive: not here.
fn tables() -> Vec<Table> {
    let w = LumWidths::default();
    let (theta_max, _, _) = default_halo_tables(&w);
    let halo = default_halo();
    let model = GlareModel::default();
    let det = Determinants::default();
    ["r", "g", "b"]
        .iter()
        .enumerate()
        .map(|(c, ch)| {
            rom(
                format!(
                    "halo_modulator_ring_{ch}_m{}_b{}",
                    w.falloff_log2, w.falloff_bits
                ),
                w.falloff_bits,
                halo.ring_codes(c).iter().map(|&v| u64::from(v)).collect(),
                "halo_modulator",
                falloff_params(
                    &w,
                    &[
                        (
                            "generator",
                            "exp(-((theta - theta1*lambda/568)/alpha)^2) at theta = j/2^m * theta_max, \
                             j = 0 ..= 2^m, code = round(v * (2^fb - 1)); theta_max = \
                             theta1*max(lambda)/568 + 4*alpha (degrees)"
                                .into(),
                        ),
                        ("lambda_nm", det.wavelengths_nm[c].to_string()),
                        ("theta1_deg", model.halo_radius_deg.to_string()),
                        ("alpha_deg", model.halo_alpha_deg.to_string()),
                        ("theta_max_deg", format!("{theta_max:.12}")),
                        (
                            "loaded",
                            "by the host with each halo primitive; the same for every source of \
                             a scene with the default model and determinants"
                                .into(),
                        ),
                    ],
                ),
            )
        })
        .collect()
}

fn trace(pixels: usize, seed: u64, w: &mut dyn Write) -> Result<Counters, String> {
    let inputs = random_inputs(&mut seeded(seed), pixels);
    trace_unit(&default_halo(), (), &inputs, w)
}
