//! `raylab render` on a scene that takes a while: before it starts, a trial frame says about how many
//! rays the render will cast and how long that takes on this machine; past a second, a progress bar
//! counts the rows, and Ctrl-C stops cleanly (no image is written; a second Ctrl-C stops at once).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::platform::{Progress, Sliced, Stopwatch};
use crate::render::ray_kinds::short_count as count;
use crate::render::{Image, Prepared, RenderJob, Stats};

/// A render this long or longer (estimated) shows its estimate and progress, and stops on Ctrl-C.
const SHOW_PAST_SECONDS: f64 = 1.0;

/// Renders below this many samples (pixels × samples a pixel) need no trial: they take moments.
const TRIAL_PAST_SAMPLES: usize = 1 << 16;

/// The trial frame divides the image's sides by this.
const TRIAL_DIVISOR: u32 = 8;

/// What the trial frame predicts for the whole render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Rays the render will cast, about.
    pub rays: f64,
    /// Seconds it will take on this machine, about.
    pub seconds: f64,
}

impl Estimate {
    /// The line said before the render starts.
    pub fn line(&self) -> String {
        format!(
            "raylab render: about {} rays, about {} on {} threads here (a trial frame at 1/{TRIAL_DIVISOR} \
             size, scaled up); Ctrl-C stops",
            count(self.rays),
            duration(self.seconds),
            rayon::current_num_threads()
        )
    }
}

/// The trial frame stops after this long and scales up what it did (a scene whose every ray is
/// slow, such as an exact method or a bug that tests every triangle, must not hang in the trial).
const TRIAL_SECONDS: f64 = 1.5;

/// Renders a 1/8-size frame with one sample a pixel, a few rows at a time for at most
/// [`TRIAL_SECONDS`], and scales its rays and time up to the whole render (pixels × samples), or
/// `None` for a render too small to need it.
pub fn estimate(prepared: &Prepared) -> Option<Estimate> {
    let samples_per_side = prepared.lighting.settings.samples_per_side.max(1) as usize;
    let samples = prepared.width * prepared.height * samples_per_side * samples_per_side;
    if samples < TRIAL_PAST_SAMPLES {
        return None;
    }
    let trial = Arc::new(prepared.quick_frame(TRIAL_DIVISOR));
    let (width, height) = (trial.width, trial.height);
    // Bands of 8 rows (two tasks a band, for two threads), fewer on a short frame.
    let mut job = RenderJob::new(trial).rows_per_step((height / 8).clamp(1, 8));
    let clock = Stopwatch::start();
    let mut rows = height;
    while let Progress::Working { done, .. } = job.step() {
        if clock.seconds() > TRIAL_SECONDS {
            rows = done;
            break;
        }
    }
    let seconds = clock.seconds();
    // The share of the trial done, then the trial's share of the render.
    let scale =
        height as f64 / rows.max(1) as f64 * samples as f64 / (width * height).max(1) as f64;
    Some(Estimate {
        rays: job.stats().all_rays() as f64 * scale,
        seconds: seconds * scale,
    })
}

/// Why a render wrote nothing.
#[derive(Debug, thiserror::Error)]
pub enum NotRendered {
    /// Ctrl-C stopped it.
    #[error("render stopped by Ctrl-C after {rows} of {total} rows: no image was written")]
    Interrupted {
        /// Rows done.
        rows: usize,
        /// Rows in all.
        total: usize,
    },
    /// Its worst case is past [`crate::render::budget::WORST_CASE_RAYS`].
    #[error(
        "{0}: lower samples_per_side, max_depth or occlusion_rays, or pass --budget 0 to render it \
         anyway"
    )]
    MayCastTooMany(crate::render::budget::WorstCase),
    /// The trial frame says it would take longer than the budget.
    #[error(
        "this render would take about {} on {} threads here (about {} rays), past the budget of {}: \
         render a smaller image, fewer samples or effects, another --method or no --bug, or pass \
         --budget {} (0: no limit) to render it anyway",
        duration(.estimate.seconds),
        rayon::current_num_threads(),
        count(.estimate.rays),
        duration(*.budget),
        suggested_budget(.estimate.seconds)
    )]
    OverBudget {
        /// What the trial frame predicts.
        estimate: Estimate,
        /// The budget, in seconds.
        budget: f64,
    },
}

