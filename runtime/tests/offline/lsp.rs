//! `lightbench lsp` driven over stdio as an editor drives it: JSON-RPC with Content-Length
//! framing, on the bundled pipelines and on broken copies; its diagnostics against `check
//! --format json`; malformed input.

use crate::cli_common;

use cli_common::{lightbench_in, root, scratch};
use serde_json::{json, Value};
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::time::{Duration, Instant};

pub(crate) struct Client {
    child: Child,
    stdin: ChildStdin,
    rx: Receiver<Value>,
    /// Notifications (and stray messages) read while waiting for something else.
    seen: Vec<Value>,
    next_id: i64,
}

fn read_message(r: &mut impl BufRead) -> Option<Value> {
    let mut len = None;
    loop {
        let mut line = String::new();
        if r.read_line(&mut line).ok()? == 0 {
            return None;
        }
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some(v) = line.strip_prefix("Content-Length: ") {
            len = v.parse::<usize>().ok();
        }
    }
    let mut body = vec![0; len?];
    r.read_exact(&mut body).ok()?;
    serde_json::from_slice(&body).ok()
}

impl Client {
    pub(crate) fn start(dir: &Path) -> Client {
        let mut child = Command::new(env!("CARGO_BIN_EXE_lightbench"))
            .arg("lsp")
            .current_dir(dir)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start lightbench lsp");
        let stdin = child.stdin.take().unwrap();
        let mut stdout = BufReader::new(child.stdout.take().unwrap());
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            while let Some(m) = read_message(&mut stdout) {
                if tx.send(m).is_err() {
                    break;
                }
            }
        });
        let mut c = Client {
            child,
            stdin,
            rx,
            seen: vec![],
            next_id: 1,
        };
        let folders = json!([{"uri": uri(dir), "name": "project"}]);
        let init = c.request("initialize", json!({"capabilities": {}, "workspaceFolders": folders}));
        assert!(init["capabilities"]["hoverProvider"].as_bool().unwrap_or(false), "{init}");
        c.notify("initialized", json!({}));
        c
    }

    fn send_raw(&mut self, body: &[u8]) {
        let _ = write!(self.stdin, "Content-Length: {}\r\n\r\n", body.len());
        let _ = self.stdin.write_all(body);
        let _ = self.stdin.flush();
    }

    fn send(&mut self, v: Value) {
        self.send_raw(v.to_string().as_bytes());
    }

    pub(crate) fn notify(&mut self, method: &str, params: Value) {
        self.send(json!({"jsonrpc": "2.0", "method": method, "params": params}));
    }

    /// The whole response (`result` or `error`) to a request.
    pub(crate) fn call(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        self.send(json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        let deadline = Instant::now() + Duration::from_secs(60);
        loop {
            let m = self
                .rx
                .recv_timeout(deadline.saturating_duration_since(Instant::now()))
                .expect("a response in time");
            if m["id"] == json!(id) {
                return m;
            }
            self.seen.push(m);
        }
    }

    pub(crate) fn request(&mut self, method: &str, params: Value) -> Value {
        let r = self.call(method, params);
        assert!(r.get("error").is_none(), "{method}: {r}");
        r["result"].clone()
    }

    /// The next diagnostics published for `path` (waiting for the debounce and the check).
    pub(crate) fn diagnostics(&mut self, path: &Path) -> Vec<Value> {
        let want = uri(path);
        let found = |m: &Value| m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == want;
        if let Some(i) = self.seen.iter().position(found) {
            return self.seen.remove(i)["params"]["diagnostics"].as_array().unwrap().clone();
        }
        let deadline = Instant::now() + Duration::from_secs(120);
        loop {
            let m = self
                .rx
                .recv_timeout(deadline.saturating_duration_since(Instant::now()))
                .expect("diagnostics in time");
            if found(&m) {
                return m["params"]["diagnostics"].as_array().unwrap().clone();
            }
            self.seen.push(m);
        }
    }

    pub(crate) fn open(&mut self, path: &Path, text: &str) {
        let doc = json!({"uri": uri(path), "languageId": "lbp", "version": 1, "text": text});
        self.notify("textDocument/didOpen", json!({"textDocument": doc}));
    }

    pub(crate) fn change(&mut self, path: &Path, version: i64, text: &str) {
        let doc = json!({"uri": uri(path), "version": version});
        self.notify(
            "textDocument/didChange",
            json!({"textDocument": doc, "contentChanges": [{"text": text}]}),
        );
    }

    /// `shutdown`, `exit`, and the exit code.
    pub(crate) fn finish(mut self) -> i32 {
        self.request("shutdown", Value::Null);
        self.notify("exit", Value::Null);
        wait(&mut self.child)
    }
}

