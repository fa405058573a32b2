//! The shop-floor clients of `fivex-load --mtconnect`: one MTConnect `/sample` stream per
//! controller (that device's observations, `interval` long-poll) and one client that polls the
//! whole agent's `/sample` from each `nextSequence` and checks the sequence has no gap; and the
//! OPC UA client (`--opcua-client`, a program run beside, its JSON report taken in).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use http_body_util::{BodyExt, Empty};
use serde_json::{json, Value};

type Client =
    hyper_util::client::legacy::Client<hyper_util::client::legacy::connect::HttpConnector, Empty<bytes::Bytes>>;

/// What the MTConnect clients saw while measuring.
#[derive(Debug, Default)]
pub struct Seen {
    pub parts: usize,
    pub observations: usize,
    /// A part whose sequences are not all above the stream's last one.
    pub out_of_order: usize,
    /// Error documents (`OUT_OF_RANGE`: the client fell out of the buffer) and ended streams.
    pub errors: usize,
    /// Milliseconds from the newest observation's timestamp to its part's arrival.
    pub ages_ms: Vec<f64>,
    /// The whole agent's polls, and the sequence numbers they missed (must stay 0).
    pub polls: usize,
    pub polled: u64,
    pub gaps: u64,
}

pub fn client() -> Client {
    hyper_util::client::legacy::Client::builder(hyper_util::rt::TokioExecutor::new()).build_http()
}

/// `attribute="VALUE"` after `after` in `xml`.
fn attribute<'a>(xml: &'a str, after: &str, name: &str) -> Option<&'a str> {
    let rest = &xml[xml.find(after)?..];
    let start = rest.find(&format!(" {name}=\""))? + name.len() + 3;
    Some(&rest[start..start + rest[start..].find('"')?])
}

/// Every `NAME="…"` value in `xml`.
fn all<'a>(xml: &'a str, name: &str) -> Vec<&'a str> {
    let marker = format!(" {name}=\"");
    xml.match_indices(&marker)
        .filter_map(|(at, m)| {
            let rest = &xml[at + m.len()..];
            Some(&rest[..rest.find('"')?])
        })
        .collect()
}

/// The length of the first part in `text` if it has arrived whole (`--BOUNDARY`, headers with
/// `Content-length`, a blank line, the document).
fn complete_part(text: &str) -> Option<usize> {
    let headers_end = text.find("\r\n\r\n")? + 4;
    let length: usize = text[..headers_end]
        .lines()
        .find_map(|l| l.strip_prefix("Content-length: "))
        .and_then(|v| v.trim().parse().ok())?;
    (text.len() >= headers_end + length).then_some(headers_end + length)
}

fn unix_ms(rfc3339: &str) -> Option<f64> {
    let t = time::OffsetDateTime::parse(rfc3339, &time::format_description::well_known::Rfc3339).ok()?;
    Some((t.unix_timestamp_nanos() / 1000) as f64 / 1000.0)
}

/// The agent's next sequence now.
pub async fn next_sequence(client: &Client, agent: &str) -> u64 {
    let response = client.get(format!("{agent}/current").parse().unwrap()).await.expect("the agent answers");
    let body = response.into_body().collect().await.expect("a document").to_bytes();
    let text = String::from_utf8_lossy(&body);
    attribute(&text, "<Header", "nextSequence").and_then(|v| v.parse().ok()).expect("nextSequence")
}

