//! The 3D coupling element, `CouplingElement<D3>`, checked through the generic
//! code it shares with the plane one (test-only): its kinematics on a TET4 face,
//! a warped HEX8 face and inside a HEX8 (the volume form, 27 DOFs), its
//! stiffness against a finite difference of its force, and the invariance of
//! its results under a turn of the tangent pair (t₁, t₂) in the face plane.

use super::element::{CouplingElement, MAX_DOFS};
use super::face::{cross, quad_normal, quad_shape, unit};
use super::law::{Law, LawParams, PairHistory, PairState, return_map};
use crate::dim::{D3, Dim, Tangent};
use crate::dofs::DofMap;

/// D3 with its tangent pair turned by `K` × 0.37 rad about n: another right-handed
/// orthonormal frame (n, t₁', t₂') of the same face — a choice no result may
/// depend on.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Turned<const K: i32>;

impl<const K: i32> Dim for Turned<K> {
    const N: usize = 3;
    const RIGID_MODES: usize = 6;
    const VOIGT: usize = 6;
    type Vector = [f64; 3];
    type Tangent = [f64; 2];
    type Frame = [[f64; 3]; 3];

    fn length(v: &[f64]) -> f64 {
        D3::length(v)
    }

    fn frame(n: [f64; 3]) -> [[f64; 3]; 3] {
        let [n, t1, t2] = D3::frame(n);
        let (s, c) = (K as f64 * 0.37).sin_cos();
        [
            n,
            std::array::from_fn(|i| c * t1[i] + s * t2[i]),
            std::array::from_fn(|i| -s * t1[i] + c * t2[i]),
        ]
    }

    fn axis(r: &[[f64; 3]; 3], k: usize) -> [f64; 3] {
        D3::axis(r, k)
    }

    fn to_local(r: &[[f64; 3]; 3], v: [f64; 3]) -> (f64, [f64; 2]) {
        D3::to_local(r, v)
    }

    fn to_global(r: &[[f64; 3]; 3], v_n: f64, v_t: [f64; 2]) -> [f64; 3] {
        D3::to_global(r, v_n, v_t)
    }

    fn across(v: [f64; 3], m: [f64; 3]) -> f64 {
        D3::across(v, m)
    }

    fn rigid_mode(k: usize, x: [f64; 3]) -> [f64; 3] {
        D3::rigid_mode(k, x)
    }
}

/// A host of a 3D coupling element: its nodes' coordinates, the shape values at
/// the coupling node, the node's position Σ N̄ᵢ Xᵢ and the unit normal there.
struct Host {
    x: Vec<[f64; 3]>,
    shape: Vec<f64>,
    position: [f64; 3],
    normal: [f64; 3],
}

fn at(x: &[[f64; 3]], shape: &[f64]) -> [f64; 3] {
    std::array::from_fn(|c| x.iter().zip(shape).map(|(p, n)| n * p[c]).sum())
}

/// The three forms: a TET4 face (barycentric (0.2, 0.5, 0.3)), a warped HEX8 face
/// (the saddle z = −0.2 x y at (0.3, −0.5)) and a node inside a distorted HEX8
/// (trilinear values at (0.2, −0.4, 0.6): all 8 nodes, 27 DOFs).
fn hosts() -> Vec<Host> {
    let tri = vec![[0.0, 0.0, 0.0], [3.0, 0.5, 0.2], [0.4, 2.5, -0.3]];
    let tri_shape = vec![0.2, 0.5, 0.3];
    let w = 0.2;
    let quad = [
        [-1.0, -1.0, -w],
        [1.0, -1.0, w],
        [1.0, 1.0, -w],
        [-1.0, 1.0, w],
    ];
    let quad_xi = [0.3, -0.5];
    let hex: Vec<[f64; 3]> = (0..8)
        .map(|k| {
            let s = [
                [-1.0, -1.0],
                [1.0, -1.0],
                [1.0, 1.0],
                [-1.0, 1.0],
            ][k % 4];
            let z = if k < 4 { -1.0 } else { 1.0 };
            [2.0 * s[0] + 0.1 * z, 1.5 * s[1] - 0.2 * s[0] * z, 1.2 * z + 0.05 * s[0] * s[1]]
        })
        .collect();
    let (a, b, c) = (0.2, -0.4, 0.6);
    let hex_shape: Vec<f64> = (0..8)
        .map(|k| {
            let s = [
                [-1.0, -1.0],
                [1.0, -1.0],
                [1.0, 1.0],
                [-1.0, 1.0],
            ][k % 4];
            let z = if k < 4 { -1.0 } else { 1.0 };
            0.125 * (1.0 + s[0] * a) * (1.0 + s[1] * b) * (1.0 + z * c)
        })
        .collect();
    vec![
        Host {
            position: at(&tri, &tri_shape),
            normal: unit(cross(
                std::array::from_fn(|i| tri[1][i] - tri[0][i]),
                std::array::from_fn(|i| tri[2][i] - tri[0][i]),
            )),
            x: tri,
            shape: tri_shape,
        },
        Host {
            position: at(&quad, &quad_shape(quad_xi)),
            normal: quad_normal(&quad, quad_xi),
            x: quad.to_vec(),
            shape: quad_shape(quad_xi).to_vec(),
        },
        Host {
            position: at(&hex, &hex_shape),
            normal: unit([0.48, -0.6, 0.64]),
            x: hex,
            shape: hex_shape,
        },
    ]
}

