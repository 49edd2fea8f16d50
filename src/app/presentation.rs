//! Presentation mode: the view fills the screen beside one step at a time, stepped with the keys a
//! clicker sends, each step highlighting what it is about (and sliding the handles it computes).

use egui::{RichText, Ui};

use super::widgets::palette::Readable as _;
use super::{ActiveSolve, Notice, RaylabApp, enlarge, highlight, lesson_view, step_panel, widgets};

impl RaylabApp {
    /// Enters or leaves presentation mode (only views that solve one problem have steps to show).
    pub fn toggle_presentation(&mut self, ctx: &egui::Context) {
        self.presented_views.clear();
        if self.presentation.take().is_some() {
            ctx.send_viewport_cmd(egui::ViewportCommand::Fullscreen(false));
            return;
        }
        if self.view(self.state.view).presents() {
            self.presentation = Some(0);
            ctx.send_viewport_cmd(egui::ViewportCommand::Fullscreen(true));
        } else {
            self.notice = Some(Notice {
                text: "Presentation steps through one solve: open the Segments, Triangle or \
                       Parallelogram view first"
                    .into(),
                error: true,
                view: Some(self.state.view),
            });
        }
    }

    /// Presentation mode: the view fills the window, one step at a time beside it, large; the keys a
    /// presentation clicker sends move between steps.
    pub(super) fn presentation_ui(&mut self, ui: &mut Ui, solved: &ActiveSolve, index: usize) {
        let Some(trace) = solved.trace().filter(|t| !t.steps.is_empty()) else {
            self.presentation = None;
            return;
        };
        let count = trace.steps.len();
        let mut index = index.min(count - 1);
        let lesson_view::PresenterKeys { next, back, leave } = lesson_view::presenter_keys(ui);
        let mut moved = (next && index + 1 < count) || (back && index > 0);
        if next && index + 1 < count {
            index += 1;
        } else if back && index > 0 {
            index -= 1;
        }
        let step = &trace.steps[index];
        let elements = highlight::of_step(&trace.solver, &step.id);
        let mut leave = leave;
        egui::Panel::top("presenter").show(ui, |ui| {
            ui.horizontal_wrapped(|ui| {
                if ui
                    .add_enabled(index > 0, egui::Button::new("◀ Back"))
                    .on_hover_text("The step before (← or Page Up)")
                    .clicked()
                {
                    index -= 1;
                    moved = true;
                }
                ui.label(RichText::new(format!("Step {} of {count}", index + 1)).strong());
                if ui
                    .add_enabled(index + 1 < count, egui::Button::new("Next ▶"))
                    .on_hover_text("The next step (Space, → or Page Down)")
                    .clicked()
                {
                    index += 1;
                    moved = true;
                }
                if ui
                    .button("Leave (Esc)")
                    .on_hover_text("Back to the usual layout")
                    .clicked()
                {
                    leave = true;
                }
            });
            let names: Vec<String> = elements.iter().map(|e| e.name(&trace.solver)).collect();
            highlighted_row(ui, &names);
        });
        if leave {
            self.toggle_presentation(ui.ctx());
            return;
        }
        let left = self.presentation.replace(index);
        let step = &trace.steps[index];
        let elements = highlight::of_step(&trace.solver, &step.id);
        if moved {
            self.step_moved(left, index);
            // Forward, the step computes its parameters again (β slides to β* each time).
            if left.is_none_or(|left| left < index) {
                self.reveal(&elements, solved, ui.input(|i| i.time));
            }
        }
        self.set_highlight(elements);
        // The view keeps its verdict (and hit ring) until the steps reach it: the first step
        // does not answer what the rest derive.
        let ctx = ui.ctx().clone();
        let hidden_before = widgets::answers_hidden(&ctx);
        let before_verdict = trace.verdict_step().is_some_and(|verdict| index < verdict);
        widgets::hide_answers(&ctx, hidden_before || before_verdict);
        let page = egui::Id::unique(("presented-step", index));
        self.beside_the_view(ui, solved, "presented-step", Some((1.4, page)), |ui| {
            step_panel::step_ui(ui, index + 1, step, None);
        });
        widgets::hide_answers(&ctx, hidden_before);
    }

    /// Keeps the open view as step `left` leaves it; going back to `index`, puts back the view as
    /// that step left it (its parameters, camera and scene as Next had set them).
    fn step_moved(&mut self, left: Option<usize>, index: usize) {
        let kind = self.state.view;
        if let Some(left) = left {
            if self.presented_views.len() <= left {
                self.presented_views.resize_with(left + 1, || None);
            }
            self.presented_views[left] = Some(self.view(kind).clone_view());
        }
        let back = left.is_some_and(|left| index < left);
        if back
            && let Some(Some(view)) = self.presented_views.get(index)
            && let Some(tab) = self.state.tab_mut(kind)
        {
            tab.view = view.clone_view();
        }
    }

