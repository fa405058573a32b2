//! The agent's requests: `/probe`, `/current`, `/sample` (streamed as
//! `multipart/x-mixed-replace` with `interval`), `/assets` and `/asset/{ids}`, each device's
//! under `/{device}/` (its name or uuid); `/` is `/probe`. Errors are MTConnectError documents.

use std::collections::HashMap;
use std::time::Duration;

use axum::body::{Body, Bytes};
use axum::extract::{FromRequestParts, Path, RawQuery, State};
use axum::http::request::Parts;
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use tokio::time::Instant;

use super::buffer::{Buffer, Observation};
use super::doc::{self, Element};
use super::documents::{self, AssetCounts, ErrorCode, Tool};
use super::Shared;

/// `/sample`'s count when none is given (the standard's default).
const DEFAULT_COUNT: usize = 100;
/// A stream's empty document when nothing happened for this long, unless `heartbeat` says.
const DEFAULT_HEARTBEAT: Duration = Duration::from_secs(10);
/// The longest `interval` and `heartbeat` a stream takes: an hour.
const LONGEST_WAIT: Duration = Duration::from_secs(3600);
/// `/assets`' count when none is given.
const DEFAULT_ASSETS: usize = 100;

pub fn router(shared: Shared) -> Router {
    Router::new()
        .route("/", get(|s, d, h, q| request(s, d, h, q, probe)))
        .route("/probe", get(|s, d, h, q| request(s, d, h, q, probe)))
        .route("/current", get(|s, d, h, q| request(s, d, h, q, current)))
        .route("/sample", get(|s, d, h, q| request(s, d, h, q, sample)))
        .route("/assets", get(|s, d, h, q| request(s, d, h, q, assets)))
        .route("/asset/{ids}", get(asset_ids))
        .route("/{device}", get(|s, d, h, q| request(s, d, h, q, probe)))
        .route("/{device}/probe", get(|s, d, h, q| request(s, d, h, q, probe)))
        .route("/{device}/current", get(|s, d, h, q| request(s, d, h, q, current)))
        .route("/{device}/sample", get(|s, d, h, q| request(s, d, h, q, sample)))
        .route("/{device}/assets", get(|s, d, h, q| request(s, d, h, q, assets)))
        .fallback(|State(shared): State<Shared>, headers: HeaderMap| async move {
            let format = Format::of(&headers, &Query::default());
            refuse(&shared, format, ErrorCode::InvalidUri, "no such request: the agent answers /probe, /current, /sample, /assets and /asset/{ids}, each also under /{device}/")
        })
        .with_state(shared)
}

/// XML (the default) or the JSON form (`Accept: application/json` or `?format=json`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    Xml,
    Json,
}

impl Format {
    fn of(headers: &HeaderMap, query: &Query) -> Format {
        match query.0.get("format").map(String::as_str) {
            Some(f) if f.eq_ignore_ascii_case("json") => return Format::Json,
            Some(_) => return Format::Xml,
            None => {}
        }
        let accept = headers.get(header::ACCEPT).and_then(|v| v.to_str().ok()).unwrap_or("");
        if accept.contains("application/json") && !accept.contains("xml") {
            Format::Json
        } else {
            Format::Xml
        }
    }

    fn content_type(self) -> &'static str {
        match self {
            Format::Xml => "text/xml; charset=utf-8",
            Format::Json => "application/json",
        }
    }

    fn print(self, root: &Element, kind: &str) -> String {
        match self {
            Format::Xml => doc::xml(root, kind),
            Format::Json => doc::json(root),
        }
    }
}

/// The query's parameters (the last of a repeated one wins).
#[derive(Debug, Default)]
struct Query(HashMap<String, String>);

impl Query {
    fn parse(raw: Option<String>) -> Query {
        let raw = raw.unwrap_or_default();
        Query(url::form_urlencoded::parse(raw.as_bytes()).map(|(k, v)| (k.into_owned(), v.into_owned())).collect())
    }

    /// A refusal for any parameter other than `allowed` (and `format`).
    fn only(&self, allowed: &[&str]) -> Result<(), (ErrorCode, String)> {
        for key in self.0.keys() {
            if key != "format" && !allowed.contains(&key.as_str()) {
                let code = if matches!(key.as_str(), "path" | "at" | "to" | "deviceType") {
                    ErrorCode::Unsupported
                } else {
                    ErrorCode::InvalidRequest
                };
                let known = if allowed.is_empty() { "none".to_string() } else { allowed.join(", ") };
                return Err((code, format!("parameter '{key}' is not supported here (supported: {known}, format)")));
            }
        }
        Ok(())
    }

