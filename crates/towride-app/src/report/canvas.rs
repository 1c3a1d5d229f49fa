//! Drawing primitives over a plotters backend (bitmap or SVG): clipped polylines of a
//! given width, dots, rectangles and text in the bundled DejaVu Sans.
//!
//! Wide lines on the bitmap are drawn as parallel one-pixel lines (plotters' own wide
//! strokes fill one polygon per path, which leaves a dense zig-zag hollow), and text on
//! the bitmap is rasterised here from the glyph outlines so that its baseline and size
//! are exact (the digits' height is what the figure test checks).

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::sync::OnceLock;

use super::ReportError;

/// The bundled font.
pub fn font() -> &'static FontRef<'static> {
    static F: OnceLock<FontRef<'static>> = OnceLock::new();
    F.get_or_init(|| {
        let bytes: &'static [u8] = include_bytes!("../../assets/DejaVuSans.ttf");
        FontRef::try_from_slice(bytes).expect("the bundled font is valid")
    })
}

/// Height of a digit at font size `size` [px] (the size is the glyphs' ascent plus
/// descent, as ab_glyph scales).
pub fn digit_height(size: f64) -> f64 {
    let f = font();
    let g = f.glyph_id('0').with_scale(PxScale::from(size as f32));
    f.outline_glyph(g)
        .map_or(0.7 * size, |o| o.px_bounds().height() as f64)
}

/// Width of `text` at font size `size` [px].
pub fn text_width(text: &str, size: f64) -> f64 {
    let f = font().as_scaled(PxScale::from(size as f32));
    let mut w = 0.0;
    let mut prev = None;
    for c in text.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            w += f.kern(p, id);
        }
        w += f.h_advance(id);
        prev = Some(id);
    }
    w as f64
}

/// Horizontal placement of text relative to its anchor.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Align {
    /// The anchor is the text's left end.
    Left,
    /// The anchor is the text's middle.
    Centre,
    /// The anchor is the text's right end.
    Right,
}

/// A pixel rectangle: x0 <= x < x1, y0 <= y < y1.
#[derive(Clone, Copy, Debug)]
pub struct Rect {
    /// Left column.
    pub x0: i32,
    /// Top row.
    pub y0: i32,
    /// One past the right column.
    pub x1: i32,
    /// One past the bottom row.
    pub y1: i32,
}

impl Rect {
    /// True when the pixel lies inside.
    pub fn contains(&self, x: i32, y: i32) -> bool {
        (self.x0..self.x1).contains(&x) && (self.y0..self.y1).contains(&y)
    }
}

/// A drawing surface: a plotters drawing area and whether it is vector (SVG).
pub struct Canvas<'a, DB: DrawingBackend> {
    /// The whole picture.
    pub root: &'a DrawingArea<DB, plotters::coord::Shift>,
    /// SVG: wide lines and text go to the backend as they are.
    pub vector: bool,
}

fn err<E: std::fmt::Debug>(e: E) -> ReportError {
    ReportError::Plot(format!("{e:?}"))
}

fn colour(c: [u8; 3]) -> RGBColor {
    RGBColor(c[0], c[1], c[2])
}

/// Clips the segment a-b to the closed box [x0, x1] x [y0, y1] (Liang-Barsky).
pub fn clip(a: (f64, f64), b: (f64, f64), bx: [f64; 4]) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - bx[0]),
        (dx, bx[2] - a.0),
        (-dy, a.1 - bx[1]),
        (dy, bx[3] - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some((
        (a.0 + t0 * dx, a.1 + t0 * dy),
        (a.0 + t1 * dx, a.1 + t1 * dy),
    ))
}

