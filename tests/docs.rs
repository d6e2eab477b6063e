//! Docs that cannot drift: every repository path cited in the README, the
//! CHANGELOG, `docs/*.md` or a source comment (`src/`, `hal-sim/`, `xtask/`,
//! `scripts/`) exists; every `method.md §n` has its section; no comment cites
//! the section marks of the background note outside the repository; every `#[inline(never)]` in
//! `src/` and `examples/` carries a reason tag that `docs/avr-traps.md`
//! defines; the README stays a short front page. (The documented commands of
//! `armsim` and the main job are parsed beside the binaries that own them:
//! `hal-sim/bench/tests/doc_commands.rs`, since it runs both binaries.)
//!
//! The path check is tolerant only in the way listed below ([`GENERATED`]).

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// Where a cited path may start (the repository's top level).
const TOP_DIRS: &[&str] =
    &["src/", "hal-sim/", "docs/", "scripts/", "tests/", "examples/", "reference/", "xtask/", ".ci/", ".cargo/"];
/// Files at the top level that prose cites by name alone.
const TOP_FILES: &[&str] = &[
    "Cargo.toml",
    "Cargo.lock",
    "build.rs",
    "memory.x",
    "BENCHMARKS.md",
    "README.md",
    "CHANGELOG.md",
    "Ravedude.toml",
    "rust-toolchain.toml",
    "rustfmt.toml",
    "LICENSE-MIT",
    "LICENSE-APACHE",
];

/// Written by a build or a run, never committed: `target/` (cargo), `out/`
/// (the main job), `node_modules/` (`npm ci` for the page test).
const GENERATED: &[&str] = &["target/", "out/", "node_modules/"];

/// Where comments are read: the code folders and the scripts.
const COMMENT_DIRS: &[&str] = &["src", "hal-sim", "xtask", "scripts", "examples", "tests", "reference"];

fn root() -> PathBuf {
    PathBuf::from(ROOT)
}

fn files_under(dir: &Path, exts: &[&str], out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else { return };
    for e in entries {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if p.is_dir() {
            if name != "target" && name != "node_modules" && !name.starts_with('.') {
                files_under(&p, exts, out);
            }
        } else if exts.iter().any(|x| name.ends_with(x)) {
            out.push(p);
        }
    }
}

/// README.md, CHANGELOG.md and docs/*.md.
fn markdown_files() -> Vec<PathBuf> {
    let mut v = vec![root().join("README.md"), root().join("CHANGELOG.md")];
    files_under(&root().join("docs"), &[".md"], &mut v);
    v
}

/// The comment text of a source file, line by line (`//` in Rust and
/// JavaScript, `#` in shell, TOML and scenario files), with line numbers.
fn comments(path: &Path) -> Vec<(usize, String)> {
    let text = fs::read_to_string(path).unwrap();
    let hash = path.extension().is_some_and(|x| x == "sh" || x == "toml" || x == "scn" || x == "py");
    let marker = if hash { "#" } else { "//" };
    text.lines()
        .enumerate()
        .filter_map(|(i, l)| l.find(marker).map(|at| (i + 1, l[at + marker.len()..].to_string())))
        .collect()
}

fn comment_files() -> Vec<PathBuf> {
    let mut v = Vec::new();
    for d in COMMENT_DIRS {
        files_under(&root().join(d), &[".rs", ".sh", ".toml", ".scn", ".mjs", ".py"], &mut v);
    }
    for f in ["build.rs", "Cargo.toml", "memory.x", ".cargo/config.toml", ".ci/run"] {
        v.push(root().join(f));
    }
    v
}

fn path_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '/' | '*')
}

