//! Physics as data: one table of the plausible ranges of every physical quantity greybox
//! reads, fits, exports or simulates, and one check that every reader, law, export and
//! simulation calls.
//!
//! Each [`Quantity`] has a **hard** range — outside it the value is impossible for the
//! machining and tribometer contacts greybox models, and [`check`] refuses it — and a
//! **usual** range — outside it the value is possible but rare, and [`check`] returns a
//! [`Flag`] the caller prints in its result and summary. Both messages carry the number, the
//! ranges and, where one fits, the likely unit mistake: "μ 2.94 … a load in kgf read as N
//! (÷9.807 → 0.3)?". A mistake is offered only when undoing it lands the number in the usual
//! range.
//!
//! Values are SI inside greybox (N, m/s, m, Pa, K); the table states them in SI. Quantities
//! with a direction (μ and forces of a reciprocating test) are checked by their magnitude:
//! the caller passes `abs()`.

use crate::setting::{SettingError, SettingPath};
use crate::units::Compact;

/// Every physical quantity greybox takes or produces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// Friction coefficient μ of one step, one law point or one table entry (dimensionless).
    Mu,
    /// The median μ of a whole identified campaign (dimensionless).
    CampaignMu,
    /// Normal force on a pin or tool, N.
    NormalForce,
    /// Tangential (friction) force, N.
    TangentialForce,
    /// Sliding velocity of a tribometer step or law point, m/s.
    SlidingVelocity,
    /// Track radius of a pin-on-disc or lathe tribometer, m.
    TrackRadius,
    /// Contact pressure (Hertz or nominal), Pa.
    ContactPressure,
    /// Shear flow stress of the softer body, Pa.
    ShearFlowStress,
    /// Temperature, K.
    Temperature,
    /// A share of a whole (ploughing share of μ, a fraction), 0..1.
    Share,
    /// Tresca shear (friction) factor m, τ = m·k, 0..1.
    ShearFactor,
    /// Cutting speed of a simulated cut, m/s.
    CuttingSpeed,
    /// Mass scaling factor of an explicit simulation (dimensionless, ≥ 1).
    MassScaling,
    /// Cutting (or feed) force per unit width of cut, N/m.
    ForcePerWidth,
    /// Density of a solid, kg/m³.
    Density,
    /// Young's modulus of a solid, Pa.
    YoungsModulus,
    /// Radius of curvature of a contact body (a pin's tip), m.
    ContactRadius,
    /// Width of a wear track, m.
    TrackWidth,
}

