//! The growth of a disturbance where it can be seen: |ω⊥|, the spin off
//! the starting axis, on a logarithmic axis against time. Exponential
//! growth is a straight line there, drawn beside the line of slope √k the
//! formula gives; on a linear axis the same 1.5 s are a flat line.

use nalgebra::Vector3;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line as TextLine, Span};
use ratatui::widgets::canvas::{Canvas, Context, Line, Points};
use ratatui::widgets::{Block, Borders};

use crate::sim::rigid::formula;
use crate::sim::scene::SceneRun;
use crate::text::num::Num;
use crate::tui::i18n::sim_words as w;
use crate::tui::plots::{dashed, fitted_title};
use crate::tui::theme::Theme;

/// log10 |ω⊥| at each trace point so far, skipping exact zeros.
pub fn log_perp(run: &SceneRun) -> Vec<(f64, f64)> {
    let axis = formula::dominant_axis(&run.omega0());
    let perp = |o: &Vector3<f64>| o[(axis + 1) % 3].hypot(o[(axis + 2) % 3]);
    let now = run.frame();
    run.trace()
        .iter()
        .map(|s| (s.t, perp(&s.omega)))
        .chain([(now.t, perp(&now.omega))])
        .filter(|&(_, p)| p > 0.0 && p.is_finite())
        .map(|(t, p)| (t, p.log10()))
        .collect()
}

/// "10⁻³".
fn decade(e: i32) -> String {
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let digits: String = e
        .unsigned_abs()
        .to_string()
        .chars()
        .map(|c| SUP[c.to_digit(10).unwrap_or(0) as usize])
        .collect();
    format!("10{}{digits}", if e < 0 { "⁻" } else { "" })
}

pub fn growth(frame: &mut Frame, area: Rect, run: &SceneRun, lang: &str, theme: &Theme) {
    let omega0 = run.omega0();
    let axis = formula::dominant_axis(&omega0);
    let perp0 = omega0[(axis + 1) % 3].hypot(omega0[(axis + 2) % 3]);
    let bound = run.body().omega_bound(&run.omega0()).max(f64::MIN_POSITIVE);
    let (lo, hi) = if perp0 > 0.0 {
        ((perp0.log10() - 0.5).floor(), (bound.log10() + 0.3).ceil())
    } else {
        (bound.log10() - 4.0, bound.log10() + 1.0)
    };
    let d = run.scene().duration;
    let unit = run.scene().time_unit.clone();
    let k = formula::stability(run.body(), axis, omega0[axis]);
    let points = log_perp(run);
    // The formula's line, through the trace where the growth has settled
    // (grown e² from the start, as the measurement's fit begins).
    let slope = (k > 0.0).then(|| k.sqrt() / std::f64::consts::LN_10);
    let settled = (perp0 * std::f64::consts::E.powi(2)).log10();
    let anchor = points.iter().find(|p| p.1 >= settled).copied();
    let reference: Vec<(f64, f64)> = match (slope, anchor) {
        (Some(s), Some((ta, ya))) => {
            let t_hi = (ta + (hi - ya) / s).min(d);
            vec![(0.0, ya - s * ta), (t_hi, ya + s * (t_hi - ta))]
        }
        _ => Vec::new(),
    };
    let dim = theme.plot(Color::DarkGray);
    let trace_c = theme.plot(Color::LightCyan);
    let title = vec![
        Span::styled(format!(" {} ", w::GROWTH.get(lang)), theme.heading()),
        Span::styled(
            format!("{}…{} ", decade(lo as i32), decade(hi as i32)),
            theme.dim(),
        ),
        Span::styled(
            format!("╌ {} ", w::FORMULA_SLOPE.get(lang)),
            Style::new().fg(dim),
        ),
    ];
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(theme.border())
        .title(fitted_title(title, area.width.saturating_sub(2) as usize))
        .title_bottom(TextLine::styled("0", Style::new().fg(dim)))
        .title_bottom(
            TextLine::styled(format!("{} {unit}", Num(d)), Style::new().fg(dim)).right_aligned(),
        );
    let dots = (
        f64::from(area.width.saturating_sub(2)) * 2.0 / d.max(f64::MIN_POSITIVE),
        f64::from(area.height.saturating_sub(2)) * 4.0 / (hi - lo).max(1e-9),
    );
    let canvas = Canvas::default()
        .block(block)
        .marker(Marker::Braille)
        .x_bounds([0.0, d])
        .y_bounds([lo, hi])
        .paint(move |ctx: &mut Context| {
            for e in (lo as i32)..=(hi as i32) {
                let marks = dashed(&[(0.0, f64::from(e)), (d, f64::from(e))], dots, 1.0, 6.0);
                ctx.draw(&Points {
                    coords: &marks,
                    color: dim,
                });
            }
            if reference.len() == 2 {
                let marks = dashed(&reference, dots, 3.0, 6.0);
                ctx.draw(&Points {
                    coords: &marks,
                    color: theme.plot(Color::Yellow),
                });
            }
            ctx.layer();
            for w in points.windows(2) {
                ctx.draw(&Line::new(w[0].0, w[0].1, w[1].0, w[1].1, trace_c));
            }
        });
    frame.render_widget(canvas, area);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decades_are_written_with_superscripts() {
        assert_eq!(decade(-3), "10⁻³");
        assert_eq!(decade(0), "10⁰");
        assert_eq!(decade(12), "10¹²");
    }
}
