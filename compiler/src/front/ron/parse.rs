//! The RON parser: text -> the spanned syntax tree, keeping the span of every key and value.
//!
//! The `ron` crate's serde path loses positions once a value is deserialized, and every
//! semantic diagnostic (unknown key, bad value, wrong type) needs file:line:col. So RON's
//! syntax is read into `syntax::tree` here and lowered like every other front end's tree.
//! The grammar follows the RON spec: structs, tuples, lists, maps, strings (with escapes and
//! raw strings), numbers, bools, unit enums, comments.

use crate::diag::{Code, Diagnostic};
use crate::span::{FileId, Span};
use crate::tree::{Node, Value};

pub fn parse(file: FileId, src: &str) -> Result<Node, Diagnostic> {
    let mut p = Parser {
        src,
        bytes: src.as_bytes(),
        pos: 0,
        file,
        depth: 0,
    };
    p.skip_ws()?;
    p.skip_attributes()?;
    let node = p.value()?;
    p.skip_ws()?;
    if p.pos < p.bytes.len() {
        return Err(p.err_here("unexpected text after the pipeline value", 1));
    }
    Ok(node)
}

struct Parser<'a> {
    src: &'a str,
    bytes: &'a [u8],
    pos: usize,
    file: FileId,
    depth: usize,
}

const MAX_DEPTH: usize = crate::front::MAX_NESTING;

impl<'a> Parser<'a> {
    fn span(&self, start: usize) -> Span {
        Span::new(self.file, start, self.pos)
    }

    fn err_here(&self, msg: impl Into<String>, len: usize) -> Diagnostic {
        let end = (self.pos + len).min(self.bytes.len());
        Diagnostic::error(Code::RonSyntax, msg, Span::new(self.file, self.pos, end))
    }

    fn found(&self) -> String {
        match self.src[self.pos..].chars().next() {
            None => "end of file".into(),
            Some(c) => format!("`{c}`"),
        }
    }

    fn peek(&self) -> Option<u8> {
        self.bytes.get(self.pos).copied()
    }

    fn skip_ws(&mut self) -> Result<(), Diagnostic> {
        loop {
            match self.peek() {
                Some(b' ' | b'\t' | b'\n' | b'\r') => self.pos += 1,
                Some(b'/') if self.bytes.get(self.pos + 1) == Some(&b'/') => {
                    while let Some(c) = self.peek() {
                        if c == b'\n' {
                            break;
                        }
                        self.pos += 1;
                    }
                }
                Some(b'/') if self.bytes.get(self.pos + 1) == Some(&b'*') => {
                    let start = self.pos;
                    self.pos += 2;
                    let mut nest = 1;
                    while nest > 0 {
                        if self.pos >= self.bytes.len() {
                            return Err(Diagnostic::error(
                                Code::RonSyntax,
                                "unterminated block comment",
                                Span::new(self.file, start, start + 2),
                            ));
                        }
                        if self.bytes[self.pos..].starts_with(b"*/") {
                            nest -= 1;
                            self.pos += 2;
                        } else if self.bytes[self.pos..].starts_with(b"/*") {
                            nest += 1;
                            self.pos += 2;
                        } else {
                            self.pos += 1;
                        }
                    }
                }
                _ => return Ok(()),
            }
        }
    }

    /// `#![enable(...)]` extension attributes are accepted and ignored.
    fn skip_attributes(&mut self) -> Result<(), Diagnostic> {
        while self.bytes[self.pos..].starts_with(b"#![") {
            while let Some(c) = self.peek() {
                self.pos += 1;
                if c == b']' {
                    break;
                }
            }
            self.skip_ws()?;
        }
        Ok(())
    }

    fn expect(&mut self, c: u8, what: &str) -> Result<(), Diagnostic> {
        self.skip_ws()?;
        if self.peek() == Some(c) {
            self.pos += 1;
            Ok(())
        } else {
            Err(self.err_here(format!("expected {what}, found {}", self.found()), 1))
        }
    }

