//! Support check: is every part held against rigid-body motion by its Dirichlet
//! conditions and its bonded coupling pairs? Each part is treated as a rigid body
//! with [`M`] motions (in 2D two translations, one rotation); every fixed DOF and every
//! bonded pair is a constraint row on those motions. The assembly is supported when
//! the constraint rows have full rank; otherwise the null space names the parts that
//! can move freely. This turns a singular stiffness into an error a user can act on.
//!
//! [`FrictionHold`] asks the question before any solve for a part (or parts
//! taken together) held along its faces by friction alone: can friction hold its
//! load at all? (The rank test cannot tell: a slipping pair keeps a stabilising
//! spring.)

use crate::assembly::{DofMap, FIXED};
use crate::coupling::{Interface, Law, PairHistory, PairState};
use crate::dim::{D2, Dim};
use crate::domain::Part;
use crate::error::{Error, Result};
use faer::{Mat, Side};
use std::f64::consts::FRAC_PI_2;

/// The constant part of the support check, computed once per model: each part's
/// frame (centre and size, so the rotation column is scaled like the others) and
/// the constraint rows of the fixed DOFs, summed into the Gram matrix `Σ r rᵀ`
/// (one pass over the nodes). [`SupportCheck::check`] then adds only the closed
/// pairs, so a check costs O(pairs) however fine the meshes.
pub struct SupportCheck {
    /// Per part: centre and size.
    frames: Vec<([f64; 2], f64)>,
    /// `Σ r rᵀ` over the fixed DOFs ([`M`] rows and columns per part).
    supports: Mat<f64>,
    /// Per part: whether a support fixes any of its DOFs.
    supported: Vec<bool>,
}

const AXES: [[f64; 2]; 2] = [[1.0, 0.0], [0.0, 1.0]];

/// Rigid-body modes per part (the dimension's).
const M: usize = D2::RIGID_MODES;

/// The entries of part `p`'s rigid-body row `r` in the Gram matrix: `(M p + m, r[m])`.
fn entries(p: usize, r: [f64; M]) -> [(usize, f64); M] {
    std::array::from_fn(|m| (M * p + m, r[m]))
}

impl SupportCheck {
    /// The frames and the supports' rows of `parts` under the DOF map `dofs`.
    pub fn new(parts: &[Part], dofs: &DofMap) -> Self {
        let frames: Vec<([f64; 2], f64)> = parts
            .iter()
            .map(|p| {
                let n = p.mesh.nodes.len() as f64;
                let c = p
                    .mesh
                    .nodes
                    .iter()
                    .fold([0.0, 0.0], |a, x| [a[0] + x[0] / n, a[1] + x[1] / n]);
                let size = p
                    .mesh
                    .nodes
                    .iter()
                    .map(|x| crate::mesh::dist(*x, c))
                    .fold(0.0, f64::max)
                    .max(1e-300);
                (c, size)
            })
            .collect();
        let np = parts.len();
        let mut check = SupportCheck {
            frames,
            supports: Mat::<f64>::zeros(M * np, M * np),
            supported: (0..np).map(|p| has_support(dofs, p)).collect(),
        };
        let mut g = Mat::<f64>::zeros(M * np, M * np);
        for (p, part) in parts.iter().enumerate() {
            for (n, x) in part.mesh.nodes.iter().enumerate() {
                let gn = dofs.node(p, n);
                for (c, axis) in AXES.iter().enumerate() {
                    if dofs.eq[D2::N * gn + c] == FIXED {
                        let r = check.row(p, *x, *axis);
                        add(&mut g, &entries(p, r));
                    }
                }
            }
        }
        // An axisymmetric part's only rigid motion is along the axis: a radial
        // translation or an in-plane rotation strains its rings (the hoop strain
        // u_r / r), so they are held whatever its supports.
        for (p, part) in parts.iter().enumerate() {
            if part.material.is_axisymmetric() {
                add(&mut g, &[(M * p, 1.0)]);
                add(&mut g, &[(M * p + 2, 1.0)]);
            }
        }
        check.supports = g;
        check
    }

    /// Rigid-body row of part `p` for a motion component along `d` at point `x`.
    fn row(&self, p: usize, x: [f64; 2], d: [f64; 2]) -> [f64; M] {
        let (c, s) = self.frames[p];
        let (rx, ry) = ((x[0] - c[0]) / s, (x[1] - c[1]) / s);
        [d[0], d[1], -ry * d[0] + rx * d[1]]
    }

