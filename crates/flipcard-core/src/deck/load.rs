//! Finding deck files and their content files, and running both stages on
//! them.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Component, Path, PathBuf};

use super::cache::{DeckCache, MIN_CACHED_BYTES};
use super::chunked;
use super::diag::{Diagnostic, LineIndex, Severity};
use super::files::{Disk, Probe, Tree};
use super::model::Deck;
use super::raw;
use super::report::FileReport;
use super::syntax;
use super::validate::{self, content::ContentFile};

/// Everything a load found: the valid decks, every diagnostic (in file
/// order), and the text of each file read, for rendering.
#[derive(Debug, Default)]
pub struct Loaded {
    /// The decks without errors (warnings allowed), in the order loaded.
    pub decks: Vec<Deck>,
    pub diagnostics: Vec<Diagnostic>,
    /// The text of every file read, by the path diagnostics use.
    pub sources: BTreeMap<PathBuf, String>,
}

impl Loaded {
    pub fn errors(&self) -> usize {
        self.diagnostics.iter().filter(|d| d.is_error()).count()
    }

    pub fn warnings(&self) -> usize {
        self.diagnostics.len() - self.errors()
    }

    /// One diagnostic with its source line (headline and help only when the
    /// file could not be read).
    pub fn render(&self, d: &Diagnostic) -> String {
        d.render(self.sources.get(&d.path).map_or("", String::as_str))
    }

    /// Every diagnostic rendered, separated by blank lines (each file's
    /// lines indexed once, so many diagnostics in a big file stay cheap).
    pub fn render_all(&self) -> String {
        let mut indexes: HashMap<&Path, LineIndex> = HashMap::new();
        let rendered: Vec<String> = self
            .diagnostics
            .iter()
            .map(|d| {
                let source = self.sources.get(&d.path).map_or("", String::as_str);
                let index = indexes
                    .entry(&d.path)
                    .or_insert_with(|| LineIndex::new(source));
                d.render_line(index.line(source, d.line))
            })
            .collect();
        rendered.join("\n")
    }
}

/// Loads every deck in a folder (each `*.toml` directly in it) or one file.
pub fn load_dir(path: &Path) -> Loaded {
    load_paths(&[path.to_path_buf()])
}

/// Loads deck files and folders of deck files (each `*.toml` directly in
/// the folder, in name order). Paths in diagnostics are built from the paths
/// given, so relative paths stay relative.
pub fn load_paths(paths: &[PathBuf]) -> Loaded {
    load_tree(&Disk, paths)
}

/// [`load_paths`] over the files of `tree`.
pub fn load_tree(tree: &dyn Tree, paths: &[PathBuf]) -> Loaded {
    let sources: Vec<(&dyn Tree, PathBuf)> = paths.iter().map(|p| (tree, p.clone())).collect();
    load_sources(&sources).0
}

/// What became of one deck file (or of a folder that could not be read).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FileStatus {
    /// Index of the source it came from.
    pub source: usize,
    pub path: PathBuf,
    /// Errors and warnings in the deck file and its content files.
    pub errors: usize,
    pub warnings: usize,
    /// Index of its deck in [`Loaded::decks`] when it loaded.
    pub deck: Option<usize>,
}

/// Loads every deck of several sources, each a folder or file in its own
/// tree, in order: a deck id found in two files is an error at the second,
/// naming the first. Returns what was loaded and, per deck file, its fate.
pub fn load_sources(sources: &[(&dyn Tree, PathBuf)]) -> (Loaded, Vec<FileStatus>) {
    load_sources_cached(sources, None)
}

