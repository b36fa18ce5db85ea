//! Chip presets: which chip's behaviour the units follow where the GeForce2 (NV15), whose
//! behaviour the project's defaults reproduce, and the original Xbox's NV2A (a
//! GeForce3-class chip, the chip of the public hardware captures the conformance suites
//! compare with) differ. This is the one mapping from a chip to its units' modes: a
//! scene's `chip` field and `conformance run --chip` both go through it.
//!
//! Per unit (docs/conformance.md, "Where they differ"):
//! * `register_combiner`: the NV2A's BIAS_BY_NEGATIVE_ONE_HALF subtracts 2^(N−2) codes
//!   ([`BiasConstant::HalfCode`]) and its mux tests SPARE0 alpha's low bit
//!   ([`MuxSelect::Lsb`], NV097_SET_COMBINER_CONTROL's reset value); the GeForce2
//!   follows GL_NV_register_combiners (exactly ½, the top bit). Read from the CC0
//!   Combiner captures of github.com/abaire/nxdk_pgraph_tests_golden_results
//!   (CombinerOps, Mux). The NV20 register state the GeForce2 has no field for
//!   (blue-to-alpha, per-stage constants) is the application's to set, not the
//!   chip's: at its reset value (off, shared constants) the NV2A computes as the
//!   GeForce2, so the preset leaves it.
//! * `final_combiner`: no behavioural difference. Its NV2A fields (the add-invert
//!   flags of SPARE0 + SECONDARY, its own constants) are register state the
//!   application sets, off at reset.
//! * `blend`: the NV2A rounds (s·f_s ± d·f_d)/M once ([`BlendRounding::Once`], the
//!   Blend_tests captures: every compared pixel); the GeForce2 preset weights a term
//!   with a `modulate` and then adds it, as the project's GeForce2 pipelines blend
//!   (a texture modulate, then `additive_blend`): [`BlendRounding::PerTerm`]. With a
//!   destination factor of ONE (the project's additive blends) the two are equal.
//! * `shadow_compare`: no behavioural difference. The compare function and the depth
//!   texel format are state the application sets (the Texture_shadow_comparator
//!   captures show the NV2A doing what each test sets, as the unit does).
//! * `vertex_lighting`: the NV2A keeps a directional light's vector as the host wrote it
//!   (no normalisation at load) and lights into two colours under its light-control
//!   switches (the Specular ControlFlags captures); the GeForce2 preset is GL 1.3's
//!   single colour with the direction normalised.
//! * unbound texture units: the NV2A reads (0, 0, 0, 1) (Combiner/UnboundTexSampler);
//!   GL leaves it to the texture environment, and no pipeline of the project leaves a
//!   unit unbound.

use crate::error::ConfigError;
use crate::units::blend::{BlendConfig, BlendRounding};
use crate::units::final_combiner::FinalCombinerConfig;
use crate::units::register_combiner::{
    unbound_texture, BiasConstant, MuxSelect, RegisterCombinerConfig,
};
use crate::units::shadow_compare::ShadowCompareConfig;
use crate::units::vertex_lighting::{LightControl, VertexLightingConfig};
use serde::{Deserialize, Serialize};

/// A chip whose behaviour the units follow where the two differ (module notes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ChipPreset {
    /// The GeForce2 (NV15): the project's defaults; the built-in scenes' bytes.
    #[default]
    GeForce2,
    /// The original Xbox's NV2A (GeForce3-class): the hardware captures' chip.
    Nv2a,
}

/// The light-control switches an OpenGL program's state gives the NV2A: lighting on,
/// specular on, GL's default LIGHT_MODEL_COLOR_CONTROL = SINGLE_COLOR (the specular
/// sum joins the primary colour), no specular alpha from the vertex.
pub const GL_SINGLE_COLOR: LightControl = LightControl {
    lighting: true,
    specular_enable: true,
    separate_specular: false,
    specular_alpha_from_vertex: false,
};

