//! polygon_interpolator's vectors: random small triangles and parallelograms are set
//! up by the model (`setup_triangle`, `setup_parallelogram`), each walked by its
//! serpentine moves (`PolySetup::moves`) through the kernel, primitive after primitive,
//! until `count` moves. A transaction is `{load, move}`: `load` is set on each
//! primitive's first move (Hold) and makes the Verilog take that primitive's start
//! state (the setup's `PolyState`) from its read ports, one table entry per primitive
//! in order. The setup itself (plane equations, divisions) is the model's: the Verilog
//! is the walker. Implemented: 4 attributes, WRAP accumulators, RND output rounding.
//!
//! The barycentric mode (`barycentric: Some(..)`, the Verilog's `BARY = 1`) has its
//! own sets ([`polygon_interpolator_mode_sets`]): several weight widths, strict and
//! floor, at the default and narrow widths. A triangle's mode registers (`BaryRegs`)
//! are more read ports (bary_ctl: {en, sel2, bias2, bias0}, bary_den, and per
//! attribute bary_base, bary_d0, bary_d2); a parallelogram's entry has en = 0.

use super::vector_set::{Field, RomPort, RtlConfig, VectorSet};
use crate::registry::unit_entry::seeded;
use rand::Rng;
use rtl_model::fixed_point::{Format, Overflow, Quant};
use rtl_model::units::polygon_interpolator::{
    Barycentric, Move, PolyState, PolygonInterpolator, PolygonInterpolatorConfig, Vertex, EDGES,
};
use rtl_model::{Counters, Unit};

/// Attributes the Verilog has ports for.
const ATTRS: usize = 4;

/// The configuration built at `config`: the default (4 attributes s16.16, positions
/// s13.4, accumulators s20.24, output s16.8), or narrow (positions s5.1 — ±16 px —,
/// unsigned attributes u4.2, accumulators s6.6, output u4.1).
pub fn config_of(config: RtlConfig) -> PolygonInterpolatorConfig {
    match config {
        RtlConfig::Default => PolygonInterpolatorConfig::default(),
        RtlConfig::Narrow => PolygonInterpolatorConfig {
            attrs: ATTRS as u32,
            subpixel_bits: 1,
            coord_int_bits: 5,
            attr_fmt: Format {
                int_bits: 4,
                frac_bits: 2,
                signed: false,
            },
            acc_int_bits: 6,
            acc_frac_bits: 6,
            acc_overflow: Overflow::Wrap,
            out_int_bits: 4,
            out_frac_bits: 1,
            out_quant: Quant::Rnd,
            barycentric: None,
        },
    }
}

fn mask(v: i64, w: u32) -> u64 {
    (v as u64) & (u64::MAX >> (64 - w))
}

pub(super) fn polygon_interpolator_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    vectors_at(config_of(config), config, count, seed)
}

/// The barycentric mode's sets, each its own tag: at the default widths w = 8 strict
/// (the NV2A's), w = 8 floor, w = 16 strict and w = 1 floor; at the narrow widths
/// w = 1 strict, w = 3 floor, w = 5 strict and w = 12 floor, and w = 1 floor with 4
/// output fraction bits (more than the attributes' 2 + w: the rounding shifts left).
/// Triangles of both windings and parallelograms (which keep their planes), as in the
/// configurations' sets.
pub fn polygon_interpolator_mode_sets(count: usize, seed: u64) -> Result<Vec<VectorSet>, String> {
    let modes = [
        (RtlConfig::Default, 8, true, None),
        (RtlConfig::Default, 8, false, None),
        (RtlConfig::Default, 16, true, None),
        (RtlConfig::Default, 1, false, None),
        (RtlConfig::Narrow, 1, true, None),
        (RtlConfig::Narrow, 3, false, None),
        (RtlConfig::Narrow, 5, true, None),
        (RtlConfig::Narrow, 12, false, None),
        (RtlConfig::Narrow, 1, false, Some(4)),
    ];
    modes
        .into_iter()
        .map(|(config, w, strict, out_frac)| {
            let b = Barycentric {
                weight_bits: w,
                strict,
            };
            let mut v = mode_vectors_at(b, config, out_frac, count, seed)?;
            let of = out_frac.map_or(String::new(), |f| format!("_of{f}"));
            let kind = if strict { "strict" } else { "floor" };
            v.variant = Some(format!("bary_w{w}_{kind}{of}"));
            Ok(v)
        })
        .collect()
}

/// The vectors of the barycentric mode `b` at the widths of `config` (no variant tag).
pub fn polygon_interpolator_mode_vectors(
    b: Barycentric,
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    mode_vectors_at(b, config, None, count, seed)
}

