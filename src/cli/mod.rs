//! The command line: `raylab solve …` prints every step of a solve as text, JSON or LaTeX.
//!
//! Every subcommand returns `Result<ExitCode, CliError>`: an error is each subcommand's own enum, wrapped
//! in [`CliError`] and written once, by the launcher (`src/main.rs`), as one line naming the flag (or the
//! batch line, or the file) with its exit status (1: the work failed; 2: what the user typed is refused).

/// Prints a line to standard output, ignoring a closed pipe (`raylab bench | head` must not panic,
/// as `println!` does).
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($arg)*);
    }};
}

/// Prints a note (what was written where) to standard error, ignoring a closed or failing stream: a
/// note must never become a panic (`eprintln!` panics when standard error is a closed pipe). Errors are
/// not written here but returned, as a [`CliError`].
macro_rules! note {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr().lock(), $($arg)*);
    }};
}

// After the macros above, which they use.
pub mod batch;
pub mod class;
pub mod input;
pub mod render_progress;
mod scan;
pub mod solve;
pub mod worksheet;

use std::io::Write;
use std::process::ExitCode;

/// A value as indented JSON.
#[allow(
    clippy::expect_used,
    reason = "raylab's reports, traces and records are maps with string keys, numbers and strings, which \
              serde_json always writes"
)]
pub(crate) fn pretty_json(value: &impl serde::Serialize) -> String {
    serde_json::to_string_pretty(value).expect("JSON values always serialize")
}

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::geometry::Precision;
use crate::trace;
use input::{Coords, Literal, parse_coords2, parse_coords3, parse_literal};
use solve::Case;

/// raylab: parametric forms and ray–primitive intersection, every step shown.
#[derive(Debug, Parser)]
#[command(
    name = "raylab",
    version,
    after_help = "With no command, raylab opens the interactive app."
)]
pub struct Cli {
    /// What to do (nothing: open the app).
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Open the app playing a built-in lesson from its first slide (seed000-segments-and-triangle,
    /// seed001-parallelogram, seed002-symbolic-cramer, seed003-one-ray-to-a-render,
    /// seed004-barycentrics-and-transforms).
    #[arg(long, value_name = "NAME")]
    pub lesson: Option<String>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Solve one intersection problem and print every step (M X = Y, determinants, checks, verdict).
    Solve(Box<SolveArgs>),
    /// Measure what accuracy costs: every method in f32 and f64 on hard ray families, against exact.
    Bench(BenchArgs),
    /// Render a scene file (RON) to a PNG, one ray per pixel, computing only the scene's effects.
    Render(RenderArgs),
    /// Write a printable worksheet, its answer key (LaTeX) and the problems (JSON) from a seed.
    Worksheet(worksheet::WorksheetArgs),
    /// Run a live class: students answer on their phones, the teacher's app sees every answer.
    /// Prints the join address and code; `raylab class export CODE --csv` writes the answers.
    Class(class::ClassArgs),
}

impl Command {
    /// The subcommand's name, as typed.
    pub fn name(&self) -> &'static str {
        match self {
            Command::Solve(_) => "solve",
            Command::Bench(_) => "bench",
            Command::Render(_) => "render",
            Command::Worksheet(_) => "worksheet",
            Command::Class(_) => "class",
        }
    }
}

/// `raylab render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The scene file: a render scene such as assets/scenes/seed003-facing.ron.
    pub scene: std::path::PathBuf,
    /// The PNG to write.
    #[arg(short, long, value_name = "PNG")]
    pub output: std::path::PathBuf,
    /// The intersection method (default: the scene's, else watertight for meshes and moller-trumbore
    /// otherwise). watertight renders with the crack-free test (exact signs, a tie rule, no big
    /// integers); watertight-exact with the exact-deciding one the accuracy study runs.
    #[arg(long, value_name = "NAME")]
    pub method: Option<crate::intersect::Method>,
    /// Render with a common bug: and-for-or, negative-t, v-instead-of-sum, normalized-direction.
    #[arg(long, value_name = "BUG")]
    pub bug: Option<crate::render::Bug>,
    /// Only these effects instead of the scene's (comma-separated, e.g. coverage,depth).
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub effects: Option<Vec<String>>,
    /// Print the work done (rays, tests, hits, interpolations, texture samples, shading) and the time.
    #[arg(long)]
    pub stats: bool,
    /// Render this many times and report the median time (as the peer script does).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub repeat: u32,
    /// Refuse a render that a trial frame says would take longer than this many seconds on this
    /// machine (0: no limit).
    #[arg(long, default_value_t = crate::render::budget::TIME_BUDGET_SECONDS, value_parser = clap::value_parser!(u32))]
    pub budget: u32,
    /// Refuse a scene whose meshes and textures would hold more than this many MiB together (a
    /// file several objects name counts once).
    #[arg(
        long,
        value_name = "MIB",
        default_value_t = crate::render::budget::MEMORY_BUDGET_BYTES >> 20,
        value_parser = clap::value_parser!(u64).range(1..=1_000_000)
    )]
    pub memory: u64,
}

