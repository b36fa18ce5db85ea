//! One name for "this build has the AVX-512 subsets the lane kernels use" (F, BW, VL on
//! x86-64), so each kernel's vector form and its fallback carry `cfg(avx512_lanes)`
//! instead of the four-part feature list. The features are the build's (the workspace
//! builds for the machine it runs on: `target-cpu=native` in .cargo/config.toml).

fn main() {
    println!("cargo::rustc-check-cfg=cfg(avx512_lanes)");
    println!("cargo::rustc-check-cfg=cfg(avx2_lanes)");
    println!("cargo::rerun-if-changed=build.rs");
    let arch = std::env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let features = std::env::var("CARGO_CFG_TARGET_FEATURE").unwrap_or_default();
    let has = |f: &str| features.split(',').any(|x| x == f);
    if arch == "x86_64" && has("avx512f") && has("avx512bw") && has("avx512vl") {
        println!("cargo::rustc-cfg=avx512_lanes");
    } else if arch == "x86_64" && has("avx2") {
        // AVX2 without those subsets (AMD before Zen 4, Intel client parts): the
        // kernels' 256-bit forms.
        println!("cargo::rustc-cfg=avx2_lanes");
    }
}
