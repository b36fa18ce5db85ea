//! Units wired into pipelines; frames driven; counters gathered.

pub mod envmap;
pub mod glare;
pub mod raster;
pub mod shading;
pub mod shafts;
pub mod test_scene;
