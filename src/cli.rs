//! The clap front end: `units`, `render`, `reproduce`, `sweep`, `tables`, `trace`.
//!
//! The doc comments of the argument structs are the command's `--help` text, where
//! `<model>`, `<suite>` and the like are literal placeholders a user reads, not HTML.
#![allow(rustdoc::invalid_html_tags)]

use crate::frame::sweep::SweepPath;
use crate::registry;
use crate::report::alternates::modulate_alternates;
use crate::report::shard::Shard;
use crate::report::table::text_table;
use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    name = "glare-pipeline",
    version,
    about = "Cycle-level, bit-accurate model of a GeForce2/3-era glare and shading pipeline"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Print every unit with its default widths, latency, II, gates and RAM bits.
    Units {
        /// JSON array instead of a table.
        #[arg(long)]
        json: bool,
        /// Also print the modulate alternates' error against round(a·b/255) and gates.
        #[arg(long)]
        alternates: bool,
        /// Instead: the chip a scene elaborates (built-in name or TOML file): which
        /// unit instances it needs, and what it leaves out with the gates saved.
        #[arg(long, conflicts_with_all = ["alternates", "datasheet"])]
        scene: Option<String>,
        /// Rewrite the registry's figures in this datasheet (docs/units.md) instead.
        #[arg(long, value_name = "PATH", conflicts_with_all = ["json", "alternates"])]
        datasheet: Option<PathBuf>,
        /// Also synthesise each unit that has Verilog (rtl_model/verilog/units/) with
        /// Yosys at its default widths and report `gates_yosys` beside the model's
        /// gates (docs/rtl.md). Needs `yosys` on PATH.
        #[arg(long, conflicts_with_all = ["scene", "datasheet", "alternates"])]
        synth: bool,
        /// With --synth: synthesise only these units (comma-separated names); the
        /// others report no Yosys count. Synthesis of every unit takes tens of minutes.
        #[arg(long, value_name = "UNITS", value_delimiter = ',', requires = "synth")]
        only: Vec<String>,
        /// Instead: the speed table of the units with Verilog — the model's batch
        /// kernel (pixels/s) beside Verilator (cycles/s, transactions/s) on the same
        /// vectors and configuration, in one run (docs/rtl.md): in an in-memory C++
        /// harness (vectors loaded first, one build per unit) and in the vector
        /// testbench (`$fscanf` per transaction). Needs verilator, g++ and make.
        #[arg(long, conflicts_with_all = ["scene", "datasheet", "alternates", "synth"])]
        rtl_speed: bool,
        /// With --rtl-speed: transactions per unit (exhaustive vector sets keep their
        /// size).
        #[arg(long, default_value_t = 1_000_000, requires = "rtl_speed")]
        count: usize,
        /// With --rtl-speed: the configuration (default or narrow).
        #[arg(long, default_value = "default", requires = "rtl_speed")]
        config: String,
    },
    /// Render a scene (default: the paper's Fig. 6(b) sphere under a spotlight) to PNG
    /// through its pass plan, and print the plan, the chip, each pipeline's counters
    /// and elaboration, and the predicted time per pass.
    Render {
        /// A built-in scene (fig6, fig4, stage, or `test` for the foundation test scene;
        /// the glare scenes glare-point, glare-elliptic, glare-flare, street-light,
        /// leaves, shaded-metal, shaded-dielectric; the showcase night-street, every
        /// pipeline in one frame; the environment-map scenes env-MAP-OBJECT: env-pattern-sphere,
        /// env-pattern-teapot, env-venice_sunset-sphere, env-venice_sunset-teapot,
        /// env-st_fagans_interior-sphere, env-st_fagans_interior-teapot), a shading
        /// scene (shading-<model>, shading-specular, shading-vertex: the sphere of
        /// `sweep`'s shading path at the GeForce widths) or a TOML scene file (one
        /// with a `[shading_sphere]` section, or its alias a top-level `[shading]`
        /// table, is a shading scene at its widths; one with `[test_scene]` the test
        /// scene: docs/scenes.md). Every command takes the same scenes.
        #[arg(long, default_value = "fig6")]
        scene: String,
        /// Output PNG.
        #[arg(long, default_value = "out/render.png")]
        out: PathBuf,
        /// Counters as JSON instead of a table.
        #[arg(long)]
        json: bool,
        /// Also write the f64 reference image here and print the error against it
        /// (per pass and in total).
        #[arg(long)]
        reference: Option<PathBuf>,
        /// Print the pass plan and the chip's elaboration only; render nothing.
        #[arg(long)]
        plan: bool,
        /// Memory budget: a scene whose estimated buffers, tables and maps exceed it
        /// is refused before anything is allocated, with what is large and how to
        /// shrink it. Bytes with an optional suffix K, M, G, T (512M, 8G); default
        /// half of the machine's available memory (MemAvailable). docs/inputs.md.
        #[arg(long, value_name = "SIZE", allow_negative_numbers = true, value_parser = crate::frame::budget::parse_bytes)]
        max_memory: Option<u64>,
        /// Override the scene's image size, WIDTHxHEIGHT (e.g. 360x240; square for a
        /// shading scene's sphere view; the test scene's size is fixed).
        #[arg(long, value_name = "WxH")]
        image: Option<String>,
        /// Write the scene as a self-contained OpenGL 1.3 C program into DIR instead of
        /// rendering it here: scene.c (one function per pass, the pass list in main),
        /// the model's tables, light maps and vertices as raw files, build.sh (cc …
        /// -lOSMesa -lm) and model.png (the model's picture at the same size). The
        /// program renders offscreen on OSMesa and writes framebuffer.png. Passes with
        /// no OpenGL 1.3 form (glare, the shading units) are listed, not exported. The
        /// shading spheres with a GL 1.3 path (shading-lambert and the factored ones),
        /// shading-vertex (its vertex colours as a picture) and the test scene have
        /// their own programs; the other spheres are refused with the reason.
        #[arg(long, value_name = "DIR", conflicts_with_all = ["out", "plan", "reference", "json"])]
        emit_gl: Option<PathBuf>,
        #[command(flatten)]
        timing: crate::frame::cli::TimingArgs,
    },
    /// Reproduce a paper figure: shafts-fig4, shafts-fig5, shafts-vs-raymarch,
    /// shafts-stage, glare-fig4, glare-fig5, glare-fig7, glare-fig8, glare-throughput,
    /// glare-asic-throughput (the glare ASIC clocked on glare-flare, street-light and
    /// leaves: sustained pixels/s against the paper's 1.2 Gpixel/s, the bottleneck),
    /// glare-scaling (a city at night, 96 × 64, with 250 … 10 000 light sources: the
    /// render's time per source),
    /// glare-gauss-seeds (seeds 1 ..= 1000, or $GLARE_GAUSS_SEEDS),
    /// envmap-table3 (side 128, or $ENVMAP_TABLE3_S), envmap-table5 and envmap-images
    /// (side 128 or $ENVMAP_TABLE3_S, images 256 × 256 or $ENVMAP_IMAGE_SIZE),
    /// envmap-timing (640 × 480 frames, side 128 or $ENVMAP_TABLE3_S),
    /// envmap-lambda-sweep and envmap-roughness (the pattern; side and size as
    /// envmap-table5), shading-normalize-cube (the normalisation cube map's error
    /// table over F = 16 … 256), shading-specular ((n·h)^s by squaring in the
    /// register combiners vs the lookup), shading-brdfs (one sphere per model, units
    /// beside the f64 reference), shading-brdf-properties (reciprocity and albedo of
    /// every BRDF reference, the HG moments and the dipole integral), shading-vertex-float (vertex-lighting
    /// error against the float mantissa width, 4 ..= 23 at exponents 8 and 5, 1 and 8
    /// lights), shading-factorization (factor-texture error against resolution and bits),
    /// frame-elaboration (night-street and four reduced variants: units, gates, RAM
    /// bits, predicted and simulated time, error against the f64 reference),
    /// assumptions (each selectable alternative of docs/assumptions.md on the
    /// built-ins it affects: assumptions.csv, assumptions_maps.csv — the dome pick's
    /// maps against the exact prefilter — and a PNG strip per assumption),
    /// sim-speed (the Fig. 6(b) frame against its 180-sample ray-march, and the glare
    /// and envmap frames, wall time in one run),
    /// vs-gl (fig6, fig4, stage, the shading spheres with an OpenGL 1.3 path —
    /// shading-lambert and the factored ones — and shading-vertex's vertex colours,
    /// the model in its GeForce and its
    /// Mesa-matching rounding, against the scenes' OpenGL programs run on Mesa's
    /// llvmpipe and softpipe through OSMesa: vs_gl.csv, a histogram CSV and a
    /// difference PNG per row, fig6's and the spheres' ablation in vs_gl_ablation.csv
    /// and their difference classes in vs_gl_classes.csv, and the model's frame time
    /// over the GL draw's (fig6, fig4, stage: each the median of 3 runs, softpipe's
    /// draw timed once); needs cc and libOSMesa; --image WxH sets the size, the
    /// spheres' side the smaller of the two).
    /// Writes CSV and PNG into --out.
    Reproduce {
        name: String,
        #[arg(long, default_value = "out/reproduce")]
        out: PathBuf,
        /// Override the swept values (fig4: planes, default 10,20,…,200; fig5:
        /// sub-planes, default 1,…,25), comma-separated.
        #[arg(long, value_delimiter = ',', allow_negative_numbers = true, value_parser = arg_u32)]
        values: Option<Vec<u32>>,
        /// Continue an interrupted run with the same --values, --out and environment
        /// variables from the rows (items) it saved as each finished, computing only
        /// the rest: shafts-fig4 and shafts-fig5 (their CSVs), and glare-gauss-seeds,
        /// the envmap-* reproductions, frame-elaboration and shading-brdf-properties
        /// (DIR/NAME.resume.jsonl). Refused, naming the file and what differs, if the
        /// rows there are another run's; refused with the reason for the others.
        #[arg(long)]
        resume: bool,
        /// Memory budget, as for `render`: checked for the largest scene the
        /// reproduction renders before any work.
        #[arg(long, value_name = "SIZE", allow_negative_numbers = true, value_parser = crate::frame::budget::parse_bytes)]
        max_memory: Option<u64>,
        /// The image size, NxN (8 ..= 1024), of envmap-table5, envmap-images,
        /// envmap-lambda-sweep and envmap-roughness (default 256x256). Wins over
        /// $ENVMAP_IMAGE_SIZE, which sets the same size when --image is not given;
        /// and of vs-gl (WxH; default each scene's own, 720x480).
        #[arg(long, value_name = "WxH")]
        image: Option<String>,
    },
    /// Print a scene as the TOML file that renders the same, to start a scene file
    /// from: `glare-pipeline scene fig6 > my.toml`, edit, then `render --scene
    /// my.toml`. Any name `render --scene` takes: the built-in scenes (compact,
    /// each section commented, units after the values), `test` (its `[test_scene]`
    /// form) and the shading-* scenes (the `[shading]` alias of their
    /// `[shading_sphere]` section); a scene file prints
    /// the same way. Every field of the format: docs/scenes.md.
    Scene {
        /// A built-in scene name (a misspelt one gets the nearest names) or a TOML file.
        #[arg(required_unless_present = "reference")]
        name: Option<String>,
        /// Instead: write the scene format's reference (every section and field with
        /// its type, unit, range, default and where the range comes from) to this
        /// Markdown file, as docs/scenes.md is made.
        #[arg(long, value_name = "FILE", conflicts_with = "name")]
        reference: Option<PathBuf>,
    },
    /// Bit-width optimisation (docs/optimize.md): from the GeForce defaults,
    /// the cheapest widths of a shafts, glare, environment-map or shading scene within an error budget (a greedy
    /// descent, pruned by a sound bound before simulating); writes DIR/pareto.csv
    /// (every configuration evaluated), DIR/pareto.png (the objective against the first
    /// budget's error, that plane's front, the default) and DIR/best.toml (the scene with the widths found, for
    /// `render --scene`; for a shading scene the `[shading]` alias of its `[shading_sphere]` section), verified by a
    /// fresh render. With `--params` naming the clocked chip's parameters (pipes,
    /// tmus, fifo_depth, cache_kb, …) and a time budget (`--budget "seconds<=0.17"`):
    /// the cheapest chip whose clocked frame time meets it, with DIR/pareto.csv,
    /// DIR/pareto.png and DIR/best_chip.toml (the chip's every field), verified by a
    /// fresh clocked frame.
    Optimize(crate::optimize::cli::OptimizeArgs),
    /// Error attribution: render the scene as configured, then once per
    /// error source with only that source made ideal (a wide width, a larger table,
    /// more planes, the better scaling), then all ideal; write DIR/attribution.csv,
    /// DIR/attribution.png (shares of the squared error) and a difference image per
    /// source above 5 %, and print the table (docs/results.md, "Error attribution").
    /// Shafts scenes (fig4, fig6, stage, files), glare scenes, env-MAP-OBJECT scenes,
    /// shading-* scenes (not shading-vertex), and frame scenes of several pipelines
    /// (night-street, shaded-metal, street-light, …: every pipeline's sources on the
    /// whole frame's error).
    Attribute {
        /// A built-in scene or a TOML scene file (the scenes `render --scene` takes; a
        /// shading sphere file with its own widths or chip is refused: attribute
        /// starts from the GeForce defaults).
        #[arg(long)]
        scene: String,
        /// Output directory.
        #[arg(long, default_value = "out/attribute")]
        out: PathBuf,
        /// Override the scene's image size, WIDTHxHEIGHT (e.g. 360x240; square for a
        /// shading scene's sphere view).
        #[arg(long, value_name = "WxH")]
        image: Option<String>,
    },
    /// Error against run time for one shafts parameter (or glare / shading width, or
    /// `side` of an environment-map scene, or any width of any pipeline of a frame
    /// scene such as night-street): renders the scene for each
    /// value, compares with the f64 ray-marched reference, writes
    /// DIR/sweep_<param>.csv and .png and prints a table. With --shard K/N, only
    /// its share of the values, to DIR/sweep_<param>.shard-K-of-N.csv; `sweep merge`
    /// joins the shards (docs/sweep.md).
    // `sweep merge DIR…` is a subcommand of `sweep` beside its own options: the
    // options are required only without it, and the two do not mix.
    #[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
    Sweep {
        #[command(subcommand)]
        merge: Option<SweepCommand>,
        #[command(flatten)]
        args: SweepArgs,
    },
    /// The model against captures of real GeForce3-class silicon (the original Xbox's
    /// NV2A, github.com/abaire/nxdk_pgraph_tests_golden_results): each hardware test
    /// described as regions the model's units predict, compared pixel by pixel
    /// (docs/conformance.md).
    Conformance {
        #[command(subcommand)]
        cmd: crate::conformance::cli::ConformanceCommand,
    },
    /// Write every RAM/ROM table as $readmemh hex plus a manifest.
    Tables {
        /// Output directory.
        #[arg(long, default_value = "tables")]
        dir: PathBuf,
    },
    /// Write the prefiltered environment map of a scene with an `[environment]`
    /// section (built as `render` builds it): DIR/volume.raw (16-bit little-endian
    /// codes, RGB, x fastest), one PNG per z slice and DIR/map.json with the side,
    /// bits, layout and the exposure (docs/envmap.md).
    EnvmapDump {
        /// A built-in env-MAP-OBJECT scene or a TOML scene file.
        #[arg(long)]
        scene: String,
        /// Output directory.
        #[arg(long, default_value = "out/envmap-dump")]
        out: PathBuf,
        /// Map side instead of the scene's (a power of two, as `environment.side`).
        #[arg(long, allow_negative_numbers = true, value_parser = arg_u32)]
        side: Option<u32>,
    },
    /// Write a VCD trace of a unit for a few random pixels (tick driver).
    Trace {
        /// Unit name (see `units`).
        unit: String,
        /// Number of pixels (input words).
        #[arg(long, default_value_t = 8, allow_negative_numbers = true, value_parser = arg_pixels)]
        pixels: usize,
        /// Random seed for the inputs.
        #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = arg_u64)]
        seed: u64,
        /// Output VCD file.
        #[arg(long, default_value = "out/trace.vcd")]
        out: PathBuf,
        /// Instead of a VCD: write stimulus and expected-response vectors for the
        /// unit's Verilog into this directory (header.txt, stimulus.hex, expected.hex,
        /// cosim_<unit>_<config>.v; docs/rtl.md).
        #[arg(long, value_name = "DIR", conflicts_with = "pixels")]
        vectors: Option<PathBuf>,
        /// Transactions in the vector set (ignored when the input space is ≤ 2^20:
        /// then every input word is written).
        #[arg(long, requires = "vectors", allow_negative_numbers = true, value_parser = arg_u64)]
        count: Option<u64>,
        /// The unit's configuration for the vectors: default (GeForce) or narrow.
        #[arg(long, requires = "vectors", default_value = "default")]
        config: String,
    },
}

