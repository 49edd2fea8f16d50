//! A class under load, on loopback: the release `raylab class`, a teacher and 300 students, each a
//! WebSocket client on a thread of its own. All join, the teacher asks seed 000's triangle, and all
//! answer within a 5-second burst (send times drawn uniformly, seeded). Each answer's latency is the
//! time from its send to the first tally the teacher reads that holds it (each student's β is unique,
//! so its answer is known in the tally). Then 30 students reconnect with their tokens and must get
//! their answer back in the welcome, and once the server is killed with SIGKILL the database must hold
//! every acknowledged answer.
//!
//! `cargo bench --bench class` prints a table and writes it to `target/class-bench.json`: latency p50,
//! p99 and max; answers acknowledged, in the tally, back after a reconnect and stored (none lost, or it
//! fails); the server's CPU time and peak memory; the wall time. It stops by itself, and fails past
//! 60 seconds.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

#[path = "../tests/class/client.rs"]
mod client;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use client::{Client, PATIENCE, Server, seed000_triangle, token_of};
use rand::{Rng, SeedableRng};
use raylab::class::protocol::{Given, ToClient};
use serde_json::json;

/// Students in the class.
const STUDENTS: usize = 300;

/// The answers arrive within this long.
const BURST: Duration = Duration::from_secs(5);

/// Students that disconnect and come back with their token.
const RECONNECTS: usize = 30;

/// The whole benchmark fails past this.
const LIMIT: Duration = Duration::from_secs(60);

/// Student `i`'s β: unique, so its answer is found in the tally (0.100000, 0.100001, …).
fn beta_of(i: usize) -> String {
    format!("0.1{i:05}")
}

/// The student whose β this is.
fn student_of(beta: f64) -> Option<usize> {
    let i = ((beta - 0.1) * 1e6).round();
    (0.0..STUDENTS as f64)
        .contains(&i)
        .then_some(i as usize)
        .filter(|&i| (beta - (0.1 + i as f64 * 1e-6)).abs() < 1e-9)
}

/// What a student's thread tells the conductor.
enum Report {
    Joined,
    Ready,
    Acked {
        student: usize,
        sent: Instant,
        acked: Instant,
    },
    /// A student back with its token: whether its welcome held its answer.
    Back {
        student: usize,
        answer_kept: bool,
    },
}

/// What the conductor tells a student's thread.
enum Cue {
    /// Answer at this instant.
    AnswerAt(Instant),
    /// Disconnect and come back (true), or just leave (false).
    Reconnect(bool),
}

/// One student: joins, waits for the question, answers when cued, then comes back or leaves.
fn student(
    i: usize,
    address: String,
    code: String,
    cues: mpsc::Receiver<Cue>,
    out: mpsc::Sender<Report>,
) {
    let cue = || cues.recv_timeout(LIMIT).expect("a cue from the conductor");
    let (mut client, welcome) = Client::student(&address, &code, None, None);
    let token = token_of(&welcome);
    out.send(Report::Joined).unwrap();
    let ToClient::Question { question } =
        client.recv_until("the question", |m| matches!(m, ToClient::Question { .. }))
    else {
        unreachable!()
    };
    out.send(Report::Ready).unwrap();
    let Cue::AnswerAt(at) = cue() else {
        panic!("student {i}: cued out of order")
    };
    std::thread::sleep(at.saturating_duration_since(Instant::now()));
    let given = Given {
        outcome: Some("hit".into()),
        values: vec![Some(beta_of(i)), Some("0.3".into())],
    };
    let sent = Instant::now();
    client.send(json!({"type": "answer", "question": question.id, "outcome": given.outcome, "values": given.values}));
    let ack = client.recv_until("the ack", |m| {
        matches!(m, ToClient::Ack { .. } | ToClient::Error { .. })
    });
    assert!(
        matches!(ack, ToClient::Ack { changes: 1, .. }),
        "student {i}: {ack:?}"
    );
    out.send(Report::Acked {
        student: i,
        sent,
        acked: Instant::now(),
    })
    .unwrap();
    let Cue::Reconnect(back) = cue() else {
        panic!("student {i}: cued out of order")
    };
    client.close();
    if back {
        let (client, welcome) = Client::student(&address, &code, Some(&token), None);
        let answer_kept =
            matches!(welcome, ToClient::Welcome { answer: Some(ref a), .. } if *a == given);
        out.send(Report::Back {
            student: i,
            answer_kept,
        })
        .unwrap();
        client.close();
    }
}

/// Percentile `p` (0–1) of sorted values.
fn percentile(sorted: &[f64], p: f64) -> f64 {
    let rank = ((p * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[rank - 1]
}

/// The server's CPU time so far (user + system), in seconds, from /proc.
fn cpu_seconds(pid: u32, ticks_per_second: f64) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).expect("/proc/PID/stat");
    // Fields after the command name (which is in parentheses and may hold spaces): state is field 3,
    // utime and stime fields 14 and 15.
    let rest = &stat[stat.rfind(')').unwrap() + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = fields[11].parse::<f64>().unwrap() + fields[12].parse::<f64>().unwrap();
    ticks / ticks_per_second
}

/// The server's peak resident memory (VmHWM), in MiB.
fn peak_mib(pid: u32) -> f64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).expect("/proc/PID/status");
    let line = status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .expect("VmHWM");
    let kib: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    kib / 1024.0
}

