//! docs/architecture.md's rule that the modules of `src/` import one another without cycles:
//! a file that another file imports does not import it back, directly or through others.
//!
//! Each `.rs` file of `src/` is a module (`a/mod.rs` is `a`). A file depends on the module
//! each of its paths names (`crate::…`, `super::…`, `self::…`, or a child module's name), the
//! longest prefix of the path that is a module file; `use` trees are expanded. A module and
//! its ancestors are exempt from each other: a parent declares and re-exports its children,
//! and children use the types their parent defines, which is Rust's layout rather than a
//! cycle. Unit tests (`#[cfg(test)] mod …` at the end of a file) are left out, since they may
//! reach anything to check it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

type Module = Vec<String>;

/// Every `.rs` file under `dir`, with its module path below `src/`.
fn modules(root: &Path, dir: &Path, out: &mut BTreeMap<Module, PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            modules(root, &path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let relative = path.strip_prefix(root).unwrap().with_extension("");
            let mut module: Module = relative
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            if matches!(
                module.last().map(String::as_str),
                Some("mod" | "lib" | "main")
            ) {
                module.pop();
            }
            // Unit tests in a file of their own (`#[cfg(test)] mod tests;`).
            if module.last().is_some_and(|m| m == "tests") {
                continue;
            }
            out.insert(module, path);
        }
    }
}

/// The source without comments, string and character literals' contents, and the unit
/// tests at its end.
fn code_of(source: &str) -> String {
    let mut out = String::with_capacity(source.len());
    let chars: Vec<char> = source.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if c == '"' {
            // A string (raw strings of this crate hold no unbalanced quote): skip to its end.
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                i += if chars[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == '\'' && next.is_some_and(|n| n != '\\') && chars.get(i + 2) == Some(&'\'') {
            // A character literal such as ',' or '{' (not a lifetime).
            i += 3;
        } else if c == '\'' && next == Some('\\') {
            i += 2;
            while i < chars.len() && chars[i] != '\'' {
                i += 1;
            }
            i += 1;
        } else {
            out.push(c);
            i += 1;
        }
    }
    match out.find("#[cfg(test)]\nmod ") {
        Some(at) => out[..at].to_string(),
        None => out,
    }
}

/// The paths a `use` tree names, braces expanded: `a::{b, c::{d, e}}` is `a::b`, `a::c::d`,
/// `a::c::e`.
fn expand_use(tree: &str, prefix: &str, out: &mut Vec<String>) {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        let path = tree.split(" as ").next().unwrap_or("").trim();
        out.push(format!("{prefix}{path}"));
        return;
    };
    let head = &tree[..open];
    let body = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
    let (mut depth, mut start) = (0, 0);
    for (k, c) in body.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                expand_use(&body[start..k], &format!("{prefix}{head}"), out);
                start = k + 1;
            }
            _ => {}
        }
    }
    if !body[start..].trim().is_empty() {
        expand_use(&body[start..], &format!("{prefix}{head}"), out);
    }
}

/// Every path of `code`: the expanded `use` trees, and each `a::b::…` in expressions and types.
fn paths_of(code: &str) -> Vec<String> {
    let mut paths = Vec::new();
    let is_ident = |c: char| c.is_alphanumeric() || c == '_';
    let bytes: Vec<char> = code.chars().collect();
    let mut i = 0;
    while i < bytes.len() {
        let starts_word = i == 0 || !is_ident(bytes[i - 1]);
        if starts_word && code_at(&bytes, i, "use ") {
            let end = (i..bytes.len())
                .find(|&k| bytes[k] == ';')
                .unwrap_or(bytes.len());
            let tree: String = bytes[i + 4..end].iter().collect();
            expand_use(&tree, "", &mut paths);
            i = end;
            continue;
        }
        if starts_word && is_ident(bytes[i]) {
            let mut end = i;
            loop {
                while end < bytes.len() && is_ident(bytes[end]) {
                    end += 1;
                }
                if code_at(&bytes, end, "::") && bytes.get(end + 2).is_some_and(|&c| is_ident(c)) {
                    end += 2;
                } else {
                    break;
                }
            }
            let path: String = bytes[i..end].iter().collect();
            if path.contains("::") {
                paths.push(path);
            }
            i = end.max(i + 1);
            continue;
        }
        i += 1;
    }
    paths
}

fn code_at(chars: &[char], at: usize, text: &str) -> bool {
    text.chars()
        .enumerate()
        .all(|(k, c)| chars.get(at + k) == Some(&c))
}

