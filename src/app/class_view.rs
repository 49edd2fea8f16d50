//! The live class in the app: the teacher starts a class server (desktop) or joins one by its
//! address, asks the class about the scene on screen, watches the answers arrive (the count, the
//! outcomes as bars, the predictions as a cloud of points drawn in the view itself), then locks and
//! reveals. While a question is open the view and the steps keep the answer to themselves.
//!
//! The app speaks [`crate::class::protocol`] over a WebSocket (ewebsock, native and web), and comes
//! back by itself when the link drops: the class's address, code and key are saved with the app's
//! state, so a restarted app resumes its class (and restarts the server it had started).

use std::sync::Arc;

use egui::{Color32, RichText, Stroke, Ui};
use serde::{Deserialize, Serialize};

use super::widgets::palette::{self, Readable as _};
use super::{Notice, RaylabApp};
use crate::class::protocol::{
    QuestionSpec, QuestionState, QuestionView, Reveal, Tally, ToClient, ToServer,
};
use crate::class::question::{default_prompt, spec_of_scene};
use crate::scene;

/// The colour of the class's predictions in the views (a violet apart from every colour of the
/// palette, for each colour-vision deficiency too).
pub const CLOUD: Color32 = Color32::from_rgb(0x5e, 0x3c, 0x99);

/// Where the app's class is, saved with the app's state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClassLink {
    /// The server's WebSocket address (`ws://HOST:PORT/ws`).
    pub ws_url: String,
    /// The page students open.
    pub join_url: String,
    /// The join code.
    pub code: String,
    /// The teacher's key.
    pub key: String,
    /// The address this app's own server listened on, when the app started it (it is started again
    /// on resume).
    #[serde(default)]
    pub serve: Option<String>,
}

/// A class in progress.
pub struct ClassRun {
    /// Where it is.
    pub link: ClassLink,
    #[cfg(not(target_arch = "wasm32"))]
    server: Option<crate::class::server::Running>,
    socket: Option<(ewebsock::WsSender, ewebsock::WsReceiver)>,
    /// True once the server took the teacher's key on this connection.
    pub connected: bool,
    retry_at: Option<f64>,
    retries: u32,
    /// The current question.
    pub question: Option<QuestionView>,
    /// The answers so far.
    pub tally: Tally,
    /// The reveal, once made.
    pub reveal: Option<Reveal>,
    /// The last error the server sent, or why the link is down.
    pub error: Option<String>,
    /// Whether the tally names students (off unless the teacher asks).
    pub show_names: bool,
    /// The teacher ended the class.
    pub ended: bool,
    /// The panel shows the address and the QR code (until the first question, or on request).
    pub show_join: bool,
    qr: Option<(String, Vec<bool>, usize)>,
}

/// What the Class → Start / Join dialog holds.
#[derive(Clone, Debug)]
pub struct ClassDialog {
    /// Start a server here (true) or join one (false).
    pub start: bool,
    /// Start: listen on the room's network (0.0.0.0) rather than this machine only.
    pub room: bool,
    /// Start: the port.
    pub port: String,
    /// Join: the server's address.
    pub address: String,
    /// Join: the code.
    pub code: String,
    /// Join: the teacher's key.
    pub key: String,
}

impl ClassDialog {
    fn new(start: bool) -> ClassDialog {
        ClassDialog {
            start,
            room: true,
            port: crate::class::DEFAULT_PORT.to_string(),
            address: crate::platform::page_origin().unwrap_or_default(),
            code: String::new(),
            key: String::new(),
        }
    }
}

/// The predictions a view draws, with the question they answer.
#[derive(Clone, Debug, PartialEq)]
pub struct Cloud {
    /// The question's inputs (the cloud is drawn only on the same scene).
    pub spec: QuestionSpec,
    /// Each prediction's first two values (β, γ; t, s; α, β), when given.
    pub points: Vec<[Option<f64>; 2]>,
    /// Whether each was right: shown only after the reveal.
    pub right: Option<Vec<bool>>,
}

fn cloud_id() -> egui::Id {
    egui::Id::unique("raylab-class-cloud")
}

fn drawn_id() -> egui::Id {
    egui::Id::unique("raylab-class-cloud-drawn")
}

