//! A large collection: a deck of 50,000 cards (about 14 MB of TOML, the
//! size of a medical Anki deck brought over), timed through the app's own
//! code. Targets (issue 25 §6): the first frame of home < 100 ms, `check`
//! < 0.5 s.
//!
//! - `check`: the deck file read, validated and checked as `flipcard check
//!   big.toml` does (no cache);
//! - `load, cold`: the decks loaded with an empty deck cache (the first
//!   start after the deck file changed; the cache is written);
//! - `load, warm`: the decks loaded with the deck cache written before;
//! - `first frame, warm`: what the app does before its first frame: the
//!   decks loaded (cache written before), the store opened, the app built
//!   and home drawn at 120×40.
//!
//! Each is run several times; the minimum and the median are printed.
//! Whole-process figures (peak memory) are measured on the release binary.
//!
//!     cargo bench --bench large [-- CARDS]

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use ratatui::Terminal;
use ratatui::backend::TestBackend;

use flipcard::cmd::library::{self, Origin, Source};
use flipcard::deck::DeckCache;
use flipcard::sched::Config;
use flipcard::store::Store;
use flipcard::tui::services::{Clock, DayZone, Services};
use flipcard::tui::theme::Theme;
use flipcard::tui::{Tui, view};

const WORDS: &[&str] = &[
    "heart",
    "lung",
    "kidney",
    "liver",
    "nerve",
    "artery",
    "vein",
    "muscle",
    "bone",
    "cell",
    "protein",
    "enzyme",
    "hormone",
    "receptor",
    "membrane",
    "channel",
    "potassium",
    "sodium",
    "calcium",
    "glucose",
    "insulin",
    "cortisol",
    "pressure",
    "volume",
    "flow",
    "rate",
];

/// A deck of `n` cards (one in ten reversed), each with two tags and a
/// little math, and its empty content file.
fn write_deck(root: &Path, n: usize) -> PathBuf {
    let decks = root.join("decks");
    std::fs::create_dir_all(&decks).unwrap();
    std::fs::create_dir_all(root.join("content/big")).unwrap();
    std::fs::write(root.join("content/big/en.toml"), "").unwrap();
    let mut seed: u64 = 7;
    let mut word = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        WORDS[(seed >> 33) as usize % WORDS.len()]
    };
    let mut s =
        String::from("[deck]\nid = \"big\"\ntitle = \"A big deck\"\nlanguages = [\"en\"]\n\n");
    for i in 0..n {
        let w = |k: usize, word: &mut dyn FnMut() -> &'static str| {
            (0..k).map(|_| word()).collect::<Vec<_>>().join(" ")
        };
        s.push_str(&format!("[[card]]\nid = \"c{i}\"\n"));
        if i % 10 == 0 {
            s.push_str("kind = \"reversed\"\n");
        }
        s.push_str(&format!(
            "tags = [\"med::{}\", \"set{}\"]\nfront.en = '''What does the {} do when $x^2 + {i}$ rises?'''\nback.en = '''It {}, so the {} falls.'''\n\n",
            word(),
            i % 50,
            w(6, &mut word),
            w(8, &mut word),
            w(4, &mut word),
        ));
    }
    std::fs::write(decks.join("big.toml"), s).unwrap();
    decks
}

fn sources(decks: &Path) -> Vec<Source> {
    vec![
        Source {
            origin: Origin::Bundled,
            path: PathBuf::from(flipcard::bundled::DECKS),
        },
        Source {
            origin: Origin::CommandLine,
            path: decks.to_path_buf(),
        },
    ]
}

fn report(name: &str, mut times: Vec<Duration>) {
    times.sort();
    println!(
        "{name:<24} min {:>8.1} ms   median {:>8.1} ms   ({} runs)",
        times[0].as_secs_f64() * 1e3,
        times[times.len() / 2].as_secs_f64() * 1e3,
        times.len()
    );
}

fn timed(runs: usize, mut f: impl FnMut()) -> Vec<Duration> {
    (0..runs)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed()
        })
        .collect()
}

fn main() {
    let cards: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(50_000);
    let root = tempfile::tempdir().unwrap();
    let decks = write_deck(root.path(), cards);
    let size = std::fs::metadata(decks.join("big.toml")).unwrap().len();
    println!("{cards} cards, a deck file of {:.1} MB", size as f64 / 1e6);

    report(
        "check",
        timed(5, || {
            let lib = library::load_with(vec![Source {
                origin: Origin::CommandLine,
                path: decks.join("big.toml"),
            }]);
            assert_eq!(lib.loaded.errors(), 0);
            let found = flipcard::predict::audit::check_loaded(&lib.loaded);
            assert!(found.is_empty());
        }),
    );

    let cache_dir = root.path().join("cache");
    let cache = DeckCache::new(cache_dir.clone(), "bench".to_string());
    report(
        "load, cold",
        timed(5, || {
            let _ = std::fs::remove_dir_all(&cache_dir);
            let lib = library::load_cached(sources(&decks), Some(&cache));
            assert_eq!(lib.loaded.decks.len(), 5);
        }),
    );
    report(
        "load, warm",
        timed(9, || {
            let lib = library::load_cached(sources(&decks), Some(&cache));
            assert_eq!(lib.loaded.decks.len(), 5);
        }),
    );

    let data = root.path().join("data");
    report(
        "first frame, warm",
        timed(9, || {
            let lib = library::load_cached(sources(&decks), Some(&cache));
            let store = Store::open(&data).unwrap();
            let services = Services::new(
                Clock::System,
                Config::default(),
                None,
                DayZone::Local,
                store,
            );
            let app = Tui::new(lib.loaded.decks, services, "en", Theme::COLOR);
            let mut t = Terminal::new(TestBackend::new(120, 40)).unwrap();
            t.draw(|f| view::draw(f, &app)).unwrap();
            let screen = format!("{:?}", t.backend().buffer());
            assert!(screen.contains("A big deck"));
        }),
    );
}
