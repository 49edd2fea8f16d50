//! The web page's side of the platform: save a scene as a download, open one with the file picker, and
//! the page's document and errors as the app's launcher ([`crate::app::launch`]) needs them.

use wasm_bindgen::JsCast as _;
use wasm_bindgen::prelude::*;

use super::{Inbox, Picked, PlatformError};

/// The page's document.
pub fn document() -> Result<web_sys::Document, PlatformError> {
    web_sys::window()
        .and_then(|window| window.document())
        .ok_or_else(|| PlatformError::Page("no document: raylab must run in a web page".into()))
}

/// A JavaScript error as the platform's error.
pub fn refused(value: &JsValue) -> PlatformError {
    PlatformError::Browser(describe(value))
}

/// A JavaScript error as text.
pub fn describe(value: &JsValue) -> String {
    value
        .as_string()
        .or_else(|| {
            value
                .dyn_ref::<js_sys::Error>()
                .map(|error| String::from(error.message()))
        })
        .unwrap_or_else(|| format!("{value:?}"))
}

/// Offers `text` as a file download: a Blob behind a temporary link, clicked.
pub fn download(file_name: &str, text: &str) -> Result<(), PlatformError> {
    let parts = js_sys::Array::of1(&JsValue::from_str(text));
    let options = web_sys::BlobPropertyBag::new();
    options.set_type("text/plain;charset=utf-8");
    let blob = web_sys::Blob::new_with_str_sequence_and_options(&parts, &options)
        .map_err(|e| refused(&e))?;
    let url = web_sys::Url::create_object_url_with_blob(&blob).map_err(|e| refused(&e))?;
    let link: web_sys::HtmlAnchorElement = document()?
        .create_element("a")
        .map_err(|e| refused(&e))?
        .dyn_into()
        .map_err(|_| PlatformError::Page("not a link".into()))?;
    link.set_href(&url);
    link.set_download(file_name);
    // In the page while it is clicked, as Firefox wants; the Blob's URL is left alone, because
    // revoking it at once can cancel the download there (a scene file is a few hundred bytes).
    let body = document()?
        .body()
        .ok_or_else(|| PlatformError::Page("the page has no body".into()))?;
    body.append_child(&link).map_err(|e| refused(&e))?;
    link.click();
    let _ = body.remove_child(&link);
    Ok(())
}

/// Opens the browser's file picker; the chosen file's text is read asynchronously into `inbox`.
pub fn pick_file(
    accept: &str,
    inbox: &Inbox,
    wake: impl Fn() + 'static,
) -> Result<(), PlatformError> {
    let input: web_sys::HtmlInputElement = document()?
        .create_element("input")
        .map_err(|e| refused(&e))?
        .dyn_into()
        .map_err(|_| PlatformError::Page("not an input".into()))?;
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
                .map_err(|error| PlatformError::Read {
                    name: name.clone(),
                    error: describe(&error),
                });
            inbox.put(text);
            wake();
        });
    });
    input.set_onchange(Some(on_change.unchecked_ref()));
    input.click();
    Ok(())
}
