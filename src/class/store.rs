//! The class's database: one SQLite file holding every session, student, question, answer (each
//! change kept) and reveal. One thread owns the connection ("class-db"); callers send it jobs and
//! wait for their result, which comes only after the job's transaction is committed, so an answer the
//! server acknowledges is on disk. Jobs that arrive together share one transaction (a group commit):
//! 300 answers in a burst cost a few commits, not 300.
//!
//! The file is in WAL mode with `synchronous = FULL`: a commit survives the process being killed and
//! the machine losing power.

use std::path::Path;
use std::sync::mpsc;

use rusqlite::{Connection, OptionalExtension, params};

use super::protocol::QuestionState;

/// A failure of the database, as one line for the user.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// SQLite refused.
    #[error("database: {0}")]
    Sql(#[from] rusqlite::Error),
    /// The database thread is gone (the server is stopping).
    #[error("the database is closed")]
    Closed,
    /// The file could not be opened or made.
    #[error("cannot open the class database {path}: {error}")]
    Open {
        /// The file.
        path: String,
        /// Why.
        error: String,
    },
}

type Reply = Box<dyn FnOnce(bool) + Send>;
type Job = Box<dyn FnOnce(&Connection) -> Reply + Send>;

/// A handle to the database thread; clones share it.
#[derive(Clone)]
pub struct Store {
    jobs: mpsc::Sender<Job>,
}

/// The schema. `answers` holds each student's current answer, `answer_changes` every answer ever
/// given (the first and each change), so nothing a student sent is lost.
const SCHEMA: &str = "
CREATE TABLE IF NOT EXISTS sessions (
    id INTEGER PRIMARY KEY,
    code TEXT NOT NULL UNIQUE,
    teacher_key TEXT NOT NULL,
    show_names INTEGER NOT NULL DEFAULT 0,
    started_ms INTEGER NOT NULL,
    ended_ms INTEGER
);
CREATE TABLE IF NOT EXISTS students (
    id INTEGER PRIMARY KEY,
    session_id INTEGER NOT NULL REFERENCES sessions(id),
    number INTEGER NOT NULL,
    token TEXT NOT NULL UNIQUE,
    nickname TEXT,
    joined_ms INTEGER NOT NULL,
    UNIQUE (session_id, number)
);
CREATE TABLE IF NOT EXISTS questions (
    id INTEGER PRIMARY KEY,
    session_id INTEGER NOT NULL REFERENCES sessions(id),
    number INTEGER NOT NULL,
    spec TEXT NOT NULL,
    state TEXT NOT NULL,
    asked_ms INTEGER NOT NULL,
    locked_ms INTEGER,
    revealed_ms INTEGER,
    UNIQUE (session_id, number)
);
CREATE TABLE IF NOT EXISTS answers (
    question_id INTEGER NOT NULL REFERENCES questions(id),
    student_id INTEGER NOT NULL REFERENCES students(id),
    given TEXT NOT NULL,
    is_right INTEGER NOT NULL,
    changes INTEGER NOT NULL,
    answered_ms INTEGER NOT NULL,
    PRIMARY KEY (question_id, student_id)
);
CREATE TABLE IF NOT EXISTS answer_changes (
    id INTEGER PRIMARY KEY,
    question_id INTEGER NOT NULL REFERENCES questions(id),
    student_id INTEGER NOT NULL REFERENCES students(id),
    given TEXT NOT NULL,
    is_right INTEGER NOT NULL,
    answered_ms INTEGER NOT NULL
);
";

/// A session as stored.
#[derive(Clone, Debug, PartialEq)]
pub struct SessionRow {
    /// Its id.
    pub id: i64,
    /// The join code.
    pub code: String,
    /// The teacher's key.
    pub key: String,
    /// Whether the tally names students.
    pub show_names: bool,
    /// When it started (ms since 1970).
    pub started_ms: i64,
}

/// A student as stored.
#[derive(Clone, Debug, PartialEq)]
pub struct StudentRow {
    /// Its id.
    pub id: i64,
    /// Its number in the session, from 1.
    pub number: i64,
    /// Its token.
    pub token: String,
    /// Its nickname.
    pub nickname: Option<String>,
}

/// A question as stored.
#[derive(Clone, Debug, PartialEq)]
pub struct QuestionRow {
    /// Its id.
    pub id: i64,
    /// Its number in the session.
    pub number: i64,
    /// The spec as JSON.
    pub spec: String,
    /// Its state.
    pub state: QuestionState,
}

