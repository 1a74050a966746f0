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

pub fn parse(text: &str) -> Result<Side> {
    let (file, config) = match text.rsplit_once('@') {
        Some((f, c)) => (f, Some(c)),
        None => (text, None),
    };
    if file.is_empty() {
        return Err(Error::Usage(format!("`{text}`: no pipeline file before `@`")));
    }
    let mut settings: Vec<(String, String)> = vec![];
    for part in config.into_iter().flat_map(|c| c.split(',')) {
        let Some((k, v)) = part.split_once('=').filter(|(k, v)| !k.trim().is_empty() && !v.trim().is_empty()) else {
            return Err(Error::Usage(format!(
                "`{text}`: `{part}` is not KEY=VALUE (after `@`: variant=option or parameter=value, comma-separated)"
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
        for bad in ["@x=1", "a.ron@x", "a.ron@x=", "a.ron@x=1,x=2", "a.ron@=1"] {
            assert!(matches!(parse(bad), Err(Error::Usage(_))), "{bad}");
        }
    }
}
