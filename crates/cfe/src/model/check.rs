//! Checks of the problem file's values where they are read: every number finite,
//! in its physical range (with the reason) and within the range double precision
//! can carry through a solve. Each error names the file, the line and the key
//! (a dotted path such as `materials.steel.E` or `part.base.thickness`), found in
//! a span-preserving parse of the same text.
//!
//! A new key gets its check as one call of [`Values::check`] (a range rule) and,
//! for a dimensional value that enters the stiffness or the load, of
//! [`Values::magnitude`].

use crate::coupling::Law;
use crate::error::{Error, Result};
use crate::fem::PlaneKind;
use std::collections::HashMap;
use std::fmt::Display;
use std::ops::Range;
use std::path::Path;
use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// The largest magnitude of a dimensional input (a modulus, a penalty, a
/// coordinate, a load): its products in the stiffness, the factorization and the
/// energy stay far below the largest double (1.8e308).
pub const MAX_MAGNITUDE: f64 = 1e100;
/// The smallest magnitude of a stiffness (E·t, a penalty): below it products
/// underflow towards the smallest double (2.2e-308) and pivots vanish.
pub const MIN_STIFFNESS: f64 = 1e-100;
/// The largest penalty relative to the softer part's E·t: beyond 1/ε (ε = 2.2e-16,
/// double precision's relative round-off) the part's stiffness is below the
/// round-off of the penalty entries, so the solve cannot see it.
pub const MAX_PENALTY_RATIO: f64 = 1e16;

/// The smallest penalty relative to the softer part's E·t: below it the
/// coupling's compliance is a million times the part's, so the interface holds
/// nothing a user meant it to (and far below, in round-off, nothing at all).
pub const MIN_PENALTY_RATIO: f64 = 1e-6;
/// How close ν may come to its bounds: within this of −1 (the shear modulus
/// E/(2(1+ν)) grows without bound) or, in plane strain, of 0.5 (the bulk modulus
/// E/(2(1+ν)(1−2ν)) does), one modulus is more than 1/(2 `NU_MARGIN`) times the
/// other or than E. One ulp from the bound the factorization fails as if the
/// model were a mechanism; the seed's plate on its base in plane strain already
/// loses equilibrium to 1.4e-6 at 0.5 − 1e-10 (8e-8 at 0.5 − 1e-8).
pub const NU_MARGIN: f64 = 1e-10;

/// The most load increments a run may have.
pub const MAX_INCREMENTS: usize = 10_000_000;

/// One step of a key path: a table key or an index into an array of tables.
#[derive(Debug, Clone, Copy)]
pub enum Seg<'k> {
    /// A table key.
    K(&'k str),
    /// An index into an array (of tables).
    I(usize),
}

/// The problem text with its span-preserving parse, to find the line and the
/// readable key of a value by its path.
pub struct Values<'a> {
    path: &'a Path,
    text: &'a str,
    root: Option<DeTable<'a>>,
    /// A solid model's values: its messages name the stiffness scale E·h (h
    /// the interface's face size) where a plane model's name E·t.
    pub(super) solid: bool,
}

impl<'a> Values<'a> {
    /// The values of `text`, read from `path` (for messages).
    pub fn new(text: &'a str, path: &'a Path) -> Self {
        Values {
            path,
            text,
            root: DeTable::parse(text).ok().map(|t| t.into_inner()),
            solid: false,
        }
    }

    /// The value at `at` and its span: the deepest part of the path found.
    fn lookup(&self, at: &[Seg]) -> (Option<&DeValue<'a>>, Option<Range<usize>>) {
        let Some(root) = &self.root else {
            return (None, None);
        };
        let mut span = None;
        let mut value: Option<&DeValue<'a>> = None;
        for (i, seg) in at.iter().enumerate() {
            let next = match (i, seg, value) {
                (0, Seg::K(k), _) => root.get(*k),
                (_, Seg::K(k), Some(DeValue::Table(t))) => t.get(*k),
                (_, Seg::I(j), Some(DeValue::Array(a))) => a.get(*j),
                _ => None,
            };
            let Some(next) = next else { break };
            span = Some(next.span());
            value = Some(next.get_ref());
        }
        (value, span)
    }

