//! Rolling on any surface, from shapes: what the vocabulary of issue 26 states, against what
//! nobody here wrote.
//!
//! 1. The two copies of the vocabulary — `hamel::geometry` at run time, its mirror in the
//!    macro — give the same values for every function (`#[differentiate]`'s `_generic`
//!    methods evaluate the mirror).
//! 2. A disk rolling straight down an inclined plane accelerates at (2/3) g sin α.
//! 3. A disk on a tilted turntable: the right-hand side against Lagrange's equations with
//!    multipliers (`common/affine_multipliers.rs`), its kinematics written here by hand.
//! 4. A ball in a spherical bowl and a ball on a fixed sphere: the energy, the spin about the
//!    normal and the area integral about the vertical kept; the steady circular motion in the
//!    bowl at the closed form's spin.
//! 5. Chaplygin's ball with its body rates as speeds moves as with Euler-angle rates; oriented
//!    by a quaternion, it runs through the Euler angles' singularity with its integrals kept.
//! 6. A free asymmetric top oriented by a quaternion tumbles as the Euler–Poinsot solution in
//!    Jacobi's elliptic functions says, its angular momentum fixed in space.
use crate::common::affine_multipliers::{Mechanism as Multipliers, Real, reference};
use hamel::geometry::{Rotation3, Shape, Surface, Vector3};
use hamel::models::ChaplyginBall;
use hamel::prelude::*;
use std::f64::consts::PI;

/// The largest |a − b| relative to max|b|.
fn normwise(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale.max(f64::MIN_POSITIVE)
}

// ---------------------------------------------------------------------------------------
// 1. The vocabulary both ways
// ---------------------------------------------------------------------------------------

/// Every function of the vocabulary in a form `#[differentiate]` takes: an array of reals in,
/// an array out. `f` runs `hamel::geometry`; `f_generic::<f64>` runs the macro's mirror.
struct Vocabulary;

#[hamel::differentiate]
impl Vocabulary {
    fn vectors(&self, x: [f64; 6]) -> [f64; 12] {
        let a = Vector3::new(x[0], x[1], x[2]);
        let b = Vector3::new(x[3], x[4], x[5]);
        let c = a.cross(&b) + 2.0 * a - b / 3.0 - Vector3::x() * x[0] + Vector3::zeros();
        let n = (a - b).normalize();
        [
            c.x,
            c[1],
            c.z,
            a.dot(&b),
            a.norm(),
            b.norm_squared(),
            n.x,
            n.y,
            n.z,
            (-a).to_array()[0],
            Vector3::y().dot(&b),
            Vector3::z().dot(&a),
        ]
    }

    fn rotations(&self, x: [f64; 7]) -> [f64; 9] {
        let axis = Vector3::new(x[0], x[1], x[2]);
        let r = Rotation3::about_x(x[3])
            * Rotation3::about_y(x[4]).transpose()
            * Rotation3::about_z(x[5]).inverse()
            * Rotation3::from_axis_angle(&axis, x[6])
            * Rotation3::from_euler_angles(x[4], x[5], x[6])
            * Rotation3::from_quaternion(x[3], x[4], x[5], x[6])
            * Rotation3::identity();
        let m = Rotation3::from_matrix_unchecked(r.matrix()).matrix();
        [
            m[0][0],
            m[0][1],
            m[0][2],
            m[1][0],
            m[1][1],
            m[1][2],
            m[2][0],
            r[(2, 1)],
            m[2][2],
        ]
    }

    /// Inertias, bodies and their fields.
    fn bodies(&self, x: [f64; 6]) -> [f64; 10] {
        let inertia = Inertia::new(x[0], x[1], x[2], x[3], x[4], x[5]);
        let m = inertia.matrix();
        let point = Body::point_mass(x[0], Vector3::new(x[1], x[2], x[3]));
        let body = Body::new(x[4], inertia, point.centre, Rotation3::about_x(x[5]));
        let contact = Contact::ground(body, point.point(Vector3::x()));
        let rotated = body.orientation * Vector3::new(x[0], x[1], x[2]);
        [
            m[0][1],
            m[2][0] + inertia.yz,
            contact.body.mass,
            contact.body.inertia.zz,
            point.mass + point.inertia.xx,
            rotated.z,
            contact.point.x,
            body.centre.y,
            body.orientation[(1, 2)],
            point.orientation.matrix()[0][0],
        ]
    }

    /// Bodies with each shape, on each surface: the contact point, the surface's normal and
    /// the height there.
    fn contacts(&self, x: [f64; 8]) -> [f64; 36] {
        let orientation = Rotation3::about_z(x[0]) * Rotation3::about_x(x[1]);
        let centre = Vector3::new(x[2], x[3], x[4]);
        let body = Body::new(1.0, Inertia::principal(0.2, 0.3, 0.4), centre, orientation);
        let axle = Vector3::new(0.1, 1.0, 0.2);
        let offset = Vector3::new(0.01, -0.02, 0.03);
        let shapes = [
            Shape::disk(x[5], axle),
            Shape::torus(x[5], x[6], axle),
            Shape::sphere(x[5]).at(offset),
            Shape::ellipsoid(x[5], x[6], x[7]).at(offset),
        ];
        let plane = Surface::plane(Vector3::new(0.1, 0.2, -0.3), Rotation3::about_y(x[7]));
        let sphere = Surface::sphere(Vector3::new(0.3, -0.2, -2.0), 1.5);
        let bowl = Surface::bowl(Vector3::new(0.3, -0.2, 2.0), 3.0);
        let turntable = Surface::of(body);
        let mut out = [0.0; 36];
        for k in 0..4 {
            let c = Contact::rolling(body.with_shape(shapes[k]), plane);
            let n = c.surface.normal(c.point);
            out[5 * k] = c.point.x;
            out[5 * k + 1] = c.point.y;
            out[5 * k + 2] = c.point.z;
            out[5 * k + 3] = n.x;
            out[5 * k + 4] = plane.height(c.point);
        }
        let ball = body.with_shape(Shape::sphere(x[5]).at(offset));
        let surfaces = [sphere, bowl, turntable, Surface::ground()];
        for k in 0..4 {
            let c = Contact::rolling(ball, surfaces[k]);
            let n = surfaces[k].normal(c.point);
            out[20 + 4 * k] = c.point.y;
            out[21 + 4 * k] = n.y;
            out[22 + 4 * k] = n.z;
            out[23 + 4 * k] = surfaces[k].height(c.point);
        }
        let written = Contact::new(ball, bowl, centre);
        let on = Contact::on(ball, body, centre);
        let ground = Contact::ground(
            ball,
            disk_contact(centre, axle.normalize(), x[5], Vector3::z()),
        );
        out[34] = written.surface.height(written.point) + on.surface.height(on.point);
        out[35] = ground.point.x + body.point(offset).y;
        out
    }
}

