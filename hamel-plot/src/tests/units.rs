//! Axis labels carry the units a model states: its quantities' (`units(..)` in
//! `#[hamel_system]`) and its parameters' (their doc comments).

use super::super::*;
use super::texts;
use hamel::models::{MobileRobot, WhippleBicycle};
use hamel::{DormandPrince, HamelSystem, Simulation};

fn robot_run() -> hamel::Trajectory {
    let robot = MobileRobot::default();
    let x0 = robot
        .state_from_speeds(0.0, &[0.0, 0.0, 0.3, 0.0, 0.0], &[0.0, 0.5, 0.4])
        .unwrap();
    Simulation::new(&robot, x0)
        .end_time(0.5)
        .sample_interval(0.05)
        .run_constant(&DormandPrince::new(1e-8, 1e-10), [0.1, -0.1])
        .unwrap()
}

#[test]
fn trajectory_panels_label_their_axes_with_the_models_units() {
    let run = robot_run();
    let units = Units::of::<MobileRobot>();
    let labels = |panel: Panel| panel.units(&units).labels();
    let pair = |x: &str, y: &str| (x.to_string(), y.to_string());
    assert_eq!(
        labels(Panel::xy(&run, "x", "y").unwrap()),
        pair("x (m)", "y (m)")
    );
    assert_eq!(
        labels(Panel::time_series(&run, &["alpha"]).unwrap()),
        pair("t (s)", "alpha (rad)")
    );
    assert_eq!(
        labels(Panel::time_series(&run, &["phi1", "phi2"]).unwrap()),
        pair("t (s)", "phi1, phi2 (rad)")
    );
    assert_eq!(
        labels(Panel::time_series(&run, &["w3", "w4", "energy_balance"]).unwrap()),
        pair("t (s)", "w3 (rad/s), w4 (m/s), energy_balance (J)")
    );
    assert_eq!(
        labels(Panel::energy_drift(&run).unwrap()),
        pair("t (s)", "energy error (J)")
    );
    let robot = MobileRobot::default();
    assert_eq!(
        labels(Panel::constraint_residual(&robot, &run).unwrap()),
        pair("t (s)", "residual")
    );
    // Without units, or with a label of one's own, the label stays as it is.
    assert_eq!(Panel::xy(&run, "x", "y").unwrap().labels(), pair("x", "y"));
    let relabelled = Panel::xy(&run, "x", "y")
        .unwrap()
        .y_label("lateral")
        .units(&units);
    assert_eq!(relabelled.labels(), pair("x (m)", "lateral"));
    // Drawn: the SVG's labels have the units.
    let figure = Figure::from(Panel::time_series(&run, &["alpha"]).unwrap().units(&units));
    let svg = figure.to_svg().unwrap();
    assert!(texts(&svg).contains(&"alpha (rad)") && texts(&svg).contains(&"t (s)"));
}

#[test]
fn units_come_from_the_model_its_parameters_and_what_is_given() {
    let units = Units::of::<WhippleBicycle>();
    assert_eq!(units.unit("phi"), Some("rad"));
    assert_eq!(units.unit("t"), WhippleBicycle::unit("t"));
    assert_eq!(units.unit("c"), Some("m"), "the trail's doc comment");
    assert_eq!(units.unit("m_b"), Some("kg"));
    assert_eq!(units.unit("v"), None);
    let units = units.with("v", "m/s").with("c", "mm");
    assert_eq!(units.label("forward speed v", "v"), "forward speed v (m/s)");
    assert_eq!(units.unit("c"), Some("mm"), "given over the model's");
    let parameters = Units::of_parameters::<WhippleBicycle>();
    assert_eq!(
        (parameters.unit("c"), parameters.unit("phi")),
        (Some("m"), None)
    );
    assert_eq!(Units::new().label("x", "x"), "x");
}
