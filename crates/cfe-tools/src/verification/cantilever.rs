//! The tied cantilever (plane stress, L = 100, D = 10, t = 1, E = 210000, ν = 0.31,
//! 1 N end shear) split at mid-span into a coarse host and a finer node part,
//! against the Timoshenko–Goodier closed form and conforming meshes.
//!
//! ```text
//!   |▒ host (h) ▒▒▒▒▒▒▒▒▒▒▒▒|░ node part (h / r) ░░░|  ↓ P = 1 N on x = 100
//!   x = 0                  x = 50 (tied)          x = 100
//! ```
//!
//! Reference: S. P. Timoshenko, J. N. Goodier, *Theory of Elasticity*, 3rd ed.
//! (McGraw-Hill, 1970), §21 "Bending of a cantilever loaded at the end". With the
//! support at x = 0, the load P (in +y) at x = L, y ∈ [−D/2, D/2], I = t D³/12, t = 1:
//!
//! ```text
//!   σxx = −P (L − x) y / I,   σyy = 0,   σxy = P (D²/4 − y²) / (2 I)
//!   ux  = −P y / (6 E I) · [ (6L − 3x) x + (2 + ν)(y² − D²/4) ]
//!   uy  =  P / (6 E I) · [ 3ν y² (L − x) + (4 + 5ν) D² x / 4 + (3L − x) x² ]
//! ```
//!
//! (the form of A. Augarde, A. Deeks, *Finite Elements in Analysis and Design* 44
//! (2008) 595–601, with their origin moved to the support). One checks directly
//! that the strains of u are D⁻¹σ in plane stress, that σ is in equilibrium, that
//! the faces y = ±D/2 are free and that the shear on x = L sums to P. The field is
//! exact for a beam whose end x = 0 follows u(0, y) and whose end x = L carries the
//! parabolic shear: the *exact end conditions*. A fully clamped end differs from
//! them near x = 0 (the clamp also stops the section's warping), which changes the
//! tip deflection by a few tenths of a per cent.
//!
//! Tip deflection: v(L) = P L³/(3 E I) + (4 + 5ν) P D² L/(24 E I).

use super::{
    Case, Plot, Table, displacement_at, energy_density, for_each_stress_point, orders, prepare,
    sci, solve, toml_kind,
};
use cfe::analysis::Analysis;
use cfe::error::Result;
use cfe::mesh::ElementKind;
use cfe::output::chart::Series;
use cfe::solve::nonlinear::IncrementResult;
use std::collections::BTreeMap;
use std::fmt::Write as _;

const E: f64 = 210000.0;
const NU: f64 = 0.31;
const L: f64 = 100.0;
const D: f64 = 10.0;
/// End force (downwards).
const P: f64 = -1.0;

fn inertia() -> f64 {
    D.powi(3) / 12.0
}

/// Tip deflection of the Timoshenko–Goodier cantilever (downwards positive).
pub fn timoshenko_goodier() -> f64 {
    -tg_displacement(L, 0.0)[1]
}

/// The Timoshenko–Goodier displacement at (x, y).
pub fn tg_displacement(x: f64, y: f64) -> [f64; 2] {
    let i = inertia();
    let ux =
        -P * y / (6.0 * E * i) * ((6.0 * L - 3.0 * x) * x + (2.0 + NU) * (y * y - D * D / 4.0));
    let uy = P / (6.0 * E * i)
        * (3.0 * NU * y * y * (L - x) + (4.0 + 5.0 * NU) * D * D * x / 4.0 + (3.0 * L - x) * x * x);
    [ux, uy]
}

/// The Timoshenko–Goodier stress (σxx, σyy, σxy) at (x, y).
pub fn tg_stress(x: f64, y: f64) -> [f64; 3] {
    let i = inertia();
    [
        -P * (L - x) * y / i,
        0.0,
        P * (D * D / 4.0 - y * y) / (2.0 * i),
    ]
}

/// End conditions of the cantilever problems.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ends {
    /// x = 0 fully clamped, the load spread uniformly over x = L (the problem as a
    /// user would set it up).
    Clamped,
    /// x = 0 follows the Timoshenko–Goodier displacement node by node, x = L carries
    /// the consistent nodal forces of the parabolic shear: the closed form is exact.
    Exact,
}

/// Supports of the end x = 0 of `part` meshed with `ny` cells over the depth.
fn support_text(part: &str, ny: usize, ends: Ends) -> String {
    match ends {
        Ends::Clamped => {
            format!("[[support]]\npart = \"{part}\"\nboundary = \"left\"\nfix = [\"x\", \"y\"]\n")
        }
        Ends::Exact => {
            let mut s = String::new();
            for j in 0..=ny {
                let y = -D / 2.0 + D * j as f64 / ny as f64;
                let u = tg_displacement(0.0, y);
                let _ = writeln!(
                    s,
                    "[[support]]\npart = \"{part}\"\nat = [0.0, {y:e}]\nfix = [\"x\", \"y\"]\nvalue = [{:e}, {:e}]",
                    u[0], u[1]
                );
            }
            s
        }
    }
}

