//! The seed's two examples (SPEC §4): the two contact schemes against each other as
//! the number of increments grows, and the results under mesh refinement.

use super::{Case, Plot, Table, sci, solve};
use crate::analysis::Analysis;
use crate::error::Result;
use crate::model::{Model, Scheme};
use crate::output::chart::Series;
use std::path::{Path, PathBuf};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name)
}

/// Case: implex against active-set, and the examples under refinement K.
pub fn schemes_and_refinement(quick: bool) -> Result<Case> {
    let names = ["plate_on_base.toml", "bar_in_bearing.toml"];
    let mut schemes = Table {
        caption: "implex against active-set (10 increments): the increment at which implex first has the active-set's final pattern, whether it ends with it, and the largest displacement difference at the end relative to the largest displacement.".into(),
        header: vec!["example".into(), "implex increments".into(), "pattern reached at".into(), "same final pattern".into(), "largest Δu / largest u (magnitudes)".into()],
        rows: Vec::new(),
    };
    let mut schemes_ok = true;
    for name in names {
        let active = Analysis::new(Model::from_file(&example(name), 1)?)?;
        let ref_last = solve(&active)?.pop().expect("increments");
        let umax = ref_last.u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let counts: &[usize] = if quick { &[10] } else { &[5, 10, 20, 40] };
        for &n in counts {
            let mut m = Model::from_file(&example(name), 1)?;
            m.settings.scheme = Scheme::Implex;
            m.settings.increments = n;
            let a = Analysis::new(m)?;
            let incs = solve(&a)?;
            let reached = incs
                .iter()
                .position(|i| i.states == ref_last.states)
                .map(|k| k + 1);
            let last = incs.last().expect("increments");
            let same = last.states == ref_last.states;
            let du = last
                .u
                .iter()
                .zip(&ref_last.u)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
                / umax;
            if n >= 10 {
                schemes_ok &= same && du < 1e-8;
            }
            schemes.rows.push(vec![
                name.trim_end_matches(".toml").into(),
                n.to_string(),
                reached.map_or("never".into(), |k| k.to_string()),
                same.to_string(),
                sci(du),
            ]);
        }
    }

    let ks: &[usize] = if quick { &[1, 2] } else { &[1, 2, 4, 8] };
    let mut refinement = Table {
        caption: "Under refinement K (every part's cells × K): the largest displacement and where each interface's contact zone (first to last bonded pair) lies.".into(),
        header: vec!["example".into(), "K".into(), "unknowns".into(), "largest displacement".into(), "change from K/2".into(), "order".into(), "contact zones (x from – to)".into()],
        rows: Vec::new(),
    };
    let mut series = Vec::new();
    let mut converging = true;
    let mut observed: Vec<String> = Vec::new();
    for name in names {
        let mut values = Vec::new();
        let mut pts = Vec::new();
        for &k in ks {
            let a = Analysis::new(Model::from_file(&example(name), k)?)?;
            let last = solve(&a)?.pop().expect("increments");
            let umax = last
                .u
                .chunks(2)
                .map(|d| d[0].hypot(d[1]))
                .fold(0.0, f64::max);
            let rows = a.pair_rows(&last);
            let zones: Vec<String> = a
                .interfaces
                .iter()
                .map(|i| {
                    let bonded: Vec<f64> = rows
                        .iter()
                        .filter(|r| r.interface == i.name && r.state == "bonded")
                        .map(|r| r.x)
                        .collect();
                    match (bonded.first(), bonded.last()) {
                        (Some(f), Some(l)) => format!("{}: {f:.3} – {l:.3}", i.name),
                        _ => format!("{}: none", i.name),
                    }
                })
                .collect();
            let change = values.last().map(|p: &f64| umax - p);
            values.push(umax);
            refinement.rows.push(vec![
                name.trim_end_matches(".toml").into(),
                k.to_string(),
                a.dofs.n_eq.to_string(),
                sci(umax),
                change.map_or(String::new(), sci),
                String::new(),
                zones.join("; "),
            ]);
            if let Some(c) = change {
                pts.push((5.0 / k as f64, c.abs()));
            }
        }
        // Orders from successive changes.
        let n = values.len();
        let first_row = refinement.rows.len() - n;
        let mut these = Vec::new();
        for i in 2..n {
            let (d1, d2) = (values[i - 1] - values[i - 2], values[i] - values[i - 1]);
            let order = (d1 / d2).abs().log2();
            refinement.rows[first_row + i][5] = format!("{order:.2}");
            these.push(format!("{order:.2}"));
            converging &= d2.abs() < d1.abs();
        }
        observed.push(format!(
            "{}: {}",
            name.trim_end_matches(".toml"),
            these.join(", ")
        ));
        series.push(Series {
            name: name.trim_end_matches(".toml").into(),
            points: pts,
            reference: false,
        });
    }
    Ok(Case {
        title: "Seed examples: schemes and refinement".into(),
        setup: "The two examples of SPEC §4 (plate on a base, bar in a bearing), as in `examples/`. First the seed's implex scheme against the default active-set at growing numbers of increments; then active-set under refinement K.".into(),
        reference: "Under proportional load with a receding contact area the state pattern does not depend on the load level, so both schemes must end on the same pattern and, the law being secant, on the same displacements; under refinement the results must settle.".into(),
        tables: vec![schemes, refinement],
        plots: vec![Plot {
            file: "seed_refinement.png".into(),
            title: "Change of the largest displacement between refinements".into(),
            x: "5 / K".into(),
            y: "|change of max |u||".into(),
            log: (true, true),
            series,
        }],
        verdict: format!(
            "implex {} the active-set pattern and displacements once it has enough increments; the largest displacement {} under refinement (observed orders {}).",
            if schemes_ok { "reaches" } else { "does NOT reach" },
            if converging { "converges, its changes shrinking" } else { "does not settle monotonically" },
            observed.join("; ")
        ),
        passed: schemes_ok && converging,
    })
}