/// One mode a preset sets: the unit, its config field and the value.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct PresetMode {
    /// The unit the preset configures, by its file name ("register_combiner", …).
    pub unit: &'static str,
    /// The config field of that unit the preset sets ("bias_constant", …).
    pub field: &'static str,
    /// The value the preset gives the field, as text (a mode name or a number).
    pub value: String,
}

impl ChipPreset {
    /// Every preset, the default first.
    pub const ALL: [ChipPreset; 2] = [ChipPreset::GeForce2, ChipPreset::Nv2a];
    /// Their names, as scene files and `--chip` write them.
    pub const NAMES: [&'static str; 2] = ["geforce2", "nv2a"];

    /// The preset's name ("geforce2", "nv2a").
    pub fn name(self) -> &'static str {
        match self {
            ChipPreset::GeForce2 => Self::NAMES[0],
            ChipPreset::Nv2a => Self::NAMES[1],
        }
    }

    /// The preset named `s`; anything else is an error naming `field`.
    pub fn parse(field: &str, s: &str) -> Result<ChipPreset, ConfigError> {
        Self::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| {
                ConfigError::invalid(
                    field,
                    &format!(
                        "unknown chip preset '{s}' (known: {})",
                        Self::NAMES.join(", ")
                    ),
                )
            })
    }

    /// Whether this is the default (the GeForce2): scene files leave it out.
    pub fn is_default(&self) -> bool {
        *self == ChipPreset::GeForce2
    }

    /// `register_combiner`: `cfg` with this chip's bias constant and default mux select
    /// (an application that sets MUX_SELECT itself overrides the latter).
    pub fn register_combiner(self, cfg: RegisterCombinerConfig) -> RegisterCombinerConfig {
        let (bias_constant, mux_select) = match self {
            ChipPreset::GeForce2 => (BiasConstant::ExactHalf, MuxSelect::Msb),
            ChipPreset::Nv2a => (BiasConstant::HalfCode, MuxSelect::Lsb),
        };
        RegisterCombinerConfig {
            bias_constant,
            mux_select,
            ..cfg
        }
    }

    /// `final_combiner`: `cfg` as given on both chips (module notes: its NV2A fields are
    /// register state, not behaviour).
    pub fn final_combiner(self, cfg: FinalCombinerConfig) -> FinalCombinerConfig {
        cfg
    }

    /// `blend`: where the weighted terms return to n bits on this chip.
    pub fn blend_rounding(self) -> BlendRounding {
        match self {
            ChipPreset::GeForce2 => BlendRounding::PerTerm,
            ChipPreset::Nv2a => BlendRounding::Once,
        }
    }

    /// `blend`: `cfg` with this chip's rounding.
    pub fn blend(self, cfg: BlendConfig) -> BlendConfig {
        BlendConfig {
            rounding: self.blend_rounding(),
            ..cfg
        }
    }

    /// `shadow_compare`: `cfg` as given on both chips (module notes: the compare
    /// function and texel format are the application's state).
    pub fn shadow_compare(self, cfg: ShadowCompareConfig) -> ShadowCompareConfig {
        cfg
    }

    /// `vertex_lighting`: `cfg` with this chip's directional-light load and colour
    /// output; `switches` is the application's light-control state (the NV2A's
    /// registers; [`GL_SINGLE_COLOR`] for an OpenGL program's), which the GeForce2's
    /// single-colour datapath has no use for.
    pub fn vertex_lighting(
        self,
        cfg: VertexLightingConfig,
        switches: LightControl,
    ) -> VertexLightingConfig {
        match self {
            ChipPreset::GeForce2 => VertexLightingConfig {
                normalize_directional: true,
                light_control: None,
                ..cfg
            },
            ChipPreset::Nv2a => VertexLightingConfig {
                normalize_directional: false,
                light_control: Some(switches),
                ..cfg
            },
        }
    }

    /// What a texture stage with no texture bound reads, `bits`-bit unorm RGBA: the
    /// NV2A's (0, 0, 0, 1); None on the GeForce2 preset (GL leaves it to the texture
    /// environment).
    pub fn unbound_texture(self, bits: u32) -> Option<[u32; 4]> {
        match self {
            ChipPreset::GeForce2 => None,
            ChipPreset::Nv2a => Some(unbound_texture(bits)),
        }
    }

    /// The modes this preset sets, each read back from the methods above (so the list
    /// cannot disagree with them), for reports.
    pub fn modes(self) -> Vec<PresetMode> {
        let rc = self.register_combiner(RegisterCombinerConfig::geforce());
        let vl = self.vertex_lighting(VertexLightingConfig::geforce(), GL_SINGLE_COLOR);
        let m = |unit, field, value: String| PresetMode { unit, field, value };
        vec![
            m(
                "register_combiner",
                "bias_constant",
                format!("{:?}", rc.bias_constant),
            ),
            m(
                "register_combiner",
                "mux_select",
                format!("{:?}", rc.mux_select),
            ),
            m("blend", "rounding", format!("{:?}", self.blend_rounding())),
            m(
                "vertex_lighting",
                "normalize_directional",
                vl.normalize_directional.to_string(),
            ),
            m(
                "vertex_lighting",
                "light_control",
                match vl.light_control {
                    None => "none (one colour)".into(),
                    Some(_) => "two colours (NV2A light control)".into(),
                },
            ),
        ]
    }

    /// Whether the preset gives `unit` (a registry name) other modes than the GeForce2
    /// preset does.
    pub fn changes(self, unit: &str) -> bool {
        self != ChipPreset::GeForce2
            && ChipPreset::GeForce2
                .modes()
                .iter()
                .zip(self.modes())
                .any(|(a, b)| a.unit == unit && a.value != b.value)
    }
}

