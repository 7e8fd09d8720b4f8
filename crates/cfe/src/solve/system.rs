//! The linear system `K(D̂) x = b` for a set of pair states, solved with the least
//! work: the Cholesky factor of the stiffness for some *base* states is kept, and a
//! new state set that differs from the base in a few pairs is solved by a low-rank
//! (Sherman–Morrison–Woodbury) correction of that factor instead of a new
//! factorization. A cost model chooses: refactorization costs one numeric
//! factorization; an update costs two triangular solves per changed pair (cached
//! between iterations) plus one. Each call reports what it did.
//!
//! A CFE's stiffness is `K_e = Σ_k c_k w_k w_kᵀ` with `w_k = (R_k B_e)ᵀ` (k = n, s), so
//! flipping a pair adds or removes a rank-2 term, and
//! `K = K₀ + W Δ Wᵀ`, `K⁻¹ b = y − Z (Δ⁻¹ + Wᵀ Z)⁻¹ Wᵀ y`, with `y = K₀⁻¹ b`, `Z = K₀⁻¹ W`.

use super::linear::CholeskySolver;
use crate::assembly::{DofMap, FIXED, Stiffness};
use crate::coupling::{Interface, PairState, PairStates};
use std::collections::HashMap;
use std::time::Instant;

/// How one solve was done.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// A numeric factorization for these states, then a solve.
    Factorization,
    /// A solve with the factorization of the same states.
    Reuse,
    /// A low-rank correction of the factorization of other states.
    LowRank {
        /// Rank of the correction (2 per changed pair).
        rank: usize,
    },
}

/// When to use a low-rank update instead of a new factorization.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UpdatePolicy {
    /// Whichever the cost model says is cheaper (default).
    Auto,
    /// Always update when the cached columns fit in memory (for tests and studies).
    Always,
    /// Always refactorize.
    Never,
}

/// One column of the correction: the free equations and values of `w_k` (its
/// weight, the change of the penalty c_k between the base state and the current
/// one, is taken at each solve).
struct Column {
    eq: Vec<usize>,
    w: Vec<f64>,
}

/// The stiffness, its factorization for the base states, and the cached
/// low-rank correction columns.
pub struct ContactSystem {
    /// The stiffness with its fixed pattern.
    pub k: Stiffness,
    chol: CholeskySolver,
    base: Option<PairStates>,
    /// Correction columns per changed pair (relative to `base`): (column index in `z`).
    cached: HashMap<(usize, usize), usize>,
    columns: Vec<Column>,
    /// `Z = K₀⁻¹ W`, column-major, n × columns.len().
    z: Vec<f64>,
    /// Seconds of the last numeric factorization.
    t_factor: f64,
    /// Seconds per right-hand side of a multi-column solve.
    t_column: f64,
    /// Largest memory for cached columns (bytes).
    budget: usize,
    /// When to update instead of refactorizing.
    pub policy: UpdatePolicy,
    /// Numeric factorizations so far.
    pub factorizations: usize,
    /// Low-rank updates so far.
    pub updates: usize,
    /// Seconds in numeric factorizations.
    pub factor_seconds: f64,
    /// Seconds of the first numeric factorization.
    pub first_factor_seconds: Option<f64>,
    /// Seconds in solves (including update columns).
    pub solve_seconds: f64,
}

impl ContactSystem {
    /// Wraps the stiffness and its symbolic factorization.
    pub fn new(k: Stiffness, chol: CholeskySolver) -> Self {
        let n = k.n();
        ContactSystem {
            k,
            chol,
            base: None,
            cached: HashMap::new(),
            columns: Vec::new(),
            z: Vec::new(),
            t_factor: f64::INFINITY,
            t_column: 0.0,
            budget: (1usize << 30).max(64 * 8 * n),
            policy: UpdatePolicy::Auto,
            factorizations: 0,
            updates: 0,
            factor_seconds: 0.0,
            first_factor_seconds: None,
            solve_seconds: 0.0,
        }
    }

    /// Nonzeros of the Cholesky factor.
    pub fn factor_nnz(&self) -> usize {
        self.chol.factor_nnz()
    }

    /// Forgets the factorization, so the next solve refactorizes.
    pub fn invalidate(&mut self) {
        self.base = None;
        self.cached.clear();
        self.columns.clear();
        self.z.clear();
    }

