//! Exploring a scene with its knobs (issue 24 §1, PhET in a terminal):
//! after the verdict (or from the prompt list, `x`) `←/→` (`h/l`) turn the
//! selected knob by its step, `Tab` selects the next, and the run restarts
//! at once with the new value (a new [`Live`]; the keys are never held up,
//! the run advances in the frame's slices as any run does). The scene's
//! `explore` measure is plotted against the selected knob, one point per
//! value visited, measured off the UI thread on the scene's reference run
//! (the run a verdict reads), so the curve grows as fast as the learner
//! turns; a value where the measure is undefined says so.

use std::sync::mpsc::{Receiver, TryRecvError, channel};

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::{Canvas, Line as Segment, Points};
use ratatui::widgets::{Block, Borders, Paragraph};

use crate::deck::{Deck, Explore, Measure, Prompt, SystemPanel};
use crate::sim::Method;
use crate::sim::scene::knob::{self, Knob};
use crate::text::num::sig;
use crate::tui::app::App;
use crate::tui::i18n::{SystemWord, Words};
use crate::tui::live::{Live, Sim, system_reference};

/// Words of the explore view (English, Hinglish).
const MEASURING: Words = Words("measuring…", "naap rahe hain…");
const NOT_MEASURABLE: Words = Words(
    "not measurable at this value",
    "is value pe naapa nahi ja sakta",
);
const NOT_YET: Words = Words("not measurable yet", "abhi naapa nahi ja sakta");
const NO_KNOBS: Words = Words(
    "this scene has no knobs to explore",
    "is scene mein explore karne ke liye knobs nahi hain",
);
const POINTS: Words = Words("points", "points");
const AT: Words = Words("at", "pe");
const TURN: Words = Words("turn", "ghumao");
const NEXT_KNOB: Words = Words("next knob", "agla knob");

/// One point of the curve: the knobs' values (each in its own unit) and
/// what the measure was there, or why there is none.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub values: Vec<f64>,
    pub measured: Result<f64, Unmeasured>,
}

/// Why a point has no value.
#[derive(Debug, Clone, PartialEq)]
pub enum Unmeasured {
    /// The run gives no value of the measure there (too few crossings,
    /// fewer than two flips …).
    Undefined,
    /// The run itself failed there.
    Failed(String),
}

/// The explore state of the predict screen.
pub struct Exploring {
    pub explore: Explore,
    /// Each knob's value, in its own unit.
    pub values: Vec<f64>,
    /// The knob `←/→` turn.
    pub selected: usize,
    /// The points measured so far, in the order visited.
    pub curve: Vec<Point>,
    /// The prompt's measures (kept so a system run plans the same).
    measures: Vec<Measure>,
    /// A measurement under way: the values it is for.
    pending: Option<(Vec<f64>, Receiver<Measured>)>,
}

/// What a measurement thread sends: the measure's value (`None`: undefined
/// there), or why the run failed.
type Measured = Result<Option<f64>, String>;

/// The scene as the knobs set it: a rigid body's or a system's.
enum Turned {
    Rigid(Box<crate::deck::Scene>),
    System(Box<crate::deck::SystemScene>),
}

impl Exploring {
    /// The explore state of `prompt`'s scene at its own values; `None`
    /// when the scene has no knobs.
    pub fn new(deck: &Deck, prompt: &Prompt) -> Option<Exploring> {
        let explore = deck.explore(&prompt.scene)?.clone();
        if explore.knobs.is_empty() {
            return None;
        }
        let own = |k: &Knob| {
            let v = if let Some(s) = deck.system(&prompt.scene) {
                knob::system_value(s, &k.target)
            } else {
                deck.scene(&prompt.scene)
                    .and_then(|s| knob::rigid_value(s, &k.target))
            };
            let v = v.map_or(k.min, |v| (v / k.scale).clamp(k.min, k.max));
            // On the grid but for the rounding of the unit's conversion
            // (30° is 30.000000000000004 after radians and back): the grid
            // point, so a value visited again is the same point.
            let grid = k.min + ((v - k.min) / k.step).round() * k.step;
            if (v - grid).abs() <= 1e-9 * v.abs().max(1.0) && grid <= k.max {
                grid
            } else {
                v
            }
        };
        let values = explore.knobs.iter().map(own).collect();
        Some(Exploring {
            values,
            selected: 0,
            curve: Vec::new(),
            measures: super::system::measures(prompt),
            pending: None,
            explore,
        })
    }

