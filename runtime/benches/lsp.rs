//! `cargo bench -p lightbench --bench lsp`: how long after an edit the language server
//! publishes diagnostics. In process, no debounce (the check alone), for
//! `pipelines/deferred_gi.lbp` (it uses `deferred.lbp`; 47 shader files): cold (first open,
//! nothing compiled) and after an edit that touches no shader (modules cached). Then end to
//! end from headless Neovim with the manual's snippet (`lsp_neovim.lua` types): last
//! keystroke to the diagnostics shown, p50 and p95, for `deferred.lbp` (goal ≤ 50 ms) and
//! an included shader (goal ≤ 100 ms), both checked by two pipelines. And how the time to
//! diagnostics grows with a document's size (goal: linearly), and the resident memory over
//! rounds of documents opened and closed (goal: flat). `cargo test` runs it at its smallest.

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
    let sizes = Size::from_args().pick([10_000, 40_000], [500, 2_000]);
    let by_size = scaling(&client, &root, &text, sizes, Size::from_args().pick(3, 1));
    let cycles = Size::from_args().pick(500, 5);
    let rss: Vec<String> = (0..3)
        .map(|round| format!("{:.1}", open_close(&client, &root, &text, cycles, round)))
        .collect();
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
    println!(
        "deferred_gi.lbp and {} more parameters: {:>8.1} ms; and {}: {:>8.1} ms; ratio {:.2}x for {}x the text (goal: linear, <= {:.1}x)",
        sizes[0],
        by_size[0],
        sizes[1],
        by_size[1],
        by_size[1] / by_size[0],
        sizes[1] / sizes[0],
        1.25 * (sizes[1] / sizes[0]) as f64
    );
    println!(
        "resident memory after each of 3 rounds of {cycles} documents opened, checked and closed: {} MB (goal: flat after the first)",
        rss.join(", ")
    );
    client
        .sender
        .send(Request::new(RequestId::from(1), "shutdown".into(), json!(null)).into())
        .unwrap();
    client.sender.send(Notification::new("exit".into(), json!(null)).into()).unwrap();
    running.join().unwrap().unwrap();
    from_neovim(&root, Size::from_args().pick(20, 1));
}

/// Milliseconds from opening to diagnostics for `text` with each count of parameters more
/// (median of `rounds`, the sizes interleaved), each a document of its own, closed after.
fn scaling(client: &Connection, root: &Path, text: &str, sizes: [usize; 2], rounds: usize) -> [f64; 2] {
    let mut took: [Vec<f64>; 2] = [vec![], vec![]];
    for round in 0..rounds {
        for (i, n) in sizes.into_iter().enumerate() {
            let mut big = text.to_string();
            for k in 0..n {
                big += &format!("\nparam bench{k}.value: Float = 1 in 0..2 \"parameter {k}\"");
            }
            // Beside the bundled pipelines (never written: the editor's text is what is read).
            let path = root.join(format!("pipelines/bench-{n}-{round}.lbp"));
            let uri = uri_of(&path).unwrap().as_str().to_string();
            let open = json!({"textDocument": {"uri": uri, "languageId": "lbp", "version": 1, "text": big}});
            let t = until_published(client, Notification::new("textDocument/didOpen".into(), open), &uri);
            took[i].push(t.as_secs_f64() * 1e3);
            let close = json!({"textDocument": {"uri": uri}});
            client
                .sender
                .send(Notification::new("textDocument/didClose".into(), close).into())
                .unwrap();
        }
    }
    took.map(|mut v| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    })
}

/// `count` documents (unsaved copies of `text`) opened, checked and closed; the process's
/// resident memory after, in MB.
fn open_close(client: &Connection, root: &Path, text: &str, count: usize, round: usize) -> f64 {
    for k in 0..count {
        let uri = uri_of(&root.join(format!("pipelines/cycle-{round}-{k}.lbp")))
            .unwrap()
            .as_str()
            .to_string();
        let open = json!({"textDocument": {"uri": uri, "languageId": "lbp", "version": 1, "text": text}});
        until_published(client, Notification::new("textDocument/didOpen".into(), open), &uri);
        let close = json!({"textDocument": {"uri": uri}});
        until_published(client, Notification::new("textDocument/didClose".into(), close), &uri);
    }
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kb = status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.split_whitespace().next()?.parse::<f64>().ok());
    kb.unwrap_or(f64::NAN) / 1024.0
}

/// Edit → diagnostics from Neovim: `rounds` typos into deferred.lbp and out again, and as
/// many errors into a shader and out again, on a copy of the bundled files.
fn from_neovim(root: &Path, rounds: usize) {
    let dir = std::env::temp_dir().join(format!("lightbench-lsp-bench-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for sub in ["pipelines", "shaders"] {
        let copied = std::process::Command::new("cp").arg("-r").arg(root.join(sub)).arg(&dir).status();
        assert!(copied.unwrap().success());
    }
    let bin = Path::new(env!("CARGO_BIN_EXE_lightbench")).parent().unwrap().to_path_buf();
    let out = dir.join("latencies.json");
    let status = std::process::Command::new("nvim")
        .args(["--headless", "-i", "NONE", "-n", "-u"])
        .arg(root.join("editors/neovim/lightbench.lua"))
        .arg("-c")
        .arg(format!("luafile {}", root.join("runtime/benches/lsp_neovim.lua").display()))
        .env("PATH", format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default()))
        .env("LB_DIR", &dir)
        .env("LB_OUT", &out)
        .env("LB_ROUNDS", rounds.to_string())
        .status()
        .expect("Neovim (`nvim`, Debian's `neovim`; .ci/run installs it)");
    assert!(status.success());
    let got: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    for (key, what, goal) in [
        ("pipeline", "deferred.lbp, a typo typed and undone", 50.0),
        ("shader", "ambient.wgsl, an error typed and undone", 100.0),
    ] {
        let mut ms: Vec<f64> = got[key].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        assert!(ms.iter().all(|&m| m >= 0.0), "{key}: a publication never came: {ms:?}");
        ms.sort_by(f64::total_cmp);
        let at = |q: f64| ms[((ms.len() - 1) as f64 * q).round() as usize];
        println!(
            "Neovim, last keystroke -> diagnostics, {what}: p50 {:>6.1} ms, p95 {:>6.1} ms (goal <= {goal} ms; {} edits; {})",
            at(0.5),
            at(0.95),
            ms.len(),
            load_line()
        );
    }
}
