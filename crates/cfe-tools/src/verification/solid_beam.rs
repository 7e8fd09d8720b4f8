//! A tied non-matching 3D cantilever against beam theory and the conforming
//! mesh, and a 2D plane-strain contact model extruded one element thick
//! against the 2D answer.

use super::solid::{face_load, hold, interface, part, roller, solve};
use super::{Case, Table, orders, prepare, sci};
use cfe::coupling::{Law, PairState};
use cfe::dim::D3;
use cfe::domain::FaceLoad;
use cfe::error::{Error, Result};
use cfe::mesh::{Mesh, SolidKind};

const E: f64 = 210_000.0;
const NU: f64 = 0.3;
/// The cantilever's length and its square section's side.
const LENGTH: f64 = 10.0;
const SIDE: f64 = 1.0;
/// The tip load (a shear traction P / A on the end face, along −z).
const P: f64 = 1.0;

fn hex(x: [f64; 2], cells: [usize; 3]) -> Mesh<D3> {
    Mesh::<D3>::block(x, [0.0, SIDE], [0.0, SIDE], cells, SolidKind::Hex8)
}

/// The mean z displacement of the nodes of side `side` of part `p`.
fn mean_uz(s: &super::solid::Solved, p: usize, side: &str) -> f64 {
    let nodes = s.analysis.model.parts[p]
        .mesh
        .boundary_nodes(side)
        .unwrap_or_default();
    nodes.iter().map(|&n| s.u(p, n)[2]).sum::<f64>() / nodes.len() as f64
}

/// The tip deflection (mean over the end face, > 0 downwards) of the
/// conforming cantilever of `c` cells across (10 c along), clamped at x = 0.
fn conforming(c: usize) -> Result<f64> {
    let parts = vec![part("beam", hex([0.0, LENGTH], [10 * c, c, c]), E, NU)?];
    let supports = vec![hold(&parts, 0, "left", [true; 3], [0.0; 3])?];
    let load = face_load(&parts, 0, "right", FaceLoad::Traction([0.0, 0.0, -P]), 0)?;
    let s = solve("cantilever", parts, vec![], supports, vec![load], &[1])?;
    Ok(-mean_uz(&s, 0, "right"))
}

/// The tip deflection of the cantilever cut at x = L/2 into two parts meshed
/// apart, tied: the root half `c` cells across (5 c along) hosts the tip
/// half's face, the tip half 3c/2 across (15c/2 along), non-nested.
fn tied(c: usize) -> Result<(f64, bool)> {
    let f = 3 * c / 2;
    let parts = vec![
        part("root", hex([0.0, LENGTH / 2.0], [5 * c, c, c]), E, NU)?,
        part("tip", hex([LENGTH / 2.0, LENGTH], [5 * f, f, f]), E, NU)?,
    ];
    let h = SIDE / c as f64;
    let def = interface(&parts, 0, 1, "left", Law::Rigid, 1e3 * E * h)?;
    let supports = vec![hold(&parts, 0, "left", [true; 3], [0.0; 3])?];
    let load = face_load(&parts, 1, "right", FaceLoad::Traction([0.0, 0.0, -P]), 0)?;
    let s = solve(
        "tied cantilever",
        parts,
        vec![def],
        supports,
        vec![load],
        &[1],
    )?;
    Ok((-mean_uz(&s, 1, "right"), s.completed()))
}

