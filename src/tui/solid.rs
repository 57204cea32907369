//! The body panel: the rigid body drawn with its real proportions, as a
//! solid. A body with three equal moments is a sphere, two equal moments a
//! spheroid, three distinct ones a box (a plate when one side all but
//! vanishes, a needle when two do); the shape's sides give the body's
//! moments (the same ratios for a box and an ellipsoid). Each surface
//! point is found by casting a ray per Braille dot, shaded by its angle to
//! a fixed light (dot density, so the faces differ without colour), and
//! coloured by the body axis its surface faces, in the plots' axis
//! colours. The fixed angular momentum L points up.

use nalgebra::{UnitQuaternion, Vector3};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line as TextLine, Span};
use ratatui::widgets::canvas::{Canvas, Context, Line, Points};
use ratatui::widgets::{Block, Borders};

use crate::sim::scene::SceneRun;
use crate::tui::geometry::{Camera, box_half_sides};
use crate::tui::i18n::{Msg, Words, sim_words as w};
use crate::tui::plots::fitted_title;
use crate::tui::theme::Theme;

/// The solid a body is drawn as.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    Sphere,
    /// Two equal moments: an ellipsoid of revolution, flattened along its
    /// symmetry axis (the largest moment) or drawn out along it.
    Oblate([f64; 3]),
    Prolate([f64; 3]),
    /// Three distinct moments, one side all but zero.
    Plate([f64; 3]),
    /// Three distinct moments, two sides all but zero.
    Needle([f64; 3]),
    /// Three distinct moments.
    Block([f64; 3]),
}

/// Below this fraction of the longest side a side counts as vanishing.
const THIN: f64 = 0.12;
/// The thinnest side drawn, as a fraction of the longest: a plate seen
/// edge-on stays a visible line.
const MIN_SIDE: f64 = 0.04;

impl Shape {
    pub fn of(inertia: [f64; 3]) -> Shape {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
        let [i1, i2, i3] = inertia;
        let half = box_half_sides(inertia).map(|s| s.max(MIN_SIDE));
        if close(i1, i2) && close(i2, i3) {
            return Shape::Sphere;
        }
        let thin = half.iter().filter(|&&s| s < THIN).count();
        let pair = [(0, 1, 2), (1, 2, 0), (0, 2, 1)]
            .into_iter()
            .find(|&(a, b, _)| close(inertia[a], inertia[b]));
        match (pair, thin) {
            (_, 2) => Shape::Needle(half),
            (Some((_, _, axis)), _) if half[axis] < half[(axis + 1) % 3] => Shape::Oblate(half),
            (Some(_), _) => Shape::Prolate(half),
            (None, 1) => Shape::Plate(half),
            (None, _) => Shape::Block(half),
        }
    }

    pub fn name(&self) -> Words {
        match self {
            Shape::Sphere => w::SPHERE,
            Shape::Oblate(_) => w::OBLATE,
            Shape::Prolate(_) => w::PROLATE,
            Shape::Plate(_) => w::PLATE,
            Shape::Needle(_) => w::NEEDLE,
            Shape::Block(_) => w::BLOCK,
        }
    }

    /// Half-sides (box) or semi-axes (ellipsoid), longest 1.
    pub fn half(&self) -> [f64; 3] {
        match *self {
            Shape::Sphere => [1.0; 3],
            Shape::Oblate(h)
            | Shape::Prolate(h)
            | Shape::Plate(h)
            | Shape::Needle(h)
            | Shape::Block(h) => h,
        }
    }

    /// The same shape with no side thinner than `min`: a side below the
    /// screen's resolution would fall between the dots.
    pub fn at_least(&self, min: f64) -> Shape {
        let f = |h: [f64; 3]| h.map(|s| s.max(min));
        match *self {
            Shape::Sphere => Shape::Sphere,
            Shape::Oblate(h) => Shape::Oblate(f(h)),
            Shape::Prolate(h) => Shape::Prolate(f(h)),
            Shape::Plate(h) => Shape::Plate(f(h)),
            Shape::Needle(h) => Shape::Needle(f(h)),
            Shape::Block(h) => Shape::Block(f(h)),
        }
    }

    fn is_box(&self) -> bool {
        matches!(self, Shape::Plate(_) | Shape::Needle(_) | Shape::Block(_))
    }

