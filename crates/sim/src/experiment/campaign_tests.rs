use super::*;
use crate::experiment::{campaign_plan, nominal_plant_parameters, preset, ScenarioSpec};

fn spec() -> ScenarioSpec {
    preset::load_any("thesis-ch3").unwrap()
}

/// The indices (in the pump's parameter table) of the parameters a pump campaign draws,
/// in [`TOLERANCES`] order, and their nominal values.
fn drawn() -> (Vec<usize>, Vec<f64>) {
    let table = nominal_plant_parameters("pump").unwrap();
    TOLERANCES
        .iter()
        .map(|t| {
            let i = table.iter().position(|p| p.name == t.name).unwrap();
            (i, table[i].nominal)
        })
        .unzip()
}

#[test]
fn a_draw_depends_only_on_seed_and_index_and_stays_in_the_box() {
    let plan = campaign_plan(&spec()).unwrap();
    let (at, base) = drawn();
    assert_eq!(plan.varying(), at);
    for i in 0..200 {
        let a = draw(&plan, 7, i, Sampling::Random);
        assert_eq!(a, draw(&plan, 7, i, Sampling::Random));
        for ((&j, b), t) in at.iter().zip(&base).zip(&TOLERANCES) {
            assert!((a[j] / b - 1.0).abs() <= t.tolerance + 1e-12, "{} {b}", a[j]);
        }
    }
    assert_ne!(
        draw(&plan, 7, 0, Sampling::Random),
        draw(&plan, 8, 0, Sampling::Random)
    );
    assert_ne!(
        draw(&plan, 7, 0, Sampling::Random),
        draw(&plan, 7, 1, Sampling::Random)
    );
    let c = draw(&plan, 0, 0b10110, Sampling::Corners);
    let f = [0.8, 1.2, 1.2, 0.9, 1.1];
    for (k, &j) in at.iter().enumerate() {
        assert!((c[j] / base[k] - f[k]).abs() < 1e-12);
    }
    assert_eq!(plan.corner_runs(), 32);
}

#[test]
fn overrides_change_one_parameter_and_leave_the_others_draws() {
    let mut s = spec();
    let plan0 = campaign_plan(&s).unwrap();
    s.campaign = Some(
        toml::from_str(
            r#"
            beta_mpa = { min = 1000.0, max = 1100.0 }
            mu_1 = { distribution = "normal", std_relative = 0.05 }
            q_0_dm3_s = { distribution = "fixed" }
            "#,
        )
        .unwrap(),
    );
    let plan = campaign_plan(&s).unwrap();
    assert_eq!(plan.corner_runs(), 16);
    let (at, base) = drawn();
    let mut mu = Vec::new();
    for i in 0..2000 {
        let a = draw(&plan, 3, i, Sampling::Random);
        let a0 = draw(&plan0, 3, i, Sampling::Random);
        assert!((1000.0..=1100.0).contains(&a[at[0]]));
        assert!((a[at[1]] / base[1] - 1.0).abs() <= 0.2 + 1e-12);
        assert_eq!(a[at[3]], base[3]);
        // Untouched parameters draw exactly as without the overrides.
        assert_eq!((a[at[2]], a[at[4]]), (a0[at[2]], a0[at[4]]));
        mu.push(a[at[1]] / base[1] - 1.0);
    }
    let m = mu.iter().sum::<f64>() / mu.len() as f64;
    let sd = (mu.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / mu.len() as f64).sqrt();
    assert!(m.abs() < 0.005 && (sd - 0.05).abs() < 0.004, "mean {m}, std {sd}");
    // Corners: the fixed parameter stays, the others take both ends.
    let c = draw(&plan, 0, 0b1111, Sampling::Corners);
    assert_eq!((c[at[0]], c[at[3]]), (1100.0, base[3]));
    let c = draw(&plan, 0, 0, Sampling::Corners);
    assert_eq!(c[at[0]], 1000.0);
}

#[test]
fn bad_overrides_name_the_field_and_a_run_checks_them() {
    let cases = [
        ("beta_mpa = { relative = 1.5 }", "campaign.beta_mpa.relative"),
        ("mu_1 = { min = 1e-5 }", "campaign.mu_1.max"),
        ("mu_2 = { min = 2.0, max = 1.0 }", "campaign.mu_2.max"),
        (
            "q_0_dm3_s = { distribution = \"fixed\", relative = 0.1 }",
            "campaign.q_0_dm3_s.distribution",
        ),
        (
            "beta_mpa = { distribution = \"normal\", min = 1.0, max = 2.0 }",
            "campaign.beta_mpa.min",
        ),
        (
            "beta_mpa = { std_relative = 0.1 }",
            "campaign.beta_mpa.std_relative",
        ),
        (
            "beta_mpa = { relative = 0.1, min = 1.0, max = 2.0 }",
            "campaign.beta_mpa.relative",
        ),
    ];
    for (text, field) in cases {
        let mut s = spec();
        s.campaign = Some(toml::from_str(text).unwrap());
        let e = campaign_plan(&s).unwrap_err().to_string();
        assert!(e.contains(field), "{text}: {e}");
        // A run checks its `[campaign]` too (before anything runs).
        let e = s.run_summary().unwrap_err().to_string();
        assert!(e.contains(field), "{text}: {e}");
    }
    // A key that is no parameter names the pump's.
    let mut s = spec();
    s.campaign = Some(toml::from_str("beta = { relative = 0.1 }").unwrap());
    let e = campaign_plan(&s).unwrap_err().to_string();
    assert!(
        e.contains("campaign.beta") && e.contains("beta_mpa, mu_1, mu_2, q_0_dm3_s, qdot_max_dm3_s2"),
        "{e}"
    );
}

#[test]
fn envelope_quantiles_per_point() {
    let a = [0.0, 10.0];
    let b = [1.0, 20.0];
    let c = [2.0, 30.0];
    let e = Envelope::of(&[&a, &b, &c], 2);
    assert_eq!(
        (e.min.clone(), e.median.clone(), e.max.clone()),
        (vec![0.0, 10.0], vec![1.0, 20.0], vec![2.0, 30.0])
    );
    assert!((e.q05[1] - 11.0).abs() < 1e-12 && (e.q95[0] - 1.9).abs() < 1e-12);
}

#[test]
fn quantiles_as_numpy() {
    // numpy.quantile([0, 1, 2, 3, 4], [0.05, 0.5, 0.95]) = [0.2, 2.0, 3.8]; the
    // non-finite values (a failed run's) are left out.
    let s = figure_stats("x", vec![3.0, f64::NAN, 0.0, 4.0, 1.0, 2.0, f64::INFINITY]);
    assert!((s.q05 - 0.2).abs() < 1e-12 && s.median == 2.0 && (s.q95 - 3.8).abs() < 1e-12);
    assert_eq!((s.min, s.max, s.mean), (0.0, 4.0, 2.0));
}
