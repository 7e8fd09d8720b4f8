//! `--refine` on a curved Gmsh face keeps the file's polygon, and says so.

use cfe::RunStatus;
use cfe::analysis::Analysis;
use cfe::model::Model;
use std::path::Path;

/// examples/hertz/hertz.toml refined twice: the cylinder's arc (a Gmsh curve
/// meshed by chords) is a curved boundary whose new nodes lie on the chords, so
/// the run warns — in the summary, at increment 0, naming the part and the
/// boundary and --refine — without changing its status (the law and equilibrium
/// hold on the polygon). The block's straight sides give no warning, nor does
/// the file as given (no refinement), nor a built-in annulus refined (meshed
/// anew on its circles).
#[test]
fn a_refined_curved_gmsh_face_warns_that_it_keeps_its_polygon() {
    let hertz = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/hertz/hertz.toml");
    assert!(
        Model::from_file(&hertz, 1)
            .unwrap()
            .kept_polygons
            .is_empty()
    );
    let model = Model::from_file(&hertz, 2).unwrap();
    let kept: Vec<(&str, &str)> = model
        .kept_polygons
        .iter()
        .map(|(part, b)| (part.as_str(), b.name.as_str()))
        .collect();
    assert_eq!(kept, [("cylinder", "arc")]);
    let summary = Analysis::new(model).unwrap().solve().unwrap().summary;
    let warnings: Vec<&cfe::analysis::Warning> = summary
        .warnings
        .iter()
        .filter(|w| w.increment == 0)
        .collect();
    assert_eq!(warnings.len(), 1, "{:?}", summary.warnings);
    let m = &warnings[0].message;
    assert!(
        m.contains("part 'cylinder', boundary 'arc'")
            && m.contains("--refine 2")
            && m.contains("polygon"),
        "{m}"
    );
    assert_eq!(
        summary.status,
        RunStatus::Completed,
        "{:?}",
        summary.warnings
    );

    let annulus = r#"
[materials.m]
E = 1000.0
nu = 0.3
[[part]]
name = "ring"
material = "m"
annulus = { center = [0.0, 0.0], r = [1.0, 2.0], theta = [0.0, 90.0], cells = [2, 6] }
"#;
    let model = Model::from_str(annulus, Path::new("ring.toml"), 3).unwrap();
    assert!(model.kept_polygons.is_empty());
}