    /// The radius of the smallest sphere about the centre holding the body
    /// in every orientation.
    pub fn radius(&self) -> f64 {
        let h = self.half();
        if self.is_box() {
            (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt()
        } else {
            h.iter().cloned().fold(0.0, f64::max)
        }
    }

    /// Where a ray (body frame) first meets the surface: the distance along
    /// it and the outward normal there.
    pub fn hit(&self, o: Vector3<f64>, d: Vector3<f64>) -> Option<(f64, Vector3<f64>)> {
        let h = self.half();
        if self.is_box() {
            let (mut near, mut far, mut normal) =
                (f64::NEG_INFINITY, f64::INFINITY, Vector3::zeros());
            for i in 0..3 {
                if d[i].abs() < 1e-12 {
                    if o[i].abs() > h[i] {
                        return None;
                    }
                    continue;
                }
                let (a, b) = ((-h[i] - o[i]) / d[i], (h[i] - o[i]) / d[i]);
                let (lo, hi) = if a < b { (a, b) } else { (b, a) };
                if lo > near {
                    near = lo;
                    normal = Vector3::zeros();
                    normal[i] = -d[i].signum();
                }
                far = far.min(hi);
            }
            (near <= far && near > 0.0).then_some((near, normal))
        } else {
            // The ellipsoid scaled to the unit sphere.
            let (os, ds) = (
                o.component_div(&Vector3::from(h)),
                d.component_div(&Vector3::from(h)),
            );
            let (a, b, c) = (ds.dot(&ds), 2.0 * os.dot(&ds), os.dot(&os) - 1.0);
            let disc = b * b - 4.0 * a * c;
            if disc < 0.0 {
                return None;
            }
            let t = (-b - disc.sqrt()) / (2.0 * a);
            let p = o + d * t;
            let n = Vector3::new(
                p[0] / (h[0] * h[0]),
                p[1] / (h[1] * h[1]),
                p[2] / (h[2] * h[2]),
            );
            (t > 0.0).then(|| (t, n.normalize()))
        }
    }
}

/// 2×4 ordered-dither thresholds, one per dot of a Braille cell.
const BAYER: [[f64; 2]; 4] = [[0.0, 4.0], [6.0, 2.0], [1.0, 5.0], [7.0, 3.0]];

/// A lit dot of the body on screen: its position (canvas units) and the
/// body axis its surface faces.
pub type Dot = (f64, f64, usize);

/// The dots of `shape` turned by `q`, seen by `camera` (orthographic) on a
/// canvas of `cols` × `rows` cells spanning `[-xr, xr] × [-yr, yr]`.
pub fn raster(
    shape: &Shape,
    q: &UnitQuaternion<f64>,
    camera: &Camera,
    (cols, rows): (u16, u16),
    (xr, yr): (f64, f64),
) -> Vec<Dot> {
    let (nx, ny) = (usize::from(cols) * 2, usize::from(rows) * 4);
    let dot = (2.0 * xr / nx.max(1) as f64).max(2.0 * yr / ny.max(1) as f64);
    let shape = &shape.at_least(0.75 * dot);
    let light = (camera.right() * -0.45 + camera.up() * 0.6 - camera.forward() * 0.66).normalize();
    let inv = q.inverse();
    let radius = shape.radius();
    let back = radius * 4.0;
    // The screen's axes in the body frame, turned once per frame.
    let (right, up, d) = (
        inv * camera.right(),
        inv * camera.up(),
        inv * camera.forward(),
    );
    let mut out = Vec::new();
    for py in 0..ny {
        let y = yr - (py as f64 + 0.5) / ny as f64 * 2.0 * yr;
        if y.abs() > radius {
            continue;
        }
        for px in 0..nx {
            let x = -xr + (px as f64 + 0.5) / nx as f64 * 2.0 * xr;
            // Outside the body's bounding circle no ray can hit it.
            if x * x + y * y > radius * radius {
                continue;
            }
            let o = right * x + up * y - d * back;
            let Some((_, n)) = shape.hit(o, d) else {
                continue;
            };
            let lit = (q * n).dot(&light).max(0.0);
            // Never below three dots in eight: a face turned from the light
            // (or a plate's rim) stays visible.
            let level = 0.35 + 0.65 * lit;
            if level * 8.0 > BAYER[py % 4][px % 2] {
                let face = (0..3)
                    .max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
                    .unwrap_or(0);
                out.push((x, y, face));
            }
        }
    }
    out
}

/// The body panel: the solid, its axes labelled 1, 2, 3 at their tips,
/// and the fixed L drawn up from the centre.
pub fn draw(frame: &mut Frame, area: Rect, run: &SceneRun, lang: &str, theme: &Theme) {
    let shape = Shape::of(run.scene().inertia);
    let title = format!(
        " {}: {} ",
        crate::tui::i18n::tr(lang, Msg::Body),
        shape.name().get(lang)
    );
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(theme.border())
        .title(fitted_title(
            vec![Span::styled(title, theme.heading())],
            area.width.saturating_sub(2) as usize,
        ));
    let inner = block.inner(area);
    let l_space = run.body().momentum(&run.omega0());
    let camera = Camera::new(l_space, Vector3::new(1.0, 0.7, 0.4), 0.35, None);
    let q = run.frame().q.unwrap_or_else(UnitQuaternion::identity);
    // The body in every orientation, its axis labels and L's arrowhead fit.
    let yr = shape.radius() * 1.3;
    let (cw, ch) = (
        f64::from(inner.width.max(1)),
        f64::from(inner.height.max(1)),
    );
    // Cells are about twice as tall as wide: keep circles round.
    let (xr, yr) = if cw / (2.0 * ch) >= 1.0 {
        (yr * cw / (2.0 * ch), yr)
    } else {
        (yr, yr * 2.0 * ch / cw)
    };
    let dots = raster(&shape, &q, &camera, (inner.width, inner.height), (xr, yr));
    let half = shape.half();
    let top = yr * 0.92;
    let l_color = theme.plot(Color::White);
    let canvas = Canvas::default()
        .block(block)
        .marker(Marker::Braille)
        .x_bounds([-xr, xr])
        .y_bounds([-yr, yr])
        .paint(move |ctx: &mut Context| {
            ctx.draw(&Line::new(0.0, 0.0, 0.0, top, l_color));
            ctx.layer();
            for face in 0..3 {
                let coords: Vec<(f64, f64)> = dots
                    .iter()
                    .filter(|d| d.2 == face)
                    .map(|d| (d.0, d.1))
                    .collect();
                ctx.draw(&Points {
                    coords: &coords,
                    color: theme.axis(face),
                });
            }
            ctx.layer();
            ctx.print(0.0, top, TextLine::styled("▲L", Style::new().fg(l_color)));
            for i in 0..3 {
                let mut axis = Vector3::zeros();
                axis[i] = half[i] + 0.12;
                let tip = q * axis;
                let (x, y, _) = camera.project(&tip);
                ctx.print(
                    x,
                    y,
                    TextLine::styled(["1", "2", "3"][i], Style::new().fg(theme.axis(i))),
                );
            }
        });
    frame.render_widget(canvas, area);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera::new(Vector3::z(), Vector3::new(1.0, 0.7, 0.4), 0.35, None)
    }

