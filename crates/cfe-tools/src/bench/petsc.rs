//! The report's PETSc section (`cfe bench --only petsc`): the 3D plate on a
//! base on `--solver petsc` (CG + GAMG) on 1 and 2 MPI ranks — setup against
//! solve, CG iterations per contact iteration, peak memory per rank — the
//! crossover with the direct rows of the same report, the target at a
//! million unknowns, the largest model in 24 GiB and a written extrapolation
//! to a cluster, every figure from the rows.

use super::Run;
use cfe::Summary;
use std::fmt::Write as _;

/// The target: 10⁶ 3D unknowns with contact in at most this many
/// seconds end to end…
const TARGET_SECONDS: f64 = 60.0;
/// …and this much memory (GiB, the whole machine: every rank).
const TARGET_GIB: f64 = 12.0;

/// Bytes in a GiB.
const GIB: f64 = 1073741824.0;

/// The figures of one PETSc row, from its summary.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Row {
    /// Unknowns.
    pub n: f64,
    /// MPI ranks.
    pub ranks: usize,
    /// End-to-end seconds.
    pub total: f64,
    /// Seconds assembling `K(states)` into PETSc and building preconditioners.
    pub setup: f64,
    /// Seconds in CG solves.
    pub solve: f64,
    /// Linear solves (contact iterations that solved).
    pub solves: usize,
    /// CG iterations of all solves.
    pub iterations: usize,
    /// The most CG iterations of one solve.
    pub most: usize,
    /// Contact iterations (every increment's, a reuse included).
    pub contact: usize,
    /// Preconditioners built.
    pub builds: usize,
    /// Rank 0's peak resident memory, bytes (the ranks hold alike).
    pub peak: f64,
}

impl Row {
    /// The figures of `m`, a run on `ranks` ranks.
    pub fn of(m: &Summary, ranks: usize) -> Row {
        let its = m.linear_solver.as_ref().map_or(&[][..], |l| &l.iterations);
        Row {
            n: m.unknowns as f64,
            ranks,
            total: m.timings.total,
            setup: m.timings.solve.factorization,
            solve: m.timings.solve.solve,
            solves: its.len(),
            iterations: its.iter().sum(),
            most: its.iter().copied().max().unwrap_or(0),
            contact: m.iteration_history.iter().map(Vec::len).sum(),
            builds: m.factorizations,
            peak: m.peak_memory_bytes.unwrap_or(0) as f64,
        }
    }

    /// CG iterations per linear solve (per contact iteration that solved).
    pub fn per_solve(&self) -> f64 {
        self.iterations as f64 / (self.solves.max(1)) as f64
    }

    /// Seconds outside PETSc's setup and solves: meshing, pair search, the
    /// replicated contact scheme, stresses, output (what more ranks do not
    /// shorten).
    pub fn replicated_seconds(&self) -> f64 {
        (self.total - self.setup - self.solve).max(0.0)
    }
}

/// Where the PETSc path starts to beat the direct solver, from rows of the
/// same refinements: `pairs` holds per size (ascending) the unknowns, the
/// direct run's seconds and the PETSc run's. `None` without a pair;
/// `Crossover::Below` when PETSc is faster at every pair, `Beyond` when at
/// none, else `Between` the last size where the direct solver is faster and
/// the first from which PETSc stays faster, with the size where the log of
/// the time ratio, interpolated linearly in log n, is zero.
pub(super) fn crossover(pairs: &[(f64, f64, f64)]) -> Option<Crossover> {
    let first = pairs.first()?;
    let faster = |p: &(f64, f64, f64)| p.2 < p.1;
    // The first size from which PETSc is faster at every larger one.
    let from = pairs.iter().rposition(|p| !faster(p)).map_or(0, |i| i + 1);
    if from == 0 {
        return Some(Crossover::Below(first.0));
    }
    if from == pairs.len() {
        return Some(Crossover::Beyond(pairs[pairs.len() - 1].0));
    }
    let (a, b) = (pairs[from - 1], pairs[from]);
    let (ra, rb) = ((a.2 / a.1).ln(), (b.2 / b.1).ln());
    let t = if ra == rb { 1.0 } else { ra / (ra - rb) };
    let at = (a.0.ln() + t * (b.0.ln() - a.0.ln())).exp();
    Some(Crossover::Between {
        at,
        from: a.0,
        to: b.0,
    })
}