/// The repository paths a text cites: maximal runs of path characters that
/// start at a top-level folder or name a top-level file.
fn cited_paths(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let chars: Vec<(usize, char)> = text.char_indices().collect();
    let mut i = 0;
    while i < chars.len() {
        if !path_char(chars[i].1) || (i > 0 && path_char(chars[i - 1].1)) {
            i += 1;
            continue;
        }
        let start = chars[i].0;
        let mut j = i;
        while j < chars.len() && path_char(chars[j].1) {
            j += 1;
        }
        let end = if j < chars.len() { chars[j].0 } else { text.len() };
        let tok = text[start..end].trim_end_matches(['.', ',']);
        // A sentence's or an option's neighbours: "(see src/lib.rs)", "--out=docs/y.svg".
        let preceded_by_word = i > 0 && (chars[i - 1].1 == '=' || chars[i - 1].1 == '@');
        if !preceded_by_word
            && (TOP_DIRS.iter().any(|d| tok.starts_with(d) && tok.len() >= d.len()) || TOP_FILES.contains(&tok))
        {
            out.push(tok.to_string());
        }
        i = j;
    }
    out
}

/// Markdown link targets `](target)` that are files of the repository,
/// resolved against the document's folder.
fn link_targets(doc: &Path, text: &str) -> Vec<String> {
    let dir = doc.parent().unwrap().strip_prefix(root()).unwrap().to_path_buf();
    let mut out = Vec::new();
    for (at, _) in text.match_indices("](") {
        let rest = &text[at + 2..];
        let Some(end) = rest.find(')') else { continue };
        let target = rest[..end].split('#').next().unwrap();
        if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
            continue;
        }
        let joined = dir.join(target);
        let mut parts: Vec<String> = Vec::new();
        for c in joined.components() {
            match c.as_os_str().to_str().unwrap() {
                ".." => {
                    parts.pop();
                }
                "." => {}
                s => parts.push(s.to_string()),
            }
        }
        out.push(parts.join("/"));
    }
    out
}

/// Whether `rel` (segments may hold `*`) names something under `base`.
fn exists_under(base: &Path, rel: &str) -> bool {
    let segs: Vec<&str> = rel.trim_end_matches('/').split('/').filter(|s| !s.is_empty()).collect();
    fn walk(dir: &Path, segs: &[&str]) -> bool {
        let Some((first, rest)) = segs.split_first() else { return true };
        if !first.contains('*') {
            let p = dir.join(first);
            return p.exists() && walk(&p, rest);
        }
        let (pre, post) = first.split_once('*').unwrap();
        let Ok(entries) = fs::read_dir(dir) else { return false };
        entries.flatten().any(|e| {
            let n = e.file_name().to_string_lossy().into_owned();
            n.starts_with(pre) && n.ends_with(post.trim_start_matches('*')) && walk(&e.path(), rest)
        })
    }
    walk(base, &segs)
}

fn tolerated(rel: &str) -> bool {
    GENERATED.iter().any(|g| rel.starts_with(g) || rel.contains(&format!("/{g}")))
}

/// A cited path resolves against the repository root or, in a source file,
/// against the file's crate (the nearest folder with a Cargo.toml) or folder.
fn resolves(rel: &str, from: &Path) -> bool {
    if tolerated(rel) || exists_under(&root(), rel) {
        return true;
    }
    let mut dir = from.parent();
    while let Some(d) = dir {
        if !d.starts_with(root()) {
            break;
        }
        if exists_under(d, rel) {
            return true;
        }
        if d.join("Cargo.toml").exists() {
            break;
        }
        dir = d.parent();
    }
    false
}

fn shown(p: &Path) -> String {
    p.strip_prefix(root()).unwrap().display().to_string()
}

#[test]
fn every_cited_path_exists() {
    let mut missing = Vec::new();
    let mut checked = 0;
    for doc in markdown_files() {
        let text = fs::read_to_string(&doc).unwrap();
        for (n, line) in text.lines().enumerate() {
            for p in cited_paths(line) {
                checked += 1;
                if !resolves(&p, &doc) {
                    missing.push(format!("{}:{}: {p}", shown(&doc), n + 1));
                }
            }
        }
        for p in link_targets(&doc, &text) {
            checked += 1;
            if !(tolerated(&p) || exists_under(&root(), &p)) {
                missing.push(format!("{}: link {p}", shown(&doc)));
            }
        }
    }
    for file in comment_files() {
        for (n, c) in comments(&file) {
            for p in cited_paths(&c) {
                checked += 1;
                if !resolves(&p, &file) {
                    missing.push(format!("{}:{n}: {p}", shown(&file)));
                }
            }
        }
    }
    assert!(checked > 300, "only {checked} citations found: the scan is broken");
    assert!(missing.is_empty(), "cited paths that do not exist:\n{}", missing.join("\n"));
}

