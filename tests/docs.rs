//! The user guide cannot go stale: every `critspeed` command and option and every study key
//! the README and `docs/*.md` name exists in the code, and every command, option and study key
//! of the code is named in them; every relative link and anchor resolves; every `sh` example
//! runs (or is marked as not run); and no tracked file refers to a folder outside the
//! repository.
//!
//! The lists come from the code, not from this file: the commands and options from clap's
//! definition ([`critspeed::cli::Cli`]), the study keys from the serde schema
//! ([`critspeed::study::keys::study_keys`]). A new subcommand, option or schema field therefore
//! fails this test until a page documents it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

use clap::CommandFactory;

mod common;
use common::root;

#[path = "docs/links.rs"]
mod links;
#[path = "docs/snippets.rs"]
mod snippets;

/// File extensions of output and input files: `sweep.csv` is a file, not a study key.
const FILE_EXTENSIONS: &[&str] = &["csv", "svg", "json", "toml", "md", "rs", "dat", "txt", "py"];

/// The README and every page of the guide, as (path relative to the root, text).
fn pages() -> Vec<(String, String)> {
    let mut files = vec![root().join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .expect("docs/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    files
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).expect("read page");
            let rel = p
                .strip_prefix(root())
                .expect("under the root")
                .display()
                .to_string();
            (rel, text)
        })
        .collect()
}

/// A fenced code block: its language (the info string's first word), the info string's other
/// words (`long`), its text and the line of its opening fence (from 1).
struct Block {
    lang: String,
    flags: Vec<String>,
    text: String,
    line: usize,
}

/// Fenced code blocks, and the prose with the blocks removed.
fn split(text: &str) -> (Vec<Block>, String) {
    let (mut blocks, mut prose) = (Vec::new(), String::new());
    let mut open: Option<Block> = None;
    for (number, line) in text.lines().enumerate() {
        let fence = line.trim_start().strip_prefix("```");
        match (&mut open, fence) {
            (None, Some(info)) => {
                let mut words = info
                    .split(|c: char| c.is_whitespace() || c == ',')
                    .filter(|w| !w.is_empty())
                    .map(str::to_string);
                open = Some(Block {
                    lang: words.next().unwrap_or_default(),
                    flags: words.collect(),
                    text: String::new(),
                    line: number + 1,
                })
            }
            (Some(_), Some(_)) => blocks.extend(open.take()),
            (Some(b), None) => {
                b.text += line;
                b.text.push('\n');
            }
            (None, None) => {
                prose += line;
                prose.push('\n');
            }
        }
    }
    (blocks, prose)
}

