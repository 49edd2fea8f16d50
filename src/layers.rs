//! The direction of imports, checked: each top-level module may import only modules of a lower layer, so
//! the core never depends on the app and no two modules depend on each other. `src/ARCHITECTURE.md`
//! explains the layers; [`LAYERS`] is the rule, and the test below parses every file under `src/` with
//! `syn` and fails on any reference that goes up or sideways: a `use`, a `crate::…` or `super::…` path in
//! an expression, a type, a pattern or an attribute, or a `crate::…` path inside a macro's tokens
//! (`$crate::…` in a `macro_rules!` included), in unit tests (`#[cfg(test)]` modules, `tests.rs`) too.

/// The layers, bottom first. A module imports only from the layers below its own.
pub const LAYERS: &[&[&str]] = &[
    // Below everything: the clock, background jobs, file dialogs; atomic writes and size limits; the
    // parser of enums named by a word.
    &["platform", "files", "names"],
    // Numbers: exact rationals, the Real trait, small vectors and matrices.
    &["math"],
    // One record of every solver step, and its text and LaTeX readers.
    &["trace"],
    // The lecture's solvers: segments, triangle, parallelogram.
    &["geometry"],
    // Every ray–triangle method; symbolic derivations; exercise generation and checking.
    &["intersect", "symbolic", "exercise"],
    // Scene files: the lecture's problems and render scenes.
    &["scene"],
    // What is built on scenes: the renderer, the accuracy study.
    &["render", "accuracy"],
    // Lessons: slides of scenes, a render slide with a common bug beside it.
    &["lesson"],
    // The live class: its protocol, the exact judging of answers, and (desktop) its server.
    &["class"],
    // The window and the command line (which opens the window).
    &["app", "cli"],
];

/// The one import allowed within a layer: the command line opens the app's window.
pub const SIDEWAYS: &[(&str, &str)] = &[("cli", "app")];

#[cfg(test)]
mod tests {
    use super::{LAYERS, SIDEWAYS};
    use std::path::{Path, PathBuf};
    use syn::visit::Visit;

    fn layer(module: &str) -> Option<usize> {
        LAYERS.iter().position(|layer| layer.contains(&module))
    }

    /// One reference to a top-level module of the crate: which module, and the path as written.
    #[derive(Debug, PartialEq)]
    struct Reference {
        module: String,
        path: String,
        /// Written in a unit test: inside `#[cfg(test)]`, or in a `tests.rs` file.
        in_test: bool,
    }

    /// Walks a parsed file, knowing which module it is in (inline `mod x { … }` included), and collects
    /// the top-level module every crate-relative path resolves to.
    struct References {
        /// The module being walked, from the crate root: `["cli", "batch"]` for src/cli/batch.rs.
        module: Vec<String>,
        /// How many `#[cfg(test)]` items the walk is inside.
        tests: usize,
        found: Vec<Reference>,
    }

    impl References {
        /// The top-level module a path's segments name, if the path is relative to this crate
        /// (`crate::…`, `self::…`, `super::…`): a bare path names a local item or another crate.
        fn resolve(&mut self, segments: &[String]) {
            let mut at = match segments.first().map(String::as_str) {
                Some("crate") => Vec::new(),
                Some("self" | "super") => self.module.clone(),
                _ => return,
            };
            for segment in segments {
                match segment.as_str() {
                    "crate" | "self" => {}
                    "super" => {
                        if at.pop().is_none() {
                            return; // above the crate root: not a path of this crate
                        }
                    }
                    name => {
                        at.push(name.to_string());
                        break;
                    }
                }
            }
            if let Some(module) = at.first() {
                self.found.push(Reference {
                    module: module.clone(),
                    path: segments.join("::"),
                    in_test: self.tests > 0 || self.module.iter().any(|m| m == "tests"),
                });
            }
        }

        /// Every path a `use` tree names, flattened (`crate::{a::{X, Y}, b}` is a::X, a::Y and b).
        fn use_tree(&mut self, prefix: &mut Vec<String>, tree: &syn::UseTree) {
            match tree {
                syn::UseTree::Path(path) => {
                    prefix.push(path.ident.to_string());
                    self.use_tree(prefix, &path.tree);
                    prefix.pop();
                }
                syn::UseTree::Name(name) => self.resolve_with(prefix, name.ident.to_string()),
                syn::UseTree::Rename(rename) => self.resolve_with(prefix, rename.ident.to_string()),
                syn::UseTree::Glob(_) => self.resolve(&prefix.clone()),
                syn::UseTree::Group(group) => {
                    for tree in &group.items {
                        self.use_tree(prefix, tree);
                    }
                }
            }
        }

