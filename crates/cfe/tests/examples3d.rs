//! The solid (3D) examples run end to end from their problem files and checked
//! against independent truth: the sphere on a block (examples/sphere_on_block,
//! Gmsh TET4) against Hertz's contact radius and peak pressure, and the bolted
//! joint (examples/bolted_joint: a head tied to a plate, the plate on a base
//! with Coulomb friction) against statics and the slip resistance μ F_p (held
//! below it, no state of rest beyond it); in both, every pair row is checked
//! against its law and the loads balance. And the 3D plate on a base under the
//! seed's stick law: no consistent state in the window of its settled rim pairs.

use cfe::analysis::{Analysis, Results, RunStatus};
use cfe::coupling::PairState;
use cfe::dim::D3;
use cfe::model::FromProblemFile;
use cfe::results::PairRow;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

fn solve(name: &str) -> Results<D3> {
    let a = Analysis::<D3>::from_file(&example(name), 1).unwrap();
    let res = a.solve().unwrap();
    assert_eq!(
        res.summary.status,
        RunStatus::Completed,
        "{name}: {:?}",
        res.summary.warnings
    );
    res
}

/// The rows of interface `name`.
fn rows<'a>(res: &'a Results<D3>, name: &str) -> Vec<&'a PairRow> {
    let r: Vec<&PairRow> = res.pairs.iter().filter(|r| r.interface == name).collect();
    assert!(!r.is_empty(), "no pairs on '{name}'");
    r
}

/// Σ of the pairs' global forces on the node part.
fn resultant(rows: &[&PairRow]) -> [f64; 3] {
    let mut f = [0.0; 3];
    for r in rows {
        f[0] += r.force_x.unwrap();
        f[1] += r.force_y.unwrap();
        f[2] += r.force_z.unwrap();
    }
    f
}

/// Σ of the reactions.
fn reactions(res: &Results<D3>) -> [f64; 3] {
    let mut f = [0.0; 3];
    for r in res.reactions() {
        f[0] += r.fx;
        f[1] += r.fy;
        f[2] += r.fz.unwrap();
    }
    f
}

/// A penalty pair's normal law read off its row alone: a closed pair presses
/// (f_n ≥ 0) with f_n = c_n × its penetration −(g₀ + [[u_n]]); an open pair
/// carries nothing and does not penetrate (beyond `depth`).
fn assert_normal_law(r: &PairRow, c_n: f64, scale: f64, depth: f64) {
    match r.state {
        PairState::Open => {
            assert_eq!(r.force_n, 0.0, "{r:?}");
            assert_eq!(r.force_s, 0.0, "{r:?}");
            assert!(r.gap > -depth, "open pair penetrates: {r:?}");
        }
        PairState::Bonded | PairState::Slip => {
            assert!(r.force_n >= 0.0, "closed pair pulls: {r:?}");
            assert!(
                (r.force_n + c_n * r.gap).abs() < 1e-6 * scale,
                "f_n ≠ −c_n g: {r:?}"
            );
        }
    }
}