/// How a unit mistake changed the number: the intended value is `value / factor`
/// ([`Mistake::Scale`]), `1 / value` ([`Mistake::Inverse`]) or `value + offset`
/// ([`Mistake::Offset`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mistake {
    /// The number is `factor` × the intended one.
    Scale(f64, &'static str),
    /// The number is the reciprocal of the intended one (two channels swapped).
    Inverse(&'static str),
    /// The number is the intended one minus `offset` (°C read as K: offset 273.15).
    Offset(f64, &'static str),
    /// A spindle speed in rpm read as a speed: offered for any too-high value from 1 to 60 000.
    Rpm(&'static str),
}

/// One row of the table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spec {
    pub quantity: Quantity,
    /// The name in messages ("μ", "normal force").
    pub name: &'static str,
    /// SI unit ("" for dimensionless).
    pub unit: &'static str,
    /// Outside: refused. Inclusive.
    pub hard: (f64, f64),
    /// Outside: flagged. Inclusive, inside `hard`.
    pub usual: (f64, f64),
    /// Unit mistakes that move a usual value out of range.
    pub mistakes: &'static [Mistake],
    /// Why these ranges.
    pub why: &'static str,
}

const MU_MISTAKES: &[Mistake] = &[
    Mistake::Scale(9.80665, "a load in kgf read as N"),
    Mistake::Scale(100.0, "a COF (or a model's target) in % read as a fraction"),
    Mistake::Inverse("normal and friction channels swapped"),
    Mistake::Scale(
        1000.0,
        "the normal force in kN (or the tangential in mN) read as N",
    ),
    Mistake::Scale(
        1e-3,
        "the tangential force in kN (or the normal in mN) read as N",
    ),
];
const FORCE_MISTAKES: &[Mistake] = &[
    Mistake::Scale(1000.0, "a force in mN read as N"),
    Mistake::Scale(1e-3, "a force in kN read as N"),
    Mistake::Scale(1.0 / 9.80665, "a load in kgf read as N"),
];
const SPEED_MISTAKES: &[Mistake] = &[
    Mistake::Scale(60.0, "a speed in m/min read as m/s"),
    Mistake::Scale(1000.0, "a speed in mm/s read as m/s"),
    Mistake::Rpm("a spindle speed in rpm read as m/s"),
    Mistake::Scale(1e-3, "a speed in m/s read as mm/s"),
];
const LENGTH_MISTAKES: &[Mistake] = &[
    Mistake::Scale(1000.0, "a length in mm read as m"),
    Mistake::Scale(1e-3, "a length in m read as mm"),
];
const STRESS_MISTAKES: &[Mistake] = &[
    Mistake::Scale(
        1e6,
        "a stress in Pa given where MPa is asked (MPa read as Pa)",
    ),
    Mistake::Scale(1e-6, "a stress in MPa read as Pa"),
    Mistake::Scale(1e-9, "a stress in GPa read as Pa"),
    Mistake::Scale(1e-3, "a stress in GPa given where MPa is asked"),
];
const TEMPERATURE_MISTAKES: &[Mistake] =
    &[Mistake::Offset(273.15, "a temperature in °C read as K")];
const SHARE_MISTAKES: &[Mistake] = &[Mistake::Scale(100.0, "a share in % read as a fraction")];
const SMALL_LENGTH_MISTAKES: &[Mistake] = &[
    Mistake::Scale(
        1000.0,
        "a length in µm given where mm is asked (or mm where m)",
    ),
    Mistake::Scale(1e-3, "a length in mm given where µm is asked"),
];

/// The table: one row per [`Quantity`], in its declaration order.
pub const TABLE: &[Spec] = &[
    Spec {
        quantity: Quantity::Mu,
        name: "μ",
        unit: "",
        hard: (0.0, 3.0),
        usual: (0.005, 1.0),
        mistakes: MU_MISTAKES,
        why: "dry sliding of engineering materials gives 0.1-1, lubricated 0.005-0.15 (Bhushan, Introduction to Tribology, tab. 5.1); above 3 only clean metals in vacuum",
    },
    Spec {
        quantity: Quantity::CampaignMu,
        name: "the campaign's median μ",
        unit: "",
        hard: (0.005, 3.0),
        usual: (0.005, 1.0),
        mistakes: MU_MISTAKES,
        why: "a channel in the wrong unit in every pin moves all steps together: below 0.005 only superlubric contacts (kN read as N gives 0.0002-0.0007 for steel on steel)",
    },
    Spec {
        quantity: Quantity::NormalForce,
        name: "normal force",
        unit: "N",
        hard: (0.0, 1e6),
        usual: (1e-3, 5e4),
        mistakes: FORCE_MISTAKES,
        why: "micro-tribometers load from 1 mN, pin-on-disc and lathe rigs up to tens of kN; 1 MN is a press, not a contact",
    },
    Spec {
        quantity: Quantity::TangentialForce,
        name: "tangential force",
        unit: "N",
        hard: (0.0, 1e6),
        usual: (1e-4, 5e4),
        mistakes: FORCE_MISTAKES,
        why: "μ (≤ 3) times the normal force's range",
    },
    Spec {
        quantity: Quantity::SlidingVelocity,
        name: "sliding velocity",
        unit: "m/s",
        hard: (0.0, 200.0),
        usual: (1e-6, 20.0),
        mistakes: SPEED_MISTAKES,
        why: "tribometers slide from µm/s to ~10 m/s, high-speed machining reaches 1200 m/min (20 m/s); 200 m/s (12 000 m/min) is beyond any rig",
    },
    Spec {
        quantity: Quantity::TrackRadius,
        name: "track radius",
        unit: "m",
        hard: (1e-4, 5.0),
        usual: (1e-3, 0.5),
        mistakes: LENGTH_MISTAKES,
        why: "a pin is millimetres wide, a disc or turned workpiece at most a metre across",
    },
    Spec {
        quantity: Quantity::ContactPressure,
        name: "contact pressure",
        unit: "Pa",
        hard: (0.0, 1e11),
        usual: (1e3, 2e10),
        mistakes: STRESS_MISTAKES,
        why: "Hertz pressures of ceramics reach a few GPa, a diamond anvil 100 GPa",
    },
    Spec {
        quantity: Quantity::ShearFlowStress,
        name: "shear flow stress",
        unit: "Pa",
        hard: (0.0, 1e11),
        usual: (1e6, 5e9),
        mistakes: STRESS_MISTAKES,
        why: "soft polymers shear at MPa, hardened steels and carbides at a few GPa",
    },
    Spec {
        quantity: Quantity::Temperature,
        name: "temperature",
        unit: "K",
        hard: (0.0, 5000.0),
        usual: (200.0, 3000.0),
        mistakes: TEMPERATURE_MISTAKES,
        why: "absolute zero is the floor; tool and chip temperatures stay below the melting points (W 3695 K)",
    },
    Spec {
        quantity: Quantity::Share,
        name: "share",
        unit: "",
        hard: (0.0, 1.0),
        usual: (0.0, 1.0),
        mistakes: SHARE_MISTAKES,
        why: "a part of a whole",
    },
    Spec {
        quantity: Quantity::ShearFactor,
        name: "shear factor m",
        unit: "",
        hard: (0.0, 1.0),
        usual: (0.0, 1.0),
        mistakes: SHARE_MISTAKES,
        why: "τ = m·k, and the interface cannot shear above the softer body's shear flow stress k",
    },
    Spec {
        quantity: Quantity::CuttingSpeed,
        name: "cutting speed",
        unit: "m/s",
        hard: (1e-6, 1000.0),
        usual: (0.01, 100.0),
        mistakes: SPEED_MISTAKES,
        why: "turning runs at 0.1-20 m/s, a simulation may be sped up 10×; 1000 m/s is near the wave speeds of the workpiece",
    },
    Spec {
        quantity: Quantity::MassScaling,
        name: "mass scaling",
        unit: "",
        hard: (1.0, 1e8),
        usual: (1.0, 1e4),
        mistakes: &[],
        why: "explicit cutting simulations scale mass by 1-1000; beyond 1e8 inertia swamps the cut",
    },
    Spec {
        quantity: Quantity::ForcePerWidth,
        name: "force per width",
        unit: "N/m",
        hard: (0.0, 1e8),
        usual: (1e3, 1e7),
        mistakes: &[
            Mistake::Scale(1000.0, "a force per width in N/mm read as N/m"),
            Mistake::Scale(1e-3, "a force per width in N/m read as N/mm"),
        ],
        why: "orthogonal cuts give 1 N/mm (soft metal, thin chip) to 10 kN/mm",
    },
    Spec {
        quantity: Quantity::Density,
        name: "density",
        unit: "kg/m³",
        hard: (10.0, 30_000.0),
        usual: (500.0, 25_000.0),
        mistakes: &[
            Mistake::Scale(1e-3, "a density in g/cm³ read as kg/m³"),
            Mistake::Scale(1e3, "a density in g/m³ read as kg/m³"),
        ],
        why: "foams and polymers from a few hundred kg/m³, tungsten carbide 15 600, osmium 22 600",
    },
    Spec {
        quantity: Quantity::YoungsModulus,
        name: "Young's modulus",
        unit: "Pa",
        hard: (1e5, 2e12),
        usual: (1e8, 1.2e12),
        mistakes: &[
            Mistake::Scale(1e-9, "a modulus in GPa read as Pa"),
            Mistake::Scale(1e-6, "a modulus in MPa read as Pa"),
            Mistake::Scale(1e9, "a modulus in Pa given where GPa is asked"),
            Mistake::Scale(1e3, "a modulus in MPa given where GPa is asked"),
        ],
        why: "polymers from 0.1 GPa, steels 210 GPa, tungsten carbide 650 GPa, diamond 1 050-1 200 GPa",
    },
    Spec {
        quantity: Quantity::ContactRadius,
        name: "contact radius",
        unit: "m",
        hard: (1e-7, 100.0),
        usual: (1e-4, 1.0),
        mistakes: LENGTH_MISTAKES,
        why: "pin tips and balls of tribometers are 0.1-50 mm in radius; a flat has no finite one",
    },
    Spec {
        quantity: Quantity::TrackWidth,
        name: "track width",
        unit: "m",
        hard: (1e-7, 0.1),
        usual: (1e-5, 0.02),
        mistakes: SMALL_LENGTH_MISTAKES,
        why: "wear tracks of pin-on-disc tests are tens of µm to a few mm wide",
    },
];

impl Quantity {
    /// Its row of [`TABLE`] (the table lists the quantities in declaration order; a test
    /// checks it).
    pub const fn spec(self) -> &'static Spec {
        &TABLE[self as usize]
    }
    /// Outside: refused.
    pub fn hard(self) -> std::ops::RangeInclusive<f64> {
        let (a, b) = self.spec().hard;
        a..=b
    }
    /// Outside: flagged.
    pub fn usual(self) -> std::ops::RangeInclusive<f64> {
        let (a, b) = self.spec().usual;
        a..=b
    }
}

/// A value outside its usual range (inside the hard one): a line for the result and summary.
#[derive(Debug, Clone, PartialEq)]
pub struct Flag {
    pub quantity: Quantity,
    pub value: f64,
    pub text: String,
}

impl std::fmt::Display for Flag {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}

fn range_text(r: (f64, f64), unit: &str) -> String {
    let u = if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    };
    format!("{}..{}{u}", Compact(r.0), Compact(r.1))
}

