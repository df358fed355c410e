//! Maps built from a log: the occupancy grid, the line map and the robot's path, as the
//! paper's Fig. 8 (SVG, with the grid embedded as a PNG), and the grid alone as a PNG.

use laserlines::math::Point2;

use crate::canvas::{Canvas, LegendEntry, Swatch};
use crate::geometry::Extent;
use crate::panel::Panel;
use crate::style::{Color, Marker, Style};

/// An 8-bit grey image placed in the map frame (as ROS `map_server` shades a grid:
/// occupied black, free white, unknown grey).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GreyMap<'a> {
    /// `width * height` grey values, rows from the top (largest y) down.
    pub pixels: &'a [u8],
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Side of a pixel, m.
    pub resolution_m: f64,
    /// The map-frame position of the image's lower-left corner, m.
    pub origin: Point2,
}

impl GreyMap<'_> {
    /// The rectangle the image covers, m.
    #[must_use]
    pub fn extent(&self) -> Extent {
        Extent::new(
            self.origin.x,
            self.origin.y,
            self.origin.x + self.width as f64 * self.resolution_m,
            self.origin.y + self.height as f64 * self.resolution_m,
        )
    }
}

/// What [`render_map`] draws.
#[derive(Debug, Clone, PartialEq)]
pub struct MapFigure<'a> {
    /// The title.
    pub title: String,
    /// The occupancy grid.
    pub grid: Option<GreyMap<'a>>,
    /// The walls of the line map, m.
    pub walls: &'a [(Point2, Point2)],
    /// The robot's path, m.
    pub path: &'a [Point2],
    /// Loop closures drawn as thin segments between the two poses they join, m.
    pub closures: &'a [(Point2, Point2)],
}

const WALL: Color = Color::rgb(0x1f, 0x77, 0xb4);
const PATH: Color = Color::rgb(0xd6, 0x27, 0x28);
const CLOSURE: Color = Color::rgb(0x2c, 0xa0, 0x2c);

/// The map as an SVG: the grid (embedded PNG), the line map over it, the path, the closures,
/// the start; axes in metres, a scale bar and a legend.
///
/// # Errors
/// The PNG encoder's error for the grid.
pub fn render_map(fig: &MapFigure<'_>) -> Result<String, png::EncodingError> {
    let mut pts: Vec<Point2> = fig.path.to_vec();
    pts.extend(fig.walls.iter().flat_map(|w| [w.0, w.1]));
    if let Some(g) = &fig.grid {
        let e = g.extent();
        pts.extend([Point2::new(e.min_x, e.min_y), Point2::new(e.max_x, e.max_y)]);
    }
    let view = Extent::fit_map(pts, 4.0).padded(0.5);
    let mut panel = Panel::map(view, 900.0);
    panel.set_title(fig.title.clone());
    panel.set_labels("x [m]", "y [m]");
    if let Some(g) = &fig.grid {
        let png = encode_grey_png(g.pixels, g.width, g.height)?;
        panel.image(
            g.extent(),
            &format!("data:image/png;base64,{}", base64(&png)),
        );
    }
    let closure = Style::stroke(CLOSURE, 0.6)
        .with_opacity(0.6)
        .with_class("closure");
    for &(a, b) in fig.closures {
        panel.line(a, b, &closure);
    }
    let wall = Style::stroke(WALL, 1.2).with_class("wall");
    for &(a, b) in fig.walls {
        panel.line(a, b, &wall);
    }
    panel.polyline(fig.path, &Style::stroke(PATH, 1.0).with_class("path"));
    if let Some(&start) = fig.path.first() {
        panel.marker(start, Marker::Circle, 10.0, &Style::stroke(PATH, 2.0));
    }
    let mut canvas = Canvas::new(1);
    canvas.add_panel(panel);
    if fig.grid.is_some() {
        canvas.add_legend(LegendEntry::new(
            Swatch::Patch(Style::fill(Color::BLACK)),
            "occupancy grid: occupied (free white, unknown grey)",
        ));
    }
    canvas.add_legend(LegendEntry::new(
        Swatch::Line(Style::stroke(WALL, 1.2)),
        "line map: the scans' lines merged into walls",
    ));
    canvas.add_legend(LegendEntry::new(
        Swatch::Line(Style::stroke(PATH, 1.0)),
        "path",
    ));
    if !fig.closures.is_empty() {
        canvas.add_legend(LegendEntry::new(
            Swatch::Line(Style::stroke(CLOSURE, 0.6)),
            "loop closures",
        ));
    }
    canvas.add_legend(LegendEntry::new(
        Swatch::Marker(Marker::Circle, 10.0, Style::stroke(PATH, 2.0)),
        "start",
    ));
    Ok(canvas.to_svg())
}

/// An 8-bit greyscale PNG of `pixels` (`width * height`, rows from the top).
///
/// # Errors
/// The encoder's error (e.g. a wrong number of pixels, a zero size).
pub fn encode_grey_png(
    pixels: &[u8],
    width: usize,
    height: usize,
) -> Result<Vec<u8>, png::EncodingError> {
    let too_big = || png::EncodingError::LimitsExceeded;
    let w = u32::try_from(width).map_err(|_| too_big())?;
    let h = u32::try_from(height).map_err(|_| too_big())?;
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, w, h);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::High);
    let mut writer = enc.write_header()?;
    writer.write_image_data(pixels)?;
    writer.finish()?;
    Ok(out)
}

/// Standard base64 (RFC 4648, with padding).
#[must_use]
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(char::from(ALPHABET[(n >> (18 - 6 * k)) as usize & 63]));
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_of_known_strings() {
        // RFC 4648 section 10.
        for (plain, coded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(plain.as_bytes()), coded);
        }
    }

    #[test]
    fn a_map_figure_embeds_its_grid_and_draws_walls_and_path() {
        let pixels = [0u8, 254, 205, 254];
        let grid = GreyMap {
            pixels: &pixels,
            width: 2,
            height: 2,
            resolution_m: 0.5,
            origin: Point2::new(-1.0, -1.0),
        };
        let walls = [(Point2::new(-1.0, 0.0), Point2::new(0.0, 0.0))];
        let path = [Point2::new(-0.5, -0.5), Point2::new(-0.2, -0.4)];
        let svg = render_map(&MapFigure {
            title: "t".into(),
            grid: Some(grid),
            walls: &walls,
            path: &path,
            closures: &[],
        })
        .unwrap();
        assert!(
            svg.contains("data:image/png;base64,iVBORw0KGgo"),
            "PNG signature"
        );
        assert!(svg.contains("class=\"wall\""));
        assert!(svg.contains("class=\"path\""));
        let png = encode_grey_png(&pixels, 2, 2).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        assert!(encode_grey_png(&pixels, 3, 2).is_err());
    }
}
