//! 3D contact against closed forms, quarter models with symmetry supports: a
//! rigid flat circular punch on a half-space (Sneddon: stiffness 2aE*), a
//! sphere on a flat block (Hertz: a and p₀), and a shrink fit of a hollow shaft
//! in a thick ring (Lamé, plane strain).

use super::closed_forms::{contact_modulus, fit_ellipse, ring_ur, shrink_fit_pressure};
use super::solid::{Solved, face_load, hold, interface, part, roller, solve};
use super::solid_mesh::{extrude, graded, grid, quarter_annulus, quarter_disc};
use super::{Case, Plot, Table, orders, sci};
use cfe::coupling::{Law, PairState};
use cfe::dim::D3;
use cfe::domain::{FaceLoad, Load, Part, Support};
use cfe::error::{Error, Result};
use cfe::mesh::{Mesh, SolidKind};
use cfe::output::chart::Series;
use std::f64::consts::PI;

/// A quarter block [0, L]² × [−L, 0] graded towards the origin: cells of `h`
/// up to `inner` in x, y and depth, then growing by at most `ratio`.
fn quarter_block(l: f64, inner: f64, h: f64, ratio: f64) -> Mesh<D3> {
    let xs = graded(0.0, inner, h, l, ratio);
    let zs: Vec<f64> = xs.iter().rev().map(|z| -z).collect();
    grid(&xs, &xs, &zs, SolidKind::Hex8)
}

/// The symmetry supports x on `left`, y on `front` of part `p`.
fn symmetry(parts: &[Part<D3>], p: usize) -> Result<Vec<Support>> {
    Ok(vec![
        roller(parts, p, "left", 0)?,
        roller(parts, p, "front", 1)?,
    ])
}

/// A uniform load along −z on `side` of part `p` whose resultant is −`f`
/// (a traction scaled to the faces' area as meshed).
fn downward(parts: &[Part<D3>], p: usize, side: &str, f: f64) -> Result<Load<D3>> {
    let mut load = face_load(parts, p, side, FaceLoad::Traction([0.0, 0.0, -1.0]), 0)?;
    let scale = f / -load.resultant[2];
    for (_, v) in &mut load.nodal {
        *v = v.map(|c| c * scale);
    }
    load.resultant = load.resultant.map(|c| c * scale);
    Ok(load)
}

const E_BLOCK: f64 = 210_000.0;
const NU_BLOCK: f64 = 0.3;
/// The punch's indentation (prescribed on its top).
const INDENT: f64 = 1e-3;

/// The quarter punch model: a cylinder of radius 1 (O-grid, core cells
/// `n`), 0.5 high, 1000 × stiffer, frictionless on a block of side `l` (cells
/// `h` up to 1.25), pressed `INDENT` on its top. Returns the total force
/// (4 × the quarter's) and the pairs closed and paired.
fn punch_force(l: f64, h: f64, n: usize) -> Result<(f64, usize, usize, Solved)> {
    let block = quarter_block(l, 1.25, h, 1.35);
    let disc = quarter_disc(1.0, 0.55, n, (n * 3).div_ceil(4));
    let punch = extrude(&disc, 2, |_, k| 0.25 * k as f64, 0.0);
    let parts = vec![
        part("block", block, E_BLOCK, NU_BLOCK)?,
        part("punch", punch, 1000.0 * E_BLOCK, NU_BLOCK)?,
    ];
    let def = interface(&parts, 0, 1, "bottom", Law::Frictionless, 1e5 * E_BLOCK * h)?;
    let mut supports = symmetry(&parts, 0)?;
    supports.extend(symmetry(&parts, 1)?);
    supports.push(hold(&parts, 0, "bottom", [true; 3], [0.0; 3])?);
    supports.push(hold(
        &parts,
        1,
        "top",
        [false, false, true],
        [0.0, 0.0, -INDENT],
    )?);
    let s = solve("flat punch", parts, vec![def], supports, vec![], &[1])?;
    let press = (s.results.reactions().iter())
        .find(|r| r.support == "punch/top")
        .ok_or_else(|| Error::Model("no reaction 'punch/top'".into()))?;
    let f = -4.0 * press.fz.unwrap_or(f64::NAN);
    let closed = (s.results.pairs.iter())
        .filter(|r| r.state == PairState::Bonded)
        .count();
    let pairs = s.results.pairs.len();
    Ok((f, closed, pairs, s))
}

