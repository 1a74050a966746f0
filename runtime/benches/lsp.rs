//! `cargo bench -p lightbench --bench lsp`: how long after an edit the language server
//! publishes diagnostics for `pipelines/deferred_gi.lbp` (it uses `deferred.lbp`; 47 shader
//! files): cold (first open, nothing compiled) and after an edit that touches no shader
//! (modules cached; goal ≤ 100 ms on 2 cores). In process, no debounce, so the figure is the
//! check alone. `cargo test` runs it at its smallest.

use lightbench::lsp::{serve, text::uri_of};
use lsp_server::{Connection, Message, Notification, Request, RequestId};
use serde_json::json;
use std::path::Path;
use std::time::{Duration, Instant};

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{load_line, Size};

/// Send a document notification and wait for the diagnostics of that document.
fn until_published(client: &Connection, note: Notification, uri: &str) -> Duration {
    let t = Instant::now();
    client.sender.send(note.into()).unwrap();
    loop {
        match client.receiver.recv_timeout(Duration::from_secs(120)).expect("diagnostics") {
            Message::Notification(n) if n.method == "textDocument/publishDiagnostics" && n.params["uri"] == uri => {
                assert_eq!(n.params["diagnostics"], json!([]), "the bundled pipeline checks clean");
                return t.elapsed();
            }
            _ => {}
        }
    }
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf();
    let path = root.join("pipelines/deferred_gi.lbp");
    let text = std::fs::read_to_string(&path).unwrap();
    let uri = uri_of(&path).unwrap().as_str().to_string();
    let (server, client) = Connection::memory();
    let running = std::thread::spawn(move || serve(&server, Duration::ZERO));
    let init = Request::new(RequestId::from(0), "initialize".into(), json!({"capabilities": {}}));
    client.sender.send(init.into()).unwrap();
    let _ = client.receiver.recv();
    client
        .sender
        .send(Notification::new("initialized".into(), json!({})).into())
        .unwrap();
    let open = json!({"textDocument": {"uri": uri, "languageId": "lbp", "version": 1, "text": text}});
    let cold = until_published(&client, Notification::new("textDocument/didOpen".into(), open), &uri);
    let mut warm = vec![];
    let edits = Size::from_args().pick(20, 2);
    for v in 2..2 + edits {
        // An edit that touches no shader: a comment grows.
        let edited = format!("{text}\n// edit {v}\n");
        let change = json!({"textDocument": {"uri": uri, "version": v}, "contentChanges": [{"text": edited}]});
        warm.push(until_published(
            &client,
            Notification::new("textDocument/didChange".into(), change),
            &uri,
        ));
    }
    warm.sort();
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    println!(
        "deferred_gi.lbp diagnostics after open (cold, nothing compiled): {:>8.1} ms",
        ms(cold)
    );
    println!(
        "deferred_gi.lbp diagnostics after an edit (shaders cached):      {:>8.1} ms (median of {}; goal <= 100 ms; {})",
        ms(warm[warm.len() / 2]),
        warm.len(),
        load_line()
    );
    client
        .sender
        .send(Request::new(RequestId::from(1), "shutdown".into(), json!(null)).into())
        .unwrap();
    client.sender.send(Notification::new("exit".into(), json!(null)).into()).unwrap();
    running.join().unwrap().unwrap();
}