/// The likely unit mistakes behind `value` (outside the usual range): every mistake of the
/// quantity whose undoing lands in the usual range, with the corrected number, joined by
/// " or ". `None` when none fits.
pub fn likely_mistake(q: Quantity, value: f64) -> Option<String> {
    let s = q.spec();
    let usual = q.usual();
    if !value.is_finite() || usual.contains(&value) {
        return None;
    }
    let found: Vec<String> = s
        .mistakes
        .iter()
        .filter_map(|m| {
            let (fixed, how, text) = match *m {
                Mistake::Scale(f, t) => (value / f, undo_text(f), t),
                Mistake::Inverse(t) => (1.0 / value, "1/μ".to_string(), t),
                Mistake::Offset(o, t) => (value + o, format!("+{o}"), t),
                Mistake::Rpm(t) => {
                    return (value > *usual.end() && (1.0..=60_000.0).contains(&value))
                        .then(|| t.to_string());
                }
            };
            usual
                .contains(&fixed)
                .then(|| format!("{text} ({how} → {})", Compact(round3(fixed))))
        })
        .collect();
    (!found.is_empty()).then(|| found.join(" or "))
}

/// How a scale mistake moved the number: "×1000", "÷9.80665".
fn factor_text(f: f64) -> String {
    if f >= 1.0 {
        format!("×{}", Compact(round_sig(f, 6)))
    } else {
        format!("÷{}", Compact(round_sig(1.0 / f, 6)))
    }
}

