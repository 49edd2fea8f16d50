//! What the app remembers across restarts ([`AppState`], saved by eframe under [`STATE_KEY`]), how an
//! older saved state is read, and the tabs ([`ViewKind`]).
//!
//! The state keeps each view under its name: `views: {"triangle": (view: "…", title: …, loaded: …)}`,
//! where `view` is what the view saves of itself ([`View::save`], RON). A state saved before that
//! (one field per view, titles and loaded scenes in arrays in tab order) still reads.

use std::collections::BTreeMap;

use serde::ser::SerializeStruct as _;
use serde::{Deserialize, Serialize};

use super::VIEWS;
use super::parallelogram_view::ParallelogramView;
use super::render_view::RenderView;
use super::segments_view::SegmentsView;
use super::triangle_view::TriangleView;
use super::view::{View, ViewEntry};
use crate::geometry::Precision;
use crate::scene::{self, Problem};

/// The storage key of the state.
pub(super) const STATE_KEY: &str = "raylab-state";

/// A tab: its name (a web page's `?view=`, the key of its saved state) and its label.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ViewKind {
    name: &'static str,
    label: &'static str,
}

// The tabs the app itself refers to (the Render view's probe opens the Triangle view, …), spelled as
// the enum they replace was, so the code that names them reads as before.
#[allow(non_upper_case_globals)]
impl ViewKind {
    /// Two 2D segments.
    pub const Segments: ViewKind = ViewKind::new("segments", "Segments (2D)");
    /// A ray and a triangle in 3D.
    pub const Triangle: ViewKind = ViewKind::new("triangle", "Triangle (3D)");
    /// A ray and a parallelogram in 3D.
    pub const Parallelogram: ViewKind = ViewKind::new("parallelogram", "Parallelogram");
    /// A per-pixel render with effects, a pixel probe and common bugs.
    pub const Render: ViewKind = ViewKind::new("render", "Render");
    /// What accuracy costs: methods × precisions against exact.
    pub const Accuracy: ViewKind = ViewKind::new("accuracy", "Accuracy");
}

impl ViewKind {
    /// Every view of the registry, in tab order.
    pub const ALL: [ViewKind; VIEWS.len()] = {
        let mut all = [ViewKind::Segments; VIEWS.len()];
        let mut i = 0;
        while i < VIEWS.len() {
            all[i] = VIEWS[i].kind;
            i += 1;
        }
        all
    };

    /// A tab named `name` (lower case, as a web page's `?view=` gives it) with the label `label`.
    pub const fn new(name: &'static str, label: &'static str) -> ViewKind {
        ViewKind { name, label }
    }

    /// The short name a web page's `?view=` uses, and the key of the view's saved state.
    pub fn name(self) -> &'static str {
        self.name
    }

    /// The tab label.
    pub fn label(self) -> &'static str {
        self.label
    }
}

impl Default for ViewKind {
    fn default() -> ViewKind {
        VIEWS[0].kind
    }
}

/// Saved as its name, a bare identifier (`view: triangle`), as the enum before it was saved.
impl Serialize for ViewKind {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_unit_variant("ViewKind", 0, self.name)
    }
}

/// Read by name, whatever its case (`Triangle`, as the enum before it was saved, or `triangle`); a
/// name the registry does not know reads as the first tab.
impl<'de> Deserialize<'de> for ViewKind {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<ViewKind, D::Error> {
        struct Name;
        impl serde::de::Visitor<'_> for Name {
            type Value = ViewKind;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("the name of a view")
            }
            fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<ViewKind, E> {
                Ok(ViewKind::ALL
                    .into_iter()
                    .find(|kind| kind.name.eq_ignore_ascii_case(name))
                    .unwrap_or_default())
            }
        }
        deserializer.deserialize_identifier(Name)
    }
}

/// A tab's view, the title and note of the scene it last loaded, and that scene as it was loaded (to
/// tell when its inputs have been edited).
#[derive(Debug)]
pub struct Tab {
    /// Its name and label.
    pub kind: ViewKind,
    /// The view.
    pub view: Box<dyn View>,
    /// Title and note of the scene last loaded.
    pub title: (String, String),
    /// The scene as it was loaded.
    pub loaded: Option<Problem>,
}

impl Clone for Tab {
    fn clone(&self) -> Tab {
        Tab {
            kind: self.kind,
            view: self.view.clone_view(),
            title: self.title.clone(),
            loaded: self.loaded.clone(),
        }
    }
}

