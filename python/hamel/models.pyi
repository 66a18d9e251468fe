"""Type stubs of the catalogue (hamel.models): each model's parameters as keywords,
with their defaults, units and doc comments (written from the models' descriptions)."""

from ._model import Model

__all__: list[str]

class BallOnTurntable(Model):
    """The model BallOnTurntable.

    State: x, y, phi, theta, psi, omega_x, omega_y, omega_z.
    """
    def __init__(self, *, m: float = 1.0, radius: float = 0.5, inertia: float = 0.1, omega0: float = 1.0, epsilon: float = 0.1) -> None:
        """m: mass of the ball (kg); radius: radius of the ball (m); inertia: moment of inertia of the ball about any axis through its centre (kg m²); omega0: rate of the table at t = 0 (rad/s); epsilon: angular acceleration of the table (rad/s²)"""

class ChaplyginBall(Model):
    """The model ChaplyginBall.

    State: x, y, alpha, beta, gamma, alpha_rate, beta_rate, gamma_rate.
    """
    def __init__(self, *, m: float = 1.0, r: float = 0.1, i1: float = 0.002, i2: float = 0.003, i3: float = 0.004) -> None:
        """m: mass (kg); r: radius (m); i1: principal moments of inertia about the body's x, y and z axes (kg m²); i2: ; i3: """

class ChaplyginSleigh(Model):
    """The model ChaplyginSleigh.

    State: x, y, theta, v, omega.
    """
    def __init__(self, *, m: float = 2.0, inertia: float = 0.5, a: float = 0.4) -> None:
        """m: mass (kg); inertia: moment of inertia about the centre of mass (kg m²); a: distance of the contact point behind the centre of mass (m)"""

class ContactOscillator(Model):
    """The model ContactOscillator.

    State: x, y, z, vy, vz.
    """
    def __init__(self, *, epsilon: float = 0.3) -> None:
        """epsilon: coupling of x and z in the potential, ½ε x² z²"""

class KnifeEdge(Model):
    """The model KnifeEdge.

    State: x, y, phi, v, omega.
    """
    def __init__(self, *, m: float = 1.0, j: float = 0.1, g: float = 9.81, incline: float = 0.3) -> None:
        """m: mass (kg); j: moment of inertia about the vertical through the contact point (kg m²); g: gravitational acceleration (m/s²); incline: inclination of the plane (rad)"""

class MobileRobot(Model):
    """The model MobileRobot.

    State: x, y, alpha, phi1, phi2, w3, w4, w5.
    Inputs: tau1, tau2.
    """
    def __init__(self, *, m0: float = 10.0, mw: float = 1.0, jx: float = 0.4, jy: float = 0.3, jz: float = 0.2, r: float = 0.1, b: float = 0.5, l: float = 0.2, g: float = 9.81) -> None:
        """m0: mass of the body (kg); mw: mass of one wheel (kg); jx: body's principal moment of inertia about its x axis (forward) (kg m²); jy: body's principal moment of inertia about its y axis (the axle) (kg m²); jz: body's principal moment of inertia about its z axis (vertical) (kg m²); r: wheel radius (m); b: axle length, wheel to wheel (m); l: distance of the body's centre of gravity from the axle (m); g: gravitational acceleration (m/s²)"""

class MobileRobotPaper(Model):
    """The model MobileRobotPaper.

    State: x, y, alpha, phi1, phi2, w3, w4, w5.
    Inputs: tau1, tau2.
    """
    def __init__(self, *, m0: float = 10.0, mw: float = 1.0, jx: float = 0.4, jy: float = 0.3, jz: float = 0.2, r: float = 0.1, b: float = 0.5, l: float = 0.2, g: float = 9.81) -> None:
        """m0: mass of the body (kg); mw: mass of one wheel (kg); jx: body's principal moment of inertia about its x axis (kg m²); jy: body's principal moment of inertia about its y axis (the axle) (kg m²); jz: body's principal moment of inertia about its z axis (kg m²); r: wheel radius (m); b: axle length (m); l: distance of the body's centre of gravity from the axle (m); g: gravitational acceleration (m/s²)"""

