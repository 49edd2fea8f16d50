//! The teacher's side in the real app (egui_kittest): the app joins a running `raylab class` with the
//! code and key, asks about the scene on screen by clicking, the students' answers arrive over the
//! network, the panel counts them and the Triangle view draws each prediction in the cloud; the answer
//! stays hidden until Reveal is clicked.
//!
//! `RAYLAB_SCREENSHOTS=1 cargo test --test class teacher` also writes
//! `assets/screenshots/class-projector.png`.

use egui::Vec2;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use raylab::app::RaylabApp;
use raylab::class::protocol::{QuestionState, ToClient};
use serde_json::json;

use super::client::{Client, Server, TempDir};

/// Steps the app until `done` holds (the network answers on its own threads), at most 20 s.
pub fn step_until(
    harness: &mut Harness<'static, RaylabApp>,
    what: &str,
    done: impl Fn(&Harness<'static, RaylabApp>) -> bool,
) {
    let start = std::time::Instant::now();
    while !done(harness) {
        assert!(
            start.elapsed().as_secs() < 20,
            "the app never showed {what}"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
        harness.step();
    }
    harness.run();
}

/// Loads a preset and joins the class as its teacher, as Class → Join does.
pub fn join(
    harness: &mut Harness<'static, RaylabApp>,
    preset: &str,
    address: &str,
    code: &str,
    key: &str,
) {
    let preset = raylab::scene::preset(preset).unwrap();
    harness.state_mut().load_scene(&preset).unwrap();
    let ctx = harness.ctx.clone();
    harness.state_mut().join_class(&ctx, address, code, key);
    step_until(harness, "the link to the class", |h| {
        h.state().class.as_ref().is_some_and(|c| c.connected)
    });
}

/// Clicks Ask about this scene and waits for the question to come back.
pub fn ask(harness: &mut Harness<'static, RaylabApp>) {
    harness.get_by_label("Ask about this scene").click();
    step_until(harness, "the question", |h| {
        h.state()
            .class
            .as_ref()
            .is_some_and(|c| c.question.is_some())
    });
}

pub fn shows(harness: &Harness<'static, RaylabApp>, text: &str) -> bool {
    harness.query_by_label_contains(text).is_some()
}

#[test]
fn the_teachers_view_counts_answers_and_draws_their_cloud() {
    let folder = TempDir::new("class-teacher");
    let server = Server::start(&folder.join("class.sqlite3"), &[]);
    let mut harness = app_with(None);
    let (address, code) = (server.address.clone(), server.code.clone());
    // As a teacher types them: the address with its scheme, the code in lower case.
    join(
        &mut harness,
        "seed000-triangle",
        &format!("http://{address}"),
        &code.to_lowercase(),
        &server.key,
    );
    assert!(
        shows(&harness, &format!("Code {code}")),
        "the projector shows the code"
    );

    // The students join; the teacher asks about the scene on screen by clicking.
    let mut students: Vec<Client> = (0..12)
        .map(|_| Client::student(&address, &code, None, None).0)
        .collect();
    ask(&mut harness);
    assert!(
        harness.state().class_hides_answer(),
        "the answer is hidden while the question is open"
    );

    // Twelve predictions of P(β, γ) around the true 1/3, 1/3, one "behind"; each acknowledged.
    let question =
        match students[0].recv_until("the question", |m| matches!(m, ToClient::Question { .. })) {
            ToClient::Question { question } => question.id,
            _ => unreachable!(),
        };
    for (i, student) in students.iter_mut().enumerate() {
        if i > 0 {
            student.recv_until("the question", |m| matches!(m, ToClient::Question { .. }));
        }
        // A scatter around the answer, as a class's guesses are (a fixed sequence, not random).
        let angle = i as f64 * 2.4;
        let radius = 0.04 + 0.012 * i as f64;
        let (beta, gamma) = (0.3 + radius * angle.cos(), 0.3 + radius * angle.sin());
        let outcome = if i == 7 { "behind" } else { "hit" };
        student.send(
            json!({"type": "answer", "question": question, "outcome": outcome,
                            "values": [format!("{beta:.3}"), format!("{gamma:.3}"), null]}),
        );
        student.recv_until("the ack", |m| matches!(m, ToClient::Ack { .. }));
    }
    step_until(&mut harness, "12 answered", |h| shows(h, "12 answered"));
    assert_eq!(
        raylab::app::class_view::cloud_drawn(&harness.ctx),
        12,
        "every prediction is a point of the cloud in the Triangle view"
    );
    // On the projector at 200% (1280x800 pixels: 640x400 points) the count, the bars and the buttons
    // are on screen without scrolling: the address and QR code fold away once a question is asked.
    let mut zoomed = Harness::builder()
        .with_size(Vec2::new(640.0, 400.0))
        .with_pixels_per_point(2.0)
        .with_max_steps(200)
        .build_eframe(|cc| {
            raylab::app::set_style(&cc.egui_ctx);
            RaylabApp::new()
        });
    join(
        &mut zoomed,
        "seed000-triangle",
        &address,
        &code,
        &server.key,
    );
    step_until(&mut zoomed, "12 answered at 200%", |h| {
        shows(h, "12 answered")
    });
    for text in [
        "12 answered",
        "Ask about this scene",
        "Reveal",
        &format!("Code {code}"),
    ] {
        let rect = zoomed.get_by_label_contains(text).rect();
        assert!(
            rect.max.y <= 400.0 && rect.min.y >= 0.0,
            "at 200% '{text}' is off screen at {rect:?}"
        );
    }
    // This second app joined after the question was asked: it draws the same cloud (the question
    // brings its scene's exact inputs).
    assert_eq!(raylab::app::class_view::cloud_drawn(&zoomed.ctx), 12);
    drop(zoomed);
    let tally = harness.state().class.as_ref().unwrap().tally.clone();
    let hits = tally.outcomes.iter().find(|(o, _)| o == "hit").unwrap().1;
    assert_eq!(hits, 11);
    assert!(
        !shows(&harness, "Answer: hit"),
        "no answer before the reveal"
    );

    let write = std::env::var_os("RAYLAB_SCREENSHOTS").is_some();
    if write {
        harness.hover_at(egui::pos2(2.0, 790.0));
        harness.run();
        let image = harness.render().expect("the CPU renderer draws");
        image
            .save(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/assets/screenshots/class-projector.png"
            ))
            .unwrap();
    }

    // Lock, then Reveal: the true answer shows on the projector and every student learns it.
    harness.get_by_label("Lock").click();
    step_until(&mut harness, "the lock", |h| {
        h.state()
            .class
            .as_ref()
            .and_then(|c| c.question.as_ref())
            .is_some_and(|q| q.state == QuestionState::Locked)
    });
    harness.get_by_label("Reveal").click();
    step_until(&mut harness, "the reveal", |h| {
        shows(h, "Answer: hit; β = 1/3, γ = 1/3, t = 1")
    });
    assert!(!harness.state().class_hides_answer());
    for student in &mut students {
        let revealed = student.recv_until("the reveal", |m| matches!(m, ToClient::Revealed { .. }));
        assert!(
            matches!(revealed, ToClient::Revealed { ref reveal, .. } if reveal.answer.outcome == "hit")
        );
    }
    if write {
        harness.run();
        let image = harness.render().expect("the CPU renderer draws");
        image
            .save(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/assets/screenshots/class-reveal.png"
            ))
            .unwrap();
    }
}

