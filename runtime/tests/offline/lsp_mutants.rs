//! The language server against 1,000 generated message streams (seeded, reproducible): valid
//! and mutated documents, requests with wrong shapes, positions far out of range, unknown
//! methods, a shader symlink loop. Every stream must end (no hang), every request get one
//! answer, and nothing panic. In process, over `lsp-server`'s memory connection.

use crate::cli_common;

use cli_common::scratch;
use lsp_server::{Connection, Message, Notification, Request, RequestId};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// xorshift64*: a fixed seed gives the same streams on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

const FILL: &str = "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(1.0);\n}\n";

fn pipeline(shader: &str) -> String {
    format!(
        "pipeline p\n\nparam k: Float = 1 in 0..2 \"a knob\"\n\ntexture out: Rgba8Unorm viewport\n\nfullscreen f \"{shader}\" {{\n    color out\n    params k\n}}\n\nvariant v = a \"choice\" {{\n    option a \"A\"\n    option b \"B\"\n}}\n\noutput out\n"
    )
}

fn project() -> PathBuf {
    let dir = scratch("streams");
    std::fs::create_dir_all(dir.join("pipelines")).unwrap();
    std::fs::create_dir_all(dir.join("shaders")).unwrap();
    std::fs::write(dir.join("shaders/fill.wgsl"), FILL).unwrap();
    std::os::unix::fs::symlink("loop.wgsl", dir.join("shaders/loop.wgsl")).unwrap();
    std::fs::write(dir.join("pipelines/p.lbp"), pipeline("fill.wgsl")).unwrap();
    dir
}

/// A document: the pipeline (its shader sometimes the link loop), mutated by a few random
/// deletions, duplications and odd characters.
fn document(rng: &mut Rng) -> String {
    let mut t: Vec<char> = pipeline(if rng.below(4) == 0 { "loop.wgsl" } else { "fill.wgsl" })
        .chars()
        .collect();
    for _ in 0..rng.below(4) {
        if t.is_empty() {
            break;
        }
        let at = rng.below(t.len());
        match rng.below(4) {
            0 => {
                t.remove(at.min(t.len() - 1));
            }
            1 => {
                let c = t[at.min(t.len() - 1)];
                t.insert(at, c);
            }
            2 => t.insert(at, ['{', '}', '"', '\n', 'é', '😀', '\0'][rng.below(7)]),
            _ => t.truncate(at),
        }
    }
    t.into_iter().collect()
}

fn uri(p: &Path) -> String {
    format!("file://{}", p.display())
}

fn position(rng: &mut Rng) -> Value {
    let big = [0u64, 1, 3, 7, 12, 40, 1 << 20, u32::MAX as u64];
    json!({"line": big[rng.below(big.len())], "character": big[rng.below(big.len())]})
}

/// One message of a stream: a document change, a request of any kind, or junk.
fn message(rng: &mut Rng, doc: &str, id: i32) -> Message {
    let text_doc = json!({"uri": doc});
    let at = json!({"textDocument": text_doc, "position": position(rng)});
    let req = |method: &str, params: Value| Message::Request(Request::new(RequestId::from(id), method.into(), params));
    let note = |method: &str, params: Value| Message::Notification(Notification::new(method.into(), params));
    match rng.below(14) {
        0 => note(
            "textDocument/didOpen",
            json!({"textDocument": {"uri": doc, "languageId": "lbp", "version": 1, "text": document(rng)}}),
        ),
        1 => note(
            "textDocument/didChange",
            json!({"textDocument": {"uri": doc, "version": 2}, "contentChanges": [{"text": document(rng)}]}),
        ),
        2 => note("textDocument/didChange", json!({"textDocument": text_doc, "contentChanges": []})),
        3 => note("textDocument/didClose", json!({"textDocument": text_doc})),
        4 => req("textDocument/hover", at),
        5 => req("textDocument/definition", at),
        6 => req(
            "textDocument/references",
            json!({"textDocument": text_doc, "position": position(rng), "context": {"includeDeclaration": true}}),
        ),
        7 => req("textDocument/completion", at),
        8 => {
            let name = ["k2", "", "a b", "out"][rng.below(4)];
            req(
                "textDocument/rename",
                json!({"textDocument": text_doc, "position": position(rng), "newName": name}),
            )
        }
        9 => req("textDocument/documentSymbol", json!({"textDocument": text_doc})),
        10 => req(
            "textDocument/formatting",
            json!({"textDocument": text_doc, "options": {"tabSize": 4, "insertSpaces": true}}),
        ),
        11 => {
            let method = ["textDocument/hover", "lightbench/nothing", "workspace/symbol"][rng.below(3)];
            req(method, [json!(null), json!(5), json!({"x": []})][rng.below(3)].clone())
        }
        12 => note(
            ["textDocument/didOpen", "$/cancelRequest", "unknown/note"][rng.below(3)],
            json!([1, 2]),
        ),
        _ => note("textDocument/didSave", json!({"textDocument": text_doc})),
    }
}

/// Run one stream against a fresh server; the number of requests answered of those sent.
fn stream(seed: u64, dir: &Path) -> (usize, usize) {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let (server, client) = Connection::memory();
    let running = std::thread::spawn(move || lightbench::lsp::serve(&server, Duration::from_millis(0)));
    let docs = [
        uri(&dir.join("pipelines/p.lbp")),
        uri(&dir.join("pipelines/new.lbp")),
        uri(&dir.join("shaders/fill.wgsl")),
        "untitled:x".to_string(),
    ];
    let init = Request::new(
        RequestId::from(0),
        "initialize".into(),
        json!({"capabilities": {}, "workspaceFolders": [{"uri": uri(dir), "name": "p"}]}),
    );
    client.sender.send(init.into()).unwrap();
    client
        .sender
        .send(Notification::new("initialized".into(), json!({})).into())
        .unwrap();
    let mut sent = 0;
    for id in 1..=(4 + rng.below(12) as i32) {
        let doc = docs[rng.below(docs.len())].clone();
        let m = message(&mut rng, &doc, id);
        sent += matches!(m, Message::Request(_)) as usize;
        client.sender.send(m).unwrap();
        if rng.below(3) == 0 {
            // Let the debounce run out now and then, so edits are checked mid-stream.
            std::thread::sleep(Duration::from_millis(2));
        }
    }
    client
        .sender
        .send(Request::new(RequestId::from(9999), "shutdown".into(), json!(null)).into())
        .unwrap();
    client.sender.send(Notification::new("exit".into(), json!(null)).into()).unwrap();
    let deadline = std::time::Instant::now() + Duration::from_secs(60);
    while !running.is_finished() {
        assert!(std::time::Instant::now() < deadline, "stream {seed} hung");
        std::thread::sleep(Duration::from_millis(1));
    }
    let served = running.join();
    assert!(served.is_ok(), "stream {seed}: the server panicked");
    let answered = client
        .receiver
        .try_iter()
        .filter(|m| matches!(m, Message::Response(r) if r.id != RequestId::from(0) && r.id != RequestId::from(9999)))
        .count();
    (sent, answered)
}

#[test]
fn a_thousand_malformed_streams_neither_panic_nor_hang() {
    // A handler's panic would be answered as an internal error; none may happen at all.
    static PANICS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        PANICS.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        default(info);
    }));
    let dir = project();
    for seed in 0..1000 {
        let (sent, answered) = stream(seed, &dir);
        assert_eq!(sent, answered, "stream {seed}: every request is answered once");
        assert_eq!(PANICS.load(std::sync::atomic::Ordering::SeqCst), 0, "stream {seed} panicked");
    }
}
