//! The Accuracy view: what accuracy costs in time. Runs the study as a [`Job`] (on a named background
//! thread on the desktop, in slices between frames in a web page) with a progress bar and Cancel,
//! plots error against time per test for every method × precision and error against the grazing
//! angle, shows the table, and a gallery of hard cases that load into the Triangle view with what
//! each method decides.

use super::RaylabApp;
use super::view::{ActiveSolve, OpenError, Request, View};
use super::widgets::palette::Readable as _;
use egui::{Color32, RichText, Ui};
use egui_plot::{Line, MarkerShape, Plot, PlotPoints, Points};

use super::widgets::palette;
use crate::accuracy::families::Family;
use crate::accuracy::hard_cases::{HardCase, gallery, verdicts};
use crate::accuracy::study::{self, Config, Record, StudyRun};
use crate::geometry::Precision;
use crate::intersect::Method;
use crate::platform::Job;
use crate::scene::{Problem, TriangleScene};

/// The Accuracy view's state (results are not persisted: a run takes seconds).
#[derive(Default)]
pub struct AccuracyView {
    /// The last finished study.
    pub records: Vec<Record>,
    running: Option<Job<Vec<Record>>>,
    /// The family the table and the scatter show (`None`: the worst over all families).
    pub family: Option<Family>,
    full: bool,
    gallery: Vec<HardCase>,
    /// A message about the last run.
    pub status: String,
    /// A study size to use instead of quick/full (tests use a tiny one).
    pub config_override: Option<Config>,
}

/// What the view asks the app to do.
pub enum Action {
    /// Load this case into the Triangle view.
    LoadTriangle(TriangleScene, String, String),
}

/// A copy of the view: its results, without a study in flight (a copy does not run it twice).
impl Clone for AccuracyView {
    fn clone(&self) -> AccuracyView {
        AccuracyView {
            records: self.records.clone(),
            running: None,
            family: self.family,
            full: self.full,
            gallery: self.gallery.clone(),
            status: self.status.clone(),
            config_override: self.config_override.clone(),
        }
    }
}

impl View for AccuracyView {
    fn opens(&self, _problem: &Problem) -> bool {
        false
    }

    fn open(&mut self, _problem: &Problem, _folder: Option<String>) -> Result<(), OpenError> {
        Err(OpenError::NotMine)
    }

    fn problem(&self) -> Option<Problem> {
        None
    }

    fn solve_frame(&self, _precision: Precision) -> ActiveSolve {
        ActiveSolve::nothing()
    }

    fn frame_ui(
        &mut self,
        ui: &mut Ui,
        _solved: &ActiveSolve,
        _canvas_only: bool,
    ) -> Option<Request> {
        let Action::LoadTriangle(scene, title, note) = self.ui(ui)?;
        Some(Request::new(move |app: &mut RaylabApp| {
            app.load_hard_case(scene, title, note)
        }))
    }
}

/// A colour per method, for the legend.
fn method_color(name: &str) -> Color32 {
    match name {
        "cramer" => palette::BETA,
        "moller-trumbore" => palette::OUTSIDE,
        "plane" => palette::GAMMA,
        "normal-equations" => palette::RHS,
        "inverse" => Color32::from_rgb(0x80, 0x80, 0x80),
        "watertight" => palette::INSIDE,
        _ => palette::RAY,
    }
}

/// The plots' shared legend: one colour per method (squares and dashes are f32).
/// A row of the table as a sentence, for a screen reader.
fn row_text(r: &crate::accuracy::study::Record) -> String {
    format!(
        "{} in {}, {} rays: {} tests, {} wrong, {} cracks, {} double hits, largest relative error \
         of t {:.1e}, {:.1e} ulps, {} exact fallbacks, {:.1} ns a test",
        r.method,
        r.precision,
        r.family,
        r.tests,
        r.wrong_decisions,
        r.cracks,
        r.double_hits,
        r.max_rel_err_t,
        r.max_ulps_t,
        r.exact_fallbacks,
        r.ns_per_test
    )
}

fn legend_ui(ui: &mut Ui) {
    ui.horizontal_wrapped(|ui| {
        for method in Method::FLOAT {
            ui.label(
                RichText::new(format!("● {}", method.name()))
                    .color(method_color(method.name()).readable(ui)),
            );
        }
        ui.label(
            RichText::new("(squares and dashed lines: f32; circles and solid lines: f64)").weak(),
        );
    });
}

