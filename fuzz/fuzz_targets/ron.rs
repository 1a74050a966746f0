//! The RON front end must never panic on arbitrary bytes.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data).into_owned();
    let mut s = lightbench_compiler::Session::new();
    let _ = s.parse_pipeline("fuzz.ron", text);
    let _ = s.render();
});
