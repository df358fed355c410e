//! # laserlines-render
//!
//! Pictures of scans, accumulators and lines as SVG, written by a small SVG writer of its
//! own (no dependency besides the core crate, the navigation crate for the sector objects,
//! and `png` for occupancy maps). Output is deterministic: the same input gives the same
//! bytes, so figures can be kept as golden files.
//!
//! Figures:
//! - [`render_hough_split`]: the paper's Fig. 3a, 3b, 4 and 5 for one scan, as four panels;
//! - [`render_scan_lines`]: a scan and the lines of any extractor;
//! - [`sectors_svg`]: the paper's Fig. 7, the three sectors and the selected objects;
//! - [`exploration_map_svg`]: the paper's Fig. 8, an exploration run as a map.
//! - [`render_map`]: a map built from a log (occupancy grid, line map, path), as the paper's
//!   Fig. 8; [`encode_grey_png`] writes the grid alone.
//!
//! Building blocks, for more pictures:
//! - [`Canvas`]: a figure with a title, panels in a grid and a legend;
//! - [`Panel`]: one plot area with axes, ticks, grid and scale bar; draws lines, polylines,
//!   polygons, circles, arcs, wedges, markers and text in world coordinates;
//! - [`ScatterChart`]: an x-y chart of labelled points, optionally logarithmic in x;
//! - [`svg`]: the writer itself, with escaping and fixed number formatting.
//!
//! Maps are drawn in the sensor (or world) frame with equal scales and y up: following
//! REP 103, x (forward) points right on the page and y (left) points up; the axis labels say
//! so. Units are metres.

mod canvas;
mod chart;
mod figures;
mod geometry;
mod map;
mod navigation;
mod panel;
pub mod style;
pub mod svg;

pub use canvas::{Canvas, LegendEntry, Swatch};
pub use chart::{ChartPoint, ScatterChart};
pub use figures::{RenderOptions, render_hough_split, render_scan_lines};
pub use geometry::{Extent, decimals_for, nice_floor, nice_step, ticks};
pub use map::{GreyMap, MapFigure, base64, encode_grey_png, render_map};
pub use navigation::{ExplorationMap, exploration_map_svg, sectors_svg};
pub use panel::{Axis, Panel};
pub use style::{Anchor, Color, Marker, Style, TextStyle};
