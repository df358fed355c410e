//! Colours, stroke and fill styles, text styles, point markers and palettes.

/// An opaque sRGB colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Color {
    /// Red, 0..255.
    pub r: u8,
    /// Green, 0..255.
    pub g: u8,
    /// Blue, 0..255.
    pub b: u8,
}

impl Color {
    /// A colour from its components.
    #[must_use]
    pub const fn rgb(r: u8, g: u8, b: u8) -> Self {
        Self { r, g, b }
    }

    /// Black.
    pub const BLACK: Self = Self::rgb(0, 0, 0);
    /// White.
    pub const WHITE: Self = Self::rgb(255, 255, 255);
    /// Near-black ink for data and text.
    pub const INK: Self = Self::rgb(0x22, 0x22, 0x22);
    /// Mid grey (removed points, secondary text).
    pub const GREY: Self = Self::rgb(0x80, 0x80, 0x80);
    /// Light grey (faint context, grid).
    pub const LIGHT_GREY: Self = Self::rgb(0xc4, 0xc4, 0xc4);
    /// Very light grey (grid lines).
    pub const GRID: Self = Self::rgb(0xe6, 0xe6, 0xe6);
    /// Red (the robot, end points).
    pub const RED: Self = Self::rgb(0xd6, 0x27, 0x28);
    /// Blue (radius groups).
    pub const BLUE: Self = Self::rgb(0x1f, 0x77, 0xb4);
    /// Dark blue (extracted lines).
    pub const NAVY: Self = Self::rgb(0x15, 0x2f, 0x6b);

    /// `#rrggbb`.
    #[must_use]
    pub fn hex(self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.r, self.g, self.b)
    }

    /// Linear blend from `self` (t = 0) to `other` (t = 1); `t` is clamped, NaN gives `self`.
    #[must_use]
    pub fn lerp(self, other: Self, t: f64) -> Self {
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
        let mix = |a: u8, b: u8| (f64::from(a) + (f64::from(b) - f64::from(a)) * t).round() as u8;
        Self::rgb(
            mix(self.r, other.r),
            mix(self.g, other.g),
            mix(self.b, other.b),
        )
    }
}

/// Eight qualitative colours (ColorBrewer "Dark2"), none of them pure red or blue, so that
/// they stay apart from the robot, the end points and the radius groups.
pub const CATEGORY: [Color; 8] = [
    Color::rgb(0x1b, 0x9e, 0x77),
    Color::rgb(0xd9, 0x5f, 0x02),
    Color::rgb(0x75, 0x70, 0xb3),
    Color::rgb(0xe7, 0x29, 0x8a),
    Color::rgb(0x66, 0xa6, 0x1e),
    Color::rgb(0xe6, 0xab, 0x02),
    Color::rgb(0xa6, 0x76, 0x1d),
    Color::rgb(0x44, 0x44, 0x44),
];

/// The `i`-th qualitative colour, cycling through [`CATEGORY`].
#[must_use]
pub fn category(i: usize) -> Color {
    CATEGORY[i % CATEGORY.len()]
}

const VIRIDIS: [Color; 11] = [
    Color::rgb(0x44, 0x01, 0x54),
    Color::rgb(0x48, 0x24, 0x75),
    Color::rgb(0x41, 0x44, 0x87),
    Color::rgb(0x35, 0x5f, 0x8d),
    Color::rgb(0x2a, 0x78, 0x8e),
    Color::rgb(0x21, 0x91, 0x8c),
    Color::rgb(0x22, 0xa8, 0x84),
    Color::rgb(0x44, 0xbf, 0x70),
    Color::rgb(0x7a, 0xd1, 0x51),
    Color::rgb(0xbd, 0xdf, 0x26),
    Color::rgb(0xfd, 0xe7, 0x25),
];

/// The viridis colour map at `t` in `[0, 1]` (dark purple at 0, yellow at 1), clamped; NaN
/// gives the colour at 0. Perceptually uniform and readable by colour-blind readers.
#[must_use]
pub fn viridis(t: f64) -> Color {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    VIRIDIS[i].lerp(VIRIDIS[i + 1], x - i as f64)
}

/// How a shape is painted: stroke, fill, opacity, dash and an optional CSS class (which the
/// tests and any style sheet can select on).
#[derive(Debug, Clone, PartialEq)]
pub struct Style {
    /// Outline colour; `None` draws no outline.
    pub stroke: Option<Color>,
    /// Outline width, px.
    pub stroke_width: f64,
    /// Fill colour; `None` leaves the inside empty.
    pub fill: Option<Color>,
    /// Opacity of the whole shape, 0..1.
    pub opacity: f64,
    /// Dash pattern `[on, off]`, px; `None` draws a solid outline.
    pub dash: Option<[f64; 2]>,
    /// CSS class written on the element.
    pub class: Option<String>,
}

impl Default for Style {
    fn default() -> Self {
        Self {
            stroke: Some(Color::INK),
            stroke_width: 1.0,
            fill: None,
            opacity: 1.0,
            dash: None,
            class: None,
        }
    }
}

impl Style {
    /// An outline of `color`, `width` px, no fill.
    #[must_use]
    pub fn stroke(color: Color, width: f64) -> Self {
        Self {
            stroke: Some(color),
            stroke_width: width,
            ..Self::default()
        }
    }

    /// A fill of `color`, no outline.
    #[must_use]
    pub fn fill(color: Color) -> Self {
        Self {
            stroke: None,
            fill: Some(color),
            ..Self::default()
        }
    }

