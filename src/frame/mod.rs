//! One frame through every pipeline.
//!
//! Data flows one way: scene → validate → [`plan`] (the pass list, as data) →
//! [`chip`] (which units the scene needs at all) → [`run`] (the passes over one frame
//! state: depth buffer, shadow maps, framebuffer, J buffer, textures) → report. This
//! is the only module that calls more than one pipeline: each pipeline is a set of
//! passes and never imports another; the frame hands one pass's output to the next
//! (the shafts framebuffer to the glare pass, the shading units' highlights to the
//! glare conditions).

pub mod assumptions;
pub mod attribute;
pub mod budget;
pub mod check;
pub mod chip;
pub mod chip_sweep;
pub mod cli;
pub mod emit_gl;
pub mod glare_link;
pub mod glare_scaling;
pub mod gpu;
pub mod objects;
pub mod plan;
pub mod range;
pub mod reflection;
pub mod reproduce;
pub mod run;
pub mod scene_text;
pub mod speed;
pub mod strata;
pub mod sweep;
pub mod timing;
pub mod vs_gl;
