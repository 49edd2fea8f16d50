//! The hard-case suite: every method against the exact reference on named cases. A method may be wrong
//! only where `assets/hard_cases.ron` says so (the gallery shows those answers); the watertight method
//! is never wrong.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use raylab::accuracy::hard_cases::{gallery, verdicts};

#[test]
fn every_method_agrees_or_its_disagreement_is_listed() {
    let gallery = gallery();
    assert!(!gallery.is_empty(), "assets/hard_cases.ron lists no case");
    for hard in gallery {
        let verdicts = verdicts(&hard.case());
        let mut disagree: Vec<String> = verdicts
            .iter()
            .filter(|v| v.hit != v.exact_hit)
            .map(|v| v.who.clone())
            .collect();
        disagree.sort();
        let mut listed = hard.disagree.clone();
        listed.sort();
        assert_eq!(disagree, listed, "{}: the disagreements changed", hard.name);
        assert!(
            !disagree.iter().any(|w| w.starts_with("watertight")),
            "{}: watertight must agree",
            hard.name
        );
    }
}

#[test]
fn a_power_of_two_shift_keeps_every_exact_decision() {
    let cases = gallery();
    let edge = cases.iter().find(|c| c.name == "through an edge").unwrap();
    let moved = cases
        .iter()
        .find(|c| c.name == "moved by a power of two")
        .unwrap();
    // Same geometry up to an exact translation by 2^20 (and the triangle scaled by 1, the ray the same).
    let before = verdicts(&edge.case());
    let after = verdicts(&moved.case());
    // One verdict per method on each side, so the zip below compares every method.
    assert_eq!(before.len(), after.len());
    assert!(!before.is_empty(), "no method gave a verdict");
    for (b, a) in before.iter().zip(&after) {
        assert_eq!(b.exact_hit, a.exact_hit);
        if b.who.starts_with("watertight") {
            assert_eq!(b.hit, a.hit, "{}", b.who);
        }
    }
}