/// Sneddon's rigid flat circular punch on a half-space, a quarter model: the
/// force against 2aE*δ on two block sizes (the finite block's correction by
/// extrapolation in a/L) and two meshes.
pub fn flat_punch(quick: bool) -> Result<Case> {
    let e_star = E_BLOCK / (1.0 - NU_BLOCK * NU_BLOCK);
    let sneddon = 2.0 * e_star * INDENT;
    let levels: &[(f64, usize)] = if quick {
        &[(0.125, 4)]
    } else {
        &[(0.125, 4), (1.0 / 12.0, 6)]
    };
    let sizes = [6.0, 12.0, 24.0];
    let mut table = Table {
        caption: format!(
            "Force on the punch (4 × the quarter model's reaction) over Sneddon's 2aE*δ = {sneddon:.2} N (a = 1 mm, δ = {INDENT} mm, E* = E/(1 − ν²)); \"L → ∞\": 2F(2L) − F(L), the block's correction extrapolated linearly in a/L from the two largest blocks."
        ),
        header: [
            "element size at the punch",
            "block L",
            "pairs closed",
            "F / (2aE*δ)",
        ]
        .map(String::from)
        .to_vec(),
        rows: Vec::new(),
    };
    let mut passed = true;
    let mut extrapolated = Vec::new();
    let mut series = Vec::new();
    for &(h, n) in levels {
        let mut f = Vec::new();
        for &l in &sizes {
            let (force, closed, pairs, s) = punch_force(l, h, n)?;
            passed &= s.completed() && closed + closed / 8 >= pairs;
            f.push(force / sneddon);
            table.rows.push(vec![
                format!("{h:.4} mm"),
                format!("{l} mm"),
                format!("{closed} of {pairs}"),
                format!("{:.4}", force / sneddon),
            ]);
            if l == sizes[1] && (h, n) == levels[levels.len() - 1] {
                let mut pts: Vec<(f64, f64)> = (s.results.pairs.iter())
                    .map(|r| (r.x.hypot(r.y), r.pressure))
                    .collect();
                pts.sort_by(|p, q| p.0.total_cmp(&q.0));
                series.push(Series {
                    name: format!("pairs (h = {h:.4} mm, L = {l} mm)"),
                    points: pts,
                    reference: false,
                });
                series.push(Series {
                    name: "Sneddon, F / (2πa√(a² − r²)) at the model's F".into(),
                    points: (0..=48)
                        .map(|i| {
                            let r = 0.97 * i as f64 / 48.0;
                            (r, force / (2.0 * PI * (1.0 - r * r).sqrt()))
                        })
                        .collect(),
                    reference: true,
                });
            }
        }
        let inf = 2.0 * f[2] - f[1];
        extrapolated.push(inf);
        table.rows.push(vec![
            format!("{h:.4} mm"),
            "→ ∞".into(),
            String::new(),
            format!("{inf:.4}"),
        ]);
    }
    let last = extrapolated[extrapolated.len() - 1];
    // The mesh's stiffening at the singular rim makes the model stiffer than
    // the half-space (the axisymmetric model at h = 1/8 is +6.6 % on a block
    // of 24): above Sneddon's, within 8 % once the block is removed, and
    // falling with h.
    passed &= last > 1.0 && last < 1.08 && extrapolated.windows(2).all(|w| w[1] < w[0]);
    Ok(Case {
        title: "3D rigid flat circular punch (Sneddon)".into(),
        setup: "A quarter model: a cylinder of radius a = 1 mm, 0.5 mm high (an O-grid of HEX8 mapped from a square core and two blocks onto the quarter disc, two layers), 1000 × stiffer than the block, pressed δ = 1e-3 mm (prescribed on its top) into a block [0, L]² × [−L, 0] (HEX8, cells of size h up to 1.25 mm, then growing by ≤ 1.35 ×) held at its bottom; symmetry supports on x = 0 and y = 0 of both parts; frictionless node coupling, the punch's face the node part (its mesh does not match the block's). The force is 4 × the punch top's reaction.\n\n```text\n          δ on the top\n        +----+\n        |    |  punch, r ≤ a (quarter)\n  ------+====+-------------- z = 0\n  |   block [0, L]² × [−L, 0]  |\n  |                            |\n  +----------------------------+  held\n```".into(),
        reference: "Sneddon (1946): a rigid flat punch of radius a on an elastic half-space, F = 2aE*δ with E* = E/(1 − ν²); pressure F / (2πa√(a² − r²)) (Johnson, Contact Mechanics, §3.8). The punch's own compression (E × 1000) changes F by ~3e-4. A finite block is stiffer by O(a/L): extrapolated from L = 6 and 12 mm.".into(),
        tables: vec![table],
        plots: vec![Plot {
            file: "solid_flat_punch.png".into(),
            title: "3D flat punch: pair pressure against the radius".into(),
            x: "r [mm]".into(),
            y: "pressure [MPa]".into(),
            log: (false, false),
            series,
        }],
        verdict: format!(
            "With the block's size extrapolated away (the differences between L = 6, 12 and 24 halve with L, as O(a/L)), the force is {last:.4} × Sneddon's at the finest mesh: the singular rim makes a finite element model stiffer, falling with h (asserted within +8 %; the axisymmetric model at h = 1/8 is +6.6 % on a block of 24). A few pairs next to the rim open (at most 1 in 9 asserted): a block face pinned by several pairs of the stiff punch tilts under the rim's large forces and drops below an inner punch node — the node-to-face discretization, not the law: the run completes with every pair lawful."
        ),
        passed,
    })
}