/// Inline code spans of the prose.
fn spans(prose: &str) -> Vec<String> {
    prose
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// The code the guide shows: inline spans and the lines of shell-like blocks.
fn code_lines(page: &str) -> Vec<String> {
    let (blocks, prose) = split(page);
    let mut lines = spans(&prose);
    for b in blocks {
        if ["", "sh", "bash", "console", "text", "shell"].contains(&b.lang.as_str()) {
            lines.extend(b.text.lines().map(str::to_string));
        }
    }
    lines
}

/// Every `critspeed <command>` in `line`, with the `--options` that follow it (up to the next
/// `critspeed`).
fn invocations(line: &str) -> Vec<(String, Vec<String>)> {
    let words: Vec<&str> = line
        .split(|c: char| c.is_whitespace() || "\"'()[]|`".contains(c))
        .filter(|w| !w.is_empty())
        .collect();
    let mut out: Vec<(String, Vec<String>)> = Vec::new();
    for (k, w) in words.iter().enumerate() {
        if *w == "critspeed" {
            if let Some(cmd) = words.get(k + 1) {
                if cmd.chars().all(|c| c.is_ascii_lowercase() || c == '-')
                    && cmd.starts_with(|c: char| c.is_ascii_lowercase())
                {
                    out.push((cmd.to_string(), Vec::new()));
                }
            }
        } else if let (Some(opt), Some(last)) = (w.strip_prefix("--"), out.last_mut()) {
            let name = opt.split('=').next().unwrap_or(opt);
            if name.starts_with(|c: char| c.is_ascii_lowercase()) {
                last.1.push(name.to_string());
            }
        }
    }
    out
}

/// The commands and the long options each accepts (with the global ones), from clap.
fn cli() -> BTreeMap<String, BTreeSet<String>> {
    let cmd = critspeed::cli::Cli::command();
    let global: BTreeSet<String> = cmd
        .get_arguments()
        .filter_map(|a| a.get_long().map(str::to_string))
        .chain(["help".to_string(), "version".to_string()])
        .collect();
    cmd.get_subcommands()
        .map(|s| {
            let mut opts = global.clone();
            opts.extend(
                s.get_arguments()
                    .filter_map(|a| a.get_long().map(str::to_string)),
            );
            (s.get_name().to_string(), opts)
        })
        .collect()
}

/// `wheelset.{mass, yaw_inertia}` → `wheelset.mass`, `wheelset.yaw_inertia`.
fn expand_braces(token: &str) -> Vec<String> {
    match (token.find('{'), token.rfind('}')) {
        (Some(a), Some(b)) if a < b => token[a + 1..b]
            .split(',')
            .map(|part| format!("{}{}{}", &token[..a], part.trim(), &token[b + 1..]))
            .collect(),
        _ => vec![token.to_string()],
    }
}

/// `sweep.axes[0].key` → `sweep.axes[].key`.
fn normalise(key: &str) -> String {
    let mut out = String::new();
    let mut in_index = false;
    for c in key.chars() {
        match c {
            '[' => {
                in_index = true;
                out.push('[');
            }
            ']' => {
                in_index = false;
                out.push(']');
            }
            _ if in_index => {}
            _ => out.push(c),
        }
    }
    out
}

/// The study keys a page names: every key of its TOML blocks, every dotted key in an inline
/// span (`contact.conicity`, `wheelset.{mass, yaw_inertia}`) whose first part is a top-level
/// section, and every section in brackets (`[sweep]`).
fn named_keys(page: &str, top: &BTreeSet<String>) -> Result<BTreeSet<String>, String> {
    let (blocks, prose) = split(page);
    let mut keys = BTreeSet::new();
    for b in blocks.iter().filter(|b| b.lang == "toml") {
        let t: toml::Table = toml::from_str(&b.text)
            .map_err(|e| format!("a toml block does not parse: {e}\n{}", b.text))?;
        keys.extend(critspeed::study::keys::keys_of(&t));
    }
    for span in spans(&prose) {
        let span = span.trim();
        if let Some(section) = span.strip_prefix('[').and_then(|s| s.strip_suffix(']')) {
            if section
                .chars()
                .all(|c| c.is_ascii_lowercase() || c == '_' || c == '.')
                && top.contains(section.split('.').next().unwrap_or(section))
            {
                keys.insert(section.to_string());
            }
            continue;
        }
        let token = span.split(" = ").next().unwrap_or(span).trim();
        for key in expand_braces(token) {
            let key = normalise(&key);
            let Some((first, _)) = key.split_once(['.', '[']) else {
                continue;
            };
            let last = key.rsplit('.').next().unwrap_or(&key);
            let is_key = key
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "._[]".contains(c));
            if is_key && top.contains(first) && !FILE_EXTENSIONS.contains(&last) {
                keys.insert(key);
            }
        }
    }
    Ok(keys)
}

