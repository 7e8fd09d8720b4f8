//! Domain: the resolved problem below the numerics — parts (mesh + material),
//! supports, loads, interface parameters and analysis settings. The problem-file
//! schema ([`crate::model`]) translates into these types; the element routines, the
//! coupling, the assembly and the solver take only these, never the input types.

use crate::coupling::Law;
use crate::fem::Material;
use crate::mesh::Mesh;
use serde::Deserialize;

/// The nonlinear scheme for contact interfaces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scheme {
    /// Iterate within each increment until no pair changes state (default).
    ActiveSet,
    /// The seed's scheme: states lagged by one increment, one solve per increment.
    Implex,
}

/// Analysis settings (`[analysis]`).
#[derive(Debug, Clone, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Number of load increments (the load grows linearly to its full value).
    pub increments: usize,
    /// `active-set` or `implex`.
    pub scheme: Scheme,
    /// Iteration limit per increment (active-set).
    pub max_iterations: usize,
    /// A pair opens when `[[u_n]]` exceeds this fraction of the largest displacement
    /// magnitude among its four nodes.
    pub gap_tolerance: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            increments: 10,
            scheme: Scheme::ActiveSet,
            max_iterations: 50,
            gap_tolerance: 1e-9,
        }
    }
}

/// A part: its mesh and material.
#[derive(Debug, Clone)]
pub struct Part {
    /// Name from the problem file.
    pub name: String,
    /// The part's mesh.
    pub mesh: Mesh,
    /// Material, 2D idealisation and thickness.
    pub material: Material,
}

/// An interface as defined in the problem file, with its parts resolved.
#[derive(Debug, Clone)]
pub struct InterfaceDef {
    /// Name (default `host/nodes`).
    pub name: String,
    /// Index of the host part.
    pub host: usize,
    /// Index of the node part.
    pub node_part: usize,
    /// Coupling nodes: the nodes of the node part's named boundary.
    pub nodes: Vec<usize>,
    /// Name of that boundary.
    pub boundary: String,
    /// `rigid` or `contact`.
    pub law: Law,
    /// Normal penalty.
    pub c_n: f64,
    /// Tangential penalty.
    pub c_s: f64,
    /// Relative geometric tolerance of the pair search.
    pub tolerance: f64,
}

/// A Dirichlet condition on a set of nodes of one part.
#[derive(Debug, Clone)]
pub struct Support {
    /// Label, e.g. `base/bottom`.
    pub name: String,
    /// Part index.
    pub part: usize,
    /// Nodes of the part.
    pub nodes: Vec<usize>,
    /// Which components are fixed (x, y).
    pub fix: [bool; 2],
    /// Prescribed values of the fixed components at full load.
    pub value: [f64; 2],
}

/// An external load resolved to nodal forces at full load.
#[derive(Debug, Clone)]
pub struct Load {
    /// Label, e.g. `plate/top`.
    pub name: String,
    /// Part index.
    pub part: usize,
    /// Nodal forces (node of the part, force).
    pub nodal: Vec<(usize, [f64; 2])>,
    /// The resultant the user asked for.
    pub resultant: [f64; 2],
}
