//! The command line: `raylab solve …` prints every step of a solve as text, JSON or LaTeX.
//!
//! Errors in what the user typed are one line naming the flag (or the batch line), and a non-zero exit.

pub mod batch;
pub mod input;
mod scan;
pub mod solve;
pub mod worksheet;

/// Prints a line to standard output, ignoring a closed pipe (`raylab bench | head` must not panic,
/// as `println!` does).
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($arg)*);
    }};
}

/// Prints a line to standard error, ignoring a closed or failing stream: a message about a problem
/// must never become a panic of its own (`eprintln!` panics when standard error is a closed pipe).
macro_rules! err {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr().lock(), $($arg)*);
    }};
}

// After the macros above, which it uses.
pub mod class;

use std::io::Write;

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

/// Parses the arguments; a usage error prints one line and exits with status 2.
pub fn parse_or_exit() -> Cli {
    Cli::try_parse().unwrap_or_else(|error| {
        use clap::error::ErrorKind;
        if matches!(
            error.kind(),
            ErrorKind::DisplayHelp
                | ErrorKind::DisplayVersion
                | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
        ) {
            error.exit();
        }
        // clap spreads some messages over several lines (the missing flags on their own lines, then a
        // usage block): keep the message, drop the usage and hints, and join it into one line.
        let rendered = error.render().to_string();
        let message: Vec<&str> = rendered
            .lines()
            .map(str::trim)
            .take_while(|line| !line.starts_with("Usage:"))
            .filter(|line| !line.is_empty() && !line.starts_with("For more information"))
            .collect();
        let message = message.join(" ");
        err!(
            "raylab: {} (see --help)",
            message.trim_start_matches("error: ")
        );
        std::process::exit(2);
    })
}

/// Runs a parsed command line; returns the process exit code.
pub fn run(cli: Cli) -> i32 {
    match cli.command {
        Some(Command::Solve(args)) => run_solve(*args),
        Some(Command::Bench(args)) => run_bench(args),
        Some(Command::Render(args)) => run_render(args),
        Some(Command::Worksheet(args)) => worksheet::run(args),
        Some(Command::Class(args)) => class::run(args),
        None if cli
            .lesson
            .as_deref()
            .is_some_and(|name| crate::lesson::lesson(name).is_none()) =>
        {
            let _ = writeln!(
                std::io::stderr(),
                "raylab: no lesson named '{}' (there are: {})",
                cli.lesson.unwrap_or_default(),
                crate::lesson::lesson_names().join(", ")
            );
            2
        }
        None => match crate::app::launch::open_window(crate::app::Launch {
            lesson: cli.lesson,
            ..Default::default()
        }) {
            Ok(()) => 0,
            Err(error) => {
                err!("raylab: could not open the window: {error}");
                1
            }
        },
    }
}

/// Why `raylab render` cannot write its image.
#[derive(Debug, thiserror::Error)]
enum ImageOutputError {
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

fn run_render(args: RenderArgs) -> i32 {
    use crate::render::render;
    use crate::scene::render::Effect;
    use crate::scene::{Problem, Scene};
    let name = args.scene.display().to_string();
    if let Err(message) = check_png_name(&args.output) {
        err!("raylab: {message}");
        return 2;
    }
    let scene = match Scene::load(&args.scene) {
        Ok(Scene {
            problem: Problem::Render(scene),
            ..
        }) => scene,
        Ok(_) => {
            err!("raylab: {name}: not a render scene (its problem is not Render(...))");
            return 1;
        }
        Err(error) => {
            err!("raylab: {error}");
            return 1;
        }
    };
    let assets = crate::render::loading::assets::OnDisk::beside(&args.scene);
    let mut prepared = match prepare_showing_progress(&scene, assets) {
        Ok(prepared) => prepared,
        Err(message) => {
            err!("raylab: {name}: {message}");
            return 1;
        }
    };
    if let Some(method) = args.method {
        prepared.method = Some(method);
    }
    prepared.bug = args.bug;
    if let Some(names) = &args.effects {
        match names
            .iter()
            .map(|n| Effect::try_from(n.trim().to_string()))
            .collect::<Result<Vec<_>, _>>()
        {
            Ok(effects) => prepared.effects = effects,
            Err(message) => {
                err!("raylab: --effects: {message}");
                return 2;
            }
        }
    }
    let timed = || {
        let clock = crate::platform::Stopwatch::start();
        let rendered = render(&prepared);
        (clock.seconds(), rendered)
    };
    let (first, (image, stats)) = timed();
    let mut times = vec![first];
    times.extend((1..args.repeat).map(|_| timed().0));
    times.sort_by(f64::total_cmp);
    let seconds = times[times.len() / 2];
    if let Err(message) = write_png(&image, &args.output) {
        err!(
            "raylab: could not write {}: {message}",
            args.output.display()
        );
        return 1;
    }
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
        out!("{}", crate::render::rays::by_kind_line(&stats));
    }
    0
}

fn print_hard_cases() -> i32 {
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
    0
}

/// `bench --out` names a folder (made if missing); a file there is said before the run.
fn out_is_a_file(dir: &std::path::Path) -> bool {
    std::fs::metadata(dir).is_ok_and(|metadata| !metadata.is_dir())
}

