//! `laserlines render`: the paper's figures for one scan as one SVG.

use std::path::{Path, PathBuf};

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
    #[arg(long, default_value_t = 0, value_parser = super::index, allow_negative_numbers = true)]
    scan: usize,
    /// Output SVG file (`.svg`), or `-` for standard output.
    #[arg(short, long)]
    output: PathBuf,
    /// Line extraction algorithm; `hough-split` draws all four stages of the paper, any
    /// other algorithm draws its lines over the scan.
    #[arg(long, default_value = "hough-split", value_parser = super::algorithm_parser())]
    algorithm: String,
    #[command(flatten)]
    params: super::ParamsArgs,
    /// Width of the figure, pixels, from 400 to 8000: the panels are sized to it, and the
    /// SVG comes out up to 5 % narrower, as wide as its axis labels need (the `--sectors`
    /// figure has a plot 560 px wide).
    #[arg(long, default_value_t = 1200.0, allow_negative_numbers = true)]
    width: f64,
    /// Draw the paper's Fig. 7 instead: the three sectors (left 50..120 deg, front -50..50,
    /// right -120..-50; the laser frame taken as the robot's, x forward) and the "biggest
    /// and nearest" object of each, selected from the scan's lines; the objects' distance,
    /// width and angle are also printed, one line per sector.
    #[arg(long)]
    sectors: bool,
    /// Skip bad records (each named on standard error) instead of stopping at the first, so
    /// that `--scan` counts the scans as `extract --skip-bad` numbers them. A failed read of
    /// the input itself (an I/O error, a corrupt gzip stream) still ends the run with an
    /// error.
    #[arg(long)]
    skip_bad: bool,
}

/// Runs the command.
pub fn run(args: &RenderArgs) -> Result<()> {
    check_output(&args.output)?;
    super::output_folder_exists(&args.output)?;
    if !(400.0..=8000.0).contains(&args.width) {
        anyhow::bail!(
            "--width must lie from 400 to 8000 px, got {}",
            super::compact(args.width)
        );
    }
    super::note_unused_tables(args.params.file_path(), &[&args.algorithm], "render")?;
    let to_stdout = args.output == Path::new("-");
    let record = nth_scan(&args.input, args.scan, args.skip_bad)?;
    let opts = RenderOptions {
        width: args.width,
        ..RenderOptions::default()
    };
    let svg = if args.sectors {
        let mut ex = super::make_extractor(&args.algorithm, &args.params)?;
        let lines = ex.extract(&record.scan);
        let objects = select_objects(&lines, &Isometry2::identity(), &SectorParams::default());
        for sector in Sector::ALL {
            let text = match objects.get(sector) {
                Some(o) => format!(
                    "{}: distance {:.3} m, width {:.3} m, line direction {:.1} deg",
                    sector.name(),
                    o.distance_m,
                    o.width_m,
                    // Rounded first: a small negative angle reads 0.0, not -0.0.
                    (o.angle_rad.to_degrees() * 10.0).round() / 10.0 + 0.0
                ),
                None => format!("{}: none", sector.name()),
            };
            // Standard output carries the SVG with `-o -`.
            if to_stdout {
                errln!("{text}");
            } else {
                outln!("{text}");
            }
        }
        let points: Vec<Point2> = record
            .scan
            .points(record.scan.range_window(None))
            .iter()
            .map(|p| p.point)
            .collect();
        let segments: Vec<(Point2, Point2)> = lines.iter().map(|l| (l.start, l.end)).collect();
        // The file's name, not its whole path: the title has one plot's width.
        let input = &args.input.input;
        let shown = input.file_name().map_or_else(
            || input.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        let title = format!(
            "{shown}, scan {}: three sectors and the selected objects (laser frame)",
            args.scan
        );
        laserlines_render::sectors_svg(&title, &points, &segments, &objects)
    } else if args.algorithm == "hough-split" {
        let mut hs = super::make_hough_split(&args.params)?;
        let lines = hs.extract(&record.scan);
        render_hough_split(&record.scan, &hs, &lines, &opts)
    } else {
        let mut ex = super::make_extractor(&args.algorithm, &args.params)?;
        let lines = ex.extract(&record.scan);
        render_scan_lines(&record.scan, &lines, &opts)
    };
    if to_stdout {
        use std::io::Write as _;
        let mut out = std::io::stdout().lock();
        out.write_all(svg.as_bytes())
            .and_then(|()| out.flush())
            .context("cannot write the SVG to standard output")?;
        return Ok(());
    }
    std::fs::write(&args.output, svg)
        .with_context(|| format!("cannot write {}", args.output.display()))?;
    errln!("wrote {}", args.output.display());
    Ok(())
}

/// Scan `index` of the input, counting scans from 0; a bad record before it is the error
/// (as `extract` gives it), not a shortage of scans, unless `skip_bad` skips it (it then
/// takes no number).
fn nth_scan(input: &InputArgs, index: usize, skip_bad: bool) -> Result<laserlines_io::ScanRecord> {
    let mut reader = super::open_input(input)?;
    let mut seen = 0usize;
    for item in reader.by_ref() {
        let record = match item {
            Ok(r) => r,
            Err(e) if super::skips(skip_bad, &e) => {
                errln!("laserlines: skipped: {e}");
                continue;
            }
            Err(e) => return Err(super::read_error(e, skip_bad)),
        };
        if seen == index {
            return Ok(record);
        }
        seen += 1;
    }
    Err(anyhow!(
        "{}: has no scan {index} (it holds {})",
        input.input.display(),
        super::count(seen as u64, "scan")
    ))
}

/// `render` writes SVG: to a `.svg` file or standard output (`-`); any other name (a `.png`
/// would hold SVG text) is refused.
fn check_output(path: &Path) -> Result<()> {
    let is_svg = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
    if path.is_dir() {
        anyhow::bail!(
            "{}: is a folder; render writes one SVG file: name it, as {}",
            path.display(),
            path.join("scan.svg").display()
        );
    }
    if path == Path::new("-") || is_svg {
        return Ok(());
    }
    anyhow::bail!(
        "{}: render writes SVG; name the output .svg (or - for standard output) and convert it \
         to another format with an SVG tool (rsvg-convert, inkscape, a browser)",
        path.display()
    )
}
