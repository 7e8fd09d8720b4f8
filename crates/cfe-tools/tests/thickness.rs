//! The Hertz and Cattaneo–Mindlin extractions read stresses and loads per unit
//! thickness: unchanged for t = 1, and the same a, p₀ and stick zone when the
//! parts' thickness and the loads are scaled together.

use cfe_tools::verification::hertz;

/// Relative difference of `a` and `b`.
fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

/// Hertz at n = 4 with t = 1 and with both parts 2.5 thick under 2.5 × the
/// load: the same displacements (stiffness, penalties and loads all scale with
/// t), so the same pressures, fitted a and p₀, peak and P′ carried, to
/// round-off; and at t = 1 each pair's pressure is bit for bit its normal force
/// over its tributary length (the extraction as it was).
#[test]
fn hertz_extraction_scales_with_thickness() {
    let (n, k) = (4, 2.5);
    let law = "law = \"frictionless\"";
    let one = hertz::measure(
        &hertz::problem(n, law, hertz::CYLINDER, [0.0, -hertz::LOAD], true),
        n,
    )
    .unwrap();
    for p in &one.pairs {
        assert_eq!(p.pressure, p.f_n / p.length);
        assert_eq!(p.shear, p.f_s / p.length);
    }
    let thick = hertz::measure(
        &hertz::with_thickness(
            &hertz::problem(n, law, hertz::CYLINDER, [0.0, -k * hertz::LOAD], true),
            k,
        ),
        n,
    )
    .unwrap();
    assert_eq!(one.closed, thick.closed);
    for (x, y, what) in [
        (one.fit.a, thick.fit.a, "a"),
        (one.fit.p0, thick.fit.p0, "p₀"),
        (one.p_max, thick.p_max, "p_max"),
        (one.edge, thick.edge, "edge half-width"),
        (one.total, thick.total, "P′ carried"),
    ] {
        assert!(rel(y, x) < 1e-8, "{what}: t = 1: {x}, t = {k}: {y}");
    }
    assert!(rel(one.total, hertz::LOAD) < 1e-6, "{}", one.total);
    for (p, q) in one.pairs.iter().zip(&thick.pairs) {
        assert!(rel(q.f_n, k * p.f_n) < 1e-8 || p.f_n.abs() < 1e-9 * hertz::LOAD);
        assert!((q.pressure - p.pressure).abs() < 1e-8 * one.p_max);
    }
}

/// Cattaneo–Mindlin at n = 4 with t = 1 and t = 2.5 (loads × 2.5): the same P′
/// and Q per unit thickness, Hertz's a and p₀ from them, fitted a, stick zone
/// and shear error.
#[test]
fn cattaneo_mindlin_extraction_scales_with_thickness() {
    let (n, k) = (4, 2.5);
    let one = hertz::cattaneo_run(n, 4, 1.0).unwrap();
    let thick = hertz::cattaneo_run(n, 4, k).unwrap();
    assert_eq!((one.stick, one.slip), (thick.stick, thick.slip));
    assert!(rel(one.p_total, hertz::LOAD) < 1e-6, "{}", one.p_total);
    for (x, y, what) in [
        (one.p_total, thick.p_total, "P′"),
        (one.q, thick.q, "Q"),
        (one.a_h, thick.a_h, "a"),
        (one.p0, thick.p0, "p₀"),
        (one.fit_a, thick.fit_a, "a (fit)"),
        (one.c_h, thick.c_h, "c (run)"),
        (one.rms, thick.rms, "shear RMS"),
    ] {
        assert!(rel(y, x) < 1e-6, "{what}: t = 1: {x}, t = {k}: {y}");
    }
}