#[test]
fn the_vocabulary_gives_the_same_values_both_ways() {
    let v = Vocabulary;
    let points = [
        [0.3, -0.7, 1.1, 0.4, 0.9, -0.2, 0.6, 0.25],
        [-1.2, 0.5, 0.2, -0.8, 0.1, 0.3, 0.15, 0.35],
    ];
    let mut worst = 0.0f64;
    for x in points {
        let six: [f64; 6] = std::array::from_fn(|i| x[i]);
        let seven: [f64; 7] = std::array::from_fn(|i| x[i]);
        let pairs = [
            (
                v.vectors(six).to_vec(),
                v.vectors_generic::<f64>(six).to_vec(),
            ),
            (
                v.rotations(seven).to_vec(),
                v.rotations_generic::<f64>(seven).to_vec(),
            ),
            (
                v.contacts(x).to_vec(),
                v.contacts_generic::<f64>(x).to_vec(),
            ),
            (
                v.bodies(six).to_vec(),
                v.bodies_generic::<f64>(six).to_vec(),
            ),
        ];
        for (runtime, mirror) in pairs {
            let err = normwise(&mirror, &runtime);
            assert!(
                err < 1e-14,
                "{err:e}: run time {runtime:?}, macro {mirror:?}"
            );
            worst = worst.max(err);
        }
    }
    println!("the vocabulary, run time against the macro's mirror: worst {worst:.1e}");
}

// ---------------------------------------------------------------------------------------
// 2. A disk down an incline
// ---------------------------------------------------------------------------------------

/// A thin disk rolling on a plane inclined by `alpha` about the ground's y axis: (x, y) its
/// contact point in the plane's axes, yaw, lean and spin relative to the plane.
#[hamel_system]
pub struct InclinedDisk {
    pub m: f64,
    pub r: f64,
    pub g: f64,
    pub alpha: f64,
}

#[hamel_system(
    coordinates(x, y, psi, phi, theta),
    speeds(yaw_rate, lean_rate, spin_rate)
)]
impl InclinedDisk {
    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
        let incline = Rotation3::about_y(self.alpha);
        let heading = incline * Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]);
        let centre =
            incline * Vector3::new(q[0], q[1], 0.0) + heading * Vector3::new(0.0, 0.0, self.r);
        let diameter = self.m * self.r * self.r / 4.0;
        let inertia = Inertia::principal(diameter, 2.0 * diameter, diameter);
        let disk = Body::new(self.m, inertia, centre, heading * Rotation3::about_y(q[4]));
        [disk.with_shape(Shape::disk(self.r, Vector3::y()))]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        let [disk] = self.bodies(q);
        let incline = Surface::plane(Vector3::zeros(), Rotation3::about_y(self.alpha));
        [Contact::rolling(disk, incline)]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[2], qd[3], qd[4]]
    }
}

/// Upright, heading straight down the incline (its x axis), the disk's centre accelerates at
/// a = g sin α / (1 + I/(m r²)) = (2/3) g sin α for I = m r²/2 (Routh; any textbook's
/// rolling cylinder), so its spin at a/r; it neither yaws nor leans. At random spins and
/// places, and along a run: x(t) = a t²/2 exactly (the integrator is exact on a quadratic).
#[test]
fn a_disk_rolls_straight_down_an_incline_at_two_thirds_g_sin_alpha() {
    let mut worst = 0.0f64;
    for alpha in [0.1, 0.35, 1.0] {
        let disk = InclinedDisk {
            m: 0.7,
            r: 0.3,
            g: 9.81,
            alpha,
        };
        let a = 2.0 / 3.0 * disk.g * alpha.sin();
        for (i, spin) in [-3.0, 0.0, 0.5, 12.0].into_iter().enumerate() {
            let x = [0.3 * i as f64, -0.2, 0.0, 0.0, 1.7, 0.0, 0.0, spin];
            let mut dx = [0.0; 8];
            disk.rhs(0.0, &x, &[], &mut dx).unwrap();
            let expected = [spin * disk.r, 0.0, 0.0, 0.0, spin, 0.0, 0.0, a / disk.r];
            let err = normwise(&dx, &expected);
            assert!(
                err < 1e-12,
                "α = {alpha}, spin {spin}: {dx:?} against {expected:?}"
            );
            worst = worst.max(err);
        }
        let x0 = [0.0; 8];
        let run = Simulation::new(&disk, x0)
            .end_time(2.0)
            .sample_interval(0.5)
            .run_constant(&DormandPrince::new(1e-12, 1e-14), [])
            .unwrap();
        for (t, x) in run.times().iter().zip(run.column("x").unwrap()) {
            let err = (x - 0.5 * a * t * t).abs() / (0.5 * a * 4.0);
            assert!(err < 1e-12, "α = {alpha}, t = {t}: x = {x}");
            worst = worst.max(err);
        }
    }
    println!("disk down an incline against (2/3) g sin α: worst {worst:.1e}");
}

// ---------------------------------------------------------------------------------------
// 3. A disk on a tilted turntable
// ---------------------------------------------------------------------------------------

mod tables {
    use hamel::geometry::{Body, Inertia, Rotation3, Vector3};

    pub struct Tables;

    #[hamel::helpers]
    impl Tables {
        /// A turntable tilted by `tilt` about the ground's x axis and turned by `spin` t about
        /// its own normal.
        pub fn table(tilt: f64, spin: f64, t: f64) -> Body {
            let pose = Rotation3::about_x(tilt) * Rotation3::about_z(spin * t);
            Body::new(
                1.0,
                Inertia::principal(1.0, 1.0, 1.0),
                Vector3::zeros(),
                pose,
            )
        }

        /// A thin disk (mass m, radius r) on `table`: q its contact point in the table's
        /// axes, its yaw, lean and spin relative to it.
        pub fn disk(m: f64, r: f64, table: Body, q: &[f64; 5]) -> Body {
            let heading = table.orientation * Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]);
            let contact = table.point(Vector3::new(q[0], q[1], 0.0));
            let centre = contact + heading * Vector3::new(0.0, 0.0, r);
            let diameter = m * r * r / 4.0;
            let inertia = Inertia::principal(diameter, 2.0 * diameter, diameter);
            Body::new(m, inertia, centre, heading * Rotation3::about_y(q[4]))
        }
    }
}

use tables::Tables;

/// A thin disk on a turntable tilted by `tilt` about the ground's x axis and turning at
/// `spin` rad/s about its own normal: the coordinates are relative to the table (the contact
/// point in its axes, yaw, lean and spin).
#[hamel_system]
pub struct TurntableDisk {
    pub m: f64,
    pub r: f64,
    pub g: f64,
    pub tilt: f64,
    pub spin: f64,
}

#[hamel_system(
    coordinates(x, y, psi, phi, theta),
    speeds(yaw_rate, lean_rate, spin_rate),
    helpers(Tables)
)]
impl TurntableDisk {
    #[bodies]
    fn bodies(&self, t: f64, q: &[f64; 5]) -> [Body; 1] {
        let table = Tables::table(self.tilt, self.spin, t);
        let disk = Tables::disk(self.m, self.r, table, q);
        [disk.with_shape(Shape::disk(self.r, Vector3::y()))]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    #[contacts]
    fn contacts(&self, t: f64, q: &[f64; 5]) -> [Contact; 1] {
        let [disk] = self.bodies(t, q);
        let table = Tables::table(self.tilt, self.spin, t);
        [Contact::rolling(disk, Surface::of(table))]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[2], qd[3], qd[4]]
    }
}

