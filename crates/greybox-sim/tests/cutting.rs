//! Orthogonal cutting with friction windows and the in-process grey-box loop (coarse and
//! fast: AISI 1045 at 20 µm spacing, 5 particles across h).
use greybox_core::{ContactState, FrictionLaw};
use greybox_sim::cut_run::CutRun;
use greybox_sim::cutting::CuttingSetup;
use greybox_sim::ConstantMu;
use std::sync::Arc;

mod common;
use common::coarse_cut;

/// A strongly velocity-dependent law: μ = 0.15 + 0.45 exp(−v / 0.5 m/s) (0.6 when sticking,
/// 0.21 at the chip's sliding speed).
struct VelocityLaw;

impl FrictionLaw for VelocityLaw {
    fn name(&self) -> String {
        "test velocity law".into()
    }
    fn mu(&self, s: &ContactState) -> f64 {
        0.15 + 0.45 * (-s.sliding_velocity_m_s / 0.5).exp()
    }
}

#[test]
fn greybox_loop_sets_each_window_to_the_law_at_its_recorded_state() {
    let setup = coarse_cut();
    let law: Arc<dyn FrictionLaw> = Arc::new(VelocityLaw);
    let r = CutRun::execute(
        &setup,
        law.clone(),
        1.0,
        None,
        &mut greybox_sim::Hooks::new(),
    )
    .unwrap();
    let h = &r.updater.history;
    assert!(h.len() > 50, "only {} window updates", h.len());
    // Each update: μ is the law at the state averaged over that interval, to round-off.
    for u in h {
        let state = ContactState {
            pressure_pa: u.stats.pressure_pa,
            sliding_velocity_m_s: u.stats.sliding_velocity_m_s,
            temperature_k: u.stats.temperature_k,
        };
        assert_eq!(u.mu, law.mu(&state));
        assert!(u.stats.pressure_pa > 0.0 && u.stats.pressure_pa.is_finite());
    }
    // The window keeps the μ of its last update.
    let tool = &r.sim.tools[0];
    for (k, w) in tool.windows.iter().enumerate() {
        if let Some(last) = h.iter().rev().find(|u| u.window == k) {
            assert_eq!(w.mu, last.mu, "window {k}");
        }
    }
    // A different, consistent profile: sticking windows near the edge carry a high μ,
    // sliding windows further up the rake a low one.
    let rake: Vec<_> = r
        .profile
        .iter()
        .filter(|p| p.distance_m >= 0.0 && p.stats.is_some())
        .collect();
    let mu_max = rake.iter().map(|p| p.mu).fold(0.0, f64::max);
    let mu_min = rake.iter().map(|p| p.mu).fold(1.0, f64::min);
    assert!(mu_max - mu_min > 0.1, "μ spread {mu_min}..{mu_max}");
    // Spearman-free check: the fastest-sliding window has a lower μ than the slowest.
    let by_v = |a: &&&greybox_sim::chip::ProfilePoint, b: &&&greybox_sim::chip::ProfilePoint| {
        let v = |p: &greybox_sim::chip::ProfilePoint| p.stats.unwrap().sliding_velocity_m_s;
        v(a).total_cmp(&v(b))
    };
    let slow = rake.iter().min_by(by_v).unwrap();
    let fast = rake.iter().max_by(by_v).unwrap();
    assert!(fast.mu < slow.mu);

    // Against a constant μ equal to the law's value at the nominal state: the forces differ.
    let nominal = law.mu(&setup.nominal_contact());
    let c = CutRun::execute(
        &setup,
        Arc::new(ConstantMu(nominal)),
        1.0,
        None,
        &mut greybox_sim::Hooks::new(),
    )
    .unwrap();
    assert!(c.updater.history.iter().all(|u| u.mu == nominal));
    let rel = (r.force[0] - c.force[0]).abs() / c.force[0];
    println!(
        "grey-box F'c {:.1} N/mm vs constant μ = {nominal:.3}: {:.1} N/mm; rake μ {mu_min:.3}..{mu_max:.3}",
        r.force[0] * 1e-3,
        c.force[0] * 1e-3
    );
    assert!(rel > 0.01, "forces differ by only {:.2} %", 100.0 * rel);
}

