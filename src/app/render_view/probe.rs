//! The Render view's probe: a clicked pixel's ray, what it met, and the button that opens it in the
//! Triangle or Parallelogram view with its steps.

use super::*;
use crate::render::{At, Ray};

impl RenderView {
    /// The choices a probe depends on.
    pub(super) fn probe_key(&self) -> Choices {
        Choices {
            scene: self.scene.clone(),
            camera: self.view_camera(),
            effects: self.effects.clone(),
            method: self.method,
            bug: self.probed_bug,
            pixel: self.probed,
            draft: None,
        }
    }

    /// Casts the probed pixel's ray again under the current choices.
    pub(super) fn reprobe(&mut self) {
        // A bug's image probed after its bug was turned off or changed: the correct image's pixel.
        if self.probed_bug.is_some() && self.probed_bug != self.bug {
            self.probed_bug = None;
        }
        self.runtime.probe_key = Some(self.probe_key());
        let (probe, problem) = match (self.probed, self.prepared(self.probed_bug)) {
            (Some((row, column)), Ok(prepared))
                if row < prepared.height && column < prepared.width =>
            {
                let result = probe(&prepared, row, column);
                let problem = probed_problem(&prepared, &result);
                // Ray casting alone has no tree: one ray, shown above.
                self.runtime.tree = crate::render::secondary::applies(&prepared)
                    .then(|| ray_tree(&prepared, row, column));
                (Some(result), problem)
            }
            _ => {
                self.runtime.tree = None;
                (None, None)
            }
        };
        self.runtime.probe = probe;
        self.runtime.probed_problem = problem;
        self.runtime.opened = None;
    }

    /// The pixel's ray last loaded into the Triangle (or Parallelogram) view: "Pixel (row 3,
    /// column 4)", or "Pixel (row 3, column 4): the shadow ray to light 1 from the primary ray".
    pub fn probed_ray_name(&self) -> String {
        let pixel = self.probed_pixel_name();
        match &self.runtime.opened {
            Some(name) => format!("{pixel}: {name}"),
            None => pixel,
        }
    }

    /// The probed pixel and the image it was clicked on: "Pixel (row 3, column 4) of the correct
    /// image", or "… of the image with the bug “accepting t < 0”".
    pub fn probed_pixel_name(&self) -> String {
        let pixel = pixel_name(self.probed.unwrap_or_default());
        match (self.probed_bug, self.bug) {
            (Some(bug), _) => format!("{pixel} of the image with the bug “{}”", bug.name()),
            (None, Some(_)) => format!("{pixel} of the correct image"),
            (None, None) => pixel,
        }
    }

    /// The ray whose steps the step panel shows: the probed pixel's primary ray, or the ray of its
    /// tree last opened.
    pub fn steps_subject(&self) -> Option<String> {
        self.probed?;
        let ray = match &self.runtime.opened {
            Some(name) => name.clone(),
            None => "the primary ray".to_string(),
        };
        Some(format!("{}: {ray}", self.probed_pixel_name()))
    }

    /// Probes a pixel of the correct image (`bug` `None`) or of the bug's image beside it.
    pub fn probe_pixel_in(&mut self, pixel: (usize, usize), bug: Option<Bug>) -> Option<Action> {
        self.probed_bug = bug;
        self.probe_pixel(pixel)
    }

    /// The problem of a ray of the tree and what it hit, for its view.
    pub(super) fn hit_problem(&self, ray: Ray, hit: Hit) -> Option<Action> {
        let (_, Ok(prepared)) = self.runtime.prepared.as_ref()? else {
            return None;
        };
        problem_of(prepared, ray, hit)
    }

    /// Loads a ray of the tree into its view, and switches to that view on the next frame.
    pub(super) fn open_ray(&mut self, opened: tree::Opened) -> Action {
        self.runtime.opened = Some(opened.name);
        self.load_problem(opened.problem)
    }

    /// Loads a probed problem into its view, and switches to that view on the next frame.
    fn load_problem(&mut self, problem: Action) -> Action {
        self.runtime.probed_problem = Some(problem.clone());
        self.runtime.pending = Some(Action::Open(view_of(&problem)));
        problem
    }

    /// Probes a pixel; the hit (or nearest missed) primitive goes to its view.
    pub fn probe_pixel(&mut self, pixel: (usize, usize)) -> Option<Action> {
        self.probed = Some(pixel);
        self.reprobe();
        self.runtime.probed_problem.clone()
    }

    /// What the probe found, a button to the view that shows its steps, and the pixel's ray tree.
    pub(super) fn probe_ui(&mut self, ui: &mut Ui) -> Option<Action> {
        let action = self.primary_ui(ui);
        let Some(tree) = self.runtime.tree.take() else {
            return action;
        };
        ui.add_space(6.0);
        let opened = self.ray_tree_ui(ui, &tree);
        self.runtime.tree = Some(tree);
        match opened {
            Some(opened) => Some(self.open_ray(opened)),
            None => action,
        }
    }