/// The module file a path in module `from` names: the longest prefix of it that is a module.
fn resolve(from: &Module, path: &str, modules: &BTreeMap<Module, PathBuf>) -> Option<Module> {
    let mut segments = path.split("::").map(str::trim).filter(|s| !s.is_empty());
    let first = segments.next()?;
    let mut base: Module = match first {
        "crate" => vec![],
        "self" => from.clone(),
        "super" => from[..from.len().checked_sub(1)?].to_vec(),
        child => {
            let mut module = from.clone();
            module.push(child.to_string());
            if !modules.contains_key(&module) {
                return None;
            }
            module
        }
    };
    let mut rest: Vec<&str> = segments.collect();
    while rest.first() == Some(&"super") {
        base.pop();
        rest.remove(0);
    }
    let mut best = modules.contains_key(&base).then(|| base.clone());
    for segment in rest {
        base.push(segment.to_string());
        if modules.contains_key(&base) {
            best = Some(base.clone());
        } else {
            break;
        }
    }
    best
}

fn is_ancestor(a: &Module, b: &Module) -> bool {
    a.len() < b.len() && b[..a.len()] == a[..]
}

fn name(module: &Module) -> String {
    if module.is_empty() {
        "lib".into()
    } else {
        module.join("/")
    }
}

/// The import graph of `src/`: each module's dependencies, with a path that makes each.
fn import_graph() -> BTreeMap<Module, BTreeMap<Module, String>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = BTreeMap::new();
    modules(&root, &root, &mut files);
    let mut graph = BTreeMap::new();
    for (module, path) in &files {
        let code = code_of(&std::fs::read_to_string(path).unwrap());
        let mut edges = BTreeMap::new();
        for path in paths_of(&code) {
            if let Some(target) = resolve(module, &path, &files)
                && target != *module
                && !is_ancestor(&target, module)
                && !is_ancestor(module, &target)
            {
                edges.entry(target).or_insert(path);
            }
        }
        graph.insert(module.clone(), edges);
    }
    graph
}

/// The modules `from` reaches through the graph, itself excluded unless on a cycle.
fn reachable(
    graph: &BTreeMap<Module, BTreeMap<Module, String>>,
    from: &Module,
) -> BTreeSet<Module> {
    let mut seen = BTreeSet::new();
    let mut stack: Vec<&Module> = graph[from].keys().collect();
    while let Some(m) = stack.pop() {
        if seen.insert(m.clone()) {
            stack.extend(graph.get(m).into_iter().flat_map(|e| e.keys()));
        }
    }
    seen
}

#[test]
fn the_modules_import_one_another_without_cycles() {
    let graph = import_graph();
    assert!(graph.len() > 100, "only {} modules found", graph.len());
    let edges: usize = graph.values().map(BTreeMap::len).sum();
    assert!(edges > 200, "only {edges} imports found");
    let mut cycles = Vec::new();
    for (module, imports) in &graph {
        for (target, path) in imports {
            if reachable(&graph, target).contains(module) {
                cycles.push(format!(
                    "{} imports {} ({path}), which imports it back",
                    name(module),
                    name(target)
                ));
            }
        }
    }
    assert!(cycles.is_empty(), "import cycles:\n{}", cycles.join("\n"));
}

/// The checker finds a cycle where there is one and reads `use` trees and paths as Rust
/// writes them, so that its silence above means something.
#[test]
fn the_checker_sees_paths_and_cycles() {
    let mut paths = Vec::new();
    expand_use("super::{a::{B, c}, d as e}", "", &mut paths);
    assert_eq!(paths, ["super::a::B", "super::a::c", "super::d"]);
    let code = code_of(
        "use crate::x::Y; // crate::commented::Out\nfn f() { let _ = \"crate::in_string\"; \
         crate::z::w(); }\n#[cfg(test)]\nmod tests { use crate::t::U; }\n",
    );
    assert_eq!(paths_of(&code), ["crate::x::Y", "crate::z::w"]);

    let module = |s: &str| -> Module { s.split('/').map(String::from).collect() };
    let files: BTreeMap<Module, PathBuf> = ["a", "a/b", "a/c", "d"]
        .into_iter()
        .map(|m| (module(m), PathBuf::new()))
        .collect();
    assert_eq!(
        resolve(&module("a/b"), "super::c::Item", &files),
        Some(module("a/c"))
    );
    assert_eq!(
        resolve(&module("a/b"), "crate::d::f", &files),
        Some(module("d"))
    );
    assert_eq!(
        resolve(&module("a"), "b::Item", &files),
        Some(module("a/b"))
    );
    assert_eq!(resolve(&module("a/b"), "std::fmt::Write", &files), None);

    let graph: BTreeMap<Module, BTreeMap<Module, String>> =
        [("a/b", "a/c"), ("a/c", "d"), ("d", "a/b")]
            .into_iter()
            .map(|(from, to)| (module(from), BTreeMap::from([(module(to), String::new())])))
            .collect();
    assert!(reachable(&graph, &module("a/c")).contains(&module("a/b")));
}
