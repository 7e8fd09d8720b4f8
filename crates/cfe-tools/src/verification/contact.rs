//! Case 10: the contact iteration. Does the active set end on a state that satisfies
//! the law whenever one exists, say so honestly when none does, and give the same
//! answer whatever its start and however its systems are solved?
//!
//! ```text
//!              load (28 mm wide, centre c)
//!                 ↓↓↓↓↓↓↓
//!        ┌──────────────────────────┐  plate, thickness h, x ∈ [30, 170]
//!        └──────────────────────────┘  ← 29·K coupling pairs (contact law)
//!   ┌────────────────────────────────────┐
//!   │              base (host)           │  x ∈ [0, 200], y ∈ [0, 120]
//!   └────────────────────────────────────┘
//!   ///////////////// clamped //////////////
//! ```
//!
//! The reference is the law itself, checked from the pairs table independently of
//! the solver's own check, and an exhaustive search over the patterns around every
//! settled pair (a consistent pattern there would be one the iteration missed).

use super::{Case, Table, sci};
use cfe::analysis::Analysis;
use cfe::coupling::{PairState, PairStates, ViolationKind};
use cfe::error::{Error, Result};
use cfe::model::{Model, Scheme};
use cfe::solve::nonlinear::IncrementResult;
use cfe::solve::system::UpdatePolicy;
use std::path::Path;

/// The load of the plate-on-base variants (N).
pub const LOAD: f64 = 1500.0;

/// The seed's plate on a base (SPEC §4) with plate thickness `h` (2.5 mm cells
/// through it, at least two), the 28 mm wide load centred at x = `c`, meshes
/// refined `k` times, two increments.
pub fn plate_variant(h: f64, c: f64, k: usize) -> Result<Analysis> {
    let ny = ((h / 2.5).round() as usize).max(2);
    let text = format!(
        r#"
[materials.steel]
E = 210000.0
nu = 0.31
[[part]]
name = "base"
material = "steel"
rectangle = {{ x = [0.0, 200.0], y = [0.0, 120.0], cells = [20, 12] }}
[[part]]
name = "plate"
material = "steel"
rectangle = {{ x = [30.0, 170.0], y = [120.0, {top}], cells = [28, {ny}] }}
[[interface]]
host = "base"
nodes = "plate"
boundary = "bottom"
c_n = 1e9
c_s = 1e9
[[support]]
part = "base"
boundary = "bottom"
fix = ["x", "y"]
[[load]]
part = "plate"
boundary = "top"
from = [{a}, {top}]
to = [{b}, {top}]
force = [0.0, -{LOAD}]
[analysis]
increments = 2
"#,
        top = 120.0 + h,
        a = c - 14.0,
        b = c + 14.0,
    );
    Analysis::new(Model::from_str(&text, Path::new("variant.toml"), k)?)
}

/// The bar in its bearing (SPEC §4) with every cell split along the falling
/// diagonal (`\`): a mesh on which the strict stick law has no consistent state.
pub fn bearing_falling_diagonals() -> Result<Analysis> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/bar_in_bearing.toml");
    let text = std::fs::read_to_string(&path)
        .map_err(|e| Error::ReadInput {
            path: path.clone(),
            source: e,
        })?
        .replace(
            "cells = [120, 8] }",
            "cells = [120, 8], diagonal = \"falling\" }",
        )
        .replace(
            "cells = [15, 9] }",
            "cells = [15, 9], diagonal = \"falling\" }",
        );
    Analysis::new(Model::from_str(&text, Path::new("falling.toml"), 1)?)
}

/// Runs the solver on `a` in memory, optionally from the pattern `start` and with
/// an update policy; returns every increment.
pub fn run(
    a: &Analysis,
    start: Option<PairStates>,
    policy: Option<UpdatePolicy>,
) -> Result<Vec<IncrementResult>> {
    let mut solver = a.solver()?;
    if let Some(s) = start {
        solver.set_initial_states(s);
    }
    if let Some(p) = policy {
        solver.set_update_policy(p);
    }
    let mut all = Vec::new();
    solver.run(|inc| {
        all.push(inc.clone());
        Ok(())
    })?;
    Ok(all)
}

