//! Shrink fits with no applied load: the interference is the only cause.
//!
//! A hollow shaft (a ≤ r ≤ b + δ) in a hub (b ≤ r ≤ c), same material, both
//! meshed with the annulus mesher (Q4), the shaft's outer face paired with the
//! hub's bore within a search distance at its initial gap g₀ ≈ −δ. Lamé (thick
//! cylinders, same E and ν): the hub's bore moves out by
//! u_h = (p b / E′)((c² + b²)/(c² − b²) + ν′) and the shaft's face in by
//! u_s = (p b / E′)((b² + a²)/(b² − a²) − ν′); u_h + u_s = δ gives
//!
//! ```text
//! p = E′ δ / (b [ (c² + b²)/(c² − b²) + (b² + a²)/(b² − a²) ])
//! ```
//!
//! (ν′ cancels; E′ = E in plane stress, E/(1 − ν²) in plane strain; for a solid
//! shaft, a = 0, p = E′ δ (c² − b²) / (2 b c²)).

mod common;

use cfe::RunStatus;
use common::Problem;

const E: f64 = 210_000.0;
const NU: f64 = 0.3;
const A: f64 = 5.0;
const B: f64 = 20.0;
const C: f64 = 40.0;
const DELTA: f64 = 0.01;

/// Lamé's interface pressure for the shaft and hub above (`plane_strain`: E′ =
/// E / (1 − ν²)).
fn lame_pressure(plane_strain: bool) -> f64 {
    let e = if plane_strain { E / (1.0 - NU * NU) } else { E };
    let (a2, b2, c2) = (A * A, B * B, C * C);
    e * DELTA / (B * ((c2 + b2) / (c2 - b2) + (b2 + a2) / (b2 - a2)))
}

/// The shaft and hub over `theta` (degrees) with `cells` around each (shaft,
/// hub), `coupling`, the law `law` and the supports `supports` adds, one
/// increment.
fn fit(
    plane: &str,
    theta: [f64; 2],
    cells: [usize; 2],
    law: &str,
    coupling: &str,
    supports: fn(Problem) -> Problem,
) -> String {
    let problem = Problem::compact()
        .plane(plane)
        .material("steel", E, NU)
        .part("shaft", "steel")
        .annulus([0.0, 0.0], [A, B + DELTA], theta, [6, cells[0]], "q4")
        .part("hub", "steel")
        .annulus([0.0, 0.0], [B, C], theta, [6, cells[1]], "q4")
        .interface("hub", "shaft", "outer")
        .law(law)
        .iface_key("coupling", coupling)
        .iface_key("search_distance", 0.5);
    supports(problem).increments(1).text()
}

/// Symmetry supports on both parts' radial edges (a quarter model).
fn symmetry(p: Problem) -> Problem {
    p.quarter_symmetry("shaft").quarter_symmetry("hub")
}

/// The shaft's bore pinned at (a, 0) in x and y and at (−a, 0) in y.
fn pinned_bore(p: Problem) -> Problem {
    p.support_at("shaft", [A, 0.0], ["x", "y"])
        .support_at("shaft", [-A, 0.0], ["y"])
}

