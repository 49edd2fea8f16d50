//! The one place the code touches the platform: a monotonic clock for timing, background jobs, how
//! scene files are opened and saved.
//!
//! Everything else in `math`, `geometry`, `intersect`, `render` and `accuracy` is plain computation, so it also
//! builds for a web page. A web build has neither `std::time::Instant` nor threads: its clock is the
//! browser's (`web-time`), and it runs a [`Job`] in slices from the UI's frames instead of on a thread.
//! It has no file system either: a scene is saved as a download and opened with the browser's file
//! picker. How the app starts (a window or a canvas) is the app's own ([`crate::app::launch`]): the
//! platform is below everything and imports nothing of raylab.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

#[cfg(target_arch = "wasm32")]
pub mod web;

/// A started stopwatch.
#[derive(Clone, Copy, Debug)]
pub struct Stopwatch(web_time::Instant);

impl Stopwatch {
    /// Starts now.
    pub fn start() -> Stopwatch {
        Stopwatch(web_time::Instant::now())
    }

    /// Seconds since the start.
    pub fn seconds(&self) -> f64 {
        self.0.elapsed().as_secs_f64()
    }
}

/// True where a [`Job`] runs on its own thread (the desktop); false in a web page, where it runs in
/// [`Job::poll`], so whoever polls must ask for another frame while it is not finished.
pub const THREADS: bool = cfg!(not(target_arch = "wasm32"));

/// True where scene files are opened and saved by typing a path (the desktop); false in a web page,
/// which saves with [`download`] and opens with [`pick_file`].
pub const TYPED_PATHS: bool = cfg!(not(target_arch = "wasm32"));

/// A text file the user chose (its name and text), or why it could not be read. Files arrive later
/// than they are asked for: the browser reads them asynchronously.
pub type Picked = Result<(String, String), PlatformError>;

/// Why the platform could not do what was asked.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PlatformError {
    /// Asked of the desktop, which saves and opens typed paths instead.
    #[error("{0} are for the web page; the desktop uses a path")]
    WebOnly(&'static str),
    /// The page lacks something raylab needs (a document, a body, the canvas).
    #[error("{0}")]
    Page(String),
    /// The browser refused (its error's text).
    #[error("{0}")]
    Browser(String),
    /// A chosen file could not be read.
    #[error("could not read {name}: {error}")]
    Read {
        /// The file's name.
        name: String,
        /// The browser's reason.
        error: String,
    },
}

/// Where [`pick_file`] delivers the files the user chose; the app empties it each frame.
#[derive(Clone, Default)]
pub struct Inbox(Arc<Mutex<Vec<Picked>>>);

impl Inbox {
    /// Takes every file that has arrived.
    pub fn take(&self) -> Vec<Picked> {
        self.0
            .lock()
            .map(|mut files| std::mem::take(&mut *files))
            .unwrap_or_default()
    }

    /// Delivers a file.
    pub fn put(&self, file: Picked) {
        if let Ok(mut files) = self.0.lock() {
            files.push(file);
        }
    }
}

/// The address of the web page the app runs in (`http://host:port`), or none on the desktop: a
/// teacher's app opened from a class server joins that server by default.
pub fn page_origin() -> Option<String> {
    #[cfg(target_arch = "wasm32")]
    return web_sys::window().and_then(|window| window.location().origin().ok());
    #[cfg(not(target_arch = "wasm32"))]
    None
}

/// Offers `text` to the user as a file download named `file_name` (web only: the desktop saves to a
/// typed path).
pub fn download(file_name: &str, text: &str) -> Result<(), PlatformError> {
    #[cfg(target_arch = "wasm32")]
    return web::download(file_name, text);
    #[cfg(not(target_arch = "wasm32"))]
    {
        let _ = (file_name, text);
        Err(PlatformError::WebOnly("downloads"))
    }
}

/// Opens the browser's file picker for files matching `accept` (such as `.ron`); the file chosen
/// arrives in `inbox`, then `wake` is called (web only: the desktop opens a typed path).
pub fn pick_file(
    accept: &str,
    inbox: &Inbox,
    wake: impl Fn() + 'static,
) -> Result<(), PlatformError> {
    #[cfg(target_arch = "wasm32")]
    return web::pick_file(accept, inbox, wake);
    #[cfg(not(target_arch = "wasm32"))]
    {
        let _ = (accept, inbox, wake);
        Err(PlatformError::WebOnly("file pickers"))
    }
}

