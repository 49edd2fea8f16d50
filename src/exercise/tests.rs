use super::*;

fn q(text: &str) -> Exact {
    text.parse().unwrap()
}

/// Every kind at every level it has, for a few seeds.
fn all_problems() -> Vec<Problem> {
    let mut problems = Vec::new();
    for seed in 0..8 {
        for level in Level::ALL {
            for &kind in level.kinds() {
                problems.push(problem_for(seed, kind, level).unwrap());
            }
        }
    }
    problems
}

#[test]
fn every_level_produces_its_outcome_in_every_solver() {
    for problem in all_problems() {
        let level = problem.level();
        let status = problem.trace.verdict().unwrap().status.word();
        let expected: &[&str] = match level {
            Level::Hit => &["hit", "crossing"],
            Level::Outside => &["miss-outside", "lines-cross-outside"],
            Level::Behind => &["miss-behind"],
            Level::Parallel => &["parallel"],
            Level::Degenerate => &["degenerate-triangle", "degenerate-segment"],
        };
        assert!(
            expected.contains(&status),
            "{} at {level}: the solver says {status}",
            problem.kind().name()
        );
        let solvable = matches!(level, Level::Hit | Level::Outside | Level::Behind);
        assert_eq!(
            problem.answer.values.len(),
            if solvable {
                problem.kind().unknowns().len()
            } else {
                0
            }
        );
    }
}

#[test]
fn outside_names_the_one_edge_the_trace_fails() {
    for problem in all_problems() {
        if let Outcome::Outside { beyond } = &problem.answer.outcome {
            assert!(problem.kind().edges().contains(&beyond.as_str()));
            let failed: Vec<&str> = problem
                .trace
                .checks()
                .filter(|c| !c.passed)
                .map(|c| c.meaning.as_str())
                .collect();
            assert_eq!(failed.len(), 1, "{failed:?}");
        }
    }
}

#[test]
fn answers_are_short_fractions_taken_from_the_trace() {
    let mut denominators = std::collections::BTreeSet::new();
    for problem in all_problems() {
        for value in &problem.answer.values {
            let denominator = value.value.0.denom().to_string().parse::<i64>().unwrap();
            assert!(denominator <= MAX_DENOMINATOR, "{}", value.value.fraction());
            denominators.insert(denominator);
            // The answer is the trace's own number, not a recomputation.
            let step = problem.trace.scalar(value.id).unwrap();
            assert_eq!(
                step.value.exact.as_deref(),
                Some(value.value.fraction().as_str())
            );
        }
        for input in problem.inputs.named() {
            assert!(input.value.iter().all(|x| x.is_integer()), "{:?}", input);
        }
    }
    // The answers are fractions, not only integers.
    assert!(denominators.iter().any(|&d| d > 1), "{denominators:?}");
}

#[test]
fn the_same_seed_gives_the_same_problems() {
    let first = generate(42, 12, None).unwrap();
    assert_eq!(first, generate(42, 12, None).unwrap());
    assert_ne!(first, generate(43, 12, None).unwrap());
    let levels: Vec<Level> = first.iter().map(Problem::level).collect();
    assert_eq!(&levels[..5], &Level::ALL);
    assert!(
        generate(1, 5, Some(Level::Behind))
            .unwrap()
            .iter()
            .all(|p| p.level() == Level::Behind)
    );
    assert!(
        generate(1, 0, None)
            .unwrap_err()
            .to_string()
            .contains("1 to 100")
    );
    assert!(generate(1, MAX_COUNT + 1, None).is_err());
    assert!(problem_for(1, Kind::Segments, Level::Behind).is_err());
    assert!(
        "sideways"
            .parse::<Level>()
            .unwrap_err()
            .to_string()
            .contains("expected hit, outside")
    );
}

/// A triangle hit with β, γ, t known: A = (0,0,0), B = (4,0,0), C = (0,4,0), L = (1,2,5), D = (0,0,-2).
/// P = (1, 2, 0): β = 1/4, γ = 1/2, t = 5/2.
fn known_triangle() -> Problem {
    let v = |x: i64, y: i64, z: i64| [x, y, z].map(Exact::from_int);
    let inputs = Inputs::Triangle([v(0, 0, 0), v(4, 0, 0), v(0, 4, 0), v(1, 2, 5), v(0, 0, -2)]);
    Problem::new(1, inputs).unwrap()
}

