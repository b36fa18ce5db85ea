//! `optimize` over the clocked chip's architecture within a time budget: the
//! arguments checked up front (each error naming its argument), the chip's cost by
//! hand, and the search on a small Fig. 6(b): the best chip meets the budget, costs no
//! more than the start, no clocked step down from it is cheaper and still meets the
//! budget, and a fresh clocked frame of it takes the same cycles.

use glare_pipeline::chip::config::ChipConfig;
use glare_pipeline::chip::params::ChipParam;
use glare_pipeline::frame::run::render_timed;
use glare_pipeline::frame::timing::{TimingMode, TimingRequest};
use glare_pipeline::optimize::chip::{
    check_chip, chip_cost, ladder, parse_time_budget, search_chip, ChipEnd, ChipPlan, PipeGates,
    FIFO_ENTRY_BITS, MEMORY_REQUEST_BITS,
};
use glare_pipeline::optimize::cli::{check, OptimizeArgs};
use glare_pipeline::optimize::search::Objective;
use std::time::Instant;

mod common;

fn args(params: &str, budget: &[&str]) -> OptimizeArgs {
    OptimizeArgs {
        scene: "fig6".into(),
        budget: budget.iter().map(|b| b.to_string()).collect(),
        objective: "area".into(),
        params: Some(params.into()),
        out: std::env::temp_dir().join(format!("optimize-chip-{}", std::process::id())),
        image: Some("64x48".into()),
        max_evals: None,
        seconds: None,
        seed: 0,
        reference: "wide".into(),
        timing: None,
    }
}

#[test]
fn arguments_are_checked_up_front_naming_the_argument() {
    let ok = check_chip(&args("cache_kb,fifo_depth", &["seconds<=0.01"])).unwrap();
    assert_eq!(ok.params, vec![ChipParam::CacheKb, ChipParam::FifoDepth]);
    assert_eq!(ok.limit_seconds, 0.01);
    let err = |a: OptimizeArgs| check_chip(&a).err().expect("refused");
    let e = err(args("cache_kb", &["max<=1"]));
    assert!(e.starts_with("budget:") && e.contains("seconds<="), "{e}");
    let e = err(args("cache_kb", &[]));
    assert!(e.starts_with("budget:"), "{e}");
    let e = err(args("cache_kb,texel_bits", &["seconds<=1"]));
    assert!(e.starts_with("params:") && e.contains("texel_bits"), "{e}");
    let e = err(args("bandwidth_mbs", &["seconds<=1"]));
    assert!(
        e.starts_with("params:") && e.contains("sweep --param bandwidth_mbs"),
        "{e}"
    );
    let e = err(args("pipes,pipes", &["seconds<=1"]));
    assert!(e.starts_with("params:") && e.contains("twice"), "{e}");
    let mut a = args("pipes", &["seconds<=1"]);
    a.reference = "truth".into();
    assert!(err(a).starts_with("reference:"));
    let mut a = args("pipes", &["seconds<=1"]);
    a.scene = "glare-point".into();
    let e = err(a);
    assert!(
        e.starts_with("params:") && e.contains("glare ASIC") && e.contains("fig6"),
        "{e}"
    );
    for bad in ["seconds<=0", "seconds<=-1", "seconds<=x", "seconds=1"] {
        assert!(
            parse_time_budget(bad).unwrap_err().starts_with("budget:"),
            "{bad}"
        );
    }
    // A time budget on a search of bit widths is refused, naming it.
    let mut a = args("texel_bits", &["seconds<=1"]);
    a.params = Some("texel_bits".into());
    let e = check(&a).err().expect("refused");
    assert!(
        e.starts_with("budget:") && e.contains("architecture"),
        "{e}"
    );
}

