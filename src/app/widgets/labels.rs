//! One label-placement pass for the 2D and 3D canvases, so labels never overprint each other.
//!
//! A view asks for labels (an anchor on screen, a text, a priority) and says what they must keep clear
//! of (handles, the verdict box) and would rather not cross (the legs, the ray). [`LabelLayer::paint`]
//! then places the labels in priority order: each tries a few candidate positions around its anchor,
//! nearest first, and takes the cheapest one that stays inside the canvas and clear of every label
//! already placed and every obstacle. A label moved away from its anchor gets a thin leader line; a
//! label with no free place is dropped rather than drawn over another. Each placed label is also a
//! node in the accessibility tree (role Label, its text and rectangle), so tests and screen readers
//! see what the canvas shows.

use egui::{Color32, FontId, Id, Painter, Pos2, Rect, Stroke, Ui, Vec2, pos2, vec2};

/// How important a label is: more important labels are placed first and keep their best place.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Priority {
    /// The names of the problem's points (A, B, C, L, P): a student must always find them.
    Key,
    /// Labels of derived things (D, a hit, a miss reason).
    Normal,
    /// Axis names and grid numbers: dropped first.
    Minor,
}

/// Where a label may go relative to its anchor.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Placement {
    /// Around the anchor, at increasing distances.
    Around,
    /// Exactly here (grid numbers): placed if free, else dropped.
    Fixed(egui::Align2),
}

#[derive(Clone, Debug)]
struct Request {
    anchor: Pos2,
    text: String,
    color: Color32,
    font: FontId,
    priority: Priority,
    placement: Placement,
    /// Radius around the anchor kept clear (the handle drawn there).
    clearance: f32,
}

/// A label where the pass put it.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedLabel {
    /// The text.
    pub text: String,
    /// Its rectangle on screen.
    pub rect: Rect,
    /// The point it names.
    pub anchor: Pos2,
    /// True when it was moved off its nearest place and drawn with a leader line.
    pub moved: bool,
}

/// Collects a canvas's labels and obstacles for one frame; see the module comment.
pub struct LabelLayer {
    bounds: Rect,
    obstacles: Vec<Rect>,
    guides: Vec<[Pos2; 2]>,
    requests: Vec<Request>,
}

/// Distances (points) from the anchor's clearance circle to the label, nearest first.
const RINGS: [f32; 4] = [3.0, 14.0, 28.0, 46.0];

/// Directions tried on each ring, in order of preference: up-right first, as labels usually sit.
const DIRECTIONS: [Vec2; 8] = [
    vec2(1.0, -1.0),
    vec2(-1.0, -1.0),
    vec2(1.0, 1.0),
    vec2(-1.0, 1.0),
    vec2(1.0, 0.0),
    vec2(-1.0, 0.0),
    vec2(0.0, -1.0),
    vec2(0.0, 1.0),
];

/// Space kept between two labels.
const GAP: f32 = 2.0;

impl LabelLayer {
    /// A layer for a canvas; labels stay inside `bounds`.
    pub fn new(bounds: Rect) -> LabelLayer {
        LabelLayer {
            bounds,
            obstacles: Vec::new(),
            guides: Vec::new(),
            requests: Vec::new(),
        }
    }

    /// A rectangle no label may cover (the verdict box).
    pub fn avoid(&mut self, rect: Rect) {
        self.obstacles.push(rect);
    }

    /// A handle or dot of this radius that no label may cover.
    pub fn avoid_point(&mut self, at: Pos2, radius: f32) {
        if at.x.is_finite() && at.y.is_finite() {
            self.obstacles
                .push(Rect::from_center_size(at, Vec2::splat(2.0 * radius)));
        }
    }

    /// A line labels would rather not cross (a leg, the ray): crossing costs, but is allowed.
    pub fn prefer_clear_of(&mut self, a: Pos2, b: Pos2) {
        if a.x.is_finite() && a.y.is_finite() && b.x.is_finite() && b.y.is_finite() {
            self.guides.push([a, b]);
        }
    }

    /// A label next to `anchor`, which has a handle of radius `clearance` drawn on it.
    pub fn add(
        &mut self,
        anchor: Pos2,
        text: impl Into<String>,
        color: Color32,
        font: FontId,
        priority: Priority,
        clearance: f32,
    ) {
        self.requests.push(Request {
            anchor,
            text: text.into(),
            color,
            font,
            priority,
            placement: Placement::Around,
            clearance,
        });
    }

    /// A label at exactly this position and alignment (a grid number), dropped if it is not free.
    pub fn add_fixed(
        &mut self,
        at: Pos2,
        align: egui::Align2,
        text: impl Into<String>,
        color: Color32,
        font: FontId,
    ) {
        self.requests.push(Request {
            anchor: at,
            text: text.into(),
            color,
            font,
            priority: Priority::Minor,
            placement: Placement::Fixed(align),
            clearance: 0.0,
        });
    }

