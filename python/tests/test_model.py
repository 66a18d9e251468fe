"""The model class: parameters, names and units, states, runs with every integrator and every
form of inputs and events, linearization and LQR, scenes."""

import math

import numpy as np
import pytest

import hamel
from hamel.models import ChaplyginSleigh, MobileRobot, WhippleBicycle


def test_parameters_are_keywords_with_the_models_defaults():
    robot = MobileRobot(m0=12.0)
    assert robot.parameters["m0"] == 12.0
    assert robot.parameters["mw"] == MobileRobot.defaults()["mw"] == 1.0
    assert robot.parameters.units["r"] == "m"
    assert robot.parameters.units["m0"] == "kg"
    assert list(robot.parameters) == ["m0", "mw", "jx", "jy", "jz", "r", "b", "l", "g"]
    assert robot.with_parameters(m0=5.0).parameters["m0"] == 5.0
    assert robot.parameters["m0"] == 12.0


def test_names_and_units():
    robot = MobileRobot()
    assert robot.coordinates == ("x", "y", "alpha", "phi1", "phi2")
    assert robot.speeds == ("w3", "w4", "w5")
    assert robot.inputs == ("tau1", "tau2")
    assert robot.state_names == robot.coordinates + robot.speeds
    assert robot.coordinates.units["x"] == "m"
    assert robot.inputs.units["tau1"] == "N m"


def test_a_state_by_name_solves_the_holonomic_constraint():
    bicycle = WhippleBicycle()
    x = bicycle.state(rear_wheel_rate=-3.0 / bicycle.parameters["r_r"], phi=0.05, delta=0.1)
    theta = bicycle.state_names.index("theta")
    # The pitch follows from the lean and steer through the front wheel's contact.
    assert bicycle._description["dependent"] == ["theta"]
    assert -1e-3 < x[theta] < -1e-4
    run = bicycle.simulate(x, t_end=0.2, dt=0.1)
    assert run.summary.max_holonomic_residual < 1e-8


def test_state_from_velocities():
    sleigh = ChaplyginSleigh()
    a = sleigh.parameters["a"]
    # Straight ahead along x at 1 m/s turning at 0.5 rad/s: the blade's row is
    # -ẋ sinθ + ẏ cosθ − a θ̇ = 0 at θ = 0, so ẏ = a θ̇.
    x = sleigh.state(velocities={"x": 1.0, "y": a * 0.5, "theta": 0.5})
    assert x[sleigh.state_names.index("v")] == pytest.approx(1.0)
    assert x[sleigh.state_names.index("omega")] == pytest.approx(0.5)


@pytest.mark.parametrize("method", ["dopri5", "radau5", "rodas5p", "rodas4", "rk4", "midpoint",
                                    "gauss2", "gauss3"])
def test_every_integrator_by_name(method):
    robot = MobileRobot()
    x0 = robot.state(alpha=0.3, w4=0.5, w5=0.4)
    # Steps that give each method's order an error below 1e-6 (the midpoint rule's is 2).
    steps = {"rk4": 0.002, "midpoint": 0.0002, "gauss2": 0.002, "gauss3": 0.002}
    settings = {"step": steps[method]} if method in steps else {"rtol": 1e-10, "atol": 1e-12}
    run = robot.simulate(x0, t_end=1.0, dt=0.1, method=method, **settings)
    reference = robot.simulate(x0, t_end=1.0, dt=0.1, rtol=1e-12, atol=1e-14)
    assert np.max(np.abs(run["x"] - reference["x"])) < 1e-6
    assert run.summary.steps > 0


def test_inputs_as_constants_functions_and_samples_agree():
    robot = MobileRobot()
    x0 = robot.state(alpha=0.3, w4=0.5)
    by_name = robot.simulate(x0, t_end=2.0, inputs={"tau1": 0.1, "tau2": -0.05})
    as_list = robot.simulate(x0, t_end=2.0, inputs=[0.1, -0.05])
    as_function = robot.simulate(x0, t_end=2.0, inputs=lambda t, x: [0.1, -0.05])
    sampled = robot.simulate(x0, t_end=2.0, inputs={"t": [0.0, 5.0], "tau1": [0.1, 0.1],
                                                     "tau2": np.array([-0.05, -0.05])})
    for run in (as_list, as_function, sampled):
        assert np.array_equal(run.to_numpy(), by_name.to_numpy())
    assert by_name["tau1"][5] == 0.1


def test_sampled_inputs_are_interpolated_linearly():
    robot = MobileRobot()
    run = robot.simulate(robot.state(), t_end=1.0, dt=0.25,
                         inputs={"t": [0.0, 1.0], "tau1": [0.0, 2.0]})
    assert list(run["tau1"]) == [0.0, 0.5, 1.0, 1.5, 2.0]
    assert list(run["tau2"]) == [0.0] * 5


