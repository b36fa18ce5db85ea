//! Which GPU runs a frame's GPU passes: a type the frame's run (`run.rs`) and its
//! timing (`timing.rs`) share, below both.

use crate::chip::GpuModel;
use crate::scene::format::Scene;
use serde::Serialize;

/// Which GPU runs the frame's GPU passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Gpu {
    /// GeForce 256 (DDR): only when asked for (`render --chip geforce256`).
    GeForce256,
    GeForce2Gts,
    GeForce3,
}

impl Gpu {
    /// GeForce3 when the scene needs its 3D textures (an environment map), else the
    /// GeForce2 GTS the shafts paper measured on.
    pub fn for_scene(scene: &Scene) -> Gpu {
        if scene.environment.is_some() {
            Gpu::GeForce3
        } else {
            Gpu::GeForce2Gts
        }
    }

    pub fn model(self) -> GpuModel {
        match self {
            Gpu::GeForce256 => GpuModel::geforce256(),
            Gpu::GeForce2Gts => GpuModel::geforce2_gts(),
            Gpu::GeForce3 => GpuModel::geforce3(),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Gpu::GeForce256 => "GeForce 256",
            Gpu::GeForce2Gts => "GeForce2 GTS",
            Gpu::GeForce3 => "GeForce3",
        }
    }
}
