//! How the app starts: in a desktop window ([`open_window`], from the command line) or on a web page's
//! canvas ([`start`], the wasm build's `main`). Everything below the app is free of both.

use super::RaylabApp;

/// What to open on start, over the remembered state: a web page's `?preset=<file stem>&view=<name>`
/// (`?preset=triangle-outside`, `?view=accuracy`) or `?lesson=<file stem>`, so a course page can link
/// straight to an example or a lecture; on the desktop, `raylab --lesson NAME`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Launch {
    /// A built-in scene by its file name without `.ron`.
    pub preset: Option<String>,
    /// A view by [`ViewKind::name`] (applied after the preset).
    pub view: Option<String>,
    /// A built-in lesson by its file name without `.ron`, played from its first slide.
    pub lesson: Option<String>,
}

impl Launch {
    /// Reads a URL's query string (with or without its `?`); unknown keys are ignored.
    pub fn from_query(query: &str) -> Launch {
        let mut launch = Launch::default();
        for pair in query.trim_start_matches('?').split('&') {
            let (key, value) = pair.split_once('=').unwrap_or((pair, ""));
            let value = value.trim();
            if value.is_empty() {
                continue;
            }
            match key {
                "preset" => launch.preset = Some(value.into()),
                "view" => launch.view = Some(value.to_ascii_lowercase()),
                "lesson" => launch.lesson = Some(value.into()),
                _ => {}
            }
        }
        launch
    }
}

/// Opens the app in a desktop window (1280x800, the projector size), opening what `launch` asks for.
#[cfg(not(target_arch = "wasm32"))]
pub fn open_window(launch: Launch) -> eframe::Result {
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("raylab")
            .with_inner_size([1280.0, 800.0])
            .with_min_inner_size([640.0, 420.0]),
        ..Default::default()
    };
    eframe::run_native(
        "raylab",
        options,
        Box::new(move |cc| {
            let mut app = RaylabApp::from_creation_context(cc);
            app.launch(&launch);
            Ok(Box::new(app))
        }),
    )
}

#[cfg(target_arch = "wasm32")]
pub use web::start;

/// The web page: `assets/web/index.html`, a `<canvas id="raylab_canvas">` and a `<p id="raylab_status">`
/// that says "Loading…" until the app runs, and the error if it cannot.
#[cfg(target_arch = "wasm32")]
mod web {
    use wasm_bindgen::JsCast as _;

    use super::{Launch, RaylabApp};
    use crate::platform::PlatformError;
    use crate::platform::web::{document, refused};

    /// The canvas the app draws on.
    const CANVAS_ID: &str = "raylab_canvas";
    /// The page's loading and error message.
    const STATUS_ID: &str = "raylab_status";

    /// Shows `message` in the page's status line, as an error (the canvas is hidden, so the page is not
    /// blank or frozen).
    fn show_error(message: &str) {
        let Ok(document) = document() else {
            return;
        };
        if let Some(status) = document.get_element_by_id(STATUS_ID) {
            status.set_text_content(Some(message));
            let _ = status.set_attribute("class", "error");
        }
        if let Some(canvas) = document.get_element_by_id(CANVAS_ID) {
            let _ = canvas.set_attribute("hidden", "");
        }
    }

    /// Hides the loading message once the app runs.
    fn hide_status() {
        if let Ok(document) = document()
            && let Some(status) = document.get_element_by_id(STATUS_ID)
        {
            let _ = status.set_attribute("hidden", "");
        }
    }

    /// The page's query string (`?preset=…&view=…`), which says what to open first.
    fn query() -> String {
        web_sys::window()
            .and_then(|window| window.location().search().ok())
            .unwrap_or_default()
    }

    /// The web entry point (`main` of the wasm build): starts the app on the page's canvas.
    pub fn start() {
        // A panic shows on the page. eframe's own panic handler, installed by WebRunner::new, logs it to
        // the console and then calls this one.
        std::panic::set_hook(Box::new(|info| {
            show_error(&format!("raylab stopped with an error: {info}"))
        }));
        eframe::WebLogger::init(log::LevelFilter::Warn).ok();
        let launch = Launch::from_query(&query());
        wasm_bindgen_futures::spawn_local(async move {
            if let Err(error) = run(launch).await {
                show_error(&format!("raylab could not start: {error}"));
            }
        });
    }

    async fn run(launch: Launch) -> Result<(), PlatformError> {
        let canvas = document()?
            .get_element_by_id(CANVAS_ID)
            .and_then(|element| element.dyn_into::<web_sys::HtmlCanvasElement>().ok())
            .ok_or_else(|| {
                PlatformError::Page(format!("the page has no <canvas id=\"{CANVAS_ID}\">"))
            })?;
        let runner = eframe::WebRunner::new();
        runner
            .start(
                canvas,
                eframe::WebOptions::default(),
                Box::new(move |cc| {
                    let mut app = RaylabApp::from_creation_context(cc);
                    app.launch(&launch);
                    Ok(Box::new(app))
                }),
            )
            .await
            .map_err(|error| refused(&error))?;
        save_on_the_way_out(&runner)?;
        hide_status();
        Ok(())
    }

    /// Saves the state when the tab is hidden or the page goes away: eframe saves every 30 s and on
    /// `beforeunload`, which mobile browsers and closing tabs often never send.
    fn save_on_the_way_out(runner: &eframe::WebRunner) -> Result<(), PlatformError> {
        let window: web_sys::EventTarget = web_sys::window()
            .ok_or_else(|| PlatformError::Page("no window".into()))?
            .into();
        let page: web_sys::EventTarget = document()?.into();
        let listen = |target: &web_sys::EventTarget, event: &'static str| {
            runner
                .add_event_listener(target, event, |_: web_sys::Event, app| app.save())
                .map_err(|error| refused(&error))
        };
        listen(&window, "pagehide")?;
        listen(&page, "visibilitychange")
    }
}
