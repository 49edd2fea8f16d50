//! The web page's side of the platform: start the app on the page's canvas, show what went wrong on
//! the page itself (not only in the console), save a scene as a download, open one with the file
//! picker.
//!
//! The page is `assets/web/index.html`: a `<canvas id="raylab_canvas">` and a `<p id="raylab_status">`
//! that says "Loading…" until the app runs, and the error if it cannot.

use wasm_bindgen::JsCast as _;
use wasm_bindgen::prelude::*;

use super::{Inbox, Picked};
use crate::app::{Launch, RaylabApp};

/// The canvas the app draws on.
const CANVAS_ID: &str = "raylab_canvas";
/// The page's loading and error message.
const STATUS_ID: &str = "raylab_status";

fn document() -> Result<web_sys::Document, String> {
    web_sys::window()
        .and_then(|window| window.document())
        .ok_or_else(|| "no document: raylab must run in a web page".to_string())
}

/// A JavaScript error as text.
fn describe(value: &JsValue) -> String {
    value
        .as_string()
        .or_else(|| {
            value
                .dyn_ref::<js_sys::Error>()
                .map(|error| String::from(error.message()))
        })
        .unwrap_or_else(|| format!("{value:?}"))
}

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

async fn run(launch: Launch) -> Result<(), String> {
    let canvas = document()?
        .get_element_by_id(CANVAS_ID)
        .and_then(|element| element.dyn_into::<web_sys::HtmlCanvasElement>().ok())
        .ok_or_else(|| format!("the page has no <canvas id=\"{CANVAS_ID}\">"))?;
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
        .map_err(|error| describe(&error))?;
    save_on_the_way_out(&runner)?;
    hide_status();
    Ok(())
}

/// Saves the state when the tab is hidden or the page goes away: eframe saves every 30 s and on
/// `beforeunload`, which mobile browsers and closing tabs often never send.
fn save_on_the_way_out(runner: &eframe::WebRunner) -> Result<(), String> {
    let window: web_sys::EventTarget = web_sys::window().ok_or("no window")?.into();
    let page: web_sys::EventTarget = document()?.into();
    let listen = |target: &web_sys::EventTarget, event: &'static str| {
        runner
            .add_event_listener(target, event, |_: web_sys::Event, app| app.save())
            .map_err(|error| describe(&error))
    };
    listen(&window, "pagehide")?;
    listen(&page, "visibilitychange")
}

/// Offers `text` as a file download: a Blob behind a temporary link, clicked.
pub fn download(file_name: &str, text: &str) -> Result<(), String> {
    let parts = js_sys::Array::of1(&JsValue::from_str(text));
    let options = web_sys::BlobPropertyBag::new();
    options.set_type("text/plain;charset=utf-8");
    let blob = web_sys::Blob::new_with_str_sequence_and_options(&parts, &options)
        .map_err(|e| describe(&e))?;
    let url = web_sys::Url::create_object_url_with_blob(&blob).map_err(|e| describe(&e))?;
    let link: web_sys::HtmlAnchorElement = document()?
        .create_element("a")
        .map_err(|e| describe(&e))?
        .dyn_into()
        .map_err(|_| "not a link".to_string())?;
    link.set_href(&url);
    link.set_download(file_name);
    // In the page while it is clicked, as Firefox wants; the Blob's URL is left alone, because
    // revoking it at once can cancel the download there (a scene file is a few hundred bytes).
    let body = document()?.body().ok_or("the page has no body")?;
    body.append_child(&link).map_err(|e| describe(&e))?;
    link.click();
    let _ = body.remove_child(&link);
    Ok(())
}

/// Opens the browser's file picker; the chosen file's text is read asynchronously into `inbox`.
pub fn pick_file(accept: &str, inbox: &Inbox, wake: impl Fn() + 'static) -> Result<(), String> {
    let input: web_sys::HtmlInputElement = document()?
        .create_element("input")
        .map_err(|e| describe(&e))?
        .dyn_into()
        .map_err(|_| "not an input".to_string())?;
    input.set_type("file");
    input.set_accept(accept);
    let (inbox, chosen) = (inbox.clone(), input.clone());
    // Called once, when the user has chosen (a cancelled picker never calls it).
    let on_change = Closure::once_into_js(move || {
        let Some(file) = chosen.files().and_then(|files| files.get(0)) else {
            return;
        };
        wasm_bindgen_futures::spawn_local(async move {
            let name = file.name();
            let text: Picked = wasm_bindgen_futures::JsFuture::from(file.text())
                .await
                .map(|text| (name.clone(), text.as_string().unwrap_or_default()))
                .map_err(|error| format!("could not read {name}: {}", describe(&error)));
            inbox.put(text);
            wake();
        });
    });
    input.set_onchange(Some(on_change.unchecked_ref()));
    input.click();
    Ok(())
}
