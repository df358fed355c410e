//! Writes one of each picture into a folder (default `./render-gallery`): the paper's figure
//! and a scan with its lines for a simulated room, an accuracy-against-speed chart and the
//! building blocks (navigation sectors, a path, a circle), and the figure of a scan without
//! any valid range.
//!
//! `cargo run -p laserlines-render --example gallery -- OUT_DIR`

use std::f64::consts::PI;

use laserlines::math::Point2;
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor, Scan};
use laserlines_render::{
    Canvas, Color, Extent, LegendEntry, Marker, Panel, RenderOptions, ScatterChart, Style, Swatch,
    TextStyle, render_hough_split, render_scan_lines,
};

/// A 5 m x 3 m room seen from (1, 1), facing +x, without noise.
fn room() -> Result<Scan, laserlines::ScanError> {
    let inc = (360.0_f64 / 1024.0).to_radians();
    let min = -120.0_f64.to_radians();
    let ranges = (0..682)
        .map(|i| {
            let a = min + f64::from(i) * inc;
            let (c, s) = (a.cos(), a.sin());
            let tx = if c > 1e-12 {
                4.0 / c
            } else if c < -1e-12 {
                -1.0 / c
            } else {
                f64::INFINITY
            };
            let ty = if s > 1e-12 {
                2.0 / s
            } else if s < -1e-12 {
                -1.0 / s
            } else {
                f64::INFINITY
            };
            tx.min(ty)
        })
        .collect();
    Scan::new(min, inc, 0.02, 5.6, ranges)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "render-gallery".to_owned());
    std::fs::create_dir_all(&dir)?;
    let scan = room()?;
    let mut hs = HoughSplit::new(HoughSplitParams::default())?;
    let lines = hs.extract(&scan);
    let opts = RenderOptions::default();
    std::fs::write(
        format!("{dir}/hough_split.svg"),
        render_hough_split(&scan, &hs, &lines, &opts),
    )?;
    std::fs::write(
        format!("{dir}/scan_lines.svg"),
        render_scan_lines(&scan, &lines, &opts),
    )?;
    std::fs::write(format!("{dir}/chart.svg"), chart().to_svg())?;
    std::fs::write(format!("{dir}/blocks.svg"), blocks().to_svg())?;

    // A scan without a single valid range still gives a figure, with notes.
    let empty = Scan::new(-2.0, 0.01, 0.02, 5.6, vec![f64::NAN; 400])?;
    let lines = hs.extract(&empty);
    std::fs::write(
        format!("{dir}/empty.svg"),
        render_hough_split(&empty, &hs, &lines, &RenderOptions::default()),
    )?;
    println!("wrote {dir}/hough_split.svg, scan_lines.svg, chart.svg, blocks.svg, empty.svg");
    Ok(())
}

/// A scatter chart on a log axis, with made-up points (the real comparison is
/// `laserlines bench`'s chart).
fn chart() -> ScatterChart {
    let mut chart = ScatterChart::new(
        "A scatter chart (made-up points)",
        "time per scan [us]",
        "wall pieces found [%]",
    );
    chart.log_x = true;
    for (x, y, name) in [
        (20.0, 98.0, "A"),
        (480.0, 97.0, "B"),
        (50.0, 95.0, "C"),
        (900.0, 92.0, "D"),
        (11.0, 90.0, "E"),
    ] {
        chart.add(x, y, name);
    }
    chart
}

/// Navigation sectors, a path, a circle and a robot on one map panel, with a legend.
fn blocks() -> Canvas {
    let mut map = Panel::map(Extent::new(-2.5, -2.5, 3.0, 2.5), 420.0);
    map.set_title("Navigation sectors around the robot");
    let colors = [
        Color::rgb(0x1b, 0x9e, 0x77),
        Color::rgb(0x75, 0x70, 0xb3),
        Color::rgb(0xd9, 0x5f, 0x02),
    ];
    let front = 50.0_f64.to_radians();
    let side = 70.0_f64.to_radians();
    let sectors = [
        (front, front + side, "left"),
        (-front, front, "front"),
        (-front - side, -front, "right"),
    ];
    for ((from, to, name), color) in sectors.iter().zip(colors) {
        map.wedge(
            Point2::origin(),
            0.0,
            2.0,
            *from,
            *to,
            &Style::stroke(color, 1.0)
                .with_fill(color)
                .with_opacity(0.25),
        );
        let mid = 0.5 * (from + to);
        map.text(
            Point2::new(1.4 * mid.cos(), 1.4 * mid.sin()),
            name,
            &TextStyle::size(12.0).anchored(laserlines_render::Anchor::Middle),
        );
    }
    map.polyline(
        &(0..=40)
            .map(|k| {
                let t = f64::from(k) / 40.0;
                Point2::new(-2.0 + 4.5 * t, 1.5 * (PI * t).sin() - 1.0)
            })
            .collect::<Vec<_>>(),
        &Style::stroke(Color::NAVY, 2.0).with_dash(6.0, 4.0),
    );
    map.circle(Point2::new(2.2, 1.6), 0.3, &Style::stroke(Color::RED, 1.5));
    map.marker(
        Point2::new(2.2, 1.6),
        Marker::Plus,
        8.0,
        &Style::stroke(Color::RED, 1.5),
    );
    map.robot(Point2::origin(), 0.0, 15.0, &Style::fill(Color::RED));
    let mut canvas = Canvas::new(1);
    canvas.set_title("Building blocks");
    canvas.add_panel(map);
    canvas.add_legend(LegendEntry::new(
        Swatch::Patch(Style::fill(colors[1]).with_opacity(0.25)),
        "sector",
    ));
    canvas.add_legend(LegendEntry::new(
        Swatch::Line(Style::stroke(Color::NAVY, 2.0).with_dash(6.0, 4.0)),
        "path",
    ));
    canvas
}
