//! Axisymmetric analysis (`plane = "axisymmetric"`) against Lamé: the thick
//! cylinder under internal pressure (convergence of Q4 and T3) and the press fit
//! of two cylinders with interference (node and segment coupling), both with
//! plane-strain ends (εzz = 0), for which Lamé's solutions are exact.

use super::{Case, Plot, Table, prepare};
use cfe::RunStatus;
use cfe::error::{Error, Result};
use cfe::output::chart::Series;
use std::f64::consts::PI;

const E: f64 = 210_000.0;
const NU: f64 = 0.3;
const A: f64 = 10.0;
const B: f64 = 20.0;
const P: f64 = 100.0;

/// Lamé's thick cylinder A ≤ r ≤ B under internal pressure P, εzz = 0:
/// (u, σrr, σθθ) at r.
fn lame(r: f64) -> (f64, f64, f64) {
    let aa = P * A * A / (B * B - A * A);
    let bb = aa * B * B;
    let u = (1.0 + NU) / E * ((1.0 - 2.0 * NU) * aa * r + bb / r);
    (u, aa - bb / (r * r), aa + bb / (r * r))
}

/// The cylinder's problem text: `cells` (radial, axial) of `elements`.
fn cylinder(cells: [usize; 2], elements: &str) -> String {
    format!(
        "plane = \"axisymmetric\"\n[materials.steel]\nE = {E:?}\nnu = {NU:?}\n[[part]]\nname = \"tube\"\nmaterial = \"steel\"\nrectangle = {{ x = [{A:?}, {B:?}], y = [0.0, 2.0], cells = [{}, {}], elements = \"{elements}\" }}\n[[support]]\npart = \"tube\"\nboundary = \"bottom\"\nfix = [\"y\"]\n[[support]]\npart = \"tube\"\nboundary = \"top\"\nfix = [\"y\"]\n[[load]]\npart = \"tube\"\nboundary = \"left\"\npressure = {P:?}\n[analysis]\nincrements = 1\n",
        cells[0], cells[1]
    )
}

/// The largest nodal displacement error (radial against Lamé, axial against 0)
/// relative to u(A), and the largest element σrr, σθθ error (against Lamé at the
/// element's centroid radius) relative to P.
fn cylinder_errors(cells: [usize; 2], elements: &str) -> Result<(f64, f64)> {
    let a = prepare(&cylinder(cells, elements))?;
    let res = a.solve()?;
    let part = &a.model.parts[0];
    let u_a = lame(A).0;
    let mut eu: f64 = 0.0;
    for (n, x) in part.mesh.nodes.iter().enumerate() {
        let g = a.dofs.node(0, n);
        eu = eu
            .max((res.last.u[2 * g] - lame(x[0]).0).abs() / u_a)
            .max(res.last.u[2 * g + 1].abs() / u_a);
    }
    let s = &res.stresses[0];
    let hoop = s
        .hoop
        .as_ref()
        .ok_or_else(|| Error::Model("no hoop stress".into()))?;
    let mut es: f64 = 0.0;
    for (e, el) in part.mesh.elements.iter().enumerate() {
        let nodes = el.nodes();
        let r = nodes.iter().map(|&n| part.mesh.nodes[n][0]).sum::<f64>() / nodes.len() as f64;
        let (_, srr, stt) = lame(r);
        es = es
            .max((s.element[e][0] - srr).abs() / P)
            .max((hoop.element[e] - stt).abs() / P);
    }
    Ok((eu, es))
}

