//! The history of a run (issue 40): every converged increment's step, load
//! factor, time, reactions, contact resultants, contact length, largest
//! pressure and probe displacements, kept in `summary.json`'s `history`,
//! written as `history.csv` and drawn as `history.png`. Checked against
//! independent truth: equilibrium (each increment's reaction balances its
//! load, the contact resultant carries it), linearity of a tied model in the
//! load factor, the probe's value interpolated in its element (the exact
//! linear field of a stretched strip) or its nearest node's outside; the
//! input checks by error variant.

mod common;

use cfe::Error;
use cfe::analysis::Analysis;
use cfe::model::Model;
use std::path::Path;

/// A unit block (4 × 4 T3) on a base (5 × 3 T3, bottom clamped) with the
/// interface law `law`, pressed by 2 N on its top over 4 increments, a probe
/// `tip` near the block's top corner (0.98, 1.01: nearest node (1, 1)),
/// `extra` appended.
fn pressed(law: &str, extra: &str) -> String {
    format!(
        "{}[[probe]]\nname = \"tip\"\npart = \"block\"\nat = [0.98, 1.01]\n{extra}",
        common::Problem::block_on_base()
            .law(law)
            .load("block", "top", [0.0, -2.0])
            .increments(4)
            .text()
    )
}

/// Each increment's history row: the reaction balances λ × the load, the
/// interface's normal resultant carries it (Σ f_n = λ P) and its tangential
/// resultant vanishes (the block is held in x by the interface alone and
/// loaded in y only), the largest pressure is at least the mean, the tied model's probe displacement grows linearly with λ and is
/// that of node (1, 1); `history.csv` has one row per increment under named
/// columns, and `history.png` is drawn and listed in the folder's manifest.
#[test]
fn history_rows_follow_every_increment() {
    let out = std::env::temp_dir().join(format!("cfe-history-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let mut a =
        Analysis::new(Model::from_str(&pressed("contact", ""), Path::new("t.toml"), 1).unwrap())
            .unwrap();
    let summary = a.run(&out, &mut |_| {}).unwrap();
    let h = &summary.history;
    assert_eq!(h.len(), 4);
    for (k, row) in h.iter().enumerate() {
        let lambda = (k + 1) as f64 / 4.0;
        assert_eq!(row.increment, k + 1);
        assert_eq!((row.step.as_str(), row.step_index), ("step-1", 1));
        assert!((row.load_factor - lambda).abs() < 1e-15);
        assert!(
            (row.reactions[0].fy - 2.0 * lambda).abs() < 1e-9,
            "{:?}",
            row.reactions
        );
        assert!(row.reactions[0].fx.abs() < 1e-9);
        let i = &row.interfaces[0];
        assert!(
            (i.force_n - 2.0 * lambda).abs() < 1e-6,
            "Σ f_n = {}",
            i.force_n
        );
        assert!(i.force_s.abs() < 1e-6, "Σ f_s = {}", i.force_s);
        assert!(i.contact_length > 0.0 && i.contact_length <= 1.0 + 1e-12);
        assert!(
            i.max_pressure >= i.force_n / 1.0 - 1e-9,
            "max ≥ mean pressure"
        );
    }
    assert_eq!(summary.probes[0].node, 24);
    assert_eq!((summary.probes[0].x, summary.probes[0].y), (1.0, 1.0));
    let csv = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 5);
    assert!(lines[0].starts_with(
        "increment,step,step_index,load_factor,time,reaction:base/bottom.fx,reaction:base/bottom.fy,interface:base/block.force_n"
    ));
    assert!(lines[0].ends_with("probe:tip.ux,probe:tip.uy"));
    assert!(lines[4].starts_with("4,step-1,1,1,1,"));
    assert_eq!(
        &std::fs::read(out.join("history.png")).unwrap()[..4],
        b"\x89PNG"
    );
    let manifest = std::fs::read_to_string(out.join(".cfe-manifest")).unwrap();
    assert!(manifest.lines().any(|l| l == "history.csv"));
    assert!(manifest.lines().any(|l| l == "history.png"));
    let json = common::summary_json(&out);
    assert_eq!(json["history"].as_array().unwrap().len(), 4);
    let _ = std::fs::remove_dir_all(&out);

    // Tied: linear in λ, and the probe is node (1, 1)'s displacement.
    let a = common::analysis(&pressed("rigid", ""));
    let res = a.solve().unwrap();
    let h = &res.summary.history;
    let last = h.last().unwrap().probes[0].uy;
    let node = common::displacement_at(&a, &res.last, "block", [1.0, 1.0]);
    assert_eq!(last, node[1]);
    assert!(last < 0.0);
    for (k, row) in h.iter().enumerate() {
        let lambda = (k + 1) as f64 / 4.0;
        assert!((row.probes[0].uy - lambda * last).abs() < 1e-12 * last.abs());
    }
}

/// A probe on a part that does not exist and a `history_plot` column that is
/// none of `history.csv`'s are `Invalid` errors naming the key and its line;
/// a valid `history_plot` is accepted.
#[test]
fn probes_and_plot_are_checked() {
    let invalid = |text: String, key: &str| match Model::from_str(&text, Path::new("t.toml"), 1) {
        Err(Error::Invalid { key: k, line, .. }) => {
            assert_eq!(k, key);
            assert!(line.is_some());
        }
        other => panic!("{key}: {other:?}"),
    };
    invalid(
        pressed("contact", "").replace(
            "part = \"block\"\nat = [0.98",
            "part = \"blok\"\nat = [0.98",
        ),
        "probe.tip.part",
    );
    invalid(
        pressed(
            "contact",
            "[output]\nhistory_plot = { x = \"probe:tip.uz\", y = \"reaction:base/bottom.fy\" }\n",
        ),
        "output.history_plot.x",
    );
    let ok = pressed(
        "contact",
        "[output]\nhistory_plot = { x = \"probe:tip.uy\", y = \"interface:base/block.force_n\" }\n",
    );
    let m = Model::from_str(&ok, Path::new("t.toml"), 1).unwrap();
    assert_eq!(
        m.history_plot,
        Some([
            "probe:tip.uy".to_string(),
            "interface:base/block.force_n".to_string()
        ])
    );
}

/// Probes are interpolated inside their element (issue 40): a plane-stress
/// strip 10 × 2 (Q4 and T3) pulled by σ = 50 on its right end, held in x on
/// its left and in y on its bottom, has the exact linear field
/// u = (σ x / E, −ν σ y / E), which the elements interpolate exactly: a probe
/// at a point inside an element (3.3, 0.7) records it to 1e-12 (the nearest
/// node's value differs by 10 %), `summary.json` names the element; a probe on
/// a node records that node's value bit for bit, and one outside the part
/// its nearest node's.
#[test]
fn probes_are_interpolated_inside_their_element() {
    for elements in ["q4", "t3"] {
        let text = format!(
            "plane = \"stress\"\n[materials.m]\nE = 1000.0\nnu = 0.25\n[[part]]\nname = \"strip\"\nmaterial = \"m\"\nrectangle = {{ x = [0.0, 10.0], y = [0.0, 2.0], cells = [5, 2], elements = \"{elements}\" }}\n[[support]]\npart = \"strip\"\nboundary = \"left\"\nfix = [\"x\"]\n[[support]]\npart = \"strip\"\nboundary = \"bottom\"\nfix = [\"y\"]\n[[load]]\npart = \"strip\"\nboundary = \"right\"\npressure = -50.0\n[[probe]]\nname = \"inside\"\npart = \"strip\"\nat = [3.3, 0.7]\n[[probe]]\nname = \"node\"\npart = \"strip\"\nat = [4.0, 1.0]\n[[probe]]\nname = \"outside\"\npart = \"strip\"\nat = [10.2, 2.1]\n[analysis]\nincrements = 1\n"
        );
        let a = common::analysis(&text);
        let res = common::solve_completed(&a);
        let row = res.summary.history.last().unwrap();
        let exact = |x: [f64; 2]| [50.0 * x[0] / 1000.0, -0.25 * 50.0 * x[1] / 1000.0];
        let want = exact([3.3, 0.7]);
        let got = [row.probes[0].ux, row.probes[0].uy];
        for c in 0..2 {
            assert!(
                (got[c] - want[c]).abs() < 1e-12 * want[0].abs(),
                "{elements}: {got:?} vs {want:?}"
            );
        }
        let near = [res.summary.probes[0].x, res.summary.probes[0].y];
        assert!((exact(near)[0] - want[0]).abs() > 0.05 * want[0]);
        assert!(res.summary.probes[0].element.is_some());
        let node = common::displacement_at(&a, &res.last, "strip", [4.0, 1.0]);
        assert_eq!([row.probes[1].ux, row.probes[1].uy], node);
        assert_eq!(res.summary.probes[1].element, None);
        let corner = common::displacement_at(&a, &res.last, "strip", [10.0, 2.0]);
        assert_eq!([row.probes[2].ux, row.probes[2].uy], corner);
        assert_eq!(res.summary.probes[2].element, None);
    }
}