/// See [`crossover`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Crossover {
    /// PETSc is faster at every size measured, from this one.
    Below(f64),
    /// The direct solver is faster at every size measured, up to this one.
    Beyond(f64),
    /// Between two sizes, about at `at` unknowns.
    Between { at: f64, from: f64, to: f64 },
}

/// The replicated and the distributed memory of a run, from the peaks per
/// rank on 1 and 2 ranks of the same model (`p(N) ≈ R + D / N`): `R = 2 p₂ −
/// p₁`, `D = 2 (p₁ − p₂)`; `None` when they do not fit that (`p₂ ≥ p₁` or `p₂
/// ≤ p₁ / 2`).
pub(super) fn memory_split(p1: f64, p2: f64) -> Option<(f64, f64)> {
    (p2 < p1 && 2.0 * p2 > p1).then_some((2.0 * p2 - p1, 2.0 * (p1 - p2)))
}

/// The unknowns at which a peak memory growing as from `(n_a, m_a)` to `(n_b,
/// m_b)` (as a power of n) reaches `budget` bytes; `None` unless it grows.
pub(super) fn largest_in(a: (f64, f64), b: (f64, f64), budget: f64) -> Option<(f64, f64)> {
    if b.0 <= a.0 || b.1 <= a.1 || a.1 <= 0.0 {
        return None;
    }
    let p = (b.1 / a.1).ln() / (b.0 / a.0).ln();
    Some((b.0 * (budget / b.1).powf(1.0 / p), p))
}

/// The PETSc section: its table, the crossover with `direct` (the 3D rows on
/// the direct solver), the target, the largest model in 24 GiB and the cluster
/// extrapolation.
pub(super) fn petsc_section(s: &mut String, direct: &[Run], petsc: &[Run]) {
    let _ = writeln!(
        s,
        "## 3D on PETSc: the plate on a base on `--solver petsc` (CG + GAMG), 1 and 2 MPI ranks\n"
    );
    let _ = writeln!(
        s,
        "Each row is `cfe run --solver petsc` (one rank) or `mpirun -n 2 -x RAYON_NUM_THREADS … cfe run --solver petsc` (each rank one thread per core it has), the same model and law as the 3D rows on the direct solver. *contact it.* the contact iterations (every increment's), *solves* the linear solves among them, *CG / solve* CG's iterations per solve (mean, most), *PC builds* the GAMG preconditioners built (kept across the contact iterations otherwise), *setup* assembling `K(states)` into PETSc and building the preconditioners, *solve* the CG solves, *other* the rest (meshing, pair search, the replicated contact scheme, stresses, output: what more ranks do not shorten), *peak per rank* rank 0's peak resident memory (the ranks hold alike; the machine holds ranks × it).\n"
    );
    let _ = writeln!(
        s,
        "| K | unknowns | ranks | status | contact it. | solves | CG / solve (mean, most) | PC builds | setup | solve | other | **total** | peak per rank MiB | machine GiB |"
    );
    let _ = writeln!(s, "|{}", "---|".repeat(14));
    for r in petsc {
        let ranks = r.case.ranks.unwrap_or(1);
        let row = Row::of(r.summary, ranks);
        let _ = writeln!(
            s,
            "| {} | {} | {ranks} | {} | {} | {} | {:.0}, {} | {} | {:.2} | {:.2} | {:.2} | **{:.2}** | {:.0} | {:.2} |",
            r.case.refine,
            r.summary.unknowns,
            super::report::status(r.summary),
            row.contact,
            row.solves,
            row.per_solve(),
            row.most,
            row.builds,
            row.setup,
            row.solve,
            row.replicated_seconds(),
            row.total,
            row.peak / 1048576.0,
            row.peak * ranks as f64 / GIB,
        );
    }
    let _ = writeln!(s);
    let on = |ranks: usize| -> Vec<(usize, Row)> {
        petsc
            .iter()
            .filter(|r| r.case.ranks.unwrap_or(1) == ranks)
            .map(|r| (r.case.refine, Row::of(r.summary, ranks)))
            .collect()
    };
    let (one, two) = (on(1), on(2));
    crossover_lines(s, direct, &one, &two);
    target_line(s, &one, &two);
    largest_line(s, &one);
    cluster(s, &one, &two);
}

