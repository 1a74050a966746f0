//! `lightbench lsp` while a user types: completion that replaces the whole dotted word (or
//! path) in every context, hover and definition where the IR keeps no span (formats, entry
//! points, `use`, `after`, `param(…)`), renames that would merge two names refused, and one
//! diagnostic per mistake in a file two pipelines check.

use crate::lsp::{apply, at, pos, project, uri, Client};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// A project of its own with its pipeline `file` open in a server, which finds it clean: the
/// project, the file, its text and the client.
fn opened(tag: &str, file: &str) -> (PathBuf, PathBuf, String, Client) {
    let dir = project(tag);
    let (path, text, c) = open_in(&dir, file);
    (dir, path, text, c)
}

/// `opened` in a project already made (a server of its own).
fn open_in(dir: &Path, file: &str) -> (PathBuf, String, Client) {
    let path = dir.join(file);
    let text = std::fs::read_to_string(&path).unwrap();
    let mut c = Client::start(dir);
    c.open(&path, &text);
    assert_eq!(c.diagnostics(&path), Vec::<Value>::new());
    (path, text, c)
}

/// The completion items at the end of the first `needle` in `text`.
fn complete(c: &mut Client, path: &Path, text: &str, needle: &str) -> Vec<Value> {
    let r = c.request("textDocument/completion", at(path, text, needle, needle.len()));
    r.as_array().unwrap().clone()
}

/// The text after accepting the item labelled `label` (its text edit applied).
fn accept(items: &[Value], text: &str, label: &str) -> String {
    let labels: Vec<&str> = items.iter().map(|i| i["label"].as_str().unwrap()).collect();
    let item = items
        .iter()
        .find(|i| i["label"] == label)
        .unwrap_or_else(|| panic!("`{label}` among {labels:?}"));
    assert_eq!(item["filterText"], json!(label), "{item}");
    apply(text, &[item["textEdit"].clone()])
}

#[test]
fn completion_replaces_the_whole_dotted_word_in_every_context() {
    let (dir, path, good, mut c) = opened("complete-words", "pipelines/deferred.lbp");

    // Half-typed names: the whole dotted word is replaced, whatever the client calls a word.
    let text = good
        .replacen("reads gbuf.albedo, gbuf.emissive", "reads gbuf.alb, gbuf.emissive", 1)
        .replacen("params ambient.color", "params shadow.p", 1);
    c.change(&path, 2, &text);
    let items = complete(&mut c, &path, &text, "reads gbuf.alb");
    assert!(accept(&items, &text, "gbuf.albedo").contains("reads gbuf.albedo, gbuf.emissive"));
    let items = complete(&mut c, &path, &text, "params shadow.p");
    assert!(accept(&items, &text, "peel.layers").contains("\n    params peel.layers\n"));
    assert!(accept(&items, &text, "shadow.pcf").contains("\n    params shadow.pcf\n"));

    // In a choice: an arm's value is the key's (entry points — in a template, of the shaders
    // of the passes like it — and resources), its options the variant's.
    let items = complete(&mut c, &path, &good, "fragment match(gbuffer) { packed: fs_main, fat: fs_");
    assert!(accept(&items, &good, "fs_fat_position").contains("{ packed: fs_main, fat: fs_fat_position }"));
    let items = complete(&mut c, &path, &good, "color match(gbuffer) { packed: gbuf.normal, fat: gbuf.f");
    assert!(accept(&items, &good, "gbuf.fat_normal").contains("fat: gbuf.fat_normal }, gbuf.albedo"));
    let items = complete(&mut c, &path, &good, "fragment match(gbuffer) { pa");
    assert!(accept(&items, &good, "fat").contains("fragment match(gbuffer) { fat: fs_main"));
    // Formats after `texture NAME:`, the word being the whole format.
    let items = complete(&mut c, &path, &good, "texture gbuf.albedo: Rgba");
    assert!(accept(&items, &good, "Rgba16Float").contains("texture gbuf.albedo: Rgba16Float viewport\n"));
    // Shader files in a pass's quotes (below the shader folder, `lib/` too): the path.
    let items = complete(&mut c, &path, &good, "fullscreen ambient \"amb");
    assert!(accept(&items, &good, "taa.wgsl").contains("fullscreen ambient \"taa.wgsl\" like deferred_only, first_light {"));
    assert!(items.iter().any(|i| i["label"] == "lib/material.wgsl"), "{items:?}");

    // Between items: the grammar's top-level keywords.
    let top = good.replacen("\nsampler shadow_cmp", "\ntex\nsampler shadow_cmp", 1);
    c.change(&path, 3, &top);
    let items = complete(&mut c, &path, &top, "\ntex");
    assert!(accept(&items, &top, "texture").contains("\ntexture\nsampler shadow_cmp"));
    assert!(items.iter().any(|i| i["label"] == "acceleration_structure"));
    assert!(!items.iter().any(|i| i["label"] == "reads"), "{items:?}");
    assert_eq!(c.finish(), 0);

    // In a pipeline that uses another: passes after `after` (the used file's too), files
    // beside it after `use` (not itself).
    let (gi, gi_text, mut c) = open_in(&dir, "pipelines/deferred_gi.lbp");
    let items = complete(&mut c, &gi, &gi_text, "    after amb");
    // (the AO passes' group says `after ambient` for them)
    assert!(accept(&items, &gi_text, "light_point").contains("group ambient_occlusion {\n    after light_point\n\n    fullscreen ssao"));
    let items = complete(&mut c, &gi, &gi_text, "use \"defe");
    assert!(accept(&items, &gi_text, "deferred.ron").contains("use \"deferred.ron\"\n"));
    assert!(!items.iter().any(|i| i["label"] == "deferred_gi.lbp"), "{items:?}");
    assert_eq!(c.finish(), 0);
}

