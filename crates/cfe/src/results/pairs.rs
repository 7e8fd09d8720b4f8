//! The rows of `pairs.csv`: one coupling pair at one increment — its state, jumps,
//! gaps and forces on the node part — and their evaluation from an increment.

use super::{Problem, ResultsDim};
use crate::coupling::{Law, PairState, ViolationKind};
use crate::dim::Tangent;
use crate::solve::nonlinear::IncrementResult;
use serde::Serialize;

/// One coupling pair at one increment, as written to `pairs.csv`.
#[derive(Debug, Clone, Serialize)]
pub struct PairRow {
    /// Interface name.
    pub interface: String,
    /// Coupling node (index in the node part).
    pub node: usize,
    /// Reference position x of the pair: with the node coupling, the coupling
    /// node's projection on its host edge (where the node is placed; with a search
    /// distance the node stays where it is meshed, |g₀| away); with the segment
    /// coupling, the coupling node's own position.
    #[serde(serialize_with = "plain")]
    pub x: f64,
    /// Reference position y of the pair (as `x`).
    #[serde(serialize_with = "plain")]
    pub y: f64,
    /// Reference position z of the pair (as `x`; a solid model only, absent
    /// from a plane model's rows).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub z: Option<f64>,
    /// Host element (index in the host part).
    pub host_element: usize,
    /// `bonded` or `open`.
    pub state: PairState,
    /// Normal jump `[[u_n]]` (> 0: the faces separate).
    #[serde(serialize_with = "sci")]
    pub gap_n: f64,
    /// Tangential jump `[[u_s]]` (in 3D its component along the frame's t₁).
    #[serde(serialize_with = "sci")]
    pub slip_s: f64,
    /// The tangential jump's component along t₂ (a solid model only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slip_t2: Option<f64>,
    /// Normal force on the node part (> 0: the faces press together).
    #[serde(serialize_with = "sci")]
    pub force_n: f64,
    /// Tangential force on the node part along s (in 3D along t₁).
    #[serde(serialize_with = "sci")]
    pub force_s: f64,
    /// Tangential force on the node part along t₂ (a solid model only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub force_t2: Option<f64>,
    /// The force on the node part in global components x, y, z (a solid model
    /// only; a plane row states it by its normal and tangential parts).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub force_x: Option<f64>,
    /// See `force_x`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub force_y: Option<f64>,
    /// See `force_x`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub force_z: Option<f64>,
    /// State fixed against the law by the active-set scheme to settle a cycle.
    pub settled: bool,
    /// Every way the pair breaks its law, as the law check found them and
    /// `summary.json` lists them (the normal law first): none (empty), one
    /// (`tension`, `penetration`, `friction`, `slip`), or a stick pair that pulls
    /// while carrying shear, `tension;friction` (the only pair the law breaks
    /// twice).
    #[serde(serialize_with = "kinds")]
    pub violation: Vec<ViolationKind>,
    /// Each violation's amount, in the order of `violation`: the tensile force,
    /// the penetration depth, the friction excess over μ f_n (`0e0` when none;
    /// `a;b` for two).
    #[serde(serialize_with = "amounts")]
    pub violation_amount: Vec<f64>,
    /// Initial normal gap g₀ (0 unless paired within a search distance).
    #[serde(serialize_with = "sci")]
    pub gap0: f64,
    /// Current normal gap g₀ + `[[u_n]]` (< 0: penetration).
    #[serde(serialize_with = "sci")]
    pub gap: f64,
    /// Slip not carried elastically: the plastic slip s_p of a closed pair with
    /// friction (0 for the seed's stick law), the tangential jump of an open or
    /// frictionless pair.
    #[serde(serialize_with = "sci")]
    pub slip: f64,
    /// That slip's component along t₂ (a solid model only; `slip` is along t₁).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slip_t2_plastic: Option<f64>,
    /// Contact pressure, a stress: `force_n` / (tributary length × the node part's
    /// thickness t) (> 0 in compression; `coupling::traction`).
    #[serde(serialize_with = "sci")]
    pub pressure: f64,
    /// Shear traction, a stress: `force_s` / (tributary length × t) (in 3D
    /// along t₁, over the tributary area).
    #[serde(serialize_with = "sci")]
    pub shear: f64,
    /// Shear traction along t₂ (a solid model only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shear_t2: Option<f64>,
    /// Tributary length of the coupling node on the node part's face (with segment
    /// coupling, its share of the face m_a = ∫ N_a ds).
    #[serde(serialize_with = "sci")]
    pub tributary: f64,
    /// With segment coupling, the node-part nodes of the pair's averaged jump (the
    /// coupling node and its face neighbours), as `a-b-c`; empty for the node CFE.
    pub segment: Option<String>,
    /// The increment (1-based, over all steps).
    pub increment: usize,
    /// The increment's load step (its name).
    pub step: String,
    /// The step's load factor at this increment.
    #[serde(serialize_with = "plain")]
    pub load_factor: f64,
}