/// `raylab bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// A small run (well under 30 s) instead of the full one (a few minutes).
    #[arg(long)]
    pub quick: bool,
    /// Write results.json and results.csv into this folder.
    #[arg(long, value_name = "DIR")]
    pub out: Option<std::path::PathBuf>,
    /// The random seed of the ray families.
    #[arg(long, default_value_t = 2019)]
    pub seed: u64,
    /// Rays per family, the seam sweep and the vertex fan included (default: 1500 and 5000 with
    /// --quick, 20 000 and 200 000 otherwise); a small number makes a run of a second.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub rays: Option<u32>,
    /// Print the hard-case gallery instead: what every method decides on each named case.
    #[arg(long, conflicts_with = "out")]
    pub hard_cases: bool,
}

/// How to print a result.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// Every step of the trace, for a terminal.
    Text,
    /// One JSON object: status, parameters, point, exact values and the trace.
    Json,
    /// The trace as LaTeX (amsmath), to paste into slides.
    Latex,
}

/// Arithmetic precision on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PrecisionArg {
    /// IEEE single precision.
    F32,
    /// IEEE double precision.
    F64,
    /// Exact rational arithmetic (numbers are read exactly as written: 0.1 is 1/10).
    Exact,
    /// Seed 002's derivation in symbols (triangle only): M X = Y in ax … dz, the determinants
    /// expanded, the common terms merged, each identity checked on the given numbers exactly.
    Symbolic,
}

impl From<PrecisionArg> for Precision {
    fn from(p: PrecisionArg) -> Precision {
        match p {
            PrecisionArg::F32 => Precision::F32,
            PrecisionArg::F64 => Precision::F64,
            // Symbols are checked on the exact numbers.
            PrecisionArg::Exact | PrecisionArg::Symbolic => Precision::Exact,
        }
    }
}

/// `raylab solve`.
#[derive(Debug, Args)]
#[command(
    args_conflicts_with_subcommands = true,
    after_help = "Numbers may be integers, decimals or fractions: --dir 1/3,0.5,-2e-1.\n\
                  With --batch, read one JSON case per line from standard input (see the README)."
)]
pub struct SolveArgs {
    /// The problem to solve.
    #[command(subcommand)]
    pub problem: Option<Problem>,
    /// Arithmetic to solve in.
    #[arg(long, value_enum, default_value = "f64", global = true)]
    pub precision: PrecisionArg,
    /// Output format (batch mode always writes JSON lines).
    #[arg(long, value_enum, global = true)]
    pub format: Option<Format>,
    /// Read JSON cases from standard input, one per line; write one JSON result per line.
    #[arg(long)]
    pub batch: bool,
    /// Leave the step-by-step trace out of JSON output.
    #[arg(long, global = true)]
    pub no_trace: bool,
}

