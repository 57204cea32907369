//! The work–precision plot: for each case a panel of the ω error against
//! wall time, both logarithmic, one curve per method. Drawn with plotters'
//! SVG backend only; text goes out as SVG `<text>` elements, so no font is
//! read from the system.

use plotters::prelude::*;

use super::{Case, Row};

const WIDTH: u32 = 1200;
const HEIGHT: u32 = 760;
/// Errors are drawn no lower than this: the exact solver's own error
/// against itself is 0, and sits on this floor.
pub const ERROR_FLOOR: f64 = 1e-17;

const METHODS: [(&str, RGBColor); 5] = [
    ("exact", RGBColor(0, 0, 0)),
    ("adaptive", RGBColor(31, 119, 180)),
    ("splitting", RGBColor(44, 160, 44)),
    ("splitting4", RGBColor(214, 39, 40)),
    ("rk4", RGBColor(255, 127, 14)),
];

fn floor_log(x: f64) -> f64 {
    10f64.powf(x.log10().floor())
}

fn ceil_log(x: f64) -> f64 {
    10f64.powf(x.log10().ceil())
}

/// The SVG document.
pub fn svg(rows: &[Row], cases: &[Case]) -> anyhow::Result<String> {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e}"))?;
        let (title, body) = root.split_vertically(36);
        title
            .titled(
                "flipcard work-precision: max relative error of w vs wall time (log-log)",
                ("sans-serif", 20),
            )
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        let panels = body.split_evenly((2, 3));
        for (case, area) in cases.iter().zip(panels.iter()) {
            panel(area, case, rows).map_err(|e| anyhow::anyhow!("case {}: {e}", case.id))?;
        }
        if let Some(area) = panels.get(cases.len()) {
            legend(area).map_err(|e| anyhow::anyhow!("{e}"))?;
        }
        root.present().map_err(|e| anyhow::anyhow!("{e}"))?;
    }
    Ok(out)
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

fn panel(area: &Area<'_>, case: &Case, rows: &[Row]) -> Result<(), Box<dyn std::error::Error>> {
    let points: Vec<(&str, f64, f64)> = rows
        .iter()
        .filter(|r| r.case == case.id)
        .filter_map(|r| {
            let m = r.outcome.as_ref().ok()?;
            let err = m.errors.omega.max(ERROR_FLOOR);
            (m.wall > 0.0 && err.is_finite()).then_some((r.method.name(), m.wall, err))
        })
        .collect();
    let (mut t_lo, mut t_hi, mut e_lo, mut e_hi) = (1e-6f64, 1e-3f64, 1e-16f64, 1.0f64);
    for &(_, t, e) in &points {
        t_lo = t_lo.min(t);
        t_hi = t_hi.max(t);
        e_lo = e_lo.min(e);
        e_hi = e_hi.max(e);
    }
    let x = floor_log(t_lo)..ceil_log(t_hi);
    let y = floor_log(e_lo)..ceil_log(e_hi.max(e_lo * 10.0));
    let mut chart = ChartBuilder::on(area)
        .caption(format!("({}) {}", case.id, case.name), ("sans-serif", 15))
        .margin(8)
        .x_label_area_size(34)
        .y_label_area_size(52)
        .build_cartesian_2d(x.log_scale(), y.log_scale())?;
    chart
        .configure_mesh()
        .x_desc("wall time (s)")
        .y_desc("error of w")
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 11))
        .axis_desc_style(("sans-serif", 12))
        .draw()?;
    for (name, color) in METHODS {
        let mut curve: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.0 == name)
            .map(|p| (p.1, p.2))
            .collect();
        // Along the sweep the error falls as the work grows; drawn in order
        // of error so the curve reads from cheap to accurate.
        curve.sort_by(|a, b| b.1.total_cmp(&a.1));
        chart.draw_series(LineSeries::new(
            curve.iter().copied(),
            color.stroke_width(2),
        ))?;
        chart.draw_series(
            curve
                .iter()
                .map(|&(t, e)| Circle::new((t, e), 3, color.filled())),
        )?;
    }
    Ok(())
}

fn legend(area: &Area<'_>) -> Result<(), Box<dyn std::error::Error>> {
    let style = ("sans-serif", 15).into_font();
    for (k, (name, color)) in METHODS.iter().enumerate() {
        let y = 40 + 28 * k as i32;
        area.draw(&PathElement::new(
            vec![(40, y), (90, y)],
            color.stroke_width(3),
        ))?;
        area.draw(&Circle::new((65, y), 4, color.filled()))?;
        area.draw(&Text::new(name.to_string(), (100, y - 8), style.clone()))?;
    }
    let note = ("sans-serif", 12).into_font();
    let lines = [
        "error: max over 1001 points of |w - w_exact| / |w_exact|",
        "time: minimum of several runs, with the orientation q",
        "exact: the reference itself, drawn at 1e-17",
        "fixed steps: 8 ... 2048 per turn of the fastest rate",
    ];
    for (k, line) in lines.iter().enumerate() {
        area.draw(&Text::new(
            line.to_string(),
            (40, 200 + 20 * k as i32),
            note.clone(),
        ))?;
    }
    Ok(())
}
