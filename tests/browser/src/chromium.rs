//! Headless Chromium, driven over the DevTools protocol on a pipe (`--remote-debugging-pipe`:
//! the browser reads commands on its file descriptor 3 and writes replies and events on 4,
//! each message a JSON text ended by a NUL byte). No port is opened and nothing is fetched.

use std::io::{BufRead, BufReader, Write};
use std::os::fd::{FromRawFd, OwnedFd};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError, channel};
use std::time::{Duration, Instant};

use base64::Engine as _;
use serde_json::{Value, json};

/// How to get Chromium, for the message of a skipped test.
pub const INSTALL: &str = "install Debian's Chromium (`apt-get install -y chromium`), or set \
                           CHROMIUM to a Chromium or Chrome executable";

/// How long any one command may take before the browser is given up on.
const TIMEOUT: Duration = Duration::from_secs(90);

/// The flags every run starts Chromium with: headless, no sandbox (CI runs as root), no
/// network of its own, WebGL rendered in software by SwiftShader.
const FLAGS: &[&str] = &[
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--hide-scrollbars",
    "--mute-audio",
    "--remote-debugging-pipe",
];

/// The Chromium to use: `$CHROMIUM`, else the first of Debian's `chromium`, `chromium-browser`
/// and `google-chrome` on the `PATH`. `CHROMIUM=` (set but empty) means none, to run without
/// one where one is installed.
pub fn find() -> Option<PathBuf> {
    if let Some(path) = std::env::var_os("CHROMIUM") {
        return (!path.is_empty()).then(|| PathBuf::from(path));
    }
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .flat_map(|dir| {
            ["chromium", "chromium-browser", "google-chrome"]
                .into_iter()
                .map(move |name| dir.join(name))
        })
        .find(|p| p.is_file())
}

/// A console message or an uncaught exception of a page.
#[derive(Clone, Debug, PartialEq)]
pub struct ConsoleError(pub String);

/// A running headless Chromium with one page attached.
pub struct Browser {
    child: Child,
    commands: std::fs::File,
    replies: Receiver<Value>,
    session: String,
    next_id: u64,
    /// Events received while waiting for replies, oldest first.
    events: Vec<Value>,
    profile: PathBuf,
}

