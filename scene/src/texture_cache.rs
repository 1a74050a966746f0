//! glTF loading, its textures: images decoded once — in parallel, and kept decoded on disk in
//! a content-addressed cache, so that a second run of the same scene reads texels instead of
//! decoding JPEG and PNG files again.
//!
//! An entry is keyed by a 128-bit hash (XXH3) of the image's encoded bytes (file, buffer view or `data:`
//! URI), their length and this module's `VERSION` (what the decoding makes of them): an image
//! edited in place gets a new key, an old entry is simply never read again. Each entry holds
//! the width, height and a checksum (XXH3) of its texels; one that is short, long or whose
//! texels do not match it (a damaged disk, a killed writer of an older version) is decoded again
//! and rewritten, atomically.
//!
//! A cached image's texels are the entry file mapped into memory, not read into a buffer of
//! their own: a fresh buffer's pages are zeroed by the kernel and then copied into, four times
//! what mapping costs (24 ms against 6 ms for four 2048² images in a fresh process). Entries
//! are only ever replaced by renaming a whole new file over them (`files::write_atomic_parts`),
//! never written in place, so a mapped entry does not change under the texels that use it.
//! Texels decoded now stay the decoded buffer: mapping their new entry back in its place
//! raised a first render's peak (the assets benchmark: 2.1× the GPU-resident bytes against
//! 1.0–1.3×).

use std::path::{Path, PathBuf};

/// Bumped when the decoded texels change for the same encoded bytes.
const VERSION: u32 = 1;
const MAGIC: &[u8; 8] = b"LBTEX\0\0\x01";
const HEADER: usize = 8 + 4 + 4 + 8;
/// The largest entry read: a 32768² RGBA8 image.
const MAX_ENTRY_BYTES: u64 = HEADER as u64 + (4 << 30);
/// Where the cache goes instead of the user's cache folder; empty: no cache.
pub const CACHE_ENV: &str = "LIGHTBENCH_CACHE_DIR";

/// An image decoded to 8-bit RGBA, level 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Texels {
    pub width: u32,
    pub height: u32,
    pub rgba: TexelBytes,
}

/// Texel bytes: decoded now (owned), or a cache entry's mapped into memory (shared by clones).
#[derive(Clone)]
pub enum TexelBytes {
    Owned(Vec<u8>),
    Mapped(std::sync::Arc<Mapped>),
}

/// A cache entry's texels in memory: the file's mapping and where in it they begin.
pub struct Mapped {
    map: memmap2::Mmap,
    start: usize,
}

impl std::ops::Deref for TexelBytes {
    type Target = [u8];
    fn deref(&self) -> &[u8] {
        match self {
            TexelBytes::Owned(v) => v,
            TexelBytes::Mapped(m) => &m.map[m.start..],
        }
    }
}

impl TexelBytes {
    /// The texels to change: a mapped entry's are copied first (the entry is never written).
    pub fn to_mut(&mut self) -> &mut Vec<u8> {
        if let TexelBytes::Mapped(_) = self {
            let mapped = std::mem::replace(self, TexelBytes::Owned(vec![]));
            *self = TexelBytes::Owned(mapped.into_vec());
        }
        match self {
            TexelBytes::Owned(v) => v,
            TexelBytes::Mapped(_) => unreachable!("made owned above"),
        }
    }

    /// The texels as a buffer of their own: a decoded one's as it is, a mapped one's copied.
    pub fn into_vec(self) -> Vec<u8> {
        match self {
            TexelBytes::Owned(v) => v,
            TexelBytes::Mapped(m) => m.map[m.start..].to_vec(),
        }
    }
}

impl FromIterator<u8> for TexelBytes {
    fn from_iter<I: IntoIterator<Item = u8>>(iter: I) -> Self {
        TexelBytes::Owned(iter.into_iter().collect())
    }
}

