//! Text mutations for the robustness tests (scene files, sweep specs, view scripts): byte
//! flips, token deletions and duplications, swapped lines, numbers replaced by NaN, infinity,
//! values beyond f32 and negatives.

#![allow(dead_code)]

use proptest::prelude::*;

/// One mutation of a text file.
#[derive(Clone, Debug)]
pub enum Mutation {
    FlipByte(usize, u8),
    DeleteToken(usize),
    DuplicateToken(usize),
    SwapLines(usize, usize),
    ReplaceNumber(usize, &'static str),
}

pub const NUMBERS: [&str; 9] = ["NaN", "inf", "-inf", "1e39", "-1e39", "1e30", "-3.5", "0", "0.0"];

/// Byte ranges of tokens: runs of word characters and single punctuation.
pub fn tokens(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let (mut out, mut i) = (vec![], 0);
    while i < b.len() {
        let word = |c: u8| c.is_ascii_alphanumeric() || c == b'_' || c == b'.' || c == b'-';
        if b[i].is_ascii_whitespace() {
            i += 1;
        } else if word(b[i]) {
            let s = i;
            while i < b.len() && word(b[i]) {
                i += 1;
            }
            out.push((s, i));
        } else {
            out.push((i, i + 1));
            i += 1;
        }
    }
    out
}

pub fn mutate(text: &str, m: &Mutation) -> Vec<u8> {
    let toks = tokens(text);
    let mut bytes = text.as_bytes().to_vec();
    match *m {
        Mutation::FlipByte(i, x) => {
            let i = i % bytes.len();
            bytes[i] ^= x.max(1);
        }
        Mutation::DeleteToken(i) => {
            let (s, e) = toks[i % toks.len()];
            bytes.drain(s..e);
        }
        Mutation::DuplicateToken(i) => {
            let (s, e) = toks[i % toks.len()];
            let t = bytes[s..e].to_vec();
            bytes.splice(e..e, t);
        }
        Mutation::SwapLines(a, b) => {
            let mut lines: Vec<&str> = text.lines().collect();
            let n = lines.len();
            lines.swap(a % n, b % n);
            bytes = lines.join("\n").into_bytes();
        }
        Mutation::ReplaceNumber(i, n) => {
            let nums: Vec<_> = toks
                .iter()
                .filter(|(s, _)| text.as_bytes()[*s].is_ascii_digit() || text.as_bytes()[*s] == b'-')
                .collect();
            if let Some((s, e)) = nums.get(i % nums.len().max(1)) {
                bytes.splice(*s..*e, n.bytes());
            }
        }
    }
    bytes
}

pub fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, x)| Mutation::FlipByte(i, x)),
        any::<usize>().prop_map(Mutation::DeleteToken),
        any::<usize>().prop_map(Mutation::DuplicateToken),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        (any::<usize>(), prop::sample::select(NUMBERS.to_vec())).prop_map(|(i, n)| Mutation::ReplaceNumber(i, n)),
    ]
}
