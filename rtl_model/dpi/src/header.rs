//! The C header, generated from the ABI's source (`src/abi.rs`): one prototype per
//! `pub extern "C" fn`, its `///` lines as the comment above it. Regenerate with
//! `cargo run -p glare_dpi --bin glare-dpi-header > rtl_model/dpi/include/glare_dpi.h`;
//! `tests/header.rs` fails when the committed header differs.

/// The C spelling of a Rust parameter or return type of the ABI.
fn c_type(rust: &str) -> Result<&'static str, String> {
    Ok(match rust.trim() {
        "u32" => "uint32_t",
        "i32" => "int32_t",
        "u64" => "uint64_t",
        "i64" => "int64_t",
        "f64" => "double",
        "*mut Model" => "glare_dpi_handle *",
        "*const Model" => "const glare_dpi_handle *",
        "*const c_char" => "const char *",
        "*const u32" => "const uint32_t *",
        "*mut u32" => "uint32_t *",
        "*const f64" => "const double *",
        other => return Err(format!("header: no C type for `{other}`")),
    })
}

/// One C prototype from a Rust signature `name(params) -> ret`.
fn prototype(sig: &str) -> Result<String, String> {
    let open = sig.find('(').ok_or("header: no (")?;
    let close = sig.rfind(')').ok_or("header: no )")?;
    let name = sig[..open].trim();
    let ret = match sig[close + 1..].split_once("->") {
        Some((_, r)) => c_type(r)?,
        None => "void",
    };
    let mut params = Vec::new();
    for p in sig[open + 1..close].split(',') {
        let p = p.trim();
        if p.is_empty() {
            continue;
        }
        let (n, t) = p
            .split_once(':')
            .ok_or_else(|| format!("header: parameter `{p}`"))?;
        let ct = c_type(t)?;
        let sep = if ct.ends_with('*') { "" } else { " " };
        params.push(format!("{ct}{sep}{}", n.trim()));
    }
    let params = if params.is_empty() {
        "void".to_string()
    } else {
        params.join(", ")
    };
    let sep = if ret.ends_with('*') { "" } else { " " };
    Ok(format!("{ret}{sep}{name}({params});"))
}

/// The header text for the ABI source `src`.
pub fn generate(src: &str) -> Result<String, String> {
    let mut h = String::new();
    h.push_str("/* glare_dpi.h — GENERATED from rtl_model/dpi/src/abi.rs by\n");
    h.push_str(
        " *   cargo run -p glare_dpi --bin glare-dpi-header > rtl_model/dpi/include/glare_dpi.h\n",
    );
    h.push_str(
        " * Do not edit: rtl_model/dpi/tests/header.rs fails when this file is stale.\n *\n",
    );
    for l in src.lines().take_while(|l| l.starts_with("//!")) {
        let t = l.trim_start_matches("//!").trim_start();
        h.push_str(if t.is_empty() { " *\n" } else { " * " });
        if !t.is_empty() {
            h.push_str(t);
            h.push('\n');
        }
    }
    h.push_str(" *\n * Library: cargo build -p glare_dpi --features dpi (target/<profile>/libglare_dpi.so).\n */\n");
    h.push_str("#ifndef GLARE_DPI_H\n#define GLARE_DPI_H\n\n#include <stdint.h>\n\n");
    h.push_str("#ifdef __cplusplus\nextern \"C\" {\n#endif\n\n");
    h.push_str("/* A unit with its config, tables and state (opaque). */\n");
    h.push_str("typedef struct glare_dpi_handle glare_dpi_handle;\n");
    let mut doc: Vec<String> = Vec::new();
    let mut sig: Option<String> = None;
    for line in src.lines() {
        let t = line.trim();
        if let Some(s) = sig.as_mut() {
            s.push(' ');
            s.push_str(t);
        } else if let Some(d) = t.strip_prefix("///") {
            doc.push(d.trim().to_string());
            continue;
        } else if t.starts_with("#[") {
            continue;
        } else if let Some(rest) = t
            .strip_prefix("pub extern \"C\" fn ")
            .or_else(|| t.strip_prefix("pub unsafe extern \"C\" fn "))
        {
            sig = Some(rest.to_string());
        } else {
            doc.clear();
            continue;
        }
        let s = sig.as_ref().map_or("", String::as_str);
        if let Some(body) = s.find('{') {
            let proto = prototype(&s[..body])?;
            h.push('\n');
            for d in &doc {
                h.push_str("/* ");
                h.push_str(d);
                h.push_str(" */\n");
            }
            h.push_str(&proto);
            h.push('\n');
            doc.clear();
            sig = None;
        }
    }
    h.push_str("\n#ifdef __cplusplus\n}\n#endif\n\n#endif /* GLARE_DPI_H */\n");
    Ok(h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prototypes() {
        assert_eq!(
            prototype("f(h: *mut Model, a: u32, y: *mut u32) -> i32").unwrap(),
            "int32_t f(glare_dpi_handle *h, uint32_t a, uint32_t *y);"
        );
        assert_eq!(
            prototype("g() -> *const c_char").unwrap(),
            "const char *g(void);"
        );
        assert!(prototype("f(x: String)").unwrap_err().contains("String"));
    }
}