/// An answer as stored.
#[derive(Clone, Debug, PartialEq)]
pub struct AnswerRow {
    /// The student's id.
    pub student_id: i64,
    /// The answer as JSON.
    pub given: String,
    /// Whether it was right.
    pub right: bool,
    /// How often it was given.
    pub changes: i64,
}

/// One line of the export: a student's answer to a question.
#[derive(Clone, Debug, PartialEq)]
pub struct ExportRow {
    /// The question's number.
    pub question: i64,
    /// Its wording.
    pub prompt: String,
    /// The student's number.
    pub student: i64,
    /// The nickname, or empty.
    pub nickname: String,
    /// The answer as JSON.
    pub given: String,
    /// When it was last changed, UTC, ISO 8601.
    pub answered_at: String,
    /// How often it was given.
    pub changes: i64,
    /// Whether it was right.
    pub right: bool,
}

/// Milliseconds since 1970, the time every row keeps.
pub fn now_ms() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_millis() as i64)
        .unwrap_or(0)
}

impl Store {
    /// Opens (or makes) the database file and starts its thread.
    pub fn open(path: &Path) -> Result<Store, StoreError> {
        let fail = |error: String| StoreError::Open {
            path: path.display().to_string(),
            error,
        };
        if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent).map_err(|e| fail(e.to_string()))?;
        }
        let connection = Connection::open(path).map_err(|e| fail(e.to_string()))?;
        connection
            .execute_batch(
                "PRAGMA journal_mode = WAL; PRAGMA synchronous = FULL; PRAGMA foreign_keys = ON;",
            )
            .and_then(|()| connection.execute_batch(SCHEMA))
            .map_err(|e| fail(e.to_string()))?;
        let (jobs, inbox) = mpsc::channel::<Job>();
        std::thread::Builder::new()
            .name("class-db".into())
            .spawn(move || serve(connection, inbox))
            .map_err(|e| fail(e.to_string()))?;
        Ok(Store { jobs })
    }

    /// Runs `job` on the database thread and returns its result once its transaction is committed.
    pub async fn call<T: Send + 'static>(
        &self,
        job: impl FnOnce(&Connection) -> rusqlite::Result<T> + Send + 'static,
    ) -> Result<T, StoreError> {
        let (reply, result) = tokio::sync::oneshot::channel();
        self.send(job, move |outcome| {
            let _ = reply.send(outcome);
        })?;
        result.await.map_err(|_| StoreError::Closed)?
    }

    /// [`Store::call`] for code that is not async (start-up, the export command).
    pub fn call_blocking<T: Send + 'static>(
        &self,
        job: impl FnOnce(&Connection) -> rusqlite::Result<T> + Send + 'static,
    ) -> Result<T, StoreError> {
        let (reply, result) = mpsc::channel();
        self.send(job, move |outcome| {
            let _ = reply.send(outcome);
        })?;
        result.recv().map_err(|_| StoreError::Closed)?
    }

    fn send<T: Send + 'static>(
        &self,
        job: impl FnOnce(&Connection) -> rusqlite::Result<T> + Send + 'static,
        reply: impl FnOnce(Result<T, StoreError>) + Send + 'static,
    ) -> Result<(), StoreError> {
        let job: Job = Box::new(move |connection| {
            let result = job(connection);
            Box::new(move |committed| {
                reply(match result {
                    Ok(_) if !committed => Err(StoreError::Closed),
                    other => other.map_err(StoreError::from),
                })
            })
        });
        self.jobs.send(job).map_err(|_| StoreError::Closed)
    }
}

/// The database thread: takes the jobs waiting, runs them in one transaction, commits, then replies.
fn serve(connection: Connection, inbox: mpsc::Receiver<Job>) {
    while let Ok(first) = inbox.recv() {
        let began = connection.execute_batch("BEGIN IMMEDIATE").is_ok();
        let mut replies = vec![first(&connection)];
        // At most 512 jobs a transaction, so a flood still commits (and answers) as it goes.
        while replies.len() < 512 {
            match inbox.try_recv() {
                Ok(job) => replies.push(job(&connection)),
                Err(_) => break,
            }
        }
        let committed = began && connection.execute_batch("COMMIT").is_ok();
        if began && !committed {
            let _ = connection.execute_batch("ROLLBACK");
        }
        for reply in replies {
            reply(committed);
        }
    }
}

/// The queries, each run on the database thread inside [`Store::call`].
pub mod sql {
    use super::*;

