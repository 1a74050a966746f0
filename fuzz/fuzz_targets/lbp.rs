//! The LBP front end must never panic: arbitrary bytes are either a pipeline or diagnostics,
//! and rendering those diagnostics (with snippets) must not panic either.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data).into_owned();
    let mut s = lightbench_compiler::Session::new();
    if let Some(p) = s.parse_pipeline("fuzz.lbp", text.clone()) {
        // Whatever parses must print and parse back to the same pipeline.
        let printed = lightbench_compiler::front::lbp::print::print(&p, Some(&text));
        let mut again = lightbench_compiler::Session::new();
        let back = again.parse_pipeline("fuzz.lbp", printed).expect("printed LBP parses");
        assert!(back.same_as(&p));
    }
    let _ = s.render();
});
