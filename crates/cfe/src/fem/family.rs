//! The part elements of a dimension, behind one trait: what assembly and stress
//! recovery call without knowing the element kinds. A plane model's parts are
//! T3/Q4 (plane stress, plane strain, or axisymmetric: [`super::element`],
//! [`super::axisymmetric`]); a solid model's are TET4/HEX8 ([`super::tet4`],
//! [`super::hex8`]). The element matrices and vectors are fixed arrays sized for
//! the dimension's largest element (8 DOFs in 2D, 24 in 3D) whose leading
//! `N n` entries are the element's (n its node count): no allocation per element.
//!
//! Each routine is the dimension's element routines composed, nothing more: the
//! plane implementation is bit for bit the code the 2D assembly ran before it
//! (the same calls in the same order).

use super::element::{self, MAX_DOFS};
use super::recovery::{self, PartStress};
use super::{Material, axisymmetric, hex8, material, tet4};
use crate::dim::{D2, D3};
use crate::mesh::{Element, Mesh, MeshDim, SolidElement};

/// Most DOFs a solid element has (HEX8: 8 nodes × 3).
pub const SOLID_MAX_DOFS: usize = 24;

/// The part elements of a dimension: their constitutive data, stiffness,
/// internal force and stress recovery over a part's mesh.
pub trait ElementFamily: MeshDim {
    /// An element matrix: a square array of row stride [`Self::STRIDE`], whose
    /// leading `N n × N n` block is the element's.
    type ElementMatrix: Copy + Send;
    /// An element vector of DOFs (length [`Self::STRIDE`]); the leading `N n`
    /// entries are the element's.
    type ElementVector: Copy + Send + Sync + AsRef<[f64]> + AsMut<[f64]>;
    /// The global DOFs of an element (length [`Self::STRIDE`]; the leading `N n`
    /// are the element's).
    type ElementDofs: Copy + Send + AsRef<[usize]> + AsMut<[usize]>;
    /// What a part's material gives each of its elements (its constitutive
    /// matrices, thickness), computed once per part.
    type Constitutive: Send + Sync;
    /// A stress in the dimension's Voigt order: (σxx, σyy, σxy) in 2D,
    /// (xx, yy, zz, xy, yz, zx) in 3D ([`super::solid::VOIGT`]).
    type Stress: Copy + Send + Sync + std::fmt::Debug + PartialEq + AsRef<[f64]> + AsMut<[f64]>;
    /// The row stride of an element matrix, and an element vector's length.
    const STRIDE: usize;
    /// Most nodes an element of the dimension has.
    const MAX_NODES: usize;

    /// The constitutive data of `material` for this dimension's elements.
    fn constitutive(material: &Material) -> Self::Constitutive;

    /// A zero element vector.
    fn zero_vector() -> Self::ElementVector;

    /// A zero list of element DOFs.
    fn zero_dofs() -> Self::ElementDofs;

    /// The stiffness `K_e` of `element` of `mesh`.
    fn stiffness(mesh: &Mesh<Self>, element: &Self::Cell, c: &Self::Constitutive) -> Self::ElementMatrix;

    /// An element matrix's entries, row after row (stride [`Self::STRIDE`]).
    fn flat(k: &Self::ElementMatrix) -> &[f64];

    /// The internal force `K_e u_e` of `element` for its displacements `u`,
    /// point by point without forming `K_e`.
    fn internal_force(
        mesh: &Mesh<Self>,
        element: &Self::Cell,
        c: &Self::Constitutive,
        u: &Self::ElementVector,
    ) -> Self::ElementVector;

    /// The stresses of a part (its `mesh` and `material`) from its nodal
    /// displacements `u` (N per node, the part's own numbering): per element and
    /// averaged per node within the part.
    fn recover(mesh: &Mesh<Self>, material: &Material, u: &[f64]) -> PartStress<Self::Stress>;
}

/// The constitutive data of a plane part: its D, thickness, and the 4×4 D when
/// it is axisymmetric.
#[derive(Debug, Clone, Copy)]
pub struct PlaneConstitutive {
    /// The plane D ([`Material::d_matrix`]).
    pub d: [[f64; 3]; 3],
    /// Thickness.
    pub thickness: f64,
    /// The 4×4 D of an axisymmetric part (`None` for a plane part).
    pub axi: Option<[[f64; 4]; 4]>,
}

