//! Exact tables of tree ensembles, adaptive tables of smooth laws, and table files.
//!
//! The references are independent of the tables: tree ensembles walked node by node
//! (`TreeEnsemble::predict_one`, not the decision grid or the table), the laws themselves on
//! fresh random states that the refinement never saw, and table files written by hand.

mod common;
use common::{eq7, model, state};
use greybox_core::law::Range;
use greybox_core::{ContactState, FrictionLaw};
use greybox_friction::adaptive::AdaptiveTable;
use greybox_friction::adaptive_refine::RefineOptions;
use greybox_friction::exact_table::{ExactTable, DEFAULT_MAX_CELLS};
use greybox_friction::greybox::{GreyBoxLaw, PowerLaw};
use greybox_friction::learned::LearnedLaw;
use greybox_friction::spec::load_law;
use greybox_friction::table_file::{read_table, AnyTable, TableKind};
use greybox_model::family::FittedModel;
use greybox_model::tree::LEAF;
use greybox_model::Family;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Random states over (a margin around) a law's domain, with negative velocities too.
fn random_states(law: &dyn FrictionLaw, n: usize, seed: u64, margin: f64) -> Vec<ContactState> {
    let d = law.domain().unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut pick = |r: Range| {
        let pad = margin * (r.max - r.min);
        rng.gen_range(r.min - pad..=r.max + pad)
    };
    let t = d.temperature_k;
    (0..n)
        .map(|_| {
            state([
                pick(d.pressure_pa),
                pick(d.sliding_velocity_m_s),
                t.map_or(ContactState::ROOM_TEMPERATURE_K, &mut pick),
            ])
        })
        .collect()
}

#[test]
fn exact_tables_equal_the_walked_trees_bit_for_bit() {
    let cases: [(Family, &[&str]); 3] = [
        (
            Family::GradientBoosting,
            &["normal_force_N", "sliding_velocity_m_per_min"],
        ),
        (
            Family::RandomForest,
            &["hertz_pressure_MPa", "sliding_velocity_m_per_min"],
        ),
        (
            Family::GradientBoosting,
            &[
                "hertz_pressure_MPa",
                "sliding_velocity_m_per_min",
                "temperature_degC",
            ],
        ),
    ];
    for (family, features) in cases {
        let m = model(family, features);
        let FittedModel::TreeEnsemble(trees) = m.model.clone() else {
            panic!("not trees")
        };
        let law = LearnedLaw::new(m, None).unwrap();
        let mut table = ExactTable::build(&law, DEFAULT_MAX_CELLS).unwrap();
        let shape = table.shape();
        assert!(shape[0] > 20 && shape[1] > 10, "{features:?}: {shape:?}");
        assert_eq!(shape[2] > 1, features.len() == 3);
        // the table's own check: random states, every line and its neighbouring floats
        assert_eq!(table.check(&law, 20_000, 9, None), 0.0);
        // independently: the trees walked on the law's features, at every line ± 1 ulp and on
        // random states inside and around the domain (negative velocities included)
        let mut states = random_states(&law, 20_000, 4, 0.2);
        for s in states.iter_mut().step_by(2) {
            s.sliding_velocity_m_s = -s.sliding_velocity_m_s;
        }
        let lines = [
            &table.pressure_pa,
            &table.velocity_m_s,
            &table.temperature_k,
        ];
        let base = states[0];
        for (a, l) in lines.iter().enumerate() {
            for &b in l.iter() {
                for x in [b.next_down(), b, b.next_up()] {
                    let mut s = [
                        base.pressure_pa,
                        base.sliding_velocity_m_s,
                        base.temperature_k,
                    ];
                    s[a] = x;
                    states.push(state(s));
                }
            }
        }
        let n = features.len();
        for s in &states {
            let x = law.features(s);
            let want = trees.predict_one(&x[..n]);
            assert_eq!(
                table.mu(s).to_bits(),
                want.to_bits(),
                "{features:?} at {s:?}"
            );
        }
        // every line is a threshold restated: the feature goes left at b and right at b⁺
        for (a, l) in lines.iter().enumerate() {
            for &b in l.iter() {
                let (mut lo, mut hi) = ([1e9, 1.0, 400.0], [1e9, 1.0, 400.0]);
                lo[a] = b;
                hi[a] = b.next_up();
                let (xl, xh) = (law.features(&state(lo)), law.features(&state(hi)));
                let split = trees.nodes.iter().any(|nd| {
                    nd.feature != LEAF && {
                        let f = nd.feature as usize;
                        xl[f] <= nd.value && xh[f] > nd.value
                    }
                });
                assert!(
                    split,
                    "{features:?}: line {b:e} on axis {a} is no threshold"
                );
            }
        }
    }
}

