//! The Render view's live camera: drag the image to orbit the scene's pinhole camera about its
//! target, Shift-drag to pan, scroll over the image to dolly, R (or the button) to go back to the
//! scene's camera. While the camera moves, quick frames follow it (1/n of the image's sides, one
//! sample a pixel, n chosen so that a frame takes about
//! [`QUICK_FRAME_SECONDS`](crate::render::QUICK_FRAME_SECONDS)); when it stops, the full image
//! renders. The scene keeps its own camera: the moved one is saved with the scene only when
//! the user saves it.

use std::collections::VecDeque;

use super::*;
use crate::scene::render::Camera;

/// The camera counts as moving this long after the last scroll.
const SETTLE_SECONDS: f64 = 0.3;
/// Radians of orbit per point dragged (as the 3D views turn).
const RADIANS_PER_POINT: f64 = 0.008;

/// The camera's motion and the frames shown while it moves.
#[derive(Default)]
pub(super) struct Orbit {
    /// A drag on the image is under way.
    dragging: bool,
    /// Until when (the app's clock) the camera counts as moving after a scroll.
    moving_until: f64,
    /// Whether it moved as of this frame.
    moving: bool,
    /// The next quick frame's divisor (0: not known yet).
    factor: u32,
    /// Frames shown since the view opened its scene, quick and full.
    pub(super) frames: u64,
    /// When the frames of the last second were shown.
    recent: VecDeque<f64>,
}

impl Orbit {
    /// Notes the clock at the start of a frame.
    pub(super) fn tick(&mut self, now: f64) {
        self.moving = self.dragging || now < self.moving_until;
    }

    /// The pointer is up: no drag goes on.
    pub(super) fn end_drag(&mut self) {
        self.dragging = false;
    }

    /// True while the camera moves (a drag, or a scroll a moment ago).
    pub(super) fn moving(&self) -> bool {
        self.moving
    }

    /// The next frame's quick-frame divisor, while the camera moves.
    pub(super) fn draft(&self) -> Option<u32> {
        self.moving
            .then_some(self.factor.max(crate::render::MIN_QUICK_DIVISOR))
    }

    /// Seconds until the camera counts as still, when a repaint must come then.
    pub(super) fn settles_in(&self, now: f64) -> Option<f64> {
        (!self.dragging && now < self.moving_until).then_some(self.moving_until - now + 0.01)
    }

    /// A frame (its quick-frame divisor and render seconds) was shown at `now`: the next quick
    /// frame's divisor follows it ([`crate::render::next_quick_divisor`]).
    pub(super) fn frame_shown(&mut self, (draft, seconds): (Option<u32>, f64), now: f64) {
        self.frames += 1;
        self.recent.push_back(now);
        while self.recent.front().is_some_and(|t| *t < now - 1.0) {
            self.recent.pop_front();
        }
        self.factor = crate::render::next_quick_divisor(draft, seconds);
    }

    /// Frames shown in the last second, while the camera moves.
    pub(super) fn frames_per_second(&self) -> Option<usize> {
        self.moving.then_some(self.recent.len())
    }
}

/// What the pointer did to an image this frame.
#[derive(Default)]
pub(super) struct Motion {
    /// Dragged by this many points (with Shift: a pan).
    drag: Vec2,
    pan: bool,
    /// Scrolled by this many points over the image.
    scroll: f32,
    /// A drag is under way.
    dragging: bool,
    /// The image's height on screen, in points.
    height: f32,
    /// Keys moved the camera (it counts as moving for a moment, as after a scroll).
    keyed: bool,
}

impl Motion {
    /// Reads the pointer on the image `response`; the scroll over it is taken (it dollies the
    /// camera, not the page) when the camera can move.
    pub(super) fn read(&mut self, ui: &Ui, response: &egui::Response, movable: bool) {
        if !movable {
            return;
        }
        self.height = response.rect.height().max(1.0);
        if response.dragged_by(egui::PointerButton::Primary) {
            self.dragging = true;
            self.drag += response.drag_delta();
            self.pan |= ui.input(|i| i.modifiers.shift);
        }
        if response.hovered() {
            self.scroll += ui.input_mut(|i| std::mem::take(&mut i.smooth_scroll_delta.y));
        }
        // The image focused (Tab): Ctrl + arrows pan (as a Shift-drag), the arrows orbit as a
        // 30-point drag, + and − dolly as a notch.
        if response.has_focus() {
            let moved =
                ui.input_mut(|i| crate::app::widgets::handles::arrows(i, egui::Modifiers::CTRL));
            // A drag down is a positive y; the up arrow is a positive y.
            let pan = Vec2::new(moved.x, -moved.y);
            if pan != Vec2::ZERO {
                self.drag += pan * 20.0;
                self.pan = true;
                self.keyed = true;
            }
        }
        let keys = crate::app::widgets::handles::focused_keys(ui, response);
        if keys != crate::app::widgets::handles::CanvasKeys::default() {
            self.drag += Vec2::new(keys.right, keys.up) * 30.0;
            self.scroll += keys.zoom * 60.0;
            self.keyed = true;
        }
    }
}

