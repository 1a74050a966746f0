//! The README's diagnostic-code table lists exactly the codes the compiler can report.

use lightbench_compiler::diag::Code;
use std::collections::BTreeSet;

#[test]
fn readme_lists_every_diagnostic_code() {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md")).unwrap();
    let start = readme
        .find("| code | meaning |")
        .expect("the README has a table of diagnostic codes");
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
    assert!(missing.is_empty(), "codes missing from the README's table: {missing:?}");
    assert!(unknown.is_empty(), "README lists codes the compiler does not have: {unknown:?}");
    for c in Code::ALL {
        let row = format!("| `{}` | {} |", c.as_str(), c.doc().replace('|', "\\|"));
        assert!(table.contains(&row), "README row for `{c}` should read: {row}");
    }
}
