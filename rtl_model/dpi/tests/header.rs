//! The committed C header is the one generated from src/abi.rs.
#[test]
fn committed_header_is_fresh() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("include/glare_dpi.h");
    let want = glare_dpi::header::generate(glare_dpi::ABI_SOURCE).unwrap();
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "{} is stale: run `cargo run -p glare_dpi --bin glare-dpi-header > rtl_model/dpi/include/glare_dpi.h`",
        path.display()
    );
    // Every exported function has its prototype.
    let n_fns = glare_dpi::ABI_SOURCE.matches("extern \"C\" fn ").count();
    let n_protos = want.lines().filter(|l| l.ends_with(");")).count();
    assert_eq!(n_fns, n_protos);
    assert!(want.contains("glare_dpi_handle *modulate_new(uint32_t bits, uint32_t mode);"));
}