/// Same set-up, same bytes: twice, and on one and on two threads; with refinement too.
#[test]
fn same_setup_same_bytes() {
    let mut setup = coarse_cut();
    setup.cut_length_m = 0.1e-3;
    same_bytes_on_any_thread_count(&setup);
    same_bytes_on_any_thread_count(&common::refined(setup));
}

fn same_bytes_on_any_thread_count(setup: &greybox_sim::cutting::CuttingSetup) {
    let run = || {
        let r = CutRun::execute(
            setup,
            Arc::new(VelocityLaw),
            1.0,
            None,
            &mut greybox_sim::Hooks::new(),
        )
        .unwrap();
        (
            r.forces.rows.clone(),
            r.updater.history.iter().map(|u| u.mu).collect::<Vec<_>>(),
            r.sim.particles.x.clone(),
        )
    };
    // The half-list sums run in one fixed order: the same bytes on any thread count.
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(run)
    };
    let one = on(1);
    assert_eq!(one, on(2));
    assert_eq!(one, run());
}

#[test]
fn inverse_rate_sensitivity_recovers_the_c_that_made_the_force() {
    // "Measured" force: the coarse cut with C = 0.03; search C in [0, 0.1].
    let mut setup = coarse_cut();
    let law: Arc<dyn FrictionLaw> = Arc::new(ConstantMu(0.35));
    let mut truth = setup.clone();
    truth
        .material
        .plasticity
        .as_mut()
        .unwrap()
        .set_rate_sensitivity(0.03);
    let measured = CutRun::execute(
        &truth,
        law.clone(),
        1.0,
        None,
        &mut greybox_sim::Hooks::new(),
    )
    .unwrap()
    .force[0];
    setup
        .material
        .plasticity
        .as_mut()
        .unwrap()
        .set_rate_sensitivity(0.0);
    let fit = greybox_sim::cut_run::find_rate_sensitivity(
        &setup,
        law,
        measured,
        (0.0, 0.1),
        0.002 * measured,
        8,
    )
    .unwrap();
    println!(
        "C = {:.4} after {} runs: {:?}",
        fit.c,
        fit.runs.len(),
        fit.runs
    );
    assert!((fit.c - 0.03).abs() < 0.005, "C = {}", fit.c);
    assert!(fit.runs.len() <= 8);
    // Out of range: a clear error.
    let e = greybox_sim::cut_run::find_rate_sensitivity(
        &setup,
        Arc::new(ConstantMu(0.35)),
        10.0 * measured,
        (0.0, 0.1),
        1.0,
        4,
    )
    .unwrap_err();
    assert!(e.to_string().contains("widen the C range"), "{e}");
}

/// Stops the run after a given step (stands in for `kill -9` after a checkpoint).
struct KillAt(u64);
impl greybox_sim::Observer for KillAt {
    fn after_step(
        &mut self,
        sim: &greybox_sim::Solver,
    ) -> Result<greybox_sim::Control, greybox_sim::SimError> {
        Ok(if sim.step >= self.0 {
            greybox_sim::Control::Stop
        } else {
            greybox_sim::Control::Continue
        })
    }
}

/// A run killed after a checkpoint and resumed from it gives the uninterrupted run's force
/// history, chip samples, steady state, window updates, μ history, averages and profile, bit for bit
/// (resumed runs used to report only the rows after the checkpoint: F'c 213.9 against 202.0).
#[test]
fn resume_equals_the_uninterrupted_run() {
    let mut setup = coarse_cut();
    setup.cut_length_m = 0.15e-3;
    resume_equals_uninterrupted(&setup, 150);
}

