//! Minimal hand-written SVG: a builder writing into the page's buffer,
//! linear axes with "nice" ticks and a plot frame. Coordinates are written
//! with fixed decimals so that the output is deterministic and
//! diff-friendly. Styling is by CSS class (the classes are defined in the
//! HTML page's stylesheet).

use super::markup::{fixed, push_escaped, push_fixed, TextSink};

/// Decimals of pixel coordinates.
const PX_DECIMALS: usize = 2;
/// Space between the plot area and the left SVG edge (tick labels), px.
pub const MARGIN_LEFT: f64 = 70.0;
/// Space between the plot area and the right SVG edge, px.
pub const MARGIN_RIGHT: f64 = 20.0;
/// Space above the plot area (title line), px.
pub const MARGIN_TOP: f64 = 30.0;
/// Space below the plot area (tick labels and axis title), px.
pub const MARGIN_BOTTOM: f64 = 45.0;
/// Length of a tick mark, px.
const TICK_PX: f64 = 5.0;
/// Most ticks per axis.
const MAX_TICKS: usize = 10;

/// Appends a pixel coordinate; a non-finite value (callers leave such
/// points out) becomes 0 so that the SVG stays valid.
pub fn push_px(out: &mut Vec<u8>, value: f64) {
    push_fixed(
        out,
        if value.is_finite() { value } else { 0.0 },
        PX_DECIMALS,
    );
}

/// A pixel value as [`push_px`] writes it.
pub fn px_text(value: f64) -> Vec<u8> {
    let mut text = Vec::new();
    push_px(&mut text, value);
    text
}

/// Pixel points formatted once for the several elements that draw them
/// (a trace and its markers, a curve and the needles that start on it).
#[derive(Debug, Default)]
pub struct PixelTexts {
    /// The x and y of every point as [`push_px`] writes them, back to back.
    text: Vec<u8>,
    /// Per point: where its x ends and where its y ends in `text`.
    ends: Vec<(usize, usize)>,
}

impl PixelTexts {
    /// Formats the points.
    pub fn new(points: impl ExactSizeIterator<Item = (f64, f64)>) -> PixelTexts {
        /// Typical bytes of one point's x and y.
        const POINT_BYTES: usize = 12;
        let mut texts = PixelTexts {
            text: Vec::with_capacity(points.len() * POINT_BYTES),
            ends: Vec::with_capacity(points.len()),
        };
        for (x, y) in points {
            push_px(&mut texts.text, x);
            let x_end = texts.text.len();
            push_px(&mut texts.text, y);
            texts.ends.push((x_end, texts.text.len()));
        }
        texts
    }

    /// How many points there are.
    pub fn count(&self) -> usize {
        self.ends.len()
    }

    /// The x and y text of point `k`.
    fn get(&self, k: usize) -> Option<(&[u8], &[u8])> {
        let start = match k.checked_sub(1) {
            Some(previous) => self.ends.get(previous)?.1,
            None => 0,
        };
        let (x_end, y_end) = *self.ends.get(k)?;
        Some((self.text.get(start..x_end)?, self.text.get(x_end..y_end)?))
    }
}

/// Bytes reserved for a new SVG: the frame, axes and captions of a plot.
const INITIAL_CAPACITY: usize = 4096;

/// An SVG document under construction, written straight into the page
/// that shows it.
#[derive(Debug)]
pub struct Svg<'a> {
    out: &'a mut Vec<u8>,
}

