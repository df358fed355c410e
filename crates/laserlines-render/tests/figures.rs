//! Structure of the rendered figures: well-formed XML, one mark per drawn object, no panic
//! and no NaN on any input.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers fail loudly

mod common;

use common::{Element, parse};
use laserlines::math::Point2;
use laserlines::{HoughSplit, HoughSplitParams, Line, LineExtractor, Scan};
use laserlines_render::{
    Axis, Canvas, Color, Extent, LegendEntry, Marker, Panel, RenderOptions, ScatterChart, Style,
    Swatch, TextStyle, render_hough_split, render_scan_lines,
};

fn hough(scan: &Scan) -> (HoughSplit, Vec<Line>, String) {
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let lines = hs.extract(scan);
    let svg = render_hough_split(scan, &hs, &lines, &RenderOptions::default());
    (hs, lines, svg)
}

/// Panels (a), (c) and (d) draw every point, every data segment (its chord, its two ends
/// and its points) and every line of `hs`'s last scan.
fn assert_stage_marks(root: &Element, hs: &HoughSplit, lines: &[Line]) {
    let st = hs.stages();
    assert_eq!(
        root.count_in_group("raw-point", "circle"),
        st.points().len()
    );
    let segments = st.segments().count();
    assert_eq!(root.count("line", "segment-chord"), segments);
    assert_eq!(root.count_in_group("segment-end", "rect"), 2 * segments);
    assert_eq!(
        root.count_in_group("segment-point", "circle"),
        st.kept().count()
    );
    assert_eq!(root.count("line", "extracted-line"), lines.len());
}

fn panels(root: &Element) -> Vec<&Element> {
    root.children
        .iter()
        .filter(|e| e.name == "g" && e.has_class("panel"))
        .collect()
}

/// Every number in the document is finite and written plainly (no exponent, no NaN).
fn assert_plain_numbers(svg: &str) {
    let root = parse(svg).unwrap();
    let numeric = [
        "x",
        "y",
        "x1",
        "y1",
        "x2",
        "y2",
        "cx",
        "cy",
        "r",
        "width",
        "height",
        "stroke-width",
        "font-size",
        "opacity",
    ];
    for e in root.find_all(&|_| true) {
        for (k, v) in &e.attrs {
            if numeric.contains(&k.as_str()) {
                let x: f64 = v
                    .parse()
                    .unwrap_or_else(|_| panic!("{k}={v:?} is not a number"));
                assert!(x.is_finite() && !v.contains(['e', 'E']), "{k}={v:?}");
            }
            if ["d", "points", "viewBox", "transform", "stroke-dasharray"].contains(&k.as_str()) {
                let ok = v
                    .chars()
                    .all(|c| c.is_ascii_digit() || " .,-MLtranslateo()".contains(c));
                assert!(ok, "{k}={v:?}");
            }
        }
    }
}

/// Line marks inside each panel's plot stay near the plot area (clipped geometry).
fn assert_clipped(root: &Element) {
    for panel in panels(root) {
        let rect = panel
            .find_all(&|e| e.name == "rect" && e.has_class("frame"))
            .first()
            .map(|r| {
                (
                    r.attr("width").unwrap().parse::<f64>().unwrap(),
                    r.attr("height").unwrap().parse::<f64>().unwrap(),
                )
            })
            .unwrap();
        for plot in panel.find_all(&|e| e.name == "g" && e.has_class("plot")) {
            for l in plot.find_all(&|e| e.name == "line") {
                for (k, lim) in [
                    ("x1", rect.0),
                    ("x2", rect.0),
                    ("y1", rect.1),
                    ("y2", rect.1),
                ] {
                    let v: f64 = l.attr(k).unwrap().parse().unwrap();
                    assert!(
                        (-12.001..=lim + 12.001).contains(&v),
                        "{k}={v} outside the plot"
                    );
                }
            }
        }
    }
}

