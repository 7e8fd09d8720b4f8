//! A problem whose part meshes are given in memory ([`Model::from_str_with_meshes`],
//! e.g. from [`Mesh::from_arrays`], as the Python package gives them) solves to
//! the same numbers as the same problem meshed from its text.

use cfe::mesh::{BoundarySelection, ElementKind, Mesh};
use cfe::{Analysis, Model};
use std::collections::BTreeMap;
use std::path::Path;

const PROBLEM: &str = "../../examples/plate_on_base.toml";
const PLATE: &str =
    "rectangle = { x = [30.0, 170.0], y = [120.0, 135.0], cells = [28, 6] } # 336 T3";

/// The plate's mesh given as arrays (the mesher's nodes and elements, the
/// boundaries as node sets) gives the file's displacements and pair states.
#[test]
fn given_mesh_equals_the_meshed_text() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(PROBLEM);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains(PLATE));
    let reference = Analysis::new(Model::from_file(&path, 1).unwrap())
        .unwrap()
        .solve()
        .unwrap();

    let m = Mesh::rectangle([30.0, 170.0], [120.0, 135.0], [28, 6], ElementKind::T3);
    let boundaries = ["bottom", "top"]
        .map(|b| {
            let nodes = m.boundary_nodes(b).unwrap();
            (b.to_string(), BoundarySelection::Nodes(nodes))
        })
        .to_vec();
    let plate =
        Mesh::from_arrays("plate", m.nodes.clone(), m.elements.clone(), boundaries).unwrap();
    let meshes = BTreeMap::from([("plate".to_string(), plate)]);
    let model = Model::from_str_with_meshes(&text.replace(PLATE, ""), &path, 1, meshes).unwrap();
    let results = Analysis::new(model).unwrap().solve().unwrap();

    assert_eq!(results.last.states, reference.last.states);
    let scale = reference
        .displacements()
        .iter()
        .fold(0.0f64, |a, v| a.max(v.abs()));
    for (a, b) in results
        .displacements()
        .iter()
        .zip(reference.displacements())
    {
        assert!((a - b).abs() <= 1e-12 * scale, "{a} vs {b}");
    }
}

/// A mesh given for a part the text does not define, or for a part that has a
/// mesh key too, is an error naming the part.
#[test]
fn given_mesh_must_belong_to_a_meshless_part() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(PROBLEM);
    let text = std::fs::read_to_string(&path).unwrap();
    let m = Mesh::rectangle([30.0, 170.0], [120.0, 135.0], [28, 6], ElementKind::T3);
    let err = |name: &str| {
        let meshes = BTreeMap::from([(name.to_string(), m.clone())]);
        Model::from_str_with_meshes(&text, &path, 1, meshes)
            .unwrap_err()
            .to_string()
    };
    let e = err("lid");
    assert!(e.contains("'lid'") && e.contains("does not define"), "{e}");
    let e = err("plate");
    assert!(
        e.contains("'plate'") && e.contains("given in memory"),
        "{e}"
    );
}
