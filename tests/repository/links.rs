//! The documentation's links: every relative link in the README, `docs/` and the crates'
//! READMEs names a file of the repository and, with `#anchor`, a heading of that page; and
//! no file points outside the repository (a clone carries everything it cites).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The Markdown pages whose links are checked.
fn pages() -> Vec<PathBuf> {
    let mut pages = vec![root().join("README.md")];
    for dir in ["docs", "crates"] {
        let mut stack = vec![root().join(dir)];
        while let Some(dir) = stack.pop() {
            for entry in std::fs::read_dir(&dir).unwrap().flatten() {
                let path = entry.path();
                if path.is_dir() {
                    if path.file_name().is_some_and(|n| n != "target") {
                        stack.push(path);
                    }
                } else if path.extension().is_some_and(|e| e == "md") {
                    pages.push(path);
                }
            }
        }
    }
    pages.sort();
    pages
}

/// The targets of inline links `[text](target)` outside code blocks and code spans.
fn link_targets(text: &str) -> Vec<String> {
    let mut targets = Vec::new();
    let mut in_fence = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_fence = !in_fence;
            continue;
        }
        if in_fence {
            continue;
        }
        // Code spans hold example syntax, not links.
        let outside_code: String = line
            .split('`')
            .enumerate()
            .filter(|(i, _)| i % 2 == 0)
            .map(|(_, s)| s)
            .collect::<Vec<_>>()
            .join(" ");
        let mut rest = outside_code.as_str();
        while let Some(start) = rest.find("](") {
            let after = &rest[start + 2..];
            let Some(end) = after.find(')') else { break };
            let target = after[..end].split_whitespace().next().unwrap_or("");
            targets.push(target.to_string());
            rest = &after[end..];
        }
    }
    targets
}

#[path = "../common/anchor.rs"]
mod anchor;
use anchor::github_anchor as slug;

/// The anchors of a page's headings (outside code blocks), with GitHub's `-1`, `-2` suffixes
/// for repeated headings.
fn anchors(text: &str) -> BTreeSet<String> {
    let mut anchors = BTreeSet::new();
    let mut in_fence = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_fence = !in_fence;
            continue;
        }
        if in_fence || !line.starts_with('#') {
            continue;
        }
        let heading = line.trim_start_matches('#');
        if !heading.starts_with(' ') {
            continue;
        }
        let base = slug(&heading.replace('`', ""));
        let mut anchor = base.clone();
        let mut n = 0;
        while anchors.contains(&anchor) {
            n += 1;
            anchor = format!("{base}-{n}");
        }
        anchors.insert(anchor);
    }
    anchors
}

#[test]
fn every_documentation_link_resolves() {
    let root = root().canonicalize().unwrap();
    let mut broken = Vec::new();
    let mut checked = 0;
    for page in pages() {
        let text = std::fs::read_to_string(&page).unwrap();
        for target in link_targets(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            checked += 1;
            let (path, anchor) = target.split_once('#').unwrap_or((&target, ""));
            let file = if path.is_empty() {
                page.clone()
            } else {
                page.parent().unwrap().join(path)
            };
            let Ok(resolved) = file.canonicalize() else {
                broken.push(format!("{}: {target} (no such file)", page.display()));
                continue;
            };
            if !resolved.starts_with(&root) {
                broken.push(format!(
                    "{}: {target} (outside the repository)",
                    page.display()
                ));
                continue;
            }
            if !anchor.is_empty() && resolved.extension().is_some_and(|e| e == "md") {
                let headings = anchors(&std::fs::read_to_string(&resolved).unwrap());
                if !headings.contains(anchor) {
                    broken.push(format!("{}: {target} (no such heading)", page.display()));
                }
            }
        }
    }
    println!("checked {checked} links");
    assert!(
        checked > 50,
        "only {checked} links found: is the link parser broken?"
    );
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn no_file_points_outside_the_repository() {
    let output = std::process::Command::new("git")
        .args(["ls-files", "-z"])
        .current_dir(root())
        .output()
        .expect("git runs");
    let files = String::from_utf8(output.stdout).unwrap();
    // Spelled in pieces so that this file does not name the paths it looks for.
    let patterns = [["..", "shared"].join("/"), ["shared", "MODEL.md"].join("/")];
    let mut offenders = Vec::new();
    for file in files.split('\0').filter(|f| !f.is_empty()) {
        let Ok(text) = std::fs::read_to_string(root().join(file)) else {
            continue; // binary files (images, EXR test data)
        };
        if patterns.iter().any(|p| text.contains(p.as_str())) {
            offenders.push(file.to_string());
        }
    }
    assert!(
        offenders.is_empty(),
        "files that point outside the repository: {offenders:?}"
    );
}

#[test]
fn slugs_follow_github() {
    assert_eq!(
        slug("Which table or evaluation to pick"),
        "which-table-or-evaluation-to-pick"
    );
    assert_eq!(
        slug("Shadowing and masking (M, P)"),
        "shadowing-and-masking-m-p"
    );
    assert_eq!(slug("`clothbake render`"), "clothbake-render");
    let repeated = anchors("## Notes\ntext\n## Notes\n");
    assert!(repeated.contains("notes") && repeated.contains("notes-1"));
    assert_eq!(link_targets("see [a](b.md#c) and `[x](y)`"), vec!["b.md#c"]);
}
