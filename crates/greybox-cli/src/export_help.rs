//! `greybox export --help` states each option's defaults, per format where they differ. The
//! text comes from the library's defaults (`greybox_pipeline::export::edge::default_help`),
//! so a default is typed once, in the library, and Python's `export_defaults` reads the same.

use clap::Command;

/// `cmd` with the export subcommand's options stating their defaults.
pub fn state_export_defaults(cmd: Command) -> Command {
    cmd.mut_subcommand("export", |mut export| {
        for (field, text) in greybox_pipeline::export::edge::default_help() {
            if export.get_arguments().any(|a| a.get_id() == field.as_str()) {
                export = export.mut_arg(field, |arg| {
                    let help = arg.get_help().map(|h| h.to_string()).unwrap_or_default();
                    arg.help(format!("{help} [default: {text}]"))
                });
            }
        }
        export
    })
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    /// Every default the library has for an export option appears in its help.
    #[test]
    fn the_export_help_states_the_librarys_defaults() {
        let cmd = super::state_export_defaults(crate::Cli::command());
        let export = cmd.find_subcommand("export").unwrap();
        let help = |id: &str| {
            export
                .get_arguments()
                .find(|a| a.get_id() == id)
                .and_then(|a| a.get_help())
                .map(|h| h.to_string())
                .unwrap_or_default()
        };
        assert!(
            help("pressure_Pa").ends_with("[default: 500:2500:21]"),
            "{}",
            help("pressure_Pa")
        );
        assert!(help("velocity_m_per_s").ends_with("[default: 10:300:30]"));
        assert!(
            help("units").contains("MPa-mm-s for abaqus, lsdyna"),
            "{}",
            help("units")
        );
        assert!(help("deform_reference_velocity_m_per_s").contains("[default: 150 for deform]"));
        let tolerance = greybox_friction::export::engine::DEFAULT_TOLERANCE;
        assert!(
            help("tolerance").contains(&format!("{tolerance}")),
            "{}",
            help("tolerance")
        );
        for (field, _) in greybox_pipeline::export::edge::default_help() {
            assert!(help(&field).contains("[default: "), "{field}");
        }
    }
}
