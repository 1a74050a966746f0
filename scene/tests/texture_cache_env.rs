//! Where the texture cache goes (docs/scenes.md): `$LIGHTBENCH_CACHE_DIR/textures`, none when
//! it is empty, else `$XDG_CACHE_HOME/lightbench/textures` (absolute only), else
//! `~/.cache/lightbench/textures`. A test binary of its own: it sets the process's environment.

use lightbench_scene::texture_cache::{Key, TextureCache, CACHE_ENV};
use std::path::Path;

fn dir_of(cache: &TextureCache) -> Option<std::path::PathBuf> {
    cache.entry(Key::of("png", b"x")).map(|e| e.parent().unwrap().to_path_buf())
}

#[test]
fn the_cache_folder_follows_the_environment() {
    std::env::set_var("HOME", "/home/someone");
    std::env::set_var("XDG_CACHE_HOME", "/var/cache/someone");
    std::env::set_var(CACHE_ENV, "/tmp/lb");
    assert_eq!(dir_of(&TextureCache::from_env()).as_deref(), Some(Path::new("/tmp/lb/textures")));
    std::env::set_var(CACHE_ENV, "");
    assert_eq!(dir_of(&TextureCache::from_env()), None);
    std::env::remove_var(CACHE_ENV);
    assert_eq!(
        dir_of(&TextureCache::from_env()).as_deref(),
        Some(Path::new("/var/cache/someone/lightbench/textures"))
    );
    std::env::set_var("XDG_CACHE_HOME", "relative");
    assert_eq!(
        dir_of(&TextureCache::from_env()).as_deref(),
        Some(Path::new("/home/someone/.cache/lightbench/textures"))
    );
    std::env::remove_var("XDG_CACHE_HOME");
    std::env::remove_var("HOME");
    assert_eq!(dir_of(&TextureCache::from_env()), None);
}
