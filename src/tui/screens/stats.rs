//! Statistics: due forecast, reviews per day, true retention, prompt
//! accuracy, and the numerics report (the bench's work–precision table).

use std::path::Path;

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{
    Bar, BarChart, BarGroup, Block, Borders, Cell, Paragraph, Row, Sparkline, Table, Wrap,
};

use crate::store::{Stats, StatsScope};
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::{Msg, Noun, marks, stats_more as more, study};
use crate::tui::wrap::{Run, ellipsize, wrap};

use super::Nav;
use crate::tui::i18n::Words;
use crate::tui::keymap::Binding;
use crossterm::event::KeyCode::{Char, Esc};

pub const KEYS: &[Binding] = &[
    Binding::new(
        "w",
        Words(
            "show / hide the solvers' work–precision table",
            "solvers ki work–precision table dikhao / chhupao",
        ),
        &[(Char('w'), Action::ToggleBench)],
    ),
    Binding::new(
        "Esc q",
        Words("back", "wapas"),
        &[(Esc, Action::Back), (Char('q'), Action::Back)],
    ),
];

/// The most accurate run of one method on one problem of the bench.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchRow {
    pub case: String,
    pub method: String,
    pub setting: String,
    pub wall_s: f64,
    pub err_omega: f64,
    pub err_energy: f64,
}

pub struct StatsState {
    pub deck: usize,
    pub stats: Result<Stats, String>,
    pub bench: Option<Vec<BenchRow>>,
    /// Where the bench table came from (the numerics report's folder).
    pub bench_path: Option<std::path::PathBuf>,
    pub memory: Result<crate::tui::memory::MemoryPanel, String>,
    /// The bench table is shown (`w`); a learner's statistics come first.
    pub show_bench: bool,
}

impl StatsState {
    /// Reads everything the screen shows (drawing does no I/O).
    pub fn open(app: &App, deck: usize) -> StatsState {
        let stats = match app.decks.get(deck) {
            Some(d) => {
                let items = crate::sched::deck_items(d);
                let scope = StatsScope {
                    deck: Some(&d.id),
                    items: &items,
                };
                let now = app.services.now();
                let s = &app.services.study;
                let r = s.store.stats(scope, now, &s.days());
                r.map(|mut st| {
                    crate::catalog::name_leeches(&mut st.leeches, &app.decks, &app.lang);
                    st
                })
                .map_err(|e| e.to_string())
            }
            None => Err("no such deck".into()),
        };
        let bench = app.services.bench_csv.as_deref().and_then(read_bench);
        let bench_path = bench.as_ref().and(app.services.bench_csv.clone());
        let memory = match app.decks.get(deck) {
            Some(d) => crate::tui::memory::MemoryPanel::open(app, &d.id),
            None => Err("no such deck".into()),
        };
        StatsState {
            deck,
            stats,
            bench,
            bench_path,
            memory,
            show_bench: false,
        }
    }
}

/// The bench CSV reduced to the most accurate run per (case, method), in
/// file order. `None` when the file is missing or unreadable.
pub fn read_bench(path: &Path) -> Option<Vec<BenchRow>> {
    let mut reader = csv::Reader::from_path(path).ok()?;
    let headers = reader.headers().ok()?.clone();
    let col = |name: &str| headers.iter().position(|h| h == name);
    let (c, m, s, w, e, en) = (
        col("case")?,
        col("method")?,
        col("setting")?,
        col("wall_s")?,
        col("err_omega")?,
        col("err_energy")?,
    );
    let mut rows: Vec<BenchRow> = Vec::new();
    for record in reader.records().flatten() {
        let num = |i: usize| record.get(i).and_then(|v| v.parse::<f64>().ok());
        let (Some(wall_s), Some(err_omega)) = (num(w), num(e)) else {
            continue;
        };
        let row = BenchRow {
            case: record.get(c).unwrap_or("").to_string(),
            method: record.get(m).unwrap_or("").to_string(),
            setting: record.get(s).unwrap_or("").to_string(),
            wall_s,
            err_omega,
            err_energy: num(en).unwrap_or(f64::NAN),
        };
        match rows
            .iter_mut()
            .find(|r| r.case == row.case && r.method == row.method)
        {
            Some(best) if row.err_omega < best.err_omega => *best = row,
            Some(_) => {}
            None => rows.push(row),
        }
    }
    Some(rows)
}

