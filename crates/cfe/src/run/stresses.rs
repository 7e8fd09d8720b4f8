//! The stresses of a run's written increments: recovered once per linear
//! solution and shared, scaled, by the increments that are multiples of it, so
//! a run of proportional increments holds one copy whatever their number.

use crate::fem::recovery::{Hoop, PartStress, scalar_scaled_in_turn};
use std::sync::Arc;

/// Scaling factors a [`Stresses`] applies in turn before it materializes the
/// scaled values (so a long run of multiples costs a bounded number of
/// multiplications per value).
const MAX_FACTORS: usize = 8;

/// The stresses of a written increment: `base` (recovered from a solution)
/// scaled by each of `factors` in turn. An increment that is a multiple of the
/// same linear solution shares `base` with the increments before it (the
/// writers scale while they read) instead of holding a scaled copy; the values
/// are bit for bit those of successive [`PartStress::scaled`] calls. `S` is the
/// dimension's stress (`[f64; 3]` in 2D, `[f64; 6]` in 3D).
#[derive(Clone)]
pub struct Stresses<S = [f64; 3]> {
    /// The stresses recovered from a solution, shared by its multiples.
    pub(super) base: Arc<Vec<PartStress<S>>>,
    /// The factors `base` is scaled by, in turn.
    pub(super) factors: Vec<f64>,
}

/// A stress `v` scaled by each of `factors` in turn, component by component:
/// bit for bit [`crate::fem::recovery::scaled_in_turn`] in any dimension.
fn stress_scaled_in_turn<S: Copy + AsMut<[f64]>>(mut v: S, factors: &[f64]) -> S {
    for x in v.as_mut() {
        *x = scalar_scaled_in_turn(*x, factors);
    }
    v
}

impl<S: Copy + AsMut<[f64]>> Stresses<S> {
    /// The stresses recovered from one solution, unscaled.
    pub(super) fn recovered(base: Vec<PartStress<S>>) -> Self {
        Stresses {
            base: Arc::new(base),
            factors: Vec::new(),
        }
    }

    /// The stress `v` of `base` as this increment's.
    pub(super) fn value(&self, v: S) -> S {
        stress_scaled_in_turn(v, &self.factors)
    }

    /// A hoop stress of `base` at these stresses' scale.
    pub(super) fn hoop_value(&self, v: f64) -> f64 {
        scalar_scaled_in_turn(v, &self.factors)
    }

    /// These stresses times `factor`: shares `base`, or, once [`MAX_FACTORS`]
    /// factors are pending, a new base holding the scaled values.
    pub(super) fn times(&self, factor: f64) -> Self {
        if self.factors.len() < MAX_FACTORS {
            let mut factors = self.factors.clone();
            factors.push(factor);
            return Stresses {
                base: Arc::clone(&self.base),
                factors,
            };
        }
        let scale = |v: &[S]| -> Vec<S> { v.iter().map(|&s| self.value(s)).collect() };
        let base = self
            .base
            .iter()
            .map(|p| PartStress {
                element: scale(&p.element),
                nodal: scale(&p.nodal),
                hoop: p.hoop.as_ref().map(|h| Hoop {
                    element: h.element.iter().map(|&v| self.hoop_value(v)).collect(),
                    nodal: h.nodal.iter().map(|&v| self.hoop_value(v)).collect(),
                }),
            })
            .collect();
        Stresses {
            base: Arc::new(base),
            factors: Vec::new(),
        }
        .times(factor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Awkward stresses (round-off in every scaling) of two small parts.
    fn sample() -> Vec<PartStress> {
        let v = |k: f64| [1.0 / 3.0 * k, -7.1e5 / k, 0.1 + k];
        vec![
            PartStress {
                element: (1..4).map(|k| v(k as f64)).collect(),
                nodal: (1..6).map(|k| v(k as f64 * 0.7)).collect(),
                hoop: None,
            },
            PartStress {
                element: vec![v(11.0)],
                nodal: vec![v(0.3), v(1e-9)],
                hoop: None,
            },
        ]
    }

    /// A run of multiples scaled in turn through shared stresses (past the
    /// materialization after `MAX_FACTORS`) gives, bit for bit, the values of
    /// scaling a copy at every increment, as the run did before sharing.
    #[test]
    fn shared_stresses_scale_like_copies() {
        let factors: Vec<f64> = (0..3 * MAX_FACTORS + 2)
            .map(|i| 1.0 + 0.1 * (i as f64 + 1.0) / 3.0)
            .collect();
        let mut copies = sample();
        let first = Arc::new(sample());
        let mut shared = Stresses {
            base: Arc::clone(&first),
            factors: Vec::new(),
        };
        for (i, &f) in factors.iter().enumerate() {
            copies = copies.iter().map(|p| p.scaled(f)).collect();
            shared = shared.times(f);
            // Shared until MAX_FACTORS are pending, then materialized.
            assert_eq!(Arc::ptr_eq(&shared.base, &first), i < MAX_FACTORS, "{i}");
            assert!(shared.factors.len() <= MAX_FACTORS);
            for (c, s) in copies.iter().zip(shared.base.iter()) {
                for (a, b) in [(&c.element, &s.element), (&c.nodal, &s.nodal)] {
                    let b: Vec<[f64; 3]> = b.iter().map(|&v| shared.value(v)).collect();
                    let bits = |v: &[[f64; 3]]| -> Vec<[u64; 3]> {
                        v.iter().map(|s| s.map(f64::to_bits)).collect()
                    };
                    assert_eq!(bits(a), bits(&b));
                }
            }
        }
    }
}
