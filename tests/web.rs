//! raylab in a real browser: builds the web page with `assets/web/build-web.sh`, serves it on 127.0.0.1,
//! opens it in headless Chromium (software WebGL through SwiftShader) and checks from screenshots
//! that the app drew, that `?preset=` and `?view=` open what they name, and that the state persists
//! in the browser's local storage.
//!
//! It needs the wasm32-unknown-unknown target, wasm-bindgen-cli at Cargo.lock's version of
//! wasm-bindgen, and Chromium (`.ci/run` installs them when it can). Without one of them it prints
//! `skipped: <why>` and passes, unless `RAYLAB_WEB_TEST=require`, which `.ci/run` sets once it has
//! installed them, so that a missing tool there is a failure, not a silent skip.
//!
//! `RAYLAB_SCREENSHOTS=1 cargo test --test web` also writes `assets/screenshots/web.png`.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use image::{Rgba, RgbaImage};

/// The window Chromium draws into: the projector size the desktop app opens at.
const SIZE: (u32, u32) = (1280, 800);

/// The central view, left of the step panel and under the top bar.
const VIEW: (u32, u32, u32, u32) = (0, 64, 840, 800);

/// egui's panel colours (light and dark themes): most of a drawn app is one of them.
const PANEL_FILLS: [[u8; 3]; 2] = [[248, 248, 248], [27, 27, 27]];

/// The page's own background (assets/web/index.html), which the app's canvas covers.
const PAGE_BACKGROUNDS: [[u8; 3]; 2] = [[0xe4, 0xe4, 0xe4], [0x0c, 0x0c, 0x0c]];

