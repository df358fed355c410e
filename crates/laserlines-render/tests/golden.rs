//! Golden SVG of the paper's figures for one fixed synthetic scan.
//!
//! Run with `REGENERATE=1` to rewrite `tests/golden/hough_split.svg` after an intended change
//! (of the figure, or of the extractor's defaults), then review the picture and commit it.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers fail loudly

mod common;

use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};
use laserlines_render::{RenderOptions, render_hough_split};

#[test]
fn hough_split_figure_matches_golden_file() {
    let scan = common::room_scan();
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let lines = hs.extract(&scan);
    let svg = render_hough_split(&scan, &hs, &lines, &RenderOptions::default());
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/hough_split.svg");
    if std::env::var("REGENERATE").is_ok_and(|v| v == "1") {
        std::fs::write(&path, &svg).unwrap();
        return;
    }
    let golden = std::fs::read_to_string(&path).unwrap_or_default();
    if golden != svg {
        let actual = std::env::temp_dir().join("laserlines-render-hough_split.actual.svg");
        std::fs::write(&actual, &svg).unwrap();
        let first_diff = golden
            .lines()
            .zip(svg.lines())
            .position(|(a, b)| a != b)
            .map_or_else(
                || "in the length".to_owned(),
                |k| format!("at line {}", k + 1),
            );
        panic!(
            "the figure differs from {} ({first_diff}); the new one is in {}. If the change is \
             intended, rerun with REGENERATE=1 and commit the new golden file.",
            path.display(),
            actual.display()
        );
    }
}
