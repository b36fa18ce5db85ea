//! `render --scene NAME [--image WxH] --emit-gl DIR`: the checks before any work, the
//! model's frame, the program written beside its picture.

use super::{check_exportable, write_program, Export};
use std::path::Path;

/// `render --scene NAME [--image WxH] --emit-gl DIR`.
pub fn emit_gl_cli(
    name: &str,
    dir: &Path,
    image: Option<&str>,
    max_memory: Option<u64>,
) -> Result<(), String> {
    crate::report::outputs::check_dir_out("emit-gl", dir)?;
    let mut scene = crate::scene::load::load_scene(name)?;
    match crate::frame::cli::render_path(&scene) {
        crate::frame::cli::RenderPath::TestScene => return emit_test_scene(dir, image),
        crate::frame::cli::RenderPath::ShadingSphere => {
            return emit_sphere(&scene, dir, image, max_memory)
        }
        _ => {}
    }
    let size = image
        .map(crate::report::image_arg::parse_image)
        .transpose()?;
    if let Some((w, h)) = size {
        scene.image.width = w;
        scene.image.height = h;
    }
    let exports = check_exportable(&scene)?;
    let (budget, from) = crate::frame::budget::resolve(max_memory);
    crate::frame::budget::check(&scene, budget, &from)?;
    for e in &exports {
        if let Export::NotExported { pass, why } = e {
            eprintln!("--emit-gl: not exported: {pass}: {why}");
        }
    }
    // The model's frame (its PNG, and the tables its planes read).
    let frame = crate::frame::run::render(&scene).map_err(|e| e.to_string())?;
    let program = write_program(&frame, &exports, dir)?;
    let exported = exports
        .iter()
        .filter(|e| matches!(e, Export::Shafts(_)))
        .count();
    let what = format!(
        "{exported} {} exported, {} not",
        if exported == 1 { "pass" } else { "passes" },
        exports.len() - exported
    );
    print_written(dir, &program, &what);
    Ok(())
}

/// What `--emit-gl` wrote into `dir` (`what`: the passes it holds) and how to run it.
fn print_written(dir: &Path, program: &super::Program, what: &str) {
    let data = program.files.len() - 2;
    println!(
        "wrote {} (scene.c, build.sh, {data} data {}, model.png): {what}",
        dir.display(),
        if data == 1 { "file" } else { "files" }
    );
    println!(
        "build and run: cd {} && sh build.sh && ./scene   (writes framebuffer.png)",
        dir.display()
    );
}

/// `--emit-gl` of a shading sphere scene: the Lambert sphere's program, or the reason
/// the scene has none, before any work.
fn emit_sphere(
    scene: &crate::scene::format::Scene,
    dir: &Path,
    image: Option<&str>,
    max_memory: Option<u64>,
) -> Result<(), String> {
    let mut f = crate::pipeline::shading::scene_file::ShadingFile::from_scene(scene)?;
    if let Some(why) = super::sphere::not_exportable(&f) {
        return Err(format!("--emit-gl: {why}"));
    }
    let vertex = f.point.vertex_config().is_some();
    if let Some(img) = image {
        if vertex {
            return Err(
                "--image: shading-vertex lights sphere vertices; it has no image to size".into(),
            );
        }
        let side = crate::report::image_arg::square_side(img)?;
        rtl_model::error::check_range("--image", side.into(), 2, 4096)
            .map_err(|e| e.to_string())?;
        f.image = Some(side);
    }
    let (budget, from) = crate::frame::budget::resolve(max_memory);
    crate::frame::budget::check_estimate(
        crate::frame::budget::shading_estimate(f.image),
        budget,
        &from,
    )?;
    if vertex {
        let p = super::vertex::vertex_program(&f)?;
        p.write(dir)?;
        let what = format!(
            "the vertices lit by GL's fixed-function lighting, their colours as a {}x{} picture",
            crate::pipeline::shading::sweep::VERTEX_SEGMENTS,
            crate::pipeline::shading::sweep::VERTEX_RINGS
        );
        print_written(dir, &p.program, &what);
    } else {
        let p = super::sphere::sphere_program(&f)?;
        p.write(dir)?;
        print_written(dir, &p.program, "the sphere's one pass exported");
    }
    Ok(())
}

/// `--emit-gl` of the foundation test scene (its size is fixed: `--image` refused).
fn emit_test_scene(dir: &Path, image: Option<&str>) -> Result<(), String> {
    if image.is_some() {
        return Err("--image: the foundation test scene's size is fixed".into());
    }
    let (fb, _) = crate::pipeline::test_scene::render().map_err(|e| e.to_string())?;
    let program = super::test_scene::test_scene_program();
    super::write_files(&program, dir, |path| {
        fb.save_png(path).map_err(|e| e.to_string())
    })?;
    print_written(dir, &program, "2 passes exported, 0 not");
    Ok(())
}