        fn resolve_with(&mut self, prefix: &[String], last: String) {
            let mut path = prefix.to_vec();
            path.push(last);
            self.resolve(&path);
        }

        /// The paths in a macro's tokens, which syn leaves unparsed: each run `ident :: ident …`.
        fn tokens(&mut self, tokens: proc_macro2::TokenStream) {
            let mut path: Vec<String> = Vec::new();
            let mut colons = 0;
            for token in tokens {
                match token {
                    proc_macro2::TokenTree::Ident(ident) if path.is_empty() || colons == 2 => {
                        path.push(ident.to_string());
                        colons = 0;
                        continue;
                    }
                    proc_macro2::TokenTree::Punct(punct)
                        if punct.as_char() == ':' && !path.is_empty() && colons < 2 =>
                    {
                        colons += 1;
                        continue;
                    }
                    proc_macro2::TokenTree::Group(group) => {
                        self.flush(&mut path);
                        self.tokens(group.stream());
                    }
                    proc_macro2::TokenTree::Ident(ident) => {
                        self.flush(&mut path);
                        path.push(ident.to_string());
                        colons = 0;
                        continue;
                    }
                    _ => self.flush(&mut path),
                }
                colons = 0;
            }
            self.flush(&mut path);
        }

        fn flush(&mut self, path: &mut Vec<String>) {
            if path.len() > 1 {
                self.resolve(path);
            }
            path.clear();
        }
    }

    impl<'ast> Visit<'ast> for References {
        fn visit_item_mod(&mut self, item: &'ast syn::ItemMod) {
            let test = is_cfg_test(&item.attrs);
            self.tests += usize::from(test);
            self.module.push(item.ident.to_string());
            syn::visit::visit_item_mod(self, item);
            self.module.pop();
            self.tests -= usize::from(test);
        }

        fn visit_item_fn(&mut self, item: &'ast syn::ItemFn) {
            let test = is_cfg_test(&item.attrs);
            self.tests += usize::from(test);
            syn::visit::visit_item_fn(self, item);
            self.tests -= usize::from(test);
        }

        fn visit_item_use(&mut self, item: &'ast syn::ItemUse) {
            // `use ::name` names another crate.
            if item.leading_colon.is_none() {
                self.use_tree(&mut Vec::new(), &item.tree);
            }
        }

        fn visit_path(&mut self, path: &'ast syn::Path) {
            if path.leading_colon.is_none() {
                let segments: Vec<String> =
                    path.segments.iter().map(|s| s.ident.to_string()).collect();
                self.resolve(&segments);
            }
            syn::visit::visit_path(self, path);
        }

        fn visit_macro(&mut self, mac: &'ast syn::Macro) {
            self.tokens(mac.tokens.clone());
            syn::visit::visit_macro(self, mac);
        }
    }

    /// Whether an item is compiled for unit tests only: `#[cfg(test)]`.
    fn is_cfg_test(attrs: &[syn::Attribute]) -> bool {
        attrs.iter().any(|attr| {
            attr.path().is_ident("cfg")
                && attr
                    .parse_args::<syn::Ident>()
                    .is_ok_and(|ident| ident == "test")
        })
    }

    /// The crate modules that `source`, the file of module `module`, refers to.
    fn references(module: &[&str], source: &str) -> syn::Result<Vec<Reference>> {
        let file = syn::parse_file(source)?;
        let mut walker = References {
            module: module.iter().map(|m| m.to_string()).collect(),
            tests: 0,
            found: Vec::new(),
        };
        walker.visit_file(&file);
        Ok(walker.found)
    }

