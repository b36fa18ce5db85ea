//! The `Combiner` suite: nxdk_pgraph_tests' src/tests/combiner_tests.cpp on the NV2A,
//! predicted through the `register_combiner` and `final_combiner` units (and, where a
//! half-quad is alpha-blended over the background, the `blend` unit: SRC_ALPHA,
//! ONE_MINUS_SRC_ALPHA, ADD with the hardware's one rounding, in both chips' modes:
//! this suite is about the combiners).
//!
//! How the test programs map onto the units (read from the test source; names are the
//! NV2A's, the units' are GL_NV_register_combiners'):
//! - Registers: R0 = SPARE0, R1 = SPARE1, V0 = PRIMARY_COLOR (diffuse), V1 =
//!   SECONDARY_COLOR (specular), C0/C1 = CONSTANT_COLOR0/1, T0..T3 = TEXTURE0..3.
//!   `OneInput()` is ZERO under UNSIGNED_INVERT. On the alpha portion an input without
//!   the alpha flag reads the register's BLUE.
//! - Output operations (COLOR_OCW bits 15..17): IDENTITY, BIAS (−½), SHIFT_LEFT_1 (×2),
//!   SHIFT_LEFT_1_BIAS, SHIFT_LEFT_2 (×4), SHIFT_RIGHT_1 (×½).
//! - Constants: the host packs a float colour with `(uint32_t)(f · 255)` (truncation:
//!   0.25 → 63, 0.1 → 25, 0.7 → 178), and each stage has its own C0/C1
//!   (`stage_constants`); the final combiner has its own pair (`constants`).
//! - No texture is bound: every TEXn reads the NV2A's unbound value (0, 0, 0, 1)
//!   ([`unbound_texture`]).
//! - The final combiner's G is ZERO inverted (alpha 1) on every left half-quad and full
//!   quad, and a register's alpha on the right half-quads of CombinerOps and
//!   AlphaFromBlue, which the captures show blended over the background
//!   (SRC_ALPHA, ONE_MINUS_SRC_ALPHA): those regions lie inside one checkerboard cell
//!   each (the board `DrawCheckerboardUnproject(0xFF333333, 0xFF444444)` draws; cell
//!   edges as the captures show them: columns every 20 px, rows at [`CHECKER_ROWS`]).
//! - Stages not set by a test keep their state from the test before; where that could
//!   reach a region (an alpha portion nobody set) the case writes nothing there, and
//!   only registers the regions do not read could differ.
//!
//! Patch rectangles are where the captures put the quads (640 × 480), inset by 2 px;
//! text printed over a quad is left out (Mux compares the strips above and below it).
//!
//! [`Chip::GeForce2`] predicts with the units' defaults (the spec's −½ and mux test);
//! [`Chip::Nv2a`] with the NV2A modes: `BiasConstant::HalfCode` and the combiner
//! control's mux select (`MuxSelect::Lsb` unless the test sets MSB). The NV2A-only
//! inputs the tests use (per-stage and final constants, blue-to-alpha, the final
//! combiner's add-invert flags, the unbound sampler) are the same under both: the
//! GeForce2 has no way to express them, and the comparison isolates the two modes
//! that differ.

use super::case::{Case, Chip, Prediction, Rect, Region, Suite};
use rtl_model::units::blend::{Blend, BlendEquation, BlendFactor};
use rtl_model::units::final_combiner::{
    FinalCombiner, FinalCombinerConfig, FinalInput, FinalVariable,
};
use rtl_model::units::register_combiner::{
    unbound_texture, Bias, BiasConstant, ComponentUsage, FragmentInputs, Mapping, MuxSelect,
    PortionConfig, Register, RegisterCombiner, RegisterCombinerConfig, Scale, VariableInput,
};
use rtl_model::{Counters, Quant, Unit};

pub const SUITE: Suite = Suite {
    name: "Combiner",
    source: "src/tests/combiner_tests.cpp",
    cases,
};

/// The register width of the NV2A's combiners as the captures need it: 9 bits (8-bit
/// colours load exactly, code c ↔ c/255).
const N: u32 = 9;

