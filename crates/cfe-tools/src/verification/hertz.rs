//! Hertz contact of a cylinder on a block (plane strain, different materials),
//! with the frictionless law: the contact half-width and the peak pressure
//! against Hertz's closed form under refinement, the pressure profile against
//! p₀√(1 − x²/a²), and the independence of the answer from the penalty c_n with
//! augmented-Lagrangian enforcement; and Cattaneo–Mindlin's partial slip with
//! the Coulomb law, loaded in two steps (normal force, then tangential force).
//!
//! ```text
//!              ↓ ↓ ↓ ↓  P′ on the diameter y = R ("load")
//!        _______________________
//!        \     cylinder (steel) /     node part: the arc's nodes within
//!         '-._             _.-'       search_distance of the block's face pair
//!   __________'-._______.-'__________  with it, at initial gap g₀ = R − √(R² − x²)
//!  |     block (aluminium, host)     |
//!  |_________________________________|  base clamped
//! ```
//!
//! The meshes are examples/hertz/hertz.geo at n = 4, 8, 16, 32 elements per
//! contact half-width a₀ = 1 mm (crates/cfe-tools/meshes/hertz_n*.msh; the
//! example itself uses n = 10), graded from the contact outwards.
//!
//! **Extraction.** The pressure of a pair is its normal force over its tributary
//! length on the cylinder's arc (half of each adjoining arc edge) times the
//! cylinder's thickness t ([`cfe::coupling::traction`]; t = 1 here, so the loads
//! are per unit thickness, P′ in N/mm). a and p₀ come
//! from a least-squares fit of p² = p₀² − (p₀²/a²)(x − x₀)² over the pairs carrying
//! pressure, the outermost one on each side left out when there are more than
//! ten ([`fit_ellipse`]); the
//! "edge" half-width — from the outermost closed pair to half-way to its open
//! neighbour ([`edge_half_width`]) — is shown beside it: it can only move in steps
//! of the arc's spacing.

use super::closed_forms::{
    Fitted, contact_modulus, edge_half_width, fit_ellipse, hertz_half_width, hertz_peak,
    hertz_pressure,
};
use super::{Case, Plot, Table, orders, prepare, sci, solve};
use cfe::analysis::Analysis;
use cfe::error::{Error, Result};
use cfe::output::chart::Series;
use cfe::solve::nonlinear::IncrementResult;
use std::collections::HashMap;

/// Cylinder (steel): E₁, ν₁.
pub const CYLINDER: (f64, f64) = (210000.0, 0.3);
/// Block (aluminium): E₂, ν₂.
pub const BLOCK: (f64, f64) = (70000.0, 0.33);
/// Cylinder radius.
pub const R: f64 = 10.0;
/// Load per unit length (N/mm).
pub const LOAD: f64 = 4000.0;
/// How far from the block's face the arc's nodes are paired (g₀ up to 0.5:
/// |x| up to 3.2 mm, about 3.4 a).
pub const SEARCH: f64 = 0.5;

/// The mesh file of level n (elements per contact half-width).
pub fn mesh_file(n: usize) -> String {
    format!("{}/meshes/hertz_n{n}.msh", env!("CARGO_MANIFEST_DIR"))
}

/// Hertz's a and p₀ of the case.
pub fn reference() -> (f64, f64) {
    let es = contact_modulus(CYLINDER.0, CYLINDER.1, BLOCK.0, BLOCK.1);
    let a = hertz_half_width(LOAD, R, es);
    (a, hertz_peak(LOAD, a))
}

/// The problem at mesh level `n` with the interface's law and enforcement
/// lines `law` (e.g. `law = "frictionless"`), cylinder material `cyl`, and the
/// load `[q, −P′]` on the cylinder, the cylinder's axis held in x at `axis`
/// (centre and bottom) when true.
pub fn problem(n: usize, law: &str, cyl: (f64, f64), load: [f64; 2], axis: bool) -> String {
    let file = mesh_file(n);
    let axis_supports = if axis {
        "[[support]]\npart = \"cylinder\"\nat = [0.0, 10.0]\nfix = [\"x\"]\n[[support]]\npart = \"cylinder\"\nat = [0.0, 0.0]\nfix = [\"x\"]\n"
    } else {
        ""
    };
    format!(
        r#"plane = "strain"
[materials.cyl]
E = {:?}
nu = {:?}
[materials.block]
E = {:?}
nu = {:?}
[[part]]
name = "block"
material = "block"
gmsh = {{ file = "{file}", surfaces = ["block"] }}
[[part]]
name = "cylinder"
material = "cyl"
gmsh = {{ file = "{file}", surfaces = ["cylinder"] }}
[[interface]]
name = "contact"
host = "block"
nodes = "cylinder"
boundary = "arc"
search_distance = {SEARCH:?}
{law}
[[support]]
part = "block"
boundary = "base"
fix = ["x", "y"]
{axis_supports}[[load]]
part = "cylinder"
boundary = "load"
force = [{:?}, {:?}]
[analysis]
increments = 1
"#,
        cyl.0, cyl.1, BLOCK.0, BLOCK.1, load[0], load[1]
    )
}

/// One pair on the arc: its position, normal force (compression positive),
/// tangential force, tributary length, pressure and shear traction (stresses:
/// the forces over the tributary length × the cylinder's thickness).
#[derive(Debug, Clone, Copy)]
pub struct ArcPair {
    /// x of the coupling node.
    pub x: f64,
    /// Normal force on the cylinder (compression positive).
    pub f_n: f64,
    /// Tangential force on the cylinder.
    pub f_s: f64,
    /// Tributary length on the arc.
    pub length: f64,
    /// f_n / (length × t).
    pub pressure: f64,
    /// f_s / (length × t).
    pub shear: f64,
}

