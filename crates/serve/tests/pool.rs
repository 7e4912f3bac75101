//! The server's worker pool ([`planner_serve::server::answer_in_pool`]) outlives a panic
//! in one connection's answer.

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use planner_serve::server::answer_in_pool;

/// A connection whose answer panics is closed, and the pool's only thread answers the next
/// one.
#[test]
fn a_panicking_answer_closes_its_connection_and_keeps_the_thread() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap();
    let stop = Arc::new(AtomicBool::new(false));
    let pool = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || {
            answer_in_pool(&listener, 1, &stop, |mut stream: TcpStream| {
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
        stream.write_all(&[byte]).unwrap();
        let mut answer = Vec::new();
        let _ = stream.read_to_end(&mut answer);
        answer
    };
    for _ in 0..3 {
        assert_eq!(ask(b'p'), b"");
        assert_eq!(ask(b'x'), b"answered");
    }
    stop.store(true, Ordering::SeqCst);
    let _ = TcpStream::connect(addr);
    pool.join().unwrap();
}
