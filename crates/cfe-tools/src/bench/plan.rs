//! Which cases the benchmark runs: the refined problem with the `rigid` and the
//! `contact` law at refinements doubling up to the largest size, the
//! `frictionless` and `coulomb` laws at its headline sizes, and beside them a
//! Gmsh problem and a frictional run at about a quarter of that size; and the
//! 3D plate on a base at about 50k, 100k, 200k and 400k unknowns; and (`--only
//! petsc`) the same 3D problem on the PETSc back end from 50k to a million
//! unknowns, on 1 and 2 MPI ranks.

use super::Group;
use cfe::Law;
use std::path::{Path, PathBuf};

/// Friction coefficient of the benchmark's frictional run.
pub const FRICTION: f64 = 0.2;

/// The refinement factors to run: 1, 2, 4, … doubling while within
/// `max_unknowns` and a million unknowns, then the first factors that reach the
/// reference sizes of 1 M and 4 M unknowns and `max_unknowns` itself (the last
/// replacing the last doubling when within 25 % of it). `unknowns(K)` predicts the
/// unknowns at refinement K.
pub fn refinements(unknowns: impl Fn(usize) -> f64, max_unknowns: usize) -> Vec<usize> {
    let max = max_unknowns as f64;
    let mut ks = vec![1usize];
    let mut last = 1;
    while unknowns(2 * last) <= max.min(1e6) {
        last *= 2;
        ks.push(last);
    }
    let reaching = |size: f64| {
        let mut k = 1;
        while unknowns(k) < size {
            k += 1;
        }
        k
    };
    for size in [1e6, 4e6] {
        if size <= max {
            ks.push(reaching(size));
        }
    }
    let last = ks[ks.len() - 1];
    let reach = reaching(max);
    if reach > last {
        if reach as f64 <= 1.25 * last as f64 && ks.len() > 1 {
            let end = ks.len() - 1;
            ks[end] = reach;
        } else {
            ks.push(reach);
        }
    }
    ks.sort_unstable();
    ks.dedup();
    ks
}

/// The headline refinements among `ks` (ascending): the first reaching each
/// reference size, 1 M and 4 M unknowns, within `max_unknowns`; the largest
/// when none does. `unknowns(K)` predicts the unknowns at refinement K.
pub fn headline(ks: &[usize], unknowns: impl Fn(usize) -> f64, max_unknowns: usize) -> Vec<usize> {
    let mut heads: Vec<usize> = [1e6, 4e6]
        .into_iter()
        .filter(|&size| size <= max_unknowns as f64)
        .filter_map(|size| ks.iter().copied().find(|&k| unknowns(k) >= size))
        .collect();
    heads.dedup();
    if heads.is_empty() {
        heads.extend(ks.last().copied());
    }
    heads
}

/// The unknowns of a 2D structured model at refinement K, `a K² + b K`, fitted to
/// the counts at K = 1 and K = 2.
pub fn unknowns_model(n1: usize, n2: usize) -> impl Fn(usize) -> f64 {
    let (n1, n2) = (n1 as f64, n2 as f64);
    let a = (n2 - 2.0 * n1) / 2.0;
    let b = n1 - a;
    move |k: usize| a * (k * k) as f64 + b * k as f64
}

/// The 3D rows' sizes (unknowns): the refinement of the 3D problem nearest each
/// (in ratio) is run.
pub const SOLID_SIZES: [f64; 4] = [5e4, 1e5, 2e5, 4e5];

/// The unknowns of a 3D structured model at refinement K, `a K³ + b K² + c K`
/// (nodes of boxes of K-times the cells, less the held components), through
/// the counts at K = 1, 2 and 3.
pub fn solid_unknowns_model(n: [usize; 3]) -> impl Fn(usize) -> f64 {
    let [n1, n2, n3] = n.map(|v| v as f64);
    // a + b + c = n1, 8a + 4b + 2c = n2, 27a + 9b + 3c = n3.
    let (p, q) = (n2 - 2.0 * n1, n3 - 3.0 * n1); // 6a + 2b, 24a + 6b
    let a = (q - 3.0 * p) / 6.0;
    let b = (p - 6.0 * a) / 2.0;
    let c = n1 - a - b;
    move |k: usize| {
        let k = k as f64;
        ((a * k + b) * k + c) * k
    }
}

