//! The HTTP server of `gridplan serve`: the embedded page and a small JSON API over the
//! served directory.
//!
//! | Request | Answer |
//! |---|---|
//! | `GET /`, `/app.js`, `/style.css`, `/favicon.svg` | the page (embedded in the binary) |
//! | `GET /api/planners` | the registry: name, summary, declared parameters |
//! | `GET /api/maps` | map files (not `.csv` weight files) and results directories under the served directory |
//! | `GET /api/map?path=P` | map `P`: size, cells (one character each, row-major: `0` free, `1` blocked, `2` a ROS map's unknown cell, blocked too), its own problems or its `.scen`'s, and its `version` ([`map_version`]) |
//! | `POST /api/plan` | plans one query (JSON body, [`PlanRequest`]); `plan --json`'s object and the expanded cells; 409 when the request's `map_version` is not the map's as read now (the file changed on disk since the page loaded it) |
//! | `POST /api/cancel?run=ID` | cancels the plan request with that `run` id |
//! | `GET /api/results?path=P` | results directory `P`: runs.json's table, the kept paths, where the maps it names lie (`maps`; `null` and a `map_notes` sentence when not located, [`crate::located`]) |
//!
//! HTTP/1.1 on plain TCP, one request per connection (answered with `Connection: close`),
//! heads parsed by httparse. `HEAD` answers a `GET` path's head without its body; another
//! method on a known path is 405 with an `Allow` header. `/api/map` and `/api/results`
//! without `path` are 400; `graded` takes `true` or `false` (`1` or `0`), anything else is
//! 400. Error messages name files by their path under the served directory, never by the
//! server's absolute path; a directory where a file is asked for is 400.
//!
//! # Connections, threads and time limits
//!
//! Each connection is answered on a thread of its own ([`answer_connections`]), so a
//! client that sends nothing or sends slowly (a browser's preconnected socket, a stalled
//! upload, another tab's request) holds only its own thread and never delays another
//! client's answer (a fixed pool of four threads let four idle connections stall every
//! other request for the 10 s of their read timeout). The limits that keep the threads and
//! their memory bounded:
//!
//! - at most [`ServeOptions::max_connections`] connections (default 128) are open at
//!   once; a connection beyond them is answered 503 at once and closed, without a thread;
//! - the request head must arrive within [`ServeOptions::head_timeout`] (10 s) of
//!   connecting: a connection that has sent nothing by then (a browser's unused
//!   preconnection) is closed without an answer, one that sent part of a head gets 408;
//! - the body must arrive within [`ServeOptions::body_timeout`] (30 s) of the head (408);
//! - a client that takes none of the answer for [`WRITE_TIMEOUT`] (30 s) is dropped;
//! - after the answer, what the client still sends is read and dropped for at most one
//!   second and 1 MiB (a lingering close, so that a refused body does not reset the
//!   connection before the client has read why);
//! - memory per connection is bounded: a head over 16 KiB is refused (431), and a body
//!   over [`ServeOptions::max_body_bytes`] is refused with 413 by its `Content-Length`,
//!   before a byte of it is read (a body without a length, chunked, is refused with 411);
//!   a body's buffer grows with the bytes that arrive, not with the length declared.
//!
//! Planning is limited apart from connections: at most [`ServeOptions::max_running`]
//! plans run at once (503 beyond), each within [`crate::query::Caps`]: ten million
//! expansions, 2 GiB and one minute of wall-clock time by default
//! ([`crate::query::DEFAULT_MAX_TIME`]), after which the plan answers `budget_exhausted`.
//!
//! # Safety
//!
//! Paths go through [`crate::safe::Root`] (403/404 before anything is read); a `Host`
//! that is a DNS name other than `localhost`, or an `Origin` of another site, is refused
//! with 403 (DNS rebinding and cross-site requests from pages in the user's browser).
//!
//! # Cancelling
//!
//! A cancelled plan answers at once (409); its search stops at
//! the planner's next budget check (the run's [`planner_api::Budget::cancel`] flag, read
//! every [`planner_api::BudgetClock::TIME_CHECK_INTERVAL`] expansions), so its worker
//! thread ends and frees its place, its result dropped. A plan whose client has gone (its
//! connection closed or reset while the search runs: a closed tab, a reloaded page, an
//! interrupted `curl`) is cancelled the same way, checked every 20 ms, so that an abandoned
//! search does not hold one of the places until its budget runs out; as nginx does (its
//! status 499), a client that closes its sending side after the request counts as gone.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::io::{Read as _, Write as _};
use std::net::{IpAddr, Shutdown, SocketAddr, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::time::{Duration, Instant};

use planner_api::{CancelFlag, CancelPool, Cell};
use serde::Deserialize;

use crate::located::{Extent, Recorded};
use crate::query::{self, Caps, Query};
use crate::safe::{Refusal, Root};

const INDEX_HTML: &str = include_str!("../assets/index.html");
const APP_JS: &str = include_str!("../assets/app.js");
const STYLE_CSS: &str = include_str!("../assets/style.css");
/// The page's icon (a browser asks for one on every load; without it, a 404 in the console).
const FAVICON_SVG: &str = "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 4 4\"><rect width=\"4\" height=\"4\" fill=\"#fff\"/><rect x=\"1\" width=\"1\" height=\"3\" fill=\"#2d2d2d\"/><rect y=\"3\" width=\"4\" height=\"1\" fill=\"#e6194b\"/></svg>";

/// The map file extensions listed and read (what planner-maps reads).
pub const MAP_EXTENSIONS: &[&str] = &["map", "txt", "csv", "yaml", "png", "pgm"];

/// How to serve.
#[derive(Debug, Clone)]
pub struct ServeOptions {
    /// The served directory.
    pub dir: PathBuf,
    /// The address to bind (default 127.0.0.1).
    pub host: IpAddr,
    /// The port (0: any free port).
    pub port: u16,
    /// The largest request body accepted, in bytes (default 8 MiB).
    pub max_body_bytes: u64,
    /// Limits of every planning run.
    pub caps: Caps,
    /// Plans running at once, at most (default 2).
    pub max_running: usize,
    /// Connections open at once, at most (default 128), each answered on its own thread;
    /// one beyond them is answered 503 and closed.
    pub max_connections: usize,
    /// How long a connection may take to send its request head (default
    /// [`HEAD_TIMEOUT`]).
    pub head_timeout: Duration,
    /// How long a request body may take to arrive after its head (default
    /// [`BODY_TIMEOUT`]).
    pub body_timeout: Duration,
}

impl ServeOptions {
    /// Serving `dir` on 127.0.0.1:`port` with the default limits.
    pub fn new(dir: &Path, port: u16) -> ServeOptions {
        ServeOptions {
            dir: dir.to_path_buf(),
            host: IpAddr::from([127, 0, 0, 1]),
            port,
            max_body_bytes: 8 << 20,
            caps: Caps::default(),
            max_running: 2,
            max_connections: 128,
            head_timeout: HEAD_TIMEOUT,
            body_timeout: BODY_TIMEOUT,
        }
    }
}

/// Why the server could not start.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The served directory.
    #[error("{}: {source}", dir.display())]
    Dir {
        /// The directory given.
        dir: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Binding the address.
    #[error("cannot listen on {addr}: {message}")]
    Bind {
        /// The address.
        addr: SocketAddr,
        /// The system's message.
        message: String,
    },
    /// The bound socket reports no address.
    #[error("the server has no IP address")]
    NoAddress,
}

/// A bound server, not yet answering.
pub struct Server {
    listener: TcpListener,
    state: Arc<State>,
    max_connections: usize,
    stop: Arc<AtomicBool>,
}

struct State {
    root: Root,
    max_body_bytes: u64,
    caps: Caps,
    max_running: usize,
    head_timeout: Duration,
    body_timeout: Duration,
    running: AtomicUsize,
    cancels: Mutex<HashMap<String, CancelFlag>>,
    /// Cancel flags no running plan holds, for reuse (a [`CancelFlag`] is never freed):
    /// at most [`ServeOptions::max_running`] are ever made.
    flags: CancelPool,
}

impl Server {
    /// Binds the address of `options` and checks the directory.
    pub fn bind(options: &ServeOptions) -> Result<Server, ServeError> {
        let root = Root::new(&options.dir).map_err(|source| ServeError::Dir {
            dir: options.dir.clone(),
            source,
        })?;
        let addr = SocketAddr::new(options.host, options.port);
        let listener = TcpListener::bind(addr).map_err(|e| ServeError::Bind {
            addr,
            message: e.to_string(),
        })?;
        Ok(Server {
            listener,
            state: Arc::new(State {
                root,
                max_body_bytes: options.max_body_bytes,
                caps: options.caps,
                max_running: options.max_running.max(1),
                head_timeout: options.head_timeout,
                body_timeout: options.body_timeout,
                running: AtomicUsize::new(0),
                cancels: Mutex::new(HashMap::new()),
                flags: CancelPool::new(),
            }),
            max_connections: options.max_connections.max(1),
            stop: Arc::new(AtomicBool::new(false)),
        })
    }

    /// The address it listens on (with the port chosen when 0 was asked for).
    pub fn addr(&self) -> Option<SocketAddr> {
        self.listener.local_addr().ok()
    }

    /// Answers connections until [`Server::stopper`]'s handle is called (forever
    /// otherwise): each connection on a thread of its own, one request per connection, at
    /// most [`ServeOptions::max_connections`] at once (see [`answer_connections`]).
    pub fn run(self) {
        let state = self.state;
        answer_connections(
            &self.listener,
            self.max_connections,
            &self.stop,
            move |stream| connection(&state, stream),
        );
    }

    /// A handle that stops [`Server::run`]: it returns at once, and the requests being
    /// answered finish on their own threads (within the limits of the module's docs).
    pub fn stopper(&self) -> impl Fn() + Send + 'static {
        let stop = Arc::clone(&self.stop);
        let addr = self.addr();
        move || {
            stop.store(true, Ordering::SeqCst);
            // Wake the accept loop.
            if let Some(addr) = addr {
                let _ = TcpStream::connect_timeout(&addr, Duration::from_secs(1));
            }
        }
    }
}

