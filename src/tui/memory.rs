//! The stats screen's memory panel: a calendar of answers over the last 52
//! weeks, the true-retention table by maturity, how likely each card is to
//! be recalled right now, and which FSRS parameters schedule them.

use chrono::{DateTime, Datelike, Duration, FixedOffset, NaiveDate};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Bar, BarChart, BarGroup, Block, Borders, Cell, Paragraph, Row, Table};

use crate::sched::DayOf;
use crate::store::true_retention::{PassFail, TrueRetention};
use crate::tui::app::App;
use crate::tui::i18n::Msg;
use crate::tui::theme::Theme;

/// Weeks the calendar covers.
pub const WEEKS: usize = 52;

/// Intensity glyphs, from one answer up to the busiest day.
const LEVELS: [char; 4] = ['░', '▒', '▓', '█'];
/// A day without answers.
const EMPTY: char = '·';

#[derive(Debug, Clone, PartialEq)]
pub struct MemoryPanel {
    /// Answers per learning day, oldest first, today last.
    pub calendar: Vec<(NaiveDate, u32)>,
    pub true_retention: TrueRetention,
    /// Cards with a memory by current retrievability: [0, 10 %), … [90, 100 %].
    pub recall: [u64; 10],
    /// When the parameters in use were fitted (`None`: the defaults).
    pub fitted: Option<Option<DateTime<FixedOffset>>>,
}

impl MemoryPanel {
    /// Reads what the panel shows for one deck (drawing does no I/O).
    pub fn open(app: &App, deck: &str) -> Result<MemoryPanel, String> {
        let now = app.services.now();
        let s = &app.services.study;
        let today_weekday = |today: NaiveDate| today.weekday().num_days_from_monday() as usize;
        let read = |grid_today: NaiveDate| (WEEKS - 1) * 7 + today_weekday(grid_today) + 1;
        let days = s.days();
        let read = read(days.day_of(now));
        let calendar = s.store.answers_per_day(Some(deck), now, &days, read);
        let true_retention = s.store.true_retention(Some(deck), now, &days);
        let mut recall = [0u64; 10];
        // The deck's preset's parameters, when it has its own.
        let scheduler = s.scheduler_for(deck);
        let config = s.config.for_deck(deck);
        for c in s
            .store
            .cached_states_in(Some(deck))
            .map_err(|e| e.to_string())?
        {
            if c.state.stability.is_none() {
                continue;
            }
            let r = scheduler.retrievability(&c.state, now);
            if r.is_finite() {
                recall[((r * 10.0).floor() as usize).min(9)] += 1;
            }
        }
        Ok(MemoryPanel {
            calendar: calendar.map_err(|e| e.to_string())?,
            true_retention: true_retention.map_err(|e| e.to_string())?,
            recall,
            fitted: config.fsrs_parameters.map(|_| s.config.fsrs_fitted_at),
        })
    }
}

/// The glyph of a day with `n` answers when the busiest day had `max`.
pub fn level(n: u32, max: u32) -> char {
    if n == 0 || max == 0 {
        return EMPTY;
    }
    let i = (n as usize * LEVELS.len()).div_ceil(max as usize);
    LEVELS[i.clamp(1, LEVELS.len()) - 1]
}

/// The calendar as seven lines (Monday first), one column per week, the
/// newest week on the right, at most `width` columns of weeks; today's cell
/// reversed.
pub fn calendar_lines(days: &[(NaiveDate, u32)], width: usize, t: &Theme) -> Vec<Line<'static>> {
    let max = days.iter().map(|d| d.1).max().unwrap_or(0);
    let Some(&(today, _)) = days.last() else {
        return Vec::new();
    };
    let monday = today - Duration::days(i64::from(today.weekday().num_days_from_monday()));
    let weeks = WEEKS.min(width.saturating_sub(3)).max(1);
    let first = monday - Duration::weeks(weeks as i64 - 1);
    let names = ["Mo", "", "We", "", "Fr", "", "Su"];
    (0..7)
        .map(|row| {
            let mut spans = vec![Span::styled(format!("{:<3}", names[row]), t.dim())];
            for w in 0..weeks {
                let date = first + Duration::days((w * 7 + row) as i64);
                if date > today {
                    spans.push(Span::raw(" "));
                    continue;
                }
                let n = days.iter().find(|d| d.0 == date).map_or(0, |d| d.1);
                let mut style = if n == 0 { t.dim() } else { t.good() };
                if date == today {
                    style = style.add_modifier(Modifier::REVERSED | Modifier::BOLD);
                }
                spans.push(Span::styled(level(n, max).to_string(), style));
            }
            Line::from(spans)
        })
        .collect()
}

