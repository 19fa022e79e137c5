use greybox_sim::cutting::CuttingSetup;
use greybox_sim::output::{ForceHistory, VtkSeries};
use greybox_sim::*;
fn main() {
    let frac: f64 = std::env::args()
        .nth(1)
        .map(|a| a.parse().unwrap())
        .unwrap_or(0.1);
    let setup = CuttingSetup::iwf_ti64_reference();
    let (model, duration) = setup.model().unwrap();
    let mut sim = Solver::new(model).unwrap();
    println!(
        "particles {} dt {:.3e} steps for full cut {:.0}",
        sim.particle_count(),
        sim.dt,
        duration / sim.dt
    );
    let mut hist = ForceHistory::new(0, 200);
    let mut vtk = VtkSeries::new(std::path::Path::new("/tmp/cutvtk"), 20000);
    let s = run(&mut sim, duration * frac, &mut [&mut hist, &mut vtk]).unwrap();
    println!("{:?}", s);
    println!(
        "per core {:.3e}",
        s.particle_steps_per_s / rayon::current_num_threads() as f64
    );
    for r in hist.rows.iter().step_by((hist.rows.len() / 10).max(1)) {
        println!(
            "t {:.3e} Fx {:.1} Fy {:.1} N/mm n {}",
            r[0],
            r[3] * 1e-3,
            r[4] * 1e-3,
            r[5]
        );
    }
    println!(
        "nl builds {} stride {}",
        sim.neighbours.builds, sim.neighbours.stride
    );
}
