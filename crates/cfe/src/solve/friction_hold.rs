//! The statics check of friction: can friction hold each part, or group of
//! parts, whose only hold along its faces is friction? (The rank test of
//! [`super::support`] cannot tell: a slipping pair keeps a stabilising
//! spring.) Asked before any solve of an increment ([`FrictionHold::check`]),
//! and at a settled state for a part a support holds only across its faces
//! ([`FrictionHold::check_settled`]). In any dimension: the faces' mean
//! direction m, the load's part along m ([`Dim::dot`]) and across it
//! ([`Dim::across`]).

use super::support::{groups, has_support, unheld_groups};
use crate::assembly::DofMap;
use crate::coupling::{Interface, Law, PairHistory, PairState};
use crate::dim::{D2, Dim};
use crate::domain::Part;
use crate::error::{Error, Result};
use std::f64::consts::FRAC_PI_2;

/// Can friction hold each part, or group of parts, whose only hold along its
/// faces is friction?
///
/// A body — one part, or parts coupled to each other taken together, whose
/// mutual pair forces cancel — with no support, whose every interface to the
/// rest is frictional (`coulomb`, or `frictionless` beside one) and whose faces
/// all push it the same way is held by those faces' pair forces alone. Pair i
/// pushes the body along its direction dᵢ (the host face's outward normal when
/// the body holds the node side, its opposite when it holds the host) with
/// f_n,i ≥ 0 and carries at most μ f_n,i across it. With m the mean of the dᵢ,
/// ε the largest angle between a dᵢ and m, and φ = atan μ_max, the force any
/// such set of pairs exerts lies in the cone of half-angle φ + ε about m.
/// Equilibrium with the body's load F then needs
///
/// ```text
///   |F·t| ≤ tan(φ + ε) · (−F·m)        (t ⟂ m)
/// ```
///
/// the inclined plane's `tan θ ≤ μ` (a flat face: ε = 0). A load beyond it has
/// no state of rest, whatever the pair states: rather than search the patterns
/// for one (each a fixed point on the slip forces that cannot converge, the
/// body drifting under the slipping pairs' springs), the run stops before the
/// increment's first solve. Where φ + ε reaches 90° (a groove, a curved seat)
/// the faces can wedge the body against any load, and it is not checked.
///
/// The bodies checked: every part without a support; and the connected groups
/// of such parts, linked by any interface and by the `rigid` and `contact`
/// interfaces only (a block bonded to a plate that rests on a frictional face;
/// a stack whose middle part is pressed from both sides). Each is a necessary
/// condition: a body that passes may still find no state.
pub struct FrictionHold<D: Dim = D2> {
    bodies: Vec<FrictionBody<D>>,
    /// The parts a support holds only across their faces, with the axis (0: x,
    /// 1: y, 2: z) of every DOF their supports fix ([`FrictionHold::check_settled`]).
    across: Vec<(FrictionBody<D>, usize)>,
    /// Whether every part without a support that touches a `coulomb`
    /// interface is in a body checked (see [`FrictionHold::judges_all`]).
    judges_all: bool,
}

/// A body held along its faces by friction alone (see [`FrictionHold`]).
struct FrictionBody<D: Dim> {
    /// Its parts' names.
    parts: Vec<String>,
    /// Its parts' global nodes (their DOFs are `D::dof(g, c)`).
    nodes: Vec<std::ops::Range<usize>>,
    /// The interfaces holding it, with the sign of the direction their pairs
    /// push it (+1: it holds their node side).
    holding: Vec<(usize, f64)>,
    /// The interfaces holding it, their names quoted, for messages.
    interfaces: String,
    /// Number of their coupling pairs.
    pairs: usize,
    /// Unit mean direction m in which its faces push it.
    normal: D::Vector,
    /// Largest friction coefficient of those interfaces.
    friction: f64,
    /// Largest angle ε between a pair's direction and m (radians).
    spread: f64,
}

