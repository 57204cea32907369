//! The simulation panels, drawn on Braille canvases: ω against time and
//! the polhode on the momentum sphere (the body is drawn by `solid`).

use nalgebra::Vector3;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line as TextLine, Span};
use ratatui::widgets::canvas::{Canvas, Context, Line, Points};
use ratatui::widgets::{Block, Borders};

use crate::text::num::Num;

use super::geometry::Camera;
use super::theme::Theme;
use crate::sim::scene::SceneRun;

const AXIS_NAMES: [&str; 3] = ["ω₁", "ω₂", "ω₃"];

/// A bordered panel titled `title`, cut with "…" to the panel's `width`.
fn block<'a>(title: String, theme: &Theme, width: u16) -> Block<'a> {
    Block::default()
        .borders(Borders::ALL)
        .border_style(theme.border())
        .title(fitted_title(
            vec![Span::styled(title, theme.heading())],
            usize::from(width.saturating_sub(2)),
        ))
}

/// x half-range that keeps circles round in `area` (cells are about twice
/// as tall as wide), for a y half-range of `r`.
fn aspect_x(area: Rect, r: f64) -> f64 {
    let w = f64::from(area.width.saturating_sub(2).max(1));
    let h = f64::from(area.height.saturating_sub(2).max(1));
    r * w / (2.0 * h)
}

/// How each ω component is drawn without colour: solid, dotted, dashed
/// (`on` of every `period` Braille dots along the curve), and the glyph
/// the legend shows for it.
const STROKES: [(f64, f64, &str); 3] = [(1.0, 1.0, "━"), (1.0, 3.0, "┅"), (5.0, 8.0, "╌")];

/// The points of a polyline (data coordinates) kept by a dash pattern, the
/// pattern measured in Braille dots on screen so it looks the same however
/// the plot is scaled. `scale`: dots per data unit along x and y.
pub fn dashed(points: &[(f64, f64)], scale: (f64, f64), on: f64, period: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut s = 0.0;
    for w in points.windows(2) {
        let (dx, dy) = ((w[1].0 - w[0].0) * scale.0, (w[1].1 - w[0].1) * scale.1);
        let len = dx.hypot(dy);
        let steps = (len * 2.0).ceil().max(1.0) as usize;
        for k in 0..steps {
            let f = k as f64 / steps as f64;
            if s % period < on {
                out.push((
                    w[0].0 + f * (w[1].0 - w[0].0),
                    w[0].1 + f * (w[1].1 - w[0].1),
                ));
            }
            s += len / steps as f64;
        }
    }
    out
}

