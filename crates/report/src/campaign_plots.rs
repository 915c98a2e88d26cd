//! A campaign's plots: the envelope of the kept traces (traces.csv, envelope.csv,
//! envelope.svg) and the histograms of its figures.

use crate::Result;
use rhonn::experiment::campaign::Envelope;
use rhonn::experiment::campaign::PumpCampaign;

/// The envelope files of a campaign of `scenario` that kept traces: traces.csv (its
/// `header`, then the `traces` rows), envelope.csv and envelope.svg (None without
/// traces).
#[allow(clippy::type_complexity)]
pub(crate) fn envelope_files<'a>(
    spec: &PumpCampaign,
    scenario: &str,
    header: Vec<String>,
    traces: impl Iterator<Item = &'a Vec<String>>,
    grid: &[f64],
    env: &[(String, Envelope, usize)],
) -> Result<Option<(Vec<u8>, Vec<u8>, String)>> {
    if env.is_empty() {
        return Ok(None);
    }
    let mut traces_buf = Vec::new();
    let mut env_buf = Vec::new();
    let mut w = csv::Writer::from_writer(&mut traces_buf);
    w.write_record(header)?;
    for t in traces {
        w.write_record(t)?;
    }
    w.flush().map_err(csv::Error::from)?;
    drop(w);
    let p_ref = spec.setpoint_mpa(grid)?;
    let mut w = csv::Writer::from_writer(&mut env_buf);
    let mut h = vec!["t".to_string()];
    for (name, _, _) in env {
        for q in ["min", "q05", "median", "q95", "max"] {
            h.push(format!("{name}_{q}_mpa"));
        }
    }
    if p_ref.is_some() {
        h.push("p_ref_mpa".into());
    }
    w.write_record(&h)?;
    for (k, t) in grid.iter().enumerate() {
        let mut r = vec![t.to_string()];
        for (_, e, _) in env {
            for v in [&e.min, &e.q05, &e.median, &e.q95, &e.max] {
                r.push(format!("{:.4}", v[k]));
            }
        }
        if let Some(p) = &p_ref {
            r.push(p[k].to_string());
        }
        w.write_record(&r)?;
    }
    w.flush().map_err(csv::Error::from)?;
    drop(w);
    let label = |n: &str| match n {
        "p_line" if p_ref.is_some() && env.len() > 1 => "p_line (RHONN adaptive)".to_string(),
        "p_line_pi" => format!("p_line ({})", baseline_label(spec)),
        n => n.to_string(),
    };
    // The baseline first, so that the adaptive controller's band lies on top.
    let mut bands: Vec<crate::Band> = env
        .iter()
        .map(|(n, e, _)| crate::Band {
            label: label(n),
            envelope: e.clone(),
        })
        .collect();
    bands.reverse();
    let mut lines = Vec::new();
    if let Some(p) = &p_ref {
        lines.push(crate::Series {
            label: "set-point".into(),
            y: p.clone(),
            dashed: true,
        });
    }
    lines.push(crate::Series {
        label: "P_min".into(),
        y: vec![spec.p_min_mpa(); grid.len()],
        dashed: true,
    });
    let n_tr = env[0].2;
    let svg = crate::EnvelopePlot {
        title: format!("{}: line pressure over {n_tr} runs", scenario),
        y_label: "line pressure [MPa]".into(),
        t: grid.to_vec(),
        bands,
        lines,
    }
    .render(1200, 600);
    Ok(Some((traces_buf, env_buf, svg)))
}

/// How plots name an adaptive scenario's baseline.
fn baseline_label(spec: &PumpCampaign) -> &'static str {
    match spec.adaptive_baseline_kind() {
        Some("cascade-pi") => "cascade PI baseline",
        _ => "PI baseline",
    }
}

/// Whether `name` gets a histogram panel among a pump campaign's figures `names`: the
/// key figures (IAE, the largest settled deviation, the time below P_min, each of the
/// controller and of its baseline, and the fits) when there are any, else every figure.
pub(crate) fn shown(names: &[String], name: &str) -> bool {
    let key = |n: &str| {
        [
            "iae_mpa_s",
            "max_abs_deviation_settled_mpa",
            "time_below_p_min_after_1s_s",
            "baseline_iae_mpa_s",
            "baseline_max_abs_deviation_settled_mpa",
            "baseline_time_below_p_min_after_1s_s",
        ]
        .contains(&n)
            || n.ends_with("fit_percent")
    };
    !names.iter().any(|n| key(n)) || key(name)
}
