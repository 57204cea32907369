//! The panels of a system scene on Braille canvases: the plotted quantities
//! against time, the phase portrait, the sketch (lines, dots and trails
//! from the deck's expressions, scaled to the run so far with the aspect
//! kept), and the diagnostics line.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line as TextLine, Span};
use ratatui::widgets::canvas::{Canvas, Context, Line, Points};
use ratatui::widgets::{Block, Borders};

use crate::sim::scene::spec::Mark;
use crate::sim::scene::system::SystemRun;
use crate::text::num::Num;
use crate::text::variable_name as shown_name;
use crate::tui::i18n::{SystemWord, system_word};

use super::theme::Theme;

fn block<'a>(title: String, theme: &Theme) -> Block<'a> {
    Block::default()
        .borders(Borders::ALL)
        .border_style(theme.border())
        .title(Span::styled(title, theme.heading()))
}

/// The smallest and largest finite value, `None` when there is none.
fn extent(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    lo.is_finite().then_some((lo, hi))
}

/// [lo, hi] of `values`, widened a little and never empty.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let Some((lo, hi)) = extent(values) else {
        return (-1.0, 1.0);
    };
    let pad = ((hi - lo) * 0.05)
        .max(hi.abs().max(lo.abs()) * 1e-9)
        .max(1e-300);
    (lo - pad, hi + pad)
}

/// How the plots name a quantity: the scene's label for it (the name the
/// question uses, `A` for `xc`), else its own name with Greek names as
/// letters (`theta` → θ).
fn label(scene: &crate::deck::SystemScene, name: &str) -> String {
    scene
        .label(name)
        .map_or_else(|| shown_name(name), str::to_string)
}

/// The plotted quantities against time over the whole run, drawn up to now.
pub fn plot(frame: &mut Frame, area: Rect, run: &SystemRun, lang: &str, theme: &Theme) {
    let scene = run.scene();
    let k = run.plot_count();
    let trace = run.trace();
    let d = scene.duration;
    // The run's extent, its extremes between samples located on the dense
    // output, with the trace (the same samples) for a run that has none.
    let whole = run.plot_extent().into_iter().flat_map(|(a, b)| [a, b]);
    let values = || (trace.iter().flat_map(|p| p.values[..k].iter().copied())).chain(whole.clone());
    let (lo, hi) = range(values());
    // The labels give the data's own extremes, not the padded frame's
    // (a swing to 2.97 rad is not labelled past π).
    let data = extent(values());
    let dim = theme.plot(Color::DarkGray);
    let names: Vec<String> = scene.plot.iter().map(|n| label(scene, n)).collect();
    // The run's length with its time unit at the right end of the time
    // axis, moved left as far as it needs to show whole ("50 time units",
    // never "50 time u").
    let end_label = format!("{} {}", Num(d), scene.time_unit);
    let inner = f64::from(area.width.saturating_sub(2)).max(1.0);
    let room = inner - unicode_width::UnicodeWidthStr::width(end_label.as_str()) as f64 - 1.0;
    let end_at = d * (room / inner).clamp(0.0, 0.85);
    let title = format!(
        " {} {} ",
        names.join(", "),
        system_word(SystemWord::Plot).get(lang)
    );
    let canvas = Canvas::default()
        .block(block(title, theme))
        .marker(Marker::Braille)
        .x_bounds([0.0, d])
        .y_bounds([lo, hi])
        .paint(move |ctx: &mut Context| {
            if lo < 0.0 && hi > 0.0 {
                ctx.draw(&Line::new(0.0, 0.0, d, 0.0, dim));
                ctx.layer();
            }
            for (i, name) in names.iter().enumerate() {
                let color = theme.axis(i % 3);
                for w in trace.windows(2) {
                    ctx.draw(&Line::new(
                        w[0].t,
                        w[0].values[i],
                        w[1].t,
                        w[1].values[i],
                        color,
                    ));
                }
                ctx.layer();
                ctx.print(
                    d * (0.02 + 0.12 * i as f64),
                    hi,
                    TextLine::styled(name.clone(), Style::new().fg(color)),
                );
            }
            if let Some((min, max)) = data {
                let label = |word: SystemWord, v: f64| {
                    let text = format!(
                        "{} {}",
                        system_word(word).get(lang),
                        crate::text::num::rounded(v, 3)
                    );
                    TextLine::styled(text, Style::new().fg(dim))
                };
                ctx.print(0.0, lo, label(SystemWord::Lowest, min));
                ctx.print(d * 0.6, hi, label(SystemWord::Highest, max));
            }
            ctx.print(
                end_at,
                lo,
                TextLine::styled(end_label.clone(), Style::new().fg(dim)),
            );
        });
    frame.render_widget(canvas, area);
}