/// Hertz's load P (total; the quarter carries P/4), sphere radius R.
const P_HERTZ: f64 = 7800.0;
const R_HERTZ: f64 = 10.0;

/// The quarter sphere-on-block model at sphere core cells `n`, block cells
/// `h` near the contact: the pairs' (r, pressure) and Σ f_z.
fn hertz_run(n: usize, h: f64, layers: usize) -> Result<(Solved, f64)> {
    let block = quarter_block(6.0, 1.5, h, 1.35);
    let (rho, top) = (2.5, 2.5);
    let cap = |p: [f64; 2]| R_HERTZ - (R_HERTZ * R_HERTZ - p[0] * p[0] - p[1] * p[1]).sqrt();
    let disc = quarter_disc(rho, 0.5, n, n);
    let sphere = extrude(
        &disc,
        layers,
        |p, k| {
            let t = k as f64 / layers as f64;
            cap(p) + (top - cap(p)) * t.powf(1.5)
        },
        0.0,
    );
    let parts = vec![
        part("block", block, 70_000.0, 0.33)?,
        part("sphere", sphere, 210_000.0, 0.3)?,
    ];
    let mut def = interface(
        &parts,
        0,
        1,
        "bottom",
        Law::Frictionless,
        1e5 * 70_000.0 * h,
    )?;
    def.search_distance = 0.5;
    let mut supports = symmetry(&parts, 0)?;
    supports.extend(symmetry(&parts, 1)?);
    supports.push(hold(&parts, 0, "bottom", [true; 3], [0.0; 3])?);
    let load = downward(&parts, 1, "top", P_HERTZ / 4.0)?;
    let s = solve("Hertz sphere", parts, vec![def], supports, vec![load], &[1])?;
    let fz = s.pair_resultant()[2];
    Ok((s, fz))
}

