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
    let shallow = simulate(&small_pin(20e-6), &mut []).unwrap().0;
    let deep = simulate(&small_pin(40e-6), &mut []).unwrap().0;
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
