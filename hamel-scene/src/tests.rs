//! What a scene and a picture carry against what the model says, and every error. The
//! browser test (`tests/browser`) checks that the page draws it.

use std::path::PathBuf;

use base64::Engine as _;

use super::*;
use hamel::geometry::{Body, Contact, Inertia, Mechanism, Rotation3, Shape, Surface, Vector3};
use hamel::models::KnifeEdge;
use hamel::{DormandPrince, HamelSystem, Simulation, Trajectory, hamel_system};

/// A fresh directory for one test's files.
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hamel-scene-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A wheel on an axle that carries a pendulum: a rolling disk (yaw ψ, lean φ, spin θ about
/// the axle y, z up) with a rod hanging from its centre, swinging with the lean. Its second
/// body's inertia is `rod` (a thin rod along its z axis by default).
#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct Penny {
    pub m: f64,
    pub r: f64,
    pub g: f64,
    pub rod_mass: f64,
    pub rod_length: f64,
    pub rod_ixx: f64,
    pub rod_izz: f64,
}

impl Default for Penny {
    fn default() -> Self {
        Penny {
            m: 0.1,
            r: 0.05,
            g: 9.81,
            rod_mass: 0.02,
            rod_length: 0.04,
            rod_ixx: 0.02 * 0.04 * 0.04 / 12.0,
            rod_izz: 0.0,
        }
    }
}

#[hamel_system(
    coordinates(x, y, psi, phi, theta),
    speeds(yaw_rate, lean_rate, spin_rate),
    constraints(slip_x, slip_y),
    bodies(disk, rod),
    units(t = "s", phi = "rad", spin_rate = "rad/s")
)]
impl Penny {
    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [Body; 2] {
        let heading = Rotation3::about_z(q[2]) * Rotation3::about_x(q[3]);
        let centre = Vector3::new(q[0], q[1], 0.0) + heading * Vector3::new(0.0, 0.0, self.r);
        let (diameter, axle) = (
            self.m * self.r * self.r / 4.0,
            self.m * self.r * self.r / 2.0,
        );
        [
            Body::new(
                self.m,
                Inertia::principal(diameter, axle, diameter),
                centre,
                heading * Rotation3::about_y(q[4]),
            ),
            Body::new(
                self.rod_mass,
                Inertia::principal(self.rod_ixx, self.rod_ixx, self.rod_izz),
                centre + heading * Vector3::new(0.0, 0.0, -0.5 * self.rod_length),
                heading,
            ),
        ]
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        let [disk, _] = self.bodies(q);
        [Contact::ground(disk, Vector3::new(q[0], q[1], 0.0))]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[2], qd[3], qd[4]]
    }
}

/// The penny rolling and leaning for `seconds`, sampled at 60 per second.
fn penny_run(penny: &Penny, seconds: f64) -> Trajectory {
    let x0 = penny
        .state_builder()
        .set("phi", 0.2)
        .set("spin_rate", -15.0)
        .set("yaw_rate", 2.0)
        .build()
        .unwrap();
    Simulation::new(penny, x0)
        .end_time(seconds)
        .sample_interval(1.0 / 60.0)
        .run_constant(&DormandPrince::new(1e-8, 1e-10), [])
        .unwrap()
}

/// The page's data object, as text.
fn data_of(html: &str) -> &str {
    let start = html.find(r#"id="hamel-data">"#).unwrap() + r#"id="hamel-data">"#.len();
    &html[start..start + html[start..].find("</script>").unwrap()]
}

/// The base64 string that follows `"key":"` in the data.
fn field<'a>(data: &'a str, key: &str) -> &'a str {
    let marker = format!("\"{key}\":\"");
    let start = data.find(&marker).unwrap() + marker.len();
    &data[start..start + data[start..].find('"').unwrap()]
}

fn floats32(base64: &str) -> Vec<f64> {
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(base64)
        .unwrap();
    bytes
        .chunks_exact(4)
        .map(|c| f64::from(f32::from_le_bytes(c.try_into().unwrap())))
        .collect()
}

