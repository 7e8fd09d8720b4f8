//! The segment coupling's cost against the node coupling's on a benchmark
//! problem (`cfe bench --coupling-cost K`): the same tied model solved once with
//! each, in this process.

use cfe::error::Result;
use std::fmt::Write as _;
use std::path::Path;

/// The cost of one coupling formulation on a benchmark problem (see
/// [`coupling_cost`]).
#[derive(Debug, Clone)]
pub struct CouplingCost {
    /// `node` or `segment`.
    pub coupling: &'static str,
    /// Unknowns of the model.
    pub unknowns: usize,
    /// Coupling elements over all interfaces.
    pub pairs: usize,
    /// Nonzeros of the Cholesky factor.
    pub factor_nonzeros: usize,
    /// Pair search (and, for `segment`, the face integration) with DOF numbering, s.
    pub pair_search: f64,
    /// Node graph, ordering, pattern and symbolic factorization, s.
    pub pattern: f64,
    /// Assembly of K, s.
    pub assembly: f64,
    /// Numeric factorization, s.
    pub factorization: f64,
}

/// Solves `problem` refined `refine` times, tied (every interface `rigid`, one
/// increment: one assembly and one factorization), once with `coupling = "node"`
/// and once with `coupling = "segment"` on every interface, in this process, and
/// returns the cost of each. The two runs differ only in the coupling elements, so
/// the ratio of their assembly + factorization times is the segment coupling's
/// cost.
pub fn coupling_cost(problem: &Path, refine: usize) -> Result<Vec<CouplingCost>> {
    use cfe::coupling::{Coupling, Law};
    let mut rows = Vec::new();
    for (name, coupling) in [("node", Coupling::Node), ("segment", Coupling::Segment)] {
        let mut model = cfe::model::Model::from_file(problem, refine)?;
        for def in &mut model.interfaces {
            def.coupling = coupling;
        }
        model.settings.increments = 1;
        let mut a = cfe::analysis::Analysis::new(model)?;
        a.override_law(Law::Rigid);
        let pair_search = a.timings.pair_search;
        let r = a.solve()?;
        let t = &r.summary.timings.solve;
        rows.push(CouplingCost {
            coupling: name,
            unknowns: r.summary.unknowns,
            pairs: a.interfaces.iter().map(|i| i.elements.len()).sum(),
            factor_nonzeros: r.summary.factor_nonzeros,
            pair_search,
            pattern: t.pattern_and_symbolic,
            assembly: t.assembly,
            factorization: t.factorization,
        });
    }
    Ok(rows)
}

/// The rows of [`coupling_cost`] as a Markdown table, with the segment / node
/// ratio of assembly + factorization.
pub fn coupling_cost_table(rows: &[CouplingCost]) -> String {
    let mut s = String::from(
        "| coupling | unknowns | pairs | factor nonzeros | pair search (s) | pattern + symbolic (s) | assembly (s) | factorization (s) | assembly + factorization (s) |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} |",
            r.coupling,
            r.unknowns,
            r.pairs,
            r.factor_nonzeros,
            r.pair_search,
            r.pattern,
            r.assembly,
            r.factorization,
            r.assembly + r.factorization
        );
    }
    if let [node, segment] = rows {
        let _ = writeln!(
            s,
            "\nsegment / node, assembly + factorization: {:.3}",
            (segment.assembly + segment.factorization) / (node.assembly + node.factorization)
        );
    }
    s
}