    /// Solves `K(states) x = rhs` in place. A non-positive pivot returns the
    /// equation where it occurred.
    pub fn solve(
        &mut self,
        interfaces: &[Interface],
        dofs: &DofMap,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
    ) -> Result<Method, usize> {
        let n = self.k.n();
        let Some(base) = &self.base else {
            return self.refactor_and_solve(interfaces, dofs, states, rhs);
        };
        let flips: Vec<(usize, usize)> = states
            .iter()
            .zip(base)
            .enumerate()
            .flat_map(|(i, (s, b))| {
                s.iter()
                    .zip(b)
                    .enumerate()
                    .filter(|(_, (x, y))| x != y)
                    .map(move |(k, _)| (i, k))
            })
            .collect();
        if flips.is_empty() {
            let t = Instant::now();
            self.chol.solve_in_place(rhs);
            self.solve_seconds += t.elapsed().as_secs_f64();
            return Ok(Method::Reuse);
        }
        let new: Vec<(usize, usize)> = flips
            .iter()
            .copied()
            .filter(|p| !self.cached.contains_key(p))
            .collect();
        let cost_update = (2 * new.len() + 1) as f64 * self.t_column.max(1e-9);
        let memory = (self.columns.len() + 2 * new.len()) * n * 8;
        let cheaper = match self.policy {
            UpdatePolicy::Auto => cost_update < self.t_factor,
            UpdatePolicy::Always => true,
            UpdatePolicy::Never => false,
        };
        if !cheaper || memory > self.budget {
            return self.refactor_and_solve(interfaces, dofs, states, rhs);
        }
        // New correction columns, solved in one blocked solve together with the
        // right-hand side (y = K₀⁻¹ b).
        let t = Instant::now();
        let first = self.columns.len();
        for &(i, k) in &new {
            self.cached.insert((i, k), self.columns.len());
            let columns = pair_columns(&interfaces[i], k, dofs);
            self.columns.extend(columns);
        }
        let added = self.columns.len() - first;
        let start = self.z.len();
        self.z.resize(start + (added + 1) * n, 0.0);
        for (j, col) in self.columns[first..].iter().enumerate() {
            for (&e, &w) in col.eq.iter().zip(&col.w) {
                self.z[start + j * n + e] = w;
            }
        }
        self.z[start + added * n..].copy_from_slice(rhs);
        let ts = Instant::now();
        self.chol.solve_columns(&mut self.z[start..], n, added + 1);
        if added > 0 {
            self.t_column = ts.elapsed().as_secs_f64() / (added + 1) as f64;
        }
        rhs.copy_from_slice(&self.z[start + added * n..]);
        self.z.truncate(start + added * n);
        // Woodbury on the columns of the flipped pairs whose penalty changed (by
        // ±c_k: a pair bonding or opening changes both, a stick pair slipping or a
        // frictionless pair closing only the normal one).
        let mut idx: Vec<usize> = Vec::with_capacity(2 * flips.len());
        let mut weights: Vec<f64> = Vec::with_capacity(2 * flips.len());
        for &(i, k) in &flips {
            let law = interfaces[i].params();
            let (now, was) = (law.penalties(states[i][k]), law.penalties(base[i][k]));
            let c = self.cached[&(i, k)];
            for t in 0..2 {
                if now[t] != was[t] {
                    idx.push(c + t);
                    weights.push(now[t] - was[t]);
                }
            }
        }
        let r = idx.len();
        let mut m = faer::Mat::<f64>::zeros(r, r);
        let mut t_vec = faer::Mat::<f64>::zeros(r, 1);
        for (a, &ca) in idx.iter().enumerate() {
            let col = &self.columns[ca];
            t_vec[(a, 0)] = col.eq.iter().zip(&col.w).map(|(&e, &w)| w * rhs[e]).sum();
            for (bcol, &cb) in idx.iter().enumerate() {
                let zb = &self.z[cb * n..(cb + 1) * n];
                m[(a, bcol)] = col.eq.iter().zip(&col.w).map(|(&e, &w)| w * zb[e]).sum();
            }
            m[(a, a)] += 1.0 / weights[a];
        }
        let lu = m.partial_piv_lu();
        use faer::linalg::solvers::Solve;
        lu.solve_in_place(&mut t_vec);
        for (a, &ca) in idx.iter().enumerate() {
            let v = t_vec[(a, 0)];
            let za = &self.z[ca * n..(ca + 1) * n];
            for (x, z) in rhs.iter_mut().zip(za) {
                *x -= v * z;
            }
        }
        self.solve_seconds += t.elapsed().as_secs_f64();
        self.updates += 1;
        Ok(Method::LowRank { rank: r })
    }

    fn refactor_and_solve(
        &mut self,
        interfaces: &[Interface],
        dofs: &DofMap,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
    ) -> Result<Method, usize> {
        self.invalidate();
        self.k.assemble(interfaces, states, dofs);
        let t = Instant::now();
        self.chol.factorize(self.k.matrix())?;
        self.t_factor = t.elapsed().as_secs_f64();
        self.factor_seconds += self.t_factor;
        self.first_factor_seconds.get_or_insert(self.t_factor);
        self.factorizations += 1;
        self.base = Some(states.to_vec());
        let t = Instant::now();
        self.chol.solve_in_place(rhs);
        let dt = t.elapsed().as_secs_f64();
        self.solve_seconds += dt;
        if self.t_column == 0.0 {
            // Until a multi-column solve is timed: a column of a blocked solve costs
            // about a third of a single solve.
            self.t_column = dt / 3.0;
        }
        Ok(Method::Factorization)
    }
}

/// The two correction columns (normal, tangential) of pair `k` of `iface`: the
/// element's rank-2 terms `w_k` restricted to the free equations.
fn pair_columns(iface: &Interface, k: usize, dofs: &DofMap) -> [Column; 2] {
    let c = &iface.elements[k];
    let g = c.dofs(dofs, iface.host, iface.node_part);
    let g = g.as_slice();
    c.stiffness_terms(iface.c_n, iface.c_s).map(|(_, w)| {
        let mut col = Column {
            eq: Vec::with_capacity(g.len()),
            w: Vec::with_capacity(g.len()),
        };
        for (p, &gp) in g.iter().enumerate() {
            let e = dofs.eq[gp];
            if e != FIXED {
                col.eq.push(e);
                col.w.push(w[p]);
            }
        }
        col
    })
}