/// A whole-number option, parsed with a message that says what is wrong and the
/// allowed range (clap adds the option's name): a negative value is "negative", not
/// the parser's "invalid digit".
fn parse_whole(text: &str, max: u64) -> Result<u64, String> {
    let t = text.trim();
    if let Ok(n) = t.parse::<u64>() {
        if n <= max {
            return Ok(n);
        }
        return Err(format!("{t} is too large (allowed 0 ..= {max})"));
    }
    match t.parse::<f64>() {
        Ok(x) if x < 0.0 => Err(format!(
            "{t} is negative; a whole number in 0 ..= {max} is needed"
        )),
        Ok(x) if x.is_finite() && x.fract() != 0.0 => {
            Err(format!("{t} is not a whole number (allowed 0 ..= {max})"))
        }
        Ok(_) => Err(format!("{t} is too large (allowed 0 ..= {max})")),
        Err(_) => Err(format!(
            "'{t}' is not a number (a whole number in 0 ..= {max} is needed)"
        )),
    }
}

fn arg_u32(text: &str) -> Result<u32, String> {
    parse_whole(text, u32::MAX.into()).map(|n| n as u32)
}

fn arg_u64(text: &str) -> Result<u64, String> {
    parse_whole(text, u64::MAX)
}

/// `trace --pixels`: 1 ..= [`MAX_TRACE_PIXELS`].
fn arg_pixels(text: &str) -> Result<usize, String> {
    match parse_whole(text, MAX_TRACE_PIXELS as u64)? {
        0 => Err(format!("{text} is out of range (1 ..= {MAX_TRACE_PIXELS})")),
        n => Ok(n as usize),
    }
}

