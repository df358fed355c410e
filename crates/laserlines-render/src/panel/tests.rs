//! Tests of [`Panel`](super::Panel) and [`Axis`](super::Axis).

use super::write::{axis_ticks, fmt_log_tick};
use super::*;

#[test]
fn map_keeps_equal_scales() {
    let p = Panel::map(Extent::new(0.0, 0.0, 4.0, 1.0), 400.0);
    let v = p.view();
    let [w, h] = p.plot_size();
    assert!((w / v.width() - h / v.height()).abs() < 1e-9);
    assert!((h - 200.0).abs() < 1e-9);
    let tall = Panel::map(Extent::new(0.0, 0.0, 1.0, 10.0), 400.0);
    let v = tall.view();
    let [w, h] = tall.plot_size();
    assert!((w / v.width() - h / v.height()).abs() < 1e-9);
    assert!((h - 500.0).abs() < 1e-9);
}

#[test]
fn y_points_up() {
    let p = Panel::map(Extent::new(0.0, 0.0, 2.0, 2.0), 200.0);
    let a = p.to_px(Point2::new(0.0, 0.0)).unwrap();
    let b = p.to_px(Point2::new(0.0, 1.0)).unwrap();
    assert!(b[1] < a[1]);
    assert_eq!(a, [0.0, 200.0]);
}

#[test]
fn log_ticks_label_decades() {
    let s = Scale {
        min: 1.0,
        max: 1000.0,
        log: true,
        px0: 0.0,
        px1: 300.0,
    };
    let t = axis_ticks(&s, 300.0);
    let labels: Vec<&str> = t
        .iter()
        .filter(|x| !x.1.is_empty())
        .map(|x| x.1.as_str())
        .collect();
    assert_eq!(labels, ["1", "10", "100", "1000"]);
    assert_eq!(fmt_log_tick(1e7, 7.0), "1e7");
}

#[test]
fn primitives_skip_non_finite_input() {
    let mut p = Panel::map(Extent::new(-1.0, -1.0, 1.0, 1.0), 200.0);
    let nan = Point2::new(f64::NAN, 0.0);
    p.line(nan, Point2::origin(), &Style::default());
    p.polyline(&[nan, nan], &Style::default());
    p.polygon(&[nan], &Style::default());
    p.circle(nan, 1.0, &Style::default());
    p.markers(&[nan], Marker::Dot, 3.0, &Style::default());
    p.text(nan, "x", &TextStyle::default());
    p.robot(nan, 0.0, 10.0, &Style::default());
    p.arc(Point2::origin(), f64::INFINITY, 0.0, 1.0, &Style::default());
    assert!(p.body.is_empty());
    p.line(
        Point2::new(-1e300, 0.0),
        Point2::new(1e300, 0.0),
        &Style::default(),
    );
    let s = p.body.clone().finish();
    assert!(s.contains("x1=\"-12\"") && s.contains("x2=\"212\""), "{s}");
}

#[test]
fn polyline_breaks_around_gaps() {
    let mut p = Panel::map(Extent::new(0.0, 0.0, 10.0, 10.0), 100.0);
    let pts = [
        Point2::new(1.0, 1.0),
        Point2::new(2.0, 1.0),
        Point2::new(f64::NAN, 1.0),
        Point2::new(3.0, 1.0),
        Point2::new(4.0, 1.0),
    ];
    p.polyline(&pts, &Style::default());
    let s = p.body.finish();
    assert_eq!(s.matches('M').count(), 2, "{s}");
}

#[test]
fn wrap_splits_long_titles() {
    let lines = wrap("one two three four five six", 10.0, false, 60.0);
    assert!(lines.len() > 1);
    assert_eq!(lines.join(" "), "one two three four five six");
}

#[test]
fn wrap_cuts_a_path_longer_than_the_line_after_its_separators() {
    use crate::style::text_width;
    let path = "/home/someone/data/a-rather-long-folder-name/another_one/exp1.dat.gz,";
    let lines = wrap(&format!("{path} scan 3"), 12.0, true, 120.0);
    assert!(lines.len() > 2, "{lines:?}");
    for line in &lines {
        assert!(
            text_width(line, 12.0, true) <= 120.0,
            "{line:?} in {lines:?}"
        );
    }
    // Nothing lost: the pieces hold the text's characters but its spaces.
    let text = format!("{path} scan 3").replace(' ', "");
    assert_eq!(lines.concat().replace(' ', ""), text);
    assert!(lines[0].ends_with('/'), "{lines:?}");
}