/// Hertz's sphere on a flat (examples/sphere_on_block: steel R = 10 mm on
/// aluminium, P = 7800 N, a quarter model meshed in TET4 by Gmsh, initial gaps,
/// frictionless): the contact radius and the peak pressure of the ellipse fitted
/// to the pairs' pressures are within 5 % of a = (3PR/4E*)^⅓ and p₀ = 3P/(2πa²);
/// every pair keeps the frictionless law; the pairs and the reactions carry P/4.
#[test]
fn the_sphere_on_a_block_meets_hertz() {
    let res = solve("sphere_on_block/sphere_on_block.toml");
    let (p, r) = (7800.0, 10.0);
    let e_star = 1.0 / ((1.0 - 0.3f64.powi(2)) / 210_000.0 + (1.0 - 0.33f64.powi(2)) / 70_000.0);
    let a_h = (3.0 * p * r / (4.0 * e_star)).cbrt();
    let p0_h = 3.0 * p / (2.0 * PI * a_h * a_h);
    // Equilibrium: the quarter's load P/4 reaches the block's supports (the
    // symmetry rollers' x and y reactions cancel the bottom's) and crosses the
    // interface.
    let q = p / 4.0;
    let f = reactions(&res);
    assert!(f[0].abs() < 1e-8 * q && f[1].abs() < 1e-8 * q, "{f:?}");
    assert!((f[2] - q).abs() < 1e-8 * q, "{f:?}");
    let pairs = rows(&res, "contact");
    let fp = resultant(&pairs);
    assert!((fp[2] - q).abs() < 1e-8 * q, "the pairs carry {fp:?}");
    assert!(res.summary.equilibrium_error < 1e-8);
    // The law on every pair, from its row.
    let c_n = res.summary.interfaces[0].c_n;
    for r in &pairs {
        assert_normal_law(r, c_n, q, 1e-9 * a_h);
        assert_eq!(r.force_s, 0.0, "frictionless: {r:?}");
        assert_eq!(r.force_t2, Some(0.0), "frictionless: {r:?}");
    }
    // Hertz: p² = p₀²(1 − r²/a²) is linear in r²; its least-squares line
    // through the closed pairs (all but the outermost, whose tributary area
    // straddles the edge of contact) gives p₀² and p₀²/a².
    let mut pts: Vec<(f64, f64)> = (pairs.iter())
        .filter(|r| r.state == PairState::Bonded)
        .map(|r| (r.x * r.x + r.y * r.y, r.pressure * r.pressure))
        .collect();
    pts.sort_by(|u, v| u.0.total_cmp(&v.0));
    pts.pop();
    assert!(pts.len() > 30, "{} closed pairs", pts.len());
    let n = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |s, q| (s.0 + q.0, s.1 + q.1));
    let (mx, my) = (sx / n, sy / n);
    let sxx: f64 = pts.iter().map(|q| (q.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
    let slope = sxy / sxx;
    let p0 = (my - slope * mx).sqrt();
    let a = (-p0 * p0 / slope).sqrt();
    // The mesh resolves the edge of contact to one pair spacing, h = 1/8 mm
    // = 12.5 % of a: half of it is the contact radius's resolution (6 %);
    // the fit over some 70 pairs averages the single pairs' scatter. 5 % for
    // a and p₀ (this mesh: a +2 %, p₀ +1 %).
    assert!((a / a_h - 1.0).abs() < 0.05, "a = {a}, Hertz {a_h}");
    assert!((p0 / p0_h - 1.0).abs() < 0.05, "p₀ = {p0}, Hertz {p0_h}");
}

/// The bolted joint (examples/bolted_joint: a head tied to a plate, the plate on
/// a base with Coulomb μ = 0.3; preload F_p = 20 kN, then a pull T = 4 kN <
/// μ F_p): the tied interface carries exactly F_p (the head has no other load),
/// its mean pressure F_p / (40 × 40 mm²) = 12.5 MPa; the frictional interface
/// carries F_p normal and T tangential, every pair within Coulomb's cone (on it
/// when slipping) and the normal penalty law; some pairs stick (T < μ F_p: no
/// gross slip); the base's supports react (T, 0, F_p).
#[test]
fn the_bolted_joint_holds_by_friction() {
    let res = solve("bolted_joint/bolted_joint.toml");
    let (fp, t, mu) = (20_000.0, 4_000.0, 0.3);
    let f = reactions(&res);
    assert!((f[0] - t).abs() < 1e-8 * fp, "{f:?}");
    assert!(f[1].abs() < 1e-8 * fp, "{f:?}");
    assert!((f[2] - fp).abs() < 1e-8 * fp, "{f:?}");
    assert!(res.summary.equilibrium_error < 1e-8);
    let c_n = |name: &str| {
        (res.summary.interfaces.iter())
            .find(|i| i.name == name)
            .unwrap()
            .c_n
    };
    // The tied head: all bonded, carrying F_p down onto the plate (on the head,
    // the node part: up), 12.5 MPa on average.
    let tied = rows(&res, "head-plate");
    assert!(tied.iter().all(|r| r.state == PairState::Bonded));
    let ft = resultant(&tied);
    assert!((ft[2] - fp).abs() < 1e-6 * fp, "{ft:?}");
    assert!(ft[0].abs() < 1e-6 * fp && ft[1].abs() < 1e-6 * fp, "{ft:?}");
    let area: f64 = tied.iter().map(|r| r.tributary).sum();
    assert!((area - 1600.0).abs() < 1e-9 * 1600.0, "head area {area}");
    let mean: f64 = tied.iter().map(|r| r.force_n).sum::<f64>() / area;
    assert!((mean - 12.5).abs() < 1e-6 * 12.5, "mean pressure {mean}");
    // The faying surface: F_p normal, T tangential (on the plate: +x against
    // the pull), Coulomb on every pair.
    let fric = rows(&res, "plate-base");
    let ff = resultant(&fric);
    assert!((ff[2] - fp).abs() < 1e-6 * fp, "{ff:?}");
    assert!(
        (ff[0] - t).abs() < 1e-6 * fp && ff[1].abs() < 1e-6 * fp,
        "{ff:?}"
    );
    let c = c_n("plate-base");
    let mut sticking = 0;
    for r in &fric {
        assert_normal_law(r, c, fp, 1e-9);
        let fs = r.force_s.hypot(r.force_t2.unwrap());
        match r.state {
            PairState::Open => assert_eq!(fs, 0.0, "{r:?}"),
            PairState::Bonded => {
                sticking += 1;
                assert!(
                    fs <= mu * r.force_n + 1e-6 * fp,
                    "stick beyond μ f_n: {r:?}"
                );
            }
            PairState::Slip => assert!(
                (fs - mu * r.force_n).abs() < 1e-6 * fp,
                "slip off μ f_n: {r:?}"
            ),
        }
    }
    // The slip resistance: Σ |f_t| ≤ μ Σ f_n = μ F_p = 6 kN > T, so the plate
    // holds with a stick zone (pairs sticking, not all slipping).
    assert!(sticking > 0, "gross slip at T = {t} < μ F_p = {}", mu * fp);
}

/// The 3D plate on a base (examples/plate_on_base_3d.toml) under the seed's
/// stick law (`contact`: bonded in compression, open in tension) ends
/// `completed_with_violations` with pairs settled at the contact zone's rim:
/// that law has no consistent state there. Every open/bonded assignment of the
/// settled pairs and their neighbours within one cell (5 mm; 2ⁿ patterns, the
/// other pairs as cfe left them) is solved: none satisfies the law, and none
/// violates it less than cfe's settled state by the settlement rule's measure
/// (no penetration first, then the smallest largest violation) — as the 2D
/// seed example's end window (docs/method.md, "Why the discrete stick law can
/// have no consistent state").
#[test]
fn the_3d_plate_under_the_stick_law_has_no_consistent_state_at_its_rim() {
    use cfe::coupling::{Law, ViolationKind};
    use cfe::error::Error;
    let mut a = Analysis::<D3>::from_file(&example("plate_on_base_3d.toml"), 1).unwrap();
    a.override_law(Law::Contact);
    let res = a.solve().unwrap();
    assert_eq!(res.summary.status, RunStatus::CompletedWithViolations);
    let last = &res.last;
    assert!(!last.settled.is_empty());
    let at = |p: usize| a.interfaces[0].elements[p].position;
    let near = |p: usize, q: usize| {
        let (x, y) = (at(p), at(q));
        (x[0] - y[0]).hypot(x[1] - y[1]) < 5.0 + 1e-9
    };
    let n = last.states[0].len();
    let window: Vec<usize> = (0..n)
        .filter(|&p| last.settled.iter().any(|&(_, s)| near(p, s)))
        .collect();
    assert!(window.len() <= 12, "{} pairs", window.len());
    let score = |r: &cfe::solve::nonlinear::IncrementResult<D3>| {
        let penetrates = (r.violations.iter()).any(|v| v.kind == ViolationKind::Penetration);
        (penetrates, r.max_violation_force())
    };
    let mut solver = a.solver().unwrap();
    let settled = score(&solver.solve_pattern(1.0, &last.states).unwrap());
    assert!(settled.1 > 0.0);
    let mut best: Option<(bool, f64)> = None;
    for mask in 0u32..1 << window.len() {
        let mut s = last.states.clone();
        for (j, &p) in window.iter().enumerate() {
            s[0][p] = if mask >> j & 1 == 1 {
                PairState::Open
            } else {
                PairState::Bonded
            };
        }
        let r = match solver.solve_pattern(1.0, &s) {
            Ok(r) => r,
            Err(Error::Unsupported { .. } | Error::Singular(_)) => continue,
            Err(e) => panic!("{e}"),
        };
        assert!(
            !r.violations.is_empty(),
            "pattern {mask:b} satisfies the law"
        );
        let sc = score(&r);
        if best.is_none_or(|b| sc < b) {
            best = Some(sc);
        }
    }
    let least = best.expect("some pattern supports the plate");
    assert_eq!(least.0, settled.0);
    assert!(
        least.1 >= settled.1 * (1.0 - 1e-9),
        "{least:?} < {settled:?}"
    );
}

/// The bolted joint's slip resistance is μ F_p: pulled with T = 6.5 kN > μ F_p =
/// 6 kN (the example with only its pull changed) the plate and its head have
/// no state of rest, and the run stops with the typed error naming them.
#[test]
fn the_bolted_joint_slips_beyond_mu_times_the_preload() {
    use cfe::error::Error;
    use cfe::model::{FromProblemText, Model};
    let path = example("bolted_joint/bolted_joint.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let pull = "force = [-4000.0, 0.0, 0.0]";
    assert!(text.contains(pull));
    let text = text.replace(pull, "force = [-6500.0, 0.0, 0.0]");
    let model = Model::<D3>::from_str(&text, &path, 1).unwrap();
    match Analysis::new(model).unwrap().solve() {
        Err(Error::Unsupported { parts, message }) => {
            assert!(parts.iter().any(|p| p == "plate"), "{parts:?}: {message}");
        }
        Err(e) => panic!("expected a part without a state of rest, got {e}"),
        Ok(r) => panic!("completed beyond μ F_p: {:?}", r.summary.status),
    }
}
