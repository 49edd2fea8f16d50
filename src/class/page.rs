//! The student's page: one HTML file with its script and style inside (`assets/class/student.html`),
//! built into the binary and gzipped once at start, so a phone on a crowded room's Wi-Fi loads it in
//! one small request. It draws the question's figure as SVG and sends answers over the WebSocket;
//! every number is judged by the server's exact solver, never by the page.

use std::io::Write;

use axum::http::header;
use axum::response::{IntoResponse, Response};

/// The page as written.
pub const STUDENT_HTML: &str = include_str!("../../assets/class/student.html");

/// The page, plain and gzipped.
pub struct Page {
    gzipped: Option<Vec<u8>>,
}

impl Page {
    /// Compresses the page once.
    pub fn new() -> Page {
        let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
        let gzipped = encoder
            .write_all(STUDENT_HTML.as_bytes())
            .ok()
            .and_then(|()| encoder.finish().ok());
        Page { gzipped }
    }

    /// The page's bytes as sent: gzipped when the browser takes it.
    pub fn response(&self, gzip: bool) -> Response {
        let headers = [
            (header::CONTENT_TYPE, "text/html; charset=utf-8"),
            (header::CACHE_CONTROL, "no-cache"),
            (header::VARY, "accept-encoding"),
        ];
        match (&self.gzipped, gzip) {
            (Some(bytes), true) => {
                (headers, [(header::CONTENT_ENCODING, "gzip")], bytes.clone()).into_response()
            }
            _ => (headers, STUDENT_HTML).into_response(),
        }
    }
}
