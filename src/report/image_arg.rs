//! `--image WIDTHxHEIGHT`: the one parser of the image-size option of `render`,
//! `sweep`, `attribute`, `optimize` and `reproduce`. A malformed size is an error
//! naming `--image`; the range of each side is the scene's to check (as
//! `image.width` / `image.height`).

/// `WIDTHxHEIGHT` (also `WIDTHXHEIGHT`), each side a whole number.
pub fn parse_image(text: &str) -> Result<(u32, u32), String> {
    let t = text.trim();
    let bad = |why: String| format!("--image: {why}; --image takes WIDTHxHEIGHT, e.g. 360x240");
    let (a, b) = t
        .split_once(['x', 'X'])
        .ok_or_else(|| bad(format!("'{t}' is not of the form WIDTHxHEIGHT")))?;
    let side = |s: &str, what: &str| {
        s.trim().parse::<u32>().map_err(|_| {
            bad(format!(
                "the {what} '{}' is not a whole number in 0 ..= 4294967295",
                s.trim()
            ))
        })
    };
    Ok((side(a, "width")?, side(b, "height")?))
}

/// A square image's side (a shading scene's sphere view): `--image NxN`.
pub fn square_side(text: &str) -> Result<u32, String> {
    let (w, h) = parse_image(text)?;
    if w != h {
        return Err(format!(
            "--image: {w}x{h} is not square; a shading scene renders a square sphere view (e.g. {w}x{w})"
        ));
    }
    Ok(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_errors_name_the_option() {
        assert_eq!(parse_image("360x240"), Ok((360, 240)));
        assert_eq!(parse_image(" 64X48 "), Ok((64, 48)));
        for bad in ["12x", "wide", "x4", "-3x4", "3.5x4"] {
            let e = parse_image(bad).unwrap_err();
            assert!(e.starts_with("--image:"), "{bad}: {e}");
        }
        assert!(square_side("64x32").unwrap_err().contains("square"));
        assert_eq!(square_side("32x32"), Ok(32));
    }
}
