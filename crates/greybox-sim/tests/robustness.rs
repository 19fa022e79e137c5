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

/// Issue 62: a checkpoint is an input like any other. A state edited to a group index past
/// the set-up's groups (which panicked on the first step), a step of 2⁶⁴−1, a negative time,
/// a window at μ = 1000 or a non-finite particle value is refused naming the field; a FIFO in
/// its place is never opened.
#[test]
fn damaged_checkpoints_are_refused_naming_the_field() {
    let d = tempfile::tempdir().unwrap();
    let groups = vec![BoundaryGroup {
        name: "driver".into(),
        vx: Some(1.0),
        vy: None,
    }];
    let model = || {
        common::block_model(
            20,
            10,
            10e-6,
            Material::elastic_steel(),
            groups.clone(),
            |i, _| (i == 0) as u8,
        )
    };
    let mut sim = Solver::new(model()).unwrap();
    let path = d.path().join("ck.json");
    let mut ck = Checkpointer::new(&path, 50, "test");
    run(&mut sim, 1e-6, "test", Hooks::new().checkpoint(&mut ck)).unwrap();
    let good: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let edited = |f: &dyn Fn(&mut serde_json::Value)| {
        let mut v = good.clone();
        f(&mut v);
        let p = d.path().join("edited.json");
        std::fs::write(&p, v.to_string()).unwrap();
        p
    };
    let refused = |f: &dyn Fn(&mut serde_json::Value), needle: &str| {
        let e = Checkpoint::read(&edited(f)).unwrap_err().to_string();
        assert!(e.contains("edited.json") && e.contains(needle), "{e}");
    };
    refused(
        &|v| v["step"] = serde_json::json!(u64::MAX),
        "step 18446744073709551615",
    );
    refused(&|v| v["time_s"] = serde_json::json!(-1.0), "time_s = -1");
    refused(&|v| v["dt_s"] = serde_json::json!(0.0), "dt_s = 0");
    refused(
        &|v| v["particles"]["mass"] = serde_json::json!(0.0),
        "particles.mass = 0",
    );
    refused(
        &|v| v["particles"]["damage"][3] = serde_json::json!(-0.5),
        "particles.damage[3] = -0.5",
    );
    refused(
        &|v| v["particles"]["damage"][4] = serde_json::json!(2.5),
        "particles.damage[4] = 2.5",
    );
    // windows at μ = 1000 (the block has no tool: one added to the state read)
    let mut c = Checkpoint::read(&path).unwrap();
    c.tools.push(greybox_sim::checkpoint::ToolState {
        position: [0.0, 0.0],
        window_mu: vec![0.3, 1000.0],
        window_acc: vec![Default::default(); 2],
    });
    let e = c.check().unwrap_err();
    assert!(
        e.contains("tools[0].window_mu[1]") && e.contains("μ 1000"),
        "{e}"
    );
    // a group index past the set-up's one group: refused on restore, not a panic in a step
    let c = Checkpoint::read(&edited(&|v| {
        v["particles"]["group"][0] = serde_json::json!(7)
    }))
    .unwrap();
    let mut fresh = Solver::new(model()).unwrap();
    let e = c.restore(&mut fresh, "test").unwrap_err().to_string();
    assert!(
        e.contains("particles.group[0] = 7") && e.contains("1 boundary group"),
        "{e}"
    );
    // a FIFO named as the checkpoint
    let fifo = d.path().join("fifo.json");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let e = Checkpoint::read(&fifo).unwrap_err().to_string();
    assert!(e.contains("FIFO"), "{e}");
}