    /// Width and height (canvas units) of what the raster lit.
    fn extent(dots: &[Dot]) -> (f64, f64) {
        let span = |f: fn(&Dot) -> f64| {
            let lo = dots.iter().map(f).fold(f64::INFINITY, f64::min);
            let hi = dots.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
            hi - lo
        };
        (span(|d| d.0), span(|d| d.1))
    }

    #[test]
    fn shapes_are_named_for_their_moments() {
        assert_eq!(Shape::of([2.0, 2.0, 2.0]), Shape::Sphere);
        assert!(matches!(Shape::of([1.0, 2.0, 3.0]), Shape::Plate(_)));
        assert!(matches!(Shape::of([2.0, 2.0, 3.0]), Shape::Oblate(_)));
        assert!(matches!(Shape::of([1.0, 1.0, 1.0033]), Shape::Oblate(_)));
        assert!(matches!(Shape::of([2.0, 3.0, 3.0]), Shape::Prolate(_)));
        assert!(matches!(Shape::of([0.01, 1.0, 1.0]), Shape::Needle(_)));
        assert!(matches!(Shape::of([2.0, 3.0, 4.0]), Shape::Block(_)));
    }

    #[test]
    fn a_sphere_is_round_and_fits_the_canvas_however_turned() {
        let s = Shape::of([2.0, 2.0, 2.0]);
        for angle in [0.0, 0.7, 2.1] {
            let q = UnitQuaternion::from_euler_angles(angle, angle * 0.5, 0.3);
            // 20 × 10 cells over [-2.6, 2.6]²: square in dots (40 × 40).
            let dots = raster(&s, &q, &camera(), (20, 10), (2.6, 2.6));
            let (w, h) = extent(&dots);
            assert!((w - 2.0).abs() < 0.2 && (h - 2.0).abs() < 0.3, "{w} × {h}");
            assert!(dots.iter().all(|d| d.0.abs() <= 2.6 && d.1.abs() <= 2.6));
        }
    }

    #[test]
    fn a_plate_is_wide_face_on_and_thin_edge_on() {
        let s = Shape::of([1.0, 2.0, 3.0]);
        let cam = Camera::new(Vector3::z(), Vector3::x(), 0.0, None);
        // Seen along its thin axis 3 turned towards the eye: a full face.
        let face_on =
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
        let (w, h) = extent(&raster(&s, &face_on, &cam, (40, 20), (1.5, 1.5)));
        assert!(w > 1.0 && h > 1.0, "face on: {w} × {h}");
        // Its thin axis vertical on screen: a line, still drawn in a small
        // panel (6 rows, 24 dots over 3 units: the plate is 2 dots thick).
        let edge_on = UnitQuaternion::identity();
        for rows in [20, 6] {
            let dots = raster(&s, &edge_on, &cam, (40, rows), (1.5, 1.5));
            assert!(dots.len() > 10, "edge on, {rows} rows: {} dots", dots.len());
            let (w, h) = extent(&dots);
            assert!(h < 0.25 && w > 1.0, "edge on, {rows} rows: {w} × {h}");
        }
    }

    #[test]
    fn the_faces_of_a_box_are_told_apart() {
        let s = Shape::of([2.0, 3.0, 4.0]);
        let dots = raster(
            &s,
            &UnitQuaternion::identity(),
            &camera(),
            (30, 15),
            (2.0, 2.0),
        );
        let faces: std::collections::BTreeSet<usize> = dots.iter().map(|d| d.2).collect();
        assert_eq!(faces.len(), 3, "three faces seen from a corner");
        // And by shading alone: the lit share of dots differs per face.
        let share = |f: usize| dots.iter().filter(|d| d.2 == f).count();
        assert!(share(0) != share(1) || share(1) != share(2));
    }
}
