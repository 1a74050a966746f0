//! The manual's diagnostics page (`docs/diagnostics.md`) lists exactly the codes the compiler
//! can report, each with the description `diag::Code` gives it.

use lightbench_compiler::diag::Code;
use std::collections::BTreeSet;

#[test]
fn the_diagnostics_page_lists_every_code() {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/diagnostics.md")).unwrap();
    let start = readme
        .find("| code | meaning |")
        .expect("docs/diagnostics.md has a table of diagnostic codes");
    let table: String = readme[start..]
        .lines()
        .take_while(|l| l.starts_with('|'))
        .collect::<Vec<_>>()
        .join("\n");
    let listed: BTreeSet<&str> = table
        .lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split_once("` |"))
        .map(|(code, _)| code)
        .collect();
    let known: BTreeSet<&str> = Code::ALL.iter().map(|c| c.as_str()).collect();
    let missing: Vec<_> = known.difference(&listed).collect();
    let unknown: Vec<_> = listed.difference(&known).collect();
    assert!(missing.is_empty(), "codes missing from docs/diagnostics.md's table: {missing:?}");
    assert!(
        unknown.is_empty(),
        "docs/diagnostics.md lists codes the compiler does not have: {unknown:?}"
    );
    for c in Code::ALL {
        let row = format!("| `{}` | {} |", c.as_str(), c.doc().replace('|', "\\|"));
        assert!(table.contains(&row), "docs/diagnostics.md row for `{c}` should read: {row}");
    }
}
