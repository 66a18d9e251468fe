//! Every catalogue scene opened in headless Chromium (software WebGL): it loads without a
//! console error, and at two times the checked body is drawn where the trajectory puts it,
//! projected with the camera the page published; the two pictures differ. A wheel is found
//! by its dark hub at its centre; another body by what hiding it uncovers there.
//!
//! Without Chromium the test prints how to install it and passes as skipped. Cost: about
//! 20 s on two cores for the five scenes (a browser start, then two or three page loads and
//! screenshots each).
//!
//! Two tests need no browser and always run: the command line of the examples that write
//! scenes (`examples/support/animate.rs`), and the bicycle example's ride
//! (`examples/support/capsize.rs`) ending at a physical event.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use hamel_browser::catalogue::{Case, capsize, cases, long_ride, rolling_disk};
use hamel_browser::chromium::{Browser, INSTALL, Image, find};
use hamel_browser::page::{show_at, shown_now};

// The examples' command line (`--animate`, `--help`), read by the examples that write scenes.
#[allow(dead_code)]
#[path = "../../../examples/support/animate.rs"]
mod animate;

/// The tests take turns: one Chromium at a time on the machine's cores.
fn one_browser_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    static BROWSER: std::sync::Mutex<()> = std::sync::Mutex::new(());
    BROWSER.lock().unwrap_or_else(|e| e.into_inner())
}

/// The hub's colour in the page (`HUB` in `viewer.js`).
const HUB: [u8; 3] = [0x1a, 0x1a, 0x1a];

/// A fresh directory for one test's files.
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hamel-browser-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The fraction of the 5 × 5 pixels about (x, y) that satisfy `test`.
fn share(image: &Image, (x, y): (f64, f64), test: impl Fn([u8; 3]) -> bool) -> f64 {
    let (x, y) = (x.round() as i64, y.round() as i64);
    let window: Vec<[u8; 3]> = (-2..=2)
        .flat_map(|dy| (-2..=2).map(move |dx| (dx, dy)))
        .filter_map(|(dx, dy)| image.pixel(x + dx, y + dy))
        .collect();
    window.iter().filter(|p| test(**p)).count() as f64 / 25.0
}

fn is_hub(p: [u8; 3]) -> bool {
    p.iter().zip(HUB).all(|(a, b)| a.abs_diff(b) <= 12)
}

/// The share of pixels that differ between two pictures by more than 40 in some channel.
fn changed(a: &Image, b: &Image) -> f64 {
    let differ = a
        .rgba
        .chunks(4)
        .zip(b.rgba.chunks(4))
        .filter(|(p, q)| {
            p.iter()
                .zip(q.iter())
                .take(3)
                .any(|(x, y)| x.abs_diff(*y) > 40)
        })
        .count();
    differ as f64 / (a.width * a.height) as f64
}

fn check(browser: &mut Browser, case: &Case, dir: &Path) {
    let name = case.name;
    let mut pictures = Vec::new();
    let mut positions = Vec::new();
    for &i in &case.samples {
        let t = case.times[i];
        let (shown, image) =
            show_at(browser, &case.html, t, "&follow=0").unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(
            (shown.sample, shown.time),
            (i, t),
            "{name}: the page shows another sample"
        );
        let at = shown.project(case.centres[i]);
        let [left, top, width, height] = shown.viewport.map(|v| v * shown.pixel_ratio);
        assert!(
            at.0 >= left && at.1 >= top && at.0 < left + width && at.1 < top + height,
            "{name}: the body is outside the scene's canvas at t = {t} ({at:?})"
        );
        if case.wheel {
            let hub = share(&image, at, is_hub);
            if hub < 0.5 {
                let _ = std::fs::write(dir.join(format!("{name}-{i}.png")), image.png().unwrap());
            }
            assert!(
                hub >= 0.5,
                "{name}: no hub at the wheel's centre {at:?} at t = {t} ({hub})"
            );
        } else {
            let (hidden_shown, hidden) = show_at(
                browser,
                &case.html,
                t,
                &format!("&follow=0&hide={}", case.body),
            )
            .unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(hidden_shown.view, shown.view, "{name}: the camera moved");
            let covered = share(&image, at, |_| true);
            let differs = {
                let (x, y) = (at.0.round() as i64, at.1.round() as i64);
                (-2..=2)
                    .flat_map(|dy| (-2..=2).map(move |dx| (dx, dy)))
                    .filter(|&(dx, dy)| {
                        let (p, q) = (image.pixel(x + dx, y + dy), hidden.pixel(x + dx, y + dy));
                        matches!((p, q), (Some(p), Some(q)) if p.iter().zip(q).any(|(a, b)| a.abs_diff(b) > 30))
                    })
                    .count() as f64
                    / 25.0
            };
            assert!(
                covered == 1.0 && differs >= 0.8,
                "{name}: hiding the body uncovers little at its centre {at:?} at t = {t} ({differs})"
            );
        }
        positions.push((shown, at));
        pictures.push(image);
    }
    let moved = changed(&pictures[0], &pictures[1]);
    assert!(
        moved > 0.002,
        "{name}: the two pictures are the same ({moved})"
    );
    if case.wheel {
        // At the second time, the hub is not where the wheel was at the first: the page shows
        // the sample it says, not a stale one.
        let (shown, at) = &positions[1];
        let before = shown.project(case.centres[case.samples[0]]);
        if (before.0 - at.0).hypot(before.1 - at.1) > 30.0 {
            let stale = share(&pictures[1], before, is_hub);
            assert!(
                stale < 0.2,
                "{name}: a hub where the wheel was before ({stale})"
            );
        }
    }
}

