//! Highlights through the glare-condition unit (Table 2).

use super::host::ScreenSource;
use crate::scene::format::Scene;
use rtl_model::{ConfigError, Counters, UnitSummary};
use std::collections::BTreeMap;

/// Highlight sources (with their intensity) and the unit's summary, if elaborated.
pub fn highlight_sources(
    scene: &Scene,
    _ctr: &mut BTreeMap<String, Counters>,
) -> Result<(Vec<(ScreenSource, f64)>, (bool, Option<UnitSummary>)), ConfigError> {
    let g = super::frame::glare_of(scene)?;
    if g.highlights.is_empty() {
        return Ok((Vec::new(), (false, None)));
    }
    Err(ConfigError::invalid("glare.highlights", "not wired yet"))
}
