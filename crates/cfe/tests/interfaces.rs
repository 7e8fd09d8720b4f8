//! Many parts and interfaces: a stack of three independently meshed blocks, the
//! middle one hosting the interface above it and providing the nodes of the one
//! below, with mixed element types; and the errors of conflicting interfaces.
//!
//! ```text
//!   ↓↓↓↓↓↓↓↓ p            y = 3
//!   ┌────────┐  C: 8 × 8 T3 (nodes of 'B-C')
//!   ├────────┤            y = 2
//!   │   B    │  4 × 4 Q4 (hosts 'B-C', nodes of 'A-B')
//!   ├────────┤            y = 1
//!   │   A    │  2 × 2 T3 (hosts 'A-B')
//!   └────────┘            y = 0, rollers (one node pinned)
//! ```
//!
//! Every host vertex on an interface coincides with a coupling node, so the
//! uniform state passes the ties exactly up to the penalty's O(E·t/c).

mod common;

use common::Problem;

use cfe::model::Model;
use std::path::Path;

fn stack(e: [f64; 3], nu: f64) -> String {
    Problem::compact()
        .material("a", e[0], nu)
        .material("b", e[1], nu)
        .material("c", e[2], nu)
        .part("A", "a")
        .rectangle([0.0, 1.0], [0.0, 1.0], [2, 2])
        .part("B", "b")
        .rectangle_of([0.0, 1.0], [1.0, 2.0], [4, 4], "q4")
        .part("C", "c")
        .rectangle([0.0, 1.0], [2.0, 3.0], [8, 8])
        .named_interface("A-B", "A", "B", "bottom")
        .law("rigid")
        .named_interface("B-C", "B", "C", "bottom")
        .law("rigid")
        .rollers("A", [0.0, 0.0])
        .pressure("C", "top", 1.0)
        .increments(1)
        .text()
}

/// Uniform compression of the stack (one material, ν = 0.3): every element of all
/// three parts carries σ = (0, −p, 0) to the penalty's accuracy, and the support
/// reaction balances the pressure's resultant.
#[test]
fn stack_carries_a_uniform_stress_through_two_interfaces() {
    let a = common::analysis(&stack([1000.0; 3], 0.3));
    assert_eq!(a.interfaces.len(), 2);
    assert_eq!(a.interfaces[0].elements.len(), 5);
    assert_eq!(a.interfaces[1].elements.len(), 9);
    // The B-C pairs are 5-node CFEs on B's quadrilaterals.
    assert!(
        a.interfaces[1]
            .elements
            .iter()
            .all(|c| c.host_nodes.len() == 4)
    );
    let inc = common::solve(&a).pop().unwrap();
    for (part, s) in a.model.parts.iter().zip(a.recover(&inc.u)) {
        for v in &s.element {
            let err = (v[0].abs()).max((v[1] + 1.0).abs()).max(v[2].abs());
            // The default penalty is 1e5 E·t: the tie's error is O(1e-5).
            assert!(err < 1e-5, "part {}: {v:?}", part.name);
        }
    }
    let fy = common::total_reaction(&a, &inc)[1];
    assert!((fy - 1.0).abs() < 1e-9, "reaction {fy}");
}

/// Three materials in series (ν = 0): the top shortens by p Σ hᵢ/Eᵢ, the springs
/// of the two ties adding only O(E·t/c) to it.
#[test]
fn stack_shortens_like_springs_in_series() {
    let e = [1000.0, 4000.0, 250.0];
    let a = common::analysis(&stack(e, 0.0));
    let inc = common::solve(&a).pop().unwrap();
    let expected = -(1.0 / e[0] + 1.0 / e[1] + 1.0 / e[2]);
    for x in [0.0, 0.375, 1.0] {
        let v = common::displacement_at(&a, &inc, "C", [x, 3.0])[1];
        assert!(
            ((v - expected) / expected).abs() < 1e-4,
            "top at x = {x}: {v} vs {expected}"
        );
    }
}

/// A node can couple through one interface only: C's bottom nodes claimed by a
/// second interface is an error naming the node, the part and both interfaces.
#[test]
fn a_node_claimed_by_two_interfaces_is_an_error() {
    // One A-C interface (before the first support; two would be refused as a
    // name given twice before the claim is seen).
    let text = stack([1000.0; 3], 0.3).replacen(
        "[[support]]",
        "[[interface]]\nname = \"A-C\"\nhost = \"A\"\nnodes = \"C\"\nboundary = \"bottom\"\n\n[[support]]",
        1,
    );
    let e = Model::from_str(&text, Path::new("stack.toml"), 1)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("of part 'C' is claimed by interfaces 'B-C' and 'A-C'"),
        "{e}"
    );
}
