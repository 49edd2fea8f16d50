//! Playing a lesson: presentation mode, a slide at a time. Each slide loads its scene, shows the step
//! it is about (highlighted in the view, its handles slid to their solution) beside the narration,
//! large. The view stays live: a student can drag anything, and **Restore slide** (or coming back to
//! the slide) puts it back as the lesson has it.

use egui::{RichText, Ui};

use super::widgets::formula_text::keep_formulas_whole;
use super::widgets::palette::{self, Readable as _};
use super::{ActiveSolve, Notice, RaylabApp, highlight, step_panel};
use crate::lesson::{self, Lesson};

/// A lesson being played.
#[derive(Clone, Debug)]
pub struct LessonRun {
    /// The lesson's name (its file stem).
    pub name: String,
    /// The lesson.
    pub lesson: Lesson,
    /// The slide on screen.
    pub slide: usize,
    /// Whether the slide's question has its answer shown.
    pub answer_shown: bool,
    /// The slide's scene is loaded but its step has not been revealed yet (next frame, once solved).
    reveal_pending: bool,
}

/// What the presenter asked for this frame.
#[derive(Default)]
struct Asked {
    next: bool,
    back: bool,
    restore: bool,
    leave: bool,
}

impl RaylabApp {
    /// Starts the built-in lesson `name` at its first slide; an unknown name is reported.
    pub fn start_lesson(&mut self, name: &str) -> Result<(), lesson::UnknownLesson> {
        let lesson = lesson::lesson(name).ok_or_else(|| lesson::UnknownLesson {
            name: name.to_string(),
        })?;
        self.presentation = None;
        self.practice = None;
        self.lesson = Some(LessonRun {
            name: name.to_string(),
            lesson,
            slide: 0,
            answer_shown: false,
            reveal_pending: false,
        });
        self.show_slide(0);
        Ok(())
    }

    /// Leaves the lesson (the scene of its last slide stays open, to explore).
    pub fn leave_lesson(&mut self, ctx: &egui::Context) {
        if let Some(run) = self.lesson.take() {
            // Said in the view the lesson left (not carried into other tabs).
            self.notice = Some(Notice {
                view: Some(self.state.view),
                ..Notice::info(format!(
                    "Left “{}” at slide {} of {}: Lessons → the same lesson starts it again",
                    run.lesson.title,
                    run.slide + 1,
                    run.lesson.slides.len()
                ))
            });
        }
        ctx.send_viewport_cmd(egui::ViewportCommand::Fullscreen(false));
    }

    /// Loads slide `index` as the lesson has it: its scene (undoing any drag) and its precision.
    fn show_slide(&mut self, index: usize) {
        let Some(run) = &mut self.lesson else {
            return;
        };
        let index = index.min(run.lesson.slides.len().saturating_sub(1));
        run.slide = index;
        run.answer_shown = false;
        run.reveal_pending = true;
        let slide = run.lesson.slides[index].clone();
        self.state.precision = slide.precision;
        self.state.symbolic = slide.symbolic;
        match crate::scene::preset(&slide.scene) {
            Some(scene) => {
                if let Err(error) = self.load_scene(&scene) {
                    self.notice = Some(Notice::error(format!("Slide {}: {error}", index + 1)));
                }
                if let Some(kind) = self.state.kind_of(&scene.problem) {
                    self.state.view = kind;
                }
                // A live class gets the slide's question on every device.
                if let Some(question) = &slide.question
                    && self.class.is_some()
                {
                    self.ask_class(Some(&question.ask));
                }
                if matches!(scene.problem, crate::scene::Problem::Render(_)) {
                    self.state.get_mut::<super::render_view::RenderView>().bug = slide.bug;
                }
                if let Some(camera) = slide.camera {
                    let (yaw, pitch) = (camera.yaw.to_radians(), camera.pitch.to_radians());
                    // The views frame the scene from this direction on their next frame.
                    for tab in &mut self.state.tabs {
                        tab.view.aim(yaw, pitch);
                    }
                }
            }
            None => {
                self.notice = Some(Notice::error(format!(
                    "Slide {}: no scene “{}”",
                    index + 1,
                    slide.scene
                )))
            }
        }
    }

