//! A plant scenario with neither `[identifier]` nor `[control]`: the plant driven by its
//! inputs alone, its states sampled, and a summary of where each went.

use crate::shipped;
use rhonn::experiment::{run_plant_scenario, PlantRunOutput, ScenarioSpec};

fn run(text: &str) -> rhonn::Result<PlantRunOutput> {
    run_plant_scenario(&ScenarioSpec::from_toml(text, "open.toml")?, None)
}

fn column<'a>(out: &'a PlantRunOutput, name: &str) -> &'a [f64] {
    &out.trajectory.iter().find(|c| c.name == name).unwrap().values
}

/// The identification scenario without its identifier: the same plant under the same
/// input, so its levels are those the identification recorded (each run's solver steps
/// its own way, so to its tolerance, not to the bit).
#[test]
fn the_tanks_driven_by_their_input_alone_are_the_identification_s_plant() {
    let ident = shipped("tanks-identify");
    let cut = ident.find("[identifier]").unwrap();
    let open = run(&ident[..cut]).unwrap();
    let with = run(&ident).unwrap();
    let names: Vec<&str> = open.trajectory.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["t", "voltage", "h1", "h2"]);
    assert_eq!(column(&open, "t"), column(&with, "t"));
    assert_eq!(column(&open, "voltage"), column(&with, "voltage"));
    for h in ["h1", "h2"] {
        let worst = column(&open, h)
            .iter()
            .zip(column(&with, h))
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-6, "{h}: {worst} m apart");
    }
    // The summary: where each state went, in mm, and as a campaign's figures.
    let ranges = open.summary.open_loop.clone().unwrap();
    let h2 = column(&open, "h2");
    assert_eq!(ranges[1].state, "h2");
    assert_eq!(ranges[1].final_value, 1e3 * h2[h2.len() - 1]);
    assert_eq!(
        ranges[1].max_value,
        1e3 * h2.iter().copied().fold(f64::MIN, f64::max)
    );
    assert!(ranges
        .iter()
        .all(|r| r.min_value <= r.initial && r.initial <= r.max_value && r.unit == "mm"));
    let figures: Vec<String> = open.summary.figures().into_iter().map(|(n, _)| n).collect();
    assert_eq!(
        figures,
        ["h1_final", "h1_min", "h1_max", "h2_final", "h2_min", "h2_max"]
    );
    assert!(
        open.summary.findings[0].starts_with("h1: from 100 to "),
        "{:?}",
        open.summary.findings
    );
    assert!(open.summary.identification.is_none() && open.summary.control.is_none());
}

#[test]
fn a_held_input_settles_the_tanks_and_sections_of_other_experiments_are_refused() {
    let base = "name = \"held\"\nduration_s = 20000.0\noutput_interval_s = 10.0\n\
                [plant]\nkind = \"tanks\"\n[input]\nvoltage = { kind = \"constant\", value = 5.0 }\n";
    let out = run(base).unwrap();
    let h2 = column(&out, "h2");
    let n = h2.len();
    assert_eq!(n, 2001);
    // Settled: the last samples agree to a micrometre, far from where they started.
    assert!(
        (h2[n - 1] - h2[n - 2]).abs() < 1e-6 && h2[n - 1] > 0.05,
        "{}",
        h2[n - 1]
    );
    for (tail, want) in [
        (
            "[validation]\nduration_s = 10.0\ninput = {}\n",
            "only with an [identifier]",
        ),
        (
            "[measurement]\nnoise_std = { h2 = 1.0 }\n",
            "only with a [control] section",
        ),
    ] {
        let e = run(&format!("{base}{tail}")).unwrap_err().to_string();
        assert!(e.contains(want), "{e}");
    }
}

/// `[identifier] epochs` on a plant other than the pump (it was read and ignored): each
/// epoch runs the record again from the last epoch's weights (the law's own state, such
/// as a least-squares gain, starts afresh, as on the pump), so a second epoch learns on
/// from where the first ended; `epochs = 1` is the run without the key; and
/// `validate = false` beside a `[validation]` section is refused, not ignored.
#[test]
fn an_identifier_s_epochs_and_validate_are_done_not_ignored() {
    let text = shipped("tanks-identify");
    let with = |key: &str| {
        let t = text.replace("law = {", &format!("{key}\nlaw = {{"));
        run(&t)
    };
    let one = run(&text).unwrap();
    assert_eq!(with("epochs = 1").unwrap(), one);
    let two = with("epochs = 2").unwrap();
    let f = |o: &PlantRunOutput, k: usize| o.summary.identification.clone().unwrap()[k].clone();
    for k in 0..2 {
        // The second epoch's training fit (its second half) is at least the first's, and
        // its weights moved on from the first epoch's end.
        assert!(
            f(&two, k).training_fit_percent >= f(&one, k).training_fit_percent - 0.5,
            "{:?} against {:?}",
            f(&two, k),
            f(&one, k)
        );
        assert_ne!(f(&two, k).final_weight_norm, f(&one, k).final_weight_norm);
    }
    let e = with("validate = false").unwrap_err().to_string();
    assert!(
        e.contains("`validation`") && e.contains("identifier.validate = false"),
        "{e}"
    );
}

/// `validate = true` (the default) without a `[validation]` section on a plant other than
/// the pump (it was read and ignored there): the frozen model runs again on the training
/// inputs, its series-parallel estimate and its free run in one integration, as the pump's
/// runner validates thesis-ch5: validation.csv's columns are the pump's names, the summary
/// has both figures per state, and `validate = false` leaves the validation out.
#[test]
fn without_a_validation_section_the_frozen_model_runs_again_on_the_training_inputs() {
    let text = shipped("tanks-identify");
    let text = &text[..text.find("[validation]").unwrap()];
    let text = text.replace("duration_s = 6000.0", "duration_s = 3000.0");
    let out = run(&text).unwrap();
    let v = out
        .validation
        .as_ref()
        .expect("a validation on the training inputs");
    let names: Vec<&str> = v.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "t",
            "voltage",
            "h1",
            "h1_hat_series_parallel",
            "h1_hat_parallel",
            "h2",
            "h2_hat_series_parallel",
            "h2_hat_parallel"
        ]
    );
    // The same inputs and plant: the measured levels are the training run's (each run
    // steps its own way: to the solver's tolerance).
    let (h_train, h_again) = (column(&out, "h2"), &v[5].values);
    assert_eq!(h_train.len(), h_again.len());
    let worst = h_train
        .iter()
        .zip(h_again)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-5, "{worst} m");
    for s in out.summary.identification.as_ref().unwrap() {
        let (sp, free) = (
            s.series_parallel_fit_percent.unwrap(),
            s.validation_fit_percent.unwrap(),
        );
        // On the measured levels the frozen model tracks; running free it drifts more.
        assert!(sp > 90.0 && sp >= free, "{s:?}");
        assert!(
            s.series_parallel_rms_error.unwrap() <= s.validation_rms_error.unwrap(),
            "{s:?}"
        );
    }
    assert!(
        out.summary.findings[0].contains("series-parallel"),
        "{:?}",
        out.summary.findings
    );
    let off = run(&text.replace("law = {", "validate = false\nlaw = {")).unwrap();
    assert!(off.validation.is_none());
    assert!(off.summary.identification.unwrap()[0]
        .series_parallel_fit_percent
        .is_none());
}
