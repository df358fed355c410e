//! `laserlines render`: the paper's figures for one scan as one SVG.

use std::path::PathBuf;

use anyhow::{Context, Result, anyhow};
use clap::Args;
use laserlines::LineExtractor;
use laserlines::math::{Isometry2, Point2};
use laserlines_nav::{Sector, SectorParams, select_objects};
use laserlines_render::{RenderOptions, render_hough_split, render_scan_lines};

use crate::InputArgs;

/// Arguments of `laserlines render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    #[command(flatten)]
    input: InputArgs,
    /// Index of the scan to draw (0-based, in input order).
    #[arg(long, default_value_t = 0)]
    scan: usize,
    /// Output SVG file.
    #[arg(short, long)]
    output: PathBuf,
    /// Line extraction algorithm; `hough-split` draws all four stages of the paper, any
    /// other algorithm draws its lines over the scan.
    #[arg(long, default_value = "hough-split")]
    algorithm: String,
    /// TOML file of parameters (one table per algorithm).
    #[arg(long)]
    params: Option<PathBuf>,
    /// Width of the four-panel figure, pixels (the `--sectors` figure has a plot 560 px
    /// wide).
    #[arg(long, default_value_t = 1200.0)]
    width: f64,
    /// Draw the paper's Fig. 7 instead: the three sectors (left 50..120 deg, front -50..50,
    /// right -120..-50; the laser frame taken as the robot's, x forward) and the "biggest
    /// and nearest" object of each, selected from the scan's lines; the objects' distance,
    /// width and angle are also printed, one line per sector.
    #[arg(long)]
    sectors: bool,
}

/// Runs the command.
pub fn run(args: &RenderArgs) -> Result<()> {
    let mut reader = super::open_input(&args.input)?;
    let record = reader.by_ref().nth(args.scan).ok_or_else(|| {
        anyhow!(
            "{}: has no scan {} (it holds {} scans)",
            args.input.input.display(),
            args.scan,
            reader.records()
        )
    })??;
    let opts = RenderOptions {
        width: args.width,
        ..RenderOptions::default()
    };
    let svg = if args.sectors {
        let mut ex = super::make_extractor(&args.algorithm, args.params.as_deref())?;
        let lines = ex.extract(&record.scan);
        let objects = select_objects(&lines, &Isometry2::identity(), &SectorParams::default());
        for sector in Sector::ALL {
            match objects.get(sector) {
                Some(o) => outln!(
                    "{}: distance {:.3} m, width {:.3} m, angle {:.1} deg",
                    sector.name(),
                    o.distance_m,
                    o.width_m,
                    o.angle_rad.to_degrees()
                ),
                None => outln!("{}: none", sector.name()),
            }
        }
        let points: Vec<Point2> = record
            .scan
            .points(record.scan.range_window(None))
            .iter()
            .map(|p| p.point)
            .collect();
        let segments: Vec<(Point2, Point2)> = lines.iter().map(|l| (l.start, l.end)).collect();
        let title = format!(
            "{}, scan {}: three sectors and the selected objects (laser frame)",
            args.input.input.display(),
            args.scan
        );
        laserlines_render::sectors_svg(&title, &points, &segments, &objects)
    } else if args.algorithm == "hough-split" {
        let mut hs = super::make_hough_split(args.params.as_deref())?;
        let lines = hs.extract(&record.scan);
        render_hough_split(&record.scan, &hs, &lines, &opts)
    } else {
        let mut ex = super::make_extractor(&args.algorithm, args.params.as_deref())?;
        let lines = ex.extract(&record.scan);
        render_scan_lines(&record.scan, &lines, &opts)
    };
    std::fs::write(&args.output, svg)
        .with_context(|| format!("cannot write {}", args.output.display()))?;
    eprintln!("wrote {}", args.output.display());
    Ok(())
}
