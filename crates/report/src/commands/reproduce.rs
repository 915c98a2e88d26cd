//! `rhonn reproduce`: the main job. Runs [`REPRODUCED`] into a folder each and leads with
//! what they reproduced, one line per scenario, each figure beside what it means (an
//! expected failure, such as the thesis's identifier not running free, said as such).

use super::run::{run_scenario_into_dir, REPRODUCED};
use super::Outcome;
use crate::Result;
use rhonn::experiment::{RunOutput, ScenarioRun, Trace};
use rhonn::metrics::sig;
use std::path::Path;

/// Run the main job's scenarios into `root/<name>`: the lead (what was reproduced), then
/// each scenario's own outcome.
pub fn reproduce(root: &Path) -> Result<Vec<Outcome>> {
    let mut lead = Outcome::default();
    lead.lines.push(format!(
        "reproduced (each folder in {} holds its report.html):",
        root.display()
    ));
    let mut each = Vec::new();
    for name in REPRODUCED {
        let (run, o) = run_scenario_into_dir(name, &root.join(name))?;
        if let ScenarioRun::Pump { output, trace, .. } = &run {
            lead.lines
                .push(format!("  {name}: {}", headline(name, output, trace)));
        }
        each.push(o);
    }
    Ok(std::iter::once(lead).chain(each).collect())
}

/// When the online pressure estimate's error falls for good within 1 % of its initial
/// value, before the pressure's first transient (taken as 1 s): the thesis's chapter 5
/// convergence figure (about 0.08 s there). None without the columns or the crossing.
fn pressure_convergence_s(trace: &Trace) -> Option<f64> {
    let (t, p, ph) = (
        trace.column("t")?,
        trace.column("p_line")?,
        trace.column("p_line_hat")?,
    );
    let band = 0.01 * (ph.first()? - p.first()?).abs();
    let end = t.iter().position(|&v| v >= 1.0)?;
    let last_out = (0..end).rev().find(|&k| (ph[k] - p[k]).abs() > band)?;
    t.get(last_out + 1).copied()
}

/// What scenario `name` of the main job shows, in one line.
fn headline(name: &str, out: &RunOutput, trace: &Trace) -> String {
    let f = &out.summary.figures;
    match (name, &out.summary.identification, &out.summary.control) {
        ("thesis-ch3", _, _) => format!(
            "the open-loop pump of the thesis's chapter 3: the stroke rises to {} mm, the line pressure is held at P_max ({} MPa) while it is large and is below P_min for {} s",
            sig(f.stroke_max_mm, 4),
            sig(f.p_line_max_mpa, 3),
            sig(f.time_below_p_min_s, 3)
        ),
        (_, Some(id), _) => {
            let fits = |figs: &[rhonn::experiment::StateFigures]| {
                figs.iter()
                    .map(|s| format!("{} % ({})", sig(s.fit_percent, 3), s.state))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let converged = pressure_convergence_s(trace).map_or(String::new(), |t| {
                format!(
                    "; its pressure error is within 1 % of its initial value from {} s (the thesis, figure 5.5: about 0.08 s)",
                    sig(t, 2)
                )
            });
            format!(
                "the thesis's online identifier (chapter 5) fits {} while it learns{converged}; run free with its weights frozen it fits {}, as expected of it: it tracks while it adapts, and its frozen weights describe little more than the last operating point",
                fits(&id.training),
                fits(&id.parallel)
            )
        }
        (_, _, Some(c)) => match (&f.regulation, &c.baseline.figures.regulation) {
            (Some(a), Some(b)) => {
                let second = c.second_baseline.as_ref().and_then(|s| s.figures.regulation.as_ref());
                let (iae2, tv2) = second.map_or((String::new(), String::new()), |s| {
                    (
                        format!(" and {} for its nominal-optimal tuning", sig(s.iae_mpa_s, 3)),
                        format!(" and {}", sig(s.current_total_variation_a, 3)),
                    )
                });
                format!(
                    "RHONN adaptive control beside the cascade PI on identical plants: IAE {} MPa s against {} for the PI's robust tuning{iae2}, the current moving {} A in all against {}{tv2} A",
                    sig(a.iae_mpa_s, 3),
                    sig(b.iae_mpa_s, 3),
                    sig(a.current_total_variation_a, 3),
                    sig(b.current_total_variation_a, 3),
                )
            }
            _ => format!("{} s simulated", sig(f.duration_s, 3)),
        },
        _ => match &f.regulation {
            Some(r) => format!(
                "the PI baseline holds its set-point under the demand: ISE {} MPa^2 s, IAE {} MPa s, the current saturated {} s",
                sig(r.ise_mpa2_s, 3),
                sig(r.iae_mpa_s, 3),
                sig(r.time_current_saturated_s, 3)
            ),
            None => format!("{} s simulated", sig(f.duration_s, 3)),
        },
    }
}
