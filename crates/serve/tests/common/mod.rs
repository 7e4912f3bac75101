//! Helpers shared by the server's test files: start a server, send it a request over real
//! HTTP, read the answer.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::time::Duration;

use planner_serve::{ServeOptions, Server};

/// A fresh directory under the system's temp dir.
pub fn scratch(name: &str) -> PathBuf {
    // Under the target directory (not the system's temporary one, which runs of the tests
    // filled with thousands of directories), one per call; a later run replaces them.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("planner-serve-{name}-{call}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The repository's root.
pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Starts a server with `options` on a thread; its address and its stop function.
pub fn start(options: &ServeOptions) -> (SocketAddr, impl Fn()) {
    let server = Server::bind(options).unwrap();
    let addr = server.addr().unwrap();
    let stop = server.stopper();
    std::thread::spawn(move || server.run());
    (addr, stop)
}

/// Sends `head` (request line and headers, without the blank line) and `body`; the status
/// and the body of the answer.
pub fn send(addr: SocketAddr, head: &str, body: &[u8]) -> (u16, String) {
    let mut stream = TcpStream::connect(addr).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(60)))
        .unwrap();
    let mut request = format!("{head}\r\nHost: {addr}\r\nConnection: close\r\n");
    if !head.contains("Content-Length") && !body.is_empty() {
        request.push_str(&format!("Content-Length: {}\r\n", body.len()));
    }
    request.push_str("\r\n");
    stream.write_all(request.as_bytes()).unwrap();
    let _ = stream.write_all(body);
    read_answer(&mut stream)
}

/// The status and the body of the answer read from `stream` to its end.
pub fn read_answer(stream: &mut TcpStream) -> (u16, String) {
    let mut answer = Vec::new();
    let _ = stream.read_to_end(&mut answer);
    let text = String::from_utf8_lossy(&answer).into_owned();
    let status = text
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let body = text
        .split_once("\r\n\r\n")
        .map_or(String::new(), |(_, b)| b.to_string());
    (status, body)
}

/// `GET url`: the status and the body of the answer.
pub fn get(addr: SocketAddr, url: &str) -> (u16, String) {
    send(addr, &format!("GET {url} HTTP/1.1"), b"")
}

/// `POST url` with the JSON `body`: the status and the body of the answer.
pub fn post(addr: SocketAddr, url: &str, body: &str) -> (u16, String) {
    send(
        addr,
        &format!("POST {url} HTTP/1.1\r\nContent-Type: application/json"),
        body.as_bytes(),
    )
}

/// `body` parsed as JSON (the test fails naming it if it is not).
pub fn json(body: &str) -> serde_json::Value {
    serde_json::from_str(body).unwrap_or_else(|e| panic!("{e}: {body}"))
}
