//! The summary's bookkeeping: a run's [`Summary`] started from its problem and
//! brought up to date with each converged increment (law violations, warnings,
//! interfaces, largest displacement, reactions, equilibrium).

use super::history::{HistoryRow, InterfaceHistory, ProbeHistory, ReactionHistory};
use super::pairs::PairRow;
use super::summary::{
    IncrementStep, InterfaceSummary, MaxDisplacement, PartSummary, ProbeSummary, Reaction,
    RunStatus, SettledPair, StepSummary, Summary, Timings, Tolerances, ViolationRecord, Warning,
};
use super::{Problem, ResultsDim};
use crate::coupling::{Interface, Law, PairState, ViolationKind};
use crate::dim::{Dim, Tangent};
use crate::dofs::DofMap;
use crate::domain::{Scheme, Step};
use crate::mesh::{CurvedBoundary, MeshCell};
use crate::solve::nonlinear::{IncrementResult, RESIDUAL_WARN};
use std::path::PathBuf;

/// What a summary states of its problem besides [`Problem`]: read from the model
/// by the analysis.
pub(crate) struct Heading<'a> {
    /// The model's title.
    pub title: String,
    /// The problem file.
    pub problem: PathBuf,
    /// The refinement factor.
    pub refine: usize,
    /// The load steps (one, named, without `[[step]]` tables).
    pub steps: Vec<Step>,
    /// Warnings about the model as meshed (increment 0).
    pub warnings: Vec<Warning>,
    /// Advice about the model as a whole (noted at increment 0).
    pub notes: Vec<String>,
    /// Why the proportional-load shortcuts are off (`None`: on).
    pub shortcut_off: Option<String>,
    /// The preparation's timings so far (meshing, pair search, its CPU time).
    pub setup: &'a Timings,
}

impl Summary {
    /// The summary of `p` before its first increment: status `running`, the
    /// problem as `h` states it, the tolerances, parts and steps.
    pub(crate) fn new<D: ResultsDim>(p: &Problem<'_, D>, h: Heading<'_>) -> Summary {
        Summary {
            status: RunStatus::Running,
            error: None,
            warnings: h.warnings,
            violations: Vec::new(),
            max_violation: 0.0,
            tolerances: Tolerances {
                tension: p.settings.force_tolerance,
                penetration: p.settings.gap_tolerance,
                max_violation: p.settings.max_violation,
                residual_warn: RESIDUAL_WARN,
                residual_fail: p.settings.max_residual,
            },
            title: h.title,
            problem: h.problem,
            refine: h.refine,
            scheme: p.settings.scheme,
            unknowns: p.dofs.n_eq,
            matrix_nonzeros: 0,
            factor_nonzeros: 0,
            parts: p
                .parts
                .iter()
                .map(|p| {
                    let count = |kind: &str| {
                        (p.mesh.elements.iter())
                            .filter(|e| e.kind_name() == kind)
                            .count()
                    };
                    PartSummary {
                        name: p.name.clone(),
                        nodes: p.mesh.nodes.len(),
                        elements: p.mesh.elements.len(),
                        t3: count("T3"),
                        q4: count("Q4"),
                        tet4: count("TET4"),
                        hex8: count("HEX8"),
                    }
                })
                .collect(),
            interfaces: Vec::new(),
            increments: p.settings.increments,
            converged_increments: 0,
            iterations: Vec::new(),
            iteration_history: Vec::new(),
            factorizations: 0,
            low_rank_updates: 0,
            first_factorization_seconds: None,
            max_displacement: MaxDisplacement::default(),
            reactions: Vec::new(),
            applied: vec![0.0; D::N],
            equilibrium_error: 0.0,
            residual: 0.0,
            proportional_shortcut: h.shortcut_off.is_none(),
            proportional_shortcut_off: h.shortcut_off,
            steps: h
                .steps
                .into_iter()
                .map(|s| StepSummary {
                    name: s.name,
                    increments: s.increments,
                })
                .collect(),
            increment_steps: Vec::new(),
            probes: p
                .probes
                .iter()
                .map(|pr| {
                    let part = &p.parts[pr.part];
                    let x = part.mesh.nodes[pr.node];
                    let x = x.as_ref();
                    ProbeSummary {
                        name: pr.name.clone(),
                        part: part.name.clone(),
                        node: pr.node,
                        element: pr.element,
                        at: pr.at.as_ref().to_vec(),
                        x: x[0],
                        y: x[1],
                        z: x.get(2).copied(),
                    }
                })
                .collect(),
            history: Vec::new(),
            fixed_point_iterations: Vec::new(),
            augmented_penetration: 0.0,
            // Advice about the model as a whole (volumetric locking) is noted
            // at increment 0, before any increment.
            notes: h
                .notes
                .into_iter()
                .map(|message| Warning {
                    increment: 0,
                    message,
                })
                .collect(),
            peak_memory_bytes: None,
            peak_over_factor: None,
            solve_flops: 0.0,
            linear_solver: None,
            total_over_factorization: None,
            threads: rayon::current_num_threads(),
            timings: Timings {
                meshing: h.setup.meshing,
                pair_search: h.setup.pair_search,
                setup_cpu: h.setup.setup_cpu,
                ..Default::default()
            },
        }
    }

