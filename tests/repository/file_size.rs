//! docs/architecture.md's rule that a source file holds one unit that can be read in one
//! sitting: no file under `src/` is longer than 600 lines (tests beside their code count), and
//! a longer one is split by what it holds, as `table/thread/` and `formats/wif/` are.

use std::path::Path;

/// The most lines a file of `src/` may hold.
const MOST_LINES: usize = 600;

fn long_files(dir: &Path, out: &mut Vec<String>, checked: &mut usize) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            long_files(&path, out, checked);
        } else if path.extension().is_some_and(|e| e == "rs") {
            *checked += 1;
            let lines = std::fs::read_to_string(&path).unwrap().lines().count();
            if lines > MOST_LINES {
                out.push(format!("{}: {lines} lines", path.display()));
            }
        }
    }
}

#[test]
fn no_source_file_is_longer_than_600_lines() {
    let (mut long, mut checked) = (Vec::new(), 0);
    long_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut long,
        &mut checked,
    );
    assert!(checked > 100, "only {checked} source files found");
    assert!(
        long.is_empty(),
        "longer than {MOST_LINES} lines:\n{}",
        long.join("\n")
    );
}