    /// The primary ray: what it met, and a button to the view that shows its steps.
    fn primary_ui(&mut self, ui: &mut Ui) -> Option<Action> {
        let Some(probe) = self.runtime.probe.clone() else {
            ui.label(
                RichText::new(
                    "Click a pixel: its ray goes into the Triangle view and the step panel.",
                )
                .weak(),
            );
            return None;
        };
        let probe = &probe;
        let vector = |v: &[f64; 3]| format!("({:.4}, {:.4}, {:.4})", v[0], v[1], v[2]);
        let (row, column) = probe.pixel;
        let mut action = None;
        let probed_image = if self.probed_bug.is_some() {
            self.rendered_with_bug()
        } else {
            self.rendered()
        };
        let in_image =
            probed_image.and_then(|r| r.image.covered.get(row * r.image.width + column).copied());
        if in_image.is_some_and(|covered| covered != probe.hit.is_some()) {
            ui.label(
                RichText::new(
                    "On this edge pixel the image and the probe disagree: the image took the fast \
                     path (Möller–Trumbore in f32, a row at a time), the probe casts in f64.",
                )
                .color(palette::OUTSIDE.readable(ui)),
            );
        }
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new(self.probed_pixel_name()).strong());
            ui.label(format!(
                "O = {}  D = {}",
                vector(&probe.origin),
                vector(&probe.dir)
            ));
        });
        ui.horizontal_wrapped(|ui| {
            match probe.hit {
                Some(hit) => {
                    let names = match hit.at {
                        At::Parallelogram { .. } => ("α", "β"),
                        At::Triangle { .. } => ("β", "γ"),
                    };
                    let [first, second] = hit.coordinates();
                    ui.label(
                        RichText::new(format!(
                            "hit {}: t = {:.6}, {} = {:.6}, {} = {:.6}",
                            self.hit_object_text(&hit),
                            hit.t,
                            names.0,
                            first,
                            names.1,
                            second
                        ))
                        .color(palette::INSIDE.readable(ui)),
                    );
                    if let Some(facing) = probe.facing {
                        ui.label(format!("facing ratio n̂·(−ê) = {facing:.4}"));
                    }
                    let [r, g, b] = probe
                        .color
                        .map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
                    ui.label(format!("colour ({r}, {g}, {b})"));
                    let (rect, _) = ui.allocate_exact_size(Vec2::splat(16.0), Sense::hover());
                    ui.painter()
                        .rect_filled(rect, 2.0, Color32::from_rgb(r, g, b));
                }
                None => {
                    let text = match probe.nearest_miss {
                        Some((object, triangle)) => format!(
                            "missed everything; the nearest is object {} triangle {triangle}: \
                             the step panel says why",
                            object + 1
                        ),
                        None => "missed everything: no triangle to show".into(),
                    };
                    ui.label(RichText::new(text).color(palette::OUTSIDE.readable(ui)));
                }
            }
            let target = match probe.triangle {
                Some(_) => Some(super::ViewKind::Triangle),
                None if probe.hit.is_some() => Some(super::ViewKind::Parallelogram),
                None => None,
            };
            if let Some(kind) = target
                && ui
                    .button(format!("Open in {} →", kind.label()))
                    .on_hover_text("The same ray and primitive, with sliders and every step")
                    .clicked()
            {
                action = Some(Action::Open(kind));
            }
        });
        // After a ray of the tree was opened, the view holds that ray: load the primary again.
        if action.is_some()
            && self.runtime.opened.is_some()
            && let Ok(prepared) = self.prepared(None)
            && let Some(problem) = probed_problem(&prepared, probe)
        {
            self.runtime.opened = None;
            return Some(self.load_problem(problem));
        }
        action
    }

    pub(super) fn object_kind(&self, index: usize) -> &'static str {
        match self.scene.objects.get(index).map(|o| &o.shape) {
            Some(crate::scene::render::Shape::Triangle { .. }) => "triangle",
            Some(crate::scene::render::Shape::Parallelogram { .. }) => "parallelogram",
            Some(crate::scene::render::Shape::Mesh { .. }) => "mesh",
            None => "?",
        }
    }
}

/// "Pixel (row 3, column 4)": a bare "(3, 4)" reads as x and y, and the pixel is (row, column).
fn pixel_name((row, column): (usize, usize)) -> String {
    format!("Pixel (row {row}, column {column})")
}

/// The problem a probe loads into a view: the ray with the triangle it hit or came nearest to, or the
/// parallelogram it hit (in world space: a corner is a point, edges are directions).
pub(super) fn probed_problem(prepared: &Prepared, result: &Probe) -> Option<Action> {
    if let Some([a, b, c]) = result.triangle {
        return Some(Action::Triangle(TriangleScene {
            a,
            b,
            c,
            origin: result.origin,
            dir: result.dir,
            t_min: 0.0,
        }));
    }
    problem_of(prepared, Ray::new(result.origin, result.dir), result.hit?)
}

/// The ray with the triangle or parallelogram it hit, in world space.
fn problem_of(prepared: &Prepared, Ray { origin, dir }: Ray, hit: Hit) -> Option<Action> {
    let object = prepared.objects.get(hit.object)?;
    if let Some([a, b, c]) = crate::render::world_triangle(object, hit.primitive) {
        return Some(Action::Triangle(TriangleScene {
            a,
            b,
            c,
            origin,
            dir,
            t_min: 0.0,
        }));
    }
    let Geometry::Parallelogram { corner, e1, e2, .. } = &object.geometry else {
        return None;
    };
    let m = object.world_from_object;
    Some(Action::Parallelogram(ParallelogramScene {
        corner: m.transform_point3(DVec3::from(*corner)).to_array(),
        e1: m.transform_vector3(DVec3::from(*e1)).to_array(),
        e2: m.transform_vector3(DVec3::from(*e2)).to_array(),
        origin,
        dir,
    }))
}

/// The view that shows a probed problem: the Parallelogram view for a parallelogram, else the
/// Triangle view.
pub(super) fn view_of(problem: &Action) -> super::ViewKind {
    match problem {
        Action::Parallelogram(_) => super::ViewKind::Parallelogram,
        _ => super::ViewKind::Triangle,
    }
}