/// One controller's `/sample` stream from `from` on: its parts are counted while `measuring`.
pub fn stream(
    client: Client,
    agent: String,
    device: String,
    from: u64,
    seen: Arc<Mutex<Seen>>,
    measuring: Arc<AtomicBool>,
) {
    tokio::spawn(async move {
        let url = format!("{agent}/{device}/sample?from={from}&interval=100&count=10000&heartbeat=2000");
        let Ok(response) = client.get(url.parse().unwrap()).await else {
            seen.lock().unwrap().errors += 1;
            return;
        };
        let mut body = response.into_body();
        let (mut text, mut last) = (String::new(), 0u64);
        while let Some(Ok(frame)) = body.frame().await {
            let Ok(data) = frame.into_data() else { continue };
            text.push_str(&String::from_utf8_lossy(&data));
            // Every complete part: its headers, then as many bytes as its Content-length says.
            while let Some(end) = complete_part(&text) {
                let part: String = text.drain(..end).collect();
                let arrived = crate::now_ms();
                let mut s = seen.lock().unwrap();
                if part.contains("<MTConnectError") {
                    s.errors += 1;
                    continue;
                }
                let sequences: Vec<u64> = all(&part, "sequence").iter().filter_map(|v| v.parse().ok()).collect();
                if sequences.iter().any(|&q| q <= last) {
                    s.out_of_order += 1;
                }
                last = sequences.iter().copied().max().unwrap_or(last);
                if measuring.load(Ordering::Relaxed) && !sequences.is_empty() {
                    s.parts += 1;
                    s.observations += sequences.len();
                    if let Some(newest) = all(&part, "timestamp").into_iter().filter_map(unix_ms).reduce(f64::max) {
                        s.ages_ms.push(arrived - newest);
                    }
                }
            }
        }
        // The stream ended while the service runs.
        seen.lock().unwrap().errors += 1;
    });
}

/// Polls the whole agent's `/sample` from each `nextSequence`, counting the numbers missing.
pub fn poll(client: Client, agent: String, from: u64, seen: Arc<Mutex<Seen>>, measuring: Arc<AtomicBool>) {
    tokio::spawn(async move {
        let mut from = from;
        loop {
            tokio::time::sleep(Duration::from_millis(250)).await;
            let url = format!("{agent}/sample?from={from}&count=100000");
            let Ok(response) = client.get(url.parse().unwrap()).await else { continue };
            let Ok(body) = response.into_body().collect().await else { continue };
            let text = String::from_utf8_lossy(&body.to_bytes()).into_owned();
            let mut s = seen.lock().unwrap();
            if text.contains("<MTConnectError") {
                s.errors += 1;
                return;
            }
            let Some(next) = attribute(&text, "<Header", "nextSequence").and_then(|v| v.parse::<u64>().ok()) else {
                s.errors += 1;
                return;
            };
            let count = all(&text, "sequence").len() as u64;
            if measuring.load(Ordering::Relaxed) {
                s.polls += 1;
                s.polled += count;
                s.gaps += (next - from).saturating_sub(count);
            }
            from = next;
        }
    });
}

/// Whether the OPC UA client's report says every subscription kept up: no error, every one saw
/// changes, none went back in time.
pub fn opcua_kept_up(report: &Value) -> bool {
    report.get("error").is_none()
        && report["subscriptions"].as_u64().is_some_and(|n| n > 0)
        && report["subscriptions_without_change"] == 0
        && report["timestamps_backwards"] == 0
}

pub fn report(seen: &Seen, controllers: usize, wall: f64) -> Value {
    let mut ages = seen.ages_ms.clone();
    ages.sort_by(f64::total_cmp);
    json!({
        "streams": controllers,
        "parts": seen.parts,
        "observations_streamed": seen.observations,
        "observations_per_s": seen.observations as f64 / wall,
        "age_ms": {"p50": crate::percentile(&ages, 0.5), "p99": crate::percentile(&ages, 0.99), "max": ages.last().copied().unwrap_or(f64::NAN)},
        "out_of_order": seen.out_of_order,
        "errors": seen.errors,
        "polls": seen.polls,
        "polled": seen.polled,
        "gaps": seen.gaps,
    })
}

/// Runs `command` (split on blanks) with the OPC UA endpoint and the seconds to measure as its
/// last two arguments; its stdout must be one JSON object (its report).
pub async fn opcua_client(command: &str, endpoint: &str, seconds: f64) -> Value {
    let mut words = command.split_whitespace();
    let program = words.next().expect("--opcua-client needs a command");
    let output = tokio::process::Command::new(program)
        .args(words)
        .arg(endpoint)
        .arg(format!("{seconds}"))
        .output()
        .await
        .expect("run the OPC UA client");
    let stderr = String::from_utf8_lossy(&output.stderr);
    let last = stderr.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("");
    serde_json::from_slice(&output.stdout).unwrap_or_else(|_| json!({"error": format!("{}: {last}", output.status)}))
}