/// Where a sliced computation stands after one slice.
pub enum Progress<T> {
    /// Not finished: `done` of `total` units.
    Working {
        /// Units done.
        done: usize,
        /// Units in all.
        total: usize,
    },
    /// Finished, with its result.
    Finished(T),
}

/// A long computation cut into slices of a few milliseconds each, so it can run on a thread or,
/// where there are none, a slice per UI frame.
pub trait Sliced: Send + 'static {
    /// What it computes.
    type Output: Send + 'static;
    /// Does one slice of the work.
    fn step(&mut self) -> Progress<Self::Output>;
}

/// What a job's two sides share.
struct Shared<T> {
    done: AtomicUsize,
    total: AtomicUsize,
    cancel: AtomicBool,
    result: Mutex<Option<T>>,
    /// What went wrong, if the work panicked (the worker ends; the app shows this and goes on).
    failure: Mutex<Option<String>>,
}

/// The shortest time between two wakes of the UI for a job's progress (its end wakes it at once).
#[cfg(not(target_arch = "wasm32"))]
const PROGRESS_WAKE_SECONDS: f64 = 0.25;

/// A running [`Sliced`] computation: on a named thread natively, in slices from [`Job::poll`] on the
/// web. Dropping or cancelling it stops the work at the next slice.
pub struct Job<T> {
    shared: Arc<Shared<T>>,
    /// The web's stepper, advanced from `poll` (there are no threads there).
    #[cfg(target_arch = "wasm32")]
    stepper: Option<Box<dyn Sliced<Output = T>>>,
}

impl<T: Send + 'static> Job<T> {
    /// Starts `work`; `wake` is called (from the worker) whenever there is progress to show.
    pub fn start(
        name: &str,
        work: impl Sliced<Output = T>,
        wake: impl Fn() + Send + 'static,
    ) -> Result<Job<T>, String> {
        let shared = Arc::new(Shared {
            done: AtomicUsize::new(0),
            total: AtomicUsize::new(1),
            cancel: AtomicBool::new(false),
            result: Mutex::new(None),
            failure: Mutex::new(None),
        });
        #[cfg(not(target_arch = "wasm32"))]
        {
            let worker = shared.clone();
            let mut work = work;
            std::thread::Builder::new()
                .name(name.into())
                .spawn(move || {
                    // Progress wakes the UI at most this often: a slice takes a few ms, and a frame
                    // drawn after each kept the UI busy on a core the work needs.
                    let mut last_wake = Stopwatch::start();
                    while !worker.cancel.load(Ordering::Relaxed) {
                        // A bug in a slice must not leave the app "rendering…" forever: catch the
                        // panic, say what it was, and end the job.
                        let step =
                            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| work.step()));
                        match step {
                            Ok(progress) => {
                                if worker.record(progress) {
                                    break;
                                }
                                if last_wake.seconds() < PROGRESS_WAKE_SECONDS {
                                    continue;
                                }
                                last_wake = Stopwatch::start();
                            }
                            Err(panic) => {
                                if let Ok(mut failure) = worker.failure.lock() {
                                    *failure = Some(panic_message(panic.as_ref()));
                                }
                                break;
                            }
                        }
                        wake();
                    }
                    wake();
                })
                .map_err(|error| format!("could not start {name}: {error}"))?;
            Ok(Job { shared })
        }
        #[cfg(target_arch = "wasm32")]
        {
            let _ = (name, wake);
            Ok(Job {
                shared,
                stepper: Some(Box::new(work)),
            })
        }
    }

    /// Takes the result once it is finished. On the web this is where the work runs: slices for up
    /// to about 12 ms per call, so the page stays responsive (the caller asks for another frame while
    /// [`Job::poll`] returns `None`).
    pub fn poll(&mut self) -> Option<T> {
        #[cfg(target_arch = "wasm32")]
        if let Some(stepper) = self.stepper.as_mut() {
            let clock = Stopwatch::start();
            while !self.shared.cancel.load(Ordering::Relaxed) {
                if self.shared.record(stepper.step()) {
                    self.stepper = None;
                    break;
                }
                if clock.seconds() > 0.012 {
                    break;
                }
            }
        }
        self.shared.result.lock().ok().and_then(|mut r| r.take())
    }

    /// `(done, total)` units so far.
    pub fn progress(&self) -> (usize, usize) {
        (
            self.shared.done.load(Ordering::Relaxed),
            self.shared.total.load(Ordering::Relaxed).max(1),
        )
    }

    /// Why the work stopped without a result, if it panicked (it then never finishes).
    pub fn failure(&self) -> Option<String> {
        self.shared.failure.lock().ok().and_then(|f| f.clone())
    }

    /// Asks the work to stop at its next slice; [`Job::poll`] then never returns a result.
    pub fn cancel(&self) {
        self.shared.cancel.store(true, Ordering::Relaxed);
    }
}

