//! A rigid body's run sampled at N evenly spaced times and written as CSV
//! or JSON: the checked request (`--samples`, the method), the rows and the
//! writer. `flipcard sim --inertia …` and `sim --scene ID --samples N` of a
//! rigid scene both write it; a system scene's samples obey the same
//! [`check_samples`].

use std::io::Write;

use anyhow::bail;
use nalgebra::Vector3;
use serde::Serialize;

use crate::cmd::args::{MethodArg, SimArgs, SimFormat};
use crate::sim::rigid::model::{Body, State};
use crate::sim::solvers::registry;
use crate::sim::solvers::{Method, Solver};
use crate::text::num::{self, Num};

/// The CSV header; columns follow the axes in the order given.
pub const CSV_HEADER: &str = "t,w1,w2,w3,qw,qx,qy,qz,energy,l2";
/// The most samples any run prints: 2⁵⁰ + 1 (see [`max_samples`]).
pub const MAX_SAMPLES: usize = (1 << 50) + 1;

/// The most samples over [0, t_end] whose times k·T/(N−1) stay distinct and
/// increasing in f64: their spacing must be at least two ulps of T, since
/// each time is rounded by up to half an ulp. Two samples (0 and T) always
/// are; past 2⁵⁰ intervals the spacing is under four ulps of any T.
pub fn max_samples(t_end: f64) -> usize {
    let ulp = f64::from_bits(t_end.to_bits() + 1) - t_end;
    let intervals = (t_end / (2.0 * ulp)).floor();
    if intervals.is_nan() || intervals < 1.0 {
        return 2;
    }
    (intervals.min((MAX_SAMPLES - 1) as f64) as usize + 1).max(2)
}

/// A checked `sim` request.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    pub body: Body,
    pub omega0: Vector3<f64>,
    pub t_end: f64,
    pub samples: usize,
    pub method: Method,
}

impl Request {
    /// A request for `body` from `omega0` over [0, `t_end`] with the
    /// arguments' samples and method.
    pub fn new(
        args: &SimArgs,
        body: Body,
        omega0: Vector3<f64>,
        t_end: f64,
    ) -> anyhow::Result<Request> {
        let samples = check_samples(args.samples.unwrap_or(DEFAULT_SAMPLES), t_end)?;
        let kind = crate::sim::Kind::try_from(args.method.unwrap_or(MethodArg::Exact))?;
        let method = registry::method(kind, args.tol, args.dt, &body, &omega0)?;
        Ok(Request {
            body,
            omega0,
            t_end,
            samples,
            method,
        })
    }

    /// t = k·T/(N−1), with the last sample exactly T.
    pub fn time(&self, k: usize) -> f64 {
        let last = self.samples - 1;
        if k == last {
            self.t_end
        } else {
            k as f64 * self.t_end / last as f64
        }
    }
}

/// Samples printed when `--samples` is not given.
pub const DEFAULT_SAMPLES: usize = 101;

/// `--samples N` checked against the span: at least 2, at most what keeps
/// the sample times distinct.
pub fn check_samples(samples: usize, t_end: f64) -> anyhow::Result<usize> {
    if samples < 2 {
        bail!("--samples: need at least 2 (the start and the end), got {samples}");
    }
    let most = max_samples(t_end);
    if samples > most {
        bail!(
            "--samples: at most {most} over t = {}, got {samples} (neighbouring sample times k·T/(N−1) would be less than two ulps apart in f64)",
            Num(t_end)
        );
    }
    Ok(samples)
}

/// One output row.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Sample {
    pub t: f64,
    pub w1: f64,
    pub w2: f64,
    pub w3: f64,
    pub qw: f64,
    pub qx: f64,
    pub qy: f64,
    pub qz: f64,
    pub energy: f64,
    pub l2: f64,
}

impl Sample {
    pub fn new(body: &Body, t: f64, state: &State) -> Sample {
        let (w, q) = (state.omega, state.q.quaternion());
        Sample {
            t,
            w1: w[0],
            w2: w[1],
            w3: w[2],
            qw: q.w,
            qx: q.i,
            qy: q.j,
            qz: q.k,
            energy: body.energy(&w),
            l2: body.l2(&w),
        }
    }

