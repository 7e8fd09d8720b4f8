//! Verification: the solver against independent truth — closed-form solutions,
//! conforming meshes, invariants — each case a function that builds its models in
//! memory, solves them and returns its tables, plots and verdict. `cfe verify`
//! runs them all ([`CASES`]) and writes `docs/verification.md` with its
//! pictures; the tests assert every case of that list, quick and full.

pub mod axisymmetric;
pub mod axisymmetric_contact;
pub mod cantilever;
pub mod closed_forms;
pub mod contact;
pub mod curved;
pub mod fits;
pub mod hertz;
pub mod patch;
pub mod punch;
pub mod quads;
pub mod seed;
pub mod segment;
pub mod solid;
pub mod solid_beam;
pub mod solid_contact;
pub mod solid_mesh;
pub mod solid_patch;
pub mod solid_peer;

use cfe::analysis::Analysis;
use cfe::analysis::Start;
use cfe::error::{Error, Result};
use cfe::model::Model;
use cfe::output::chart::{self, Axes, Series};
use cfe::solve::nonlinear::IncrementResult;
use std::fmt::Write as _;
use std::path::Path;

/// A table of a verification case.
#[derive(Debug, Clone)]
pub struct Table {
    /// Caption.
    pub caption: String,
    /// Column headers.
    pub header: Vec<String>,
    /// Rows of cells.
    pub rows: Vec<Vec<String>>,
}

/// A plot of a verification case, drawn when the report is written.
#[derive(Debug, Clone)]
pub struct Plot {
    /// File name (in the report's picture folder).
    pub file: String,
    /// Title.
    pub title: String,
    /// x-axis label.
    pub x: String,
    /// y-axis label.
    pub y: String,
    /// Logarithmic axes (x, y).
    pub log: (bool, bool),
    /// Curves.
    pub series: Vec<Series>,
}

/// One verification case: what was set up, against what, the results and verdict.
#[derive(Debug, Clone)]
pub struct Case {
    /// Title.
    pub title: String,
    /// The setup, in words (and an ASCII drawing).
    pub setup: String,
    /// The reference and its source.
    pub reference: String,
    /// Result tables.
    pub tables: Vec<Table>,
    /// Plots.
    pub plots: Vec<Plot>,
    /// One-line verdict.
    pub verdict: String,
    /// Whether the case met its reference.
    pub passed: bool,
}

/// Reads, meshes and prepares a problem given as text.
pub fn prepare(text: &str) -> Result<Analysis> {
    Analysis::new(Model::from_str(text, Path::new("verification.toml"), 1)?)
}

/// Solves a prepared problem in memory as `cfe run` does (from the start its
/// `[analysis] start` names); returns every increment.
pub fn solve(a: &Analysis) -> Result<Vec<IncrementResult>> {
    let mut all = Vec::new();
    a.solve_with(|inc| {
        all.push(inc.clone());
        Ok(())
    })?;
    Ok(all)
}

/// Solves a prepared problem in memory, starting the contact iteration from the
/// coarser model's pattern (`coarse_start`, for K ≥ 4) or from all pairs bonded;
/// returns every increment.
pub fn solve_with(a: &Analysis, coarse_start: bool) -> Result<Vec<IncrementResult>> {
    let start = if coarse_start {
        Start::Coarse
    } else {
        Start::AllBonded
    };
    let mut all = Vec::new();
    a.solve_from(start, |inc| {
        all.push(inc.clone());
        Ok(())
    })?;
    Ok(all)
}

/// Displacement of the node of `part` at `at`.
pub fn displacement_at(
    a: &Analysis,
    inc: &IncrementResult,
    part: &str,
    at: [f64; 2],
) -> Result<[f64; 2]> {
    let p = a
        .model
        .part_index(part)
        .ok_or_else(|| Error::Model(format!("no part '{part}'")))?;
    let n = a.model.parts[p]
        .mesh
        .nodes
        .iter()
        .position(|x| (x[0] - at[0]).abs() < 1e-9 && (x[1] - at[1]).abs() < 1e-9)
        .ok_or_else(|| Error::Model(format!("no node of '{part}' at {at:?}")))?;
    let g = a.dofs.node(p, n);
    Ok([inc.u[2 * g], inc.u[2 * g + 1]])
}

/// A verification case: builds its models, solves them and returns its tables,
/// plots and verdict; `true` asks for its reduced (quick) version.
pub type CaseFn = fn(bool) -> Result<Case>;

