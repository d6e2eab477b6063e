//! The core crate's module graph: lower layers never import higher ones, and
//! no two modules import each other, directly or around a loop.
//!
//! The graph is read from the sources: every `crate::a::b…` path and every
//! `super::…` path in code (comments and doc comments are left out, so doc
//! links do not count) is an edge from the file's module to the deepest
//! module the path names. A module and its own submodules are one unit for
//! the cycle check (a folder's `mod.rs` declaring its children and the
//! children using their parent's items is the normal Rust shape), but every
//! other loop fails the test, naming the modules on it.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// The pipeline's layers, lowest first. A module may import its own layer's
/// module (itself) and any lower layer, never a higher one nor a sibling of
/// the same rank.
const LAYERS: &[(&str, u8)] = &[
    ("text", 0),
    ("math", 1),
    ("seam", 2),
    ("touch", 3),
    ("geometry", 3),
    ("motion", 4),
    ("servo", 5),
    ("config", 6),
    ("protocol", 7),
    ("ui", 8),
    ("app", 9),
    ("board", 10),
];

fn rank(top: &str) -> Option<u8> {
    LAYERS.iter().find(|(n, _)| *n == top).map(|(_, r)| *r)
}

/// Every library source file (binaries under `src/bin` and `src/main.rs` use
/// the crate from outside and are not part of the graph).
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            if p.file_name().unwrap() != "bin" {
                sources(&p, out);
            }
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// `src/motion/planner/duration.rs` → `["motion", "planner", "duration"]`;
/// `mod.rs` names its folder; `lib.rs` is the root (empty path).
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap();
    let mut parts: Vec<String> = rel.iter().map(|s| s.to_string_lossy().into_owned()).collect();
    let last = parts.pop().unwrap();
    let stem = last.trim_end_matches(".rs");
    if stem != "mod" && stem != "lib" {
        parts.push(stem.to_string());
    }
    parts
}

