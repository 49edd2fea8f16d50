//! Real clients of a real `raylab class`: the server started as a user starts it (the binary, a free
//! loopback port, a database file), and WebSocket clients speaking its JSON protocol. Shared by the
//! class tests and the load benchmark (`benches/class.rs`).

#![allow(dead_code, reason = "the benchmark uses a part of it")]

use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use raylab::class::protocol::{QuestionSpec, ToClient};
use serde_json::{Value, json};
use tungstenite::stream::MaybeTlsStream;
use tungstenite::{Message, WebSocket};

/// How long any one wait for the server may take before the test fails (generous: CI is 2 busy cores).
pub const PATIENCE: Duration = Duration::from_secs(20);

/// A running `raylab class`.
pub struct Server {
    child: Child,
    /// `127.0.0.1:PORT`.
    pub address: String,
    /// The join code.
    pub code: String,
    /// The teacher's key.
    pub key: String,
    /// Its database.
    pub db: PathBuf,
    /// Its process id (for CPU and memory figures).
    pub pid: u32,
}

/// The `raylab` binary Cargo built for these tests.
pub fn raylab() -> &'static str {
    env!("CARGO_BIN_EXE_raylab")
}

impl Server {
    /// Starts `raylab class` on a free loopback port with `db`, and reads what it prints.
    pub fn start(db: &Path, extra: &[&str]) -> Server {
        let mut child = Command::new(raylab())
            .args(["class", "--listen", "127.0.0.1:0", "--db"])
            .arg(db)
            .args(extra)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("raylab class starts");
        let mut lines = BufReader::new(child.stdout.take().expect("its output"));
        let (mut address, mut code, mut key) = (None, None, None);
        let mut line = String::new();
        while key.is_none() {
            line.clear();
            if lines.read_line(&mut line).expect("read its output") == 0 {
                panic!("raylab class stopped before printing its key");
            }
            let words: Vec<&str> = line.split_whitespace().collect();
            match words.as_slice() {
                ["raylab", "class:", "listening", "on", url, ..] => {
                    address = Some(url.trim_start_matches("http://").to_string())
                }
                ["class", c, ..] => code = Some(c.to_string()),
                ["teacher", "key", k, ..] => key = Some(k.to_string()),
                _ => {}
            }
        }
        // Keep reading (and dropping) its output so that it never blocks on a full pipe.
        std::thread::spawn(move || for _ in lines.lines() {});
        Server {
            pid: child.id(),
            child,
            address: address.expect("the address line"),
            code: code.expect("the class line"),
            key: key.expect("the key line"),
            db: db.to_path_buf(),
        }
    }

    /// Kills the server with SIGKILL: no chance to flush or clean up.
    pub fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.kill();
    }
}

/// A WebSocket client of the class server.
pub struct Client {
    socket: WebSocket<MaybeTlsStream<TcpStream>>,
}

impl Client {
    /// Connects to `ws://ADDRESS/ws`.
    pub fn connect(address: &str) -> Client {
        Client::try_connect(address).expect("the server takes the connection")
    }

    /// Connects, or says why not.
    pub fn try_connect(address: &str) -> Result<Client, String> {
        let stream = TcpStream::connect(address).map_err(|e| e.to_string())?;
        stream
            .set_read_timeout(Some(PATIENCE))
            .map_err(|e| e.to_string())?;
        stream.set_nodelay(true).map_err(|e| e.to_string())?;
        let (socket, _) =
            tungstenite::client(format!("ws://{address}/ws"), MaybeTlsStream::Plain(stream))
                .map_err(|e| e.to_string())?;
        Ok(Client { socket })
    }

    /// Sends a message.
    pub fn send(&mut self, message: Value) {
        self.send_text(&message.to_string());
    }

    /// Sends a message, or says why it could not (the server closed the connection).
    pub fn try_send(&mut self, message: Value) -> Result<(), String> {
        self.socket
            .send(Message::text(message.to_string()))
            .map_err(|e| e.to_string())
    }

    /// Sends any text, even text that is not a message.
    pub fn send_text(&mut self, text: &str) {
        self.socket
            .send(Message::text(text))
            .expect("the message is sent");
    }

    /// The next message from the server, or the reason there is none (closed, timed out).
    pub fn try_recv(&mut self) -> Result<ToClient, String> {
        loop {
            match self.socket.read().map_err(|e| e.to_string())? {
                Message::Text(text) => {
                    return serde_json::from_str(text.as_str())
                        .map_err(|e| format!("not a server message: {e}: {text}"));
                }
                Message::Close(_) => return Err("closed".into()),
                _ => {}
            }
        }
    }

    /// The next message.
    pub fn recv(&mut self) -> ToClient {
        self.try_recv().expect("a message from the server")
    }

    /// Skips messages until one that `want` takes (tallies and pongs may come in between).
    pub fn recv_until(&mut self, what: &str, want: impl Fn(&ToClient) -> bool) -> ToClient {
        let start = Instant::now();
        loop {
            assert!(start.elapsed() < PATIENCE, "no {what} within {PATIENCE:?}");
            let message = self
                .try_recv()
                .unwrap_or_else(|e| panic!("waiting for {what}: {e}"));
            if want(&message) {
                return message;
            }
        }
    }

    /// Joins as a student; returns the client and its welcome.
    pub fn student(
        address: &str,
        code: &str,
        token: Option<&str>,
        nickname: Option<&str>,
    ) -> (Client, ToClient) {
        let mut client = Client::connect(address);
        client.send(json!({"type": "join", "code": code, "token": token, "nickname": nickname}));
        let welcome = client.recv();
        (client, welcome)
    }

    /// Takes the teacher's controls; returns the client and its welcome.
    pub fn teacher(address: &str, code: &str, key: &str) -> (Client, ToClient) {
        let mut client = Client::connect(address);
        client.send(json!({"type": "teach", "code": code, "key": key}));
        let welcome = client.recv();
        (client, welcome)
    }

    /// Closes the connection.
    pub fn close(mut self) {
        let _ = self.socket.close(None);
        let _ = self.socket.flush();
    }
}

/// The token of a student's welcome.
pub fn token_of(welcome: &ToClient) -> String {
    match welcome {
        ToClient::Welcome {
            token: Some(token), ..
        } => token.clone(),
        other => panic!("expected a student's welcome, got {other:?}"),
    }
}

/// Seed 000's triangle question: A (1, 0, 0), B (0, 1, 0), C (0, 0, 1), L at the origin, D (1, 1, 1);
/// the ray hits at β = γ = t = 1/3.
pub fn seed000_triangle() -> QuestionSpec {
    let point = |p: [&str; 3]| p.iter().map(|c| c.to_string()).collect();
    QuestionSpec {
        kind: "triangle".into(),
        prompt: "Where does the ray meet the triangle?".into(),
        inputs: vec![
            point(["1", "0", "0"]),
            point(["0", "1", "0"]),
            point(["0", "0", "1"]),
            point(["0", "0", "0"]),
            point(["1", "1", "1"]),
        ],
    }
}

/// A temporary folder removed when dropped.
pub struct TempDir(pub PathBuf);

impl TempDir {
    /// A new empty folder under the system's temporary folder.
    pub fn new(name: &str) -> TempDir {
        let path = std::env::temp_dir().join(format!(
            "raylab-{name}-{}-{}",
            std::process::id(),
            Instant::now().elapsed().as_nanos() ^ (std::ptr::addr_of!(name) as u128)
        ));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).expect("a temporary folder");
        TempDir(path)
    }

    /// A path inside it.
    pub fn join(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
