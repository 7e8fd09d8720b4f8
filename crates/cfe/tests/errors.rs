//! Bad input and failing analyses give errors a user can act on (which part, node,
//! key or line), never a panic; converged increments stay on disk after a failure.

mod common;

use common::{Problem, Text};

use cfe::Error;
use cfe::analysis::Analysis;
use cfe::model::Model;
use std::path::Path;

/// The seed's plate on a base, without a load.
static BASE: Text = Text::new(|| Problem::plate_on_base().text());

/// The seed's load: 1500 down on the middle of the plate's top.
static LOAD_DOWN: Text = Text::new(|| Problem::spaced().plate_load_down().text());

fn parse(text: &str) -> Result<Model, Error> {
    Model::from_str(text, Path::new("bad.toml"), 1)
}

/// The error of reading `text`, which must be of the kind `kind` says; as text.
fn parse_err(text: &str, kind: impl Fn(&Error) -> bool) -> String {
    let e = parse(text).expect_err("an error");
    assert!(kind(&e), "unexpected kind of error: {e:?}");
    e.to_string()
}

/// An unknown key is an error naming the key, the file and the line.
#[test]
fn unknown_key_names_key_file_and_line() {
    let text = BASE.replace("nu = 0.31", "nu = 0.31\npoisson = 0.3");
    let e = parse_err(&text, |e| matches!(e, Error::Parse { line: Some(5), .. }));
    assert!(
        e.contains("bad.toml") && e.contains("poisson") && e.contains("line 5"),
        "{e}"
    );
}

/// A missing key is an error naming it.
#[test]
fn missing_key_is_named() {
    let e = parse_err(&BASE.replace("nu = 0.31\n", ""), |e| {
        matches!(e, Error::Parse { .. })
    });
    assert!(e.contains("nu"), "{e}");
}

/// References to undefined parts or boundaries name the line and the alternatives.
#[test]
fn undefined_part_and_boundary() {
    let e = parse_err(
        &BASE.replace("nodes = \"plate\"", "nodes = \"plat\""),
        |e| matches!(e, Error::Parse { line: Some(18), .. }),
    );
    assert!(
        e.contains("'plat'") && e.contains("line 18") && e.contains("base, plate"),
        "{e}"
    );
    let e = parse_err(
        &BASE.replace(
            "boundary = \"bottom\"\n\n[[support]]",
            "boundary = \"botom\"\n\n[[support]]",
        ),
        |e| matches!(e, Error::Parse { line: Some(_), .. }),
    );
    assert!(e.contains("botom") && e.contains("left, right, top"), "{e}");
}

/// Invalid material constants are errors naming the material's table
/// (`materials.steel.nu`) and its line, not the first part that uses it.
#[test]
fn invalid_material() {
    let e = parse_err(
        &BASE.replace("nu = 0.31", "nu = 0.7"),
        |e| matches!(e, Error::Invalid { key, line: Some(4), .. } if key == "materials.steel.nu"),
    );
    assert!(e.contains("(-1, 0.5)") && e.contains("bad.toml:4"), "{e}");
}

/// A load segment that is not on the part's boundary, and a point that matches no
/// node, are errors rather than silently lost loads.
#[test]
fn selections_that_match_nothing() {
    let text = format!(
        "{BASE}{}",
        LOAD_DOWN.replace("[114.0, 135.0]", "[114.0, 130.0]")
    );
    let e = parse_err(&text, |e| matches!(e, Error::Parse { .. }));
    assert!(e.contains("must lie on the part's boundary"), "{e}");
    let text =
        format!("{BASE}[[load]]\npart = \"plate\"\nat = [31.0, 135.0]\nforce = [0.0, 1.0]\n");
    let e = parse_err(&text, |e| matches!(e, Error::Parse { .. }));
    assert!(e.contains("matches no node"), "{e}");
}

