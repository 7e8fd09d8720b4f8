//! The segment coupling (`coupling = "segment"`) end to end: with the contact law
//! on the seed's plate on a base (pairs open and bonded), its outputs, and its
//! input errors.

mod common;

use cfe::analysis::Analysis;
use cfe::coupling::{Coupling, PairState};
use cfe::model::Model;
use std::path::Path;

fn plate_on_base(coupling: Coupling) -> Analysis {
    let mut model = Model::from_file(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml"),
        1,
    )
    .unwrap();
    model.interfaces[0].coupling = coupling;
    Analysis::new(model).unwrap()
}

/// The seed's plate pressed on a base through a contact interface with segment
/// coupling: one pair per coupling node (29), every increment ends on a state that
/// satisfies the law at every pair (no violation, no settled pair), bonded pairs
/// do not penetrate and open ones carry nothing, the pair forces balance the
/// 1500 N load, the ends lift off as with the node CFE, and the bonded zone is the
/// node CFE's to within one node at each end.
#[test]
fn contact_law_on_the_plate_on_base() {
    let a = plate_on_base(Coupling::Segment);
    assert_eq!(a.interfaces[0].elements.len(), 29);
    let incs = common::solve(&a);
    let last = incs.last().unwrap();
    for inc in &incs {
        assert!(
            inc.violations.is_empty() && inc.settled.is_empty(),
            "increment {}",
            inc.index
        );
    }
    common::check_contact_conditions(&a, last);
    let rows = a.pair_rows(last);
    // Global y force on the plate from the pairs: Σ (f_n n + f_s s)_y.
    let fy: f64 = rows
        .iter()
        .zip(&a.interfaces[0].elements)
        .map(|(r, c)| r.force_n * c.normal[1] + r.force_s * c.normal[0])
        .sum();
    assert!((fy - 1500.0).abs() < 1e-6 * 1500.0, "{fy}");
    assert!(
        rows.iter()
            .all(|r| r.segment.is_some() && r.tributary > 0.0)
    );
    let node = plate_on_base(Coupling::Node);
    let node_last = common::solve(&node).pop().unwrap();
    let bonded = |states: &[PairState]| -> Vec<usize> {
        states
            .iter()
            .enumerate()
            .filter(|(_, s)| **s == PairState::Bonded)
            .map(|(k, _)| k)
            .collect()
    };
    let (seg, nod) = (bonded(&last.states[0]), bonded(&node_last.states[0]));
    assert!(!seg.is_empty() && seg.len() < 29, "{seg:?}");
    let (s0, s1) = (seg[0], *seg.last().unwrap());
    let (n0, n1) = (nod[0], *nod.last().unwrap());
    assert!(
        s0.abs_diff(n0) <= 1 && s1.abs_diff(n1) <= 1,
        "{seg:?} vs {nod:?}"
    );
}

/// A misspelt coupling is an input error naming the accepted values.
#[test]
fn unknown_coupling_is_an_error() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml"),
    )
    .unwrap()
    .replace("[[interface]]", "[[interface]]\ncoupling = \"segments\"");
    let e = Model::from_str(&text, Path::new("p.toml"), 1)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("segments") && e.contains("segment") && e.contains("node"),
        "{e}"
    );
}
