//! glare_dpi — the model's units as a C library, the golden reference of a
//! SystemVerilog testbench over DPI-C (docs/rtl.md, section DPI-C).
//!
//! * [`model`]: a unit with its state and counters behind one type-erased handle,
//!   stepped on the values of its Verilog ports (`Unit::in_signals` /
//!   `Unit::out_signals`: the bits of each wire, zero-extended), or on the packed
//!   port word the generic testbench drives.
//! * [`abi`]: the C ABI over it (exported under its C names with feature `dpi`) — `<unit>_new(config fields…)`,
//!   `<unit>_kernel(handle, inputs…, outputs*)`, `<unit>_free`, and the generic
//!   `glare_dpi_*` calls the SystemVerilog testbench imports.
//! * [`header`]: the C header, generated from the ABI's source
//!   (`include/glare_dpi.h`; `tests/header.rs` fails when it is stale).
//!
//! Nothing here imports the main crate: it depends on `rtl_model` only.

pub mod abi;
pub mod header;
pub mod model;

/// The ABI's source, from which the header is generated.
pub const ABI_SOURCE: &str = include_str!("abi.rs");
