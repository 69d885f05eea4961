//! The invariant docs/architecture.md names first: the model is pure maths. `src/model/`
//! reads and writes nothing and depends on no other module of the crate, so that every
//! other part depends on it and not the reverse.

use std::path::Path;

#[test]
fn the_model_does_no_io_and_depends_on_nothing_else_in_the_crate() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/model");
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
                    "{}:{}: the model does I/O ({forbidden})",
                    path.display(),
                    number + 1
                );
            }
            if let Some(at) = code.find("crate::") {
                assert!(
                    code[at..].starts_with("crate::model"),
                    "{}:{}: the model depends on {}",
                    path.display(),
                    number + 1,
                    &code[at..]
                );
            }
        }
        checked += 1;
    }
    assert!(checked >= 5, "only {checked} model files found");
}
