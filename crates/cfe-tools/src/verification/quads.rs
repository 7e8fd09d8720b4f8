//! Q4 (bilinear quadrilateral) and mixed T3/Q4 meshes: (a) the constant-stress
//! patch test through a tied interface with Q4 on either side or both (the 5-node
//! CFE on a Q4 host, the 4-node one on a T3 host), (b) a mixed T3/Q4 Gmsh mesh
//! under constant stress, (c) the tied cantilever with Q4 against
//! Timoshenko–Goodier and against the same meshes with T3.
//!
//! ```text
//!   (a)  +-----------+  node part (T3 or Q4), y ∈ [1, 2]     σ·n on every
//!        +===========+  ← tied, y = 1                        outer edge
//!        +-----------+  host (T3 or Q4),     y ∈ [0, 1]
//!
//!   (b)  +--+--+--+--+   tests/data/gmsh/mixed.msh: 2 × 1,
//!        |Q4|Q4|/ | /|   left half 4 Q4, right half 8 T3,
//!        +--+--+--+--+   σ·n on every edge
//!        |Q4|Q4|/ | /|
//!        +--+--+--+--+
//!
//!   (c)  |▒ host Q4 (h) ▒▒▒▒▒▒▒|░ node part Q4 (h/2) ░|  ↓ P
//! ```
//!
//! References: the exact constant stress state (a, b); S. P. Timoshenko,
//! J. N. Goodier, *Theory of Elasticity*, 3rd ed. (1970), §21 (c, see
//! [`cantilever`]).

use super::cantilever::{self, Ends, Measured};
use super::patch::{ET, SIGMA};
use super::{Case, Plot, Table, for_each_stress_point, orders, prepare, sci, solve};
use cfe::analysis::Analysis;
use cfe::error::Result;
use cfe::mesh::ElementKind;
use cfe::model::Model;
use cfe::output::chart::Series;
use std::path::Path;

const T3: ElementKind = ElementKind::T3;
const Q4: ElementKind = ElementKind::Q4;