    /// Whether the file gives the value at `at` (the whole path is present).
    pub fn has(&self, at: &[Seg]) -> bool {
        let Some(root) = &self.root else {
            return false;
        };
        let mut value: Option<&DeValue<'a>> = None;
        for (i, seg) in at.iter().enumerate() {
            let next = match (i, seg, value) {
                (0, Seg::K(k), _) => root.get(*k),
                (_, Seg::K(k), Some(DeValue::Table(t))) => t.get(*k),
                (_, Seg::I(j), Some(DeValue::Array(a))) => a.get(*j),
                _ => None,
            };
            match next {
                Some(n) => value = Some(n.get_ref()),
                None => return false,
            }
        }
        true
    }

    /// The 1-based line of the value at `at` (or of its deepest enclosing item).
    pub fn line(&self, at: &[Seg]) -> Option<usize> {
        self.lookup(at).1.map(|s| self.line_at(s.start))
    }

    /// The 1-based line of byte offset `at` of the text.
    pub fn line_at(&self, at: usize) -> usize {
        super::schema::line_of(self.text, at)
    }

    /// The readable key of `at`: dotted, with an array item named by its `name`
    /// key when it has one (`part.base.thickness`) and by its 1-based number
    /// otherwise (`support#2.value`).
    pub fn key(&self, at: &[Seg]) -> String {
        let mut key = String::new();
        for (i, seg) in at.iter().enumerate() {
            match seg {
                Seg::K(k) => {
                    if !key.is_empty() {
                        key.push('.');
                    }
                    key.push_str(k);
                }
                Seg::I(j) => {
                    let name = match self.lookup(&at[..=i]).0 {
                        Some(DeValue::Table(t)) => t.get("name").and_then(|n| match n.get_ref() {
                            DeValue::String(s) => Some(s.to_string()),
                            _ => None,
                        }),
                        _ => None,
                    };
                    match name {
                        Some(n) => {
                            key.push('.');
                            key.push_str(&n);
                        }
                        None => key.push_str(&format!("#{}", j + 1)),
                    }
                }
            }
        }
        key
    }

    /// An [`Error::Invalid`] for the value at `at`.
    pub fn invalid(&self, at: &[Seg], message: impl Display) -> Error {
        Error::Invalid {
            path: self.path.to_path_buf(),
            line: self.line(at),
            key: self.key(at),
            message: message.to_string(),
        }
    }

    /// Checks that `v` (the value at `at`) is finite and satisfies `ok`; `rule`
    /// says what is allowed and why, e.g. "must be positive (a material without
    /// stiffness)".
    pub fn check(&self, at: &[Seg], v: f64, ok: impl Fn(f64) -> bool, rule: &str) -> Result<()> {
        if !v.is_finite() {
            return Err(self.invalid(at, format!("= {v} is not a finite number")));
        }
        if !ok(v) {
            return Err(self.invalid(at, format!("= {v} {rule}")));
        }
        Ok(())
    }

    /// [`Values::check`] of each entry of an array of `N` values (its key is
    /// `at`, each entry named by its index).
    pub fn check_pair<const N: usize>(
        &self,
        at: &[Seg],
        v: [f64; N],
        ok: impl Fn(f64) -> bool,
        rule: &str,
    ) -> Result<()> {
        for (i, x) in v.into_iter().enumerate() {
            if !x.is_finite() {
                return Err(self.invalid(at, format!("[{i}] = {x} is not a finite number")));
            }
            if !ok(x) {
                return Err(self.invalid(at, format!("[{i}] = {x} {rule}")));
            }
        }
        Ok(())
    }

