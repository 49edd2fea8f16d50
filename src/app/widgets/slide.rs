//! Parameters sliding to their values at the solution ("Solve", "Go to intersection", a presentation
//! step that computes them): one slide shared by every view. egui's animation manager keeps the
//! clock (`animate_value_with_time`, which also asks for the frames while it runs); raylab eases its
//! 0 → 1 progress with smoothstep and moves the parameters in f64, landing exactly on the solution.

/// How long a slide takes, seconds.
pub const SECONDS: f32 = 0.8;

/// N parameters on their way from `from` to `to`.
#[derive(Clone, Debug, PartialEq)]
pub struct Slide<const N: usize> {
    from: [f64; N],
    to: [f64; N],
    /// The slide's own animation in egui (a new one each slide, so none resumes an old one).
    id: egui::Id,
    /// Its progress was set to 0 in egui (on the first frame it is drawn).
    started: bool,
}

impl<const N: usize> Slide<N> {
    /// A slide from `from` to `to` asked for at `now` (egui's clock, seconds); `None` when there is
    /// nowhere to go.
    pub fn new(from: [f64; N], to: [f64; N], now: f64) -> Option<Slide<N>> {
        (from != to).then(|| Slide {
            from,
            to,
            id: egui::Id::unique(("raylab-slide", N, now.to_bits(), from.map(f64::to_bits))),
            started: false,
        })
    }

    /// Where the parameters are going: a new slide asked for mid-way starts from here, so a
    /// parameter still on its way to its solution keeps going there (a presentation step pressed
    /// quickly after the one that moved it).
    pub fn target(&self) -> [f64; N] {
        self.to
    }

    /// Where the parameters are at `progress` (0 to 1), and whether the slide has arrived.
    pub fn at(&self, progress: f64) -> ([f64; N], bool) {
        let k = progress.clamp(0.0, 1.0);
        if k >= 1.0 {
            return (self.to, true);
        }
        let eased = k * k * (3.0 - 2.0 * k);
        let at = std::array::from_fn(|i| self.from[i] + (self.to[i] - self.from[i]) * eased);
        (at, false)
    }
}

/// Moves `values` along `slide` for this frame and ends the slide on arrival.
pub fn advance<const N: usize>(ui: &egui::Ui, slide: &mut Option<Slide<N>>, values: &mut [f64; N]) {
    let Some(running) = slide.as_mut() else {
        return;
    };
    let ctx = ui.ctx();
    if !running.started {
        // egui takes the first value it sees as where the animation is: 0, then on towards 1.
        ctx.animate_value_with_time(running.id, 0.0, SECONDS);
        running.started = true;
    }
    let progress = ctx.animate_value_with_time(running.id, 1.0, SECONDS);
    let (at, arrived) = running.at(f64::from(progress));
    *values = at;
    if arrived {
        *slide = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slide_eases_from_start_to_end_and_arrives_exactly() {
        let slide = Slide::new([0.0, 1.0], [1.0, 3.0], 10.0).unwrap();
        assert_eq!(slide.at(0.0), ([0.0, 1.0], false));
        let (middle, arrived) = slide.at(0.5);
        assert!(!arrived);
        assert!((middle[0] - 0.5).abs() < 1e-12 && (middle[1] - 2.0).abs() < 1e-12);
        assert_eq!(slide.at(1.0), ([1.0, 3.0], true));
        assert!(Slide::new([0.5], [0.5], 0.0).is_none());
    }

    /// Through egui's clock: the values move over the frames of about [`SECONDS`], never pass the
    /// end, and land on it exactly.
    #[test]
    fn egui_drives_the_slide_to_its_end() {
        let ctx = egui::Context::default();
        let mut slide = Slide::new([0.0], [0.3], 0.0);
        let mut values = [0.0];
        let mut seen = Vec::new();
        for frame in 0..200 {
            let input = egui::RawInput {
                time: Some(frame as f64 / 60.0),
                ..Default::default()
            };
            let mut output = ctx.run_ui(input, |ui| advance(ui, &mut slide, &mut values));
            output.textures_delta.clear();
            seen.push(values[0]);
            if slide.is_none() {
                break;
            }
        }
        assert!(slide.is_none(), "the slide never arrived");
        assert_eq!(values, [0.3]);
        assert!(seen.windows(2).all(|w| w[0] <= w[1] && w[1] <= 0.3));
        let frames = seen.len() as f32 / 60.0;
        assert!(
            (SECONDS - 0.1..=SECONDS + 0.1).contains(&frames),
            "{frames} s"
        );
    }
}