#[test]
fn a_chips_cost_by_hand() {
    let c = ChipConfig::geforce2_gts();
    let g = PipeGates {
        other: 1000.0,
        texture_unit: 300.0,
    };
    let (gates, ram) = chip_cost(&c, g);
    // 4 pipes × (1000 + 2 texture units × 300).
    assert_eq!((c.pipes, c.tmus_per_pipe), (4, 2));
    assert_eq!(gates, 4.0 * (1000.0 + 2.0 * 300.0));
    // One shared 16 KiB cache, six FIFOs of 64 quads, a 16-request queue.
    assert!(c.texture_cache.shared);
    assert_eq!(c.texture_cache.size_bytes, 16 * 1024);
    let fifos = glare_pipeline::chip::clock::fifo_names(&c).len() as u64;
    assert_eq!(fifos, 6);
    assert_eq!(
        ram,
        16 * 1024 * 8
            + fifos * u64::from(c.fifo_depth) * FIFO_ENTRY_BITS
            + u64::from(c.memory.queue_depth) * MEMORY_REQUEST_BITS
    );
    // The ladders step in powers of two (the cache from none), the texture units by one.
    assert_eq!(ladder(ChipParam::Tmus), vec![1, 2, 3, 4]);
    assert_eq!(ladder(ChipParam::CacheKb)[..3], [0, 1, 2]);
    assert!(ladder(ChipParam::BandwidthMbs).is_empty());
}