fn wait(child: &mut Child) -> i32 {
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        if let Some(s) = child.try_wait().unwrap() {
            let mut err = String::new();
            let _ = child.stderr.take().unwrap().read_to_string(&mut err);
            assert!(!err.contains("panicked"), "{err}");
            return s.code().unwrap_or(-1);
        }
        assert!(Instant::now() < deadline, "the server did not exit");
        std::thread::sleep(Duration::from_millis(20));
    }
}

pub(crate) fn uri(p: &Path) -> String {
    let mut s = String::from("file://");
    for b in p.to_str().unwrap().bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'_' | b'.' | b'~' => s.push(b as char),
            _ => s.push_str(&format!("%{b:02X}")),
        }
    }
    s
}

/// 0-based line and UTF-16 column of the first `needle` (plus `skip` characters) in `text`.
pub(crate) fn pos(text: &str, needle: &str, skip: usize) -> Value {
    let at = text.find(needle).unwrap_or_else(|| panic!("`{needle}` in the text")) + skip;
    let line = text[..at].matches('\n').count();
    let col = text[..at].rsplit('\n').next().unwrap().encode_utf16().count();
    json!({"line": line, "character": col})
}

pub(crate) fn at(path: &Path, text: &str, needle: &str, skip: usize) -> Value {
    json!({"textDocument": {"uri": uri(path)}, "position": pos(text, needle, skip)})
}

/// A project of its own: the bundled pipelines and shaders copied.
pub(crate) fn project(tag: &str) -> PathBuf {
    let dir = scratch(tag);
    for sub in ["pipelines", "shaders"] {
        let ok = Command::new("cp").arg("-r").arg(root().join(sub)).arg(&dir).status().unwrap();
        assert!(ok.success());
    }
    dir
}