/// Lamé's thick cylinder (10 ≤ r ≤ 20, p = 100 on the bore, εzz = 0) on meshes
/// refined by halving: the displacement and stress errors of Q4 and T3 and their
/// observed rates.
pub fn thick_cylinder(quick: bool) -> Result<Case> {
    let levels: &[usize] = if quick { &[4, 8] } else { &[4, 8, 16, 32] };
    let mut table = Table {
        caption: "Largest errors against Lamé: nodal displacement / u(a), element σrr and σθθ / p; rate = log₂ of the error ratio per halving.".into(),
        header: ["elements", "cells (r × z)", "displacement error", "rate", "stress error", "rate"]
            .map(String::from)
            .to_vec(),
        rows: Vec::new(),
    };
    let mut series = Vec::new();
    let mut passed = true;
    let mut last = Vec::new();
    for elements in ["q4", "t3"] {
        let mut errors = Vec::new();
        for &n in levels {
            errors.push((n, cylinder_errors([n, n / 2], elements)?));
        }
        for (i, &(n, (eu, es))) in errors.iter().enumerate() {
            let rate = |k: usize| {
                if i == 0 {
                    "".to_string()
                } else {
                    let prev = if k == 0 {
                        errors[i - 1].1.0
                    } else {
                        errors[i - 1].1.1
                    };
                    let now = if k == 0 { eu } else { es };
                    format!("{:.2}", (prev / now).log2())
                }
            };
            table.rows.push(vec![
                elements.to_uppercase(),
                format!("{n} × {}", n / 2),
                format!("{eu:.3e}"),
                rate(0),
                format!("{es:.3e}"),
                rate(1),
            ]);
        }
        // Displacement at least O(h^1.5) per halving, stresses at least O(h^0.5).
        for w in errors.windows(2) {
            passed &= (w[0].1.0 / w[1].1.0).log2() > 1.5 && (w[0].1.1 / w[1].1.1).log2() > 0.5;
        }
        series.push(Series {
            name: format!("{} displacement", elements.to_uppercase()),
            points: errors
                .iter()
                .map(|&(n, (eu, _))| (10.0 / n as f64, eu))
                .collect(),
            reference: false,
        });
        series.push(Series {
            name: format!("{} stress", elements.to_uppercase()),
            points: errors
                .iter()
                .map(|&(n, (_, es))| (10.0 / n as f64, es))
                .collect(),
            reference: false,
        });
        last.push((elements, errors.last().map(|e| e.1).unwrap_or_default()));
    }
    Ok(Case {
        title: "Axisymmetric thick cylinder (Lamé)".into(),
        setup: "plane = \"axisymmetric\": a steel cylinder 10 ≤ r ≤ 20 mm, 0 ≤ z ≤ 2 mm, E = 210 GPa, ν = 0.3, pressure 100 MPa on the bore, top and bottom held in z (εzz = 0). One part of Q4 or T3 (rising diagonals), n × n/2 cells, n halving the mesh size level by level.".into(),
        reference: "Lamé (plane strain): σrr = A − B/r², σθθ = A + B/r², A = p a²/(b² − a²), B = A b², u = (1 + ν)/E ((1 − 2ν) A r + B/r), u_z = 0.".into(),
        tables: vec![table],
        plots: vec![Plot {
            file: "axisymmetric_cylinder.png".into(),
            title: "Axisymmetric thick cylinder: error against Lamé".into(),
            x: "element size [mm]".into(),
            y: "relative error".into(),
            log: (true, true),
            series,
        }],
        verdict: format!(
            "Both element types converge to Lamé (displacement faster than h^1.5, stresses than h^0.5 per halving); finest: {}.",
            last.iter()
                .map(|(e, (eu, es))| format!("{} displacement {eu:.1e}, stress {es:.1e}", e.to_uppercase()))
                .collect::<Vec<_>>()
                .join("; ")
        ),
        passed,
    })
}

/// Lamé's press-fit pressure (same material, εzz = 0): shaft a ≤ r ≤ b + δ, hub
/// b ≤ r ≤ c, `p = E′ δ / (b [(c² + b²)/(c² − b²) + (b² + a²)/(b² − a²)])`, E′ = E/(1 − ν²).
fn press_fit_pressure(a: f64, b: f64, c: f64, delta: f64) -> f64 {
    let (a2, b2, c2) = (a * a, b * b, c * c);
    E / (1.0 - NU * NU) * delta / (b * ((c2 + b2) / (c2 - b2) + (b2 + a2) / (b2 - a2)))
}

/// The press fit: shaft 5 ≤ r ≤ 20.01, hub 20 ≤ r ≤ 40, 0 ≤ z ≤ 4, held in z
/// top and bottom, frictionless within a search distance, faces meshed `n` : 3n/4.
fn press_fit_text(n: usize, coupling: &str) -> String {
    let m = (3 * n).div_ceil(4);
    format!(
        "plane = \"axisymmetric\"\n[materials.steel]\nE = {E:?}\nnu = {NU:?}\n[[part]]\nname = \"shaft\"\nmaterial = \"steel\"\nrectangle = {{ x = [5.0, 20.01], y = [0.0, 4.0], cells = [16, {n}], elements = \"q4\" }}\n[[part]]\nname = \"hub\"\nmaterial = \"steel\"\nrectangle = {{ x = [20.0, 40.0], y = [0.0, 4.0], cells = [16, {m}], elements = \"q4\" }}\n[[support]]\npart = \"shaft\"\nboundary = \"bottom\"\nfix = [\"y\"]\n[[support]]\npart = \"shaft\"\nboundary = \"top\"\nfix = [\"y\"]\n[[support]]\npart = \"hub\"\nboundary = \"bottom\"\nfix = [\"y\"]\n[[support]]\npart = \"hub\"\nboundary = \"top\"\nfix = [\"y\"]\n[[interface]]\nhost = \"hub\"\nnodes = \"shaft\"\nboundary = \"right\"\nlaw = \"frictionless\"\ncoupling = \"{coupling}\"\nsearch_distance = 0.5\n[analysis]\nincrements = 1\n"
    )
}

