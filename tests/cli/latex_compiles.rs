//! The LaTeX output compiles: every outcome of every solver, pasted into a plain article.
//!
//! Needs `pdflatex` (Debian: texlive-latex-base, texlive-latex-recommended); where it is missing the test
//! prints `skipped: pdflatex is not installed` and passes (the structure of the LaTeX is also checked by
//! the unit tests), unless `RAYLAB_LATEX_TEST=require`, which `.ci/run` sets since it installs texlive.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::run;

use std::process::Command;

use run::PARALLELOGRAM_HIT;

fn raylab_latex(args: &[&str]) -> String {
    let output = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(args)
        .args(["--format", "latex"])
        .output()
        .unwrap();
    assert!(output.status.success());
    String::from_utf8(output.stdout).unwrap()
}

#[test]
fn every_outcome_compiles_with_pdflatex() {
    if !run::pdflatex_or_skip() {
        return;
    }
    let tri = |origin: &str, dir: &str, precision: &str| {
        raylab_latex(&[
            "solve",
            "triangle",
            "--a",
            "3,0,0",
            "--b",
            "0,3,0",
            "--c",
            "0,0,3",
            "--origin",
            origin,
            "--dir",
            dir,
            "--precision",
            precision,
        ])
    };
    let mut body = String::new();
    for (origin, dir) in [
        ("0,0,0", "1,1,1"),
        ("0,0,0", "1,1,-0.5"),
        ("0,0,0", "-1,-1,-1"),
        ("1,1,1", "1,-1,0"),
        ("0,0,0", "0,0,0"),
        ("0,0,0", "1e-20,1,3e-9"),
    ] {
        for precision in ["f32", "f64", "exact"] {
            body += &tri(origin, dir, precision);
        }
    }
    // Seed 002's derivation in symbols (long polynomials: overfull lines are fine, errors are not).
    body += &tri("0,0,0", "1,1,1", "symbolic");
    for b in [
        ["2,6", "5,1"],
        ["6,0", "2,0"],
        ["1,1", "1,1"],
        ["0,5", "1,6"],
    ] {
        body += &raylab_latex(&[
            "solve",
            "segments",
            "--a1",
            "0,0",
            "--a2",
            "4,0",
            "--b1",
            b[0],
            "--b2",
            b[1],
            "--precision",
            "exact",
        ]);
    }
    body += &raylab_latex(&[&PARALLELOGRAM_HIT[..], &["--precision", "exact"]].concat());
    let dir = std::env::temp_dir().join(format!("raylab-latex-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let document = format!(
        "\\documentclass{{article}}\\usepackage{{amsmath,amssymb,xcolor}}\\begin{{document}}\n{body}\\end{{document}}\n"
    );
    std::fs::write(dir.join("trace.tex"), document).unwrap();
    let run = Command::new("pdflatex")
        .args(["-interaction=nonstopmode", "-halt-on-error", "trace.tex"])
        .current_dir(&dir)
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&run.stdout).to_string();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(run.status.success(), "pdflatex failed:\n{log}");
}
