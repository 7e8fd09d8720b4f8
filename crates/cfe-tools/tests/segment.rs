//! Segment-to-segment coupling (issue 15): the constant-stress patch test through a
//! tied interface on non-matching meshes, against the node CFE.

use cfe::mesh::ElementKind;
use cfe_tools::verification::patch::nonmatching_patch;

const ET: f64 = cfe_tools::verification::patch::ET;

/// The meshes of the patch test: host : node cells per side and, for the randomly
/// perturbed faces, the seed.
const LAYOUTS: [(usize, usize, Option<u64>); 4] = [
    (2, 3, None),
    (3, 7, None),
    (3, 4, Some(7)),
    (4, 5, Some(2026)),
];

/// The segment coupling reproduces a constant stress (tension and shear across
/// and along the interface) through 2:3, 3:7 and randomly perturbed non-matching
/// faces, for T3, Q4 and mixed meshes, with the rigid law and with the contact law
/// under compression (every pair bonded), to the penalty's accuracy: the error
/// falls with c like E·t/c, far below the node CFE's on the same meshes.
#[test]
fn segment_coupling_passes_the_nonmatching_patch_test() {
    let kinds = [
        [ElementKind::T3, ElementKind::T3],
        [ElementKind::Q4, ElementKind::Q4],
        [ElementKind::Q4, ElementKind::T3],
    ];
    for law in ["rigid", "contact"] {
        for k in kinds {
            for (h, n, seed) in LAYOUTS {
                let (seg, seg_rms, bonded) =
                    nonmatching_patch(h, n, k, "segment", law, 1e6 * ET, seed).unwrap();
                let (node, _, _) = nonmatching_patch(h, n, k, "node", law, 1e6 * ET, seed).unwrap();
                eprintln!(
                    "{law} {k:?} {h}:{n} {seed:?}: segment {seg:.3e} (rms {seg_rms:.3e}), node {node:.3e}, bonded {bonded}"
                );
                assert!(bonded, "{law} {k:?} {h}:{n}");
                assert!(seg < 1e-6, "{law} {k:?} {h}:{n} {seed:?}: {seg:e}");
                assert!(
                    node > 1e-3,
                    "{law} {k:?} {h}:{n}: the node CFE passes? {node:e}"
                );
            }
        }
    }
}

/// The verification cases of the segment coupling (quick versions) meet their
/// references: the patch test on non-matching faces, and optimal convergence of
/// the tied cantilever and Lamé's cylinder with a converging interface traction.
#[test]
fn segment_verification_cases_pass() {
    use cfe_tools::verification::segment;
    for case in [
        segment::patch_comparison(true).unwrap(),
        segment::convergence(true).unwrap(),
    ] {
        for t in &case.tables {
            eprintln!("{}\n{}", t.caption, t.header.join(" | "));
            for r in &t.rows {
                eprintln!("{}", r.join(" | "));
            }
        }
        eprintln!("{}", case.verdict);
        assert!(case.passed, "{}: {}", case.title, case.verdict);
    }
}