fn run_bench(args: BenchArgs) -> i32 {
    use crate::accuracy::study;
    if args.hard_cases {
        return print_hard_cases();
    }
    if let Some(dir) = &args.out
        && out_is_a_file(dir)
    {
        err!(
            "raylab: --out {}: is a file, not a folder (bench writes results.json and results.csv \
             into a folder)",
            dir.display()
        );
        return 2;
    }
    let mut config = if args.quick {
        study::Config::quick()
    } else {
        study::Config::full()
    };
    config.seed = args.seed;
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
    let Some(records) = records else {
        err!("raylab: the study was cancelled");
        return 1;
    };
    out!("{}", study::table(&records).trim_end());
    out!(
        "{} tests in {:.1} s",
        records.iter().map(|r| r.tests).sum::<usize>(),
        clock.seconds()
    );
    if let Some(dir) = args.out {
        let json = pretty_json(&records);
        let csv = match study::csv(&records) {
            Ok(csv) => csv,
            Err(error) => {
                err!("raylab: {error}");
                return 1;
            }
        };
        let (json_path, csv_path) = (dir.join("results.json"), dir.join("results.csv"));
        if let Err(error) = std::fs::create_dir_all(&dir) {
            err!("raylab: could not write to {}: {error}", dir.display());
            return 1;
        }
        // Both or neither: results.json must not be new while results.csv is old or missing.
        let files = [
            (json_path.as_path(), json.as_bytes()),
            (csv_path.as_path(), csv.as_bytes()),
        ];
        if let Err((path, error)) = crate::files::write_all_or_none(&files) {
            err!(
                "raylab: could not write {} (neither file was written): {error}",
                path.display()
            );
            return 1;
        }
        err!("wrote {0}/results.json and {0}/results.csv", dir.display());
    }
    0
}

/// `solve triangle … --precision symbolic`: seed 002's derivation, its identities checked on the
/// case's numbers read exactly.
fn run_symbolic(problem: &Problem, format: Format) -> i32 {
    let Problem::Triangle {
        a,
        b,
        c,
        origin,
        dir,
        ..
    } = problem
    else {
        let _ = writeln!(
            std::io::stderr(),
            "raylab: --precision symbolic derives the triangle's solution (seed 002); use it with `solve triangle`"
        );
        return 2;
    };
    let numbers = [a, b, c, origin, dir].map(|v| v.exact());
    let trace = crate::symbolic::trace(Some(&numbers));
    let output = match format {
        Format::Text => trace::to_text(&trace),
        Format::Json => format!("{}\n", pretty_json(&trace)),
        Format::Latex => trace::to_latex(&trace),
    };
    write_stdout(&output).unwrap_or(0)
}

fn run_solve(args: SolveArgs) -> i32 {
    let precision = Precision::from(args.precision);
    if args.batch && args.precision == PrecisionArg::Symbolic {
        let _ = writeln!(
            std::io::stderr(),
            "raylab: --batch solves with numbers; --precision symbolic is for one triangle"
        );
        return 2;
    }
    if args.batch {
        if matches!(args.format, Some(Format::Text | Format::Latex)) {
            err!("raylab: --batch writes JSON lines; --format text and latex do not apply");
            return 2;
        }
        let stdin = std::io::BufReader::with_capacity(1 << 16, std::io::stdin().lock());
        return match batch::run_batch(
            stdin,
            std::io::stdout().lock(),
            std::io::stderr(),
            precision,
            !args.no_trace,
        ) {
            Ok(0) => 0,
            Ok(bad) => {
                err!("raylab: {bad} bad line(s) in the batch");
                1
            }
            Err(error) => {
                err!("raylab: {error}");
                1
            }
        };
    }
    let Some(problem) = args.problem else {
        err!(
            "raylab: name a problem (segments, triangle, parallelogram) or pass --batch (see --help)"
        );
        return 2;
    };
    if args.precision == PrecisionArg::Symbolic {
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
            match solve::method_report(&vectors, tmin, *method, precision) {
                Ok(report) => report,
                Err(message) => {
                    err!("raylab: {message}");
                    return 2;
                }
            }
        }
        _ => {
            let case = problem.into_case();
            if let Err(message) = case.fits(precision) {
                err!("raylab: {message}");
                return 2;
            }
            solve::run(&case, precision)
        }
    };
    let output = match args.format.unwrap_or(Format::Text) {
        Format::Text => trace::to_text(&report.trace),
        Format::Json => format!("{}\n", pretty_json(&report.to_json(!args.no_trace))),
        Format::Latex => trace::to_latex(&report.trace),
    };
    write_stdout(&output).unwrap_or(0)
}

/// Writes a report to standard output and flushes it; on failure, the exit code (1). A full disk or a
/// closed stream is said on standard error (a closed pipe, as `| head` leaves, silently: the reader
/// chose to stop), never a panic and never a success.
fn write_stdout(output: &str) -> Option<i32> {
    let mut stdout = std::io::stdout().lock();
    match stdout
        .write_all(output.as_bytes())
        .and_then(|()| stdout.flush())
    {
        Ok(()) => None,
        Err(error) if error.kind() == std::io::ErrorKind::BrokenPipe => Some(1),
        Err(error) => {
            err!("raylab: cannot write the output: {error}");
            Some(1)
        }
    }
}
