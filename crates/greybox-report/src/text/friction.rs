//! Plain text of the friction stages after identification: the ploughing correction, the
//! fit of the model families and a model's predictions.

use super::table::Table;
use greybox_contact::ploughing::Correction;
use greybox_learn::protocol::FitReport;
use greybox_model::modelfile::ModelFile;
use greybox_pipeline::fit::FitOutputs;
use greybox_pipeline::predict::PredictedPoint;
use std::fmt::Write as _;

/// The ploughing correction per load.
pub fn correction(c: &Correction) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "ploughing correction ({}), pin radius {} mm",
        c.method, c.pin_tip_radius_mm
    );
    let _ = writeln!(
        text,
        "  w(F) = {:.2} um * F^{:.4}",
        c.width_law.a_um, c.width_law.b
    );
    let mut t = Table::new(&["F_N [N]", "track width [um]", "depth [um]", "mu_plough"]);
    for l in &c.per_load {
        t.row(vec![
            format!("{:.1}", l.normal_force_n),
            format!("{:.0}", l.width_um),
            format!("{:.2}", l.depth_um),
            format!("{:.4}", l.mu_plough),
        ]);
    }
    let _ = write!(text, "{}", t.render());
    let _ = writeln!(
        text,
        "  mean reduction of the COF: {:.2} % (article: 7.29 % at its highest loads)",
        c.mean_reduction_percent
    );
    text
}

/// Predictions with their intervals, one row per point.
pub fn predictions(m: &ModelFile, rows: &[PredictedPoint]) -> String {
    let mut text = String::new();
    let names: Vec<String> = m.features.iter().map(|f| f.name.clone()).collect();
    let mut head: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
    let target = format!("{} ({})", m.target.name, m.family.name());
    let low = format!("{:.0} % low", m.prediction_interval.coverage * 100.0);
    let high = format!("{:.0} % high", m.prediction_interval.coverage * 100.0);
    head.extend([target.as_str(), low.as_str(), high.as_str(), "in domain"]);
    let mut t = Table::new(&head);
    for r in rows {
        let mut cells: Vec<String> = r.features.iter().map(|v| format!("{v}")).collect();
        cells.push(format!("{:.5}", r.prediction.value));
        cells.push(format!("{:.5}", r.prediction.low));
        cells.push(format!("{:.5}", r.prediction.high));
        cells.push(r.prediction.in_domain.to_string());
        t.row(cells);
    }
    let _ = write!(text, "{}", t.render());
    text
}

/// The fit report (markdown tables), time per family and the files written.
pub fn fit(report: &FitReport, outputs: &FitOutputs) -> String {
    let mut text = String::new();
    let _ = writeln!(text, "{}", greybox_learn::protocol::markdown(report));
    for f in &report.families {
        let _ = writeln!(text, "{}: {:.1} s", f.family.name(), f.seconds);
    }
    let _ = writeln!(
        text,
        "wrote {}, {}, {} models, {} plots",
        outputs.report_json,
        outputs.report_md,
        outputs.models.len(),
        outputs.plots.len()
    );
    text
}