#[test]
fn hover_and_definition_reach_formats_entry_points_uses_after_and_param_names() {
    let (dir, path, text, mut c) = opened("definitions", "pipelines/deferred.lbp");
    let hover = |c: &mut Client, path: &Path, text: &str, needle: &str, skip: usize| {
        let h = c.request("textDocument/hover", at(path, text, needle, skip));
        h["contents"]["value"].as_str().unwrap_or_default().to_string()
    };
    let definition = |c: &mut Client, path: &Path, text: &str, needle: &str, skip: usize| {
        c.request("textDocument/definition", at(path, text, needle, skip))
    };

    let f = hover(&mut c, &path, &text, "gbuf.albedo: Rgba8Unorm", 15);
    assert!(
        f.starts_with("**format** `Rgba8Unorm`: 4 bytes per texel, 4 channels of float"),
        "{f}"
    );
    assert!(f.contains("Can be a color target, filtered, blended, a storage texture"), "{f}");
    let d = hover(&mut c, &path, &text, "gbuf.depth: Depth32Float", 13);
    assert!(d.contains("1 channel of depth") && d.contains("Can be a depth target"), "{d}");

    // Entry points: of a single stage and of each arm of a choice.
    let shader = dir.join("shaders/gbuffer.wgsl");
    let shader_text = std::fs::read_to_string(&shader).unwrap();
    for (needle, entry) in [("fragment fs_fat_position", "fs_fat_position("), ("fat: fs_fat }", "fs_fat(")] {
        let skip = needle.find("fs_").unwrap() + 2;
        let d = definition(&mut c, &path, &text, needle, skip);
        assert_eq!(d["uri"], json!(uri(&shader)), "{needle}: {d}");
        assert_eq!(d["range"]["start"], pos(&shader_text, &format!("fn {entry}"), 3), "{needle}");
    }
    // `repeat param(peel.layers)`: the parameter.
    let d = definition(&mut c, &path, &text, "repeat param(peel.layers)", 15);
    assert_eq!(d["range"]["start"], pos(&text, "param peel.layers", 6));
    // A pass choosing by light kind: hover shows each pass it makes; it is not renamed alone
    // (its passes' names follow it).
    let h = hover(&mut c, &path, &text, "fullscreen light like", 12);
    assert!(
        h.starts_with("**fullscreen pass** `light_directional_spot`") && h.contains("**fullscreen pass** `light_point`"),
        "{h}"
    );
    assert!(
        h.contains("runs per Directional or Spot light") && h.contains("runs per Point light"),
        "{h}"
    );
    let mut rename = at(&path, &text, "fullscreen light like", 12);
    rename["newName"] = json!("shade");
    let refused = c.call("textDocument/rename", rename);
    assert!(
        refused["error"]["message"]
            .as_str()
            .unwrap_or_default()
            .contains("one pass per light kind"),
        "{refused}"
    );
    // A template: hover says what it gives and what is like it; definition leads from a
    // `like` to it; a rename renames every `like`.
    let h = hover(&mut c, &path, &text, "like shadowed(maps)", 6);
    assert!(
        h.starts_with("**template** `shadowed(technique)`\n\ngives `per_light`, `when`")
            && h.contains("like it: template `shadow_mapped`, template `shadow_traced`"),
        "{h}"
    );
    let h = hover(&mut c, &path, &text, "template two_sided {", 10);
    assert!(
        h.contains("like it: template `blended_surfaces`, pass `gbuffer`, pass `gbuffer_fat_position`, group `shadow_maps`"),
        "{h}"
    );
    let d = definition(&mut c, &path, &text, "like shadowed(rt)", 6);
    assert_eq!(d["range"]["start"], pos(&text, "shadowed(technique) {", 0), "{d}");
    let mut rename = at(&path, &text, "template two_sided {", 10);
    rename["newName"] = json!("both_faces");
    let edits = c.request("textDocument/rename", rename);
    let edits = edits["changes"][uri(&path)].as_array().unwrap().clone();
    let renamed = apply(&text, &edits);
    assert_eq!(
        renamed.matches("both_faces").count(),
        text.matches("two_sided").count(),
        "{renamed}"
    );
    assert!(!renamed.contains("two_sided") && renamed.contains("group forward_models like both_faces {"));
    assert_eq!(c.finish(), 0);

    let (gi, gi_text, mut c) = open_in(&dir, "pipelines/deferred_gi.lbp");
    // `use "deferred.lbp"`: the file.
    let d = definition(&mut c, &gi, &gi_text, "use \"deferred.lbp\"", 7);
    assert_eq!(d["uri"], json!(uri(&path)), "{d}");
    let h = hover(&mut c, &gi, &gi_text, "use \"deferred.lbp\"", 7);
    // What the composed pipeline keeps of the used file's declarations (some are replaced,
    // removed or fixed by this one): as many as it declares at most, and some.
    let declared = |word: &str| text.lines().filter(|l| l.starts_with(word)).count();
    // Passes, grouped ones too (indented).
    let pass = |word: &str| text.lines().filter(|l| l.trim_start().starts_with(word)).count();
    let passes = pass("raster ") + pass("fullscreen ") + pass("compute ");
    let counts: Vec<usize> = h.split([' ', ',']).filter_map(|w| w.parse().ok()).collect();
    assert!(h.starts_with("**uses** `pipelines/deferred.lbp`: "), "{h}");
    let most = [
        declared("param "),
        declared("texture ") + declared("buffer ") + declared("acceleration_structure "),
        passes,
        declared("variant "),
    ];
    assert!(
        counts.len() == 4 && counts.iter().zip(most).all(|(&c, m)| 0 < c && c <= m),
        "{h} {most:?}"
    );
    // `after ambient`: the pass, declared in the used file; hover says what it is.
    let d = definition(&mut c, &gi, &gi_text, "    after ambient", 12);
    assert_eq!(d["uri"], json!(uri(&path)), "{d}");
    assert_eq!(d["range"]["start"], pos(&text, "fullscreen ambient", 11));
    let h = hover(&mut c, &gi, &gi_text, "    after ambient", 12);
    assert!(h.starts_with("**fullscreen pass** `ambient`"), "{h}");
    // `viewport*param(ao.scale)`: the parameter.
    let d = definition(&mut c, &gi, &gi_text, "viewport*param(ao.scale)", 17);
    assert_eq!(d["range"]["start"], pos(&gi_text, "param ao.scale", 6));
    assert_eq!(c.finish(), 0);
}

