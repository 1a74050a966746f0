//! The RON front end never panics, whatever bytes it is given, and errors stay in bounds.

mod common;

use lightbench_compiler::Session;
use proptest::prelude::*;

const SAMPLE: &str = include_str!("../../pipelines/deferred.ron");

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,400}") {
        let mut s = Session::new();
        let _ = s.parse_pipeline("fuzz.ron", text.clone());
        for d in &s.diags.list {
            if let Some(span) = d.primary_span() {
                prop_assert!(span.end as usize <= text.len());
            }
        }
    }

    #[test]
    fn truncated_or_mutated_pipelines_never_panic(cut in 0usize..SAMPLE.len(), pos in 0usize..SAMPLE.len(), byte in proptest::sample::select(vec!['(', ')', '"', ',', ':', '[', ']', '{', '}', 'x', '1', ' ', '/', '\\'])) {
        let mut text: Vec<char> = SAMPLE.chars().collect();
        let pos = pos.min(text.len().saturating_sub(1));
        text[pos] = byte;
        let cut = cut.min(text.len());
        let text: String = text[..cut].iter().collect();
        let mut s = Session::new();
        let _ = s.parse_pipeline("fuzz.ron", text);
        // Rendering with snippets must not panic either.
        let _ = s.render();
    }
}
