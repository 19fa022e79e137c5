//! A run that goes non-finite stops with a clear error, and the checkpoint observer writes the
//! last good state (finite) for inspection.
mod common;
use greybox_material::Material;
use greybox_sim::checkpoint::{Checkpoint, Checkpointer};
use greybox_sim::{run, BoundaryGroup, Control, Controller, Hooks, SimError, Solver};

/// Corrupts one particle at a given step (stands in for any numerical blow-up).
struct Poison(u64);
impl Controller for Poison {
    fn after_step(&mut self, sim: &mut Solver) -> Result<Control, SimError> {
        if sim.step == self.0 {
            sim.particles.sxx[5] = f64::NAN;
        }
        Ok(Control::Continue)
    }
}

#[test]
fn unstable_run_stops_with_error_and_last_good_state() {
    let d = tempfile::tempdir().unwrap();
    let groups = vec![BoundaryGroup {
        name: "driver".into(),
        vx: Some(1.0),
        vy: None,
    }];
    let model = common::block_model(20, 10, 10e-6, Material::elastic_steel(), groups, |i, _| {
        (i == 0) as u8
    });
    let mut sim = Solver::new(model).unwrap();
    let mut ck = Checkpointer::new(&d.path().join("ck.json"), 100, "test");
    let e = run(
        &mut sim,
        1.0,
        "test",
        Hooks::new().control(&mut Poison(450)).checkpoint(&mut ck),
    )
    .unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("unstable") && msg.contains("non-finite"),
        "{msg}"
    );
    let path = ck.failure_path.expect("last good state written");
    let last = Checkpoint::read(&path).unwrap();
    assert!(last.step <= 450 && last.step > 0);
    assert!(last.particles.sxx.iter().all(|v| v.is_finite()));
}
