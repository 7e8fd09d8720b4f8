//! The roller in its cradle (examples/roller_in_cradle): two Gmsh meshes, a coarse
//! Q4 roller hosting a fine T3 cradle's circular seat, the load 30° from the
//! vertical. Checks the curved coupling (every seat node projected on the roller's
//! chords, no farther than their sagitta), equilibrium, the contact conditions at
//! every pair, and the state pattern: bonded on the loaded side, open on the other.

mod common;

use cfe::analysis::Analysis;
use cfe::coupling::PairState;
use cfe::model::Model;
use std::path::Path;

fn example_at(refine: usize) -> Analysis {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join("examples/roller_in_cradle/roller_in_cradle.toml");
    Analysis::new(Model::from_file(&path, refine).unwrap()).unwrap()
}

fn example() -> Analysis {
    example_at(1)
}

/// 43 five-node CFEs on the roller's quadrilaterals; the seat's nodes, which lie
/// on the circle, are moved onto the roller's chords by at most the sagitta
/// h²/(8R) of the roller's 10° edges (0.076 mm), and do move (the faces are
/// curved).
#[test]
fn curved_seat_couples_to_the_chords() {
    let a = example();
    let (roller, cradle) = (&a.model.parts[0], &a.model.parts[1]);
    assert_eq!(roller.mesh.counts().1, roller.mesh.elements.len(), "all Q4");
    assert_eq!(cradle.mesh.counts().0, cradle.mesh.elements.len(), "all T3");
    let seat = &a.interfaces[0];
    assert_eq!(seat.elements.len(), 43);
    assert!(seat.elements.iter().all(|c| c.host_nodes.len() == 4));
    let (r, h) = (20.0f64, 2.0 * 20.0 * (5f64.to_radians()).sin());
    let sagitta = r * (1.0 - 5f64.to_radians().cos());
    assert!((sagitta - h * h / (8.0 * r)).abs() < 1e-2 * sagitta);
    assert!(
        seat.max_projection_distance > 0.5 * sagitta
            && seat.max_projection_distance <= sagitta * (1.0 + 1e-9),
        "{} vs sagitta {sagitta}",
        seat.max_projection_distance
    );
    // The moved nodes sit on the roller's boundary: Σ N̄ᵢ Xᵢ = X_C, and in the
    // cradle's mesh.
    for c in &seat.elements {
        let x: [f64; 2] = std::array::from_fn(|k| {
            c.host_nodes
                .iter()
                .zip(&c.shape)
                .map(|(&n, w)| w * roller.mesh.nodes[n][k])
                .sum()
        });
        assert!(cfe::mesh::dist(x, c.position) < 1e-12 * r);
        assert_eq!(cradle.mesh.nodes[c.node], c.position);
    }
}

/// The load pushes the roller down and to the right: the seat stays bonded on the
/// right (loaded) side and opens on the far left, with no penetration where bonded
/// and no force where open; the base's reaction balances the 1000 N load.
#[test]
fn bonded_on_the_loaded_side_open_on_the_other() {
    let a = example();
    let incs = common::solve(&a);
    let last = incs.last().unwrap();
    common::check_contact_conditions(&a, last);
    let rows = a.pair_rows(last);
    for r in &rows {
        if r.x > 0.0 {
            assert_eq!(
                r.state,
                PairState::Bonded,
                "pair at x = {} on the loaded side",
                r.x
            );
        }
        if r.x < -12.0 {
            assert_eq!(
                r.state,
                PairState::Open,
                "pair at x = {} on the far side",
                r.x
            );
        }
    }
    let open = rows.iter().filter(|r| r.state == PairState::Open).count();
    assert!((5..=20).contains(&open), "{open} open pairs");
    // Equilibrium: Σ reactions = −Σ loads.
    let reaction = common::total_reaction(&a, last);
    let load = [500.0, -1000.0 * 30f64.to_radians().cos()];
    for k in 0..2 {
        assert!(
            (reaction[k] + load[k]).abs() < 1e-8 * 1000.0,
            "{reaction:?}"
        );
    }
    // Proportional load: the pattern is found in the first increment and kept.
    assert!(incs.iter().all(|i| i.states == last.states));
    assert!(incs[1..].iter().all(|i| i.iterations == 1));
}

/// `--refine 3` subdivides both Gmsh meshes (the seat stays the files' polygons):
/// 3 × 42 + 1 seat pairs, still coupled, moved by the same largest distance — the
/// tolerance refers to the host's edges as meshed in the file, as the gap between
/// the two polygons does not shrink with subdivision.
#[test]
fn refined_meshes_keep_the_curved_coupling() {
    let coarse = example();
    let fine = example_at(3);
    let seat = &fine.interfaces[0];
    assert_eq!(seat.elements.len(), 3 * 42 + 1);
    let (a, b) = (
        coarse.interfaces[0].max_projection_distance,
        seat.max_projection_distance,
    );
    assert!((a - b).abs() < 1e-9 * a, "{a} vs {b}");
}