#[test]
fn a_rename_to_a_name_in_use_is_refused() {
    let (_, path, text, mut c) = opened("rename-clash", "pipelines/deferred.lbp");
    // At the name after the declaring keyword.
    let rename = |c: &mut Client, needle: &str, to: &str| {
        let mut p = at(&path, &text, needle, needle.find(' ').unwrap() + 2);
        p["newName"] = json!(to);
        c.call("textDocument/rename", p)
    };
    for (needle, to, says) in [
        (
            "texture gbuf.albedo",
            "gbuf.emissive",
            "a resource named `gbuf.emissive` exists already",
        ),
        ("sampler taa_linear", "hdr", "a sampler named `hdr` exists already"),
        ("param tonemap.key", "exposure.ev", "a parameter named `exposure.ev` exists already"),
    ] {
        let r = rename(&mut c, needle, to);
        assert_eq!(r["error"]["message"], json!(says), "{needle}: {r}");
    }
    // A free name is accepted.
    let ok = rename(&mut c, "texture gbuf.albedo", "gbuf.base_color");
    assert!(ok["result"]["changes"].as_object().is_some_and(|c| !c.is_empty()), "{ok}");
    assert_eq!(c.finish(), 0);
}

#[test]
fn a_mistake_in_a_file_two_pipelines_check_is_one_diagnostic() {
    let dir = project("one-per-mistake");
    let (path, gi) = (dir.join("pipelines/deferred.lbp"), dir.join("pipelines/deferred_gi.lbp"));
    let good = std::fs::read_to_string(&path).unwrap();
    let mut c = Client::start(&dir);
    c.open(&gi, &std::fs::read_to_string(&gi).unwrap());
    assert_eq!(c.diagnostics(&gi), Vec::<Value>::new());
    // deferred_gi.lbp uses deferred.lbp: both checks find the typo.
    let broken = good.replacen("reads gbuf.albedo, gbuf.emissive", "reads gbuf.albdo, gbuf.emissive", 1);
    c.open(&path, &broken);
    let got = c.diagnostics(&path);
    let typo: Vec<&Value> = got.iter().filter(|d| d["code"] == "unknown-resource").collect();
    assert_eq!(typo.len(), 1, "{got:?}");
    assert_eq!(
        typo[0]["message"],
        json!("no resource named `gbuf.albdo`\ndid you mean `gbuf.albedo`?")
    );
    // The shader's error (the read is missing) once too: first as the edited pipeline's own
    // check found it (it is checked first), then naming both pipelines.
    let shader = dir.join("shaders/ambient.wgsl");
    let related = |sd: Vec<Value>| {
        assert_eq!(sd.len(), 1, "{sd:?}");
        sd[0]["relatedInformation"].to_string()
    };
    let first = related(c.diagnostics(&shader));
    assert!(
        first.contains("found checking `pipelines/deferred.lbp`") && !first.contains("deferred_gi"),
        "{first}"
    );
    let then = related(c.diagnostics(&shader));
    assert!(
        then.contains("found checking `pipelines/deferred.lbp`") && then.contains("found checking `pipelines/deferred_gi.lbp`"),
        "{then}"
    );
    assert_eq!(c.finish(), 0);
}