/// Rows of the checkerboard's cell edges (y of each cell's first row) in the captures
/// that draw it; columns are every 20 px. The cell at column 0, row 0 is 0x33.
pub const CHECKER_ROWS: [u32; 31] = [
    16, 31, 46, 61, 76, 91, 106, 121, 136, 151, 166, 181, 196, 211, 226, 241, 255, 270, 285, 300,
    315, 330, 345, 360, 375, 390, 405, 420, 435, 450, 465,
];
const CHECKER_COL: u32 = 20;
const CHECKER: [u32; 2] = [0x33, 0x44];

/// The host's float → byte packing (`TO_BGRA`: `(uint32_t)(f · 255.0f)`).
fn host_byte(f: f32) -> u32 {
    (f * 255.0f32) as u32
}

fn host_rgba(c: [f32; 4]) -> [u32; 4] {
    c.map(host_byte)
}

/// A byte colour as register codes (the combiners' own unorm load).
fn codes(c: [u32; 4]) -> [i32; 4] {
    let loader = RegisterCombiner::geforce();
    c.map(|u| loader.load_unorm(u, &mut Counters::default()))
}

fn var(r: Register, u: ComponentUsage) -> VariableInput {
    VariableInput::new(r, Mapping::UnsignedIdentity, u)
}

/// `OneInput()`: ZERO under UNSIGNED_INVERT.
fn one(u: ComponentUsage) -> VariableInput {
    VariableInput::new(Register::Zero, Mapping::UnsignedInvert, u)
}

fn zero(u: ComponentUsage) -> VariableInput {
    var(Register::Zero, u)
}

/// A portion that writes A · 1 to R0 (SPARE0): the test's "copy this input" stage.
fn into_r0(usage: ComponentUsage, a: VariableInput) -> PortionConfig {
    portion(
        usage,
        [a, one(usage), zero(usage), zero(usage)],
        [Some(Register::Spare0), None, None],
        Scale::None,
        Bias::None,
        false,
    )
}

/// A portion A·B → ab, C·D → cd, sum or mux → sum, with scale and bias.
fn portion(
    usage: ComponentUsage,
    vars: [VariableInput; 4],
    outs: [Option<Register>; 3],
    scale: Scale,
    bias: Bias,
    mux_sum: bool,
) -> PortionConfig {
    let [a, b, c, d] = vars;
    PortionConfig {
        a,
        b,
        c,
        d,
        ab_output: outs[0],
        cd_output: outs[1],
        sum_output: outs[2],
        scale,
        bias,
        mux_sum,
        ..PortionConfig::discard(usage)
    }
}

/// A portion that writes nothing.
fn discard(usage: ComponentUsage) -> PortionConfig {
    PortionConfig::discard(usage)
}

/// The modes the suite predicts with: the chip's, and (for the calibration of the
/// undocumented widths) the general combiners' guard bits and the rounding of both
/// combiner units, and optionally a bias constant other than the chip's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Modes {
    pub chip: Chip,
    pub guard_bits: u32,
    pub rounding: Quant,
    pub bias_constant: Option<BiasConstant>,
}

impl Modes {
    /// The units' defaults (G = 0, round half up) in `chip`'s modes.
    pub fn of(chip: Chip) -> Modes {
        Modes {
            chip,
            guard_bits: 0,
            rounding: Quant::Rnd,
            bias_constant: None,
        }
    }
}

/// One general stage with its own C0/C1 (host byte colours), in `m`'s modes;
/// `mux_msb` is the test's combiner-control MUX_SELECT.
fn stage(
    m: Modes,
    rgb: PortionConfig,
    alpha: PortionConfig,
    c0: [u32; 4],
    c1: [u32; 4],
    mux_msb: bool,
) -> RegisterCombinerConfig {
    let base = RegisterCombinerConfig {
        internal_bits: N,
        guard_bits: m.guard_bits,
        rounding: m.rounding,
        rgb,
        alpha,
        stage_constants: Some([codes(c0), codes(c1)]),
        ..RegisterCombinerConfig::geforce()
    };
    // The chip's bias constant and reset mux select; a test that sets MUX_SELECT_MSB
    // overrides the latter (the GeForce2's is MSB already).
    let chip = m.chip.register_combiner(base);
    let chip = if mux_msb {
        RegisterCombinerConfig {
            mux_select: MuxSelect::Msb,
            ..chip
        }
    } else {
        chip
    };
    RegisterCombinerConfig {
        bias_constant: m.bias_constant.unwrap_or(chip.bias_constant),
        ..chip
    }
}

