//! Every command the docs show still parses: each line of a fenced code
//! block in README.md and docs/*.md that starts with `armsim ` (or `$ armsim
//! `) goes through armsim's own clap definition (`armsim::cli::Cli`),
//! and each `scripts/run.sh …` through the binary run.sh starts
//! (`touch-arm-live` after `--live`, else `touch-arm-sim`) with
//! [`armsim::args::CHECK_ARGS`] set, so it parses and exits without
//! simulating; a `--finger FILE` names a file of the repository that parses
//! as a finger script. (The paths and sections the docs cite: the core crate's
//! `tests/docs.rs`.)

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use armsim::cli::Cli;
use clap::error::ErrorKind;
use clap::Parser;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// README.md and docs/*.md.
fn documents() -> Vec<PathBuf> {
    let mut v = vec![root().join("README.md")];
    let mut docs: Vec<PathBuf> = fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    v.extend(docs);
    v
}

/// (document, line number, line) of every line inside a fenced code block.
fn code_lines() -> Vec<(String, usize, String)> {
    let mut out = Vec::new();
    for doc in documents() {
        let name = doc.file_name().unwrap().to_string_lossy().into_owned();
        let mut inside = false;
        for (i, line) in fs::read_to_string(&doc).unwrap().lines().enumerate() {
            if line.trim_start().starts_with("```") {
                inside = !inside;
            } else if inside {
                out.push((name.clone(), i + 1, line.trim().to_string()));
            }
        }
    }
    out
}

/// Shell words of a command line: a `#` comment dropped, single and double
/// quotes honoured (no expansion: the docs' commands need none).
fn words(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quote: Option<char> = None;
    let mut any = false;
    for c in line.chars() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => cur.push(c),
            (None, '\'' | '"') => {
                quote = Some(c);
                any = true;
            }
            (None, '#') if cur.is_empty() && !any => break,
            (None, c) if c.is_whitespace() => {
                if any || !cur.is_empty() {
                    out.push(std::mem::take(&mut cur));
                    any = false;
                }
            }
            (None, c) => cur.push(c),
        }
    }
    if any || !cur.is_empty() {
        out.push(cur);
    }
    out
}

#[test]
fn the_word_splitter_drops_comments_and_keeps_quotes() {
    assert_eq!(words("armsim plan --raw 700,600   # a comment"), ["armsim", "plan", "--raw", "700,600"]);
    assert_eq!(words("scripts/run.sh --xy -0.5,0.3 'a b'"), ["scripts/run.sh", "--xy", "-0.5,0.3", "a b"]);
}

#[test]
fn documented_armsim_commands_parse() {
    let mut checked = 0;
    let mut bad = Vec::new();
    for (doc, n, line) in code_lines() {
        let line = line.strip_prefix("$ ").unwrap_or(&line);
        if !line.starts_with("armsim ") {
            continue;
        }
        checked += 1;
        match Cli::try_parse_from(words(line)) {
            Ok(_) => {}
            Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => {}
            Err(e) => bad.push(format!("{doc}:{n}: {line}\n  {}", e.render().to_string().lines().next().unwrap())),
        }
    }
    assert!(checked >= 5, "only {checked} armsim commands found in the docs' code blocks");
    assert!(bad.is_empty(), "documented armsim commands that no longer parse:\n{}", bad.join("\n"));
}

#[test]
fn documented_main_job_and_live_bench_commands_parse() {
    let mut checked = [0, 0];
    let mut bad = Vec::new();
    for (doc, n, line) in code_lines() {
        let line = line.strip_prefix("$ ").unwrap_or(&line);
        if !line.starts_with("scripts/run.sh") {
            continue;
        }
        let w = words(line);
        let (bin, args, k) = match w.get(1).map(String::as_str) {
            Some("--live") => (env!("CARGO_BIN_EXE_touch-arm-live"), &w[2..], 1),
            _ => (env!("CARGO_BIN_EXE_touch-arm-sim"), &w[1..], 0),
        };
        checked[k] += 1;
        // A documented finger script exists and parses (docs/simulation.md).
        if let Some(i) = args.iter().position(|a| a == "--finger") {
            let file = args.get(i + 1).map(|f| root().join(f));
            match file.as_ref().map(|f| fs::read_to_string(f).map_err(|e| e.to_string())) {
                Some(Ok(text)) => {
                    if let Err(e) = hal_sim::finger::FingerScript::parse_csv(&text) {
                        bad.push(format!("{doc}:{n}: {line}\n  the finger script does not parse: {e}"));
                    }
                }
                Some(Err(e)) => bad.push(format!("{doc}:{n}: {line}\n  the finger script: {e}")),
                None => bad.push(format!("{doc}:{n}: {line}\n  --finger without a file")),
            }
        }
        let out = Command::new(bin).args(args).env(armsim::args::CHECK_ARGS, "1").output().unwrap();
        if !out.status.success() {
            bad.push(format!("{doc}:{n}: {line}\n  {}", String::from_utf8_lossy(&out.stderr).trim()));
        }
    }
    assert!(checked[0] >= 5 && checked[1] >= 1, "too few scripts/run.sh lines found: {checked:?}");
    assert!(bad.is_empty(), "documented scripts/run.sh commands that no longer parse:\n{}", bad.join("\n"));
}

/// The parse-only switch is no rubber stamp: a bad argument still fails.
#[test]
fn the_parse_only_switch_still_refuses_bad_arguments() {
    let sim = Command::new(env!("CARGO_BIN_EXE_touch-arm-sim"))
        .args(["--xy", "2,2"])
        .env(armsim::args::CHECK_ARGS, "1")
        .output()
        .unwrap();
    assert_eq!(sim.status.code(), Some(2));
    let live = Command::new(env!("CARGO_BIN_EXE_touch-arm-live"))
        .args(["--port", "x"])
        .env(armsim::args::CHECK_ARGS, "1")
        .output()
        .unwrap();
    assert!(!live.status.success());
    assert!(Cli::try_parse_from(["armsim", "traj", "--frobnicate"]).is_err());
}
