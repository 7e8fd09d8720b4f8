//! The history of a run (issue 40; as CalculiX's `*NODE PRINT` / `*CONTACT
//! PRINT`, Abaqus's history output): one [`HistoryRow`] per converged increment
//! — its step, load factor and time, every support's reaction, every
//! interface's contact resultants, contact length and largest pressure, every
//! probe point's displacement — kept in the summary (`summary.json`'s
//! `history`) and laid out as named columns ([`columns`]) for `history.csv`,
//! Python's `result.history` and `history.png`.

use serde::{Deserialize, Serialize};

/// One interface at one increment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InterfaceHistory {
    /// The interface's name.
    pub interface: String,
    /// Σ f_n over its pairs (> 0: the faces press together): on a straight
    /// face the normal resultant on the node part.
    pub force_n: f64,
    /// Σ f_s over its pairs (along each pair's s = n turned +90°): on a straight
    /// face the tangential resultant on the node part. In a solid model the
    /// magnitude of the sum of its pairs' tangential force vectors (≥ 0; on a
    /// flat face the magnitude of the tangential resultant), which no choice of
    /// the pairs' tangents t₁, t₂ changes.
    pub force_s: f64,
    /// The resultant of its pairs' forces on the node part along x (a solid
    /// model only; absent in a plane one): the summary's `resultant`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fx: Option<f64>,
    /// As `fx`, along y.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fy: Option<f64>,
    /// As `fx`, along z.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fz: Option<f64>,
    /// The distance between its closed pairs with the smallest and the largest
    /// x (then y) (0 when none is closed): the summary's `contact_length`.
    pub contact_length: f64,
    /// Its largest pair pressure, a stress (force_n / (tributary × t)).
    pub max_pressure: f64,
}

/// One probe point at one increment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProbeHistory {
    /// The probe's name.
    pub probe: String,
    /// Displacement x at its point (the shape functions of the element that
    /// contains it; its node's at a node or outside every element).
    pub ux: f64,
    /// Displacement y, as `ux`.
    pub uy: f64,
    /// Displacement z, as `ux` (a solid model only; absent in a plane one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uz: Option<f64>,
}

/// One support's reaction at one increment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReactionHistory {
    /// The support's name.
    pub support: String,
    /// Reaction x (the force the support exerts on the part).
    pub fx: f64,
    /// Reaction y.
    pub fy: f64,
    /// Reaction z (a solid model only; absent in a plane one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fz: Option<f64>,
}

/// One converged increment of the history.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HistoryRow {
    /// 1-based increment over all steps.
    pub increment: usize,
    /// The step's name.
    pub step: String,
    /// The step's 1-based index.
    pub step_index: usize,
    /// The step's load factor (its progress k / n, 1 at its end).
    pub load_factor: f64,
    /// Total time: step index − 1 + load factor.
    pub time: f64,
    /// Per support, in the model's order.
    pub reactions: Vec<ReactionHistory>,
    /// Per interface, in the model's order.
    pub interfaces: Vec<InterfaceHistory>,
    /// Per probe, in the model's order.
    pub probes: Vec<ProbeHistory>,
}

/// A column's values over the increments.
#[derive(Debug, Clone, PartialEq)]
pub enum Values {
    /// Counts (increment, step index).
    Count(Vec<usize>),
    /// Names (the step).
    Name(Vec<String>),
    /// Numbers.
    Number(Vec<f64>),
}

/// The quantities of a reaction, an interface and a probe of a plane model, in
/// column order.
pub const REACTION_QUANTITIES: [&str; 2] = ["fx", "fy"];
/// See [`REACTION_QUANTITIES`].
pub const INTERFACE_QUANTITIES: [&str; 4] =
    ["force_n", "force_s", "contact_length", "max_pressure"];