#[test]
fn bundled_pipeline_checks_clean_and_answers_hover_definition_completion() {
    let dir = project("bundled");
    let path = dir.join("pipelines/deferred.lbp");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut c = Client::start(&dir);
    c.open(&path, &text);
    assert_eq!(c.diagnostics(&path), Vec::<Value>::new(), "the bundled pipeline checks clean");

    // Hover a resource where a pass reads it: its description, writers and readers.
    let read_at = at(&path, &text, "gbuf.albedo, gbuf.emissive\n", 2);
    let hover = c.request("textDocument/hover", read_at.clone());
    let shown = hover["contents"]["value"].as_str().unwrap();
    assert!(shown.contains("**texture** `gbuf.albedo`: Rgba8Unorm, viewport"), "{shown}");
    assert!(shown.contains("written by `gbuffer`") && shown.contains("`ambient`"), "{shown}");
    assert!(
        shown.contains("default options): ") && shown.contains("; usage ") && shown.contains("RENDER_ATTACHMENT"),
        "{shown}"
    );

    // Definition: the declaration line.
    let def = c.request("textDocument/definition", read_at.clone());
    assert_eq!(def["uri"], json!(uri(&path)));
    assert_eq!(def["range"]["start"], pos(&text, "gbuf.albedo: Rgba8Unorm", 0));
    let refs = c.request(
        "textDocument/references",
        json!({"textDocument": {"uri": uri(&path)}, "position": read_at["position"], "context": {"includeDeclaration": true}}),
    );
    assert!(refs.as_array().unwrap().len() >= 6, "{refs}");

    // Hover a parameter and a variant option in a condition.
    let p = c.request("textDocument/hover", at(&path, &text, "params ambient.color", 8));
    assert!(
        p["contents"]["value"]
            .as_str()
            .unwrap()
            .contains("**parameter** `ambient.color`: Color"),
        "{p}"
    );
    let o = c.request("textDocument/hover", at(&path, &text, "variant(lighting, forward_single)", 20));
    assert!(
        o["contents"]["value"]
            .as_str()
            .unwrap()
            .contains("**option** `forward_single` of variant `lighting`"),
        "{o}"
    );

    // A pass: what it does on the default scene.
    let pass = c.request("textDocument/hover", at(&path, &text, "fullscreen ambient", 12));
    let shown = pass["contents"]["value"].as_str().unwrap();
    assert!(
        shown.contains("**fullscreen pass** `ambient`")
            && shown.contains("On the default scene (`cornell` at its size, default options): runs once"),
        "{shown}"
    );
    let culled = c.request("textDocument/hover", at(&path, &text, "raster forward_single", 8));
    assert!(
        culled["contents"]["value"].as_str().unwrap().contains("culled: variant not chosen"),
        "{culled}"
    );

    // A shader path: its entry points; definition: the file.
    let sh = c.request("textDocument/hover", at(&path, &text, "\"ambient.wgsl\"", 2));
    assert!(sh["contents"]["value"].as_str().unwrap().contains("`fs_main` (fragment)"), "{sh}");
    let file = c.request("textDocument/definition", at(&path, &text, "\"ambient.wgsl\"", 2));
    assert_eq!(file["uri"], json!(uri(&dir.join("shaders/ambient.wgsl"))));

    // Completion: resources after `reads`, entry points after `fragment`, keys elsewhere.
    let line_end = |needle: &str| {
        let v = pos(&text, needle, needle.len());
        json!({"textDocument": {"uri": uri(&path)}, "position": v})
    };
    let labels = |r: Value| -> Vec<String> {
        r.as_array()
            .unwrap()
            .iter()
            .map(|i| i["label"].as_str().unwrap().to_string())
            .collect()
    };
    let res = labels(c.request("textDocument/completion", line_end("    reads ")));
    assert!(
        res.contains(&"gbuf.albedo".to_string()) && res.contains(&"hdr".to_string()),
        "{res:?}"
    );
    let entries = labels(c.request("textDocument/completion", line_end("    fragment fs_depth")));
    assert!(
        entries.contains(&"fs_single".to_string()) && entries.contains(&"fs_ambient".to_string()),
        "{entries:?}"
    );
    let opts = labels(c.request("textDocument/completion", line_end("when variant(lighting, ")));
    assert!(opts.contains(&"deferred_volumes".to_string()), "{opts:?}");

    // Symbols and formatting (already formatted: no edit).
    let syms = c.request("textDocument/documentSymbol", json!({"textDocument": {"uri": uri(&path)}}));
    let names: Vec<&str> = syms.as_array().unwrap().iter().map(|s| s["name"].as_str().unwrap()).collect();
    assert!(
        names.contains(&"light_point") && names.contains(&"cube_shadow") && names.contains(&"gbuf.albedo"),
        "{names:?}"
    );
    // A template is a class-like symbol (kind 5).
    let template = syms
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["name"] == "two_sided")
        .expect("the template");
    assert_eq!(template["kind"], json!(5), "{template}");
    let edits = c.request(
        "textDocument/formatting",
        json!({"textDocument": {"uri": uri(&path)}, "options": {"tabSize": 4, "insertSpaces": true}}),
    );
    assert_eq!(edits, json!([]));
    assert_eq!(c.finish(), 0);
}

