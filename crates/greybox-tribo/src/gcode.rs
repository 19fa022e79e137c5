//! ISO (Fanuc-style) lathe programs for a tribometer plan, and a parser that reads them back.
//!
//! One program per pin: `G97` constant spindle speed, `S… M03` per velocity step, `G04 X…`
//! dwell in seconds (the NC does not wait for speed arrival, so each dwell is the nominal
//! ramp time plus the plateau dwell), and a configurable M-code pair that switches the
//! recording trigger output. The plan parameters are stated in `(PLAN KEY=VALUE)` header
//! comments so that the program alone documents — and can rebuild — the campaign.

use crate::plan::{PinCount, Plan, PlanSpec, VelocityCount};
use greybox_core::{units, Error, Result, SourcePos};
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// Write the NC program of one pin (1-based).
pub fn write_program(plan: &Plan, pin: u32) -> String {
    let spec = &plan.spec;
    let sched = &plan.pins[pin as usize - 1];
    let steps = plan.pin_steps(pin);
    let d = spec.rpm_decimals as usize;
    let mut g = String::new();
    let mut n = 0u32;
    let mut block = |g: &mut String, text: &str| {
        n += 10;
        let _ = writeln!(g, "N{n} {text}");
    };
    let _ = writeln!(g, "%");
    let _ = writeln!(
        g,
        "O{} (GREYBOX TRIBOMETER PIN {} OF {})",
        1000 + pin,
        pin,
        plan.pins.len()
    );
    let v_first = units::m_per_s_to_m_per_min(steps[0].sliding_velocity_m_s);
    let v_last = units::m_per_s_to_m_per_min(steps[steps.len() - 1].sliding_velocity_m_s);
    for (k, v) in [
        ("PIN", format!("{pin}")),
        ("PINS", format!("{}", plan.pins.len())),
        ("NORMAL_FORCE_N", format!("{}", sched.normal_force_n)),
        (
            "TRACK_RADIUS_MM",
            format!("{}", plan.track_radius_m() / units::M_PER_MM),
        ),
        ("VELOCITY_STEPS", format!("{}", steps.len())),
        ("VELOCITY_FIRST_M_PER_MIN", format!("{v_first}")),
        ("VELOCITY_LAST_M_PER_MIN", format!("{v_last}")),
        ("DWELL_S", format!("{}", spec.dwell_s)),
        (
            "SPINDLE_ACCEL_RPM_PER_S",
            format!("{}", spec.spindle_accel_rpm_per_s),
        ),
        ("MAX_SPINDLE_RPM", format!("{}", spec.max_spindle_rpm)),
        ("ZERO_TIME_S", format!("{}", spec.zero_time_s)),
        ("LOAD_TIME_S", format!("{}", spec.load_time_s)),
        ("TRIGGER_ON", format!("M{}", spec.trigger_on_mcode)),
        ("TRIGGER_OFF", format!("M{}", spec.trigger_off_mcode)),
    ] {
        let _ = writeln!(g, "(PLAN {k}={v})");
    }
    let _ = writeln!(
        g,
        "(EACH G04 AFTER AN S WORD = NOMINAL SPINDLE RAMP + DWELL)"
    );
    block(&mut g, "G97 M05");
    block(
        &mut g,
        &format!("M{} (RECORDING TRIGGER ON)", spec.trigger_on_mcode),
    );
    block(
        &mut g,
        &format!("G04 X{:.3} (UNLOADED ZERO REFERENCE)", spec.zero_time_s),
    );
    block(
        &mut g,
        &format!("(APPLY NORMAL LOAD {} N)", sched.normal_force_n),
    );
    block(&mut g, &format!("G04 X{:.3}", spec.load_time_s));
    for s in steps {
        let v = units::m_per_s_to_m_per_min(s.sliding_velocity_m_s);
        block(
            &mut g,
            &format!("S{:.d$} M03 (STEP {} V={v} M/MIN)", s.spindle_rpm, s.step),
        );
        block(
            &mut g,
            &format!("G04 X{:.3}", s.plateau_end_s - s.step_start_s),
        );
    }
    block(&mut g, "M05 (SPINDLE STOP)");
    block(
        &mut g,
        &format!(
            "G04 X{:.3} (SPINDLE RAMP DOWN)",
            sched.unload_start_s - sched.spindle_stop_s
        ),
    );
    block(&mut g, "(RELEASE NORMAL LOAD)");
    block(&mut g, &format!("G04 X{:.3}", spec.load_time_s));
    block(
        &mut g,
        &format!("G04 X{:.3} (UNLOADED ZERO REFERENCE)", spec.zero_time_s),
    );
    block(
        &mut g,
        &format!("M{} (RECORDING TRIGGER OFF)", spec.trigger_off_mcode),
    );
    block(&mut g, "M30");
    let _ = writeln!(g, "%");
    g
}

