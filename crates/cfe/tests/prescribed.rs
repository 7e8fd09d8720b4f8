//! Prescribed displacements and point loads.
//!
//! ```text
//!        uy = −δ on the top (prescribed)
//!      +-------------------+   y = 2
//!      |  upper (fine)     |
//!      +===================+   y = 1, tied, 3:6 (host vertices are coupling nodes)
//!      |  lower (coarse)   |
//!      +-------------------+   y = 0, uy = 0; (0,0) also ux = 0
//! ```
//!
//! Plane stress, free sides: uniaxial compression, σyy = −E δ / H everywhere
//! (H = 2), σxx = σxy = 0, up to the tie's penalty error O(E·t/c) = 1e-6 here; the
//! reaction on the bottom balances the one on the top.

mod common;

use common::{Problem, Raw};

const E: f64 = 1000.0;
const DELTA: f64 = 0.01;

fn problem(extra: &str) -> String {
    Problem::spaced()
        .material("m", E, 0.25)
        .part("lower", "m")
        .rectangle([0.0, 1.0], [0.0, 1.0], [3, 3])
        .part("upper", "m")
        .rectangle([0.0, 1.0], [1.0, 2.0], [6, 6])
        .interface("lower", "upper", "bottom")
        .law("rigid")
        .iface_key("c_n", Raw("1e9"))
        .rollers("lower", [0.0, 0.0])
        .raw(extra)
        .increments(2)
        .text()
}

/// A prescribed top displacement compresses the tied pair of blocks uniformly:
/// every element has σyy = −E δ / H to 1e-5 (the penalty's error), and the reactions of the two supports
/// that carry it are equal and opposite, each E δ / H × width.
#[test]
fn prescribed_displacement_gives_uniaxial_stress() {
    let text = problem(&format!(
        "[[support]]\npart = \"upper\"\nboundary = \"top\"\nfix = [\"y\"]\nvalue = [0.0, {}]\n",
        -DELTA
    ));
    let a = common::analysis(&text);
    let inc = common::solve(&a).pop().unwrap();
    let sigma = -E * DELTA / 2.0;
    for s in a.recover(&inc.u).iter().flat_map(|p| p.element.iter()) {
        assert!(
            (s[1] - sigma).abs() < 1e-5 * sigma.abs(),
            "σyy = {} (expected {sigma})",
            s[1]
        );
        assert!(
            s[0].abs() < 1e-5 * sigma.abs() && s[2].abs() < 1e-5 * sigma.abs(),
            "{s:?}"
        );
    }
    // Reactions per support (forces of the supports on the blocks): the bottom
    // pushes up and the top pushes down, by |σ| × width.
    let r = a.reactions(&inc);
    assert!(
        (r[0][1] + sigma).abs() < 1e-5 * sigma.abs(),
        "bottom reaction {:?}",
        r[0]
    );
    assert!(
        (r[2][1] - sigma).abs() < 1e-5 * sigma.abs(),
        "top reaction {:?}",
        r[2]
    );
    assert!(
        (r[0][1] + r[2][1]).abs() < 1e-9 * sigma.abs(),
        "reactions do not balance"
    );
    // The top moved by exactly −δ at full load.
    let top = common::displacement_at(&a, &inc, "upper", [0.5, 2.0]);
    assert!((top[1] + DELTA).abs() < 1e-15);
}

/// A point load at a node is carried to the supports: the reactions balance it to
/// 1e-7 (the round-off of a tie 1e6 times stiffer than the blocks).
#[test]
fn point_load_is_balanced() {
    let text = problem("[[load]]\npart = \"upper\"\nat = [0.5, 2.0]\nforce = [0.3, -2.0]\n");
    let a = common::analysis(&text);
    let inc = common::solve(&a).pop().unwrap();
    let total = common::total_reaction(&a, &inc);
    // Round-off of the stiff tie (c = 1e6 E·t) limits the balance to about 1e-9.
    assert!(
        (total[0] + 0.3).abs() < 1e-7 * 2.0 && (total[1] - 2.0).abs() < 1e-7 * 2.0,
        "{total:?}"
    );
}