/// The tied non-matching cantilever against beam theory and the conforming
/// mesh, section cells 2, 4 (and 8).
pub fn cantilever(quick: bool) -> Result<Case> {
    let levels: &[usize] = if quick { &[2, 4] } else { &[2, 4, 8] };
    let i = SIDE.powi(4) / 12.0;
    let g = E / (2.0 * (1.0 + NU));
    let kappa = 10.0 * (1.0 + NU) / (12.0 + 11.0 * NU);
    let bending = P * LENGTH.powi(3) / (3.0 * E * i);
    let shear = P * LENGTH / (kappa * g * SIDE * SIDE);
    let beam = bending + shear;
    let mut tied_w = Vec::new();
    let mut conf_w = Vec::new();
    let mut passed = true;
    for &c in levels {
        let (w, ok) = tied(c)?;
        passed &= ok;
        tied_w.push(w);
        conf_w.push(conforming(c)?);
    }
    let err = |w: &[f64]| w.iter().map(|v| v / beam - 1.0).collect::<Vec<_>>();
    let (et, ec) = (err(&tied_w), err(&conf_w));
    let (ot, oc) = (orders(&et), orders(&ec));
    let mut table = Table {
        caption: format!(
            "Tip deflection (mean u_z over the end face) against Timoshenko's beam: PL³/(3EI) = {} + PL/(κGA) = {} (κ = 10(1 + ν)/(12 + 11ν)) = {}; the order of the error against it when the cell size halves; the tied model against the conforming one of the root's cells.",
            sci(bending),
            sci(shear),
            sci(beam)
        ),
        header: [
            "cells across (root / tip)",
            "tied",
            "error",
            "order",
            "conforming",
            "error",
            "order",
            "tied / conforming − 1",
        ]
        .map(String::from)
        .to_vec(),
        rows: Vec::new(),
    };
    let mut rel = Vec::new();
    for (k, &c) in levels.iter().enumerate() {
        let r = tied_w[k] / conf_w[k] - 1.0;
        rel.push(r);
        table.rows.push(vec![
            format!("{c} / {}", 3 * c / 2),
            sci(tied_w[k]),
            format!("{:+.3} %", 100.0 * et[k]),
            ot[k].clone(),
            sci(conf_w[k]),
            format!("{:+.3} %", 100.0 * ec[k]),
            oc[k].clone(),
            format!("{:+.3} %", 100.0 * r),
        ]);
    }
    // Self-convergence (no reference): the order from three levels'
    // successive differences.
    let self_order =
        |w: &[f64]| (w.len() >= 3).then(|| ((w[1] - w[0]) / (w[2] - w[1])).abs().log2());
    let (st, sc) = (self_order(&tied_w), self_order(&conf_w));
    let n = levels.len() - 1;
    // HEX8 (full integration) is too stiff in bending on coarse sections
    // (−4 % at 4 cells across, −1.6 % at 8): the tied model must be no
    // farther from beam theory than the conforming one plus 0.5 %, within
    // TOL_BEAM at the finest level, its difference from the conforming mesh
    // falling with h and within TOL_CONF.
    passed &= et[n].abs() < TOL_BEAM
        && et.iter().zip(&ec).all(|(t, c)| t.abs() <= c.abs() + 0.005)
        && et[n].abs() < et[0].abs()
        && rel[n].abs() < TOL_CONF
        && rel.windows(2).all(|w| w[1].abs() < w[0].abs())
        && st.is_none_or(|p| p > 1.5);
    let fmt = |o: Option<f64>| o.map_or("—".into(), |p| format!("{p:.2}"));
    Ok(Case {
        title: "3D tied non-matching cantilever".into(),
        setup: format!(
            "A cantilever {LENGTH} × {SIDE} × {SIDE} mm (E = 210 GPa, ν = 0.3) clamped at x = 0 (every component of the root face), a shear traction P/A = {P} MPa along −z on its end face. Tied: cut at x = L/2 into two HEX8 parts meshed apart — the root half c × c cells across (5c along) hosting the tip half's face, the tip half 3c/2 × 3c/2 (non-nested faces) — joined by `rigid` node coupling (c_n = c_s = 1e3 E h, h the root's cell: the tip deflection moves by 1e-5 of itself from 1e3 to 1e4 E h, while 1e4–1e5 E h leave an out-of-balance force above 1e-8 of the 1 N load on the finest mesh, `completed_imprecise`). Conforming: one HEX8 block of c × c × 10c.\n\n```text\n  ▨|‾‾‾‾‾‾‾‾‾‾‾‾‾‾|‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾|\n  ▨|  root (c)    ‖  tip (3c/2)    | ↓ P\n  ▨|______________|________________|\n   x = 0        x = L/2 (tied)    x = L\n```"
        ),
        reference: "Timoshenko's cantilever: w = PL³/(3EI) + PL/(κGA), κ = 10(1 + ν)/(12 + 11ν) for a rectangle (Cowper 1966) — a beam theory: the 3D clamp (no Poisson contraction at the root) and the end's traction differ from it by a fraction of a per cent, so the error stalls there; and the conforming mesh of the root's cells (the same discretization without the cut).".into(),
        tables: vec![table],
        plots: vec![],
        verdict: format!(
            "At the finest level the tied cantilever is {:+.3} % from beam theory (asserted {:.0} %, falling with h, and at every level no farther than the conforming mesh + 0.5 %: HEX8 with full integration is stiff in bending on coarse sections) and {:+.3} % from the conforming mesh (asserted {:.0} %, falling with h; the tied model is the more flexible, its tip half being finer): the cut with non-nested faces costs far less than the element's own error. Self-convergence order from three levels: tied {}, conforming {} (full run; asserted > 1.5, HEX8's 2 for displacements).",
            100.0 * et[n],
            100.0 * TOL_BEAM,
            100.0 * rel[n],
            100.0 * TOL_CONF,
            fmt(st),
            fmt(sc)
        ),
        passed,
    })
}