/// |σ| of the patch-test stress state.
fn sigma_norm() -> f64 {
    SIGMA.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// (largest, RMS) deviation of the stress from [`SIGMA`] over the quadrature points
/// of every element (a Q4's stress varies inside it: its 3 × 3 points are
/// checked, not only its mean), relative to |σ|; RMS area-weighted.
fn patch_errors(a: &Analysis, u: &[f64]) -> (f64, f64) {
    let (mut max, mut sq, mut area) = (0.0f64, 0.0, 0.0);
    for_each_stress_point(a, u, |_, _, _, w, s| {
        let d = [0, 1, 2].map(|k| s[k] - SIGMA[k]);
        max = max.max(d.iter().fold(0.0f64, |m, v| m.max(v.abs())));
        sq += w * d.iter().map(|v| v * v).sum::<f64>();
        area += w;
    });
    let n = sigma_norm();
    (max / n, (sq / area).sqrt() / n)
}

/// Solves the tied patch test (host cells, node cells, penalty factor × E·t,
/// element types [host, node]) and returns its (largest, RMS) stress errors.
pub fn tied_patch(
    host: usize,
    node: usize,
    factor: f64,
    kinds: [ElementKind; 2],
) -> Result<(f64, f64)> {
    let a = prepare(&super::patch::problem_with_elements(
        host,
        node,
        SIGMA,
        factor * ET,
        kinds,
    ))?;
    let inc = solve(&a)?.pop().expect("one increment");
    Ok(patch_errors(&a, &inc.u))
}

fn pair_name(kinds: [ElementKind; 2]) -> String {
    format!("{} host / {} nodes", kinds[0].as_str(), kinds[1].as_str())
}

/// The mixed T3/Q4 Gmsh mesh under the constant stress state: (largest stress
/// error, largest displacement error) relative to |σ| and to the largest exact
/// displacement, and the element counts (Q4, T3).
pub fn mixed_patch() -> Result<(f64, f64, usize, usize)> {
    let [sxx, syy, sxy] = SIGMA;
    let text = format!(
        r#"
[materials.m]
E = {ET}
nu = 0.3

[[part]]
name = "body"
material = "m"
gmsh = {{ file = "mixed.msh", surfaces = ["body"] }}

[[support]]
part = "body"
at = [0.0, 0.0]
fix = ["x", "y"]

[[support]]
part = "body"
at = [2.0, 0.0]
fix = ["y"]

[[load]]
part = "body"
boundary = "bottom"
force = [{:e}, {:e}]

[[load]]
part = "body"
boundary = "top"
force = [{:e}, {:e}]

[[load]]
part = "body"
boundary = "left"
force = [{:e}, {:e}]

[[load]]
part = "body"
boundary = "right"
force = [{:e}, {:e}]

[analysis]
increments = 1
"#,
        -2.0 * sxy,
        -2.0 * syy,
        2.0 * sxy,
        2.0 * syy,
        -sxx,
        -sxy,
        sxx,
        sxy
    );
    // The mesh file is found relative to the (notional) problem file's folder.
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join("tests/data/gmsh/verification.toml");
    let a = Analysis::new(Model::from_str(&text, &path, 1)?)?;
    let inc = solve(&a)?.pop().expect("one increment");
    let (stress, _) = patch_errors(&a, &inc.u);
    // The exact displacement: strains ε = D⁻¹σ (plane stress), the rigid motion
    // fixed by u(0, 0) = 0 and v(2, 0) = 0: u = (εxx x + γxy y, εyy y).
    let nu = 0.3;
    let exx = (sxx - nu * syy) / ET;
    let eyy = (syy - nu * sxx) / ET;
    let gxy = 2.0 * (1.0 + nu) * sxy / ET;
    let m = &a.model.parts[0].mesh;
    let (mut err, mut scale) = (0.0f64, 0.0f64);
    for (n, x) in m.nodes.iter().enumerate() {
        let g = a.dofs.node(0, n);
        let exact = [exx * x[0] + gxy * x[1], eyy * x[1]];
        err = err.max((inc.u[2 * g] - exact[0]).hypot(inc.u[2 * g + 1] - exact[1]));
        scale = scale.max(exact[0].hypot(exact[1]));
    }
    let q4 = m.elements.iter().filter(|e| e.kind() == Q4).count();
    Ok((stress, err / scale, q4, m.elements.len() - q4))
}

/// The tied cantilever with exact end conditions, host cells 10k × 2k, node part
/// `ratio` times finer, both parts of `kind`.
fn cantilever_tied(k: usize, ratio: usize, kind: ElementKind) -> Result<Measured> {
    cantilever::measure(
        &cantilever::tied_with_elements(
            [10 * k, 2 * k],
            [10 * k * ratio, 2 * k * ratio],
            None,
            Ends::Exact,
            false,
            [kind; 2],
        ),
        "fine",
    )
}

/// The cantilever meshed conformingly with `nx × nx/10` cells of `kind`, exact ends.
fn cantilever_conforming(nx: usize, kind: ElementKind) -> Result<Measured> {
    cantilever::measure(
        &cantilever::conforming_with_elements([nx, nx / 10], Ends::Exact, kind),
        "beam",
    )
}

/// The four host / node-part element pairs.
const COMBOS: [[ElementKind; 2]; 4] = [[Q4, T3], [T3, Q4], [Q4, Q4], [T3, T3]];

/// Results of part (a1), coincident vertices.
struct CoincidentPatches {
    table: Table,
    /// The error is O(E·t/c) and below 1e-6 at 1e6 E·t for every combination.
    ok_penalty: bool,
    /// The largest error at 1e6 E·t.
    worst_coincident: f64,
}

/// Results of part (a2), non-matching meshes under refinement.
struct NonMatchingPatches {
    table: Table,
    /// The largest error stays below 0.1.
    ok_bounded: bool,
    /// The RMS error's order between the two finest exceeds 0.4.
    ok_rms: bool,
    /// The largest error at any refinement.
    worst_max: f64,
    /// The range of the RMS orders.
    o_min: f64,
    o_max: f64,
    /// RMS errors of the 3:7 meshes with the slope-½ guide.
    patch_series: Vec<Series>,
}

/// Results of part (b), the mixed Gmsh mesh.
struct MixedMesh {
    table: Table,
    /// Exact to round-off.
    ok_mixed: bool,
    /// The largest stress and displacement errors.
    mixed_stress: f64,
    mixed_u: f64,
}

/// Results of part (c), the tied cantilever with Q4.
struct QuadCantilever {
    table: Table,
    tip_series: Vec<Series>,
    /// Q4's finest orders are 2 (tip) and 1 (energy norm).
    ok_cantilever: bool,
    /// Q4 is more accurate than T3 at every level.
    ok_better: bool,
    /// The tie adds no energy-norm error beyond the conforming prediction.
    ok_no_extra: bool,
    /// The Q4 tied / predicted ratio farthest from 1.
    worst_pred: f64,
    /// Q4's orders between the two finest levels.
    o_tip: f64,
    o_en: f64,
    /// The range of T3 / Q4 tip error ratios.
    r_min: f64,
    r_max: f64,
}

/// The case: Q4 and mixed meshes through the patch test and the cantilever.
pub fn q4_and_mixed(quick: bool) -> Result<Case> {
    let coincident = coincident_patches()?;
    let scales: &[usize] = if quick { &[1, 2] } else { &[1, 2, 4, 8] };
    let nonmatching = nonmatching_patches(scales)?;
    let mixed = mixed_mesh()?;
    let levels: &[usize] = if quick { &[2, 4] } else { &[1, 2, 4, 8] };
    let cantilever = quad_cantilever(levels)?;
    Ok(quads_case(coincident, nonmatching, mixed, cantilever))
}

/// (a1) Coincident vertices: the penalty's error.
fn coincident_patches() -> Result<CoincidentPatches> {
    let coincident = [(2, 4), (3, 6)];
    let mut table_a = Table {
        caption: "(a) Constant-stress patch test through the tied interface, host vertices coinciding with coupling nodes (host : node cells per side): the largest stress error / |σ| over every quadrature point (3 × 3 per Q4) at c = 1e4 and 1e6 × E·t. T3/T3 is the case-1 baseline.".into(),
        header: std::iter::once("host / node part".to_string())
            .chain(coincident.iter().flat_map(|(h, n)| {
                [format!("{h}:{n}, c = 1e4 E·t"), format!("{h}:{n}, c = 1e6 E·t")]
            }))
            .collect(),
        rows: Vec::new(),
    };
    let mut ok_penalty = true;
    let mut worst_coincident: f64 = 0.0;
    for kinds in COMBOS {
        let mut row = vec![pair_name(kinds)];
        for &(h, n) in &coincident {
            let (e4, _) = tied_patch(h, n, 1e4, kinds)?;
            let (e6, _) = tied_patch(h, n, 1e6, kinds)?;
            // O(E·t/c): 100 times stiffer, 100 times smaller, and below 1e-6 at 1e6.
            ok_penalty &= e6 <= 1e-6 && (50.0..200.0).contains(&(e4 / e6));
            worst_coincident = worst_coincident.max(e6);
            row.push(sci(e4));
            row.push(sci(e6));
        }
        table_a.rows.push(row);
    }
    Ok(CoincidentPatches {
        table: table_a,
        ok_penalty,
        worst_coincident,
    })
}

/// (a2) Non-matching meshes under refinement by `scales`.
fn nonmatching_patches(scales: &[usize]) -> Result<NonMatchingPatches> {
    let nonmatching = [(2, 3), (3, 7)];
    let last = scales[scales.len() - 1];
    let mut study = NonMatchingPatches {
        table: Table {
            caption: format!(
                "(a) Non-matching meshes (host : node cells per side, both scaled by the refinement ×1 … ×{last}), c = 1e6 E·t: the largest stress error / |σ| (in the elements along the interface) at the coarsest and finest refinement, the RMS error over the patch at each, and its order between the two finest. As with T3 (case 1), node-to-element coupling cannot transfer a constant traction exactly when coupling nodes fall inside host edges: the largest error stays put, confined to one layer of elements, so the RMS falls as √h."
            ),
            header: [
                "host / node part".to_string(),
                "host : node".into(),
                "max error ×1".into(),
                format!("max error ×{last}"),
            ]
            .into_iter()
            .chain(scales.iter().map(|k| format!("RMS ×{k}")))
            .chain(std::iter::once("RMS order".to_string()))
            .collect(),
            rows: Vec::new(),
        },
        ok_bounded: true,
        ok_rms: true,
        worst_max: 0.0,
        o_min: f64::INFINITY,
        o_max: 0.0,
        patch_series: Vec::new(),
    };
    let mut rms_orders = Vec::new();
    for kinds in COMBOS {
        for &(h, n) in &nonmatching {
            rms_orders.push(nonmatching_patch(kinds, (h, n), scales, &mut study)?);
        }
    }
    let h0 = 1.0 / 3.0;
    let h1 = h0 / scales[scales.len() - 1] as f64;
    let r0 = study.patch_series[0].points[0].1 * 1.3;
    study.patch_series.push(Series {
        name: "slope ½".into(),
        points: vec![(h0, r0), (h1, r0 * (h1 / h0).sqrt())],
        reference: true,
    });
    (study.o_min, study.o_max) = rms_orders
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &o| (a.min(o), b.max(o)));
    Ok(study)
}

