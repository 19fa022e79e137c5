//! The pair passes run on the widest instruction set the CPU has (baseline SSE2, AVX2,
//! AVX-512; `greybox_sim::cpu`). Every path must give the same bits: the same cut on each
//! path the running CPU offers ends in an identical particle state and force history.
//!
//! This file holds one test only: the path is chosen process-wide, so no other test may run
//! beside it in this binary.

mod common;

use greybox_sim::cpu::{self, SimdPath};
use greybox_sim::cut_run::CutRun;
use greybox_sim::ConstantMu;
use std::sync::Arc;

/// Every float of the final state and the force history, as bits.
fn fingerprint(r: &CutRun) -> Vec<u64> {
    let p = &r.sim.particles;
    let mut bits: Vec<u64> = [
        &p.x, &p.y, &p.vx, &p.vy, &p.rho, &p.p, &p.sxx, &p.sxy, &p.syy, &p.eps_p, &p.temp,
    ]
    .iter()
    .flat_map(|v| v.iter().map(|f| f.to_bits()))
    .collect();
    bits.extend(
        r.forces
            .rows
            .iter()
            .flat_map(|row| row.iter().map(|f| f.to_bits())),
    );
    bits
}

#[test]
fn every_simd_path_gives_the_same_bits() {
    let mut setup = common::coarse_cut();
    // Long enough for a formed chip: contact, plasticity, heating and conduction all active.
    setup.cut_length_m = 0.15e-3;
    let run_on = |path: SimdPath| {
        let taken = cpu::set_path(path);
        let r = CutRun::execute(
            &setup,
            Arc::new(ConstantMu(0.35)),
            1.0,
            None,
            &mut greybox_sim::Hooks::new(),
        )
        .unwrap();
        (taken, fingerprint(&r), r.force)
    };
    let (_, reference, force) = run_on(SimdPath::Baseline);
    assert!(force[0] > 0.0 && force[1] > 0.0, "no cut: {force:?}");
    let mut compared = vec!["baseline"];
    for path in [SimdPath::Avx2, SimdPath::Avx512] {
        if !path.available() {
            eprintln!("{}: not on this CPU, not compared", path.name());
            continue;
        }
        let (taken, bits, _) = run_on(path);
        assert_eq!(taken, path);
        let differing = bits.iter().zip(&reference).filter(|(a, b)| a != b).count();
        assert_eq!(
            differing,
            0,
            "{} differs from the baseline in {differing} of {} values",
            path.name(),
            bits.len()
        );
        compared.push(path.name());
    }
    cpu::set_path(SimdPath::Avx512);
    eprintln!("identical bits on: {}", compared.join(", "));
}