    fn value(&mut self) -> Result<Node, Diagnostic> {
        self.skip_ws()?;
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            let msg = format!("values nested more than {MAX_DEPTH} levels deep");
            let d = self.err_here(msg, 1);
            return Err(Diagnostic {
                code: Code::NestingTooDeep,
                ..d
            });
        }
        let start = self.pos;
        let v = match self.peek() {
            None => return Err(self.err_here("expected a value, found end of file", 0)),
            Some(b'"') => Value::Str(self.string()?),
            Some(b'r') if matches!(self.bytes.get(self.pos + 1), Some(b'"' | b'#')) => Value::Str(self.raw_string()?),
            Some(b'[') => self.list()?,
            Some(b'{') => self.map()?,
            Some(b'(') => self.parens(None)?,
            Some(c) if c == b'-' || c == b'+' || c == b'.' || c.is_ascii_digit() => self.number()?,
            Some(c) if c == b'_' || c.is_ascii_alphabetic() => {
                let ident = self.ident();
                let ispan = self.span(start);
                match ident.as_str() {
                    "true" => Value::Bool(true),
                    "false" => Value::Bool(false),
                    "inf" => Value::Float(f64::INFINITY),
                    "NaN" => Value::Float(f64::NAN),
                    _ => {
                        self.skip_ws()?;
                        if self.peek() == Some(b'(') {
                            self.parens(Some((ident, ispan)))?
                        } else {
                            Value::Ident(ident)
                        }
                    }
                }
            }
            Some(_) => return Err(self.err_here(format!("expected a value, found {}", self.found()), 1)),
        };
        self.depth -= 1;
        Ok(Node::new(v, self.span(start)))
    }

    fn ident(&mut self) -> String {
        let start = self.pos;
        while let Some(c) = self.peek() {
            if c == b'_' || c.is_ascii_alphanumeric() {
                self.pos += 1;
            } else {
                break;
            }
        }
        self.src[start..self.pos].to_string()
    }

    fn number(&mut self) -> Result<Value, Diagnostic> {
        let start = self.pos;
        if matches!(self.peek(), Some(b'-' | b'+')) {
            self.pos += 1;
        }
        if self.bytes[self.pos..].starts_with(b"inf") {
            self.pos += 3;
            let neg = self.bytes[start] == b'-';
            return Ok(Value::Float(if neg { f64::NEG_INFINITY } else { f64::INFINITY }));
        }
        let body = self.pos;
        let mut is_float = false;
        if self.bytes[self.pos..].starts_with(b"0x") {
            self.pos += 2;
            let hs = self.pos;
            while self.peek().is_some_and(|c| c.is_ascii_hexdigit() || c == b'_') {
                self.pos += 1;
            }
            let digits: String = self.src[hs..self.pos].chars().filter(|c| *c != '_').collect();
            let v = i64::from_str_radix(&digits, 16)
                .map_err(|_| Diagnostic::error(Code::RonSyntax, "invalid hexadecimal number", self.span(start)))?;
            return Ok(Value::Int(if self.bytes[start] == b'-' { -v } else { v }));
        }
        while let Some(c) = self.peek() {
            match c {
                b'0'..=b'9' | b'_' => self.pos += 1,
                b'.' | b'e' | b'E' => {
                    is_float = true;
                    self.pos += 1;
                    if (c == b'e' || c == b'E') && matches!(self.peek(), Some(b'-' | b'+')) {
                        self.pos += 1;
                    }
                }
                _ => break,
            }
        }
        if self.pos == body {
            return Err(Diagnostic::error(
                Code::RonSyntax,
                "expected a number",
                Span::new(self.file, start, start + 1),
            ));
        }
        // A number glued to letters (`12px`) is a typo, not two tokens.
        if self.peek().is_some_and(|c| c.is_ascii_alphabetic()) {
            while self.peek().is_some_and(|c| c.is_ascii_alphanumeric()) {
                self.pos += 1;
            }
            return Err(Diagnostic::error(
                Code::RonSyntax,
                format!("invalid number `{}`", &self.src[start..self.pos]),
                self.span(start),
            ));
        }
        let text: String = self.src[start..self.pos].chars().filter(|c| *c != '_').collect();
        if is_float {
            text.parse::<f64>()
                .map(Value::Float)
                .map_err(|_| Diagnostic::error(Code::RonSyntax, format!("invalid number `{text}`"), self.span(start)))
        } else {
            text.parse::<i64>().map(Value::Int).map_err(|_| {
                Diagnostic::error(
                    Code::RonSyntax,
                    format!("invalid or out-of-range integer `{text}`"),
                    self.span(start),
                )
            })
        }
    }

    fn string(&mut self) -> Result<String, Diagnostic> {
        let start = self.pos;
        self.pos += 1;
        let mut out = String::new();
        loop {
            let Some(c) = self.src[self.pos..].chars().next() else {
                return Err(Diagnostic::error(
                    Code::RonSyntax,
                    "unterminated string",
                    Span::new(self.file, start, start + 1),
                ));
            };
            self.pos += c.len_utf8();
            match c {
                '"' => return Ok(out),
                '\\' => {
                    let esc_start = self.pos - 1;
                    let Some(e) = self.src[self.pos..].chars().next() else {
                        return Err(Diagnostic::error(
                            Code::RonSyntax,
                            "unterminated string",
                            Span::new(self.file, start, start + 1),
                        ));
                    };
                    self.pos += e.len_utf8();
                    match e {
                        'n' => out.push('\n'),
                        't' => out.push('\t'),
                        'r' => out.push('\r'),
                        '0' => out.push('\0'),
                        '\\' => out.push('\\'),
                        '"' => out.push('"'),
                        '\'' => out.push('\''),
                        'u' => {
                            let close = self.src[self.pos..].find('}');
                            let parsed = if self.src[self.pos..].starts_with('{') {
                                close
                                    .and_then(|c| u32::from_str_radix(&self.src[self.pos + 1..self.pos + c], 16).ok())
                                    .and_then(char::from_u32)
                            } else {
                                None
                            };
                            match parsed {
                                Some(ch) => {
                                    out.push(ch);
                                    self.pos += close.unwrap_or(0) + 1;
                                }
                                None => {
                                    return Err(Diagnostic::error(
                                        Code::RonSyntax,
                                        "invalid unicode escape, expected `\\u{XXXX}`",
                                        self.span(esc_start),
                                    ))
                                }
                            }
                        }
                        other => {
                            return Err(Diagnostic::error(
                                Code::RonSyntax,
                                format!("unknown escape `\\{other}`"),
                                self.span(esc_start),
                            ))
                        }
                    }
                }
                c => out.push(c),
            }
        }
    }

    fn raw_string(&mut self) -> Result<String, Diagnostic> {
        let start = self.pos;
        self.pos += 1;
        let mut hashes = 0;
        while self.peek() == Some(b'#') {
            hashes += 1;
            self.pos += 1;
        }
        if self.peek() != Some(b'"') {
            return Err(self.err_here("expected `\"` to open a raw string", 1));
        }
        self.pos += 1;
        let close = format!("\"{}", "#".repeat(hashes));
        match self.src[self.pos..].find(&close) {
            Some(i) => {
                let s = self.src[self.pos..self.pos + i].to_string();
                self.pos += i + close.len();
                Ok(s)
            }
            None => Err(Diagnostic::error(
                Code::RonSyntax,
                "unterminated raw string",
                Span::new(self.file, start, start + 1),
            )),
        }
    }

    fn list(&mut self) -> Result<Value, Diagnostic> {
        self.pos += 1;
        let mut items = vec![];
        loop {
            self.skip_ws()?;
            if self.peek() == Some(b']') {
                self.pos += 1;
                return Ok(Value::List(items));
            }
            items.push(self.value()?);
            self.skip_ws()?;
            match self.peek() {
                Some(b',') => self.pos += 1,
                Some(b']') => {}
                _ => return Err(self.err_here(format!("expected `,` or `]` in list, found {}", self.found()), 1)),
            }
        }
    }

    fn map(&mut self) -> Result<Value, Diagnostic> {
        self.pos += 1;
        let mut entries = vec![];
        loop {
            self.skip_ws()?;
            if self.peek() == Some(b'}') {
                self.pos += 1;
                return Ok(Value::Map(entries));
            }
            let k = self.value()?;
            self.expect(b':', "`:` after map key")?;
            let v = self.value()?;
            entries.push((k, v));
            self.skip_ws()?;
            match self.peek() {
                Some(b',') => self.pos += 1,
                Some(b'}') => {}
                _ => return Err(self.err_here(format!("expected `,` or `}}` in map, found {}", self.found()), 1)),
            }
        }
    }

    /// After `Name` (or nothing) and at `(`: a struct if the first item is `ident:`, else a tuple.
    fn parens(&mut self, name: Option<(String, Span)>) -> Result<Value, Diagnostic> {
        self.pos += 1;
        self.skip_ws()?;
        let save = self.pos;
        let is_struct = if self.peek().is_some_and(|c| c == b'_' || c.is_ascii_alphabetic()) {
            self.ident();
            self.skip_ws()?;
            let r = self.peek() == Some(b':');
            self.pos = save;
            r
        } else {
            false
        };
        if is_struct {
            let mut fields = vec![];
            loop {
                self.skip_ws()?;
                if self.peek() == Some(b')') {
                    self.pos += 1;
                    return Ok(Value::Struct { name, fields });
                }
                let kstart = self.pos;
                if !self.peek().is_some_and(|c| c == b'_' || c.is_ascii_alphabetic()) {
                    return Err(self.err_here(format!("expected a field name, found {}", self.found()), 1));
                }
                let key = self.ident();
                let kspan = self.span(kstart);
                self.expect(b':', "`:` after field name")?;
                let v = self.value()?;
                fields.push((key, kspan, v));
                self.skip_ws()?;
                match self.peek() {
                    Some(b',') => self.pos += 1,
                    Some(b')') => {}
                    _ => return Err(self.err_here(format!("expected `,` or `)` after field, found {}", self.found()), 1)),
                }
            }
        } else {
            let mut items = vec![];
            loop {
                self.skip_ws()?;
                if self.peek() == Some(b')') {
                    self.pos += 1;
                    return Ok(Value::Tuple { name, items });
                }
                items.push(self.value()?);
                self.skip_ws()?;
                match self.peek() {
                    Some(b',') => self.pos += 1,
                    Some(b')') => {}
                    _ => return Err(self.err_here(format!("expected `,` or `)` in tuple, found {}", self.found()), 1)),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_nested_values_with_spans() {
        let src = r#"Pipeline(name: "x", list: [1, -2.5, r"raw"], m: {"a": Foo(1, true)}, u: ())"#;
        let n = parse(0, src).unwrap();
        let Value::Struct { name, fields } = &*n.value else { panic!() };
        assert_eq!(name.as_ref().unwrap().0, "Pipeline");
        assert_eq!(fields.len(), 4);
        assert_eq!(&src[fields[0].2.span.range()], "\"x\"");
        assert_eq!(&src[fields[1].1.range()], "list");
    }

    #[test]
    fn syntax_error_points_at_the_problem() {
        let e = parse(0, "Pipeline(name: \"x\" passes: [])").unwrap_err();
        assert!(e.message.contains("expected `,` or `)`"), "{}", e.message);
        assert_eq!(e.primary_span().unwrap().start, 19);
    }

    #[test]
    fn never_panics_on_garbage() {
        for s in [
            "",
            "(",
            "\"",
            "r#\"",
            "/*",
            "0x",
            "-",
            "[1,",
            "{1:",
            "A(b:",
            "\\u",
            "\"\\u{zz}\"",
            "1e",
            "(((((",
        ] {
            let _ = parse(0, s);
        }
    }
}