    /// Checks that a dimensional value (or each of `vs`) at `at` is at most
    /// [`MAX_MAGNITUDE`] in size, and, for a stiffness (`stiffness`), at least
    /// [`MIN_STIFFNESS`]: beyond that the solve overflows or underflows.
    pub fn magnitude(&self, at: &[Seg], vs: &[f64], stiffness: bool) -> Result<()> {
        for &v in vs {
            let a = v.abs();
            let what = if a > MAX_MAGNITUDE {
                format!(
                    "= {v:e} is too large: its products in the stiffness, the factorization or the load sums overflow double precision (largest number 1.8e308); keep dimensional values below {MAX_MAGNITUDE:e} by choosing other units"
                )
            } else if stiffness && a < MIN_STIFFNESS {
                format!(
                    "= {v:e} is too small: its products in the stiffness and the factorization underflow double precision (smallest number 2.2e-308), so pivots vanish; keep stiffnesses above {MIN_STIFFNESS:e} by choosing other units"
                )
            } else {
                continue;
            };
            return Err(Error::Overflow {
                path: Some(self.path.to_path_buf()),
                line: self.line(at),
                key: self.key(at),
                message: format!("`{}` {what}", self.key(at)),
            });
        }
        Ok(())
    }

    /// The name of the stiffness scale a penalty is measured against: E·t
    /// in a plane model, E·h in a solid one.
    fn scale(&self) -> &'static str {
        if self.solid { "E·h" } else { "E·t" }
    }

    /// An [`Error::PenaltyPrecision`] when the penalty `c` at `at` exceeds
    /// [`MAX_PENALTY_RATIO`] × `et` (the softer part's E·t, of part `part`).
    pub fn penalty(&self, at: &[Seg], c: f64, et: f64, part: &str) -> Result<()> {
        let ratio = c / et;
        if ratio <= MAX_PENALTY_RATIO {
            return Ok(());
        }
        let et_name = self.scale();
        Err(Error::PenaltyPrecision {
            path: self.path.to_path_buf(),
            line: self.line(at),
            key: self.key(at),
            ratio,
            message: format!(
                "= {c:e} is {ratio:.1e} × {et_name} of part '{part}'{}: the part's stiffness is below the round-off of the penalty (double precision keeps 16 digits), so the solve cannot see it; use a penalty of 1e3 to 1e8 × {et_name}, or leave `c_n`/`c_s` out for the default {:e} × {et_name}",
                self.h_note(),
                super::DEFAULT_PENALTY_FACTOR
            ),
        })
    }
}

impl Values<'_> {
    /// What h is, in a solid model's penalty messages (nothing in a plane
    /// model's).
    fn h_note(&self) -> &'static str {
        if self.solid {
            " (h the mean edge of the interface's faces on the node part)"
        } else {
            ""
        }
    }

    /// An [`Error::WeakPenalty`] when the penalty `c` at `at` is below
    /// [`MIN_PENALTY_RATIO`] × `et` (the softer part's E·t, of part `part`).
    pub fn weak_penalty(&self, at: &[Seg], c: f64, et: f64, part: &str) -> Result<()> {
        let ratio = c / et;
        if ratio >= MIN_PENALTY_RATIO {
            return Ok(());
        }
        let et_name = self.scale();
        Err(Error::WeakPenalty {
            path: self.path.to_path_buf(),
            line: self.line(at),
            key: self.key(at),
            ratio,
            message: format!(
                "= {c:e} is far below {et_name} = {et:e} of part '{part}'{} ({ratio:.1e} × {et_name}, below {MIN_PENALTY_RATIO:e}): the penalty is the coupling's stiffness, so the interface would hold the faces {:.0e} times more loosely than the part itself deforms, and in round-off not at all (the factorization then reports a mechanism); use a penalty of 1e3 to 1e8 × {et_name}, or leave `c_n`/`c_s` out for the default {:e} × {et_name}",
                self.h_note(),
                1.0 / ratio,
                super::DEFAULT_PENALTY_FACTOR
            ),
        })
    }
}

// ------------------------------------------------------- the problem file's keys

use super::schema::{
    InterfaceSpec, LoadSpec, MaterialSpec, PartSpec, ProblemFile, StepSpec, SupportSpec,
};
use Seg::{I, K};