/// The thickness t of the first interface's node part (the cylinder): the
/// forces are over it, P′ = Σ f_n / t per unit thickness.
fn node_thickness(a: &Analysis) -> f64 {
    a.model.parts[a.interfaces[0].node_part].material.thickness
}

/// `text` (a problem) with every part given the thickness `t`: a load scaled by t
/// with it leaves the displacements, the per-unit-thickness forces and the
/// tractions unchanged.
pub fn with_thickness(text: &str, t: f64) -> String {
    text.replace("[[part]]\n", &format!("[[part]]\nthickness = {t:?}\n"))
}

/// Tributary lengths of the nodes of boundary `name` of part `part`: half of
/// each adjoining boundary edge.
pub fn tributary(a: &Analysis, part: usize, name: &str) -> Result<HashMap<usize, f64>> {
    let m = &a.model.parts[part].mesh;
    let edges = m
        .boundaries
        .get(name)
        .ok_or_else(|| Error::Model(format!("no boundary '{name}'")))?;
    let mut t = HashMap::new();
    for e in edges {
        let l = cfe::mesh::dist(m.nodes[e.nodes[0]], m.nodes[e.nodes[1]]);
        for &n in &e.nodes {
            *t.entry(n).or_insert(0.0) += l / 2.0;
        }
    }
    Ok(t)
}

/// The pairs of the first interface at increment `inc`, sorted by x, with their
/// pressure and shear from the forces, the tributary lengths on `boundary` and
/// the node part's thickness.
pub fn arc_pairs(a: &Analysis, inc: &IncrementResult, boundary: &str) -> Result<Vec<ArcPair>> {
    let iface = &a.interfaces[0];
    let trib = tributary(a, iface.node_part, boundary)?;
    let t = node_thickness(a);
    let mut out: Vec<ArcPair> = a
        .pair_rows(inc)
        .iter()
        .filter(|r| r.interface == iface.name)
        .map(|r| {
            let length = trib.get(&r.node).copied().unwrap_or(f64::NAN);
            ArcPair {
                x: r.x,
                f_n: r.force_n,
                f_s: r.force_s,
                length,
                pressure: cfe::coupling::traction(r.force_n, length, t),
                shear: cfe::coupling::traction(r.force_s, length, t),
            }
        })
        .collect();
    out.sort_by(|p, q| p.x.total_cmp(&q.x));
    Ok(out)
}

/// What one Hertz run gives.
#[derive(Debug, Clone)]
pub struct HertzRun {
    /// Mesh level.
    pub n: usize,
    /// Pairs (all, sorted by x).
    pub pairs: Vec<ArcPair>,
    /// The ellipse fit.
    pub fit: Fitted,
    /// The edge half-width.
    pub edge: f64,
    /// Σ f_n over the pairs per unit thickness (/ t): the P′ they carry.
    pub total: f64,
    /// Largest pair pressure.
    pub p_max: f64,
    /// Pairs carrying pressure.
    pub closed: usize,
    /// Linear solves of the run.
    pub solves: usize,
}

/// Solves the problem `text` and measures it.
pub fn measure(text: &str, n: usize) -> Result<HertzRun> {
    let a = prepare(text)?;
    let incs = solve(&a)?;
    let inc = incs.last().expect("one increment");
    let pairs = arc_pairs(&a, inc, "arc")?;
    let pts: Vec<(f64, f64)> = pairs.iter().map(|p| (p.x, p.pressure.max(0.0))).collect();
    let fit = fit_ellipse(&pts)
        .ok_or_else(|| Error::Model("the Hertz pressure profile could not be fitted".into()))?;
    Ok(HertzRun {
        n,
        edge: edge_half_width(&pts).unwrap_or(0.0),
        total: pairs.iter().map(|p| p.f_n).sum::<f64>() / node_thickness(&a),
        p_max: pairs.iter().map(|p| p.pressure).fold(0.0, f64::max),
        closed: pairs.iter().filter(|p| p.pressure > 0.0).count(),
        solves: incs.iter().map(|i| i.iterations).sum(),
        pairs,
        fit,
    })
}

/// The frictionless law's lines.
const FRICTIONLESS: &str = "law = \"frictionless\"";

