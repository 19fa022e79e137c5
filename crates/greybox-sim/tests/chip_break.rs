//! Chip breaking (`chip_break_height_m`, see `greybox_sim::sink`): the chip above the line
//! leaves the model, the cut below it is untouched until then, and the energy books close.
use greybox_sim::cut_run::CutRun;
use greybox_sim::particles::FREE;
use greybox_sim::{ConstantMu, Control, Observer, SimError, Solver};
use std::sync::Arc;

mod common;
use common::coarse_cut;

/// Notes the time the first free particle rose above `line` (model frame, m).
struct FirstAbove {
    line: f64,
    time: Option<f64>,
}

impl Observer for FirstAbove {
    fn after_step(&mut self, sim: &Solver) -> Result<Control, SimError> {
        let p = &sim.particles;
        if self.time.is_none() && (0..p.len()).any(|i| p.group[i] == FREE && p.y[i] > self.line) {
            self.time = Some(sim.time);
        }
        Ok(Control::Continue)
    }
}

fn run(setup: &greybox_sim::cutting::CuttingSetup, obs: &mut FirstAbove) -> CutRun {
    CutRun::execute(
        setup,
        Arc::new(ConstantMu(setup.mu)),
        1.0,
        None,
        &mut greybox_sim::Hooks::new().observe(obs),
    )
    .unwrap()
}

#[test]
fn the_chip_above_the_break_leaves_and_the_cut_below_is_untouched_until_then() {
    let mut whole = coarse_cut();
    // long enough for the chip to rise well above the break
    whole.cut_length_m = 0.8e-3;
    let mut broken = whole.clone();
    let height = 0.285e-3;
    broken.chip_break_height_m = Some(height);
    // the top particle centres lie half a spacing below y = 0
    let line = -0.5 * whole.spacing_m + height;
    let mut first = FirstAbove { line, time: None };
    let a = run(&whole, &mut first);
    let t_first = first.time.expect("the whole chip rises above the line");
    let mut after = FirstAbove { line, time: None };
    let b = run(&broken, &mut after);
    let removed = b.sim.energy.removed_particles;
    assert!(removed > 10, "{removed} particles removed");
    assert_eq!(
        a.sim.particles.len(),
        b.sim.particles.len() + removed as usize,
        "every particle is kept or counted as removed"
    );
    // until the first particle crosses, the two cuts are the same cut, to the bit
    let before = |r: &CutRun| -> Vec<[f64; 6]> {
        r.forces
            .rows
            .iter()
            .filter(|row| row[0] < t_first)
            .copied()
            .collect()
    };
    assert!(before(&a).len() > 5);
    assert_eq!(before(&a), before(&b));
    // a particle is removed at the start of the step after it crossed: none stays above
    // the line by more than one step's travel
    let p = &b.sim.particles;
    let highest = (0..p.len())
        .filter(|&i| p.group[i] == FREE)
        .map(|i| p.y[i])
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(
        highest < line + 0.1 * whole.spacing_m,
        "{highest} above {line}"
    );
    // the energy they carried is booked: the balance closes as well as the whole chip's
    let (ea, eb) = (a.sim.energy_balance(), b.sim.energy_balance());
    assert!(eb.removed > 0.0);
    assert!(
        eb.relative_error.abs() < ea.relative_error.abs() + 0.01,
        "energy error {} with the break, {} without",
        eb.relative_error,
        ea.relative_error
    );
    // forces at the tool stay within the cut's scatter (the chip's far part is gone)
    let mean = |r: &CutRun| r.force;
    let (fa, fb) = (mean(&a), mean(&b));
    assert!(
        (fa[0] - fb[0]).abs() < 0.1 * fa[0].abs(),
        "F'c {fa:?} vs {fb:?}"
    );
    eprintln!(
        "steps {} first crossing at {t_first:e} s of {:e}; removed {removed}; energy {} vs {}",
        b.sim.step, b.sim.time, eb.relative_error, ea.relative_error
    );
}

#[test]
fn a_break_below_the_measured_chip_is_refused() {
    let mut setup = coarse_cut();
    setup.chip_break_height_m = Some(1.5 * setup.uncut_chip_thickness_m);
    let e = setup.validate().unwrap_err().to_string();
    assert!(e.contains("chip_break_height_m"), "{e}");
    setup.chip_break_height_m = Some(f64::NAN);
    assert!(setup.validate().is_err());
}
