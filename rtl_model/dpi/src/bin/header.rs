//! Print the generated C header (include/glare_dpi.h).
fn main() {
    match glare_dpi::header::generate(glare_dpi::ABI_SOURCE) {
        Ok(h) => print!("{h}"),
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    }
}