class NTrailer1(Model):
    """The model NTrailer1.

    State: x, y, theta0, theta1, v, omega.
    Inputs: drive, steer.
    """
    def __init__(self, *, m0: float = 2.0, m1: float = 1.0, inertia0: float = 0.1, inertia1: float = 0.05, d0: float = 0.0, d1: float = 0.5) -> None:
        """m0: mass of each body, a point mass at its axle centre (kg) [0]; m1: mass of each body, a point mass at its axle centre (kg) [1]; inertia0: moment of inertia of each body about the vertical through its axle centre (kg m²) [0]; inertia1: moment of inertia of each body about the vertical through its axle centre (kg m²) [1]; d0: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [0]; d1: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [1]"""

class NTrailer2(Model):
    """The model NTrailer2.

    State: x, y, theta0, theta1, theta2, v, omega.
    Inputs: drive, steer.
    """
    def __init__(self, *, m0: float = 2.0, m1: float = 1.0, m2: float = 1.0, inertia0: float = 0.1, inertia1: float = 0.05, inertia2: float = 0.05, d0: float = 0.0, d1: float = 0.5, d2: float = 0.5) -> None:
        """m0: mass of each body, a point mass at its axle centre (kg) [0]; m1: mass of each body, a point mass at its axle centre (kg) [1]; m2: mass of each body, a point mass at its axle centre (kg) [2]; inertia0: moment of inertia of each body about the vertical through its axle centre (kg m²) [0]; inertia1: moment of inertia of each body about the vertical through its axle centre (kg m²) [1]; inertia2: moment of inertia of each body about the vertical through its axle centre (kg m²) [2]; d0: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [0]; d1: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [1]; d2: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [2]"""

class NTrailer8(Model):
    """The model NTrailer8.

    State: x, y, theta0, theta1, theta2, theta3, theta4, theta5, theta6, theta7, theta8, v, omega.
    Inputs: drive, steer.
    """
    def __init__(self, *, m0: float = 2.0, m1: float = 1.0, m2: float = 1.0, m3: float = 1.0, m4: float = 1.0, m5: float = 1.0, m6: float = 1.0, m7: float = 1.0, m8: float = 1.0, inertia0: float = 0.1, inertia1: float = 0.05, inertia2: float = 0.05, inertia3: float = 0.05, inertia4: float = 0.05, inertia5: float = 0.05, inertia6: float = 0.05, inertia7: float = 0.05, inertia8: float = 0.05, d0: float = 0.0, d1: float = 0.5, d2: float = 0.5, d3: float = 0.5, d4: float = 0.5, d5: float = 0.5, d6: float = 0.5, d7: float = 0.5, d8: float = 0.5) -> None:
        """m0: mass of each body, a point mass at its axle centre (kg) [0]; m1: mass of each body, a point mass at its axle centre (kg) [1]; m2: mass of each body, a point mass at its axle centre (kg) [2]; m3: mass of each body, a point mass at its axle centre (kg) [3]; m4: mass of each body, a point mass at its axle centre (kg) [4]; m5: mass of each body, a point mass at its axle centre (kg) [5]; m6: mass of each body, a point mass at its axle centre (kg) [6]; m7: mass of each body, a point mass at its axle centre (kg) [7]; m8: mass of each body, a point mass at its axle centre (kg) [8]; inertia0: moment of inertia of each body about the vertical through its axle centre (kg m²) [0]; inertia1: moment of inertia of each body about the vertical through its axle centre (kg m²) [1]; inertia2: moment of inertia of each body about the vertical through its axle centre (kg m²) [2]; inertia3: moment of inertia of each body about the vertical through its axle centre (kg m²) [3]; inertia4: moment of inertia of each body about the vertical through its axle centre (kg m²) [4]; inertia5: moment of inertia of each body about the vertical through its axle centre (kg m²) [5]; inertia6: moment of inertia of each body about the vertical through its axle centre (kg m²) [6]; inertia7: moment of inertia of each body about the vertical through its axle centre (kg m²) [7]; inertia8: moment of inertia of each body about the vertical through its axle centre (kg m²) [8]; d0: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [0]; d1: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [1]; d2: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [2]; d3: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [3]; d4: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [4]; d5: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [5]; d6: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [6]; d7: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [7]; d8: distance from each trailer's hitch to its axle centre (m); entry 0 is unused [8]"""

