//! What a 3D lecture view's canvas remembers between frames: the orbit camera (saved), and the
//! framing, projection and labels of the last frame (not saved). The Triangle and Parallelogram views
//! each hold one; a new 3D view takes one too instead of copying these fields.

use egui::{Rect, Vec2};
use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::labels::PlacedLabel;
use super::scene3d::{OrbitCamera, Projector};

/// The state of a 3D canvas. It is saved as its camera alone (`camera: (yaw: …, …)` in a view's saved
/// state, as before it had a struct of its own), so saved states read the same either way.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(from = "OrbitCamera", into = "OrbitCamera")]
pub struct CanvasState {
    /// The camera.
    pub camera: OrbitCamera,
    /// Keep the camera framing the scene to fill the canvas (on load, resize and zoom) until the
    /// user orbits or zooms it themselves.
    pub auto_frame: bool,
    /// The canvas size the camera was last framed for.
    framed_for: Option<(Vec2, f32)>,
    /// The last frame's projection (tests use it to find handles on screen).
    pub projector: Option<Projector>,
    /// Where each label went last frame (tests read it).
    pub labels: Vec<PlacedLabel>,
}

impl Default for CanvasState {
    fn default() -> CanvasState {
        CanvasState::from(OrbitCamera::default())
    }
}

impl From<OrbitCamera> for CanvasState {
    fn from(camera: OrbitCamera) -> CanvasState {
        CanvasState {
            camera,
            auto_frame: true,
            framed_for: None,
            projector: None,
            labels: Vec::new(),
        }
    }
}

impl From<CanvasState> for OrbitCamera {
    fn from(canvas: CanvasState) -> OrbitCamera {
        canvas.camera
    }
}

impl CanvasState {
    /// Starts again from `camera` (a scene was loaded, or "Reset view"): the canvas frames the scene
    /// again on its next frame.
    pub fn reset(&mut self, camera: OrbitCamera) {
        self.camera = camera;
        self.auto_frame = true;
        self.framed_for = None;
    }

    /// Orbits by a drag and stops framing the scene on its own (the user holds the camera now).
    pub fn orbit(&mut self, drag: Vec2) {
        self.camera.orbit(drag);
        self.auto_frame = false;
    }

    /// Zooms by the pointer's scroll over `response`, if any, and then stops framing on its own.
    pub fn zoom_on_scroll(&mut self, ui: &egui::Ui, response: &egui::Response) {
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.camera.zoom(scroll);
                self.auto_frame = false;
            }
        }
    }

    /// Orbits and zooms by the keys pressed on the focused canvas (an arrow turns as a 30-point drag
    /// does, + and − zoom as a wheel notch).
    pub fn orbit_by_keys(&mut self, keys: super::handles::CanvasKeys) {
        if keys == super::handles::CanvasKeys::default() {
            return;
        }
        self.camera
            .orbit(egui::vec2(keys.right * 30.0, keys.up * 30.0));
        self.camera.zoom(keys.zoom * 60.0);
        self.auto_frame = false;
    }

    /// The projection for this frame's canvas `rect`. While framing on its own, the camera is first
    /// fitted to `points` whenever the canvas has a new size, below the top `reserved` points (the
    /// verdict box); both are only worked out then.
    pub fn projector_for(
        &mut self,
        rect: Rect,
        points: impl FnOnce() -> Vec<DVec3>,
        reserved: impl FnOnce() -> f32,
    ) -> Projector {
        if !self.auto_frame {
            return self.camera.projector(rect);
        }
        // Framed again when the verdict's height changes too: a scene's first frame may still
        // carry the last scene's one-row verdict, and a vertex then sat under its two rows.
        let reserved = reserved();
        let framed_for = (rect.size(), reserved);
        if self.framed_for != Some(framed_for) {
            let points = points();
            self.camera = self.camera.clone().fitted_to(&points, rect, reserved);
            self.framed_for = Some(framed_for);
        }
        self.camera.projector(rect)
    }

    /// Where a world point was drawn last frame.
    pub fn screen_from_world(&self, p: DVec3) -> Option<egui::Pos2> {
        self.projector.as_ref()?.screen_from_world(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The canvas is saved as its camera alone, as the views saved `camera` before it existed, so a
    /// saved view reads the same either way; reading it back frames the scene again.
    #[test]
    fn a_canvas_saves_as_its_camera() {
        let camera = OrbitCamera {
            yaw: 0.25,
            ..OrbitCamera::default()
        };
        let mut canvas = CanvasState::from(camera.clone());
        canvas.auto_frame = false;
        let saved = ron::to_string(&canvas).unwrap();
        assert_eq!(saved, ron::to_string(&camera).unwrap());
        let read: CanvasState = ron::from_str(&saved).unwrap();
        assert_eq!(read.camera, camera);
        assert!(read.auto_frame && read.projector.is_none());
    }

    /// Framing happens once per canvas size, and not after the user orbits.
    #[test]
    fn the_camera_is_fitted_once_per_size_until_the_user_orbits() {
        let mut canvas = CanvasState::default();
        let rect = Rect::from_min_size(egui::Pos2::ZERO, Vec2::new(400.0, 300.0));
        let points = || vec![DVec3::ZERO, DVec3::X * 10.0];
        canvas.projector_for(rect, points, || 0.0);
        let fitted = canvas.camera.clone();
        assert_ne!(fitted, OrbitCamera::default());
        let mut asked = false;
        canvas.projector_for(
            rect,
            || {
                asked = true;
                points()
            },
            || 0.0,
        );
        assert!(!asked, "the same size is not framed again");
        canvas.orbit(Vec2::new(10.0, 0.0));
        let bigger = rect.expand(50.0);
        let orbited = canvas.camera.clone();
        canvas.projector_for(bigger, points, || 0.0);
        assert_eq!(canvas.camera, orbited, "an orbited camera is the user's");
        canvas.reset(fitted.clone());
        canvas.projector_for(bigger, points, || 0.0);
        assert_ne!(canvas.camera, fitted, "a reset canvas frames again");
    }
}