impl std::fmt::Display for ChipPreset {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geforce2_preset_is_the_units_defaults_but_for_the_blend_rounding() {
        let g = ChipPreset::GeForce2;
        assert_eq!(
            g.register_combiner(RegisterCombinerConfig::geforce()),
            RegisterCombinerConfig::geforce()
        );
        assert_eq!(
            g.vertex_lighting(VertexLightingConfig::geforce(), GL_SINGLE_COLOR),
            VertexLightingConfig::geforce()
        );
        assert_eq!(g.blend_rounding(), BlendRounding::PerTerm);
        assert!(g.unbound_texture(8).is_none());
    }

    #[test]
    fn nv2a_preset_sets_the_captures_modes() {
        let n = ChipPreset::Nv2a;
        let rc = n.register_combiner(RegisterCombinerConfig::geforce());
        assert_eq!(rc.bias_constant, BiasConstant::HalfCode);
        assert_eq!(rc.mux_select, MuxSelect::Lsb);
        let vl = n.vertex_lighting(VertexLightingConfig::geforce(), GL_SINGLE_COLOR);
        assert!(!vl.normalize_directional);
        assert_eq!(vl.light_control, Some(GL_SINGLE_COLOR));
        assert_eq!(n.blend_rounding(), BlendRounding::Once);
        assert_eq!(n.unbound_texture(8), Some([0, 0, 0, 255]));
        for u in ["register_combiner", "blend", "vertex_lighting"] {
            assert!(n.changes(u), "{u}");
            assert!(!ChipPreset::GeForce2.changes(u), "{u}");
        }
        for u in ["final_combiner", "shadow_compare", "texture_combiner"] {
            assert!(!n.changes(u), "{u}");
        }
    }

    #[test]
    fn names_parse_back_and_others_name_the_field() {
        for c in ChipPreset::ALL {
            assert_eq!(ChipPreset::parse("chip", c.name()).unwrap(), c);
        }
        let e = ChipPreset::parse("scene.chip", "nv20").unwrap_err();
        assert_eq!(e.field(), "scene.chip");
        assert!(e.to_string().contains("geforce2, nv2a"), "{e}");
    }
}
