//! Error messages a user acts on: long lists of nodes are summarised (the first
//! few, then a count), and an assembly with no support says so rather than
//! blaming its interfaces or friction.

mod common;

use cfe::Error;
use cfe::analysis::Analysis;
use cfe::model::Model;
use std::path::Path;

/// The seed's plate on a base (examples/plate_on_base.toml).
fn plate_on_base() -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml"),
    )
    .unwrap()
}

/// The error of solving `text`, which must be an [`Error::Unsupported`] naming
/// exactly `parts`; returns its message.
fn unsupported(text: &str, parts: &[&str]) -> String {
    let model = Model::from_str(text, Path::new("test.toml"), 1).unwrap();
    let e = Analysis::new(model)
        .unwrap()
        .solve()
        .expect_err("must fail");
    let Error::Unsupported { parts: named, .. } = &e else {
        panic!("unexpected error {e:?}");
    };
    assert_eq!(named, parts, "{e}");
    e.to_string()
}

/// Host and node part swapped: the base's 21 bottom nodes lie on none of the
/// plate's edges. The error is the typed `OrphanNodes` with all 21 nodes, and
/// its message lists the first five and counts the others, in a few hundred
/// characters (it was one 2,000-character line).
#[test]
fn swapped_host_and_nodes_give_a_short_message() {
    let text = plate_on_base()
        .replace("host = \"base\"", "host = \"plate\"")
        .replace("nodes = \"plate\"", "nodes = \"base\"");
    let model = Model::from_str(&text, Path::new("test.toml"), 1).unwrap();
    let e = Analysis::new(model).err().expect("no pairs");
    let Error::OrphanNodes { nodes, .. } = &e else {
        panic!("unexpected error {e:?}");
    };
    assert_eq!(nodes.len(), 21);
    let message = e.to_string();
    assert!(
        message.contains("21 coupling node(s)")
            && message.contains("node 4 at (40, 0)")
            && !message.contains("node 5 at")
            && message.contains("… and 16 more"),
        "{message}"
    );
    assert!(
        message.chars().count() < 900,
        "{}: {message}",
        message.len()
    );
}

/// No support anywhere (the base's removed), with the Coulomb law and a load
/// pushing the plate along the base harder than μ = 0.3 holds it: the error
/// names both parts and says the assembly has no support, without blaming
/// friction (the plate is not held by friction against a base that is itself
/// free).
#[test]
fn an_assembly_without_support_says_so() {
    let text = plate_on_base()
        .replace(
            "[[support]]\npart = \"base\"\nboundary = \"bottom\"\nfix = [\"x\", \"y\"]\n",
            "",
        )
        .replace("law = \"contact\"", "law = \"coulomb\"\nfriction = 0.3");
    for load in ["[0.0, -1500.0]", "[1000.0, -1500.0]"] {
        let text = text.replace("[0.0, -1500.0]", load);
        assert!(!text.contains("[[support]]") && text.contains(load));
        let message = unsupported(&text, &["base", "plate"]);
        assert!(
            message.contains("system: the assembly has no support")
                && message.contains("'base', 'plate'")
                && !message.contains("friction"),
            "{load}: {message}"
        );
    }
}

/// A third part with neither a support nor an interface, beside the supported
/// plate on a base: the error names it alone and says nothing holds it.
#[test]
fn a_part_with_no_support_and_no_interface_is_named() {
    let text = plate_on_base().replace(
        "[[interface]]",
        "[[part]]\nname = \"loose\"\nmaterial = \"steel\"\nrectangle = { x = [300.0, 310.0], y = [0.0, 10.0], cells = [1, 1] }\n\n[[interface]]",
    );
    let message = unsupported(&text, &["loose"]);
    assert!(
        message.contains("system: part 'loose' has no support and no interface"),
        "{message}"
    );
}