fn element<D: Dim<Vector = [f64; 3]>>(h: &Host) -> CouplingElement<D> {
    CouplingElement {
        node: 0,
        host_element: 0,
        host_nodes: (0..h.x.len()).collect(),
        shape: h.shape.clone(),
        normal: h.normal,
        position: h.position,
        distance: 0.0,
        gap0: 0.0,
        tributary: 1.0,
        edge_length: 1.0,
        ring: 1.0,
        segment: None,
    }
}

/// The element displacements of the displacement field `u(X)` at the host nodes,
/// then the coupling node.
fn field(h: &Host, u: impl Fn([f64; 3]) -> [f64; 3]) -> Vec<f64> {
    h.x.iter()
        .chain([&h.position])
        .flat_map(|&p| u(p))
        .collect()
}

/// The 6 rigid modes of node and host together — three translations and three
/// infinitesimal rotations θ × X — give no jump and no stiffness force (K d = 0),
/// on a TET4 face, a warped HEX8 face and inside a HEX8; a translation t of the
/// coupling node alone gives the jump t, whose local components are (t·n, t·t₁,
/// t·t₂).
#[test]
fn rigid_motions_give_no_jump_and_a_node_translation_is_the_jump() {
    for h in hosts() {
        let c = element::<D3>(&h);
        assert_eq!(c.n_dofs(), 3 * (h.x.len() + 1));
        let k = c.stiffness(1e9, 4e8, PairState::Bonded);
        for axis in 0..3 {
            let mut t = [0.0; 3];
            t[axis] = 1.0;
            let mut theta = [0.0; 3];
            theta[axis] = 1.0;
            for d in [field(&h, |_| t), field(&h, |p| cross(theta, p))] {
                let j = c.jump(&d);
                assert!(j.iter().all(|v| v.abs() < 1e-14), "{j:?}");
                let kd = k.mul(&d);
                assert!(kd.iter().all(|v| v.abs() < 1e-14 * 1e9), "{kd:?}");
            }
        }
        let t = [0.3, -0.7, 1.1];
        let mut d = vec![0.0; c.n_dofs()];
        d[c.n_dofs() - 3..].copy_from_slice(&t);
        assert_eq!(c.jump(&d), t);
        let r = D3::frame(h.normal);
        let dot = |a: [f64; 3]| a[0] * t[0] + a[1] * t[1] + a[2] * t[2];
        let (u_n, u_t) = c.local_jump(&d);
        assert!((u_n - dot(r[0])).abs() < 1e-15);
        assert!((u_t[0] - dot(r[1])).abs() < 1e-15 && (u_t[1] - dot(r[2])).abs() < 1e-15);
    }
}

/// The element displacements used by the comparisons: a fixed pseudo-random set.
fn displacements(n: usize) -> Vec<f64> {
    (0..n).map(|i| ((i * 7 + 3) % 11) as f64 * 0.01 - 0.05).collect()
}