/// The class's cloud, if it answers a question about `problem` (the scene on screen).
pub fn cloud_for(ctx: &egui::Context, problem: &scene::Problem) -> Option<Arc<Cloud>> {
    let cloud: Arc<Cloud> = ctx.data(|d| d.get_temp(cloud_id()))?;
    let here = spec_of_scene(problem, "")?;
    (here.kind == cloud.spec.kind && here.inputs == cloud.spec.inputs).then_some(cloud)
}

/// A view says how many of the cloud's points it drew this frame (tests read it).
pub fn note_drawn(ctx: &egui::Context, count: usize) {
    ctx.data_mut(|d| d.insert_temp(drawn_id(), count));
}

/// How many points of the cloud the view drew last frame.
pub fn cloud_drawn(ctx: &egui::Context) -> usize {
    ctx.data(|d| d.get_temp(drawn_id()).unwrap_or(0))
}

/// Draws one prediction at `at`: a filled disc before the reveal; after it a filled disc when right
/// and a hollow ring with a cross when wrong (shape, not only colour, tells them apart).
pub fn paint_prediction(painter: &egui::Painter, at: egui::Pos2, right: Option<bool>) {
    let color = CLOUD.gamma_multiply(0.85);
    match right {
        Some(false) => {
            painter.circle_stroke(at, 5.0, Stroke::new(2.0, color));
            let d = 3.0;
            let stroke = Stroke::new(1.5, color);
            painter.line_segment([at + egui::vec2(-d, -d), at + egui::vec2(d, d)], stroke);
            painter.line_segment([at + egui::vec2(-d, d), at + egui::vec2(d, -d)], stroke);
        }
        _ => {
            painter.circle_filled(at, 5.0, color);
            painter.circle_stroke(at, 5.0, Stroke::new(1.0, Color32::WHITE));
        }
    }
}

impl ClassRun {
    fn new(link: ClassLink) -> ClassRun {
        ClassRun {
            link,
            #[cfg(not(target_arch = "wasm32"))]
            server: None,
            socket: None,
            connected: false,
            retry_at: None,
            retries: 0,
            question: None,
            tally: Tally::default(),
            reveal: None,
            error: None,
            show_names: false,
            ended: false,
            show_join: true,
            qr: None,
        }
    }

    /// Opens the WebSocket; events wake the UI.
    fn connect(&mut self, ctx: &egui::Context) {
        let waker = ctx.clone();
        match ewebsock::connect_with_wakeup(
            self.link.ws_url.clone(),
            ewebsock::Options::default(),
            move || waker.request_repaint(),
        ) {
            Ok(socket) => self.socket = Some(socket),
            Err(error) => self.lost(ctx, error),
        }
    }

    /// The link is down: try again in a moment (0.5 s, doubling, at most 10 s).
    fn lost(&mut self, ctx: &egui::Context, why: String) {
        self.socket = None;
        self.connected = false;
        if self.ended {
            return;
        }
        self.error = Some(format!("link to the class lost ({why}): reconnecting…"));
        let wait = (0.5 * 2f64.powi(self.retries.min(5) as i32)).min(10.0);
        self.retries += 1;
        self.retry_at = Some(ctx.input(|i| i.time) + wait);
        ctx.request_repaint_after(std::time::Duration::from_secs_f64(wait));
    }

    /// Sends a message to the server (dropped while the link is down; the UI says so).
    pub fn send(&mut self, message: &ToServer) {
        if let (Some((sender, _)), Ok(text)) = (&mut self.socket, serde_json::to_string(message)) {
            sender.send(ewebsock::WsMessage::Text(text));
        }
    }

    /// Reads what arrived; reconnects when it is time.
    pub fn poll(&mut self, ctx: &egui::Context) {
        if self.socket.is_none()
            && !self.ended
            && self.retry_at.is_none_or(|at| ctx.input(|i| i.time) >= at)
        {
            self.retry_at = None;
            self.connect(ctx);
        }
        let mut events = Vec::new();
        if let Some((_, receiver)) = &self.socket {
            while let Some(event) = receiver.try_recv() {
                events.push(event);
            }
        }
        for event in events {
            match event {
                ewebsock::WsEvent::Opened => {
                    let teach = ToServer::Teach {
                        code: self.link.code.clone(),
                        key: self.link.key.clone(),
                    };
                    self.send(&teach);
                }
                ewebsock::WsEvent::Message(ewebsock::WsMessage::Text(text)) => {
                    match serde_json::from_str::<ToClient>(&text) {
                        Ok(message) => self.receive(message),
                        Err(error) => {
                            self.error = Some(format!("unreadable from the server: {error}"))
                        }
                    }
                }
                ewebsock::WsEvent::Message(_) => {}
                ewebsock::WsEvent::Error(error) => self.lost(ctx, error),
                ewebsock::WsEvent::Closed => self.lost(ctx, "closed".into()),
            }
        }
    }