/// Loads of the end x = L of `part` meshed with `ny` cells over the depth.
fn load_text(part: &str, ny: usize, ends: Ends) -> String {
    match ends {
        Ends::Clamped => {
            format!("[[load]]\npart = \"{part}\"\nboundary = \"right\"\nforce = [0.0, {P:e}]\n")
        }
        Ends::Exact => {
            // Consistent nodal forces ∫ σxy(L, y) N_j dy: 2-point Gauss per edge is
            // exact (quadratic traction × linear shape function).
            let dy = D / ny as f64;
            let mut f = vec![0.0; ny + 1];
            let g = 0.5 / 3f64.sqrt();
            for j in 0..ny {
                for xi in [0.5 - g, 0.5 + g] {
                    let t = tg_stress(L, -D / 2.0 + dy * (j as f64 + xi))[2];
                    f[j] += 0.5 * dy * t * (1.0 - xi);
                    f[j + 1] += 0.5 * dy * t * xi;
                }
            }
            let mut s = String::new();
            for (j, fj) in f.iter().enumerate() {
                let y = -D / 2.0 + dy * j as f64;
                let _ = writeln!(
                    s,
                    "[[load]]\npart = \"{part}\"\nat = [{L:e}, {y:e}]\nforce = [0.0, {fj:e}]"
                );
            }
            s
        }
    }
}

const HEAD: &str = "[materials.steel]\nE = 210000.0\nnu = 0.31\n[analysis]\nincrements = 1\n";

/// The split cantilever, clamped: host cells `host` on [0, 50], node-part cells
/// `fine` on [50, 100], tie penalty `c` (None: default).
pub fn tied(host: [usize; 2], fine: [usize; 2], c: Option<f64>) -> String {
    tied_with(host, fine, c, Ends::Clamped, false)
}

/// The split cantilever with the given end conditions; `fine_hosts` reverses the
/// roles (the fine right half hosts, the coarse left half's nodes couple).
pub fn tied_with(
    host: [usize; 2],
    fine: [usize; 2],
    c: Option<f64>,
    ends: Ends,
    fine_hosts: bool,
) -> String {
    tied_with_elements(host, fine, c, ends, fine_hosts, [ElementKind::T3; 2])
}

/// [`tied_with`] with the element types of the coarse (left) and fine (right)
/// halves given (`[coarse, fine]`).
pub fn tied_with_elements(
    host: [usize; 2],
    fine: [usize; 2],
    c: Option<f64>,
    ends: Ends,
    fine_hosts: bool,
    kinds: [ElementKind; 2],
) -> String {
    let c = c.map_or(String::new(), |c| format!("c_n = {c:e}\n"));
    let (h, n, b) = if fine_hosts {
        ("fine", "coarse", "right")
    } else {
        ("coarse", "fine", "left")
    };
    format!(
        r#"{HEAD}
[[part]]
name = "coarse"
material = "steel"
rectangle = {{ x = [0.0, 50.0], y = [-5.0, 5.0], cells = [{}, {}], elements = "{}" }}
[[part]]
name = "fine"
material = "steel"
rectangle = {{ x = [50.0, 100.0], y = [-5.0, 5.0], cells = [{}, {}], elements = "{}" }}
[[interface]]
host = "{h}"
nodes = "{n}"
boundary = "{b}"
law = "rigid"
{c}
{}
{}"#,
        host[0],
        host[1],
        toml_kind(kinds[0]),
        fine[0],
        fine[1],
        toml_kind(kinds[1]),
        support_text("coarse", host[1], ends),
        load_text("fine", fine[1], ends)
    )
}

/// The same cantilever meshed conformingly with `cells`, clamped.
pub fn conforming(cells: [usize; 2]) -> String {
    conforming_with(cells, Ends::Clamped)
}

/// The cantilever meshed conformingly with `cells` and the given end conditions.
pub fn conforming_with(cells: [usize; 2], ends: Ends) -> String {
    conforming_with_elements(cells, ends, ElementKind::T3)
}

/// [`conforming_with`] meshed with elements of `kind`.
pub fn conforming_with_elements(cells: [usize; 2], ends: Ends, kind: ElementKind) -> String {
    format!(
        r#"{HEAD}
[[part]]
name = "beam"
material = "steel"
rectangle = {{ x = [0.0, 100.0], y = [-5.0, 5.0], cells = [{}, {}], elements = "{}" }}
{}
{}"#,
        cells[0],
        cells[1],
        toml_kind(kind),
        support_text("beam", cells[1], ends),
        load_text("beam", cells[1], ends)
    )
}

/// Tip deflection (downwards positive) of a cantilever problem.
pub fn tip(text: &str, part: &str) -> Result<f64> {
    Ok(measure(text, part)?.tip)
}

/// What is measured on one cantilever run.
#[derive(Debug, Clone, Copy)]
pub struct Measured {
    /// Tip deflection at (L, 0), downwards positive.
    pub tip: f64,
    /// Squared energy norm of σ_h − σ_TG over x < 50 (t = 1).
    pub left: f64,
    /// The same over x > 50.
    pub right: f64,
}