impl super::View for StatsState {
    fn context(&self) -> crate::tui::keymap::Context {
        crate::tui::keymap::Context::Stats
    }
    fn apply(&mut self, app: &mut App, action: Action) -> Nav {
        apply(app, self, action)
    }
    fn draw(&self, frame: &mut Frame, area: Rect, app: &App) {
        draw(frame, area, app, self)
    }
    fn name(&self) -> Msg {
        Msg::Stats
    }
    fn deck(&self) -> Option<usize> {
        Some(self.deck)
    }
}

pub fn apply(_app: &mut App, state: &mut StatsState, action: Action) -> Nav {
    match action {
        Action::Back => Nav::Pop,
        Action::ToggleBench => {
            state.show_bench = !state.show_bench;
            Nav::Stay
        }
        _ => Nav::Stay,
    }
}

fn pct(rate: Option<f64>) -> String {
    rate.map_or("—".into(), |r| format!("{:.0}%", 100.0 * r))
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, state: &StatsState) {
    let t = &app.theme;
    let stats = match &state.stats {
        Ok(s) => s,
        Err(e) => {
            frame.render_widget(
                Paragraph::new(e.clone())
                    .style(t.bad())
                    .wrap(Wrap { trim: true }),
                area,
            );
            return;
        }
    };
    // The bench table only on request: one line says how to see it.
    let bench_h = match (&state.bench, state.show_bench) {
        (Some(rows), true) => {
            let (methods, _) = bench_axes(rows);
            (methods.len() as u16 + 2).min(area.height / 2)
        }
        (None, true) => 2,
        (_, false) => 1,
    };
    let c = &stats.cards;
    let lang = app.lang.as_str();
    let cards = app.decks.get(state.deck).map_or(0, |d| d.cards.len());
    let prompts = app.decks.get(state.deck).map_or(0, |d| d.prompts.len());
    // Review items, not cards: a card asked both ways is two items, and
    // each prompt is one.
    let from = if prompts == 0 {
        app.count(cards, Noun::Card)
    } else {
        format!(
            "{} + {}",
            app.count(cards, Noun::Card),
            app.count(prompts, Noun::Prompt)
        )
    };
    let states = format!(
        "{} {} ({} {}): {} {} · {} {} · {} {} · {} {}",
        c.total,
        study::REVIEW_ITEMS.get(lang),
        study::FROM_CARDS.get(lang),
        from,
        c.new,
        app.tr(Msg::New),
        c.learning,
        app.tr(Msg::Learning),
        c.review,
        app.tr(Msg::InReview),
        c.relearning,
        app.tr(Msg::Relearning)
    );
    let p = &stats.prompts.overall;
    let mut lines = vec![
        Line::styled(states, t.text()),
        Line::from(vec![
            Span::styled(format!(" {}: ", app.tr(Msg::Retention)), t.dim()),
            Span::styled(pct(stats.retention.last_30_days.rate), t.good()),
            Span::styled(
                format!(
                    " (30 {}, {} {}) · {} {}",
                    app.tr(Msg::Days),
                    stats.retention.last_30_days.total,
                    app.tr(Msg::Reviewed),
                    pct(stats.retention.all_time.rate),
                    app.tr(Msg::AllTime)
                ),
                t.dim(),
            ),
        ]),
        Line::from(vec![
            Span::styled(format!(" {}: ", app.tr(Msg::PromptAccuracy)), t.dim()),
            Span::styled(pct(p.rate), t.good()),
            Span::styled(format!(" ({}/{})", p.passed, p.total), t.dim()),
        ]),
        Line::from(vec![
            Span::styled(format!(" {} ", study::DUE.get(lang)), t.dim()),
            Span::styled(
                format!("{} {}", study::TODAY.get(lang), stats.due.today),
                t.good(),
            ),
            Span::styled(
                format!(
                    " · {} {} · {} {}",
                    study::TOMORROW.get(lang),
                    stats.due.tomorrow,
                    study::NEXT_7_DAYS.get(lang),
                    stats
                        .due
                        .per_day
                        .iter()
                        .take(7)
                        .map(|d| u64::from(d.due))
                        .sum::<u64>()
                ),
                t.dim(),
            ),
            Span::styled(
                format!(
                    " · {} {}",
                    more::NEXT_90_DAYS.get(lang),
                    stats.due.next_90_days
                ),
                t.dim(),
            ),
            Span::styled(format!(" ({})", study::REVIEW_ITEMS.get(lang)), t.dim()),
        ]),
    ];
    // Prediction accuracy over time, per prompt (the three most attempted;
    // `flipcard stats` lists every one): each week's share right.
    let mut by_prompt: Vec<&crate::store::stats::PromptLine> = stats
        .prompts
        .by_prompt
        .iter()
        .filter(|p| !p.weeks.is_empty())
        .collect();
    by_prompt.sort_by(|a, b| b.attempts.cmp(&a.attempts).then(a.prompt.cmp(&b.prompt)));
    for p in by_prompt.into_iter().take(3) {
        let weeks: Vec<String> = p
            .weeks
            .iter()
            .rev()
            .take(4)
            .rev()
            .map(|w| format!("{}/{}", w.correct, w.attempts))
            .collect();
        lines.push(Line::from(vec![
            Span::styled(
                format!("   {}: ", crate::text::safe::one_line(&p.prompt)),
                t.dim(),
            ),
            Span::styled(weeks.join(" → "), t.text()),
            Span::styled(format!(" ({})", study::BY_WEEK.get(lang)), t.dim()),
        ]));
    }
    lines.extend(marks_lines(app, stats));
    // Last: on a short screen the counts above come first.
    lines.push(time_and_buttons(app, stats));
    // The summary wraps; the charts get what is left, and on a screen too
    // short for them the summary's numbers come first.
    let width = usize::from(area.width.max(1));
    let summary_lines: Vec<Line> = lines
        .iter()
        .flat_map(|l| {
            let runs: Vec<Run> = l
                .spans
                .iter()
                .map(|s| Run::new(s.content.to_string(), s.style))
                .collect();
            wrap(
                &runs,
                width,
                Run::new(" ", t.text()),
                Run::new(" ", t.text()),
            )
        })
        .collect();
    let summary_h = (summary_lines.len() as u16).min(area.height.saturating_sub(bench_h));
    let charts_h = area.height.saturating_sub(summary_h + bench_h);
    let [summary, charts, bench] = Layout::vertical([
        Constraint::Length(summary_h),
        Constraint::Length(if charts_h >= 5 { charts_h } else { 0 }),
        Constraint::Fill(1),
    ])
    .areas(area);
    // The memory panel (true retention, calendar, recall) below the charts
    // when they have room for both.
    let memory_h = if charts.height >= 15 { 10 } else { 0 };
    let [charts, memory] =
        Layout::vertical([Constraint::Fill(1), Constraint::Length(memory_h)]).areas(charts);
    if memory.height > 0 {
        crate::tui::memory::draw(frame, memory, app, &state.memory);
    }
    let bench = Rect {
        y: bench.bottom().saturating_sub(bench_h),
        height: bench_h.min(bench.height),
        ..bench
    };
    frame.render_widget(Paragraph::new(summary_lines), summary);
    draw_bench(frame, bench, app, state);
    if charts.height == 0 {
        return;
    }

    let [forecast, per_day] =
        Layout::horizontal([Constraint::Fill(1), Constraint::Fill(1)]).areas(charts);
    // As many days as fit, three columns per bar.
    let fit = (forecast.width.saturating_sub(2) / 3).max(1) as usize;
    let bars: Vec<Bar> = stats
        .due
        .per_day
        .iter()
        .take(fit)
        .enumerate()
        .map(|(i, d)| {
            Bar::default()
                .value(u64::from(d.due))
                .label(Line::from(format!("{i}")))
                .style(t.good())
        })
        .collect();
    let chart = BarChart::default()
        .block(
            Block::default()
                .borders(Borders::ALL)
                .border_style(t.border())
                .title(Span::styled(
                    ellipsize(
                        &format!(" {} ", app.tr(Msg::DueForecast)),
                        usize::from(forecast.width.saturating_sub(2)),
                    ),
                    t.heading(),
                )),
        )
        .data(BarGroup::default().bars(&bars))
        .bar_width(2)
        .bar_gap(1);
    frame.render_widget(chart, forecast);

    let counts: Vec<u64> = stats
        .reviews_per_day
        .iter()
        .map(|d| u64::from(d.total))
        .collect();
    let total: u64 = counts.iter().sum();
    let spark = Sparkline::default()
        .block(
            Block::default()
                .borders(Borders::ALL)
                .border_style(t.border())
                .title(Span::styled(
                    ellipsize(
                        &format!(" {} ", app.tr(Msg::ReviewsPerDay)),
                        usize::from(per_day.width.saturating_sub(2)),
                    ),
                    t.heading(),
                ))
                .title_bottom(Span::styled(format!(" Σ {total} "), t.dim())),
        )
        .data(&counts)
        .style(t.warn());
    frame.render_widget(spark, per_day);
}

