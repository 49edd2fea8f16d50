//! A render's budget, checked before it starts, the same way by `raylab render` and the Render
//! view, with the figures: the most rays its settings may cast ([`worst_case`]), the memory its
//! meshes and textures hold ([`MemoryTally`]) and the time a trial frame estimates ([`Trial`]).

use std::sync::Arc;

use super::ray_kinds::short_count;
use super::{Prepared, RenderJob};
use crate::files::size_text;
use crate::platform::{Progress, Sliced, Stopwatch};
use crate::scene::render::Effect;

/// A render that may cast more rays than this (its worst case: every ray of its ray tree hit
/// something that sends more) is refused before it starts: at a billion rays a second it would take
/// over a quarter of an hour.
pub const WORST_CASE_RAYS: f64 = 1e12;

/// A render's worst case, with the settings that make it.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error(
    "this render may cast up to {} rays ({}×{} pixels, {} samples each, max_depth {}, {} occlusion \
     rays), past the budget of {}",
    short_count(self.rays),
    self.width,
    self.height,
    self.samples,
    self.max_depth,
    self.occlusion_rays,
    short_count(WORST_CASE_RAYS)
)]
pub struct WorstCase {
    /// The most rays it may cast.
    pub rays: f64,
    /// The image's width.
    pub width: usize,
    /// The image's height.
    pub height: usize,
    /// Samples a pixel.
    pub samples: usize,
    /// Bounces.
    pub max_depth: u32,
    /// Occlusion rays a hit.
    pub occlusion_rays: u32,
}

/// The most rays `prepared` may cast: per camera sample, a ray tree of max_depth levels (two
/// children a node with refraction, one with reflections alone), each node with a shadow ray a light
/// and the occlusion rays when those effects are on.
pub fn worst_case(prepared: &Prepared) -> WorstCase {
    let on = |effect| prepared.effects.contains(&effect);
    let settings = &prepared.lighting.settings;
    let samples = prepared.samples_per_pixel();
    let depth = f64::from(settings.max_depth);
    let nodes = if on(Effect::Refraction) {
        2f64.powf(depth + 1.0) - 1.0
    } else if on(Effect::Reflections) {
        depth + 1.0
    } else {
        1.0
    };
    let shadows = if on(Effect::Shadows) {
        prepared.lighting.lights.len() as f64
    } else {
        0.0
    };
    let occlusion = if on(Effect::AmbientOcclusion) {
        f64::from(settings.occlusion_rays)
    } else {
        0.0
    };
    WorstCase {
        rays: (prepared.width * prepared.height * samples) as f64
            * nodes
            * (1.0 + shadows + occlusion),
        width: prepared.width,
        height: prepared.height,
        samples,
        max_depth: settings.max_depth,
        occlusion_rays: settings.occlusion_rays,
    }
}

/// The worst case of `prepared` when it is past [`WORST_CASE_RAYS`].
pub fn past_budget(prepared: &Prepared) -> Option<WorstCase> {
    Some(worst_case(prepared)).filter(|w| w.rays > WORST_CASE_RAYS)
}

/// The most memory a scene's meshes and textures may hold together (each file counted once, however
/// many objects name it), so that a render fits a school laptop's memory beside the app.
pub const MEMORY_BUDGET_BYTES: u64 = 2 << 30;

/// Bytes a mesh's hierarchy may take per triangle, at most: its 4-wide and 8-wide nodes, slot
/// order and four-triangle packs, with leaves padded to four slots and the 8-wide walk's packed
/// leaves after them (550 measured on the 1.3-million-triangle sphere, 280–320 on spheres of 512
/// and 20 480, 90–120 on a grid box and thin triangles; a test checks the bound).
pub const BVH_BYTES_PER_TRIANGLE: u64 = 640;

/// Bytes a mesh of `triangles` triangles holds once prepared: the triangles and their hierarchy.
pub fn mesh_bytes(triangles: usize) -> u64 {
    triangles as u64
        * (std::mem::size_of::<super::objects::PreparedTriangle>() as u64 + BVH_BYTES_PER_TRIANGLE)
}

/// Bytes a decoded texture of `width` × `height` texels holds (three bytes a texel).
pub fn texture_bytes(width: usize, height: usize) -> u64 {
    3 * width as u64 * height as u64
}

/// The memory a scene's files hold so far, checked against a budget as each file is added.
#[derive(Clone, Debug)]
pub struct MemoryTally {
    budget: u64,
    files: Vec<(String, u64)>,
}

impl MemoryTally {
    /// Nothing held yet; at most `budget` bytes.
    pub fn new(budget: u64) -> MemoryTally {
        MemoryTally {
            budget,
            files: Vec::new(),
        }
    }