/// One quantity against the other.
pub fn phase(frame: &mut Frame, area: Rect, run: &SystemRun, lang: &str, theme: &Theme) {
    let Some([a, b]) = run.scene().phase.clone() else {
        return;
    };
    let k = run.plot_count();
    let trace = run.trace();
    let whole = run.phase_extent();
    let ends = |i: usize| whole.into_iter().flat_map(move |e| [e[i].0, e[i].1]);
    let (x0, x1) = range(trace.iter().map(|p| p.values[k]).chain(ends(0)));
    let (y0, y1) = range(trace.iter().map(|p| p.values[k + 1]).chain(ends(1)));
    let color = theme.axis(0);
    let dim = theme.plot(Color::DarkGray);
    let title = format!(
        " {} ({}, {}) ",
        system_word(SystemWord::Phase).get(lang),
        label(run.scene(), &a),
        label(run.scene(), &b)
    );
    let (a_shown, b_shown) = (label(run.scene(), &a), label(run.scene(), &b));
    let canvas = Canvas::default()
        .block(block(title, theme))
        .marker(Marker::Braille)
        .x_bounds([x0, x1])
        .y_bounds([y0, y1])
        .paint(move |ctx: &mut Context| {
            for w in trace.windows(2) {
                ctx.draw(&Line::new(
                    w[0].values[k],
                    w[0].values[k + 1],
                    w[1].values[k],
                    w[1].values[k + 1],
                    color,
                ));
            }
            if let Some(p) = trace.last() {
                ctx.layer();
                ctx.draw(&Points {
                    coords: &[(p.values[k], p.values[k + 1])],
                    color: Color::White,
                });
            }
            ctx.print(
                x0,
                y0,
                TextLine::styled(a_shown.clone(), Style::new().fg(dim)),
            );
            ctx.print(
                x0,
                y1,
                TextLine::styled(b_shown.clone(), Style::new().fg(dim)),
            );
        });
    frame.render_widget(canvas, area);
}

/// Bounds of the sketch: the run's extent so far (every mark's coordinates,
/// their extremes between samples located on the dense output, and the
/// frame's), with equal scales on both axes (a terminal cell is about twice
/// as tall as wide).
pub fn sketch_bounds(run: &SystemRun, area: Rect) -> ([f64; 2], [f64; 2]) {
    let now = run.marks_now();
    let whole = run.sketch_extent();
    let axis = |i: usize| {
        let ends = whole.into_iter().flat_map(move |e| [e[i].0, e[i].1]);
        // The trail's points too: the same samples, for a run that follows
        // no extent.
        let trail = run
            .trail()
            .iter()
            .flat_map(move |p| p.values.iter().copied().skip(i).step_by(2));
        range(
            now.iter()
                .copied()
                .skip(i)
                .step_by(2)
                .chain(ends)
                .chain(trail),
        )
    };
    let (x0, x1) = axis(0);
    let (y0, y1) = axis(1);
    let w = f64::from(area.width.saturating_sub(2).max(1));
    let h = f64::from(area.height.saturating_sub(2).max(1)) * 2.0;
    // Units per cell-width on each axis made equal: widen the tighter one.
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let sx = (x1 - x0) / w;
    let sy = (y1 - y0) / h;
    let s = sx.max(sy);
    (
        [cx - 0.5 * s * w, cx + 0.5 * s * w],
        [cy - 0.5 * s * h, cy + 0.5 * s * h],
    )
}