/// The same disk with its contact written (`Contact::on`, the point (x, y) of the table):
/// the tilt of the table is its surface's, not ignored.
#[hamel_system]
pub struct TurntableDiskWritten {
    pub m: f64,
    pub r: f64,
    pub g: f64,
    pub tilt: f64,
    pub spin: f64,
}

#[hamel_system(
    coordinates(x, y, psi, phi, theta),
    speeds(yaw_rate, lean_rate, spin_rate),
    helpers(Tables)
)]
impl TurntableDiskWritten {
    #[bodies]
    fn bodies(&self, t: f64, q: &[f64; 5]) -> [Body; 1] {
        let table = Tables::table(self.tilt, self.spin, t);
        [Tables::disk(self.m, self.r, table, q)]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    #[contacts]
    fn contacts(&self, t: f64, q: &[f64; 5]) -> [Contact; 1] {
        let [disk] = self.bodies(t, q);
        let table = Tables::table(self.tilt, self.spin, t);
        [Contact::on(
            disk,
            table,
            table.point(Vector3::new(q[0], q[1], 0.0)),
        )]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[2], qd[3], qd[4]]
    }
}

/// The disk on the tilted turntable by hand: its kinematics relative to the table, written
/// here with rotation matrices, for Lagrange's equations with multipliers. Rows: the slip of
/// the disk's material point at the contact relative to the table, along the table's x and
/// y axes (in the table's frame, ċ_T + ω_rel × (P_T − c_T)); then the relative rates.
struct TurntableByHand<'a>(&'a TurntableDisk);

type V3<T> = [T; 3];

fn mat_vec<T: Real>(m: &[[T; 3]; 3], v: V3<T>) -> V3<T> {
    std::array::from_fn(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

fn mat_mat<T: Real>(a: &[[T; 3]; 3], b: &[[T; 3]; 3]) -> [[T; 3]; 3] {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j])
    })
}

fn cross<T: Real>(a: V3<T>, b: V3<T>) -> V3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot<T: Real>(a: V3<T>, b: V3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn add<T: Real>(a: V3<T>, b: V3<T>) -> V3<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// Elementary rotations, as matrices, about the axis `k` (0, 1, 2).
fn about<T: Real>(k: usize, angle: T) -> [[T; 3]; 3] {
    let (s, c) = (angle.sin(), angle.cos());
    let (o, l) = (T::zero(), T::one());
    match k {
        0 => [[l, o, o], [o, c, -s], [o, s, c]],
        1 => [[c, o, s], [o, l, o], [-s, o, c]],
        _ => [[c, -s, o], [s, c, o], [o, o, l]],
    }
}

impl TurntableByHand<'_> {
    /// In the ground frame: the table's rotation and angular velocity; the disk's centre, its
    /// velocity, its angular velocity and its axle.
    #[allow(clippy::type_complexity)]
    fn kinematics<T: Real>(&self, t: T, q: &[T; 5], qd: &[T; 5]) -> (V3<T>, V3<T>, V3<T>, V3<T>) {
        let p = self.0;
        let z = T::zero();
        let table = mat_mat(&about(0, T::from(p.tilt)), &about(2, t * p.spin));
        let table_spin = mat_vec(&about(0, T::from(p.tilt)), [z, z, T::from(p.spin)]);
        let (yaw, lean) = (about(2, q[2]), about(0, q[3]));
        let yaw_lean = mat_mat(&yaw, &lean);
        let relative = mat_mat(&yaw_lean, &about(1, q[4]));
        let up = mat_vec(&yaw_lean, [z, z, T::from(p.r)]);
        let centre_t = add([q[0], q[1], z], up);
        // ω_rel = ψ̇ e_z + R_z φ̇ e_x + R_z R_x θ̇ e_y, in the table's axes.
        let heading_rate = add([z, z, qd[2]], mat_vec(&yaw, [qd[3], z, z]));
        let omega_rel = add(heading_rate, mat_vec(&yaw_lean, [z, qd[4], z]));
        let centre_rate_t = add([qd[0], qd[1], z], cross(heading_rate, up));
        let centre = mat_vec(&table, centre_t);
        let velocity = add(cross(table_spin, centre), mat_vec(&table, centre_rate_t));
        let omega = add(table_spin, mat_vec(&table, omega_rel));
        let axle = mat_vec(&mat_mat(&table, &relative), [z, T::one(), z]);
        (centre, velocity, omega, axle)
    }
}

impl Multipliers<5> for TurntableByHand<'_> {
    const P: usize = 2;

    fn lagrangian<T: Real>(&self, t: T, q: &[T; 5], qd: &[T; 5]) -> T {
        let p = self.0;
        let (centre, velocity, omega, axle) = self.kinematics(t, q, qd);
        let (a, c) = (p.m * p.r * p.r / 4.0, p.m * p.r * p.r / 2.0);
        let along = dot(omega, axle);
        let rotation = (dot(omega, omega) - along * along) * a + along * along * c;
        (dot(velocity, velocity) * p.m + rotation) * 0.5 - centre[2] * (p.m * p.g)
    }

    fn rows<T: Real>(&self, _t: T, q: &[T; 5], qd: &[T; 5]) -> [T; 5] {
        let p = self.0;
        let z = T::zero();
        let (yaw, lean) = (about(2, q[2]), about(0, q[3]));
        let yaw_lean = mat_mat(&yaw, &lean);
        let up = mat_vec(&yaw_lean, [z, z, T::from(p.r)]);
        let heading_rate = add([z, z, qd[2]], mat_vec(&yaw, [qd[3], z, z]));
        let omega_rel = add(heading_rate, mat_vec(&yaw_lean, [z, qd[4], z]));
        let centre_rate = add([qd[0], qd[1], z], cross(heading_rate, up));
        let down = [-up[0], -up[1], -up[2]];
        let slip = add(centre_rate, cross(omega_rel, down));
        [slip[0], slip[1], qd[2], qd[3], qd[4]]
    }

    fn forces(&self, _t: f64, _q: &[f64; 5], _qd: &[f64; 5], _u: &[f64]) -> [f64; 5] {
        [0.0; 5]
    }
}