/// How to undo it: "÷1000", "×9.80665".
fn undo_text(f: f64) -> String {
    if f >= 1.0 {
        format!("÷{}", Compact(round_sig(f, 6)))
    } else {
        format!("×{}", Compact(round_sig(1.0 / f, 6)))
    }
}

/// Three significant digits, for a corrected value in a hint.
fn round3(v: f64) -> f64 {
    round_sig(v, 3)
}

/// `v` to `digits` significant digits (the nearest double to the decimal, so that it prints
/// short; unchanged where that cannot be computed).
fn round_sig(v: f64, digits: usize) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    format!("{:.*e}", digits.saturating_sub(1), v)
        .parse()
        .unwrap_or(v)
}

/// The likely unit mistake behind a measured `value` that differs from its `reference` (a
/// planned load, a set point): the scale mistakes of `q` whose factor the ratio
/// `value / reference` matches within 15 %, with the ratio. `None` when none does.
pub fn mistake_against(q: Quantity, value: f64, reference: f64) -> Option<String> {
    let ratio = value / reference;
    if !(ratio.is_finite() && ratio > 0.0) {
        return None;
    }
    let found: Vec<String> = q
        .spec()
        .mistakes
        .iter()
        .filter_map(|m| match *m {
            Mistake::Scale(f, t) if (ratio / f - 1.0).abs() <= 0.15 => Some(format!(
                "{t} ({} × the reference {})",
                Compact(round3(ratio)),
                Compact(reference)
            )),
            _ => None,
        })
        .collect();
    (!found.is_empty()).then(|| found.join(" or "))
}