/// The code of a file without comments (line comments, doc comments and
/// block comments); string literals are kept, which is harmless here.
fn code(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find("/") {
        let (before, after) = rest.split_at(i);
        out.push_str(before);
        if after.starts_with("//") {
            rest = after.find('\n').map_or("", |j| &after[j..]);
        } else if after.starts_with("/*") {
            rest = after.find("*/").map_or("", |j| &after[j + 2..]);
        } else {
            out.push('/');
            rest = &after[1..];
        }
    }
    out.push_str(rest);
    out
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The module paths a file's code refers to, resolved to absolute paths
/// (`crate::x::y` and `super::x`, including inside `use a::{b, c}` groups,
/// whose first segment is enough: an edge goes to the deepest *module* the
/// path names, found later against the set of modules).
fn references(module: &[String], is_mod_file: bool, text: &str) -> Vec<Vec<String>> {
    let code = code(text);
    let mut refs = Vec::new();
    for (kw, base) in [
        ("crate::", Vec::new()),
        ("super::", {
            // `super` in `a/b.rs` (module a::b) is `a`; in `a/b/mod.rs` (module
            // a::b) it is `a` as well.
            let _ = is_mod_file;
            module[..module.len().saturating_sub(1)].to_vec()
        }),
    ] {
        let mut from = 0;
        while let Some(i) = code[from..].find(kw) {
            let at = from + i;
            from = at + kw.len();
            if at > 0 && code[..at].chars().next_back().is_some_and(|c| is_ident(c) || c == ':') {
                // `$crate::` in macros, or `super::super::` handled below.
                if !code[..at].ends_with("super::") {
                    continue;
                }
            }
            let tail: String = code[from..].chars().take_while(|c| is_ident(*c) || *c == ':').collect();
            let mut path = base.clone();
            path.extend(tail.split("::").filter(|s| !s.is_empty() && *s != "super").map(str::to_string));
            let after = &code[from + tail.len()..];
            if tail.ends_with("::") && after.starts_with('{') {
                // A `use` group: one reference per item, by its leading path.
                let mut depth = 0;
                let group: String = after
                    .chars()
                    .take_while(|c| {
                        depth += match c {
                            '{' => 1,
                            '}' => -1,
                            _ => 0,
                        };
                        depth > 0
                    })
                    .collect();
                let mut item = String::new();
                let mut d = 0;
                for c in group[1..].chars().chain([',']) {
                    match c {
                        '{' => d += 1,
                        '}' => d -= 1,
                        ',' if d == 0 => {
                            let lead: String = item.trim().chars().take_while(|c| is_ident(*c) || *c == ':').collect();
                            let mut p = path.clone();
                            p.extend(lead.split("::").filter(|s| !s.is_empty() && *s != "self").map(str::to_string));
                            refs.push(p);
                            item.clear();
                            continue;
                        }
                        _ => {}
                    }
                    if d == 0 {
                        item.push(c);
                    }
                }
            } else {
                refs.push(path);
            }
        }
    }
    refs
}

#[test]
fn modules_import_only_lower_layers_and_form_no_cycle() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    files.retain(|f| f.file_name().unwrap() != "main.rs");
    let modules: BTreeSet<Vec<String>> = files.iter().map(|f| module_of(&src, f)).collect();

    // Edges between modules (deepest existing module of each reference).
    let mut edges: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
    let mut upward = Vec::new();
    for f in &files {
        let m = module_of(&src, f);
        let is_mod = f.file_name().unwrap() == "mod.rs";
        let text = fs::read_to_string(f).unwrap();
        for r in references(&m, is_mod, &text) {
            let mut target = r.clone();
            while !target.is_empty() && !modules.contains(&target) {
                target.pop();
            }
            if target.is_empty() || target == m {
                continue;
            }
            if let (Some(a), Some(b)) = (m.first(), target.first()) {
                let (ra, rb) = (rank(a), rank(b));
                assert!(ra.is_some(), "module `{a}` has no layer in LAYERS: add it");
                assert!(rb.is_some(), "module `{b}` has no layer in LAYERS: add it");
                if a != b && rb >= ra {
                    upward.push(format!("{} → {}", m.join("::"), target.join("::")));
                }
            }
            edges.entry(m.clone()).or_default().insert(target);
        }
    }
    assert!(upward.is_empty(), "imports from a lower layer to a higher or equal one:\n{}", upward.join("\n"));

    // Cycles: an edge between a module and its own ancestor or descendant is
    // not part of a loop (declaration and use of the parent's items).
    let related = |a: &[String], b: &[String]| a.starts_with(b) || b.starts_with(a);
    let mut cycles = Vec::new();
    for start in edges.keys() {
        // Depth-first search for a path back to `start`.
        let mut stack = vec![(start.clone(), vec![start.clone()])];
        let mut seen = BTreeSet::new();
        while let Some((node, path)) = stack.pop() {
            for next in edges.get(&node).into_iter().flatten() {
                if related(&node, next) {
                    continue;
                }
                if next == start {
                    let names: Vec<String> = path.iter().map(|p| p.join("::")).collect();
                    cycles.push(format!("{} → {}", names.join(" → "), start.join("::")));
                } else if seen.insert(next.clone()) {
                    let mut p = path.clone();
                    p.push(next.clone());
                    stack.push((next.clone(), p));
                }
            }
        }
    }
    assert!(cycles.is_empty(), "import cycles between modules:\n{}", cycles.join("\n"));
    // The graph was really read: the pipeline's known edges are in it.
    let has = |a: &str, b: &str| {
        let a: Vec<String> = a.split("::").map(str::to_string).collect();
        let b: Vec<String> = b.split("::").map(str::to_string).collect();
        edges.get(&a).is_some_and(|s| s.contains(&b))
    };
    assert!(has("geometry::ik", "math::real"));
    assert!(has("motion::planner::duration", "motion::planner::peak_rate"));
    assert!(has("protocol::command", "config::settings"));
}

#[test]
fn the_checker_sees_an_upward_import_and_a_cycle() {
    // The reference reader on hand-written sources: a `use` group, a path in
    // an expression, `super`, and a doc link that must not count.
    let m: Vec<String> = vec!["motion".into(), "zat".into()];
    let refs = references(
        &m,
        false,
        "//! see [`crate::app::App`]\nuse crate::servo::{map::Joint, track};\nfn f() { super::laws::x(); crate::math::real::R::ONE; }\n",
    );
    let flat: Vec<String> = refs.iter().map(|r| r.join("::")).collect();
    assert_eq!(flat, ["servo::map::Joint", "servo::track", "math::real::R::ONE", "motion::laws::x"]);
    assert!(rank("servo") > rank("motion"), "servo from motion is upward");
}