/// The cantilever's tolerances at its finest level: against beam theory and
/// against the conforming mesh.
const TOL_BEAM: f64 = 0.05;
const TOL_CONF: f64 = 0.02;

/// The 2D plane-strain model extruded: a block [1, 3] × [1, 1.5] (Q4 6 × 2)
/// on a base [0, 4] × [0, 1] (Q4 8 × 2), the stick law (`contact`), the base
/// held at its bottom, the block's top loaded by (Q, −P) in total per unit
/// thickness, penalty `c` per pair.
fn plane_text(c: f64, q: f64, p: f64) -> String {
    format!(
        "plane = \"strain\"\n[materials.m]\nE = {E:?}\nnu = {NU:?}\n[[part]]\nname = \"base\"\nmaterial = \"m\"\nrectangle = {{ x = [0.0, 4.0], y = [0.0, 1.0], cells = [8, 2], elements = \"q4\" }}\n[[part]]\nname = \"block\"\nmaterial = \"m\"\nrectangle = {{ x = [1.0, 3.0], y = [1.0, 1.5], cells = [6, 2], elements = \"q4\" }}\n[[support]]\npart = \"base\"\nboundary = \"bottom\"\nfix = [\"x\", \"y\"]\n[[load]]\npart = \"block\"\nboundary = \"top\"\nforce = [{q:?}, {:?}]\n[[interface]]\nhost = \"base\"\nnodes = \"block\"\nboundary = \"bottom\"\nlaw = \"contact\"\nc_n = {c:e}\nc_s = {c:e}\n[analysis]\nincrements = 1\n",
        -p
    )
}

