//! The seed's two examples (SPEC §4): the two contact schemes against each other as
//! the number of increments grows, and the results under mesh refinement.
//!
//! ```text
//!   plate on a base                      bar in a bearing
//!        ↓↓↓ 1500 N                        ▒▒▒ upper block (clamped top)
//!     ░░░░░░░░░░░░░░  plate (nodes)     ═══════════════════════▒▒▒═════════ ↑ 100 N
//!   ┌──────────────────┐                 bar (host), clamped at x = 0
//!   │ base (host)      │              ═══════════════════════▒▒▒═════════
//!   └──────────────────┘ clamped                            ▒▒▒ lower block (clamped bottom)
//! ```

use super::{Case, Plot, Table, displacement_at, sci, solve};
use cfe::analysis::Analysis;
use cfe::coupling::PairState;
use cfe::error::Result;
use cfe::model::{Model, Scheme};
use cfe::output::chart::Series;
use std::path::{Path, PathBuf};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join("examples")
        .join(name)
}

/// An example with its load point (part, position) where the displacement is
/// measured (the centre of the loaded segment).
const EXAMPLES: [(&str, &str, [f64; 2]); 2] = [
    ("plate_on_base.toml", "plate", [100.0, 135.0]),
    ("bar_in_bearing.toml", "bar", [480.0, 16.0]),
];

/// One end of a contact zone: between the outermost bonded pair and the nearest
/// open pair beyond it (or the face's end when none is open there).
#[derive(Debug, Clone, Copy)]
pub struct ZoneEnd {
    /// The outermost bonded pair's x.
    pub bonded: f64,
    /// The nearest open pair's x beyond it, if any.
    pub open: Option<f64>,
}

impl ZoneEnd {
    /// The interval that contains the end of the zone.
    fn interval(&self) -> (f64, f64) {
        let o = self.open.unwrap_or(self.bonded);
        (self.bonded.min(o), self.bonded.max(o))
    }
    fn mid(&self) -> f64 {
        let (a, b) = self.interval();
        0.5 * (a + b)
    }
    fn text(&self) -> String {
        match self.open {
            Some(o) => format!("{:.2}…{:.2}", self.bonded.min(o), self.bonded.max(o)),
            None => format!("{:.2} (face end)", self.bonded),
        }
    }
}

/// Each interface's bonded zone: its name, its two ends (left, right) and the
/// number of open pairs inside it (between its ends).
pub type Zone = (String, Option<[ZoneEnd; 2]>, usize);

/// The bonded zone of each interface.
pub fn zone_ends(a: &Analysis, inc: &cfe::solve::nonlinear::IncrementResult) -> Vec<Zone> {
    let rows = a.pair_rows(inc);
    a.interfaces
        .iter()
        .map(|i| {
            let mut pairs: Vec<(f64, bool)> = rows
                .iter()
                .filter(|r| r.interface == i.name)
                .map(|r| (r.x, r.state == PairState::Bonded))
                .collect();
            pairs.sort_by(|p, q| p.0.total_cmp(&q.0));
            let first = pairs.iter().position(|p| p.1);
            let last = pairs.iter().rposition(|p| p.1);
            let ends = first.zip(last).map(|(f, l)| {
                [
                    ZoneEnd {
                        bonded: pairs[f].0,
                        open: f.checked_sub(1).map(|k| pairs[k].0),
                    },
                    ZoneEnd {
                        bonded: pairs[l].0,
                        open: pairs.get(l + 1).map(|p| p.0),
                    },
                ]
            });
            let holes = first
                .zip(last)
                .map_or(0, |(f, l)| pairs[f..=l].iter().filter(|p| !p.1).count());
            (i.name.clone(), ends, holes)
        })
        .collect()
}

/// The finest model solved again from the coarser model's pattern: the example,
/// the pairs whose state differs from the all-bonded start's result, how many pairs
/// break the law in either run, and the relative load-point difference.
type StartCheck = (String, Vec<String>, usize, f64);

/// Results of the implex-against-active-set study.
struct SchemeStudy {
    table: Table,
    /// With 10 or more increments implex ends on the active-set's pattern and
    /// displacements.
    ok: bool,
    series: Vec<Series>,
    /// Per example, when implex with 10 increments first has the final pattern.
    first_reached: Vec<String>,
}