impl From<Vec<u8>> for TexelBytes {
    fn from(v: Vec<u8>) -> Self {
        TexelBytes::Owned(v)
    }
}

impl PartialEq for TexelBytes {
    fn eq(&self, other: &Self) -> bool {
        self[..] == other[..]
    }
}

impl PartialEq<Vec<u8>> for TexelBytes {
    fn eq(&self, other: &Vec<u8>) -> bool {
        self[..] == other[..]
    }
}

impl std::fmt::Debug for TexelBytes {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let how = match self {
            TexelBytes::Owned(_) => "decoded",
            TexelBytes::Mapped(_) => "mapped",
        };
        write!(f, "{} texel bytes ({how})", self.len())
    }
}

/// How far a model's images have got: `done` of its `total` distinct images, `decoded` of
/// them decoded now (the others read from the cache).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    pub done: usize,
    pub total: usize,
    pub decoded: usize,
}

/// Who is told of decoding progress: the application's, set once (a library draws nothing).
static PROGRESS: std::sync::OnceLock<Box<dyn Fn(Progress) + Send + Sync>> = std::sync::OnceLock::new();

/// Have `report` told how a model's image decoding goes — once with `done` 0, then after each
/// image, from the decoding threads (so in any order) — to show progress. Set once per
/// process; `false` if it was set already.
pub fn on_progress(report: impl Fn(Progress) + Send + Sync + 'static) -> bool {
    PROGRESS.set(Box::new(report)).is_ok()
}

/// Tell the progress observer, if there is one.
pub(crate) fn report(p: Progress) {
    if let Some(f) = PROGRESS.get() {
        f(p);
    }
}

/// Where decoded textures are kept, if anywhere.
#[derive(Clone, Debug)]
pub struct TextureCache {
    dir: Option<PathBuf>,
}

/// How an image was had: from the cache, or decoded now (and whether writing it failed).
pub enum Got {
    Cached,
    Decoded,
    NotKept(String),
}

impl TextureCache {
    /// `$LIGHTBENCH_CACHE_DIR/textures` if set (an empty value: no cache), else the user's
    /// cache folder (`$XDG_CACHE_HOME/lightbench/textures` or `~/.cache/lightbench/textures`),
    /// else none.
    pub fn from_env() -> Self {
        let var = |k: &str| std::env::var_os(k).map(PathBuf::from);
        let root = match var(CACHE_ENV) {
            Some(d) if d.as_os_str().is_empty() => None,
            Some(d) => Some(d),
            None => var("XDG_CACHE_HOME")
                .filter(|d| d.is_absolute())
                .or_else(|| var("HOME").map(|h| h.join(".cache")))
                .map(|d| d.join("lightbench")),
        };
        Self::at(root.as_deref())
    }

    /// A cache under `root` (its `textures` folder), or none.
    pub fn at(root: Option<&Path>) -> Self {
        TextureCache {
            dir: root.map(|r| r.join("textures")),
        }
    }

    /// The entry file for `key`, if there is a cache.
    pub fn entry(&self, key: Key) -> Option<PathBuf> {
        Some(self.dir.as_ref()?.join(format!("{:032x}-{}.rgba", key.hash, key.len)))
    }

    /// The texels of the image of `key`: from the cache when a whole entry is there, else
    /// from `decode`, then kept.
    pub fn get(
        &self,
        key: Key,
        decode: impl FnOnce() -> std::result::Result<Texels, String>,
    ) -> std::result::Result<(Texels, Got), String> {
        let Some(entry) = self.entry(key) else {
            return Ok((decode()?, Got::Decoded));
        };
        if let Some(t) = read_entry(&entry) {
            return Ok((t, Got::Cached));
        }
        let t = decode()?;
        let got = match crate::files::write_atomic_parts(&entry, &[&entry_header(&t), &t.rgba]) {
            Ok(()) => Got::Decoded,
            Err(e) => Got::NotKept(e.to_string()),
        };
        Ok((t, got))
    }
}