def test_a_feedback_function_sees_the_state():
    robot = MobileRobot()
    seen = []

    def brake(t, x):
        seen.append(x.copy())
        return [-0.5 * x[6], -0.5 * x[6]]

    run = robot.simulate(robot.state(w4=1.0), t_end=3.0, inputs=brake)
    assert len(seen) > 10
    assert abs(run["w4"][-1]) < abs(run["w4"][0])


def test_events_in_scipys_form_and_by_state():
    robot = MobileRobot()
    x0 = robot.state(alpha=0.3, w4=0.5, w5=0.4)

    def half_turn(t, x):
        return x[2] - math.pi

    half_turn.terminal = True
    half_turn.direction = 1
    run = robot.simulate(x0, t_end=10.0, events=[half_turn])
    assert run.events[0].name == "half_turn" and run.events[0].terminal
    t = run.events[0].t
    assert run.t[-1] == t and run.summary.stopped == "event half_turn"
    same = robot.simulate(x0, t_end=10.0, events=[
        hamel.Event("half_turn", state="alpha", value=math.pi, direction=1, terminal=True)])
    assert same.events[0].t == t
    assert abs(same.events[0].state["alpha"] - math.pi) < 1e-9


def test_constraint_forces_are_recorded_on_request():
    robot = MobileRobot()
    run = robot.simulate(robot.state(w4=0.5), t_end=1.0, lambdas=True)
    lambdas = [c for c in run.columns if c.startswith("lambda_")]
    assert len(lambdas) == len(robot.constraints) == 2


def test_runs_to_pandas_and_arrow():
    robot = MobileRobot()
    run = robot.simulate(robot.state(w4=0.5), t_end=1.0)
    frame = run.to_pandas()
    assert list(frame.columns) == list(run.columns)
    assert np.array_equal(frame["x"].to_numpy(), run["x"])
    table = run.to_arrow()
    assert table.num_rows == len(run)
    # A column is a read-only view of the run's memory.
    assert not run["x"].flags.writeable
    assert "steps" in str(run.summary) and run.summary.steps == run.summary["steps"]


def test_linearize_and_lqr_hold_the_bicycle_upright():
    bicycle = WhippleBicycle()
    v = 2.0
    x0 = bicycle.state(rear_wheel_rate=-v / bicycle.parameters["r_r"])
    lin = bicycle.linearize(x0)
    lateral = lin.reduce("phi", "delta", "roll_rate", "steer_rate").with_inputs("steer_torque")
    assert lateral.A.shape == (4, 4) and lateral.B.shape == (4, 1)
    assert max(e.real for e in lateral.eigenvalues) > 0  # the weave is unstable at 2 m/s
    mode = max(lateral.modes, key=lambda m: m.value.real)
    assert set(mode.vector) == {"phi", "delta", "roll_rate", "steer_rate"}
    # `cargo run --release --example bicycle_control`: Q = diag(10, 1, 1, 0.1), R = 1, and
    # the README's closed loop at 2 m/s, −2.7166 ± 1.6779i, −3.0734, −8.7591.
    lqr = lateral.lqr({"phi": 10.0, "delta": 1.0, "roll_rate": 1.0, "steer_rate": 0.1}, 1.0)
    expected = sorted([-2.7166, -2.7166, -3.0734, -8.7591])
    assert np.allclose(sorted(lqr.closed_loop_eigenvalues.real), expected, atol=1e-4)
    start = bicycle.state(rear_wheel_rate=-v / bicycle.parameters["r_r"], phi=0.1)
    run = bicycle.simulate(start, t_end=10.0, dt=0.01, rtol=1e-10, atol=1e-12, inputs=lqr)
    late = run.t >= 5.0
    # The README: |φ| ≤ 1.4e-7 rad from 5 s to 10 s.
    assert np.max(np.abs(run["phi"][late])) < 1.5e-7


def test_the_scene_is_a_page_shown_inline():
    robot = MobileRobot()
    run = robot.simulate(robot.state(alpha=0.3, w4=0.5, w5=0.4), t_end=1.0, dt=0.05)
    scene = robot.scene(run)
    assert scene.html.lstrip().lower().startswith("<!doctype html")
    assert "<iframe srcdoc=" in scene._repr_html_()
    with pytest.raises(TypeError, match="no bodies"):
        ChaplyginSleigh().scene(ChaplyginSleigh().simulate(ChaplyginSleigh().state(), t_end=0.1))