/// Time spent today and over 30 days, and the answers by rating (every
/// kind together), with the share right of mature reviews.
fn time_and_buttons(app: &App, stats: &Stats) -> Line<'static> {
    let t = &app.theme;
    let lang = app.lang.as_str();
    let today = stats.reviews_per_day.last().map_or(0.0, |d| d.seconds);
    let month: f64 = stats.reviews_per_day.iter().map(|d| d.seconds).sum();
    let b = &stats.answer_buttons;
    let all = [b.learn, b.relearn, b.young, b.mature, b.cram];
    let sum = |f: fn(&crate::store::stats::Buttons) -> u64| all.iter().map(f).sum::<u64>();
    let m = b.mature;
    let mature = m.again + m.hard + m.good + m.easy;
    let right = if mature == 0 {
        "—".to_string()
    } else {
        format!("{:.0}%", (mature - m.again) as f64 * 100.0 / mature as f64)
    };
    Line::from(vec![
        Span::styled(format!(" {} ", more::TIME.get(lang)), t.dim()),
        Span::styled(
            format!("{} {}", more::TODAY.get(lang), duration(today)),
            t.good(),
        ),
        Span::styled(
            format!(
                " · {} {} · {} {} {} {} {} {} {} {} · {} {right}",
                more::DAYS_30.get(lang),
                duration(month),
                app.tr(Msg::Again),
                sum(|x| x.again),
                app.tr(Msg::Hard),
                sum(|x| x.hard),
                app.tr(Msg::Good),
                sum(|x| x.good),
                app.tr(Msg::Easy),
                sum(|x| x.easy),
                more::MATURE_RIGHT.get(lang),
            ),
            t.dim(),
        ),
    ])
}