fn floats64(base64: &str) -> Vec<f64> {
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(base64)
        .unwrap();
    bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

#[test]
fn the_page_carries_every_sample_as_computed() {
    let penny = Penny::default();
    let run = penny_run(&penny, 0.5);
    let html = Scene::new(&penny, &run)
        .unwrap()
        .show(["phi", "spin_rate"])
        .to_html()
        .unwrap();
    let data = data_of(&html);
    let times = floats64(field(data, "times"));
    assert_eq!(times, run.times());
    let poses = floats32(field(data, "poses"));
    let points = floats32(field(data, "points"));
    let values = floats64(field(data, "values"));
    assert_eq!(poses.len(), run.len() * 2 * 7);
    assert_eq!(points.len(), run.len() * 3);
    let names = Penny::COORDINATES;
    for i in 0..run.len() {
        let q: [f64; 5] = core::array::from_fn(|k| run.column(names[k]).unwrap()[i]);
        let bodies = penny.bodies_at(times[i], &q);
        for (b, body) in bodies.iter().enumerate() {
            let pose = &poses[(i * 2 + b) * 7..(i * 2 + b + 1) * 7];
            for (k, coordinate) in pose[..3].iter().enumerate() {
                assert!(
                    (coordinate - body.centre[k]).abs() < 1e-6,
                    "sample {i}, body {b}"
                );
            }
            // The quaternion turns x as the orientation does.
            let [qx, qy, qz, qw] = [pose[3], pose[4], pose[5], pose[6]];
            let turned_x = Vector3::new(
                1.0 - 2.0 * (qy * qy + qz * qz),
                2.0 * (qx * qy + qz * qw),
                2.0 * (qx * qz - qy * qw),
            );
            assert!((turned_x - body.orientation * Vector3::x()).norm() < 1e-6);
        }
        assert!((points[3 * i] - q[0]).abs() < 1e-6 && (points[3 * i + 1] - q[1]).abs() < 1e-6);
        assert_eq!(values[2 * i], run.column("phi").unwrap()[i]);
        assert_eq!(values[2 * i + 1], run.column("spin_rate").unwrap()[i]);
    }
    // The disk is the wheel its contact runs round; the rod is drawn from its inertia.
    assert!(
        data.contains(r#""solid":{"kind":"disk","radius":0.05"#),
        "{data:.300}"
    );
    assert!(data.contains(r#""kind":"ellipsoid""#));
    assert!(data.contains(
        r#""columns":[{"name":"phi","unit":"rad"},{"name":"spin_rate","unit":"rad/s"}]"#
    ));
    assert!(data.contains(r#""gravity":[0.0,0.0,-9.81]"#));
    assert!(data.contains(r#""up":[-0.0,-0.0,1.0]"#) || data.contains(r#""up":[0.0,0.0,1.0]"#));
}

#[test]
fn a_wheel_is_its_contact_disk_and_a_rod_its_inertia() {
    let penny = Penny::default();
    let q = [0.1, -0.2, 0.3, 0.25, 1.0];
    let looks = look::looks(&snapshot::Snapshot::of(&penny, 0.0, &q).unwrap(), &[]).unwrap();
    let look::Drawn::Disk { radius, axis } = looks[0].solid else {
        panic!("the disk is {:?}", looks[0].solid)
    };
    assert!((radius - 0.05).abs() < 1e-15);
    // The disk's axle is its y axis.
    assert!((axis.y.abs() - 1.0).abs() < 1e-12, "{axis}");
    // The rod: I = m l² / 12 about x and y, none about z: the ellipsoid of the same inertia
    // has semi-axis √(5 · 2 I / (2m)) = l √(5/12) along z (its first principal axis, of the
    // least moment) and none across (drawn a fiftieth as thick).
    let look::Drawn::Ellipsoid { semi_axes, axes } = looks[1].solid else {
        panic!("the rod is {:?}", looks[1].solid)
    };
    let length = penny.rod_length * (5.0f64 / 12.0).sqrt();
    assert!((semi_axes[0] - length).abs() < 1e-12, "{semi_axes:?}");
    assert!((semi_axes[1] - 0.02 * length).abs() < 1e-12);
    assert!((axes[2][0].abs() - 1.0).abs() < 1e-12);
    assert!(looks.iter().all(|l| l.warning.is_none()));
}

#[test]
fn an_impossible_inertia_is_a_warning_and_a_red_marker() {
    let penny = Penny {
        rod_izz: 10.0 * Penny::default().rod_ixx,
        ..Penny::default()
    };
    let q = [0.0; 5];
    let scene_warnings = Picture::new(&penny, 0.0, &q).unwrap().warnings().unwrap();
    assert_eq!(scene_warnings.len(), 1);
    assert!(scene_warnings[0].contains("body `rod`") && scene_warnings[0].contains("triangle"));
    let svg = Picture::new(&penny, 0.0, &q).unwrap().to_svg().unwrap();
    assert!(svg.contains("rod (cannot be drawn from its inertia)"));
    assert!(!svg.contains("NaN"));
}

#[test]
fn bad_input_is_an_error_naming_it_and_writes_nothing() {
    let penny = Penny::default();
    let run = penny_run(&penny, 0.1);
    let dir = scratch("errors");
    // A run of another model: its coordinates are not the penny's.
    let skate = KnifeEdge::default();
    let x0 = skate
        .state_from_speeds(0.0, &[0.0; 3], &[1.0, 0.5])
        .unwrap();
    let other = Simulation::new(&skate, x0)
        .end_time(0.1)
        .run_constant(&DormandPrince::new(1e-8, 1e-10), [])
        .unwrap();
    let err = Scene::new(&penny, &other).err().unwrap();
    assert!(matches!(err.kind(), ErrorKind::MissingCoordinate { name, .. } if name == "psi"));
    assert!(err.to_string().contains("no column `psi`"), "{err}");

    let path = dir.join("scene.html");
    let unknown = Scene::new(&penny, &run).unwrap().show(["phi", "lean"]);
    let err = unknown.write_html(&path).unwrap_err();
    assert!(matches!(err.kind(), ErrorKind::UnknownColumn { name, .. } if name == "lean"));
    assert_eq!(err.path(), Some(path.display().to_string().as_str()));
    let body = Scene::new(&penny, &run)
        .unwrap()
        .shape("wheel", Shape::sphere(0.1));
    let err = body.write_html(&path).unwrap_err();
    assert!(
        err.to_string()
            .contains("no body `wheel`; its bodies are disk, rod")
    );
    let shape = Scene::new(&penny, &run)
        .unwrap()
        .shape("rod", Solid::box_(0.1, -1.0, 0.1));
    let err = shape.write_html(&path).unwrap_err();
    assert!(
        err.to_string()
            .contains("the shape given for body `rod` has the size -1")
    );
    assert!(!path.exists(), "a refused scene wrote its file");

    // A path in a directory that does not exist, and a path that is a directory: the error
    // names the path, and nothing is left behind.
    let scene = Scene::new(&penny, &run).unwrap();
    let missing = dir.join("no such directory").join("scene.html");
    let err = scene.write_html(&missing).unwrap_err();
    assert!(matches!(err.kind(), ErrorKind::Io { .. }));
    assert!(
        err.to_string()
            .starts_with(&format!("cannot write {}", missing.display()))
    );
    let err = scene.write_html(&dir).unwrap_err();
    assert!(err.to_string().contains("cannot replace the file"), "{err}");
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(left.is_empty(), "files left behind: {left:?}");

    // A written scene replaces an older file whole.
    std::fs::write(&path, "old").unwrap();
    scene.write_html(&path).unwrap();
    let html = std::fs::read_to_string(&path).unwrap();
    assert!(html.starts_with("<!doctype html>") && html.trim_end().ends_with("</html>"));
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);

    // Pictures: a configuration that is not finite, and an unknown extension.
    let err = Picture::new(&penny, 0.0, &[0.0, f64::NAN, 0.0, 0.0, 0.0])
        .err()
        .unwrap();
    assert_eq!(
        err.to_string(),
        "cannot make the scene: coordinate `y` is not finite at t = 0"
    );
    let picture = Picture::new(&penny, 0.0, &[0.0; 5]).unwrap();
    let err = picture.save(dir.join("penny.jpg")).unwrap_err();
    assert!(matches!(err.kind(), ErrorKind::UnknownFormat));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn pictures_are_written_in_both_formats() {
    let penny = Penny::default();
    let dir = scratch("pictures");
    let picture = Picture::new(&penny, 0.0, &[0.0, 0.0, 0.0, 0.3, 0.0]).unwrap();
    picture.save(dir.join("penny.svg")).unwrap();
    picture.save(dir.join("penny.PNG")).unwrap();
    let svg = std::fs::read_to_string(dir.join("penny.svg")).unwrap();
    for text in [
        "front, looking along −x",
        "side, looking along y",
        "top, looking along −z",
    ] {
        assert!(svg.contains(text), "no `{text}`");
    }
    assert!(svg.contains("disk") && svg.contains("contacts") && svg.contains("ground"));
    let png = std::fs::read(dir.join("penny.PNG")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Runs `model` from `x0` for `seconds`, sampled at 60 per second.
fn sixty_per_second<M: HamelSystem>(model: &M, x0: M::State, seconds: f64) -> Trajectory {
    Simulation::new(model, x0)
        .end_time(seconds)
        .sample_interval(1.0 / 60.0)
        .project_holonomic(true)
        .run_constant(
            &DormandPrince::new(1e-7, 1e-9),
            <M::Inputs as hamel::Vector>::zeros(),
        )
        .unwrap()
}

/// Every catalogue model with bodies, in a run of `seconds` at 60 samples a second: its
/// name and its scene page.
fn catalogue_pages(seconds: f64) -> Vec<(&'static str, String)> {
    use hamel::models::{ChaplyginBall, MobileRobot, Rattleback, RollingDisk, WhippleBicycle};
    let page = |html: Result<String, SceneError>| html.unwrap();
    let bike = WhippleBicycle::default();
    let ride = bike.state_builder().set("rear_wheel_rate", -4.6 / bike.r_r);
    let bike_run = sixty_per_second(&bike, ride.set("roll_rate", 0.5).build().unwrap(), seconds);
    let disk = RollingDisk::default();
    let x0 = disk
        .state_builder()
        .set("phi", 0.2)
        .set("spin_rate", -10.0)
        .set("yaw_rate", 3.0);
    let disk_run = sixty_per_second(&disk, x0.build().unwrap(), seconds);
    let ball = ChaplyginBall::default();
    let x0 = ball
        .state_builder()
        .set("beta", 1.0)
        .set("alpha_rate", 3.0)
        .set("gamma_rate", 1.0);
    let ball_run = sixty_per_second(&ball, x0.build().unwrap(), seconds);
    let celt = Rattleback::default();
    let x0 = celt
        .state_builder()
        .set("yaw_rate", -3.0)
        .set("roll_rate", 0.1);
    let celt_run = sixty_per_second(&celt, x0.build().unwrap(), seconds);
    let robot = MobileRobot::default();
    let x0 = robot
        .state_builder()
        .set("w4", 0.5)
        .set("w5", 0.4)
        .build()
        .unwrap();
    let robot_run = sixty_per_second(&robot, x0, seconds);
    vec![
        (
            "whipple_bicycle",
            page(Scene::new(&bike, &bike_run).and_then(|s| s.to_html())),
        ),
        (
            "rolling_disk",
            page(Scene::new(&disk, &disk_run).and_then(|s| s.to_html())),
        ),
        (
            "chaplygin_ball",
            page(Scene::new(&ball, &ball_run).and_then(|s| s.to_html())),
        ),
        (
            "rattleback",
            page(Scene::new(&celt, &celt_run).and_then(|s| s.to_html())),
        ),
        (
            "mobile_robot",
            page(Scene::new(&robot, &robot_run).and_then(|s| s.to_html())),
        ),
    ]
}

#[test]
fn every_catalogue_scene_of_ten_seconds_at_sixty_frames_is_under_two_megabytes() {
    for (name, html) in catalogue_pages(10.0) {
        let samples = floats64(field(data_of(&html), "times")).len();
        assert_eq!(samples, 601, "{name}");
        // The sizes, with `-- --nocapture`.
        println!("{name}: {} bytes for {samples} samples", html.len());
        assert!(html.len() <= 2_000_000, "{name}: {} bytes", html.len());
    }
}

#[test]
fn catalogue_bodies_are_drawn_as_what_they_are() {
    use hamel::models::{ChaplyginBall, MobileRobot, Rattleback, RollingDisk, WhippleBicycle};
    fn solids<M: Mechanism>(model: &M) -> Vec<look::Drawn> {
        let q = model
            .assemble(0.0, &<M::Coordinates as hamel::Vector>::zeros())
            .unwrap();
        let snapshot = snapshot::Snapshot::of(model, 0.0, &q).unwrap();
        look::looks(&snapshot, &[])
            .unwrap()
            .into_iter()
            .map(|l| l.solid)
            .collect()
    }
    let disk = |solid: &look::Drawn, r: f64| {
        let look::Drawn::Disk { radius, axis } = solid else {
            return false;
        };
        (radius - r).abs() < 1e-12 && (axis.y.abs() - 1.0).abs() < 1e-12
    };
    let bike = solids(&WhippleBicycle::default());
    assert!(disk(&bike[0], 0.3) && disk(&bike[3], 0.35), "{bike:?}");
    assert!(
        matches!(bike[1], look::Drawn::Ellipsoid { .. })
            && matches!(bike[2], look::Drawn::Ellipsoid { .. })
    );
    assert!(disk(&solids(&RollingDisk::default())[0], 0.05));
    let ball = solids(&ChaplyginBall::default());
    assert!(
        matches!(ball[0], look::Drawn::Sphere { radius } if (radius - 0.1).abs() < 1e-12),
        "{ball:?}"
    );
    // The rattleback's base is a paraboloid: its contact point's distance from the centre
    // varies, so it is drawn from its inertia.
    let celt = solids(&Rattleback::default());
    assert!(matches!(celt[0], look::Drawn::Ellipsoid { .. }), "{celt:?}");
    // The robot's wheels are given their shape in the model: drawn as it, not inferred.
    let robot = MobileRobot::default();
    let q = robot.assemble(0.0, &[0.0; 5]).unwrap();
    let looks = look::looks(&snapshot::Snapshot::of(&robot, 0.0, &q).unwrap(), &[]).unwrap();
    assert!(
        disk(&looks[1].solid, 0.1) && disk(&looks[2].solid, 0.1),
        "{looks:?}"
    );
    assert_eq!(looks[1].description, "disk of radius 0.1, its shape");
    assert!(matches!(looks[0].solid, look::Drawn::Ellipsoid { .. }));
}

/// The catalogue's models with bodies, each in its reference configuration (q = 0, the
/// dependent coordinates assembled): its name in the guide and its picture, as drawn now.
fn catalogue_pictures() -> Vec<(&'static str, String)> {
    use hamel::models::{ChaplyginBall, MobileRobot, Rattleback, RollingDisk, WhippleBicycle};
    fn svg<M: Mechanism>(model: &M) -> String {
        let q = model
            .assemble(0.0, &<M::Coordinates as hamel::Vector>::zeros())
            .unwrap();
        Picture::new(model, 0.0, &q)
            .unwrap()
            .size(1200, 420)
            .to_svg()
            .unwrap()
    }
    vec![
        ("WhippleBicycle", svg(&WhippleBicycle::default())),
        ("RollingDisk", svg(&RollingDisk::default())),
        ("ChaplyginBall", svg(&ChaplyginBall::default())),
        ("Rattleback", svg(&Rattleback::default())),
        ("MobileRobot", svg(&MobileRobot::default())),
        (
            "a disk on an incline",
            Picture::new(&incline_disk(), 0.0, &ON_THE_INCLINE)
                .unwrap()
                .size(1200, 420)
                .to_svg()
                .unwrap(),
        ),
    ]
}

/// The guide's pictures are what `Picture` draws now; `UPDATE_PICTURES=1` writes them into
/// the guide instead of comparing (then read the diff).
#[test]
fn the_guide_shows_each_catalogue_model_as_it_is_drawn_now() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../src/docs/geometry.md");
    let mut guide = std::fs::read_to_string(path).unwrap();
    let update = std::env::var_os("UPDATE_PICTURES").is_some();
    for (name, svg) in catalogue_pictures() {
        let start = format!("<!-- picture of {name} -->\n");
        let end = "<!-- end of picture -->";
        let Some(from) = guide.find(&start).map(|i| i + start.len()) else {
            panic!("the guide has no `{}`", start.trim_end());
        };
        let to = from + guide[from..].find(end).unwrap();
        let committed = &guide[from..to];
        let drawn = format!("{}\n", svg.trim_end());
        if update {
            guide.replace_range(from..to, &drawn);
        } else {
            assert!(
                committed == drawn,
                "the guide's picture of {name} is not what Picture draws now: rerun with \
                 UPDATE_PICTURES=1 and read the diff"
            );
        }
    }
    if update {
        std::fs::write(path, guide).unwrap();
    }
}

#[test]
fn a_body_takes_the_shape_given_by_name() {
    let penny = Penny::default();
    let run = penny_run(&penny, 0.1);
    let offset = Vector3::new(0.0, 0.0, 0.01);
    let html = Scene::new(&penny, &run)
        .unwrap()
        .shape(
            "rod",
            Solid::box_(0.01, 0.02, 0.04).at(offset).color(0x123456),
        )
        .shape("disk", Solid::inertia_box())
        .to_html()
        .unwrap();
    let data = data_of(&html);
    assert!(
        data.contains(
            r#""name":"rod","color":1193046.0,"description":"box 0.01 × 0.02 × 0.04, as given""#
        ),
        "{data:.600}"
    );
    assert!(
        data.contains(r#""offset":[0.0,0.0,0.01],"solid":{"kind":"box","edges":[0.01,0.02,0.04]"#)
    );
    // The disk's inertia as a box: a thin disk of radius r has the inertia of a square plate
    // of side r √3 (m l²/12 · 2 = m r²/2 about the axle), thickened to a fiftieth.
    let side = 0.05 * 3f64.sqrt();
    let looks = look::looks(
        &snapshot::Snapshot::of(&penny, 0.0, &[0.0; 5]).unwrap(),
        &[("disk".into(), Solid::inertia_box())],
    )
    .unwrap();
    let look::Drawn::Box { edges, .. } = looks[0].solid else {
        panic!("{:?}", looks[0].solid)
    };
    // Moments ascending: the two diameters first, the axle last.
    let expected = [side, side, 0.02 * side];
    assert!(
        edges
            .iter()
            .zip(expected)
            .all(|(e, x)| (e - x).abs() < 1e-12),
        "{edges:?}"
    );
}

/// A disk on a plane inclined by `alpha` about the ground's y axis (as in the validation
/// suite's `rolling.rs`).
#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct InclineDisk {
    pub m: f64,
    pub r: f64,
    pub g: f64,
    pub alpha: f64,
}

#[hamel_system(
    coordinates(x, y, psi, phi, theta),
    speeds(yaw_rate, lean_rate, spin_rate),
    bodies(disk)
)]
impl InclineDisk {
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

/// The disk on an incline of 0.3 rad.
fn incline_disk() -> InclineDisk {
    InclineDisk {
        m: 1.0,
        r: 0.1,
        g: 9.81,
        alpha: 0.3,
    }
}

/// 0.4 down the incline's x axis, upright: the contact point 0.4 sin 0.3 = 0.118 below z = 0.
const ON_THE_INCLINE: [f64; 5] = [0.4, 0.0, 0.0, 0.0, 0.0];

#[test]
fn a_tilted_plane_is_drawn_in_its_own_plane_and_a_body_placed_as_on_flat_ground_is_a_warning() {
    let disk = incline_disk();
    let picture = Picture::new(&disk, 0.0, &ON_THE_INCLINE).unwrap();
    assert_eq!(picture.warnings().unwrap(), Vec::<String>::new());
    assert!(picture.to_svg().unwrap().contains("\nplane\n</text>"));
    // The scene carries the plane's pose: a turn by 0.3 about y, (0, sin 0.15, 0, cos 0.15).
    let x0 = disk.state_builder().set("spin_rate", -5.0).build().unwrap();
    let run = Simulation::new(&disk, x0)
        .end_time(0.05)
        .sample_interval(0.01)
        .run_constant(&DormandPrince::new(1e-8, 1e-10), [])
        .unwrap();
    let html = Scene::new(&disk, &run).unwrap().to_html().unwrap();
    let data = data_of(&html);
    let (s, c) = 0.15f64.sin_cos();
    let pose = format!(r#""kind":"plane","origin":[0.0,0.0,0.0],"rotation":[0.0,{s:?},0.0,{c:?}]"#);
    assert!(data.contains(&pose), "{data:.2000}");
    assert!(data.contains(r#""contacts":[{"body":0.0,"surface":0.0}]"#));

    // The mistake: the disk placed as on flat ground (its centre r above z = 0) but said to
    // roll on the incline. Its contact point, the rim's point nearest the plane, is
    // 0.4 sin 0.3 + 0.1 cos 0.3 − 0.1 = 0.1137 off the plane, and that is a warning. (In a model the macro refuses
    // it already: the contact's height then varies with x, a holonomic constraint.)
    let flat = Body::new(
        1.0,
        Inertia::principal(1.0, 2.0, 1.0),
        Vector3::new(0.4, 0.0, 0.1),
        Rotation3::identity(),
    )
    .with_shape(Shape::disk(0.1, Vector3::y()));
    let incline = Surface::plane(Vector3::zeros(), Rotation3::about_y(0.3));
    let contact = Contact::rolling(flat, incline);
    let warning = snapshot::off_surface(0, Some("disk"), &contact, 0.1, 0.0).unwrap();
    assert!(
        warning.starts_with("contact point 1 (of body `disk`) is 0.1137")
            && warning.contains("from its surface at t = 0"),
        "{warning}"
    );
    let right = Contact::rolling(disk.bodies(&ON_THE_INCLINE)[0], incline);
    assert_eq!(
        snapshot::off_surface(0, Some("disk"), &right, 0.1, 0.0),
        None
    );
}

/// A writer killed before it renamed its file leaves it (`<name>.partial-<pid>-<n>`); the
/// next write of the same name removes it, but not a running writer's. Before, the page
/// was written through `.<name>.<pid>.<n>.partial` and nothing removed what a killed writer
/// left.
#[test]
fn a_killed_writers_leftover_goes_with_the_next_write() {
    let penny = Penny::default();
    let run = penny_run(&penny, 0.1);
    let dir = scratch("leftover");
    let path = dir.join("scene.html");
    // A process id above Linux's largest (2²²) runs nowhere; this process runs.
    let dead = dir.join("scene.html.partial-4194305-0");
    let running = dir.join(format!("scene.html.partial-{}-999", std::process::id()));
    std::fs::write(&dead, "<!doctype html><html><body>cut sh").unwrap();
    std::fs::write(&running, "<!doctype html>").unwrap();
    Scene::new(&penny, &run).unwrap().write_html(&path).unwrap();
    assert!(!dead.exists(), "the killed writer's file is still there");
    assert!(running.exists(), "a running writer's file was removed");
    let picture = Picture::new(&penny, 0.0, &[0.0; 5]).unwrap();
    let svg = dir.join("penny.svg");
    let dead = dir.join("penny.svg.partial-4194305-3");
    std::fs::write(&dead, "<svg").unwrap();
    picture.save(&svg).unwrap();
    assert!(!dead.exists(), "the killed writer's picture is still there");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A body drawn through a surface is a warning (the page, the picture's legend and
/// `warnings`): the rattleback's inertia ellipsoid sits 5.8 mm into the floor its base rolls
/// on (its centre of mass is h = 10 mm above its base, the ellipsoid's semi-axis 15.8 mm),
/// and the robot's body, which has no contact, reaches 5.4 mm under the floor upright.
/// Wheels and balls touch their surfaces and no more (the bicycle's z points down: its
/// bodies are below the plane z = 0, and no warning says they are in it). Before, nothing
/// was said.
#[test]
fn a_body_drawn_through_a_surface_is_a_warning() {
    use hamel::models::{ChaplyginBall, MobileRobot, Rattleback, RollingDisk, WhippleBicycle};
    fn picture<M: Mechanism>(model: &M) -> Picture {
        let q = model
            .assemble(0.0, &<M::Coordinates as hamel::Vector>::zeros())
            .unwrap();
        Picture::new(model, 0.0, &q).unwrap()
    }
    assert_eq!(
        picture(&WhippleBicycle::default()).warnings().unwrap(),
        Vec::<String>::new()
    );
    assert_eq!(
        picture(&RollingDisk::default()).warnings().unwrap(),
        Vec::<String>::new()
    );
    assert_eq!(
        picture(&ChaplyginBall::default()).warnings().unwrap(),
        Vec::<String>::new()
    );
    let celt = picture(&Rattleback::default());
    let warnings = celt.warnings().unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].starts_with("body `rattleback` is drawn 0.005811 m into the plane it rolls on")
            && warnings[0].contains("is not the body's shape")
            && warnings[0].contains("Scene::shape"),
        "{warnings:?}"
    );
    assert!(
        celt.to_svg()
            .unwrap()
            .contains("rattleback (drawn into the plane)")
    );
    let robot = picture(&MobileRobot::default()).warnings().unwrap();
    assert_eq!(robot.len(), 1, "{robot:?}");
    assert!(
        robot[0].starts_with("body `body` is drawn 0.05355 m through the plane the contacts touch")
            && robot[0].contains("it has no contact with it"),
        "{robot:?}"
    );
    // In a scene, at any sample: the page lists the deepest. A flat box with its bottom on
    // the base's lowest point dips its corners into the floor as the body rocks (the base
    // curves up from there); one that lies above the base everywhere stays out of it.
    let rattleback = Rattleback::default();
    let x0 = rattleback
        .state_builder()
        .set("yaw_rate", 3.0)
        .set("roll_rate", 0.5)
        .build()
        .unwrap();
    let run = sixty_per_second(&rattleback, x0, 1.0);
    let scene = Scene::new(&rattleback, &run).unwrap();
    let warnings = scene.warnings().unwrap();
    assert!(
        warnings.len() == 1 && warnings[0].contains("into the plane it rolls on"),
        "{warnings:?}"
    );
    assert!(
        scene
            .to_html()
            .unwrap()
            .contains("into the plane it rolls on")
    );
    let flat = Solid::box_(0.1, 0.03, 0.008).at(Vector3::new(0.0, 0.0, -0.006));
    let rocking = Scene::new(&rattleback, &run)
        .unwrap()
        .shape("rattleback", flat);
    let warnings = rocking.warnings().unwrap();
    assert!(
        warnings.len() == 1 && warnings[0].contains("box 0.1 × 0.03 × 0.008, as given"),
        "{warnings:?}"
    );
    // Its corners (±0.03, ±0.01, −0.005) are above the base, −0.01 + ξ²/(2 R₁) + η²/(2 R₂).
    let inside = Solid::box_(0.06, 0.02, 0.004).at(Vector3::new(0.0, 0.0, -0.003));
    let shaped = Scene::new(&rattleback, &run)
        .unwrap()
        .shape("rattleback", inside);
    assert_eq!(shaped.warnings().unwrap(), Vec::<String>::new());
}

/// `run` with its rows replaced: through the trajectory's `Sink`, as any producer fills one.
fn rewritten(run: &Trajectory, names: &[&str], edit: impl Fn(usize, &mut Vec<f64>)) -> Trajectory {
    use hamel::Sink;
    let mut out = run.clone();
    let names: Vec<String> = names.iter().map(|n| n.to_string()).collect();
    out.begin(&names).unwrap();
    for (i, mut row) in run.rows().enumerate() {
        edit(i, &mut row);
        Sink::row(&mut out, &row).unwrap();
    }
    out
}

/// Times that are not finite or do not increase, a column name given twice and a unit for
/// a column the trajectory does not have are errors naming them (before, each made a page:
/// the slider jumped back, or a column was shown with another's values).
#[test]
fn times_that_do_not_increase_and_ambiguous_columns_are_errors() {
    let penny = Penny::default();
    let run = penny_run(&penny, 0.1);
    let names: Vec<&str> = run.names().iter().map(String::as_str).collect();
    let error = |trajectory: &Trajectory| {
        Scene::new(&penny, trajectory)
            .err()
            .expect("the scene was made")
            .to_string()
    };
    let nan = rewritten(&run, &names, |i, row| {
        if i == 3 {
            row[0] = f64::NAN;
        }
    });
    let e = error(&nan);
    assert!(
        e.contains("the time of sample 3 is NaN: a scene's times must be finite"),
        "{e}"
    );
    let back = rewritten(&run, &names, |i, row| {
        if i == 4 {
            row[0] = 0.01;
        }
    });
    let e = error(&back);
    assert!(
        e.contains("the time of sample 4, 0.01, is before the time of sample 3, 0.05"),
        "{e}"
    );
    let repeated = rewritten(&run, &names, |i, row| {
        if i == 2 {
            row[0] = 1.0 / 60.0;
        }
    });
    let e = error(&repeated);
    assert!(e.contains("samples 1 and 2 have the same time"), "{e}");
    let mut twice = names.clone();
    twice[7] = "phi";
    let e = error(&rewritten(&run, &twice, |_, _| {}));
    assert!(e.contains("two columns named `phi`"), "{e}");
    let e = Scene::new(&penny, &run)
        .unwrap()
        .unit("lean", "rad")
        .to_html()
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("a unit is given for `lean`, which is not a column of the trajectory"),
        "{e}"
    );
}

/// A trajectory of more samples than a page carries is drawn at one sample in k and its
/// last, the values shown with them, and a warning says so; within the limit, every sample.
/// Before, 10⁷ samples made a page of 1.2 GB, built in 6.6 GB of memory.
#[test]
fn a_trajectory_longer_than_a_page_carries_is_thinned_with_a_warning() {
    assert_eq!(motion::rows_drawn(5, 5), [0, 1, 2, 3, 4]);
    assert_eq!(motion::rows_drawn(6, 5), [0, 2, 4, 5]);
    assert_eq!(motion::rows_drawn(10, 4), [0, 3, 6, 9]);
    let penny = Penny::default();
    let run = penny_run(&penny, 2.0);
    assert_eq!(run.len(), 121);
    let scene = Scene::at_most(&penny, &run, 50).unwrap().show(["phi"]);
    let html = scene.to_html().unwrap();
    let data = data_of(&html);
    let times = floats64(field(data, "times"));
    let rows: Vec<usize> = (0..120).step_by(3).chain([120]).collect();
    assert_eq!(
        times,
        rows.iter().map(|&r| run.times()[r]).collect::<Vec<_>>()
    );
    let phi = run.column("phi").unwrap();
    assert_eq!(
        floats64(field(data, "values")),
        rows.iter().map(|&r| phi[r]).collect::<Vec<_>>()
    );
    let warnings = scene.warnings().unwrap();
    assert!(
        warnings.iter().any(|w| w.contains(
            "the trajectory has 121 samples, more than a page carries (50): it is drawn at one \
             sample in 3 and the last (41 samples)"
        )),
        "{warnings:?}"
    );
    assert!(html.contains("drawn at one sample in 3"));
    let whole = Scene::new(&penny, &run).unwrap();
    assert!(
        whole
            .warnings()
            .unwrap()
            .iter()
            .all(|w| !w.contains("samples"))
    );
    assert_eq!(MAX_SCENE_SAMPLES, 250_000);
}