#[test]
fn broken_copy_reports_what_check_reports_and_an_edit_clears_it() {
    let dir = project("broken");
    let path = dir.join("pipelines/deferred.lbp");
    let good = std::fs::read_to_string(&path).unwrap();
    let broken = good.replacen("reads gbuf.albedo, gbuf.emissive", "reads gbuf.albdo, gbuf.emissive", 1);
    std::fs::write(&path, &broken).unwrap();
    let (_, out, _) = lightbench_in(&dir, &["check", "--format", "json", path.to_str().unwrap()]);
    let all: Vec<Value> = out.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    let in_file = |f: &Path| -> Vec<Value> { all.iter().filter(|d| d["file"] == json!(f.to_str().unwrap())).cloned().collect() };
    let shader = dir.join("shaders/ambient.wgsl");
    assert_eq!(all.len(), in_file(&path).len() + in_file(&shader).len(), "{all:?}");

    let mut c = Client::start(&dir);
    c.open(&path, &broken);
    // Each diagnostic in the file `check` locates it in, with its code, message and place.
    for (file, expected) in [(&path, in_file(&path)), (&shader, in_file(&shader))] {
        let got = c.diagnostics(file);
        assert_eq!(got.len(), expected.len(), "{got:?}\n{expected:?}");
        for (g, e) in got.iter().zip(&expected) {
            assert_eq!(g["code"], e["code"]);
            // The notes ("did you mean …") follow the message, where every client shows them.
            let mut lines = vec![e["message"].as_str().unwrap()];
            lines.extend(e["notes"].as_array().unwrap().iter().map(|n| n.as_str().unwrap()));
            assert_eq!(g["message"], json!(lines.join("\n")));
            // `check` counts from 1, the protocol from 0 (the lines are ASCII: columns agree).
            assert_eq!(g["range"]["start"]["line"].as_i64().unwrap() + 1, e["line"].as_i64().unwrap());
            assert_eq!(
                g["range"]["start"]["character"].as_i64().unwrap() + 1,
                e["column"].as_i64().unwrap()
            );
            assert_eq!(g["severity"], json!(1));
            // The code links to the manual's table of codes.
            assert_eq!(g["codeDescription"]["href"], json!(uri(&root().join("docs/diagnostics.md"))));
        }
    }
    let got = in_file(&path);
    assert!(got[0]["message"].as_str().unwrap().contains("gbuf.albdo"));

    // The unsaved fix clears them (the file on disk is still broken).
    c.change(&path, 2, &good);
    assert_eq!(c.diagnostics(&path), Vec::<Value>::new());
    assert_eq!(c.diagnostics(&shader), Vec::<Value>::new());

    // A shader broken in the editor: located in the shader, naming the pipeline checked.
    let shader_text = std::fs::read_to_string(&shader).unwrap();
    c.open(&shader, &shader_text.replacen("fn ", "fn fn ", 1));
    let sd = c.diagnostics(&shader);
    assert!(!sd.is_empty() && sd[0]["code"] == "wgsl-parse", "{sd:?}");
    let related = sd[0]["relatedInformation"].to_string();
    assert!(
        related.contains("deferred.lbp") && related.contains("used by pass `ambient`"),
        "{related}"
    );
    assert_eq!(c.finish(), 0);
}