    /// Counts file `name` holding `bytes` (a file already counted is not counted again); an error
    /// when the files together pass the budget.
    pub fn add(&mut self, name: &str, bytes: u64) -> Result<(), OverMemory> {
        if self.files.iter().any(|(n, _)| n == name) {
            return Ok(());
        }
        self.files.push((name.to_string(), bytes));
        let held = self.files.iter().map(|(_, b)| b).sum();
        if held <= self.budget {
            return Ok(());
        }
        let mut files = self.files.clone();
        files.sort_by_key(|f| std::cmp::Reverse(f.1));
        Err(OverMemory {
            held,
            budget: self.budget,
            files,
        })
    }
}

/// A scene whose meshes and textures would hold more memory than the budget.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "the scene's meshes and textures would hold about {} in memory ({}), past the budget of {}: use fewer or \
     smaller meshes and textures, or name a file once for several objects (it is then held once)",
    size_text(*.held),
    .files.iter().take(3).map(|(n, b)| format!("{n} {}", size_text(*b))).chain(
        (.files.len() > 3).then(|| format!("{} more", .files.len() - 3))
    ).collect::<Vec<_>>().join(", "),
    size_text(*.budget)
)]
pub struct OverMemory {
    /// Bytes the files would hold together.
    pub held: u64,
    /// The budget.
    pub budget: u64,
    /// Each file with its bytes, largest first.
    pub files: Vec<(String, u64)>,
}

/// The time a render may take, estimated, before `raylab render` and the Render view refuse it
/// (the command line's `--budget` changes it; the app's "Render anyway" waives it). A debug build
/// renders 20–40 times slower than a release build, so `raylab render`'s budget there is that much
/// larger (the app's Render view has none in a debug build: see its `default_time_budget`).
pub const TIME_BUDGET_SECONDS: u32 = if cfg!(debug_assertions) { 30 * 60 } else { 60 };

/// Renders below this many samples (pixels × samples a pixel) need no trial: they take moments.
const TRIAL_PAST_SAMPLES: usize = 1 << 16;

/// The trial frame divides the image's sides by this.
const TRIAL_DIVISOR: u32 = 8;

/// The trial frame stops after this long and scales up what it did (a scene whose every ray is
/// slow, such as an exact method or a bug that tests every triangle, must not hang in the trial).
const TRIAL_SECONDS: f64 = 1.5;

/// What the trial frame predicts for the whole render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Rays the render will cast, about.
    pub rays: f64,
    /// Seconds it will take on this machine, about.
    pub seconds: f64,
    /// The threads it was measured on.
    pub threads: usize,
}

impl std::fmt::Display for Estimate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "about {} rays, about {} on {} threads here (a trial frame at 1/{TRIAL_DIVISOR} size, \
             scaled up)",
            short_count(self.rays),
            duration(self.seconds),
            self.threads
        )
    }
}

/// A render estimated past its time budget.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error(
    "this render would take about {} on {} threads here (about {} rays), past the budget of {}",
    duration(self.estimate.seconds),
    self.estimate.threads,
    short_count(self.estimate.rays),
    duration(self.budget)
)]
pub struct OverTime {
    /// What the trial frame predicts.
    pub estimate: Estimate,
    /// The budget, in seconds.
    pub budget: f64,
}

/// The trial frame, a [`Sliced`] job (the app runs it before a full render, on the render's
/// thread): a 1/8-size frame with one sample a pixel, a few rows at a time for at most
/// [`TRIAL_SECONDS`], its rays and time scaled up to the whole render (pixels × samples).
pub struct Trial {
    job: RenderJob,
    clock: Stopwatch,
    /// The whole render's samples.
    samples: usize,
    /// The trial's rows and width.
    rows: usize,
    width: usize,
}

impl Trial {
    /// The trial of `prepared`, or `None` for a render too small to need one.
    pub fn of(prepared: &Prepared) -> Option<Trial> {
        let samples = prepared.width * prepared.height * prepared.samples_per_pixel();
        if samples < TRIAL_PAST_SAMPLES {
            return None;
        }
        let trial = Arc::new(prepared.quick_frame(TRIAL_DIVISOR));
        let (width, rows) = (trial.width, trial.height);
        // Bands of 8 rows (two tasks a band, for two threads), fewer on a short frame.
        let job = RenderJob::new(trial).rows_per_step((rows / 8).clamp(1, 8));
        Some(Trial {
            job,
            clock: Stopwatch::start(),
            samples,
            rows,
            width,
        })
    }

