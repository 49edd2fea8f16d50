//! Practice: predict, then reveal. A generated problem (seeded, small inputs, readable fractions) opens
//! in its view with the verdict hidden; the student types the unknowns or names the outcome, the
//! answer is checked exactly (decimals within a stated tolerance), and a wrong answer gets the first
//! step of the solve that differs as a hint, then the next. A score counts the session.

use egui::{RichText, Ui};

use super::widgets::palette::{self, Readable as _};
use super::{ActiveSolve, Notice, RaylabApp, step_panel};
use crate::exercise::{self, DECIMAL_TOLERANCE, Inputs, Kind, Level, Practice, Verdict};
use crate::scene::{ParallelogramScene, Problem, Scene, SegmentsScene, TriangleScene};

/// A practice session.
#[derive(Clone, Debug)]
pub struct PracticeRun {
    /// The solver practised.
    pub kind: Kind,
    /// This problem's outcome.
    pub level: Level,
    /// The levels are mixed: each problem's outcome is drawn, and not named until the answer is
    /// right or revealed (the level's name would give it away).
    pub mixed: bool,
    /// The problem's seed (shown, so a class can compare the same problem).
    pub seed: u64,
    /// The problem and the wrong answers so far.
    pub practice: Practice,
    /// What the student typed.
    pub answer: String,
    /// The last check.
    pub verdict: Option<Verdict>,
    /// The steps are shown (after a right answer, or on request).
    pub revealed: bool,
    /// Problems answered right this session.
    pub right: usize,
    /// Problems tried this session: answered (readably) or revealed at least once.
    pub tried: usize,
    /// This problem counts in `tried` already.
    pub attempted: bool,
}

/// The level a mixed problem is drawn at: one of `kind`'s levels, picked by the seed (so a class
/// comparing problem numbers sees the same one). Hits and misses past an edge come three times as
/// often as a parallel ray or a degenerate shape, behind twice: the special cases stay special.
fn mixed_level(kind: Kind, seed: u64) -> Level {
    let weight = |level: Level| match level {
        Level::Hit | Level::Outside => 3,
        Level::Behind => 2,
        Level::Parallel | Level::Degenerate => 1,
    };
    let levels: Vec<Level> = Level::ALL
        .into_iter()
        .filter(|level| level.kinds().contains(&kind))
        .flat_map(|level| std::iter::repeat_n(level, weight(level)))
        .collect();
    // A multiplicative hash: neighbouring seeds land on different levels.
    let pick = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 32;
    levels[pick as usize % levels.len()]
}

impl RaylabApp {
    /// Starts practising `kind` with a new problem whose outcome is drawn from every level (see
    /// [`PracticeRun::mixed`]).
    pub fn start_mixed_practice(&mut self, kind: Kind) {
        let level = mixed_level(kind, self.practice_seed + 1);
        self.start_practice_at(kind, level, true);
    }

    /// Starts practising `kind` at `level` with a new problem.
    pub fn start_practice(&mut self, kind: Kind, level: Level) {
        self.start_practice_at(kind, level, false);
    }

    fn start_practice_at(&mut self, kind: Kind, level: Level, mixed: bool) {
        let (right, tried) = self
            .practice
            .as_ref()
            .map_or((0, 0), |run| (run.right, run.tried));
        self.practice_seed += 1;
        let level = if level.kinds().contains(&kind) {
            level
        } else {
            Level::Hit
        };
        let seed = self.practice_seed;
        match exercise::problem_for(seed, kind, level) {
            Ok(problem) => {
                let scene = scene_of(&problem.inputs, seed, (!mixed).then_some(level));
                if let Err(error) = self.load_scene(&scene) {
                    self.notice = Some(Notice::error(error.to_string()));
                    return;
                }
                if let Some(kind) = self.state.kind_of(&scene.problem) {
                    self.state.view = kind;
                }
                self.state.precision = crate::geometry::Precision::Exact;
                self.state.symbolic = false;
                self.presentation = None;
                self.lesson = None;
                self.practice = Some(PracticeRun {
                    kind,
                    level,
                    mixed,
                    seed,
                    practice: Practice::new(problem),
                    answer: String::new(),
                    verdict: None,
                    revealed: false,
                    right,
                    tried,
                    attempted: false,
                });
            }
            Err(error) => {
                self.notice = Some(Notice::error(format!("Could not make a problem: {error}")))
            }
        }
    }