/// Most input words `trace` writes.
pub const MAX_TRACE_PIXELS: usize = 100_000;

/// `sweep`'s options (without `merge`).
#[derive(Args, Debug)]
pub struct SweepArgs {
    /// A built-in scene (fig4, fig6, stage, the glare, env-MAP-OBJECT and frame
    /// scenes), a TOML scene file, or a shading scene (shading-<model> of the
    /// shading-brdfs catalogue, shading-specular, shading-vertex, or a file with a
    /// `[shading_sphere]` section or its `[shading]` alias, at the GeForce widths;
    /// its image side is the sweep's default). The scenes `render --scene` takes.
    #[arg(long, required = true)]
    pub scene: Option<String>,
    /// Shafts scenes: planes, subplanes, texel_bits, fb_bits, weight_bits,
    /// coord_frac_bits, mesh, shadow_resolution, shadow_depth_bits, f_texels, h_texels,
    /// light_map_texels, acc_int_bits, acc_frac_bits (the interpolator's accumulators),
    /// recip_index_bits, recip_entry_bits, newton_frac_bits (the projective
    /// reciprocal). Glare scenes: shape_log2, shape_bits, falloff_log2,
    /// falloff_bits, weight_bits, coord_frac_bits, noise_bits, fb_bits, radial (0/1).
    /// Shading scenes (shading-<model>, shading-specular, shading-vertex):
    /// combiner_bits, factor_size, factor_bits, lookup_log2, lookup_bits, cube_face,
    /// cube_bits, vertex_mantissa, vertex_exponent (docs/shading.md).
    /// Frame scenes (several pipelines: night-street, shaded-metal, street-light):
    /// PIPELINE.FIELD, e.g. shafts.planes, glare.fb_bits, shading.cube_face,
    /// environment.side, or a field only one of its pipelines has (docs/sweep.md).
    /// The clocked chip's architecture (a scene the chip clocks, e.g. fig4, fig6,
    /// stage: the frame drawn once and clocked on every value): pipes, tmus,
    /// fifo_depth, cache_kb, cache_line, cache_ways, misses_in_flight, bandwidth_mbs,
    /// mem_latency, mem_queue, clock_mhz (docs/throughput.md).
    #[arg(long, required = true)]
    pub param: Option<String>,
    /// Comma list (10,20,30; 15x10,30x20 for mesh and h_texels), items may be
    /// inclusive ranges start..end:step for numeric params (10..200:10).
    #[arg(long, required = true)]
    pub values: Option<String>,
    /// Output directory.
    #[arg(long, default_value = "out/sweep")]
    pub out: PathBuf,
    /// Samples per ray of the ray-marched reference (computed once per sweep).
    #[arg(long, default_value_t = crate::pipeline::shafts::sweep::DEFAULT_TRUTH_SAMPLES, allow_negative_numbers = true, value_parser = arg_u32)]
    pub truth_samples: u32,
    /// Override the scene's image size, WIDTHxHEIGHT (e.g. 360x240 for quick sweeps;
    /// square for a shading scene's sphere view).
    #[arg(long, value_name = "WxH")]
    pub image: Option<String>,
    /// Run only shard K of N (1 <= K <= N): the values whose index i (from 0) has
    /// i mod N = K - 1, written to DIR/sweep_<param>.shard-K-of-N.csv for
    /// `sweep merge`.
    #[arg(long, value_name = "K/N", value_parser = Shard::parse)]
    pub shard: Option<Shard>,
    /// Continue an interrupted run of the same sweep (same scene, param, values and
    /// options, same --out and --shard) from the rows it saved, running only the
    /// values left; the final CSV, plot and table are the uninterrupted run's but for
    /// wall times. Refused, naming the file, if the rows there are another sweep's.
    #[arg(long)]
    pub resume: bool,
    /// Memory budget, as for `render`: the largest point of the sweep is checked
    /// against it before the first point runs (docs/inputs.md).
    #[arg(long, value_name = "SIZE", allow_negative_numbers = true, value_parser = crate::frame::budget::parse_bytes)]
    pub max_memory: Option<u64>,
    /// Add each row's dominant error source (`attribute` at that row's configuration)
    /// as the columns dominant_source and dominant_share; the attributions go to
    /// DIR/attribute_<param>_<value>/. Shading scenes only, not with
    /// --shard or --resume.
    #[arg(long)]
    pub attribute: bool,
    /// An architecture sweep's timing on every value's chip: clocked (every fragment,
    /// the default) or sampled (the passes and screen bands `render --timing sampled`
    /// clocks, the rest scaled; each row with its stated error). Architecture
    /// parameters only.
    #[arg(long, value_enum, value_name = "MODE")]
    pub timing: Option<crate::frame::timing::TimingMode>,
}

/// `sweep`'s subcommands.
#[derive(Subcommand, Debug)]
pub enum SweepCommand {
    /// Join the shard files of one sweep (`sweep … --shard K/N`) into the CSV, plot
    /// and table the unsharded sweep writes. Refuses, naming the file and writing
    /// nothing, shards of different sweeps, a missing or duplicated shard, or a
    /// malformed file.
    Merge {
        /// Output directory.
        #[arg(long, default_value = "out/sweep")]
        out: PathBuf,
        /// Directories holding the shard files (every sweep_<param>.shard-K-of-N.csv
        /// in them), or shard files.
        #[arg(required = true, value_name = "DIR")]
        dirs: Vec<PathBuf>,
    },
}