#[test]
fn hough_figure_draws_a_full_turn_across_its_seam() {
    // The wall x = 0 lies across the seam: one line, and one data segment of the walk's
    // points, drawn whole in panel (c); no field of view in panel (a).
    let scan = common::turn_scan();
    let (hs, lines, svg) = hough(&scan);
    let root = parse(&svg).unwrap();
    let st = hs.stages();
    assert!(
        lines
            .iter()
            .any(|l| l.wraps() && l.covers(0) && (l.r - 1.3).abs() < 0.03)
    );
    assert!(st.segments().any(|s| s.covers(359) && s.covers(0)));
    assert_stage_marks(&root, &hs, &lines);
    assert_eq!(root.count("line", "field-of-view"), 0);
}

#[test]
fn hough_figure_draws_every_stage() {
    let scan = common::room_scan();
    let (hs, lines, svg) = hough(&scan);
    let root = parse(&svg).unwrap();
    assert_eq!(root.name, "svg");
    assert_plain_numbers(&svg);
    assert_clipped(&root);
    let st = hs.stages();
    assert_eq!(panels(&root).len(), 4);
    // The scene has walls and a box: the pipeline found something to draw in every panel.
    assert!(lines.len() >= 6, "{} lines", lines.len());
    assert!(!st.removed().is_empty());

    // (a), (c) and (d): every point the extractor used, every segment and every line.
    assert_stage_marks(&root, &hs, &lines);
    // The robot in each panel.
    assert_eq!(root.count("polygon", "robot"), 4);
    // (b) one mark per cell, kept or not.
    let kept = st.cells().iter().filter(|c| c.kept).count();
    assert!(kept > 0);
    assert_eq!(root.count("line", "cell-kept"), kept);
    assert_eq!(root.count("line", "cell-rejected"), st.cells().len() - kept);
    // (c) radius groups and removed points.
    assert_eq!(root.count("path", "radius-group"), st.radius_groups().len());
    assert_eq!(
        root.count_in_group("removed-point", "path"),
        st.removed().len()
    );
    // (d) the lines' end points, over the faint points.
    assert_eq!(root.count_in_group("line-end", "circle"), 2 * lines.len());
    assert_eq!(
        root.count_in_group("faint-point", "circle"),
        st.points().len()
    );
    // Axes, scale bars and one legend.
    for panel in panels(&root) {
        assert_eq!(panel.count("g", "scale-bar"), 1);
        assert_eq!(panel.count("text", "axis-label"), 2);
        assert!(panel.count("text", "tick-label") >= 4);
    }
    assert_eq!(root.count("g", "legend"), 1);
    let legend = root.find_all(&|e| e.has_class("legend"))[0].all_text();
    for words in [
        "valid point",
        "robot",
        "kept cell",
        "radius group",
        "removed point",
        "extracted line",
        "line end point",
    ] {
        assert!(legend.contains(words), "legend lacks {words:?}: {legend}");
    }
}

#[test]
fn same_input_gives_the_same_bytes() {
    let scan = common::room_scan();
    assert_eq!(hough(&scan).2, hough(&scan).2);
}

#[test]
fn degenerate_scans_give_empty_panels_with_a_note() {
    let empty = Scan::new(-1.0, 0.01, 0.02, 5.6, vec![]).unwrap();
    let invalid = Scan::new(
        -1.0,
        0.01,
        0.02,
        5.6,
        vec![f64::NAN, 0.0, -1.0, f64::INFINITY, 9.0],
    )
    .unwrap();
    let broken = Scan {
        angle_min: f64::NAN,
        angle_increment: f64::INFINITY,
        range_min: f64::NAN,
        range_max: -1.0,
        ranges: vec![1.0, f64::NAN, 1e300],
        intensities: None,
        stamp: None,
    };
    for scan in [empty, invalid, broken] {
        let (_, lines, svg) = hough(&scan);
        assert!(lines.is_empty());
        let root = parse(&svg).unwrap();
        assert_plain_numbers(&svg);
        assert_eq!(panels(&root).len(), 4);
        let notes = root.find_all(&|e| e.name == "text" && e.has_class("note"));
        assert_eq!(notes.len(), 4, "{svg}");
        assert!(notes[0].text.contains("no valid points"));
        let one = render_scan_lines(&scan, &lines, &RenderOptions::default());
        let root = parse(&one).unwrap();
        assert_eq!(panels(&root).len(), 1);
        assert_eq!(root.count("text", "note"), 1);
    }
}

