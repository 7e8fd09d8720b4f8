//! The fast paths of the solver give the same answers as the plain ones: a
//! low-rank update of a factorization against a fresh factorization, and an
//! active-set iteration started from a coarse mesh's pattern against one started
//! from all pairs bonded.

mod common;

use cfe::analysis::{Analysis, Start};
use cfe::assembly::{NodeGraph, Stiffness};
use cfe::coupling::PairState;
use cfe::model::Model;
use cfe::solve::linear::CholeskySolver;
use cfe::solve::system::{ContactSystem, Method, Solve, UpdatePolicy};
use std::path::Path;

/// The contact system of `a`, its solves cut into `parts` parallel subtrees (1:
/// sequential; the fast paths under test use 2, whatever the size).
fn system(a: &Analysis, parts: usize) -> ContactSystem<'_> {
    let graph = NodeGraph::new(&a.model.parts, &a.interfaces, &a.dofs);
    let k = Stiffness::new(&a.model.parts, &a.dofs, &graph);
    let mut chol = k.with_matrix(|m| CholeskySolver::new(m, None)).unwrap();
    assert_eq!(chol.set_solve_parts(parts), parts);
    ContactSystem::new(&a.model.parts, k, chol)
}

/// The solution of `states` by a fresh factorization.
fn fresh(a: &Analysis, states: &[Vec<PairState>], rhs: &[f64]) -> Vec<f64> {
    let mut s = system(a, 1);
    let mut x = rhs.to_vec();
    assert_eq!(
        s.solve(&a.interfaces, &a.dofs, states, &mut x).unwrap(),
        Method::Factorization
    );
    x
}

/// Largest difference of `x` from `y`, relative to the largest entry of `y`.
fn relative_difference(x: &[f64], y: &[f64]) -> f64 {
    let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    x.iter()
        .zip(y)
        .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()))
        / scale
}

/// Opening the three outermost pairs at each end of the plate, then every third
/// pair, then the first pattern again with two pairs closed back (cached columns
/// reused, columns dropped): each Woodbury correction of the all-bonded
/// factorization (sparse forward solves of its columns) equals a fresh
/// factorization of the new states to 1e-10 relative; after the factor is freed,
/// the next solve refactorizes.
#[test]
fn low_rank_update_equals_refactorization() {
    let a = common::example("plate_on_base.toml", 2);
    let rhs = common::free_load(&a);
    let n = a.interfaces[0].elements.len();
    let [bonded, ends, thirds] = common::contact_patterns(n);
    let mut back = ends.clone();
    back[0][0] = PairState::Bonded;
    back[0][n - 1] = PairState::Bonded;
    let mut s = system(&a, 2);
    s.policy = UpdatePolicy::Always;
    let mut x0 = rhs.clone();
    assert_eq!(
        s.solve(&a.interfaces, &a.dofs, &bonded, &mut x0).unwrap(),
        Method::Factorization
    );
    for (states, rank) in [(&ends, 12), (&thirds, 2 * n.div_ceil(3)), (&back, 8)] {
        let mut x = rhs.clone();
        let m = s.solve(&a.interfaces, &a.dofs, states, &mut x).unwrap();
        assert_eq!(m, Method::LowRank { rank });
        let err = relative_difference(&x, &fresh(&a, states, &rhs));
        assert!(
            err < 1e-10,
            "rank {rank}: update differs from refactorization by {err:e}"
        );
    }
    // Freeing the factor: the next solve refactorizes, with the same answer.
    s.release();
    let mut x = rhs.clone();
    assert_eq!(
        s.solve(&a.interfaces, &a.dofs, &back, &mut x).unwrap(),
        Method::Factorization
    );
    assert!(relative_difference(&x, &fresh(&a, &back, &rhs)) < 1e-14);
}