    /// A non-negative integer parameter.
    fn number(&self, key: &str) -> Result<Option<u64>, (ErrorCode, String)> {
        match self.0.get(key) {
            None => Ok(None),
            Some(v) => {
                v.trim().parse::<u64>().map(Some).map_err(|_| {
                    (ErrorCode::InvalidRequest, format!("'{key}' must be a non-negative integer, not '{v}'"))
                })
            }
        }
    }
}

fn document(format: Format, root: &Element, kind: &str) -> Response {
    ([(header::CONTENT_TYPE, format.content_type())], format.print(root, kind)).into_response()
}

fn refuse(shared: &Shared, format: Format, code: ErrorCode, message: &str) -> Response {
    let status = match code {
        ErrorCode::NoDevice | ErrorCode::InvalidUri | ErrorCode::AssetNotFound => StatusCode::NOT_FOUND,
        _ => StatusCode::BAD_REQUEST,
    };
    let mut response = document(format, &documents::error(&shared.sender, code, message), "Error");
    *response.status_mut() = status;
    response
}

/// The device a path names (its name or uuid), as its uuid.
fn find(shared: &Shared, name: &str) -> Result<String, (ErrorCode, String)> {
    let buffer = shared.buffer();
    buffer
        .devices
        .iter()
        .find(|d| d.model.is(name))
        .map(|d| d.model.uuid.clone())
        .ok_or_else(|| (ErrorCode::NoDevice, format!("no device named '{name}'")))
}

type Answer = Result<Response, (ErrorCode, String)>;

/// The name a request's path gives (`/{device}/…`, `/asset/{ids}`), percent-decoded; `None` for
/// the agent's own requests. A segment that is not UTF-8 once decoded (`/%FF/probe`) is refused
/// with an MTConnectError document, `INVALID_URI`, like any path the agent does not answer
/// (axum's own rejection was a `text/plain` 400).
struct Named(Option<String>);

impl FromRequestParts<Shared> for Named {
    type Rejection = Response;

    async fn from_request_parts(parts: &mut Parts, s: &Shared) -> Result<Named, Response> {
        match Option::<Path<String>>::from_request_parts(parts, s).await {
            Ok(named) => Ok(Named(named.map(|Path(name)| name))),
            Err(rejection) => {
                let format = Format::of(&parts.headers, &Query::parse(parts.uri.query().map(str::to_string)));
                let why = format!("the path is not a request of the agent: {}", rejection.body_text());
                Err(refuse(s, format, ErrorCode::InvalidUri, &why))
            }
        }
    }
}

/// One request of the agent's or of a device's (`/{device}/…`: its name or uuid), answered by
/// `answer_with` with the device's uuid, or its refusal as an Error document.
async fn request(
    State(s): State<Shared>,
    Named(device): Named,
    headers: HeaderMap,
    RawQuery(q): RawQuery,
    answer_with: fn(&Shared, Format, &Query, Option<String>) -> Answer,
) -> Response {
    let q = Query::parse(q);
    let format = Format::of(&headers, &q);
    let device = match device {
        Some(name) => find(&s, &name).map(Some),
        None => Ok(None),
    };
    answer(&s, format, device.and_then(|uuid| answer_with(&s, format, &q, uuid)))
}

/// A handler's answer, its refusal as an Error document.
fn answer(shared: &Shared, format: Format, result: Answer) -> Response {
    result.unwrap_or_else(|(code, message)| refuse(shared, format, code, &message))
}

fn probe(s: &Shared, format: Format, q: &Query, device: Option<String>) -> Answer {
    q.only(&[])?;
    let counts = asset_counts(s);
    let buffer = s.buffer();
    let devices: Vec<_> = buffer
        .devices
        .iter()
        .filter(|d| device.as_ref().is_none_or(|u| &d.model.uuid == u))
        .map(|d| d.model.clone())
        .collect();
    Ok(document(format, &documents::probe(&s.sender, &buffer, &devices, counts), "Devices"))
}

fn current(s: &Shared, format: Format, q: &Query, device: Option<String>) -> Answer {
    q.only(&[])?;
    let buffer = s.buffer();
    let observations = buffer
        .devices
        .iter()
        .filter(|d| device.as_ref().is_none_or(|u| &d.model.uuid == u))
        .flat_map(|d| d.current.iter().flatten());
    let root = documents::streams(&s.sender, &buffer, observations, buffer.next_sequence());
    Ok(document(format, &root, "Streams"))
}

/// What a `/sample` asks for.
#[derive(Debug, Clone)]
struct Window {
    from: u64,
    count: usize,
    device: Option<String>,
}

