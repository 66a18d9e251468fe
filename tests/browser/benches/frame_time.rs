//! The frame time of a scene playing in headless Chromium with software WebGL (SwiftShader)
//! on this machine: the interval between frames while it plays in real time, and the time
//! the page spends drawing each one.
//!
//! ```text
//! cargo bench -p hamel-browser --bench frame_time                  # the bicycle falling
//! cargo bench -p hamel-browser --bench frame_time -- bicycle.html  # any scene page
//! ```
//!
//! Five rounds of 120 frames after 60 frames of warm-up, in a 1280 × 720 viewport; prints the
//! median frame interval with its p10–p90, the median time the page's script spends on a
//! frame, and the CPU time each of Chromium's processes spends per frame (from `/proc`: on a
//! loaded machine the intervals grow, the CPU per frame much less). The figures of record are
//! in `tests/browser/README.md`.

use std::path::PathBuf;
use std::process::ExitCode;

use hamel_browser::chromium::{Browser, INSTALL, find};
use hamel_browser::page::url;

fn quantile(sorted: &[f64], q: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

fn measure(browser: &mut Browser, frames: usize) -> Result<(Vec<f64>, Vec<f64>), String> {
    let value = browser.evaluate(&format!("window.hamelScene.measure({frames})"))?;
    let list = |key: &str| -> Result<Vec<f64>, String> {
        value[key]
            .as_array()
            .ok_or(format!("no {key}"))?
            .iter()
            .map(|v| v.as_f64().ok_or(format!("{key}: not numbers")))
            .collect()
    };
    Ok((list("intervals")?, list("drawing")?))
}

fn run() -> Result<(), String> {
    let page: PathBuf = match std::env::args().skip(1).find(|a| !a.starts_with("--")) {
        Some(path) => PathBuf::from(path),
        None => hamel_browser::catalogue::bicycle_capsize_page(&std::env::temp_dir())
            .map_err(|e| e.to_string())?,
    };
    let executable = find().ok_or(format!("no Chromium: {INSTALL}"))?;
    let mut browser = Browser::launch(&executable, 1280, 720)?;
    browser.open(&url(&page, "t=0")?)?;
    browser.evaluate("window.hamelScene.ready")?;
    measure(&mut browser, 60)?;
    let (mut intervals, mut drawing) = (Vec::new(), Vec::new());
    let before = browser.cpu_times();
    for _ in 0..5 {
        let (i, d) = measure(&mut browser, 120)?;
        intervals.extend(i);
        drawing.extend(d);
    }
    let after = browser.cpu_times();
    let scale = browser.evaluate("window.hamelScene.state().scale")?;
    let errors = browser.console_errors();
    if !errors.is_empty() {
        return Err(format!("console errors: {errors:?}"));
    }
    intervals.sort_by(f64::total_cmp);
    drawing.sort_by(f64::total_cmp);
    println!(
        "{}: {} frames at 1280 × 720, software WebGL (SwiftShader)",
        page.display(),
        intervals.len()
    );
    println!(
        "frame interval: median {:.1} ms (p10 {:.1}, p90 {:.1}); drawing: median {:.2} ms (p90 {:.2})",
        quantile(&intervals, 0.5),
        quantile(&intervals, 0.1),
        quantile(&intervals, 0.9),
        quantile(&drawing, 0.5),
        quantile(&drawing, 0.9)
    );
    // What each of Chromium's processes spent per frame: with nothing else running, they
    // work in parallel, and the slowest sets the frame rate.
    let frames = intervals.len() as f64;
    let mut spent: Vec<String> = after
        .iter()
        .map(|(kind, ms)| {
            let was = before
                .iter()
                .find(|(k, _)| k == kind)
                .map_or(0.0, |(_, m)| *m);
            (kind, (ms - was) / frames)
        })
        .filter(|(_, per_frame)| *per_frame >= 0.05)
        .map(|(kind, per_frame)| format!("{kind} {per_frame:.1} ms"))
        .collect();
    spent.sort();
    println!("CPU per frame: {}", spent.join(", "));
    println!(
        "resolution while playing: {} of the canvas' (the page lowers it when frames are slow)",
        scale
            .as_f64()
            .map_or("?".to_string(), |s| format!("{:.0} %", 100.0 * s))
    );
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