impl RenderView {
    /// The camera the view looks through: the one the user moved, else the scene's.
    pub fn view_camera(&self) -> Camera {
        self.camera
            .clone()
            .unwrap_or_else(|| self.scene.camera.clone())
    }

    /// True when the camera can move (a pinhole; seed 003's image plane stays).
    pub(super) fn camera_moves(&self) -> bool {
        self.scene.camera.orbit_angles().is_some()
    }

    /// Moves the camera by what the pointer did this frame.
    pub(super) fn apply_motion(&mut self, motion: Motion, now: f64) {
        let camera = self.view_camera();
        let orbit = &mut self.runtime.orbit;
        orbit.dragging = motion.dragging;
        let mut moved = camera.clone();
        if motion.drag != Vec2::ZERO {
            moved = if motion.pan {
                let (right, up) = (motion.drag / motion.height).into();
                moved.panned(-f64::from(right), f64::from(up))
            } else {
                moved.orbited(
                    -f64::from(motion.drag.x) * RADIANS_PER_POINT,
                    f64::from(motion.drag.y) * RADIANS_PER_POINT,
                )
            };
        }
        if motion.scroll != 0.0 {
            moved = moved.dollied((-f64::from(motion.scroll) * 0.002).exp());
        }
        if motion.scroll != 0.0 || motion.keyed {
            orbit.moving_until = now + SETTLE_SECONDS;
        }
        orbit.tick(now);
        if moved != camera {
            self.camera = Some(moved);
        }
    }

    /// Back to the scene's own camera.
    pub fn reset_camera(&mut self) {
        self.camera = None;
    }

    /// Turns the camera to look from `yaw` about z and `pitch` above the xy plane (radians), at its
    /// distance from the target (a lesson's slide).
    pub fn look_from(&mut self, yaw: f64, pitch: f64) {
        if let Some((distance, _, _)) = self.scene.camera.orbit_angles() {
            self.camera = Some(self.scene.camera.placed(distance, yaw, pitch));
        }
    }

    /// The "Reset camera" button (R), and how to move the camera.
    pub(super) fn camera_ui(&mut self, ui: &mut Ui) {
        if !self.camera_moves() {
            return;
        }
        let reset = ui
            .add_enabled(self.camera.is_some(), egui::Button::new("Reset camera"))
            .on_hover_text(
                "Back to the scene's own camera (R). Drag the image to orbit, Shift-drag to pan, \
                 scroll over it to move nearer or farther",
            )
            .on_disabled_hover_text(
                "The scene's own camera. Drag the image to orbit, Shift-drag to pan, scroll over \
                 it to move nearer or farther",
            )
            .clicked();
        // R, unless a text field takes the keys.
        let key = !ui.ctx().text_edit_focused()
            && ui.input_mut(|i| i.consume_key(egui::Modifiers::NONE, egui::Key::R));
        if reset || key {
            self.reset_camera();
        }
    }

    /// The frame counter and speed: the frame's number, the frames a second while the camera
    /// moves and the rays a second first (at 200% only the summary's first line shows under the
    /// image, and they are what changes live), then the frame's kind, size and time.
    pub(super) fn frame_summary(&self, rendered: &Rendered, draft: Option<u32>) -> String {
        let orbit = &self.runtime.orbit;
        let kind = match draft {
            Some(n) => format!(" (quick, 1/{n} size, one sample a pixel)"),
            None => String::new(),
        };
        let rays_per_second = if rendered.seconds > 0.0 {
            rendered.stats.all_rays() as f64 / rendered.seconds
        } else {
            0.0
        };
        let rate = match orbit.frames_per_second() {
            Some(1) => " 1 frame/s,".to_string(),
            Some(fps) => format!(" {fps} frames/s,"),
            None => String::new(),
        };
        format!(
            "Frame {}:{rate} {} rays/s, {}×{}{kind} in {:.1} ms",
            orbit.frames,
            crate::render::ray_kinds::short_count(rays_per_second),
            rendered.image.width,
            rendered.image.height,
            rendered.seconds * 1e3,
        )
    }
}