/// The columns of a plane model's `pairs.csv` (the serialized fields of
/// [`PairRow`]; a solid model's are [`SOLID_PAIR_COLUMNS`]).
pub const PAIR_COLUMNS: [&str; 23] = [
    "interface",
    "node",
    "x",
    "y",
    "host_element",
    "state",
    "gap_n",
    "slip_s",
    "force_n",
    "force_s",
    "settled",
    "violation",
    "violation_amount",
    "gap0",
    "gap",
    "slip",
    "pressure",
    "shear",
    "tributary",
    "segment",
    "increment",
    "step",
    "load_factor",
];

/// The columns of a solid model's `pairs.csv` (the serialized fields of
/// [`PairRow`] with its solid-only ones: the position's `z`, the tangential
/// jump, force, slip and shear along t₂ beside those along t₁ (`slip_s`,
/// `force_s`, `slip`, `shear`), and the force on the node part in global
/// components).
pub const SOLID_PAIR_COLUMNS: [&str; 31] = [
    "interface",
    "node",
    "x",
    "y",
    "z",
    "host_element",
    "state",
    "gap_n",
    "slip_s",
    "slip_t2",
    "force_n",
    "force_s",
    "force_t2",
    "force_x",
    "force_y",
    "force_z",
    "settled",
    "violation",
    "violation_amount",
    "gap0",
    "gap",
    "slip",
    "slip_t2_plastic",
    "pressure",
    "shear",
    "shear_t2",
    "tributary",
    "segment",
    "increment",
    "step",
    "load_factor",
];

/// A number as Rust's `Display` writes it (`100`, `0.5`): the positions' format.
fn plain<S: serde::Serializer>(v: &f64, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_str(v)
}

/// A number in scientific notation (`-1.25e-3`): the jumps' and forces' format.
fn sci<S: serde::Serializer>(v: &f64, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{v:e}"))
}

/// The violation kinds as `a;b` (empty: none), as serde names them.
fn kinds<S: serde::Serializer>(v: &[ViolationKind], s: S) -> std::result::Result<S::Ok, S::Error> {
    let names: Vec<&str> = v.iter().map(|k| k.as_str()).collect();
    s.collect_str(&names.join(";"))
}

/// The violation amounts as `a;b` in scientific notation (`0e0`: none).
fn amounts<S: serde::Serializer>(v: &[f64], s: S) -> std::result::Result<S::Ok, S::Error> {
    if v.is_empty() {
        return s.collect_str(&format_args!("{:e}", 0.0));
    }
    let text: Vec<String> = v.iter().map(|a| format!("{a:e}")).collect();
    s.collect_str(&text.join(";"))
}

impl PairRow {
    /// The pair's reference position: (x, y), or (x, y, z) in a solid model.
    pub fn position(&self) -> Vec<f64> {
        let mut p = vec![self.x, self.y];
        p.extend(self.z);
        p
    }

    /// The magnitude of the tangential jump (|`slip_s`| in a plane model).
    pub fn tangential_jump(&self) -> f64 {
        match self.slip_t2 {
            None => self.slip_s.abs(),
            Some(t2) => self.slip_s.hypot(t2),
        }
    }

    /// The magnitude of the shear traction (|`shear`| in a plane model).
    pub fn shear_magnitude(&self) -> f64 {
        match self.shear_t2 {
            None => self.shear.abs(),
            Some(t2) => self.shear.hypot(t2),
        }
    }

    /// Whether the pair breaks its law.
    pub fn breaks_law(&self) -> bool {
        !self.violation.is_empty()
    }