/// Plane parts: T3/Q4 in plane stress or strain, or axisymmetric.
impl ElementFamily for D2 {
    type ElementMatrix = element::ElementMatrix;
    type ElementVector = [f64; MAX_DOFS];
    type ElementDofs = [usize; MAX_DOFS];
    type Constitutive = PlaneConstitutive;
    type Stress = [f64; 3];
    const STRIDE: usize = MAX_DOFS;
    const MAX_NODES: usize = element::MAX_NODES;

    fn constitutive(material: &Material) -> PlaneConstitutive {
        PlaneConstitutive {
            d: material.d_matrix(),
            thickness: material.thickness,
            axi: material.is_axisymmetric().then(|| material.d_axisymmetric()),
        }
    }

    #[inline(always)]
    fn zero_vector() -> [f64; MAX_DOFS] {
        [0.0; MAX_DOFS]
    }

    #[inline(always)]
    fn zero_dofs() -> [usize; MAX_DOFS] {
        [0; MAX_DOFS]
    }

    #[inline(always)]
    fn stiffness(mesh: &Mesh, el: &Element, c: &PlaneConstitutive) -> element::ElementMatrix {
        let x = element::coordinates(mesh, el);
        match &c.axi {
            None => element::stiffness(el, &x, &c.d, c.thickness),
            Some(d) => axisymmetric::stiffness(el, &x, d),
        }
    }

    #[inline(always)]
    fn flat(k: &element::ElementMatrix) -> &[f64] {
        k.as_flattened()
    }

    #[inline(always)]
    fn internal_force(
        mesh: &Mesh,
        el: &Element,
        c: &PlaneConstitutive,
        u: &[f64; MAX_DOFS],
    ) -> [f64; MAX_DOFS] {
        let x = element::coordinates(mesh, el);
        match &c.axi {
            None => element::internal_force(el, &x, &c.d, c.thickness, u),
            Some(d) => axisymmetric::internal_force(el, &x, d, u),
        }
    }

    fn recover(mesh: &Mesh, material: &Material, u: &[f64]) -> PartStress {
        recovery::recover(mesh, material, u)
    }
}

/// The 6×6 isotropic D of a solid part (its material's E and ν; a solid part
/// has no plane idealisation and no thickness).
#[derive(Debug, Clone, Copy)]
pub struct SolidConstitutive {
    /// [`material::d_solid`].
    pub d: [[f64; 6]; 6],
}

/// The corners of `element` of a solid `mesh`.
#[inline(always)]
fn corners<const N: usize>(mesh: &Mesh<D3>, nodes: &[usize; N]) -> [[f64; 3]; N] {
    nodes.map(|n| mesh.nodes[n])
}

/// `v` in a solid element vector (the leading `v.len()` entries).
#[inline(always)]
fn padded(v: &[f64]) -> [f64; SOLID_MAX_DOFS] {
    let mut out = [0.0; SOLID_MAX_DOFS];
    out[..v.len()].copy_from_slice(v);
    out
}

/// Solid parts: TET4 and HEX8.
impl ElementFamily for D3 {
    type ElementMatrix = [[f64; SOLID_MAX_DOFS]; SOLID_MAX_DOFS];
    type ElementVector = [f64; SOLID_MAX_DOFS];
    type ElementDofs = [usize; SOLID_MAX_DOFS];
    type Constitutive = SolidConstitutive;
    type Stress = [f64; 6];
    const STRIDE: usize = SOLID_MAX_DOFS;
    const MAX_NODES: usize = 8;

    fn constitutive(m: &Material) -> SolidConstitutive {
        SolidConstitutive {
            d: material::d_solid(m.young, m.poisson),
        }
    }

    #[inline(always)]
    fn zero_vector() -> [f64; SOLID_MAX_DOFS] {
        [0.0; SOLID_MAX_DOFS]
    }

    #[inline(always)]
    fn zero_dofs() -> [usize; SOLID_MAX_DOFS] {
        [0; SOLID_MAX_DOFS]
    }