/// The crossover with the direct rows, on 1 and on 2 ranks.
fn crossover_lines(s: &mut String, direct: &[Run], one: &[(usize, Row)], two: &[(usize, Row)]) {
    let _ = writeln!(s, "### Crossover with the direct solver\n");
    for (ranks, rows) in [(1, one), (2, two)] {
        let pairs: Vec<(f64, f64, f64)> = rows
            .iter()
            .filter_map(|(k, row)| {
                let d = direct.iter().find(|d| d.case.refine == *k)?;
                Some((row.n, d.summary.timings.total, row.total))
            })
            .collect();
        let list: Vec<String> = pairs
            .iter()
            .map(|(n, d, p)| format!("{:.0}k: {d:.1} s direct, {p:.1} s PETSc", n / 1e3))
            .collect();
        let verdict = match crossover(&pairs) {
            None => "no refinement ran on both (run `--only petsc`: it runs the direct rows too)"
                .to_string(),
            Some(Crossover::Below(n)) => format!(
                "PETSc is faster at every size measured, from {:.0}k unknowns: the crossover is below it",
                n / 1e3
            ),
            Some(Crossover::Beyond(n)) => format!(
                "the direct solver is faster at every size measured, up to {:.0}k unknowns: the crossover is beyond it",
                n / 1e3
            ),
            Some(Crossover::Between { at, from, to }) => format!(
                "PETSc is faster from about {:.0}k unknowns (between the rows of {:.0}k and {:.0}k, the time ratio interpolated in log n)",
                at / 1e3,
                from / 1e3,
                to / 1e3
            ),
        };
        let _ = writeln!(
            s,
            "- {ranks} rank{}: {verdict}{}.",
            if ranks == 1 { "" } else { "s" },
            if list.is_empty() {
                String::new()
            } else {
                format!(" ({})", list.join("; "))
            }
        );
    }
    let _ = writeln!(s);
}

/// The target at a million unknowns, met or not, from the row nearest
/// it (within 25 %) on each rank count.
fn target_line(s: &mut String, one: &[(usize, Row)], two: &[(usize, Row)]) {
    let _ = writeln!(
        s,
        "### Target: 10⁶ 3D unknowns with contact in ≤ {TARGET_SECONDS:.0} s and ≤ {TARGET_GIB:.0} GiB\n"
    );
    for rows in [one, two] {
        let nearest = rows
            .iter()
            .map(|(_, r)| r)
            .min_by(|a, b| (a.n / 1e6).ln().abs().total_cmp(&(b.n / 1e6).ln().abs()))
            .filter(|r| (r.n / 1e6 - 1.0).abs() <= 0.25);
        let _ = match nearest {
            Some(r) => {
                let gib = r.peak * r.ranks as f64 / GIB;
                let met = r.total <= TARGET_SECONDS && gib <= TARGET_GIB;
                writeln!(
                    s,
                    "- {} rank{}, {:.0} unknowns: {:.1} s (≤ {TARGET_SECONDS:.0} s: {}), {gib:.2} GiB on the machine (≤ {TARGET_GIB:.0} GiB: {}): **{}**.",
                    r.ranks,
                    if r.ranks == 1 { "" } else { "s" },
                    r.n,
                    r.total,
                    yes(r.total <= TARGET_SECONDS),
                    yes(gib <= TARGET_GIB),
                    if met { "met" } else { "not met" }
                )
            }
            None => writeln!(
                s,
                "- no row within 25 % of a million unknowns on this rank count: not measured."
            ),
        };
    }
    let _ = writeln!(s);
}

/// `yes` or `no`.
fn yes(ok: bool) -> &'static str {
    if ok { "yes" } else { "no" }
}

