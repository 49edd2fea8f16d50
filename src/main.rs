//! The `raylab` launcher: parse the command line and run a subcommand.

fn main() {
    let cli = raylab::cli::parse_or_exit();
    std::process::exit(raylab::cli::run(cli));
}
