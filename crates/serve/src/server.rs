//! The HTTP server of `gridplan serve`: the embedded page and a small JSON API over the
//! served directory.
//!
//! | Request | Answer |
//! |---|---|
//! | `GET /`, `/app.js`, `/style.css` | the page (embedded in the binary) |
//! | `GET /api/planners` | the registry: name, summary, declared parameters |
//! | `GET /api/maps` | map files and results directories under the served directory |
//! | `GET /api/map?path=P` | map `P`: size, cells, its own problems or its `.scen`'s |
//! | `POST /api/plan` | plans one query (JSON body, [`PlanRequest`]); `plan --json`'s object and the expanded cells |
//! | `POST /api/cancel?run=ID` | cancels the plan request with that `run` id |
//! | `GET /api/results?path=P` | results directory `P`: runs.json's table, the kept paths, the maps it names |
//!
//! HTTP/1.1 on plain TCP: a fixed pool of threads, one request per connection (answered
//! with `Connection: close`), heads parsed by httparse. Safety: paths go through
//! [`crate::safe::Root`] (403/404 before anything is read); a request head over 16 KiB is
//! refused (431), and a body over [`ServeOptions::max_body_bytes`] is refused with 413 by
//! its `Content-Length`, before a byte of it is read (a body without a length, chunked, is
//! refused with 411); memory per connection is bounded by those limits; a `Host` that is
//! a DNS name other than `localhost`, or an `Origin` of another site, is refused with 403
//! (DNS rebinding and cross-site requests from pages in the user's browser);
//! planning runs get [`crate::query::Caps`]; at most [`ServeOptions::max_running`] plans
//! run at once (503 beyond). A cancelled plan answers at once (409); its search stops at
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
use std::time::Duration;

use planner_api::{CancelFlag, CancelPool, Cell};
use serde::Deserialize;

use crate::query::{self, Caps, Query};
use crate::safe::{Refusal, Root};

const INDEX_HTML: &str = include_str!("../assets/index.html");
const APP_JS: &str = include_str!("../assets/app.js");
const STYLE_CSS: &str = include_str!("../assets/style.css");

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
    /// Threads answering requests (default 4).
    pub threads: usize,
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
            threads: 4,
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
    threads: usize,
    stop: Arc<AtomicBool>,
}

struct State {
    root: Root,
    max_body_bytes: u64,
    caps: Caps,
    max_running: usize,
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
                running: AtomicUsize::new(0),
                cancels: Mutex::new(HashMap::new()),
                flags: CancelPool::new(),
            }),
            threads: options.threads.max(1),
            stop: Arc::new(AtomicBool::new(false)),
        })
    }

    /// The address it listens on (with the port chosen when 0 was asked for).
    pub fn addr(&self) -> Option<SocketAddr> {
        self.listener.local_addr().ok()
    }

    /// Answers connections until [`Server::stopper`]'s handle is called (forever
    /// otherwise): a fixed pool of threads, each answering one request per connection; at
    /// most 64 connections wait, more are closed at once.
    pub fn run(self) {
        let state = self.state;
        answer_in_pool(&self.listener, self.threads, &self.stop, move |stream| {
            connection(&state, stream)
        });
    }

    /// A handle that stops [`Server::run`] (its threads return after their request).
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

/// Hands the connections of `listener` to `threads` threads that each run `answer` on
/// one at a time, until `stop` is set (and the next connection wakes the loop): at most 64
/// connections wait, more are closed at once. A panic in `answer` closes that connection
/// (the stream is dropped) and keeps the thread, so the pool never shrinks into a server
/// that accepts and never answers. [`Server::run`] is this pool with the page's answers.
pub fn answer_in_pool(
    listener: &TcpListener,
    threads: usize,
    stop: &AtomicBool,
    answer: impl Fn(TcpStream) + Send + Sync + 'static,
) {
    let (send, receive) = mpsc::sync_channel::<TcpStream>(64);
    let receive = Arc::new(Mutex::new(receive));
    let answer = Arc::new(answer);
    let workers: Vec<_> = (0..threads)
        .map(|_| {
            let receive = Arc::clone(&receive);
            let answer = Arc::clone(&answer);
            std::thread::spawn(move || loop {
                let next = match receive.lock() {
                    Ok(receive) => receive.recv(),
                    Err(_) => return,
                };
                match next {
                    Ok(stream) => {
                        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                            answer(stream)
                        }));
                    }
                    Err(_) => return,
                }
            })
        })
        .collect();
    for stream in listener.incoming() {
        if stop.load(Ordering::SeqCst) {
            break;
        }
        if let Ok(stream) = stream {
            // A full queue drops (closes) the connection.
            let _ = send.try_send(stream);
        }
    }
    drop(send);
    for worker in workers {
        let _ = worker.join();
    }
}

