//! The coupling element's tangent checked against its force: central finite
//! differences of [`super::Interface::pair_at`] (pmsim style), on the law
//! fixture's interface. A test-only file: the fixture and the module it tests
//! are both below it.

use super::fixture;
use super::{Law, PairHistory, PairState, SegmentSide};

/// The coupling element's stiffness is the derivative of its force
/// (central finite differences of `Interface::pair_at`'s nodal force, pmsim
/// style): for a bonded pair of every unilateral law (the frictionless one
/// without tangential stiffness), with an initial gap, a plastic slip and
/// multipliers (constant terms), and for a slipping pair (its stabilising
/// spring), on a node CFE and a segment point with weight ω, tilted normal.
#[test]
fn stiffness_is_the_derivative_of_the_force() {
    let h = PairHistory {
        slip: 0.05,
        slip_force: 0.7,
        anchor: -0.02,
        multiplier: (-0.3, 0.1),
    };
    let dofs = fixture::dofs(2);
    let u0: Vec<f64> = (0..10).map(|i| 0.01 * ((i * 7) % 5) as f64 - 0.02).collect();
    for (law, state) in [
        (Law::Contact, PairState::Bonded),
        (Law::Frictionless, PairState::Bonded),
        (Law::Coulomb, PairState::Bonded),
        (Law::Coulomb, PairState::Slip),
    ] {
        let mut iface = fixture::interface(law, 2, 0.5);
        let a: f64 = 0.4;
        iface.elements[0].normal = [a.cos(), a.sin()];
        iface.elements[0].gap0 = 0.01;
        iface.elements[1].normal = [a.cos(), a.sin()];
        iface.elements[1].segment = Some(SegmentSide {
            nodes: vec![0, 1],
            shape: vec![0.7, 0.3],
            length: 0.4,
            weight: 0.6,
        });
        for (k, c) in iface.elements.iter().enumerate() {
            let [c_n, c_s] = iface.params().penalties(state);
            let ke = c.stiffness(c_n, c_s, PairState::Bonded);
            let g = c.dofs(&dofs, iface.host, iface.node_part);
            let force = |u: &[f64]| c.nodal_force(iface.pair_at(k, &dofs, u, state, &h).force);
            let step = 1e-4;
            let scale = (0..ke.dofs)
                .flat_map(|p| (0..ke.dofs).map(move |q| (p, q)))
                .map(|(p, q)| ke.get(p, q).abs())
                .fold(0.0, f64::max);
            for (q, &dof) in g.as_slice().iter().enumerate() {
                let (mut up, mut down) = (u0.clone(), u0.clone());
                up[dof] += step;
                down[dof] -= step;
                let (fp, fm) = (force(&up), force(&down));
                for p in 0..ke.dofs {
                    let fd = (fp[p] - fm[p]) / (2.0 * step);
                    assert!(
                        (fd - ke.get(p, q)).abs() <= 1e-8 * scale,
                        "{law:?} {state:?} pair {k}: K[{p}][{q}] = {} but dF/du = {fd}",
                        ke.get(p, q)
                    );
                }
            }
        }
    }
}
