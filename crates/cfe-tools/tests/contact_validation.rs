//! The quick versions of the contact-law validation cases (issue 12): each must
//! meet its closed form or reference. `cfe verify` runs the full versions.

use cfe_tools::verification::{Case, fits, hertz};

fn check(case: cfe::error::Result<Case>) {
    let c = case.expect("case runs");
    assert!(c.passed, "{}: {}", c.title, c.verdict);
}

/// Hertz (frictionless, initial gaps, two materials): a and p₀ from the fitted
/// pressure profile approach the closed form as the mesh is refined (n = 4, 8)
/// and the pairs carry the load.
#[test]
fn hertz_converges() {
    let (a_ref, p0_ref) = hertz::reference();
    let mut errors = Vec::new();
    for n in [4, 8] {
        let r = hertz::measure(
            &hertz::problem(
                n,
                "law = \"frictionless\"",
                hertz::CYLINDER,
                [0.0, -hertz::LOAD],
                true,
            ),
            n,
        )
        .expect("Hertz runs");
        assert!(
            (r.total / hertz::LOAD - 1.0).abs() < 1e-6,
            "load {}",
            r.total
        );
        errors.push((
            (r.fit.a / a_ref - 1.0).abs(),
            (r.fit.p0 / p0_ref - 1.0).abs(),
        ));
    }
    // Loose at these coarse levels: the finest run within 5 %, errors falling.
    assert!(errors[1].0 < 0.05 && errors[1].1 < 0.05, "{errors:?}");
    assert!(
        errors[1].0 < errors[0].0 && errors[1].1 < errors[0].1,
        "{errors:?}"
    );
}

/// Hertz with the segment coupling at n = 16: a and p₀ within 2 % of the closed
/// form, the load carried, and the pressure profile inside the contact
/// (|x| < 0.8 a) at least twice as close to Hertz's ellipse (RMS) as the node
/// coupling's on the same mesh, whose collocated gaps give a dip at x = 0.
#[test]
fn hertz_segment_is_smoother() {
    let (a_ref, p0_ref) = hertz::reference();
    let n = 16;
    let run = |law: &str| {
        hertz::measure(
            &hertz::problem(n, law, hertz::CYLINDER, [0.0, -hertz::LOAD], true),
            n,
        )
        .expect("Hertz runs")
    };
    let seg = run("law = \"frictionless\"\ncoupling = \"segment\"");
    let node = run("law = \"frictionless\"");
    assert!(
        (seg.total / hertz::LOAD - 1.0).abs() < 1e-6,
        "{}",
        seg.total
    );
    assert!(
        (seg.fit.a / a_ref - 1.0).abs() < 0.02 && (seg.fit.p0 / p0_ref - 1.0).abs() < 0.02,
        "a {} p0 {}",
        seg.fit.a,
        seg.fit.p0
    );
    let rms = |r: &hertz::HertzRun| hertz::profile_rms(&r.pairs, 0.8 * a_ref, a_ref, p0_ref);
    assert!(
        2.0 * rms(&seg) < rms(&node),
        "segment {} node {}",
        rms(&seg),
        rms(&node)
    );
}

/// Shrink fit: the frictionless interface with negative initial gaps gives
/// Lamé's interface pressure with the node and the segment coupling (quick
/// levels), and uniform pair pressures when the two faces' nodes face each other.
#[test]
fn shrink_fit() {
    check(fits::shrink_fit(true));
}

/// Frictionless contact patch test on non-matching meshes: the uniform pressure
/// is transmitted (interior pairs and the upper block's stress within 5 %).
#[test]
fn frictionless_patch() {
    check(fits::frictionless_patch(true));
}

/// Receding contact of the plate on a base: each law's contact zone as
/// CalculiX's on the same mesh.
#[test]
fn receding() {
    check(fits::receding(true));
}

/// Augmented Lagrangian: Hertz's a and p₀ do not depend on c_n over four decades.
#[test]
fn augmented_independent_of_penalty() {
    check(hertz::penalty_independence(true));
}

/// Cattaneo–Mindlin (Coulomb; load step 1 the normal force P′, step 2 a growing
/// tangential force Q = ½ μP′):
/// the stick zone's half-width within two pair spacings of a√(1 − Q/(μP′)) and
/// the shear traction close to the closed-form profile.
#[test]
fn cattaneo_mindlin() {
    check(hertz::cattaneo_mindlin(true));
}