    /// The estimate from `done` of the trial's rows, in the time so far.
    fn scaled(&self, done: usize) -> Estimate {
        // The share of the trial done, then the trial's share of the render.
        let scale = self.rows as f64 / done.max(1) as f64 * self.samples as f64
            / (self.width * self.rows).max(1) as f64;
        Estimate {
            rays: self.job.stats().all_rays() as f64 * scale,
            seconds: self.clock.seconds() * scale,
            threads: rayon::current_num_threads(),
        }
    }
}

impl Sliced for Trial {
    type Output = Estimate;

    fn step(&mut self) -> Progress<Estimate> {
        match self.job.step() {
            Progress::Working { done, total } if self.clock.seconds() <= TRIAL_SECONDS => {
                Progress::Working { done, total }
            }
            Progress::Working { done, .. } => Progress::Finished(self.scaled(done)),
            Progress::Finished(_) => Progress::Finished(self.scaled(self.rows)),
        }
    }
}

/// The trial of `prepared` run to its end, or `None` for a render too small to need one.
pub fn estimate(prepared: &Prepared) -> Option<Estimate> {
    let mut trial = Trial::of(prepared)?;
    loop {
        if let Progress::Finished(estimate) = trial.step() {
            return Some(estimate);
        }
    }
}

/// A render that first runs its trial (when it needs one) and renders nothing when the trial says
/// it would take past `budget` seconds.
pub struct BudgetedRender {
    trial: Option<Trial>,
    budget: f64,
    render: RenderJob,
}

impl BudgetedRender {
    /// A render of `prepared` within `budget` seconds; `None`: no budget, and no trial.
    pub fn new(prepared: Arc<Prepared>, budget: Option<f64>) -> BudgetedRender {
        BudgetedRender {
            trial: budget.and_then(|_| Trial::of(&prepared)),
            budget: budget.unwrap_or(f64::INFINITY),
            render: RenderJob::new(prepared),
        }
    }
}

impl Sliced for BudgetedRender {
    type Output = Result<super::Rendered, OverTime>;

    fn step(&mut self) -> Progress<Self::Output> {
        if let Some(trial) = &mut self.trial {
            match trial.step() {
                // The render's own rows have not started.
                Progress::Working { .. } => return Progress::Working { done: 0, total: 1 },
                Progress::Finished(estimate) if estimate.seconds > self.budget => {
                    return Progress::Finished(Err(OverTime {
                        estimate,
                        budget: self.budget,
                    }));
                }
                Progress::Finished(_) => self.trial = None,
            }
        }
        match self.render.step() {
            Progress::Working { done, total } => Progress::Working { done, total },
            Progress::Finished(rendered) => Progress::Finished(Ok(rendered)),
        }
    }
}

/// A duration in the unit that reads best: 2.1 s, 4 min, 3.2 h, 2.5 days.
pub fn duration(seconds: f64) -> String {
    match seconds {
        s if s >= 2.0 * 86_400.0 => format!("{:.1} days", s / 86_400.0),
        s if s >= 2.0 * 3600.0 => format!("{:.1} h", s / 3600.0),
        s if s >= 120.0 => format!("{:.0} min", s / 60.0),
        s => format!("{s:.1} s"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_named_twice_is_counted_once_and_the_refusal_names_the_largest() {
        const MIB: u64 = 1 << 20;
        let mut tally = MemoryTally::new(100 * MIB);
        assert_eq!(tally.add("a.obj", 60 * MIB), Ok(()));
        assert_eq!(tally.add("a.obj", 60 * MIB), Ok(()));
        let over = tally.add("b.png", 48 * MIB).unwrap_err();
        assert_eq!(over.held, 108 * MIB);
        assert_eq!(
            over.to_string(),
            "the scene's meshes and textures would hold about 108.0 MiB in memory (a.obj 60.0 MiB, \
             b.png 48.0 MiB), past the budget of 100.0 MiB: use fewer or smaller meshes and textures, \
             or name a file once for several objects (it is then held once)"
        );
    }

    #[test]
    fn counts_and_durations_read_at_a_glance() {
        let count = short_count;
        assert_eq!(count(5.5e6), "5.5 M");
        assert_eq!(count(2.6e13), "26.0 T");
        assert_eq!(count(830_000.0), "830 k");
        assert_eq!(count(12.0), "12");
        assert_eq!(duration(2.14), "2.1 s");
        assert_eq!(duration(600.0), "10 min");
        assert_eq!(duration(4.0 * 3600.0), "4.0 h");
        assert_eq!(duration(3.0 * 86_400.0), "3.0 days");
    }
}