impl<D: Dim> FrictionHold<D> {
    /// The bodies of `parts` that friction alone holds along their faces,
    /// under the supports of `dofs` and the interfaces `interfaces`.
    ///
    /// An axisymmetric model has no such body to judge: a ring's pairs push it
    /// radially from all sides, their resultant is along the axis alone, and the
    /// cone of one direction does not bound it (the search decides).
    pub fn new(parts: &[Part], interfaces: &[Interface<D>], dofs: &DofMap<D>) -> Self {
        if parts.iter().any(|p| p.material.is_axisymmetric()) {
            return FrictionHold {
                bodies: Vec::new(),
                across: Vec::new(),
                judges_all: false,
            };
        }
        let free: Vec<bool> = (0..parts.len()).map(|p| !has_support(dofs, p)).collect();
        let candidates = candidate_bodies(interfaces, &free);
        let bodies: Vec<FrictionBody<D>> = candidates
            .into_iter()
            .filter_map(|body| friction_body(parts, interfaces, dofs, &body))
            .collect();
        // Parts a support holds only across their faces: every DOF their
        // supports fix is along one axis, the faces' mean direction, so along
        // the faces only friction holds them (a block held in y on a face in x).
        let across: Vec<(FrictionBody<D>, usize)> = (0..parts.len())
            .filter(|&p| !free[p])
            .filter_map(|p| {
                let axis = support_axis(dofs, p)?;
                let body = friction_body(parts, interfaces, dofs, &[p])?;
                (body.normal.as_ref()[axis].abs() >= 1.0 - 1e-12).then_some((body, axis))
            })
            .collect();
        let judged: Vec<&String> = bodies.iter().flat_map(|b| &b.parts).collect();
        let judges_all = (0..parts.len()).all(|p| {
            !free[p]
                || judged.contains(&&parts[p].name)
                || !interfaces
                    .iter()
                    .any(|i| i.law == Law::Coulomb && (i.host == p || i.node_part == p))
        });
        FrictionHold {
            bodies,
            across,
            judges_all,
        }
    }

    /// Whether every part friction holds along its faces (a part without a
    /// support touching a `coulomb` interface) is in a body the check judges:
    /// then, once [`FrictionHold::check`] has passed, friction can hold the
    /// loads, as far as statics tells.
    pub fn judges_all(&self) -> bool {
        self.judges_all
    }

    /// Checks every such body under the load `lambda × f_ext` (by global DOF,
    /// `D::dof(g, c)` for component c of global node g). `slack` is the force by which the law
    /// check lets each pair exceed its cone (a completed run's tolerance): a load
    /// is refused only when it exceeds the cone by more than the pairs' slack
    /// together, so no pattern the law check would accept is ruled out. `when`
    /// says where on the load path, for the message (formed only for one). Returns an
    /// [`Error::Unsupported`] naming the parts of every body friction cannot
    /// hold (a group only when none of its parts is named already).
    pub fn check(
        &self,
        f_ext: &[f64],
        lambda: f64,
        slack: f64,
        when: impl Fn() -> String,
    ) -> Result<()> {
        let mut held: Vec<String> = Vec::new();
        let mut messages = Vec::new();
        for body in &self.bodies {
            if body.parts.iter().any(|p| held.contains(p)) {
                continue;
            }
            let load = body.load(f_ext, lambda);
            let cone = (body.friction.atan() + body.spread).tan();
            let margin = body.pairs as f64 * slack * (1.0 + cone);
            let Some(limit) = beyond_friction::<D>(load, body.normal, cone, margin) else {
                continue;
            };
            held.extend(body.parts.iter().cloned());
            let quoted: Vec<String> = body.parts.iter().map(|n| format!("'{n}'")).collect();
            let (who, its, it) = match quoted.len() {
                1 => (quoted[0].clone(), "its", "it"),
                _ => (format!("{} taken together", quoted.join(", ")), "their", "them"),
            };
            let spread = if body.spread > 1e-6 {
                format!(
                    ", the faces turning up to {0:.2}° from their mean direction: tan(atan μ + {0:.2}°) × the pressing force",
                    body.spread.to_degrees()
                )
            } else {
                String::new()
            };
            let pressed = if limit.pressing >= 0.0 {
                // (+ 0: no "-0" for a load along the faces alone.)
                format!("press {it} onto {its} faces with {:.4e}", limit.pressing + 0.0)
            } else {
                format!(
                    "press {it} onto {its} faces with nothing (they pull {it} away with {:.4e})",
                    -limit.pressing
                )
            };
            messages.push(format!(
                "{who} at {}: {its} loads {pressed} and push {it} along {its} faces with {:.4e}, but friction (μ = {} on {}{spread}) holds at most {:.4e}, and nothing else holds {it} along {its} faces (no support, no bonded interface)",
                when(),
                limit.along,
                body.friction,
                body.interfaces,
                limit.capacity,
            ));
        }
        if held.is_empty() {
            return Ok(());
        }
        let quoted: Vec<String> = held.iter().map(|n| format!("'{n}'")).collect();
        Err(Error::Unsupported {
            message: format!(
                "part(s) {} pushed along their faces harder than friction holds them, so no state of rest exists: {}. Hold the part, raise the friction coefficient, or reduce the tangential load",
                quoted.join(", "),
                messages.join("; ")
            ),
            parts: held,
        })
    }