#[test]
fn the_answer_is_the_exact_solvers() {
    let problem = known_triangle();
    assert_eq!(problem.answer.outcome, Outcome::Hit);
    let values: Vec<Exact> = problem
        .answer
        .values
        .iter()
        .map(|v| v.value.clone())
        .collect();
    assert_eq!(values, [q("1/4"), q("1/2"), q("5/2")]);
    assert_eq!(problem.answer.text(), "hit; β = 1/4, γ = 1/2, t = 5/2");
}

/// Fails, naming the answer and its verdict, unless `check` calls every one of `answers` right.
fn assert_right(problem: &Problem, answers: &[&str]) {
    for right in answers {
        assert!(
            matches!(check(problem, right, 0), Verdict::Right { .. }),
            "{right}: {:?}",
            check(problem, right, 0)
        );
    }
}

#[test]
fn the_checker_accepts_right_fractions_and_close_decimals() {
    assert_right(
        &known_triangle(),
        &[
            "1/4, 1/2, 5/2",
            "β = 1/4, γ = 2/4, t = 5/2",
            "t = 2.5, beta = 0.25, gamma = 0.5",
            "0.2504, 0.4996, 2.5009",
            "hit",
            "HIT; 1/4, 1/2, 5/2",
        ],
    );
    // 17/22 = 0.772727…: 0.773 is within 1e-3, 0.77 is not.
    let segments = Problem::new(
        1,
        Inputs::Segments([[0, 0], [22, 0], [17, -1], [17, 1]].map(|p| p.map(Exact::from_int))),
    )
    .unwrap();
    assert_eq!(segments.answer.values[0].value, q("17/22"));
    assert!(matches!(
        check(&segments, "0.773, 0.5", 0),
        Verdict::Right { .. }
    ));
    assert!(matches!(
        check(&segments, "0.77, 0.5", 0),
        Verdict::Wrong { .. }
    ));
    assert!(matches!(
        check(&segments, "0.7727, 1/2", 0),
        Verdict::Right { .. }
    ));
}

fn hint_step(verdict: Verdict) -> String {
    match verdict {
        Verdict::Wrong { hint } => {
            assert!(!hint.title.is_empty() && !hint.text.is_empty());
            hint.step_id
        }
        other => panic!("expected a wrong answer, got {other:?}"),
    }
}

#[test]
fn a_wrong_answer_gets_the_first_differing_step_then_the_next() {
    let problem = known_triangle();
    // γ wrong: the γ step differs first, then the checks that test γ (γ ≥ 0 holds, β + γ changes).
    assert_eq!(hint_step(check(&problem, "1/4, 1/3, 5/2", 0)), "gamma");
    assert_eq!(hint_step(check(&problem, "1/4, 1/3, 5/2", 1)), "check_ab");
    assert_eq!(hint_step(check(&problem, "1/4, 1/3, 5/2", 2)), "check_bc");
    // A fraction is checked exactly, however close.
    assert_eq!(hint_step(check(&problem, "1/4, 1/2, 2501/1000", 0)), "t");
    // Wrong outcomes point at the check that decides them.
    assert_eq!(hint_step(check(&problem, "outside BC", 0)), "check_bc");
    assert_eq!(hint_step(check(&problem, "outside BC", 1)), "verdict");
    assert_eq!(hint_step(check(&problem, "behind", 0)), "check_t");
    assert_eq!(hint_step(check(&problem, "parallel", 0)), "check_det");
    assert_eq!(hint_step(check(&problem, "degenerate", 0)), "check_area");

    let mut practice = Practice::new(problem);
    assert_eq!(hint_step(practice.check("1/5, 1/2, 5/2")), "beta");
    assert_eq!(hint_step(practice.check("1/5, 1/2, 5/2")), "check_ca");
    assert!(matches!(
        practice.check("1/4, 1/2, 5/2"),
        Verdict::Right { .. }
    ));
    assert_eq!(practice.wrong_answers, 2);
}

/// The text of the hint of a verdict that must be wrong, checked to be on `step` and to say `says`.
fn hint_saying(verdict: Verdict, step: &str, says: &str) -> String {
    match verdict {
        Verdict::Wrong { hint } => {
            assert_eq!(hint.step_id, step);
            assert!(hint.text.contains(says), "{}", hint.text);
            hint.text
        }
        other => panic!("not wrong at {step}: {other:?}"),
    }
}

#[test]
fn a_changed_answer_gets_the_hint_of_its_own_first_wrong_step_with_its_value() {
    let mut practice = Practice::new(known_triangle());
    let hint = hint_saying(
        practice.check("1/4, 1/3, 5/2"),
        "gamma",
        "Your answer gives γ = 1/3.",
    );
    assert!(hint.contains("with |M2| = "), "{hint}");
    // γ mended, t now wrong: the t step, not the next step of the earlier answer (check γ ≥ 0).
    assert_eq!(hint_step(practice.check("1/4, 1/2, 3")), "t");
    // The same answer again moves on.
    assert_ne!(hint_step(practice.check("1/4,1/2,3")), "t");
    // β + γ past 1: the check says what the student's numbers give.
    hint_saying(
        check(&known_triangle(), "3/4, 1/2, 5/2", 2),
        "check_bc",
        "Your answer gives β + γ = 5/4.",
    );
}