/// See [`REACTION_QUANTITIES`].
pub const PROBE_QUANTITIES: [&str; 2] = ["ux", "uy"];
/// The quantities of a reaction, an interface and a probe of a solid model, in
/// column order: the plane ones with the z components, and an interface's
/// resultant (fx, fy, fz) after its normal and tangential sums.
pub const SOLID_REACTION_QUANTITIES: [&str; 3] = ["fx", "fy", "fz"];
/// See [`SOLID_REACTION_QUANTITIES`].
pub const SOLID_INTERFACE_QUANTITIES: [&str; 7] = [
    "force_n",
    "force_s",
    "fx",
    "fy",
    "fz",
    "contact_length",
    "max_pressure",
];
/// See [`SOLID_REACTION_QUANTITIES`].
pub const SOLID_PROBE_QUANTITIES: [&str; 3] = ["ux", "uy", "uz"];

/// The column names of the history of a plane model with these supports,
/// interfaces and probes: `increment`, `step`, `step_index`, `load_factor`,
/// `time`, then `reaction:SUPPORT.fx|fy`, `interface:NAME.force_n|force_s|
/// contact_length|max_pressure`, `probe:NAME.ux|uy` ([`column_names_in`] 2).
pub fn column_names<'a>(
    supports: impl Iterator<Item = &'a str>,
    interfaces: impl Iterator<Item = &'a str>,
    probes: impl Iterator<Item = &'a str>,
) -> Vec<String> {
    column_names_in(2, supports, interfaces, probes)
}

/// The column names of the history of a model whose vectors have `n`
/// components (2: plane, [`column_names`]; 3: solid, with
/// `reaction:SUPPORT.fz`, `interface:NAME.fx|fy|fz` and `probe:NAME.uz`, see
/// [`SOLID_REACTION_QUANTITIES`]).
pub fn column_names_in<'a>(
    n: usize,
    supports: impl Iterator<Item = &'a str>,
    interfaces: impl Iterator<Item = &'a str>,
    probes: impl Iterator<Item = &'a str>,
) -> Vec<String> {
    let solid = n > 2;
    let (reaction, interface, probe): (&[&str], &[&str], &[&str]) = if solid {
        (
            &SOLID_REACTION_QUANTITIES,
            &SOLID_INTERFACE_QUANTITIES,
            &SOLID_PROBE_QUANTITIES,
        )
    } else {
        (
            &REACTION_QUANTITIES,
            &INTERFACE_QUANTITIES,
            &PROBE_QUANTITIES,
        )
    };
    let mut names: Vec<String> = ["increment", "step", "step_index", "load_factor", "time"]
        .map(String::from)
        .to_vec();
    let mut add = |kind: &str, name: &str, quantities: &[&str]| {
        names.extend(quantities.iter().map(|q| format!("{kind}:{name}.{q}")));
    };
    for s in supports {
        add("reaction", s, reaction);
    }
    for i in interfaces {
        add("interface", i, interface);
    }
    for p in probes {
        add("probe", p, probe);
    }
    names
}

/// Whether `row` is a solid model's (its reactions, interfaces or probes state
/// z components).
fn is_solid(row: &HistoryRow) -> bool {
    row.reactions.iter().any(|r| r.fz.is_some())
        || row.interfaces.iter().any(|i| i.fz.is_some())
        || row.probes.iter().any(|p| p.uz.is_some())
}

