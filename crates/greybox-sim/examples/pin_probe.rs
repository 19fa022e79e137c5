use greybox_sim::pin::{simulate, PinSetup};
fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let mut s = PinSetup::article(args[0] * 1e-6, args[1], args[2] * 1e-6);
    if args.len() > 3 {
        s.slide_length_m = args[3] * 1e-3;
    }
    if args.len() > 4 {
        s.mach = args[4];
    }
    if std::env::var("ELASTIC").is_ok() {
        s.material = greybox_material::Material::elastic_steel();
    }
    if std::env::var("NOAS").is_ok() {
        s.numerics.artificial_stress = 0.0;
    }
    if std::env::var("NOTH").is_ok() {
        s.numerics.thermal = false;
    }
    if let Ok(v) = std::env::var("RADIUS") {
        s.pin_radius_m = v.parse::<f64>().unwrap() * 1e-3;
    }
    if let Ok(v) = std::env::var("HEIGHT") {
        s.workpiece_height_m = v.parse::<f64>().unwrap() * 1e-3;
    }
    let (r, h, sim) = simulate(&s, &mut []).unwrap();
    println!("{}", serde_json::to_string_pretty(&r).unwrap());
    println!("{:?}", sim.energy_balance());
    println!("builds {}", sim.neighbours.builds);
    if std::env::var("HIST").is_ok() {
        for row in h.rows.iter().step_by(10) {
            println!("{:?}", row);
        }
    }
}
