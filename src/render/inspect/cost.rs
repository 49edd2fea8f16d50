//! What each effect costs: the scene rendered with its effects, then with each one off in turn, one
//! render after another as a sliced job, so the app measures in the background (a thread natively,
//! frame slices on the web) what `cargo bench --bench render -- cost-table` measures.

use std::sync::Arc;

use crate::platform::{Progress, Sliced};
use crate::render::{Prepared, RenderJob, Stats};
use crate::scene::render::Effect;

/// One render of the measurement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EffectCost {
    /// The effect left out (`None`: all of them on).
    pub without: Option<Effect>,
    /// Wall-clock seconds of the render.
    pub seconds: f64,
    /// Its work.
    pub stats: Stats,
}

/// `effects` with each one left out in turn: that effect, and the others in their order.
pub fn each_left_out(effects: &[Effect]) -> impl Iterator<Item = (Effect, Vec<Effect>)> + '_ {
    effects.iter().map(|&off| {
        let rest = effects.iter().copied().filter(|&e| e != off).collect();
        (off, rest)
    })
}

/// Renders `prepared` with its effects, then without each in turn.
pub struct CostJob {
    renders: Vec<(Option<Effect>, Arc<Prepared>)>,
    running: Option<RenderJob>,
    done: Vec<EffectCost>,
}

impl CostJob {
    /// The renders: all of `prepared`'s effects, then each one left out.
    pub fn new(prepared: &Prepared) -> CostJob {
        let mut renders = vec![(None, Arc::new(prepared.clone()))];
        for (effect, rest) in each_left_out(&prepared.effects) {
            let mut without = prepared.clone();
            without.effects = rest;
            renders.push((Some(effect), Arc::new(without)));
        }
        CostJob {
            renders,
            running: None,
            done: Vec::new(),
        }
    }

    fn rows(&self) -> usize {
        self.renders.first().map_or(1, |(_, p)| p.height.max(1))
    }
}

impl Sliced for CostJob {
    type Output = Vec<EffectCost>;

    fn step(&mut self) -> Progress<Vec<EffectCost>> {
        let index = self.done.len();
        let Some((without, prepared)) = self.renders.get(index).cloned() else {
            return Progress::Finished(std::mem::take(&mut self.done));
        };
        let rows = self.rows();
        let total = self.renders.len() * rows;
        let job = self.running.get_or_insert_with(|| RenderJob::new(prepared));
        match job.step() {
            Progress::Working { done, .. } => Progress::Working {
                done: index * rows + done,
                total,
            },
            Progress::Finished(rendered) => {
                self.running = None;
                self.done.push(EffectCost {
                    without,
                    seconds: rendered.seconds,
                    stats: rendered.stats,
                });
                Progress::Working {
                    done: (index + 1) * rows,
                    total,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::loading::assets::Embedded;
    use crate::render::ray_kinds::RayKind;
    use crate::scene::{Problem, Scene};

    #[test]
    fn each_effect_is_measured_off_and_its_rays_go_with_it() {
        let text = r#"(title: "t", note: "n", problem: Render((
            width: 12, height: 8,
            camera: Pinhole(position: (0.0, -3.0, 2.0), target: (0.0, 0.0, 0.0), fov_y: 40.0),
            objects: [(shape: Parallelogram(corner: (-5.0, -5.0, 0.0), e1: (10.0, 0.0, 0.0), e2: (0.0, 10.0, 0.0)))],
            effects: ["shadows", "antialiasing"],
            lights: [Point(position: (0.0, 0.0, 2.0), intensity: 4.0)],
        )))"#;
        let Ok(Scene {
            problem: Problem::Render(scene),
            ..
        }) = Scene::from_ron(text, "t.ron")
        else {
            panic!("the scene reads");
        };
        let prepared = Prepared::new(&scene, &Embedded).expect("it prepares");
        let mut job = CostJob::new(&prepared);
        let costs = loop {
            if let Progress::Finished(costs) = job.step() {
                break costs;
            }
        };
        let without: Vec<_> = costs.iter().map(|c| c.without).collect();
        assert_eq!(
            without,
            [None, Some(Effect::Shadows), Some(Effect::Antialiasing)]
        );
        let rays = |i: usize, kind| costs[i].stats.secondary.rays(kind);
        assert!(rays(0, RayKind::Shadow) > 0 && rays(0, RayKind::Sample) > 0);
        assert_eq!(rays(1, RayKind::Shadow), 0);
        assert_eq!(rays(2, RayKind::Sample), 0);
        assert!(costs.iter().all(|c| c.stats.rays == 96));
    }
}
