//! A part for the unit tests of the linear algebra's set-up: a structured T3
//! rectangle with its bottom clamped (test-only).

use crate::dofs::DofMap;
use crate::domain::{Part, Support};
use crate::fem::{Material, PlaneKind};
use crate::mesh::{ElementKind, Mesh};

/// One part `p`, the rectangle `x` × `y` of `cells` T3 cells (E = 1, ν = 0.3,
/// plane stress, t = 1), its bottom fixed in x and y, with its DOF numbering.
pub fn clamped_rectangle(x: [f64; 2], y: [f64; 2], cells: [usize; 2]) -> (Vec<Part>, DofMap) {
    let parts = vec![Part {
        name: "p".into(),
        mesh: Mesh::rectangle(x, y, cells, ElementKind::T3),
        material: Material::new(1.0, 0.3, PlaneKind::Stress, 1.0, "p").unwrap(),
    }];
    let supports = vec![Support {
        name: "s".into(),
        part: 0,
        nodes: parts[0].mesh.boundary_nodes("bottom").unwrap(),
        fix: [true, true, false],
        value: [0.0; 3],
        step: 0,
    }];
    let dofs = DofMap::new(&parts, &supports);
    (parts, dofs)
}