#[test]
fn malformed_requests_are_answered_and_bad_framing_ends_without_a_panic() {
    let dir = project("malformed");
    let path = dir.join("pipelines/deferred.lbp");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut c = Client::start(&dir);
    c.open(&path, &text);
    // Unknown method, wrong params, a position past the end, a document of another scheme.
    assert_eq!(c.call("lightbench/unknown", json!({}))["error"]["code"], json!(-32601));
    assert_eq!(c.call("textDocument/hover", json!({"nonsense": 1}))["error"]["code"], json!(-32602));
    let far = json!({"textDocument": {"uri": uri(&path)}, "position": {"line": 99999, "character": 5}});
    assert_eq!(c.request("textDocument/hover", far), Value::Null);
    let other = json!({"textDocument": {"uri": "untitled:Untitled-1"}, "position": {"line": 0, "character": 0}});
    assert_eq!(c.request("textDocument/definition", other), Value::Null);
    // A document beyond the size a check reads: an error on it, not a crash.
    let huge = dir.join("pipelines/huge.lbp");
    c.open(&huge, &"// padding\n".repeat(17 << 20 >> 4 << 1));
    let d = c.diagnostics(&huge);
    assert!(d[0]["message"].as_str().unwrap().contains("larger than"), "{d:?}");
    // An include leaving the shader root, or found only outside the workspace, leads nowhere.
    let evil = dir.join("shaders/evil.wgsl");
    let evil_text = "#include \"../pipelines/deferred.lbp\"\n#include \"etc/hostname\"\n";
    c.open(&evil, evil_text);
    for line in [0, 1] {
        let p = json!({"textDocument": {"uri": uri(&evil)}, "position": {"line": line, "character": 12}});
        assert_eq!(c.request("textDocument/definition", p), Value::Null);
    }
    // Bytes that are not JSON: the server stops reading and exits, without a panic.
    c.send_raw(b"{not json");
    drop(c.stdin);
    let code = wait(&mut c.child);
    assert_eq!(code, 1);
}

/// `lightbench lsp` fed `input` raw and then closed: (exit code, stderr, stdout).
fn raw_session(input: &[u8]) -> (i32, String, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_lightbench"))
        .arg("lsp")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let input = input.to_vec();
    let writer = std::thread::spawn(move || {
        let _ = stdin.write_all(&input);
    });
    let out = child.wait_with_output().unwrap();
    let _ = writer.join();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!err.contains("panicked"), "{err}");
    (
        out.status.code().unwrap_or(-1),
        err,
        String::from_utf8_lossy(&out.stdout).into_owned(),
    )
}

fn framed(v: Value) -> Vec<u8> {
    let body = v.to_string();
    format!("Content-Length: {}\r\n\r\n{body}", body.len()).into_bytes()
}

/// The protocol's edges: lengths no one can allocate and endless header lines end the
/// connection with a short error and exit code 1 (they aborted or panicked, or were echoed
/// whole); `exit` without `shutdown` is exit code 1; after `shutdown` a request is an error
/// and `exit` ends with 0.
#[test]
fn the_protocol_edges_end_cleanly_with_the_right_exit_codes() {
    for length in ["1099511627776", "18446744073709551615"] {
        let (code, err, _) = raw_session(format!("Content-Length: {length}\r\n\r\n").as_bytes());
        assert_eq!(code, 1, "{err}");
        assert!(err.contains("over the limit of 67108864 bytes"), "{err}");
    }
    let (code, err, _) = raw_session(&vec![b'x'; 10 << 20]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("a header line is longer than 1024 bytes") && err.len() < 300,
        "{} bytes",
        err.len()
    );
    let init = json!({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}});
    let initialized = json!({"jsonrpc": "2.0", "method": "initialized", "params": {}});
    let exit = json!({"jsonrpc": "2.0", "method": "exit"});
    let (code, err, _) = raw_session(&[framed(init.clone()), framed(initialized.clone()), framed(exit.clone())].concat());
    assert_eq!(code, 1, "exit without shutdown: {err}");
    assert!(err.contains("`exit` came without `shutdown`"), "{err}");
    let shutdown = json!({"jsonrpc": "2.0", "id": 2, "method": "shutdown"});
    let hover = json!({"jsonrpc": "2.0", "id": 3, "method": "textDocument/hover", "params": {"textDocument": {"uri": "file:///x.lbp"}, "position": {"line": 0, "character": 0}}});
    let (code, err, out) = raw_session(&[framed(init), framed(initialized), framed(shutdown), framed(hover), framed(exit)].concat());
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains(r#""id":3"#) && out.contains("-32600") && out.contains("shut down"),
        "{out}"
    );
}

