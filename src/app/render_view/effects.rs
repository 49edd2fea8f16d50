//! The Render view's effects past ray casting: a tooltip per effect saying what it does and what it
//! costs, the last render's rays by kind, and the per-effect cost (the scene rendered again with each
//! effect off in turn, in the background).

use super::*;
use crate::render::inspect::cost::{CostJob, EffectCost};
use crate::render::ray_kinds::RayKind;

/// A measurement of each effect's cost, for the choices it was started under.
pub(super) struct Cost {
    pub(super) key: Choices,
    pub(super) job: Option<Job<Vec<EffectCost>>>,
    pub(super) result: Option<Vec<EffectCost>>,
    pub(super) error: Option<String>,
}

/// What an effect does, in a sentence a student understands, and what it costs.
pub(super) fn effect_hint(effect: Effect, scene: &RenderScene) -> String {
    let s = &scene.settings;
    let lights = scene.lights.len();
    let plural = |n: usize, word: &str| format!("{n} {word}{}", if n == 1 { "" } else { "s" });
    let (what, cost) = match effect {
        Effect::Shadows => (
            "Is anything between this point and the light? From every point the camera sees, a \
             shadow ray goes towards each light; if it meets something first, that light does not \
             count there."
                .to_string(),
            format!(
                "one ray per light at every shaded hit ({} here), each stopping at the first thing \
                 it meets.",
                plural(lights, "light")
            ),
        ),
        Effect::Reflections => (
            "Mirrors show the room: where a ray meets a mirror, a new ray leaves at the same angle \
             (r = d − 2(d·n)n) and what it sees is mixed into the mirror's colour."
                .to_string(),
            format!(
                "one more ray per mirror hit, and again at each bounce, up to {}.",
                plural(s.max_depth as usize, "bounce")
            ),
        ),
        Effect::Refraction => (
            "Glass bends light: a ray going into glass turns by Snell's law (η₁ sin θ₁ = η₂ sin θ₂) \
             and goes on through; too steep from inside, it is reflected back instead (total \
             internal reflection)."
                .to_string(),
            format!(
                "one more ray per glass hit, and again each time it crosses a surface, up to {}.",
                plural(s.max_depth as usize, "bounce")
            ),
        ),
        Effect::AmbientOcclusion => (
            "Corners and creases are darker: random rays leave each hit over the half-sphere above \
             it, and the share that gets out scales the ambient light."
                .to_string(),
            format!(
                "{} at every shaded hit: often the dearest effect.",
                plural(s.occlusion_rays as usize, "ray")
            ),
        ),
        Effect::Antialiasing => {
            let k = s.samples_per_side.max(1);
            (
                format!(
                    "Smooth edges: instead of one ray through the pixel's centre, {k}×{k} rays \
                     spread over the pixel (one in each cell of a {k}×{k} grid) and the pixel shows \
                     the mean of their colours."
                ),
                format!(
                    "{} times the rays of every pixel, and of everything they lead to.",
                    k * k
                ),
            )
        }
        Effect::Coverage => (effect.explanation().into(), "nothing past the hit.".into()),
        Effect::Depth => (effect.explanation().into(), "a division per hit.".into()),
        Effect::FacingRatio => (effect.explanation().into(), "a dot product per hit.".into()),
        Effect::BarycentricColor => (effect.explanation().into(), "a weighted sum per hit.".into()),
        Effect::SmoothNormals => (
            effect.explanation().into(),
            "a weighted sum and a normalisation per hit.".into(),
        ),
        Effect::Texture => (effect.explanation().into(), "a texel lookup per hit.".into()),
    };
    format!("{what}\nCost: {cost}")
}

/// 1234567 as "1 234 567": big counts read at a glance from the back of a room.
pub fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// Milliseconds, with a decimal below 100.
fn millis(seconds: f64) -> String {
    let ms = seconds * 1e3;
    if ms < 100.0 {
        format!("{ms:.1} ms")
    } else {
        format!("{ms:.0} ms")
    }
}

