//! A screenshot of a scene page at a time, paused, as the README's picture is made:
//!
//! ```text
//! cargo run --release --features png --example bicycle -- --animate bicycle.html
//! cargo run --release -p hamel-browser --bin screenshot -- bicycle.html 2.5 images/bicycle_capsize.png
//! ```
//!
//! Options after the three arguments: `--size WIDTHxHEIGHT` (default 1280x720). A console
//! error in the page is an error.

use std::path::PathBuf;
use std::process::ExitCode;

use hamel_browser::chromium::{Browser, INSTALL, find};
use hamel_browser::page::show_at;

fn run() -> Result<String, String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: screenshot <scene.html> <time> <out.png> [--size WIDTHxHEIGHT]";
    let [page, time, out, rest @ ..] = args.as_slice() else {
        return Err(usage.into());
    };
    let t: f64 = time
        .parse()
        .map_err(|_| format!("{time}: not a time; {usage}"))?;
    let (mut width, mut height) = (1280, 720);
    match rest {
        [] => {}
        [flag, size] if flag == "--size" => {
            let (w, h) = size.split_once('x').ok_or(usage)?;
            (width, height) = (w.parse().map_err(|_| usage)?, h.parse().map_err(|_| usage)?);
        }
        _ => return Err(usage.into()),
    }
    let executable = find().ok_or(format!("no Chromium: {INSTALL}"))?;
    let mut browser = Browser::launch(&executable, width, height)?;
    let (shown, image) = show_at(&mut browser, &PathBuf::from(page), t, "")?;
    let png = image.png()?;
    std::fs::write(out, png).map_err(|e| format!("{out}: {e}"))?;
    Ok(format!(
        "wrote {out} ({width} × {height}): {page} at sample {} (t = {})",
        shown.sample, shown.time
    ))
}

fn main() -> ExitCode {
    match run() {
        Ok(message) => {
            println!("{message}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
