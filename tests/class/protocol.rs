//! A whole class over the real protocol: a teacher and students join, a question is asked, answered
//! and changed, a student reconnects, a forged teacher command is refused, the server is killed with
//! SIGKILL mid-question and restarted with every acknowledged answer, then lock, reveal and export.

use raylab::class::protocol::{QuestionState, Role, ToClient};
use serde_json::json;

use super::client::{Client, Server, TempDir, raylab, seed000_triangle, token_of};

/// The answers the students give: (nickname, outcome, β, γ). Student 0 later changes its answer.
const ANSWERS: [(&str, &str, &str, &str); 5] = [
    ("Ada", "outside BC", "0.6", "0.6"),
    ("", "hit", "0.34", "0.31"),
    ("Grace", "hit", "1/3", "1/3"),
    ("", "behind", "0.3", "0.3"),
    ("Alan", "hit", "0.5", "0.1"),
];

fn tally_of(message: &ToClient) -> Option<&raylab::class::protocol::Tally> {
    match message {
        ToClient::Tally(tally) => Some(tally),
        _ => None,
    }
}

#[test]
fn a_class_survives_reconnects_forgery_and_a_killed_server() {
    let folder = TempDir::new("class-protocol");
    let db = folder.join("class.sqlite3");
    let mut server = Server::start(&db, &[]);
    let address = server.address.clone();
    let code = server.code.clone();

    let (mut teacher, welcome) = Client::teacher(&address, &code, &server.key);
    assert!(matches!(
        welcome,
        ToClient::Welcome {
            role: Role::Teacher,
            question: None,
            ..
        }
    ));

    // Students join: each gets its own token; a lower-case code with spaces still finds the class.
    let typed = format!(" {} ", code.to_lowercase());
    let mut students = Vec::new();
    for (nickname, ..) in ANSWERS {
        let nickname = (!nickname.is_empty()).then_some(nickname);
        let (client, welcome) = Client::student(&address, &typed, None, nickname);
        students.push((client, token_of(&welcome)));
    }
    let tokens: Vec<String> = students.iter().map(|(_, token)| token.clone()).collect();
    assert!(
        tokens
            .iter()
            .enumerate()
            .all(|(i, t)| !tokens[..i].contains(t)),
        "tokens differ"
    );

    // The teacher asks; every student gets the question.
    teacher.send(json!({"type": "ask", "question": seed000_triangle()}));
    let asked = teacher.recv_until("the asked question", |m| {
        matches!(m, ToClient::Question { .. })
    });
    let ToClient::Question { question } = asked else {
        unreachable!()
    };
    assert_eq!(question.unknowns, ["β", "γ", "t"]);
    for (student, _) in &mut students {
        let got = student.recv_until("the question", |m| matches!(m, ToClient::Question { .. }));
        assert!(
            matches!(got, ToClient::Question { question: ref q } if q.id == question.id && q.state == QuestionState::Open)
        );
    }

    // Everyone answers and is acknowledged; student 0 changes its mind.
    for ((student, _), (_, outcome, beta, gamma)) in students.iter_mut().zip(ANSWERS) {
        student.send(json!({"type": "answer", "question": question.id, "outcome": outcome, "values": [beta, gamma, null]}));
        let ack = student.recv_until("the ack", |m| matches!(m, ToClient::Ack { .. }));
        assert_eq!(
            ack,
            ToClient::Ack {
                question: question.id,
                changes: 1
            }
        );
    }
    students[0].0.send(json!({"type": "answer", "question": question.id, "outcome": "hit", "values": ["0.3", "0.35", "1/3"]}));
    let ack = students[0].0.recv_until("the changed answer's ack", |m| {
        matches!(m, ToClient::Ack { .. })
    });
    assert_eq!(
        ack,
        ToClient::Ack {
            question: question.id,
            changes: 2
        }
    );

    // The teacher's tally counts them all, with no names (the teacher did not ask for them).
    let tally = teacher.recv_until("a tally of 5 answers", |m| {
        tally_of(m).is_some_and(|t| {
            t.answered == 5
                && t.predictions
                    .iter()
                    .any(|p| p.values.get(2) == Some(&Some(1.0 / 3.0)))
        })
    });
    let tally = tally_of(&tally).unwrap();
    assert_eq!(tally.joined, 5);
    let count = |o: &str| {
        tally
            .outcomes
            .iter()
            .find(|(name, _)| name == o)
            .map(|(_, n)| *n)
    };
    assert_eq!(count("hit"), Some(4));
    assert_eq!(count("behind"), Some(1));
    assert_eq!(count("outside BC"), Some(0));
    assert!(
        tally.predictions.iter().all(|p| p.name.is_none()),
        "no names on the projector"
    );
    // Right: hit with β, γ within 0.05 of 1/3 (students 0 after its change, 1 and 2).
    assert_eq!(tally.right, 3);
    // Names only when the teacher asks for them; anonymous students stay anonymous.
    teacher.send(json!({"type": "show_names", "show": true}));
    let named = teacher.recv_until("a tally with names", |m| {
        tally_of(m).is_some_and(|t| t.predictions.iter().any(|p| p.name.is_some()))
    });
    let names: Vec<Option<String>> = tally_of(&named)
        .unwrap()
        .predictions
        .iter()
        .map(|p| p.name.clone())
        .collect();
    assert_eq!(
        names,
        [
            Some("Ada".to_string()),
            None,
            Some("Grace".to_string()),
            None,
            Some("Alan".to_string())
        ]
    );
    teacher.send(json!({"type": "show_names", "show": false}));
    teacher.recv_until("a tally without names", |m| {
        tally_of(m).is_some_and(|t| t.predictions.iter().all(|p| p.name.is_none()))
    });

    // A student cannot drive the class, or answer for another.
    students[1].0.send(json!({"type": "reveal"}));
    let refused = students[1]
        .0
        .recv_until("the refusal", |m| matches!(m, ToClient::Error { .. }));
    assert!(
        matches!(refused, ToClient::Error { ref message } if message.contains("only the teacher")),
        "{refused:?}"
    );
    students[1]
        .0
        .send(json!({"type": "answer", "question": question.id, "student": 3, "outcome": "hit"}));
    let refused = students[1]
        .0
        .recv_until("the refusal", |m| matches!(m, ToClient::Error { .. }));
    assert!(
        matches!(refused, ToClient::Error { ref message } if message.contains("unknown field")),
        "{refused:?}"
    );
    // A wrong key does not make a teacher.
    let (_, wrong) = Client::teacher(&address, &code, "0123456789abcdef0123456789abcdef");
    assert!(
        matches!(wrong, ToClient::Error { ref message } if message.contains("wrong teacher key"))
    );

    // Student 3 drops off and comes back with its token: the same student, its answer kept.
    let (old, token) = students.remove(3);
    old.close();
    let (back, welcome) = Client::student(&address, &code, Some(&token), None);
    match &welcome {
        ToClient::Welcome {
            token: Some(t),
            answer: Some(answer),
            question: Some(q),
            ..
        } => {
            assert_eq!(t, &token);
            assert_eq!(q.id, question.id);
            assert_eq!(answer.outcome.as_deref(), Some("behind"));
        }
        other => panic!("expected the student's welcome back, got {other:?}"),
    }
    students.insert(3, (back, token));

    // SIGKILL mid-question, then a restart on the same database: the class resumes, every
    // acknowledged answer is there.
    server.kill();
    drop(students);
    drop(teacher);
    let server = Server::start(&db, &[]);
    assert_eq!(
        server.code, code,
        "the restarted server resumes the open class"
    );
    let address = server.address.clone();
    let (mut teacher, welcome) = Client::teacher(&address, &code, &server.key);
    assert!(
        matches!(welcome, ToClient::Welcome { question: Some(ref q), .. } if q.id == question.id)
    );
    let tally = teacher.recv_until("the tally after the restart", |m| tally_of(m).is_some());
    let tally = tally_of(&tally).unwrap();
    assert_eq!(
        tally.answered, 5,
        "every acknowledged answer survived SIGKILL"
    );
    assert_eq!(tally.right, 3);

    // Students come back after the restart with their tokens.
    let mut students: Vec<Client> = Vec::new();
    for token in &tokens {
        let (client, welcome) = Client::student(&address, &code, Some(token), None);
        assert!(
            matches!(
                welcome,
                ToClient::Welcome {
                    answer: Some(_),
                    ..
                }
            ),
            "{welcome:?}"
        );
        students.push(client);
    }

    // Lock: answers stop; then reveal: each student learns whether it was right.
    teacher.send(json!({"type": "lock"}));
    for student in &mut students {
        let locked = student.recv_until("the lock", |m| matches!(m, ToClient::Question { .. }));
        assert!(
            matches!(locked, ToClient::Question { ref question } if question.state == QuestionState::Locked)
        );
    }
    students[4].send(json!({"type": "answer", "question": question.id, "outcome": "hit", "values": ["1/3", "1/3"]}));
    let late = students[4].recv_until("the refusal", |m| matches!(m, ToClient::Error { .. }));
    assert!(matches!(late, ToClient::Error { ref message } if message.contains("locked")));
    teacher.send(json!({"type": "reveal"}));
    let expected_right = [true, true, true, false, false];
    for (student, right) in students.iter_mut().zip(expected_right) {
        let revealed = student.recv_until("the reveal", |m| matches!(m, ToClient::Revealed { .. }));
        let ToClient::Revealed { reveal, .. } = revealed else {
            unreachable!()
        };
        assert_eq!(reveal.answer.values, ["1/3", "1/3", "1/3"]);
        assert_eq!(reveal.right, Some(right));
        assert_eq!((reveal.answered, reveal.right_count), (5, 3));
    }

    // Export: one row per student, the changed answer as last given, right or not.
    let export = std::process::Command::new(raylab())
        .args(["class", "export", &code, "--csv", "--db"])
        .arg(&db)
        .output()
        .expect("raylab class export runs");
    assert!(
        export.status.success(),
        "{}",
        String::from_utf8_lossy(&export.stderr)
    );
    let csv = String::from_utf8(export.stdout).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "question,prompt,student,nickname,outcome,values,answered_at,changes,right"
    );
    assert_eq!(lines.len(), 6, "{csv}");
    assert!(
        lines[1].starts_with("1,Where does the ray meet the triangle?,1,Ada,hit,0.3; 0.35; 1/3,"),
        "{csv}"
    );
    assert!(lines[1].ends_with(",2,yes"), "{csv}");
    assert!(
        lines[4].contains(",behind,") && lines[4].ends_with(",1,no"),
        "{csv}"
    );
    // An unknown session is a clear error.
    let unknown = std::process::Command::new(raylab())
        .args(["class", "export", "NOSUCH", "--csv", "--db"])
        .arg(&db)
        .output()
        .unwrap();
    assert_eq!(unknown.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&unknown.stderr).contains("no class session with code NOSUCH"));
}