/// Everything that persists across restarts.
#[derive(Clone, Debug)]
pub struct AppState {
    /// The open tab.
    pub view: ViewKind,
    /// The step panel's arithmetic.
    pub precision: Precision,
    /// Show the step panel.
    pub show_steps: bool,
    /// Show the Triangle view's steps in symbols (seed 002) instead of numbers.
    pub symbolic: bool,
    /// The tabs, in the registry's order.
    pub tabs: Vec<Tab>,
    /// The path in the open / save dialog.
    pub scene_path: String,
    /// The live class being taught, to resume it after a restart.
    pub class: Option<super::class_view::ClassLink>,
}

impl Default for AppState {
    fn default() -> AppState {
        AppState::with_views(VIEWS)
    }
}

impl AppState {
    /// The state of an app whose tabs are `registry` (the app's is [`VIEWS`]), each view at its
    /// default with the title of the first preset it opens.
    pub fn with_views(registry: &[ViewEntry]) -> AppState {
        AppState::restored(registry, Saved::default())
    }

    /// The tab of a view, if the registry has it.
    pub fn tab(&self, kind: ViewKind) -> Option<&Tab> {
        self.tabs.iter().find(|tab| tab.kind == kind)
    }

    /// The tab of a view, to change.
    pub fn tab_mut(&mut self, kind: ViewKind) -> Option<&mut Tab> {
        self.tabs.iter_mut().find(|tab| tab.kind == kind)
    }

    /// Title and note of the scene a view last loaded (empty for a view with no scene).
    pub fn title(&self, kind: ViewKind) -> (String, String) {
        self.tab(kind)
            .map(|tab| tab.title.clone())
            .unwrap_or_default()
    }

    /// The view of a type, if the registry has one.
    pub fn find<V: View>(&self) -> Option<&V> {
        self.tabs
            .iter()
            .find_map(|tab| tab.view.as_any().downcast_ref())
    }

    /// The view of a type, to change, if the registry has one.
    pub fn find_mut<V: View>(&mut self) -> Option<&mut V> {
        self.tabs
            .iter_mut()
            .find_map(|tab| tab.view.as_any_mut().downcast_mut())
    }

    /// The view of a type. Panics if the registry has none: for code that knows the registry
    /// (tests; the app itself uses [`AppState::find`]).
    pub fn get<V: View>(&self) -> &V {
        self.find()
            .unwrap_or_else(|| panic!("no {} in the registry", std::any::type_name::<V>()))
    }

    /// The view of a type, to change. Panics as [`AppState::get`] does.
    pub fn get_mut<V: View>(&mut self) -> &mut V {
        self.find_mut()
            .unwrap_or_else(|| panic!("no {} in the registry", std::any::type_name::<V>()))
    }

    /// The view of a tab (the first tab's when the registry has no such tab).
    pub(super) fn view_of_kind(&self, kind: ViewKind) -> &dyn View {
        let index = self.tabs.iter().position(|tab| tab.kind == kind);
        self.tabs[index.unwrap_or(0)].view.as_ref()
    }

    /// The view of a tab, to change.
    pub(super) fn view_of_kind_mut(&mut self, kind: ViewKind) -> &mut dyn View {
        let index = self.tabs.iter().position(|tab| tab.kind == kind);
        self.tabs[index.unwrap_or(0)].view.as_mut()
    }

    /// The tab whose view opens a problem.
    pub fn kind_of(&self, problem: &Problem) -> Option<ViewKind> {
        self.tabs
            .iter()
            .find(|tab| tab.view.opens(problem))
            .map(|tab| tab.kind)
    }

    /// The state as `saved` has it, the rest as a new app's; `registry` makes the views.
    fn restored(registry: &[ViewEntry], mut saved: Saved) -> AppState {
        let presets = scene::built_in();
        let tabs = registry
            .iter()
            .map(|entry| {
                let name = entry.kind.name;
                let mine = saved.views.remove(name);
                let view = match (&mine, saved.legacy_view(name)) {
                    (Some(tab), _) => (entry.build)(tab.view.as_deref()),
                    (None, Some(old)) => old,
                    (None, None) => (entry.build)(None),
                };
                let preset = presets.iter().find(|s| view.opens(&s.problem));
                let title = mine.as_ref().and_then(|tab| tab.title.clone());
                let title = title
                    .or_else(|| saved.legacy_title(name))
                    .or_else(|| preset.map(|s| (s.title.clone(), s.note.clone())))
                    .unwrap_or_default();
                let loaded = match mine {
                    Some(tab) => tab.loaded,
                    None => saved
                        .legacy_loaded(name)
                        .unwrap_or_else(|| preset.map(|s| s.problem.clone())),
                };
                Tab {
                    kind: entry.kind,
                    view,
                    title,
                    loaded,
                }
            })
            .collect();
        AppState {
            view: saved.view,
            precision: saved.precision,
            show_steps: saved.show_steps,
            symbolic: saved.symbolic,
            tabs,
            scene_path: saved.scene_path,
            class: saved.class,
        }
    }
}