    /// Records converged increment `inc` of `p` (of the load step named `step`,
    /// with its pair rows `rows`): its step, iterations, law violations and
    /// warnings, the interfaces' pair counts and extents, the largest
    /// displacement, the reactions, the applied load and the equilibrium error.
    pub(crate) fn record_increment<D: ResultsDim>(
        &mut self,
        p: &Problem<'_, D>,
        inc: &IncrementResult<D>,
        rows: &[PairRow],
        step: String,
    ) {
        let s = self;
        s.converged_increments = inc.index;
        s.increment_steps.push(IncrementStep {
            increment: inc.index,
            step,
            load_factor: inc.lambda,
            time: inc.time,
        });
        s.record_violations(p, inc);
        s.iterations.push(inc.iterations);
        s.iteration_history.push(inc.history.clone());
        s.residual = inc.residual;
        s.interfaces = p
            .interfaces
            .iter()
            .map(|iface| {
                let mine: Vec<&PairRow> =
                    rows.iter().filter(|r| r.interface == iface.name).collect();
                let bonded = mine.iter().filter(|r| r.state == PairState::Bonded).count();
                InterfaceSummary {
                    name: iface.name.clone(),
                    host: p.parts[iface.host].name.clone(),
                    node_part: p.parts[iface.node_part].name.clone(),
                    law: iface.law,
                    coupling: iface.coupling,
                    c_n: iface.c_n,
                    c_s: iface.c_s,
                    pairs: mine.len(),
                    bonded,
                    open: mine.iter().filter(|r| r.state == PairState::Open).count(),
                    settled: mine
                        .iter()
                        .filter(|r| r.settled)
                        .map(|r| SettledPair {
                            node: r.node,
                            x: r.x,
                            y: r.y,
                            z: r.z,
                            state: r.state,
                            force_n: r.force_n,
                        })
                        .collect(),
                    violations: mine.iter().filter(|r| r.breaks_law()).count(),
                    max_penetration: mine.iter().map(|r| -r.gap).fold(0.0, f64::max),
                    total_force_n: mine.iter().map(|r| r.force_n).sum(),
                    max_projection_distance: iface.max_projection_distance,
                    bonded_extent: bonded_extent(&mine),
                    friction: iface.friction,
                    enforcement: iface.enforcement,
                    slip: mine.iter().filter(|r| r.state == PairState::Slip).count(),
                    unpaired: iface.unpaired,
                    max_pressure: mine.iter().map(|r| r.pressure).fold(0.0, f64::max),
                    max_shear: (mine.iter())
                        .map(|r| r.shear_magnitude())
                        .fold(0.0, f64::max),
                    contact_extent: contact_extent(&mine),
                    contact_length: contact_extent(&mine).map_or(0.0, |[a, b]| {
                        let d: Vec<f64> = b.iter().zip(&a).map(|(b, a)| b - a).collect();
                        D::length(&d)
                    }),
                    max_slip_ratio: iface
                        .elements
                        .iter()
                        .zip(rows.iter().filter(|r| r.interface == iface.name))
                        .map(|(c, r)| r.tangential_jump() / c.edge_length.max(f64::MIN_POSITIVE))
                        .fold(0.0, f64::max),
                    resultant: resultant(&mine),
                    contact_area: (D::N == 3).then(|| {
                        (iface.elements.iter())
                            .zip(rows.iter().filter(|r| r.interface == iface.name))
                            .filter(|(_, r)| r.state != PairState::Open)
                            .map(|(c, _)| c.tributary)
                            .sum()
                    }),
                }
            })
            .collect();
        s.fixed_point_iterations.push(inc.fixed_point_iterations);
        s.augmented_penetration = inc.augmented_error;
        for i in &s.interfaces {
            let noted = s
                .notes
                .iter()
                .any(|n| n.message.contains(&format!("'{}'", i.name)));
            if i.max_slip_ratio > 0.5 && i.law != Law::Rigid && !noted {
                s.notes.push(Warning {
                    increment: inc.index,
                    message: format!(
                        "interface '{}': a pair's tangential jump reaches {:.2} × its host edge's length; the pairs and normals are fixed in the reference configuration (geometrically linear), which assumes sliding small against a host edge",
                        i.name, i.max_slip_ratio
                    ),
                });
            }
        }
        if inc.friction_continuation {
            s.notes.push(Warning {
                increment: inc.index,
                message: format!(
                    "the search from the contact states it started with found no state satisfying the law; its states were found from the same start with every friction coefficient scaled by {} and then 1 (a continuation in μ, {} solves in all)",
                    crate::solve::nonlinear::CONTINUATION.map(|f| f.to_string()).join(", "),
                    inc.iterations,
                ),
            });
        }
        // Maximum displacement.
        let best = largest_magnitude(p.dofs, &inc.u);
        let (part, n) = p.dofs.locate(best.1);
        let x = p.parts[part].mesh.nodes[n];
        let x = x.as_ref();
        s.max_displacement = MaxDisplacement {
            value: best.0,
            x: x[0],
            y: x[1],
            z: x.get(2).copied(),
            part: p.parts[part].name.clone(),
            node: n,
        };
        let r = p.reactions(inc);
        s.reactions = p
            .supports
            .iter()
            .zip(&r)
            .map(|(sup, r)| {
                let r = r.as_ref();
                Reaction {
                    support: sup.name.clone(),
                    fx: r[0],
                    fy: r[1],
                    fz: r.get(2).copied(),
                }
            })
            .collect();
        // The summary states a model's forces by their `D::N` components.
        let mut applied = vec![0.0; D::N];
        for (d, f) in inc.f_ext.iter().enumerate() {
            applied[d % p.dofs.per_node()] += f;
        }
        let mut total: Vec<f64> = (0..D::N)
            .map(|c| applied[c] + r.iter().map(|r| r.as_ref()[c]).sum::<f64>())
            .collect();
        // In an axisymmetric model the forces are totals over the ring: their
        // radial sums balance through the hoop stresses (a ring's radial
        // resultant is zero), so statics checks the axial direction only.
        if p.parts.iter().any(|p| p.material.is_axisymmetric()) {
            total[0] = 0.0;
        }
        let scale = D::length(&applied);
        s.equilibrium_error = if scale > 0.0 {
            D::length(&total) / scale
        } else {
            0.0
        };
        s.applied = applied;
        s.record_history(p, inc, rows);
    }

