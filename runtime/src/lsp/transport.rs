//! Stage `lsp`, its transport: JSON-RPC messages framed by `Content-Length` over stdio, read
//! with the limits lsp-server's own reader lacks (a length it could not allocate aborted the
//! process; a header line was buffered whole, however long). A message over a limit, a
//! malformed header or body ends the connection with one short, clear line on stderr.

use lsp_server::{Connection, Message};
use std::io::{BufRead, Read, Write};
use std::thread::JoinHandle;

/// The largest message read: a 16 MiB document (the most a check reads) JSON-escaped, twice.
pub const MAX_MESSAGE: u64 = 64 << 20;
/// The longest header line (`Content-Length: N`, `Content-Type: ...`).
pub const MAX_HEADER_LINE: u64 = 1024;

/// The reader and writer threads; joining them gives the reader's protocol error, if any.
pub struct IoThreads {
    reader: JoinHandle<Result<(), String>>,
    writer: JoinHandle<()>,
}

impl IoThreads {
    pub fn join(self) -> Result<(), String> {
        let read = self.reader.join().map_err(|_| "the reader thread panicked".to_string())?;
        let _ = self.writer.join();
        read
    }
}

/// A connection over stdin and stdout.
pub fn stdio() -> (Connection, IoThreads) {
    let (to_server, receiver) = crossbeam_channel::bounded::<Message>(0);
    let (sender, from_server) = crossbeam_channel::bounded::<Message>(0);
    let reader = std::thread::spawn(move || {
        let mut input = std::io::stdin().lock();
        loop {
            let msg = match read_message(&mut input) {
                Ok(Some(m)) => m,
                Ok(None) => return Ok(()),
                // (`lightbench lsp` prints it as it exits.)
                Err(e) => return Err(format!("{e}; the connection is closed")),
            };
            let exit = matches!(&msg, Message::Notification(n) if n.method == "exit");
            if to_server.send(msg).is_err() || exit {
                return Ok(());
            }
        }
    });
    let writer = std::thread::spawn(move || {
        let mut out = std::io::stdout().lock();
        for msg in from_server {
            if msg.write(&mut out).and_then(|()| out.flush()).is_err() {
                return;
            }
        }
    });
    (Connection { sender, receiver }, IoThreads { reader, writer })
}

/// The next message; `None` at the end of the input before a message begins.
pub fn read_message(r: &mut impl BufRead) -> Result<Option<Message>, String> {
    let mut length: Option<u64> = None;
    let mut first = true;
    loop {
        let mut line = Vec::new();
        let n = r
            .by_ref()
            .take(MAX_HEADER_LINE + 1)
            .read_until(b'\n', &mut line)
            .map_err(|e| format!("cannot read: {e}"))?;
        if n == 0 {
            return match first {
                true => Ok(None),
                false => Err("the input ended inside a message's header".into()),
            };
        }
        first = false;
        if !line.ends_with(b"\n") {
            return Err(match n as u64 > MAX_HEADER_LINE {
                true => format!("a header line is longer than {MAX_HEADER_LINE} bytes"),
                false => "the input ended inside a message's header".into(),
            });
        }
        let text = String::from_utf8_lossy(&line);
        let text = text.trim_end();
        if text.is_empty() {
            break;
        }
        let (name, value) = text.split_once(':').ok_or_else(|| format!("not a header line: `{}`", clip(text)))?;
        if name.trim().eq_ignore_ascii_case("content-length") {
            let n = value.trim().parse::<u64>();
            length = Some(n.map_err(|_| format!("Content-Length `{}` is not a byte count", clip(value.trim())))?);
        }
    }
    let length = length.ok_or("a message without a Content-Length header")?;
    if length > MAX_MESSAGE {
        return Err(format!(
            "a message of {length} bytes is over the limit of {MAX_MESSAGE} bytes (64 MiB)"
        ));
    }
    let mut body = vec![0u8; length as usize];
    r.read_exact(&mut body)
        .map_err(|e| format!("the input ended inside a message ({e})"))?;
    serde_json::from_slice(&body)
        .map(Some)
        .map_err(|e| format!("a message that is not JSON-RPC: {e}"))
}

/// At most 60 characters of `s`, for a message that quotes the input.
fn clip(s: &str) -> String {
    match s.char_indices().nth(60) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(bytes: &[u8]) -> Result<Option<Message>, String> {
        read_message(&mut std::io::Cursor::new(bytes))
    }

    #[test]
    fn frames_and_limits() {
        let body = br#"{"jsonrpc":"2.0","method":"initialized","params":{}}"#;
        let framed = [format!("Content-Length: {}\r\n\r\n", body.len()).as_bytes(), body].concat();
        assert!(matches!(read(&framed), Ok(Some(Message::Notification(_)))));
        assert!(matches!(read(b""), Ok(None)));
        for huge in ["1099511627776", "18446744073709551615"] {
            let e = read(format!("Content-Length: {huge}\r\n\r\n").as_bytes()).unwrap_err();
            assert!(e.contains("over the limit"), "{e}");
        }
        let long = vec![b'x'; 10 << 20];
        let e = read(&long).unwrap_err();
        assert!(e.contains("longer than 1024 bytes") && e.len() < 200, "{e}");
        let e = read(b"Content-Length: lots\r\n\r\n").unwrap_err();
        assert!(e.contains("not a byte count"), "{e}");
        let e = read(b"Content-Type: x\r\n\r\n{}").unwrap_err();
        assert!(e.contains("without a Content-Length"), "{e}");
    }
}