impl<'a> Svg<'a> {
    /// Starts an inline `<svg>` of the given size (px) with an accessible
    /// title at the end of `out`.
    pub fn new(out: &'a mut Vec<u8>, width: f64, height: f64, title: &str) -> Svg<'a> {
        out.reserve(INITIAL_CAPACITY);
        let mut svg = Svg { out };
        svg.out.push_text("<svg class=\"plot\"");
        svg.attr(" width=\"", width);
        svg.attr(" height=\"", height);
        svg.out.push_text(" viewBox=\"0 0 ");
        push_px(svg.out, width);
        svg.out.push(b' ');
        push_px(svg.out, height);
        svg.out.push_text("\" role=\"img\"><title>");
        push_escaped(svg.out, title);
        svg.out.push_text("</title>\n");
        svg
    }

    /// Reserves room for `additional` more bytes of markup.
    pub fn reserve(&mut self, additional: usize) {
        self.out.reserve(additional);
    }

    /// ` name="value"` with a pixel value; `lead` is ` name="`.
    fn attr(&mut self, lead: &str, value: f64) {
        self.out.push_text(lead);
        push_px(self.out, value);
        self.out.push(b'"');
    }

    /// ` name="text"` with a pixel value formatted before; `lead` is
    /// ` name="`.
    fn attr_text(&mut self, lead: &str, text: &[u8]) {
        self.out.push_text(lead);
        self.out.extend_from_slice(text);
        self.out.push(b'"');
    }

    /// ` class="class"/>` and the line end.
    fn end_empty(&mut self, class: &str) {
        self.out.push_text(" class=\"");
        self.out.push_text(class);
        self.out.push_text("\"/>\n");
    }

    /// A line segment.
    pub fn line(&mut self, a: (f64, f64), b: (f64, f64), class: &str) {
        self.out.push_text("<line");
        self.attr(" x1=\"", a.0);
        self.attr(" y1=\"", a.1);
        self.attr(" x2=\"", b.0);
        self.attr(" y2=\"", b.1);
        self.end_empty(class);
    }

    /// A line segment from point `k` of `texts` to `b` (nothing when
    /// there is no such point).
    pub fn line_from(&mut self, texts: &PixelTexts, k: usize, b: (f64, f64), class: &str) {
        let Some((x, y)) = texts.get(k) else {
            return;
        };
        self.out.push_text("<line");
        self.attr_text(" x1=\"", x);
        self.attr_text(" y1=\"", y);
        self.attr(" x2=\"", b.0);
        self.attr(" y2=\"", b.1);
        self.end_empty(class);
    }

    /// An axis-aligned rectangle from its top-left corner and size.
    pub fn rect(&mut self, corner: (f64, f64), size: (f64, f64), class: &str) {
        self.out.push_text("<rect");
        self.attr(" x=\"", corner.0);
        self.attr(" y=\"", corner.1);
        self.attr(" width=\"", size.0.max(0.0));
        self.attr(" height=\"", size.1.max(0.0));
        self.end_empty(class);
    }

    /// A circle centred on point `k` of `texts`, its radius formatted by
    /// [`px_text`] (nothing when there is no such point).
    pub fn circle_at(&mut self, texts: &PixelTexts, k: usize, radius: &[u8], class: &str) {
        let Some((x, y)) = texts.get(k) else {
            return;
        };
        self.out.push_text("<circle");
        self.attr_text(" cx=\"", x);
        self.attr_text(" cy=\"", y);
        self.attr_text(" r=\"", radius);
        self.end_empty(class);
    }

    /// The polyline through the points of `texts`, back to the first when
    /// `closed` (nothing for fewer than two points in all).
    pub fn polyline_texts(&mut self, texts: &PixelTexts, closed: bool, class: &str) {
        let count = texts.count();
        let closing = closed && count > 0;
        if count + usize::from(closing) < 2 {
            return;
        }
        self.out.reserve(texts.text.len() + 2 * count + 64);
        self.out.push_text("<polyline points=\"");
        let order = (0..count).chain(closing.then_some(0));
        for (n, k) in order.enumerate() {
            let Some((x, y)) = texts.get(k) else {
                continue;
            };
            if n > 0 {
                self.out.push(b' ');
            }
            self.out.extend_from_slice(x);
            self.out.push(b',');
            self.out.extend_from_slice(y);
        }
        self.out.push(b'"');
        self.end_empty(class);
    }

    /// An open polyline (nothing for fewer than two points).
    pub fn polyline(&mut self, points: &[(f64, f64)], class: &str) {
        if points.len() < 2 {
            return;
        }
        self.points_element("polyline", points, class);
    }

    /// A closed polygon.
    pub fn polygon(&mut self, points: &[(f64, f64)], class: &str) {
        self.points_element("polygon", points, class);
    }

    /// `<tag points="x,y x,y ..." class="class"/>`.
    fn points_element(&mut self, tag: &str, points: &[(f64, f64)], class: &str) {
        /// Typical bytes of one `x,y` pair with its separator.
        const PAIR_BYTES: usize = 14;
        self.out.reserve(points.len() * PAIR_BYTES + 64);
        self.out.push(b'<');
        self.out.push_text(tag);
        self.out.push_text(" points=\"");
        for (k, (x, y)) in points.iter().enumerate() {
            if k > 0 {
                self.out.push(b' ');
            }
            push_px(self.out, *x);
            self.out.push(b',');
            push_px(self.out, *y);
        }
        self.out.push(b'"');
        self.end_empty(class);
    }

    /// Text; `anchor` is `start`, `middle` or `end`.
    pub fn text(&mut self, at: (f64, f64), anchor: &str, class: &str, content: &str) {
        self.out.push_text("<text");
        self.attr(" x=\"", at.0);
        self.attr(" y=\"", at.1);
        self.out.push_text(" text-anchor=\"");
        self.out.push_text(anchor);
        self.out.push_text("\" class=\"");
        self.out.push_text(class);
        self.out.push_text("\">");
        push_escaped(self.out, content);
        self.out.push_text("</text>\n");
    }

    /// Closes the element.
    pub fn finish(self) {
        self.out.push_text("</svg>\n");
    }
}

/// A placeholder plot that only says why there is nothing to draw,
/// appended to `out`.
pub fn empty_plot(out: &mut Vec<u8>, width: f64, height: f64, title: &str, message: &str) {
    let mut svg = Svg::new(out, width, height, title);
    svg.rect((0.5, 0.5), (width - 1.0, height - 1.0), "frame");
    svg.text((width / 2.0, height / 2.0), "middle", "note", message);
    svg.finish()
}

/// A linear map from a data interval onto a pixel interval.
#[derive(Debug, Clone, Copy)]
pub struct Axis {
    /// Data value at `px_lo`.
    pub lo: f64,
    /// Data value at `px_hi`.
    pub hi: f64,
    /// Pixel position of `lo`.
    pub px_lo: f64,
    /// Pixel position of `hi`.
    pub px_hi: f64,
}

impl Axis {
    /// The pixel position of a data value.
    pub fn map(&self, value: f64) -> f64 {
        let span = self.hi - self.lo;
        if span.abs() < f64::MIN_POSITIVE || !span.is_finite() {
            return (self.px_lo + self.px_hi) / 2.0;
        }
        self.px_lo + (value - self.lo) / span * (self.px_hi - self.px_lo)
    }
}

/// The data range `[lo, hi]` widened by `fraction` of its width on each
/// side; an empty or degenerate range becomes `value ± 0.5`.
pub fn padded(lo: f64, hi: f64, fraction: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) || hi < lo {
        return (-0.5, 0.5);
    }
    if hi == lo {
        return (lo - 0.5, hi + 0.5);
    }
    let pad = (hi - lo) * fraction.max(0.0);
    (lo - pad, hi + pad)
}