    /// Checks that the parts cannot move as rigid bodies under the supports and
    /// the closed pairs in `states` (each along the directions its law
    /// stiffens). Returns an error naming every part that can.
    pub fn check(
        &self,
        parts: &[Part],
        interfaces: &[Interface],
        states: &[Vec<PairState>],
    ) -> Result<()> {
        let np = parts.len();
        let mut g = self.supports.clone();
        for (iface, st) in interfaces.iter().zip(states) {
            let (h, q) = (iface.host, iface.node_part);
            let law = iface.params();
            for (c, &s) in iface.elements.iter().zip(st) {
                // A pair constrains the directions its penalties act in: both when
                // bonded or slipping (x and y: a slipping pair keeps its stabilising
                // spring), the normal only when frictionless.
                let [k_n, k_s] = law.penalties(s);
                let directions: &[[f64; 2]] = match (k_n > 0.0, k_s > 0.0) {
                    (true, true) => &AXES,
                    (true, false) => &[c.normal],
                    (false, true) => &[[-c.normal[1], c.normal[0]]],
                    (false, false) => &[],
                };
                for &axis in directions {
                    let (rh, rq) = (self.row(h, c.position, axis), self.row(q, c.position, axis));
                    let (eq, eh) = (entries(q, rq), entries(h, rh.map(|v| -v)));
                    let both: [(usize, f64); 2 * M] =
                        std::array::from_fn(|m| if m < M { eq[m] } else { eh[m - M] });
                    add(&mut g, &both);
                }
            }
        }
        let eig = g
            .self_adjoint_eigen(Side::Lower)
            .map_err(|e| Error::Singular(format!("support check failed: {e:?}")))?;
        let s = eig.S();
        let u = eig.U();
        let lmax = (0..M * np).map(|i| s[i].abs()).fold(1.0, f64::max);
        let mut free = vec![false; np];
        for k in 0..M * np {
            if s[k] > 1e-10 * lmax {
                continue;
            }
            for (p, f) in free.iter_mut().enumerate() {
                let w: f64 = (0..M).map(|c| u[(M * p + c, k)].powi(2)).sum();
                if w > 1e-6 {
                    *f = true;
                }
            }
        }
        if free.iter().any(|&f| f) {
            Err(unsupported(
                parts,
                interfaces,
                states,
                &free,
                &self.supported,
            ))
        } else {
            Ok(())
        }
    }
}

/// Adds the outer product `Σ a b` of the sparse row `entries` to `g`.
fn add(g: &mut Mat<f64>, entries: &[(usize, f64)]) {
    for &(i, a) in entries {
        for &(j, b) in entries {
            g[(i, j)] += a * b;
        }
    }
}

/// Whether a support fixes any DOF of part `p`.
fn has_support(dofs: &DofMap, p: usize) -> bool {
    let nodes = dofs.node_offset[p]..dofs.node_offset[p + 1];
    dofs.eq[D2::N * nodes.start..D2::N * nodes.end].contains(&FIXED)
}

/// The groups of parts linked by any interface in which no part has a support
/// (`supported` per part): whatever the pairs do, each moves as one rigid body.
fn unheld_groups(n: usize, interfaces: &[Interface], supported: &[bool]) -> Vec<Vec<usize>> {
    groups(n, interfaces.iter().map(|i| (i.host, i.node_part)))
        .into_iter()
        .filter(|g| g.iter().all(|&p| !supported[p]))
        .collect()
}