/// The history `rows` as named columns ([`column_names_in`] of the first row's
/// supports, interfaces and probes, with the z components when they are a
/// solid model's; every row has the same). Empty without rows.
pub fn columns(rows: &[HistoryRow]) -> Vec<(String, Values)> {
    let Some(first) = rows.first() else {
        return Vec::new();
    };
    let solid = is_solid(first);
    let names = column_names_in(
        if solid { 3 } else { 2 },
        first.reactions.iter().map(|r| r.support.as_str()),
        first.interfaces.iter().map(|i| i.interface.as_str()),
        first.probes.iter().map(|p| p.probe.as_str()),
    );
    let mut values = vec![
        Values::Count(rows.iter().map(|r| r.increment).collect()),
        Values::Name(rows.iter().map(|r| r.step.clone()).collect()),
        Values::Count(rows.iter().map(|r| r.step_index).collect()),
        Values::Number(rows.iter().map(|r| r.load_factor).collect()),
        Values::Number(rows.iter().map(|r| r.time).collect()),
    ];
    let number = |f: &dyn Fn(&HistoryRow) -> f64| Values::Number(rows.iter().map(f).collect());
    // A z component a row lacks (never, in a solid model's history) reads 0.
    let z = |v: Option<f64>| v.unwrap_or(0.0);
    for k in 0..first.reactions.len() {
        values.push(number(&|r| r.reactions[k].fx));
        values.push(number(&|r| r.reactions[k].fy));
        if solid {
            values.push(number(&|r| z(r.reactions[k].fz)));
        }
    }
    for k in 0..first.interfaces.len() {
        values.push(number(&|r| r.interfaces[k].force_n));
        values.push(number(&|r| r.interfaces[k].force_s));
        if solid {
            values.push(number(&|r| z(r.interfaces[k].fx)));
            values.push(number(&|r| z(r.interfaces[k].fy)));
            values.push(number(&|r| z(r.interfaces[k].fz)));
        }
        values.push(number(&|r| r.interfaces[k].contact_length));
        values.push(number(&|r| r.interfaces[k].max_pressure));
    }
    for k in 0..first.probes.len() {
        values.push(number(&|r| r.probes[k].ux));
        values.push(number(&|r| r.probes[k].uy));
        if solid {
            values.push(number(&|r| z(r.probes[k].uz)));
        }
    }
    names.into_iter().zip(values).collect()
}

/// The numbers of column `name` of `columns` (counts as numbers), if it is one.
pub fn numbers(columns: &[(String, Values)], name: &str) -> Option<Vec<f64>> {
    columns
        .iter()
        .find(|(n, _)| n == name)
        .and_then(|(_, v)| match v {
            Values::Number(x) => Some(x.clone()),
            Values::Count(x) => Some(x.iter().map(|&c| c as f64).collect()),
            Values::Name(_) => None,
        })
}