/// The disk on a tilted, turning table: q̇ and ẇ of both models (the contact found from the
/// disk's shape, and written) against Lagrange's equations with multipliers for the
/// kinematics written by hand, at random states and times; then a run.
#[test]
fn a_disk_on_a_tilted_turntable_moves_as_lagranges_equations_with_multipliers_say() {
    let disk = TurntableDisk {
        m: 0.4,
        r: 0.15,
        g: 9.81,
        tilt: 0.3,
        spin: 2.0,
    };
    let written = TurntableDiskWritten {
        m: disk.m,
        r: disk.r,
        g: disk.g,
        tilt: disk.tilt,
        spin: disk.spin,
    };
    let by_hand = TurntableByHand(&disk);
    let mut worst = 0.0f64;
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut random = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for _ in 0..50 {
        let t = 3.0 * random();
        let q = [
            random(),
            random(),
            3.0 * random(),
            0.8 * random(),
            3.0 * random(),
        ];
        let w = [5.0 * random(), 2.0 * random(), 20.0 * random()];
        let r = reference(&by_hand, t, &q, &w, &[]);
        let expected: Vec<f64> =
            r.qd.iter()
                .chain(r.omega_dot.iter().skip(2))
                .copied()
                .collect();
        let x: [f64; 8] = std::array::from_fn(|i| if i < 5 { q[i] } else { w[i - 5] });
        let (mut a, mut b) = ([0.0; 8], [0.0; 8]);
        disk.rhs(t, &x, &[], &mut a).unwrap();
        written.rhs(t, &x, &[], &mut b).unwrap();
        for got in [a, b] {
            let err = normwise(&got, &expected);
            assert!(
                err < 1e-11,
                "{err:e} at t = {t}, x = {x:?}: {got:?} against {expected:?}"
            );
            worst = worst.max(err);
        }
    }
    let x0 = disk
        .state_builder()
        .set("x", 0.2)
        .set("spin_rate", 15.0)
        .set("yaw_rate", 1.0)
        .build()
        .unwrap();
    let run = Simulation::new(&disk, x0)
        .end_time(1.0)
        .run_constant(&DormandPrince::new(1e-10, 1e-12), [])
        .unwrap();
    let summary = run.summary();
    assert!(summary.max_constraint_residual < 1e-12, "{summary}");
    assert!(summary.relative_energy_balance < 1e-8, "{summary}");
    println!(
        "disk on a tilted turntable against the multiplier system: worst {worst:.1e}; a run of \
         1 s: energy balance {:.1e}",
        summary.relative_energy_balance
    );
}

// ---------------------------------------------------------------------------------------
// 4. A ball in a bowl and on a sphere
// ---------------------------------------------------------------------------------------
//
// A ball of radius r, mass m and moment of inertia I about every axis (a homogeneous ball has
// I = 2mr²/5), oriented by a quaternion, its centre (x, y, z), rolling on a sphere of radius
// R about O. With u the unit vector from O to the ball's centre and F the contact force,
// Newton–Euler give m v̇ = F + m g and I ω̇ = (P − c) × F, P − c = ±r u (+ in a bowl, − on a
// sphere). Hence (Routh, Advanced Rigid Dynamics, the sphere rolling on a sphere; Borisov &
// Mamaev, Regul. Chaotic Dyn. 7, 2002, for the ball with spherical inertia):
//
// * ω·u is constant: ω̇ ⊥ u, and u̇ ∝ u × ω ⊥ ω;
// * about the vertical through O, K = e_z·[m (c − O) × v + I (1 ∓ R/r) ω] is constant: the
//   torque about O of the contact force, R u × F, is ±(R/r) I ω̇, and gravity's has no
//   vertical part;
// * and the energy.
//
// In the bowl, the centre can circle at a polar angle θ from the bottom at a rate Ω: with
// ρ = R − r, ω = (s − ρΩ cos θ/r) u − (ρΩ/r) e_z, and Euler's equation in the direction of
// motion gives I Ω (s − ρΩ cos θ/r) = m r (ρ Ω² cos θ − g) for the spin about the normal
// s = ω·u (without inertia, I = 0, the conical pendulum ρ Ω² cos θ = g).

/// The ball in a bowl of radius `bowl` whose lowest point is the origin.
#[hamel_system]
pub struct BowlBall {
    pub m: f64,
    pub r: f64,
    pub i: f64,
    pub bowl: f64,
    pub g: f64,
}

