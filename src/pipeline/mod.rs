//! Units wired into pipelines; frames driven; counters gathered.

pub mod registry;
pub mod test_scene;
