//! A friction law of your own in greybox's cutting simulation: implement
//! [`greybox::FrictionLaw`] (μ from contact pressure, sliding velocity and temperature),
//! hand it to the cut, and compare with constant Coulomb friction.
//!
//! `cargo run --release -p greybox --example custom_friction_law`

use anyhow::Result;
use greybox::pipeline::simulate::{read_cutting_setup, run_cut, CutCase, RunOutput};
use greybox::{ContactState, FrictionLaw};
use std::path::Path;
use std::sync::Arc;

/// μ falling with pressure and sliding velocity, as the article's tribometer data do:
/// μ = μ_ref (p / p_ref)^a (v / v_ref)^b, kept within [0.05, 1].
struct PressureVelocityPowerLaw {
    mu_ref: f64,
    /// Reference pressure, Pa.
    p_ref_pa: f64,
    /// Reference sliding velocity, m/s.
    v_ref_m_s: f64,
    a: f64,
    b: f64,
}

impl FrictionLaw for PressureVelocityPowerLaw {
    fn name(&self) -> String {
        format!(
            "power law mu = {} (p/{} MPa)^{} (v/{} m/s)^{}",
            self.mu_ref,
            self.p_ref_pa * 1e-6,
            self.a,
            self.v_ref_m_s,
            self.b
        )
    }
    fn mu(&self, s: &ContactState) -> f64 {
        // no contact pressure or no sliding: the reference value (the power law is singular)
        if s.pressure_pa <= 0.0 || s.sliding_velocity_m_s <= 0.0 {
            return self.mu_ref;
        }
        let mu = self.mu_ref
            * (s.pressure_pa / self.p_ref_pa).powf(self.a)
            * (s.sliding_velocity_m_s / self.v_ref_m_s).powf(self.b);
        mu.clamp(0.05, 1.0)
    }
}

fn main() -> Result<()> {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut setup = read_cutting_setup(&examples.join("aisi1045-cut.toml"))?.setup;
    setup.spacing_m = 12.5e-6;
    setup.friction.window_length_m = 12.5e-6;
    setup.cut_length_m = 0.25e-3;
    let dir = tempfile::tempdir()?;
    let laws: [(&str, Arc<dyn FrictionLaw>); 2] = [
        (
            "custom",
            Arc::new(PressureVelocityPowerLaw {
                mu_ref: 0.35,
                p_ref_pa: 1.5e9,
                v_ref_m_s: 2.5,
                a: -0.8,
                b: -0.2,
            }),
        ),
        ("coulomb", Arc::new(greybox::sim::ConstantMu(setup.mu))),
    ];
    for (tag, law) in laws {
        let case = CutCase {
            setup: setup.clone(),
            law_source: tag.into(),
            law,
            inputs: Vec::new(),
        };
        let s = run_cut(&case, 1.0, &RunOutput::to(dir.path().join(tag)))?;
        println!(
            "{:<60} F'c = {:6.1} N/mm, F'f = {:6.1} N/mm, contact length {}",
            s.law,
            s.cutting_force_n_per_mm,
            s.feed_force_n_per_mm,
            s.measures
                .contact_length_mm
                .map_or("n/a".into(), |l| format!("{l:.3} mm"))
        );
    }
    Ok(())
}
