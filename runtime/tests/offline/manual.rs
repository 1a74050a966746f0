//! The manual's shape: a short README, every page of `docs/` in `docs/SUMMARY.md`, and every
//! relative link in the README and the manual pointing at a file that exists.

use crate::cli_common;

use cli_common::root;
use std::path::Path;

fn pages() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md"))
        .collect();
    names.sort();
    names
}

/// `](target)` links of a Markdown text.
fn links(text: &str) -> Vec<&str> {
    text.split("](").skip(1).filter_map(|rest| rest.split(')').next()).collect()
}

#[test]
fn the_readme_is_what_a_newcomer_needs_first() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let n = readme.lines().count();
    assert!(n <= 150, "README.md has {n} lines; the manual (docs/) is the place for the rest");
    for must in ["cargo run --release -- render", "cargo test --workspace", "docs/SUMMARY.md"] {
        assert!(readme.contains(must), "README lacks {must}");
    }
}

#[test]
fn every_page_is_in_the_summary() {
    let summary = std::fs::read_to_string(root().join("docs/SUMMARY.md")).unwrap();
    let listed = links(&summary);
    for page in pages().iter().filter(|p| *p != "SUMMARY.md") {
        assert!(listed.contains(&page.as_str()), "docs/{page} is not reachable from docs/SUMMARY.md");
    }
}

#[test]
fn relative_links_point_at_files() {
    let mut docs: Vec<(String, std::path::PathBuf)> = vec![("README.md".into(), root())];
    docs.extend(pages().into_iter().map(|p| (format!("docs/{p}"), root().join("docs"))));
    let mut checked = 0;
    for (doc, dir) in docs {
        let text = std::fs::read_to_string(root().join(&doc)).unwrap();
        for link in links(&text) {
            if link.starts_with("http") || link.starts_with('#') || link.contains(' ') {
                continue;
            }
            let file = link.split('#').next().unwrap();
            assert!(Path::new(&dir).join(file).exists(), "{doc}: link to {link}, which does not exist");
            checked += 1;
        }
    }
    assert!(checked >= 20, "only {checked} links found");
}