/// One non-matching patch (`cells` = host : node cells per side) of `kinds`
/// under refinement: its table row (and series for 3:7); the RMS order.
fn nonmatching_patch(
    kinds: [ElementKind; 2],
    cells: (usize, usize),
    scales: &[usize],
    study: &mut NonMatchingPatches,
) -> Result<f64> {
    let (h, n) = cells;
    let (mut rms, mut maxes) = (Vec::new(), Vec::new());
    for &k in scales {
        let (e, r) = tied_patch(h * k, n * k, 1e6, kinds)?;
        study.ok_bounded &= e < 0.1;
        study.worst_max = study.worst_max.max(e);
        rms.push(r);
        maxes.push(e);
    }
    let o = (rms[rms.len() - 2] / rms[rms.len() - 1]).log2();
    study.ok_rms &= o > 0.4;
    study.table.rows.push(
        [
            pair_name(kinds),
            format!("{h}:{n}"),
            sci(maxes[0]),
            sci(maxes[maxes.len() - 1]),
        ]
        .into_iter()
        .chain(rms.iter().map(|&r| sci(r)))
        .chain(std::iter::once(format!("{o:.2}")))
        .collect(),
    );
    if (h, n) == (3, 7) {
        study.patch_series.push(Series {
            name: format!("{} / {}", kinds[0].as_str(), kinds[1].as_str()),
            points: scales
                .iter()
                .zip(&rms)
                .map(|(&k, &r)| (1.0 / (h * k) as f64, r))
                .collect(),
            reference: false,
        });
    }
    Ok(o)
}