impl AccuracyView {
    /// True while a study runs.
    pub fn is_running(&self) -> bool {
        self.running.is_some()
    }

    /// Starts the study (on a named thread, or in slices on the web); the UI is woken as it
    /// progresses.
    pub fn start(&mut self, ctx: &egui::Context) {
        if self.running.is_some() {
            return;
        }
        let config = match &self.config_override {
            Some(config) => config.clone(),
            None if self.full => Config::full(),
            None => Config::quick(),
        };
        let ctx = ctx.clone();
        match Job::start("raylab-accuracy-study", StudyRun::new(config), move || {
            ctx.request_repaint()
        }) {
            Ok(job) => {
                self.status = "running…".into();
                self.running = Some(job);
            }
            Err(error) => self.status = format!("could not start the study: {error}"),
        }
    }

    /// Advances the study (on the web, this is where it runs) and takes its result when finished.
    fn poll(&mut self, ctx: &egui::Context) {
        let Some(job) = self.running.as_mut() else {
            return;
        };
        if let Some(failure) = job.failure() {
            self.running = None;
            self.status = format!(
                "the study stopped on an internal error ({failure}); the app goes on: press Run to try again"
            );
        } else if let Some(records) = job.poll() {
            self.running = None;
            self.status = format!(
                "{} tests measured",
                records.iter().map(|r| r.tests).sum::<usize>()
            );
            self.records = records;
        } else if !crate::platform::THREADS {
            // No thread wakes the UI on the web: the next frame runs the next slice.
            ctx.request_repaint();
        }
    }

    /// Stops the running study; the results of an earlier run, if any, stay on screen.
    fn cancel(&mut self) {
        if let Some(job) = self.running.take() {
            job.cancel();
            self.status = if self.records.is_empty() {
                "cancelled before any result: press Run to start again".into()
            } else {
                "cancelled; the results of the previous run are still shown".into()
            };
        }
    }

    /// The view.
    pub fn ui(&mut self, ui: &mut Ui) -> Option<Action> {
        self.poll(ui.ctx());
        let mut action = None;
        egui::ScrollArea::vertical().auto_shrink([false, false]).show(ui, |ui| {
            self.controls_ui(ui);
            if self.records.is_empty() {
                ui.label("Press Run to measure every method in f32 and f64 against exact arithmetic.");
            } else {
                if self.running.is_some() {
                    // Not this run's: said, so nobody reads the old figures as the new ones.
                    ui.label(
                        RichText::new(
                            "Below: the last run's results, until this run finishes and replaces them",
                        )
                        .italics(),
                    );
                }
                self.family_picker(ui);
                legend_ui(ui);
                // Side by side where there is room; stacked on a zoomed projector, so each plot
                // keeps the width its tick numbers need.
                if ui.available_width() >= 900.0 {
                    ui.columns(2, |columns| {
                        self.scatter_ui(&mut columns[0]);
                        self.grazing_ui(&mut columns[1]);
                    });
                } else {
                    self.scatter_ui(ui);
                    self.grazing_ui(ui);
                }
                self.table_ui(ui);
            }
            ui.separator();
            action = self.gallery_ui(ui);
        });
        action
    }

    fn controls_ui(&mut self, ui: &mut Ui) {
        ui.horizontal_wrapped(|ui| {
            ui.heading("What accuracy costs");
            let running = self.running.is_some();
            if ui
                .add_enabled(!running, egui::Button::new("Run"))
                .on_hover_text("Measure every method in f32 and f64 on the ray families, judged by exact arithmetic")
                .clicked()
            {
                self.start(ui.ctx());
            }
            ui.add_enabled(!running, egui::Checkbox::new(&mut self.full, "Full run"))
                .on_hover_text("More rays (a minute or more) instead of the quick run (seconds)");
            if let Some(job) = &self.running {
                let (done, total) = job.progress();
                ui.add(
                    egui::ProgressBar::new(done as f32 / total.max(1) as f32)
                        .desired_width(220.0)
                        .text(format!("{done} / {total}")),
                );
                if ui.button("Cancel").on_hover_text("Stop the run (the results of an earlier run stay on screen)").clicked() {
                    self.cancel();
                }
            }
            ui.label(RichText::new(&self.status).weak());
        });
    }