    fn receive(&mut self, message: ToClient) {
        match message {
            ToClient::Welcome {
                question, reveal, ..
            } => {
                self.connected = true;
                self.retries = 0;
                self.error = None;
                self.show_join &= question.is_none();
                self.question = question.map(|q| *q);
                self.reveal = reveal.map(|r| *r);
            }
            ToClient::Question { question } => {
                if self.question.as_ref().is_none_or(|q| q.id != question.id) {
                    self.reveal = None;
                    // A question asked: the answers need the panel's room more than the QR code.
                    self.show_join = false;
                }
                self.question = Some(*question);
            }
            ToClient::Revealed { reveal, question } => {
                if let Some(q) = self.question.as_mut().filter(|q| q.id == question) {
                    q.state = QuestionState::Revealed;
                }
                self.reveal = Some(*reveal);
            }
            ToClient::Tally(tally) => self.tally = tally,
            ToClient::Error { message } => self.error = Some(message),
            ToClient::Ended => {
                self.ended = true;
                self.socket = None;
            }
            ToClient::Ack { .. } | ToClient::Pong => {}
        }
    }

    /// True while a question is asked and its answer not yet revealed.
    pub fn answer_hidden(&self) -> bool {
        self.question
            .as_ref()
            .is_some_and(|q| q.state != QuestionState::Revealed)
    }

    /// The cloud of the current question's predictions.
    fn cloud(&self) -> Option<Cloud> {
        let question = self.question.as_ref()?;
        let spec = question.spec.clone();
        if self.tally.question != Some(question.id) {
            return None;
        }
        let predictions = &self.tally.predictions;
        Some(Cloud {
            spec,
            points: predictions
                .iter()
                .map(|p| [0, 1].map(|i| p.values.get(i).copied().flatten()))
                .collect(),
            right: (question.state == QuestionState::Revealed)
                .then(|| predictions.iter().map(|p| p.right).collect()),
        })
    }

    /// The QR code of the join address: (address, dark modules row by row, width).
    fn qr(&mut self) -> Option<&(String, Vec<bool>, usize)> {
        if self
            .qr
            .as_ref()
            .is_none_or(|(url, ..)| *url != self.link.join_url)
        {
            let code = qrcode::QrCode::new(self.link.join_url.as_bytes()).ok()?;
            let dark = code
                .to_colors()
                .into_iter()
                .map(|c| c == qrcode::Color::Dark)
                .collect();
            self.qr = Some((self.link.join_url.clone(), dark, code.width()));
        }
        self.qr.as_ref()
    }
}

/// The WebSocket address for what a teacher typed: `ws://…/ws` as is, `http://host:port` or a bare
/// `host:port` turned into it.
pub fn ws_url_of(address: &str) -> String {
    let address = address.trim().trim_end_matches('/');
    let address = address.strip_suffix("/ws").unwrap_or(address);
    let rest = address
        .strip_prefix("https://")
        .map(|r| format!("wss://{r}"))
        .or_else(|| address.strip_prefix("http://").map(|r| format!("ws://{r}")))
        .or_else(|| {
            (address.starts_with("ws://") || address.starts_with("wss://"))
                .then(|| address.to_string())
        })
        .unwrap_or_else(|| format!("ws://{address}"));
    format!("{rest}/ws")
}