/// (b) The mixed Gmsh mesh.
fn mixed_mesh() -> Result<MixedMesh> {
    let (mixed_stress, mixed_u, n_q4, n_t3) = mixed_patch()?;
    let ok_mixed = mixed_stress < 1e-10 && mixed_u < 1e-10;
    let table_m = Table {
        caption: "(b) One part meshed in Gmsh with Q4 and T3 together (tests/data/gmsh/mixed.msh, the rectangle [0, 2] × [0, 1]), the tractions of σ on its four physical curves, no interface: the largest stress error / |σ| over every quadrature point, and the largest nodal displacement error against the exact linear field relative to its largest value.".into(),
        header: ["Q4 elements", "T3 elements", "max stress error", "max displacement error"]
            .map(String::from)
            .to_vec(),
        rows: vec![vec![
            n_q4.to_string(),
            n_t3.to_string(),
            sci(mixed_stress),
            sci(mixed_u),
        ]],
    };
    Ok(MixedMesh {
        table: table_m,
        ok_mixed,
        mixed_stress,
        mixed_u,
    })
}

/// The tip and energy-norm errors of part (c) per level.
#[derive(Default)]
struct CantileverErrors {
    q4_tips: Vec<f64>,
    t3_tips: Vec<f64>,
    q4_en: Vec<f64>,
    /// Conforming Q4 of size h: (h, |tip error|).
    conf_tips: Vec<(f64, f64)>,
    /// T3 / Q4 tip error.
    tip_ratios: Vec<f64>,
}

