//! Every verification case `cfe verify` reports, at both levels it prints:
//! `cfe verify --quick` (the reduced versions) and `cfe verify` (the full
//! versions, whose tables docs/verification.md shows). The cases come from the
//! one list `cfe verify` runs ([`verification::CASES`]), so a case added there
//! is asserted here without a test of its own.

use cfe_tools::verification::{self, Case};

/// Runs every case of the list at `quick` (all of them, not stopping at the
/// first failure) and prints each verdict as `cfe verify` does; returns the
/// title and verdict of every case that did not meet its reference or did not
/// run.
fn failures(quick: bool) -> Vec<String> {
    let mut failed = Vec::new();
    for (name, f) in verification::CASES {
        match f(quick) {
            Ok(Case {
                title,
                verdict,
                passed,
                ..
            }) => {
                eprintln!("{} {title}", if passed { "pass" } else { "FAIL" });
                if !passed {
                    failed.push(format!("{title}: {verdict}"));
                }
            }
            Err(e) => failed.push(format!("{name}: did not run: {e}")),
        }
    }
    failed
}

/// Every case of `cfe verify --quick` meets its independent reference.
#[test]
fn every_quick_case_meets_its_reference() {
    let failed = failures(true);
    assert!(failed.is_empty(), "{}", failed.join("\n\n"));
}

/// Every case of `cfe verify` (the full levels of the committed report) meets
/// its independent reference.
#[test]
fn every_full_case_meets_its_reference() {
    let failed = failures(false);
    assert!(failed.is_empty(), "{}", failed.join("\n\n"));
}
