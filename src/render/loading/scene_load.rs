//! Preparing a render scene in the background: its meshes load a slice at a time with their progress
//! (a 1 M-triangle OBJ takes seconds), then the scene is prepared. It is a [`Sliced`] job, so the app
//! runs it on a thread (or, on the web, in slices of its frames) and can cancel it.

use crate::platform::{Progress, Sliced, Stopwatch};
use crate::render::budget::{MEMORY_BUDGET_BYTES, MemoryTally, mesh_bytes};
use crate::render::loading::assets::{AssetSource, MeshLoad, Preloaded, load_mesh_with_progress};
use crate::render::{PrepareError, Prepared};
use crate::scene::render::{RenderScene, Shape};

/// The mesh files a scene names, each once, in the order of its objects.
pub fn mesh_names(scene: &RenderScene) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for object in &scene.objects {
        if let Shape::Mesh { obj } = &object.shape
            && !names.contains(obj)
        {
            names.push(obj.clone());
        }
    }
    names
}

/// The job's progress units for each mesh (its `done` of `total` counts these, plus one for the
/// final preparation).
pub const UNITS_PER_MESH: usize = 1000;

/// The most time one slice takes where it can be cut (the OBJ parse of a mesh cannot).
const SLICE_SECONDS: f64 = 0.008;

/// Prepares `scene` after loading its meshes one slice at a time.
pub struct SceneLoad<S> {
    scene: RenderScene,
    assets: Preloaded<S>,
    names: Vec<String>,
    /// The mesh being loaded (an index in `names`), and its load once started.
    next: usize,
    current: Option<MeshLoad>,
    /// The scene's numbers were checked.
    checked: bool,
    /// The meshes' memory so far, against the budget.
    memory: MemoryTally,
}

impl<S: AssetSource> SceneLoad<S> {
    /// A load of `scene`, its files from `assets`.
    pub fn new(scene: RenderScene, assets: S) -> SceneLoad<S> {
        SceneLoad {
            names: mesh_names(&scene),
            scene,
            assets: Preloaded::new(assets),
            next: 0,
            current: None,
            checked: false,
            memory: MemoryTally::new(MEMORY_BUDGET_BYTES),
        }
    }

    /// `(done, total)` units so far.
    fn units(&self) -> (usize, usize) {
        let within = self
            .current
            .as_ref()
            .map_or(0.0, |load| load.progress().fraction);
        (
            self.next * UNITS_PER_MESH + (within * UNITS_PER_MESH as f64) as usize,
            self.names.len() * UNITS_PER_MESH + 1,
        )
    }

    /// One slice: the prepared scene (or why not) when finished.
    fn advance(&mut self) -> Option<Result<Prepared, PrepareError>> {
        if !self.checked {
            self.checked = true;
            if let Err(error) = self.scene.check() {
                return Some(Err(PrepareError::Scene(error)));
            }
        }
        let clock = Stopwatch::start();
        while let Some(name) = self.names.get(self.next) {
            let load = match &mut self.current {
                Some(load) => load,
                None => match MeshLoad::start(&self.assets, name) {
                    Ok(load) => self.current.insert(load),
                    // Prepared::new reports it, with the object it belongs to.
                    Err(_) => break,
                },
            };
            match load.step() {
                Ok(None) => {}
                Ok(Some(triangles)) => {
                    if let Err(over) = self.memory.add(name, mesh_bytes(triangles.len())) {
                        return Some(Err(PrepareError::Memory(over)));
                    }
                    self.assets.insert(name, triangles);
                    self.next += 1;
                    self.current = None;
                }
                Err(_) => break,
            }
            if clock.seconds() > SLICE_SECONDS {
                return None;
            }
        }
        self.names.clear();
        self.current = None;
        Some(Prepared::new(&self.scene, &self.assets))
    }
}

impl<S: AssetSource + Send + 'static> Sliced for SceneLoad<S> {
    type Output = Result<Prepared, PrepareError>;

    fn step(&mut self) -> Progress<Self::Output> {
        match self.advance() {
            Some(result) => Progress::Finished(result),
            None => {
                let (done, total) = self.units();
                Progress::Working { done, total }
            }
        }
    }
}

