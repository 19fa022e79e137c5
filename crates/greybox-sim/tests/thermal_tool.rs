//! The thermal tool in a cut: the heat balance closes with the heat that went into the tool,
//! and the tool takes heat out of the chip (coarse and fast: Ti6Al4V at 20 µm spacing).
use greybox_material::Material;
use greybox_sim::cut_run::CutRun;
use greybox_sim::cutting::CuttingSetup;
use greybox_sim::tool_thermal::ToolThermalSetup;

mod common;
use common::coarse_cut;

fn coarse_ti_cut(thermal_tool: bool) -> CuttingSetup {
    let mut s = coarse_cut();
    s.material = Material::ti6al4v();
    s.initial_temperature_k = 300.0;
    s.numerics.friction_heat_share = 0.5;
    s.tool_thermal = thermal_tool.then(ToolThermalSetup::carbide_altin);
    s
}

use common::cut_with_its_mu as run;

/// Heat balance: the workpiece's heat content gained plus the tool's plus what left the
/// tool through its held boundaries equals the heat sources, β W_plastic + W_friction
/// (all friction work becomes heat: half in the chip, half in the tool). Ti6Al4V has a
/// constant c_p, so the workpiece's heat content is Σ (m/f) c ΔT exactly.
#[test]
fn heat_balance_of_a_cut_includes_the_heat_into_the_tool() {
    let setup = coarse_ti_cut(true);
    let r = run(&setup);
    let sim = &r.sim;
    let p = &sim.particles;
    let cp = setup.material.thermal.specific_heat.eval(300.0);
    let m_phys = p.mass / setup.numerics.mass_scaling;
    let workpiece: f64 = p.temp.iter().map(|t| m_phys * cp * (t - 300.0)).sum();
    let tt = sim.tools[0].thermal.as_ref().unwrap();
    let tool = tt.stored_heat(300.0) + tt.heat_to_ambient;
    let e = &sim.energy;
    let sources = setup.material.thermal.taylor_quinney * e.plastic_work + e.friction_work;
    let balance = (workpiece + tool) / sources - 1.0;
    eprintln!(
        "workpiece {workpiece:.4} J/m, tool {tool:.4} J/m (held boundary {:.4}), booked into tool {:.4}, sources {sources:.4} J/m (plastic {:.4}, friction {:.4}): residual {:.2} %; hottest tool cell {:.0} K",
        tt.heat_to_ambient,
        e.tool_heat,
        e.plastic_work,
        e.friction_work,
        100.0 * balance,
        tt.max_temperature()
    );
    assert!(balance.abs() < 0.02, "heat balance residual {balance}");
    // What the contact booked into the tool is what the tool holds, with the heat of the
    // sub-cycle not yet conducted (the explicit update uses c(T) at the start of each tool
    // step, the stored heat integrates c(T): 0.1 % apart here).
    let pending: f64 = tt.heat_in.iter().sum();
    assert!(((tool + pending) / e.tool_heat - 1.0).abs() < 0.005);
    // The tool takes a real share: at least half its friction share.
    assert!(
        e.tool_heat > 0.25 * e.friction_work,
        "tool heat {}",
        e.tool_heat
    );
    assert!(tt.max_temperature() > 350.0);
    // The contact profile reports tool temperatures where in contact.
    let rake: Vec<f64> = r
        .profile
        .iter()
        .filter_map(|w| w.stats.and_then(|s| s.tool_temperature_k))
        .collect();
    assert!(!rake.is_empty() && rake.iter().all(|&t| t > 300.0 && t < 1900.0));
}

/// The conducting tool cools the contact: the chip's hottest particle and the rake-face
/// temperature are lower than with the adiabatic tool.
#[test]
fn the_thermal_tool_cools_the_contact() {
    let adiabatic = run(&coarse_ti_cut(false));
    let thermal = run(&coarse_ti_cut(true));
    let hottest = |r: &CutRun| r.sim.particles.temp.iter().copied().fold(0.0, f64::max);
    let contact_t = |r: &CutRun| {
        let (mut num, mut den) = (0.0, 0.0);
        for s in r.profile.iter().filter_map(|w| w.stats) {
            num += s.temperature_k * s.normal_stress_pa;
            den += s.normal_stress_pa;
        }
        num / den
    };
    eprintln!(
        "hottest particle {:.0} K adiabatic, {:.0} K thermal; contact {:.0} K vs {:.0} K",
        hottest(&adiabatic),
        hottest(&thermal),
        contact_t(&adiabatic),
        contact_t(&thermal)
    );
    assert!(contact_t(&thermal) < contact_t(&adiabatic) - 5.0);
    assert!(adiabatic.sim.tools[0].thermal.is_none() && adiabatic.sim.energy.tool_heat == 0.0);
    // The peak over the run bounds the hottest particle at the end, and the cut heated up.
    for r in [&adiabatic, &thermal] {
        let peak = r.peak_temperature.peak_k;
        assert!(peak >= hottest(r) && peak > 293.15 + 100.0, "peak {peak} K");
    }
    assert!(thermal.peak_temperature.peak_k < adiabatic.peak_temperature.peak_k);
}
