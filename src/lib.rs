//! The system around the hardware: f64 references, scenes, pipelines, reports, CLI.
//!
//! The hardware itself is the `rtl_model` crate (bit-accurate, cycle-level units); this
//! crate holds each unit's f64 twin ([`reference`](mod@crate::reference)), the scene
//! format ([`scene`]), the pipelines that chain the units into passes ([`pipeline`]),
//! one frame through every pipeline ([`frame`]), the chip's time ([`chip`]) and the
//! outputs ([`report`]).
//!
//! # A unit at your widths against its f64 twin
//!
//! Configure a unit, run a batch through the batch driver, and hold it to the bound its
//! widths give: `modulate` at 6 bits with exact rounding is within half an LSB of the
//! real product. The tick driver runs the same inputs clock by clock and writes a VCD.
//!
//! ```
//! use glare_pipeline::reference::modulate::modulate_codes;
//! use rtl_model::driver::{run_batch, run_tick};
//! use rtl_model::trace::VcdTrace;
//! use rtl_model::units::modulate::{Modulate, ModulateIn, ModulateMode};
//! use rtl_model::{Counters, Unit};
//!
//! let unit = Modulate::new(6, ModulateMode::Exact)?; // u6 × u6 → u12 → u6
//! let inputs: Vec<ModulateIn> = (0..64u32)
//!     .flat_map(|a| (0..64u32).map(move |b| ModulateIn { a, b }))
//!     .collect();
//! let mut ctr = Counters::default();
//! let out = run_batch(&unit, &mut (), &inputs, 256, &mut ctr);
//! for (x, &o) in inputs.iter().zip(&out) {
//!     let exact = modulate_codes(x.a, x.b, 6); // a·b / 63, in output LSBs
//!     assert!((o as f64 - exact).abs() <= 0.5, "{x:?}: {o} against {exact}");
//! }
//! // (n − 1)·II + latency + 1 clocks for the span, from the unit's timing.
//! assert_eq!(ctr.cycles, unit.timing().span_cycles(inputs.len() as u64));
//!
//! // The same inputs one clock at a time, traced.
//! let mut vcd = Vec::new();
//! let first = &inputs[0];
//! let mut trace = VcdTrace::new(
//!     &mut vcd,
//!     unit.name(),
//!     unit.timing().latency,
//!     &unit.in_signals(first),
//!     &unit.out_signals(&out[0]),
//! )?;
//! let mut tick_ctr = Counters::default();
//! let ticked = run_tick(&unit, &mut (), &inputs[..16], &mut tick_ctr, Some(&mut trace))?;
//! trace.finish()?;
//! assert_eq!(ticked, out[..16]);
//! assert!(String::from_utf8_lossy(&vcd).contains("$var wire"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # A built-in scene to a framebuffer, and its counters
//!
//! ```
//! use glare_pipeline::frame::run::render;
//! use glare_pipeline::scene::load::load_scene;
//!
//! let mut scene = load_scene("fig4")?; // Dobashi et al.'s Fig. 4 spot light
//! scene.image.width = 48; // a small frame, for speed
//! scene.image.height = 32;
//! scene.shafts.planes = 4;
//! let frame = render(&scene)?;
//! assert_eq!((frame.fb.width, frame.fb.height), (48, 32));
//! let shafts = &frame.counters()["shafts"];
//! let interpolator = shafts
//!     .iter()
//!     .find(|(unit, _)| unit.starts_with("polygon_interpolator"))
//!     .map(|(_, c)| c)
//!     .expect("the planes go through the interpolator");
//! assert!(interpolator.pixels_out > 0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Sweeping one width from code
//!
//! A scene is plain data: set a width, render, compare. Here the framebuffer's bits of
//! the shafts pipeline, 4 against 8: fewer bits, a coarser picture.
//!
//! ```
//! use glare_pipeline::frame::run::render;
//! use glare_pipeline::pipeline::shafts::sweep::{Param, Value};
//! use glare_pipeline::scene::load::load_scene;
//!
//! let mut base = load_scene("fig4")?;
//! (base.image.width, base.image.height, base.shafts.planes) = (48, 32, 4);
//! let param = Param::from_name("fb_bits")?;
//! let mut distinct = Vec::new();
//! for bits in [4, 8] {
//!     let mut s = base.clone();
//!     param.apply(&mut s.shafts, Value::One(bits))?;
//!     let f = render(&s)?;
//!     let mut codes: Vec<u32> = f.fb.data.clone();
//!     codes.sort_unstable();
//!     codes.dedup();
//!     distinct.push(codes.len());
//! }
//! assert!(distinct[0] < distinct[1], "4 bits hold fewer levels: {distinct:?}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod chip;
pub mod cli;
pub mod conformance;
pub mod frame;
pub mod optimize;
pub mod pipeline;
pub mod reference;
pub mod registry;
pub mod report;
pub mod scene;
pub mod tables;