/// `sweep merge`: read and check every shard, then let the sweep that wrote them
/// write its outputs.
fn sweep_merge(out: &std::path::Path, dirs: &[PathBuf]) -> Result<(), String> {
    let set = crate::report::shard::load(dirs)?;
    match set.id.kind.as_str() {
        "shafts" => crate::pipeline::shafts::sweep::merge_cli(&set, out),
        "glare" | "shading" | "envmap" | "frame" => {
            crate::report::sweep_out::merge_sweep(&set, out)
        }
        other => Err(format!(
            "{}: unknown kind of sweep '{other}' (known: shafts, glare, shading, envmap, frame)",
            set.files[0].display()
        )),
    }
}

impl Command {
    /// The command as a user typed it, for the start of an error message: its name
    /// and the scene or item it works on (`sweep --scene night-street`,
    /// `reproduce shafts-fig4`).
    pub fn label(&self) -> String {
        let with_scene = |cmd: &str, scene: Option<&str>| match scene {
            Some(s) => format!("{cmd} --scene {s}"),
            None => cmd.to_string(),
        };
        match self {
            Command::Units { scene, .. } => with_scene("units", scene.as_deref()),
            Command::Render { scene, .. } => with_scene("render", Some(scene)),
            Command::Reproduce { name, .. } => format!("reproduce {name}"),
            Command::Scene { name, .. } => match name {
                Some(n) => format!("scene {n}"),
                None => "scene --reference".into(),
            },
            Command::Optimize(a) => with_scene("optimize", Some(&a.scene)),
            Command::Attribute { scene, .. } => with_scene("attribute", Some(scene)),
            Command::Sweep { merge: Some(_), .. } => "sweep merge".into(),
            Command::Sweep { args, .. } => with_scene("sweep", args.scene.as_deref()),
            Command::Tables { .. } => "tables".into(),
            Command::Conformance { cmd } => cmd.label(),
            Command::EnvmapDump { scene, .. } => with_scene("envmap-dump", Some(scene)),
            Command::Trace { unit, .. } => format!("trace {unit}"),
        }
    }
}

/// Run a parsed command; errors are returned as text naming the field at fault.
pub fn run(cli: Cli) -> Result<(), String> {
    match cli.command {
        Command::Units {
            json,
            synth: true,
            only,
            ..
        } => units_synth(json, &only),
        Command::Units {
            json,
            rtl_speed: true,
            count,
            config,
            ..
        } => units_rtl_speed(json, count, &config),
        Command::Units {
            json,
            alternates,
            scene,
            datasheet,
            ..
        } => match (scene, datasheet) {
            (Some(name), _) => crate::frame::cli::units_scene_cli(&name, json),
            (None, Some(path)) => registry::datasheet::refresh_file(&path).map(|m| println!("{m}")),
            (None, None) => units(json, alternates),
        },
        Command::Render {
            scene,
            max_memory,
            image,
            emit_gl: Some(dir),
            ..
        } => {
            crate::frame::emit_gl::command::emit_gl_cli(&scene, &dir, image.as_deref(), max_memory)
        }
        Command::Render {
            scene,
            out,
            json,
            reference,
            plan,
            max_memory,
            image,
            emit_gl: None,
            timing,
        } => crate::frame::cli::render_cli(
            &scene,
            &out,
            json,
            reference.as_deref(),
            plan,
            max_memory,
            image.as_deref(),
            &timing,
        ),
        Command::Reproduce {
            name,
            out,
            values,
            resume,
            max_memory,
            image,
        } => reproduce(&name, &out, values, resume, max_memory, image.as_deref()),
        Command::Optimize(a) => crate::optimize::command::optimize_cli(&a),
        Command::Attribute { scene, out, image } => attribute_cmd(&scene, &out, image.as_deref()),
        Command::Scene { name, reference } => {
            crate::frame::scene_text::scene_cli(name.as_deref(), reference.as_deref())
        }
        Command::Sweep {
            merge: Some(SweepCommand::Merge { out, dirs }),
            ..
        } => {
            check_dir_out("out", &out)?;
            sweep_merge(&out, &dirs)
        }
        Command::Sweep { merge: None, args } => sweep(args),
        Command::Conformance { cmd } => crate::conformance::cli::conformance_cli(cmd),
        Command::Tables { dir } => tables_cmd(&dir),
        Command::EnvmapDump { scene, out, side } => envmap_dump_cmd(&scene, &out, side),
        Command::Trace {
            unit,
            vectors: Some(dir),
            count,
            seed,
            config,
            ..
        } => trace_vectors_cmd(&unit, &dir, count, seed, &config),
        Command::Trace {
            unit,
            pixels,
            seed,
            out,
            ..
        } => trace_pixels_cmd(&unit, pixels, seed, &out),
    }
}

/// `tables --dir`: every unit's ROM tables and their manifest.
fn tables_cmd(dir: &std::path::Path) -> Result<(), String> {
    check_dir_out("dir", dir)?;
    let t = registry::tables();
    crate::tables::write_all(dir, &t).map_err(|e| format!("dir: {e}"))?;
    println!(
        "wrote {} tables and manifest.json to {}",
        t.len(),
        dir.display()
    );
    Ok(())
}

/// `envmap-dump`: a scene's environment-map volume as slices with its sidecar.
fn envmap_dump_cmd(scene: &str, out: &std::path::Path, side: Option<u32>) -> Result<(), String> {
    let sc = crate::scene::load::load_frame_scene(scene)?;
    check_dir_out("out", out)?;
    let (_, car) = crate::pipeline::envmap::dump::dump_scene(&sc, side, out)?;
    println!(
        "wrote {}³ × {} bits ({}, exposure {}) to {}: {}, {} slices, {}",
        car.side,
        car.bits,
        car.prefilter,
        car.exposure,
        out.display(),
        car.volume,
        car.slices.len(),
        crate::pipeline::envmap::dump::SIDECAR_FILE
    );
    Ok(())
}

/// `trace --vectors`: a unit's stimulus and expected-response vectors.
fn trace_vectors_cmd(
    unit: &str,
    dir: &std::path::Path,
    count: Option<u64>,
    seed: u64,
    config: &str,
) -> Result<(), String> {
    let cfg = registry::rtl::RtlConfig::parse(config)?;
    let n = count.unwrap_or(100_000);
    let max = registry::rtl::MAX_VECTORS as u64;
    if n == 0 || n > max {
        return Err(format!("count: {n} is out of range (1 ..= {max})"));
    }
    let v = registry::rtl::vectors(unit, cfg, n as usize, seed)?;
    v.write(dir)?;
    println!(
        "wrote {} transactions of {} ({}, {}; latency {}, II {}) into {}",
        v.stimulus.len(),
        v.unit,
        cfg.name(),
        if v.exhaustive {
            "exhaustive"
        } else {
            "seeded random + corners"
        },
        v.latency,
        v.ii,
        dir.display()
    );
    Ok(())
}

/// `trace`: a unit's VCD over `pixels` seeded pixels.
fn trace_pixels_cmd(
    unit: &str,
    pixels: usize,
    seed: u64,
    out: &std::path::Path,
) -> Result<(), String> {
    if pixels == 0 || pixels > MAX_TRACE_PIXELS {
        return Err(format!(
            "pixels: {pixels} is out of range (1 ..= {MAX_TRACE_PIXELS})"
        ));
    }
    let mut buf = Vec::new();
    let ctr = registry::trace(unit, pixels, seed, &mut buf)?;
    write_file(out, &buf)?;
    println!(
        "wrote {} ({} cycles, {} pixels in, {} out, {} stalls)",
        out.display(),
        ctr.cycles,
        ctr.pixels_in,
        ctr.pixels_out,
        ctr.stalls
    );
    Ok(())
}

/// Every `reproduce` name, in the order `--help` lists them.
pub const REPRODUCTIONS: &[&str] = &[
    "shafts-fig4",
    "shafts-fig5",
    "shafts-vs-raymarch",
    "shafts-stage",
    "glare-fig4",
    "glare-fig5",
    "glare-fig7",
    "glare-fig8",
    "glare-throughput",
    "glare-asic-throughput",
    "glare-scaling",
    "glare-gauss-seeds",
    "envmap-table3",
    "envmap-table5",
    "envmap-images",
    "envmap-timing",
    "envmap-lambda-sweep",
    "envmap-roughness",
    "shading-normalize-cube",
    "shading-specular",
    "shading-brdfs",
    "shading-brdf-properties",
    "shading-factorization",
    "shading-vertex-float",
    "frame-elaboration",
    "sim-speed",
    "assumptions",
    "vs-gl",
];

