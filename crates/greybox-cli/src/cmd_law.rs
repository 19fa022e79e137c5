//! `greybox law`.

use anyhow::Result;
use greybox_pipeline::settings::law::GreyBoxSettings;

/// Write the grey-box friction law around a fitted model: the model inside its training
/// domain, a power law fitted to its training data outside, blended over a fraction of each
/// range, μ clamped, optionally Zorev's shear cap τ ≤ k. The same settings and defaults as
/// Python's `greybox.grey_box_law`; the file states each of them.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub settings: GreyBoxSettings,
}

pub fn run(args: Args) -> Result<()> {
    let law = args.settings.write()?;
    print!("{}", serde_json::to_string_pretty(&law)?);
    println!("\nlaw -> {}", args.settings.out.display());
    Ok(())
}