/// The 2D plane-strain contact model extruded one element thick (HEX8, the
/// thickness along y, held on both faces) gives the 2D answer.
pub fn extrusion(_quick: bool) -> Result<Case> {
    let (q, p, c) = (1.5, 1.0, 1e5 * E);
    let a2 = prepare(&plane_text(c, q, p))?;
    let r2 = a2.solve()?;
    // The same model in 3D: (x, y) of the plane → (x, z), thickness t = 1 along y.
    let t = 1.0;
    let block = |x: [f64; 2], z: [f64; 2], cells: [usize; 2]| {
        Mesh::<D3>::block(x, [0.0, t], z, [cells[0], 1, cells[1]], SolidKind::Hex8)
    };
    let parts = vec![
        part("base", block([0.0, 4.0], [0.0, 1.0], [8, 2]), E, NU)?,
        part("block", block([1.0, 3.0], [1.0, 1.5], [6, 2]), E, NU)?,
    ];
    // Each plane pair becomes two pairs (y = 0 and y = t), each half the spring.
    let def = interface(&parts, 0, 1, "bottom", Law::Contact, 0.5 * c)?;
    let mut supports = vec![hold(&parts, 0, "bottom", [true; 3], [0.0; 3])?];
    for part in 0..2 {
        supports.push(roller(&parts, part, "front", 1)?);
        supports.push(roller(&parts, part, "back", 1)?);
    }
    let area = 2.0 * t;
    let load = face_load(
        &parts,
        1,
        "top",
        FaceLoad::Traction([q / area, 0.0, -p / area]),
        0,
    )?;
    let s3 = solve("extruded", parts, vec![def], supports, vec![load], &[1])?;
    // Displacements node by node: plane (x, y) against (x, 0 or t, y).
    let mut du = 0.0f64;
    let mut umax = 0.0f64;
    let u2 = r2.displacements();
    for (pi, part2) in a2.model.parts.iter().enumerate() {
        let m3 = &s3.analysis.model.parts[pi].mesh;
        let index: std::collections::HashMap<[i64; 3], usize> = (m3.nodes.iter().enumerate())
            .map(|(n, x)| (x.map(|c| (c * 1e9).round() as i64), n))
            .collect();
        for (n, x) in part2.mesh.nodes.iter().enumerate() {
            let g = a2.dofs.node(pi, n);
            let (ux, uy) = (u2[2 * g], u2[2 * g + 1]);
            umax = umax.max(ux.hypot(uy));
            for y in [0.0, t] {
                let key = [x[0], y, x[1]].map(|c| (c * 1e9).round() as i64);
                let n3 = *index
                    .get(&key)
                    .ok_or_else(|| Error::Model(format!("no 3D node at {x:?}")))?;
                let u = s3.u(pi, n3);
                du = du
                    .max((u[0] - ux).abs())
                    .max((u[2] - uy).abs())
                    .max(u[1].abs());
            }
        }
    }
    // Pairs: the plane pair at x against the two solid pairs at (x, 0) and
    // (x, t): states equal, forces per unit thickness summed (the plane
    // row's global force: f_n n + f_s s with n = (0, 1), s = (−1, 0)).
    let mut same_states = true;
    let mut df = 0.0f64;
    let mut fmax = 0.0f64;
    let (mut open, mut bonded) = (0, 0);
    for r in &r2.pairs {
        let pair3: Vec<_> = (s3.results.pairs.iter())
            .filter(|q3| (q3.x - r.x).abs() < 1e-9 && (q3.z.unwrap_or(f64::NAN) - r.y).abs() < 1e-9)
            .collect();
        same_states &= pair3.len() == 2 && pair3.iter().all(|q3| q3.state == r.state);
        match r.state {
            PairState::Open => open += 1,
            _ => bonded += 1,
        }
        let fx: f64 = pair3.iter().map(|q3| q3.force_x.unwrap_or(0.0)).sum();
        let fz: f64 = pair3.iter().map(|q3| q3.force_z.unwrap_or(0.0)).sum();
        fmax = fmax.max(r.force_n.abs()).max(r.force_s.abs());
        df = df.max((fx + r.force_s).abs()).max((fz - r.force_n).abs());
    }
    let (eu, ef) = (du / umax, df / fmax);
    let passed = r2.summary.status == cfe::RunStatus::Completed
        && s3.completed()
        && same_states
        && s3.results.pairs.len() == 2 * r2.pairs.len()
        && open > 0
        && eu < 1e-8
        && ef < 1e-8;
    let table = Table {
        caption: "The plane-strain model and its extrusion: pairs (open / closed), the largest displacement difference over every node (relative to the largest displacement; and u_y of the solid, which must vanish), the largest difference of the pair forces per unit thickness (relative to the largest).".into(),
        header: [
            "model",
            "status",
            "pairs",
            "open",
            "closed",
            "max |Δu| / max |u|",
            "max |Δf| / max |f|",
        ]
        .map(String::from)
        .to_vec(),
        rows: vec![
            vec![
                "2D plane strain (Q4)".into(),
                r2.summary.status.to_string(),
                r2.pairs.len().to_string(),
                open.to_string(),
                bonded.to_string(),
                String::new(),
                String::new(),
            ],
            vec![
                "3D, one HEX8 thick".into(),
                s3.results.summary.status.to_string(),
                s3.results.pairs.len().to_string(),
                (s3.results.pairs.iter())
                    .filter(|q3| q3.state == PairState::Open)
                    .count()
                    .to_string(),
                (s3.results.pairs.iter())
                    .filter(|q3| q3.state != PairState::Open)
                    .count()
                    .to_string(),
                sci(eu),
                sci(ef),
            ],
        ],
    };
    Ok(Case {
        title: "3D extrusion of a plane-strain contact model".into(),
        setup: format!(
            "The plane-strain model: a block [1, 3] × [1, 1.5] (Q4 6 × 2) on a base [0, 4] × [0, 1] (Q4 8 × 2: the faces do not match), the stick law (`contact`), penalties c = 1e5 E per pair, the base held at its bottom, the block's top loaded by (Q, −P) = ({q}, −{p}) N per unit thickness — the push lifts the block's trailing end, so some pairs open. The same model extruded one HEX8 thick (t = 1 along y, the plane's y becoming z), y held on both faces y = 0, t of both parts, each plane pair becoming two pairs with half its spring, the load the same traction.\n\n```text\n          (Q, −P) on the top\n        +-----------+        block 6 × 2 (× 1 thick)\n  +-----+===========+-----+  ← contact (stick law)\n  |  base 8 × 2 (× 1 thick)|\n  +------------------------+  held\n```"
        ),
        reference: "The plane-strain answer: a HEX8 whose nodes move alike on both faces is the Q4 (its shape functions are the Q4's times a linear function of y; full integration), so with y held the solid model is the plane model, node for node, pair for pair.".into(),
        tables: vec![table],
        plots: vec![],
        verdict: format!(
            "The extruded model gives the plane-strain answer: the same pair states ({open} of {} open), displacements to {} and pair forces per unit thickness to {} of their largest (asserted 1e-8).",
            r2.pairs.len(),
            sci(eu),
            sci(ef)
        ),
        passed,
    })
}
