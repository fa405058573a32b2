//! The observer's rounds into the address space: a machine for each controller that appears,
//! removed when it goes, and in each round the values that changed (one write of the address
//! space for all of them, so that subscribers get a round's changes together) and an event for
//! each alarm that appeared.

use std::collections::HashMap;
use std::sync::Arc;

use opcua::server::node_manager::memory::CoreNodeManager;
use opcua::server::ServerHandle;
use opcua::types::{DataValue, DateTime, NodeId, ObjectId};
use tokio::sync::watch;

use super::events;
use super::instance::{self, Types};
use super::machine::{Model, Shown};
use super::manager::Manager;
use crate::host::stream::AlarmInfo;
use crate::shopfloor::observe::Round;

pub struct Follower {
    model: Model,
    handle: ServerHandle,
    manager: Arc<Manager>,
    core: Arc<CoreNodeManager>,
    shown: HashMap<String, Shown>,
}

impl Follower {
    pub fn new(
        handle: ServerHandle,
        manager: Arc<Manager>,
        core: Arc<CoreNodeManager>,
        fivex: u16,
    ) -> Result<Follower, String> {
        let missing = || "--opcua: the Machinery / Machine Tools nodesets lack what fivex shows".to_string();
        let (machinery, machine_tool) =
            Model::namespaces(handle.type_tree().read().namespaces()).ok_or_else(missing)?;
        let model = {
            let (own, core_space) = (manager.address_space().read(), core.address_space().read());
            Model::read(&Types::new(&own, &core_space), fivex, machinery, machine_tool).ok_or_else(missing)?
        };
        Ok(Follower { model, handle, manager, core, shown: HashMap::new() })
    }

    /// Follows the rounds until the observer stops, once the server has `started` (its node
    /// managers' start locks the address spaces and the type tree).
    pub async fn run(mut self, mut started: watch::Receiver<bool>, mut rounds: watch::Receiver<Arc<Round>>) {
        if started.wait_for(|s| *s).await.is_err() {
            return;
        }
        loop {
            let round = rounds.borrow_and_update().clone();
            self.apply(&round);
            if rounds.changed().await.is_err() {
                return;
            }
        }
    }

    pub fn apply(&mut self, round: &Round) {
        self.add_and_remove(round);
        let mut alarms: Vec<(NodeId, NodeId, String, AlarmInfo)> = Vec::new();
        let mut changes: Vec<(&NodeId, DataValue)> = Vec::new();
        let mut found = Vec::new();
        let at = DateTime::now();
        for entry in &round.controllers {
            let Some(shown) = self.shown.get(&entry.id) else { continue };
            let (root, messages) = (shown.root.clone(), shown.messages.clone());
            shown.update(&self.model, entry, at, &mut changes, &mut found);
            alarms.extend(found.drain(..).map(|a| (root.clone(), messages.clone(), entry.name.clone(), a)));
        }
        if !changes.is_empty() {
            let values = changes.into_iter().map(|(id, value)| (id, None, value));
            if let Err(status) = self.manager.set_values(self.handle.subscriptions(), values) {
                tracing::warn!(%status, "OPC UA: a machine's value could not be set");
            }
        }
        if !alarms.is_empty() {
            self.raise(&alarms);
        }
    }

    /// Machines for the controllers that appeared (or changed what they are), none for those
    /// gone.
    fn add_and_remove(&mut self, round: &Round) {
        let mut new = Vec::new();
        for entry in &round.controllers {
            match self.shown.get_mut(&entry.id) {
                Some(shown) if shown.shows(entry) => shown.seen = round.number,
                _ => new.push(entry.clone()),
            }
        }
        // Not seen in this round: gone, or to be made again (among `new`).
        let gone: Vec<String> =
            self.shown.iter().filter(|(_, s)| s.seen != round.number).map(|(id, _)| id.clone()).collect();
        let gone: Vec<Shown> = gone.iter().filter_map(|id| self.shown.remove(id)).collect();
        if gone.is_empty() && new.is_empty() {
            return;
        }
        if !gone.is_empty() {
            let mut space = self.manager.address_space().write();
            for shown in &gone {
                shown.remove(&mut space);
            }
        }
        // One machine at a time, planned under read locks: clients keep reading meanwhile.
        let mut constants = Vec::new();
        for entry in &new {
            let mut planned = Vec::new();
            let mut shown = {
                let (own, core) = (self.manager.address_space().read(), self.core.address_space().read());
                Shown::plan(&self.model, &Types::new(&own, &core), entry, &mut planned)
            };
            let mut space = self.manager.address_space().write();
            instance::insert(&mut space, planned);
            match shown.finish(&mut space, entry) {
                Ok(values) => constants.extend(values),
                Err(e) => {
                    tracing::error!(controller = %entry.id, "OPC UA: cannot show the controller: {e}");
                    shown.remove(&mut space);
                    continue;
                }
            }
            shown.seen = round.number;
            self.shown.insert(entry.id.clone(), shown);
        }
        let values = constants.iter().map(|(id, value)| (id, None, value.clone()));
        if let Err(status) = self.manager.set_values(self.handle.subscriptions(), values) {
            tracing::warn!(%status, "OPC UA: a machine's constant could not be set");
        }
    }

    /// An event per alarm, to the machine, its `Notification/Messages` and the Server object
    /// (a client may subscribe to any of them).
    fn raise(&self, alarms: &[(NodeId, NodeId, String, AlarmInfo)]) {
        let tree = self.handle.type_tree().read();
        let made: Vec<_> = alarms
            .iter()
            .map(|(root, messages, name, alarm)| {
                (events::alarm(tree.namespaces(), root, name, &alarm.code, &alarm.message), root, messages)
            })
            .collect();
        drop(tree);
        let server = NodeId::from(ObjectId::Server);
        let notifiers = made.iter().flat_map(|(event, root, messages)| {
            let event = events::as_event(event);
            [(event, *root), (event, *messages), (event, &server)]
        });
        self.handle.subscriptions().notify_events(notifiers);
    }
}