/// Once an increment is accepted (`forget_right_hand_side`), the next
/// right-hand side's forward solve is kept and reused by the iterations that
/// share it: the same bits as a system that forward-solves it every time, less
/// work (one forward solve fewer), and a fresh factorization's answer to 1e-10.
#[test]
fn the_next_right_hand_side_is_kept_once_the_last_is_forgotten() {
    let a = common::example("plate_on_base.toml", 2);
    let rhs = common::free_load(&a);
    let other: Vec<f64> = rhs
        .iter()
        .enumerate()
        .map(|(i, v)| 2.0 * v + if i % 7 == 0 { 1.0 } else { 0.0 })
        .collect();
    let [bonded, ends, thirds] = common::contact_patterns(a.interfaces[0].elements.len());
    let solve = |s: &mut ContactSystem<'_>, states: &[Vec<PairState>], b: &[f64]| {
        let mut x = b.to_vec();
        s.solve(&a.interfaces, &a.dofs, states, &mut x).unwrap();
        x
    };
    let (mut kept, mut plain) = (system(&a, 2), system(&a, 2));
    for s in [&mut kept, &mut plain] {
        s.policy = UpdatePolicy::Always;
        solve(s, &bonded, &rhs);
    }
    kept.forget_right_hand_side();
    for states in [&ends, &thirds] {
        let x = solve(&mut kept, states, &other);
        let y = solve(&mut plain, states, &other);
        assert!(x.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()));
        assert!(relative_difference(&x, &fresh(&a, states, &other)) < 1e-10);
    }
    assert!(
        kept.flops < plain.flops,
        "the kept forward solve was not reused: {} flops against {}",
        kept.flops,
        plain.flops
    );
}

/// At refinement 4 the analysis starts from the pattern of refinement 1: the
/// result is the one found from an all-bonded start (the same pattern, the same
/// settled pairs and violations), satisfies the law on every pair but the settled
/// ones (no penetration, no tension where bonded; gap and no force where open), and
/// balances the load.
#[test]
fn coarse_start_reaches_a_law_consistent_pattern() {
    let a = common::example("plate_on_base.toml", 4);
    let start = a.coarse_states().expect("a coarser level exists");
    assert_eq!(start[0].len(), a.interfaces[0].elements.len());
    let run = |initial: Option<Vec<Vec<PairState>>>| {
        let start = initial.map_or(Start::AllBonded, Start::States);
        a.solve_from(start, |_| Ok(())).unwrap()
    };
    let (warm, cold) = (run(Some(start)), run(None));
    if warm.settled.is_empty() {
        assert!(warm.history.len() <= cold.history.len());
    }
    let umax = warm
        .u
        .chunks(2)
        .map(|d| d[0].hypot(d[1]))
        .fold(0.0, f64::max);
    for row in a.pair_rows(&warm) {
        if row.settled {
            continue;
        }
        if row.state == PairState::Bonded {
            assert!(-row.gap_n <= 1e-4 * umax);
            assert!(row.force_n >= -1e-6 * 1500.0, "tension {:e}", row.force_n);
        } else {
            assert!(row.gap_n > 0.0 && row.force_n == 0.0);
        }
    }
    assert!(warm.residual < 1e-8);
    assert_eq!(warm.states, cold.states);
    assert_eq!(warm.settled, cold.settled);
    assert_eq!(warm.violations.len(), cold.violations.len());
}

/// The solve restricted to the elimination-tree paths of the coupling equations
/// (what an active-set iteration checks the law with) gives a fresh
/// factorization's values at every coupling element's DOFs to 1e-10 relative:
/// with the factorized states themselves (no correction) and after Woodbury
/// corrections of rank 12 and 2⌈n/3⌉, for the load and for forces on the
/// coupling equations alone (forward-solved on the paths too); a first solve
/// (a factorization) is complete.
#[test]
fn interface_solve_equals_full_solve_at_the_pairs() {
    let a = common::example("plate_on_base.toml", 2);
    let rhs = common::free_load(&a);
    let iface = &a.interfaces[0];
    let n = iface.elements.len();
    let [bonded, ends, thirds] = common::contact_patterns(n);
    let coupling_eqs: Vec<usize> = common::coupling_equations(&a, 0);
    let mut s = system(&a, 2);
    s.policy = UpdatePolicy::Always;
    let mut x = rhs.clone();
    let (m, complete) = s
        .solve_interface(&a.interfaces, &a.dofs, &bonded, &mut x, false)
        .unwrap();
    assert_eq!((m, complete), (Method::Factorization, true));
    for (states, method) in [
        (&bonded, Method::Reuse),
        (&ends, Method::LowRank { rank: 12 }),
        (
            &thirds,
            Method::LowRank {
                rank: 2 * n.div_ceil(3),
            },
        ),
    ] {
        let mut x = rhs.clone();
        let (m, complete) = s
            .solve_interface(&a.interfaces, &a.dofs, states, &mut x, false)
            .unwrap();
        assert_eq!((m, complete), (method, false));
        let full = fresh(&a, states, &rhs);
        let scale = full.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for &e in &coupling_eqs {
            assert!(
                (x[e] - full[e]).abs() < 1e-10 * scale,
                "{method:?}: equation {e}: {} against {}",
                x[e],
                full[e]
            );
        }
        // A right-hand side on the coupling equations only (a change of the
        // pairs' forces), forward-solved on the paths too.
        let mut pair_forces = vec![0.0; rhs.len()];
        for (i, &e) in coupling_eqs.iter().enumerate() {
            pair_forces[e] = (0.7 * i as f64).cos();
        }
        let mut x = pair_forces.clone();
        let (_, complete) = s
            .solve_interface(&a.interfaces, &a.dofs, states, &mut x, true)
            .unwrap();
        assert!(!complete);
        let full = fresh(&a, states, &pair_forces);
        let scale = full.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for &e in &coupling_eqs {
            assert!(
                (x[e] - full[e]).abs() < 1e-10 * scale,
                "{method:?}: pair forces"
            );
        }
    }
}