/// The default axes of `history.png` for these `rows`: y the reaction
/// component (x, y, and in a solid model z) that varies most over the run (max − min over the increments; its
/// largest magnitude with one increment), the first of equal ones: the
/// support and direction the loading drives; x the first probe's displacement
/// in that direction, or the time without probes. `None` without supports.
pub fn default_plot(rows: &[HistoryRow]) -> Option<[String; 2]> {
    let first = rows.first()?;
    let components = if is_solid(first) { 3 } else { 2 };
    let mut best: Option<(f64, usize, usize)> = None;
    for k in 0..first.reactions.len() {
        for c in 0..components {
            let v = |r: &HistoryRow| {
                let f = &r.reactions[k];
                [f.fx, f.fy, f.fz.unwrap_or(0.0)][c]
            };
            let (lo, hi) = (rows.iter().map(v))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                    (a.min(x), b.max(x))
                });
            let spread = if rows.len() > 1 {
                hi - lo
            } else {
                v(first).abs()
            };
            if best.is_none_or(|b| spread > b.0) {
                best = Some((spread, k, c));
            }
        }
    }
    let (_, k, c) = best?;
    let y = format!(
        "reaction:{}.{}",
        first.reactions[k].support, SOLID_REACTION_QUANTITIES[c]
    );
    let x = match first.probes.first() {
        Some(p) => format!("probe:{}.{}", p.probe, SOLID_PROBE_QUANTITIES[c]),
        None => "time".to_string(),
    };
    Some([x, y])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(increment: usize, f: f64) -> HistoryRow {
        HistoryRow {
            increment,
            step: "s".into(),
            step_index: 1,
            load_factor: increment as f64 / 2.0,
            time: increment as f64 / 2.0,
            reactions: vec![ReactionHistory {
                support: "base".into(),
                fx: 0.1 * f,
                fy: f,
                fz: None,
            }],
            interfaces: vec![InterfaceHistory {
                interface: "c".into(),
                force_n: f,
                force_s: 0.0,
                fx: None,
                fy: None,
                fz: None,
                contact_length: 2.0,
                max_pressure: 3.0,
            }],
            probes: vec![ProbeHistory {
                probe: "tip".into(),
                ux: 0.0,
                uy: -f / 100.0,
                uz: None,
            }],
        }
    }

    /// The columns are named kind:name.quantity in the model's order and hold
    /// every row's value; the default plot is the largest reaction component
    /// (fy here) against the first probe's displacement in its direction.
    #[test]
    fn columns_are_named_and_filled() {
        let rows = [row(1, 2.0), row(2, 4.0)];
        let cols = columns(&rows);
        let names: Vec<&str> = cols.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [
                "increment",
                "step",
                "step_index",
                "load_factor",
                "time",
                "reaction:base.fx",
                "reaction:base.fy",
                "interface:c.force_n",
                "interface:c.force_s",
                "interface:c.contact_length",
                "interface:c.max_pressure",
                "probe:tip.ux",
                "probe:tip.uy"
            ]
        );
        assert_eq!(numbers(&cols, "reaction:base.fy"), Some(vec![2.0, 4.0]));
        assert_eq!(numbers(&cols, "probe:tip.uy"), Some(vec![-0.02, -0.04]));
        assert_eq!(numbers(&cols, "increment"), Some(vec![1.0, 2.0]));
        assert_eq!(numbers(&cols, "step"), None);
        assert_eq!(
            default_plot(&rows),
            Some(["probe:tip.uy".to_string(), "reaction:base.fy".to_string()])
        );
        assert!(columns(&[]).is_empty());
    }

    /// A solid model's rows (z components present) add the `fz`, the
    /// interface resultant's `fx|fy|fz` and the `uz` columns, filled from the
    /// rows; the default plot follows the reaction's z component when it
    /// varies most, against the probe's uz.
    #[test]
    fn solid_columns_add_the_z_components() {
        let solid = |increment: usize, f: f64| {
            let mut r = row(increment, f);
            r.reactions[0].fz = Some(-3.0 * f);
            (r.interfaces[0].fx, r.interfaces[0].fy, r.interfaces[0].fz) =
                (Some(0.0), Some(0.5), Some(3.0 * f));
            r.probes[0].uz = Some(-f / 50.0);
            r
        };
        let rows = [solid(1, 2.0), solid(2, 4.0)];
        let cols = columns(&rows);
        let names: Vec<&str> = cols.iter().map(|(n, _)| n.as_str()).collect();
        let want = column_names_in(
            3,
            ["base"].into_iter(),
            ["c"].into_iter(),
            ["tip"].into_iter(),
        );
        assert_eq!(names, want);
        assert_eq!(
            &names[5..],
            [
                "reaction:base.fx",
                "reaction:base.fy",
                "reaction:base.fz",
                "interface:c.force_n",
                "interface:c.force_s",
                "interface:c.fx",
                "interface:c.fy",
                "interface:c.fz",
                "interface:c.contact_length",
                "interface:c.max_pressure",
                "probe:tip.ux",
                "probe:tip.uy",
                "probe:tip.uz"
            ]
        );
        assert_eq!(numbers(&cols, "reaction:base.fz"), Some(vec![-6.0, -12.0]));
        assert_eq!(numbers(&cols, "interface:c.fz"), Some(vec![6.0, 12.0]));
        assert_eq!(numbers(&cols, "probe:tip.uz"), Some(vec![-0.04, -0.08]));
        assert_eq!(
            default_plot(&rows),
            Some(["probe:tip.uz".to_string(), "reaction:base.fz".to_string()])
        );
        // A plane model's names are unchanged.
        let plane = column_names(["base"].into_iter(), ["c"].into_iter(), ["tip"].into_iter());
        assert_eq!(plane.len(), 5 + 2 + 4 + 2);
    }
}