/// The problems `raylab solve` knows.
#[derive(Debug, Subcommand)]
pub enum Problem {
    /// Two 2D segments A1–A2 and B1–B2 (seed 000): A(t) = A1 + t(A2−A1), B(s) = B1 + s(B2−B1).
    Segments {
        /// Start of segment A.
        #[arg(long, value_name = "X,Y", value_parser = parse_coords2, allow_hyphen_values = true)]
        a1: Coords<2>,
        /// End of segment A.
        #[arg(long, value_name = "X,Y", value_parser = parse_coords2, allow_hyphen_values = true)]
        a2: Coords<2>,
        /// Start of segment B.
        #[arg(long, value_name = "X,Y", value_parser = parse_coords2, allow_hyphen_values = true)]
        b1: Coords<2>,
        /// End of segment B.
        #[arg(long, value_name = "X,Y", value_parser = parse_coords2, allow_hyphen_values = true)]
        b2: Coords<2>,
    },
    /// A ray L + tD against the triangle A, B, C by Cramer's rule (seed 000).
    Triangle {
        /// Vertex A.
        #[arg(long, value_name = "X,Y,Z", value_parser = parse_coords3, allow_hyphen_values = true)]
        a: Coords<3>,
        /// Vertex B.
        #[arg(long, value_name = "X,Y,Z", value_parser = parse_coords3, allow_hyphen_values = true)]
        b: Coords<3>,
        /// Vertex C.
        #[arg(long, value_name = "X,Y,Z", value_parser = parse_coords3, allow_hyphen_values = true)]
        c: Coords<3>,
        /// The ray's origin L.
        #[arg(long, value_name = "X,Y,Z", value_parser = parse_coords3, allow_hyphen_values = true)]
        origin: Coords<3>,
        /// The ray's direction D (any length; t is measured in units of |D|).
        #[arg(long, value_name = "X,Y,Z", value_parser = parse_coords3, allow_hyphen_values = true)]
        dir: Coords<3>,
        /// A hit needs t > tmin (open: t = tmin is a miss).
        #[arg(long, value_name = "T", value_parser = parse_literal, default_value = "0", allow_hyphen_values = true)]
        tmin: Literal,
        /// Which method solves it: cramer (the lecture's solver, the default, with its 16ε parallel and
        /// degenerate tolerances), moller-trumbore, plane, normal-equations, inverse, watertight (these
        /// five are the accuracy study's, in f32 or f64, testing t > 0), exact.
        #[arg(long, value_name = "NAME")]
        method: Option<crate::intersect::Method>,
    },
    /// A ray o + t d against the parallelogram c + α e1 + β e2 (seed 001).
    Parallelogram {
        /// The corner c.
        #[arg(long, value_name = "X,Y,Z", value_parser = parse_coords3, allow_hyphen_values = true)]
        corner: Coords<3>,
        /// The first edge vector e1.
        #[arg(long, value_name = "X,Y,Z", value_parser = parse_coords3, allow_hyphen_values = true)]
        e1: Coords<3>,
        /// The second edge vector e2.
        #[arg(long, value_name = "X,Y,Z", value_parser = parse_coords3, allow_hyphen_values = true)]
        e2: Coords<3>,
        /// The ray's origin o.
        #[arg(long, value_name = "X,Y,Z", value_parser = parse_coords3, allow_hyphen_values = true)]
        origin: Coords<3>,
        /// The ray's direction d.
        #[arg(long, value_name = "X,Y,Z", value_parser = parse_coords3, allow_hyphen_values = true)]
        dir: Coords<3>,
    },
}

impl Problem {
    fn into_case(self) -> Case {
        match self {
            Problem::Segments { a1, a2, b1, b2 } => Case::Segments {
                points: [a1, a2, b1, b2],
            },
            Problem::Triangle {
                a,
                b,
                c,
                origin,
                dir,
                tmin,
                ..
            } => Case::Triangle {
                vectors: [a, b, c, origin, dir],
                t_min: tmin,
            },
            Problem::Parallelogram {
                corner,
                e1,
                e2,
                origin,
                dir,
            } => Case::Parallelogram {
                vectors: [corner, e1, e2, origin, dir],
            },
        }
    }
}

