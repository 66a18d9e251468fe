//! A scene page in the browser: opened at a time, paused, with the camera it drew with, so
//! that a point of the trajectory can be found on the screenshot.

use std::path::Path;

use serde_json::Value;

use crate::chromium::{Browser, Image};

/// What the page showed: the sample, and the camera that drew it.
#[derive(Clone, Debug, PartialEq)]
pub struct Shown {
    pub sample: usize,
    pub time: f64,
    /// The camera's view and projection matrices, column by column (three.js' layout).
    pub view: [f64; 16],
    pub projection: [f64; 16],
    /// The canvas: left, top, width, height, in CSS pixels.
    pub viewport: [f64; 4],
    pub pixel_ratio: f64,
    /// The point the camera looks at and orbits about.
    pub target: [f64; 3],
}

impl Shown {
    /// Where the world point `p` is on the screenshot, in device pixels: the camera's
    /// projection, applied here from the matrices the page published.
    pub fn project(&self, p: [f64; 3]) -> (f64, f64) {
        let apply = |m: &[f64; 16], v: [f64; 4]| -> [f64; 4] {
            std::array::from_fn(|i| (0..4).map(|j| m[i + 4 * j] * v[j]).sum())
        };
        let clip = apply(&self.projection, apply(&self.view, [p[0], p[1], p[2], 1.0]));
        let (x, y) = (clip[0] / clip[3], clip[1] / clip[3]);
        let [left, top, width, height] = self.viewport;
        (
            (left + 0.5 * (x + 1.0) * width) * self.pixel_ratio,
            (top + 0.5 * (1.0 - y) * height) * self.pixel_ratio,
        )
    }

    fn from_json(state: &Value) -> Result<Shown, String> {
        let numbers = |key: &str| -> Result<Vec<f64>, String> {
            state[key]
                .as_array()
                .ok_or(format!("no `{key}` in the page's state {state}"))?
                .iter()
                .map(|v| v.as_f64().ok_or(format!("`{key}` is not numbers")))
                .collect()
        };
        let fixed = |key: &str| -> Result<[f64; 16], String> {
            numbers(key)?
                .try_into()
                .map_err(|_| format!("`{key}` has not 16 entries"))
        };
        Ok(Shown {
            sample: state["sample"].as_u64().ok_or("no sample")? as usize,
            time: state["time"].as_f64().ok_or("no time")?,
            view: fixed("view")?,
            projection: fixed("projection")?,
            viewport: numbers("viewport")?
                .try_into()
                .map_err(|_| "the viewport has not 4 entries")?,
            pixel_ratio: state["pixelRatio"].as_f64().ok_or("no pixel ratio")?,
            target: numbers("target")?
                .try_into()
                .map_err(|_| "the target has not 3 entries")?,
        })
    }
}

/// The `file://` URL of a page, with a fragment.
pub fn url(path: &Path, fragment: &str) -> Result<String, String> {
    let absolute = std::fs::canonicalize(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut url = String::from("file://");
    for byte in absolute.to_string_lossy().bytes() {
        match byte {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'_' | b'.' | b'~' => {
                url.push(byte as char);
            }
            other => url.push_str(&format!("%{other:02X}")),
        }
    }
    Ok(format!("{url}#{fragment}"))
}

/// Opens the scene at `path` paused at time `t` (with more of the fragment in `extra`, such
/// as `&follow=0`), waits until that sample is on the screen, and returns what was shown and
/// the screenshot. Any console error or exception is an error.
pub fn show_at(
    browser: &mut Browser,
    path: &Path,
    t: f64,
    extra: &str,
) -> Result<(Shown, Image), String> {
    browser.open(&url(path, &format!("t={t:?}&pause{extra}"))?)?;
    let state = browser.evaluate("window.hamelScene.ready")?;
    let errors = browser.console_errors();
    if !errors.is_empty() {
        return Err(format!(
            "{} at t = {t}: console errors: {errors:?}",
            path.display()
        ));
    }
    let shown = Shown::from_json(&state)?;
    let image = browser.screenshot()?;
    Ok((shown, image))
}

/// What the open page shows once two more frames are drawn (so that an input or a change of
/// time has reached the screen).
pub fn shown_now(browser: &mut Browser) -> Result<Shown, String> {
    let state = browser.evaluate(
        "new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(() => \
         done(window.hamelScene.state()))))",
    )?;
    Shown::from_json(&state)
}
