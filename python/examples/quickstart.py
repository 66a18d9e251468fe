"""hamel from Python in one page: the paper's robot and the Whipple bicycle.

    pip install ./python
    python python/examples/quickstart.py

Runs the robot (the README's run), linearizes and stabilizes the bicycle with LQR, runs an
ensemble of robots into pandas, and writes the robot's run as a 3D scene (robot.html) and,
where matplotlib is installed, a figure (robot.png).
"""

import numpy as np

import hamel
from hamel.models import MobileRobot, WhippleBicycle

# The paper's robot: parameters as keywords (the others at their defaults), a state by name
# (the rest zero), the whole run in Rust.
robot = MobileRobot(m0=10.0)
print(robot)
print("coordinates", robot.coordinates, "speeds", robot.speeds, "inputs", robot.inputs)
x0 = robot.state(alpha=0.3, w4=0.5, w5=0.4)
run = robot.simulate(x0, t_end=10.0, dt=0.01, method="dopri5", rtol=1e-9, atol=1e-12)
print(run)
print(run.summary)
print(f"final position: x = {run['x'][-1]:.4f} m, y = {run['y'][-1]:.4f} m")

# Torques as a function of time and state (a Python function u(t, x)), and an event that
# ends the run: the body swinging through half a turn.
half_turn = hamel.Event("half_turn", state="alpha", value=np.pi, terminal=True)
driven = robot.simulate(x0, t_end=10.0, inputs=lambda t, x: [0.1 * np.sin(t), 0.1 * np.cos(t)],
                        events=[half_turn])
ended = f"by {driven.events[0].name} at t = {driven.events[0].t:.3f} s" if driven.events else "at t = 10 s"
print(f"driven by torques 0.1 sin t, 0.1 cos t: the run ended {ended}, "
      f"work done {driven.summary.work:.4f} J")

# The bicycle: linearized about upright straight running at 2 m/s, below its weave speed,
# then held upright by LQR on the steer torque.
bicycle = WhippleBicycle()
v = 2.0
upright = bicycle.state(rear_wheel_rate=-v / bicycle.parameters["r_r"])
lateral = (bicycle.linearize(upright)
           .reduce("phi", "delta", "roll_rate", "steer_rate")
           .with_inputs("steer_torque"))
print("bicycle at 2 m/s, eigenvalues:", np.round(lateral.eigenvalues, 4))
for mode in lateral.modes:
    print(f"  {mode.value:.4f}: mostly {mode.dominant}")
lqr = lateral.lqr({"phi": 10.0, "delta": 1.0, "roll_rate": 1.0, "steer_rate": 0.1}, 1.0)
print("LQR gain K:", np.round(lqr.K, 4), "closed loop:", np.round(lqr.closed_loop_eigenvalues, 4))
leaning = bicycle.state(rear_wheel_rate=-v / bicycle.parameters["r_r"], phi=0.1)
ride = bicycle.simulate(leaning, t_end=10.0, rtol=1e-10, atol=1e-12, inputs=lqr)
print(f"from a lean of 0.1 rad: |phi| <= {np.max(np.abs(ride['phi'][ride.t >= 5.0])):.2e} rad after 5 s")

# An ensemble: 200 robots of different masses and pitches, on every core, into pandas.
rng = np.random.default_rng(1)
cases = {"m0": rng.uniform(5.0, 15.0, 200), "alpha": rng.uniform(-0.5, 0.5, 200),
         "w4": np.full(200, 0.5), "w5": np.full(200, 0.4)}
table = robot.ensemble(cases, t_end=10.0)
frame = table.to_pandas()
print(frame[["m0", "alpha", "final_x", "final_y", "steps", "energy_error"]].describe().loc[["mean", "min", "max"]])

# The run as a 3D scene (in Jupyter it shows inline), and a figure.
robot.scene(run, show=["x", "y", "alpha", "w4", "energy"]).save("robot.html")
print("wrote robot.html (the run as a 3D scene)")
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib is not installed: no figure")
else:
    fig, (path, pitch) = plt.subplots(1, 2, figsize=(9, 3.5))
    path.plot(run["x"], run["y"])
    path.set(xlabel="x (m)", ylabel="y (m)", title="path", aspect="equal")
    pitch.plot(run.t, run["alpha"])
    pitch.set(xlabel="t (s)", ylabel="alpha (rad)", title="pitch")
    fig.tight_layout()
    fig.savefig("robot.png", dpi=100)
    print("wrote robot.png (the path and the pitch)")