    /// The references of a file in `top` that go up or sideways, as messages naming `file`.
    fn against_the_layers(file: &str, top: &str, references: &[Reference]) -> Vec<String> {
        let Some(own) = layer(top) else {
            return vec![format!("{file}: {top} is in no layer: add it to LAYERS")];
        };
        let mut wrong = Vec::new();
        for Reference { module, path, .. } in references {
            if module == top {
                continue;
            }
            match layer(module) {
                None => wrong.push(format!("{file}: {path}: {module} is in no layer")),
                Some(theirs)
                    if theirs > own
                        || (theirs == own && !SIDEWAYS.contains(&(top, module.as_str()))) =>
                {
                    wrong.push(format!(
                        "{file}: {top} (layer {own}) refers to {path} (layer {theirs})"
                    ))
                }
                Some(_) => {}
            }
        }
        wrong
    }

    /// The module a file under src/ is: src/cli/batch.rs is cli::batch, src/cli/mod.rs is cli.
    fn module_of(relative: &Path) -> Vec<String> {
        let mut module: Vec<String> = relative
            .with_extension("")
            .components()
            .filter_map(|c| c.as_os_str().to_str().map(str::to_string))
            .collect();
        if module.last().is_some_and(|last| last == "mod") {
            module.pop();
        }
        module
    }

    fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).expect("src is readable").flatten() {
            let path = entry.path();
            if path.is_dir() {
                rust_files(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }

    #[test]
    fn imports_go_down_the_layers_only() {
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        let mut wrong = Vec::new();
        let mut checked = 0;
        for file in &files {
            let relative = file.strip_prefix(&src).expect("under src");
            let module = module_of(relative);
            let top = module.first().map(String::as_str).unwrap_or("");
            // The crate root declares the modules; the binary and this checker import none.
            if ["lib", "main", "layers"].contains(&top) {
                continue;
            }
            let text = std::fs::read_to_string(file).expect("a source file is readable");
            let modules: Vec<&str> = module.iter().map(String::as_str).collect();
            let found = references(&modules, &text)
                .unwrap_or_else(|error| panic!("{}: {error}", relative.display()));
            checked += found.len();
            let name = relative.display().to_string();
            wrong.extend(against_the_layers(&name, top, &found));
        }
        wrong.sort();
        wrong.dedup();
        assert!(
            checked > 1000,
            "only {checked} references found: is the walker broken?"
        );
        assert!(
            wrong.is_empty(),
            "references against the layers:\n{}",
            wrong.join("\n")
        );
    }

    /// The walker finds an upward reference wherever it is written: a grouped `use`, a path in an
    /// expression or a type, a `super::` path that climbs out of the module, a macro's tokens, and a
    /// `#[cfg(test)]` module at the end of the file.
    #[test]
    fn the_check_catches_an_upward_reference_anywhere_in_a_file() {
        let source = r#"
            use crate::{math::{Real, real::X}, trace};
            use std::fmt;
            fn f(x: crate::scene::Scene) -> usize { crate::render::go(); 0 }
            fn g() { println!("{}", crate::lesson::name()); }
            macro_rules! m { () => { $crate::accuracy::study() }; }
            #[cfg(test)]
            mod tests {
                use super::*;
                use super::super::super::app::Window;
            }
        "#;
        let found = references(&["geometry", "triangle"], source).unwrap();
        let modules: Vec<&str> = found.iter().map(|r| r.module.as_str()).collect();
        for expected in [
            "math", "trace", "scene", "render", "lesson", "accuracy", "app",
        ] {
            assert!(modules.contains(&expected), "{expected} in {modules:?}");
        }
        assert!(
            !modules.contains(&"std") && !modules.contains(&"fmt"),
            "{modules:?}"
        );
        let wrong = against_the_layers("geometry/triangle.rs", "geometry", &found);
        let names = ["scene", "render", "lesson", "accuracy", "app"];
        assert_eq!(wrong.len(), names.len(), "{wrong:#?}");
        for name in names {
            assert!(wrong.iter().any(|w| w.contains(name)), "{name}: {wrong:#?}");
        }
        // A sideways import is refused too, except the one SIDEWAYS allows.
        let sideways = references(&["render"], "use crate::accuracy::Study;").unwrap();
        assert_eq!(
            against_the_layers("render/mod.rs", "render", &sideways).len(),
            1
        );
        let allowed = references(&["cli"], "use crate::app::launch;").unwrap();
        assert!(against_the_layers("cli/mod.rs", "cli", &allowed).is_empty());
    }
}
