//! The live class's messages: what a student's page and the teacher's app send the server, and what it
//! sends back, as JSON text frames over one WebSocket (`/ws`). Each message is an object whose `type`
//! names it; unknown types and unknown fields are refused with an [`ToClient::Error`] naming the
//! problem, so a mistyped or forged message never does something else.
//!
//! A connection first says who it is: [`ToServer::Join`] (a student, with the token it was given last
//! time to come back as itself) or [`ToServer::Teach`] (the teacher, with the session's key). Everything
//! else before that is refused.

use serde::{Deserialize, Serialize};

/// The largest message the server reads, in bytes: an answer is about 100, a question about 600.
pub const MAX_MESSAGE_BYTES: usize = 4096;

/// The longest nickname, in characters.
pub const MAX_NICKNAME_CHARS: usize = 24;

/// What a client sends. Variants without data are written with braces (`Lock {}`) so that an extra
/// field is refused for them too (serde ignores extra fields of a unit variant).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ToServer {
    /// A student joins the session with this code; with the token from an earlier [`ToClient::Welcome`]
    /// it comes back as the same student, with its answers.
    Join {
        /// The session's join code (case and spaces do not matter).
        code: String,
        /// The token from the last welcome, kept by the page.
        #[serde(default)]
        token: Option<String>,
        /// A nickname, or none to stay anonymous.
        #[serde(default)]
        nickname: Option<String>,
    },
    /// The teacher takes the session's controls.
    Teach {
        /// The session's join code.
        code: String,
        /// The teacher's key, made when the session started and never sent to students.
        key: String,
    },
    /// A student's answer to the open question; a later one replaces it until the teacher locks.
    Answer {
        /// The question's id, as [`QuestionView::id`] gave it.
        question: i64,
        /// The predicted outcome, one of [`QuestionView::outcomes`] (`hit`, `outside BC` …), or none.
        #[serde(default)]
        outcome: Option<String>,
        /// The predicted values, in [`QuestionView::unknowns`] order, each a decimal or a fraction
        /// (`0.25`, `1/4`), or null where the student gave none.
        #[serde(default)]
        values: Vec<Option<String>>,
    },
    /// Teacher: ask every student this question (the previous one is closed).
    Ask {
        /// The problem and its wording.
        question: QuestionSpec,
    },
    /// Teacher: no more answers to the open question.
    Lock {},
    /// Teacher: show the true answer on every device.
    Reveal {},
    /// Teacher: include (or leave out) the students' nicknames in the tally. Off by default, so a
    /// projector never shows a name unless the teacher asks.
    ShowNames {
        /// Whether names are sent.
        show: bool,
    },
    /// Teacher: end the session; its code stops working.
    End {},
    /// Keeps an idle connection alive; answered with [`ToClient::Pong`].
    Ping {},
}

/// A question as the teacher's app asks it: which solver, the exact inputs, and the wording.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuestionSpec {
    /// `segments`, `triangle` or `parallelogram`.
    pub kind: String,
    /// What the students read (`Where does the ray meet the triangle?`).
    pub prompt: String,
    /// The inputs in `raylab solve`'s order (A1, A2, B1, B2; A, B, C, L, D; c, e1, e2, o, d), each
    /// coordinate a decimal or fraction as text, read exactly.
    pub inputs: Vec<Vec<String>>,
}

/// Who a connection is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// Answers questions.
    Student,
    /// Asks, locks and reveals.
    Teacher,
}

/// Where a question stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum QuestionState {
    /// Students may answer and change their answers.
    Open,
    /// No more answers; the answer is not shown yet.
    Locked,
    /// The true answer is shown everywhere.
    Revealed,
}

impl QuestionState {
    /// The word stored in the database.
    pub fn name(self) -> &'static str {
        match self {
            QuestionState::Open => "open",
            QuestionState::Locked => "locked",
            QuestionState::Revealed => "revealed",
        }
    }

    /// The state a stored word names.
    pub fn from_name(name: &str) -> Option<QuestionState> {
        [
            QuestionState::Open,
            QuestionState::Locked,
            QuestionState::Revealed,
        ]
        .into_iter()
        .find(|state| state.name() == name)
    }
}

