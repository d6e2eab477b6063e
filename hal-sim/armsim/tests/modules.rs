//! armsim's modules import each other without a cycle: each larger
//! subcommand (`path`, `paper`) and the command line (`cli`) take the
//! shared argument types from `opts`, never from each other, so a change to
//! one subcommand does not reach back into the others. The rule is read
//! from the sources (`use crate::m` and `crate::m::` paths), as the core
//! crate's `tests/layers.rs` reads its layers.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;

/// Module name → the crate modules its file (and its folder's files) name.
fn imports() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut modules = BTreeMap::new();
    for entry in fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        let Some(name) = path.file_stem().and_then(|s| s.to_str()).map(str::to_owned) else { continue };
        if path.extension().is_none_or(|e| e != "rs") || name == "lib" || name == "main" {
            continue;
        }
        let mut text = fs::read_to_string(&path).unwrap();
        if let Ok(dir) = fs::read_dir(src.join(&name)) {
            for f in dir {
                text.push_str(&fs::read_to_string(f.unwrap().path()).unwrap());
            }
        }
        modules.insert(name, text);
    }
    let names: Vec<String> = modules.keys().cloned().collect();
    modules
        .iter()
        .map(|(m, text)| {
            let used = names
                .iter()
                .filter(|n| {
                    *n != m
                        && (text.contains(&format!("crate::{n}::"))
                            || text.contains(&format!("crate::{n};"))
                            || text.contains(&format!("crate::{n}::{{")))
                })
                .cloned()
                .collect();
            (m.clone(), used)
        })
        .collect()
}

/// A cycle through `m`, if any (depth-first, the path so far in `stack`).
fn cycle(
    g: &BTreeMap<String, BTreeSet<String>>,
    m: &str,
    stack: &mut Vec<String>,
    done: &mut BTreeSet<String>,
) -> Option<Vec<String>> {
    if let Some(i) = stack.iter().position(|s| s == m) {
        let mut c = stack[i..].to_vec();
        c.push(m.to_owned());
        return Some(c);
    }
    if done.contains(m) {
        return None;
    }
    stack.push(m.to_owned());
    for n in g.get(m).into_iter().flatten() {
        if let Some(c) = cycle(g, n, stack, done) {
            return Some(c);
        }
    }
    stack.pop();
    done.insert(m.to_owned());
    None
}

#[test]
fn no_module_imports_in_a_cycle() {
    let g = imports();
    // The rule has something to check: the modules this test is about.
    for m in ["cli", "opts", "path", "paper"] {
        assert!(g.contains_key(m), "module {m} not found in src/");
    }
    assert!(g["paper"].contains("path") && g["cli"].contains("opts"), "imports not read: {g:?}");
    let mut done = BTreeSet::new();
    for m in g.keys() {
        if let Some(c) = cycle(&g, m, &mut Vec::new(), &mut done) {
            panic!("armsim modules import each other in a cycle: {}", c.join(" -> "));
        }
    }
}

#[test]
fn the_cycle_check_fires() {
    let mut g = BTreeMap::new();
    g.insert("cli".to_owned(), BTreeSet::from(["paper".to_owned()]));
    g.insert("paper".to_owned(), BTreeSet::from(["cli".to_owned()]));
    let c = cycle(&g, "cli", &mut Vec::new(), &mut BTreeSet::new());
    assert_eq!(c, Some(vec!["cli".to_owned(), "paper".to_owned(), "cli".to_owned()]));
}