/// Results of the active-set refinement study.
struct RefinementStudy {
    table: Table,
    series: Vec<Series>,
    /// The load-point displacement's changes shrink.
    converging: bool,
    /// Every bonded-zone end stays within one coarser pair spacing.
    consistent: bool,
    /// Observed orders per example.
    observed: Vec<String>,
    /// Richardson-extrapolated load-point displacements per example.
    extrapolated: Vec<String>,
    /// Orders of the zone ends' midpoints.
    end_orders: Vec<String>,
    /// The zone ends that jumped.
    jumps: Vec<String>,
    /// What the coarse start changes in the finest model's result (finest
    /// K ≥ 4 only): per example, the pairs whose state differs, how many pairs
    /// break the law in either run, and the relative load-point difference.
    start_check: Option<Vec<StartCheck>>,
}

/// Case 6: implex against active-set, and the examples under refinement K.
pub fn schemes_and_refinement(quick: bool) -> Result<Case> {
    let schemes = scheme_study(quick)?;
    let refinement = refinement_study(quick)?;
    Ok(seed_case(schemes, refinement))
}

/// implex with a growing number of increments against active-set with the
/// file's 10, for both examples.
fn scheme_study(quick: bool) -> Result<SchemeStudy> {
    let mut study = SchemeStudy {
        table: Table {
            caption: "implex against active-set (10 increments) as the number of implex increments grows: the increment at which implex first has the active-set's final state pattern, whether it ends with it, how many pairs differ at the end, and the largest displacement difference at the end relative to the largest displacement.".into(),
            header: ["example", "implex increments", "pattern reached at increment", "same final pattern", "pairs differing", "largest Δu / largest u"].map(String::from).to_vec(),
            rows: Vec::new(),
        },
        ok: true,
        series: Vec::new(),
        first_reached: Vec::new(),
    };
    let counts: &[usize] = if quick {
        &[10]
    } else {
        &[1, 2, 3, 4, 5, 10, 20, 40]
    };
    for (name, _, _) in EXAMPLES {
        implex_example(name, counts, &mut study)?;
    }
    Ok(study)
}

/// The scheme study of example `name` with `counts` implex increments.
fn implex_example(name: &str, counts: &[usize], study: &mut SchemeStudy) -> Result<()> {
    let active = Analysis::new(Model::from_file(&example(name), 1)?)?;
    let ref_last = solve(&active)?.pop().expect("increments");
    let umax = ref_last.u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut pts = Vec::new();
    for &n in counts {
        let mut m = Model::from_file(&example(name), 1)?;
        m.settings.scheme = Scheme::Implex;
        m.settings.increments = n;
        // With too few increments implex ends on a wrong pattern on purpose: the
        // study measures how wrong, so the violation limit is lifted.
        m.settings.max_violation = f64::INFINITY;
        let a = Analysis::new(m)?;
        let incs = solve(&a)?;
        let reached = incs
            .iter()
            .position(|i| i.states == ref_last.states)
            .map(|k| k + 1);
        let last = incs.last().expect("increments");
        let same = last.states == ref_last.states;
        let differing: usize = last
            .states
            .iter()
            .zip(&ref_last.states)
            .map(|(a, b)| a.iter().zip(b).filter(|(x, y)| x != y).count())
            .sum();
        let du = last
            .u
            .iter()
            .zip(&ref_last.u)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
            / umax;
        if n >= 10 {
            study.ok &= same && du < 1e-8;
        }
        if n == 10 {
            study.first_reached.push(format!(
                "{} at its {}",
                name.trim_end_matches(".toml"),
                reached.map_or("— never".into(), ordinal)
            ));
        }
        pts.push((n as f64, du.max(1e-16)));
        study.table.rows.push(vec![
            name.trim_end_matches(".toml").into(),
            n.to_string(),
            reached.map_or("never".into(), |k| k.to_string()),
            same.to_string(),
            differing.to_string(),
            sci(du),
        ]);
    }
    study.series.push(Series {
        name: name.trim_end_matches(".toml").into(),
        points: pts,
        reference: false,
    });
    Ok(())
}