/// Checks every number of the problem file, and that names are unique, before
/// anything is meshed.
pub(super) fn problem<const N: usize>(v: &Values, f: &ProblemFile<N>) -> Result<()> {
    names(v, f)?;
    // A solid is constrained in every direction, as plane strain is out of plane.
    let plane = if N == 3 { PlaneKind::Strain } else { f.plane };
    for (name, m) in &f.materials {
        material(v, name, m, plane)?;
    }
    for (i, p) in f.parts.iter().enumerate() {
        part(v, i, p, f.materials.get(p.material.get_ref()))?;
    }
    for (i, s) in f.interfaces.iter().enumerate() {
        interface(v, i, s)?;
    }
    for (i, s) in f.supports.iter().enumerate() {
        support(v, i, s)?;
    }
    for (i, l) in f.loads.iter().enumerate() {
        load(v, i, l)?;
    }
    steps(v, f)?;
    for (i, p) in f.probes.iter().enumerate() {
        probe(v, i, p)?;
    }
    analysis(v, &f.analysis)
}

/// The names of the parts, interfaces, supports, loads and steps: each unique
/// within its kind ([`unique`]). Unnamed interfaces, supports and loads get
/// default names when built (made unique there).
fn names<const N: usize>(v: &Values, f: &ProblemFile<N>) -> Result<()> {
    let parts: Vec<_> = f.parts.iter().map(|p| Some(&p.name)).collect();
    unique(v, "part", &parts)?;
    let interfaces: Vec<_> = f.interfaces.iter().map(|i| i.name.as_ref()).collect();
    unique(v, "interface", &interfaces)?;
    let supports: Vec<_> = f.supports.iter().map(|s| s.name.as_ref()).collect();
    unique(v, "support", &supports)?;
    let loads: Vec<_> = f.loads.iter().map(|l| l.name.as_ref()).collect();
    unique(v, "load", &loads)?;
    let steps: Vec<_> = f.steps.iter().map(|s| Some(&s.name)).collect();
    unique(v, "step", &steps)?;
    let probes: Vec<_> = f.probes.iter().map(|p| Some(&p.name)).collect();
    unique(v, "probe", &probes)
}

/// `[[probe]]`: a finite point.
fn probe<const N: usize>(v: &Values, i: usize, p: &super::schema::ProbeSpec<N>) -> Result<()> {
    let at = [K("probe"), I(i), K("at")];
    v.check_pair(&at, p.at, f64::is_finite, "")?;
    v.magnitude(&at, &p.at, false)
}

/// Refuses a `name` of a `[[table]]` given to an earlier table of the same kind
/// (`names` holds each table's `name` key, `None` where it has none) with an
/// [`Error::DuplicateName`] naming the line of the duplicate and of the first.
pub(super) fn unique(v: &Values, table: &str, names: &[Option<&Spanned<String>>]) -> Result<()> {
    let mut seen: HashMap<&str, usize> = HashMap::with_capacity(names.len());
    for (i, name) in names.iter().enumerate() {
        let Some(name) = name else { continue };
        if let Some(&first) = seen.get(name.get_ref().as_str()) {
            let line_of = |s: &Spanned<String>| v.line_at(s.span().start);
            let first_line = names[first].map(line_of);
            return Err(Error::DuplicateName {
                path: v.path.to_path_buf(),
                line: Some(line_of(name)),
                key: format!("{table}#{}.name", i + 1),
                name: name.get_ref().clone(),
                message: format!(
                    "= \"{}\" is defined twice: [[{table}]] #{}{} has this name too; {table} names must be unique (results, reactions and references are keyed by name): rename one",
                    name.get_ref(),
                    first + 1,
                    first_line.map_or(String::new(), |l| format!(" on line {l}")),
                ),
            });
        }
        seen.insert(name.get_ref().as_str(), i);
    }
    Ok(())
}