/// The Hertz convergence study.
pub fn hertz(quick: bool) -> Result<Case> {
    // The quick report ends at n = 16, not 8: at n = 8 the contact's edge is
    // resolved by two pairs a side, and the segment coupling's pressure there
    // alternates (about 0.6 and 1.3 × Hertz's), which moves its fitted a by
    // +13 % while its p₀ is within 1 % (the verdict says so whenever a coarser
    // level misses 2 %). The criteria are applied at the finest level.
    let levels: &[usize] = if quick { &[4, 8, 16] } else { &[4, 8, 16, 32] };
    let (a_ref, p0_ref) = reference();
    let mut runs = Vec::new();
    for &n in levels {
        runs.push(measure(
            &problem(n, FRICTIONLESS, CYLINDER, [0.0, -LOAD], true),
            n,
        )?);
    }
    // The same levels with the segment coupling (the gap averaged over each
    // node's face segments).
    let mut seg_runs = Vec::new();
    for &n in levels {
        seg_runs.push(measure(
            &problem(n, SEGMENT, CYLINDER, [0.0, -LOAD], true),
            n,
        )?);
    }
    let err_a: Vec<f64> = runs.iter().map(|r| r.fit.a / a_ref - 1.0).collect();
    let err_p: Vec<f64> = runs.iter().map(|r| r.fit.p0 / p0_ref - 1.0).collect();
    let (oa, op) = (orders(&err_a), orders(&err_p));
    let mut table = Table {
        caption: format!(
            "Hertz under refinement: n elements per a₀ = 1 mm on the cylinder near the contact (h = 1/n; the block 1.25/n). a and p₀ from the least-squares fit of p² (module doc); the edge half-width from the outermost closed pair and half-way to its open neighbour; p_max the largest pair pressure. Hertz: a = {a_ref:.5}, p₀ = {p0_ref:.2}. Σ f_n is the pairs' total normal force against P′ = {LOAD}."
        ),
        header: [
            "n",
            "pairs closed",
            "a (fit)",
            "error",
            "order",
            "a (edge)",
            "error",
            "p₀ (fit)",
            "error",
            "order",
            "p_max",
            "error",
            "Σ f_n / P′ − 1",
            "solves",
        ]
        .map(String::from)
        .to_vec(),
        rows: Vec::new(),
    };
    for (i, r) in runs.iter().enumerate() {
        table.rows.push(vec![
            r.n.to_string(),
            r.closed.to_string(),
            format!("{:.5}", r.fit.a),
            format!("{:+.2} %", 100.0 * err_a[i]),
            oa[i].clone(),
            format!("{:.5}", r.edge),
            format!("{:+.2} %", 100.0 * (r.edge / a_ref - 1.0)),
            format!("{:.1}", r.fit.p0),
            format!("{:+.2} %", 100.0 * err_p[i]),
            op[i].clone(),
            format!("{:.1}", r.p_max),
            format!("{:+.2} %", 100.0 * (r.p_max / p0_ref - 1.0)),
            sci(r.total / LOAD - 1.0),
            r.solves.to_string(),
        ]);
    }
    let last = runs.len() - 1;
    let within = err_a[last].abs() < 0.02 && err_p[last].abs() < 0.02;
    let falling = err_a[last].abs() < err_a[0].abs() && err_p[last].abs() < err_p[0].abs();
    let balanced = runs
        .iter()
        .chain(&seg_runs)
        .all(|r| (r.total / LOAD - 1.0).abs() < 1e-6);
    let (seg_table, seg_within) = coupling_table(&runs, &seg_runs, a_ref, p0_ref);
    let passed = within && falling && balanced && seg_within;
    let smooth = |r: &HertzRun, f: f64| profile_rms(&r.pairs, f * a_ref, a_ref, p0_ref);
    let plots = vec![
        profile_plot(&runs, a_ref, p0_ref),
        coupling_plot(&runs[last], &seg_runs[last], a_ref, p0_ref),
        Plot {
            file: "hertz_convergence.png".into(),
            title: "Hertz: errors of a and p₀ under refinement".into(),
            x: "elements per a₀ (n)".into(),
            y: "|relative error|".into(),
            log: (true, true),
            series: vec![
                Series {
                    name: "a (fit)".into(),
                    points: runs
                        .iter()
                        .zip(&err_a)
                        .map(|(r, e)| (r.n as f64, e.abs().max(1e-6)))
                        .collect(),
                    reference: false,
                },
                Series {
                    name: "p₀ (fit)".into(),
                    points: runs
                        .iter()
                        .zip(&err_p)
                        .map(|(r, e)| (r.n as f64, e.abs().max(1e-6)))
                        .collect(),
                    reference: false,
                },
            ],
        },
    ];
    Ok(Case {
        title: "Hertz: cylinder on a block (frictionless, initial gaps)".into(),
        setup: format!(
            "A steel cylinder (E₁ = {}, ν₁ = {}, R = {R}) pressed on an aluminium block (E₂ = {}, ν₂ = {}, 40 × 20, base clamped) by P′ = {LOAD} N/mm, plane strain — examples/hertz/hertz.toml at mesh levels n = {:?} (Gmsh, hertz.geo; graded towards the contact). The cylinder's arc is the node part's boundary; `search_distance = {SEARCH}` pairs its nodes with the block's face at their initial gaps g₀ = R − √(R² − x²) (nodes not moved); law `frictionless`, default penalty. The cylinder's axis is held in x at its centre and bottom (symmetry). One increment (the active set finds the contact zone). Every level is solved with the node coupling (first table) and again with `coupling = \"segment\"` (second table): there every Gauss point of the arc's segments is paired with its nearest face edge within the search distance and the node's initial gap is their N_a-weighted mean (a node with a segment point beyond the distance is unpaired, so the segment runs have one pair fewer at each end).\n\n```text\n              ↓ ↓ ↓ ↓  P′ on the diameter y = R\n        _______________________\n        \\     cylinder (steel) /\n         '-._             _.-'\n   __________'-._______.-'__________\n  |     block (aluminium, host)     |\n  |_________________________________|  base clamped\n```",
            CYLINDER.0, CYLINDER.1, BLOCK.0, BLOCK.1, levels
        ),
        reference: format!(
            "Hertz, plane strain (K. L. Johnson, *Contact Mechanics*, 1985, §4.2, §5.6): 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂, a = √(4P′R/(πE*)) = {a_ref:.5}, p₀ = 2P′/(πa) = {p0_ref:.2}, p(x) = p₀√(1 − x²/a²). a/R = {:.3}: the bodies are large against a, as the half-plane theory assumes.",
            a_ref / R
        ),
        tables: vec![table, seg_table],
        plots,
        verdict: format!(
            "At the finest level (n = {}) a is off by {:+.2} % and p₀ by {:+.2} % (criterion 2 %), both errors smaller than at the coarsest level; the pairs carry P′ to {:.1e}. With the segment coupling a is off by {:+.2} % and p₀ by {:+.2} %, and the pressure profile is smoother: its RMS deviation from Hertz's over |x| < 0.8 a is {:.2} % of p₀ against the node coupling's {:.2} % (the node coupling's dip at x = 0, p/p₀ = {:.3}, is gone: {:.3}); near the edge of the contact both depart from the ellipse by a pair spacing's worth (RMS over |x| < a: {:.2} % and {:.2} %). Pass criteria (2 % at the finest level with either coupling, node errors falling, load balanced): {}.",
            runs[last].n,
            100.0 * err_a[last],
            100.0 * err_p[last],
            runs.iter()
                .chain(&seg_runs)
                .map(|r| (r.total / LOAD - 1.0).abs())
                .fold(0.0, f64::max),
            100.0 * (seg_runs[last].fit.a / a_ref - 1.0),
            100.0 * (seg_runs[last].fit.p0 / p0_ref - 1.0),
            100.0 * smooth(&seg_runs[last], 0.8),
            100.0 * smooth(&runs[last], 0.8),
            centre_pressure(&runs[last]) / p0_ref,
            centre_pressure(&seg_runs[last]) / p0_ref,
            100.0 * smooth(&seg_runs[last], 1.0),
            100.0 * smooth(&runs[last], 1.0),
            if passed { "met" } else { "NOT met" }
        ) + &coarse_misses(&seg_runs, a_ref, p0_ref),
        passed,
    })
}