/// The reproductions that ran past 30 s and do not save their rows as they go, each
/// with the reason (release build, defaults, one run each on the shared 2-core machine
/// under load, `reproduce NAME` timed with a 300 s cap: docs/sweep.md): `--resume` is
/// refused for them with it. The others not here and not in
/// [`RESUMABLE_REPRODUCTIONS`] finish in under 30 s.
pub const LONG_REPRODUCTIONS: &[(&str, &str)] = &[
    (
        "shafts-stage",
        "takes about 110 s but is one frame and one row, so no finished item exists \
         before the end",
    ),
    (
        "sim-speed",
        "takes about 110 s but is a timing: its rows are best-of-several wall times, \
         which a resumed run would mix from two machine states",
    ),
    (
        "vs-gl",
        "takes about 230 s but is a timing: each row's model ÷ GL draw ratio is from \
         one run on one machine state, which a resumed run would mix",
    ),
];

/// The reproductions that save their rows (or items) as they go and take `--resume`:
/// shafts-fig4 and shafts-fig5 through `report::resume::Journal`, the others through
/// `report::items::ItemJournal` (docs/sweep.md).
pub const RESUMABLE_REPRODUCTIONS: &[&str] = &[
    "shafts-fig4",
    "shafts-fig5",
    "glare-gauss-seeds",
    "envmap-table3",
    "envmap-table5",
    "envmap-timing",
    "envmap-lambda-sweep",
    "envmap-roughness",
    "envmap-images",
    "frame-elaboration",
    "shading-brdf-properties",
    "shading-factorization",
];

fn reproduce(
    name: &str,
    out: &std::path::Path,
    values: Option<Vec<u32>>,
    resume: bool,
    max_memory: Option<u64>,
    image: Option<&str>,
) -> Result<(), String> {
    check_reproduction_args(name, values.as_deref(), resume, image)?;
    crate::frame::budget::check_reproduction(name, values.as_deref(), max_memory)?;
    let points = crate::frame::budget::reproduction_points(name, values.as_deref())?;
    check_dir_out("out", out)?;
    std::fs::create_dir_all(out).map_err(|e| format!("out: {}: {e}", out.display()))?;
    let t0 = std::time::Instant::now();
    if name == "vs-gl" {
        crate::frame::vs_gl::vs_gl_cli(out, image)?;
    } else if name.starts_with("envmap-") {
        run_envmap_reproduction(name, out, resume)?;
    } else if name.starts_with("shading-") {
        run_shading_reproduction(name, out, resume)?;
    } else {
        run_frame_reproduction(name, out, values, resume)?;
    }
    println!(
        "{name}: wrote {} in {:.1} s",
        out.display(),
        t0.elapsed().as_secs_f64()
    );
    // The range warnings of the frames it rendered, once each.
    if let Some(points) = points {
        crate::frame::range::print_points(&crate::frame::range::check_points(&points));
    }
    Ok(())
}

/// `reproduce`'s arguments checked before any work: the name, `--image`, `--values`,
/// `--resume`, and the environment variables of the environment-map reproductions.
fn check_reproduction_args(
    name: &str,
    values: Option<&[u32]>,
    resume: bool,
    image: Option<&str>,
) -> Result<(), String> {
    if !REPRODUCTIONS.contains(&name) {
        return Err(format!(
            "name: unknown reproduction '{name}' (known: {})",
            REPRODUCTIONS.join(", ")
        ));
    }
    if name == "vs-gl" {
        // The size, then the tools, before any file is written.
        if let Some(img) = image {
            crate::report::image_arg::parse_image(img)?;
        }
        if let Some(why) = crate::frame::vs_gl::missing_tools() {
            return Err(why);
        }
    } else if let Some(img) = image {
        use crate::pipeline::envmap::reproduce::{set_image_side, IMAGE_REPRODUCTIONS};
        if !IMAGE_REPRODUCTIONS.contains(&name) {
            return Err(format!(
                "--image: '{name}' has no image size to set; --image sizes {}",
                IMAGE_REPRODUCTIONS.join(", ")
            ));
        }
        set_image_side(img)?;
    }
    if values.is_some() && !matches!(name, "shafts-fig4" | "shafts-fig5") {
        return Err(format!(
            "values: only shafts-fig4 (planes) and shafts-fig5 (sub-planes) take --values, not '{name}'"
        ));
    }
    if resume && !RESUMABLE_REPRODUCTIONS.contains(&name) {
        let why = match LONG_REPRODUCTIONS.iter().find(|(n, _)| *n == name) {
            Some((_, why)) => {
                format!("{why}, so there is nothing to resume from; run it again without --resume")
            }
            None => "finishes in seconds (under 30 s in release) and writes its files whole \
                     when it is done, so there is nothing to resume: run it again without \
                     --resume"
                .to_string(),
        };
        return Err(format!(
            "resume: '{name}' {why}. These save their items as they go and can resume: {}",
            RESUMABLE_REPRODUCTIONS.join(", ")
        ));
    }
    if let Some(v) = values.and_then(|v| v.iter().position(|&x| x == 0)) {
        return Err(format!("values[{v}]: must be at least 1"));
    }
    if name.starts_with("envmap-") {
        // Refuse a malformed ENVMAP_PATTERN_SIZE before any build or file.
        crate::pipeline::envmap::reproduce::cli_env("pattern")?;
        // And an ENVMAP_TABLE3_S beyond the supported side.
        crate::pipeline::envmap::reproduce::cli_side()?;
        crate::pipeline::envmap::reproduce::cli_thresholds()?;
    }
    Ok(())
}

/// The shafts, glare and frame reproductions.
fn run_frame_reproduction(
    name: &str,
    out: &std::path::Path,
    values: Option<Vec<u32>>,
    resume: bool,
) -> Result<(), String> {
    use crate::pipeline::glare::reproduce as g;
    use crate::pipeline::shafts::reproduce as r;
    match name {
        "shafts-fig4" => r::fig4(
            out,
            &values.unwrap_or_else(|| (1..=20).map(|k| 10 * k).collect()),
            resume,
        )?,
        "shafts-fig5" => r::fig5(out, &values.unwrap_or_else(|| (1..=25).collect()), resume)?,
        "shafts-vs-raymarch" => r::vs_raymarch(out)?,
        "shafts-stage" => r::stage(out)?,
        "glare-fig4" => g::fig4(out)?,
        "glare-fig5" => g::fig5(out)?,
        "glare-fig7" => g::fig7(
            out,
            &crate::frame::run::shafts_backdrop(&crate::scene::builtin_glare::street_light())
                .map_err(|e| e.to_string())?,
        )?,
        "glare-fig8" => g::fig8(out)?,
        "glare-throughput" => g::throughput(out)?,
        "glare-asic-throughput" => {
            crate::pipeline::glare::clocked::asic_throughput(out)?;
        }
        "glare-scaling" => {
            use crate::frame::glare_scaling as gs;
            let rows = gs::glare_scaling(out, &gs::SOURCE_COUNTS)?;
            print!("{}", gs::table(&rows));
        }
        "glare-gauss-seeds" => {
            crate::pipeline::glare::gauss_seeds::gauss_seeds_resumable(
                out,
                crate::pipeline::glare::gauss_seeds::cli_seeds()?,
                resume,
            )?;
        }
        "sim-speed" => crate::frame::speed::sim_speed(out)?,
        "assumptions" => {
            let rows = crate::frame::assumptions::assumptions(out, None, None)?;
            print!("{}", crate::frame::assumptions::table(&rows));
        }
        "frame-elaboration" => {
            let rows = crate::frame::reproduce::frame_elaboration_resumable(out, None, resume)?;
            print!("{}", crate::frame::reproduce::elaboration_rows_table(&rows));
        }
        _ => {
            return Err(format!(
                "name: unknown reproduction '{name}' (known: {})",
                REPRODUCTIONS.join(", ")
            ))
        }
    }
    Ok(())
}