/// `[[step]]`: unique (see [`names`]), non-empty names, at least one increment each (at most
/// [`MAX_INCREMENTS`] in all), no `[analysis] increments` beside them (each step
/// gives its own), and every `step` key of a load or support naming one of them.
fn steps<const N: usize>(v: &Values, f: &ProblemFile<N>) -> Result<()> {
    let names: Vec<&str> = f.steps.iter().map(|s| s.name.get_ref().as_str()).collect();
    let mut total: usize = 0;
    for (i, s) in f.steps.iter().enumerate() {
        let StepSpec {
            name,
            increments,
            scale,
            factors,
        } = s;
        if name.get_ref().trim().is_empty() {
            return Err(v.invalid(
                &[K("step"), I(i), K("name")],
                "is empty: a step needs a name the loads and supports can refer to",
            ));
        }
        if *increments == 0 {
            return Err(v.invalid(
                &[K("step"), I(i), K("increments")],
                "= 0 must be at least 1: a step applies its loads over its increments",
            ));
        }
        if let Some(scale) = scale {
            let at = [K("step"), I(i), K("scale")];
            if i == 0 {
                return Err(v.invalid(
                    &at,
                    "is given on the first step: `scale` sets the loads of the earlier steps, and the first step has none (give a load's own factor in `factors`)",
                ));
            }
            v.check(&at, *scale, f64::is_finite, "")?;
            v.magnitude(&at, &[*scale], false)?;
        }
        for (key, f) in factors {
            let at = [K("step"), I(i), K("factors"), K(key)];
            v.check(&at, *f, f64::is_finite, "")?;
            v.magnitude(&at, &[*f], false)?;
        }
        total = total.saturating_add(*increments);
    }
    if total > MAX_INCREMENTS {
        return Err(v.invalid(
            &[K("step")],
            format!(
                "the steps have {total} increments in all, more than {MAX_INCREMENTS}: each increment is at least one solve and a line of summary.json"
            ),
        ));
    }
    if !f.steps.is_empty() && v.has(&[K("analysis"), K("increments")]) {
        return Err(v.invalid(
            &[K("analysis"), K("increments")],
            "is given together with [[step]] tables: with steps, each step gives its own `increments` (their total is the run's); remove `[analysis] increments`",
        ));
    }
    let known = if names.is_empty() {
        "there are no [[step]] tables: define the step with [[step]] name = \"…\", increments = N"
            .to_string()
    } else {
        format!("steps: {}", names.join(", "))
    };
    let refs = f
        .loads
        .iter()
        .enumerate()
        .map(|(i, l)| ("load", i, &l.step))
        .chain(
            f.supports
                .iter()
                .enumerate()
                .map(|(i, s)| ("support", i, &s.step)),
        );
    for (table, i, step) in refs {
        if let Some(step) = step
            && !names.contains(&step.get_ref().as_str())
        {
            return Err(v.invalid(
                &[K(table), I(i), K("step")],
                format!("= \"{}\" names no step ({known})", step.get_ref()),
            ));
        }
    }
    Ok(())
}

/// `[materials.NAME]`: 0 < E (within the computable range), −1 < ν < 0.5, and
/// ν not within [`NU_MARGIN`] of −1 or (in plane strain) of 0.5.
fn material(v: &Values, name: &str, m: &MaterialSpec, plane: PlaneKind) -> Result<()> {
    let e = [K("materials"), K(name), K("E")];
    v.check(
        &e,
        m.young,
        |x| x > 0.0,
        "must be positive: Young's modulus is the material's stiffness",
    )?;
    v.magnitude(&e, &[m.young], true)?;
    let nu = [K("materials"), K(name), K("nu")];
    v.check(
        &nu,
        m.nu,
        |x| x > -1.0 && x < 0.5,
        "must lie in (-1, 0.5): outside it the elastic energy is not positive (0.5 is incompressible, which displacement elements cannot carry)",
    )?;
    if m.nu + 1.0 < NU_MARGIN {
        return Err(v.invalid(
            &nu,
            format!(
                "= {} is within {NU_MARGIN:e} of -1: the shear modulus E/(2(1+ν)) is {:.1e} × E, so the stiffness (the D matrix) is too ill-conditioned for double precision (at one ulp from -1 it is singular and the factorization reports a mechanism); use ν ≥ {}",
                m.nu,
                0.5 / (1.0 + m.nu),
                -1.0 + NU_MARGIN
            ),
        ));
    }
    if matches!(plane, PlaneKind::Strain | PlaneKind::Axisymmetric) && 0.5 - m.nu < NU_MARGIN {
        let (within, advice) = if v.solid {
            ("in a solid", "")
        } else {
            (
                "in plane strain (or axisymmetry)",
                ", or plane = \"stress\" if the part is thin",
            )
        };
        return Err(v.invalid(
            &nu,
            format!(
                "= {} is within {NU_MARGIN:e} of 0.5 {within}: the bulk modulus E/(2(1+ν)(1−2ν)) is {:.1e} × the shear modulus, so the stiffness (the D matrix) is too ill-conditioned for double precision (at one ulp from 0.5 it is singular and the factorization reports a mechanism); use ν ≤ 0.499 (near-incompressible displacement elements lock anyway){advice}",
                m.nu,
                1.0 / (1.0 - 2.0 * m.nu)
            ),
        ));
    }
    Ok(())
}