    /// Adds increment `inc`'s row to the history (after its step, reactions and
    /// interfaces are recorded): reactions, each interface's Σ f_n, Σ f_s,
    /// contact length and largest pressure, each probe's displacement.
    fn record_history<D: ResultsDim>(
        &mut self,
        p: &Problem<'_, D>,
        inc: &IncrementResult<D>,
        rows: &[PairRow],
    ) {
        let step = self
            .increment_steps
            .last()
            .map_or(String::new(), |s| s.step.clone());
        let row = HistoryRow {
            increment: inc.index,
            step,
            step_index: inc.step + 1,
            load_factor: inc.lambda,
            time: inc.time,
            reactions: (self.reactions.iter())
                .map(|r| ReactionHistory {
                    support: r.support.clone(),
                    fx: r.fx,
                    fy: r.fy,
                    fz: r.fz,
                })
                .collect(),
            interfaces: (self.interfaces.iter().zip(p.interfaces))
                .map(|(i, iface)| {
                    let resultant = |k: usize| i.resultant.as_ref().map(|r| r[k]);
                    InterfaceHistory {
                        interface: i.name.clone(),
                        force_n: i.total_force_n,
                        force_s: tangential_sum(iface, rows),
                        fx: resultant(0),
                        fy: resultant(1),
                        fz: resultant(2),
                        contact_length: i.contact_length,
                        max_pressure: i.max_pressure,
                    }
                })
                .collect(),
            probes: (p.probes.iter())
                .map(|pr| {
                    let d = pr.displacement(&inc.u, p.dofs.node_offset[pr.part]);
                    let d = d.as_ref();
                    ProbeHistory {
                        probe: pr.name.clone(),
                        ux: d[0],
                        uy: d[1],
                        uz: d.get(2).copied(),
                    }
                })
                .collect(),
        };
        self.history.push(row);
    }