    /// Checks, at a solution in which the contact search found no state
    /// satisfying the law (`u` in the pair `states` with the pairs' `history`,
    /// under the load `lambda × f_ext`), every part a support holds only across
    /// its faces: along them only friction holds it, so at rest its faces carry
    /// its whole load along them, |F·t|, and friction holds at most
    /// tan(φ + ε) × the force N with which they press it — here the force they
    /// carry in this state (its loads' and its supports' share: statics alone
    /// cannot tell it, the supports' reaction being indeterminate). A load beyond
    /// it (by more than the pairs' `slack`, as [`FrictionHold::check`]) is
    /// Coulomb's no-rest case: an [`Error::Unsupported`] naming the part, the
    /// axis its supports fix and the amounts.
    #[allow(clippy::too_many_arguments)]
    pub fn check_settled(
        &self,
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        f_ext: &[f64],
        lambda: f64,
        slack: f64,
        u: &[f64],
        states: &[Vec<PairState>],
        history: &[Vec<PairHistory<D>>],
        when: impl Fn() -> String,
    ) -> Result<()> {
        let mut held = Vec::new();
        let mut messages = Vec::new();
        for (body, axis) in &self.across {
            let load = body.load(f_ext, lambda);
            // The force with which the faces press the body: each closed
            // pair's normal force on it (−f_n, > 0 pressing).
            let mut pressing: f64 = 0.0;
            for &(i, _) in &body.holding {
                for (k, &state) in states[i].iter().enumerate() {
                    if state.is_closed() {
                        let h = history.get(i).and_then(|h| h.get(k)).copied().unwrap_or_default();
                        pressing -= interfaces[i].pair_at(k, dofs, u, state, &h).force.0;
                    }
                }
            }
            let m = body.normal;
            let along = D::across(load, m);
            let cone = (body.friction.atan() + body.spread).tan();
            let capacity = cone * pressing.max(0.0);
            let margin = body.pairs as f64 * slack * (1.0 + cone);
            if along <= capacity + margin {
                continue;
            }
            let part = &body.parts[0];
            let by_loads = -D::dot(load.as_ref(), m.as_ref());
            messages.push(format!(
                "'{part}' at {}: its supports fix only {} (across its faces), so along its faces only friction holds it; in the least-violating state the contact search settled on, its faces press it with {:.4e} (its loads with {:.4e}, its supports with the rest), and its loads push it along them with {:.4e}, but friction (μ = {} on {}) holds at most {:.4e} × {:.4e} = {:.4e}",
                when(),
                ["x", "y", "z"][*axis],
                pressing,
                by_loads + 0.0,
                along,
                body.friction,
                body.interfaces,
                cone,
                pressing.max(0.0),
                capacity,
            ));
            held.push(part.clone());
        }
        if held.is_empty() {
            return Ok(());
        }
        let quoted: Vec<String> = held.iter().map(|n| format!("'{n}'")).collect();
        Err(Error::Unsupported {
            message: format!(
                "part(s) {} pushed along their faces harder than friction holds them at the normal force their faces carry (Coulomb: a tangential load beyond μ × the normal force), so no state of rest was found and none exists at that normal force: {}. Hold the part along its faces, raise the friction coefficient, or reduce the tangential load",
                quoted.join(", "),
                messages.join("; ")
            ),
            parts: held,
        })
    }
}