fn plan(limit_seconds: f64) -> ChipPlan {
    let out = std::env::temp_dir().join(format!("optimize-chip-search-{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    ChipPlan {
        scene_arg: "fig6".into(),
        scene: common::small_shafts_scene("fig6"),
        params: vec![ChipParam::CacheKb, ChipParam::FifoDepth],
        limit_seconds,
        objective: Objective::Area,
        out,
        base: ChipConfig::geforce2_gts(),
        max_evals: Some(24),
        seconds: None,
        mode: glare_pipeline::frame::timing::TimingMode::Clocked,
    }
}

#[test]
fn the_search_finds_a_cheaper_chip_within_the_budget_and_it_verifies() {
    // The start's own time, with a tenth to spare: the start meets the budget, so the
    // search steps down.
    let probe = search_chip(
        &ChipPlan {
            max_evals: Some(1),
            ..plan(1.0)
        },
        Instant::now(),
    )
    .unwrap();
    assert_eq!(probe.points.len(), 1);
    assert_eq!(probe.end, ChipEnd::MaxEvals);
    let start = &probe.points[0];
    let p = plan(start.seconds * 1.1);
    let o = search_chip(&p, Instant::now()).unwrap();
    let b = &o.points[o.best.expect("the start meets the budget")];
    assert!(b.meets(p.limit_seconds));
    assert!(
        b.cost(p.objective) < o.points[0].cost(p.objective),
        "a tenth of slack buys a cheaper chip"
    );
    assert_eq!(o.points[0].cycles, start.cycles, "deterministic");
    assert_eq!(
        o.end,
        ChipEnd::Converged,
        "{} chips clocked",
        o.points.len()
    );
    {
        // No clocked chip one step down a ladder from the best is cheaper and meets it.
        for q in &o.points {
            let one_down = q
                .values
                .iter()
                .zip(&b.values)
                .filter(|(a, b)| a != b)
                .count()
                == 1
                && q.values.iter().zip(&b.values).all(|(a, b)| a <= b);
            if one_down {
                assert!(
                    !q.meets(p.limit_seconds) || q.cost(p.objective) >= b.cost(p.objective),
                    "{:?} beats the best {:?}",
                    q.values,
                    b.values
                );
            }
        }
    }
    // Every point's time is its chip's: a fresh clocked frame of the best.
    let req = TimingRequest {
        mode: TimingMode::Clocked,
        chip: None,
        window: None,
    };
    let (f, _) = render_timed(&p.scene, &req, Some(b.chip.clone()), None).unwrap();
    assert_eq!(f.timing.unwrap().cycles_total(), b.cycles);
    // A budget no chip can meet: no best.
    let none = search_chip(
        &ChipPlan {
            max_evals: Some(4),
            ..plan(start.seconds * 1e-3)
        },
        Instant::now(),
    )
    .unwrap();
    assert!(none.best.is_none());
}

#[test]
fn the_cli_writes_the_csv_the_plot_and_the_best_chip() {
    let mut a = args("cache_kb,fifo_depth", &["seconds<=1"]);
    a.image = Some("32x24".into());
    a.max_evals = Some(3);
    a.out = std::env::temp_dir().join(format!("optimize-chip-cli-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&a.out);
    glare_pipeline::optimize::chip::optimize_chip_cli(&a).unwrap();
    let csv = std::fs::read_to_string(a.out.join("pareto.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 3, "{csv}");
    assert!(
        csv.starts_with("index,round,config,clocked_seconds,cycles"),
        "{csv}"
    );
    let png = image::open(a.out.join("pareto.png")).unwrap();
    assert!(png.width() >= 640);
    let chip = std::fs::read_to_string(a.out.join("best_chip.toml")).unwrap();
    assert!(chip.starts_with("# optimize --scene fig6"), "{chip}");
    assert!(
        chip.contains("fifo_depth = ") && chip.contains("[texture_cache]"),
        "{chip}"
    );
    let _ = std::fs::remove_dir_all(&a.out);
}

/// `--timing`: sampled or clocked candidates; the roofline, which does not see the
/// chip's parameters, is refused before any work.
#[test]
fn the_search_times_its_candidates_clocked_or_sampled() {
    use glare_pipeline::frame::timing::TimingMode;
    let with = |t| OptimizeArgs {
        timing: t,
        ..args("cache_kb", &["seconds<=0.01"])
    };
    assert_eq!(check_chip(&with(None)).unwrap().mode, TimingMode::Clocked);
    assert_eq!(
        check_chip(&with(Some(TimingMode::Sampled))).unwrap().mode,
        TimingMode::Sampled
    );
    let e = check_chip(&with(Some(TimingMode::Roofline))).err().unwrap();
    assert!(
        e.contains("--timing roofline") && e.contains("sampled"),
        "{e}"
    );
}

/// After a sampled search the best chip is clocked in full: over the budget there, the
/// run is an error naming its full time and the budget, with `pareto.csv` and
/// `best_chip.toml` (whose header carries the full time) kept; within it, no error.
#[test]
fn a_sampled_best_over_the_budget_in_full_is_an_error_with_its_files_kept() {
    let out = std::env::temp_dir().join(format!("optimize-chip-full-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    // The start chip, sampled: a one-point search whose best it is.
    let sampled = |limit_seconds| ChipPlan {
        max_evals: Some(1),
        mode: TimingMode::Sampled,
        out: out.clone(),
        ..plan(limit_seconds)
    };
    let o = search_chip(&sampled(1.0), Instant::now()).unwrap();
    let best = &o.points[o.best.expect("a second meets the budget")];
    // Its time clocked in full.
    let req = TimingRequest {
        mode: TimingMode::Clocked,
        chip: None,
        window: None,
    };
    let scene = sampled(1.0).scene;
    let (f, _) = render_timed(&scene, &req, Some(best.chip.clone()), None).unwrap();
    let full = f.timing.unwrap().clocked_seconds();
    // Report the search's outcome against a budget just under, then just over, that time.
    let csv = out.join("pareto.csv");
    std::fs::write(&csv, "kept\n").unwrap();
    let report =
        |limit: f64| glare_pipeline::optimize::chip::report(&sampled(limit), &o, Instant::now());
    let e = report(full * 0.999).unwrap_err();
    assert!(
        e.starts_with("budget:") && e.contains("clocked in full") && e.contains("best_chip.toml"),
        "{e}"
    );
    let chip = std::fs::read_to_string(out.join("best_chip.toml")).unwrap();
    let header = chip.lines().nth(1).unwrap();
    assert!(
        header.starts_with("# clocked in full:") && header.contains("OVER the budget"),
        "{chip}"
    );
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), "kept\n");
    report(full * 1.001).unwrap();
    let chip = std::fs::read_to_string(out.join("best_chip.toml")).unwrap();
    assert!(chip.contains("within the budget"), "{chip}");
    let _ = std::fs::remove_dir_all(&out);
}