/// The texels' checksum, which finds a damaged entry.
/// What an image's texels depend on: its encoded bytes, what they are declared as (a MIME
/// type or file name: what chooses the decoder) and the decoding's `VERSION`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Key {
    hash: u128,
    len: usize,
}

impl Key {
    pub fn of(kind: &str, bytes: &[u8]) -> Key {
        Key {
            hash: xxhash_rust::xxh3::xxh3_128_with_seed(bytes, Key::seed(kind)),
            len: bytes.len(),
        }
    }

    /// `of` the bytes `read` gives, at most `limit` of them (more: an error), hashed a piece
    /// at a time: a file's key without a buffer for the whole file, whose fresh pages the
    /// kernel zeroes before they are copied into — that cost more than the hash.
    pub fn of_read(kind: &str, read: impl std::io::Read, limit: u64) -> std::io::Result<Key> {
        use std::io::Read;
        let mut hash = xxhash_rust::xxh3::Xxh3::with_seed(Key::seed(kind));
        let (mut read, mut piece, mut len) = (read.take(limit + 1), [0u8; 1 << 16], 0u64);
        loop {
            let n = match read.read(&mut piece) {
                Ok(0) => break,
                Ok(n) => n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            hash.update(&piece[..n]);
            len += n as u64;
        }
        if len > limit {
            return Err(lightbench_compiler::vfs::too_large(limit));
        }
        Ok(Key {
            hash: hash.digest128(),
            len: len as usize,
        })
    }

    /// What the hash is seeded with: the declared kind and the decoding's version.
    fn seed(kind: &str) -> u64 {
        xxhash_rust::xxh3::xxh3_64(format!("v{VERSION} rgba8 {kind}").as_bytes())
    }
}

fn texel_hash(rgba: &[u8]) -> u64 {
    xxhash_rust::xxh3::xxh3_64(rgba)
}

/// What an entry holds before the texels: the magic, the size and the texels' checksum.
fn entry_header(t: &Texels) -> [u8; HEADER] {
    let mut head = [0u8; HEADER];
    head[..8].copy_from_slice(MAGIC);
    head[8..12].copy_from_slice(&t.width.to_le_bytes());
    head[12..16].copy_from_slice(&t.height.to_le_bytes());
    head[16..24].copy_from_slice(&texel_hash(&t.rgba).to_le_bytes());
    head
}

/// A whole entry's texels, mapped; `None` for a missing, short, long or damaged one, or for
/// anything but a regular file (a pipe there would wait forever).
fn read_entry(path: &Path) -> Option<Texels> {
    use std::io::Read;
    lightbench_compiler::vfs::regular_file(path, MAX_ENTRY_BYTES).ok()?;
    let mut file = std::fs::File::open(path).ok()?;
    let mut head = [0u8; HEADER];
    file.read_exact(&mut head).ok()?;
    let word = |i: usize| u32::from_le_bytes(head[i..i + 4].try_into().unwrap());
    let (width, height) = (word(8), word(12));
    let hash = u64::from_le_bytes(head[16..24].try_into().unwrap());
    let len = (width as u64) * (height as u64) * 4;
    if &head[..8] != MAGIC || file.metadata().ok()?.len() != HEADER as u64 + len {
        return None;
    }
    // SAFETY: the mapping is read only, of a regular file of the length just checked, which
    // this program never writes in place (see the module's description); `populate` maps every
    // page at once, as the checksum below reads them all anyway.
    let map = unsafe { memmap2::MmapOptions::new().populate().map(&file) }.ok()?;
    let rgba = TexelBytes::Mapped(std::sync::Arc::new(Mapped { map, start: HEADER }));
    (rgba.len() as u64 == len && texel_hash(&rgba) == hash).then_some(Texels { width, height, rgba })
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(unix)]
    use std::os::unix::fs::FileTypeExt;