/// The law checked from the pairs table alone, independently of the solver: a
/// bonded pair pulls with no more than 1e-6 of `load` × λ, an open pair carries no
/// force and penetrates by no more than 1e-9 of the largest displacement. Returns
/// a description of every pair that breaks it.
pub fn law_breakers(a: &Analysis, inc: &IncrementResult, load: f64) -> Vec<String> {
    let umax = inc
        .u
        .chunks(2)
        .map(|d| d[0].hypot(d[1]))
        .fold(0.0, f64::max);
    let scale = inc.lambda * load;
    a.pair_rows(inc)
        .iter()
        .filter(|r| {
            if r.state == PairState::Bonded {
                r.force_n < -1e-6 * scale
            } else {
                r.force_n != 0.0 || r.gap_n < -1e-9 * umax
            }
        })
        .map(|r| {
            format!(
                "{} x = {}: {} force_n {}, gap {}",
                r.interface,
                r.x,
                r.state,
                sci(r.force_n),
                sci(r.gap_n)
            )
        })
        .collect()
}

/// Whether some pattern that differs from `states` only within `radius` pairs of
/// pair `p` of interface `i` satisfies the law (an exhaustive search: 2^(2 radius + 1)
/// patterns, each solved once).
pub fn consistent_pattern_near(
    a: &Analysis,
    states: &[Vec<PairState>],
    i: usize,
    p: usize,
    radius: usize,
) -> Result<bool> {
    let n = states[i].len();
    let (lo, hi) = (p.saturating_sub(radius), (p + radius).min(n - 1));
    let mut solver = a.solver()?;
    for mask in 0u32..1 << (hi - lo + 1) {
        let mut s = states.to_vec();
        for (j, st) in s[i][lo..=hi].iter_mut().enumerate() {
            *st = if mask >> j & 1 == 1 {
                PairState::Open
            } else {
                PairState::Bonded
            };
        }
        match solver.solve_pattern(1.0, &s) {
            Ok(r) if r.violations.is_empty() => return Ok(true),
            // A pattern that leaves a part unsupported is no solution either.
            Ok(_) | Err(Error::Unsupported { .. } | Error::Singular(_)) => {}
            Err(e) => return Err(e),
        }
    }
    Ok(false)
}

/// Largest |a − b| relative to the largest |b|.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale.max(f64::MIN_POSITIVE)
}

/// Case 10: the contact iteration on plate-on-base variants, a mesh without a
/// consistent state, the warm start and updates, and implex.
pub fn contact_iteration(quick: bool) -> Result<Case> {
    let (hs, cs, ks): (&[f64], &[f64], &[usize]) = if quick {
        (&[5.0, 10.0, 20.0], &[45.0, 100.0], &[1, 2])
    } else {
        (
            &[5.0, 6.0, 8.0, 10.0, 12.5, 15.0, 20.0],
            &[45.0, 75.0, 100.0],
            &[1, 2, 4],
        )
    };
    let (variants, counts, worst, variants_ok) = variants_table(hs, cs, ks)?;
    let (exact, settled) = counts;
    let (starts, starts_ok) = starts_table(if quick { &[4] } else { &[4, 16] })?;
    let (bearing, rule, bearing_ok) = no_consistent_state()?;
    let (implex, implex_ok) = implex_table(if quick { &[1] } else { &[1, 4] })?;
    let passed = variants_ok && starts_ok && bearing_ok && implex_ok;
    Ok(Case {
        title: "The contact iteration".into(),
        setup: format!(
            "The plate on a base (SPEC §4) with the plate {} mm thick, the load's centre at x = {} (the plate spans 30–170 mm, so 45 is near its left end and 100 its middle) and meshes refined K = {} times: {} runs of the `active-set` scheme from all pairs bonded. Then the same plate solved from the 4× coarser model's pattern, from all bonded with low-rank updates, and from all bonded refactorizing every iteration; the bar in its bearing meshed with falling diagonals; and `implex` on the seed plate.",
            hs.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(", "),
            cs.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(", "),
            ks.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(", "),
            exact + settled
        ),
        reference: "The contact law itself, checked from the pairs table independently of the solver: no bonded pair pulls by more than 1e-6 of the load, no open pair carries force or penetrates by more than 1e-9 of the largest displacement. A run that ends on such a pattern must reproduce itself when started from it. Where the solver settles instead, an exhaustive search over the 2⁹ patterns of the four pairs either side of each settled pair (2¹¹ for the bearing) must find none that satisfies the law: otherwise the iteration missed one.".into(),
        tables: vec![variants, starts, bearing, implex],
        plots: Vec::new(),
        verdict: format!(
            "{exact} of {} variants end on a pattern that satisfies the law at every pair (the independent check agrees, and each reproduces itself in one iteration from its own pattern); the other {settled} have no consistent pattern within four pairs of any settled pair, and report each settled pair with its tension, at most {} of the load. The warm start and the low-rank updates {} the answer. {rule} implex {}.",
            exact + settled,
            sci(worst),
            if starts_ok { "change nothing in" } else { "CHANGE" },
            if implex_ok {
                "ends on the active-set pattern, with the same violations, once it has reached it"
            } else {
                "does NOT reach the active-set result"
            }
        ),
        passed,
    })
}