    fn family_picker(&mut self, ui: &mut Ui) {
        ui.horizontal_wrapped(|ui| {
            ui.label("Family:");
            ui.selectable_value(&mut self.family, None, "all (worst)")
                .on_hover_text("The largest error over every family, and the mean time");
            for family in Family::ALL {
                ui.selectable_value(&mut self.family, Some(family), family.name());
            }
        });
    }

    fn scatter_ui(&self, ui: &mut Ui) {
        ui.label(RichText::new("Largest relative error of t against time per test").strong());
        let points = study::summary(&self.records, self.family.map(Family::name));
        let log = |x: f64| x.max(1e-18).log10();
        Plot::new("error-vs-time")
            .height(280.0)
            .x_axis_label("ns per test (log)")
            .y_axis_label("max relative error of t (log)")
            .x_axis_formatter(|mark, _| format!("{:.0}", 10f64.powf(mark.value)))
            .y_axis_formatter(|mark, _| format!("1e{:.0}", mark.value))
            .label_formatter(|hover| match hover {
                egui_plot::HoverPosition::NearDataPoint {
                    plot_name,
                    position,
                    ..
                } => Some(format!(
                    "{plot_name}\n{:.1} ns per test\nlargest relative error of t {:.2e}",
                    10f64.powf(position.x),
                    10f64.powf(position.y)
                )),
                _ => None,
            })
            .show(ui, |plot| {
                for point in &points {
                    let (method, precision) = (&point.method, &point.precision);
                    let (ns, error) = (&point.ns_per_test, &point.max_rel_err_t);
                    let shape = if precision == "f32" {
                        MarkerShape::Square
                    } else {
                        MarkerShape::Circle
                    };
                    // One legend entry per method: f32 and f64 share the name (and colour).
                    plot.points(
                        Points::new(
                            method.clone(),
                            PlotPoints::from(vec![[log(*ns), log(*error)]]),
                        )
                        .shape(shape)
                        .radius(6.0)
                        .filled(true)
                        .color(method_color(method)),
                    );
                }
            });
        ui.label(
            RichText::new("Squares are f32, circles f64. Errors of 0 are drawn at 1e-18.").weak(),
        );
    }

    fn grazing_ui(&self, ui: &mut Ui) {
        ui.label(RichText::new("Relative error of t against the grazing angle").strong());
        let log = |x: f64| x.max(1e-18).log10();
        Plot::new("error-vs-angle")
            .height(280.0)
            .x_axis_label("angle to the plane, radians (log)")
            .y_axis_label("max relative error of t (log)")
            .x_axis_formatter(|mark, _| format!("1e{:.0}", mark.value))
            .y_axis_formatter(|mark, _| format!("1e{:.0}", mark.value))
            .show(ui, |plot| {
                for record in self
                    .records
                    .iter()
                    .filter(|r| r.family == "grazing" && !r.error_by_parameter.is_empty())
                {
                    let series: Vec<[f64; 2]> = record
                        .error_by_parameter
                        .iter()
                        .map(|[angle, error]| [log(*angle), log(*error)])
                        .collect();
                    let mut line = Line::new(record.method.clone(), PlotPoints::from(series))
                        .color(method_color(&record.method));
                    if record.precision == "f32" {
                        line = line.style(egui_plot::LineStyle::dashed_loose());
                    }
                    plot.line(line);
                }
            });
        ui.label(
            RichText::new("Smaller angles are harder: the ray nearly lies in the plane.").weak(),
        );
    }