    /// A new session.
    pub fn create_session(c: &Connection, code: &str, key: &str) -> rusqlite::Result<SessionRow> {
        let started_ms = now_ms();
        c.execute(
            "INSERT INTO sessions (code, teacher_key, started_ms) VALUES (?1, ?2, ?3)",
            params![code, key, started_ms],
        )?;
        Ok(SessionRow {
            id: c.last_insert_rowid(),
            code: code.into(),
            key: key.into(),
            show_names: false,
            started_ms,
        })
    }

    fn session_of(row: &rusqlite::Row) -> rusqlite::Result<SessionRow> {
        Ok(SessionRow {
            id: row.get(0)?,
            code: row.get(1)?,
            key: row.get(2)?,
            show_names: row.get(3)?,
            started_ms: row.get(4)?,
        })
    }

    /// Every session not ended, oldest first.
    pub fn open_sessions(c: &Connection) -> rusqlite::Result<Vec<SessionRow>> {
        let mut statement = c.prepare(
            "SELECT id, code, teacher_key, show_names, started_ms FROM sessions
             WHERE ended_ms IS NULL ORDER BY id",
        )?;
        statement.query_map([], session_of)?.collect()
    }

    /// The codes of every ended session (so that a student typing one hears it has ended).
    pub fn ended_codes(c: &Connection) -> rusqlite::Result<Vec<String>> {
        let mut statement = c.prepare("SELECT code FROM sessions WHERE ended_ms IS NOT NULL")?;
        statement.query_map([], |row| row.get(0))?.collect()
    }

    /// The session with this code, ended or not.
    pub fn session_by_code(c: &Connection, code: &str) -> rusqlite::Result<Option<SessionRow>> {
        c.query_row(
            "SELECT id, code, teacher_key, show_names, started_ms FROM sessions WHERE code = ?1",
            [code],
            session_of,
        )
        .optional()
    }

    /// Ends a session.
    pub fn end_session(c: &Connection, session: i64) -> rusqlite::Result<()> {
        c.execute(
            "UPDATE sessions SET ended_ms = ?2 WHERE id = ?1",
            params![session, now_ms()],
        )
        .map(drop)
    }

    /// Whether the tally names students.
    pub fn set_show_names(c: &Connection, session: i64, show: bool) -> rusqlite::Result<()> {
        c.execute(
            "UPDATE sessions SET show_names = ?2 WHERE id = ?1",
            params![session, show],
        )
        .map(drop)
    }

    /// A new student, numbered after the session's last.
    pub fn add_student(
        c: &Connection,
        session: i64,
        token: &str,
        nickname: Option<&str>,
    ) -> rusqlite::Result<StudentRow> {
        let number: i64 = c.query_row(
            "SELECT COALESCE(MAX(number), 0) + 1 FROM students WHERE session_id = ?1",
            [session],
            |row| row.get(0),
        )?;
        c.execute(
            "INSERT INTO students (session_id, number, token, nickname, joined_ms)
             VALUES (?1, ?2, ?3, ?4, ?5)",
            params![session, number, token, nickname, now_ms()],
        )?;
        Ok(StudentRow {
            id: c.last_insert_rowid(),
            number,
            token: token.into(),
            nickname: nickname.map(String::from),
        })
    }

    /// A student's new nickname.
    pub fn rename_student(
        c: &Connection,
        student: i64,
        nickname: Option<&str>,
    ) -> rusqlite::Result<()> {
        c.execute(
            "UPDATE students SET nickname = ?2 WHERE id = ?1",
            params![student, nickname],
        )
        .map(drop)
    }

    /// Every student of a session.
    pub fn students(c: &Connection, session: i64) -> rusqlite::Result<Vec<StudentRow>> {
        let mut statement = c.prepare(
            "SELECT id, number, token, nickname FROM students WHERE session_id = ?1 ORDER BY number",
        )?;
        statement
            .query_map([session], |row| {
                Ok(StudentRow {
                    id: row.get(0)?,
                    number: row.get(1)?,
                    token: row.get(2)?,
                    nickname: row.get(3)?,
                })
            })?
            .collect()
    }

    /// A new question, numbered after the session's last; the one before is closed (revealed).
    pub fn add_question(c: &Connection, session: i64, spec: &str) -> rusqlite::Result<QuestionRow> {
        let now = now_ms();
        c.execute(
            "UPDATE questions SET state = 'revealed', revealed_ms = COALESCE(revealed_ms, ?2)
             WHERE session_id = ?1 AND state != 'revealed'",
            params![session, now],
        )?;
        let number: i64 = c.query_row(
            "SELECT COALESCE(MAX(number), 0) + 1 FROM questions WHERE session_id = ?1",
            [session],
            |row| row.get(0),
        )?;
        c.execute(
            "INSERT INTO questions (session_id, number, spec, state, asked_ms)
             VALUES (?1, ?2, ?3, 'open', ?4)",
            params![session, number, spec, now],
        )?;
        Ok(QuestionRow {
            id: c.last_insert_rowid(),
            number,
            spec: spec.into(),
            state: QuestionState::Open,
        })
    }

