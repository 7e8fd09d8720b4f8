//! The contact scheme's vocabulary of results and loads, below everything else
//! in it: what an increment hands out ([`IncrementResult`], each solve an
//! [`Iteration`], every pair off its law a [`PairViolation`], the phase
//! [`SolveTimings`]) and the load path it follows ([`LoadSteps`], [`LoadPath`]).

use crate::coupling::{PairHistories, PairState, PairStates, ViolationKind};
use crate::dim::D2;
use crate::fem::ElementFamily;
use crate::solve::system::Method;

/// What an iterative linear back end did over a run (summary.json's
/// `linear_solver`, present only when the run used one).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct IterativeSolves {
    /// The back end (`cg`).
    pub back_end: String,
    /// Its preconditioner (`jacobi`).
    pub preconditioner: String,
    /// The relative residual `‖b − K x‖ / ‖b‖` every solve had to reach.
    pub tolerance: f64,
    /// Iterations of each linear solve, in the order solved (0: the initial
    /// guess met the tolerance).
    pub iterations: Vec<usize>,
    /// The largest relative residual of a solve returned (at most `tolerance`).
    pub largest_relative_residual: f64,
}

/// Seconds spent in each phase of the solution.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct SolveTimings {
    /// Node graph, ordering, sparsity pattern and symbolic factorization (once),
    /// and the pattern built again when a freed one is needed
    /// (`ContactSystem::keep_pattern`).
    pub pattern_and_symbolic: f64,
    /// Assembly of K values and right-hand sides.
    pub assembly: f64,
    /// Numeric factorizations.
    pub factorization: f64,
    /// Triangular solves, including low-rank update columns.
    pub solve: f64,
    /// State updates, support checks, internal forces.
    pub contact_update: f64,
}

/// One linear solve of an increment.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Iteration {
    /// How the system was solved (or `None` when the solution of the same states
    /// at another load factor was scaled: no solve). In `summary.json` both a
    /// solve with the same factorization and a scaled solution read `"reuse"`.
    #[serde(serialize_with = "method_or_reuse")]
    pub method: Option<Method>,
    /// Pairs whose state the law changed after this solve.
    pub changed: usize,
    /// Seconds spent on this iteration (solve, internal forces, state update).
    pub seconds: f64,
}

/// Serializes a scaled solution (`None`) as `"reuse"`, like a solve that
/// reused its factorization.
fn method_or_reuse<S: serde::Serializer>(
    m: &Option<Method>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&m.unwrap_or(Method::Reuse), s)
}

/// The converged result of one increment (of a model of dimension `D`: its
/// pairs' histories' tangent).
#[derive(Debug, Clone)]
pub struct IncrementResult<D: ElementFamily = D2> {
    /// 1-based increment number (counted over all steps).
    pub index: usize,
    /// Load factor λ of the increment's step (1 at its last increment).
    pub lambda: f64,
    /// The increment's load step (0-based index; 0 without steps).
    pub step: usize,
    /// The total time: step index + λ (0-based step, so λ without steps; grows
    /// monotonically over the steps).
    pub time: f64,
    /// Linear solves in this increment.
    pub iterations: usize,
    /// What each solve did.
    pub history: Vec<Iteration>,
    /// Displacements of all DOFs.
    pub u: Vec<f64>,
    /// Pair states used in the final solve, per interface.
    pub states: PairStates,
    /// Pairs whose state was fixed against the law to settle a cycle:
    /// (interface, pair), sorted. Empty when the law holds everywhere.
    pub settled: Vec<(usize, usize)>,
    /// Every pair that breaks its law at this increment (settled pairs, and with
    /// `implex` pairs whose lagged state is wrong), sorted by interface and pair.
    pub violations: Vec<PairViolation>,
    /// The load scale of this increment: the larger of Σ‖λ f‖ over the loaded
    /// nodes and the largest support reaction (force); the law's tolerances are
    /// relative to it.
    pub load_scale: f64,
    /// The scale the out-of-balance force is measured against
    /// (`Solver::balance_scale`): the load scale, or, where larger, the largest
    /// pair force (an interference fit) or `BALANCE_FLOOR` × the smallest E·t
    /// × the largest nodal |u| (a rigid approach under a prescribed displacement).
    pub balance_scale: f64,
    /// Internal force of all DOFs (reactions are F_int − F_ext at fixed DOFs).
    pub f_int: Vec<f64>,
    /// External force of all DOFs at this λ.
    pub f_ext: Vec<f64>,
    /// Largest out-of-balance force at a free DOF relative to the balance scale.
    pub residual: f64,
    /// The global balance: ‖Σ reactions + Σ loads‖ relative to the balance scale.
    pub balance: f64,
    /// Each pair's history after this increment (plastic slip, slip force,
    /// multipliers), per interface; all zero for the seed's laws.
    pub pair_history: PairHistories<D>,
    /// Fixed-point solves of this increment beyond the first per pattern: slip
    /// forces (Coulomb) and Uzawa steps (augmented Lagrangian), each one triangular
    /// solve with the factorization of the pattern.
    pub fixed_point_iterations: usize,
    /// Augmented Lagrangian: the largest penetration of a closed pair (and stick
    /// error) at the end of the increment (0 without augmented interfaces).
    pub augmented_error: f64,
    /// With the proportional-load shortcuts, the linear solution these
    /// displacements are a multiple of (`None` otherwise): everything linear in
    /// `u` (strains, stresses) is that multiple of the solution's.
    pub multiple_of: Option<MultipleOf>,
    /// Whether the increment's state was found from the pattern a continuation
    /// in the friction coefficients led to: the search from the previous
    /// increment's pattern found none, only settled, or reached a pattern that
    /// leaves a part free.
    pub friction_continuation: bool,
}

