//! The live class: students answer on their phones, the teacher's app sees every answer arrive and
//! draws the class's predictions inside the geometry, then reveals.
//!
//! - [`protocol`]: the JSON messages over the WebSocket, shared by the server, the app and the tests.
//! - [`question`]: a question read exactly, its true answer from the exact solver, and the judging of
//!   a prediction. Pure, like the core below it.
//! - `server`, `store`, `page` (desktop only): `raylab class`, an HTTP and WebSocket server on tokio
//!   with every session in one SQLite file, and the phone page it serves.
//!
//! This module sits above the core (it asks the core's exact solver for the truth) and below the app
//! and the command line, which start and drive it (see [`crate::layers`]).

pub mod protocol;
pub mod question;

#[cfg(all(feature = "app", not(target_arch = "wasm32")))]
mod page;
#[cfg(all(feature = "app", not(target_arch = "wasm32")))]
pub mod server;
#[cfg(all(feature = "app", not(target_arch = "wasm32")))]
pub mod store;

/// The port `raylab class` listens on unless told otherwise.
pub const DEFAULT_PORT: u16 = 7878;