/// What the NC does, in program order.
#[derive(Debug, Clone, PartialEq)]
pub enum NcEvent {
    /// Spindle on (M03/M04) at a speed, rpm.
    Spindle { rpm: f64 },
    /// Spindle stop (M05).
    SpindleStop,
    /// Dwell, s.
    Dwell { seconds: f64 },
    /// Any other M-code.
    MCode(u32),
}

/// A parsed NC program: its header parameters and its events.
#[derive(Debug, Clone, PartialEq)]
pub struct NcProgram {
    pub source: String,
    pub program_number: Option<u32>,
    /// `(PLAN KEY=VALUE)` comments.
    pub plan_params: BTreeMap<String, String>,
    pub events: Vec<NcEvent>,
}

/// Parse an ISO program (the subset greybox writes, tolerant of spacing, `;` comments and
/// word order; rejects unknown G-codes and malformed words with the line number).
pub fn parse_program(text: &str, source: &str) -> Result<NcProgram> {
    let mut prog = NcProgram {
        source: source.to_string(),
        program_number: None,
        plan_params: BTreeMap::new(),
        events: Vec::new(),
    };
    let mut spindle_on = false;
    let mut s_word: Option<f64> = None;
    for (i, raw) in text.lines().enumerate() {
        let line = i as u64 + 1;
        let pos = || SourcePos::file(source).line(line);
        let code = strip_comments(raw, &pos, &mut prog.plan_params)?;
        let code = code.trim();
        if code.is_empty() || code == "%" {
            continue;
        }
        let words = words(code, &pos)?;
        let mut dwell = false;
        let mut dwell_s: Option<f64> = None;
        let mut mcodes = Vec::new();
        for &(letter, value, num) in &words {
            match letter {
                'N' => {}
                'O' => prog.program_number = Some(value as u32),
                'G' => match value as u32 {
                    4 => dwell = true,
                    97 | 96 | 21 | 18 | 40 | 90 => {}
                    g => return Err(Error::input(pos(), format!("unsupported G-code G{g}"))),
                },
                'S' => {
                    if value <= 0.0 {
                        return Err(Error::input(
                            pos(),
                            format!("spindle speed must be positive, found S{num}"),
                        ));
                    }
                    s_word = Some(value);
                }
                'X' | 'P' if dwell || words.iter().any(|w| w.0 == 'G' && w.1 == 4.0) => {
                    // Fanuc: X in seconds; P in milliseconds (integer)
                    dwell_s = Some(if letter == 'X' { value } else { value / 1000.0 });
                }
                'M' => mcodes.push(value as u32),
                other => {
                    return Err(Error::input(
                        pos(),
                        format!("unsupported word {other}{num}"),
                    ))
                }
            }
        }
        if let Some(rpm) = s_word.filter(|_| words.iter().any(|w| w.0 == 'S')) {
            if spindle_on || mcodes.iter().any(|m| matches!(m, 3 | 4)) {
                prog.events.push(NcEvent::Spindle { rpm });
            }
        }
        for m in mcodes {
            match m {
                3 | 4 => {
                    if !spindle_on && !words.iter().any(|w| w.0 == 'S') {
                        let rpm = s_word
                            .ok_or_else(|| Error::input(pos(), "M03 without a spindle speed S"))?;
                        prog.events.push(NcEvent::Spindle { rpm });
                    }
                    spindle_on = true;
                }
                5 => {
                    if spindle_on {
                        prog.events.push(NcEvent::SpindleStop);
                    }
                    spindle_on = false;
                }
                30 | 2 => {}
                other => prog.events.push(NcEvent::MCode(other)),
            }
        }
        if dwell {
            let s = dwell_s
                .ok_or_else(|| Error::input(pos(), "G04 without a dwell time X (s) or P (ms)"))?;
            if !(s >= 0.0) {
                return Err(Error::input(
                    pos(),
                    format!("dwell must be non-negative, found {s}"),
                ));
            }
            prog.events.push(NcEvent::Dwell { seconds: s });
        }
    }
    Ok(prog)
}