/// The parts, and groups of parts, without a support that friction may hold
/// (`free[p]`: part p has no support): single parts, then the groups linked by
/// any interface, then by the `rigid` and `contact` ones only (sorted, no
/// repeats). A part linked to no supported part at all is left out: nothing
/// holds it by friction, the support check names it (no support), and
/// friction is not blamed.
fn candidate_bodies<D: Dim>(interfaces: &[Interface<D>], free: &[bool]) -> Vec<Vec<usize>> {
    let n = free.len();
    let supported: Vec<bool> = free.iter().map(|f| !f).collect();
    let mut unheld = vec![false; n];
    for p in unheld_groups(n, interfaces, &supported).concat() {
        unheld[p] = true;
    }
    let mut candidates: Vec<Vec<usize>> = (0..n)
        .filter(|&p| free[p] && !unheld[p])
        .map(|p| vec![p])
        .collect();
    for bonded_only in [false, true] {
        let linked = |i: &Interface<D>| {
            free[i.host]
                && free[i.node_part]
                && (!bonded_only || matches!(i.law, Law::Rigid | Law::Contact))
        };
        let links = interfaces
            .iter()
            .filter(|i| linked(i))
            .map(|i| (i.host, i.node_part));
        for group in groups(n, links) {
            if group.len() > 1
                && group.iter().all(|&p| free[p] && !unheld[p])
                && !candidates.contains(&group)
            {
                candidates.push(group);
            }
        }
    }
    candidates
}

/// The body of the parts `body` held along its faces by friction alone, if
/// every interface between it and the rest is frictional (`coulomb`, or
/// `frictionless` beside one), its faces push it one way and the friction
/// cone does not reach 90° (see [`FrictionHold`]).
fn friction_body<D: Dim>(
    parts: &[Part],
    interfaces: &[Interface<D>],
    dofs: &DofMap<D>,
    body: &[usize],
) -> Option<FrictionBody<D>> {
    let inside = |p: usize| body.contains(&p);
    // The interfaces between the body and the rest, with the sign of the
    // direction their pairs push the body.
    let holding: Vec<(usize, f64)> = (0..interfaces.len())
        .filter_map(|i| {
            let iface = &interfaces[i];
            match (inside(iface.host), inside(iface.node_part)) {
                (false, true) => Some((i, 1.0)),
                (true, false) => Some((i, -1.0)),
                _ => None,
            }
        })
        .collect();
    let laws = || holding.iter().map(|&(i, _)| interfaces[i].law);
    if !laws().all(|l| matches!(l, Law::Coulomb | Law::Frictionless))
        || !laws().any(|l| l == Law::Coulomb)
    {
        return None;
    }
    let directions = holding.iter().flat_map(|&(i, sign)| {
        interfaces[i]
            .elements
            .iter()
            .map(move |c| scaled::<D>(sign, c.normal))
    });
    let (normal, spread) = face_direction::<D>(directions)?;
    let friction = holding
        .iter()
        .map(|&(i, _)| interfaces[i].friction)
        .fold(0.0, f64::max);
    // Past 90° the cone holds every direction: no bound.
    if friction.atan() + spread >= FRAC_PI_2 - 1e-9 {
        return None;
    }
    let names: Vec<String> = holding
        .iter()
        .map(|&(i, _)| format!("'{}'", interfaces[i].name))
        .collect();
    Some(FrictionBody {
        parts: body.iter().map(|&p| parts[p].name.clone()).collect(),
        nodes: body
            .iter()
            .map(|&p| dofs.node_offset[p]..dofs.node_offset[p + 1])
            .collect(),
        pairs: holding.iter().map(|&(i, _)| interfaces[i].elements.len()).sum(),
        interfaces: names.join(", "),
        holding,
        normal,
        friction,
        spread,
    })
}

