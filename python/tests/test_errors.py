"""Errors a Python user can act on: hamel's errors as `hamel.Error` subclasses with the kind,
the time and the state, the same messages as Rust; mistakes in arguments as TypeError or
ValueError naming the argument; a Python exception from an input or event function raised as
it is."""

import math
import re

import numpy as np
import pytest

import hamel
from hamel import errors
from hamel.models import ChaplyginSleigh, MobileRobot


def test_every_kind_of_the_rust_error_has_its_class(repository):
    source = (repository / "hamel-runtime" / "src" / "error_kind.rs").read_text()
    kinds = set(re.findall(r'=> "([a-z_]+)"', source))
    assert len(kinds) > 40
    for kind in kinds:
        cls = errors.error_class(kind)
        assert cls is not hamel.Error and cls.kind == kind, kind
        assert issubclass(cls, hamel.Error)
        assert cls.__name__ == "".join(p.capitalize() for p in kind.split("_"))


def test_a_parameter_that_is_not_finite():
    with pytest.raises(errors.InvalidParameter) as caught:
        MobileRobot(m0=math.nan)
    e = caught.value
    assert isinstance(e, ValueError) and e.kind == "invalid_parameter"
    assert str(e) == "parameter `m0` is NaN: parameters must be finite numbers"


def test_an_unknown_parameter_is_a_type_error_naming_it():
    with pytest.raises(TypeError, match="unknown parameter `mass`; the parameters are: m0, mw"):
        MobileRobot(mass=3.0)
    with pytest.raises(TypeError, match="m0: expected a number"):
        MobileRobot(m0="heavy")


