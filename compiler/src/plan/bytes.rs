//! Plan serialization of a data resource's bytes: one base64 string in JSON (a number per
//! byte would make a 32 KiB table 100 KiB of text).

use base64::Engine;
use serde::{Deserialize, Deserializer, Serializer};
use std::sync::Arc;

const CODEC: base64::engine::GeneralPurpose = base64::engine::general_purpose::STANDARD;

pub fn serialize<S: Serializer>(bytes: &Option<Arc<Vec<u8>>>, s: S) -> Result<S::Ok, S::Error> {
    match bytes {
        Some(b) => s.serialize_str(&CODEC.encode(b.as_slice())),
        None => s.serialize_none(),
    }
}

pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Arc<Vec<u8>>>, D::Error> {
    let Some(text) = Option::<String>::deserialize(d)? else {
        return Ok(None);
    };
    CODEC
        .decode(text.as_bytes())
        .map(|b| Some(Arc::new(b)))
        .map_err(|e| serde::de::Error::custom(format!("`contents` is not base64: {e}")))
}