/// A right-hand side on the coupling equations only (a change of the pairs'
/// forces) solved with its forward half on the interface's tree paths gives the
/// full solve's bits: with the factorized states (a factorization, then a reuse)
/// and after a Woodbury correction.
#[test]
fn pair_forces_solve_on_the_paths_with_the_full_solves_bits() {
    let a = common::example("plate_on_base.toml", 2);
    let n = a.interfaces[0].elements.len();
    let [bonded, ends, _] = common::contact_patterns(n);
    let iface = &a.interfaces[0];
    let mut forces = vec![0.0; a.dofs.n_eq];
    for (i, c) in iface.elements.iter().enumerate() {
        for &d in c.dofs(&a.dofs, iface.host, iface.node_part).as_slice() {
            let e = a.dofs.eq[d];
            if e != usize::MAX {
                forces[e] += (0.3 * i as f64 + d as f64).sin();
            }
        }
    }
    let (mut paths, mut full) = (system(&a, 2), system(&a, 2));
    paths.policy = UpdatePolicy::Always;
    full.policy = UpdatePolicy::Always;
    for (states, method) in [
        (&bonded, Method::Factorization),
        (&bonded, Method::Reuse),
        (&ends, Method::LowRank { rank: 12 }),
    ] {
        let (mut x, mut y) = (forces.clone(), forces.clone());
        let m = paths
            .solve_pair_forces(&a.interfaces, &a.dofs, states, &mut x)
            .unwrap();
        assert_eq!(m, method);
        full.solve(&a.interfaces, &a.dofs, states, &mut y).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&x), bits(&y), "{method:?}");
    }
}

/// Trials of one increment and load factor reuse the last trial's vectors
/// once it is given back (proportional loads: the right-hand side does not
/// depend on the states): a trial that reused them gives a fresh
/// factorization's displacements at every coupling DOF to 1e-10 of the
/// largest, and NaN at every other free DOF, as does a trial built anew (the
/// first, and one at another load factor), on the plate with the three
/// outermost pairs at each end open, then every third pair open.
#[test]
fn a_trial_reusing_the_last_ones_vectors_solves_its_own_pattern() {
    let a = common::example("plate_on_base.toml", 2);
    let n = a.interfaces[0].elements.len();
    let [bonded, ends, thirds] = common::contact_patterns(n);
    let coupling = cfe::coupling::coupling_dofs(&a.interfaces, &a.dofs);
    let mut solver = a.solver().unwrap();
    let mut direct = a.solver().unwrap();
    direct.set_update_policy(UpdatePolicy::Never);
    assert!(solver.proportional());
    // The complete solve that factorizes, as an increment's first iteration.
    solver.solve_pattern(1.0, &bonded).unwrap();
    for (states, lambda) in [(&ends, 1.0), (&thirds, 1.0), (&ends, 1.0), (&thirds, 0.5)] {
        let (u, method) = solver.solve_interface(lambda, states, 1).unwrap();
        assert!(matches!(method, Some(Method::LowRank { .. })), "{method:?}");
        let full = direct.solve_pattern(lambda, states).unwrap().u;
        let scale = full.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (d, &e) in a.dofs.eq.iter().enumerate() {
            if coupling.binary_search(&d).is_ok() {
                assert!((u[d] - full[d]).abs() < 1e-10 * scale, "DOF {d}");
            } else if e != usize::MAX {
                assert!(u[d].is_nan(), "DOF {d} off the interface: {}", u[d]);
            }
        }
        // As the active-set iteration does, once the law is checked.
        solver.return_trial(u);
    }
}

