//! Coulomb friction as a semi-smooth Newton (primal–dual active set) on the
//! pairs, with each pattern solved exactly (docs/method.md §2.1, "A Newton
//! solve of Coulomb friction").
//!
//! For a fixed *pattern* — every pair open, stick, or slipping along a fixed unit
//! direction ξ — the penalty problem is linear: a slipping pair's tangential force
//! is `μ ξ (−f_n)` with `f_n = c_n g_n` affine in the displacements, a rank-one,
//! non-symmetric coupling of the pair's tangential row to its normal row. So a
//! pattern has one solution, found in one shot ([`solve_pattern_linear`] on a
//! condensed interface, `Solver::solve_pattern_exact` on a model: the
//! symmetric factorization of the pattern's K plus a dense correction of rank
//! the number of slipping pairs), with no fixed point. The outer loop over
//! patterns is the Newton step of the complementarity function
//! ([`next_active`]: the radial return of the trial force onto the cone, the
//! normal law's gap and tension), globalised by taking one flip at a time once a
//! pattern repeats ([`newton_condensed`]).
//!
//! Everything per pair is written on [`Tangent`], so the 3D law (a two-component
//! tangent, the radial return and its consistent tangent
//! `μ (−f_n)/|trial| (I − ξ⊗ξ)`, [`return_map_derivative`]) uses it unchanged.
//!
//! In a run, `[analysis] friction_solve = "newton"` (the default in plane models) starts
//! every pattern's fixed point on the slip forces with their Newton step
//! (`Solver::newton_slip_terms`, in `slip_newton`), its columns read from the interface's
//! condensed operator the low-rank machinery caches
//! ([`crate::solve::backend::PairFlexibility`]); the fixed point confirms them
//! and remains the fallback. The search over patterns is still the active
//! set's, not [`newton_condensed`]; docs/method.md gives what remains and why.

use crate::dim::Tangent;
use faer::Mat;
use faer::linalg::solvers::{PartialPivLu, Solve};
use std::collections::HashSet;

/// A pair's place in a Newton pattern: open, stick, or slipping along the unit
/// direction ξ (fixed for the pattern).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Active<T: Tangent> {
    /// No force.
    Open,
    /// Closed, sticking: `f_s = c_s ([[u_s]] − s_p)`.
    Stick,
    /// Closed, slipping along ξ: `f_s = μ (−f_n) ξ`.
    Slip(T),
}

/// The tolerances of the complementarity rule: a force (tension of a closed
/// pair, a trial force beyond the cone) and a length (penetration of an open
/// pair).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// Force tolerance.
    pub force: f64,
    /// Length tolerance.
    pub gap: f64,
}

/// The Newton update of one pair: its place in the next pattern from its
/// solution in this one. `closed` says whether it is closed now, `gap` is its
/// normal gap `g₀ + [[u_n]]`, `f_n` the normal force it carries if closed
/// (`c_n g_n`, negative in compression), `trial` its trial tangential force
/// `c_s ([[u_s]] − s_p)` and `mu` the friction coefficient. A closed pair in
/// tension beyond the tolerance opens, an open pair penetrating beyond it
/// closes; a closed pair sticks when its trial force is inside the cone
/// `μ (−f_n)` (with the tolerance) and slips along the trial force otherwise —
/// the radial return, in any number of tangent components. This is the
/// active-set form of the semi-smooth Newton step on the complementarity
/// function `C(f, u) = max(μ(−f_n), |f_t + c_s u_t|) f_t − μ(−f_n)(f_t + c_s u_t)`
/// (with its normal part `min(−f_n, −c_n g_n)`).
pub fn next_active<T: Tangent>(
    closed: bool,
    gap: f64,
    f_n: f64,
    trial: T,
    mu: f64,
    tol: Tolerance,
) -> Active<T> {
    let stays_open = if closed {
        f_n > tol.force
    } else {
        gap >= -tol.gap
    };
    if stays_open {
        return Active::Open;
    }
    let limit = mu * (-f_n).max(0.0);
    if trial.norm() <= limit + tol.force {
        Active::Stick
    } else {
        Active::Slip(trial.direction())
    }
}

