//! The dimension of a model: what the coupling layer (and, later, the mesh, the
//! element routines and the assembly) reads of "2D" or "3D" instead of writing it
//! out. A [`Dim`] names the DOFs per node, the rigid-body modes, the Voigt size, the
//! point/vector type, the tangent type of the interface law and the local frame of
//! a coupling pair (the host normal n and the tangent(s)). [`D2`] is the plane
//! instance; [`D3`] has `N = 3`, six rigid modes, Voigt size 6, `[f64; 3]` points,
//! a 2-component tangent (`[f64; 2]`) and a frame of n and two orthonormal
//! tangents in the face plane — and the law, the pair histories and the return map
//! take it unchanged.
//!
//! It sits below mesh, fem and coupling and imports nothing of the crate.

use std::fmt::Debug;

/// A tangential vector of the interface law, in the tangent plane of a pair's
/// local frame: the tangential jump, the plastic slip, the tangential force, the
/// tangential multiplier. One component in 2D (`f64`, along s), two in 3D
/// (`[f64; 2]`, along t₁ and t₂). The law is written with these operations only,
/// so it reads the same in any dimension.
pub trait Tangent:
    Copy + Debug + PartialEq + Default + serde::Serialize + Send + Sync + 'static
{
    /// Number of components (1 in 2D, 2 in 3D).
    const COMPONENTS: usize;

    /// `f` applied to each component.
    fn map_each(self, f: impl Fn(f64) -> f64) -> Self;

    /// `f` applied to each pair of components of `self` and `other`.
    fn zip_each(self, other: Self, f: impl Fn(f64, f64) -> f64) -> Self;

    /// Component `j` (0 ≤ j < [`Tangent::COMPONENTS`]).
    fn component(self, j: usize) -> f64;

    /// Sets component `j` (0 ≤ j < [`Tangent::COMPONENTS`]) to `v`.
    fn set_component(&mut self, j: usize, v: f64);

    /// The dot product `self · other`.
    fn dot(self, other: Self) -> f64;

    /// The Euclidean length |self| (in one component the absolute value, exactly).
    fn norm(self) -> f64;

    /// The unit vector along `self`, `self / |self|` (in one component its sign,
    /// exactly ±1). A zero vector has no direction; it is given the first axis,
    /// signed by its first component's sign bit (`f64::signum`'s rule in one
    /// component), so the answer is always a unit vector.
    fn direction(self) -> Self;

    /// `a · self`.
    fn scale(self, a: f64) -> Self {
        self.map_each(|x| a * x)
    }

    /// `self + other`, component by component.
    fn add(self, other: Self) -> Self {
        self.zip_each(other, |a, b| a + b)
    }

    /// `self − other`, component by component.
    fn sub(self, other: Self) -> Self {
        self.zip_each(other, |a, b| a - b)
    }
}

/// The tangent of a plane model: one component, along s (the normal turned +90°).
impl Tangent for f64 {
    const COMPONENTS: usize = 1;

    fn map_each(self, f: impl Fn(f64) -> f64) -> Self {
        f(self)
    }

    fn zip_each(self, other: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        f(self, other)
    }

    fn component(self, j: usize) -> f64 {
        debug_assert_eq!(j, 0);
        self
    }

    fn set_component(&mut self, j: usize, v: f64) {
        debug_assert_eq!(j, 0);
        *self = v;
    }

    fn dot(self, other: Self) -> f64 {
        self * other
    }

    fn norm(self) -> f64 {
        self.abs()
    }

    fn direction(self) -> Self {
        self.signum()
    }
}

/// The tangent of a 3D model: two components, along t₁ and t₂.
impl Tangent for [f64; 2] {
    const COMPONENTS: usize = 2;

    fn map_each(self, f: impl Fn(f64) -> f64) -> Self {
        [f(self[0]), f(self[1])]
    }

    fn zip_each(self, other: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        [f(self[0], other[0]), f(self[1], other[1])]
    }

    fn component(self, j: usize) -> f64 {
        self[j]
    }

    fn set_component(&mut self, j: usize, v: f64) {
        self[j] = v;
    }

    fn dot(self, other: Self) -> f64 {
        self[0] * other[0] + self[1] * other[1]
    }

    fn norm(self) -> f64 {
        self[0].hypot(self[1])
    }

    fn direction(self) -> Self {
        let n = self.norm();
        if n > 0.0 {
            [self[0] / n, self[1] / n]
        } else {
            [self[0].signum(), 0.0]
        }
    }
}