/// The ratio of node-part to host refinement in part (c).
const CANTILEVER_RATIO: usize = 2;

/// (c) The tied cantilever with Q4 at `levels`, against T3 and conforming Q4.
fn quad_cantilever(levels: &[usize]) -> Result<QuadCantilever> {
    let exact = cantilever::timoshenko_goodier();
    let ratio = CANTILEVER_RATIO;
    let hs: Vec<f64> = levels.iter().map(|&k| 5.0 / k as f64).collect();
    let mut study = QuadCantilever {
        table: Table {
            caption: format!(
                "(c) The tied cantilever of case 2 with exact end conditions: host cells 10k × 2k on [0, 50] (size h = 5/k), node part 1:{ratio} on [50, 100], both Q4, against the same meshes with T3. Tip deflection error against the closed form v(L) = {} (negative: too stiff), energy-norm error ‖σ_h − σ_TG‖_E / ‖σ_TG‖_E, and, for Q4, the energy-norm error predicted for an interface that adds nothing, √(e²_left(conforming Q4, h) + e²_right(conforming Q4, h/{ratio})).",
                sci(exact)
            ),
            header: [
                "k",
                "h",
                "Q4 tip error",
                "order",
                "T3 tip error",
                "order",
                "T3 / Q4 tip error",
                "Q4 energy-norm error",
                "order",
                "T3 energy-norm error",
                "Q4 predicted",
                "Q4 tied / predicted",
            ]
            .map(String::from)
            .to_vec(),
            rows: Vec::new(),
        },
        tip_series: Vec::new(),
        ok_cantilever: false,
        ok_better: true,
        ok_no_extra: true,
        worst_pred: 1.0,
        o_tip: f64::NAN,
        o_en: f64::NAN,
        r_min: f64::INFINITY,
        r_max: 0.0,
    };
    let errors = quad_cantilever_rows(levels, &hs, &mut study)?;
    let n = levels.len();
    study.o_tip = (errors.q4_tips[n - 2] / errors.q4_tips[n - 1]).abs().log2();
    study.o_en = (errors.q4_en[n - 2] / errors.q4_en[n - 1]).log2();
    study.ok_cantilever = study.o_tip > 1.7 && (0.85..1.2).contains(&study.o_en);
    (study.r_min, study.r_max) = errors
        .tip_ratios
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &r| (a.min(r), b.max(r)));
    study.tip_series = quad_tip_series(&hs, errors);
    Ok(study)
}