/// Runs `answer` on each connection of `listener`, each on a thread of its own, until
/// `stop` is set (and the next connection wakes the loop); then returns without waiting
/// for the connections being answered. [`Server::run`] is this loop with the page's
/// answers.
///
/// At most `max_connections` are answered at once: a connection beyond them gets a 503
/// (written without blocking, no thread) and is closed, so that a flood of connections
/// costs neither threads nor memory. One connection's `answer` never waits for
/// another's: a client that sends nothing holds its own thread only (which `answer`
/// bounds with its timeouts). A panic in `answer` ends its thread and closes its
/// connection; its place is freed, so the server never fills up with dead connections.
pub fn answer_connections(
    listener: &TcpListener,
    max_connections: usize,
    stop: &AtomicBool,
    answer: impl Fn(TcpStream) + Send + Sync + 'static,
) {
    /// One open connection's place, freed when its thread ends (a panic too).
    struct Place(Arc<AtomicUsize>);
    impl Drop for Place {
        fn drop(&mut self) {
            self.0.fetch_sub(1, Ordering::SeqCst);
        }
    }
    let answer = Arc::new(answer);
    let open = Arc::new(AtomicUsize::new(0));
    for stream in listener.incoming() {
        if stop.load(Ordering::SeqCst) {
            break;
        }
        let stream = match stream {
            Ok(stream) => stream,
            Err(_) => {
                // Out of file descriptors (or a connection aborted before it was
                // accepted): wait a little rather than spin on the error.
                std::thread::sleep(Duration::from_millis(10));
                continue;
            }
        };
        // Only this loop adds places, so the count cannot grow between the check and
        // the add.
        if open.load(Ordering::SeqCst) >= max_connections.max(1) {
            refuse_busy(stream);
            continue;
        }
        open.fetch_add(1, Ordering::SeqCst);
        let place = Place(Arc::clone(&open));
        let answer = Arc::clone(&answer);
        // A thread that cannot be made drops the closure: the connection closes and its
        // place is freed.
        let _ = std::thread::Builder::new()
            .name("gridplan-serve".to_string())
            .spawn(move || {
                let _place = place;
                answer(stream);
            });
    }
}

/// Answers a connection beyond the limit 503 and closes it, without blocking: the answer
/// fits in a new socket's send buffer, and what the client has already sent is read
/// first, so that the close does not reset the connection before the answer is read.
fn refuse_busy(mut stream: TcpStream) {
    if stream.set_nonblocking(true).is_err() {
        return;
    }
    let busy = Answer::error(503, "busy: too many open connections; try again");
    let _ = stream.write_all(head(&busy).as_bytes());
    let _ = stream.write_all(&busy.body);
    let mut sink = [0u8; 4096];
    for _ in 0..16 {
        match stream.read(&mut sink) {
            Ok(n) if n > 0 => {}
            _ => break,
        }
    }
    let _ = stream.shutdown(Shutdown::Write);
}

/// One answer: status, content type, body.
struct Answer {
    status: u16,
    kind: &'static str,
    body: Vec<u8>,
    /// The methods a 405's `Allow` header lists.
    allow: Option<&'static str>,
}

impl Answer {
    fn json(status: u16, body: String) -> Answer {
        Answer {
            status,
            kind: "application/json",
            body: body.into_bytes(),
            allow: None,
        }
    }

    fn error(status: u16, message: &str) -> Answer {
        Answer::json(status, serde_json::json!({ "error": message }).to_string())
    }

    fn refusal(refusal: &Refusal) -> Answer {
        Answer::error(refusal.status(), &refusal.to_string())
    }

    fn asset(kind: &'static str, text: &'static str) -> Answer {
        Answer {
            status: 200,
            kind,
            body: text.as_bytes().to_vec(),
            allow: None,
        }
    }

    /// 405, with the methods `path` answers in `Allow`.
    fn not_allowed(allow: &'static str) -> Answer {
        Answer {
            allow: Some(allow),
            ..Answer::error(
                405,
                &format!("method not allowed; this path answers {allow}"),
            )
        }
    }
}

/// The absolute path of the served directory in `text` taken out: what a refusal or a
/// reader's error says names files by their path under the served directory, as the page
/// asked for them, never by where the server keeps them.
fn relative_message(root: &Root, text: &str) -> String {
    let mut prefix = root.path().display().to_string();
    prefix.push(std::path::MAIN_SEPARATOR);
    text.replace(&prefix, "")
}

