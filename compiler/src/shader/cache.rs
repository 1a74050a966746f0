//! The compiled-module cache a workspace keeps across compilations: keyed by language,
//! capabilities and a hash of the expanded source (the source itself is compared on a hit,
//! so a hash collision costs only a recompile), least recently used evicted past capacity.
//! Failures are not kept, so every compilation reports its own located errors.

use super::{Compiled, Lang};
use std::collections::{HashMap, HashSet};
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Condvar, Mutex};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Key {
    lang: Lang,
    caps: u64,
    text: u64,
}

impl Key {
    /// One number for the whole key (the identity of a compiled module).
    pub fn hash(&self) -> u64 {
        let mut h = std::hash::DefaultHasher::new();
        Hash::hash(self, &mut h);
        h.finish()
    }
}

pub fn key(lang: Lang, caps: u64, text: &str) -> Key {
    keyed(lang, caps, text_hash(text))
}

/// The key of a module whose text hashes to `text` (`text_hash`).
pub fn keyed(lang: Lang, caps: u64, text: u64) -> Key {
    Key { lang, caps, text }
}

pub fn text_hash(text: &str) -> u64 {
    let mut h = std::hash::DefaultHasher::new();
    text.hash(&mut h);
    h.finish()
}

/// What the cache did: naga compilations (misses), hits and evictions since it was made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CacheStats {
    pub compiled: u64,
    pub hits: u64,
    pub evicted: u64,
    pub entries: usize,
}

struct Entry {
    source: String,
    compiled: Arc<Compiled>,
    last_used: u64,
}

struct Inner {
    map: HashMap<Key, Entry>,
    /// Modules some thread is compiling now.
    compiling: HashSet<Key>,
    clock: u64,
    stats: CacheStats,
}

pub struct ModuleCache {
    inner: Mutex<Inner>,
    /// Signalled when a compilation in `compiling` ends.
    done: Condvar,
    /// Most modules kept; the least recently used beyond it are dropped.
    pub capacity: usize,
}

impl Default for ModuleCache {
    fn default() -> Self {
        Self::with_capacity(256)
    }
}

impl ModuleCache {
    pub fn with_capacity(capacity: usize) -> Self {
        ModuleCache {
            inner: Mutex::new(Inner {
                map: HashMap::new(),
                compiling: HashSet::new(),
                clock: 0,
                stats: CacheStats::default(),
            }),
            done: Condvar::new(),
            capacity: capacity.max(1),
        }
    }

    /// Is the module there? (Counts nothing: for compiling ahead.)
    pub fn contains(&self, key: &Key, text: &str) -> bool {
        self.inner.lock().is_ok_and(|g| g.map.get(key).is_some_and(|e| e.source == text))
    }

    /// Compile the module with `compile` and keep it, unless it is here already; `false`
    /// (nothing done) when another thread is compiling it now: compilations running at once
    /// (the pipelines of one `check`) compile a module they share once, each doing others'
    /// work meanwhile, then `wait_for` what they skipped. A failure is not kept; whoever
    /// asks next compiles it again and reports it.
    pub fn try_compile(&self, key: Key, text: &str, compile: impl FnOnce() -> Option<Arc<Compiled>>) -> bool {
        {
            let Ok(mut g) = self.inner.lock() else { return true };
            if g.map.get(&key).is_some_and(|e| e.source == text) {
                return true;
            }
            if !g.compiling.insert(key) {
                return false;
            }
        }
        // Ends the compilation however `compile` returns, so no waiter is left waiting.
        struct Ending<'a>(&'a ModuleCache, Key);
        impl Drop for Ending<'_> {
            fn drop(&mut self) {
                if let Ok(mut g) = self.0.inner.lock() {
                    g.compiling.remove(&self.1);
                }
                self.0.done.notify_all();
            }
        }
        let _ending = Ending(self, key);
        if let Some(c) = compile() {
            self.put(key, text, c);
        }
        true
    }

    /// Wait until no thread is compiling the module.
    pub fn wait_for(&self, key: &Key) {
        // On a worker of the thread pool, take others' work meanwhile (the compiling thread's
        // remaining modules among them) rather than block while it compiles them alone.
        while self.inner.lock().is_ok_and(|g| g.compiling.contains(key)) {
            if rayon::yield_now() != Some(rayon::Yield::Executed) {
                break;
            }
        }
        let Ok(mut g) = self.inner.lock() else { return };
        while g.compiling.contains(key) {
            g = match self.done.wait(g) {
                Ok(g) => g,
                Err(_) => return,
            };
        }
    }

    pub fn get(&self, key: &Key, text: &str) -> Option<Arc<Compiled>> {
        let mut g = self.inner.lock().ok()?;
        g.clock += 1;
        let now = g.clock;
        let hit = g.map.get_mut(key).filter(|e| e.source == text).map(|e| {
            e.last_used = now;
            e.compiled.clone()
        });
        if hit.is_some() {
            g.stats.hits += 1;
        }
        hit
    }

    pub fn put(&self, key: Key, text: &str, compiled: Arc<Compiled>) {
        let Ok(mut g) = self.inner.lock() else { return };
        g.clock += 1;
        g.stats.compiled += 1;
        let last_used = g.clock;
        g.map.insert(
            key,
            Entry {
                source: text.to_string(),
                compiled,
                last_used,
            },
        );
        while g.map.len() > self.capacity {
            let Some(oldest) = g.map.iter().min_by_key(|(_, e)| e.last_used).map(|(k, _)| *k) else {
                break;
            };
            g.map.remove(&oldest);
            g.stats.evicted += 1;
        }
    }

    pub fn stats(&self) -> CacheStats {
        self.inner
            .lock()
            .map(|g| CacheStats {
                entries: g.map.len(),
                ..g.stats
            })
            .unwrap_or_default()
    }
}
