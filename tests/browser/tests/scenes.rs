//! Every catalogue scene opened in headless Chromium (software WebGL): it loads without a
//! console error, and at two times the checked body is drawn where the trajectory puts it,
//! projected with the camera the page published; the two pictures differ. A wheel is found
//! by its dark hub at its centre; another body by what hiding it uncovers there.
//!
//! Without Chromium the test prints how to install it and passes as skipped. Cost: about
//! 20 s on two cores for the five scenes (a browser start, then two or three page loads and
//! screenshots each).

use std::io::Write as _;
use std::path::{Path, PathBuf};

use hamel_browser::catalogue::{Case, cases};
use hamel_browser::chromium::{Browser, INSTALL, Image, find};
use hamel_browser::page::show_at;

/// The hub's colour in the page (`HUB` in `viewer.js`).
const HUB: [u8; 3] = [0x1a, 0x1a, 0x1a];

fn scratch() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hamel-browser-{}", std::process::id()));
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
    let dir = scratch();
    let cases = cases(&dir).expect("the catalogue's scenes");
    let mut browser = Browser::launch(&executable, 1280, 720)
        .unwrap_or_else(|e| panic!("cannot start {}: {e}", executable.display()));
    for case in &cases {
        check(&mut browser, case, &dir);
    }
    drop(browser);
    let _ = std::fs::remove_dir_all(&dir);
}