/// `[[part]]`: thickness > 0 with E·t computable, finite geometry.
fn part(v: &Values, i: usize, p: &PartSpec, m: Option<&MaterialSpec>) -> Result<()> {
    let t = [K("part"), I(i), K("thickness")];
    v.check(
        &t,
        p.thickness,
        |x| x > 0.0,
        "must be positive: a part without thickness has no stiffness",
    )?;
    v.magnitude(&t, &[p.thickness], false)?;
    if let Some(m) = m {
        // The stiffness scale E·t must itself be computable.
        v.magnitude(&t, &[m.young * p.thickness], true)
            .map_err(|e| match e {
                Error::Overflow {
                    path, line, key, ..
                } => Error::Overflow {
                    message: format!(
                        "`{key}` = {:e} with E = {:e} of material '{}' gives E·t = {:e}, outside [{MIN_STIFFNESS:e}, {MAX_MAGNITUDE:e}]: the stiffness products overflow or underflow double precision; choose other units",
                        p.thickness,
                        m.young,
                        p.material.get_ref(),
                        m.young * p.thickness
                    ),
                    path,
                    line,
                    key,
                },
                e => e,
            })?;
    }
    let any = |x: f64| x.is_finite();
    if let Some(r) = &p.rectangle {
        for (k, xs) in [("x", r.x), ("y", r.y)] {
            let at = [K("part"), I(i), K("rectangle"), K(k)];
            v.check_pair(&at, xs, any, "")?;
            v.magnitude(&at, &xs, false)?;
        }
    }
    if let Some(a) = &p.annulus {
        for (k, xs) in [("center", a.center), ("r", a.r), ("theta", a.theta)] {
            let at = [K("part"), I(i), K("annulus"), K(k)];
            v.check_pair(&at, xs, any, "")?;
            v.magnitude(&at, &xs, false)?;
        }
    }
    if let Some(b) = &p.block {
        for (k, xs) in [("x", b.x), ("y", b.y), ("z", b.z)] {
            let at = [K("part"), I(i), K("box"), K(k)];
            v.check_pair(&at, xs, any, "")?;
            v.magnitude(&at, &xs, false)?;
        }
    }
    Ok(())
}