/// A question as a device shows it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct QuestionView {
    /// The question's id (answers name it).
    pub id: i64,
    /// Its number in the session, from 1.
    pub number: i64,
    /// `segments`, `triangle` or `parallelogram`.
    pub kind: String,
    /// The question as the teacher asked it (its exact inputs): a teacher's app that joins later or
    /// restarts draws the class's cloud on the same scene.
    pub spec: QuestionSpec,
    /// What is asked.
    pub prompt: String,
    /// The unknowns to predict, as the lecture writes them (`β`, `γ`, `t`; `t`, `s`).
    pub unknowns: Vec<String>,
    /// The outcomes to pick from: `hit`, `outside BC`, …, `parallel`, `degenerate`.
    pub outcomes: Vec<String>,
    /// The inputs by name with their exact values as text (`A = (1, 0, 0)`), for the student to read.
    pub inputs: Vec<String>,
    /// The figure to draw and drag on, in its own plane (see [`Figure`]).
    pub figure: Figure,
    /// Open, locked or revealed.
    pub state: QuestionState,
}

/// The figure a phone draws for a question, flat: for segments the four endpoints A1, A2, B1, B2 as
/// given; for a triangle A, B, C and for a parallelogram its corner c and c + e1, c + e1 + e2, c + e2,
/// laid into their own plane with lengths and angles kept (A at the origin, B on the x axis), so that
/// dragging P(β, γ) there is dragging it on the real triangle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Figure {
    /// The named points, in the order above.
    pub points: Vec<(String, [f64; 2])>,
}

/// A student's current answer, as the server holds it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Given {
    /// The outcome picked, if any.
    pub outcome: Option<String>,
    /// The values as typed or dragged, in [`QuestionView::unknowns`] order.
    pub values: Vec<Option<String>>,
}

/// The true answer, sent at the reveal.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrueAnswer {
    /// `hit`, `outside BC` …
    pub outcome: String,
    /// The exact values as fractions, in [`QuestionView::unknowns`] order (empty without a single
    /// solution).
    pub values: Vec<String>,
    /// The same as numbers, for drawing.
    pub numbers: Vec<f64>,
    /// `hit; β = 1/4, γ = 1/2, t = 3`.
    pub text: String,
}

/// What the server sends.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ToClient {
    /// The connection is in: who it is, and where the session stands.
    Welcome {
        /// Student or teacher.
        role: Role,
        /// The session's join code.
        code: String,
        /// A student's token: the page keeps it to come back as the same student.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        token: Option<String>,
        /// A student's nickname, or none when anonymous.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        nickname: Option<String>,
        /// The current question, if one was asked.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        question: Option<Box<QuestionView>>,
        /// This student's answer to it, if any.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        answer: Option<Given>,
        /// The true answer, once revealed.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reveal: Option<Box<Reveal>>,
    },
    /// A new question, or the current one's state changed (locked).
    Question {
        /// The question.
        question: Box<QuestionView>,
    },
    /// The answer is stored: it survives the server's restart.
    Ack {
        /// The question answered.
        question: i64,
        /// How often this student has answered it (1 for the first answer).
        changes: i64,
    },
    /// The true answer, and whether this student's was right.
    Revealed {
        /// The question.
        question: i64,
        /// The reveal.
        reveal: Box<Reveal>,
    },
    /// Teacher only: the answers so far.
    Tally(Tally),
    /// Something was refused; the connection stays open unless it says otherwise.
    Error {
        /// What went wrong and what to do, one line.
        message: String,
    },
    /// The teacher ended the session.
    Ended,
    /// The answer to [`ToServer::Ping`].
    Pong,
}

/// The reveal as one student sees it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Reveal {
    /// The true answer.
    pub answer: TrueAnswer,
    /// Whether this student's answer was right (none for the teacher or a student who gave none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub right: Option<bool>,
    /// How many answered, and how many of them were right.
    pub answered: usize,
    /// How many were right.
    pub right_count: usize,
}