    fn texels() -> Texels {
        Texels {
            width: 2,
            height: 1,
            rgba: vec![1, 2, 3, 4, 5, 6, 7, 8].into(),
        }
    }

    /// A key read a piece at a time is the key of the bytes at once, across the hash's block
    /// sizes and the pieces' size; over the limit, an error.
    #[test]
    fn a_key_read_in_pieces_is_the_key_of_the_whole() {
        for n in [0, 1, 16, 17, 128, 129, 240, 241, 1024, 1 << 18, (1 << 18) + 1, 3 << 18 | 77] {
            let bytes: Vec<u8> = (0..n).map(|i| (i * 31 % 251) as u8).collect();
            let read = Key::of_read("png", &bytes[..], n as u64).unwrap();
            assert_eq!(read, Key::of("png", &bytes), "{n} bytes");
        }
        let err = Key::of_read("png", &[0u8; 10][..], 9).unwrap_err();
        assert!(err.to_string().contains("limit"), "{err}");
    }

    /// A kept entry is read back whole; a damaged one (a texel flipped, cut short) is decoded
    /// again and rewritten.
    #[test]
    fn entries_are_kept_and_a_damaged_one_is_rebuilt() {
        let dir = std::env::temp_dir().join(format!("lightbench-texcache-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let cache = TextureCache::at(Some(&dir));
        let decodes = std::cell::Cell::new(0);
        let decode = || {
            decodes.set(decodes.get() + 1);
            Ok(texels())
        };
        let (t, got) = cache.get(Key::of("png", b"encoded"), decode).unwrap();
        assert!(matches!(got, Got::Decoded) && t == texels());
        assert!(matches!(t.rgba, TexelBytes::Owned(_)), "decoded now: {:?}", t.rgba);
        let (mut t, got) = cache.get(Key::of("png", b"encoded"), decode).unwrap();
        assert!(matches!(got, Got::Cached) && t == texels() && decodes.get() == 1);
        // Read from the cache, the texels are the entry mapped; changed, a copy of their own.
        assert!(matches!(t.rgba, TexelBytes::Mapped(_)), "{:?}", t.rgba);
        t.rgba.to_mut()[0] = 9;
        assert!(matches!(t.rgba, TexelBytes::Owned(_)) && t.rgba[..2] == [9, 2]);
        drop(t);
        let entry = cache.entry(Key::of("png", b"encoded")).unwrap();
        assert_eq!(read_entry(&entry), Some(texels()), "the entry is as it was");
        let mut bytes = std::fs::read(&entry).unwrap();
        bytes[HEADER] ^= 0x40;
        std::fs::write(&entry, &bytes).unwrap();
        let (t, got) = cache.get(Key::of("png", b"encoded"), decode).unwrap();
        assert!(matches!(got, Got::Decoded) && t == texels() && decodes.get() == 2);
        std::fs::write(&entry, &bytes[..HEADER + 3]).unwrap();
        let (_, got) = cache.get(Key::of("png", b"encoded"), decode).unwrap();
        assert!(matches!(got, Got::Decoded) && decodes.get() == 3);
        assert_eq!(read_entry(&entry), Some(texels()), "rewritten whole");
        // A pipe where the entry goes: not read (it would wait for a writer), not replaced.
        #[cfg(unix)]
        {
            let key = Key::of("png", b"piped");
            let pipe = cache.entry(key).unwrap();
            assert!(std::process::Command::new("mkfifo").arg(&pipe).status().unwrap().success());
            let (t, got) = cache.get(key, decode).unwrap();
            assert!(matches!(got, Got::NotKept(_)) && t == texels());
            assert!(
                std::fs::metadata(&pipe).unwrap().file_type().is_fifo(),
                "the pipe is left as it was"
            );
        }
        // Other bytes or another declared kind, another entry.
        assert_ne!(cache.entry(Key::of("png", b"encoded!")), Some(entry.clone()));
        assert_ne!(cache.entry(Key::of("jpeg", b"encoded")), Some(entry));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