/// The final combiner: A … D (RGB), E, F, G, its own C0/C1, the add-invert and clamp
/// flags.
#[derive(Clone)]
struct Final {
    abcd: [FinalVariable; 4],
    ef: [FinalVariable; 2],
    g: FinalVariable,
    constants: [[u32; 4]; 2],
    invert_r0: bool,
    invert_v1: bool,
    clamp: bool,
}

fn freg(r: Register, u: ComponentUsage) -> FinalVariable {
    FinalVariable::register(r, u)
}

fn fzero() -> FinalVariable {
    freg(Register::Zero, ComponentUsage::Rgb)
}

/// G = ZERO inverted: alpha 1.
fn g_one() -> FinalVariable {
    FinalVariable::new(
        FinalInput::Register(Register::Zero),
        Mapping::UnsignedInvert,
        ComponentUsage::Alpha,
    )
}

impl Final {
    /// `SetFinalCombiner0Just(src)`: RGB = D = `d`; G as given.
    fn just(d: FinalVariable, g: FinalVariable) -> Final {
        Final {
            abcd: [fzero(), fzero(), fzero(), d],
            ef: [fzero(), fzero()],
            g,
            constants: [[0; 4]; 2],
            invert_r0: false,
            invert_v1: false,
            clamp: false,
        }
    }

    fn config(&self, rounding: Quant) -> FinalCombinerConfig {
        let [a, b, c, d] = self.abcd;
        FinalCombinerConfig {
            internal_bits: N,
            rounding,
            a,
            b,
            c,
            d,
            e: self.ef[0],
            f: self.ef[1],
            g: self.g,
            color_sum_clamp: self.clamp,
            specular_add_invert_r0: self.invert_r0,
            specular_add_invert_v1: self.invert_v1,
            constants: Some(self.constants.map(codes)),
            ..FinalCombinerConfig::geforce()
        }
    }
}

/// One fragment through the stages and the final combiner: RGBA bytes.
fn shade(m: Modes, stages: &[RegisterCombinerConfig], fin: &Final, diffuse: [u32; 4]) -> [u32; 4] {
    let mut ctr = Counters::default();
    let frag = FragmentInputs {
        primary_color: diffuse,
        secondary_color: [0; 4],
        texture: [unbound_texture(8); 4],
        constant_color0: [0; 4],
        constant_color1: [0; 4],
        fog: [0; 4],
    };
    let loader = RegisterCombiner::geforce();
    let mut file = loader.load_fragment(&frag, &mut ctr);
    for s in stages {
        let unit = s.build().expect("the suite's stages are valid configs");
        file = unit.kernel(&mut (), &file, &mut ctr);
    }
    let fin: FinalCombiner = fin
        .config(m.rounding)
        .build()
        .expect("the suite's final combiners are valid configs");
    fin.kernel(&mut (), &file, &mut ctr)
}

fn rgb(c: [u32; 4]) -> [u8; 3] {
    [c[0] as u8, c[1] as u8, c[2] as u8]
}

/// src over dst with SRC_ALPHA, ONE_MINUS_SRC_ALPHA, ADD through the `blend` unit (one
/// rounding, as the NV2A blends).
fn blend_over(src: [u32; 4], dst: [u32; 3]) -> [u8; 3] {
    let unit = Blend::with(
        BlendEquation::Add,
        BlendFactor::SrcAlpha,
        BlendFactor::OneMinusSrcAlpha,
    );
    rgb(unit.blend_pixel(&src, &[dst[0], dst[1], dst[2], 255]).0)
}

fn flat(name: &str, feature: &str, rect: Rect, c: [u8; 3]) -> Region {
    Region {
        name: name.to_string(),
        feature: feature.to_string(),
        rect: rect.inset(2),
        predicted: Prediction::Flat(c),
    }
}

/// The checkerboard cell rows and columns as (start, end) pairs.
fn cells(edges: &[u32], end: u32) -> Vec<(u32, u32)> {
    let mut v = Vec::new();
    let mut a = 0;
    for &e in edges.iter().chain(std::iter::once(&end)) {
        v.push((a, e));
        a = e;
    }
    v
}