/// Active-set under refinement K for both examples, with the order-2 guide.
fn refinement_study(quick: bool) -> Result<RefinementStudy> {
    let ks: &[usize] = if quick { &[1, 2] } else { &[1, 2, 4, 8] };
    let mut study = RefinementStudy {
        table: Table {
            caption: "Active-set under refinement K (every part's cells × K): the vertical displacement of the load point (the centre of the loaded segment), its change from K/2 and the observed order; where each interface's bonded zone ends (between the outermost bonded pair and the nearest open pair beyond it, x), and how many open pairs lie inside the zone.".into(),
            header: ["example", "K", "unknowns", "load-point displacement", "change from K/2", "order", "bonded zone ends (left; right)", "open pairs inside the zone"].map(String::from).to_vec(),
            rows: Vec::new(),
        },
        series: Vec::new(),
        converging: true,
        consistent: true,
        observed: Vec::new(),
        extrapolated: Vec::new(),
        end_orders: Vec::new(),
        jumps: Vec::new(),
        start_check: (ks[ks.len() - 1] >= 4).then(Vec::new),
    };
    for (name, part, at) in EXAMPLES {
        refine_example(name, part, at, ks, &mut study)?;
    }
    if let Some(s0) = study.series.first().and_then(|s| s.points.first()) {
        let k_max = ks[ks.len() - 1] as f64;
        let guide = Series {
            name: "order 2".into(),
            points: vec![(2.0, s0.1), (k_max, s0.1 * (2.0 / k_max).powi(2))],
            reference: true,
        };
        study.series.push(guide);
    }
    Ok(study)
}

/// The zone ends of every refinement of one example, and their pair spacing.
struct ZoneHistory<'a> {
    ks: &'a [usize],
    ends_by_k: Vec<Vec<Zone>>,
    spacing_by_k: Vec<f64>,
}

/// The refinement study of example `name` (load point `at` on `part`) at `ks`.
fn refine_example(
    name: &str,
    part: &str,
    at: [f64; 2],
    ks: &[usize],
    st: &mut RefinementStudy,
) -> Result<()> {
    let short = name.trim_end_matches(".toml");
    let mut values = Vec::new();
    let mut pts = Vec::new();
    let mut history = ZoneHistory {
        ks,
        ends_by_k: Vec::new(),
        spacing_by_k: Vec::new(),
    };
    let first_row = st.table.rows.len();
    for &k in ks {
        let a = Analysis::new(Model::from_file(&example(name), k)?)?;
        let last = solve(&a)?.pop().expect("increments");
        let v = displacement_at(&a, &last, part, at)?[1];
        let ends = zone_ends(&a, &last);
        let zones: Vec<String> = ends
            .iter()
            .map(|(n, e, _)| match e {
                Some([l, r]) => format!("{n}: {}; {}", l.text(), r.text()),
                None => format!("{n}: none bonded"),
            })
            .collect();
        let holes: Vec<String> = ends.iter().map(|(n, _, h)| format!("{n}: {h}")).collect();
        if let Some(pattern) = st.start_check.as_mut().filter(|_| k == ks[ks.len() - 1]) {
            pattern.push(coarse_start_check(&a, &last, part, at, short, v)?);
        }
        let change = values.last().map(|p: &f64| v - p);
        values.push(v);
        st.table.rows.push(vec![
            short.into(),
            k.to_string(),
            a.dofs.n_eq.to_string(),
            format!("{v:.6e}"),
            change.map_or(String::new(), sci),
            String::new(),
            zones.join(" — "),
            holes.join(", "),
        ]);
        if let Some(c) = change {
            pts.push((k as f64, c.abs()));
        }
        history.ends_by_k.push(ends);
        // Pair spacing of the node parts at this K (the examples' node parts
        // have cells of 5/K and 2/K mm).
        history
            .spacing_by_k
            .push(if short == "plate_on_base" { 5.0 } else { 2.0 } / k as f64);
    }
    refinement_orders(short, &values, first_row, st);
    zone_end_check(&history, st);
    st.series.push(Series {
        name: short.into(),
        points: pts,
        reference: false,
    });
    Ok(())
}

