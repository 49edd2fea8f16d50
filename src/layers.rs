//! The direction of imports, checked: each top-level module may import only modules of a lower layer, so
//! the core never depends on the app and no two modules depend on each other. The README's Layout
//! section explains the layers; [`LAYERS`] is the rule, and the test below fails on any `crate::…` path
//! that goes up or sideways. Unit tests (`#[cfg(test)]` to the end of a file, and `tests.rs` files) may
//! use anything.

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
    // What is built on scenes: the renderer, the accuracy study, lessons.
    &["render", "accuracy", "lesson"],
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
    use std::path::Path;

    fn layer(module: &str) -> Option<usize> {
        LAYERS.iter().position(|layer| layer.contains(&module))
    }

    /// The top-level modules named in `crate::` paths of `code`, grouped paths included
    /// (`crate::{a::{X, Y}, b}` names a and b).
    fn imported_modules(code: &str) -> Vec<String> {
        let name_at = |text: &str| -> String {
            text.trim_start()
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect()
        };
        let mut found = Vec::new();
        for (start, _) in code.match_indices("crate::") {
            let rest = &code[start + "crate::".len()..];
            let Some(group) = rest.strip_prefix('{') else {
                found.push(name_at(rest));
                continue;
            };
            // Each item of the group starts at the group's opening brace or after a comma at depth 0.
            let mut depth = 0;
            let mut item_start = 0;
            for (i, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => {
                        found.push(name_at(&group[item_start..i]));
                        break;
                    }
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        found.push(name_at(&group[item_start..i]));
                        item_start = i + 1;
                    }
                    _ => {}
                }
            }
        }
        found.retain(|name| !name.is_empty());
        found
    }

    /// The code of a file that is not a unit test and not a comment.
    fn code_outside_tests(text: &str) -> String {
        let before_tests = text.split("#[cfg(test)]").next().unwrap_or("");
        before_tests
            .lines()
            .filter(|line| !line.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n")
    }

    fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
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
            let top = relative
                .components()
                .next()
                .and_then(|c| c.as_os_str().to_str())
                .map(|name| name.trim_end_matches(".rs"))
                .unwrap_or("");
            if ["lib", "main", "layers"].contains(&top) || relative.ends_with("tests.rs") {
                continue;
            }
            let own =
                layer(top).unwrap_or_else(|| panic!("{top} is in no layer: add it to LAYERS"));
            let text = std::fs::read_to_string(file).expect("a source file is readable");
            for module in imported_modules(&code_outside_tests(&text)) {
                checked += 1;
                if module == top || module == "self" || module == "super" {
                    continue;
                }
                let Some(theirs) = layer(&module) else {
                    wrong.push(format!(
                        "{}: crate::{module} is in no layer",
                        relative.display()
                    ));
                    continue;
                };
                let sideways_allowed = SIDEWAYS.contains(&(top, module.as_str()));
                if theirs > own || (theirs == own && !sideways_allowed) {
                    wrong.push(format!(
                        "{}: {top} (layer {own}) imports crate::{module} (layer {theirs})",
                        relative.display()
                    ));
                }
            }
        }
        wrong.sort();
        wrong.dedup();
        assert!(
            checked > 100,
            "only {checked} imports found: is the parser broken?"
        );
        assert!(
            wrong.is_empty(),
            "imports against the layers:\n{}",
            wrong.join("\n")
        );
    }

    /// The check itself catches an upward import, a grouped one included.
    #[test]
    fn the_check_sees_grouped_and_plain_paths() {
        let code = "use crate::{math::{Real, real::X}, app::Y};\nlet y = crate::render::go();";
        assert_eq!(imported_modules(code), ["math", "app", "render"]);
        let with_tests = "use crate::math;\n#[cfg(test)]\nmod tests { use crate::app; }";
        assert_eq!(imported_modules(&code_outside_tests(with_tests)), ["math"]);
    }
}
