//! A worker thread: every [`TICK`] it advances each controller of its share by the real time
//! that passed (times the controller's speed factor), so simulated time keeps pace with real
//! time however long a round takes — a slow round makes coarser steps, never a backlog.

use std::sync::atomic::Ordering;
use std::sync::{Arc, Weak};
use std::time::Instant;

use super::{Hosted, Inner, Published, Reading, TICK};

/// The longest real time one step covers: after a stall (a suspended process) the controllers
/// jump at most this far instead of replaying the whole gap.
const MAX_STEP_S: f64 = 1.0;

pub(super) fn run(inner: Weak<Inner>, index: usize, count: usize) {
    let mut mine: Vec<Arc<Hosted>> = Vec::new();
    let mut generation = u64::MAX;
    let mut last = Instant::now();
    loop {
        let Some(inner) = inner.upgrade() else { return };
        if inner.stop.load(Ordering::SeqCst) {
            return;
        }
        let now = Instant::now();
        let real_dt = now.duration_since(last).as_secs_f64().min(MAX_STEP_S);
        last = now;
        let current = inner.generation.load(Ordering::SeqCst);
        if current != generation {
            generation = current;
            let all = inner.controllers.read().unwrap_or_else(|e| e.into_inner());
            mine = all.iter().skip(index).step_by(count).cloned().collect();
        }
        let local_s = super::local_now_s();
        for hosted in &mine {
            step(&inner, hosted, real_dt, local_s);
            hosted.ticked.store(super::since_epoch(now), Ordering::Relaxed);
        }
        drop(inner);
        // Sleep to the next tick boundary of this worker's own schedule.
        let spent = now.elapsed();
        if spent < TICK {
            std::thread::sleep(TICK - spent);
        }
    }
}

/// Advance one controller and send out what it produced.
fn step(inner: &Inner, hosted: &Hosted, real_dt: f64, local_s: f64) {
    let watching = hosted.events.receiver_count() > 0;
    let positions = hosted.position.receiver_count() > 0;
    let mut station = hosted.station();
    // #3011/#3012 read the host's clock (set each tick; between ticks it runs with simulated
    // time, and so does it in an estimate run copied from this controller).
    station.controller.interpreter_mut().state.set_wall_clock(local_s);
    station.controller.tick(real_dt * hosted.speed());
    let (messages, records) = station.collect(&hosted.id, real_dt, watching);
    let frame = positions.then(|| Reading::of(&station));
    // The records and messages leave before the station is unlocked (neither send blocks), so
    // they reach the writer and the streams in the order the station produced them, whoever
    // (this worker or a panel command, `service::panel::execute`) holds it next.
    for record in records {
        match &record {
            super::Record::Alarm { alarm, .. } => {
                tracing::info!(controller = %hosted.id, code = %alarm.code, line = alarm.line, "alarm: {}", alarm.message)
            }
            super::Record::Run { program, result, cycle_time_s, .. } => {
                tracing::info!(controller = %hosted.id, ?program, result, cycle_time_s, "run ended")
            }
            _ => {}
        }
        inner.record(record);
    }
    hosted.publish(messages);
    drop(station);
    if let Some(reading) = frame {
        // Only a change is published: an idle controller's subscribers get nothing.
        let moved = hosted.position.borrow().as_ref().is_none_or(|last| !last.reading.same_frame(&reading));
        if moved {
            hosted.position.send_replace(Some(Arc::new(Published::new(reading))));
        }
    }
}