/// The verdict's note on the segment coupling's coarser levels whose fitted a or
/// p₀ is off by 2 % or more (the criteria apply at the finest level only): at
/// n = 8 its pressure alternates over the contact's last two pairs a side, which
/// the fit of p² follows. Empty when every level is within 2 %.
fn coarse_misses(seg: &[HertzRun], a: f64, p0: f64) -> String {
    let misses: Vec<String> = seg[..seg.len().saturating_sub(1)]
        .iter()
        .filter(|r| (r.fit.a / a - 1.0).abs() >= 0.02 || (r.fit.p0 / p0 - 1.0).abs() >= 0.02)
        .map(|r| {
            format!(
                "n = {}: a {:+.2} %, p₀ {:+.2} %",
                r.n,
                100.0 * (r.fit.a / a - 1.0),
                100.0 * (r.fit.p0 / p0 - 1.0)
            )
        })
        .collect();
    if misses.is_empty() {
        return String::new();
    }
    format!(
        " With the segment coupling the coarser levels miss 2 % ({}): there the contact's edge is resolved by a pair or two a side and the segment coupling's pressure alternates over them (a known limit of its per-node contact decision at coarse edges; the node coupling's does not), and the fit of p² follows it; the criteria are applied at the finest level, n = {}.",
        misses.join("; "),
        seg[seg.len() - 1].n
    )
}

/// The frictionless law's lines with the segment coupling.
const SEGMENT: &str = "law = \"frictionless\"\ncoupling = \"segment\"";

/// The RMS of (p − p_Hertz) / p₀ over the pairs with |x| < `within`.
pub fn profile_rms(pairs: &[ArcPair], within: f64, a: f64, p0: f64) -> f64 {
    let (mut e2, mut m) = (0.0, 0usize);
    for p in pairs.iter().filter(|p| p.x.abs() < within) {
        e2 += ((p.pressure - hertz_pressure(p.x, a, p0)) / p0).powi(2);
        m += 1;
    }
    (e2 / m.max(1) as f64).sqrt()
}

/// The pressure of the pair nearest to x = 0.
fn centre_pressure(r: &HertzRun) -> f64 {
    r.pairs
        .iter()
        .min_by(|p, q| p.x.abs().total_cmp(&q.x.abs()))
        .map_or(f64::NAN, |p| p.pressure)
}

/// The node and segment couplings side by side at every level: a, p₀, the centre
/// pressure and the profile's RMS deviation from Hertz's; and whether the
/// segment coupling's a and p₀ are within 2 % at the finest level.
fn coupling_table(node: &[HertzRun], seg: &[HertzRun], a: f64, p0: f64) -> (Table, bool) {
    let mut table = Table {
        caption: format!(
            "The node coupling (one pair per arc node, its gap collocated at the node) against the segment coupling (`coupling = \"segment\"`: each node's gap g₀_a + [[u_n]]_a averaged over its two arc segments with the weight N_a, g₀_a = ∫ N_a g₀ ds / m_a) on the same meshes. p(0): the pressure of the pair at x = 0; RMS: the root mean square of (p − p₀√(1 − x²/a²)) / p₀ over the pairs within |x| < 0.5 a, 0.8 a and a (Hertz's a = {a:.5}, p₀ = {p0:.2})."
        ),
        header: [
            "n",
            "coupling",
            "pairs",
            "closed",
            "a (fit) error",
            "p₀ (fit) error",
            "p_max error",
            "p(0)/p₀",
            "RMS |x| < 0.5a",
            "RMS |x| < 0.8a",
            "RMS |x| < a",
        ]
        .map(String::from)
        .to_vec(),
        rows: Vec::new(),
    };
    for (rn, rs) in node.iter().zip(seg) {
        for (name, r) in [("node", rn), ("segment", rs)] {
            table.rows.push(vec![
                r.n.to_string(),
                name.into(),
                r.pairs.len().to_string(),
                r.closed.to_string(),
                format!("{:+.2} %", 100.0 * (r.fit.a / a - 1.0)),
                format!("{:+.2} %", 100.0 * (r.fit.p0 / p0 - 1.0)),
                format!("{:+.2} %", 100.0 * (r.p_max / p0 - 1.0)),
                format!("{:.3}", centre_pressure(r) / p0),
                format!("{:.2} %", 100.0 * profile_rms(&r.pairs, 0.5 * a, a, p0)),
                format!("{:.2} %", 100.0 * profile_rms(&r.pairs, 0.8 * a, a, p0)),
                format!("{:.2} %", 100.0 * profile_rms(&r.pairs, a, a, p0)),
            ]);
        }
    }
    let last = &seg[seg.len() - 1];
    let within = (last.fit.a / a - 1.0).abs() < 0.02 && (last.fit.p0 / p0 - 1.0).abs() < 0.02;
    (table, within)
}