fn clock_ticks() -> f64 {
    let out = Command::new("getconf")
        .arg("CLK_TCK")
        .output()
        .expect("getconf runs");
    String::from_utf8_lossy(&out.stdout).trim().parse().unwrap()
}

/// Fails the benchmark when it runs past its limit.
fn check_time(start: Instant, stage: &str) {
    assert!(
        start.elapsed() < LIMIT,
        "the benchmark ran past {LIMIT:?} (at: {stage})"
    );
}

fn main() {
    // `cargo bench` passes `--bench`; a filter that names something else skips this.
    let filter: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    if !filter.is_empty() && !filter.iter().any(|f| "class".contains(f.as_str())) {
        return;
    }
    let wall = Instant::now();
    let target: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .unwrap()
        .to_path_buf();
    // The database on the target's disk (not a RAM disk), so commits cost what they cost;
    // RAYLAB_CLASS_BENCH_DIR puts it elsewhere (/dev/shm: the same run without the disk's fsync).
    let base = std::env::var_os("RAYLAB_CLASS_BENCH_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_TARGET_TMPDIR")));
    let folder = base.join(format!("class-bench-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).unwrap();
    let db = folder.join("class.sqlite3");
    let mut server = Server::start(&db, &[]);
    let pid = server.pid;

    // A hard stop: past the limit (a stuck thread, say), kill the server and fail.
    std::thread::spawn(move || {
        std::thread::sleep(LIMIT + Duration::from_secs(5));
        let _ = Command::new("kill")
            .args(["-KILL", &pid.to_string()])
            .status();
        eprintln!("class bench: ran past {LIMIT:?}; the server is killed");
        std::process::exit(101);
    });

    let ticks = clock_ticks();
    let (mut teacher, _) = Client::teacher(&server.address, &server.code, &server.key);

    // Students join, each on its own thread.
    let (out, reports) = mpsc::channel();
    let mut cues = Vec::new();
    let mut threads = Vec::new();
    for i in 0..STUDENTS {
        let (cue, cued) = mpsc::channel();
        cues.push(cue);
        let (address, code, out) = (server.address.clone(), server.code.clone(), out.clone());
        threads.push(
            std::thread::Builder::new()
                .name(format!("student-{i}"))
                .stack_size(256 * 1024)
                .spawn(move || student(i, address, code, cued, out))
                .unwrap(),
        );
    }
    drop(out);
    let wait_for = |what: &str, n: usize, want: &dyn Fn(&Report) -> bool| {
        let mut got = Vec::new();
        while got.len() < n {
            let report = reports
                .recv_timeout(PATIENCE)
                .unwrap_or_else(|e| panic!("waiting for {what} ({} of {n}): {e}", got.len()));
            assert!(
                want(&report),
                "a report out of order while waiting for {what}"
            );
            got.push(report);
            check_time(wall, what);
        }
        got
    };
    wait_for("joins", STUDENTS, &|r| matches!(r, Report::Joined));
    let joined_in = wall.elapsed();

    // The teacher asks; every student has the question.
    teacher.send(json!({"type": "ask", "question": seed000_triangle()}));
    teacher.recv_until("the asked question", |m| {
        matches!(m, ToClient::Question { .. })
    });
    wait_for("the question on every phone", STUDENTS, &|r| {
        matches!(r, Report::Ready)
    });

    // The burst: each student answers at a time drawn uniformly over 5 s.
    let mut rng = rand_pcg::Pcg64::seed_from_u64(300);
    let cpu_before = cpu_seconds(pid, ticks);
    let burst_start = Instant::now() + Duration::from_millis(100);
    for cue in &cues {
        let offset = Duration::from_secs_f64(rng.random_range(0.0..BURST.as_secs_f64()));
        cue.send(Cue::AnswerAt(burst_start + offset)).unwrap();
    }
    // The teacher reads tallies until every answer is in one: when each was first seen.
    let mut seen: HashMap<usize, Instant> = HashMap::new();
    let mut tallies = 0;
    let mut last_answered = 0;
    while seen.len() < STUDENTS {
        check_time(wall, "the tallies");
        let message = teacher
            .try_recv()
            .unwrap_or_else(|e| panic!("the teacher, with {} answers seen: {e}", seen.len()));
        let now = Instant::now();
        if let ToClient::Tally(tally) = message {
            tallies += 1;
            last_answered = tally.answered;
            for prediction in &tally.predictions {
                if let Some(Some(beta)) = prediction.values.first()
                    && let Some(i) = student_of(*beta)
                {
                    seen.entry(i).or_insert(now);
                }
            }
        }
    }
    let cpu_burst = cpu_seconds(pid, ticks) - cpu_before;
    let acks = wait_for("the acks", STUDENTS, &|r| matches!(r, Report::Acked { .. }));
    let mut latencies = Vec::new();
    let mut ack_latencies = Vec::new();
    for report in &acks {
        let Report::Acked {
            student,
            sent,
            acked,
        } = report
        else {
            unreachable!()
        };
        latencies.push(seen[student].saturating_duration_since(*sent).as_secs_f64() * 1e3);
        ack_latencies.push(acked.duration_since(*sent).as_secs_f64() * 1e3);
    }
    latencies.sort_by(f64::total_cmp);
    ack_latencies.sort_by(f64::total_cmp);

    // 30 students disconnect and come back with their tokens; the rest leave.
    for (i, cue) in cues.iter().enumerate() {
        cue.send(Cue::Reconnect(i % (STUDENTS / RECONNECTS) == 0))
            .unwrap();
    }
    let backs = wait_for("the reconnects", RECONNECTS, &|r| {
        matches!(r, Report::Back { .. })
    });
    let kept = backs
        .iter()
        .filter(|r| {
            matches!(
                r,
                Report::Back {
                    answer_kept: true,
                    ..
                }
            )
        })
        .count();
    for report in &backs {
        if let Report::Back {
            student,
            answer_kept: false,
        } = report
        {
            eprintln!("student {student} came back without its answer");
        }
    }
    for thread in threads {
        thread.join().expect("a student's thread");
    }
    check_time(wall, "the students' end");
    let cpu_total = cpu_seconds(pid, ticks);
    let peak = peak_mib(pid);

    // SIGKILL, then count what the database holds.
    server.kill();
    let stored: i64 = rusqlite::Connection::open(&db)
        .unwrap()
        .query_row("SELECT COUNT(*) FROM answers", [], |row| row.get(0))
        .unwrap();
    let wall_s = wall.elapsed().as_secs_f64();
    let _ = std::fs::remove_dir_all(&folder);

    let acked = acks.len();
    let lost = acked.saturating_sub(seen.len())
        + acked.saturating_sub(stored as usize)
        + (RECONNECTS - kept);
    let p = |sorted: &[f64], q: f64| percentile(sorted, q);
    println!(
        "raylab class under load: {STUDENTS} students on loopback, answers spread over {} s (release build)",
        BURST.as_secs()
    );
    println!(
        "  {:<40} {:>9} {:>9} {:>9}",
        "latency (ms)", "p50", "p99", "max"
    );
    for (what, sample) in [
        ("answer sent → in the teacher's tally", &latencies),
        ("answer sent → ack (committed)", &ack_latencies),
    ] {
        println!(
            "  {what:<40} {:>9.1} {:>9.1} {:>9.1}",
            p(sample, 0.5),
            p(sample, 0.99),
            p(sample, 1.0)
        );
    }
    println!(
        "  answers: {acked} acknowledged, {} in the teacher's tally (its count {last_answered}), \
         {stored} stored after SIGKILL, {kept} of {RECONNECTS} back after a reconnect; lost {lost}",
        seen.len()
    );
    println!("  tallies the teacher read: {tallies}");
    println!(
        "  server CPU: {cpu_burst:.2} s during the burst, {cpu_total:.2} s in all (user + system)"
    );
    println!("  server peak memory (VmHWM): {peak:.1} MiB");
    println!(
        "  wall time: {wall_s:.1} s ({:.1} s to join {STUDENTS})",
        joined_in.as_secs_f64()
    );
    let report = json!({
        "students": STUDENTS,
        "burst_s": BURST.as_secs_f64(),
        "latency_tally_ms": {"p50": p(&latencies, 0.5), "p99": p(&latencies, 0.99), "max": p(&latencies, 1.0)},
        "latency_ack_ms": {"p50": p(&ack_latencies, 0.5), "p99": p(&ack_latencies, 0.99), "max": p(&ack_latencies, 1.0)},
        "answers_acknowledged": acked,
        "answers_in_tally": seen.len(),
        "tally_answered": last_answered,
        "answers_stored_after_sigkill": stored,
        "reconnected": RECONNECTS,
        "answers_back_after_reconnect": kept,
        "answers_lost": lost,
        "tallies_read": tallies,
        "server_cpu_burst_s": cpu_burst,
        "server_cpu_total_s": cpu_total,
        "server_peak_mib": peak,
        "wall_s": wall_s,
    });
    let json_path = target.join("class-bench.json");
    std::fs::write(&json_path, serde_json::to_string_pretty(&report).unwrap()).unwrap();
    println!("  written to {}", json_path.display());
    assert_eq!(lost, 0, "answers were lost");
    assert!(wall.elapsed() < LIMIT, "the benchmark ran past {LIMIT:?}");
}
