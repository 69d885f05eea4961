//! What scripts/test.sh relies on when it builds the workspace in one graph and runs only the
//! CLI's tests again without the `runtime` feature:
//! - the feature changes only `src/lib.rs`'s list of modules, the CLI's commands
//!   (`src/main.rs`, `src/cli/`) and the evaluators' GPU forms (`src/evaluator/`), so every
//!   other core module builds the same with and without it;
//! - the Bevy plugin uses no runtime module: it depends on the core without the feature, but
//!   in the workspace's build cargo unifies the core's features, where a path into a runtime
//!   module would compile.

use std::path::{Path, PathBuf};

const FEATURE: &str = "feature = \"runtime\"";

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The `.rs` files under `dir`, recursively, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(rust_files(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            files.push(path);
        }
    }
    files.sort();
    files
}

/// The modules the core compiles only with the feature: those declared right after
/// `#[cfg(feature = "runtime")]` in `src/lib.rs`.
fn runtime_modules() -> Vec<String> {
    let lib = std::fs::read_to_string(root().join("src/lib.rs")).unwrap();
    let lines: Vec<&str> = lib.lines().map(str::trim).collect();
    let modules: Vec<String> = lines
        .windows(2)
        .filter(|pair| pair[0] == format!("#[cfg({FEATURE})]"))
        .filter_map(|pair| pair[1].strip_prefix("pub mod "))
        .map(|name| name.trim_end_matches(';').to_string())
        .collect();
    assert!(
        modules.iter().any(|m| m == "gpu"),
        "no runtime modules found in src/lib.rs: {modules:?}"
    );
    modules
}

/// The first path segment after each `clothbake::` in `source`; for a `{…}` group, the first
/// segment of each of its top-level items.
fn clothbake_paths(source: &str) -> Vec<String> {
    let first_segment = |item: &str| -> String {
        item.trim()
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let mut found = Vec::new();
    for (start, _) in source.match_indices("clothbake::") {
        let rest = &source[start + "clothbake::".len()..];
        let Some(group) = rest.strip_prefix('{') else {
            found.push(first_segment(rest));
            continue;
        };
        // Top-level items: split at commas outside nested braces, stop at the group's end.
        let (mut depth, mut item_start) = (0, 0);
        for (i, c) in group.char_indices() {
            match c {
                '{' => depth += 1,
                '}' if depth > 0 => depth -= 1,
                ',' | '}' if depth == 0 => {
                    found.push(first_segment(&group[item_start..i]));
                    item_start = i + 1;
                    if c == '}' {
                        break;
                    }
                }
                _ => {}
            }
        }
    }
    found
}

/// Where the feature may appear besides the runtime's own modules: the module list, the CLI
/// (whose tests run with and without it), each evaluator's GPU form (its CPU form, the
/// same either way, is exercised without the runtime by `clothbake eval --evaluator`), and
/// unit tests.
fn may_depend_on_the_runtime(relative: &Path) -> bool {
    relative == Path::new("lib.rs")
        || relative == Path::new("main.rs")
        || relative.starts_with("cli")
        || relative.starts_with("evaluator")
        || relative.file_name().is_some_and(|n| n == "tests.rs")
}

#[test]
fn only_the_module_list_the_cli_and_gpu_forms_depend_on_the_runtime_feature() {
    let runtime = runtime_modules();
    let src = root().join("src");
    let mut checked = 0;
    for path in rust_files(&src) {
        let relative = path.strip_prefix(&src).unwrap();
        let top = relative.components().next().unwrap().as_os_str();
        let module = Path::new(top).file_stem().unwrap().to_string_lossy();
        if may_depend_on_the_runtime(relative) || runtime.iter().any(|m| *m == module) {
            continue;
        }
        let source = std::fs::read_to_string(&path).unwrap();
        assert!(
            !source.contains(FEATURE),
            "{} depends on the runtime feature: scripts/test.sh no longer tests it without",
            path.display()
        );
        checked += 1;
    }
    assert!(checked >= 20, "only {checked} core source files found");
}

#[test]
fn the_bevy_plugin_uses_only_the_core() {
    assert_eq!(
        clothbake_paths("use clothbake::{table::{a, b}, gpu::G};\nclothbake::render::x"),
        ["table", "gpu", "render"]
    );
    let runtime = runtime_modules();
    let files = rust_files(&root().join("crates/clothbake_bevy/src"));
    assert!(files.len() >= 6, "plugin sources not found: {files:?}");
    for path in files {
        let source = std::fs::read_to_string(&path).unwrap();
        for segment in clothbake_paths(&source) {
            assert!(
                !runtime.contains(&segment),
                "{} uses clothbake::{segment}, which needs the core's runtime feature",
                path.display()
            );
        }
    }
}
