//! Coupling: the interfaces between independently meshed parts. Finds the coupling
//! pairs (each coupling node of the node part and the host element that contains it),
//! builds one coupling finite element (CFE) per pair, and evaluates the interface
//! law that decides whether a pair is bonded or open.

pub mod element;
pub mod law;
pub(crate) mod search;
pub mod segment;

pub use element::{CouplingElement, SegmentSide};
pub use law::{Law, LawTolerance, LawViolation, PairState, PairStates, ViolationKind};

/// An interface between a host part and a node part, with its coupling elements.
#[derive(Debug, Clone)]
pub struct Interface {
    /// Name used in messages and outputs.
    pub name: String,
    /// Index of the host part (usually the coarser mesh).
    pub host: usize,
    /// Index of the node part (usually the finer mesh), whose boundary nodes couple.
    pub node_part: usize,
    /// `rigid` (always bonded) or `contact` (bonded in compression, open in tension).
    pub law: Law,
    /// Normal penalty c_n (force per length).
    pub c_n: f64,
    /// Tangential penalty c_s (force per length).
    pub c_s: f64,
    /// One coupling element per coupling node.
    pub elements: Vec<CouplingElement>,
    /// Largest distance from a coupling node to its host edge (geometric check).
    pub max_projection_distance: f64,
    /// How the coupling elements' jumps are taken: collocated at the coupling
    /// node, or averaged over its face segments.
    pub coupling: Coupling,
}

/// The coupling formulation of an interface (`coupling` in the problem file).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Coupling {
    /// One CFE per coupling node, collocated at the node (the seed's, default).
    #[default]
    Node,
    /// Segment coupling: one CFE per coupling node whose jump is averaged over its
    /// face segments, integrated exactly on the face cut at the host's vertices
    /// ([`segment`]); passes the patch test on non-matching meshes.
    Segment,
}

impl Coupling {
    /// Lower-case name as in the problem file (`node`, `segment`).
    pub fn as_str(self) -> &'static str {
        match self {
            Coupling::Node => "node",
            Coupling::Segment => "segment",
        }
    }
}
