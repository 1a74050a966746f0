//! Stage `spec` of `diff`: one side as the command line names it — a pipeline file with an
//! optional configuration, `pipelines/deferred.ron@cube_shadow=instanced,shadow.pcf=false`.

use crate::error::{Error, Result};
use std::path::PathBuf;

#[derive(Clone, Debug, PartialEq)]
pub struct Side {
    /// As written on the command line (the report's column title).
    pub label: String,
    pub pipeline: PathBuf,
    /// `key=value` pairs after `@`, in order: a key naming one of the pipeline's variants
    /// chooses its option, any other is a parameter (see `cli::diff`).
    pub settings: Vec<(String, String)>,
}

/// A side splits at its last `@`: a path that contains `@` is written with a trailing `@`
/// and no settings (`my@dir/p.ron@`). Settings are comma-separated `KEY=VALUE`; a part with
/// no `=` continues the value before it, so a vector is written as on `--param`
/// (`ambient.color=0.1,0.1,0.12`).
pub fn parse(text: &str) -> Result<Side> {
    let (file, config) = match text.rsplit_once('@') {
        Some((f, c)) => (f, Some(c).filter(|c| !c.is_empty())),
        None => (text, None),
    };
    if file.is_empty() {
        return Err(Error::Usage(format!("`{text}`: no pipeline file before `@`")));
    }
    let mut settings: Vec<(String, String)> = vec![];
    for part in config.into_iter().flat_map(|c| c.split(',')) {
        if let (Some(last), false) = (settings.last_mut(), part.contains('=')) {
            if !part.trim().is_empty() {
                last.1 = format!("{},{}", last.1, part.trim());
                continue;
            }
        }
        let Some((k, v)) = part.split_once('=').filter(|(k, v)| !k.trim().is_empty() && !v.trim().is_empty()) else {
            let hint = if std::path::Path::new(text).exists() {
                format!(" (a path that contains `@` ends with `@`: `{text}@`)")
            } else {
                String::new()
            };
            return Err(Error::Usage(format!(
                "`{text}`: `{part}` is not KEY=VALUE (after `@`: variant=option or parameter=value, comma-separated){hint}"
            )));
        };
        let k = k.trim().to_string();
        if settings.iter().any(|(name, _)| *name == k) {
            return Err(Error::Usage(format!("`{text}` sets `{k}` twice")));
        }
        settings.push((k, v.trim().to_string()));
    }
    Ok(Side {
        label: text.to_string(),
        pipeline: PathBuf::from(file),
        settings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sides_parse_with_and_without_settings() {
        let s = parse("pipelines/deferred.ron@cube_shadow=instanced, shadow.pcf=false").unwrap();
        assert_eq!(s.pipeline, PathBuf::from("pipelines/deferred.ron"));
        assert_eq!(
            s.settings,
            vec![("cube_shadow".into(), "instanced".into()), ("shadow.pcf".into(), "false".into())]
        );
        assert!(parse("a.lbp").unwrap().settings.is_empty());
        for bad in ["@x=1", "a.ron@x", "a.ron@x=", "a.ron@x=1,x=2", "a.ron@=1", "a.ron@x=1,,y=2"] {
            assert!(matches!(parse(bad), Err(Error::Usage(_))), "{bad}");
        }
    }

    /// A vector's numbers continue the value before them; a path with `@` ends with `@`.
    #[test]
    fn vectors_and_paths_with_at() {
        let s = parse("p.ron@ambient.color=0.1, 0.1,0.12,shadow.pcf=false").unwrap();
        assert_eq!(
            s.settings,
            vec![
                ("ambient.color".into(), "0.1,0.1,0.12".into()),
                ("shadow.pcf".into(), "false".into())
            ]
        );
        let s = parse("my@dir/p.ron@").unwrap();
        assert_eq!((s.pipeline, s.settings), (PathBuf::from("my@dir/p.ron"), vec![]));
        let s = parse("my@dir/p.ron@x=1").unwrap();
        assert_eq!(
            (s.pipeline, s.settings),
            (PathBuf::from("my@dir/p.ron"), vec![("x".into(), "1".into())])
        );
    }
}