/// The same with refinement: the particles split after the checkpoint are split alike, and
/// a checkpoint holds the split particles.
#[test]
fn a_refined_run_resumes_bit_for_bit() {
    let mut setup = common::refined(coarse_cut());
    setup.cut_length_m = 0.1e-3;
    resume_equals_uninterrupted(&setup, 150);
}

/// The same with a chip break: the checkpoint is written after the first particles left
/// (the chip of this cut first rises above 0.285 mm at about step 9 000 of 13 700), so it
/// holds fewer particles than the set-up lays out, and the resumed run removes the same
/// ones after it.
#[test]
fn a_run_with_a_chip_break_resumes_bit_for_bit() {
    let mut setup = coarse_cut();
    setup.cut_length_m = 0.8e-3;
    setup.chip_break_height_m = Some(0.285e-3);
    resume_equals_uninterrupted(&setup, 4800);
}

/// The same with ductile damage: the damage state is in the checkpoint, and the run is the
/// same bytes on one and on two threads. Damage must have initiated (a fracture energy of
/// 2 kJ/m² at 20 µm spacing softens within the cut), or the test would prove nothing.
#[test]
fn a_run_with_damage_resumes_bit_for_bit_on_any_thread_count() {
    let mut setup = coarse_cut();
    setup.cut_length_m = 0.15e-3;
    let mut damage = greybox_material::JohnsonCookDamage::ti6al4v_lesuer(293.15, 1773.0);
    damage.fracture_energy_j_m2 = 2000.0;
    setup.material.damage = Some(damage);
    let r = CutRun::execute(
        &setup,
        Arc::new(VelocityLaw),
        1.0,
        None,
        &mut greybox_sim::Hooks::new(),
    )
    .unwrap();
    let state = r.sim.particles.damage_state();
    assert!(
        state.initiated > 20 && state.max_degradation > 0.1,
        "{state:?}"
    );
    same_bytes_on_any_thread_count(&setup);
    resume_equals_uninterrupted(&setup, 150);
}

/// The same with local time stepping: a checkpoint is written only at the end of a coarse
/// step (here every = 151 is odd, so one step after the multiple when the coarse steps fall
/// on even steps), the rates and split lists are set alike after the resume, and the run is
/// the same bytes on one and on two threads. The slow particles must have taken 2Δt steps,
/// or the test would prove nothing.
#[test]
fn a_run_with_local_time_stepping_resumes_bit_for_bit_on_any_thread_count() {
    let mut setup = common::refined(coarse_cut());
    setup.cut_length_m = 0.1e-3;
    setup.numerics.local_time_stepping = true;
    let mut single_rate = setup.clone();
    single_rate.numerics.local_time_stepping = false;
    let work =
        |s: &greybox_sim::cutting::CuttingSetup| common::cut_with_its_mu(s).sim.particle_steps;
    let (multi, single) = (work(&setup), work(&single_rate));
    assert!(
        multi < single * 95 / 100,
        "{multi} particle-steps against {single} in one rate"
    );
    same_bytes_on_any_thread_count(&setup);
    resume_equals_uninterrupted(&setup, 151);
}

/// The same with the machined surface coarsened behind the tool (and the chip above 3h)
/// and local time stepping: merges happen before the checkpoint (it holds merged particles
/// and the split families the later merges read) and after it, alike in the resumed run and
/// on any thread count.
#[test]
fn a_run_with_coarsening_resumes_bit_for_bit_on_any_thread_count() {
    let mut setup = common::refined(coarse_cut());
    let r = setup.refinement.as_mut().unwrap();
    r.coarsen_behind_m = Some(0.06e-3);
    r.coarsen_chip_above_m = Some(0.3e-3);
    setup.numerics.local_time_stepping = true;
    let r = common::cut_with_its_mu(&setup);
    assert!(
        r.sim.energy.coarsened_particles > 30,
        "{} merged away",
        r.sim.energy.coarsened_particles
    );
    same_bytes_on_any_thread_count(&setup);
    // the first merge is at step 4020 (1668 idle; 4015 before merges waited for
    // the lists' rebuild): the checkpoint at 4402 holds
    // merged particles
    resume_equals_uninterrupted(&setup, 2201);
}