/// The teacher's view of the answers to the current question.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Tally {
    /// The question, if one was asked.
    pub question: Option<i64>,
    /// Students who ever joined the session.
    pub joined: usize,
    /// Students connected now.
    pub connected: usize,
    /// Students who answered the question.
    pub answered: usize,
    /// Each outcome offered with how many picked it, in the question's order.
    pub outcomes: Vec<(String, usize)>,
    /// Every answer, anonymous unless the teacher asked for names.
    pub predictions: Vec<Prediction>,
    /// How many of the answers are right (known to the teacher before the reveal).
    pub right: usize,
}

/// One student's answer, for the cloud.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Prediction {
    /// The student's number in the session (1, 2, …): the same student keeps it, and it says nothing
    /// about who they are.
    pub student: i64,
    /// The nickname, only when the teacher asked for names.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The outcome picked, if any.
    pub outcome: Option<String>,
    /// The values as numbers (none where not given or unreadable).
    pub values: Vec<Option<f64>>,
    /// Whether the answer is right.
    pub right: bool,
}

/// Reads a client's message, or says in one line why it cannot be read.
pub fn read_message(text: &str) -> Result<ToServer, String> {
    if text.len() > MAX_MESSAGE_BYTES {
        return Err(format!(
            "message too long ({} bytes; at most {MAX_MESSAGE_BYTES})",
            text.len()
        ));
    }
    serde_json::from_str(text).map_err(|e| format!("unreadable message: {e}"))
}

/// A nickname as stored: trimmed, none when empty. Refuses one that is too long or holds control
/// characters, markup or anything but letters, digits, spaces and `-_.'`.
pub fn clean_nickname(nickname: Option<&str>) -> Result<Option<String>, String> {
    let Some(name) = nickname.map(str::trim).filter(|name| !name.is_empty()) else {
        return Ok(None);
    };
    if name.chars().count() > MAX_NICKNAME_CHARS {
        return Err(format!(
            "a nickname has at most {MAX_NICKNAME_CHARS} characters"
        ));
    }
    let plain = |c: char| c.is_alphanumeric() || c == ' ' || "-_.'".contains(c);
    if !name.chars().all(plain) {
        return Err("a nickname is letters, digits, spaces and - _ . ' only".into());
    }
    Ok(Some(name.split_whitespace().collect::<Vec<_>>().join(" ")))
}

/// A join code as typed, normalised: upper case, spaces and dashes dropped.
pub fn normalise_code(code: &str) -> String {
    code.chars()
        .filter(|c| !c.is_whitespace() && *c != '-')
        .map(|c| c.to_ascii_uppercase())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_read_by_type_and_refuse_unknown_fields() {
        let join = read_message(r#"{"type":"join","code":"abc"}"#).unwrap();
        assert_eq!(
            join,
            ToServer::Join {
                code: "abc".into(),
                token: None,
                nickname: None
            }
        );
        assert!(read_message(r#"{"type":"lock","student":3}"#).is_err());
        assert!(read_message(r#"{"type":"vote"}"#).is_err());
        assert!(read_message("not json").is_err());
        let long = format!(r#"{{"type":"ping","x":"{}"}}"#, "a".repeat(5000));
        assert!(read_message(&long).unwrap_err().contains("too long"));
    }

    #[test]
    fn nicknames_are_plain_short_text() {
        assert_eq!(
            clean_nickname(Some("  Ada  L ")).unwrap(),
            Some("Ada L".into())
        );
        assert_eq!(clean_nickname(Some("   ")).unwrap(), None);
        assert!(clean_nickname(Some("<script>")).is_err());
        assert!(clean_nickname(Some(&"x".repeat(25))).is_err());
        assert!(clean_nickname(Some("a\u{7}b")).is_err());
        assert_eq!(normalise_code(" k7p-3qx "), "K7P3QX");
    }
}