/// Every case `cfe verify` runs, in the report's order, each with the name its
/// progress line shows. The one list: [`run_all`] runs it and the tests
/// (`crates/cfe-tools/tests/verification.rs`) assert every case of it at both
/// levels, so a case added here is asserted without a test of its own.
pub const CASES: [(&str, CaseFn); 31] = [
    ("patch tests", patch::constant_stress),
    ("contact patch test", patch::contact_patch),
    ("tied cantilever", cantilever::convergence),
    ("penalty study", cantilever::penalty_study),
    ("bonded punch", punch::bonded_punch),
    ("host choice", patch::host_choice),
    ("seed examples", seed::schemes_and_refinement),
    ("curved interface", curved::lame_cylinder),
    ("Q4 and mixed meshes", quads::q4_and_mixed),
    ("contact iteration", contact::contact_iteration),
    ("segment patch test", segment::patch_comparison),
    ("segment convergence", segment::convergence),
    ("Hertz", hertz::hertz),
    ("augmented Lagrangian", hertz::penalty_independence),
    ("Cattaneo–Mindlin", hertz::cattaneo_mindlin),
    ("shrink fit", fits::shrink_fit),
    ("frictionless patch test", fits::frictionless_patch),
    ("receding contact", fits::receding),
    ("axisymmetric cylinder", axisymmetric::thick_cylinder),
    ("axisymmetric press fit", axisymmetric::press_fit),
    ("axisymmetric flat punch", axisymmetric_contact::flat_punch),
    (
        "axisymmetric Hertz sphere",
        axisymmetric_contact::hertz_sphere,
    ),
    ("3D tied patch tests", solid_patch::tied_patch),
    ("3D contact patch test", solid_patch::contact_patch),
    ("3D Coulomb", solid_patch::coulomb),
    ("3D flat punch", solid_contact::flat_punch),
    ("3D Hertz", solid_contact::hertz),
    ("3D shrink fit", solid_contact::shrink_fit),
    ("3D tied cantilever", solid_beam::cantilever),
    ("3D extrusion", solid_beam::extrusion),
    ("3D plate on a base vs CalculiX", solid_peer::calculix),
];

/// Runs every case of [`CASES`] (`quick`: the reduced versions), calling
/// `progress` with each one's name before it runs.
pub fn run_all(quick: bool, progress: &mut dyn FnMut(&str)) -> Result<Vec<Case>> {
    let mut cases = Vec::with_capacity(CASES.len());
    for (name, f) in CASES {
        progress(name);
        cases.push(f(quick)?);
    }
    Ok(cases)
}

/// The cases that did not meet their reference: `cfe verify` fails (exits
/// non-zero) when there is any.
pub fn failures(cases: &[Case]) -> Vec<&Case> {
    cases.iter().filter(|c| !c.passed).collect()
}

/// Writes `verification.md` and its pictures (`verification/*.png`) into `out`.
pub fn write_report(out: &Path, cases: &[Case], quick: bool) -> Result<()> {
    let pictures = out.join("verification");
    std::fs::create_dir_all(&pictures).map_err(|e| Error::output(&pictures, e))?;
    let mut s = String::new();
    let _ = writeln!(s, "# Verification report\n");
    let _ = writeln!(
        s,
        "Generated by `cargo run --release -- verify --out docs{}` from the code in `crates/cfe-tools/src/verification/`. Each case states its setup, its independent reference, the numbers and a verdict. {} of {} cases meet their reference.\n",
        if quick { " --quick" } else { "" },
        cases.iter().filter(|c| c.passed).count(),
        cases.len()
    );
    for (i, c) in cases.iter().enumerate() {
        let _ = writeln!(s, "## {}. {}\n", i + 1, c.title);
        let _ = writeln!(s, "**Setup.** {}\n", c.setup);
        let _ = writeln!(s, "**Reference.** {}\n", c.reference);
        for t in &c.tables {
            let _ = writeln!(s, "{}\n", t.caption);
            let _ = writeln!(s, "| {} |", t.header.join(" | "));
            let _ = writeln!(s, "|{}", "---|".repeat(t.header.len()));
            for r in &t.rows {
                let _ = writeln!(s, "| {} |", r.join(" | "));
            }
            let _ = writeln!(s);
        }
        for p in &c.plots {
            chart::line_chart(
                &pictures.join(&p.file),
                &Axes {
                    title: &p.title,
                    x: &p.x,
                    y: &p.y,
                    log_x: p.log.0,
                    log_y: p.log.1,
                },
                &p.series,
            )?;
            let _ = writeln!(s, "![{}](verification/{})\n", p.title, p.file);
        }
        let _ = writeln!(
            s,
            "**Verdict.** {} {}\n",
            if c.passed { "✅" } else { "❌" },
            c.verdict
        );
    }
    cfe::output::write_atomic(&out.join("verification.md"), |w| w.write_all(s.as_bytes()))
}

/// The complementary energy density σᵀ D⁻¹ σ of a stress (σxx, σyy, σxy) in `m`
/// (per unit volume; multiply by t dA).
pub fn energy_density(m: &cfe::fem::material::Material, s: [f64; 3]) -> f64 {
    let d = m.d_matrix();
    // D⁻¹ by cofactors (D is symmetric positive definite).
    let det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1])
        - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
        + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
    let c = |i: usize, j: usize| {
        let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
        let (c0, c1) = ((j + 1) % 3, (j + 2) % 3);
        d[r0][c0] * d[r1][c1] - d[r0][c1] * d[r1][c0]
    };
    let mut e = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            // (D⁻¹)_ij = cofactor_ji / det
            e += s[i] * c(j, i) / det * s[j];
        }
    }
    e
}

