//! Writing a finished voxel map out, and reading it back (`envmap-dump`):
//! a user can inspect the prefiltered map or reuse it elsewhere.
//!
//! A dump is a directory of
//! - `volume.raw`: the s³ map as 16-bit little-endian words, three per voxel (R, G, B,
//!   interleaved), x fastest, then y, then z (the [`VoxelMap`] layout: voxel (x, y, z)
//!   has its centre at t = 2(k + ½)/s − 1 per axis). Each word is the voxel's unorm
//!   code at the map's `bits` (8 by default: codes 0 ..= 255), not rescaled;
//! - `slice_zNNN.png`: one RGB PNG per z (x to the right, y down as stored), codes
//!   scaled to 8 bits (round(code · 255 / max)) for a look;
//! - `map.json`: the sidecar — side, bits, layout, the exposure the environment's
//!   radiance was read at (level 255 = radiance 1/exposure), the source map, the
//!   prefilter and the file names.
//!
//! [`read_dump`] reads `volume.raw` and `map.json` back into a [`VoxelMap`] equal to
//! the one written (tests/envmap_dump.rs: bit for bit at s = 32).

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::scene_render::{build_map, MapBuild};
use super::voxmap::VoxelMap;
use crate::scene::format::Scene;

/// The volume's file name inside a dump.
pub const VOLUME_FILE: &str = "volume.raw";
/// The sidecar's file name inside a dump.
pub const SIDECAR_FILE: &str = "map.json";
/// The sidecar's `format` string.
pub const FORMAT: &str = "glare-pipeline voxel map, version 1";
/// The sidecar's `layout` string.
pub const LAYOUT: &str =
    "u16 little-endian, 3 words per voxel (R, G, B), x fastest, then y, then z; \
     voxel (x, y, z) centre t = 2(k + 0.5)/side - 1";

/// `map.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sidecar {
    pub format: String,
    pub side: u32,
    /// Bits per channel of the codes in the volume (1 ..= 16).
    pub bits: u32,
    pub layout: String,
    /// Radiance × exposure → levels (255 = full scale) before prefiltering.
    pub exposure: f64,
    /// The built-in map's name or the `.hdr` path as written in the scene.
    pub source: String,
    /// "accelerated, th = …" or "exact".
    pub prefilter: String,
    pub volume: String,
    pub slices: Vec<String>,
}

fn slice_name(z: u32) -> String {
    format!("slice_z{z:03}.png")
}

/// Write `map` (built as `build` says) into `dir`; returns the sidecar written.
pub fn write_dump(dir: &Path, map: &VoxelMap, build: &MapBuild) -> Result<Sidecar, String> {
    let s = map.side();
    let mut raw = Vec::with_capacity(map.data().len() * 6);
    for v in map.data() {
        for c in v {
            // Codes are at most 16 bits (VoxelMap::new refuses more).
            raw.extend_from_slice(&(*c as u16).to_le_bytes());
        }
    }
    crate::report::atomic::write_bytes(&dir.join(VOLUME_FILE), &raw)
        .map_err(|e| format!("out: {e}"))?;
    let max = map.max_code().max(1) as f64;
    let mut slices = Vec::with_capacity(s as usize);
    for z in 0..s {
        let img = image::RgbaImage::from_fn(s, s, |x, y| {
            let v = map.get(x, y, z);
            let q = |c: u32| (c as f64 * 255.0 / max).round().clamp(0.0, 255.0) as u8;
            image::Rgba([q(v[0]), q(v[1]), q(v[2]), 255])
        });
        let name = slice_name(z);
        let path = dir.join(&name);
        crate::report::atomic::write_atomically(&path, |tmp| {
            img.save(tmp)
                .map_err(|e| format!("{}: {e}", path.display()))
        })
        .map_err(|e| format!("out: {e}"))?;
        slices.push(name);
    }
    let sidecar = Sidecar {
        format: FORMAT.to_string(),
        side: s,
        bits: map.bits(),
        layout: LAYOUT.to_string(),
        exposure: build.exposure,
        source: build.source.clone(),
        prefilter: build.prefilter.clone(),
        volume: VOLUME_FILE.to_string(),
        slices,
    };
    let json = serde_json::to_string_pretty(&sidecar).map_err(|e| e.to_string())?;
    crate::report::atomic::write_bytes(&dir.join(SIDECAR_FILE), json.as_bytes())
        .map_err(|e| format!("out: {e}"))?;
    Ok(sidecar)
}

/// Read a dump written by [`write_dump`]: the map and its sidecar. Errors name the file
/// and what is wrong (a missing file, a sidecar of another format, a volume whose size
/// is not side³ × 6 bytes, a code above the sidecar's bits).
pub fn read_dump(dir: &Path) -> Result<(VoxelMap, Sidecar), String> {
    let sc_path = dir.join(SIDECAR_FILE);
    let text = std::fs::read_to_string(&sc_path)
        .map_err(|e| format!("{}: cannot read: {e}", sc_path.display()))?;
    let sidecar: Sidecar =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", sc_path.display()))?;
    if sidecar.format != FORMAT {
        return Err(format!(
            "{}: format is '{}', not '{FORMAT}'",
            sc_path.display(),
            sidecar.format
        ));
    }
    let mut map = VoxelMap::new(sidecar.side, sidecar.bits)
        .map_err(|e| format!("{}: {e}", sc_path.display()))?;
    let vol_path = dir.join(&sidecar.volume);
    let raw = std::fs::read(&vol_path)
        .map_err(|e| format!("{}: cannot read: {e}", vol_path.display()))?;
    let want = map.data().len() * 6;
    if raw.len() != want {
        return Err(format!(
            "{}: {} bytes, but side {} needs {want}",
            vol_path.display(),
            raw.len(),
            sidecar.side
        ));
    }
    let max = map.max_code();
    for (i, (v, w)) in map
        .data_mut()
        .iter_mut()
        .zip(raw.chunks_exact(6))
        .enumerate()
    {
        for (c, b) in v.iter_mut().zip(w.chunks_exact(2)) {
            *c = u16::from_le_bytes([b[0], b[1]]) as u32;
            if *c > max {
                return Err(format!(
                    "{}: voxel {i} holds code {c} above the {}-bit maximum {max}",
                    vol_path.display(),
                    sidecar.bits
                ));
            }
        }
    }
    Ok((map, sidecar))
}

/// Build the voxel map of `scene`'s `[environment]` section (as `render` does:
/// [`build_map`]) and write it into `dir`. `side` overrides the section's side.
pub fn dump_scene(
    scene: &Scene,
    side: Option<u32>,
    dir: &Path,
) -> Result<(VoxelMap, Sidecar), String> {
    let mut scene = scene.clone();
    let Some(section) = scene.environment.as_mut() else {
        return Err("scene: has no [environment] section: there is no map to dump".to_string());
    };
    if let Some(s) = side {
        section.side = s;
    }
    scene.validate().map_err(|e| {
        if side.is_some() && e.to_string().contains("environment.side") {
            format!("side: {e}")
        } else {
            e.to_string()
        }
    })?;
    let section = scene.environment.as_ref().expect("checked above");
    let env = section.load().map_err(|e| e.to_string())?;
    let (map, build) = build_map(section, &env).map_err(|e| e.to_string())?;
    let sidecar = write_dump(dir, &map, &build)?;
    Ok((map, sidecar))
}
