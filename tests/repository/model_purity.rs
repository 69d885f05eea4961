//! The invariant docs/architecture.md names first: the model is pure maths. `src/model/`
//! reads and writes nothing and depends on no other module of the crate, so that every
//! other part depends on it and not the reverse. The weaves beside it (`src/weave/`) are pure
//! maths too, over the model alone: WIF files are read in `src/formats/`.

use std::path::Path;

/// Checks that the `.rs` files of `folder` do no I/O and name no module of the crate but
/// `allowed`; returns how many files were checked.
fn check_pure(folder: &str, allowed: &[&str]) -> usize {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join(folder);
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap().flatten() {
        let path = entry.path();
        if path.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        let source = std::fs::read_to_string(&path).unwrap();
        for (number, line) in source.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for forbidden in [
                "std::fs",
                "std::io",
                "File::",
                "println!",
                "eprintln!",
                "print!",
                "std::env",
            ] {
                assert!(
                    !code.contains(forbidden),
                    "{}:{}: pure maths does I/O ({forbidden})",
                    path.display(),
                    number + 1
                );
            }
            if let Some(at) = code.find("crate::") {
                assert!(
                    allowed.iter().any(|a| code[at..].starts_with(a)),
                    "{}:{}: {folder} depends on {}",
                    path.display(),
                    number + 1,
                    &code[at..]
                );
            }
        }
        checked += 1;
    }
    checked
}

#[test]
fn the_model_does_no_io_and_depends_on_nothing_else_in_the_crate() {
    let checked = check_pure("src/model", &["crate::model"]);
    assert!(checked >= 5, "only {checked} model files found");
}

#[test]
fn the_weaves_do_no_io_and_depend_on_the_model_alone() {
    let checked = check_pure("src/weave", &["crate::model", "crate::weave"]);
    assert!(checked >= 4, "only {checked} weave files found");
}