class Rattleback(Model):
    """The model Rattleback.

    State: x, y, z, psi, phi, theta, yaw_rate, roll_rate, pitch_rate.
    """
    def __init__(self, *, m: float = 0.1, a: float = 2e-05, b: float = 0.00016, c: float = 0.00017, r1: float = 0.2, r2: float = 0.025, h: float = 0.01, delta: float = 0.05, g: float = 9.81) -> None:
        """m: mass (kg); a: principal moments of inertia about the body's x (long), y and z axes (kg m²); b: ; c: ; r1: radii of curvature of the base along its ξ and η axes (m); r2: ; h: height of the centre of mass above the base's lowest point (m); delta: angle from the inertia axes to the base's axes, about the body's z axis (rad); g: gravitational acceleration (m/s²)"""

class RollingDisk(Model):
    """The model RollingDisk.

    State: x, y, psi, phi, theta, yaw_rate, lean_rate, spin_rate.
    """
    def __init__(self, *, m: float = 0.1, r: float = 0.05, g: float = 9.81) -> None:
        """m: mass (kg); r: radius (m); g: gravitational acceleration (m/s²)"""

class VerticalDisk(Model):
    """The model VerticalDisk.

    State: x, y, theta, phi, roll, turn.
    """
    def __init__(self, *, m: float = 1.0, i_roll: float = 0.125, i_turn: float = 0.0625, r: float = 0.5) -> None:
        """m: mass (kg); i_roll: moment of inertia about the axle, for the rolling (kg m²); i_turn: moment of inertia about the vertical diameter, for the turning (kg m²); r: radius (m)"""

class WhippleBicycle(Model):
    """The model WhippleBicycle.

    State: x, y, psi, phi, theta, delta, theta_r, theta_f, roll_rate, steer_rate, rear_wheel_rate.
    Inputs: roll_torque, steer_torque.
    """
    def __init__(self, *, w: float = 1.02, c: float = 0.08, lambda: float = 0.3141592653589793, g: float = 9.81, r_r: float = 0.3, m_r: float = 2.0, i_rxx: float = 0.0603, i_ryy: float = 0.12, x_b: float = 0.3, z_b: float = -0.9, m_b: float = 85.0, i_bxx: float = 9.2, i_byy: float = 11.0, i_bzz: float = 2.8, i_bxz: float = 2.4, x_h: float = 0.9, z_h: float = -0.7, m_h: float = 4.0, i_hxx: float = 0.05892, i_hyy: float = 0.06, i_hzz: float = 0.00708, i_hxz: float = -0.00756, r_f: float = 0.35, m_f: float = 3.0, i_fxx: float = 0.1405, i_fyy: float = 0.28) -> None:
        """w: wheelbase (m); c: trail (m); lambda: steer axis tilt from the vertical (rad); g: gravitational acceleration (m/s²); r_r: rear wheel radius (m); m_r: rear wheel mass (kg); i_rxx: rear wheel moment of inertia about a diameter (kg m²); i_ryy: rear wheel moment of inertia about its axle (kg m²); x_b: rear frame centre of mass, forward of the rear contact (m); z_b: rear frame centre of mass, z (negative: above the ground) (m); m_b: rear frame mass (kg); i_bxx: rear frame inertia I_xx about its centre of mass (kg m²); i_byy: rear frame inertia I_yy (kg m²); i_bzz: rear frame inertia I_zz (kg m²); i_bxz: rear frame product of inertia I_xz (kg m²); x_h: front frame centre of mass, forward of the rear contact (m); z_h: front frame centre of mass, z (m); m_h: front frame mass (kg); i_hxx: front frame inertia I_xx about its centre of mass (kg m²); i_hyy: front frame inertia I_yy (kg m²); i_hzz: front frame inertia I_zz (kg m²); i_hxz: front frame product of inertia I_xz (kg m²); r_f: front wheel radius (m); m_f: front wheel mass (kg); i_fxx: front wheel moment of inertia about a diameter (kg m²); i_fyy: front wheel moment of inertia about its axle (kg m²)"""