pub fn sketch(frame: &mut Frame, area: Rect, run: &SystemRun, lang: &str, theme: &Theme) {
    let (xb, yb) = sketch_bounds(run, area);
    let marks = run.scene().sketch.clone();
    let now = run.marks_now();
    let trail = run.trail();
    let title = format!(" {} ", system_word(SystemWord::Sketch).get(lang));
    let canvas = Canvas::default()
        .block(block(title, theme))
        .marker(Marker::Braille)
        .x_bounds(xb)
        .y_bounds(yb)
        .paint(move |ctx: &mut Context| {
            let mut k = 0;
            let mut dots = Vec::new();
            for (i, m) in marks.iter().enumerate() {
                let color = theme.axis(i % 3);
                match m {
                    Mark::Line(_) => ctx.draw(&Line::new(
                        now[k],
                        now[k + 1],
                        now[k + 2],
                        now[k + 3],
                        color,
                    )),
                    Mark::Dot(_, label) => {
                        dots.push((now[k], now[k + 1], label.as_ref().map(|l| l.get(lang))))
                    }
                    Mark::Trail(_) => {
                        for w in trail.windows(2) {
                            ctx.draw(&Line::new(
                                w[0].values[k],
                                w[0].values[k + 1],
                                w[1].values[k],
                                w[1].values[k + 1],
                                color,
                            ));
                        }
                    }
                }
                k += m.exprs().len();
            }
            // Dots last, on top, each its own glyph and colour: the Sun and
            // the planet are two objects, not two identical points.
            for (j, (x, y, label)) in dots.into_iter().enumerate() {
                let (glyph, color) = DOTS[j % DOTS.len()];
                let style = Style::new().fg(theme.plot(color));
                let text = match label {
                    // The label after the glyph, on the dot's row.
                    Some(l) => format!("{glyph} {}", crate::text::safe::one_line(l)),
                    None => glyph.to_string(),
                };
                ctx.print(x, y, TextLine::styled(text, style));
            }
        });
    frame.render_widget(canvas, area);
}

/// The glyph and colour of the sketch's first, second, … dot.
const DOTS: [(&str, Color); 5] = [
    ("●", Color::White),
    ("◆", Color::Yellow),
    ("■", Color::LightCyan),
    ("▲", Color::LightMagenta),
    ("★", Color::LightGreen),
];