/// [`load_sources`], taking a large deck file that has not changed from
/// `cache` (and keeping one that loads clean there): see [`DeckCache`].
pub fn load_sources_cached(
    sources: &[(&dyn Tree, PathBuf)],
    cache: Option<&DeckCache>,
) -> (Loaded, Vec<FileStatus>) {
    let mut loaded = Loaded::default();
    let mut statuses = Vec::new();
    let mut seen_ids: HashMap<String, PathBuf> = HashMap::new();
    let mut parents: Vec<super::tree::ParentAt> = Vec::new();
    // Every deck file of every source first, each once (the same file named
    // twice, `decks decks/x.toml`, is one deck), with what its source said.
    let mut seen_files: HashSet<PathBuf> = HashSet::new();
    let listed: Vec<(usize, Vec<Diagnostic>, Vec<PathBuf>)> = sources
        .iter()
        .enumerate()
        .map(|(source, (tree, path))| {
            let mut said = Loaded::default();
            let files = deck_files(*tree, path, &mut said)
                .into_iter()
                .filter(|f| seen_files.insert(tree.identity(f)))
                .collect();
            (source, said.diagnostics, files)
        })
        .collect();
    let jobs: Vec<(&dyn Tree, &Path)> = listed
        .iter()
        .flat_map(|(source, _, files)| files.iter().map(|f| (sources[*source].0, f.as_path())))
        .collect();
    std::thread::scope(|scope| {
        let mut next = read_ahead(scope, &jobs, cache);
        for (source, said, files) in &listed {
            let (tree, path) = &sources[*source];
            if !said.is_empty() {
                statuses.push(FileStatus {
                    source: *source,
                    path: path.clone(),
                    errors: said.len(),
                    warnings: 0,
                    deck: None,
                });
                loaded.diagnostics.extend(said.iter().cloned());
            }
            for file in files {
                let read = next();
                let (diags, decks) = (loaded.diagnostics.len(), loaded.decks.len());
                load_deck(
                    *tree,
                    file,
                    read,
                    &mut loaded,
                    &mut seen_ids,
                    &mut parents,
                    cache,
                );
                let errors = loaded.diagnostics[diags..]
                    .iter()
                    .filter(|d| d.is_error())
                    .count();
                statuses.push(FileStatus {
                    source: *source,
                    path: file.clone(),
                    errors,
                    warnings: loaded.diagnostics.len() - diags - errors,
                    deck: (loaded.decks.len() > decks).then_some(decks),
                });
            }
        }
    });
    // Parents across every source: missing ones said, cycles refused.
    let (said, refused) = super::tree::check_parents(&loaded.decks, &parents, &loaded.sources);
    for d in &said {
        if let Some(s) = statuses.iter_mut().find(|s| s.path == d.path) {
            if d.is_error() {
                s.errors += 1;
            } else {
                s.warnings += 1;
            }
        }
    }
    loaded.diagnostics.extend(said);
    if !refused.is_empty() {
        let mut kept = Vec::with_capacity(loaded.decks.len());
        let mut new_index = vec![None; loaded.decks.len()];
        for (i, d) in std::mem::take(&mut loaded.decks).into_iter().enumerate() {
            if !refused.contains(&i) {
                new_index[i] = Some(kept.len());
                kept.push(d);
            }
        }
        loaded.decks = kept;
        for s in &mut statuses {
            s.deck = s.deck.and_then(|i| new_index.get(i).copied().flatten());
        }
    }
    (loaded, statuses)
}

/// A deck file as read: its text (`None` when it could not be read, with
/// the problems saying why and the lossy text of invalid UTF-8 kept for
/// rendering), and the deck the cache kept for these bytes.
struct Read {
    text: Option<String>,
    problems: Vec<Diagnostic>,
    lossy: BTreeMap<PathBuf, String>,
    hit: Option<super::cache::Cached>,
}

/// Reads a deck file and, when it is large and a cache is given, looks it
/// up there: the kept entry is read and decoded on this thread while
/// another reads the deck file and computes the key its bytes give.
fn read_deck_file(tree: &dyn Tree, path: &Path, cache: Option<&DeckCache>) -> Read {
    let read = || {
        let mut problems = Vec::new();
        let mut lossy = BTreeMap::new();
        let text = read_text_into(tree, path, &mut problems, &mut lossy);
        (text, (problems, lossy))
    };
    let large = |len: u64| len >= MIN_CACHED_BYTES as u64;
    let Some((c, len)) = cache.zip(tree.len(path).filter(|&l| large(l))) else {
        let (text, (problems, lossy)) = read();
        return Read {
            text,
            problems,
            lossy,
            hit: None,
        };
    };
    let stem = stem_of(path);
    let dir = content_dir(path, &stem);
    let content = |lang: &str| {
        let file = dir.join(format!("{lang}.toml"));
        if tree.probe(&file) != Probe::Regular {
            return None;
        }
        let text = String::from_utf8(tree.read(&file).ok()?).ok()?;
        Some((file, text))
    };
    let (text, (problems, lossy), hit) = c.get(&stem, len, read, content, path);
    Read {
        text,
        problems,
        lossy,
        hit,
    }
}

