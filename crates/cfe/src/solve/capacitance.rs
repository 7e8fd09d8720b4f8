//! The capacitance matrix of a low-rank (Woodbury) correction, factorized so that
//! a change of a few of its entries costs little.
//!
//! A correction with the entries S (each a cached correction column `v_a` and its
//! weight `w_a`, the change of a pair's penalty) solves
//!
//! ```text
//!     M_S t = s,    M_S = Δ_S⁻¹ + V_Sᵀ V_S,   (M_S)_ab = G_ab + δ_ab / w_a
//! ```
//!
//! with `G = VᵀV` the Gram matrix of the cached columns. An active-set iteration
//! changes a few pairs at a time, so consecutive sets differ in a few entries
//! while S itself grows to hundreds or thousands (2 per pair flipped since the
//! factorization): an LU of M_S at every iteration costs (2/3) r³ flops, 4.6
//! Gflop at r = 1900. Instead an *anchor* set A keeps its LU and a set S near it is
//! solved through a bordered system. With K = A ∩ S, R = A \ S (entries removed)
//! and N = S \ A (entries added), the unknowns `x_A` (over A), `μ` (over R) and
//! `x_N` satisfy
//!
//! ```text
//!     ⎡ M_A   E_R   M_AN ⎤ ⎡ x_A ⎤   ⎡ s at K, 0 at R ⎤
//!     ⎢ E_Rᵀ  0     0    ⎥ ⎢ μ   ⎥ = ⎢ 0              ⎥
//!     ⎣ M_NA  0     M_NN ⎦ ⎣ x_N ⎦   ⎣ s_N            ⎦
//! ```
//!
//! (E_R picks the entries of R): the middle rows force `x_R = 0`, so the rows of K
//! and N are exactly `M_S t = s`, and μ absorbs the rows of R. With the border
//! `Z = [E_R  M_AN]` (m × k, k = |R| + |N|) and `D = diag(0, M_NN)`, the Schur
//! complement `C = D − Zᵀ M_A⁻¹ Z` (k × k) gives
//!
//! ```text
//!     y = M_A⁻¹ b_A,   x_2 = C⁻¹ (b_2 − Zᵀ y),   x_A = y − (M_A⁻¹ Z) x_2,
//! ```
//!
//! for 2 m² k + (2/3) k³ flops to set up (the columns `M_A⁻¹ Z` and C's LU) and
//! 2 m² + 4 m k + 2 k² per solve. When the border grows past [`MAX_BORDER`] of the
//! anchor, S becomes the new anchor (one LU of M_S).

use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{Accum, Mat, Par};
use std::collections::HashMap;

/// Largest border, as a fraction of the anchor's size, solved through the
/// bordered system; a larger change factorizes the new set (setting up the
/// border costs 2 m² k flops against the LU's (2/3) m³: a quarter of it here).
pub const MAX_BORDER: f64 = 1.0 / 12.0;

/// Sets at most this large are factorized anew at every change.
const SMALL: usize = 32;

/// One entry of a correction: a cached column and its weight (compared by bits,
/// so a column whose weight changed is another entry).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entry {
    /// Index of the cached correction column.
    pub column: usize,
    /// The change of the penalty it carries (non-zero).
    pub weight: f64,
}

impl Entry {
    fn key(self) -> (usize, u64) {
        (self.column, self.weight.to_bits())
    }
}

/// The factorized capacitance matrix of the entries it was built for.
pub struct Capacitance {
    /// The entries of S, in the order of the right-hand sides and solutions.
    entries: Vec<Entry>,
    /// The anchor A and the LU of M_A.
    anchor: Vec<Entry>,
    anchor_lu: PartialPivLu<f64>,
    /// Where each entry of S lies: `Some(p)` at position p of the anchor (K), or
    /// `None` (N, in the order of `added`).
    place: Vec<Option<usize>>,
    /// The bordered part, if S is not the anchor.
    border: Option<Border>,
    /// Dense flops spent building this capacitance (anchor LU or border).
    flops: f64,
}