/// The section numbers of docs/method.md: `## 7.` → "7", `### 7.3` → "7.3".
fn method_sections() -> BTreeSet<String> {
    let text = fs::read_to_string(root().join("docs/method.md")).unwrap();
    text.lines()
        .filter(|l| l.starts_with("## ") || l.starts_with("### "))
        .filter_map(|l| l.trim_start_matches('#').trim().split(' ').next())
        .map(|n| n.trim_end_matches('.').to_string())
        .filter(|n| n.chars().next().is_some_and(|c| c.is_ascii_digit()))
        .collect()
}

/// The section numbers a `§` at `at` cites: `§7.3`, `§3–6` (both ends),
/// `§§`-free.
fn section_numbers(text: &str, at: usize) -> Vec<String> {
    let rest = &text[at + '§'.len_utf8()..];
    let num = |s: &str| -> String {
        let n: String = s.chars().take_while(|c| c.is_ascii_digit() || *c == '.').collect();
        n.trim_end_matches('.').to_string()
    };
    let first = num(rest);
    if first.is_empty() {
        return vec![];
    }
    let mut v = vec![first.clone()];
    let after = &rest[first.len()..];
    if let Some(r) = after.strip_prefix('–').or_else(|| after.strip_prefix('-')) {
        let second = num(r);
        if !second.is_empty() {
            v.push(second);
        }
    }
    v
}

/// Each `§` that cites docs/method.md: any `§` inside it, and elsewhere one
/// that follows "method.md" (a link's closing parenthesis and spaces between).
fn method_citations(text: &str, inside_method: bool) -> Vec<(usize, Vec<String>)> {
    let mut out = Vec::new();
    for (at, _) in text.match_indices('§') {
        let cites = inside_method || {
            let before = text[..at].trim_end().trim_end_matches(')').trim_end();
            before.ends_with("method.md") || before.ends_with("method")
        };
        if cites {
            out.push((at, section_numbers(text, at)));
        }
    }
    out
}

/// The background note's name as a word (four capitals, see the test): the
/// note the method came from is not part of the repository (docs/method.md
/// replaces it).
fn cites_outside_note(line: &str) -> bool {
    line.match_indices("SPEC").any(|(at, _)| {
        let before = line[..at].chars().next_back();
        let after = line[at + 4..].chars().next();
        !before.is_some_and(|c| c.is_alphanumeric() || c == '_')
            && !after.is_some_and(|c| c.is_alphanumeric() || c == '_')
    })
}

#[test]
fn every_method_section_cited_exists() {
    let sections = method_sections();
    assert!(sections.contains("7.3") && sections.contains("11"), "{sections:?}");
    let mut bad = Vec::new();
    let mut sources: Vec<(PathBuf, Vec<(usize, String)>)> = Vec::new();
    for doc in markdown_files() {
        let text = fs::read_to_string(&doc).unwrap();
        sources.push((doc, text.lines().enumerate().map(|(i, l)| (i + 1, l.to_string())).collect()));
    }
    for file in comment_files() {
        let c = comments(&file);
        sources.push((file, c));
    }
    let mut checked = 0;
    for (file, lines) in &sources {
        let inside = file.ends_with("docs/method.md");
        for (n, line) in lines {
            if cites_outside_note(line) {
                bad.push(format!("{}:{n}: cites the SPEC note, which is not in the repository", shown(file)));
            }
            for (_, nums) in method_citations(line, inside) {
                for s in nums {
                    checked += 1;
                    if !sections.contains(&s) {
                        bad.push(format!("{}:{n}: method.md §{s} does not exist", shown(file)));
                    }
                }
            }
        }
    }
    assert!(checked > 20, "only {checked} section citations found: the scan is broken");
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// The reason tags docs/avr-traps.md defines: its table rows that start with
/// a backticked `avr-trap: <tag>` or `reason: <tag>`.
fn defined_tags() -> BTreeSet<String> {
    let text = fs::read_to_string(root().join("docs/avr-traps.md")).unwrap();
    text.lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split('`').next())
        .filter(|t| t.starts_with("avr-trap: ") || t.starts_with("reason: "))
        .map(str::to_string)
        .collect()
}

