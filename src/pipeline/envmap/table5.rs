//! The thesis' Table 5 (§4.3): errors of the rendered sphere and teapot against the
//! cos φ truth for λ = 1, 0.75, 0.5, 0.25 and non-uniform.

use rtl_model::error::ConfigError;

use super::objects::{LambdaSpec, Object};
use super::render::render_object;
use super::voxmap::VoxelMap;
use crate::scene::envmap::EnvMap;

/// One row of the thesis' Table 5 (errors against the cos φ truth, 8-bit levels).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Table5Row {
    pub object: String,
    pub env: String,
    pub lambda: String,
    pub accelerated: bool,
    pub mean: [f64; 3],
    pub var: [f64; 3],
}

impl Table5Row {
    pub const CSV_HEADER: &'static str =
        "object,env,lambda,accelerated,mean_r,mean_g,mean_b,var_r,var_g,var_b";

    pub fn to_csv(&self) -> String {
        format!(
            "{},{},{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4}",
            self.object,
            self.env,
            self.lambda,
            self.accelerated,
            self.mean[0],
            self.mean[1],
            self.mean[2],
            self.var[0],
            self.var[1],
            self.var[2]
        )
    }
}

/// The λ cases of Table 5: 1, 0.75, 0.5, 0.25, non-uniform.
pub const TABLE5_LAMBDAS: [LambdaSpec; 5] = [
    LambdaSpec::Uniform(1.0),
    LambdaSpec::Uniform(0.75),
    LambdaSpec::Uniform(0.5),
    LambdaSpec::Uniform(0.25),
    LambdaSpec::NonUniform,
];

/// Table 5 rows for `objects` × [`TABLE5_LAMBDAS`] with `map` (the caller says whether
/// it was built accelerated and names the environment), at `size`.
pub fn table5_rows(
    env: &EnvMap,
    env_name: &str,
    map: &VoxelMap,
    accelerated: bool,
    objects: &[Object],
    size: (u32, u32),
) -> Result<Vec<Table5Row>, ConfigError> {
    let mut rows = Vec::new();
    for &object in objects {
        for lambda in TABLE5_LAMBDAS {
            let (_, _, st) = render_object(env, map, object, lambda, size)?;
            rows.push(Table5Row {
                object: object.name().to_string(),
                env: env_name.to_string(),
                lambda: lambda.label(),
                accelerated,
                mean: st.cos_phi.mean,
                var: st.cos_phi.var,
            });
        }
    }
    Ok(rows)
}