/// The longest request head (request line and headers) read, in bytes.
const MAX_HEAD_BYTES: usize = 16 << 10;

/// How long a connection may take, from its opening, to send its request head, by
/// default ([`ServeOptions::head_timeout`]): one that has sent nothing by then (a
/// browser's unused preconnection) is closed without an answer, one that sent part of a
/// head is answered 408.
pub const HEAD_TIMEOUT: Duration = Duration::from_secs(10);

/// How long a request's body may take to arrive after its head (408 beyond), by default
/// ([`ServeOptions::body_timeout`]): 8 MiB, the default limit, at 280 KB/s.
pub const BODY_TIMEOUT: Duration = Duration::from_secs(30);

/// How long the server waits for a client to take any of its answer before dropping the
/// connection.
pub const WRITE_TIMEOUT: Duration = Duration::from_secs(30);

/// How long, and how many bytes, the lingering close after an answer reads.
const LINGER: (Duration, usize) = (Duration::from_secs(1), 1 << 20);

/// One connection: one request (head parsed by httparse, body read only up to the limit),
/// one answer, then the connection closes; each step within its time limit.
fn connection(state: &Arc<State>, mut stream: TcpStream) {
    let opened = Instant::now();
    let _ = stream.set_write_timeout(Some(WRITE_TIMEOUT));
    let mut head_only = false;
    let answer = match read_request(state, &mut stream, opened + state.head_timeout) {
        // HEAD is GET's answer without its body.
        Ok(Some((method, target, body))) if method == "HEAD" => {
            head_only = true;
            handle(state, "GET", &target, &body, &stream)
        }
        Ok(Some((method, target, body))) => handle(state, &method, &target, &body, &stream),
        Ok(None) => return,
        Err(answer) => answer,
    };
    let body: &[u8] = if head_only { &[] } else { &answer.body };
    if stream
        .write_all(head(&answer).as_bytes())
        .and_then(|()| stream.write_all(body))
        .and_then(|()| stream.flush())
        .is_err()
    {
        return;
    }
    // A lingering close: stop writing, then read (and drop) what the client still sends,
    // for at most a second and 1 MiB, so that closing with unread data (a refused body)
    // does not reset the connection before the client has read the answer.
    let _ = stream.shutdown(Shutdown::Write);
    let deadline = Instant::now() + LINGER.0;
    let mut sink = [0u8; 16 << 10];
    let mut drained = 0usize;
    while drained < LINGER.1 {
        match read_by(&mut stream, &mut sink, deadline) {
            Ok(0) | Err(_) => break,
            Ok(n) => drained += n,
        }
    }
}

/// The status line and headers of `answer`.
fn head(answer: &Answer) -> String {
    let reason = match answer.status {
        200 => "OK",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        409 => "Conflict",
        411 => "Length Required",
        413 => "Content Too Large",
        431 => "Request Header Fields Too Large",
        503 => "Service Unavailable",
        _ => "Error",
    };
    let allow = answer
        .allow
        .map_or_else(String::new, |allow| format!("Allow: {allow}\r\n"));
    format!(
        "HTTP/1.1 {} {reason}\r\n{allow}Content-Type: {}\r\nContent-Length: {}\r\nConnection: close\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nContent-Security-Policy: default-src 'self'; style-src 'self'; script-src 'self'\r\n\r\n",
        answer.status,
        answer.kind,
        answer.body.len()
    )
}

/// One read from `stream` into `buffer`, waiting until `deadline` at most (an error of
/// kind `TimedOut` or `WouldBlock` past it).
fn read_by(stream: &mut TcpStream, buffer: &mut [u8], deadline: Instant) -> std::io::Result<usize> {
    let left = deadline.saturating_duration_since(Instant::now());
    if left.is_zero() {
        return Err(std::io::ErrorKind::TimedOut.into());
    }
    stream.set_read_timeout(Some(left))?;
    stream.read(buffer)
}

/// Whether `error` is a read's time limit running out.
fn timed_out(error: &std::io::Error) -> bool {
    matches!(
        error.kind(),
        std::io::ErrorKind::TimedOut | std::io::ErrorKind::WouldBlock
    )
}

/// Reads one request, its head by `head_deadline` and its body within the body timeout
/// after: method, target and body, or the refusal to answer (400 malformed, 408 too
/// slow, 411 no length for a body, 413 body over the limit, 431 head too long); `None`
/// when the client sent nothing (closed, or idle until the deadline).
#[allow(clippy::type_complexity)]
fn read_request(
    state: &State,
    stream: &mut TcpStream,
    head_deadline: Instant,
) -> Result<Option<(String, String, Vec<u8>)>, Answer> {
    let mut buffer = Vec::with_capacity(4096);
    let mut chunk = [0u8; 16 << 10];
    let head_end = loop {
        if let Some(at) = find_head_end(&buffer) {
            if at > MAX_HEAD_BYTES {
                return Err(Answer::error(431, "request head too long"));
            }
            break at;
        }
        if buffer.len() > MAX_HEAD_BYTES {
            return Err(Answer::error(431, "request head too long"));
        }
        match read_by(stream, &mut chunk, head_deadline) {
            Ok(0) if buffer.is_empty() => return Ok(None),
            Ok(0) => return Err(Answer::error(400, "incomplete request")),
            Ok(n) => buffer.extend_from_slice(&chunk[..n]),
            Err(_) if buffer.is_empty() => return Ok(None),
            Err(e) if timed_out(&e) => {
                return Err(Answer::error(
                    408,
                    &format!(
                        "the request head did not arrive within {:?}",
                        state.head_timeout
                    ),
                ))
            }
            Err(e) => return Err(Answer::error(400, &format!("reading the request: {e}"))),
        }
    };
    let mut headers = [httparse::EMPTY_HEADER; 64];
    let mut request = httparse::Request::new(&mut headers);
    match request.parse(&buffer[..head_end]) {
        Ok(httparse::Status::Complete(_)) => {}
        Ok(httparse::Status::Partial) => return Err(Answer::error(400, "incomplete request head")),
        Err(httparse::Error::TooManyHeaders) => {
            return Err(Answer::error(431, "too many request headers"))
        }
        Err(e) => return Err(Answer::error(400, &format!("malformed request: {e}"))),
    }
    let method = request.method.unwrap_or("").to_string();
    let target = request.path.unwrap_or("").to_string();
    let header = |name: &str| {
        request
            .headers
            .iter()
            .find(|h| h.name.eq_ignore_ascii_case(name))
            .map(|h| String::from_utf8_lossy(h.value).trim().to_string())
    };
    check_origin(header("Host").as_deref(), header("Origin").as_deref())?;
    if header("Transfer-Encoding").is_some() {
        return Err(Answer::error(
            411,
            "request bodies need a Content-Length (no transfer encoding)",
        ));
    }
    let length = match header("Content-Length") {
        None => 0,
        Some(text) => text
            .parse::<u64>()
            .map_err(|_| Answer::error(400, &format!("Content-Length {text:?} is not a number")))?,
    };
    let cap = state.max_body_bytes;
    if length > cap {
        return Err(Answer::error(
            413,
            &format!("request body of {length} bytes, over the server's limit of {cap} bytes"),
        ));
    }
    let length = length as usize;
    let mut body = buffer.split_off(head_end);
    body.truncate(length);
    // Grown as the bytes arrive: a declared length costs no memory before its body comes.
    body.reserve((length - body.len()).min(1 << 20));
    let body_deadline = Instant::now() + state.body_timeout;
    while body.len() < length {
        let want = (length - body.len()).min(chunk.len());
        match read_by(stream, &mut chunk[..want], body_deadline) {
            Ok(0) => return Err(Answer::error(400, "the request body ended early")),
            Ok(n) => body.extend_from_slice(&chunk[..n]),
            Err(e) if timed_out(&e) => {
                return Err(Answer::error(
                    408,
                    &format!(
                        "the request body did not arrive within {:?}",
                        state.body_timeout
                    ),
                ))
            }
            Err(e) => {
                return Err(Answer::error(
                    400,
                    &format!("reading the request body: {e}"),
                ))
            }
        }
    }
    Ok(Some((method, target, body)))
}

