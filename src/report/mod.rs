//! Error metrics, tables, images and plots.

pub mod alternates;
pub mod atomic;
pub mod attribution;
pub mod chip_timing;
pub mod csv_out;
pub mod elaboration;
pub mod image_arg;
pub mod image_out;
pub mod interrupt;
pub mod items;
pub mod metrics;
pub mod outputs;
pub mod plot;
pub mod progress;
pub mod render_json;
pub mod resume;
pub mod shard;
pub mod spectrum;
pub mod suggest;
pub mod sweep_out;
pub mod table;