    /// The same style with a fill.
    #[must_use]
    pub fn with_fill(mut self, color: Color) -> Self {
        self.fill = Some(color);
        self
    }

    /// The same style with an opacity (clamped to 0..1).
    #[must_use]
    pub fn with_opacity(mut self, opacity: f64) -> Self {
        self.opacity = if opacity.is_nan() {
            1.0
        } else {
            opacity.clamp(0.0, 1.0)
        };
        self
    }

    /// The same style, dashed `[on, off]` px.
    #[must_use]
    pub fn with_dash(mut self, on: f64, off: f64) -> Self {
        self.dash = Some([on, off]);
        self
    }

    /// The same style with a CSS class.
    #[must_use]
    pub fn with_class(mut self, class: impl Into<String>) -> Self {
        self.class = Some(class.into());
        self
    }

    pub(crate) fn write_attrs(&self, out: &mut Vec<(&'static str, String)>) {
        use crate::svg::fmt_px;
        if let Some(c) = &self.class {
            out.push(("class", c.clone()));
        }
        out.push((
            "fill",
            self.fill.map_or_else(|| "none".to_owned(), Color::hex),
        ));
        match self.stroke {
            Some(c) => {
                out.push(("stroke", c.hex()));
                out.push(("stroke-width", fmt_px(self.stroke_width.max(0.0))));
                if let Some([on, off]) = self.dash {
                    out.push((
                        "stroke-dasharray",
                        format!("{} {}", fmt_px(on.max(0.0)), fmt_px(off.max(0.0))),
                    ));
                }
            }
            None => out.push(("stroke", "none".to_owned())),
        }
        if self.opacity < 1.0 {
            out.push(("opacity", crate::svg::fmt_trimmed(self.opacity.max(0.0), 3)));
        }
    }
}

/// Horizontal alignment of text at its anchor point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Anchor {
    /// Text starts at the anchor.
    #[default]
    Start,
    /// Text is centred on the anchor.
    Middle,
    /// Text ends at the anchor.
    End,
}

impl Anchor {
    pub(crate) fn svg(self) -> &'static str {
        match self {
            Self::Start => "start",
            Self::Middle => "middle",
            Self::End => "end",
        }
    }
}

/// How text is set.
#[derive(Debug, Clone, PartialEq)]
pub struct TextStyle {
    /// Font size, px.
    pub size: f64,
    /// Text colour.
    pub color: Color,
    /// Horizontal alignment.
    pub anchor: Anchor,
    /// Bold weight.
    pub bold: bool,
    /// Italic.
    pub italic: bool,
    /// Offset from the anchor point, px (right, down).
    pub offset: [f64; 2],
    /// A white outline behind the glyphs, so that the text stays readable over data.
    pub halo: bool,
    /// CSS class written on the element.
    pub class: Option<String>,
}

impl Default for TextStyle {
    fn default() -> Self {
        Self {
            size: 12.0,
            color: Color::INK,
            anchor: Anchor::Start,
            bold: false,
            italic: false,
            offset: [0.0, 0.0],
            halo: false,
            class: None,
        }
    }
}

impl TextStyle {
    /// Text of `size` px, otherwise default.
    #[must_use]
    pub fn size(size: f64) -> Self {
        Self {
            size,
            ..Self::default()
        }
    }

    /// The same style with an alignment.
    #[must_use]
    pub fn anchored(mut self, anchor: Anchor) -> Self {
        self.anchor = anchor;
        self
    }

    /// The same style with an offset, px (right, down).
    #[must_use]
    pub fn offset(mut self, dx: f64, dy: f64) -> Self {
        self.offset = [dx, dy];
        self
    }

    /// The same style with a white halo.
    #[must_use]
    pub fn with_halo(mut self) -> Self {
        self.halo = true;
        self
    }

    /// The same style in a colour.
    #[must_use]
    pub fn colored(mut self, color: Color) -> Self {
        self.color = color;
        self
    }

    /// The same style, bold.
    #[must_use]
    pub fn bold(mut self) -> Self {
        self.bold = true;
        self
    }

    /// The same style, italic.
    #[must_use]
    pub fn italic(mut self) -> Self {
        self.italic = true;
        self
    }

    /// The same style with a CSS class.
    #[must_use]
    pub fn with_class(mut self, class: impl Into<String>) -> Self {
        self.class = Some(class.into());
        self
    }

    /// Rough width of `text` in this style, px (for layout; no font metrics are read).
    #[must_use]
    pub fn width_of(&self, text: &str) -> f64 {
        text_width(text, self.size, self.bold)
    }
}

/// Estimated advance width of `text` in a sans-serif font of `size` px: about 0.56 em per
/// character (0.6 em bold). Layout uses it to keep labels apart; no font file is read, so the
/// result is the same on every machine.
#[must_use]
pub fn text_width(text: &str, size: f64, bold: bool) -> f64 {
    let em = if bold { 0.6 } else { 0.56 };
    text.chars().count() as f64 * em * size
}

/// A point marker, drawn with a size in pixels whatever the zoom.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Marker {
    /// A filled disc.
    #[default]
    Dot,
    /// A circle outline (filled only if the style has a fill).
    Circle,
    /// An `x` cross.
    Cross,
    /// A `+` cross.
    Plus,
    /// A square.
    Square,
    /// A diamond.
    Diamond,
    /// A triangle pointing up the page.
    Triangle,
    /// A triangle pointing right (along +x on a map): the robot facing forward.
    TriangleRight,
}