/// Runs `setup` whole, and killed at 2.5 × `every` steps after a checkpoint at 2 × `every`
/// and resumed from it; both must give the same bytes.
fn resume_equals_uninterrupted(setup: &greybox_sim::cutting::CuttingSetup, every: u64) {
    use greybox_sim::checkpoint::{Checkpoint, Checkpointer};
    let d = tempfile::tempdir().unwrap();
    let setup = setup.clone();
    let law: Arc<dyn FrictionLaw> = Arc::new(VelocityLaw);
    let id = greybox_sim::cut_run::fingerprint(&setup);
    let clean_ck = d.path().join("clean.json");
    let mut ck = Checkpointer::new(&clean_ck, every, &id);
    let clean = CutRun::execute(
        &setup,
        law.clone(),
        1.0,
        None,
        &mut greybox_sim::Hooks::new().checkpoint(&mut ck),
    )
    .unwrap();
    let steps = clean.sim.step;
    assert!(steps > 3 * every - every / 4, "{steps} steps");
    // the interrupted run: checkpoints, then killed between two of them
    let ck_path = d.path().join("killed.json");
    let mut ck = Checkpointer::new(&ck_path, every, &id);
    let kill_at = 2 * every + every / 2;
    let _ = CutRun::execute(
        &setup,
        law.clone(),
        1.0,
        None,
        &mut greybox_sim::Hooks::new()
            .observe(&mut KillAt(kill_at))
            .checkpoint(&mut ck),
    )
    .unwrap();
    let c = Checkpoint::read(&ck_path).unwrap();
    // at the end of the coarse step that reached 2 × every (one step later at most with
    // local time stepping)
    assert!((2 * every..=2 * every + 1).contains(&c.step), "{}", c.step);
    if setup.chip_break_height_m.is_some() {
        assert!(
            c.energy.removed_particles > 0,
            "the checkpoint precedes the break"
        );
    }
    if setup
        .refinement
        .as_ref()
        .is_some_and(|r| r.coarsen_behind_m.is_some())
    {
        assert!(
            c.energy.coarsened_particles > 0,
            "the checkpoint precedes the first merge"
        );
    }
    let mut ck = Checkpointer::new(&ck_path, every, &id);
    let resumed = CutRun::execute(
        &setup,
        law.clone(),
        1.0,
        Some(c),
        &mut greybox_sim::Hooks::new().checkpoint(&mut ck),
    )
    .unwrap();
    assert_eq!(resumed.sim.step, steps);
    assert_eq!(resumed.sim.particles.x, clean.sim.particles.x, "particles");
    assert_eq!(resumed.forces.rows, clean.forces.rows, "force history");
    assert_eq!(resumed.chip.samples, clean.chip.samples, "chip samples");
    assert_eq!(
        resumed.steady_state, clean.steady_state,
        "steady state and its intervals"
    );
    assert_eq!(resumed.sure_at_s, clean.sure_at_s);
    assert_eq!(
        resumed.updater.history, clean.updater.history,
        "window updates / μ history"
    );
    assert_eq!(resumed.force, clean.force, "averaged forces");
    assert_eq!(resumed.averaged_from_s, clean.averaged_from_s);
    assert_eq!(resumed.profile.len(), clean.profile.len());
    for (a, b) in resumed.profile.iter().zip(&clean.profile) {
        assert_eq!(format!("{a:?}"), format!("{b:?}"), "contact profile");
    }
    // a checkpoint at the end: nothing left to run is an error, not a force of zero
    let end = Checkpoint::read(&ck_path).unwrap();
    let done = CutRun::execute(
        &setup,
        law.clone(),
        (end.time_s / clean.sim.time).min(1.0) * 0.5,
        Some(end),
        &mut greybox_sim::Hooks::new(),
    );
    let e = done
        .err()
        .expect("a checkpoint past the end must be refused")
        .to_string();
    assert!(e.contains("past the requested end"), "{e}");
    // and a fraction shorter than one step
    let e = CutRun::execute(&setup, law, 1e-9, None, &mut greybox_sim::Hooks::new())
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("`fraction`") && e.contains("no step would run"),
        "{e}"
    );
}