/// Prepares `scene`, loading its meshes first with `progress` told each one's progress (the mesh's
/// name, then the fraction done and the triangles counted); `progress` returning false cancels.
/// Its meshes and textures may hold at most `memory` bytes together.
pub fn prepare_with_progress(
    scene: &RenderScene,
    assets: impl AssetSource,
    memory: u64,
    progress: &mut dyn FnMut(&str, crate::render::loading::assets::MeshProgress) -> bool,
) -> Result<Prepared, PrepareError> {
    scene.check().map_err(PrepareError::Scene)?;
    let mut assets = Preloaded::new(assets);
    let mut tally = MemoryTally::new(memory);
    for name in mesh_names(scene) {
        match load_mesh_with_progress(&assets, &name, &mut |p| progress(&name, p)) {
            Ok(triangles) => {
                tally.add(&name, mesh_bytes(triangles.len()))?;
                assets.insert(&name, triangles);
            }
            Err(error) if error.is_cancelled() => return Err(PrepareError::Cancelled(error)),
            // Prepared::new reports it, with the object it belongs to.
            Err(_) => break,
        }
    }
    Prepared::within(scene, &assets, memory)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::files::FileKind;
    use crate::render::loading::assets::{CANCELLED, FetchError};
    use crate::scene::render::Object;

    /// One generated OBJ file, `meshes/grid.obj`: a grid of `n` × `n` squares (2n² triangles).
    struct Grid(usize);

    impl AssetSource for Grid {
        fn read(&self, name: &str, _: FileKind) -> Result<Vec<u8>, FetchError> {
            if name != "meshes/grid.obj" {
                return Err(FetchError::Other(format!("cannot find '{name}'")));
            }
            Ok(grid_obj(self.0).into_bytes())
        }
    }

    use crate::render::generate::grid_obj;

    /// A shipped render scene with the grid as its one object.
    fn scene_with_grid() -> RenderScene {
        let mut scene = crate::scene::built_in()
            .into_iter()
            .find_map(|s| match s.problem {
                crate::scene::Problem::Render(r) => Some(r),
                _ => None,
            })
            .expect("a render scene ships");
        scene.objects = vec![Object {
            shape: Shape::Mesh {
                obj: "meshes/grid.obj".into(),
            },
            color: [0.8, 0.8, 0.8],
            texture: None,
            transform: Default::default(),
        }];
        scene
    }

    #[test]
    fn a_mesh_load_reports_rising_progress_up_to_all_of_it() {
        let n = 300; // 180 000 triangles
        let mut seen = Vec::new();
        let triangles = load_mesh_with_progress(&Grid(n), "meshes/grid.obj", &mut |p| {
            seen.push(p);
            true
        })
        .unwrap();
        assert_eq!(triangles.len(), 2 * n * n);
        assert!(seen.len() > 3, "{} reports", seen.len());
        assert!(seen.windows(2).all(|w| w[0].fraction <= w[1].fraction));
        let last = seen.last().unwrap();
        assert_eq!(last.fraction, 1.0);
        assert_eq!(last.triangles, (2 * n * n) as u64);
        // The same triangles as the plain load.
        assert_eq!(
            triangles,
            crate::render::loading::assets::load_mesh(&Grid(n), "meshes/grid.obj").unwrap()
        );
    }

    #[test]
    fn a_mesh_load_can_be_cancelled() {
        let mut calls = 0;
        let error = load_mesh_with_progress(&Grid(200), "meshes/grid.obj", &mut |_| {
            calls += 1;
            calls < 2
        })
        .unwrap_err();
        assert!(error.is_cancelled(), "{error}");
        assert!(error.to_string().ends_with(CANCELLED), "{error}");
    }

    #[test]
    fn the_sliced_job_prepares_the_scene_the_plain_way() {
        let scene = scene_with_grid();
        let mut job = SceneLoad::new(scene.clone(), Grid(100));
        let mut last = 0;
        let prepared = loop {
            match job.step() {
                Progress::Working { done, total } => {
                    assert!(done >= last && done < total);
                    last = done;
                }
                Progress::Finished(result) => break result.unwrap(),
            }
        };
        let plain = Prepared::new(&scene, &Grid(100)).unwrap();
        assert_eq!(format!("{prepared:?}"), format!("{plain:?}"));
        // A missing mesh is reported as the plain preparation reports it.
        let mut missing = scene.clone();
        missing.objects[0].shape = Shape::Mesh {
            obj: "meshes/none.obj".into(),
        };
        let mut job = SceneLoad::new(missing.clone(), Grid(2));
        let error = loop {
            if let Progress::Finished(result) = job.step() {
                break result.unwrap_err();
            }
        };
        assert_eq!(
            error.to_string(),
            Prepared::new(&missing, &Grid(2)).unwrap_err().to_string()
        );
    }

    /// A million triangles (a 707x707 grid, 32 MB of OBJ): loaded with rising progress, timed.
    /// `cargo test --release --lib one_million -- --ignored --nocapture` prints the time (about 1 s
    /// on one core of the development machine); the bound is a hang guard.
    #[test]
    #[ignore = "a release-build measurement"]
    fn one_million_triangles_load_with_progress() {
        /// The file's bytes, made before the clock starts.
        struct Made(Vec<u8>);
        impl AssetSource for Made {
            fn read(&self, _: &str, _: FileKind) -> Result<Vec<u8>, FetchError> {
                Ok(self.0.clone())
            }
        }
        let file = Made(grid_obj(707).into_bytes());
        let clock = Stopwatch::start();
        let mut reports = 0;
        let mut last = 0.0;
        let triangles = load_mesh_with_progress(&file, "meshes/grid.obj", &mut |p| {
            assert!(p.fraction >= last);
            (last, reports) = (p.fraction, reports + 1);
            true
        })
        .unwrap();
        let seconds = clock.seconds();
        assert_eq!(triangles.len(), 2 * 707 * 707);
        assert_eq!(last, 1.0);
        println!(
            "{} triangles in {seconds:.2} s, {reports} progress reports",
            triangles.len()
        );
        assert!(seconds < 60.0, "{seconds} s");
    }
}