/// The message a panic carried (`panic!("…")` gives a `&str` or a `String`).
#[cfg(not(target_arch = "wasm32"))]
fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "an internal error".into())
}

impl<T> Drop for Job<T> {
    fn drop(&mut self) {
        self.shared.cancel.store(true, Ordering::Relaxed);
    }
}

impl<T> Shared<T> {
    /// Records one slice's outcome; true when the work is finished.
    fn record(&self, progress: Progress<T>) -> bool {
        match progress {
            Progress::Working { done, total } => {
                self.done.store(done, Ordering::Relaxed);
                self.total.store(total, Ordering::Relaxed);
                false
            }
            Progress::Finished(result) => {
                self.done
                    .store(self.total.load(Ordering::Relaxed), Ordering::Relaxed);
                if let Ok(mut slot) = self.result.lock() {
                    *slot = Some(result);
                }
                true
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Counts to a number, one per slice.
    struct CountTo(usize, usize);

    impl Sliced for CountTo {
        type Output = usize;
        fn step(&mut self) -> Progress<usize> {
            self.0 += 1;
            if self.0 == self.1 {
                Progress::Finished(self.0)
            } else {
                Progress::Working {
                    done: self.0,
                    total: self.1,
                }
            }
        }
    }

    #[test]
    fn a_job_runs_to_its_result() {
        let mut job = Job::start("count", CountTo(0, 1000), || {}).unwrap();
        let clock = Stopwatch::start();
        let result = loop {
            if let Some(result) = job.poll() {
                break result;
            }
            assert!(clock.seconds() < 10.0, "the job never finished");
            std::thread::yield_now();
        };
        assert_eq!(result, 1000);
        assert_eq!(job.progress(), (1000, 1000));
    }

    /// Slices of a tenth of a millisecond, like a render's bands of a few rows.
    struct Naps(usize);

    impl Sliced for Naps {
        type Output = ();
        fn step(&mut self) -> Progress<()> {
            std::thread::sleep(std::time::Duration::from_micros(100));
            self.0 -= 1;
            match self.0 {
                0 => Progress::Finished(()),
                left => Progress::Working {
                    done: 1000 - left,
                    total: 1000,
                },
            }
        }
    }

    #[test]
    fn progress_wakes_the_ui_a_few_times_a_second_not_after_every_slice() {
        let wakes = Arc::new(AtomicUsize::new(0));
        let counter = wakes.clone();
        let clock = Stopwatch::start();
        let mut job = Job::start("naps", Naps(1000), move || {
            counter.fetch_add(1, Ordering::Relaxed);
        })
        .unwrap();
        while job.poll().is_none() {
            assert!(clock.seconds() < 60.0, "the job never finished");
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        let seconds = clock.seconds();
        // The end wakes it once more after the result is in (the poll above may beat that wake).
        let clock = Stopwatch::start();
        while wakes.load(Ordering::Relaxed) == 0 {
            assert!(clock.seconds() < 10.0, "the end never woke the UI");
            std::thread::yield_now();
        }
        let most = 2 + (seconds / PROGRESS_WAKE_SECONDS) as usize;
        let woken = wakes.load(Ordering::Relaxed);
        assert!(
            woken <= most,
            "{woken} wakes in {seconds:.3} s of 1000 slices: at most {most}"
        );
    }

    /// Panics in its third slice.
    struct Faulty(usize);

    impl Sliced for Faulty {
        type Output = ();
        fn step(&mut self) -> Progress<()> {
            self.0 += 1;
            assert!(self.0 < 3, "slice {} went wrong", self.0);
            Progress::Working {
                done: self.0,
                total: 10,
            }
        }
    }

    #[test]
    fn a_job_that_panics_says_so_instead_of_running_forever() {
        let mut job = Job::start("faulty", Faulty(0), || {}).unwrap();
        let clock = Stopwatch::start();
        while job.failure().is_none() {
            assert!(clock.seconds() < 10.0, "the failure was never reported");
            std::thread::yield_now();
        }
        assert!(job.failure().unwrap().contains("slice 3 went wrong"));
        assert!(job.poll().is_none());
    }
}