impl Browser {
    /// Starts `executable` with a fresh profile and a viewport of `width` × `height` CSS
    /// pixels at one device pixel per CSS pixel.
    pub fn launch(executable: &Path, width: u32, height: u32) -> Result<Browser, String> {
        let profile = std::env::temp_dir().join(format!(
            "hamel-chromium-{}-{}",
            std::process::id(),
            unique()
        ));
        std::fs::create_dir_all(&profile).map_err(|e| format!("{}: {e}", profile.display()))?;
        let (to_browser_read, to_browser_write) = pipe()?;
        let (from_browser_read, from_browser_write) = pipe()?;
        let (fd3, fd4) = (raw(&to_browser_read), raw(&from_browser_write));
        let mut command = Command::new(executable);
        command
            .args(FLAGS)
            .arg(format!("--user-data-dir={}", profile.display()))
            .arg(format!("--window-size={width},{height}"))
            .arg("about:blank")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null());
        // SAFETY: between fork and exec only async-signal-safe calls (fcntl, dup2) run. The
        // pipe's ends are first copied above 10, so that moving them onto 3 and 4 cannot
        // close one with the other.
        unsafe {
            command.pre_exec(move || {
                let a = libc::fcntl(fd3, libc::F_DUPFD, 10);
                let b = libc::fcntl(fd4, libc::F_DUPFD, 10);
                if a < 0 || b < 0 || libc::dup2(a, 3) < 0 || libc::dup2(b, 4) < 0 {
                    return Err(std::io::Error::last_os_error());
                }
                Ok(())
            });
        }
        let child = command
            .spawn()
            .map_err(|e| format!("cannot start {}: {e}", executable.display()))?;
        drop((to_browser_read, from_browser_write));
        let (sender, replies) = channel();
        let reader = std::fs::File::from(from_browser_read);
        std::thread::spawn(move || {
            let mut reader = BufReader::new(reader);
            let mut message = Vec::new();
            while reader.read_until(0, &mut message).is_ok_and(|n| n > 0) {
                message.pop();
                if let Ok(value) = serde_json::from_slice::<Value>(&message) {
                    if sender.send(value).is_err() {
                        break;
                    }
                }
                message.clear();
            }
        });
        let mut browser = Browser {
            child,
            commands: std::fs::File::from(to_browser_write),
            replies,
            session: String::new(),
            next_id: 0,
            events: Vec::new(),
            profile,
        };
        browser.attach(width, height)?;
        Ok(browser)
    }

    /// Attaches to the page Chromium opened and sets its viewport.
    fn attach(&mut self, width: u32, height: u32) -> Result<(), String> {
        let targets = self.call("Target.getTargets", json!({}), false)?;
        let page = targets["targetInfos"]
            .as_array()
            .and_then(|all| all.iter().find(|t| t["type"] == "page"))
            .and_then(|t| t["targetId"].as_str())
            .ok_or("Chromium opened no page")?
            .to_string();
        let attached = self.call(
            "Target.attachToTarget",
            json!({ "targetId": page, "flatten": true }),
            false,
        )?;
        self.session = attached["sessionId"]
            .as_str()
            .ok_or("no session")?
            .to_string();
        for domain in ["Page.enable", "Runtime.enable", "Log.enable"] {
            self.call(domain, json!({}), true)?;
        }
        self.call(
            "Emulation.setDeviceMetricsOverride",
            json!({ "width": width, "height": height, "deviceScaleFactor": 1, "mobile": false }),
            true,
        )?;
        Ok(())
    }

    /// Sends a command (to the page's session, or to the browser) and waits for its reply.
    fn call(&mut self, method: &str, params: Value, page: bool) -> Result<Value, String> {
        self.next_id += 1;
        let id = self.next_id;
        let mut message = json!({ "id": id, "method": method, "params": params });
        if page {
            message["sessionId"] = Value::from(self.session.clone());
        }
        let mut bytes = serde_json::to_vec(&message).map_err(|e| e.to_string())?;
        bytes.push(0);
        self.commands
            .write_all(&bytes)
            .map_err(|e| format!("{method}: cannot reach Chromium: {e}"))?;
        let deadline = Instant::now() + TIMEOUT;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.replies.recv_timeout(left) {
                Ok(reply) if reply["id"] == id => {
                    if let Some(error) = reply.get("error") {
                        return Err(format!("{method}: {error}"));
                    }
                    return Ok(reply["result"].clone());
                }
                Ok(event) => self.events.push(event),
                Err(RecvTimeoutError::Timeout) => {
                    return Err(format!("{method}: no reply in {TIMEOUT:?}"));
                }
                Err(RecvTimeoutError::Disconnected) => {
                    return Err(format!("{method}: Chromium closed the pipe"));
                }
            }
        }
    }

    /// Waits for an event of the page called `method`.
    fn wait_for(&mut self, method: &str) -> Result<Value, String> {
        if let Some(at) = self.events.iter().position(|e| e["method"] == method) {
            return Ok(self.events.remove(at));
        }
        let deadline = Instant::now() + TIMEOUT;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.replies.recv_timeout(left) {
                Ok(event) if event["method"] == method => return Ok(event),
                Ok(event) => self.events.push(event),
                Err(_) => return Err(format!("no {method} in {TIMEOUT:?}")),
            }
        }
    }

    /// Opens `url` in the page afresh and waits for its load event. (The page goes through
    /// `about:blank` first: a URL that differs from the current one only in its fragment would
    /// otherwise not load again.)
    pub fn open(&mut self, url: &str) -> Result<(), String> {
        for target in ["about:blank", url] {
            self.events.clear();
            let navigated = self.call("Page.navigate", json!({ "url": target }), true)?;
            if let Some(error) = navigated.get("errorText") {
                return Err(format!("cannot open {target}: {error}"));
            }
            self.wait_for("Page.loadEventFired")?;
        }
        Ok(())
    }

    /// Evaluates a JavaScript expression in the page, awaiting it if it is a promise, and
    /// returns its value (JSON).
    pub fn evaluate(&mut self, expression: &str) -> Result<Value, String> {
        let result = self.call(
            "Runtime.evaluate",
            json!({ "expression": expression, "awaitPromise": true, "returnByValue": true }),
            true,
        )?;
        if let Some(details) = result.get("exceptionDetails") {
            return Err(format!("`{expression}` threw: {details}"));
        }
        Ok(result["result"]["value"].clone())
    }

    /// Drags the mouse from `from` to `to` (CSS pixels in the viewport) with `button`
    /// (`"left"`, `"right"`) held, in `steps` moves, as a user's hand does.
    pub fn drag(
        &mut self,
        from: (f64, f64),
        to: (f64, f64),
        button: &str,
        steps: usize,
    ) -> Result<(), String> {
        let buttons = if button == "right" { 2 } else { 1 };
        let event = |kind: &str, (x, y): (f64, f64), held: u32| {
            json!({ "type": kind, "x": x, "y": y, "button": button, "buttons": held,
                    "clickCount": 1 })
        };
        self.call(
            "Input.dispatchMouseEvent",
            event("mouseMoved", from, 0),
            true,
        )?;
        self.call(
            "Input.dispatchMouseEvent",
            event("mousePressed", from, buttons),
            true,
        )?;
        for k in 1..=steps.max(1) {
            let f = k as f64 / steps.max(1) as f64;
            let at = (from.0 + f * (to.0 - from.0), from.1 + f * (to.1 - from.1));
            self.call(
                "Input.dispatchMouseEvent",
                event("mouseMoved", at, buttons),
                true,
            )?;
        }
        self.call(
            "Input.dispatchMouseEvent",
            event("mouseReleased", to, 0),
            true,
        )?;
        Ok(())
    }

    /// A screenshot of the viewport, decoded.
    pub fn screenshot(&mut self) -> Result<Image, String> {
        let shot = self.call("Page.captureScreenshot", json!({ "format": "png" }), true)?;
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(shot["data"].as_str().ok_or("no screenshot data")?)
            .map_err(|e| e.to_string())?;
        Image::decode(&bytes)
    }

    /// The CPU time (user and system, milliseconds) the browser's processes have used so
    /// far, by process type (`browser`, `renderer`, `gpu-process`, …), read from `/proc`:
    /// the browser's process and its descendants.
    pub fn cpu_times(&self) -> Vec<(String, f64)> {
        // (pid, parent, type, milliseconds) of every process.
        let processes: Vec<(u32, u32, String, f64)> = std::fs::read_dir("/proc")
            .into_iter()
            .flatten()
            .flatten()
            .filter_map(|entry| {
                let pid: u32 = entry.file_name().to_str()?.parse().ok()?;
                let stat = std::fs::read_to_string(entry.path().join("stat")).ok()?;
                // After the command's closing parenthesis: state, ppid, …, utime and stime
                // (the 12th and 13th), in clock ticks of 10 ms.
                let fields: Vec<&str> = stat.rsplit(')').next()?.split_whitespace().collect();
                let parent: u32 = fields.get(1)?.parse().ok()?;
                let user: f64 = fields.get(11)?.parse().ok()?;
                let system: f64 = fields.get(12)?.parse().ok()?;
                let command =
                    std::fs::read_to_string(entry.path().join("cmdline")).unwrap_or_default();
                let kind = command
                    .split(['\0', ' '])
                    .find_map(|a| a.strip_prefix("--type="))
                    .unwrap_or("browser")
                    .to_string();
                Some((pid, parent, kind, 10.0 * (user + system)))
            })
            .collect();
        let mut family = vec![self.child.id()];
        let mut next = 0;
        while next < family.len() {
            let pid = family[next];
            family.extend(processes.iter().filter(|p| p.1 == pid).map(|p| p.0));
            next += 1;
        }
        let mut totals: Vec<(String, f64)> = Vec::new();
        for (_, _, kind, ms) in processes.iter().filter(|p| family.contains(&p.0)) {
            match totals.iter_mut().find(|(k, _)| k == kind) {
                Some((_, total)) => *total += ms,
                None => totals.push((kind.clone(), *ms)),
            }
        }
        totals
    }

    /// The console errors and uncaught exceptions of the page since it was opened, with
    /// every event received so far.
    pub fn console_errors(&mut self) -> Vec<ConsoleError> {
        while let Ok(event) = self.replies.try_recv() {
            self.events.push(event);
        }
        self.events
            .iter()
            .filter_map(|e| {
                let p = &e["params"];
                match e["method"].as_str()? {
                    "Runtime.exceptionThrown" => Some(p["exceptionDetails"].to_string()),
                    "Runtime.consoleAPICalled" if p["type"] == "error" || p["type"] == "assert" => {
                        Some(p["args"].to_string())
                    }
                    "Log.entryAdded" if p["entry"]["level"] == "error" => {
                        Some(p["entry"].to_string())
                    }
                    _ => None,
                }
            })
            .map(ConsoleError)
            .collect()
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.call("Browser.close", json!({}), false);
        let deadline = Instant::now() + Duration::from_secs(10);
        while Instant::now() < deadline {
            if let Ok(Some(_)) = self.child.try_wait() {
                break;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = std::fs::remove_dir_all(&self.profile);
    }
}

/// An RGBA screenshot.
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub rgba: Vec<u8>,
}