    /// Adds the increment's law violations and precision warning to the summary
    /// (with `implex`, those of the final increment only: its early increments lag
    /// by design).
    fn record_violations<D: ResultsDim>(&mut self, p: &Problem<'_, D>, inc: &IncrementResult<D>) {
        let s = self;
        let settings = p.settings;
        if settings.scheme == Scheme::Implex && inc.index < settings.increments {
            return;
        }
        for v in &inc.violations {
            let iface = &p.interfaces[v.interface];
            let c = &iface.elements[v.pair];
            let relative = if inc.load_scale > 0.0 {
                v.force / inc.load_scale
            } else {
                0.0
            };
            s.max_violation = s.max_violation.max(relative);
            s.violations.push(ViolationRecord {
                increment: inc.index,
                interface: iface.name.clone(),
                node: c.node,
                x: c.position.as_ref()[0],
                y: c.position.as_ref()[1],
                z: c.position.as_ref().get(2).copied(),
                kind: v.kind,
                amount: v.amount,
                force: v.force,
                relative,
                settled: inc.settled.binary_search(&(v.interface, v.pair)).is_ok(),
            });
        }
        if let Some(worst) = inc
            .violations
            .iter()
            .max_by(|a, b| a.force.total_cmp(&b.force))
        {
            let iface = &p.interfaces[worst.interface];
            let c = &iface.elements[worst.pair];
            // Pairs, not violations: a stick pair that pulls while carrying
            // shear breaks the law twice (tension and friction) but is one pair.
            let mut pairs: Vec<(usize, usize)> = inc
                .violations
                .iter()
                .map(|v| (v.interface, v.pair))
                .collect();
            pairs.sort_unstable();
            pairs.dedup();
            let why = if inc.settled.is_empty() {
                "lagged states of the implex scheme"
            } else {
                "no state satisfies the law; settled on the least-violating pattern"
            };
            s.warnings.push(Warning {
                increment: inc.index,
                message: format!(
                    "{} pair(s) break the contact law ({why}); the worst, node {} at ({}) of interface '{}', {} {:.4e} ({:.2e} of the load scale)",
                    pairs.len(),
                    c.node,
                    (c.position.as_ref().iter())
                        .map(|v| v.to_string())
                        .collect::<Vec<_>>()
                        .join(", "),
                    iface.name,
                    match worst.kind {
                        ViolationKind::Tension => "pulls with",
                        ViolationKind::Penetration => "penetrates by",
                        ViolationKind::Friction => "sticks beyond μ|f_n| by",
                        ViolationKind::Slip => "slips off μ|f_n| by",
                    },
                    worst.amount,
                    worst.force / inc.load_scale.max(f64::MIN_POSITIVE)
                ),
            });
        }
        let imbalance = inc.residual.max(inc.balance);
        if imbalance > RESIDUAL_WARN {
            s.warnings.push(Warning {
                increment: inc.index,
                message: format!(
                    "the out-of-balance force is {imbalance:.1e} of the balance scale {:.4e} (above {RESIDUAL_WARN:.0e}; the largest at a free DOF, or the reactions against the applied load; the scale is the largest of the load (or the support reactions), the pair forces and 1e-4 × the softest part's {} × the largest displacement): the solution has lost accuracy; a penalty far above {et} (more than about 1e7 × {et}) is the usual cause",
                    inc.balance_scale,
                    if D::N == 3 { "E × 1 (unit length)" } else { "E·t" },
                    et = if D::N == 3 { "E·h (h the face size)" } else { "E·t" },
                ),
            });
        }
    }
}