/// The largest model in 24 GiB on one rank, extrapolated from the two largest
/// one-rank rows.
fn largest_line(s: &mut String, one: &[(usize, Row)]) {
    let sized: Vec<&Row> = one
        .iter()
        .map(|(_, r)| r)
        .filter(|r| r.peak > 0.0)
        .collect();
    let line = match sized.as_slice() {
        [.., a, b] => match largest_in((a.n, a.peak), (b.n, b.peak), 24.0 * GIB) {
            Some((n, p)) => format!(
                "- Largest 3D model in 24 GiB on `--solver petsc`, one rank: about {:.1} million unknowns — an EXTRAPOLATION, not a run: from {:.0}k to {:.0}k unknowns the peak grows as n^{p:.2} ({:.2} → {:.2} GiB), extended to 24 GiB. `cfe bench --only petsc --max-unknowns N` adds a row at N to measure it.",
                n / 1e6,
                a.n / 1e3,
                b.n / 1e3,
                a.peak / GIB,
                b.peak / GIB
            ),
            None => "- Largest 3D model in 24 GiB on `--solver petsc`: the two largest one-rank rows do not grow.".into(),
        },
        _ => "- Largest 3D model in 24 GiB on `--solver petsc`: needs two one-rank rows with their peak memory.".into(),
    };
    let _ = writeln!(s, "{line}\n");
}