/// The one axis (0: x, 1: y, 2: z) along which the supports of part `p` fix
/// its DOFs, if they fix some and all along the same axis.
fn support_axis<D: Dim>(dofs: &DofMap<D>, p: usize) -> Option<usize> {
    let (a, b) = (D::dof(dofs.node_offset[p], 0), D::dof(dofs.node_offset[p + 1], 0));
    let first = dofs.fixed.partition_point(|&(d, _)| d < a);
    let last = dofs.fixed.partition_point(|&(d, _)| d < b);
    let mut axes = dofs.fixed[first..last].iter().map(|&(d, _)| d % D::N);
    let axis = axes.next()?;
    axes.all(|c| c == axis).then_some(axis)
}

/// The unit mean m of `directions` and the largest angle ε between one of them
/// and m; `None` when there are none or they cancel (a nonzero sum means at
/// least one).
fn face_direction<D: Dim>(
    directions: impl Iterator<Item = D::Vector> + Clone,
) -> Option<(D::Vector, f64)> {
    let sum = directions.clone().fold(D::Vector::default(), |mut a, d| {
        for c in 0..D::N {
            a.as_mut()[c] += d.as_ref()[c];
        }
        a
    });
    let len = D::length(sum.as_ref());
    if len.is_nan() || len <= 0.0 {
        return None;
    }
    let m = scaled::<D>(1.0 / len, sum);
    let spread = directions
        .map(|d| D::across(d, m).atan2(D::dot(d.as_ref(), m.as_ref())))
        .fold(0.0, f64::max);
    Some((m, spread))
}

/// A load beyond the friction a face holds: its components and the most the face
/// holds.
#[derive(Debug, Clone, Copy, PartialEq)]
struct BeyondFriction {
    /// −F·m: how hard the load presses the part onto the face (negative: pulls it
    /// away).
    pressing: f64,
    /// |F·t|: how hard it pushes the part along the face.
    along: f64,
    /// tan(φ + ε) × max(pressing, 0): the most friction holds along the face.
    capacity: f64,
}

/// Whether the load `f` on a part whose faces push it along the unit direction
/// `m` with the friction cone `cone` = tan(φ + ε) exceeds what they hold by more
/// than `margin` (see [`FrictionHold`]).
fn beyond_friction<D: Dim>(
    f: D::Vector,
    m: D::Vector,
    cone: f64,
    margin: f64,
) -> Option<BeyondFriction> {
    let pressing = -D::dot(f.as_ref(), m.as_ref());
    let along = D::across(f, m);
    let capacity = cone * pressing.max(0.0);
    (along > capacity + margin).then_some(BeyondFriction {
        pressing,
        along,
        capacity,
    })
}

impl<D: Dim> FrictionBody<D> {
    /// The body's load at factor `lambda`: `λ f_ext` summed over its nodes.
    fn load(&self, f_ext: &[f64], lambda: f64) -> D::Vector {
        self.nodes
            .iter()
            .flat_map(|r| r.clone())
            .fold(D::Vector::default(), |mut a, g| {
                for c in 0..D::N {
                    a.as_mut()[c] += lambda * f_ext[D::dof(g, c)];
                }
                a
            })
    }
}