#[test]
fn answers_are_read_forgivingly() {
    assert_right(
        &known_triangle(),
        &[
            "(1/4, 1/2, 5/2)",
            "[1/4, 1/2, 5/2]",
            "1/4; 1/2; 5/2",
            "t=5/2 beta=1/4 gamma=1/2",
            "t = 5/2 β = 1/4 γ = 1/2",
            "hit; (β = 1/4; γ = 1/2; t = 5/2)",
        ],
    );
}

#[test]
fn a_decimal_rounded_too_far_is_told_to_round_less() {
    let segments = Problem::new(
        1,
        Inputs::Segments([[0, 0], [22, 0], [17, -1], [17, 1]].map(|p| p.map(Exact::from_int))),
    )
    .unwrap();
    // 17/22 = 0.7727…: 0.77 is close; 0.6 is not (that is a wrong value, back to Cramer's rule).
    let Verdict::Wrong { hint } = check(&segments, "0.77, 0.5", 0) else {
        panic!("0.77 is outside the tolerance")
    };
    assert_eq!(hint.title, "Round less");
    assert!(hint.text.contains("t = 0.77"), "{}", hint.text);
    let Verdict::Wrong { hint } = check(&segments, "0.6, 0.5", 0) else {
        panic!("0.6 is wrong")
    };
    assert_eq!(hint.step_id, "t");
    assert_ne!(hint.title, "Round less");
    // Segments have no 'behind': the error does not offer it.
    let Verdict::Unreadable { error } = check(&segments, "", 0) else {
        panic!("empty")
    };
    assert!(!error.to_string().contains("behind"), "{error}");
}

#[test]
fn outcomes_are_read_by_name_for_every_solver() {
    for problem in all_problems() {
        let outcome = problem.answer.outcome.text();
        assert!(
            matches!(check(&problem, &outcome, 0), Verdict::Right { .. }),
            "{outcome} for {}",
            problem.kind().name()
        );
        let answer = problem.answer.text();
        assert!(
            matches!(check(&problem, &answer, 0), Verdict::Right { .. }),
            "{answer}"
        );
        let wrong = if problem.answer.outcome == Outcome::Hit {
            "parallel"
        } else {
            "hit"
        };
        let hint = hint_step(check(&problem, wrong, 0));
        assert!(problem.trace.step(&hint).is_some());
        if problem.answer.values.is_empty() {
            // Numbers for a system with no single solution: the hint is the check that says so.
            let numbers = vec!["1"; problem.kind().unknowns().len()].join(", ");
            let hint = hint_step(check(&problem, &numbers, 0));
            let expected = match problem.answer.outcome {
                Outcome::Parallel => "check_det",
                _ if problem.kind() == Kind::Segments => "check_lengths",
                _ => "check_area",
            };
            assert_eq!(hint, expected, "{}", problem.kind().name());
        }
    }
    let problem = known_triangle();
    assert!(matches!(
        check(&problem, "outside edge ba", 0),
        Verdict::Wrong { .. }
    ));
    for (bad, says) in [
        ("outside XY", "expected one of AB, BC, CA"),
        ("1/4, 1/2", "expected β, γ, t"),
        ("", "expected β, γ, t"),
        ("1/4, x, 3", "not a number"),
        ("δ = 1, γ = 1, t = 1", "not one of the unknowns"),
        ("hit now", "nothing may follow"),
    ] {
        match check(&problem, bad, 0) {
            Verdict::Unreadable { error } => {
                let message = error.to_string();
                assert!(message.contains(says), "{bad}: {message}")
            }
            other => panic!("{bad}: {other:?}"),
        }
    }
}

#[test]
fn the_sheets_hold_every_exact_answer() {
    let problems = generate(7, 10, None).unwrap();
    let key = key_latex(7, &problems);
    let sheet = worksheet_latex(7, &problems);
    for problem in &problems {
        assert!(key.contains(&format!("% key {}: outcome=", problem.number)));
    }
    assert_eq!(sheet.matches("\\item ").count(), 10);
    assert!(!sheet.contains("% key"));
    let json = problems_json(7, &problems);
    assert_eq!(json["problems"].as_array().unwrap().len(), 10);
}