    /// Places every label, paints the placed ones (on a faint backing, so lines under them do not
    /// hide them), and names them in the accessibility tree. Returns where they went.
    pub fn paint(self, ui: &Ui, painter: &Painter, id: Id) -> Vec<PlacedLabel> {
        let backing = ui.visuals().extreme_bg_color.gamma_multiply(0.7);
        let mut requests = self.requests.clone();
        // Stable: among equals, the order the view asked in.
        requests.sort_by_key(|r| r.priority);
        let mut taken: Vec<Rect> = Vec::new();
        let mut placed = Vec::new();
        for request in requests {
            if !(request.anchor.x.is_finite() && request.anchor.y.is_finite()) {
                continue;
            }
            let ink = super::palette::ink(request.color, ui.visuals());
            let galley = painter.layout_no_wrap(request.text.clone(), request.font.clone(), ink);
            let size = galley.size();
            let Some((rect, moved)) = self.best_place(&request, size, &taken) else {
                continue;
            };
            if moved {
                let end = closest_point(rect, request.anchor);
                let start = request.anchor
                    + (end - request.anchor).normalized() * (request.clearance + 1.0);
                painter.line_segment([start, end], Stroke::new(1.0, request.color));
            }
            painter.rect_filled(rect.expand(1.0), 3.0, backing);
            painter.galley(rect.min, galley, ink);
            taken.push(rect);
            placed.push(PlacedLabel {
                text: request.text,
                rect,
                anchor: request.anchor,
                moved,
            });
        }
        for (index, label) in placed.iter().enumerate() {
            describe(ui, id.with(index), label);
        }
        placed
    }

    /// The cheapest free rectangle for a label of this size, and whether it is off its nearest ring.
    fn best_place(&self, request: &Request, size: Vec2, taken: &[Rect]) -> Option<(Rect, bool)> {
        let inside = self.bounds.shrink(2.0);
        let free = |rect: Rect| {
            inside.contains_rect(rect)
                && !taken.iter().any(|t| t.expand(GAP).intersects(rect))
                && !self.obstacles.iter().any(|o| o.intersects(rect))
        };
        if let Placement::Fixed(align) = request.placement {
            let rect = align.anchor_size(request.anchor, size);
            return free(rect).then_some((rect, false));
        }
        let mut best: Option<(f32, Rect, bool)> = None;
        for (ring, distance) in RINGS.iter().enumerate() {
            for (rank, direction) in DIRECTIONS.iter().enumerate() {
                let rect = rect_beside(
                    request.anchor,
                    *direction,
                    request.clearance + distance,
                    size,
                );
                if !free(rect) {
                    continue;
                }
                let crossings = self
                    .guides
                    .iter()
                    .filter(|[a, b]| segment_hits_rect(*a, *b, rect))
                    .count();
                // Off the nearest ring a leader line joins it to its anchor: a line through
                // another label reads as that label's.
                let leader_crossings = if ring >= 1 {
                    let end = closest_point(rect, request.anchor);
                    taken
                        .iter()
                        .filter(|t| segment_hits_rect(request.anchor, end, **t))
                        .count()
                } else {
                    0
                };
                let cost = ring as f32 * 4.0
                    + rank as f32 * 0.5
                    + (crossings + 2 * leader_crossings) as f32 * 5.0;
                if best.is_none_or(|(c, _, _)| cost < c) {
                    // Any ring past the nearest is far enough to need its line back to the anchor.
                    best = Some((cost, rect, ring >= 1));
                }
            }
            // A free place with no crossings on this ring beats anything further out.
            if best.is_some_and(|(cost, _, _)| cost < (ring as f32 + 1.0) * 4.0) {
                break;
            }
        }
        best.map(|(_, rect, moved)| (rect, moved))
    }
}

/// The rectangle of `size` beside `anchor` in `direction`, `distance` away from it (its nearest corner
/// or edge midpoint at that distance).
fn rect_beside(anchor: Pos2, direction: Vec2, distance: f32, size: Vec2) -> Rect {
    let offset = direction.normalized() * distance;
    let corner = anchor + offset;
    // Align the rectangle so it grows away from the anchor along each axis.
    let min_x = match direction.x {
        x if x > 0.0 => corner.x,
        x if x < 0.0 => corner.x - size.x,
        _ => corner.x - size.x / 2.0,
    };
    let min_y = match direction.y {
        y if y > 0.0 => corner.y,
        y if y < 0.0 => corner.y - size.y,
        _ => corner.y - size.y / 2.0,
    };
    Rect::from_min_size(pos2(min_x, min_y), size)
}

/// The point of `rect` nearest to `p`.
fn closest_point(rect: Rect, p: Pos2) -> Pos2 {
    pos2(
        p.x.clamp(rect.min.x, rect.max.x),
        p.y.clamp(rect.min.y, rect.max.y),
    )
}

/// True if segment a–b passes through the rectangle.
fn segment_hits_rect(a: Pos2, b: Pos2, rect: Rect) -> bool {
    super::scene3d::clip_to_rect(a, b, rect).is_some()
}