impl RaylabApp {
    /// Starts this app's own class server and joins it as the teacher (desktop only).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn start_class(&mut self, ctx: &egui::Context, listen: &str) -> Result<(), String> {
        let address: std::net::SocketAddr = listen
            .parse()
            .map_err(|_| format!("'{listen}' is not an address such as 0.0.0.0:7878"))?;
        let options = crate::class::server::Options {
            listen: address,
            db: crate::class::server::default_db_path(),
            new_session: false,
            public_url: None,
            site: None,
        };
        let running = crate::class::server::start(&options).map_err(|e| e.to_string())?;
        let started = &running.started;
        let link = ClassLink {
            ws_url: format!(
                "ws://{}/ws",
                std::net::SocketAddr::new([127, 0, 0, 1].into(), started.address.port())
            ),
            join_url: started.join_url.clone(),
            code: started.code.clone(),
            key: started.key.clone(),
            serve: Some(listen.to_string()),
        };
        let mut run = ClassRun::new(link.clone());
        run.server = Some(running);
        run.connect(ctx);
        self.state.class = Some(link);
        self.class = Some(run);
        Ok(())
    }

    /// Joins a class server as its teacher.
    pub fn join_class(&mut self, ctx: &egui::Context, address: &str, code: &str, key: &str) {
        let ws_url = ws_url_of(address);
        let code = crate::class::protocol::normalise_code(code);
        let join_url = format!(
            "{}/?code={code}",
            ws_url
                .trim_end_matches("/ws")
                .replacen("wss://", "https://", 1)
                .replacen("ws://", "http://", 1)
        );
        let link = ClassLink {
            ws_url,
            join_url,
            code,
            key: key.trim().to_string(),
            serve: None,
        };
        let mut run = ClassRun::new(link.clone());
        run.connect(ctx);
        self.state.class = Some(link);
        self.class = Some(run);
    }

    /// Comes back to the saved class after a restart (restarting this app's own server if it had one).
    pub(super) fn resume_class(&mut self, ctx: &egui::Context) {
        if self.class.is_some() || self.class_resumed {
            return;
        }
        self.class_resumed = true;
        let Some(link) = self.state.class.clone() else {
            return;
        };
        #[cfg(not(target_arch = "wasm32"))]
        if let Some(listen) = &link.serve {
            if let Err(error) = self.start_class(ctx, listen) {
                self.notice = Some(Notice::error(format!(
                    "could not restart the class server: {error}"
                )));
            }
            return;
        }
        let mut run = ClassRun::new(link);
        run.connect(ctx);
        self.class = Some(run);
    }

    /// Asks the class about the scene on screen (or says why it cannot).
    pub fn ask_class(&mut self, prompt: Option<&str>) {
        let Some(problem) = self.view(self.state.view).problem() else {
            self.notice = Some(Notice::error("this view has no question to ask"));
            return;
        };
        let Some(mut spec) = spec_of_scene(&problem, "") else {
            self.notice = Some(Notice::error(
                "a render cannot be asked: open the Segments, Triangle or Parallelogram view",
            ));
            return;
        };
        spec.prompt = prompt
            .unwrap_or_else(|| default_prompt(&spec.kind))
            .to_string();
        let Some(run) = &mut self.class else {
            return;
        };
        run.send(&ToServer::Ask { question: spec });
    }

    /// Reads the class's news and hands the views its cloud; call once a frame.
    pub(super) fn class_frame(&mut self, ctx: &egui::Context) {
        self.resume_class(ctx);
        let Some(run) = &mut self.class else {
            ctx.data_mut(|d| d.remove::<Arc<Cloud>>(cloud_id()));
            return;
        };
        run.poll(ctx);
        if run.ended {
            let code = run.link.code.clone();
            self.class = None;
            self.state.class = None;
            self.notice = Some(Notice::info(format!(
                "The class {code} has ended; `raylab class export {code} --csv` writes its answers"
            )));
            ctx.data_mut(|d| d.remove::<Arc<Cloud>>(cloud_id()));
            return;
        }
        match run.cloud() {
            Some(cloud) => {
                ctx.data_mut(|d| d.insert_temp(cloud_id(), Arc::new(cloud)));
            }
            None => ctx.data_mut(|d| d.remove::<Arc<Cloud>>(cloud_id())),
        }
    }

    /// True while the class's question is open or locked: the views and steps hide the answer.
    pub fn class_hides_answer(&self) -> bool {
        self.class.as_ref().is_some_and(ClassRun::answer_hidden)
    }

    /// The Class menu.
    pub(super) fn class_menu(&mut self, ui: &mut Ui) {
        let Some(run) = &mut self.class else {
            #[cfg(not(target_arch = "wasm32"))]
            if ui
                .button("Start a class…")
                .on_hover_text(
                    "Run the class server on this computer: students join from their phones",
                )
                .clicked()
            {
                self.class_dialog = Some(ClassDialog::new(true));
            }
            if ui
                .button("Join a class server…")
                .on_hover_text("Teach a class whose server runs elsewhere (`raylab class` prints its address, code and key)")
                .clicked()
            {
                self.class_dialog = Some(ClassDialog::new(false));
            }
            return;
        };
        let ask = question_buttons_ui(
            ui,
            run,
            [
                "Ask the class about this scene",
                "Lock answers",
                "Reveal the answer",
            ],
        );
        let mut names = run.show_names;
        if ui
            .checkbox(&mut names, "Show students' names")
            .on_hover_text("Off by default: the projector shows no name unless you ask")
            .changed()
        {
            run.show_names = names;
            run.send(&ToServer::ShowNames { show: names });
        }
        ui.separator();
        if ui
            .button("End the class")
            .on_hover_text("Students are told the class has ended; the answers stay in the database for `raylab class export`")
            .clicked()
        {
            // The class is let go once the server says it has ended (this app's own server must
            // not stop before it has stored the end).
            run.send(&ToServer::End {});
        } else if ui
            .button("Leave (the class keeps running)")
            .on_hover_text("Stop teaching from this app; Join brings you back with the code and key")
            .clicked()
        {
            self.class = None;
            self.state.class = None;
        }
        if ask {
            self.ask_class(None);
        }
    }

    /// The Start / Join dialog.
    pub(super) fn class_dialog_ui(&mut self, ctx: &egui::Context) {
        let Some(mut dialog) = self.class_dialog.clone() else {
            return;
        };
        let mut open = true;
        let mut done = false;
        let title = if dialog.start {
            "Start a class"
        } else {
            "Join a class server"
        };
        egui::Window::new(title)
            .open(&mut open)
            .collapsible(false)
            .resizable(false)
            .show(ctx, |ui| {
                if dialog.start {
                    ui.checkbox(&mut dialog.room, "Open to the room's network")
                        .on_hover_text("Phones on the same Wi-Fi can join (listens on 0.0.0.0). Off: this computer only.");
                    ui.horizontal(|ui| {
                        let label = ui.label("Port:");
                        ui.add(egui::TextEdit::singleline(&mut dialog.port).desired_width(80.0))
                            .labelled_by(label.id);
                    });
                    if ui.button("Start").clicked() {
                        let host = if dialog.room { "0.0.0.0" } else { "127.0.0.1" };
                        let listen = format!("{host}:{}", dialog.port.trim());
                        done = true;
                        #[cfg(not(target_arch = "wasm32"))]
                        if let Err(error) = self.start_class(ctx, &listen) {
                            self.notice = Some(Notice::error(format!("could not start the class: {error}")));
                        }
                        #[cfg(target_arch = "wasm32")]
                        let _ = listen;
                    }
                } else {
                    for (name, value, hint) in [
                        ("Server address:", &mut dialog.address, "http://192.168.1.20:7878"),
                        ("Class code:", &mut dialog.code, "K7P3QX"),
                        ("Teacher key:", &mut dialog.key, "as `raylab class` printed it"),
                    ] {
                        let label = ui.label(name);
                        ui.add(egui::TextEdit::singleline(value).hint_text(hint).desired_width(360.0))
                            .labelled_by(label.id);
                    }
                    let ready = [&dialog.address, &dialog.code, &dialog.key]
                        .iter()
                        .all(|v| !v.trim().is_empty());
                    if ui.add_enabled(ready, egui::Button::new("Join")).clicked() {
                        let (address, code, key) =
                            (dialog.address.clone(), dialog.code.clone(), dialog.key.clone());
                        self.join_class(ctx, &address, &code, &key);
                        done = true;
                    }
                }
            });
        self.class_dialog = (open && !done).then_some(dialog);
    }

    /// The class on the projector: the join code, the address and its QR code, large; the count of
    /// students; the question with the count answered and the outcomes as bars; Lock and Reveal.
    pub(super) fn class_panel_ui(&mut self, ui: &mut Ui) {
        let Some(run) = &mut self.class else {
            return;
        };
        let mut ask = false;
        egui::ScrollArea::vertical().show(ui, |ui| {
            ui.heading("Live class");
            if run.ended {
                ui.label("The class has ended.");
                return;
            }
            // How to join, large, until the first question; then folded to the code (a latecomer
            // still reads it) so the answers have the room, and unfolded on request.
            let code = RichText::new(format!("Code {}", run.link.code)).strong();
            if run.show_join {
                ui.label(code.size(34.0));
                ui.label(RichText::new(&run.link.join_url).size(18.0).monospace());
                if let Some((_, dark, width)) = run.qr() {
                    qr_ui(ui, dark, *width);
                }
            } else {
                ui.label(code.size(24.0))
                    .on_hover_text(format!("Students open {}", run.link.join_url));
            }
            let fold = if run.show_join {
                "Hide the address and QR code"
            } else {
                "Show the address and QR code"
            };
            if ui.button(fold).clicked() {
                run.show_join = !run.show_join;
            }
            let students = format!(
                "{} joined · {} connected",
                run.tally.joined, run.tally.connected
            );
            ui.label(RichText::new(students).size(20.0));
            if let Some(error) = &run.error {
                ui.label(RichText::new(error).color(palette::OUTSIDE.readable(ui)));
            } else if !run.connected {
                ui.label("Connecting…");
            }
            // The teacher's buttons before the answers: on a zoomed projector they stay on screen.
            ui.horizontal_wrapped(|ui| {
                ask = question_buttons_ui(ui, run, ["Ask about this scene", "Lock", "Reveal"]);
            });
            ui.separator();
            match &run.question {
                None => {
                    ui.label("No question yet: set up a scene, then ask.");
                }
                Some(question) => {
                    ui.label(
                        RichText::new(format!("Q{}. {}", question.number, question.prompt))
                            .strong(),
                    );
                    let state = match question.state {
                        QuestionState::Open => "open: students are answering",
                        QuestionState::Locked => "locked: no more answers",
                        QuestionState::Revealed => "revealed",
                    };
                    ui.label(format!("Answers {state}"));
                    ui.label(
                        RichText::new(format!("{} answered", run.tally.answered))
                            .size(26.0)
                            .strong(),
                    );
                    bars_ui(ui, &run.tally);
                    if let Some(reveal) = &run.reveal {
                        ui.label(
                            RichText::new(format!("Answer: {}", reveal.answer.text))
                                .size(18.0)
                                .strong(),
                        );
                        ui.label(format!(
                            "{} of {} right",
                            reveal.right_count, reveal.answered
                        ));
                    }
                    if run.show_names {
                        let names: Vec<String> = run
                            .tally
                            .predictions
                            .iter()
                            .map(|p| p.name.clone().unwrap_or_else(|| format!("#{}", p.student)))
                            .collect();
                        ui.label(format!("Answered: {}", names.join(", ")));
                    }
                }
            }
        });
        if ask {
            self.ask_class(None);
        }
    }
}

