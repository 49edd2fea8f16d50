//! The student's page in a real browser: headless Chromium at a phone's size (390 × 844 CSS pixels,
//! touch, device scale 2) opens the page from a running `raylab class`, and a "person" joins with a
//! nickname, drags P(β, γ) with a finger, taps the outcome, reloads and comes back as the same
//! student, and sees the reveal. The teacher's side is a WebSocket client checking what arrived.
//!
//! Chromium is driven over the DevTools protocol (CDP) on a WebSocket of its own. Without Chromium
//! the test prints `skipped: …` and passes, unless `RAYLAB_WEB_TEST=require`.
//! `RAYLAB_SCREENSHOTS=1` also writes the phone's screenshot to `assets/screenshots/class-phone.png`.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use raylab::class::protocol::{QuestionState, Tally, ToClient};
use serde_json::{Value, json};
use tungstenite::stream::MaybeTlsStream;
use tungstenite::{Message, WebSocket};

use super::client::{Client, PATIENCE, Server, TempDir};
use super::teacher;

/// The phone: an iPhone 12-14's viewport in CSS pixels.
const PHONE: (u32, u32) = (390, 844);

/// Device pixels per CSS pixel.
const SCALE: u32 = 2;

/// Where the finger drags P to, as (β, γ): inside the triangle and far from the start (0.15, 0.15).
const DRAG_TO: (f64, f64) = (0.5, 0.3);

/// The browser to drive.
fn chromium() -> String {
    std::env::var("RAYLAB_CHROMIUM").unwrap_or_else(|_| "chromium".into())
}

/// Whether Chromium runs here.
fn chromium_runs() -> bool {
    Command::new(chromium())
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|status| status.success())
}

/// A headless Chromium with its own profile folder: killed (its whole process group) and the folder
/// removed when dropped, also when the test panics.
struct Browser {
    child: Child,
    profile: TempDir,
}

