//! The Render view's spaces: the probed ray and its object drawn in world space and in object space,
//! so a student sees what the inverse transform does to the ray.

use super::*;

impl RenderView {
    /// The probed ray and its object in world space and in object space, side by side.
    pub(super) fn spaces_ui(&mut self, ui: &mut Ui) {
        let Some(probe) = self.runtime.probe.clone() else {
            ui.label("Click a pixel in the image first (try the transformed-object preset): its ray and the triangle it meets are drawn here in both spaces.");
            return;
        };
        let Ok(prepared) = self.prepared(None) else {
            return;
        };
        let target = probe
            .hit
            .map(|h| (h.object, h.primitive))
            .or(probe.nearest_miss);
        let Some((index, primitive)) = target else {
            ui.label("The probed ray met no triangle: probe another pixel.");
            return;
        };
        let object = &prepared.objects[index];
        let object_vertices = match &object.geometry {
            Geometry::Triangles { triangles, .. } => triangles[primitive].vertices,
            Geometry::Parallelogram { corner, e1, e2, .. } => [
                *corner,
                crate::math::linalg::add(corner, e1),
                crate::math::linalg::add(corner, e2),
            ],
        };
        let world_vertices = object_vertices.map(|v| {
            object
                .world_from_object
                .transform_point3(DVec3::from(v))
                .to_array()
        });
        let mut stats = crate::render::Stats::default();
        let world_ray = crate::render::Ray::new(probe.origin, probe.dir);
        let crate::render::Ray {
            origin: object_origin,
            dir: object_dir,
        } = crate::render::cast::to_object_space(object, world_ray, None, &mut stats);
        let t = probe.hit.map(|h| h.t);
        let transformed = object.object_from_world.is_some();
        ui.label(if transformed {
            "The ray goes into object space as O' = M⁻¹O (a point) and D' = M⁻¹D (a direction, not normalised), so O' + tD' = M⁻¹(O + tD): the same t in both spaces."
        } else {
            "This object has no transform: object space is world space. Probe the stretched sphere of the transformed-object preset to see the two differ."
        });
        let half = (ui.available_width() - 12.0) / 2.0;
        let height = (ui.available_height() - 130.0).max(160.0);
        ui.horizontal_top(|ui| {
            for (title, vertices, origin, dir) in [
                ("World space", world_vertices, probe.origin, probe.dir),
                ("Object space", object_vertices, object_origin, object_dir),
            ] {
                ui.vertical(|ui| {
                    ui.set_width(half);
                    ui.label(RichText::new(title).strong());
                    // Each space solves its own problem (Cramer, f64, the t where the ray meets the
                    // plane): the t shown is not copied from the other side.
                    let own = crate::intersect::Method::Cramer.run(&crate::intersect::Case {
                        tri: vertices,
                        origin,
                        dir,
                    });
                    let t = own.values.filter(|_| t.is_some()).map(|[t, _, _]| t);
                    draw_space(ui, Vec2::new(half, height), vertices, origin, dir, t);
                    let v = |p: [f64; 3]| format!("({:.3}, {:.3}, {:.3})", p[0], p[1], p[2]);
                    ui.label(format!(
                        "origin {}, direction {} (|D| = {:.4})",
                        v(origin),
                        v(dir),
                        norm_f64(&dir)
                    ));
                    if let Some(t) = t {
                        let point = add(&origin, &scale(&t, &dir));
                        ui.label(format!("t = {t:.6}, hit point {}", v(point)));
                    }
                });
            }
        });
        if let Some(t) = t
            && transformed
        {
            ui.label(
                RichText::new(format!(
                    "Normalising D' would make the object-space t read t·|D'| = {:.6} instead of {t:.6}: the bug \"normalising D in object space\".",
                    t * norm_f64(&object_dir)
                ))
                .color(palette::OUTSIDE.readable(ui)),
            );
        }
    }
}

/// A small 3D drawing framed on the triangle: the triangle, the ray towards it, and the hit at t.
pub(super) fn draw_space(
    ui: &mut Ui,
    size: Vec2,
    vertices: [[f64; 3]; 3],
    origin: [f64; 3],
    dir: [f64; 3],
    t: Option<f64>,
) {
    let (response, painter) = ui.allocate_painter(size, Sense::hover());
    let (o, d) = (DVec3::from(origin), DVec3::from(dir));
    // A mesh's triangle is small beside the ray: draw around the hit, scaled so the triangle fills
    // the canvas (only the picture is scaled; the numbers below it are the real ones).
    let center = o + d * t.unwrap_or(0.0);
    let size_of = vertices
        .iter()
        .map(|v| (DVec3::from(*v) - center).length())
        .fold(1e-300, f64::max);
    let local = |p: DVec3| (p - center) / size_of * 2.0;
    let [a, b, c] = vertices.map(|v| local(DVec3::from(v)));
    let hit = DVec3::ZERO;
    let framed = [a, b, c, hit];
    let camera = OrbitCamera::framing(&framed).across(d, Some((b - a).cross(c - a)));
    let projector = camera.projector(response.rect);
    let canvas = Canvas {
        painter: &painter,
        projector: &projector,
    };
    canvas.polygon(
        &[a, b, c],
        palette::faded(palette::BETA, 90),
        Stroke::new(2.0, palette::BETA),
    );
    // Labels go through the label pass: they avoid each other, the hit dot and the canvas edge.
    let mut labels = LabelLayer::new(response.rect);
    for (p, name) in [(a, "A"), (b, "B"), (c, "C")] {
        if let Some(at) = canvas.dot(p, 3.5, palette::BETA) {
            labels.avoid_point(at, 4.0);
        }
        canvas.place_label(&mut labels, p, name, palette::BETA, Priority::Normal);
    }
    // The ray from well before the triangle to a little past it (the scaled triangle reaches 2 from
    // the hit), its direction drawn where it comes in.
    let step = d.normalize_or_zero() * 4.0;
    canvas.line(hit - step, hit + step * 0.5, Stroke::new(2.0, palette::RAY));
    canvas.arrow(
        hit - step,
        hit - step + step * 0.4,
        Stroke::new(3.0, palette::RAY),
    );
    canvas.place_label(
        &mut labels,
        hit - step,
        "ray",
        palette::RAY,
        Priority::Minor,
    );
    if let Some(t) = t {
        if let Some(at) = canvas.dot(hit, 6.0, palette::SOLUTION) {
            labels.avoid_point(at, 7.0);
        }
        let text = format!("t = {t:.4}");
        canvas.place_label(&mut labels, hit, text, palette::SOLUTION, Priority::Key);
    }
    labels.paint(ui, &painter, response.id.with("space-labels"));
}