#[test]
fn every_inline_never_has_a_defined_reason() {
    let tags = defined_tags();
    assert!(tags.len() >= 4, "docs/avr-traps.md defines {tags:?}");
    let mut files = Vec::new();
    files_under(&root().join("src"), &[".rs"], &mut files);
    files_under(&root().join("examples"), &[".rs"], &mut files);
    let mut bad = Vec::new();
    let mut used = BTreeSet::new();
    for f in &files {
        for (n, line) in fs::read_to_string(f).unwrap().lines().enumerate() {
            let code = line.split("//").next().unwrap();
            if !code.contains("#[inline(never)]") {
                continue;
            }
            let tag = line.split_once("// ").map(|(_, t)| t.trim().to_string());
            match tag {
                Some(t) if tags.contains(&t) => {
                    used.insert(t);
                }
                other => bad.push(format!("{}:{}: {:?}", shown(f), n + 1, other)),
            }
        }
    }
    assert!(bad.is_empty(), "#[inline(never)] without a tag of docs/avr-traps.md:\n{}", bad.join("\n"));
    let unused: Vec<_> = tags.difference(&used).collect();
    assert!(unused.is_empty(), "docs/avr-traps.md defines tags no code uses: {unused:?}");
}

#[test]
fn the_readme_is_a_front_page() {
    let text = fs::read_to_string(root().join("README.md")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines.len() < 300, "README.md has {} lines (under 300: reference material goes to docs/)", lines.len());
    // The first screen after the title is the quick start, with its three paths.
    let first: String = lines.iter().skip(1).take(30).copied().collect::<Vec<_>>().join("\n");
    for needle in ["## Quick start", "scripts/run.sh --live", "cargo install --path hal-sim/armsim", "STOP"] {
        assert!(first.contains(needle), "the README's first 30 lines lack {needle:?}");
    }
    // Every document in docs/ is linked from the README or another document.
    let mut linked = BTreeSet::new();
    for doc in markdown_files() {
        let t = fs::read_to_string(&doc).unwrap();
        linked.extend(link_targets(&doc, &t).into_iter().filter(|p| p != &shown(&doc)));
    }
    let mut docs = Vec::new();
    files_under(&root().join("docs"), &[".md"], &mut docs);
    let orphans: Vec<String> = docs.iter().map(|d| shown(d)).filter(|d| !linked.contains(d)).collect();
    assert!(orphans.is_empty(), "documents nothing links to: {orphans:?}");
}

#[test]
fn the_scanners_see_what_they_should() {
    assert_eq!(
        cited_paths(
            "see `src/app/mod.rs`, hal-sim/twin/tests/scenarios/*.scn and Cargo.toml. Not touch::map or x/src/y"
        ),
        ["src/app/mod.rs", "hal-sim/twin/tests/scenarios/*.scn", "Cargo.toml"]
    );
    assert_eq!(section_numbers("§3–6", 0), ["3", "6"]);
    assert_eq!(section_numbers("§7.3.", 0), ["7.3"]);
    let cites = method_citations("[method](docs/method.md) §8.1 and issue #14 §2", false);
    assert_eq!(cites.len(), 1);
    assert_eq!(cites[0].1, ["8.1"]);
    assert!(cites_outside_note("as SPEC §5 says") && cites_outside_note("the SPEC's G"));
    assert!(!cites_outside_note("SPECIAL, INSPECT"));
    assert!(exists_under(&root(), "hal-sim/twin/tests/scenarios/*.scn"));
    assert!(!exists_under(&root(), "src/touch_filter.rs"));
    assert!(
        tolerated("target/avr-none/release/touch-arm.elf") && tolerated("hal-sim/bench/tests/browser/node_modules/x")
    );
}