/// Every numeric field of a cutting set-up: a bad value is refused with the field's name and
/// the rule it breaks (they used to share one sentence listing every rule at once).
#[test]
fn bad_configurations_name_the_field_and_the_rule() {
    type Mutation = fn(&mut CuttingSetup);
    let cases: Vec<(Mutation, &str)> = vec![
        (
            |s| s.cutting_speed_m_s = -5.0,
            "cutting_speed_m_s: cutting speed -5 m/s is outside the possible range 1e-6..1000 m/s",
        ),
        // used to run and report 0.0 N/mm
        (
            |s| s.cutting_speed_m_s = 1e9,
            "cutting_speed_m_s: cutting speed 1e9 m/s is outside the possible range 1e-6..1000 m/s",
        ),
        (
            |s| s.cutting_speed_m_s = 6000.0,
            "a speed in m/min read as m/s (÷60 → 100)",
        ),
        (
            |s| s.uncut_chip_thickness_m = 0.0,
            "uncut_chip_thickness_m must be > 0",
        ),
        (
            |s| s.cut_length_m = f64::NAN,
            "cut_length_m must be > 0, got NaN",
        ),
        (
            |s| s.spacing_m = f64::INFINITY,
            "spacing_m must be > 0, got inf",
        ),
        (|s| s.workpiece_height_m = 0.1e-3, "workpiece_height_m"),
        (
            |s| s.mu = -0.1,
            "mu: μ -0.1 is outside the possible range 0..3",
        ),
        (|s| s.mu = 30.0, "in % read as a fraction (÷100 → 0.3)"),
        (
            |s| s.initial_temperature_k = -10.0,
            "a temperature in °C read as K (+273.15 → 263)",
        ),
        (
            |s| s.initial_temperature_k = 0.0,
            "initial_temperature_k must be > 0",
        ),
        (
            |s| s.insert.rake_deg = 60.0,
            "insert.rake_deg must be in (-45, 45)",
        ),
        (
            |s| s.insert.clearance_deg = 0.0,
            "insert.clearance_deg must be in (0, 45)",
        ),
        (
            |s| s.insert.edge_radius_m = -1e-6,
            "insert.edge_radius_m must be ≥ 0",
        ),
        (
            |s| s.insert.rake_length_m = 0.0,
            "insert.rake_length_m must be > 0",
        ),
        (
            |s| s.insert.flank_length_m = -1.0,
            "insert.flank_length_m must be > 0",
        ),
        (
            |s| s.friction.window_length_m = 0.0,
            "friction.window_length_m must be > 0",
        ),
        (
            |s| s.friction.update_every_steps = 0,
            "friction.update_every_steps must be ≥ 1",
        ),
        (
            |s| s.steady.cutting_force_rel_ci95 = -1.0,
            "steady.cutting_force_rel_ci95 must be in (0, 1]",
        ),
        (
            |s| s.steady.feed_force_rel_ci95 = 0.0,
            "steady.feed_force_rel_ci95 must be in (0, 1]",
        ),
        (|s| s.numerics.cfl = 2.0, "cfl must be in (0, 1], got 2"),
        (
            |s| {
                *s = common::refined(s.clone());
                s.refinement.as_mut().unwrap().regions[0].below_m = f64::NAN;
            },
            "[refinement]: refinement region 1 is empty or not finite",
        ),
        (
            |s| {
                *s = common::refined(s.clone());
                let r = s.refinement.as_mut().unwrap();
                r.regions = vec![r.regions[0]; 4];
            },
            "refinement needs 1 to 3 regions (one per level), found 4",
        ),
        (
            |s| {
                *s = common::refined(s.clone());
                let r = s.refinement.as_mut().unwrap();
                let mut wider = r.regions[0];
                wider.ahead_m *= 2.0;
                r.regions.push(wider);
            },
            "refinement region 2 (level 2) must lie inside region 1",
        ),
        // the band three levels of refinement would sweep is counted before anything runs:
        // 10⁵ particles at 20 µm, 6.4·10⁶ with the children
        (
            |s| {
                *s = common::refined(s.clone());
                s.workpiece_height_m = 2e-3;
                s.cut_length_m = 0.02;
                let r = s.refinement.as_mut().unwrap();
                r.regions[0].below_m = 2e-3;
                r.regions = vec![r.regions[0]; 3];
            },
            "particles (its refinement included)",
        ),
        (
            |s| s.numerics.mass_scaling = 0.5,
            "mass_scaling: mass scaling 0.5 is outside the possible range 1..1e8",
        ),
        // used to run and report 0.0 N/mm
        (
            |s| s.numerics.mass_scaling = 1e300,
            "mass_scaling: mass scaling 1e300 is outside the possible range 1..1e8",
        ),
        (
            |s| s.numerics.friction_heat_share = 1.5,
            "friction_heat_share must be in [0, 1]",
        ),
        (
            |s| s.numerics.smoothing_ratio = 0.5,
            "smoothing_ratio must be in [1, 3]",
        ),
        (
            |s| s.material.density_kg_m3 = -1.0,
            "density_kg_m3 must be > 0",
        ),
        (
            |s| s.material.elastic.poisson_ratio = 0.5,
            "elastic.poisson_ratio must be in (-1, 0.5)",
        ),
        (
            |s| {
                s.material.plasticity = Some(
                    greybox_material::JohnsonCook {
                        n: 1.5,
                        ..greybox_material::JohnsonCook::aisi1045_article()
                    }
                    .into(),
                )
            },
            "n must be in (0, 1], got 1.5",
        ),
        (|s| s.spacing_m = 40e-6, "fewer than 4 particle spacings"),
    ];
    for (k, (mutate, want)) in cases.iter().enumerate() {
        let mut s = coarse_cut();
        mutate(&mut s);
        let e = s.validate().expect_err(want).to_string();
        assert!(e.contains(want), "case {k}: {e}");
        // and it reaches the run as an error, never a panic or a NaN
        let r = CutRun::execute(
            &s,
            Arc::new(ConstantMu(0.3)),
            1.0,
            None,
            &mut greybox_sim::Hooks::new(),
        );
        assert!(r.is_err(), "case {k}: ran");
    }
    coarse_cut().validate().unwrap();
    common::refined(coarse_cut()).validate().unwrap();
}