/// A quarter model (symmetry supports on both parts' radial edges) whose shaft
/// end nodes, at (b + δ, 0) and (0, b + δ), lie on the hub's symmetry edges
/// (distance 0). The gap pairs are made with the hub's bore only, never with a
/// symmetry edge: every pair's normal is the inward radial direction to within
/// half a hub edge's angle (the end pairs' too, where once the node coupling
/// took the symmetry edge's normal, tangent to the bore, and lost the
/// interference, g₀ = 0, and the segment coupling a normal 49° off radial), the
/// end pairs keep g₀ = −δ (to the chord's cos(h/2)), and every pair — the
/// ends included — carries Lamé's pressure × its tributary length to 1.5 %, with
/// the node and the segment coupling, in plane stress and plane strain.
#[test]
fn quarter_model_end_nodes_pair_with_the_bore() {
    let n = 32;
    let half_edge = (90.0 / n as f64 / 2.0f64).to_radians();
    for (plane, strain) in [("stress", false), ("strain", true)] {
        let p = lame_pressure(strain);
        for coupling in ["node", "segment"] {
            let what = format!("plane {plane}, {coupling} coupling");
            let a = common::analysis(&fit(
                plane,
                [0.0, 90.0],
                [n, n],
                "frictionless",
                coupling,
                symmetry,
            ));
            let iface = &a.interfaces[0];
            assert_eq!(iface.elements.len(), n + 1, "{what}");
            assert_eq!(iface.unpaired, 0, "{what}");
            let shaft = &a.model.parts[a.model.part_index("shaft").unwrap()].mesh;
            let mut ends = 0;
            for c in &iface.elements {
                let x = shaft.nodes[c.node];
                let r = x[0].hypot(x[1]);
                let inward = [-x[0] / r, -x[1] / r];
                let cos = c.normal[0] * inward[0] + c.normal[1] * inward[1];
                assert!(
                    cos >= half_edge.cos() - 1e-12,
                    "{what}: node at ({}, {}) has normal {:?}, {:.2}° off radial",
                    x[0],
                    x[1],
                    c.normal,
                    cos.min(1.0).acos().to_degrees()
                );
                assert!(
                    (c.gap0 + DELTA).abs() <= DELTA * (1.0 - half_edge.cos()) + 1e-12,
                    "{what}: node at ({}, {}) has g0 = {}",
                    x[0],
                    x[1],
                    c.gap0
                );
                if x[0].abs() < 1e-9 || x[1].abs() < 1e-9 {
                    ends += 1;
                }
            }
            assert_eq!(ends, 2, "{what}");
            let res = a.solve().expect("solves");
            assert_eq!(
                res.summary.status,
                RunStatus::Completed,
                "{what}: {:?}",
                res.summary.warnings
            );
            for row in &res.pairs {
                let traction = row.force_n / row.tributary;
                assert!(
                    (traction - p).abs() < 0.015 * p,
                    "{what}: pair at ({}, {}) carries {} × its tributary {}, Lamé {p}",
                    row.x,
                    row.y,
                    traction,
                    row.tributary
                );
            }
        }
    }
}

/// A full ring shrink-fitted on the shaft, the assembly pinned statically
/// determinately (the shaft's bore at (a, 0) in x and y, at (−a, 0) in y):
/// nothing is loaded, so the load scale (applied force, reactions) is ≈ 0,
/// and the run once stopped or warned with an out-of-balance force "of the load
/// scale". Measured against the pair forces it completes: every pair carries
/// Lamé's pressure to 1.5 %, and the reactions are ≈ 0 (below 1e-6 of the
/// largest pair force: the interference is self-equilibrated).
#[test]
fn interference_ring_with_no_load_completes_at_lame() {
    let n = 64;
    for (plane, strain) in [("stress", false), ("strain", true)] {
        let p = lame_pressure(strain);
        let a = common::analysis(&fit(
            plane,
            [0.0, 360.0],
            [n, n],
            "contact",
            "node",
            pinned_bore,
        ));
        let res = a.solve().expect("solves");
        assert_eq!(
            res.summary.status,
            RunStatus::Completed,
            "plane {plane}: {:?}",
            res.summary.warnings
        );
        assert!(res.summary.violations.is_empty() && res.summary.warnings.is_empty());
        assert_eq!(res.pairs.len(), n);
        let mut largest: f64 = 0.0;
        for row in &res.pairs {
            let traction = row.force_n / row.tributary;
            assert!(
                (traction - p).abs() < 0.015 * p,
                "plane {plane}: pair at ({}, {}) carries {traction} × its tributary, Lamé {p}",
                row.x,
                row.y
            );
            largest = largest.max(row.force_n);
        }
        for r in &res.summary.reactions {
            assert!(
                r.fx.hypot(r.fy) < 1e-6 * largest,
                "plane {plane}: reaction {} = ({}, {}) against pair forces up to {largest}",
                r.support,
                r.fx,
                r.fy
            );
        }
    }
}