/// A plain HTTP/1.1 GET: the status code, the headers (lower-case names) and the body.
fn http_get(address: &str, path: &str, gzip: bool) -> (u16, String, Vec<u8>) {
    use std::io::{Read, Write};
    let mut stream = std::net::TcpStream::connect(address).unwrap();
    stream
        .set_read_timeout(Some(super::client::PATIENCE))
        .unwrap();
    let encoding = if gzip {
        "Accept-Encoding: gzip, deflate\r\n"
    } else {
        ""
    };
    write!(
        stream,
        "GET {path} HTTP/1.1\r\nHost: {address}\r\n{encoding}Connection: close\r\n\r\n"
    )
    .unwrap();
    let mut response = Vec::new();
    stream.read_to_end(&mut response).unwrap();
    let split = response
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("a header");
    let head = String::from_utf8_lossy(&response[..split]).to_lowercase();
    let status = head.split_whitespace().nth(1).unwrap().parse().unwrap();
    (status, head, response[split + 4..].to_vec())
}

#[test]
fn the_phone_page_is_small_and_gzipped_and_the_web_build_is_served_without_escaping_its_folder() {
    let folder = TempDir::new("class-pages");
    let site = folder.join("site");
    std::fs::create_dir_all(&site).unwrap();
    std::fs::write(
        site.join("index.html"),
        "<!doctype html><title>raylab</title>".repeat(50),
    )
    .unwrap();
    std::fs::write(folder.join("secret.txt"), "not for the web").unwrap();
    let server = Server::start(
        &folder.join("class.sqlite3"),
        &["--site", site.to_str().unwrap()],
    );

    // The page a student needs, as a phone gets it: gzipped, well under 1.5 MB.
    let (status, head, body) = http_get(&server.address, "/?code=ABC", true);
    assert_eq!(status, 200);
    assert!(head.contains("content-encoding: gzip"), "{head}");
    assert!(
        body.len() < 1_500_000 / 100,
        "the page is {} bytes gzipped",
        body.len()
    );
    let mut page = String::new();
    std::io::Read::read_to_string(&mut flate2::read::GzDecoder::new(&body[..]), &mut page).unwrap();
    assert!(page.contains("Join the class"));
    let (_, head, plain) = http_get(&server.address, "/", false);
    assert!(!head.contains("content-encoding"), "{head}");
    assert_eq!(plain, page.as_bytes());

    // The whole app's web build at /app/, and nothing outside its folder.
    let (status, _, body) = http_get(&server.address, "/app/", false);
    assert_eq!(status, 200);
    assert!(String::from_utf8_lossy(&body).starts_with("<!doctype html>"));
    for path in [
        "/app/..%2Fsecret.txt",
        "/app/../secret.txt",
        "/app/.%2e/secret.txt",
        "/app/%2E%2E",
        "/app/nothing.js",
    ] {
        let (status, _, body) = http_get(&server.address, path, false);
        assert!(status == 404 || status == 400, "{path}: {status}");
        assert!(
            !String::from_utf8_lossy(&body).contains("not for the web"),
            "{path}"
        );
    }
    // Without a web build, /app/ says how to make one.
    drop(server);
    let bare = Server::start(
        &folder.join("other.sqlite3"),
        &["--site", folder.join("none").to_str().unwrap()],
    );
    let (status, _, body) = http_get(&bare.address, "/app/", false);
    assert_eq!(status, 404);
    assert!(String::from_utf8_lossy(&body).contains("build-web.sh"));
}