    /// The table of every record, its header kept in view while the rows scroll.
    fn table_ui(&self, ui: &mut Ui) {
        use egui_extras::{Column, TableBuilder};
        const HEADS: [(&str, &str); 11] = [
            ("method", "The intersection method"),
            ("precision", "The arithmetic it ran in"),
            (
                "family",
                "The family of rays (all: the worst of every family)",
            ),
            ("tests", "Rays tested"),
            (
                "wrong",
                "Hit or miss decided differently from exact arithmetic",
            ),
            (
                "cracks",
                "Rays through a shared edge that hit neither triangle",
            ),
            (
                "double",
                "Rays through a shared edge that hit both triangles",
            ),
            (
                "rel err t",
                "Largest relative error of t against the exact t",
            ),
            ("ulps t", "Largest error of t in units in the last place"),
            ("exact", "Rays decided by the exact fallback"),
            ("ns/test", "Mean time per ray–triangle test"),
        ];
        ui.label(RichText::new("The table").strong());
        let row_height = ui.text_style_height(&egui::TextStyle::Body) + 6.0;
        let rows: Vec<_> = self
            .records
            .iter()
            .filter(|r| self.family.is_none_or(|f| r.family == f.name()))
            .collect();
        // At most about half the screen, so the plots above stay in reach.
        let height = (ui.ctx().content_rect().height() * 0.5).max(6.0 * row_height);
        ui.push_id("accuracy-table", |ui| {
            // One line per cell: a method's name must not break into "moller-trumbo / re".
            ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
            TableBuilder::new(ui)
                .striped(true)
                .columns(Column::auto().at_least(40.0), HEADS.len())
                .min_scrolled_height(0.0)
                .max_scroll_height(height)
                .header(row_height, |mut header| {
                    for (head, tip) in HEADS {
                        header.col(|ui| {
                            ui.label(RichText::new(head).strong()).on_hover_text(tip);
                        });
                    }
                })
                .body(|body| {
                    body.rows(row_height, rows.len(), |mut row| {
                        let r = rows[row.index()];
                        let outside = |ui: &Ui, text: RichText, bad: bool| {
                            if bad {
                                text.color(palette::OUTSIDE.readable(ui)).strong()
                            } else {
                                text
                            }
                        };
                        row.col(|ui| {
                            let colour = method_color(&r.method).readable(ui);
                            // A screen reader reads the row whole from its first cell, each
                            // number with its column's name.
                            ui.label(RichText::new(&r.method).color(colour))
                                .widget_info(|| {
                                    egui::WidgetInfo::labeled(egui::Role::Row, true, row_text(r))
                                });
                        });
                        row.col(|ui| {
                            ui.label(&r.precision);
                        });
                        row.col(|ui| {
                            ui.label(&r.family);
                        });
                        row.col(|ui| {
                            ui.label(r.tests.to_string());
                        });
                        row.col(|ui| {
                            let text = RichText::new(r.wrong_decisions.to_string());
                            ui.label(outside(ui, text, r.wrong_decisions > 0));
                        });
                        row.col(|ui| {
                            let text = RichText::new(r.cracks.to_string());
                            ui.label(outside(ui, text, r.cracks > 0));
                        });
                        row.col(|ui| {
                            ui.label(r.double_hits.to_string());
                        });
                        row.col(|ui| {
                            ui.label(format!("{:.1e}", r.max_rel_err_t));
                        });
                        row.col(|ui| {
                            ui.label(format!("{:.1e}", r.max_ulps_t));
                        });
                        row.col(|ui| {
                            ui.label(r.exact_fallbacks.to_string());
                        });
                        row.col(|ui| {
                            ui.label(format!("{:.1}", r.ns_per_test));
                        });
                    });
                });
        });
    }

    fn gallery_ui(&mut self, ui: &mut Ui) -> Option<Action> {
        ui.heading("Hard cases");
        ui.label(RichText::new("Each case against the exact reference; Load opens it in the Triangle view with its trace.").weak());
        if self.gallery.is_empty() {
            self.gallery = gallery();
        }
        let mut action = None;
        for hard in &self.gallery {
            ui.horizontal_wrapped(|ui| {
                if ui
                    .button("Load")
                    .on_hover_text("Open this case in the Triangle view")
                    .clicked()
                {
                    let scene = TriangleScene {
                        a: hard.a,
                        b: hard.b,
                        c: hard.c,
                        origin: hard.origin,
                        dir: hard.dir,
                        t_min: 0.0,
                    };
                    action = Some(Action::LoadTriangle(
                        scene,
                        format!("Hard case: {}", hard.name),
                        hard.note.clone(),
                    ));
                }
                ui.label(RichText::new(&hard.name).strong());
                ui.label(RichText::new(&hard.note).weak());
            });
            let verdicts = verdicts(&hard.case());
            ui.horizontal_wrapped(|ui| {
                ui.add_space(24.0);
                for v in &verdicts {
                    let (mark, color) = if v.hit == v.exact_hit {
                        ("✓", palette::INSIDE)
                    } else {
                        ("✗", palette::OUTSIDE)
                    };
                    let said = if v.invalid_input {
                        "out of range"
                    } else if v.hit {
                        "hit"
                    } else {
                        "miss"
                    };
                    ui.label(
                        RichText::new(format!("{mark} {} {said}", v.who))
                            .color(color.readable(ui))
                            .small(),
                    )
                    .on_hover_text(if v.exact_hit {
                        "exact: hit"
                    } else {
                        "exact: miss"
                    });
                }
            });
        }
        action
    }
}