/// `a v`, component by component.
fn scaled<D: Dim>(a: f64, v: D::Vector) -> D::Vector {
    let mut w = v;
    for x in w.as_mut() {
        *x *= a;
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The inclined plane (any statics text, e.g. Beer & Johnston, *Vector
    /// Mechanics for Engineers: Statics*, §8.2): a block of weight W on a face
    /// inclined at θ stays at rest iff tan θ ≤ μ.
    ///
    /// ```text
    ///          ↓ W
    ///        ▟██▙
    ///      ╱▔▔▔▔      face at θ, normal d = (−sin θ, cos θ)
    ///    ╱ θ
    /// ```
    #[test]
    fn the_inclined_plane_holds_the_block_iff_tan_theta_is_at_most_mu() {
        for mu in [0.1_f64, 0.3, 0.8] {
            let phi = mu.atan();
            for (theta, held) in [(phi - 1e-6, true), (phi + 1e-6, false), (0.0, true)] {
                let d = [-theta.sin(), theta.cos()];
                let (m, spread) = face_direction::<D2>([d; 7].into_iter()).unwrap();
                assert!(spread < 1e-12, "one flat face has no spread: {spread}");
                let cone = (mu.atan() + spread).tan();
                let w = 1234.5;
                let beyond = beyond_friction::<D2>([0.0, -w], m, cone, 1e-9 * w);
                assert_eq!(beyond.is_none(), held, "μ = {mu}, θ = {theta}");
                if let Some(b) = beyond {
                    // N = W cos θ, T = W sin θ, capacity μN.
                    assert!((b.pressing - w * theta.cos()).abs() < 1e-9 * w);
                    assert!((b.along - w * theta.sin()).abs() < 1e-9 * w);
                    assert!((b.capacity - mu * w * theta.cos()).abs() < 1e-9 * w);
                }
            }
        }
    }

    /// A block in a V-groove of faces at ±α to the horizontal, pushed sideways by
    /// Q and down by P: it rides up one face, so it is held iff
    /// Q ≤ tan(α + φ) P (the other face opens); the bound of the faces' spread
    /// is that limit exactly. With α + φ ≥ 90° the groove wedges the block
    /// against any load: no direction is found beyond the cone.
    #[test]
    fn a_v_groove_holds_up_to_its_wedge_angle() {
        let (alpha, mu) = (45f64.to_radians(), 0.3_f64);
        let faces = [[-alpha.sin(), alpha.cos()], [alpha.sin(), alpha.cos()]];
        let (m, spread) = face_direction::<D2>(faces.into_iter()).unwrap();
        assert!((m[0]).abs() < 1e-15 && (m[1] - 1.0).abs() < 1e-15);
        assert!((spread - alpha).abs() < 1e-12);
        let cone = (mu.atan() + spread).tan();
        let p = 100.0;
        let limit = (alpha + mu.atan()).tan() * p;
        assert!(beyond_friction::<D2>([limit * (1.0 - 1e-6), -p], m, cone, 1e-9).is_none());
        assert!(beyond_friction::<D2>([limit * (1.0 + 1e-6), -p], m, cone, 1e-9).is_some());
        // Pulled away: nothing holds it along the face.
        let b = beyond_friction::<D2>([1.0, 10.0], m, cone, 1e-9).unwrap();
        assert!(b.pressing < 0.0 && b.capacity == 0.0);
        // Opposite faces (a part clamped between two): no mean direction.
        assert!(face_direction::<D2>([[0.0, 1.0], [0.0, -1.0]].into_iter()).is_none());
        assert!(face_direction::<D2>(std::iter::empty()).is_none());
    }

    /// The inclined plane in 3D: a face tilted by θ about a horizontal axis
    /// of any direction holds the block iff tan θ ≤ μ, and the amounts are the
    /// plane ones (N = W cos θ, T = W sin θ).
    #[test]
    fn the_solid_inclined_plane_holds_the_block_iff_tan_theta_is_at_most_mu() {
        use crate::dim::D3;
        let mu = 0.4_f64;
        let phi = mu.atan();
        for psi in [0.0_f64, 0.7, 2.0] {
            for (theta, held) in [(phi - 1e-6, true), (phi + 1e-6, false)] {
                // Tilted about the horizontal axis (cos ψ, sin ψ, 0).
                let (s, c) = (theta.sin(), theta.cos());
                let d = [s * psi.sin(), -s * psi.cos(), c];
                let (m, spread) = face_direction::<D3>([d; 4].into_iter()).unwrap();
                assert!(spread < 1e-7, "one flat face: {spread}");
                let w = 10.0;
                let b = beyond_friction::<D3>([0.0, 0.0, -w], m, mu, 1e-9 * w);
                assert_eq!(b.is_none(), held, "ψ = {psi}, θ = {theta}");
                if let Some(b) = b {
                    assert!((b.pressing - w * c).abs() < 1e-9 * w);
                    assert!((b.along - w * s).abs() < 1e-9 * w);
                }
            }
        }
    }
}