/// The environment-map reproductions.
fn run_envmap_reproduction(name: &str, out: &std::path::Path, resume: bool) -> Result<(), String> {
    match name {
        "envmap-table3" => crate::pipeline::envmap::reproduce::table3_at(
            out,
            crate::pipeline::envmap::reproduce::cli_side()?,
            &crate::pipeline::envmap::reproduce::cli_thresholds()?,
            resume,
        )?,
        "envmap-table5" => {
            crate::pipeline::envmap::reproduce::table5_resumable(
                out,
                crate::pipeline::envmap::reproduce::RenderRun::cli()?,
                resume,
            )?;
        }
        "envmap-timing" => {
            crate::pipeline::envmap::reproduce::timing_resumable(
                out,
                crate::pipeline::envmap::reproduce::cli_side()?,
                resume,
            )?;
        }
        "envmap-lambda-sweep" => {
            crate::pipeline::envmap::studies::lambda_sweep_resumable(
                out,
                crate::pipeline::envmap::reproduce::RenderRun::cli()?,
                resume,
            )?;
        }
        "envmap-roughness" => {
            crate::pipeline::envmap::studies::roughness_resumable(
                out,
                crate::pipeline::envmap::reproduce::RenderRun::cli()?,
                resume,
            )?;
        }
        "envmap-images" => {
            crate::pipeline::envmap::reproduce::images_resumable(
                out,
                crate::pipeline::envmap::reproduce::RenderRun::cli()?,
                resume,
            )?;
        }
        _ => {
            return Err(format!(
                "name: unknown reproduction '{name}' (known: {})",
                REPRODUCTIONS.join(", ")
            ))
        }
    }
    Ok(())
}

/// The shading reproductions.
fn run_shading_reproduction(name: &str, out: &std::path::Path, resume: bool) -> Result<(), String> {
    match name {
        "shading-brdf-properties" => {
            crate::pipeline::shading::brdf_properties::brdf_properties_resumable(out, resume)?;
        }
        "shading-factorization" => {
            use crate::pipeline::shading::factor::reproduce as f;
            // The shading-brdfs sphere (E = π) and its Cook–Torrance metal lobe.
            let brdf =
                crate::pipeline::shading::brdfs::factorization_brdf().map_err(|e| e.to_string())?;
            // Ceilings relative to the output's saturation R·cos θ_i = 1/E: none, 4×, 1×
            // (the last is what the shading path fits: `path.rs`).
            let view = crate::pipeline::shading::brdfs::brdfs_view();
            let e = view.irradiance;
            let sweep = f::FactorSweep {
                view,
                ceilings: vec![f64::INFINITY, 4.0 / e, 1.0 / e],
                ..f::FactorSweep::default()
            };
            for line in f::factorization_resumable(out, brdf.as_ref(), &sweep, resume)? {
                println!("{line}");
            }
        }
        "shading-normalize-cube" => {
            crate::pipeline::shading::normalize_cube::reproduce(out)?;
        }
        "shading-specular" => {
            let rows = crate::pipeline::shading::specular::shading_specular(out)?;
            print!("{}", crate::pipeline::shading::specular::table(&rows));
        }
        "shading-brdfs" => {
            let rows = crate::pipeline::shading::brdfs::shading_brdfs(out)?;
            print!("{}", crate::pipeline::shading::brdfs::table(&rows));
        }
        "shading-vertex-float" => {
            crate::pipeline::shading::vertex_float::reproduce(out)?;
        }
        _ => {
            return Err(format!(
                "name: unknown reproduction '{name}' (known: {})",
                REPRODUCTIONS.join(", ")
            ))
        }
    }
    Ok(())
}

/// `sweep`: the scene loaded once, then its path ([`SweepPath`]) by what it holds: a
/// shading sphere, the clocked chip's parameter, an environment scene, a scene of
/// several pipelines, a glare scene, a shafts scene.
fn sweep(args: SweepArgs) -> Result<(), String> {
    // clap requires the three without `merge`; an error, not a panic, if not.
    let need = |v: Option<String>, what: &str| {
        v.ok_or_else(|| format!("{what}: missing (sweep needs --scene, --param and --values)"))
    };
    let (scene, param, values) = (
        &need(args.scene, "scene")?,
        &need(args.param, "param")?,
        &need(args.values, "values")?,
    );
    let (out, truth_samples, image, shard, resume) = (
        args.out.as_path(),
        args.truth_samples,
        args.image.as_deref(),
        args.shard,
        args.resume,
    );
    // One resolver for every kind of scene; what it holds picks the path.
    let loaded = crate::scene::load::load_scene(scene)?;
    let path = crate::frame::sweep::sweep_path(&loaded, param, args.attribute)?;
    match path {
        SweepPath::TestScene => {
            return Err(
                "scene: the foundation test scene (`render --scene test`) has no sample \
                 planes to sweep; use fig4, fig6, stage or a TOML scene file"
                    .to_string(),
            )
        }
        SweepPath::Shading => {
            return shading_sweep(
                &loaded,
                param,
                values,
                out,
                image,
                (shard, resume),
                (args.attribute, args.max_memory),
            )
        }
        // An architecture parameter of the clocked chip: the frame drawn once, clocked
        // on every value.
        SweepPath::Chip => {
            let p = crate::chip::params::ChipParam::from_name(param)
                .ok_or_else(|| format!("param: unknown parameter '{param}'"))?;
            return crate::frame::chip_sweep::chip_sweep_cli(
                scene,
                loaded,
                (p, args.timing),
                values,
                out,
                image,
                args.max_memory,
                (shard.is_some(), resume, args.attribute),
            );
        }
        _ => {}
    }
    if let Some(t) = args.timing {
        return Err(format!(
            "--timing {}: only an architecture sweep (--param pipes, tmus, fifo_depth, \
             cache_kb, …, on a scene the chip clocks) times the chip; '{param}' is not one",
            t.name()
        ));
    }
    crate::frame::budget::check_sweep(&loaded, param, values, image, args.max_memory)?;
    check_dir_out("out", out)?;
    if path == SweepPath::AttributeRefused {
        return Err(format!(
            "--attribute: sweep attributes shading-* scenes only, not '{scene}'"
        ));
    }
    // The range warnings of the points it runs (its shard's share), once each.
    let points = crate::frame::budget::sweep_points(&loaded, param, values, image)?;
    let request = SweepRequest {
        scene,
        param,
        values,
        out,
        truth_samples,
        image,
        shard,
        resume,
    };
    sweep_kinds(loaded, path, &request)?;
    if let Some(mut points) = points {
        if let Some(sh) = shard {
            let keep = sh.indices(points.len());
            points = keep.into_iter().map(|i| points[i].clone()).collect();
        }
        crate::frame::range::print_points(&crate::frame::range::check_points(&points));
    }
    Ok(())
}

/// `sweep` of a shading sphere: a width of the section's built-in shading scene from
/// its GeForce defaults, on the section's image side unless `--image` gives one
/// (with `--attribute`, each point attributed).
// The command line's options, one argument each.
#[allow(clippy::too_many_arguments)]
fn shading_sweep(
    loaded: &crate::scene::format::Scene,
    param: &str,
    values: &str,
    out: &std::path::Path,
    image: Option<&str>,
    (shard, resume): (Option<Shard>, bool),
    (attribute, max_memory): (bool, Option<u64>),
) -> Result<(), String> {
    let Some(s) = &loaded.shading_sphere else {
        return Err("scene: not a shading sphere".into());
    };
    defaults_only(s, "sweep")?;
    let image = match image {
        Some(img) => Some(crate::pipeline::shafts::sweep::parse_image(img)?),
        None => s.image.map(|side| (side, side)),
    };
    // Square views only (the sweep refuses others); 256 by default.
    let side = image.map_or(crate::scene::shading_sphere::DEFAULT_IMAGE, |(w, _)| w);
    crate::frame::budget::check_shading_sweep(side, max_memory)?;
    check_dir_out("out", out)?;
    if attribute {
        return crate::pipeline::shading::attributed_sweep::attributed_sweep_cli(
            &s.scene, param, values, out, image, shard, resume,
        );
    }
    crate::pipeline::shading::sweep::shading_sweep_cli(
        &s.scene, param, values, out, image, shard, resume,
    )
}

