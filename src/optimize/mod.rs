//! `optimize` (docs/optimize.md): for a scene and an error budget, the
//! cheapest widths found by a pruned greedy descent, and the Pareto front of gates,
//! RAM bits and error of every configuration evaluated. A module of its own beside
//! `frame`, above it: a tool over scenes, not part of the frame; it drives the frame
//! and more than one pipeline (shafts, glare, environment-map and shading scenes).

pub mod chip;
pub mod cli;
pub mod command;
pub mod eval;
pub mod search;
pub mod shading;