/// The derivative of the radial return `f_t = μ (−f_n) trial/|trial|` of a
/// slipping pair applied to a change `(d_fn, d_trial)`: `μ (−d_fn) ξ +
/// μ (−f_n)/|trial| (I − ξ⊗ξ) d_trial`, ξ the trial's direction. In one
/// tangent component the second term is zero (the direction does not turn):
/// the 2D pattern's coupling is the rank-one `μ ξ c_n` of the normal row alone;
/// in two it is the consistent tangent of the 3D return map (symmetric, so it
/// joins K).
pub fn return_map_derivative<T: Tangent>(trial: T, f_n: f64, mu: f64, d_fn: f64, d_trial: T) -> T {
    let xi = trial.direction();
    let along = xi.scale(-mu * d_fn);
    let norm = trial.norm();
    if norm == 0.0 {
        return along;
    }
    let turn = d_trial.sub(xi.scale(xi.dot(d_trial)));
    along.add(turn.scale(mu * (-f_n).max(0.0) / norm))
}

/// One pair of a condensed interface (2D: one tangent component): penalties,
/// friction coefficient, initial gap and plastic slip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CondensedPair {
    /// Normal penalty.
    pub c_n: f64,
    /// Tangential penalty.
    pub c_s: f64,
    /// Friction coefficient.
    pub mu: f64,
    /// Initial normal gap g₀.
    pub gap0: f64,
    /// Plastic slip s_p.
    pub slip: f64,
}

impl CondensedPair {
    /// The local force `(f_n, f_s)` of the pair at jump `(j_n, j_s)` in `place`.
    pub fn force(&self, place: Active<f64>, j: [f64; 2]) -> [f64; 2] {
        let f_n = self.c_n * (self.gap0 + j[0]);
        match place {
            Active::Open => [0.0, 0.0],
            Active::Stick => [f_n, self.c_s * (j[1] - self.slip)],
            Active::Slip(xi) => [f_n, -self.mu * xi * f_n],
        }
    }
}

/// An interface condensed onto its pairs: the local jumps `j` (2 per pair,
/// normal then tangential) of the model under its loads are `j = free − F f`,
/// `f` the pairs' local forces, `F` the interface's flexibility (2m × 2m, the
/// Schur complement's inverse: `R B K⁻¹ Bᵀ Rᵀ` of the parts alone).
#[derive(Debug, Clone)]
pub struct Condensed {
    /// The flexibility F, row-major.
    pub flex: Vec<f64>,
    /// The jumps with no pair force.
    pub free: Vec<f64>,
    /// The pairs.
    pub pairs: Vec<CondensedPair>,
}

/// The exact solution of one pattern of a condensed interface: the jumps `j`
/// solving `(I + F L) j = free − F l₀`, `f = L j + l₀` the pattern's (affine)
/// pair forces. `None` when the pattern's system is singular (no state of rest
/// in it, e.g. every pair of a part slipping one way under a load along the
/// faces).
pub fn solve_pattern_linear(c: &Condensed, pattern: &[Active<f64>]) -> Option<Vec<f64>> {
    let n = 2 * c.pairs.len();
    // L (block-diagonal 2×2 per pair) and l₀.
    let mut l = vec![[[0.0; 2]; 2]; c.pairs.len()];
    let mut l0 = vec![0.0; n];
    for (p, (pair, place)) in c.pairs.iter().zip(pattern).enumerate() {
        let at_zero = pair.force(*place, [0.0, 0.0]);
        l0[2 * p] = at_zero[0];
        l0[2 * p + 1] = at_zero[1];
        for a in 0..2 {
            let mut e = [0.0; 2];
            e[a] = 1.0;
            let f = pair.force(*place, e);
            l[p][0][a] = f[0] - at_zero[0];
            l[p][1][a] = f[1] - at_zero[1];
        }
    }
    let a = Mat::<f64>::from_fn(n, n, |r, col| {
        let (q, b) = (col / 2, col % 2);
        let fl: f64 = (0..2).map(|k| c.flex[r * n + 2 * q + k] * l[q][k][b]).sum();
        fl + if r == col { 1.0 } else { 0.0 }
    });
    let rhs = Mat::<f64>::from_fn(n, 1, |r, _| {
        c.free[r] - (0..n).map(|k| c.flex[r * n + k] * l0[k]).sum::<f64>()
    });
    let j = PartialPivLu::new(a.as_ref()).solve(rhs.as_ref());
    let j: Vec<f64> = (0..n).map(|r| j[(r, 0)]).collect();
    j.iter().all(|v| v.is_finite()).then_some(j)
}

