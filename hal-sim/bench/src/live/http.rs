//! The HTTP side: the page's assets, the JSON API and the event stream, on
//! tiny_http (small and blocking: one short-lived thread per request, one
//! long-lived thread per open event stream, both capped).
//!
//! tiny_http's own streaming responses go through a chunked encoder that
//! holds back 8 KiB before it writes, which would stall server-sent events;
//! the event stream therefore writes its response on the raw connection
//! (`Request::into_writer`) and flushes every event.

use std::io::{Cursor, Read, Write};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{channel, sync_channel, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use hal_sim::finger::Glass;
use serde_json::{json, Value};
use tiny_http::{Header, Method, Request, Response, Server, StatusCode};
use touch_arm::ui::layout::Layout;

use super::api::{self, refuse, Refusal};
use super::bench::{Command, Snapshot, EVENT_QUEUE};
use super::{screen, serial};

const INDEX_HTML: &str = include_str!("assets/index.html");
const APP_JS: &str = include_str!("assets/app.js");
const STYLE_CSS: &str = include_str!("assets/style.css");

/// Requests handled at once; more get 503.
const MAX_HANDLERS: usize = 64;
/// Open event streams at once; more get 503.
const MAX_STREAMS: usize = 8;
/// How long a request waits for the bench thread (it answers within a
/// slice, ~10 ms, unless it is gone).
const BENCH_TIMEOUT: Duration = Duration::from_secs(5);
/// `/api/serial` waits in wall time for the bench to close the answer
/// window (`serial::answer_window_s`, simulated) this many times the window,
/// plus [`SERIAL_SLACK`]: room for a simulator that runs behind.
const SERIAL_TIMEOUT_FACTOR: f64 = 2.0;
const SERIAL_SLACK: Duration = Duration::from_secs(1);
/// A comment line on an idle event stream, so a closed page is noticed.
const KEEPALIVE: Duration = Duration::from_secs(10);

pub struct Context {
    pub bench: Mutex<Sender<Command>>,
    pub snapshot: Arc<Mutex<Snapshot>>,
    /// `GET /api/geometry`, computed once.
    pub geometry: String,
    /// The simulated screen's layout (the pixels a press may name).
    pub layout: Layout,
    pub port: u16,
    handlers: AtomicUsize,
    streams: AtomicUsize,
}

impl Context {
    pub fn new(
        bench: Sender<Command>,
        snapshot: Arc<Mutex<Snapshot>>,
        geometry: String,
        layout: Layout,
        port: u16,
    ) -> Context {
        Context {
            bench: Mutex::new(bench),
            snapshot,
            geometry,
            layout,
            port,
            handlers: AtomicUsize::new(0),
            streams: AtomicUsize::new(0),
        }
    }

    fn send(&self, c: Command) -> Result<(), Refusal> {
        let tx = self.bench.lock().unwrap_or_else(|e| e.into_inner()).clone();
        tx.send(c).map_err(|_| refuse(503, "the simulator has stopped"))
    }

    /// Sends a command built around a reply channel and waits for the reply.
    fn ask<T>(&self, make: impl FnOnce(Sender<T>) -> Command, timeout: Duration) -> Result<T, Refusal> {
        let (tx, rx) = channel();
        self.send(make(tx))?;
        rx.recv_timeout(timeout).map_err(|_| refuse(503, "the simulator did not answer"))
    }

    fn snapshot(&self) -> Snapshot {
        self.snapshot.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }
}

/// Answers requests until the server is unblocked.
pub fn serve(server: Arc<Server>, ctx: Arc<Context>) {
    for req in server.incoming_requests() {
        if ctx.handlers.fetch_add(1, Ordering::SeqCst) >= MAX_HANDLERS {
            ctx.handlers.fetch_sub(1, Ordering::SeqCst);
            let _ = req.respond(error_response(&refuse(503, "too many requests at once")));
            continue;
        }
        let c = ctx.clone();
        let spawned = std::thread::Builder::new().name("live-http".into()).spawn(move || {
            handle(req, &c);
            c.handlers.fetch_sub(1, Ordering::SeqCst);
        });
        if spawned.is_err() {
            ctx.handlers.fetch_sub(1, Ordering::SeqCst);
        }
    }
}

type Body = Response<Cursor<Vec<u8>>>;

fn header(name: &str, value: &str) -> Header {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("ASCII header")
}

fn response(status: u16, content_type: &str, body: Vec<u8>) -> Body {
    // Always a Content-Length (tiny_http would chunk bodies over 32 KiB,
    // such as the geometry; simple clients read a length more easily).
    Response::from_data(body)
        .with_chunked_threshold(usize::MAX)
        .with_status_code(StatusCode(status))
        .with_header(header("Content-Type", content_type))
        .with_header(header("Cache-Control", "no-store"))
        .with_header(header("X-Content-Type-Options", "nosniff"))
}

/// Millimetres per pixel of the panel `lay` is laid out for: the 2.8"
/// 320×240 or the 3.5" 480×320 (`hal_sim::finger::Glass`).
fn mm_per_px(lay: &Layout) -> f64 {
    if lay.width() == Glass::HVGA_35.w_px {
        Glass::HVGA_35.mm_per_px
    } else {
        Glass::QVGA_28.mm_per_px
    }
}

fn json_response(status: u16, v: &Value) -> Body {
    response(status, "application/json", format!("{v}\n").into_bytes())
}

/// `{"error": "<one line>"}` with the refusal's status.
fn error_response(r: &Refusal) -> Body {
    json_response(r.status, &json!({ "error": r.reason.replace('\n', " ") }))
}

fn header_value<'a>(req: &'a Request, name: &'static str) -> Option<&'a str> {
    req.headers().iter().find(|h| h.field.equiv(name)).map(|h| h.value.as_str())
}

/// Only this machine's own pages and scripts may drive the bench: the Host
/// header must name the loopback address (a DNS-rebound name reaching
/// 127.0.0.1 does not), and a browser POST must come from the bench's own
/// origin (another site's page cannot press the panel or power-cycle).
fn check_origin(req: &Request, port: u16) -> Result<(), Refusal> {
    let ours = [format!("127.0.0.1:{port}"), format!("localhost:{port}")];
    match header_value(req, "Host") {
        Some(h) if ours.iter().any(|o| o == h) => {}
        Some(h) => return Err(refuse(403, format!("Host {h:?} is not this bench (use http://127.0.0.1:{port}/)"))),
        None => return Err(refuse(400, "missing Host header")),
    }
    if let Some(origin) = header_value(req, "Origin") {
        if !ours.iter().any(|o| origin == format!("http://{o}")) {
            return Err(refuse(403, format!("requests from {origin} are not accepted")));
        }
    }
    Ok(())
}

fn read_body(req: &mut Request, max: usize) -> Result<Vec<u8>, Refusal> {
    let mut body = Vec::new();
    req.as_reader()
        .take(max as u64 + 1)
        .read_to_end(&mut body)
        .map_err(|e| refuse(400, format!("reading the body: {e}")))?;
    if body.len() > max {
        return Err(refuse(413, format!("body over {max} bytes")));
    }
    Ok(body)
}

fn handle(mut req: Request, ctx: &Context) {
    let path = req.url().split('?').next().unwrap_or("").to_string();
    let method = req.method().clone();
    if let Err(r) = check_origin(&req, ctx.port) {
        let _ = req.respond(error_response(&r));
        return;
    }
    if method == Method::Get && path == "/api/events" {
        return events(req, ctx);
    }
    let result = match (&method, path.as_str()) {
        (Method::Get, "/" | "/index.html") => Ok(response(200, "text/html; charset=utf-8", INDEX_HTML.into())),
        (Method::Get, "/app.js") => Ok(response(200, "text/javascript; charset=utf-8", APP_JS.into())),
        (Method::Get, "/style.css") => Ok(response(200, "text/css; charset=utf-8", STYLE_CSS.into())),
        (Method::Get, "/favicon.ico") => Ok(response(204, "image/x-icon", Vec::new())),
        (Method::Get, "/api/state") => Ok(json_response(200, &ctx.snapshot().state_json())),
        (Method::Get, "/api/bench") => Ok(json_response(200, &ctx.snapshot().bench)),
        (Method::Get, "/api/console") => api::console_since(req.url().split_once('?').map(|(_, q)| q))
            .and_then(|since| ctx.ask(|tx| Command::Console(since, tx), BENCH_TIMEOUT))
            .map(|v| json_response(200, &v)),
        (Method::Get, "/api/geometry") => Ok(response(200, "application/json", ctx.geometry.clone().into_bytes())),
        (Method::Get, "/api/layout") => Ok(json_response(200, &api::layout_json(&ctx.layout, mm_per_px(&ctx.layout)))),
        (Method::Get, "/api/screen.png") => screen::png(&ctx.snapshot().screen)
            .map(|png| response(200, "image/png", png))
            .map_err(|e| refuse(500, format!("encoding the screen: {e}"))),
        (Method::Post, "/api/finger") => {
            read_body(&mut req, api::MAX_FINGER_BODY).and_then(|body| post(&path, &body, ctx))
        }
        (
            Method::Post,
            "/api/touch" | "/api/press" | "/api/release" | "/api/switch" | "/api/serial" | "/api/control",
        ) => read_body(&mut req, api::MAX_BODY).and_then(|body| post(&path, &body, ctx)),
        (
            _,
            "/" | "/index.html" | "/app.js" | "/style.css" | "/favicon.ico" | "/api/state" | "/api/bench"
            | "/api/geometry" | "/api/screen.png" | "/api/console",
        ) => Err(refuse(405, format!("{path} takes GET"))),
        (
            _,
            "/api/touch" | "/api/finger" | "/api/press" | "/api/release" | "/api/switch" | "/api/serial"
            | "/api/control",
        ) => Err(refuse(405, format!("{path} takes POST with a JSON body"))),
        _ => Err(refuse(404, format!("no such endpoint: {path}"))),
    };
    let _ = match result {
        Ok(r) => req.respond(r),
        Err(r) => req.respond(error_response(&r)),
    };
}

fn post(path: &str, body: &[u8], ctx: &Context) -> Result<Body, Refusal> {
    // A refusal from the bench itself (e.g. a stall while booting) is a
    // conflict with the bench's state, not a malformed request.
    let conflict = |r: Result<Value, String>| r.map_err(|e| refuse(409, e));
    let v = match path {
        "/api/touch" => {
            let p = api::touch(body, &ctx.layout)?;
            conflict(ctx.ask(|tx| Command::Press(p, tx), BENCH_TIMEOUT)?)?
        }
        "/api/finger" => {
            let f = api::finger(body)?;
            conflict(ctx.ask(|tx| Command::Finger(Box::new(f), tx), BENCH_TIMEOUT)?)?
        }
        "/api/press" => {
            let p = api::press(body, &ctx.layout)?;
            conflict(ctx.ask(|tx| Command::Press(p, tx), BENCH_TIMEOUT)?)?
        }
        "/api/release" => {
            api::release(body)?;
            conflict(ctx.ask(Command::Release, BENCH_TIMEOUT)?)?
        }
        "/api/switch" => {
            let down = api::switch(body)?;
            conflict(ctx.ask(|tx| Command::Switch(down, tx), BENCH_TIMEOUT)?)?
        }
        "/api/serial" => {
            let line = api::serial(body)?;
            // The bench answers when the firmware has, or when the answer
            // window closed (then with what arrived, possibly nothing).
            let wait = Duration::from_secs_f64(serial::answer_window_s(&line) * SERIAL_TIMEOUT_FACTOR) + SERIAL_SLACK;
            let (tx, rx) = channel();
            ctx.send(Command::Serial(line, tx))?;
            json!({ "replies": rx.recv_timeout(wait).unwrap_or_default() })
        }
        "/api/control" => {
            let c = api::control(body, u64::from(touch_arm::config::store::EEPROM_SIZE))?;
            conflict(ctx.ask(|tx| Command::Control(c, tx), BENCH_TIMEOUT)?)?
        }
        _ => return Err(refuse(404, format!("no such endpoint: {path}"))),
    };
    Ok(json_response(200, &v))
}

/// `GET /api/events`: server-sent events `screen`, `history`, `serial` and
/// `state` (see the bench), until the page goes or the bench stops.
fn events(req: Request, ctx: &Context) {
    if ctx.streams.fetch_add(1, Ordering::SeqCst) >= MAX_STREAMS {
        ctx.streams.fetch_sub(1, Ordering::SeqCst);
        let _ = req.respond(error_response(&refuse(503, "too many event streams open")));
        return;
    }
    let (tx, rx) = sync_channel::<Arc<str>>(EVENT_QUEUE);
    if let Err(r) = ctx.send(Command::Subscribe(tx)) {
        ctx.streams.fetch_sub(1, Ordering::SeqCst);
        let _ = req.respond(error_response(&r));
        return;
    }
    let mut w = req.into_writer();
    let head =
        "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n";
    let mut ok = w.write_all(head.as_bytes()).and_then(|()| w.flush()).is_ok();
    while ok {
        ok = match rx.recv_timeout(KEEPALIVE) {
            Ok(e) => w.write_all(e.as_bytes()).and_then(|()| w.flush()).is_ok(),
            Err(RecvTimeoutError::Timeout) => w.write_all(b": keepalive\n\n").and_then(|()| w.flush()).is_ok(),
            Err(RecvTimeoutError::Disconnected) => false,
        };
    }
    ctx.streams.fetch_sub(1, Ordering::SeqCst);
}