impl Measured {
    /// Energy-norm error relative to the energy norm of the exact solution.
    pub fn energy_error(&self) -> f64 {
        ((self.left + self.right) / exact_energy()).sqrt()
    }
}

/// Squared energy norm of the exact stress over the beam, ∫ σᵀ D⁻¹ σ t dA
/// = P² L³/(3 E I) + (1+ν) P² L D⁵/(60 E I²) (t = 1).
pub fn exact_energy() -> f64 {
    let i = inertia();
    P * P * L.powi(3) / (3.0 * E * i) + (1.0 + NU) * P * P * L * D.powi(5) / (60.0 * E * i * i)
}

/// Solves a cantilever problem and measures its tip deflection and its energy-norm
/// error against the Timoshenko–Goodier stress.
pub fn measure(text: &str, tip_part: &str) -> Result<Measured> {
    let a = prepare(text)?;
    let inc = solve(&a)?.pop().expect("one increment");
    let tip = -displacement_at(&a, &inc, tip_part, [L, 0.0])?[1];
    let (left, right) = energy_error_split(&a, &inc);
    Ok(Measured { tip, left, right })
}

/// ∫ (σ_h − σ_TG)ᵀ D⁻¹ (σ_h − σ_TG) t dA over the elements left and right of x = 50
/// (by their centroids). In a T3 the integrand is a polynomial of degree 4 (σ_h
/// constant, σ_TG quadratic), integrated exactly; in a rectangular Q4 one of degree
/// 4 in each of ξ, η, integrated exactly by 3 × 3 Gauss points.
fn energy_error_split(a: &Analysis, inc: &IncrementResult) -> (f64, f64) {
    let (mut left, mut right) = (0.0, 0.0);
    for_each_stress_point(a, &inc.u, |p, e, x, w, s| {
        let part = &a.model.parts[p];
        let m = &part.mesh;
        let nodes = m.elements[e].nodes();
        let cx = nodes.iter().map(|&n| m.nodes[n][0]).sum::<f64>() / nodes.len() as f64;
        let ex = tg_stress(x[0], x[1]);
        let d = [0, 1, 2].map(|k| s[k] - ex[k]);
        let v = w * energy_density(&part.material, d);
        if cx < 50.0 {
            left += v;
        } else {
            right += v;
        }
    });
    (left, right)
}

/// Conforming runs, memoised by cell count (several ratios share them).
struct Conforming {
    ends: Ends,
    runs: BTreeMap<usize, Measured>,
}

impl Conforming {
    fn get(&mut self, nx: usize) -> Result<Measured> {
        if let Some(m) = self.runs.get(&nx) {
            return Ok(*m);
        }
        let m = measure(&conforming_with([nx, nx / 10], self.ends), "beam")?;
        self.runs.insert(nx, m);
        Ok(m)
    }
}

/// The grid of a convergence study: mesh ratios 1:r and refinement levels k
/// (host element size h = 5/k).
struct Refinement<'a> {
    ratios: &'a [usize],
    levels: &'a [usize],
    hs: Vec<f64>,
}

/// Results of part (i) of case 2, the exact end conditions.
struct ExactEnds {
    table: Table,
    tip_series: Vec<Series>,
    energy_series: Vec<Series>,
    /// The finest tip-deflection orders are near 2.
    tip_ok: bool,
    /// The finest energy-norm orders are near 1.
    energy_ok: bool,
    /// The tied energy-norm error equals the conforming halves' prediction.
    no_extra: bool,
    /// The tied / predicted ratio farthest from 1.
    worst_ratio: f64,
    /// The finest orders per ratio, "1:r tip / energy".
    finest: Vec<String>,
}

/// Results of part (ii) of case 2, the clamped end.
struct ClampedEnd {
    table: Table,
    /// Every tied tip lies between the conforming meshes of its two sizes.
    bracketed: bool,
    /// Cell count along x of the finest conforming mesh.
    finest_nx: usize,
    /// Its tip deflection against the closed form.
    end_effect: f64,
}

/// Case 2: the tied cantilever for mesh ratios 1:1 … 1:8 under refinement: tip
/// deflection against the closed form (clamped, as a user would model it, and with
/// the exact end conditions), energy-norm error against the exact stress, and both
/// against conforming meshes of the two element sizes.
pub fn convergence(quick: bool) -> Result<Case> {
    let ratios: &[usize] = if quick { &[1, 4] } else { &[1, 2, 4, 8] };
    // k = 1 (two elements through the depth) is pre-asymptotic; the quick run
    // starts at k = 2.
    let levels: &[usize] = if quick { &[2, 4] } else { &[1, 2, 4, 8] };
    let grid = Refinement {
        ratios,
        levels,
        hs: levels.iter().map(|&k| 5.0 / k as f64).collect(),
    };
    let exact_ends = exact_ends_study(&grid)?;
    let clamped = clamped_study(&grid)?;
    Ok(convergence_case(exact_ends, clamped))
}