/// Coupling nodes that lie in no host element are listed with coordinates (the
/// first five in the message, every one in the error's `nodes`).
#[test]
fn coupling_nodes_outside_the_host() {
    let text = BASE.replace("x = [30.0, 170.0]", "x = [150.0, 290.0]")
        + LOAD_DOWN
            .replace("86.0", "206.0")
            .replace("114.0", "234.0")
            .as_str();
    let model = parse(&text).unwrap();
    let e = Analysis::new(model).err().expect("orphans");
    let Error::OrphanNodes {
        interface, nodes, ..
    } = &e
    else {
        panic!("unexpected kind of error: {e:?}");
    };
    assert_eq!(interface, "base/plate");
    for at in [[210.0, 120.0], [290.0, 120.0]] {
        assert!(nodes.iter().any(|(_, x)| *x == at), "{nodes:?}");
    }
    // The message lists the first five (all 18 are in `nodes`) and counts the rest.
    assert_eq!(nodes.len(), 18);
    let e = e.to_string();
    assert!(
        e.contains("lie on no host boundary edge within the tolerance")
            && e.contains("(210, 120)")
            && e.contains("(225, 120)")
            && e.contains("… and 13 more"),
        "{e}"
    );
}

/// A plate pulled off its base (uniformly, over its whole top) is left without support: with implex the first
/// increment (all bonded) converges and is written; the second opens every pair
/// and fails with an error naming the plate; increment 1 stays on disk and the
/// summary records the failure.
#[test]
fn unsupported_part_fails_cleanly_and_keeps_results() {
    let pull = "[[load]]\npart = \"plate\"\nboundary = \"top\"\nforce = [0.0, 1500.0]\n";
    let text = format!("{BASE}{pull}[analysis]\nscheme = \"implex\"\nincrements = 3\n");
    let mut a = Analysis::new(parse(&text).unwrap()).unwrap();
    let out = std::env::temp_dir().join(format!("cfe-test-unsupported-{}", std::process::id()));
    let e = a.run(&out, &mut |_| {}).expect_err("must fail");
    assert!(
        matches!(&e, Error::Unsupported { parts, .. } if parts == &["plate"]),
        "{e:?}"
    );
    let e = e.to_string();
    assert!(
        e.contains("'plate'")
            && e.contains("without support")
            && e.contains("29 of its 29 coupling pairs open"),
        "{e}"
    );
    assert!(out.join("vtu/parts_0001.vtu").is_file());
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        summary.contains("\"failed\"") && summary.contains("\"converged_increments\": 1"),
        "{summary}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// The same pull with active-set fails in the first increment, also naming the plate.
#[test]
fn unsupported_part_active_set() {
    let text = format!("{BASE}{}", LOAD_DOWN.replace("-1500.0", "1500.0"));
    let a = Analysis::new(parse(&text).unwrap()).unwrap();
    let e = a.solve().err().unwrap();
    assert!(
        matches!(&e, Error::Unsupported { parts, .. } if parts == &["plate"]),
        "{e:?}"
    );
    let e = e.to_string();
    assert!(
        e.contains("'plate'") && e.contains("without support"),
        "{e}"
    );
}

/// A model with no support at all is singular, named part by part.
#[test]
fn no_support_at_all() {
    let text = BASE.replace(
        "[[support]]\npart = \"base\"\nboundary = \"bottom\"\nfix = [\"x\", \"y\"]\n",
        "",
    ) + &LOAD_DOWN;
    let a = Analysis::new(parse(&text).unwrap()).unwrap();
    let e = a.solve().err().unwrap();
    assert!(
        matches!(&e, Error::Unsupported { parts, .. } if parts == &["base", "plate"]),
        "{e:?}"
    );
    let e = e.to_string();
    assert!(e.contains("'base'") && e.contains("'plate'"), "{e}");
}

/// Coupling nodes moved onto the host edges must leave the node part's mesh
/// valid: a plate meshed 0.4 mm into the base (within the 5 % tolerance of the
/// base's 10 mm edges) with one 0.4 mm row of cells along it collapses when its
/// bottom nodes are moved up, and the error names the interface, the move and the
/// element.
#[test]
fn moving_coupling_nodes_must_not_spoil_the_node_part() {
    let text = BASE.replace(
        "rectangle = { x = [30.0, 170.0], y = [120.0, 135.0], cells = [28, 6] }",
        "rectangle = { x = [30.0, 170.0], y = [119.6, 120.0], cells = [28, 1] }",
    );
    let model = parse(&text).unwrap();
    let e = Analysis::new(model).err().expect("collapsed");
    assert!(
        matches!(&e, Error::Coupling { interface, .. } if interface == "base/plate"),
        "{e:?}"
    );
    let e = e.to_string();
    assert!(
        e.contains("interface 'base/plate'")
            && e.contains("by up to 4.0000")
            && e.contains("degenerate"),
        "{e}"
    );
}

/// An annulus with its radii the wrong way round, and a pressure given together
/// with a force, are errors naming the part and what to give instead.
#[test]
fn annulus_and_pressure_misuse() {
    let ring = BASE.replace(
        "rectangle = { x = [0.0, 200.0], y = [0.0, 120.0], cells = [20, 12] }",
        "annulus = { r = [20.0, 10.0], cells = [2, 8] }",
    );
    let e = parse_err(&ring, |e| matches!(e, Error::Parse { line: Some(_), .. }));
    assert!(
        e.contains("part 'base': annulus needs 0 < r0 < r1") && e.contains("r = [20.0, 10.0]"),
        "{e}"
    );
    let both = format!(
        "{BASE}[[load]]\npart = \"plate\"\nboundary = \"top\"\npressure = 1.0\nforce = [0.0, 1.0]\n"
    );
    let e = parse_err(&both, |e| matches!(e, Error::Parse { line: Some(_), .. }));
    assert!(
        e.contains("a pressure [[load]] needs `boundary` and `pressure` only"),
        "{e}"
    );
    let neither = format!("{BASE}[[load]]\npart = \"plate\"\nboundary = \"top\"\n");
    let e = parse_err(&neither, |e| {
        matches!(e, Error::Parse { line: Some(_), .. })
    });
    assert!(
        e.contains("needs `force`") && e.contains("or `pressure`"),
        "{e}"
    );
}

/// A two-value array with another number of values (a third force component, a
/// third cell count, one coordinate) is an error naming the line, not silently cut
/// to two; so is a `fix` that names a component twice or none.
#[test]
fn arrays_of_the_wrong_length_and_bad_fix() {
    for (from, to) in [
        ("force = [0.0, -1500.0]", "force = [0.0, -1500.0, -99999.0]"),
        ("cells = [20, 12] }", "cells = [20, 12, 3] }"),
        ("x = [0.0, 200.0]", "x = [0.0]"),
        ("from = [86.0, 135.0]", "from = [86.0, 135.0, 1.0]"),
    ] {
        let text = format!("{BASE}{LOAD_DOWN}").replacen(from, to, 1);
        assert_ne!(text, format!("{BASE}{LOAD_DOWN}"), "{from}");
        let line = 1 + text[..text.find(to).unwrap()].matches('\n').count();
        let e = parse_err(&text, |e| matches!(e, Error::Parse { .. }));
        assert!(
            e.contains("exactly 2 values") && e.contains(&format!("line {line}")),
            "{to}: {e}"
        );
    }
    for fix in ["[\"x\", \"x\"]", "[]", "[\"y\", \"x\", \"y\"]"] {
        let text = BASE.replace("fix = [\"x\", \"y\"]", &format!("fix = {fix}"));
        let e = parse_err(&text, |e| matches!(e, Error::Parse { line: Some(_), .. }));
        assert!(
            e.contains("`fix`") && e.contains("base/bottom"),
            "{fix}: {e}"
        );
    }
}

/// Sizes are checked before memory is spent: a refinement or a cell count whose
/// node count overflows is an error naming the part, and a model whose estimated
/// memory exceeds what the machine has is refused before meshing (no allocation
/// failure, no abort).
#[test]
fn oversized_models_are_refused_before_meshing() {
    let text = format!("{BASE}{LOAD_DOWN}");
    for k in [1usize << 32, (1usize << 62) + 1] {
        let e = Model::from_str(&text, Path::new("bad.toml"), k).unwrap_err();
        assert!(matches!(e, Error::Parse { .. }), "{e:?}");
        assert!(e.to_string().contains("too many to count"), "{e}");
    }
    if cfe::output::memory::available_memory_bytes().is_some() {
        let e = Model::from_str(&text, Path::new("bad.toml"), 100_000).unwrap_err();
        assert!(
            matches!(e, Error::TooLarge { unknowns, .. } if unknowns > 8_000_000_000_000),
            "{e:?}"
        );
        let huge = text.replace("cells = [20, 12]", "cells = [100000, 100000]");
        let e = parse_err(&huge, |e| matches!(e, Error::TooLarge { .. }));
        assert!(e.contains("GiB") && e.contains("unknowns"), "{e}");
    }
}

/// A run asked to stop (as by SIGINT) ends after the increment being solved with
/// `Error::Interrupted`; the folder is a consistent snapshot: `summary.json` says
/// `interrupted`, `results.pvd` names only files that exist, no `.tmp` file is
/// left, and the files of an earlier, longer run in the same folder (a temporary
/// file of its own included) are gone while a user's own file stays.
#[test]
fn interrupted_run_leaves_a_consistent_folder() {
    let out = std::env::temp_dir().join(format!("cfe-test-interrupt-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let mut a = common::analysis(&format!("{BASE}{LOAD_DOWN}"));
    a.run(&out, &mut |_| {}).unwrap();
    assert!(out.join("vtu/parts_0010.vtu").is_file());
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    // The temporary file of a write the earlier run's kill interrupted (its
    // manifest lists it).
    std::fs::write(out.join("vtu/.parts_0003.vtu.tmp"), "half").unwrap();

    let stop = std::sync::atomic::AtomicUsize::new(0);
    let e = a
        .run_until(
            &out,
            &mut |inc| {
                if inc.index == 2 {
                    stop.store(15, std::sync::atomic::Ordering::Relaxed);
                }
            },
            &stop,
        )
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::Interrupted {
                increment: 2,
                signal: 15
            }
        ),
        "{e:?}"
    );
    let summary = common::summary_json(&out);
    assert_eq!(summary["status"], "interrupted");
    assert_eq!(summary["converged_increments"], 2);
    let pvd = std::fs::read_to_string(out.join("results.pvd")).unwrap();
    assert_eq!(common::pvd_files_exist(&out, &pvd), 4, "{pvd}");
    let vtu = common::vtu_files(&out);
    assert_eq!(
        vtu,
        [
            "pairs_0001.vtu",
            "pairs_0002.vtu",
            "parts_0001.vtu",
            "parts_0002.vtu"
        ]
    );
    assert!(
        !out.join("sigma_yy.png").exists(),
        "a picture of the earlier run"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// The memory check after the symbolic factorization refuses, with a typed
/// error naming the estimate and the available memory, a solve whose estimated
/// peak exceeds an (injected) available amount, and passes one that fits.
#[test]
fn memory_check_refuses_before_the_factorization() {
    let a = common::analysis(&format!("{BASE}{LOAD_DOWN}"));
    let solver = a.solver().unwrap();
    let e = cfe::Analysis::check_memory(&solver, Some(1 << 20)).unwrap_err();
    match &e {
        Error::TooLarge {
            bytes, available, ..
        } => assert!(*bytes > *available && *available == 1 << 20, "{e:?}"),
        other => panic!("{other:?}"),
    }
    assert!(
        e.to_string().contains("GiB") && e.to_string().contains("nonzeros"),
        "{e}"
    );
    assert!(cfe::Analysis::check_memory(&solver, Some(u64::MAX)).is_ok());
    assert!(cfe::Analysis::check_memory(&solver, None).is_ok());
}

/// An interface between faces 1000 mm apart with a 1 mm `search_distance`
/// (node or segment coupling) is refused where its pairs are sought, naming the
/// interface, the distance and the nearest gap found (exactly 1000: the plate's
/// bottom nodes lie straight above the base's top) — not solved and then failed
/// as a picture without points.
#[test]
fn faces_beyond_the_search_distance_have_no_pair() {
    for coupling in ["node", "segment"] {
        let text = format!(
            "{}{}",
            BASE.replace("y = [120.0, 135.0]", "y = [1120.0, 1135.0]")
                .replace(
                    "boundary = \"bottom\"\n\n[[support]]",
                    &format!(
                        "boundary = \"bottom\"\nsearch_distance = 1.0\ncoupling = \"{coupling}\"\n\n[[support]]"
                    )
                ),
            LOAD_DOWN.replace(", 135.0]", ", 1135.0]")
        );
        let model = parse(&text).expect("a valid model");
        let e = Analysis::new(model).err().expect("no pair refused");
        match &e {
            Error::NoPairs {
                interface,
                search_distance,
                nearest: Some(d),
                ..
            } => {
                assert_eq!(interface, "base/plate", "{e}");
                assert_eq!(*search_distance, 1.0);
                assert!((d - 1000.0).abs() < 1e-9, "{coupling}: nearest {d}");
            }
            other => panic!("{coupling}: {other:?}"),
        }
        let m = e.to_string();
        assert!(
            m.contains("no pair within search_distance = 1")
                && m.contains("interface 'base/plate'")
                && m.contains("1e3 away"),
            "{m}"
        );
    }
}

/// Some nodes within the search distance: the interface is built, the others
/// unpaired (the refusal above is for an interface that couples nothing).
#[test]
fn faces_partly_within_the_search_distance_are_paired() {
    // The plate's bottom 0.5 above the base's top: every node is within 1.0;
    // within 0.4 none is, and the refusal names 0.5.
    let text = BASE
        .replace("y = [120.0, 135.0]", "y = [120.5, 135.5]")
        .replace(
            "boundary = \"bottom\"\n\n[[support]]",
            "boundary = \"bottom\"\nsearch_distance = 1.0\n\n[[support]]",
        );
    let a = Analysis::new(parse(&text).unwrap()).expect("paired");
    assert_eq!(a.interfaces[0].elements.len(), 29);
    let text = text.replace("search_distance = 1.0", "search_distance = 0.4");
    match Analysis::new(parse(&text).unwrap()).err() {
        Some(Error::NoPairs {
            nearest: Some(d), ..
        }) => assert!((d - 0.5).abs() < 1e-12, "{d}"),
        other => panic!("{other:?}"),
    }
}

/// Unnamed interfaces, supports and loads get default names, made unique with
/// ` (2)`, ` (3)` when they repeat (a second support on one boundary); a given
/// name is kept and a default equal to it moves aside. Names are then unique
/// in the model, as results and reactions are keyed by them.
#[test]
fn default_names_are_made_unique() {
    let support_y = "\n[[support]]\npart = \"base\"\nboundary = \"bottom\"\nfix = [\"y\"]\n";
    let named = "\n[[support]]\nname = \"base/bottom (2)\"\npart = \"base\"\nboundary = \"left\"\nfix = [\"x\"]\n";
    let text = format!("{BASE}{support_y}{support_y}{named}{LOAD_DOWN}{LOAD_DOWN}");
    let m = parse(&text).unwrap();
    let names: Vec<&str> = m.supports.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "base/bottom",
            "base/bottom (3)",
            "base/bottom (4)",
            "base/bottom (2)"
        ]
    );
    assert_ne!(m.loads[0].name, m.loads[1].name);
    assert!(m.loads[1].name.ends_with(" (2)"), "{}", m.loads[1].name);
    m.check_names().unwrap();
    // Two unnamed interfaces of the same host and node part (the plate's
    // bottom and its top, which no base edge holds: names are given before
    // anything is paired) are `base/plate` and `base/plate (2)`.
    let twice = BASE.replace(
        "[[interface]]\nhost = \"base\"\nnodes = \"plate\"\nboundary = \"bottom\"\n",
        "[[interface]]\nhost = \"base\"\nnodes = \"plate\"\nboundary = \"bottom\"\n\n[[interface]]\nhost = \"base\"\nnodes = \"plate\"\nboundary = \"top\"\n",
    );
    let m = parse(&twice).unwrap();
    let names: Vec<&str> = m.interfaces.iter().map(|i| i.name.as_str()).collect();
    assert_eq!(names, ["base/plate", "base/plate (2)"]);
}

/// A model built or changed in code is checked as a file is: a name given to
/// two interfaces (or supports, loads, steps, parts) is refused by
/// `Model::from_parts` and by `Analysis::new`, with the key counting from 1.
#[test]
fn names_given_twice_in_code_are_refused() {
    let m = parse(&format!("{BASE}{LOAD_DOWN}")).unwrap();
    let e = cfe::Model::from_parts(
        "in code",
        m.parts.clone(),
        vec![m.interfaces[0].clone(), m.interfaces[0].clone()],
        m.supports.clone(),
        m.loads.clone(),
        m.settings.clone(),
    )
    .expect_err("refused");
    match &e {
        Error::DuplicateName {
            key, name, line, ..
        } => {
            assert_eq!(key, "interface#2.name");
            assert_eq!(name, "base/plate");
            assert_eq!(*line, None);
        }
        other => panic!("{other:?}"),
    }
    assert!(
        e.to_string().starts_with("model: `interface#2.name`"),
        "{e}"
    );
    cfe::Model::from_parts(
        "in code",
        m.parts.clone(),
        m.interfaces.clone(),
        m.supports.clone(),
        m.loads.clone(),
        m.settings.clone(),
    )
    .expect("unique names");
    for kind in ["part", "support", "load"] {
        let mut changed = parse(&format!("{BASE}{LOAD_DOWN}{LOAD_DOWN}")).unwrap();
        match kind {
            "part" => changed.parts[1].name = changed.parts[0].name.clone(),
            "support" => changed.supports.push(changed.supports[0].clone()),
            _ => changed.loads[1].name = changed.loads[0].name.clone(),
        }
        match Analysis::new(changed).err() {
            Some(Error::DuplicateName { key, .. }) => {
                assert_eq!(key, format!("{kind}#2.name"))
            }
            other => panic!("{kind}: {other:?}"),
        }
    }
}

/// Plane strain with ν = 0.4999999 (bulk modulus 5e6 × shear): the T3 parts
/// lock, which is said in the model's warnings, in `cfe check`'s description
/// and in the summary's notes at increment 0 (advice: Q4 or plane stress), and
/// does not mark the run as breaking its law. Q4 parts get their own advice;
/// plane stress or a moderate ν get none.
#[test]
fn nearly_incompressible_plane_strain_warns_of_locking() {
    let strain = |nu: &str, plane: &str| {
        format!("plane = \"{plane}\"\n{BASE}{LOAD_DOWN}")
            .replace("nu = 0.31", &format!("nu = {nu}"))
    };
    let m = parse(&strain("0.4999999", "strain")).unwrap();
    let w = m.warnings();
    assert_eq!(w.len(), 2, "{w:?}");
    for (w, part) in w.iter().zip(["base", "plate"]) {
        assert!(
            w.contains(&format!("part '{part}'"))
                && w.contains("T3 elements lock")
                && w.contains("Q4")
                && w.contains("plane = \"stress\"")
                && w.contains("5.0e6"),
            "{w}"
        );
    }
    let a = Analysis::new(m).unwrap();
    assert!(a.describe().contains("warning: part 'base'"));
    let res = a.solve().unwrap();
    let notes: Vec<_> = res
        .summary
        .notes
        .iter()
        .filter(|n| n.increment == 0)
        .collect();
    assert_eq!(notes.len(), 2);
    assert!(notes[0].message.contains("lock"));
    assert!(
        res.summary
            .warnings
            .iter()
            .all(|w| !w.message.contains("lock"))
    );
    // Q4 parts: warned, with the Q4 advice.
    let q4 = strain("0.4999999", "strain").replace(
        "cells = [20, 12] }",
        "cells = [20, 12], elements = \"q4\" }",
    );
    let w = parse(&q4).unwrap().warnings();
    assert_eq!(w.len(), 2);
    assert!(w[0].contains("Q4 elements (full integration)"), "{}", w[0]);
    assert!(w[1].contains("T3 elements lock"), "{}", w[1]);
    for (nu, plane) in [
        ("0.4999999", "stress"),
        ("0.45", "strain"),
        ("0.31", "strain"),
    ] {
        assert!(
            parse(&strain(nu, plane)).unwrap().warnings().is_empty(),
            "{nu} {plane}"
        );
    }
}