/// A budget that lets an estimate through, in round seconds.
fn suggested_budget(seconds: f64) -> u64 {
    let needed = (seconds * 1.5).ceil() as u64;
    needed.next_multiple_of(60)
}

/// Renders the whole image; past [`SHOW_PAST_SECONDS`] (estimated) it says the estimate first,
/// shows a progress bar and stops on Ctrl-C; past `budget` seconds (estimated; 0: no limit) it
/// refuses with the figures. Returns the image, its work and the seconds the render itself took
/// (not the trial's).
pub fn render(prepared: &Arc<Prepared>, budget: f64) -> Result<(Image, Stats, f64), NotRendered> {
    if budget > 0.0
        && let Some(worst) = crate::render::budget::past_budget(prepared)
    {
        return Err(NotRendered::MayCastTooMany(worst));
    }
    let long = estimate(prepared).filter(|e| e.seconds >= SHOW_PAST_SECONDS);
    let clock = Stopwatch::start();
    let Some(estimate) = long else {
        let (image, stats) = crate::render::render(prepared);
        return Ok((image, stats, clock.seconds()));
    };
    if budget > 0.0 && estimate.seconds > budget {
        return Err(NotRendered::OverBudget { estimate, budget });
    }
    let stop = stop_on_ctrl_c();
    note!("{}", estimate.line());
    let bar = indicatif::ProgressBar::new(prepared.height as u64).with_style(
        indicatif::ProgressStyle::with_template(
            "rendering: {pos}/{len} rows {wide_bar} {elapsed} (about {eta} left)",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let mut job = RenderJob::new(Arc::clone(prepared));
    loop {
        match job.step() {
            Progress::Working { done, total } => {
                bar.set_position(done as u64);
                if stop.load(Ordering::SeqCst) {
                    bar.abandon();
                    return Err(NotRendered::Interrupted { rows: done, total });
                }
            }
            Progress::Finished(rendered) => {
                bar.finish_and_clear();
                return Ok((rendered.image, rendered.stats, rendered.seconds));
            }
        }
    }
}

/// Sets the returned flag on the first Ctrl-C (the render stops after the rows in flight) and ends
/// the process on the second. Returns once the handler is in place (or could not be: then Ctrl-C
/// still stops the render, only without a message).
fn stop_on_ctrl_c() -> Arc<AtomicBool> {
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    let (ready, installed) = std::sync::mpsc::channel();
    let watcher =
        std::thread::Builder::new()
            .name("ctrl-c".into())
            .spawn(move || {
                let Ok(runtime) = tokio::runtime::Builder::new_current_thread()
                    .enable_all()
                    .build()
                else {
                    let _ = ready.send(());
                    return;
                };
                runtime.block_on(async {
            use tokio::signal::unix::{SignalKind, signal};
            let interrupts = signal(SignalKind::interrupt());
            let _ = ready.send(());
            let Ok(mut interrupts) = interrupts else {
                return;
            };
            while interrupts.recv().await.is_some() {
                if flag.swap(true, Ordering::SeqCst) {
                    note!("raylab render: stopped at once; no image was written");
                    std::process::exit(130);
                }
                note!("raylab render: stopping after the rows in flight (Ctrl-C again: at once)");
            }
        });
            });
    if watcher.is_ok() {
        let _ = installed.recv_timeout(std::time::Duration::from_secs(2));
    }
    stop
}

/// A duration in the unit that reads best: 2.1 s, 4 min, 3.2 h, 2.5 days.
fn duration(seconds: f64) -> String {
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
    fn counts_and_durations_read_at_a_glance() {
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