/// A line's code without its comments (`(...)`, each replaced by a space, and `;` to the end
/// of the line); `(PLAN KEY=VALUE)` comments go into `plan_params`.
fn strip_comments(
    raw: &str,
    pos: &impl Fn() -> SourcePos,
    plan_params: &mut BTreeMap<String, String>,
) -> Result<String> {
    let mut code = String::new();
    let mut rest = raw;
    while let Some(open) = rest.find(['(', ';']) {
        code.push_str(&rest[..open]);
        if rest.as_bytes()[open] == b';' {
            rest = "";
            break;
        }
        let close = rest[open..]
            .find(')')
            .ok_or_else(|| Error::input(pos(), "unclosed comment '('"))?
            + open;
        let comment = rest[open + 1..close].trim();
        if let Some(kv) = comment.strip_prefix("PLAN ") {
            let (k, v) = kv.split_once('=').ok_or_else(|| {
                Error::input(pos(), format!("plan comment without '=': '{comment}'"))
            })?;
            plan_params.insert(k.trim().to_string(), v.trim().to_string());
        }
        code.push(' ');
        rest = &rest[close + 1..];
    }
    code.push_str(rest);
    Ok(code)
}

/// The words of a line's code: (letter in upper case, value, the number as written).
fn words<'c>(code: &'c str, pos: &impl Fn() -> SourcePos) -> Result<Vec<(char, f64, &'c str)>> {
    let bytes = code.as_bytes();
    let mut words: Vec<(char, f64, &str)> = Vec::new();
    let mut j = 0;
    while j < bytes.len() {
        let c = bytes[j] as char;
        if c.is_whitespace() {
            j += 1;
            continue;
        }
        if !c.is_ascii_alphabetic() {
            return Err(Error::input(
                pos(),
                format!("unexpected character '{c}' in '{code}'"),
            ));
        }
        let start = j + 1;
        let mut k = start;
        while k < bytes.len()
            && (bytes[k].is_ascii_digit() || matches!(bytes[k], b'.' | b'-' | b'+'))
        {
            k += 1;
        }
        let num = &code[start..k];
        let value: f64 = num.parse().map_err(|_| {
            Error::input(pos(), format!("word '{c}' needs a number, found '{num}'"))
        })?;
        words.push((c.to_ascii_uppercase(), value, num));
        j = k;
    }
    Ok(words)
}

impl NcProgram {
    fn param(&self, key: &str) -> Result<f64> {
        let v = self.plan_params.get(key).ok_or_else(|| {
            Error::input(
                SourcePos::file(&self.source).field(key),
                format!("missing header comment (PLAN {key}=...)"),
            )
        })?;
        v.trim_start_matches('M').parse().map_err(|_| {
            Error::input(
                SourcePos::file(&self.source).field(key),
                format!("expected a number, found '{v}'"),
            )
        })
    }
}