/// One answer: status, content type, body.
struct Answer {
    status: u16,
    kind: &'static str,
    body: Vec<u8>,
}

impl Answer {
    fn json(status: u16, body: String) -> Answer {
        Answer {
            status,
            kind: "application/json",
            body: body.into_bytes(),
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
        }
    }
}

/// The longest request head (request line and headers) read, in bytes.
const MAX_HEAD_BYTES: usize = 16 << 10;

/// How long a connection may take to send its request.
const READ_TIMEOUT: Duration = Duration::from_secs(10);

/// One connection: one request (head parsed by httparse, body read only up to the limit),
/// one answer, then the connection closes.
fn connection(state: &Arc<State>, mut stream: TcpStream) {
    let _ = stream.set_read_timeout(Some(READ_TIMEOUT));
    let _ = stream.set_write_timeout(Some(Duration::from_secs(60)));
    let answer = match read_request(state, &mut stream) {
        Ok(Some((method, target, body))) => handle(state, &method, &target, &body, &stream),
        Ok(None) => return,
        Err(answer) => answer,
    };
    let reason = match answer.status {
        200 => "OK",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        409 => "Conflict",
        411 => "Length Required",
        413 => "Content Too Large",
        431 => "Request Header Fields Too Large",
        503 => "Service Unavailable",
        _ => "Error",
    };
    let head = format!(
        "HTTP/1.1 {} {reason}\r\nContent-Type: {}\r\nContent-Length: {}\r\nConnection: close\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nContent-Security-Policy: default-src 'self'; style-src 'self'; script-src 'self'\r\n\r\n",
        answer.status,
        answer.kind,
        answer.body.len()
    );
    if stream
        .write_all(head.as_bytes())
        .and_then(|()| stream.write_all(&answer.body))
        .and_then(|()| stream.flush())
        .is_err()
    {
        return;
    }
    // A lingering close: stop writing, then read (and drop) what the client still sends,
    // at most 1 MiB or one second, so that closing with unread data (a refused body) does
    // not reset the connection before the client has read the answer.
    let _ = stream.shutdown(Shutdown::Write);
    let _ = stream.set_read_timeout(Some(Duration::from_secs(1)));
    let mut sink = [0u8; 16 << 10];
    let mut drained = 0usize;
    while drained < (1 << 20) {
        match stream.read(&mut sink) {
            Ok(0) | Err(_) => break,
            Ok(n) => drained += n,
        }
    }
}

