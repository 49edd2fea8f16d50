//! Steps the kittest tests and the screenshots share: waiting for a render, clicking into an image.

use egui::Vec2;
use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use raylab::app::RaylabApp;
use raylab::app::render_view::RenderView;
use raylab::app::view::View;

/// The app in a 1280x800 window (the projector size) with its own style.
#[allow(
    dead_code,
    reason = "the screenshot and projector tests build their own sizes and themes"
)]
pub fn app_harness() -> Harness<'static, RaylabApp> {
    Harness::builder()
        .with_size(Vec2::new(1280.0, 800.0))
        .with_max_steps(200)
        .build_eframe(|cc| {
            raylab::app::set_style(&cc.egui_ctx);
            RaylabApp::new()
        })
}

/// [`app_harness`] with a preset loaded (see [`load_preset`]).
#[allow(
    dead_code,
    reason = "the screenshot and projector tests build their own sizes and themes"
)]
pub fn app_at(preset: &str) -> Harness<'static, RaylabApp> {
    let mut harness = app_harness();
    load_preset(&mut harness, preset);
    harness
}

/// Steps frames until the Render view's renders are done (they run on a worker thread): one frame
/// for the click, one for the view to start its render, then until it has finished.
pub fn wait_for_render(harness: &mut Harness<'static, RaylabApp>) {
    harness.step();
    harness.step();
    step_while(harness, 10, "the render did not finish", |h| {
        h.state().state.get::<RenderView>().is_rendering()
    });
}

/// Steps frames `pause_ms` apart while `busy` holds (work on a worker thread, or a text not shown
/// yet), then runs the app to rest; fails with `failure` after two minutes.
pub fn step_while(
    harness: &mut Harness<'static, RaylabApp>,
    pause_ms: u64,
    failure: &str,
    busy: impl Fn(&Harness<'static, RaylabApp>) -> bool,
) {
    let started = std::time::Instant::now();
    while busy(harness) {
        assert!(started.elapsed().as_secs() < 120, "{failure}");
        std::thread::sleep(std::time::Duration::from_millis(pause_ms));
        harness.step();
    }
    harness.run();
}

/// Presses each key in turn, the app running after each, as a presentation clicker sends them.
#[allow(
    dead_code,
    reason = "not every test crate that includes common presses keys"
)]
pub fn press(harness: &mut Harness<'static, RaylabApp>, keys: impl IntoIterator<Item = egui::Key>) {
    for key in keys {
        harness.key_press(key);
        harness.run();
    }
}

/// Presses and releases the mouse on the image with this label, at a fraction of its size.
pub fn click_image(harness: &mut Harness<'static, RaylabApp>, label: &str, at: Vec2) {
    let rect = harness.get_by_label(label).rect();
    let point = rect.min + rect.size() * at;
    harness.hover_at(point);
    harness.run();
    harness.drag_at(point);
    harness.step();
    harness.drop_at(point);
    harness.run();
}

/// Loads a preset through the Presets menu, by its title; a render preset's render is waited for.
pub fn load_preset(harness: &mut Harness<'static, RaylabApp>, title: &str) {
    harness.get_by_label("Presets").click();
    harness.run();
    // The list scrolls on a small or zoomed screen: bring the preset into view first.
    harness
        .get_by_role_and_label(Role::Button, title)
        .scroll_to_me();
    harness.run();
    harness.get_by_role_and_label(Role::Button, title).click();
    wait_for_render(harness);
}

/// The "Highlighted: …" line of presentation mode and lessons, as a screen reader reads it.
pub fn highlighted(harness: &Harness<'static, RaylabApp>) -> String {
    harness
        .query_all_by(|node| {
            node.value()
                .is_some_and(|text| text.starts_with("Highlighted:"))
        })
        .next()
        .and_then(|node| node.accesskit_node().value())
        .unwrap_or_default()
}

/// Opens the Accuracy view and starts a study of `rays` rays a family (`shared_rays` for the shared
/// families), seeded, timing each method for `timing_seconds`.
#[allow(dead_code, reason = "only the test crates that run a study use it")]
pub fn start_study(
    harness: &mut Harness<'static, RaylabApp>,
    [rays, shared_rays]: [usize; 2],
    seed: u64,
    timing_seconds: f64,
) {
    harness
        .state_mut()
        .state
        .get_mut::<raylab::app::accuracy_view::AccuracyView>()
        .config_override = Some(raylab::accuracy::study::Config {
        rays,
        shared_rays,
        seed,
        timing_seconds,
    });
    harness.get_by_label("Accuracy").click();
    harness.run();
    harness.get_by_label("Run").click();
    harness.step();
}

/// True if some widget's label or value contains `text`.
#[allow(
    dead_code,
    reason = "not every test crate that includes common reads text"
)]
pub fn shows_text_containing(harness: &Harness<'static, RaylabApp>, text: &str) -> bool {
    harness
        .query_all_by(|node| {
            node.label().is_some_and(|l| l.contains(text))
                || node.value().is_some_and(|v| v.contains(text))
        })
        .next()
        .is_some()
}

/// The app's view of a type.
pub fn app_view<'a, V: View>(harness: &'a Harness<'static, RaylabApp>) -> &'a V {
    harness.state().state.get::<V>()
}

/// Picks a bug in the Render view's "Compare with a bug:" box, by its name, and waits for both
/// images.
#[allow(
    dead_code,
    reason = "not every test crate that includes common picks a bug"
)]
pub fn pick_bug(harness: &mut Harness<'static, RaylabApp>, bug: &str) {
    harness.get_by_label("Compare with a bug:").click();
    harness.run();
    harness.get_by_role_and_label(Role::Button, bug).click();
    wait_for_render(harness);
}

/// Presses the mouse on the centre of the image with this label and keeps it down (a drag
/// begins); returns where.
#[allow(
    dead_code,
    reason = "not every test crate that includes common drags an image"
)]
pub fn press_on_image(harness: &mut Harness<'static, RaylabApp>, label: &str) -> egui::Pos2 {
    let centre = harness.get_by_label(label).rect().center();
    harness.hover_at(centre);
    harness.run();
    harness.drag_at(centre);
    harness.step();
    centre
}

/// The exact answer to the practice problem on screen.
#[allow(
    dead_code,
    reason = "only the test crates that answer practice problems use it"
)]
pub fn practice_answer<'a>(
    harness: &'a Harness<'static, RaylabApp>,
) -> &'a raylab::exercise::Answer {
    &harness
        .state()
        .practice
        .as_ref()
        .expect("a practice problem is open")
        .practice
        .problem
        .answer
}