/// For each size of `sizes`, the refinement whose unknowns (`unknowns(K)`) are
/// nearest it in ratio, ascending without repeats.
pub fn solid_refinements(unknowns: impl Fn(usize) -> f64, sizes: &[f64]) -> Vec<usize> {
    let mut ks: Vec<usize> = sizes
        .iter()
        .map(|&size| {
            let off = |k: usize| (unknowns(k).max(1.0) / size).ln().abs();
            let mut k = 1;
            while off(k + 1) < off(k) {
                k += 1;
            }
            k
        })
        .collect();
    ks.sort_unstable();
    ks.dedup();
    ks
}

/// The benchmark's 3D problem: `plate_on_base_3d_bench.toml` next to the
/// problem file, as in the repository's examples, when it is there.
pub(super) fn solid_problem(problem: &Path) -> Option<PathBuf> {
    let solid = problem
        .parent()
        .unwrap_or(Path::new("."))
        .join("plate_on_base_3d_bench.toml");
    solid.exists().then_some(solid)
}

/// The 3D rows: `problem` (a solid model) with the `frictionless` law (its
/// file's: consistent states on every mesh) at the refinements of
/// [`solid_refinements`] for [`SOLID_SIZES`], from its unknowns `n` at K = 1,
/// 2 and 3.
pub(super) fn solid_plan(problem: &Path, n: [usize; 3]) -> Vec<Planned> {
    solid_refinements(solid_unknowns_model(n), &SOLID_SIZES)
        .into_iter()
        .map(|refine| Planned {
            path: problem.to_path_buf(),
            group: Group::Solid,
            law: Law::Frictionless,
            refine,
            ranks: None,
        })
        .collect()
}

/// The PETSc rows' sizes (unknowns of the 3D problem): the direct rows'
/// ([`SOLID_SIZES`], for the crossover) and on to a million.
pub const PETSC_SIZES: [f64; 6] = [5e4, 1e5, 2e5, 4e5, 7e5, 1e6];

/// The MPI ranks each PETSc row runs on (`mpirun -n 2` for 2).
pub const PETSC_RANKS: [usize; 2] = [1, 2];

/// The sizes of `sizes` within `max_unknowns`, or `max_unknowns` alone when
/// it is below them all (a small check of the rows); with `beyond`, also
/// `max_unknowns` itself when it is beyond the last of them (a larger row
/// asked for: the largest model the memory holds).
pub fn sizes_within(sizes: &[f64], max_unknowns: usize, beyond: bool) -> Vec<f64> {
    let max = max_unknowns as f64;
    let mut within: Vec<f64> = sizes.iter().copied().filter(|&s| s <= max).collect();
    match within.last() {
        None => within.push(max),
        Some(&last) if beyond && max > last => within.push(max),
        Some(_) => {}
    }
    within
}

/// `cfe bench --only petsc`: the 3D problem (a solid model) with the
/// `frictionless` law, first on the direct solver at the refinements of
/// [`SOLID_SIZES`] (for the crossover), then on `--solver petsc` (CG + GAMG)
/// at those of [`PETSC_SIZES`], each on every rank count of [`PETSC_RANKS`];
/// the sizes within `max_unknowns` ([`sizes_within`]: a PETSc row beyond a
/// million when `max_unknowns` is, no direct row beyond 400k), from the unknowns
/// `n` at K = 1, 2 and 3.
pub(super) fn petsc_plan(problem: &Path, n: [usize; 3], max_unknowns: usize) -> Vec<Planned> {
    let model = solid_unknowns_model(n);
    let row = |group, refine, ranks| Planned {
        path: problem.to_path_buf(),
        group,
        law: Law::Frictionless,
        refine,
        ranks,
    };
    let direct = solid_refinements(&model, &sizes_within(&SOLID_SIZES, max_unknowns, false));
    let petsc = solid_refinements(&model, &sizes_within(&PETSC_SIZES, max_unknowns, true));
    let mut cases: Vec<Planned> = direct
        .into_iter()
        .map(|k| row(Group::Solid, k, None))
        .collect();
    for k in petsc {
        for ranks in PETSC_RANKS {
            cases.push(row(Group::Petsc, k, Some(ranks)));
        }
    }
    cases
}

/// A case the benchmark runs: the problem file, its row group and law, and the
/// refinement.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Planned {
    /// The problem file.
    pub path: PathBuf,
    /// The report's row group.
    pub group: Group,
    /// The law (`--law`).
    pub law: Law,
    /// Refinement factor (`--refine`).
    pub refine: usize,
    /// The MPI ranks of a run on `--solver petsc` (`None`: the direct solver).
    pub ranks: Option<usize>,
}