/// A steel punch (20 × 10, plane strain) an initial gap g₀ = 0.01 above a steel
/// block (40 × 20, its base clamped), paired within a search distance, its top
/// driven down by a prescribed displacement `push` over 8 increments (law
/// `contact`); `bottom` is the punch's bottom.
fn punch_above_block(bottom: f64, push: f64, increments: usize) -> String {
    Problem::compact()
        .plane("strain")
        .material("steel", 210000.0, 0.3)
        .part("block", "steel")
        .rectangle([0.0, 40.0], [0.0, 20.0], [16, 8])
        .part("punch", "steel")
        .rectangle([10.0, 30.0], [bottom, bottom + 10.0], [30, 10])
        .interface("block", "punch", "bottom")
        .law("contact")
        .iface_key("search_distance", 0.5)
        .support("block", "bottom", ["x", "y"])
        .support("punch", "top", ["x", "y"])
        .key("value", [0.0, -push])
        .increments(increments)
        .text()
}

/// A punch driven down onto a block across an initial gap g₀ = 0.01 by a
/// prescribed displacement (0.036 over 8 increments): the increments before
/// contact move it rigidly with no force anywhere — every pair open, carrying
/// nothing, its gap g₀ − the push, the reactions 0 to 1e-9 of the final one —
/// and are not flagged (they once ended "out-of-balance force 1.9e-8 of the
/// load scale", a scale of ≈ 0, and the run `completed_with_violations` with no
/// violation). After contact the punch carries what the same punch starting in
/// touch carries when pushed by the push less g₀ (to 1e-6: the gap's rigid
/// approach stores nothing), the interface transmits it (Σ f_n = the reaction),
/// and the run is `completed` with no warning.
#[test]
fn a_punch_approaching_across_a_gap_completes() {
    let (g0, push) = (0.01, 0.036);
    let a = common::analysis(&punch_above_block(20.0 + g0, push, 8));
    let incs = common::solve(&a);
    let last = incs.last().unwrap();
    let top = |inc: &cfe::solve::nonlinear::IncrementResult| a.reactions(inc)[1];
    // The support pushes the punch down (a reaction is the support's force on
    // the part).
    let final_reaction = -top(last)[1];
    assert!(final_reaction > 0.0, "the support pushes the punch down");
    let mut before = 0;
    for inc in &incs {
        let moved = push * inc.lambda;
        let rows = a.pair_rows(inc);
        if moved < g0 - 1e-9 {
            before += 1;
            for row in &rows {
                assert_eq!(row.state, cfe::coupling::PairState::Open);
                assert!(row.force_n == 0.0 && row.force_s == 0.0);
                assert!((row.gap - (g0 - moved)).abs() < 1e-9, "gap {}", row.gap);
            }
            for r in a.reactions(inc) {
                assert!(
                    r[0].hypot(r[1]) < 1e-9 * final_reaction,
                    "increment {}: reaction {r:?}",
                    inc.index
                );
            }
        }
    }
    assert_eq!(before, 2);
    // Pushed by the same net amount from touching.
    let touching = common::analysis(&punch_above_block(20.0, push - g0, 1));
    let reference = -top(&common::solve(&touching).pop().unwrap())[1];
    assert!(
        (final_reaction - reference).abs() < 1e-6 * reference,
        "{final_reaction} vs {reference} from touching"
    );
    let carried: f64 = a.pair_rows(last).iter().map(|r| r.force_n).sum();
    assert!(
        (carried - final_reaction).abs() < 1e-6 * final_reaction,
        "pairs carry {carried}, the support {final_reaction}"
    );
    let summary = a.solve().unwrap().summary;
    assert_eq!(
        summary.status,
        cfe::RunStatus::Completed,
        "{:?}",
        summary.warnings
    );
    assert!(summary.warnings.is_empty());
}