def test_wrong_arguments_name_themselves():
    robot = MobileRobot()
    with pytest.raises(ValueError, match=r"x0: 3 values given; the state of MobileRobot has 8"):
        robot.simulate([0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"x0: expected a one-dimensional array"):
        robot.simulate(np.zeros((2, 8)))
    with pytest.raises(TypeError, match=r"x0: expected an array of 8 numbers"):
        robot.simulate("state")
    with pytest.raises(ValueError, match="method: unknown integrator `euler`; the integrators are dopri5"):
        robot.simulate(robot.state(), method="euler")
    with pytest.raises(ValueError, match="rtol: the method `rk4` is a fixed-step method"):
        robot.simulate(robot.state(), method="rk4", rtol=1e-6)
    with pytest.raises(ValueError, match="inputs: unknown input `torque`; the model's inputs are: tau1, tau2"):
        robot.simulate(robot.state(), inputs={"torque": 1.0})
    with pytest.raises(ValueError, match="inputs: 3 values given"):
        robot.simulate(robot.state(), inputs=[1.0, 2.0, 3.0])
    with pytest.raises(TypeError, match="unexpected keyword argument 'tend'"):
        robot.simulate(robot.state(), tend=3.0)
    with pytest.raises(TypeError, match="t_end"):
        robot.simulate(robot.state(), t_end="soon")


def test_run_settings_are_refused_with_rusts_message():
    robot = MobileRobot()
    with pytest.raises(errors.InvalidSetting) as caught:
        robot.simulate(robot.state(), dt=-1.0)
    assert isinstance(caught.value, ValueError)
    assert str(caught.value).startswith("invalid setting `sample interval` = -1")
    with pytest.raises(errors.TooManySamples):
        robot.simulate(robot.state(), t_end=10.0, dt=0.01, max_samples=100)


def test_an_unknown_state_name():
    with pytest.raises(errors.UnknownStateName, match="unknown name `speed`"):
        MobileRobot().state(speed=1.0)


def test_velocities_that_violate_the_constraints():
    with pytest.raises(errors.ConstraintViolation) as caught:
        ChaplyginSleigh().state(velocities={"y": 1.0})
    assert "the initial velocities violate constraint" in str(caught.value)


def test_an_integration_that_runs_out_of_steps_names_the_time_and_state():
    robot = MobileRobot()
    with pytest.raises(errors.TooManySteps) as caught:
        robot.simulate(robot.state(alpha=0.3, w4=0.5), t_end=10.0, max_steps=20)
    e = caught.value
    assert e.kind == "too_many_steps"
    assert 0.0 < e.time < 10.0
    # The state, and the work done on the robot that the run integrates beside it.
    assert set(robot.state_names) <= set(e.state)
    assert f"state: x = " in str(e)


def test_an_input_function_returning_nan_is_named_with_time_and_state():
    robot = MobileRobot()
    with pytest.raises(errors.NonFiniteInput) as caught:
        robot.simulate(robot.state(w4=0.5), t_end=2.0,
                       inputs=lambda t, x: [math.nan if t > 1.0 else 0.0, 0.0])
    e = caught.value
    assert e.time > 1.0 and e.state is not None
    assert str(e).startswith("the input `tau1` is NaN at t = ")


def test_an_exception_in_an_input_or_event_function_is_raised_as_it_is():
    robot = MobileRobot()

    def inputs(t, x):
        if t > 0.5:
            raise ZeroDivisionError("from the inputs")
        return [0.0, 0.0]

    with pytest.raises(ZeroDivisionError, match="from the inputs"):
        robot.simulate(robot.state(w4=0.5), t_end=2.0, inputs=inputs)

    def event(t, x):
        raise KeyError("from the event")

    with pytest.raises(KeyError, match="from the event"):
        robot.simulate(robot.state(w4=0.5), t_end=2.0, events=[event])
    with pytest.raises(TypeError, match="it must return one number per input"):
        robot.simulate(robot.state(), t_end=1.0, inputs=lambda t, x: "none")


def test_a_body_no_matter_makes_is_refused():
    with pytest.raises(hamel.Error) as caught:
        MobileRobot(m0=-10.0).state(w4=0.5)
    assert caught.value.kind in ("unphysical_body", "indefinite_mass_matrix")
    assert isinstance(caught.value, ValueError)


def test_an_lqr_that_has_no_solution():
    robot = MobileRobot()
    lin = robot.linearize(robot.state())
    with pytest.raises(errors.InvalidWeights):
        lin.lqr(-np.eye(8), np.eye(2))
    with pytest.raises(ValueError, match="Q: the weight is 3×3; it must be 8×8"):
        lin.lqr(np.eye(3), np.eye(2))


def test_errors_pickle_their_message_kind_time_and_state():
    import pickle

    robot = MobileRobot()
    try:
        robot.simulate(robot.state(alpha=0.3, w4=0.5), max_steps=5)
    except hamel.Error as e:
        again = pickle.loads(pickle.dumps(e))
        assert (str(again), again.kind, again.time) == (str(e), e.kind, e.time)


def test_an_impossible_geometry_is_refused_with_its_reason():
    with pytest.raises(errors.ImpossibleGeometry) as caught:
        MobileRobot(r=-0.1).state(w4=0.5)
    e = caught.value
    assert isinstance(e, ValueError) and e.kind == "impossible_geometry"
    assert str(e) == ("the shape of body `right_wheel` is impossible: a disk: its radius is -0.1; "
                      "it must be positive (check the parameters it is made of)")


def test_an_orientation_at_its_singularity_names_the_time_and_state():
    # The Chaplygin ball's Euler angles are singular at beta = 0 (hamel::docs::geometry).
    ball = hamel.models.ChaplyginBall()
    x0 = ball.state(alpha_rate=1.0, beta_rate=1.0, gamma_rate=1.0)
    with pytest.raises(errors.SingularOrientation) as caught:
        ball.simulate(x0, t_end=1.0)
    e = caught.value
    assert e.kind == "singular_orientation" and e.time == 0.0
    assert e.state is not None and e.state["beta"] == 0.0
    assert "Rotation3::from_quaternion(w, x, y, z)" in str(e)
