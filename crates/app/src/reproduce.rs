//! `rhonn reproduce`: the main job. Runs [`REPRODUCED`] into a folder each and leads with
//! what they reproduced, one line per scenario, each figure beside what it means (an
//! expected failure, such as the thesis's identifier not running free, said as such).

use super::run::{run_scenario_into_dir, REPRODUCED};
use super::Outcome;
use rhonn::experiment::PlantRunOutput;
use rhonn::metrics::sig;
use rhonn_report::Result;
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
        lead.lines.push(format!("  {name}: {}", headline(name, &run)));
        each.push(o);
    }
    Ok(std::iter::once(lead).chain(each).collect())
}

/// When the online pressure estimate's error falls for good within 1 % of its initial
/// value, before the pressure's first transient (taken as 1 s): the thesis's chapter 5
/// convergence figure (about 0.08 s there). None without the columns or the crossing.
fn pressure_convergence_s(run: &PlantRunOutput) -> Option<f64> {
    let col = |name: &str| run.trajectory.iter().find(|c| c.name == name).map(|c| &c.values);
    let (t, p, ph) = (col("t")?, col("p_line")?, col("p_line_hat")?);
    let band = 0.01 * (ph.first()? - p.first()?).abs();
    let end = t.iter().position(|&v| v >= 1.0)?;
    let last_out = (0..end).rev().find(|&k| (ph[k] - p[k]).abs() > band)?;
    t.get(last_out + 1).copied()
}

/// What scenario `name` of the main job shows, in one line.
fn headline(name: &str, run: &PlantRunOutput) -> String {
    let s = &run.summary;
    let range = |state: &str| s.open_loop.iter().flatten().find(|r| r.state == state);
    match (name, &s.identification, &s.control) {
        ("thesis-ch3", _, _) => format!(
            "the open-loop pump of the thesis's chapter 3: the stroke rises to {} mm, the line pressure is held at P_max ({} MPa) while it is large and is below P_min for {} s",
            sig(range("stroke").map_or(f64::NAN, |r| r.max_value), 4),
            sig(range("p_line").map_or(f64::NAN, |r| r.max_value), 3),
            sig(s.floor.as_ref().map_or(f64::NAN, |f| f.time_below_s), 3)
        ),
        (_, Some(id), _) => {
            let fits = |free: bool| {
                id.iter()
                    .map(|f| {
                        let w = &f.whole_run;
                        let r = if free { w.free_run.as_ref() } else { Some(&w.training) };
                        format!("{} % ({})", sig(r.map_or(f64::NAN, |r| r.fit_percent), 3), f.state)
                    })
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let converged = pressure_convergence_s(run).map_or(String::new(), |t| {
                format!(
                    "; its pressure error is within 1 % of its initial value from {} s (the thesis, figure 5.5: about 0.08 s)",
                    sig(t, 2)
                )
            });
            format!(
                "the thesis's online identifier (chapter 5) fits {} while it learns{converged}; run free with its weights frozen it fits {}, as expected of it: it tracks while it adapts, and its frozen weights describe little more than the last operating point",
                fits(false),
                fits(true)
            )
        }
        (_, _, Some(c)) if c.len() >= 2 => {
            let (a, b) = (&c[0], &c[1]);
            let (iae2, tv2) = c.get(2).map_or((String::new(), String::new()), |s| {
                (
                    format!(" and {} for its nominal-optimal tuning", sig(s.iae, 3)),
                    format!(" and {}", sig(s.input_total_variation, 3)),
                )
            });
            format!(
                "RHONN adaptive control beside the cascade PI on identical plants: IAE {} MPa s against {} for the PI's robust tuning{iae2}, the current moving {} A in all against {}{tv2} A",
                sig(a.iae, 3),
                sig(b.iae, 3),
                sig(a.input_total_variation, 3),
                sig(b.input_total_variation, 3),
            )
        }
        (_, _, Some(c)) if !c.is_empty() => format!(
            "the PI baseline holds its set-point under the demand: ISE {} MPa^2 s, IAE {} MPa s, the current saturated {} s",
            sig(c[0].ise, 3),
            sig(c[0].iae, 3),
            sig(c[0].time_input_saturated_s, 3)
        ),
        _ => format!("{} s simulated", sig(run.duration_s, 3)),
    }
}