impl RaylabApp {
    /// The class in one strip under a lesson, presentation or practice: the code, the count, the
    /// outcomes so far, and Ask, Lock and Reveal, so the teacher drives the class from any mode.
    pub(super) fn class_strip_ui(&mut self, ui: &mut Ui) {
        let Some(run) = &mut self.class else {
            return;
        };
        let mut ask = false;
        ui.horizontal_wrapped(|ui| {
            ui.label(
                RichText::new(format!("Class {}", run.link.code))
                    .strong()
                    .size(20.0),
            )
            .on_hover_text(format!("Students open {}", run.link.join_url));
            ui.label(format!("{} joined", run.tally.joined));
            if let Some(question) = &run.question {
                let mut counts = format!("Q{}: {} answered", question.number, run.tally.answered);
                for (outcome, count) in run.tally.outcomes.iter().filter(|(_, n)| *n > 0) {
                    counts.push_str(&format!(" · {outcome} {count}"));
                }
                ui.label(RichText::new(counts).strong());
                if let Some(reveal) = &run.reveal {
                    ui.label(format!(
                        "{} of {} right",
                        reveal.right_count, reveal.answered
                    ));
                }
            }
            if let Some(error) = &run.error {
                ui.label(RichText::new(error).color(palette::OUTSIDE.readable(ui)));
            }
            ask = question_buttons_ui(ui, run, ["Ask about this scene", "Lock", "Reveal"]);
        });
        if ask {
            self.ask_class(None);
        }
    }