/// The border of S around the anchor.
struct Border {
    /// Anchor positions of the removed entries R.
    removed: Vec<usize>,
    /// Positions in S of the added entries N.
    added: Vec<usize>,
    /// `M_AN` (m × |N|): the Gram entries between the anchor and N.
    m_an: Mat<f64>,
    /// `M_A⁻¹ Z` (m × k).
    w: Mat<f64>,
    /// LU of the Schur complement C (k × k).
    schur: PartialPivLu<f64>,
}

impl Capacitance {
    /// Factorizes `M_S` for the entries `entries` (`gram(a, b)` = `v_aᵀ v_b` of the
    /// cached columns a and b).
    pub fn new(entries: Vec<Entry>, gram: impl Fn(usize, usize) -> f64) -> Self {
        let r = entries.len();
        let m = Mat::<f64>::from_fn(r, r, |a, b| {
            let g = gram(entries[a].column, entries[b].column);
            if a == b { g + 1.0 / entries[a].weight } else { g }
        });
        let anchor_lu = m.partial_piv_lu();
        Capacitance {
            place: (0..r).map(Some).collect(),
            anchor: entries.clone(),
            entries,
            anchor_lu,
            border: None,
            flops: 2.0 / 3.0 * (r as f64).powi(3),
        }
    }

    /// The capacitance of `entries`, from this one: the same when the entries are
    /// the same, bordered around this one's anchor when few entries differ from
    /// it, factorized anew otherwise.
    pub fn update(self, entries: Vec<Entry>, gram: impl Fn(usize, usize) -> f64) -> Self {
        if entries == self.entries {
            return Capacitance { flops: 0.0, ..self };
        }
        let (place, removed, added) = placement(&self.anchor, &entries);
        let (m, k) = (self.anchor.len(), removed.len() + added.len());
        if m <= SMALL || k as f64 > MAX_BORDER * m as f64 {
            return Capacitance::new(entries, gram);
        }
        if k == 0 {
            // The anchor's entries in another order.
            return Capacitance {
                entries,
                place,
                border: None,
                flops: 0.0,
                ..self
            };
        }
        let border = Border::new(&self.anchor, &self.anchor_lu, &entries, removed, added, gram);
        let (mf, kf) = (m as f64, k as f64);
        Capacitance {
            entries,
            anchor: self.anchor,
            anchor_lu: self.anchor_lu,
            place,
            border: Some(border),
            flops: 2.0 * mf * mf * kf + 2.0 * mf * kf * kf + 2.0 / 3.0 * kf * kf * kf,
        }
    }

    /// The entries this solves for.
    pub fn entries(&self) -> &[Entry] {
        &self.entries
    }

    /// Dense flops spent building it (zero when it was reused as it was).
    pub fn flops(&self) -> f64 {
        self.flops
    }

    /// Size of the border around the anchor (0 when the set is the anchor).
    #[cfg(test)]
    pub fn border_size(&self) -> usize {
        self.border
            .as_ref()
            .map_or(0, |b| b.removed.len() + b.added.len())
    }

    /// Solves `M_S t = s` in place (`s` and `t` in the order of the entries).
    pub fn solve_in_place(&self, s: &mut [f64]) {
        assert_eq!(s.len(), self.entries.len(), "one value per entry");
        let m = self.anchor.len();
        let mut y = Mat::<f64>::zeros(m, 1);
        for (i, p) in self.place.iter().enumerate() {
            if let Some(p) = p {
                y[(*p, 0)] = s[i];
            }
        }
        self.anchor_lu.solve_in_place(y.as_mut());
        let Some(b) = &self.border else {
            for (i, p) in self.place.iter().enumerate() {
                s[i] = y[(p.expect("every entry is in the anchor"), 0)];
            }
            return;
        };
        let nr = b.removed.len();
        let k = nr + b.added.len();
        // x_2 = C⁻¹ (b_2 − Zᵀ y).
        let mut x2 = Mat::<f64>::zeros(k, 1);
        for (j, &p) in b.removed.iter().enumerate() {
            x2[(j, 0)] = -y[(p, 0)];
        }
        for (j, &i) in b.added.iter().enumerate() {
            x2[(nr + j, 0)] = s[i];
        }
        faer::linalg::matmul::matmul(
            x2.as_mut().subrows_mut(nr, b.added.len()),
            Accum::Add,
            b.m_an.transpose(),
            y.as_ref(),
            -1.0,
            Par::Seq,
        );
        b.schur.solve_in_place(x2.as_mut());
        // x_A = y − W x_2.
        faer::linalg::matmul::matmul(y.as_mut(), Accum::Add, b.w.as_ref(), x2.as_ref(), -1.0, Par::Seq);
        for (i, p) in self.place.iter().enumerate() {
            if let Some(p) = p {
                s[i] = y[(*p, 0)];
            }
        }
        for (j, &i) in b.added.iter().enumerate() {
            s[i] = x2[(nr + j, 0)];
        }
    }
}

