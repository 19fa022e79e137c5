//! A cut's steady state with its intervals, on real (coarse) cuts: two cuts whose μ differs by
//! 0.001 — the same cut within its scatter — give intervals that overlap; a cut that asks to
//! stop when sure stops once its targets are met, and runs to its limit (saying so) when
//! they cannot be.

mod common;

use greybox_core::stats::MeanInterval;

use common::cut_with_its_mu as cut;

fn overlap(a: &MeanInterval, b: &MeanInterval) -> bool {
    let (ha, hb) = (a.half_width.unwrap(), b.half_width.unwrap());
    (a.mean - b.mean).abs() <= ha + hb
}

#[test]
fn cuts_at_mu_0_001_apart_have_overlapping_intervals() {
    let mut setup = common::coarse_cut();
    setup.cut_length_m = 0.8e-3;
    setup.steady.min_cut_length_m = 0.15e-3;
    let a = cut(&setup);
    setup.mu += 0.001;
    let b = cut(&setup);
    let (sa, sb) = (a.steady_state.unwrap(), b.steady_state.unwrap());
    for (name, qa, qb) in [
        ("F'c", sa.cutting_force, sb.cutting_force),
        ("F'f", sa.feed_force, sb.feed_force),
    ] {
        println!(
            "{name}: {:.1} ± {:.1} and {:.1} ± {:.1} N/mm ({} and {} batches)",
            qa.mean * 1e-3,
            qa.half_width.unwrap_or(f64::NAN) * 1e-3,
            qb.mean * 1e-3,
            qb.half_width.unwrap_or(f64::NAN) * 1e-3,
            qa.batches,
            qb.batches
        );
        assert!(qa.batches >= 4 && qb.batches >= 4, "{name}: no interval");
        assert!(overlap(&qa, &qb), "{name}: {qa:?} {qb:?}");
        // the two cuts are one cut within its scatter: neither interval is degenerate
        assert!(qa.relative().unwrap() > 1e-4 && qa.relative().unwrap() < 0.5);
    }
    let (ha, hb) = (sa.chip_thickness.unwrap(), sb.chip_thickness.unwrap());
    if ha.half_width.is_some() && hb.half_width.is_some() {
        assert!(overlap(&ha, &hb), "chip thickness: {ha:?} {hb:?}");
    }
    // the stretch averaged holds whole units ending with the run
    let w = sa.window;
    assert!((w.to_s - w.from_s - w.units as f64 * w.unit_s).abs() < 1e-12 * w.to_s.max(1.0));
    assert!(w.from_s * setup.cutting_speed_m_s >= setup.steady.min_cut_length_m * (1.0 - 1e-9));
}

#[test]
fn a_cut_stops_once_sure_and_says_when_it_could_not_be() {
    let mut setup = common::coarse_cut();
    setup.cut_length_m = 0.8e-3;
    setup.steady.min_cut_length_m = 0.15e-3;
    setup.steady.stop_when_sure = true;
    setup.steady.cutting_force_rel_ci95 = 0.05;
    setup.steady.feed_force_rel_ci95 = 0.10;
    setup.steady.min_contact_renewals = 0.5;
    let sure = cut(&setup);
    let at = sure.sure_at_s.expect("loose targets are met");
    let v = setup.cutting_speed_m_s;
    let st = sure.steady_state.as_ref().unwrap();
    println!(
        "sure at {:.3} mm of {:.3}, contact renewal {:.3} mm, {:.2} renewals",
        at * v * 1e3,
        setup.cut_length_m * 1e3,
        st.contact_renewal_m.unwrap() * 1e3,
        st.renewals.unwrap()
    );
    assert!(
        at * v < 0.95 * setup.cut_length_m,
        "stopped at {:.3} mm",
        at * v * 1e3
    );
    assert!(sure.summary.stopped_by_observer);
    assert!(
        st.sure(&setup.steady),
        "the stretch at the stop meets the targets"
    );
    // the contact renewal: the contact length times the chip ratio, a fraction of a mm here
    let renewal = st.contact_renewal_m.unwrap();
    assert!(
        renewal > setup.uncut_chip_thickness_m && renewal < 2e-3,
        "{renewal}"
    );
    // the same targets but a stretch of 100 renewals asked: never sure, run to the limit
    setup.steady.min_contact_renewals = 100.0;
    let short = cut(&setup);
    assert_eq!(short.sure_at_s, None);
    assert!(short.steady_state.as_ref().unwrap().short(&setup.steady));
    // targets no cut of this length can meet: the same
    setup.steady.min_contact_renewals = 0.5;
    setup.steady.cutting_force_rel_ci95 = 1e-4;
    let limit = cut(&setup);
    assert_eq!(limit.sure_at_s, None);
    assert!(!limit.summary.stopped_by_observer);
    assert!(limit.sim.time * v >= 0.999 * setup.cut_length_m);
}

/// Collects the grey-box loop's contact length as each interval closes, the way the stop rule
/// reads it.
struct ContactAtClose {
    reader: greybox_sim::cut_series::LoopContact,
    samples: Vec<(f64, f64)>,
}

impl greybox_sim::Observer for ContactAtClose {
    fn after_step(
        &mut self,
        sim: &greybox_sim::Solver,
    ) -> Result<greybox_sim::Control, greybox_sim::SimError> {
        if let Some(l) = self.reader.at_close(sim, 0) {
            self.samples.push((sim.time, l));
        }
        Ok(greybox_sim::Control::Continue)
    }
}

#[test]
fn the_stop_rule_reads_every_interval_the_loop_closes_at_its_own_cadence() {
    let mut setup = common::coarse_cut();
    setup.cut_length_m = 0.4e-3;
    // the reader is made for the set-up as it was (every 100 steps); the loop then runs at a
    // cadence no other step count of the cut shares
    let mut seen = ContactAtClose {
        reader: greybox_sim::cut_series::LoopContact::new(&setup).unwrap(),
        samples: Vec::new(),
    };
    setup.friction.update_every_steps = 37;
    let run = greybox_sim::cut_run::CutRun::execute(
        &setup,
        std::sync::Arc::new(greybox_sim::ConstantMu(setup.mu)),
        1.0,
        None,
        &mut greybox_sim::Hooks::new().observe(&mut seen),
    )
    .unwrap();
    let [series, _, _] = greybox_sim::cut_series::contact_series(
        &run.updater,
        &run.sim.tools[0],
        &run.layout,
        run.sim.particles.spacing,
        setup.friction.window_length_m,
    );
    // the same samples, bit for bit: the summary's series leaves out the partial interval
    // the cut's end closes, which the stop rule never sees
    assert!(seen.samples.len() > 10, "{} samples", seen.samples.len());
    let last = run.updater.intervals.last().unwrap();
    assert!(
        last.partial,
        "the cut ends off the loop's cadence: its last interval is partial"
    );
    assert_eq!(seen.samples, series);
}