/// Byte offset of a protocol position (UTF-16 columns).
pub(crate) fn byte_at(text: &str, p: &Value) -> usize {
    let (line, col) = (p["line"].as_u64().unwrap() as usize, p["character"].as_u64().unwrap() as usize);
    let start: usize = text.split_inclusive('\n').take(line).map(str::len).sum();
    let mut units = 0;
    for (i, c) in text[start..].char_indices() {
        if units >= col || c == '\n' {
            return start + i;
        }
        units += c.len_utf16();
    }
    text.len()
}

/// The text with a rename's edits applied (last first, so earlier offsets hold).
pub(crate) fn apply(text: &str, edits: &[Value]) -> String {
    let mut spans: Vec<(usize, usize, &str)> = edits
        .iter()
        .map(|e| {
            (
                byte_at(text, &e["range"]["start"]),
                byte_at(text, &e["range"]["end"]),
                e["newText"].as_str().unwrap(),
            )
        })
        .collect();
    spans.sort_by_key(|s| std::cmp::Reverse(s.0));
    let mut out = text.to_string();
    for (a, b, t) in spans {
        out.replace_range(a..b, t);
    }
    out
}

#[test]
fn renaming_a_pass_renames_every_naming_of_it_in_either_front_end() {
    let dir = project("rename");
    let mut c = Client::start(&dir);
    for (file, decl, skip) in [("deferred.lbp", "fullscreen tonemap", 12), ("deferred.ron", "name: \"tonemap\"", 8)] {
        let path = dir.join("pipelines").join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        c.open(&path, &text);
        let mut params = at(&path, &text, decl, skip);
        params["newName"] = json!("tone_map");
        let edit = c.request("textDocument/rename", params);
        let edits = edit["changes"][uri(&path)].as_array().unwrap().clone();
        assert_eq!(edits.len(), 2, "the pass and the variant option substituting its shader: {edits:?}");
        let renamed = apply(&text, &edits);
        // The variant of the same name stays; the file still checks.
        assert!(renamed.contains("tone_map") && renamed.matches("tonemap").count() == text.matches("tonemap").count() - 2);
        std::fs::write(&path, &renamed).unwrap();
        let (code, _, err) = lightbench_in(&dir, &["check", path.to_str().unwrap()]);
        assert_eq!(code, 0, "{file}: {err}");
        // A bad name and a place with nothing to rename are refused.
        let mut bad = at(&path, &renamed, "tone_map", 2);
        bad["newName"] = json!("two words");
        assert_eq!(c.call("textDocument/rename", bad)["error"]["code"], json!(-32602));
    }
    assert_eq!(c.finish(), 0);
}