    /// The lesson on screen: a presenter bar, the slide's narration and step, and the live view.
    pub(super) fn lesson_ui(&mut self, ui: &mut Ui, solved: &ActiveSolve) {
        let Some(run) = self.lesson.clone() else {
            return;
        };
        let count = run.lesson.slides.len();
        let pressed = presenter_keys(ui);
        let mut asked = Asked {
            next: pressed.next,
            back: pressed.back,
            restore: false,
            leave: pressed.leave,
        };
        let slide = &run.lesson.slides[run.slide];
        // The step the slide is about, in this frame's solve (or seed 002's symbols), and what it
        // highlights.
        let symbolic = slide.symbolic.then(|| {
            self.refresh_symbolic();
            self.symbolic.as_ref().map(|(_, trace)| trace.clone())
        });
        let trace = match &symbolic {
            Some(symbolic) => symbolic.as_ref(),
            None => solved.trace(),
        };
        let step = slide
            .step
            .as_deref()
            .and_then(|id| trace.and_then(|t| t.steps.iter().position(|s| s.id == id)))
            .and_then(|index| trace.map(|t| (index, &t.steps[index], t.solver.clone())));
        let highlighted = step
            .as_ref()
            .map(|(_, step, solver)| highlight::of_step(solver, &step.id))
            .unwrap_or_default();
        egui::Panel::top("lesson-bar").show(ui, |ui| {
            ui.horizontal_wrapped(|ui| {
                asked.back |= ui
                    .add_enabled(run.slide > 0, egui::Button::new("◀ Back"))
                    .on_hover_text("The slide before (← or Page Up)")
                    .clicked();
                ui.label(RichText::new(format!("Slide {} of {count}", run.slide + 1)).strong());
                asked.next |= ui
                    .add_enabled(run.slide + 1 < count, egui::Button::new("Next ▶"))
                    .on_hover_text("The next slide (Space, → or Page Down)")
                    .clicked();
                asked.restore |= ui
                    .button("↺ Restore slide")
                    .on_hover_text("Put the scene back as the slide has it, after exploring")
                    .clicked();
                asked.leave |= ui
                    .button("Leave (Esc)")
                    .on_hover_text("Back to the usual layout, with this slide's scene open")
                    .clicked();
                ui.separator();
                ui.label(RichText::new(&run.lesson.title).weak());
            });
            let solver = step.as_ref().map_or("", |(_, _, solver)| solver.as_str());
            let names: Vec<String> = highlighted.iter().map(|e| e.name(solver)).collect();
            super::presentation::highlighted_row(ui, &names);
        });
        if asked.leave {
            self.leave_lesson(ui.ctx());
            return;
        }
        let target = if asked.next && run.slide + 1 < count {
            Some(run.slide + 1)
        } else if asked.back && run.slide > 0 {
            Some(run.slide - 1)
        } else if asked.restore {
            Some(run.slide)
        } else {
            None
        };
        if let Some(index) = target {
            self.show_slide(index);
            ui.ctx().request_repaint();
            return;
        }
        let elements = highlighted;
        if run.reveal_pending {
            let now = ui.input(|i| i.time);
            // What the steps before this one computed is in place at once (the narration goes on
            // from there: "β = γ = 1/3" on the check after both), then this step's own slides.
            // (Not on a slide in symbols: its steps have no numbers to put in place.)
            if let (Some((index, _, solver)), Some(trace), false) = (&step, trace, slide.symbolic) {
                let earlier: Vec<highlight::Element> = trace.steps[..*index]
                    .iter()
                    .flat_map(|s| highlight::of_step(solver, &s.id))
                    .collect();
                self.reveal(&earlier, solved, now);
                self.view_mut(self.state.view).settle();
            }
            self.reveal(&elements, solved, now);
            if let Some(run) = &mut self.lesson {
                run.reveal_pending = false;
            }
        }
        let mut answer_shown = run.answer_shown;
        self.set_highlight(elements);
        // A question is asked before it is answered: the view keeps its verdict, hit ring and
        // values to itself until "Show the answer" (a live class's lock hides them as well).
        let ctx = ui.ctx().clone();
        let hidden_before = super::widgets::answers_hidden(&ctx);
        // Nor does a slide before the verdict show it: "the segments cross at t = 17/22" would
        // answer the slides that derive t.
        // A slide in symbols comes before any number: its view keeps the verdict too.
        let before_verdict = self.view(self.state.view).presents()
            && (slide.symbolic
                || trace.is_some_and(|trace| {
                    let at = step.as_ref().map(|(index, _, _)| *index);
                    trace
                        .verdict_step()
                        .is_some_and(|verdict| at.is_none_or(|at| at < verdict))
                }));
        super::widgets::hide_answers(&ctx, hidden_before || before_verdict);
        // The panel's text scale is found again for each page: a slide of a lesson, its answer shown.
        let page = egui::Id::unique((&run.name, run.slide, answer_shown));
        self.beside_the_view(ui, solved, "lesson-slide", Some((1.3, page)), |ui| {
            ui.add(egui::Label::new(RichText::new(&slide.title).heading()).wrap());
            for line in &slide.narration {
                ui.add(egui::Label::new(keep_formulas_whole(line)).wrap());
            }
            if let Some(question) = &slide.question {
                ui.add_space(6.0);
                let ask = RichText::new(format!("? {}", keep_formulas_whole(&question.ask)))
                    .strong()
                    .color(palette::SOLUTION.readable(ui));
                ui.add(egui::Label::new(ask).wrap());
                if answer_shown {
                    ui.add(egui::Label::new(keep_formulas_whole(&question.answer)).wrap());
                } else if ui
                    .button("Show the answer")
                    .on_hover_text("Reveal the answer to the room")
                    .clicked()
                {
                    answer_shown = true;
                }
                // Read as the view draws, after this panel: shown from this frame on.
                // A question about a step's result is answered by the view too; a question on a
                // picture slide (no step) is not, and the view keeps the verdict for later.
                let revealed = answer_shown && (step.is_some() || !before_verdict);
                super::widgets::hide_answers(&ctx, hidden_before || !revealed);
            }
            if let Some((index, step, _)) = &step {
                ui.add_space(8.0);
                step_panel::step_ui(ui, index + 1, step, None);
            }
        });
        super::widgets::hide_answers(&ctx, hidden_before);
        if answer_shown && self.lesson.as_ref().is_some_and(|run| !run.answer_shown) {
            self.reveal_to_class();
        }
        if let Some(run) = &mut self.lesson {
            run.answer_shown = answer_shown;
        }
    }
}