    /// A question's new state, with the time it changed.
    pub fn set_question_state(
        c: &Connection,
        question: i64,
        state: QuestionState,
    ) -> rusqlite::Result<()> {
        let column = match state {
            QuestionState::Open => "asked_ms",
            QuestionState::Locked => "locked_ms",
            QuestionState::Revealed => "revealed_ms",
        };
        c.execute(
            &format!(
                "UPDATE questions SET state = ?2, {column} = COALESCE({column}, ?3) WHERE id = ?1"
            ),
            params![question, state.name(), now_ms()],
        )
        .map(drop)
    }

    /// The session's latest question.
    pub fn latest_question(c: &Connection, session: i64) -> rusqlite::Result<Option<QuestionRow>> {
        c.query_row(
            "SELECT id, number, spec, state FROM questions WHERE session_id = ?1
             ORDER BY number DESC LIMIT 1",
            [session],
            |row| {
                let state: String = row.get(3)?;
                Ok(QuestionRow {
                    id: row.get(0)?,
                    number: row.get(1)?,
                    spec: row.get(2)?,
                    state: QuestionState::from_name(&state).unwrap_or(QuestionState::Revealed),
                })
            },
        )
        .optional()
    }

    /// Stores a student's answer (replacing the last one, keeping it in the history); returns how
    /// often the student has answered this question.
    pub fn save_answer(
        c: &Connection,
        question: i64,
        student: i64,
        given: &str,
        right: bool,
    ) -> rusqlite::Result<i64> {
        let now = now_ms();
        c.execute(
            "INSERT INTO answer_changes (question_id, student_id, given, is_right, answered_ms)
             VALUES (?1, ?2, ?3, ?4, ?5)",
            params![question, student, given, right, now],
        )?;
        c.execute(
            "INSERT INTO answers (question_id, student_id, given, is_right, changes, answered_ms)
             VALUES (?1, ?2, ?3, ?4, 1, ?5)
             ON CONFLICT (question_id, student_id) DO UPDATE SET
                 given = excluded.given, is_right = excluded.is_right,
                 changes = changes + 1, answered_ms = excluded.answered_ms",
            params![question, student, given, right, now],
        )?;
        c.query_row(
            "SELECT changes FROM answers WHERE question_id = ?1 AND student_id = ?2",
            params![question, student],
            |row| row.get(0),
        )
    }

    /// Every current answer to a question.
    pub fn answers(c: &Connection, question: i64) -> rusqlite::Result<Vec<AnswerRow>> {
        let mut statement = c.prepare(
            "SELECT student_id, given, is_right, changes FROM answers WHERE question_id = ?1",
        )?;
        statement
            .query_map([question], |row| {
                Ok(AnswerRow {
                    student_id: row.get(0)?,
                    given: row.get(1)?,
                    right: row.get(2)?,
                    changes: row.get(3)?,
                })
            })?
            .collect()
    }

    /// One row per student per question of a session: the last answer, its time, right or not.
    pub fn export(c: &Connection, session: i64) -> rusqlite::Result<Vec<ExportRow>> {
        let mut statement = c.prepare(
            "SELECT q.number, q.spec, s.number, COALESCE(s.nickname, ''), a.given,
                    strftime('%Y-%m-%dT%H:%M:%fZ', a.answered_ms / 1000.0, 'unixepoch'),
                    a.changes, a.is_right
             FROM answers a JOIN questions q ON q.id = a.question_id
                            JOIN students s ON s.id = a.student_id
             WHERE q.session_id = ?1 ORDER BY q.number, s.number",
        )?;
        statement
            .query_map([session], |row| {
                let spec: String = row.get(1)?;
                let prompt = serde_json::from_str::<super::super::protocol::QuestionSpec>(&spec)
                    .map(|spec| spec.prompt)
                    .unwrap_or_default();
                Ok(ExportRow {
                    question: row.get(0)?,
                    prompt,
                    student: row.get(2)?,
                    nickname: row.get(3)?,
                    given: row.get(4)?,
                    answered_at: row.get(5)?,
                    changes: row.get(6)?,
                    right: row.get(7)?,
                })
            })?
            .collect()
    }
}