/// The VS Code extension folder: its manifest names what exists, starts `lightbench lsp`,
/// and its grammar colours every keyword of the LBP grammar.
#[test]
fn the_vscode_extension_is_complete_and_its_grammar_knows_every_keyword() {
    let ext = root().join("editors/vscode");
    let manifest: Value = serde_json::from_str(&std::fs::read_to_string(ext.join("package.json")).unwrap()).unwrap();
    let lang = &manifest["contributes"]["languages"][0];
    assert_eq!(lang["extensions"], json!([".lbp"]));
    for key in [
        &manifest["main"],
        &lang["configuration"],
        &manifest["contributes"]["grammars"][0]["path"],
    ] {
        assert!(ext.join(key.as_str().unwrap()).is_file(), "{key}");
    }
    let js = std::fs::read_to_string(ext.join("extension.js")).unwrap();
    assert!(js.contains("args: ['lsp']") && js.contains("language: 'lbp'"), "{js}");
    let grammar_path = ext.join(manifest["contributes"]["grammars"][0]["path"].as_str().unwrap());
    let grammar: Value = serde_json::from_str(&std::fs::read_to_string(grammar_path).unwrap()).unwrap();
    let words = grammar["repository"]["keyword"]["match"].as_str().unwrap().to_string();
    let words: Vec<&str> = words.trim_start_matches("\\b(").trim_end_matches(")\\b").split('|').collect();
    let pest = std::fs::read_to_string(root().join("compiler/src/front/lbp/lbp.pest")).unwrap();
    let missing: Vec<&str> = pest
        .lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .flat_map(|l| l.split('"').skip(1).step_by(2))
        .filter(|w| w.len() > 1 && w.chars().all(|c| c.is_ascii_alphabetic() || c == '_'))
        .filter(|w| !matches!(*w, "true" | "false") && !words.contains(w))
        .collect();
    assert!(missing.is_empty(), "keywords the grammar does not colour: {missing:?}");
}

/// The README's Neovim snippet is the file the end-to-end test starts Neovim with.
#[test]
fn the_readme_shows_the_neovim_snippet_as_tested() {
    let readme = cli_common::manual();
    let block = readme
        .split("```lua\n")
        .nth(1)
        .and_then(|b| b.split("```").next())
        .expect("a lua block");
    assert_eq!(
        block,
        std::fs::read_to_string(root().join("editors/neovim/lightbench.lua")).unwrap()
    );
}

/// A shader opened before any pipeline: the pipelines under the workspace's `pipelines/` are
/// checked for it. A scene file is checked as `render --scene` reads it.
#[test]
fn a_shader_opened_first_and_a_scene_file_get_their_diagnostics() {
    let dir = project("shader-first");
    let mut c = Client::start(&dir);
    let shader = dir.join("shaders/tonemap.wgsl");
    let text = std::fs::read_to_string(&shader).unwrap();
    c.open(&shader, &text.replacen("fn ", "fn fn ", 1));
    let d = c.diagnostics(&shader);
    assert!(!d.is_empty() && d[0]["code"] == "wgsl-parse", "{d:?}");
    let scene = dir.join("scenes/bad.ron");
    let scene_text = "Scene(\n    camera: Camera(position: (0, 1, 3)),\n    lights: [Point(position: (0, 1, 0), colour: (1, 1, 1))],\n    effects: [Bloom],\n)\n";
    c.open(&scene, scene_text);
    let d = c.diagnostics(&scene);
    assert!(!d.is_empty() && d[0]["message"].as_str().unwrap().contains("colour"), "{d:?}");
    // Completion in a scene file: effects in `effects`, light kinds in `lights`.
    let labels = |r: Value| -> Vec<String> {
        r.as_array()
            .unwrap()
            .iter()
            .map(|i| i["label"].as_str().unwrap().to_string())
            .collect()
    };
    let effects = labels(c.request("textDocument/completion", at(&scene, scene_text, "effects: [", 10)));
    assert!(effects.contains(&"AmbientOcclusion".to_string()), "{effects:?}");
    let kinds = labels(c.request("textDocument/completion", at(&scene, scene_text, "lights: [", 9)));
    assert_eq!(kinds, ["Directional", "Spot", "Point"]);
    assert_eq!(c.finish(), 0);
}