/// The finest level's pressure profiles with the node and the segment coupling
/// against Hertz's ellipse.
fn coupling_plot(node: &HertzRun, seg: &HertzRun, a: f64, p0: f64) -> Plot {
    let profile = |r: &HertzRun| -> Vec<(f64, f64)> {
        r.pairs
            .iter()
            .filter(|p| p.x.abs() < 1.5 * a)
            .map(|p| (p.x, p.pressure))
            .collect()
    };
    Plot {
        file: "hertz_pressure_coupling.png".into(),
        title: format!("Hertz at n = {}: node against segment coupling", node.n),
        x: "x (mm)".into(),
        y: "pressure (MPa)".into(),
        log: (false, false),
        series: vec![
            Series {
                name: "node coupling".into(),
                points: profile(node),
                reference: false,
            },
            Series {
                name: "segment coupling".into(),
                points: profile(seg),
                reference: false,
            },
            Series {
                name: "Hertz p₀√(1 − x²/a²)".into(),
                points: (0..=200)
                    .map(|i| {
                        let x = -1.5 * a + 3.0 * a * i as f64 / 200.0;
                        (x, hertz_pressure(x, a, p0))
                    })
                    .collect(),
                reference: true,
            },
        ],
    }
}

/// The pressure profiles of the runs against Hertz's ellipse.
fn profile_plot(runs: &[HertzRun], a: f64, p0: f64) -> Plot {
    let mut series: Vec<Series> = runs
        .iter()
        .map(|r| Series {
            name: format!("n = {}", r.n),
            points: r
                .pairs
                .iter()
                .filter(|p| p.x.abs() < 1.5 * a)
                .map(|p| (p.x, p.pressure))
                .collect(),
            reference: false,
        })
        .collect();
    series.push(Series {
        name: "Hertz p₀√(1 − x²/a²)".into(),
        points: (0..=200)
            .map(|i| {
                let x = -1.5 * a + 3.0 * a * i as f64 / 200.0;
                (x, hertz_pressure(x, a, p0))
            })
            .collect(),
        reference: true,
    });
    Plot {
        file: "hertz_pressure.png".into(),
        title: "Hertz: contact pressure along the block's face".into(),
        x: "x (mm)".into(),
        y: "pressure (MPa)".into(),
        log: (false, false),
        series,
    }
}

/// The penalties of the c_n study, as multiples of the block's E·t.
const PENALTY_FACTORS: [f64; 5] = [1.0, 10.0, 100.0, 1000.0, 10000.0];
/// The augmented-Lagrangian penetration tolerance of the c_n study (mm): 1e-4 of
/// the cylinder's approach at the contact (about a²/(2R) ≈ 0.04 mm).
pub const PENETRATION_TOLERANCE: f64 = 4e-6;

/// Hertz's a and p₀ over four decades of c_n, with the penalty alone and with
/// augmented-Lagrangian enforcement.
pub fn penalty_independence(quick: bool) -> Result<Case> {
    let n = if quick { 8 } else { 16 };
    let (a_ref, p0_ref) = reference();
    let mut table = Table {
        caption: format!(
            "Hertz at mesh level n = {n} with c_n = factor × E_block·t (E_block·t = {}), penalty alone and augmented Lagrangian (`enforcement = \"augmented\"`, `penetration_tolerance = {PENETRATION_TOLERANCE:e}` mm). a and p₀ by the fit of p²; spread = (largest − smallest)/Hertz over the factors.",
            BLOCK.0
        ),
        header: [
            "c_n / (E·t)",
            "penalty: a",
            "p₀",
            "augmented: a",
            "p₀",
            "augmented: solves",
        ]
        .map(String::from)
        .to_vec(),
        rows: Vec::new(),
    };
    let mut pen = Vec::new();
    let mut aug = Vec::new();
    for f in PENALTY_FACTORS {
        let c = f * BLOCK.0;
        let p = measure(
            &problem(
                n,
                &format!("{FRICTIONLESS}\nc_n = {c:e}"),
                CYLINDER,
                [0.0, -LOAD],
                true,
            ),
            n,
        )?;
        let g = measure(
            &problem(
                n,
                &format!(
                    "{FRICTIONLESS}\nc_n = {c:e}\nenforcement = \"augmented\"\npenetration_tolerance = {PENETRATION_TOLERANCE:e}"
                ),
                CYLINDER,
                [0.0, -LOAD],
                true,
            ),
            n,
        )?;
        table.rows.push(vec![
            format!("{f:e}"),
            format!("{:.5}", p.fit.a),
            format!("{:.1}", p.fit.p0),
            format!("{:.5}", g.fit.a),
            format!("{:.1}", g.fit.p0),
            g.solves.to_string(),
        ]);
        pen.push(p);
        aug.push(g);
    }
    let spread = |runs: &[HertzRun], f: fn(&HertzRun) -> f64, r: f64| {
        let v: Vec<f64> = runs.iter().map(f).collect();
        (v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min))
            / r
    };
    let (pa, pp) = (
        spread(&pen, |r| r.fit.a, a_ref),
        spread(&pen, |r| r.fit.p0, p0_ref),
    );
    let (ga, gp) = (
        spread(&aug, |r| r.fit.a, a_ref),
        spread(&aug, |r| r.fit.p0, p0_ref),
    );
    table.rows.push(vec![
        "spread".into(),
        format!("{:.2} %", 100.0 * pa),
        format!("{:.2} %", 100.0 * pp),
        format!("{:.3} %", 100.0 * ga),
        format!("{:.3} %", 100.0 * gp),
        String::new(),
    ]);
    // Converged augmented runs agree to well under the discretization error;
    // the penalty alone drifts with c_n.
    let passed = ga < 0.002 && gp < 0.002 && pa.max(pp) > ga.max(gp);
    Ok(Case {
        title: "Augmented Lagrangian: Hertz independent of c_n".into(),
        setup: format!(
            "The Hertz case (previous section) at mesh level n = {n}, frictionless, with c_n from 1 to 10⁴ × E·t of the block (four decades), solved with the penalty alone and with augmented-Lagrangian (Uzawa) iterations until the largest penetration is below {PENETRATION_TOLERANCE:e} mm."
        ),
        reference: "Once the augmented iterations converge the multipliers carry the contact force and the answer is that of exact enforcement, whatever c_n; the penalty alone leaves a penetration f_n/c_n, which softens the contact and widens it as c_n falls.".into(),
        tables: vec![table],
        plots: vec![],
        verdict: format!(
            "With augmented enforcement a and p₀ vary by {:.3} % and {:.3} % of Hertz's values over four decades of c_n (criterion 0.2 %); with the penalty alone by {:.2} % and {:.2} %: {}.",
            100.0 * ga,
            100.0 * gp,
            100.0 * pa,
            100.0 * pp,
            if passed { "met" } else { "NOT met" }
        ),
        passed,
    })
}