/// What [`newton_condensed`] did: the patterns it solved, in order, and the
/// jumps of the last.
#[derive(Debug, Clone)]
pub struct NewtonRun {
    /// Every pattern solved, the first the start.
    pub patterns: Vec<Vec<Active<f64>>>,
    /// The jumps of the consistent pattern.
    pub jumps: Vec<f64>,
}

/// The semi-smooth Newton on a condensed interface from `start`: solve the
/// pattern exactly ([`solve_pattern_linear`]), update every pair
/// ([`next_active`]), repeat until no pair changes. Damping: once the update
/// leads back to a pattern already solved (a cycle of the full step), only the
/// pair with the largest complementarity residual changes — the least step that
/// leaves the cycle. `None` when a pattern is singular, or `max` patterns pass,
/// or a repeated pattern has no single change left: no state of rest is within
/// reach.
pub fn newton_condensed(
    c: &Condensed,
    start: Vec<Active<f64>>,
    tol: Tolerance,
    max: usize,
) -> Option<NewtonRun> {
    let mut seen: HashSet<Vec<u8>> = HashSet::new();
    let key = |p: &[Active<f64>]| -> Vec<u8> {
        p.iter()
            .map(|a| match a {
                Active::Open => 0,
                Active::Stick => 1,
                Active::Slip(x) if *x > 0.0 => 2,
                Active::Slip(_) => 3,
            })
            .collect()
    };
    let mut pattern = start;
    let mut patterns = Vec::new();
    for _ in 0..max {
        seen.insert(key(&pattern));
        patterns.push(pattern.clone());
        let j = solve_pattern_linear(c, &pattern)?;
        let mut next = Vec::with_capacity(pattern.len());
        let mut residual = Vec::with_capacity(pattern.len());
        for (p, (pair, place)) in c.pairs.iter().zip(&pattern).enumerate() {
            let jp = [j[2 * p], j[2 * p + 1]];
            let gap = pair.gap0 + jp[0];
            let f_n = pair.c_n * gap;
            let trial = pair.c_s * (jp[1] - pair.slip);
            let closed = *place != Active::Open;
            let n = next_active(closed, gap, f_n, trial, pair.mu, tol);
            let f = pair.force(*place, jp);
            // The residual of the law in this pattern: how far the pair's force
            // is from what the law gives it.
            let r = if n == *place {
                0.0
            } else {
                let law = pair.force(n, jp);
                (law[0] - f[0]).abs().max((law[1] - f[1]).abs()).max(tol.force)
            };
            next.push(n);
            residual.push(r);
        }
        if next == pattern {
            return Some(NewtonRun { patterns, jumps: j });
        }
        if seen.contains(&key(&next)) {
            // Damped: the single worst change, if it leads somewhere new.
            let mut order: Vec<usize> = (0..next.len()).filter(|&p| next[p] != pattern[p]).collect();
            order.sort_by(|&a, &b| residual[b].total_cmp(&residual[a]).then(a.cmp(&b)));
            let step = order.into_iter().find_map(|p| {
                let mut one = pattern.clone();
                one[p] = next[p];
                (!seen.contains(&key(&one))).then_some(one)
            })?;
            pattern = step;
        } else {
            pattern = next;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOL: Tolerance = Tolerance {
        force: 1e-9,
        gap: 1e-12,
    };

    /// The complementarity rule: tension opens a closed pair, penetration closes
    /// an open one, a closed pair sticks inside the cone and slips along its trial
    /// force beyond it — in one tangent component and in two (the radial return:
    /// the direction is the trial's, whatever the axes).
    #[test]
    fn the_newton_update_is_the_return_map() {
        assert_eq!(next_active(true, 1e-3, 5.0, 0.0, 0.3, TOL), Active::Open);
        assert_eq!(next_active(false, 1e-3, 0.0, 0.0, 0.3, TOL), Active::Open);
        assert_eq!(next_active(false, -1e-3, -10.0, 2.0, 0.3, TOL), Active::Stick);
        assert_eq!(next_active(true, -1e-3, -10.0, -3.5, 0.3, TOL), Active::Slip(-1.0));
        let t = [3.0, 4.0];
        match next_active(true, -1e-3, -10.0, t, 0.3, TOL) {
            Active::Slip(xi) => {
                let e = xi.sub([0.6, 0.8]).norm();
                assert!(e < 1e-15, "ξ = {xi:?}");
            }
            other => panic!("{other:?}"),
        }
    }

    /// The consistent tangent of the radial return, against central differences
    /// of `μ (−f_n) t/|t|`: in two components it turns with the trial force
    /// (μ f/|t| (I − ξ⊗ξ)); in one it is the normal coupling μ ξ alone.
    #[test]
    fn the_return_maps_derivative_is_its_difference_quotient() {
        let map = |t: [f64; 2], f_n: f64| t.direction().scale(0.4 * -f_n);
        let (t, f_n) = ([3.0, -1.5], -7.0);
        let (d_fn, d_t) = (0.3, [-0.2, 0.5]);
        let h = 1e-6;
        let fd = map(t.add(d_t.scale(h)), f_n + h * d_fn)
            .sub(map(t.sub(d_t.scale(h)), f_n - h * d_fn))
            .scale(0.5 / h);
        let exact = return_map_derivative(t, f_n, 0.4, d_fn, d_t);
        assert!(fd.sub(exact).norm() < 1e-8, "{fd:?} vs {exact:?}");
        // ξ = −1: μ (−d_fn) ξ = 0.4 × 0.3.
        assert_eq!(return_map_derivative(-2.0, -7.0, 0.4, 0.3, 5.0), 0.4 * 0.3);
    }

    /// A tiny condensed model: two pairs on one elastic body (flexibility with
    /// coupling between them), pressed and pushed sideways.
    fn two_pairs(push: f64, mu: f64) -> Condensed {
        let flex = vec![
            1.0, 0.2, 0.3, 0.0, //
            0.2, 2.0, 0.1, 0.4, //
            0.3, 0.1, 1.0, 0.2, //
            0.0, 0.4, 0.2, 2.0,
        ]
        .into_iter()
        .map(|v| v * 1e-3)
        .collect();
        let pair = CondensedPair {
            c_n: 1e6,
            c_s: 1e6,
            mu,
            gap0: 0.0,
            slip: 0.0,
        };
        Condensed {
            flex,
            free: vec![-0.1, push, -0.1, 0.2 * push],
            pairs: vec![pair; 2],
        }
    }

    /// Per-pattern exactness: the one-shot solve of a pattern with both pairs
    /// slipping equals the fixed point of the slip forces (the explicit
    /// right-hand-side iteration with its stabilising spring, run to round-off),
    /// and the solution obeys the pattern's law: |f_s| = μ (−f_n) along ξ.
    #[test]
    fn a_pattern_solved_in_one_shot_is_the_fixed_points_limit() {
        let c = two_pairs(0.3, 0.2);
        let pattern = vec![Active::Slip(1.0); 2];
        let j = solve_pattern_linear(&c, &pattern).unwrap();
        // The fixed point: slip force t and anchor a as right-hand-side terms,
        // a spring c_slip in the pattern's matrix.
        let c_slip = 1e3;
        let (mut t, mut a) = ([0.0; 2], [0.0; 2]);
        let mut jf = vec![0.0; 4];
        for _ in 0..2000 {
            // Solve (I + F L_s) j = free − F l₀ with L_s: c_n normal, c_slip tangential.
            let cs = Condensed {
                pairs: c
                    .pairs
                    .iter()
                    .map(|p| CondensedPair { c_s: c_slip, ..*p })
                    .collect(),
                free: (0..4)
                    .map(|r| {
                        let l0 = [0.0, t[0] - c_slip * a[0], 0.0, t[1] - c_slip * a[1]];
                        c.free[r] - (0..4).map(|k| c.flex[r * 4 + k] * l0[k]).sum::<f64>()
                    })
                    .collect(),
                ..c.clone()
            };
            jf = solve_pattern_linear(&cs, &[Active::Stick, Active::Stick]).unwrap();
            for p in 0..2 {
                t[p] = -0.2 * c.pairs[p].c_n * jf[2 * p];
                a[p] = jf[2 * p + 1];
            }
        }
        for r in 0..4 {
            assert!((j[r] - jf[r]).abs() <= 1e-12 * 0.1, "{j:?} vs {jf:?}");
        }
        // Consistent: each pair in compression, its trial force beyond the cone
        // along ξ.
        for (p, pair) in c.pairs.iter().enumerate() {
            let f = pair.force(pattern[p], [j[2 * p], j[2 * p + 1]]);
            assert!(f[0] < 0.0);
            assert!(pair.c_s * j[2 * p + 1] > 0.2 * -f[0], "pair {p}: {f:?}");
        }
    }

    /// The Newton loop's state changes on the tiny model: from all stick, a
    /// light push stays stuck (one pattern); a push beyond friction slips a
    /// pair (two patterns or more, the last consistent) and the answer obeys
    /// Coulomb's law on both pairs; with μ = 0 both pairs slip.
    #[test]
    fn the_newton_loop_changes_states_until_the_law_holds() {
        let stick = vec![Active::Stick; 2];
        let light = newton_condensed(&two_pairs(0.001, 0.2), stick.clone(), TOL, 20).unwrap();
        assert_eq!(light.patterns.len(), 1);
        let c = two_pairs(0.1, 0.2);
        let run = newton_condensed(&c, stick.clone(), TOL, 20).unwrap();
        let last = run.patterns.last().unwrap();
        assert!(run.patterns.len() >= 2, "{:?}", run.patterns);
        assert!(last.iter().any(|a| matches!(a, Active::Slip(_))), "{last:?}");
        for (p, pair) in c.pairs.iter().enumerate() {
            let j = [run.jumps[2 * p], run.jumps[2 * p + 1]];
            let f = pair.force(last[p], j);
            let cone = pair.mu * (-f[0]).max(0.0);
            assert!(f[0] <= 0.0);
            assert!(f[1].abs() <= cone + 1e-9, "pair {p}: {f:?}");
            if let Active::Slip(xi) = last[p] {
                assert!((f[1] - xi * cone).abs() <= 1e-9);
                assert!(pair.c_s * (j[1] - pair.slip) * xi > cone);
            }
        }
        // μ = 0: the pairs carry no shear, the body (bounded F) takes the push.
        let free = newton_condensed(&two_pairs(0.1, 0.0), stick, TOL, 20).unwrap();
        assert!(free.patterns.last().unwrap().iter().all(|a| matches!(a, Active::Slip(_))));
    }
}