/// Part (i): the tied models with the exact end conditions at every ratio and
/// level, their tip and energy-norm errors and orders, against the error predicted
/// from conforming meshes of the two halves; with the convergence plots' series.
fn exact_ends_study(grid: &Refinement) -> Result<ExactEnds> {
    let exact = timoshenko_goodier();
    let mut conf = Conforming {
        ends: Ends::Exact,
        runs: BTreeMap::new(),
    };
    let mut study = ExactEnds {
        table: Table {
            caption: format!(
                "(i) Exact end conditions. Host cells 10k × 2k on [0, 50] (size h = 5/k), node part r times finer on [50, 100]. Tip deflection error against the closed form v(L) = {}; energy-norm error ‖σ_h − σ_TG‖_E / ‖σ_TG‖_E; and the energy-norm error *predicted* for an interface that adds nothing: √(e²_left(conforming h) + e²_right(conforming h/r)), the conforming meshes' errors over the half each part covers.",
                sci(exact)
            ),
            header: [
                "ratio",
                "k",
                "h",
                "tied tip error",
                "order",
                "energy-norm error",
                "order",
                "predicted from conforming halves",
                "tied / predicted",
            ]
            .map(String::from)
            .to_vec(),
            rows: Vec::new(),
        },
        tip_series: Vec::new(),
        energy_series: Vec::new(),
        tip_ok: true,
        energy_ok: true,
        no_extra: true,
        worst_ratio: 1.0,
        finest: Vec::new(),
    };
    for &r in grid.ratios {
        exact_ends_ratio(grid, r, &mut conf, &mut study)?;
    }
    add_conforming_and_slopes(grid, &mut conf, &mut study)?;
    Ok(study)
}

/// Part (i) at mesh ratio 1:`r`: its table rows, orders and series.
fn exact_ends_ratio(
    grid: &Refinement,
    r: usize,
    conf: &mut Conforming,
    study: &mut ExactEnds,
) -> Result<()> {
    let exact = timoshenko_goodier();
    let hs = &grid.hs;
    let mut tips = Vec::new();
    let mut energies = Vec::new();
    let first = study.table.rows.len();
    for (i, &k) in grid.levels.iter().enumerate() {
        let m = measure(
            &tied_with(
                [10 * k, 2 * k],
                [10 * k * r, 2 * k * r],
                None,
                Ends::Exact,
                false,
            ),
            "fine",
        )?;
        let coarse = conf.get(20 * k)?;
        let fine = conf.get(20 * k * r)?;
        let predicted = ((coarse.left + fine.right) / exact_energy()).sqrt();
        let e_tip = (m.tip - exact) / exact;
        let e_en = m.energy_error();
        let ratio = e_en / predicted;
        study.worst_ratio = if (ratio - 1.0).abs() > (study.worst_ratio - 1.0).abs() {
            ratio
        } else {
            study.worst_ratio
        };
        study.no_extra &= (ratio - 1.0).abs() < 0.02;
        tips.push(e_tip);
        energies.push(e_en);
        study.table.rows.push(vec![
            format!("1:{r}"),
            k.to_string(),
            format!("{:.3}", hs[i]),
            sci(e_tip),
            String::new(),
            sci(e_en),
            String::new(),
            sci(predicted),
            format!("{ratio:.4}"),
        ]);
    }
    for (i, (o1, o2)) in orders(&tips).into_iter().zip(orders(&energies)).enumerate() {
        study.table.rows[first + i][4] = o1;
        study.table.rows[first + i][6] = o2;
    }
    if let ([.., t1, t2], [.., e1, e2]) = (tips.as_slice(), energies.as_slice()) {
        let (ot, oe) = ((t1 / t2).abs().log2(), (e1 / e2).log2());
        study.tip_ok &= ot > 1.7;
        study.energy_ok &= (0.85..1.2).contains(&oe);
        study.finest.push(format!("1:{r} {ot:.2} / {oe:.2}"));
    }
    study.tip_series.push(Series {
        name: format!("tied 1:{r}"),
        points: hs.iter().zip(&tips).map(|(&h, e)| (h, e.abs())).collect(),
        reference: false,
    });
    study.energy_series.push(Series {
        name: format!("tied 1:{r}"),
        points: hs.iter().copied().zip(energies.iter().copied()).collect(),
        reference: false,
    });
    Ok(())
}