/// `radau rtol 1e-8 · 412 steps · stiff from t = 0.8 s: switched to radau ·
/// drift energy 2.1e-9 · error vs reference 3.4e-7`.
pub fn diagnostics_line(run: &SystemRun, lang: &str) -> String {
    let d = run.diagnostics();
    let sci = |x: f64| {
        if x == 0.0 {
            "0".to_string()
        } else {
            format!("{x:.1e}")
        }
    };
    let w = |x| system_word(x).get(lang);
    let mut s = format!(
        " {} ({}) · {} {}",
        run.method().label(),
        d.solver,
        d.work.steps,
        w(SystemWord::Steps)
    );
    match d.stiff_at {
        Some(t) => s.push_str(&format!(
            " · {} t = {} {}: {}",
            w(SystemWord::StiffFrom),
            crate::text::num::rounded(t, 3),
            run.scene().time_unit,
            w(SystemWord::SwitchedToRadau)
        )),
        None if run.method().kind == crate::sim::solvers::ode::OdeKind::Auto => {
            s.push_str(&format!(" · {}", w(SystemWord::Explicit)))
        }
        None => {}
    }
    for (name, drift) in &d.drift {
        s.push_str(&format!(
            " · {} {name} {}",
            w(SystemWord::Drift),
            sci(*drift)
        ));
    }
    if let Some(e) = d.error {
        s.push_str(&format!(
            " · {} {}",
            w(SystemWord::ErrorVsReference),
            sci(e)
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use ratatui::Terminal;
    use ratatui::backend::TestBackend;

    use super::*;
    use crate::deck::{SystemPanel, SystemScene};
    use crate::sim::solvers::ode::{OdeKind, OdeMethod};
    use crate::tui::theme::Theme;

    /// A scene of the bundled deck `central-forces`.
    fn bundled_scene(id: &str) -> SystemScene {
        let loaded = crate::bundled::load();
        let deck = loaded
            .decks
            .iter()
            .find(|d| d.id == "central-forces")
            .expect("the bundled deck central-forces");
        deck.systems
            .iter()
            .find(|s| s.id == id)
            .unwrap_or_else(|| panic!("no scene {id}"))
            .clone()
    }

    /// The scene run to its end and its sketch drawn in a `w` × `h`
    /// terminal: the columns and rows the trail's Braille dots cover
    /// (inclusive), counted in cells.
    fn drawn_extent(scene: &SystemScene, w: u16, h: u16) -> (usize, usize) {
        let method = OdeMethod::default_for(OdeKind::Auto, scene.duration);
        let mut run = SystemRun::new(scene, method, &[]).expect("the run starts");
        run.run_to_end().expect("the run ends");
        let mut terminal = Terminal::new(TestBackend::new(w, h)).expect("test backend");
        terminal
            .draw(|f| sketch(f, f.area(), &run, "en", &Theme::PLAIN))
            .expect("draw");
        let buffer = terminal.backend().buffer().clone();
        let (mut cols, mut rows) = (Vec::new(), Vec::new());
        for y in 0..h {
            for x in 0..w {
                let c = buffer[(x, y)].symbol().chars().next().unwrap_or(' ');
                // A Braille cell with at least one dot raised.
                if ('\u{2801}'..='\u{28FF}').contains(&c) {
                    cols.push(x);
                    rows.push(y);
                }
            }
        }
        assert!(!cols.is_empty(), "nothing drawn");
        let span = |v: &[u16]| usize::from(*v.iter().max().unwrap() - *v.iter().min().unwrap()) + 1;
        (span(&cols), span(&rows))
    }

    /// The e = 0.9 orbit (a = 1 AU, period 1 yr) started at aphelion,
    /// (−1.9, 0), so perihelion (0.1, 0) comes at t = ½, 1½, …; run 40
    /// periods at RK4 dt 1/8448 yr, the drawn record keeps every 256th
    /// sample and perihelion (sample 4224 of each period) falls halfway
    /// between two kept ones, 0.015 yr from each, where the planet is back
    /// at x = −0.08 AU. Only the trail is sketched (the Sun's label would
    /// cover the cells near perihelion).
    fn from_aphelion() -> SystemScene {
        let mut scene = bundled_scene("eccentric");
        let gm = 4.0 * std::f64::consts::PI.powi(2);
        let va = (gm * 0.1 / 1.9f64).sqrt();
        scene.initial = vec![-1.9, 0.0, 0.0, -va];
        scene.duration = 40.0;
        scene.show = vec![SystemPanel::Sketch];
        scene.sketch = vec![Mark::Trail(["x".into(), "y".into()])];
        scene
    }

    /// The sketch of an orbit whose samples skip perihelion reaches out to
    /// it: the panel is scaled to the continuous solution's extent
    /// (perihelion at x = a(1 − e) = 0.1 AU), and the trail is drawn
    /// through perihelion, not along the chord between the samples either
    /// side (at x = −0.08 AU, 9 columns short in this panel).
    #[test]
    fn the_sketch_reaches_the_perihelion_its_samples_skip() {
        let scene = from_aphelion();
        let method = OdeMethod::with_setting(OdeKind::Rk4, 1.0 / 8448.0).unwrap();
        let mut run = SystemRun::new(&scene, method, &[]).expect("the run starts");
        run.run_to_end().expect("the run ends");
        let (w, h) = (100u16, 30u16);
        let (xb, yb) = sketch_bounds(&run, Rect::new(0, 0, w, h));
        assert!(
            xb[1] >= 0.1,
            "the sketch reaches x = {} only, perihelion is at 0.1",
            xb[1]
        );
        let mut terminal = Terminal::new(TestBackend::new(w, h)).expect("test backend");
        terminal
            .draw(|f| sketch(f, f.area(), &run, "en", &Theme::PLAIN))
            .expect("draw");
        let buffer = terminal.backend().buffer().clone();
        let raised = |x: u16, y: u16| {
            let c = buffer[(x, y)].symbol().chars().next().unwrap_or(' ');
            ('\u{2801}'..='\u{28FF}').contains(&c)
        };
        // The cell of (x, y) inside the border.
        let (iw, ih) = (f64::from(w - 2), f64::from(h - 2));
        let col = |x: f64| {
            1 + ((x - xb[0]) / (xb[1] - xb[0]) * iw)
                .floor()
                .clamp(0.0, iw - 1.0) as u16
        };
        let row = |y: f64| {
            1 + ((yb[1] - y) / (yb[1] - yb[0]) * ih)
                .floor()
                .clamp(0.0, ih - 1.0) as u16
        };
        let (pc, pr) = (col(0.1), row(0.0));
        let rightmost = (1..w - 1)
            .rev()
            .find(|&x| (1..h - 1).any(|y| raised(x, y)))
            .expect("a trail drawn");
        assert!(
            rightmost.abs_diff(pc) <= 1,
            "the trail's near end is drawn at column {rightmost}, perihelion is at column {pc}"
        );
        assert!(
            (pr - 1..=pr + 1).any(|y| (pc - 1..=pc + 1).any(|x| raised(x, y))),
            "nothing drawn at perihelion (column {pc}, row {pr})"
        );
    }

    /// The launch scene at the circular speed 2π AU/yr: a circle of 1 AU.
    fn circle() -> SystemScene {
        let mut scene = bundled_scene("launch");
        let vy = scene.variables.iter().position(|v| v == "vy").unwrap();
        scene.initial[vy] = 2.0 * std::f64::consts::PI;
        scene
    }

    /// A circular orbit is drawn as a circle, whatever the panel's shape:
    /// a terminal cell is about twice as tall as wide, so its curve covers
    /// twice as many columns as rows.
    #[test]
    fn a_circular_orbit_is_drawn_round_in_any_panel() {
        let scene = circle();
        for (w, h) in [(60, 20), (100, 14), (40, 30), (120, 40)] {
            let (cols, rows) = drawn_extent(&scene, w, h);
            let ratio = cols as f64 / rows as f64;
            assert!(
                (ratio - 2.0).abs() <= 0.25,
                "{w}×{h}: the circle covers {cols} columns and {rows} rows ({ratio:.2}:1, not 2:1)"
            );
        }
    }

    /// The e = 0.9 orbit keeps its shape: 2a = 2 AU across and 2b =
    /// 2 sqrt(1 − e²) = 0.872 AU high, so 2 × 2/0.872 = 4.6 times as many
    /// columns as rows.
    #[test]
    fn an_eccentric_orbit_keeps_its_aspect() {
        let scene = bundled_scene("eccentric");
        let want = 2.0 * 2.0 / (2.0 * (1.0f64 - 0.81).sqrt());
        for (w, h) in [(100, 30), (120, 24)] {
            let (cols, rows) = drawn_extent(&scene, w, h);
            let ratio = cols as f64 / rows as f64;
            assert!(
                (ratio / want - 1.0).abs() <= 0.12,
                "{w}×{h}: the ellipse covers {cols} columns and {rows} rows ({ratio:.2}:1, not {want:.2}:1)"
            );
        }
    }
}