/// Refuses (403) what a web page of another site could make the user's browser send: a
/// request whose `Host` is a name other than `localhost` (DNS rebinding: a site's name
/// made to point at this machine, so that its page reads the maps and results served
/// here), and one whose `Origin` is another site's (cross-site requests: a page starting
/// plans here). Browsers send both headers; a request without them (curl, the tests'
/// clients) is answered as before.
fn check_origin(host: Option<&str>, origin: Option<&str>) -> Result<(), Answer> {
    if let Some(host) = host {
        if !is_local_host(host) {
            return Err(Answer::error(
                403,
                &format!(
                    "Host {host:?} is not an address of this server (gridplan serve answers \
                     only to localhost and IP addresses); open the page by the address it printed"
                ),
            ));
        }
    }
    if let (Some(origin), Some(host)) = (origin, host) {
        let authority = origin
            .strip_prefix("http://")
            .or_else(|| origin.strip_prefix("https://"));
        if !authority.is_some_and(|a| a.eq_ignore_ascii_case(host)) {
            return Err(Answer::error(
                403,
                &format!("a request from {origin:?}, another site than this page's, is refused"),
            ));
        }
    }
    Ok(())
}

/// Whether a `Host` header names this machine without a DNS name that another site could
/// control: `localhost` or an IP address, with or without a port.
fn is_local_host(host: &str) -> bool {
    let name = match host.strip_prefix('[') {
        // `[v6]` or `[v6]:port`.
        Some(rest) => match rest.split_once(']') {
            Some((v6, port)) if port.is_empty() || port.starts_with(':') => {
                return v6.parse::<std::net::Ipv6Addr>().is_ok() && valid_port(port);
            }
            _ => return false,
        },
        None => host,
    };
    let (name, port) = match name.rsplit_once(':') {
        Some((name, port)) => (name, format!(":{port}")),
        None => (name, String::new()),
    };
    valid_port(&port)
        && (name.eq_ignore_ascii_case("localhost") || name.parse::<std::net::Ipv4Addr>().is_ok())
}

/// Whether `port` is empty or `:` and a port number.
fn valid_port(port: &str) -> bool {
    port.is_empty() || port[1..].parse::<u16>().is_ok()
}

/// The offset just past the blank line that ends a request head.
fn find_head_end(buffer: &[u8]) -> Option<usize> {
    buffer
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .map(|at| at + 4)
}

fn handle(state: &Arc<State>, method: &str, url: &str, body: &[u8], client: &TcpStream) -> Answer {
    let (path, query) = url.split_once('?').unwrap_or((url, ""));
    let params = parse_query(query);
    match (method, path) {
        ("GET", "/" | "/index.html") => Answer::asset("text/html; charset=utf-8", INDEX_HTML),
        ("GET", "/app.js") => Answer::asset("text/javascript; charset=utf-8", APP_JS),
        ("GET", "/style.css") => Answer::asset("text/css; charset=utf-8", STYLE_CSS),
        ("GET", "/favicon.svg") => Answer::asset("image/svg+xml", FAVICON_SVG),
        ("GET", "/api/planners") => planners(),
        ("GET", "/api/maps") => maps(state),
        ("GET", "/api/map") => {
            let Some(relative) = params.get("path") else {
                return missing_path("map");
            };
            let graded = match params.get("graded").map(String::as_str) {
                None | Some("false" | "0") => false,
                Some("true" | "1") => true,
                Some(other) => {
                    return Answer::error(
                        400,
                        &format!("graded={other:?}: `graded` takes true or false (or 1 or 0)"),
                    )
                }
            };
            let costs = MapCosts {
                weights: params.get("weights").filter(|w| !w.is_empty()).cloned(),
                graded,
            };
            map(state, relative, &costs)
        }
        ("GET", "/api/results") => match params.get("path") {
            Some(relative) => results(state, relative),
            None => missing_path("results directory"),
        },
        ("POST", "/api/plan") => plan(state, body, client),
        ("POST" | "GET", "/api/cancel") => {
            cancel(state, params.get("run").map_or("", String::as_str))
        }
        (_, "/api/plan") => Answer::not_allowed("POST"),
        (_, "/api/cancel") => Answer::not_allowed("GET, HEAD, POST"),
        (_, "/" | "/index.html" | "/app.js" | "/style.css" | "/favicon.svg" | "/api/planners")
        | (_, "/api/maps" | "/api/map" | "/api/results") => Answer::not_allowed("GET, HEAD"),
        _ => Answer::error(404, "not found"),
    }
}

/// 400: a request for a `what` without the `path` parameter that names it.
fn missing_path(what: &str) -> Answer {
    Answer::error(
        400,
        &format!("the `path` parameter is missing: ?path=P names the {what}, relative to the served directory"),
    )
}

/// `a=b&c=d`, percent-decoded (`+` is a space).
fn parse_query(query: &str) -> HashMap<String, String> {
    query
        .split('&')
        .filter(|p| !p.is_empty())
        .map(|pair| {
            let (k, v) = pair.split_once('=').unwrap_or((pair, ""));
            (percent_decode(k), percent_decode(v))
        })
        .collect()
}