/// Part (c)'s rows with their orders and pass criteria; the errors per level.
fn quad_cantilever_rows(
    levels: &[usize],
    hs: &[f64],
    study: &mut QuadCantilever,
) -> Result<CantileverErrors> {
    let exact = cantilever::timoshenko_goodier();
    let ratio = CANTILEVER_RATIO;
    let mut errors = CantileverErrors::default();
    let mut t3_en = Vec::new();
    for (i, &k) in levels.iter().enumerate() {
        let q = cantilever_tied(k, ratio, Q4)?;
        let t = cantilever_tied(k, ratio, T3)?;
        let ch = cantilever_conforming(20 * k, Q4)?;
        let cf = cantilever_conforming(20 * k * ratio, Q4)?;
        let predicted = ((ch.left + cf.right) / cantilever::exact_energy()).sqrt();
        let rp = q.energy_error() / predicted;
        if (rp - 1.0).abs() > (study.worst_pred - 1.0).abs() {
            study.worst_pred = rp;
        }
        study.ok_no_extra &= (rp - 1.0).abs() < 0.02;
        let (eq, et) = ((q.tip - exact) / exact, (t.tip - exact) / exact);
        study.ok_better &= eq.abs() < et.abs() && q.energy_error() < t.energy_error();
        errors.tip_ratios.push(et / eq);
        errors.q4_tips.push(eq);
        errors.t3_tips.push(et);
        errors.q4_en.push(q.energy_error());
        t3_en.push(t.energy_error());
        errors
            .conf_tips
            .push((hs[i], ((ch.tip - exact) / exact).abs()));
        study.table.rows.push(vec![
            k.to_string(),
            format!("{:.3}", hs[i]),
            sci(eq),
            String::new(),
            sci(et),
            String::new(),
            format!("{:.1}", et / eq),
            sci(q.energy_error()),
            String::new(),
            sci(t.energy_error()),
            sci(predicted),
            format!("{rp:.4}"),
        ]);
    }
    for (i, ((a, b), c)) in orders(&errors.q4_tips)
        .into_iter()
        .zip(orders(&errors.t3_tips))
        .zip(orders(&errors.q4_en))
        .enumerate()
    {
        study.table.rows[i][3] = a;
        study.table.rows[i][5] = b;
        study.table.rows[i][8] = c;
    }
    Ok(errors)
}

/// Part (c)'s plot: the tip errors of tied Q4, conforming Q4 and tied T3, with
/// the slope-2 guide.
fn quad_tip_series(hs: &[f64], errors: CantileverErrors) -> Vec<Series> {
    let ratio = CANTILEVER_RATIO;
    let n = hs.len();
    let abs_pts = |v: &[f64]| hs.iter().copied().zip(v.iter().map(|e| e.abs())).collect();
    let mut tip_series = vec![
        Series {
            name: format!("Q4 tied 1:{ratio}"),
            points: abs_pts(&errors.q4_tips),
            reference: false,
        },
        Series {
            name: "Q4 conforming h".into(),
            points: errors.conf_tips,
            reference: false,
        },
        Series {
            name: format!("T3 tied 1:{ratio}"),
            points: abs_pts(&errors.t3_tips),
            reference: false,
        },
    ];
    let (x0, x1) = (hs[0], hs[n - 1]);
    let y0 = errors.q4_tips[0].abs() * 0.6;
    tip_series.push(Series {
        name: "slope 2".into(),
        points: vec![(x0, y0), (x1, y0 * (x1 / x0).powi(2))],
        reference: true,
    });
    tip_series
}

