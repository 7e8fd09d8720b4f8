//! Shared helpers of the integration tests: build a model from text and solve it
//! without writing files.
#![allow(dead_code)]

use cfe::analysis::Analysis;
use cfe::analysis::Start;
use cfe::coupling::PairState;
use cfe::model::Model;
use cfe::solve::nonlinear::{IncrementResult, Solver};
use std::path::Path;

/// Prepares an analysis from problem text.
pub fn analysis(text: &str) -> Analysis {
    let model = Model::from_str(text, Path::new("test.toml"), 1).expect("valid problem");
    Analysis::new(model).expect("pairs found")
}

/// Solves every increment in memory and returns them all.
pub fn solve(a: &Analysis) -> Vec<IncrementResult> {
    let mut all = Vec::new();
    a.solve_from(Start::AllBonded, |inc| {
        all.push(inc.clone());
        Ok(())
    })
    .expect("converges");
    all
}

/// Runs `solver` to its end and returns every increment.
pub fn run_all(mut solver: Solver<'_>) -> Vec<IncrementResult> {
    let mut all = Vec::new();
    solver
        .run(|inc| {
            all.push(inc.clone());
            Ok(())
        })
        .expect("converges");
    all
}

/// Displacement (x, y) of the node of `part` at `at`.
pub fn displacement_at(a: &Analysis, inc: &IncrementResult, part: &str, at: [f64; 2]) -> [f64; 2] {
    let p = a.model.part_index(part).expect("part");
    let n = a.model.parts[p]
        .mesh
        .nodes
        .iter()
        .position(|x| (x[0] - at[0]).abs() < 1e-9 && (x[1] - at[1]).abs() < 1e-9)
        .expect("node at point");
    let g = a.dofs.node(p, n);
    [inc.u[2 * g], inc.u[2 * g + 1]]
}

/// Checks the contact conditions of a converged increment: no bonded pair
/// penetrates by more than 1e-4 of the largest displacement, every open pair has
/// gap_n > 0 and carries no force.
pub fn check_contact_conditions(a: &Analysis, inc: &IncrementResult) {
    let umax = inc
        .u
        .chunks(2)
        .map(|d| d[0].hypot(d[1]))
        .fold(0.0, f64::max);
    for row in a.pair_rows(inc) {
        if row.state == PairState::Bonded {
            assert!(
                -row.gap_n <= 1e-4 * umax,
                "bonded pair at x = {} penetrates by {:e}",
                row.x,
                -row.gap_n
            );
        } else {
            assert!(
                row.gap_n > 0.0,
                "open pair at x = {} has gap {:e}",
                row.x,
                row.gap_n
            );
            assert!(
                row.force_n == 0.0 && row.force_s == 0.0,
                "open pair at x = {} carries force",
                row.x
            );
        }
    }
}

/// The sum of all support reactions (x, y).
pub fn total_reaction(a: &Analysis, inc: &IncrementResult) -> [f64; 2] {
    a.reactions(inc)
        .iter()
        .fold([0.0; 2], |t, r| [t[0] + r[0], t[1] + r[1]])
}