/// The finest model `a` once more from the coarser model's pattern
/// (`start = "coarse"`): how much the start can change its result `last`, whose
/// load-point displacement is `v`.
fn coarse_start_check(
    a: &Analysis,
    last: &cfe::solve::nonlinear::IncrementResult,
    part: &str,
    at: [f64; 2],
    short: &str,
    v: f64,
) -> Result<StartCheck> {
    let again = super::solve_with(a, true)?.pop().expect("increments");
    let differing: Vec<String> = a
        .pair_rows(&again)
        .iter()
        .zip(a.pair_rows(last))
        .filter(|(p, q)| p.state != q.state)
        .map(|(p, q)| {
            let describe = |r: &cfe::output::report::PairRow| {
                if r.state == PairState::Bonded {
                    format!("bonded pressing with {}", sci(r.force_n))
                } else {
                    format!("open with gap {}", sci(r.gap_n))
                }
            };
            format!(
                "{} pair at x = {}: {} from all bonded, {} from the coarse start",
                p.interface,
                p.x,
                describe(&q),
                describe(p)
            )
        })
        .collect();
    // Pairs breaking the law in either run (settled or otherwise).
    let settled = again.violations.len() + last.violations.len();
    let w = displacement_at(a, &again, part, at)?[1];
    Ok((short.to_string(), differing, settled, ((w - v) / v).abs()))
}

/// The observed orders of the load-point displacements `values` of one example
/// (its rows from `first_row`) and the Richardson extrapolation.
fn refinement_orders(short: &str, values: &[f64], first_row: usize, st: &mut RefinementStudy) {
    let n = values.len();
    let mut these = Vec::new();
    let mut last_order = f64::NAN;
    for i in 2..n {
        let (d1, d2) = (values[i - 1] - values[i - 2], values[i] - values[i - 1]);
        let order = (d1 / d2).abs().log2();
        st.table.rows[first_row + i][5] = format!("{order:.2}");
        these.push(format!("{order:.2}"));
        st.converging &= d2.abs() < d1.abs();
        last_order = order;
    }
    if n >= 3 && last_order.is_finite() {
        let p = last_order.max(0.5);
        let ext = values[n - 1] + (values[n - 1] - values[n - 2]) / (2f64.powf(p) - 1.0);
        st.extrapolated.push(format!(
            "{short}: {:.5e} (finest differs by {:.2} %)",
            ext,
            100.0 * ((values[n - 1] - ext) / ext).abs()
        ));
    }
    st.observed.push(format!("{short}: {}", these.join(", ")));
}

/// The zone ends: each refinement's interval must lie within one pair spacing of
/// the coarser mesh from the previous one (the end does not jump), and their
/// midpoints settle.
fn zone_end_check(history: &ZoneHistory, st: &mut RefinementStudy) {
    let ZoneHistory {
        ks,
        ends_by_k,
        spacing_by_k,
    } = history;
    for (iface, _, _) in &ends_by_k[0] {
        for side in 0..2 {
            let seq: Vec<ZoneEnd> = ends_by_k
                .iter()
                .filter_map(|e| {
                    e.iter()
                        .find(|(n, _, _)| n == iface)
                        .and_then(|(_, z, _)| z.map(|z| z[side]))
                })
                .collect();
            for (i, w) in seq.windows(2).enumerate() {
                let ((a0, a1), (b0, b1)) = (w[0].interval(), w[1].interval());
                let tol = spacing_by_k[i] + 1e-9;
                let near = b0 <= a1 + tol && a0 <= b1 + tol;
                st.consistent &= near;
                if !near {
                    st.jumps.push(format!(
                        "{iface} {} at K = {}",
                        if side == 0 { "left" } else { "right" },
                        ks[i + 1]
                    ));
                }
            }
            let mids: Vec<f64> = seq.iter().map(ZoneEnd::mid).collect();
            if let [.., m0, m1, m2] = mids.as_slice() {
                let (d1, d2) = (m1 - m0, m2 - m1);
                let o = if d2.abs() < 1e-12 {
                    "∞ (unchanged)".to_string()
                } else {
                    format!("{:.2}", (d1 / d2).abs().log2())
                };
                st.end_orders.push(format!(
                    "{iface} {}: {o}",
                    if side == 0 { "left" } else { "right" }
                ));
            }
        }
    }
}