/// Friction coefficient of the Cattaneo–Mindlin case.
pub const MU: f64 = 0.3;
/// The tangential force of the Cattaneo–Mindlin case as a fraction of μP′.
pub const Q_RATIO: f64 = 0.5;

/// The Cattaneo–Mindlin problem at mesh level `n`, in two load steps: `normal`
/// (`normal_increments`) presses the cylinder on the block with P′ = [`LOAD`]
/// on its diameter; `shear` (`shear_increments`) adds the tangential force
/// Q = [`Q_RATIO`] μP′ on the diameter with the couple that puts its line of
/// action through the first point of contact (±Q/2 vertical at the diameter's
/// ends), so that the contact carries P′ and Q without a moment, as the
/// closed form assumes. Both parts steel (Dundurs' β = 0), Coulomb friction μ;
/// the cylinder is held by the contact alone. Both parts have the thickness
/// `thickness` and the loads are P′ and Q per unit thickness times it.
pub fn cattaneo_problem(
    n: usize,
    normal_increments: usize,
    shear_increments: usize,
    thickness: f64,
) -> String {
    let file = mesh_file(n);
    let load = LOAD * thickness;
    let q = Q_RATIO * MU * load;
    let text = format!(
        r#"plane = "strain"
[materials.steel]
E = {:?}
nu = {:?}
[[part]]
name = "block"
material = "steel"
gmsh = {{ file = "{file}", surfaces = ["block"] }}
[[part]]
name = "cylinder"
material = "steel"
gmsh = {{ file = "{file}", surfaces = ["cylinder"] }}
[[interface]]
name = "contact"
host = "block"
nodes = "cylinder"
boundary = "arc"
law = "coulomb"
friction = {MU:?}
search_distance = {SEARCH:?}
[[support]]
part = "block"
boundary = "base"
fix = ["x", "y"]
[[step]]
name = "normal"
increments = {normal_increments}
[[step]]
name = "shear"
increments = {shear_increments}
[[load]]
part = "cylinder"
boundary = "load"
force = [0.0, {:?}]
step = "normal"
[[load]]
part = "cylinder"
boundary = "load"
force = [{q:?}, 0.0]
step = "shear"
[[load]]
part = "cylinder"
at = [{R:?}, {R:?}]
force = [0.0, {:?}]
step = "shear"
[[load]]
part = "cylinder"
at = [{:?}, {R:?}]
force = [0.0, {:?}]
step = "shear"
"#,
        CYLINDER.0,
        CYLINDER.1,
        -load,
        q / 2.0,
        -R,
        -q / 2.0
    );
    with_thickness(&text, thickness)
}

/// One level of the Cattaneo–Mindlin study: the measures of its last increment.
#[derive(Debug, Clone)]
pub struct CattaneoRun {
    /// Mesh level.
    pub n: usize,
    /// P′: the pairs' total normal force per unit thickness (Σ f_n / t).
    pub p_total: f64,
    /// Q: the pairs' total tangential force per unit thickness, in the direction
    /// of the applied Q (positive).
    pub q: f64,
    /// Hertz's half-width for P′.
    pub a_h: f64,
    /// Hertz's peak pressure for P′.
    pub p0: f64,
    /// The half-width of the ellipse fitted to the pairs' pressures.
    pub fit_a: f64,
    /// The closed form's stick half-width c.
    pub c_ref: f64,
    /// The run's stick half-width.
    pub c_h: f64,
    /// Sticking (bonded) pairs.
    pub stick: usize,
    /// Slipping pairs.
    pub slip: usize,
    /// RMS of the shear traction's error over the contact, relative to μp₀.
    pub rms: f64,
    /// The pairs' normal force at the end of the normal step and at the end,
    /// the largest change relative to the largest force (β = 0: none expected).
    pub pressure_change: f64,
    /// The sign of the applied Q along x.
    pub sign: f64,
    /// The pairs (all, sorted by x).
    pub pairs: Vec<ArcPair>,
}