    /// The practice screen: a bar with the level and score, the problem and the answer box beside the
    /// view, whose verdict stays hidden until the answer is right (or revealed).
    pub(super) fn practice_ui(&mut self, ui: &mut Ui, solved: &ActiveSolve) {
        let Some(mut run) = self.practice.clone() else {
            return;
        };
        // `Some(None)`: mixed.
        let mut new_level: Option<Option<Level>> = None;
        // Esc on a focused canvas handle only lets the handle go.
        let mut leave = !super::widgets::handles::handle_focused(ui.ctx())
            && ui.input_mut(|i| i.consume_key(egui::Modifiers::NONE, egui::Key::Escape));
        egui::Panel::top("practice-bar").show(ui, |ui| {
            ui.horizontal_wrapped(|ui| {
                ui.label(RichText::new(format!("Practice: {}", run.kind.name())).strong());
                ui.label("level");
                let mixed = ui.selectable_label(run.mixed, "mixed").on_hover_text(
                    "Any outcome: hit, outside, behind, parallel or degenerate, not named \
                         until you answer",
                );
                if mixed.clicked() {
                    new_level = Some(None);
                }
                for level in Level::ALL {
                    if !level.kinds().contains(&run.kind) {
                        continue;
                    }
                    let chosen = ui
                        .selectable_label(!run.mixed && run.level == level, level.name())
                        .on_hover_text(level_tip(level));
                    if chosen.clicked() {
                        new_level = Some(Some(level));
                    }
                }
                ui.separator();
                ui.label(format!("Score: {} right of {} tried", run.right, run.tried));
                if ui
                    .button("New problem")
                    .on_hover_text("Another problem at this level")
                    .clicked()
                {
                    new_level = Some((!run.mixed).then_some(run.level));
                }
                leave |= ui
                    .button("Leave (Esc)")
                    .on_hover_text("Back to the usual layout")
                    .clicked();
            });
        });
        if leave {
            self.practice = None;
            return;
        }
        if let Some(pick) = new_level {
            match pick {
                Some(level) => self.start_practice(run.kind, level),
                None => self.start_mixed_practice(run.kind),
            }
            ui.ctx().request_repaint();
            return;
        }
        // The view keeps the verdict to itself while the problem is open (the flag is read as the
        // view draws, after the panel has taken this frame's answer).
        let ctx = ui.ctx().clone();
        self.beside_the_view(ui, solved, "practice-panel", None, |ui| {
            problem_ui(ui, &mut run, solved);
            super::widgets::hide_answers(&ctx, !run.revealed);
        });
        super::widgets::hide_answers(&ctx, false);
        self.practice = Some(run);
    }
}