/// A spatial dimension: what the coupling layer reads of it. Implemented by
/// zero-sized markers ([`D2`], [`D3`]), used as a type parameter
/// (`PairHistory<D>`, the law's generic methods).
pub trait Dim: Copy + Debug + PartialEq + Default + Send + Sync + 'static {
    /// Displacement DOFs per node (2 in 2D, 3 in 3D): node g's component c is DOF
    /// `N g + c`.
    const N: usize;
    /// Rigid-body modes of a free part (3 in 2D: two translations and a rotation;
    /// 6 in 3D).
    const RIGID_MODES: usize;
    /// Components of a symmetric stress or strain in Voigt notation (3 in 2D:
    /// xx, yy, xy; 6 in 3D).
    const VOIGT: usize;
    /// A point or vector (`[f64; N]`).
    type Vector: Copy
        + Debug
        + PartialEq
        + Default
        + AsRef<[f64]>
        + AsMut<[f64]>
        + Send
        + Sync
        + 'static;
    /// The tangential part of a pair's local vectors (1 component in 2D, 2 in 3D).
    type Tangent: Tangent;
    /// A pair's local frame: the unit normal n and the unit tangent(s), orthonormal.
    type Frame: Copy + Debug + PartialEq + Send + Sync + 'static;

    /// The global DOF of component `c` (0 ≤ c < N) of global node `node`: `N node
    /// + c`. The one home of the DOF numbering by node.
    fn dof(node: usize, c: usize) -> usize {
        Self::N * node + c
    }

    /// The Euclidean length of a vector given by its `N` components `v` (in 2D
    /// `hypot`, to the bit).
    fn length(v: &[f64]) -> f64;

    /// The dot product `a · b` of two vectors given by their `N` components
    /// (summed in component order: in 2D `a₀b₀ + a₁b₁`, to the bit).
    fn dot(a: &[f64], b: &[f64]) -> f64 {
        let mut s = a[0] * b[0];
        for c in 1..Self::N {
            s += a[c] * b[c];
        }
        s
    }

    /// The length of the part of `v` across the unit vector `m`, `|v × m|` (in
    /// 2D `|v₀m₁ − v₁m₀|`): how far `v` points off `m`, times `|v|`.
    fn across(v: Self::Vector, m: Self::Vector) -> f64;

    /// The `k`-th rigid-body velocity (0 ≤ k < `RIGID_MODES`) at the point `x`
    /// (relative to the body's centre): the translations along the axes, then
    /// the rotations about them (`e_j × x`; in 2D the one about the normal to
    /// the plane, `(−x₁, x₀)`). Each is a motion without strain.
    fn rigid_mode(k: usize, x: Self::Vector) -> Self::Vector;

    /// The local frame at a host boundary point of outward unit normal `normal`:
    /// n and the tangent(s) completing it to a right-handed orthonormal basis.
    fn frame(normal: Self::Vector) -> Self::Frame;

    /// Axis `k` of `frame` as a global unit vector: the normal n for k = 0, the
    /// tangent k for 1 ≤ k ≤ `Tangent::COMPONENTS`.
    fn axis(frame: &Self::Frame, k: usize) -> Self::Vector;

    /// The local components of the global vector `v` in `frame`: `(v · n, v
    /// along the tangent(s))`.
    fn to_local(frame: &Self::Frame, v: Self::Vector) -> (f64, Self::Tangent);

    /// The global vector of the local components `(v_n, v_t)` in `frame`:
    /// `v_n n + v_t · tangents` (the inverse of [`Dim::to_local`]).
    fn to_global(frame: &Self::Frame, v_n: f64, v_t: Self::Tangent) -> Self::Vector;
}

/// Plane models (plane stress or strain): 2 DOFs per node, 3 rigid modes, Voigt
/// size 3, the tangent s = n turned +90° (one component).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct D2;

impl Dim for D2 {
    const N: usize = 2;
    const RIGID_MODES: usize = 3;
    const VOIGT: usize = 3;
    type Vector = [f64; 2];
    type Tangent = f64;
    /// The rotation `R = [n, s]` by rows: `[[n₁, n₂], [s₁, s₂]]`, s = (−n₂, n₁).
    type Frame = [[f64; 2]; 2];

    fn length(v: &[f64]) -> f64 {
        v[0].hypot(v[1])
    }

    fn across(v: [f64; 2], m: [f64; 2]) -> f64 {
        (v[0] * m[1] - v[1] * m[0]).abs()
    }

    fn rigid_mode(k: usize, x: [f64; 2]) -> [f64; 2] {
        match k {
            0 => [1.0, 0.0],
            1 => [0.0, 1.0],
            _ => [-x[1], x[0]],
        }
    }

