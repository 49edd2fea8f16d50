//! The `raylab` launcher: on the desktop, parse the command line and run a subcommand (or open the
//! app); in a web page, start the app on the page's canvas.

#[cfg(not(target_arch = "wasm32"))]
fn main() {
    let cli = raylab::cli::parse_or_exit();
    std::process::exit(raylab::cli::run(cli));
}

#[cfg(target_arch = "wasm32")]
fn main() {
    raylab::platform::web::start();
}