/// A document that is no file (never saved): checked while open, cleared when closed (a
/// saved one closed is checked again as the disk holds it).
#[test]
fn closing_an_unsaved_document_clears_its_diagnostics() {
    let dir = project("unsaved");
    let path = dir.join("pipelines/draft.lbp");
    let good = std::fs::read_to_string(dir.join("pipelines/deferred.lbp")).unwrap();
    let broken = good.replacen("reads gbuf.albedo, gbuf.emissive", "reads gbuf.albdo, gbuf.emissive", 1);
    let mut c = Client::start(&dir);
    c.open(&path, &broken);
    assert!(c.diagnostics(&path).iter().any(|d| d["code"] == "unknown-resource"));
    c.notify("textDocument/didClose", json!({"textDocument": {"uri": uri(&path)}}));
    assert_eq!(c.diagnostics(&path), Vec::<Value>::new());
    assert!(!path.exists());
    assert_eq!(c.finish(), 0);
}

/// The editor's text is held to the limit a file on disk is: over 16 MiB, `file-too-large`
/// (as `check` says of such a file), located at the top, the path relative.
#[test]
fn a_document_over_16_mib_is_file_too_large() {
    let dir = project("too-large");
    let path = dir.join("pipelines/huge.lbp");
    let mut c = Client::start(&dir);
    c.open(&path, &format!("pipeline huge\n// {}\n", "x".repeat(17 << 20)));
    let d = c.diagnostics(&path);
    assert_eq!(d.len(), 1, "{d:?}");
    assert_eq!(d[0]["code"], "file-too-large");
    // Paths as `check` run in the project prints them: relative to the workspace folder.
    assert_eq!(
        d[0]["message"],
        "cannot read pipeline `pipelines/huge.lbp`: larger than the 16 MiB limit (the text held in memory)"
    );
    assert_eq!(d[0]["range"]["start"], json!({"line": 0, "character": 0}));
    assert_eq!(c.finish(), 0);
}