/// The conforming meshes of size h and the slope-2 / slope-1 guides, added to
/// part (i)'s plot series.
fn add_conforming_and_slopes(
    grid: &Refinement,
    conf: &mut Conforming,
    study: &mut ExactEnds,
) -> Result<()> {
    let exact = timoshenko_goodier();
    let hs = &grid.hs;
    let conf_h: Vec<Measured> = grid
        .levels
        .iter()
        .map(|&k| conf.get(20 * k))
        .collect::<Result<_>>()?;
    study.tip_series.push(Series {
        name: "conforming, size h".into(),
        points: hs
            .iter()
            .zip(&conf_h)
            .map(|(&h, m)| (h, ((m.tip - exact) / exact).abs()))
            .collect(),
        reference: false,
    });
    study.energy_series.push(Series {
        name: "conforming, size h".into(),
        points: hs
            .iter()
            .zip(&conf_h)
            .map(|(&h, m)| (h, m.energy_error()))
            .collect(),
        reference: false,
    });
    let (h0, h1) = (hs[0], hs[hs.len() - 1]);
    let t0 = study.tip_series[0].points[0].1;
    study.tip_series.push(Series {
        name: "slope 2".into(),
        points: vec![(h0, t0 * 1.5), (h1, t0 * 1.5 * (h1 / h0).powi(2))],
        reference: true,
    });
    let e0 = study.energy_series[0].points[0].1;
    study.energy_series.push(Series {
        name: "slope 1".into(),
        points: vec![(h0, e0 * 1.3), (h1, e0 * 1.3 * h1 / h0)],
        reference: true,
    });
    Ok(())
}

/// Part (ii): the clamped end, as a user would set it up: tip deflection of the
/// tied models against conforming meshes of the two element sizes.
fn clamped_study(grid: &Refinement) -> Result<ClampedEnd> {
    let (ratios, levels) = (grid.ratios, grid.levels);
    let exact = timoshenko_goodier();
    let mut clamped = Conforming {
        ends: Ends::Clamped,
        runs: BTreeMap::new(),
    };
    let mut table = Table {
        caption: "(ii) Fully clamped end, load spread uniformly over x = 100 (the problem as specified): tip deflection of the tied models and of conforming meshes with the host's size h and with the node part's size h/r.".into(),
        header: std::iter::once("k".to_string())
            .chain(std::iter::once("conforming h".to_string()))
            .chain(ratios.iter().map(|r| format!("tied 1:{r}")))
            .chain(std::iter::once(format!("conforming h/{}", ratios[ratios.len() - 1])))
            .collect(),
        rows: Vec::new(),
    };
    let mut bracketed = true;
    for &k in levels {
        let coarse = clamped.get(20 * k)?.tip;
        let mut row = vec![k.to_string(), sci(coarse)];
        for &r in ratios {
            let t = tip(
                &tied([10 * k, 2 * k], [10 * k * r, 2 * k * r], None),
                "fine",
            )?;
            let fine = clamped.get(20 * k * r)?.tip;
            bracketed &= t >= coarse * (1.0 - 1e-6) && t <= fine * (1.0 + 1e-6);
            row.push(sci(t));
        }
        row.push(sci(clamped.get(20 * k * ratios[ratios.len() - 1])?.tip));
        table.rows.push(row);
    }
    let (finest_nx, best_clamped) = clamped
        .runs
        .iter()
        .next_back()
        .map_or((0, f64::NAN), |(n, m)| (*n, m.tip));
    Ok(ClampedEnd {
        table,
        bracketed,
        finest_nx,
        end_effect: (best_clamped - exact) / exact,
    })
}

/// Case 2's report from its two parts: tables, plots and the verdict.
fn convergence_case(exact_ends: ExactEnds, clamped: ClampedEnd) -> Case {
    let exact = timoshenko_goodier();
    let ExactEnds {
        table,
        tip_series,
        energy_series,
        tip_ok,
        energy_ok,
        no_extra,
        worst_ratio,
        finest,
    } = exact_ends;
    let ClampedEnd {
        table: table_c,
        bracketed,
        finest_nx,
        end_effect,
    } = clamped;
    Case {
        title: "Tied non-matching cantilever".into(),
        setup: "Plane stress cantilever L = 100, D = 10, t = 1, E = 210000, ν = 0.31, 1 N downward shear at x = 100. Split at x = 50: the left half (host) with square cells of size h = 5/k split into two T3 each, the right half r times finer, tied with the rigid law and the default penalty. Mesh ratios 1:r, refinement levels k. (i) with the exact end conditions of the closed form (each node of x = 0 prescribed to the Timoshenko–Goodier displacement, the parabolic shear on x = 100 as consistent nodal forces), so the closed form is the exact solution of the discrete problem's continuum; (ii) fully clamped at x = 0 with the load spread uniformly, as a user would model it.\n\n```text\n  |▒ host (h) ▒▒▒▒▒▒▒▒▒▒▒▒|░ node part (h / r) ░░░|  ↓ P = 1 N on x = 100\n  x = 0                  x = 50 (tied)          x = 100\n```".into(),
        reference: format!(
            "Timoshenko & Goodier, *Theory of Elasticity*, 3rd ed., 1970, §21: σxx = −P(L−x)y/I, σyy = 0, σxy = P(D²/4 − y²)/(2I); ux = −Py/(6EI)·[(6L−3x)x + (2+ν)(y² − D²/4)], uy = P/(6EI)·[3νy²(L−x) + (4+5ν)D²x/4 + (3L−x)x²] (support at x = 0, P in +y at x = L; the form of Augarde & Deeks, Finite Elements in Analysis and Design 44 (2008) 595); tip deflection v(L) = PL³/(3EI) + (4+5ν)PD²L/(24EI) = {}. Energy norm ‖σ‖²_E = ∫ σᵀ D⁻¹ σ t dA, integrated exactly per element (6-point degree-4 rule); ‖σ_TG‖²_E = P²L³/(3EI) + (1+ν)P²LD⁵/(60EI²). Linear triangles converge at order 1 in the energy norm and order 2 in the tip deflection.",
            sci(exact)
        ),
        tables: vec![table, table_c],
        plots: vec![
            Plot {
                file: "cantilever_convergence.png".into(),
                title: "Tied cantilever (exact ends): tip deflection error".into(),
                x: "host element size h".into(),
                y: "|tip error| / closed form".into(),
                log: (true, true),
                series: tip_series,
            },
            Plot {
                file: "cantilever_energy.png".into(),
                title: "Tied cantilever (exact ends): energy-norm error".into(),
                x: "host element size h".into(),
                y: "‖σh − σTG‖E / ‖σTG‖E".into(),
                log: (true, true),
                series: energy_series,
            },
        ],
        verdict: format!(
            "With the exact end conditions the tied tip deflection converges to the closed form at order 2 and the energy-norm error at order 1, as linear triangles must (finest orders, tip / energy: {}); the tied energy-norm error equals that predicted from conforming meshes of the two halves' sizes to within {:.2} % at every ratio and level (worst tied / predicted = {:.4}): the interface adds no error beyond the bulk discretization. Clamped: the tied tip deflection lies between the conforming meshes of its two element sizes at every level and ratio ({}); on the finest conforming mesh ({} × {} cells) the clamped tip differs from the closed form by {}, the clamp's end effect plus that mesh's own error.",
            finest.join(", "),
            100.0 * (worst_ratio - 1.0).abs(),
            worst_ratio,
            if bracketed { "bracketed" } else { "NOT always bracketed" },
            finest_nx,
            finest_nx / 10,
            sci(end_effect)
        ),
        passed: tip_ok && energy_ok && no_extra && bracketed,
    }
}

