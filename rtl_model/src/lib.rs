//! The hardware: bit-accurate, cycle-level units of a GeForce2/GeForce3-era glare and
//! shading pipeline. Integers only in datapaths; nothing here imports the main crate.
//!
//! Every unit ([`units`]) obeys one contract ([`Unit`]): a validated config whose widths
//! are runtime fields, an integer kernel, its timing (latency and initiation interval)
//! and its cost in NAND2 gates. Three drivers ([`driver`]) run the same arithmetic: the
//! tick driver one clock at a time (and to VCD), the span driver, and the batch path the
//! pipelines use; they give the same outputs and counters.
//!
//! ```
//! use rtl_model::driver::{run_batch, run_span};
//! use rtl_model::units::modulate::{Modulate, ModulateIn, ModulateMode};
//! use rtl_model::{ConfigError, Counters, Unit};
//!
//! // A 10-bit multiplier that drops the divide: (a·b) >> 10, low by up to 2 LSB.
//! let unit = Modulate::new(10, ModulateMode::Shift)?;
//! let inputs: Vec<ModulateIn> = (0..1000u32)
//!     .map(|i| ModulateIn { a: (i * 37) % 1024, b: (i * 101) % 1024 })
//!     .collect();
//! let (mut span, mut batch) = (Counters::default(), Counters::default());
//! let a = run_span(&unit, &mut (), &inputs, &mut span);
//! let b = run_batch(&unit, &mut (), &inputs, 64, &mut batch);
//! assert_eq!(a, b);
//! assert_eq!(span, batch);
//! for (x, &o) in inputs.iter().zip(&a) {
//!     let exact = (x.a * x.b) as f64 / 1023.0;
//!     assert!(o as f64 <= exact && exact - (o as f64) < 2.0);
//! }
//! assert!(unit.cost().gates_nand2() > 0.0);
//! // A width out of range is an error naming the field, never a panic.
//! let e: ConfigError = Modulate::new(17, ModulateMode::Exact).unwrap_err();
//! assert_eq!(e.field(), "modulate.bits");
//! # Ok::<(), ConfigError>(())
//! ```

#![warn(missing_docs)]

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
