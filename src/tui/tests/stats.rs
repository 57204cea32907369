//! Stats: forecast, reviews per day, retention, prompt accuracy, the bench table.

use std::io::Write;

use crossterm::event::KeyCode;

use super::{press, press_all};
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::screens::Screen;
use crate::tui::screens::stats::read_bench;
use crate::tui::testkit::{self, render};

#[test]
fn stats_show_todays_reviews_and_the_bench_table() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = testkit::app(lang);
        let csv = app.dir.path().join("work_precision.csv");
        let written = std::fs::File::create(&csv).and_then(|mut f| {
            f.write_all(
                b"case,method,setting,steps,rhs_evals,wall_s,err_omega,err_energy,err_l2,err_lspace,err_qnorm\n\
                  a,rk4,dt=1e-2,100,400,0.0002,3e-5,1e-6,1e-6,1e-6,0\n\
                  a,rk4,dt=1e-3,1000,4000,0.002,3e-9,1e-10,1e-10,1e-10,0\n\
                  a,adaptive,tol=1e-10,200,2400,0.0005,1e-11,1e-13,1e-13,1e-13,0\n\
                  b,rk4,dt=1e-3 (over budget),,,,,,,,\n\
                  b,adaptive,tol=1e-10,900,9000,0.0021,4e-10,1e-12,1e-12,1e-12,0\n",
            )
        });
        assert!(written.is_ok());
        app.services.bench_csv = Some(csv);
        // Two reviews today: one Good, one Again.
        press(&mut app, KeyCode::Enter);
        press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('3')]);
        press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('1')]);
        press_all(&mut app, &[KeyCode::Esc, KeyCode::Char('t')]);
        let Screen::Stats(s) = app.screen() else {
            panic!("stats not open");
        };
        let stats = s.stats.as_ref().map_err(|e| e.clone());
        assert_eq!(
            stats.map(|s| s.reviews_per_day.last().map(|d| d.total)),
            Ok(Some(2))
        );
        // The learner's numbers first; the solvers' table behind `w`.
        let first = render(&app);
        assert!(!first.contains("3e-9"), "{first}");
        assert!(first.contains("w "), "{first}");
        assert!(
            first.contains("review items (from 3 cards + 2 prompts)") || lang == HINGLISH,
            "{first}"
        );
        assert!(first.contains("Due today") || lang == HINGLISH, "{first}");
        press(&mut app, KeyCode::Char('w'));
        let text = render(&app);
        assert!(
            text.contains("3e-9 2.00ms"),
            "the most accurate rk4 run: {text}"
        );
        assert!(!text.contains("3e-5"), "{text}");
        assert!(
            text.contains("case b") && text.contains("4e-10 2.10ms"),
            "{text}"
        );
        let dir = app.dir.path().display().to_string();
        assert!(
            text.contains(&dir[..dir.len().min(20)]),
            "the report's folder is named: {text}"
        );
        insta::assert_snapshot!(format!("stats_{lang}"), text.replace(&dir, "<data dir>"));
        press(&mut app, KeyCode::Esc);
        assert!(matches!(app.screen(), Screen::Home(_)));
    }
}

#[test]
fn missing_bench_file_says_how_to_make_one() {
    let mut app = testkit::app(ENGLISH);
    app.services.bench_csv = None;
    press_all(&mut app, &[KeyCode::Char('t'), KeyCode::Char('w')]);
    assert!(render(&app).contains("flipcard bench"));
    assert!(read_bench(std::path::Path::new("/nonexistent/work_precision.csv")).is_none());
}