/// A half-quad whose fragment `src` (alpha included) is blended over the checkerboard:
/// per background colour, the largest part of the half inside one cell (2 px from the
/// cell's edges), whatever the predicted alpha (the regions do not depend on it).
fn blended(name: &str, feature: &str, rect: Rect, src: [u32; 4]) -> Vec<Region> {
    let r = rect.inset(2);
    let cols: Vec<u32> = (1..32).map(|k| k * CHECKER_COL).collect();
    let mut best: [Option<Rect>; 2] = [None, None];
    for (cy, &(y0, y1)) in cells(&CHECKER_ROWS, 480).iter().enumerate() {
        for (cx, &(x0, x1)) in cells(&cols, 640).iter().enumerate() {
            let (x0, x1) = ((x0 + 2).max(r.x), (x1.saturating_sub(2)).min(r.x + r.w));
            let (y0, y1) = ((y0 + 2).max(r.y), (y1.saturating_sub(2)).min(r.y + r.h));
            if x1 <= x0 || y1 <= y0 {
                continue;
            }
            let c = Rect::new(x0, y0, x1 - x0, y1 - y0);
            let k = (cx + cy) % 2;
            if best[k].is_none_or(|b| b.pixels() < c.pixels()) {
                best[k] = Some(c);
            }
        }
    }
    let mut out = Vec::new();
    for (k, b) in best.iter().enumerate() {
        if let Some(c) = b {
            let dst = [CHECKER[k]; 3];
            let shade = if k == 0 { "dark" } else { "light" };
            out.push(Region {
                name: format!("{name}/over_{shade}"),
                feature: feature.to_string(),
                rect: *c,
                predicted: Prediction::Flat(blend_over(src, dst)),
            });
        }
    }
    out
}

use ComponentUsage::{Alpha, Blue, Rgb};

/// CombinerOps: stage 0 R0 = op(C0 · 1) on both portions (the alpha portion reads C0's
/// blue), C0 = (0.1, 0.25, 1, 0.5); left half RGB opaque, right half blended by R0.a.
fn combiner_ops(m: Modes) -> Case {
    let c0 = host_rgba([0.1, 0.25, 1.0, 0.5]);
    let ops = [
        ("IDENTITY", Scale::None, Bias::None, 200, 74),
        ("BIAS", Scale::None, Bias::ByNegativeOneHalf, 200, 146),
        ("SHIFT_LEFT_1", Scale::ByTwo, Bias::None, 200, 218),
        (
            "SHIFT_LEFT_1_BIAS",
            Scale::ByTwo,
            Bias::ByNegativeOneHalf,
            200,
            290,
        ),
        ("SHIFT_LEFT_2", Scale::ByFour, Bias::None, 200, 362),
        ("SHIFT_RIGHT_1", Scale::ByOneHalf, Bias::None, 500, 74),
    ];
    let mut regions = Vec::new();
    for (name, scale, bias, x, y) in ops {
        let rgb_p = portion(
            Rgb,
            [
                var(Register::ConstantColor0, Rgb),
                one(Rgb),
                zero(Rgb),
                zero(Rgb),
            ],
            [Some(Register::Spare0), None, None],
            scale,
            bias,
            false,
        );
        let alpha_p = portion(
            Alpha,
            [
                var(Register::ConstantColor0, Blue),
                one(Alpha),
                zero(Alpha),
                zero(Alpha),
            ],
            [Some(Register::Spare0), None, None],
            scale,
            bias,
            false,
        );
        let st = [stage(m, rgb_p, alpha_p, c0, [0; 4], false)];
        let feature = format!("combiner output {name}");
        let alpha_feature = format!("{feature} (alpha, blended)");
        regions.extend(r0_halves(
            m,
            &st,
            [0; 4],
            (x, y),
            name,
            &feature,
            &alpha_feature,
        ));
    }
    Case {
        image: "CombinerOps.png".into(),
        regions,
    }
}

/// A 64 × 64 quad whose stages write R0: its left half (32 px) shows R0's RGB, opaque;
/// its right half shows R0's RGB blended over the checkerboard by R0's alpha.
fn r0_halves(
    m: Modes,
    stages: &[RegisterCombinerConfig],
    diffuse: [u32; 4],
    (x, y): (u32, u32),
    name: &str,
    feature: &str,
    alpha_feature: &str,
) -> Vec<Region> {
    let r0 = freg(Register::Spare0, Rgb);
    let left = shade(m, stages, &Final::just(r0, g_one()), diffuse);
    let right = shade(
        m,
        stages,
        &Final::just(r0, freg(Register::Spare0, Alpha)),
        diffuse,
    );
    let mut regions = vec![flat(
        &format!("{name}/rgb"),
        feature,
        Rect::new(x, y, 32, 64),
        rgb(left),
    )];
    regions.extend(blended(
        &format!("{name}/alpha"),
        alpha_feature,
        Rect::new(x + 32, y, 32, 64),
        right,
    ));
    regions
}

