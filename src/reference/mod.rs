//! f64 twins of the hardware units (one per unit, named after it) and whole-image
//! references. The reference never imports a unit's kernel; tests are where they meet.

pub mod blend;
pub mod bloom_flare_modulator;
pub mod brdf;
pub mod chaos_map;
pub mod clipper;
pub mod cube_map_address;
pub mod envmap_prefilter;
pub mod final_combiner;
pub mod gaussian_noise;
pub mod glare_combiner;
pub mod glare_condition;
pub mod glare_model;
pub mod halo_modulator;
pub mod luminance_ram;
pub mod modulate;
pub mod modulate_chain;
pub mod phong_truth;
pub mod polygon_interpolator;
pub mod polygon_variable_generator;
pub mod projective_texcoord;
pub mod quadrature;
pub mod raymarch;
pub mod reflection_vector;
pub mod register_combiner;
pub mod shadow_compare;
pub mod shafts_model;
pub mod specular_lookup;
pub mod test_scene;
pub mod texture_combiner;
pub mod texture_sampler;
pub mod vertex_lighting;