/// The bonded stiffness in global components does not depend on the tangent
/// pair: turned by four angles in the face plane, K_e agrees with D3's to
/// round-off (c_n ≠ c_s: C = c_n n nᵀ + c_s (I − n nᵀ)); with c_n = c_s = c it
/// is c I per node pair, `C = c I` exactly as it must be, whatever (t₁, t₂).
#[test]
fn the_bonded_stiffness_does_not_depend_on_the_tangent_pair() {
    fn compare<D: Dim<Vector = [f64; 3]>>(h: &Host) {
        let a = element::<D3>(h).stiffness(2e3, 7e2, PairState::Bonded);
        let b = element::<D>(h).stiffness(2e3, 7e2, PairState::Bonded);
        for p in 0..a.dofs {
            for q in 0..a.dofs {
                assert!((a.get(p, q) - b.get(p, q)).abs() < 1e-12 * 2e3, "({p}, {q})");
            }
        }
        let eq = element::<D>(h).stiffness(5e2, 5e2, PairState::Bonded);
        for i in 0..3 {
            for j in 0..3 {
                let want = if i == j { 5e2 } else { 0.0 };
                assert!((eq.c[i][j] - want).abs() < 1e-12 * 5e2, "{:?}", eq.c);
            }
        }
    }
    for h in hosts() {
        compare::<Turned<0>>(&h);
        compare::<Turned<1>>(&h);
        compare::<Turned<4>>(&h);
        compare::<Turned<-3>>(&h);
    }
}

/// The global nodal force of a slipping Coulomb pair (f_n = c_n g_n < 0, the
/// slip force the return map of the trial force c_s ([[u_t]] − s_p), the spring
/// at its anchor) for a global plastic slip s_p in the face plane.
fn coulomb_force<D: Dim<Vector = [f64; 3]>>(h: &Host, d: &[f64], slip: [f64; 3]) -> [f64; MAX_DOFS] {
    let law = LawParams {
        law: Law::Coulomb,
        c_n: 1e3,
        c_s: 4e2,
        friction: 0.3,
        c_slip: 0.4,
    };
    let c = element::<D>(h);
    let frame = D::frame(c.normal);
    let (u_n, u_t) = c.local_jump(d);
    let mut hist = PairHistory::<D> {
        slip: D::to_local(&frame, slip).1,
        anchor: u_t,
        ..Default::default()
    };
    let gap = c.gap((u_n, u_t));
    let trial = law.trial_shear(u_t, &hist);
    hist.slip_force = return_map(trial, law.cone(law.c_n * gap));
    c.nodal_force(law.local_force(PairState::Slip, gap, u_t, &hist))
}

/// The Coulomb return map is radial, so a slipping pair's global force does not
/// depend on the tangent pair: for four turns of (t₁, t₂) it agrees with D3's to
/// round-off, and on the coupling node its tangential part is μ|f_n| along the
/// global trial force c_s ((I − n nᵀ)[[U]] − s_p) — computed here without any
/// tangent.
#[test]
fn the_coulomb_return_map_does_not_depend_on_the_tangent_pair() {
    for h in hosts() {
        let c = element::<D3>(&h);
        let m = c.n_dofs();
        let n = h.normal;
        // A compressive jump: the host barely moved, the node pushed 0.02 into
        // it and sheared by 0.05 along a tangent direction.
        let mut d: Vec<f64> = displacements(m).iter().map(|v| 0.01 * v).collect();
        let along = unit(cross(n, [0.3, 0.9, -0.2]));
        for i in 0..3 {
            d[m - 3 + i] += -0.02 * n[i] + 0.05 * along[i];
        }
        let slip_raw = [0.004, -0.002, 0.003];
        let sn: f64 = (0..3).map(|i| slip_raw[i] * n[i]).sum();
        let slip: [f64; 3] = std::array::from_fn(|i| slip_raw[i] - sn * n[i]);
        let base = coulomb_force::<D3>(&h, &d, slip);
        for other in [
            coulomb_force::<Turned<1>>(&h, &d, slip),
            coulomb_force::<Turned<4>>(&h, &d, slip),
            coulomb_force::<Turned<-3>>(&h, &d, slip),
            coulomb_force::<Turned<9>>(&h, &d, slip),
        ] {
            for p in 0..m {
                assert!((base[p] - other[p]).abs() < 1e-12 * 1e3, "{p}: {} {}", base[p], other[p]);
            }
        }
        // Independent truth on the coupling node (b = 1 there): f = f_n n + μ|f_n| τ.
        let jump = c.jump(&d);
        let jn: f64 = (0..3).map(|i| jump[i] * n[i]).sum();
        let f_n = 1e3 * jn;
        assert!(f_n < 0.0);
        let trial: [f64; 3] = std::array::from_fn(|i| 4e2 * (jump[i] - jn * n[i] - slip[i]));
        let tau = unit(trial);
        assert!(crate::coupling::face::norm(trial) > 0.3 * -f_n, "the pair must slip");
        for i in 0..3 {
            let want = f_n * n[i] + 0.3 * -f_n * tau[i];
            assert!((base[m - 3 + i] - want).abs() < 1e-12 * 1e3, "{i}");
        }
    }
}

