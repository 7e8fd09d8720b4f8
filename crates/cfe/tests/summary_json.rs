//! `summary.json` reads back: the summary of a solved model, written as JSON, read
//! into a [`Summary`] and written again, gives the same text, so a tool reading
//! summaries (the benchmark) sees every field as the run wrote it.

use cfe::Summary;
use cfe::analysis::Analysis;
use cfe::model::Model;
use std::path::Path;

/// The summary of the plate on a base refined `refine` times, with friction `mu`
/// (Coulomb) when given.
fn solved(refine: usize, mu: Option<f64>) -> Summary {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plate_on_base.toml");
    let mut a = Analysis::new(Model::from_file(&path, refine).unwrap()).unwrap();
    if let Some(mu) = mu {
        a.override_friction(mu).unwrap();
    }
    a.solve().unwrap().summary
}

/// JSON → `Summary` → JSON reproduces the text exactly, for a run whose search
/// settled pairs off the law (violations, warnings, a settled pair; low-rank
/// updates and reuses in its history) and for a frictional run (slipping pairs):
/// every field, including the flattened solve timings and the solve methods,
/// reads back as written.
#[test]
fn a_summary_reads_back_as_written() {
    let settled = solved(4, None);
    assert!(
        !settled.violations.is_empty()
            && !settled.warnings.is_empty()
            && settled.interfaces.iter().any(|i| !i.settled.is_empty()),
        "the case must exercise violations, warnings and settled pairs"
    );
    let friction = solved(1, Some(0.2));
    assert!(friction.interfaces.iter().any(|i| i.slip > 0));
    for summary in [settled, friction] {
        let text = serde_json::to_string_pretty(&summary).unwrap();
        let read: Summary = serde_json::from_str(&text).unwrap();
        assert_eq!(serde_json::to_string_pretty(&read).unwrap(), text);
    }
}
