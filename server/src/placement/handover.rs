//! Rebalancing (docs/cluster.md, "Rebalancing"): a node placing more than its fair share of the
//! controllers hands the surplus, one idle controller at a time, to the members below theirs.
//!
//! The rule, which makes a controller move at most once per change of the cluster (no
//! ping-pong): with `share` = ⌈controllers ÷ members⌉,
//! - only a node placing **more than** `share` gives, and only down to `share`;
//! - only to a member placing **fewer than** `share`, and never beyond `share` (the receivers
//!   with the fewest first);
//! - at most [`PER_BEAT`] a beat, and only while every controller has a live owner (a takeover
//!   or a placement under way first settles who owns what);
//! - only idle controllers: at rest ([`fivex_engine::controller::Controller::at_rest`]: no
//!   program under way or held, no motion, no alarm, no emergency stop), nobody watching (no
//!   open stream), and no command or write addressed to it for [`QUIET`] (its operator is
//!   not at it; reads do not count);
//!   a busy one moves at a later beat, once it is idle.
//!
//! A giver never falls below `share` and a receiver never rises above it, so a controller it
//! moved can only move again when the members or the controllers change.
//!
//! The handover itself ([`hand_over`]) loses nothing acknowledged, as a clean leave does: the
//! controller leaves the host under its station's lock (a command that waited for it is refused,
//! 503), then nothing may still act for it (the workers' next round, requests under way, its
//! streams closing), then every record it produced is written, and only then the placement
//! names the receiver (revision-checked), whose view wakes it to host the controller from the
//! database.

use std::collections::{BTreeMap, HashMap};
use std::hash::{Hash, Hasher};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::view::Placed;
use super::Cluster;
use crate::http::AppState;

/// The most controllers a node hands over in one beat.
pub const PER_BEAT: usize = 16;
/// How long a controller must have had no command or write before it may move (nor may one
/// that has just come to this node).
pub const QUIET: Duration = Duration::from_secs(10);
/// How long a handover waits for the requests and streams still holding a controller.
const RELEASE_WAIT: Duration = Duration::from_secs(5);
/// How long it waits for the database writer to write what the controllers produced.
const FLUSH_WAIT: Duration = Duration::from_secs(10);

/// The receivers of this node's surplus, one entry per controller to hand over (empty when it
/// holds no more than its share, nobody is below theirs, or a controller has no live owner).
/// `placed`: how many controllers each member places; `controllers`: how many are stored;
/// `settled`: every controller is placed on a live member.
pub fn receivers(me: &str, placed: &BTreeMap<String, usize>, controllers: usize, settled: bool) -> Vec<String> {
    if !settled || placed.is_empty() {
        return Vec::new();
    }
    let share = controllers.div_ceil(placed.len());
    let mine = placed.get(me).copied().unwrap_or(0);
    let mut below: Vec<(usize, u64, &String)> = placed
        .iter()
        .filter(|(node, n)| *node != me && **n < share)
        .map(|(node, n)| (*n, spread(me, node), node))
        .collect();
    let mut out = Vec::new();
    for _ in 0..mine.saturating_sub(share).min(PER_BEAT) {
        // The receiver with the fewest; among equals an order of this giver's own, so that
        // givers deciding at once spread over the receivers.
        below.sort();
        match below.first_mut() {
            Some((n, _, node)) if *n < share => {
                *n += 1;
                out.push(node.to_string());
            }
            _ => break,
        }
    }
    out
}

/// A number of (giver, receiver): the givers' preference among receivers equally short.
fn spread(giver: &str, receiver: &str) -> u64 {
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    (giver, receiver).hash(&mut hasher);
    hasher.finish()
}

