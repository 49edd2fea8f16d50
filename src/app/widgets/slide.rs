//! Parameters sliding to their values at the solution ("Solve", "Go to intersection", a presentation
//! step that computes them): smoothstep-eased over [`SECONDS`], one slide shared by every view.

/// How long a slide takes, seconds.
pub const SECONDS: f64 = 0.8;

/// N parameters on their way from `from` to `to`, started at `started` (egui's clock, seconds).
#[derive(Clone, Debug, PartialEq)]
pub struct Slide<const N: usize> {
    from: [f64; N],
    to: [f64; N],
    started: f64,
}

impl<const N: usize> Slide<N> {
    /// A slide from `from` to `to` starting `now`; `None` when there is nowhere to go.
    pub fn new(from: [f64; N], to: [f64; N], now: f64) -> Option<Slide<N>> {
        (from != to).then_some(Slide {
            from,
            to,
            started: now,
        })
    }

    /// Where the parameters are `now`, and whether the slide has arrived.
    pub fn at(&self, now: f64) -> ([f64; N], bool) {
        let k = ((now - self.started) / SECONDS).clamp(0.0, 1.0);
        if k >= 1.0 {
            return (self.to, true);
        }
        let eased = k * k * (3.0 - 2.0 * k);
        let at = std::array::from_fn(|i| self.from[i] + (self.to[i] - self.from[i]) * eased);
        (at, false)
    }
}

/// Moves `values` along `slide` for this frame: ends the slide on arrival, asks for another frame
/// while it runs.
pub fn advance<const N: usize>(ui: &egui::Ui, slide: &mut Option<Slide<N>>, values: &mut [f64; N]) {
    let Some(running) = slide.as_ref() else {
        return;
    };
    let (at, arrived) = running.at(ui.input(|i| i.time));
    *values = at;
    if arrived {
        *slide = None;
    } else {
        ui.ctx().request_repaint();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slide_eases_from_start_to_end_and_arrives_exactly() {
        let slide = Slide::new([0.0, 1.0], [1.0, 3.0], 10.0).unwrap();
        assert_eq!(slide.at(10.0), ([0.0, 1.0], false));
        let (middle, arrived) = slide.at(10.0 + SECONDS / 2.0);
        assert!(!arrived);
        assert!((middle[0] - 0.5).abs() < 1e-12 && (middle[1] - 2.0).abs() < 1e-12);
        assert_eq!(slide.at(10.0 + SECONDS), ([1.0, 3.0], true));
        assert!(Slide::new([0.5], [0.5], 0.0).is_none());
    }
}