/// Percent-decoding; invalid escapes stay as they are, invalid UTF-8 is replaced.
pub fn percent_decode(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match bytes[i] {
            b'%' if i + 2 < bytes.len() => match (hex(bytes[i + 1]), hex(bytes[i + 2])) {
                (Some(h), Some(l)) => {
                    out.push((h * 16 + l) as u8);
                    i += 3;
                    continue;
                }
                _ => out.push(b'%'),
            },
            b'+' => out.push(b' '),
            b => out.push(b),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

fn planners() -> Answer {
    let mut list = Vec::new();
    for entry in planner_registry::PLANNERS {
        if entry.task != planner_registry::Task::StartGoal {
            continue;
        }
        let params = match planner_registry::schema::declared(entry.name) {
            Ok(params) => params,
            Err(error) => return Answer::error(500, &error.to_string()),
        };
        let params: Vec<serde_json::Value> = params
            .into_iter()
            .map(|p| {
                serde_json::json!({
                    "key": p.key,
                    "kind": p.kind,
                    "default": p.default,
                    "allowed": p.allowed,
                    "doc": p.doc,
                })
            })
            .collect();
        list.push(serde_json::json!({
            "name": entry.name,
            "summary": entry.summary,
            "params": params,
        }));
    }
    Answer::json(200, serde_json::Value::Array(list).to_string())
}

/// The most directory entries [`maps`] looks at.
const MAX_LISTED: usize = 20_000;

fn maps(state: &State) -> Answer {
    let mut maps = Vec::new();
    let mut results = Vec::new();
    let mut seen = 0usize;
    let mut stack = vec![(state.root.path().to_path_buf(), 0u32)];
    while let Some((dir, depth)) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        let mut entries: Vec<_> = entries.filter_map(Result::ok).collect();
        entries.sort_by_key(|e| e.file_name());
        for entry in entries.into_iter().rev() {
            seen += 1;
            if seen > MAX_LISTED {
                break;
            }
            let name = entry.file_name().to_string_lossy().into_owned();
            if name.starts_with('.') || name == "target" || name == "node_modules" {
                continue;
            }
            let path = entry.path();
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            if kind.is_symlink() && !state.root.contains(&path) {
                continue;
            }
            let Ok(canonical) = path.canonicalize() else {
                continue;
            };
            let Some(relative) = state.root.relative(&canonical) else {
                continue;
            };
            if canonical.is_dir() {
                if kind.is_symlink() {
                    continue;
                }
                if canonical.join(".gridplan-results").is_file() {
                    results.push(relative);
                } else if depth < 8 {
                    stack.push((canonical, depth + 1));
                }
            } else if canonical.is_file()
                && Path::new(&name)
                    .extension()
                    .and_then(|e| e.to_str())
                    .is_some_and(|e| MAP_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
                && !is_weight_file(&canonical)
            {
                // Only a regular file (or a link to one inside the served directory), what
                // `/api/map` opens: a FIFO, socket or device named `*.map` is not a map.
                maps.push(relative);
            }
        }
    }
    maps.sort();
    results.sort();
    Answer::json(
        200,
        serde_json::json!({ "maps": maps, "results": results, "truncated": seen > MAX_LISTED })
            .to_string(),
    )
}

/// Whether `path` is a `.csv` of cell weights rather than a 0/1 map: its name ends in
/// `weights.csv`, or its first row (after `#` comments, within its first 64 KiB) holds a
/// value other than 0 and 1. Weight files go in the page's Weights box, and are not
/// listed as maps (read as one, a weight file is refused).
fn is_weight_file(path: &Path) -> bool {
    let Some(name) = path.file_name().and_then(|n| n.to_str()) else {
        return false;
    };
    let name = name.to_ascii_lowercase();
    if !name.ends_with(".csv") {
        return false;
    }
    if name.ends_with("weights.csv") {
        return true;
    }
    let mut head = Vec::new();
    let read = std::fs::File::open(path).and_then(|f| f.take(64 << 10).read_to_end(&mut head));
    if read.is_err() {
        return false;
    }
    let text = String::from_utf8_lossy(&head);
    let first = text
        .lines()
        .map(str::trim)
        .find(|line| !line.is_empty() && !line.starts_with('#'));
    first.is_some_and(|row| {
        row.split([',', ';', ' ', '\t'])
            .map(str::trim)
            .any(|value| !value.is_empty() && value != "0" && value != "1")
    })
}

/// A map's cell costs as the page asks for them: a weight file under the served directory
/// (planner-maps' weight `.csv`), and/or a ROS map's graded values read with nav2's bands.
/// Both off: the map reads unweighted, as before.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MapCosts {
    /// A weight file, relative to the served directory.
    #[serde(default)]
    pub weights: Option<String>,
    /// Read a ROS map's graded values (map_server `mode: scale` or `raw`) as costs.
    #[serde(default)]
    pub graded: bool,
}

/// Why a map of the served directory could not be read.
#[derive(Debug, thiserror::Error)]
pub enum MapReadError {
    /// The map, its ROS image or its weight file is not a file under the served
    /// directory (403/404).
    #[error(transparent)]
    Refused(#[from] Refusal),
    /// The file could not be read as a map (or weights).
    #[error(transparent)]
    Map(#[from] planner_maps::MapError),
    /// Graded costs asked for a map that is not a ROS map.
    #[error("graded costs apply to ROS maps (.yaml, .pgm, .png), not {relative}")]
    GradedNotRos {
        /// The map as asked for.
        relative: String,
    },
}

impl MapReadError {
    /// The answer that refuses the request: the refusal's status, else 400; files named
    /// by their path under `root` ([`relative_message`]).
    fn answer(&self, root: &Root) -> Answer {
        match self {
            MapReadError::Refused(refusal) => Answer::refusal(refusal),
            _ => Answer::error(400, &relative_message(root, &self.to_string())),
        }
    }
}

/// Whether `path` is a ROS map (a map_server YAML, or a PGM or PNG image).
fn is_ros(path: &Path) -> bool {
    path.extension().is_some_and(|e| {
        ["yaml", "yml", "pgm", "png"]
            .iter()
            .any(|ros| e.eq_ignore_ascii_case(ros))
    })
}

/// Reads map `relative` under the root with `costs`: the file, its grid (weighted when the
/// costs say so) and problems.
fn read_map(
    state: &State,
    relative: &str,
    costs: &MapCosts,
) -> Result<(PathBuf, planner_maps::MapFile), MapReadError> {
    let path = state.root.file(relative)?;
    let is_yaml = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("yaml") || e.eq_ignore_ascii_case("yml"));
    if is_yaml {
        // The image a ROS YAML names must lie under the root too (checked before reading it).
        let text = planner_maps::read_text_file(&path, 1 << 20)?;
        let yaml = planner_maps::parse_ros_yaml(&text, relative)?;
        let image = path
            .parent()
            .map_or_else(|| PathBuf::from(&yaml.image), |d| d.join(&yaml.image));
        if !state.root.contains(&image) {
            return Err(Refusal::Forbidden(yaml.image.clone()).into());
        }
    }
    if costs.graded && !is_ros(&path) {
        return Err(MapReadError::GradedNotRos {
            relative: relative.to_string(),
        });
    }
    let mut options = planner_maps::ReadOptions::default();
    options.costs.graded = costs.graded;
    let mut read = planner_maps::read_map_with(&path, &options)?;
    if let Some(weights) = &costs.weights {
        let weights = state.root.file(weights)?;
        read.file.grid = planner_maps::read_weights(
            &weights,
            read.file.grid,
            planner_api::CostRule::default(),
            &options,
        )?;
    }
    Ok((path, read.file))
}

/// The ROS occupancy values (-1 unknown, 0 free, up to 100 occupied) of the ROS map at
/// `path` (a YAML whose image [`read_map`] has checked, or an image), row-major; `None`
/// when it cannot be read (the map was read just before: it changed meanwhile).
fn ros_occupancy(path: &Path) -> Option<Vec<i8>> {
    let options = planner_maps::ReadOptions::default();
    let is_yaml = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("yaml") || e.eq_ignore_ascii_case("yml"));
    let map = if is_yaml {
        planner_maps::read_ros_map_with(path, &options).ok()?
    } else {
        // A regular file (checked by the root), read up to the readers' limit.
        let mut bytes = Vec::new();
        std::fs::File::open(path)
            .ok()?
            .take(options.max_file_bytes.saturating_add(1))
            .read_to_end(&mut bytes)
            .ok()?;
        if bytes.len() as u64 > options.max_file_bytes {
            return None;
        }
        let origin = path.display().to_string();
        planner_maps::ros_map_from_image_bytes(&bytes, &origin, None, &options).ok()?
    };
    Some(map.occupancy)
}

/// The most problems [`map`] sends.
const MAX_PROBLEMS: usize = 20_000;

fn map(state: &State, relative: &str, costs: &MapCosts) -> Answer {
    let (path, file) = match read_map(state, relative, costs) {
        Ok(read) => read,
        Err(error) => return error.answer(&state.root),
    };
    let grid = &file.grid;
    // A ROS map's unknown cells (map_server's -1) are blocked like occupied ones; the page
    // draws them apart, so they are sent as '2'.
    let occupancy = if is_ros(&path) {
        ros_occupancy(&path).filter(|o| o.len() == grid.free_cells().len())
    } else {
        None
    };
    let unknown = |i: usize| occupancy.as_ref().is_some_and(|o| o[i] == -1);
    let cells: String = grid
        .free_cells()
        .iter()
        .enumerate()
        .map(|(i, &free)| match free {
            true => '0',
            false if unknown(i) => '2',
            false => '1',
        })
        .collect();
    let mut problems: Vec<serde_json::Value> = file
        .problems
        .iter()
        .take(MAX_PROBLEMS)
        .map(|p| serde_json::json!([p.start.x, p.start.y, p.goal.x, p.goal.y, null, null]))
        .collect();
    if problems.is_empty() {
        let scen = format!("{relative}.scen");
        if let Ok(scen_path) = state.root.file(&scen) {
            match planner_maps::read_scenarios(&scen_path) {
                Ok(scenarios) => {
                    problems = scenarios
                        .iter()
                        .filter(|s| (s.width, s.height) == (grid.width(), grid.height()))
                        .take(MAX_PROBLEMS)
                        .map(|s| {
                            serde_json::json!([
                                s.start.x,
                                s.start.y,
                                s.goal.x,
                                s.goal.y,
                                s.bucket,
                                s.optimal_length
                            ])
                        })
                        .collect();
                }
                Err(e) => tracing::warn!("{}: {e}", scen_path.display()),
            }
        }
    }
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    Answer::json(
        200,
        serde_json::json!({
            "path": relative,
            "name": name,
            "width": grid.width(),
            "height": grid.height(),
            "cells": cells,
            "problems": problems,
            // Per cell (row-major), on a weighted map only: what the page shades by.
            "weights": grid.weights().map(|w| w.cells()),
            "cost_rule": grid.weights().map(|w| w.rule().name()),
            // What a plan request gives back as `map_version`.
            "version": map_version(grid),
            // A ROS map's frame (a map_server YAML's), so the page shows cells in metres.
            "frame": file.frame.map(|f| serde_json::json!({
                "resolution": f.resolution,
                "origin": f.origin,
            })),
        })
        .to_string(),
    )
}

/// The identity of a map as read (the served file with its costs, before wall edits): a
/// hash of its size, its cells and its weights, as 16 hex digits. `GET /api/map` answers it
/// as `version`, and a plan request that gives it back ([`PlanRequest::map_version`]) is
/// refused when the map read for the plan has another: the file changed on disk since the
/// page drew it, and the plan would run on cells the page does not show. The hash is
/// SipHash with fixed keys (std's `DefaultHasher::new`), the same within one server.
pub fn map_version(grid: &planner_api::Grid) -> String {
    use std::hash::{Hash as _, Hasher as _};
    let mut hasher = std::hash::DefaultHasher::new();
    (grid.width(), grid.height()).hash(&mut hasher);
    grid.free_cells().hash(&mut hasher);
    match grid.weights() {
        Some(weights) => {
            (1u8, weights.rule().name()).hash(&mut hasher);
            weights.cells().hash(&mut hasher);
        }
        None => 0u8.hash(&mut hasher),
    }
    format!("{:016x}", hasher.finish())
}

/// What a plan whose map changed on disk since the page loaded it is answered (409).
pub const MAP_CHANGED: &str = "the map file changed on disk since it was loaded; load it again";

/// `POST /api/plan`'s body.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanRequest {
    /// The map, relative to the served directory.
    pub map: String,
    /// Wall edits on the map: `[x, y, free]` with free 0 (wall) or 1; any other value is
    /// refused (400).
    #[serde(default)]
    pub edits: Vec<(u32, u32, u8)>,
    /// Start `[x, y]`.
    pub start: (u32, u32),
    /// Goal `[x, y]`.
    pub goal: (u32, u32),
    /// Registry name.
    pub planner: String,
    /// `key=value` parameters, as `plan --set`.
    #[serde(default)]
    pub set: Vec<String>,
    /// Expansion budget (capped by the server).
    #[serde(default)]
    pub max_expansions: Option<u64>,
    /// The id `POST /api/cancel?run=ID` cancels it by.
    #[serde(default)]
    pub run: Option<String>,
    /// The map's cell costs (as `GET /api/map` takes them); the answer then has the path's
    /// `cost`.
    #[serde(default)]
    pub costs: MapCosts,
    /// Plan on a weighted map without its weights with a planner that cannot honour them
    /// (else it is refused, as `plan --ignore-costs`).
    #[serde(default)]
    pub ignore_costs: bool,
    /// The map's `version` as `GET /api/map` gave it ([`map_version`]): the plan is refused
    /// (409, [`MAP_CHANGED`]) when the map read now has another. Without it, the map is
    /// planned on as it is now.
    #[serde(default)]
    pub map_version: Option<String>,
}