/// The variants: per run, the iterations, the result and the checks. Returns the
/// table, the numbers of exact and settled runs, the largest violation relative to
/// the load, and whether every check passed.
fn variants_table(
    hs: &[f64],
    cs: &[f64],
    ks: &[usize],
) -> Result<(Table, (usize, usize), f64, bool)> {
    let mut table = Table {
        caption: "Plate-on-base variants, `active-set` from all bonded: iterations of the first increment, the pattern found, and the checks. *exact*: the law holds on every pair; *settled*: no consistent pattern was reached, and the pairs kept against the law are reported. Independent check: pairs breaking the law by the pairs table. Last column: for an exact result, the iterations and the largest Δu/u of a run started from its own pattern; for a settled one, the exhaustive search around each settled pair.".into(),
        header: ["h [mm]", "c [mm]", "K", "pairs", "iterations", "bonded", "result", "largest violation / load", "independent check", "restart or search"].map(String::from).to_vec(),
        rows: Vec::new(),
    };
    let (mut exact, mut settled, mut ok, mut worst) = (0, 0, true, 0.0f64);
    for &h in hs {
        for &c in cs {
            for &k in ks {
                let a = plate_variant(h, c, k)?;
                let incs = run(&a, None, None)?;
                let last = incs.last().expect("increments");
                let broken = law_breakers(&a, last, LOAD);
                let violation = last.max_violation_force() / (last.lambda * LOAD);
                worst = worst.max(violation);
                let bonded = last.states[0]
                    .iter()
                    .filter(|&&s| s == PairState::Bonded)
                    .count();
                let (result, check) = if last.settled.is_empty() {
                    exact += 1;
                    let again = run(&a, Some(last.states.clone()), None)?;
                    let du = relative_difference(&again.last().expect("increments").u, &last.u);
                    ok &= broken.is_empty() && again[0].iterations == 1 && du < 1e-6;
                    (
                        "exact".to_string(),
                        format!("{} iteration, Δu/u {}", again[0].iterations, sci(du)),
                    )
                } else {
                    settled += 1;
                    let mut none = true;
                    for &(i, p) in &last.settled {
                        none &= !consistent_pattern_near(&a, &last.states, i, p, 4)?;
                    }
                    ok &= none && broken.len() == last.settled.len();
                    (
                        format!("settled: {} pair(s)", last.settled.len()),
                        if none {
                            "no consistent pattern nearby".into()
                        } else {
                            "a consistent pattern was MISSED".into()
                        },
                    )
                };
                table.rows.push(vec![
                    h.to_string(),
                    c.to_string(),
                    k.to_string(),
                    last.states[0].len().to_string(),
                    incs[0].iterations.to_string(),
                    bonded.to_string(),
                    result,
                    sci(violation),
                    if broken.is_empty() {
                        "law holds".into()
                    } else {
                        format!("{} pair(s) break it", broken.len())
                    },
                    check,
                ]);
            }
        }
    }
    Ok((table, (exact, settled), worst, ok))
}

/// The seed plate refined K times, solved from three starts/solvers.
fn starts_table(ks: &[usize]) -> Result<(Table, bool)> {
    let mut table = Table {
        caption: "The seed plate (h = 15, c = 100) refined K times: iterations of the first increment from the 4× coarser model's pattern (as `cfe run` does), from all bonded with low-rank updates, and from all bonded refactorizing at every iteration; whether the three end on the same pattern, and the largest displacement difference. When the warm start settles, the increment is redone from all bonded, so a settlement does not depend on the start (its iterations include the redo).".into(),
        header: ["K", "pairs", "iterations warm", "iterations cold (updates)", "iterations cold (refactorizing)", "same pattern", "settled pairs", "largest Δu / u"].map(String::from).to_vec(),
        rows: Vec::new(),
    };
    let mut ok = true;
    for &k in ks {
        let a = plate_variant(15.0, 100.0, k)?;
        let start = a.coarse_states();
        let warm = run(&a, start, None)?;
        let cold = run(&a, None, Some(UpdatePolicy::Always))?;
        let plain = run(&a, None, Some(UpdatePolicy::Never))?;
        let (w, c, p) = (
            warm.last().expect("increments"),
            cold.last().expect("increments"),
            plain.last().expect("increments"),
        );
        let same = w.states == c.states && p.states == c.states;
        let du = relative_difference(&w.u, &c.u).max(relative_difference(&p.u, &c.u));
        ok &= same && du < 1e-8;
        table.rows.push(vec![
            k.to_string(),
            c.states[0].len().to_string(),
            warm[0].iterations.to_string(),
            cold[0].iterations.to_string(),
            plain[0].iterations.to_string(),
            if same { "yes" } else { "NO" }.into(),
            c.settled.len().to_string(),
            sci(du),
        ]);
    }
    Ok((table, ok))
}