#[test]
fn exact_tables_refuse_smooth_laws_and_oversized_grids() {
    let svr = LearnedLaw::new(
        model(
            Family::Svr,
            &["hertz_pressure_MPa", "sliding_velocity_m_per_min"],
        ),
        None,
    )
    .unwrap();
    let e = ExactTable::build(&svr, DEFAULT_MAX_CELLS)
        .unwrap_err()
        .to_string();
    assert!(e.contains("not piecewise constant"), "{e}");
    let gb = LearnedLaw::new(
        model(
            Family::GradientBoosting,
            &["normal_force_N", "sliding_velocity_m_per_min"],
        ),
        None,
    )
    .unwrap();
    let e = ExactTable::build(&gb, 50).unwrap_err().to_string();
    assert!(e.contains("cap of 50 cells"), "{e}");
}

/// Fresh random states (a seed the refinement never used) and the nodes themselves.
fn assert_within(table: &AdaptiveTable, law: &dyn FrictionLaw, tol: f64) -> f64 {
    let d = table.domain().unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(987_654);
    let mut worst: f64 = 0.0;
    for _ in 0..100_000 {
        let s = state([
            rng.gen_range(d.pressure_pa.min..=d.pressure_pa.max),
            rng.gen_range(d.sliding_velocity_m_s.min..=d.sliding_velocity_m_s.max),
            d.temperature_k
                .map_or(table.temperature_k[0], |t| rng.gen_range(t.min..=t.max)),
        ]);
        worst = worst.max((table.mu(&s) - law.mu(&s)).abs());
    }
    assert!(
        worst <= tol,
        "{}: fresh max deviation {worst:e}",
        law.name()
    );
    // every node but the last of an axis gives its value exactly
    let (np, nv) = (table.pressure_pa.len(), table.velocity_m_s.len());
    for &p in table.pressure_pa[..np - 1].iter().step_by(7) {
        for &v in table.velocity_m_s[..nv - 1].iter().step_by(5) {
            let s = state([p, v, table.temperature_k[0]]);
            assert_eq!(table.mu(&s), law.mu(&s), "node ({p}, {v})");
        }
    }
    worst
}

#[test]
fn adaptive_tables_meet_the_tolerance_on_fresh_states() {
    let cases: [(Family, &[&str]); 3] = [
        (
            Family::Svr,
            &["normal_force_N", "sliding_velocity_m_per_min"],
        ),
        (
            Family::Mlp,
            &["hertz_pressure_MPa", "sliding_velocity_m_per_min"],
        ),
        (
            Family::Svr,
            &[
                "hertz_pressure_MPa",
                "sliding_velocity_m_per_min",
                "temperature_degC",
            ],
        ),
    ];
    for (family, features) in cases {
        let law = LearnedLaw::new(model(family, features), None).unwrap();
        let mut o = RefineOptions::over_domain(&law).unwrap();
        o.check_points = 20_000;
        let t = AdaptiveTable::refine(&law, &o).unwrap();
        let dev = t.max_deviation.unwrap();
        assert!(dev <= 1e-4, "{dev}");
        let fresh = assert_within(&t, &law, 1e-4);
        eprintln!(
            "{family:?} {features:?}: {:?} nodes, refinement max deviation {dev:.2e}, fresh {fresh:.2e}",
            t.shape()
        );
        assert_eq!(t.shape()[2] > 1, features.len() == 3);
    }
}

#[test]
fn adaptive_tables_put_two_lines_at_every_declared_jump() {
    // a grey-box law around boosted trees: steps inside the domain, smooth power law and
    // blend outside, a shear cap that kinks
    let inner = LearnedLaw::new(
        model(
            Family::GradientBoosting,
            &["hertz_pressure_MPa", "sliding_velocity_m_per_min"],
        ),
        None,
    )
    .unwrap();
    let d = inner.domain().unwrap();
    let outside = PowerLaw::fit_to(&inner, 10).unwrap();
    let law = GreyBoxLaw::new(Box::new(inner), Box::new(outside), 0.1, Some(450e6), None).unwrap();
    let breaks = law.breaks().unwrap();
    assert!(!breaks.constant_between && breaks.pressure_pa.len() > 20);
    let wider = |r: Range| Range {
        min: (r.min - 0.2 * (r.max - r.min)).max(0.0),
        max: r.max + 0.2 * (r.max - r.min),
    };
    let mut o = RefineOptions::over(wider(d.pressure_pa), wider(d.sliding_velocity_m_s), None);
    o.check_points = 20_000;
    let t = AdaptiveTable::refine(&law, &o).unwrap();
    for &b in &breaks.pressure_pa {
        assert!(t.pressure_pa.binary_search_by(|x| x.total_cmp(&b)).is_ok());
        assert!(t
            .pressure_pa
            .binary_search_by(|x| x.total_cmp(&b.next_up()))
            .is_ok());
    }
    let fresh = assert_within(&t, &law, 1e-4);
    eprintln!(
        "grey-box over trees: {:?} nodes, fresh {fresh:.2e}",
        t.shape()
    );
    // a cap too small to reach the tolerance is an error that names the cap
    o.max_nodes = 2000;
    let e = AdaptiveTable::refine(&law, &o).unwrap_err().to_string();
    assert!(
        e.contains("cap of 2000 nodes") && e.contains("`tolerance`"),
        "{e}"
    );
}

