//! Coupling: the interfaces between independently meshed parts. Finds the coupling
//! pairs (each coupling node of the node part and the host element that contains it),
//! builds one coupling finite element (CFE) per pair, and evaluates the interface
//! law that decides whether a pair is bonded or open.

pub mod element;
pub mod law;
pub(crate) mod search;

pub use element::CouplingElement;
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
}