/// The bearing with falling diagonals: the settled pair, its two states, the search.
fn no_consistent_state() -> Result<(Table, String, bool)> {
    let a = bearing_falling_diagonals()?;
    let last = run(&a, None, None)?.pop().expect("increments");
    let mut table = Table {
        caption: "The bar in its bearing with every cell split along the falling diagonal (`\\`): the pair the iteration settles, what it does in each state with every other pair as settled, and the exhaustive search over the eleven pairs around it. The rule keeps the least-violating visited pattern, preferring one without penetration.".into(),
        header: ["interface", "node", "x [mm]", "bonded: normal force [N]", "open: gap_n [mm]", "open: c_n × penetration [N]", "patterns searched", "consistent found"].map(String::from).to_vec(),
        rows: Vec::new(),
    };
    let rows = a.pair_rows(&last);
    let mut ok = last.settled.len() == 1
        && last
            .violations
            .iter()
            .all(|v| v.kind == ViolationKind::Tension);
    let mut rule = String::new();
    for &(i, p) in &last.settled {
        let iface = &a.interfaces[i];
        let offset: usize = a.interfaces[..i].iter().map(|f| f.elements.len()).sum();
        let row = &rows[offset + p];
        // The same pattern with this pair open: its gap.
        let mut flipped = last.states.clone();
        flipped[i][p] = PairState::Open;
        let mut solver = a.solver()?;
        let opened = solver.solve_pattern(1.0, &flipped)?;
        let open = a.pair_rows(&opened)[offset + p].gap_n;
        let none = !consistent_pattern_near(&a, &last.states, i, p, 5)?;
        ok &= none && row.state == PairState::Bonded && row.force_n < 0.0 && open < 0.0;
        rule = format!(
            "With falling diagonals the bearing's pair at x = {} of '{}' pulls with {} N when bonded and penetrates by {} mm when open (the same as {} N at c_n), and none of the 2048 patterns of its eleven neighbours satisfies the law: the strict stick law has no consistent state there. The rule keeps it bonded — no interpenetration — and reports it (status `completed_with_violations`).",
            row.x,
            iface.name,
            sci(-row.force_n),
            sci(-open),
            sci(-open * iface.c_n)
        );
        table.rows.push(vec![
            iface.name.clone(),
            row.node.to_string(),
            row.x.to_string(),
            sci(row.force_n),
            sci(open),
            sci(-open * iface.c_n),
            "2048".into(),
            if none { "none" } else { "FOUND" }.into(),
        ]);
    }
    Ok((table, rule, ok))
}

/// implex on the seed plate against active-set.
fn implex_table(ks: &[usize]) -> Result<(Table, bool)> {
    let mut table = Table {
        caption: "`implex` (10 increments) on the seed plate: the increment at which it first has the `active-set` pattern, and the final violations of both schemes (at K = 4 the strict law has no consistent state; both end on the same settled pair).".into(),
        header: ["K", "pattern reached at increment", "implex final violations", "active-set final violations", "same final pattern"].map(String::from).to_vec(),
        rows: Vec::new(),
    };
    let mut ok = true;
    for &k in ks {
        let model = Model::from_file(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml"),
            k,
        )?;
        let active = run(&Analysis::new(model.clone())?, None, None)?;
        let reference = active.last().expect("increments");
        let mut m = model;
        m.settings.scheme = Scheme::Implex;
        let a = Analysis::new(m)?;
        let incs = run(&a, None, None)?;
        let last = incs.last().expect("increments");
        let reached = incs.iter().position(|inc| inc.states == reference.states);
        let same = last.states == reference.states;
        ok &= same && last.violations.len() == reference.violations.len();
        table.rows.push(vec![
            k.to_string(),
            reached.map_or("never".into(), |r| (r + 1).to_string()),
            last.violations.len().to_string(),
            reference.violations.len().to_string(),
            if same { "yes" } else { "NO" }.into(),
        ]);
    }
    Ok((table, ok))
}