/// The warnings about the model as meshed (increment 0): each curved
/// boundary `kept` (part name, boundary) of a part refined `refine` times from a
/// given mesh, whose polygon `--refine` kept.
pub(crate) fn kept_polygon_warnings(
    kept: &[(String, CurvedBoundary)],
    refine: usize,
) -> Vec<Warning> {
    kept.iter()
        .map(|(part, b)| Warning {
            increment: 0,
            message: format!(
                "part '{part}', boundary '{}': a curved boundary (its consecutive edges turn by up to {:.3}°) refined by --refine {}: the new nodes lie on the given mesh's straight edges, so the geometry stays its polygon, not the curve (a contact pressure there alternates between the new mid-edge nodes and the given ones); mesh the curve finer in the mesh generator instead",
                b.name,
                b.largest_turn.to_degrees(),
                refine
            ),
        })
        .collect()
}

/// The tangential sum of the history of interface `iface` over its pair
/// `rows` (the rows of every interface, in order): in a plane model Σ f_s
/// along each pair's s; in a solid model the magnitude of the sum of the
/// pairs' tangential force vectors in global components (each
/// `force_s t₁ + force_t2 t₂` of its own frame), whatever the tangents.
fn tangential_sum<D: ResultsDim>(iface: &Interface<D>, rows: &[PairRow]) -> f64 {
    let mine = || rows.iter().filter(|r| r.interface == iface.name);
    if D::Tangent::COMPONENTS == 1 {
        return mine().map(|r| r.force_s).sum();
    }
    let mut sum = vec![0.0; D::N];
    for (c, r) in iface.elements.iter().zip(mine()) {
        let mut t = D::Tangent::default();
        t.set_component(0, r.force_s);
        t.set_component(1, r.force_t2.unwrap_or(0.0));
        let v = D::to_global(&c.frame, 0.0, t);
        for (s, v) in sum.iter_mut().zip(v.as_ref()) {
            *s += v;
        }
    }
    D::length(&sum)
}

/// Rows ordered by x, then y (then z).
fn by_x(a: &&&PairRow, b: &&&PairRow) -> std::cmp::Ordering {
    (a.x.total_cmp(&b.x))
        .then(a.y.total_cmp(&b.y))
        .then(a.z.unwrap_or(0.0).total_cmp(&b.z.unwrap_or(0.0)))
}

/// The positions of the closed (bonded or slipping) pairs with the smallest and
/// the largest x (then y, z); `None` when no pair is closed.
fn contact_extent(rows: &[&PairRow]) -> Option<[Vec<f64>; 2]> {
    let closed = || rows.iter().filter(|r| r.state.is_closed());
    match (closed().min_by(by_x), closed().max_by(by_x)) {
        (Some(a), Some(b)) => Some([a.position(), b.position()]),
        _ => None,
    }
}