/// AlphaFromBlue: stage 0 A·B (row "AB") or C·D (row "CD") of C0 = (0.25, 0.5, b, 0)
/// and the diffuse (1, 1, 1, 0) to R0 with that output's blue-to-alpha flag; the
/// alpha portion writes nothing. Right halves blended by R0.a.
fn alpha_from_blue(m: Modes) -> Case {
    let mut regions = Vec::new();
    let diffuse = host_rgba([1.0, 1.0, 1.0, 0.0]);
    for (row, y, ab) in [("AB", 192, true), ("CD", 264, false)] {
        for (k, b) in [1.0f32, 0.75, 0.5, 0.25, 0.0].into_iter().enumerate() {
            let x = 128 + 72 * k as u32;
            let c0 = host_rgba([0.25, 0.5, b, 0.0]);
            let vars = [
                var(Register::ConstantColor0, Rgb),
                var(Register::PrimaryColor, Rgb),
                var(Register::ConstantColor0, Rgb),
                var(Register::PrimaryColor, Rgb),
            ];
            let outs = if ab {
                [Some(Register::Spare0), None, None]
            } else {
                [None, Some(Register::Spare0), None]
            };
            let rgb_p = portion(Rgb, vars, outs, Scale::None, Bias::None, false);
            let st = [RegisterCombinerConfig {
                ab_blue_to_alpha: ab,
                cd_blue_to_alpha: !ab,
                ..stage(m, rgb_p, discard(Alpha), c0, [0; 4], false)
            }];
            let feature = format!("blue to alpha {row}");
            let name = format!("{row}/blue_{}", host_byte(b));
            let alpha_feature = format!("{feature} (blended)");
            regions.extend(r0_halves(
                m,
                &st,
                diffuse,
                (x, y),
                &name,
                &feature,
                &alpha_feature,
            ));
        }
    }
    Case {
        image: "AlphaFromBlue.png".into(),
        regions,
    }
}

/// The 2 × 4 grid of the vertex-buffer quads (Mux, Independence, Flags), as the
/// captures place them.
fn grid(k: usize) -> Rect {
    let x = [121, 223, 324, 425][k % 4];
    let w = if k % 4 == 3 { 95 } else { 94 };
    let y = if k < 4 { 114 } else { 225 };
    Rect::new(x, y, w, 82)
}

/// Mux: stage 0 R0 = 1, R0.a = C0.a (0x82, 0x81, 0x00); stage 1 V0 = mux(C0 = red,
/// C1 = blue) by R0.a, with the combiner control's MUX_SELECT LSB or MSB.
fn mux(m: Modes) -> Case {
    let mut regions = Vec::new();
    let draws = [
        (0x82u32, false),
        (0x82, true),
        (0x81, false),
        (0x81, true),
        (0, false),
        (0, true),
    ];
    for (k, (a, msb)) in draws.into_iter().enumerate() {
        let s0 = stage(
            m,
            into_r0(Rgb, one(Rgb)),
            into_r0(Alpha, var(Register::ConstantColor0, Alpha)),
            [0, 0, 0, a],
            [0; 4],
            msb,
        );
        let s1 = stage(
            m,
            portion(
                Rgb,
                [
                    var(Register::ConstantColor0, Rgb),
                    one(Rgb),
                    var(Register::ConstantColor1, Rgb),
                    one(Rgb),
                ],
                [None, None, Some(Register::PrimaryColor)],
                Scale::None,
                Bias::None,
                true,
            ),
            portion(
                Alpha,
                [one(Alpha), one(Alpha), zero(Alpha), zero(Alpha)],
                [Some(Register::PrimaryColor), None, None],
                Scale::None,
                Bias::None,
                false,
            ),
            host_rgba([1.0, 0.0, 0.0, 1.0]),
            host_rgba([0.0, 0.0, 1.0, 1.0]),
            msb,
        );
        let fin = Final::just(
            freg(Register::PrimaryColor, Rgb),
            freg(Register::PrimaryColor, Alpha),
        );
        let c = rgb(shade(m, &[s0, s1], &fin, [255; 4]));
        let q = grid(k);
        let sel = if msb { "MSB" } else { "LSB" };
        let feature = format!("mux {sel}");
        // The label is printed across the quad's middle: compare above and below it.
        let (top_h, gap) = if k < 4 { (36, 16) } else { (25, 16) };
        let top = Rect::new(q.x, q.y, q.w, top_h);
        let bottom = Rect::new(q.x, q.y + top_h + gap, q.w, q.h - top_h - gap);
        let name = format!("{sel}_0x{a:02x}");
        regions.push(flat(&format!("{name}/above_label"), &feature, top, c));
        regions.push(flat(&format!("{name}/below_label"), &feature, bottom, c));
    }
    Case {
        image: "Mux.png".into(),
        regions,
    }
}