/// A tab as saved.
#[derive(Default, Serialize, Deserialize)]
#[serde(default)]
struct SavedTab {
    /// What the view saved of itself ([`View::save`]).
    view: Option<String>,
    /// Title and note of its scene.
    title: Option<(String, String)>,
    /// Its scene as it was loaded.
    loaded: Option<Problem>,
}

/// The state as saved: what is missing in a saved state comes from a new app's. Fields that were
/// saved before the views were kept by name (one field per view, titles and loaded scenes in arrays
/// in tab order) are read too, and taken where `views` has nothing.
#[derive(Deserialize)]
#[serde(default)]
struct Saved {
    view: ViewKind,
    precision: Precision,
    show_steps: bool,
    symbolic: bool,
    views: BTreeMap<String, SavedTab>,
    scene_path: String,
    class: Option<super::class_view::ClassLink>,
    segments: Present<SegmentsView>,
    triangle: Present<TriangleView>,
    parallelogram: Present<ParallelogramView>,
    render: Present<RenderView>,
    #[serde(deserialize_with = "titles_of_any_age")]
    titles: Present<[(String, String); 4]>,
    loaded: Present<[Option<Problem>; 4]>,
}

impl Default for Saved {
    fn default() -> Saved {
        Saved {
            view: ViewKind::default(),
            precision: Precision::Exact,
            show_steps: true,
            symbolic: false,
            views: BTreeMap::new(),
            scene_path: default_scene_path(),
            class: None,
            segments: Present(None),
            triangle: Present(None),
            parallelogram: Present(None),
            render: Present(None),
            titles: Present(None),
            loaded: Present(None),
        }
    }
}

/// A field that may be missing from a saved state (RON reads an `Option` only as `Some(…)`).
struct Present<T>(Option<T>);

impl<T> Default for Present<T> {
    fn default() -> Present<T> {
        Present(None)
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Present<T> {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Present<T>, D::Error> {
        T::deserialize(deserializer).map(|value| Present(Some(value)))
    }
}

impl Serialize for AppState {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let views: BTreeMap<&str, SavedTab> = self
            .tabs
            .iter()
            .filter_map(|tab| {
                let view = tab.view.save()?;
                let saved = SavedTab {
                    view: Some(view),
                    title: Some(tab.title.clone()),
                    loaded: tab.loaded.clone(),
                };
                Some((tab.kind.name, saved))
            })
            .collect();
        let mut state = serializer.serialize_struct("AppState", 7)?;
        state.serialize_field("view", &self.view)?;
        state.serialize_field("precision", &self.precision)?;
        state.serialize_field("show_steps", &self.show_steps)?;
        state.serialize_field("symbolic", &self.symbolic)?;
        state.serialize_field("views", &views)?;
        state.serialize_field("scene_path", &self.scene_path)?;
        state.serialize_field("class", &self.class)?;
        state.end()
    }
}

impl<'de> Deserialize<'de> for AppState {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<AppState, D::Error> {
        Ok(AppState::restored(VIEWS, Saved::deserialize(deserializer)?))
    }
}

/// The views of a state saved before they were kept by name, in the order of its arrays.
const LEGACY_ORDER: [&str; 4] = ["segments", "triangle", "parallelogram", "render"];

impl Saved {
    /// The view of this name saved in its own field (before views were kept by name), taken out.
    fn legacy_view(&mut self, name: &str) -> Option<Box<dyn View>> {
        fn boxed<V: View>(view: Option<V>) -> Option<Box<dyn View>> {
            view.map(|v| Box::new(v) as Box<dyn View>)
        }
        match name {
            "segments" => boxed(self.segments.0.take()),
            "triangle" => boxed(self.triangle.0.take()),
            "parallelogram" => boxed(self.parallelogram.0.take()),
            "render" => boxed(self.render.0.take()),
            _ => None,
        }
    }

    /// The title of the view of this name in the legacy array; none where it was not saved (the
    /// Render view's in a state saved before that view).
    fn legacy_title(&self, name: &str) -> Option<(String, String)> {
        let index = LEGACY_ORDER.iter().position(|n| *n == name)?;
        let title = self.titles.0.as_ref()?.get(index)?;
        (!title.0.is_empty() || !title.1.is_empty()).then(|| title.clone())
    }

