//! The `raylab` launcher: on the desktop, parse the command line and run a subcommand (or open the
//! app); in a web page, start the app on the page's canvas.

/// Runs the command line. A subcommand's error is written here and only here, once, and a standard
/// error that cannot be written (a closed pipe) is ignored: the exit status still says what happened.
#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    use std::io::Write as _;
    ignore_file_size_signal();
    raylab::cli::run_command_line().unwrap_or_else(|error| {
        if let Some(message) = error.message() {
            let _ = writeln!(std::io::stderr().lock(), "{message}");
        }
        error.exit_code()
    })
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