/// Seconds as `45s`, `12m`, `2h 3m`.
fn duration(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    match s {
        0..60 => format!("{s}s"),
        60..3600 => format!("{}m", s / 60),
        _ => format!("{}h {}m", s / 3600, s % 3600 / 60),
    }
}

/// The most leeches named on the screen; `flipcard stats` lists them all.
const LEECHES_SHOWN: usize = 3;

/// The leeches (each with its lapses) and the suspended and buried counts,
/// when anything is marked: nothing is said of an unmarked deck.
fn marks_lines(app: &App, stats: &Stats) -> Vec<Line<'static>> {
    let t = &app.theme;
    let lang = app.lang.as_str();
    if stats.leeches.is_empty() && stats.suspended == 0 && stats.buried == 0 {
        return Vec::new();
    }
    let mut lines = vec![Line::from(vec![
        Span::styled(format!(" {}: ", marks::LEECHES.get(lang)), t.dim()),
        Span::styled(
            stats.leeches.len().to_string(),
            if stats.leeches.is_empty() {
                t.good()
            } else {
                t.warn()
            },
        ),
        Span::styled(
            format!(
                " · {} {} · {} {}",
                marks::SUSPENDED.get(lang),
                stats.suspended,
                marks::BURIED.get(lang),
                stats.buried
            ),
            t.dim(),
        ),
    ])];
    for l in stats.leeches.iter().take(LEECHES_SHOWN) {
        let lapses = if l.lapses == 1 {
            marks::LAPSE
        } else {
            marks::LAPSES
        };
        let mut spans = vec![
            Span::styled(format!("   {}/{} ", l.card, l.direction), t.text()),
            Span::styled(format!("{} {}", l.lapses, lapses.get(lang)), t.dim()),
        ];
        if let Some(front) = l.front.as_deref().filter(|f| !f.is_empty()) {
            spans.push(Span::styled(format!(" · {front}"), t.text()));
        }
        lines.push(Line::from(spans));
    }
    if stats.leeches.len() > LEECHES_SHOWN {
        lines.push(Line::styled(
            format!(
                "   +{} {}",
                stats.leeches.len() - LEECHES_SHOWN,
                marks::MORE.get(lang)
            ),
            t.dim(),
        ));
    }
    lines
}