/// The element's force is consistent with its stiffness: the central difference
/// of the nodal force of the law's evaluation (frictionless, bonded, with an
/// initial gap g₀ = 0.02) in each element DOF equals the column of K_e with
/// penalties (c_n, 0) — to round-off, since the law is affine there — and the
/// bonded law's with (c_n, c_s); and the forces are self-equilibrated.
#[test]
fn the_force_differences_to_the_stiffness() {
    for h in hosts() {
        for (law, c_s) in [(Law::Frictionless, 0.0), (Law::Contact, 6e2)] {
            let params = LawParams {
                law,
                c_n: 1e3,
                c_s: 6e2,
                friction: 0.0,
                c_slip: 0.0,
            };
            let mut c = element::<D3>(&h);
            c.gap0 = 0.02;
            let m = c.n_dofs();
            let force = |d: &[f64]| {
                let (u_n, u_t) = c.local_jump(d);
                let f = params.local_force(PairState::Bonded, c.gap((u_n, u_t)), u_t, &PairHistory::<D3>::default());
                c.nodal_force(f)
            };
            let k = c.stiffness(1e3, c_s, PairState::Bonded);
            let d = displacements(m);
            let eps = 1e-4;
            for q in 0..m {
                let mut up = d.clone();
                let mut down = d.clone();
                up[q] += eps;
                down[q] -= eps;
                let (fu, fd) = (force(&up), force(&down));
                for p in 0..m {
                    let fdiff = (fu[p] - fd[p]) / (2.0 * eps);
                    assert!((fdiff - k.get(p, q)).abs() < 1e-7 * 1e3, "{law:?} ({p}, {q}): {fdiff} vs {}", k.get(p, q));
                }
            }
            let f = force(&d);
            for comp in 0..3 {
                let sum: f64 = (0..m / 3).map(|a| f[3 * a + comp]).sum();
                assert!(sum.abs() < 1e-12 * 1e3);
            }
        }
    }
}

/// The volume form fits the DOF cap: a node inside a HEX8 has 9 nodes and 27
/// DOFs (= `MAX_DOFS`), numbered 3 g + c by a 3D DOF map, and its rank-one terms
/// (n, t₁, t₂) sum to its stiffness.
#[test]
fn the_volume_form_has_27_dofs_numbered_by_a_3d_dof_map() {
    let h = hosts().pop().unwrap();
    let c = element::<D3>(&h);
    assert_eq!((c.n_dofs(), MAX_DOFS), (27, 27));
    let map = DofMap::<D3> {
        node_offset: vec![0, 8, 9],
        eq: (0..27).collect(),
        n_eq: 27,
        prescribed: vec![0.0; 27],
        fixed: Vec::new(),
        dim: std::marker::PhantomData,
    };
    let ids = c.dofs(&map, 0, 1);
    assert_eq!(ids.as_slice(), (0..27).collect::<Vec<_>>());
    let k = c.stiffness(3.0, 2.0, PairState::Bonded);
    let mut sum = vec![0.0; 27 * 27];
    let mut count = 0;
    c.for_each_stiffness_term(3.0, 2.0, |_, ck, w| {
        count += 1;
        for p in 0..27 {
            for q in 0..27 {
                sum[27 * p + q] += ck * w[p] * w[q];
            }
        }
    });
    assert_eq!(count, 1 + <[f64; 2] as Tangent>::COMPONENTS);
    for p in 0..27 {
        for q in 0..27 {
            assert!((sum[27 * p + q] - k.get(p, q)).abs() < 1e-13, "({p}, {q})");
        }
    }
}
