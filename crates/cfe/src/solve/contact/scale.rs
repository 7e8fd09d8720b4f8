//! The scales the contact scheme measures a solution against: the load scale
//! (the law's force tolerance and the fixed point's are fractions of it), the
//! balance scale (the out-of-balance force is), and the drift guard's reach
//! (how far a state of rest may move a coupling node); with the two norms of
//! nodal vectors they read. Pure functions of the model's sizes ([`Scales`]).

use crate::fem::ElementFamily;

/// Out-of-balance force (relative to the balance scale) above which a result is
/// flagged as imprecise.
pub const RESIDUAL_WARN: f64 = 1e-8;

/// The balance scale's floor, as a fraction of (smallest E·t) × (largest nodal
/// |u|): the size of the terms K_ij u_j whose sums the out-of-balance force is
/// (E·t is a 2D element's stiffness scale, a force per length), so a part moved
/// without load — its internal force zero but for round-off of those terms — is
/// imprecise only when its out-of-balance force exceeds
/// [`RESIDUAL_WARN`] × 1e-4 = 1e-12 of them (about 5000 units of round-off; the
/// rigid approach of a punch gives 3e-14). Loaded models have load scales far
/// above it (the plate on a base: 1500 N against 0.27 N).
pub const BALANCE_FLOOR: f64 = 1e-4;

/// The smallest load scale of a model without the proportional shortcuts, as a
/// fraction of (largest E·t) × (largest displacement, at most the largest part's
/// size). The cap keeps the floor a floor: a pattern whose slipping pairs cannot
/// hold a part lets it drift, under their springs, by more than any part's size,
/// and a scale grown with that drift would make the drift itself pass every
/// check relative to it (the fixed point's tolerance, the law's).
pub const FORCE_FLOOR: f64 = 1e-6;

/// The model's sizes the scales read: fixed for a run, but for the total load,
/// which follows the load steps.
#[derive(Debug, Clone, Copy)]
pub(super) struct Scales {
    /// Σ‖f‖ over the loaded nodes at full load.
    pub(super) total_load: f64,
    /// The largest part's size (the diagonal of its bounding box): the largest
    /// displacement the load scale's floor reads (see [`FORCE_FLOOR`]).
    pub(super) extent: f64,
    /// The largest prescribed displacement (any support, any step, at full
    /// value) and the largest initial gap: with `extent`, how far a state of
    /// rest may move a coupling node (see [`Scales::drifted`]).
    pub(super) largest_prescribed: f64,
    /// The largest E·t of the parts (the load scale's floor).
    pub(super) stiffest: f64,
    /// The smallest E·t of the parts (the balance scale's floor; infinite
    /// without parts, then there is no floor).
    pub(super) softest: f64,
}

impl Scales {
    /// The load scale of the forces at load factor `lambda`: λ × the total load,
    /// or the largest support reaction `reaction` where larger (so a problem
    /// driven by prescribed displacements has a scale too).
    pub(super) fn of_forces(&self, lambda: f64, reaction: f64) -> f64 {
        (lambda * self.total_load).max(reaction)
    }

    /// The load scale `forces` ([`Scales::of_forces`]) without the proportional
    /// shortcuts: at least [`FORCE_FLOOR`] × the largest E·t × the largest
    /// nodal displacement `umax`, capped at the largest part's size (a part
    /// that moves without load has no force to measure round-off against).
    pub(super) fn with_floor(&self, forces: f64, umax: f64) -> f64 {
        forces.max(FORCE_FLOOR * self.stiffest * umax.min(self.extent))
    }

    /// The scale the out-of-balance force of a solution is measured against: the
    /// largest of the load scale `load_scale`, the largest pair force
    /// `pair_force` (an interference fit with no load carries its pairs' forces
    /// and nothing else) and [`BALANCE_FLOOR`] × the **smallest** E·t × the
    /// largest nodal displacement `umax` (a part moved by a prescribed
    /// displacement, or into contact, with no force anywhere). The softest part's
    /// E·t keeps the floor below the loads of a loaded model even where another
    /// part is far stiffer (a cantilever whose node part is 1e4 times stiffer than
    /// its host is judged against its load, as before the floor existed).
    pub(super) fn balance(&self, load_scale: f64, pair_force: f64, umax: f64) -> f64 {
        let floor = if self.softest.is_finite() {
            BALANCE_FLOOR * self.softest * umax
        } else {
            0.0
        };
        load_scale.max(pair_force).max(floor)
    }