/// The positions of the bonded pairs with the smallest and the largest x (then
/// y, z): the ends of the contact zone; `None` when no pair is bonded.
fn bonded_extent(rows: &[&PairRow]) -> Option<[Vec<f64>; 2]> {
    let bonded = || rows.iter().filter(|r| r.state == PairState::Bonded);
    match (bonded().min_by(by_x), bonded().max_by(by_x)) {
        (Some(a), Some(b)) => Some([a.position(), b.position()]),
        _ => None,
    }
}

/// The resultant (x, y, z) of the pairs' forces on the node part, when the
/// rows state them in global components (a solid model); `None` otherwise.
fn resultant(rows: &[&PairRow]) -> Option<Vec<f64>> {
    let mut sum = vec![0.0; 3];
    for r in rows {
        for (s, f) in sum.iter_mut().zip([r.force_x?, r.force_y?, r.force_z?]) {
            *s += f;
        }
    }
    (!rows.is_empty()).then_some(sum)
}

/// The largest magnitude of a node's displacement (its `D::N` components as
/// `dofs` numbers them) over the nodes g of `u` and the first node reaching it: found by the squared magnitudes (a product per node,
/// no `hypot`: 0.03 s per increment at 4 M unknowns), then measured ([`Dim::length`]).
/// Where the squares leave the normal range (magnitudes beyond 1e154 or below
/// 1e-154, or no displacement at all) `hypot` is taken at every node.
fn largest_magnitude<D: Dim>(_dofs: &DofMap<D>, u: &[f64]) -> (f64, usize) {
    fn first_largest<D: Dim>(u: &[f64], magnitude: impl Fn(&[f64]) -> f64) -> (f64, usize) {
        let mut best = (0.0, 0usize);
        for (g, v) in u.chunks_exact(D::N).enumerate() {
            let m = magnitude(v);
            if m > best.0 {
                best = (m, g);
            }
        }
        best
    }
    let (square, g) = first_largest::<D>(u, |v| D::dot(v, v));
    if square.is_finite() && square >= f64::MIN_POSITIVE {
        (D::length(&u[D::dof(g, 0)..D::dof(g + 1, 0)]), g)
    } else {
        first_largest::<D>(u, |v| D::length(v))
    }
}

#[cfg(test)]
mod tests {
    use super::largest_magnitude;
    use crate::dim::{D2, D3};
    use crate::dofs::DofMap;

    /// The largest nodal displacement and its node: the first of equal ones,
    /// (0, 0) for no displacement or none at all, and magnitudes whose squares
    /// overflow (5e200) or underflow (5e-200) still compared exactly.
    #[test]
    fn largest_magnitude_finds_the_first_largest_node() {
        let plane = DofMap::<D2>::numbered(&[3], &[]);
        let largest_magnitude = |u: &[f64]| largest_magnitude(&plane, u);
        assert_eq!(
            largest_magnitude(&[3.0, 4.0, 0.0, -5.0, 1.0, 1.0]),
            (5.0, 0)
        );
        assert_eq!(largest_magnitude(&[0.0, 0.0, -0.0, 0.0]), (0.0, 0));
        assert_eq!(largest_magnitude(&[]), (0.0, 0));
        let big = [3e200, 0.0, 3e200, 4e200, 1.0, 0.0];
        assert_eq!(largest_magnitude(&big), (3e200f64.hypot(4e200), 1));
        let tiny = [1e-200, 0.0, 3e-200, 4e-200, 0.0, 2e-200];
        assert_eq!(largest_magnitude(&tiny), (3e-200f64.hypot(4e-200), 1));
        // In 3D a node's three components: |(2, 3, 6)| = 7 at node 1.
        let solid = DofMap::<D3>::numbered(&[2], &[]);
        let u = [1.0, 2.0, 2.0, -2.0, 3.0, 6.0];
        assert_eq!(super::largest_magnitude(&solid, &u), (7.0, 1));
    }
}