/// The keys a presentation clicker sends, pressed this frame.
pub(super) struct PresenterKeys {
    /// Space, → or Page Down.
    pub next: bool,
    /// ← or Page Up.
    pub back: bool,
    /// Esc.
    pub leave: bool,
}

/// Reads (and consumes) the presentation keys: presentation mode and lessons share them. While a
/// canvas handle has the focus, the arrows move it and Esc only lets it go: Space and the page keys
/// still step.
pub(super) fn presenter_keys(ui: &Ui) -> PresenterKeys {
    let handle = super::widgets::handles::handle_focused(ui.ctx());
    ui.input_mut(|i| {
        // Consume every key of a group, not just the first pressed.
        let mut pressed = |keys: &[egui::Key]| {
            keys.iter()
                .filter(|key| i.consume_key(egui::Modifiers::NONE, **key))
                .count()
                > 0
        };
        use egui::Key;
        PresenterKeys {
            next: pressed(if handle {
                &[Key::Space, Key::PageDown]
            } else {
                &[Key::Space, Key::ArrowRight, Key::PageDown]
            }),
            back: pressed(if handle {
                &[Key::PageUp]
            } else {
                &[Key::ArrowLeft, Key::PageUp]
            }),
            leave: !handle && pressed(&[Key::Escape]),
        }
    })
}
