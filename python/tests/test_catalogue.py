"""The catalogue from Python: the same numbers as Rust, bit for bit, and the published values
the Rust test suite checks."""

import math

import numpy as np
import hamel
from hamel.models import (ChaplyginSleigh, MobileRobot, Rattleback, RollingDisk,
                          WhippleBicycle)


def read_csv(path):
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    # Rust writes each number in its shortest form that reads back to the same f64, which
    # Python's float() reads exactly.
    rows = [[float(v) for v in line.split(",")] for line in lines[1:]]
    return header, np.array(rows)


def test_the_robot_gives_the_rust_examples_rows_bit_for_bit(robot_csv):
    robot = MobileRobot()
    run = robot.simulate(robot.state(alpha=0.3, w4=0.5, w5=0.4), t_end=10.0, dt=0.01,
                         method="dopri5", rtol=1e-9, atol=1e-12)
    header, rows = read_csv(robot_csv)
    assert list(run.columns) == header
    assert rows.shape == (len(run), len(header)) == (1001, 13)
    ours = run.to_numpy()
    # Equal as bits, not only as numbers (a -0.0 against 0.0 would count).
    assert np.array_equal(ours.view(np.uint64), rows.view(np.uint64))
    # And the text Rust writes is the file's.
    assert run.to_csv() == robot_csv.read_text()


def test_every_catalogue_model_runs_and_keeps_its_constraints():
    for name in hamel.models.__all__:
        cls = getattr(hamel.models, name)
        model = cls()
        # Away from the singular configurations of Euler angles (a ball's, at θ = 0).
        values = {name: 0.1 * (i + 1) for i, name in enumerate(model.coordinates)}
        values[model.speeds[0]] = 0.5
        x0 = model.state(**values)
        run = model.simulate(x0, t_end=0.5, dt=0.05)
        assert len(run) == 11, name
        assert run.summary.max_constraint_residual < 1e-9, name
        assert np.isfinite(run.to_numpy()).all(), name


def test_the_sleigh_straightens_out_at_its_closed_form_speed():
    # Chaplygin's sleigh: the forward speed tends to √(2E/m) (Bloch, Nonholonomic Mechanics
    # and Control, §1.7): the energy all in forward motion.
    sleigh = ChaplyginSleigh()
    x0 = sleigh.state(v=1.0, omega=2.0)
    run = sleigh.simulate(x0, t_end=40.0, dt=0.1, rtol=1e-10, atol=1e-12)
    m = sleigh.parameters["m"]
    limit = math.sqrt(2.0 * run["energy"][0] / m)
    assert abs(run["v"][-1] - limit) < 1e-6


def weave_and_capsize(bicycle):
    """The ends of the self-stable speed range: where the largest real part of the lean and
    steer modes crosses zero, found by bisection on the linearization at each speed."""

    r_r = bicycle.parameters["r_r"]

    def growth(v):
        # Upright straight running at v: the rear wheel rolling backwards about its axle.
        x = bicycle.state(rear_wheel_rate=-v / r_r)
        lin = bicycle.linearize(x).reduce("phi", "delta", "roll_rate", "steer_rate")
        return max(e.real for e in lin.eigenvalues)

    def crossing(a, b):
        fa = growth(a)
        for _ in range(60):
            m = 0.5 * (a + b)
            fm = growth(m)
            if (fm > 0) == (fa > 0):
                a, fa = m, fm
            else:
                b = m
        return 0.5 * (a + b)

    return crossing(4.0, 5.0), crossing(5.5, 6.5)


def test_the_bicycle_linearized_from_python_gives_the_benchmark_speeds():
    bicycle = WhippleBicycle()
    weave, capsize = weave_and_capsize(bicycle)
    # Meijaard, Papadopoulos, Ruina, Schwab (2007), Table 2.
    assert abs(weave - 4.29238253634111) < 1e-9
    assert abs(capsize - 6.02426201538837) < 1e-9


def test_the_rattleback_reverses_its_spin_when_rust_says():
    # The settings of `cargo run --release --example rattleback`, which prints the reversal
    # at 13.20 s from +3 rad/s (the README's figure).
    rattleback = Rattleback()
    reversed_ = hamel.Event("reversed", state="yaw_rate", value=0.0)
    run = rattleback.simulate(rattleback.state(yaw_rate=3.0, roll_rate=0.02), t_end=30.0,
                              dt=1.0 / 60.0, rtol=1e-10, atol=1e-12, project=True,
                              events=[reversed_])
    first = run.event_times("reversed")[0]
    assert f"{first:.2f}" == "13.20"


def test_a_rolling_disk_keeps_its_energy():
    disk = RollingDisk()
    run = disk.simulate(disk.state(**{disk.speeds[0]: 3.0, disk.speeds[-1]: 1.0}), t_end=5.0)
    assert run.summary.relative_energy_drift < 1e-7
