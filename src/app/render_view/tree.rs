//! The probe's ray tree: the probed pixel's primary ray, how each light reaches its hit (the shadow
//! ray, lit or blocked), the reflected and refracted rays with their bounce, and the occlusion rays
//! summarised. A ray that hit a triangle (or parallelogram) opens in its view with its steps.
//! The tree itself is built in the core ([`crate::render::inspect::ray_tree`]); this only draws it.

use super::*;
use crate::render::Ray;
use crate::render::inspect::ray_tree::{LightRay, RayTree, TracedRay};
use crate::render::ray_kinds::RayKind;
use crate::render::secondary::LightTest;

/// A ray the tree asks to open: the problem for its view, and what to call it.
pub(super) struct Opened {
    pub(super) problem: Action,
    pub(super) name: String,
}

/// "the reflected ray (bounce 2)".
fn ray_name(ray: &TracedRay) -> String {
    let name = match ray.kind {
        RayKind::Primary => "the primary ray",
        RayKind::Sample => "an antialiasing sample",
        RayKind::Shadow => "a shadow ray",
        RayKind::Reflection => "the reflected ray",
        RayKind::Refraction => "the refracted ray",
        RayKind::Occlusion => "an occlusion ray",
    };
    if ray.depth == 0 {
        name.to_string()
    } else {
        format!("{name} (bounce {})", ray.depth)
    }
}

/// A capital first letter.
fn capitalised(text: &str) -> String {
    let mut chars = text.chars();
    chars
        .next()
        .map(|c| c.to_uppercase().chain(chars).collect())
        .unwrap_or_default()
}

impl RenderView {
    /// "object 13 (mesh), triangle 200 at t = 0.531200".
    fn hit_text(&self, hit: &Hit) -> String {
        format!("{} at t = {:.6}", self.hit_object_text(hit), hit.t)
    }

    /// "object 13 (mesh), triangle 200": the triangle only where the object has more than one.
    pub(super) fn hit_object_text(&self, hit: &Hit) -> String {
        let kind = self.object_kind(hit.object);
        let part = if kind == "mesh" {
            format!(", triangle {}", hit.primitive)
        } else {
            String::new()
        };
        format!("object {} ({kind}){part}", hit.object + 1)
    }

    /// The probed pixel's ray tree; a ray's "Steps →" button asks for it to open in its view.
    pub(super) fn ray_tree_ui(&self, ui: &mut Ui, tree: &RayTree) -> Option<Opened> {
        let mut opened = None;
        ui.label(RichText::new("Ray tree").strong()).on_hover_text(
            "Every ray this pixel led to, as the render traced it: the shadow ray to each light, \
             the reflected and refracted rays with their bounce, the occlusion rays counted",
        );
        if let Some(samples) = tree.samples {
            ui.label(format!(
                "Antialiasing: {} sample rays, {} of them hit; the pixel shows their mean. Below: \
                 the ray through the pixel's centre, traced as without antialiasing.",
                samples.cast, samples.hit
            ));
        }
        self.traced_ray_ui(ui, &tree.root, "t", &mut opened);
        opened
    }

    fn traced_ray_ui(&self, ui: &mut Ui, ray: &TracedRay, path: &str, opened: &mut Option<Opened>) {
        let name = ray_name(ray);
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new(capitalised(&name)).strong());
            match &ray.hit {
                Some(hit) => {
                    ui.label(
                        RichText::new(format!("hits {}", self.hit_text(hit)))
                            .color(palette::INSIDE.readable(ui)),
                    );
                    self.open_button(ui, (ray.ray, *hit), &name, opened);
                }
                None => {
                    ui.label("meets nothing: black");
                }
            }
        });
        ui.indent(format!("{path}-body"), |ui| {
            for light in &ray.lights {
                self.light_ui(ui, light, &name, opened);
            }
            if let Some(occlusion) = ray.occlusion {
                ui.label(format!(
                    "Occlusion: {} rays over the hemisphere, {} blocked ({} escape)",
                    occlusion.cast,
                    occlusion.blocked,
                    occlusion.cast - occlusion.blocked
                ));
            }
            if ray.children.is_empty() {
                return;
            }
            let count = ray.children.len();
            let title = format!(
                "{count} ray{} from this hit",
                if count == 1 { "" } else { "s" }
            );
            egui::CollapsingHeader::new(title)
                .id_salt(format!("{path}-children"))
                .default_open(ray.depth < 2)
                .show(ui, |ui| {
                    for (i, child) in ray.children.iter().enumerate() {
                        self.traced_ray_ui(ui, child, &format!("{path}-{i}"), opened);
                    }
                });
        });
    }

    /// How one light reaches the hit of `from`.
    fn light_ui(&self, ui: &mut Ui, light: &LightRay, from: &str, opened: &mut Option<Opened>) {
        let name = format!("the shadow ray to light {} from {from}", light.light + 1);
        ui.horizontal_wrapped(|ui| {
            ui.label(format!("Shadow ray → light {}:", light.light + 1));
            match (light.test, light.blocker) {
                (LightTest::Blocked(ray, _), blocker) => {
                    let by =
                        blocker.map_or(String::new(), |hit| format!(" by {}", self.hit_text(&hit)));
                    ui.label(
                        RichText::new(format!("blocked{by}")).color(palette::OUTSIDE.readable(ui)),
                    );
                    if let Some(hit) = blocker {
                        self.open_button(ui, (ray, hit), &name, opened);
                    }
                }
                (LightTest::Lit(..), _) => {
                    ui.label(RichText::new("lit").color(palette::INSIDE.readable(ui)))
                        .on_hover_text("Nothing between the hit and the light");
                }
                (LightTest::FacesAway, _) => {
                    ui.label("faces away: no ray").on_hover_text(
                        "The surface turns its back to this light: no light, no ray",
                    );
                }
                (LightTest::Untested, _) => {
                    ui.label("lit (shadows off: no ray)");
                }
            }
        });
    }

    /// "Steps →": opens the ray with what it hit in the Triangle (or Parallelogram) view.
    fn open_button(
        &self,
        ui: &mut Ui,
        (ray, hit): (Ray, Hit),
        name: &str,
        opened: &mut Option<Opened>,
    ) {
        let Some(problem) = self.hit_problem(ray, hit) else {
            return;
        };
        let view = super::probe::view_of(&problem);
        let label = format!("Open {name} in the {} view", view.label());
        let response = ui.button("Steps →").on_hover_text(format!(
            "{label}: the same ray and what it hit, with every step"
        ));
        response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Button, true, &label));
        if response.clicked() {
            *opened = Some(Opened {
                problem,
                name: name.to_string(),
            });
        }
    }
}