/// The case's report from its parts: tables, plots and the verdict.
fn quads_case(
    coincident: CoincidentPatches,
    nonmatching: NonMatchingPatches,
    mixed: MixedMesh,
    cantilever: QuadCantilever,
) -> Case {
    let CoincidentPatches {
        table: table_a,
        ok_penalty,
        worst_coincident,
    } = coincident;
    let NonMatchingPatches {
        table: table_b,
        ok_bounded,
        ok_rms,
        worst_max,
        o_min,
        o_max,
        patch_series,
    } = nonmatching;
    let MixedMesh {
        table: table_m,
        ok_mixed,
        mixed_stress,
        mixed_u,
    } = mixed;
    let QuadCantilever {
        table: table_c,
        tip_series,
        ok_cantilever,
        ok_better,
        ok_no_extra,
        worst_pred,
        o_tip,
        o_en,
        r_min,
        r_max,
    } = cantilever;
    let passed =
        ok_penalty && ok_bounded && ok_rms && ok_mixed && ok_cantilever && ok_better && ok_no_extra;
    Case {
        title: "Q4 and mixed T3/Q4 meshes".into(),
        setup: "(a) The patch test of case 1 (two unit squares tied along y = 1, E = 1000, ν = 0.3, plane stress, the tractions of σ = (1, 2, 0.5) on every outer edge) with a Q4 host and a T3 node part, a T3 host and a Q4 node part, and Q4 on both sides (a coupling node on a Q4 host couples through a 5-node CFE: the host's 4 nodes and itself). (b) One part meshed in Gmsh with 4 Q4 and 8 T3 under the same stress. (c) The tied cantilever of case 2 (exact end conditions, 1 N end shear) with both halves Q4.\n\n```text\n  (a)  +-----------+  node part (T3 or Q4), y ∈ [1, 2]     σ·n on every\n       +===========+  ← tied, y = 1                        outer edge\n       +-----------+  host (T3 or Q4),     y ∈ [0, 1]\n\n  (b)  +--+--+--+--+   mixed.msh: 2 × 1, left half 4 Q4,\n       |Q4|Q4|/ | /|   right half 8 T3\n       +--+--+--+--+\n       |Q4|Q4|/ | /|\n       +--+--+--+--+\n\n  (c)  |▒ host Q4 (h) ▒▒▒▒▒▒|░ node part Q4 (h/2) ░░|  ↓ P\n```".into(),
        reference: "(a, b) The constant stress σ is the exact solution of every body loaded by its tractions; Q4 and T3 both contain the linear displacement fields, so a consistent discretization reproduces it — to round-off without an interface, to the penalty's O(E·t/c) through a tie whose host vertices coincide with coupling nodes. (c) Timoshenko & Goodier, *Theory of Elasticity*, 3rd ed., §21 (case 2's reference). Q4 (full 2 × 2 integration) converges at order 2 in the tip deflection and order 1 in the energy norm, like T3, but represents bending far better: its strain varies linearly across an element where T3's is constant.".into(),
        tables: vec![table_a, table_b, table_m, table_c],
        plots: vec![
            Plot {
                file: "quads_patch.png".into(),
                title: "Non-matching patch test (3:7 cells): RMS stress error".into(),
                x: "host cell size".into(),
                y: "RMS stress error / |σ|".into(),
                log: (true, true),
                series: patch_series,
            },
            Plot {
                file: "quads_cantilever.png".into(),
                title: "Tied cantilever (exact ends): tip error, Q4 against T3".into(),
                x: "host element size h".into(),
                y: "|tip error| / closed form".into(),
                log: (true, true),
                series: tip_series,
            },
        ],
        verdict: format!(
            "(a) With coincident vertices every combination of T3 and Q4 reproduces the constant stress to the penalty's error: at most {} at c = 1e6 E·t, falling ×100 for ×100 stiffer ({}). With non-matching meshes the largest error stays bounded (at most {}, in the layer along the interface) and the RMS falls at order {:.2}–{:.2} (½ expected), as with T3. (b) The mixed T3/Q4 mesh is exact to round-off: stress {} and displacement {}. (c) The Q4 tied cantilever converges at order {o_tip:.2} in the tip deflection and {o_en:.2} in the energy norm (finest pair of levels); its tip error is {:.0}–{:.0} times smaller than T3's on the same meshes, and its energy-norm error is at most {worst_pred:.4} × that predicted from conforming Q4 meshes of the two halves — the 5-node CFE adds no error beyond the bulk. Pass criteria: coincident ≤ 1e-6 and ×100 per ×100 in c; non-matching max < 0.1 and RMS order > 0.4; mixed ≤ 1e-10; Q4 tip order > 1.7 and energy order in [0.85, 1.2], Q4 more accurate than T3 at every level, tied / predicted within 2 % (the criteria of cases 1 and 2): {}.",
            sci(worst_coincident),
            if ok_penalty { "all" } else { "NOT all" },
            sci(worst_max),
            o_min,
            o_max,
            sci(mixed_stress),
            sci(mixed_u),
            r_min,
            r_max,
            if passed { "all met" } else { "NOT all met" }
        ),
        passed,
    }
}