/// Reads one request: method, target and body, or the refusal to answer (400 malformed,
/// 411 no length for a body, 413 body over the limit, 431 head too long); `None` when the
/// client sent nothing.
#[allow(clippy::type_complexity)]
fn read_request(
    state: &State,
    stream: &mut TcpStream,
) -> Result<Option<(String, String, Vec<u8>)>, Answer> {
    let mut buffer = Vec::with_capacity(4096);
    let mut chunk = [0u8; 4096];
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
        match stream.read(&mut chunk) {
            Ok(0) if buffer.is_empty() => return Ok(None),
            Ok(0) => return Err(Answer::error(400, "incomplete request")),
            Ok(n) => buffer.extend_from_slice(&chunk[..n]),
            Err(_) if buffer.is_empty() => return Ok(None),
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
    body.reserve(length - body.len());
    while body.len() < length {
        let want = (length - body.len()).min(chunk.len());
        match stream.read(&mut chunk[..want]) {
            Ok(0) => return Err(Answer::error(400, "the request body ended early")),
            Ok(n) => body.extend_from_slice(&chunk[..n]),
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
        ("GET", "/api/planners") => planners(),
        ("GET", "/api/maps") => maps(state),
        ("GET", "/api/map") => {
            let costs = MapCosts {
                weights: params.get("weights").filter(|w| !w.is_empty()).cloned(),
                graded: params
                    .get("graded")
                    .is_some_and(|g| g == "1" || g == "true"),
            };
            map(state, params.get("path").map_or("", String::as_str), &costs)
        }
        ("GET", "/api/results") => results(state, params.get("path").map_or("", String::as_str)),
        ("POST", "/api/plan") => plan(state, body, client),
        ("POST" | "GET", "/api/cancel") => {
            cancel(state, params.get("run").map_or("", String::as_str))
        }
        (_, "/" | "/index.html" | "/app.js" | "/style.css" | "/api/planners" | "/api/maps")
        | (_, "/api/map" | "/api/results" | "/api/plan" | "/api/cancel") => {
            Answer::error(405, "method not allowed")
        }
        _ => Answer::error(404, "not found"),
    }
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
            } else if Path::new(&name)
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| MAP_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
            {
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

/// Reads map `relative` under the root with `costs`: the file, its grid (weighted when the
/// costs say so) and problems.
fn read_map(
    state: &State,
    relative: &str,
    costs: &MapCosts,
) -> Result<(PathBuf, planner_maps::MapFile), Answer> {
    let path = state.root.file(relative).map_err(|r| Answer::refusal(&r))?;
    let is_yaml = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("yaml") || e.eq_ignore_ascii_case("yml"));
    if is_yaml {
        // The image a ROS YAML names must lie under the root too (checked before reading it).
        let text = planner_maps::read_text_file(&path, 1 << 20)
            .map_err(|e| Answer::error(400, &e.to_string()))?;
        let yaml = planner_maps::parse_ros_yaml(&text, relative)
            .map_err(|e| Answer::error(400, &e.to_string()))?;
        let image = path
            .parent()
            .map_or_else(|| PathBuf::from(&yaml.image), |d| d.join(&yaml.image));
        if !state.root.contains(&image) {
            return Err(Answer::refusal(&Refusal::Forbidden(yaml.image.clone())));
        }
    }
    let is_ros = is_yaml
        || path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("pgm") || e.eq_ignore_ascii_case("png"));
    if costs.graded && !is_ros {
        return Err(Answer::error(
            400,
            &format!("graded costs apply to ROS maps (.yaml, .pgm, .png), not {relative}"),
        ));
    }
    let mut options = planner_maps::ReadOptions::default();
    options.costs.graded = costs.graded;
    let mut read = planner_maps::read_map_with(&path, &options)
        .map_err(|e| Answer::error(400, &e.to_string()))?;
    if let Some(weights) = &costs.weights {
        let weights = state.root.file(weights).map_err(|r| Answer::refusal(&r))?;
        read.file.grid = planner_maps::read_weights(
            &weights,
            read.file.grid,
            planner_api::CostRule::default(),
            &options,
        )
        .map_err(|e| Answer::error(400, &e.to_string()))?;
    }
    Ok((path, read.file))
}

/// The most problems [`map`] sends.
const MAX_PROBLEMS: usize = 20_000;

fn map(state: &State, relative: &str, costs: &MapCosts) -> Answer {
    let (path, file) = match read_map(state, relative, costs) {
        Ok(read) => read,
        Err(answer) => return answer,
    };
    let grid = &file.grid;
    let cells: String = grid
        .free_cells()
        .iter()
        .map(|&free| if free { '0' } else { '1' })
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
            // A ROS map's frame (a map_server YAML's), so the page shows cells in metres.
            "frame": file.frame.map(|f| serde_json::json!({
                "resolution": f.resolution,
                "origin": f.origin,
            })),
        })
        .to_string(),
    )
}

/// `POST /api/plan`'s body.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanRequest {
    /// The map, relative to the served directory.
    pub map: String,
    /// Wall edits on the map: `[x, y, free]` with free 0 (wall) or 1.
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
    let request: PlanRequest = match serde_json::from_slice(body) {
        Ok(request) => request,
        Err(e) => return Answer::error(400, &format!("plan request: {e}")),
    };
    let (path, file) = match read_map(state, &request.map, &request.costs) {
        Ok(read) => read,
        Err(answer) => return answer,
    };
    let mut grid = file.grid;
    let edits: Vec<(u32, u32, bool)> = request
        .edits
        .iter()
        .map(|&(x, y, free)| (x, y, free != 0))
        .collect();
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
            Err(e) => Answer::error(400, &e.to_string()),
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
                .map_err(|e| Answer::error(400, &e.to_string())),
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
    // Where each map the runs name lies under the root (by file name), for drawing.
    let mut names: Vec<String> = Vec::new();
    if let Some(table) = runs.get("runs") {
        let column = table
            .get("columns")
            .and_then(|c| c.as_array())
            .and_then(|c| c.iter().position(|v| v == "map"));
        if let (Some(column), Some(rows)) = (column, table.get("data").and_then(|d| d.as_array())) {
            for row in rows {
                if let Some(name) = row.get(column).and_then(|v| v.as_str()) {
                    if !names.iter().any(|n| n == name) {
                        names.push(name.to_string());
                    }
                }
            }
        }
    }
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
    let located: serde_json::Map<String, serde_json::Value> = names
        .into_iter()
        .map(|name| {
            let found = files
                .iter()
                .find(|f| f.rsplit('/').next() == Some(name.as_str()))
                .cloned();
            (name, serde_json::json!(found))
        })
        .collect();
    Answer::json(
        200,
        serde_json::json!({
            "path": relative,
            "runs": runs.get("runs"),
            "planners": runs.get("planners"),
            "paths": paths,
            "maps": located,
        })
        .to_string(),
    )
}