/// Results of the penalty study on matching meshes.
struct MatchingPenalty {
    table: Table,
    series: Vec<Series>,
    /// The difference falls by over 100 from c = 1e2 to 1e5 × E·t at every level.
    falls: bool,
    /// The largest difference with the default penalty.
    default_err: f64,
    /// The smallest difference per level, "k = …: … at c".
    best: Vec<String>,
}

/// Results of the penalty study on dissimilar parts.
struct DissimilarPenalty {
    table: Table,
    /// The default's difference to the tie's limit.
    default_dissimilar: f64,
    /// The difference with the penalty scaled by the stiffer part (1e9 row).
    stiff_scaled: f64,
    /// That run's residual.
    stiff_residual: f64,
}

/// Case 3: the penalty. Matching meshes (1:1) tied with c from 1e2 to 1e12 × E·t
/// against the same mesh without an interface: the only difference is the penalty's.
pub fn penalty_study(quick: bool) -> Result<Case> {
    let levels: &[usize] = if quick { &[2] } else { &[2, 8] };
    let factors: &[f64] = if quick {
        &[1e2, 1e5, 1e8]
    } else {
        &[1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12]
    };
    let x_max = factors[factors.len() - 1];
    let matching = matching_penalty(levels, factors)?;
    let dissimilar = dissimilar_penalty(quick)?;
    let default = cfe::model::DEFAULT_PENALTY_FACTOR;
    let MatchingPenalty {
        table,
        series,
        falls,
        default_err,
        best,
    } = matching;
    let DissimilarPenalty {
        table: table_d,
        default_dissimilar,
        stiff_scaled,
        stiff_residual,
    } = dissimilar;
    Ok(Case {
        title: "Penalty study".into(),
        setup: format!("The clamped cantilever of case 2 with matching meshes on both sides of the cut (1:1) at levels k = {}, tied with c from {:.0e} to {:.0e} × E·t.", levels.iter().map(|k| k.to_string()).collect::<Vec<_>>().join(" and "), factors[0], x_max),
        reference: "The same beam meshed as one part (no interface): with matching meshes an exact tie reproduces it exactly, so the difference is the penalty's error alone, O(E·t/c), plus round-off.".into(),
        tables: vec![table, table_d],
        plots: vec![Plot {
            file: "penalty.png".into(),
            title: "Tip deflection error of the tie against the penalty".into(),
            x: "c / (E·t)".into(),
            y: "relative difference to the conforming mesh".into(),
            log: (true, true),
            series,
        }],
        verdict: format!(
            "The error falls as 1/c until round-off in the penalised system takes over (smallest difference {}); beyond it the error grows about tenfold per decade of c, and the crossover moves to smaller c as the mesh is refined (the condition number grows as 1/h²). The default c = {default:.0e} × E·t gives at most {}: several orders below the discretization error (case 2) and at or below the round-off crossover, which moves towards it as meshes grow — so it is kept, and should not be raised. With dissimilar parts the tie acts in series with the softer part, so the softer part's E·t is the scale: the default (1e5 × the softer E·t) is {} off the tie's limit, while 1e5 × the stiffer part's E·t (1e9 × the softer) would be {} off with a residual of {} — why the default takes the softer part's E·t.",
            best.join(", "),
            sci(default_err),
            sci(default_dissimilar),
            sci(stiff_scaled),
            sci(stiff_residual)
        ),
        passed: falls && default_err < 1e-5 && default_dissimilar < 1e-5,
    })
}