#[hamel_system(coordinates(x, y, z, qw, qx, qy, qz), speeds(wx, wy, wz))]
impl BowlBall {
    #[bodies]
    fn bodies(&self, q: &[f64; 7]) -> [Body; 1] {
        let orientation = Rotation3::from_quaternion(q[3], q[4], q[5], q[6]);
        let inertia = Inertia::principal(self.i, self.i, self.i);
        let ball = Body::new(self.m, inertia, Vector3::new(q[0], q[1], q[2]), orientation);
        [ball.with_shape(Shape::sphere(self.r))]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    /// The quaternion's length does not change: the orientation does not see it.
    #[constraints]
    fn unit(&self, q: &[f64; 7], qd: &[f64; 7]) -> [f64; 1] {
        [q[3] * qd[3] + q[4] * qd[4] + q[5] * qd[5] + q[6] * qd[6]]
    }

    #[contacts(determines(z))]
    fn contacts(&self, q: &[f64; 7]) -> [Contact; 1] {
        let [ball] = self.bodies(q);
        let bowl = Surface::bowl(Vector3::new(0.0, 0.0, self.bowl), self.bowl);
        [Contact::rolling(ball, bowl)]
    }

    #[quasi_velocities]
    fn spin(&self, q: &[f64; 7], _qd: &[f64; 7]) -> [f64; 3] {
        let [ball] = self.bodies(q);
        angular_velocity!(ball.orientation).to_array()
    }
}

/// The ball held to a fixed sphere of radius `sphere` about the origin, hanging below it (the
/// contact is bilateral).
#[hamel_system]
pub struct SphereBall {
    pub m: f64,
    pub r: f64,
    pub i: f64,
    pub sphere: f64,
    pub g: f64,
}

#[hamel_system(coordinates(x, y, z, qw, qx, qy, qz), speeds(wx, wy, wz))]
impl SphereBall {
    #[bodies]
    fn bodies(&self, q: &[f64; 7]) -> [Body; 1] {
        let orientation = Rotation3::from_quaternion(q[3], q[4], q[5], q[6]);
        let inertia = Inertia::principal(self.i, self.i, self.i);
        let ball = Body::new(self.m, inertia, Vector3::new(q[0], q[1], q[2]), orientation);
        [ball.with_shape(Shape::sphere(self.r))]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    #[constraints]
    fn unit(&self, q: &[f64; 7], qd: &[f64; 7]) -> [f64; 1] {
        [q[3] * qd[3] + q[4] * qd[4] + q[5] * qd[5] + q[6] * qd[6]]
    }

    #[contacts(determines(z))]
    fn contacts(&self, q: &[f64; 7]) -> [Contact; 1] {
        let [ball] = self.bodies(q);
        [Contact::rolling(
            ball,
            Surface::sphere(Vector3::zeros(), self.sphere),
        )]
    }

    #[quasi_velocities]
    fn spin(&self, q: &[f64; 7], _qd: &[f64; 7]) -> [f64; 3] {
        let [ball] = self.bodies(q);
        angular_velocity!(ball.orientation).to_array()
    }
}

/// The three integrals at a state: energy, ω·u and K (`sign` +1 in a bowl, −1 on a sphere).
fn ball_integrals<S: HamelSystem<State = [f64; 10], Coordinates = [f64; 7]>>(
    model: &S,
    x: &[f64; 10],
    (m, r, i, big_r, centre): (f64, f64, f64, f64, Vector3),
    sign: f64,
) -> [f64; 3] {
    let qd = model.generalized_velocities(0.0, x).unwrap();
    let c = Vector3::new(x[0], x[1], x[2]);
    let (v, omega) = (
        Vector3::new(qd[0], qd[1], qd[2]),
        Vector3::new(x[7], x[8], x[9]),
    );
    let u = (c - centre).normalize();
    let k = m * (c - centre).cross(&v).z + i * (1.0 - sign * big_r / r) * omega.z;
    [model.energy(0.0, x).unwrap(), omega.dot(&u), k]
}

/// A run's largest change of each integral, relative to its own scale.
fn integral_drift(rows: &[[f64; 3]], scales: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|k| {
        rows.iter()
            .map(|row| (row[k] - rows[0][k]).abs() / scales[k])
            .fold(0.0, f64::max)
    })
}

/// The centre circling at polar angle θ from the bowl's bottom, rate Ω, with the closed
/// form's spin: it keeps its height and its rate, and the integrals hold; a state off the
/// closed form's spin does not circle.
#[test]
fn a_ball_in_a_bowl_circles_steadily_at_the_closed_forms_spin_and_keeps_its_integrals() {
    let ball = BowlBall {
        m: 0.3,
        r: 0.05,
        i: 0.4 * 0.3 * 0.05 * 0.05,
        bowl: 0.5,
        g: 9.81,
    };
    let (theta, rate) = (0.6f64, 6.0f64);
    let rho = ball.bowl - ball.r;
    let bottom = Vector3::new(0.0, 0.0, ball.bowl);
    let spin = rho * rate * theta.cos() / ball.r
        + ball.m * ball.r * (rho * rate * rate * theta.cos() - ball.g) / (ball.i * rate);
    let start = |spin: f64| {
        let u = Vector3::new(theta.sin(), 0.0, -theta.cos());
        let c = bottom + rho * u;
        let omega =
            (spin - rho * rate * theta.cos() / ball.r) * u - (rho * rate / ball.r) * Vector3::z();
        let q = [c.x, c.y, c.z, 1.0, 0.0, 0.0, 0.0];
        ball.state_from_speeds(0.0, &q, &omega.to_array()).unwrap()
    };
    let period = 2.0 * PI / rate;
    let run = |x0| {
        Simulation::new(&ball, x0)
            .end_time(3.0 * period)
            .sample_interval(period / 50.0)
            .run_constant(&DormandPrince::new(1e-12, 1e-14), [])
            .unwrap()
    };
    let steady = run(start(spin));
    let mut worst_path = 0.0f64;
    for row in steady.rows() {
        let t = row[0];
        let expected = bottom
            + rho
                * Vector3::new(
                    theta.sin() * (rate * t).cos(),
                    theta.sin() * (rate * t).sin(),
                    -theta.cos(),
                );
        worst_path = worst_path.max((Vector3::new(row[1], row[2], row[3]) - expected).norm() / rho);
    }
    let parameters = (ball.m, ball.r, ball.i, ball.bowl, bottom);
    let rows: Vec<[f64; 3]> = steady
        .rows()
        .map(|row| {
            let x: [f64; 10] = std::array::from_fn(|k| row[k + 1]);
            ball_integrals(&ball, &x, parameters, 1.0)
        })
        .collect();
    let drift = integral_drift(&rows, rows[0].map(|v| v.abs().max(1e-3)));
    println!(
        "ball in a bowl, steady circle at θ = {theta}, Ω = {rate} (spin {spin:.6}): the centre \
         off the closed form's circle by {worst_path:.1e} of ρ over 3 turns; energy, ω·u, K \
         drift {:?}; constraint residual {:.1e}",
        drift.map(|d| format!("{d:.1e}")),
        steady.summary().max_constraint_residual
    );
    assert!(worst_path < 1e-8, "{worst_path:e}");
    assert!(drift.iter().all(|&d| d < 1e-9), "{drift:?}");
    // With a spin 5 % off, the ball leaves the circle.
    let off = run(start(1.05 * spin));
    let heights = off.column("z").unwrap();
    let moved = heights
        .iter()
        .map(|z| (z - heights[0]).abs())
        .fold(0.0, f64::max);
    assert!(moved > 1e-3 * rho, "{moved}");
}

/// A ball hanging below a fixed sphere, set rolling and spinning: energy, ω·u and K kept.
#[test]
fn a_ball_on_a_sphere_keeps_its_energy_its_spin_about_the_normal_and_its_area_integral() {
    let ball = SphereBall {
        m: 0.3,
        r: 0.05,
        i: 0.4 * 0.3 * 0.05 * 0.05,
        sphere: 0.4,
        g: 9.81,
    };
    let rho = ball.sphere + ball.r;
    let u = Vector3::new(0.3f64.sin(), 0.0, -0.3f64.cos());
    let c = rho * u;
    let q = [c.x, c.y, c.z, 1.0, 0.0, 0.0, 0.0];
    let x0 = ball.state_from_speeds(0.0, &q, &[4.0, -7.0, 15.0]).unwrap();
    let run = Simulation::new(&ball, x0)
        .end_time(5.0)
        .sample_interval(0.01)
        .run_constant(&DormandPrince::new(1e-12, 1e-14), [])
        .unwrap();
    let parameters = (ball.m, ball.r, ball.i, ball.sphere, Vector3::zeros());
    let rows: Vec<[f64; 3]> = run
        .rows()
        .map(|row| {
            let x: [f64; 10] = std::array::from_fn(|k| row[k + 1]);
            ball_integrals(&ball, &x, parameters, -1.0)
        })
        .collect();
    let drift = integral_drift(&rows, rows[0].map(|v| v.abs().max(1e-3)));
    let swing = run
        .column("x")
        .unwrap()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    println!(
        "ball on a sphere, 5 s: energy, ω·u, K drift {:?}; the centre swings {swing:.3} \
         m from the axis",
        drift.map(|d| format!("{d:.1e}"))
    );
    assert!(swing > 0.1, "{swing}");
    assert!(drift.iter().all(|&d| d < 1e-9), "{drift:?}");
}

// ---------------------------------------------------------------------------------------
// 5. Chaplygin's ball by its body rates, and by a quaternion
// ---------------------------------------------------------------------------------------

/// The catalogue's Chaplygin ball (Euler angles about y, z and y) with its body rates as
/// speeds.
#[hamel_system]
pub struct ChaplyginRates {
    pub m: f64,
    pub r: f64,
    pub i1: f64,
    pub i2: f64,
    pub i3: f64,
}

#[hamel_system(coordinates(x, y, alpha, beta, gamma), speeds(w1, w2, w3))]
impl ChaplyginRates {
    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
        let orientation =
            Rotation3::about_y(q[2]) * Rotation3::about_z(q[3]) * Rotation3::about_y(q[4]);
        let inertia = Inertia::principal(self.i1, self.i2, self.i3);
        let ball = Body::new(
            self.m,
            inertia,
            Vector3::new(q[0], q[1], self.r),
            orientation,
        );
        [ball.with_shape(Shape::sphere(self.r))]
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        let [ball] = self.bodies(q);
        [Contact::rolling(ball, Surface::ground())]
    }

    #[quasi_velocities]
    fn rates(&self, q: &[f64; 5], _qd: &[f64; 5]) -> [f64; 3] {
        let [ball] = self.bodies(q);
        body_rates!(ball.orientation).to_array()
    }
}

/// Chaplygin's ball oriented by a quaternion, its body rates as speeds: no orientation is
/// singular.
#[hamel_system]
pub struct ChaplyginQuaternion {
    pub m: f64,
    pub r: f64,
    pub i1: f64,
    pub i2: f64,
    pub i3: f64,
}