/// Why a `POST /api/plan` body is not a [`PlanRequest`]: the key at fault (`goal[1]`,
/// `max_expansions`, `edits[0][2]`; none for malformed JSON or a missing or unknown key,
/// which serde's message names), serde's message and what the key takes.
#[derive(Debug)]
pub struct PlanRequestError {
    /// The key, with indices into lists (`edits[0][2]`).
    pub key: Option<String>,
    /// serde's message, without its position in the body.
    pub message: String,
    /// The request's key it is under (`edits`) and what that key takes.
    pub expected: Option<(String, &'static str)>,
}

impl std::fmt::Display for PlanRequestError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("plan request: ")?;
        if let Some(key) = &self.key {
            write!(f, "`{key}`: ")?;
        }
        f.write_str(&self.message)?;
        if let Some((top, takes)) = &self.expected {
            write!(f, "; `{top}` takes {takes}")?;
        }
        Ok(())
    }
}

impl std::error::Error for PlanRequestError {}

/// What each key of [`PlanRequest`] takes, in words.
fn expected(top: &str) -> Option<&'static str> {
    Some(match top {
        "start" | "goal" => "a cell [x, y]: two whole numbers from 0 to 4294967295",
        "edits" => "a list of wall edits [x, y, free]: x and y whole numbers from 0 to 4294967295, free 0 (wall) or 1 (free)",
        "max_expansions" => "a whole number from 0 to 18446744073709551615 (the server caps it)",
        "map" | "planner" | "run" | "map_version" => "a string",
        "set" => "a list of \"key=value\" strings",
        "costs" => "an object {\"weights\": a file, \"graded\": true or false}",
        "ignore_costs" => "true or false",
        _ => return None,
    })
}