fn mode_vectors_at(
    b: Barycentric,
    config: RtlConfig,
    out_frac: Option<u32>,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let base = config_of(config);
    let cfg = PolygonInterpolatorConfig {
        barycentric: Some(b),
        out_frac_bits: out_frac.unwrap_or(base.out_frac_bits),
        ..base
    };
    vectors_at(cfg, config, count, seed)
}

fn vectors_at(
    cfg: PolygonInterpolatorConfig,
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let u = cfg.build().map_err(|e| e.to_string())?;
    let c = cfg.coord_int_bits;
    let ew = u.edge_bits();
    let walked = walk_primitives(&u, &cfg, count, seed);
    // Tables: 2^PB primitives (one spare: the address runs one ahead of the loads).
    let pb = (64 - (walked.starts.len() as u64).leading_zeros()).max(1);
    let table = PrimTable {
        starts: &walked.starts,
        n: 1usize << pb,
    };
    let mut roms = state_roms(&table, c, ew, cfg.acc_int_bits + cfg.acc_frac_bits);
    if cfg.barycentric.is_some() {
        roms.extend(barycentric_roms(&table, ew, cfg.attr_fmt.width()));
    }
    let t = u.timing();
    let timed: Vec<(PolyState, &[Move])> = walked
        .starts
        .iter()
        .cloned()
        .zip(walked.walks.iter().map(Vec::as_slice))
        .collect();
    let model_batch_secs = super::vector_set::time_batch_walks(&u, &timed);
    Ok(VectorSet {
        unit: u.name(),
        config,
        latency: t.latency,
        ii: t.ii,
        params: vec![
            ("COORD_INT_BITS", c as u64),
            ("EDGE_BITS", ew as u64),
            ("ACC_INT_BITS", cfg.acc_int_bits as u64),
            ("ACC_FRAC_BITS", cfg.acc_frac_bits as u64),
            ("OUT_INT_BITS", cfg.out_int_bits as u64),
            ("OUT_FRAC_BITS", cfg.out_frac_bits as u64),
            ("OUT_SIGNED", u64::from(cfg.attr_fmt.signed)),
            ("PRIM_BITS", pb as u64),
            ("BARY", u64::from(cfg.barycentric.is_some())),
            ("W", cfg.barycentric.map_or(8, |b| b.weight_bits) as u64),
            ("STRICT", cfg.barycentric.map_or(1, |b| u64::from(b.strict))),
            ("ATTR_INT_BITS", cfg.attr_fmt.int_bits as u64),
            ("ATTR_FRAC_BITS", cfg.attr_fmt.frac_bits as u64),
        ],
        in_fields: vec![
            Field {
                name: "load",
                width: 1,
            },
            Field {
                name: "move",
                width: 2,
            },
        ],
        out_fields: walked.out_fields,
        exhaustive: false,
        stateless: false,
        model_batch_secs,
        stimulus: walked.stimulus,
        expected: walked.expected,
        gates_model: u.cost().gates_nand2(),
        roms,
        rams: Vec::new(),
        variant: None,
    })
}

/// Random small primitives walked through the kernel: their start states, each one's
/// moves (for timing the batch kernel, `units --rtl-speed`), and the packed stimulus
/// and expected words.
struct Walked {
    starts: Vec<PolyState>,
    walks: Vec<Vec<Move>>,
    stimulus: Vec<String>,
    expected: Vec<String>,
    out_fields: Vec<Field>,
}

fn walk_primitives(
    u: &PolygonInterpolator,
    cfg: &PolygonInterpolatorConfig,
    count: usize,
    seed: u64,
) -> Walked {
    let (c, s) = (cfg.coord_int_bits, cfg.subpixel_bits);
    let mut rng = seeded(seed);
    let mut ctr = Counters::default();
    // Primitive centres keep a margin from the position range; sizes up to `span` px.
    let half = 1i64 << (c - 1);
    let span: i64 = if c > 8 { 24 } else { 6 };
    let sub = 1i64 << s;
    let aw_attr = cfg.attr_fmt.width();
    let mut w = Walked {
        starts: Vec::new(),
        walks: Vec::new(),
        stimulus: Vec::with_capacity(count),
        expected: Vec::with_capacity(count),
        out_fields: Vec::new(),
    };
    while w.stimulus.len() < count {
        let cx = rng.random_range(-half + span..half - span) * sub;
        let cy = rng.random_range(-half + span..half - span) * sub;
        let mut vert = || {
            let mut attrs = [0i64; 16];
            for a in attrs.iter_mut().take(ATTRS) {
                *a = rng.random_range(0..1i64 << aw_attr);
            }
            Vertex {
                x: cx + rng.random_range(-span * sub / 2..=span * sub / 2),
                y: cy + rng.random_range(-span * sub / 2..=span * sub / 2),
                attrs,
            }
        };
        let v = [vert(), vert(), vert()];
        let setup = if rng.random_range(0..4) == 0 {
            match u.setup_parallelogram(&v, &mut ctr) {
                Ok(p) => p,
                Err(_) => continue,
            }
        } else {
            u.setup_triangle(&v, &mut ctr)
        };
        let moves = setup.moves();
        if moves.is_empty() {
            continue;
        }
        let mut st = setup.state.clone();
        w.starts.push(setup.state);
        w.walks.push(Vec::new());
        for (i, mv) in moves.iter().enumerate() {
            if w.stimulus.len() == count {
                break;
            }
            let load = u64::from(i == 0);
            debug_assert!(i > 0 || *mv == Move::Hold);
            w.stimulus.push(format!("{:x}", (load << 2) | mv.code()));
            if let Some(walk) = w.walks.last_mut() {
                walk.push(*mv);
            }
            let o = u.kernel(&mut st, mv, &mut ctr);
            let mut sig = u.out_signals(&o);
            // The Verilog's port for `inside` is `is_inside` (a SystemVerilog keyword).
            sig[2].name = "is_inside";
            if w.out_fields.is_empty() {
                w.out_fields = super::vector_set::fields(&sig);
            }
            w.expected.push(super::pack_hex(&sig));
        }
    }
    w
}