/// `u = factor × u_s`, where `u_s` is the displacement vector of the run's linear
/// solution number `solution` (one per pattern solved with the proportional
/// shortcuts on).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultipleOf {
    /// The solution's number (counted over the run).
    pub solution: usize,
    /// The multiple.
    pub factor: f64,
}

impl<D: ElementFamily> IncrementResult<D> {
    /// The largest violation as a force (0 when the law holds everywhere).
    pub fn max_violation_force(&self) -> f64 {
        self.violations.iter().map(|v| v.force).fold(0.0, f64::max)
    }
}

/// A pair that breaks its law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairViolation {
    /// Interface index.
    pub interface: usize,
    /// Pair index within the interface.
    pub pair: usize,
    /// Tension (a bonded pair pulls) or penetration (an open pair interpenetrates).
    pub kind: ViolationKind,
    /// The tensile force, or the penetration depth.
    pub amount: f64,
    /// The amount as a force (`c_n` × depth for a penetration).
    pub force: f64,
}

/// The loads of a run in load steps (the problem file's `[[step]]`), in groups
/// of the same amplitude: every group's external forces and prescribed values
/// at full value, and every increment's factors. The load of increment k is
/// Σ_g λ_g(k) f_g, its prescribed values Σ_g λ_g(k) p_g. Without factors or
/// `scale` in the steps a group is a step's loads.
#[derive(Debug, Clone)]
pub struct LoadSteps {
    /// Per group: the external force of every DOF at full value.
    pub forces: Vec<Vec<f64>>,
    /// Per group: the prescribed value of every DOF at full value (0 at the
    /// DOFs another group prescribes, and at free DOFs).
    pub prescribed: Vec<Vec<f64>>,
    /// Per increment: its step and every group's load factor λ_g.
    pub increments: Vec<(usize, Vec<f64>)>,
    /// Per increment: its step's own load factor (k / n over the step's n
    /// increments), which labels it.
    pub progress: Vec<f64>,
}

impl LoadSteps {
    /// The steps that apply some force or prescribed value.
    pub fn loaded(&self) -> Vec<usize> {
        let nonzero = |v: &Vec<f64>| v.iter().any(|&x| x != 0.0);
        (0..self.forces.len())
            .filter(|&s| nonzero(&self.forces[s]) || nonzero(&self.prescribed[s]))
            .collect()
    }

    /// Whether group `g` is ever reversed (a negative factor).
    pub fn reversed(&self, g: usize) -> bool {
        self.increments.iter().any(|(_, f)| f.get(g).is_some_and(|&x| x < 0.0))
    }

    /// The load and prescribed values of increment `k` (0-based) into `f_ext`
    /// and `prescribed` (both overwritten): Σ_s λ_s(k) f_s and Σ_s λ_s(k) p_s,
    /// summed in step order, a step at factor 0 adding nothing.
    pub fn combine(&self, k: usize, f_ext: &mut [f64], prescribed: &mut [f64]) {
        let factors = &self.increments[k].1;
        f_ext.iter_mut().for_each(|f| *f = 0.0);
        prescribed.iter_mut().for_each(|p| *p = 0.0);
        for (s, &l) in factors.iter().enumerate() {
            if l == 0.0 {
                continue;
            }
            for (f, g) in f_ext.iter_mut().zip(&self.forces[s]) {
                *f += l * g;
            }
            for (p, q) in prescribed.iter_mut().zip(&self.prescribed[s]) {
                *p += l * q;
            }
        }
    }
}