#[test]
fn far_points_and_bad_lines_stay_out_of_the_picture() {
    // A wall 2 m ahead with one point 1e300 m away, lines with NaN, and a view that is not
    // valid.
    let mut ranges: Vec<f64> = (0..50)
        .map(|i| 2.0 / (-0.5 + 0.02 * f64::from(i)).cos())
        .collect();
    ranges[10] = 1e300;
    let scan = Scan::new(-0.5, 0.02, 0.0, f64::MAX, ranges).unwrap();
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let mut lines = hs.extract(&scan);
    let mut bad = lines.first().copied().unwrap();
    bad.start = Point2::new(f64::NAN, 0.0);
    lines.push(bad);
    let opts = RenderOptions {
        view: Some(Extent::new(1.0, f64::NAN, 0.0, 2.0)),
        width: f64::NAN,
        title: None,
    };
    for svg in [
        render_hough_split(&scan, &hs, &lines, &opts),
        render_scan_lines(&scan, &lines, &opts),
    ] {
        let root = parse(&svg).unwrap();
        assert_plain_numbers(&svg);
        assert_clipped(&root);
        assert_eq!(root.count("line", "extracted-line"), lines.len() - 1);
    }
}

#[test]
fn a_view_crops_the_picture() {
    let scan = common::room_scan();
    let (hs, lines, _) = hough(&scan);
    let opts = RenderOptions {
        view: Some(Extent::new(0.0, -1.0, 2.0, 1.0)),
        width: 700.0,
        title: Some("crop".into()),
    };
    let svg = render_hough_split(&scan, &hs, &lines, &opts);
    let root = parse(&svg).unwrap();
    assert_clipped(&root);
    // Fewer points fall inside the crop than the scan has.
    let shown = root.count_in_group("raw-point", "circle");
    assert!(shown > 0 && shown < hs.stages().points().len());
    assert!(root.attr("width").unwrap().parse::<f64>().unwrap() <= 700.5);
}

#[test]
fn text_is_escaped() {
    let scan = common::room_scan();
    let opts = RenderOptions {
        title: Some("walls <&> \"quotes\" 'and' \u{7}bell".into()),
        ..RenderOptions::default()
    };
    let svg = render_scan_lines(&scan, &[], &opts);
    assert!(svg.contains("&lt;&amp;&gt; &quot;quotes&quot; &apos;and&apos;"));
    let root = parse(&svg).unwrap();
    let title = root.find_all(&|e| e.name == "text" && e.has_class("figure-title"));
    assert_eq!(title[0].text, "walls <&> \"quotes\" 'and' \u{FFFD}bell");
}

#[test]
fn scan_lines_figure_has_one_panel_and_every_line() {
    let scan = common::room_scan();
    let (_, lines, _) = hough(&scan);
    let svg = render_scan_lines(&scan, &lines, &RenderOptions::default());
    let root = parse(&svg).unwrap();
    assert_eq!(panels(&root).len(), 1);
    assert_eq!(root.count("line", "extracted-line"), lines.len());
    assert_eq!(root.count_in_group("line-end", "circle"), 2 * lines.len());
    assert_eq!(root.count("polygon", "robot"), 1);
}