/// Why a `raylab` command failed: each subcommand's own error. The launcher writes it once, as
/// [`CliError::message`] says, and exits with [`CliError::exit_code`].
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// The command line itself is refused (clap: an unknown flag, a missing value, a bad number).
    #[error("{}", usage_line(.0))]
    Usage(clap::Error),
    /// `raylab solve`.
    #[error(transparent)]
    Solve(#[from] SolveCommandError),
    /// `raylab bench`.
    #[error(transparent)]
    Bench(#[from] BenchError),
    /// `raylab render`.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// `raylab worksheet`.
    #[error(transparent)]
    Worksheet(#[from] worksheet::WorksheetError),
    /// `raylab class` and `raylab class export`.
    #[error(transparent)]
    Class(#[from] class::ClassCommandError),
    /// `raylab --lesson NAME` names no built-in lesson.
    #[error(transparent)]
    Lesson(#[from] crate::lesson::UnknownLesson),
    /// `raylab --lesson NAME` with a subcommand, which does not open the app.
    #[error(
        "--lesson opens the app at a lesson; it does not apply to `raylab {0}` (drop one of them)"
    )]
    LessonWithCommand(&'static str),
    /// `raylab` with no subcommand: the window could not open.
    #[error("could not open the window: {0}")]
    Window(String),
}

impl CliError {
    /// The exit status: 2 where what the user typed is refused before any work, 1 where the work failed.
    pub fn status(&self) -> u8 {
        match self {
            CliError::Usage(_) | CliError::Lesson(_) | CliError::LessonWithCommand(_) => 2,
            CliError::Solve(error) => error.status(),
            CliError::Bench(error) => error.status(),
            CliError::Render(error) => error.status(),
            CliError::Worksheet(_) | CliError::Class(_) | CliError::Window(_) => 1,
        }
    }

    /// [`CliError::status`] as the process's exit code.
    pub fn exit_code(&self) -> ExitCode {
        ExitCode::from(self.status())
    }

    /// What to write on standard error: one line, `raylab: …` (`raylab class: …` for the class's
    /// server), or clap's help where a subcommand is named without the arguments it needs. None where
    /// nothing is to be said: standard output's reader stopped reading (`| head`), which it chose.
    pub fn message(&self) -> Option<String> {
        match self {
            CliError::Usage(error)
                if error.kind()
                    == clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand =>
            {
                Some(error.render().to_string().trim_end().to_string())
            }
            CliError::Solve(SolveCommandError::Output(error))
                if error.kind() == std::io::ErrorKind::BrokenPipe =>
            {
                None
            }
            CliError::Class(error) => Some(format!("raylab {}: {error}", error.command())),
            error => Some(format!("raylab: {error}")),
        }
    }
}

/// clap's message on one line: clap spreads some over several lines (the missing flags on their own
/// lines, then a usage block), so the message is kept, the usage and hints dropped, and the rest joined.
fn usage_line(error: &clap::Error) -> String {
    let rendered = error.render().to_string();
    let message: Vec<&str> = rendered
        .lines()
        .map(str::trim)
        .take_while(|line| !line.starts_with("Usage:"))
        .filter(|line| !line.is_empty() && !line.starts_with("For more information"))
        .collect();
    let message = shorten_quoted(&message.join(" "));
    format!("{} (see --help)", message.trim_start_matches("error: "))
}

/// Shortens every quoted value of a message past 200 characters to its start, its end and its length:
/// clap quotes a refused argument whole, and a 100 KB argument must not become a 100 KB message.
fn shorten_quoted(message: &str) -> String {
    let parts: Vec<&str> = message.split('\'').collect();
    let mut out = String::with_capacity(message.len().min(1024));
    for (i, part) in parts.iter().enumerate() {
        let quoted_value = i % 2 == 1;
        let closed = i + 1 < parts.len();
        match (quoted_value, closed) {
            (true, true) if part.chars().count() > 200 => {
                out.push_str(&crate::math::exact::quoted(part));
            }
            (true, true) => out.push_str(&format!("'{part}'")),
            (true, false) => out.push_str(&format!("'{part}")),
            (false, _) => out.push_str(part),
        }
    }
    out
}

/// Parses the process's arguments and runs them: `--help` and `--version` print and succeed; a usage
/// error is [`CliError::Usage`] (exit status 2).
pub fn run_command_line() -> Result<ExitCode, CliError> {
    match Cli::try_parse() {
        Ok(cli) => run(cli),
        Err(error)
            if matches!(
                error.kind(),
                clap::error::ErrorKind::DisplayHelp | clap::error::ErrorKind::DisplayVersion
            ) =>
        {
            // Written to standard output; a closed one is the reader's choice.
            let _ = error.print();
            Ok(ExitCode::SUCCESS)
        }
        Err(error) => Err(CliError::Usage(error)),
    }
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<ExitCode, CliError> {
    if let (Some(_), Some(command)) = (&cli.lesson, &cli.command) {
        return Err(CliError::LessonWithCommand(command.name()));
    }
    match cli.command {
        Some(Command::Solve(args)) => Ok(run_solve(*args)?),
        Some(Command::Bench(args)) => Ok(run_bench(args)?),
        Some(Command::Render(args)) => Ok(run_render(args)?),
        Some(Command::Worksheet(args)) => Ok(worksheet::run(args)?),
        Some(Command::Class(args)) => Ok(class::run(args)?),
        None => {
            if let Some(name) = &cli.lesson
                && crate::lesson::lesson(name).is_none()
            {
                return Err(crate::lesson::UnknownLesson { name: name.clone() }.into());
            }
            crate::app::launch::open_window(crate::app::Launch {
                lesson: cli.lesson,
                ..Default::default()
            })
            .map_err(|error| CliError::Window(error.to_string()))?;
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// Why `raylab render` cannot write its image.
#[derive(Debug, thiserror::Error)]
pub enum ImageOutputError {
    /// `-o` names another image format, or none.
    #[error(
        "-o {}: raylab writes PNG images only{} (name the file .png)",
        .path.display(),
        .format.map(|f| format!(", not {f:?}")).unwrap_or_default()
    )]
    NotPng {
        path: std::path::PathBuf,
        /// The format its extension names, if any.
        format: Option<image::ImageFormat>,
    },
    /// A 0-pixel image (never from a checked scene).
    #[error("the image has no pixels")]
    NoPixels,
    /// Writing failed (the old file, if any, is left as it was).
    #[error(transparent)]
    Write(#[from] std::io::Error),
}

/// Only PNG can be written: said before anything is rendered or any file touched.
fn check_png_name(output: &std::path::Path) -> Result<(), ImageOutputError> {
    match image::ImageFormat::from_path(output) {
        Ok(image::ImageFormat::Png) => Ok(()),
        format => Err(ImageOutputError::NotPng {
            path: output.to_path_buf(),
            format: format.ok(),
        }),
    }
}

/// Encodes the image as a PNG into a temporary file beside `output`, renamed over it when complete.
fn write_png(
    image: &crate::render::Image,
    output: &std::path::Path,
) -> Result<(), ImageOutputError> {
    use image::ImageEncoder;
    if image.width == 0 || image.height == 0 {
        return Err(ImageOutputError::NoPixels);
    }
    crate::files::write_atomically(output, |out| {
        image::codecs::png::PngEncoder::new(out)
            .write_image(
                &image.to_rgb8(),
                image.width as u32,
                image.height as u32,
                image::ExtendedColorType::Rgb8,
            )
            .map_err(std::io::Error::other)
    })?;
    Ok(())
}

/// Prepares a render scene; on a terminal, a line on standard error shows the load of each mesh
/// that takes a while (a large OBJ takes seconds), redrawn as it goes and ending with its size and
/// time (indicatif draws nothing where standard error is not a terminal).
fn prepare_showing_progress(
    scene: &crate::scene::RenderScene,
    assets: crate::render::loading::assets::OnDisk,
    memory: u64,
) -> Result<crate::render::Prepared, crate::render::PrepareError> {
    use indicatif::{ProgressBar, ProgressStyle};
    let style = ProgressStyle::with_template(
        "loading {msg}: {percent:>3}% ({prefix} triangles, {elapsed})",
    )
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    let mut clock = crate::platform::Stopwatch::start();
    let mut current = String::new();
    let mut bar: Option<ProgressBar> = None;
    let prepared = crate::render::loading::scene_load::prepare_with_progress(
        scene,
        assets,
        memory,
        &mut |name, progress| {
            if current != name {
                if let Some(done) = bar.take() {
                    done.finish();
                }
                (current, clock) = (name.to_string(), crate::platform::Stopwatch::start());
            }
            // A mesh that loads within a quarter of a second shows nothing.
            if bar.is_none() && clock.seconds() > 0.25 && progress.fraction < 1.0 {
                let elapsed = std::time::Duration::from_secs_f64(clock.seconds());
                bar = Some(
                    ProgressBar::new(1000)
                        .with_style(style.clone())
                        .with_message(name.to_string())
                        .with_elapsed(elapsed),
                );
            }
            if let Some(bar) = &bar {
                bar.set_position((progress.fraction * 1000.0) as u64);
                bar.set_prefix(progress.triangles.to_string());
            }
            true
        },
    );
    if let Some(done) = bar {
        done.finish();
    }
    prepared
}

/// Why `raylab render` wrote no image.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// `-o` names no PNG file (said before anything is read or rendered).
    #[error(transparent)]
    OutputName(ImageOutputError),
    /// The scene file could not be read.
    #[error("{0}")]
    Scene(crate::scene::SceneError),
    /// The scene file poses a lecture problem, not a render.
    #[error("{0}: not a render scene (its problem is not Render(...))")]
    NotARenderScene(String),
    /// A mesh or texture of the scene could not be loaded.
    #[error("{scene}: {error}")]
    Prepare {
        /// The scene file.
        scene: String,
        /// Why.
        error: crate::render::PrepareError,
    },
    /// `--effects` names an effect that does not exist.
    #[error("--effects: {0}")]
    Effects(crate::names::UnknownName),
    /// Ctrl-C stopped the render (exit status 130, as a shell reports an interrupt), or it would
    /// take past the budget (1).
    #[error(transparent)]
    NotRendered(render_progress::NotRendered),
    /// The image could not be written (an old file is left as it was).
    #[error("could not write {}: {error}", .path.display())]
    Write {
        /// The PNG.
        path: std::path::PathBuf,
        /// Why.
        error: ImageOutputError,
    },
}

impl RenderError {
    /// 2 for a refused flag, 1 for a scene that cannot be rendered or an image that cannot be written.
    fn status(&self) -> u8 {
        match self {
            RenderError::OutputName(_) | RenderError::Effects(_) => 2,
            RenderError::NotRendered(render_progress::NotRendered::Interrupted { .. }) => 130,
            RenderError::NotRendered(
                render_progress::NotRendered::OverBudget { .. }
                | render_progress::NotRendered::MayCastTooMany { .. },
            ) => 1,
            RenderError::Scene(_)
            | RenderError::NotARenderScene(_)
            | RenderError::Prepare { .. }
            | RenderError::Write { .. } => 1,
        }
    }
}

fn run_render(args: RenderArgs) -> Result<ExitCode, RenderError> {
    use crate::render::render;
    use crate::scene::render::Effect;
    use crate::scene::{Problem, Scene};
    let name = args.scene.display().to_string();
    check_png_name(&args.output).map_err(RenderError::OutputName)?;
    let scene = match Scene::load(&args.scene).map_err(RenderError::Scene)? {
        Scene {
            problem: Problem::Render(scene),
            ..
        } => scene,
        _ => return Err(RenderError::NotARenderScene(name)),
    };
    let assets = crate::render::loading::assets::OnDisk::beside(&args.scene);
    let mut prepared = prepare_showing_progress(&scene, assets, args.memory << 20)
        .map_err(|error| RenderError::Prepare { scene: name, error })?;
    if let Some(method) = args.method {
        prepared.method = Some(method);
    }
    prepared.bug = args.bug;
    if let Some(names) = &args.effects {
        prepared.effects = names
            .iter()
            .map(|n| Effect::try_from(n.trim().to_string()))
            .collect::<Result<Vec<_>, _>>()
            .map_err(RenderError::Effects)?;
    }
    let prepared = std::sync::Arc::new(prepared);
    let timed = || {
        let clock = crate::platform::Stopwatch::start();
        let rendered = render(&prepared);
        (clock.seconds(), rendered)
    };
    // The first render says what it will cost and shows its progress when it takes a while.
    let (image, stats, first) = render_progress::render(&prepared, f64::from(args.budget))
        .map_err(RenderError::NotRendered)?;
    let mut times = vec![first];
    times.extend((1..args.repeat).map(|_| timed().0));
    times.sort_by(f64::total_cmp);
    let seconds = times[times.len() / 2];
    write_png(&image, &args.output).map_err(|error| RenderError::Write {
        path: args.output.clone(),
        error,
    })?;
    if args.stats {
        out!(
            "{}x{} with {}: median {:.3} ms in-process over {} render(s), covered pixels {}",
            image.width,
            image.height,
            prepared.method_label(),
            seconds * 1e3,
            args.repeat,
            image.covered_pixels()
        );
        let counters: Vec<String> = stats
            .counters()
            .iter()
            .map(|(name, value)| format!("{name} {value}"))
            .collect();
        out!("{}", counters.join(", "));
        out!("{}", crate::render::ray_kinds::by_kind_line(&stats));
    }
    Ok(ExitCode::SUCCESS)
}

fn print_hard_cases() -> ExitCode {
    use crate::accuracy::hard_cases::{gallery, verdicts};
    for hard in gallery() {
        let verdicts = verdicts(&hard.case());
        let exact = verdicts.first().is_some_and(|v| v.exact_hit);
        out!("{} — {}", hard.name, hard.note);
        let wrong: Vec<String> = verdicts
            .iter()
            .filter(|v| v.hit != v.exact_hit)
            .map(|v| format!("{} says {}", v.who, if v.hit { "hit" } else { "miss" }))
            .collect();
        let exact = if exact { "hit" } else { "miss" };
        let refused: Vec<&str> = verdicts
            .iter()
            .filter(|v| v.invalid_input)
            .map(|v| v.who.as_str())
            .collect();
        if !refused.is_empty() {
            out!("    input out of range for: {}", refused.join(", "));
        }
        if wrong.is_empty() {
            out!("    exact: {exact}; every method agrees");
        } else {
            out!("    exact: {exact}; wrong: {}", wrong.join(", "));
        }
    }
    ExitCode::SUCCESS
}

/// `bench --out` names a folder (made if missing); a file there is said before the run.
fn out_is_a_file(dir: &std::path::Path) -> bool {
    std::fs::metadata(dir).is_ok_and(|metadata| !metadata.is_dir())
}

/// Why `raylab bench` stopped.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// `--out` names a file (said before the run).
    #[error(
        "--out {}: is a file, not a folder (bench writes results.json and results.csv into a folder)",
        .0.display()
    )]
    OutIsAFile(std::path::PathBuf),
    /// The study was stopped before it finished.
    #[error("the study was cancelled")]
    Cancelled,
    /// The results could not be written as CSV.
    #[error(transparent)]
    Csv(#[from] crate::accuracy::study::CsvError),
    /// The `--out` folder could not be made.
    #[error("could not write to {}: {error}", .dir.display())]
    MakeFolder {
        /// The folder.
        dir: std::path::PathBuf,
        /// Why.
        error: std::io::Error,
    },
    /// A results file could not be written (neither is, then).
    #[error("could not write {} (neither file was written): {error}", .path.display())]
    Write {
        /// The file that failed.
        path: std::path::PathBuf,
        /// Why.
        error: std::io::Error,
    },
}

impl BenchError {
    /// 2 for a refused `--out`, 1 for a run that failed.
    fn status(&self) -> u8 {
        match self {
            BenchError::OutIsAFile(_) => 2,
            _ => 1,
        }
    }
}

fn run_bench(args: BenchArgs) -> Result<ExitCode, BenchError> {
    use crate::accuracy::study;
    if args.hard_cases {
        return Ok(print_hard_cases());
    }
    if let Some(dir) = &args.out
        && out_is_a_file(dir)
    {
        return Err(BenchError::OutIsAFile(dir.clone()));
    }
    let mut config = if args.quick {
        study::Config::quick()
    } else {
        study::Config::full()
    };
    config.seed = args.seed;
    if let Some(rays) = args.rays {
        (config.rays, config.shared_rays) = (rays as usize, rays as usize);
    }
    let clock = crate::platform::Stopwatch::start();
    // A bar on a terminal; nothing where stderr is a file or a pipe (indicatif hides itself there).
    let bar = indicatif::ProgressBar::new(0).with_style(
        indicatif::ProgressStyle::with_template("[{bar:40}] {pos}/{len} {elapsed}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
            .progress_chars("#  "),
    );
    let records = study::run(&config, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        true
    });
    bar.finish_and_clear();
    let records = records.ok_or(BenchError::Cancelled)?;
    out!("{}", study::table(&records).trim_end());
    out!(
        "{} tests in {:.1} s",
        records.iter().map(|r| r.tests).sum::<usize>(),
        clock.seconds()
    );
    if let Some(dir) = args.out {
        let json = pretty_json(&records);
        let csv = study::csv(&records)?;
        let (json_path, csv_path) = (dir.join("results.json"), dir.join("results.csv"));
        std::fs::create_dir_all(&dir).map_err(|error| BenchError::MakeFolder {
            dir: dir.clone(),
            error,
        })?;
        // Both or neither: results.json must not be new while results.csv is old or missing.
        let files = [
            (json_path.as_path(), json.as_bytes()),
            (csv_path.as_path(), csv.as_bytes()),
        ];
        crate::files::write_all_or_none(&files)
            .map_err(|(path, error)| BenchError::Write { path, error })?;
        note!("wrote {0}/results.json and {0}/results.csv", dir.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// Why `raylab solve` gave no answer (or, with `--batch`, not every answer).
#[derive(Debug, thiserror::Error)]
pub enum SolveCommandError {
    /// `--batch` with `--precision symbolic`.
    #[error("--batch solves with numbers; --precision symbolic is for one triangle")]
    SymbolicBatch,
    /// `--batch` with `--format text` or `latex`.
    #[error("--batch writes JSON lines; --format text and latex do not apply")]
    BatchFormat,
    /// Neither a problem nor `--batch`.
    #[error("name a problem (segments, triangle, parallelogram) or pass --batch (see --help)")]
    NoProblem,
    /// `--precision symbolic` for another problem than the triangle.
    #[error(
        "--precision symbolic derives the triangle's solution (seed 002); use it with `solve triangle`"
    )]
    SymbolicNeedsTriangle,
    /// A flag `--precision symbolic` has no use for (its derivation is in symbols, of one triangle).
    #[error("--precision symbolic derives the triangle's solution in symbols; {0} does not apply")]
    SymbolicFlag(&'static str),
    /// A number the precision cannot hold, or a flag the method does not take.
    #[error(transparent)]
    Case(#[from] solve::SolveError),
    /// Some lines of the batch were bad (each has its line on standard error and in the output).
    #[error("{0} bad line(s) in the batch")]
    BadLines(usize),
    /// The batch could not read its input or write its output.
    #[error("{0}")]
    Batch(std::io::Error),
    /// The report could not be written (a full disk; a closed pipe, which is said by nothing).
    #[error("cannot write the output: {0}")]
    Output(std::io::Error),
}

impl SolveCommandError {
    /// 2 for a refused command line, 1 for a batch with bad lines or output that could not be written.
    fn status(&self) -> u8 {
        match self {
            SolveCommandError::BadLines(_)
            | SolveCommandError::Batch(_)
            | SolveCommandError::Output(_) => 1,
            _ => 2,
        }
    }
}

/// `solve triangle … --precision symbolic`: seed 002's derivation, its identities checked on the
/// case's numbers read exactly.
fn run_symbolic(problem: &Problem, format: Format) -> Result<ExitCode, SolveCommandError> {
    let Problem::Triangle {
        a,
        b,
        c,
        origin,
        dir,
        tmin,
        method,
    } = problem
    else {
        return Err(SolveCommandError::SymbolicNeedsTriangle);
    };
    if method.is_some() {
        return Err(SolveCommandError::SymbolicFlag("--method"));
    }
    if !tmin.exact.is_zero() {
        return Err(SolveCommandError::SymbolicFlag("--tmin"));
    }
    let numbers = [a, b, c, origin, dir].map(|v| v.exact());
    let trace = crate::symbolic::trace(Some(&numbers));
    let output = match format {
        Format::Text => trace::to_text(&trace),
        Format::Json => format!("{}\n", pretty_json(&symbolic_json(&trace))),
        Format::Latex => trace::to_latex(&trace),
    };
    write_stdout(&output)
}

/// The symbolic trace as JSON, with a `status` as every other solve has: `identities-hold` when each
/// merge of seed 002 holds (as polynomials and on the numbers), else `identity-fails`.
fn symbolic_json(trace: &trace::Trace) -> serde_json::Value {
    let fails = trace
        .steps
        .iter()
        .any(|step| matches!(&step.payload, trace::Payload::Symbolic(s) if s.holds == Some(false)));
    let mut value = serde_json::to_value(trace).unwrap_or_default();
    if let serde_json::Value::Object(fields) = &mut value {
        let status = if fails {
            "identity-fails"
        } else {
            "identities-hold"
        };
        fields.insert("status".into(), status.into());
    }
    value
}

fn run_solve(args: SolveArgs) -> Result<ExitCode, SolveCommandError> {
    let precision = Precision::from(args.precision);
    if args.batch && args.precision == PrecisionArg::Symbolic {
        return Err(SolveCommandError::SymbolicBatch);
    }
    if args.batch {
        if matches!(args.format, Some(Format::Text | Format::Latex)) {
            return Err(SolveCommandError::BatchFormat);
        }
        let stdin = std::io::BufReader::with_capacity(1 << 16, std::io::stdin().lock());
        return match batch::run_batch(
            stdin,
            std::io::stdout().lock(),
            std::io::stderr(),
            precision,
            !args.no_trace,
        ) {
            Ok(0) => Ok(ExitCode::SUCCESS),
            Ok(bad) => Err(SolveCommandError::BadLines(bad)),
            Err(error) => Err(SolveCommandError::Batch(error)),
        };
    }
    let Some(problem) = args.problem else {
        return Err(SolveCommandError::NoProblem);
    };
    if args.precision == PrecisionArg::Symbolic {
        if args.no_trace {
            return Err(SolveCommandError::SymbolicFlag("--no-trace"));
        }
        return run_symbolic(&problem, args.format.unwrap_or(Format::Text));
    }
    let report = match &problem {
        Problem::Triangle {
            a,
            b,
            c,
            origin,
            dir,
            tmin,
            method: Some(method),
        } => {
            let vectors = [a.clone(), b.clone(), c.clone(), origin.clone(), dir.clone()];
            solve::method_report(&vectors, tmin, *method, precision)?
        }
        _ => {
            let case = problem.into_case();
            case.fits(precision)?;
            solve::run(&case, precision)
        }
    };
    let output = match args.format.unwrap_or(Format::Text) {
        Format::Text => trace::to_text(&report.trace),
        Format::Json => format!("{}\n", pretty_json(&report.to_json(!args.no_trace))),
        Format::Latex => trace::to_latex(&report.trace),
    };
    write_stdout(&output)
}

/// Writes a report to standard output and flushes it. A full disk or a closed stream is an error
/// (a closed pipe, as `| head` leaves, is said by nothing: the reader chose to stop), never a panic and
/// never a success.
fn write_stdout(output: &str) -> Result<ExitCode, SolveCommandError> {
    let mut stdout = std::io::stdout().lock();
    stdout
        .write_all(output.as_bytes())
        .and_then(|()| stdout.flush())
        .map_err(SolveCommandError::Output)?;
    Ok(ExitCode::SUCCESS)
}