/// Independence: a stage's outputs are written after all its reads (R1 gets R0's old
/// value), and blue-to-alpha along a three-stage chain.
fn independence(m: Modes) -> Case {
    let c0_stage = |c0: [f32; 4]| host_rgba(c0);
    let r0_only = |m, c0| {
        stage(
            m,
            into_r0(Rgb, var(Register::ConstantColor0, Rgb)),
            discard(Alpha),
            c0,
            [0; 4],
            false,
        )
    };
    let swap = |m, c0, blue: bool| RegisterCombinerConfig {
        ab_blue_to_alpha: blue,
        cd_blue_to_alpha: blue,
        ..stage(
            m,
            portion(
                Rgb,
                [
                    var(Register::ConstantColor0, Rgb),
                    one(Rgb),
                    var(Register::Spare0, Rgb),
                    one(Rgb),
                ],
                [Some(Register::Spare0), Some(Register::Spare1), None],
                Scale::None,
                Bias::None,
                false,
            ),
            discard(Alpha),
            c0,
            [0; 4],
            false,
        )
    };
    let green = [
        r0_only(m, c0_stage([0.0, 1.0, 0.0, 1.0])),
        swap(m, c0_stage([1.0, 0.0, 0.0, 1.0]), false),
    ];
    let grey = [
        r0_only(m, c0_stage([0.0, 0.0, 0.25, 0.0])),
        swap(m, c0_stage([0.0, 0.0, 0.75, 0.0]), true),
        stage(
            m,
            portion(
                Rgb,
                [
                    var(Register::Spare0, Alpha),
                    one(Rgb),
                    var(Register::Spare1, Alpha),
                    one(Rgb),
                ],
                [Some(Register::Spare0), Some(Register::Spare1), None],
                Scale::None,
                Bias::None,
                false,
            ),
            discard(Alpha),
            [0; 4],
            [0; 4],
            false,
        ),
    ];
    let r = |reg| Final::just(freg(reg, Rgb), g_one());
    let regions = vec![
        flat(
            "green_from_r0_stage0",
            "stage outputs after reads",
            grid(0),
            rgb(shade(m, &green, &r(Register::Spare1), [0; 4])),
        ),
        flat(
            "dgrey_from_r0_stage1_alpha",
            "blue to alpha AB/CD (stage chain)",
            grid(2),
            rgb(shade(m, &grey, &r(Register::Spare1), [0; 4])),
        ),
        flat(
            "lgrey_from_r0_stage1",
            "blue to alpha AB/CD (stage chain)",
            grid(4),
            rgb(shade(m, &grey, &r(Register::Spare0), [0; 4])),
        ),
    ];
    Case {
        image: "Independence.png".into(),
        regions,
    }
}

