//! The library must stay free of `std` and `alloc` so it builds for a microcontroller. The crate
//! attribute makes the build `no_std` without the `std` feature (checked in CI with
//! `cargo build -p mrbrake-control --no-default-features`); this test also scans the sources so that
//! a forbidden use fails `cargo test` with the file and line.

use std::path::Path;

#[test]
fn library_sources_use_neither_std_nor_alloc() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
    assert!(lib.contains("#![cfg_attr(not(any(test, feature = \"std\")), no_std)]"));
    assert!(lib.contains("#![forbid(unsafe_code)]"));
    let forbidden =
        ["extern crate alloc", "alloc::", "Vec<", "Box<", "String", "vec!", "format!", "println!"];
    for entry in std::fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        let mut in_tests = false;
        let mut std_gated = false;
        for (n, line) in text.lines().enumerate() {
            let trimmed = line.trim_start();
            if trimmed.starts_with("#[cfg(test)]") {
                in_tests = true;
            }
            if in_tests || trimmed.starts_with("//") {
                continue;
            }
            // The one permitted use of std: the Error impl behind the `std` feature.
            if trimmed.starts_with("#[cfg(any(test, feature = \"std\"))]") {
                std_gated = true;
                continue;
            }
            if std_gated {
                std_gated = false;
                continue;
            }
            for word in forbidden.iter().chain(["std::"].iter()) {
                assert!(
                    !line.contains(word),
                    "{}:{}: uses `{word}`: {line}",
                    path.display(),
                    n + 1
                );
            }
        }
    }
}
