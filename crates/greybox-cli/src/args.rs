//! clap glue for the library's option types: an option enum is parsed by the library's
//! [`Choice`], so the command line accepts and lists exactly the names Python and the study
//! and sweep files accept.

use greybox_core::choice::Choice;

/// A clap parser of a library [`Choice`]: its values listed in `--help` and in errors.
pub fn choice<T: Choice + Send + Sync + Clone>() -> impl clap::builder::TypedValueParser<Value = T>
{
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(T::names())
        .try_map(|s| T::parse_choice(&s).map_err(|e| e.to_string()))
}

/// A clap parser of a [`Choice`]'s names, kept as text for the library's settings to parse.
pub fn choice_name<T: Choice>() -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(T::names())
}