/// `[[interface]]`: positive, computable penalties and a positive tolerance.
fn interface(v: &Values, i: usize, s: &InterfaceSpec) -> Result<()> {
    for (k, c) in [("c_n", s.c_n), ("c_s", s.c_s)] {
        if let Some(c) = c {
            let at = [K("interface"), I(i), K(k)];
            if k == "c_s" && s.law == Law::Frictionless {
                v.check(
                    &at,
                    c,
                    |x| x >= 0.0,
                    "must be ≥ 0 (the frictionless law ignores it)",
                )?;
            } else {
                v.check(
                    &at,
                    c,
                    |x| x > 0.0,
                    "must be positive: a penalty is the coupling's stiffness",
                )?;
            }
            // A frictionless interface may carry c_s = 0: nothing to overflow.
            if c != 0.0 {
                v.magnitude(&at, &[c], true)?;
            }
        }
    }
    if let Some(tol) = s.tolerance {
        v.check(
            &[K("interface"), I(i), K("tolerance")],
            tol,
            |x| x > 0.0,
            "must be positive: it is the distance (a fraction of the host edge's length) a coupling node may lie off its host edge",
        )?;
    }
    if let Some(mu) = s.friction {
        v.check(
            &[K("interface"), I(i), K("friction")],
            mu,
            |x| x >= 0.0,
            "must be ≥ 0: it is the Coulomb friction coefficient μ",
        )?;
    }
    if let Some(d) = s.search_distance {
        let at = [K("interface"), I(i), K("search_distance")];
        v.check(
            &at,
            d,
            |x| x >= 0.0,
            "must be ≥ 0: it is the length within which a coupling node finds its host edge",
        )?;
        v.magnitude(&at, &[d], false)?;
    }
    if let Some(t) = s.penetration_tolerance {
        let at = [K("interface"), I(i), K("penetration_tolerance")];
        v.check(
            &at,
            t,
            |x| x > 0.0,
            "must be positive: it is the largest penetration (a length) the augmented Lagrangian accepts",
        )?;
        v.magnitude(&at, &[t], false)?;
    }
    Ok(())
}

/// `[[support]]`: a finite position and finite prescribed values.
fn support<const N: usize>(v: &Values, i: usize, s: &SupportSpec<N>) -> Result<()> {
    let any = |x: f64| x.is_finite();
    for (k, xs) in [
        ("at", s.at),
        ("from", s.from),
        ("to", s.to),
        ("value", Some(s.value)),
    ] {
        if let Some(xs) = xs {
            let at = [K("support"), I(i), K(k)];
            v.check_pair(&at, xs, any, "")?;
            v.magnitude(&at, &xs, false)?;
        }
    }
    Ok(())
}

/// `[[load]]`: finite positions, forces and pressures.
fn load<const N: usize>(v: &Values, i: usize, l: &LoadSpec<N>) -> Result<()> {
    let any = |x: f64| x.is_finite();
    for (k, xs) in [
        ("from", l.from),
        ("to", l.to),
        ("at", l.at),
        ("force", l.force),
        ("traction", l.traction),
    ] {
        if let Some(xs) = xs {
            let at = [K("load"), I(i), K(k)];
            v.check_pair(&at, xs, any, "")?;
            v.magnitude(&at, &xs, false)?;
        }
    }
    if let Some(p) = l.pressure {
        let at = [K("load"), I(i), K("pressure")];
        v.check(&at, p, any, "")?;
        v.magnitude(&at, &[p], false)?;
    }
    Ok(())
}

/// `[analysis]`: counts of at least 1, tolerances in their ranges.
fn analysis(v: &Values, s: &crate::domain::Settings) -> Result<()> {
    let at = |k| [K("analysis"), K(k)];
    for (k, n) in [
        ("increments", s.increments),
        ("max_iterations", s.max_iterations),
        ("output_every", s.output_every),
    ] {
        if n == 0 {
            return Err(v.invalid(&at(k), "= 0 must be at least 1"));
        }
    }
    if s.increments > MAX_INCREMENTS {
        return Err(v.invalid(
            &at("increments"),
            format!(
                "= {} is more than {MAX_INCREMENTS}: each increment is at least one solve and a line of summary.json, so the run would not end in reasonable time; a linear load ramp needs far fewer",
                s.increments
            ),
        ));
    }
    v.check(
        &at("gap_tolerance"),
        s.gap_tolerance,
        |x| x >= 0.0,
        "must be non-negative (a fraction of the largest displacement)",
    )?;
    v.check(
        &at("force_tolerance"),
        s.force_tolerance,
        |x| (0.0..1.0).contains(&x),
        "must be a fraction of the load in [0, 1)",
    )?;
    v.check(
        &at("max_violation"),
        s.max_violation,
        |x| x >= 0.0,
        "must be non-negative (a fraction of the load)",
    )?;
    v.check(
        &at("max_residual"),
        s.max_residual,
        |x| x > 0.0,
        "must be positive (a fraction of the load, default 1e-4)",
    )
}
