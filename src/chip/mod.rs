//! The chip's time: what each pass did (`work`), the GPUs it runs on (`presets`) and
//! the roofline prediction of its time (`roofline`). On the ground floor beside
//! `report/`: the pipelines record what a pass did, the frame times it; nothing here
//! imports a pipeline.

pub mod clock;
pub mod config;
pub mod presets;
mod presets_pending;
pub mod roofline;
pub mod work;

pub use presets::GpuModel;
pub use roofline::{hardware_passes, pass_seconds, predict, split_objects_shafts, Prediction};
pub use work::{kind_name, PassKind, PassStats};