/// The primitives' start states as ROM words: `n` slots (a power of two), `per` words
/// each.
struct PrimTable<'a> {
    starts: &'a [PolyState],
    n: usize,
}

impl PrimTable<'_> {
    fn words(&self, per: usize, f: impl Fn(&PolyState, usize) -> u64) -> Vec<u64> {
        let mut w = vec![0u64; self.n * per];
        for (p, st) in self.starts.iter().enumerate() {
            for i in 0..per {
                w[p * per + i] = f(st, i);
            }
        }
        w
    }
}

/// A ROM port of `ports` read ports of `width`-bit words.
fn port(name: &'static str, ports: usize, width: u32, words: Vec<u64>) -> RomPort {
    RomPort {
        name,
        ports: ports as u32,
        width,
        words,
    }
}

/// The walker's registers: position (c bits), edge functions and their steps (ew),
/// attribute accumulators and gradients (aw).
fn state_roms(t: &PrimTable, c: u32, ew: u32, aw: u32) -> Vec<RomPort> {
    vec![
        port(
            "pos",
            2,
            c,
            t.words(2, |st, i| mask(if i == 0 { st.x } else { st.y }, c)),
        ),
        port(
            "ef",
            EDGES,
            ew,
            t.words(EDGES, |st, i| mask(st.edge[i], ew)),
        ),
        port(
            "ef_dx",
            EDGES,
            ew,
            t.words(EDGES, |st, i| mask(st.edge_dx[i], ew)),
        ),
        port(
            "ef_dy",
            EDGES,
            ew,
            t.words(EDGES, |st, i| mask(st.edge_dy[i], ew)),
        ),
        port(
            "acc",
            ATTRS,
            aw,
            t.words(ATTRS, |st, i| mask(st.acc[i], aw)),
        ),
        port(
            "grad_x",
            ATTRS,
            aw,
            t.words(ATTRS, |st, i| mask(st.grad_x[i], aw)),
        ),
        port(
            "grad_y",
            ATTRS,
            aw,
            t.words(ATTRS, |st, i| mask(st.grad_y[i], aw)),
        ),
    ]
}

/// The barycentric mode's per-triangle registers (attributes `at` bits wide): the
/// control word, the area, the base vertex's attributes and the two deltas.
fn barycentric_roms(t: &PrimTable, ew: u32, at: u32) -> Vec<RomPort> {
    let regs = |st: &PolyState| st.bary.unwrap_or_default();
    let ctl = |st: &PolyState| -> u64 {
        let r = regs(st);
        let en = u64::from(st.bary.is_some());
        // q0's edge is always edge 1; q2's is edge 0 or 2 (sel2) by the winding.
        debug_assert!(st.bary.is_none() || r.edge_of[0] == 1);
        let sel2 = u64::from(r.edge_of[1] == 2);
        (en << 3) | (sel2 << 2) | ((r.bias[1] as u64 & 1) << 1) | (r.bias[0] as u64 & 1)
    };
    vec![
        port("bary_ctl", 1, 4, t.words(1, |st, _| ctl(st))),
        port(
            "bary_den",
            1,
            ew,
            t.words(1, |st, _| mask(regs(st).denom, ew)),
        ),
        port(
            "bary_base",
            ATTRS,
            at,
            t.words(ATTRS, |st, i| mask(regs(st).base[i], at)),
        ),
        port(
            "bary_d0",
            ATTRS,
            at + 1,
            t.words(ATTRS, |st, i| mask(regs(st).delta[0][i], at + 1)),
        ),
        port(
            "bary_d2",
            ATTRS,
            at + 1,
            t.words(ATTRS, |st, i| mask(regs(st).delta[1][i], at + 1)),
        ),
    ]
}