    fn stiffness(
        mesh: &Mesh<D3>,
        el: &SolidElement,
        c: &SolidConstitutive,
    ) -> [[f64; SOLID_MAX_DOFS]; SOLID_MAX_DOFS] {
        match el {
            SolidElement::Tet4(n) => {
                let k = tet4::stiffness(&corners(mesh, n), &c.d);
                let mut out = [[0.0; SOLID_MAX_DOFS]; SOLID_MAX_DOFS];
                for (o, r) in out.iter_mut().zip(&k) {
                    o[..12].copy_from_slice(r);
                }
                out
            }
            SolidElement::Hex8(n) => hex8::stiffness(&corners(mesh, n), &c.d),
        }
    }

    #[inline(always)]
    fn flat(k: &[[f64; SOLID_MAX_DOFS]; SOLID_MAX_DOFS]) -> &[f64] {
        k.as_flattened()
    }

    fn internal_force(
        mesh: &Mesh<D3>,
        el: &SolidElement,
        c: &SolidConstitutive,
        u: &[f64; SOLID_MAX_DOFS],
    ) -> [f64; SOLID_MAX_DOFS] {
        match el {
            SolidElement::Tet4(n) => {
                let ue: [f64; 12] = std::array::from_fn(|i| u[i]);
                padded(&tet4::internal_force(&corners(mesh, n), &c.d, &ue))
            }
            SolidElement::Hex8(n) => hex8::internal_force(&corners(mesh, n), &c.d, u),
        }
    }

    fn recover(mesh: &Mesh<D3>, material: &Material, u: &[f64]) -> PartStress<[f64; 6]> {
        recovery::recover_solid(mesh, &material::d_solid(material.young, material.poisson), u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::PlaneKind;
    use crate::mesh::SolidKind;

    /// Through the family, a solid element's internal force is its stiffness
    /// times its displacements (TET4 and a distorted HEX8), and a rigid motion
    /// (translation plus a small rotation's linear field) gives no force.
    #[test]
    fn solid_family_force_is_stiffness_times_displacement_and_rigid_motion_is_free() {
        let m = Material::new(70e3, 0.33, PlaneKind::Strain, 1.0, "p").unwrap();
        let c = D3::constitutive(&m);
        for kind in [SolidKind::Tet4, SolidKind::Hex8] {
            let mut mesh = Mesh::<D3>::block([0.0, 1.0], [0.0, 2.0], [0.0, 1.5], [1, 1, 1], kind);
            mesh.nodes[6][0] += 0.2;
            mesh.nodes[6][2] -= 0.1;
            for el in &mesh.elements {
                let n = 3 * el.nodes().len();
                let k = D3::stiffness(&mesh, el, &c);
                let mut u = D3::zero_vector();
                for (i, v) in u.iter_mut().take(n).enumerate() {
                    *v = (1.0 + i as f64).sin();
                }
                let got = D3::internal_force(&mesh, el, &c, &u);
                let scale = k[0][0].abs();
                for i in 0..SOLID_MAX_DOFS {
                    let want: f64 = (0..n).map(|j| k[i][j] * u[j]).sum();
                    assert!((got[i] - want).abs() <= 1e-12 * scale, "{kind:?} row {i}");
                }
                // u = a + w × x with w small: zero strain, zero force.
                let (a, w) = ([0.3, -0.2, 0.1], [0.01, -0.02, 0.015]);
                let mut rigid = D3::zero_vector();
                for (i, &node) in el.nodes().iter().enumerate() {
                    let x = mesh.nodes[node];
                    let wx = [
                        w[1] * x[2] - w[2] * x[1],
                        w[2] * x[0] - w[0] * x[2],
                        w[0] * x[1] - w[1] * x[0],
                    ];
                    for d in 0..3 {
                        rigid[3 * i + d] = a[d] + wx[d];
                    }
                }
                let f = D3::internal_force(&mesh, el, &c, &rigid);
                assert!(f.iter().all(|v| v.abs() <= 1e-10 * scale), "{kind:?}: {f:?}");
            }
        }
    }
}