impl RenderView {
    /// The last render's rays by kind: a table, a row per kind with its count right-aligned, or
    /// (`compact`) the counts on wrapped lines.
    pub(super) fn rays_by_kind_ui(&self, ui: &mut Ui, compact: bool) {
        let Some(shown) = &self.runtime.correct.shown else {
            return;
        };
        let stats = &shown.rendered.stats;
        let rows: Vec<(String, String, String)> = RayKind::ALL
            .iter()
            .map(|kind| {
                let name = kind.name();
                let off = kind
                    .effect()
                    .is_some_and(|e| !shown.key.effects.contains(&e));
                let shown_name = if off {
                    format!("{name} (off)")
                } else {
                    name.to_string()
                };
                let value = grouped(stats.rays_of(*kind));
                let info = format!("{name} rays: {value}");
                (shown_name, value, info)
            })
            .chain(std::iter::once((
                "all".to_string(),
                grouped(stats.all_rays()),
                format!("all rays: {}", grouped(stats.all_rays())),
            )))
            .collect();
        let heading = "Every ray the last render cast, by what it was for: an effect that is off \
                       casts none";
        let labelled = |response: egui::Response, info: &str| {
            response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Label, true, info));
        };
        if compact {
            ui.horizontal_wrapped(|ui| {
                ui.label(RichText::new("Rays by kind:").strong())
                    .on_hover_text(heading);
                for (name, value, info) in &rows {
                    // A kind and its count stay together on a line.
                    let text = RichText::new(format!("{name} {value}")).strong();
                    let label = egui::Label::new(text).wrap_mode(egui::TextWrapMode::Extend);
                    labelled(ui.add(label), info);
                    ui.add_space(6.0);
                }
            });
            return;
        }
        ui.label(RichText::new("Rays by kind").strong())
            .on_hover_text(heading);
        let width = rows.iter().map(|(_, v, _)| v.len()).max().unwrap_or(0);
        egui::Grid::new("render-rays-by-kind")
            .num_columns(2)
            .spacing([16.0, 2.0])
            .show(ui, |ui| {
                for (name, value, info) in &rows {
                    ui.label(name);
                    // Monospace, padded on the left: the digits line up.
                    let padded = format!("{value:>width$}");
                    labelled(ui.label(RichText::new(padded).monospace().strong()), info);
                    ui.end_row();
                }
            });
    }

    /// The choices a cost measurement depends on (the bug's image plays no part).
    fn cost_key(&self) -> Choices {
        Choices {
            pixel: None,
            bug: None,
            ..self.probe_key()
        }
    }

    /// Takes a finished measurement; drops one made under other choices.
    pub(super) fn poll_cost(&mut self, ctx: &egui::Context) {
        let key = self.cost_key();
        let Some(cost) = self.runtime.cost.as_mut() else {
            return;
        };
        if cost.key != key {
            self.runtime.cost = None;
            return;
        }
        let Some(job) = cost.job.as_mut() else {
            return;
        };
        if let Some(failure) = job.failure() {
            cost.error = Some(format!("the measurement stopped: {failure}"));
            cost.job = None;
        } else if let Some(result) = job.poll() {
            cost.result = Some(result);
            cost.job = None;
        } else if !crate::platform::THREADS {
            // No thread wakes the UI on the web: the next frame runs the next slice.
            ctx.request_repaint();
        }
    }

    /// Starts measuring each effect's cost in the background.
    fn start_cost(&mut self, ctx: &egui::Context) {
        let key = self.cost_key();
        let started = self.prepared(None).and_then(|prepared| {
            let waker = ctx.clone();
            Job::start("raylab-cost", CostJob::new(&prepared), move || {
                waker.request_repaint()
            })
        });
        self.runtime.cost = Some(match started {
            Ok(job) => Cost {
                key,
                job: Some(job),
                result: None,
                error: None,
            },
            Err(error) => Cost {
                key,
                job: None,
                result: None,
                error: Some(error),
            },
        });
    }

    /// The button that measures each effect's cost, its progress, and the table it gives.
    pub(super) fn cost_ui(&mut self, ui: &mut Ui) {
        if self.effects.is_empty() || self.runtime.correct.shown.is_none() {
            return;
        }
        let running = self.runtime.cost.as_ref().is_some_and(|c| c.job.is_some());
        ui.horizontal_wrapped(|ui| {
            let button = ui
                .add_enabled(
                    !running,
                    egui::Button::new("Measure the cost of each effect"),
                )
                .on_hover_text(
                    "Renders the scene again with all its effects on, then with each one off in \
                     turn, and shows each render's time: what leaving that effect out saves",
                );
            if button.clicked() {
                self.start_cost(ui.ctx());
            }
            if running && ui.button("Cancel").clicked() {
                self.runtime.cost = None;
            }
        });
        let Some(cost) = &self.runtime.cost else {
            return;
        };
        if let Some(job) = &cost.job {
            let (done, total) = job.progress();
            ui.add(egui::ProgressBar::new(done as f32 / total as f32).text("measuring…"));
        }
        if let Some(error) = &cost.error {
            ui.label(RichText::new(error).color(palette::OUTSIDE.readable(ui)));
        }
        if let Some(result) = &cost.result {
            cost_table(ui, result);
        }
    }
}

