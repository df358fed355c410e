//! Inputs the fuzz targets once found to panic; each must now give items without a panic.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::path::Path;

use laserlines_io::open;

/// Reads a regression input to the end; every item is a valid scan or an error naming it.
fn read_to_end(name: &str) -> Vec<String> {
    let path = Path::new("tests/fixtures/regressions").join(name);
    let file = path.display().to_string();
    open(&path, None)
        .unwrap()
        .map(|item| match item {
            Ok(r) => {
                r.scan.validate().unwrap();
                "ok".to_owned()
            }
            Err(e) => {
                assert_eq!(e.file(), file);
                e.to_string()
            }
        })
        .collect()
}

#[test]
fn json_error_column_inside_multibyte_char() {
    // A parser error whose column lands inside a two-byte UTF-8 character used to panic
    // when looking at the text around it.
    let items = read_to_end("json_error_column_inside_multibyte_char.json");
    assert_eq!(items.len(), 1);
    assert!(items[0].contains("malformed JSON"), "{}", items[0]);
}

#[test]
fn jsonl_error_column_inside_multibyte_char() {
    let items = read_to_end("jsonl_error_column_inside_multibyte_char.jsonl");
    assert!(!items.is_empty());
    assert!(
        items.iter().all(|i| i.contains("malformed JSON")),
        "{items:?}"
    );
}
