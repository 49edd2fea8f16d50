//! `raylab class`: starts the live class's server (see [`crate::class::server`]) and prints the join
//! address, the code and the teacher's key; `raylab class export CODE --csv` writes a session's answers.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;

use std::io::Write as _;

use clap::{Args, Subcommand};

use crate::class::server::{self, ClassError, Options};

/// `raylab class`.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct ClassArgs {
    /// What to do instead of serving: export a session's answers.
    #[command(subcommand)]
    pub action: Option<ClassAction>,
    /// Where to listen: 127.0.0.1:PORT for this machine only, 0.0.0.0:PORT for the room's network
    /// (port 0 picks a free one).
    #[arg(long, value_name = "ADDR", default_value_t = SocketAddr::from(([127, 0, 0, 1], crate::class::DEFAULT_PORT)))]
    pub listen: SocketAddr,
    /// The SQLite file every session is kept in (default: class.sqlite3 in the user's data folder).
    #[arg(long, value_name = "PATH")]
    pub db: Option<PathBuf>,
    /// Start a new session even when the database has one still open (by default it is resumed).
    #[arg(long)]
    pub new: bool,
    /// The address students type, when it is not the one listened on (a name, or a proxy's URL).
    #[arg(long, value_name = "URL")]
    pub public_url: Option<String>,
    /// The whole app's web build, served at /app/ (default: target/site when
    /// assets/web/build-web.sh has built it there).
    #[arg(long, value_name = "DIR")]
    pub site: Option<PathBuf>,
}

/// `raylab class export`.
#[derive(Debug, Subcommand)]
pub enum ClassAction {
    /// Write one row per student per question: question, prompt, student, nickname, outcome,
    /// values, time, changes and whether it was right.
    Export {
        /// The session's join code.
        session: String,
        /// Write CSV (the only format, and the default).
        #[arg(long)]
        csv: bool,
        /// The SQLite file (default: the one `raylab class` uses).
        #[arg(long, value_name = "PATH")]
        db: Option<PathBuf>,
        /// Write to this file instead of standard output.
        #[arg(short, long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
}

/// Why `raylab class` stopped or its export failed.
#[derive(Debug, thiserror::Error)]
pub enum ClassCommandError {
    /// The server could not start or stopped on an error.
    #[error(transparent)]
    Serve(ClassError),
    /// `raylab class export` could not read the session or write its rows.
    #[error(transparent)]
    Export(ClassError),
}

impl ClassCommandError {
    /// The command the message names: `class` or `class export`.
    pub fn command(&self) -> &'static str {
        match self {
            ClassCommandError::Serve(_) => "class",
            ClassCommandError::Export(_) => "class export",
        }
    }
}

/// Runs `raylab class`: serves until stopped, or exports.
pub fn run(args: ClassArgs) -> Result<ExitCode, ClassCommandError> {
    match args.action {
        Some(ClassAction::Export {
            session, db, out, ..
        }) => export(&session, db, out).map_err(ClassCommandError::Export),
        None => serve(args).map_err(ClassCommandError::Serve),
    }?;
    Ok(ExitCode::SUCCESS)
}

fn serve(args: ClassArgs) -> Result<(), ClassError> {
    let options = Options {
        listen: args.listen,
        db: args.db.unwrap_or_else(server::default_db_path),
        new_session: args.new,
        public_url: args.public_url,
        site: Some(args.site.unwrap_or_else(|| PathBuf::from("target/site"))),
    };
    let db = options.db.display().to_string();
    server::serve(&options, |started| {
        let verb = if started.resumed {
            "resumed"
        } else {
            "started"
        };
        out!("raylab class: listening on http://{}", started.address);
        out!("  class {} {verb} (database {db})", started.code);
        out!(
            "  students open {}  (or the address, then code {})",
            started.join_url,
            started.code
        );
        out!(
            "  teacher key {}  (Class → Join in the app; keep it off the projector)",
            started.key
        );
        out!("  Ctrl-C stops the server; answers are kept, and the next start resumes the class");
    })
}

fn export(session: &str, db: Option<PathBuf>, out: Option<PathBuf>) -> Result<(), ClassError> {
    let db = db.unwrap_or_else(server::default_db_path);
    let rows = server::export_rows(&db, session)?;
    let mut bytes = Vec::new();
    server::write_csv(&rows, &mut bytes)?;
    match &out {
        Some(path) => crate::files::write_atomically(path, |file| file.write_all(&bytes))
            .map_err(|e| ClassError::Write(format!("{}: {e}", path.display()))),
        None => {
            let mut stdout = std::io::stdout().lock();
            stdout
                .write_all(&bytes)
                .and_then(|()| stdout.flush())
                .map_err(|e| ClassError::Write(e.to_string()))
        }
    }
}