impl Browser {
    fn launch() -> Browser {
        use std::os::unix::process::CommandExt as _;
        let profile = TempDir::new("class-chromium");
        let child = Command::new(chromium())
            .args([
                "--headless=new",
                "--remote-debugging-port=0",
                &format!("--user-data-dir={}", profile.0.display()),
                "--no-sandbox",
                "--no-first-run",
                "--no-default-browser-check",
                "--disable-dev-shm-usage",
                "--hide-scrollbars",
                &format!("--window-size={},{}", PHONE.0, PHONE.1),
                "about:blank",
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            // Its own process group, so that its renderer and GPU processes are ended with it.
            .process_group(0)
            .spawn()
            .expect("chromium starts");
        Browser { child, profile }
    }

    /// The DevTools port, from the file Chromium writes into its profile once it listens.
    fn devtools_port(&mut self) -> u16 {
        let file = self.profile.join("DevToolsActivePort");
        let start = Instant::now();
        loop {
            if let Ok(text) = std::fs::read_to_string(&file)
                && let Some(port) = text.lines().next().and_then(|l| l.trim().parse().ok())
            {
                return port;
            }
            if let Ok(Some(status)) = self.child.try_wait() {
                panic!("chromium exited ({status}) before it listened for DevTools");
            }
            assert!(
                start.elapsed() < PATIENCE,
                "chromium wrote no {} within {PATIENCE:?}",
                file.display()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// Signals Chromium's process group (by its id, which is the browser's process id).
    fn signal(&self, signal: &str) {
        let _ = Command::new("kill")
            .args([signal, "--", &format!("-{}", self.child.id())])
            .stderr(Stdio::null())
            .status();
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        // Politely first (Chromium then ends its child processes), then for sure.
        self.signal("-TERM");
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(5) {
            if let Ok(Some(_)) = self.child.try_wait() {
                break;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        self.signal("-KILL");
        let _ = self.child.kill();
        let _ = self.child.wait();
        // The profile folder goes when `profile` drops, after this.
    }
}

/// A plain HTTP GET on 127.0.0.1; returns the body (read by its length: DevTools keeps the
/// connection open).
fn http_get(port: u16, path: &str) -> String {
    let mut stream = TcpStream::connect(("127.0.0.1", port)).expect("connect to DevTools");
    stream.set_read_timeout(Some(PATIENCE)).unwrap();
    write!(
        stream,
        "GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut response = Vec::new();
    let mut buffer = [0u8; 4096];
    loop {
        let text = String::from_utf8_lossy(&response);
        if let Some((head, body)) = text.split_once("\r\n\r\n") {
            assert!(head.starts_with("HTTP/1.1 200"), "GET {path}: {head}");
            let length = head
                .lines()
                .find_map(|l| {
                    let (name, value) = l.split_once(':')?;
                    name.eq_ignore_ascii_case("content-length")
                        .then(|| value.trim().parse::<usize>().ok())?
                })
                .unwrap_or_else(|| panic!("GET {path}: no Content-Length in {head}"));
            if body.len() >= length {
                return body.to_string();
            }
        }
        let n = stream
            .read(&mut buffer)
            .unwrap_or_else(|e| panic!("GET {path}: {e}"));
        assert!(n > 0, "GET {path}: the connection closed mid-response");
        response.extend_from_slice(&buffer[..n]);
    }
}

/// A DevTools protocol client on one page target: commands with ids, events skipped.
struct Cdp {
    socket: WebSocket<MaybeTlsStream<TcpStream>>,
    next_id: u64,
}

impl Cdp {
    /// Connects to the first page target of the browser listening on `port`.
    fn connect(port: u16) -> Cdp {
        let start = Instant::now();
        let url = loop {
            let targets: Value =
                serde_json::from_str(&http_get(port, "/json/list")).expect("a JSON target list");
            let page = targets.as_array().and_then(|targets| {
                targets
                    .iter()
                    .find(|t| t["type"] == "page")
                    .and_then(|t| t["webSocketDebuggerUrl"].as_str())
            });
            if let Some(url) = page {
                break url.to_string();
            }
            assert!(start.elapsed() < PATIENCE, "chromium shows no page target");
            std::thread::sleep(Duration::from_millis(100));
        };
        let address = url
            .trim_start_matches("ws://")
            .split('/')
            .next()
            .unwrap()
            .to_string();
        let stream = TcpStream::connect(&address).expect("connect to the page target");
        stream.set_read_timeout(Some(PATIENCE)).unwrap();
        let (socket, _) = tungstenite::client(url.as_str(), MaybeTlsStream::Plain(stream))
            .expect("a DevTools WebSocket");
        Cdp { socket, next_id: 1 }
    }

    /// Sends a command and waits for its result (events in between are skipped).
    fn call(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        let command = json!({"id": id, "method": method, "params": params});
        self.socket
            .send(Message::text(command.to_string()))
            .unwrap_or_else(|e| panic!("{method}: cannot send: {e}"));
        let start = Instant::now();
        loop {
            assert!(
                start.elapsed() < PATIENCE,
                "{method}: no reply within {PATIENCE:?}"
            );
            let message = self
                .socket
                .read()
                .unwrap_or_else(|e| panic!("{method}: waiting for its reply: {e}"));
            let Message::Text(text) = message else {
                continue;
            };
            let reply: Value = serde_json::from_str(text.as_str()).expect("DevTools sends JSON");
            if reply["id"] != id {
                continue;
            }
            if let Some(error) = reply.get("error") {
                panic!("{method} failed: {error}");
            }
            return reply["result"].clone();
        }
    }

    /// The value of a JavaScript expression in the page (promises awaited).
    fn eval(&mut self, expression: &str) -> Value {
        let result = self.call(
            "Runtime.evaluate",
            json!({"expression": expression, "returnByValue": true, "awaitPromise": true}),
        );
        if let Some(exception) = result.get("exceptionDetails") {
            panic!("{expression} threw: {exception}");
        }
        result["result"]["value"].clone()
    }

    /// Waits until `expression` is truthy in the page; returns its value.
    fn wait_for(&mut self, what: &str, expression: &str) -> Value {
        let start = Instant::now();
        loop {
            let value = self.eval(expression);
            let truthy = match &value {
                Value::Null => false,
                Value::Bool(b) => *b,
                Value::Number(n) => n.as_f64() != Some(0.0),
                Value::String(s) => !s.is_empty(),
                _ => true,
            };
            if truthy {
                return value;
            }
            assert!(
                start.elapsed() < PATIENCE,
                "the page shows no {what} within {PATIENCE:?} ({expression} is {value})"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// Waits until the element with this id reads `want`; says what it read instead.
    fn wait_for_text(&mut self, id: &str, want: &str) {
        let start = Instant::now();
        loop {
            let text = self.text(id);
            if text == want {
                return;
            }
            assert!(
                start.elapsed() < PATIENCE,
                "#{id} does not read {want:?} within {PATIENCE:?}: it reads {text:?}"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// The text of the element with this id.
    fn text(&mut self, id: &str) -> String {
        self.eval(&format!("document.getElementById({id:?}).textContent"))
            .as_str()
            .unwrap_or_default()
            .to_string()
    }

    /// Scrolls the element `selector` finds into the middle of the screen, as a person would, and
    /// returns its centre in CSS pixels of the viewport.
    /// (Chromium's taps land only once the scrolled page is drawn: two animation frames.)
    fn centre(&mut self, selector: &str) -> (f64, f64) {
        self.locate(selector, true)
    }

    /// The centre of the element `selector` finds, where it is now (no scrolling).
    fn position(&mut self, selector: &str) -> (f64, f64) {
        self.locate(selector, false)
    }

    fn locate(&mut self, selector: &str, scroll: bool) -> (f64, f64) {
        let value = self.eval(&format!(
            "(async () => {{ const e = document.querySelector({selector:?}); if (!e) return null;
                if ({scroll}) {{
                    const before = window.scrollY;
                    e.scrollIntoView({{block: 'center', inline: 'center'}});
                    if (window.scrollY !== before) await new Promise((r) => setTimeout(r, 250));
                    await new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
                }}
                const r = e.getBoundingClientRect();
                return [r.left + r.width / 2, r.top + r.height / 2]; }})()"
        ));
        let xy = value
            .as_array()
            .unwrap_or_else(|| panic!("no {selector} on the page"));
        (xy[0].as_f64().unwrap(), xy[1].as_f64().unwrap())
    }

    fn touch(&mut self, kind: &str, at: Option<(f64, f64)>) {
        let points = match at {
            Some((x, y)) => json!([{"x": x, "y": y, "radiusX": 4, "radiusY": 4, "force": 1}]),
            None => json!([]),
        };
        self.call(
            "Input.dispatchTouchEvent",
            json!({"type": kind, "touchPoints": points}),
        );
    }

    /// A finger taps the element `selector` finds, and the page gets the click. (Chromium makes the
    /// click from its gesture recogniser, which can miss a tap that comes as the page is still settling
    /// after a scroll: then the finger taps again, as a person would; never once the click came.)
    fn tap(&mut self, selector: &str) {
        for _ in 0..3 {
            let at = self.centre(selector);
            self.eval(&format!(
                "(() => {{ const e = document.querySelector({selector:?}); window.__tapped = false;
                    const seen = (c) => {{ if (e.contains(c.target)) window.__tapped = true; }};
                    document.addEventListener('click', seen, {{capture: true}});
                    window.__untap = () => document.removeEventListener('click', seen, {{capture: true}});
                    return true; }})()"
            ));
            self.touch("touchStart", Some(at));
            std::thread::sleep(Duration::from_millis(80));
            self.touch("touchEnd", None);
            let start = Instant::now();
            while start.elapsed() < Duration::from_secs(2) {
                if self.eval("window.__tapped") == true {
                    self.eval("window.__untap()");
                    return;
                }
                std::thread::sleep(Duration::from_millis(20));
            }
            self.eval("window.__untap()");
        }
        panic!("three taps on {selector} brought no click");
    }

    /// A finger presses at `from`, moves to `to` in steps, and lifts.
    fn drag(&mut self, from: (f64, f64), to: (f64, f64)) {
        const STEPS: u32 = 12;
        self.touch("touchStart", Some(from));
        for step in 1..=STEPS {
            let f = f64::from(step) / f64::from(STEPS);
            let at = (from.0 + f * (to.0 - from.0), from.1 + f * (to.1 - from.1));
            self.touch("touchMove", Some(at));
        }
        self.touch("touchEnd", None);
    }
}

/// The tally of a message, if it is one.
fn tally_of(message: &ToClient) -> Option<&Tally> {
    match message {
        ToClient::Tally(tally) => Some(tally),
        _ => None,
    }
}

/// How many picked this outcome.
fn count(tally: &Tally, outcome: &str) -> usize {
    tally
        .outcomes
        .iter()
        .find(|(name, _)| name == outcome)
        .map_or(0, |(_, n)| *n)
}

/// The value of a number input of the page (`#v0`, `#v1`).
fn value_of(cdp: &mut Cdp, id: &str) -> f64 {
    let text = cdp.eval(&format!("document.getElementById({id:?}).value"));
    let text = text.as_str().unwrap_or_default();
    text.parse()
        .unwrap_or_else(|_| panic!("#{id} holds {text:?}, not a number"))
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn a_phone_joins_drags_answers_reloads_and_sees_the_reveal() {
    let required = std::env::var("RAYLAB_WEB_TEST").is_ok_and(|v| v == "require");
    if !chromium_runs() {
        let why = format!("{} does not run (apt-get install chromium)", chromium());
        assert!(!required, "RAYLAB_WEB_TEST=require, but {why}");
        println!("skipped: {why}");
        return;
    }
    let folder = TempDir::new("class-browser");
    let server = Server::start(&folder.join("class.sqlite3"), &[]);
    // The teacher's app (egui_kittest) on the projector asks about the lecture triangle by clicking;
    // a second teacher connection reads the tallies, locks and reveals.
    let mut app = teacher::app_with(None);
    teacher::join(
        &mut app,
        "seed000-triangle",
        &server.address,
        &server.code,
        &server.key,
    );
    teacher::ask(&mut app);
    let (mut teacher, _) = Client::teacher(&server.address, &server.code, &server.key);

    let mut browser = Browser::launch();
    let port = browser.devtools_port();
    let mut cdp = Cdp::connect(port);
    cdp.call(
        "Emulation.setDeviceMetricsOverride",
        json!({"width": PHONE.0, "height": PHONE.1, "deviceScaleFactor": SCALE, "mobile": true}),
    );
    cdp.call(
        "Emulation.setTouchEmulationEnabled",
        json!({"enabled": true, "maxTouchPoints": 5}),
    );
    cdp.call("Page.enable", json!({}));
    let url = format!("http://{}/?code={}", server.address, server.code);
    cdp.call("Page.navigate", json!({"url": url}));

    // The code is filled in from the link; the person types a nickname and taps Join.
    let code = cdp.wait_for(
        "the join form with the code",
        "document.readyState === 'complete' && document.getElementById('code').value",
    );
    assert_eq!(code, server.code.as_str());
    cdp.tap("#nick");
    cdp.wait_for(
        "the nickname field focused",
        "document.activeElement.id === 'nick'",
    );
    cdp.call("Input.insertText", json!({"text": "Ada"}));
    cdp.tap("#joinButton");
    let prompt = cdp.wait_for(
        "the question's prompt",
        "!document.getElementById('main').classList.contains('hidden') \
         && document.getElementById('prompt').textContent.startsWith('Q1.') \
         && document.getElementById('prompt').textContent",
    );
    assert!(
        prompt
            .as_str()
            .is_some_and(|p| p.starts_with("Q1. Where does the ray meet the triangle?")),
        "{prompt}"
    );
    assert!(
        cdp.text("who").contains("you are Ada"),
        "{}",
        cdp.text("who")
    );
    // The figure's labels (A, B, C, P) are small beside it, not letters as tall as the triangle.
    let tallest = cdp.eval(
        "Math.max(...Array.from(document.querySelectorAll('#figure text'))
           .map((t) => t.getBoundingClientRect().height))
         / document.getElementById('figure').getBoundingClientRect().height",
    );
    let tallest = tallest.as_f64().unwrap();
    assert!(
        tallest > 0.0 && tallest < 0.12,
        "a label of the figure is {:.0}% of its height",
        tallest * 100.0
    );
    let start = (value_of(&mut cdp, "v0"), value_of(&mut cdp, "v1"));
    assert_eq!(start, (0.15, 0.15), "P starts near A, not at an answer");

    // A finger that slides off the figure keeps the handle, at the figure's edge, and lets go of it
    // there: a later swipe across the figure, away from the handle, does not move it.
    let from = cdp.centre("#figure circle.handle");
    let figure = cdp.eval(
        "(() => { const r = document.getElementById('figure').getBoundingClientRect();
           return [r.left, r.top, r.right, r.bottom]; })()",
    );
    let edge = |i: usize| figure[i].as_f64().unwrap();
    let (left, top, bottom) = (edge(0), edge(1), edge(3));
    cdp.drag(from, (from.0, bottom + 40.0));
    let off = (value_of(&mut cdp, "v0"), value_of(&mut cdp, "v1"));
    assert!(
        off.1 < -0.2,
        "the handle did not follow the finger off the figure: {off:?}"
    );
    let held = cdp.position("#figure circle.handle");
    assert!(
        (left..edge(2)).contains(&held.0) && (top..bottom).contains(&held.1),
        "the handle left the figure: it is at {held:?}, the figure is {figure}"
    );
    cdp.drag((left + 20.0, top + 20.0), (left + 60.0, top + 40.0));
    let after_swipe = (value_of(&mut cdp, "v0"), value_of(&mut cdp, "v1"));
    assert_eq!(
        after_swipe, off,
        "a swipe away from the handle moved it: the drag that ended off the figure never ended"
    );

    // The finger drags P(β, γ) from its centre to another point of the triangle: the triangle's
    // corners on screen (A, B, C of the drawn polygon) place the point by its β and γ.
    let from = cdp.centre("#figure circle.handle");
    let corners = cdp.eval(
        "(() => { const p = document.querySelector('#figure polygon'); const m = p.getScreenCTM();
           return Array.from(p.points).map((q) => { const s = q.matrixTransform(m); return [s.x, s.y]; }); })()",
    );
    let corner = |i: usize| {
        let xy = &corners[i];
        (xy[0].as_f64().unwrap(), xy[1].as_f64().unwrap())
    };
    let (a, b, c) = (corner(0), corner(1), corner(2));
    let to = (
        a.0 + DRAG_TO.0 * (b.0 - a.0) + DRAG_TO.1 * (c.0 - a.0),
        a.1 + DRAG_TO.0 * (b.1 - a.1) + DRAG_TO.1 * (c.1 - a.1),
    );
    cdp.drag(from, to);
    let dragged = (value_of(&mut cdp, "v0"), value_of(&mut cdp, "v1"));
    println!("dragged P from {start:?} to (β, γ) = {dragged:?}");
    for (got, want, name) in [(dragged.0, DRAG_TO.0, "β"), (dragged.1, DRAG_TO.1, "γ")] {
        assert!(
            (got - want).abs() < 0.02,
            "the drag moved {name} to {got}, not near {want}"
        );
    }
    let moved = cdp.position("#figure circle.handle");
    assert!(
        (moved.0 - to.0).hypot(moved.1 - to.1) < 3.0,
        "the handle is drawn at {moved:?}, not under the finger at {to:?}"
    );

    // One tap on "hit" sends the answer; the server acknowledges it.
    cdp.tap("#outcomes button:nth-child(1)");
    assert_eq!(
        cdp.eval("document.querySelector('#outcomes button:nth-child(1)').textContent"),
        "hit"
    );
    cdp.wait_for_text("status", "Saved ✓");

    // The teacher's app counts the phone's answer and draws it in the Triangle view's cloud.
    teacher::step_until(&mut app, "the phone's answer counted", |h| {
        teacher::shows(h, "1 answered")
    });
    assert_eq!(raylab::app::class_view::cloud_drawn(&app.ctx), 1);

    // The teacher's tally has the answer with the dragged values.
    let message = teacher.recv_until("a tally with the phone's answer", |m| {
        tally_of(m).is_some_and(|t| t.answered == 1)
    });
    let tally = tally_of(&message).unwrap();
    assert_eq!(count(tally, "hit"), 1, "{tally:?}");
    assert_eq!(tally.joined, 1);
    let prediction = &tally.predictions[0];
    assert_eq!(prediction.outcome.as_deref(), Some("hit"));
    let values: Vec<f64> = prediction
        .values
        .iter()
        .take(2)
        .map(|v| v.unwrap())
        .collect();
    assert!(
        (values[0] - dragged.0).abs() < 1e-12 && (values[1] - dragged.1).abs() < 1e-12,
        "the teacher got {values:?}, the page shows {dragged:?}"
    );
    assert!(values.iter().all(|v| (v - 0.15).abs() > 1e-6));
    assert_eq!(prediction.values.get(2), Some(&None), "t was not given");

    // A reload: the page remembers the code; the person taps Join and is the same student, with
    // the answer given.
    cdp.call("Page.reload", json!({}));
    cdp.wait_for(
        "the join form after the reload",
        "document.readyState === 'complete' \
         && !document.getElementById('join').classList.contains('hidden') \
         && document.getElementById('code').value",
    );
    cdp.tap("#joinButton");
    cdp.wait_for(
        "the answer given before the reload",
        "!document.getElementById('main').classList.contains('hidden') \
         && document.querySelector('#outcomes button[aria-pressed=true]')?.textContent === 'hit'",
    );
    assert_eq!(
        (value_of(&mut cdp, "v0"), value_of(&mut cdp, "v1")),
        dragged
    );
    assert_eq!(cdp.text("status"), "Saved ✓");

    // Lock: a tally made after it (so after the re-join) still counts one student.
    teacher.send(json!({"type": "lock"}));
    teacher.recv_until(
        "the locked question",
        |m| matches!(m, ToClient::Question { question } if question.state == QuestionState::Locked),
    );
    let message = teacher.recv_until("a tally after the lock", |m| tally_of(m).is_some());
    let tally = tally_of(&message).unwrap();
    assert_eq!(
        (tally.joined, tally.connected, tally.answered),
        (1, 1, 1),
        "the reloaded page is the same student: {tally:?}"
    );
    cdp.wait_for(
        "the locked answers",
        "document.getElementById('status').textContent.startsWith('Answers are locked')",
    );

    // Reveal: the page says whether the dragged point was right.
    teacher.send(json!({"type": "reveal"}));
    let verdict = cdp.wait_for(
        "the reveal",
        "!document.getElementById('revealCard').classList.contains('hidden') \
         && document.getElementById('verdict').textContent",
    );
    let third = 1.0 / 3.0;
    let right = (dragged.0 - third).abs() <= 0.05 && (dragged.1 - third).abs() <= 0.05;
    assert_eq!(
        verdict,
        if right {
            "Right ✓"
        } else {
            "Not this time ✗"
        },
        "dragged to {dragged:?}"
    );
    assert!(
        cdp.text("truth").starts_with("hit"),
        "{}",
        cdp.text("truth")
    );
    let status = cdp.text("status");
    assert!(
        !status.contains("wait for the reveal"),
        "after the reveal the page still says {status:?}"
    );
    // The true point is ringed on the figure.
    assert_eq!(
        cdp.eval("document.querySelectorAll('#figure circle.truth').length"),
        1
    );

    // The phone's screen from the top (the question, the figure with the dragged P and the true point
    // ringed, the values and the outcome picked): not blank.
    cdp.eval("window.scrollTo(0, 0)");
    let shot = cdp.call("Page.captureScreenshot", json!({"format": "png"}));
    let png = decode_base64(shot["data"].as_str().expect("screenshot data"));
    let image = image::load_from_memory(&png)
        .expect("a PNG screenshot")
        .to_rgba8();
    assert_eq!(
        image.dimensions(),
        (PHONE.0 * SCALE, PHONE.1 * SCALE),
        "the screenshot is the phone's screen"
    );
    let colours: std::collections::HashSet<[u8; 3]> =
        image.pixels().map(|p| [p[0], p[1], p[2]]).collect();
    println!("phone screenshot: {} colours", colours.len());
    assert!(colours.len() > 50, "the screenshot is blank");
    if std::env::var("RAYLAB_SCREENSHOTS").is_ok_and(|v| v == "1") {
        let path: PathBuf = root().join("assets/screenshots/class-phone.png");
        std::fs::write(&path, &png).unwrap();
        println!("wrote {}", path.display());
    }

    // The next question is about two segments (they cross at t = s = 1/2): the reveal clears, the
    // phone drags A(t) along segment A, taps "hit", and the teacher's tally holds the dragged t.
    let segments = raylab::class::protocol::QuestionSpec {
        kind: "segments".into(),
        prompt: "Where do the segments cross?".into(),
        inputs: [["0", "0"], ["4", "4"], ["0", "4"], ["4", "0"]]
            .iter()
            .map(|p| p.iter().map(|c| c.to_string()).collect())
            .collect(),
    };
    teacher.send(json!({"type": "ask", "question": segments}));
    cdp.wait_for(
        "the segments question",
        "document.getElementById('prompt').textContent.includes('segments cross') \
         && document.getElementById('revealCard').classList.contains('hidden') \
         && document.querySelectorAll('#figure circle.handle').length === 2",
    );
    let handle = "#figure circle.handle[aria-label='A(t)']";
    let from = cdp.centre(handle);
    cdp.drag(from, (from.0 + 30.0, from.1 - 30.0));
    let t = value_of(&mut cdp, "v0");
    assert!(
        (t - 0.5).abs() > 0.01,
        "A(t) moved along its segment (t = {t})"
    );
    assert_eq!(value_of(&mut cdp, "v1"), 0.8, "B(s) stayed");
    cdp.tap("#outcomes button:nth-child(1)");
    cdp.wait_for_text("status", "Saved ✓");
    let tally = teacher.recv_until("the segments answer", |m| {
        tally_of(m).is_some_and(|t| t.answered == 1 && t.outcomes.len() == 5)
    });
    let prediction = &tally_of(&tally).unwrap().predictions[0];
    assert_eq!(
        prediction.values[0],
        Some(t),
        "the tally holds the dragged t"
    );
    drop(cdp);
    drop(browser);
}

/// Standard base64 (as CDP sends binary data) to bytes.
fn decode_base64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let bytes: Vec<u8> = text
        .bytes()
        .filter(|c| !c.is_ascii_whitespace() && *c != b'=')
        .collect();
    let mut out = Vec::with_capacity(bytes.len() * 3 / 4);
    for chunk in bytes.chunks(4) {
        let mut n = 0u32;
        for (i, &c) in chunk.iter().enumerate() {
            n |= u32::from(value(c)) << (18 - 6 * i);
        }
        let len = chunk.len() * 6 / 8;
        out.extend_from_slice(&n.to_be_bytes()[1..1 + len]);
    }
    out
}