/// The seed case's report from its two studies: tables, plots and the verdict.
fn seed_case(schemes: SchemeStudy, refinement: RefinementStudy) -> Case {
    let SchemeStudy {
        table: schemes,
        ok: schemes_ok,
        series: scheme_series,
        first_reached,
    } = schemes;
    let RefinementStudy {
        table: refinement,
        series,
        converging,
        consistent,
        observed,
        extrapolated,
        end_orders,
        jumps,
        start_check,
    } = refinement;
    Case {
        title: "Seed examples: schemes and refinement".into(),
        setup: "The two examples of SPEC §4 (plate on a base, bar in a bearing), as in `examples/`. First the seed's implex scheme, with 1 to 40 increments, against the default active-set with the file's 10; then active-set under refinement K.".into(),
        reference: "Under proportional load with a receding contact area the state pattern does not depend on the load level, so both schemes must end on the same pattern and — the law being secant, each increment solving total equilibrium — on the same displacements to round-off; implex lags the pattern by its iterations, so it needs enough increments to reach it. Under refinement the load-point displacement must converge (the problems have corners and contact-zone ends, so no order is promised) and the ends of the bonded zones must stay put within the pair spacing.".into(),
        tables: vec![schemes, refinement],
        plots: vec![
            Plot {
                file: "seed_refinement.png".into(),
                title: "Change of the load-point displacement from K/2 to K".into(),
                x: "refinement K".into(),
                y: "|change of the load-point displacement|".into(),
                log: (true, true),
                series,
            },
            Plot {
                file: "seed_schemes.png".into(),
                title: "implex against active-set: final displacement difference".into(),
                x: "implex increments".into(),
                y: "largest Δu / largest u".into(),
                log: (true, true),
                series: scheme_series,
            },
        ],
        verdict: format!(
            "implex {} the active-set pattern and displacements (to round-off) once it has enough increments: with ten increments it first has the final pattern at increment n ({}); with fewer increments than that it ends on a wrong pattern (up to 9 % off in displacement with one), and the number needed grows with refinement (8 for the plate at K = 4, case 10). Under refinement the load-point displacement {} (observed orders {}; Richardson-extrapolated {}). Every bonded-zone end stays within one pair spacing of the interval found on the coarser mesh ({}; orders of the ends' midpoints {}). {}Open pairs inside a bonded zone (last column) are coupling nodes inside host edges next to the zone's end: with a node part finer than its host the pair forces alternate between pairs at host vertices and pairs inside host edges (case 5 (c)), and the weaker ones can open.",
            if schemes_ok { "reaches" } else { "does NOT reach" },
            first_reached.join("; "),
            if converging { "converges, its changes shrinking" } else { "does NOT settle monotonically" },
            observed.join("; "),
            extrapolated.join("; "),
            if consistent { "consistent".to_string() } else { format!("NOT consistent: {}", jumps.join(", ")) },
            end_orders.join(", "),
            match &start_check {
                Some(runs) => format!(
                    "Solving the finest models again from the coarser model's pattern (`start = \"coarse\"`) instead of all pairs bonded: {}. ",
                    runs.iter()
                        .map(|(n, diff, settled, d)| if diff.is_empty() {
                            format!("{n} ends on the same pattern (load point within {})", sci(*d))
                        } else {
                            format!("{n} ends on another pattern ({}; {} pairs breaking the law in either run; load point within {}){}", diff.join("; "), settled, sci(*d), if *settled == 0 { " — both satisfy the law at every pair: the stick law has several solutions here, and the start picks one, which is why the default start is all bonded" } else { "" })
                        })
                        .collect::<Vec<_>>()
                        .join("; ")
                ),
                None => String::new(),
            }
        ),
        passed: schemes_ok
            && converging
            && consistent
            // Another start may pick another solution of the stick law; they must
            // agree to well below the discretization error.
            && start_check.as_ref().is_none_or(|r| r.iter().all(|(_, _, _, d)| *d < 1e-3)),
    }
}

/// "1st", "2nd", "5th", … for increment numbers.
fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (1, 11) | (2, 12) | (3, 13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}
