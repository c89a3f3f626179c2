//! Links and anchors of the README, the changelog and the guide resolve inside the repository,
//! and no tracked file refers to the team folder beside the repository.

use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

use super::{pages, split};
use crate::common::root;

/// `folder/../x/./y` → `x/y`, lexically.
fn lexical(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            c => out.push(c),
        }
    }
    out
}

/// The prose of a page without fenced blocks and inline code spans.
fn prose(text: &str) -> String {
    let (_, prose) = split(text);
    prose.split('`').step_by(2).collect::<Vec<_>>().join(" ")
}

/// The targets of the page's links and images: `[text](target)`, `![alt](target "title")`.
fn targets(text: &str) -> Vec<String> {
    prose(text)
        .split("](")
        .skip(1)
        .filter_map(|part| part.split(')').next())
        .map(|t| {
            let t = t.trim().trim_start_matches('<');
            let t = t.split_whitespace().next().unwrap_or("");
            t.trim_end_matches('>').to_string()
        })
        .collect()
}

/// GitHub's anchor of a heading: lower case, letters, digits, `-` and `_` kept, spaces to `-`,
/// everything else dropped.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

/// The anchors of a page's headings (outside fenced blocks), a repeated one as `name-1`, ….
fn anchors(text: &str) -> Vec<String> {
    let (_, prose) = split(text);
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    prose
        .lines()
        .filter_map(|l| {
            let hashes = l.chars().take_while(|c| *c == '#').count();
            (1..=6)
                .contains(&hashes)
                .then(|| l[hashes..].strip_prefix(' '))
                .flatten()
        })
        .map(|h| {
            let s = slug(h);
            let n = seen.entry(s.clone()).or_insert(0);
            *n += 1;
            if *n == 1 {
                s
            } else {
                format!("{s}-{}", *n - 1)
            }
        })
        .collect()
}

/// The broken links of the page at `path` (relative to the root) with `text`.
fn broken(path: &str, text: &str) -> Vec<String> {
    let folder = Path::new(path)
        .parent()
        .map(PathBuf::from)
        .unwrap_or_default();
    let mut bad = Vec::new();
    for target in targets(text) {
        if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
            continue;
        }
        let (file, anchor) = match target.split_once('#') {
            Some((f, a)) => (f, Some(a)),
            None => (target.as_str(), None),
        };
        let rel = if file.is_empty() {
            PathBuf::from(path)
        } else {
            lexical(&folder.join(file))
        };
        let full = root().join(&rel);
        if !file.is_empty() && !full.exists() {
            bad.push(format!(
                "{path}: link to {target}: {} does not exist",
                rel.display()
            ));
            continue;
        }
        let Some(anchor) = anchor else { continue };
        let page = if file.is_empty() {
            Some(text.to_string())
        } else {
            std::fs::read_to_string(&full).ok()
        };
        match page {
            Some(p) if rel.extension().is_some_and(|e| e == "md") => {
                if !anchors(&p).iter().any(|a| a == anchor) {
                    bad.push(format!(
                        "{path}: link to {target}: no heading of {} has the anchor #{anchor}",
                        rel.display()
                    ));
                }
            }
            _ => bad.push(format!(
                "{path}: link to {target}: an anchor into a non-page"
            )),
        }
    }
    bad
}

#[test]
fn links_images_and_anchors_resolve() {
    let mut all = pages();
    let changelog = root().join("CHANGELOG.md");
    let text = std::fs::read_to_string(&changelog).expect("CHANGELOG.md");
    all.push(("CHANGELOG.md".to_string(), text));
    let bad: Vec<String> = all.iter().flat_map(|(p, t)| broken(p, t)).collect();
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// Every page of the guide can be reached from `docs/README.md` by following links.
#[test]
fn every_page_is_reachable_from_the_guide_index() {
    let pages: BTreeMap<String, String> = pages().into_iter().collect();
    let mut seen = std::collections::BTreeSet::new();
    let mut todo = vec!["docs/README.md".to_string()];
    while let Some(page) = todo.pop() {
        if !seen.insert(page.clone()) {
            continue;
        }
        let Some(text) = pages.get(&page) else {
            continue;
        };
        let folder = Path::new(&page)
            .parent()
            .map(PathBuf::from)
            .unwrap_or_default();
        for target in targets(text) {
            let file = target.split('#').next().unwrap_or("");
            if file.ends_with(".md") && !file.contains("://") {
                let rel = lexical(&folder.join(file)).display().to_string();
                todo.push(rel);
            }
        }
    }
    let unreached: Vec<&String> = pages
        .keys()
        .filter(|p| p.starts_with("docs/") && !seen.contains(*p))
        .collect();
    assert!(
        unreached.is_empty(),
        "not reachable from docs/README.md: {unreached:?}"
    );
}

#[test]
fn the_link_checker_finds_what_it_should() {
    let page = "# Top\n## The ramp method (EN 14363)\n## §1 Frame and state\n## Top\n\
                ```sh\n# not a heading [x](nowhere.md)\n```\n\
                [a](#the-ramp-method-en-14363) [b](#1-frame-and-state) [c](#top-1) \
                `[d](ignored.md)` ![e](images/none.svg) [f](#missing) [g](https://x.org/y)\n";
    assert_eq!(
        anchors(page),
        [
            "top",
            "the-ramp-method-en-14363",
            "1-frame-and-state",
            "top-1"
        ]
    );
    let bad = broken("docs/x.md", page);
    assert_eq!(bad.len(), 2, "{bad:?}");
    assert!(bad[0].contains("docs/images/none.svg"), "{bad:?}");
    assert!(bad[1].contains("#missing"), "{bad:?}");
}

/// What a tracked file must not contain: references to the team's folder beside the
/// repository, which a clone does not have (built from parts so that this file passes).
fn outside_references() -> Vec<String> {
    let shared = "shared";
    vec![
        format!("../{shared}"),
        format!("{shared}/reference/"),
        format!("{shared}/peers/"),
    ]
}

#[test]
fn no_tracked_file_refers_to_a_folder_outside_the_repository() {
    let listed = std::process::Command::new("git")
        .args(["ls-files", "-z"])
        .current_dir(root())
        .output();
    let files = match listed {
        Ok(out) if out.status.success() => out.stdout,
        Ok(out) => {
            eprintln!(
                "skipped: `git ls-files` failed here (not a git checkout?): {}",
                String::from_utf8_lossy(&out.stderr).trim()
            );
            return;
        }
        Err(e) => {
            eprintln!("skipped: git is not available to list the tracked files: {e}");
            return;
        }
    };
    let needles = outside_references();
    let mut bad = Vec::new();
    for name in files.split(|b| *b == 0).filter(|n| !n.is_empty()) {
        let name = String::from_utf8_lossy(name).to_string();
        let Ok(bytes) = std::fs::read(root().join(&name)) else {
            continue; // tracked but deleted in this work tree
        };
        for needle in &needles {
            if bytes.windows(needle.len()).any(|w| w == needle.as_bytes()) {
                bad.push(format!("{name} names `{needle}`"));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