/// A row per render: the effects, its time, and its change against all effects on (three narrow
/// columns: the table sits in the column beside the image).
fn cost_table(ui: &mut Ui, result: &[EffectCost]) {
    let Some(all) = result.first() else {
        return;
    };
    egui::Grid::new("render-cost")
        .num_columns(3)
        .spacing([12.0, 2.0])
        .show(ui, |ui| {
            ui.label(RichText::new("render").strong());
            ui.label(RichText::new("time").strong());
            ui.label(RichText::new("vs all").strong());
            ui.end_row();
            for row in result {
                let name = match row.without {
                    None => "all effects on".to_string(),
                    Some(effect) => format!("without {}", effect.name()),
                };
                let by_kind: Vec<String> = RayKind::ALL
                    .iter()
                    .map(|kind| format!("{} {}", kind.name(), grouped(row.stats.rays_of(*kind))))
                    .collect();
                ui.label(name).on_hover_text(format!(
                    "{} rays: {}",
                    grouped(row.stats.all_rays()),
                    by_kind.join(", ")
                ));
                ui.label(RichText::new(millis(row.seconds)).monospace().strong());
                let change = if row.without.is_some() && all.seconds > 0.0 {
                    let change = (row.seconds - all.seconds) / all.seconds * 100.0;
                    let sign = if change < 0.0 { "−" } else { "+" };
                    format!("{sign}{:.0}%", change.abs())
                } else {
                    String::new()
                };
                ui.label(RichText::new(change).monospace());
                ui.end_row();
            }
        })
        .response
        .on_hover_text(
            "Each render's wall-clock time, and how much faster it is than with all effects on: an \
             effect costs what its rays cost, and nothing when it is off (times vary a little from \
             run to run)",
        );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_are_grouped_by_thousands() {
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(1000), "1 000");
        assert_eq!(grouped(1_913_175), "1 913 175");
    }

    #[test]
    fn each_effect_past_ray_casting_says_what_it_costs_with_the_scene_numbers() {
        let scene = RenderScene {
            lights: vec![crate::scene::render::Light::Directional {
                direction: [0.0, 0.0, -1.0],
                color: [1.0; 3],
                intensity: 1.0,
            }],
            ..RenderView::default().scene
        };
        let hint = effect_hint(Effect::Shadows, &scene);
        assert!(hint.contains("1 light here"), "{hint}");
        let k = scene.settings.samples_per_side;
        let hint = effect_hint(Effect::Antialiasing, &scene);
        assert!(
            hint.contains(&format!("{} times the rays", k * k)),
            "{hint}"
        );
        for effect in <Effect as strum::IntoEnumIterator>::iter() {
            assert!(effect_hint(effect, &scene).contains("\nCost: "));
        }
    }
}