fn sample(s: &Shared, format: Format, q: &Query, device: Option<String>) -> Answer {
    q.only(&["from", "count", "interval", "heartbeat"])?;
    let capacity = s.buffer().capacity();
    let count = match q.number("count")? {
        None => DEFAULT_COUNT,
        Some(0) => return Err((ErrorCode::OutOfRange, "'count' must be at least 1".into())),
        Some(n) if n as usize > capacity => {
            return Err((ErrorCode::OutOfRange, format!("'count' must be at most the buffer size {capacity}")))
        }
        Some(n) => n as usize,
    };
    let from = q.number("from")?;
    let heartbeat = q.number("heartbeat")?.map_or(DEFAULT_HEARTBEAT, Duration::from_millis);
    if !(Duration::from_millis(10)..=LONGEST_WAIT).contains(&heartbeat) {
        return Err((ErrorCode::OutOfRange, "'heartbeat' must be 10 to 3,600,000 ms".into()));
    }
    let interval = q.number("interval")?.map(Duration::from_millis);
    if interval.is_some_and(|i| i > LONGEST_WAIT) {
        return Err((ErrorCode::OutOfRange, "'interval' must be at most 3,600,000 ms".into()));
    }
    let window = {
        let buffer = s.buffer();
        let from = from.unwrap_or_else(|| buffer.first_sequence());
        check_from(&buffer, from)?;
        Window { from, count, device }
    };
    match interval {
        None => {
            let buffer = s.buffer();
            let (observations, next) = collect(&buffer, &window);
            Ok(document(format, &documents::streams(&s.sender, &buffer, &observations, next), "Streams"))
        }
        Some(interval) => Ok(stream(s.clone(), format, window, interval, heartbeat)),
    }
}

/// `from` must be kept in the buffer (or be the next sequence).
fn check_from(buffer: &Buffer, from: u64) -> Result<(), (ErrorCode, String)> {
    let (first, next) = (buffer.first_sequence(), buffer.next_sequence());
    if from < first || from > next {
        return Err((
            ErrorCode::OutOfRange,
            format!("'from' must be between firstSequence {first} and nextSequence {next}, not {from}"),
        ));
    }
    Ok(())
}

/// Up to `count` observations of the window's device (of every device: no filter) from `from`,
/// and the sequence after the last one looked at (the header's nextSequence).
fn collect(buffer: &Buffer, window: &Window) -> (Vec<Observation>, u64) {
    let mut out = Vec::new();
    let mut at = window.from;
    let end = buffer.next_sequence();
    while out.len() < window.count && at < end {
        let slice = buffer.range(at, window.count - out.len());
        let Some(last) = slice.last() else { break };
        at = last.sequence + 1;
        out.extend(slice.iter().filter(|o| window.device.as_deref().is_none_or(|u| o.device.uuid == u)).cloned());
        // With a device filter, keep scanning until `count` of its observations are found.
        if window.device.is_none() && out.len() >= window.count {
            break;
        }
    }
    (out, at)
}

/// `/sample?interval=`: a `multipart/x-mixed-replace` stream of Streams documents, each as soon
/// as there is something new (but not sooner than `interval` after the last, unless the last
/// held `count` observations and more are waiting: then at once), an empty one after
/// `heartbeat` without news. A client that falls out of the buffer gets an Error part
/// and the stream ends.
fn stream(s: Shared, format: Format, window: Window, interval: Duration, heartbeat: Duration) -> Response {
    let boundary = uuid::Uuid::new_v4().simple().to_string();
    let content_type = format!("multipart/x-mixed-replace;boundary={boundary}");
    let state = Streaming { s, format, window, interval, heartbeat, boundary, last: None, more: false, done: false };
    let body = futures_util::stream::unfold(state, |mut st| async move {
        let part = st.next_part().await?;
        Some((Ok::<Bytes, std::convert::Infallible>(part), st))
    });
    ([(header::CONTENT_TYPE, content_type)], Body::from_stream(body)).into_response()
}

struct Streaming {
    s: Shared,
    format: Format,
    window: Window,
    interval: Duration,
    heartbeat: Duration,
    boundary: String,
    /// When the last part was sent.
    last: Option<Instant>,
    /// The last part held `count` observations and more were there: the next one goes at once.
    more: bool,
    done: bool,
}