/// ColorAlphaIndependence: a green quad (the diffuse), then a blue quad whose alpha is
/// R1.a = R0's blue as stage 1 reads it (0: stage 1 writes R0's RGB after its reads),
/// blended over the green: the green stays.
fn color_alpha_independence(m: Modes) -> Case {
    let diffuse = host_rgba([0.1, 1.0, 0.1, 1.0]);
    let green = shade(
        m,
        &[],
        &Final::just(freg(Register::PrimaryColor, Rgb), g_one()),
        diffuse,
    );
    let s0 = stage(
        m,
        into_r0(Rgb, var(Register::ConstantColor0, Rgb)),
        discard(Alpha),
        [0; 4],
        [0; 4],
        false,
    );
    let s1 = stage(
        m,
        into_r0(Rgb, var(Register::ConstantColor0, Rgb)),
        portion(
            Alpha,
            [
                var(Register::Spare0, Blue),
                one(Alpha),
                zero(Alpha),
                zero(Alpha),
            ],
            [Some(Register::Spare1), None, None],
            Scale::None,
            Bias::None,
            false,
        ),
        host_rgba([0.0, 0.0, 1.0, 1.0]),
        [0; 4],
        false,
    );
    let blue = shade(
        m,
        &[s0, s1],
        &Final::just(freg(Register::Spare0, Rgb), freg(Register::Spare1, Alpha)),
        diffuse,
    );
    let c = blend_over(blue, [green[0], green[1], green[2]]);
    Case {
        image: "ColorAlphaIndependence.png".into(),
        regions: vec![flat(
            "green_quad",
            "colour/alpha portions independent (blended)",
            Rect::new(93, 96, 455, 289),
            c,
        )],
    }
}

/// Flags' three stage-0 setups: V1 and R0 both 1; R0 = C0 = 0.75 (V1 = 0); V1 = C0 =
/// 0.75 (R0 = 0).
fn flags_stages(m: Modes) -> [[RegisterCombinerConfig; 1]; 3] {
    let write = |ab: Register, cd: Register, vars, c0| {
        stage(
            m,
            portion(
                Rgb,
                vars,
                [Some(ab), Some(cd), None],
                Scale::None,
                Bias::None,
                false,
            ),
            discard(Alpha),
            c0,
            [0; 4],
            false,
        )
    };
    let ones = [one(Rgb), one(Rgb), one(Rgb), one(Rgb)];
    let c_only = [
        zero(Rgb),
        zero(Rgb),
        var(Register::ConstantColor0, Rgb),
        one(Rgb),
    ];
    let c75 = host_rgba([0.75; 4]);
    let both_one = [write(
        Register::SecondaryColor,
        Register::Spare0,
        ones,
        [0; 4],
    )];
    let r0_75 = [write(
        Register::SecondaryColor,
        Register::Spare0,
        c_only,
        c75,
    )];
    let v1_75 = [write(
        Register::Spare0,
        Register::SecondaryColor,
        c_only,
        c75,
    )];
    [both_one, r0_75, v1_75]
}

/// Flags: SPARE0_PLUS_SECONDARY_COLOR (V1 + R0) unclamped and clamped, and with R0 or
/// V1 inverted.
fn flags(m: Modes) -> Case {
    let spec_r0 = FinalVariable::new(
        FinalInput::Spare0PlusSecondaryColor,
        Mapping::UnsignedIdentity,
        Rgb,
    );
    let [both_one, r0_75, v1_75] = flags_stages(m);
    let half = Final {
        abcd: [
            freg(Register::ConstantColor0, Rgb),
            spec_r0,
            fzero(),
            fzero(),
        ],
        ef: [fzero(), fzero()],
        g: g_one(),
        constants: [host_rgba([0.5; 4]), [0; 4]],
        invert_r0: false,
        invert_v1: false,
        clamp: false,
    };
    let a_one = FinalVariable::new(
        FinalInput::Register(Register::Zero),
        Mapping::UnsignedInvert,
        Rgb,
    );
    let just_b = |invert_r0, invert_v1| Final {
        abcd: [a_one, spec_r0, fzero(), fzero()],
        invert_r0,
        invert_v1,
        ..Final::just(fzero(), g_one())
    };
    let draws: [(&str, &str, &[RegisterCombinerConfig], Final); 6] = [
        (
            "uncapped",
            "final V1 + R0 unclamped",
            &both_one,
            half.clone(),
        ),
        (
            "capped",
            "final V1 + R0 SPECULAR_CLAMP",
            &both_one,
            Final {
                clamp: true,
                ..half.clone()
            },
        ),
        ("normal_r0", "final V1 + R0", &r0_75, just_b(false, false)),
        (
            "inverted_r0",
            "final add-invert R0",
            &r0_75,
            just_b(true, false),
        ),
        ("v1", "final V1 + R0", &v1_75, just_b(false, false)),
        (
            "inverted_v1",
            "final add-invert V1",
            &v1_75,
            just_b(false, true),
        ),
    ];
    let regions = draws
        .into_iter()
        .enumerate()
        .map(|(k, (name, feature, st, fin))| {
            flat(name, feature, grid(k), rgb(shade(m, st, &fin, [0; 4])))
        })
        .collect();
    Case {
        image: "Flags.png".into(),
        regions,
    }
}

