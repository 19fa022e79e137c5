//! The stages of the library's settings registry (`greybox_pipeline::settings::STAGES`) as
//! commands: each is a subcommand whose flags are its settings, one flag per key (a test; a
//! stage added to the registry without its command, or a setting without its flag, fails it).

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    /// The subcommand of each registered stage.
    const COMMANDS: &[(&str, &[&str])] = &[
        ("identify", &["identify"]),
        ("synth", &["synth"]),
        ("hertz", &["hertz"]),
        ("plan", &["plan"]),
        ("fit", &["fit"]),
        ("adhesive", &["adhesive"]),
        ("pin", &["simulate", "pin"]),
        ("couple", &["couple"]),
        ("law", &["law"]),
        ("windows", &["windows"]),
        ("flow_curves", &["material", "fit"]),
        ("rate_sensitivity", &["material", "fit-c"]),
        ("cut", &["simulate", "cutting"]),
        ("predict", &["predict"]),
        ("import", &["import"]),
        ("characterize", &["characterize"]),
        ("wear", &["wear"]),
    ];

    #[test]
    fn every_registered_stage_is_a_command_whose_flags_are_its_settings() {
        let cli = crate::Cli::command();
        for stage in greybox_pipeline::settings::STAGES {
            let (_, path) = COMMANDS
                .iter()
                .find(|(name, _)| *name == stage.name)
                .unwrap_or_else(|| panic!("stage {}: no command listed here", stage.name));
            let mut cmd = &cli;
            for name in *path {
                cmd = cmd
                    .find_subcommand(name)
                    .unwrap_or_else(|| panic!("stage {}: no `{}`", stage.name, path.join(" ")));
            }
            let ids: Vec<&str> = cmd.get_arguments().map(|a| a.get_id().as_str()).collect();
            let defaults = (stage.defaults)();
            let keys = defaults.as_object().expect("settings are an object");
            let missing: Vec<&String> =
                keys.keys().filter(|k| !ids.contains(&k.as_str())).collect();
            assert!(
                missing.is_empty(),
                "greybox {}: no flag for the settings {missing:?}",
                path.join(" ")
            );
        }
        assert_eq!(COMMANDS.len(), greybox_pipeline::settings::STAGES.len());
    }
}