/// The stiffness stored in an elimination order is the same matrix: every entry
/// of K assembled in the equations' order (parts and coupling elements, some pairs
/// open) is found, bit for bit, at its permuted place both when the assembled
/// matrix is permuted (`in_order`) and when the values are assembled directly
/// into the permuted storage, after being freed.
#[test]
fn stiffness_in_elimination_order_is_the_same_matrix() {
    let a = common::example("plate_on_base.toml", 2);
    let n = a.interfaces[0].elements.len();
    let [_, ends, _] = common::contact_patterns(n);
    let graph = NodeGraph::new(&a.model.parts, &a.interfaces, &a.dofs);
    let mut k = Stiffness::new(&a.model.parts, &a.dofs, &graph);
    let chol = k.with_matrix(|m| CholeskySolver::new(m, None)).unwrap();
    let (order, inverse) = chol.order();
    let mut ordered = k.in_order(order, inverse);
    k.assemble(&a.model.parts, &a.interfaces, &ends, &a.dofs);
    let permuted = k.in_order(order, inverse);
    ordered.free_values();
    ordered.assemble(&a.model.parts, &a.interfaces, &ends, &a.dofs);
    assert_eq!(ordered.row_idx, permuted.row_idx);
    assert_eq!(ordered.values, permuted.values);
    let (mut entries, mut largest) = (0, 0.0f64);
    for j in 0..k.n() {
        for p in k.col_ptr[j]..k.col_ptr[j + 1] {
            let i = k.row_idx[p] as usize;
            let (r, c) = (ordered.stored(i), ordered.stored(j));
            let (r, c) = (r.max(c), r.min(c));
            let s = ordered.col_ptr[c]
                + ordered.row_idx[ordered.col_ptr[c]..ordered.col_ptr[c + 1]]
                    .binary_search(&(r as u32))
                    .unwrap();
            assert_eq!(ordered.values[s].to_bits(), k.values[p].to_bits());
            entries += 1;
            largest = largest.max(k.values[p].abs());
        }
    }
    assert_eq!(entries, ordered.row_idx.len());
    assert!(largest > 0.0);
}

/// A system that frees its stiffness's pattern after each factorization
/// (`keep_pattern = false`, as with proportional loads) builds it again for the
/// next one: two factorizations of different patterns give the same bits as
/// with the pattern kept, and the stored entries are still counted.
#[test]
fn a_freed_pattern_is_built_again_for_the_next_factorization() {
    let a = common::example("plate_on_base.toml", 2);
    let b = common::free_load(&a);
    let [bonded, ends, _] = common::contact_patterns(a.interfaces[0].elements.len());
    let solve_twice = |keep: bool| {
        let mut s = system(&a, 1);
        let entries = s.matrix_nnz();
        s.keep_pattern = keep;
        s.policy = UpdatePolicy::Never;
        let mut out = Vec::new();
        for states in [&bonded, &ends] {
            let mut x = b.clone();
            let method = s.solve(&a.interfaces, &a.dofs, states, &mut x).unwrap();
            assert_eq!(method, Method::Factorization);
            assert_eq!(s.matrix_nnz(), entries);
            out.push(x.iter().map(|v| v.to_bits()).collect::<Vec<_>>());
        }
        out
    };
    assert_eq!(solve_twice(false), solve_twice(true));
}