impl Streaming {
    async fn next_part(&mut self) -> Option<Bytes> {
        if self.done {
            return None;
        }
        let mut next = self.s.next.clone();
        let mut stopped = self.s.stopped.clone();
        loop {
            if *stopped.borrow() {
                return None;
            }
            // Not sooner than `interval` after the last part, unless that part could not hold
            // all there was: what is left goes at once (else a client that asks for fewer than
            // the machines make per interval falls further behind each interval).
            if let Some(last) = self.last.filter(|_| !self.more) {
                tokio::time::sleep_until(last + self.interval).await;
            }
            let due = self.last.map_or(Instant::now(), |l| l + self.heartbeat);
            let news = *next.borrow_and_update() > self.window.from;
            if !news && self.last.is_some() && Instant::now() < due {
                tokio::select! {
                    _ = next.changed() => {}
                    _ = tokio::time::sleep_until(due) => {}
                    _ = stopped.changed() => return None,
                }
                continue;
            }
            let (root, kind) = {
                let buffer = self.s.buffer();
                if let Err((code, message)) = check_from(&buffer, self.window.from) {
                    self.done = true;
                    (documents::error(&self.s.sender, code, &message), "Error")
                } else {
                    let (observations, after) = collect(&buffer, &self.window);
                    self.window.from = after;
                    // `collect` stops short of the end only when it found `count`.
                    self.more = after < buffer.next_sequence();
                    // Only another device's news: nothing to send until the heartbeat.
                    if observations.is_empty() && self.last.is_some() && Instant::now() < due {
                        drop(buffer);
                        continue;
                    }
                    (documents::streams(&self.s.sender, &buffer, &observations, after), "Streams")
                }
            };
            self.last = Some(Instant::now());
            let text = self.format.print(&root, kind);
            let part = format!(
                "--{}\r\nContent-type: {}\r\nContent-length: {}\r\n\r\n{text}\r\n",
                self.boundary,
                self.format.content_type(),
                text.len()
            );
            return Some(Bytes::from(part));
        }
    }
}

fn assets(s: &Shared, format: Format, q: &Query, device: Option<String>) -> Answer {
    q.only(&["type", "count"])?;
    if let Some(kind) = q.0.get("type") {
        if kind != "CuttingTool" {
            return Ok(document(format, &documents::assets(&s.sender, &s.buffer(), &[], asset_counts(s)), "Assets"));
        }
    }
    let count = match q.number("count")? {
        None => DEFAULT_ASSETS,
        Some(0) => return Err((ErrorCode::OutOfRange, "'count' must be at least 1".into())),
        Some(n) => n as usize,
    };
    let mut tools = tools(s, device.as_deref());
    let counts = asset_counts(s);
    tools.truncate(count);
    Ok(document(format, &documents::assets(&s.sender, &s.buffer(), &tools, counts), "Assets"))
}

async fn asset_ids(State(s): State<Shared>, Named(ids): Named, headers: HeaderMap, RawQuery(q): RawQuery) -> Response {
    let q = Query::parse(q);
    let format = Format::of(&headers, &q);
    let result = q.only(&[]).and_then(|()| {
        let all = tools(&s, None);
        let mut found = Vec::new();
        for id in ids.iter().flat_map(|ids| ids.split(';')).filter(|i| !i.is_empty()) {
            match all.iter().find(|t| t.asset_id() == id) {
                Some(t) => found.push(t.clone()),
                None => return Err((ErrorCode::AssetNotFound, format!("no asset '{id}'"))),
            }
        }
        Ok(document(format, &documents::assets(&s.sender, &s.buffer(), &found, asset_counts(&s)), "Assets"))
    });
    answer(&s, format, result)
}

/// The cutting tools: every tool offset with a value, of one device or all, in device order.
fn tools(s: &Shared, device: Option<&str>) -> Vec<Tool> {
    let mut out = Vec::new();
    for hosted in s.host.list() {
        if device.is_some_and(|u| hosted.id != u) {
            continue;
        }
        let station = hosted.station();
        let offsets = &station.controller.interpreter().state.offsets;
        for number in 1..=fivex_engine::interp::MAX_TOOL_OFFSETS as u32 {
            let Some(t) = offsets.tool(number) else { continue };
            let (length, radius) = (t.h_geometry + t.h_wear, t.d_geometry + t.d_wear);
            if length != 0.0 || radius != 0.0 || t.corner_radius != 0.0 {
                out.push(Tool { device: hosted.id.clone(), number, length, radius, corner_radius: t.corner_radius });
            }
        }
    }
    out
}

fn asset_counts(s: &Shared) -> AssetCounts {
    let controllers = s.host.len();
    AssetCounts { room: controllers * fivex_engine::interp::MAX_TOOL_OFFSETS, count: tools(s, None).len() }
}