/// μ = 0.1 + 0.4 · p / 1.5 GPa (capped at 0.6): a law that passes every pressure jump on.
struct PressureLaw;

impl FrictionLaw for PressureLaw {
    fn name(&self) -> String {
        "test pressure law".into()
    }
    fn mu(&self, s: &ContactState) -> f64 {
        (0.1 + 0.4 * s.pressure_pa / 1.5e9).min(0.6)
    }
}

/// Mean |Δμ| between neighbouring rake/edge windows at the end, and between successive
/// updates of the same window.
fn roughness(r: &CutRun) -> (f64, f64) {
    let mus: Vec<f64> = r
        .profile
        .iter()
        .filter(|p| p.stats.is_some())
        .map(|p| p.mu)
        .collect();
    let space = mus.windows(2).map(|w| (w[1] - w[0]).abs()).sum::<f64>() / (mus.len() - 1) as f64;
    let mut last = std::collections::HashMap::new();
    let (mut sum, mut n) = (0.0, 0);
    for u in &r.updater.history {
        if let Some(prev) = last.insert(u.window, u.mu) {
            sum += (u.mu - prev).abs();
            n += 1;
        }
    }
    (space, sum / n as f64)
}

/// Smoothing in time (4 updates) and space (one neighbour each side) makes the μ profile of
/// a pressure-dependent law steadier along the tool and from update to update, and the state
/// the law saw follows the exponential average of the windows' states.
#[test]
fn smoothed_windows_give_a_steadier_mu_profile() {
    let mut setup = coarse_cut();
    setup.friction.update_every_steps = 50;
    let raw = CutRun::execute(
        &setup,
        Arc::new(PressureLaw),
        1.0,
        None,
        &mut greybox_sim::Hooks::new(),
    )
    .unwrap();
    setup.friction.smoothing = greybox_sim::friction_loop::Smoothing {
        time_updates: 4.0,
        space_windows: 1,
    };
    let smooth = CutRun::execute(
        &setup,
        Arc::new(PressureLaw),
        1.0,
        None,
        &mut greybox_sim::Hooks::new(),
    )
    .unwrap();
    let (rs, rt) = roughness(&raw);
    let (ss, st) = roughness(&smooth);
    eprintln!("mean |Δμ| between windows {rs:.4} → {ss:.4}, between updates {rt:.4} → {st:.4}");
    assert!(
        ss < 0.8 * rs && st < 0.6 * rt,
        "space {rs} → {ss}, time {rt} → {st}"
    );

    // Time only: the law state is the exponential average of the raw interval states.
    setup.friction.smoothing = greybox_sim::friction_loop::Smoothing {
        time_updates: 4.0,
        space_windows: 0,
    };
    let ema = CutRun::execute(
        &setup,
        Arc::new(PressureLaw),
        1.0,
        None,
        &mut greybox_sim::Hooks::new(),
    )
    .unwrap();
    let mut last: std::collections::HashMap<usize, f64> = Default::default();
    let mut checked = 0;
    for u in &ema.updater.history {
        let got = u.law_state.unwrap().pressure_pa;
        let want = match last.get(&u.window) {
            Some(&prev) => prev + 0.25 * (u.stats.pressure_pa - prev),
            None => u.stats.pressure_pa,
        };
        assert!(
            (got - want).abs() <= 1e-9 * want,
            "window {}: {got} vs {want}",
            u.window
        );
        assert_eq!(u.mu, PressureLaw.mu(&u.law_state.unwrap()));
        last.insert(u.window, got);
        checked += 1;
    }
    assert!(checked > 20);
}