/// The tied 1:1 clamped cantilever at levels `levels` with c = `factors` × E·t
/// against the same mesh without an interface; with the slope −1 guide.
fn matching_penalty(levels: &[usize], factors: &[f64]) -> Result<MatchingPenalty> {
    let mut study = MatchingPenalty {
        table: Table {
            caption: "Tip deflection of the tied 1:1 clamped cantilever against the same mesh without an interface: relative difference, and the largest out-of-balance force of the solve relative to the load (the solver's own round-off check: a run flags a residual above 1e-8 and, with the default [analysis] max_residual, stops above 1e-4; this study lifts that limit to show the whole curve).".into(),
            header: std::iter::once("c / (E·t)".to_string())
                .chain(levels.iter().flat_map(|k| {
                    [format!("k = {k}: tip difference"), format!("k = {k}: residual")]
                }))
                .collect(),
            rows: factors.iter().map(|f| vec![format!("{f:.0e}")]).collect(),
        },
        series: Vec::new(),
        falls: true,
        default_err: 0.0,
        best: Vec::new(),
    };
    let mut default_errs = Vec::new();
    for &k in levels {
        default_errs.push(penalty_curve(k, factors, &mut study)?);
    }
    let x_max = factors[factors.len() - 1];
    let y0 = study.series[0].points[0].1;
    study.series.push(Series {
        name: "slope −1 (penalty error ∝ E·t/c)".into(),
        points: vec![(1e2, y0), (x_max, y0 * 1e2 / x_max)],
        reference: true,
    });
    study.default_err = default_errs.iter().copied().fold(0.0, f64::max);
    Ok(study)
}

/// The penalty curve at level `k`: its table columns, series and best point; the
/// difference with the default penalty.
fn penalty_curve(k: usize, factors: &[f64], study: &mut MatchingPenalty) -> Result<f64> {
    let et = E;
    let reference = tip(&conforming([20 * k, 2 * k]), "beam")?;
    let mut pts = Vec::new();
    for (i, &f) in factors.iter().enumerate() {
        let mut a = prepare(&tied([10 * k, 2 * k], [10 * k, 2 * k], Some(f * et)))?;
        // The study goes past what a run accepts (max_residual) on purpose.
        a.model.settings.max_residual = f64::INFINITY;
        let inc = solve(&a)?.pop().expect("one increment");
        let t = -displacement_at(&a, &inc, "fine", [L, 0.0])?[1];
        let d = ((t - reference) / reference).abs();
        pts.push((f, d.max(1e-17)));
        study.table.rows[i].push(sci(d));
        study.table.rows[i].push(sci(inc.residual));
    }
    let at = |f: f64| pts.iter().find(|p| p.0 == f).map_or(f64::NAN, |p| p.1);
    study.falls &= at(1e2) / at(1e5) > 100.0;
    let (fb, eb) = pts
        .iter()
        .fold((0.0, f64::INFINITY), |b, p| if p.1 < b.1 { *p } else { b });
    study.best.push(format!("k = {k}: {} at {fb:.0e}", sci(eb)));
    let t = tip(&tied([10 * k, 2 * k], [10 * k, 2 * k], None), "fine")?;
    study.series.push(Series {
        name: format!("tied 1:1, k = {k}"),
        points: pts,
        reference: false,
    });
    Ok(((t - reference) / reference).abs())
}

/// Dissimilar parts: the node part 10⁴ times stiffer than the host. No
/// conforming mesh exists; the reference is the tie's own limit, the result at
/// c = 1e6 × the softer E·t (converged to about 1e-9 by the 1/c trend).
fn dissimilar_penalty(quick: bool) -> Result<DissimilarPenalty> {
    let et = E;
    let default = cfe::model::DEFAULT_PENALTY_FACTOR;
    let ratio = 1e4;
    let limit = tip(&tied_dissimilar(ratio, Some(1e6 * et)), "fine")?;
    let soft_factors: &[f64] = if quick {
        &[1e5, 1e9]
    } else {
        &[1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9]
    };
    let mut table = Table {
        caption: format!(
            "Dissimilar parts: the same cantilever (k = 2, 1:1) with the node part {ratio:.0e} times stiffer than the host. Tip deflection against the tie's limit (the result at c = 1e6 × the softer part's E·t) and the solve's out-of-balance force, for c in multiples of the softer part's E·t. The default, {default:.0e} × the softer part's E·t, is the 1e5 row; {default:.0e} × the stiffer part's would be the 1e9 row."
        ),
        header: [
            "c / (E·t of the softer part)",
            "tip difference to the limit",
            "residual",
        ]
        .map(String::from)
        .to_vec(),
        rows: Vec::new(),
    };
    let mut at_soft = Vec::new();
    for &f in soft_factors {
        let mut a = prepare(&tied_dissimilar(ratio, Some(f * et)))?;
        a.model.settings.max_residual = f64::INFINITY;
        let inc = solve(&a)?.pop().expect("one increment");
        let t = -displacement_at(&a, &inc, "fine", [L, 0.0])?[1];
        let d = ((t - limit) / limit).abs();
        at_soft.push((f, d, inc.residual));
        table
            .rows
            .push(vec![format!("{f:.0e}"), sci(d), sci(inc.residual)]);
    }
    let default_dissimilar = ((tip(&tied_dissimilar(ratio, None), "fine")? - limit) / limit).abs();
    let stiff = at_soft.iter().find(|p| p.0 == 1e9);
    Ok(DissimilarPenalty {
        table,
        default_dissimilar,
        stiff_scaled: stiff.map_or(f64::NAN, |p| p.1),
        stiff_residual: stiff.map_or(f64::NAN, |p| p.2),
    })
}

