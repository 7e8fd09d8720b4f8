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

/// The segment coupling with the frictionless law passes the *contact* patch test
/// (El-Abbasi & Bathe; Code_Aster SSNP121) on non-matching meshes: a uniform
/// pressure crosses the interface between blocks of different Poisson's ratios
/// with every pair's pressure (force / its share of the face) and the upper
/// block's stress uniform to the penalty's accuracy, where the node CFE is off by
/// per cents (verification case "frictionless patch test").
#[test]
fn segment_coupling_passes_the_frictionless_contact_patch_test() {
    use cfe_tools::verification::fits::patch_problem;
    use cfe_tools::verification::{prepare, solve};
    let p = 5.0;
    for (lower, upper) in [(3, 5), (4, 7)] {
        let mut worst = [0.0f64; 2];
        for (c, coupling) in ["segment", "node"].into_iter().enumerate() {
            let text = patch_problem(lower, upper, "frictionless", p).replace(
                "law = \"frictionless\"",
                &format!("law = \"frictionless\"\ncoupling = \"{coupling}\""),
            );
            let a = prepare(&text).unwrap();
            let inc = solve(&a).unwrap().pop().unwrap();
            assert!(
                inc.violations.is_empty(),
                "{coupling}: {:?}",
                inc.violations
            );
            let rows = a.pair_rows(&inc);
            // Interior pairs (the two corner pairs of the node CFE carry the
            // corner's averaged normal): every pair for the segment coupling.
            for r in &rows {
                let corner = r.x.abs() < 1e-9 || (r.x - 1.0).abs() < 1e-9;
                if coupling == "node" && corner {
                    continue;
                }
                worst[c] = worst[c].max((r.pressure / p - 1.0).abs());
            }
            let up = a.model.part_index("upper").unwrap();
            for s in &a.recover(&inc.u)[up].element {
                worst[c] = worst[c].max((s[1] / p + 1.0).abs());
            }
        }
        eprintln!(
            "{lower}:{upper}: segment {:.2e}, node {:.2e}",
            worst[0], worst[1]
        );
        assert!(worst[0] < 1e-5, "{lower}:{upper}: segment {:e}", worst[0]);
        assert!(
            worst[1] > 1e-3,
            "{lower}:{upper}: node CFE passes? {:e}",
            worst[1]
        );
    }
}

/// The segment coupling under the Coulomb law (μ = 0.2) on the plate on a base
/// (its top centre held in x, as in the receding-contact case): every increment
/// ends satisfying the friction law on every pair (stick pairs inside the cone,
/// slip pairs on it, against their slip), some pairs slip, and the pairs' forces
/// carry the 1500 N load.
#[test]
fn segment_coupling_with_the_coulomb_law() {
    use cfe::PairState;
    use cfe_tools::verification::fits::receding_problem;
    use cfe_tools::verification::{prepare, solve};
    let a = prepare(&receding_problem(
        "law = \"coulomb\"\nfriction = 0.2\ncoupling = \"segment\"",
    ))
    .unwrap();
    let incs = solve(&a).unwrap();
    for inc in &incs {
        assert!(inc.violations.is_empty(), "increment {}", inc.index);
    }
    let last = incs.last().unwrap();
    let rows = a.pair_rows(last);
    let mut fy = 0.0;
    for (r, c) in rows.iter().zip(&a.interfaces[0].elements) {
        // The force on the node part from the local frame (n, s), s = n turned +90°.
        fy += -(r.force_n * c.normal[1]) + r.force_s * c.normal[0];
        if r.state != PairState::Open {
            assert!(
                r.force_s.abs() <= 0.2 * r.force_n * (1.0 + 1e-6) + 1e-6,
                "{r:?}"
            );
        }
    }
    assert!(rows.iter().any(|r| r.state == PairState::Slip));
    assert!((fy.abs() - 1500.0).abs() < 1e-6 * 1500.0, "{fy}");
}

/// Hertz with the segment coupling on the Gmsh meshes whose arc is meshed anew at
/// each level (n = 8, 16, 32 elements per a₀; not `--refine`, which keeps the
/// coarse polygon): p₀ from the fitted profile within 1 % of Hertz's at every
/// level and its error falling, the largest pair pressure within 1 % at n = 16
/// and 32, and the load carried.
#[test]
fn hertz_peak_pressure_converges_with_segment_coupling() {
    use cfe_tools::verification::hertz;
    let (_, p0_ref) = hertz::reference();
    let mut errors = Vec::new();
    for n in [8, 16, 32] {
        let r = hertz::measure(
            &hertz::problem(
                n,
                "law = \"frictionless\"\ncoupling = \"segment\"",
                hertz::CYLINDER,
                [0.0, -hertz::LOAD],
                true,
            ),
            n,
        )
        .expect("Hertz runs");
        assert!(
            (r.total / hertz::LOAD - 1.0).abs() < 1e-6,
            "n = {n}: load {}",
            r.total
        );
        let err = (r.fit.p0 / p0_ref - 1.0).abs();
        assert!(err < 0.01, "n = {n}: p₀ {} vs {p0_ref}", r.fit.p0);
        if n > 8 {
            assert!(
                (r.p_max / p0_ref - 1.0).abs() < 0.01,
                "n = {n}: p_max {}",
                r.p_max
            );
        }
        errors.push(err);
    }
    assert!(errors[1] < errors[0] && errors[2] < errors[1], "{errors:?}");
}