/// Solves the Cattaneo–Mindlin problem at mesh level `n` with parts of
/// thickness `thickness` (and loads scaled with it) and measures it.
pub fn cattaneo_run(n: usize, shear_increments: usize, thickness: f64) -> Result<CattaneoRun> {
    let a = prepare(&cattaneo_problem(n, 1, shear_increments, thickness))?;
    let incs = solve(&a)?;
    let inc = incs.last().expect("increments");
    let normal = incs
        .iter()
        .rfind(|i| i.step == 0)
        .ok_or_else(|| Error::Model("the normal step has no increment".into()))?;
    let before = arc_pairs(&a, normal, "arc")?;
    let pairs = arc_pairs(&a, inc, "arc")?;
    let rows = a.pair_rows(inc);
    // Per unit thickness, as the closed form's P′ and Q.
    let t = node_thickness(&a);
    let p_total: f64 = pairs.iter().map(|p| p.f_n).sum::<f64>() / t;
    let q_total: f64 = pairs.iter().map(|p| p.f_s).sum::<f64>() / t;
    let sign = q_total.signum();
    // Q: the tangential force the pairs carry (= the applied Q, by equilibrium).
    let q = sign * q_total;
    let es = contact_modulus(CYLINDER.0, CYLINDER.1, CYLINDER.0, CYLINDER.1);
    let a_h = hertz_half_width(p_total, R, es);
    let p0 = hertz_peak(p_total, a_h);
    let c_ref = super::closed_forms::stick_half_width(a_h, q, MU, p_total);
    // The stick zone: the bonded (sticking) pairs among the closed ones.
    let mut by_x: Vec<(f64, cfe::coupling::PairState)> = rows
        .iter()
        .filter(|r| r.interface == "contact")
        .map(|r| (r.x, r.state))
        .collect();
    by_x.sort_by(|p, q| p.0.total_cmp(&q.0));
    let stick_pts: Vec<(f64, f64)> = by_x
        .iter()
        .map(|&(x, s)| {
            (
                x,
                f64::from(u8::from(s == cfe::coupling::PairState::Bonded)),
            )
        })
        .collect();
    let c_h = edge_half_width(&stick_pts).unwrap_or(0.0);
    let contact_pts: Vec<(f64, f64)> = pairs.iter().map(|p| (p.x, p.pressure.max(0.0))).collect();
    let fit = fit_ellipse(&contact_pts)
        .ok_or_else(|| Error::Model("the Cattaneo–Mindlin pressure could not be fitted".into()))?;
    let count = |s| by_x.iter().filter(|p| p.1 == s).count();
    let f_max = pairs.iter().map(|p| p.f_n).fold(0.0, f64::max);
    let pressure_change = before
        .iter()
        .zip(&pairs)
        .map(|(b, p)| (p.f_n - b.f_n).abs())
        .fold(0.0, f64::max)
        / f_max.max(f64::MIN_POSITIVE);
    Ok(CattaneoRun {
        n,
        p_total,
        q,
        a_h,
        p0,
        fit_a: fit.a,
        c_ref,
        c_h,
        stick: count(cfe::coupling::PairState::Bonded),
        slip: count(cfe::coupling::PairState::Slip),
        rms: shear_rms(&pairs, a_h, c_ref, p0, sign),
        pressure_change,
        sign,
        pairs,
    })
}

