//! `raylab worksheet`: a printable worksheet, its answer key and the problems as JSON, from a seed.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;

use crate::exercise::{self, Level, MAX_COUNT};

/// `raylab worksheet`.
#[derive(Debug, Args)]
#[command(
    after_help = "Writes DIR/worksheet.tex, DIR/key.tex (pdflatex) and DIR/problems.json, all three \
                  or none; a worksheet already there is replaced only with --force. The same seed \
                  gives the same files."
)]
pub struct WorksheetArgs {
    /// The seed: the same seed gives the same problems.
    #[arg(long)]
    pub seed: u64,
    /// How many problems (1 to 100).
    #[arg(long, value_name = "K",
          value_parser = clap::value_parser!(u16).range(1..=MAX_COUNT as i64))]
    pub count: u16,
    /// Only this level: hit, outside, behind, parallel, degenerate (default: the levels in turn).
    #[arg(long, value_name = "L", value_parser = parse_level)]
    pub level: Option<Level>,
    /// The folder to write into (made if missing).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Replace a worksheet already in the folder (without it, raylab refuses and says which file is
    /// there).
    #[arg(long)]
    pub force: bool,
}

fn parse_level(text: &str) -> Result<Level, crate::exercise::UnknownLevel> {
    text.parse()
}

/// Why the worksheet was not written.
#[derive(Debug, thiserror::Error)]
pub enum WorksheetError {
    /// `-o` names a file.
    #[error("-o {}: exists and is not a directory", .0.display())]
    NotAFolder(PathBuf),
    /// The folder could not be made.
    #[error("-o {}: cannot make the folder: {source}", .path.display())]
    MakeFolder {
        /// The folder.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A file could not be written (the old one, if any, is left as it was).
    #[error("cannot write {}: {source}", .path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A file of the worksheet is there already and `--force` was not given.
    #[error("{}: exists (pass --force to replace the worksheet, or choose another -o)", .0.display())]
    Exists(PathBuf),
    /// No problems (a bad count, or none readable).
    #[error(transparent)]
    Generate(#[from] exercise::GenerateError),
}

/// Writes the three files, then says where on standard error.
pub fn run(args: WorksheetArgs) -> Result<ExitCode, WorksheetError> {
    write(&args)?;
    note!(
        "wrote {0}/worksheet.tex, {0}/key.tex and {0}/problems.json",
        args.output.display()
    );
    Ok(ExitCode::SUCCESS)
}

fn write(args: &WorksheetArgs) -> Result<(), WorksheetError> {
    let dir = &args.output;
    if dir.exists() && !dir.is_dir() {
        return Err(WorksheetError::NotAFolder(dir.clone()));
    }
    let problems = exercise::generate(args.seed, usize::from(args.count), args.level)?;
    std::fs::create_dir_all(dir).map_err(|source| WorksheetError::MakeFolder {
        path: dir.clone(),
        source,
    })?;
    let json = super::pretty_json(&exercise::problems_json(args.seed, &problems));
    let texts = [
        (
            "worksheet.tex",
            exercise::worksheet_latex(args.seed, &problems),
        ),
        ("key.tex", exercise::key_latex(args.seed, &problems)),
        ("problems.json", format!("{json}\n")),
    ];
    let paths: Vec<PathBuf> = texts.iter().map(|(name, _)| dir.join(name)).collect();
    if !args.force
        && let Some(there) = paths.iter().find(|path| path.exists())
    {
        return Err(WorksheetError::Exists(there.clone()));
    }
    // The three together, whole or not at all: a full disk leaves every old file as it was.
    let files: Vec<(&Path, &[u8])> = paths
        .iter()
        .zip(&texts)
        .map(|(path, (_, text))| (path.as_path(), text.as_bytes()))
        .collect();
    crate::files::write_all_or_none(&files)
        .map_err(|(path, source)| WorksheetError::Write { path, source })
}