    /// The selected knob.
    pub fn knob(&self) -> Option<&Knob> {
        self.explore.knobs.get(self.selected)
    }

    /// Turns the selected knob one step; whether its value changed.
    pub fn turn(&mut self, up: bool) -> bool {
        let Some(k) = self.explore.knobs.get(self.selected) else {
            return false;
        };
        let Some(v) = self.values.get_mut(self.selected) else {
            return false;
        };
        let next = k.stepped(*v, up);
        let changed = next != *v;
        *v = next;
        changed
    }

    /// Selects the next knob.
    pub fn next_knob(&mut self) {
        let n = self.explore.knobs.len().max(1);
        self.selected = (self.selected + 1) % n;
    }

    fn turned(&self, deck: &Deck) -> Option<Turned> {
        let id = &self.explore.scene;
        let set = self.explore.knobs.iter().zip(&self.values);
        if let Some(s) = deck.system(id) {
            let mut s = s.clone();
            for (k, v) in set {
                s = knob::set_system(&s, &k.target, v * k.scale);
            }
            return Some(Turned::System(Box::new(s)));
        }
        let mut s = deck.scene(id)?.clone();
        for (k, v) in set {
            s = knob::set_rigid(&s, &k.target, v * k.scale);
        }
        Some(Turned::Rigid(Box::new(s)))
    }

    /// The run of the scene at the knobs' values, at `speed`.
    pub fn run(&self, deck: &Deck, speed: f64) -> Result<Live, String> {
        let mut live = match self.turned(deck) {
            Some(Turned::System(s)) => {
                let mut measures = self.measures.clone();
                measures.extend(self.explore.measure.filter(|m| m.is_system()));
                measures.sort();
                measures.dedup();
                Live::system(&s, system_reference(&s), &measures)
            }
            Some(Turned::Rigid(s)) => Live::rigid(&s, Method::Exact),
            None => Err(format!("scene {} not found", self.explore.scene)),
        }?;
        live.speed = speed;
        Ok(live)
    }

    /// Starts measuring the curve's point at the knobs' values when it is
    /// missing and no measurement is under way (one at a time: a learner
    /// holding `→` starts no crowd of threads), and takes a finished one.
    pub fn poll(&mut self, deck: &Deck) {
        if let Some((values, rx)) = &self.pending {
            let done = match rx.try_recv() {
                Ok(Ok(Some(v))) => Some(Ok(v)),
                Ok(Ok(None)) => Some(Err(Unmeasured::Undefined)),
                Ok(Err(e)) => Some(Err(Unmeasured::Failed(e))),
                Err(TryRecvError::Empty) => None,
                Err(TryRecvError::Disconnected) => Some(Err(Unmeasured::Failed(
                    "the measurement stopped".to_string(),
                ))),
            };
            match done {
                Some(measured) => {
                    let values = values.clone();
                    self.curve.retain(|p| p.values != values);
                    self.curve.push(Point { values, measured });
                    self.pending = None;
                }
                None => return,
            }
        }
        let Some(measure) = self.explore.measure else {
            return;
        };
        if self.point_here().is_some() {
            return;
        }
        let Some(scene) = self.turned(deck) else {
            return;
        };
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let value = match scene {
                Turned::Rigid(s) => crate::sim::scene::measure_scene(&s, Method::Exact)
                    .map(|m| m.get(measure))
                    .map_err(|e| e.to_string()),
                Turned::System(s) => {
                    crate::sim::scene::system::measure_system(&s, system_reference(&s), &[measure])
                        .map(|v| v.into_iter().next().and_then(Result::ok))
                        .map_err(|e| e.to_string())
                }
            };
            // The screen may have closed meanwhile: nobody listens then.
            let _ = tx.send(value);
        });
        self.pending = Some((self.values.clone(), rx));
    }

    /// Whether a measurement is under way.
    pub fn measuring(&self) -> bool {
        self.pending.is_some()
    }

    /// The point at the knobs' values, when measured.
    pub fn point_here(&self) -> Option<&Point> {
        self.curve.iter().find(|p| p.values == self.values)
    }

    /// The curve against the selected knob: the points whose other knobs
    /// are where they are now, as (knob value, measured), sorted.
    pub fn curve_now(&self) -> Vec<(f64, f64)> {
        let s = self.selected;
        let mut out: Vec<(f64, f64)> = self
            .curve
            .iter()
            .filter(|p| {
                p.values
                    .iter()
                    .zip(&self.values)
                    .enumerate()
                    .all(|(i, (a, b))| i == s || a == b)
            })
            .filter_map(|p| Some((*p.values.get(s)?, p.measured.clone().ok()?)))
            .collect();
        out.sort_by(|a, b| a.0.total_cmp(&b.0));
        out
    }
}