/// The smallest and largest of some values (`None` for none or non-finite).
pub fn range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    (lo <= hi).then_some((lo, hi))
}

/// The largest 1, 2 or 5 times a power of ten not above `value` (> 0).
pub fn nice_floor(value: f64) -> f64 {
    if !(value.is_finite() && value > 0.0) {
        return 1.0;
    }
    let power = 10f64.powf(value.log10().floor());
    let mantissa = value / power;
    let step = [5.0, 2.0, 1.0].into_iter().find(|m| mantissa >= *m);
    step.unwrap_or(1.0) * power
}

/// Tick step and ticks inside `[lo, hi]` (at most [`MAX_TICKS`] + 1).
/// A range that is not finite, or too wide for an `f64` difference, has no
/// ticks.
pub fn ticks(lo: f64, hi: f64) -> (f64, Vec<f64>) {
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) {
        return (1.0, Vec::new());
    }
    let mut step = nice_floor(span / MAX_TICKS as f64);
    // Each pass at least doubles the step, so the loop is short; the bound
    // only guards against a step that stops growing (round-off at f64's top).
    for _ in 0..64 {
        if span / step <= MAX_TICKS as f64 {
            break;
        }
        step = nice_floor(step * 2.5);
    }
    // The tolerance keeps ticks at the ends despite rounding (-0.06 / 0.02).
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    let count = (last - first).clamp(-1, MAX_TICKS as i64 + 1);
    let values = (0..=count).map(|k| (first + k) as f64 * step).collect();
    (step, values)
}

/// Decimals needed to print multiples of `step` exactly.
pub fn step_decimals(step: f64) -> usize {
    let digits = -step.log10().floor();
    if digits.is_finite() && digits > 0.0 {
        digits as usize
    } else {
        0
    }
}