/// Names a placed label in the accessibility tree: role Label, its text, its rectangle.
fn describe(ui: &Ui, id: Id, label: &PlacedLabel) {
    ui.ctx().accesskit_node_builder(id, |node| {
        node.set_role(egui::accesskit::Role::Label);
        node.set_label(label.text.clone());
        node.set_bounds(egui::accesskit::Rect {
            x0: label.rect.min.x.into(),
            y0: label.rect.min.y.into(),
            x1: label.rect.max.x.into(),
            y1: label.rect.max.y.into(),
        });
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layer() -> LabelLayer {
        LabelLayer::new(Rect::from_min_size(Pos2::ZERO, vec2(400.0, 300.0)))
    }

    fn request(anchor: Pos2) -> Request {
        Request {
            anchor,
            text: "label".into(),
            color: Color32::WHITE,
            font: FontId::proportional(16.0),
            priority: Priority::Normal,
            placement: Placement::Around,
            clearance: 7.0,
        }
    }

    #[test]
    fn a_lone_label_sits_up_and_right_of_its_anchor() {
        let (rect, moved) = layer()
            .best_place(&request(pos2(200.0, 150.0)), vec2(40.0, 18.0), &[])
            .unwrap();
        assert!(!moved);
        assert!(rect.min.x > 200.0 && rect.max.y < 150.0, "{rect:?}");
    }

    #[test]
    fn a_second_label_at_the_same_anchor_moves_clear_of_the_first() {
        let layer = layer();
        let anchor = pos2(200.0, 150.0);
        let size = vec2(40.0, 18.0);
        let (first, _) = layer.best_place(&request(anchor), size, &[]).unwrap();
        let (second, _) = layer.best_place(&request(anchor), size, &[first]).unwrap();
        assert!(!first.expand(GAP).intersects(second));
    }

    /// With every place on the nearest ring taken, a label goes further out and is joined to its
    /// anchor by a leader line (on the second ring it was not, and read as nobody's label).
    #[test]
    fn a_label_off_its_nearest_ring_gets_a_leader_line() {
        let layer = layer();
        let anchor = pos2(200.0, 150.0);
        let size = vec2(40.0, 18.0);
        let asked = request(anchor);
        let nearest: Vec<Rect> = DIRECTIONS
            .iter()
            .map(|d| rect_beside(anchor, *d, asked.clearance + RINGS[0], size))
            .collect();
        let (rect, moved) = layer.best_place(&asked, size, &nearest).unwrap();
        assert!(moved, "{rect:?} has no leader line");
    }

    /// A leader line does not run through another label when a place without that is free (the
    /// parallelogram's "o + t d" had its line through "o" at 200%).
    #[test]
    fn a_leader_line_keeps_off_other_labels() {
        let mut layer = layer();
        let anchor = pos2(200.0, 150.0);
        let size = vec2(40.0, 18.0);
        let asked = request(anchor);
        // The nearest ring is blocked (by the drawing), and a label sits between the anchor and
        // the place it would take without one, straight above.
        for direction in DIRECTIONS {
            layer.avoid(rect_beside(
                anchor,
                direction,
                asked.clearance + RINGS[0],
                size,
            ));
        }
        let between = Rect::from_center_size(pos2(200.0, 125.0), vec2(4.0, 4.0));
        let (rect, moved) = layer.best_place(&asked, size, &[between]).unwrap();
        assert!(moved);
        let end = closest_point(rect, anchor);
        assert!(
            !segment_hits_rect(anchor, end, between),
            "{rect:?}: its leader crosses a label"
        );
    }

    #[test]
    fn labels_stay_inside_the_canvas_and_out_of_obstacles() {
        let mut layer = layer();
        // The verdict box covers the top-left corner; the anchor sits in it.
        layer.avoid(Rect::from_min_size(Pos2::ZERO, vec2(150.0, 40.0)));
        let (rect, _) = layer
            .best_place(&request(pos2(5.0, 5.0)), vec2(40.0, 18.0), &[])
            .unwrap();
        assert!(layer.bounds.contains_rect(rect));
        assert!(!rect.intersects(Rect::from_min_size(Pos2::ZERO, vec2(150.0, 40.0))));
    }

    #[test]
    fn a_label_with_no_free_place_is_dropped() {
        let mut layer = layer();
        layer.avoid(layer.bounds);
        assert!(
            layer
                .best_place(&request(pos2(200.0, 150.0)), vec2(40.0, 18.0), &[])
                .is_none()
        );
    }

    #[test]
    fn a_label_prefers_a_place_that_crosses_no_line() {
        let mut layer = layer();
        let anchor = pos2(200.0, 150.0);
        // A line through the up-right place.
        layer.prefer_clear_of(pos2(200.0, 130.0), pos2(400.0, 130.0));
        let (rect, _) = layer
            .best_place(&request(anchor), vec2(40.0, 18.0), &[])
            .unwrap();
        assert!(!segment_hits_rect(
            pos2(200.0, 130.0),
            pos2(400.0, 130.0),
            rect
        ));
    }
}
