//! The fields a JSON file is recognised by (`schema`, `schema_version`), read in one pass over
//! the text with every other field skipped, not built: model files of large forests are
//! hundreds of MB, and a generic JSON tree of them takes several times that.

use serde::Deserialize;

/// A JSON document's `schema` and `schema_version`, where it is an object that has them.
#[derive(Debug, Default, Deserialize)]
pub struct JsonHead {
    pub schema: Option<serde_json::Value>,
    pub schema_version: Option<serde_json::Value>,
}

impl JsonHead {
    /// `schema` when it is a string.
    pub fn schema(&self) -> Option<&str> {
        self.schema.as_ref().and_then(|s| s.as_str())
    }
}

/// The head of `text`. Errs only when `text` is not JSON (a syntax error or an early end; the
/// error has its line); a document that is not an object, or whose head fields are not what
/// [`JsonHead`] takes, has an empty head.
pub fn read(text: &str) -> serde_json::Result<JsonHead> {
    match serde_json::from_str::<JsonHead>(text) {
        Ok(head) => Ok(head),
        Err(e) if e.is_syntax() || e.is_eof() => Err(e),
        Err(_) => Ok(JsonHead::default()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_head_and_tells_syntax_from_shape() {
        let h =
            read(r#"{"a": [1, {"b": 2}], "schema": "s", "schema_version": 2, "z": null}"#).unwrap();
        assert_eq!(h.schema(), Some("s"));
        assert_eq!(h.schema_version, Some(serde_json::json!(2)));
        for not_an_object in [
            "[1, 2]",
            "3",
            r#""schema""#,
            r#"{"schema": "a", "schema": "b"}"#,
        ] {
            assert_eq!(
                read(not_an_object).unwrap().schema(),
                None,
                "{not_an_object}"
            );
        }
        let e = read("{\n\"schema\": \"s\",\n\"x\": [1, 2\n}").unwrap_err();
        assert!(e.is_syntax() && e.line() == 4, "{e}");
        assert!(read(r#"{"schema": "s""#).unwrap_err().is_eof());
        assert!(read(r#"{"schema": "s"} trailing"#).unwrap_err().is_syntax());
    }
}