#[test]
fn each_catalogue_scene_is_drawn_where_its_trajectory_puts_it_and_moves() {
    let Some(executable) = find() else {
        // Written to the standard error stream directly, not by `eprintln!`, which the test
        // harness captures: the message shows in every run.
        let _ = writeln!(
            std::io::stderr(),
            "skipped: no Chromium to open the scenes in; {INSTALL}"
        );
        return;
    };
    let _one = one_browser_at_a_time();
    let dir = scratch("catalogue");
    let cases = cases(&dir).expect("the catalogue's scenes");
    let mut browser = Browser::launch(&executable, 1280, 720)
        .unwrap_or_else(|e| panic!("cannot start {}: {e}", executable.display()));
    for case in &cases {
        check(&mut browser, case, &dir);
    }
    drop(browser);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The share of the canvas' lower half (below the bodies, where the ground is seen) whose
/// pixels are the grid's greys: not the background, not a body's colour.
fn grid_share(image: &Image, shown: &hamel_browser::page::Shown) -> f64 {
    let [left, top, width, height] = shown.viewport.map(|v| v * shown.pixel_ratio);
    let (x0, x1) = (left as i64, (left + width) as i64);
    let (y0, y1) = ((top + 0.75 * height) as i64, (top + height) as i64);
    let mut grid = 0;
    for y in y0..y1 {
        for x in x0..x1 {
            let Some([r, g, b]) = image.pixel(x, y) else {
                continue;
            };
            let grey = r.abs_diff(g) <= 3 && g.abs_diff(b) <= 3;
            if grey && (0x9c..=0xea).contains(&r) {
                grid += 1;
            }
        }
    }
    grid as f64 / ((x1 - x0) * (y1 - y0)) as f64
}

/// A bicycle riding 100 m: the ground's grid is seen under it at the start and at the end,
/// following it. Before, the grid's lines were long lines across the whole run, and the
/// software renderer dropped every line with an end behind the camera: the bicycle rode in
/// empty space.
#[test]
fn the_ground_is_drawn_under_a_long_ride() {
    let Some(executable) = find() else {
        let _ = writeln!(std::io::stderr(), "skipped: {INSTALL}");
        return;
    };
    let _one = one_browser_at_a_time();
    let dir = scratch("long");
    let (html, run) = long_ride(&dir, 20.0).expect("the long ride");
    let x = run.column("x").unwrap();
    assert!(
        x[x.len() - 1] > 95.0,
        "the bicycle rode {} m",
        x[x.len() - 1]
    );
    let mut browser = Browser::launch(&executable, 1280, 720).unwrap();
    for t in [0.5, 19.9] {
        let (shown, image) = show_at(&mut browser, &html, t, "").unwrap();
        let share = grid_share(&image, &shown);
        if share < 0.01 {
            let _ = std::fs::write(dir.join(format!("long-{t}.png")), image.png().unwrap());
        }
        assert!(
            share >= 0.01,
            "no ground under the bicycle at t = {t}: {share}"
        );
    }
    drop(browser);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Right-drag pans, with and without following: the camera's target moves, and stays where
/// it was panned to (following, at the same offset from the mechanism as it moves on).
/// Before, the page put the target back on the mechanism (or the first sample) at the next
/// frame drawn.
#[test]
fn right_drag_pans_with_and_without_follow() {
    let Some(executable) = find() else {
        let _ = writeln!(std::io::stderr(), "skipped: {INSTALL}");
        return;
    };
    let _one = one_browser_at_a_time();
    let dir = scratch("pan");
    let disk = rolling_disk(&dir).expect("the rolling disk's scene");
    let (at, later) = (30, 45);
    let mut browser = Browser::launch(&executable, 1280, 720).unwrap();
    let distance =
        |a: [f64; 3], b: [f64; 3]| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
    let minus = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    for follow in [true, false] {
        let fragment = if follow { "" } else { "&follow=0" };
        let (before, _) = show_at(&mut browser, &disk.html, disk.times[at], fragment).unwrap();
        let [left, top, width, height] = before.viewport;
        let centre = (left + 0.5 * width, top + 0.5 * height);
        browser
            .drag(centre, (centre.0 + 150.0, centre.1 + 60.0), "right", 12)
            .unwrap();
        let panned = shown_now(&mut browser).unwrap();
        let moved = distance(panned.target, before.target);
        // The disk's radius is 0.05: a pan of 150 px moves the target by several radii.
        assert!(
            moved > 0.02,
            "follow {follow}: the pan did not move the target ({moved})"
        );
        browser
            .evaluate(&format!("window.hamelScene.setTime({})", disk.times[later]))
            .unwrap();
        let after = shown_now(&mut browser).unwrap();
        assert_eq!(after.sample, later);
        // The mechanism is one body: the centroid followed is the disk's centre.
        let expected = if follow {
            minus(disk.centres[later], disk.centres[at])
        } else {
            [0.0; 3]
        };
        let shift = minus(after.target, panned.target);
        assert!(
            distance(shift, expected) < 1e-6,
            "follow {follow}: the target moved by {shift:?}, not {expected:?}"
        );
    }
    drop(browser);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The examples that write scenes read `--animate PATH`, `--animate=PATH`, `--help` or
/// nothing, and refuse anything else naming the argument at fault. Before, `bicycle_control`
/// ignored its arguments, `--animate a.html extra` said `--animate` needed a file name, and
/// no example had `--help`.
#[test]
fn the_examples_read_their_command_line_or_name_what_is_wrong() {
    use animate::{Request, request};
    let read = |args: &[&str]| request(&args.iter().map(|a| a.to_string()).collect::<Vec<_>>());
    let run = |path: &str| Ok(Request::Run(Some(PathBuf::from(path))));
    assert_eq!(read(&[]), Ok(Request::Run(None)));
    assert_eq!(read(&["--help"]), Ok(Request::Help));
    assert_eq!(read(&["-h"]), Ok(Request::Help));
    assert_eq!(read(&["--animate", "a.html"]), run("a.html"));
    assert_eq!(read(&["--animate=a.html"]), run("a.html"));
    for missing in [
        &["--animate"][..],
        &["--animate", "--help"],
        &["--animate="],
        &["--animate", ""],
    ] {
        let e = read(missing).unwrap_err();
        assert!(
            e.contains("`--animate` needs a file name"),
            "{missing:?}: {e}"
        );
    }
    for (args, wrong) in [
        (&["--frobnicate"][..], "--frobnicate"),
        (&["a.html"], "a.html"),
        (&["--animate", "a.html", "extra"], "extra"),
        (&["--animate=a.html", "--help"], "--help"),
        (&["--help", "--animate"], "--help"),
        (&["--animatex"], "--animatex"),
    ] {
        let e = read(args).unwrap_err();
        assert!(
            e.contains(&format!("unexpected argument `{wrong}`")),
            "{args:?}: {e}"
        );
    }
}

/// The bicycle example's `--animate` ride ends at a physical event: the front wheel turned
/// square across the frame (a steer of 90°), while the model still determines the motion —
/// the energy kept. Before, it ran on until the roll reached 60°, through the steer where the
/// constraints and speeds become dependent (1.596 rad): the steer reached 5.03 rad, and the
/// energy changed by 2.5·10⁻⁴ (here 2.7·10⁻⁹).
#[test]
fn the_bicycle_falls_until_its_front_wheel_is_across_the_frame() {
    let bike = hamel::models::WhippleBicycle::default();
    let ride = capsize::ride(&bike).expect("the ride");
    let across = ride.event_times("across");
    let end = ride.times()[ride.len() - 1];
    assert_eq!(across, [end], "the ride ends where the steer reaches 90°");
    assert!(ride.event_times("fallen").is_empty());
    let steer = ride.column("delta").unwrap();
    let largest = steer.iter().fold(0.0f64, |m, d| m.max(d.abs()));
    assert!(
        (largest - capsize::ACROSS).abs() < 1e-6,
        "the steer reached {largest} rad"
    );
    let drift = ride.summary().relative_energy_drift;
    assert!(drift < 1e-7, "the energy changed by {drift:e} of itself");
}
