//! Connections are answered each on a thread of its own ([`answer_connections`]): idle
//! and slow clients (a browser's preconnected sockets, stalled uploads) delay no other
//! client's request, the number of open connections is capped (503 beyond), slow clients
//! are dropped at the time limits, and a panic in one answer frees its place.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use planner_serve::server::answer_connections;
use planner_serve::ServeOptions;

use crate::common::{get, post, read_answer, repo, scratch, start};

/// A fresh directory holding maps/paper/map10.map as map10.map.
fn served(name: &str) -> PathBuf {
    let dir = scratch(name);
    std::fs::copy(repo().join("maps/paper/map10.map"), dir.join("map10.map")).unwrap();
    dir
}

/// What the slow clients send: nothing (an idle or preconnected socket), part of a
/// request head, or a whole head that declares a body never sent.
#[derive(Clone, Copy, Debug)]
enum Slow {
    Idle,
    PartHead,
    NoBody,
}

/// Opens a connection to `addr` that sends what `slow` says and then nothing more.
fn slow_client(addr: SocketAddr, slow: Slow) -> TcpStream {
    let mut stream = TcpStream::connect(addr).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(30)))
        .unwrap();
    let sent: &[u8] = match slow {
        Slow::Idle => b"",
        Slow::PartHead => b"GET /api/maps HTTP/1.1\r\nHo",
        Slow::NoBody => {
            b"POST /api/plan HTTP/1.1\r\nContent-Type: application/json\r\nContent-Length: 100\r\n\r\n"
        }
    };
    stream.write_all(sent).unwrap();
    stream
}

/// `get` timed.
fn timed_get(addr: SocketAddr, url: &str) -> ((u16, String), Duration) {
    let started = Instant::now();
    let answer = get(addr, url);
    (answer, started.elapsed())
}

/// With the fixed pool of four threads, four idle connections held every thread for the
/// 10 s read timeout and a fifth request waited that long (8: 20 s; 64 bodiless POSTs:
/// reset). Now 90 idle and slow connections, more than a browser opens, delay no request.
#[test]
fn idle_and_slow_connections_do_not_delay_other_requests() {
    let dir = served("idle");
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    let mut slow = Vec::new();
    for i in 0..90 {
        let kind = [Slow::Idle, Slow::PartHead, Slow::NoBody][i % 3];
        slow.push(slow_client(addr, kind));
    }
    // Let the server accept them all and their threads block in their reads.
    std::thread::sleep(Duration::from_millis(200));
    // A generous bound for a loaded 2-core machine: the answers take milliseconds, and
    // took 10 s and more before.
    let bound = Duration::from_secs(2);
    for _ in 0..5 {
        let ((status, body), elapsed) = timed_get(addr, "/api/maps");
        assert_eq!(status, 200, "{body}");
        assert!(body.contains("map10.map"), "{body}");
        assert!(elapsed < bound, "GET /api/maps took {elapsed:?}");
    }
    let started = Instant::now();
    let (status, answer) = post(
        addr,
        "/api/plan",
        r#"{"map":"map10.map","start":[0,0],"goal":[11,11],"planner":"astar"}"#,
    );
    let elapsed = started.elapsed();
    assert_eq!(status, 200, "{answer}");
    assert!(elapsed < bound, "POST /api/plan took {elapsed:?}");
    // The slow connections are still open, waiting on their own threads.
    for stream in &slow {
        stream.set_nonblocking(true).unwrap();
        let mut byte = [0u8; 1];
        let read = (&*stream).read(&mut byte);
        assert!(
            matches!(&read, Err(e) if e.kind() == std::io::ErrorKind::WouldBlock),
            "a slow connection was answered or closed early: {read:?}"
        );
    }
    drop(slow);
    stop();
    let _ = std::fs::remove_dir_all(&dir);
}