/// The app as a teacher restarts it: its saved state holds the class (address, code, key).
pub fn app_with(state: Option<raylab::app::AppState>) -> Harness<'static, RaylabApp> {
    Harness::builder()
        .with_size(Vec2::new(1280.0, 800.0))
        .with_max_steps(200)
        .build_eframe(move |cc| {
            raylab::app::set_style(&cc.egui_ctx);
            let mut app = RaylabApp::new();
            if let Some(state) = state {
                app.state = state;
            }
            app
        })
}

#[test]
fn a_restarted_app_resumes_its_class() {
    let folder = TempDir::new("class-resume");
    let server = Server::start(&folder.join("class.sqlite3"), &[]);
    let mut harness = app_with(None);
    join(
        &mut harness,
        "seed000-segments-cross",
        &server.address,
        &server.code,
        &server.key,
    );
    ask(&mut harness);
    let (mut student, _) = Client::student(&server.address, &server.code, None, Some("Kim"));
    student.send(json!({"type": "answer", "question": harness.state().class.as_ref().unwrap().question.as_ref().unwrap().id,
                        "outcome": "hit", "values": ["0.75", "0.9"]}));
    student.recv_until("the ack", |m| matches!(m, ToClient::Ack { .. }));

    // The app closes (its state saved) and starts again: it comes back to the same class and question,
    // and draws the answer that arrived before it closed in the Segments view's cloud.
    let saved = harness.state().state.clone();
    drop(harness);
    let mut harness = app_with(Some(saved));
    step_until(&mut harness, "1 answered after the restart", |h| {
        shows(h, "1 answered")
    });
    assert!(shows(&harness, &format!("Code {}", server.code)));
    assert_eq!(
        raylab::app::class_view::cloud_drawn(&harness.ctx),
        2,
        "A(t) and B(s) of the one prediction"
    );

    // Class → End the class: the student is told, the code stops working, the app lets the class go.
    harness.get_by_label("Class").click();
    harness.run();
    harness.get_by_label("End the class").click();
    step_until(&mut harness, "the end of the class", |h| {
        h.state().class.is_none()
    });
    assert!(
        harness.state().state.class.is_none(),
        "an ended class is not resumed"
    );
    student.recv_until("the end", |m| matches!(m, ToClient::Ended));
    let (_, refused) = Client::student(&server.address, &server.code, None, None);
    assert!(
        matches!(refused, ToClient::Error { ref message } if message.contains("has ended")),
        "{refused:?}"
    );
    // After a restart the ended class is not resumed (a new one starts), and its old code still
    // says it has ended.
    let ended = server.code.clone();
    drop(server);
    let restarted = Server::start(&folder.join("class.sqlite3"), &[]);
    assert_ne!(restarted.code, ended);
    let (_, refused) = Client::student(&restarted.address, &ended, None, None);
    assert!(
        matches!(refused, ToClient::Error { ref message } if message.contains(&format!("{ended} has ended"))),
        "{refused:?}"
    );
}
