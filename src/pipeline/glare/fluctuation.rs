//! Fluctuating sources' patches through the chaos map (eqs. 9–11).

use super::host::ScreenSource;
use crate::scene::format::Scene;
use rtl_model::{ConfigError, Counters, UnitSummary};
use std::collections::BTreeMap;

/// S_i(t) per patch (patch order) and the unit's summary, if elaborated.
pub fn patch_levels(
    _scene: &Scene,
    screens: &[ScreenSource],
    _ctr: &mut BTreeMap<String, Counters>,
) -> Result<(Vec<f64>, (bool, Option<UnitSummary>)), ConfigError> {
    if screens.iter().all(|s| s.patch.is_none()) {
        return Ok((Vec::new(), (false, None)));
    }
    Err(ConfigError::invalid(
        "glare.sources",
        "fluctuation not wired yet",
    ))
}
