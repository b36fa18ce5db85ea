//! The light-shafts pipeline by sample planes (Dobashi, Yamamoto and Nishita;
//! docs/references.md).

pub mod attribute;
mod chunked;
pub mod cli;
pub mod frame;
pub mod host;
mod pass_log;
mod planes;
pub mod prepare;
mod record;
pub mod reproduce;
pub mod sweep;
pub mod tables;
mod units;
pub mod view;
