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

/// The whole app's web build (`assets/web/build-web.sh` writes it to `target/site`), served at
/// `/app/` so that a teacher can teach from a browser, and anyone can open the full app from the class's
/// address. Files are read when asked for and gzipped once per version (name, length, modified time).
pub struct Site {
    dir: Option<std::path::PathBuf>,
    cache: std::sync::Mutex<std::collections::HashMap<String, std::sync::Arc<Compressed>>>,
}

/// One file of the site, plain and gzipped, with the version it was made from.
struct Compressed {
    version: (u64, Option<std::time::SystemTime>),
    plain: Vec<u8>,
    gzipped: Vec<u8>,
}

impl Site {
    /// The site in `dir`, if it holds an `index.html`.
    pub fn new(dir: Option<std::path::PathBuf>) -> Site {
        Site {
            dir: dir.filter(|dir| dir.join("index.html").is_file()),
            cache: Default::default(),
        }
    }

    /// Whether there is a site to serve.
    pub fn is_built(&self) -> bool {
        self.dir.is_some()
    }

    /// The file `name` (a plain file name: no folders, no `..`), gzipped when the browser takes it.
    pub fn response(&self, name: &str, gzip: bool) -> Response {
        use axum::http::StatusCode;
        let Some(dir) = &self.dir else {
            return (
                StatusCode::NOT_FOUND,
                "The whole app's web build is not here: build it with assets/web/build-web.sh \
                 (it writes target/site), then start raylab class again, or pass --site DIR.\n",
            )
                .into_response();
        };
        let name = if name.is_empty() { "index.html" } else { name };
        let plain_name = name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "._-".contains(c))
            && !name.starts_with('.');
        let Some(file) = plain_name
            .then(|| self.file(&dir.join(name), name))
            .flatten()
        else {
            return (StatusCode::NOT_FOUND, "no such file\n").into_response();
        };
        let kind = match name.rsplit_once('.').map(|(_, ext)| ext) {
            Some("html") => "text/html; charset=utf-8",
            Some("js") => "text/javascript; charset=utf-8",
            Some("wasm") => "application/wasm",
            Some("css") => "text/css; charset=utf-8",
            Some("png") => "image/png",
            _ => "application/octet-stream",
        };
        let headers = [
            (header::CONTENT_TYPE, kind),
            (header::CACHE_CONTROL, "no-cache"),
            (header::VARY, "accept-encoding"),
        ];
        if gzip {
            (
                headers,
                [(header::CONTENT_ENCODING, "gzip")],
                file.gzipped.clone(),
            )
                .into_response()
        } else {
            (headers, file.plain.clone()).into_response()
        }
    }

    fn file(&self, path: &std::path::Path, name: &str) -> Option<std::sync::Arc<Compressed>> {
        let meta = std::fs::metadata(path).ok().filter(|m| m.is_file())?;
        let version = (meta.len(), meta.modified().ok());
        let cache = || {
            self.cache
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
        };
        if let Some(cached) = cache().get(name).filter(|c| c.version == version) {
            return Some(cached.clone());
        }
        let plain = std::fs::read(path).ok()?;
        let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        encoder.write_all(&plain).ok()?;
        let gzipped = encoder.finish().ok()?;
        let made = std::sync::Arc::new(Compressed {
            version,
            plain,
            gzipped,
        });
        cache().insert(name.to_string(), made.clone());
        Some(made)
    }
}
