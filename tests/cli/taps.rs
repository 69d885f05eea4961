//! `clothbake bake` stores each table's sample taps beside it (`NAME.taps`): built with the
//! table, found up to date on the next run, built again where the file is damaged, none with
//! `--no-taps`.

use crate::bake::clothbake;
use crate::common::*;

#[test]
fn bake_stores_sample_taps_with_each_table_and_keeps_them_up_to_date() {
    let dir = temp_dir("taps");
    let out = path_str(&dir);
    let args = [
        "bake",
        "--fabric",
        "velvet",
        "--layout",
        "grid4d",
        "--resolution",
        "4",
        "--env-samples",
        "3",
        "--out",
        out,
    ];
    let first = clothbake(&args);
    let text = output_text(&first);
    assert!(first.status.success(), "{text}");
    assert!(
        text.contains("velvet: sample taps for 3 environment samples built (the table was baked)"),
        "{text}"
    );
    let taps = dir.join("velvet.taps");
    let bytes = std::fs::read(&taps).unwrap();
    assert_eq!(&bytes[..8], b"CLOTHTAP");

    let second = clothbake(&args);
    let text = output_text(&second);
    assert!(
        text.contains("up to date")
            && text.contains("sample taps for 3 environment samples up to date"),
        "{text}"
    );
    assert_eq!(std::fs::read(&taps).unwrap(), bytes);

    // A damaged taps file beside an up-to-date table is built again, with the reason.
    std::fs::write(&taps, &bytes[..100]).unwrap();
    let third = clothbake(&args);
    let text = output_text(&third);
    assert!(third.status.success(), "{text}");
    assert!(text.contains("truncated"), "{text}");
    assert_eq!(std::fs::read(&taps).unwrap(), bytes);

    // Another sample count: built again for it.
    let mut other = args.to_vec();
    other[8] = "5";
    let fourth = clothbake(&other);
    assert!(
        output_text(&fourth).contains("3 samples per pixel, not 5"),
        "{}",
        output_text(&fourth)
    );

    let plain = temp_dir("no-taps");
    let fifth = clothbake(&[
        "bake",
        "--fabric",
        "velvet",
        "--layout",
        "grid4d",
        "--resolution",
        "4",
        "--no-taps",
        "--out",
        path_str(&plain),
    ]);
    assert!(fifth.status.success(), "{}", output_text(&fifth));
    assert!(plain.join("velvet.exr").exists() && !plain.join("velvet.taps").exists());
}