#[test]
fn every_command_and_option_named_in_the_guide_exists() {
    let cli = cli();
    let mut bad = Vec::new();
    for (path, text) in pages() {
        for line in code_lines(&text) {
            for (cmd, opts) in invocations(&line) {
                match cli.get(&cmd) {
                    None => bad.push(format!(
                        "{path}: `critspeed {cmd}` is not a command ({line})"
                    )),
                    Some(known) => {
                        bad.extend(opts.iter().filter(|o| !known.contains(*o)).map(|o| {
                            format!("{path}: critspeed {cmd} has no option --{o} ({line})")
                        }))
                    }
                }
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn every_command_and_option_of_the_cli_is_documented() {
    let mut used: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (_, text) in pages() {
        for line in code_lines(&text) {
            for (cmd, opts) in invocations(&line) {
                used.entry(cmd).or_default().extend(opts);
            }
        }
    }
    let mut missing = Vec::new();
    for (cmd, opts) in cli() {
        match used.get(&cmd) {
            None => missing.push(format!("`critspeed {cmd}` is named in no page")),
            Some(seen) => missing.extend(
                opts.iter()
                    .filter(|o| {
                        !seen.contains(*o) && !["help", "version", "out"].contains(&o.as_str())
                    })
                    .map(|o| format!("`critspeed {cmd} --{o}` is shown in no page")),
            ),
        }
    }
    // the global option, once
    let all = pages().into_iter().map(|(_, t)| t).collect::<String>();
    if !all.contains("--out DIR") {
        missing.push("the global option `--out DIR` is documented nowhere".into());
    }
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

#[test]
fn every_study_key_named_in_the_guide_exists_and_every_key_is_named() {
    let keys: BTreeSet<String> = critspeed::study::keys::study_keys()
        .expect("the schema traces")
        .into_iter()
        .collect();
    let top: BTreeSet<String> = critspeed::study::keys::top_level_keys()
        .expect("the schema traces")
        .into_iter()
        .collect();
    let mut named = BTreeSet::new();
    let mut bad = Vec::new();
    // a sweep.csv column is a key with its SI unit appended: `<key>_n_per_m`
    let column = |k: &str| {
        keys.iter().any(|key| {
            k.strip_prefix(key.as_str())
                .is_some_and(|u| u.starts_with('_'))
        })
    };
    for (path, text) in pages() {
        match named_keys(&text, &top) {
            Ok(k) => {
                bad.extend(
                    k.iter()
                        .filter(|k| !keys.contains(*k) && !column(k))
                        .map(|k| format!("{path}: `{k}` is not a study key")),
                );
                named.extend(k);
            }
            Err(e) => bad.push(format!("{path}: {e}")),
        }
    }
    bad.extend(
        keys.iter()
            .filter(|k| !named.contains(*k))
            .map(|k| format!("study key `{k}` is documented in no page")),
    );
    assert!(bad.is_empty(), "{}", bad.join("\n"));
    assert!(keys.len() > 60, "{} keys traced", keys.len());
}

/// `.ci/slurm` submits the README's job script; the clusters page shows the same script.
#[test]
fn the_job_script_is_the_same_in_the_readme_and_the_clusters_page() {
    let script = |path: &str| {
        let text = std::fs::read_to_string(root().join(path)).expect("read");
        let (blocks, _) = split(&text);
        blocks
            .into_iter()
            .find(|b| b.text.starts_with("#!/bin/bash") && b.text.contains("#SBATCH"))
            .map(|b| b.text)
            .unwrap_or_else(|| panic!("{path} has no job script"))
    };
    let readme = script("README.md");
    assert_eq!(readme, script("docs/clusters.md"));
    assert!(readme.contains("--shard-from-env --shards 16") && readme.contains("--array=0-15"));
}

#[test]
fn the_readme_fits_on_a_screen_or_two() {
    let text = std::fs::read_to_string(root().join("README.md")).expect("README.md");
    let n = text.lines().count();
    assert!(
        n < 200,
        "README.md has {n} lines; the reference belongs in docs/"
    );
    for command in ["cargo run --release -- run", "cargo test --release"] {
        assert!(
            text.contains(&format!("\n{command}\n")),
            "quick start: {command}"
        );
    }
}

#[test]
fn the_scanners_find_what_they_should() {
    // the helpers themselves, on text whose answer is known by construction
    assert_eq!(
        invocations("sbatch --wrap \"critspeed merge s.toml --partial\" | critspeed run --out o"),
        vec![
            ("merge".to_string(), vec!["partial".to_string()]),
            ("run".to_string(), vec!["out".to_string()])
        ]
    );
    assert!(invocations("import critspeed; critspeed.linear(x)").is_empty());
    let top: BTreeSet<String> = ["sweep", "wheelset", "contact"].map(String::from).into();
    let page =
        "`wheelset.{mass, rolling_radius}`, `sweep.csv`, `[sweep]`, `contact.conicity = 0.05`\n\
                ```toml\n[sweep]\naxes = [ { key = \"a\", from = 1, to = 2, count = 2 } ]\n```\n";
    let keys = named_keys(page, &top).expect("parses");
    let want: BTreeSet<String> = [
        "wheelset.mass",
        "wheelset.rolling_radius",
        "sweep",
        "contact.conicity",
        "sweep.axes",
        "sweep.axes[].key",
        "sweep.axes[].from",
        "sweep.axes[].to",
        "sweep.axes[].count",
    ]
    .map(String::from)
    .into();
    assert_eq!(keys, want);
}