/// One pin's program read against the event sequence greybox writes: the zero, load and
/// plateau dwells into `spec`, and the step velocities, m/min, from the S words on a track
/// of `radius_mm` (ramps at `accel` rpm/s taken out of each step's dwell).
fn read_pin_events(
    prog: &NcProgram,
    spec: &mut PlanSpec,
    radius_mm: f64,
    accel: f64,
) -> Result<Vec<f64>> {
    let err = |msg: String| Error::input(SourcePos::file(&prog.source), msg);
    // The event sequence: trigger on, zero dwell, load dwell, (S, dwell)*, stop, ramp-down,
    // unload dwell, zero dwell, trigger off.
    let ev = &prog.events;
    let on = ev
        .iter()
        .position(|e| *e == NcEvent::MCode(spec.trigger_on_mcode))
        .ok_or_else(|| err(format!("no trigger-on M{}", spec.trigger_on_mcode)))?;
    let dwell_at = |i: usize| match ev.get(i) {
        Some(NcEvent::Dwell { seconds }) => Ok(*seconds),
        other => Err(err(format!(
            "expected a G04 dwell as event {i}, found {other:?}"
        ))),
    };
    spec.zero_time_s = dwell_at(on + 1)?;
    spec.load_time_s = dwell_at(on + 2)?;
    let mut i = on + 3;
    let mut prev = 0.0;
    let mut vs = Vec::new();
    let mut dwells = Vec::new();
    while let Some(NcEvent::Spindle { rpm }) = ev.get(i) {
        let total = dwell_at(i + 1)?;
        dwells.push(total - (rpm - prev).abs() / accel);
        vs.push(units::m_per_s_to_m_per_min(units::velocity_for_rpm(
            *rpm,
            radius_mm * units::M_PER_MM,
        )));
        // rpm decimals as written
        prev = *rpm;
        i += 2;
    }
    if vs.is_empty() {
        return Err(err(
            "no spindle steps (S … M03 followed by G04) found".into()
        ));
    }
    if ev.get(i) != Some(&NcEvent::SpindleStop) {
        return Err(err(format!(
            "expected M05 after the last step, found {:?}",
            ev.get(i)
        )));
    }
    if !ev[i..].contains(&NcEvent::MCode(spec.trigger_off_mcode)) {
        return Err(err(format!(
            "no trigger-off M{} after the spindle stop",
            spec.trigger_off_mcode
        )));
    }
    let dwell = dwells.iter().sum::<f64>() / dwells.len() as f64;
    if dwells.iter().any(|d| (d - dwell).abs() > 2e-3) {
        return Err(err(format!(
            "plateau dwells differ between steps: {dwells:?}"
        )));
    }
    spec.dwell_s = (dwell * 1000.0).round() / 1000.0;
    Ok(vs)
}