    /// The loaded scene of the view of this name in the legacy array, if the state had the array.
    fn legacy_loaded(&self, name: &str) -> Option<Option<Problem>> {
        let index = LEGACY_ORDER.iter().position(|n| *n == name)?;
        Some(self.loaded.0.as_ref()?.get(index)?.clone())
    }
}

/// Reads the titles of a legacy state, also one saved before the Render view, which had three (the
/// Render view's then comes from the presets). Without this the whole saved state would fail to read
/// and be lost.
fn titles_of_any_age<'de, D: serde::Deserializer<'de>>(
    deserializer: D,
) -> Result<Present<[(String, String); 4]>, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Titles {
        Now([(String, String); 4]),
        BeforeRender([(String, String); 3]),
    }
    Ok(Present(Some(match Titles::deserialize(deserializer)? {
        Titles::Now(titles) => titles,
        Titles::BeforeRender([segments, triangle, parallelogram]) => {
            [segments, triangle, parallelogram, Default::default()]
        }
    })))
}

fn default_scene_path() -> String {
    std::env::var("HOME")
        .map(|home| format!("{home}/raylab-scene.ron"))
        .unwrap_or_else(|_| "raylab-scene.ron".into())
}

/// The title and note shown for a view.
pub(super) fn heading(state: &AppState) -> (String, String) {
    match state.view {
        ViewKind::Accuracy => (
            "What accuracy costs".into(),
            "Every method in f32 and f64 on easy and hard rays, judged by exact arithmetic.".into(),
        ),
        view => state.title(view),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::{Launch, RaylabApp};

    /// A state as raylab saved it before the views were kept by name (written by that code: the
    /// triangle-outside, render-mesh and seed001-parallelogram presets loaded, then β, t and a camera
    /// moved, the Triangle tab open in f32).
    const SAVED_BEFORE: &str = concat!(
        "(view:Triangle,precision:f32,show_steps:true,symbolic:false,segments:(scene:(a1:(1.0,",
        "2.0),a2:(6.0,1.0),b1:(2.0,6.0),b2:(5.0,1.0)),t:0.75,s:0.25,show_lines:true,",
        "show_samples:false,samples:32,center:(3.0,3.0),half_extent:4.0),triangle:(scene:(a:(3.0,",
        "0.0,0.0),b:(0.0,3.0,0.0),c:(0.0,0.0,3.0),origin:(0.0,0.0,0.0),dir:(1.0,1.0,-0.5),",
        "t_min:0.0),beta:0.125,gamma:0.2,t:0.5,camera:(yaw:1.7453292519943295,pitch:0.35,",
        "distance:7.127636354360398,target:(0.6,0.6,0.6)),reading:AsWritten),",
        "parallelogram:(scene:(corner:(0.0,0.0,0.0),e1:(2.0,0.0,0.0),e2:(0.0,1.0,0.0),",
        "origin:(0.5,0.5,1.0),dir:(0.0,0.0,-1.0)),alpha:0.5,beta:0.5,t:0.5,camera:(yaw:1.5,",
        "pitch:0.45,distance:4.319629613751623,target:(0.5,0.3,0.2))),render:(scene:(width:321,",
        "height:321,camera:Pinhole(position:(0.0,-4.0,0.0),target:(0.0,0.0,0.0),fov_y:35.0),",
        "method:None,objects:[(shape:Mesh(obj:\"meshes/octasphere.obj\"),color:(0.3,0.6,0.9),",
        "texture:None,transform:(translate:(0.0,0.0,0.0),rotate:(0.0,0.0,0.0),scale:(1.0,1.0,",
        "1.0)))],effects:[\"smooth-normals\"]),effects:[\"smooth-normals\"],method:None,bug:None,",
        "mode:Image,probed:None,folder:None),titles:((\"Seed 000: segments that cross\",\"A = (1,",
        "2)–(6,1), B = (2,6)–(5,1): the lecture\\'s solve gives t = 17/22, s = 21/22.\"),",
        "(\"Ray missing the triangle\",\"The lecture triangle, ray along (1, 1,",
        " −0.5): it meets the plane at γ = −1/3 < 0, beyond edge AB.\"),",
        "(\"Seed 001: ray and parallelogram\",\"c = 0, e1 = (2,0,0), e2 = (0,1,0),",
        " ray down from (0.5, 0.5, 1): α = 1/4, β = 1/2, t = 1.\"),(\"Render: a closed mesh\",",
        "\"A 512-triangle sphere read from an OBJ file, through a BVH,",
        " watertight: rays in the centre row and column run exactly along its edges.\")),",
        "scene_path:\"/root/raylab-scene.ron\",loaded:(Some(Segments((a1:(1.0,2.0),a2:(6.0,1.0),",
        "b1:(2.0,6.0),b2:(5.0,1.0)))),Some(Triangle((a:(3.0,0.0,0.0),b:(0.0,3.0,0.0),c:(0.0,0.0,",
        "3.0),origin:(0.0,0.0,0.0),dir:(1.0,1.0,-0.5),t_min:0.0))),",
        "Some(Parallelogram((corner:(0.0,0.0,0.0),e1:(2.0,0.0,0.0),e2:(0.0,1.0,0.0),origin:(0.5,",
        "0.5,1.0),dir:(0.0,0.0,-1.0)))),Some(Render((width:321,height:321,",
        "camera:Pinhole(position:(0.0,-4.0,0.0),target:(0.0,0.0,0.0),fov_y:35.0),method:None,",
        "objects:[(shape:Mesh(obj:\"meshes/octasphere.obj\"),color:(0.3,0.6,0.9),texture:None,",
        "transform:(translate:(0.0,0.0,0.0),rotate:(0.0,0.0,0.0),scale:(1.0,1.0,1.0)))],",
        "effects:[\"smooth-normals\"])))),class:None)",
    );

    /// The app that saved [`SAVED_BEFORE`], made again.
    fn the_app_that_saved_it() -> RaylabApp {
        let mut app = RaylabApp::new();
        for preset in ["triangle-outside", "render-mesh", "seed001-parallelogram"] {
            app.launch(&Launch::from_query(&format!("?preset={preset}")));
        }
        app.state.get_mut::<TriangleView>().beta = 0.125;
        app.state.get_mut::<SegmentsView>().t = 0.75;
        app.state.get_mut::<ParallelogramView>().canvas.camera.yaw = 1.5;
        app.state.view = ViewKind::Triangle;
        app.state.precision = Precision::F32;
        app
    }

    /// Everything of a state that a student would see again: the tab, the arithmetic, each tab's
    /// title, scene as loaded and what its view saves.
    fn seen(state: &AppState) -> Vec<String> {
        let mut seen = vec![format!("{:?} {:?}", state.view, state.precision)];
        for tab in &state.tabs {
            seen.push(format!(
                "{}: {:?} {:?} {:?}",
                tab.kind.name(),
                tab.title,
                tab.loaded,
                tab.view.save()
            ));
        }
        seen
    }

    #[test]
    fn a_state_saved_before_views_were_kept_by_name_reads_the_same() {
        let read: AppState = ron::from_str(SAVED_BEFORE).unwrap();
        let app = the_app_that_saved_it();
        assert_eq!(seen(&read), seen(&app.state));
        assert_eq!(read.get::<TriangleView>().beta, 0.125);
        assert_eq!(read.get::<ParallelogramView>().canvas.camera.yaw, 1.5);
        assert_eq!(read.title(ViewKind::Triangle).0, "Ray missing the triangle");
        assert_eq!(
            read.get::<RenderView>().scene,
            app.state.get::<RenderView>().scene
        );
    }

    #[test]
    fn a_state_saves_each_view_under_its_name_and_reads_back_the_same() {
        let app = the_app_that_saved_it();
        let saved = ron::to_string(&app.state).unwrap();
        for name in ["segments", "triangle", "parallelogram", "render"] {
            assert!(saved.contains(&format!("\"{name}\":")), "{name} in {saved}");
        }
        assert!(
            !saved.contains("accuracy"),
            "the Accuracy view saves nothing"
        );
        let read: AppState = ron::from_str(&saved).unwrap();
        assert_eq!(seen(&read), seen(&app.state));
        assert_eq!(ron::to_string(&read).unwrap(), saved);
    }

    /// A view the saved state does not have starts afresh; a view the registry does not have is
    /// dropped, and a tab it does not know opens the first.
    #[test]
    fn views_missing_on_either_side_are_dropped_or_start_afresh() {
        let text = r#"(view: nowhere, views: {"elsewhere": (view: Some("()")), "triangle": (view: Some("(beta: 0.5)"))})"#;
        let read: AppState = ron::from_str(text).unwrap();
        assert_eq!(read.view, ViewKind::Segments);
        assert_eq!(read.get::<TriangleView>().beta, 0.5);
        let fresh = AppState::default();
        assert_eq!(seen(&read)[1], seen(&fresh)[1]);
        assert_eq!(read.tabs.len(), VIEWS.len());
    }
}
