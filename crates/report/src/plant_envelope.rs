//! The envelope of a plant campaign: over the kept runs (index below `--envelope-runs`),
//! min to max, 5-95 % and the median per instant of the regulated output of the
//! controller under test and of its baseline, with the set-point (a control scenario), or
//! of the plant's first measured state (others: the pump's pressure): `envelope.csv` and
//! `envelope.svg`. Each kept run's series, on a grid of at most 600 of its output samples
//! in display units to 4 decimals, are rows of `traces.csv` (appended to
//! `traces.partial.csv` as the run finishes): the envelope is computed from those strings,
//! so a fresh, a resumed and a merged campaign give the same bytes.

use crate::{Band, EnvelopePlot, Result, Series};
use rhonn::experiment::campaign::Envelope;
use rhonn::experiment::{PlantColumn, PlantRunOutput, ScenarioSpec};

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
    /// The series, as `envelope.csv` names them.
    pub series: Vec<String>,
}

/// What a campaign's envelope draws, read from its nominal run: the series (the columns of
/// `trajectory.csv`), the grid, the set-point and the unit.
pub struct EnvelopeSeries {
    scenario: String,
    out: String,
    names: Vec<String>,
    reference: Option<String>,
    stride: usize,
    grid: Vec<f64>,
    setpoint: Vec<f64>,
    unit: String,
}

/// A column's values in display units.
fn shown(c: &PlantColumn) -> Vec<f64> {
    c.values.iter().map(|v| c.quantity.to_display(*v)).collect()
}

impl EnvelopeSeries {
    /// The series of `spec`'s envelope, as its `nominal` run wrote them (a series the run
    /// did not write, such as a loop's missing baseline, is left out); None when it wrote
    /// none.
    pub fn of(spec: &ScenarioSpec, nominal: &PlantRunOutput) -> Result<Option<Self>> {
        let (out, names, reference) = match &spec.control {
            Some(control) => {
                let out = control.output.clone();
                let names = vec![out.clone(), format!("{out}_baseline")];
                (out.clone(), names, Some(format!("{out}_ref")))
            }
            None => {
                let first = rhonn::experiment::plant_measured_names(&spec.plant.kind)?[0].to_string();
                (first.clone(), vec![first], None)
            }
        };
        let find = |name: &str| nominal.trajectory.iter().find(|c| c.name == name);
        let (Some(t), Some(y)) = (find("t"), find(&out)) else {
            return Ok(None);
        };
        let stride = t.values.len().div_ceil(POINTS).max(1);
        let pick = |v: &[f64]| v.iter().step_by(stride).copied().collect::<Vec<f64>>();
        Ok(Some(EnvelopeSeries {
            scenario: spec.name.clone(),
            names: names.into_iter().filter(|n| find(n).is_some()).collect(),
            setpoint: reference
                .as_deref()
                .and_then(find)
                .map_or(Vec::new(), |c| pick(&shown(c))),
            reference,
            stride,
            grid: pick(&t.values),
            unit: y.quantity.display_unit.to_string(),
            out,
        }))
    }

    /// `traces.csv`'s header: the run, the series, then the grid's times \[s\].
    pub fn header(&self) -> Vec<String> {
        let mut h = vec!["run".to_string(), "series".to_string()];
        h.extend(self.grid.iter().map(|t| t.to_string()));
        h
    }

    /// Run `index`'s rows of `traces.csv`: each series on the grid, display units to 4
    /// decimals.
    pub fn rows(&self, index: u64, run: &PlantRunOutput) -> Vec<Vec<String>> {
        let mut out = Vec::new();
        for name in &self.names {
            if let Some(c) = run.trajectory.iter().find(|c| &c.name == name) {
                let mut r = vec![index.to_string(), name.clone()];
                let q = &c.quantity;
                r.extend(
                    c.values
                        .iter()
                        .step_by(self.stride)
                        .map(|v| format!("{:.4}", q.to_display(*v))),
                );
                out.push(r);
            }
        }
        out
    }

    /// The envelope of the `traces` rows (in run order); None without any.
    pub fn envelope<'a>(
        &self,
        traces: impl Iterator<Item = &'a Vec<String>>,
    ) -> Result<Option<PlantEnvelope>> {
        let mut per: Vec<Vec<Vec<f64>>> = vec![Vec::new(); self.names.len()];
        for row in traces {
            if let Some(k) = self.names.iter().position(|n| Some(n) == row.get(1)) {
                per[k].push(row[2..].iter().map(|x| x.parse().unwrap_or(f64::NAN)).collect());
            }
        }
        if per.iter().all(Vec::is_empty) {
            return Ok(None);
        }
        let n = self.grid.len();
        let envelopes: Vec<Envelope> = per
            .iter()
            .map(|ts| Envelope::of(&ts.iter().map(Vec::as_slice).collect::<Vec<_>>(), n))
            .collect();
        let (out, unit, sp) = (&self.out, &self.unit, &self.setpoint);
        let csv = envelope_csv(
            &self.names,
            self.reference.as_deref(),
            unit,
            &self.grid,
            &envelopes,
            sp,
        )?;
        // The baseline first, so that the controller under test lies on top.
        let bands = match self.reference {
            Some(_) => envelopes
                .iter()
                .zip(["controller under test", "baseline"])
                .rev()
                .map(|(e, role)| Band {
                    label: format!("{out} ({role})"),
                    envelope: e.clone(),
                })
                .collect(),
            None => vec![Band {
                label: out.clone(),
                envelope: envelopes[0].clone(),
            }],
        };
        let runs = per[0].len();
        let plot = EnvelopePlot {
            title: format!(
                "{}: {out} over {runs} runs, min-max and 5-95 %, median",
                self.scenario
            ),
            y_label: format!("{out} [{unit}]"),
            t: self.grid.clone(),
            bands,
            lines: if sp.is_empty() {
                Vec::new()
            } else {
                vec![Series::dashed("set-point", sp.clone())]
            },
        };
        Ok(Some(PlantEnvelope {
            csv,
            svg: plot.render(900, 450),
            runs,
            series: self.names.clone(),
        }))
    }
}

/// `envelope.csv`: time, then per series its min, 5 %, median, 95 % and max, then the
/// set-point when there is one (display units).
fn envelope_csv(
    names: &[String],
    reference: Option<&str>,
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
                h.push(format!("{n}_{q}_{}", unit.to_lowercase()));
            }
        }
        if let Some(reference) = reference {
            h.push(format!("{reference}_{}", unit.to_lowercase()));
        }
        w.write_record(&h)?;
        for (k, tk) in grid.iter().enumerate() {
            let mut r = vec![tk.to_string()];
            for e in envelopes {
                for v in [&e.min, &e.q05, &e.median, &e.q95, &e.max] {
                    r.push(format!("{:.4}", v[k]));
                }
            }
            if reference.is_some() {
                r.push(sp.get(k).map_or(String::new(), |v| v.to_string()));
            }
            w.write_record(&r)?;
        }
        w.flush().map_err(csv::Error::from)?;
    }
    Ok(csv)
}