/// Rebuild the plan from the programs of all pins (in any order). Velocities come from the
/// S words (so they carry the S rounding), dwell and ramps from the G04 words.
pub fn plan_spec_from_programs(programs: &[NcProgram]) -> Result<PlanSpec> {
    if programs.is_empty() {
        return Err(Error::invalid("NC programs", "no programs given"));
    }
    let mut by_pin: Vec<(u32, &NcProgram)> = programs
        .iter()
        .map(|p| Ok((p.param("PIN")? as u32, p)))
        .collect::<Result<_>>()?;
    by_pin.sort_by_key(|(pin, _)| *pin);
    let first = by_pin[0].1;
    let radius_mm = first.param("TRACK_RADIUS_MM")?;
    let accel = first.param("SPINDLE_ACCEL_RPM_PER_S")?;
    let mut spec = PlanSpec {
        track_radius_mm: Some(radius_mm),
        spindle_accel_rpm_per_s: accel,
        max_spindle_rpm: first.param("MAX_SPINDLE_RPM")?,
        trigger_on_mcode: first.param("TRIGGER_ON")? as u32,
        trigger_off_mcode: first.param("TRIGGER_OFF")? as u32,
        ..PlanSpec::default()
    };
    let mut forces = Vec::new();
    let mut velocities: Option<Vec<f64>> = None;
    for (k, (pin, prog)) in by_pin.iter().enumerate() {
        let err = |msg: String| Error::input(SourcePos::file(&prog.source), msg);
        if *pin != k as u32 + 1 {
            return Err(err(format!(
                "expected the program of pin {}, found pin {pin}",
                k + 1
            )));
        }
        forces.push(prog.param("NORMAL_FORCE_N")?);
        let vs = read_pin_events(prog, &mut spec, radius_mm, accel)?;
        match &velocities {
            None => velocities = Some(vs),
            Some(v0) => {
                if v0.len() != vs.len() || v0.iter().zip(&vs).any(|(a, b)| (a - b).abs() > 1e-9) {
                    return Err(err("velocity steps differ from pin 1: a plan has the same velocities on every pin".into()));
                }
            }
        }
    }
    let velocities = velocities.expect("at least one program");
    let count_error = |e: String| Error::invalid("NC programs", e);
    spec.normal_force_count =
        PinCount::of_usize(forces.len(), "normal forces").map_err(count_error)?;
    spec.velocity_count =
        VelocityCount::of_usize(velocities.len(), "velocity steps").map_err(count_error)?;
    spec.normal_forces_n = Some(forces);
    spec.velocities_m_per_min = Some(velocities);
    // S words already carry the rounding; keep enough decimals to reproduce them exactly.
    spec.rpm_decimals = 4;
    Ok(spec)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::PlanSpec;

    #[test]
    fn round_trip_rebuilds_the_plan() {
        let plan = PlanSpec {
            track_radius_mm: Some(100.0),
            ..Default::default()
        }
        .build()
        .unwrap();
        let programs: Vec<NcProgram> = (1..=plan.pins.len() as u32)
            .map(|p| parse_program(&write_program(&plan, p), &format!("pin{p}.nc")).unwrap())
            .collect();
        let spec = plan_spec_from_programs(&programs).unwrap();
        let back = spec.build().unwrap();
        assert_eq!(back.steps.len(), plan.steps.len());
        for (a, b) in plan.steps.iter().zip(&back.steps) {
            assert_eq!((a.pin, a.step), (b.pin, b.step));
            assert_eq!(a.normal_force_n, b.normal_force_n);
            assert_eq!(a.spindle_rpm, b.spindle_rpm, "S word round trip");
            // velocities carry the 0.01 rpm rounding of the S word: < 0.004 m/min on R = 100 mm
            assert!((a.sliding_velocity_m_s - b.sliding_velocity_m_s).abs() * 60.0 < 0.004);
            assert!((a.plateau_start_s - b.plateau_start_s).abs() < 5e-3);
            assert!((a.plateau_end_s - b.plateau_end_s).abs() < 5e-3);
        }
        assert_eq!(spec.trigger_on_mcode, 62);
        assert_eq!(spec.dwell_s, 0.5);
    }

    #[test]
    fn program_shape() {
        let plan = PlanSpec {
            track_radius_mm: Some(100.0),
            trigger_on_mcode: 70,
            trigger_off_mcode: 71,
            ..Default::default()
        }
        .build()
        .unwrap();
        let g = write_program(&plan, 1);
        assert!(g.contains("G97"));
        assert!(g.contains("N20 M70 (RECORDING TRIGGER ON)"));
        assert!(g.contains("M71 (RECORDING TRIGGER OFF)"));
        assert!(g.contains("S31.83 M03"));
        assert_eq!(g.matches(" M03").count(), 21);
        assert!(g.contains("(PLAN NORMAL_FORCE_N=150)"));
    }

    #[test]
    fn parser_errors_name_the_line() {
        let e = parse_program("%\nN10 G97 M05\nN20 G04 XABC\n%\n", "p.nc")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("p.nc, line 3") && e.contains("needs a number"),
            "{e}"
        );
        let e = parse_program("N10 G01 X5\n", "p.nc")
            .unwrap_err()
            .to_string();
        assert!(e.contains("unsupported G-code G1"), "{e}");
        let e = parse_program("N10 (open\n", "p.nc")
            .unwrap_err()
            .to_string();
        assert!(e.contains("unclosed comment"), "{e}");
    }
}