/// Hertz's sphere on a flat block, a quarter model: a and p₀ of the ellipse
/// fitted to the pairs' pressures, two or three meshes.
pub fn hertz(quick: bool) -> Result<Case> {
    let e_star = contact_modulus(210_000.0, 0.3, 70_000.0, 0.33);
    let a_h = (3.0 * P_HERTZ * R_HERTZ / (4.0 * e_star)).cbrt();
    let p0_h = 3.0 * P_HERTZ / (2.0 * PI * a_h * a_h);
    let levels: &[(usize, f64, usize)] = if quick {
        &[(6, 0.25, 6), (8, 0.2, 8)]
    } else {
        &[(6, 0.25, 6), (8, 0.2, 8), (12, 0.125, 10)]
    };
    let mut table = Table {
        caption: format!(
            "a and p₀ of the ellipse p² = p₀²(1 − r²/a²) fitted to the pairs' pressures f_n / A_c against their radius r (mirrored about the axis), against Hertz's a = {a_h:.4} mm, p₀ = {p0_h:.1} MPa; Σ f_z of the pairs × 4 against P; pair scatter: the RMS of the single pairs' pressures about the fitted ellipse for r < 0.8a, over p₀ (the node coupling's traction-transfer error on faces that do not nest, as the patch test measures it)."
        ),
        header: [
            "sphere core cell",
            "block cell at the contact",
            "pairs closed",
            "a",
            "error",
            "p₀",
            "error",
            "4 Σ f_z / P − 1",
            "pair scatter",
        ]
        .map(String::from)
        .to_vec(),
        rows: Vec::new(),
    };
    let mut passed = true;
    let mut finest = (0.0, 0.0);
    let mut series = Vec::new();
    for &(n, h, layers) in levels {
        let (s, fz) = hertz_run(n, h, layers)?;
        passed &= s.completed();
        let mut pts = Vec::new();
        for r in &s.results.pairs {
            let rr = r.x.hypot(r.y);
            let p = r.pressure.max(0.0);
            pts.push((rr, p));
            if rr > 0.0 {
                pts.push((-rr, p));
            }
        }
        let fit = fit_ellipse(&pts)
            .ok_or_else(|| Error::Model("the 3D Hertz pressure could not be fitted".into()))?;
        let (ea, ep) = (fit.a / a_h - 1.0, fit.p0 / p0_h - 1.0);
        // The single pairs about the fitted ellipse inside r < 0.8 a: RMS
        // over p₀.
        let inside: Vec<f64> = (pts.iter())
            .filter(|q| q.0 >= 0.0 && q.0 < 0.8 * fit.a)
            .map(|q| q.1 - fit.p0 * (1.0 - (q.0 / fit.a).powi(2)).max(0.0).sqrt())
            .collect();
        let scatter = (inside.iter().map(|d| d * d).sum::<f64>() / inside.len().max(1) as f64)
            .sqrt()
            / fit.p0;
        let sum = 4.0 * fz / P_HERTZ - 1.0;
        passed &= sum.abs() < 1e-6;
        let closed = (s.results.pairs.iter())
            .filter(|r| r.state == PairState::Bonded)
            .count();
        let core = 1.25 / n as f64;
        table.rows.push(vec![
            format!("{core:.3} mm"),
            format!("{h:.4} mm"),
            format!("{closed} of {}", s.results.pairs.len()),
            format!("{:.4}", fit.a),
            format!("{ea:+.2e}"),
            format!("{:.1}", fit.p0),
            format!("{ep:+.2e}"),
            format!("{sum:.1e}"),
            format!("{:.1} %", 100.0 * scatter),
        ]);
        finest = (ea, ep);
        let mut own: Vec<(f64, f64)> = pts.into_iter().filter(|p| p.0 >= 0.0).collect();
        own.sort_by(|p, q| p.0.total_cmp(&q.0));
        series.push(Series {
            name: format!("pairs, core cell {core:.3} mm"),
            points: own.into_iter().filter(|p| p.0 <= 1.6 * a_h).collect(),
            reference: false,
        });
    }
    series.push(Series {
        name: "Hertz, p₀√(1 − r²/a²)".into(),
        points: (0..=60)
            .map(|i| {
                let r = a_h * i as f64 / 60.0;
                (r, p0_h * (1.0 - (r / a_h).powi(2)).max(0.0).sqrt())
            })
            .chain([(1.6 * a_h, 0.0)])
            .collect(),
        reference: true,
    });
    passed &= finest.0.abs() < TOL_A && finest.1.abs() < TOL_P;
    Ok(Case {
        title: "3D Hertz: a sphere on a flat block".into(),
        setup: format!(
            "A quarter model: a steel sphere R = 10 mm (E = 210 GPa, ν = 0.3) — its cap r ≤ 2.5 mm, an O-grid quarter disc of HEX8 extruded from the spherical surface z = R − √(R² − r²) to a flat top z = 2.5 mm in layers thinning towards the contact — on an aluminium block [0, 6]² × [−6, 0] mm (E = 70 GPa, ν = 0.33; HEX8 of size h up to 1.5 mm, then growing) held at its bottom; symmetry supports on x = 0 and y = 0; P/4 = {} N on the cap's top (a uniform traction), force-controlled; frictionless node coupling with search_distance = 0.5 mm: each sphere node paired with the nearest block face, its initial gap g₀ kept. One increment from all pairs bonded.\n\n```text\n          P/4 on the top\n        +------+\n        |  cap  \\   sphere r ≤ 2.5, R = 10\n         `--.__ /\n  ------------`'------------ z = 0  (g₀ = R − √(R² − r²))\n  |  block [0, 6]² × [−6, 0] |\n  +--------------------------+  held\n```",
            P_HERTZ / 4.0
        ),
        reference: "Hertz (Johnson, Contact Mechanics, §4.2): 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂, a = (3PR/(4E*))^⅓, p₀ = 3P/(2πa²), p(r) = p₀√(1 − r²/a²). The cap's finite size does not change a and p₀ at a fixed force (a ≈ 1 mm ≪ 2.5 mm); the block is 6a.".into(),
        tables: vec![table],
        plots: vec![Plot {
            file: "solid_hertz.png".into(),
            title: "3D Hertz sphere: pair pressure against the radius".into(),
            x: "r [mm]".into(),
            y: "pressure [MPa]".into(),
            log: (false, false),
            series,
        }],
        verdict: format!(
            "At the finest mesh a is within {:+.2e} and p₀ within {:+.2e} of Hertz (asserted {:.0} % and {:.0} %); the pairs carry P to round-off. Single pairs scatter about the profile (the faces do not nest), which the fit averages out.",
            finest.0,
            finest.1,
            100.0 * TOL_A,
            100.0 * TOL_P
        ),
        passed,
    })
}

