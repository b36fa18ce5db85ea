//! Error metrics, tables, images and plots.

pub mod alternates;
pub mod image_out;
pub mod table;