    /// A lesson's "Show the answer" with a class live: lock and reveal to every device too.
    pub(super) fn reveal_to_class(&mut self) {
        if let Some(run) = &mut self.class
            && run.answer_hidden()
        {
            run.send(&ToServer::Lock {});
            run.send(&ToServer::Reveal {});
        }
    }
}

/// The Ask, Lock and Reveal buttons (with these labels), Lock enabled while answers are open and
/// Reveal until the answer is shown; true when Ask was clicked (the caller asks, with the app's scene).
fn question_buttons_ui(ui: &mut Ui, run: &mut ClassRun, [ask, lock, reveal]: [&str; 3]) -> bool {
    let asked = ui
        .button(ask)
        .on_hover_text(
            "Send the scene on screen to every student: each predicts the outcome and the values",
        )
        .clicked();
    let state = run.question.as_ref().map(|q| q.state);
    if ui
        .add_enabled(state == Some(QuestionState::Open), egui::Button::new(lock))
        .on_hover_text("No more answers")
        .clicked()
    {
        run.send(&ToServer::Lock {});
    }
    if ui
        .add_enabled(
            matches!(state, Some(QuestionState::Open | QuestionState::Locked)),
            egui::Button::new(reveal),
        )
        .on_hover_text("Show the true answer here and on every device")
        .clicked()
    {
        run.send(&ToServer::Reveal {});
    }
    asked
}