/// The error naming the parts that are `free` to move. First the groups of
/// parts with no support at all (`supported` per part), whose interfaces cannot
/// help: the whole assembly, or the parts named; then every other free part
/// with how many of its coupling pairs are open in `states` (and, on a
/// frictional or frictionless face, why its pairs do not hold it).
fn unsupported(
    parts: &[Part],
    interfaces: &[Interface],
    states: &[Vec<PairState>],
    free: &[bool],
    supported: &[bool],
) -> Error {
    let quote = |g: &[usize]| {
        g.iter()
            .map(|&p| format!("'{}'", parts[p].name))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let unheld = unheld_groups(parts.len(), interfaces, supported);
    let mut clauses: Vec<String> = Vec::new();
    if unheld.len() == 1 && unheld[0].len() == parts.len() {
        clauses.push(format!(
            "the assembly has no support: no [[support]] fixes any part ({}), so it moves as a rigid body whatever its interfaces do. Add a [[support]] that holds it (x, y and a rotation)",
            quote(&unheld[0])
        ));
    } else {
        for g in &unheld {
            let linked = interfaces
                .iter()
                .any(|i| g.contains(&i.host) || g.contains(&i.node_part));
            clauses.push(match (g.len(), linked) {
                (1, false) => format!(
                    "part {} has no support and no interface: nothing holds it; add a [[support]] or an [[interface]] to a supported part",
                    quote(g)
                ),
                (1, true) => format!(
                    "part {} has no support, and its interfaces link it to no supported part: add a [[support]]",
                    quote(g)
                ),
                _ => format!(
                    "parts {} have no support, and their interfaces link them to no supported part, so they move together as a rigid body: add a [[support]] to one of them",
                    quote(g)
                ),
            });
        }
    }
    let names: Vec<String> = (0..parts.len())
        .filter(|&p| free[p] && !unheld.iter().any(|g| g.contains(&p)))
        .map(|p| {
            // Its pairs, open ones, closed ones with no tangential stiffness
            // (frictionless: sliding freely), and its Coulomb interfaces'
            // slipping pairs.
            let (mut pairs, mut open, mut sliding, mut slipping) = (0, 0, 0, 0);
            let mut frictional = false;
            let touching = interfaces
                .iter()
                .zip(states)
                .filter(|(i, _)| i.host == p || i.node_part == p);
            for (i, st) in touching {
                let law = i.params();
                frictional |= i.law == Law::Coulomb;
                pairs += st.len();
                for &s in st {
                    match s {
                        PairState::Open => open += 1,
                        PairState::Slip => slipping += 1,
                        PairState::Bonded => {}
                    }
                    if s != PairState::Open && law.penalties(s)[1] == 0.0 {
                        sliding += 1;
                    }
                }
            }
            if sliding > 0 {
                format!(
                    "'{}' ({open} of its {pairs} coupling pairs open, {sliding} closed but sliding freely: frictionless pairs carry no tangential force, so hold the part tangentially with a [[support]])",
                    parts[p].name
                )
            } else if frictional && open < pairs {
                // Free though touching on a frictional face: friction does not
                // hold it. (With every pair open it was pulled away: the plain
                // message, which says the loads should press the parts together.)
                format!(
                    "'{}' ({open} of its {pairs} coupling pairs open, {slipping} slipping: a part pushed along its faces harder than friction holds it, more than μ × the force pressing them together, has no position of rest)",
                    parts[p].name
                )
            } else {
                format!(
                    "'{}' ({open} of its {pairs} coupling pairs open)",
                    parts[p].name
                )
            }
        })
        .collect();
    if !names.is_empty() {
        clauses.push(format!(
            "part(s) {} left without support: they can move as rigid bodies. Add a [[support]], or check that the loads press the parts together",
            names.join(", ")
        ));
    }
    Error::Unsupported {
        parts: (0..parts.len())
            .filter(|&p| free[p])
            .map(|p| parts[p].name.clone())
            .collect(),
        message: clauses.join("; "),
    }
}

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
pub struct FrictionHold {
    bodies: Vec<FrictionBody>,
    /// The parts a support holds only across their faces, with the axis (0: x,
    /// 1: y) of every DOF their supports fix ([`FrictionHold::check_settled`]).
    across: Vec<(FrictionBody, usize)>,
    /// Whether every part without a support that touches a `coulomb`
    /// interface is in a body checked (see [`FrictionHold::judges_all`]).
    judges_all: bool,
}

/// A body held along its faces by friction alone (see [`FrictionHold`]).
struct FrictionBody {
    /// Its parts' names.
    parts: Vec<String>,
    /// Its parts' global nodes (their DOFs are 2g and 2g + 1).
    nodes: Vec<std::ops::Range<usize>>,
    /// The interfaces holding it, with the sign of the direction their pairs
    /// push it (+1: it holds their node side).
    holding: Vec<(usize, f64)>,
    /// The interfaces holding it, their names quoted, for messages.
    interfaces: String,
    /// Number of their coupling pairs.
    pairs: usize,
    /// Unit mean direction m in which its faces push it.
    normal: [f64; 2],
    /// Largest friction coefficient of those interfaces.
    friction: f64,
    /// Largest angle ε between a pair's direction and m (radians).
    spread: f64,
}

impl FrictionHold {
    /// The bodies of `parts` that friction alone holds along their faces,
    /// under the supports of `dofs` and the interfaces `interfaces`.
    ///
    /// An axisymmetric model has no such body to judge: a ring's pairs push it
    /// radially from all sides, their resultant is along the axis alone, and the
    /// cone of one direction does not bound it (the search decides).
    pub fn new(parts: &[Part], interfaces: &[Interface], dofs: &DofMap) -> Self {
        if parts.iter().any(|p| p.material.is_axisymmetric()) {
            return FrictionHold {
                bodies: Vec::new(),
                across: Vec::new(),
                judges_all: false,
            };
        }
        let free: Vec<bool> = (0..parts.len()).map(|p| !has_support(dofs, p)).collect();
        // A part linked to no supported part at all is not held by friction
        // against anything: the support check names it (no support), and
        // friction is not blamed.
        let supported: Vec<bool> = free.iter().map(|f| !f).collect();
        let mut unheld = vec![false; parts.len()];
        for p in unheld_groups(parts.len(), interfaces, &supported).concat() {
            unheld[p] = true;
        }
        // Candidate bodies: single parts, then the groups (sorted, no repeats).
        let mut candidates: Vec<Vec<usize>> = (0..parts.len())
            .filter(|&p| free[p] && !unheld[p])
            .map(|p| vec![p])
            .collect();
        for bonded_only in [false, true] {
            let linked = |i: &Interface| {
                free[i.host]
                    && free[i.node_part]
                    && (!bonded_only || matches!(i.law, Law::Rigid | Law::Contact))
            };
            let links = interfaces
                .iter()
                .filter(|i| linked(i))
                .map(|i| (i.host, i.node_part));
            for group in groups(parts.len(), links) {
                if group.len() > 1
                    && group.iter().all(|&p| free[p] && !unheld[p])
                    && !candidates.contains(&group)
                {
                    candidates.push(group);
                }
            }
        }
        let bodies: Vec<FrictionBody> = candidates
            .into_iter()
            .filter_map(|body| friction_body(parts, interfaces, dofs, &body))
            .collect();
        // Parts a support holds only across their faces: every DOF their
        // supports fix is along one axis, the faces' mean direction, so along
        // the faces only friction holds them (a block held in y on a face in x).
        let across: Vec<(FrictionBody, usize)> = (0..parts.len())
            .filter(|&p| !free[p])
            .filter_map(|p| {
                let axis = support_axis(dofs, p)?;
                let body = friction_body(parts, interfaces, dofs, &[p])?;
                (body.normal[axis].abs() >= 1.0 - 1e-12).then_some((body, axis))
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
    /// 2g and 2g + 1 for global node g). `slack` is the force by which the law
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
            let load = body.nodes.iter().flat_map(|r| r.clone()).fold([0.0, 0.0], |a, g| {
                [a[0] + lambda * f_ext[2 * g], a[1] + lambda * f_ext[2 * g + 1]]
            });
            let cone = (body.friction.atan() + body.spread).tan();
            let margin = body.pairs as f64 * slack * (1.0 + cone);
            let Some(limit) = beyond_friction(load, body.normal, cone, margin) else {
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
        interfaces: &[Interface],
        dofs: &DofMap,
        f_ext: &[f64],
        lambda: f64,
        slack: f64,
        u: &[f64],
        states: &[Vec<PairState>],
        history: &[Vec<PairHistory>],
        when: impl Fn() -> String,
    ) -> Result<()> {
        let mut held = Vec::new();
        let mut messages = Vec::new();
        for (body, axis) in &self.across {
            let load = body.nodes.iter().flat_map(|r| r.clone()).fold([0.0, 0.0], |a, g| {
                [a[0] + lambda * f_ext[2 * g], a[1] + lambda * f_ext[2 * g + 1]]
            });
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
            let along = (load[0] * m[1] - load[1] * m[0]).abs();
            let cone = (body.friction.atan() + body.spread).tan();
            let capacity = cone * pressing.max(0.0);
            let margin = body.pairs as f64 * slack * (1.0 + cone);
            if along <= capacity + margin {
                continue;
            }
            let part = &body.parts[0];
            let by_loads = -(load[0] * m[0] + load[1] * m[1]);
            messages.push(format!(
                "'{part}' at {}: its supports fix only {} (across its faces), so along its faces only friction holds it; in the least-violating state the contact search settled on, its faces press it with {:.4e} (its loads with {:.4e}, its supports with the rest), and its loads push it along them with {:.4e}, but friction (μ = {} on {}) holds at most {:.4e} × {:.4e} = {:.4e}",
                when(),
                ["x", "y"][*axis],
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

/// The body of the parts `body` held along its faces by friction alone, if
/// every interface between it and the rest is frictional (`coulomb`, or
/// `frictionless` beside one), its faces push it one way and the friction
/// cone does not reach 90° (see [`FrictionHold`]).
fn friction_body(
    parts: &[Part],
    interfaces: &[Interface],
    dofs: &DofMap,
    body: &[usize],
) -> Option<FrictionBody> {
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
            .map(move |c| [sign * c.normal[0], sign * c.normal[1]])
    });
    let (normal, spread) = face_direction(directions)?;
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

/// The one axis (0: x, 1: y) along which the supports of part `p` fix its
/// DOFs, if they fix some and all along the same axis.
fn support_axis(dofs: &DofMap, p: usize) -> Option<usize> {
    let (a, b) = (D2::N * dofs.node_offset[p], D2::N * dofs.node_offset[p + 1]);
    let first = dofs.fixed.partition_point(|&(d, _)| d < a);
    let last = dofs.fixed.partition_point(|&(d, _)| d < b);
    let mut axes = dofs.fixed[first..last].iter().map(|&(d, _)| d % D2::N);
    let axis = axes.next()?;
    axes.all(|c| c == axis).then_some(axis)
}

/// The connected groups of `n` parts under the `links` (pairs of parts: an
/// interface's host and node part), each sorted, in the order of their smallest
/// part.
fn groups(n: usize, links: impl Iterator<Item = (usize, usize)>) -> Vec<Vec<usize>> {
    let mut root: Vec<usize> = (0..n).collect();
    fn find(root: &mut [usize], mut p: usize) -> usize {
        while root[p] != p {
            root[p] = root[root[p]];
            p = root[p];
        }
        p
    }
    for (a, b) in links {
        let (a, b) = (find(&mut root, a), find(&mut root, b));
        root[a.max(b)] = a.min(b);
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut index = vec![usize::MAX; n];
    for p in 0..n {
        let r = find(&mut root, p);
        if index[r] == usize::MAX {
            index[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[index[r]].push(p);
    }
    groups
}

/// The unit mean m of `directions` and the largest angle ε between one of them
/// and m; `None` when there are none or they cancel (a nonzero sum means at
/// least one).
fn face_direction(directions: impl Iterator<Item = [f64; 2]> + Clone) -> Option<([f64; 2], f64)> {
    let sum = directions
        .clone()
        .fold([0.0, 0.0], |a, d| [a[0] + d[0], a[1] + d[1]]);
    let len = sum[0].hypot(sum[1]);
    if len.is_nan() || len <= 0.0 {
        return None;
    }
    let m = [sum[0] / len, sum[1] / len];
    let spread = directions
        .map(|d| (d[0] * m[1] - d[1] * m[0]).abs().atan2(d[0] * m[0] + d[1] * m[1]))
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
fn beyond_friction(f: [f64; 2], m: [f64; 2], cone: f64, margin: f64) -> Option<BeyondFriction> {
    let pressing = -(f[0] * m[0] + f[1] * m[1]);
    let along = (f[0] * m[1] - f[1] * m[0]).abs();
    let capacity = cone * pressing.max(0.0);
    (along > capacity + margin).then_some(BeyondFriction {
        pressing,
        along,
        capacity,
    })
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
                let (m, spread) = face_direction([d; 7].into_iter()).unwrap();
                assert!(spread < 1e-12, "one flat face has no spread: {spread}");
                let cone = (mu.atan() + spread).tan();
                let w = 1234.5;
                let beyond = beyond_friction([0.0, -w], m, cone, 1e-9 * w);
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

    /// The groups of parts linked by interfaces: 0–1–2 and 3–4 linked, 5 alone.
    #[test]
    fn groups_are_the_connected_parts() {
        let links = [(2, 1), (4, 3), (0, 1)];
        assert_eq!(groups(6, links.into_iter()), vec![vec![0, 1, 2], vec![3, 4], vec![5]]);
        assert_eq!(groups(2, std::iter::empty()), vec![vec![0], vec![1]]);
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
        let (m, spread) = face_direction(faces.into_iter()).unwrap();
        assert!((m[0]).abs() < 1e-15 && (m[1] - 1.0).abs() < 1e-15);
        assert!((spread - alpha).abs() < 1e-12);
        let cone = (mu.atan() + spread).tan();
        let p = 100.0;
        let limit = (alpha + mu.atan()).tan() * p;
        assert!(beyond_friction([limit * (1.0 - 1e-6), -p], m, cone, 1e-9).is_none());
        assert!(beyond_friction([limit * (1.0 + 1e-6), -p], m, cone, 1e-9).is_some());
        // Pulled away: nothing holds it along the face.
        let b = beyond_friction([1.0, 10.0], m, cone, 1e-9).unwrap();
        assert!(b.pressing < 0.0 && b.capacity == 0.0);
        // Opposite faces (a part clamped between two): no mean direction.
        assert!(face_direction([[0.0, 1.0], [0.0, -1.0]].into_iter()).is_none());
        assert!(face_direction(std::iter::empty()).is_none());
    }
}