#[hamel_system(
    coordinates(x, y, qw, qx, qy, qz),
    speeds(w1, w2, w3),
    constraints(unit, slip_x, slip_y)
)]
impl ChaplyginQuaternion {
    #[bodies]
    fn bodies(&self, q: &[f64; 6]) -> [Body; 1] {
        let orientation = Rotation3::from_quaternion(q[2], q[3], q[4], q[5]);
        let inertia = Inertia::principal(self.i1, self.i2, self.i3);
        let ball = Body::new(
            self.m,
            inertia,
            Vector3::new(q[0], q[1], self.r),
            orientation,
        );
        [ball.with_shape(Shape::sphere(self.r))]
    }

    #[constraints]
    fn unit(&self, q: &[f64; 6], qd: &[f64; 6]) -> [f64; 1] {
        [q[2] * qd[2] + q[3] * qd[3] + q[4] * qd[4] + q[5] * qd[5]]
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 6]) -> [Contact; 1] {
        let [ball] = self.bodies(q);
        [Contact::rolling(ball, Surface::ground())]
    }

    #[quasi_velocities]
    fn rates(&self, q: &[f64; 6], _qd: &[f64; 6]) -> [f64; 3] {
        let [ball] = self.bodies(q);
        body_rates!(ball.orientation).to_array()
    }
}

/// q̈ of a model at a state: the rows of its Jacobian for q̇ applied to its right-hand side
/// (dual numbers: exact to rounding).
fn accelerations<S: HamelSystem<State = [f64; 8], Inputs = [f64; 0], StateJacobian = [f64; 64]>>(
    model: &S,
    x: &[f64; 8],
) -> [f64; 5] {
    let mut dx = [0.0; 8];
    model.rhs(0.0, x, &[], &mut dx).unwrap();
    let (jacobian, _) = model.jacobian(0.0, x, &[]).unwrap();
    std::array::from_fn(|i| (0..8).map(|k| jacobian[8 * i + k] * dx[k]).sum())
}

/// The same motion: at random configurations and velocities, both models give the same q̇
/// and q̈ (to rounding), so they are the same second-order equations in q; and a run of each
/// from the same start stays together.
#[test]
fn chaplygins_ball_by_its_body_rates_moves_as_by_its_euler_angle_rates() {
    let euler = ChaplyginBall::default();
    let rates = ChaplyginRates {
        m: euler.m,
        r: euler.r,
        i1: euler.i1,
        i2: euler.i2,
        i3: euler.i3,
    };
    let mut worst = 0.0f64;
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut random = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for _ in 0..100 {
        let q = [
            random(),
            random(),
            3.0 * random(),
            1.2 + random(),
            3.0 * random(),
        ];
        let angles = [5.0 * random(), 5.0 * random(), 5.0 * random()];
        let by_euler = euler.state_from_speeds(0.0, &q, &angles).unwrap();
        let qd = euler.generalized_velocities(0.0, &by_euler).unwrap();
        let by_rates = rates.state_from_velocities(0.0, &q, &qd).unwrap();
        let (a, b) = (
            rates.generalized_velocities(0.0, &by_rates).unwrap(),
            accelerations(&rates, &by_rates),
        );
        let (c, d) = (qd, accelerations(&euler, &by_euler));
        let err = normwise(&a, &c).max(normwise(&b, &d));
        assert!(
            err < 1e-12,
            "{err:e} at q = {q:?}: q̈ {b:?} against {d:?}",
            b = &b[..],
            d = &d[..]
        );
        worst = worst.max(err);
    }
    let x0 = euler
        .state_builder()
        .set("beta", 1.2)
        .set("alpha_rate", 6.0)
        .set("beta_rate", 1.5)
        .set("gamma_rate", -1.0)
        .build()
        .unwrap();
    let q: [f64; 5] = std::array::from_fn(|i| x0[i]);
    let qd = euler.generalized_velocities(0.0, &x0).unwrap();
    let y0 = rates.state_from_velocities(0.0, &q, &qd).unwrap();
    let integrator = DormandPrince::new(1e-13, 1e-15);
    let run = |model: &dyn Fn() -> Trajectory| model();
    let a = run(&|| {
        Simulation::new(&euler, x0)
            .end_time(1.0)
            .sample_interval(0.1)
            .run_constant(&integrator, [])
            .unwrap()
    });
    let b = run(&|| {
        Simulation::new(&rates, y0)
            .end_time(1.0)
            .sample_interval(0.1)
            .run_constant(&integrator, [])
            .unwrap()
    });
    let apart = ["x", "y", "alpha", "beta", "gamma"]
        .iter()
        .map(|c| normwise(a.column(c).unwrap(), b.column(c).unwrap()))
        .fold(0.0, f64::max);
    println!(
        "Chaplygin's ball by body rates against Euler-angle rates: q̇ and q̈ at 100 states, \
         worst {worst:.1e}; two runs of 1 s at rtol 1e-13 apart by {apart:.1e}"
    );
    assert!(apart < 1e-12, "{apart:e}");
}

/// The ball's integrals from the quaternion form's state: energy, Jellett's ⟨M, γ⟩ and |M|²,
/// M = I ω + m r² (ω − ⟨ω, γ⟩ γ) about the contact point (γ = e_z).
fn quaternion_ball_integrals(ball: &ChaplyginQuaternion, x: &[f64; 9]) -> [f64; 3] {
    let r = Rotation3::from_quaternion(x[2], x[3], x[4], x[5]);
    let body = Vector3::new(x[6], x[7], x[8]);
    let omega = r * body;
    let spin = r * Vector3::new(ball.i1 * body.x, ball.i2 * body.y, ball.i3 * body.z);
    let m = spin + ball.m * ball.r * ball.r * (omega - omega.z * Vector3::z());
    [ball.energy(0.0, x).unwrap(), m.z, m.norm_squared()]
}

/// The catalogue's rolling disk lying flat (φ = π/2), where its yaw and spin turn about one
/// axis: its orientation is written through a `let` (`heading = about_z(ψ) * about_x(φ)`,
/// then `heading * about_y(θ)`). Before, only three turns written in one product were
/// found, and a run started there said the mass matrix was singular, as if the disk's
/// kinetic energy were wrong; the message names the orientation's singularity and the
/// quaternion.
#[test]
fn the_rolling_disk_lying_flat_is_at_its_orientations_singularity() {
    let disk = hamel::models::RollingDisk::default();
    let run = disk
        .state_from_speeds(0.0, &[0.0, 0.0, 0.0, PI / 2.0, 0.0], &[1.0, 0.0, 1.0])
        .and_then(|x| {
            Simulation::new(&disk, x)
                .end_time(0.1)
                .run_constant(&DormandPrince::new(1e-9, 1e-9), [])
        });
    let e = run.unwrap_err();
    assert!(matches!(e, Error::SingularOrientation { .. }), "{e}");
    let message = e.to_string();
    assert!(
        message.contains("`about_z(psi) * about_x(phi) * about_y(theta)` is at its singularity")
            && message.contains("Rotation3::from_quaternion(w, x, y, z)"),
        "{message}"
    );
}