/// `POST /api/plan`'s body as a [`PlanRequest`], or why not, naming the key.
pub fn plan_request(body: &[u8]) -> Result<PlanRequest, PlanRequestError> {
    let mut deserializer = serde_json::Deserializer::from_slice(body);
    let error = match serde_path_to_error::deserialize::<_, PlanRequest>(&mut deserializer) {
        Ok(request) => match deserializer.end() {
            Ok(()) => return Ok(request),
            Err(error) => {
                return Err(PlanRequestError {
                    key: None,
                    message: error.to_string(),
                    expected: None,
                })
            }
        },
        Err(error) => error,
    };
    let segments: Vec<String> = error.path().iter().map(|s| s.to_string()).collect();
    let inner = error.inner();
    let message = inner.to_string();
    let position = format!(" at line {} column {}", inner.line(), inner.column());
    let message = message
        .strip_suffix(&position)
        .map_or_else(|| message.clone(), str::to_string);
    // A path into the request's own keys (serde's position is not a key: `.` or an
    // unknown key's name).
    let top = segments
        .first()
        .map(String::as_str)
        .and_then(|top| (inner.is_data() && expected(top).is_some()).then_some(top));
    let Some(top) = top else {
        return Err(PlanRequestError {
            key: None,
            message,
            expected: None,
        });
    };
    let mut key = top.to_string();
    for segment in &segments[1..] {
        if !segment.starts_with('[') {
            key.push('.');
        }
        key.push_str(segment);
    }
    Err(PlanRequestError {
        key: Some(key),
        message,
        expected: expected(top).map(|takes| (top.to_string(), takes)),
    })
}

/// A running plan's place: when its worker ends, its id stops naming it, its cancel flag
/// goes back to the pool and the running-plans count drops, in that order (so a cancel
/// for the old id never reaches the flag's next run).
struct Running {
    state: Arc<State>,
    run_id: Option<String>,
    flag: CancelFlag,
}