/// The written extrapolation to a cluster from the largest size run on both
/// rank counts.
fn cluster(s: &mut String, one: &[(usize, Row)], two: &[(usize, Row)]) {
    let _ = writeln!(s, "### Extrapolation to a cluster (from the rows above)\n");
    let both = one
        .iter()
        .rev()
        .find_map(|(k, a)| two.iter().find(|(k2, _)| k2 == k).map(|(_, b)| (*k, a, b)));
    let Some((k, a, b)) = both else {
        let _ = writeln!(s, "Needs a refinement run on both 1 and 2 ranks.\n");
        return;
    };
    let n = a.n;
    let _ = writeln!(
        s,
        "At K = {k} ({n:.0} unknowns), one rank against two: {:.1} s against {:.1} s end to end (setup {:.1} → {:.1} s, solve {:.1} → {:.1} s, the rest {:.1} → {:.1} s), {:.0} against {:.0} CG iterations per solve.",
        a.total,
        b.total,
        a.setup,
        b.setup,
        a.solve,
        b.solve,
        a.replicated_seconds(),
        b.replicated_seconds(),
        a.per_solve(),
        b.per_solve()
    );
    let _ = writeln!(s);
    // Communication per CG iteration on N ranks of n/N unknowns each: the
    // halo of a compact block of m unknowns (m/3 nodes) is its surface,
    // about 6 (m/3)^(2/3) nodes of 3 components.
    let halo = |ranks: f64| 6.0 * (n / ranks / 3.0).powf(2.0 / 3.0) * 3.0 * 8.0;
    let _ = writeln!(
        s,
        "- **Communication per CG iteration.** Each matrix–vector product (one per CG iteration on the fine level, and the smoother's and residual's on every level of GAMG's V-cycle) exchanges each rank's halo: with the elements split by recursive coordinate bisection into compact blocks, about 6 (n/3N)^(2/3) nodes' 3 components — at this size {:.0} KiB per rank on 2 ranks, {:.0} KiB on 64 and {:.0} KiB on 1024 (the fine level; the coarse levels add less, with more neighbours). CG adds 2 global reductions (its two inner products) and one more for the residual norm the stop test reads: 8 bytes each, latency-bound (about log₂ N message latencies: some 10–20 µs on 64–1024 ranks of a fast interconnect). At {:.0} iterations per solve that is {:.0} reductions per solve — latency, not bandwidth, is what the reductions cost.",
        halo(2.0) / 1024.0,
        halo(64.0) / 1024.0,
        halo(1024.0) / 1024.0,
        a.per_solve(),
        3.0 * a.per_solve()
    );
    let _ = writeln!(
        s,
        "- **The gather.** After a complete solve (an increment's accepted pattern) the whole solution goes to every rank (the replicated scheme computes internal forces, reactions and stresses from it): 8n = {:.1} MB to each rank; the trial solves of the contact iterations send only the coupling equations' entries. So at most 8n per solve, {} solves in this run — on N ranks up to N × 8n bytes per solve in all, growing with N where the halo shrinks.",
        8.0 * n / 1e6,
        a.solves
    );
    let _ = match memory_split(a.peak, b.peak) {
        Some((r, d)) => writeln!(
            s,
            "- **Memory per rank.** Peak per rank {:.2} GiB on 1 rank, {:.2} GiB on 2: as p(N) ≈ R + D/N, the replicated part (mesh, coupling elements, pair states, node graph, whole-length vectors) is R ≈ {:.2} GiB ({:.0} bytes per unknown) on every rank, the distributed part (the matrices, GAMG's hierarchy, PETSc's vectors) D ≈ {:.2} GiB in all ({:.0} bytes per unknown). On N ranks a rank holds R + D/N: at 32 ranks a node {:.2} GiB each; at 10⁷ unknowns R alone is about {:.1} GiB per rank (linear in n), so the replicated part, not the solver, bounds the model per node.",
            a.peak / GIB,
            b.peak / GIB,
            r / GIB,
            r / n,
            d / GIB,
            d / n,
            (r + d / 32.0) / GIB,
            r / n * 1e7 / GIB,
        ),
        None => writeln!(
            s,
            "- **Memory per rank.** Peak per rank {:.2} GiB on 1 rank, {:.2} GiB on 2: not of the form R + D/N here (the split needs 1/2 p₁ < p₂ < p₁), so no per-rank extrapolation.",
            a.peak / GIB,
            b.peak / GIB
        ),
    };
    let other = a.replicated_seconds();
    let _ = writeln!(
        s,
        "- **What limits scaling.** The replicated mesh and contact loop (every rank meshes the whole model, finds the pairs and runs the same active-set iterations; {other:.1} s of the {:.1} s here) do not shrink with more ranks: even with setup and solve perfectly divided the run cannot go more than {:.1}× faster than on one rank at this size (Amdahl's bound total / rest); GAMG's iterations stay about constant with N (the preconditioner is algebraic over the whole matrix), but its coarse levels gather onto fewer ranks, and the gather above grows with N. Distributing the mesh and the contact scheme (each rank its own pairs, exchanging only the coupling DOFs) is what lifts both limits; it is not done.",
        a.total,
        if other > 0.0 {
            a.total / other
        } else {
            f64::INFINITY
        }
    );
    let _ = writeln!(s);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The crossover: PETSc faster everywhere is `Below` the first size,
    /// nowhere `Beyond` the last; in between, where the log of the time ratio
    /// crosses zero, linearly in log n (ratio 2 at 100k and 1/2 at 400k: at
    /// 200k); a faster PETSc at a small size followed by a slower one does not
    /// count.
    #[test]
    fn the_crossover_is_where_petsc_stays_faster() {
        assert_eq!(crossover(&[]), None);
        assert_eq!(
            crossover(&[(1e5, 10.0, 5.0), (4e5, 50.0, 20.0)]),
            Some(Crossover::Below(1e5))
        );
        assert_eq!(
            crossover(&[(1e5, 1.0, 5.0), (4e5, 50.0, 60.0)]),
            Some(Crossover::Beyond(4e5))
        );
        match crossover(&[(5e4, 1.0, 0.5), (1e5, 10.0, 20.0), (4e5, 40.0, 20.0)]) {
            Some(Crossover::Between { at, from, to }) => {
                assert_eq!((from, to), (1e5, 4e5));
                assert!((at / 2e5 - 1.0).abs() < 1e-12, "{at}");
            }
            other => panic!("{other:?}"),
        }
    }

    /// Peaks of R + D/N on 1 and 2 ranks give R and D back; peaks that do not
    /// fall, or fall by more than half, give none.
    #[test]
    fn the_memory_splits_into_replicated_and_distributed() {
        let (r, d) = (3.0, 8.0);
        assert_eq!(memory_split(r + d, r + d / 2.0), Some((r, d)));
        assert_eq!(memory_split(4.0, 4.0), None);
        assert_eq!(memory_split(4.0, 1.5), None);
    }

    /// A peak growing as n² from (1, 1) to (2, 4) reaches 16 at n = 4; one
    /// that does not grow gives none.
    #[test]
    fn the_largest_model_extends_the_peak_as_a_power() {
        let (n, p) = largest_in((1.0, 1.0), (2.0, 4.0), 16.0).unwrap();
        assert!((n - 4.0).abs() < 1e-12 && (p - 2.0).abs() < 1e-12);
        assert_eq!(largest_in((1.0, 4.0), (2.0, 4.0), 16.0), None);
    }

    /// The section from hand-made rows: a PETSc row per rank count with its
    /// CG iterations per solve (600 over 4 solves: 150, most 200), setup and
    /// solve; the crossover against the direct row of the same K (direct 100 s
    /// against 50 s: PETSc faster from the first); the million-unknown target
    /// met on 1 rank (50 s, 6 GiB) and not on 2 (2 × 7 GiB = 14 GiB > 12); the
    /// memory split R = 2 p₂ − p₁ = 8 GiB, D = 2 (p₁ − p₂) = −2 GiB refused
    /// (p₂ > p₁), so no per-rank extrapolation is claimed.
    #[test]
    fn the_section_reports_the_rows_the_crossover_and_the_target() {
        use super::super::fixture::summary;
        use super::super::{Case, Group, Outcome, runs};
        use cfe::Law;
        use serde_json::json;
        let gib = 1073741824u64;
        let m = |total: f64, peak: u64| {
            summary(json!({
                "unknowns": 1_000_000, "timings": {"total": total, "factorization": 5.0,
                    "solve": 30.0},
                "factorizations": 2, "peak_memory_bytes": peak,
                "iteration_history": [[{"method": "factorization", "changed": 3, "seconds": 1.0},
                    {"method": "reuse", "changed": 0, "seconds": 1.0}],
                    [{"method": "reuse", "changed": 1, "seconds": 1.0},
                    {"method": "reuse", "changed": 0, "seconds": 1.0},
                    {"method": "reuse", "changed": 0, "seconds": 1.0}]],
                "linear_solver": {"back_end": "petsc-cg", "preconditioner": "gamg",
                    "tolerance": 1e-8, "iterations": [200, 150, 150, 100],
                    "largest_relative_residual": 1e-9}
            }))
        };
        let case = |group, ranks, s| Case {
            problem: group,
            law: Law::Frictionless,
            refine: 11,
            ranks,
            summary: Outcome::Ran(Box::new(s)),
        };
        let cases = vec![
            case(Group::Solid, None, m(100.0, 20 * gib)),
            case(Group::Petsc, Some(1), m(50.0, 6 * gib)),
            case(Group::Petsc, Some(2), m(40.0, 7 * gib)),
        ];
        let direct: Vec<_> = runs(&cases)
            .filter(|r| r.case.problem == Group::Solid)
            .collect();
        let petsc: Vec<_> = runs(&cases)
            .filter(|r| r.case.problem == Group::Petsc)
            .collect();
        let mut s = String::new();
        petsc_section(&mut s, &direct, &petsc);
        assert!(
            s.contains("| 11 | 1000000 | 1 | completed | 5 | 4 | 150, 200 | 2 | 5.00 | 30.00 | 15.00 | **50.00** | 6144 | 6.00 |"),
            "{s}"
        );
        assert!(s.contains("| 11 | 1000000 | 2 | completed |"), "{s}");
        assert!(
            s.contains("- 1 rank: PETSc is faster at every size measured, from 1000k unknowns"),
            "{s}"
        );
        assert!(
            s.contains("- 1 rank, 1000000 unknowns: 50.0 s (≤ 60 s: yes), 6.00 GiB on the machine (≤ 12 GiB: yes): **met**."),
            "{s}"
        );
        assert!(
            s.contains("- 2 ranks, 1000000 unknowns: 40.0 s (≤ 60 s: yes), 14.00 GiB on the machine (≤ 12 GiB: no): **not met**."),
            "{s}"
        );
        assert!(s.contains("not of the form R + D/N here"), "{s}");
        assert!(s.contains("needs two one-rank rows"), "{s}");
        // Amdahl's bound: total 50 s over the 15 s outside setup and solve.
        assert!(s.contains("more than 3.3× faster"), "{s}");
    }
}