fn describe(q: Quantity, value: f64, what: &str, hard: bool) -> String {
    let s = q.spec();
    let unit = if s.unit.is_empty() {
        String::new()
    } else {
        format!(" {}", s.unit)
    };
    let (this, other, other_name) = if hard {
        (s.hard, s.usual, "usual")
    } else {
        (s.usual, s.hard, "possible")
    };
    let mut t = format!(
        "{what}: {} {}{unit} is outside the {} range {} ({other_name} {})",
        s.name,
        Compact(round_sig(value, 4)),
        if hard { "possible" } else { "usual" },
        range_text(this, s.unit),
        range_text(other, s.unit)
    );
    if let Some(h) = likely_mistake(q, value) {
        t.push_str(": ");
        t.push_str(&h);
        t.push('?');
    }
    t
}

/// Check `value` of quantity `q` (SI), found at `what` (a field, a file and step): an error
/// outside the hard range (NaN and infinities included), a [`Flag`] outside the usual range,
/// `None` inside it. Both texts name `what`, the number, the ranges and the likely mistake.
pub fn check(q: Quantity, value: f64, what: &str) -> std::result::Result<Option<Flag>, String> {
    if !q.hard().contains(&value) {
        return Err(describe(q, value, what, true));
    }
    if !q.usual().contains(&value) {
        return Ok(Some(Flag {
            quantity: q,
            value,
            text: describe(q, value, what, false),
        }));
    }
    Ok(None)
}

/// [`check`] where a physical quantity enters a stage's settings: outside the hard range the
/// error, outside the usual range the flag said ([`crate::notes::note`]: a warning on the
/// command line, a `UnusualValueWarning` in Python) and the value accepted. The one call of
/// every settings validation ([`crate::rules::Rules::physics`] calls it too).
pub fn admit(q: Quantity, value: f64, what: &str) -> std::result::Result<(), String> {
    if let Some(flag) = check(q, value, what)? {
        crate::notes::note(flag.text);
    }
    Ok(())
}

/// [`admit`] for a setting: outside the hard range a [`SettingError`] of `path` (each surface
/// names the setting its own way), outside the usual range the note, naming the setting in
/// backticks.
pub fn admit_setting(q: Quantity, value: f64, path: &SettingPath) -> Result<(), SettingError> {
    let what = format!("`{path}`");
    match check(q, value, &what) {
        Err(m) => {
            let why = m.strip_prefix(&format!("{what}: ")).unwrap_or(&m);
            Err(SettingError::new(path.clone(), why))
        }
        Ok(Some(flag)) => {
            crate::notes::note(flag.text);
            Ok(())
        }
        Ok(None) => Ok(()),
    }
}