/// At most `max_connections` connections are open: one more is answered 503 at once.
/// Slow clients are dropped at the time limits: a connection that sent nothing is closed
/// without an answer, one that sent part of a head or no promised body gets 408; their
/// places are then free again.
#[test]
fn connections_beyond_the_cap_are_refused_and_slow_clients_dropped() {
    let dir = served("cap");
    let options = ServeOptions {
        max_connections: 4,
        head_timeout: Duration::from_secs(1),
        body_timeout: Duration::from_secs(1),
        ..ServeOptions::new(&dir, 0)
    };
    let (addr, stop) = start(&options);
    let opened = Instant::now();
    let mut slow: Vec<(Slow, TcpStream)> = [Slow::Idle, Slow::Idle, Slow::PartHead, Slow::NoBody]
        .into_iter()
        .map(|kind| (kind, slow_client(addr, kind)))
        .collect();
    // The four places are taken (connections are accepted in order): a fifth connection
    // is refused at once, with a reason.
    let ((status, body), elapsed) = timed_get(addr, "/api/maps");
    assert_eq!(status, 503, "{body}");
    assert!(body.contains("too many open connections"), "{body}");
    assert!(
        elapsed < Duration::from_secs(2),
        "the refusal took {elapsed:?}"
    );
    for (kind, stream) in &mut slow {
        let (status, body) = read_answer(stream);
        match kind {
            Slow::Idle => assert_eq!((status, body.as_str()), (0, ""), "{kind:?}"),
            Slow::PartHead => {
                assert_eq!(status, 408, "{kind:?}: {body}");
                assert!(body.contains("request head did not arrive"), "{body}");
            }
            Slow::NoBody => {
                assert_eq!(status, 408, "{kind:?}: {body}");
                assert!(body.contains("request body did not arrive"), "{body}");
            }
        }
    }
    // Dropped at their limits (1 s for the head, 1 s more for the body), not at the
    // client's 30 s.
    let dropped = opened.elapsed();
    assert!(
        dropped < Duration::from_secs(10),
        "dropped after {dropped:?}"
    );
    drop(slow);
    // Their places are free again (a thread ends just after its client saw the close).
    let started = Instant::now();
    loop {
        let (status, body) = get(addr, "/api/maps");
        if status == 200 {
            break;
        }
        assert_eq!(status, 503, "{body}");
        assert!(
            started.elapsed() < Duration::from_secs(10),
            "the places of the dropped connections were not freed"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    stop();
    let _ = std::fs::remove_dir_all(&dir);
}

/// A connection whose answer panics is closed and its place freed: with room for one
/// connection, the next one is answered.
#[test]
fn a_panicking_answer_closes_its_connection_and_frees_its_place() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap();
    let stop = Arc::new(AtomicBool::new(false));
    let server = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || {
            answer_connections(&listener, 1, &stop, |mut stream: TcpStream| {
                let mut byte = [0u8; 1];
                let _ = stream.read_exact(&mut byte);
                assert_ne!(byte[0], b'p', "a bug in one request's handling");
                let _ = stream.write_all(b"answered");
            });
        })
    };
    let ask = |byte: u8| {
        let mut stream = TcpStream::connect(addr).unwrap();
        stream
            .set_read_timeout(Some(Duration::from_secs(10)))
            .unwrap();
        // A refused connection may be closed before this is written.
        let _ = stream.write_all(&[byte]);
        let mut answer = Vec::new();
        let _ = stream.read_to_end(&mut answer);
        answer
    };
    // Asks until the one place is free (its last thread ends just after its client saw
    // the close): 503 busy until then, for 10 s at most.
    let ask_when_free = |byte: u8| {
        let started = Instant::now();
        loop {
            let answer = ask(byte);
            if !answer.starts_with(b"HTTP/1.1 503") || started.elapsed() > Duration::from_secs(10) {
                return answer;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    };
    for _ in 0..3 {
        assert_eq!(ask_when_free(b'p'), b"");
        assert_eq!(ask_when_free(b'x'), b"answered");
    }
    stop.store(true, Ordering::SeqCst);
    let _ = TcpStream::connect(addr);
    server.join().unwrap();
}