/// Requests do not put the check off: with a quiet time of at most 1.5 s (before any check
/// has been timed, a quarter of that: 375 ms) and a hover every 100 ms after the edit, the
/// diagnostics still come while the hovers go on. (When every message restarted the wait, they came only after the
/// requests stopped.) In process, the server's own loop.
#[test]
fn requests_do_not_delay_the_check_after_an_edit() {
    use lsp_server::{Connection, Message, Notification, Request, RequestId};
    let dir = project("quiet");
    let path = dir.join("pipelines/deferred.lbp");
    let text = std::fs::read_to_string(&path).unwrap();
    let (server, client) = Connection::memory();
    let running = std::thread::spawn(move || lightbench::lsp::serve(&server, std::time::Duration::from_millis(1500)));
    let send = |m: Message| client.sender.send(m).unwrap();
    send(Request::new(RequestId::from(0), "initialize".into(), json!({"capabilities": {}})).into());
    send(Notification::new("initialized".into(), json!({})).into());
    let doc = json!({"uri": uri(&path), "languageId": "lbp", "version": 1, "text": text});
    send(Notification::new("textDocument/didOpen".into(), json!({"textDocument": doc})).into());
    let (mut answered, mut published) = (0, false);
    for id in 1..=200 {
        let hover = at(&path, &text, "params ambient.color", 8);
        send(Request::new(RequestId::from(id), "textDocument/hover".into(), hover).into());
        std::thread::sleep(std::time::Duration::from_millis(100));
        for m in client.receiver.try_iter() {
            match m {
                Message::Response(r) if r.id != RequestId::from(0) => answered += 1,
                Message::Notification(n) if n.method == "textDocument/publishDiagnostics" && n.params["uri"] == json!(uri(&path)) => {
                    published = true
                }
                _ => {}
            }
        }
        if published {
            break;
        }
    }
    assert!(published, "no diagnostics while requests kept coming ({answered} hovers answered)");
    assert!(answered >= 5, "the hovers were answered meanwhile: {answered}");
    send(Request::new(RequestId::from(9999), "shutdown".into(), json!(null)).into());
    send(Notification::new("exit".into(), json!(null)).into());
    assert_eq!(running.join().unwrap(), Ok(()));
}

/// Named conditions in the editor: hover on a use shows the condition, definition goes to the
/// `let`, completion in a `when` offers the names (and the conditions' words), and a rename
/// renames every use.
#[test]
fn named_conditions_hover_define_complete_and_rename() {
    let (_, path, text, mut c) = opened("lets", "pipelines/deferred.lbp");
    let h = c.request("textDocument/hover", at(&path, &text, "when deferred", 7));
    let shown = h["contents"]["value"].as_str().unwrap_or_default();
    assert!(
        shown.starts_with("**let** `deferred` = `Any(Variant(\"lighting\", \"deferred_fullscreen\")"),
        "{shown}"
    );
    let area = "when all(variant(area_lights, ltc | ltc_shadowed), deferred)";
    let d = c.request("textDocument/definition", at(&path, &text, area, area.len() - 4));
    assert_eq!(d["range"]["start"], pos(&text, "let deferred", 4), "{d}");

    let typed = text.replacen(area, "when all(def", 1);
    c.change(&path, 2, &typed);
    let items = complete(&mut c, &path, &typed, "when all(def");
    assert!(accept(&items, &typed, "deferred").contains("when all(deferred\n"));
    let labels: Vec<&str> = items.iter().filter_map(|i| i["label"].as_str()).collect();
    assert!(labels.contains(&"variant") && labels.contains(&"not"), "{labels:?}");
    c.change(&path, 3, &text);

    let mut p = at(&path, &text, "let deferred", 4);
    p["newName"] = json!("reads_gbuffer");
    let r = c.call("textDocument/rename", p);
    let edits = r["result"]["changes"][uri(&path)].as_array().cloned().unwrap_or_default();
    let uses = text.matches("deferred\n").count() + text.matches("deferred,").count() + text.matches("deferred)").count();
    assert_eq!(edits.len(), uses, "{r}");
    let renamed = apply(&text, &edits);
    assert!(
        renamed.contains("let reads_gbuffer = variant(lighting")
            && renamed.contains("when all(variant(area_lights, ltc | ltc_shadowed), reads_gbuffer)")
            && renamed.contains("template deferred_only {\n    when reads_gbuffer\n")
    );
    assert_eq!(c.finish(), 0);
}