/// Where the entries of a new set S lie against the anchor A: per entry of S
/// its position in A (`None`: added), the positions in A of the entries S
/// lacks (R, ascending) and the positions in S of the added entries (N,
/// ascending). Entries are matched by column and weight bits, so a re-weighted
/// column is one removed and one added.
fn placement(anchor: &[Entry], entries: &[Entry]) -> (Vec<Option<usize>>, Vec<usize>, Vec<usize>) {
    let at: HashMap<(usize, u64), usize> = anchor
        .iter()
        .enumerate()
        .map(|(p, e)| (e.key(), p))
        .collect();
    let place: Vec<Option<usize>> = entries.iter().map(|e| at.get(&e.key()).copied()).collect();
    let mut kept = vec![false; anchor.len()];
    for p in place.iter().flatten() {
        kept[*p] = true;
    }
    let removed: Vec<usize> = (0..kept.len()).filter(|&p| !kept[p]).collect();
    let added: Vec<usize> = (0..entries.len()).filter(|&i| place[i].is_none()).collect();
    (place, removed, added)
}

impl Border {
    /// The border of `entries` around the anchor (its entries `anchor`, the LU
    /// of M_A `anchor_lu`) with the anchor positions `removed` (R) and the
    /// positions in `entries` of the `added` ones (N): `M_AN`, `W = M_A⁻¹ Z`
    /// for `Z = [E_R  M_AN]`, and the LU of `C = D − Zᵀ W`, `D = diag(0_R, M_NN)`.
    fn new(
        anchor: &[Entry],
        anchor_lu: &PartialPivLu<f64>,
        entries: &[Entry],
        removed: Vec<usize>,
        added: Vec<usize>,
        gram: impl Fn(usize, usize) -> f64,
    ) -> Self {
        let (m, nr) = (anchor.len(), removed.len());
        let k = nr + added.len();
        // The border Z = [E_R  M_AN] and W = M_A⁻¹ Z.
        let m_an = Mat::<f64>::from_fn(m, added.len(), |p, j| {
            gram(anchor[p].column, entries[added[j]].column)
        });
        let mut w = Mat::<f64>::zeros(m, k);
        for (j, &p) in removed.iter().enumerate() {
            w[(p, j)] = 1.0;
        }
        w.as_mut().subcols_mut(nr, added.len()).copy_from(&m_an);
        anchor_lu.solve_in_place(w.as_mut());
        // C = D − Zᵀ W, D = diag(0_R, M_NN).
        let mut c = Mat::<f64>::from_fn(k, k, |a, b| {
            if a < nr || b < nr {
                0.0
            } else {
                let (ea, eb) = (entries[added[a - nr]], entries[added[b - nr]]);
                let g = gram(ea.column, eb.column);
                if a == b { g + 1.0 / ea.weight } else { g }
            }
        });
        for (j, &p) in removed.iter().enumerate() {
            for b in 0..k {
                c[(j, b)] -= w[(p, b)];
            }
        }
        faer::linalg::matmul::matmul(
            c.as_mut().subrows_mut(nr, added.len()),
            Accum::Add,
            m_an.transpose(),
            w.as_ref(),
            -1.0,
            Par::Seq,
        );
        let schur = c.partial_piv_lu();
        Border {
            removed,
            added,
            m_an,
            w,
            schur,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Gram matrix of `n` columns of length `len` from a fixed pseudo-random
    /// sequence (deterministic, no dependency).
    fn gram_of(n: usize, len: usize) -> Vec<f64> {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let v: Vec<f64> = (0..n * len).map(|_| next()).collect();
        let mut g = vec![0.0; n * n];
        for a in 0..n {
            for b in 0..n {
                g[a * n + b] = (0..len).map(|i| v[a * len + i] * v[b * len + i]).sum();
            }
        }
        g
    }

    /// `M_S t = s` solved directly (dense LU of the whole matrix).
    fn direct(entries: &[Entry], g: &[f64], n: usize, s: &[f64]) -> Vec<f64> {
        let r = entries.len();
        let m = Mat::<f64>::from_fn(r, r, |a, b| {
            g[entries[a].column * n + entries[b].column]
                + if a == b { 1.0 / entries[a].weight } else { 0.0 }
        });
        let mut x = Mat::<f64>::from_fn(r, 1, |i, _| s[i]);
        m.partial_piv_lu().solve_in_place(x.as_mut());
        (0..r).map(|i| x[(i, 0)]).collect()
    }

    /// The bordered solve equals a direct LU solve of M_S to round-off through a
    /// sequence of sets that add, remove, reorder and re-weight entries around one
    /// anchor (weights of both signs, as bonding and opening pairs give), and a
    /// large change re-anchors.
    #[test]
    fn bordered_solve_equals_direct_solve() {
        let n = 120;
        let g = gram_of(n, 40);
        let gram = |a: usize, b: usize| g[a * n + b];
        let entry = |c: usize| Entry {
            column: c,
            weight: if c.is_multiple_of(3) { -0.7 } else { 2.0 + c as f64 * 0.01 },
        };
        let first: Vec<Entry> = (0..96).map(entry).collect();
        let mut cap = Capacitance::new(first, gram);
        assert_eq!(cap.border_size(), 0);
        let sets: Vec<Vec<Entry>> = vec![
            // Two added.
            (0..98).map(entry).collect(),
            // Three removed, one added, reversed order.
            (3..97).rev().map(entry).collect(),
            // One re-weighted (removed and added with another weight).
            (0..96)
                .map(|c| if c == 10 { Entry { column: 10, weight: 5.0 } } else { entry(c) })
                .collect(),
            // Back to the anchor's set exactly.
            (0..96).map(entry).collect(),
            // A large change: re-anchored.
            (40..120).map(entry).collect(),
        ];
        let expect_border = [2, 4, 2, 0, 0];
        for (set, border) in sets.into_iter().zip(expect_border) {
            cap = cap.update(set.clone(), gram);
            assert_eq!(cap.border_size(), border);
            assert_eq!(cap.entries(), set.as_slice());
            let s: Vec<f64> = (0..set.len()).map(|i| ((i * 7) % 11) as f64 - 5.0).collect();
            let want = direct(&set, &g, n, &s);
            let mut got = s.clone();
            cap.solve_in_place(&mut got);
            let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (a, b) in got.iter().zip(&want) {
                assert!((a - b).abs() <= 1e-11 * scale, "{a} vs {b}");
            }
        }
    }

    /// The same entries give back the same factorization, with no work.
    #[test]
    fn same_entries_cost_nothing() {
        let n = 40;
        let g = gram_of(n, 10);
        let gram = |a: usize, b: usize| g[a * n + b];
        let set: Vec<Entry> = (0..n).map(|c| Entry { column: c, weight: 1.0 }).collect();
        let cap = Capacitance::new(set.clone(), gram);
        assert!(cap.flops() > 0.0);
        let cap = cap.update(set, gram);
        assert_eq!(cap.flops(), 0.0);
    }

    /// A set against its anchor: kept entries point at their anchor position
    /// (in the set's own order), a re-weighted column counts as removed and
    /// added, an entry of the anchor missing from the set as removed.
    #[test]
    fn placement_finds_kept_removed_and_added_entries() {
        let e = |column, weight| Entry { column, weight };
        let anchor = [e(0, 1.0), e(1, 2.0), e(2, 3.0), e(3, 4.0)];
        let set = [e(2, 3.0), e(5, 1.0), e(0, 1.0), e(1, -2.0)];
        let (place, removed, added) = placement(&anchor, &set);
        assert_eq!(place, vec![Some(2), None, Some(0), None]);
        assert_eq!(removed, vec![1, 3]);
        assert_eq!(added, vec![1, 3]);
    }

}
