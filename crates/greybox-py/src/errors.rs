//! Rust errors to Python exceptions, by kind, in one place. The classes live in
//! `greybox._errors` (Python, so that they can also derive from `ValueError` or
//! `FileNotFoundError`); this module only picks the class by the error's kind.

use pyo3::prelude::*;

/// The `greybox._errors` class for an error: a missing file, bad settings, other bad input;
/// a call stopped on request ([`greybox_pipeline::simulate::is_interrupted`]) is Python's
/// `KeyboardInterrupt`.
fn kind(e: &anyhow::Error) -> &'static str {
    use greybox_core::error::Error as Core;
    if greybox_pipeline::simulate::is_interrupted(e) {
        return "KeyboardInterrupt";
    }
    for cause in e.chain() {
        if let Some(io) = cause.downcast_ref::<std::io::Error>() {
            if io.kind() == std::io::ErrorKind::NotFound {
                return "MissingFileError";
            }
        }
        match cause.downcast_ref::<Core>() {
            Some(Core::Io { error, .. }) if error.kind() == std::io::ErrorKind::NotFound => {
                return "MissingFileError"
            }
            _ => {}
        }
        // a setting refused by its stage's settings type, or settings JSON that is not JSON
        if greybox_core::error::as_setting(cause).is_some()
            || cause.downcast_ref::<serde_json::Error>().is_some()
        {
            return "SettingsError";
        }
    }
    "InputError"
}

/// A setting as Python names it: the keyword argument of the call (`track_radii_mm`,
/// `track_radii_mm[1]` for an element), a reader's cap as `set_budget`'s keyword.
fn keyword(p: &greybox_core::setting::SettingPath) -> String {
    match p.stage.as_str() {
        "budget" => format!("greybox.set_budget({}=…)", p.field),
        _ => format!("{}{}", p.field, p.index_suffix()),
    }
}

/// A message's backticked cap options as Python sets them: `` `max_data_mib` `` (the command
/// line's option, in MiB) is `greybox.set_budget(max_data_bytes=…)`.
fn python_words(text: &str) -> String {
    let mut out = text.to_string();
    for cap in greybox_core::budget::Cap::ALL {
        out = out.replace(
            cap.option(),
            &format!("greybox.set_budget({}=…)", cap.name()),
        );
    }
    out
}

/// A greybox error as a Python exception of its kind, with its causes joined and each
/// setting named as Python names it ([`keyword`]).
pub(crate) fn py_err(e: impl Into<anyhow::Error>) -> PyErr {
    let e = e.into();
    let message = greybox_pipeline::settings::render_error(&e, &keyword, &python_words);
    match kind(&e) {
        "KeyboardInterrupt" => pyo3::exceptions::PyKeyboardInterrupt::new_err(message),
        class => Python::attach(|py| {
            let made = py
                .import("greybox._errors")
                .and_then(|m| m.getattr(class))
                .and_then(|c| c.call1((message.clone(),)));
            match made {
                Ok(exc) => PyErr::from_value(exc),
                Err(e) => e,
            }
        }),
    }
}