/// The axisymmetric press fit against Lamé with interference: every pair's
/// pressure and the ring's total force, node and segment coupling.
pub fn press_fit(quick: bool) -> Result<Case> {
    let p = press_fit_pressure(5.0, 20.0, 40.0, 0.01);
    let levels: &[usize] = if quick { &[8] } else { &[8, 16, 32] };
    let mut table = Table {
        caption: format!(
            "Pair pressures against Lamé's p = {p:.4} MPa (largest deviation over the pairs) and the sum of the pairs' normal forces against p · 2πb · 4 mm."
        ),
        header: [
            "coupling",
            "cells along the shaft : hub face",
            "pairs",
            "largest abs(pressure − p) / p",
            "total force error",
        ]
        .map(String::from)
        .to_vec(),
        rows: Vec::new(),
    };
    let mut passed = true;
    let mut series = Vec::new();
    let mut segment_worst: f64 = 0.0;
    for coupling in ["node", "segment"] {
        for &n in levels {
            let a = prepare(&press_fit_text(n, coupling))?;
            let res = a.solve()?;
            let worst = res
                .pairs
                .iter()
                .map(|r| (r.pressure - p).abs() / p)
                .fold(0.0, f64::max);
            let total: f64 = res.pairs.iter().map(|r| r.force_n).sum();
            let want = p * 2.0 * PI * 20.0 * 4.0;
            let total_err = (total - want).abs() / want;
            passed &= res.summary.status == RunStatus::Completed && total_err < 5e-3;
            if coupling == "segment" {
                segment_worst = segment_worst.max(worst);
                passed &= worst < 1e-3;
            }
            table.rows.push(vec![
                coupling.into(),
                format!("{n} : {}", (3 * n).div_ceil(4)),
                res.pairs.len().to_string(),
                format!("{worst:.2e}"),
                format!("{total_err:.2e}"),
            ]);
            if n == levels[levels.len() - 1] {
                series.push(Series {
                    name: format!("{coupling} coupling"),
                    points: res.pairs.iter().map(|r| (r.y, r.pressure)).collect(),
                    reference: false,
                });
            }
        }
    }
    series.push(Series {
        name: "Lamé".into(),
        points: vec![(0.0, p), (4.0, p)],
        reference: true,
    });
    Ok(Case {
        title: "Axisymmetric press fit (Lamé with interference)".into(),
        setup: "plane = \"axisymmetric\": a hollow steel shaft 5 ≤ r ≤ 20.01 mm in a steel hub 20 ≤ r ≤ 40 mm, 0 ≤ z ≤ 4 mm, both held in z top and bottom (εzz = 0), radial interference δ = 0.01 mm, frictionless, the shaft's face paired with the hub's bore within search_distance = 0.5 at its overclosure g₀ = −δ; Q4, faces meshed 4 : 3 (non-matching).".into(),
        reference: "Lamé with interference, same material, εzz = 0: p = E′ δ / (b [(c² + b²)/(c² − b²) + (b² + a²)/(b² − a²)]), E′ = E/(1 − ν²) (as the plane-strain shrink fit); pressure = force / (tributary × 2π r̄).".into(),
        tables: vec![table],
        plots: vec![Plot {
            file: "axisymmetric_press_fit.png".into(),
            title: "Axisymmetric press fit: pair pressure along z".into(),
            x: "z [mm]".into(),
            y: "pressure [MPa]".into(),
            log: (false, false),
            series,
        }],
        verdict: format!(
            "The segment coupling gives Lamé's pressure at every pair within {segment_worst:.1e} (asserted 1e-3); the node coupling oscillates about it on the non-matching faces; the ring's total force is within 0.5 % for both."
        ),
        passed,
    })
}