    fn frame(n: [f64; 2]) -> [[f64; 2]; 2] {
        [[n[0], n[1]], [-n[1], n[0]]]
    }

    fn axis(r: &[[f64; 2]; 2], k: usize) -> [f64; 2] {
        r[k]
    }

    fn to_local(r: &[[f64; 2]; 2], v: [f64; 2]) -> (f64, f64) {
        (
            r[0][0] * v[0] + r[0][1] * v[1],
            r[1][0] * v[0] + r[1][1] * v[1],
        )
    }

    fn to_global(r: &[[f64; 2]; 2], v_n: f64, v_t: f64) -> [f64; 2] {
        [r[0][0] * v_n + r[1][0] * v_t, r[0][1] * v_n + r[1][1] * v_t]
    }
}

/// Solid models: 3 DOFs per node, 6 rigid modes, Voigt size 6, `[f64; 3]` points
/// and a tangent plane of two components along t₁ and t₂.
///
/// The frame at a normal n is built deterministically: a = the coordinate axis
/// least aligned with n (the first of the smallest |nᵢ|), t₁ = the unit part of a
/// orthogonal to n, t₂ = n × t₁, so (n, t₁, t₂) is right-handed and orthonormal.
/// Any other orthonormal pair in the face plane is as good: the law is written
/// so that no result depends on the choice (the bonded element with c_n = c_s is
/// c·I, the Coulomb return map is radial).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct D3;

impl Dim for D3 {
    const N: usize = 3;
    const RIGID_MODES: usize = 6;
    const VOIGT: usize = 6;
    type Vector = [f64; 3];
    type Tangent = [f64; 2];
    /// The rotation `R = [n, t₁, t₂]` by rows.
    type Frame = [[f64; 3]; 3];

    fn length(v: &[f64]) -> f64 {
        v[0].hypot(v[1]).hypot(v[2])
    }

    fn across(v: [f64; 3], m: [f64; 3]) -> f64 {
        D3::length(&[
            v[1] * m[2] - v[2] * m[1],
            v[2] * m[0] - v[0] * m[2],
            v[0] * m[1] - v[1] * m[0],
        ])
    }

    /// Translations along x, y, z, then rotations about x, y, z: `e_j × x`.
    fn rigid_mode(k: usize, x: [f64; 3]) -> [f64; 3] {
        match k {
            0..3 => {
                let mut e = [0.0; 3];
                e[k] = 1.0;
                e
            }
            3 => [0.0, -x[2], x[1]],
            4 => [x[2], 0.0, -x[0]],
            _ => [-x[1], x[0], 0.0],
        }
    }

    fn frame(n: [f64; 3]) -> [[f64; 3]; 3] {
        let mut k = 0;
        for i in 1..3 {
            if n[i].abs() < n[k].abs() {
                k = i;
            }
        }
        // t₁ = (a − (a·n) n) / |…| with a = e_k: |…|² = 1 − n_k² ≥ 2/3 for a unit n.
        let mut t1 = [-n[k] * n[0], -n[k] * n[1], -n[k] * n[2]];
        t1[k] += 1.0;
        let l = D3::length(&t1);
        let t1 = [t1[0] / l, t1[1] / l, t1[2] / l];
        let t2 = [
            n[1] * t1[2] - n[2] * t1[1],
            n[2] * t1[0] - n[0] * t1[2],
            n[0] * t1[1] - n[1] * t1[0],
        ];
        [n, t1, t2]
    }

    fn axis(r: &[[f64; 3]; 3], k: usize) -> [f64; 3] {
        r[k]
    }

    fn to_local(r: &[[f64; 3]; 3], v: [f64; 3]) -> (f64, [f64; 2]) {
        let dot = |a: [f64; 3]| a[0] * v[0] + a[1] * v[1] + a[2] * v[2];
        (dot(r[0]), [dot(r[1]), dot(r[2])])
    }

    fn to_global(r: &[[f64; 3]; 3], v_n: f64, v_t: [f64; 2]) -> [f64; 3] {
        std::array::from_fn(|i| r[0][i] * v_n + r[1][i] * v_t[0] + r[2][i] * v_t[1])
    }
}

/// A test-only dimension whose tangent has two components (the shape `D3` will
/// have; its frame is not needed by the law's tests and is the identity here), so
/// the law's generic code is exercised with a tangent plane before 3D exists.
#[cfg(test)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct PlaneTangent;

#[cfg(test)]
impl Dim for PlaneTangent {
    const N: usize = 3;
    const RIGID_MODES: usize = 6;
    const VOIGT: usize = 6;
    type Vector = [f64; 3];
    type Tangent = [f64; 2];
    type Frame = ();