impl<DB: DrawingBackend> Canvas<'_, DB> {
    /// Fills the rectangle.
    pub fn fill(&self, r: Rect, c: [u8; 3]) -> Result<(), ReportError> {
        self.root
            .draw(&Rectangle::new(
                [(r.x0, r.y0), (r.x1 - 1, r.y1 - 1)],
                colour(c).filled(),
            ))
            .map_err(err)
    }

    /// A polyline of `width` pixels through `pts` (pixel coordinates), clipped to `clip`:
    /// no pixel of it falls outside.
    pub fn polyline(
        &self,
        pts: &[(f64, f64)],
        c: [u8; 3],
        width: u32,
        clip_to: Rect,
    ) -> Result<(), ReportError> {
        if pts.len() < 2 {
            if let Some(&p) = pts.first() {
                return self.dot(p, (width as f64 / 2.0).max(1.0), c, clip_to);
            }
            return Ok(());
        }
        let w = width.max(1) as i32;
        if self.vector {
            // The SVG stroke is centred on the path: keep it half a width inside.
            let h = 0.5 * w as f64;
            let bx = [
                clip_to.x0 as f64 + h,
                clip_to.y0 as f64 + h,
                (clip_to.x1 - 1) as f64 - h,
                (clip_to.y1 - 1) as f64 - h,
            ];
            let style = colour(c).stroke_width(width);
            let mut run: Vec<(i32, i32)> = Vec::new();
            let flush = |run: &mut Vec<(i32, i32)>| -> Result<(), ReportError> {
                if run.len() > 1 {
                    self.root
                        .draw(&PathElement::new(std::mem::take(run), style))
                        .map_err(err)?;
                }
                run.clear();
                Ok(())
            };
            for s in pts.windows(2) {
                match clip(s[0], s[1], bx) {
                    Some((a, b)) => {
                        let a = (a.0.round() as i32, a.1.round() as i32);
                        let b = (b.0.round() as i32, b.1.round() as i32);
                        if run.last() != Some(&a) {
                            flush(&mut run)?;
                            run.push(a);
                        }
                        run.push(b);
                    }
                    None => flush(&mut run)?,
                }
            }
            return flush(&mut run);
        }
        // Bitmap: `w` parallel one-pixel lines, offset across the segment's main
        // direction, each clipped to the box.
        let bx = [
            clip_to.x0 as f64,
            clip_to.y0 as f64,
            (clip_to.x1 - 1) as f64,
            (clip_to.y1 - 1) as f64,
        ];
        let lo = -(w - 1) / 2;
        for s in pts.windows(2) {
            let (a, b) = (s[0], s[1]);
            let steep = (b.1 - a.1).abs() > (b.0 - a.0).abs();
            for k in lo..lo + w {
                let d = k as f64;
                let (a, b) = if steep {
                    ((a.0 + d, a.1), (b.0 + d, b.1))
                } else {
                    ((a.0, a.1 + d), (b.0, b.1 + d))
                };
                if let Some((a, b)) = clip(a, b, bx) {
                    let a = (a.0.round() as i32, a.1.round() as i32);
                    let b = (b.0.round() as i32, b.1.round() as i32);
                    self.bresenham(a, b, c)?;
                }
            }
        }
        Ok(())
    }

    /// Every pixel of the line a-b in full colour (plotters blends the pixels of sloped
    /// lines, which would make a trace's colour depend on its slope).
    fn bresenham(&self, a: (i32, i32), b: (i32, i32), c: [u8; 3]) -> Result<(), ReportError> {
        let (dx, dy) = ((b.0 - a.0).abs(), -(b.1 - a.1).abs());
        let (sx, sy) = ((b.0 - a.0).signum(), (b.1 - a.1).signum());
        let (mut x, mut y, mut e) = (a.0, a.1, dx + dy);
        let rgb = colour(c);
        loop {
            self.root.draw_pixel((x, y), &rgb).map_err(err)?;
            if (x, y) == b {
                return Ok(());
            }
            let e2 = 2 * e;
            if e2 >= dy {
                e += dy;
                x += sx;
            }
            if e2 <= dx {
                e += dx;
                y += sy;
            }
        }
    }

    /// A filled disc of radius `r` at `p`, only its pixels inside `clip_to`.
    pub fn dot(&self, p: (f64, f64), r: f64, c: [u8; 3], clip_to: Rect) -> Result<(), ReportError> {
        let (cx, cy) = (p.0.round() as i32, p.1.round() as i32);
        let ri = r.ceil() as i32;
        if self.vector {
            if clip_to.contains(cx - ri, cy - ri) && clip_to.contains(cx + ri, cy + ri) {
                self.root
                    .draw(&Circle::new((cx, cy), r.round() as i32, colour(c).filled()))
                    .map_err(err)?;
            }
            return Ok(());
        }
        for y in cy - ri..=cy + ri {
            for x in cx - ri..=cx + ri {
                let d2 = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) as f64;
                if d2 <= r * r + 0.25 && clip_to.contains(x, y) {
                    self.root.draw_pixel((x, y), &colour(c)).map_err(err)?;
                }
            }
        }
        Ok(())
    }

    /// A one-pixel line between pixel centres (frames, grid, ticks).
    pub fn hairline(&self, a: (i32, i32), b: (i32, i32), c: [u8; 3]) -> Result<(), ReportError> {
        self.root
            .draw(&PathElement::new(vec![a, b], colour(c).stroke_width(1)))
            .map_err(err)
    }

    /// Text of font size `size` whose digits' top (`v` = 0), middle (0.5) or baseline (1)
    /// is at `y`; rotated a quarter turn anticlockwise (reading upwards) when `up`.
    #[allow(clippy::too_many_arguments)]
    pub fn text(
        &self,
        s: &str,
        x: f64,
        y: f64,
        size: f64,
        c: [u8; 3],
        align: Align,
        v: f64,
        up: bool,
    ) -> Result<(), ReportError> {
        let w = text_width(s, size);
        let cap = digit_height(size);
        let along = match align {
            Align::Left => 0.0,
            Align::Centre => -0.5 * w,
            Align::Right => -w,
        };
        // Distance from the anchor line to the baseline, across the text.
        let across = (1.0 - v) * cap;
        if self.vector {
            let (bx, by) = if up {
                (x + across, y - along)
            } else {
                (x + along, y + across)
            };
            let em = size * 2048.0 / 2384.0;
            let rgb = colour(c);
            let mut style = TextStyle::from(("sans-serif", em * 1.24).into_font())
                .color(&rgb)
                .pos(Pos::new(HPos::Left, VPos::Bottom));
            if up {
                style = style.transform(FontTransform::Rotate270);
            }
            // plotters puts the baseline 0.5 ex above a bottom anchor.
            let lift = 0.26 * em;
            let at = if up {
                ((bx + lift).round() as i32, by.round() as i32)
            } else {
                (bx.round() as i32, (by + lift).round() as i32)
            };
            return self.root.draw_text(s, &style, at).map_err(err);
        }
        let f = font().as_scaled(PxScale::from(size as f32));
        let mut pen = along;
        let mut prev = None;
        for ch in s.chars() {
            let id = f.glyph_id(ch);
            if let Some(p) = prev {
                pen += f.kern(p, id) as f64;
            }
            prev = Some(id);
            let g =
                id.with_scale_and_position(PxScale::from(size as f32), ab_glyph::point(0.0, 0.0));
            if let Some(o) = f.outline_glyph(g) {
                let bb = o.px_bounds();
                let mut px: Vec<(i32, i32, f32)> = Vec::new();
                o.draw(|gx, gy, cov| {
                    if cov > 0.02 {
                        // Glyph pixel (gx, gy) from the box's corner; y down from the
                        // baseline is bb.min.y + gy.
                        let u = pen + bb.min.x as f64 + gx as f64;
                        let t = bb.min.y as f64 + gy as f64 + across;
                        let (x, y) = if up { (x + t, y - u) } else { (x + u, y + t) };
                        px.push((x.round() as i32, y.round() as i32, cov));
                    }
                });
                for (x, y, cov) in px {
                    self.root
                        .draw_pixel((x, y), &colour(c).mix(cov.min(1.0) as f64))
                        .map_err(err)?;
                }
            }
            pen += f.h_advance(id) as f64;
        }
        Ok(())
    }
}