/// The error box's text colour (assets/web/index.html).
const ERROR_RED: [u8; 3] = [0xb0, 0x00, 0x20];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Runs a command and returns its standard output, or `None` if it cannot run or fails.
fn output(program: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(program)
        .args(args)
        .stderr(Stdio::null())
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The version of the wasm-bindgen crate in Cargo.lock.
fn locked_wasm_bindgen() -> String {
    let lock = std::fs::read_to_string(root().join("Cargo.lock")).expect("Cargo.lock");
    let mut lines = lock.lines();
    while let Some(line) = lines.next() {
        if line == "name = \"wasm-bindgen\"" {
            let version = lines.next().expect("a version line");
            return version
                .trim_start_matches("version = ")
                .trim_matches('"')
                .to_string();
        }
    }
    panic!("Cargo.lock has no wasm-bindgen");
}

/// The browser to drive.
fn chromium() -> String {
    std::env::var("RAYLAB_CHROMIUM").unwrap_or_else(|_| "chromium".into())
}

/// Why the test cannot run here, if it cannot.
fn missing_tool() -> Option<String> {
    let sysroot = output("rustc", &["--print", "sysroot"])?;
    let wasm_std = Path::new(sysroot.trim()).join("lib/rustlib/wasm32-unknown-unknown/lib");
    if !wasm_std.is_dir() {
        return Some(
            "the wasm32-unknown-unknown target is not installed \
             (rustup target add wasm32-unknown-unknown)"
                .into(),
        );
    }
    let wanted = locked_wasm_bindgen();
    let found = output("wasm-bindgen", &["--version"]).unwrap_or_default();
    if found.split_whitespace().nth(1) != Some(wanted.as_str()) {
        return Some(format!(
            "wasm-bindgen {wanted} is not installed (found: {}; cargo install --locked \
             wasm-bindgen-cli --version {wanted})",
            if found.is_empty() {
                "none"
            } else {
                found.trim()
            }
        ));
    }
    if output(&chromium(), &["--version"]).is_none() {
        return Some(format!(
            "{} does not run (apt-get install chromium)",
            chromium()
        ));
    }
    None
}

/// Serves the files of `site` on 127.0.0.1 (a port of its own) from a background thread, for a
/// bounded number of connections; returns the base URL.
fn serve(site: PathBuf) -> String {
    let listener = TcpListener::bind("127.0.0.1:0").expect("a local port");
    let address = listener.local_addr().unwrap();
    std::thread::Builder::new()
        .name("web-test-server".into())
        .spawn(move || {
            for stream in listener.incoming().take(2000).flatten() {
                let site = site.clone();
                std::thread::spawn(move || respond(stream, &site));
            }
        })
        .unwrap();
    format!("http://{address}")
}

/// Answers one request: GET of a file in the site, or 404.
fn respond(stream: TcpStream, site: &Path) {
    let _ = stream.set_read_timeout(Some(Duration::from_secs(10)));
    let mut reader = BufReader::new(&stream);
    let mut request = String::new();
    if reader.read_line(&mut request).is_err() {
        return;
    }
    // Skip the headers.
    let mut line = String::new();
    while reader.read_line(&mut line).is_ok_and(|n| n > 2) {
        line.clear();
    }
    let path = request.split_whitespace().nth(1).unwrap_or("/");
    let path = path
        .split('?')
        .next()
        .unwrap_or("/")
        .trim_start_matches('/');
    let path = if path.is_empty() { "index.html" } else { path };
    let file = site.join(path);
    let body = (!path.contains(".."))
        .then(|| std::fs::read(&file).ok())
        .flatten();
    let mut stream = &stream;
    let _ = match body {
        Some(body) => {
            let kind = match file.extension().and_then(|e| e.to_str()) {
                Some("html") => "text/html; charset=utf-8",
                Some("js") => "text/javascript",
                Some("wasm") => "application/wasm",
                _ => "application/octet-stream",
            };
            write!(
                stream,
                "HTTP/1.1 200 OK\r\nContent-Type: {kind}\r\nContent-Length: {}\r\n\
                 Connection: close\r\n\r\n",
                body.len()
            )
            .and_then(|()| stream.write_all(&body))
        }
        None => write!(
            stream,
            "HTTP/1.1 404 Not Found\r\nContent-Length: 0\r\nConnection: close\r\n\r\n"
        ),
    };
    let _ = stream.flush();
    let _ = stream.read(&mut [0; 1]);
}

/// Opens `url` in headless Chromium with its own profile folder (its local storage) and returns the
/// screenshot. Chromium's virtual time runs the page for `budget_ms` without waiting for it.
fn screenshot(url: &str, profile: &Path, budget_ms: u32, name: &str) -> RgbaImage {
    let png = profile.with_file_name(format!("{name}.png"));
    let _ = std::fs::remove_file(&png);
    let mut child = Command::new(chromium())
        .args([
            "--headless=new",
            "--no-sandbox",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--disable-dev-shm-usage",
            "--no-first-run",
            "--no-default-browser-check",
            "--hide-scrollbars",
            &format!("--user-data-dir={}", profile.display()),
            &format!("--window-size={},{}", SIZE.0, SIZE.1),
            &format!("--virtual-time-budget={budget_ms}"),
            &format!("--screenshot={}", png.display()),
            url,
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("chromium starts");
    let started = Instant::now();
    loop {
        if child.try_wait().expect("chromium runs").is_some() {
            break;
        }
        if started.elapsed() > Duration::from_secs(180) {
            let _ = child.kill();
            panic!("chromium took more than 3 minutes on {url}");
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    let image = image::open(&png)
        .unwrap_or_else(|e| panic!("no screenshot of {url}: {e}"))
        .to_rgba8();
    assert_eq!(image.dimensions(), SIZE, "screenshot of {url}");
    image
}

/// The share of pixels of any of these colours.
fn share_of(image: &RgbaImage, colours: &[[u8; 3]]) -> f64 {
    let count = image
        .pixels()
        .filter(|Rgba([r, g, b, _])| colours.contains(&[*r, *g, *b]))
        .count();
    count as f64 / image.pixels().len() as f64
}

/// Asserts that the app drew: the page is mostly egui's panels, in many colours (text, plots, the
/// palette), with neither the bare page nor the error box showing.
fn assert_drawn(image: &RgbaImage, what: &str) {
    let colours: std::collections::HashSet<[u8; 3]> = image
        .pixels()
        .map(|Rgba([r, g, b, _])| [*r, *g, *b])
        .collect();
    let panels = share_of(image, &PANEL_FILLS);
    let page = share_of(image, &PAGE_BACKGROUNDS);
    let error = share_of(image, &[ERROR_RED]);
    println!(
        "{what}: {} colours, {:.0}% panel, {:.1}% bare page, {:.2}% error red",
        colours.len(),
        panels * 100.0,
        page * 100.0,
        error * 100.0
    );
    assert!(
        colours.len() > 300,
        "{what}: too few colours, nothing drawn"
    );
    assert!(panels > 0.3, "{what}: egui's panels are missing");
    assert!(page < 0.02, "{what}: the bare page shows");
    assert!(error < 0.0005, "{what}: the error box shows");
}

/// The share of pixels in the central view that differ clearly between two screenshots.
fn view_difference(a: &RgbaImage, b: &RgbaImage) -> f64 {
    let (x0, y0, x1, y1) = VIEW;
    let mut differ = 0;
    for y in y0..y1 {
        for x in x0..x1 {
            let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
            let distance: i32 = (0..3).map(|i| (p[i] as i32 - q[i] as i32).abs()).sum();
            differ += usize::from(distance > 48);
        }
    }
    differ as f64 / ((x1 - x0) * (y1 - y0)) as f64
}

#[test]
fn the_web_page_draws_the_app_and_its_url_opens_a_preset_and_a_view() {
    let required = std::env::var("RAYLAB_WEB_TEST").is_ok_and(|v| v == "require");
    if let Some(why) = missing_tool() {
        assert!(!required, "RAYLAB_WEB_TEST=require, but {why}");
        println!("skipped: {why}");
        return;
    }
    let work = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("web-test");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).unwrap();
    let site = work.join("site");

    let clock = Instant::now();
    let status = Command::new("bash")
        .arg(root().join("assets/web/build-web.sh"))
        .arg(&site)
        .current_dir(root())
        .status()
        .expect("bash runs");
    assert!(status.success(), "assets/web/build-web.sh failed");
    println!("site built in {:.0} s", clock.elapsed().as_secs_f64());

    let base = serve(site);
    let clock = Instant::now();
    let profile = |name: &str| work.join(format!("profile-{name}"));

    // The default page: the Segments view of a first visit.
    let first = screenshot(&base, &profile("first"), 10_000, "first");
    assert_drawn(&first, "first visit");

    // A link to a preset opens the Triangle view with that ray; a link to a view opens it.
    // A first visit to `base/query`, in its own profile `name`, which must draw the app.
    let visit = |query: &str, name: &str| {
        let image = screenshot(&format!("{base}/{query}"), &profile(name), 10_000, name);
        assert_drawn(&image, query);
        image
    };
    let preset = visit("?preset=triangle-outside", "preset");
    let accuracy = visit("?view=accuracy", "accuracy");
    for (image, what) in [(&preset, "the preset"), (&accuracy, "the Accuracy view")] {
        let difference = view_difference(&first, image);
        println!(
            "{what} differs from the first visit in {:.0}% of the view",
            difference * 100.0
        );
        assert!(difference > 0.05, "{what} did not change the view");
    }
    assert!(view_difference(&preset, &accuracy) > 0.05);

    // The Render view renders in the page (in frame slices: a page has one thread): seed 003's blue
    // triangle, shaded by its facing ratio, fills a good part of the screen.
    let render = visit("?preset=seed003-facing", "render");
    let blue = render
        .pixels()
        .filter(|p| {
            let [r, g, b, _] = p.0.map(i32::from);
            b > 90 && b > r + 50 && b > g + 30
        })
        .count() as f64
        / f64::from(render.width() * render.height());
    println!(
        "seed 003's triangle covers {:.0}% of the page",
        blue * 100.0
    );
    assert!(blue > 0.05, "the Render view did not draw the triangle");

    // The state persists in local storage: eframe saves it every 30 s (virtual time here), and the
    // next visit without a parameter reopens the preset.
    let remembered = profile("remembered");
    screenshot(
        &format!("{base}/?preset=triangle-outside"),
        &remembered,
        40_000,
        "remembered-1",
    );
    let again = screenshot(&base, &remembered, 10_000, "remembered-2");
    assert_drawn(&again, "the next visit");
    let (same, changed) = (
        view_difference(&preset, &again),
        view_difference(&first, &again),
    );
    println!(
        "the next visit differs from the preset in {:.1}% and from a first visit in {:.0}% of the view",
        same * 100.0,
        changed * 100.0
    );
    assert!(same < 0.01 && changed > 0.05, "the state did not persist");
    println!("browser checks took {:.0} s", clock.elapsed().as_secs_f64());

    if std::env::var("RAYLAB_SCREENSHOTS").is_ok() {
        let shot = screenshot(
            &format!("{base}/?preset=seed000-triangle"),
            &profile("readme"),
            10_000,
            "readme",
        );
        assert_drawn(&shot, "the README's screenshot");
        shot.save(root().join("assets/screenshots/web.png"))
            .unwrap();
    }
}