/// 6-point Dunavant rule (degree 4) on a triangle: barycentric points and weights.
pub const DUNAVANT4: [([f64; 3], f64); 6] = [
    (
        [0.445948490915965, 0.445948490915965, 0.108103018168070],
        0.223381589678011,
    ),
    (
        [0.445948490915965, 0.108103018168070, 0.445948490915965],
        0.223381589678011,
    ),
    (
        [0.108103018168070, 0.445948490915965, 0.445948490915965],
        0.223381589678011,
    ),
    (
        [0.091576213509771, 0.091576213509771, 0.816847572980459],
        0.109951743655322,
    ),
    (
        [0.091576213509771, 0.816847572980459, 0.091576213509771],
        0.109951743655322,
    ),
    (
        [0.816847572980459, 0.091576213509771, 0.091576213509771],
        0.109951743655322,
    ),
];

/// 3-point Gauss–Legendre rule on [−1, 1] (exact to degree 5): abscissae and weights.
const GAUSS3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// Quadrature of a function of the finite element stress over every part: calls
/// `f(part, element, x, w, σ_h)` at each quadrature point x of each element, with
/// w its weight (its share of the element's area times the thickness) and σ_h the
/// element's stress there. T3: the 6-point degree-4 Dunavant rule (σ_h constant),
/// exact for a quadratic reference stress. Q4: 3 × 3 Gauss points in (ξ, η),
/// σ_h = D B(ξ, η) u_e and w = det J × weights × t, exact for a parallelogram and a
/// quadratic reference stress.
pub fn for_each_stress_point(
    a: &Analysis,
    u: &[f64],
    mut f: impl FnMut(usize, usize, [f64; 2], f64, [f64; 3]),
) {
    use cfe::fem::{element, q4};
    use cfe::mesh::Element;
    for (p, part) in a.model.parts.iter().enumerate() {
        let m = &part.mesh;
        let s = 2 * a.dofs.node_offset[p];
        let up = &u[s..s + 2 * m.nodes.len()];
        let d = part.material.d_matrix();
        let t = part.material.thickness;
        for (e, el) in m.elements.iter().enumerate() {
            let x = element::coordinates(m, el);
            let ue = element::gather(el, up);
            match el {
                Element::T3(_) => {
                    let sigma = element::stresses(el, &x, &d, &ue).element;
                    let area = m.element_area(e);
                    for (b, w) in DUNAVANT4 {
                        let px = b[0] * x[0][0] + b[1] * x[1][0] + b[2] * x[2][0];
                        let py = b[0] * x[0][1] + b[1] * x[1][1] + b[2] * x[2][1];
                        f(p, e, [px, py], w * area * t, sigma);
                    }
                }
                Element::Q4(_) => {
                    for (xi, wi) in GAUSS3 {
                        for (eta, wj) in GAUSS3 {
                            let n = q4::shape([xi, eta]);
                            let pt = [0, 1].map(|c| (0..4).map(|k| n[k] * x[k][c]).sum());
                            let (_, det) = q4::b_matrix(&x, [xi, eta]);
                            let sigma = q4::stress_at(&x, &d, &ue, [xi, eta]);
                            f(p, e, pt, wi * wj * det * t, sigma);
                        }
                    }
                }
            }
        }
    }
}

/// The name of an element type in a problem file (`t3`, `q4`).
pub fn toml_kind(kind: cfe::mesh::ElementKind) -> &'static str {
    match kind {
        cfe::mesh::ElementKind::T3 => "t3",
        cfe::mesh::ElementKind::Q4 => "q4",
    }
}

/// Formats a number in scientific notation with 3 significant digits.
pub fn sci(v: f64) -> String {
    format!("{v:.3e}")
}

/// Observed convergence order between successive errors when the size halves.
pub fn orders(errors: &[f64]) -> Vec<String> {
    std::iter::once(String::new())
        .chain(
            errors
                .windows(2)
                .map(|w| format!("{:.2}", (w[0] / w[1]).abs().log2())),
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use cfe::fem::material::{Material, PlaneKind};

    /// σᵀD⁻¹σ: uniaxial stress gives σ²/E, pure shear τ²/G, in plane stress and
    /// plane strain (where uniaxial in-plane stress gives (1 − ν²)σ²/E).
    #[test]
    fn energy_density_matches_hand_values() {
        let (e, nu) = (200.0, 0.25);
        let g = e / (2.0 * (1.0 + nu));
        let ps = Material::new(e, nu, PlaneKind::Stress, 1.0, "t").unwrap();
        let pe = Material::new(e, nu, PlaneKind::Strain, 1.0, "t").unwrap();
        assert!((energy_density(&ps, [2.0, 0.0, 0.0]) - 4.0 / e).abs() < 1e-14);
        assert!((energy_density(&ps, [0.0, 0.0, 3.0]) - 9.0 / g).abs() < 1e-14);
        assert!((energy_density(&pe, [2.0, 0.0, 0.0]) - 4.0 * (1.0 - nu * nu) / e).abs() < 1e-14);
    }
}