/// A low-rank update solved for refinement (`solve_unrefined`) gives the
/// plain update's values at the equations it is asked to read (every 97th
/// equation here, far from the interface too), to round-off, and nothing more
/// than a refactorization or a reuse is left unrefined; refined with a zero
/// residual it is the plain update's solution bit for bit (its forward half
/// kept whole through the backward solve on the paths).
#[test]
fn an_unrefined_update_reads_the_plain_update_and_refines_from_it() {
    let a = common::example("plate_on_base.toml", 2);
    let rhs = common::free_load(&a);
    let [bonded, ends, _] = common::contact_patterns(a.interfaces[0].elements.len());
    let read: Vec<usize> = (0..rhs.len()).step_by(97).collect();
    let (mut plain, mut split) = (system(&a, 2), system(&a, 2));
    for s in [&mut plain, &mut split] {
        s.policy = UpdatePolicy::Always;
    }
    let mut x = rhs.clone();
    plain
        .solve(&a.interfaces, &a.dofs, &bonded, &mut x)
        .unwrap();
    let mut y = rhs.clone();
    let first = split
        .solve_unrefined(&a.interfaces, &a.dofs, &bonded, &mut y, &read)
        .unwrap();
    assert!(matches!(first, Solve::Complete(Method::Factorization)));
    assert_eq!(x, y);
    let mut y = rhs.clone();
    let reuse = split
        .solve_unrefined(&a.interfaces, &a.dofs, &bonded, &mut y, &read)
        .unwrap();
    assert!(matches!(reuse, Solve::Complete(Method::Reuse)));
    assert_eq!(x, y);
    let mut x = rhs.clone();
    let method = plain.solve(&a.interfaces, &a.dofs, &ends, &mut x).unwrap();
    assert_eq!(method, Method::LowRank { rank: 12 });
    let mut y = rhs.clone();
    let Solve::Unrefined(unrefined) = split
        .solve_unrefined(&a.interfaces, &a.dofs, &ends, &mut y, &read)
        .unwrap()
    else {
        panic!("an update is left unrefined");
    };
    let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for &e in &read {
        assert!((y[e] - x[e]).abs() <= 1e-13 * scale, "equation {e}");
    }
    let mut r = vec![0.0; rhs.len()];
    assert_eq!(
        split.refine(unrefined, &mut r),
        Method::LowRank { rank: 12 }
    );
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&r), bits(&x));
}

/// Every increment of `a` solved with the update policy `policy`.
fn run_with(a: &Analysis, policy: UpdatePolicy) -> Vec<cfe::solve::nonlinear::IncrementResult> {
    let mut solver = a.solver().unwrap();
    solver.set_update_policy(policy);
    common::run_all(solver)
}

/// Two soft models where the Woodbury correction alone loses digits (pairs of
/// c = 1e9 opening from the bonded factorization): the bar in its bearing at
/// K = 4 (about 9 000 unknowns; the plain update is 6.5e-10 off) and a 6 mm
/// plate on the base loaded off-centre at K = 16 (about 170 000 unknowns; 2e-7
/// off). The refinement on the coupling equations brings the accepted solution
/// of the run by low-rank updates to that of a run refactorizing at every
/// iteration: the same states, every displacement within 1e-10 of the largest.
#[test]
fn a_refined_low_rank_solution_equals_the_refactorized_one() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let bearing =
        Analysis::new(Model::from_file(&root.join("examples/bar_in_bearing.toml"), 4).unwrap())
            .unwrap();
    // The plate 6 mm thick (3 cells), loaded over x = 120–148 on its top.
    let text = std::fs::read_to_string(root.join("examples/plate_on_base.toml"))
        .unwrap()
        .replace(
            "y = [120.0, 135.0], cells = [28, 6]",
            "y = [120.0, 126.0], cells = [28, 3]",
        )
        .replace("from = [86.0, 135.0]", "from = [120.0, 126.0]")
        .replace("to = [114.0, 135.0]", "to = [148.0, 126.0]");
    let thin =
        Analysis::new(Model::from_str(&text, Path::new("thin_plate_on_base.toml"), 16).unwrap())
            .unwrap();
    assert_eq!(
        thin.model.parts[1].mesh.nodes.len(),
        (28 * 16 + 1) * (3 * 16 + 1)
    );
    for (name, a) in [("bearing", &bearing), ("thin plate", &thin)] {
        let updated = run_with(a, UpdatePolicy::Always);
        let plain = run_with(a, UpdatePolicy::Never);
        assert!(
            updated[0]
                .history
                .iter()
                .any(|it| matches!(it.method, Some(Method::LowRank { .. }))),
            "{name}: no low-rank update was made"
        );
        for (a, b) in updated.iter().zip(&plain) {
            assert_eq!(a.states, b.states, "{name}, increment {}", a.index);
            let err = relative_difference(&a.u, &b.u);
            assert!(
                err < 1e-10,
                "{name}, increment {}: Δu {err:e} of the largest",
                a.index
            );
        }
    }
}
