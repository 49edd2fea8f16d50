//! `raylab render` on a scene that takes a while: before it starts, a trial frame says about how many
//! rays the render will cast and how long that takes on this machine; past a second, a progress bar
//! counts the rows, and Ctrl-C stops cleanly (no image is written; a second Ctrl-C stops at once).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::platform::{Progress, Sliced, Stopwatch};
use crate::render::budget::{OverTime, estimate};
use crate::render::{Image, Prepared, RenderJob, Stats};

/// A render this long or longer (estimated) shows its estimate and progress, and stops on Ctrl-C.
const SHOW_PAST_SECONDS: f64 = 1.0;

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
        "{over}: render a smaller image, fewer samples or effects, another --method or no --bug, or \
         pass --budget {} (0: no limit) to render it anyway",
        suggested_budget(.over.estimate.seconds)
    )]
    OverBudget {
        /// The estimate and the budget.
        over: OverTime,
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
        return Err(NotRendered::OverBudget {
            over: OverTime { estimate, budget },
        });
    }
    let stop = stop_on_ctrl_c();
    note!("raylab render: {estimate}; Ctrl-C stops");
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
