//! Finite elements of the parts: the linear elastic material law, the element
//! routines (stiffness, internal force, stress) of the linear triangle [`t3`] and
//! the bilinear quadrilateral [`q4`] as small pure functions, and the
//! [`element`] provider that dispatches between them for mixed meshes; and the
//! 3D solid elements' routines on corner coordinates — the linear tetrahedron
//! [`tet4`], the trilinear hexahedron [`hex8`], what they share ([`solid`]: the
//! Voigt order, B, the report of a non-positive Jacobian) and their faces' loads
//! ([`face3`]); and the [`family`] of each dimension ([`ElementFamily`]), through
//! which assembly and recovery reach a part's elements without knowing their kinds.

pub mod axisymmetric;
pub mod element;
pub mod face3;
pub mod family;
pub mod hex8;
pub(crate) mod loads;
pub mod material;
pub mod q4;
pub mod recovery;
pub mod solid;
pub mod t3;
pub mod tet4;

pub use family::ElementFamily;
pub use material::{Material, PlaneKind};

/// `Σ_{k < n} term(k)`, added in the order k = 0, 1, … from −0.0 as
/// `Iterator::sum` adds (so equal to `(0..n).map(term).sum()` to the bit), as a
/// loop that is always inlined. The element routines' small dot products are
/// written with it: as `(0..n).map(…).sum()` each compiled, depending on how the
/// crate falls into code-generation units, to an out-of-line `Map::fold` call
/// per matrix entry (27 in the T3 stiffness), which made the parts' stiffness
/// and internal forces several times slower.
#[inline(always)]
pub(crate) fn sum_of(n: usize, term: impl Fn(usize) -> f64) -> f64 {
    let mut s = -0.0;
    for k in 0..n {
        s += term(k);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::sum_of;

    /// `sum_of` is `Iterator::sum` to the bit: the same value for terms of mixed
    /// magnitude (where the order of addition shows), −0.0 for no terms and for
    /// only −0.0 terms, +0.0 when a +0.0 is among zeros.
    #[test]
    fn sum_of_is_iterator_sum_to_the_bit() {
        let cases: [&[f64]; 5] = [
            &[1e16, 1.0, -1e16, 3.5, 1e-3, -2.25],
            &[],
            &[-0.0, -0.0],
            &[-0.0, 0.0, -0.0],
            &[0.1, 0.2, 0.3, f64::MIN_POSITIVE, -0.6],
        ];
        for v in cases {
            let want: f64 = v.iter().sum();
            let got = sum_of(v.len(), |k| v[k]);
            assert_eq!(got.to_bits(), want.to_bits(), "{v:?}");
        }
    }
}