fn cell(p: PassFail) -> String {
    match p.rate {
        Some(r) => format!("{:.0}% {}/{}", r * 100.0, p.passed, p.passed + p.failed),
        None => "—".into(),
    }
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, panel: &Result<MemoryPanel, String>) {
    let t = &app.theme;
    let panel = match panel {
        Ok(p) => p,
        Err(e) => {
            frame.render_widget(Paragraph::new(e.clone()).style(t.bad()), area);
            return;
        }
    };
    // The table keeps its width; the calendar takes up to a full year of
    // what is left and the recall chart the rest.
    let table_w = 34u16.min(area.width);
    let rest = area.width - table_w;
    let calendar_w = (WEEKS as u16 + 5).min(rest * 3 / 5);
    let [calendar, retention, recall] = Layout::horizontal([
        Constraint::Length(calendar_w),
        Constraint::Length(table_w),
        Constraint::Fill(1),
    ])
    .areas(area);

    let block = |title: String| {
        Block::default()
            .borders(Borders::ALL)
            .border_style(t.border())
            .title(Span::styled(format!(" {title} "), t.heading()))
    };
    let mut lines = calendar_lines(
        &panel.calendar,
        calendar.width.saturating_sub(2) as usize,
        t,
    );
    let total: u64 = panel.calendar.iter().map(|d| u64::from(d.1)).sum();
    let mut legend = vec![Span::styled(
        format!("{} {EMPTY}", app.tr(Msg::Less)),
        t.dim(),
    )];
    legend.extend(LEVELS.iter().map(|c| Span::styled(c.to_string(), t.good())));
    legend.push(Span::styled(format!(" {}  ", app.tr(Msg::More)), t.dim()));
    legend.push(Span::styled(
        "▒",
        t.good().add_modifier(Modifier::REVERSED | Modifier::BOLD),
    ));
    legend.push(Span::styled(format!(" {}", app.tr(Msg::Today)), t.dim()));
    lines.push(Line::from(legend));
    frame.render_widget(
        Paragraph::new(lines).block(
            block(app.tr(Msg::Calendar).to_string())
                .title_bottom(Span::styled(format!(" Σ {total} "), t.dim())),
        ),
        calendar,
    );

    let tr = &panel.true_retention;
    let names = [Msg::Today, Msg::Yesterday, Msg::Week, Msg::Month, Msg::Year];
    let rows = names
        .iter()
        .zip(tr.young.rows().into_iter().zip(tr.mature.rows()))
        .map(|(name, ((_, y), (_, m)))| {
            Row::new(vec![
                Cell::from(app.tr(*name)).style(t.dim()),
                Cell::from(cell(y)),
                Cell::from(cell(m)),
            ])
        });
    let params = match panel.fitted {
        None => app.tr(Msg::FsrsDefault).to_string(),
        Some(when) => format!(
            "{} {}",
            app.tr(Msg::FsrsFitted),
            when.map_or_else(String::new, |w| w.format("%Y-%m-%d").to_string())
        ),
    };
    let table = Table::new(
        rows,
        [
            Constraint::Length(9),
            Constraint::Fill(1),
            Constraint::Fill(1),
        ],
    )
    .header(
        Row::new(vec![
            Cell::from(""),
            Cell::from(app.tr(Msg::Young)),
            Cell::from(app.tr(Msg::Mature)),
        ])
        .style(t.dim()),
    )
    .block(
        block(app.tr(Msg::TrueRetention).to_string())
            .title_bottom(Span::styled(format!(" {params} "), t.dim())),
    );
    frame.render_widget(table, retention);

    // Ten bars: as wide as fit, up to three columns; a label in tens of
    // percent when a bar is narrower than "90".
    let bar_w = (recall.width.saturating_sub(2) / 10)
        .saturating_sub(1)
        .clamp(1, 3);
    let bars: Vec<Bar> = panel
        .recall
        .iter()
        .enumerate()
        .map(|(i, n)| {
            let label = if bar_w >= 2 { i * 10 } else { i };
            Bar::default()
                .value(*n)
                .label(Line::from(format!("{label}")))
                .style(if i >= 9 { t.good() } else { t.warn() })
        })
        .collect();
    let chart = BarChart::default()
        .block(block(format!(
            "{} ({})",
            app.tr(Msg::RecallNow),
            if bar_w >= 2 { "%" } else { "×10%" }
        )))
        .data(BarGroup::default().bars(&bars))
        .bar_width(bar_w)
        .bar_gap(u16::from(recall.width >= 22))
        .value_style(Style::default().add_modifier(Modifier::BOLD));
    frame.render_widget(chart, recall);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_rise_with_the_count() {
        assert_eq!(level(0, 10), EMPTY);
        assert_eq!(level(1, 10), '░');
        assert_eq!(level(3, 10), '▒');
        assert_eq!(level(6, 10), '▓');
        assert_eq!(level(10, 10), '█');
    }

    #[test]
    fn calendar_puts_today_last_in_its_weekday_row() {
        let today = NaiveDate::from_ymd_opt(2026, 11, 25).unwrap(); // a Wednesday
        let days: Vec<(NaiveDate, u32)> = (0..30)
            .rev()
            .map(|b| (today - Duration::days(b), if b == 0 { 4 } else { 1 }))
            .collect();
        let theme = Theme::COLOR;
        let lines = calendar_lines(&days, 10, &theme);
        assert_eq!(lines.len(), 7);
        let text: Vec<String> = lines
            .iter()
            .map(|l| l.spans.iter().map(|s| s.content.as_ref()).collect())
            .collect();
        // 7 weeks fit in 10 columns: on Wednesday's row, two weeks before
        // the 30 days, four Wednesdays with one answer, then today (█);
        // Thursday's row ends with a blank (not yet).
        assert_eq!(text[2], "We ··░░░░█");
        assert!(text[3].ends_with(' '), "{:?}", text[3]);
        let today_span = lines[2].spans.last().unwrap();
        assert!(today_span.style.add_modifier.contains(Modifier::REVERSED));
    }
}