fn draw_bench(frame: &mut Frame, area: Rect, app: &App, state: &StatsState) {
    let t = &app.theme;
    if !state.show_bench {
        let hint = Line::from(vec![
            Span::styled(" w ", t.key()),
            Span::styled(study::SHOW_BENCH.get(&app.lang), t.dim()),
        ]);
        frame.render_widget(Paragraph::new(hint), area);
        return;
    }
    let rows = state.bench.as_deref();
    let mut block = Block::default()
        .borders(Borders::TOP)
        .border_style(t.border())
        .title(Span::styled(
            format!(" {} ", app.tr(Msg::WorkPrecision)),
            t.heading(),
        ));
    if let Some(path) = &state.bench_path {
        // The full report (CSV and SVG plot) sits in this folder.
        let dir = path.parent().unwrap_or(path);
        block =
            block.title_top(Line::styled(format!(" {} ", dir.display()), t.dim()).right_aligned());
    }
    let Some(rows) = rows else {
        frame.render_widget(
            Paragraph::new(Span::styled(app.tr(Msg::NoBench), t.dim())).block(block),
            area,
        );
        return;
    };
    // Methods down, problems across: the smallest error of ω each method
    // reached on each problem, and the run time it took.
    let (methods, cases) = bench_axes(rows);
    let mut header = vec![Cell::from("err ω · time")];
    header.extend(cases.iter().map(|c| Cell::from(format!("case {c}"))));
    let body = methods.iter().map(|m| {
        let mut cells = vec![Cell::from(m.clone()).style(t.strong())];
        for c in &cases {
            let cell = rows
                .iter()
                .find(|r| &r.method == m && &r.case == c)
                .map(|r| format!("{} {}", fmt_err(r.err_omega), fmt_wall(r.wall_s)))
                .unwrap_or_else(|| "—".into());
            cells.push(Cell::from(cell));
        }
        Row::new(cells)
    });
    let mut widths = vec![Constraint::Length(12)];
    widths.extend(cases.iter().map(|_| Constraint::Fill(1)));
    let table = Table::new(body, widths)
        .header(Row::new(header).style(t.dim()))
        .block(block);
    frame.render_widget(table, area);
}

/// The methods and the cases of the bench rows, each in order of first
/// appearance.
fn bench_axes(rows: &[BenchRow]) -> (Vec<String>, Vec<String>) {
    let (mut methods, mut cases): (Vec<String>, Vec<String>) = (Vec::new(), Vec::new());
    for r in rows {
        if !methods.contains(&r.method) {
            methods.push(r.method.clone());
        }
        if !cases.contains(&r.case) {
            cases.push(r.case.clone());
        }
    }
    (methods, cases)
}

/// "3e-9", and an exact zero as "0".
fn fmt_err(e: f64) -> String {
    if e == 0.0 {
        "0".into()
    } else {
        format!("{e:.0e}")
    }
}

/// "0.24ms", "12ms", "3.1s".
fn fmt_wall(s: f64) -> String {
    if s >= 1.0 {
        format!("{s:.1}s")
    } else if s >= 0.01 {
        format!("{:.0}ms", s * 1e3)
    } else {
        format!("{:.2}ms", s * 1e3)
    }
}