    /// The layout every presenter screen shares (presentation, lessons, practice): `side` in a
    /// scrolling panel of about 42% of the width on the right, the open view's canvas filling the rest.
    /// With `enlarged`, the side's text is that much larger, less as far as it takes to fit the
    /// panel's height (to at most half): a clicker cannot scroll, and a 3x3 inverse at 200% had
    /// its third row below the fold.
    pub(super) fn beside_the_view(
        &mut self,
        ui: &mut Ui,
        solved: &ActiveSolve,
        id: &'static str,
        enlarged: Option<(f32, egui::Id)>,
        side: impl FnOnce(&mut Ui),
    ) {
        let full = ui.available_width();
        let fit_id = egui::Id::unique(("raylab-fit", id));
        egui::Panel::right(id)
            .resizable(false)
            .exact_size((full * 0.42).max(220.0))
            .show(ui, |ui| {
                let Some((enlarged, page)) = enlarged else {
                    egui::ScrollArea::vertical().show(ui, side);
                    return;
                };
                // The scale found for this page (slide or step) in this much room; a new page or a
                // new size starts again from full size.
                let room = ui.available_size();
                let key = (page, room.x.round() as i64, room.y.round() as i64);
                let search = ui
                    .data(|d| d.get_temp::<((egui::Id, i64, i64), FitSearch)>(fit_id))
                    .filter(|(was, _)| *was == key)
                    .map_or_else(FitSearch::default, |(_, search)| search);
                let fit = search.now;
                let shown = egui::ScrollArea::vertical().show(ui, |ui| {
                    enlarge(ui, enlarged * fit);
                    // Rows shrink with the text: a matrix's rows are at least a widget's height
                    // apart, which at full size left smaller text with wide gaps between rows.
                    ui.spacing_mut().interact_size.y *= fit;
                    side(ui);
                });
                let refit = search.next(shown.inner_rect.height(), shown.content_size.y);
                ui.data_mut(|d| d.insert_temp(fit_id, (key, refit)));
                if refit.now != fit {
                    ui.ctx().request_repaint();
                }
            });
        let view = egui::CentralPanel::default().show(ui, |ui| self.view_ui(ui, solved, true));
        self.view_rect = Some(view.response.rect);
    }

    /// Moves the handles a newly shown step computes to their solution (β = |M1|/|M| slides β).
    pub(super) fn reveal(
        &mut self,
        elements: &[highlight::Element],
        solved: &ActiveSolve,
        now: f64,
    ) {
        for element in elements {
            let highlight::Element::Parameter(parameter) = element else {
                continue;
            };
            self.view_mut(self.state.view)
                .slide_to(*parameter, solved, now);
        }
    }
}

/// What the step (or slide) highlights, on a row of its own under the presenter's buttons, so the
/// bar keeps its height from step to step (in the buttons' row it wrapped to a second row on some
/// steps only, and the drawing jumped by 35 pixels).
/// One row, cut short with "…" where it is longer (whole on hover and to a screen reader).
pub(super) fn highlighted_row(ui: &mut Ui, names: &[String]) {
    if names.is_empty() {
        ui.label(RichText::new("Nothing highlighted").weak());
        return;
    }
    let whole = format!("Highlighted: {}", names.join(", "));
    let text = RichText::new(&whole).color(widgets::palette::SOLUTION.readable(ui));
    ui.add(egui::Label::new(text).truncate())
        .on_hover_text(&whole);
}

/// The search for a panel's text scale: the largest, in steps of 1/50, at which its content fits
/// the room, found by halving between a scale known to fit (`fits`, half at least) and one known to
/// overflow (`overflows`). Each page starts at full size and settles in a few frames; the rows
/// shrink with the text, so the content's height is not proportional to the scale and a single
/// proportional guess overshot.
#[derive(Clone, Copy, Debug, PartialEq)]
struct FitSearch {
    fits: f32,
    overflows: f32,
    now: f32,
}

impl Default for FitSearch {
    fn default() -> FitSearch {
        FitSearch {
            fits: 0.5,
            overflows: 1.01,
            now: 1.0,
        }
    }
}

impl FitSearch {
    /// After a frame drawn at `now` whose content was `content` points tall in `room`.
    fn next(self, room: f32, content: f32) -> FitSearch {
        if !(room > 0.0 && content > 0.0) {
            return self;
        }
        let mut next = self;
        if content > room {
            next.overflows = next.overflows.min(self.now);
        } else {
            next.fits = next.fits.max(self.now);
        }
        next.now = if next.overflows - next.fits <= 0.02 {
            next.fits
        } else {
            (next.fits + next.overflows) / 2.0
        };
        next
    }
}

#[cfg(test)]
mod tests {
    use super::FitSearch;

    /// The scale the search settles on, for content whose height at scale k is `height(k)`.
    fn settle(room: f32, height: impl Fn(f32) -> f32) -> (f32, usize) {
        let mut search = FitSearch::default();
        for frames in 1..50 {
            let next = search.next(room, height(search.now));
            if next == search {
                return (search.now, frames);
            }
            search = next;
        }
        panic!("no rest after 50 frames: {search:?}");
    }

    #[test]
    fn a_panel_scale_settles_on_the_largest_that_fits() {
        // Fits at full size: stays there.
        assert_eq!(settle(400.0, |k| 300.0 * k).0, 1.0);
        // Content growing faster than the scale (rows shrink with the text): the largest fitting
        // scale, within 1/50, in a few frames.
        let height = |k: f32| 700.0 * k * k;
        let (scale, frames) = settle(400.0, height);
        assert!(height(scale) <= 400.0, "{scale} overflows");
        assert!(height(scale + 0.03) > 400.0, "{scale} is not the largest");
        assert!(frames < 10, "{frames} frames");
        // Never below half, even when that overflows too.
        assert_eq!(settle(100.0, |k| 1000.0 * k).0, 0.5);
    }
}
