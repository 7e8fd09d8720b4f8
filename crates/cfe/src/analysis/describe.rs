//! The `cfe check` text: a human-readable description of a prepared analysis —
//! its parts, interfaces (pairs, penalties, projection distance, gaps), supports,
//! loads and steps, and the warnings about the model.

use super::Analysis;
use crate::coupling::Interface;
use crate::coupling::build::InterfaceDim;
use crate::dim::D3;
use crate::domain::{Coupling, CouplingForm, Enforcement, Law};
use crate::results::fmt::{num, num_rel};

impl Analysis {
    /// A human-readable description of the prepared model (for `cfe check`).
    pub fn describe(&self) -> String {
        // The model's size: lengths below 1e-10 of it are round-off, shown as 0.
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in self.model.parts.iter().flat_map(|p| &p.mesh.nodes) {
            for c in 0..2 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        let size = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(0.0);
        let load: f64 = self
            .model
            .loads
            .iter()
            .map(|l| l.resultant[0].hypot(l.resultant[1]))
            .fold(0.0, f64::max);
        let mut s = format!(
            "{} ({})\n  unknowns: {}\n",
            self.model.title,
            self.model.source.display(),
            self.dofs.n_eq
        );
        for p in &self.model.parts {
            s += &format!(
                "  part '{}': {} nodes, {} elements, E = {}, nu = {}, t = {}\n",
                p.name,
                p.mesh.nodes.len(),
                p.mesh.describe_elements(),
                num(p.material.young),
                num(p.material.poisson),
                num(p.material.thickness)
            );
        }
        for i in &self.interfaces {
            s += &describe_interface(
                i,
                &self.model.parts[i.host].name,
                &self.model.parts[i.node_part].name,
                size,
            );
        }
        for sup in &self.model.supports {
            s += &format!(
                "  support '{}': {} nodes, fix x: {}, fix y: {}\n",
                sup.name,
                sup.nodes.len(),
                sup.fix[0],
                sup.fix[1]
            );
        }
        let steps = self.model.steps.len() > 1;
        for l in &self.model.loads {
            s += &format!(
                "  load '{}': resultant ({}, {}) on {} nodal forces{}\n",
                l.name,
                num_rel(l.resultant[0], load),
                num_rel(l.resultant[1], load),
                l.nodal.len(),
                if steps {
                    format!(", step '{}'", self.step_name(l.step))
                } else {
                    String::new()
                }
            );
        }
        if steps {
            for (k, st) in self.model.steps.iter().enumerate() {
                s += &format!(
                    "  step {} '{}': {} increments\n",
                    k + 1,
                    st.name,
                    st.increments
                );
            }
        }
        for w in self.model.warnings() {
            s += &format!("  warning: {w}\n");
        }
        // What reading the input noted (a deck's ignored keywords, its mapping).
        for n in &self.model.notes {
            s += &format!("  note: {n}\n");
        }
        s
    }
}

impl Analysis<D3> {
    /// A human-readable description of the prepared solid model (for `cfe
    /// check`): its parts (nodes, elements by kind, E and ν, named boundaries
    /// with their face counts), interfaces (pairs, penalties, projection
    /// distance, gaps), supports (the components they fix), loads (resultants
    /// as 3-vectors), steps and warnings.
    pub fn describe(&self) -> String {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in self.model.parts.iter().flat_map(|p| &p.mesh.nodes) {
            for c in 0..3 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        let size = (0..3).map(|c| hi[c] - lo[c]).fold(0.0, f64::max);
        let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let load = (self.model.loads.iter())
            .map(|l| norm(l.resultant))
            .fold(0.0, f64::max);
        let mut s = format!(
            "{} ({})\n  solid model\n  unknowns: {}\n",
            self.model.title,
            self.model.source.display(),
            self.dofs.n_eq
        );
        for p in &self.model.parts {
            let faces: Vec<String> = (p.mesh.boundaries.iter())
                .map(|(name, f)| format!("'{name}' {}", f.len()))
                .collect();
            s += &format!(
                "  part '{}': {} nodes, {} elements, E = {}, nu = {}; boundaries (faces): {}\n",
                p.name,
                p.mesh.nodes.len(),
                p.mesh.describe_elements(),
                num(p.material.young),
                num(p.material.poisson),
                if faces.is_empty() {
                    "none".to_string()
                } else {
                    faces.join(", ")
                }
            );
        }
        for i in &self.interfaces {
            s += &describe_interface(
                i,
                &self.model.parts[i.host].name,
                &self.model.parts[i.node_part].name,
                size,
            );
        }
        for sup in &self.model.supports {
            let fixed: Vec<String> = (["x", "y", "z"].iter().zip(sup.fix).zip(sup.value))
                .filter(|((_, f), _)| *f)
                .map(|((c, _), v)| {
                    if v == 0.0 {
                        c.to_string()
                    } else {
                        format!("{c} = {}", num(v))
                    }
                })
                .collect();
            s += &format!(
                "  support '{}': {} nodes, fix {}\n",
                sup.name,
                sup.nodes.len(),
                fixed.join(", ")
            );
        }
        let steps = self.model.steps.len() > 1;
        for l in &self.model.loads {
            s += &format!(
                "  load '{}': resultant ({}, {}, {}) on {} nodal forces{}\n",
                l.name,
                num_rel(l.resultant[0], load),
                num_rel(l.resultant[1], load),
                num_rel(l.resultant[2], load),
                l.nodal.len(),
                if steps {
                    format!(", step '{}'", self.step_name(l.step))
                } else {
                    String::new()
                }
            );
        }
        let mut total = [0.0; 3];
        for l in &self.model.loads {
            for (t, r) in total.iter_mut().zip(l.resultant) {
                *t += r;
            }
        }
        if self.model.loads.len() > 1 {
            s += &format!(
                "  loads in all: ({}, {}, {})\n",
                num_rel(total[0], load),
                num_rel(total[1], load),
                num_rel(total[2], load)
            );
        }
        if steps {
            for (k, st) in self.model.steps.iter().enumerate() {
                s += &format!(
                    "  step {} '{}': {} increments\n",
                    k + 1,
                    st.name,
                    st.increments
                );
            }
        }
        for w in self.model.warnings() {
            s += &format!("  warning: {w}\n");
        }
        s
    }
}

/// The `cfe check` lines of one prepared interface (either dimension): its
/// parts, law, pairs, penalties and largest projection distance, the segment
/// or volume form when used, and the contact extensions (friction,
/// enforcement, initial gaps, unpaired nodes) when any is used. `size` is the
/// model's size (lengths below 1e-10 of it print as 0).
fn describe_interface<D: InterfaceDim>(
    i: &Interface<D>,
    host: &str,
    node_part: &str,
    size: f64,
) -> String {
    let mut s = format!(
        "  interface '{}': host '{}', nodes '{}', law {}, {} pairs, c_n = {}, c_s = {}, max projection distance {}\n",
        i.name,
        host,
        node_part,
        i.law.as_str(),
        i.elements.len(),
        num(i.c_n),
        num(i.c_s),
        num_rel(i.max_projection_distance, size)
    );
    if i.coupling == Coupling::Segment {
        s += "    segment coupling: each pair's gap is averaged over its node's face segments\n";
    }
    if i.form == CouplingForm::Volume {
        s += &format!(
            "    volume form: {} node(s) inside the host's elements tied, {} outside not coupled\n",
            i.elements.len(),
            i.unpaired
        );
    }
    // The contact extensions, only when used (the seed's lines unchanged).
    let gaps = i.elements.iter().any(|c| c.gap0 != 0.0);
    if i.law == Law::Coulomb
        || i.enforcement == Enforcement::Augmented
        || gaps
        || (i.unpaired > 0 && i.form == CouplingForm::Face)
    {
        let (lo, hi) = i
            .elements
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), c| {
                (a.min(c.gap0), b.max(c.gap0))
            });
        s += &format!(
            "    friction {}, enforcement {}, initial gaps from {} to {}, {} node(s) unpaired (beyond the search distance)\n",
            num(i.friction),
            i.enforcement.as_str(),
            num_rel(if lo.is_finite() { lo } else { 0.0 }, size),
            num_rel(if hi.is_finite() { hi } else { 0.0 }, size),
            i.unpaired
        );
    }
    s
}