/// The sizes a plan is made from, each measured by one run.
#[derive(Debug, Clone)]
pub(super) struct Probe {
    /// Unknowns of the problem at K = 1.
    pub n1: usize,
    /// Unknowns of the problem at K = 2.
    pub n2: usize,
    /// The Gmsh problem, when there, with its unknowns at K = 1.
    pub gmsh: Option<(PathBuf, usize)>,
    /// The 3D problem, when there, with its unknowns at K = 1, 2 and 3.
    pub solid: Option<(PathBuf, [usize; 3])>,
}

/// The Gmsh problem of the benchmark: the roller in its cradle, next to the
/// problem file's folder as in the repository's examples, when it is there.
pub(super) fn gmsh_problem(problem: &Path) -> Option<PathBuf> {
    let roller = problem
        .parent()
        .unwrap_or(Path::new("."))
        .join("roller_in_cradle/roller_in_cradle.toml");
    roller.exists().then_some(roller)
}

/// The cases to run, in order: `problem` with the `rigid` law at every
/// refinement of [`refinements`], then with `contact`; then at each
/// [`headline`] refinement with `frictionless` and `coulomb` (the stick law's
/// rows beside laws that have consistent states); then the Gmsh problem
/// (when there) and a frictional run of `problem` (every increment of which is
/// solved: no proportional shortcut), each at about a quarter of the largest size
/// (at most a million unknowns); last the 3D rows ([`solid_plan`]) when the
/// 3D problem is there.
pub(super) fn plan(problem: &Path, max_unknowns: usize, probe: &Probe) -> Vec<Planned> {
    let unknowns = unknowns_model(probe.n1, probe.n2);
    let ks = refinements(&unknowns, max_unknowns);
    let case = |path: &Path, group, law, refine| Planned {
        path: path.to_path_buf(),
        group,
        law,
        refine,
        ranks: None,
    };
    let mut cases: Vec<Planned> = [Law::Rigid, Law::Contact]
        .into_iter()
        .flat_map(|law| ks.iter().map(move |&k| (law, k)))
        .map(|(law, k)| case(problem, Group::Plate, law, k))
        .collect();
    for k in headline(&ks, &unknowns, max_unknowns) {
        for law in [Law::Frictionless, Law::Coulomb] {
            cases.push(case(problem, Group::Laws, law, k));
        }
    }
    let target = (max_unknowns as f64 / 4.0).min(1e6);
    let refine_for = |n1: usize| ((target / (n1 as f64).max(1.0)).sqrt().floor() as usize).max(1);
    if let Some((roller, n1)) = &probe.gmsh {
        cases.push(case(roller, Group::Gmsh, Law::Contact, refine_for(*n1)));
    }
    cases.push(case(
        problem,
        Group::Friction,
        Law::Coulomb,
        refine_for(probe.n1),
    ));
    if let Some((solid, n)) = &probe.solid {
        cases.extend(solid_plan(solid, *n));
    }
    cases
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Refinements double up to the target (or a million unknowns), then reach
    /// 1 M, 4 M and the target;
    /// the unknowns model reproduces the plate-on-base counts it is fitted to.
    #[test]
    fn refinement_sequence() {
        let n = unknowns_model(910, 3450);
        assert_eq!((n(1), n(2)), (910.0, 3450.0));
        assert_eq!(refinements(&n, 4_000_000), vec![1, 2, 4, 8, 16, 32, 35, 70]);
        assert_eq!(
            refinements(&n, 8_100_000),
            vec![1, 2, 4, 8, 16, 32, 35, 70, 100]
        );
        assert_eq!(refinements(&n, 100_000), vec![1, 2, 4, 8, 12]);
        assert_eq!(refinements(&n, 910), vec![1]);
    }

    /// The headline refinements are the first levels reaching 1 M and 4 M
    /// unknowns (each within the largest size), or the largest level below a
    /// million.
    #[test]
    fn the_headline_sizes_are_the_reference_sizes() {
        let n = unknowns_model(910, 3450);
        let at = |max| headline(&refinements(&n, max), &n, max);
        assert_eq!(at(4_000_000), [35, 70]);
        assert_eq!(at(8_100_000), [35, 70]);
        assert_eq!(at(1_000_000), [35]);
        assert_eq!(at(100_000), [12]);
        assert!(n(35) >= 1e6 && n(34) < 1e6 && n(70) >= 4e6 && n(69) < 4e6);
    }

    /// The levels rise and stop at the first K whose unknowns reach
    /// `max_unknowns` (K − 1 has fewer), for targets below, at and above a
    /// million unknowns.
    #[test]
    fn the_levels_reach_the_largest_size_and_no_further() {
        let n = unknowns_model(910, 3450);
        for max in [5_000, 20_000, 250_000, 1_000_000, 2_500_000] {
            let ks = refinements(&n, max);
            let last = ks[ks.len() - 1];
            assert!(
                n(last) >= max as f64 && n(last - 1) < max as f64,
                "{max}: {ks:?}"
            );
            assert!(ks.windows(2).all(|w| w[0] < w[1]), "{max}: {ks:?}");
        }
    }

    /// The plan at 4 M unknowns: the plate's eight levels with `rigid`, then
    /// with `contact`, then the roller at a quarter of the size (1 M: from its
    /// 2 000 unknowns at K = 1, K = ⌊√500⌋ = 22) and the frictional run at the
    /// same size (⌊√(1e6 / 910)⌋ = 33); without the roller, only the frictional
    /// run follows the plate.
    #[test]
    fn the_plan_runs_both_laws_then_the_roller_and_friction() {
        let problem = Path::new("examples/plate_on_base.toml");
        let roller = PathBuf::from("examples/roller_in_cradle/roller_in_cradle.toml");
        let probe = Probe {
            n1: 910,
            n2: 3450,
            gmsh: Some((roller.clone(), 2000)),
            solid: None,
        };
        let cases = plan(problem, 4_000_000, &probe);
        let levels = [1, 2, 4, 8, 16, 32, 35, 70];
        assert_eq!(cases.len(), 2 * levels.len() + 4 + 2);
        for (i, law) in [Law::Rigid, Law::Contact].into_iter().enumerate() {
            let rows = &cases[i * levels.len()..(i + 1) * levels.len()];
            assert!(rows.iter().all(|c| c.law == law && c.group == Group::Plate));
            assert_eq!(rows.iter().map(|c| c.refine).collect::<Vec<_>>(), levels);
        }
        // The headline sizes, 1 M (K = 35) and 4 M (K = 70), with the
        // frictionless and the Coulomb law.
        let laws: Vec<(Group, Law, usize)> = cases[2 * levels.len()..2 * levels.len() + 4]
            .iter()
            .map(|c| (c.group, c.law, c.refine))
            .collect();
        assert_eq!(
            laws,
            [
                (Group::Laws, Law::Frictionless, 35),
                (Group::Laws, Law::Coulomb, 35),
                (Group::Laws, Law::Frictionless, 70),
                (Group::Laws, Law::Coulomb, 70)
            ]
        );
        let extra = &cases[2 * levels.len() + 4..];
        assert_eq!(
            (
                extra[0].group,
                extra[0].law,
                extra[0].refine,
                &extra[0].path
            ),
            (Group::Gmsh, Law::Contact, 22, &roller)
        );
        assert_eq!(
            (extra[1].group, extra[1].law, extra[1].refine),
            (Group::Friction, Law::Coulomb, 33)
        );
        let small = plan(
            problem,
            20_000,
            &Probe {
                gmsh: None,
                ..probe
            },
        );
        let last = &small[small.len() - 1];
        // A quarter of 20 000 unknowns: ⌊√(5000 / 910)⌋ = 2.
        assert_eq!((last.group, last.refine), (Group::Friction, 2));
        // Below a million unknowns the headline is the largest size, K = 5.
        let laws: Vec<(Law, usize)> = small
            .iter()
            .filter(|c| c.group == Group::Laws)
            .map(|c| (c.law, c.refine))
            .collect();
        assert_eq!(laws, [(Law::Frictionless, 5), (Law::Coulomb, 5)]);
        assert_eq!(
            small
                .iter()
                .filter(|c| !matches!(c.group, Group::Plate | Group::Laws))
                .count(),
            1
        );
    }

    /// The 3D unknowns model goes through its three counts and reproduces the
    /// benchmark's 3D problem at K = 4 (counted: 3 × (113·17·9 + 41·5·13)
    /// nodes' components less 3 × 41·5 held at the base's bottom and 3 at the
    /// plate's two supports = 59 244); the 3D rows are the K = 4, 5, 6, 8 of
    /// about 50k, 100k, 200k and 400k unknowns, with the frictionless law.
    #[test]
    fn the_3d_rows_are_the_refinements_nearest_the_3d_sizes() {
        // The structured count of examples/plate_on_base_3d_bench.toml.
        let exact = |k: usize| {
            let nodes =
                (28 * k + 1) * (4 * k + 1) * (2 * k + 1) + (10 * k + 1) * (k + 1) * (3 * k + 1);
            3 * nodes - 3 * (10 * k + 1) * (k + 1) - 3
        };
        let n = solid_unknowns_model([exact(1), exact(2), exact(3)]);
        for k in 1..=3 {
            assert!((n(k) - exact(k) as f64).abs() < 1e-6 * exact(k) as f64);
        }
        assert!((n(4) - 59_244.0).abs() < 1e-6 * 59_244.0, "{}", n(4));
        // Exact up to the constant term the fit leaves out.
        for k in 4..=10 {
            assert!(
                (n(k) - exact(k) as f64).abs() <= 10.0,
                "{k}: {} {}",
                n(k),
                exact(k)
            );
        }
        assert_eq!(solid_refinements(&n, &SOLID_SIZES), vec![4, 5, 6, 8]);
        let cases = solid_plan(Path::new("p3d.toml"), [exact(1), exact(2), exact(3)]);
        assert_eq!(
            cases.iter().map(|c| c.refine).collect::<Vec<_>>(),
            [4, 5, 6, 8]
        );
        assert!(
            cases
                .iter()
                .all(|c| c.group == Group::Solid && c.law == Law::Frictionless)
        );
        // Two sizes nearest the same K give it once.
        assert_eq!(
            solid_refinements(|k| 1e5 * k as f64, &[1e5, 1.2e5, 4e5]),
            vec![1, 4]
        );
    }

    /// `--only petsc`: the direct 3D rows (K = 4, 5, 6, 8), then the PETSc
    /// rows at the refinements nearest 50k … 1M unknowns, each on 1 then 2
    /// ranks; a `--max-unknowns` beyond a million adds a PETSc row there (not
    /// a direct one), and a small one (a check) runs one size of each.
    #[test]
    fn the_petsc_rows_run_on_one_and_two_ranks_up_to_a_million() {
        let exact = |k: usize| {
            let nodes =
                (28 * k + 1) * (4 * k + 1) * (2 * k + 1) + (10 * k + 1) * (k + 1) * (3 * k + 1);
            3 * nodes - 3 * (10 * k + 1) * (k + 1) - 3
        };
        let n = [exact(1), exact(2), exact(3)];
        let rows = |max| {
            petsc_plan(Path::new("p3d.toml"), n, max)
                .iter()
                .map(|c| (c.group, c.refine, c.ranks))
                .collect::<Vec<_>>()
        };
        let mut want = vec![
            (Group::Solid, 4, None),
            (Group::Solid, 5, None),
            (Group::Solid, 6, None),
            (Group::Solid, 8, None),
        ];
        // 2e5 → K = 6 (188k), 4e5 → 8 (431k), 7e5 → 9 or 10, 1e6 → 11.
        let ks: Vec<usize> = solid_refinements(solid_unknowns_model(n), &PETSC_SIZES);
        assert_eq!(&ks[..4], [4, 5, 6, 8]);
        assert!(
            ks.windows(2).all(|w| w[0] < w[1]) && ks.len() == 6,
            "{ks:?}"
        );
        let last = ks[5];
        assert!(
            (exact(last) as f64 / 1e6 - 1.0).abs() < 0.15,
            "{last}: {}",
            exact(last)
        );
        for &k in &ks {
            want.extend([(Group::Petsc, k, Some(1)), (Group::Petsc, k, Some(2))]);
        }
        assert_eq!(rows(1_000_000), want);
        // Beyond a million: one more PETSc size, no more direct ones.
        let beyond = rows(4_000_000);
        assert_eq!(beyond.len(), want.len() + 2);
        assert_eq!(beyond[..want.len()], want[..]);
        let k4m = beyond[want.len()].1;
        let n4m = exact(k4m) as f64;
        assert!(n4m > 3.5e6 && n4m < 4.5e6, "{n4m}");
        assert_eq!(beyond[want.len() + 1], (Group::Petsc, k4m, Some(2)));
        // A small check: K = 2 (8 826 unknowns) alone, direct and PETSc.
        assert_eq!(
            rows(10_000),
            [
                (Group::Solid, 2, None),
                (Group::Petsc, 2, Some(1)),
                (Group::Petsc, 2, Some(2))
            ]
        );
        assert_eq!(sizes_within(&[1.0, 2.0], 3, false), [1.0, 2.0]);
        assert_eq!(sizes_within(&[1.0, 2.0], 3, true), [1.0, 2.0, 3.0]);
        assert_eq!(sizes_within(&[5.0], 3, false), [3.0]);
    }
}