/// Cattaneo–Mindlin partial slip, as the load history of the closed form: a
/// first load step presses the cylinder with P′, a second adds a tangential
/// force Q = ½ μP′ (ramped over its increments) while P′ stays. Measured under
/// refinement: the stick half-width against c = a√(1 − Q/(μP′)) and the shear
/// traction against q(x).
pub fn cattaneo_mindlin(quick: bool) -> Result<Case> {
    let (levels, increments): (&[usize], usize) = if quick {
        (&[8], 4)
    } else {
        (&[4, 8, 16, 32], 8)
    };
    let mut runs = Vec::new();
    for &n in levels {
        runs.push(cattaneo_run(n, increments, 1.0)?);
    }
    let finest = runs.last().expect("one level");
    let table = Table {
        caption: format!(
            "Cattaneo–Mindlin under refinement (n elements per mm on the cylinder near the contact), μ = {MU}; step 1 \"normal\" applies P′ in one increment, step 2 \"shear\" Q in {increments}. P′ and Q are the pairs' total normal and tangential forces (equal to the applied loads by equilibrium); a, p₀, c from the closed forms with them; the stick half-width of the run from the outermost sticking pair to half-way to its slipping neighbour, each side; the shear error is the RMS of (q_h − q)/(μ p₀) over the pairs within |x| < a; \"ΔP step 2\" is the largest change of a pair's normal force during the shear step relative to the largest (β = 0: Q leaves the pressure unchanged)."
        ),
        header: [
            "n",
            "P′ (N/mm)",
            "Q (N/mm)",
            "Q/(μP′)",
            "a Hertz",
            "a (fit)",
            "error",
            "stick pairs",
            "slip pairs",
            "c closed form",
            "c (run)",
            "error",
            "shear RMS error",
            "ΔP step 2",
        ]
        .map(String::from)
        .to_vec(),
        rows: runs
            .iter()
            .map(|r| {
                vec![
                    r.n.to_string(),
                    format!("{:.1}", r.p_total),
                    format!("{:.1}", r.q),
                    format!("{:.3}", r.q / (MU * r.p_total)),
                    format!("{:.4}", r.a_h),
                    format!("{:.4}", r.fit_a),
                    format!("{:+.2} %", 100.0 * (r.fit_a / r.a_h - 1.0)),
                    r.stick.to_string(),
                    r.slip.to_string(),
                    format!("{:.4}", r.c_ref),
                    format!("{:.4}", r.c_h),
                    format!("{:+.2} %", 100.0 * (r.c_h / r.c_ref - 1.0)),
                    format!("{:.3}", r.rms),
                    format!("{:.1e}", r.pressure_change),
                ]
            })
            .collect(),
    };
    let series = cattaneo_series(
        &finest.pairs,
        finest.a_h,
        finest.c_ref,
        finest.p0,
        finest.sign,
    );
    // The spacing of the arc's nodes near the contact is 1/n: at every level c
    // within two spacings, the shear within 15 % of μp₀ (RMS), partial slip.
    let ok = |r: &CattaneoRun| {
        (r.c_h - r.c_ref).abs() < 2.0 / r.n as f64 + 1e-12
            && r.rms < 0.15
            && r.q < MU * r.p_total
            && r.slip > 0
            && r.stick > 0
    };
    let passed = runs.iter().all(ok);
    let (n, c_h, c_ref) = (finest.n, finest.c_h, finest.c_ref);
    Ok(Case {
        title: "Cattaneo–Mindlin: partial slip under a tangential load (Coulomb)".into(),
        setup: format!(
            "The Hertz cylinder and block (mesh levels n = {}), both steel (E = {}, ν = {}: Dundurs' β = 0, as the closed form assumes), Coulomb friction μ = {MU}; the cylinder is held by the contact alone. Two load steps (`[[step]]`, examples/hertz/cattaneo.toml): \"normal\" applies P′ = {LOAD} N/mm on the cylinder's diameter; \"shear\" keeps it and ramps a tangential force Q = {Q_RATIO} μP′ = {} N/mm on the diameter, with the couple ±Q/2 (vertical, at the diameter's ends) that moves its line of action down to the first point of contact, so that the contact carries P′ and Q without a moment.",
            levels
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(", "),
            CYLINDER.0,
            CYLINDER.1,
            Q_RATIO * MU * LOAD
        ),
        reference: "Cattaneo (1938) and Mindlin (1949), for cylinders in K. L. Johnson, *Contact Mechanics*, 1985, §7.1: under P′ then a growing Q < μP′, stick for |x| < c = a√(1 − Q/(μP′)), slip beyond; q(x) = μp₀√(1 − x²/a²) − μp₀(c/a)√(1 − x²/c²) in the stick zone, μ p(x) in the slip zones (`closed_forms.rs`).".into(),
        tables: vec![table],
        plots: vec![Plot {
            file: "cattaneo_mindlin_shear.png".into(),
            title: format!("Cattaneo–Mindlin: shear traction along the contact (n = {n})"),
            x: "x (mm)".into(),
            y: "traction (MPa)".into(),
            log: (false, false),
            series,
        }],
        verdict: format!(
            "At the finest level the stick zone's half-width is {c_h:.4} against c = {c_ref:.4} ({:+.1} %, the pairs {:.4} apart), with {} pairs sticking and {} slipping; the shear traction follows Cattaneo–Mindlin's profile with an RMS error of {:.1} % of μp₀. Pass criteria at every level (c within two pair spacings, shear RMS below 15 % of μp₀, partial slip: Q < μP′ with pairs both sticking and slipping): {}.",
            100.0 * (c_h / c_ref - 1.0),
            1.0 / n as f64,
            finest.stick,
            finest.slip,
            100.0 * finest.rms,
            if passed { "met" } else { "NOT met" }
        ),
        passed,
    })
}

/// The RMS of the shear traction's error over the contact, (q_h − q)/(μ p₀) at
/// the pairs within |x| < a, against Cattaneo–Mindlin's q(x).
fn shear_rms(pairs: &[ArcPair], a_h: f64, c_ref: f64, p0: f64, sign: f64) -> f64 {
    let (mut e2, mut m) = (0.0, 0usize);
    for p in pairs.iter().filter(|p| p.x.abs() < a_h) {
        let exact = super::closed_forms::mindlin_shear(p.x, a_h, c_ref, MU, p0);
        e2 += ((sign * p.shear - exact) / (MU * p0)).powi(2);
        m += 1;
    }
    (e2 / m.max(1) as f64).sqrt()
}

/// The curves of the Cattaneo–Mindlin plot: the pairs' shear, μ × their pressure,
/// and the closed form's q(x).
fn cattaneo_series(pairs: &[ArcPair], a_h: f64, c_ref: f64, p0: f64, sign: f64) -> Vec<Series> {
    let mut series = vec![
        Series {
            name: "shear q_h (pairs)".into(),
            points: pairs
                .iter()
                .filter(|p| p.x.abs() < 1.3 * a_h)
                .map(|p| (p.x, sign * p.shear))
                .collect(),
            reference: false,
        },
        Series {
            name: "μ × pressure (pairs)".into(),
            points: pairs
                .iter()
                .filter(|p| p.x.abs() < 1.3 * a_h)
                .map(|p| (p.x, MU * p.pressure))
                .collect(),
            reference: false,
        },
    ];
    series.push(Series {
        name: "Cattaneo–Mindlin q(x)".into(),
        points: (0..=300)
            .map(|i| {
                let x = -1.3 * a_h + 2.6 * a_h * i as f64 / 300.0;
                (x, super::closed_forms::mindlin_shear(x, a_h, c_ref, MU, p0))
            })
            .collect(),
        reference: true,
    });
    series
}