#[test]
fn scatter_chart_labels_every_shown_point() {
    let mut chart = ScatterChart::new("Accuracy & speed", "time per scan [us]", "walls found [%]");
    chart.log_x = true;
    for (x, y, name) in [
        (4.0, 100.0, "hough-split"),
        (480.0, 97.0, "split-and-merge"),
        (50.0, 95.0, "incremental"),
        (55.0, 95.5, "line-regression"),
        (0.0, 90.0, "not on a log axis"),
        (f64::NAN, 1.0, "nan"),
    ] {
        chart.add(x, y, name);
    }
    let svg = chart.to_svg();
    let root = parse(&svg).unwrap();
    assert_plain_numbers(&svg);
    assert_eq!(root.count_in_group("chart-point", "circle"), 4);
    assert_eq!(root.count("text", "chart-label"), 4);
    let ticks: Vec<String> = root
        .find_all(&|e| e.has_class("tick-label"))
        .iter()
        .map(|e| e.text.clone())
        .collect();
    for decade in ["1", "10", "100", "1000"] {
        assert!(ticks.iter().any(|t| t == decade), "{ticks:?}");
    }
    let note = root.find_all(&|e| e.has_class("note"));
    assert!(note[0].text.starts_with("2 of 6 points not shown"));
    // An empty chart is still a document.
    let empty = ScatterChart::new("empty", "x", "y").to_svg();
    assert_eq!(parse(&empty).unwrap().count("text", "note"), 1);
}

#[test]
fn building_blocks_compose() {
    let mut map = Panel::map(Extent::new(-3.0, -3.0, 3.0, 3.0), 300.0);
    let sector = Style::stroke(Color::BLUE, 1.0)
        .with_fill(Color::BLUE)
        .with_opacity(0.2)
        .with_class("sector");
    let (l, f) = (70.0_f64.to_radians(), 50.0_f64.to_radians());
    map.wedge(Point2::origin(), 0.0, 2.0, f, f + l, &sector);
    map.wedge(Point2::origin(), 0.5, 2.0, -f, f, &sector);
    map.wedge(Point2::origin(), 0.0, 10.0, -f - l, -f, &sector);
    map.polyline(
        &[
            Point2::new(-2.0, -2.0),
            Point2::new(0.0, 1.0),
            Point2::new(5.0, 1.0),
        ],
        &Style::stroke(Color::NAVY, 2.0).with_class("path"),
    );
    map.circle(
        Point2::new(1.0, 1.0),
        0.3,
        &Style::default().with_class("ring"),
    );
    map.text(Point2::new(0.0, 2.5), "front", &TextStyle::size(12.0));
    map.text(Point2::new(9.0, 0.0), "off the map", &TextStyle::size(12.0));
    map.marker(
        Point2::new(1.0, -1.0),
        Marker::Diamond,
        8.0,
        &Style::fill(Color::RED),
    );
    let mut chart = Panel::chart(
        &Axis::linear(0.0, 1.0, "recall"),
        &Axis::log(1.0, 1e4, "time [us]"),
        300.0,
        200.0,
    );
    chart.polyline(
        &[
            Point2::new(0.0, 0.0),
            Point2::new(0.5, 10.0),
            Point2::new(1.0, 1e3),
        ],
        &Style::default().with_class("curve"),
    );
    let mut canvas = Canvas::new(2);
    canvas.set_title("blocks");
    canvas.add_panel(map);
    canvas.add_panel(chart);
    canvas.add_legend(LegendEntry::new(Swatch::Patch(sector), "sector"));
    let svg = canvas.to_svg();
    let root = parse(&svg).unwrap();
    assert_plain_numbers(&svg);
    assert_eq!(panels(&root).len(), 2);
    assert_eq!(root.count("polygon", "sector"), 3);
    assert_eq!(root.count("path", "path"), 1);
    assert_eq!(root.count("circle", "ring"), 1);
    // The point at y = 0 has no place on a log axis: the curve starts at the second point.
    let curve = root.find_all(&|e| e.has_class("curve"));
    assert_eq!(curve[0].attr("d").unwrap().matches('M').count(), 1);
    let texts: Vec<String> = root
        .find_all(&|e| e.name == "text")
        .iter()
        .map(|e| e.text.clone())
        .collect();
    assert!(texts.iter().any(|t| t == "front"));
    assert!(!texts.iter().any(|t| t == "off the map"));
}