/// Draws the class's predictions on the view of `problem` (only when the class's question is about
/// it); `at` gives the screen points of one prediction's two values (none where not given or off
/// screen). Notes the count drawn for tests.
pub fn draw_cloud(
    painter: &egui::Painter,
    problem: &scene::Problem,
    at: impl Fn([Option<f64>; 2]) -> Vec<egui::Pos2>,
) {
    let ctx = painter.ctx();
    let Some(cloud) = cloud_for(ctx, problem) else {
        note_drawn(ctx, 0);
        return;
    };
    let mut drawn = 0;
    for (i, values) in cloud.points.iter().enumerate() {
        let right = cloud.right.as_ref().and_then(|r| r.get(i).copied());
        for point in at(*values) {
            paint_prediction(painter, point, right);
            drawn += 1;
        }
    }
    note_drawn(ctx, drawn);
}

/// The QR code, drawn square by square (about 180 points wide), dark on white whatever the theme.
fn qr_ui(ui: &mut Ui, dark: &[bool], width: usize) {
    let quiet = 2;
    let side = (180.0 / (width + 2 * quiet) as f32).floor().max(2.0);
    let size = side * (width + 2 * quiet) as f32;
    let (rect, response) = ui.allocate_exact_size(egui::vec2(size, size), egui::Sense::hover());
    response.on_hover_text("Students scan this to open the class page");
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 0.0, Color32::WHITE);
    for (i, _) in dark.iter().enumerate().filter(|(_, d)| **d) {
        let (x, y) = ((i % width + quiet) as f32, (i / width + quiet) as f32);
        let cell = egui::Rect::from_min_size(
            rect.min + egui::vec2(x * side, y * side),
            egui::vec2(side, side),
        );
        painter.rect_filled(cell, 0.0, Color32::BLACK);
    }
}

/// The outcomes as horizontal bars, each with its count.
fn bars_ui(ui: &mut Ui, tally: &Tally) {
    let most = tally
        .outcomes
        .iter()
        .map(|(_, n)| *n)
        .max()
        .unwrap_or(0)
        .max(1);
    let text = ui.visuals().text_color();
    // The rows fit the panel's width (a fixed width pushed the panel wider than its room at 200%,
    // and its left edge was cut): the label takes up to 110 points, the count 36, the bar the rest.
    let width = ui.available_width();
    let label = 110.0_f32.min(width * 0.45);
    let bar_width = (width - label - 36.0 - 2.0 * ui.spacing().item_spacing.x).max(24.0);
    for (outcome, count) in &tally.outcomes {
        ui.horizontal(|ui| {
            ui.add_sized([label, 22.0], egui::Label::new(outcome.as_str()));
            let (rect, _) =
                ui.allocate_exact_size(egui::vec2(bar_width, 18.0), egui::Sense::hover());
            let share = *count as f32 / most as f32;
            let bar = egui::Rect::from_min_size(
                rect.min,
                egui::vec2(rect.width() * share, rect.height()),
            );
            ui.painter().rect_stroke(
                rect,
                2.0,
                Stroke::new(1.0, text.gamma_multiply(0.4)),
                egui::StrokeKind::Inside,
            );
            ui.painter()
                .rect_filled(bar, 2.0, CLOUD.gamma_multiply(0.8));
            ui.label(count.to_string());
        });
    }
}