/// Started with its body's y axis along the ground's — where the catalogue's Euler angles
/// are singular, and its model cannot start — and turning about a tilted axis, the ball
/// oriented by a quaternion runs through that orientation and far from it, its integrals
/// kept.
#[test]
fn chaplygins_ball_by_a_quaternion_runs_through_the_euler_angles_singularity() {
    let catalogue = ChaplyginBall::default();
    let ball = ChaplyginQuaternion {
        m: catalogue.m,
        r: catalogue.r,
        i1: catalogue.i1,
        i2: catalogue.i2,
        i3: catalogue.i3,
    };
    let x0 = ball
        .state_from_speeds(0.0, &[0.0, 0.0, 1.0, 0.0, 0.0, 0.0], &[3.0, 5.0, -2.0])
        .unwrap();
    let singular = catalogue.state_from_speeds(0.0, &[0.0; 5], &[1.0, 1.0, 1.0]);
    let euler_run = singular.and_then(|x| {
        Simulation::new(&catalogue, x)
            .end_time(1.0)
            .run_constant(&DormandPrince::new(1e-9, 1e-9), [])
    });
    // The Euler angles are singular at β = 0. Before, the message suggested checking the
    // kinetic energy (with the angles' rates as speeds) or choosing other quasi-velocities
    // (with the body rates): it names the orientation's singularity and the quaternion.
    let rates = ChaplyginRates {
        m: catalogue.m,
        r: catalogue.r,
        i1: catalogue.i1,
        i2: catalogue.i2,
        i3: catalogue.i3,
    };
    let by_rates = rates
        .state_from_speeds(0.0, &[0.0; 5], &[1.0, 1.0, 1.0])
        .and_then(|x| {
            Simulation::new(&rates, x)
                .end_time(1.0)
                .run_constant(&DormandPrince::new(1e-9, 1e-9), [])
        });
    for e in [euler_run.unwrap_err(), by_rates.unwrap_err()] {
        assert!(matches!(e, Error::SingularOrientation { .. }), "{e}");
        let message = e.to_string();
        assert!(
            message.contains(
                "`about_y(alpha) * about_z(beta) * about_y(gamma)` is at its singularity"
            ) && message.contains("Rotation3::from_quaternion(w, x, y, z)"),
            "{message}"
        );
    }
    // Away from it, nothing is said of it.
    let tilted = catalogue
        .state_from_speeds(0.0, &[0.0, 0.0, 0.0, 0.3, 0.0], &[1.0, 1.0, 1.0])
        .unwrap();
    assert!(
        Simulation::new(&catalogue, tilted)
            .end_time(0.1)
            .run_constant(&DormandPrince::new(1e-9, 1e-9), [])
            .is_ok()
    );
    let run = Simulation::new(&ball, x0)
        .end_time(20.0)
        .sample_interval(0.01)
        .run_constant(&DormandPrince::new(1e-12, 1e-14), [])
        .unwrap();
    let rows: Vec<[f64; 3]> = run
        .rows()
        .map(|row| quaternion_ball_integrals(&ball, &std::array::from_fn(|k| row[k + 1])))
        .collect();
    let drift = integral_drift(&rows, rows[0].map(f64::abs));
    // The angle β between the body's y axis and the ground's, the Euler angles' middle one.
    let beta: Vec<f64> = run
        .rows()
        .map(|row| {
            let r = Rotation3::from_quaternion(row[3], row[4], row[5], row[6]);
            (r * Vector3::y())
                .dot(&Vector3::y())
                .clamp(-1.0, 1.0)
                .acos()
        })
        .collect();
    let (near, far) = (
        beta[1..].iter().copied().fold(f64::INFINITY, f64::min),
        beta.iter().copied().fold(0.0, f64::max),
    );
    println!(
        "Chaplygin's ball by a quaternion, 20 s from β = 0: β back within {near:.1e} of 0 and \
         out to {far:.2}; energy, Jellett, |M|² drift {:?}",
        drift.map(|d| format!("{d:.1e}"))
    );
    assert!(far > 2.5 && near < 0.1, "β in [{near}, {far}]");
    assert!(drift.iter().all(|&d| d < 1e-10), "{drift:?}");
}

// ---------------------------------------------------------------------------------------
// 6. The free asymmetric top
// ---------------------------------------------------------------------------------------

/// A rigid body in no field, oriented by a quaternion, its body rates as speeds.
#[hamel_system]
pub struct FreeTop {
    pub i1: f64,
    pub i2: f64,
    pub i3: f64,
}

#[hamel_system(coordinates(qw, qx, qy, qz), speeds(w1, w2, w3), constraints(unit))]
impl FreeTop {
    #[bodies]
    fn bodies(&self, q: &[f64; 4]) -> [Body; 1] {
        let orientation = Rotation3::from_quaternion(q[0], q[1], q[2], q[3]);
        let inertia = Inertia::principal(self.i1, self.i2, self.i3);
        [Body::new(1.0, inertia, Vector3::zeros(), orientation)]
    }

    #[constraints]
    fn unit(&self, q: &[f64; 4], qd: &[f64; 4]) -> [f64; 1] {
        [q[0] * qd[0] + q[1] * qd[1] + q[2] * qd[2] + q[3] * qd[3]]
    }

    #[quasi_velocities]
    fn rates(&self, q: &[f64; 4], _qd: &[f64; 4]) -> [f64; 3] {
        let [top] = self.bodies(q);
        body_rates!(top.orientation).to_array()
    }
}

/// Jacobi's elliptic functions sn, cn, dn of u for the parameter m = k², by the arithmetic–
/// geometric mean and descending Landen transformation (Abramowitz & Stegun 16.4), the
/// argument first reduced by the period 4K, K = π / (2 AGM(1, √(1 − m))).
fn jacobi(u: f64, m: f64) -> (f64, f64, f64) {
    let (mut a, mut b, mut c) = (vec![1.0], (1.0 - m).sqrt(), vec![m.sqrt()]);
    while c.last().unwrap().abs() > 1e-16 {
        let an = *a.last().unwrap();
        c.push(0.5 * (an - b));
        a.push(0.5 * (an + b));
        b = (an * b).sqrt();
    }
    let n = a.len() - 1;
    let quarter = PI / (2.0 * a[n]);
    let u = u - 4.0 * quarter * (u / (4.0 * quarter)).round();
    let mut phi = 2f64.powi(n as i32) * a[n] * u;
    let mut previous = phi;
    for j in (1..=n).rev() {
        previous = phi;
        phi = 0.5 * (phi + (c[j] / a[j] * phi.sin()).asin());
    }
    (phi.sin(), phi.cos(), phi.cos() / (previous - phi).cos())
}