/// A sweep's command-line options, as the frame and pipeline sweeps take them.
struct SweepRequest<'a> {
    scene: &'a str,
    param: &'a str,
    values: &'a str,
    out: &'a std::path::Path,
    truth_samples: u32,
    image: Option<&'a str>,
    shard: Option<Shard>,
    resume: bool,
}

/// [`sweep`] of a scene of lights and objects by its [`SweepPath`]: an environment
/// scene, a scene of several pipelines, a glare scene, a shafts scene.
fn sweep_kinds(
    mut s: crate::scene::format::Scene,
    path: SweepPath,
    r: &SweepRequest<'_>,
) -> Result<(), String> {
    let (scene, param, values, out) = (r.scene, r.param, r.values, r.out);
    let (shard, resume) = (r.shard, r.resume);
    if path == SweepPath::Shafts {
        return crate::pipeline::shafts::sweep::sweep_cli(
            s,
            scene,
            param,
            values,
            out,
            r.truth_samples,
            r.image,
            shard,
            resume,
        );
    }
    crate::scene::load::apply_image(&mut s, r.image)?;
    match path {
        SweepPath::Environment => crate::pipeline::envmap::sweep::envmap_sweep_cli(
            &s, scene, param, values, out, shard, resume,
        ),
        SweepPath::Frame => {
            crate::frame::sweep::frame_sweep_cli(&s, scene, param, values, out, shard, resume)
        }
        _ => {
            let backdrop = if crate::frame::plan::shafts_backdrop(&s) {
                Some(crate::frame::run::shafts_backdrop(&s).map_err(|e| e.to_string())?)
            } else {
                None
            };
            crate::pipeline::glare::sweep::glare_sweep_cli(
                &s,
                scene,
                param,
                values,
                out,
                backdrop.as_ref(),
                shard,
                resume,
            )
        }
    }
}

/// `attribute`: every argument checked (scene, image size, output directory) before
/// anything renders; the pipeline picked by the scene's sections (glare, then an
/// environment object, then shafts).
fn attribute_cmd(scene: &str, out: &std::path::Path, image: Option<&str>) -> Result<(), String> {
    use crate::frame::attribute::AttributePath as P;
    // One resolver for every kind of scene; what it holds picks the path.
    let mut s = crate::scene::load::load_scene(scene)?;
    let path = crate::frame::attribute::attribute_path(&s)?;
    if path == P::TestScene {
        return Err(format!(
            "scene: '{scene}' has no error sources attribute knows (it covers shafts \
             scenes: fig4, fig6, stage; glare scenes; env-MAP-OBJECT scenes; shading-* \
             scenes; TOML files)"
        ));
    }
    let size = image
        .map(crate::pipeline::shafts::sweep::parse_image)
        .transpose()?;
    if let (P::Shading, Some(sec)) = (path, &s.shading_sphere) {
        defaults_only(sec, "attribute")?;
        let size = size.or(sec.image.map(|side| (side, side)));
        let c = crate::pipeline::shading::attribute::config_for_cli(&sec.scene, size)?;
        check_attribute_out(out)?;
        let t0 = std::time::Instant::now();
        let a = crate::pipeline::shading::attribute::attribute_shading(&c, out)?;
        let n = c.view.size;
        return print_attribution(scene, "shading", (n, n), &a, t0);
    }
    if let Some((w, h)) = size {
        s.image.width = w;
        s.image.height = h;
    }
    s.validate().map_err(|e| e.to_string())?;
    check_attribute_out(out)?;
    let t0 = std::time::Instant::now();
    let (a, kind) = match path {
        P::Frame => {
            let pipelines = crate::frame::plan::frame_pipelines(&s).map_err(|e| e.to_string())?;
            (
                crate::frame::attribute::attribute_frame(&s, out)?,
                format!("frame: {}", pipelines.join(" + ")),
            )
        }
        P::Glare => {
            let backdrop = if crate::frame::plan::shafts_backdrop(&s) {
                Some(crate::frame::run::shafts_backdrop(&s).map_err(|e| e.to_string())?)
            } else {
                None
            };
            let a = crate::pipeline::glare::attribute::attribute_glare(&s, backdrop.as_ref(), out)?;
            (a, "glare".to_string())
        }
        P::Environment => (
            crate::pipeline::envmap::attribute::attribute_envmap(&s, out)?,
            "environment map".to_string(),
        ),
        P::Shafts => (
            crate::pipeline::shafts::attribute::attribute_shafts(&s, out)?,
            "shafts".to_string(),
        ),
        P::Nothing | P::TestScene | P::Shading => {
            return Err(format!(
                "scene: '{scene}' has no lights, glare or environment object: nothing to attribute"
            ))
        }
    };
    print_attribution(scene, &kind, (s.image.width, s.image.height), &a, t0)
}

/// A shading sphere's `sweep` and `attribute` start from the scene's GeForce
/// defaults: a section that sets widths or a chip is refused, naming the field,
/// rather than its settings dropped (`render` and `optimize` take them).
fn defaults_only(
    s: &crate::scene::shading_sphere::ShadingSphereSection,
    command: &str,
) -> Result<(), String> {
    if let Some(k) = s.hw.keys().next() {
        return Err(format!(
            "{}.hw.{k}: {command} starts from the scene's GeForce widths; give the \
             built-in `{}` (render and optimize take a file's widths)",
            s.table, s.scene
        ));
    }
    if !s.chip.is_default() {
        return Err(format!(
            "{}.chip: {command} runs the GeForce2's modes; give the built-in `{}` \
             (render and optimize take a file's chip)",
            s.table, s.scene
        ));
    }
    Ok(())
}

/// `out` is a directory attribute can write (`report::outputs`).
fn check_attribute_out(out: &std::path::Path) -> Result<(), String> {
    check_dir_out("out", out)
}

pub use crate::report::outputs::check_dir_out;

/// The attribution's summary line, table, largest source and all-ideal line.
fn print_attribution(
    scene: &str,
    kind: &str,
    (w, h): (u32, u32),
    a: &crate::report::attribution::Attribution,
    t0: std::time::Instant,
) -> Result<(), String> {
    use crate::report::attribution::table;
    println!(
        "attribute {scene} ({kind}, {w}x{h}): configured mean {:.3} / RMS {:.3} / max {:.1} levels; wrote {} and {} in {:.1} s",
        a.configured.mean_abs,
        a.configured.rms,
        a.configured.max,
        a.csv.display(),
        a.png.display(),
        t0.elapsed().as_secs_f64()
    );
    print!("{}", table(&a.rows));
    if let Some(d) = a.dominant() {
        println!(
            "largest source: {} ({:.1} % of the squared error; {:.0} % of what it removes is in the {} band; pixels it changes by > 1 level: {})",
            d.source,
            d.share * 100.0,
            d.band_share * 100.0,
            d.band,
            d.bbox
        );
    }
    println!(
        "all ideal: mean {:.3}, RMS {:.3}, max {:.1} levels, {:.3} % of values off by > 2 levels: {} the bound; interaction remainder {:.1} %",
        a.all_ideal.mean_abs,
        a.all_ideal.rms,
        a.all_ideal.max,
        a.all_ideal_outliers * 100.0,
        if a.within_bound { "within" } else { "OUTSIDE" },
        a.remainder_share * 100.0
    );
    for p in &a.diff_images {
        println!("difference image: {}", p.display());
    }
    Ok(())
}

pub use crate::report::image_out::write_file;