/// A block title of `parts`, cut to `width` columns with "…" (the legend
/// parts after the first are dropped before the name is cut).
pub fn fitted_title(parts: Vec<Span<'static>>, width: usize) -> TextLine<'static> {
    let total: usize = parts.iter().map(Span::width).sum();
    if total <= width {
        return TextLine::from(parts);
    }
    let Some(first) = parts.into_iter().next() else {
        return TextLine::default();
    };
    if first.width() <= width {
        return TextLine::from(first);
    }
    let text = super::wrap::ellipsize(&first.content, width);
    TextLine::from(Span::styled(text, first.style))
}

/// ω₁, ω₂, ω₃ against time over the whole scene, drawn up to now, each
/// flip marked where it happened. The legend is in the title and the time
/// range on the bottom edge, so neither covers the curves; without colour
/// the three curves are solid, dotted and dashed.
pub fn omega(frame: &mut Frame, area: Rect, run: &SceneRun, title: String, theme: &Theme) {
    let m = run.body().omega_bound(&run.omega0()).max(f64::MIN_POSITIVE) * 1.1;
    let d = run.scene().duration;
    let unit = run.scene().time_unit.clone();
    let dim = theme.plot(Color::DarkGray);
    // The trace on its grid, then on to the frame shown now.
    let now = run.frame();
    let mut points: Vec<(f64, Vector3<f64>)> = run.trace().iter().map(|s| (s.t, s.omega)).collect();
    if points.last().is_none_or(|p| p.0 < now.t) {
        points.push((now.t, now.omega));
    }
    let flips: Vec<f64> = run.flip_times().to_vec();
    let mut parts = vec![Span::styled(format!(" {title} "), theme.heading())];
    for (i, name) in AXIS_NAMES.iter().enumerate() {
        let glyph = if theme.color { "" } else { STROKES[i].2 };
        parts.push(Span::styled(
            format!("{name}{glyph} "),
            Style::new().fg(theme.axis(i)),
        ));
    }
    let inner_w = area.width.saturating_sub(2) as usize;
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(theme.border())
        .title(fitted_title(parts, inner_w))
        .title_bottom(TextLine::styled("0", Style::new().fg(dim)))
        .title_bottom(
            TextLine::styled(format!("{} {unit}", Num(d)), Style::new().fg(dim)).right_aligned(),
        );
    // A row above the curves for the flip numbers, when there is room.
    let rows = f64::from(area.height.saturating_sub(2));
    let top = if rows >= 5.0 {
        m * (1.0 + 2.0 / (rows - 1.0))
    } else {
        m
    };
    let dots = (
        f64::from(area.width.saturating_sub(2)) * 2.0 / d.max(f64::MIN_POSITIVE),
        rows * 4.0 / (top + m),
    );
    let plain = !theme.color;
    let canvas = Canvas::default()
        .block(block)
        .marker(Marker::Braille)
        .x_bounds([0.0, d])
        .y_bounds([-m, top])
        .paint(move |ctx: &mut Context| {
            ctx.draw(&Line::new(0.0, 0.0, d, 0.0, dim));
            // Each flip: a dotted vertical through the plot.
            for &t in &flips {
                let marks = dashed(&[(t, -m), (t, m)], dots, 1.0, 3.0);
                ctx.draw(&Points {
                    coords: &marks,
                    color: dim,
                });
            }
            ctx.layer();
            for (i, &(on, period, _)) in STROKES.iter().enumerate() {
                let color = theme.axis(i);
                let curve: Vec<(f64, f64)> = points.iter().map(|p| (p.0, p.1[i])).collect();
                if plain && on < period {
                    ctx.draw(&Points {
                        coords: &dashed(&curve, dots, on, period),
                        color,
                    });
                } else {
                    for w in curve.windows(2) {
                        ctx.draw(&Line::new(w[0].0, w[0].1, w[1].0, w[1].1, color));
                    }
                }
                ctx.layer();
            }
            // The flip count above each mark, clear of the curves.
            for (k, &t) in flips.iter().enumerate().filter(|_| top > m) {
                ctx.print(
                    t,
                    top,
                    TextLine::styled(format!("↕{}", k + 1), Style::new().fg(dim)),
                );
            }
        });
    frame.render_widget(canvas, area);
}

/// The path of the body-frame angular momentum L = Iω on the sphere
/// |L| = const (drawn as the unit sphere), with the separatrix through the
/// middle axis, the orbit's closed curve, and the path so far.
pub fn polhode(frame: &mut Frame, area: Rect, run: &SceneRun, title: String, theme: &Theme) {
    let Some(picture) = run.polhode() else {
        frame.render_widget(block(title, theme, area.width), area);
        return;
    };
    let camera = Camera::new(
        Vector3::new(0.0, 0.0, 1.0),
        Vector3::new(1.0, 0.6, 0.0),
        0.45,
        None,
    );
    let r = 1.25;
    let xr = aspect_x(area, r);
    let dim = theme.plot(Color::DarkGray);
    let sep = theme.plot(Color::Yellow);
    let orbit_c = theme.plot(Color::Cyan);
    let trail = theme.plot(Color::LightCyan);
    let now_c = theme.plot(Color::White);
    let body = *run.body();
    let path: Vec<Vector3<f64>> = run
        .trace()
        .iter()
        .map(|s| picture.point(&body, &s.omega))
        .collect();
    let current = run
        .frame()
        .polhode
        .unwrap_or_else(|| picture.point(&body, &run.frame().omega));
    let canvas = Canvas::default()
        .block(block(title, theme, area.width))
        .marker(Marker::Braille)
        .x_bounds([-xr, xr])
        .y_bounds([-r, r])
        .paint(move |ctx: &mut Context| {
            // The sphere's outline (an orthographic view: a unit circle).
            let outline: Vec<(f64, f64)> = (0..=120)
                .map(|k| {
                    let th = std::f64::consts::TAU * k as f64 / 120.0;
                    (th.cos(), th.sin())
                })
                .collect();
            for w in outline.windows(2) {
                ctx.draw(&Line::new(w[0].0, w[0].1, w[1].0, w[1].1, dim));
            }
            for i in 0..3 {
                let mut axis = Vector3::zeros();
                axis[i] = 1.12;
                let (x, y, _) = camera.project(&axis);
                ctx.print(
                    x,
                    y,
                    TextLine::styled(["1", "2", "3"][i], Style::new().fg(theme.axis(i))),
                );
            }
            ctx.layer();
            // Front halves solid, back halves dotted.
            let curve = |ctx: &mut Context, pts: &[Vector3<f64>], color: Color| {
                for (k, w) in pts.windows(2).enumerate() {
                    let (a, b) = (camera.project(&w[0]), camera.project(&w[1]));
                    if a.2 <= 0.0 {
                        ctx.draw(&Line::new(a.0, a.1, b.0, b.1, color));
                    } else if k % 3 == 0 {
                        ctx.draw(&Points {
                            coords: &[(a.0, a.1)],
                            color: dim,
                        });
                    }
                }
            };
            for circle in &picture.separatrix {
                curve(ctx, circle, sep);
            }
            curve(ctx, &picture.orbit, orbit_c);
            ctx.layer();
            curve(ctx, &path, trail);
            ctx.layer();
            let (x, y, _) = camera.project(&current);
            ctx.print(x, y, TextLine::styled("●", Style::new().fg(now_c)));
        });
    frame.render_widget(canvas, area);
}
