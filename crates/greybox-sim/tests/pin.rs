//! Pin sliding (small pin, coarse): the deformation share F_t/F_N − μ grows with depth, and the
//! energy balance (kinetic + elastic + plastic + friction + penalty + viscous = external work)
//! closes within 2 %.
use greybox_sim::pin::{simulate, PinSetup};

fn small_pin(depth: f64) -> PinSetup {
    let mut s = PinSetup::article(depth, 0.2, 10e-6);
    s.pin_radius_m = 1e-3;
    s.slide_length_m = 0.3e-3;
    s.workpiece_height_m = 0.2e-3;
    s
}

#[test]
fn ploughing_share_grows_with_depth_and_energy_balances() {
    let shallow = simulate(&small_pin(20e-6), &mut greybox_sim::Hooks::new())
        .unwrap()
        .0;
    let deep = simulate(&small_pin(40e-6), &mut greybox_sim::Hooks::new())
        .unwrap()
        .0;
    for r in [&shallow, &deep] {
        eprintln!(
            "d = {:.0} µm: F_t/F_N = {:.4}, share {:.4} (analytic {:.4}), energy error {:.2} %",
            r.depth_m * 1e6,
            r.force_ratio,
            r.deformation_share,
            r.analytic_share,
            100.0 * r.energy_error
        );
        assert!(
            r.energy_error.abs() < 0.02,
            "energy balance off by {}",
            r.energy_error
        );
        assert!(r.deformation_share > 0.0);
    }
    assert!(deep.deformation_share > shallow.deformation_share);
}

/// A simulated F_t/F_N below the adhesive μ gave a negative ploughing share without a word:
/// it is now reported in the result's `unusual` lines with the numbers.
#[test]
fn a_negative_ploughing_share_is_reported() {
    use greybox_sim::pin::ploughing_share_flags;
    let f = ploughing_share_flags(0.28, 0.3);
    assert_eq!(f.len(), 1, "{f:?}");
    assert!(
        f[0].contains("ploughing (F_t/F_N 0.2800 − μ 0.3) / F_t/F_N: share -0.07143 is outside the possible range 0..1")
            && f[0].contains("below the adhesive μ"),
        "{f:?}"
    );
    assert!(ploughing_share_flags(0.35, 0.3).is_empty());
}

/// The pin set-up's μ, sliding speed and temperature are checked against the physics table.
#[test]
fn a_pin_set_up_in_the_wrong_unit_is_refused() {
    let mut s = small_pin(20e-6);
    s.mu = 30.0;
    let e = s.validate().unwrap_err().to_string();
    assert!(
        e.contains("mu: μ 30 is outside the possible range 0..3")
            && e.contains("in % read as a fraction (÷100 → 0.3)"),
        "{e}"
    );
    let mut s = small_pin(20e-6);
    s.sliding_speed_m_s = 6000.0;
    let e = s.validate().unwrap_err().to_string();
    assert!(
        e.contains(
            "sliding_speed_m_s: sliding velocity 6000 m/s is outside the possible range 0..200 m/s"
        ),
        "{e}"
    );
}
