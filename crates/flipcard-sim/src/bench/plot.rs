//! The work–precision plot: for each case a panel of the ω error against
//! wall time, both logarithmic, one curve per method. Drawn with plotters'
//! SVG backend only; text goes out as SVG `<text>` elements, so no font is
//! read from the system.

use plotters::prelude::*;

use super::{Case, Row, SystemCase, SystemRow};

const WIDTH: u32 = 1200;
const HEIGHT: u32 = 1140;
/// Height of the bottom row: the generic ODE solvers on the systems.
const SYSTEMS_HEIGHT: u32 = 380;

/// Colours of the generic ODE methods in the systems panels.
const SYSTEM_METHODS: [(&str, RGBColor); 6] = [
    ("adaptive", RGBColor(31, 119, 180)),
    ("radau", RGBColor(148, 103, 189)),
    ("rk4", RGBColor(255, 127, 14)),
    ("auto", RGBColor(140, 86, 75)),
    ("verlet", RGBColor(44, 160, 44)),
    ("verlet4", RGBColor(214, 39, 40)),
];
/// Errors are drawn no lower than this: the exact solver's own error
/// against itself is 0, and sits on this floor.
pub(crate) const ERROR_FLOOR: f64 = 1e-17;

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
pub(crate) fn svg(
    rows: &[Row],
    cases: &[Case],
    systems: &[SystemRow],
    system_cases: &[SystemCase],
) -> anyhow::Result<String> {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e}"))?;
        let (title, body) = root.split_vertically(36);
        title
            .titled(
                "flipcard work-precision: largest relative error of ω against wall time",
                ("sans-serif", 20),
            )
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        let (body, bottom) = body.split_vertically(HEIGHT - 36 - SYSTEMS_HEIGHT);
        let system_panels = bottom.split_evenly((1, system_cases.len() + 1));
        for (case, area) in system_cases.iter().zip(system_panels.iter()) {
            system_panel(area, case, systems)
                .map_err(|e| anyhow::anyhow!("case {}: {e}", case.id))?;
        }
        if let Some(area) = system_panels.get(system_cases.len()) {
            system_legend(area).map_err(|e| anyhow::anyhow!("{e}"))?;
        }
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
        .y_desc("error of ω")
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 11))
        .axis_desc_style(("sans-serif", 12))
        .draw()?;
    for (name, color) in METHODS {
        // In sweep order: from the loosest setting to the finest.
        let curve: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.0 == name)
            .map(|p| (p.1, p.2))
            .collect();
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

/// A log-log chart of error against wall time, one curve per method in
/// sweep order (loosest setting first).
fn chart(
    area: &Area<'_>,
    caption: String,
    y_desc: &str,
    points: &[(&str, f64, f64)],
    methods: &[(&str, RGBColor)],
) -> Result<(), Box<dyn std::error::Error>> {
    let (mut t_lo, mut t_hi, mut e_lo, mut e_hi) = (1e-6f64, 1e-3f64, 1e-16f64, 1.0f64);
    for &(_, t, e) in points {
        t_lo = t_lo.min(t);
        t_hi = t_hi.max(t);
        e_lo = e_lo.min(e);
        e_hi = e_hi.max(e);
    }
    let x = floor_log(t_lo)..ceil_log(t_hi);
    let y = floor_log(e_lo)..ceil_log(e_hi.max(e_lo * 10.0));
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 15))
        .margin(8)
        .x_label_area_size(34)
        .y_label_area_size(52)
        .build_cartesian_2d(x.log_scale(), y.log_scale())?;
    chart
        .configure_mesh()
        .x_desc("wall time (s)")
        .y_desc(y_desc)
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 11))
        .axis_desc_style(("sans-serif", 12))
        .draw()?;
    for &(name, color) in methods {
        let curve: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.0 == name)
            .map(|p| (p.1, p.2))
            .collect();
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

fn system_panel(
    area: &Area<'_>,
    case: &SystemCase,
    rows: &[SystemRow],
) -> Result<(), Box<dyn std::error::Error>> {
    let points: Vec<(&str, f64, f64)> = rows
        .iter()
        .filter(|r| r.case == case.id)
        .filter_map(|r| {
            let m = r.outcome.as_ref().ok()?;
            let err = m.err_state.max(ERROR_FLOOR);
            (m.wall > 0.0 && err.is_finite()).then_some((r.method.name(), m.wall, err))
        })
        .collect();
    chart(
        area,
        format!("({}) {}", case.id, case.name),
        "error of the state",
        &points,
        &SYSTEM_METHODS,
    )
}

fn system_legend(area: &Area<'_>) -> Result<(), Box<dyn std::error::Error>> {
    let style = ("sans-serif", 15).into_font();
    for (k, (name, color)) in SYSTEM_METHODS.iter().enumerate() {
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
        "generic ODE solvers on systems",
        "error: max over samples of |yᵢ − refᵢ| / max|refᵢ|",
        "pendulum: exact (Jacobi sn); kepler: Kepler's equation",
        "vdp, robertson: tight radau",
        "missing curves: refused (stiff), see the CSV",
    ];
    for (k, line) in lines.iter().enumerate() {
        area.draw(&Text::new(
            line.to_string(),
            (20, 170 + 20 * k as i32),
            note.clone(),
        ))?;
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
        "error: max over 1001 points of |ω − ω_exact| / |ω_exact|",
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