/// Hands over to `to` (one receiver per controller) controllers this node hosts and places
/// (`owners`), at rest and unwatched; the others wait for a later beat.
pub async fn hand_over(cluster: &Cluster, state: &AppState, owners: &HashMap<String, Placed>, to: Vec<String>) {
    let me = cluster.name();
    if to.is_empty() {
        *super::lock(&cluster.inner.waits) = (0, 0);
        return;
    }
    let mut to = to.into_iter();
    let mut moving = Vec::new();
    let mut busy = 0;
    for hosted in state.host.list() {
        if to.len() == 0 {
            break;
        }
        let Some(placed) = owners.get(&hosted.id).filter(|p| p.node.as_deref() == Some(me)) else { continue };
        let station = hosted.station();
        if !station.controller.at_rest() || hosted.subscribers() > 0 || hosted.unused_for(Instant::now()) < QUIET {
            busy += 1;
            continue;
        }
        let Some(receiver) = to.next() else { break };
        // Removed under the station's lock: a command waiting for the lock finds it removed.
        state.host.remove(&hosted.id);
        drop(station);
        moving.push((hosted, receiver, placed.revision));
    }
    // Said once per change, not every beat.
    let waits = (busy, to.len());
    if std::mem::replace(&mut *super::lock(&cluster.inner.waits), waits) != waits && busy > 0 && to.len() > 0 {
        tracing::info!(busy, waiting = to.len(), "surplus controllers busy: their handover waits until they are idle");
    }
    if moving.is_empty() {
        return;
    }
    // Nothing else holds them: the workers have ended the round that could tick them, the
    // requests that reached them have answered, their streams have closed.
    let deadline = Instant::now() + RELEASE_WAIT;
    while moving.iter().any(|(hosted, _, _)| Arc::strong_count(hosted) > 1) && Instant::now() < deadline {
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    for (hosted, _, _) in moving.iter().filter(|(h, _, _)| Arc::strong_count(h) > 1) {
        tracing::warn!(id = %hosted.id, "controller still in use after {} s: handed over anyway", RELEASE_WAIT.as_secs());
    }
    // Everything they produced is written before another node loads them.
    let sent = state.host.records_sent();
    let deadline = Instant::now() + FLUSH_WAIT;
    while state.db.records_done() < sent {
        if Instant::now() >= deadline {
            // Still placed here: the next beat hosts them here again.
            tracing::warn!(controllers = moving.len(), "records not written in time: handover given up");
            return;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    for (hosted, receiver, revision) in moving {
        match cluster.hand(&hosted.id, &receiver, revision).await {
            Ok(()) => tracing::info!(id = %hosted.id, to = %receiver, "controller handed over"),
            Err(e) => tracing::warn!(id = %hosted.id, to = %receiver, error = %e, "controller not handed over"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn placed(counts: &[(&str, usize)]) -> BTreeMap<String, usize> {
        counts.iter().map(|(n, c)| (n.to_string(), *c)).collect()
    }

    fn count(to: &[String], node: &str) -> usize {
        to.iter().filter(|n| *n == node).count()
    }

    #[test]
    fn a_node_above_its_share_gives_its_surplus_to_those_below() {
        // Twelve on two nodes, a third joins: each gives two to it.
        let now = placed(&[("a", 6), ("b", 6), ("c", 0)]);
        assert_eq!(receivers("a", &now, 12, true), ["c", "c"]);
        assert_eq!(receivers("b", &now, 12, true), ["c", "c"]);
        assert!(receivers("c", &now, 12, true).is_empty());
        // Everything on one node: it gives to both, the fewest first, up to their share.
        let to = receivers("a", &placed(&[("a", 12), ("b", 0), ("c", 0)]), 12, true);
        assert_eq!((to.len(), count(&to, "b"), count(&to, "c")), (8, 4, 4));
        let to = receivers("a", &placed(&[("a", 9), ("b", 3), ("c", 0)]), 12, true);
        assert_eq!((to.len(), count(&to, "b"), count(&to, "c")), (5, 1, 4));
    }

    #[test]
    fn within_the_share_nothing_moves_and_a_receiver_never_passes_it() {
        // ⌈13 ÷ 3⌉ = 5: nobody above it.
        assert!(receivers("a", &placed(&[("a", 5), ("b", 5), ("c", 3)]), 13, true).is_empty());
        // One above: one moves, to the one below.
        assert_eq!(receivers("a", &placed(&[("a", 6), ("b", 4), ("c", 3)]), 13, true), ["c"]);
        // ⌈13 ÷ 2⌉ = 7: two above, given to the one below.
        assert_eq!(receivers("a", &placed(&[("a", 9), ("b", 4)]), 13, true), ["b", "b"]);
        // ⌈13 ÷ 3⌉ = 5: the surplus, four, all to the one furthest below.
        assert_eq!(receivers("a", &placed(&[("a", 9), ("b", 4), ("c", 0)]), 13, true), ["c", "c", "c", "c"]);
        // The surplus goes to the fewest first.
        let to = receivers("a", &placed(&[("a", 8), ("b", 4), ("c", 4), ("d", 5)]), 21, true);
        assert_eq!((to.len(), count(&to, "b"), count(&to, "c")), (2, 1, 1));
    }

    #[test]
    fn at_most_a_beat_s_worth_and_nothing_while_a_controller_has_no_live_owner() {
        let now = placed(&[("a", 2000), ("b", 0)]);
        assert_eq!(receivers("a", &now, 2000, true).len(), PER_BEAT);
        assert!(receivers("a", &now, 2000, false).is_empty());
        assert!(receivers("a", &BTreeMap::new(), 0, true).is_empty());
    }
}