/// A run's load path when it is not the default ramp `k / increments`: the
/// load factors, the prescribed values and, with load steps, the steps and
/// every increment's label.
#[derive(Debug, Default)]
pub(super) struct LoadPath {
    /// The load path, when not the default ramp.
    pub(super) factors: Option<Vec<f64>>,
    /// Prescribed values of all DOFs at load factor 1, when not those of the DOF
    /// map (load steps).
    pub(super) prescribed: Option<Vec<f64>>,
    /// Loads in several steps: the per-step vectors, combined into `f_ext` and
    /// `prescribed` at every increment (then the load factor is 1).
    pub(super) steps: Option<LoadSteps>,
    /// Per increment, its step and that step's load factor (load steps).
    pub(super) labels: Option<Vec<(usize, f64)>>,
}

impl LoadPath {
    /// With load steps, increment `inc`'s (1-based) step and that step's load
    /// factor.
    pub(super) fn label(&self, inc: usize) -> Option<(usize, f64)> {
        self.labels.as_ref().and_then(|s| s.get(inc - 1)).copied()
    }

    /// Where increment `inc` (1-based, solved at factor `lambda`) is on the load
    /// path, for messages: its load factor, and with load steps its step.
    pub(super) fn describe(&self, inc: usize, lambda: f64) -> String {
        match self.label(inc) {
            Some((step, l)) => format!("step {}, load factor {l:.4}", step + 1),
            None => format!("load factor {lambda:.4}"),
        }
    }
}

/// How many pairs have another state in `a` than in `b`.
pub(super) fn count_changes(a: &[Vec<PairState>], b: &[Vec<PairState>]) -> usize {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.iter().zip(y).filter(|(p, q)| p != q).count())
        .sum()
}

/// What the Newton steps of a run's patterns did: how many patterns' slip
/// forces they solved, and how many fell back to the fixed point alone (a
/// singular system or directions that did not settle).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NewtonCounts {
    /// Patterns whose slip forces the Newton step solved.
    pub solved: usize,
    /// Patterns it left to the fixed point.
    pub fallbacks: usize,
    /// Patterns whose columns came from the interface's condensed operator
    /// (the cached correction columns), not from solves.
    pub cached: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two steps, the second at half its load while the first holds: increment
    /// loads and prescribed values are Σ_s λ_s f_s and Σ_s λ_s p_s (worked by
    /// hand), a step at factor 0 adds nothing, and a step with neither force
    /// nor prescribed value is not loaded.
    #[test]
    fn load_steps_combine_per_increment() {
        let steps = LoadSteps {
            forces: vec![vec![2.0, -4.0, 0.0, 0.0], vec![0.0, 8.0, 6.0, 0.0], vec![0.0; 4]],
            prescribed: vec![vec![0.0, 0.0, 0.0, 0.5], vec![0.0; 4], vec![0.0; 4]],
            increments: vec![(0, vec![0.5, 0.0, 0.0]), (1, vec![1.0, 0.5, 0.0])],
            progress: vec![0.5, 0.5],
        };
        assert_eq!(steps.loaded(), vec![0, 1]);
        assert!(!steps.reversed(1));
        let (mut f, mut p) = (vec![9.0; 4], vec![9.0; 4]);
        steps.combine(0, &mut f, &mut p);
        assert_eq!(f, vec![1.0, -2.0, 0.0, 0.0]);
        assert_eq!(p, vec![0.0, 0.0, 0.0, 0.25]);
        steps.combine(1, &mut f, &mut p);
        assert_eq!(f, vec![2.0, 0.0, 3.0, 0.0]);
        assert_eq!(p, vec![0.0, 0.0, 0.0, 0.5]);
    }

    /// A load path labels increment k with its step (1-based in messages) and
    /// that step's factor; without steps a message names the load factor only.
    #[test]
    fn load_path_names_the_step_of_an_increment() {
        let mut path = LoadPath::default();
        assert_eq!(path.label(1), None);
        assert_eq!(path.describe(1, 0.5), "load factor 0.5000");
        path.labels = Some(vec![(0, 1.0), (1, 0.25)]);
        assert_eq!(path.label(2), Some((1, 0.25)));
        assert_eq!(path.describe(2, 1.0), "step 2, load factor 0.2500");
    }

    /// Pairs whose states differ are counted once each, across interfaces.
    #[test]
    fn changes_count_differing_pairs() {
        use PairState::{Bonded, Open, Slip};
        let a = vec![vec![Bonded, Open], vec![Slip]];
        let b = vec![vec![Open, Open], vec![Bonded]];
        assert_eq!(count_changes(&a, &b), 2);
        assert_eq!(count_changes(&a, &a), 0);
    }
}