/// A knob value as shown: its shortest form once the rounding of
/// `min + k·step` is taken off (`0.3`, not `0.30000000000000004`).
pub fn shown(v: f64) -> String {
    crate::text::num::show(knob::tidy(v))
}

/// Enters explore mode on `prompt`'s scene: the run restarts at the
/// scene's own values. `Err` with what the status line says when the
/// scene has no knobs or cannot run.
pub fn enter(
    app: &App,
    deck: &Deck,
    prompt: &Prompt,
    speed: f64,
) -> Result<(Box<Live>, Box<Exploring>), String> {
    let Some(mut e) = Exploring::new(deck, prompt) else {
        return Err(NO_KNOBS.get(&app.lang).to_string());
    };
    let run = e.run(deck, speed)?;
    e.poll(deck);
    Ok((Box::new(run), Box::new(e)))
}

/// The message when a scene has no knobs.
pub fn no_knobs(app: &App) -> &'static str {
    NO_KNOBS.get(&app.lang)
}

/// The row of knobs: each label with its value, the selected one marked
/// and highlighted; whole entries wrapped to `width`.
fn knob_lines(app: &App, e: &Exploring, width: usize) -> Vec<Line<'static>> {
    let t = &app.theme;
    let mut lines = Vec::new();
    let mut line: Vec<Span<'static>> = Vec::new();
    let mut used = 0;
    for (i, (k, v)) in e.explore.knobs.iter().zip(&e.values).enumerate() {
        let label = crate::text::safe::one_line(k.label.get(&app.lang));
        let selected = i == e.selected;
        let text = if selected {
            format!("‹ {label} {} ›", shown(*v))
        } else {
            format!("  {label} {}  ", shown(*v))
        };
        let w = unicode_width::UnicodeWidthStr::width(text.as_str());
        let gap = usize::from(used > 0);
        if used > 0 && used + gap + w > width {
            lines.push(Line::from(std::mem::take(&mut line)));
            used = 0;
        }
        if used > 0 {
            line.push(Span::raw(" "));
            used += 1;
        }
        let style = if selected { t.selected() } else { t.text() };
        line.push(Span::styled(
            crate::tui::wrap::ellipsize(&text, width.max(1)),
            style,
        ));
        used += w;
    }
    if !line.is_empty() {
        lines.push(Line::from(line));
    }
    lines
}

/// The measure at the knobs' values, in words: its value, measuring, or
/// why there is none.
fn reading(app: &App, e: &Exploring, unit: &str) -> Option<String> {
    let m = e.explore.measure?;
    let at = e
        .knob()
        .map(|_| shown(e.values[e.selected]))
        .unwrap_or_default();
    let value = match e.point_here() {
        Some(Point {
            measured: Ok(v), ..
        }) => {
            let unit = if m.name() == "period" || m.name() == "flip_period" {
                format!(" {unit}")
            } else {
                String::new()
            };
            format!("{}{unit}", sig(*v, 4))
        }
        Some(Point {
            measured: Err(Unmeasured::Undefined),
            ..
        }) => NOT_MEASURABLE.get(&app.lang).to_string(),
        Some(Point {
            measured: Err(Unmeasured::Failed(why)),
            ..
        }) => crate::text::safe::one_line(why).into_owned(),
        None if e.measuring() => MEASURING.get(&app.lang).to_string(),
        None => NOT_YET.get(&app.lang).to_string(),
    };
    Some(format!("{m} {} {at}: {value}", AT.get(&app.lang)))
}