    /// Whether a fixed point whose coupling nodes moved by at most `moved` has
    /// one moved further than a state of rest can move it: the largest part's
    /// size beyond the largest prescribed displacement (or initial gap, should
    /// one be larger). Within a geometrically linear model only a rigid drift
    /// goes that far — a part held along its faces by slipping pairs alone,
    /// whose slip forces balance at any position along them, carried off by the
    /// fixed point's steps under their springs (the seed's plate with a block
    /// bonded on it, pushed at Q = 0.83 μP, drifted 290 m in a pattern with
    /// every closed pair slipping, and the run stopped with a loss of
    /// precision). Such a fixed point is not taken as converged: its pattern is
    /// neither accepted nor settled on, and its slipping pairs stick in the next
    /// (where one stick pair holds the part, 0.02 mm from where it started).
    pub(super) fn drifted(&self, moved: f64) -> bool {
        moved > self.extent + self.largest_prescribed
    }
}

/// Σ ‖f‖ over the nodes of the force vector `f` (`D::N` DOFs a node).
pub(super) fn total_force<D: ElementFamily>(f: &[f64]) -> f64 {
    f.chunks_exact(D::N).map(D::length).sum()
}

/// The largest nodal displacement |u_n| of `u` (`D::N` DOFs a node) over the
/// nodes not in `skip` (sorted).
pub(super) fn largest_off<D: ElementFamily>(u: &[f64], skip: &[usize]) -> f64 {
    u.chunks_exact(D::N)
        .enumerate()
        .filter(|(n, _)| skip.binary_search(n).is_err())
        .map(|(_, v)| D::length(v))
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::D2;

    fn scales() -> Scales {
        Scales {
            total_load: 10.0,
            extent: 2.0,
            largest_prescribed: 0.5,
            stiffest: 4.0e9,
            softest: 1.0e6,
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs()
    }

    /// The load scale is λ × the total load or the largest reaction, whichever
    /// is larger, and its floor 1e-6 × the largest E·t × the largest
    /// displacement, capped at the largest part's size (values by hand).
    #[test]
    fn load_scale_is_the_load_or_reaction_above_its_floor() {
        let s = scales();
        assert_eq!(s.of_forces(0.5, 3.0), 5.0);
        assert_eq!(s.of_forces(0.5, 7.0), 7.0);
        // Floor 1e-6 × 4e9 × 1e-3 = 4 < 5: the forces.
        assert_eq!(s.with_floor(5.0, 1e-3), 5.0);
        // Floor 1e-6 × 4e9 × 0.1 = 400.
        assert!(close(s.with_floor(5.0, 0.1), 400.0));
        // A drift of 30 reads the part's size 2: 8000, not 120000.
        assert!(close(s.with_floor(5.0, 30.0), 8000.0));
    }

    /// The balance scale is the largest of the load scale, the pair force and
    /// 1e-4 × the softest E·t × the largest displacement; without parts there
    /// is no floor (values by hand).
    #[test]
    fn balance_scale_takes_the_largest_of_load_pairs_and_floor() {
        let s = scales();
        // Floor 1e-4 × 1e6 × 1e-4 = 0.01: the pair force.
        assert_eq!(s.balance(5.0, 8.0, 1e-4), 8.0);
        // Floor 1e-4 × 1e6 × 1 = 100.
        assert!(close(s.balance(5.0, 8.0, 1.0), 100.0));
        let none = Scales {
            softest: f64::INFINITY,
            ..s
        };
        assert_eq!(none.balance(5.0, 3.0, 1e9), 5.0);
    }

    /// The drift guard: a coupling node moved beyond the largest part's size
    /// plus the largest prescribed displacement (2 + 0.5) has drifted.
    #[test]
    fn drift_is_beyond_the_part_size_and_prescribed_motion() {
        let s = scales();
        assert!(!s.drifted(2.4));
        assert!(s.drifted(2.6));
    }

    /// The nodal norms: Σ‖f‖ over nodes of (3, 4) and (6, 8) is 15; the largest
    /// |u| is 10, or 5 with node 1 skipped.
    #[test]
    fn nodal_norms() {
        let v = [3.0, 4.0, 6.0, 8.0];
        assert_eq!(total_force::<D2>(&v), 15.0);
        assert_eq!(largest_off::<D2>(&v, &[]), 10.0);
        assert_eq!(largest_off::<D2>(&v, &[1]), 5.0);
    }
}
