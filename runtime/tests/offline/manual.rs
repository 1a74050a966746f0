//! The manual's shape: a short README, every page of `docs/` in `docs/SUMMARY.md`, and every
//! relative link in the README and the manual pointing at a file that exists.

use crate::cli_common;

use cli_common::{manual_files, root};

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
    for page in manual_files().iter().skip(1).filter_map(|p| p.file_name()?.to_str()) {
        if page != "SUMMARY.md" {
            assert!(listed.contains(&page), "docs/{page} is not reachable from docs/SUMMARY.md");
        }
    }
}

#[test]
fn relative_links_point_at_files() {
    let mut checked = 0;
    for doc in manual_files() {
        let (text, dir) = (std::fs::read_to_string(&doc).unwrap(), doc.parent().unwrap());
        for link in links(&text) {
            if link.starts_with("http") || link.starts_with('#') || link.contains(' ') {
                continue;
            }
            let file = link.split('#').next().unwrap();
            assert!(dir.join(file).exists(), "{}: link to {link}, which does not exist", doc.display());
            checked += 1;
        }
    }
    assert!(checked >= 20, "only {checked} links found");
}
