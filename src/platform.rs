//! The one place the pure core touches the platform: a monotonic clock for timing.
//!
//! Everything else in `geometry`, `exact` and `accuracy` is plain computation, so it also builds for a
//! web page; a web build swaps the clock here.

/// A started stopwatch.
#[derive(Clone, Copy, Debug)]
pub struct Stopwatch(std::time::Instant);

impl Stopwatch {
    /// Starts now.
    pub fn start() -> Stopwatch {
        Stopwatch(std::time::Instant::now())
    }

    /// Seconds since the start.
    pub fn seconds(&self) -> f64 {
        self.0.elapsed().as_secs_f64()
    }
}