/// The explore view: the knobs, the run's panels beside the curve, the
/// measure at this value, the status line and the keys. On a small screen
/// the curve panel goes first (its reading stays as a line), then the
/// panels; text is never cut before the curve is gone.
pub fn draw(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    (live, e): (&Live, &Exploring),
    show_diagnostics: bool,
) {
    let t = &app.theme;
    let width = usize::from(area.width);
    if area.width == 0 || area.height == 0 {
        return;
    }
    let knobs = knob_lines(app, e, width.saturating_sub(1).max(1));
    let (_, unit) = live.timing();
    let reading = reading(app, e, unit);
    let diag = match (live.sim(), show_diagnostics) {
        (Sim::System { run, .. }, true)
            if run.scene().shows(crate::deck::SystemPanel::Diagnostics) =>
        {
            let line = crate::tui::system_plots::diagnostics_line(run, &app.lang);
            super::parts::fold_parts(line.trim_start(), width)
        }
        _ => Vec::new(),
    };
    let fixed = knobs.len() as u16 + u16::from(reading.is_some()) + 1 + diag.len() as u16 + 1;
    let rest = area.height.saturating_sub(fixed);
    // Too short for every line: the knobs keep one row.
    let knobs_h = if rest == 0 { 1 } else { knobs.len() as u16 };
    let [knob_area, body, reading_area, status, diag_area, hints] = Layout::vertical([
        Constraint::Length(knobs_h),
        Constraint::Length(rest),
        Constraint::Length(u16::from(reading.is_some())),
        Constraint::Length(1),
        Constraint::Length(diag.len() as u16),
        Constraint::Length(1),
    ])
    .areas(area);
    frame.render_widget(Paragraph::new(knobs), knob_area);
    // The curve beside the panels when both have room; else the panels.
    let curve_room = e.explore.measure.is_some() && body.width >= 60 && body.height >= 6;
    let (panels, curve) = if curve_room {
        let cw = (body.width / 3).max(24);
        let [p, c] = Layout::horizontal([Constraint::Fill(1), Constraint::Length(cw)]).areas(body);
        (p, Some(c))
    } else {
        (body, None)
    };
    // A few rows keep one panel whole rather than every panel squeezed:
    // ω for a rigid body, the plot against time for a system.
    let few = panels.height < 8;
    if panels.height >= 3 {
        match live.sim() {
            Sim::Rigid(r) => super::draw::rigid_panels(frame, panels, app, r, (false, few)),
            Sim::System { run, .. } if few && run.scene().shows(SystemPanel::Plot) => {
                crate::tui::system_plots::plot(frame, panels, run, &app.lang, t)
            }
            Sim::System { run, .. } => super::system::system_panels(frame, panels, app, run),
        }
    }
    if let Some(c) = curve {
        draw_curve(frame, c, app, e);
    }
    if let Some(r) = reading {
        frame.render_widget(
            Paragraph::new(Line::styled(
                crate::tui::wrap::ellipsize(&format!(" {r}"), width),
                t.strong(),
            )),
            reading_area,
        );
    }
    let flips = match live.sim() {
        Sim::Rigid(r) => Some(r.flip_times().len()),
        Sim::System { .. } => None,
    };
    frame.render_widget(
        super::parts::status_line(app, live, flips, status.width),
        status,
    );
    frame.render_widget(super::parts::diagnostics(app, diag), diag_area);
    frame.render_widget(hints_line(app, hints.width), hints);
}

/// The keys' row of the explore view: whole entries, what does not fit
/// left to the help.
fn hints_line(app: &App, width: u16) -> Paragraph<'static> {
    let keys = [
        ("← →", TURN.get(&app.lang)),
        ("Tab", NEXT_KNOB.get(&app.lang)),
        ("Space", app.tr(crate::tui::i18n::Msg::Pause)),
        ("r", app.tr(crate::tui::i18n::Msg::Restart)),
        (
            "Esc",
            crate::tui::i18n::Words("back", "wapas").get(&app.lang),
        ),
    ];
    super::parts::key_row(app, &keys, width)
}

