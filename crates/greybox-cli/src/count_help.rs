//! `--help` states the range of every count option. A count's clap parser
//! (`greybox_core::count::CountParser`) carries its range as a hidden possible value
//! `count:MIN..=MAX`; this pass appends `[count: MIN..=MAX]` to the option's help, so the cap
//! is written once, in the option's type.

use clap::{Arg, Command};
use greybox_core::count::HELP_MARKER;

/// The range of a count option (`1..=100000`), or `None` for any other option.
pub fn count_range(arg: &Arg) -> Option<String> {
    arg.get_possible_values()
        .iter()
        .find_map(|v| v.get_name().strip_prefix(HELP_MARKER).map(str::to_string))
}

/// `cmd` with every count option's range in its help, in every subcommand.
pub fn state_count_ranges(cmd: Command) -> Command {
    cmd.mut_args(|arg| match count_range(&arg) {
        Some(range) => {
            let help = arg.get_help().map(|h| h.to_string()).unwrap_or_default();
            let long = arg.get_long_help().map(|h| h.to_string());
            let arg = arg
                .help(format!("{help} [count: {range}]"))
                .hide_possible_values(true);
            match long {
                Some(l) => arg.long_help(format!("{l} [count: {range}]")),
                None => arg,
            }
        }
        None => arg,
    })
    .mut_subcommands(state_count_ranges)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::error::ErrorKind::{InvalidValue, ValueValidation};
    use clap::CommandFactory;
    use std::ffi::OsStr;

    /// Integer options that are not counts: identifiers, seeds and codes (any value is
    /// meaningful and nothing is sized by it), indices into a list (checked against the
    /// list: a sweep's case, a calibration's conditions), and the caps of the readers and walkers
    /// (`greybox_core::budget`, `report --max-*`), which a user raises on purpose; and an
    /// MLP's layer specs (`--mlp-hidden 64x32`), each width a bounded `LayerWidth` count
    /// (`settings::fit::tests::a_layer_width_beyond_its_cap_is_refused`).
    const NOT_COUNTS: &[&str] = &[
        "mlp_hidden",
        "seed",
        "lsdyna_table_id",
        "deform_objects",
        "index",
        "hold_out",
        "trigger_on_mcode",
        "trigger_off_mcode",
        "max_input_mib",
        "max_array_len",
        "max_sheet_cells",
        "max_uncompressed_mib",
        "max_line_kib",
        "max_recording_mib",
        "max_data_mib",
        "max_file_bytes",
        "max_svg_bytes",
        "max_header_bytes",
        "max_entries",
        "max_depth",
        "max_page_bytes",
    ];

    /// Every option of `cmd` and its subcommands, with the subcommand that holds it.
    fn options(cmd: &Command, path: String, out: &mut Vec<(String, Command, Arg)>) {
        for a in cmd
            .get_arguments()
            .filter(|a| a.get_action().takes_values())
        {
            out.push((path.clone(), cmd.clone(), a.clone()));
        }
        for s in cmd.get_subcommands() {
            options(s, format!("{path} {}", s.get_name()), out);
        }
    }

    #[test]
    fn every_integer_option_is_a_count_whose_range_is_in_help_and_in_its_errors() {
        let mut cmd = state_count_ranges(crate::Cli::command());
        cmd.build();
        let mut all = Vec::new();
        options(&cmd, "greybox".into(), &mut all);
        let mut counts = 0;
        let mut missing = Vec::new();
        for (path, sub, arg) in &all {
            let Some(long) = arg.get_long() else { continue };
            // the value alone decides: clap checks values while parsing, required options
            // and subcommands only after
            let parse = |v: &str| -> Result<(), clap::Error> {
                let flag = format!("--{long}={v}");
                match sub
                    .clone()
                    .try_get_matches_from([OsStr::new("greybox"), OsStr::new(&flag)])
                {
                    Err(e) if e.kind() == ValueValidation || e.kind() == InvalidValue => Err(e),
                    _ => Ok(()),
                }
            };
            let integer = parse("3").is_ok() && parse("3.5").is_err();
            if !integer || NOT_COUNTS.contains(&arg.get_id().as_str()) {
                continue;
            }
            let name = format!("{path} --{long}");
            let Some(range) = count_range(arg) else {
                missing.push(name);
                continue;
            };
            let help = arg.get_help().map(|h| h.to_string()).unwrap_or_default();
            assert!(
                help.contains(&format!("[count: {range}]")),
                "{name}: {help}"
            );
            for hostile in ["0", "-1", "1000000000", "1000000000000000000", "7e9"] {
                if let Err(e) = parse(hostile) {
                    let text = e.to_string();
                    assert!(text.contains(&range), "{name} {hostile}: {text}");
                }
            }
            assert!(
                parse("1000000000000000000").is_err(),
                "{name}: 10^18 accepted"
            );
            counts += 1;
        }
        assert!(
            missing.is_empty(),
            "integer options that are not bounded Counts: {missing:#?}"
        );
        assert!(counts >= 25, "only {counts} count options found");
    }
}