/// The 3D Hertz case's tolerances on a and p₀ at its finest mesh.
const TOL_A: f64 = 0.02;
const TOL_P: f64 = 0.03;

/// Shaft (steel) and ring (aluminium): E, ν; radii (shaft bore, fit, ring
/// outer); radial interference.
const SHAFT: (f64, f64) = (210_000.0, 0.3);
const RING: (f64, f64) = (70_000.0, 0.33);
const RADII: [f64; 3] = [5.0, 10.0, 20.0];
const DELTA: f64 = 0.05;

/// One shrink-fit run at level k, the shaft `ratio` × finer around than the
/// ring: the mean pair pressure Σ f_n / Σ A_c, the smallest and largest pair
/// pressure, the ring's outer u_r (mean), the number of pairs.
fn fit_run(k: usize, ratio: usize) -> Result<(f64, (f64, f64), f64, usize)> {
    let [a_s, b, c] = RADII;
    let t = 1.0;
    let ring = extrude(
        &quarter_annulus([b, c], 4 * k, 24 * k),
        1,
        |_, l| t * l as f64,
        0.5 * (b + c),
    );
    let shaft = extrude(
        &quarter_annulus([a_s, b + DELTA], 4 * k, 24 * ratio * k),
        1,
        |_, l| t * l as f64,
        0.5 * (a_s + b),
    );
    let parts = vec![
        part("ring", ring, RING.0, RING.1)?,
        part("shaft", shaft, SHAFT.0, SHAFT.1)?,
    ];
    let mut def = interface(&parts, 0, 1, "outer", Law::Frictionless, 1e3 * RING.0)?;
    def.search_distance = 5.0 * DELTA;
    let mut supports = Vec::new();
    for p in 0..2 {
        supports.extend(symmetry(&parts, p)?);
        supports.push(roller(&parts, p, "bottom", 2)?);
        supports.push(roller(&parts, p, "top", 2)?);
    }
    let s = solve("shrink fit", parts, vec![def], supports, vec![], &[1])?;
    if !s.completed() {
        return Err(Error::Model(format!(
            "3D shrink fit at k = {k}: {}",
            s.results.summary.status
        )));
    }
    let (mut f, mut area) = (0.0, 0.0);
    let mut range = (f64::INFINITY, f64::NEG_INFINITY);
    for r in &s.results.pairs {
        f += r.force_n;
        area += r.tributary;
        range = (range.0.min(r.pressure), range.1.max(r.pressure));
    }
    let ring = &s.analysis.model.parts[0].mesh;
    let outer = ring.boundary_nodes("outer").unwrap_or_default();
    let ur: f64 = outer
        .iter()
        .map(|&n| {
            let (x, u) = (ring.nodes[n], s.u(0, n));
            (u[0] * x[0] + u[1] * x[1]) / x[0].hypot(x[1])
        })
        .sum::<f64>()
        / outer.len() as f64;
    Ok((f / area, range, ur, s.results.pairs.len()))
}