/// `units --rtl-speed`: the model beside Verilator per unit with Verilog.
fn units_rtl_speed(json: bool, count: usize, config: &str) -> Result<(), String> {
    use registry::rtl;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = rtl::RtlConfig::parse(config).map_err(|e| format!("--{e}"))?;
    if count == 0 || count > rtl::MAX_VECTORS {
        return Err(format!(
            "--count: {count} is out of range (1 ..= {})",
            rtl::MAX_VECTORS
        ));
    }
    let dir = std::env::temp_dir().join(format!("glare_rtl_speed_{}", std::process::id()));
    let rows = rtl::speed::rtl_speed(root, &dir, config, count, 20);
    let _ = std::fs::remove_dir_all(&dir);
    let rows = rows?;
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&rows).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
    // A rate not measured is `n/a`, never 0.
    let sci = |v: Option<f64>| v.map_or("n/a".into(), |v| format!("{v:.3e}"));
    let ratio = |v: Option<f64>| {
        v.map_or("n/a".into(), |v| {
            if v < 10.0 {
                format!("{v:.2}")
            } else {
                format!("{v:.0}")
            }
        })
    };
    let t: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.unit.to_string(),
                r.config.to_string(),
                if r.set_size < r.transactions {
                    format!("{} ({} repeated)", r.transactions, r.set_size)
                } else {
                    r.transactions.to_string()
                },
                format!("{:.3e}", r.model_pixels_per_s),
                sci(r.verilator_memory_cycles_per_s),
                sci(r.verilator_memory_transactions_per_s),
                ratio(r.model_over_verilator_memory),
                sci(r.verilator_cycles_per_s),
                sci(r.verilator_transactions_per_s),
                ratio(r.model_over_verilator),
            ]
        })
        .collect();
    print!(
        "{}",
        text_table(
            &[
                "unit",
                "config",
                "transactions",
                "model pixels/s",
                "Verilator in-memory cycles/s",
                "Verilator in-memory transactions/s",
                "model ÷ Verilator (in memory)",
                "Verilator $fscanf cycles/s",
                "Verilator $fscanf transactions/s",
                "model ÷ Verilator ($fscanf)"
            ],
            &t
        )
    );
    let build: f64 = rows.iter().map(|r| r.verilator_memory_build_secs).sum();
    println!(
        "In-memory harness: one Verilator build per unit (-O3, C++ at -O3), {build:.0} s in all."
    );
    Ok(())
}

/// `units --synth`: every unit's summary, and for each unit with Verilog the Yosys
/// count at its default widths beside the model's (`only`: just those units; an
/// unknown name or one without Verilog is refused, naming `--only`, before any run).
fn units_synth(json: bool, only: &[String]) -> Result<(), String> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for name in only {
        registry::rtl::rtl_entry(name).map_err(|e| format!("--only: {e}"))?;
    }
    let mut synths = std::collections::BTreeMap::new();
    for e in registry::rtl::RTL_UNITS {
        if !only.is_empty() && !only.iter().any(|n| n == e.name) {
            continue;
        }
        // Progress on stderr: one unit can take minutes (ABC on wide multipliers).
        eprintln!("units --synth: {} …", e.name);
        let started = std::time::Instant::now();
        let s = registry::rtl::synth(root, e.name, registry::rtl::RtlConfig::Default)?;
        eprintln!(
            "units --synth: {} done in {:.0} s",
            e.name,
            started.elapsed().as_secs_f64()
        );
        synths.insert(e.name, s);
    }
    let s = registry::summaries();
    if json {
        let mut rows = Vec::new();
        for u in &s {
            let mut v = serde_json::to_value(u).map_err(|e| e.to_string())?;
            let y = synths.get(u.name);
            if let Some(o) = v.as_object_mut() {
                o.insert("gates_yosys".into(), y.map(|y| y.gates_yosys).into());
                o.insert("gates_yosys_rel_diff".into(), y.map(|y| y.rel_diff).into());
                // A hierarchical unit's kept modules (one instance each, and how many).
                if let Some(y) = y.filter(|y| !y.modules.is_empty()) {
                    let m = serde_json::to_value(&y.modules).map_err(|e| e.to_string())?;
                    o.insert("gates_yosys_modules".into(), m);
                }
            }
            rows.push(v);
        }
        println!(
            "{}",
            serde_json::to_string_pretty(&rows).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
    let rows: Vec<Vec<String>> = s
        .iter()
        .filter_map(|u| synths.get(u.name))
        .map(|y| {
            vec![
                y.name.to_string(),
                format!("{:.0}", y.gates_model),
                format!("{:.0}", y.gates_yosys),
                format!("{:+.1} %", 100.0 * y.rel_diff),
            ]
        })
        .collect();
    print!(
        "{}",
        text_table(
            &["unit", "gates_model", "gates_yosys", "model vs yosys"],
            &rows
        )
    );
    // Hierarchical units: each kept module's count (one instance, its submodules in).
    for y in synths.values().filter(|y| !y.modules.is_empty()) {
        let rows: Vec<Vec<String>> = y
            .modules
            .iter()
            .map(|m| {
                vec![
                    m.module.clone(),
                    m.instances.to_string(),
                    format!("{:.0}", m.gates_yosys),
                    format!("{:.0}", m.gates_yosys * m.instances as f64),
                ]
            })
            .collect();
        println!("\n{} (hierarchical: each module synthesised once)", y.name);
        print!(
            "{}",
            text_table(
                &[
                    "module",
                    "instances",
                    "gates_yosys (one)",
                    "gates_yosys (all)"
                ],
                &rows
            )
        );
    }
    Ok(())
}

/// The widest the `units` table's widths column gets before it wraps.
const UNITS_WIDTHS_COLUMN: usize = 44;

/// `words` joined by spaces into lines of at most `width` characters (a longer word
/// gets a line of its own); one empty line for no words.
fn wrap_words(words: &[String], width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for w in words {
        let last = lines.last_mut().expect("one line at least");
        if last.is_empty() {
            last.push_str(w);
        } else if last.chars().count() + 1 + w.chars().count() <= width {
            last.push(' ');
            last.push_str(w);
        } else {
            lines.push(w.clone());
        }
    }
    lines
}

fn units(json: bool, alternates: bool) -> Result<(), String> {
    let s = registry::summaries();
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&s).map_err(|e| e.to_string())?
        );
    } else {
        // The widths wrapped onto continuation lines, so the table fits in about 120
        // columns (`--json` has them as a list).
        let mut rows: Vec<Vec<String>> = Vec::new();
        for u in &s {
            let widths: Vec<String> = u
                .widths
                .iter()
                .map(|w| format!("{}={}", w.name, w.bits))
                .collect();
            let lines = wrap_words(&widths, UNITS_WIDTHS_COLUMN);
            for (k, line) in lines.into_iter().enumerate() {
                rows.push(if k == 0 {
                    vec![
                        u.name.to_string(),
                        line,
                        u.latency.to_string(),
                        u.ii.to_string(),
                        format!("{:.0}", u.gates_nand2),
                        u.ram_bits.to_string(),
                    ]
                } else {
                    vec![
                        String::new(),
                        line,
                        String::new(),
                        String::new(),
                        String::new(),
                        String::new(),
                    ]
                });
            }
        }
        print!(
            "{}",
            text_table(
                &[
                    "unit",
                    "widths",
                    "latency_cycles",
                    "ii_cycles",
                    "gates_nand2",
                    "ram_bits"
                ],
                &rows
            )
        );
        println!(
            "widths in bits, but *_log2 (log2 of a table or texture side) and attrs, \
             operands (counts); gates in NAND2 equivalents"
        );
    }
    if alternates {
        let rows: Vec<Vec<String>> = modulate_alternates(8)
            .iter()
            .map(|r| {
                vec![
                    format!("{:?}", r.mode),
                    r.max_err.to_string(),
                    format!("{:.4}", r.mean_err),
                    format!("{:+.4}", r.mean_bias),
                    r.pairs_differing.to_string(),
                    format!("{:.0}", r.gates_nand2),
                ]
            })
            .collect();
        println!("\nmodulate alternates, 8-bit, all 65 536 pairs, against round(a*b/255):");
        print!(
            "{}",
            text_table(
                &[
                    "mode",
                    "max_err",
                    "mean_abs_err",
                    "mean_bias",
                    "pairs_differing",
                    "gates_nand2"
                ],
                &rows
            )
        );
    }
    Ok(())
}