#[test]
fn table_files_round_trip_through_load_law() {
    let dir = tempfile::tempdir().unwrap();
    let gb = LearnedLaw::new(
        model(
            Family::GradientBoosting,
            &["normal_force_N", "sliding_velocity_m_per_min"],
        ),
        None,
    )
    .unwrap();
    let svr = LearnedLaw::new(
        model(
            Family::Svr,
            &["hertz_pressure_MPa", "sliding_velocity_m_per_min"],
        ),
        Some(&eq7()),
    )
    .unwrap();
    let exact = AnyTable::Exact(ExactTable::build(&gb, DEFAULT_MAX_CELLS).unwrap());
    let mut o = RefineOptions::over_domain(&svr).unwrap();
    o.check_points = 5_000;
    let adaptive = AnyTable::Adaptive(AdaptiveTable::refine(&svr, &o).unwrap());
    for (name, t, src) in [
        ("exact.json", &exact, &gb as &dyn FrictionLaw),
        ("adaptive.json", &adaptive, &svr),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, t.to_json().unwrap()).unwrap();
        let back = read_table(&path).unwrap();
        assert_eq!(back.kind(), t.kind());
        assert_eq!(back.shape(), t.shape());
        let loaded = load_law(&path).unwrap();
        let read_once = greybox_friction::spec::LawFile::read(&path).unwrap();
        assert_eq!(read_once.inputs(), vec![path.clone()]);
        let built = read_once.build().unwrap();
        for s in random_states(src, 5_000, 21, 0.1) {
            assert_eq!(built.mu(&s).to_bits(), loaded.mu(&s).to_bits());
            assert_eq!(loaded.mu(&s).to_bits(), t.law().mu(&s).to_bits());
        }
        // through a law file, as the C ABI loads it
        let spec = dir.path().join(format!("law-{name}"));
        std::fs::write(&spec, format!(r#"{{"law": "table", "file": "{name}"}}"#)).unwrap();
        assert_eq!(
            greybox_friction::spec::law_inputs(&spec).unwrap(),
            vec![spec.clone(), path.clone()]
        );
        let s = random_states(src, 1, 5, 0.0)[0];
        assert_eq!(load_law(&spec).unwrap().mu(&s), t.law().mu(&s));
    }
    assert_eq!(exact.kind(), TableKind::Exact);
}

/// A uniform table as `greybox export --format table` wrote it before table kinds existed
/// (no schema_version, no kind).
const OLD_TABLE: &str = r#"{"schema":"greybox-table","source":"coulomb","pressure":{"min":1e8,"max":3e8,"n":3},"velocity":{"min":0.0,"max":2.0,"n":2},"temperature":null,"temperature_k":293.15,"values":[0.1,0.2,0.3,0.4,0.5,0.6],"max_deviation":null}"#;

#[test]
fn old_uniform_table_files_still_load() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("old.json");
    std::fs::write(&path, OLD_TABLE).unwrap();
    let t = read_table(&path).unwrap();
    assert_eq!(t.kind(), TableKind::Uniform);
    let law = load_law(&path).unwrap();
    // values[iv·np + ip]: bilinear midway between (1e8, 0) = 0.1, (2e8, 0) = 0.2,
    // (1e8, 2) = 0.4 and (2e8, 2) = 0.5
    let mu = law.mu(&ContactState::new(1.5e8, 1.0));
    assert!((mu - 0.3).abs() < 1e-15, "{mu}");
    assert_eq!(law.mu(&ContactState::new(3e8, -2.0)), 0.6);
}

#[test]
fn bad_table_files_name_the_file_and_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let exact = r#"{"schema":"greybox-table","schema_version":2,"kind":"exact","source":"x","pressure_Pa":[PRESSURES],"sliding_velocity_m_per_s":[1.0],"temperature_K":[],"values":[VALUES]}"#;
    let cases = [
        (
            OLD_TABLE.replace(r#""source""#, r#""schema_version":3,"source""#),
            "schema_version",
        ),
        (
            exact
                .replace("exact", "cubic")
                .replace("PRESSURES", "1")
                .replace("VALUES", "0"),
            "kind",
        ),
        (
            exact
                .replace("PRESSURES", "2e8,1e8")
                .replace("VALUES", "0,0,0,0,0,0"),
            "pressure_Pa",
        ),
        (
            exact
                .replace("PRESSURES", "1e8")
                .replace("VALUES", "0.3,0.3,0.3"),
            "values",
        ),
        (
            exact
                .replace("PRESSURES", "1e8")
                .replace(r#","values":[VALUES]"#, ""),
            "missing field `values`",
        ),
    ];
    for (k, (text, field)) in cases.iter().enumerate() {
        let path = dir.path().join(format!("bad{k}.json"));
        std::fs::write(&path, text).unwrap();
        let e = load_law(&path).err().expect("refused").to_string();
        assert!(
            e.contains(&format!("bad{k}.json")) && e.contains(field),
            "{field}: {e}"
        );
    }
    let path = dir.path().join("schema.json");
    std::fs::write(&path, OLD_TABLE.replace("greybox-table", "greybox-tables")).unwrap();
    let e = read_table(&path).unwrap_err().to_string();
    assert!(
        e.contains("schema.json") && e.contains("field 'schema'"),
        "{e}"
    );
}