/// The shrink fit against Lamé: a quarter slice, z held on both faces (plane
/// strain), the interference through the initial gaps (overclosure).
pub fn shrink_fit(quick: bool) -> Result<Case> {
    let levels: &[usize] = if quick { &[1, 2, 4] } else { &[1, 2, 4, 8] };
    let p_ref = shrink_fit_pressure(DELTA, RADII, SHAFT, RING);
    let ur_ref = ring_ur(p_ref, RADII[1], RADII[2], RING, RADII[2]);
    let mut table = Table {
        caption: format!(
            "Level k: the ring 4k × 24k HEX8 (radial × around the quarter), the shaft 4k × 48k (twice as fine around: every other shaft node faces the middle of a ring facet, where the polygons overlap by δ + h²/(8b), so single pairs alternate, as in 2D; the last row has the shaft as fine as the ring), one layer. Mean pressure = Σ f_n / Σ A_c over the pairs; spread = (largest − smallest pair pressure) / p. Lamé (plane strain): p = {p_ref:.3} MPa, u_r(c) = {}.",
            sci(ur_ref)
        ),
        header: [
            "k",
            "pairs",
            "mean pressure",
            "error",
            "order",
            "spread",
            "u_r(c) mean",
            "error",
        ]
        .map(String::from)
        .to_vec(),
        rows: Vec::new(),
    };
    let mut errs = Vec::new();
    let mut rows = Vec::new();
    for &k in levels {
        let (mean, range, ur, pairs) = fit_run(k, 2)?;
        errs.push(mean / p_ref - 1.0);
        rows.push((k, pairs, mean, (range.1 - range.0) / p_ref, ur));
    }
    let ord = orders(&errs);
    let mut last_u = 0.0;
    for (i, (k, pairs, mean, spread, ur)) in rows.iter().enumerate() {
        last_u = ur / ur_ref - 1.0;
        table.rows.push(vec![
            k.to_string(),
            pairs.to_string(),
            format!("{mean:.3}"),
            format!("{:+.3} %", 100.0 * errs[i]),
            ord[i].clone(),
            format!("{:.2} %", 100.0 * spread),
            sci(*ur),
            format!("{:+.3} %", 100.0 * last_u),
        ]);
    }
    // The diagnosis of the single pairs' alternation: the finest level with
    // the shaft's nodes at the ring's vertices' angles (ratio 1), where the
    // two polygons overlap by δ everywhere.
    let finest = levels[levels.len() - 1];
    let (mean1, range1, _, pairs1) = fit_run(finest, 1)?;
    let spread1 = (range1.1 - range1.0) / p_ref;
    table.rows.push(vec![
        format!("{finest}, shaft as fine as the ring"),
        pairs1.to_string(),
        format!("{mean1:.3}"),
        format!("{:+.3} %", 100.0 * (mean1 / p_ref - 1.0)),
        String::new(),
        format!("{:.2} %", 100.0 * spread1),
        String::new(),
        String::new(),
    ]);
    let n = errs.len() - 1;
    let passed = errs[n].abs() < 0.01
        && last_u.abs() < 0.01
        && errs[n].abs() < errs[0].abs()
        && spread1 < 0.01;
    Ok(Case {
        title: "3D shrink fit against Lamé".into(),
        setup: format!(
            "A quarter slice (one HEX8 layer, z held on both faces of both parts: plane strain; x held on x = 0, y on y = 0): a steel hollow shaft {} ≤ r ≤ {} + δ (E = 210 GPa, ν = 0.3) in an aluminium ring {} ≤ r ≤ {} (E = 70 GPa, ν = 0.33), radial interference δ = {DELTA} mm, no load. Frictionless node coupling of the shaft's outer face on the ring (search_distance = 5δ): every pair starts overclosed, g₀ ≈ −δ to the ring's facets, and the fit is the contact's answer. (The facing rule keeps the shaft's rim nodes, which lie in the ring's symmetry planes, off those planes' faces, so the quarter model works in 3D.)\n\n```text\n   y|‾‾‾-._   ring b ≤ r ≤ c\n    |‾-.   `.\n    |   \\shaft\\\n    |__  |     |\n       | |     |\n  -----+-+-----+-- x   (δ overlap at r = b)\n```",
            RADII[0], RADII[1], RADII[1], RADII[2]
        ),
        reference: "Lamé, plane strain (as the 2D shrink-fit case): p = δ / (b(1 + ν_r)/E_r ((1 − 2ν_r)b² + c²)/(c² − b²) + b(1 + ν_s)/E_s ((1 − 2ν_s)b² + a²)/(b² − a²)), u_r(c) of the ring under p.".into(),
        tables: vec![table],
        plots: vec![],
        verdict: format!(
            "The mean contact pressure is within {:+.3} % of Lamé and the ring's outer u_r within {:+.3} % at the finest level (asserted 1 %, the pressure error falling with refinement, as the 2D node coupling's: the facets' sagitta h²/(8b) adds to the overlap); with the shaft's nodes at the ring's vertices every pair carries the same pressure (spread {:.2} %, asserted < 1 %).",
            100.0 * errs[n],
            100.0 * last_u,
            100.0 * spread1
        ),
        passed,
    })
}