impl Image {
    fn decode(bytes: &[u8]) -> Result<Image, String> {
        let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        decoder.set_transformations(png::Transformations::EXPAND);
        let mut reader = decoder.read_info().map_err(|e| e.to_string())?;
        let mut buffer = vec![0; reader.output_buffer_size().ok_or("image too large")?];
        let info = reader.next_frame(&mut buffer).map_err(|e| e.to_string())?;
        let (width, height) = (info.width as usize, info.height as usize);
        let rgba = match info.color_type {
            png::ColorType::Rgba => buffer[..width * height * 4].to_vec(),
            png::ColorType::Rgb => buffer[..width * height * 3]
                .chunks(3)
                .flat_map(|p| [p[0], p[1], p[2], 255])
                .collect(),
            other => return Err(format!("unexpected screenshot colour type {other:?}")),
        };
        Ok(Image {
            width,
            height,
            rgba,
        })
    }

    /// The pixel at (x, y), if inside.
    pub fn pixel(&self, x: i64, y: i64) -> Option<[u8; 3]> {
        if x < 0 || y < 0 || x as usize >= self.width || y as usize >= self.height {
            return None;
        }
        let at = 4 * (y as usize * self.width + x as usize);
        Some([self.rgba[at], self.rgba[at + 1], self.rgba[at + 2]])
    }

    /// The image as PNG bytes (RGB).
    pub fn png(&self) -> Result<Vec<u8>, String> {
        let mut out = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut out, self.width as u32, self.height as u32);
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
            let rgb: Vec<u8> = self
                .rgba
                .chunks(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect();
            writer.write_image_data(&rgb).map_err(|e| e.to_string())?;
        }
        Ok(out)
    }
}

fn unique() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNT: AtomicU64 = AtomicU64::new(0);
    COUNT.fetch_add(1, Ordering::Relaxed)
}

/// A pipe whose ends close on exec (the child gets copies on 3 and 4 only).
fn pipe() -> Result<(OwnedFd, OwnedFd), String> {
    let mut fds = [0; 2];
    // SAFETY: `fds` has room for the two descriptors pipe2 writes.
    if unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) } != 0 {
        return Err(format!("pipe: {}", std::io::Error::last_os_error()));
    }
    // SAFETY: pipe2 succeeded, so both are open descriptors this process owns.
    Ok(unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) })
}

fn raw(fd: &OwnedFd) -> i32 {
    use std::os::fd::AsRawFd;
    fd.as_raw_fd()
}
