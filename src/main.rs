//! The `raylab` launcher: on the desktop, parse the command line and run a subcommand (or open the
//! app); in a web page, start the app on the page's canvas.

#[cfg(not(target_arch = "wasm32"))]
fn main() {
    ignore_file_size_signal();
    let cli = raylab::cli::parse_or_exit();
    std::process::exit(raylab::cli::run(cli));
}

#[cfg(target_arch = "wasm32")]
fn main() {
    raylab::app::launch::start();
}

/// A write past the file-size limit (`ulimit -f`) then fails with "File too large", which raylab reports,
/// leaving the old file in place and no temporary file behind, instead of killing the process.
#[cfg(all(unix, not(target_arch = "wasm32")))]
fn ignore_file_size_signal() {
    // SAFETY: setting a signal's disposition to SIG_IGN at start-up, before any thread exists, installs
    // no handler code and touches no Rust state.
    #[allow(unsafe_code)]
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

#[cfg(all(not(unix), not(target_arch = "wasm32")))]
fn ignore_file_size_signal() {}
