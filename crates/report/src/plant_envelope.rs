//! The envelope of a plant control campaign: the regulated output of the controller under
//! test and of the baseline over the kept runs (index below `--envelope-runs`), min to
//! max, 5-95 % and the median per instant, with the set-point: `envelope.csv` and
//! `envelope.svg`. The kept runs are simulated again when the campaign finishes (each
//! run is deterministic in its drawn parameters), so resumed and sharded campaigns give
//! the same envelope without storing traces.

use crate::{Band, EnvelopePlot, Result, Series};
use rayon::prelude::*;
use rhonn::experiment::campaign::Envelope;
use rhonn::experiment::{run_plant_scenario, PlantColumn, PlantRunOutput, ScenarioSpec};

/// At most this many instants on the envelope's grid.
const POINTS: usize = 600;

/// What the envelope's files hold.
pub struct PlantEnvelope {
    /// `envelope.csv`.
    pub csv: Vec<u8>,
    /// `envelope.svg`.
    pub svg: String,
    /// Runs per band.
    pub runs: usize,
}

/// The envelope of the kept runs (each finished run's drawn values, in index order) of a
/// control scenario; None for other scenarios or when no kept run finished.
pub fn plant_envelope(spec: &ScenarioSpec, kept: &[Vec<f64>]) -> Result<Option<PlantEnvelope>> {
    let Some(control) = &spec.control else {
        return Ok(None);
    };
    let out = control.output.as_str();
    let (base, reference) = (format!("{out}_baseline"), format!("{out}_ref"));
    // The kept runs again, on every core (in index order: the same bytes whatever the
    // threads).
    let runs: Vec<PlantRunOutput> = kept
        .par_iter()
        .map(|values| run_plant_scenario(spec, Some(values)))
        .collect::<rhonn::Result<_>>()?;
    let mut traces: [Vec<Vec<f64>>; 2] = [Vec::new(), Vec::new()];
    let (mut t, mut setpoint, mut unit) = (Vec::new(), Vec::new(), String::new());
    for run in &runs {
        let find = |name: &str| run.trajectory.iter().find(|c| c.name == name);
        let shown = |c: &PlantColumn| {
            c.values
                .iter()
                .map(|v| c.quantity.to_display(*v))
                .collect::<Vec<f64>>()
        };
        if let (Some(y), Some(yb)) = (find(out), find(&base)) {
            if t.is_empty() {
                t = find("t").map(|c| c.values.clone()).unwrap_or_default();
                setpoint = find(&reference).map(shown).unwrap_or_default();
                unit = y.quantity.display_unit.to_string();
            }
            traces[0].push(shown(y));
            traces[1].push(shown(yb));
        }
    }
    if traces[0].is_empty() {
        return Ok(None);
    }
    let stride = t.len().div_ceil(POINTS).max(1);
    let pick = |v: &[f64]| v.iter().step_by(stride).copied().collect::<Vec<f64>>();
    let grid = pick(&t);
    let envelopes: Vec<Envelope> = traces
        .iter()
        .map(|ts| {
            let picked: Vec<Vec<f64>> = ts.iter().map(|v| pick(v)).collect();
            let refs: Vec<&[f64]> = picked.iter().map(Vec::as_slice).collect();
            Envelope::of(&refs, grid.len())
        })
        .collect();
    let sp = pick(&setpoint);
    let names = [out.to_string(), base.clone()];
    let csv = envelope_csv(&names, &reference, &unit, &grid, &envelopes, &sp)?;
    // The baseline first, so that the controller under test lies on top.
    let plot = EnvelopePlot {
        title: format!(
            "{}: {out} over {} runs, min-max and 5-95 %, median",
            spec.name,
            traces[0].len()
        ),
        y_label: format!("{out} [{unit}]"),
        t: grid,
        bands: vec![
            Band {
                label: format!("{out} (baseline)"),
                envelope: envelopes[1].clone(),
            },
            Band {
                label: format!("{out} (controller under test)"),
                envelope: envelopes[0].clone(),
            },
        ],
        lines: vec![Series::dashed("set-point", sp)],
    };
    Ok(Some(PlantEnvelope {
        csv,
        svg: plot.render(900, 450),
        runs: traces[0].len(),
    }))
}

/// `envelope.csv`: time, then per series its min, 5 %, median, 95 % and max, then the
/// set-point (display units).
fn envelope_csv(
    names: &[String; 2],
    reference: &str,
    unit: &str,
    grid: &[f64],
    envelopes: &[Envelope],
    sp: &[f64],
) -> Result<Vec<u8>> {
    let mut csv = Vec::new();
    {
        let mut w = csv::Writer::from_writer(&mut csv);
        let mut h = vec!["t".to_string()];
        for n in names {
            for q in ["min", "q05", "median", "q95", "max"] {
                h.push(format!("{n}_{q}_{unit}"));
            }
        }
        h.push(format!("{reference}_{unit}"));
        w.write_record(&h)?;
        for (k, tk) in grid.iter().enumerate() {
            let mut r = vec![tk.to_string()];
            for e in envelopes {
                for v in [&e.min, &e.q05, &e.median, &e.q95, &e.max] {
                    r.push(format!("{:.4}", v[k]));
                }
            }
            r.push(sp.get(k).map_or(String::new(), |v| v.to_string()));
            w.write_record(&r)?;
        }
        w.flush().map_err(csv::Error::from)?;
    }
    Ok(csv)
}