/// Euler–Poinsot (Landau & Lifshitz, Mechanics §37): for I₁ < I₂ < I₃ and M² > 2EI₂, with
/// Ω₂(0) = 0 and Ω₁(0), Ω₃(0) > 0, Ω₁ = a₁ cn τ, Ω₂ = a₂ sn τ, Ω₃ = a₃ dn τ, τ = λ t.
fn euler_poinsot(top: &FreeTop, start: [f64; 3], t: f64) -> [f64; 3] {
    let (i1, i2, i3) = (top.i1, top.i2, top.i3);
    let e2 = i1 * start[0] * start[0] + i3 * start[2] * start[2];
    let mm = (i1 * start[0]).powi(2) + (i3 * start[2]).powi(2);
    let lambda = ((i3 - i2) * (mm - e2 * i1) / (i1 * i2 * i3)).sqrt();
    let k2 = (i2 - i1) * (e2 * i3 - mm) / ((i3 - i2) * (mm - e2 * i1));
    let (sn, cn, dn) = jacobi(lambda * t, k2);
    [
        ((e2 * i3 - mm) / (i1 * (i3 - i1))).sqrt() * cn,
        ((e2 * i3 - mm) / (i2 * (i3 - i2))).sqrt() * sn,
        ((mm - e2 * i1) / (i3 * (i3 - i1))).sqrt() * dn,
    ]
}

/// How long the free top tumbles: 10³ s in a release build (`cargo test --release -p
/// hamel-validation --test models -- rolling::a_free_top --nocapture`, about 0.2 s of run),
/// 10² s in a debug build, where the thousand seconds take some 10 s of the suite's time.
const TUMBLE: f64 = if cfg!(debug_assertions) {
    100.0
} else {
    1000.0
};

/// The free top tumbles for 10³ s (`TUMBLE`): its body rates follow the closed form to 1e-8
/// (absolute, for rates of order 1), its angular momentum R I Ω stays fixed in space, and
/// every component of its quaternion changes sign — no chart of three angles would have
/// lasted.
#[test]
fn a_free_top_tumbles_for_a_thousand_seconds_as_euler_and_poinsot_say() {
    let (near, far) = ((jacobi(1.0, 0.0).0 - 1f64.sin()).abs(), jacobi(0.0, 0.3));
    assert!(near < 1e-15 && far == (0.0, 1.0, 1.0), "{near} {far:?}");
    let top = FreeTop {
        i1: 1.0,
        i2: 2.0,
        i3: 3.0,
    };
    let start = [1.0, 0.0, 1.0];
    let x0 = top
        .state_from_speeds(0.0, &[1.0, 0.0, 0.0, 0.0], &start)
        .unwrap();
    // The guide quotes the figures of this run with the tolerances they need (before, it
    // quoted 1.9·10⁻¹⁰ without them).
    let guide = include_str!("../../../src/docs/geometry.md").replace('\n', " ");
    assert!(
        guide.contains("DormandPrince::new(1e-14, 1e-14)"),
        "geometry.md does not say the free top's tolerances"
    );
    let run = Simulation::new(&top, x0)
        .end_time(TUMBLE)
        .sample_interval(1.0)
        .run_constant(&DormandPrince::new(1e-14, 1e-14), [])
        .unwrap();
    let momentum = |row: &[f64]| {
        let r = Rotation3::from_quaternion(row[1], row[2], row[3], row[4]);
        r * Vector3::new(top.i1 * row[5], top.i2 * row[6], top.i3 * row[7])
    };
    let rows: Vec<Vec<f64>> = run.rows().collect();
    let first = momentum(&rows[0]);
    let (mut rates, mut drift) = (0.0f64, 0.0f64);
    for row in &rows {
        let expected = euler_poinsot(&top, start, row[0]);
        rates = rates.max(normwise(&row[5..8], &expected));
        drift = drift.max((momentum(row) - first).norm() / first.norm());
    }
    let signs = (1..5).all(|k| rows.iter().any(|r| r[k] > 0.1) && rows.iter().any(|r| r[k] < -0.1));
    let summary = run.summary();
    println!(
        "free top, {TUMBLE} s, {} steps: body rates off Euler–Poinsot by {rates:.1e}, angular \
         momentum in space by {drift:.1e}, energy by {:.1e}",
        summary.steps, summary.relative_energy_drift
    );
    assert!(signs, "every quaternion component changes sign");
    assert!(rates < 1e-8, "{rates:e}");
    assert!(drift < 1e-9, "{drift:e}");
}

// ---------------------------------------------------------------------------------------
// 7. Shared helpers by path; a singularity into a boxed error
// ---------------------------------------------------------------------------------------

mod wheels {
    use hamel::geometry::{Body, Inertia, Rotation3, Shape, Vector3};

    pub struct Wheels;

    #[hamel::helpers]
    impl Wheels {
        /// A coin at (x, y) with yaw, lean and spin q[2..5].
        pub fn coin(m: f64, r: f64, q: &[f64; 5]) -> Body {
            let heading = Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]);
            let centre = Vector3::new(q[0], q[1], 0.0) + heading * Vector3::new(0.0, 0.0, r);
            let diameter = m * r * r / 4.0;
            let inertia = Inertia::principal(diameter, 2.0 * diameter, diameter);
            let body = Body::new(m, inertia, centre, heading * Rotation3::about_y(q[4]));
            body.with_shape(Shape::disk(r, Vector3::y()))
        }
    }
}

/// The catalogue's rolling disk, its helpers named and called by their path, its contact
/// found from its shape.
#[hamel_system]
pub struct PathCoin {
    pub m: f64,
    pub r: f64,
    pub g: f64,
}

#[hamel_system(coordinates(x, y, psi, phi, theta), helpers(wheels::Wheels))]
impl PathCoin {
    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
        [wheels::Wheels::coin(self.m, self.r, q)]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        [Contact::rolling(
            wheels::Wheels::coin(self.m, self.r, q),
            Surface::ground(),
        )]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[2], qd[3], qd[4]]
    }
}

fn coin_rhs(x: &[f64; 8]) -> Result<[f64; 8], Box<dyn std::error::Error>> {
    let coin = PathCoin {
        m: 0.1,
        r: 0.05,
        g: 9.81,
    };
    let mut dx = [0.0; 8];
    coin.rhs(0.0, x, &[], &mut dx)?;
    Ok(dx)
}

/// Helpers called by their path; the disk's rows along its heading and axle give the motion
/// of the catalogue's disk, whose rows are along the ground's axes; a singularity (the coin
/// lying flat) goes into a `Box<dyn Error>` with `?`.
#[test]
fn helpers_by_path_and_a_singularity_as_a_boxed_error() {
    let disk = hamel::models::RollingDisk::default();
    let x = [0.1, 0.2, 0.3, 0.2, 0.0, 1.0, -0.5, 20.0];
    let mut expected = [0.0; 8];
    disk.rhs(0.0, &x, &[], &mut expected).unwrap();
    let got = coin_rhs(&x).unwrap();
    assert!(
        normwise(&got, &expected) < 1e-13,
        "{got:?} against {expected:?}"
    );
    let flat = [0.0, 0.0, 0.0, PI / 2.0, 0.0, 1.0, 0.0, 1.0];
    // Flat, the disk's lowest point is undefined: its rows are not finite numbers.
    let error = coin_rhs(&flat).unwrap_err();
    let singularity = error.downcast_ref::<Singularity>();
    assert!(
        matches!(singularity, Some(Singularity::NonFinite { .. })),
        "{error}"
    );
    assert!(error.to_string().contains("not a finite number"), "{error}");
}
