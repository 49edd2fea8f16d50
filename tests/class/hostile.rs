//! Hostile input to the class server: malformed and oversized messages, unknown codes, a flood from
//! one connection, a thousand connections at once. Each gets a clear error or is closed, and the
//! server keeps serving everyone else. Traffic goes to 127.0.0.1 only, and every loop is bounded.

use raylab::class::protocol::ToClient;
use serde_json::json;

use super::client::{Client, Server, TempDir, seed000_triangle};

fn error_text(message: ToClient) -> String {
    match message {
        ToClient::Error { message } => message,
        other => panic!("expected an error, got {other:?}"),
    }
}

/// A student of the class still joins, answers and is acknowledged.
fn still_serves(server: &Server, question: i64) {
    let (mut student, welcome) = Client::student(&server.address, &server.code, None, None);
    assert!(matches!(welcome, ToClient::Welcome { .. }), "{welcome:?}");
    student.send(
        json!({"type": "answer", "question": question, "outcome": "hit", "values": ["0.3", "0.3"]}),
    );
    let ack = student.recv_until("an ack", |m| {
        matches!(m, ToClient::Ack { .. } | ToClient::Error { .. })
    });
    assert!(matches!(ack, ToClient::Ack { .. }), "{ack:?}");
}

#[test]
fn bad_messages_get_errors_and_the_server_keeps_serving() {
    let folder = TempDir::new("class-hostile");
    let server = Server::start(&folder.join("class.sqlite3"), &[]);
    let (mut teacher, _) = Client::teacher(&server.address, &server.code, &server.key);
    teacher.send(json!({"type": "ask", "question": seed000_triangle()}));
    let ToClient::Question { question } =
        teacher.recv_until("the question", |m| matches!(m, ToClient::Question { .. }))
    else {
        unreachable!()
    };

    // Not JSON, an unknown type, a missing field: an error each, and the connection stays usable.
    let mut client = Client::connect(&server.address);
    for bad in [
        "not json",
        r#"{"type":"vote"}"#,
        r#"{"type":"join"}"#,
        "[1,2,3]",
        "{}",
    ] {
        client.send_text(bad);
        assert!(
            error_text(client.recv()).starts_with("unreadable message"),
            "{bad}"
        );
    }
    // Anything before joining is refused with what to do.
    client.send(json!({"type": "answer", "question": question.id, "outcome": "hit"}));
    assert!(error_text(client.recv()).contains("join first"));
    // Unknown and malformed codes say so, and a right code still works on the same connection.
    client.send(json!({"type": "join", "code": "ZZZZZZ"}));
    assert!(error_text(client.recv()).contains("no class with code ZZZZZZ"));
    client.send(json!({"type": "join", "code": "<script>".repeat(100)}));
    assert!(error_text(client.recv()).contains("no class with code"));
    client.send(json!({"type": "join", "code": server.code, "nickname": "<b>bold</b>"}));
    assert!(error_text(client.recv()).contains("nickname"));
    client.send(json!({"type": "join", "code": server.code, "nickname": "Plain Name"}));
    assert!(matches!(client.recv(), ToClient::Welcome { .. }));
    // Answers that cannot be read or do not fit the question.
    for (bad, expected) in [
        (
            json!({"type": "answer", "question": question.id, "outcome": "inside"}),
            "not an outcome",
        ),
        (
            json!({"type": "answer", "question": question.id, "values": ["1e99999"]}),
            "exponent",
        ),
        (
            json!({"type": "answer", "question": question.id, "values": ["x"]}),
            "not a number",
        ),
        (
            json!({"type": "answer", "question": question.id, "values": ["1","2","3","4"]}),
            "at most 3",
        ),
        (
            json!({"type": "answer", "question": question.id + 1, "outcome": "hit"}),
            "over",
        ),
        (
            json!({"type": "answer", "question": question.id}),
            "needs an outcome",
        ),
    ] {
        client.send(bad);
        let message =
            error_text(client.recv_until("an error", |m| matches!(m, ToClient::Error { .. })));
        assert!(
            message.contains(expected),
            "{message} (expected '{expected}')"
        );
    }
    client.send_text("\u{0}\u{1}binary-ish");
    assert!(error_text(client.recv()).starts_with("unreadable"));

    // An oversized message closes that connection only.
    let mut big = Client::connect(&server.address);
    big.send_text(&format!(
        r#"{{"type":"join","code":"{}"}}"#,
        "A".repeat(10_000)
    ));
    assert!(
        big.try_recv().is_err(),
        "the oversized message's connection is closed"
    );
    still_serves(&server, question.id);

    // A flood from one connection is slowed, then cut off; others are served meanwhile. First 40
    // messages at once (past the burst of 20, short of the 50 refusals that cut a connection off):
    // each gets its answer, the ones past the burst "slow down".
    let mut flood = Client::connect(&server.address);
    for _ in 0..40 {
        flood.send(json!({"type": "ping"}));
    }
    let replies: Vec<ToClient> = (0..40).map(|_| flood.recv()).collect();
    let slowed = replies
        .iter()
        .filter(|m| matches!(m, ToClient::Error { message } if message.contains("too many messages: slow down")))
        .count();
    assert!(
        slowed >= 10,
        "a flood is told to slow down ({slowed} of 40)"
    );
    // Then 100 more: the connection is cut off (its last messages may be lost with it).
    let mut cut = false;
    for _ in 0..100 {
        if flood.try_send(json!({"type": "ping"})).is_err() {
            cut = true;
            break;
        }
    }
    // The replies already sent may be read first; then the connection ends (not a read timeout).
    for _ in 0..200 {
        if cut {
            break;
        }
        if let Err(why) = flood.try_recv() {
            let waited = ["timed out", "temporarily unavailable", "WouldBlock"]
                .iter()
                .any(|t| why.contains(t));
            assert!(!waited, "the flooding connection was never cut off: {why}");
            cut = true;
        }
    }
    assert!(cut, "the flooding connection was never cut off");
    still_serves(&server, question.id);

    // A thousand connections at once: the server holds them and still serves a real student.
    let mut crowd = Vec::new();
    for _ in 0..1000 {
        match Client::try_connect(&server.address) {
            Ok(client) => crowd.push(client),
            Err(e) => panic!("connection {} of 1000 refused: {e}", crowd.len() + 1),
        }
    }
    still_serves(&server, question.id);
    // Half of them join at once as students; the teacher's count follows.
    for client in crowd.iter_mut().take(500) {
        client.send(json!({"type": "join", "code": server.code}));
    }
    for client in crowd.iter_mut().take(500) {
        assert!(matches!(client.recv(), ToClient::Welcome { .. }));
    }
    let tally = teacher.recv_until(
        "the crowd in the tally",
        |m| matches!(m, ToClient::Tally(t) if t.connected >= 500),
    );
    assert!(matches!(tally, ToClient::Tally(ref t) if t.joined >= 502));
    drop(crowd);
    still_serves(&server, question.id);
}