/// Inside a shader: a global the pipeline binds shows the declaration it binds to (and goes
/// there), a parameter-block field its parameter, `frame.` fields their documentation.
#[test]
fn a_shader_global_leads_to_the_declaration_that_binds_it() {
    let dir = project("shader-hover");
    let path = dir.join("pipelines/deferred.lbp");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut c = Client::start(&dir);
    c.open(&path, &text);
    assert_eq!(c.diagnostics(&path), Vec::<Value>::new());
    let shader = dir.join("shaders/ambient.wgsl");
    let src = std::fs::read_to_string(&shader).unwrap();
    let h = c.request("textDocument/hover", at(&shader, &src, "var gbuf_albedo", 6));
    let shown = h["contents"]["value"].as_str().unwrap();
    assert!(
        shown.contains("deferred.lbp") && shown.contains("**texture** `gbuf.albedo`"),
        "{shown}"
    );
    let d = c.request("textDocument/definition", at(&shader, &src, "var gbuf_albedo", 6));
    assert_eq!(d[0]["range"]["start"], pos(&text, "gbuf.albedo: Rgba8Unorm", 0), "{d}");
    let p = c.request("textDocument/hover", at(&shader, &src, "params.color", 8));
    assert!(
        p["contents"]["value"].as_str().unwrap().contains("**parameter** `ambient.color`"),
        "{p}"
    );
    // `#include` leads to the file; `file#entry` in the pipeline to the entry point.
    let inc = c.request("textDocument/definition", at(&shader, &src, "#include \"lib/frame.wgsl\"", 12));
    assert_eq!(inc["uri"], json!(uri(&dir.join("shaders/lib/frame.wgsl"))), "{inc}");
    let entry = c.request(
        "textDocument/definition",
        at(&path, &text, "vertex \"light_volume.wgsl#vs_volume\"", 27),
    );
    let target = dir.join("shaders/light_volume.wgsl");
    assert_eq!(entry["uri"], json!(uri(&target)), "{entry}");
    let target_text = std::fs::read_to_string(&target).unwrap();
    assert_eq!(entry["range"]["start"], pos(&target_text, "vs_volume(", 0), "{entry}");
    // An entry point by name, of a pass whose shader (`light_shadowed.wgsl`, from a template)
    // writes its entry points in the file it includes.
    let entry = c.request("textDocument/definition", at(&path, &text, "fragment fs_forward", 12));
    let target = dir.join("shaders/lib/light_entries.wgsl");
    assert_eq!(entry["uri"], json!(uri(&target)), "{entry}");
    let target_text = std::fs::read_to_string(&target).unwrap();
    assert_eq!(entry["range"]["start"], pos(&target_text, "fs_forward(", 0), "{entry}");
    let taa = dir.join("shaders/taa.wgsl");
    let taa_src = std::fs::read_to_string(&taa).unwrap();
    let f = c.request("textDocument/hover", at(&taa, &taa_src, "frame.resolution", 7));
    let shown = f["contents"]["value"].as_str().unwrap();
    assert!(
        shown.starts_with("**frame** `resolution: vec4<f32>`") && shown.contains("output (viewport) size"),
        "{shown}"
    );
    assert_eq!(c.finish(), 0);
}

/// A pipeline that uses another: a variant's options with their presets, and a definition
/// that leads into the used file.
#[test]
fn hover_shows_presets_and_definition_leads_into_the_used_pipeline() {
    let dir = project("used");
    let path = dir.join("pipelines/deferred_gi.lbp");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut c = Client::start(&dir);
    c.open(&path, &text);
    assert_eq!(c.diagnostics(&path), Vec::<Value>::new());
    let v = c.request("textDocument/hover", at(&path, &text, "variant ao_preset", 9));
    let shown = v["contents"]["value"].as_str().unwrap();
    assert!(shown.contains("- `ssao1` (presets ao.scale = 0.25, ao.samples = 8"), "{shown}");
    // `reads hdr` in this file: `hdr` is declared by the used deferred.lbp.
    let d = c.request("textDocument/definition", at(&path, &text, " hdr", 1));
    let used = dir.join("pipelines/deferred.lbp");
    assert_eq!(d["uri"], json!(uri(&used)), "{d}");
    let used_text = std::fs::read_to_string(&used).unwrap();
    assert_eq!(d["range"]["start"], pos(&used_text, "hdr: Rgba16Float", 0));
    assert_eq!(c.finish(), 0);
}
