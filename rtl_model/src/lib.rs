//! The hardware: bit-accurate, cycle-level units of a GeForce2/GeForce3-era glare and
//! shading pipeline. Integers only in datapaths; nothing here imports the main crate.

pub mod chip_preset;
pub mod cost;
pub mod counters;
pub mod driver;
pub mod error;
pub mod fixed_point;
pub mod float_format;
pub mod lighting_state;
pub mod memory;
pub mod packed_rom;
pub mod trace;
pub mod unit;
pub mod units;
pub mod unorm;
pub mod wire;

pub use chip_preset::ChipPreset;
pub use cost::{Cells, Cost};
pub use counters::Counters;
pub use error::ConfigError;
pub use fixed_point::{Format, Fx, Overflow, Quant};
pub use float_format::{FloatFormat, Fp, Rounding, Subnormals};
pub use unit::{Signal, Timing, Unit, UnitSummary, Width};