impl Drop for Running {
    fn drop(&mut self) {
        forget_run(&self.state, self.run_id.as_deref(), self.flag);
        self.state.flags.give(self.flag);
        self.state.running.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Removes `run_id` from the cancellable runs if it still names `flag`'s run.
fn forget_run(state: &State, run_id: Option<&str>, flag: CancelFlag) {
    if let (Some(id), Ok(mut cancels)) = (run_id, state.cancels.lock()) {
        if cancels.get(id) == Some(&flag) {
            cancels.remove(id);
        }
    }
}

/// Whether the client of `stream` has gone: its side of the connection closed (a read
/// finds the end) or reset. Bytes it sent after the request (pipelined) do not count.
fn client_gone(stream: &TcpStream) -> bool {
    if stream.set_nonblocking(true).is_err() {
        return false;
    }
    let mut probe = [0u8; 1];
    let gone = match stream.peek(&mut probe) {
        Ok(0) => true,
        Ok(_) => false,
        Err(e) => !matches!(
            e.kind(),
            std::io::ErrorKind::WouldBlock | std::io::ErrorKind::Interrupted
        ),
    };
    // The answer is written blocking; a stream that cannot be set back is given up.
    if stream.set_nonblocking(false).is_err() {
        return true;
    }
    gone
}

fn plan(state: &Arc<State>, body: &[u8], client: &TcpStream) -> Answer {
    let request = match plan_request(body) {
        Ok(request) => request,
        Err(e) => return Answer::error(400, &e.to_string()),
    };
    let (path, file) = match read_map(state, &request.map, &request.costs) {
        Ok(read) => read,
        Err(error) => return error.answer(&state.root),
    };
    if let Some(version) = &request.map_version {
        if *version != map_version(&file.grid) {
            return Answer::json(
                409,
                serde_json::json!({ "error": MAP_CHANGED, "map_changed": true }).to_string(),
            );
        }
    }
    let mut grid = file.grid;
    let edits = match query::edits_from_values(&request.edits) {
        Ok(edits) => edits,
        Err(e) => return Answer::error(400, &e.to_string()),
    };
    if let Err(e) = query::apply_edits(&mut grid, &edits) {
        return Answer::error(400, &e.to_string());
    }
    if state.running.fetch_add(1, Ordering::SeqCst) >= state.max_running {
        state.running.fetch_sub(1, Ordering::SeqCst);
        return Answer::error(503, "busy: other plans are running; try again");
    }
    let cancelled = state.flags.take();
    let run_id = request
        .run
        .clone()
        .filter(|id| !id.is_empty() && id.len() <= 64);
    if let (Some(id), Ok(mut cancels)) = (&run_id, state.cancels.lock()) {
        cancels.insert(id.clone(), cancelled);
    }
    // Every search checks the flag: a run with an id can be cancelled by a request, and
    // any run when its client goes.
    let cancel = Some(cancelled);
    // The worker owns the guard: the place is freed when the worker ends, cancelled or not.
    let guard = Running {
        state: Arc::clone(state),
        run_id: run_id.clone(),
        flag: cancelled,
    };
    let (send, receive) = mpsc::channel();
    let caps = state.caps;
    let root = state.root.clone();
    std::thread::spawn(move || {
        let name = path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let query = Query {
            map_name: &name,
            map_path: &path,
            start: Cell::new(request.start.0, request.start.1),
            goal: Cell::new(request.goal.0, request.goal.1),
            planner: &request.planner,
            set: &request.set,
            max_expansions: request.max_expansions,
            ignore_costs: request.ignore_costs,
            cancel,
        };
        let answer = match query::plan(&query, grid, &caps) {
            Ok(result) => plan_answer(&result),
            Err(e) => Answer::error(400, &relative_message(&root, &e.to_string())),
        };
        // Not running any more once the answer is out (dropped on a panic too).
        drop(guard);
        let _ = send.send(answer);
    });
    // A cancelled run answers 409 whether its search was stopped by the flag (it then
    // ends as budget_exhausted, often before the next look at the flag here) or not.
    let answer = loop {
        match receive.recv_timeout(Duration::from_millis(20)) {
            Ok(_) if cancelled.is_cancelled() => {
                break Answer::json(409, r#"{"cancelled":true}"#.to_string());
            }
            Ok(answer) => break answer,
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                break Answer::error(500, "the planning thread ended without an answer")
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {
                if !cancelled.is_cancelled() && client_gone(client) {
                    cancelled.cancel();
                }
                if cancelled.is_cancelled() {
                    break Answer::json(409, r#"{"cancelled":true}"#.to_string());
                }
            }
        }
    };
    forget_run(state, run_id.as_deref(), cancelled);
    answer
}

/// The most expanded cells sent to the page (the rest are counted, not sent).
const MAX_EXPANDED_SENT: usize = 4_000_000;

fn plan_answer(result: &planner_runner::plan::PlanResult) -> Answer {
    let json = match result.to_json() {
        Ok(json) => json,
        Err(e) => return Answer::error(500, &e.to_string()),
    };
    let width = result.grid.width();
    let mut out = String::with_capacity(json.len() + result.expanded.len() * 8 + 64);
    out.push_str("{\"plan\":");
    out.push_str(&json);
    out.push_str(",\"time_ms\":");
    out.push_str(&format!("{}", result.record.time_ms));
    out.push_str(",\"expanded_total\":");
    out.push_str(&result.expanded.len().to_string());
    out.push_str(",\"expanded\":[");
    for (i, cell) in result.expanded.iter().take(MAX_EXPANDED_SENT).enumerate() {
        if i > 0 {
            out.push(',');
        }
        out.push_str(&crate::trace::id(width, *cell).to_string());
    }
    // OPEN's frontier, where the planner recorded its steps: each generated cell (the start
    // aside) with the number of expansions done when it was generated, so the page colours
    // it from that step of the playback until its own expansion paints over it.
    let (mut cells, mut steps) = (String::new(), String::new());
    let mut done = 0u64;
    let mut sent = 0usize;
    for event in &result.events {
        match event.kind {
            planner_api::SearchEventKind::Expanding => done += 1,
            planner_api::SearchEventKind::Generating if done > 0 && sent < MAX_EXPANDED_SENT => {
                let separator = if sent > 0 { "," } else { "" };
                let index = crate::trace::id(width, event.cell);
                // Written in place (a `String` never fails to take it).
                let _ = write!(cells, "{separator}{index}");
                let _ = write!(steps, "{separator}{done}");
                sent += 1;
            }
            _ => {}
        }
    }
    out.push_str(&format!(
        "],\"generated\":[{cells}],\"generated_at\":[{steps}]}}"
    ));
    Answer::json(200, out)
}

fn cancel(state: &State, run: &str) -> Answer {
    // Raised under the lock: a flag that `run` names has not gone back to the pool.
    let raised = state
        .cancels
        .lock()
        .ok()
        .is_some_and(|cancels| cancels.get(run).map(|flag| flag.cancel()).is_some());
    if raised {
        Answer::json(200, r#"{"cancelled":true}"#.to_string())
    } else {
        Answer::error(404, "no running plan with that id")
    }
}

/// The largest results file read (runs.json, paths.jsonl), in bytes.
const MAX_RESULTS_BYTES: u64 = 256 << 20;

fn results(state: &State, relative: &str) -> Answer {
    let dir = match state.root.dir(relative) {
        Ok(dir) => dir,
        Err(refusal) => return Answer::refusal(&refusal),
    };
    if !dir.join(".gridplan-results").is_file() {
        return Answer::error(
            404,
            &format!("{relative:?} is not a gridplan results directory"),
        );
    }
    let read = |name: &str| -> Result<Option<String>, Answer> {
        let file = format!("{relative}/{name}");
        match state.root.file(&file) {
            Ok(path) => planner_maps::read_text_file(&path, MAX_RESULTS_BYTES)
                .map(Some)
                .map_err(|e| Answer::error(400, &relative_message(&state.root, &e.to_string()))),
            Err(Refusal::NotFound(_)) => Ok(None),
            Err(refusal) => Err(Answer::refusal(&refusal)),
        }
    };
    let runs = match read("runs.json") {
        Ok(Some(text)) => text,
        Ok(None) => {
            // What the page opens is runs.json; say why a marked directory lacks it.
            let why = if dir.join("replans.jsonl").is_file() {
                "it holds a replanning experiment's results (configs/replan/), which the page does not draw"
            } else {
                "its config's `outputs` left runs.json out; add \"json\" to `outputs` and run it again"
            };
            return Answer::error(404, &format!("{relative:?} has no runs.json: {why}"));
        }
        Err(answer) => return answer,
    };
    let runs: serde_json::Value = match serde_json::from_str(&runs) {
        Ok(value) => value,
        Err(e) => return Answer::error(400, &format!("runs.json: {e}")),
    };
    let paths: Vec<serde_json::Value> = match read("paths.jsonl") {
        Ok(Some(text)) => text
            .lines()
            .filter_map(|line| serde_json::from_str(line).ok())
            .collect(),
        Ok(None) => Vec::new(),
        Err(answer) => return answer,
    };
    // Where each map the runs name lies under the root, for drawing (crate::located).
    let extents = run_extents(&runs, &paths);
    let listed = maps(state);
    let listed: serde_json::Value = serde_json::from_slice(&listed.body).unwrap_or_default();
    let files: Vec<String> = listed
        .get("maps")
        .and_then(|m| m.as_array())
        .map(|m| {
            m.iter()
                .filter_map(|v| v.as_str().map(String::from))
                .collect()
        })
        .unwrap_or_default();
    let recorded = Recorded {
        results: &dir,
        config: runs.get("config").and_then(|c| c.as_str()),
        config_sha256: runs
            .get("provenance")
            .and_then(|p| p.get("config_sha256"))
            .and_then(|h| h.as_str()),
    };
    let found = crate::located::locate(&state.root, &recorded, &extents, &files, |map| {
        read_map(state, map, &MapCosts::default())
            .map(|(_, file)| (file.grid.width(), file.grid.height()))
    });
    let notes: serde_json::Map<String, serde_json::Value> = found
        .unlocated
        .iter()
        .map(|(name, why)| (name.clone(), why.to_string().into()))
        .chain(
            found
                .by_name
                .iter()
                .map(|(name, how)| (name.clone(), how.to_string().into())),
        )
        .collect();
    Answer::json(
        200,
        serde_json::json!({
            "path": relative,
            "runs": runs.get("runs"),
            "planners": runs.get("planners"),
            "paths": paths,
            "maps": found.maps,
            "map_notes": notes,
        })
        .to_string(),
    )
}

/// The cells the runs of each map use, by map name: their starts and goals (runs.json's
/// table) and their kept paths (paths.jsonl).
fn run_extents(
    runs: &serde_json::Value,
    paths: &[serde_json::Value],
) -> std::collections::BTreeMap<String, Extent> {
    let mut extents: std::collections::BTreeMap<String, Extent> = Default::default();
    if let Some(table) = runs.get("runs") {
        let columns: Vec<&str> = table
            .get("columns")
            .and_then(|c| c.as_array())
            .map(|c| c.iter().map(|v| v.as_str().unwrap_or("")).collect())
            .unwrap_or_default();
        let at = |name: &str| columns.iter().position(|c| *c == name);
        let cells = [("start_x", "start_y"), ("goal_x", "goal_y")].map(|(x, y)| (at(x), at(y)));
        let rows = table.get("data").and_then(|d| d.as_array());
        if let (Some(map), Some(rows)) = (at("map"), rows) {
            for row in rows {
                let Some(name) = row.get(map).and_then(|v| v.as_str()) else {
                    continue;
                };
                let extent = extents.entry(name.to_string()).or_default();
                for (x, y) in cells {
                    let value = |column: Option<usize>| {
                        column.and_then(|c| row.get(c)).and_then(|v| v.as_u64())
                    };
                    if let (Some(x), Some(y)) = (value(x), value(y)) {
                        extent.add(x, y);
                    }
                }
            }
        }
    }
    for kept in paths {
        let (Some(name), Some(cells)) = (
            kept.get("map").and_then(|m| m.as_str()),
            kept.get("path").and_then(|p| p.as_array()),
        ) else {
            continue;
        };
        let extent = extents.entry(name.to_string()).or_default();
        for cell in cells {
            if let (Some(x), Some(y)) = (
                cell.get(0).and_then(|v| v.as_u64()),
                cell.get(1).and_then(|v| v.as_u64()),
            ) {
                extent.add(x, y);
            }
        }
    }
    extents
}