/// The measure against the selected knob: a dot per point measured, joined
/// in the knob's order, the value now marked.
fn draw_curve(frame: &mut Frame, area: Rect, app: &App, e: &Exploring) {
    let t = &app.theme;
    let Some(k) = e.knob() else {
        return;
    };
    let Some(m) = e.explore.measure else {
        return;
    };
    let label = crate::text::safe::one_line(k.label.get(&app.lang));
    let title = format!(" {m} · {label} ");
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(t.border())
        .title(Span::styled(
            crate::tui::wrap::ellipsize(&title, usize::from(area.width.saturating_sub(2))),
            t.heading(),
        ));
    let points = e.curve_now();
    let count = points.len();
    // In the corners the curve leaves empty: a rising curve ends top
    // right, so there max goes left and min right; a falling one the other
    // way round.
    let rising = match (points.first(), points.last()) {
        (Some(a), Some(b)) => b.1 > a.1,
        _ => false,
    };
    let (lo, hi) = points
        .iter()
        .map(|p| p.1)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    // The measured range, written on the panel as the time plots write
    // theirs (max at the top, min below), so the curve can be read.
    let measured = (lo.is_finite() && hi.is_finite()).then_some((lo, hi));
    let (lo, hi) = if lo.is_finite() && hi.is_finite() {
        let pad = ((hi - lo) * 0.1)
            .max(hi.abs().max(lo.abs()) * 0.05)
            .max(1e-12);
        (lo - pad, hi + pad)
    } else {
        (0.0, 1.0)
    };
    let inner = block.inner(area);
    frame.render_widget(block, area);
    if inner.height < 2 || inner.width < 4 {
        return;
    }
    let [plot, axis] = Layout::vertical([Constraint::Fill(1), Constraint::Length(1)]).areas(inner);
    let now = e.values.get(e.selected).copied().unwrap_or(k.min);
    let here: Vec<(f64, f64)> = points.iter().filter(|p| p.0 == now).copied().collect();
    let color = t.plot(t.axis(0));
    let mark = t.plot(t.axis(1));
    let canvas = Canvas::default()
        .x_bounds([k.min, k.max])
        .y_bounds([lo, hi])
        .paint(move |ctx| {
            for w in points.windows(2) {
                ctx.draw(&Segment {
                    x1: w[0].0,
                    y1: w[0].1,
                    x2: w[1].0,
                    y2: w[1].1,
                    color,
                });
            }
            ctx.draw(&Points {
                coords: &points,
                color,
            });
            // The value now, on top.
            ctx.draw(&Points {
                coords: &here,
                color: mark,
            });
        });
    frame.render_widget(canvas, plot);
    let word = |w| crate::tui::i18n::system_word(w).get(&app.lang);
    if let Some((bottom, top)) = measured
        && plot.height >= 2
    {
        for (text, row, right) in [
            (
                format!("{} {}", word(SystemWord::Highest), sig(top, 4)),
                Rect { height: 1, ..plot },
                !rising,
            ),
            (
                format!("{} {}", word(SystemWord::Lowest), sig(bottom, 4)),
                Rect {
                    y: plot.y + plot.height - 1,
                    height: 1,
                    ..plot
                },
                rising,
            ),
        ] {
            let line = Paragraph::new(Line::styled(
                crate::tui::wrap::ellipsize(&text, usize::from(row.width)),
                t.dim(),
            ));
            let line = match right {
                true => line.alignment(ratatui::layout::Alignment::Right),
                false => line,
            };
            frame.render_widget(line, row);
        }
    }
    let ends = format!(
        "{} … {}  ({}: {})",
        shown(k.min),
        shown(k.max),
        POINTS.get(&app.lang),
        count
    );
    frame.render_widget(
        Paragraph::new(Line::styled(
            crate::tui::wrap::ellipsize(&ends, usize::from(axis.width)),
            t.dim(),
        )),
        axis,
    );
}