/// SpecialInputs: E_TIMES_F of the final combiner's own C0 · C1; SPARE0 + SECONDARY
/// with no flag, R0 inverted, V1 inverted.
fn special_inputs(m: Modes) -> Case {
    let fc = [host_rgba([1.0, 0.75, 0.5, 1.0]), host_rgba([0.5; 4])];
    let ef = Final {
        abcd: [
            fzero(),
            fzero(),
            fzero(),
            FinalVariable::new(FinalInput::ETimesF, Mapping::UnsignedIdentity, Rgb),
        ],
        ef: [
            freg(Register::ConstantColor0, Rgb),
            freg(Register::ConstantColor1, Rgb),
        ],
        g: g_one(),
        constants: fc,
        invert_r0: false,
        invert_v1: false,
        clamp: false,
    };
    let s0 = [stage(
        m,
        portion(
            Rgb,
            [
                var(Register::ConstantColor0, Rgb),
                one(Rgb),
                var(Register::ConstantColor1, Rgb),
                one(Rgb),
            ],
            [Some(Register::Spare0), Some(Register::SecondaryColor), None],
            Scale::None,
            Bias::None,
            false,
        ),
        discard(Alpha),
        host_rgba([0.25, 0.5, 0.75, 0.0]),
        host_rgba([0.70, 0.5, 0.15, 0.5]),
        false,
    )];
    let spec = |invert_r0, invert_v1| Final {
        abcd: [
            fzero(),
            fzero(),
            fzero(),
            FinalVariable::new(
                FinalInput::Spare0PlusSecondaryColor,
                Mapping::UnsignedIdentity,
                Rgb,
            ),
        ],
        invert_r0,
        invert_v1,
        ..ef.clone()
    };
    let regions = vec![
        flat(
            "ef_prod",
            "final E_TIMES_F",
            Rect::new(200, 74, 64, 64),
            rgb(shade(m, &[], &ef, [0; 4])),
        ),
        flat(
            "spec_r0_sum",
            "final V1 + R0",
            Rect::new(200, 170, 64, 64),
            rgb(shade(m, &s0, &spec(false, false), [0; 4])),
        ),
        flat(
            "inv_r0",
            "final add-invert R0",
            Rect::new(500, 170, 64, 64),
            rgb(shade(m, &s0, &spec(true, false), [0; 4])),
        ),
        flat(
            "inv_spec",
            "final add-invert V1",
            Rect::new(200, 242, 64, 64),
            rgb(shade(m, &s0, &spec(false, true), [0; 4])),
        ),
    ];
    Case {
        image: "SpecialInputs.png".into(),
        regions,
    }
}

/// UnboundTexSampler: the final combiner's D = TEXn (black) and TEXn inverted (white).
fn unbound_tex_sampler(m: Modes) -> Case {
    let tex = [
        Register::Texture0,
        Register::Texture1,
        Register::Texture2,
        Register::Texture3,
    ];
    let mut regions = Vec::new();
    for (k, t) in tex.into_iter().enumerate() {
        let y = 96 + 72 * k as u32;
        for (x, map, suffix) in [
            (252, Mapping::UnsignedIdentity, ""),
            (324, Mapping::UnsignedInvert, "_inverted"),
        ] {
            let fin = Final::just(
                FinalVariable::new(FinalInput::Register(t), map, Rgb),
                g_one(),
            );
            regions.push(flat(
                &format!("tex{k}{suffix}"),
                "unbound texture sampler",
                Rect::new(x, y, 64, 64),
                rgb(shade(m, &[], &fin, [0; 4])),
            ));
        }
    }
    Case {
        image: "UnboundTexSampler.png".into(),
        regions,
    }
}

/// Every case of the suite, predicted in `chip`'s modes (sorted by image name).
pub fn cases(chip: Chip) -> Vec<Case> {
    cases_in(Modes::of(chip))
}

/// Every case, predicted in the modes `m` gives (the calibration sweeps these).
pub fn cases_in(m: Modes) -> Vec<Case> {
    vec![
        alpha_from_blue(m),
        color_alpha_independence(m),
        combiner_ops(m),
        flags(m),
        independence(m),
        mux(m),
        special_inputs(m),
        unbound_tex_sampler(m),
    ]
}