    fn length(v: &[f64]) -> f64 {
        v[0].hypot(v[1]).hypot(v[2])
    }

    fn across(v: [f64; 3], m: [f64; 3]) -> f64 {
        D3::across(v, m)
    }

    fn rigid_mode(k: usize, x: [f64; 3]) -> [f64; 3] {
        D3::rigid_mode(k, x)
    }

    fn frame(_: [f64; 3]) {}

    fn axis(_: &(), k: usize) -> [f64; 3] {
        // n along z, the tangents along x and y.
        let mut a = [0.0; 3];
        a[(k + 2) % 3] = 1.0;
        a
    }

    fn to_local(_: &(), v: [f64; 3]) -> (f64, [f64; 2]) {
        (v[2], [v[0], v[1]])
    }

    fn to_global(_: &(), v_n: f64, v_t: [f64; 2]) -> [f64; 3] {
        [v_t[0], v_t[1], v_n]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plane frame is n and n turned +90° (right-handed, orthonormal), and
    /// `to_global` inverts `to_local` (to round-off) for a tilted normal.
    #[test]
    fn plane_frame_is_orthonormal_and_invertible() {
        let a: f64 = 0.4;
        let n = [a.cos(), a.sin()];
        let r = D2::frame(n);
        assert_eq!(r[0], n);
        assert_eq!(r[1], [-n[1], n[0]]);
        assert!((r[0][0] * r[1][0] + r[0][1] * r[1][1]).abs() < 1e-16);
        // Right-handed: n × s = +1.
        assert!((r[0][0] * r[1][1] - r[0][1] * r[1][0] - 1.0).abs() < 1e-15);
        assert_eq!(D2::to_local(&r, n), (1.0, 0.0));
        assert_eq!((D2::axis(&r, 0), D2::axis(&r, 1)), (r[0], r[1]));
        // Each axis is its own unit component in the frame.
        assert_eq!(D2::to_local(&r, D2::axis(&r, 1)).0, 0.0);
        let v = [0.3, -1.7];
        let (v_n, v_t) = D2::to_local(&r, v);
        let back = D2::to_global(&r, v_n, v_t);
        assert!((back[0] - v[0]).abs() < 1e-15 && (back[1] - v[1]).abs() < 1e-15);
    }

    /// Node g's component c is DOF N g + c (in the plane 2 g + c, every DOF once);
    /// a vector's length is its Euclidean norm (`hypot` in the plane, to the
    /// bit; 13 for (3, 4, 12) with three components).
    #[test]
    fn dof_numbering_and_length() {
        let all: Vec<usize> = (0..4)
            .flat_map(|g| (0..D2::N).map(move |c| D2::dof(g, c)))
            .collect();
        assert_eq!(all, (0..8).collect::<Vec<_>>());
        assert_eq!(PlaneTangent::dof(5, 2), 17);
        let v = [1e-3, -7.1e4];
        assert_eq!(D2::length(&v).to_bits(), v[0].hypot(v[1]).to_bits());
        assert_eq!(PlaneTangent::length(&[3.0, 4.0, 12.0]), 13.0);
        let mut t = 2.5f64;
        t.set_component(0, -1.0);
        assert_eq!(t.component(0), -1.0);
    }

    /// In one component the tangent's length is the absolute value and its
    /// direction the sign, both exactly, the zeros' sign bits kept.
    #[test]
    fn one_component_tangent_is_exact() {
        for t in [3.0f64, -3.0, 1e-310, -7.5e300, 0.1] {
            assert_eq!(t.norm().to_bits(), t.abs().to_bits());
            assert_eq!(t.direction().to_bits(), t.signum().to_bits());
        }
        assert_eq!(0.0f64.direction(), 1.0);
        assert_eq!((-0.0f64).direction(), -1.0);
    }

    /// Two components: the direction is a unit vector along the vector; the
    /// length and the dot product are a rotation's invariants.
    #[test]
    fn two_component_tangent() {
        let t = [3.0, -4.0];
        assert_eq!(t.norm(), 5.0);
        assert_eq!(t.direction(), [0.6, -0.8]);
        assert_eq!(t.scale(2.0).sub([1.0, 1.0]).add([0.5, 0.0]), [5.5, -9.0]);
        let (c, s) = (0.3f64.cos(), 0.3f64.sin());
        let rot = |v: [f64; 2]| [c * v[0] - s * v[1], s * v[0] + c * v[1]];
        let u = [0.7, 2.1];
        assert!((rot(t).norm() - 5.0).abs() < 1e-14);
        assert!((rot(t).dot(rot(u)) - t.dot(u)).abs() < 1e-14);
        assert_eq!([0.0, 0.0].direction(), [1.0, 0.0]);
        let mut w = [1.0, 2.0];
        w.set_component(1, -3.0);
        assert_eq!((w.component(0), w.component(1)), (1.0, -3.0));
        assert_eq!([-0.0, 0.0].direction(), [-1.0, 0.0]);
    }

    /// The solid frame is right-handed and orthonormal for normals along the axes,
    /// tilted and nearly axis-aligned, its first axis is n, and `to_global`
    /// inverts `to_local` to round-off.
    #[test]
    fn solid_frame_is_orthonormal_right_handed_and_invertible() {
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let normals = [
            [1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.48, -0.6, 0.64],
            [1.0 - 1e-12, 1e-6, -1.4e-6],
            [-0.2, 0.1, -0.9],
        ];
        for n in normals {
            let l = D3::length(&n);
            let n = [n[0] / l, n[1] / l, n[2] / l];
            let r = D3::frame(n);
            assert_eq!(D3::axis(&r, 0), n);
            for i in 0..3 {
                for j in 0..3 {
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!((dot(r[i], r[j]) - want).abs() < 1e-15, "{n:?}: {i} {j}");
                }
            }
            // Right-handed: n · (t₁ × t₂) = +1.
            let [a, b, c] = r;
            let triple = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]);
            assert!((triple - 1.0).abs() < 1e-15);
            let v = [0.3, -1.7, 2.2];
            let (v_n, v_t) = D3::to_local(&r, v);
            assert!((v_n - dot(v, n)).abs() < 1e-15);
            assert!((v_n.hypot(v_t.norm()) - D3::length(&v)).abs() < 1e-14);
            let back = D3::to_global(&r, v_n, v_t);
            assert!((0..3).all(|i| (back[i] - v[i]).abs() < 1e-15), "{back:?}");
        }
        assert_eq!(D3::dof(5, 2), 17);
    }

    /// The rigid modes of both dimensions are rigid motions — their velocity
    /// gradient at any point is skew (zero strain: evaluated by central
    /// differences, exact for these linear fields) — and independent: sampled
    /// at the vertices of a tetrahedron (a triangle in 2D) their Gram matrix
    /// has full rank (its smallest eigenvalue well above zero).
    #[test]
    fn rigid_modes_are_independent_motions_without_strain() {
        fn check<D: Dim>(points: &[D::Vector]) {
            let h = 0.5;
            for k in 0..D::RIGID_MODES {
                for x in points {
                    // ∂v_i/∂x_j by a central difference; strain = sym part.
                    let grad = |i: usize, j: usize| {
                        let (mut a, mut b) = (*x, *x);
                        a.as_mut()[j] += h;
                        b.as_mut()[j] -= h;
                        let (va, vb) = (D::rigid_mode(k, a), D::rigid_mode(k, b));
                        (va.as_ref()[i] - vb.as_ref()[i]) / (2.0 * h)
                    };
                    for i in 0..D::N {
                        for j in 0..D::N {
                            assert_eq!(grad(i, j) + grad(j, i), 0.0, "mode {k}: strain {i}{j}");
                        }
                    }
                }
            }
            // Gram matrix of the modes sampled at the points: full rank.
            let m = D::RIGID_MODES;
            let mut g = faer::Mat::<f64>::zeros(m, m);
            for x in points {
                for c in 0..D::N {
                    let row: Vec<f64> = (0..m).map(|k| D::rigid_mode(k, *x).as_ref()[c]).collect();
                    for a in 0..m {
                        for b in 0..m {
                            g[(a, b)] += row[a] * row[b];
                        }
                    }
                }
            }
            let eig = g.self_adjoint_eigen(faer::Side::Lower).unwrap();
            let smallest = (0..m).map(|i| eig.S()[i]).fold(f64::INFINITY, f64::min);
            assert!(
                smallest > 0.1,
                "{} modes: smallest eigenvalue {smallest}",
                m
            );
        }
        check::<D2>(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
        check::<D3>(&[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ]);
        // Across: |v × m|, the plane one the absolute 2D cross product.
        assert_eq!(D2::across([3.0, 4.0], [0.0, 1.0]), 3.0);
        assert_eq!(D3::across([3.0, 4.0, 12.0], [0.0, 0.0, 1.0]), 5.0);
        assert_eq!(D3::dot(&[1.0, 2.0, 3.0], &[4.0, -5.0, 6.0]), 12.0);
    }
}