/// The table as Markdown (quantity, unit, hard, usual, unit mistakes), for docs and `--help`.
pub fn markdown_table() -> String {
    let mut t = String::from("| quantity | unit | hard (refused outside) | usual (flagged outside) | likely unit mistakes |\n|---|---|---|---|---|\n");
    for s in TABLE {
        let hints: Vec<String> = s
            .mistakes
            .iter()
            .map(|m| match *m {
                Mistake::Scale(f, t) => format!("{}: {t}", factor_text(f)),
                Mistake::Inverse(t) => format!("1/x: {t}"),
                Mistake::Offset(o, t) => format!("−{o}: {t}"),
                Mistake::Rpm(t) => t.to_string(),
            })
            .collect();
        t.push_str(&format!(
            "| {} | {} | {} | {} | {} |\n",
            s.name,
            if s.unit.is_empty() { "–" } else { s.unit },
            range_text(s.hard, ""),
            range_text(s.usual, ""),
            if hints.is_empty() {
                "–".to_string()
            } else {
                hints.join("; ")
            }
        ));
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn refused(q: Quantity, v: f64) -> String {
        check(q, v, "here").unwrap_err()
    }
    fn flagged(q: Quantity, v: f64) -> String {
        check(q, v, "here").unwrap().expect("flagged").text
    }

    #[test]
    fn every_quantity_has_one_row_with_usual_inside_hard() {
        use Quantity::*;
        let all = [
            Mu,
            CampaignMu,
            NormalForce,
            TangentialForce,
            SlidingVelocity,
            TrackRadius,
            ContactPressure,
            ShearFlowStress,
            Temperature,
            Share,
            ShearFactor,
            CuttingSpeed,
            MassScaling,
            ForcePerWidth,
            Density,
            YoungsModulus,
            ContactRadius,
            TrackWidth,
        ];
        assert_eq!(TABLE.len(), all.len());
        for q in all {
            assert_eq!(TABLE.iter().filter(|s| s.quantity == q).count(), 1, "{q:?}");
            let s = q.spec();
            assert!(s.hard.0 <= s.usual.0 && s.usual.1 <= s.hard.1, "{q:?}");
            assert!(!s.why.is_empty());
        }
        assert!(markdown_table().contains("| μ |"));
    }

    /// docs/reliability.md carries the table as the code has it.
    #[test]
    fn the_documented_table_is_this_one() {
        let doc = include_str!("../../../docs/reliability.md");
        let t = markdown_table();
        assert!(
            doc.contains(&t),
            "docs/reliability.md lacks the current table:\n{t}"
        );
    }

    #[test]
    fn usual_values_pass_and_nan_is_refused() {
        assert_eq!(check(Quantity::Mu, 0.4, "x"), Ok(None));
        assert!(refused(Quantity::Mu, f64::NAN).contains("NaN"));
        assert!(refused(Quantity::Temperature, f64::INFINITY).contains("inf"));
    }

    #[test]
    fn mu_names_each_unit_mistake() {
        // a load in kgf read as N: 0.3 × 9.81
        let t = flagged(Quantity::Mu, 2.94);
        assert!(
            t.starts_with("here: μ 2.94 is outside the usual range"),
            "{t}"
        );
        assert!(t.contains("usual range 0.005..1 (possible 0..3)"), "{t}");
        assert!(
            t.contains("a load in kgf read as N (÷9.80665 → 0.3)"),
            "{t}"
        );
        // swapped channels: 1 / 0.6
        let t = flagged(Quantity::Mu, 1.67);
        assert!(
            t.contains("normal and friction channels swapped (1/μ → 0.599)"),
            "{t}"
        );
        // a lubricated COF of 2.31 %
        let t = flagged(Quantity::Mu, 2.31);
        assert!(t.contains("in % read as a fraction (÷100 → 0.0231)"), "{t}");
        // refused beyond 3
        let t = refused(Quantity::Mu, 35.0);
        assert!(t.contains("μ 35 is outside the possible range"), "{t}");
        assert!(t.contains("in % read as a fraction (÷100 → 0.35)"), "{t}");
        let t = refused(Quantity::Mu, 1e300);
        assert!(t.contains("μ 1e300"), "{t}");
        // kN read as N
        let t = flagged(Quantity::Mu, 0.0004);
        assert!(t.contains("the tangential force in kN"), "{t}");
        let t = refused(Quantity::CampaignMu, 0.0004);
        assert!(
            t.contains("the campaign's median μ 0.0004 is outside the possible range 0.005..3"),
            "{t}"
        );
    }

    #[test]
    fn forces_name_kn_and_mn() {
        let t = refused(Quantity::NormalForce, 3e6);
        assert!(
            t.contains("normal force 3000000 N") && t.contains("mN read as N"),
            "{t}"
        );
        let t = flagged(Quantity::TangentialForce, 4e-5);
        assert!(t.contains("kN read as N"), "{t}");
        assert!(refused(Quantity::NormalForce, -1.0).contains("-1 N"));
    }

    #[test]
    fn a_load_against_its_plan_names_kgf_and_kn() {
        let t = mistake_against(Quantity::NormalForce, 15.3, 150.0).unwrap();
        assert!(
            t.contains("a load in kgf read as N (0.102 × the reference 150)"),
            "{t}"
        );
        let t = mistake_against(Quantity::NormalForce, 0.15, 150.0).unwrap();
        assert!(t.contains("kN read as N"), "{t}");
        assert_eq!(mistake_against(Quantity::NormalForce, 140.0, 150.0), None);
        assert_eq!(
            mistake_against(Quantity::NormalForce, f64::NAN, 150.0),
            None
        );
    }

    #[test]
    fn speeds_name_m_min_mm_s_and_rpm() {
        // 6000 m/min = 100 m/s: mm/s read as m/s (0.1 m/s meant)
        let t = flagged(Quantity::SlidingVelocity, 100.0);
        assert!(
            t.contains("a speed in mm/s read as m/s (÷1000 → 0.1)"),
            "{t}"
        );
        assert!(
            t.contains("a speed in m/min read as m/s (÷60 → 1.67)"),
            "{t}"
        );
        // 11 460 m/min = 191 m/s: rpm
        let t = flagged(Quantity::SlidingVelocity, 191.0);
        assert!(t.contains("a spindle speed in rpm read as m/s"), "{t}");
        let t = refused(Quantity::SlidingVelocity, 500.0);
        assert!(t.contains("rpm"), "{t}");
        let t = refused(Quantity::CuttingSpeed, 1e9);
        assert!(
            t.contains("cutting speed 1e9 m/s is outside the possible range"),
            "{t}"
        );
    }

    #[test]
    fn radii_name_mm_and_m() {
        let t = refused(Quantity::TrackRadius, 15e-6);
        assert!(t.contains("track radius 1.5e-5 m"), "{t}");
        assert!(
            t.contains("a length in m read as mm (×1000 → 0.015)"),
            "{t}"
        );
        let t = refused(Quantity::TrackRadius, 15.0);
        assert!(
            t.contains("a length in mm read as m (÷1000 → 0.015)"),
            "{t}"
        );
    }

    #[test]
    fn pressures_and_stresses_name_mpa() {
        let t = refused(Quantity::ContactPressure, 1.5e15);
        assert!(
            t.contains("MPa read as Pa") || t.contains("MPa is asked"),
            "{t}"
        );
        let t = flagged(Quantity::ShearFlowStress, 400.0);
        assert!(
            t.contains("a stress in MPa read as Pa (×1000000 → 4e8)"),
            "{t}"
        );
    }

    #[test]
    fn temperatures_name_celsius() {
        let t = flagged(Quantity::Temperature, 20.0);
        assert!(
            t.contains("a temperature in °C read as K (+273.15 → 293)"),
            "{t}"
        );
        let t = refused(Quantity::Temperature, -10.0);
        assert!(t.contains("°C read as K"), "{t}");
    }

    #[test]
    fn shares_and_shear_factors_name_percent() {
        let t = refused(Quantity::Share, -0.2);
        assert!(
            t.contains("share -0.2 is outside the possible range 0..1"),
            "{t}"
        );
        let t = refused(Quantity::ShearFactor, 5.0);
        assert!(
            t.contains("shear factor m 5") && t.contains("% read as a fraction"),
            "{t}"
        );
    }

    #[test]
    fn mass_scaling_and_force_per_width() {
        let t = refused(Quantity::MassScaling, 1e300);
        assert!(t.contains("mass scaling 1e300"), "{t}");
        assert!(flagged(Quantity::MassScaling, 1e5).contains("usual range 1..10000"));
        let t = flagged(Quantity::ForcePerWidth, 200.0);
        assert!(t.contains("N/m read as N/mm") || t.contains("N/mm"), "{t}");
    }

    /// Issue 62: the quantities of material and contact set-ups, with the slips a person
    /// makes typing them.
    #[test]
    fn densities_moduli_radii_and_track_widths_name_their_units() {
        let t = refused(Quantity::Density, 7.85);
        assert!(t.contains("g/cm³ read as kg/m³ (×1000 → 7850)"), "{t}");
        let t = refused(Quantity::YoungsModulus, 2.1e14);
        assert!(
            t.contains("MPa given where GPa is asked (÷1000 → 2.1e11)"),
            "{t}"
        );
        assert!(refused(Quantity::YoungsModulus, 650e18).contains("Young's modulus"));
        let t = flagged(Quantity::ContactRadius, 17e-6);
        assert!(
            t.contains("a length in m read as mm (×1000 → 0.017)"),
            "{t}"
        );
        assert!(refused(Quantity::ContactRadius, 1e305).contains("contact radius"));
        let t = flagged(Quantity::TrackWidth, 0.8e-6);
        assert!(
            t.contains("mm given where µm is asked (×1000 → 0.0008)"),
            "{t}"
        );
    }
}