    /// The pair's violation code in the pairs VTU and Python: 0 the law holds,
    /// 1 a bonded pair pulls, 2 an open pair penetrates, 3 a stick pair beyond
    /// μ f_n, 4 a slip pair off μ f_n, 5 a stick pair that pulls and carries shear
    /// (tension and friction; its amounts are the pull, `violation_amount`, and the
    /// friction excess, its whole |`force_s`|: the cone of a pulling pair is 0).
    pub fn violation_code(&self) -> i32 {
        use ViolationKind::*;
        match self.violation.as_slice() {
            [] => 0,
            [Tension] => 1,
            [Penetration] => 2,
            [Friction] => 3,
            [Slip] => 4,
            _ => 5,
        }
    }
}

/// One row per coupling pair of `p` at increment `inc` (of the load step named
/// `step`): state, jumps and forces on the node part.
pub(crate) fn pair_rows<D: ResultsDim>(
    p: &Problem<'_, D>,
    inc: &IncrementResult<D>,
    step: &str,
) -> Vec<PairRow> {
    let mut rows = Vec::new();
    // Every violation of the law check (the list summary.json reports): a pair
    // takes all of its own, in the check's order (its normal violation before
    // its friction one). A stable sort by pair, like the rows (the check's list
    // is sorted so already).
    let mut sorted: Vec<_> = inc.violations.iter().collect();
    sorted.sort_by_key(|v| (v.interface, v.pair));
    let mut violations = sorted.into_iter().peekable();
    for (i, iface) in p.interfaces.iter().enumerate() {
        for (k, c) in iface.elements.iter().enumerate() {
            let state = inc.states[i][k];
            // Violations are sorted by interface and pair, like the rows.
            let mut violation = Vec::new();
            let mut violation_amount = Vec::new();
            while let Some(v) = violations.next_if(|v| (v.interface, v.pair) == (i, k)) {
                violation.push(v.kind);
                violation_amount.push(v.amount);
            }
            let h = inc
                .pair_history
                .get(i)
                .and_then(|h| h.get(k))
                .copied()
                .unwrap_or_default();
            let at = iface.pair_at(k, p.dofs, &inc.u, state, &h);
            let (f, jump) = (at.force, at.jump);
            // The slip not carried by the tangential spring: the plastic slip of
            // a closed pair with friction, the whole tangential jump when
            // nothing holds it (open, or frictionless).
            let slip = if state.is_closed() && iface.law != Law::Frictionless {
                h.slip
            } else {
                jump.1
            };
            let thickness = D::traction_thickness(&p.parts[iface.node_part].material);
            // A tangent's second component (t₂), in 3D only.
            let second = |t: D::Tangent| (D::Tangent::COMPONENTS > 1).then(|| t.component(1));
            // The force on the node part in global components, in 3D only (the
            // pair's force is in its own frame).
            let global = (D::N > 2).then(|| {
                let g = D::to_global(&c.frame, f.0, f.1);
                g.as_ref().iter().map(|v| -v + 0.0).collect::<Vec<f64>>()
            });
            let position = c.position.as_ref();
            rows.push(PairRow {
                interface: iface.name.clone(),
                node: c.node,
                x: position[0],
                y: position[1],
                z: position.get(2).copied(),
                host_element: c.host_element,
                state,
                gap_n: jump.0,
                slip_s: jump.1.component(0),
                slip_t2: second(jump.1),
                // Force on the node part is −f; `+ 0.0` turns −0 into 0 for open pairs.
                force_n: -f.0 + 0.0,
                force_s: -f.1.component(0) + 0.0,
                force_t2: second(f.1).map(|v| -v + 0.0),
                force_x: global.as_ref().map(|g| g[0]),
                force_y: global.as_ref().map(|g| g[1]),
                force_z: global.as_ref().map(|g| g[2]),
                settled: inc.settled.binary_search(&(i, k)).is_ok(),
                violation,
                violation_amount,
                gap0: c.gap0,
                gap: at.gap,
                slip: slip.component(0),
                slip_t2_plastic: second(slip),
                pressure: c.traction(-f.0 + 0.0, thickness),
                shear: c.traction(-f.1.component(0) + 0.0, thickness),
                shear_t2: second(f.1).map(|v| c.traction(-v + 0.0, thickness)),
                tributary: c.tributary,
                segment: c.segment.as_ref().map(|s| {
                    s.nodes
                        .iter()
                        .map(|n| n.to_string())
                        .collect::<Vec<_>>()
                        .join("-")
                }),
                increment: inc.index,
                step: step.to_string(),
                load_factor: inc.lambda,
            });
        }
    }
    rows
}