/// A plot area of a given size with its x and y axes (y pointing up).
#[derive(Debug, Clone, Copy)]
pub struct Frame {
    /// Horizontal axis.
    pub x: Axis,
    /// Vertical axis.
    pub y: Axis,
}

impl Frame {
    /// The plot area inside the standard margins of a `width` x `height` SVG.
    pub fn new(width: f64, height: f64, x: (f64, f64), y: (f64, f64)) -> Frame {
        let bottom = height - MARGIN_BOTTOM;
        Frame {
            x: Axis {
                lo: x.0,
                hi: x.1,
                px_lo: MARGIN_LEFT,
                px_hi: width - MARGIN_RIGHT,
            },
            y: Axis {
                lo: y.0,
                hi: y.1,
                px_lo: bottom,
                px_hi: MARGIN_TOP,
            },
        }
    }

    /// The pixel position of a data point.
    pub fn map(&self, x: f64, y: f64) -> (f64, f64) {
        (self.x.map(x), self.y.map(y))
    }

    /// Draws the frame box, ticks with labels and the axis titles.
    pub fn draw_axes(&self, svg: &mut Svg<'_>, x_title: &str, y_title: &str) {
        self.draw_x_axis(svg, x_title);
        self.draw_y_ticks(svg);
        svg.text(
            (self.x.px_lo, self.y.px_hi - 10.0),
            "start",
            "axis",
            y_title,
        );
    }

    /// Draws the frame box and the x axis only (ticks, labels, title).
    pub fn draw_x_axis(&self, svg: &mut Svg<'_>, x_title: &str) {
        let (x0, x1, y0, y1) = (self.x.px_lo, self.x.px_hi, self.y.px_lo, self.y.px_hi);
        svg.rect((x0, y1), (x1 - x0, y0 - y1), "frame");
        self.draw_x_ticks(svg);
        svg.text(((x0 + x1) / 2.0, y0 + 38.0), "middle", "axis", x_title);
    }

    /// Ticks and labels along the bottom edge.
    fn draw_x_ticks(&self, svg: &mut Svg<'_>) {
        let (step, values) = ticks(self.x.lo, self.x.hi);
        let y0 = self.y.px_lo;
        for value in values {
            let x = self.x.map(value);
            svg.line((x, y0), (x, y0 + TICK_PX), "tick");
            svg.text(
                (x, y0 + 18.0),
                "middle",
                "tick-label",
                &fixed(value, step_decimals(step)),
            );
        }
    }

    /// Ticks, grid lines and labels along the left edge.
    fn draw_y_ticks(&self, svg: &mut Svg<'_>) {
        let (step, values) = ticks(self.y.lo, self.y.hi);
        let (x0, x1) = (self.x.px_lo, self.x.px_hi);
        for value in values {
            let y = self.y.map(value);
            svg.line((x0, y), (x1, y), "grid");
            svg.line((x0 - TICK_PX, y), (x0, y), "tick");
            let label = fixed(value, step_decimals(step));
            svg.text((x0 - 8.0, y + 4.0), "end", "tick-label", &label);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_steps() {
        assert_eq!(nice_floor(0.37), 0.2);
        assert_eq!(nice_floor(7.0), 5.0);
        assert_eq!(nice_floor(1.0), 1.0);
        assert_eq!(nice_floor(0.0), 1.0);
    }

    #[test]
    fn ticks_cover_range() {
        let (step, values) = ticks(-0.06, 0.06);
        assert!((step - 0.02).abs() < 1e-12);
        assert_eq!(values.len(), 7);
        assert_eq!(step_decimals(step), 2);
    }

    #[test]
    fn ranges_beyond_f64_differences_end() {
        // Their width overflows to infinity: no ticks, and no endless loop.
        let (_, values) = ticks(-1.797e308, 1.797e308);
        assert!(values.is_empty());
        let (step, values) = ticks(-1e307, 1e307);
        assert!(step.is_finite() && !values.is_empty() && values.len() <= MAX_TICKS + 2);
    }

    #[test]
    fn degenerate_ranges_are_widened() {
        assert_eq!(padded(3.0, 3.0, 0.1), (2.5, 3.5));
        assert_eq!(padded(0.0, 2.0, 0.0), (0.0, 2.0));
        assert_eq!(padded(f64::NAN, 1.0, 0.1), (-0.5, 0.5));
        assert_eq!(range([].into_iter()), None);
    }
}