/// A count in a set-up file is a bounded type: refused when the file is read, with the range
/// (`numerics.max_particles` of 0 or 10¹⁸ never reaches a run).
#[test]
fn counts_in_a_set_up_are_refused_when_read() {
    for (count, want) in [
        ("0", "0 is below the least allowed 1"),
        ("1000000000000000000", "above the cap of 1000000000"),
    ] {
        let e = toml::from_str::<greybox_sim::model::Numerics>(&format!("max_particles = {count}"))
            .unwrap_err()
            .to_string();
        assert!(e.contains(want) && e.contains("max_particles"), "{e}");
    }
}

/// A cut whose force is exactly 0 (the tool never engaged) is an error, not 0.0 N/mm; a force
/// beyond the physics table's range is refused with the number.
#[test]
fn a_zero_cutting_force_is_an_error() {
    use greybox_sim::cut_run::check_cutting_force;
    let e = check_cutting_force(0.0, 0.5e-3).unwrap_err().to_string();
    assert!(
        e.contains("cutting force of exactly 0 N/mm over 0.500 mm") && e.contains("never engaged"),
        "{e}"
    );
    let e = check_cutting_force(1e12, 0.5e-3).unwrap_err().to_string();
    assert!(
        e.contains("cutting force: force per width 1e12 N/m is outside the possible range"),
        "{e}"
    );
    check_cutting_force(2e5, 0.5e-3).unwrap();
}