    fn fields(&self) -> [f64; 10] {
        [
            self.t,
            self.w1,
            self.w2,
            self.w3,
            self.qw,
            self.qx,
            self.qy,
            self.qz,
            self.energy,
            self.l2,
        ]
    }

    fn csv(&self) -> String {
        let fields: Vec<String> = self.fields().iter().map(|&v| num::show(v)).collect();
        fields.join(",")
    }
}

/// The inputs echoed at the top of the JSON output (effective settings,
/// defaults filled in).
#[derive(Debug, Serialize)]
struct Inputs {
    inertia: [f64; 3],
    omega: [f64; 3],
    t_end: f64,
    method: &'static str,
    tol: Option<f64>,
    dt: Option<f64>,
}

impl Inputs {
    fn new(request: &Request) -> Inputs {
        let (tol, dt) = match request.method {
            Method::Exact => (None, None),
            Method::Adaptive { tol } => (Some(tol), None),
            Method::Splitting { dt } | Method::Splitting4 { dt } | Method::Rk4 { dt } => {
                (None, Some(dt))
            }
        };
        let i = request.body.inertia;
        let w = request.omega0;
        Inputs {
            inertia: [i[0], i[1], i[2]],
            omega: [w[0], w[1], w[2]],
            t_end: request.t_end,
            method: request.method.name(),
            tol,
            dt,
        }
    }
}

/// Closes the JSON document after the rows written so far: `]}`, or with
/// the reason the run stopped, `],"error":"…"}`, so that a refusal midway
/// still leaves well-formed JSON (the CSV simply ends; the reason goes to
/// stderr either way).
pub(super) fn close_json(
    out: &mut impl Write,
    error: Option<&str>,
    stats: &Stats,
) -> anyhow::Result<()> {
    write!(out, "\n]")?;
    if let Some(e) = error {
        write!(out, ",\"error\":{}", serde_json::to_string(e)?)?;
    }
    writeln!(out, ",\"stats\":{}}}", serde_json::to_string(stats)?)?;
    Ok(())
}

/// What a sampled run did: its work counters and, for `auto`, when it
/// switched to the implicit method. The JSON's `stats`; `--stats` prints
/// it as a line on stderr.
#[derive(Debug, Default, Serialize)]
pub(super) struct Stats {
    pub steps: u64,
    pub rejected: u64,
    pub rhs_evals: u64,
    pub jacobian_evals: u64,
    pub lu_decompositions: u64,
    /// How the Newton matrices were factored (`dense`, `banded`,
    /// `sparse`: `sim::solvers::ode::lu::LuKind`); null when none was.
    pub lu: Option<&'static str>,
    /// The time `auto` found the problem stiff and switched, if it did.
    pub stiff_from: Option<f64>,
    /// A system scene's `conserved` quantities: how far each moved over
    /// the run (absent when the scene declares none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub conserved: Vec<Conserved>,
    /// The sums of variables the equations keep fixed, written with the
    /// variables' names (`y2 - y3 - y4`), which the solver held against
    /// rounding (`sim::solvers::ode::fixed`; auto, adaptive and radau);
    /// absent when there are none or the method does not hold them.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub fixed_sums: Vec<String>,
}

/// How far a quantity the scene declares conserved moved over a run.
#[derive(Debug, Serialize)]
pub(super) struct Conserved {
    pub name: String,
    /// Its value at the start.
    pub start: f64,
    /// The largest |value − start| over every sample the run computed
    /// (each step's, not only the printed rows).
    pub max_change: f64,
    /// `max_change` / |start|; null when the start is 0.
    pub max_drift: Option<f64>,
}

impl Stats {
    /// `stats: 412 steps, 3 rejected, 5,101 right-hand sides, …`.
    pub(super) fn line(&self) -> String {
        let mut s = format!(
            "stats: {} steps, {} rejected, {} right-hand sides, {} Jacobians, {} LU decompositions",
            self.steps, self.rejected, self.rhs_evals, self.jacobian_evals, self.lu_decompositions
        );
        if let Some(lu) = self.lu {
            s.push_str(&format!(" ({lu})"));
        }
        if let Some(t) = self.stiff_from {
            s.push_str(&format!(", stiff from t = {}: switched to radau", Num(t)));
        }
        if !self.fixed_sums.is_empty() {
            s.push_str(&format!(", held fixed: {}", self.fixed_sums.join(", ")));
        }
        for c in &self.conserved {
            let name = crate::text::safe::one_line(&c.name);
            match c.max_drift {
                Some(d) => s.push_str(&format!(
                    ", {name} drifts by up to {} of its start",
                    num::sig(d, 3)
                )),
                None => s.push_str(&format!(
                    ", {name} moves by up to {} from 0",
                    num::sig(c.max_change, 3)
                )),
            }
        }
        s
    }
}