/// The deck files of `jobs`, read one after another as the loop asks for
/// them. With a cache, another thread reads (and takes from the cache)
/// ahead of the loop, so a large deck is decoded while the decks before it
/// are validated; without one (`check`) each is read when asked.
fn read_ahead<'scope, 'env>(
    scope: &'scope std::thread::Scope<'scope, 'env>,
    jobs: &'env [(&'env dyn Tree, &'env Path)],
    cache: Option<&'env DeckCache>,
) -> impl FnMut() -> Read + 'env {
    let mut at = 0;
    let ahead = cache.filter(|_| jobs.len() > 1).map(|_| {
        let (send, receive) = std::sync::mpsc::channel();
        scope.spawn(move || {
            for (tree, path) in jobs {
                if send.send(read_deck_file(*tree, path, cache)).is_err() {
                    break;
                }
            }
        });
        receive
    });
    move || {
        let (tree, path) = jobs[at];
        at += 1;
        match &ahead {
            Some(r) => r
                .recv()
                .unwrap_or_else(|_| read_deck_file(tree, path, cache)),
            None => read_deck_file(tree, path, cache),
        }
    }
}

fn stem_of(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// The deck files a path names: a file, or every `*.toml` entry of a
/// folder whatever it is, so that a link or FIFO there is reported by the
/// reader instead of leaving a deck out unnoticed.
fn deck_files(tree: &dyn Tree, path: &Path, loaded: &mut Loaded) -> Vec<PathBuf> {
    if !tree.is_dir(path) {
        return vec![path.to_path_buf()];
    }
    match tree.list(path) {
        Ok(entries) => {
            let mut files: Vec<PathBuf> = entries
                .into_iter()
                .filter(|p| p.extension().is_some_and(|e| e == "toml"))
                // Hidden names are an editor's (Emacs's `.#deck.toml` lock
                // is a dangling link while the deck is open), not decks.
                .filter(|p| {
                    p.file_name()
                        .and_then(|n| n.to_str())
                        .is_some_and(|n| !n.starts_with('.'))
                })
                .collect();
            files.sort();
            files
        }
        Err(e) => {
            loaded.diagnostics.push(Diagnostic::whole_file(
                path.to_path_buf(),
                format!("cannot be read: {e}"),
                None,
            ));
            Vec::new()
        }
    }
}

/// Reads a file as UTF-8 text; a path that is not a regular file, an I/O
/// problem or invalid UTF-8 is a diagnostic in `problems` (the lossy text
/// is still kept in `sources`, for rendering).
fn read_text_into(
    tree: &dyn Tree,
    path: &Path,
    problems: &mut Vec<Diagnostic>,
    sources: &mut BTreeMap<PathBuf, String>,
) -> Option<String> {
    let read = match tree.probe(path) {
        Probe::Regular => tree.read(path),
        Probe::Missing => Err("no such file or directory".to_string()),
        Probe::Unusable(why) => Err(why),
    };
    let bytes = match read {
        Ok(b) => b,
        Err(why) => {
            problems.push(Diagnostic::whole_file(path.to_path_buf(), why, None));
            return None;
        }
    };
    match String::from_utf8(bytes) {
        Ok(text) => Some(text),
        Err(e) => {
            let valid = e.utf8_error().valid_up_to();
            let bytes = e.into_bytes();
            let text = String::from_utf8_lossy(&bytes).into_owned();
            let prefix = String::from_utf8_lossy(&bytes[..valid]).into_owned();
            let mut rep = FileReport::new(path, &prefix);
            rep.error(
                valid..valid + 1,
                format!("not valid UTF-8 (byte 0x{:02X})", bytes[valid]),
                Some("deck and content files are UTF-8 text".to_string()),
            );
            problems.extend(rep.finish());
            sources.insert(path.to_path_buf(), text);
            None
        }
    }
}

/// Where a deck's content files live: `<deck folder>/../content/<deck-id>/`,
/// built lexically so a relative deck path gives a relative content path.
pub fn content_dir(deck_file: &Path, deck_id: &str) -> PathBuf {
    let folder = deck_file.parent().unwrap_or(Path::new(""));
    let root = match folder.components().next_back() {
        Some(Component::Normal(_)) => folder.parent().unwrap_or(Path::new("")).to_path_buf(),
        _ => folder.join(".."),
    };
    root.join("content").join(deck_id)
}

fn load_deck(
    tree: &dyn Tree,
    path: &Path,
    read: Read,
    loaded: &mut Loaded,
    seen_ids: &mut HashMap<String, PathBuf>,
    parents: &mut Vec<super::tree::ParentAt>,
    cache: Option<&DeckCache>,
) {
    loaded.diagnostics.extend(read.problems);
    loaded.sources.extend(read.lossy);
    let Some(text) = read.text else {
        return;
    };
    let stem = stem_of(path);
    if let Some(hit) = read.hit
        && !seen_ids.contains_key(&hit.deck.id)
    {
        let dir = content_dir(path, &stem);
        seen_ids.insert(hit.deck.id.clone(), path.to_path_buf());
        loaded
            .diagnostics
            .extend(stray_content_files(tree, &dir, &hit.deck.languages));
        loaded.sources.insert(path.to_path_buf(), text);
        loaded.sources.extend(hit.content);
        if let Some(span) = hit.parent_span {
            parents.push(super::tree::ParentAt {
                deck: loaded.decks.len(),
                path: path.to_path_buf(),
                span,
            });
        }
        loaded.decks.push(hit.deck);
        return;
    }
    let cached = cache.filter(|_| text.len() >= MIN_CACHED_BYTES);
    let mut rep = FileReport::new(path, &text);
    let parsed = chunked::read_deck(&mut rep, &text);
    let Some(raw) = parsed else {
        loaded.diagnostics.extend(rep.finish());
        loaded.sources.insert(path.to_path_buf(), text);
        return;
    };
    let header = validate::header(&mut rep, &raw, &stem);

    if let (Some(id), Some(d)) = (&header.id, &raw.deck) {
        match seen_ids.get(id) {
            Some(first) => {
                let span = d.id.as_ref().map_or(0..0, |s| s.span.clone());
                rep.error(
                    span,
                    format!("deck id `{id}` is also used by {}", first.display()),
                    Some("deck ids must be unique: review history is keyed by them".to_string()),
                );
            }
            None => {
                seen_ids.insert(id.clone(), path.to_path_buf());
            }
        }
    }

    // Content files: one per declared language, found by deck id.
    // By file name: the deck id must equal it, and a mismatch is reported
    // once above rather than again as missing content.
    let dir = content_dir(path, &stem);
    let mut texts: Vec<(String, PathBuf, Option<String>)> = Vec::new();
    let mut stray = Vec::new();
    // Content files that cannot be read are reported after the deck file.
    let mut unreadable = Vec::new();
    if header.langs.known {
        for (lang, span) in &header.lang_spans {
            let file = dir.join(format!("{lang}.toml"));
            if tree.probe(&file) != Probe::Missing {
                // Whatever is there is read, or reported as what it is.
                let text = read_text_into(tree, &file, &mut unreadable, &mut loaded.sources);
                texts.push((lang.clone(), file, text));
            } else {
                rep.error(
                    span.clone(),
                    format!("no content file for language `{lang}`"),
                    Some(format!(
                        "expected {} (an empty file is fine when the deck has no explanations)",
                        file.display()
                    )),
                );
                texts.push((lang.clone(), file, None));
            }
        }
        stray = stray_content_files(tree, &dir, &header.langs.list);
    }
    let mut files: Vec<ContentFile> = texts
        .iter()
        .map(|(lang, file, text)| {
            let mut crep = FileReport::new(file, text.as_deref().unwrap_or(""));
            let raw = text.as_deref().and_then(|t| {
                let (root, span) = syntax::parse(&mut crep, t)?;
                Some(raw::read_content_file(&mut crep, &root, span))
            });
            ContentFile {
                lang: lang.clone(),
                rep: crep,
                raw,
            }
        })
        .collect();
    let sections = if files.is_empty() {
        validate::content::Sections {
            sections: None,
            ids: None,
            anchors: validate::Anchors::default(),
            titles: validate::prose::Titles::default(),
        }
    } else {
        validate::content::sections(&mut files)
    };
    let body = validate::body(
        &mut rep,
        &raw,
        &header.langs,
        sections.ids.as_ref(),
        (&sections.anchors, &sections.titles),
    );

    let clean = !rep.has_errors() && files.iter().all(|f| !f.rep.has_errors());
    let deck = match (clean, header, body, sections.sections) {
        (true, h, Some(body), Some(sections)) => (|| {
            Some(Deck {
                id: h.id?,
                title: h.title?,
                description: h.description?,
                languages: h.langs.list,
                cards: body.cards,
                prompts: body.prompts,
                scenes: body.scenes,
                systems: body.systems,
                sections,
                units: h.units,
                misconceptions: body.misconceptions,
                explore: body.explore,
                derivations: body.derivations,
                path: path.to_path_buf(),
                parent: h.parent,
            })
        })(),
        _ => None,
    };
    let mut diagnostics = rep.finish();
    for f in files {
        diagnostics.extend(f.rep.finish());
    }
    diagnostics.extend(unreadable);
    diagnostics.extend(stray);
    // Only a deck with nothing at all to say is kept: a cached deck is
    // shown without its file's warnings.
    if let (Some(c), Some(deck), true) = (cached, &deck, diagnostics.is_empty()) {
        let content: Vec<(String, &str)> = texts
            .iter()
            .filter_map(|(lang, _, text)| Some((lang.clone(), text.as_deref()?)))
            .collect();
        let parent_span = raw
            .deck
            .as_ref()
            .and_then(|d| d.parent.as_ref())
            .map(|p| p.span.clone());
        c.put((&stem, &text), deck, parent_span, &content);
    }
    loaded.diagnostics.extend(diagnostics);
    loaded.sources.insert(path.to_path_buf(), text);
    for (_, file, text) in texts {
        if let Some(text) = text {
            loaded.sources.insert(file, text);
        }
    }
    if let (Some(deck), Some(span)) = (
        &deck,
        raw.deck
            .as_ref()
            .and_then(|d| d.parent.as_ref())
            .map(|p| p.span.clone()),
    ) && deck.parent.is_some()
    {
        parents.push(super::tree::ParentAt {
            deck: loaded.decks.len(),
            path: path.to_path_buf(),
            span,
        });
    }
    loaded.decks.extend(deck);
}

/// A content file for a language the deck does not declare is never shown:
/// most likely a tag spelt differently (`hi-latn`), so say so.
fn stray_content_files(tree: &dyn Tree, dir: &Path, langs: &[String]) -> Vec<Diagnostic> {
    let Ok(entries) = tree.list(dir) else {
        return Vec::new();
    };
    let mut stray: Vec<PathBuf> = entries
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter(|p| {
            p.file_stem()
                .is_none_or(|s| !langs.iter().any(|l| *l == s.to_string_lossy()))
        })
        .collect();
    stray.sort();
    stray
        .into_iter()
        .map(|p| {
        let lang = p
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        Diagnostic {
            path: p.clone(),
            line: 1,
            col: 1,
            severity: Severity::Warning,
            message: format!("content file for language `{lang}`, which the deck does not declare; it is not used"),
            hint: super::suggest::did_you_mean(&lang, langs.iter().map(String::as_str))
                .or_else(|| Some("add the language to the deck's `languages`, or remove the file".to_string())),
            width: 1,
        }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_named_twice_is_loaded_once() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/decks/valid/full/decks");
        let loaded = load_paths(&[dir.clone(), dir.join("spinning-top.toml")]);
        assert_eq!(loaded.errors(), 0, "{}", loaded.render_all());
        assert_eq!(loaded.decks.len(), 1);
    }

    #[test]
    fn content_dir_sits_beside_the_deck_folder() {
        let cases = [
            ("decks/x.toml", "content/x"),
            (
                "tests/decks/valid/decks/x.toml",
                "tests/decks/valid/content/x",
            ),
            ("/abs/decks/x.toml", "/abs/content/x"),
            ("x.toml", "../content/x"),
            ("./x.toml", "./../content/x"),
            ("../x.toml", "../../content/x"),
        ];
        for (deck, want) in cases {
            assert_eq!(
                content_dir(Path::new(deck), "x"),
                PathBuf::from(want),
                "{deck}"
            );
        }
    }
}
