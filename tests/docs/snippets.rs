//! Every `sh` block of the README and the guide runs: its `critspeed …` lines (and
//! `cargo run --release -- …`, the same program) run in order against the binary this test
//! was built with, from the repository's root, with `--out` pointing at a scratch folder of
//! the block, and must exit 0. A block whose info string has the word `long` (```` ```sh long ````)
//! is not run, nor is a command on the line after a comment `# long: reason`: they take more
//! than a minute, need a cluster, or install or run other software. Any other line fails the
//! test, so an example is either run or marked.

use std::path::PathBuf;
use std::process::Command;
use std::sync::Mutex;

use super::{pages, split};
use crate::common::{root, scratch};

/// One runnable block: where it is, and the argument lists of its commands.
struct Script {
    place: String,
    commands: Vec<Vec<String>>,
}

/// Words of a command line, with `'…'` and `"…"` quoting; `None` when it holds shell syntax
/// the test does not run (pipes, redirections, variables, several commands).
fn words(line: &str) -> Option<Vec<String>> {
    let (mut out, mut word, mut quote, mut any) = (Vec::new(), String::new(), None, false);
    for c in line.chars() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => word.push(c),
            (None, '\'' | '"') => {
                quote = Some(c);
                any = true;
            }
            (None, c) if c.is_whitespace() => {
                if any || !word.is_empty() {
                    out.push(std::mem::take(&mut word));
                }
                any = false;
            }
            (None, '|' | '&' | ';' | '<' | '>' | '$' | '`' | '(' | ')' | '*') => return None,
            (None, c) => word.push(c),
        }
    }
    if quote.is_some() {
        return None;
    }
    if any || !word.is_empty() {
        out.push(word);
    }
    Some(out)
}

/// The arguments of `critspeed ARGS` or `cargo run --release -- ARGS`.
fn critspeed_args(w: &[String]) -> Option<Vec<String>> {
    match w {
        [first, rest @ ..] if first == "critspeed" => Some(rest.to_vec()),
        [c, r, rel, dash, rest @ ..]
            if c == "cargo" && r == "run" && rel == "--release" && dash == "--" =>
        {
            Some(rest.to_vec())
        }
        _ => None,
    }
}

/// The scripts of a page, and the lines that are neither run nor marked.
fn scripts(path: &str, text: &str) -> (Vec<Script>, Vec<String>) {
    let (blocks, _) = split(text);
    let (mut out, mut bad) = (Vec::new(), Vec::new());
    for b in blocks.iter().filter(|b| b.lang == "sh") {
        if b.flags.iter().any(|f| f == "long") {
            continue;
        }
        let mut commands = Vec::new();
        let mut skip_next = false;
        for (k, line) in b.text.lines().enumerate() {
            let line = line.trim();
            let place = format!("{path}:{}", b.line + 1 + k);
            if line.is_empty() {
                continue;
            }
            if let Some(comment) = line.strip_prefix('#') {
                skip_next |= comment.trim_start().starts_with("long:");
                continue;
            }
            if std::mem::take(&mut skip_next) {
                continue;
            }
            let command = line.split(" #").next().unwrap_or(line);
            match words(command).as_deref().and_then(critspeed_args) {
                Some(args) => commands.push(args),
                None => bad.push(format!(
                    "{place}: `{line}` is not a critspeed command this test can run; mark it \
                     (`# long: reason` on the line before, or the block `sh long`) or make the \
                     block `text`"
                )),
            }
        }
        out.push(Script {
            place: format!("{path}:{}", b.line),
            commands,
        });
    }
    (out, bad)
}

/// Runs one script in its own scratch folder; the failures.
fn run(script: &Script, n: usize) -> Vec<String> {
    let out: PathBuf = scratch(&format!("snippet-{n}"));
    let mut bad = Vec::new();
    for args in &script.commands {
        let result = Command::new(env!("CARGO_BIN_EXE_critspeed"))
            .args(args)
            .arg("--out")
            .arg(&out)
            .current_dir(root())
            .output();
        match result {
            Ok(o) if o.status.success() => {}
            Ok(o) => bad.push(format!(
                "{}: `critspeed {}` exited {:?}: {}",
                script.place,
                args.join(" "),
                o.status.code(),
                String::from_utf8_lossy(&o.stderr).trim()
            )),
            Err(e) => bad.push(format!("{}: cannot run the binary: {e}", script.place)),
        }
    }
    let _ = std::fs::remove_dir_all(&out);
    bad
}

#[test]
fn every_sh_example_runs_or_is_marked() {
    let (mut all, mut bad) = (Vec::new(), Vec::new());
    for (path, text) in pages() {
        let (s, b) = scripts(&path, &text);
        all.extend(s);
        bad.extend(b);
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
    assert!(
        all.iter().map(|s| s.commands.len()).sum::<usize>() >= 10,
        "the guide runs fewer than 10 commands"
    );
    // two workers: the examples are independent, each in its own folder
    let next = Mutex::new(0usize);
    let failures = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| loop {
                let k = {
                    let mut n = next.lock().expect("lock");
                    *n += 1;
                    *n - 1
                };
                let Some(script) = all.get(k) else { break };
                let f = run(script, k);
                failures.lock().expect("lock").extend(f);
            });
        }
    });
    let failures = failures.into_inner().expect("lock");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_snippet_scanner_finds_what_it_should() {
    let page = "```sh\ncritspeed linear studies/seed.toml --json   # a comment\n\
                # long: a minute\ncritspeed sweep big.toml\n\
                cargo run --release -- run\npip install ./python\ncritspeed a | head\n```\n\
                ```sh long\npip install x\n```\n```text\ncritspeed ramp STUDY [--rate R]\n```\n";
    let (s, bad) = scripts("p.md", page);
    assert_eq!(s.len(), 1);
    assert_eq!(
        s[0].commands,
        vec![vec!["linear", "studies/seed.toml", "--json"], vec!["run"]]
    );
    assert_eq!(bad.len(), 2, "{bad:?}");
    assert!(
        bad[0].starts_with("p.md:6:") && bad[0].contains("pip install"),
        "{bad:?}"
    );
    assert!(bad[1].contains("critspeed a | head"), "{bad:?}");
    assert_eq!(
        words(r#"critspeed sweep s.toml --threads "2" 'a b'"#),
        Some(
            vec!["critspeed", "sweep", "s.toml", "--threads", "2", "a b"]
                .into_iter()
                .map(String::from)
                .collect()
        )
    );
}
