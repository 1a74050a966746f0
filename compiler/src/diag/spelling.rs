//! Diagnostics' spelling: checks exist once and write their hints in RON; a diagnostic about
//! an `.lbp` file shows the RON forms it quotes as LBP would write them.

/// `text` with every backticked RON form the checks quote rewritten in LBP.
pub fn spell(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut parts = text.split('`');
    out.push_str(parts.next().unwrap_or(""));
    for (i, part) in parts.enumerate() {
        out.push('`');
        // Odd parts (the 1st, 3rd, ... after the first split) are inside backticks.
        out.push_str(&if i % 2 == 0 { form(part) } else { part.to_string() });
    }
    out
}

/// One quoted form in LBP: whole forms first, then the calls inside conditions and reads.
fn form(ron: &str) -> String {
    let whole = match ron {
        "history: true" => Some("history"),
        "always: true" => Some("always"),
        "load: Load" => Some("load"),
        "write: false" => Some("nowrite"),
        "values" => Some("set"),
        "bind: {...}" => Some("bind NAME = RESOURCE"),
        "per_light: [..]" => Some("per_light(..)"),
        "per_mip: (from, to)" => Some("per_mip FROM..TO"),
        "Fixed(width, height)" => Some("WIDTHxHEIGHT"),
        _ => None,
    };
    if let Some(w) = whole {
        return w.to_string();
    }
    if let Some(rest) = ron.strip_prefix("bind: {").and_then(|r| r.strip_suffix('}')) {
        let pairs: Vec<String> = rest
            .split(", ")
            .filter_map(|kv| kv.split_once(": "))
            .map(|(k, v)| format!("{} = {}", unquote(k), unquote(v)))
            .collect();
        return format!("bind {}", pairs.join(", "));
    }
    if let Some(rest) = ron.strip_prefix("draw: ") {
        return format!("draw {}", calls(rest));
    }
    if let Some(rest) = ron.strip_prefix("when: ") {
        return format!("when {}", calls(rest));
    }
    calls(ron)
}

/// `Prev("x")`, `Mip("x", 2)`, `Layer("x", n)`, `Variant("v", "o")`, `Effect(Ssr)`, `Not(..)`,
/// `All([..])`, `Any([..])`, `Triangles(..)`: the LBP calls (lowercase, names unquoted, no list
/// brackets).
fn calls(ron: &str) -> String {
    const NAMES: [(&str, &str); 10] = [
        ("Prev(", "prev("),
        ("Mip(", "mip("),
        ("Layer(", "layer("),
        ("Variant(", "variant("),
        ("Effect(", "effect("),
        ("Light(", "light("),
        ("Toggle(", "toggle("),
        ("All([", "all("),
        ("Any([", "any("),
        ("Triangles(", "triangles("),
    ];
    let mut s = ron.to_string();
    let mut changed = false;
    for (from, to) in NAMES {
        if s.contains(from) {
            s = s.replace(from, to);
            changed = true;
        }
    }
    while let Some(i) = s.find("Not(") {
        // `Not(c)` is `not c`: drop the call's own parentheses.
        let inner_start = i + "Not(".len();
        let mut depth = 1;
        let close = s[inner_start..].char_indices().find_map(|(j, c)| {
            depth += match c {
                '(' => 1,
                ')' => -1,
                _ => 0,
            };
            (depth == 0).then_some(inner_start + j)
        });
        let Some(close) = close else { break };
        s = format!("{}not {}{}", &s[..i], &s[inner_start..close], &s[close + 1..]);
        changed = true;
    }
    if !changed {
        return ron.to_string();
    }
    s.replace("])", ")")
        .replace("Reflective", "reflective")
        .replace("Blended", "blended")
        .replace('"', "")
}

fn unquote(s: &str) -> &str {
    s.trim().trim_matches('"')
}

#[cfg(test)]
mod tests {
    use super::spell;

    #[test]
    fn ron_forms_become_lbp() {
        for (ron, lbp) in [
            (
                "declare `hdr` with `history: true` and read `Prev(\"hdr\")`",
                "declare `hdr` with `history` and read `prev(hdr)`",
            ),
            (
                "or map it with `bind: {\"input\": \"resource\"}`",
                "or map it with `bind input = resource`",
            ),
            ("set it under `values`", "set it under `set`"),
            (
                "`when: All([Effect(Ssr), Not(Reflective)])`",
                "`when all(effect(Ssr), not reflective)`",
            ),
            ("`Not(Variant(\"a\", \"b\"))`", "`not variant(a, b)`"),
            (
                "`Variant(\"ao\", \"ssao\")` and `draw: Triangles(..)`",
                "`variant(ao, ssao)` and `draw triangles(..)`",
            ),
            ("plain `gbuf.depth` text", "plain `gbuf.depth` text"),
        ] {
            assert_eq!(spell(ron), lbp);
        }
    }
}
