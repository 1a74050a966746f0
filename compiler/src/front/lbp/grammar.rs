//! LBP front end, the grammar's words: which keywords may begin a rule, read from `lbp.pest`
//! itself, so that editors (completion) and the grammar never disagree.

const GRAMMAR: &str = include_str!("lbp.pest");

/// The keywords that may begin a top-level item (`param`, `texture`, `raster`, `use`, …), in
/// the grammar's order.
pub fn top_level_keywords() -> Vec<&'static str> {
    let mut out = vec![];
    first_words("item", 0, &mut out);
    out
}

/// A rule's body: the text between its first `{` and the `}` that closes it.
fn body(rule: &str) -> Option<&'static str> {
    // The offset of the `{` that opens the rule's line `NAME = … {`.
    let mut line_start = 0;
    let mut at = None;
    for line in GRAMMAR.split_inclusive('\n') {
        if let Some((name, rest)) = line.split_once('=') {
            if name.trim() == rule {
                at = Some(line_start + name.len() + 1 + rest.find('{')? + 1);
                break;
            }
        }
        line_start += line.len();
    }
    let at = at?;
    // Braces in quotes (`open_brace = { "{" }`) are the language's, not the grammar's.
    let (mut depth, mut quoted) = (1, false);
    for (i, c) in GRAMMAR[at..].char_indices() {
        match c {
            '"' => quoted = !quoted,
            '{' if !quoted => depth += 1,
            '}' if !quoted && depth == 1 => return Some(&GRAMMAR[at..at + i]),
            '}' if !quoted => depth -= 1,
            _ => {}
        }
    }
    None
}

/// The literal words each alternative of `text` begins with (rules followed to their own).
fn first_words(rule: &str, depth: usize, out: &mut Vec<&'static str>) {
    if depth > 8 {
        return;
    }
    if let Some(b) = body(rule) {
        alternatives(b, depth, out);
    }
}

fn alternatives(text: &'static str, depth: usize, out: &mut Vec<&'static str>) {
    for alt in split_top(text, '|') {
        let alt = alt.trim();
        if let Some(rest) = alt.strip_prefix('"') {
            let word = &rest[..rest.find('"').unwrap_or(rest.len())];
            if !out.contains(&word) {
                out.push(word);
            }
        } else if let Some(inner) = alt.strip_prefix('(') {
            let close = split_top(inner, ')').next().unwrap_or("");
            alternatives(close, depth + 1, out);
        } else {
            let name: String = alt.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
            first_words(&name, depth + 1, out);
        }
    }
}

/// `text` split at `sep` outside parentheses and quotes.
fn split_top(text: &'static str, sep: char) -> impl Iterator<Item = &'static str> {
    let (mut depth, mut quoted, mut from) = (0i32, false, 0);
    let mut parts = vec![];
    for (i, c) in text.char_indices() {
        match c {
            '"' => quoted = !quoted,
            '(' if !quoted => depth += 1,
            ')' if !quoted && depth > 0 => depth -= 1,
            c if c == sep && !quoted && depth == 0 => {
                parts.push(&text[from..i]);
                from = i + c.len_utf8();
                if sep == ')' {
                    return parts.into_iter();
                }
            }
            _ => {}
        }
    }
    parts.push(&text[from..]);
    parts.into_iter()
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_top_level_keywords_are_the_items_of_the_grammar() {
        assert_eq!(
            super::top_level_keywords(),
            [
                "param",
                "sampler",
                "texture",
                "buffer",
                "acceleration_structure",
                "let",
                "template",
                "raster",
                "fullscreen",
                "compute",
                "group",
                "variant",
                "hdr_output",
                "output",
                "always",
                "jitter",
                "use",
                "fix",
                "remove",
                "replace"
            ]
        );
    }
}