/// The problem, the answer box, the verdict and the hint.
fn problem_ui(ui: &mut Ui, run: &mut PracticeRun, solved: &ActiveSolve) {
    let problem = run.practice.problem.clone();
    ui.heading(format!("Problem {}", run.seed));
    for input in problem.inputs.named() {
        let coordinates: Vec<String> = input.value.iter().map(|x| x.fraction()).collect();
        ui.label(
            RichText::new(format!("{} = ({})", input.name, coordinates.join(", "))).monospace(),
        );
    }
    let unknowns: Vec<&str> = run.kind.unknowns().iter().map(|(_, s, _)| *s).collect();
    let edges = run.kind.edges().join(", ");
    ui.add(
        egui::Label::new(
            RichText::new(format!(
                "Predict {}, or name the outcome: hit, outside (and the edge: {edges}), behind, \
                 parallel or degenerate. Fractions such as 17/22 are checked exactly, decimals to \
                 within {DECIMAL_TOLERANCE}.",
                unknowns.join(", ")
            ))
            .weak(),
        )
        .wrap(),
    );
    let mut check = false;
    let label = ui.label(RichText::new("Your answer:").strong());
    ui.horizontal(|ui| {
        let edit = ui
            .add(
                egui::TextEdit::singleline(&mut run.answer)
                    .hint_text(format!("{} = …", unknowns.join(", ")))
                    .desired_width(ui.available_width() - 90.0),
            )
            .labelled_by(label.id);
        check |= edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        check |= ui
            .button("Check")
            .on_hover_text("Check the answer (Enter)")
            .clicked();
    });
    // Or pick the outcome: one click names it and checks it.
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new("The outcome:").weak());
        let mut outcomes = vec!["hit".to_string()];
        outcomes.extend(run.kind.edges().iter().map(|e| format!("outside {e}")));
        if Level::Behind.kinds().contains(&run.kind) {
            outcomes.push("behind".into());
        }
        outcomes.extend(["parallel".into(), "degenerate".into()]);
        for outcome in outcomes {
            if ui
                .small_button(&outcome)
                .on_hover_text(format!("Answer “{outcome}” and check it"))
                .clicked()
            {
                run.answer = outcome;
                check = true;
            }
        }
    });
    if check && !run.answer.trim().is_empty() {
        let verdict = run.practice.check(&run.answer);
        // A problem counts as tried once an answer is read (not when it is shown).
        if !matches!(verdict, Verdict::Unreadable { .. }) && !run.attempted {
            run.attempted = true;
            run.tried += 1;
        }
        if matches!(verdict, Verdict::Right { .. }) && !run.revealed {
            run.right += 1;
            run.revealed = true;
        }
        run.verdict = Some(verdict);
    }
    let feedback = match &run.verdict {
        Some(Verdict::Right { answer }) => Some(
            ui.add(
                egui::Label::new(
                    RichText::new(format!("Right: {answer}"))
                        .strong()
                        .color(palette::INSIDE.readable(ui)),
                )
                .wrap(),
            )
            .rect,
        ),
        Some(Verdict::Wrong { hint }) => {
            let title = ui.add(
                egui::Label::new(
                    RichText::new(format!(
                        "Not yet ({} wrong so far). Look again at “{}”:",
                        run.practice.wrong_answers, hint.title
                    ))
                    .strong()
                    .color(palette::OUTSIDE.readable(ui)),
                )
                .wrap(),
            );
            let text = ui.add(egui::Label::new(&hint.text).wrap());
            Some(title.rect.union(text.rect))
        }
        Some(Verdict::Unreadable { error }) => Some(
            ui.add(
                egui::Label::new(RichText::new(error.to_string()).color(palette::RHS.readable(ui)))
                    .wrap(),
            )
            .rect,
        ),
        None => None,
    };
    // Checked: the feedback scrolls into view (at 200% it falls below the fold of the panel).
    if check && let Some(rect) = feedback {
        ui.scroll_to_rect(rect, None);
    }
    if !run.revealed
        && ui
            .button("Reveal the answer")
            .on_hover_text("Show the answer and every step (the problem counts as not right)")
            .clicked()
    {
        run.revealed = true;
        if !run.attempted {
            run.attempted = true;
            run.tried += 1;
        }
    }
    if run.revealed {
        ui.separator();
        ui.label(RichText::new(format!("Answer: {}", problem.answer.text())).strong());
        if let Some(trace) = solved.trace() {
            for (index, step) in trace.steps.iter().enumerate() {
                step_panel::step_ui(ui, index + 1, step, None);
            }
        }
    }
}

fn level_tip(level: Level) -> &'static str {
    match level {
        Level::Hit => "The ray (or segment) hits: find the parameters",
        Level::Outside => "It meets the plane (or line) beyond one edge: which one?",
        Level::Behind => "Inside, but behind the ray's origin",
        Level::Parallel => "Parallel: |M| = 0, no single solution",
        Level::Degenerate => "The triangle, parallelogram or a segment has no extent",
    }
}

/// The problem as a scene its view can load (the inputs are small integers, exact as floats); its
/// note names the level unless the levels are mixed (`None`).
fn scene_of(inputs: &Inputs, seed: u64, level: Option<Level>) -> Scene {
    let f =
        |v: &[crate::math::exact::Exact]| -> Vec<f64> { v.iter().map(|x| x.to_f64()).collect() };
    let v2 = |v: &[crate::math::exact::Exact; 2]| -> [f64; 2] { [v[0].to_f64(), v[1].to_f64()] };
    let v3 = |v: &[crate::math::exact::Exact; 3]| -> [f64; 3] {
        let x = f(v);
        [x[0], x[1], x[2]]
    };
    let problem = match inputs {
        Inputs::Segments([a1, a2, b1, b2]) => Problem::Segments(SegmentsScene {
            a1: v2(a1),
            a2: v2(a2),
            b1: v2(b1),
            b2: v2(b2),
        }),
        Inputs::Triangle([a, b, c, origin, dir]) => Problem::Triangle(TriangleScene {
            a: v3(a),
            b: v3(b),
            c: v3(c),
            origin: v3(origin),
            dir: v3(dir),
            t_min: 0.0,
        }),
        Inputs::Parallelogram([corner, e1, e2, origin, dir]) => {
            Problem::Parallelogram(ParallelogramScene {
                corner: v3(corner),
                e1: v3(e1),
                e2: v3(e2),
                origin: v3(origin),
                dir: v3(dir),
            })
        }
    };
    Scene {
        title: format!("Practice problem {seed}"),
        note: match level {
            Some(level) => format!("A {} problem: predict, then check.", level.name()),
            None => "A problem: predict, then check.".into(),
        },
        problem,
    }
}
