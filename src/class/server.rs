//! `raylab class`: the class server. One HTTP port serves the phone page (`/`, gzipped), the live
//! channel (`/ws`, WebSocket, see [`super::protocol`]) and the teacher's export (`/export.csv`).
//!
//! Every session lives in memory for speed and in the SQLite file ([`super::store`]) for safety: a
//! change is made in the database first, and only once it is committed is it applied in memory,
//! acknowledged and broadcast. A server killed and restarted reads its open sessions back with their
//! students, current question and answers.
//!
//! Defences: messages over [`MAX_MESSAGE_BYTES`] are refused by the WebSocket layer; every message is
//! read strictly (unknown types or fields get an error back); each connection has a token bucket of
//! messages; a connection must say who it is within [`JOIN_DEADLINE`]; the server holds at most
//! [`MAX_CONNECTIONS`] at once and answers the rest with 503. No input can panic the server: errors
//! go back to the one client that sent them.

use std::collections::HashMap;
use std::net::{IpAddr, SocketAddr};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use axum::Router;
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::extract::{Query, State};
use axum::http::{HeaderMap, StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use tokio::sync::{broadcast, watch};

use super::page::{Page, Site};
use super::protocol::{
    Given, MAX_MESSAGE_BYTES, Prediction, QuestionSpec, QuestionState, Reveal, Role, Tally,
    ToClient, ToServer, clean_nickname, normalise_code, read_message,
};
use super::question::{Asked, numbers_of, outcomes};
use super::store::{ExportRow, SessionRow, Store, StoreError, sql};

/// The most connections held at once; past it the upgrade is answered 503 (try again).
pub const MAX_CONNECTIONS: usize = 4096;

/// How long a connection may stay silent before saying who it is.
pub const JOIN_DEADLINE: Duration = Duration::from_secs(15);

/// A connection silent for this long is closed (the page pings every 20 s).
const IDLE_LIMIT: Duration = Duration::from_secs(90);

/// The most students one session takes.
const MAX_STUDENTS: usize = 2000;

/// Each connection's token bucket: this many messages at once, refilled at [`RATE_PER_SECOND`].
const BURST: f64 = 20.0;
const RATE_PER_SECOND: f64 = 10.0;

/// Messages refused for the rate before the connection is closed.
const RATE_STRIKES: u32 = 50;

/// Wrong teacher keys before the connection is closed.
const KEY_STRIKES: u32 = 5;

/// Why the server cannot start.
#[derive(Debug, thiserror::Error)]
pub enum ClassError {
    /// The database.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// The address is taken or not ours.
    #[error("cannot listen on {address}: {error}")]
    Listen {
        /// The address asked for.
        address: SocketAddr,
        /// Why.
        error: std::io::Error,
    },
    /// The runtime or a thread could not start.
    #[error("cannot start the server: {0}")]
    Start(std::io::Error),
    /// No such session to export.
    #[error("no class session with code {0} in {1}")]
    UnknownSession(String, String),
    /// The operating system gave no random bytes for codes, keys and tokens.
    #[error("no random source for the class's codes and keys: {0}")]
    Random(String),
    /// The export could not be written.
    #[error("cannot write the export: {0}")]
    Write(String),
}

/// How to start the server.
#[derive(Clone, Debug)]
pub struct Options {
    /// Where to listen (`127.0.0.1:7878`; port 0 picks a free one).
    pub listen: SocketAddr,
    /// The database file.
    pub db: PathBuf,
    /// Start a new session even when the database has an open one.
    pub new_session: bool,
    /// The address students type, when the listening one is not it (behind a proxy, or a name).
    pub public_url: Option<String>,
    /// The whole app's web build to serve at `/app/` (none: not served).
    pub site: Option<PathBuf>,
}

/// A started server: where it listens and the session it runs.
#[derive(Clone, Debug)]
pub struct Started {
    /// The address it listens on (the port filled in).
    pub address: SocketAddr,
    /// The session's join code.
    pub code: String,
    /// The teacher's key (never shown to students).
    pub key: String,
    /// True when the session was open in the database already.
    pub resumed: bool,
    /// The page students open: `http://HOST:PORT/?code=CODE`.
    pub join_url: String,
    /// The WebSocket address the app connects to.
    pub ws_url: String,
    /// The whole app in a browser (`…/app/`), when its web build is served.
    pub app_url: Option<String>,
}

/// The user's data folder's class database: `$XDG_DATA_HOME/raylab/class.sqlite3` (or
/// `~/.local/share/…`), `%APPDATA%\raylab\…` on Windows, `~/Library/Application Support/raylab/…` on
/// macOS; the current folder when none is known.
pub fn default_db_path() -> PathBuf {
    let env = |name: &str| {
        std::env::var_os(name)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    let base = if cfg!(windows) {
        env("APPDATA")
    } else if cfg!(target_os = "macos") {
        env("HOME").map(|home| home.join("Library/Application Support"))
    } else {
        env("XDG_DATA_HOME").or_else(|| env("HOME").map(|home| home.join(".local/share")))
    };
    base.unwrap_or_else(|| PathBuf::from("."))
        .join("raylab")
        .join("class.sqlite3")
}

/// Random bytes from the operating system. Without them (never seen on a desktop) the server refuses
/// rather than make guessable codes, keys and tokens.
fn random_bytes<const N: usize>() -> Result<[u8; N], ClassError> {
    let mut buffer = [0u8; N];
    getrandom::fill(&mut buffer).map_err(|e| ClassError::Random(e.to_string()))?;
    Ok(buffer)
}

/// `N` random bytes as lowercase hex (keys and tokens).
fn random_hex<const N: usize>() -> Result<String, ClassError> {
    Ok(random_bytes::<N>()?
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect())
}

/// A six-letter join code from 32 letters and digits that cannot be mistaken for each other (32
/// divides 256, so each is equally likely).
fn new_code() -> Result<String, ClassError> {
    const ALPHABET: &[u8; 32] = b"ABCDEFGHJKLMNPQRSTUVWXYZ23456789";
    Ok(random_bytes::<6>()?
        .iter()
        .map(|b| char::from(ALPHABET[usize::from(*b) % ALPHABET.len()]))
        .collect())
}

/// Compares two secrets in time that does not depend on where they differ.
fn same_secret(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
}

/// The server's shared state.
struct Hub {
    store: Store,
    sessions: Mutex<HashMap<String, Arc<Live>>>,
    /// Codes of sessions ended before this start.
    ended: std::collections::HashSet<String>,
    connections: AtomicUsize,
    page: Page,
    site: Site,
}

/// One session in memory.
struct Live {
    id: i64,
    code: String,
    key: String,
    state: Mutex<LiveState>,
    /// What students must hear: a question asked or locked, a reveal, the end.
    events: broadcast::Sender<Event>,
    /// Bumped on every change a teacher's tally shows.
    changed: watch::Sender<u64>,
}

#[derive(Clone, Copy, Debug)]
enum Event {
    Question,
    Revealed,
    Ended,
}

#[derive(Default)]
struct LiveState {
    students: HashMap<i64, Student>,
    by_token: HashMap<String, i64>,
    question: Option<Current>,
    show_names: bool,
    ended: bool,
}

struct Student {
    number: i64,
    nickname: Option<String>,
    connected: u32,
}

struct Current {
    id: i64,
    number: i64,
    asked: Asked,
    state: QuestionState,
    answers: HashMap<i64, Answered>,
}

struct Answered {
    given: Given,
    right: bool,
}

/// Locks a mutex, carrying on with its data if a thread panicked while holding it (no handler here
/// panics, and a half-made change is still better served than none).
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl Live {
    fn bump(&self) {
        self.changed.send_modify(|n| *n += 1);
    }

    /// Reads a stored session back: its students, its latest question and that question's answers.
    fn load(store: &Store, session: SessionRow) -> Result<Live, StoreError> {
        let id = session.id;
        let (students, question) = store.call_blocking(move |c| {
            let students = sql::students(c, id)?;
            let question = match sql::latest_question(c, id)? {
                Some(row) => {
                    let answers = sql::answers(c, row.id)?;
                    Some((row, answers))
                }
                None => None,
            };
            Ok((students, question))
        })?;
        let mut state = LiveState {
            show_names: session.show_names,
            ..LiveState::default()
        };
        for student in students {
            state.by_token.insert(student.token.clone(), student.id);
            state.students.insert(
                student.id,
                Student {
                    number: student.number,
                    nickname: student.nickname,
                    connected: 0,
                },
            );
        }
        if let Some((row, answers)) = question
            && let Ok(spec) = serde_json::from_str::<QuestionSpec>(&row.spec)
            && let Ok(asked) = Asked::new(spec)
        {
            let answers = answers
                .into_iter()
                .filter_map(|a| {
                    let given = serde_json::from_str(&a.given).ok()?;
                    Some((
                        a.student_id,
                        Answered {
                            given,
                            right: a.right,
                        },
                    ))
                })
                .collect();
            state.question = Some(Current {
                id: row.id,
                number: row.number,
                asked,
                state: row.state,
                answers,
            });
        }
        Ok(Live::new(session, state))
    }

    fn new(session: SessionRow, state: LiveState) -> Live {
        Live {
            id: session.id,
            code: session.code,
            key: session.key,
            state: Mutex::new(state),
            events: broadcast::channel(64).0,
            changed: watch::channel(0).0,
        }
    }

    /// The teacher's tally of the current question.
    fn tally(&self) -> Tally {
        let state = lock(&self.state);
        let mut tally = Tally {
            joined: state.students.len(),
            connected: state.students.values().filter(|s| s.connected > 0).count(),
            ..Tally::default()
        };
        let Some(current) = &state.question else {
            return tally;
        };
        tally.question = Some(current.id);
        tally.answered = current.answers.len();
        let kind = current.asked.problem.kind();
        tally.outcomes = outcomes(kind).into_iter().map(|o| (o, 0)).collect();
        for (student_id, answered) in &current.answers {
            if let Some(outcome) = &answered.given.outcome
                && let Some(bar) = tally.outcomes.iter_mut().find(|(o, _)| o == outcome)
            {
                bar.1 += 1;
            }
            tally.right += usize::from(answered.right);
            let student = state.students.get(student_id);
            tally.predictions.push(Prediction {
                student: student.map_or(0, |s| s.number),
                name: student
                    .filter(|_| state.show_names)
                    .and_then(|s| s.nickname.clone()),
                outcome: answered.given.outcome.clone(),
                values: numbers_of(&answered.given),
                right: answered.right,
            });
        }
        tally.predictions.sort_by_key(|p| p.student);
        tally
    }

    /// The reveal as `student` sees it (none before the reveal).
    fn reveal_for(state: &LiveState, student: Option<i64>) -> Option<Box<Reveal>> {
        let current = state.question.as_ref()?;
        (current.state == QuestionState::Revealed).then(|| {
            Box::new(Reveal {
                answer: current.asked.truth(),
                right: student.and_then(|s| current.answers.get(&s).map(|a| a.right)),
                answered: current.answers.len(),
                right_count: current.answers.values().filter(|a| a.right).count(),
            })
        })
    }
}

/// The server, running on its own thread; dropping it stops the server.
pub struct Running {
    /// Where it listens and its session.
    pub started: Started,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Drop for Running {
    fn drop(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// Opens the database, takes (or makes) the session and binds the port; what the caller prints.
fn prepare(options: &Options) -> Result<(Arc<Hub>, std::net::TcpListener, Started), ClassError> {
    // The port first: a start that cannot listen makes no session.
    let listener =
        std::net::TcpListener::bind(options.listen).map_err(|error| ClassError::Listen {
            address: options.listen,
            error,
        })?;
    let store = Store::open(&options.db)?;
    let open = store.call_blocking(sql::open_sessions)?;
    let (session, resumed) = match open.last() {
        Some(last) if !options.new_session => (last.clone(), true),
        _ => {
            let (code, key) = (new_code()?, random_hex::<16>()?);
            (
                store.call_blocking(move |c| sql::create_session(c, &code, &key))?,
                false,
            )
        }
    };
    let mut sessions = HashMap::new();
    for row in open.into_iter().chain((!resumed).then(|| session.clone())) {
        let live = Live::load(&store, row)?;
        sessions.insert(live.code.clone(), Arc::new(live));
    }
    listener.set_nonblocking(true).map_err(ClassError::Start)?;
    let address = listener.local_addr().map_err(ClassError::Start)?;
    let base = options
        .public_url
        .clone()
        .map(|url| url.trim_end_matches('/').to_string())
        .unwrap_or_else(|| format!("http://{}", shown_address(address)));
    let ws_base = base
        .replacen("https://", "wss://", 1)
        .replacen("http://", "ws://", 1);
    let site = Site::new(options.site.clone());
    let started = Started {
        address,
        code: session.code.clone(),
        key: session.key.clone(),
        resumed,
        join_url: format!("{base}/?code={}", session.code),
        ws_url: format!("{ws_base}/ws"),
        app_url: site.is_built().then(|| format!("{base}/app/")),
    };
    let ended = store.call_blocking(sql::ended_codes)?.into_iter().collect();
    let hub = Arc::new(Hub {
        store,
        sessions: Mutex::new(sessions),
        ended,
        connections: AtomicUsize::new(0),
        page: Page::new(),
        site,
    });
    Ok((hub, listener, started))
}

/// The address students type for a listening one: a wildcard becomes this machine's address on the
/// room's network (the first non-loopback IPv4 address), a loopback one stays as it is.
fn shown_address(address: SocketAddr) -> String {
    let ip = if address.ip().is_unspecified() {
        room_address().unwrap_or(address.ip())
    } else {
        address.ip()
    };
    SocketAddr::new(ip, address.port()).to_string()
}

/// This machine's first IPv4 address that is not loopback, read from the interfaces (no packet sent).
fn room_address() -> Option<IpAddr> {
    #[cfg(unix)]
    {
        local_interfaces()
            .into_iter()
            .find(|ip| ip.is_ipv4() && !ip.is_loopback())
    }
    #[cfg(not(unix))]
    {
        None
    }
}

#[cfg(unix)]
#[allow(unsafe_code)]
fn local_interfaces() -> Vec<IpAddr> {
    let mut found = Vec::new();
    let mut list: *mut libc::ifaddrs = std::ptr::null_mut();
    // SAFETY: getifaddrs fills `list` with a linked list we only read and then free with
    // freeifaddrs; each ifa_addr is null or points to a sockaddr of the family it names.
    unsafe {
        if libc::getifaddrs(&mut list) != 0 {
            return found;
        }
        let mut entry = list;
        while !entry.is_null() {
            let address = (*entry).ifa_addr;
            if !address.is_null() && i32::from((*address).sa_family) == libc::AF_INET {
                let v4 = &*(address as *const libc::sockaddr_in);
                found.push(IpAddr::from(u32::from_be(v4.sin_addr.s_addr).to_be_bytes()));
            }
            entry = (*entry).ifa_next;
        }
        libc::freeifaddrs(list);
    }
    found
}

fn router(hub: Arc<Hub>) -> Router {
    Router::new()
        .route("/", get(page))
        .route(
            "/app",
            get(|| async { axum::response::Redirect::permanent("/app/") }),
        )
        .route("/app/", get(site_file))
        .route("/app/{name}", get(site_file))
        .route("/ws", get(upgrade))
        .route("/export.csv", get(export_http))
        .route("/healthz", get(|| async { "ok" }))
        .with_state(hub)
}

fn runtime() -> Result<tokio::runtime::Runtime, ClassError> {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .thread_name("class-server")
        .enable_all()
        .build()
        .map_err(ClassError::Start)
}

/// Starts the server on a thread of its own (the app's Class → Start); it runs until dropped.
pub fn start(options: &Options) -> Result<Running, ClassError> {
    let (hub, listener, started) = prepare(options)?;
    let runtime = runtime()?;
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let thread = std::thread::Builder::new()
        .name("class-server-main".into())
        .spawn(move || {
            runtime.block_on(async move {
                if let Ok(listener) = tokio::net::TcpListener::from_std(listener) {
                    let _ = axum::serve(listener, router(hub))
                        .with_graceful_shutdown(async {
                            let _ = stopped.await;
                        })
                        .await;
                }
            });
            runtime.shutdown_timeout(Duration::from_secs(1));
        })
        .map_err(ClassError::Start)?;
    Ok(Running {
        started,
        stop: Some(stop),
        thread: Some(thread),
    })
}

/// Runs the server until Ctrl-C (`raylab class`); `on_start` prints where it listens.
pub fn serve(options: &Options, on_start: impl FnOnce(&Started)) -> Result<(), ClassError> {
    let (hub, listener, started) = prepare(options)?;
    on_start(&started);
    let runtime = runtime()?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::from_std(listener).map_err(ClassError::Start)?;
        axum::serve(listener, router(hub))
            .with_graceful_shutdown(async {
                let _ = tokio::signal::ctrl_c().await;
            })
            .await
            .map_err(ClassError::Start)
    })
}

/// The export of a session, read from the database file: one row per student per question.
pub fn export_rows(db: &Path, code: &str) -> Result<Vec<ExportRow>, ClassError> {
    if !db.exists() {
        return Err(ClassError::UnknownSession(
            normalise_code(code),
            db.display().to_string(),
        ));
    }
    let store = Store::open(db)?;
    let code = normalise_code(code);
    let wanted = code.clone();
    let rows = store.call_blocking(move |c| match sql::session_by_code(c, &wanted)? {
        Some(session) => sql::export(c, session.id).map(Some),
        None => Ok(None),
    })?;
    rows.ok_or_else(|| ClassError::UnknownSession(code, db.display().to_string()))
}

/// Writes export rows as CSV: question, prompt, student, nickname, outcome, values, answered_at,
/// changes, right.
pub fn write_csv(rows: &[ExportRow], out: impl std::io::Write) -> Result<(), ClassError> {
    let fail = |e: csv::Error| ClassError::Write(e.to_string());
    let mut writer = csv::Writer::from_writer(out);
    writer
        .write_record([
            "question",
            "prompt",
            "student",
            "nickname",
            "outcome",
            "values",
            "answered_at",
            "changes",
            "right",
        ])
        .map_err(fail)?;
    for row in rows {
        let given: Given = serde_json::from_str(&row.given).unwrap_or(Given {
            outcome: None,
            values: Vec::new(),
        });
        let values: Vec<&str> = given
            .values
            .iter()
            .map(|v| v.as_deref().unwrap_or(""))
            .collect();
        writer
            .write_record([
                row.question.to_string(),
                row.prompt.clone(),
                row.student.to_string(),
                row.nickname.clone(),
                given.outcome.unwrap_or_default(),
                values.join("; "),
                row.answered_at.clone(),
                row.changes.to_string(),
                if row.right { "yes" } else { "no" }.to_string(),
            ])
            .map_err(fail)?;
    }
    writer.flush().map_err(|e| ClassError::Write(e.to_string()))
}

/// Whether the browser takes gzip.
fn takes_gzip(headers: &HeaderMap) -> bool {
    headers
        .get(header::ACCEPT_ENCODING)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.contains("gzip"))
}

async fn page(State(hub): State<Arc<Hub>>, headers: HeaderMap) -> Response {
    hub.page.response(takes_gzip(&headers))
}

async fn site_file(
    State(hub): State<Arc<Hub>>,
    name: Option<axum::extract::Path<String>>,
    headers: HeaderMap,
) -> Response {
    let name = name.map(|n| n.0).unwrap_or_default();
    let gzip = takes_gzip(&headers);
    // Reading and compressing a file (the app's 8 MB of wasm) is blocking work.
    tokio::task::spawn_blocking(move || hub.site.response(&name, gzip))
        .await
        .unwrap_or_else(|_| StatusCode::INTERNAL_SERVER_ERROR.into_response())
}

#[derive(serde::Deserialize)]
struct ExportQuery {
    code: String,
    key: String,
}

async fn export_http(State(hub): State<Arc<Hub>>, Query(query): Query<ExportQuery>) -> Response {
    let code = normalise_code(&query.code);
    let live = lock(&hub.sessions).get(&code).cloned();
    let Some(live) = live.filter(|live| same_secret(&live.key, &query.key)) else {
        return (StatusCode::FORBIDDEN, "unknown code or wrong teacher key\n").into_response();
    };
    let id = live.id;
    let rows = match hub.store.call(move |c| sql::export(c, id)).await {
        Ok(rows) => rows,
        Err(e) => return (StatusCode::INTERNAL_SERVER_ERROR, e.to_string()).into_response(),
    };
    let mut csv = Vec::new();
    if let Err(e) = write_csv(&rows, &mut csv) {
        return (StatusCode::INTERNAL_SERVER_ERROR, e.to_string()).into_response();
    }
    ([(header::CONTENT_TYPE, "text/csv; charset=utf-8")], csv).into_response()
}

/// Holds one of the server's connection places while a connection lives.
struct Place(Arc<Hub>);

impl Drop for Place {
    fn drop(&mut self) {
        self.0.connections.fetch_sub(1, Ordering::SeqCst);
    }
}

async fn upgrade(State(hub): State<Arc<Hub>>, ws: WebSocketUpgrade) -> Response {
    if hub.connections.fetch_add(1, Ordering::SeqCst) >= MAX_CONNECTIONS {
        hub.connections.fetch_sub(1, Ordering::SeqCst);
        return (
            StatusCode::SERVICE_UNAVAILABLE,
            "the class is full: try again in a moment\n",
        )
            .into_response();
    }
    let place = Place(hub.clone());
    ws.max_message_size(MAX_MESSAGE_BYTES)
        .max_frame_size(MAX_MESSAGE_BYTES)
        .on_upgrade(move |socket| async move {
            Connection::new(hub).run(socket).await;
            drop(place);
        })
}

/// Who a connection turned out to be.
enum Who {
    Nobody,
    Student { live: Arc<Live>, id: i64 },
    Teacher { live: Arc<Live> },
}

/// One WebSocket: its identity, its rate bucket, its strikes.
struct Connection {
    hub: Arc<Hub>,
    who: Who,
    tokens: f64,
    refilled: tokio::time::Instant,
    rate_strikes: u32,
    key_strikes: u32,
}

/// What a handled message asks of the connection.
enum Next {
    Stay,
    Close,
}

impl Connection {
    fn new(hub: Arc<Hub>) -> Connection {
        Connection {
            hub,
            who: Who::Nobody,
            tokens: BURST,
            refilled: tokio::time::Instant::now(),
            rate_strikes: 0,
            key_strikes: 0,
        }
    }

    async fn run(mut self, mut socket: WebSocket) {
        let deadline = tokio::time::Instant::now() + JOIN_DEADLINE;
        // Before it says who it is, a connection only has its messages and the join deadline.
        let mut events: Option<broadcast::Receiver<Event>> = None;
        let mut changes: Option<watch::Receiver<u64>> = None;
        loop {
            let idle = tokio::time::sleep(if matches!(self.who, Who::Nobody) {
                deadline.saturating_duration_since(tokio::time::Instant::now())
            } else {
                IDLE_LIMIT
            });
            let next = tokio::select! {
                incoming = socket.recv() => match incoming {
                    Some(Ok(Message::Text(text))) => self.on_text(&mut socket, text.as_str()).await,
                    Some(Ok(Message::Binary(_))) => {
                        send(&mut socket, &error("messages are JSON text")).await
                    }
                    Some(Ok(Message::Ping(_) | Message::Pong(_))) => Next::Stay,
                    Some(Ok(Message::Close(_))) | Some(Err(_)) | None => Next::Close,
                },
                event = recv_event(&mut events) => match event {
                    Ok(Event::Ended) => {
                        let _ = send(&mut socket, &ToClient::Ended).await;
                        Next::Close
                    }
                    Ok(event) => self.on_event(&mut socket, Some(event)).await,
                    Err(broadcast::error::RecvError::Lagged(_)) => self.on_event(&mut socket, None).await,
                    Err(broadcast::error::RecvError::Closed) => Next::Close,
                },
                changed = wait_changed(&mut changes) => match changed {
                    true => self.send_tally(&mut socket).await,
                    false => Next::Close,
                },
                () = idle => Next::Close,
            };
            if matches!(next, Next::Close) {
                break;
            }
            // Once it is in, a student hears the session's events and a teacher its changes.
            match &self.who {
                Who::Student { live, .. } if events.is_none() => {
                    events = Some(live.events.subscribe());
                }
                Who::Teacher { live } if changes.is_none() => {
                    let mut receiver = live.changed.subscribe();
                    receiver.mark_changed();
                    changes = Some(receiver);
                }
                _ => {}
            }
        }
        self.leave();
        let _ = socket.send(Message::Close(None)).await;
    }

    /// A student leaving is no longer counted as connected.
    fn leave(&self) {
        if let Who::Student { live, id } = &self.who {
            if let Some(student) = lock(&live.state).students.get_mut(id) {
                student.connected = student.connected.saturating_sub(1);
            }
            live.bump();
        }
    }

    /// Takes a token from the bucket; false when the connection is sending too fast.
    fn take_token(&mut self) -> bool {
        let now = tokio::time::Instant::now();
        let elapsed = now.duration_since(self.refilled).as_secs_f64();
        self.refilled = now;
        self.tokens = (self.tokens + elapsed * RATE_PER_SECOND).min(BURST);
        if self.tokens >= 1.0 {
            self.tokens -= 1.0;
            true
        } else {
            false
        }
    }

    async fn on_text(&mut self, socket: &mut WebSocket, text: &str) -> Next {
        if !self.take_token() {
            self.rate_strikes += 1;
            if self.rate_strikes > RATE_STRIKES {
                let _ = send(socket, &error("too many messages: disconnected")).await;
                return Next::Close;
            }
            return send(socket, &error("too many messages: slow down")).await;
        }
        let message = match read_message(text) {
            Ok(message) => message,
            Err(why) => return send(socket, &error(why)).await,
        };
        let replies = match self.handle(message).await {
            Ok(replies) => replies,
            Err(why) => vec![error(why)],
        };
        for reply in &replies {
            if matches!(send(socket, reply).await, Next::Close) {
                return Next::Close;
            }
        }
        if self.key_strikes >= KEY_STRIKES {
            return Next::Close;
        }
        Next::Stay
    }

    /// What a message does, and the replies to this connection.
    async fn handle(&mut self, message: ToServer) -> Result<Vec<ToClient>, String> {
        match (message, &self.who) {
            (ToServer::Ping {}, _) => Ok(vec![ToClient::Pong]),
            (
                ToServer::Join {
                    code,
                    token,
                    nickname,
                },
                Who::Nobody,
            ) => self.join(&code, token, nickname.as_deref()).await,
            (ToServer::Teach { code, key }, Who::Nobody) => self.teach(&code, &key),
            (ToServer::Join { .. } | ToServer::Teach { .. }, _) => {
                Err("this connection has joined already".into())
            }
            (_, Who::Nobody) => Err("join first: send your class code".into()),
            (
                ToServer::Answer {
                    question,
                    outcome,
                    values,
                },
                Who::Student { live, id },
            ) => {
                let (live, id) = (live.clone(), *id);
                self.answer(&live, id, question, Given { outcome, values })
                    .await
            }
            (ToServer::Answer { .. }, Who::Teacher { .. }) => {
                Err("the teacher's connection does not answer".into())
            }
            (command, Who::Student { .. }) => Err(format!(
                "only the teacher can {}",
                match command {
                    ToServer::Ask { .. } => "ask a question",
                    ToServer::Lock {} => "lock answers",
                    ToServer::Reveal {} => "reveal the answer",
                    ToServer::ShowNames { .. } => "show names",
                    _ => "end the class",
                }
            )),
            (command, Who::Teacher { live }) => {
                let live = live.clone();
                self.command(&live, command).await
            }
        }
    }

    fn find(&self, code: &str) -> Result<Arc<Live>, String> {
        let code = normalise_code(code);
        let live = lock(&self.hub.sessions).get(&code).cloned();
        match live {
            Some(live) if lock(&live.state).ended => Err(format!(
                "the class {code} has ended: ask your teacher for the new code"
            )),
            Some(live) => Ok(live),
            None if self.hub.ended.contains(&code) => Err(format!(
                "the class {code} has ended: ask your teacher for the new code"
            )),
            None => Err(format!(
                "no class with code {}: check the code on the projector",
                code.chars().take(12).collect::<String>()
            )),
        }
    }

    async fn join(
        &mut self,
        code: &str,
        token: Option<String>,
        nickname: Option<&str>,
    ) -> Result<Vec<ToClient>, String> {
        let live = self.find(code)?;
        let nickname = clean_nickname(nickname)?;
        let known = token
            .as_deref()
            .and_then(|token| lock(&live.state).by_token.get(token).copied());
        let (id, token) = match known {
            Some(id) => {
                let renamed = nickname.is_some()
                    && lock(&live.state).students.get(&id).map(|s| &s.nickname) != Some(&nickname);
                if renamed {
                    let name = nickname.clone();
                    self.hub
                        .store
                        .call(move |c| sql::rename_student(c, id, name.as_deref()))
                        .await
                        .map_err(|e| e.to_string())?;
                    if let Some(student) = lock(&live.state).students.get_mut(&id) {
                        student.nickname = nickname.clone();
                    }
                }
                (id, token.unwrap_or_default())
            }
            None => {
                if lock(&live.state).students.len() >= MAX_STUDENTS {
                    return Err(format!("the class is full ({MAX_STUDENTS} students)"));
                }
                let (session, token, name) = (
                    live.id,
                    random_hex::<16>().map_err(|e| e.to_string())?,
                    nickname.clone(),
                );
                let row = self
                    .hub
                    .store
                    .call(move |c| sql::add_student(c, session, &token, name.as_deref()))
                    .await
                    .map_err(|e| e.to_string())?;
                let mut state = lock(&live.state);
                state.by_token.insert(row.token.clone(), row.id);
                state.students.insert(
                    row.id,
                    Student {
                        number: row.number,
                        nickname: row.nickname,
                        connected: 0,
                    },
                );
                (row.id, row.token)
            }
        };
        let welcome = {
            let mut state = lock(&live.state);
            let student = state.students.get_mut(&id);
            let nickname = student.as_ref().and_then(|s| s.nickname.clone());
            if let Some(student) = student {
                student.connected += 1;
            }
            let current = state.question.as_ref();
            ToClient::Welcome {
                role: Role::Student,
                code: live.code.clone(),
                token: Some(token),
                nickname,
                question: current.map(|q| Box::new(q.asked.view(q.id, q.number, q.state))),
                answer: current.and_then(|q| q.answers.get(&id).map(|a| a.given.clone())),
                reveal: Live::reveal_for(&state, Some(id)),
            }
        };
        live.bump();
        self.who = Who::Student { live, id };
        Ok(vec![welcome])
    }

    fn teach(&mut self, code: &str, key: &str) -> Result<Vec<ToClient>, String> {
        let live = self.find(code)?;
        if !same_secret(&live.key, key.trim()) {
            self.key_strikes += 1;
            return Err("wrong teacher key".into());
        }
        let welcome = {
            let state = lock(&live.state);
            let current = state.question.as_ref();
            ToClient::Welcome {
                role: Role::Teacher,
                code: live.code.clone(),
                token: None,
                nickname: None,
                question: current.map(|q| Box::new(q.asked.view(q.id, q.number, q.state))),
                answer: None,
                reveal: Live::reveal_for(&state, None),
            }
        };
        self.who = Who::Teacher { live };
        Ok(vec![welcome])
    }

    async fn answer(
        &mut self,
        live: &Arc<Live>,
        student: i64,
        question: i64,
        given: Given,
    ) -> Result<Vec<ToClient>, String> {
        let (given, right) = {
            let state = lock(&live.state);
            let current = state
                .question
                .as_ref()
                .filter(|q| q.id == question)
                .ok_or("that question is over: answer the one on screen")?;
            if current.state != QuestionState::Open {
                return Err("answers are locked: yours was not changed".into());
            }
            let given = current.asked.check_given(given)?;
            let right = current.asked.is_right(&given);
            (given, right)
        };
        let json = serde_json::to_string(&given).map_err(|e| e.to_string())?;
        let changes = self
            .hub
            .store
            .call(move |c| sql::save_answer(c, question, student, &json, right))
            .await
            .map_err(|e| format!("your answer was not saved ({e}): send it again"))?;
        if let Some(current) = lock(&live.state)
            .question
            .as_mut()
            .filter(|q| q.id == question)
        {
            current.answers.insert(student, Answered { given, right });
        }
        live.bump();
        Ok(vec![ToClient::Ack { question, changes }])
    }

    async fn command(
        &mut self,
        live: &Arc<Live>,
        command: ToServer,
    ) -> Result<Vec<ToClient>, String> {
        let store = &self.hub.store;
        let session = live.id;
        match command {
            ToServer::Ask { question } => {
                let asked = Asked::new(question.clone()).map_err(|e| e.to_string())?;
                let spec = serde_json::to_string(&question).map_err(|e| e.to_string())?;
                let row = store
                    .call(move |c| sql::add_question(c, session, &spec))
                    .await
                    .map_err(|e| e.to_string())?;
                let view = asked.view(row.id, row.number, QuestionState::Open);
                lock(&live.state).question = Some(Current {
                    id: row.id,
                    number: row.number,
                    asked,
                    state: QuestionState::Open,
                    answers: HashMap::new(),
                });
                let _ = live.events.send(Event::Question);
                live.bump();
                Ok(vec![ToClient::Question {
                    question: Box::new(view),
                }])
            }
            ToServer::Lock {} | ToServer::Reveal {} => {
                let to = if matches!(command, ToServer::Lock {}) {
                    QuestionState::Locked
                } else {
                    QuestionState::Revealed
                };
                let id = lock(&live.state)
                    .question
                    .as_ref()
                    .map(|q| q.id)
                    .ok_or("no question has been asked")?;
                store
                    .call(move |c| sql::set_question_state(c, id, to))
                    .await
                    .map_err(|e| e.to_string())?;
                let reply = {
                    let mut state = lock(&live.state);
                    let current = state.question.as_mut().filter(|q| q.id == id);
                    let Some(current) = current else {
                        return Ok(Vec::new());
                    };
                    current.state = to;
                    let view = current.asked.view(current.id, current.number, to);
                    match Live::reveal_for(&state, None) {
                        Some(reveal) => ToClient::Revealed {
                            question: id,
                            reveal,
                        },
                        None => ToClient::Question {
                            question: Box::new(view),
                        },
                    }
                };
                let _ = live.events.send(if to == QuestionState::Revealed {
                    Event::Revealed
                } else {
                    Event::Question
                });
                live.bump();
                Ok(vec![reply])
            }
            ToServer::ShowNames { show } => {
                store
                    .call(move |c| sql::set_show_names(c, session, show))
                    .await
                    .map_err(|e| e.to_string())?;
                lock(&live.state).show_names = show;
                live.bump();
                Ok(Vec::new())
            }
            ToServer::End {} => {
                store
                    .call(move |c| sql::end_session(c, session))
                    .await
                    .map_err(|e| e.to_string())?;
                lock(&live.state).ended = true;
                let _ = live.events.send(Event::Ended);
                Ok(vec![ToClient::Ended])
            }
            _ => Ok(Vec::new()),
        }
    }

    /// A session event reaches a student: the question as it stands now, or the reveal (on a lag,
    /// whatever is current).
    async fn on_event(&mut self, socket: &mut WebSocket, event: Option<Event>) -> Next {
        let Who::Student { live, id } = &self.who else {
            return Next::Stay;
        };
        let message = {
            let state = lock(&live.state);
            let Some(current) = state.question.as_ref() else {
                return Next::Stay;
            };
            match (event, Live::reveal_for(&state, Some(*id))) {
                (Some(Event::Revealed) | None, Some(reveal)) => ToClient::Revealed {
                    question: current.id,
                    reveal,
                },
                _ => ToClient::Question {
                    question: Box::new(current.asked.view(
                        current.id,
                        current.number,
                        current.state,
                    )),
                },
            }
        };
        send(socket, &message).await
    }

    async fn send_tally(&mut self, socket: &mut WebSocket) -> Next {
        let Who::Teacher { live } = &self.who else {
            return Next::Stay;
        };
        let tally = live.tally();
        send(socket, &ToClient::Tally(tally)).await
    }
}

/// The next session event, or never when the connection hears none.
async fn recv_event(
    events: &mut Option<broadcast::Receiver<Event>>,
) -> Result<Event, broadcast::error::RecvError> {
    match events {
        Some(receiver) => receiver.recv().await,
        None => std::future::pending().await,
    }
}

/// Waits for the tally to change; false when the session is gone; never when there is no tally.
async fn wait_changed(changes: &mut Option<watch::Receiver<u64>>) -> bool {
    match changes {
        Some(receiver) => receiver.changed().await.is_ok(),
        None => std::future::pending().await,
    }
}

fn error(message: impl Into<String>) -> ToClient {
    ToClient::Error {
        message: message.into(),
    }
}

async fn send(socket: &mut WebSocket, message: &ToClient) -> Next {
    let Ok(text) = serde_json::to_string(message) else {
        return Next::Stay;
    };
    match socket.send(Message::Text(text.into())).await {
        Ok(()) => Next::Stay,
        Err(_) => Next::Close,
    }
}