/// Streams the samples; a failure midway (the step budget, say) ends the
/// output there and is reported by the caller (the JSON closed with it).
pub(super) fn write_samples(
    request: &Request,
    solver: &mut dyn Solver,
    format: SimFormat,
    show_stats: bool,
    out: &mut impl Write,
) -> anyhow::Result<()> {
    let rows = write_rows(request, solver, format, out);
    let work = solver.work();
    let stats = Stats {
        steps: work.steps,
        rejected: work.rejected,
        rhs_evals: work.rhs_evals,
        ..Stats::default()
    };
    if format == SimFormat::Json {
        close_json(
            out,
            rows.as_ref().err().map(|e| e.to_string()).as_deref(),
            &stats,
        )?;
    } else if show_stats {
        crate::errln!("{}", stats.line());
    }
    out.flush()?;
    rows
}

fn write_rows(
    request: &Request,
    solver: &mut dyn Solver,
    format: SimFormat,
    out: &mut impl Write,
) -> anyhow::Result<()> {
    match format {
        SimFormat::Csv => writeln!(out, "{CSV_HEADER}")?,
        SimFormat::Json => {
            let inputs = serde_json::to_string(&Inputs::new(request))?;
            // Open the inputs object and append the sample array to it.
            let head = inputs.strip_suffix('}').unwrap_or(&inputs);
            write!(out, "{head},\"samples\":[")?;
        }
    }
    for k in 0..request.samples {
        let t = request.time(k);
        let state = solver.advance(t)?;
        let sample = Sample::new(&request.body, t, &state);
        // The solvers refuse non-finite states already; this keeps the
        // contract of the output itself (JSON would print `null`).
        if let Some(v) = sample.fields().iter().find(|v| !v.is_finite()) {
            bail!(
                "{} gave a non-finite number ({}) at t = {}",
                request.method.name(),
                Num(*v),
                Num(t)
            );
        }
        match format {
            SimFormat::Csv => writeln!(out, "{}", sample.csv())?,
            SimFormat::Json => {
                // Each row after a separator, so that the document can be
                // closed after any of them.
                let sep = if k > 0 { "," } else { "" };
                write!(out, "{sep}\n{}", serde_json::to_string(&sample)?)?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_times_stay_distinct() {
        assert_eq!(max_samples(1.0), MAX_SAMPLES);
        assert_eq!(max_samples(1e300), MAX_SAMPLES);
        assert_eq!(max_samples(5e-324), 2);
        // 20 subnormal steps: times at least two of them apart.
        assert_eq!(max_samples(20.0 * 5e-324), 11);
        for t_end in [5e-324, 1e-322, 3e-310, 1e-300, 1.0] {
            let n = max_samples(t_end).min(1000);
            let times: Vec<f64> = (0..n)
                .map(|k| {
                    let request = Request {
                        body: Body::new([1.0, 2.0, 3.0]).unwrap(),
                        omega0: Vector3::zeros(),
                        t_end,
                        samples: n,
                        method: Method::Exact,
                    };
                    request.time(k)
                })
                .collect();
            assert!(
                times.windows(2).all(|w| w[0] < w[1]),
                "{t_end:e}: {times:?}"
            );
        }
    }

    #[test]
    fn csv_row_round_trips() {
        let body = Body::new([1.0, 2.0, 3.0]).unwrap();
        let state = State::new(Vector3::new(0.1, 1.0 / 3.0, -2e-300));
        let row = Sample::new(&body, 0.7, &state).csv();
        let back: Vec<f64> = row.split(',').map(|v| v.parse().unwrap()).collect();
        assert_eq!(back[2], 1.0 / 3.0);
        assert_eq!(back[3], -2e-300);
        assert_eq!(back[8], body.energy(&state.omega));
    }
}
