//! Fluctuating sources' patches through the chaos map (eqs. 9–11): each fluctuating
//! source has its own chaos-map unit with one state per patch, stepped `frame` times.

use super::host::ScreenSource;
use crate::scene::format::Scene;
use rtl_model::units::chaos_map::{ChaosMap, ChaosMapConfig, ChaosState};
use rtl_model::{ConfigError, Counters, Unit, UnitSummary};
use std::collections::BTreeMap;

/// The chaos-map unit of fluctuating source `i` with `patches` patches, and its
/// seeded start state.
pub fn chaos_unit(
    scene: &Scene,
    i: usize,
    patches: u32,
) -> Result<(ChaosMap, ChaosState), ConfigError> {
    let g = super::host::glare_of(scene)?;
    let u = ChaosMapConfig {
        a: g.model.chaos_a,
        z: g.model.chaos_z,
        patches,
        ..ChaosMapConfig::geforce()
    }
    .build()?;
    let st = u.seeded_state(scene.seed ^ ((i as u64 + 1) << 32));
    Ok((u, st))
}

/// Whether a unit was elaborated, and its summary.
pub type Elab = (bool, Option<UnitSummary>);

/// S_i(t) at t = the scene's frame, aligned with `screens` (1 for sources that do
/// not fluctuate), and (elaborated?, the unit's summary).
#[allow(clippy::type_complexity)]
pub fn patch_levels(
    scene: &Scene,
    screens: &[ScreenSource],
    ctr: &mut BTreeMap<String, Counters>,
) -> Result<(Vec<f64>, Elab), ConfigError> {
    let g = super::host::glare_of(scene)?;
    let mut levels = vec![1.0; screens.len()];
    let mut summary = None;
    for (i, src) in g.sources.iter().enumerate() {
        let Some(f) = src.fluctuation else { continue };
        let (u, mut st) = chaos_unit(scene, i, f.patches)?;
        let mut c = Counters::default();
        u.run_trace(&mut st, g.frame as usize, &mut c);
        *ctr.entry(u.name().to_string()).or_default() += c;
        let scale = (u.state_max() + 1) as f64;
        for (k, s) in screens.iter().enumerate() {
            if let Some((si, p)) = s.patch {
                if si == i {
                    levels[k] = st.s[p] as f64 / scale;
                }
            }
        }
        summary.get_or_insert_with(|| UnitSummary::of(&u));
    }
    let used = summary.is_some();
    let summary = match summary {
        Some(s) => Some(s),
        None => Some(UnitSummary::of(&ChaosMap::geforce())),
    };
    Ok((levels, (used, summary)))
}