/// The clamped split cantilever (k = 2, 1:1) with a node part `ratio` times
/// stiffer than the host, tied with `c` (None: the default).
pub fn tied_dissimilar(ratio: f64, c: Option<f64>) -> String {
    tied([20, 4], [20, 4], c)
        .replacen(
            "[analysis]",
            &format!(
                "[materials.stiff]\nE = {:e}\nnu = 0.31\n[analysis]",
                E * ratio
            ),
            1,
        )
        .replace(
            "name = \"fine\"\nmaterial = \"steel\"",
            "name = \"fine\"\nmaterial = \"stiff\"",
        )
}

/// Reversed roles on the cantilever: tip deflection and energy-norm error with the
/// coarse part hosting and with the fine part hosting (exact end conditions).
pub fn reversed_cantilever(k: usize, r: usize) -> Result<(Measured, Measured)> {
    let run = |fine_hosts: bool| {
        let text = tied_with(
            [10 * k, 2 * k],
            [10 * k * r, 2 * k * r],
            None,
            Ends::Exact,
            fine_hosts,
        );
        measure(&text, "fine")
    };
    Ok((run(false)?, run(true)?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::verification::DUNAVANT4;
    use cfe::fem::material::{Material, PlaneKind};

    /// The closed form is a plane-stress elasticity solution: strains of u equal
    /// D⁻¹σ (central differences), and the shear on x = L sums to P.
    #[test]
    fn timoshenko_goodier_is_consistent() {
        let m = Material::new(E, NU, PlaneKind::Stress, 1.0, "t").unwrap();
        let d = m.d_matrix();
        let h = 1e-4;
        for &(x, y) in &[(10.0, 2.0), (50.0, -4.0), (90.0, 3.3)] {
            let g = |dx: f64, dy: f64| tg_displacement(x + dx, y + dy);
            let exx = (g(h, 0.0)[0] - g(-h, 0.0)[0]) / (2.0 * h);
            let eyy = (g(0.0, h)[1] - g(0.0, -h)[1]) / (2.0 * h);
            let gxy = (g(0.0, h)[0] - g(0.0, -h)[0] + g(h, 0.0)[1] - g(-h, 0.0)[1]) / (2.0 * h);
            let s = tg_stress(x, y);
            for (r, row) in d.iter().enumerate() {
                let from_strain = row[0] * exx + row[1] * eyy + row[2] * gxy;
                assert!(
                    (from_strain - s[r]).abs() < 1e-6 * (1.0 + s[r].abs()),
                    "{r}: {from_strain} vs {}",
                    s[r]
                );
            }
        }
        let n = 1000;
        let shear: f64 = (0..n)
            .map(|j| tg_stress(L, -D / 2.0 + D * (j as f64 + 0.5) / n as f64)[2] * D / n as f64)
            .sum();
        assert!((shear - P).abs() < 1e-6);
    }

    /// The closed-form energy norm of the exact stress equals its exact integration
    /// over a mesh of the beam.
    #[test]
    fn exact_energy_matches_quadrature() {
        let mesh = cfe::mesh::Mesh::rectangle(
            [0.0, L],
            [-D / 2.0, D / 2.0],
            [10, 2],
            cfe::mesh::ElementKind::T3,
        );
        let m = Material::new(E, NU, PlaneKind::Stress, 1.0, "t").unwrap();
        let mut sum = 0.0;
        for (e, el) in mesh.elements.iter().enumerate() {
            let x: Vec<[f64; 2]> = el.nodes().iter().map(|&n| mesh.nodes[n]).collect();
            for (b, w) in DUNAVANT4 {
                let px = b[0] * x[0][0] + b[1] * x[1][0] + b[2] * x[2][0];
                let py = b[0] * x[0][1] + b[1] * x[1][1] + b[2] * x[2][1];
                sum += w * mesh.element_area(e) * energy_density(&m, tg_stress(px, py));
            }
        }
        assert!(
            (sum - exact_energy()).abs() < 1e-10 * exact_energy(),
            "{sum} vs {}",
            exact_energy()
        );
    }
}
